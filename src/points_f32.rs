//! [`PointsF32`]: a block of single-precision points, for [`Sampler::fill_f32`].
//!
//! The same structure-of-arrays layout as [`Points`](crate::Points), with `f32` coordinates:
//! half the memory traffic, twice the lanes per vector for integrands evaluated in `f32`.
//!
//! [`Sampler::fill_f32`]: crate::Sampler::fill_f32

use crate::{Error, Result};

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
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PointsF32 {
    dims: usize,
    len: usize,
    /// Column-major: coordinate `d` of point `i` is at `d * len + i`.
    data: Vec<f32>,
}

impl PointsF32 {
    /// A zero-filled block of `len` points in `dims` dimensions (`dims >= 1`; `len` may be 0).
    ///
    /// ```
    /// use mcint::points_f32::PointsF32;
    /// assert_eq!(PointsF32::new(3, 8).unwrap().len(), 8);
    /// assert!(PointsF32::new(0, 8).is_err());
    /// assert!(PointsF32::new(1, usize::MAX / 2).is_err());
    /// ```
    pub fn new(dims: usize, len: usize) -> Result<Self> {
        if dims == 0 {
            return Err(Error::invalid("dims", dims, "at least 1"));
        }
        let limit = isize::MAX as usize / std::mem::size_of::<f32>();
        let size =
            dims.checked_mul(len)
                .filter(|&size| size <= limit)
                .ok_or(Error::IndexOutOfRange {
                    what: "dims * len of a point block",
                    limit: limit as u64,
                })?;
        Ok(PointsF32 {
            dims,
            len,
            data: vec![0.0; size],
        })
    }

    /// Number of dimensions (columns).
    ///
    /// ```
    /// assert_eq!(mcint::points_f32::PointsF32::new(5, 2).unwrap().dims(), 5);
    /// ```
    pub fn dims(&self) -> usize {
        self.dims
    }

    /// Number of points (rows).
    ///
    /// ```
    /// assert_eq!(mcint::points_f32::PointsF32::new(5, 2).unwrap().len(), 2);
    /// ```
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when the block holds no points.
    ///
    /// ```
    /// assert!(mcint::points_f32::PointsF32::new(1, 0).unwrap().is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Coordinate `dim` of every point. Panics if `dim >= self.dims()`, like slice indexing.
    ///
    /// ```
    /// let block = mcint::points_f32::PointsF32::new(2, 4).unwrap();
    /// assert_eq!(block.column(1), &[0.0; 4]);
    /// ```
    pub fn column(&self, dim: usize) -> &[f32] {
        &self.data[dim * self.len..(dim + 1) * self.len]
    }

    /// Mutable column `dim`. Panics if `dim >= self.dims()`, like slice indexing.
    ///
    /// ```
    /// let mut block = mcint::points_f32::PointsF32::new(1, 2).unwrap();
    /// block.column_mut(0).copy_from_slice(&[0.5, 0.75]);
    /// assert_eq!(block.get(1, 0), 0.75);
    /// ```
    pub fn column_mut(&mut self, dim: usize) -> &mut [f32] {
        &mut self.data[dim * self.len..(dim + 1) * self.len]
    }

    /// Coordinate `dim` of point `index`. Panics when out of bounds, like slice indexing.
    ///
    /// ```
    /// let block = mcint::points_f32::PointsF32::new(2, 2).unwrap();
    /// assert_eq!(block.get(1, 1), 0.0);
    /// ```
    pub fn get(&self, index: usize, dim: usize) -> f32 {
        assert!(
            index < self.len,
            "point index {index} out of range for {} points",
            self.len
        );
        self.data[dim * self.len + index]
    }
}
