//! [`TwoStage`]: two-stage adaptive stratified sampling that stays unbiased (Kirk & Arvo,
//! "Unbiased sampling techniques for image synthesis", SIGGRAPH 1991).
//!
//! The domain is cut into a grid of `k^d` equal strata. A pilot stage samples every stratum a
//! few times and estimates each stratum's standard deviation `sigma_j`; the main budget is
//! then shared by Neyman allocation, `n_j ∝ V_j sigma_j`, with at least two points in every
//! stratum (so a stratum whose pilot happened to see no variation is still sampled, and still
//! has a variance estimate). The estimate uses only the second-stage samples:
//!
//! `I = sum_j V_j mean_j`, `Var = sum_j V_j^2 s_j^2 / n_j`.
//!
//! Given the pilot, the allocation is fixed and the second-stage samples are fresh, so
//! `E[I | pilot] = I` exactly and the variance estimate is unbiased too: the adaptivity costs
//! no bias. The degrees of freedom of the Student-t interval are Welch-Satterthwaite's.
//!
//! The naive alternative, [`TwoStage::reuse_pilot`], also averages the pilot samples into
//! each stratum. Its allocation depends on the very samples it averages, so it is biased (the
//! seed's A.3.5): a stratum whose pilot saw a rare large value gets many more samples, which
//! dilute that value, while a stratum whose pilot saw only small values keeps them at full
//! weight, so rare large values are systematically under-counted.

use super::batches::{BLOCK, Batches, Workspace};
use super::cell::Cell;
use super::scalar_batch::{ScalarBatch, ScalarIntegrand};
use crate::engine::{
    self, ChunkJob, Drive, Executor, Limits, Next, NonFinite, RunConfig, StageEnd, Stages, Targets,
    run_settings,
};
use crate::error::{Error, Result};
use crate::pdf::{Pdf, UniformBox};
use crate::points::Points;
use crate::stats::rounding::{UNIT_ROUNDOFF, gamma};
use crate::stats::{Accumulator, ErrorBasis, Estimate, StopReason, VectorEstimate};

/// Pilot points per stratum without [`TwoStage::pilot`].
const DEFAULT_PILOT: u64 = 8;
/// Without [`TwoStage::samples`], the total is this many times the pilot.
const DEFAULT_TOTAL_PER_PILOT: u64 = 4;
/// Second-stage points every stratum gets whatever its pilot showed.
const MIN_MAIN: u64 = 2;
/// The most strata a grid may have (the per-stratum statistics are kept in memory).
const MAX_STRATA: u64 = 1 << 24;
/// The most strata [`TwoStage::strata_per_axis_for`] plans: each costs memory (its
/// statistics in both stages), and beyond this many more strata gain little.
const MAX_PLANNED_STRATA: u64 = 1 << 20;
/// Coordinates a chunk of work draws at most (about): a stratum with more points is sampled
/// in pieces, so that limits are checked every few milliseconds of work whatever the strata
/// and the dimension.
const CHUNK_COORDINATES: u64 = 1 << 22;
/// The fewest and the most evaluations of a chunk, whatever the dimension.
const CHUNK_EVALUATIONS: (u64, u64) = (BLOCK as u64, 1 << 16);
/// Chunks evaluated between two checks of the window's outputs (bounds their memory).
const WINDOW: u64 = 256;

/// Two-stage adaptive stratified sampling: a pilot estimates each stratum's spread, the main
/// budget follows Neyman allocation, and the estimate comes from fresh samples only.
///
/// Points come from any [`Sampler`](crate::Sampler) with independent points or extensible passes (a scrambled
/// Sobol' sequence gives every stratum's batch its own randomized net). Strata are units of
/// work, so the result is bit-identical for any thread count.
///
/// ```
/// use mcint::{adaptive::TwoStage, pdf::UniformBox};
/// // A peak in one corner: most of the variance sits in a few strata.
/// let f = |x: &[f64]| (-200.0 * ((x[0] - 0.9).powi(2) + (x[1] - 0.9).powi(2))).exp();
/// let e = TwoStage::new(f, UniformBox::unit(2).unwrap(), 8)
///     .pilot(8)
///     .samples(20_000)
///     .seed(5)
///     .run()
///     .unwrap();
/// let half = 0.5 * (std::f64::consts::PI / 200.0).sqrt();
/// let axis = half * (libm::erf(0.9 * 200f64.sqrt()) + libm::erf(0.1 * 200f64.sqrt()));
/// assert!((e.mean - axis * axis).abs() < 5.0 * e.std_error.unwrap());
/// assert_eq!(e.evaluations, 20_000);
/// ```
pub struct TwoStage<F> {
    f: F,
    domain: UniformBox,
    strata_per_axis: usize,
    pilot: u64,
    reuse_pilot: bool,
    config: RunConfig,
}

