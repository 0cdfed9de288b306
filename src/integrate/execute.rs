//! [`Integrator::run`]: a whole run, at a fixed budget or to a tolerance, through the engine.

use super::engine::{Integration, RunEstimator};
use super::plan::Plan;
use super::{Integrator, stages};
use crate::engine::Drive;
use crate::error::Result;
use crate::stats::VectorEstimate;

/// Running: the whole run, at a fixed budget or to a tolerance.
impl<E: Integration> Integrator<E> {
    /// Runs the integration: an [`Estimate`](crate::Estimate) for a scalar estimator, a [`VectorEstimate`] of
    /// every output over the same points for a vector one.
    ///
    /// Errors when a setting is out of range, when the sampler's dimension differs from the
    /// estimator's, when the integrand panics (with the panic message), and when any
    /// contribution is NaN or infinite (the error gives their count, the first offending
    /// point, and its output in a vector run): such a mean would be silently wrong. With
    /// [`NonFinitePolicy::Skip`](super::NonFinitePolicy::Skip) they are left out and counted instead, but a replicate with
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
    pub(super) fn run_sampler(&self) -> Result<crate::engine::RunSampler<'_>>
    where
        E: RunEstimator,
    {
        self.config.sampler(
            RunEstimator::canonical_dims(&self.estimator),
            "sampler (the estimator's canonical points)",
        )
    }
}
