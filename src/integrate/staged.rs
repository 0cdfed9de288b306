//! Runs of the [`Integrator`] that stop at a [`Tolerance`]: a two-stage rule for independent
//! points, and doubling with fixed replicates for randomized QMC and stratified points, both
//! judged by the engine's [`Stopping`] rule.

use std::cell::Cell;

use super::Plan;
use super::plan::{Folded, MAX_REPLICATES, balance_warning};
use crate::engine::{Executor, RunConfig, Stopping, TOLERANCE_REPLICATES, Targets};
use crate::estimator::VectorEstimator;
use crate::sampler::{PassKind, Sampler};
use crate::special::{normal_quantile, student_t_quantile};
use crate::stats::{StopReason, VectorEstimate};
use crate::{Error, Result};

/// Pilot size of the two-stage rule when the caller gives none.
const DEFAULT_PILOT: u64 = 4096;
/// Inflation of the pilot's standard deviation when sizing the main stage.
const SD_INFLATION: f64 = 1.1;
/// First points per replicate of a doubling run when the sampler has no pass size.
const DEFAULT_FIRST_STAGE: u64 = 1024;

/// Integrates with `estimator` until every target is met or a limit is reached. Counts are of
/// contributions; the caller turns them into integrand evaluations.
pub(super) fn run_to_tolerance(
    estimator: &dyn VectorEstimator,
    config: &RunConfig,
    sampler: &dyn Sampler,
    executor: &Executor,
    targets: &Targets<'_>,
) -> Result<VectorEstimate> {
    if !sampler.is_randomized() {
        return Err(Error::invalid(
            "tolerance",
            "requested",
            format!(
                "a randomized sampler (the unrandomized {} sampler has no error bar to compare \
                 with a tolerance; choose a scramble)",
                sampler.name()
            ),
        ));
    }
    let Some(limits) = targets.limits() else {
        return Err(Error::invalid(
            "tolerance",
            "none",
            "a tolerance for a run to a tolerance",
        ));
    };
    config.check_budget("max_evals", limits.evaluation_limit())?;
    let stage = Stage {
        estimator,
        config,
        sampler,
        executor,
        targets,
        stopping: Stopping::new(&limits, config.limits(), *executor),
        cost: estimator.evaluations_per_contribution().max(1),
        spent: Cell::new(0),
    };
    if sampler.passes() == PassKind::Independent {
        two_stage(&stage)
    } else {
        doubling(&stage)
    }
}

/// What every stage of one run shares.
struct Stage<'a> {
    estimator: &'a dyn VectorEstimator,
    config: &'a RunConfig,
    sampler: &'a dyn Sampler,
    executor: &'a Executor,
    targets: &'a Targets<'a>,
    stopping: Stopping<'a>,
    /// Integrand evaluations per contribution.
    cost: u64,
    /// Evaluations folded so far, for the progress callback.
    spent: Cell<u64>,
}

impl Stage<'_> {
    /// Why the run should stop before `next` more contributions, `used` spent so far.
    fn limit(&self, used: u64, next: u64) -> Result<Option<StopReason>> {
        self.stopping.limit(
            used.saturating_mul(self.cost),
            next.saturating_mul(self.cost),
        )
    }

    /// The evaluation limit, in contributions.
    fn contribution_limit(&self) -> u64 {
        self.stopping.tolerance().evaluation_limit() / self.cost
    }

    /// The fold of the points of `plan`, and the limit that stopped the stage before its end,
    /// if one did (the fold then holds the chunks finished before it).
    fn run(&self, plan: &Plan) -> Result<(Folded, Option<StopReason>)> {
        let mut on_points = |points: u64| {
            self.spent.set(self.spent.get() + points * self.cost);
            self.config.report(self.spent.get(), 0);
        };
        let (folded, _, stop) = plan.run_folded(
            self.executor,
            self.stopping.limits(),
            self.sampler,
            self.estimator,
            &mut on_points,
        )?;
        plan.check_finite(self.sampler, &folded, self.config.non_finite)?;
        Ok((folded, stop))
    }
}

