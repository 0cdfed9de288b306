//! The basic Monte Carlo estimator over a box (Jarosz's A.14) for an integrand with several
//! outputs, written per point.

use super::VectorEstimator;
use super::box_block::{is_unit, with_mapped};
use crate::pdf::{Pdf, UniformBox};
use crate::points::Points;

/// `volume * f(x)` for each output of `f(x, out)`, with `x` uniform in a box: output `k` gets
/// exactly the bits [`UniformEstimator`](super::UniformEstimator) gives for the scalar
/// integrand `f_k`. Each call starts with `out` filled with NaN, so an output the integrand
/// forgets to write is reported as a non-finite contribution of that output, not read as a
/// stale value.
///
/// ```
/// use mcint::Integrator;
/// use mcint::pdf::UniformBox;
/// // E[x] and E[x^2] of a uniform x in [0, 1): 1/2 and 1/3, over the same points.
/// let moments = |x: &[f64], out: &mut [f64]| {
///     out[0] = x[0];
///     out[1] = x[0] * x[0];
/// };
/// let run = Integrator::over_box_vector(2, moments, UniformBox::unit(1).unwrap())
///     .samples(100_000)
///     .run()
///     .unwrap();
/// assert!((run.outputs[0].mean - 0.5).abs() < 5.0 * run.outputs[0].std_error.unwrap());
/// assert!((run.outputs[1].mean - 1.0 / 3.0).abs() < 5.0 * run.outputs[1].std_error.unwrap());
/// assert_eq!(run.evaluations, 100_000); // one evaluation per point for both outputs
/// ```
#[derive(Debug, Clone)]
pub struct VectorUniformEstimator<F> {
    outputs: usize,
    f: F,
    domain: UniformBox,
    unit: bool,
}

impl<F: Fn(&[f64], &mut [f64]) + Send + Sync> VectorUniformEstimator<F> {
    /// The estimator of the `outputs` integrals of `f` over `domain` (`outputs` in
    /// `1..=`[`MAX_OUTPUTS`](super::MAX_OUTPUTS), checked when a run starts).
    ///
    /// ```
    /// use mcint::estimator::VectorUniformEstimator;
    /// use mcint::pdf::UniformBox;
    /// let f = |_: &[f64], out: &mut [f64]| out.fill(1.0);
    /// use mcint::Integrator;
    /// let none = VectorUniformEstimator::new(0, f, UniformBox::unit(1).unwrap());
    /// assert!(Integrator::new_vector(none).run().unwrap_err().to_string().contains("1 to 256 outputs"));
    /// ```
    pub fn new(outputs: usize, f: F, domain: UniformBox) -> Self {
        let unit = is_unit(&domain);
        VectorUniformEstimator {
            outputs,
            f,
            domain,
            unit,
        }
    }

    /// The integration domain.
    ///
    /// ```
    /// use mcint::estimator::VectorUniformEstimator;
    /// use mcint::pdf::UniformBox;
    /// let f = |_: &[f64], out: &mut [f64]| out.fill(1.0);
    /// let e = VectorUniformEstimator::new(1, f, UniformBox::unit(2).unwrap());
    /// assert_eq!(e.domain().volume(), 1.0);
    /// ```
    pub fn domain(&self) -> &UniformBox {
        &self.domain
    }
}

impl<F: Fn(&[f64], &mut [f64]) + Send + Sync> VectorEstimator for VectorUniformEstimator<F> {
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
        out.fill(f64::NAN);
        (self.f)(x, out);
        let volume = self.domain.volume();
        for y in out.iter_mut() {
            *y *= volume;
        }
    }

    fn contributions(&self, points: &Points, out: &mut [f64]) {
        let (len, m) = (points.len(), self.outputs);
        let volume = self.domain.volume();
        with_mapped(&self.domain, self.unit, points, |mapped| {
            let mut x = vec![0.0; mapped.dims()];
            let mut row = vec![0.0; m];
            for i in 0..len {
                mapped.copy_point(i, &mut x);
                row.fill(f64::NAN);
                (self.f)(&x, &mut row);
                for (k, &y) in row.iter().enumerate() {
                    // The scalar estimator's `volume * f`: IEEE multiplication commutes.
                    out[k * len + i] = y * volume;
                }
            }
        });
    }
}
