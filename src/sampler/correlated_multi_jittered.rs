//! Correlated multi-jittered sampling (Kensler 2013, "Correlated Multi-Jittered Sampling",
//! Pixar Technical Memo 13-01, section 4 and Listing 3).
//!
//! Like multi-jittered sampling (Chiu, Shirley & Wang 1994) a pass of `N = m * n` points is
//! jittered on the `m x n` grid and N-rooks in both coordinates, but the sub-cell shuffle is
//! *correlated*: one permutation of `0..n` reorders the sub-columns of every column and one
//! permutation of `0..m` the sub-rows of every row. The canonical arrangement's regular,
//! near-lattice spacing between neighbouring cells then survives the shuffle, which Kensler
//! shows lowers the variance further for smooth integrands. The permutations are hashed
//! random-access ones, so any point is computed directly from `(seed, pass, index)`, and a
//! further hashed permutation of `0..N` assigns point numbers to cells.
//!
//! More than two dimensions are taken in pairs `(0, 1), (2, 3), ...` with independent seeds
//! and independent point-to-cell assignments; an odd last dimension is a one-dimensional
//! N-rooks (Latin) stratification. See [`MultiJittered`](super::MultiJittered) for the
//! uncorrelated variant, with which this shares its implementation.

use super::multi_jittered::MjCore;
use super::{PassKind, Sampler};
use crate::error::Result;
use crate::points::Points;

/// Correlated multi-jittered sampling: `N = m * n` points per pass, jittered on the `m x n`
/// grid and N-rooks in both coordinates of every pair of dimensions, with one sub-column and
/// one sub-row shuffle shared by all columns and rows (Kensler 2013).
///
/// Only whole passes are stratified: integrators use passes of `N` points as replicates.
///
/// ```
/// use mcint::sampler::{CorrelatedMultiJittered, Sampler};
/// let s = CorrelatedMultiJittered::new(2, 4, 4, 7).unwrap(); // 16 points per pass
/// let (mut cells, mut x_slabs, mut y_slabs) = (vec![0; 16], vec![0; 16], vec![0; 16]);
/// let mut p = [0.0; 2];
/// for i in 16..32 {
///     // The second pass.
///     s.point(i, &mut p).unwrap();
///     cells[(p[0] * 4.0) as usize + 4 * (p[1] * 4.0) as usize] += 1;
///     x_slabs[(p[0] * 16.0) as usize] += 1;
///     y_slabs[(p[1] * 16.0) as usize] += 1;
/// }
/// assert!(cells.iter().chain(&x_slabs).chain(&y_slabs).all(|&c| c == 1));
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CorrelatedMultiJittered {
    core: MjCore,
}

impl CorrelatedMultiJittered {
    /// `m >= 1` columns by `n >= 1` rows of cells, `N = m * n <= 2^53` points per pass, in
    /// `dims >= 1` dimensions.
    ///
    /// ```
    /// use mcint::sampler::{CorrelatedMultiJittered, PassKind, Sampler};
    /// let s = CorrelatedMultiJittered::new(4, 8, 8, 0).unwrap();
    /// assert_eq!(s.passes(), PassKind::Fixed { size: 64 });
    /// assert!(CorrelatedMultiJittered::new(2, 8, 0, 0).is_err());
    /// assert!(CorrelatedMultiJittered::new(0, 8, 8, 0).is_err());
    /// ```
    pub fn new(dims: usize, m: u64, n: u64, seed: u64) -> Result<Self> {
        Ok(CorrelatedMultiJittered {
            core: MjCore::new(dims, m, n, seed, true)?,
        })
    }

    /// `points` per pass (`1 <= points <= 2^53`), with `m <= n`, `m * n = points` and `m` as
    /// close to `sqrt(points)` as possible. A prime count gives a `1 x N` grid.
    /// The grid comes from the prime factors of `points` (by Pollard's rho), so any count is
    /// quick.
    ///
    /// ```
    /// use mcint::sampler::CorrelatedMultiJittered;
    /// let s = CorrelatedMultiJittered::with_points(2, 100, 0).unwrap();
    /// assert_eq!((s.m(), s.n()), (10, 10));
    /// let err = CorrelatedMultiJittered::with_points(2, 0, 0).unwrap_err().to_string();
    /// assert!(err.contains("points") && err.contains("between 1 and 2^53"), "{err}");
    /// ```
    pub fn with_points(dims: usize, points: u64, seed: u64) -> Result<Self> {
        Ok(CorrelatedMultiJittered {
            core: MjCore::with_points(dims, points, seed, true)?,
        })
    }

    /// Columns of cells, `m`.
    ///
    /// ```
    /// assert_eq!(mcint::sampler::CorrelatedMultiJittered::new(2, 3, 5, 0).unwrap().m(), 3);
    /// ```
    pub fn m(&self) -> u64 {
        self.core.m()
    }

    /// Rows of cells, `n`.
    ///
    /// ```
    /// assert_eq!(mcint::sampler::CorrelatedMultiJittered::new(2, 3, 5, 0).unwrap().n(), 5);
    /// ```
    pub fn n(&self) -> u64 {
        self.core.n()
    }
}

impl Sampler for CorrelatedMultiJittered {
    fn name(&self) -> &'static str {
        "cmj"
    }

    fn dims(&self) -> usize {
        self.core.dims
    }

    fn passes(&self) -> PassKind {
        PassKind::Fixed {
            size: self.core.pass_size,
        }
    }

    fn seed(&self) -> u64 {
        self.core.seed
    }

    fn reseed(&mut self, seed: u64) {
        self.core.seed = seed;
    }

    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        self.core.point(index, out)
    }

    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        self.core.fill(start, points)
    }
}
