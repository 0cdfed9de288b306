//! Measures of point-set quality and of convergence: how a user chooses a sampler by measuring
//! it (the seed's discussion of discrepancy, blue-noise spectra and convergence rates).
//!
//! Every measure takes points as rows of a slice of `[f64]` points or a
//! [`Points`](crate::Points) block, works in `[0,1)^d`, and returns plain numbers, so the
//! example binaries can print and plot them.

mod convergence;

pub use convergence::{Convergence, ConvergencePoint, ConvergenceStudy};
