//! [`drive`]: the one stage loop under every runner.
//!
//! A runner describes its run as [`Stages`]: what its next stage costs (or why there is none),
//! how to run it on the executor, and the estimate of the stages so far. The driver does the
//! rest, the same way for every method:
//!
//! * before each stage it reads the time limit and the cancellation (in agreement over MPI
//!   ranks), and, once there is an estimate, refuses a stage past the evaluation limit;
//! * it runs the stage, and fails the run on a non-finite contribution unless the policy is
//!   to skip them;
//! * after a stage of a run to a tolerance it judges the estimate with the one judge,
//!   [`Targets`], and asks the method's own verdict (VEGAS's iterations must agree);
//! * at the end it records how the run ended: the stop reason, whether the targets were met,
//!   and the warnings that go with them.
//!
//! A stage cut short by a limit leaves the estimate of the stages before it (each method
//! decides what it keeps of the cut stage); a run with no estimate by then is
//! [`Error::Interrupted`].

use super::{Executor, Limits, RunConfig, Targets};
use crate::error::{Error, Result};
use crate::non_finite::NonFinitePolicy;
use crate::stats::{StopReason, VectorEstimate, Warning};

/// A run as the driver sees it: a sequence of stages.
pub(crate) trait Stages {
    /// The evaluations the next stage plans, at most `left` where the method can (the
    /// evaluation limit minus what was spent; `u64::MAX` without one), or why there is no next
    /// stage.
    fn next(&mut self, left: u64) -> Result<Next>;

    /// Runs the stage `next` planned, checking `limits` chunk by chunk, telling `progress` the
    /// stage's evaluations folded so far.
    fn run(
        &mut self,
        executor: &Executor,
        limits: &Limits,
        progress: &mut dyn FnMut(u64),
    ) -> Result<StageEnd>;

    /// Whether the stages so far give an estimate (VEGAS's warm-up gives none).
    fn has_estimate(&self) -> bool;

    /// The estimate of the stages so far, with its evaluations and stages counted; `None`
    /// when there is none.
    fn estimate(&mut self) -> Result<Option<VectorEstimate>>;

    // The driver finalizes the estimate it returns (finalizing is idempotent), after the
    // warnings of how the run ended: an estimate need not be finalized here.

    /// Whether a judged estimate stops the run: `met` says whether it meets every target.
    /// Methods whose error bar needs more than the interval to be trusted override it.
    fn verdict(&mut self, _judged: &VectorEstimate, met: bool, _targets: &Targets<'_>) -> Verdict {
        if met { Verdict::Met } else { Verdict::Continue }
    }
}

/// What comes next in a run.
pub(crate) enum Next {
    /// A stage of this many evaluations.
    Stage(u64),
    /// No more stages, for this reason (its budget spent, its sampler exhausted, or no stage
    /// fits the evaluation limit).
    Done(StopReason),
}

/// How a stage ended.
#[derive(Default)]
pub(crate) struct StageEnd {
    /// The limit that cut it short, if one did.
    pub(crate) stop: Option<StopReason>,
    /// The first non-finite contribution it met, kept out of its sums, if any.
    pub(crate) non_finite: Option<NonFinite>,
}

/// Whether a judged estimate stops the run.
pub(crate) enum Verdict {
    Continue,
    /// Every target is met.
    Met,
    /// The run stops without meeting them, for this reason.
    Stop(StopReason),
}

/// The first non-finite contribution of a stage: the only source of
/// [`Error::NonFiniteContribution`].
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct NonFinite {
    /// Non-finite contributions in all.
    pub(crate) count: u64,
    /// The replicate (iteration, stratum) of the first one, and its index there.
    pub(crate) replicate: u64,
    pub(crate) index: u64,
    /// Its output, in a run of several.
    pub(crate) output: Option<usize>,
    pub(crate) value: f64,
    /// The point, in the sampler's canonical coordinates.
    pub(crate) point: Vec<f64>,
}

impl NonFinite {
    /// The error of a run that met it.
    pub(crate) fn into_error(self) -> Error {
        Error::NonFiniteContribution {
            count: self.count,
            first_index: self.index,
            first_replicate: self.replicate,
            first_output: self.output,
            first_value: self.value,
            first_point: self.point,
        }
    }
}

/// What a run shares with its driver.
pub(crate) struct Drive<'a> {
    pub(crate) executor: &'a Executor,
    pub(crate) limits: &'a Limits,
    /// What a run to a tolerance must reach; none for a fixed budget.
    pub(crate) targets: &'a Targets<'a>,
    pub(crate) config: &'a RunConfig,
    /// Evaluations spent before the first stage (a pilot's).
    pub(crate) spent: u64,
    /// Evaluations a fixed budget plans, for progress and the stopped-early warning (0 when
    /// a run to a tolerance cannot know).
    pub(crate) planned: u64,
}

/// Runs `stages` to its end (see the module documentation), on a thread of the executor's
/// pool: the work between stages then wakes no thread, and each stage's parallel work starts
/// on the thread already running instead of waiting for a sleeping one.
pub(crate) fn drive(stages: &mut (dyn Stages + Send), drive: &Drive<'_>) -> Result<VectorEstimate> {
    drive.executor.on_pool(|| drive_here(stages, drive))
}

/// [`drive`] on the calling thread.
fn drive_here(stages: &mut (dyn Stages + Send), drive: &Drive<'_>) -> Result<VectorEstimate> {
    let targets = drive.targets;
    let limit = targets.limits().map_or(u64::MAX, |t| t.evaluation_limit());
    let mut spent = drive.spent;
    let stop = loop {
        let planned = match stages.next(limit.saturating_sub(spent))? {
            Next::Stage(evaluations) => evaluations,
            Next::Done(reason) => break reason,
        };
        if let Some(reason) = drive.executor.reached(drive.limits)? {
            break reason;
        }
        if stages.has_estimate() && spent.checked_add(planned).is_none_or(|t| t > limit) {
            break StopReason::MaxEvaluations;
        }
        let before = spent;
        let mut progress = |done: u64| {
            spent = before + done;
            drive.config.report(spent, drive.planned);
        };
        let end = stages.run(drive.executor, drive.limits, &mut progress)?;
        if let Some(found) = end.non_finite
            && drive.config.non_finite == NonFinitePolicy::Fail
        {
            return Err(found.into_error());
        }
        if let Some(reason) = end.stop {
            break reason;
        }
        if !targets.any() || !stages.has_estimate() {
            continue;
        }
        let Some(estimate) = stages.estimate()? else {
            continue;
        };
        targets.check_representable(&estimate)?;
        let (judged, met) = targets.judge(estimate);
        match stages.verdict(&judged, met, targets) {
            Verdict::Continue => {}
            Verdict::Met => break StopReason::ToleranceMet,
            Verdict::Stop(reason) => break reason,
        }
    };
    let Some(mut estimate) = stages.estimate()? else {
        return Err(Error::Interrupted {
            stop,
            evaluations: spent,
        });
    };
    if targets.any() {
        // The reported interval is the judged one.
        estimate = targets.judge(estimate).0;
        targets.finish(&mut estimate, stop);
    } else {
        estimate.for_each_output(|_, output| {
            output.stop = stop;
            if stop != StopReason::Budget {
                output.warn(Warning::StoppedEarly {
                    stop,
                    done: output.evaluations,
                    planned: drive.planned,
                });
            }
            output.finalize();
        });
        estimate.stop = stop;
    }
    Ok(estimate)
}
