//! [`Integrator`]: the front door that drives sampler, estimator and accumulator.
//!
//! The index range of every replicate is cut into fixed chunks, independent of the thread
//! count; threads take chunks in any order, and the chunk accumulators are merged in chunk
//! order afterwards. Every point is a pure function of its index, so the result is
//! bit-identical for any number of threads.

use crate::estimator::{BatchUniformEstimator, Estimator, ImportanceEstimator, UniformEstimator};
use crate::pdf::{Pdf, UniformBox};
use crate::sampler::{Independent, PassKind, Sampler};
use crate::stats::{Accumulator, Estimate, Tolerance};
use crate::{Error, Points, Result};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

mod non_finite;
mod partial;
mod staged;

pub use non_finite::NonFinitePolicy;
pub use partial::PartialRun;

/// Points generated and evaluated together: small enough to stay in L1/L2 cache.
const BLOCK: u64 = 1024;
/// Chunk results held in memory at once by a run: bounds the memory of huge runs.
const CHUNKS_IN_MEMORY: u64 = 1 << 16;
/// Points per unit of work handed to a thread (and per partial accumulator).
const CHUNK: u64 = 16 * BLOCK;
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
/// [`fill`](Sampler::fill) and hands it straight to the estimator's
/// [`contributions`](Estimator::contributions), reusing the same block and value buffers for
/// the whole run; no buffer of all the points is ever built, so memory traffic does not grow
/// with the number of samples. A batch integrand ([`over_box_batch`](Integrator::over_box_batch))
/// sees those blocks directly.
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
    sampler: Option<Box<dyn Sampler>>,
    samples: Option<u64>,
    replicates: Option<u64>,
    seed: Option<u64>,
    threads: Option<usize>,
    tolerance: Option<Tolerance>,
    non_finite: NonFinitePolicy,
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync> Integrator<UniformEstimator<F>> {
    /// Integrates `f` over a box with the uniform estimator (A.14).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let e = Integrator::over_box(|x: &[f64]| x[0], UniformBox::new(vec![0.0], vec![2.0]).unwrap())
    ///     .samples(10_000)
    ///     .run()
    ///     .unwrap();
    /// assert!((e.mean - 2.0).abs() < 5.0 * e.std_error.unwrap());
    /// ```
    pub fn over_box(f: F, domain: UniformBox) -> Self {
        Integrator::new(UniformEstimator::new(f, domain))
    }
}

impl<F: Fn(&Points, &mut [f64]) + Send + Sync> Integrator<BatchUniformEstimator<F>> {
    /// Integrates a batch integrand over a box with the uniform estimator (A.14): `f(points,
    /// out)` gets a block of up to 1024 domain points (one column per coordinate) and must
    /// write `f(x_i)` to every `out[i]`; see [`BatchUniformEstimator`]. With the same
    /// arithmetic per point, the estimate has the same bits as [`over_box`](Integrator::over_box).
    ///
    /// ```
    /// use mcint::{Integrator, Points, pdf::UniformBox};
    /// // x0 * x1 over [0, 2)^2 is 4, one column pass per coordinate.
    /// let product = |p: &Points, out: &mut [f64]| {
    ///     for (y, (&x0, &x1)) in out.iter_mut().zip(p.column(0).iter().zip(p.column(1))) {
    ///         *y = x0 * x1;
    ///     }
    /// };
    /// let domain = UniformBox::new(vec![0.0; 2], vec![2.0; 2]).unwrap();
    /// let batch = Integrator::over_box_batch(product, domain.clone()).samples(10_000).run().unwrap();
    /// assert!((batch.mean - 4.0).abs() < 5.0 * batch.std_error.unwrap());
    /// let per_point = Integrator::over_box(|x: &[f64]| x[0] * x[1], domain).samples(10_000).run().unwrap();
    /// assert_eq!(batch, per_point);
    /// ```
    pub fn over_box_batch(f: F, domain: UniformBox) -> Self {
        Integrator::new(BatchUniformEstimator::new(f, domain))
    }
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync, P: Pdf> Integrator<ImportanceEstimator<F, P>> {
    /// Integrates `f` over the domain of `pdf`, sampling from `pdf` (A.19).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::Exponential};
    /// // The integral of x e^{-x} over [0, inf) is 1.
    /// let pdf = Exponential::new(1.0, 0.0, f64::INFINITY).unwrap();
    /// let e = Integrator::with_pdf(|x: &[f64]| x[0] * (-x[0]).exp(), pdf).samples(20_000).run().unwrap();
    /// assert!((e.mean - 1.0).abs() < 5.0 * e.std_error.unwrap());
    /// ```
    pub fn with_pdf(f: F, pdf: P) -> Self {
        Integrator::new(ImportanceEstimator::new(f, pdf))
    }
}

impl<E: Estimator> Integrator<E> {
    /// An integrator for any estimator, with independent points, one replicate, `2^16`
    /// samples and all available threads until told otherwise.
    ///
    /// ```
    /// use mcint::{Integrator, estimator::UniformEstimator, pdf::UniformBox};
    /// let est = UniformEstimator::new(|_: &[f64]| 3.0, UniformBox::unit(1).unwrap());
    /// assert_eq!(Integrator::new(est).run().unwrap().mean, 3.0);
    /// ```
    pub fn new(estimator: E) -> Self {
        Integrator {
            estimator,
            sampler: None,
            samples: None,
            replicates: None,
            seed: None,
            threads: None,
            tolerance: None,
            non_finite: NonFinitePolicy::Fail,
        }
    }

