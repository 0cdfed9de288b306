//! [`PartialRun`]: the finished chunks of a fixed-budget run, for checkpoints, resumption and
//! runs split across processes or machines.

use std::collections::BTreeMap;
use std::ops::Range;

use super::Integrator;
use super::engine::Integration;
use super::engine::RunEstimator;
use super::layout::Layout;
use super::plan::{CHUNKS_IN_MEMORY, ChunkResult, Chunks, Folded, Plan, keeps_covariance};
use crate::engine::Executor;
use crate::error::{Error, Result};
use crate::sampler::Sampler;
use crate::stats::VectorEstimate;

/// The results of some chunks of a fixed-budget [`Integrator`] run.
///
/// A run's sample indices are cut into chunks of 16384 points, numbered replicate by
/// replicate ([`Integrator::total_chunks`]). [`Integrator::run_part`] evaluates any range of
/// them, [`Integrator::resume`] continues where a partial run stopped, [`merge`](Self::merge)
/// joins parts computed anywhere, and [`Integrator::finish`] combines the chunks in index
/// order, so the estimate has the same bits as one uninterrupted [`Integrator::run`],
/// however the work was split, stopped, saved (with the `serde` feature) and resumed.
///
/// With JSON, use a parser that reads floats back exactly (serde_json's `float_roundtrip`
/// feature), or the resumed run may differ in the last bits.
///
/// The part carries a fingerprint of everything that decides the run's numbers (points and
/// replicates, chunk layout, the sampler's name, seed and dimension, the non-finite policy,
/// the format version, an optional [`label`](Integrator::label) for the integrand, and a
/// CRC-32 of the sampler's points and the integrand's values at a few probe points, which
/// change with any scramble, generating vector, domain, pdf or estimator), and resume, finish
/// and merge refuse a part of another run with an error naming the first field that differs.
/// An integrand that differs only away from the probe points is not detected: label it. Saved
/// with serde, the part also carries a CRC-32 of its whole content, and a part that fails it
/// (a corrupted file) does not deserialize; nor does a part whose state its plan cannot reach
/// (an edited file with its CRC recomputed: a replicate or chunk whose counts are not its
/// points, chunks out of order), with an error naming the field.
///
/// Chunks finished in order from the first are folded as they arrive, so a part holds one
/// accumulator per replicate plus the chunks finished out of order: its size does not grow
/// with the run.
///
/// ```
/// use mcint::{Integrator, pdf::UniformBox};
/// let integrator = Integrator::over_box(|x: &[f64]| x[0] * x[1], UniformBox::unit(2).unwrap())
///     .samples(100_000)
///     .seed(7);
/// let total = integrator.total_chunks().unwrap();
/// // Two "machines" take halves; the parts merge into the uninterrupted answer.
/// let mut part = integrator.run_part(0..total / 2).unwrap();
/// part.merge(integrator.run_part(total / 2..total).unwrap()).unwrap();
/// assert!(part.is_complete());
/// assert_eq!(integrator.finish(&part).unwrap(), integrator.run().unwrap());
/// ```
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(
        into = "super::partial_format::Saved",
        try_from = "super::partial_format::Saved"
    )
)]
pub struct PartialRun {
    pub(super) layout: Layout,
    /// Chunks `0..prefix` are finished and folded into `folded`.
    pub(super) prefix: u64,
    pub(super) folded: Folded,
    /// Finished chunks after the first missing one.
    pub(super) chunks: BTreeMap<u64, ChunkResult>,
}

impl PartialRun {
    /// An empty part of the run of `layout`, with the empty fold of its chunks.
    fn new(layout: Layout, folded: Folded) -> PartialRun {
        PartialRun {
            folded,
            layout,
            prefix: 0,
            chunks: BTreeMap::new(),
        }
    }

    /// Folds the chunks that now follow the prefix without a gap.
    fn compact(&mut self) {
        let per_replicate = self.layout.chunks_per_replicate();
        while let Some(result) = self.chunks.remove(&self.prefix) {
            self.folded.add(per_replicate, self.prefix, &result);
            self.prefix += 1;
        }
    }

    /// Adds finished chunks, refusing any chunk the part already has.
    fn insert(&mut self, chunks: impl IntoIterator<Item = (u64, ChunkResult)>) -> Result<()> {
        for (chunk, result) in chunks {
            if chunk < self.prefix || self.chunks.contains_key(&chunk) {
                return Err(Error::invalid(
                    "partial run",
                    format!("with chunk {chunk}"),
                    "parts with disjoint chunks (this chunk is in both)",
                ));
            }
            self.chunks.insert(chunk, result);
        }
        self.compact();
        Ok(())
    }

