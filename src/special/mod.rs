//! Special functions: the normal, Student t and chi-square distribution functions.
//!
//! A bottom-layer private module: the normal warps of [`pdf`](crate::pdf) invert the normal
//! cdf, [`Estimate::confidence_interval`](crate::Estimate::confidence_interval) (the
//! user-facing way to get an interval) takes a Student t quantile, and the goodness-of-fit
//! test and VEGAS's `Q` value take a chi-square tail. None of it is public API.
//!
//! These are our own implementations rather than `statrs`: against 50-digit mpmath references
//! over the ranges this crate uses they are more accurate (statrs' Student t quantile fails
//! outright in the far tails), they bring no dependencies, and their bits, which normal warps
//! and confidence intervals inherit and `tests/contracts/value_stability.rs` pins, change only
//! when we change them. `docs/measurements.md` keeps the comparison.

mod chi_square;
mod normal;
mod student_t;

pub(crate) use chi_square::chi_square_sf;
pub(crate) use normal::{normal_cdf, normal_quantile, normal_sf};
pub(crate) use student_t::{student_t_quantile, student_t_upper_quantile};
