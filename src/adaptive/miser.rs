//! [`Miser`]: recursive stratified sampling (Press & Farrar 1990), after GSL's
//! `gsl_monte_miser` and Numerical Recipes' `miser`.
//!
//! A region with enough points spends a fraction of them (`explore_fraction`) exploring: for
//! every axis it estimates the spread `sigma` of the integrand in each half of the region.
//! It bisects along the axis whose halves promise the smallest variance, gives each half
//! `min_points` plus a share of the rest in proportion to `(V_h sigma_h)^(2/(1+alpha))`, and
//! recurses; a region with fewer than `min_points_per_bisection` points is integrated by
//! plain Monte Carlo. Only those leaf samples enter the estimate. Each exploration is drawn
//! before, and independently of, the samples its decisions steer, so the estimate is
//! unbiased (Jarosz's A.3.5 caveat does not apply).
//!
//! The choice of `alpha` comes from Press & Farrar's model: if the variance of a half's
//! estimate falls as `sigma^2 / N^alpha` (faster than `1/N` because the half is stratified
//! further), then minimising `sum V_h^2 sigma_h^2 / N_h^alpha` gives
//! `N_h ∝ (V_h sigma_h)^(2/(1+alpha))`, and the best axis minimises
//! `sum_h (V_h sigma_h)^(2/(1+alpha))`. `alpha = 1` is Neyman allocation; GSL and NR use 2.
//! Without dither (the default) the halves have equal volumes and this is exactly GSL's rule;
//! the spreads are the sample standard deviations of the exploration values in each half,
//! as GSL's `estimate_corrmc` intends.
//!
//! MISER's own error estimate (summing the leaves' sample variances) is heuristic: the leaves
//! are small and the tree is shaped by noisy explorations. The error bar here instead comes
//! from `R` independent replicates, each a complete MISER run with its own randomness: the
//! replicate means are independent and identically distributed, so their Student-t interval
//! with `R - 1` degrees of freedom is honest ([`Estimate::from_replicates`]).

use super::batches::{Batches, Workspace};
use super::cell::Cell;
use super::scalar_batch::{ScalarBatch, ScalarIntegrand};
use crate::engine::{
    self, ChunkJob, DEFAULT_REPLICATES, Drive, Executor, Limits, Next, NonFinite, RunConfig,
    StageEnd, Stages, Targets, run_settings,
};
use crate::error::{Error, Result};
use crate::hash::hash_words;
use crate::pdf::{Pdf, UniformBox};
use crate::points::Points;
use crate::stats::rounding::{UNIT_ROUNDOFF, contribution_allowance, gamma};
use crate::stats::{Estimate, StopReason, VectorEstimate};
use crate::stats::{UNSCALED_LIMIT, scale_for};

/// Points per replicate of a run without [`Miser::samples`].
const DEFAULT_SAMPLES: u64 = 1 << 14;
/// The most replicates a run may have (their results are kept in memory).
const MAX_REPLICATES: u64 = 1 << 20;
/// A region this deep is integrated as a leaf, which bounds the recursion (and the stack)
/// even for a tiny `explore_fraction`; typical trees are a few dozen levels deep.
const MAX_DEPTH: u32 = 512;
/// Both halves need this many points before they are offered to other threads.
const SPLIT_MIN: u64 = 1 << 14;
/// Separates MISER's coin flips from every other use of the seed.
const TAG: u64 = 0x004d_4953_4552;

/// MISER: recursive stratified sampling with variance-driven bisection, with an error bar
/// from independent replicates.
///
/// Points come from any [`Sampler`](crate::Sampler) with independent points or extensible passes (independent
/// points by default; a scrambled Sobol' sequence gives each exploration and each leaf its own
/// randomized net). The result is bit-identical for any number of threads: replicates, and
/// large subregions, are units of work whose points and decisions depend only on their
/// place in the plan, and partial results are added in a fixed order.
///
/// With a [`tolerance`](Self::tolerance), the run starts with [`samples`](Self::samples) per
/// replicate and doubles them, each stage a fresh, independent run, until the 95% half-width
/// meets the tolerance or a limit stops it; the estimate is the last stage's (`n` its
/// evaluations, exploration included) and `evaluations` counts every stage. As for the
/// Integrator's replicates, the standard error of a run to a tolerance is inflated by 1.2
/// against optional stopping.
///
/// ```
/// use mcint::{adaptive::Miser, pdf::UniformBox};
/// // A sharp peak: the integral of exp(-50 |x - c|^2) over the unit square is about pi/50.
/// let f = |x: &[f64]| (-50.0 * ((x[0] - 0.5).powi(2) + (x[1] - 0.5).powi(2))).exp();
/// let e = Miser::new(f, UniformBox::unit(2).unwrap())
///     .samples(1 << 12)
///     .seed(1)
///     .run()
///     .unwrap();
/// let exact = std::f64::consts::PI / 50.0 * libm::erf(0.5 * 50f64.sqrt()).powi(2);
/// assert!((e.mean - exact).abs() < 5.0 * e.std_error.unwrap());
/// assert_eq!(e.replicates, 16);
/// ```
pub struct Miser<F> {
    f: F,
    domain: UniformBox,
    config: RunConfig,
    explore_fraction: f64,
    min_points: Option<u64>,
    min_points_per_bisection: Option<u64>,
    dither: f64,
    alpha: f64,
}

