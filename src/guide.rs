//! The guide: how to use mcint, chapter by chapter, with examples that compile and run (every
//! Rust block here is a doctest). The README gives one example per capability; the API docs
//! give every item; these chapters explain the choices in between.
//!
//! 1. [`point_sets`]: which sampler for which integrand, the convergence rates measured, the
//!    scipy-style point sets, and the measures of a point set's quality.
//! 2. [`error_bars`]: reading an error bar, runs to a tolerance, what the warnings mean, and
//!    where the source text (Jarosz's Appendix A) is wrong.
//! 3. [`runs`]: how a run is executed: chunks, threads, limits, progress, checkpoints.
//! 4. [`vector_outputs`]: several outputs over the same points, their covariance, ratios.
//! 5. [`measures`]: expectations under Gaussian, lognormal and Brownian-motion laws, option
//!    prices, control variates over a measure.
//! 6. [`multilevel`]: SDE expectations by multilevel Monte Carlo and multilevel QMC.
//! 7. [`mpi`]: runs spread over MPI ranks with the bits of one process.
//! 8. [`programs`]: the command-line programs (`integrate`, `points`, `convergence`,
//!    `asian_option`, `sensitivity`, `mlmc`, ...).
//!
//! Measured tables (speed against peers, scaling) are in `docs/benchmarks.md` and
//! `docs/measurements.md` in the repository, with their dates and machines.
//!
//! ```
//! // The guide is documentation only; this crate-level example is what each chapter builds on.
//! use mcint::{Integrator, pdf::UniformBox};
//! let e = Integrator::over_box(|x: &[f64]| x[0] * x[1], UniformBox::unit(2)?).seed(1).run()?;
//! assert!((e.mean - 0.25).abs() < 5.0 * e.std_error.unwrap());
//! # Ok::<(), mcint::Error>(())
//! ```

#[doc = include_str!("guide/point_sets.md")]
pub mod point_sets {}

#[doc = include_str!("guide/error_bars.md")]
pub mod error_bars {}

#[doc = include_str!("guide/runs.md")]
pub mod runs {}

#[doc = include_str!("guide/vector_outputs.md")]
pub mod vector_outputs {}

#[doc = include_str!("guide/measures.md")]
pub mod measures {}

#[doc = include_str!("guide/multilevel.md")]
pub mod multilevel {}

#[doc = include_str!("guide/mpi.md")]
pub mod mpi {}

#[doc = include_str!("guide/programs.md")]
pub mod programs {}
