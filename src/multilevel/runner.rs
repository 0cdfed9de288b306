//! [`Multilevel`]: Giles' adaptive multilevel Monte Carlo (and multilevel QMC) on the engine.

use super::Level;
use super::checkpoint::MultilevelCheckpoint;
use super::estimate::{LevelSummary, MultilevelEstimate, level_warnings};
use super::fit::log_slope;
use super::sums::{Extension, LevelJob, LevelSums, chunk_size, run_job};
use crate::engine::{Executor, Limits, RunConfig, run_settings};
use crate::error::{Error, Result};
use crate::hash::hash_words;
use crate::sampler::{Independent, Sampler, Scramble, Sobol};
use crate::stats::{Accumulator, StopReason, Warning};

/// Share of the squared target left to the bias (Giles' `theta`): the sampling variance must
/// fall below `(1 - theta) eps^2` and the bias below `sqrt(theta) eps`.
const THETA: f64 = 0.5;
/// Samples per level a Monte Carlo run starts with (Giles' `N0`).
const INITIAL_SAMPLES: u64 = 1000;
/// Samples a level added by the Monte Carlo algorithm takes at least.
const NEW_LEVEL_SAMPLES: u64 = 16;
/// Points per randomization a multilevel QMC level starts with.
const INITIAL_QMC_POINTS: u64 = 8;
/// Randomizations per level of multilevel QMC (Giles and Waterhouse 2009 used 32).
const QMC_REPLICATES: u64 = 32;
/// Points on the cube's diagonal at which a checkpoint's fingerprint samples the model.
const DIAGONAL_PROBES: usize = 64;
/// The default deepest level.
const MAX_LEVEL: usize = 20;
/// The default cost limit.
const MAX_COST: f64 = 1e12;
/// Giles' consistency check (a gap over three of its standard errors) at which a run adds no
/// more levels: twice his warning threshold, six standard errors, which a rightly coupled
/// model essentially never reaches. A coupling error keeps every correction from shrinking,
/// so without this the run would add levels, each twice as costly, to the deepest allowed.
const STOP_CONSISTENCY: f64 = 2.0;
/// Samples a level needs before its consistency check can stop a run: the check divides by
/// sample standard deviations, which a few samples of a rare-jump correction understate.
const CONSISTENCY_SAMPLES: u64 = 1000;
/// Salt of the per-level seeds.
const LEVEL_SALT: u64 = 0x6d6c_6d63;
/// The stride between the passes of a Sobol' sampler (its pass length).
const SOBOL_PASS: u64 = 1 << 32;
/// The most coordinates a Sobol' point has.
const SOBOL_DIMS: usize = 21201;
/// The most coordinates a Monte Carlo sample may take.
const MC_DIMS: usize = 1 << 24;

/// Giles' adaptive multilevel Monte Carlo (Operations Research 56(3), 2008; Acta Numerica
/// 24, 2015) to a root-mean-square error target `eps`: it estimates `V_l` and `C_l` per level,
/// takes the optimal `N_l = sqrt(V_l / C_l) sum_k sqrt(V_k C_k) / (eps^2 / 2)`, adds levels
/// while the bias extrapolated from the decay of `E[P_l - P_{l-1}]` is above `eps / sqrt(2)`,
/// and stops when both the sampling error and the bias are within their share. With
/// [`qmc`](Self::qmc), multilevel QMC (Giles and Waterhouse 2009): each level takes `R`
/// Owen-scrambled Sobol' sequences, the variance of its mean comes from their spread, and the
/// level whose points buy the most variance per cost is doubled until the variance is within
/// `eps^2 / 2`.
///
/// Samples are drawn by the engine's executor in chunks fixed by the level alone, so results
/// are the same bits for any thread count (and over MPI ranks with the `mpi` feature); time
/// limits and cancellation stop between chunks with the estimate so far.
///
/// ```
/// use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
/// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
/// let call = SdeLevels::new(gbm, Scheme::Milstein, Payoff::european_call(100.0).unwrap(), 1.0)
///     .unwrap()
///     .discount((-0.05f64).exp())
///     .unwrap();
/// let run = Multilevel::new(call).rmse(0.02).seed(1).run().unwrap();
/// assert!((run.estimate - 10.450583572185565).abs() < 0.08, "{run}");
/// assert!(run.beta > 1.5); // Milstein: V_l falls like h_l^2
/// ```
pub struct Multilevel<L> {
    model: L,
    config: RunConfig,
    target: Option<f64>,
    qmc: bool,
    replicates: Option<u64>,
    initial: Option<u64>,
    min_level: usize,
    max_level: usize,
    max_cost: f64,
}

/// The state of one level: a sum per replicate, and the samples each replicate holds.
#[derive(Clone)]
struct LevelState {
    sums: Vec<LevelSums>,
    per_replicate: u64,
}

impl<L: Level> Multilevel<L> {
    /// A run of `model`'s levels; set the target with [`rmse`](Self::rmse).
    ///
    /// ```
    /// use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// let err = Multilevel::new(levels).run().unwrap_err();
    /// assert!(err.to_string().contains("rmse"), "{err}");
    /// ```
    pub fn new(model: L) -> Multilevel<L> {
        Multilevel {
            model,
            config: RunConfig::default(),
            target: None,
            qmc: false,
            replicates: None,
            initial: None,
            min_level: 2,
            max_level: MAX_LEVEL,
            max_cost: MAX_COST,
        }
    }