impl<F: Fn(&[f64]) -> f64 + Sync> Miser<F> {
    /// MISER for `f` over a box, with GSL's defaults: `explore_fraction` 0.1,
    /// `min_points` `16 d`, `min_points_per_bisection` `32 min_points`, `alpha` 2, no dither;
    /// and 16 replicates of `2^14` points, independent points, all threads.
    ///
    /// ```
    /// use mcint::{adaptive::Miser, pdf::UniformBox};
    /// let e = Miser::new(|x: &[f64]| x[0] + x[1], UniformBox::unit(2).unwrap()).run().unwrap();
    /// assert!((e.mean - 1.0).abs() < 1e-2);
    /// ```
    pub fn new(f: F, domain: UniformBox) -> Self {
        Miser::with_defaults(f, domain)
    }

    /// Runs the integration.
    ///
    /// Errors name the setting that is out of range, report a sampler of the wrong dimension
    /// or kind, and report NaN or infinite integrand values (their count and the first
    /// point, in coordinates relative to the domain), since such a mean would be silently
    /// wrong.
    ///
    /// ```
    /// use mcint::{adaptive::Miser, pdf::UniformBox};
    /// let bad = Miser::new(|x: &[f64]| 1.0 / (x[0] - x[0]), UniformBox::unit(1).unwrap()).run();
    /// assert!(bad.unwrap_err().to_string().contains("non-finite"));
    /// ```
    pub fn run(&self) -> Result<Estimate> {
        self.run_with(&self.f)
    }
}

impl<G: Fn(&Points, &mut [f64]) + Sync> Miser<ScalarBatch<G>> {
    /// MISER for an integrand evaluated a block of points at a time (see [`ScalarBatch`]),
    /// with the defaults of [`new`](Miser::new): the same points, decisions and bits as the
    /// per-point integrand with the same values.
    ///
    /// ```
    /// use mcint::{adaptive::Miser, pdf::UniformBox, Points};
    /// let per_point = Miser::new(|x: &[f64]| x[0] * x[1], UniformBox::unit(2).unwrap());
    /// let by_blocks = Miser::new_batch(
    ///     |p: &Points, out: &mut [f64]| {
    ///         for (y, (a, b)) in out.iter_mut().zip(p.column(0).iter().zip(p.column(1))) {
    ///             *y = a * b;
    ///         }
    ///     },
    ///     UniformBox::unit(2).unwrap(),
    /// );
    /// let (a, b) = (per_point.seed(3).run().unwrap(), by_blocks.seed(3).run().unwrap());
    /// assert_eq!(a.mean.to_bits(), b.mean.to_bits());
    /// ```
    pub fn new_batch(f: G, domain: UniformBox) -> Self {
        Miser::with_defaults(ScalarBatch(f), domain)
    }

    /// Runs the integration, as [`Miser::run`] does for a per-point integrand.
    ///
    /// ```
    /// use mcint::{adaptive::Miser, pdf::UniformBox, Points};
    /// let f = |p: &Points, out: &mut [f64]| out.fill(f64::NAN);
    /// let bad = Miser::new_batch(f, UniformBox::unit(1).unwrap()).run();
    /// assert!(bad.unwrap_err().to_string().contains("non-finite"));
    /// ```
    pub fn run(&self) -> Result<Estimate> {
        self.run_with(&self.f)
    }
}

impl<F> Miser<F> {
    /// MISER over `f` (per point or by blocks) with GSL's defaults.
    fn with_defaults(f: F, domain: UniformBox) -> Self {
        Miser {
            f,
            domain,
            config: RunConfig::default(),
            explore_fraction: 0.1,
            min_points: None,
            min_points_per_bisection: None,
            dither: 0.0,
            alpha: 2.0,
        }
    }

    run_settings! {
        setup: "use mcint::{adaptive::Miser, pdf::UniformBox};\n\
                const DIMS: usize = 2;\n\
                let runner = || Miser::new(|x: &[f64]| (x[0] * x[1]).exp(), UniformBox::unit(DIMS).unwrap()).samples(2048);",
        run: ".run().unwrap()";
        sampler, seed, threads, tolerance, non_finite, time_limit, deadline, cancel_token, progress, cluster
    }

