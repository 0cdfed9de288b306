//! The [`Integrator`](super::Integrator)'s runs as stages for the engine's driver: a fixed
//! budget (one stage), and the runs to a [`Tolerance`](crate::stats::Tolerance): a two-stage
//! rule for independent points, and doubling with fixed replicates for randomized QMC and
//! stratified points.

use super::plan::{Folded, MAX_ACCUMULATORS, MAX_REPLICATES, Plan, balance_warning};
use crate::engine::{
    Executor, Limits, Next, RunConfig, StageEnd, Stages, TOLERANCE_REPLICATES, Targets, Verdict,
};
use crate::error::{Error, Result};
use crate::estimator::VectorEstimator;
use crate::sampler::{PassKind, Sampler};
use crate::special::{normal_quantile, student_t_quantile};
use crate::stats::{StopReason, VectorEstimate};

/// Pilot size of the two-stage rule when the caller gives none.
const DEFAULT_PILOT: u64 = 4096;
/// Inflation of the pilot's standard deviation when sizing the main stage.
const SD_INFLATION: f64 = 1.1;
/// First points per replicate of a doubling run when the sampler has no pass size.
const DEFAULT_FIRST_STAGE: u64 = 1024;

/// What every stage of one run shares: the estimator's points, and how counts of
/// contributions become evaluations.
pub(super) struct Common<'a> {
    pub(super) estimator: &'a dyn VectorEstimator,
    pub(super) config: &'a RunConfig,
    pub(super) sampler: &'a dyn Sampler,
    /// Integrand evaluations per contribution.
    pub(super) cost: u64,
    /// Evaluations of the estimator's pilot, before the first stage.
    pub(super) pilot_evaluations: u64,
}

impl Common<'_> {
    /// The fold of the points of `plan`, the chunks folded, the limit that stopped it before
    /// its end (if one did), and the first non-finite contribution (if any); `progress` is told
    /// the plan's evaluations folded so far.
    fn run(
        &self,
        plan: &Plan,
        executor: &Executor,
        limits: &Limits,
        progress: &mut dyn FnMut(u64),
    ) -> Result<(Folded, u64, StageEnd)> {
        let mut points = 0;
        let mut on_points = |more: u64| {
            points += more;
            progress(points * self.cost);
        };
        let (folded, chunks, stop) = plan.run_folded(
            executor,
            limits,
            self.sampler,
            self.estimator,
            &mut on_points,
        )?;
        let non_finite = plan.non_finite(self.sampler, &folded, self.config.non_finite)?;
        Ok((folded, chunks, StageEnd { stop, non_finite }))
    }

    /// `run` with its evaluations counted as integrand evaluations, pilot included.
    fn counted(&self, mut run: VectorEstimate, stages: u64) -> VectorEstimate {
        run.for_each_output(|_, output| {
            output.evaluations = output
                .evaluations
                .saturating_mul(self.cost)
                .saturating_add(self.pilot_evaluations);
            output.iterations = stages;
        });
        run
    }
}

/// A fixed budget: one stage of the whole plan. A limit that stops it keeps the finished
/// chunks of independent points, or the complete replicates of dependent ones.
pub(super) struct Fixed<'a> {
    pub(super) common: Common<'a>,
    pub(super) plan: Plan,
    /// The fold, the chunks folded and the limit that stopped it, once run.
    pub(super) done: Option<(Folded, u64, Option<StopReason>)>,
}

impl Stages for Fixed<'_> {
    fn next(&mut self, _left: u64) -> Result<Next> {
        if self.done.is_some() {
            return Ok(Next::Done(StopReason::Budget));
        }
        let planned = self.plan.samples.saturating_mul(self.plan.replicates);
        Ok(Next::Stage(planned.saturating_mul(self.common.cost)))
    }

    fn run(
        &mut self,
        executor: &Executor,
        limits: &Limits,
        progress: &mut dyn FnMut(u64),
    ) -> Result<StageEnd> {
        let (folded, chunks, end) = self.common.run(&self.plan, executor, limits, progress)?;
        self.done = Some((folded, chunks, end.stop));
        Ok(end)
    }

    fn has_estimate(&self) -> bool {
        self.done.is_some()
    }

    fn estimate(&mut self) -> Result<Option<VectorEstimate>> {
        let Some((folded, chunks, stop)) = &self.done else {
            return Ok(None);
        };
        let (sampler, policy) = (self.common.sampler, self.common.config.non_finite);
        let run = match stop {
            None => self.plan.estimate(sampler, folded, policy)?,
            Some(stop) => {
                self.plan
                    .estimate_stopped(sampler, folded.clone(), *chunks, policy, *stop)?
            }
        };
        Ok(Some(self.common.counted(run, 1)))
    }
}

