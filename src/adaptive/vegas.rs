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
//! which tempers it further; here `sigma_h^beta` follows the paper. With stratification off
//! this is classic VEGAS: one hypercube, importance sampling through the grid alone.
//!
//! Every iteration's points are new (the next unused indices of an independent sampler, pass
//! `k` of an extensible one for iteration `k`) and every decision that shapes an iteration
//! (grid, allocation) is made before its points are drawn, so each iteration's estimate is
//! unbiased and its variance estimate honest. Iterations after the warm-up are combined with
//! inverse-variance weights, as `vegas` does; their `chi^2` tells whether they agree. Like
//! `vegas`, this trusts the per-iteration variances: where they are poorly estimated (a
//! discontinuous integrand, whose edge the grid squeezes into a sliver that most iterations
//! miss), the combination can sit several standard errors from the truth.
//!
//! Work is cut into fixed chunks of the iteration's index range, independent of the thread
//! count. Chunks are merged strictly in order (a chunk finished ahead of its turn waits in a
//! reorder buffer, while its worker goes on), so sums, training data and allocations, and
//! hence the result, are bit-identical for any number of threads.

use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};
use std::time::Instant;

use super::vegas_grid::{VegasGrid, check_alpha, check_increments};
use crate::pdf::UniformBox;
use crate::sampler::{Independent, PassKind, Sampler};
use crate::stats::{ErrorBasis, Estimate, StopReason, Tolerance, chi_square_sf};
use crate::{Error, Points, Result};

/// Points drawn from the sampler at once.
const BLOCK: usize = 512;
/// Points per unit of work handed to a thread (and per partial result merged in order), at
/// least: chunks grow with the budget so that an iteration never has more than
/// `MAX_CHUNKS` of them.
const CHUNK: u64 = 1 << 12;
const MAX_CHUNKS: u64 = 1 << 16;
/// Most hypercubes in the stratification: bounds the two per-hypercube arrays (64 MiB).
const MAX_HYPERCUBES: u64 = 1 << 22;
/// Grid increments are capped at one per this many evaluations (as `vegas` does), so that
/// every increment sees some points in each iteration.
const EVALUATIONS_PER_INCREMENT: u64 = 10;
/// Smallest iteration variance used as a weight, so that exact (zero-variance) iterations
/// do not divide by zero (the `TINY` of `vegas`).
const TINY_VARIANCE: f64 = 1e-250;
/// Relative roundoff floor of a hypercube's variance (the `EPSILON` of `vegas`).
const ROUNDOFF: f64 = 10.0 * f64::EPSILON;
/// Keeps the proportional allocation from exceeding its budget through rounding.
const ALLOCATION_SAFETY: f64 = 1.0 - 1e-12;

