//! How the iterations of a VEGAS run to a tolerance grow.
//!
//! A grid of `n_inc` increments trained on `N` points per iteration sees about `N / n_inc`
//! points per increment, and its noise sets a floor under the variance per evaluation: on the
//! 4-D Genz Gaussian that floor at `N = 10^4` was 3 to 6 times the one at `4 x 10^4`
//! (docs/measurements.md). And iterations too small for a sharp peak or an edge miss it in
//! most iterations and hit it in a few: their variances are then too small in most, and the
//! iterations disagree. Python's `vegas` leaves the iteration size to its user; here a run to
//! a tolerance doubles it
//!
//! * when its iterations disagree (`Q` below [`DISAGREEMENT_Q`](crate::stats::DISAGREEMENT_Q),
//!   or a first iteration against the warm-up): the iterations so far are set aside as
//!   warm-up, since their variances cannot be trusted, at most [`DISAGREEMENT_GROWTHS`]
//!   times; a run that still disagrees after that stops and says so;
//! * when the grid has settled at this size (its variance per evaluation no longer halves
//!   over [`SETTLING`] iterations) and the tolerance still needs more than
//!   [`ITERATIONS_PER_SIZE`] iterations like the last: the iterations so far stay in the
//!   combination, and the next one's weight allows for its size.
//!
//! A run grows only with room for [`ROOM`] more iterations of the grown size, under its
//! evaluation limit and its most iterations. Fixed-budget runs never grow: their size is the
//! user's.

/// Each growth doubles the evaluations per iteration.
pub(super) const GROWTH: u64 = 2;
/// Growths on disagreement before a run that still disagrees stops.
pub(super) const DISAGREEMENT_GROWTHS: u32 = 4;
/// Iterations over which a settled grid's variance per evaluation falls by less than
/// [`SETTLED_FALL`] of itself.
const SETTLING: usize = 4;
const SETTLED_FALL: f64 = 0.5;
/// A run grows when the tolerance needs more than this many iterations of the current size.
const ITERATIONS_PER_SIZE: f64 = 32.0;
/// Iterations of the grown size that must fit under the limits.
const ROOM: u64 = 8;

/// What the run does after an iteration that did not meet its tolerance.
#[derive(Debug, PartialEq)]
pub(super) enum Step {
    Continue,
    /// Double the iterations, setting the earlier ones aside (`restart`) or keeping them.
    Grow {
        restart: bool,
    },
    /// The iterations still disagree after every growth they were allowed.
    GiveUp,
}

/// The size of a run's iterations and what decides its growth.
pub(super) struct Growth {
    /// Evaluations per iteration.
    pub(super) size: u64,
    /// The most it may grow to (the sampler's pass, the chunk plan).
    largest: u64,
    disagreement_growths: u32,
    /// The variance per evaluation of each combined iteration since the last growth.
    per_evaluation: Vec<f64>,
}

impl Growth {
    pub(super) fn new(size: u64, largest: u64) -> Growth {
        Growth {
            size,
            largest,
            disagreement_growths: 0,
            per_evaluation: Vec::new(),
        }
    }

    /// Notes a combined iteration's variance per evaluation.
    pub(super) fn record(&mut self, per_evaluation: f64) {
        self.per_evaluation.push(per_evaluation);
    }

    /// The step after an iteration whose combination did not meet the tolerance: `disagree`
    /// when its iterations disagree, `needed` the iterations like the last one that the
    /// tolerance still needs, `left` the evaluations and `iterations_left` the iterations left
    /// under the limits.
    pub(super) fn step(
        &mut self,
        disagree: bool,
        needed: f64,
        left: u64,
        iterations_left: u64,
    ) -> Step {
        let grown = self.size.saturating_mul(GROWTH);
        let fits =
            grown <= self.largest && grown.saturating_mul(ROOM) <= left && iterations_left >= ROOM;
        if disagree {
            if self.disagreement_growths == DISAGREEMENT_GROWTHS {
                return Step::GiveUp;
            }
            if fits {
                self.disagreement_growths += 1;
                return self.grow(true);
            }
            return Step::Continue;
        }
        if fits && self.settled() && needed > ITERATIONS_PER_SIZE {
            return self.grow(false);
        }
        Step::Continue
    }

    fn grow(&mut self, restart: bool) -> Step {
        self.size *= GROWTH;
        self.per_evaluation.clear();
        Step::Grow { restart }
    }

    /// Whether the variance per evaluation no longer halves over [`SETTLING`] iterations
    /// (each end the smaller of two iterations, against a lone high one).
    fn settled(&self) -> bool {
        let h = &self.per_evaluation;
        let n = h.len();
        if n < SETTLING + 2 {
            return false;
        }
        let low = |i: usize| h[i].min(h[i + 1]);
        low(n - 2) > SETTLED_FALL * low(n - 2 - SETTLING)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fed(values: &[f64]) -> Growth {
        let mut g = Growth::new(10_000, 1 << 30);
        for &v in values {
            g.record(v);
        }
        g
    }

    #[test]
    fn a_grid_still_adapting_does_not_grow() {
        // Falling by a quarter per iteration, as on the 4-D Gaussian's first 30 iterations.
        let falling: Vec<f64> = (0..10).map(|i| 0.75f64.powi(i)).collect();
        assert_eq!(
            fed(&falling).step(false, 1e6, u64::MAX, u64::MAX),
            Step::Continue
        );
        // Flat: settled; grows only when many iterations are still needed.
        let flat = [1.0, 1.1, 0.9, 1.2, 1.0, 0.95];
        assert_eq!(
            fed(&flat).step(false, 20.0, u64::MAX, u64::MAX),
            Step::Continue
        );
        let mut g = fed(&flat);
        assert_eq!(
            g.step(false, 1e3, u64::MAX, u64::MAX),
            Step::Grow { restart: false }
        );
        assert_eq!(g.size, 20_000);
        // The history starts again at the new size.
        assert_eq!(g.step(false, 1e3, u64::MAX, u64::MAX), Step::Continue);
    }

    #[test]
    fn growth_must_fit_the_limit_and_the_largest_size() {
        let flat = [1.0; 6];
        // 8 iterations of 20_000 need 160_000 evaluations left.
        assert_eq!(
            fed(&flat).step(false, 1e3, 159_999, u64::MAX),
            Step::Continue
        );
        assert_eq!(
            fed(&flat).step(false, 1e3, 160_000, u64::MAX),
            Step::Grow { restart: false }
        );
        let mut capped = Growth::new(10_000, 19_999);
        for v in flat {
            capped.record(v);
        }
        assert_eq!(capped.step(false, 1e3, u64::MAX, u64::MAX), Step::Continue);
    }

    #[test]
    fn disagreement_restarts_a_bounded_number_of_times() {
        let mut g = Growth::new(10_000, 1 << 30);
        for _ in 0..DISAGREEMENT_GROWTHS {
            assert_eq!(
                g.step(true, 1.0, u64::MAX, u64::MAX),
                Step::Grow { restart: true }
            );
        }
        assert_eq!(g.size, 160_000);
        assert_eq!(g.step(true, 1.0, u64::MAX, u64::MAX), Step::GiveUp);
        // Without room to grow, a disagreeing run goes on (its limits bound it).
        let mut tight = Growth::new(10_000, 1 << 30);
        assert_eq!(tight.step(true, 1.0, 100_000, u64::MAX), Step::Continue);
        assert_eq!(tight.step(true, 1.0, u64::MAX, 7), Step::Continue);
    }
}