    /// Number of chunks finished.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(50_000);
    /// assert_eq!(i.run_part(1..3).unwrap().chunks_done(), 2);
    /// ```
    pub fn chunks_done(&self) -> u64 {
        self.prefix + self.chunks.len() as u64
    }

    /// Number of chunks of the whole run.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(50_000);
    /// assert_eq!(i.run_part(0..1).unwrap().total_chunks(), 4);
    /// ```
    pub fn total_chunks(&self) -> u64 {
        self.layout.total_chunks
    }

    /// Whether every chunk is finished.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(10);
    /// assert!(i.run_part(0..1).unwrap().is_complete());
    /// ```
    pub fn is_complete(&self) -> bool {
        self.prefix == self.total_chunks()
    }

    /// The first chunk not yet finished, if any.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(50_000);
    /// assert_eq!(i.run_part(0..2).unwrap().next_missing(), Some(2));
    /// ```
    pub fn next_missing(&self) -> Option<u64> {
        (!self.is_complete()).then_some(self.prefix)
    }

    /// Adds the chunks of `other`, a part of the same run with none of the same chunks.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(50_000);
    /// let mut a = i.run_part(0..2).unwrap();
    /// assert!(a.merge(i.run_part(1..3).unwrap()).is_err()); // chunk 1 twice
    /// a.merge(i.run_part(2..4).unwrap()).unwrap();
    /// assert!(a.is_complete());
    /// ```
    pub fn merge(&mut self, mut other: PartialRun) -> Result<()> {
        self.layout.check(&other.layout)?;
        if self.prefix > 0 && other.prefix > 0 {
            return Err(Error::invalid(
                "partial run",
                "with chunk 0",
                "parts with disjoint chunks (this chunk is in both)",
            ));
        }
        // The part that holds chunk 0 keeps its fold; the other's chunks join it.
        if other.prefix > 0 {
            std::mem::swap(self, &mut other);
        }
        let mut merged = self.clone();
        merged.insert(other.chunks)?;
        *self = merged;
        Ok(())
    }
}

/// Resuming: a fixed-budget run by chunks, for checkpoints and runs split across processes.
impl<E: Integration> Integrator<E> {
    /// Number of chunks of this run (fixed budget only), the unit of [`run_part`](Self::run_part).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(40_000).replicates(2);
    /// assert_eq!(i.total_chunks().unwrap(), 2 * 3);
    /// let f = |x: &[f64], out: &mut [f64]| out.fill(x[0]);
    /// let v = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap()).samples(40_000);
    /// assert_eq!(v.total_chunks().unwrap(), 3);
    /// ```
    pub fn total_chunks(&self) -> Result<u64> {
        self.with_plan(|plan, _, _| plan.total_chunks())
    }

    /// Evaluates chunks `range` of this run (see [`PartialRun`]). A time limit or a
    /// cancellation stops it after the chunks finished by then, which the part keeps.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(50_000);
    /// assert!(i.run_part(3..5).is_err()); // only 4 chunks
    /// let f = |x: &[f64], out: &mut [f64]| { out[0] = x[0]; out[1] = x[0].sin(); };
    /// let v = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap()).samples(50_000);
    /// let mut part = v.run_part(0..2).unwrap();
    /// part.merge(v.run_part(2..4).unwrap()).unwrap();
    /// assert_eq!(v.finish(&part).unwrap(), v.run().unwrap());
    /// ```
    pub fn run_part(&self, range: Range<u64>) -> Result<PartialRun> {
        self.run_part_engine(range)
    }

    /// Evaluates up to `max_chunks` more chunks of `partial`, from its first missing one
    /// on (stopping before any chunk it already has); a run stopped at any chunk boundary
    /// and resumed this way finishes with the same bits as an uninterrupted one.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::over_box(|x: &[f64]| x[0].sin(), UniformBox::unit(1).unwrap()).samples(100_000);
    /// let mut part = i.run_part(0..1).unwrap();
    /// while !part.is_complete() {
    ///     i.resume(&mut part, 2).unwrap();
    /// }
    /// assert_eq!(i.finish(&part).unwrap(), i.run().unwrap());
    /// ```
    pub fn resume(&self, partial: &mut PartialRun, max_chunks: u64) -> Result<()> {
        self.resume_engine(partial, max_chunks)
    }

    /// The estimate of a complete [`PartialRun`] of this run: the same bits as
    /// [`run`](Self::run). A part of another run (another number of outputs among others) is
    /// refused.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(50_000);
    /// let part = i.run_part(0..2).unwrap();
    /// assert!(i.finish(&part).unwrap_err().to_string().contains("chunk 2"));
    /// let f = |x: &[f64], out: &mut [f64]| out.fill(x[0]);
    /// let v = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap()).samples(50_000);
    /// let err = v.finish(&i.run_part(0..4).unwrap()).unwrap_err();
    /// assert!(err.to_string().contains("outputs"), "{err}");
    /// ```
    pub fn finish(&self, partial: &PartialRun) -> Result<E::Output> {
        E::output(self.finish_engine(partial)?)
    }
}

