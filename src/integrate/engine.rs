//! [`RunEstimator`]: what the Integrator's engine needs from a scalar or a vector estimator,
//! so that one engine (plan, stages, checkpoints) serves both.

// `RunEstimator` names crate-private types on purpose: that is what seals `Integration`.
#![allow(private_interfaces)]

use super::layout::Layout;
use super::plan::Plan;
use super::{VectorRun, pilot};
use crate::engine::{Executor, Limits, RunConfig, Targets};
use crate::error::{Error, Result};
use crate::estimator::{Estimator, SingleOutput, VectorEstimator};
use crate::sampler::Sampler;
use crate::stats::{Estimate, VectorEstimate};

/// A scalar [`Estimator`] (one output, maybe with a pilot stage) or a [`VectorRun`] of outputs:
/// what the engine needs of them. Public in a private module, as the supertrait of
/// [`Integration`]: its methods name crate-private types, so no other crate can implement it,
/// which seals `Integration` to the two implementations here.
pub trait RunEstimator {
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

/// What an [`Integrator`](super::Integrator) integrates: a scalar [`Estimator`], whose runs
/// give an [`Estimate`], or a [`VectorRun`] of outputs, whose runs give a [`VectorEstimate`].
/// Implemented for those two only.
///
/// ```
/// use mcint::{Estimate, Integrator, VectorEstimate, pdf::UniformBox};
/// let scalar: Estimate = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).run().unwrap();
/// let f = |x: &[f64], out: &mut [f64]| out.fill(x[0]);
/// let vector: VectorEstimate = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap()).run().unwrap();
/// assert_eq!((scalar.mean, vector.len()), (vector.outputs[0].mean, 2));
/// ```
pub trait Integration: RunEstimator {
    /// What a run gives: an [`Estimate`] or a [`VectorEstimate`].
    type Output: Into<VectorEstimate>;

    /// The result of a run of every output, checked for overflow.
    #[doc(hidden)]
    fn output(run: VectorEstimate) -> Result<Self::Output>;
}

impl<E: Estimator> Integration for E {
    type Output = Estimate;

    fn output(run: VectorEstimate) -> Result<Estimate> {
        let single = run.outputs.into_iter().next();
        single
            .ok_or_else(|| Error::invalid("outputs", 0, "one output"))
            .and_then(Estimate::checked)
    }
}

impl<E: VectorEstimator> Integration for VectorRun<E> {
    type Output = VectorEstimate;

    fn output(run: VectorEstimate) -> Result<VectorEstimate> {
        run.checked()
    }
}