/// VEGAS and VEGAS+ adaptive Monte Carlo integration over a box.
///
/// Defaults: `10_000` evaluations per iteration, 5 warm-up iterations (they train the grid
/// and the allocation and are then discarded, as `vegas` users do with a separate training
/// call) followed by 10 iterations that are combined, 1000 grid increments per axis at most,
/// `alpha = 0.5`, adaptive stratification on with `beta = 0.75`, independent points with
/// seed 0, all available threads.
///
/// The estimate's standard error is the inverse-variance combination of the iterations'
/// (basis [`ErrorBasis::PerSample`], with `dof` the sum of `n_h - 1` over hypercubes and
/// iterations); `iterations` and `replicates` are the number of iterations combined,
/// `chi2_dof` and `q_value` their agreement (from the second one on), `n` counts the
/// evaluations of the combined iterations and `evaluations` every one spent, warm-up included.
///
/// ```
/// use mcint::{adaptive::Vegas, pdf::UniformBox};
/// // A narrow Gaussian peak in 3 dimensions; its integral over [0,1]^3 is about 0.1^3 pi^(3/2).
/// let f = |x: &[f64]| {
///     let r2: f64 = x.iter().map(|v| (v - 0.5) * (v - 0.5)).sum();
///     (-r2 / 0.01).exp()
/// };
/// let e = Vegas::new(f, UniformBox::unit(3).unwrap()).seed(1).run().unwrap();
/// let exact = 0.001 * std::f64::consts::PI.powf(1.5); // the tails outside the cube are < 1e-20
/// assert!((e.mean - exact).abs() < 5.0 * e.std_error.unwrap());
/// assert_eq!(e.iterations, 10);
/// ```
pub struct Vegas<F> {
    f: F,
    domain: UniformBox,
    sampler: Option<Box<dyn Sampler>>,
    evaluations: u64,
    iterations: u64,
    warmup: u64,
    increments: usize,
    alpha: f64,
    stratified: bool,
    beta: f64,
    tolerance: Option<Tolerance>,
    seed: Option<u64>,
    threads: Option<usize>,
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
        Vegas {
            f,
            domain,
            sampler: None,
            evaluations: 10_000,
            iterations: 10,
            warmup: 5,
            increments: 1000,
            alpha: 0.5,
            stratified: true,
            beta: 0.75,
            tolerance: None,
            seed: None,
            threads: None,
        }
    }

    /// The source of uniform points (default [`Independent`]); its dimension must equal the
    /// domain's. Iteration `k` uses pass `k` of an extensible sampler (a randomized Sobol'
    /// sequence: an independent randomization per iteration) and the next unused indices
    /// of an independent one. Samplers with fixed passes (jittered, Latin hypercube) are
    /// accepted only with stratification off and a multiple of their pass size per
    /// iteration, since a single point of theirs is not uniform on its own; unrandomized
    /// sequences are refused. A seed set with [`seed`](Self::seed) overrides the sampler's.
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox, sampler::{Scramble, Sobol}};
    /// let e = Vegas::new(|x: &[f64]| x[0] + x[1], UniformBox::unit(2).unwrap())
    ///     .sampler(Sobol::new(2, Scramble::Owen, 3).unwrap())
    ///     .run()
    ///     .unwrap();
    /// assert!((e.mean - 1.0).abs() < 5.0 * e.std_error.unwrap());
    /// ```
    pub fn sampler(mut self, sampler: impl Sampler + 'static) -> Self {
        let mut boxed: Box<dyn Sampler> = Box::new(sampler);
        if let Some(seed) = self.seed {
            boxed.reseed(seed);
        }
        self.sampler = Some(boxed);
        self
    }

    /// Evaluations per iteration, `N` (at least 2; default `10_000`). With stratification
    /// an iteration uses at most `N` (the rounding down of the proportional shares usually
    /// leaves a few unused); without, exactly `N`.
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let e = Vegas::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .stratified(false).evaluations_per_iteration(1000).warmup(1).iterations(2)
    ///     .run().unwrap();
    /// // Two measured iterations in the estimate, one warm-up spent before them.
    /// assert_eq!((e.n, e.evaluations), (2000, 3000));
    /// ```
    pub fn evaluations_per_iteration(mut self, n: u64) -> Self {
        self.evaluations = n;
        self
    }

    /// The most iterations combined into the estimate, after the warm-up (at least 1;
    /// default 10). A [`tolerance`](Self::tolerance) may stop the run earlier.
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let e = Vegas::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).iterations(3).run().unwrap();
    /// assert_eq!(e.iterations, 3);
    /// ```
    pub fn iterations(mut self, n: u64) -> Self {
        self.iterations = n;
        self
    }

    /// Warm-up iterations: they adapt the grid and the allocation, and their estimates are
    /// discarded (default 5; 0 keeps every iteration). Their evaluations count in
    /// [`Estimate::evaluations`], not in `n`.
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let e = Vegas::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .stratified(false).evaluations_per_iteration(100).warmup(0).iterations(4)
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

    /// Damping exponent of the grid's adaptation (finite, `>= 0`; default 0.5). Smaller
    /// values adapt more slowly and more stably; 0 freezes the grid (uniform).
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let e = Vegas::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).alpha(0.0).run().unwrap();
    /// assert!((e.mean - 0.5).abs() < 5.0 * e.std_error.unwrap());
    /// ```
    pub fn alpha(mut self, alpha: f64) -> Self {
        self.alpha = alpha;
        self
    }

    /// Adaptive stratification (VEGAS+) on or off (default on). Off gives classic VEGAS:
    /// importance sampling through the grid alone.
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
    /// (in `[0, 1]`; default 0.75; 1 is the theoretical optimum, 0 gives fixed uniform
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

    /// Stops after the first iteration at which the weighted combination meets `tolerance`
    /// (its 95% half-width), or before an iteration that would exceed its evaluation limit
    /// (which must leave room for the warm-up and one iteration), or after the iteration
    /// during which its time limit passed (the warm-up always runs in full). The estimate
    /// says which (`stop`) and whether the tolerance was met (`converged`).
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox, stats::{StopReason, Tolerance}};
    /// let e = Vegas::new(|x: &[f64]| x[0].exp(), UniformBox::unit(1).unwrap())
    ///     .iterations(100)
    ///     .tolerance(Tolerance::relative(1e-4).unwrap())
    ///     .run()
    ///     .unwrap();
    /// assert_eq!((e.stop, e.converged), (StopReason::ToleranceMet, Some(true)));
    /// ```
    pub fn tolerance(mut self, tolerance: Tolerance) -> Self {
        self.tolerance = Some(tolerance);
        self
    }

    /// The seed of the points (the same seed gives the same result).
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let run = |s| Vegas::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).seed(s).run().unwrap();
    /// assert_eq!(run(1), run(1));
    /// assert_ne!(run(1).mean, run(2).mean);
    /// ```
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = Some(seed);
        if let Some(sampler) = self.sampler.as_mut() {
            sampler.reseed(seed);
        }
        self
    }

    /// Worker threads (at least 1; default: all available). The result does not depend on
    /// it.
    ///
    /// ```
    /// use mcint::{adaptive::Vegas, pdf::UniformBox};
    /// let run = |t| Vegas::new(|x: &[f64]| x[0].sin(), UniformBox::unit(1).unwrap())
    ///     .evaluations_per_iteration(50_000).threads(t).run().unwrap();
    /// assert_eq!(run(1), run(3));
    /// ```
    pub fn threads(mut self, threads: usize) -> Self {
        self.threads = Some(threads);
        self
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
        let dims = self.domain.lo().len();
        let default_sampler;
        let sampler: &dyn Sampler = match &self.sampler {
            Some(s) => s.as_ref(),
            None => {
                default_sampler = Independent::new(dims, self.seed.unwrap_or(0))?;
                &default_sampler
            }
        };
        let settings = self.settings(sampler)?;
        let strata = Strata::new(
            dims,
            self.evaluations,
            self.stratified,
            self.beta,
            settings.increments,
            self.increments,
        );
        let mut grid = VegasGrid::with_increments(&self.domain, &strata.increments)?;
        let allocating = strata.allocation_budget.is_some();
        let per_cube = if allocating { strata.cubes as usize } else { 0 };
        // Equal sigma_h^beta before anything is known: the first iteration is uniform.
        let mut sigf = vec![1.0; per_cube];
        let mut next_sigf = vec![0.0; per_cube];
        let mut sum_sigf = per_cube as f64;
        let mut training = vec![0.0; 2 * grid.cells()];
        let mut combination = Combination::default();
        let mut spent: u64 = 0;
        let mut measured_evaluations: u64 = 0;
        let mut stop = StopReason::Budget;
        let started = Instant::now();
        let total_iterations = self.warmup + self.iterations;

        for k in 0..total_iterations {
            let measured = k >= self.warmup;
            let scale = strata
                .allocation_budget
                .map(|budget| budget / sum_sigf * ALLOCATION_SAFETY);
            let allocation = Allocation {
                min: strata.min_per_cube,
                scale,
                sigf: &sigf,
            };
            let (chunks, total) = plan_chunks(&strata, &allocation);
            if measured
                && combination.count() > 0
                && let Some(t) = &self.tolerance
                && spent + total > t.evaluation_limit()
            {
                stop = StopReason::MaxEvaluations;
                break;
            }
            let base = match sampler.passes() {
                PassKind::Extensible { max } => k * max,
                _ => spent,
            };
            training.fill(0.0);
            let pass = Pass {
                f: &self.f,
                sampler,
                grid: &grid,
                strata: &strata,
                allocation,
                chunks: &chunks,
                total,
                base,
                beta: self.beta,
                allocating,
            };
            let totals = run_pass(&pass, settings.threads, &mut training, &mut next_sigf)?;
            if totals.non_finite > 0 {
                let (index, value) = totals.first_non_finite.unwrap_or((0, f64::NAN));
                let mut point = vec![0.0; dims];
                sampler.point(base + index, &mut point)?;
                return Err(Error::NonFiniteContribution {
                    count: totals.non_finite,
                    first_index: index,
                    first_replicate: k,
                    first_value: value,
                    first_point: point,
                });
            }
            spent += total;
            grid.adapt_to(&training, self.alpha);
            if allocating {
                std::mem::swap(&mut sigf, &mut next_sigf);
                sum_sigf = sigf.iter().sum();
                if !(sum_sigf > 0.0 && sum_sigf.is_finite()) {
                    // No variance anywhere (a constant integrand): back to uniform.
                    sigf.fill(1.0);
                    sum_sigf = per_cube as f64;
                }
            }
            if !measured {
                continue;
            }
            combination.add(totals.mean, totals.variance, total - strata.cubes);
            measured_evaluations += total;
            if let Some(t) = &self.tolerance {
                if t.is_met(&combination.estimate(measured_evaluations, spent, stop, None)) {
                    stop = StopReason::ToleranceMet;
                    break;
                }
                if k + 1 < total_iterations && t.time().is_some_and(|l| started.elapsed() >= l) {
                    stop = StopReason::TimeLimit;
                    break;
                }
            }
        }
        let converged = self.tolerance.map(|_| stop == StopReason::ToleranceMet);
        Ok(combination.estimate(measured_evaluations, spent, stop, converged))
    }

    /// Checks every setting against each other and the sampler.
    fn settings(&self, sampler: &dyn Sampler) -> Result<Settings> {
        let dims = self.domain.lo().len();
        let n = self.evaluations;
        if n < 2 {
            return Err(Error::invalid(
                "evaluations_per_iteration",
                n,
                "at least 2 (every hypercube needs two evaluations for its variance)",
            ));
        }
        if self.iterations == 0 {
            return Err(Error::invalid(
                "iterations",
                0,
                "at least 1 iteration after the warm-up",
            ));
        }
        check_increments(self.increments)?;
        check_alpha(self.alpha)?;
        if !(0.0..=1.0).contains(&self.beta) {
            return Err(Error::invalid(
                "beta",
                self.beta,
                "a damping exponent in [0, 1] (VEGAS+ uses 0.75)",
            ));
        }
        let threads = crate::threads::resolve(self.threads)?;
        if sampler.dims() != dims {
            return Err(Error::DimensionMismatch {
                what: "sampler (the domain's dimensions)",
                expected: dims,
                found: sampler.dims(),
            });
        }
        if !sampler.is_randomized() {
            return Err(Error::invalid(
                "sampler",
                sampler.name(),
                "a randomized sampler (every iteration needs new points; choose a scramble)",
            ));
        }
        let total_iterations =
            self.warmup
                .checked_add(self.iterations)
                .ok_or(Error::IndexOutOfRange {
                    what: "warm-up plus iterations",
                    limit: u64::MAX,
                })?;
        let stride = match sampler.passes() {
            PassKind::Independent => n,
            PassKind::Extensible { max } => {
                if n > max {
                    return Err(Error::invalid(
                        "evaluations_per_iteration",
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
                        "evaluations_per_iteration",
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
            return Err(Error::IndexOutOfRange {
                what: "sample index of the last iteration",
                limit: u64::MAX,
            });
        }
        if let Some(t) = &self.tolerance {
            let needed = (self.warmup + 1).saturating_mul(n);
            if t.evaluation_limit() < needed {
                return Err(Error::invalid(
                    "max_evals",
                    t.evaluation_limit(),
                    format!(
                        "at least (warmup + 1) x evaluations_per_iteration = {needed}, so that \
                         one iteration after the warm-up fits"
                    ),
                ));
            }
        }
        let increments = (self.increments as u64)
            .min(n / EVALUATIONS_PER_INCREMENT)
            .max(2) as usize;
        Ok(Settings {
            increments,
            threads,
        })
    }
}

/// Settings derived and checked once per run.
struct Settings {
    increments: usize,
    threads: usize,
}

/// The hypercubes of `y`-space, the fixed part of the allocation, and the grid's increments.
struct Strata {
    /// Strata per axis, `s_d`.
    per_axis: Vec<u64>,
    /// `1 / s_d`.
    inverse: Vec<f64>,
    /// `prod_d s_d`.
    cubes: u64,
    /// Volume of one hypercube in `y`-space, `1 / cubes`.
    cube_volume: f64,
    /// Evaluations every hypercube gets whatever its variance.
    min_per_cube: u64,
    /// Evaluations shared in proportion to `sigma_h^beta` (VEGAS+ only).
    allocation_budget: Option<f64>,
    /// Grid increments per axis.
    increments: Vec<usize>,
    /// Points per chunk of work.
    chunk: u64,
}

impl Strata {
    /// The rules of the Python `vegas` package (version 6). With adaptive allocation a
    /// quarter of the `N` evaluations is spread evenly with at least two per hypercube (so
    /// at most `N / 8` hypercubes) and three quarters follow `sigma_h^beta`; with a fixed
    /// uniform allocation (`beta = 0`), up to `N / 2` hypercubes of two points or more.
    /// Strata are as equal as possible across axes (one more on the first axes where that
    /// still fits), so high dimensions cut some axes in two and leave the rest whole. Each
    /// axis then gets a multiple of its strata as increments (`max_increments` rounded
    /// down), or one increment per stratum when strata outnumber increments, so that no
    /// stratum straddles a jump of the Jacobian; past `increments_cap` strata the strata
    /// are rounded down to a multiple of the increments instead.
    fn new(
        dims: usize,
        evaluations: u64,
        stratified: bool,
        beta: f64,
        max_increments: usize,
        increments_cap: usize,
    ) -> Strata {
        let adaptive = stratified && beta > 0.0;
        let even = if adaptive {
            evaluations / 4
        } else {
            evaluations
        };
        let max_cubes = if stratified {
            (even / 2).clamp(1, MAX_HYPERCUBES)
        } else {
            1
        };
        let mut base = (max_cubes as f64).powf(1.0 / dims as f64).floor().max(1.0) as u64;
        while base > 1 && product(base, dims) > max_cubes {
            base -= 1;
        }
        while product(base + 1, dims) <= max_cubes {
            base += 1;
        }
        let mut per_axis = vec![base; dims];
        let mut cubes = product(base, dims);
        for s in per_axis.iter_mut() {
            let more = cubes / base * (base + 1);
            if more > max_cubes {
                break;
            }
            *s = base + 1;
            cubes = more;
        }
        let ni = max_increments as u64;
        let increments = per_axis
            .iter_mut()
            .map(|s| {
                if ni >= *s {
                    (ni / *s * *s) as usize
                } else if *s <= increments_cap as u64 {
                    *s as usize
                } else {
                    *s = *s / ni * ni;
                    max_increments
                }
            })
            .collect();
        let cubes: u64 = per_axis.iter().product();
        let min_per_cube = if cubes == 1 {
            evaluations
        } else {
            (even / cubes).max(2)
        };
        Strata {
            inverse: per_axis.iter().map(|&s| 1.0 / s as f64).collect(),
            per_axis,
            cubes,
            cube_volume: 1.0 / cubes as f64,
            min_per_cube,
            allocation_budget: (adaptive && cubes > 1)
                .then_some((evaluations - evaluations / 4) as f64),
            increments,
            chunk: evaluations.div_ceil(MAX_CHUNKS).max(CHUNK),
        }
    }
}

/// `base^dims`, saturating.
fn product(base: u64, dims: usize) -> u64 {
    (0..dims).fold(1u64, |p, _| p.saturating_mul(base))
}

/// How many points each hypercube gets in one iteration.
#[derive(Clone, Copy)]
struct Allocation<'a> {
    min: u64,
    /// Points per unit of `sigma_h^beta` added to `min`; `None` for the uniform allocation.
    scale: Option<f64>,
    /// `sigma_h^beta` per hypercube, from the previous iteration.
    sigf: &'a [f64],
}

impl Allocation<'_> {
    #[inline]
    fn evaluations(&self, cube: u64) -> u64 {
        match self.scale {
            // The float-to-int cast saturates (and sends NaN to 0).
            Some(scale) => self.min + (self.sigf[cube as usize] * scale) as u64,
            None => self.min,
        }
    }
}

/// Where a chunk starts: its first index, the hypercube holding it and the offset within.
#[derive(Clone, Copy)]
struct ChunkStart {
    index: u64,
    cube: u64,
    offset: u64,
}

/// Cuts the iteration's index range into chunks of `strata.chunk` points; returns them and the
/// iteration's number of points.
fn plan_chunks(strata: &Strata, allocation: &Allocation) -> (Vec<ChunkStart>, u64) {
    let mut chunks = Vec::new();
    let mut total = 0u64;
    let mut boundary = 0u64;
    for cube in 0..strata.cubes {
        let n = allocation.evaluations(cube);
        while boundary < total + n {
            chunks.push(ChunkStart {
                index: boundary,
                cube,
                offset: boundary - total,
            });
            boundary += strata.chunk;
        }
        total += n;
    }
    (chunks, total)
}

/// Everything one iteration's workers share.
struct Pass<'a, F> {
    f: &'a F,
    sampler: &'a dyn Sampler,
    grid: &'a VegasGrid,
    strata: &'a Strata,
    allocation: Allocation<'a>,
    chunks: &'a [ChunkStart],
    total: u64,
    /// Sampler index of the iteration's first point.
    base: u64,
    beta: f64,
    /// Whether `sigma_h^beta` is recorded for the next allocation (VEGAS+).
    allocating: bool,
}

