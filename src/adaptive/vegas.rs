//! [`Vegas`]: VEGAS (Lepage 1978) with the adaptive stratified sampling of VEGAS+ (Lepage
//! 2021, arXiv:2009.05112), after the Python `vegas` package.
//!
//! Each iteration maps uniform points `y` through the adaptive grid ([`VegasGrid`]) to `x`
//! and estimates the integral as the mean of `J(y) f(x(y))`. With stratification on
//! (VEGAS+), `y`-space is cut into `prod_d s_d` equal hypercubes; hypercube `h` receives `n_h`
//! points, and its estimate and variance are
//!
//! `I_h = V_h mean_h(J f)`, `var_h = V_h^2 s_h^2 / n_h`,
//!
//! with `V_h` its volume and `s_h^2` the sample variance of `J f` in it. The iteration's
//! estimate is `sum_h I_h` with variance `sum_h var_h`. After the iteration, the grid is
//! retrained on `(J f)^2` averaged over each increment of each axis, and the next iteration
//! gives hypercube `h`
//!
//! `n_h = n_min + floor(3N/4 * sigma_h^beta / sum_h' sigma_h'^beta)`, `sigma_h = V_h s_h`:
//!
//! a quarter of the `N` evaluations is spread evenly (at least two per hypercube) and three
//! quarters go where the variance is, as in the Python `vegas` package (version 6, whose
//! `neval_frac = 0.75`). With `beta = 1` this is Neyman's optimal allocation; `beta < 1`
//! tempers it against noisy estimates of `sigma_h` (Lepage 2021, section 3). The package
//! feeds its allocation the hypercube's error `sigma_h^2 / n_h` rather than `sigma_h^2`,
//! which tempers it further: once the allocation settles, `n_h ∝ sigma_h^(beta / (1 + beta /
//! 2))`, `sigma_h^0.55` at its default `beta = 0.75`. Here `sigma_h^beta` follows the paper,
//! with a default `beta = 0.5` close to the package's settled exponent: an allocation that
//! follows `sigma_h` harder starves a hypercube whose peak an iteration happened to miss,
//! and with it the grid's increments there (`docs/measurements.md`). With stratification off
//! this is classic VEGAS: one hypercube, importance sampling through the grid alone.
//!
//! Every iteration's points are new (the next unused indices of an independent sampler, pass
//! `k` of an extensible one for iteration `k`) and every decision that shapes an iteration
//! (grid, allocation) is made before its points are drawn, so each iteration's estimate is
//! unbiased and its variance estimate honest. Iterations after the warm-up are combined with
//! weights fixed before their points are drawn, the inverse of the previous iteration's variance
//! (`vegas` weights each by its own, which pulls a combination of many iterations off by up to
//! a standard error, see `combination`); their `chi^2` tells whether they agree. Like `vegas`,
//! this trusts the per-iteration variances: where they are poorly estimated (a discontinuous
//! integrand, whose edge the grid squeezes into a sliver that most iterations miss), the
//! combination can sit several standard errors from the truth, and a `Q` below 0.01 warns.
//!
//! Work is cut into fixed chunks of the iteration's index range, independent of the thread
//! count; their grid training data are summed in fixed groups of chunks (on each MPI rank
//! before the exchange) and then axis by axis in group order, and their hypercube sums folded
//! strictly in order ([`pass`]), so sums, training data and allocations, and hence the
//! result, are bit-identical for any number of threads or ranks. The driver runs on a
//! thread of the pool, and in one process each axis of the grid adapts as a tail task of the
//! iteration's last window, on whichever thread is out of chunks first.
//!
//! With several threads, and non-finite values skipped rather than fatal, a hypercube's mean
//! is over its finite values only (the skipped points are counted in the estimate).

mod combination;
mod growth;
mod integrand;
mod moments;
mod pass;
mod stages;
mod strata;
mod training;
mod units;

use super::vegas_grid::{VegasGrid, check_alpha, check_density_floor, check_increments};
use crate::engine::{self, Drive, RunConfig, Targets, require_randomized, run_settings};
use crate::error::{Error, Result};
use crate::estimator::checked_outputs;
use crate::pdf::{Pdf, UniformBox};
use crate::points::Points;
use crate::sampler::{PassKind, Sampler};
use crate::stats::{Derived, Estimate, Tolerance, VectorEstimate};
use combination::VectorCombination;
use growth::Growth;
use integrand::{Integrand, Scalar};
pub use integrand::{VegasBatch, VegasOutputs};
use stages::Iterations;
use strata::Strata;

