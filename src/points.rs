//! [`PointBlock`]: a block of points stored as structure of arrays, in double precision
//! ([`Points`]) or single precision ([`PointsF32`](crate::points_f32::PointsF32)).
//!
//! Samplers write blocks of points with [`Sampler::fill`](crate::Sampler::fill) and estimators
//! read them back. Each dimension is one contiguous column, so kernels that generate or consume
//! one coordinate for many points run over unit-stride memory (the layout SIMD code wants).
//!
//! Both precisions share one generic type; they are type aliases of it, not a generic type
//! with a default parameter, so that `Points::new(dims, len)` needs no type annotation.

use crate::error::{Error, Result};

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

    /// Point `index` as a row of coordinates, or `None` past the last point.
    ///
    /// ```
    /// let mut block = mcint::Points::new(2, 3).unwrap();
    /// block.column_mut(1)[2] = 0.5;
    /// assert_eq!(block.row(2), Some(vec![0.0, 0.5]));
    /// assert_eq!(block.row(3), None);
    /// ```
    pub fn row(&self, index: usize) -> Option<Vec<T>> {
        (index < self.len).then(|| (0..self.dims).map(|d| self.get(index, d)).collect())
    }

    /// The points as rows, in order.
    ///
    /// ```
    /// let block = mcint::Points::from_rows(&[[0.1, 0.2], [0.3, 0.4]]).unwrap();
    /// let sums: Vec<f64> = block.rows().map(|r| r.iter().sum()).collect();
    /// assert_eq!(sums.len(), 2);
    /// assert!((sums[1] - 0.7).abs() < 1e-15);
    /// ```
    pub fn rows(&self) -> impl ExactSizeIterator<Item = Vec<T>> + '_ {
        (0..self.len).map(|i| (0..self.dims).map(|d| self.get(i, d)).collect())
    }

    /// The points as a vector of rows, as scipy's `(n, d)` arrays hold them.
    ///
    /// ```
    /// use mcint::sampler::{Sampler, Scramble, Sobol};
    /// let rows = Sobol::new(10, Scramble::Owen, 0).unwrap().random(1024).unwrap().to_rows();
    /// assert_eq!((rows.len(), rows[0].len()), (1024, 10));
    /// ```
    pub fn to_rows(&self) -> Vec<Vec<T>> {
        self.rows().collect()
    }

    /// A block from rows of equal length (at least one row, of at least one coordinate).
    ///
    /// ```
    /// use mcint::Points;
    /// let block = Points::from_rows(&[vec![0.1, 0.2], vec![0.3, 0.4]]).unwrap();
    /// assert_eq!(block.column(1), &[0.2, 0.4]);
    /// assert_eq!(Points::from_rows(&block.to_rows()).unwrap(), block);
    /// assert!(Points::from_rows(&[vec![0.1], vec![0.2, 0.3]]).is_err());
    /// assert!(Points::from_rows::<Vec<f64>>(&[]).is_err());
    /// ```
    pub fn from_rows<R: AsRef<[T]>>(rows: &[R]) -> Result<Self> {
        let Some(first) = rows.first() else {
            return Err(Error::invalid(
                "rows",
                "none",
                "at least one row (its length is the dimension)",
            ));
        };
        let mut block = Self::new(first.as_ref().len(), rows.len())?;
        for (i, row) in rows.iter().enumerate() {
            let row = row.as_ref();
            if row.len() != block.dims {
                return Err(Error::DimensionMismatch {
                    what: "row",
                    expected: block.dims,
                    found: row.len(),
                });
            }
            for (d, &x) in row.iter().enumerate() {
                block.data[d * block.len + i] = x;
            }
        }
        Ok(block)
    }
}

impl Points {
    /// The points mapped from the unit cube to the box `[lower, upper)`, coordinate by
    /// coordinate (scipy's `qmc.scale`): `lower + u (upper - lower)`; a coordinate outside
    /// `[0, 1]` is refused, as scipy refuses it.
    ///
    /// ```
    /// use mcint::Points;
    /// let unit = Points::from_rows(&[[0.5, 0.25]]).unwrap();
    /// let scaled = unit.scale(&[-1.0, 10.0], &[1.0, 20.0]).unwrap();
    /// assert_eq!(scaled.row(0), Some(vec![0.0, 12.5]));
    /// assert_eq!(scaled.unscale(&[-1.0, 10.0], &[1.0, 20.0]).unwrap(), unit);
    /// assert!(unit.scale(&[0.0, 1.0], &[1.0, 1.0]).is_err()); // an empty side
    /// assert!(scaled.scale(&[0.0; 2], &[1.0; 2]).is_err()); // 12.5 is not in [0, 1]
    /// ```
    pub fn scale(&self, lower: &[f64], upper: &[f64]) -> Result<Points> {
        self.check_box(lower, upper)?;
        let mut out = self.clone();
        for (d, (&l, &u)) in lower.iter().zip(upper).enumerate() {
            for (i, x) in out.column_mut(d).iter_mut().enumerate() {
                if !(0.0..=1.0).contains(x) {
                    return Err(Error::invalid(
                        "point",
                        format!("{x} at point {i}, dimension {d}"),
                        "coordinates in the unit cube [0, 1] (as qmc.scale requires)",
                    ));
                }
                *x = l + *x * (u - l);
            }
        }
        Ok(out)
    }

    /// The inverse of [`scale`](Self::scale) (scipy's `qmc.scale(..., reverse=True)`):
    /// points of the box `[lower, upper]` mapped to the unit cube; a point outside the box is
    /// refused.
    ///
    /// ```
    /// use mcint::Points;
    /// let data = Points::from_rows(&[[5.0], [7.5]]).unwrap();
    /// assert_eq!(data.unscale(&[5.0], &[10.0]).unwrap().column(0), &[0.0, 0.5]);
    /// assert!(data.unscale(&[6.0], &[10.0]).is_err()); // 5 is outside [6, 10]
    /// ```
    pub fn unscale(&self, lower: &[f64], upper: &[f64]) -> Result<Points> {
        self.check_box(lower, upper)?;
        let mut out = self.clone();
        for (d, (&l, &u)) in lower.iter().zip(upper).enumerate() {
            for (i, x) in out.column_mut(d).iter_mut().enumerate() {
                if !(l..=u).contains(x) {
                    return Err(Error::invalid(
                        "point",
                        format!("{x} at point {i}, dimension {d}"),
                        format!("inside the box's side [{l}, {u}]"),
                    ));
                }
                *x = (*x - l) / (u - l);
            }
        }
        Ok(out)
    }

    /// Checks that `lower` and `upper` bound a box of this block's dimension with sides of
    /// finite, positive length.
    fn check_box(&self, lower: &[f64], upper: &[f64]) -> Result<()> {
        for (what, bounds) in [("lower bounds", lower), ("upper bounds", upper)] {
            if bounds.len() != self.dims {
                return Err(Error::DimensionMismatch {
                    what,
                    expected: self.dims,
                    found: bounds.len(),
                });
            }
        }
        for (d, (&l, &u)) in lower.iter().zip(upper).enumerate() {
            if !(l < u && (u - l).is_finite()) {
                return Err(Error::invalid(
                    "box",
                    format!("[{l}, {u}] in dimension {d}"),
                    "finite bounds with lower < upper",
                ));
            }
        }
        Ok(())
    }
}