/// Count, mean and sum of squared deviations, merged exactly (Chan, Golub & LeVeque 1979).
#[derive(Clone, Copy, Default, Debug)]
struct Moments {
    n: u64,
    mean: f64,
    m2: f64,
}

impl Moments {
    fn merge(&mut self, other: &Moments) {
        if other.n == 0 {
            return;
        }
        if self.n == 0 {
            *self = *other;
            return;
        }
        let (na, nb) = (self.n as f64, other.n as f64);
        let n = na + nb;
        let delta = other.mean - self.mean;
        self.mean += delta * (nb / n);
        self.m2 += other.m2 + delta * delta * (na * nb / n);
        self.n += other.n;
    }
}

/// Running sums shifted by the first value, which keep the variance accurate without a
/// division per point.
#[derive(Clone, Copy, Default)]
struct ShiftedSums {
    n: u64,
    shift: f64,
    s1: f64,
    s2: f64,
}

impl ShiftedSums {
    #[inline]
    fn push(&mut self, v: f64) {
        if self.n == 0 {
            self.shift = v;
        }
        let d = v - self.shift;
        self.n += 1;
        self.s1 += d;
        self.s2 += d * d;
    }

    fn moments(&self) -> Moments {
        if self.n == 0 {
            return Moments::default();
        }
        let n = self.n as f64;
        Moments {
            n: self.n,
            mean: self.shift + self.s1 / n,
            m2: (self.s2 - self.s1 * self.s1 / n).max(0.0),
        }
    }
}

