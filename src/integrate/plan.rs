//! [`Plan`]: which sample indices each replicate of an [`Integrator`](super::Integrator) run
//! uses, cut into fixed chunks that the [`Executor`] evaluates and folds in chunk order.

use super::{CHUNK, DEFAULT_SAMPLES, NonFinitePolicy};
use crate::engine::{self, ChunkJob, Executor, Limits};
use crate::error::{Error, Result};
use crate::estimator::VectorEstimator;
use crate::points::Points;
use crate::sampler::{PassKind, Sampler};
use crate::stats::{Accumulator, CovarianceAccumulator, StopReason, VectorEstimate, Warning};

/// Points summed together (and, unless the estimator asks for more per call, generated and
/// evaluated together): small enough to stay in L1/L2 cache. The summation blocks fix the
/// result's bits, so they never change with the estimator's call size.
const BLOCK: u64 = crate::estimator::DEFAULT_POINTS_PER_CALL as u64;
/// The most replicates of a run (each keeps an accumulator in memory).
pub(super) const MAX_REPLICATES: u64 = 1 << 20;
/// The most accumulators (64 bytes each) a run's fold keeps, one per output of each
/// replicate: 256 MiB, and the chunk results in flight (one accumulator per output each, a
/// chunk per replicate at least) may hold as many again.
pub(super) const MAX_ACCUMULATORS: u64 = 1 << 22;
/// Chunk results held in memory at once by a run: bounds the memory of huge runs.
pub(super) const CHUNKS_IN_MEMORY: u64 = 1 << 16;

/// The index layout of one run: which sample indices each replicate uses.
#[derive(Debug, Clone, Copy)]
pub(super) struct Plan {
    /// Points per replicate in this run.
    pub(super) samples: u64,
    /// Local index (within each replicate) of the first point of this run: later stages of
    /// a run to a tolerance continue where the earlier ones stopped.
    pub(super) offset: u64,
    pub(super) replicates: u64,
    /// Number of the first replicate of this run: a run to a tolerance may add replicates
    /// to those it has.
    pub(super) first_replicate: u64,
    /// Distance between the first indices of consecutive replicates.
    pub(super) stride: u64,
    pub(super) chunks_per_replicate: u64,
}

impl Plan {
    /// The plan of a fixed-budget run of `samples` points (default: the pass size, or `2^16`)
    /// in each of `replicates` replicates (default 1) of `sampler`.
    pub(super) fn new(
        samples: Option<u64>,
        replicates: Option<u64>,
        sampler: &dyn Sampler,
    ) -> Result<Plan> {
        let replicates = replicates.unwrap_or(1);
        if !(1..=MAX_REPLICATES).contains(&replicates) {
            return Err(Error::invalid(
                "replicates",
                replicates,
                format!("1 to {MAX_REPLICATES} (each keeps an accumulator in memory)"),
            ));
        }
        if replicates > 1 && !sampler.is_randomized() {
            return Err(Error::invalid(
                "replicates",
                replicates,
                format!(
                    "1 for the unrandomized {} sampler (its passes repeat each other; choose a \
                     scramble to get independent replicates and an error bar)",
                    sampler.name()
                ),
            ));
        }
        let passes = sampler.passes();
        let samples = samples.unwrap_or(match passes {
            PassKind::Fixed { size } => size,
            _ => DEFAULT_SAMPLES,
        });
        if samples == 0 {
            return Err(Error::invalid(
                "samples",
                0,
                "at least 1 point per replicate",
            ));
        }
        let stride = match passes {
            PassKind::Independent => samples,
            PassKind::Fixed { size } => {
                if !samples.is_multiple_of(size) {
                    let below = samples / size * size;
                    let nearest = if below == 0 {
                        format!("{size}")
                    } else {
                        format!("{below} or {}", below.saturating_add(size))
                    };
                    return Err(Error::invalid(
                        "samples",
                        samples,
                        format!(
                            "a multiple of the {} sampler's pass size {size} (nearest: {nearest})",
                            sampler.name()
                        ),
                    ));
                }
                samples
            }
            PassKind::Extensible { max } => {
                if samples > max {
                    return Err(Error::invalid(
                        "samples",
                        samples,
                        format!(
                            "at most {max} points per replicate for the {} sampler",
                            sampler.name()
                        ),
                    ));
                }
                max
            }
        };
        Plan::stage(replicates, stride, 0, samples)
    }

