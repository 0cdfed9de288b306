//! Samplers: points in the unit cube `[0,1)^k`, knowing nothing of integrands.
//!
//! Every point is a pure function of `(seed, pass, index, dim)`, so a sampler is random-access,
//! deterministic and trivially parallel. A sampler with a fixed-size point set (jittered, Latin
//! hypercube) numbers its points `p * N + i` for point `i` of pass `p`, and each pass is an
//! independent re-randomization: every sampler is an endless stream of independent passes,
//! which is what honest error bars need (see [`PassKind`]).
//!
//! The seed's section A.3.3 motivates the stratified placements: stratified (jittered)
//! sampling (equation A.30), and N-rooks / Latin hypercube sampling (Shirley 1990; McKay,
//! Beckman & Conover 1979). [`Antithetic`] wraps any sampler to pair every point with its
//! reflection (Hammersley & Morton 1956), a variance-reduction companion of A.3's techniques.

mod antithetic;
mod best_candidate;
mod correlated_multi_jittered;
mod draw;
mod halton;
mod hammersley;
mod independent;
mod jittered;
mod latin_hypercube;
mod lattice;
mod lloyd;
mod multi_jittered;
mod multi_stage_n_rooks;
mod named;
mod nearest_point;
mod number_theory;
mod orthogonal_array;
pub(crate) mod owen;
mod pass_cache;
mod pass_rng;
pub(crate) mod permutation;
mod pmj02;
mod poisson_disk;
mod radical_inverse;
mod random_cd;
mod scramble;
#[doc(hidden)]
pub mod simd;
mod sobol;
mod torus;
mod torus_grid;

pub use antithetic::{Antithetic, reflect};
pub use best_candidate::BestCandidate;
pub use correlated_multi_jittered::CorrelatedMultiJittered;
pub use halton::Halton;
pub use hammersley::Hammersley;
pub use independent::Independent;
pub use jittered::Jittered;
pub use latin_hypercube::LatinHypercube;
pub use lattice::Lattice;
pub use lloyd::{Lloyd, lloyd};
pub use multi_jittered::MultiJittered;
pub use multi_stage_n_rooks::MultiStageNRooks;
pub use named::{SamplerKind, build_sampler};
pub use orthogonal_array::{OaOffset, OrthogonalArray};
pub use pmj02::Pmj02;
pub use poisson_disk::PoissonDisk;
#[cfg(test)]
pub(crate) use radical_inverse::thread_table_slots;
pub use random_cd::{RandomCd, random_cd};
pub use scramble::Scramble;
pub use sobol::Sobol;

use crate::error::{Error, Result};
use crate::points::{PointBlock, Points};
use crate::points_f32::{PointsF32, to_unit_f32};

/// How a sampler's points relate to each other, which decides how error bars are computed.
///
/// ```
/// use mcint::sampler::{Jittered, PassKind, Sampler};
/// let s = Jittered::new(2, 4, 0).unwrap();
/// assert_eq!(s.passes(), PassKind::Fixed { size: 16 });
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PassKind {
    /// Every point is independent of every other: the per-sample variance gives an honest
    /// standard error, and any number of points may be used.
    Independent,
    /// Points come in independent passes of exactly `size` points. Only whole passes keep
    /// the construction's stratification (and, for some, unbiasedness), so error bars come
    /// from the spread between passes.
    Fixed {
        /// Points per pass.
        size: u64,
    },
    /// Points come in independent passes of up to `max` points, and any prefix of a pass is
    /// a valid point set (extensible quasi-Monte Carlo sequences). Error bars come from the
    /// spread between passes.
    Extensible {
        /// The most points one pass can hold.
        max: u64,
    },
}

/// A source of points in the unit cube.
///
/// Implementors guarantee that every coordinate lies in `[0, 1)`, that [`point`](Self::point)
/// and [`fill`](Self::fill) give bit-identical values, and that the same seed always gives the
/// same points.
///
/// ```
/// use mcint::{Points, sampler::{Independent, Sampler}};
/// let sampler = Independent::new(3, 42).unwrap();
/// let mut block = Points::new(3, 8).unwrap();
/// sampler.fill(100, &mut block).unwrap();
/// let mut p = [0.0; 3];
/// sampler.point(105, &mut p).unwrap();
/// assert_eq!(p[2], block.get(5, 2));
/// ```
pub trait Sampler: Send + Sync {
    /// A short lower-case name (`"independent"`, `"jittered"`, ...).
    fn name(&self) -> &'static str;