/// One hypercube's contribution to the estimate and its variance, and `sigma_h^beta`.
fn cube_result(m: &Moments, cube_volume: f64, beta: f64) -> (f64, f64, f64) {
    if m.n == 0 {
        return (0.0, 0.0, 0.0);
    }
    let n = m.n as f64;
    let s2 = if m.n > 1 { m.m2 / (n - 1.0) } else { 0.0 };
    let v2 = cube_volume * cube_volume;
    let sigma2 = v2 * s2;
    let variance = (sigma2 / n).max(ROUNDOFF * v2 * (m.mean * m.mean + s2) / n);
    (cube_volume * m.mean, variance, sigma2.powf(0.5 * beta))
}

/// The iteration's sums, built chunk by chunk in order.
#[derive(Default)]
struct Totals {
    mean: f64,
    variance: f64,
    /// The hypercube that straddles the last merged chunk's end.
    open: Moments,
    non_finite: u64,
    /// Index within the iteration and value of the first non-finite `J f`.
    first_non_finite: Option<(u64, f64)>,
}

/// State shared by the workers of one iteration, behind a mutex.
struct Shared<'a> {
    /// The next chunk to merge.
    next: usize,
    /// Chunks finished ahead of their turn.
    pending: BTreeMap<usize, ChunkOutput>,
    /// Merged outputs, ready for reuse.
    pool: Vec<ChunkOutput>,
    error: Option<Error>,
    totals: Totals,
    training: &'a mut [f64],
    next_sigf: &'a mut [f64],
}

