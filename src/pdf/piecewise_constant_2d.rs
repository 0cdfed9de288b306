//! A density proportional to an image-like table on a box, sampled by a marginal row and
//! then a point within the row.
//!
//! Writing the density as `p(x, y) = p(y) p(x | y)` turns two-dimensional inverse-cdf sampling
//! into two one-dimensional ones (the warp of Jarosz's A.13/A.19 applied coordinate by
//! coordinate): `u[1]` picks `y` from the marginal density of the rows, and `u[0]` picks `x`
//! from the conditional density within that row. Each step is monotone, so stratified `u`
//! give stratified rows and, within a row, stratified columns. This is the marginal-conditional
//! method of pbrt-v4's `PiecewiseConstant2D` (Pharr, Jakob & Humphreys, *Physically Based
//! Rendering*, 4th ed., sec. 2.4.2 and appendix A.5) and of environment-map sampling in
//! Mitsuba 3; the implementation is our own, built on [`PiecewiseConstant1d`].

use super::{Pdf, Pdf1d, PiecewiseConstant1d, debug_assert_len};
use crate::error::{Error, Result};

/// Density proportional to a `width x height` table of non-negative values (row-major: row
/// `j` is `values[j * width .. (j + 1) * width]`, covering `y` in the `j`-th of `height` equal
/// slices of `[lo[1], hi[1])`) on the box `[lo[0], hi[0]) x [lo[1], hi[1])`.
///
/// The density in cell `(i, j)` is `values[j * width + i] / integral`. Sampling uses `u[1]`
/// for the row (marginal) and `u[0]` for the column (conditional), so with `u = (s, t)` a
/// constant table maps to `x = lo[0] + s (hi[0] - lo[0])`, `y = lo[1] + t (hi[1] - lo[1])`.
/// Rows and cells of zero value are never sampled and have density zero.
///
/// ```
/// use mcint::pdf::{Pdf, PiecewiseConstant2d};
/// // Two columns, two rows on [0,2) x [0,1): all the mass in the upper-right cell and the
/// // lower-left cell, three times as much in the former.
/// let p = PiecewiseConstant2d::new([0.0, 0.0], [2.0, 1.0], 2, 2, &[1.0, 0.0, 0.0, 3.0])
///     .unwrap();
/// assert_eq!(p.pdf(&[0.5, 0.25]), 0.5); // 1/4 of the mass on a cell of area 1/2
/// assert_eq!(p.pdf(&[1.5, 0.75]), 1.5);
/// assert_eq!(p.pdf(&[1.5, 0.25]), 0.0);
/// let mut x = [0.0; 2];
/// p.sample(&[0.5, 0.5], &mut x);
/// assert_eq!(x, [1.5, 2.0 / 3.0]); // u[1] = 1/2 is a third of the way into the upper row
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseConstant2d {
    /// The density of `y`: one cell per row, weighted by the row's sum.
    marginal: PiecewiseConstant1d,
    /// The density of `x` given the row; `None` for rows of zeros, which are never sampled.
    conditionals: Vec<Option<PiecewiseConstant1d>>,
    width: usize,
    /// `(lo[0], hi[0])`.
    x_range: (f64, f64),
}

