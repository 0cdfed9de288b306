//! Runs of the [`Integrator`] that stop at a [`Tolerance`]: a two-stage rule for independent
//! points, and doubling with fixed replicates for randomized QMC and stratified points.

use std::time::Instant;

use super::{CHUNK, Integrator, Plan};
use crate::estimator::Estimator;
use crate::sampler::{PassKind, Sampler};
use crate::stats::{Accumulator, Estimate, StopReason, Tolerance, normal_quantile};
use crate::{Error, Result};

/// Pilot size of the two-stage rule when the caller gives none.
const DEFAULT_PILOT: u64 = 4096;
/// Inflation of the pilot's standard deviation when sizing the main stage.
const SD_INFLATION: f64 = 1.1;
/// Replicates of a randomized run to a tolerance when the caller gives none.
const DEFAULT_REPLICATES: u64 = 16;
/// Inflation of the replicates' standard error in a randomized run to a tolerance (QMCPy's
/// `CubQMCCLT` inflates by the same 1.2 by default).
const RQMC_INFLATION: f64 = 1.2;
/// First points per replicate of a doubling run when the sampler has no pass size.
const DEFAULT_FIRST_STAGE: u64 = 1024;

/// Runs `integrator` until `tolerance` is met or a limit is reached.
pub(super) fn run_to_tolerance<E: Estimator>(
    integrator: &Integrator<E>,
    sampler: &dyn Sampler,
    threads: usize,
    tolerance: &Tolerance,
) -> Result<Estimate> {
    let dims = integrator.estimator.canonical_dims();
    if sampler.dims() != dims {
        return Err(Error::DimensionMismatch {
            what: "sampler (the estimator's canonical points)",
            expected: dims,
            found: sampler.dims(),
        });
    }
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
    let started = Instant::now();
    let stage = Stage {
        integrator,
        sampler,
        threads,
    };
    if sampler.passes() == PassKind::Independent {
        two_stage(&stage, tolerance, started)
    } else {
        doubling(&stage, tolerance, started)
    }
}

/// What every stage of one run shares.
struct Stage<'a, E> {
    integrator: &'a Integrator<E>,
    sampler: &'a dyn Sampler,
    threads: usize,
}

impl<E: Estimator> Stage<'_, E> {
    /// Accumulators of points `offset .. offset + samples` of each of `replicates`
    /// replicates, `stride` apart.
    fn run(
        &self,
        replicates: u64,
        stride: u64,
        offset: u64,
        samples: u64,
    ) -> Result<Vec<Accumulator>> {
        let plan = Plan {
            samples,
            offset,
            replicates,
            stride,
            chunks_per_replicate: samples.div_ceil(CHUNK),
        };
        let folded = plan.run_folded(self.sampler, &self.integrator.estimator, self.threads)?;
        plan.check_finite(self.sampler, &folded, self.integrator.non_finite)?;
        Ok(folded.replicates)
    }
}

/// Why the run should stop before spending `next` more evaluations, if it should.
fn limit_reached(
    tolerance: &Tolerance,
    started: Instant,
    used: u64,
    next: u64,
) -> Option<StopReason> {
    if tolerance
        .time()
        .is_some_and(|limit| started.elapsed() >= limit)
    {
        return Some(StopReason::TimeLimit);
    }
    if used
        .checked_add(next)
        .is_none_or(|total| total > tolerance.evaluation_limit())
    {
        return Some(StopReason::MaxEvaluations);
    }
    None
}

