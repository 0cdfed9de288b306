//! [`PointBlock`]: a block of points stored as structure of arrays, in double precision
//! ([`Points`]) or single precision ([`PointsF32`](crate::points_f32::PointsF32)).
//!
//! Samplers write blocks of points with [`Sampler::fill`](crate::Sampler::fill) and estimators
//! read them back. Each dimension is one contiguous column, so kernels that generate or consume
//! one coordinate for many points run over unit-stride memory (the layout SIMD code wants).
//!
//! Both precisions share one generic type; they are type aliases of it, not a generic type
//! with a default parameter, so that `Points::new(dims, len)` needs no type annotation.

use crate::{Error, Result};

/// A block of `len` points in `dims` dimensions with coordinates of type `T`, one contiguous
/// column per dimension: [`Points`] for `f64`, [`PointsF32`](crate::points_f32::PointsF32) for
/// `f32`.
///
/// ```
/// use mcint::{PointBlock, Points};
/// let mut block: PointBlock<f64> = Points::new(2, 3).unwrap();
/// block.column_mut(1)[2] = 0.25;
/// assert_eq!(block.get(2, 1), 0.25);
/// let narrow = PointBlock::<f32>::new(2, 3).unwrap();
/// assert_eq!(narrow.column(0), &[0.0f32; 3]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PointBlock<T> {
    dims: usize,
    len: usize,
    /// Column-major: coordinate `d` of point `i` is at `d * len + i`.
    data: Vec<T>,
}

/// A block of `len` points in `dims` dimensions, one contiguous column per dimension.
///
/// ```
/// use mcint::Points;
/// let mut block = Points::new(2, 3).unwrap();
/// block.column_mut(1)[2] = 0.25;
/// assert_eq!(block.get(2, 1), 0.25);
/// let mut p = [0.0; 2];
/// block.copy_point(2, &mut p);
/// assert_eq!(p, [0.0, 0.25]);
/// ```
pub type Points = PointBlock<f64>;

impl<T: Copy + Default> PointBlock<T> {
    /// A zero-filled block of `len` points in `dims` dimensions (`dims >= 1`; `len` may be 0).
    ///
    /// ```
    /// let block = mcint::Points::new(3, 1024).unwrap();
    /// assert_eq!((block.dims(), block.len()), (3, 1024));
    /// assert!(mcint::Points::new(0, 4).is_err());
    /// // More coordinates than an allocation can hold is an error, not a panic.
    /// assert!(mcint::Points::new(1, usize::MAX / 4).is_err());
    /// assert!(mcint::points_f32::PointsF32::new(1, usize::MAX / 2).is_err());
    /// ```
    pub fn new(dims: usize, len: usize) -> Result<Self> {
        if dims == 0 {
            return Err(Error::invalid("dims", dims, "at least 1"));
        }
        // Refused beyond the crate's bound on one buffer, rather than aborting in `vec!`.
        let limit = (crate::error::MAX_BUFFER_BYTES / std::mem::size_of::<T>() as u64) as usize;
        let size =
            dims.checked_mul(len)
                .filter(|&size| size <= limit)
                .ok_or(Error::IndexOutOfRange {
                    what: "dims * len of a point block (8 GiB at most)",
                    limit: limit as u64,
                })?;
        Ok(PointBlock {
            dims,
            len,
            data: vec![T::default(); size],
        })
    }

    /// Number of dimensions (columns).
    ///
    /// ```
    /// assert_eq!(mcint::Points::new(5, 2).unwrap().dims(), 5);
    /// ```
    pub fn dims(&self) -> usize {
        self.dims
    }

    /// Number of points (rows).
    ///
    /// ```
    /// assert_eq!(mcint::Points::new(5, 2).unwrap().len(), 2);
    /// ```
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when the block holds no points.
    ///
    /// ```
    /// assert!(mcint::Points::new(1, 0).unwrap().is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Changes the number of points, keeping the dimension; contents become unspecified
    /// (zero or stale values), to be overwritten by the next fill. Reuses the allocation when
    /// shrinking.
    ///
    /// # Panics
    ///
    /// When `dims * len` values do not fit in memory, like `Vec::resize` (use
    /// [`new`](Self::new) to get an error instead).
    ///
    /// ```
    /// let mut block = mcint::Points::new(2, 8).unwrap();
    /// block.set_len(3);
    /// assert_eq!(block.len(), 3);
    /// assert_eq!(block.column(1).len(), 3);
    /// ```
    pub fn set_len(&mut self, len: usize) {
        // Checked: a wrapped product would leave `len` and the storage out of step.
        let values = self
            .dims
            .checked_mul(len)
            .expect("Points::set_len: dims * len overflows usize");
        self.len = len;
        self.data.resize(values, T::default());
    }

    /// Coordinate `dim` of every point. Panics if `dim >= self.dims()`, like slice indexing.
    ///
    /// ```
    /// let block = mcint::Points::new(2, 4).unwrap();
    /// assert_eq!(block.column(0), &[0.0; 4]);
    /// ```
    pub fn column(&self, dim: usize) -> &[T] {
        &self.data[dim * self.len..(dim + 1) * self.len]
    }

    /// Mutable column `dim`. Panics if `dim >= self.dims()`, like slice indexing.
    ///
    /// ```
    /// let mut block = mcint::Points::new(1, 2).unwrap();
    /// block.column_mut(0).copy_from_slice(&[0.5, 0.75]);
    /// assert_eq!(block.get(1, 0), 0.75);
    /// ```
    pub fn column_mut(&mut self, dim: usize) -> &mut [T] {
        &mut self.data[dim * self.len..(dim + 1) * self.len]
    }

    /// Coordinate `dim` of point `index`. Panics when out of bounds, like slice indexing.
    ///
    /// ```
    /// let block = mcint::Points::new(2, 2).unwrap();
    /// assert_eq!(block.get(1, 1), 0.0);
    /// ```
    pub fn get(&self, index: usize, dim: usize) -> T {
        assert!(
            index < self.len,
            "point index {index} out of range for {} points",
            self.len
        );
        self.data[dim * self.len + index]
    }

    /// Copies point `index` into `out` (`out.len()` must equal `self.dims()`); panics when
    /// out of bounds, like slice indexing.
    ///
    /// ```
    /// let block = mcint::Points::new(3, 1).unwrap();
    /// let mut p = [1.0; 3];
    /// block.copy_point(0, &mut p);
    /// assert_eq!(p, [0.0; 3]);
    /// ```
    pub fn copy_point(&self, index: usize, out: &mut [T]) {
        assert_eq!(
            out.len(),
            self.dims,
            "output buffer must have one slot per dimension"
        );
        for (dim, slot) in out.iter_mut().enumerate() {
            *slot = self.get(index, dim);
        }
    }

    /// All columns at once, mutably, in dimension order.
    ///
    /// ```
    /// let mut block = mcint::Points::new(2, 3).unwrap();
    /// for (dim, column) in block.columns_mut().enumerate() {
    ///     column.fill(dim as f64 / 2.0);
    /// }
    /// assert_eq!(block.get(0, 1), 0.5);
    /// ```
    pub fn columns_mut(&mut self) -> impl Iterator<Item = &mut [T]> {
        // `chunks_mut(0)` panics; a block of no points yields `dims` empty columns instead.
        let len = self.len.max(1);
        let dims = self.dims;
        self.data
            .chunks_mut(len)
            .chain(std::iter::repeat_with(|| &mut [][..]))
            .take(dims)
    }
}
