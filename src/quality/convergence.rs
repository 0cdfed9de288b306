//! Convergence studies: how fast a sampler's error falls with the number of points.
//!
//! At each point count `N` of a list, `R` independent randomizations ("passes") of the sampler
//! each give an estimate `Q̂ = (1/N) Σ f(u_i)` of an integrand with a known integral `I`. The
//! root mean squared error over the passes, `RMSE_N = sqrt((1/R) Σ (Q̂ - I)²)`, is what the
//! papers plot against `N` on log-log axes, and the slope of that plot is the sampler's rate on
//! that integrand: `-1/2` for independent points, `-1` for jittered points on smooth
//! integrands, `-3/2` for scrambled nets on smooth integrands, `-3/4` for stratified points
//! on a disk.
//!
//! # Uncertainties and the fit
//!
//! * Each RMSE carries a standard error by the delta method: the mean squared error is a mean
//!   of `R` independent squared errors, so its standard error is `s(e²)/√R` (the sample
//!   standard deviation of the squared errors), and `RMSE = √MSE` has standard error
//!   `s(e²)/(2 √R RMSE)`. The log of the RMSE then has standard error
//!   `σ_k = s(e²)/(2 √R MSE)`, which is about `1/√(2R)` when the errors are normal.
//! * The slope and intercept come from an ordinary (unweighted) least-squares fit of
//!   `ln RMSE` on `ln N`. Weighting by `1/σ_k²` would be the textbook choice, but each `σ_k`
//!   is estimated from the same passes as its RMSE, and a point whose spread happens to be
//!   underestimated also tends to have its RMSE underestimated, so weights estimated this
//!   way bias the slope; since `σ_k` is nearly the same at every `N` for near-normal errors,
//!   equal weights lose little.
//! * The slope's standard error propagates the `σ_k` through the fit,
//!   `√(Σ c_k² σ_k²)` with `c_k = (x_k - x̄)/Σ(x_j - x̄)²` and `x = ln N` (every point count uses
//!   its own independent passes, so the `σ_k` are independent). That is the error from
//!   sampling noise alone; a power law that does not fit (pre-asymptotic curvature, or
//!   oscillation of the error with `N`) shows as residuals larger than the `σ_k`, measured
//!   by `χ² = Σ r_k² / σ_k²` on `K - 2` degrees of freedom. When `χ²/(K-2) > 1` the standard
//!   error is multiplied by `√(χ²/(K-2))` (the Birge ratio, as the Particle Data Group scales
//!   inconsistent fits), so that a poor fit reports a correspondingly wide slope.
//!
//! Both uncertainties are large-`R` approximations; with `R` of 32 or more they are good to a
//! few tens of percent, which is what a `4σ` test needs.
//!
//! # Determinism
//!
//! Pass `r` at point count `N` uses the sampler that the factory builds for `N` with a seed
//! hashed from `(seed, N, r)`, and takes its points `0..N`. The result depends only on the
//! seed, the point counts and the number of passes: not on the thread count, and not on the
//! other point counts in the list.

use std::fmt;

use crate::engine::{ChunkJob, Limits, NonFinite, RunConfig, run_settings};
use crate::error::{Error, Result};
use crate::hash::hash_words;
use crate::points::Points;
use crate::sampler::{PassKind, Sampler};
use crate::testfns::TestFunction;

/// Passes per point count when none is given.
const DEFAULT_PASSES: u64 = 32;
/// The most passes per point count: the error of every pass is kept in memory.
const MAX_PASSES: u64 = 1 << 20;
/// Points filled and evaluated at a time.
const BLOCK: usize = 1024;
/// Salt separating the pass seeds from other uses of the seed.
const SALT: u64 = 0x636f_6e76_6572_6765;

/// The error measured at one point count.
///
/// ```
/// use mcint::quality::Convergence;
/// use mcint::sampler::Independent;
/// use mcint::testfns::GraphicsIntegrand;
/// let study = Convergence::new(&GraphicsIntegrand::Bilinear, &[64, 256])
///     .run(|_n, seed| Independent::new(2, seed))?;
/// let p = study.points[0];
/// assert_eq!(p.n, 64);
/// assert!(p.rmse > 0.0 && p.rmse_std_error > 0.0 && p.rmse_std_error < p.rmse);
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConvergencePoint {
    /// Points per estimate.
    pub n: u64,
    /// Root mean squared error of the estimates over the passes.
    pub rmse: f64,
    /// Standard error of `rmse` (delta method: `s(e²) / (2 √R rmse)`).
    pub rmse_std_error: f64,
    /// Mean signed error over the passes (near zero for an unbiased sampler).
    pub mean_error: f64,
    /// Standard error of `mean_error`: `s(e) / √R`.
    pub mean_error_std_error: f64,
}

