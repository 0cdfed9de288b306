//! Measures of point-set quality and of convergence: how a user chooses a sampler by measuring
//! it (Jarosz's discussion of discrepancy, blue-noise spectra and convergence rates).
//!
//! Every measure takes a [`Points`](crate::Points) block (or a sampler), works in `[0,1)^d`,
//! and returns plain numbers, so the example binaries can print and plot them.

mod convergence;
mod discrepancy;
mod geometric_discrepancy;
mod nets;
mod spectrum;
mod star_discrepancy;
mod update_discrepancy;

pub use convergence::{Convergence, ConvergencePoint, ConvergenceStudy};
pub use discrepancy::Discrepancy;
pub(crate) use discrepancy::check_unit_cube;
pub use geometric_discrepancy::{GeometricCriterion, geometric_discrepancy};
pub use nets::{
    NetCheck, UnbalancedInterval, elementary_intervals_balanced, shape_balanced, t_value,
};
pub use spectrum::{
    Periodogram, RadialSpectrum, mean_periodogram, mean_periodogram_with_threads, periodogram,
    periodogram_with_threads,
};
pub use star_discrepancy::{STAR_DISCREPANCY_MAX_POINTS, star_discrepancy};
pub use update_discrepancy::update_discrepancy;