impl<F: Fn(&[f64]) -> f64 + Sync> TwoStage<F> {
    /// Two-stage sampling of `f` over a box cut into `strata_per_axis^d` equal strata
    /// (`strata_per_axis >= 1`, at most `2^24` strata), with 8 pilot points per stratum, a
    /// total of 4 times the pilot, independent points and all threads until told otherwise.
    ///
    /// ```
    /// use mcint::{adaptive::TwoStage, pdf::UniformBox};
    /// let e = TwoStage::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap(), 16).run().unwrap();
    /// assert_eq!(e.evaluations, 4 * 8 * 16);
    /// assert!(TwoStage::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap(), 0).run().is_err());
    /// ```
    pub fn new(f: F, domain: UniformBox, strata_per_axis: usize) -> Self {
        TwoStage::with_defaults(f, domain, strata_per_axis)
    }

    /// Runs both stages.
    ///
    /// Errors name the setting that is out of range, report a sampler of the wrong dimension
    /// or kind, and report NaN or infinite integrand values (their count and the first point,
    /// in coordinates relative to the domain).
    ///
    /// ```
    /// use mcint::{adaptive::TwoStage, pdf::UniformBox, stats::ErrorBasis};
    /// let e = TwoStage::new(|x: &[f64]| x[0] * x[0], UniformBox::unit(1).unwrap(), 8).run().unwrap();
    /// assert_eq!((e.basis, e.iterations), (ErrorBasis::PerSample, 2));
    /// ```
    pub fn run(&self) -> Result<Estimate> {
        self.run_with(&self.f)
    }
}

impl<G: Fn(&Points, &mut [f64]) + Sync> TwoStage<ScalarBatch<G>> {
    /// Two-stage sampling of an integrand evaluated a block of points at a time (see
    /// [`ScalarBatch`]; the points of a block may lie in many strata), with the defaults of
    /// [`new`](TwoStage::new): the same points, allocation and bits as the per-point integrand
    /// with the same values.
    ///
    /// ```
    /// use mcint::{adaptive::TwoStage, pdf::UniformBox, Points};
    /// let per_point = TwoStage::new(|x: &[f64]| x[0] * x[1], UniformBox::unit(2).unwrap(), 8);
    /// let by_blocks = TwoStage::new_batch(
    ///     |p: &Points, out: &mut [f64]| {
    ///         for (y, (a, b)) in out.iter_mut().zip(p.column(0).iter().zip(p.column(1))) {
    ///             *y = a * b;
    ///         }
    ///     },
    ///     UniformBox::unit(2).unwrap(),
    ///     8,
    /// );
    /// let (a, b) = (per_point.seed(3).run().unwrap(), by_blocks.seed(3).run().unwrap());
    /// assert_eq!(a.mean.to_bits(), b.mean.to_bits());
    /// ```
    pub fn new_batch(f: G, domain: UniformBox, strata_per_axis: usize) -> Self {
        TwoStage::with_defaults(ScalarBatch(f), domain, strata_per_axis)
    }

    /// Runs both stages, as [`TwoStage::run`] does for a per-point integrand.
    ///
    /// ```
    /// use mcint::{adaptive::TwoStage, pdf::UniformBox, Points};
    /// let f = |p: &Points, out: &mut [f64]| out.fill(f64::INFINITY);
    /// let bad = TwoStage::new_batch(f, UniformBox::unit(1).unwrap(), 4).run();
    /// assert!(bad.unwrap_err().to_string().contains("non-finite"));
    /// ```
    pub fn run(&self) -> Result<Estimate> {
        self.run_with(&self.f)
    }
}

impl<F> TwoStage<F> {
    /// Two-stage sampling over `f` (per point or by blocks) with the defaults of `new`.
    fn with_defaults(f: F, domain: UniformBox, strata_per_axis: usize) -> Self {
        TwoStage {
            f,
            domain,
            strata_per_axis,
            pilot: DEFAULT_PILOT,
            reuse_pilot: false,
            config: RunConfig::default(),
        }
    }

    run_settings! {
        setup: "use mcint::{adaptive::TwoStage, pdf::UniformBox};\n\
                const DIMS: usize = 2;\n\
                let runner = || TwoStage::new(|x: &[f64]| (x[0] * x[1]).exp(), UniformBox::unit(DIMS).unwrap(), 8).samples(4096);",
        run: ".run().unwrap()";
        sampler, seed, threads, non_finite, time_limit, deadline, cancel_token, progress, cluster
    }

    /// Pilot points per stratum (at least 2, for a standard deviation; default 8).
    ///
    /// ```
    /// use mcint::{adaptive::TwoStage, pdf::UniformBox};
    /// let run = |p| TwoStage::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap(), 4).pilot(p).run();
    /// assert!(run(4).is_ok());
    /// assert!(run(1).unwrap_err().to_string().contains("pilot"));
    /// ```
    pub fn pilot(mut self, per_stratum: u64) -> Self {
        self.pilot = per_stratum;
        self
    }

