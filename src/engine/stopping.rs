//! [`Stopping`]: the one rule every runner asks "stop now, and with which interval?".
//!
//! A run to a [`Tolerance`] works in stages (the Integrator's doublings, MISER's doublings,
//! VEGAS's iterations). Before a stage, [`Stopping::limit`] says whether the evaluation or
//! time limit stops the run; after it, [`Stopping::judge`] gives the interval the run reports
//! and whether it meets the tolerance.
//!
//! Replicate-based standard errors are inflated by [`REPLICATE_INFLATION`] when judged: the
//! replicate means of scrambled nets and of small adaptive runs are not normal at small sizes,
//! and stopping the first time their spread looks small favours runs whose spread is small by
//! chance (optional stopping); without the inflation the Integrator's RQMC intervals covered
//! 181-185 of 200 Genz cases where 190 were due. QMCPy's `CubQMCCLT` inflates by the same
//! factor by default. Per-sample errors of independent points (two-stage rule, VEGAS) are
//! judged as they are: their `n` is large and their variance estimate stable.

use super::{Executor, Limits};
use crate::error::Result;
use crate::stats::{ErrorBasis, Estimate, StopReason, Tolerance, Warning};

/// Inflation of a replicate-based standard error in a run to a tolerance.
pub(crate) const REPLICATE_INFLATION: f64 = 1.2;

/// Replicates of a fixed-budget randomized QMC run, and of MISER's runs, when the caller
/// gives none.
pub(crate) const DEFAULT_REPLICATES: u64 = 16;

/// Replicates the Integrator's run to a tolerance starts with when the caller gives none:
/// fewer, larger replicates reach a tolerance with fewer points (the spread of a scrambled
/// net's mean falls faster than `1/sqrt(n)`), and the run adds replicates when that is cheaper
/// than doubling. scipy's `qmc_quad` defaults to 8 as well.
pub(crate) const TOLERANCE_REPLICATES: u64 = 8;

/// The stopping rule of one run to a tolerance.
pub(crate) struct Stopping<'a> {
    tolerance: &'a Tolerance,
    limits: Limits,
    /// Reads the limits, agreed between the ranks of a run spread over a cluster.
    executor: Executor,
}

impl<'a> Stopping<'a> {
    /// The rule for a run that starts now, under `limits` (its time limit and cancellation),
    /// on `executor`.
    pub(crate) fn new(tolerance: &'a Tolerance, limits: Limits, executor: Executor) -> Self {
        Stopping {
            tolerance,
            limits,
            executor,
        }
    }

    /// The run's limits of time and cancellation, which its stages also check chunk by chunk.
    pub(crate) fn limits(&self) -> &Limits {
        &self.limits
    }

    /// The tolerance.
    pub(crate) fn tolerance(&self) -> &Tolerance {
        self.tolerance
    }

    /// Why the run should stop before spending `next` more evaluations, `used` spent so far:
    /// the time limit has passed, the run was cancelled, or `next` would exceed the
    /// evaluation limit.
    pub(crate) fn limit(&self, used: u64, next: u64) -> Result<Option<StopReason>> {
        if let Some(reason) = self.executor.reached(&self.limits)? {
            return Ok(Some(reason));
        }
        if used
            .checked_add(next)
            .is_none_or(|total| total > self.tolerance.evaluation_limit())
        {
            return Ok(Some(StopReason::MaxEvaluations));
        }
        Ok(None)
    }

    /// The estimate a stage reports (a replicate-based standard error inflated, see the
    /// module documentation) and whether it meets the tolerance.
    pub(crate) fn judge(&self, mut estimate: Estimate) -> (Estimate, bool) {
        if estimate.basis == ErrorBasis::Replicates {
            estimate.std_error = estimate.std_error.map(|s| s * REPLICATE_INFLATION);
        }
        let met = self.tolerance.is_met(&estimate);
        (estimate, met)
    }

    /// Records how the run ended on its final estimate, with a warning when it stopped on a
    /// limit.
    pub(crate) fn finish(&self, estimate: &mut Estimate, stop: StopReason, stages: u64) {
        estimate.stop = stop;
        estimate.converged = Some(self.tolerance.is_met(estimate));
        estimate.iterations = stages;
        if stop != StopReason::ToleranceMet {
            estimate.warn(Warning::ToleranceNotMet { stop });
        }
        estimate.finalize();
    }
}