impl Shared<'_> {
    /// Adds one chunk's results; chunks arrive in index order.
    fn merge<F>(&mut self, out: &ChunkOutput, pass: &Pass<F>) {
        let t = &mut self.totals;
        if let Some(head) = &out.head {
            t.open.merge(head);
            if out.head_ends {
                let (mean, variance, sigf) =
                    cube_result(&t.open, pass.strata.cube_volume, pass.beta);
                t.mean += mean;
                t.variance += variance;
                if let Some(slot) = self.next_sigf.get_mut(out.start_cube as usize) {
                    *slot = sigf;
                }
                t.open = Moments::default();
            }
        }
        t.mean += out.closed_mean;
        t.variance += out.closed_variance;
        if !self.next_sigf.is_empty() {
            let first = out.first_closed as usize;
            self.next_sigf[first..first + out.closed_sigf.len()].copy_from_slice(&out.closed_sigf);
        }
        if let Some(tail) = out.tail {
            t.open = tail;
        }
        for (sum, &part) in self.training.iter_mut().zip(&out.training) {
            *sum += part;
        }
        t.non_finite += out.non_finite;
        if t.first_non_finite.is_none() {
            t.first_non_finite = out.first_non_finite;
        }
    }

    /// Files a finished chunk and merges every chunk whose turn has come; returns an output
    /// buffer to reuse, if one is free.
    fn deliver<F>(
        &mut self,
        chunk: usize,
        out: ChunkOutput,
        pass: &Pass<F>,
    ) -> Option<ChunkOutput> {
        self.pending.insert(chunk, out);
        while let Some(ready) = self.pending.remove(&self.next) {
            self.merge(&ready, pass);
            self.next += 1;
            self.pool.push(ready);
        }
        self.pool.pop()
    }
}

