//! [`StopReason`]: why a run stopped.

/// Why a run stopped.
///
/// ```
/// use mcint::{Integrator, pdf::UniformBox, stats::StopReason};
/// let e = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(10).run().unwrap();
/// assert_eq!(e.stop, StopReason::Budget);
/// ```
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// The fixed number of samples asked for was used.
    Budget,
    /// The requested absolute or relative tolerance was met.
    ToleranceMet,
    /// The maximum number of integrand evaluations was reached first.
    MaxEvaluations,
    /// The time limit was reached first.
    TimeLimit,
}
