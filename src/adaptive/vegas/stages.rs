//! A VEGAS run as stages for the engine's driver: each iteration is a stage, the warm-up
//! ones adapt the grid and the allocation and are discarded, and the iterations after them
//! are combined.

use super::combination::VectorCombination;
use super::growth::{GROWTH, Growth, Step};
use super::integrand::Integrand;
use super::pass::{LocalAdaptation, Pass};
use super::strata::{ALLOCATION_SAFETY, Allocation, ChunkStart, Strata, plan_chunks};
use super::training::{GroupTraining, SpareTraining, summed};
use super::units::Units;
use super::{Vegas, output_weights};
use crate::adaptive::VegasGrid;
use crate::adaptive::vegas_grid::increment_averages;
use crate::engine::{Executor, Limits, Next, NonFinite, StageEnd, Stages, Targets, Verdict};
use crate::error::Result;
use crate::sampler::{PassKind, Sampler};
use crate::stats::{DISAGREEMENT_Q, StopReason, VectorEstimate};

/// The state of a VEGAS run between its iterations.
pub(super) struct Iterations<'a, F, I> {
    pub(super) vegas: &'a Vegas<F>,
    pub(super) f: &'a I,
    pub(super) sampler: &'a dyn Sampler,
    pub(super) strata: Strata,
    pub(super) grid: VegasGrid,
    /// `sigma_h^beta` per hypercube for this iteration's allocation, the next one's being
    /// recorded, and their sum.
    pub(super) sigf: Vec<f64>,
    pub(super) next_sigf: Vec<f64>,
    pub(super) sum_sigf: f64,
    pub(super) spare: SpareTraining,
    pub(super) combination: VectorCombination,
    /// Each output's weight in the training data and in `sigma_h` (see `output_weights`).
    pub(super) weights: Vec<f64>,
    /// The units the values are summed in, and whether they are chosen yet (by the first
    /// iteration).
    pub(super) units: Units,
    pub(super) units_chosen: bool,
    /// Evaluations of a first iteration run again in new units (0 when it was not).
    pub(super) rerun: u64,
    /// The iteration next to run (warm-up included).
    pub(super) k: u64,
    /// Evaluations of every whole iteration, and of the combined ones.
    pub(super) spent: u64,
    pub(super) measured_evaluations: u64,
    pub(super) non_finite: u64,
    /// The evaluations spent when the interval first met the tolerance but for iterations
    /// that disagree.
    pub(super) held_back_at: Option<u64>,
    /// The size of the iterations and when it grows (runs to a tolerance).
    pub(super) growth: Growth,
    /// The estimate of the iterations the last restart set aside.
    pub(super) set_aside: Option<VectorEstimate>,
    /// The number of iterations, warm-up included, at which the run ends.
    pub(super) last_iteration: u64,
    /// The grid's most increments per axis, for the strata of a grown iteration.
    pub(super) max_increments: usize,
    /// The evaluations left under the limit when the next stage was planned.
    pub(super) left: u64,
    /// The next iteration's plan: its chunks, evaluations, allocation scale and first index.
    pub(super) chunks: Vec<ChunkStart>,
    pub(super) total: u64,
    pub(super) scale: Option<f64>,
    pub(super) base: u64,
    /// Whether the run goes to a tolerance: its most iterations are then a limit it stops
    /// on, as on any other evaluation limit.
    pub(super) to_tolerance: bool,
}

