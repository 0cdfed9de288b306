//! The uniform estimator over a box for a batch integrand: one call per block of points.

use super::Estimator;
use super::box_block::{evaluate_scaled, is_unit, with_mapped};
use super::{DEFAULT_POINTS_PER_CALL, checked_points_per_call};
use crate::error::Result;
use crate::pdf::{Pdf, UniformBox};
use crate::points::Points;

/// `<F^N> = V (1/N) sum f(X_i)` with `X_i` uniform in a box of volume `V` (A.14), for an
/// integrand that evaluates a whole block of points per call.
///
/// The integrand `f(points, out)` receives a block of domain points in structure-of-arrays
/// layout (one contiguous column per coordinate, see [`Points`]) and must write `f(X_i)` to
/// `out[i]` for **every** `i < points.len()` (`out.len() == points.len()`). That lets it loop
/// over columns in unit stride, vectorize, or hand the block to other code. The
/// [`Integrator`](crate::Integrator) calls it with blocks of up to 1024 points, generated just
/// before, so the points are still in cache.
///
/// `out` is filled with NaN before each call: a value the integrand leaves unwritten is NaN,
/// so it is caught like any other non-finite value by the run's
/// [`NonFinitePolicy`](crate::NonFinitePolicy) (an error by default; under `Skip` such values
/// are silently dropped and only counted).
///
/// The estimate has the same bits as [`UniformEstimator`](super::UniformEstimator) with the
/// same sampler and seed, provided `f` computes each value with the same arithmetic as the
/// per-point integrand: points are mapped into the box coordinate by coordinate exactly as
/// [`UniformBox`] maps one point, and each value is multiplied by the volume. Over the unit
/// cube the canonical block is passed as it is (no copy); over any other box it is mapped into
/// a per-thread scratch block, so no block allocates.
///
/// ```
/// use mcint::Points;
/// use mcint::estimator::{BatchUniformEstimator, Estimator};
/// use mcint::pdf::UniformBox;
/// // f(x, y) = x + y, one column at a time.
/// let sum = |p: &Points, out: &mut [f64]| {
///     out.copy_from_slice(p.column(0));
///     for (y, &x1) in out.iter_mut().zip(p.column(1)) {
///         *y += x1;
///     }
/// };
/// let e = BatchUniformEstimator::new(sum, UniformBox::new(vec![0.0; 2], vec![2.0; 2]).unwrap());
/// let mut block = Points::new(2, 2).unwrap();
/// block.column_mut(0).copy_from_slice(&[0.25, 0.5]);
/// block.column_mut(1).copy_from_slice(&[0.5, 0.5]);
/// let mut out = [0.0; 2];
/// e.contributions(&block, &mut out);
/// // Volume 4 times f at (0.5, 1.0) and (1.0, 1.0).
/// assert_eq!(out, [4.0 * 1.5, 4.0 * 2.0]);
/// ```
#[derive(Debug, Clone)]
pub struct BatchUniformEstimator<F> {
    f: F,
    domain: UniformBox,
    /// The domain is `[0,1)^d`: canonical points need no mapping.
    unit: bool,
    /// The most points per call of `f`.
    per_call: usize,
}

impl<F: Fn(&Points, &mut [f64]) + Send + Sync> BatchUniformEstimator<F> {
    /// Estimates the integral of the batch integrand `f` over `domain`.
    ///
    /// ```
    /// use mcint::{Points, estimator::BatchUniformEstimator, pdf::UniformBox};
    /// let e = BatchUniformEstimator::new(|_: &Points, out: &mut [f64]| out.fill(1.0), UniformBox::unit(2).unwrap());
    /// assert_eq!(e.domain().volume(), 1.0);
    /// ```
    pub fn new(f: F, domain: UniformBox) -> Self {
        let unit = is_unit(&domain);
        BatchUniformEstimator {
            f,
            domain,
            unit,
            per_call: DEFAULT_POINTS_PER_CALL,
        }
    }

    /// Asks for calls of `f` on up to `points` points (1 to 2^20; default 1024): more for an
    /// integrand that pays a cost per call (an interpreter, a GPU kernel). The Integrator
    /// calls with whole blocks of 1024 points, as many as fit in `points` (at least one, at
    /// most the 16 of a chunk of work), and still sums contributions 1024 at a time, so the
    /// estimate has the same bits.
    ///
    /// ```
    /// use mcint::estimator::{BatchUniformEstimator, Estimator};
    /// use mcint::{Integrator, Points, pdf::UniformBox};
    /// let sum = |p: &Points, out: &mut [f64]| {
    ///     assert!(p.len() <= 8192);
    ///     for (y, (a, b)) in out.iter_mut().zip(p.column(0).iter().zip(p.column(1))) {
    ///         *y = a + b;
    ///     }
    /// };
    /// let square = || UniformBox::unit(2).unwrap();
    /// let big = BatchUniformEstimator::new(sum, square()).with_points_per_call(8192).unwrap();
    /// assert_eq!(big.points_per_call(), 8192);
    /// let by_8192 = Integrator::new(big).samples(20_000).run().unwrap();
    /// let by_1024 = Integrator::over_box_batch(sum, square()).samples(20_000).run().unwrap();
    /// assert_eq!(by_8192, by_1024);
    /// assert!(BatchUniformEstimator::new(sum, square()).with_points_per_call(0).is_err());
    /// ```
    pub fn with_points_per_call(mut self, points: usize) -> Result<Self> {
        self.per_call = checked_points_per_call(points)?;
        Ok(self)
    }

    /// The integration domain.
    ///
    /// ```
    /// use mcint::{Points, estimator::BatchUniformEstimator, pdf::UniformBox};
    /// let e = BatchUniformEstimator::new(|_: &Points, out: &mut [f64]| out.fill(0.0), UniformBox::unit(3).unwrap());
    /// assert_eq!(e.domain().lo().len(), 3);
    /// ```
    pub fn domain(&self) -> &UniformBox {
        &self.domain
    }

    /// Evaluates `f` on `mapped` (domain points) and scales by the volume.
    fn evaluate(&self, mapped: &Points, out: &mut [f64]) {
        evaluate_scaled(self.domain.volume(), out, |out| (self.f)(mapped, out));
    }
}

impl<F: Fn(&Points, &mut [f64]) + Send + Sync> Estimator for BatchUniformEstimator<F> {
    fn points_per_call(&self) -> usize {
        self.per_call
    }

    fn canonical_dims(&self) -> usize {
        self.domain.dims()
    }

    fn domain_dims(&self) -> usize {
        self.domain.dims()
    }

    /// One point as a block of one: allocates, so it is slow; the Integrator uses
    /// [`contributions`](Estimator::contributions).
    fn contribution(&self, u: &[f64], x: &mut [f64]) -> f64 {
        self.domain.sample(u, x);
        // A box has at least one dimension, so the block of one point exists.
        let Ok(block) = Points::from_rows(&[&*x]) else {
            return f64::NAN;
        };
        let mut out = [0.0];
        self.evaluate(&block, &mut out);
        out[0]
    }

    fn contributions(&self, points: &Points, out: &mut [f64]) {
        let out = &mut out[..points.len()];
        with_mapped(&self.domain, self.unit, points, |mapped| {
            self.evaluate(mapped, out)
        });
    }
}
