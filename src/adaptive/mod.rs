//! Adaptive integrators: methods that learn where the integrand matters while they sample
//! (Jarosz's A.3.4), with the caveats of A.3.5 (adaptive reuse of samples can bias an
//! estimate unless, as here, every estimate comes from samples drawn after the decisions that
//! shaped it).
//!
//! [`SobolG`] adapts its number of points only: it doubles one randomized Sobol' sequence
//! until a bound read from the integrand's Walsh coefficients meets the tolerance. Every
//! other method takes its uniform points from any [`Sampler`](crate::sampler::Sampler)
//! (independent points by default). Every method runs on all threads with results that do
//! not depend on the thread count, stops at a [`Tolerance`](crate::stats::Tolerance) or a
//! fixed budget, and returns the crate's [`Estimate`](crate::stats::Estimate).

mod batches;
mod cell;
mod miser;
mod scalar_batch;
mod sobol_g;
mod two_stage;
mod vegas;
mod vegas_grid;
mod walsh;

pub use miser::Miser;
pub use scalar_batch::ScalarBatch;
pub use sobol_g::SobolG;
pub use two_stage::{TwoStage, strata_per_axis_for};
pub use vegas::{Vegas, VegasBatch, VegasOutputs};
pub use vegas_grid::VegasGrid;
