//! A density proportional to the linear interpolation of values at breakpoints, sampled by
//! choosing a segment from the cdf and inverting the linear density within it.
//!
//! Inverse-cdf sampling (the warp behind Jarosz's A.13 and A.19) in two steps: the segments'
//! masses form a discrete cdf that picks a segment, and the rest of `u` inverts the segment's
//! quadratic cdf. The quadratic is solved in the form that has no cancellation (Press et al.,
//! *Numerical Recipes*, 3rd ed., sec. 5.6; the same rearrangement as [`Linear`](super::Linear)
//! and pbrt-v4's `SampleLinear`), so nearly flat segments are as accurate as steep ones. The
//! table of segments is the piecewise-linear distribution of Mitsuba 3's
//! `ContinuousDistribution`; this implementation is our own.

use super::Pdf1d;
use super::piecewise_constant::CellCdf;
use crate::error::{Error, Result};

/// Density proportional to the function that interpolates `values[i]` at `xs[i]` linearly,
/// on `[xs[0], xs[n-1])`.
///
/// A segment whose two values are zero has density zero and is never sampled. Only the
/// values' ratios matter: they are rescaled so the largest is one, which keeps every product
/// finite for values anywhere in the `f64` range.
///
/// Sampling at a `u` that falls exactly on the start of a segment whose value there is zero
/// (for example `u = 0` when `values[0] = 0`) returns that breakpoint, where the density is
/// zero; any other `u` gives a point of positive density.
///
/// ```
/// use mcint::pdf::{Pdf1d, PiecewiseLinear1d};
/// // A tent on [0, 2] peaking at 1: density x on [0, 1), 2 - x on [1, 2).
/// let p = PiecewiseLinear1d::new(&[0.0, 1.0, 2.0], &[0.0, 1.0, 0.0]).unwrap();
/// assert_eq!(p.pdf_1d(0.5), 0.5);
/// assert_eq!(p.pdf_1d(1.5), 0.5);
/// assert!((p.sample_1d(0.125) - 0.5).abs() < 1e-15); // cdf x^2 / 2 = 1/8 at x = 1/2
/// assert!((p.invert_1d(1.5) - 0.875).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseLinear1d {
    xs: Vec<f64>,
    /// The values over their largest, so in `[0, 1]`.
    values: Vec<f64>,
    /// Integral of the rescaled interpolant: the density is `value / integral`.
    integral: f64,
    segments: CellCdf,
}

impl PiecewiseLinear1d {
    /// The density interpolating `values` at the breakpoints `xs`.
    ///
    /// Requires at least two finite, strictly increasing breakpoints with `xs[n-1] - xs[0]`
    /// finite, as many values, each finite and `>= 0` and not all zero, and a peak density
    /// that is finite. Errors name the parameter (`xs` or `values`).
    ///
    /// ```
    /// use mcint::pdf::PiecewiseLinear1d;
    /// assert!(PiecewiseLinear1d::new(&[0.0], &[1.0]).is_err());
    /// assert!(PiecewiseLinear1d::new(&[0.0, 1.0], &[1.0]).is_err());
    /// assert!(PiecewiseLinear1d::new(&[0.0, 0.0], &[1.0, 1.0]).is_err());
    /// assert!(PiecewiseLinear1d::new(&[0.0, 1.0], &[0.0, 0.0]).is_err());
    /// assert!(PiecewiseLinear1d::new(&[0.0, 1.0], &[0.0, 2.0]).is_ok());
    /// ```
    pub fn new(xs: &[f64], values: &[f64]) -> Result<Self> {
        if xs.len() < 2 {
            return Err(Error::invalid(
                "xs",
                format!("{} breakpoint(s)", xs.len()),
                "at least two breakpoints",
            ));
        }
        if let Some((i, x)) = xs.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(Error::invalid(
                "xs",
                format!("{x} at index {i}"),
                "finite breakpoints",
            ));
        }
        if let Some(i) = (1..xs.len()).find(|&i| xs[i] <= xs[i - 1]) {
            return Err(Error::invalid(
                "xs",
                format!("{} at index {i} after {}", xs[i], xs[i - 1]),
                "strictly increasing breakpoints",
            ));
        }
        let span = xs[xs.len() - 1] - xs[0];
        if !span.is_finite() {
            return Err(Error::invalid(
                "xs",
                format!("[{}, {}]", xs[0], xs[xs.len() - 1]),
                "breakpoints spanning a finite width",
            ));
        }
        if values.len() != xs.len() {
            return Err(Error::invalid(
                "values",
                format!("{} values", values.len()),
                format!("one value per breakpoint ({})", xs.len()),
            ));
        }
        if let Some((i, v)) = values
            .iter()
            .enumerate()
            .find(|(_, v)| !v.is_finite() || **v < 0.0)
        {
            return Err(Error::invalid(
                "values",
                format!("{v} at index {i}"),
                "finite values >= 0",
            ));
        }
        let peak = values.iter().fold(0.0f64, |m, &v| m.max(v));
        if peak == 0.0 {
            return Err(Error::invalid(
                "values",
                "all zero",
                "at least one positive value (the density needs mass)",
            ));
        }
        let values: Vec<f64> = values.iter().map(|v| v / peak).collect();
        // Trapezoids: values are at most one, so each mass is at most its width and the sum
        // at most the (finite) span.
        let masses: Vec<f64> = xs
            .windows(2)
            .zip(values.windows(2))
            .map(|(x, v)| 0.5 * (v[0] + v[1]) * (x[1] - x[0]))
            .collect();
        let integral: f64 = masses.iter().sum();
        if !(1.0 / integral).is_finite() {
            return Err(Error::invalid(
                "xs",
                format!("[{}, {}]", xs[0], xs[xs.len() - 1]),
                format!(
                    "breakpoints spread enough that the peak density is finite (the \
                     normalised interpolant has integral {integral:e})"
                ),
            ));
        }
        Ok(PiecewiseLinear1d {
            xs: xs.to_vec(),
            values,
            integral,
            segments: CellCdf::new(&masses),
        })
    }

    /// The breakpoints.
    ///
    /// ```
    /// use mcint::pdf::PiecewiseLinear1d;
    /// let p = PiecewiseLinear1d::new(&[0.0, 1.0, 3.0], &[1.0, 2.0, 1.0]).unwrap();
    /// assert_eq!(p.breakpoints(), &[0.0, 1.0, 3.0]);
    /// ```
    pub fn breakpoints(&self) -> &[f64] {
        &self.xs
    }

    /// Probability of each segment `[xs[i], xs[i+1])`.
    ///
    /// ```
    /// use mcint::pdf::PiecewiseLinear1d;
    /// let p = PiecewiseLinear1d::new(&[0.0, 1.0, 3.0], &[1.0, 1.0, 1.0]).unwrap();
    /// assert_eq!(p.segment_probabilities(), &[1.0 / 3.0, 2.0 / 3.0]);
    /// ```
    pub fn segment_probabilities(&self) -> &[f64] {
        self.segments.probabilities()
    }

    /// The segment holding `x` (`xs[i] <= x < xs[i+1]`), or `None` outside the support.
    fn segment_at(&self, x: f64) -> Option<usize> {
        let n = self.xs.len();
        if !(self.xs[0]..self.xs[n - 1]).contains(&x) {
            return None;
        }
        Some(self.xs.partition_point(|&b| b <= x) - 1)
    }

    /// The values at the ends of segment `i`, rescaled so the larger is one (so the squares
    /// in the quadratic neither underflow nor lose precision for small values), or `None`
    /// for a segment of zeros.
    fn segment_shape(&self, i: usize) -> Option<(f64, f64)> {
        let (v0, v1) = (self.values[i], self.values[i + 1]);
        let scale = v0.max(v1);
        (scale > 0.0).then(|| (v0 / scale, v1 / scale))
    }
}

