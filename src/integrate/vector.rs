//! [`VectorRun`]: the Integrator for integrands with several outputs, integrated over the same
//! points by the same engine as scalar ones.

use super::Integrator;
use crate::engine::RunConfig;
use crate::estimator::{
    BatchVectorUniformEstimator, VectorEstimator, VectorExpectationEstimator,
    VectorImportanceEstimator, VectorUniformEstimator,
};
use crate::measure::Measure;
use crate::pdf::{Pdf, UniformBox};
use crate::points::Points;
use crate::stats::{Derived, Tolerance};

/// A [`VectorEstimator`] with the tolerances of its run: what
/// [`Integrator::over_box_vector`] and the other vector constructors integrate.
///
/// Everything the scalar Integrator does, it does for all outputs at once, over the same
/// points and with one integrand evaluation per point: plain, stratified and randomized QMC
/// runs with replicates, thread-count-independent bits, checkpoints
/// ([`run_part`](Integrator::run_part)), runs to a tolerance, non-finite policies (a
/// non-finite value is reported with its output; under
/// [`Skip`](crate::NonFinitePolicy::Skip) each output leaves out its own non-finite values and
/// the covariance uses the points where every output is finite). Output `k` of a vector run
/// has the same bits as the scalar run of `f_k` with the same settings, except in a run to a
/// tolerance, whose stages depend on every output.
///
/// A run to a tolerance stops when every target is met: [`tolerance`](Integrator::tolerance)
/// sets one for every output, [`output_tolerances`](Integrator::output_tolerances) one per
/// output, and [`derived_tolerance`](Integrator::derived_tolerance) one on a function of the
/// integrals; its evaluation and time limits are the tightest any of them sets.
///
/// ```
/// use mcint::{Integrator, pdf::UniformBox};
/// let f = |x: &[f64], out: &mut [f64]| {
///     out[0] = x[0];
///     out[1] = x[0] * x[1];
/// };
/// let run = Integrator::over_box_vector(2, f, UniformBox::unit(2).unwrap())
///     .samples(10_000)
///     .seed(3)
///     .threads(2)
///     .run()
///     .unwrap();
/// assert!((run.outputs[1].mean - 0.25).abs() < 5.0 * run.outputs[1].std_error.unwrap());
/// ```
pub struct VectorRun<E> {
    pub(super) estimator: E,
    pub(super) output_tolerances: Option<Vec<Tolerance>>,
    pub(super) derived_tolerances: Vec<(Derived, Tolerance)>,
}

impl<F: Fn(&[f64], &mut [f64]) + Send + Sync> Integrator<VectorRun<VectorUniformEstimator<F>>> {
    /// Integrates the `outputs` outputs of `f(x, out)` over a box with the uniform estimator
    /// (A.14); `f` writes output `k` to `out[k]`. See [`VectorUniformEstimator`]; a bad
    /// `outputs` (0, or above [`MAX_OUTPUTS`](crate::estimator::MAX_OUTPUTS)) is reported by
    /// `run`.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let f = |x: &[f64], out: &mut [f64]| { out[0] = x[0]; out[1] = 1.0; };
    /// let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap()).samples(1000).run().unwrap();
    /// assert_eq!(run.outputs[1].mean, 1.0);
    /// let none = Integrator::over_box_vector(0, f, UniformBox::unit(1).unwrap()).run();
    /// assert!(none.unwrap_err().to_string().contains("outputs"));
    /// ```
    pub fn over_box_vector(outputs: usize, f: F, domain: UniformBox) -> Self {
        Integrator::new_vector(VectorUniformEstimator::new(outputs, f, domain))
    }
}

impl<F: Fn(&Points, &mut [f64]) + Send + Sync>
    Integrator<VectorRun<BatchVectorUniformEstimator<F>>>
{
    /// Integrates a batch integrand with `outputs` outputs over a box: `f(points, out)`
    /// writes output `k` of point `i` to `out[k * points.len() + i]`. See
    /// [`BatchVectorUniformEstimator`].
    ///
    /// ```
    /// use mcint::{Integrator, Points, pdf::UniformBox};
    /// let f = |p: &Points, out: &mut [f64]| {
    ///     let (x, n) = (p.column(0), p.len());
    ///     for i in 0..n {
    ///         out[i] = x[i];
    ///         out[n + i] = x[i] * x[i];
    ///     }
    /// };
    /// let per_point = |x: &[f64], out: &mut [f64]| { out[0] = x[0]; out[1] = x[0] * x[0]; };
    /// let batch = Integrator::over_box_vector_batch(2, f, UniformBox::unit(1).unwrap()).samples(5000).run().unwrap();
    /// let single = Integrator::over_box_vector(2, per_point, UniformBox::unit(1).unwrap()).samples(5000).run().unwrap();
    /// assert_eq!(batch, single);
    /// ```
    pub fn over_box_vector_batch(outputs: usize, f: F, domain: UniformBox) -> Self {
        Integrator::new_vector(BatchVectorUniformEstimator::new(outputs, f, domain))
    }
}

