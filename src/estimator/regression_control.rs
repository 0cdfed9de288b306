//! The regression estimator for control variates: the coefficients of A.29 estimated from the
//! same samples by least squares.
//!
//! With controls `g_1..g_k` of known integrals `G_1..G_k` (the seed's A.26-A.29 with several
//! controls), write `Y = f(X)/pdf(X)` and `Z_j = g_j(X)/pdf(X)`, so that `E[Z_j] = G_j`. For any
//! fixed `beta`, `mean(Y) - beta^T (mean(Z) - G)` is unbiased; its variance is smallest at
//! `beta* = Cov(Z)^-1 Cov(Z, Y)`, where it is `(1 - R^2) Var(Y) / n` with `R^2` the squared
//! multiple correlation of `Y` on `Z` (`rho^2` for one control). The regression estimator
//! replaces `beta*` by the least-squares coefficients of the samples, which makes the estimate
//! the fitted intercept of the regression of `Y` on `Z - G` (Lavenberg & Welch 1981; Nelson
//! 1990; Glasserman 2004, section 4.1.3; Owen, *Monte Carlo theory, methods and examples*,
//! section 8.9).
//!
//! Because `beta` now depends on the samples, the estimate has a bias of order `1/n`, far below
//! its standard error of order `1/sqrt(n)`; it is consistent. Its standard error is the
//! ordinary least-squares standard error of the intercept,
//! `s_e sqrt(1/n + (mean(Z) - G)^T S_ZZ^-1 (mean(Z) - G))`, with `s_e^2` the residual variance
//! on `n - k - 1` degrees of freedom and `S_ZZ` the co-moment matrix of the controls. That
//! formula assumes independent samples, so only samplers whose points are all independent
//! ([`PassKind::Independent`]) are accepted; for stratified or quasi-Monte Carlo points use
//! [`ControlVariate`](super::ControlVariate) with a fixed coefficient (for example from a pilot
//! run) in the [`Integrator`](crate::Integrator) with replicates.

use crate::pdf::Pdf;
use crate::sampler::{Independent, PassKind, Sampler};
use crate::stats::{CovarianceAccumulator, ErrorBasis, Estimate, StopReason};
use crate::{Error, Points, Result};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// Points generated and evaluated together (as in the integrator).
const BLOCK: u64 = 1024;
/// Points per unit of work handed to a thread; the chunking, and so the result, does not
/// depend on the number of threads.
const CHUNK: u64 = 16 * BLOCK;
/// Samples when the caller does not say.
const DEFAULT_SAMPLES: u64 = 1 << 16;
/// A control whose variance left after regressing it on the controls before it is below this
/// fraction of its variance is treated as a linear combination of them (`1 - R_j^2 < 1e-10`,
/// a correlation within `5e-11` of one): its coefficient would be numerical noise.
const COLLINEARITY_TOLERANCE: f64 = 1e-10;

/// A control function boxed so that controls of different closure types can share a list.
type ControlFn<'a> = Box<dyn Fn(&[f64]) -> f64 + Send + Sync + 'a>;

/// The result of a [`RegressionControlVariates`] run.
///
/// ```
/// use mcint::{estimator::RegressionControlVariates, pdf::UniformBox};
/// let r = RegressionControlVariates::new(|x: &[f64]| x[0].exp(), UniformBox::unit(1)?)
///     .control(|x: &[f64]| x[0], 0.5)
///     .samples(4096)
///     .run()?;
/// assert_eq!(r.coefficients.len(), 1);
/// assert!(r.residual_variance < r.plain_variance);
/// assert!(r.variance_reduction < 0.02); // 1 - rho^2 = 0.0163 for e^x and x on [0,1]
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct ControlVariateEstimate {
    /// The estimate of the integral with its standard error (per-sample basis, `n - k - 1`
    /// degrees of freedom).
    pub estimate: Estimate,
    /// The least-squares coefficients `beta_j`, one per control, in the order added.
    pub coefficients: Vec<f64>,
    /// The sample variance per sample of `f/pdf` alone: plain importance sampling's
    /// `sigma^2[Y]` (A.21), with `n - 1` degrees of freedom.
    pub plain_variance: f64,
    /// The residual variance per sample, `sum e_i^2 / (n - k - 1)`: the controlled estimator's
    /// `sigma^2`, so that `std_error ~ sqrt(residual_variance / n)`.
    pub residual_variance: f64,
    /// The achieved variance-reduction factor `1 - R^2` (residual over total sum of squares;
    /// `1 - rho^2` for one control): the fraction of the plain variance left. It is 1 when
    /// `f/pdf` is constant over the samples (nothing to reduce).
    pub variance_reduction: f64,
}

