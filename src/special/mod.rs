//! Special functions: the normal, Student t and chi-square distribution functions.
//!
//! A bottom-layer private module: the normal warps of [`pdf`](crate::pdf) invert the normal
//! cdf, [`Estimate::confidence_interval`](crate::Estimate::confidence_interval) (the
//! user-facing way to get an interval) takes a Student t quantile, and the goodness-of-fit
//! test and VEGAS's `Q` value take a chi-square tail. None of it is public API.
//!
//! These are our own implementations rather than `statrs` (0.19, default features off), which
//! was measured against 50-digit mpmath references over the ranges this crate uses:
//!
//! | function | ours, largest relative error | statrs |
//! | --- | --- | --- |
//! | normal cdf and sf, `\|x\| <= 38` | 3e-16 | 1e-10 (at `\|x\| = 0.8`) |
//! | normal quantile, `p` in `[1e-300, 1 - 1e-16]` | 7e-16 | 4e-16 |
//! | Student t cdf, dof 1 to 1e6 | 4e-14 | 9e-10 (dof 1e6) |
//! | Student t quantile, dof 1 to 1e6, `p` in `[1e-300, 1 - 1e-16]` | 2e-14 | see below |
//! | chi-square sf, dof 1 to 1e4 | 9e-14 | 1e-11 |
//!
//! From a million degrees of freedom on, the chi-square sf switches to Temme's uniform
//! asymptotic expansion: within 6e-15 of mpmath from 1e6 to 1e15 degrees of freedom within
//! five standard deviations of the mean, and 3e-13 at thirty (tails near 1e-197). The series
//! and continued fraction used there before lost digits from about 1e7 and were wrong by
//! 16% to 100% from 1e10.
//!
//! statrs' Student t quantile panics at `p = 1e-300` for every dof, is wrong by a factor of
//! order one at `p = 1e-100` for dof up to 15, did not return within ten minutes at dof 1000
//! and `p = 1e-100`, fails for `p <= 1e-30` at dof 1e3 and above, and is off by 1e-8 to 3e-4
//! at ordinary `p` (0.9, 0.025) for dof 1e4 to 1e6. It would also bring eight crates (approx,
//! num-traits, thiserror and its proc-macro stack), and any change to these functions would
//! change the bits of normal warps and confidence intervals that
//! `tests/contracts/value_stability.rs` pins.

mod chi_square;
mod normal;
mod student_t;

pub(crate) use chi_square::chi_square_sf;
pub(crate) use normal::{normal_cdf, normal_quantile, normal_sf};
pub(crate) use student_t::student_t_quantile;
