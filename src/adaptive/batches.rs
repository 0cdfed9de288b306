//! [`Batches`]: batches of uniform points for adaptive methods that sample many sub-boxes separately.
//!
//! An adaptive method draws its points in batches (one per exploration, leaf or stratum) whose
//! sizes depend on what it has learned. Every batch must be independent of every other and
//! a pure function of where it sits in the method's plan, so that results do not depend on
//! the thread count. Batches are therefore numbered by *slots*: a batch of `n` points that
//! starts at slot `s` owns slots `s .. s + n`, and batches with disjoint slots never share a
//! point.
//!
//! * For independent points a slot is one sample index.
//! * For an extensible sampler (a randomized quasi-Monte Carlo sequence) a slot is one whole
//!   pass: a batch takes the first `n` points of the pass at its first slot (spilling into the
//!   following passes only when `n` exceeds the pass size), so each batch is a low-discrepancy
//!   set of its own under an independent randomization, and a power-of-two batch of a Sobol'
//!   sequence is a net.
//!
//! Samplers with fixed-size passes (jittered, Latin hypercube, ...) are refused: a batch of
//! arbitrary size would be a partial pass, which is not uniformly distributed for every
//! construction.

use crate::engine::{require_randomized, require_uniform_points};
use crate::error::{Error, Result};
use crate::points::Points;
use crate::sampler::{PassKind, Sampler};

/// Points generated and evaluated together.
pub(in crate::adaptive) const BLOCK: usize = 256;

/// Per-thread buffers of a method that draws batches: a block of canonical points, one point
/// in canonical and in domain coordinates, and the buffers of an integrand evaluated by blocks.
pub(in crate::adaptive) struct Workspace {
    pub(in crate::adaptive) points: Points,
    pub(in crate::adaptive) unit: Vec<f64>,
    pub(in crate::adaptive) x: Vec<f64>,
    pub(in crate::adaptive) block: BlockBuffers,
}

/// A block's points in canonical and in domain coordinates and its values, for an integrand
/// evaluated by blocks (empty until one is).
pub(in crate::adaptive) struct BlockBuffers {
    pub(in crate::adaptive) units: Points,
    pub(in crate::adaptive) xs: Points,
    pub(in crate::adaptive) values: Vec<f64>,
}

impl Workspace {
    /// The buffers for blocks of up to `block` points of `dims` coordinates.
    pub(in crate::adaptive) fn new(dims: usize, block: usize) -> Result<Workspace> {
        Ok(Workspace {
            points: Points::new(dims, block)?,
            unit: vec![0.0; dims],
            x: vec![0.0; dims],
            block: BlockBuffers {
                units: Points::new(dims, 0)?,
                xs: Points::new(dims, 0)?,
                values: Vec::new(),
            },
        })
    }
}

/// The source of every batch of one run.
pub(in crate::adaptive) struct Batches<'a> {
    sampler: &'a dyn Sampler,
    /// Points per slot: 1 for independent points, the pass size for an extensible sampler.
    slot_size: u64,
}

impl<'a> Batches<'a> {
    /// Checks that `sampler` can feed `method` (named in messages) over `domain`.
    pub(in crate::adaptive) fn new(sampler: &'a dyn Sampler, method: &str) -> Result<Self> {
        require_uniform_points(
            sampler,
            &format!("{method}, which draws batches of any size"),
        )?;
        require_randomized(
            sampler,
            &format!(
                "{method} needs independent batches, and an unscrambled sequence repeats the same points in every batch"
            ),
        )?;
        let slot_size = match sampler.passes() {
            PassKind::Extensible { max } => max,
            _ => 1,
        };
        if slot_size == 0 {
            return Err(Error::invalid(
                "sampler pass size",
                0,
                "at least 1 point per pass",
            ));
        }
        Ok(Batches { sampler, slot_size })
    }

    /// Number of slots the sampler holds.
    pub(in crate::adaptive) fn slots(&self) -> u64 {
        u64::MAX / self.slot_size
    }

    /// Fills `points` with points `first ..` of the batch at `slot`, at most `max_len` of them,
    /// stopping early at a pass boundary; returns how many were written.
    pub(in crate::adaptive) fn fill(
        &self,
        slot: u64,
        first: u64,
        max_len: usize,
        points: &mut Points,
    ) -> Result<usize> {
        let overflow = || Error::IndexOutOfRange {
            what: "sample index of a batch",
            limit: u64::MAX,
        };
        let (index, len) = if self.slot_size == 1 {
            (slot.checked_add(first).ok_or_else(overflow)?, max_len)
        } else {
            let pass = slot
                .checked_add(first / self.slot_size)
                .ok_or_else(overflow)?;
            let within = first % self.slot_size;
            let room = usize::try_from(self.slot_size - within).unwrap_or(usize::MAX);
            let index = pass
                .checked_mul(self.slot_size)
                .and_then(|start| start.checked_add(within))
                .ok_or_else(overflow)?;
            (index, max_len.min(room))
        };
        points.set_len(len);
        self.sampler.fill(index, points)?;
        Ok(len)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampler::{Independent, Jittered, Pmj02, Scramble, Sobol};

    fn point(sampler: &dyn Sampler, index: u64) -> Vec<f64> {
        let mut p = vec![0.0; sampler.dims()];
        sampler.point(index, &mut p).unwrap();
        p
    }

    fn rows(points: &Points) -> Vec<Vec<f64>> {
        (0..points.len())
            .map(|i| (0..points.dims()).map(|d| points.get(i, d)).collect())
            .collect()
    }

    #[test]
    fn independent_slots_are_sample_indices() {
        let sampler = Independent::new(2, 3).unwrap();
        let batches = Batches::new(&sampler, "test").unwrap();
        assert_eq!(batches.slots(), u64::MAX);
        let mut points = Points::new(2, 8).unwrap();
        assert_eq!(batches.fill(10, 3, 5, &mut points).unwrap(), 5);
        let want: Vec<Vec<f64>> = (13..18).map(|i| point(&sampler, i)).collect();
        assert_eq!(rows(&points), want);
    }

    #[test]
    fn extensible_slots_are_passes_and_batches_spill_into_the_next_pass() {
        // Passes of 4 points: point 6 of the batch at slot 7 is point 2 of pass 8, and the
        // block stops at the end of that pass.
        let sampler = Pmj02::with_max_points(2, 2, 1).unwrap();
        let batches = Batches::new(&sampler, "test").unwrap();
        assert_eq!(batches.slots(), u64::MAX / 4);
        let mut points = Points::new(2, 8).unwrap();
        assert_eq!(batches.fill(7, 6, 10, &mut points).unwrap(), 2);
        assert_eq!(
            rows(&points),
            vec![point(&sampler, 34), point(&sampler, 35)]
        );
        assert_eq!(batches.fill(7, 0, 10, &mut points).unwrap(), 4);
        assert_eq!(rows(&points)[0], point(&sampler, 28));
    }

    #[test]
    fn fixed_passes_and_unscrambled_sequences_are_refused() {
        let jittered = Jittered::new(2, 2, 0).unwrap();
        let plain = Sobol::new(2, Scramble::None, 0).unwrap();
        for sampler in [&jittered as &dyn Sampler, &plain] {
            assert!(Batches::new(sampler, "test").is_err(), "{}", sampler.name());
        }
    }
}
