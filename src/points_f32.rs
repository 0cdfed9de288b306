//! [`PointsF32`]: a block of single-precision points, for [`Sampler::fill_f32`].
//!
//! The same structure-of-arrays layout as [`Points`](crate::Points), with `f32` coordinates:
//! half the memory traffic, twice the lanes per vector for integrands evaluated in `f32`. Both
//! are [`PointBlock`]s, so they share every accessor.
//!
//! [`Sampler::fill_f32`]: crate::Sampler::fill_f32

use crate::points::PointBlock;

/// The largest `f32` below one, `1 - 2^-24`: where [`to_unit_f32`] sends the values that
/// would round to 1.0.
pub const F32_BELOW_ONE: f32 = 1.0 - f32::EPSILON / 2.0;

/// The `f32` a coordinate `x` in `[0, 1)` becomes in [`Sampler::fill_f32`]: `x` rounded to
/// the nearest `f32` (ties to even), except that values at or above `1 - 2^-25`, which would
/// round to 1.0, become [`F32_BELOW_ONE`], the `f32` just below them. So the result is in
/// `[0, 1)` and within half a unit in the last place of `x` (one unit near 1).
///
/// [`Sampler::fill_f32`]: crate::Sampler::fill_f32
///
/// ```
/// use mcint::points_f32::{F32_BELOW_ONE, to_unit_f32};
/// assert_eq!(to_unit_f32(0.25), 0.25);
/// assert_eq!(to_unit_f32(1.0 - 2f64.powi(-53)), F32_BELOW_ONE);
/// assert_eq!(to_unit_f32(0.1), 0.1f32);
/// ```
#[inline(always)]
pub fn to_unit_f32(x: f64) -> f32 {
    (x as f32).min(F32_BELOW_ONE)
}

/// A block of `len` points in `dims` dimensions with `f32` coordinates, one contiguous column
/// per dimension.
///
/// ```
/// use mcint::points_f32::PointsF32;
/// let mut block = PointsF32::new(2, 3).unwrap();
/// block.column_mut(1)[2] = 0.25;
/// assert_eq!(block.get(2, 1), 0.25);
/// assert_eq!((block.dims(), block.len()), (2, 3));
/// assert!(PointsF32::new(0, 8).is_err());
/// ```
pub type PointsF32 = PointBlock<f32>;