/// Independent points: a pilot, which stands if it meets the tolerance, else sizes a fresh
/// main stage of at least its own size (extended if it still misses).
fn two_stage(stage: &Stage<'_>) -> Result<VectorEstimate> {
    let pilot_size = stage.config.samples.unwrap_or(DEFAULT_PILOT).max(2);
    if pilot_size > stage.contribution_limit() {
        return Err(Error::invalid(
            "max_evals",
            stage.stopping.tolerance().evaluation_limit(),
            format!(
                "at least the pilot's {} evaluations",
                pilot_size.saturating_mul(stage.cost)
            ),
        ));
    }
    // Replicate 0 only: the pilot takes indices 0 .. pilot, the main stage what follows.
    let (pilot, pilot_stop) = stage.run(&Plan::stage(1, 0, 0, pilot_size)?)?;
    if let Some(stop) = pilot_stop {
        // Independent points: the pilot's finished chunks are an estimate of their own.
        if pilot.accumulators[0].count() < 2 {
            return Err(Error::Interrupted {
                stop,
                evaluations: pilot.points() * stage.cost,
            });
        }
        let mut estimate = pilot.independent_estimate();
        stage.targets.finish(&mut estimate, stop, 1);
        return Ok(estimate);
    }
    // A pilot that meets the tolerance is a sample of fixed size judged once, whose interval
    // is as honest as any; the main stage it would size could be a handful of points, whose
    // own spread is no error bar (13 points of the 4-D Genz discontinuous function under
    // importance sampling covered 81% of such runs).
    if pilot.accumulators[0].count() >= 2 {
        let (mut estimate, met) = stage.targets.judge(pilot.independent_estimate());
        if met {
            stage
                .targets
                .finish(&mut estimate, StopReason::ToleranceMet, 1);
            return Ok(estimate);
        }
    }
    let z = normal_quantile(0.975);
    let mut used = pilot_size;
    let mut main: Option<Folded> = None;
    let mut stages = 1;
    let stop = loop {
        let current = main.as_ref().unwrap_or(&pilot);
        // The main stage is never smaller than the pilot that sized it.
        let needed = points_needed(stage.targets, current, z * SD_INFLATION).max(pilot_size);
        let main_count = main.as_ref().map_or(0, |m| m.accumulators[0].count());
        let more = needed.saturating_sub(main_count).max(1);
        let more = match stage.limit(used, more)? {
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
        let (part, part_stop) = stage.run(&Plan::stage(1, 0, used, more)?)?;
        used += part.points();
        match main.as_mut() {
            Some(main) => main.merge(&part),
            None => main = Some(part),
        }
        stages += 1;
        if let Some(stop) = part_stop {
            break stop;
        }
        let main = main.as_ref().expect("set above");
        if main.accumulators[0].count() >= 2 && stage.targets.judge(main.independent_estimate()).1 {
            break StopReason::ToleranceMet;
        }
    };
    // Before any main stage ran, the pilot is all there is.
    let source = match &main {
        Some(main) if main.accumulators[0].count() >= 2 => main,
        _ => &pilot,
    };
    let mut estimate = source.independent_estimate();
    estimate.for_each_output(|_, output| output.evaluations = used);
    stage.targets.finish(&mut estimate, stop, stages);
    Ok(estimate)
}

/// Randomized QMC and stratified points: `R` replicates, whose points are doubled, or whose
/// number is raised when that is cheaper, until the judged interval over the replicates meets
/// the tolerance.
///
/// Doubling the points of every replicate spends as much again as the run so far and often
/// overshoots the tolerance by far; when the interval is within reach, new replicates of the
/// current size bring it down by `sqrt(R / R')` (their spread stays that of the others), so
/// the rule adds the fewest that are predicted to meet the tolerance whenever they cost less
/// than a doubling. Nothing else is predicted: the judgement after each stage decides.
fn doubling(stage: &Stage<'_>) -> Result<VectorEstimate> {
    let tolerance = stage.stopping.tolerance();
    let first_replicates = stage.config.replicates.unwrap_or(TOLERANCE_REPLICATES);
    if first_replicates < 2 {
        return Err(Error::invalid(
            "replicates",
            first_replicates,
            "at least 2 for a run to a tolerance (the error bar comes from their spread)",
        ));
    }
    let limit = stage.contribution_limit();
    let (first, stride) = first_stage_and_stride(stage, first_replicates, limit)?;
    Plan::stage(first_replicates, stride, 0, stride)?;
    let mut folded: Option<Folded> = None;
    // Points per replicate so far, and replicates so far.
    let (mut done, mut replicates) = (0u64, first_replicates);
    let mut grow = Grow::Points(first);
    let mut stages = 0;
    let mut estimate = None;
    let stop = loop {
        let (plan, cost) = match grow {
            Grow::Points(next) => {
                if next > stride {
                    // The next doubling would run past the end of the sampler's pass.
                    break StopReason::SamplerExhausted;
                }
                let plan = Plan::stage(replicates, stride, done, next - done)?;
                (plan, (next - done).saturating_mul(replicates))
            }
            Grow::Replicates(more) => {
                let plan = Plan::added(replicates, more, stride, 0, done)?;
                (plan, more.saturating_mul(done))
            }
        };
        if let Some(reason) = stage.limit(done.saturating_mul(replicates), cost)? {
            // A first stage past the evaluation limit is refused below; limits of time and
            // cancellation stop the first stage inside it.
            if stages > 0 || reason == StopReason::MaxEvaluations {
                break reason;
            }
        }
        let (parts, part_stop) = stage.run(&plan)?;
        if let Some(stop) = part_stop {
            // A stage cut short leaves replicates of unequal sizes: the last whole stage's
            // estimate stands.
            if estimate.is_none() {
                return Err(Error::Interrupted {
                    stop,
                    evaluations: stage.spent.get(),
                });
            }
            break stop;
        }
        let all = match (folded.as_mut(), grow) {
            (Some(all), Grow::Points(_)) => {
                all.merge(&parts);
                all
            }
            (Some(all), Grow::Replicates(_)) => {
                all.append(&parts);
                all
            }
            (None, _) => folded.insert(parts),
        };
        match grow {
            Grow::Points(next) => done = next,
            Grow::Replicates(more) => replicates += more,
        }
        stages += 1;
        let current = VectorEstimate::replicates(&all.accumulators, all.outputs)?;
        let (current, met) = stage.targets.judge(current);
        if met {
            estimate = Some(current);
            break StopReason::ToleranceMet;
        }
        // The first stage's spread, of the smallest replicates, is the least reliable (their
        // means are the most skewed): the run doubles at least once before adding replicates,
        // and adds them only when that costs less than a doubling.
        let added = (done > first)
            .then(|| replicates_to_meet(stage.targets.shortfall(&current), replicates))
            .flatten()
            .map(|enough| enough - replicates)
            .filter(|&more| more < replicates);
        grow = added.map_or(Grow::Points(done.saturating_mul(2)), Grow::Replicates);
        estimate = Some(current);
    };
    let mut estimate = estimate.ok_or_else(|| {
        Error::invalid(
            "max_evals",
            tolerance.evaluation_limit(),
            format!(
                "at least {} evaluations ({first_replicates} replicates of {first} points)",
                first_replicates
                    .saturating_mul(first)
                    .saturating_mul(stage.cost)
            ),
        )
    })?;
    if let Some(warning) = balance_warning(stage.sampler, first) {
        estimate.for_each_output(|_, output| output.warn(warning.clone()));
    }
    stage.targets.finish(&mut estimate, stop, stages);
    Ok(estimate)
}

/// The next stage of a doubling run.
#[derive(Debug, Clone, Copy)]
enum Grow {
    /// Every replicate continues up to this many points.
    Points(u64),
    /// This many new replicates of the current size.
    Replicates(u64),
}

/// The fewest replicates (more than `replicates`, at most twice as many and within the
/// plan's limit) whose 95% half-width, with the replicates' spread unchanged, is predicted to
/// be at most the targets: `shortfall` is the largest ratio of half-width to target now.
fn replicates_to_meet(shortfall: f64, replicates: u64) -> Option<u64> {
    if !shortfall.is_finite() {
        return None;
    }
    // t_{r-1} / sqrt(r) falls as r grows: the predicate holds from some r on, found by
    // bisection (a run may have up to 2^20 replicates).
    let scale = |r: u64| student_t_quantile(0.975, (r - 1) as f64) / (r as f64).sqrt();
    let now = scale(replicates);
    let enough = |r: u64| shortfall * scale(r) <= now;
    let (mut low, mut high) = (replicates, (2 * replicates).min(MAX_REPLICATES));
    if high <= low || !enough(high) {
        return None;
    }
    // Invariant: `low` is not enough (or is the current count), `high` is.
    while high - low > 1 {
        let middle = low + (high - low) / 2;
        if enough(middle) {
            high = middle;
        } else {
            low = middle;
        }
    }
    Some(high)
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

/// Points of independent samples the main stage needs for every target, from the
/// per-sample spread seen in `folded` (one replicate), each standard deviation inflated
/// by `z_inflated / z` (the two-stage rule's sizing, `(z * 1.1 * s / target)^2`).
fn points_needed(targets: &Targets<'_>, folded: &Folded, z_inflated: f64) -> u64 {
    let size = |sd: f64, target: f64| -> u64 {
        if sd == 0.0 {
            return 2;
        }
        let n = (z_inflated * sd / target).powi(2).ceil();
        if n.is_finite() && n < u64::MAX as f64 {
            (n as u64).max(2)
        } else {
            u64::MAX
        }
    };
    let mut needed = 2u64;
    for (k, t) in targets.outputs.iter().enumerate() {
        if let Some(t) = t {
            let acc = &folded.accumulators[k];
            needed = needed.max(size(acc.variance().sqrt(), t.target(acc.mean())));
        }
    }
    if !targets.derived.is_empty() {
        let run = folded.independent_estimate();
        let count = folded.accumulators[0].count();
        for (quantity, t) in targets.derived {
            needed = needed.max(match run.derived(quantity) {
                Ok(e) => match e.std_error {
                    Some(se) => size(se * (count as f64).sqrt(), t.target(e.mean)),
                    None => count.saturating_mul(2),
                },
                // A ratio whose denominator is not yet known to be nonzero: more points.
                Err(_) => count.saturating_mul(2),
            });
        }
    }
    needed
}
