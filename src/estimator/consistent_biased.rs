//! Jarosz's example of a biased but consistent estimator (A.34, A.35).

use super::Estimator;
use crate::error::Result;
use crate::points::Points;
use crate::sampler::check_block;

/// `(1/(N+1)) sum_{i=0}^{N-1} Y_i`: Jarosz's A.35, kept as a documented teaching example.
///
/// Its expectation is `N F / (N + 1)`, so its bias (A.34) is `-F / (N + 1)`: wrong for every
/// finite `N`, yet consistent, since the bias vanishes as `N` grows. Use the ordinary mean
/// (what [`Integrator`](crate::Integrator) computes) for real work; this type exists to measure
/// bias and mean squared error.
///
/// ```
/// use mcint::estimator::{ConsistentBiased, UniformEstimator};
/// use mcint::pdf::UniformBox;
/// use mcint::Points;
/// let f = UniformEstimator::new(|_: &[f64]| 2.0, UniformBox::unit(1).unwrap());
/// let biased = ConsistentBiased::new(f);
/// let points = Points::new(1, 4).unwrap();
/// assert_eq!(biased.estimate(&points).unwrap(), 2.0 * 4.0 / 5.0);
/// assert_eq!(ConsistentBiased::<()>::bias(2.0, 4), -0.4);
/// ```
#[derive(Debug, Clone)]
pub struct ConsistentBiased<E> {
    inner: E,
}

impl<E> ConsistentBiased<E> {
    /// Wraps an estimator whose contributions are averaged with `N + 1` in the denominator.
    ///
    /// ```
    /// let _ = mcint::estimator::ConsistentBiased::new(());
    /// ```
    pub fn new(inner: E) -> Self {
        ConsistentBiased { inner }
    }

    /// The exact bias `E[<F^N>] - F = -F / (N + 1)` for an integral `F` (A.34).
    ///
    /// ```
    /// assert_eq!(mcint::estimator::ConsistentBiased::<()>::bias(1.0, 9), -0.1);
    /// ```
    pub fn bias(exact: f64, n: u64) -> f64 {
        -exact / (n as f64 + 1.0)
    }

    /// The exact mean squared error, `variance + bias^2`, for `N` independent samples whose
    /// contributions have variance `sigma2`: `N sigma2 / (N+1)^2 + F^2 / (N+1)^2`.
    ///
    /// ```
    /// use mcint::estimator::ConsistentBiased;
    /// assert_eq!(ConsistentBiased::<()>::mse(1.0, 1, 0.0), 0.25);
    /// ```
    pub fn mse(exact: f64, n: u64, sigma2: f64) -> f64 {
        let n = n as f64;
        (n * sigma2 + exact * exact) / ((n + 1.0) * (n + 1.0))
    }
}

impl<E: Estimator> ConsistentBiased<E> {
    /// The biased estimate from the canonical points of `points` (`N = points.len()`).
    ///
    /// ```
    /// use mcint::estimator::{ConsistentBiased, UniformEstimator};
    /// let e = ConsistentBiased::new(UniformEstimator::new(|_: &[f64]| 1.0, mcint::pdf::UniformBox::unit(2).unwrap()));
    /// assert!(e.estimate(&mcint::Points::new(3, 2).unwrap()).is_err()); // wrong dimension
    /// ```
    pub fn estimate(&self, points: &Points) -> Result<f64> {
        check_block(self.inner.canonical_dims(), 0, points)?;
        let mut values = vec![0.0; points.len()];
        self.inner.contributions(points, &mut values);
        Ok(values.iter().sum::<f64>() / (points.len() as f64 + 1.0))
    }
}
