//! [`RunEstimator`]: what the Integrator's engine needs from a scalar or a vector estimator,
//! so that one engine (plan, stages, checkpoints) serves both.

use super::layout::Layout;
use super::plan::Plan;
use super::{VectorRun, pilot};
use crate::engine::{Executor, Limits, RunConfig, Targets};
use crate::error::Result;
use crate::estimator::{Estimator, SingleOutput, VectorEstimator};
use crate::sampler::Sampler;

/// A scalar [`Estimator`] (one output, maybe with a pilot stage) or a [`VectorRun`] of outputs.
pub(super) trait RunEstimator {
    /// Number of canonical coordinates per point.
    fn canonical_dims(&self) -> usize;

    /// Calls `work` with the estimator of the main run, seen as a vector estimator, and the
    /// evaluations a pilot stage spent before it.
    fn with_main<R>(
        &self,
        config: &RunConfig,
        executor: &Executor,
        limits: &Limits,
        work: impl FnOnce(&dyn VectorEstimator, u64) -> Result<R>,
    ) -> Result<R>;

    /// The tolerances the run must reach (none for a fixed budget), checked against its
    /// outputs.
    fn targets<'a>(&'a self, config: &RunConfig) -> Result<Targets<'a>>;

    /// The fingerprint of the run of `plan` with `sampler`.
    fn layout(&self, plan: &Plan, sampler: &dyn Sampler, config: &RunConfig) -> Result<Layout>;
}

impl<E: Estimator> RunEstimator for E {
    fn canonical_dims(&self) -> usize {
        Estimator::canonical_dims(self)
    }

    fn with_main<R>(
        &self,
        config: &RunConfig,
        executor: &Executor,
        limits: &Limits,
        work: impl FnOnce(&dyn VectorEstimator, u64) -> Result<R>,
    ) -> Result<R> {
        match self.pilot() {
            None => work(&SingleOutput(self), 0),
            Some(fit) => {
                let (summary, spent) = pilot::run(fit, self, config, executor, limits)?;
                let fitted = fit.fitted(&summary)?;
                work(&SingleOutput(&*fitted), spent)
            }
        }
    }

    fn targets<'a>(&'a self, config: &RunConfig) -> Result<Targets<'a>> {
        Targets::new(1, config.tolerance, None, &[])
    }

    fn layout(&self, plan: &Plan, sampler: &dyn Sampler, config: &RunConfig) -> Result<Layout> {
        Layout::of(plan, sampler, &SingleOutput(self), self.pilot(), config)
    }
}

impl<E: VectorEstimator> RunEstimator for VectorRun<E> {
    fn canonical_dims(&self) -> usize {
        self.estimator.canonical_dims()
    }

    fn with_main<R>(
        &self,
        _: &RunConfig,
        _: &Executor,
        _: &Limits,
        work: impl FnOnce(&dyn VectorEstimator, u64) -> Result<R>,
    ) -> Result<R> {
        work(&self.estimator, 0)
    }

    fn targets<'a>(&'a self, config: &RunConfig) -> Result<Targets<'a>> {
        Targets::new(
            self.estimator.outputs(),
            config.tolerance,
            self.output_tolerances.as_deref(),
            &self.derived_tolerances,
        )
    }

    fn layout(&self, plan: &Plan, sampler: &dyn Sampler, config: &RunConfig) -> Result<Layout> {
        Layout::of(plan, sampler, &self.estimator, None, config)
    }
}
