//! A density proportional to a table of weights on equal cells of an interval, sampled by
//! binary search on its cdf.
//!
//! This is inverse-cdf sampling (the warp behind Jarosz's A.13 and A.19) of a step function:
//! the discrete cdf picks a cell, and the leftover fraction of `u` places the point inside it
//! uniformly, so the warp stays monotone and stratified `u` stay stratified. The method is the
//! classic one of pbrt-v4's `PiecewiseConstant1D` (Pharr, Jakob & Humphreys, *Physically Based
//! Rendering*, 4th ed., appendix A.4) and Mitsuba 3's `DiscreteDistribution`; this is our own
//! implementation.

use super::{Pdf1d, check_interval};
use crate::error::{Error, Result};
use crate::float::ONE_BELOW;

/// `u` moved into `[0, 1)` (NaN to 0), so that a table lookup cannot leave the table or land
/// on a cell of zero weight even for input outside the documented range.
pub(super) fn into_canonical(u: f64) -> f64 {
    if u >= 0.0 { u.min(ONE_BELOW) } else { 0.0 }
}

/// Checks a table of weights: non-empty, every weight finite and `>= 0`, with a sum that is
/// positive and finite. Returns the sum (accumulated in index order, as the cdf is).
pub(super) fn check_weights(name: &'static str, weights: &[f64]) -> Result<f64> {
    if weights.is_empty() {
        return Err(Error::invalid(
            name,
            "[]",
            "a non-empty table of finite weights >= 0",
        ));
    }
    if let Some((i, w)) = weights
        .iter()
        .enumerate()
        .find(|(_, w)| !w.is_finite() || **w < 0.0)
    {
        return Err(Error::invalid(
            name,
            format!("{w} at index {i}"),
            "finite weights >= 0",
        ));
    }
    let sum: f64 = weights.iter().sum();
    if sum == 0.0 {
        return Err(Error::invalid(
            name,
            "a table of zeros",
            "at least one positive weight (the density needs mass)",
        ));
    }
    if !sum.is_finite() {
        return Err(Error::invalid(
            name,
            format!("a table summing to {sum}"),
            "weights with a finite sum (only their ratios matter: scale them down)",
        ));
    }
    Ok(sum)
}

/// A discrete distribution over cells, sampled by binary search on its cdf. Shared by the
/// piecewise-constant and piecewise-linear densities, whose cells it picks.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct CellCdf {
    /// `cdf[i]`: probability of the cells before `i`; `cdf[0] = 0` and `cdf[n] = 1` exactly.
    cdf: Vec<f64>,
    /// Probability of each cell, `w_i / sum` (full relative precision even for tiny cells,
    /// which differences of the cdf would not give).
    probabilities: Vec<f64>,
    /// Sum of the weights.
    sum: f64,
}

impl CellCdf {
    /// The distribution of `weights`, which must have passed [`check_weights`].
    pub(super) fn new(weights: &[f64]) -> Self {
        let mut cdf = Vec::with_capacity(weights.len() + 1);
        let mut running = 0.0;
        cdf.push(0.0);
        for &w in weights {
            running += w;
            cdf.push(running);
        }
        // Dividing by the last running sum makes cdf[n] exactly 1; sums of non-negative terms
        // never decrease, so neither does the cdf.
        let sum = running;
        for c in &mut cdf {
            *c /= sum;
        }
        let probabilities = weights.iter().map(|w| w / sum).collect();
        CellCdf {
            cdf,
            probabilities,
            sum,
        }
    }

    pub(super) fn len(&self) -> usize {
        self.probabilities.len()
    }

    pub(super) fn sum(&self) -> f64 {
        self.sum
    }

    pub(super) fn probabilities(&self) -> &[f64] {
        &self.probabilities
    }

    /// The cell `i` with `cdf[i] <= u < cdf[i+1]` and the fraction of the way `u` is through
    /// it, in `[0, 1)`. That cell has positive probability, so cells of zero weight are never
    /// returned (and `u` outside `[0, 1)`, or NaN, is first moved into it).
    pub(super) fn sample(&self, u: f64) -> (usize, f64) {
        let u = into_canonical(u);
        // cdf[0] = 0 <= u < 1 = cdf[n], so the count is in 1..=n.
        let i = self.cdf.partition_point(|&c| c <= u) - 1;
        let (lo, hi) = (self.cdf[i], self.cdf[i + 1]);
        let fraction = ((u - lo) / (hi - lo)).min(ONE_BELOW);
        (i, fraction)
    }

    /// The cdf a `fraction` of the way through cell `i`: the inverse of [`sample`](Self::sample).
    pub(super) fn cdf_at(&self, i: usize, fraction: f64) -> f64 {
        let (lo, hi) = (self.cdf[i], self.cdf[i + 1]);
        (lo + fraction * (hi - lo)).clamp(0.0, 1.0)
    }
}

