//! The estimator of an integral against a [`Measure`]: `f(T(u)) w(u)`.

use super::{Estimator, VectorEstimator};
use crate::measure::Measure;

/// `f(T(u)) w(u)` for a [`Measure`]'s map `T` and weight `w`: the mean estimates
/// `E[f(X)]` under a probability law, or the integral of `f` for a Lebesgue measure. A zero
/// `f` contributes zero whatever the weight (no `0 * inf`).
///
/// ```
/// use mcint::estimator::{Estimator, ExpectationEstimator};
/// use mcint::measure::Gaussian;
/// let e = ExpectationEstimator::new(|x: &[f64]| x[0] * x[0], Gaussian::standard(1).unwrap());
/// let mut x = [0.0];
/// assert_eq!(e.contribution(&[0.5], &mut x), 0.0); // the median 0, squared
/// ```
#[derive(Debug, Clone)]
pub struct ExpectationEstimator<F, M> {
    f: F,
    measure: M,
}

impl<F, M: Measure> ExpectationEstimator<F, M> {
    /// The estimator of `int f dmeasure`.
    ///
    /// ```
    /// use mcint::estimator::ExpectationEstimator;
    /// use mcint::measure::Gaussian;
    /// let e = ExpectationEstimator::new(|x: &[f64]| x[0], Gaussian::standard(1).unwrap());
    /// assert_eq!(e.measure().mean(), &[0.0]);
    /// ```
    pub fn new(f: F, measure: M) -> Self {
        ExpectationEstimator { f, measure }
    }

    /// The measure.
    ///
    /// ```
    /// use mcint::estimator::ExpectationEstimator;
    /// use mcint::measure::{Gaussian, Measure};
    /// let e = ExpectationEstimator::new(|x: &[f64]| x[0], Gaussian::standard(2).unwrap());
    /// assert_eq!(e.measure().dims(), 2);
    /// ```
    pub fn measure(&self) -> &M {
        &self.measure
    }
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync, M: Measure> Estimator for ExpectationEstimator<F, M> {
    fn canonical_dims(&self) -> usize {
        self.measure.canonical_dims()
    }

    fn domain_dims(&self) -> usize {
        self.measure.dims()
    }

    #[inline]
    fn contribution(&self, u: &[f64], x: &mut [f64]) -> f64 {
        let weight = self.measure.map(u, x);
        let value = (self.f)(x);
        if value == 0.0 { 0.0 } else { value * weight }
    }
}

/// [`ExpectationEstimator`] for an integrand with `outputs` outputs (`f(x, out)`).
///
/// ```
/// use mcint::Integrator;
/// use mcint::measure::Gaussian;
/// // The first two moments of a standard normal over the same points.
/// let f = |x: &[f64], out: &mut [f64]| { out[0] = x[0]; out[1] = x[0] * x[0]; };
/// let run = Integrator::expectation_vector(2, f, Gaussian::standard(1).unwrap()).samples(100_000).run().unwrap();
/// assert!((run.outputs[1].mean - 1.0).abs() < 5.0 * run.outputs[1].std_error.unwrap());
/// ```
#[derive(Debug, Clone)]
pub struct VectorExpectationEstimator<F, M> {
    outputs: usize,
    f: F,
    measure: M,
}

impl<F, M: Measure> VectorExpectationEstimator<F, M> {
    /// The estimator of the `outputs` integrals of `f` against `measure` (`outputs` checked
    /// when a run starts).
    ///
    /// ```
    /// use mcint::estimator::{VectorEstimator, VectorExpectationEstimator};
    /// use mcint::measure::Gaussian;
    /// let f = |x: &[f64], out: &mut [f64]| out.fill(x[0]);
    /// assert_eq!(VectorExpectationEstimator::new(3, f, Gaussian::standard(1).unwrap()).outputs(), 3);
    /// ```
    pub fn new(outputs: usize, f: F, measure: M) -> Self {
        VectorExpectationEstimator {
            outputs,
            f,
            measure,
        }
    }
}

impl<F: Fn(&[f64], &mut [f64]) + Send + Sync, M: Measure> VectorEstimator
    for VectorExpectationEstimator<F, M>
{
    fn outputs(&self) -> usize {
        self.outputs
    }

    fn canonical_dims(&self) -> usize {
        self.measure.canonical_dims()
    }

    fn domain_dims(&self) -> usize {
        self.measure.dims()
    }

    fn contribution(&self, u: &[f64], x: &mut [f64], out: &mut [f64]) {
        let weight = self.measure.map(u, x);
        out.fill(f64::NAN);
        (self.f)(x, out);
        for y in out.iter_mut() {
            if *y != 0.0 {
                *y *= weight;
            }
        }
    }
}