    /// Total evaluations of the run (its one replicate), pilot included (at least
    /// `(pilot + 2)` per stratum; default `4 pilot` per stratum).
    ///
    /// ```
    /// use mcint::{adaptive::TwoStage, pdf::UniformBox};
    /// let run = |n| TwoStage::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap(), 4).pilot(2).samples(n).run();
    /// assert_eq!(run(100).unwrap().evaluations, 100);
    /// assert!(run(15).unwrap_err().to_string().contains("samples"));
    /// ```
    pub fn samples(mut self, evaluations: u64) -> Self {
        self.config.samples = Some(evaluations);
        self
    }

    /// Also average the pilot samples into the estimate (default false). This is the naive
    /// variant and it is **biased**: the allocation depends on the samples it then averages.
    /// It exists to show that bias; do not use it for answers.
    ///
    /// ```
    /// use mcint::{adaptive::TwoStage, pdf::UniformBox};
    /// // For a linear integrand the pilot's spread says nothing about its mean, so no bias shows.
    /// let e = TwoStage::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap(), 4)
    ///     .reuse_pilot(true).samples(4000).run().unwrap();
    /// assert!((e.mean - 0.5).abs() < 5.0 * e.std_error.unwrap());
    /// ```
    pub fn reuse_pilot(mut self, reuse: bool) -> Self {
        self.reuse_pilot = reuse;
        self
    }

    /// The run over `f` (the integrand, per point or by blocks), its result checked for
    /// overflow.
    fn run_with<E: ScalarIntegrand>(&self, f: &E) -> Result<Estimate> {
        self.run_unchecked(f).and_then(Estimate::checked)
    }

    /// [`run_with`](Self::run_with) before its result is checked for overflow.
    fn run_unchecked<E: ScalarIntegrand>(&self, f: &E) -> Result<Estimate> {
        let dims = self.domain.dims();
        let strata = self.strata()?;
        if self.pilot < 2 {
            return Err(Error::invalid(
                "pilot",
                self.pilot,
                "at least 2 points per stratum (a standard deviation needs two)",
            ));
        }
        let Some(least) = self
            .pilot
            .checked_add(MIN_MAIN)
            .and_then(|n| strata.checked_mul(n))
        else {
            return Err(Error::invalid(
                "pilot",
                self.pilot,
                format!("a pilot whose {strata} strata x (pilot + {MIN_MAIN}) points fit 64 bits"),
            ));
        };
        let total = self.config.samples.unwrap_or_else(|| {
            strata
                .saturating_mul(self.pilot)
                .saturating_mul(DEFAULT_TOTAL_PER_PILOT)
        });
        self.config.check_budget("samples", total)?;
        if total < least {
            return Err(Error::invalid(
                "samples",
                total,
                format!("at least (pilot + {MIN_MAIN}) x {strata} strata = {least} evaluations"),
            ));
        }
        let (executor, _run) = self.config.executor()?;
        let sampler = self
            .config
            .sampler(dims, "sampler (the dimension of the domain)")?;
        let batches = Batches::new(&*sampler, "two-stage sampling")?;
        if total > batches.slots() {
            return Err(Error::IndexOutOfRange {
                what: "evaluations of the sampler's stream (sample indices or passes)",
                limit: batches.slots(),
            });
        }
        let grid = Grid {
            f,
            domain: &self.domain,
            batches,
            per_axis: self.strata_per_axis,
        };
        let mut stages = Stratified {
            grid: &grid,
            strata: strata as usize,
            pilot: self.pilot,
            total,
            reuse_pilot: self.reuse_pilot,
            pilot_stats: None,
            counts: Vec::new(),
            starts: Vec::new(),
            main_stats: None,
            cut: 0,
        };
        let limits = self.config.limits();
        let targets = Targets::new(1, None, None, &[])?;
        let drive = Drive {
            executor: &executor,
            limits: &limits,
            targets: &targets,
            config: &self.config,
            spent: 0,
            planned: total,
        };
        let run = engine::drive(&mut stages, &drive)?;
        run.outputs
            .into_iter()
            .next()
            .ok_or_else(|| Error::invalid("outputs", 0, "one output"))
    }

    /// Number of strata, checked.
    fn strata(&self) -> Result<u64> {
        let k = self.strata_per_axis;
        if k == 0 {
            return Err(Error::invalid("strata_per_axis", 0, "at least 1"));
        }
        let mut strata: u64 = 1;
        for _ in 0..self.domain.dims() {
            strata = strata.saturating_mul(k as u64);
        }
        if strata > MAX_STRATA {
            return Err(Error::invalid(
                "strata_per_axis",
                k,
                format!(
                    "at most {MAX_STRATA} strata in all (strata_per_axis^{})",
                    self.domain.dims()
                ),
            ));
        }
        Ok(strata)
    }
}