impl PiecewiseConstant2d {
    /// The density of `values` (row-major, `width * height` of them) on the box with corners
    /// `lo` and `hi`.
    ///
    /// Requires `width, height >= 1` with `values.len() == width * height`, values finite and
    /// `>= 0` with a positive, finite sum, and finite `lo[d] < hi[d]` whose cells have distinct
    /// edges and an area whose reciprocal is finite. Errors name the parameter (`width`,
    /// `height`, `values`, `x range`, `y range`, `box`). (On boxes so large that
    /// `1 / area` is below about `1e-308` the density of light cells underflows to zero.)
    ///
    /// ```
    /// use mcint::pdf::PiecewiseConstant2d;
    /// let unit = ([0.0, 0.0], [1.0, 1.0]);
    /// assert!(PiecewiseConstant2d::new(unit.0, unit.1, 2, 2, &[1.0; 3]).is_err());
    /// assert!(PiecewiseConstant2d::new(unit.0, unit.1, 0, 0, &[]).is_err());
    /// assert!(PiecewiseConstant2d::new(unit.0, unit.1, 2, 1, &[0.0, 0.0]).is_err());
    /// assert!(PiecewiseConstant2d::new([0.0, 1.0], [1.0, 1.0], 1, 1, &[1.0]).is_err());
    /// ```
    pub fn new(
        lo: [f64; 2],
        hi: [f64; 2],
        width: usize,
        height: usize,
        values: &[f64],
    ) -> Result<Self> {
        if width == 0 {
            return Err(Error::invalid("width", width, "at least one column"));
        }
        if height == 0 {
            return Err(Error::invalid("height", height, "at least one row"));
        }
        if width.checked_mul(height) != Some(values.len()) {
            return Err(Error::invalid(
                "values",
                format!("{} values", values.len()),
                format!("width * height = {width} * {height} values, row by row"),
            ));
        }
        let total = super::piecewise_constant::check_weights("values", values)?;
        let rename = |name: &'static str| {
            move |e: Error| match e {
                Error::InvalidParameter { value, allowed, .. } => Error::InvalidParameter {
                    name,
                    value,
                    allowed,
                },
                other => other,
            }
        };
        // The rows' shares of the table weight the marginal (dividing each value by the total
        // first keeps every partial sum finite). The table is valid, so an error here is about
        // the y range.
        let row_shares: Vec<f64> = values
            .chunks_exact(width)
            .map(|row| row.iter().map(|v| v / total).sum())
            .collect();
        let marginal =
            PiecewiseConstant1d::new(lo[1], hi[1], &row_shares).map_err(rename("y range"))?;
        // Check the x range once, with a table that is always valid.
        PiecewiseConstant1d::new(lo[0], hi[0], &vec![1.0; width]).map_err(rename("x range"))?;
        // The density is at most 1 / (cell area); the two 1-D checks bound each factor only.
        let cell_area = (hi[0] - lo[0]) / width as f64 * ((hi[1] - lo[1]) / height as f64);
        if !(1.0 / cell_area).is_finite() {
            return Err(Error::invalid(
                "box",
                format!("[{}, {}) x [{}, {})", lo[0], hi[0], lo[1], hi[1]),
                format!("a box whose cells have a finite density (cell area {cell_area:e})"),
            ));
        }
        let conditionals = values
            .chunks_exact(width)
            .map(|row| {
                if row.iter().all(|&v| v == 0.0) {
                    Ok(None)
                } else {
                    PiecewiseConstant1d::new(lo[0], hi[0], row).map(Some)
                }
            })
            .collect::<Result<Vec<_>>>()
            .map_err(rename("values"))?;
        Ok(PiecewiseConstant2d {
            marginal,
            conditionals,
            width,
            x_range: (lo[0], hi[0]),
        })
    }

    /// Number of columns.
    ///
    /// ```
    /// use mcint::pdf::PiecewiseConstant2d;
    /// let p = PiecewiseConstant2d::new([0.0; 2], [1.0; 2], 3, 2, &[1.0; 6]).unwrap();
    /// assert_eq!((p.width(), p.height()), (3, 2));
    /// ```
    pub fn width(&self) -> usize {
        self.width
    }

    /// Number of rows.
    ///
    /// ```
    /// use mcint::pdf::PiecewiseConstant2d;
    /// let p = PiecewiseConstant2d::new([0.0; 2], [1.0; 2], 1, 4, &[1.0; 4]).unwrap();
    /// assert_eq!(p.height(), 4);
    /// ```
    pub fn height(&self) -> usize {
        self.conditionals.len()
    }

    /// The marginal density of `y`: one cell per row, with the row's share of the table.
    ///
    /// ```
    /// use mcint::pdf::PiecewiseConstant2d;
    /// let p = PiecewiseConstant2d::new([0.0; 2], [1.0; 2], 2, 2, &[1.0, 1.0, 0.0, 2.0])
    ///     .unwrap();
    /// assert_eq!(p.marginal().probabilities(), &[0.5, 0.5]);
    /// ```
    pub fn marginal(&self) -> &PiecewiseConstant1d {
        &self.marginal
    }

    /// The conditional density of `x` in row `row`, or `None` for a row of zeros (or beyond
    /// the table).
    ///
    /// ```
    /// use mcint::pdf::PiecewiseConstant2d;
    /// let p = PiecewiseConstant2d::new([0.0; 2], [1.0; 2], 2, 2, &[1.0, 3.0, 0.0, 0.0])
    ///     .unwrap();
    /// assert_eq!(p.conditional(0).unwrap().probabilities(), &[0.25, 0.75]);
    /// assert!(p.conditional(1).is_none());
    /// ```
    pub fn conditional(&self, row: usize) -> Option<&PiecewiseConstant1d> {
        self.conditionals.get(row)?.as_ref()
    }

    /// Probability of cell `(column, row)`: its value over the table's sum (zero beyond the
    /// table).
    ///
    /// ```
    /// use mcint::pdf::PiecewiseConstant2d;
    /// let p = PiecewiseConstant2d::new([0.0; 2], [1.0; 2], 2, 2, &[1.0, 3.0, 0.0, 4.0])
    ///     .unwrap();
    /// assert_eq!(p.cell_probability(1, 0), 0.375);
    /// assert_eq!(p.cell_probability(1, 1), 0.5);
    /// ```
    pub fn cell_probability(&self, column: usize, row: usize) -> f64 {
        match self.conditional(row) {
            Some(c) => self.marginal.cell_probability(row) * c.cell_probability(column),
            None => 0.0,
        }
    }
}