    /// The root-mean-square error target `eps` (finite, above 0).
    ///
    /// ```
    /// # use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// # let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// # let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// let err = Multilevel::new(levels).rmse(-1.0).run().unwrap_err();
    /// assert!(err.to_string().contains("above 0"), "{err}");
    /// ```
    pub fn rmse(mut self, eps: f64) -> Self {
        self.target = Some(eps);
        self
    }

    /// Multilevel QMC (default: off, independent samples): each level takes
    /// [`replicates`](Self::replicates) Owen-scrambled Sobol' sequences.
    ///
    /// ```
    /// # use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// # let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// # let levels = SdeLevels::new(gbm, Scheme::Milstein, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// let run = Multilevel::new(levels).rmse(0.05).qmc(true).seed(2).run().unwrap();
    /// assert_eq!(run.replicates, 32);
    /// ```
    pub fn qmc(mut self, on: bool) -> Self {
        self.qmc = on;
        self
    }

    /// Independent randomizations per level of multilevel QMC (at least 2; default 32).
    ///
    /// ```
    /// # use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// # let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// # let levels = SdeLevels::new(gbm, Scheme::Milstein, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// let err = Multilevel::new(levels).rmse(0.05).qmc(true).replicates(1).run().unwrap_err();
    /// assert!(err.to_string().contains("at least 2"), "{err}");
    /// ```
    pub fn replicates(mut self, replicates: u64) -> Self {
        self.replicates = Some(replicates);
        self
    }

    /// Samples the first levels (`0..=min_level`) start with, Giles' `N0` (per randomization
    /// under QMC, where every new level starts with it too; at least 2, and a power of 2
    /// under QMC; default 1000 for Monte Carlo, 8 for QMC). Levels the Monte Carlo algorithm
    /// adds later start with their optimal number, at least 16.
    ///
    /// ```
    /// # use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// # let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// # let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// let run = Multilevel::new(levels).rmse(0.2).initial_samples(200).seed(1).run().unwrap();
    /// assert!(run.levels[..3].iter().all(|l| l.samples >= 200));
    /// ```
    pub fn initial_samples(mut self, samples: u64) -> Self {
        self.initial = Some(samples);
        self
    }

    /// The levels every run takes, `0..=level` (at least 1, so that the rates can be fitted;
    /// default 2, as Giles' `Lmin`).
    ///
    /// ```
    /// # use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// # let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// # let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// let run = Multilevel::new(levels).rmse(1.0).min_level(4).seed(1).run().unwrap();
    /// assert!(run.levels.len() >= 5);
    /// ```
    pub fn min_level(mut self, level: usize) -> Self {
        self.min_level = level;
        self
    }

    /// The deepest level allowed (default 20; at most 60): a run that needs a deeper one stops
    /// with [`StopReason::MaxLevel`] once its sampling error meets its share.
    ///
    /// ```
    /// use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// use mcint::stats::StopReason;
    /// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// let run = Multilevel::new(levels).rmse(0.01).min_level(1).max_level(1).seed(1).run().unwrap();
    /// assert_eq!((run.stop, run.converged), (StopReason::MaxLevel, false));
    /// ```
    pub fn max_level(mut self, level: usize) -> Self {
        self.max_level = level;
        self
    }

    /// The most cost (in the model's unit) the run may spend (default 1e12): a run that would
    /// pass it stops with [`StopReason::MaxEvaluations`] and the estimate so far.
    ///
    /// ```
    /// # use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// # use mcint::stats::StopReason;
    /// # let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// # let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// let run = Multilevel::new(levels).rmse(1e-4).max_cost(1e6).seed(1).run().unwrap();
    /// assert_eq!(run.stop, StopReason::MaxEvaluations);
    /// assert!(run.cost <= 1e6 && !run.converged);
    /// ```
    pub fn max_cost(mut self, cost: f64) -> Self {
        self.max_cost = cost;
        self
    }

    run_settings! {
        setup: "use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};\n\
                const DIMS: usize = 1;\n\
                let runner = || Multilevel::new(SdeLevels::new(Sde::gbm(100.0, 0.05, 0.2).unwrap(), \
                Scheme::Milstein, Payoff::european_call(100.0).unwrap(), 1.0).unwrap()).rmse(0.2);",
        run: ".run().unwrap()";
        seed, threads, cancel_token, cluster
    }

    /// The longest the run may take, checked before every chunk of work: the run returns with
    /// the estimate of the samples so far, [`StopReason::TimeLimit`] and not converged (or
    /// [`Error::Interrupted`] before any sample of level 0).
    ///
    /// ```
    /// # use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// # let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// # let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// use std::time::Duration;
    /// let run = Multilevel::new(levels).rmse(0.1).time_limit(Duration::from_secs(3600)).run().unwrap();
    /// assert!(run.converged); // well within it
    /// ```
    pub fn time_limit(mut self, limit: std::time::Duration) -> Self {
        self.config.time_limit = Some(limit);
        self
    }

    /// The instant by which the run must stop, as for a [time limit](Self::time_limit) (the
    /// earlier of the two applies).
    ///
    /// ```
    /// # use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// # let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// # let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// let past = Multilevel::new(levels).rmse(0.1).deadline(std::time::Instant::now()).run();
    /// assert!(matches!(past, Err(mcint::Error::Interrupted { .. })));
    /// ```
    pub fn deadline(mut self, deadline: std::time::Instant) -> Self {
        self.config.deadline = Some(deadline);
        self
    }

