//! Statistics: accumulation of contributions (scalar, and vector-valued with a covariance
//! matrix for control variates), estimates with confidence intervals, and the distribution
//! functions those need.

mod accumulator;
mod chi_square;
mod covariance;
mod estimate;
mod normal;
mod student_t;
mod tolerance;

pub use accumulator::Accumulator;
pub use chi_square::{GoodnessOfFit, chi_square_goodness_of_fit, chi_square_sf};
pub use covariance::CovarianceAccumulator;
pub use estimate::{ErrorBasis, Estimate, StopReason};
pub use normal::{normal_cdf, normal_quantile, normal_sf};
pub use student_t::{student_t_cdf, student_t_quantile};
pub use tolerance::Tolerance;
