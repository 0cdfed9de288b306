//! [`RunConfig`]: the settings every runner shares, and the checks of a run's sampler.

use std::ops::Deref;

use std::sync::Arc;
use std::time::{Duration, Instant};

use super::{CancelToken, Executor, Limits, RunScope};
use crate::error::{Error, Result};
use crate::non_finite::NonFinitePolicy;
use crate::sampler::{Independent, PassKind, Sampler};
use crate::stats::Tolerance;

/// What every runner is told the same way: where points come from (and with which seed),
/// on how many threads, how many points, until when, and what to do with non-finite values.
/// Each runner keeps one and exposes the setters of `run_settings!`.
#[derive(Default)]
pub(crate) struct RunConfig {
    sampler: Option<Box<dyn Sampler>>,
    seed: Option<u64>,
    pub(crate) threads: Option<usize>,
    /// Points per replicate (or per iteration, for iterative methods).
    pub(crate) samples: Option<u64>,
    /// Independent replicates (or passes).
    pub(crate) replicates: Option<u64>,
    pub(crate) tolerance: Option<Tolerance>,
    pub(crate) non_finite: NonFinitePolicy,
    /// A name for the integrand, checked when a checkpoint is resumed.
    pub(crate) label: Option<String>,
    /// The longest the run may take (checked before every chunk of work).
    pub(crate) time_limit: Option<Duration>,
    /// The instant the run must stop by, whatever its time limit.
    pub(crate) deadline: Option<Instant>,
    pub(crate) cancel: Option<CancelToken>,
    /// Told `(evaluations done, evaluations planned or 0 if unknown)` as the run goes.
    pub(crate) progress: Option<Progress>,
    /// The MPI ranks the run's work is spread over.
    #[cfg(feature = "mpi")]
    pub(crate) cluster: Option<super::Cluster>,
}

/// A progress callback: `(evaluations done, evaluations planned, or 0 when unknown)`.
pub(crate) type Progress = Arc<dyn Fn(u64, u64) + Send + Sync>;

/// Replicates of a fixed-budget randomized QMC run, and of MISER's runs, when the caller
/// gives none.
pub(crate) const DEFAULT_REPLICATES: u64 = 16;

/// Replicates the Integrator's run to a tolerance starts with when the caller gives none:
/// fewer, larger replicates reach a tolerance with fewer points (the spread of a scrambled
/// net's mean falls faster than `1/sqrt(n)`), and the run adds replicates when that is cheaper
/// than doubling. scipy's `qmc_quad` defaults to 8 as well.
pub(crate) const TOLERANCE_REPLICATES: u64 = 8;

/// The most evaluations a run may plan without a time limit: beyond it, a run would take
/// days, and one that does so by mistake should say so up front.
pub(crate) const MAX_UNTIMED_EVALUATIONS: u64 = 1 << 52;

impl RunConfig {
    /// Uses `sampler`, reseeded with the seed set so far, if any.
    pub(crate) fn set_sampler(&mut self, mut sampler: Box<dyn Sampler>) {
        if let Some(seed) = self.seed {
            sampler.reseed(seed);
        }
        self.sampler = Some(sampler);
    }

    /// Sets the seed, and reseeds the sampler given so far, if any.
    pub(crate) fn set_seed(&mut self, seed: u64) {
        self.seed = Some(seed);
        if let Some(sampler) = self.sampler.as_mut() {
            sampler.reseed(seed);
        }
    }

    /// The seed set, if any.
    pub(crate) fn seed(&self) -> Option<u64> {
        self.seed
    }

    /// The executor of the thread setting (spread over the cluster, if one is set), and the
    /// run's [`RunScope`]: a runner holds it until its run ends.
    pub(crate) fn executor(&self) -> Result<(Executor, RunScope)> {
        let executor = Executor::new(self.threads)?;
        #[cfg(feature = "mpi")]
        let executor = executor.spread_over(self.cluster);
        Ok((executor, RunScope::enter()))
    }

