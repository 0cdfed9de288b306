//! Blocks of canonical points mapped into a box, shared by the uniform estimators' block
//! paths: the same arithmetic as [`UniformBox`]'s per-point `sample`, column by column.

use crate::pdf::UniformBox;
use crate::points::Points;
use crate::simd::{Kernel, dispatch};
use std::cell::Cell;

thread_local! {
    /// Scratch block for mapping canonical points into a non-unit box, reused by every block
    /// a thread evaluates (taken out while in use, so a nested integration gets its own).
    static SCRATCH: Cell<Option<Points>> = const { Cell::new(None) };
}

/// Whether `domain` is the unit cube `[0, 1)^d`, where canonical points need no mapping.
pub(super) fn is_unit(domain: &UniformBox) -> bool {
    domain.lo().iter().all(|&lo| lo == 0.0) && domain.hi().iter().all(|&hi| hi == 1.0)
}

/// Calls `work` with the block `points` mapped into `domain`: over the unit cube (`unit`) a
/// canonical block is passed as it is (no copy), otherwise it is mapped into a per-thread
/// scratch block, so no block allocates.
pub(super) fn with_mapped(
    domain: &UniformBox,
    unit: bool,
    points: &Points,
    work: impl FnOnce(&Points),
) {
    if unit && all_canonical(points) {
        return work(points);
    }
    let mut scratch = SCRATCH
        .take()
        .filter(|s| s.dims() == points.dims())
        .or_else(|| Points::new(points.dims(), 0).ok());
    // A block has at least one dimension, so the scratch block always exists.
    if let Some(x) = scratch.as_mut() {
        x.set_len(points.len());
        map_block(domain, points, x);
        work(x);
    }
    SCRATCH.set(scratch);
}

/// Fills `out` with NaN (so a value the integrand leaves unwritten is caught as non-finite),
/// lets `f` write it, and scales it by `volume`: the per-point estimator's `volume * f`, bit
/// for bit (IEEE multiplication commutes exactly; over a volume of one the product is the
/// value itself, so there is no pass).
pub(super) fn evaluate_scaled(volume: f64, out: &mut [f64], f: impl FnOnce(&mut [f64])) {
    out.fill(f64::NAN);
    f(out);
    if volume != 1.0 {
        for y in out.iter_mut() {
            *y *= volume;
        }
    }
}

/// Whether every coordinate is in `[+0, 1)`: then `0 + u * (1 - 0)` is `u` itself. Written
/// without early exits so that it vectorizes: a comparison below one (false for NaN and
/// `+inf`) and the OR of all sign bits (set for negative numbers, `-0.0` and `-inf`).
fn all_canonical(points: &Points) -> bool {
    dispatch(AllCanonical(points))
}

/// [`all_canonical`] as a kernel for the run-time dispatch.
struct AllCanonical<'a>(&'a Points);

impl Kernel for AllCanonical<'_> {
    type Output = bool;
    #[inline(always)]
    fn run(self) -> bool {
        let points = self.0;
        (0..points.dims()).all(|d| {
            let (mut below_one, mut signs) = (true, 0u64);
            for &u in points.column(d) {
                below_one &= u < 1.0;
                signs |= u.to_bits();
            }
            below_one && signs >> 63 == 0
        })
    }
}

/// Maps the canonical block `u` into `domain`, column by column, with the arithmetic of
/// [`UniformBox`]'s `sample` (so every coordinate has the same bits).
fn map_block(domain: &UniformBox, u: &Points, x: &mut Points) {
    for (d, column) in x.columns_mut().enumerate() {
        let (lo, hi) = (domain.lo()[d], domain.hi()[d]);
        let top = hi.next_down();
        for (x, &u) in column.iter_mut().zip(u.column(d)) {
            let v = lo + u * (hi - lo);
            *x = if v < hi { v } else { top };
        }
    }
}