/// Locks, recovering the state if a thread panicked while holding the lock (the run then
/// fails anyway).
fn lock<'a, 'b>(shared: &'a Mutex<Shared<'b>>) -> MutexGuard<'a, Shared<'b>> {
    shared.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Tells the other workers to stop taking chunks if this one unwinds.
struct FailOnPanic<'a>(&'a AtomicBool);

impl Drop for FailOnPanic<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.store(true, Ordering::Relaxed);
        }
    }
}

/// Runs one iteration on `threads` workers; fills `training` and `next_sigf`.
fn run_pass<F: Fn(&[f64]) -> f64 + Sync>(
    pass: &Pass<F>,
    threads: usize,
    training: &mut [f64],
    next_sigf: &mut [f64],
) -> Result<Totals> {
    let chunks = pass.chunks.len();
    let shared = Mutex::new(Shared {
        next: 0,
        pending: BTreeMap::new(),
        pool: Vec::new(),
        error: None,
        totals: Totals::default(),
        training,
        next_sigf,
    });
    let failed = AtomicBool::new(false);
    let counter = AtomicUsize::new(0);
    let work = || worker(pass, &shared, &failed, &counter);
    let workers = threads.min(chunks).max(1);
    let all_joined = if workers == 1 {
        catch_unwind(AssertUnwindSafe(work)).is_ok()
    } else {
        std::thread::scope(|scope| {
            let handles: Vec<_> = (0..workers).map(|_| scope.spawn(work)).collect();
            // Join every handle before judging, so no panic goes unobserved.
            let joined: Vec<bool> = handles.into_iter().map(|h| h.join().is_ok()).collect();
            joined.into_iter().all(|ok| ok)
        })
    };
    let shared = shared.into_inner().unwrap_or_else(PoisonError::into_inner);
    if let Some(e) = shared.error {
        return Err(e);
    }
    if !all_joined || shared.next != chunks {
        return Err(crate::threads::worker_panicked());
    }
    Ok(shared.totals)
}

/// Takes chunks until none is left (or a worker failed), handing each to the merge.
fn worker<F: Fn(&[f64]) -> f64 + Sync>(
    pass: &Pass<F>,
    shared: &Mutex<Shared<'_>>,
    failed: &AtomicBool,
    counter: &AtomicUsize,
) {
    let _guard = FailOnPanic(failed);
    let fail = |e: Error| {
        failed.store(true, Ordering::Relaxed);
        lock(shared).error.get_or_insert(e);
    };
    let mut scratch = match Scratch::new(pass) {
        Ok(scratch) => scratch,
        Err(e) => return fail(e),
    };
    let mut out = ChunkOutput::new(pass);
    loop {
        let chunk = counter.fetch_add(1, Ordering::Relaxed);
        if chunk >= pass.chunks.len() || failed.load(Ordering::Relaxed) {
            return;
        }
        if let Err(e) = scratch.run_chunk(pass, chunk, &mut out) {
            return fail(e);
        }
        let reuse = lock(shared).deliver(chunk, out, pass);
        out = reuse.unwrap_or_else(|| ChunkOutput::new(pass));
    }
}

/// What one chunk contributes, merged in chunk order.
struct ChunkOutput {
    /// Training data of the grid, as [`VegasGrid`] lays it out.
    training: Vec<f64>,
    start_cube: u64,
    /// The piece of a hypercube begun in an earlier chunk, and whether it ends here.
    head: Option<Moments>,
    head_ends: bool,
    /// Hypercubes begun and ended in this chunk, from `first_closed` on.
    first_closed: u64,
    closed_mean: f64,
    closed_variance: f64,
    closed_sigf: Vec<f64>,
    /// The hypercube begun here that continues in the next chunk.
    tail: Option<Moments>,
    non_finite: u64,
    first_non_finite: Option<(u64, f64)>,
}

impl ChunkOutput {
    fn new<F>(pass: &Pass<F>) -> ChunkOutput {
        ChunkOutput {
            training: vec![0.0; 2 * pass.grid.cells()],
            start_cube: 0,
            head: None,
            head_ends: false,
            first_closed: 0,
            closed_mean: 0.0,
            closed_variance: 0.0,
            closed_sigf: Vec::new(),
            tail: None,
            non_finite: 0,
            first_non_finite: None,
        }
    }

    /// Clears the results for chunk `start`.
    fn reset(&mut self, start: &ChunkStart) {
        self.training.fill(0.0);
        self.start_cube = start.cube;
        self.head = None;
        self.head_ends = false;
        self.first_closed = if start.offset > 0 {
            start.cube + 1
        } else {
            start.cube
        };
        self.closed_mean = 0.0;
        self.closed_variance = 0.0;
        self.closed_sigf.clear();
        self.tail = None;
        self.non_finite = 0;
        self.first_non_finite = None;
    }

