//! Statistics: accumulation of contributions, estimates with confidence intervals, and the
//! distribution functions those need.

mod accumulator;
mod chi_square;
mod estimate;
mod normal;
mod student_t;

pub use accumulator::Accumulator;
pub use chi_square::{GoodnessOfFit, chi_square_goodness_of_fit, chi_square_sf};
pub use estimate::{ErrorBasis, Estimate};
pub use normal::{normal_cdf, normal_quantile, normal_sf};
pub use student_t::{student_t_cdf, student_t_quantile};
