//! The pilot stage of an estimator that fits itself before the main run ([`PilotFit`]), and
//! the Integrator's control-variate mode built on it.

use super::{Integrator, NonFinitePolicy};
use crate::engine::{ChunkJob, Executor, Limits, RunConfig};
use crate::error::{Error, Result};
use crate::estimator::{
    ControlDomain, ControlFit, Estimator, FittedControlVariates, OverMeasure, PilotFit,
};
use crate::hash::hash_words;
use crate::measure::Measure;
use crate::pdf::Pdf;
use crate::points::Points;
use crate::sampler::{Independent, Sampler};
use crate::stats::CovarianceAccumulator;

/// Points per chunk of the pilot.
const CHUNK: u64 = 4096;
/// Separates the pilot's seed from the main run's.
const TAG_PILOT: u64 = 0x0070_696c_6f74;

/// Runs the pilot of `pilot` on independent points seeded from the run's seed (independent of
/// the main run's points, whatever its sampler): the rows' summary and the evaluations spent.
pub(super) fn run(
    pilot: &dyn PilotFit,
    estimator: &dyn Estimator,
    config: &RunConfig,
    executor: &Executor,
    limits: &Limits,
) -> Result<(CovarianceAccumulator, u64)> {
    let points = pilot.points();
    if points == 0 {
        return Err(Error::invalid("pilot points", 0, "at least 1"));
    }
    // The pilot is part of the run: held to its limits before it starts, as the main run is.
    let evaluations = points.saturating_mul(estimator.evaluations_per_contribution());
    config.check_budget("pilot points", evaluations)?;
    if let Some(limit) = config.tolerance.map(|t| t.evaluation_limit())
        && evaluations >= limit
    {
        return Err(Error::invalid(
            "pilot points",
            points,
            format!(
                "a pilot below the run's evaluation limit, {limit} (it would spend \
                 {evaluations}): a smaller pilot or a larger max_evaluations"
            ),
        ));
    }
    let seed = hash_words(config.seed().unwrap_or(0), &[TAG_PILOT]);
    let job = PilotChunks {
        pilot,
        sampler: Independent::new(estimator.canonical_dims(), seed)?,
        domain_dims: estimator.domain_dims(),
        points,
    };
    let mut summary = CovarianceAccumulator::new(pilot.values())?;
    let stop = executor.run(&job, 0..points.div_ceil(CHUNK), 64, limits, |_, part| {
        summary.merge(&part)
    })?;
    if let Some(stop) = stop {
        return Err(Error::Interrupted {
            stop,
            evaluations: summary.count() + summary.non_finite(),
        });
    }
    if summary.non_finite() > 0 && config.non_finite == NonFinitePolicy::Fail {
        return Err(Error::invalid(
            "integrand",
            format!(
                "{} non-finite pilot values among {points} points",
                summary.non_finite()
            ),
            "finite values of the integrand and controls over their pdf at every pilot point \
             (or NonFinitePolicy::Skip to fit on the finite ones)",
        ));
    }
    Ok((summary, evaluations))
}

/// The pilot's chunks, as work for the executor.
struct PilotChunks<'a> {
    pilot: &'a dyn PilotFit,
    sampler: Independent,
    domain_dims: usize,
    points: u64,
}

/// A pilot thread's buffers: a block of points, the mapped point and one row.
struct Scratch {
    points: Points,
    u: Vec<f64>,
    x: Vec<f64>,
    row: Vec<f64>,
}

impl ChunkJob for PilotChunks<'_> {
    type Scratch = Scratch;
    type Output = CovarianceAccumulator;

    fn scratch(&self) -> Result<Scratch> {
        Ok(Scratch {
            points: Points::new(self.sampler.dims(), CHUNK as usize)?,
            u: vec![0.0; self.sampler.dims()],
            x: vec![0.0; self.domain_dims],
            row: vec![0.0; self.pilot.values()],
        })
    }

    fn run(
        &self,
        work: &mut Scratch,
        chunk: u64,
        _: &Limits,
    ) -> Result<Option<CovarianceAccumulator>> {
        let start = chunk * CHUNK;
        let len = (self.points - start).min(CHUNK) as usize;
        work.points.set_len(len);
        self.sampler.fill(start, &mut work.points)?;
        let mut summary = CovarianceAccumulator::new(work.row.len())?;
        for i in 0..len {
            work.points.copy_point(i, &mut work.u);
            self.pilot.row(&work.u, &mut work.x, &mut work.row);
            summary.push(&work.row)?;
        }
        Ok(Some(summary))
    }

    fn origin(&self, chunk: u64) -> (u64, u64) {
        (0, chunk * CHUNK)
    }
}

