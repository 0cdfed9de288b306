//! [`ScalarBatch`]: a scalar integrand of MISER or the two-stage rule evaluated a block of
//! points at a time, and [`ScalarIntegrand`], how both methods evaluate either form.

use super::batches::{BLOCK, Workspace};
use crate::points::Points;

/// Points per call of a [`ScalarBatch`] integrand: calls that pay a fixed cost (an
/// interpreter, a GPU) amortize it over many points.
const BATCH_BLOCK: usize = 4096;

/// A scalar integrand evaluated a block of points (up to 4,096) at a time, `f(points, out)`
/// writing `f(x_i)` to `out[i]`: what [`Miser::new_batch`](super::Miser::new_batch) and
/// [`TwoStage::new_batch`](super::TwoStage::new_batch) wrap. The points are in the domain's
/// coordinates, one column per axis; a value left unwritten counts as non-finite.
///
/// ```
/// use mcint::adaptive::{Miser, ScalarBatch};
/// use mcint::{Points, pdf::UniformBox};
/// let f = |p: &Points, out: &mut [f64]| out.copy_from_slice(p.column(0));
/// let run: Miser<ScalarBatch<_>> = Miser::new_batch(f, UniformBox::unit(2).unwrap());
/// assert!((run.samples(4096).seed(1).run().unwrap().mean - 0.5).abs() < 0.01);
/// ```
pub struct ScalarBatch<G>(pub(super) G);

/// How MISER and the two-stage rule evaluate their integrand: over the points of a block,
/// each placed in the domain by the method, the values visited in the points' order (so a
/// per-point and a block integrand give the same bits).
pub(super) trait ScalarIntegrand: Sync {
    /// The most points generated and evaluated together.
    fn block(&self) -> usize {
        BLOCK
    }

    /// For each of the first `len` points of `work.points` in order: `place(points, i, unit,
    /// x)` writes its coordinates in the unit cube and in the domain, and `visit(i, f(x),
    /// unit)` receives the value.
    fn each(
        &self,
        len: usize,
        work: &mut Workspace,
        place: impl Fn(&Points, usize, &mut [f64], &mut [f64]),
        visit: impl FnMut(usize, f64, &[f64]),
    );
}

impl<F: Fn(&[f64]) -> f64 + Sync> ScalarIntegrand for F {
    #[inline]
    fn each(
        &self,
        len: usize,
        work: &mut Workspace,
        place: impl Fn(&Points, usize, &mut [f64], &mut [f64]),
        mut visit: impl FnMut(usize, f64, &[f64]),
    ) {
        for i in 0..len {
            place(&work.points, i, &mut work.unit, &mut work.x);
            visit(i, self(&work.x), &work.unit);
        }
    }
}

impl<G: Fn(&Points, &mut [f64]) + Sync> ScalarIntegrand for ScalarBatch<G> {
    fn block(&self) -> usize {
        BATCH_BLOCK
    }

    fn each(
        &self,
        len: usize,
        work: &mut Workspace,
        place: impl Fn(&Points, usize, &mut [f64], &mut [f64]),
        mut visit: impl FnMut(usize, f64, &[f64]),
    ) {
        let dims = work.unit.len();
        let block = &mut work.block;
        block.units.set_len(len);
        block.xs.set_len(len);
        for i in 0..len {
            place(&work.points, i, &mut work.unit, &mut work.x);
            for d in 0..dims {
                block.units.column_mut(d)[i] = work.unit[d];
                block.xs.column_mut(d)[i] = work.x[d];
            }
        }
        block.values.clear();
        block.values.resize(len, f64::NAN);
        (self.0)(&block.xs, &mut block.values);
        for (i, &y) in block.values.iter().enumerate() {
            block.units.copy_point(i, &mut work.unit);
            visit(i, y, &work.unit);
        }
    }
}
