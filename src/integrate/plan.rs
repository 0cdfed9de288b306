//! [`Plan`]: which sample indices each replicate of an [`Integrator`](super::Integrator) run
//! uses, cut into fixed chunks that the [`Executor`] evaluates and folds in chunk order.

use super::{CHUNK, DEFAULT_SAMPLES, NonFinitePolicy};
use crate::engine::{ChunkJob, Executor, Limits, require_randomized};
use crate::estimator::Estimator;
use crate::sampler::{PassKind, Sampler};
use crate::stats::{Accumulator, Estimate, StopReason, Warning};
use crate::{Error, Points, Result};

/// Points generated and evaluated together: small enough to stay in L1/L2 cache.
const BLOCK: u64 = 1024;
/// The most replicates of a run (each keeps an accumulator in memory).
const MAX_REPLICATES: u64 = 1 << 20;
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
        if replicates > 1 {
            require_randomized(
                sampler,
                "independent replicates, whose spread is the error bar, need a randomized \
                 sampler: the passes of an unrandomized one repeat each other",
            )
            .map_err(|_| {
                Error::invalid(
                    "replicates",
                    replicates,
                    format!(
                        "1 for the unrandomized {} sampler (its passes repeat each other; \
                         choose a scramble to get independent replicates and an error bar)",
                        sampler.name()
                    ),
                )
            })?;
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
        (replicates - 1)
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
        let replicate = chunk / self.chunks_per_replicate;
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
        estimator: &dyn Estimator,
        on_points: &mut dyn FnMut(u64),
    ) -> Result<(Folded, u64, Option<StopReason>)> {
        let job = Chunks {
            plan: self,
            sampler,
            estimator,
        };
        let mut folded = Folded::new(self.replicates);
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
    /// [`Error::Interrupted`] when there is none), with the reason and a warning.
    pub(super) fn estimate_stopped(
        &self,
        sampler: &dyn Sampler,
        mut folded: Folded,
        done: u64,
        policy: NonFinitePolicy,
        stop: StopReason,
    ) -> Result<Estimate> {
        let spent: u64 = folded
            .replicates
            .iter()
            .map(|r| r.count() + r.non_finite())
            .sum();
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
        folded.replicates.truncate(complete as usize);
        let kept = Plan {
            replicates: complete,
            ..*self
        };
        let mut estimate = kept.estimate(sampler, &folded, policy)?;
        estimate.stop = stop;
        estimate.warn(Warning::StoppedEarly {
            stop,
            done: estimate.evaluations,
            planned: self.samples.saturating_mul(self.replicates),
        });
        Ok(estimate)
    }

    /// Fails with the first offending point when a contribution was not finite (under
    /// [`NonFinitePolicy::Skip`], only when a replicate has no finite contribution left).
    pub(super) fn check_finite(
        &self,
        sampler: &dyn Sampler,
        folded: &Folded,
        policy: NonFinitePolicy,
    ) -> Result<()> {
        let reps = &folded.replicates;
        let count: u64 = reps.iter().map(|r| r.non_finite()).sum();
        let Some(first) = folded.first_non_finite else {
            return Ok(());
        };
        if policy == NonFinitePolicy::Skip {
            return match reps.iter().position(|r| r.count() == 0) {
                None => Ok(()),
                Some(replicate) => Err(Error::invalid(
                    "integrand",
                    format!("non-finite at every point of replicate {replicate}"),
                    "at least one finite contribution per replicate, even when skipping",
                )),
            };
        }
        let mut point = vec![0.0; sampler.dims()];
        sampler.point(first.replicate * self.stride + first.index, &mut point)?;
        Err(Error::NonFiniteContribution {
            count,
            first_index: first.index,
            first_replicate: first.replicate,
            first_value: first.value,
            first_point: point,
        })
    }

    /// The estimate from the folded chunks of a complete run: the same bits whichever
    /// threads, processes or checkpoints produced the chunks.
    pub(super) fn estimate(
        &self,
        sampler: &dyn Sampler,
        folded: &Folded,
        policy: NonFinitePolicy,
    ) -> Result<Estimate> {
        self.check_finite(sampler, folded, policy)?;
        let reps = &folded.replicates;
        if sampler.passes() == PassKind::Independent {
            // Independent points: all samples are iid, so the per-sample variance is honest.
            let mut all = Accumulator::new();
            for r in reps {
                all.merge(r);
            }
            let mut estimate = all.estimate();
            estimate.replicates = self.replicates;
            return Ok(estimate);
        }
        let mut estimate = Estimate::from_replicate_accumulators(reps)?;
        if let Some(warning) = balance_warning(sampler, self.samples) {
            estimate.warn(warning);
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
}

/// Serializes an `f64` as its IEEE-754 bits, so NaN and infinities survive any format.
#[cfg(feature = "serde")]
mod f64_bits {
    pub fn serialize<S: serde::Serializer>(value: &f64, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u64(value.to_bits())
    }

    pub fn deserialize<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        let bits: u64 = serde::Deserialize::deserialize(d)?;
        Ok(f64::from_bits(bits))
    }
}

/// What one chunk of work produced.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct ChunkResult {
    pub(super) accumulator: Accumulator,
    pub(super) first_non_finite: Option<NonFinite>,
}

