//! Runs of the [`Integrator`] that stop at a [`Tolerance`]: a two-stage rule for independent
//! points, and doubling with fixed replicates for randomized QMC and stratified points, both
//! judged by the engine's [`Stopping`] rule.

use super::Plan;
use super::plan::balance_warning;
use crate::engine::{DEFAULT_REPLICATES, Executor, RunConfig, Stopping, require_randomized};
use crate::estimator::Estimator;
use crate::sampler::{PassKind, Sampler};
use crate::special::normal_quantile;
use crate::stats::{Accumulator, Estimate, StopReason, Tolerance};
use crate::{Error, Result};

/// Pilot size of the two-stage rule when the caller gives none.
const DEFAULT_PILOT: u64 = 4096;
/// Inflation of the pilot's standard deviation when sizing the main stage.
const SD_INFLATION: f64 = 1.1;
/// First points per replicate of a doubling run when the sampler has no pass size.
const DEFAULT_FIRST_STAGE: u64 = 1024;

/// Integrates with `estimator` until `tolerance` is met or a limit is reached. Counts are of
/// contributions; the caller turns them into integrand evaluations.
pub(super) fn run_to_tolerance(
    estimator: &dyn Estimator,
    config: &RunConfig,
    sampler: &dyn Sampler,
    executor: &Executor,
    tolerance: &Tolerance,
) -> Result<Estimate> {
    require_randomized(
        sampler,
        "a run to a tolerance compares an error bar with the tolerance, and the passes of an \
         unrandomized sampler give none",
    )
    .map_err(|_| {
        Error::invalid(
            "tolerance",
            "requested",
            format!(
                "a randomized sampler (the unrandomized {} sampler has no error bar to compare \
                 with a tolerance; choose a scramble)",
                sampler.name()
            ),
        )
    })?;
    let stage = Stage {
        estimator,
        config,
        sampler,
        executor,
        stopping: Stopping::new(tolerance),
        cost: estimator.evaluations_per_contribution().max(1),
    };
    if sampler.passes() == PassKind::Independent {
        two_stage(&stage)
    } else {
        doubling(&stage)
    }
}

/// What every stage of one run shares.
struct Stage<'a> {
    estimator: &'a dyn Estimator,
    config: &'a RunConfig,
    sampler: &'a dyn Sampler,
    executor: &'a Executor,
    stopping: Stopping<'a>,
    /// Integrand evaluations per contribution.
    cost: u64,
}

impl Stage<'_> {
    /// Why the run should stop before `next` more contributions, `used` spent so far.
    fn limit(&self, used: u64, next: u64) -> Option<StopReason> {
        self.stopping.limit(
            used.saturating_mul(self.cost),
            next.saturating_mul(self.cost),
        )
    }

    /// The evaluation limit, in contributions.
    fn contribution_limit(&self) -> u64 {
        self.stopping.tolerance().evaluation_limit() / self.cost
    }

    /// Accumulators of points `offset .. offset + samples` of each of `replicates`
    /// replicates, `stride` apart.
    fn run(
        &self,
        replicates: u64,
        stride: u64,
        offset: u64,
        samples: u64,
    ) -> Result<Vec<Accumulator>> {
        let plan = Plan::stage(replicates, stride, offset, samples)?;
        let folded = plan.run_folded(self.executor, self.sampler, self.estimator)?;
        plan.check_finite(self.sampler, &folded, self.config.non_finite)?;
        Ok(folded.replicates)
    }
}

/// Independent points: a pilot sizes a fresh main stage (extended if it still misses).
fn two_stage(stage: &Stage<'_>) -> Result<Estimate> {
    let tolerance = stage.stopping.tolerance();
    let pilot_size = stage.config.samples.unwrap_or(DEFAULT_PILOT).max(2);
    if pilot_size > stage.contribution_limit() {
        return Err(Error::invalid(
            "max_evals",
            tolerance.evaluation_limit(),
            format!(
                "at least the pilot's {} evaluations",
                pilot_size.saturating_mul(stage.cost)
            ),
        ));
    }
    // Replicate 0 only: the pilot takes indices 0 .. pilot, the main stage what follows.
    let pilot = stage.run(1, 0, 0, pilot_size)?.remove(0);
    let z = normal_quantile(0.975);
    let mut used = pilot_size;
    let mut main = Accumulator::new();
    let mut sd = pilot.variance().sqrt();
    let mut mean = pilot.mean();
    let mut stages = 1;
    let stop = loop {
        let target = tolerance.target(mean);
        let needed = if sd == 0.0 {
            2
        } else {
            let n = (z * SD_INFLATION * sd / target).powi(2).ceil();
            if n.is_finite() && n < u64::MAX as f64 {
                (n as u64).max(2)
            } else {
                u64::MAX
            }
        };
        let more = needed.saturating_sub(main.count()).max(1);
        let more = match stage.limit(used, more) {
            None => more,
            Some(StopReason::MaxEvaluations) => {
                let left = stage.contribution_limit().saturating_sub(used);
                if left == 0 {
                    break StopReason::MaxEvaluations;
                }
                left
            }
            Some(reason) => break reason,
        };
        let part = stage.run(1, 0, used, more)?.remove(0);
        main.merge(&part);
        used += more;
        stages += 1;
        if main.count() >= 2 && stage.stopping.judge(main.estimate()).1 {
            break StopReason::ToleranceMet;
        }
        sd = main.variance().sqrt();
        mean = main.mean();
    };
    // Before any main stage ran, the pilot is all there is.
    let source = if main.count() >= 2 { &main } else { &pilot };
    let mut estimate = source.estimate();
    estimate.evaluations = used;
    stage.stopping.finish(&mut estimate, stop, stages);
    Ok(estimate)
}