    /// Integrand evaluations per replicate, exploration included (at least 1; default
    /// `2^14`); with a tolerance, those of the first stage.
    ///
    /// ```
    /// use mcint::{adaptive::Miser, pdf::UniformBox};
    /// let e = Miser::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .samples(125).replicates(8).run().unwrap();
    /// assert_eq!(e.n, 1000);
    /// ```
    pub fn samples(mut self, n: u64) -> Self {
        self.config.samples = Some(n);
        self
    }

    /// Fraction of a region's points spent exploring before it is bisected (in `(0, 1)`;
    /// default 0.1, as GSL). At least `min_points` are always spent.
    ///
    /// ```
    /// use mcint::{adaptive::Miser, pdf::UniformBox};
    /// let run = |f| Miser::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).explore_fraction(f).run();
    /// assert!(run(0.2).is_ok());
    /// assert!(run(1.0).unwrap_err().to_string().contains("explore_fraction"));
    /// ```
    pub fn explore_fraction(mut self, fraction: f64) -> Self {
        self.explore_fraction = fraction;
        self
    }

    /// The fewest points a region receives, and explores with (at least 2; default `16 d`, as
    /// GSL, which gives each of the `2 d` half-regions about 8 exploration points).
    ///
    /// ```
    /// use mcint::{adaptive::Miser, pdf::UniformBox};
    /// let run = |n| Miser::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).min_points(n).run();
    /// assert!(run(8).is_ok());
    /// assert!(run(1).unwrap_err().to_string().contains("min_points"));
    /// ```
    pub fn min_points(mut self, n: u64) -> Self {
        self.min_points = Some(n);
        self
    }

    /// Regions with fewer points are not bisected but integrated by plain Monte Carlo (at
    /// least `3 min_points`: an exploration and two halves; default `32 min_points`, as GSL).
    ///
    /// ```
    /// use mcint::{adaptive::Miser, pdf::UniformBox};
    /// let run = |n| Miser::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .min_points(16).min_points_per_bisection(n).run();
    /// assert!(run(64).is_ok());
    /// assert!(run(40).unwrap_err().to_string().contains("min_points_per_bisection"));
    /// ```
    pub fn min_points_per_bisection(mut self, n: u64) -> Self {
        self.min_points_per_bisection = Some(n);
        self
    }

    /// Moves each bisection off-centre by `±dither` of the region's width, with a random sign
    /// per axis (in `[0, 0.5)`; default 0, as GSL). A little dither (GSL suggests 0.1) keeps
    /// the cuts away from features symmetric about the centre.
    ///
    /// ```
    /// use mcint::{adaptive::Miser, pdf::UniformBox};
    /// let run = |d| Miser::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).dither(d).run();
    /// assert!(run(0.1).is_ok());
    /// assert!(run(0.5).unwrap_err().to_string().contains("dither"));
    /// ```
    pub fn dither(mut self, dither: f64) -> Self {
        self.dither = dither;
        self
    }

    /// The exponent of Press & Farrar's variance model (finite, `>= 0`; default 2, as GSL
    /// and NR): halves get points in proportion to `(V_h sigma_h)^(2/(1+alpha))`.
    ///
    /// ```
    /// use mcint::{adaptive::Miser, pdf::UniformBox};
    /// let run = |a| Miser::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).alpha(a).run();
    /// assert!(run(1.0).is_ok());
    /// assert!(run(-1.0).unwrap_err().to_string().contains("alpha"));
    /// ```
    pub fn alpha(mut self, alpha: f64) -> Self {
        self.alpha = alpha;
        self
    }

    /// Number of independent replicates (1 to `2^20`; default 16). The error bar is their
    /// Student-t interval with `R - 1` degrees of freedom; a single replicate gives none.
    ///
    /// ```
    /// use mcint::{adaptive::Miser, pdf::UniformBox};
    /// let e = Miser::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).replicates(1).run().unwrap();
    /// assert_eq!(e.std_error, None);
    /// ```
    pub fn replicates(mut self, replicates: u64) -> Self {
        self.config.replicates = Some(replicates);
        self
    }

    /// The run over `f` (the integrand, per point or by blocks), its result checked for
    /// overflow.
    fn run_with<E: ScalarIntegrand>(&self, f: &E) -> Result<Estimate> {
        self.run_unchecked(f).and_then(Estimate::checked)
    }