impl<F, I: Integrand> Stages for Iterations<'_, F, I> {
    fn next(&mut self, left: u64) -> Result<Next> {
        self.left = left;
        if self.k == self.last_iteration {
            return Ok(Next::Done(if self.to_tolerance {
                StopReason::MaxEvaluations
            } else {
                StopReason::Budget
            }));
        }
        self.scale = self
            .strata
            .allocation_budget
            .map(|budget| budget / self.sum_sigf * ALLOCATION_SAFETY);
        (self.chunks, self.total) = plan_chunks(&self.strata, &self.allocation());
        self.base = match self.sampler.passes() {
            PassKind::Extensible { max } => self.k * max,
            // The points an iteration run again in other units had, once more.
            _ => self.spent - self.rerun,
        };
        Ok(Next::Stage(self.total))
    }

    fn run(
        &mut self,
        executor: &Executor,
        limits: &Limits,
        progress: &mut dyn FnMut(u64),
    ) -> Result<StageEnd> {
        let local = (!executor.spread()).then(|| {
            let (alpha, floor) = (self.vegas.alpha, self.vegas.density_floor);
            LocalAdaptation::new(self.chunks.len(), self.grid.dims(), alpha, floor)
        });
        let pass = Pass {
            f: self.f,
            weights: &self.weights,
            inverse_units: self.units.inverses(),
            probing: !self.units_chosen,
            sampler: self.sampler,
            grid: &self.grid,
            strata: &self.strata,
            allocation: Allocation {
                min: self.strata.min_per_cube,
                scale: self.scale,
                sigf: &self.sigf,
            },
            chunks: &self.chunks,
            total: self.total,
            iteration: self.k,
            base: self.base,
            beta: self.vegas.beta,
            allocating: self.strata.allocation_budget.is_some(),
            spare: &self.spare,
            local: local.as_ref(),
        };
        let mut totals = match pass.run(executor, limits, &mut self.next_sigf, progress)? {
            Ok(totals) => totals,
            // An iteration cut short is discarded: its hypercubes are unevenly sampled.
            Err(reason) => {
                return Ok(StageEnd {
                    stop: Some(reason),
                    non_finite: None,
                });
            }
        };
        let non_finite = match totals.first_non_finite.take() {
            Some(first) if totals.non_finite > 0 => Some(NonFinite {
                count: totals.non_finite,
                replicate: self.k,
                index: first.index,
                output: (self.f.outputs() > 1).then_some(first.output),
                value: first.value,
                point: first.point,
            }),
            _ => None,
        };
        if !self.units_chosen {
            self.units_chosen = true;
            let volume = self.vegas.domain.volume();
            if let Some(units) = Units::needed(&totals.largest, volume) {
                // Sums of these values' squares may overflow or underflow: the iteration
                // is run again in units near them, and this one leaves no trace.
                self.units = units;
                self.rerun = self.total;
                self.spent += self.total;
                match local {
                    Some(local) => local.slots.give_back(&self.spare),
                    None => self.spare.give(std::mem::take(&mut totals.training)),
                }
                return Ok(StageEnd {
                    stop: None,
                    non_finite: None,
                });
            }
        }
        let measured = self.k >= self.vegas.warmup;
        self.k += 1;
        self.spent += self.total;
        match local {
            Some(local) => self.adapt_locally(local),
            None => self.adapt(std::mem::take(&mut totals.training), executor),
        }
        if self.allocating() {
            std::mem::swap(&mut self.sigf, &mut self.next_sigf);
            self.sum_sigf = self.sigf.iter().sum();
            if !(self.sum_sigf > 0.0 && self.sum_sigf.is_finite()) {
                // No variance anywhere (a constant integrand): back to uniform.
                self.sigf.fill(1.0);
                self.sum_sigf = self.sigf.len() as f64;
            }
        }
        if self.f.outputs() > 1 {
            self.weights = output_weights(&totals, self.total);
        }
        if measured {
            self.combination
                .add(&totals, self.total - self.strata.cubes);
            self.measured_evaluations += self.total;
            self.non_finite += totals.non_finite;
        } else {
            self.combination.warm_up(&totals);
        }
        Ok(StageEnd {
            stop: None,
            non_finite,
        })
    }

    fn has_estimate(&self) -> bool {
        self.combination.count() > 0 || self.set_aside.is_some()
    }

    fn estimate(&mut self) -> Result<Option<VectorEstimate>> {
        if self.combination.count() > 0 {
            return Ok(Some(self.combined()));
        }
        // A limit right after a restart: the iterations set aside are all there is.
        Ok(self.set_aside.clone().map(|mut run| {
            run.evaluations = self.spent;
            run.for_each_output(|_, estimate| estimate.evaluations = self.spent);
            run
        }))
    }

    fn verdict(&mut self, judged: &VectorEstimate, met: bool, targets: &Targets<'_>) -> Verdict {
        // Two or more iterations carry their own chi^2 (`Tolerance::is_met` refuses those
        // that disagree); a first one is checked against the warm-up ones, except after a
        // restart, where it waits for a second.
        let first = match self.combination.count() {
            1 => self.combination.first_agrees(),
            _ => Some(true),
        };
        if first == Some(true) && met {
            return Verdict::Met;
        }
        let disagree = first == Some(false)
            || judged
                .outputs
                .iter()
                .any(|e| e.q_value.is_some_and(|q| q < DISAGREEMENT_Q));
        let last = self.combination.last_variance();
        self.growth.record(last * self.total as f64);
        // Iterations like the last one that the tolerance still needs: the combination's
        // shortfall squared, times its variance over the last iteration's.
        let combined = judged.outputs[0].std_error.unwrap_or(f64::NAN) / self.units.of(0);
        let needed = targets.shortfall(judged).powi(2) * last / (combined * combined);
        let iterations_left = self.last_iteration.saturating_sub(self.k);
        match self
            .growth
            .step(disagree, needed, self.left, iterations_left)
        {
            Step::Grow { restart } => {
                self.grow(restart);
                return Verdict::Continue;
            }
            Step::GiveUp => return Verdict::Stop(StopReason::IterationsDisagree),
            Step::Continue => {}
        }
        // Narrow enough but for the disagreement, with no room to grow: the run doubles its
        // evaluations, so that a chance disagreement (1% of honest runs) can pass;
        // iterations that still disagree then have error bars too small for more of them
        // to help.
        let mut without_agreement = judged.clone();
        without_agreement.for_each_output(|_, e| e.q_value = None);
        if disagree && targets.met(&without_agreement) {
            let since = *self.held_back_at.get_or_insert(self.spent);
            if self.spent >= 2 * since {
                return Verdict::Stop(StopReason::IterationsDisagree);
            }
        }
        Verdict::Continue
    }
}

