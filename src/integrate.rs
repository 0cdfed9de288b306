//! [`Integrator`]: the front door that drives sampler, estimator and accumulator.
//!
//! A run's sample indices are laid out by a [`Plan`](plan::Plan): replicate by replicate, cut
//! into fixed chunks of 16384 points that the crate's executor evaluates on any number of
//! threads and folds in chunk order, so the result is bit-identical for every thread count,
//! and for any split into parts ([`PartialRun`]). Runs to a tolerance ([`staged`]) repeat
//! such runs over growing index ranges, judged by the engine's stopping rule.
//!
//! The engine runs every estimator as a vector of outputs (`engine::RunEstimator`): a
//! scalar [`Estimator`] is one output, with the very arithmetic it always had, and a
//! [`VectorRun`] carries `m` outputs and their tolerances through the same plan, stages and
//! checkpoints.

use crate::engine::{Drive, RunConfig, run_settings};
use crate::error::Result;
use crate::estimator::{
    BatchUniformEstimator, Estimator, ExpectationEstimator, ImportanceEstimator, UniformEstimator,
    WarpImportanceEstimator,
};
use crate::measure::Measure;
use crate::pdf::{GeometricWarp, Pdf, UniformBox, WarpPoint};
use crate::points::Points;
use crate::stats::VectorEstimate;

mod engine;
mod layout;
mod partial;
#[cfg(feature = "serde")]
mod partial_format;
mod pilot;
mod plan;
mod stages;
mod vector;

pub use crate::non_finite::NonFinitePolicy;
pub use engine::Integration;
use engine::RunEstimator;
pub use partial::PartialRun;
use plan::Plan;
pub use vector::VectorRun;

/// Points per unit of work handed to a thread (and per partial accumulator).
const CHUNK: u64 = 16 * 1024;
/// Points per replicate when neither the caller nor the sampler's pass size says otherwise.
const DEFAULT_SAMPLES: u64 = 1 << 16;

