//! The general `f/pdf` estimator (Jarosz's A.19): importance sampling.

use super::Estimator;
use crate::pdf::Pdf;

/// `<F^N> = (1/N) sum f(X_i) / pdf(X_i)` with `X_i` drawn from `pdf` (A.19).
///
/// The estimate is unbiased when `pdf > 0` wherever `f != 0`. Where `f(x) = 0` the
/// contribution is 0 whatever the pdf; where the pdf is zero but `f` is not, the contribution
/// is infinite (or NaN), which the integrator reports as an error instead of averaging.
///
/// ```
/// use mcint::estimator::{Estimator, ImportanceEstimator};
/// use mcint::pdf::Linear;
/// // f(x) = 2x on [0,1] sampled exactly proportionally: every contribution is the integral, 1.
/// let e = ImportanceEstimator::new(|x: &[f64]| 2.0 * x[0], Linear::new(0.0, 1.0, 0.0, 1.0).unwrap());
/// let mut x = [0.0];
/// for u in [0.1, 0.5, 0.9] {
///     assert!((e.contribution(&[u], &mut x) - 1.0).abs() < 1e-15);
/// }
/// ```
#[derive(Debug, Clone)]
pub struct ImportanceEstimator<F, P> {
    f: F,
    pdf: P,
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync, P: Pdf> ImportanceEstimator<F, P> {
    /// Estimates the integral of `f` over the pdf's domain, sampling from `pdf`.
    ///
    /// ```
    /// use mcint::estimator::ImportanceEstimator;
    /// use mcint::pdf::{Exponential, Pdf};
    /// let e = ImportanceEstimator::new(|x: &[f64]| (-x[0]).exp(), Exponential::new(1.0, 0.0, f64::INFINITY).unwrap());
    /// assert_eq!(e.pdf().dims(), 1);
    /// ```
    pub fn new(f: F, pdf: P) -> Self {
        ImportanceEstimator { f, pdf }
    }

    /// The sampling density.
    ///
    /// ```
    /// use mcint::pdf::Pdf;
    /// let e = mcint::estimator::ImportanceEstimator::new(|_: &[f64]| 1.0, mcint::pdf::UniformBox::unit(2).unwrap());
    /// assert_eq!(e.pdf().canonical_dims(), 2);
    /// ```
    pub fn pdf(&self) -> &P {
        &self.pdf
    }
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync, P: Pdf> Estimator for ImportanceEstimator<F, P> {
    fn canonical_dims(&self) -> usize {
        self.pdf.canonical_dims()
    }

    fn domain_dims(&self) -> usize {
        self.pdf.dims()
    }

    #[inline]
    fn contribution(&self, u: &[f64], x: &mut [f64]) -> f64 {
        self.pdf.sample(u, x);
        let value = (self.f)(x);
        if value == 0.0 {
            // Zero integrand contributes zero even where the pdf is zero (no 0/0).
            return 0.0;
        }
        value / self.pdf.pdf(x)
    }
}