/// The most strata per axis a [`TwoStage`] run of `evaluations` in `dims` dimensions affords
/// with the default pilot (8 points per stratum, a total of 4 pilots): the largest `k >= 1` with
/// `32 k^dims <= evaluations`, and at most `2^20` strata in all (each stratum's statistics
/// are kept in memory, and beyond that more strata gain little).
///
/// ```
/// use mcint::{adaptive::{TwoStage, strata_per_axis_for}, pdf::UniformBox};
/// assert_eq!(strata_per_axis_for(2, 65536), 45);
/// assert_eq!(strata_per_axis_for(1, u64::MAX), 1 << 20);
/// let k = strata_per_axis_for(3, 100_000);
/// let e = TwoStage::new(|x: &[f64]| x[0], UniformBox::unit(3).unwrap(), k).samples(100_000).run();
/// assert!(e.is_ok());
/// ```
pub fn strata_per_axis_for(dims: usize, evaluations: u64) -> usize {
    let strata = (evaluations / (4 * DEFAULT_PILOT)).min(MAX_PLANNED_STRATA);
    usize::try_from(integer_root(strata, dims)).unwrap_or(usize::MAX)
}

/// The grid of strata and what sampling one stratum needs.
struct Grid<'a, F> {
    f: &'a F,
    domain: &'a UniformBox,
    batches: Batches<'a>,
    per_axis: usize,
}

/// A stratum's first non-finite value: stratum, index within its batch, value, point.
type FirstBad = (usize, u64, f64, Vec<f64>);

impl<F: ScalarIntegrand> Grid<'_, F> {
    /// The cell of stratum `j`: digit `i` of `j` in base `per_axis` is its row along axis `i`.
    fn cell(&self, mut j: usize) -> Cell {
        let k = self.per_axis;
        let dims = self.domain.dims();
        let mut cell = Cell::unit(dims);
        for (lo, hi) in cell.lo.iter_mut().zip(cell.hi.iter_mut()) {
            let row = j % k;
            j /= k;
            *lo = row as f64 / k as f64;
            *hi = (row + 1) as f64 / k as f64;
        }
        cell
    }

    /// Samples every stratum `j` with the batch `batch(j) = (first slot, points)`, whose
    /// slots follow each other without a gap and hold `evaluations` in all, on `executor`
    /// under `limits`: the per-stratum statistics in stratum order (each computed in index
    /// order, in pieces of a fixed size, so the result does not depend on the thread count),
    /// or, when a limit stops the stage, the evaluations done; and the first non-finite value
    /// met. `progress` is told the evaluations folded so far, after every chunk.
    fn sample_strata(
        &self,
        strata: usize,
        batch: &(dyn Fn(usize) -> (u64, u64) + Sync),
        evaluations: u64,
        (executor, limits): (&Executor, &Limits),
        progress: &mut dyn FnMut(u64),
    ) -> Result<(Sampled, Option<NonFinite>)> {
        let job = StrataJob {
            grid: self,
            stage: Stage {
                strata,
                batch,
                base: batch(0).0,
                evaluations,
                per_chunk: chunk_evaluations(self.domain.dims()),
            },
        };
        let chunks = evaluations.div_ceil(job.stage.per_chunk);
        let mut all: Vec<Accumulator> = Vec::with_capacity(strata);
        let mut first_bad = None;
        let mut folded = 0;
        let stopped = executor.run(&job, 0..chunks, WINDOW, limits, |_, (pieces, bad)| {
            for (j, piece) in pieces {
                folded += piece.count() + piece.non_finite();
                match all.get_mut(j) {
                    Some(stratum) => stratum.merge(&piece),
                    None => all.push(piece),
                }
            }
            first_bad = first_bad.take().or(bad);
            progress(folded);
            Ok(())
        })?;
        let count = all.iter().map(|a| a.non_finite()).sum();
        let non_finite = first_bad.map(|(stratum, index, value, point)| NonFinite {
            count,
            replicate: stratum as u64,
            index,
            output: None,
            value,
            point,
        });
        let sampled = match stopped {
            // A stage cut short leaves strata unsampled: it has no estimate of its own.
            Some(stop) => Sampled::Stopped {
                stop,
                evaluations: folded,
            },
            None => Sampled::All(all),
        };
        Ok((sampled, non_finite))
    }

    /// The statistics of the pieces `(stratum j, (first, n))` in order: points `first ..
    /// first + n` of stratum `j`'s batch, whose first slot is `slot(j)`, each piece's values
    /// pushed in index order. Points of consecutive pieces share blocks, so that an integrand
    /// evaluated by blocks is called with many small strata at once.
    fn sample_pieces(
        &self,
        pieces: &[(usize, (u64, u64))],
        slot: &dyn Fn(usize) -> u64,
        work: &mut Workspace,
        bad: &mut Option<FirstBad>,
    ) -> Result<Vec<(usize, Accumulator)>> {
        let cells: Vec<Cell> = pieces.iter().map(|&(j, _)| self.cell(j)).collect();
        let mut stats: Vec<(usize, Accumulator)> = pieces
            .iter()
            .map(|&(j, _)| (j, Accumulator::new()))
            .collect();
        let block = self.f.block();
        let dims = self.domain.dims();
        // Where each point of the block came from: its piece and its index in the batch.
        let mut origins: Vec<(usize, u64)> = Vec::with_capacity(block);
        let mut staged = Points::new(dims, 0)?;
        work.points.set_len(block);
        let mut flush = |work: &mut Workspace, origins: &mut Vec<(usize, u64)>| {
            let place = |points: &Points, i: usize, unit: &mut [f64], x: &mut [f64]| {
                cells[origins[i].0].place(points, i, self.domain, unit, x);
            };
            self.f.each(origins.len(), work, place, |i, y, unit| {
                let (piece, index) = origins[i];
                stats[piece].1.push(y);
                if !y.is_finite() && bad.is_none() {
                    *bad = Some((pieces[piece].0, index, y, unit.to_vec()));
                }
            });
            origins.clear();
        };
        for (piece, &(j, (first, n))) in pieces.iter().enumerate() {
            let mut k = first;
            while k < first + n {
                let want = (first + n - k).min((block - origins.len()) as u64) as usize;
                let len = self.batches.fill(slot(j), k, want, &mut staged)?;
                let at = origins.len();
                for d in 0..dims {
                    work.points.column_mut(d)[at..at + len].copy_from_slice(staged.column(d));
                }
                origins.extend((0..len as u64).map(|i| (piece, k + i)));
                k += len as u64;
                if origins.len() == block {
                    flush(work, &mut origins);
                }
            }
        }
        if !origins.is_empty() {
            // The block keeps its length: its first points are the ones staged.
            flush(work, &mut origins);
        }
        Ok(stats)
    }
}

