//! # mcint: Monte Carlo integration with honest error bars
//!
//! The crate follows the Monte Carlo appendix it was built from, W. Jarosz, "Efficient Monte
//! Carlo Methods for Light Transport in Scattering Media", PhD dissertation, UC San Diego,
//! 2008, Appendix A "Monte Carlo Integration" (equation numbers A.x, here and throughout the
//! documentation, are that appendix's), in three layers, with one direction of data:
//!
//! ```text
//! Sampler --u in [0,1)^k--> Pdf (warp) --x, pdf(x)--> Estimator --Y_i--> Accumulator --> Estimate
//! ```
//!
//! * [`sampler`]: points in the unit cube, each a pure function of `(seed, pass, index, dim)`,
//!   with random access and structure-of-arrays batch fills into [`Points`].
//! * [`pdf`]: warps from canonical points to a domain with their densities.
//! * [`estimator`]: one contribution `Y_i` per point (`f/pdf`, A.19), or `m` of them for an
//!   integrand with several outputs ([`estimator::VectorEstimator`]).
//! * [`measure`]: Gaussian, lognormal and Brownian-motion laws and unbounded Lebesgue
//!   measure, seen from the unit cube, for expectations `E[f(X)]`.
//! * [`stats`]: Welford/Chan accumulators, [`Estimate`]s with Student-t intervals,
//!   [`VectorEstimate`]s with the covariance of several outputs, and derived quantities
//!   (ratios, smooth functions) with delta-method errors.
//! * [`Integrator`]: the front door; runs blocks on threads, with results that do not depend
//!   on the thread count, and error bars from independent replicates wherever the points are
//!   not independent.
//! * [`adaptive`]: VEGAS/VEGAS+, MISER, two-stage stratified sampling, and `SobolG` (QMCPy's
//!   `CubQMCSobolG` rule: one Sobol' sequence, a bound from its Walsh coefficients).
//!
//! Every runner sits on one crate-private engine: an executor that cuts a run into fixed
//! chunks, evaluates them on a rayon pool and folds their results in chunk order (so results
//! are bit-identical for any thread count, and a panic becomes
//! [`Error::IntegrandPanicked`]); one run configuration whose setters (`sampler`, `seed`,
//! `threads`, `tolerance`, `time_limit`, `non_finite`, ...) every builder shares; and one
//! stage driver: a runner describes its stages (what the next costs, how to run it, its
//! estimate), and the driver reads the limits before each stage, applies the non-finite
//! policy, judges a run to a [`Tolerance`] with one judge, and records how the run ended, the
//! same way for every method. Every runner implements the public [`Run`] trait, so a program
//! can hold a `Box<dyn Run>` and choose its method at run time.
//! With the `mpi` feature, a `Cluster` spreads any runner's chunks over MPI ranks: every rank
//! gathers every chunk's result and folds them in the same order, so every rank gets the
//! one-process result, bit for bit.
//! * [`testfns`]: the Genz families and other integrands with known integrals.
//! * [`vector_math`]: `exp` and `cos` over slices, vectorized at run time, for batch
//!   integrands.
//! * [`guide`]: how to use all of it, chapter by chapter (choosing a point set, reading an
//!   error bar, runs, vector outputs, measures, multilevel Monte Carlo, MPI, the programs).
//!
//! Cargo features, all off by default: `serde` (serialization of accumulators, estimates and
//! [`PartialRun`] checkpoints) and `mpi` (runs spread over MPI ranks with the bits of one
//! process; needs an MPI library and libclang, and implies `serde`).
//!
//! ```
//! use mcint::{Integrator, pdf::UniformBox, sampler::LatinHypercube};
//! // The integral of x*y*z over the unit cube is 1/8.
//! let estimate = Integrator::over_box(|x: &[f64]| x[0] * x[1] * x[2], UniformBox::unit(3)?)
//!     .sampler(LatinHypercube::new(3, 4096, 0)?)
//!     .samples(4096)
//!     .replicates(16)
//!     .seed(42)
//!     .run()?;
//! let (lo, hi) = estimate.confidence_interval(0.999)?.expect("16 replicates give an interval");
//! assert!(lo < 0.125 && 0.125 < hi);
//! # Ok::<(), mcint::Error>(())
//! ```

#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod adaptive;
mod engine;
mod error;
pub mod estimator;
mod float;
pub mod guide;
mod hash;
mod integrate;
pub mod measure;
mod method;
pub mod multilevel;
mod non_finite;
mod panics;
pub mod pdf;
mod points;
pub mod points_f32;
mod quadrature;
pub mod quality;
mod run;
pub mod sampler;
pub mod sensitivity;
mod simd;
mod special;
pub mod stats;
mod stop_reason;
pub mod testfns;
mod threads;
mod uniformity;
pub mod vector_math;

pub use engine::CancelToken;
#[cfg(feature = "mpi")]
pub use engine::Cluster;
pub use error::{Error, MAX_BUFFER_BYTES, Result};
pub use estimator::Estimator;
/// The vector types of the geometric warps and integrands (`DVec2`, `DVec3`, ...), at the
/// version mcint uses.
pub use glam;
pub use integrate::{Integration, Integrator, PartialRun, VectorRun};
pub use method::Method;
/// The MPI bindings (rsmpi) the `mpi` feature is built on, for `mpi::initialize` and anything
/// else a distributed program needs, at the version mcint uses.
#[cfg(feature = "mpi")]
pub use mpi;
pub use non_finite::NonFinitePolicy;
pub use pdf::Pdf;
pub use points::{PointBlock, Points};
pub use points_f32::PointsF32;
pub use run::Run;
pub use sampler::{Sampler, SamplerKind, Scramble};
pub use stats::{Accumulator, Estimate, StopReason, Tolerance, VectorEstimate};

/// The README's Rust examples, compiled and run as doctests so they cannot go stale.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
