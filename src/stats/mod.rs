//! Statistics: accumulation of contributions (scalar, and vector-valued with a covariance
//! matrix for control variates and vector integrands), estimates with confidence intervals
//! (one integral, several over the same points, and smooth functions of them), stopping tolerances, and
//! Pearson's chi-square test of sample quality. The distribution functions behind them live
//! in the private `special` module.

mod accumulator;
mod covariance;
mod derived;
mod display;
mod estimate;
mod goodness_of_fit;
pub(crate) mod rounding;
mod tolerance;
mod vector_estimate;
mod warning;

pub use crate::stop_reason::StopReason;
pub use accumulator::Accumulator;
pub(crate) use accumulator::{UNSCALED_LIMIT, scale_for};
pub use covariance::CovarianceAccumulator;
pub use derived::Derived;
pub(crate) use derived::unrepresentable_output;
pub use estimate::{ErrorBasis, Estimate};
pub use goodness_of_fit::{GoodnessOfFit, chi_square_goodness_of_fit};
pub use tolerance::Tolerance;
pub use vector_estimate::VectorEstimate;
pub use warning::{DISAGREEMENT_Q, HEAVY_TAIL_KURTOSIS, Warning};