/// The runs to a tolerance, checked and set up: a two-stage rule for independent points, and
/// doubling for the others.
pub(super) fn to_tolerance<'a>(
    common: Common<'a>,
    targets: &'a Targets<'a>,
) -> Result<Box<dyn Stages + Send + 'a>> {
    let sampler = common.sampler;
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
    common
        .config
        .check_budget("max_evals", limits.evaluation_limit())?;
    // Contributions the evaluation limit allows.
    let limit = limits.evaluation_limit() / common.cost.max(1);
    if sampler.passes() == PassKind::Independent {
        Ok(Box::new(PilotAndMain::new(common, targets, limit)?))
    } else {
        Ok(Box::new(Doubling::new(common, limit)?))
    }
}

/// Independent points: a pilot, which stands if it meets the tolerance, else sizes a fresh
/// main stage of at least its own size (extended if it still misses).
struct PilotAndMain<'a> {
    common: Common<'a>,
    targets: &'a Targets<'a>,
    pilot_size: u64,
    /// The contributions the evaluation limit allows.
    limit: u64,
    pilot: Option<Folded>,
    main: Option<Folded>,
    /// Contributions folded so far, and whole stages.
    used: u64,
    stages: u64,
    /// The next stage's points.
    next: u64,
}

impl<'a> PilotAndMain<'a> {
    fn new(common: Common<'a>, targets: &'a Targets<'a>, limit: u64) -> Result<Self> {
        let pilot_size = common.config.samples.unwrap_or(DEFAULT_PILOT).max(2);
        if pilot_size > limit {
            return Err(Error::invalid(
                "max_evals",
                limit.saturating_mul(common.cost),
                format!(
                    "at least the pilot's {} evaluations",
                    pilot_size.saturating_mul(common.cost)
                ),
            ));
        }
        Ok(PilotAndMain {
            common,
            targets,
            pilot_size,
            limit,
            pilot: None,
            main: None,
            used: 0,
            stages: 0,
            next: 0,
        })
    }

    /// The fold the estimate comes from: the main stages once they have two values, before
    /// that the pilot.
    fn source(&self) -> Option<&Folded> {
        match &self.main {
            Some(main) if main.accumulators[0].count() >= 2 => Some(main),
            _ => self.pilot.as_ref(),
        }
    }
}

impl Stages for PilotAndMain<'_> {
    fn next(&mut self, _left: u64) -> Result<Next> {
        let Some(pilot) = &self.pilot else {
            self.next = self.pilot_size;
            return Ok(Next::Stage(self.pilot_size * self.common.cost));
        };
        let z = normal_quantile(0.975) * SD_INFLATION;
        let current = self.main.as_ref().unwrap_or(pilot);
        // The main stage is never smaller than the pilot that sized it.
        let needed = points_needed(self.targets, current, z).max(self.pilot_size);
        let main_count = self.main.as_ref().map_or(0, |m| m.accumulators[0].count());
        let more = needed.saturating_sub(main_count).max(1);
        // The last stage is cut to what the evaluation limit leaves.
        let left = self.limit.saturating_sub(self.used);
        if left == 0 {
            return Ok(Next::Done(StopReason::MaxEvaluations));
        }
        self.next = more.min(left);
        Ok(Next::Stage(self.next * self.common.cost))
    }

    fn run(
        &mut self,
        executor: &Executor,
        limits: &Limits,
        progress: &mut dyn FnMut(u64),
    ) -> Result<StageEnd> {
        // Replicate 0 only: the pilot takes indices 0 .. pilot, the main stages what follows.
        let plan = Plan::stage(1, 0, self.used, self.next)?;
        let (part, _, end) = self.common.run(&plan, executor, limits, progress)?;
        self.used += part.points();
        match (&mut self.pilot, &mut self.main) {
            (None, _) => self.pilot = Some(part),
            (Some(_), Some(main)) => main.merge(&part),
            (Some(_), None) => self.main = Some(part),
        }
        // Independent points: the finished chunks of a stage cut short are an estimate of
        // their own (the pilot's), or join the main fold as they are.
        self.stages += 1;
        Ok(end)
    }

    fn has_estimate(&self) -> bool {
        self.source()
            .is_some_and(|folded| folded.accumulators[0].count() >= 2)
    }

    fn estimate(&mut self) -> Result<Option<VectorEstimate>> {
        if !self.has_estimate() {
            return Ok(None);
        }
        let Some(source) = self.source() else {
            return Ok(None);
        };
        let mut run = source.independent_estimate();
        if self.main.is_some() {
            let used = self.used;
            run.for_each_output(|_, output| output.evaluations = used);
        }
        Ok(Some(self.common.counted(run, self.stages)))
    }
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
struct Doubling<'a> {
    common: Common<'a>,
    /// Points per replicate of the first stage, and the distance between replicates.
    first: u64,
    stride: u64,
    folded: Option<Folded>,
    /// Points per replicate so far, and replicates so far.
    done: u64,
    replicates: u64,
    grow: Grow,
    stages: u64,
}

/// The next stage of a doubling run.
#[derive(Debug, Clone, Copy)]
enum Grow {
    /// Every replicate continues up to this many points.
    Points(u64),
    /// This many new replicates of the current size.
    Replicates(u64),
}

