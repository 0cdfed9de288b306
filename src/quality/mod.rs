//! Measures of point-set quality and of convergence: how a user chooses a sampler by measuring
//! it (Jarosz's discussion of discrepancy, blue-noise spectra and convergence rates).
//!
//! Every measure takes a [`Points`](crate::Points) block (or a sampler), works in `[0,1)^d`,
//! and returns plain numbers, so the example binaries can print and plot them. The measures
//! of one point set (discrepancies, t-values) live in a lower module that samplers may use
//! too; the studies here (convergence rates, spectra) run samplers through the engine.

mod convergence;
mod spectrum;

pub use crate::uniformity::{
    Discrepancy, GeometricCriterion, NetCheck, STAR_DISCREPANCY_MAX_POINTS, UnbalancedInterval,
    elementary_intervals_balanced, geometric_discrepancy, shape_balanced, star_discrepancy,
    t_value, update_discrepancy,
};
pub use convergence::{Convergence, ConvergencePoint, ConvergenceStudy};
pub use spectrum::{
    Periodogram, RadialSpectrum, mean_periodogram, mean_periodogram_with_threads, periodogram,
    periodogram_with_threads,
};