    /// A callback told `(cost spent, 0)` after each batch of samples of a level, on the thread
    /// that called `run` (the cost is the model's unit, rounded down).
    ///
    /// ```
    /// # use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// # let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// # let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// use std::sync::{Arc, Mutex};
    /// let seen = Arc::new(Mutex::new(Vec::new()));
    /// let log = Arc::clone(&seen);
    /// let run = Multilevel::new(levels).rmse(0.1).progress(move |done, _| log.lock().unwrap().push(done));
    /// let run = run.run().unwrap();
    /// assert_eq!(*seen.lock().unwrap().last().unwrap(), run.cost as u64);
    /// ```
    pub fn progress(mut self, progress: impl Fn(u64, u64) + Send + Sync + 'static) -> Self {
        self.config.progress = Some(std::sync::Arc::new(progress));
        self
    }

    /// The checked settings: (target, replicates, initial samples per replicate).
    fn checked(&self, survey: bool) -> Result<(f64, u64, u64)> {
        let target = if survey {
            f64::NAN
        } else {
            match self.target {
                None => {
                    return Err(Error::invalid(
                        "rmse",
                        "unset",
                        "a target root-mean-square error: set it with .rmse(eps)",
                    ));
                }
                Some(t) if t.is_finite() && t > 0.0 => t,
                Some(t) => return Err(Error::invalid("rmse", t, "a finite target above 0")),
            }
        };
        let replicates = match (self.qmc, self.replicates) {
            (false, _) => 1,
            (true, None) => QMC_REPLICATES,
            (true, Some(r)) if (2..=1 << 16).contains(&r) => r,
            (true, Some(r)) => {
                return Err(Error::invalid(
                    "replicates",
                    r,
                    "at least 2 and at most 65536",
                ));
            }
        };
        let initial = match self.initial {
            None if self.qmc => INITIAL_QMC_POINTS,
            None => INITIAL_SAMPLES,
            Some(n) if !(2..=1 << 31).contains(&n) => {
                return Err(Error::invalid("initial_samples", n, "2 to 2^31"));
            }
            Some(n) if self.qmc && !n.is_power_of_two() => {
                return Err(Error::invalid(
                    "initial_samples",
                    n,
                    "a power of 2 for multilevel QMC (the nets of Sobol' points)",
                ));
            }
            Some(n) => n,
        };
        if self.min_level == 0 || self.min_level > self.max_level || self.max_level > 60 {
            return Err(Error::invalid(
                "min_level and max_level",
                format!("{} and {}", self.min_level, self.max_level),
                "1 <= min_level <= max_level <= 60",
            ));
        }
        if !(self.max_cost.is_finite() && self.max_cost > 0.0) {
            return Err(Error::invalid(
                "max_cost",
                self.max_cost,
                "a finite cost above 0",
            ));
        }
        if !(2..=1 << 16).contains(&self.model.refinement()) {
            return Err(Error::invalid(
                "refinement",
                self.model.refinement(),
                "2 to 65536 (the model's refinement factor)",
            ));
        }
        Ok((target, replicates, initial))
    }

    /// The sampler of `level`, or `None` when the level has more coordinates than the
    /// sampler can give.
    fn sampler(&self, level: usize, dims: usize) -> Result<Option<Box<dyn Sampler>>> {
        let seed = hash_words(self.config.seed().unwrap_or(0), &[level as u64, LEVEL_SALT]);
        if dims == 0 {
            return Err(Error::invalid(
                "level dims",
                0,
                "at least 1 coordinate per sample",
            ));
        }
        Ok(if self.qmc {
            (dims <= SOBOL_DIMS)
                .then(|| Sobol::new(dims, Scramble::Owen, seed))
                .transpose()?
                .map(|s| Box::new(s) as Box<dyn Sampler>)
        } else {
            (dims <= MC_DIMS)
                .then(|| Independent::new(dims, seed))
                .transpose()?
                .map(|s| Box::new(s) as Box<dyn Sampler>)
        })
    }

    /// The cost of one sample of `level`, checked.
    fn level_cost(&self, level: usize) -> Result<f64> {
        let cost = self.model.cost(level);
        if cost.is_finite() && cost > 0.0 {
            Ok(cost)
        } else {
            Err(Error::invalid(
                "level cost",
                format!("{cost} at level {level}"),
                "a finite cost above 0",
            ))
        }
    }

    /// Adds `count` samples per replicate to `state` (level `level`), continuing `resume`
    /// (an extension of it a limit cut short) if given. Returns the samples (over every
    /// replicate) newly drawn, and, when a limit cuts it short, the extension under way with
    /// the limit; `state` then keeps its samples so far.
    fn extend(
        &self,
        executor: &Executor,
        limits: &Limits,
        level: usize,
        state: &mut LevelState,
        count: u64,
        resume: Option<Extension>,
    ) -> Result<(u64, Option<(Extension, StopReason)>)> {
        let dims = self.model.dims(level);
        let Some(sampler) = self.sampler(level, dims)? else {
            return Err(Error::invalid(
                "level dims",
                dims,
                "at most the sampler's dimensions",
            ));
        };
        let job = LevelJob {
            model: &self.model,
            level,
            sampler: sampler.as_ref(),
            first: state.per_replicate,
            count,
            replicates: state.sums.len() as u64,
            stride: if self.qmc { SOBOL_PASS } else { 0 },
            chunk: chunk_size(dims, self.level_cost(level)?),
        };
        let from = resume.map(|e| (e.sums, e.chunks));
        let start = from.as_ref().map_or(0, |f| f.1);
        let (sums, done, stop) = run_job(executor, &job, limits, from).map_err(|e| match e {
            // The executor knows the chunk, not the level: name it, or a deep level's panic
            // reads as the first samples of the run.
            Error::IntegrandPanicked {
                message,
                replicate,
                first_index,
            } => Error::IntegrandPanicked {
                message: format!("{message} (in level {level})"),
                replicate,
                first_index,
            },
            other => other,
        })?;
        let added = job.samples_in(start..done);
        if let Some(reason) = stop {
            let chunks = done;
            return Ok((
                added,
                Some((
                    Extension {
                        level,
                        sums,
                        chunks,
                    },
                    reason,
                )),
            ));
        }
        for (total, new) in state.sums.iter_mut().zip(&sums) {
            total.merge(new);
        }
        state.per_replicate = state.sums[0].count();
        Ok((added, None))
    }