/// Two-stage sampling as stages for the engine's driver: the pilot, then the main stage
/// that its spreads allocate. A main stage cut short leaves the pilot, a whole stage and an
/// unbiased stratified estimate of its own.
struct Stratified<'a, 'b, F> {
    grid: &'a Grid<'b, F>,
    strata: usize,
    pilot: u64,
    /// Evaluations of the run, pilot included.
    total: u64,
    reuse_pilot: bool,
    pilot_stats: Option<Vec<Accumulator>>,
    /// The main stage's points per stratum, and its first slot per stratum.
    counts: Vec<u64>,
    starts: Vec<u64>,
    main_stats: Option<Vec<Accumulator>>,
    /// Evaluations of a stage cut short.
    cut: u64,
}

impl<F: ScalarIntegrand> Stratified<'_, '_, F> {
    /// Evaluations of the pilot: stratum `j` at slots `j * pilot ..`.
    fn pilot_evaluations(&self) -> u64 {
        self.strata as u64 * self.pilot
    }
}

impl<F: ScalarIntegrand> Stages for Stratified<'_, '_, F> {
    fn next(&mut self, _left: u64) -> Result<Next> {
        let main_base = self.pilot_evaluations();
        match (&self.pilot_stats, &self.main_stats) {
            (None, _) => Ok(Next::Stage(main_base)),
            (Some(pilot), None) => {
                // Fresh samples, stratum j right after stratum j - 1.
                self.counts = neyman_allocation(pilot, self.total - main_base);
                self.starts = self
                    .counts
                    .iter()
                    .scan(main_base, |next, &n| {
                        let start = *next;
                        *next += n;
                        Some(start)
                    })
                    .collect();
                Ok(Next::Stage(self.total - main_base))
            }
            (Some(_), Some(_)) => Ok(Next::Done(StopReason::Budget)),
        }
    }

    fn run(
        &mut self,
        executor: &Executor,
        limits: &Limits,
        progress: &mut dyn FnMut(u64),
    ) -> Result<StageEnd> {
        let (sampled, non_finite) = match self.pilot_stats {
            None => {
                let pilot = self.pilot;
                let pilot_batch = move |j: usize| (j as u64 * pilot, pilot);
                let evaluations = self.pilot_evaluations();
                self.grid.sample_strata(
                    self.strata,
                    &pilot_batch,
                    evaluations,
                    (executor, limits),
                    progress,
                )?
            }
            Some(_) => {
                let (starts, counts) = (&self.starts, &self.counts);
                let main_batch = |j: usize| (starts[j], counts[j]);
                let evaluations = self.total - self.pilot_evaluations();
                self.grid.sample_strata(
                    self.strata,
                    &main_batch,
                    evaluations,
                    (executor, limits),
                    progress,
                )?
            }
        };
        let stop = match sampled {
            Sampled::All(stats) if self.pilot_stats.is_none() => {
                self.pilot_stats = Some(stats);
                None
            }
            Sampled::All(stats) => {
                self.main_stats = Some(stats);
                None
            }
            Sampled::Stopped { stop, evaluations } => {
                self.cut = evaluations;
                Some(stop)
            }
        };
        Ok(StageEnd { stop, non_finite })
    }

    fn has_estimate(&self) -> bool {
        self.pilot_stats.is_some()
    }