/// Evaluations per iteration when the caller gives none.
const DEFAULT_SAMPLES: u64 = 10_000;
/// The fewest evaluations per iteration: fewer make the iterations' variances, which weight
/// their combination, too noisy for honest intervals (docs/measurements.md).
const MIN_SAMPLES: u64 = 50;
/// The lowest density, as a fraction of the uniform one, that the grid keeps on any axis:
/// without it, runs on discontinuous integrands claimed tolerances their intervals missed
/// (docs/measurements.md); grids that never get that thin are unchanged to the bit.
const DEFAULT_DENSITY_FLOOR: f64 = 0.001;
/// Grid increments are capped at one per this many evaluations (as `vegas` does), so that
/// every increment sees some points in each iteration.
const EVALUATIONS_PER_INCREMENT: u64 = 10;
/// Iterations after the warm-up, by default, with a fixed budget and to a tolerance.
const FIXED_ITERATIONS: u64 = 10;
const TOLERANCE_ITERATIONS: u64 = 1 << 20;
/// The largest iteration a run to a tolerance grows to.
const LARGEST_ITERATION: u64 = 1 << 32;

/// VEGAS and VEGAS+ adaptive Monte Carlo integration over a box.
///
/// Defaults: `10_000` evaluations per iteration ([`samples`](Self::samples)), 5 warm-up
/// iterations (they train the grid and the allocation and are then discarded, as `vegas`
/// users do with a separate training call) followed by 10 iterations that are combined, 1000
/// grid increments per axis at most, `alpha = 0.5`, a
/// [`density_floor`](Self::density_floor) of 0.001, adaptive stratification on with
/// `beta = 0.5`, independent points with seed 0, all available threads.
///
/// The estimate is the combination of the iterations weighted by the inverse of the variance of the
/// iteration before each, and its standard error that of this weighted mean (basis
/// [`ErrorBasis::PerSample`](crate::stats::ErrorBasis::PerSample), with `dof` the sum of `n_h - 1`
/// over hypercubes and iterations); `iterations` and `replicates` are the number of iterations
/// combined, `chi2_dof` and `q_value` their agreement (from the second one on), `n` counts the
/// evaluations of the combined iterations and `evaluations` every one spent, warm-up included.
/// An integrand whose values are far from 1 (beyond about `1e±77`) is summed in units of a
/// power of two near them, so that the run is that of the integrand at magnitude 1, scaled;
/// the first iteration chooses the units and is then run again, its evaluations counted.
///
/// ```
/// use mcint::{adaptive::Vegas, pdf::UniformBox};
/// // A narrow Gaussian peak in 3 dimensions; its integral over [0,1]^3 is about 0.1^3 pi^(3/2).
/// let f = |x: &[f64]| {
///     let r2: f64 = x.iter().map(|v| (v - 0.5) * (v - 0.5)).sum();
///     (-r2 / 0.01).exp()
/// };
/// let e = Vegas::new(f, UniformBox::unit(3).unwrap()).seed(1).run().unwrap();
/// let exact = 0.001 * std::f64::consts::PI.powf(1.5); // the tails outside the cube: 5e-12 of it
/// assert!((e.mean - exact).abs() < 5.0 * e.std_error.unwrap());
/// assert_eq!(e.iterations, 10);
/// ```
///
/// With a [`tolerance`](Self::tolerance), the run stops after the first iteration at which the
/// weighted combination meets it and the iterations agree, or before an iteration that would
/// exceed its evaluation limit (which must leave room for the warm-up and one iteration), or
/// before the next iteration once its time limit has passed (the warm-up always runs in full).
/// Iterations that disagree (`Q` below [`DISAGREEMENT_Q`](crate::stats::DISAGREEMENT_Q)) have
/// underestimated variances, and meet no tolerance; the first combined iteration, which has no
/// `Q` yet, must agree in the same sense with the warm-up iterations, whose estimates are as
/// unbiased and whose variances are as honest, but for the first of several, drawn before the
/// grid adapted (without a warm-up it is not checked).
///
/// A run to a tolerance also chooses its iteration size, starting from
/// [`samples`](Self::samples): it doubles it when its iterations disagree (setting the earlier
/// ones aside as warm-up, at most four times), and when its grid has settled but the tolerance
/// still needs more than 32 iterations of the current size (keeping them). Larger iterations
/// train the grid on more points per increment and hit a narrow peak in every iteration. A run
/// whose iterations still disagree after four doublings stops on
/// [`StopReason::IterationsDisagree`](crate::stats::StopReason::IterationsDisagree) with the
/// tolerance not met; so does one that cannot grow (its evaluation limit too close) once its
/// interval is narrow enough but for the disagreement and twice its evaluations have not made
/// them agree. A fixed budget keeps its size.
///
/// ```
/// use mcint::{adaptive::Vegas, pdf::UniformBox, stats::Tolerance};
/// // A Gaussian peak about 1/30 wide per axis in 6-D, off-centre.
/// let f = |x: &[f64]| (-x.iter().map(|v| 900.0 * (v - 0.3) * (v - 0.3)).sum::<f64>()).exp();
/// let e = Vegas::new(f, UniformBox::unit(6).unwrap())
///     .tolerance(Tolerance::relative(1e-3).unwrap())
///     .seed(1)
///     .run()
///     .unwrap();
/// let per_axis = std::f64::consts::PI.sqrt() / 30.0; // the tails outside: below 1e-100
/// assert_eq!(e.stop, mcint::stats::StopReason::ToleranceMet);
/// assert!((e.mean - per_axis.powi(6)).abs() < 5.0 * e.std_error.unwrap());
/// // Iterations grew past the 10^4 points of the first ones.
/// assert!(e.n > 10_000 * e.iterations);
/// ```
pub struct Vegas<F> {
    f: F,
    domain: UniformBox,
    config: RunConfig,
    /// The most iterations after the warm-up, when set.
    iterations: Option<u64>,
    warmup: u64,
    increments: usize,
    alpha: f64,
    density_floor: f64,
    stratified: bool,
    beta: f64,
}

