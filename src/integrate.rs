//! [`Integrator`]: the front door that drives sampler, estimator and accumulator.
//!
//! A run's sample indices are laid out by a [`Plan`](plan::Plan): replicate by replicate, cut
//! into fixed chunks of 16384 points that the crate's executor evaluates on any number of
//! threads and folds in chunk order, so the result is bit-identical for every thread count,
//! and for any split into parts ([`PartialRun`]). Runs to a tolerance ([`staged`]) repeat
//! such runs over growing index ranges, judged by the engine's stopping rule.
//!
//! The engine runs every estimator as a vector of outputs (`engine::RunEstimator`): a
//! scalar [`Estimator`] is one output, with the very arithmetic it always had, and a
//! [`VectorRun`] carries `m` outputs and their tolerances through the same plan, stages and
//! checkpoints.

use crate::engine::RunConfig;

// The Integrator's API page lists the impl blocks of these modules in the order they are
// declared, so they read as a user meets them: construct, configure, run, resume.
mod construct;

mod vector;

mod pilot;

mod configure;

mod execute;

mod partial;

mod engine;
mod layout;
#[cfg(feature = "serde")]
mod partial_format;
mod plan;
mod stages;

pub use crate::non_finite::NonFinitePolicy;
pub use engine::Integration;
pub use partial::PartialRun;
pub use vector::VectorRun;

/// Points per unit of work handed to a thread (and per partial accumulator).
const CHUNK: u64 = 16 * 1024;
/// Points per replicate when neither the caller nor the sampler's pass size says otherwise.
const DEFAULT_SAMPLES: u64 = 1 << 16;

/// Integrates with a given estimator, sampler, budget, seed and thread count.
///
/// `samples` is the number of points per replicate and `replicates` the number of
/// independent replicates (passes of the sampler with independent randomization). For
/// independent points the standard error comes from the per-sample variance; for stratified
/// and quasi-random points it comes from the spread of replicate means (Student-t with `R - 1`
/// degrees of freedom), and with a single replicate no standard error is reported.
///
/// Generation and evaluation are fused: each worker thread fills a block of 1024 points (8 KiB
/// per dimension, sized to stay in L1/L2 cache) with the sampler's batch
/// [`fill`](crate::Sampler::fill) and hands it straight to the estimator's
/// [`contributions`](crate::Estimator::contributions), reusing the same block and value buffers for
/// the whole run; no buffer of all the points is ever built, so memory traffic does not grow
/// with the number of samples. A batch integrand ([`over_box_batch`](Integrator::over_box_batch))
/// sees those blocks directly.
///
/// With a [`tolerance`](Integrator::tolerance), independent points use a two-stage rule: a pilot of
/// [`samples`](Integrator::samples) points (default 4096) gives the estimate if its interval meets
/// the tolerance; else it estimates the standard deviation `s`, and a fresh main stage of
/// `(1.96 * 1.1 * s / target)^2` points (at least the pilot's), independent of the pilot, gives the
/// estimate and its CLT interval (the factor 1.1 inflates the variance against an unlucky pilot; should the
/// main stage still miss, it is extended by the same rule). The interval assumes the CLT holds at
/// that size, which needs `n` well above the square of the integrand's skewness: sharply peaked or
/// heavy-tailed integrands need a tighter tolerance, or importance sampling. Randomized QMC and
/// stratified points keep `R` replicates (default 8) and double the points per replicate, starting
/// from `samples` (default: the pass size, or 1024), until the Student-t interval over the
/// replicates, with its standard error inflated by 1.2 against optional stopping, meets the
/// tolerance; each stage adds only the new points.
///
/// ```
/// use mcint::{Integrator, pdf::UniformBox, sampler::Jittered};
/// let estimate = Integrator::over_box(|x: &[f64]| x[0] * x[1], UniformBox::unit(2).unwrap())
///     .sampler(Jittered::new(2, 32, 0).unwrap())
///     .samples(1024)
///     .replicates(8)
///     .seed(7)
///     .threads(2)
///     .run()
///     .unwrap();
/// assert!((estimate.mean - 0.25).abs() < 5.0 * estimate.std_error.unwrap());
/// ```
pub struct Integrator<E> {
    estimator: E,
    config: RunConfig,
}
