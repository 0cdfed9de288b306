//! A VEGAS run as stages for the engine's driver: each iteration is a stage, the warm-up
//! ones adapt the grid and the allocation and are discarded, and the iterations after them
//! are combined.

use super::combination::VectorCombination;
use super::integrand::Integrand;
use super::pass::Pass;
use super::strata::{ALLOCATION_SAFETY, Allocation, ChunkStart, Strata, plan_chunks};
use super::training::{GroupTraining, SpareTraining, summed};
use super::{Vegas, output_weights};
use crate::adaptive::VegasGrid;
use crate::adaptive::vegas_grid::increment_averages;
use crate::engine::{Executor, Limits, Next, NonFinite, StageEnd, Stages, Targets, Verdict};
use crate::error::Result;
use crate::sampler::{PassKind, Sampler};
use crate::stats::{StopReason, VectorEstimate};

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
    /// The iteration next to run (warm-up included).
    pub(super) k: u64,
    /// Evaluations of every whole iteration, and of the combined ones.
    pub(super) spent: u64,
    pub(super) measured_evaluations: u64,
    pub(super) non_finite: u64,
    /// The evaluations spent when the interval first met the tolerance but for iterations
    /// that disagree.
    pub(super) held_back_at: Option<u64>,
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
    fn next(&mut self, _left: u64) -> Result<Next> {
        if self.k == self.vegas.warmup + self.vegas.iterations {
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
            _ => self.spent,
        };
        Ok(Next::Stage(self.total))
    }

    fn run(
        &mut self,
        executor: &Executor,
        limits: &Limits,
        progress: &mut dyn FnMut(u64),
    ) -> Result<StageEnd> {
        let pass = Pass {
            f: self.f,
            weights: &self.weights,
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
        let non_finite = match totals.first_non_finite {
            Some((index, value, output)) if totals.non_finite > 0 => {
                let mut point = vec![0.0; self.sampler.dims()];
                self.sampler.point(self.base + index, &mut point)?;
                Some(NonFinite {
                    count: totals.non_finite,
                    replicate: self.k,
                    index,
                    output: (self.f.outputs() > 1).then_some(output),
                    value,
                    point,
                })
            }
            _ => None,
        };
        let measured = self.k >= self.vegas.warmup;
        self.k += 1;
        self.spent += self.total;
        self.adapt(std::mem::take(&mut totals.training), executor);
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
        self.combination.count() > 0
    }

    fn estimate(&mut self) -> Result<Option<VectorEstimate>> {
        if !self.has_estimate() {
            return Ok(None);
        }
        let mut run = self
            .combination
            .estimate(self.measured_evaluations, self.spent);
        run.for_each_output(|_, estimate| estimate.non_finite = self.non_finite);
        Ok(Some(run))
    }

    fn verdict(&mut self, judged: &VectorEstimate, met: bool, targets: &Targets<'_>) -> Verdict {
        // Two or more iterations carry their own chi^2 (`Tolerance::is_met` refuses those
        // that disagree); a first one is checked against the warm-up ones.
        let checked = self.combination.count() > 1 || self.combination.first_agrees();
        if checked && met {
            return Verdict::Met;
        }
        // Narrow enough but for the disagreement: the run doubles its evaluations, so that a
        // chance disagreement (1% of honest runs) can pass; iterations that still disagree
        // then have error bars too small for more of them to help.
        let mut without_agreement = judged.clone();
        without_agreement.for_each_output(|_, e| e.q_value = None);
        if targets.met(&without_agreement) {
            let since = *self.held_back_at.get_or_insert(self.spent);
            if self.spent >= 2 * since {
                return Verdict::Stop(StopReason::IterationsDisagree);
            }
        }
        Verdict::Continue
    }
}

impl<F, I> Iterations<'_, F, I> {
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
