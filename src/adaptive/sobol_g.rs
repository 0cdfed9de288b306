//! [`SobolG`]: cubature on one randomized Sobol' sequence that doubles its points until an
//! error bound read from the decay of the integrand's discrete Walsh coefficients meets the
//! tolerance (Hickernell & Jiménez Rugama 2016, "Reliable adaptive cubature using digital
//! sequences"; GAIL's `cubSobol_g`, QMCPy's `CubQMCSobolG`).

use super::walsh::WalshCoefficients;
use crate::engine::{
    self, ChunkJob, Drive, Executor, Limits, Next, NonFinite, RunConfig, StageEnd, Stages, Targets,
    run_settings,
};
use crate::error::{Error, Result};
use crate::estimator::{BatchUniformEstimator, Estimator, UniformEstimator};
use crate::pdf::UniformBox;
use crate::points::Points;
use crate::sampler::{Sampler, Scramble, Sobol};
use crate::stats::{Accumulator, ErrorBasis, Estimate, StopReason, VectorEstimate, Warning};

/// Points of the first stage without [`samples`](SobolG::samples) (QMCPy's default).
const DEFAULT_FIRST: u64 = 1 << 10;
/// The fewest points of the first stage: the bound reads slots `[N/32, N/16)`, eight of them
/// at 256 points (QMCPy's minimum).
const MIN_FIRST: u64 = 1 << 8;
/// The most points a run keeps coefficients for (12 bytes each: 3 GiB).
const MAX_POINTS: u64 = 1 << 28;
/// The bound's factor `C(m) = FUDGE / 2^m` (QMCPy's and GAIL's default inflation).
const FUDGE: f64 = 5.0;
/// Points a thread evaluates at a time.
const CHUNK: u64 = 4096;