    /// Points `offset .. offset + samples` of each of `replicates` replicates, `stride` apart.
    pub(super) fn stage(replicates: u64, stride: u64, offset: u64, samples: u64) -> Result<Plan> {
        Plan::added(0, replicates, stride, offset, samples)
    }

    /// Points `offset .. offset + samples` of replicates `first_replicate ..
    /// first_replicate + replicates`, `stride` apart.
    pub(super) fn added(
        first_replicate: u64,
        replicates: u64,
        stride: u64,
        offset: u64,
        samples: u64,
    ) -> Result<Plan> {
        (first_replicate + replicates - 1)
            .checked_mul(stride)
            .and_then(|s| s.checked_add(offset))
            .and_then(|s| s.checked_add(samples))
            .ok_or(Error::IndexOutOfRange {
                what: "sample index of the last replicate",
                limit: u64::MAX,
            })?;
        let plan = Plan {
            samples,
            offset,
            replicates,
            first_replicate,
            stride,
            chunks_per_replicate: samples.div_ceil(CHUNK),
        };
        plan.total_chunks()?;
        Ok(plan)
    }

    pub(super) fn total_chunks(&self) -> Result<u64> {
        self.replicates
            .checked_mul(self.chunks_per_replicate)
            .ok_or(Error::IndexOutOfRange {
                what: "number of work chunks",
                limit: u64::MAX,
            })
    }

    /// Replicate number and the range of local indices (within the replicate) of a chunk.
    fn chunk_range(&self, chunk: u64) -> (u64, u64, u64) {
        let replicate = self.first_replicate + chunk / self.chunks_per_replicate;
        let first = self.offset + (chunk % self.chunks_per_replicate) * CHUNK;
        // Saturating: a replicate may end at the very last index, u64::MAX - 1.
        let end = self.offset.saturating_add(self.samples);
        (replicate, first, first.saturating_add(CHUNK).min(end))
    }

    /// Evaluates every chunk and folds the results in chunk order, telling `on_points` the
    /// points of each chunk folded, until a limit stops it: the fold, the number of chunks
    /// folded, and the limit that stopped it, if one did.
    pub(super) fn run_folded(
        &self,
        executor: &Executor,
        limits: &Limits,
        sampler: &dyn Sampler,
        estimator: &dyn VectorEstimator,
        on_points: &mut dyn FnMut(u64),
    ) -> Result<(Folded, u64, Option<StopReason>)> {
        let job = Chunks::new(self, sampler, estimator);
        let mut folded = job.folded()?;
        let mut done = 0;
        let stop = executor.run(
            &job,
            0..self.total_chunks()?,
            CHUNKS_IN_MEMORY,
            limits,
            |chunk, r| {
                folded.add(self.chunks_per_replicate, chunk, &r);
                let (_, first, end) = self.chunk_range(chunk);
                on_points(end - first);
                done += 1;
                Ok(())
            },
        )?;
        Ok((folded, done, stop))
    }

    /// The estimate of a run that a limit stopped after `done` chunks: the finished part of
    /// independent points, or the complete replicates of dependent ones (an
    /// [`Error::Interrupted`] when there is none).
    pub(super) fn estimate_stopped(
        &self,
        sampler: &dyn Sampler,
        mut folded: Folded,
        done: u64,
        policy: NonFinitePolicy,
        stop: StopReason,
    ) -> Result<VectorEstimate> {
        let spent = folded.points();
        let complete = if sampler.passes() == PassKind::Independent {
            done.div_ceil(self.chunks_per_replicate)
        } else {
            done / self.chunks_per_replicate
        };
        if complete == 0 || spent == 0 {
            return Err(Error::Interrupted {
                stop,
                evaluations: spent,
            });
        }
        folded.truncate(complete);
        let kept = Plan {
            replicates: complete,
            ..*self
        };
        kept.estimate(sampler, &folded, policy)
    }

