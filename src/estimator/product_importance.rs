//! Importance sampling one known factor of a product integrand: Jarosz's A.25.
//!
//! When `f(x) = g(x) h(x)` and `g` can be sampled exactly, the seed takes
//! `pdf_g(x) = c g(x)`, so that `c = 1 / integral g` (the normalisation of A.24 applied to `g`),
//! and A.19 simplifies to
//!
//! ```text
//! <F^N> = (1/N) sum f(X_i) / pdf_g(X_i) = (1/N) sum g(X_i) h(X_i) / (c g(X_i)) = (1/(c N)) sum h(X_i)
//! ```
//!
//! (A.25). Only `h` is evaluated, and the variance is that of `h` under `pdf_g` times
//! `(integral g)^2`, small when `h` is smoother than `g h`.

use super::Estimator;
use crate::error::{Error, Result};
use crate::pdf::Pdf;

/// The estimator `Y = h(X) / c = G h(X)` of A.25, with `X` drawn from `pdf_g = g / G`, where
/// `G = integral g = 1/c`.
///
/// The user supplies the pdf proportional to `g` (sampled exactly) and `G`; nothing checks that
/// the pdf really is `g / G`, since the point of A.25 is that neither `g` nor the pdf is
/// evaluated. The estimate is unbiased for `integral g h` exactly when it is; with any other
/// density the mean is `G integral h pdf`.
///
/// ```
/// use mcint::estimator::{Estimator, ProductImportanceEstimator};
/// use mcint::pdf::Exponential;
/// // f(x) = g h with g = exp(-x) on [0, inf) (G = 1) and h = x^2: the integral is 2.
/// let e = ProductImportanceEstimator::new(|x: &[f64]| x[0] * x[0], Exponential::new(1.0, 0.0, f64::INFINITY)?, 1.0)?;
/// let mut x = [0.0];
/// assert_eq!(e.contribution(&[0.5], &mut x), x[0] * x[0]);
/// let estimate = mcint::Integrator::new(e).samples(50_000).seed(3).run()?;
/// assert!((estimate.mean - 2.0).abs() < 5.0 * estimate.std_error.unwrap());
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct ProductImportanceEstimator<H, P> {
    h: H,
    pdf_g: P,
    g_integral: f64,
}

impl<H: Fn(&[f64]) -> f64 + Send + Sync, P: Pdf> ProductImportanceEstimator<H, P> {
    /// Estimates `integral g h` from `h`, the pdf `pdf_g = g / G` and `g_integral = G`, the
    /// integral of `g` (finite and `> 0`).
    ///
    /// ```
    /// use mcint::estimator::ProductImportanceEstimator;
    /// use mcint::pdf::UniformInterval;
    /// let pdf = || UniformInterval::new(0.0, 1.0).unwrap();
    /// assert!(ProductImportanceEstimator::new(|x: &[f64]| x[0], pdf(), 0.0).is_err());
    /// assert_eq!(ProductImportanceEstimator::new(|x: &[f64]| x[0], pdf(), 2.0).unwrap().g_integral(), 2.0);
    /// ```
    pub fn new(h: H, pdf_g: P, g_integral: f64) -> Result<Self> {
        if !(g_integral.is_finite() && g_integral > 0.0) {
            return Err(Error::invalid(
                "g_integral",
                g_integral,
                "the integral of g: finite and > 0",
            ));
        }
        Ok(ProductImportanceEstimator {
            h,
            pdf_g,
            g_integral,
        })
    }

    /// The same estimator in Jarosz's notation: `pdf_g = c g`, so `c = 1 / integral g`
    /// (finite and `> 0`) and each contribution is `h(X) / c` (A.25).
    ///
    /// ```
    /// use mcint::estimator::{Estimator, ProductImportanceEstimator};
    /// use mcint::pdf::UniformInterval;
    /// // g = 2 on [0, 1): pdf_g = 1 = c g with c = 1/2.
    /// let e = ProductImportanceEstimator::from_normalization(|x: &[f64]| x[0], UniformInterval::new(0.0, 1.0).unwrap(), 0.5).unwrap();
    /// let mut x = [0.0];
    /// assert_eq!(e.contribution(&[0.25], &mut x), 0.25 / 0.5);
    /// assert!(ProductImportanceEstimator::from_normalization(|x: &[f64]| x[0], UniformInterval::new(0.0, 1.0).unwrap(), -1.0).is_err());
    /// ```
    pub fn from_normalization(h: H, pdf_g: P, c: f64) -> Result<Self> {
        if !(c.is_finite() && c > 0.0) {
            return Err(Error::invalid(
                "c",
                c,
                "Jarosz's normalisation pdf_g = c g: finite and > 0",
            ));
        }
        let g_integral = 1.0 / c;
        if !g_integral.is_finite() {
            return Err(Error::invalid(
                "c",
                c,
                "a normalisation whose reciprocal 1/c is finite",
            ));
        }
        Ok(ProductImportanceEstimator {
            h,
            pdf_g,
            g_integral,
        })
    }

    /// `G`, the integral of `g` (Jarosz's `1/c`).
    ///
    /// ```
    /// use mcint::estimator::ProductImportanceEstimator;
    /// let e = ProductImportanceEstimator::from_normalization(|_: &[f64]| 1.0, mcint::pdf::UniformInterval::new(0.0, 1.0).unwrap(), 4.0).unwrap();
    /// assert_eq!(e.g_integral(), 0.25);
    /// ```
    pub fn g_integral(&self) -> f64 {
        self.g_integral
    }

    /// The pdf proportional to `g`.
    ///
    /// ```
    /// use mcint::estimator::ProductImportanceEstimator;
    /// use mcint::pdf::Pdf;
    /// let e = ProductImportanceEstimator::new(|_: &[f64]| 1.0, mcint::pdf::UniformBox::unit(2).unwrap(), 1.0).unwrap();
    /// assert_eq!(e.pdf_g().dims(), 2);
    /// ```
    pub fn pdf_g(&self) -> &P {
        &self.pdf_g
    }
}

impl<H: Fn(&[f64]) -> f64 + Send + Sync, P: Pdf> Estimator for ProductImportanceEstimator<H, P> {
    fn canonical_dims(&self) -> usize {
        self.pdf_g.canonical_dims()
    }

    fn domain_dims(&self) -> usize {
        self.pdf_g.dims()
    }

    #[inline]
    fn contribution(&self, u: &[f64], x: &mut [f64]) -> f64 {
        self.pdf_g.sample(u, x);
        self.g_integral * (self.h)(x)
    }
}
