//! [`LevelSums`] and [`LevelJob`]: samples of one level drawn on the engine's executor.

use super::Level;
use crate::Points;
use crate::engine::{ChunkJob, Executor, Limits};
use crate::error::{Error, Result};
use crate::sampler::Sampler;
use crate::stats::{Accumulator, StopReason};

/// What samples of one level sum to: `Y = P_l - P_{l-1}` and `P_l`, with the third and
/// fourth power sums of `Y` (for the kurtosis of Giles' test).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct LevelSums {
    pub(super) difference: Accumulator,
    pub(super) fine: Accumulator,
    pub(super) cube: f64,
    pub(super) fourth: f64,
}

impl LevelSums {
    /// The sums of a block of samples `(fine[i], coarse[i])`; `coarse` is overwritten with
    /// the differences `Y`. Whole slices go to the accumulators: two vectorized passes, where
    /// a Welford update per sample weighed on the first levels, whose samples take a step or
    /// two.
    pub(super) fn of_block(fine: &[f64], coarse: &mut [f64]) -> LevelSums {
        for (y, &fine) in coarse.iter_mut().zip(fine) {
            *y = fine - *y;
        }
        let mut sums = LevelSums::default();
        sums.difference.extend(coarse);
        sums.fine.extend(fine);
        for &y in coarse.iter() {
            let square = y * y;
            sums.cube += square * y;
            sums.fourth += square * square;
        }
        sums
    }

    pub(super) fn merge(&mut self, other: &LevelSums) {
        self.difference.merge(&other.difference);
        self.fine.merge(&other.fine);
        self.cube += other.cube;
        self.fourth += other.fourth;
    }

    pub(super) fn count(&self) -> u64 {
        self.difference.count()
    }

    /// The kurtosis of `Y`, from its power sums (Giles' `mlmc_test`); `None` without variance,
    /// or when the fourth powers leave f64's normal range (values above about `1e77`, or so
    /// small that the squared variance is subnormal, below about `1e-77`, where its rounding
    /// would be reported as a kurtosis).
    pub(super) fn kurtosis(&self) -> Option<f64> {
        let n = self.count() as f64;
        let m1 = self.difference.mean();
        let m2 = self.difference.m2() / n + m1 * m1;
        let (m3, m4) = (self.cube / n, self.fourth / n);
        let central4 = m4 - 4.0 * m3 * m1 + 6.0 * m2 * m1 * m1 - 3.0 * m1.powi(4);
        let variance = m2 - m1 * m1;
        let squared = variance * variance;
        Some(central4 / squared).filter(|k| variance > 0.0 && squared.is_normal() && k.is_finite())
    }
}

/// Samples `first .. first + count` of each of `replicates` passes of a level's sampler,
/// `chunk` samples per chunk of work.
/// A thread's buffers for a chunk of samples: its canonical points, their fine and coarse
/// values, and the model's scratch space.
pub(super) struct Block {
    points: Points,
    fine: Vec<f64>,
    coarse: Vec<f64>,
    scratch: Vec<f64>,
}

pub(super) struct LevelJob<'a, L> {
    pub(super) model: &'a L,
    pub(super) level: usize,
    pub(super) sampler: &'a dyn Sampler,
    pub(super) first: u64,
    pub(super) count: u64,
    pub(super) replicates: u64,
    /// The sampler index of the first point of pass `r` is `r * stride`.
    pub(super) stride: u64,
    pub(super) chunk: u64,
}

/// Values of canonical points one chunk holds, at most: bounds a chunk's memory.
const CHUNK_VALUES: u64 = 1 << 18;
/// Units of cost one chunk aims at: enough work to amortize its start.
const CHUNK_COST: f64 = 65_536.0;

/// Samples per chunk for a level of `dims` coordinates and `cost` per sample: fixed by the
/// level alone, so chunks (and every sum) are the same for any thread count.
pub(super) fn chunk_size(dims: usize, cost: f64) -> u64 {
    let by_cost = if cost >= 1.0 {
        (CHUNK_COST / cost) as u64
    } else {
        CHUNK_COST as u64
    };
    by_cost
        .min(CHUNK_VALUES / dims.max(1) as u64)
        .clamp(1, 4096)
}

