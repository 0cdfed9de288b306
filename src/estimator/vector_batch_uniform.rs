//! The uniform estimator over a box for a batch integrand with several outputs: one call per
//! block of points.

use super::VectorEstimator;
use super::box_block::{evaluate_scaled, is_unit, with_mapped};
use super::{DEFAULT_POINTS_PER_CALL, checked_points_per_call};
use crate::error::Result;
use crate::pdf::{Pdf, UniformBox};
use crate::points::Points;

/// The uniform estimator for a batch integrand `f(points, out)` with `m` outputs: `points` is
/// a block of up to 1024 domain points (one column per coordinate) and `f` writes output `k`
/// of point `i` to `out[k * points.len() + i]` (one column per output). `out` starts filled
/// with NaN, so a value left unwritten is reported as non-finite, with its output. With the
/// same arithmetic per point, the estimate has the same bits as
/// [`VectorUniformEstimator`](super::VectorUniformEstimator).
///
/// ```
/// use mcint::{Integrator, Points, pdf::UniformBox};
/// // An RGB pixel: three color channels of one integrand over the same points.
/// let shade = |p: &Points, out: &mut [f64]| {
///     let n = p.len();
///     for i in 0..n {
///         let (x, y) = (p.column(0)[i], p.column(1)[i]);
///         out[i] = x;             // red
///         out[n + i] = y;         // green
///         out[2 * n + i] = x * y; // blue
///     }
/// };
/// let pixel = Integrator::over_box_vector_batch(3, shade, UniformBox::unit(2).unwrap())
///     .samples(50_000)
///     .run()
///     .unwrap();
/// for (channel, exact) in pixel.outputs.iter().zip([0.5, 0.5, 0.25]) {
///     assert!((channel.mean - exact).abs() < 5.0 * channel.std_error.unwrap());
/// }
/// ```
#[derive(Debug, Clone)]
pub struct BatchVectorUniformEstimator<F> {
    outputs: usize,
    f: F,
    domain: UniformBox,
    unit: bool,
    /// The most points per call of `f`.
    per_call: usize,
}

impl<F: Fn(&Points, &mut [f64]) + Send + Sync> BatchVectorUniformEstimator<F> {
    /// The estimator of the `outputs` integrals of the batch integrand `f` over `domain`
    /// (`outputs` in `1..=`[`MAX_OUTPUTS`](super::MAX_OUTPUTS), checked when a run starts).
    ///
    /// ```
    /// use mcint::{Points, estimator::BatchVectorUniformEstimator, pdf::UniformBox};
    /// let f = |_: &Points, out: &mut [f64]| out.fill(1.0);
    /// use mcint::estimator::VectorEstimator;
    /// assert_eq!(BatchVectorUniformEstimator::new(2, f, UniformBox::unit(1).unwrap()).outputs(), 2);
    /// ```
    pub fn new(outputs: usize, f: F, domain: UniformBox) -> Self {
        let unit = is_unit(&domain);
        BatchVectorUniformEstimator {
            outputs,
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
    /// use mcint::estimator::{BatchVectorUniformEstimator, VectorEstimator};
    /// use mcint::pdf::UniformBox;
    /// let f = |_: &mcint::Points, out: &mut [f64]| out.fill(1.0);
    /// let e = BatchVectorUniformEstimator::new(2, f, UniformBox::unit(1).unwrap());
    /// assert_eq!(e.with_points_per_call(4096).unwrap().points_per_call(), 4096);
    /// ```
    pub fn with_points_per_call(mut self, points: usize) -> Result<Self> {
        self.per_call = checked_points_per_call(points)?;
        Ok(self)
    }

    fn evaluate(&self, mapped: &Points, out: &mut [f64]) {
        let out = &mut out[..self.outputs * mapped.len()];
        evaluate_scaled(self.domain.volume(), out, |out| (self.f)(mapped, out));
    }
}

impl<F: Fn(&Points, &mut [f64]) + Send + Sync> VectorEstimator for BatchVectorUniformEstimator<F> {
    fn points_per_call(&self) -> usize {
        self.per_call
    }

    fn outputs(&self) -> usize {
        self.outputs
    }

    fn canonical_dims(&self) -> usize {
        self.domain.dims()
    }

    fn domain_dims(&self) -> usize {
        self.domain.dims()
    }

    fn contribution(&self, u: &[f64], x: &mut [f64], out: &mut [f64]) {
        self.domain.sample(u, x);
        // A box has at least one dimension, so the block of one point exists.
        let Ok(block) = Points::from_rows(&[&*x]) else {
            return out.fill(f64::NAN);
        };
        self.evaluate(&block, out);
    }

    fn contributions(&self, points: &Points, out: &mut [f64]) {
        with_mapped(&self.domain, self.unit, points, |mapped| {
            self.evaluate(mapped, out)
        });
    }
}