    fn estimate(&mut self) -> Result<Option<VectorEstimate>> {
        let Some(pilot) = &self.pilot_stats else {
            return Ok(None);
        };
        let volume = self.grid.domain.volume() / self.strata as f64;
        let estimate = match &self.main_stats {
            // The pilot alone, when the main stage was cut short.
            None => {
                let mut estimate =
                    stratified_estimate(pilot, volume, self.pilot_evaluations() + self.cut)?;
                estimate.iterations = 1;
                estimate
            }
            Some(main) if self.reuse_pilot => {
                let all: Vec<Accumulator> = pilot
                    .iter()
                    .zip(main)
                    .map(|(p, m)| {
                        let mut all = *p;
                        all.merge(m);
                        all
                    })
                    .collect();
                stratified_estimate(&all, volume, self.total)?
            }
            Some(main) => stratified_estimate(main, volume, self.total)?,
        };
        Ok(Some(VectorEstimate::assemble(vec![estimate], None)))
    }
}

/// A stage's per-stratum statistics, or how far it got before a limit stopped it.
enum Sampled {
    All(Vec<Accumulator>),
    Stopped { stop: StopReason, evaluations: u64 },
}

/// Evaluations per chunk of work in `dims` dimensions.
fn chunk_evaluations(dims: usize) -> u64 {
    let (least, most) = CHUNK_EVALUATIONS;
    (CHUNK_COORDINATES / dims.max(1) as u64).clamp(least, most)
}

/// The largest `k >= 1` with `k^dims <= n` (1 when `n <= 1`).
fn integer_root(n: u64, dims: usize) -> u64 {
    if n <= 1 || dims == 0 {
        return 1;
    }
    let fits = |k: u64| {
        u32::try_from(dims)
            .ok()
            .and_then(|d| k.checked_pow(d))
            .is_some_and(|p| p <= n)
    };
    // The floating-point root is within one of the answer; step to it exactly.
    let mut k = ((n as f64).powf(1.0 / dims as f64).round() as u64).max(1);
    while k > 1 && !fits(k) {
        k -= 1;
    }
    while k.checked_add(1).is_some_and(fits) {
        k += 1;
    }
    k
}

/// A stage as work for the executor: its strata, laid end to end, cut into chunks of
/// `per_chunk` evaluations. Chunk `c` samples whole every stratum that starts in its range
/// (only the first `per_chunk` points of a larger one), and the next piece of the larger
/// stratum its range begins in, if any; a stratum's pieces start at multiples of `per_chunk`
/// from its own start, so the pieces, and hence the bits, do not depend on the thread count.
struct StrataJob<'a, 'b, F> {
    grid: &'a Grid<'b, F>,
    stage: Stage<'a>,
}

/// A stage's strata laid end to end, and its chunks.
struct Stage<'a> {
    strata: usize,
    batch: &'a (dyn Fn(usize) -> (u64, u64) + Sync),
    /// The slot of stratum 0: stratum `j` starts `batch(j).0 - base` evaluations in.
    base: u64,
    evaluations: u64,
    per_chunk: u64,
}

impl Stage<'_> {
    /// Where stratum `j` starts in the stage, and its points.
    fn span(&self, j: usize) -> (u64, u64) {
        let (slot, n) = (self.batch)(j);
        (slot - self.base, n)
    }

    /// The pieces of chunk `chunk`, in order: `(stratum, (first point, points))`.
    fn pieces(&self, chunk: u64) -> Vec<(usize, (u64, u64))> {
        let lo = chunk * self.per_chunk;
        let hi = lo.saturating_add(self.per_chunk).min(self.evaluations);
        // The first stratum that starts at or after `lo` (starts increase with `j`).
        let (mut a, mut b) = (0, self.strata);
        while a < b {
            let mid = a + (b - a) / 2;
            if self.span(mid).0 < lo {
                a = mid + 1;
            } else {
                b = mid;
            }
        }
        let mut pieces = Vec::new();
        if a > 0 {
            let (start, n) = self.span(a - 1);
            let first = (lo - start).div_ceil(self.per_chunk) * self.per_chunk;
            if first < n && start + first < hi {
                pieces.push((a - 1, (first, (n - first).min(self.per_chunk))));
            }
        }
        for j in a..self.strata {
            let (start, n) = self.span(j);
            if start >= hi {
                break;
            }
            pieces.push((j, (0, n.min(self.per_chunk))));
        }
        pieces
    }
}

impl<F: ScalarIntegrand> ChunkJob for StrataJob<'_, '_, F> {
    type Scratch = Workspace;
    type Output = (Vec<(usize, Accumulator)>, Option<FirstBad>);

    fn scratch(&self) -> Result<Workspace> {
        Workspace::new(self.grid.domain.dims(), self.grid.f.block())
    }