/// Control variates with coefficients estimated by least squares from the same samples: the
/// regression estimator (the seed's A.29 with several controls and fitted coefficients).
///
/// With `Y = f(X)/pdf(X)` and `Z_j = g_j(X)/pdf(X)` (so `E[Z_j] = G_j`), the estimate is
/// `mean(Y) - beta^T (mean(Z) - G)` with `beta = S_ZZ^-1 S_ZY` from the sample co-moments,
/// solved by a Cholesky factorization. The best fixed coefficients would leave the fraction
/// `1 - R^2` of the plain variance (`1 - rho^2` for one control); the run reports the achieved
/// fraction in [`ControlVariateEstimate::variance_reduction`].
///
/// - **Error bar.** The estimate is the fitted intercept of the regression of `Y` on `Z - G`,
///   and its standard error is the least-squares one,
///   `s_e sqrt(1/n + (mean(Z) - G)^T S_ZZ^-1 (mean(Z) - G))`, with the residual variance
///   `s_e^2` on `n - k - 1` degrees of freedom (Student-t intervals). This assumes the samples
///   are **independent**: samplers with dependent points (fixed or extensible passes:
///   stratified, Latin hypercube, quasi-Monte Carlo) are rejected with an error. For those, use
///   [`ControlVariate`](super::ControlVariate) with a fixed coefficient (for example from a
///   pilot run) in the [`Integrator`](crate::Integrator) with replicates.
/// - **Bias.** Because `beta` is estimated from the same samples, the estimate has a bias of
///   order `1/n` (about `-E[e z^2] / (n Var z)` for one control, `e` the residual), far below
///   its `1/sqrt(n)` standard error; the estimator is consistent.
/// - **Determinism.** Points come in fixed chunks merged in chunk order with a
///   [`CovarianceAccumulator`], so the result is the same for any number of threads.
///
/// ```
/// use mcint::{estimator::RegressionControlVariates, pdf::UniformBox, sampler::Independent};
/// // int_0^1 e^x dx = e - 1, with the controls x (integral 1/2) and x^2 (integral 1/3).
/// let r = RegressionControlVariates::new(|x: &[f64]| x[0].exp(), UniformBox::unit(1)?)
///     .control(|x: &[f64]| x[0], 0.5)
///     .control(|x: &[f64]| x[0] * x[0], 1.0 / 3.0)
///     .sampler(Independent::new(1, 0)?)
///     .samples(10_000)
///     .seed(3)
///     .threads(2)
///     .run()?;
/// let exact = std::f64::consts::E - 1.0;
/// let e = &r.estimate;
/// assert!((e.mean - exact).abs() < 4.5 * e.std_error.unwrap());
/// assert!(r.variance_reduction < 1e-3); // a quadratic fits e^x on [0,1] closely
/// # Ok::<(), mcint::Error>(())
/// ```
pub struct RegressionControlVariates<'a, F, P> {
    f: F,
    pdf: P,
    controls: Vec<(ControlFn<'a>, f64)>,
    sampler: Option<Box<dyn Sampler + 'a>>,
    samples: u64,
    seed: Option<u64>,
    threads: Option<usize>,
}

impl<'a, F: Fn(&[f64]) -> f64 + Send + Sync, P: Pdf> RegressionControlVariates<'a, F, P> {
    /// Estimates the integral of `f` over the domain of `pdf`, sampling from `pdf` (a
    /// [`UniformBox`](crate::pdf::UniformBox) for plain Monte Carlo). Add controls with
    /// [`control`](Self::control); by default the run uses `2^16` independent points, seed 0
    /// and all available threads.
    ///
    /// ```
    /// use mcint::{estimator::RegressionControlVariates, pdf::UniformBox};
    /// let r = RegressionControlVariates::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap());
    /// assert!(r.run().unwrap_err().to_string().contains("at least one control"));
    /// ```
    pub fn new(f: F, pdf: P) -> Self {
        RegressionControlVariates {
            f,
            pdf,
            controls: Vec::new(),
            sampler: None,
            samples: DEFAULT_SAMPLES,
            seed: None,
            threads: None,
        }
    }