/// Density proportional to a table of weights `w_0, ..., w_{n-1}` on the `n` equal cells of
/// `[a, b)`: `pdf(x) = w_i / integral` in cell `i`, where `integral = sum(w) (b - a) / n`
/// (more exactly, `w_i / sum(w)` over the cell's width between its floating-point edges).
///
/// Sampling picks a cell by binary search on the cdf (`O(log n)`) and places the point
/// uniformly inside it, using the rest of `u`. Cells of zero weight have density zero and are
/// never sampled. The density is `w_i / sum(w)` per cell to full relative precision; the
/// sampling probabilities are differences of the rounded cdf, so they agree with it to about
/// `1e-16` absolutely (a cell `1e-16` times lighter than the whole table may never be hit).
///
/// ```
/// use mcint::pdf::{Pdf1d, PiecewiseConstant1d};
/// let p = PiecewiseConstant1d::new(0.0, 2.0, &[1.0, 3.0]).unwrap(); // cells [0,1), [1,2)
/// assert_eq!(p.pdf_1d(0.5), 0.25);
/// assert_eq!(p.pdf_1d(1.5), 0.75);
/// assert_eq!(p.sample_1d(0.25 + 0.75 / 2.0), 1.5); // the middle of the second cell
/// assert_eq!(p.invert_1d(1.5), 0.625);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseConstant1d {
    a: f64,
    b: f64,
    /// `(b - a) / n`.
    cell_width: f64,
    /// Density in each cell: its probability over its width between the float edges that
    /// sampling uses, so the density is exactly that of the samples even where rounding makes
    /// the cells unequal (narrow intervals far from zero).
    densities: Vec<f64>,
    cells: CellCdf,
}

impl PiecewiseConstant1d {
    /// The density of `weights` on `n = weights.len()` equal cells of `[a, b)`.
    ///
    /// Requires finite `a < b` with `b - a` finite, cells wide enough to have distinct edges
    /// and a finite density, and a non-empty table of finite weights `>= 0` whose sum is
    /// positive and finite. Errors name the parameter (`a`, `b` or `weights`).
    ///
    /// ```
    /// use mcint::pdf::PiecewiseConstant1d;
    /// assert!(PiecewiseConstant1d::new(0.0, 1.0, &[]).is_err());
    /// assert!(PiecewiseConstant1d::new(0.0, 1.0, &[0.0, 0.0]).is_err());
    /// assert!(PiecewiseConstant1d::new(0.0, 1.0, &[1.0, -1.0]).is_err());
    /// assert!(PiecewiseConstant1d::new(1.0, 0.0, &[1.0]).is_err());
    /// assert!(PiecewiseConstant1d::new(0.0, 1.0, &[0.0, 2.0]).is_ok());
    /// ```
    pub fn new(a: f64, b: f64, weights: &[f64]) -> Result<Self> {
        check_interval(a, b, false)?;
        check_weights("weights", weights)?;
        let n = weights.len();
        let cell_width = (b - a) / n as f64;
        if !(1.0 / cell_width).is_finite() {
            return Err(Error::invalid(
                "b",
                b,
                format!(
                    "an interval whose {n} cells have a finite density (cells {cell_width:e} wide)"
                ),
            ));
        }
        let mut p = PiecewiseConstant1d {
            a,
            b,
            cell_width,
            densities: Vec::new(),
            cells: CellCdf::new(weights),
        };
        // Every cell must hold a float, or sampling could not place a point in it.
        if let Some(i) = (0..n).find(|&i| p.edge(i) >= p.edge(i + 1)) {
            return Err(Error::invalid(
                "b",
                b,
                format!(
                    "an interval wide enough for {n} cells with distinct edges \
                     (cell {i} starts at {} and ends at {})",
                    p.edge(i),
                    p.edge(i + 1)
                ),
            ));
        }
        p.densities = (0..n)
            .map(|i| p.cells.probabilities()[i] / (p.edge(i + 1) - p.edge(i)))
            .collect();
        if let Some(i) = (0..n).find(|&i| !p.densities[i].is_finite()) {
            return Err(Error::invalid(
                "b",
                b,
                format!(
                    "an interval whose cells have a finite density (cell {i} is {:e} wide)",
                    p.edge(i + 1) - p.edge(i)
                ),
            ));
        }
        Ok(p)
    }

    /// Lower edge of cell `i` (and `b` for `i = n`). Sampling, `pdf` and `invert` all use
    /// these edges, so they agree on which cell a point is in.
    fn edge(&self, i: usize) -> f64 {
        if i >= self.cells.len() {
            self.b
        } else {
            self.a + i as f64 * self.cell_width
        }
    }

    /// Number of cells.
    ///
    /// ```
    /// use mcint::pdf::PiecewiseConstant1d;
    /// assert_eq!(PiecewiseConstant1d::new(0.0, 1.0, &[1.0; 7]).unwrap().cell_count(), 7);
    /// ```
    pub fn cell_count(&self) -> usize {
        self.cells.len()
    }

    /// The edges `[lo, hi)` of cell `i`, or `None` if there is no such cell.
    ///
    /// ```
    /// use mcint::pdf::PiecewiseConstant1d;
    /// let p = PiecewiseConstant1d::new(-1.0, 1.0, &[1.0, 2.0, 3.0, 4.0]).unwrap();
    /// assert_eq!(p.cell_bounds(1), Some((-0.5, 0.0)));
    /// assert_eq!(p.cell_bounds(4), None);
    /// ```
    pub fn cell_bounds(&self, i: usize) -> Option<(f64, f64)> {
        (i < self.cells.len()).then(|| (self.edge(i), self.edge(i + 1)))
    }