    /// [`run_with`](Self::run_with) before its result is checked for overflow.
    fn run_unchecked<E: ScalarIntegrand>(&self, f: &E) -> Result<Estimate> {
        let settings = self.settings()?;
        let (executor, _run) = self.config.executor()?;
        let sampler = self
            .config
            .sampler(self.domain.dims(), "sampler (the dimension of the domain)")?;
        let limits = self.config.limits();
        let run = Recursion {
            f,
            domain: &self.domain,
            batches: Batches::new(&*sampler, "MISER")?,
            settings,
            seed: self.config.seed().unwrap_or_else(|| sampler.seed()),
            executor,
            limits: limits.clone(),
        };
        let r = settings.replicates;
        let mut per_replicate = self.config.samples.unwrap_or(DEFAULT_SAMPLES);
        let tolerance = self.config.tolerance;
        let planned = match &tolerance {
            Some(t) => t.evaluation_limit(),
            None => per_replicate.saturating_mul(r),
        };
        self.config.check_budget("samples x replicates", planned)?;
        if let Some(t) = &tolerance {
            // The first stage fits the evaluation limit, if any stage does.
            per_replicate = per_replicate.min(t.evaluation_limit() / r);
        }
        if per_replicate == 0 {
            let (name, value) = match &self.config.tolerance {
                Some(t) if self.config.samples.is_none_or(|n| n > 0) => {
                    ("max_evals", t.evaluation_limit())
                }
                _ => ("samples", 0),
            };
            return Err(Error::invalid(
                name,
                value,
                format!("at least one evaluation per replicate ({r})"),
            ));
        }

        let targets = Targets::new(1, self.config.tolerance, None, &[])?;
        let mut stages = MiserStages {
            run: &run,
            per_replicate,
            next_slot: 0,
            doubling: targets.any(),
            stages: 0,
            spent: 0,
            last: None,
        };
        let drive = Drive {
            executor: &executor,
            limits: &limits,
            targets: &targets,
            config: &self.config,
            spent: 0,
            planned,
        };
        let run = engine::drive(&mut stages, &drive)?;
        run.outputs
            .into_iter()
            .next()
            .ok_or_else(|| Error::invalid("outputs", 0, "one output"))
    }

    fn settings(&self) -> Result<Settings> {
        let dims = self.domain.dims();
        let replicates = self.config.replicates.unwrap_or(DEFAULT_REPLICATES);
        if !(1..=MAX_REPLICATES).contains(&replicates) {
            return Err(Error::invalid(
                "replicates",
                replicates,
                format!("1 to {MAX_REPLICATES}"),
            ));
        }
        if replicates < 2 && self.config.tolerance.is_some() {
            return Err(Error::invalid(
                "replicates",
                replicates,
                "at least 2 with a tolerance (the error bar comes from the replicates)",
            ));
        }
        let f = self.explore_fraction;
        if !(f > 0.0 && f < 1.0) {
            return Err(Error::invalid(
                "explore_fraction",
                f,
                "a fraction strictly between 0 and 1",
            ));
        }
        let min_points = self
            .min_points
            .unwrap_or_else(|| 16u64.saturating_mul(dims as u64));
        if min_points < 2 {
            return Err(Error::invalid("min_points", min_points, "at least 2"));
        }
        let least = min_points.saturating_mul(3);
        let min_bisect = self
            .min_points_per_bisection
            .unwrap_or_else(|| min_points.saturating_mul(32));
        if min_bisect < least {
            return Err(Error::invalid(
                "min_points_per_bisection",
                min_bisect,
                format!(
                    "at least 3 x min_points = {least} (an exploration and two halves of \
                     min_points each)"
                ),
            ));
        }
        if !(self.dither >= 0.0 && self.dither < 0.5) {
            return Err(Error::invalid("dither", self.dither, "a value in [0, 0.5)"));
        }
        if !(self.alpha.is_finite() && self.alpha >= 0.0) {
            return Err(Error::invalid("alpha", self.alpha, "a finite value >= 0"));
        }
        Ok(Settings {
            dims,
            replicates,
            explore_fraction: f,
            min_points,
            min_bisect,
            dither: self.dither,
            beta: 2.0 / (1.0 + self.alpha),
        })
    }
}

/// Validated settings.
#[derive(Debug, Clone, Copy)]
struct Settings {
    dims: usize,
    replicates: u64,
    explore_fraction: f64,
    min_points: u64,
    min_bisect: u64,
    dither: f64,
    /// `2 / (1 + alpha)`.
    beta: f64,
}

/// Everything a region's computation reads.
struct Recursion<'a, F> {
    f: &'a F,
    domain: &'a UniformBox,
    batches: Batches<'a>,
    settings: Settings,
    seed: u64,
    executor: Executor,
    /// The run's time limit and cancellation, checked before every exploration and leaf.
    limits: Limits,
}