impl<F: Fn(&[f64], &mut [f64]) + Send + Sync, P: Pdf>
    Integrator<VectorRun<VectorImportanceEstimator<F, P>>>
{
    /// Integrates the `outputs` outputs of `f(x, out)` over the domain of `pdf`, sampling
    /// from `pdf` (A.19). See [`VectorImportanceEstimator`].
    ///
    /// ```
    /// use mcint::{Integrator, pdf::Exponential};
    /// let pdf = Exponential::new(1.0, 0.0, f64::INFINITY).unwrap();
    /// let f = |x: &[f64], out: &mut [f64]| { out[0] = (-x[0]).exp(); out[1] = x[0] * (-x[0]).exp(); };
    /// let run = Integrator::with_pdf_vector(2, f, pdf).samples(1000).run().unwrap();
    /// assert!((run.outputs[0].mean - 1.0).abs() < 1e-12); // f/pdf is exactly 1
    /// ```
    pub fn with_pdf_vector(outputs: usize, f: F, pdf: P) -> Self {
        Integrator::new_vector(VectorImportanceEstimator::new(outputs, f, pdf))
    }
}

impl<F: Fn(&[f64], &mut [f64]) + Send + Sync, M: Measure>
    Integrator<VectorRun<VectorExpectationEstimator<F, M>>>
{
    /// Integrates the `outputs` outputs of `f(x, out)` against `measure` (see
    /// [`Integrator::expectation`]).
    ///
    /// ```
    /// use mcint::{Integrator, measure::Gaussian, stats::Derived};
    /// // P(X > 1) and E[X | X > 1] for a standard normal, over the same points.
    /// let f = |x: &[f64], out: &mut [f64]| {
    ///     let above = f64::from(u8::from(x[0] > 1.0));
    ///     out[0] = above;
    ///     out[1] = above * x[0];
    /// };
    /// let run = Integrator::expectation_vector(2, f, Gaussian::standard(1).unwrap()).samples(400_000).run().unwrap();
    /// let conditional = run.derived(&Derived::ratio(1, 0)).unwrap();
    /// let exact = (-0.5f64).exp() / (2.0 * std::f64::consts::PI).sqrt() / 0.158_655_253_931_457_05;
    /// assert!((conditional.mean - exact).abs() < 5.0 * conditional.std_error.unwrap());
    /// ```
    pub fn expectation_vector(outputs: usize, f: F, measure: M) -> Self {
        Integrator::new_vector(VectorExpectationEstimator::new(outputs, f, measure))
    }
}

impl<E: VectorEstimator> Integrator<VectorRun<E>> {
    /// An integrator for any vector estimator, with the defaults of [`Integrator::new`].
    ///
    /// ```
    /// use mcint::{Integrator, estimator::VectorUniformEstimator, pdf::UniformBox};
    /// let f = |_: &[f64], out: &mut [f64]| { out[0] = 1.0; out[1] = 2.0; };
    /// let e = VectorUniformEstimator::new(2, f, UniformBox::unit(1).unwrap());
    /// assert_eq!(Integrator::new_vector(e).run().unwrap().means(), vec![1.0, 2.0]);
    /// ```
    pub fn new_vector(estimator: E) -> Self {
        Integrator {
            estimator: VectorRun {
                estimator,
                output_tolerances: None,
                derived_tolerances: Vec::new(),
            },
            config: RunConfig::default(),
        }
    }

    /// A tolerance for each output (`tolerances.len()` must be the number of outputs): a run
    /// to a tolerance stops when every output meets its own. Replaces the one
    /// [`tolerance`](Integrator::tolerance) gives all outputs; the evaluation and time limits
    /// are the tightest any tolerance sets.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox, stats::Tolerance};
    /// let f = |x: &[f64], out: &mut [f64]| { out[0] = x[0]; out[1] = 100.0 * x[0]; };
    /// let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap())
    ///     .output_tolerances(vec![Tolerance::absolute(1e-3).unwrap(), Tolerance::relative(1e-3).unwrap()])
    ///     .run()
    ///     .unwrap();
    /// assert_eq!(run.converged, Some(true));
    /// assert!(run.outputs[0].half_width(0.95).unwrap().unwrap() <= 1e-3);
    /// assert!(run.outputs[1].half_width(0.95).unwrap().unwrap() <= 1e-3 * run.outputs[1].mean);
    /// ```
    pub fn output_tolerances(mut self, tolerances: Vec<Tolerance>) -> Self {
        self.estimator.output_tolerances = Some(tolerances);
        self
    }

    /// A tolerance on a quantity derived from the integrals (a ratio, any smooth function):
    /// a run to a tolerance stops when its delta-method interval meets it (and every other
    /// target is met). Without [`tolerance`](Integrator::tolerance) or
    /// [`output_tolerances`](Integrator::output_tolerances), the outputs themselves need meet
    /// no tolerance. May be called several times.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox, stats::{Derived, Tolerance}};
    /// // The posterior mean 4/5 of a uniform prior with likelihood x^3, to 1e-3 relative.
    /// let f = |x: &[f64], out: &mut [f64]| { out[0] = x[0].powi(4); out[1] = x[0].powi(3); };
    /// let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap())
    ///     .derived_tolerance(Derived::ratio(0, 1), Tolerance::relative(1e-3).unwrap())
    ///     .run()
    ///     .unwrap();
    /// let mean = run.derived(&Derived::ratio(0, 1)).unwrap();
    /// assert_eq!(run.converged, Some(true));
    /// assert!(mean.half_width(0.95).unwrap().unwrap() <= 1e-3 * mean.mean);
    /// ```
    pub fn derived_tolerance(mut self, quantity: Derived, tolerance: Tolerance) -> Self {
        self.estimator
            .derived_tolerances
            .push((quantity, tolerance));
        self
    }
}
