//! Hammersley point sets (Hammersley 1960): a Halton sequence (Halton 1960) with `i / N` as
//! first coordinate.
//!
//! The Halton coordinates come from the radical-inverse engine in `radical_inverse.rs`, with the
//! same randomizations as Halton's: random digit permutations (Braaten & Weller 1979; Faure &
//! Tezuka 2002) and nested uniform scrambling (Owen 1995). The first coordinate gets a
//! Cranley-Patterson rotation (Cranley & Patterson 1976). The public [`Hammersley`] documents
//! the choices.

use super::radical_inverse::{
    PASS_SIZE, SCRAMBLES, Scratch, bases, check_halton_dims, column_key, coordinate, fill_column,
};
use super::{PassKind, Sampler, Scramble, check_block, check_point, pass_runs};
use crate::error::{Error, Result};
use crate::float::ONE_BELOW;
use crate::hash::{hash_words, mix64, unit_f64};
use crate::points::Points;

/// Hash tag of the Hammersley randomizations.
const TAG_HAMMERSLEY: u64 = 0x6861_6d6d;
/// Hash tag of the rotation of the first coordinate.
const TAG_ROTATION: u64 = 0x726f_7461;

/// `N` points per pass: `(i / N, phi_2(i), phi_3(i), ...)`, optionally randomized.
///
/// Point `i` of a set of `N` points is `(i / N, phi_2(i), phi_3(i), phi_5(i), ...)`, where
/// `phi_b` is the radical inverse in base `b` (Halton 1960; see [`Halton`](super::Halton)).
/// Knowing `N` in advance buys the first coordinate: the star discrepancy drops from
/// `O(log^d N / N)` for the Halton sequence to `O(log^(d-1) N / N)`, but the set is not
/// extensible, so a pass is exactly `N` points ([`PassKind::Fixed`](super::PassKind::Fixed)).
/// In two dimensions with `N = 2^m` it is a `(0, m, 2)`-net in base 2: every box
/// `[a / 2^j, (a + 1) / 2^j) x [c / 2^(m-j), (c + 1) / 2^(m-j))` holds exactly one point.
///
/// # Randomization
///
/// Index `p * N + i` is point `i` of pass `p`. The Halton coordinates take the same random digit
/// permutations ([`Scramble::Permute`]: Braaten & Weller 1979, Faure & Tezuka 2002) or nested
/// uniform scrambles ([`Scramble::Owen`], Owen 1995) as [`Halton`](super::Halton), drawn afresh
/// for each pass. The first coordinate gets a Cranley-Patterson rotation (Cranley & Patterson
/// 1976): `x_0 = (i / N + U) mod 1` with one uniform `U` per pass. We draw `U = (c + u) / N`
/// with `c` uniform in `0..N` and `u` uniform in `[0, 1)`, and compute
/// `x_0 = (((i + c) mod N) + u) / N`, so the equal spacing `1 / N` is kept exactly and every
/// point of a pass stays in its own slab `[s / N, (s + 1) / N)`, `s = (i + c) mod N`.
///
/// Why a rotation rather than jittering each `i / N` within its slab or scrambling its digits:
/// the rotation makes every point, not just the set, uniformly distributed in `[0, 1)^d` (a
/// jitter `(i + u) / N` would leave point `i` in slab `i` in every pass), and it keeps the net
/// structure: the points whose first coordinate falls in `b^(m-j)` consecutive slabs are
/// `b^(m-j)` consecutive indices modulo `N = b^m`, whose lowest `m - j` digits take every value
/// once, so the first `m - j` digits of their (scrambled) radical inverses do too. A pass's
/// mean is unbiased because each point is uniform; the tests check this and the net property.
///
/// With [`Scramble::None`] every pass repeats the same points.
///
/// ```
/// use mcint::sampler::{Hammersley, PassKind, Sampler, Scramble};
/// let s = Hammersley::new(2, 8, Scramble::None, 0).unwrap();
/// assert_eq!(s.passes(), PassKind::Fixed { size: 8 });
/// let mut p = [0.0; 2];
/// s.point(3, &mut p).unwrap();
/// assert_eq!(p, [3.0 / 8.0, 0.75]);
/// s.point(8 + 3, &mut p).unwrap(); // point 3 of the second pass: the same without scrambling
/// assert_eq!(p, [3.0 / 8.0, 0.75]);
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Hammersley {
    dims: usize,
    pass_size: u64,
    scramble: Scramble,
    seed: u64,
}

impl Hammersley {
    /// The most dimensions: the first coordinate plus 9,999 prime bases.
    ///
    /// ```
    /// use mcint::sampler::{Hammersley, Scramble};
    /// assert!(Hammersley::new(Hammersley::MAX_DIMS, 16, Scramble::None, 0).is_ok());
    /// assert!(Hammersley::new(Hammersley::MAX_DIMS + 1, 16, Scramble::None, 0).is_err());
    /// ```
    pub const MAX_DIMS: usize = super::radical_inverse::MAX_DIMS;