    /// The samples of an extension cut short, in `state` for an estimate: all of them under
    /// Monte Carlo, none under QMC (every randomization must keep the same points).
    fn absorb(&self, state: &mut LevelState, cut: &Extension) {
        if !self.qmc {
            for (total, new) in state.sums.iter_mut().zip(&cut.sums) {
                total.merge(new);
            }
            state.per_replicate = state.sums[0].count();
        }
    }

    /// Whether `level` can be sampled at all (its coordinates fit the sampler).
    fn can_sample(&self, level: usize) -> bool {
        let dims = self.model.dims(level);
        dims > 0 && dims <= self.most_dims()
    }

    /// The most coordinates a sample can take from this run's sampler.
    fn most_dims(&self) -> usize {
        if self.qmc { SOBOL_DIMS } else { MC_DIMS }
    }

    /// Why levels `0..=deepest` cannot all be sampled, if one cannot: at level 0 the model's
    /// dimensions are at fault; past it, `setting` (`name = value`) asks for too deep a level.
    fn refuse_unsampleable(&self, deepest: usize, setting: (&'static str, usize)) -> Result<()> {
        let Some(level) = (0..=deepest).find(|&level| !self.can_sample(level)) else {
            return Ok(());
        };
        let dims = self.model.dims(level);
        let allowed = format!(
            "1 to {} coordinates per sample ({})",
            self.most_dims(),
            if self.qmc {
                "Sobol' points"
            } else {
                "independent points"
            }
        );
        Err(if level == 0 {
            Error::invalid("level dims", format!("{dims} at level 0"), allowed)
        } else {
            Error::invalid(
                setting.0,
                setting.1,
                format!(
                    "levels whose samples fit the sampler (level {level} takes {dims}; {allowed})"
                ),
            )
        })
    }

    /// Runs Giles' algorithm to the target.
    ///
    /// ```
    /// use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::digital_call(100.0).unwrap(), 1.0).unwrap();
    /// let run = Multilevel::new(levels).rmse(0.01).seed(5).run().unwrap();
    /// // Undiscounted: P(S(1) > 100) = Phi(0.15) = 0.5596...
    /// assert!((run.estimate - 0.559618).abs() < 0.04, "{run}");
    /// ```
    pub fn run(&self) -> Result<MultilevelEstimate> {
        let mut state = self.checkpoint()?;
        self.run_from(&mut state)
    }

    /// The state of this run before its first sample, to run with
    /// [`run_from`](Self::run_from) (see [`MultilevelCheckpoint`]).
    ///
    /// ```
    /// # use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// # let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// # let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// let runner = Multilevel::new(levels).rmse(0.1).seed(2);
    /// let mut state = runner.checkpoint().unwrap();
    /// assert_eq!(runner.run_from(&mut state).unwrap(), runner.run().unwrap());
    /// ```
    pub fn checkpoint(&self) -> Result<MultilevelCheckpoint> {
        let (target, replicates, initial) = self.checked(false)?;
        self.refuse_unsampleable(self.min_level, ("min_level", self.min_level))?;
        let levels = vec![vec![LevelSums::default(); replicates as usize]; self.min_level + 1];
        let pending = vec![initial; levels.len()];
        let fingerprint = self.fingerprint(target, replicates, initial)?;
        Ok(MultilevelCheckpoint::new(fingerprint, levels, pending))
    }

    /// Runs from `state` (a [`checkpoint`](Self::checkpoint) of a run of the same settings,
    /// maybe saved and read back) to the target, leaving in `state` where it stopped (down to
    /// the chunk of samples a limit stopped at): a run stopped by a time limit, a cancellation
    /// or the cost limit resumes from it and ends with the bits of a run that never stopped. The cost limit,
    /// time limits and thread count may differ between calls; the seed, target, QMC settings,
    /// levels and model may not.
    ///
    /// ```
    /// # use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// # let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// # let levels = || SdeLevels::new(gbm.clone(), Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// let mut state = Multilevel::new(levels()).rmse(0.1).seed(2).checkpoint().unwrap();
    /// let err = Multilevel::new(levels()).rmse(0.1).seed(3).run_from(&mut state).unwrap_err();
    /// assert!(err.to_string().contains("fingerprint"), "{err}");
    /// ```
    pub fn run_from(&self, state: &mut MultilevelCheckpoint) -> Result<MultilevelEstimate> {
        let (target, replicates, initial) = self.checked(false)?;
        let fingerprint = self.fingerprint(target, replicates, initial)?;
        state.check(fingerprint, replicates, self.min_level + 1)?;
        let (executor, _scope) = self.config.executor()?;
        let limits = self.config.limits();
        executor.on_pool(|| self.run_on(&executor, &limits, target, replicates, initial, state))
    }

    /// What a checkpoint must share with the run that resumes it.
    fn fingerprint(&self, target: f64, replicates: u64, initial: u64) -> Result<u64> {
        let mut words = vec![
            u64::from(self.qmc),
            replicates,
            initial,
            self.min_level as u64,
            self.max_level as u64,
            target.to_bits(),
            u64::from(self.model.refinement()),
            self.model.weak_order().map_or(0, f64::to_bits),
        ];
        for level in 0..=2 {
            words.push(self.model.dims(level) as u64);
            words.push(self.level_cost(level)?.to_bits());
            words.push(self.model.fine_cost(level).to_bits());
        }
        words.extend(self.model_probe());
        Ok(hash_words(self.config.seed().unwrap_or(0), &words))
    }

    /// The model's samples of levels 0 and 1 at fixed points: what tells two models with
    /// the same levels apart (another strike, payoff, volatility or maturity). One point is
    /// not enough: a call can be out of the money there under both volatilities. So besides
    /// a point spread over the cube, the probe walks the diagonal `u = (p, ..., p)` through
    /// [`DIAGONAL_PROBES`] quantiles, from paths that fall to paths that rise, where a payoff's
    /// kink or jump moves with each parameter.
    fn model_probe(&self) -> Vec<u64> {
        let mut scratch = Vec::new();
        let mut words = Vec::new();
        for level in 0..=1 {
            let dims = self.model.dims(level);
            let spread: Vec<f64> = (0..dims)
                .map(|k| ((k as f64 + 0.5) * 0.618_033_988_749_894_9).fract())
                .collect();
            let diagonal =
                (0..DIAGONAL_PROBES).map(|i| vec![(i as f64 + 0.5) / DIAGONAL_PROBES as f64; dims]);
            for u in std::iter::once(spread).chain(diagonal) {
                // A model that panics here panics in the run too, where the executor
                // reports it.
                let probe = || self.model.sample(level, &u, &mut scratch);
                let (fine, coarse) = std::panic::catch_unwind(std::panic::AssertUnwindSafe(probe))
                    .unwrap_or((f64::NAN, f64::NAN));
                words.extend([fine.to_bits(), coarse.to_bits()]);
            }
        }
        words
    }

    fn run_on(
        &self,
        executor: &Executor,
        limits: &Limits,
        target: f64,
        replicates: u64,
        initial: u64,
        state: &mut MultilevelCheckpoint,
    ) -> Result<MultilevelEstimate> {
        let m = f64::from(self.model.refinement());
        let fresh = LevelState {
            sums: vec![LevelSums::default(); replicates as usize],
            per_replicate: 0,
        };
        let mut levels: Vec<LevelState> = state
            .levels
            .iter()
            .map(|sums| LevelState {
                sums: sums.clone(),
                per_replicate: sums[0].count(),
            })
            .collect();
        let mut pending = state.pending.clone();
        let mut spent = state.spent;
        let mut bias_stuck = state.bias_stuck;
        let mut in_flight = state.in_flight.take();
        let save = |state: &mut MultilevelCheckpoint,
                    levels: &[LevelState],
                    pending: &[u64],
                    spent: f64,
                    bias_stuck: bool,
                    in_flight: Option<Extension>| {
            state.levels = levels.iter().map(|l| l.sums.clone()).collect();
            state.pending = pending.to_vec();
            state.spent = spent;
            state.bias_stuck = bias_stuck;
            state.in_flight = in_flight;
            state.seal();
        };
        let stop = 'run: loop {
            if let Some(finished) = state.finished {
                break finished;
            }
            save(
                state,
                &levels,
                &pending,
                spent,
                bias_stuck,
                in_flight.clone(),
            );
            // What is left of this iteration (an extension under way has spent some of it).
            let mut planned = 0.0;
            for (level, &count) in pending.iter().enumerate() {
                planned += (count * replicates) as f64 * self.level_cost(level)?;
            }
            if let Some(cut) = &in_flight {
                let drawn: u64 = cut.sums.iter().map(LevelSums::count).sum();
                planned -= drawn as f64 * self.level_cost(cut.level)?;
            }
            if spent + planned > self.max_cost {
                if spent == 0.0 {
                    return Err(Error::invalid(
                        "max_cost",
                        self.max_cost,
                        format!("at least the first samples' cost, {planned:.3e}"),
                    ));
                }
                break StopReason::MaxEvaluations;
            }
            if let Some(reason) = executor.reached(limits)? {
                break reason;
            }
            for level in 0..levels.len() {
                if pending[level] == 0 {
                    continue;
                }
                let resume = in_flight.take_if(|cut| cut.level == level);
                let (added, cut) = self.extend(
                    executor,
                    limits,
                    level,
                    &mut levels[level],
                    pending[level],
                    resume,
                )?;
                spent += added as f64 * self.level_cost(level)?;
                self.config.report(spent as u64, 0);
                if let Some((cut, reason)) = cut {
                    save(
                        state,
                        &levels,
                        &pending,
                        spent,
                        bias_stuck,
                        Some(cut.clone()),
                    );
                    self.absorb(&mut levels[level], &cut);
                    break 'run reason;
                }
                pending[level] = 0;
                save(state, &levels, &pending, spent, bias_stuck, None);
            }
            let stats = Stats::of(&levels, m, self)?;
            let ended = |done: bool, bias_stuck: bool| {
                done.then_some(if bias_stuck {
                    StopReason::MaxLevel
                } else {
                    StopReason::ToleranceMet
                })
            };
            let mut finished = if self.qmc {
                self.plan_qmc(&stats, &levels, &mut pending, target, initial)
            } else {
                let done = self.plan_mc(&stats, &levels, &mut pending, target, &mut bias_stuck);
                ended(done, bias_stuck)
            };
            if finished.is_none() && pending.len() > levels.len() && coupling_error(&levels) {
                pending.truncate(levels.len());
                finished = Some(StopReason::InconsistentLevels);
            }
            if let Some(finished) = finished {
                bias_stuck = finished == StopReason::MaxLevel;
                save(state, &levels, &pending, spent, bias_stuck, None);
                state.finished = Some(finished);
                state.seal();
                break finished;
            }
            while levels.len() < pending.len() {
                levels.push(fresh.clone());
            }
        };
        if levels[0].per_replicate == 0 {
            return Err(Error::Interrupted {
                stop,
                evaluations: spent as u64,
            });
        }
        levels.retain(|l| l.per_replicate > 0);
        let stats = Stats::of(&levels, m, self)?;
        Ok(self.result(&stats, &levels, Some(target), replicates, spent, stop))
    }

