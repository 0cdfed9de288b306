//! The `f/pdf` estimator (Jarosz's A.19) for an integrand with several outputs.

use super::VectorEstimator;
use crate::pdf::Pdf;

/// `f_k(x) / pdf(x)` for each output of `f(x, out)`, with `x` drawn from `pdf`: output `k`
/// gets exactly the bits [`ImportanceEstimator`](super::ImportanceEstimator) gives for `f_k`
/// (a zero output contributes zero even where the pdf is zero). `out` starts filled with NaN.
///
/// Self-normalized importance sampling is a ratio of two such outputs (see
/// [`Derived::ratio`](crate::stats::Derived::ratio)).
///
/// ```
/// use mcint::Integrator;
/// use mcint::pdf::Exponential;
/// use mcint::stats::Derived;
/// // A posterior mean: E[x] under the density proportional to x e^{-x} on [0, inf), which
/// // is 2, as the ratio of the integrals of x * x e^{-x} and x e^{-x}, sampled from e^{-x}.
/// let pdf = Exponential::new(1.0, 0.0, f64::INFINITY).unwrap();
/// let f = |x: &[f64], out: &mut [f64]| {
///     let weight = x[0] * (-x[0]).exp();
///     out[0] = x[0] * weight;
///     out[1] = weight;
/// };
/// let run = Integrator::with_pdf_vector(2, f, pdf).samples(100_000).run().unwrap();
/// let mean = run.derived(&Derived::ratio(0, 1)).unwrap();
/// assert!((mean.mean - 2.0).abs() < 5.0 * mean.std_error.unwrap());
/// ```
#[derive(Debug, Clone)]
pub struct VectorImportanceEstimator<F, P> {
    outputs: usize,
    f: F,
    pdf: P,
}

impl<F: Fn(&[f64], &mut [f64]) + Send + Sync, P: Pdf> VectorImportanceEstimator<F, P> {
    /// The estimator of the `outputs` integrals of `f` over the domain of `pdf` (`outputs`
    /// in `1..=`[`MAX_OUTPUTS`](super::MAX_OUTPUTS), checked when a run starts).
    ///
    /// ```
    /// use mcint::estimator::VectorImportanceEstimator;
    /// use mcint::pdf::UniformBox;
    /// let f = |_: &[f64], out: &mut [f64]| out.fill(1.0);
    /// use mcint::{Integrator, estimator::VectorEstimator};
    /// let e = VectorImportanceEstimator::new(usize::MAX, f, UniformBox::unit(1).unwrap());
    /// assert!(Integrator::new_vector(e).run().unwrap_err().to_string().contains("outputs"));
    /// ```
    pub fn new(outputs: usize, f: F, pdf: P) -> Self {
        VectorImportanceEstimator { outputs, f, pdf }
    }
}

impl<F: Fn(&[f64], &mut [f64]) + Send + Sync, P: Pdf> VectorEstimator
    for VectorImportanceEstimator<F, P>
{
    fn outputs(&self) -> usize {
        self.outputs
    }

    fn canonical_dims(&self) -> usize {
        self.pdf.canonical_dims()
    }

    fn domain_dims(&self) -> usize {
        self.pdf.dims()
    }

    fn contribution(&self, u: &[f64], x: &mut [f64], out: &mut [f64]) {
        self.pdf.sample(u, x);
        out.fill(f64::NAN);
        (self.f)(x, out);
        if out.iter().all(|&y| y == 0.0) {
            return;
        }
        let density = self.pdf.pdf(x);
        for y in out.iter_mut() {
            // Zero integrand contributes zero even where the pdf is zero (no 0/0).
            if *y != 0.0 {
                *y /= density;
            }
        }
    }
}