impl<'a, F, P> Integrator<FittedControlVariates<'a, F, P>>
where
    F: Fn(&[f64]) -> f64 + Send + Sync,
    P: Pdf,
{
    /// Integrates `f` over the domain of `pdf`, sampling from `pdf`, with control variates
    /// added by [`control`](Self::control): a pilot of independent points fits their
    /// coefficients by least squares, and the main run (any sampler, replicates, tolerance)
    /// integrates `(f - beta^T g)/pdf + beta^T G` with them fixed, so its estimate is unbiased
    /// and its error bar the usual one (see [`FittedControlVariates`]). [`Estimate::evaluations`]
    /// includes the pilot's.
    ///
    /// [`Estimate::evaluations`]: crate::Estimate::evaluations
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox, sampler::{Scramble, Sobol}};
    /// // Randomized QMC with a control: replicates give the error bar.
    /// let e = Integrator::with_controls(|x: &[f64]| (x[0] * x[1]).exp(), UniformBox::unit(2).unwrap())
    ///     .control(|x: &[f64]| x[0] * x[1], 0.25)
    ///     .sampler(Sobol::new(2, Scramble::Owen, 1).unwrap())
    ///     .samples(1024)
    ///     .replicates(8)
    ///     .run()
    ///     .unwrap();
    /// assert!((e.mean - 1.317_902_151_454_404).abs() < 5.0 * e.std_error.unwrap());
    /// assert_eq!(e.evaluations, 8 * 1024 + 4096);
    /// ```
    pub fn with_controls(f: F, pdf: P) -> Self {
        Integrator::new(FittedControlVariates::new(f, pdf))
    }
}

impl<'a, F, M> Integrator<FittedControlVariates<'a, F, OverMeasure<M>>>
where
    F: Fn(&[f64]) -> f64 + Send + Sync,
    M: Measure,
{
    /// The expectation `E[f(X)]` of `f` under a [`Measure`] (see
    /// [`Integrator::expectation`]), with control variates added by
    /// [`control`](Self::control): each control `g` with its exact expectation `E[g(X)]`,
    /// coefficients fitted on a pilot of independent points as for
    /// [`with_controls`](Self::with_controls).
    ///
    /// An arithmetic-average Asian call with the geometric-average call as control, whose price
    /// is known in closed form:
    ///
    /// ```
    /// use mcint::{Integrator, measure::{Construction, GeometricBrownianMotion}};
    /// let dates: Vec<f64> = (1..=12).map(|i| i as f64 / 12.0).collect();
    /// let gbm = GeometricBrownianMotion::new(100.0, 0.05, 0.2, dates, Construction::Bridge)?;
    /// let geometric_price = gbm.geometric_average_call(100.0)?;
    /// let discount = (-0.05f64).exp();
    /// let arithmetic = move |s: &[f64]| discount * (s.iter().sum::<f64>() / 12.0 - 100.0).max(0.0);
    /// let geometric = move |s: &[f64]| {
    ///     discount * ((s.iter().map(|v| v.ln()).sum::<f64>() / 12.0).exp() - 100.0).max(0.0)
    /// };
    /// let e = Integrator::expectation_with_controls(arithmetic, gbm.clone())
    ///     .control(geometric, geometric_price)
    ///     .samples(1 << 14)
    ///     .run()?;
    /// let plain = Integrator::expectation(arithmetic, gbm).samples(1 << 14).run()?;
    /// assert!(e.std_error.unwrap() < plain.std_error.unwrap() / 10.0);
    /// assert!((e.mean - plain.mean).abs() < 5.0 * plain.std_error.unwrap());
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn expectation_with_controls(f: F, measure: M) -> Self {
        Integrator::new(FittedControlVariates::new(f, OverMeasure(measure)))
    }
}

impl<'a, F, P> Integrator<FittedControlVariates<'a, F, P>>
where
    F: Fn(&[f64]) -> f64 + Send + Sync,
    P: ControlDomain,
{
    /// Adds a control `g` whose exact integral over the pdf's domain is `integral`.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let none = Integrator::with_controls(|x: &[f64]| x[0], UniformBox::unit(1).unwrap());
    /// assert!(none.run().unwrap_err().to_string().contains("at least one control"));
    /// ```
    pub fn control(mut self, g: impl Fn(&[f64]) -> f64 + Send + Sync + 'a, integral: f64) -> Self {
        self.estimator = self.estimator.control(g, integral);
        self
    }

    /// Points of the pilot that fits the coefficients (more than the number of controls plus
    /// one; default 4096).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let i = Integrator::with_controls(|x: &[f64]| x[0].exp(), UniformBox::unit(1).unwrap())
    ///     .control(|x: &[f64]| x[0], 0.5);
    /// assert!(i.pilot(2).run().unwrap_err().to_string().contains("at least 3"));
    /// ```
    pub fn pilot(mut self, points: u64) -> Self {
        self.estimator = self.estimator.pilot_points(points);
        self
    }

    /// Runs the pilot alone and returns its fit: the coefficients the main run would use and
    /// the variance reduction they achieve on the pilot.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let fit = Integrator::with_controls(|x: &[f64]| 3.0 + 2.0 * x[0], UniformBox::unit(1).unwrap())
    ///     .control(|x: &[f64]| x[0], 0.5)
    ///     .fit()
    ///     .unwrap();
    /// assert!((fit.coefficients[0] - 2.0).abs() < 1e-12);
    /// assert!(fit.variance_reduction < 1e-12);
    /// ```
    pub fn fit(&self) -> Result<ControlFit> {
        let (executor, _run) = self.config.executor()?;
        let limits = self.config.limits();
        let (summary, _) = run(
            &self.estimator,
            &self.estimator,
            &self.config,
            &executor,
            &limits,
        )?;
        self.estimator.fit(&summary)
    }
}