impl Pdf1d for PiecewiseLinear1d {
    fn sample_1d(&self, u: f64) -> f64 {
        let (i, fraction) = self.segments.sample(u);
        // Solve t ((1 - t/2) v0 + (t/2) v1) = fraction (v0 + v1) / 2 for t in [0, 1]:
        // t = 2 f / (v0 + sqrt(v0^2 (1 - f) + v1^2 f)) * (v0 + v1) / 2, the root written
        // without the difference v1 - v0, which would cancel on a nearly flat segment.
        let t = match self.segment_shape(i) {
            Some((v0, v1)) => {
                let root = ((1.0 - fraction) * v0 * v0 + fraction * v1 * v1).sqrt();
                let denominator = v0 + root;
                if denominator > 0.0 {
                    fraction * (v0 + v1) / denominator
                } else {
                    0.0
                }
            }
            // Never chosen (no mass); a uniform placement keeps the function total.
            None => fraction,
        };
        let (lo, hi) = (self.xs[i], self.xs[i + 1]);
        let x = lo + t.min(1.0) * (hi - lo);
        // Stay inside the segment (the next one may have zero density at its start).
        if x < hi { x } else { hi.next_down() }
    }

    fn pdf_1d(&self, x: f64) -> f64 {
        let Some(i) = self.segment_at(x) else {
            return 0.0;
        };
        let (lo, hi) = (self.xs[i], self.xs[i + 1]);
        let t = (x - lo) / (hi - lo);
        let (v0, v1) = (self.values[i], self.values[i + 1]);
        (v0 + t * (v1 - v0)).max(0.0) / self.integral
    }

    fn invert_1d(&self, x: f64) -> f64 {
        if x.is_nan() {
            return f64::NAN;
        }
        let Some(i) = self.segment_at(x) else {
            return if x < self.xs[0] { 0.0 } else { 1.0 };
        };
        let (lo, hi) = (self.xs[i], self.xs[i + 1]);
        let t = ((x - lo) / (hi - lo)).clamp(0.0, 1.0);
        // Fraction of the segment's mass below t: t (2 v0 + (v1 - v0) t) / (v0 + v1).
        let fraction = match self.segment_shape(i) {
            Some((v0, v1)) => t * (2.0 * v0 + (v1 - v0) * t) / (v0 + v1),
            None => t,
        };
        self.segments.cdf_at(i, fraction.clamp(0.0, 1.0))
    }

    fn support(&self) -> (f64, f64) {
        (self.xs[0], self.xs[self.xs.len() - 1])
    }
}