impl<L> LevelJob<'_, L> {
    fn chunks_per_replicate(&self) -> u64 {
        self.count.div_ceil(self.chunk)
    }

    /// The chunks of the job.
    pub(super) fn chunks(&self) -> u64 {
        self.chunks_per_replicate() * self.replicates
    }

    /// The replicate of chunk `chunk`.
    pub(super) fn replicate(&self, chunk: u64) -> u64 {
        chunk / self.chunks_per_replicate()
    }

    /// The first sample of `chunk` in its replicate, and how many it holds.
    fn span(&self, chunk: u64) -> (u64, u64) {
        let start = self.first + (chunk % self.chunks_per_replicate()) * self.chunk;
        (start, self.chunk.min(self.first + self.count - start))
    }
}

impl<L: Level> ChunkJob for LevelJob<'_, L> {
    type Scratch = Block;
    type Output = LevelSums;

    fn scratch(&self) -> Result<Block> {
        let dims = self.sampler.dims();
        let len = usize::try_from(self.chunk).unwrap_or(usize::MAX);
        Ok(Block {
            points: Points::new(dims, len)?,
            fine: vec![0.0; len],
            coarse: vec![0.0; len],
            scratch: Vec::new(),
        })
    }

    fn run(&self, block: &mut Block, chunk: u64, _: &Limits) -> Result<Option<LevelSums>> {
        let (start, len) = self.span(chunk);
        let replicate = self.replicate(chunk);
        let len = len as usize;
        block.points.set_len(len);
        self.sampler
            .fill(replicate * self.stride + start, &mut block.points)?;
        let (fine, coarse) = (&mut block.fine[..len], &mut block.coarse[..len]);
        self.model
            .sample_block(self.level, &block.points, fine, coarse, &mut block.scratch);
        for (i, (&fine, &coarse)) in fine.iter().zip(coarse.iter()).enumerate() {
            if !(fine.is_finite() && coarse.is_finite()) {
                let mut u = vec![0.0; block.points.dims()];
                block.points.copy_point(i, &mut u);
                return Err(Error::invalid(
                    "level sample",
                    format!(
                        "(P_l, P_l-1) = ({fine}, {coarse}) at sample {} of replicate {replicate} \
                         of level {}, canonical point {}",
                        start + i as u64,
                        self.level,
                        leading_coordinates(&u)
                    ),
                    "finite values of the fine and coarse approximations",
                ));
            }
        }
        Ok(Some(LevelSums::of_block(fine, coarse)))
    }

    fn origin(&self, chunk: u64) -> (u64, u64) {
        (self.replicate(chunk), self.span(chunk).0)
    }
}

/// The first coordinates of a point, for a message: a deep level's point has millions.
fn leading_coordinates(u: &[f64]) -> String {
    const SHOWN: usize = 8;
    if u.len() <= SHOWN {
        format!("{u:?}")
    } else {
        let head = format!("{:?}", &u[..SHOWN]);
        format!(
            "{}, ... ({} coordinates)]",
            &head[..head.len() - 1],
            u.len()
        )
    }
}

/// A level's extension under way, cut short by a limit: the sums of its first `chunks`
/// chunks, per replicate, folded as an uninterrupted extension folds them.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct Extension {
    pub(super) level: usize,
    pub(super) sums: Vec<LevelSums>,
    pub(super) chunks: u64,
}

impl<L> LevelJob<'_, L> {
    /// The samples (over every replicate) in `chunks`.
    pub(super) fn samples_in(&self, chunks: std::ops::Range<u64>) -> u64 {
        chunks.map(|c| self.span(c).1).sum()
    }
}

/// Runs the chunks of `job` from `from` (the chunks an interrupted extension folded, or none),
/// folding them into one sum per replicate in chunk order; returns the sums, the chunks
/// folded in all, and the limit that cut the job short, if one did.
pub(super) fn run_job<L: Level>(
    executor: &Executor,
    job: &LevelJob<'_, L>,
    limits: &Limits,
    from: Option<(Vec<LevelSums>, u64)>,
) -> Result<(Vec<LevelSums>, u64, Option<StopReason>)> {
    let (mut sums, start) =
        from.unwrap_or_else(|| (vec![LevelSums::default(); job.replicates as usize], 0));
    let mut done = start;
    let stop = executor.run(job, start..job.chunks(), 64, limits, |chunk, out| {
        sums[job.replicate(chunk) as usize].merge(&out);
        done = chunk + 1;
        Ok(())
    })?;
    Ok((sums, done, stop))
}