    /// Records a hypercube that ends in this chunk.
    fn close_cube<F>(&mut self, sums: &ShiftedSums, continued: bool, pass: &Pass<F>) {
        let moments = sums.moments();
        if continued {
            self.head = Some(moments);
            self.head_ends = true;
            return;
        }
        let (mean, variance, sigf) = cube_result(&moments, pass.strata.cube_volume, pass.beta);
        self.closed_mean += mean;
        self.closed_variance += variance;
        if pass.allocating {
            self.closed_sigf.push(sigf);
        }
    }
}

/// Per-worker buffers, allocated once per iteration.
struct Scratch {
    points: Points,
    /// The block's points, one row per point.
    rows: Vec<f64>,
    x: Vec<f64>,
    cells: Vec<usize>,
    /// Coordinates of the current hypercube, as integers and as floats.
    coords: Vec<u64>,
    coords_f: Vec<f64>,
}

impl Scratch {
    fn new<F>(pass: &Pass<F>) -> Result<Scratch> {
        let dims = pass.grid.dims();
        Ok(Scratch {
            points: Points::new(dims, BLOCK)?,
            rows: vec![0.0; dims * BLOCK],
            x: vec![0.0; dims],
            cells: vec![0; dims],
            coords: vec![0; dims],
            coords_f: vec![0.0; dims],
        })
    }

    /// Sets the coordinates of hypercube `cube` (axis 0 varies fastest).
    fn set_coords(&mut self, mut cube: u64, strata: &Strata) {
        for ((c, cf), &s) in self
            .coords
            .iter_mut()
            .zip(self.coords_f.iter_mut())
            .zip(&strata.per_axis)
        {
            *c = cube % s;
            *cf = *c as f64;
            cube /= s;
        }
    }

    /// Steps to the next hypercube, like an odometer.
    fn next_coords(&mut self, strata: &Strata) {
        for ((c, cf), &s) in self
            .coords
            .iter_mut()
            .zip(self.coords_f.iter_mut())
            .zip(&strata.per_axis)
        {
            *c += 1;
            if *c < s {
                *cf = *c as f64;
                return;
            }
            *c = 0;
            *cf = 0.0;
        }
    }

    /// Evaluates chunk `chunk` into `out`.
    fn run_chunk<F: Fn(&[f64]) -> f64>(
        &mut self,
        pass: &Pass<F>,
        chunk: usize,
        out: &mut ChunkOutput,
    ) -> Result<()> {
        let start = pass.chunks[chunk];
        let end = pass.chunks.get(chunk + 1).map_or(pass.total, |c| c.index);
        let dims = self.x.len();
        let grid = pass.grid;
        let strata = pass.strata;
        out.reset(&start);

        let mut cube = start.cube;
        self.set_coords(cube, strata);
        let mut cube_n = pass.allocation.evaluations(cube);
        let mut remaining = cube_n - start.offset;
        let mut continued = start.offset > 0;
        // Each point's share of y-space volume weights its training data, so that the
        // per-increment averages of (J f)^2 are consistent under any allocation.
        let mut share = strata.cube_volume / cube_n as f64;
        let mut sums = ShiftedSums::default();

        let mut index = start.index;
        while index < end {
            let len = (end - index).min(BLOCK as u64) as usize;
            self.points.set_len(len);
            pass.sampler.fill(pass.base + index, &mut self.points)?;
            for d in 0..dims {
                for (j, &u) in self.points.column(d).iter().enumerate() {
                    self.rows[j * dims + d] = u;
                }
            }
            for j in 0..len {
                if remaining == 0 {
                    out.close_cube(&sums, continued, pass);
                    continued = false;
                    sums = ShiftedSums::default();
                    cube += 1;
                    self.next_coords(strata);
                    cube_n = pass.allocation.evaluations(cube);
                    remaining = cube_n;
                    share = strata.cube_volume / cube_n as f64;
                }
                remaining -= 1;
                let u = &self.rows[j * dims..(j + 1) * dims];
                let mut jacobian = 1.0;
                for (d, &u) in u.iter().enumerate() {
                    let y = (self.coords_f[d] + u) * strata.inverse[d];
                    let (x, factor, cell) = grid.map_axis(d, y);
                    self.x[d] = x;
                    self.cells[d] = cell;
                    jacobian *= factor;
                }
                let v = jacobian * (pass.f)(&self.x);
                if !v.is_finite() {
                    out.non_finite += 1;
                    out.first_non_finite.get_or_insert((index + j as u64, v));
                    continue;
                }
                sums.push(v);
                let weighted = v * v * share;
                for &cell in &self.cells {
                    out.training[2 * cell] += weighted;
                    out.training[2 * cell + 1] += share;
                }
            }
            index += len as u64;
        }
        if remaining == 0 {
            out.close_cube(&sums, continued, pass);
        } else if continued {
            out.head = Some(sums.moments());
            out.head_ends = false;
        } else {
            out.tail = Some(sums.moments());
        }
        Ok(())
    }
}

/// Inverse-variance weighted combination of the iterations after the warm-up.
#[derive(Default)]
struct Combination {
    /// Each iteration's estimate and variance.
    results: Vec<(f64, f64)>,
    sum_weights: f64,
    sum_weighted: f64,
    dof: f64,
}

impl Combination {
    fn count(&self) -> u64 {
        self.results.len() as u64
    }

