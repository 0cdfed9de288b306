//! Bounds on the floating-point error of a computed mean: the floor below which no standard
//! error is reported.
//!
//! The model is IEEE-754 binary64 with rounding to nearest: every operation returns its exact
//! result times `1 + d`, `|d| <= u = 2^-53` (Higham, *Accuracy and Stability of Numerical
//! Algorithms*, 2nd ed., 2002, section 2.2). The bounds are first order in `u` and hold for
//! any data:
//!
//! * A sum evaluated along any tree of additions of height `h` errs by at most
//!   `gamma_h * sum |x_i|`, `gamma_h = h u / (1 - h u)` (Higham, section 4.2: each value is
//!   rounded into at most `h` partial sums).
//! * Welford's update `m += (y - m) / k` adds at most `u (|m_k| + 2 |y - m_{k-1}| / k)` and
//!   shrinks the error carried in by `1 - 1/k`; Chan's merge
//!   `m = m_a + (m_b - m_a) n_b / n` carries in `(n_a e_a + n_b e_b) / n` and adds at most
//!   `u (|m| + 3 |m_b - m_a| n_b / n)`. [`Accumulator`](super::Accumulator) keeps this
//!   running bound on its mean.
//! * The rounding inside each contribution (the integrand, the density, the `f/pdf`
//!   division) is out of the accumulator's sight; the floor allows [`CONTRIBUTION_ULPS`] units
//!   in the last place of each contribution's magnitude for it. An integrand computed less
//!   accurately than that (a long cancelling sum, a table lookup) has a larger rounding error
//!   than the floor claims.
//!
//! The floor of an [`Estimate`](super::Estimate) is the bound on the error of its `mean`
//! (`Estimate::rounding_error`); `std_error` is never reported below it. It only matters where
//! the statistical error vanishes: perfect importance sampling, a constant integrand, a
//! control variate equal to the integrand.

/// The unit roundoff of `f64`, `2^-53`.
pub(crate) const UNIT_ROUNDOFF: f64 = f64::EPSILON / 2.0;

/// Units in the last place allowed each contribution for its own evaluation (integrand,
/// density, `f/pdf`): a few roundings in each of a few library calls, with room to spare.
pub(crate) const CONTRIBUTION_ULPS: f64 = 64.0;

/// `gamma_k = k u / (1 - k u)`, the relative error bound of `k` chained roundings (infinite
/// once `k u >= 1`).
pub(crate) fn gamma(k: f64) -> f64 {
    let ku = k * UNIT_ROUNDOFF;
    if ku < 1.0 {
        ku / (1.0 - ku)
    } else {
        f64::INFINITY
    }
}

/// The smallest positive `f64`, `2^-1074`: the absolute error of a result that underflows.
const SMALLEST_SUBNORMAL: f64 = 5e-324;

/// The allowance for the evaluation of contributions whose magnitudes average at most
/// `scale`: [`CONTRIBUTION_ULPS`] units in the last place, relative to the contributions and
/// absolute at the bottom of the subnormal range (so that contributions that underflowed to
/// zero still carry an error).
pub(crate) fn contribution_allowance(scale: f64) -> f64 {
    CONTRIBUTION_ULPS * (UNIT_ROUNDOFF * scale + SMALLEST_SUBNORMAL)
}

/// The rounding bound of the plain mean `sum_i m_i / R` of values `m_i` that each carry an
/// error bound `e_i`: the carried errors averaged, plus the sequential sum and the division.
pub(crate) fn mean_of_means(means: &[f64], bounds: &[f64]) -> f64 {
    let r = means.len() as f64;
    let carried: f64 = bounds.iter().sum::<f64>() / r;
    let largest = means.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    carried + (gamma(r) + UNIT_ROUNDOFF) * largest
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_allowance_never_vanishes() {
        assert_eq!(SMALLEST_SUBNORMAL, f64::from_bits(1));
        assert!(contribution_allowance(0.0) > 0.0);
    }

    #[test]
    fn gamma_is_k_u_to_first_order_and_infinite_past_one() {
        assert!((gamma(10.0) / (10.0 * UNIT_ROUNDOFF) - 1.0).abs() < 1e-14);
        assert_eq!(gamma(1.0 / UNIT_ROUNDOFF), f64::INFINITY);
    }

    #[test]
    fn the_mean_of_exact_means_only_pays_for_its_sum() {
        let bound = mean_of_means(&[1.0, -3.0], &[0.0, 0.0]);
        assert_eq!(bound, (gamma(2.0) + UNIT_ROUNDOFF) * 3.0);
        assert!(mean_of_means(&[1.0, 1.0], &[2e-10, 4e-10]) > 3e-10);
    }
}