    /// Number of dimensions `k` of each point.
    fn dims(&self) -> usize;

    /// How points are grouped into independent passes.
    fn passes(&self) -> PassKind;

    /// The seed that selects this sampler's randomization.
    fn seed(&self) -> u64;

    /// Selects a different randomization; the structure (dimension, pass size) is unchanged.
    fn reseed(&mut self, seed: u64);

    /// Whether passes are independent randomizations. A deterministic point set (an
    /// unscrambled quasi-Monte Carlo sequence) returns false: its passes repeat each other, so
    /// no standard error can be computed from them.
    fn is_randomized(&self) -> bool {
        true
    }

    /// The base `b` when `n` points per replicate break this sampler's balance: its points
    /// are nets or lattices only in blocks of a whole power of `b` (Sobol', pmj02, rank-1
    /// lattices; Hammersley sets of a power-of-two size), so other sizes lose the structure
    /// and the convergence rate, as scipy warns. `None` (the default) when `n` keeps it, or
    /// the sampler has no such structure.
    ///
    /// ```
    /// use mcint::sampler::{Independent, Sampler, Scramble, Sobol};
    /// let sobol = Sobol::new(2, Scramble::Owen, 0).unwrap();
    /// assert_eq!(sobol.unbalanced_by(1000), Some(2));
    /// assert_eq!(sobol.unbalanced_by(1024), None);
    /// assert_eq!(Independent::new(2, 0).unwrap().unbalanced_by(1000), None);
    /// ```
    fn unbalanced_by(&self, n: u64) -> Option<u64> {
        let _ = n;
        None
    }

    /// Writes point `index` into `out` (`out.len()` must equal [`dims`](Self::dims)).
    fn point(&self, index: u64, out: &mut [f64]) -> Result<()>;

    /// Points `0..n` of pass 0 as a block, as scipy's `qmc.Sobol(d).random(n)` gives them
    /// (rows with [`Points::to_rows`]). A sampler with fixed passes takes `n` equal to its pass
    /// size (part of a pass is not stratified); an extensible one at most its length.
    ///
    /// ```
    /// use mcint::sampler::{Jittered, Sampler, Scramble, Sobol};
    /// let sobol = Sobol::new(10, Scramble::Owen, 0).unwrap();
    /// let points = sobol.random(1024).unwrap();
    /// assert_eq!((points.len(), points.dims()), (1024, 10));
    /// assert_eq!(points.row(3).unwrap()[0], points.get(3, 0));
    /// let grid = Jittered::new(2, 4, 0).unwrap(); // 16 points per pass
    /// assert!(grid.random(16).is_ok());
    /// assert!(grid.random(10).unwrap_err().to_string().contains("pass size"));
    /// ```
    fn random(&self, n: usize) -> Result<Points> {
        draw::random(self, n)
    }

    /// Points `0..2^m` of pass 0 (scipy's `random_base2`), refused where `2^m` points would
    /// break the sampler's nets (see [`unbalanced_by`](Self::unbalanced_by)).
    ///
    /// ```
    /// use mcint::sampler::{Lattice, Sampler, Scramble, Sobol};
    /// let sobol = Sobol::new(3, Scramble::Owen, 1).unwrap();
    /// assert_eq!(sobol.random_base2(8).unwrap(), sobol.random(256).unwrap());
    /// assert!(sobol.random_base2(64).is_err());
    /// ```
    fn random_base2(&self, m: u32) -> Result<Points> {
        draw::random_base2(self, m)
    }