/// The checkpoint machinery, shared by scalar and vector runs.
impl<E> Integrator<E> {
    fn run_part_engine(&self, range: Range<u64>) -> Result<PartialRun>
    where
        E: RunEstimator,
    {
        self.with_plan(|plan, sampler, executor| {
            let total = plan.total_chunks()?;
            if range.start >= range.end || range.end > total {
                return Err(Error::invalid(
                    "chunk range",
                    format!("{}..{}", range.start, range.end),
                    format!("a non-empty range within 0..{total}"),
                ));
            }
            let layout = self.estimator.layout(plan, sampler, &self.config)?;
            // A limit stops the part where it is: the chunks before it are kept.
            let limits = self.config.limits();
            self.estimator
                .with_main(&self.config, executor, &limits, |estimator, _| {
                    let job = Chunks::new(plan, sampler, estimator);
                    let mut part = PartialRun::new(layout, job.folded()?);
                    executor.run(&job, range, CHUNKS_IN_MEMORY, &limits, |chunk, result| {
                        part.insert([(chunk, result)])
                    })?;
                    Ok(part)
                })
        })
    }

    fn resume_engine(&self, partial: &mut PartialRun, max_chunks: u64) -> Result<()>
    where
        E: RunEstimator,
    {
        self.with_plan(|plan, sampler, _| {
            self.estimator
                .layout(plan, sampler, &self.config)?
                .check(&partial.layout)
        })?;
        if max_chunks == 0 {
            return Err(Error::invalid("max_chunks", 0, "at least 1"));
        }
        let Some(start) = partial.next_missing() else {
            return Ok(());
        };
        let limit = start.saturating_add(max_chunks).min(partial.total_chunks());
        let end = partial
            .chunks
            .range(start..limit)
            .next()
            .map_or(limit, |(&done, _)| done);
        partial.merge(self.run_part_engine(start..end)?)
    }

    fn finish_engine(&self, partial: &PartialRun) -> Result<VectorEstimate>
    where
        E: RunEstimator,
    {
        self.with_plan(|plan, sampler, executor| {
            self.estimator
                .layout(plan, sampler, &self.config)?
                .check(&partial.layout)?;
            if let Some(missing) = partial.next_missing() {
                return Err(Error::invalid(
                    "partial run",
                    format!(
                        "{} of {} chunks",
                        partial.chunks_done(),
                        partial.total_chunks()
                    ),
                    format!("every chunk finished (chunk {missing} is missing)"),
                ));
            }
            // The layout does not say whether the run keeps covariances; its sampler does.
            let keeps = keeps_covariance(partial.layout.outputs, sampler);
            if keeps == partial.folded.covariances.is_empty() {
                let (has, wants) = if keeps {
                    (
                        "without covariances",
                        "keeps the covariance of its outputs per replicate",
                    )
                } else {
                    ("with covariances", "keeps no covariance")
                };
                return Err(Error::invalid(
                    "partial run",
                    has,
                    format!("a part of this run, which {wants}"),
                ));
            }
            let mut run = plan.estimate(sampler, &partial.folded, self.config.non_finite)?;
            // Evaluations counted as the uninterrupted run counts them: those of each
            // contribution, and the pilot's (which each part ran again, to the same fit).
            let limits = self.config.limits();
            let (cost, pilot) =
                self.estimator
                    .with_main(&self.config, executor, &limits, |estimator, pilot| {
                        Ok((estimator.evaluations_per_contribution(), pilot))
                    })?;
            run.for_each_output(|_, output| {
                output.evaluations = output
                    .evaluations
                    .saturating_mul(cost)
                    .saturating_add(pilot);
            });
            Ok(run)
        })
    }

    /// Calls `work` with the plan of a fixed-budget run, the sampler and the executor.
    fn with_plan<R>(
        &self,
        work: impl FnOnce(&Plan, &dyn Sampler, &Executor) -> Result<R>,
    ) -> Result<R>
    where
        E: RunEstimator,
    {
        if self.estimator.targets(&self.config)?.any() {
            return Err(Error::invalid(
                "tolerance",
                "set",
                "no tolerance for a run in parts (its stages depend on the results so far; \
                 checkpoint fixed-budget runs)",
            ));
        }
        let sampler = self.run_sampler()?;
        let (executor, _run) = self.config.executor()?;
        let plan = Plan::new(self.config.samples, self.config.replicates, &*sampler)?;
        work(&plan, &*sampler, &executor)
    }
}
