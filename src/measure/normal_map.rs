//! The inverse normal cdf applied to canonical coordinates, shared by the Gaussian measures.

use crate::special::normal_quantile;

/// The smallest canonical coordinate used: `u = 0` (which only unrandomized points produce)
/// is read as `2^-54`, the mirror of the largest coordinate below 1, so that every point
/// maps to a finite normal value (about -8.3).
const SMALLEST: f64 = 1.0 / (1u64 << 54) as f64;

/// `Phi^-1(u)` for `u` in `[0, 1)`.
#[inline]
pub(crate) fn standard_normal(u: f64) -> f64 {
    normal_quantile(u.max(SMALLEST))
}

/// The largest `|Phi^-1(u)|` over canonical `u`: `-Phi^-1(2^-54)`, about 8.29 (the top,
/// `Phi^-1(1 - 2^-53)`, is about 8.21).
pub(super) fn largest_normal() -> f64 {
    -standard_normal(0.0)
}

/// Checks that every value is finite, naming `what` otherwise.
pub(super) fn check_finite(what: &'static str, values: &[f64]) -> crate::error::Result<()> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(crate::error::Error::invalid(
            what,
            format!("{} at index {i}", values[i]),
            "finite values",
        )),
    }
}