    /// Adds a control `g` whose exact integral over the pdf's domain is `integral` (checked to
    /// be finite when the run starts).
    ///
    /// ```
    /// use mcint::{estimator::RegressionControlVariates, pdf::UniformBox};
    /// let r = RegressionControlVariates::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .control(|x: &[f64]| x[0], f64::NAN);
    /// assert!(r.run().unwrap_err().to_string().contains("integral of control 0"));
    /// ```
    pub fn control(mut self, g: impl Fn(&[f64]) -> f64 + Send + Sync + 'a, integral: f64) -> Self {
        self.controls.push((Box::new(g), integral));
        self
    }

    /// The sampler of canonical points: its dimension must be the pdf's canonical dimension and
    /// its points independent. A seed set with [`seed`](Self::seed) overrides the sampler's.
    ///
    /// ```
    /// use mcint::{estimator::RegressionControlVariates, pdf::UniformBox, sampler::Jittered};
    /// let r = RegressionControlVariates::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .control(|x: &[f64]| x[0] * x[0], 1.0 / 3.0)
    ///     .sampler(Jittered::new(1, 64, 0).unwrap())
    ///     .samples(64);
    /// assert!(r.run().unwrap_err().to_string().contains("independent"));
    /// ```
    pub fn sampler(mut self, sampler: impl Sampler + 'a) -> Self {
        let mut boxed: Box<dyn Sampler + 'a> = Box::new(sampler);
        if let Some(seed) = self.seed {
            boxed.reseed(seed);
        }
        self.sampler = Some(boxed);
        self
    }

    /// Number of samples (more than the number of controls plus one; default `2^16`).
    ///
    /// ```
    /// use mcint::{estimator::RegressionControlVariates, pdf::UniformBox};
    /// let r = RegressionControlVariates::new(|x: &[f64]| x[0].sin(), UniformBox::unit(1).unwrap())
    ///     .control(|x: &[f64]| x[0], 0.5)
    ///     .samples(100)
    ///     .run()
    ///     .unwrap();
    /// assert_eq!(r.estimate.n, 100);
    /// assert_eq!(r.estimate.dof, Some(98.0));
    /// ```
    pub fn samples(mut self, samples: u64) -> Self {
        self.samples = samples;
        self
    }