    /// The sampler that provides canonical points; its dimension must equal the estimator's
    /// canonical dimension. A seed set with [`seed`](Self::seed) overrides the sampler's.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox, sampler::LatinHypercube};
    /// let e = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .sampler(LatinHypercube::new(1, 100, 0).unwrap())
    ///     .samples(100)
    ///     .run()
    ///     .unwrap();
    /// assert_eq!(e.std_error, None); // one replicate of stratified points: no honest error bar
    /// ```
    pub fn sampler(mut self, sampler: impl Sampler + 'static) -> Self {
        let mut boxed: Box<dyn Sampler> = Box::new(sampler);
        if let Some(seed) = self.seed {
            boxed.reseed(seed);
        }
        self.sampler = Some(boxed);
        self
    }

    /// Points per replicate (at least 1; a multiple of the pass size for samplers with
    /// fixed passes, at most the pass size for extensible sequences). Defaults to the pass
    /// size for fixed passes and `2^16` otherwise.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let e = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).samples(10).run().unwrap();
    /// assert_eq!(e.n, 10);
    /// ```
    pub fn samples(mut self, samples: u64) -> Self {
        self.samples = Some(samples);
        self
    }

    /// Number of independent replicates (at least 1; default 1).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let e = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .samples(10).replicates(3).run().unwrap();
    /// assert_eq!((e.n, e.replicates), (30, 3));
    /// ```
    pub fn replicates(mut self, replicates: u64) -> Self {
        self.replicates = Some(replicates);
        self
    }

    /// The seed of the sampler's randomization (the same seed gives the same result).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let run = |seed| Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .samples(100).seed(seed).run().unwrap().mean;
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
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let run = |t| Integrator::over_box(|x: &[f64]| x[0].sin(), UniformBox::unit(1).unwrap())
    ///     .samples(100_000).threads(t).run().unwrap();
    /// assert_eq!(run(1), run(3));
    /// ```
    pub fn threads(mut self, threads: usize) -> Self {
        self.threads = Some(threads);
        self
    }