/// A convergence study's measurements and the power law fitted to them,
/// `RMSE ≈ exp(intercept) · N^slope`.
///
/// ```
/// use mcint::quality::Convergence;
/// use mcint::sampler::Independent;
/// use mcint::testfns::GraphicsIntegrand;
/// let study = Convergence::new(&GraphicsIntegrand::Gaussian, &[64, 256, 1024, 4096])
///     .passes(64)
///     .seed(3)
///     .run(|_n, seed| Independent::new(2, seed))?;
/// // Independent points: RMSE ~ N^-1/2.
/// assert!((study.slope + 0.5).abs() < 4.0 * study.slope_std_error);
/// assert_eq!(study.sampler, "independent");
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ConvergenceStudy {
    /// The integrand's name.
    pub integrand: String,
    /// The sampler's name.
    pub sampler: String,
    /// Independent passes per point count (`R`).
    pub passes: u64,
    /// One entry per point count, in increasing `n`.
    pub points: Vec<ConvergencePoint>,
    /// Fitted slope of `ln RMSE` against `ln N`: the convergence rate.
    pub slope: f64,
    /// Standard error of the slope: the propagated sampling error, inflated by
    /// `√(χ²/dof)` when the points scatter more than their errors allow (see the module
    /// documentation).
    pub slope_std_error: f64,
    /// The slope's standard error from sampling noise alone, before any inflation.
    pub slope_sampling_error: f64,
    /// Fitted intercept: `ln RMSE` extrapolated to `N = 1`.
    pub intercept: f64,
    /// `χ²` of the fit per degree of freedom (`K - 2` for `K` point counts); `None` with only
    /// two point counts. Near 1 when a power law describes the points within their errors.
    pub chi2_per_dof: Option<f64>,
}

impl ConvergenceStudy {
    /// The fitted power law's RMSE at `n` points: `exp(intercept) · n^slope`.
    ///
    /// ```
    /// use mcint::quality::Convergence;
    /// use mcint::sampler::Independent;
    /// use mcint::testfns::GraphicsIntegrand;
    /// let study = Convergence::new(&GraphicsIntegrand::Disk, &[100, 400, 1600])
    ///     .run(|_n, seed| Independent::new(2, seed))?;
    /// // The disk's indicator has variance 1/4, so the RMSE is 0.5 / sqrt(N).
    /// let ratio = study.fitted_rmse(400) / (0.5 / 20.0);
    /// assert!(ratio > 0.7 && ratio < 1.4, "{ratio}");
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn fitted_rmse(&self, n: u64) -> f64 {
        (self.intercept + self.slope * (n as f64).ln()).exp()
    }
}

/// The settings of a convergence study, and [`run`](Self::run) to carry it out.
///
/// ```
/// use mcint::quality::Convergence;
/// use mcint::sampler::{Scramble, Sobol};
/// use mcint::testfns::GraphicsIntegrand;
/// let sizes: Vec<u64> = (6..=12).map(|m| 1 << m).collect();
/// let study = Convergence::new(&GraphicsIntegrand::Bilinear, &sizes)
///     .passes(32)
///     .seed(7)
///     .threads(2)
///     .run(|_n, seed| Sobol::new(2, Scramble::Owen, seed))?;
/// // Owen-scrambled Sobol' on a smooth integrand: close to N^-3/2.
/// assert!(study.slope < -1.2 && study.slope > -1.8, "{}", study.slope);
/// # Ok::<(), mcint::Error>(())
/// ```
pub struct Convergence<'a> {
    integrand: &'a dyn TestFunction,
    sizes: Vec<u64>,
    passes: u64,
    config: RunConfig,
    progress: Option<&'a dyn Fn(u64, u64)>,
}

