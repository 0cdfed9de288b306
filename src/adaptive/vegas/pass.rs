//! One VEGAS iteration as chunks of work for the engine's executor: each chunk maps its
//! points through the grid, evaluates them and sums them per hypercube. The chunks' grid
//! training data are summed in fixed groups of [`GROUP`] chunks and then over the groups in
//! order (see `training`: on each MPI rank before the exchange, which then carries one array
//! per group, or the arrays of a group's later part where two ranks split it), and the
//! hypercube sums are folded in chunk order, so sums, training data and allocations (and hence
//! the result) are bit-identical for any number of threads or ranks.
//!
//! An integrand with several outputs gets every output's sums per hypercube, and the sums of
//! the products of each pair for their covariance; a point with any non-finite output is left
//! out of every output.

use super::integrand::Integrand;
use super::moments::{CubeMoments, CubeSums, CubeTotals};
use super::strata::{Allocation, ChunkStart, Strata};
use super::training::{GroupTraining, SpareTraining, TrainingSlots};
use crate::adaptive::VegasGrid;
use crate::adaptive::vegas_grid::increment_averages;
use crate::engine::{ChunkJob, Executor, Grouping, Limits};
use crate::error::Result;
use crate::points::Points;
use crate::sampler::Sampler;
use crate::stats::StopReason;
use std::sync::OnceLock;

/// Coordinates drawn at once, at most (about): a block of a high dimension is a few points,
/// so that limits are checked every few milliseconds whatever the dimension.
const BLOCK_COORDINATES: usize = 1 << 16;
/// Chunks whose training data are summed before they are folded (or sent to other ranks).
const GROUP: u64 = 8;
/// Groups (each with a copy of the grid's training data) held in memory at once.
const WINDOW_GROUPS: u64 = 8;

/// Everything one iteration's chunks share.
pub(super) struct Pass<'a, I> {
    pub(super) f: &'a I,
    pub(super) sampler: &'a dyn Sampler,
    pub(super) grid: &'a VegasGrid,
    pub(super) strata: &'a Strata,
    pub(super) allocation: Allocation<'a>,
    pub(super) chunks: &'a [ChunkStart],
    pub(super) total: u64,
    /// The iteration's number (warm-up included), named by errors.
    pub(super) iteration: u64,
    /// Sampler index of the iteration's first point.
    pub(super) base: u64,
    pub(super) beta: f64,
    /// Whether `sigma_h^beta` is recorded for the next allocation (VEGAS+).
    pub(super) allocating: bool,
    /// Each output's weight in the grid's training data and in `sigma_h` (`[1.0]` for a
    /// single output, whose arithmetic is then the scalar one).
    pub(super) weights: &'a [f64],
    /// What each output's values are multiplied by before they are summed (see `units`).
    pub(super) inverse_units: &'a [f64],
    /// Whether the chunks record each output's largest finite `|f_k|`, from which the first
    /// iteration chooses the units.
    pub(super) probing: bool,
    /// Training arrays for the chunks, reused from iteration to iteration.
    pub(super) spare: &'a SpareTraining,
    /// In one process: where the chunks leave their training arrays and the grid's new
    /// nodes, computed as the iteration's tail tasks. `None` over MPI ranks, where the
    /// arrays travel with the chunks' outputs and the grid adapts after the exchange.
    pub(super) local: Option<&'a LocalAdaptation>,
}

/// The grid's adaptation at the end of an iteration in one process: the chunks' training
/// arrays, the damping settings, and each axis's new nodes once its tail task has run.
pub(super) struct LocalAdaptation {
    pub(super) slots: TrainingSlots,
    pub(super) alpha: f64,
    pub(super) floor: f64,
    /// Per axis, the new nodes (`None` inside when the axis stays put).
    pub(super) nodes: Vec<OnceLock<Option<Vec<f64>>>>,
}

impl LocalAdaptation {
    /// Slots for an iteration of `chunks` chunks on a grid of `dims` axes.
    pub(super) fn new(chunks: usize, dims: usize, alpha: f64, floor: f64) -> LocalAdaptation {
        LocalAdaptation {
            slots: TrainingSlots::new(chunks),
            alpha,
            floor,
            nodes: (0..dims).map(|_| OnceLock::new()).collect(),
        }
    }