    /// Runs until the estimate meets `tolerance` (or its evaluation or time limit), instead
    /// of a fixed number of samples.
    ///
    /// Independent points use a two-stage rule: a pilot of [`samples`](Self::samples) points
    /// (default 4096) estimates the standard deviation `s`, and a fresh main stage of
    /// `(1.96 * 1.1 * s / target)^2` points, independent of the pilot, gives the estimate and
    /// its CLT interval (the factor 1.1 inflates the variance against an unlucky pilot; should
    /// the main stage still miss, it is extended by the same rule). The interval assumes the
    /// CLT holds at that size, which needs `n` well above the square of the integrand's
    /// skewness: sharply peaked or heavy-tailed integrands need a tighter tolerance, or
    /// importance sampling.
    ///
    /// Randomized QMC and stratified points keep `R` replicates (default 16; set with
    /// [`replicates`](Self::replicates)) and double the points per replicate, starting from
    /// [`samples`](Self::samples) (default: the pass size, or 1024), until the Student-t
    /// interval over the replicates meets the tolerance. Each stage adds only the new points.
    /// The replicates' standard error is inflated by 1.2 (as in QMCPy's `CubQMCCLT`):
    /// replicate means of scrambled nets at small sizes are not normal, and stopping the first
    /// time the spread looks small favours runs whose spread is small by chance; without it
    /// the intervals cover less often than they say.
    ///
    /// [`Estimate::evaluations`] counts every evaluation spent, pilot included; `stop`,
    /// `converged` and `iterations` (stages) say how the run ended.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox, stats::{StopReason, Tolerance}};
    /// let e = Integrator::over_box(|x: &[f64]| x[0] * x[0], UniformBox::unit(1).unwrap())
    ///     .tolerance(Tolerance::absolute(1e-3).unwrap())
    ///     .seed(1)
    ///     .run()
    ///     .unwrap();
    /// assert_eq!((e.stop, e.converged), (StopReason::ToleranceMet, Some(true)));
    /// assert!(e.half_width(0.95).unwrap().unwrap() <= 1e-3);
    /// ```
    pub fn tolerance(mut self, tolerance: Tolerance) -> Self {
        self.tolerance = Some(tolerance);
        self
    }

    /// What to do with NaN or infinite contributions: fail (the default) or skip and count
    /// them (see [`NonFinitePolicy`]).
    ///
    /// ```
    /// use mcint::{Integrator, NonFinitePolicy, pdf::UniformBox};
    /// let e = Integrator::over_box(|x: &[f64]| 1.0 / x[0].round(), UniformBox::unit(1).unwrap())
    ///     .samples(100)
    ///     .non_finite(NonFinitePolicy::Skip)
    ///     .run()
    ///     .unwrap();
    /// assert_eq!(e.n + e.non_finite, 100);
    /// ```
    pub fn non_finite(mut self, policy: NonFinitePolicy) -> Self {
        self.non_finite = policy;
        self
    }

    /// Runs the integration.
    ///
    /// Errors when a setting is out of range, when the sampler's dimension differs from the
    /// estimator's, and when any contribution is NaN or infinite (the error gives their count
    /// and the first offending point): such a mean would be silently wrong. With
    /// [`NonFinitePolicy::Skip`] they are left out and counted instead, but a replicate with
    /// no finite contribution at all is still an error.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let bad = Integrator::over_box(|x: &[f64]| 1.0 / (x[0] - x[0]), UniformBox::unit(1).unwrap())
    ///     .samples(10)
    ///     .run();
    /// assert!(bad.unwrap_err().to_string().contains("10 non-finite"));
    /// ```
    pub fn run(&self) -> Result<Estimate> {
        self.with_sampler(|sampler, threads| {
            if let Some(tolerance) = &self.tolerance {
                return staged::run_to_tolerance(self, sampler, threads, tolerance);
            }
            let plan = Plan::new(self, sampler)?;
            let folded = plan.run_folded(sampler, &self.estimator, threads)?;
            plan.finish(self, sampler, &folded)
        })
    }