impl<F: Fn(&[f64]) -> f64 + Sync> Vegas<F> {
    /// VEGAS+ for `f` over `domain`, with the defaults listed on [`Vegas`].
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let e = Vegas::new(|x: &[f64]| x[0] * x[1], UniformBox::unit(2).unwrap()).run().unwrap();
    /// assert!((e.mean - 0.25).abs() < 5.0 * e.std_error.unwrap());
    /// ```
    pub fn new(f: F, domain: UniformBox) -> Self {
        Vegas::with_defaults(f, domain)
    }

    /// Runs the warm-up and the iterations and combines the latter.
    ///
    /// Errors when a setting is out of range (the message names it), when the sampler does
    /// not fit (dimension, passes, randomization), and when `J f` is NaN or infinite at any
    /// point ([`Error::NonFiniteContribution`], with the iteration as the replicate and the
    /// sampler's point).
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let bad = Vegas::new(|x: &[f64]| 1.0 / (x[0] - x[0]), UniformBox::unit(1).unwrap()).run();
    /// assert!(bad.unwrap_err().to_string().contains("non-finite"));
    /// ```
    pub fn run(&self) -> Result<Estimate> {
        let targets = Targets::new(1, self.config.tolerance, None, &[])?;
        let run = self.run_engine(&Scalar(&self.f), &targets)?;
        let single = run.outputs.into_iter().next();
        single
            .ok_or_else(|| Error::invalid("outputs", 0, "one output"))
            .and_then(Estimate::checked)
    }
}

/// The settings of scalar and vector runs.
impl<F> Vegas<F> {
    /// The run of `f` over `domain` with the default settings (see [`Vegas`]).
    fn with_defaults(f: F, domain: UniformBox) -> Self {
        Vegas {
            f,
            domain,
            config: RunConfig::default(),
            iterations: None,
            warmup: 5,
            increments: 1000,
            alpha: 0.5,
            density_floor: DEFAULT_DENSITY_FLOOR,
            stratified: true,
            beta: 0.5,
        }
    }

    run_settings! {
        setup: "use mcint::{adaptive::Vegas, pdf::UniformBox};\n\
                const DIMS: usize = 2;\n\
                let runner = || Vegas::new(|x: &[f64]| (x[0] * x[1]).exp(), UniformBox::unit(DIMS).unwrap()).samples(4000);",
        run: ".run().unwrap()";
        sampler, seed, threads, tolerance, non_finite, time_limit, deadline, cancel_token, progress, cluster
    }

