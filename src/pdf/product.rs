//! Products of independent one-dimensional densities: a density on a box.

use super::{Pdf, Pdf1d, debug_assert_len};
use crate::error::{Error, Result};

/// The density `p_1(x_1) p_2(x_2) ... p_d(x_d)` of independent coordinates, each sampled by
/// its own [`Pdf1d`] from one canonical coordinate.
///
/// ```
/// use mcint::pdf::{Linear, Pdf, ProductPdf, UniformInterval};
/// let p = ProductPdf::new(vec![
///     Box::new(UniformInterval::new(0.0, 2.0).unwrap()),
///     Box::new(Linear::new(0.0, 1.0, 0.0, 1.0).unwrap()),
/// ])
/// .unwrap();
/// let mut x = [0.0; 2];
/// p.sample(&[0.5, 0.25], &mut x);
/// assert_eq!(x, [1.0, 0.5]);
/// assert!((p.pdf(&x) - 0.5 * 1.0).abs() < 1e-15);
/// ```
pub struct ProductPdf {
    factors: Vec<Box<dyn Pdf1d>>,
}

impl ProductPdf {
    /// The product of `factors` (at least one), whose density at the median point (every
    /// factor's `sample_1d(0.5)`) must be a finite normal float and whose peak (found on a
    /// grid of 257 samples per factor) must be finite: a product of many narrow or wide
    /// factors can overflow to infinity, which would make `f / pdf` silently 0, or underflow
    /// to 0.
    ///
    /// ```
    /// use mcint::pdf::{Linear, Pdf1d, ProductPdf, UniformInterval};
    /// assert!(ProductPdf::new(vec![]).is_err());
    /// // 400 factors of density 10 would have density 1e400.
    /// let narrow = || Box::new(UniformInterval::new(0.0, 0.1).unwrap()) as Box<dyn Pdf1d>;
    /// assert!(ProductPdf::new((0..400).map(|_| narrow()).collect()).is_err());
    /// assert!(ProductPdf::new((0..300).map(|_| narrow()).collect()).is_ok());
    /// // Densities 2x on [0, 1): 1.41^1100 at the median, but 2^1100 = inf at the corner.
    /// let ramp = || Box::new(Linear::new(0.0, 1.0, 0.0, 1.0).unwrap()) as Box<dyn Pdf1d>;
    /// assert!(ProductPdf::new((0..1100).map(|_| ramp()).collect()).is_err());
    /// assert!(ProductPdf::new((0..1000).map(|_| ramp()).collect()).is_ok());
    /// ```
    pub fn new(factors: Vec<Box<dyn Pdf1d>>) -> Result<Self> {
        if factors.is_empty() {
            return Err(Error::invalid(
                "factors",
                "[]",
                "at least one one-dimensional pdf",
            ));
        }
        // Multiplied in the order `pdf` uses, so these are values it would compute: the
        // density at the median point, and the product of every factor's largest density at
        // the samples of a grid of canonical points (the peak of a product of independent
        // factors is the product of their peaks).
        let median_density: f64 = factors.iter().map(|p| p.pdf_1d(p.sample_1d(0.5))).product();
        let peak_density: f64 = factors.iter().map(|p| grid_peak(p.as_ref())).product();
        if !(median_density.is_finite()
            && median_density >= f64::MIN_POSITIVE
            && peak_density.is_finite())
        {
            return Err(Error::invalid(
                "factors",
                format!(
                    "{} pdfs with density {median_density:e} at their median and up to \
                     {peak_density:e}",
                    factors.len()
                ),
                "factors whose product density is a finite normal float at the median and \
                 finite everywhere (use fewer, or less narrow or wide, factors)",
            ));
        }
        Ok(ProductPdf { factors })
    }
}

/// Canonical points (plus one) at which [`grid_peak`] evaluates a factor.
const PEAK_GRID: u32 = 256;

/// The largest density of `p` at its samples of `u = k / 256` (and the largest `u` below one),
/// which finds the peak of unimodal and monotone densities up to the grid spacing.
fn grid_peak(p: &dyn Pdf1d) -> f64 {
    (0..=PEAK_GRID)
        .map(|k| {
            let u = (f64::from(k) / f64::from(PEAK_GRID)).min(1.0 - f64::EPSILON / 2.0);
            p.pdf_1d(p.sample_1d(u))
        })
        .fold(0.0, f64::max)
}

impl std::fmt::Debug for ProductPdf {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let supports: Vec<(f64, f64)> = self.factors.iter().map(|p| p.support()).collect();
        f.debug_struct("ProductPdf")
            .field("supports", &supports)
            .finish()
    }
}

impl Pdf for ProductPdf {
    fn canonical_dims(&self) -> usize {
        self.factors.len()
    }

    fn dims(&self) -> usize {
        self.factors.len()
    }

    fn sample(&self, u: &[f64], x: &mut [f64]) {
        debug_assert_len!(self, sample, u, canonical_dims);
        debug_assert_len!(self, sample, x, dims);
        // Slicing, not zip alone, makes a too-short slice panic in release builds too.
        let n = self.factors.len();
        for ((x, &u), p) in x[..n].iter_mut().zip(&u[..n]).zip(&self.factors) {
            *x = p.sample_1d(u);
        }
    }

    fn pdf(&self, x: &[f64]) -> f64 {
        debug_assert_len!(self, pdf, x, dims);
        x[..self.factors.len()]
            .iter()
            .zip(&self.factors)
            .map(|(&x, p)| p.pdf_1d(x))
            .product()
    }

    fn invert(&self, x: &[f64], u: &mut [f64]) -> Result<()> {
        debug_assert_len!(self, invert, x, dims);
        debug_assert_len!(self, invert, u, canonical_dims);
        let n = self.factors.len();
        for ((u, &x), p) in u[..n].iter_mut().zip(&x[..n]).zip(&self.factors) {
            *u = p.invert_1d(x);
        }
        Ok(())
    }
}