    /// Calls `work` with the sampler (the default one built if none was given) and the
    /// number of threads.
    fn with_sampler<R>(&self, work: impl FnOnce(&dyn Sampler, usize) -> Result<R>) -> Result<R> {
        let threads = crate::threads::resolve(self.threads)?;
        match &self.sampler {
            Some(s) => work(s.as_ref(), threads),
            None => {
                let sampler =
                    Independent::new(self.estimator.canonical_dims(), self.seed.unwrap_or(0))?;
                work(&sampler, threads)
            }
        }
    }
}

/// The index layout of one run: which sample indices each replicate uses.
struct Plan {
    /// Points per replicate in this run.
    samples: u64,
    /// Local index (within each replicate) of the first point of this run: later stages of
    /// a run to a tolerance continue where the earlier ones stopped.
    offset: u64,
    replicates: u64,
    /// Distance between the first indices of consecutive replicates.
    stride: u64,
    chunks_per_replicate: u64,
}

impl Plan {
    fn new<E: Estimator>(integrator: &Integrator<E>, sampler: &dyn Sampler) -> Result<Plan> {
        let dims = integrator.estimator.canonical_dims();
        if sampler.dims() != dims {
            return Err(Error::DimensionMismatch {
                what: "sampler (the estimator's canonical points)",
                expected: dims,
                found: sampler.dims(),
            });
        }
        let replicates = integrator.replicates.unwrap_or(1);
        if replicates == 0 {
            return Err(Error::invalid("replicates", 0, "at least 1"));
        }
        if replicates > 1 && !sampler.is_randomized() {
            return Err(Error::invalid(
                "replicates",
                replicates,
                format!(
                    "1 for the unrandomized {} sampler (its passes repeat each other; choose a \
                     scramble to get independent replicates and an error bar)",
                    sampler.name()
                ),
            ));
        }
        let passes = sampler.passes();
        let samples = integrator.samples.unwrap_or(match passes {
            PassKind::Fixed { size } => size,
            _ => DEFAULT_SAMPLES,
        });
        if samples == 0 {
            return Err(Error::invalid(
                "samples",
                0,
                "at least 1 point per replicate",
            ));
        }
        let stride = match passes {
            PassKind::Independent => samples,
            PassKind::Fixed { size } => {
                if !samples.is_multiple_of(size) {
                    let below = samples / size * size;
                    let nearest = if below == 0 {
                        format!("{size}")
                    } else {
                        format!("{below} or {}", below.saturating_add(size))
                    };
                    return Err(Error::invalid(
                        "samples",
                        samples,
                        format!(
                            "a multiple of the {} sampler's pass size {size} (nearest: {nearest})",
                            sampler.name()
                        ),
                    ));
                }
                samples
            }
            PassKind::Extensible { max } => {
                if samples > max {
                    return Err(Error::invalid(
                        "samples",
                        samples,
                        format!(
                            "at most {max} points per replicate for the {} sampler",
                            sampler.name()
                        ),
                    ));
                }
                max
            }
        };
        let overflow = Error::IndexOutOfRange {
            what: "sample index of the last replicate",
            limit: u64::MAX,
        };
        (replicates - 1)
            .checked_mul(stride)
            .and_then(|s| s.checked_add(samples))
            .ok_or(overflow)?;
        Ok(Plan {
            samples,
            offset: 0,
            replicates,
            stride,
            chunks_per_replicate: samples.div_ceil(CHUNK),
        })
    }

    fn total_chunks(&self) -> Result<u64> {
        self.replicates
            .checked_mul(self.chunks_per_replicate)
            .ok_or(Error::IndexOutOfRange {
                what: "number of work chunks",
                limit: u64::MAX,
            })
    }

    /// Replicate number and the range of local indices (within the replicate) of a chunk.
    fn chunk_range(&self, chunk: u64) -> (u64, u64, u64) {
        let replicate = chunk / self.chunks_per_replicate;
        let first = self.offset + (chunk % self.chunks_per_replicate) * CHUNK;
        // Saturating: a replicate may end at the very last index, u64::MAX - 1.
        let end = self.offset.saturating_add(self.samples);
        (replicate, first, first.saturating_add(CHUNK).min(end))
    }

    /// Evaluates every chunk on `threads` workers, at most `CHUNKS_IN_MEMORY` at a time, and
    /// folds the results in chunk order.
    fn run_folded<E: Estimator>(
        &self,
        sampler: &dyn Sampler,
        estimator: &E,
        threads: usize,
    ) -> Result<Folded> {
        let total = self.total_chunks()?;
        let mut folded = Folded::new(self.replicates);
        let mut start = 0;
        while start < total {
            let end = start.saturating_add(CHUNKS_IN_MEMORY).min(total);
            let results = run_chunk_range(self, sampler, estimator, threads, start..end)?;
            for (chunk, result) in (start..end).zip(&results) {
                folded.add(self, chunk, result);
            }
            start = end;
        }
        Ok(folded)
    }

