//! [`Targets`]: the one judge of a run to a tolerance: what it must reach (a tolerance per
//! output, on derived quantities, or both), and whether an estimate reaches it.
//!
//! Replicate-based standard errors are inflated by [`REPLICATE_INFLATION`] when judged: the
//! replicate means of scrambled nets and of small adaptive runs are not normal at small sizes,
//! and stopping the first time their spread looks small favours runs whose spread is small by
//! chance (optional stopping); the inflation keeps the intervals of such runs at their nominal
//! coverage (the measurement is in docs/). QMCPy's `CubQMCCLT` inflates by the same factor by
//! default. Per-sample errors of independent points (the two-stage rule, VEGAS) are judged as
//! they are: their `n` is large and their variance estimate stable.

use std::time::Duration;

use crate::error::{Error, Result};
use crate::estimator::checked_outputs;
use crate::stats::{Derived, ErrorBasis, Estimate, StopReason, Tolerance, VectorEstimate, Warning};

/// Inflation of a replicate-based standard error in a run to a tolerance.
pub(crate) const REPLICATE_INFLATION: f64 = 1.2;

/// The tolerances of one run: `outputs[k]` for output `k` (none where only derived quantities
/// decide), and a tolerance for each derived quantity. A run meets them when every one is met.
pub(crate) struct Targets<'a> {
    pub(crate) outputs: Vec<Option<Tolerance>>,
    pub(crate) derived: &'a [(Derived, Tolerance)],
}

impl<'a> Targets<'a> {
    /// The targets of a run of `outputs` outputs: `each` output's own tolerance, or
    /// `tolerance` for all of them, and the derived quantities' (checked against `outputs`).
    pub(crate) fn new(
        outputs: usize,
        tolerance: Option<Tolerance>,
        each: Option<&[Tolerance]>,
        derived: &'a [(Derived, Tolerance)],
    ) -> Result<Targets<'a>> {
        let m = checked_outputs(outputs)?;
        let outputs = match each {
            Some(each) if each.len() != m => {
                return Err(Error::invalid(
                    "output tolerances",
                    format!("{} tolerances", each.len()),
                    format!("one tolerance per output ({m})"),
                ));
            }
            Some(each) => each.iter().copied().map(Some).collect(),
            // One tolerance for all outputs; none when only derived quantities decide.
            None => vec![tolerance; m],
        };
        for (quantity, _) in derived {
            quantity.check(m)?;
        }
        Ok(Targets { outputs, derived })
    }

    /// Whether there is anything to reach (otherwise the run has a fixed budget).
    pub(crate) fn any(&self) -> bool {
        self.outputs.iter().any(Option::is_some) || !self.derived.is_empty()
    }

    /// The run's limits, as a tolerance: the fewest evaluations and the shortest time any of
    /// the tolerances allows (`None` without targets: a fixed budget).
    pub(crate) fn limits(&self) -> Option<Tolerance> {
        let mut all = self
            .outputs
            .iter()
            .flatten()
            .chain(self.derived.iter().map(|(_, t)| t));
        let mut limits = *all.next()?;
        for t in all {
            if t.evaluation_limit() < limits.evaluation_limit() {
                limits = limits
                    .max_evaluations(t.evaluation_limit())
                    .unwrap_or(limits);
            }
            if let Some(time) = t.time() {
                limits = limits.time_limit(limits.time().map_or(time, |own| own.min(time)));
            }
        }
        Some(limits)
    }

    /// The shortest time limit of the tolerances, if any.
    pub(crate) fn time(&self) -> Option<Duration> {
        self.limits().and_then(|t| t.time())
    }

    /// An error when a derived quantity's error bar cannot be formed from `run` at all (its
    /// outputs' variances below what f64 holds: see `Derived`), or its function panicked:
    /// more points would not help, so the run stops at once rather than at its evaluation
    /// limit.
    pub(crate) fn check_representable(&self, run: &VectorEstimate) -> Result<()> {
        self.derived
            .iter()
            .try_for_each(|(quantity, _)| quantity.check_representable(run))
    }

    /// Whether the estimate meets every target.
    pub(crate) fn met(&self, run: &VectorEstimate) -> bool {
        let outputs = self
            .outputs
            .iter()
            .zip(&run.outputs)
            .all(|(t, e)| t.is_none_or(|t| t.is_met(e)));
        outputs
            && self
                .derived
                .iter()
                .all(|(quantity, t)| run.derived(quantity).is_ok_and(|e| t.is_met(&e)))
    }

    /// How far the estimate is from meeting every target: the largest ratio of a 95%
    /// half-width to its target (at most 1 when every target is met; infinite when one has no
    /// error bar yet).
    pub(crate) fn shortfall(&self, run: &VectorEstimate) -> f64 {
        let ratio = |e: &Estimate, t: &Tolerance| match e.half_width(0.95) {
            Ok(Some(h)) => h / t.target(e.mean),
            _ => f64::INFINITY,
        };
        let outputs = self
            .outputs
            .iter()
            .zip(&run.outputs)
            .filter_map(|(t, e)| t.as_ref().map(|t| ratio(e, t)));
        let derived = self.derived.iter().map(|(quantity, t)| {
            run.derived(quantity)
                .map_or(f64::INFINITY, |e| ratio(&e, t))
        });
        outputs.chain(derived).fold(0.0, |worst, r| {
            if r.is_nan() {
                f64::INFINITY
            } else {
                worst.max(r)
            }
        })
    }

    /// The estimate a stage reports (replicate-based standard errors and covariances inflated,
    /// see the module documentation) and whether it meets every target.
    pub(crate) fn judge(&self, mut run: VectorEstimate) -> (VectorEstimate, bool) {
        if run.outputs[0].basis == ErrorBasis::Replicates {
            run.inflate(REPLICATE_INFLATION);
        }
        let met = self.met(&run);
        (run, met)
    }

    /// Records how the run ended on its final estimate: per output, whether its own target
    /// (or, without one, every target) was met, and a warning when it stopped on a limit. A
    /// run that stopped because its iterations disagree met none: its intervals cannot be
    /// trusted, however narrow. Outputs whose iterations disagree get intervals as wide as
    /// the iterations' scatter (see `VectorEstimate::widen_where_iterations_disagree`).
    pub(crate) fn finish(&self, run: &mut VectorEstimate, stop: StopReason) {
        run.widen_where_iterations_disagree();
        let trusted = stop != StopReason::IterationsDisagree;
        let all = trusted && self.met(run);
        let own: Vec<bool> = self
            .outputs
            .iter()
            .zip(&run.outputs)
            .map(|(t, e)| trusted && t.map_or(all, |t| t.is_met(e)))
            .collect();
        run.for_each_output(|k, output| {
            output.stop = stop;
            output.converged = Some(own[k]);
            if stop != StopReason::ToleranceMet {
                output.warn(Warning::ToleranceNotMet { stop });
            }
            output.finalize();
        });
        run.converged = Some(all);
        run.stop = stop;
    }
}