impl fmt::Debug for Convergence<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Convergence")
            .field("integrand", &self.integrand.name())
            .field("sizes", &self.sizes)
            .field("passes", &self.passes)
            .field("seed", &self.config.seed())
            .field("threads", &self.config.threads)
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

impl<'a> Convergence<'a> {
    /// A study of `integrand` at the point counts `sizes` (at least two, strictly increasing,
    /// each valid for the sampler), with 32 passes each and seed 0 unless set.
    ///
    /// ```
    /// use mcint::quality::Convergence;
    /// use mcint::testfns::GraphicsIntegrand;
    /// let study = Convergence::new(&GraphicsIntegrand::Step, &[16, 64, 256]);
    /// assert!(format!("{study:?}").contains("[16, 64, 256]"));
    /// ```
    pub fn new(integrand: &'a dyn TestFunction, sizes: &[u64]) -> Self {
        Convergence {
            integrand,
            sizes: sizes.to_vec(),
            passes: DEFAULT_PASSES,
            config: RunConfig::default(),
            progress: None,
        }
    }

    run_settings! {
        setup: "use mcint::{quality::Convergence, sampler::Independent, testfns::GraphicsIntegrand};\n\
                const DIMS: usize = 2;\n\
                let runner = || Convergence::new(&GraphicsIntegrand::Disk, &[16, 64]).passes(4);",
        run: ".run(|_n, seed| Independent::new(DIMS, seed)).unwrap()";
        seed, threads
    }

    /// Independent passes `R` per point count (2 to `2^20`; default 32). The slope's standard
    /// error falls like `1/√R`.
    ///
    /// ```
    /// use mcint::quality::Convergence;
    /// use mcint::sampler::Independent;
    /// use mcint::testfns::GraphicsIntegrand;
    /// let study = |r| Convergence::new(&GraphicsIntegrand::Disk, &[16, 64]).passes(r);
    /// assert!(study(1).run(|_n, seed| Independent::new(2, seed)).is_err());
    /// assert!(study(u64::MAX).run(|_n, seed| Independent::new(2, seed)).is_err());
    /// ```
    pub fn passes(mut self, passes: u64) -> Self {
        self.passes = passes;
        self
    }

    /// A callback told `(points evaluated so far, total points)` after every pass, on the
    /// thread that called [`run`](Self::run) (the total is `R · Σ N`), for progress bars.
    ///
    /// ```
    /// use std::cell::Cell;
    /// use mcint::quality::Convergence;
    /// use mcint::sampler::Independent;
    /// use mcint::testfns::GraphicsIntegrand;
    /// let last = Cell::new((0, 0));
    /// let report = |done, total| last.set((done, total));
    /// Convergence::new(&GraphicsIntegrand::Disk, &[16, 64]).passes(4).progress(&report)
    ///     .run(|_n, s| Independent::new(2, s))?;
    /// assert_eq!(last.get(), (320, 320));
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn progress(mut self, progress: &'a dyn Fn(u64, u64)) -> Self {
        self.progress = Some(progress);
        self
    }