    /// Points `0..n` of pass 0 mapped to integers (scipy's `integers` with `endpoint=False`):
    /// coordinate `j` becomes `floor(u_j (upper[j] - lower[j]) + lower[j])`, in
    /// `lower[j]..upper[j]`, for lattice-valued designs. The bounds need `lower < upper`, both
    /// within `+-2^53`.
    ///
    /// ```
    /// use mcint::sampler::{Sampler, Scramble, Sobol};
    /// let sobol = Sobol::new(2, Scramble::Owen, 4).unwrap();
    /// let levels = sobol.integers(&[0, -5], &[4, 5], 64).unwrap();
    /// assert!(levels.column(0).iter().all(|&k| (0..4).contains(&k)));
    /// // A net: each of the 4 levels of the first factor gets 64 / 4 points.
    /// assert_eq!(levels.column(0).iter().filter(|&&k| k == 2).count(), 16);
    /// assert!(sobol.integers(&[3, 0], &[3, 1], 8).is_err()); // empty range
    /// ```
    fn integers(&self, lower: &[i64], upper: &[i64], n: usize) -> Result<PointBlock<i64>> {
        draw::integers(self, lower, upper, n)
    }

    /// Reseeds from a random number generator the caller already has (one `u64` drawn from
    /// it), as [`reseed`](Self::reseed) does from a seed.
    ///
    /// ```
    /// use mcint::sampler::{Sampler, Scramble, Sobol};
    /// use rand_core::SeedableRng;
    /// let mut rng = rand_pcg::Pcg64::seed_from_u64(9);
    /// let mut a = Sobol::new(2, Scramble::Owen, 0).unwrap();
    /// a.reseed_from_rng(&mut rng);
    /// let mut again = rand_pcg::Pcg64::seed_from_u64(9);
    /// let mut b = Sobol::new(2, Scramble::Owen, 0).unwrap();
    /// b.reseed_from_rng(&mut again);
    /// assert_eq!(a.random(8).unwrap(), b.random(8).unwrap());
    /// ```
    fn reseed_from_rng(&mut self, rng: &mut dyn rand_core::Rng) {
        self.reseed(rng.next_u64());
    }

    /// Writes points `start .. start + points.len()` into `points` (which must have
    /// [`dims`](Self::dims) columns). The default calls [`point`](Self::point) for each index;
    /// samplers override it with block kernels that give identical bits.
    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        fill_pointwise(self, start, points)
    }

    /// Writes points `start .. start + points.len()` in single precision into `points` (which
    /// must have [`dims`](Self::dims) columns). Every value is
    /// [`to_unit_f32`] of the `f64` coordinate
    /// [`fill`](Self::fill) and [`point`](Self::point) give: the nearest `f32` (ties to even),
    /// except that values that would round to 1.0 become the largest `f32` below one, so every
    /// value is in `[0, 1)`. The default fills `f64` points in steps of 1024 and converts them;
    /// Sobol' converts its integer words straight to `f32`, with the same result.
    ///
    /// ```
    /// use mcint::points_f32::{PointsF32, to_unit_f32};
    /// use mcint::sampler::{Halton, Sampler, Scramble};
    /// let s = Halton::new(2, Scramble::Owen, 5).unwrap();
    /// let mut block = PointsF32::new(2, 10).unwrap();
    /// s.fill_f32(40, &mut block).unwrap();
    /// let mut p = [0.0; 2];
    /// s.point(43, &mut p).unwrap();
    /// assert_eq!(block.get(3, 1), to_unit_f32(p[1]));
    /// ```
    fn fill_f32(&self, start: u64, points: &mut PointsF32) -> Result<()> {
        check_shape(self.dims(), start, points.dims(), points.len())?;
        let mut done = 0;
        let mut buffer = Points::new(self.dims(), F32_STEP.min(points.len()))?;
        while done < points.len() {
            let n = F32_STEP.min(points.len() - done);
            buffer.set_len(n);
            self.fill(start + done as u64, &mut buffer)?;
            for dim in 0..self.dims() {
                let out = &mut points.column_mut(dim)[done..done + n];
                for (y, &x) in out.iter_mut().zip(buffer.column(dim)) {
                    *y = to_unit_f32(x);
                }
            }
            done += n;
        }
        Ok(())
    }
}