/// Cubature on one LMS-scrambled and digitally shifted Sobol' sequence, doubling its points
/// until a cone-based bound on the error from the integrand's discrete Walsh coefficients
/// meets the tolerance (the rule of QMCPy's `CubQMCSobolG`).
///
/// The error of the mean of `N = 2^m` points of a digitally shifted digital net is a sum of
/// the integrand's Walsh coefficients at the wavenumbers the net cannot see. The rule assumes
/// the integrand lies in a cone where those coefficients decay steadily with the wavenumber,
/// so that the discrete coefficients one level coarser than the four finest, at slots
/// `[N/32, N/16)` of the wavenumber map, bound the rest: the error bound is
/// `5 / N * sum_(p in [N/32, N/16)) |yt_kappa(p)|` (see `walsh.rs`). There is no confidence
/// level and no replicate: every point of the one sequence counts toward the estimate, which
/// is why the rule needs fewer points than replicated RQMC for smooth integrands, and why it
/// can be fooled by an integrand outside the cone (a spike that the first `N` points miss
/// looks like a constant). Among the customary 5-D Genz families the corner peak is such a
/// case (at `1e-4` the first 1024 points meet the tolerance with a bound that covers the exact
/// value in 18 of 40 seeds), and the discontinuous family's coefficients decay too slowly to
/// reach `1e-4` within 2^26 points: use replicated RQMC ([`Integrator`](crate::Integrator)),
/// whose error bar is a confidence interval, where the cone is in doubt.
///
/// The estimate has no standard error: its basis is [`ErrorBasis::WalshBound`] and
/// [`Estimate::error_bound`] bounds `|mean - integral|` for integrands in the rule's cone
/// ([`Estimate::half_width`] returns it). Without a tolerance the run evaluates the first
/// stage only ([`samples`](Self::samples), default 1024 points). The points are split into
/// chunks and folded in index order, so the result is the same for any thread count. A NaN or
/// infinite value is an error naming its point: the transform has no way to leave it out.
///
/// ```
/// use mcint::{adaptive::SobolG, pdf::UniformBox, stats::Tolerance};
/// let f = |x: &[f64]| (x[0] + x[1] + x[2]).cos();
/// let e = SobolG::new(f, UniformBox::unit(3).unwrap())
///     .tolerance(Tolerance::absolute(1e-6).unwrap())
///     .seed(3)
///     .run()
///     .unwrap();
/// // The integral of cos(x + y + z) over the unit cube is -sin 3 + 3 sin 2 - 3 sin 1.
/// let exact = 3.0f64.sin() * -1.0 + 3.0 * 2.0f64.sin() - 3.0 * 1.0f64.sin();
/// assert!((e.mean - exact).abs() <= e.error_bound.unwrap());
/// assert!(e.error_bound.unwrap() <= 1e-6);
/// assert_eq!(e.evaluations, e.n);
/// assert!(e.n.is_power_of_two());
/// ```
pub struct SobolG<E> {
    estimator: E,
    config: RunConfig,
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync> SobolG<UniformEstimator<F>> {
    /// The rule for `f` over a box, with 1024 points in the first stage, seed 0 and all
    /// threads until told otherwise.
    ///
    /// ```
    /// use mcint::{adaptive::SobolG, pdf::UniformBox};
    /// let e = SobolG::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).run().unwrap();
    /// assert_eq!(e.evaluations, 1024);
    /// assert!((e.mean - 0.5).abs() <= e.error_bound.unwrap().max(1e-12));
    /// ```
    pub fn new(f: F, domain: UniformBox) -> Self {
        SobolG::with_estimator(UniformEstimator::new(f, domain))
    }
}

impl<F: Fn(&Points, &mut [f64]) + Send + Sync> SobolG<BatchUniformEstimator<F>> {
    /// The rule for an integrand that evaluates a block of points per call (see
    /// [`BatchUniformEstimator`]); the same bits as [`new`](SobolG::new) with the per-point
    /// form of the same arithmetic.
    ///
    /// ```
    /// use mcint::{Points, adaptive::SobolG, pdf::UniformBox};
    /// let per_point = SobolG::new(|x: &[f64]| x[0] * x[1], UniformBox::unit(2).unwrap());
    /// let product = |p: &Points, out: &mut [f64]| {
    ///     for ((y, &a), &b) in out.iter_mut().zip(p.column(0)).zip(p.column(1)) {
    ///         *y = a * b;
    ///     }
    /// };
    /// let batch = SobolG::new_batch(product, UniformBox::unit(2).unwrap());
    /// assert_eq!(per_point.run().unwrap(), batch.run().unwrap());
    /// ```
    pub fn new_batch(f: F, domain: UniformBox) -> Self {
        SobolG::with_estimator(BatchUniformEstimator::new(f, domain))
    }
}

impl<E: Estimator> SobolG<E> {
    /// The rule for any estimator of the integral from uniform canonical points (its
    /// contributions are averaged; evaluations count
    /// [`evaluations_per_contribution`](Estimator::evaluations_per_contribution)).
    ///
    /// ```
    /// use mcint::{adaptive::SobolG, estimator::UniformEstimator, pdf::UniformBox};
    /// let f = |x: &[f64]| x[0].exp();
    /// let estimator = UniformEstimator::new(f, UniformBox::unit(1).unwrap());
    /// let e = SobolG::with_estimator(estimator).run().unwrap();
    /// assert!((e.mean - (1f64.exp() - 1.0)).abs() <= e.error_bound.unwrap());
    /// ```
    pub fn with_estimator(estimator: E) -> Self {
        SobolG {
            estimator,
            config: RunConfig::default(),
        }
    }

    run_settings! {
        setup: "use mcint::{adaptive::SobolG, pdf::UniformBox};\n\
                const DIMS: usize = 2;\n\
                let runner = || SobolG::new(|x: &[f64]| (x[0] * x[1]).exp(), UniformBox::unit(DIMS).unwrap());",
        run: ".run().unwrap()";
        seed, threads, tolerance, time_limit, deadline, cancel_token, progress, cluster
    }

    /// Points of the first stage: a power of two from 256 to 2^28 (default 1024). Without a
    /// tolerance the run stops there; with one it doubles from there.
    ///
    /// ```
    /// use mcint::{adaptive::SobolG, pdf::UniformBox};
    /// let run = |n| SobolG::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(n).run();
    /// assert_eq!(run(4096).unwrap().n, 4096);
    /// assert!(run(1000).unwrap_err().to_string().contains("power of two"));
    /// assert!(run(128).is_err());
    /// ```
    pub fn samples(mut self, points: u64) -> Self {
        self.config.samples = Some(points);
        self
    }