    /// Runs the study. `sampler(n, seed)` builds the sampler for `n` points per estimate with
    /// the given seed (each pass asks for a new one); the estimate uses its points `0..n`.
    ///
    /// Errors when fewer than two point counts are given or they are not strictly increasing
    /// and positive, when `R < 2` or `threads == 0`, when the factory fails for a point count
    /// (its own error is returned, naming what it accepts), when a sampler's dimension differs
    /// from the integrand's, when it is not randomized (its passes would all be equal), when
    /// `n` does not fit its pass structure (a fixed pass size other than `n`, or a sequence
    /// whose passes are shorter than `n`), when the integrand is not finite at some point,
    /// and when some point count has a zero RMSE (its logarithm cannot be fitted).
    ///
    /// ```
    /// use mcint::quality::Convergence;
    /// use mcint::sampler::{SamplerKind, Jittered};
    /// use mcint::testfns::GraphicsIntegrand;
    /// let f = GraphicsIntegrand::Gaussian;
    /// // Jittered points need n = k^2: the sampler's own error says which sizes would do.
    /// let err = Convergence::new(&f, &[16, 50])
    ///     .run(|n, seed| Jittered::with_points(2, n, seed)).unwrap_err();
    /// assert!(err.to_string().contains("nearest valid"), "{err}");
    /// let study = Convergence::new(&f, &[16, 64, 256, 1024])
    ///     .run(|n, seed| SamplerKind::Jittered.build(2, n, seed))?;
    /// assert!((study.slope + 1.0).abs() < 0.2, "{}", study.slope);
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn run<S, F>(&self, sampler: F) -> Result<ConvergenceStudy>
    where
        S: Sampler,
        F: Fn(u64, u64) -> Result<S> + Sync,
    {
        self.check_settings()?;
        // Pass 0 of every size is built here, so that a size the sampler rejects is reported
        // before any work, and always the same one (the smallest).
        let first_passes = self
            .sizes
            .iter()
            .map(|&n| self.plan().build(&sampler, n, 0))
            .collect::<Result<Vec<S>>>()?;
        let sampler_name = first_passes[0].name().to_string();
        let errors = self.run_passes(&sampler, &first_passes)?;
        let points = self
            .sizes
            .iter()
            .zip(&errors)
            .map(|(&n, e)| summarize(n, e))
            .collect::<Vec<_>>();
        // Estimates that take few values (an indicator's counts, a stratified sampler's
        // discrete errors) can agree by chance in a few passes.
        let few = if self.passes < 32 {
            "; with more passes a chance agreement becomes unlikely"
        } else {
            ""
        };
        if let Some(p) = points.iter().find(|p| p.rmse == 0.0) {
            return Err(Error::invalid(
                "passes",
                self.passes,
                format!(
                    "passes whose estimates are not all exact: every one at N = {} was, so \
                     log RMSE is undefined (the sampler may integrate {} exactly){few}",
                    p.n,
                    self.integrand.name()
                ),
            ));
        }
        if let Some(p) = points.iter().find(|p| p.rmse_std_error == 0.0) {
            return Err(Error::invalid(
                "passes",
                self.passes,
                format!(
                    "passes whose squared errors differ: every one at N = {} had the same, so \
                     the spread of its RMSE, and the slope's error bar, are undefined{few}",
                    p.n
                ),
            ));
        }
        let fit = fit_log_log(&points);
        Ok(ConvergenceStudy {
            integrand: self.integrand.name(),
            sampler: sampler_name,
            passes: self.passes,
            points,
            slope: fit.slope,
            slope_std_error: fit.slope_std_error,
            slope_sampling_error: fit.slope_sampling_error,
            intercept: fit.intercept,
            chi2_per_dof: fit.chi2_per_dof,
        })
    }

    fn plan(&self) -> PassPlan<'a> {
        PassPlan {
            integrand: self.integrand,
            seed: self.config.seed().unwrap_or(0),
        }
    }

    fn check_settings(&self) -> Result<()> {
        if self.sizes.len() < 2 {
            return Err(Error::invalid(
                "sizes",
                format!("{:?}", self.sizes),
                "at least two point counts, to fit a slope",
            ));
        }
        if self.sizes[0] == 0 || self.sizes.windows(2).any(|w| w[0] >= w[1]) {
            return Err(Error::invalid(
                "sizes",
                format!("{:?}", self.sizes),
                "positive point counts in strictly increasing order",
            ));
        }
        if !(2..=MAX_PASSES).contains(&self.passes) {
            return Err(Error::invalid(
                "passes",
                self.passes,
                "2 to 2^20 independent passes per point count (at least 2 to measure a \
                 spread; the error of each is kept in memory)",
            ));
        }
        Ok(())
    }

    /// The signed errors of every pass, `errors[k][r]` for size `k` and pass `r`.
    fn run_passes<S, F>(&self, factory: &F, first_passes: &[S]) -> Result<Vec<Vec<f64>>>
    where
        S: Sampler,
        F: Fn(u64, u64) -> Result<S> + Sync,
    {
        let (executor, _run) = self.config.executor()?;
        let passes = usize::try_from(self.passes).map_err(|_| Error::IndexOutOfRange {
            what: "number of passes",
            limit: usize::MAX as u64,
        })?;
        // Largest sizes first: the long jobs start early, so the workers finish together.
        let order: Vec<(usize, u64)> = (0..self.sizes.len())
            .rev()
            .flat_map(|k| (0..self.passes).map(move |r| (k, r)))
            .collect();
        let total_points = self.sizes.iter().fold(0u64, |sum, &n| {
            sum.saturating_add(n.saturating_mul(self.passes))
        });
        let job = PassJobs {
            plan: self.plan(),
            factory,
            first_passes,
            sizes: &self.sizes,
            order: &order,
        };
        let mut errors = vec![vec![0.0; passes]; self.sizes.len()];
        let mut done = 0u64;
        // A few items per thread at a time, so the progress callback is told often.
        let window = 4 * executor.threads() as u64;
        executor.run(
            &job,
            0..order.len() as u64,
            window,
            &Limits::default(),
            |item, error| {
                let (k, r) = order[item as usize];
                errors[k][r as usize] = error;
                done = done.saturating_add(self.sizes[k]);
                if let Some(progress) = self.progress {
                    progress(done, total_points);
                }
                Ok(())
            },
        )?;
        Ok(errors)
    }
}