    /// The seed of the sampler's randomization (the same seed gives the same result).
    ///
    /// ```
    /// use mcint::{estimator::RegressionControlVariates, pdf::UniformBox};
    /// let run = |seed| RegressionControlVariates::new(|x: &[f64]| x[0].sin(), UniformBox::unit(1).unwrap())
    ///     .control(|x: &[f64]| x[0], 0.5)
    ///     .samples(100)
    ///     .seed(seed)
    ///     .run()
    ///     .unwrap();
    /// assert_eq!(run(1), run(1));
    /// assert_ne!(run(1), run(2));
    /// ```
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = Some(seed);
        if let Some(sampler) = self.sampler.as_mut() {
            sampler.reseed(seed);
        }
        self
    }

    /// Number of worker threads (at least 1; default: all available). The result does not
    /// depend on it.
    ///
    /// ```
    /// use mcint::{estimator::RegressionControlVariates, pdf::UniformBox};
    /// let run = |t| RegressionControlVariates::new(|x: &[f64]| x[0].sin(), UniformBox::unit(1).unwrap())
    ///     .control(|x: &[f64]| x[0], 0.5)
    ///     .samples(100_000)
    ///     .threads(t)
    ///     .run()
    ///     .unwrap();
    /// assert_eq!(run(1), run(3));
    /// ```
    pub fn threads(mut self, threads: usize) -> Self {
        self.threads = Some(threads);
        self
    }

    /// Runs the estimator.
    ///
    /// Errors when there is no control, a control's integral is not finite, the sampler's
    /// dimension differs from the pdf's canonical dimension, the sampler's points are not
    /// independent, there are too few samples for the regression (`n <= k + 1`), a value of
    /// `f/pdf` or `g_j/pdf` is NaN or infinite (with their count and the first offending
    /// point), a control is constant or a linear combination of the others over the samples
    /// (its coefficient would not be determined), or a control's integral is so far from its
    /// sample mean that the corrected mean overflows.
    ///
    /// ```
    /// use mcint::{estimator::RegressionControlVariates, pdf::UniformBox};
    /// let r = RegressionControlVariates::new(|x: &[f64]| x[0].exp(), UniformBox::unit(1).unwrap())
    ///     .control(|x: &[f64]| x[0], 0.5)
    ///     .control(|x: &[f64]| 1.0 - 2.0 * x[0], 0.0) // collinear with the first
    ///     .samples(1000)
    ///     .run();
    /// assert!(r.unwrap_err().to_string().contains("linear combination"));
    /// let far = RegressionControlVariates::new(|x: &[f64]| x[0].exp(), UniformBox::unit(1).unwrap())
    ///     .control(|x: &[f64]| x[0], f64::MAX)
    ///     .samples(1000)
    ///     .run();
    /// assert!(far.unwrap_err().to_string().starts_with("invalid control integral"));
    /// ```
    pub fn run(&self) -> Result<ControlVariateEstimate> {
        let k = self.controls.len();
        if k == 0 {
            return Err(Error::invalid(
                "controls",
                0,
                "at least one control (add one with .control(g, integral))",
            ));
        }
        if let Some((j, (_, integral))) = self
            .controls
            .iter()
            .enumerate()
            .find(|(_, (_, g))| !g.is_finite())
        {
            return Err(Error::invalid(
                "control integral",
                format!("{integral} (integral of control {j})"),
                "the finite, exactly known integral of the control over the domain",
            ));
        }
        let default_sampler;
        let sampler: &dyn Sampler = match &self.sampler {
            Some(s) => s.as_ref(),
            None => {
                default_sampler =
                    Independent::new(self.pdf.canonical_dims(), self.seed.unwrap_or(0))?;
                &default_sampler
            }
        };
        if sampler.dims() != self.pdf.canonical_dims() {
            return Err(Error::DimensionMismatch {
                what: "sampler (the pdf's canonical points)",
                expected: self.pdf.canonical_dims(),
                found: sampler.dims(),
            });
        }
        if sampler.passes() != PassKind::Independent {
            return Err(Error::invalid(
                "sampler",
                format!("{} ({:?})", sampler.name(), sampler.passes()),
                "a sampler of independent points (PassKind::Independent): the regression's \
                 standard error assumes independent samples, and stratified or quasi-random \
                 points are not; use ControlVariate with a fixed coefficient in the Integrator \
                 with replicates instead",
            ));
        }
        let min_samples = k as u64 + 2;
        if self.samples < min_samples {
            return Err(Error::invalid(
                "samples",
                self.samples,
                format!(
                    "at least {min_samples} (the number of controls plus two, for one degree of \
                     freedom in the residual variance)"
                ),
            ));
        }
        let threads = crate::threads::resolve(self.threads)?;
        let chunks = self.run_chunks(sampler, threads)?;
        let mut total = CovarianceAccumulator::new(k + 1)?;
        for chunk in &chunks {
            total.merge(&chunk.accumulator)?;
        }
        if let Some(first) = chunks.iter().find_map(|c| c.first_non_finite) {
            let mut point = vec![0.0; sampler.dims()];
            sampler.point(first.index, &mut point)?;
            return Err(Error::NonFiniteContribution {
                count: total.non_finite(),
                first_index: first.index,
                first_replicate: 0,
                first_value: first.value,
                first_point: point,
            });
        }
        let integrals: Vec<f64> = self.controls.iter().map(|(_, g)| *g).collect();
        regression(&total, &integrals)
    }

    /// Evaluates every chunk on `threads` workers and returns the results in chunk order.
    fn run_chunks(&self, sampler: &dyn Sampler, threads: usize) -> Result<Vec<ChunkResult>> {
        let total = self.samples.div_ceil(CHUNK);
        let slots = usize::try_from(total).map_err(|_| Error::IndexOutOfRange {
            what: "number of work chunks",
            limit: usize::MAX as u64,
        })?;
        let next = AtomicU64::new(0);
        let failed = AtomicBool::new(false);
        let workers = threads.min(slots.max(1));
        let outcomes: Vec<Result<Vec<(u64, ChunkResult)>>> = std::thread::scope(|scope| {
            let handles: Vec<_> = (0..workers)
                .map(|_| {
                    scope.spawn(|| {
                        let mut work = Workspace::new(sampler.dims(), self.controls.len() + 1)?;
                        let mut done = Vec::new();
                        loop {
                            let chunk = next.fetch_add(1, Ordering::Relaxed);
                            if chunk >= total || failed.load(Ordering::Relaxed) {
                                return Ok(done);
                            }
                            match work.run_chunk(self, sampler, chunk) {
                                Ok(result) => done.push((chunk, result)),
                                Err(e) => {
                                    failed.store(true, Ordering::Relaxed);
                                    return Err(e);
                                }
                            }
                        }
                    })
                })
                .collect();
            handles
                .into_iter()
                .map(|h| {
                    h.join().unwrap_or_else(|_| {
                        Err(Error::invalid(
                            "worker thread",
                            "panicked",
                            "an integrand, controls and pdf that do not panic",
                        ))
                    })
                })
                .collect()
        });
        let mut results: Vec<Option<ChunkResult>> = vec![None; slots];
        for outcome in outcomes {
            for (chunk, result) in outcome? {
                results[chunk as usize] = Some(result);
            }
        }
        results
            .into_iter()
            .collect::<Option<Vec<_>>>()
            .ok_or(Error::invalid(
                "worker thread",
                "stopped early",
                "every chunk evaluated",
            ))
    }
}