/// Where a replicate's first non-finite value occurred.
#[cfg_attr(feature = "mpi", derive(serde::Serialize, serde::Deserialize))]
#[derive(Debug, Clone)]
struct FirstNonFinite {
    /// Position of the point in the replicate's share of the evaluations.
    index: u64,
    value: f64,
    /// The point, relative to the domain.
    point: Vec<f64>,
}

/// The outcome of one region: its integral over the unit cube's measure (the domain volume is
/// applied at the end) and the non-finite values met.
#[cfg_attr(feature = "mpi", derive(serde::Serialize, serde::Deserialize))]
#[derive(Debug, Clone, Default)]
struct Partial {
    integral: f64,
    /// A bound on the rounding error of `integral`.
    rounding: f64,
    non_finite: u64,
    first: Option<FirstNonFinite>,
}

impl Partial {
    /// Left then right: the order is fixed by the tree, whoever computed the halves.
    fn join(left: Partial, right: Partial) -> Partial {
        let integral = left.integral + right.integral;
        Partial {
            integral,
            rounding: left.rounding + right.rounding + UNIT_ROUNDOFF * integral.abs(),
            non_finite: left.non_finite + right.non_finite,
            first: left.first.or(right.first),
        }
    }

    fn record(&mut self, index: u64, value: f64, point: &[f64]) {
        self.non_finite += 1;
        if self.first.is_none() {
            self.first = Some(FirstNonFinite {
                index,
                value,
                point: point.to_vec(),
            });
        }
    }
}

/// Shifted sums of the exploration values that fell in one half of one axis.
#[derive(Debug, Clone, Copy, Default)]
struct HalfSums {
    count: u64,
    sum: f64,
    sum_sq: f64,
}

/// The units of the exploration's deviations: 1 for ordinary values, a power of two near
/// them for values whose squares would overflow or underflow (as [`scale_for`] chooses for
/// the Accumulator), so that the halves' spreads, and the bisection they choose, are those
/// of the same integrand at magnitude 1.
struct DeviationUnits {
    unit: f64,
    /// Whether a nonzero deviation was met: the first sets the units, which only grow after.
    nonzero: bool,
}

impl DeviationUnits {
    /// `deviation` in the units, after moving every half's sums to larger units when it
    /// calls for them.
    fn express(&mut self, deviation: f64, halves: &mut [(HalfSums, HalfSums)]) -> f64 {
        if deviation != 0.0 {
            let wanted = scale_for(deviation.abs());
            if !self.nonzero {
                // Every sum is still zero: nothing to move.
                self.unit = wanted;
                self.nonzero = true;
            } else if wanted > self.unit {
                let ratio = self.unit / wanted;
                for side in halves.iter_mut().flat_map(|(l, r)| [l, r]) {
                    side.sum *= ratio;
                    side.sum_sq *= ratio * ratio;
                }
                self.unit = wanted;
            }
        }
        deviation / self.unit
    }
}

impl HalfSums {
    /// Sample standard deviation (`None` with fewer than two values).
    fn std_dev(&self) -> Option<f64> {
        if self.count < 2 {
            return None;
        }
        let n = self.count as f64;
        let m2 = self.sum_sq - self.sum * self.sum / n;
        Some((m2.max(0.0) / (n - 1.0)).sqrt())
    }
}

/// The slots of one stage's replicates.
struct Stage {
    /// First slot of the stage.
    base: u64,
    per_replicate: u64,
}

