//! [`StopReason`]: why a run stopped.
//!
//! It sits below every other module because the error of an interrupted run
//! ([`Error::Interrupted`](crate::Error::Interrupted)) names it; users reach it as
//! `mcint::StopReason` and `mcint::stats::StopReason`.

/// Why a run stopped.
///
/// ```
/// use mcint::{Integrator, pdf::UniformBox, stats::StopReason};
/// let e = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(10).run().unwrap();
/// assert_eq!(e.stop, StopReason::Budget);
/// ```
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum StopReason {
    /// The fixed number of samples asked for was used.
    Budget,
    /// The requested absolute or relative tolerance was met.
    ToleranceMet,
    /// The maximum number of integrand evaluations was reached first.
    MaxEvaluations,
    /// The time limit was reached first.
    TimeLimit,
    /// The run was cancelled through its [`CancelToken`](crate::CancelToken).
    Cancelled,
    /// The sampler ran out of points: a run to a tolerance reached the end of a pass (the
    /// most points per replicate an extensible sequence has).
    SamplerExhausted,
    /// The iterations a run to a tolerance combines kept disagreeing
    /// ([`Warning::IterationsDisagree`](crate::stats::Warning::IterationsDisagree)) after
    /// their size had doubled four times (or, where it could not grow, after twice the
    /// evaluations at which the interval would otherwise have met the tolerance): their error
    /// bars are too small, and more iterations would not make the interval honest (VEGAS). The
    /// run is not `converged`, and its standard error is the iterations' scatter (see the
    /// warning). The CLI calls it `disagreement`.
    IterationsDisagree,
    /// A multilevel run reached its deepest level allowed with the bias estimate still above
    /// its share of the target ([`Warning::BiasAboveTarget`](crate::stats::Warning::BiasAboveTarget)):
    /// the sampling error meets its share, the bias may not. The run is not `converged`.
    MaxLevel,
    /// A multilevel run found a level whose coarse samples do not have the law of the previous
    /// level's fine ones (Giles' consistency check at six standard errors,
    /// [`Warning::InconsistentLevels`](crate::stats::Warning::InconsistentLevels)): a coupling
    /// error in the model, which biases the estimate and which more levels cannot mend, so
    /// the run adds none. The run is not `converged`.
    InconsistentLevels,
}

impl StopReason {
    /// A short lower-case name, the one the command line prints (`"budget"`, `"tolerance
    /// met"`, `"max evaluations"`, `"time limit"`, `"cancelled"`, `"sampler exhausted"`,
    /// `"disagreement"`, `"max level"`, `"inconsistent levels"`).
    ///
    /// ```
    /// assert_eq!(mcint::StopReason::IterationsDisagree.name(), "disagreement");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            StopReason::Budget => "budget",
            StopReason::ToleranceMet => "tolerance met",
            StopReason::MaxEvaluations => "max evaluations",
            StopReason::TimeLimit => "time limit",
            StopReason::Cancelled => "cancelled",
            StopReason::SamplerExhausted => "sampler exhausted",
            StopReason::IterationsDisagree => "disagreement",
            StopReason::MaxLevel => "max level",
            StopReason::InconsistentLevels => "inconsistent levels",
        }
    }
}