    /// Fails with the first offending point when a contribution was not finite (under
    /// [`NonFinitePolicy::Skip`], only when a replicate has an output with no finite
    /// contribution left).
    pub(super) fn check_finite(
        &self,
        sampler: &dyn Sampler,
        folded: &Folded,
        policy: NonFinitePolicy,
    ) -> Result<()> {
        match self.non_finite(sampler, folded, policy)? {
            Some(found) if policy == NonFinitePolicy::Fail => Err(found.into_error()),
            _ => Ok(()),
        }
    }

    /// The first non-finite contribution of `folded`, if any, with its point; an error when,
    /// under [`NonFinitePolicy::Skip`], a replicate has an output with no finite contribution
    /// left.
    pub(super) fn non_finite(
        &self,
        sampler: &dyn Sampler,
        folded: &Folded,
        policy: NonFinitePolicy,
    ) -> Result<Option<engine::NonFinite>> {
        let Some(first) = folded.first_non_finite else {
            return Ok(None);
        };
        let count: u64 = folded.accumulators.iter().map(|r| r.non_finite()).sum();
        if policy == NonFinitePolicy::Skip
            && let Some(at) = folded.accumulators.iter().position(|r| r.count() == 0)
        {
            let (replicate, output) = (
                self.first_replicate + (at / folded.outputs) as u64,
                at % folded.outputs,
            );
            let what = if folded.outputs > 1 {
                format!("non-finite at every point of replicate {replicate} in output {output}")
            } else {
                format!("non-finite at every point of replicate {replicate}")
            };
            return Err(Error::invalid(
                "integrand",
                what,
                "at least one finite contribution per replicate, even when skipping",
            ));
        }
        let mut point = vec![0.0; sampler.dims()];
        sampler.point(first.replicate * self.stride + first.index, &mut point)?;
        Ok(Some(engine::NonFinite {
            count,
            replicate: first.replicate,
            index: first.index,
            output: (folded.outputs > 1).then_some(first.output),
            value: first.value,
            point,
        }))
    }

    /// The estimate from the folded chunks of a complete run: the same bits whichever
    /// threads, processes or checkpoints produced the chunks.
    pub(super) fn estimate(
        &self,
        sampler: &dyn Sampler,
        folded: &Folded,
        policy: NonFinitePolicy,
    ) -> Result<VectorEstimate> {
        self.check_finite(sampler, folded, policy)?;
        let m = folded.outputs;
        if sampler.passes() == PassKind::Independent {
            // Independent points: all samples are iid, so the per-sample (co)variance is
            // honest.
            let mut outputs = vec![Accumulator::new(); m];
            for replicate in folded.accumulators.chunks_exact(m) {
                for (all, part) in outputs.iter_mut().zip(replicate) {
                    all.merge(part);
                }
            }
            let covariance = folded.covariances.split_first().map(|(first, rest)| {
                let mut all = first.clone();
                for part in rest {
                    // Same dimension by construction.
                    let _ = all.merge(part);
                }
                all
            });
            return Ok(VectorEstimate::independent(
                &outputs,
                covariance.as_ref(),
                self.replicates,
            ));
        }
        let mut estimate = VectorEstimate::replicates(&folded.accumulators, m)?;
        if let Some(warning) = balance_warning(sampler, self.samples) {
            estimate.for_each_output(|_, output| output.warn(warning.clone()));
        }
        if self.replicates == 1 {
            let warning = Warning::NoErrorBar {
                sampler: sampler.name().to_string(),
                randomized: sampler.is_randomized(),
            };
            estimate.for_each_output(|_, output| output.warn(warning.clone()));
        }
        Ok(estimate)
    }
}