impl<F: ScalarIntegrand> Recursion<'_, F> {
    /// Stops the work of a stage once its time limit has passed or it was cancelled (checked
    /// before every region and every block of points).
    fn check_limits(&self) -> Result<()> {
        match self.limits.reached() {
            None => Ok(()),
            Some(stop) => Err(Error::Interrupted {
                stop,
                evaluations: 0,
            }),
        }
    }

    /// One stage: `replicates` independent MISER runs of `per_replicate` evaluations each,
    /// from slot `base` on, as one estimate from the replicates (`None` when a limit cut the
    /// stage short), and the first non-finite value met; `progress` is told the stage's
    /// evaluations folded so far, after every replicate.
    fn stage(
        &self,
        per_replicate: u64,
        replicates: u64,
        base: u64,
        progress: &mut dyn FnMut(u64),
    ) -> Result<(Option<Estimate>, StageEnd)> {
        let needed = per_replicate
            .checked_mul(replicates)
            .and_then(|n| n.checked_add(base));
        if needed.is_none_or(|n| n > self.batches.slots()) {
            return Err(Error::IndexOutOfRange {
                what: "evaluations of the sampler's stream (sample indices or passes)",
                limit: self.batches.slots(),
            });
        }
        let stage = StageJob {
            run: self,
            stage: Stage {
                base,
                per_replicate,
            },
        };
        let mut partials = Vec::with_capacity(replicates as usize);
        // Every replicate at once: their results are small.
        let stopped =
            self.executor
                .run(&stage, 0..replicates, replicates, &self.limits, |_, p| {
                    partials.push(p);
                    progress(partials.len() as u64 * per_replicate);
                    Ok(())
                })?;
        if let Some(stop) = stopped {
            let end = StageEnd {
                stop: Some(stop),
                non_finite: None,
            };
            return Ok((None, end));
        }
        let count: u64 = partials.iter().map(|p| p.non_finite).sum();
        let non_finite = partials.iter().enumerate().find_map(|(r, p)| {
            p.first.as_ref().map(|first| NonFinite {
                count,
                replicate: r as u64,
                index: first.index,
                output: None,
                value: first.value,
                point: first.point.clone(),
            })
        });
        let volume = self.domain.volume();
        let means: Vec<f64> = partials.iter().map(|p| volume * p.integral).collect();
        let bounds: Vec<f64> = partials
            .iter()
            .zip(&means)
            .map(|(p, m)| volume * p.rounding + UNIT_ROUNDOFF * m.abs())
            .collect();
        let mut estimate = Estimate::from_bounded_replicates(&means, &bounds, per_replicate)?;
        estimate.non_finite = count;
        estimate.finalize();
        Ok((
            Some(estimate),
            StageEnd {
                stop: None,
                non_finite,
            },
        ))
    }

    /// MISER on one region with `budget` evaluations, drawing its batches from slot `slot` on.
    fn region(
        &self,
        stage: &Stage,
        cell: Cell,
        budget: u64,
        slot: u64,
        depth: u32,
        work: &mut Workspace,
    ) -> Result<Partial> {
        self.check_limits()?;
        let s = &self.settings;
        let explore = s
            .min_points
            .max((budget as f64 * s.explore_fraction) as u64);
        let bisect = budget >= s.min_bisect
            && depth < MAX_DEPTH
            && budget.saturating_sub(explore) >= 2 * s.min_points;
        if !bisect {
            return self.leaf(stage, &cell, budget, slot, work);
        }

        let coin = hash_words(self.seed, &[TAG, slot]);
        let mid: Vec<f64> = (0..s.dims)
            .map(|i| {
                let (lo, hi) = (cell.lo[i], cell.hi[i]);
                let shift = if s.dither > 0.0 {
                    let heads = hash_words(self.seed, &[TAG, slot, 1 + i as u64]) & 1 == 1;
                    if heads { s.dither } else { -s.dither }
                } else {
                    0.0
                };
                lo + (0.5 - shift) * (hi - lo)
            })
            .collect();
        let mut partial = Partial::default();
        let halves = self.explore(stage, &cell, &mid, explore, slot, work, &mut partial)?;

        // The axis whose halves promise the least variance; the scan starts at a random axis
        // so that exact ties (a constant region) are broken at random, not always the same way.
        let start = (coin % s.dims as u64) as usize;
        let mut best: Option<(usize, f64, f64)> = None;
        for k in 0..s.dims {
            let i = (start + k) % s.dims;
            let (Some(sl), Some(sr)) = (halves[i].0.std_dev(), halves[i].1.std_dev()) else {
                continue;
            };
            let frac_l = (mid[i] - cell.lo[i]) / (cell.hi[i] - cell.lo[i]);
            let wl = (frac_l * sl).powf(s.beta);
            let wr = ((1.0 - frac_l) * sr).powf(s.beta);
            if best.is_none_or(|(_, bl, br)| wl + wr < bl + br) {
                best = Some((i, wl, wr));
            }
        }
        let (axis, wl, wr) = best.unwrap_or((start, 1.0, 1.0));
        let frac_l = (mid[axis] - cell.lo[axis]) / (cell.hi[axis] - cell.lo[axis]);
        let share_l = if wl + wr > 0.0 && (wl + wr).is_finite() {
            wl / (wl + wr)
        } else {
            frac_l
        };
        let rest = budget - explore;
        let free = rest - 2 * s.min_points;
        let n_left = s.min_points + ((free as f64 * share_l) as u64).min(free);
        let n_right = rest - n_left;

        let mut left = cell.clone();
        left.hi[axis] = mid[axis];
        let mut right = cell;
        right.lo[axis] = mid[axis];
        let slot_left = slot + explore;
        let slot_right = slot_left + n_left;

        let (l, r) = if n_left >= SPLIT_MIN && n_right >= SPLIT_MIN {
            // Large halves are offered to other threads; the tree fixes the order of the sum.
            let origin = (stage.replicate_of(slot), slot - stage.base_of(slot));
            self.executor.join(
                origin,
                || {
                    let mut own = Workspace::new(s.dims, self.f.block())?;
                    self.region(stage, left, n_left, slot_left, depth + 1, &mut own)
                },
                || {
                    let mut own = Workspace::new(s.dims, self.f.block())?;
                    self.region(stage, right, n_right, slot_right, depth + 1, &mut own)
                },
            )
        } else {
            let l = self.region(stage, left, n_left, slot_left, depth + 1, work);
            let r = self.region(stage, right, n_right, slot_right, depth + 1, work);
            (l, r)
        };
        let children = Partial::join(l?, r?);
        Ok(Partial::join(partial, children))
    }

    /// Draws `n` exploration points and returns, per axis, the sums of the values that fell
    /// in its left and right halves. As in GSL, point `k` is forced into the right (`k` even)
    /// or left half of axis `(k / 2) mod d`, so every half-region gets points.
    #[allow(clippy::too_many_arguments)]
    fn explore(
        &self,
        stage: &Stage,
        cell: &Cell,
        mid: &[f64],
        n: u64,
        slot: u64,
        work: &mut Workspace,
        partial: &mut Partial,
    ) -> Result<Vec<(HalfSums, HalfSums)>> {
        let dims = self.settings.dims;
        let mut halves = vec![(HalfSums::default(), HalfSums::default()); dims];
        // Sums are taken about the first value, so that a large constant offset does not
        // cancel away the spread.
        let mut shift: Option<f64> = None;
        let mut units = DeviationUnits {
            unit: 1.0,
            nonzero: false,
        };
        let mut k = 0u64;
        while k < n {
            self.check_limits()?;
            let want = (n - k).min(self.f.block() as u64) as usize;
            let len = self.batches.fill(slot, k, want, &mut work.points)?;
            let place = |points: &Points, i: usize, unit: &mut [f64], x: &mut [f64]| {
                let forced = ((k + i as u64) / 2 % dims as u64) as usize;
                let right_side = (k + i as u64).is_multiple_of(2);
                for (dim, u) in unit.iter_mut().enumerate() {
                    let (lo, hi) = if dim != forced {
                        (cell.lo[dim], cell.hi[dim])
                    } else if right_side {
                        (mid[dim], cell.hi[dim])
                    } else {
                        (cell.lo[dim], mid[dim])
                    };
                    *u = lo + points.get(i, dim) * (hi - lo);
                }
                self.domain.sample(unit, x);
            };
            self.f.each(len, work, place, |i, y, unit| {
                if !y.is_finite() {
                    partial.record(slot - stage.base_of(slot) + k + i as u64, y, unit);
                    return;
                }
                let first = *shift.get_or_insert(y);
                let deviation = y - first;
                let y = if deviation.is_finite() {
                    units.express(deviation, &mut halves)
                } else {
                    // Values near `f64::MAX` of both signs: the half of their difference is
                    // finite, and its units are those of the difference (exactly twice it).
                    2.0 * units.express(0.5 * y - 0.5 * first, &mut halves)
                };
                for ((half, &u), &m) in halves.iter_mut().zip(unit).zip(mid) {
                    let side = if u <= m { &mut half.0 } else { &mut half.1 };
                    side.count += 1;
                    side.sum += y;
                    side.sum_sq += y * y;
                }
            });
            k += len as u64;
        }
        Ok(halves)
    }

    /// Plain Monte Carlo with `n` points in `cell`.
    fn leaf(
        &self,
        stage: &Stage,
        cell: &Cell,
        n: u64,
        slot: u64,
        work: &mut Workspace,
    ) -> Result<Partial> {
        let mut partial = Partial::default();
        // The sum is kept in units of a power of two near the largest value, 1 unless values
        // pass 2^480: two values near `f64::MAX` would overflow it.
        let mut sum = LeafSum::default();
        let mut largest = 0.0f64;
        let mut k = 0u64;
        while k < n {
            self.check_limits()?;
            let want = (n - k).min(self.f.block() as u64) as usize;
            let len = self.batches.fill(slot, k, want, &mut work.points)?;
            let place = |points: &Points, i: usize, unit: &mut [f64], x: &mut [f64]| {
                cell.place(points, i, self.domain, unit, x);
            };
            self.f.each(len, work, place, |i, y, unit| {
                if y.is_finite() {
                    sum.add(y);
                    largest = largest.max(y.abs());
                } else {
                    partial.record(slot - stage.base_of(slot) + k + i as u64, y, unit);
                }
            });
            k += len as u64;
        }
        // The finite values only (all of them, unless non-finite ones are skipped).
        let finite = n - partial.non_finite;
        if finite > 0 {
            partial.integral = cell.volume() * (sum.total / finite as f64) * sum.unit;
            // The running sum of `finite` values, each evaluated to the allowance.
            partial.rounding = cell.volume() * (gamma(finite as f64) * largest)
                + cell.volume() * contribution_allowance(largest)
                + 2.0 * UNIT_ROUNDOFF * partial.integral.abs();
        }
        Ok(partial)
    }
}

