//! [`PartialRun`]: the finished chunks of a fixed-budget run, for checkpoints, resumption and
//! runs split across processes or machines.

use std::collections::BTreeMap;
use std::ops::Range;

use super::Integrator;
use super::plan::{CHUNKS_IN_MEMORY, ChunkResult, Chunks, Folded, Plan};
use crate::engine::Executor;
use crate::estimator::Estimator;
use crate::sampler::Sampler;
use crate::stats::Estimate;
use crate::{Error, Result};

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
/// The part records the run's layout (points and replicates, the sampler's name, seed and
/// dimension) and refuses to be finished or merged under another; it cannot check that the
/// integrand is the same.
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
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PartialRun {
    layout: Layout,
    chunks: BTreeMap<u64, ChunkResult>,
}

/// What must agree for two parts to belong to the same run.
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Layout {
    samples: u64,
    replicates: u64,
    stride: u64,
    total_chunks: u64,
    sampler: String,
    seed: u64,
    dims: usize,
}

impl Layout {
    fn of(plan: &Plan, sampler: &dyn Sampler) -> Result<Layout> {
        Ok(Layout {
            samples: plan.samples,
            replicates: plan.replicates,
            stride: plan.stride,
            total_chunks: plan.total_chunks()?,
            sampler: sampler.name().to_string(),
            seed: sampler.seed(),
            dims: sampler.dims(),
        })
    }

    fn check(&self, other: &Layout) -> Result<()> {
        if self == other {
            return Ok(());
        }
        Err(Error::invalid(
            "partial run",
            format!(
                "{} points x {} replicates of {} (seed {}, {} dims)",
                other.samples, other.replicates, other.sampler, other.seed, other.dims
            ),
            format!(
                "a part of the same run: {} points x {} replicates of {} (seed {}, {} dims)",
                self.samples, self.replicates, self.sampler, self.seed, self.dims
            ),
        ))
    }
}

impl PartialRun {
    /// Number of chunks finished.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(50_000);
    /// assert_eq!(i.run_part(1..3).unwrap().chunks_done(), 2);
    /// ```
    pub fn chunks_done(&self) -> u64 {
        self.chunks.len() as u64
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
        self.chunks_done() == self.total_chunks()
    }

    /// The first chunk not yet finished, if any.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(50_000);
    /// assert_eq!(i.run_part(0..2).unwrap().next_missing(), Some(2));
    /// ```
    pub fn next_missing(&self) -> Option<u64> {
        // The chunks are kept in order: the first gap is where a key differs from its rank.
        let mut expected = 0;
        for &chunk in self.chunks.keys() {
            if chunk != expected {
                return Some(expected);
            }
            expected += 1;
        }
        (expected < self.total_chunks()).then_some(expected)
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
    pub fn merge(&mut self, other: PartialRun) -> Result<()> {
        self.layout.check(&other.layout)?;
        if let Some(twice) = other.chunks.keys().find(|c| self.chunks.contains_key(c)) {
            return Err(Error::invalid(
                "partial run",
                format!("with chunk {twice}"),
                "parts with disjoint chunks (this chunk is in both)",
            ));
        }
        self.chunks.extend(other.chunks);
        Ok(())
    }
}

impl<E: Estimator> Integrator<E> {
    /// Number of chunks of this run (fixed budget only), the unit of [`run_part`](Self::run_part).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(40_000).replicates(2);
    /// assert_eq!(i.total_chunks().unwrap(), 2 * 3);
    /// ```
    pub fn total_chunks(&self) -> Result<u64> {
        self.with_plan(|plan, _, _| plan.total_chunks())
    }

    /// Evaluates chunks `range` of this run (see [`PartialRun`]).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(50_000);
    /// assert!(i.run_part(3..5).is_err()); // only 4 chunks
    /// ```
    pub fn run_part(&self, range: Range<u64>) -> Result<PartialRun> {
        self.with_plan(|plan, sampler, executor| {
            let total = plan.total_chunks()?;
            if range.start >= range.end || range.end > total {
                return Err(Error::invalid(
                    "chunk range",
                    format!("{}..{}", range.start, range.end),
                    format!("a non-empty range within 0..{total}"),
                ));
            }
            let mut chunks = BTreeMap::new();
            self.with_estimator(executor, |estimator, _| {
                let job = Chunks {
                    plan,
                    sampler,
                    estimator,
                };
                executor.run(&job, range, CHUNKS_IN_MEMORY, |chunk, result| {
                    chunks.insert(chunk, result);
                    Ok(())
                })
            })?;
            Ok(PartialRun {
                layout: Layout::of(plan, sampler)?,
                chunks,
            })
        })
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
        partial.merge(self.run_part(start..end)?)
    }

    /// The estimate of a complete [`PartialRun`] of this run: the same bits as
    /// [`run`](Self::run).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(50_000);
    /// let part = i.run_part(0..2).unwrap();
    /// assert!(i.finish(&part).unwrap_err().to_string().contains("chunk 2"));
    /// ```
    pub fn finish(&self, partial: &PartialRun) -> Result<Estimate> {
        self.with_plan(|plan, sampler, _| {
            Layout::of(plan, sampler)?.check(&partial.layout)?;
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
            let mut folded = Folded::new(plan.replicates);
            for (&chunk, result) in &partial.chunks {
                folded.add(plan, chunk, result);
            }
            plan.estimate(sampler, &folded, self.config.non_finite)
        })
    }

    /// Calls `work` with the plan of a fixed-budget run, the sampler and the executor.
    fn with_plan<R>(
        &self,
        work: impl FnOnce(&Plan, &dyn Sampler, &Executor) -> Result<R>,
    ) -> Result<R> {
        if self.config.tolerance.is_some() {
            return Err(Error::invalid(
                "tolerance",
                "set",
                "no tolerance for a run in parts (its stages depend on the results so far; \
                 checkpoint fixed-budget runs)",
            ));
        }
        let sampler = self.run_sampler()?;
        let executor = self.config.executor()?;
        let plan = Plan::new(self.config.samples, self.config.replicates, &*sampler)?;
        work(&plan, &*sampler, &executor)
    }
}