/// Points converted per step of the default [`Sampler::fill_f32`].
const F32_STEP: usize = 1024;

/// The default [`Sampler::fill`]: point by point into a buffer, scattered to the columns.
pub(crate) fn fill_pointwise<S: Sampler + ?Sized>(
    sampler: &S,
    start: u64,
    points: &mut Points,
) -> Result<()> {
    check_block(sampler.dims(), start, points)?;
    let mut buffer = vec![0.0; sampler.dims()];
    let len = points.len();
    let mut columns: Vec<&mut [f64]> = points.columns_mut().collect();
    for i in 0..len {
        sampler.point(start + i as u64, &mut buffer)?;
        for (column, &x) in columns.iter_mut().zip(&buffer) {
            column[i] = x;
        }
    }
    Ok(())
}

/// The runs of a block of `len` points from index `start` that share a pass of `size` points,
/// in order: `(done, pass, local, run)` for block positions `done .. done + run`, which are
/// points `local ..` of pass `pass`.
#[inline(always)]
pub(crate) fn pass_runs(
    start: u64,
    len: usize,
    size: u64,
) -> impl Iterator<Item = (usize, u64, u64, usize)> {
    let mut done = 0;
    std::iter::from_fn(move || {
        (done < len).then(|| {
            let index = start + done as u64;
            let (pass, local) = (index / size, index % size);
            let run = (len - done).min(usize::try_from(size - local).unwrap_or(usize::MAX));
            done += run;
            (done - run, pass, local, run)
        })
    })
}

/// Checks that a point buffer has the sampler's dimension.
pub(crate) fn check_point(dims: usize, out: &[f64]) -> Result<()> {
    if out.len() != dims {
        return Err(Error::DimensionMismatch {
            what: "point buffer",
            expected: dims,
            found: out.len(),
        });
    }
    Ok(())
}

/// Checks that a block has the sampler's dimension and that its indices do not overflow.
pub(crate) fn check_block(dims: usize, start: u64, points: &Points) -> Result<()> {
    check_shape(dims, start, points.dims(), points.len())
}

/// Checks a block of `found` columns and `len` points starting at `start`.
pub(crate) fn check_shape(dims: usize, start: u64, found: usize, len: usize) -> Result<()> {
    if found != dims {
        return Err(Error::DimensionMismatch {
            what: "point block",
            expected: dims,
            found,
        });
    }
    // The last index, start + len - 1, must fit (an empty block always does).
    if len > 1 && start.checked_add(len as u64 - 1).is_none() {
        return Err(Error::IndexOutOfRange {
            what: "last sample index of the block",
            limit: u64::MAX,
        });
    }
    Ok(())
}

/// Validates a dimension count given to a constructor.
pub(crate) fn check_dims(dims: usize) -> Result<()> {
    if dims == 0 {
        return Err(Error::invalid("dims", dims, "at least 1"));
    }
    Ok(())
}

/// Validates a dimension count given to a constructor that supports at most `max`.
pub(crate) fn check_supported_dims(dims: usize, max: usize) -> Result<()> {
    if dims == 0 || dims > max {
        return Err(Error::invalid("dims", dims, format!("1 ..= {max}")));
    }
    Ok(())
}

impl<S: Sampler + ?Sized> Sampler for Box<S> {
    fn name(&self) -> &'static str {
        (**self).name()
    }

    fn dims(&self) -> usize {
        (**self).dims()
    }

    fn passes(&self) -> PassKind {
        (**self).passes()
    }

    fn seed(&self) -> u64 {
        (**self).seed()
    }

    fn reseed(&mut self, seed: u64) {
        (**self).reseed(seed)
    }

    fn is_randomized(&self) -> bool {
        (**self).is_randomized()
    }

    fn unbalanced_by(&self, n: u64) -> Option<u64> {
        (**self).unbalanced_by(n)
    }

    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        (**self).point(index, out)
    }

    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        (**self).fill(start, points)
    }

    fn fill_f32(&self, start: u64, points: &mut PointsF32) -> Result<()> {
        (**self).fill_f32(start, points)
    }
}