/// The warning for `samples` points per replicate of `sampler`, if they break its balance.
pub(super) fn balance_warning(sampler: &dyn Sampler, samples: u64) -> Option<Warning> {
    let base = sampler.unbalanced_by(samples)?;
    let mut below = 1u64;
    while below.checked_mul(base).is_some_and(|next| next <= samples) {
        below *= base;
    }
    Some(Warning::UnbalancedSampleSize {
        sampler: sampler.name().to_string(),
        samples,
        base,
        below,
        above: below.saturating_mul(base),
    })
}

/// Where the first non-finite contribution of a chunk occurred.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct NonFinite {
    pub(super) replicate: u64,
    pub(super) index: u64,
    /// NaN or an infinity, serialized by its bits (JSON has no form for them).
    #[cfg_attr(feature = "serde", serde(with = "f64_bits"))]
    pub(super) value: f64,
    /// The output it belongs to (0 for a scalar integrand, and then not saved).
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "is_first_output")
    )]
    pub(super) output: usize,
}

#[cfg(feature = "serde")]
fn is_first_output(output: &usize) -> bool {
    *output == 0
}

/// Serializes an `f64` as its IEEE-754 bits, so NaN and infinities survive any format.
#[cfg(feature = "serde")]
pub(super) mod f64_bits {
    pub fn serialize<S: serde::Serializer>(value: &f64, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u64(value.to_bits())
    }

    pub fn deserialize<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        let bits: u64 = serde::Deserialize::deserialize(d)?;
        Ok(f64::from_bits(bits))
    }
}

/// What one chunk of work produced: an accumulator per output, the outputs' covariance (for
/// several outputs of independent points) and the first non-finite contribution.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(
        into = "super::partial_format::SavedChunk",
        from = "super::partial_format::SavedChunk"
    )
)]
pub(super) struct ChunkResult {
    pub(super) accumulators: Vec<Accumulator>,
    pub(super) covariance: Option<CovarianceAccumulator>,
    pub(super) first_non_finite: Option<NonFinite>,
}

/// Chunk results folded in chunk order: an accumulator per output of each replicate
/// (`accumulators[r * outputs + k]`), the covariance of the outputs per replicate where it is
/// kept, and the first non-finite contribution.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct Folded {
    /// Saved under the name of the scalar form, which had one per replicate.
    #[cfg_attr(feature = "serde", serde(rename = "replicates"))]
    pub(super) accumulators: Vec<Accumulator>,
    pub(super) first_non_finite: Option<NonFinite>,
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Vec::is_empty")
    )]
    pub(super) covariances: Vec<CovarianceAccumulator>,
    #[cfg_attr(
        feature = "serde",
        serde(default = "one", skip_serializing_if = "is_one")
    )]
    pub(super) outputs: usize,
}

#[cfg(feature = "serde")]
pub(super) fn one() -> usize {
    1
}

#[cfg(feature = "serde")]
pub(super) fn is_one(n: &usize) -> bool {
    *n == 1
}

impl Folded {
    /// Empty accumulators for `replicates` replicates of `outputs` outputs, with a covariance
    /// per replicate if `covariance`.
    pub(super) fn new(replicates: u64, outputs: usize, covariance: bool) -> Result<Folded> {
        if replicates.saturating_mul(outputs as u64) > MAX_ACCUMULATORS {
            return Err(Error::invalid(
                "replicates",
                format!("{replicates} with {outputs} outputs"),
                format!(
                    "at most {MAX_ACCUMULATORS} replicates x outputs ({} replicates for {outputs} \
                     outputs): the run keeps an accumulator of each output of each replicate",
                    (MAX_ACCUMULATORS / outputs.max(1) as u64).min(MAX_REPLICATES)
                ),
            ));
        }
        let r = replicates as usize;
        let covariances = if covariance {
            vec![CovarianceAccumulator::new(outputs)?; r]
        } else {
            Vec::new()
        };
        Ok(Folded {
            accumulators: vec![Accumulator::new(); r * outputs],
            first_non_finite: None,
            covariances,
            outputs,
        })
    }