    /// Giles' Monte Carlo step: the optimal `N_l`, and a new level when the samples asked for
    /// are (almost) all taken and the bias is too large. Returns whether the run is done.
    fn plan_mc(
        &self,
        stats: &Stats,
        levels: &[LevelState],
        pending: &mut Vec<u64>,
        target: f64,
        bias_stuck: &mut bool,
    ) -> bool {
        let target = target / stats.unit;
        let variance_share = (1.0 - THETA) * target * target;
        let optimal = |v: &[f64], c: &[f64]| -> Vec<f64> {
            let total: f64 = v.iter().zip(c).map(|(v, c)| (v * c).sqrt()).sum();
            v.iter()
                .zip(c)
                .map(|(v, c)| ((v / c).sqrt() * total / variance_share).ceil())
                .collect()
        };
        let n: Vec<u64> = levels.iter().map(|l| l.per_replicate).collect();
        let wanted = optimal(&stats.variance, &stats.cost);
        *pending = wanted.iter().zip(&n).map(|(&w, &n)| extra(w, n)).collect();
        let almost = pending
            .iter()
            .zip(&n)
            .all(|(&p, &n)| p as f64 <= 0.01 * n as f64);
        if almost {
            if stats.bias <= THETA.sqrt() * target {
                *bias_stuck = false;
            } else if levels.len() > self.max_level || !self.can_sample(levels.len()) {
                *bias_stuck = true;
            } else {
                let mut variance = stats.variance.clone();
                let mut cost = stats.cost.clone();
                let deepest = levels.len() - 1;
                variance.push(variance[deepest] / stats.m.powf(stats.beta));
                cost.push(self.model.cost(levels.len()));
                let wanted = optimal(&variance, &cost);
                let mut n = n;
                n.push(0);
                *pending = wanted.iter().zip(&n).map(|(&w, &n)| extra(w, n)).collect();
                // A few samples at least, for a variance to start from.
                let newest = pending.len() - 1;
                pending[newest] = pending[newest].max(NEW_LEVEL_SAMPLES);
            }
        }
        pending.iter().all(|&p| p == 0)
    }

