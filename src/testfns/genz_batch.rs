//! The Genz families evaluated a block at a time: sums over the axes column by column, then
//! one vectorized `exp` or `cos` ([`crate::vector_math`]) over the block.
//!
//! The sums, products and powers are formed in the same order as `Genz::eval`, so only the
//! final `exp` or `cos` differs from it, by an ulp or two (product and corner peaks, which
//! need neither, give the same bits).

use std::f64::consts::PI;

use super::GenzFamily;
use crate::points::Points;
use crate::simd::{Kernel, dispatch};
use crate::vector_math::{cos_in_place, exp_in_place};

/// A Genz integrand's parameters, borrowed for one block.
pub(super) struct Parameters<'a> {
    pub(super) family: GenzFamily,
    pub(super) a: &'a [f64],
    pub(super) u: &'a [f64],
    /// `a_i^{-2}`.
    pub(super) inv_a_sq: &'a [f64],
}

impl Parameters<'_> {
    /// `out[i] = f(x_i)` for every point of the block, compiled for the widest vector
    /// instructions the CPU has (the same bits on every instruction set: no sum is
    /// reordered).
    pub(super) fn eval_batch(&self, points: &Points, out: &mut [f64]) {
        dispatch(Block {
            parameters: self,
            points,
            out,
        });
    }

    /// [`eval_batch`](Parameters::eval_batch), inlined into each dispatched build.
    #[inline(always)]
    fn eval_inline(&self, points: &Points, out: &mut [f64]) {
        let out = &mut out[..points.len()];
        let axes = || self.a.iter().zip(self.u).enumerate();
        match self.family {
            GenzFamily::Oscillatory => {
                out.fill(0.0);
                for (k, (ak, _)) in axes() {
                    add_each(out, points.column(k), |x| ak * x);
                }
                let shift = 2.0 * PI * self.u[0];
                out.iter_mut().for_each(|y| *y += shift);
                // Each y is now 2π u_1 + Σ a_k x_k, summed as `eval` does.
                cos_in_place(out);
            }
            GenzFamily::ProductPeak => {
                out.fill(1.0);
                for (k, (_, uk)) in axes() {
                    let c = self.inv_a_sq[k];
                    let column = points.column(k);
                    for (y, x) in out.iter_mut().zip(column) {
                        *y *= 1.0 / (c + (x - uk) * (x - uk));
                    }
                }
            }
            GenzFamily::CornerPeak => {
                out.fill(0.0);
                for (k, (ak, _)) in axes() {
                    add_each(out, points.column(k), |x| ak * x);
                }
                out.iter_mut().for_each(|y| *y += 1.0);
                inverse_power(out, self.a.len() + 1);
            }
            GenzFamily::Gaussian => {
                out.fill(0.0);
                for (k, (ak, uk)) in axes() {
                    add_each(out, points.column(k), |x| {
                        let t = ak * (x - uk);
                        t * t
                    });
                }
                out.iter_mut().for_each(|y| *y = -*y);
                exp_in_place(out);
            }
            GenzFamily::Continuous => {
                out.fill(0.0);
                for (k, (ak, uk)) in axes() {
                    add_each(out, points.column(k), |x| ak * (x - uk).abs());
                }
                out.iter_mut().for_each(|y| *y = -*y);
                exp_in_place(out);
            }
            GenzFamily::Discontinuous => {
                out.fill(0.0);
                for (k, (ak, _)) in axes() {
                    add_each(out, points.column(k), |x| ak * x);
                }
                exp_in_place(out);
                // The cut is on the first two axes only.
                for (k, uk) in self.u.iter().enumerate().take(2) {
                    for (y, x) in out.iter_mut().zip(points.column(k)) {
                        if x > uk {
                            *y = 0.0;
                        }
                    }
                }
            }
        }
    }
}

/// One block's evaluation, as a kernel for the run-time dispatch.
struct Block<'a> {
    parameters: &'a Parameters<'a>,
    points: &'a Points,
    out: &'a mut [f64],
}

impl Kernel for Block<'_> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        self.parameters.eval_inline(self.points, self.out);
    }
}

/// `out[i] += term(column[i])`.
#[inline(always)]
fn add_each(out: &mut [f64], column: &[f64], term: impl Fn(f64) -> f64) {
    for (y, &x) in out.iter_mut().zip(column) {
        *y += term(x);
    }
}

/// `y^-n` for every `y`, as `f64::powi` computes it (square and multiply over the bits of `n`
/// from the lowest, then one reciprocal), but a stack-sized run of values at a time.
#[inline(always)]
fn inverse_power(out: &mut [f64], n: usize) {
    if i32::try_from(n).is_err() {
        out.iter_mut().for_each(|y| *y = y.powf(-(n as f64)));
        return;
    }
    const RUN: usize = 256;
    for run in out.chunks_mut(RUN) {
        let mut base = [0.0; RUN];
        let base = &mut base[..run.len()];
        base.copy_from_slice(run);
        run.fill(1.0);
        let mut bits = n;
        loop {
            if bits & 1 == 1 {
                run.iter_mut().zip(base.iter()).for_each(|(r, b)| *r *= b);
            }
            bits >>= 1;
            if bits == 0 {
                break;
            }
            base.iter_mut().for_each(|b| *b *= *b);
        }
        run.iter_mut().for_each(|r| *r = 1.0 / *r);
    }
}
