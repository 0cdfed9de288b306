//! [`Integrand`]: VEGAS's view of a scalar or a vector-valued integrand, evaluated one point
//! or one block of points at a time, so that one iteration loop serves every form.

use crate::points::Points;

/// `m` values `f_k(x)` per point.
pub(super) trait Integrand: Sync {
    /// Number of outputs `m`.
    fn outputs(&self) -> usize;

    /// The most points evaluated together: a cache-sized block for a per-point integrand,
    /// larger for one that pays per call.
    fn block(&self) -> usize {
        512
    }

    /// Writes `f_k` at point `i` of `rows` (one row of `dims` coordinates per point, in
    /// `points` when the integrand takes blocks: the same coordinates, one column per axis)
    /// to `out[k * n + i]`, for the `n` points of the block.
    fn eval_block(&self, rows: &[f64], points: &mut Points, out: &mut [f64]);
}

/// Writes `f(x_i)` of a per-point integrand `f(x, out)` to `out[k * n + i]`.
#[inline]
fn per_point(
    m: usize,
    rows: &[f64],
    n: usize,
    out: &mut [f64],
    mut f: impl FnMut(&[f64], &mut [f64]),
) {
    let dims = rows.len() / n.max(1);
    let mut values = [0.0; 1];
    let mut many = Vec::new();
    let point_out: &mut [f64] = if m == 1 {
        &mut values
    } else {
        many.resize(m, 0.0);
        &mut many
    };
    for i in 0..n {
        f(&rows[i * dims..(i + 1) * dims], point_out);
        for (k, &y) in point_out.iter().enumerate() {
            out[k * n + i] = y;
        }
    }
}

/// A scalar integrand: one output, the very value of `f`.
pub(super) struct Scalar<'a, F>(pub(super) &'a F);

impl<F: Fn(&[f64]) -> f64 + Sync> Integrand for Scalar<'_, F> {
    fn outputs(&self) -> usize {
        1
    }

    #[inline]
    fn eval_block(&self, rows: &[f64], points: &mut Points, out: &mut [f64]) {
        per_point(1, rows, points.len(), out, |x, y| y[0] = (self.0)(x));
    }
}

/// The integrand of a vector VEGAS run, with what the run must reach: see
/// [`Vegas::new_vector`](super::super::Vegas::new_vector), which builds it, and
/// [`Vegas::new_batch`](super::super::Vegas::new_batch) for one evaluated by blocks.
///
/// ```
/// use mcint::adaptive::{Vegas, VegasOutputs};
/// use mcint::pdf::UniformBox;
/// fn both(x: &[f64], out: &mut [f64]) {
///     out[0] = x[0];
///     out[1] = x[0] * x[0];
/// }
/// let run: Vegas<VegasOutputs<fn(&[f64], &mut [f64])>> =
///     Vegas::new_vector(2, both as fn(&[f64], &mut [f64]), UniformBox::unit(1).unwrap());
/// assert_eq!(run.run().unwrap().len(), 2);
/// ```
pub struct VegasOutputs<F> {
    pub(super) outputs: usize,
    pub(super) f: F,
    pub(super) output_tolerances: Option<Vec<crate::stats::Tolerance>>,
    pub(super) derived_tolerances: Vec<(crate::stats::Derived, crate::stats::Tolerance)>,
}

impl<F: Fn(&[f64], &mut [f64]) + Sync> Integrand for VegasOutputs<F> {
    fn outputs(&self) -> usize {
        self.outputs
    }

    #[inline]
    fn eval_block(&self, rows: &[f64], points: &mut Points, out: &mut [f64]) {
        per_point(self.outputs, rows, points.len(), out, |x, y| {
            // An output the integrand does not write is reported as non-finite.
            y.fill(f64::NAN);
            (self.f)(x, y);
        });
    }
}

/// An integrand evaluated a block of points (up to 4096) at a time, `f(points, out)` writing output `k` at
/// point `i` to `out[k * n + i]` (the layout of
/// [`Integrator::over_box_vector_batch`](crate::Integrator::over_box_vector_batch)): what
/// [`Vegas::new_batch`](super::super::Vegas::new_batch) wraps, for integrands that pay a cost
/// per call (an interpreter, a GPU, a vectorized kernel).
///
/// ```
/// use mcint::adaptive::{Vegas, VegasBatch, VegasOutputs};
/// use mcint::{Points, pdf::UniformBox};
/// let f = |p: &Points, out: &mut [f64]| out.copy_from_slice(p.column(0));
/// let run: Vegas<VegasOutputs<VegasBatch<_>>> = Vegas::new_batch(1, f, UniformBox::unit(1).unwrap());
/// assert!((run.samples(1000).run().unwrap().outputs[0].mean - 0.5).abs() < 0.05);
/// ```
pub struct VegasBatch<G>(pub(super) G);

impl<G: Fn(&Points, &mut [f64]) + Sync> Integrand for VegasOutputs<VegasBatch<G>> {
    fn outputs(&self) -> usize {
        self.outputs
    }

    fn block(&self) -> usize {
        4096
    }

    #[inline]
    fn eval_block(&self, rows: &[f64], points: &mut Points, out: &mut [f64]) {
        let (n, dims) = (points.len(), points.dims());
        for (d, column) in points.columns_mut().enumerate() {
            for (i, x) in column.iter_mut().enumerate() {
                *x = rows[i * dims + d];
            }
        }
        // An output the integrand does not write is reported as non-finite.
        out[..n * self.outputs].fill(f64::NAN);
        (self.f.0)(points, &mut out[..n * self.outputs]);
    }
}