    /// Giles and Waterhouse's QMC step: double the points of the level whose variance per
    /// cost is largest until the variance is within its share, then add a level while the
    /// bias is too large. Returns how the run ends, if it does: the target met, the deepest
    /// level reached, or a level's Sobol' sequences too short to double.
    fn plan_qmc(
        &self,
        stats: &Stats,
        levels: &[LevelState],
        pending: &mut Vec<u64>,
        target: f64,
        initial: u64,
    ) -> Option<StopReason> {
        let target = target / stats.unit;
        let variance: f64 = stats.mean_variance.iter().sum();
        if variance > (1.0 - THETA) * target * target {
            let worst = (0..levels.len())
                .max_by(|&a, &b| {
                    let gain = |l: usize| {
                        stats.mean_variance[l] / (stats.cost[l] * levels[l].per_replicate as f64)
                    };
                    gain(a).total_cmp(&gain(b))
                })
                .unwrap_or(0);
            if 2 * levels[worst].per_replicate > SOBOL_PASS {
                return Some(StopReason::SamplerExhausted);
            }
            pending[worst] = levels[worst].per_replicate;
            return None;
        }
        if stats.bias <= THETA.sqrt() * target {
            return Some(StopReason::ToleranceMet);
        }
        if levels.len() > self.max_level || !self.can_sample(levels.len()) {
            return Some(StopReason::MaxLevel);
        }
        pending.push(initial);
        None
    }