    /// Evaluations per iteration, `N` (at least 50; default `10_000`). With stratification
    /// an iteration uses at most `N` (the rounding down of the proportional shares usually
    /// leaves a few unused); without, exactly `N`. A run to a tolerance starts with `N` and
    /// may grow it (see [`Vegas`]).
    ///
    /// Choose `N` for the integrand's hardest feature: the grid and the allocation move on
    /// each iteration's points, so a peak that a few iterations in a row miss loses its share
    /// of both for good, and nothing the run sees afterwards tells. With several separated
    /// peaks in many dimensions, larger iterations make such a streak rarer, at a price on a
    /// single peak (two Gaussians in 8-D: `docs/measurements.md`).
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let e = Vegas::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .stratified(false).samples(1000).warmup(1).iterations(2)
    ///     .run().unwrap();
    /// // Two measured iterations in the estimate, one warm-up spent before them.
    /// assert_eq!((e.n, e.evaluations), (2000, 3000));
    /// ```
    pub fn samples(mut self, n: u64) -> Self {
        self.config.samples = Some(n);
        self
    }

    /// The most iterations combined into the estimate, after the warm-up (at least 1;
    /// default 10 with a fixed budget, and `2^20` for a run to a [`tolerance`](Self::tolerance),
    /// whose evaluation limit stops it first). A tolerance may stop the run earlier.
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let e = Vegas::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).iterations(3).run().unwrap();
    /// assert_eq!(e.iterations, 3);
    /// ```
    pub fn iterations(mut self, n: u64) -> Self {
        self.iterations = Some(n);
        self
    }

    /// Warm-up iterations: they adapt the grid and the allocation, and their estimates are
    /// discarded (default 5; 0 keeps every iteration). Their evaluations count in
    /// [`Estimate::evaluations`], not in `n`.
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let e = Vegas::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .stratified(false).samples(100).warmup(0).iterations(4)
    ///     .run().unwrap();
    /// assert_eq!((e.iterations, e.n), (4, 400));
    /// ```
    pub fn warmup(mut self, n: u64) -> Self {
        self.warmup = n;
        self
    }

    /// The most grid increments per axis (2 to `2^20`; default 1000, `vegas`'s
    /// `maxinc_axis`). A run uses `min(n, N / 10)` of them (at least 2), so that each
    /// increment receives about ten points per iteration, as `vegas` does.
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let v = Vegas::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).grid_increments(1);
    /// assert!(v.run().unwrap_err().to_string().contains("grid_increments"));
    /// ```
    pub fn grid_increments(mut self, n: usize) -> Self {
        self.increments = n;
        self
    }

    /// Damping exponent of the grid's adaptation (in `[0, 2]`; default 0.5). Smaller values
    /// adapt more slowly and more stably; 0 freezes the grid (uniform). Larger values, which
    /// make the grid chase one iteration's noise and gave intervals that missed by many
    /// standard errors, are refused.
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let e = Vegas::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).alpha(0.0).run().unwrap();
    /// assert!((e.mean - 0.5).abs() < 5.0 * e.std_error.unwrap());
    /// assert!(Vegas::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).alpha(7.0).run().is_err());
    /// ```
    pub fn alpha(mut self, alpha: f64) -> Self {
        self.alpha = alpha;
        self
    }

    /// The lowest density the grid keeps on each axis, as a fraction of the uniform density
    /// (in `[0, 1)`; default 0.001; 0 gives the classic grid, as in `vegas`).
    ///
    /// Without a floor the grid can starve a region that holds part of the integral: an
    /// increment that straddles a jump sees the nonzero side so rarely that it keeps widening,
    /// and every iteration then misses the same part of the integral while agreeing with the
    /// others, so a run claims a tolerance that its interval does not cover. The floor bounds
    /// every increment's width by about `1 / floor` times the average, and (with any floor
    /// above 0) the density falls by at most a factor 8 from one increment to the next, so
    /// that no increment left wide straddles a jump; grids that never get that thin or that
    /// steep are unchanged.
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// // A jump at 0.2: the integral is 0.2.
    /// let f = |x: &[f64]| if x[0] < 0.2 { 1.0 } else { 0.0 };
    /// let e = Vegas::new(f, UniformBox::unit(1).unwrap()).density_floor(0.01).run().unwrap();
    /// assert!((e.mean - 0.2).abs() < 5.0 * e.std_error.unwrap());
    /// assert!(Vegas::new(f, UniformBox::unit(1).unwrap()).density_floor(1.0).run().is_err());
    /// ```
    pub fn density_floor(mut self, floor: f64) -> Self {
        self.density_floor = floor;
        self
    }

    /// Adaptive stratification (VEGAS+) on or off (default on). Off gives classic VEGAS:
    /// importance sampling through the grid alone, whose separable grid can settle on one of
    /// several peaks that do not line up with the axes and then claim a part of the integral
    /// with agreeing iterations ([`crate::guide::error_bars`] shows two peaks on a diagonal);
    /// keep it on where the integrand may have such peaks.
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let e = Vegas::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).stratified(false).run().unwrap();
    /// assert!((e.mean - 0.5).abs() < 5.0 * e.std_error.unwrap());
    /// ```
    pub fn stratified(mut self, on: bool) -> Self {
        self.stratified = on;
        self
    }

    /// Damping exponent of the allocation of points to hypercubes, `n_h ∝ sigma_h^beta`
    /// (in `[0, 1]`; default 0.5; 1 is the theoretical optimum, 0 gives fixed uniform
    /// stratification). Used only with stratification on.
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let v = Vegas::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).beta(1.5);
    /// assert!(v.run().unwrap_err().to_string().contains("beta"));
    /// ```
    pub fn beta(mut self, beta: f64) -> Self {
        self.beta = beta;
        self
    }

    /// The run of the integrand `f` (scalar or vector) to `targets`, before its result is
    /// checked for overflow.
    fn run_engine<I: Integrand>(&self, f: &I, targets: &Targets<'_>) -> Result<VectorEstimate>
    where
        F: Sync,
    {
        let m = checked_outputs(f.outputs())?;
        let dims = self.domain.dims();
        let sampler = self
            .config
            .sampler(dims, "sampler (the domain's dimensions)")?;
        let limit = targets.limits();
        let settings = self.settings(&*sampler, limit.as_ref())?;
        let (executor, _run) = self.config.executor()?;
        let limits = self.config.limits_with(limit.and_then(|t| t.time()));
        let strata = Strata::new(
            dims,
            settings.samples,
            self.stratified,
            self.beta,
            settings.increments,
            self.increments,
        );
        let grid = VegasGrid::with_increments(&self.domain, &strata.increments)?;
        let per_cube = if strata.allocation_budget.is_some() {
            strata.cubes as usize
        } else {
            0
        };
        let mut iterations = Iterations {
            vegas: self,
            f,
            sampler: &*sampler,
            strata,
            grid,
            // Equal sigma_h^beta before anything is known: the first iteration is uniform.
            sigf: vec![1.0; per_cube],
            next_sigf: vec![0.0; per_cube],
            sum_sigf: per_cube as f64,
            spare: Default::default(),
            combination: VectorCombination::new(m),
            // 1 for a single output (the map and allocation do not depend on a common scale);
            // for several, one over the previous iteration's mean of (J f_k)^2, so that every
            // output shapes the map whatever its units (all 1 in the first iteration).
            weights: vec![1.0; m],
            units: units::Units::one(m),
            units_chosen: false,
            rerun: 0,
            k: 0,
            spent: 0,
            measured_evaluations: 0,
            non_finite: 0,
            held_back_at: None,
            growth: Growth::new(settings.samples, settings.largest_size),
            set_aside: None,
            max_increments: settings.increments,
            last_iteration: settings.iterations,
            left: u64::MAX,
            chunks: Vec::new(),
            total: 0,
            scale: None,
            base: 0,
            to_tolerance: targets.any(),
        };
        let drive = Drive {
            executor: &executor,
            limits: &limits,
            targets,
            config: &self.config,
            spent: 0,
            // A run to a tolerance cannot know its evaluations.
            planned: if targets.any() {
                0
            } else {
                settings.samples * settings.iterations
            },
        };
        engine::drive(&mut iterations, &drive)
    }

    fn settings(&self, sampler: &dyn Sampler, limit: Option<&Tolerance>) -> Result<Settings> {
        let n = self.config.samples.unwrap_or(DEFAULT_SAMPLES);
        if n < MIN_SAMPLES {
            return Err(Error::invalid(
                "samples",
                n,
                format!(
                    "at least {MIN_SAMPLES} per iteration (fewer make the iterations' variances, \
                     which weight their combination, too noisy: 2 per iteration gave estimates \
                     27 standard errors off)"
                ),
            ));
        }
        let iterations = self.iterations.unwrap_or(if limit.is_some() {
            TOLERANCE_ITERATIONS
        } else {
            FIXED_ITERATIONS
        });
        if iterations == 0 {
            return Err(Error::invalid(
                "iterations",
                0,
                "at least 1 iteration after the warm-up",
            ));
        }
        check_increments(self.increments)?;
        check_alpha(self.alpha)?;
        check_density_floor(self.density_floor)?;
        if !(0.0..=1.0).contains(&self.beta) {
            return Err(Error::invalid(
                "beta",
                self.beta,
                "a damping exponent in [0, 1] (default 0.5)",
            ));
        }
        require_randomized(sampler, "every iteration needs new points")?;
        let total_iterations = self.warmup.checked_add(iterations).ok_or_else(|| {
            Error::invalid(
                "warmup + iterations",
                format!("{} + {iterations}", self.warmup),
                "a total within 64 bits (the sample indices of every iteration must fit)",
            )
        })?;
        let stride = match sampler.passes() {
            PassKind::Independent => n,
            PassKind::Extensible { max } => {
                if n > max {
                    return Err(Error::invalid(
                        "samples",
                        n,
                        format!(
                            "at most {max}, the points in one pass of the {} sampler",
                            sampler.name()
                        ),
                    ));
                }
                max
            }
            PassKind::Fixed { size } => {
                if self.stratified {
                    return Err(Error::invalid(
                        "sampler",
                        sampler.name(),
                        "a sampler with independent or extensible passes for VEGAS+ (a single \
                         point of a fixed pass is not uniform on its own); or stratified(false)",
                    ));
                }
                if !n.is_multiple_of(size) {
                    return Err(Error::invalid(
                        "samples",
                        n,
                        format!(
                            "a multiple of the {} sampler's pass size {size}",
                            sampler.name()
                        ),
                    ));
                }
                n
            }
        };
        if total_iterations.checked_mul(stride).is_none() {
            // Iteration i draws sample indices from i x stride on. Blame the samples only
            // where a valid count of them would fit.
            let most_samples = u64::MAX / total_iterations;
            return Err(if stride == n && most_samples >= MIN_SAMPLES {
                Error::invalid(
                    "samples",
                    n,
                    format!(
                        "at most {most_samples} per iteration, so that the sample indices of \
                         {total_iterations} iterations fit in 64 bits",
                    ),
                )
            } else {
                Error::invalid(
                    "warmup + iterations",
                    total_iterations,
                    format!(
                        "at most {} iterations of {stride} points (the {} sampler's stride), so \
                         that their sample indices fit in 64 bits",
                        u64::MAX / stride,
                        sampler.name()
                    ),
                )
            });
        }
        let planned = match limit {
            Some(t) => t.evaluation_limit(),
            None => total_iterations.saturating_mul(n),
        };
        self.config
            .check_budget("samples x (warmup + iterations)", planned)?;
        if let Some(t) = limit {
            let needed = (self.warmup + 1).saturating_mul(n);
            if t.evaluation_limit() < needed {
                return Err(Error::invalid(
                    "max_evals",
                    t.evaluation_limit(),
                    format!(
                        "at least {needed} ({} warm-up iterations and one more, of {n} \
                         points each), so that one iteration after the warm-up fits",
                        self.warmup
                    ),
                ));
            }
        }
        let increments = (self.increments as u64)
            .min(n / EVALUATIONS_PER_INCREMENT)
            .max(2) as usize;
        // A run to a tolerance may grow its iterations (see `growth`) up to one pass of an
        // extensible sampler; a fixed pass stays the size asked for.
        let largest_size = match sampler.passes() {
            PassKind::Independent => LARGEST_ITERATION,
            PassKind::Extensible { max } => max.min(LARGEST_ITERATION),
            PassKind::Fixed { .. } => n,
        };
        Ok(Settings {
            samples: n,
            increments,
            largest_size: largest_size.max(n),
            iterations: total_iterations,
        })
    }
}