    /// Fails with the first offending point when a contribution was not finite (under
    /// [`NonFinitePolicy::Skip`], only when a replicate has no finite contribution left).
    fn check_finite(
        &self,
        sampler: &dyn Sampler,
        folded: &Folded,
        policy: NonFinitePolicy,
    ) -> Result<()> {
        let reps = &folded.replicates;
        let count: u64 = reps.iter().map(|r| r.non_finite()).sum();
        let Some(first) = folded.first_non_finite else {
            return Ok(());
        };
        if policy == NonFinitePolicy::Skip {
            return match reps.iter().position(|r| r.count() == 0) {
                None => Ok(()),
                Some(replicate) => Err(Error::invalid(
                    "integrand",
                    format!("non-finite at every point of replicate {replicate}"),
                    "at least one finite contribution per replicate, even when skipping",
                )),
            };
        }
        let mut point = vec![0.0; sampler.dims()];
        sampler.point(first.replicate * self.stride + first.index, &mut point)?;
        Err(Error::NonFiniteContribution {
            count,
            first_index: first.index,
            first_replicate: first.replicate,
            first_value: first.value,
            first_point: point,
        })
    }

    /// The estimate from every chunk's result, folded in chunk order: the same bits
    /// whichever threads, processes or checkpoints produced the chunks.
    fn finish<E: Estimator>(
        &self,
        integrator: &Integrator<E>,
        sampler: &dyn Sampler,
        folded: &Folded,
    ) -> Result<Estimate> {
        self.check_finite(sampler, folded, integrator.non_finite)?;
        self.estimate(sampler.passes(), &folded.replicates)
    }

    fn estimate(&self, passes: PassKind, reps: &[Accumulator]) -> Result<Estimate> {
        if passes == PassKind::Independent {
            // Independent points: all samples are iid, so the per-sample variance is honest.
            let mut all = Accumulator::new();
            for r in reps {
                all.merge(r);
            }
            let mut estimate = all.estimate();
            estimate.replicates = self.replicates;
            return Ok(estimate);
        }
        let means: Vec<f64> = reps.iter().map(|r| r.mean()).collect();
        let mut estimate = Estimate::from_replicates(&means, self.samples)?;
        estimate.non_finite = reps.iter().map(Accumulator::non_finite).sum();
        estimate.n = reps.iter().map(Accumulator::count).sum();
        Ok(estimate)
    }
}

/// Where the first non-finite contribution of a chunk occurred.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct NonFinite {
    replicate: u64,
    index: u64,
    /// NaN or an infinity, serialized by its bits (JSON has no form for them).
    #[cfg_attr(feature = "serde", serde(with = "f64_bits"))]
    value: f64,
}

/// Serializes an `f64` as its IEEE-754 bits, so NaN and infinities survive any format.
#[cfg(feature = "serde")]
mod f64_bits {
    pub fn serialize<S: serde::Serializer>(value: &f64, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u64(value.to_bits())
    }

    pub fn deserialize<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        let bits: u64 = serde::Deserialize::deserialize(d)?;
        Ok(f64::from_bits(bits))
    }
}

/// What one chunk of work produced.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct ChunkResult {
    accumulator: Accumulator,
    first_non_finite: Option<NonFinite>,
}

/// Chunk results folded in chunk order: one accumulator per replicate, and the first
/// non-finite contribution.
struct Folded {
    replicates: Vec<Accumulator>,
    first_non_finite: Option<NonFinite>,
}

impl Folded {
    fn new(replicates: u64) -> Folded {
        Folded {
            replicates: vec![Accumulator::new(); replicates as usize],
            first_non_finite: None,
        }
    }