/// Randomized QMC and stratified points: `R` replicates, doubling the points of each until
/// the judged interval over the replicates meets the tolerance.
fn doubling(stage: &Stage<'_>) -> Result<Estimate> {
    let tolerance = stage.stopping.tolerance();
    let replicates = stage.config.replicates.unwrap_or(DEFAULT_REPLICATES);
    if replicates < 2 {
        return Err(Error::invalid(
            "replicates",
            replicates,
            "at least 2 for a run to a tolerance (the error bar comes from their spread)",
        ));
    }
    let limit = stage.contribution_limit();
    let (first, stride) = first_stage_and_stride(stage, replicates, limit)?;
    Plan::stage(replicates, stride, 0, stride)?;
    let mut accumulators = vec![Accumulator::new(); replicates as usize];
    let (mut done, mut next) = (0u64, first);
    let mut stages = 0;
    let mut estimate = None;
    let stop = loop {
        if next > stride {
            break StopReason::MaxEvaluations;
        }
        let cost = (next - done).saturating_mul(replicates);
        if let Some(reason) = stage.limit(done * replicates, cost) {
            // The first stage always runs within the evaluation limit, whatever the time.
            if stages > 0 || cost > limit {
                break reason;
            }
        }
        let parts = stage.run(replicates, stride, done, next - done)?;
        for (acc, part) in accumulators.iter_mut().zip(&parts) {
            acc.merge(part);
        }
        done = next;
        stages += 1;
        let current = Estimate::from_replicate_accumulators(&accumulators)?;
        let (current, met) = stage.stopping.judge(current);
        estimate = Some(current);
        if met {
            break StopReason::ToleranceMet;
        }
        next = done.saturating_mul(2);
    };
    let mut estimate = estimate.ok_or_else(|| {
        Error::invalid(
            "max_evals",
            tolerance.evaluation_limit(),
            format!(
                "at least {} evaluations ({replicates} replicates of {first} points)",
                replicates.saturating_mul(first).saturating_mul(stage.cost)
            ),
        )
    })?;
    if let Some(warning) = balance_warning(stage.sampler, first) {
        estimate.warn(warning);
    }
    stage.stopping.finish(&mut estimate, stop, stages);
    Ok(estimate)
}

/// Points per replicate of the first stage, and the distance between replicates.
fn first_stage_and_stride(stage: &Stage<'_>, replicates: u64, limit: u64) -> Result<(u64, u64)> {
    let samples = stage.config.samples;
    match stage.sampler.passes() {
        PassKind::Fixed { size } => {
            let first = samples.unwrap_or(size);
            if first == 0 || !first.is_multiple_of(size) {
                return Err(Error::invalid(
                    "samples",
                    first,
                    format!(
                        "a positive multiple of the {} sampler's pass size {size}",
                        stage.sampler.name()
                    ),
                ));
            }
            // Room for the most points per replicate the budget allows.
            let most = (limit / replicates / size).max(1) * size;
            Ok((first, most.max(first)))
        }
        PassKind::Extensible { max } => {
            let first = samples.unwrap_or(DEFAULT_FIRST_STAGE.min(max));
            if first == 0 || first > max {
                return Err(Error::invalid(
                    "samples",
                    first,
                    format!(
                        "1 ..= {max} points per replicate for the {} sampler",
                        stage.sampler.name()
                    ),
                ));
            }
            Ok((first, max))
        }
        PassKind::Independent => unreachable!("independent points take the two-stage rule"),
    }
}