    /// Axis `axis`'s new nodes from the summed training data of every chunk (`None` when
    /// the axis stays put).
    pub(super) fn axis_nodes(&self, grid: &VegasGrid, axis: usize) -> Option<Vec<f64>> {
        let pairs = self.slots.summed(GROUP as usize, grid.training_range(axis));
        grid.axis_nodes(axis, &increment_averages(&pairs), self.alpha, self.floor)
    }
}

/// The iteration's sums, built chunk by chunk in order: per output, and per pair of outputs
/// for their covariance.
pub(super) struct Totals {
    /// Per output `mean`, `variance` and a bound on the rounding error of `mean`; per pair of
    /// outputs `(j, k)` their covariance at `pair(j, k)`.
    pub(super) sums: CubeTotals,
    /// The hypercube that straddles the last merged chunk's end.
    open: CubeMoments,
    /// Points with a non-finite output.
    pub(super) non_finite: u64,
    /// The first non-finite `J f`.
    pub(super) first_non_finite: Option<FirstNonFinite>,
    /// Each output's largest finite `|f_k|` (when probing; 0 otherwise).
    pub(super) largest: Vec<f64>,
    /// The grid's training data of each group of chunks, in order: summed element by element
    /// in this order, axis by axis in parallel, when the grid adapts.
    pub(super) training: Vec<GroupTraining>,
}

/// The first point of an iteration whose `J f` is not finite: its index within the
/// iteration, the value, the output, and its canonical point (in its hypercube, before the
/// grid maps it: the sampler's own point lies in the whole cube).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "mpi", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct FirstNonFinite {
    pub(super) index: u64,
    pub(super) value: f64,
    pub(super) output: usize,
    pub(super) point: Vec<f64>,
}

/// The canonical point of a sample whose uniform coordinates in hypercube `cube` are `u`,
/// as the mapping computes it.
fn canonical_point(u: &[f64], mut cube: u64, strata: &Strata) -> Vec<f64> {
    u.iter()
        .zip(&strata.per_axis)
        .zip(&strata.inverse)
        .map(|((&u, &s), &inverse)| {
            let c = cube % s;
            cube /= s;
            (c as f64 + u) * inverse
        })
        .collect()
}

impl Totals {
    fn new(m: usize) -> Totals {
        Totals {
            sums: CubeTotals::zero(m),
            open: CubeMoments::empty(m),
            non_finite: 0,
            first_non_finite: None,
            largest: vec![0.0; m],
            training: Vec::new(),
        }
    }
}

impl<I: Integrand> Pass<'_, I> {
    /// Runs the iteration: its sums, with the grid's training data added to `training` and
    /// each hypercube's `sigma_h^beta` written to `next_sigf` (when allocating); or the limit
    /// that stopped it before its end. `progress` is told the evaluations of the iteration
    /// folded so far, after every chunk.
    pub(super) fn run(
        &self,
        executor: &Executor,
        limits: &Limits,
        next_sigf: &mut [f64],
        progress: &mut dyn FnMut(u64),
    ) -> Result<std::result::Result<Totals, StopReason>> {
        let mut totals = Totals::new(self.f.outputs());
        let merge = |group: &mut ChunkOutput, mut next: ChunkOutput| {
            group.pieces.append(&mut next.pieces);
            group.training.append(&mut next.training);
        };
        let stop = executor.run_grouped(
            self,
            0..self.chunks.len() as u64,
            Grouping::new(GROUP, WINDOW_GROUPS),
            limits,
            merge,
            |first, out| {
                totals.merge(&out, self, next_sigf);
                totals.training.push(out.training);
                let next = self.chunks.get((first + GROUP) as usize);
                progress(next.map_or(self.total, |c| c.index));
                Ok(())
            },
        )?;
        Ok(match stop {
            None => Ok(totals),
            Some(reason) => Err(reason),
        })
    }
}

