//! Measures of how evenly a point set fills the unit cube: discrepancies and the t-values of
//! digital nets.
//!
//! Each is a pure function of a [`Points`](crate::Points) block in `[0,1)^d`, so the samplers
//! that optimize their points (Lloyd relaxation, the centered-discrepancy search) can use
//! them; [`quality`](crate::quality) hands them to users beside the studies that run samplers
//! through the engine.

mod discrepancy;
mod geometric_discrepancy;
mod nets;
mod star_discrepancy;
mod update_discrepancy;

pub use discrepancy::Discrepancy;
pub(crate) use discrepancy::check_unit_cube;
pub use geometric_discrepancy::{GeometricCriterion, geometric_discrepancy};
pub use nets::{
    NetCheck, UnbalancedInterval, elementary_intervals_balanced, shape_balanced, t_value,
};
pub use star_discrepancy::{STAR_DISCREPANCY_MAX_POINTS, star_discrepancy};
pub use update_discrepancy::update_discrepancy;