    fn add(&mut self, mean: f64, variance: f64, dof: u64) {
        let variance = variance.max(TINY_VARIANCE);
        self.results.push((mean, variance));
        self.sum_weights += 1.0 / variance;
        self.sum_weighted += mean / variance;
        self.dof += dof.max(1) as f64;
    }

    /// The combined estimate of `n` measured evaluations, out of `evaluations` spent.
    fn estimate(
        &self,
        n: u64,
        evaluations: u64,
        stop: StopReason,
        converged: Option<bool>,
    ) -> Estimate {
        let mean = self.sum_weighted / self.sum_weights;
        let m = self.count();
        let (chi2_dof, q_value) = if m > 1 {
            let chi2: f64 = self
                .results
                .iter()
                .map(|(v, var)| (v - mean) * (v - mean) / var)
                .sum();
            let dof = (m - 1) as f64;
            (Some(chi2 / dof), Some(chi_square_sf(chi2, dof)))
        } else {
            (None, None)
        };
        Estimate {
            mean,
            std_error: Some((1.0 / self.sum_weights).sqrt()),
            dof: Some(self.dof),
            basis: ErrorBasis::PerSample,
            n,
            evaluations,
            replicates: m,
            non_finite: 0,
            stop,
            converged,
            iterations: m,
            chi2_dof,
            q_value,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strata_follow_the_vegas_rule() {
        // N = 10^5 in 5 dimensions: at most 12_500 hypercubes; 6^5 = 7776, and 7^3 * 6^2 =
        // 12348 still fits, 7^4 * 6 = 14406 does not. Increments: multiples of the strata.
        let s = Strata::new(5, 100_000, true, 0.75, 1000, 1000);
        assert_eq!(s.per_axis, [7, 7, 7, 6, 6]);
        assert_eq!(s.cubes, 12348);
        assert_eq!(s.min_per_cube, 2);
        assert_eq!(s.allocation_budget, Some(75_000.0));
        assert_eq!(s.increments, [994, 994, 994, 996, 996]);
        // beta = 0: fixed stratification with two points per hypercube.
        let s = Strata::new(2, 1000, true, 0.0, 100, 1000);
        assert_eq!(
            (s.cubes, s.min_per_cube, s.allocation_budget),
            (484, 2, None)
        );
        assert_eq!(s.increments, [88, 88]);
        // High dimension: some axes cut in two, the rest whole.
        let s = Strata::new(20, 1000, true, 0.75, 100, 1000);
        assert_eq!((s.cubes, s.min_per_cube), (64, 3));
        assert_eq!(s.per_axis.iter().filter(|&&a| a == 2).count(), 6);
        // One dimension: 1250 strata exceed the 1000 increments and are cut to 1000.
        let s = Strata::new(1, 10_000, true, 0.75, 1000, 1000);
        assert_eq!((s.cubes, s.min_per_cube, s.increments[0]), (1000, 2, 1000));
        // Off: one hypercube holding every point.
        let s = Strata::new(3, 1000, false, 0.75, 100, 1000);
        assert_eq!(
            (s.cubes, s.min_per_cube, s.allocation_budget),
            (1, 1000, None)
        );
        assert_eq!(s.increments, [100; 3]);
    }

    #[test]
    fn allocation_never_exceeds_the_budget() {
        let s = Strata::new(2, 1001, true, 0.75, 100, 1000);
        assert_eq!((s.cubes, s.min_per_cube), (121, 2));
        let sigf: Vec<f64> = (0..s.cubes)
            .map(|h| ((h * 7919) % 13) as f64 + 0.1)
            .collect();
        let sum: f64 = sigf.iter().sum();
        let allocation = Allocation {
            min: s.min_per_cube,
            scale: Some(s.allocation_budget.unwrap() / sum * ALLOCATION_SAFETY),
            sigf: &sigf,
        };
        let (chunks, total) = plan_chunks(&s, &allocation);
        // Each floor loses less than one point.
        assert!((1001 - s.cubes..=1001).contains(&total), "{total}");
        assert_eq!(chunks.len(), 1);
        // All the variance in one hypercube: it gets the 751 allocated points (less the
        // safety margin's rounding down) on top of its two.
        let mut sigf = vec![0.0; s.cubes as usize];
        sigf[17] = 3.0;
        let allocation = Allocation {
            min: s.min_per_cube,
            scale: Some(s.allocation_budget.unwrap() / 3.0 * ALLOCATION_SAFETY),
            sigf: &sigf,
        };
        assert_eq!(allocation.evaluations(17), 752);
        assert_eq!(plan_chunks(&s, &allocation).1, 752 + 120 * 2);
    }

    #[test]
    fn shifted_sums_and_merges_agree_with_two_pass_moments() {
        let values: Vec<f64> = (0..100).map(|i| 1e6 + ((i * 37) % 11) as f64).collect();
        let mean = values.iter().sum::<f64>() / 100.0;
        let m2: f64 = values.iter().map(|v| (v - mean) * (v - mean)).sum();
        let mut left = ShiftedSums::default();
        let mut right = ShiftedSums::default();
        values[..30].iter().for_each(|&v| left.push(v));
        values[30..].iter().for_each(|&v| right.push(v));
        let mut merged = left.moments();
        merged.merge(&right.moments());
        assert_eq!(merged.n, 100);
        assert!((merged.mean - mean).abs() < 1e-9);
        assert!((merged.m2 - m2).abs() < 1e-9 * m2);
    }
}