impl Pdf for PiecewiseConstant2d {
    fn canonical_dims(&self) -> usize {
        2
    }

    fn dims(&self) -> usize {
        2
    }

    fn sample(&self, u: &[f64], x: &mut [f64]) {
        debug_assert_len!(self, sample, u, canonical_dims);
        debug_assert_len!(self, sample, x, dims);
        let y = self.marginal.sample_1d(u[1]);
        // The marginal only lands in rows of positive weight, which have a conditional.
        let row = self.marginal.cell_at(y).unwrap_or(0);
        x[0] = match &self.conditionals[row] {
            Some(c) => c.sample_1d(u[0]),
            // Unreachable for u in [0, 1): the marginal never picks a row of zeros.
            None => {
                let (x0, x1) = self.x_range;
                x0 + u[0].clamp(0.0, 1.0) * (x1 - x0)
            }
        };
        x[1] = y;
    }

    fn pdf(&self, x: &[f64]) -> f64 {
        debug_assert_len!(self, pdf, x, dims);
        let Some(row) = self.marginal.cell_at(x[1]) else {
            return 0.0;
        };
        match &self.conditionals[row] {
            Some(c) => self.marginal.pdf_1d(x[1]) * c.pdf_1d(x[0]),
            None => 0.0,
        }
    }

    /// `u[1]` is the marginal cdf of `x[1]` and `u[0]` the conditional cdf of `x[0]` in its
    /// row (for a point in a row of zeros, which no `u` reaches, `u[0]` is its uniform
    /// fraction of the row).
    fn invert(&self, x: &[f64], u: &mut [f64]) -> Result<()> {
        debug_assert_len!(self, invert, x, dims);
        debug_assert_len!(self, invert, u, canonical_dims);
        u[1] = self.marginal.invert_1d(x[1]);
        let (lo, hi) = self.marginal.support();
        let row = self
            .marginal
            .cell_at(x[1].clamp(lo, hi.next_down()))
            .unwrap_or(0);
        u[0] = match &self.conditionals[row] {
            Some(c) => c.invert_1d(x[0]),
            None => {
                let (x0, x1) = self.x_range;
                ((x[0] - x0) / (x1 - x0)).clamp(0.0, 1.0)
            }
        };
        Ok(())
    }
}