/// Settings derived and checked once per run.
struct Settings {
    /// Evaluations per iteration.
    samples: u64,
    increments: usize,
    /// The most evaluations an iteration may grow to.
    largest_size: u64,
    /// The most iterations, warm-up included.
    iterations: u64,
}

/// Each output's weight in the next iteration's training data and allocation: one over its
/// mean of `(J f_k)^2` over y-space, `N var_k + I_k^2` from the iteration's `N` evaluations
/// (0 for an output that is zero everywhere; all 1 should every output be).
fn output_weights(totals: &pass::Totals, evaluations: u64) -> Vec<f64> {
    let n = evaluations as f64;
    let weights: Vec<f64> = totals
        .sums
        .outputs
        .iter()
        .map(|cube| {
            let square = n * cube.variance + cube.mean * cube.mean;
            if square > 0.0 && square.is_finite() {
                1.0 / square
            } else {
                0.0
            }
        })
        .collect();
    if weights.iter().all(|&w| w == 0.0) {
        vec![1.0; weights.len()]
    } else {
        weights
    }
}

impl<G: Fn(&[f64], &mut [f64]) + Sync> Vegas<VegasOutputs<G>> {
    /// VEGAS (or VEGAS+) for an integrand with `outputs` outputs, `f(x, out)` writing output
    /// `k` to `out[k]`: every output is integrated over the same points, one evaluation per
    /// point, with the defaults and settings of [`Vegas::new`].
    ///
    /// The map and the strata adapt to all outputs together: the grid is trained on
    /// `sum_k w_k (J f_k)^2` and the allocation uses `sigma_h^2 = sum_k w_k sigma_hk^2`, where
    /// `w_k` is one over the previous iteration's mean of `(J f_k)^2`, so that each output
    /// counts in proportion to its own relative variation whatever its units. Lepage's `vegas`
    /// (its `_vegas.pyx`) trains the map and the allocation on the first component only; here
    /// integrands whose outputs peak in different places get a map that serves them all.
    /// A point with any non-finite output is left out of every output. Each output's
    /// iterations are combined with its own weights (see [`Vegas`]); the covariance of the
    /// combined outputs comes from the per-hypercube covariances of every iteration.
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox, stats::Derived};
    /// // A peak and its first moment: the mean of x0 under the peak is 0.5.
    /// let f = |x: &[f64], out: &mut [f64]| {
    ///     let r2: f64 = x.iter().map(|v| (v - 0.5) * (v - 0.5)).sum();
    ///     out[0] = (-r2 / 0.01).exp();
    ///     out[1] = x[0] * out[0];
    /// };
    /// let run = Vegas::new_vector(2, f, UniformBox::unit(3).unwrap()).seed(1).run().unwrap();
    /// let mean = run.derived(&Derived::ratio(1, 0)).unwrap();
    /// assert!((mean.mean - 0.5).abs() < 5.0 * mean.std_error.unwrap());
    /// assert_eq!(run.evaluations, run.outputs[1].evaluations);
    /// ```
    pub fn new_vector(outputs: usize, f: G, domain: UniformBox) -> Self {
        let f = VegasOutputs {
            outputs,
            f,
            output_tolerances: None,
            derived_tolerances: Vec::new(),
        };
        Vegas::with_defaults(f, domain)
    }

    /// Runs the warm-up and the iterations and combines the latter, for every output.
    ///
    /// Errors as [`Vegas::run`] does, and when the number of outputs is 0 or above
    /// [`MAX_OUTPUTS`](crate::estimator::MAX_OUTPUTS), the per-output tolerances are not one
    /// per output, or a derived quantity names an output that does not exist; a non-finite
    /// value is reported with its output.
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let f = |x: &[f64], out: &mut [f64]| out[0] = x[0]; // out[1] never written
    /// let err = Vegas::new_vector(2, f, UniformBox::unit(1).unwrap()).run().unwrap_err();
    /// assert!(err.to_string().contains("in output 1"), "{err}");
    /// ```
    pub fn run(&self) -> Result<VectorEstimate> {
        let targets = Targets::new(
            self.f.outputs,
            self.config.tolerance,
            self.f.output_tolerances.as_deref(),
            &self.f.derived_tolerances,
        )?;
        self.run_engine(&self.f, &targets)?.checked()
    }
}