/// Integrates with a given estimator, sampler, budget, seed and thread count.
///
/// `samples` is the number of points per replicate and `replicates` the number of
/// independent replicates (passes of the sampler with independent randomization). For
/// independent points the standard error comes from the per-sample variance; for stratified
/// and quasi-random points it comes from the spread of replicate means (Student-t with `R - 1`
/// degrees of freedom), and with a single replicate no standard error is reported.
///
/// Generation and evaluation are fused: each worker thread fills a block of 1024 points (8 KiB
/// per dimension, sized to stay in L1/L2 cache) with the sampler's batch
/// [`fill`](crate::Sampler::fill) and hands it straight to the estimator's
/// [`contributions`](Estimator::contributions), reusing the same block and value buffers for
/// the whole run; no buffer of all the points is ever built, so memory traffic does not grow
/// with the number of samples. A batch integrand ([`over_box_batch`](Integrator::over_box_batch))
/// sees those blocks directly.
///
/// With a [`tolerance`](Integrator::tolerance), independent points use a two-stage rule: a pilot of
/// [`samples`](Integrator::samples) points (default 4096) gives the estimate if its interval meets
/// the tolerance; else it estimates the standard deviation `s`, and a fresh main stage of
/// `(1.96 * 1.1 * s / target)^2` points (at least the pilot's), independent of the pilot, gives the
/// estimate and its CLT interval (the factor 1.1 inflates the variance against an unlucky pilot; should the
/// main stage still miss, it is extended by the same rule). The interval assumes the CLT holds at
/// that size, which needs `n` well above the square of the integrand's skewness: sharply peaked or
/// heavy-tailed integrands need a tighter tolerance, or importance sampling. Randomized QMC and
/// stratified points keep `R` replicates (default 8) and double the points per replicate, starting
/// from `samples` (default: the pass size, or 1024), until the Student-t interval over the
/// replicates, with its standard error inflated by 1.2 against optional stopping, meets the
/// tolerance; each stage adds only the new points.
///
/// ```
/// use mcint::{Integrator, pdf::UniformBox, sampler::Jittered};
/// let estimate = Integrator::over_box(|x: &[f64]| x[0] * x[1], UniformBox::unit(2).unwrap())
///     .sampler(Jittered::new(2, 32, 0).unwrap())
///     .samples(1024)
///     .replicates(8)
///     .seed(7)
///     .threads(2)
///     .run()
///     .unwrap();
/// assert!((estimate.mean - 0.25).abs() < 5.0 * estimate.std_error.unwrap());
/// ```
pub struct Integrator<E> {
    estimator: E,
    config: RunConfig,
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync> Integrator<UniformEstimator<F>> {
    /// Integrates `f` over a box with the uniform estimator (A.14).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let e = Integrator::over_box(|x: &[f64]| x[0], UniformBox::new(vec![0.0], vec![2.0]).unwrap())
    ///     .samples(10_000)
    ///     .run()
    ///     .unwrap();
    /// assert!((e.mean - 2.0).abs() < 5.0 * e.std_error.unwrap());
    /// ```
    pub fn over_box(f: F, domain: UniformBox) -> Self {
        Integrator::new(UniformEstimator::new(f, domain))
    }
}

impl<F: Fn(&Points, &mut [f64]) + Send + Sync> Integrator<BatchUniformEstimator<F>> {
    /// Integrates a batch integrand over a box with the uniform estimator (A.14): `f(points,
    /// out)` gets a block of up to 1024 domain points (one column per coordinate) and must
    /// write `f(x_i)` to every `out[i]`; see [`BatchUniformEstimator`]. With the same
    /// arithmetic per point, the estimate has the same bits as [`over_box`](Integrator::over_box).
    ///
    /// ```
    /// use mcint::{Integrator, Points, pdf::UniformBox};
    /// // x0 * x1 over [0, 2)^2 is 4, one column pass per coordinate.
    /// let product = |p: &Points, out: &mut [f64]| {
    ///     for (y, (&x0, &x1)) in out.iter_mut().zip(p.column(0).iter().zip(p.column(1))) {
    ///         *y = x0 * x1;
    ///     }
    /// };
    /// let domain = UniformBox::new(vec![0.0; 2], vec![2.0; 2]).unwrap();
    /// let batch = Integrator::over_box_batch(product, domain.clone()).samples(10_000).run().unwrap();
    /// assert!((batch.mean - 4.0).abs() < 5.0 * batch.std_error.unwrap());
    /// let per_point = Integrator::over_box(|x: &[f64]| x[0] * x[1], domain).samples(10_000).run().unwrap();
    /// assert_eq!(batch, per_point);
    /// ```
    pub fn over_box_batch(f: F, domain: UniformBox) -> Self {
        Integrator::new(BatchUniformEstimator::new(f, domain))
    }
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync, P: Pdf> Integrator<ImportanceEstimator<F, P>> {
    /// Integrates `f` over the domain of `pdf`, sampling from `pdf` (A.19).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::Exponential};
    /// // The integral of x e^{-x} over [0, inf) is 1.
    /// let pdf = Exponential::new(1.0, 0.0, f64::INFINITY).unwrap();
    /// let e = Integrator::with_pdf(|x: &[f64]| x[0] * (-x[0]).exp(), pdf).samples(20_000).run().unwrap();
    /// assert!((e.mean - 1.0).abs() < 5.0 * e.std_error.unwrap());
    /// ```
    pub fn with_pdf(f: F, pdf: P) -> Self {
        Integrator::new(ImportanceEstimator::new(f, pdf))
    }
}

impl<P: WarpPoint, R: Into<f64>, F: Fn(P) -> R + Send + Sync, W: GeometricWarp<P>>
    Integrator<WarpImportanceEstimator<F, W, P, R>>
{
    /// Integrates `f` over directions, the points of a triangle or of a disk, handed to it as
    /// a glam vector (`DVec3`, or `DVec2` for the disk; a renderer's `f32` `Vec3` and `Vec2`
    /// too, the sampled point rounded, and `f` may return `f32`), sampling from `warp` (see
    /// [`WarpImportanceEstimator`]): a sphere, a hemisphere or cap about any normal
    /// ([`Warp3::about`](crate::pdf::Warp3::about)), a triangle, a disk.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// use mcint::pdf::{UniformHemisphere, Warp3};
    /// use mcint::Integrator;
    /// // The cosine-weighted integral of a constant over the hemisphere about n is pi.
    /// let n = DVec3::new(1.0, -2.0, 0.5);
    /// let f = move |d: DVec3| d.dot(n.normalize()).max(0.0);
    /// let e = Integrator::over_warp(f, UniformHemisphere.about(n)?).samples(100_000).run()?;
    /// assert!((e.mean - std::f64::consts::PI).abs() < 5.0 * e.std_error.unwrap());
    /// // The integral of |p|^2 over the unit disk is pi / 2.
    /// let disk = mcint::pdf::UniformDisk::unit();
    /// let e = Integrator::over_warp(|p: mcint::glam::DVec2| p.length_squared(), disk)
    ///     .samples(100_000)
    ///     .run()?;
    /// assert!((e.mean - std::f64::consts::FRAC_PI_2).abs() < 5.0 * e.std_error.unwrap());
    /// // A renderer's f32 vectors and f32 radiance: the same integral of cos over the hemisphere.
    /// let n32 = mcint::glam::Vec3::new(1.0, -2.0, 0.5).normalize();
    /// let cosine = move |d: mcint::glam::Vec3| d.dot(n32).max(0.0);
    /// let e = Integrator::over_warp(cosine, UniformHemisphere.about(n)?).samples(100_000).run()?;
    /// assert!((e.mean - std::f64::consts::PI).abs() < 5.0 * e.std_error.unwrap());
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn over_warp(f: F, warp: W) -> Self {
        Integrator::new(WarpImportanceEstimator::new(f, warp))
    }
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync, M: Measure> Integrator<ExpectationEstimator<F, M>> {
    /// Integrates `f` against `measure`: `E[f(X)]` under a probability law (a
    /// [`Gaussian`](crate::measure::Gaussian), a [`BrownianMotion`](crate::measure::BrownianMotion)
    /// path, ...), or the integral of `f` over an unbounded box
    /// ([`Lebesgue`](crate::measure::Lebesgue)). Any sampler of the measure's canonical
    /// dimension serves; see [`ExpectationEstimator`].
    ///
    /// ```
    /// use mcint::{Integrator, measure::Gaussian, sampler::{Scramble, Sobol}};
    /// // E[|X|^2] = 3 for a standard normal in 3-D, with scrambled Sobol' points.
    /// let e = Integrator::expectation(|x: &[f64]| x.iter().map(|v| v * v).sum(), Gaussian::standard(3).unwrap())
    ///     .sampler(Sobol::new(3, Scramble::Owen, 1).unwrap())
    ///     .samples(4096)
    ///     .replicates(16)
    ///     .run()
    ///     .unwrap();
    /// assert!((e.mean - 3.0).abs() < 5.0 * e.std_error.unwrap());
    /// ```
    pub fn expectation(f: F, measure: M) -> Self {
        Integrator::new(ExpectationEstimator::new(f, measure))
    }
}

impl<E: Estimator> Integrator<E> {
    /// An integrator for any estimator, with independent points, one replicate, `2^16`
    /// samples and all available threads until told otherwise.
    ///
    /// ```
    /// use mcint::{Integrator, estimator::UniformEstimator, pdf::UniformBox};
    /// let est = UniformEstimator::new(|_: &[f64]| 3.0, UniformBox::unit(1).unwrap());
    /// assert_eq!(Integrator::new(est).run().unwrap().mean, 3.0);
    /// ```
    pub fn new(estimator: E) -> Self {
        Integrator {
            estimator,
            config: RunConfig::default(),
        }
    }
}

/// The settings every run shares, scalar or vector.
impl<E> Integrator<E> {
    run_settings! {
        setup: "use mcint::{Integrator, pdf::UniformBox};\n\
                const DIMS: usize = 2;\n\
                let runner = || Integrator::over_box(|x: &[f64]| x[0] * x[1], UniformBox::unit(DIMS).unwrap()).samples(4096);",
        run: ".run().unwrap()";
        sampler, seed, threads, tolerance, non_finite, time_limit, deadline, cancel_token, progress, cluster
    }

    /// Points per replicate (at least 1; a multiple of the pass size for samplers with
    /// fixed passes, at most the pass size for extensible sequences). Defaults to the pass
    /// size for fixed passes and `2^16` otherwise; with a tolerance, the first stage's size.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let e = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(10).run().unwrap();
    /// assert_eq!(e.n, 10);
    /// ```
    pub fn samples(mut self, samples: u64) -> Self {
        self.config.samples = Some(samples);
        self
    }

    /// Number of independent replicates (at least 1; default 1, or 8 in a run to a
    /// tolerance with dependent points).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let e = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .samples(10).replicates(3).run().unwrap();
    /// assert_eq!((e.n, e.replicates), (30, 3));
    /// ```
    pub fn replicates(mut self, replicates: u64) -> Self {
        self.config.replicates = Some(replicates);
        self
    }
}

impl<E: Integration> Integrator<E> {
    /// Runs the integration: an [`Estimate`](crate::Estimate) for a scalar estimator, a [`VectorEstimate`] of
    /// every output over the same points for a vector one.
    ///
    /// Errors when a setting is out of range, when the sampler's dimension differs from the
    /// estimator's, when the integrand panics (with the panic message), and when any
    /// contribution is NaN or infinite (the error gives their count, the first offending
    /// point, and its output in a vector run): such a mean would be silently wrong. With
    /// [`NonFinitePolicy::Skip`] they are left out and counted instead, but a replicate with
    /// no finite contribution at all is still an error. A vector run also errs when the number
    /// of outputs is 0 or above [`MAX_OUTPUTS`](crate::estimator::MAX_OUTPUTS), when the
    /// per-output tolerances are not one per output, or when a derived quantity names an output
    /// that does not exist.
    ///
    /// ```
    /// use mcint::{Error, Integrator, pdf::UniformBox};
    /// let bad = Integrator::over_box(|x: &[f64]| 1.0 / (x[0] - x[0]), UniformBox::unit(1).unwrap())
    ///     .samples(10)
    ///     .run();
    /// assert!(bad.unwrap_err().to_string().contains("10 non-finite"));
    /// let f = |x: &[f64], out: &mut [f64]| { out[0] = 1.0; out[1] = if x[0] < 0.5 { f64::NAN } else { 1.0 }; };
    /// let err = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap()).samples(100).run().unwrap_err();
    /// assert!(matches!(err, Error::NonFiniteContribution { first_output: Some(1), .. }));
    /// assert!(err.to_string().contains("in output 1"), "{err}");
    /// ```
    pub fn run(&self) -> Result<E::Output> {
        E::output(self.run_engine()?)
    }
}

impl<E> Integrator<E> {
    /// The run of the engine, for a scalar or vector estimator, before overflow checks.
    fn run_engine(&self) -> Result<VectorEstimate>
    where
        E: RunEstimator,
    {
        let targets = self.estimator.targets(&self.config)?;
        let sampler = self.run_sampler()?;
        let (executor, _run) = self.config.executor()?;
        let limits = self.config.limits_with(targets.time());
        self.estimator.with_main(
            &self.config,
            &executor,
            &limits,
            |estimator, pilot_evaluations| {
                let cost = estimator.evaluations_per_contribution();
                let common = stages::Common {
                    estimator,
                    config: &self.config,
                    sampler: &*sampler,
                    cost,
                    pilot_evaluations,
                };
                let mut drive = Drive {
                    executor: &executor,
                    limits: &limits,
                    targets: &targets,
                    config: &self.config,
                    spent: 0,
                    planned: 0,
                };
                if targets.any() {
                    let mut stages = stages::to_tolerance(common, &targets)?;
                    return crate::engine::drive(&mut *stages, &drive);
                }
                let plan = Plan::new(self.config.samples, self.config.replicates, &*sampler)?;
                let planned = plan.samples.saturating_mul(plan.replicates);
                self.config
                    .check_budget("samples x replicates", planned.saturating_mul(cost))?;
                drive.spent = pilot_evaluations;
                drive.planned = planned
                    .saturating_mul(cost)
                    .saturating_add(pilot_evaluations);
                let mut fixed = stages::Fixed {
                    common,
                    plan,
                    done: None,
                };
                crate::engine::drive(&mut fixed, &drive)
            },
        )
    }

    /// The run's sampler, checked against the estimator's canonical dimension.
    fn run_sampler(&self) -> Result<crate::engine::RunSampler<'_>>
    where
        E: RunEstimator,
    {
        self.config.sampler(
            RunEstimator::canonical_dims(&self.estimator),
            "sampler (the estimator's canonical points)",
        )
    }
}