/// Independent points: a pilot sizes a fresh main stage (extended if it still misses).
fn two_stage<E: Estimator>(
    stage: &Stage<'_, E>,
    tolerance: &Tolerance,
    started: Instant,
) -> Result<Estimate> {
    let pilot_size = stage.integrator.samples.unwrap_or(DEFAULT_PILOT).max(2);
    if pilot_size > tolerance.evaluation_limit() {
        return Err(Error::invalid(
            "max_evals",
            tolerance.evaluation_limit(),
            format!("at least the pilot's {pilot_size} evaluations"),
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
        let more = match limit_reached(tolerance, started, used, more) {
            None => more,
            Some(StopReason::MaxEvaluations) => {
                let left = tolerance.evaluation_limit() - used;
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
        if main.count() >= 2 && tolerance.is_met(&main.estimate()) {
            break StopReason::ToleranceMet;
        }
        sd = main.variance().sqrt();
        mean = main.mean();
    };
    // Before any main stage ran, the pilot is all there is.
    let source = if main.count() >= 2 { &main } else { &pilot };
    let mut estimate = source.estimate();
    estimate.evaluations = used;
    finish(&mut estimate, tolerance, stop, stages);
    Ok(estimate)
}

/// Randomized QMC and stratified points: `R` replicates, doubling the points of each until
/// the Student-t interval over the replicates, with the standard error inflated by
/// [`RQMC_INFLATION`], meets the tolerance.
///
/// The inflation guards against two ways the plain interval covers less often than it
/// says: replicate means of scrambled nets at small sizes are not normal, and stopping the
/// first time the spread looks small favours runs whose spread is small by chance.
fn doubling<E: Estimator>(
    stage: &Stage<'_, E>,
    tolerance: &Tolerance,
    started: Instant,
) -> Result<Estimate> {
    let replicates = stage.integrator.replicates.unwrap_or(DEFAULT_REPLICATES);
    if replicates < 2 {
        return Err(Error::invalid(
            "replicates",
            replicates,
            "at least 2 for a run to a tolerance (the error bar comes from their spread)",
        ));
    }
    let limit = tolerance.evaluation_limit();
    let (first, stride) = first_stage_and_stride(stage, replicates, limit)?;
    (replicates - 1)
        .checked_mul(stride)
        .and_then(|s| s.checked_add(stride))
        .ok_or(Error::IndexOutOfRange {
            what: "sample index of the last replicate",
            limit: u64::MAX,
        })?;
    let mut accumulators = vec![Accumulator::new(); replicates as usize];
    let (mut done, mut next) = (0u64, first);
    let mut stages = 0;
    let mut estimate = None;
    let stop = loop {
        if next > stride {
            break StopReason::MaxEvaluations;
        }
        let cost = (next - done).saturating_mul(replicates);
        if let Some(reason) = limit_reached(tolerance, started, done * replicates, cost) {
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
        let means: Vec<f64> = accumulators.iter().map(Accumulator::mean).collect();
        let mut current = Estimate::from_replicates(&means, done)?;
        current.non_finite = accumulators.iter().map(Accumulator::non_finite).sum();
        current.n = accumulators.iter().map(Accumulator::count).sum();
        current.std_error = current.std_error.map(|s| s * RQMC_INFLATION);
        let met = tolerance.is_met(&current);
        estimate = Some(current);
        if met {
            break StopReason::ToleranceMet;
        }
        next = done.saturating_mul(2);
    };
    let mut estimate = estimate.ok_or_else(|| {
        Error::invalid(
            "max_evals",
            limit,
            format!(
                "at least {} evaluations ({replicates} replicates of {first} points)",
                replicates.saturating_mul(first)
            ),
        )
    })?;
    finish(&mut estimate, tolerance, stop, stages);
    Ok(estimate)
}

/// Points per replicate of the first stage, and the distance between replicates.
fn first_stage_and_stride<E: Estimator>(
    stage: &Stage<'_, E>,
    replicates: u64,
    limit: u64,
) -> Result<(u64, u64)> {
    match stage.sampler.passes() {
        PassKind::Fixed { size } => {
            let first = stage.integrator.samples.unwrap_or(size);
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
            let first = stage
                .integrator
                .samples
                .unwrap_or(DEFAULT_FIRST_STAGE.min(max));
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

fn finish(estimate: &mut Estimate, tolerance: &Tolerance, stop: StopReason, stages: u64) {
    estimate.stop = stop;
    estimate.converged = Some(tolerance.is_met(estimate));
    estimate.iterations = stages;
}