/// The settings of vector runs, per point or by blocks.
impl<G> Vegas<VegasOutputs<G>> {
    /// A tolerance for each output (one per output): the run stops when every output meets
    /// its own (see [`Integrator::output_tolerances`](crate::Integrator::output_tolerances)).
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox, stats::Tolerance};
    /// let f = |x: &[f64], out: &mut [f64]| { out[0] = x[0]; out[1] = (x[0] * x[1]).exp(); };
    /// let t = |rel| Tolerance::relative(rel).unwrap();
    /// let run = Vegas::new_vector(2, f, UniformBox::unit(2).unwrap())
    ///     .output_tolerances(vec![t(1e-3), t(1e-4)])
    ///     .iterations(1000)
    ///     .run()
    ///     .unwrap();
    /// assert_eq!(run.converged, Some(true));
    /// ```
    pub fn output_tolerances(mut self, tolerances: Vec<Tolerance>) -> Self {
        self.f.output_tolerances = Some(tolerances);
        self
    }

    /// A tolerance on a quantity derived from the integrals (see
    /// [`Integrator::derived_tolerance`](crate::Integrator::derived_tolerance)).
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox, stats::{Derived, Tolerance}};
    /// let f = |x: &[f64], out: &mut [f64]| { out[0] = x[0].powi(4); out[1] = x[0].powi(3); };
    /// let run = Vegas::new_vector(2, f, UniformBox::unit(1).unwrap())
    ///     .derived_tolerance(Derived::ratio(0, 1), Tolerance::relative(1e-3).unwrap())
    ///     .iterations(1000)
    ///     .run()
    ///     .unwrap();
    /// assert_eq!(run.converged, Some(true));
    /// ```
    pub fn derived_tolerance(mut self, quantity: Derived, tolerance: Tolerance) -> Self {
        self.f.derived_tolerances.push((quantity, tolerance));
        self
    }
}