/// A leaf's sum of values, in units of a power of two: 1 for ordinary values (the sum then
/// has the bits of a plain one), larger ones, as [`scale_for`] chooses them, once a value
/// passes [`UNSCALED_LIMIT`].
struct LeafSum {
    total: f64,
    unit: f64,
    /// `UNSCALED_LIMIT` in the units: a value beyond it calls for larger units.
    ceiling: f64,
}

impl Default for LeafSum {
    fn default() -> Self {
        LeafSum {
            total: 0.0,
            unit: 1.0,
            ceiling: UNSCALED_LIMIT,
        }
    }
}

impl LeafSum {
    fn add(&mut self, y: f64) {
        if y.abs() > self.ceiling {
            let wanted = scale_for(y.abs());
            // Powers of two: the change of units is exact (short of the subnormals).
            self.total *= self.unit / wanted;
            self.unit = wanted;
            self.ceiling = UNSCALED_LIMIT * wanted;
        }
        self.total += y / self.unit;
    }
}

/// The replicates of one stage, as work for the executor: chunk `r` is replicate `r`.
struct StageJob<'a, 'b, F> {
    run: &'a Recursion<'b, F>,
    stage: Stage,
}

impl<F: ScalarIntegrand> ChunkJob for StageJob<'_, '_, F> {
    type Scratch = Workspace;
    type Output = Partial;