    /// Runs the rule: the first stage, then, with a tolerance, doublings until the bound is
    /// at most `max(abs, rel |mean|)`, the next stage would pass the tolerance's evaluation
    /// limit (or 2^28 points), or a time limit or cancellation stops it (then the estimate of
    /// the last whole stage is returned, with the evaluations of the partial one counted).
    ///
    /// ```
    /// use mcint::{adaptive::SobolG, pdf::UniformBox, stats::{StopReason, Tolerance}};
    /// let f = |x: &[f64]| (-(x[0] * x[0])).exp();
    /// let tight = Tolerance::absolute(1e-14).unwrap().max_evaluations(1 << 14).unwrap();
    /// let e = SobolG::new(f, UniformBox::unit(1).unwrap()).tolerance(tight).run().unwrap();
    /// assert_eq!((e.stop, e.converged, e.n), (StopReason::MaxEvaluations, Some(false), 1 << 14));
    /// ```
    pub fn run(&self) -> Result<Estimate> {
        let dims = self.estimator.canonical_dims();
        let first = self.config.samples.unwrap_or(DEFAULT_FIRST);
        if !(first.is_power_of_two() && (MIN_FIRST..=MAX_POINTS).contains(&first)) {
            return Err(Error::invalid(
                "samples",
                first,
                "a power of two from 256 to 2^28 points for the first stage",
            ));
        }
        let tolerance = self.config.tolerance;
        let per_point = self.estimator.evaluations_per_contribution();
        let limit = match tolerance {
            Some(t) => (t.evaluation_limit() / per_point).min(MAX_POINTS),
            None => first,
        };
        if first > limit {
            return Err(Error::invalid(
                "max_evals",
                limit,
                format!(
                    "at least the {first} points of the first stage ({per_point} evaluations each)"
                ),
            ));
        }
        let sobol = Sobol::new(dims, Scramble::Lms, self.config.seed().unwrap_or(0))?;
        let (executor, _run) = self.config.executor()?;
        let limits = self.config.limits();
        let planned = if tolerance.is_some() {
            0
        } else {
            first * per_point
        };
        let mut doublings = Doublings {
            estimator: &self.estimator,
            sobol: &sobol,
            per_point,
            limit,
            doubling: tolerance.is_some(),
            acc: Accumulator::new(),
            walsh: WalshCoefficients::default(),
            natural: Vec::new(),
            best: None,
            range: (0, first),
            stages: 0,
            spent: 0,
        };
        let targets = Targets::new(1, tolerance, None, &[])?;
        let drive = Drive {
            executor: &executor,
            limits: &limits,
            targets: &targets,
            config: &self.config,
            spent: 0,
            planned,
        };
        let run = engine::drive(&mut doublings, &drive)?;
        run.outputs
            .into_iter()
            .next()
            .ok_or_else(|| Error::invalid("outputs", 0, "one output"))
            .and_then(Estimate::checked)
    }
}

/// A run as stages for the engine's driver: the first stage, then (to a tolerance) stages
/// that double the points of the one sequence, each judged by the Walsh bound of all the
/// values so far.
struct Doublings<'a, E> {
    estimator: &'a E,
    sobol: &'a Sobol,
    /// Evaluations per point, and the most points the run may take.
    per_point: u64,
    limit: u64,
    doubling: bool,
    acc: Accumulator,
    walsh: WalshCoefficients,
    /// The stage's values in natural order (a buffer).
    natural: Vec<f64>,
    /// The estimate of the last stage judged.
    best: Option<Estimate>,
    /// The next stage's points `start .. end`.
    range: (u64, u64),
    stages: u64,
    /// Points evaluated, the stage cut short included.
    spent: u64,
}

