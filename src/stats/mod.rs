//! Statistics: accumulation of contributions, estimates with confidence intervals, and the
//! distribution functions those need.

mod accumulator;
mod estimate;
mod normal;
mod student_t;

pub use accumulator::Accumulator;
pub use estimate::{ErrorBasis, Estimate};
pub use normal::{normal_cdf, normal_quantile, normal_sf};
pub use student_t::{student_t_cdf, student_t_quantile};