    fn scratch(&self) -> Result<Workspace> {
        Workspace::new(self.run.settings.dims, self.run.f.block())
    }

    fn run(&self, work: &mut Workspace, r: u64, _: &Limits) -> Result<Option<Partial>> {
        let slot = self.stage.base + r * self.stage.per_replicate;
        let cell = Cell::unit(self.run.settings.dims);
        // The run's own limits are checked before every region and block: a replicate they
        // interrupt is dropped.
        match self
            .run
            .region(&self.stage, cell, self.stage.per_replicate, slot, 0, work)
        {
            Err(Error::Interrupted { .. }) => Ok(None),
            other => other.map(Some),
        }
    }

    fn origin(&self, r: u64) -> (u64, u64) {
        (r, 0)
    }
}

/// A MISER run as stages for the engine's driver: one stage of replicates for a fixed
/// budget; with a tolerance, stages that double the evaluations per replicate, each a fresh,
/// independent run whose estimate replaces the last.
struct MiserStages<'a, 'b, F> {
    run: &'a Recursion<'b, F>,
    per_replicate: u64,
    next_slot: u64,
    /// Whether stages double until a tolerance is met (else there is one stage).
    doubling: bool,
    /// Whole stages so far, and the evaluations they spent.
    stages: u64,
    spent: u64,
    /// The last whole stage's estimate.
    last: Option<Estimate>,
}

impl<F: ScalarIntegrand> Stages for MiserStages<'_, '_, F> {
    fn next(&mut self, _left: u64) -> Result<Next> {
        if self.stages > 0 {
            if !self.doubling {
                return Ok(Next::Done(StopReason::Budget));
            }
            self.per_replicate = self.per_replicate.saturating_mul(2);
        }
        let replicates = self.run.settings.replicates;
        Ok(Next::Stage(self.per_replicate.saturating_mul(replicates)))
    }

    fn run(&mut self, _: &Executor, _: &Limits, progress: &mut dyn FnMut(u64)) -> Result<StageEnd> {
        let r = self.run.settings.replicates;
        let (estimate, end) = self
            .run
            .stage(self.per_replicate, r, self.next_slot, progress)?;
        if let Some(estimate) = estimate {
            let evaluations = self.per_replicate * r;
            self.spent = self.spent.saturating_add(evaluations);
            self.next_slot += evaluations;
            self.stages += 1;
            self.last = Some(estimate);
        }
        Ok(end)
    }

    fn has_estimate(&self) -> bool {
        self.last.is_some()
    }

    fn estimate(&mut self) -> Result<Option<VectorEstimate>> {
        Ok(self.last.clone().map(|mut estimate| {
            estimate.evaluations = self.spent;
            estimate.iterations = self.stages;
            VectorEstimate::assemble(vec![estimate], None)
        }))
    }
}

impl Stage {
    /// The replicate that slot `slot` belongs to.
    fn replicate_of(&self, slot: u64) -> u64 {
        (slot - self.base) / self.per_replicate
    }

    /// The first slot of the replicate that owns `slot`.
    fn base_of(&self, slot: u64) -> u64 {
        self.base + (slot - self.base) / self.per_replicate * self.per_replicate
    }
}