impl<I> Pass<'_, I> {
    /// Adds the share of the iteration of a hypercube with moments `m` to `totals`, and
    /// returns its `sigma_h^beta`.
    fn add_cube(&self, totals: &mut CubeTotals, m: &CubeMoments) -> f64 {
        totals.add_cube(
            m,
            self.strata.cube_volume,
            self.beta,
            self.strata.cubes,
            self.weights,
        )
    }
}

impl<I: Integrand> ChunkJob for Pass<'_, I> {
    type Scratch = Scratch;
    type Output = ChunkOutput;

    fn scratch(&self) -> Result<Scratch> {
        Scratch::new(self)
    }

    fn run(
        &self,
        scratch: &mut Scratch,
        chunk: u64,
        limits: &Limits,
    ) -> Result<Option<ChunkOutput>> {
        let mut piece = Piece::new(self.f.outputs());
        let mut training = self.spare.take(2 * self.grid.cells());
        let finished = scratch.run_chunk(
            self,
            chunk as usize,
            &mut piece,
            &mut training.values,
            limits,
        )?;
        Ok(finished.then(|| {
            let training = match self.local {
                Some(local) => {
                    local.slots.put(chunk as usize, training);
                    GroupTraining::default()
                }
                None => GroupTraining::of_chunk(training, chunk.is_multiple_of(GROUP)),
            };
            ChunkOutput {
                pieces: vec![piece],
                training,
            }
        }))
    }

    fn origin(&self, chunk: u64) -> (u64, u64) {
        (self.iteration, self.chunks[chunk as usize].index)
    }

    /// One task per axis after the iteration's last chunk, in one process.
    fn tail_tasks(&self, chunks: &std::ops::Range<u64>) -> usize {
        let last_window = chunks.end == self.chunks.len() as u64;
        match self.local {
            Some(_) if last_window => self.grid.dims(),
            _ => 0,
        }
    }

    /// Adapts axis `axis` of the grid when every chunk left its training data (an iteration
    /// that a limit cut short is discarded, its grid unchanged).
    fn run_tail(&self, axis: usize) {
        if let Some(local) = self.local
            && local.slots.complete()
        {
            let _ = local.nodes[axis].set(local.axis_nodes(self.grid, axis));
        }
    }
}

impl Totals {
    /// Adds the hypercube sums of a group of chunks; groups arrive in index order.
    fn merge<I>(&mut self, out: &ChunkOutput, pass: &Pass<I>, next_sigf: &mut [f64]) {
        for piece in &out.pieces {
            self.merge_piece(piece, pass, next_sigf);
        }
    }

    /// Adds the hypercube sums of one chunk; chunks arrive in index order.
    fn merge_piece<I>(&mut self, out: &Piece, pass: &Pass<I>, next_sigf: &mut [f64]) {
        if let Some(head) = &out.head {
            self.open.merge(head);
            if out.head_ends {
                let sigf = pass.add_cube(&mut self.sums, &self.open);
                if let Some(slot) = next_sigf.get_mut(out.start_cube as usize) {
                    *slot = sigf;
                }
                self.open.clear();
            }
        }
        self.sums.add(&out.closed);
        if !next_sigf.is_empty() {
            let first = out.first_closed as usize;
            next_sigf[first..first + out.closed_sigf.len()].copy_from_slice(&out.closed_sigf);
        }
        if let Some(tail) = &out.tail {
            self.open.clone_from(tail);
        }
        self.non_finite += out.non_finite;
        if self.first_non_finite.is_none() {
            self.first_non_finite.clone_from(&out.first_non_finite);
        }
        for (largest, &value) in self.largest.iter_mut().zip(&out.largest) {
            *largest = largest.max(value);
        }
    }
}

/// What a chunk, or a group of chunks, contributes: the hypercube sums of each chunk, in
/// chunk order, and their grid training data summed.
#[cfg_attr(feature = "mpi", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct ChunkOutput {
    pieces: Vec<Piece>,
    /// Training data of the grid, as [`VegasGrid`] lays it out.
    training: GroupTraining,
}