    /// Adds the result of `chunk`; chunks must come in index order.
    fn add(&mut self, plan: &Plan, chunk: u64, result: &ChunkResult) {
        let replicate = (chunk / plan.chunks_per_replicate) as usize;
        self.replicates[replicate].merge(&result.accumulator);
        if self.first_non_finite.is_none() {
            self.first_non_finite = result.first_non_finite;
        }
    }
}

/// Evaluates chunks `range` on `threads` workers and returns the results in chunk order.
fn run_chunk_range<E: Estimator>(
    plan: &Plan,
    sampler: &dyn Sampler,
    estimator: &E,
    threads: usize,
    range: std::ops::Range<u64>,
) -> Result<Vec<ChunkResult>> {
    let (first, total) = (range.start, range.end.saturating_sub(range.start));
    let slots = usize::try_from(total).map_err(|_| Error::IndexOutOfRange {
        what: "number of work chunks",
        limit: usize::MAX as u64,
    })?;
    let next = AtomicU64::new(0);
    let failed = AtomicBool::new(false);
    let first_error: Mutex<Option<Error>> = Mutex::new(None);
    let workers = threads.min(slots.max(1));
    let mut results: Vec<Option<ChunkResult>> = vec![None; slots];

    let per_worker: Vec<Vec<(u64, ChunkResult)>> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..workers)
            .map(|_| {
                scope.spawn(|| {
                    let mut done = Vec::new();
                    let mut work = match Workspace::new(sampler.dims()) {
                        Ok(work) => work,
                        Err(e) => {
                            failed.store(true, Ordering::Relaxed);
                            if let Ok(mut slot) = first_error.lock() {
                                slot.get_or_insert(e);
                            }
                            return done;
                        }
                    };
                    loop {
                        let chunk = next.fetch_add(1, Ordering::Relaxed);
                        if chunk >= total || failed.load(Ordering::Relaxed) {
                            break;
                        }
                        match work.run_chunk(plan, sampler, estimator, first + chunk) {
                            Ok(result) => done.push((chunk, result)),
                            Err(e) => {
                                failed.store(true, Ordering::Relaxed);
                                if let Ok(mut slot) = first_error.lock() {
                                    slot.get_or_insert(e);
                                }
                                break;
                            }
                        }
                    }
                    done
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_default())
            .collect()
    });

    if let Some(e) = first_error.into_inner().ok().flatten() {
        return Err(e);
    }
    for (chunk, result) in per_worker.into_iter().flatten() {
        results[chunk as usize] = Some(result);
    }
    results
        .into_iter()
        .collect::<Option<Vec<_>>>()
        .ok_or_else(crate::threads::worker_panicked)
}

/// Per-thread buffers, allocated once.
struct Workspace {
    points: Points,
    values: Vec<f64>,
}

impl Workspace {
    fn new(dims: usize) -> Result<Workspace> {
        Ok(Workspace {
            points: Points::new(dims, BLOCK as usize)?,
            values: vec![0.0; BLOCK as usize],
        })
    }

    fn run_chunk<E: Estimator>(
        &mut self,
        plan: &Plan,
        sampler: &dyn Sampler,
        estimator: &E,
        chunk: u64,
    ) -> Result<ChunkResult> {
        let (replicate, first, end) = plan.chunk_range(chunk);
        let base = replicate * plan.stride;
        let mut accumulator = Accumulator::new();
        let mut first_non_finite = None;
        let mut start = first;
        while start < end {
            let len = (end - start).min(BLOCK) as usize;
            self.points.set_len(len);
            sampler.fill(base + start, &mut self.points)?;
            let values = &mut self.values[..len];
            estimator.contributions(&self.points, values);
            let before = accumulator.non_finite();
            accumulator.extend(values);
            if accumulator.non_finite() > before && first_non_finite.is_none() {
                first_non_finite =
                    values
                        .iter()
                        .position(|y| !y.is_finite())
                        .map(|offset| NonFinite {
                            replicate,
                            index: start + offset as u64,
                            value: values[offset],
                        });
            }
            start += len as u64;
        }
        Ok(ChunkResult {
            accumulator,
            first_non_finite,
        })
    }
}