impl<'a> Doubling<'a> {
    fn new(common: Common<'a>, limit: u64) -> Result<Self> {
        let first_replicates = common.config.replicates.unwrap_or(TOLERANCE_REPLICATES);
        if first_replicates < 2 {
            return Err(Error::invalid(
                "replicates",
                first_replicates,
                "at least 2 for a run to a tolerance (the error bar comes from their spread)",
            ));
        }
        let (first, stride) = first_stage_and_stride(&common, first_replicates, limit)?;
        Plan::stage(first_replicates, stride, 0, stride)?;
        if first_replicates.saturating_mul(first) > limit {
            return Err(Error::invalid(
                "max_evals",
                limit.saturating_mul(common.cost),
                format!(
                    "at least {} evaluations ({first_replicates} replicates of {first} points)",
                    first_replicates
                        .saturating_mul(first)
                        .saturating_mul(common.cost)
                ),
            ));
        }
        Ok(Doubling {
            common,
            first,
            stride,
            folded: None,
            done: 0,
            replicates: first_replicates,
            grow: Grow::Points(first),
            stages: 0,
        })
    }

    /// The plan of the next stage and its contributions.
    fn plan(&self) -> Result<(Plan, u64)> {
        let (done, replicates) = (self.done, self.replicates);
        Ok(match self.grow {
            Grow::Points(next) => (
                Plan::stage(replicates, self.stride, done, next - done)?,
                (next - done).saturating_mul(replicates),
            ),
            Grow::Replicates(more) => (
                Plan::added(replicates, more, self.stride, 0, done)?,
                more.saturating_mul(done),
            ),
        })
    }
}

impl Stages for Doubling<'_> {
    fn next(&mut self, _left: u64) -> Result<Next> {
        if let Grow::Points(next) = self.grow
            && next > self.stride
        {
            // The next doubling would run past the end of the sampler's pass.
            return Ok(Next::Done(StopReason::SamplerExhausted));
        }
        let (_, cost) = self.plan()?;
        Ok(Next::Stage(cost.saturating_mul(self.common.cost)))
    }

    fn run(
        &mut self,
        executor: &Executor,
        limits: &Limits,
        progress: &mut dyn FnMut(u64),
    ) -> Result<StageEnd> {
        let (plan, _) = self.plan()?;
        let (parts, _, end) = self.common.run(&plan, executor, limits, progress)?;
        // A stage cut short leaves replicates of unequal sizes: the last whole stage's
        // estimate stands.
        if end.stop.is_some() {
            return Ok(end);
        }
        match (self.folded.as_mut(), self.grow) {
            (Some(all), Grow::Points(_)) => all.merge(&parts),
            (Some(all), Grow::Replicates(_)) => all.append(&parts),
            (None, _) => self.folded = Some(parts),
        }
        match self.grow {
            Grow::Points(next) => self.done = next,
            Grow::Replicates(more) => self.replicates += more,
        }
        self.stages += 1;
        Ok(end)
    }

    fn has_estimate(&self) -> bool {
        self.folded.is_some()
    }

    fn estimate(&mut self) -> Result<Option<VectorEstimate>> {
        let Some(all) = &self.folded else {
            return Ok(None);
        };
        let mut run = VectorEstimate::replicates(&all.accumulators, all.outputs)?;
        if let Some(warning) = balance_warning(self.common.sampler, self.first) {
            run.for_each_output(|_, output| output.warn(warning.clone()));
        }
        Ok(Some(self.common.counted(run, self.stages)))
    }

    fn verdict(&mut self, judged: &VectorEstimate, met: bool, targets: &Targets<'_>) -> Verdict {
        if met {
            return Verdict::Met;
        }
        // The first stage's spread, of the smallest replicates, is the least reliable (their
        // means are the most skewed): the run doubles at least once before adding replicates,
        // and adds them only when that costs less than a doubling.
        let added = (self.done > self.first)
            .then(|| replicates_to_meet(targets.shortfall(judged), self.replicates))
            .flatten()
            // Within the fold's accumulators (one per output of each replicate).
            .filter(|&enough| {
                enough.saturating_mul(self.common.estimator.outputs() as u64) <= MAX_ACCUMULATORS
            })
            .map(|enough| enough - self.replicates)
            .filter(|&more| more < self.replicates);
        self.grow = added.map_or(Grow::Points(self.done.saturating_mul(2)), Grow::Replicates);
        Verdict::Continue
    }
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
fn first_stage_and_stride(common: &Common<'_>, replicates: u64, limit: u64) -> Result<(u64, u64)> {
    let samples = common.config.samples;
    match common.sampler.passes() {
        PassKind::Fixed { size } => {
            let first = samples.unwrap_or(size);
            if first == 0 || !first.is_multiple_of(size) {
                return Err(Error::invalid(
                    "samples",
                    first,
                    format!(
                        "a positive multiple of the {} sampler's pass size {size}",
                        common.sampler.name()
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
                        common.sampler.name()
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
            needed = needed.max(size(acc.std_dev(), t.target(acc.mean())));
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