/// Chunk results folded in chunk order: one accumulator per replicate, and the first
/// non-finite contribution.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct Folded {
    pub(super) replicates: Vec<Accumulator>,
    pub(super) first_non_finite: Option<NonFinite>,
}

impl Folded {
    pub(super) fn new(replicates: u64) -> Folded {
        Folded {
            replicates: vec![Accumulator::new(); replicates as usize],
            first_non_finite: None,
        }
    }

    /// Adds the result of `chunk` of a run of `chunks_per_replicate` chunks per replicate;
    /// chunks must come in index order.
    pub(super) fn add(&mut self, chunks_per_replicate: u64, chunk: u64, result: &ChunkResult) {
        let replicate = (chunk / chunks_per_replicate) as usize;
        self.replicates[replicate].merge(&result.accumulator);
        if self.first_non_finite.is_none() {
            self.first_non_finite = result.first_non_finite;
        }
    }
}

/// The chunks of one plan, as work for the [`Executor`].
pub(super) struct Chunks<'a> {
    pub(super) plan: &'a Plan,
    pub(super) sampler: &'a dyn Sampler,
    pub(super) estimator: &'a dyn Estimator,
}

/// Per-thread buffers, allocated once.
pub(super) struct Workspace {
    points: Points,
    values: Vec<f64>,
}

impl ChunkJob for Chunks<'_> {
    type Scratch = Workspace;
    type Output = ChunkResult;

    fn scratch(&self) -> Result<Workspace> {
        Ok(Workspace {
            points: Points::new(self.sampler.dims(), BLOCK as usize)?,
            values: vec![0.0; BLOCK as usize],
        })
    }

    fn run(&self, work: &mut Workspace, chunk: u64) -> Result<ChunkResult> {
        let (replicate, first, end) = self.plan.chunk_range(chunk);
        let base = replicate * self.plan.stride;
        let mut accumulator = Accumulator::new();
        let mut first_non_finite = None;
        let mut start = first;
        while start < end {
            let len = (end - start).min(BLOCK) as usize;
            work.points.set_len(len);
            self.sampler.fill(base + start, &mut work.points)?;
            let values = &mut work.values[..len];
            self.estimator.contributions(&work.points, values);
            let before = accumulator.non_finite();
            accumulator.extend(values);
            if accumulator.non_finite() > before && first_non_finite.is_none() {
                first_non_finite =
                    values
                        .iter()
                        .position(|y| !y.is_finite())
                        .map(|offset| NonFinite {
                            replicate,
                            index: start + offset as u64,
                            value: values[offset],
                        });
            }
            start += len as u64;
        }
        Ok(ChunkResult {
            accumulator,
            first_non_finite,
        })
    }

    fn origin(&self, chunk: u64) -> (u64, u64) {
        let (replicate, first, _) = self.plan.chunk_range(chunk);
        (replicate, first)
    }
}