impl<E: Estimator> Stages for Doublings<'_, E> {
    fn next(&mut self, _left: u64) -> Result<Next> {
        if self.stages > 0 {
            if !self.doubling {
                return Ok(Next::Done(StopReason::Budget));
            }
            let end = self.range.1;
            if end * 2 > self.limit {
                return Ok(Next::Done(StopReason::MaxEvaluations));
            }
            self.range = (end, 2 * end);
        }
        let (start, end) = self.range;
        Ok(Next::Stage((end - start) * self.per_point))
    }

    fn run(
        &mut self,
        executor: &Executor,
        limits: &Limits,
        progress: &mut dyn FnMut(u64),
    ) -> Result<StageEnd> {
        let (start, end) = self.range;
        // The stage's values in natural order: Sobol' point i is natural point i ^ (i >> 1),
        // which maps [start, end) onto itself.
        self.natural.clear();
        self.natural.resize((end - start) as usize, 0.0);
        let job = StageJob {
            estimator: self.estimator,
            sobol: self.sobol,
            start,
            end,
        };
        let chunks = (end - start).div_ceil(CHUNK);
        let mut first_bad: Option<NonFinite> = None;
        let (natural, acc, spent) = (&mut self.natural, &mut self.acc, &mut self.spent);
        let per_point = self.per_point;
        let stop = executor.run(&job, 0..chunks, 64, limits, |chunk, values| {
            let first_index = start + chunk * CHUNK;
            let bad = values.iter().filter(|y| !y.is_finite()).count() as u64;
            if let Some(found) = first_bad.as_mut() {
                found.count += bad;
            } else if let Some(at) = values.iter().position(|y| !y.is_finite()) {
                let index = first_index + at as u64;
                let mut point = vec![0.0; self.sobol.dims()];
                // The point exists: it was just evaluated.
                self.sobol.point(index, &mut point)?;
                first_bad = Some(NonFinite {
                    count: bad,
                    replicate: 0,
                    index,
                    output: None,
                    value: values[at],
                    point,
                });
            }
            for (offset, &y) in values.iter().enumerate() {
                let i = first_index + offset as u64;
                natural[((i ^ (i >> 1)) - start) as usize] = y;
            }
            acc.extend(&values);
            *spent += values.len() as u64;
            progress((*spent - start) * per_point);
            Ok(())
        })?;
        if stop.is_some() || first_bad.is_some() {
            return Ok(StageEnd {
                stop,
                non_finite: first_bad,
            });
        }
        // Judging a stage transforms all its values, seconds of serial work for a large one:
        // a limit reached meanwhile stops it, and the last stage judged stands.
        if start == 0 {
            self.walsh = WalshCoefficients::new(std::mem::take(&mut self.natural));
        } else if !self.walsh.double(&mut self.natural, &|| {
            // Read in agreement over MPI ranks, which all ask as often.
            executor.reached(limits).map_or(true, |stop| stop.is_some())
        }) {
            let stop = executor.reached(limits)?.unwrap_or(StopReason::Cancelled);
            return Ok(StageEnd {
                stop: Some(stop),
                non_finite: None,
            });
        }
        self.stages += 1;
        let mut estimate =
            bounded_estimate(&self.acc, FUDGE / end as f64 * self.walsh.lagged_sum());
        estimate.iterations = self.stages;
        self.best = Some(estimate);
        Ok(StageEnd::default())
    }

    fn has_estimate(&self) -> bool {
        self.best.is_some()
    }

    fn estimate(&mut self) -> Result<Option<VectorEstimate>> {
        Ok(self.best.clone().map(|mut estimate| {
            estimate.evaluations = self.spent * self.per_point;
            VectorEstimate::assemble(vec![estimate], None)
        }))
    }
}

/// The estimate of the values folded into `acc` with the Walsh bound `bound`, raised to the
/// rounding error of the mean where that is larger.
fn bounded_estimate(acc: &Accumulator, bound: f64) -> Estimate {
    let mut estimate = acc.estimate();
    estimate.std_error = None;
    estimate.dof = None;
    estimate.basis = ErrorBasis::WalshBound;
    estimate.error_bound = Some(bound.max(estimate.rounding_error));
    // The per-sample warnings (a standard error at the rounding floor) do not apply.
    estimate
        .warnings
        .retain(|w| matches!(w, Warning::AllZero { .. }));
    estimate
}

/// One stage's points `start .. end` in chunks of `CHUNK`, each giving its contributions
/// in index order.
struct StageJob<'a, E> {
    estimator: &'a E,
    sobol: &'a Sobol,
    start: u64,
    end: u64,
}

impl<E: Estimator> ChunkJob for StageJob<'_, E> {
    type Scratch = Points;
    type Output = Vec<f64>;

    fn scratch(&self) -> Result<Points> {
        Points::new(self.sobol.dims(), CHUNK as usize)
    }

    fn run(&self, points: &mut Points, chunk: u64, _: &Limits) -> Result<Option<Vec<f64>>> {
        let first = self.start + chunk * CHUNK;
        let len = CHUNK.min(self.end - first) as usize;
        points.set_len(len);
        self.sobol.fill(first, points)?;
        let mut values = vec![0.0; len];
        self.estimator.contributions(points, &mut values);
        Ok(Some(values))
    }

    fn origin(&self, chunk: u64) -> (u64, u64) {
        (0, self.start + chunk * CHUNK)
    }
}