/// One chunk's hypercube sums, merged in chunk order.
#[cfg_attr(feature = "mpi", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct Piece {
    start_cube: u64,
    /// The piece of a hypercube begun in an earlier chunk, and whether it ends here.
    head: Option<CubeMoments>,
    head_ends: bool,
    /// Hypercubes begun and ended in this chunk, from `first_closed` on, summed.
    first_closed: u64,
    closed: CubeTotals,
    closed_sigf: Vec<f64>,
    /// The moments of the hypercube being closed (a buffer, reused; not sent to other ranks).
    #[cfg_attr(feature = "mpi", serde(skip))]
    moments: CubeMoments,
    /// The hypercube begun here that continues in the next chunk.
    tail: Option<CubeMoments>,
    non_finite: u64,
    first_non_finite: Option<FirstNonFinite>,
    /// Each output's largest finite `|f_k|` (when probing).
    largest: Vec<f64>,
}

impl Piece {
    fn new(m: usize) -> Piece {
        Piece {
            start_cube: 0,
            head: None,
            head_ends: false,
            first_closed: 0,
            closed: CubeTotals::zero(m),
            closed_sigf: Vec::new(),
            moments: CubeMoments::empty(m),
            tail: None,
            non_finite: 0,
            first_non_finite: None,
            largest: vec![0.0; m],
        }
    }

    /// Sets the results to those of chunk `start` before any point.
    fn reset(&mut self, start: &ChunkStart) {
        self.start_cube = start.cube;
        self.head = None;
        self.head_ends = false;
        self.first_closed = if start.offset > 0 {
            start.cube + 1
        } else {
            start.cube
        };
        self.closed.clear();
        self.closed_sigf.clear();
        self.tail = None;
        self.non_finite = 0;
        self.first_non_finite = None;
        self.largest.fill(0.0);
    }

    /// Records a hypercube that ends in this chunk.
    #[inline(always)]
    fn close_cube<I>(&mut self, sums: &CubeSums, continued: bool, pass: &Pass<I>) {
        if continued {
            self.head = Some(sums.moments());
            self.head_ends = true;
            return;
        }
        sums.moments_into(&mut self.moments);
        let sigf = pass.add_cube(&mut self.closed, &self.moments);
        if pass.allocating {
            self.closed_sigf.push(sigf);
        }
    }
}

/// Per-worker buffers, allocated once per iteration.
pub(super) struct Scratch {
    /// Points per block.
    block: usize,
    points: Points,
    /// The block's points, one row per point.
    rows: Vec<f64>,
    /// The block's points mapped through the grid, one row per point; their Jacobians; and
    /// the grid cell of each coordinate.
    x: Vec<f64>,
    jacobians: Vec<f64>,
    cells: Vec<usize>,
    /// The mapped block, one column per axis, for integrands that take blocks.
    mapped: Points,
    /// Coordinates of the current hypercube, as integers and as floats.
    coords: Vec<u64>,
    coords_f: Vec<f64>,
    /// The block's outputs (`k * len + i`), and one point's.
    values: Vec<f64>,
    point: Vec<f64>,
}