    fn result(
        &self,
        stats: &Stats,
        levels: &[LevelState],
        target: Option<f64>,
        replicates: u64,
        spent: f64,
        stop: StopReason,
    ) -> MultilevelEstimate {
        let summaries: Vec<LevelSummary> = levels
            .iter()
            .enumerate()
            .map(|(l, state)| {
                let pooled = pooled_of(state);
                LevelSummary {
                    level: l,
                    samples: pooled.count(),
                    mean: pooled.difference.mean(),
                    variance: pooled.difference.variance(),
                    std_error: stats.mean_variance[l].sqrt() * stats.unit,
                    cost: stats.cost[l],
                    fine_mean: pooled.fine.mean(),
                    fine_variance: pooled.fine.variance(),
                    kurtosis: pooled.kurtosis(),
                    consistency: consistency(levels, l),
                }
            })
            .collect();
        let estimate = summaries.iter().map(|l| l.mean).sum();
        // In the statistics' units, then scaled back (exact: a power of two).
        let unit = stats.unit;
        let std_error_in_units = stats.mean_variance.iter().sum::<f64>().sqrt();
        let deepest = summaries.len() - 1;
        let sampling_share = target.map_or(std_error_in_units * std_error_in_units, |t| {
            (1.0 - THETA) * (t / unit) * (t / unit)
        });
        let fine_cost = self.model.fine_cost(deepest);
        let standard_mc_cost = if sampling_share > 0.0 {
            pooled_of(&levels[deepest]).fine.variance_in(unit) * fine_cost / sampling_share
        } else {
            0.0
        };
        let converged = stop == StopReason::ToleranceMet;
        let mut warnings = Vec::new();
        if stop == StopReason::MaxLevel {
            warnings.push(Warning::BiasAboveTarget {
                level: deepest,
                bias: stats.bias * unit,
                target: THETA.sqrt() * target.unwrap_or(f64::NAN),
            });
        }
        let all_zero = levels
            .iter()
            .flat_map(|l| &l.sums)
            .all(|s| s.fine.all_zero() && s.difference.all_zero());
        if all_zero {
            let count = summaries.iter().map(|l| l.samples).sum();
            warnings.push(Warning::AllZero { count });
        }
        if !converged && target.is_some() && stop != StopReason::MaxLevel {
            warnings.push(Warning::ToleranceNotMet { stop });
        }
        warnings.extend(level_warnings(&summaries));
        let rmse_in_units =
            (std_error_in_units * std_error_in_units + stats.bias * stats.bias).sqrt();
        MultilevelEstimate {
            estimate,
            std_error: std_error_in_units * unit,
            bias: stats.bias * unit,
            rmse: rmse_in_units * unit,
            target,
            levels: summaries,
            alpha: stats.alpha,
            beta: stats.beta,
            gamma: stats.gamma,
            refinement: self.model.refinement(),
            cost: spent,
            standard_mc_cost,
            replicates,
            stop,
            converged,
            warnings,
        }
    }

    /// Giles' `mlmc_test` survey: `samples` samples (2 to 2^40; under QMC, at most 2^32 per
    /// randomization) of every level `0..=levels`, with the fitted rates and, per level, the
    /// means, variances, kurtosis and consistency check. The result's `target` is `None`; its
    /// standard MC cost is for the survey's own standard error.
    ///
    /// ```
    /// use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
    /// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
    /// let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
    /// let survey = Multilevel::new(levels).seed(1).survey(5, 20_000).unwrap();
    /// assert_eq!(survey.levels.len(), 6);
    /// assert!((survey.beta - 1.0).abs() < 0.3, "{survey}"); // Euler: V_l ~ h_l
    /// assert!(survey.levels.iter().skip(1).all(|l| l.consistency.unwrap() < 1.0));
    /// ```
    pub fn survey(&self, levels: usize, samples: u64) -> Result<MultilevelEstimate> {
        let (_, replicates, _) = self.checked(true)?;
        if levels == 0 || levels > self.max_level {
            return Err(Error::invalid(
                "levels",
                levels,
                format!("1 to max_level = {}", self.max_level),
            ));
        }
        if !(2..=1 << 40).contains(&samples) {
            return Err(Error::invalid("samples", samples, "2 to 2^40"));
        }
        if self.qmc && samples > SOBOL_PASS {
            // Each randomization is one pass of the sequence; past it, the next one's points.
            return Err(Error::invalid(
                "samples",
                samples,
                "2 to 2^32 with qmc (the points of one Sobol' pass per randomization)",
            ));
        }
        // Before any sampling: a level that cannot be sampled would end the survey anyway.
        self.refuse_unsampleable(levels, ("levels", levels))?;
        let (executor, _scope) = self.config.executor()?;
        let limits = self.config.limits();
        let m = f64::from(self.model.refinement());
        executor.on_pool(|| {
            let mut states = Vec::new();
            let mut spent = 0.0;
            let mut stop = StopReason::Budget;
            for level in 0..=levels {
                let mut state = LevelState {
                    sums: vec![LevelSums::default(); replicates as usize],
                    per_replicate: 0,
                };
                let (added, cut) =
                    self.extend(&executor, &limits, level, &mut state, samples, None)?;
                spent += added as f64 * self.level_cost(level)?;
                if let Some((cut, _)) = &cut {
                    self.absorb(&mut state, cut);
                }
                if state.per_replicate > 1 {
                    states.push(state);
                }
                if let Some((_, reason)) = cut {
                    stop = reason;
                    break;
                }
            }
            if states.len() < 2 {
                return Err(Error::Interrupted {
                    stop,
                    evaluations: spent as u64,
                });
            }
            let stats = Stats::of(&states, m, self)?;
            let mut survey = self.result(&stats, &states, None, replicates, spent, stop);
            survey.converged = false;
            Ok(survey)
        })
    }
}

