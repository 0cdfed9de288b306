//! Weighting functions of multiple importance sampling, and the checked weighted term that both
//! MIS estimators use.
//!
//! Veach's MIS estimators (Veach & Guibas 1995; Veach 1997, chapter 9) are unbiased for *any*
//! weighting functions `w_i(x)` that sum to one over the techniques wherever the integrand is
//! non-zero (and vanish where `p_i(x) = 0`). [`MisWeighting`] is that general interface: the
//! built-in [`MisHeuristic`](super::MisHeuristic)s implement it, and so does any closure
//! `Fn(technique, x, densities) -> f64`. A user's weighting is checked at every sample: weights
//! that do not sum to one within `1e-9` over the techniques whose density is positive at the
//! sample make the contribution NaN, so the
//! [`Integrator`](crate::Integrator) fails with
//! [`Error::NonFiniteContribution`](crate::Error::NonFiniteContribution), which gives the count of
//! affected contributions and the first offending canonical point, instead of averaging a
//! biased estimate.

use crate::error::Result;

/// How far the weights at a point may sum from one before the contribution is rejected.
pub(crate) const WEIGHT_SUM_TOLERANCE: f64 = 1e-9;

/// A weighting function of multiple importance sampling: `w_i(x)` from the point `x` and the
/// values `densities[j] = n_j p_j(x)` of every technique (`c_j p_j(x)` in the one-sample model).
///
/// Implementations must give weights that sum to one over the techniques at every point
/// where the integrand is non-zero, and vanish for a technique whose density is zero there
/// (its weight would be lost: the sum is checked over the techniques of positive density);
/// the MIS estimators check this at every sample unless
/// [`is_partition_of_unity`](Self::is_partition_of_unity) promises it. Closures implement the
/// trait (annotate the argument types):
///
/// ```
/// use mcint::estimator::{MisHeuristic, MisWeighting};
/// // A fixed split, whatever the densities: valid when both pdfs are positive wherever the
/// // integrand is non-zero.
/// let half = |_technique: usize, _x: &[f64], _q: &[f64]| 0.5;
/// assert_eq!(half.weight(0, &[0.3], &[1.0, 2.0]), 0.5);
/// assert!(!half.is_partition_of_unity()); // checked at every sample
/// assert!(MisHeuristic::Balance.is_partition_of_unity());
/// ```
pub trait MisWeighting: Send + Sync {
    /// The weight of technique `technique` at `x`, given `densities[j] = n_j p_j(x)`.
    fn weight(&self, technique: usize, x: &[f64], densities: &[f64]) -> f64;

    /// Checks the weighting's parameters; the MIS estimators call it in their constructors.
    /// The default accepts.
    ///
    /// ```
    /// use mcint::estimator::{MisHeuristic, MisWeighting};
    /// assert!(MisWeighting::check(&MisHeuristic::Power { beta: 0.0 }).is_err());
    /// ```
    fn check(&self) -> Result<()> {
        Ok(())
    }

    /// True when the weights sum to one at every point where some density is positive, so
    /// that the estimators may skip the per-sample check. The default, `false`, has every
    /// sample checked; only weightings proven to sum to one (the built-in heuristics) should
    /// return `true`.
    ///
    /// ```
    /// use mcint::estimator::{MisHeuristic, MisWeighting};
    /// assert!(MisHeuristic::Maximum.is_partition_of_unity());
    /// ```
    fn is_partition_of_unity(&self) -> bool {
        false
    }
}

impl<F: Fn(usize, &[f64], &[f64]) -> f64 + Send + Sync> MisWeighting for F {
    fn weight(&self, technique: usize, x: &[f64], densities: &[f64]) -> f64 {
        self(technique, x, densities)
    }
}

/// The MIS term `w_i(x) f(x) / q_i` of a sample `x` of technique `i` with integrand value
/// `value != 0`, where `densities[j] = q_j` (`n_j p_j(x)` or `c_j p_j(x)`).
///
/// NaN when the technique's own density is not finite and positive at its own sample (a pdf
/// that is zero or NaN where the integrand is not), and when an unproven weighting's weights
/// over the techniques of positive density at `x` do not sum to one within
/// [`WEIGHT_SUM_TOLERANCE`]: the integrator then reports the point instead of averaging a
/// biased value.
pub(crate) fn weighted_term<W: MisWeighting + ?Sized>(
    weighting: &W,
    technique: usize,
    x: &[f64],
    densities: &[f64],
    value: f64,
) -> f64 {
    let own = densities[technique];
    if !(own.is_finite() && own > 0.0) {
        return f64::NAN;
    }
    if !weighting.is_partition_of_unity() {
        // Over the techniques that can produce x: a weight given to one whose density is 0
        // there (a pdf without support at x, a technique never chosen) is mass no sample
        // carries, and the estimate would lose it.
        let sum: f64 = (0..densities.len())
            .filter(|&j| densities[j] > 0.0)
            .map(|j| weighting.weight(j, x, densities))
            .sum();
        // Written so that a NaN sum fails too.
        let sums_to_one = (sum - 1.0).abs() <= WEIGHT_SUM_TOLERANCE;
        if !sums_to_one {
            return f64::NAN;
        }
    }
    weighting.weight(technique, x, densities) * value / own
}

/// Number of techniques whose densities fit on the stack in [`with_densities`].
const STACK_TECHNIQUES: usize = 16;

/// Runs `body` on a zeroed scratch slice of length `len`: on the stack for up to 16
/// techniques, so that the per-sample path does not allocate in the common case.
pub(crate) fn with_densities<R>(len: usize, body: impl FnOnce(&mut [f64]) -> R) -> R {
    if len <= STACK_TECHNIQUES {
        let mut buffer = [0.0; STACK_TECHNIQUES];
        body(&mut buffer[..len])
    } else {
        body(&mut vec![0.0; len])
    }
}