impl Scratch {
    fn new<I: Integrand>(pass: &Pass<I>) -> Result<Scratch> {
        let dims = pass.grid.dims();
        let block = (BLOCK_COORDINATES / dims.max(1)).clamp(1, pass.f.block());
        let m = pass.f.outputs();
        Ok(Scratch {
            block,
            points: Points::new(dims, block)?,
            rows: vec![0.0; dims * block],
            x: vec![0.0; dims * block],
            jacobians: vec![0.0; block],
            cells: vec![0; dims * block],
            mapped: Points::new(dims, block)?,
            coords: vec![0; dims],
            coords_f: vec![0.0; dims],
            values: vec![0.0; m * block],
            point: vec![0.0; m],
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

    /// Evaluates chunk `chunk` into `out`, block by block: the block's points are mapped
    /// through the grid (walking the hypercubes they fall in), evaluated together, then summed
    /// per hypercube (walking the hypercubes again).
    fn run_chunk<I: Integrand>(
        &mut self,
        pass: &Pass<I>,
        chunk: usize,
        out: &mut Piece,
        training: &mut [f64],
        limits: &Limits,
    ) -> Result<bool> {
        let start = pass.chunks[chunk];
        let end = pass.chunks.get(chunk + 1).map_or(pass.total, |c| c.index);
        let dims = self.coords.len();
        let grid = pass.grid;
        let strata = pass.strata;
        out.reset(&start);

        // The hypercube being summed, its points still to come, and whether it began in an
        // earlier chunk; the mapping runs ahead within a block with its own count.
        let mut cube = start.cube;
        self.set_coords(cube, strata);
        let mut cube_n = pass.allocation.evaluations(cube);
        let mut remaining = cube_n - start.offset;
        let (mut mapping_cube, mut mapping_remaining) = (cube, remaining);
        let mut continued = start.offset > 0;
        // Each point's share of y-space volume weights its training data, so that the
        // per-increment averages of (J f)^2 are consistent under any allocation.
        let mut share = strata.cube_volume / cube_n as f64;
        // Known at compile time for a scalar integrand, so its loops over outputs vanish.
        let m = pass.f.outputs();
        let mut sums = CubeSums::new(m);

        let block = self.block as u64;
        let mut index = start.index;
        while index < end {
            if limits.reached().is_some() {
                return Ok(false);
            }
            let len = (end - index).min(block) as usize;
            self.points.set_len(len);
            pass.sampler.fill(pass.base + index, &mut self.points)?;
            for d in 0..dims {
                for (j, &u) in self.points.column(d).iter().enumerate() {
                    self.rows[j * dims + d] = u;
                }
            }
            for j in 0..len {
                if mapping_remaining == 0 {
                    mapping_cube += 1;
                    self.next_coords(strata);
                    mapping_remaining = pass.allocation.evaluations(mapping_cube);
                }
                mapping_remaining -= 1;
                let mut jacobian = 1.0;
                for d in 0..dims {
                    let y = (self.coords_f[d] + self.rows[j * dims + d]) * strata.inverse[d];
                    let (x, factor, cell) = grid.map_axis(d, y);
                    self.x[j * dims + d] = x;
                    self.cells[j * dims + d] = cell;
                    jacobian *= factor;
                }
                self.jacobians[j] = jacobian;
            }
            self.mapped.set_len(len);
            let values = &mut self.values[..m * len];
            pass.f
                .eval_block(&self.x[..len * dims], &mut self.mapped, values);
            if pass.probing {
                for (largest, values) in out.largest.iter_mut().zip(values.chunks(len)) {
                    for v in values.iter().filter(|v| v.is_finite()) {
                        *largest = largest.max(v.abs());
                    }
                }
            }
            for j in 0..len {
                if remaining == 0 {
                    out.close_cube(&sums, continued, pass);
                    continued = false;
                    sums.clear();
                    cube += 1;
                    cube_n = pass.allocation.evaluations(cube);
                    remaining = cube_n;
                    share = strata.cube_volume / cube_n as f64;
                }
                remaining -= 1;
                let jacobian = self.jacobians[j];
                let point = &mut self.point[..m];
                let mut weighted = 0.0;
                let mut bad = None;
                let outputs = point.iter_mut().zip(&pass.weights[..m]);
                for (k, ((y, w), inverse)) in outputs.zip(&pass.inverse_units[..m]).enumerate() {
                    *y = self.values[k * len + j] * inverse * jacobian;
                    if !y.is_finite() {
                        bad.get_or_insert((k, *y));
                    }
                    weighted += w * (*y * *y);
                }
                if let Some((k, v)) = bad {
                    out.non_finite += 1;
                    out.first_non_finite.get_or_insert_with(|| FirstNonFinite {
                        index: index + j as u64,
                        value: v,
                        output: k,
                        point: canonical_point(&self.rows[j * dims..(j + 1) * dims], cube, strata),
                    });
                    continue;
                }
                sums.push(point);
                let weighted = weighted * share;
                for &cell in &self.cells[j * dims..(j + 1) * dims] {
                    training[2 * cell] += weighted;
                    training[2 * cell + 1] += share;
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
        Ok(true)
    }
}