/// `value / density`, with a zero value contributing zero even where the density is zero.
#[inline]
fn ratio(value: f64, density: f64) -> f64 {
    if value == 0.0 { 0.0 } else { value / density }
}

/// Where the first non-finite value of a chunk occurred.
#[derive(Debug, Clone, Copy)]
struct NonFinite {
    index: u64,
    value: f64,
}

/// What one chunk of work produced.
#[derive(Debug, Clone)]
struct ChunkResult {
    accumulator: CovarianceAccumulator,
    first_non_finite: Option<NonFinite>,
}

/// Per-thread buffers, allocated once.
struct Workspace {
    points: Points,
    u: Vec<f64>,
    x: Vec<f64>,
    /// `(f/pdf, g_1/pdf, ..., g_k/pdf)` of one sample.
    row: Vec<f64>,
}

impl Workspace {
    fn new(dims: usize, row: usize) -> Result<Workspace> {
        Ok(Workspace {
            points: Points::new(dims, BLOCK as usize)?,
            u: vec![0.0; dims],
            x: Vec::new(),
            row: vec![0.0; row],
        })
    }

    fn run_chunk<F: Fn(&[f64]) -> f64 + Send + Sync, P: Pdf>(
        &mut self,
        run: &RegressionControlVariates<'_, F, P>,
        sampler: &dyn Sampler,
        chunk: u64,
    ) -> Result<ChunkResult> {
        self.x.resize(run.pdf.dims(), 0.0);
        let first = chunk * CHUNK;
        let end = (first + CHUNK).min(run.samples);
        let mut accumulator = CovarianceAccumulator::new(self.row.len())?;
        let mut first_non_finite = None;
        let mut start = first;
        while start < end {
            let len = (end - start).min(BLOCK) as usize;
            self.points.set_len(len);
            sampler.fill(start, &mut self.points)?;
            for i in 0..len {
                self.points.copy_point(i, &mut self.u);
                run.pdf.sample(&self.u, &mut self.x);
                let density = run.pdf.pdf(&self.x);
                self.row[0] = ratio((run.f)(&self.x), density);
                for (slot, (g, _)) in self.row[1..].iter_mut().zip(&run.controls) {
                    *slot = ratio(g(&self.x), density);
                }
                if first_non_finite.is_none()
                    && let Some(&value) = self.row.iter().find(|v| !v.is_finite())
                {
                    first_non_finite = Some(NonFinite {
                        index: start + i as u64,
                        value,
                    });
                }
                accumulator.push(&self.row)?;
            }
            start += len as u64;
        }
        Ok(ChunkResult {
            accumulator,
            first_non_finite,
        })
    }
}