    /// The most points per pass, `2^40`, as for a pass of [`Halton`](super::Halton).
    ///
    /// ```
    /// use mcint::sampler::{Hammersley, Scramble};
    /// assert!(Hammersley::new(2, Hammersley::MAX_POINTS, Scramble::Owen, 0).is_ok());
    /// assert!(Hammersley::new(2, Hammersley::MAX_POINTS + 1, Scramble::Owen, 0).is_err());
    /// ```
    pub const MAX_POINTS: u64 = PASS_SIZE;

    /// `points` (1 to [`MAX_POINTS`](Self::MAX_POINTS)) per pass in `dims` dimensions (1 to
    /// [`MAX_DIMS`](Self::MAX_DIMS)), randomized by [`Scramble::None`], [`Scramble::Permute`]
    /// or [`Scramble::Owen`].
    ///
    /// ```
    /// use mcint::sampler::{Hammersley, Scramble};
    /// assert!(Hammersley::new(3, 1024, Scramble::Permute, 5).is_ok());
    /// assert!(Hammersley::new(3, 0, Scramble::Permute, 5).unwrap_err().to_string().contains("points"));
    /// assert!(Hammersley::new(3, 8, Scramble::Shift, 5).is_err());
    /// ```
    pub fn new(dims: usize, points: u64, scramble: Scramble, seed: u64) -> Result<Self> {
        check_halton_dims(dims)?;
        if points == 0 || points > PASS_SIZE {
            return Err(Error::invalid(
                "points",
                points,
                format!("1 to 2^40 = {PASS_SIZE} points per pass"),
            ));
        }
        scramble.check("hammersley", &SCRAMBLES)?;
        Ok(Hammersley {
            dims,
            pass_size: points,
            scramble,
            seed,
        })
    }

    /// The randomization applied to each pass.
    ///
    /// ```
    /// use mcint::sampler::{Hammersley, Scramble};
    /// let s = Hammersley::new(2, 64, Scramble::Owen, 0).unwrap();
    /// assert_eq!(s.scramble(), Scramble::Owen);
    /// ```
    pub fn scramble(&self) -> Scramble {
        self.scramble
    }

    /// The first coordinate of point `local` of `pass`.
    #[inline]
    fn first(&self, rotation: Option<(u64, f64)>, local: u64) -> f64 {
        let n = self.pass_size;
        match rotation {
            None => local as f64 / n as f64,
            Some((shift, jitter)) => {
                // local, shift < n <= 2^40: no overflow, and the slab index is exact.
                let slab = (local + shift) % n;
                ((slab as f64 + jitter) / n as f64).min(ONE_BELOW)
            }
        }
    }

    /// The rotation of the first coordinate in `pass`: a slab shift and a jitter within it.
    fn rotation(&self, pass: u64) -> Option<(u64, f64)> {
        if self.scramble == Scramble::None {
            return None;
        }
        let h = hash_words(self.seed, &[TAG_ROTATION, pass]);
        let shift = ((u128::from(h) * u128::from(self.pass_size)) >> 64) as u64;
        Some((shift, unit_f64(mix64(h ^ TAG_ROTATION))))
    }
}

impl Sampler for Hammersley {
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

    /// Each pass is one Hammersley set, a net when its size is a power of two.
    fn unbalanced_by(&self, _n: u64) -> Option<u64> {
        (!self.pass_size.is_power_of_two()).then_some(2)
    }

    fn name(&self) -> &'static str {
        "hammersley"
    }

    fn is_randomized(&self) -> bool {
        self.scramble != Scramble::None
    }

    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        check_point(self.dims, out)?;
        let (pass, local) = (index / self.pass_size, index % self.pass_size);
        let Some((first, rest)) = out.split_first_mut() else {
            return Ok(());
        };
        *first = self.first(self.rotation(pass), local);
        for ((dim, x), base) in rest.iter_mut().enumerate().zip(bases()) {
            let key = column_key(self.seed, TAG_HAMMERSLEY, pass, dim);
            *x = coordinate(self.scramble, base, key, local);
        }
        Ok(())
    }

    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        check_block(self.dims, start, points)?;
        let n = self.pass_size;
        let mut scratch = Scratch::default();
        for dim in 0..self.dims {
            let column = points.column_mut(dim);
            for (offset, pass, local, run) in pass_runs(start, column.len(), n) {
                let out = &mut column[offset..offset + run];
                if dim == 0 {
                    let rotation = self.rotation(pass);
                    for (x, i) in out.iter_mut().zip(local..) {
                        *x = self.first(rotation, i);
                    }
                } else {
                    let key = column_key(self.seed, TAG_HAMMERSLEY, pass, dim - 1);
                    let base = &bases()[dim - 1];
                    fill_column(self.scramble, base, key, local, out, &mut scratch);
                }
            }
        }
        Ok(())
    }
}