impl<F, I> Iterations<'_, F, I> {
    /// Starts iterations of the grown size (see [`growth`](super::growth)): new strata
    /// on the same grid (whose increments then need not be multiples of the strata), an
    /// even allocation for the first of them, and the combination either started again or
    /// told that the next iteration is larger.
    fn grow(&mut self, restart: bool) {
        let ratio = 1.0 / GROWTH as f64;
        let increments = std::mem::take(&mut self.strata.increments);
        self.strata = Strata::new(
            self.grid.dims(),
            self.growth.size,
            self.vegas.stratified,
            self.vegas.beta,
            self.max_increments,
            self.vegas.increments,
        );
        self.strata.increments = increments;
        if self.allocating() {
            let cubes = self.strata.cubes as usize;
            self.sigf = vec![1.0; cubes];
            self.next_sigf = vec![0.0; cubes];
            self.sum_sigf = cubes as f64;
        }
        if restart {
            self.set_aside = Some(self.combined());
            self.combination.restart(ratio);
            self.measured_evaluations = 0;
            self.non_finite = 0;
        } else {
            self.combination.scale_next(ratio);
        }
        self.held_back_at = None;
    }

    /// Moves the grid to the iteration's training data, `groups` (each group's arrays, in
    /// order), one axis per task: each task sums its axis's part of every group in order and
    /// adapts the axis. The arrays then go back to the spares.
    fn adapt(&mut self, groups: Vec<GroupTraining>, executor: &Executor) {
        let (alpha, floor) = (self.vegas.alpha, self.vegas.density_floor);
        let grid = &self.grid;
        let axes: Vec<usize> = (0..grid.dims()).collect();
        let new_nodes = executor.map_each(axes, |axis| {
            let pairs = summed(&groups, grid.training_range(axis));
            grid.axis_nodes(axis, &increment_averages(&pairs), alpha, floor)
        });
        for (axis, nodes) in new_nodes.into_iter().enumerate() {
            if let Some(nodes) = nodes {
                self.grid.set_axis_nodes(axis, &nodes);
            }
        }
        self.spare.give(groups);
    }

    /// Moves the grid to the nodes the iteration's tail tasks computed (see `Pass::run_tail`),
    /// computing here the nodes of any axis whose task did not run. The arrays then go back to
    /// the spares.
    fn adapt_locally(&mut self, mut local: LocalAdaptation) {
        for axis in 0..self.grid.dims() {
            let nodes = match local.nodes[axis].take() {
                Some(nodes) => nodes,
                None => local.axis_nodes(&self.grid, axis),
            };
            if let Some(nodes) = nodes {
                self.grid.set_axis_nodes(axis, &nodes);
            }
        }
        local.slots.give_back(&self.spare);
    }

    /// The combined estimate of the iterations since the last restart.
    fn combined(&self) -> VectorEstimate {
        let mut run = self
            .combination
            .estimate(self.measured_evaluations, self.spent, &self.units);
        run.for_each_output(|_, estimate| estimate.non_finite = self.non_finite);
        run
    }

    /// Whether the allocation adapts (VEGAS+).
    fn allocating(&self) -> bool {
        self.strata.allocation_budget.is_some()
    }

    /// The next iteration's allocation of points to hypercubes.
    fn allocation(&self) -> Allocation<'_> {
        Allocation {
            min: self.strata.min_per_cube,
            scale: self.scale,
            sigf: &self.sigf,
        }
    }
}