    /// The limits of a run that starts now: the shorter of the time limit and the
    /// tolerance's, and the cancellation token.
    pub(crate) fn limits(&self) -> Limits {
        self.limits_with(None)
    }

    /// [`limits`](Self::limits), with another time limit that applies too (the tolerances
    /// of a vector run's outputs and derived quantities).
    pub(crate) fn limits_with(&self, time: Option<Duration>) -> Limits {
        let shortest = |a: Option<Duration>, b: Option<Duration>| match (a, b) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        let tolerance = self.tolerance.as_ref().and_then(|t| t.time());
        Limits::new(
            shortest(shortest(self.time_limit, tolerance), time),
            self.deadline,
            self.cancel.clone(),
        )
    }

    /// Refuses a plan of more than [`MAX_UNTIMED_EVALUATIONS`] evaluations unless a time
    /// limit bounds the run; `what` names the setting that plans them.
    pub(crate) fn check_budget(&self, what: &'static str, evaluations: u64) -> Result<()> {
        let timed = self.time_limit.is_some()
            || self.deadline.is_some()
            || self.tolerance.as_ref().is_some_and(|t| t.time().is_some());
        if evaluations <= MAX_UNTIMED_EVALUATIONS || timed {
            return Ok(());
        }
        // Products of settings saturate: u64::MAX stands for any count past it.
        let planned = if evaluations == u64::MAX {
            "2^64 or more evaluations".to_string()
        } else {
            format!("{evaluations} evaluations")
        };
        Err(Error::invalid(
            what,
            planned,
            format!(
                "at most 2^52 = {MAX_UNTIMED_EVALUATIONS} evaluations without a time limit (a \
                 run with one may go further on purpose)"
            ),
        ))
    }

    /// Tells the progress callback, if any.
    pub(crate) fn report(&self, done: u64, planned: u64) {
        if let Some(progress) = &self.progress {
            progress(done, planned);
        }
    }

    /// The run's sampler, checked to have `dims` dimensions (`what` names them in the
    /// error): the one given, or independent points with the seed (0 if none was set).
    pub(crate) fn sampler(&self, dims: usize, what: &'static str) -> Result<RunSampler<'_>> {
        let sampler = match &self.sampler {
            Some(s) => RunSampler::Given(s.as_ref()),
            None => RunSampler::Default(Independent::new(dims, self.seed.unwrap_or(0))?),
        };
        if sampler.dims() != dims {
            return Err(Error::DimensionMismatch {
                what,
                expected: dims,
                found: sampler.dims(),
            });
        }
        Ok(sampler)
    }
}

/// A run's sampler: the caller's, or the default one built for the run.
pub(crate) enum RunSampler<'a> {
    Given(&'a (dyn Sampler + 'static)),
    Default(Independent),
}

impl Deref for RunSampler<'_> {
    type Target = dyn Sampler;

    fn deref(&self) -> &(dyn Sampler + 'static) {
        match self {
            RunSampler::Given(s) => *s,
            RunSampler::Default(s) => s,
        }
    }
}

/// Refuses an unrandomized sampler for `method`, which needs fresh randomness (`purpose`
/// says for what).
pub(crate) fn require_randomized(sampler: &dyn Sampler, purpose: &str) -> Result<()> {
    if sampler.is_randomized() {
        return Ok(());
    }
    Err(Error::invalid(
        "sampler",
        sampler.name(),
        format!("a randomized sampler ({purpose}; choose a scramble)"),
    ))
}

/// Refuses a sampler with fixed passes, whose single points are not uniform on their own,
/// for `method`; independent points and extensible (randomized) sequences are accepted.
pub(crate) fn require_uniform_points(sampler: &dyn Sampler, method: &str) -> Result<()> {
    if let PassKind::Fixed { size } = sampler.passes() {
        return Err(Error::invalid(
            "sampler",
            format!("{} (fixed passes of {size} points)", sampler.name()),
            format!(
                "a sampler with independent or extensible passes for {method} (a single point \
                 of a fixed pass is not uniform on its own)"
            ),
        ));
    }
    Ok(())
}
