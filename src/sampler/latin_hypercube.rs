//! N-rooks / Latin hypercube sampling (Shirley 1990; McKay, Beckman & Conover 1979).
//!
//! Each pass of `N` points has exactly one point in each of the `N` equal slabs of every axis:
//! coordinate `j` of point `i` is `(pi_j(i) + xi) / N` for independent random permutations
//! `pi_j`. Unlike jittered sampling, `N` is free and does not grow as `k^d`; the variance is
//! never much worse than independent sampling (at most `N/(N-1)` times, Owen 1997) and removes
//! the additive (one-dimensional) part of the integrand's variation.

use super::permutation::Permutation;
use super::simd::{BlockFill, dispatch_fill};
use super::{PassKind, Sampler, check_dims, check_point, pass_runs};
use crate::float::ONE_BELOW;
use crate::hash::{hash_absorb, hash_words, unit_f64};
use crate::simd::Kernel;

/// Salts this sampler's hashes, so that other samplers given the same seed (which hash the
/// same `(pass, index, dim)` words for their jitter) draw unrelated numbers.
const SALT: u64 = 0x006c_6873; // "lhs"
use crate::error::{Error, Result};
use crate::points::Points;

/// `N` points per pass, one in each `1/N` slab of every coordinate.
///
/// The permutations are hashed (Kensler 2013), so any point is computed directly from
/// `(seed, pass, index, dim)` without storing a permutation.
///
/// ```
/// use mcint::sampler::{LatinHypercube, Sampler};
/// let s = LatinHypercube::new(2, 10, 3).unwrap();
/// let mut rows = vec![0; 10];
/// let mut p = [0.0; 2];
/// for i in 0..10 {
///     s.point(i, &mut p).unwrap();
///     rows[(p[1] * 10.0) as usize] += 1;
/// }
/// assert!(rows.iter().all(|&r| r == 1));
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LatinHypercube {
    dims: usize,
    pass_size: u64,
    seed: u64,
}

impl LatinHypercube {
    /// `points >= 1` points per pass in `dims >= 1` dimensions.
    ///
    /// ```
    /// assert!(mcint::sampler::LatinHypercube::new(2, 0, 0).is_err());
    /// ```
    pub fn new(dims: usize, points: u64, seed: u64) -> Result<Self> {
        check_dims(dims)?;
        if points == 0 {
            return Err(Error::invalid("points", 0, "at least 1 point per pass"));
        }
        Ok(LatinHypercube {
            dims,
            pass_size: points,
            seed,
        })
    }

    /// The permutation of slabs used for `dim` in `pass`.
    fn permutation(&self, pass: u64, dim: usize) -> Permutation {
        Permutation::new(
            self.pass_size,
            hash_words(self.seed, &[pass, dim as u64, SALT]),
        )
    }

    /// Coordinate of point `index` in `dim`, given that dimension's permutation for its pass.
    #[inline]
    fn coordinate(&self, permutation: &Permutation, index: u64, dim: usize) -> f64 {
        let pass = index / self.pass_size;
        let slab = permutation.apply(index % self.pass_size);
        let jitter = unit_f64(hash_words(self.seed, &[SALT, pass, index, dim as u64]));
        ((slab as f64 + jitter) / self.pass_size as f64).min(ONE_BELOW)
    }
}

impl Sampler for LatinHypercube {
    fn dims(&self) -> usize {
        self.dims
    }

    fn passes(&self) -> PassKind {
        PassKind::Fixed {
            size: self.pass_size,
        }
    }

    fn seed(&self) -> u64 {
        self.seed
    }

    fn reseed(&mut self, seed: u64) {
        self.seed = seed;
    }

    fn name(&self) -> &'static str {
        "latin"
    }

    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        check_point(self.dims, out)?;
        let pass = index / self.pass_size;
        for (dim, x) in out.iter_mut().enumerate() {
            *x = self.coordinate(&self.permutation(pass, dim), index, dim);
        }
        Ok(())
    }

    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        dispatch_fill(self, self.dims, start, points)
    }
}

/// Indices per step of the block fill kernel (a multiple of the 16 permutation lanes).
const CHUNK: usize = 256;

/// The block fill, compiled for each instruction set by [`dispatch_fill`]. Per column and per run
/// of indices within one pass: the slabs of a chunk of indices by the pass's permutation,
/// 16 indices at a time (independent chains of hash rounds, vector lanes on a wide
/// instruction set), and the jitter hash with its seed and pass words absorbed once per run.
/// The integers and the final `f64` expression are those of `coordinate`, so the values are
/// bit-identical to `point`.
impl Kernel for BlockFill<'_, LatinHypercube> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let (sampler, start, points) = (self.sampler, self.start, self.points);
        let size = sampler.pass_size;
        let size_f64 = size as f64;
        let len = points.len();
        let (mut inputs, mut slabs) = ([0u64; CHUNK], [0u64; CHUNK]);
        for dim in 0..sampler.dims {
            let column = points.column_mut(dim);
            for (done, pass, local, run) in pass_runs(start, len, size) {
                let index = start + done as u64;
                let permutation = sampler.permutation(pass, dim);
                // hash_words(seed, [SALT, pass, index, dim]) with the seed, salt and pass
                // absorbed.
                let pass_hash = hash_words(sampler.seed, &[SALT, pass]);
                for offset in (0..run).step_by(CHUNK) {
                    let c = CHUNK.min(run - offset);
                    let first = local + offset as u64;
                    for (j, input) in inputs[..c].iter_mut().enumerate() {
                        *input = first + j as u64;
                    }
                    permutation.apply_into(&inputs[..c], &mut slabs[..c]);
                    let first_index = index + offset as u64;
                    let out = &mut column[done + offset..done + offset + c];
                    for (j, (x, &slab)) in out.iter_mut().zip(&slabs[..c]).enumerate() {
                        let jitter = unit_f64(hash_absorb(
                            hash_absorb(pass_hash, first_index + j as u64),
                            dim as u64,
                        ));
                        *x = ((slab as f64 + jitter) / size_f64).min(ONE_BELOW);
                    }
                }
            }
        }
    }
}