    /// The cell holding `x`, or `None` outside `[a, b)` (and for NaN).
    ///
    /// ```
    /// use mcint::pdf::PiecewiseConstant1d;
    /// let p = PiecewiseConstant1d::new(0.0, 1.0, &[1.0; 4]).unwrap();
    /// assert_eq!(p.cell_at(0.3), Some(1));
    /// assert_eq!(p.cell_at(0.25), Some(1));
    /// assert_eq!(p.cell_at(1.0), None);
    /// ```
    pub fn cell_at(&self, x: f64) -> Option<usize> {
        if !(self.a..self.b).contains(&x) {
            return None;
        }
        let n = self.cells.len();
        // The division is within a cell or so of the answer; the edges settle it.
        let mut i = (((x - self.a) / self.cell_width) as usize).min(n - 1);
        while i > 0 && x < self.edge(i) {
            i -= 1;
        }
        while i + 1 < n && x >= self.edge(i + 1) {
            i += 1;
        }
        Some(i)
    }

    /// The cell a canonical `u` selects and the remapped `u` within it: the cell `i` whose
    /// slice `[cdf_i, cdf_{i+1})` of `[0, 1)` holds `u`, and `(u - cdf_i) / p_i` in `[0, 1)`.
    ///
    /// The remapped value is again a canonical coordinate (uniform and independent of the cell
    /// when `u` is uniform), so it can drive a further warp: this is how a table picks a row
    /// and then a point within it. Cells of zero weight are never selected.
    ///
    /// ```
    /// use mcint::pdf::PiecewiseConstant1d;
    /// let p = PiecewiseConstant1d::new(0.0, 1.0, &[1.0, 0.0, 3.0]).unwrap();
    /// assert_eq!(p.sample_cell(0.125), (0, 0.5));
    /// assert_eq!(p.sample_cell(0.625), (2, 0.5)); // the zero cell is skipped
    /// ```
    pub fn sample_cell(&self, u: f64) -> (usize, f64) {
        self.cells.sample(u)
    }

    /// Probability of cell `i`, `w_i / sum(w)` (zero for `i` beyond the table).
    ///
    /// ```
    /// use mcint::pdf::PiecewiseConstant1d;
    /// let p = PiecewiseConstant1d::new(0.0, 1.0, &[1.0, 3.0]).unwrap();
    /// assert_eq!(p.cell_probability(1), 0.75);
    /// assert_eq!(p.cell_probability(2), 0.0);
    /// ```
    pub fn cell_probability(&self, i: usize) -> f64 {
        self.cells.probabilities().get(i).copied().unwrap_or(0.0)
    }

    /// Probabilities of all cells, `w_i / sum(w)`.
    ///
    /// ```
    /// use mcint::pdf::PiecewiseConstant1d;
    /// let p = PiecewiseConstant1d::new(0.0, 1.0, &[1.0, 0.0, 3.0]).unwrap();
    /// assert_eq!(p.probabilities(), &[0.25, 0.0, 0.75]);
    /// ```
    pub fn probabilities(&self) -> &[f64] {
        self.cells.probabilities()
    }

    /// The integral of the step function the table describes, `sum(w) (b - a) / n`: the
    /// normalising constant that turns the weights into the density. (It can overflow or
    /// underflow for extreme tables; the density does not depend on it.)
    ///
    /// ```
    /// use mcint::pdf::PiecewiseConstant1d;
    /// let p = PiecewiseConstant1d::new(0.0, 2.0, &[1.0, 3.0]).unwrap();
    /// assert_eq!(p.integral(), 4.0);
    /// ```
    pub fn integral(&self) -> f64 {
        self.cells.sum() * self.cell_width
    }
}

impl Pdf1d for PiecewiseConstant1d {
    fn sample_1d(&self, u: f64) -> f64 {
        let (i, fraction) = self.cells.sample(u);
        let (lo, hi) = (self.edge(i), self.edge(i + 1));
        let x = lo + fraction * (hi - lo);
        // Rounding may reach the next cell's edge, which could be a cell of zero weight.
        if x < hi { x } else { hi.next_down() }
    }

    fn pdf_1d(&self, x: f64) -> f64 {
        match self.cell_at(x) {
            Some(i) => self.densities[i],
            None => 0.0,
        }
    }

    fn invert_1d(&self, x: f64) -> f64 {
        if x.is_nan() {
            return f64::NAN;
        }
        match self.cell_at(x) {
            Some(i) => {
                let (lo, hi) = (self.edge(i), self.edge(i + 1));
                self.cells.cdf_at(i, ((x - lo) / (hi - lo)).clamp(0.0, 1.0))
            }
            None if x < self.a => 0.0,
            None => 1.0,
        }
    }

    fn support(&self) -> (f64, f64) {
        (self.a, self.b)
    }
}