    /// Adds the result of `chunk` of a run of `chunks_per_replicate` chunks per replicate;
    /// chunks must come in index order.
    pub(super) fn add(&mut self, chunks_per_replicate: u64, chunk: u64, result: &ChunkResult) {
        let replicate = (chunk / chunks_per_replicate) as usize;
        let outputs = &mut self.accumulators[replicate * self.outputs..][..self.outputs];
        for (acc, part) in outputs.iter_mut().zip(&result.accumulators) {
            acc.merge(part);
        }
        if let (Some(all), Some(part)) = (self.covariances.get_mut(replicate), &result.covariance) {
            // Same dimension by construction.
            let _ = all.merge(part);
        }
        self.first_non_finite = self.first_non_finite.or(result.first_non_finite);
    }

    /// Merges a fold of the same shape (later points of the same replicates).
    pub(super) fn merge(&mut self, other: &Folded) {
        for (acc, part) in self.accumulators.iter_mut().zip(&other.accumulators) {
            acc.merge(part);
        }
        for (cov, part) in self.covariances.iter_mut().zip(&other.covariances) {
            // Same dimension by construction.
            let _ = cov.merge(part);
        }
        self.first_non_finite = self.first_non_finite.or(other.first_non_finite);
    }

    /// The estimate of a fold of one replicate of independent points.
    pub(super) fn independent_estimate(&self) -> VectorEstimate {
        VectorEstimate::independent(&self.accumulators, self.covariances.first(), 1)
    }

    /// Points evaluated (finite or not), from the first output's accumulators.
    pub(super) fn points(&self) -> u64 {
        self.accumulators
            .iter()
            .step_by(self.outputs)
            .map(|r| r.count() + r.non_finite())
            .sum()
    }

    /// Appends the replicates of `added` (a fold of new replicates of the same outputs).
    pub(super) fn append(&mut self, added: &Folded) {
        self.accumulators.extend_from_slice(&added.accumulators);
        self.covariances.extend_from_slice(&added.covariances);
        self.first_non_finite = self.first_non_finite.or(added.first_non_finite);
    }

    /// Keeps the first `replicates` replicates.
    fn truncate(&mut self, replicates: u64) {
        self.accumulators
            .truncate(replicates as usize * self.outputs);
        if !self.covariances.is_empty() {
            self.covariances.truncate(replicates as usize);
        }
    }
}

/// Whether a run of `outputs` outputs with `sampler` keeps the outputs' covariance per
/// replicate: several outputs of independent points (with dependent points it comes from the
/// replicate means).
pub(super) fn keeps_covariance(outputs: usize, sampler: &dyn Sampler) -> bool {
    outputs > 1 && sampler.passes() == PassKind::Independent
}

/// The chunks of one plan, as work for the [`Executor`].
pub(super) struct Chunks<'a> {
    plan: &'a Plan,
    sampler: &'a dyn Sampler,
    estimator: &'a dyn VectorEstimator,
    /// Whether to keep the outputs' covariance (several outputs of independent points; with
    /// dependent points it comes from the replicate means).
    covariance: bool,
}

impl<'a> Chunks<'a> {
    pub(super) fn new(
        plan: &'a Plan,
        sampler: &'a dyn Sampler,
        estimator: &'a dyn VectorEstimator,
    ) -> Self {
        let covariance = keeps_covariance(estimator.outputs(), sampler);
        Chunks {
            plan,
            sampler,
            estimator,
            covariance,
        }
    }

    /// An empty fold of this plan's chunks.
    pub(super) fn folded(&self) -> Result<Folded> {
        Folded::new(
            self.plan.replicates,
            self.estimator.outputs(),
            self.covariance,
        )
    }
}