/// Every (size, pass) of a study, as work for the executor: item `i` is `order[i]`.
struct PassJobs<'a, S, F> {
    plan: PassPlan<'a>,
    factory: &'a F,
    first_passes: &'a [S],
    sizes: &'a [u64],
    order: &'a [(usize, u64)],
}

impl<S, F> ChunkJob for PassJobs<'_, S, F>
where
    S: Sampler,
    F: Fn(u64, u64) -> Result<S> + Sync,
{
    type Scratch = Points;
    type Output = f64;

    fn scratch(&self) -> Result<Points> {
        Points::new(self.plan.integrand.dims(), BLOCK)
    }

    fn run(&self, block: &mut Points, item: u64, _: &Limits) -> Result<Option<f64>> {
        let (k, r) = self.order[item as usize];
        let n = self.sizes[k];
        let integrand = self.plan.integrand;
        if r == 0 {
            pass_error(&self.first_passes[k], integrand, n, r, block).map(Some)
        } else {
            let sampler = self.plan.build(self.factory, n, r)?;
            pass_error(&sampler, integrand, n, r, block).map(Some)
        }
    }

    fn origin(&self, item: u64) -> (u64, u64) {
        let (_, r) = self.order[item as usize];
        (r, 0)
    }
}

#[derive(Clone, Copy)]
struct PassPlan<'a> {
    integrand: &'a dyn TestFunction,
    seed: u64,
}

impl PassPlan<'_> {
    /// The sampler of pass `pass` at `n` points, checked to fit the study.
    fn build<S: Sampler, F: Fn(u64, u64) -> Result<S>>(
        &self,
        factory: &F,
        n: u64,
        pass: u64,
    ) -> Result<S> {
        let sampler = factory(n, hash_words(self.seed, &[n, pass, SALT]))?;
        if sampler.dims() != self.integrand.dims() {
            return Err(Error::DimensionMismatch {
                what: "sampler",
                expected: self.integrand.dims(),
                found: sampler.dims(),
            });
        }
        if !sampler.is_randomized() {
            return Err(Error::invalid(
                "sampler",
                sampler.name(),
                "a randomized sampler (a deterministic one repeats the same estimate in \
                 every pass, so it has no spread to measure)",
            ));
        }
        match sampler.passes() {
            PassKind::Fixed { size } if size != n => Err(Error::invalid(
                "n",
                n,
                format!(
                    "the pass size of the {} sampler built for it, {size} (build the sampler \
                     for the point count it is given)",
                    sampler.name()
                ),
            )),
            PassKind::Extensible { max } if n > max => Err(Error::invalid(
                "n",
                n,
                format!(
                    "at most {max}, the pass size of the {} sampler",
                    sampler.name()
                ),
            )),
            _ => Ok(sampler),
        }
    }
}