/// The Cholesky factor `L` (row-major, lower triangle) of the controls' co-moment matrix,
/// which is entry `(1 + i, 1 + j)` of the accumulator; fails when a control is constant or a
/// linear combination of the controls before it.
fn cholesky(total: &CovarianceAccumulator, k: usize) -> Result<Vec<f64>> {
    let mut l = vec![0.0; k * k];
    for j in 0..k {
        let diagonal = total.comoment(1 + j, 1 + j);
        if diagonal <= 0.0 {
            return Err(Error::invalid(
                "control",
                format!("{j} (constant over the {} samples)", total.count()),
                "controls that vary over the domain (a constant control is collinear with the \
                 intercept, and its coefficient is not determined)",
            ));
        }
        let pivot = diagonal - (0..j).map(|m| l[j * k + m] * l[j * k + m]).sum::<f64>();
        if pivot.is_nan() || pivot <= COLLINEARITY_TOLERANCE * diagonal {
            return Err(Error::invalid(
                "control",
                format!(
                    "{j} (over the {} samples, a linear combination of the controls before \
                     it, 0 to {}, up to a relative residual variance {:.1e})",
                    total.count(),
                    j.saturating_sub(1),
                    pivot / diagonal
                ),
                format!(
                    "controls that are not collinear (relative residual variance above \
                     {COLLINEARITY_TOLERANCE:e}): drop the redundant control"
                ),
            ));
        }
        let root = pivot.sqrt();
        l[j * k + j] = root;
        for i in j + 1..k {
            let s = total.comoment(1 + i, 1 + j)
                - (0..j).map(|m| l[i * k + m] * l[j * k + m]).sum::<f64>();
            l[i * k + j] = s / root;
        }
    }
    Ok(l)
}

/// Solves `L w = b` (forward substitution) in place.
fn forward(l: &[f64], k: usize, b: &mut [f64]) {
    for i in 0..k {
        let s: f64 = (0..i).map(|m| l[i * k + m] * b[m]).sum();
        b[i] = (b[i] - s) / l[i * k + i];
    }
}

/// Solves `L^T x = b` (back substitution) in place.
fn backward(l: &[f64], k: usize, b: &mut [f64]) {
    for i in (0..k).rev() {
        let s: f64 = (i + 1..k).map(|m| l[m * k + i] * b[m]).sum();
        b[i] = (b[i] - s) / l[i * k + i];
    }
}

/// The regression estimate from the merged moments of `(Y, Z_1..Z_k)` and the known `G`.
fn regression(total: &CovarianceAccumulator, integrals: &[f64]) -> Result<ControlVariateEstimate> {
    let k = integrals.len();
    let n = total.count();
    let l = cholesky(total, k)?;
    // beta = S_ZZ^-1 S_ZY, through L w = S_ZY and L^T beta = w.
    let mut beta: Vec<f64> = (0..k).map(|j| total.comoment(1 + j, 0)).collect();
    forward(&l, k, &mut beta);
    // With w = L^-1 S_ZY, the explained sum of squares is S_YZ S_ZZ^-1 S_ZY = |w|^2.
    let explained: f64 = beta.iter().map(|w| w * w).sum();
    backward(&l, k, &mut beta);

    let offsets: Vec<f64> = (0..k).map(|j| total.mean(1 + j) - integrals[j]).collect();
    let correction: f64 = beta.iter().zip(&offsets).map(|(b, d)| b * d).sum();
    let mean = total.mean(0) - correction;
    if !mean.is_finite() {
        // Finite samples, so the correction overflowed: a known integral far from the
        // control's sample mean.
        return Err(Error::invalid(
            "control integral",
            format!("{integrals:?}"),
            format!(
                "integrals near the controls' sample means {:?} (the correction beta (mean - \
                 integral) = {correction:e} overflows)",
                (0..k).map(|j| total.mean(1 + j)).collect::<Vec<_>>()
            ),
        ));
    }

    let total_ss = total.comoment(0, 0);
    // Rounding can leave a tiny negative residual when f is (nearly) a combination of controls.
    let residual_ss = (total_ss - explained).max(0.0);
    let dof = (n - k as u64 - 1) as f64;
    let residual_variance = residual_ss / dof;
    // Var(intercept) = s_e^2 (1/n + d^T S_ZZ^-1 d), d = mean(Z) - G, and d^T S^-1 d = |L^-1 d|^2.
    let mut whitened = offsets;
    forward(&l, k, &mut whitened);
    let leverage: f64 = whitened.iter().map(|w| w * w).sum();
    let std_error = (residual_variance * (1.0 / n as f64 + leverage)).sqrt();

    Ok(ControlVariateEstimate {
        estimate: Estimate {
            mean,
            std_error: Some(std_error),
            dof: Some(dof),
            basis: ErrorBasis::PerSample,
            n,
            evaluations: n,
            replicates: 1,
            non_finite: 0,
            stop: StopReason::Budget,
            converged: None,
            iterations: 1,
            chi2_dof: None,
            q_value: None,
        },
        coefficients: beta,
        plain_variance: total_ss / (n - 1) as f64,
        residual_variance,
        variance_reduction: if total_ss > 0.0 {
            residual_ss / total_ss
        } else {
            1.0
        },
    })
}