/// Samples still to take on a level that wants `wanted` and holds `held`.
fn extra(wanted: f64, held: u64) -> u64 {
    // An infinite want (a target so far below the samples' spread that its square underflows)
    // is more than any cost limit, which then ends the run; NaN wants nothing.
    if wanted > held as f64 {
        (wanted.min(1e18) as u64).saturating_sub(held)
    } else {
        0
    }
}

/// A level's sums over every replicate.
fn pooled_of(state: &LevelState) -> LevelSums {
    let mut all = LevelSums::default();
    for s in &state.sums {
        all.merge(s);
    }
    all
}

/// Giles' consistency check of level `l >= 1`: `|E[Y_l] - E[P_l] + E[P_{l-1}]|`, where
/// `P_{l-1}` is level `l - 1`'s fine sample, over three standard errors (`None` on level 0,
/// or where the samples show no spread).
fn consistency(levels: &[LevelState], l: usize) -> Option<f64> {
    let previous = pooled_of(levels.get(l.checked_sub(1)?)?).fine;
    let pooled = pooled_of(&levels[l]);
    let gap = pooled.difference.mean() - pooled.fine.mean() + previous.mean();
    let spread = pooled.difference.std_dev() + pooled.fine.std_dev() + previous.std_dev();
    Some(gap.abs() / (3.0 * spread / (pooled.count() as f64).sqrt())).filter(|c| c.is_finite())
}

/// Whether a level with enough samples fails the consistency check by
/// [`STOP_CONSISTENCY`]: a coupling error that more levels cannot mend.
fn coupling_error(levels: &[LevelState]) -> bool {
    (1..levels.len()).any(|l| {
        let enough =
            levels[l].sums.iter().map(LevelSums::count).sum::<u64>() >= CONSISTENCY_SAMPLES;
        enough && consistency(levels, l).is_some_and(|c| c >= STOP_CONSISTENCY)
    })
}

/// What the allocation reads of the levels so far.
struct Stats {
    m: f64,
    /// The units (a power of two, 1 for samples from about 1e-145 to 1e144) of the means,
    /// variances and bias below, so that the squares of samples near 1e-160 or 1e160 neither
    /// underflow nor overflow.
    unit: f64,
    /// `V_l` per sample, with Giles' floor for levels too few samples show no variance in.
    variance: Vec<f64>,
    /// The variance of each level's mean.
    mean_variance: Vec<f64>,
    cost: Vec<f64>,
    alpha: f64,
    beta: f64,
    gamma: f64,
    bias: f64,
}

impl Stats {
    fn of<L: Level>(levels: &[LevelState], m: f64, run: &Multilevel<L>) -> Result<Stats> {
        let pooled: Vec<LevelSums> = levels.iter().map(pooled_of).collect();
        let differences: Vec<Accumulator> = pooled.iter().map(|p| p.difference).collect();
        let unit = Accumulator::common_unit(&differences);
        let mut mean: Vec<f64> = differences.iter().map(|d| d.mean().abs() / unit).collect();
        let mut variance: Vec<f64> = differences.iter().map(|d| d.variance_in(unit)).collect();
        // A variance that overflowed even in these units would leave the allocation blind,
        // spending the whole cost limit on infinite error bars.
        if let Some(&value) = variance.iter().find(|v| !v.is_finite()) {
            return Err(Error::Overflow {
                what: "variance of a level's samples",
                value,
            });
        }
        let cost = (0..levels.len())
            .map(|l| run.level_cost(l))
            .collect::<Result<Vec<f64>>>()?;
        let mean_variance = levels
            .iter()
            .zip(&pooled)
            .map(|(state, p)| {
                if state.sums.len() == 1 {
                    p.difference.variance_in(unit) / p.count() as f64
                } else {
                    let r = state.sums.len() as f64;
                    let means: Vec<f64> = state
                        .sums
                        .iter()
                        .map(|s| s.difference.mean() / unit)
                        .collect();
                    let centre = means.iter().sum::<f64>() / r;
                    means.iter().map(|x| (x - centre).powi(2)).sum::<f64>() / (r - 1.0) / r
                }
            })
            .collect();
        let rate = |values: &[f64]| {
            let points: Vec<(usize, f64)> = values
                .iter()
                .enumerate()
                .skip(1)
                .map(|(l, &v)| (l, v))
                .collect();
            log_slope(&points, m)
        };
        let alpha = rate(&mean).map_or(0.5, |s| (-s).max(0.5));
        let beta = rate(&variance).map_or(0.5, |s| (-s).max(0.5));
        let gamma = rate(&cost).map_or(0.5, |s| s.max(0.5));
        // Giles' floor: a level whose few samples show (almost) no mean or variance borrows
        // half its predecessor's, decayed at the fitted rate.
        for l in 2..levels.len() {
            mean[l] = mean[l].max(0.5 * mean[l - 1] / m.powf(alpha));
            variance[l] = variance[l].max(0.5 * variance[l - 1] / m.powf(beta));
        }
        let deepest = levels.len() - 1;
        let decay = run
            .model
            .weak_order()
            .map_or(alpha, |known| alpha.min(known));
        let extrapolated = (0..=deepest.min(2))
            .filter(|&r| deepest - r >= 1)
            .map(|r| mean[deepest - r] / m.powf(decay * r as f64))
            .fold(0.0, f64::max);
        let bias = extrapolated / (m.powf(decay) - 1.0);
        Ok(Stats {
            m,
            unit,
            variance,
            mean_variance,
            cost,
            alpha,
            beta,
            gamma,
            bias,
        })
    }
}