/// The signed error `Q̂ - I` of the estimate from points `0..n` of `sampler` (pass `pass` of
/// the study, for error messages).
fn pass_error(
    sampler: &dyn Sampler,
    f: &dyn TestFunction,
    n: u64,
    pass: u64,
    block: &mut Points,
) -> Result<f64> {
    let mut x = vec![0.0; f.dims()];
    // Block sums added with Neumaier's compensation: the errors measured can be 1e-9 of the
    // values summed.
    let (mut sum, mut compensation) = (0.0f64, 0.0f64);
    let mut start = 0u64;
    while start < n {
        let len = (n - start).min(BLOCK as u64) as usize;
        block.set_len(len);
        sampler.fill(start, block)?;
        let mut block_sum = 0.0;
        for i in 0..len {
            block.copy_point(i, &mut x);
            let y = f.eval(&x);
            if !y.is_finite() {
                let found = NonFinite {
                    count: 1,
                    replicate: pass,
                    index: start + i as u64,
                    output: None,
                    value: y,
                    point: x,
                };
                return Err(found.into_error());
            }
            block_sum += y;
        }
        let t = sum + block_sum;
        compensation += if sum.abs() >= block_sum.abs() {
            (sum - t) + block_sum
        } else {
            (block_sum - t) + sum
        };
        sum = t;
        start += len as u64;
    }
    Ok((sum + compensation) / n as f64 - f.exact())
}

/// Errors within `[2^-64, 2^64]` of 1 are summarized as they are (their fourth powers, over up
/// to 2^20 passes, stay normal); others in units of a power of two.
const ORDINARY_ERRORS: f64 = 1.0 / 18_446_744_073_709_551_616.0;

/// `2^e` exactly, for `e` from -1074 (the least subnormal) to 1023.
fn power_of_two(e: i32) -> f64 {
    if e >= -1022 {
        f64::from_bits(((e + 1023) as u64) << 52)
    } else {
        f64::from_bits(1u64 << (e + 1074))
    }
}

/// RMSE, mean error and their standard errors from the signed errors of the passes.
fn summarize(n: u64, errors: &[f64]) -> ConvergencePoint {
    // The spread of the squared errors takes fourth powers, which overflow beyond about 1e77
    // and vanish below about 1e-77: errors far from 1 are taken in units of a power of two
    // near the largest, exactly, and the results scaled back.
    let largest = errors.iter().fold(0.0f64, |m, e| m.max(e.abs()));
    let unit = if largest == 0.0 || (ORDINARY_ERRORS..=1.0 / ORDINARY_ERRORS).contains(&largest) {
        1.0
    } else {
        power_of_two(largest.log2().floor() as i32)
    };
    if unit != 1.0 {
        let scaled: Vec<f64> = errors.iter().map(|e| e / unit).collect();
        let point = summarize(n, &scaled);
        return ConvergencePoint {
            n,
            rmse: point.rmse * unit,
            rmse_std_error: point.rmse_std_error * unit,
            mean_error: point.mean_error * unit,
            mean_error_std_error: point.mean_error_std_error * unit,
        };
    }
    let r = errors.len() as f64;
    let mean_error = errors.iter().sum::<f64>() / r;
    let error_var = errors.iter().map(|e| (e - mean_error).powi(2)).sum::<f64>() / (r - 1.0);
    let mse = errors.iter().map(|e| e * e).sum::<f64>() / r;
    let squares_var = errors.iter().map(|e| (e * e - mse).powi(2)).sum::<f64>() / (r - 1.0);
    let rmse = mse.sqrt();
    let mse_std_error = (squares_var / r).sqrt();
    ConvergencePoint {
        n,
        rmse,
        rmse_std_error: if rmse > 0.0 {
            mse_std_error / (2.0 * rmse)
        } else {
            0.0
        },
        mean_error,
        mean_error_std_error: (error_var / r).sqrt(),
    }
}

/// The least-squares line through `(ln N, ln RMSE)` and its uncertainties.
struct LogLogFit {
    slope: f64,
    intercept: f64,
    slope_std_error: f64,
    slope_sampling_error: f64,
    chi2_per_dof: Option<f64>,
}