    fn run(&self, work: &mut Workspace, chunk: u64, _: &Limits) -> Result<Option<Self::Output>> {
        let mut bad = None;
        let pieces = self.stage.pieces(chunk);
        let slot = |j: usize| (self.stage.batch)(j).0;
        let stats = self.grid.sample_pieces(&pieces, &slot, work, &mut bad)?;
        Ok(Some((stats, bad)))
    }

    fn origin(&self, chunk: u64) -> (u64, u64) {
        let (j, (first, _)) = self
            .stage
            .pieces(chunk)
            .first()
            .copied()
            .unwrap_or_default();
        (j as u64, first)
    }
}

/// Second-stage points per stratum: `MIN_MAIN` each, and the rest of `main` in proportion to
/// the pilot standard deviations (all strata have the same volume), rounded by largest
/// remainders so that the counts add up to `main` exactly. With no spread anywhere the rest
/// is shared equally.
fn neyman_allocation(pilot: &[Accumulator], main: u64) -> Vec<u64> {
    let strata = pilot.len();
    let free = main - MIN_MAIN * strata as u64;
    // Standard deviations in common units: those of values near 1e-160 or 1e160 would
    // underflow or overflow as plain variances.
    let unit = Accumulator::common_unit(pilot);
    let sigmas: Vec<f64> = pilot
        .iter()
        .map(|a| {
            let s = a.variance_in(unit).sqrt();
            if s.is_finite() { s } else { 0.0 }
        })
        .collect();
    let sum: f64 = sigmas.iter().sum();
    let weights: Vec<f64> = if sum > 0.0 && sum.is_finite() {
        sigmas.iter().map(|s| s / sum).collect()
    } else {
        vec![1.0 / strata as f64; strata]
    };
    let mut counts = Vec::with_capacity(strata);
    let mut remainders = Vec::with_capacity(strata);
    let mut given = 0u64;
    for (j, w) in weights.iter().enumerate() {
        let exact = free as f64 * w;
        let whole = (exact.floor() as u64).min(free - given);
        given += whole;
        counts.push(MIN_MAIN + whole);
        remainders.push((exact - whole as f64, j));
    }
    // Largest remainders first; ties go to the lower stratum index.
    remainders.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    for &(_, j) in remainders.iter().cycle().take((free - given) as usize) {
        counts[j] += 1;
    }
    counts
}