impl<G: Fn(&Points, &mut [f64]) + Sync> Vegas<VegasOutputs<VegasBatch<G>>> {
    /// VEGAS (or VEGAS+) for an integrand evaluated a block of points at a time:
    /// `f(points, out)` gets up to 4096 points of the domain (one column per axis) and writes
    /// output `k` at point `i` to `out[k * n + i]`. For integrands that pay a cost per call
    /// (an interpreter, a GPU kernel, vectorized code); with the same arithmetic per point,
    /// the result has the bits of [`new_vector`](Vegas::new_vector) (or of [`new`](Vegas::new)
    /// for one output).
    ///
    /// ```
    /// use mcint::{Points, adaptive::Vegas, pdf::UniformBox};
    /// let peak = |x: &[f64]| (-x.iter().map(|v| 100.0 * (v - 0.4).powi(2)).sum::<f64>()).exp();
    /// let block = |p: &Points, out: &mut [f64]| {
    ///     let mut x = [0.0; 3];
    ///     for (i, y) in out.iter_mut().enumerate() {
    ///         p.copy_point(i, &mut x);
    ///         *y = peak(&x);
    ///     }
    /// };
    /// let square = || UniformBox::unit(3).unwrap();
    /// let batch = Vegas::new_batch(1, block, square()).samples(2000).seed(3).run().unwrap();
    /// let point = Vegas::new(peak, square()).samples(2000).seed(3).run().unwrap();
    /// assert_eq!(batch.outputs[0], point);
    /// ```
    pub fn new_batch(outputs: usize, f: G, domain: UniformBox) -> Self {
        let f = VegasOutputs {
            outputs,
            f: VegasBatch(f),
            output_tolerances: None,
            derived_tolerances: Vec::new(),
        };
        Vegas::with_defaults(f, domain)
    }

    /// Runs the warm-up and the iterations and combines the latter, for every output; errors
    /// as [`run`](Vegas::run) of [`new_vector`](Vegas::new_vector).
    ///
    /// ```
    /// use mcint::{Points, adaptive::Vegas, pdf::UniformBox};
    /// let unwritten = |_: &Points, _: &mut [f64]| {};
    /// let err = Vegas::new_batch(1, unwritten, UniformBox::unit(1).unwrap()).run().unwrap_err();
    /// assert!(err.to_string().contains("non-finite"), "{err}");
    /// ```
    pub fn run(&self) -> Result<VectorEstimate> {
        let targets = Targets::new(
            self.f.outputs,
            self.config.tolerance,
            self.f.output_tolerances.as_deref(),
            &self.f.derived_tolerances,
        )?;
        self.run_engine(&self.f, &targets)?.checked()
    }
}
