//! Measures of point-set quality and of convergence: how a user chooses a sampler by measuring
//! it (the seed's discussion of discrepancy, blue-noise spectra and convergence rates).
//!
//! Every measure takes points as rows of a slice of `[f64]` points or a
//! [`Points`](crate::Points) block, works in `[0,1)^d`, and returns plain numbers, so the
//! example binaries can print and plot them.

mod discrepancy;
mod star_discrepancy;

pub use discrepancy::{
    centered_l2, centered_l2_squared, l2_star, l2_star_squared, mixture_l2, mixture_l2_squared,
    wrap_around_l2, wrap_around_l2_squared,
};
pub use star_discrepancy::{STAR_DISCREPANCY_MAX_POINTS, star_discrepancy};