/// Ordinary least squares of `ln RMSE` on `ln N`, with the slope's error propagated from each
/// point's `σ_k` and inflated by the Birge ratio (see the module documentation). Needs at
/// least two points with positive RMSE.
fn fit_log_log(points: &[ConvergencePoint]) -> LogLogFit {
    let k = points.len() as f64;
    let xs: Vec<f64> = points.iter().map(|p| (p.n as f64).ln()).collect();
    let ys: Vec<f64> = points.iter().map(|p| p.rmse.ln()).collect();
    // σ of ln RMSE: relative standard error of the RMSE.
    let sigmas: Vec<f64> = points.iter().map(|p| p.rmse_std_error / p.rmse).collect();
    let mean_x = xs.iter().sum::<f64>() / k;
    let mean_y = ys.iter().sum::<f64>() / k;
    let sxx: f64 = xs.iter().map(|x| (x - mean_x).powi(2)).sum();
    let sxy: f64 = xs
        .iter()
        .zip(&ys)
        .map(|(x, y)| (x - mean_x) * (y - mean_y))
        .sum();
    let slope = sxy / sxx;
    let intercept = mean_y - slope * mean_x;
    let slope_sampling_error = xs
        .iter()
        .zip(&sigmas)
        .map(|(x, s)| ((x - mean_x) / sxx * s).powi(2))
        .sum::<f64>()
        .sqrt();
    let chi2: f64 = xs
        .iter()
        .zip(&ys)
        .zip(&sigmas)
        .map(|((x, y), s)| {
            let residual = y - intercept - slope * x;
            // A point that fits exactly adds nothing, even with a zero spread.
            if residual == 0.0 {
                0.0
            } else {
                (residual / s).powi(2)
            }
        })
        .sum();
    let dof = points.len().saturating_sub(2);
    let chi2_per_dof = (dof > 0).then(|| chi2 / dof as f64);
    let inflation = chi2_per_dof.map_or(1.0, |c| c.sqrt().max(1.0));
    LogLogFit {
        slope,
        intercept,
        slope_std_error: slope_sampling_error * inflation,
        slope_sampling_error,
        chi2_per_dof,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(n: u64, rmse: f64, rel: f64) -> ConvergencePoint {
        ConvergencePoint {
            n,
            rmse,
            rmse_std_error: rel * rmse,
            mean_error: 0.0,
            mean_error_std_error: 0.0,
        }
    }

    #[test]
    fn exact_power_law_is_fitted_exactly_with_the_propagated_error() {
        // RMSE = 2 N^-0.75 at N = 1, 4, 16: x = 0, ln 4, ln 16.
        let points: Vec<_> = [1u64, 4, 16]
            .iter()
            .map(|&n| point(n, 2.0 * (n as f64).powf(-0.75), 0.1))
            .collect();
        let fit = fit_log_log(&points);
        assert!((fit.slope + 0.75).abs() < 1e-12);
        assert!((fit.intercept - 2f64.ln()).abs() < 1e-12);
        assert!(fit.chi2_per_dof.unwrap() < 1e-20);
        // c = (x - mean)/Sxx with x = (0, a, 2a), a = ln 4: Sxx = 2 a², Σ c² = 1/Sxx.
        let a = 4f64.ln();
        let expected = 0.1 / (2.0 * a * a).sqrt();
        assert!((fit.slope_sampling_error - expected).abs() < 1e-12);
        assert_eq!(fit.slope_std_error, fit.slope_sampling_error);
    }

    #[test]
    fn scatter_beyond_the_errors_inflates_the_slope_error() {
        // Residuals of ±0.3 in ln RMSE against σ = 0.01 give χ²/dof ≫ 1.
        let points = vec![
            point(1, 1.0, 0.01),
            point(10, 0.1f64 * 0.3f64.exp(), 0.01),
            point(100, 0.01f64 * (-0.3f64).exp(), 0.01),
            point(1000, 0.001, 0.01),
        ];
        let fit = fit_log_log(&points);
        let chi2 = fit.chi2_per_dof.unwrap();
        assert!(chi2 > 100.0, "{chi2}");
        let ratio = fit.slope_std_error / fit.slope_sampling_error;
        assert!((ratio - chi2.sqrt()).abs() < 1e-9);
    }

    #[test]
    fn summary_of_known_errors() {
        let p = summarize(8, &[1.0, -1.0, 1.0, -1.0]);
        assert_eq!((p.rmse, p.mean_error, p.rmse_std_error), (1.0, 0.0, 0.0));
        let q = summarize(8, &[0.0, 2.0]);
        // MSE = 2; the squares 0 and 4 have s² = 8, so SE(MSE) = √(8/2) = 2 and
        // SE(RMSE) = 2 / (2 √2).
        assert!((q.rmse - 2f64.sqrt()).abs() < 1e-15);
        assert!((q.rmse_std_error - 1.0 / 2f64.sqrt()).abs() < 1e-15);
        assert_eq!(q.mean_error, 1.0);
        assert_eq!(q.mean_error_std_error, 1.0);
    }
}