/// Per-thread buffers, allocated once.
pub(super) struct Workspace {
    points: Points,
    values: Vec<f64>,
    /// One summation block of every output, when a call holds several (for the covariance).
    block: Vec<f64>,
}

impl Chunks<'_> {
    /// Points per call of the estimator: as many whole summation blocks as fit in what it
    /// asks for, at least one, and no more than a chunk holds.
    fn call(&self) -> u64 {
        let asked = self.estimator.points_per_call() as u64;
        ((asked / BLOCK).max(1) * BLOCK).min(CHUNK.max(BLOCK))
    }
}

impl ChunkJob for Chunks<'_> {
    type Scratch = Workspace;
    type Output = ChunkResult;

    fn scratch(&self) -> Result<Workspace> {
        let call = self.call() as usize;
        let m = self.estimator.outputs();
        Ok(Workspace {
            points: Points::new(self.sampler.dims(), call)?,
            values: vec![0.0; call * m],
            block: if call > BLOCK as usize && self.covariance {
                vec![0.0; BLOCK as usize * m]
            } else {
                Vec::new()
            },
        })
    }

    /// A fixed pass is built whole on first use: a thread claims the chunks of about one pass
    /// (one replicate at most), so that threads build different passes at once.
    fn claim(&self) -> u64 {
        match self.sampler.passes() {
            PassKind::Fixed { size } => size.div_ceil(CHUNK).min(self.plan.chunks_per_replicate),
            _ => 1,
        }
    }

    fn run(
        &self,
        work: &mut Workspace,
        chunk: u64,
        limits: &Limits,
    ) -> Result<Option<ChunkResult>> {
        let (replicate, first, end) = self.plan.chunk_range(chunk);
        let base = replicate * self.plan.stride;
        let m = self.estimator.outputs();
        let mut accumulators = vec![Accumulator::new(); m];
        let mut covariance = (self.covariance)
            .then(|| CovarianceAccumulator::new(m))
            .transpose()?;
        let mut first_non_finite = None;
        let call = self.call();
        let mut start = first;
        while start < end {
            if start > first && limits.reached().is_some() {
                return Ok(None);
            }
            let len = (end - start).min(call) as usize;
            work.points.set_len(len);
            self.sampler.fill(base + start, &mut work.points)?;
            let values = &mut work.values[..len * m];
            self.estimator.contributions(&work.points, values);
            // Summed BLOCK at a time from the chunk's start, whatever the call size.
            for offset in (0..len).step_by(BLOCK as usize) {
                let n = (len - offset).min(BLOCK as usize);
                let column = |k: usize| &values[k * len + offset..k * len + offset + n];
                let mut finite = true;
                for (k, acc) in accumulators.iter_mut().enumerate() {
                    let before = acc.non_finite();
                    acc.extend(column(k));
                    finite &= acc.non_finite() == before;
                }
                if let Some(cov) = covariance.as_mut() {
                    if n == len {
                        cov.extend_columns(values, len);
                    } else {
                        let block = &mut work.block[..n * m];
                        for (k, part) in block.chunks_exact_mut(n).enumerate() {
                            part.copy_from_slice(column(k));
                        }
                        cov.extend_columns(block, n);
                    }
                }
                if !finite && first_non_finite.is_none() {
                    first_non_finite = (0..n)
                        .flat_map(|i| (0..m).map(move |k| (i, k)))
                        .find(|&(i, k)| !column(k)[i].is_finite())
                        .map(|(i, k)| NonFinite {
                            replicate,
                            index: start + (offset + i) as u64,
                            value: column(k)[i],
                            output: k,
                        });
                }
            }
            start += len as u64;
        }
        Ok(Some(ChunkResult {
            accumulators,
            covariance,
            first_non_finite,
        }))
    }

    fn origin(&self, chunk: u64) -> (u64, u64) {
        let (replicate, first, _) = self.plan.chunk_range(chunk);
        (replicate, first)
    }
}