/// `sum_j V_j mean_j` with variance `sum_j V_j^2 s_j^2 / n_j` and Welch-Satterthwaite degrees
/// of freedom; an error when a stratum has fewer than the two finite values its variance
/// needs (skipping non-finite values can leave it so).
fn stratified_estimate(strata: &[Accumulator], volume: f64, evaluations: u64) -> Result<Estimate> {
    if let Some(j) = strata.iter().position(|a| a.count() < 2) {
        return Err(Error::invalid(
            "integrand",
            format!(
                "non-finite at all but {} points of stratum {j}",
                strata[j].count()
            ),
            "at least two finite values per stratum, even when skipping",
        ));
    }
    // Variances in common units (a power of two, exact), so that the squares of values near
    // 1e-160 or 1e160 neither underflow nor overflow; the standard error is scaled back. The
    // volume is split likewise into a power of two and a factor in [1, 2), so that the
    // square of a tiny or huge stratum volume neither underflows nor overflows either.
    let unit = Accumulator::common_unit(strata);
    let volume_unit = 2f64.powi((volume.log2().floor() as i32).clamp(-1022, 1023));
    let relative_volume = volume / volume_unit;
    let mut mean = 0.0;
    let mut variance = 0.0;
    let mut dof_denominator = 0.0;
    let mut samples = 0u64;
    // Each stratum's own bound, its product with the volume and its share of the sum.
    let per_term = gamma(strata.len() as f64) + UNIT_ROUNDOFF;
    let mut rounding = 0.0;
    let mut terms = Vec::with_capacity(strata.len());
    for acc in strata {
        let n = acc.count();
        samples += n;
        mean += volume * acc.mean();
        rounding += volume * (acc.rounding_error() + per_term * acc.mean().abs());
        let v = relative_volume * relative_volume * acc.variance_in(unit) / n as f64;
        variance += v;
        dof_denominator += v * v / (n - 1) as f64;
        terms.push((v, n));
    }
    let squared = variance * variance;
    let dof = if dof_denominator >= f64::MIN_POSITIVE && squared.is_finite() {
        squared / dof_denominator
    } else if variance > 0.0 && variance.is_finite() {
        // The squares left the range of f64 (variances beyond about 1e154, or below 1e-154,
        // in these units): the same ratio with every term divided by the largest.
        let largest = terms.iter().fold(0.0, |m, &(v, _)| f64::max(m, v));
        let (sum, squares) = terms.iter().fold((0.0, 0.0), |(sum, squares), &(v, n)| {
            let r = v / largest;
            (sum + r, squares + r * r / (n - 1) as f64)
        });
        sum * sum / squares
    } else {
        // No spread anywhere: any dof will do; take the pooled one.
        (samples - strata.len() as u64) as f64
    };
    let mut estimate = Estimate {
        mean,
        std_error: Some(variance.sqrt() * unit * volume_unit),
        dof: Some(dof),
        basis: ErrorBasis::PerSample,
        n: samples,
        evaluations,
        replicates: 1,
        non_finite: strata.iter().map(Accumulator::non_finite).sum(),
        stop: StopReason::Budget,
        converged: None,
        iterations: 2,
        chi2_dof: None,
        q_value: None,
        rounding_error: rounding,
        warnings: Vec::new(),
        error_bound: None,
    };
    estimate.finalize();
    Ok(estimate)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pilot(values: &[&[f64]]) -> Vec<Accumulator> {
        values
            .iter()
            .map(|v| {
                let mut acc = Accumulator::new();
                acc.extend(v);
                acc
            })
            .collect()
    }

    #[test]
    fn allocation_follows_the_pilot_spread_and_adds_up() {
        // Standard deviations 0, 1 and 3: the 40 free points go 0 : 10 : 30.
        let stats = pilot(&[
            &[5.0, 5.0],
            &[0.0, 2.0f64.sqrt()],
            &[0.0, 3.0 * 2f64.sqrt()],
        ]);
        assert_eq!(neyman_allocation(&stats, 46), vec![2, 12, 32]);
        // Remainders: 7 free points at 1 : 1 : 1 give 2, 2, 2 and one more to the first.
        let even = pilot(&[&[0.0, 1.0], &[0.0, 1.0], &[0.0, 1.0]]);
        assert_eq!(neyman_allocation(&even, 13), vec![5, 4, 4]);
        // No spread anywhere: shared equally, never zero.
        let flat = pilot(&[&[1.0, 1.0], &[2.0, 2.0]]);
        assert_eq!(neyman_allocation(&flat, 4), vec![2, 2]);
        assert_eq!(neyman_allocation(&flat, 9), vec![5, 4]);
    }

    #[test]
    fn integer_roots_are_exact() {
        for dims in 1..6 {
            for n in 0..5000u64 {
                let k = integer_root(n, dims);
                let brute = (1..)
                    .take_while(|k: &u64| k.pow(dims as u32) <= n.max(1))
                    .last();
                assert_eq!(Some(k), brute, "{n}^(1/{dims})");
            }
        }
        assert_eq!(integer_root(u64::MAX, 1), u64::MAX);
        assert_eq!(integer_root(u64::MAX, 2), u64::from(u32::MAX));
        assert_eq!(integer_root(1 << 62, 64), 1);
        assert_eq!(integer_root(u64::MAX, usize::MAX), 1);
    }

    #[test]
    fn chunks_cover_every_point_of_every_stratum_once_in_order() {
        // Strata of 1 to 40 points (and one of 333), chunks of 16 evaluations.
        let counts: Vec<u64> = (0..50)
            .map(|j| if j == 7 { 333 } else { 1 + (j * 7) % 40 })
            .collect();
        let starts: Vec<u64> = counts
            .iter()
            .scan(100, |next, n| {
                let start = *next;
                *next += n;
                Some(start)
            })
            .collect();
        let batch = |j: usize| (starts[j], counts[j]);
        let stage = Stage {
            strata: counts.len(),
            batch: &batch,
            base: 100,
            evaluations: counts.iter().sum(),
            per_chunk: 16,
        };
        let mut seen: Vec<(usize, u64, u64)> = Vec::new();
        for chunk in 0..stage.evaluations.div_ceil(16) {
            let pieces = stage.pieces(chunk);
            assert!(!pieces.is_empty(), "chunk {chunk}");
            // A chunk holds less than two chunks' worth of points plus one piece.
            let points: u64 = pieces.iter().map(|(_, (_, n))| n).sum();
            assert!(points < 3 * 16, "chunk {chunk}: {points}");
            for (j, (first, n)) in pieces {
                assert!((1..=16).contains(&n) && first % 16 == 0);
                seen.push((j, first, n));
            }
        }
        // Every stratum's points, in order, in pieces that start where the last one ended.
        let mut expected = Vec::new();
        for (j, &n) in counts.iter().enumerate() {
            let mut first = 0;
            while first < n {
                expected.push((j, first, (n - first).min(16)));
                first += 16;
            }
        }
        assert_eq!(seen, expected);
    }

    #[test]
    fn stratified_estimate_adds_strata_and_their_variances() {
        let strata = pilot(&[&[1.0, 3.0], &[2.0, 2.0, 2.0]]);
        let e = stratified_estimate(&strata, 0.5, 10).unwrap();
        assert_eq!(e.mean, 0.5 * 2.0 + 0.5 * 2.0);
        // Only the first stratum varies: 0.25 * 2 / 2, with its 1 degree of freedom.
        assert_eq!((e.std_error, e.dof), (Some(0.5), Some(1.0)));
        // The five samples of the strata are behind the estimate; ten were spent.
        assert_eq!((e.n, e.evaluations), (5, 10));
    }
}
