//! Halton sequences (Halton 1960) and their randomizations by digit permutations.
//!
//! Coordinate `j` of point `i` is the radical inverse of `i` in the `j`-th prime base
//! (van der Corput 1935 for one base, Halton 1960 for one prime per coordinate), computed by
//! the engine in `radical_inverse.rs`, which Hammersley (1960) point sets share. Two
//! randomizations keep each coordinate's stratification and make every point uniform: random
//! digit permutations (Braaten & Weller 1979 with fixed permutations; random ones as in Owen
//! 2017 and scipy, and as analysed by Faure & Tezuka 2002 and Matoušek 1998) and nested uniform
//! scrambling in base `b` (Owen 1995). The public [`Halton`] documents the index convention, the
//! precision (correctly rounded radical inverses), how the infinite tail of zero digits is
//! handled, and the passes.

use super::radical_inverse::{
    MAX_DIMS, PASS_BITS, PASS_SIZE, SCRAMBLES, Scratch, bases, check_halton_dims, column_key,
    coordinate, fill_column,
};
use super::{PassKind, Sampler, Scramble, check_block, check_point, pass_runs};
use crate::error::Result;
use crate::points::Points;

/// Hash tags that keep the random streams of different purposes apart.
const TAG_HALTON: u64 = 0x6861_6c74;

/// The Halton sequence in up to 10,000 dimensions, optionally randomized.
///
/// Coordinate `j` of point `i` is the radical inverse of `i` in the `j`-th prime base
/// `b = 2, 3, 5, 7, ...`: write `i = a_1 + a_2 b + a_3 b^2 + ...` and mirror the digits about
/// the radix point, `phi_b(i) = a_1 / b + a_2 / b^2 + a_3 / b^3 + ...` (van der Corput 1935
/// for one base; Halton 1960 for one prime base per coordinate). Each coordinate on its own is a
/// `(0,1)`-sequence in base `b`: the points `i = m b^k .. (m + 1) b^k - 1` put exactly one
/// point in each interval `[a / b^k, (a + 1) / b^k)`. Hammersley (1960) replaced the first
/// coordinate by `i / N` for a point set of fixed size `N` (see
/// [`Hammersley`](super::Hammersley), which shares this sampler's machinery).
///
/// # Index convention and precision
///
/// Point `i` is the radical inverse of `i` itself, so point 0 is the origin: this is scipy's
/// convention (`scipy.stats.qmc.Halton(d, scramble=False).random(n)` returns points
/// `0 .. n - 1`). Unscrambled coordinates are the correctly rounded value of the exact rational
/// `phi_b(i)`: the digit-reversed integer numerator is divided once by `b^k` (exact in `f64`
/// when `b^k <= 2^53`, otherwise by an integer long division with round-half-to-even). scipy
/// sums `a_k * b^-k` term by term in floating point and so differs from the exact value by up
/// to two units in the last place (by one in about a third of the coordinates of its first
/// 1000 points in 100 dimensions, by two in 0.2%); the tests check both facts.
///
/// # Randomizations
///
/// * [`Scramble::Permute`]: random digit permutations. Digit `k` of every coordinate in base
///   `b` is replaced by `pi_k(a_k)`, where the permutations `pi_1, pi_2, ...` of `{0, .., b-1}`
///   are independent and uniformly random, one set per dimension and per pass. Braaten &
///   Weller (1979) introduced digit permutations for the Halton sequence with fixed
///   hand-picked permutations; random ones are Owen's (2017, "A randomized Halton algorithm in
///   R") and what `scipy.stats.qmc.Halton(d, scramble=True)` does, and Faure & Tezuka (2002)
///   and Matoušek (1998) analyse such random digit scrambles. The point distribution is
///   scipy's, up to the near-uniformity of hashed permutations noted below (the values are
///   not: the random numbers differ).
/// * [`Scramble::Owen`]: nested scrambling in base `b` (Owen 1995): the permutation applied to
///   digit `k` is chosen afresh for every value of the higher digits of the output, that is,
///   for every prefix `(a_1, .., a_{k-1})`, by hashing the prefix with the pass and the
///   dimension (hash-based, like pbrt-v4's Owen-scrambled radical inverse). In bases up to 13
///   each node's permutation is uniformly random, as in Owen's nested uniform scramble; in
///   larger bases it is a uniformly random affine map `a -> (alpha a + t) mod b` (`alpha` in
///   `1..b`, `t` in `0..b`). The affine maps of a prime base are sharply 2-transitive: two
///   distinct digits go to a uniformly random pair of distinct digits, exactly as under a
///   uniform permutation, so every pair of scrambled points has the joint law it has under
///   the nested uniform scramble, and the variance of an estimate, which depends on the
///   points two at a time only, is the same (Owen 2003, "Variance with alternative
///   scramblings of digital nets", makes the same argument for other cheap scrambles).
///
/// Both keep each coordinate a `(0,1)`-sequence: a digit-wise bijection maps every interval
/// `[a / b^k, (a + 1) / b^k)` onto another one, so the stratification survives, while every
/// point becomes uniformly distributed in `[0, 1)^d`.
///
/// **The digit tail.** Beyond its last non-zero digit an index has infinitely many zero digits,
/// and a random permutation does not map 0 to 0, so every one of them contributes. We do not use
/// permutations that fix 0 (that would leave small indices unrandomized, point 0 would stay at
/// the origin). Instead every digit position `k = 1 .. K` is permuted, zeros included, where
/// `K` is the least integer with `b^K >= 2^53`: the remaining tail adds less than
/// `b^-K <= 2^-53`, below the resolution of an `f64` near 1, and is dropped (scipy does the
/// same with its `ceil(54 / log2(b)) - 1` permuted digits; pbrt-v4 likewise). Each randomized
/// coordinate is then exactly uniform on the grid `{m / b^K}`, rounded to the nearest `f64`
/// and capped at the largest `f64` below one.
///
/// **Permutations.** A uniformly random permutation `pi` of `{0, .., b-1}` is drawn as
/// `pi(0) = t` with `t` uniform, and `pi(a) = (t + 1 + rho(a - 1)) mod b` for `a >= 1` with
/// `rho` a uniformly random permutation of `{0, .., b-2}` independent of `t` (every permutation
/// arises from exactly one pair `(t, rho)`). The zero digits, the bulk of the tail, need only
/// `t`, and the `t` of successive digit positions are read as successive digits of a random
/// base-`b` digit stream, `m` digits per 64-bit hash with `b^m <= 2^32` (32 per hash in base
/// 2; each `m`-tuple is uniform within a relative `2^-32`). With `Owen` the stream belongs to
/// the node's prefix: every node `(k, prefix)` has `prefix < b^k`, so the tail of an index
/// reads the stream of the index itself. `rho`, needed for non-zero digits only, is decoded
/// from one hash by Fisher-Yates in mixed radix for `b <= 13` (each of the `(b-1)!`
/// permutations has probability within `(b-1)! / 2^64 < 3e-11` relative of uniform) and is
/// the crate's hashed random-access permutation (swap-or-not shuffle or Feistel network) for
/// larger bases with `Permute`; an `Owen` node in a larger base reads the slope `alpha` of its
/// affine map from one hash, so that `rho(a - 1) = (alpha a mod b) - 1`.
///
/// **Cost.** [`fill`](Sampler::fill) shares work between the indices of a block, so use it for
/// throughput; [`point`](Sampler::point) recomputes everything per call. Unscrambled blocks
/// run an odometer over the digits, with no division. `Permute` blocks find the images of the
/// digits each position meets once per block, sixteen at a time, and round each value by one
/// multiplication (in thousands of dimensions, bases above the block length give every index
/// a lowest digit of its own to permute, which costs more). `Owen` blocks keep the nodes of a
/// pass in tables of the filling thread (the nodes of every digit position with at most 2^16
/// prefixes and the digit images of those with at most 2^16 residues; up to 8 MiB per thread,
/// past which further columns get tables of their block only; the crate's runners release
/// them on every thread when a run ends), so each node is computed once per pass whatever the
/// block size; what remains per value is the tail of digits below the index's own (two
/// hashes) and one correct rounding. That is still many times what Owen-scrambled Sobol'
/// costs per value: `cargo bench --bench samplers -- owen_halton_vs_sobol` compares them,
/// and `docs/measurements.md` keeps the figures.
///
/// # Passes
///
/// An index is `p * 2^40 + i`: point `i` of pass `p`. Within a pass the points are the
/// sequence's points `0 .. 2^40 - 1`; each pass of a randomized sequence has its own
/// randomization, seeded by a hash of `(seed, pass, dimension)`, so passes are independent
/// replicates. `2^40` (about `1.1e12`) points per pass is more than any run uses and leaves
/// `2^24` passes in the 64-bit index space; it also keeps every radical inverse exact: with
/// `i < 2^40` and bases below `2^17`, the numerator and denominator `b^k < 2^57` fit in 64 bits.
/// (A pass of `2^53` points, where base-2 radical inverses run out of `f64` precision, would
/// leave no room for passes: `p * 2^53 + i` overflows `u64` for `p >= 2048`.)
///
/// ```
/// use mcint::sampler::{Halton, Sampler, Scramble};
/// let halton = Halton::new(3, Scramble::None, 0).unwrap();
/// let mut p = [0.0; 3];
/// halton.point(5, &mut p).unwrap();
/// // 5 is 101 in base 2, 12 in base 3 and 10 in base 5.
/// assert_eq!(p, [5.0 / 8.0, 7.0 / 9.0, 1.0 / 25.0]);
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Halton {
    dims: usize,
    scramble: Scramble,
    seed: u64,
}

impl Halton {
    /// The most dimensions: the bases are the first 10,000 primes (2 to 104,729).
    ///
    /// ```
    /// use mcint::sampler::{Halton, Scramble};
    /// assert!(Halton::new(Halton::MAX_DIMS, Scramble::Owen, 1).is_ok());
    /// assert!(Halton::new(Halton::MAX_DIMS + 1, Scramble::Owen, 1).is_err());
    /// ```
    pub const MAX_DIMS: usize = MAX_DIMS;

    /// Points per pass, `2^40`: index `p * 2^40 + i` is point `i` of pass `p`.
    ///
    /// ```
    /// use mcint::sampler::{Halton, PassKind, Sampler, Scramble};
    /// let halton = Halton::new(2, Scramble::Permute, 7).unwrap();
    /// assert_eq!(halton.passes(), PassKind::Extensible { max: Halton::PASS_SIZE });
    /// assert_eq!(Halton::PASS_SIZE, 1 << 40);
    /// ```
    pub const PASS_SIZE: u64 = PASS_SIZE;

    /// A Halton sequence in `dims` dimensions (1 to [`MAX_DIMS`](Self::MAX_DIMS)) with
    /// randomization [`Scramble::None`], [`Scramble::Permute`] or [`Scramble::Owen`].
    ///
    /// ```
    /// use mcint::sampler::{Halton, Scramble};
    /// assert!(Halton::new(2, Scramble::Owen, 42).is_ok());
    /// assert!(Halton::new(0, Scramble::None, 0).is_err());
    /// let err = Halton::new(2, Scramble::Xor, 0).unwrap_err();
    /// assert!(err.to_string().contains("none, permute, owen"));
    /// ```
    pub fn new(dims: usize, scramble: Scramble, seed: u64) -> Result<Self> {
        check_halton_dims(dims)?;
        scramble.check("halton", &SCRAMBLES)?;
        Ok(Halton {
            dims,
            scramble,
            seed,
        })
    }

    /// The randomization applied to each pass.
    ///
    /// ```
    /// use mcint::sampler::{Halton, Scramble};
    /// assert_eq!(Halton::new(1, Scramble::Permute, 0).unwrap().scramble(), Scramble::Permute);
    /// ```
    pub fn scramble(&self) -> Scramble {
        self.scramble
    }
}

impl Sampler for Halton {
    fn dims(&self) -> usize {
        self.dims
    }

    fn seed(&self) -> u64 {
        self.seed
    }

    fn reseed(&mut self, seed: u64) {
        self.seed = seed;
    }

    fn name(&self) -> &'static str {
        "halton"
    }

    fn passes(&self) -> PassKind {
        PassKind::Extensible { max: PASS_SIZE }
    }

    fn is_randomized(&self) -> bool {
        self.scramble != Scramble::None
    }

    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        check_point(self.dims, out)?;
        let (pass, local) = (index >> PASS_BITS, index & (PASS_SIZE - 1));
        for ((dim, x), base) in out.iter_mut().enumerate().zip(bases()) {
            let key = column_key(self.seed, TAG_HALTON, pass, dim);
            *x = coordinate(self.scramble, base, key, local);
        }
        Ok(())
    }

    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        check_block(self.dims, start, points)?;
        let mut scratch = Scratch::default();
        for (dim, base) in bases().iter().enumerate().take(self.dims) {
            let column = points.column_mut(dim);
            for (offset, pass, local, run) in pass_runs(start, column.len(), PASS_SIZE) {
                let key = column_key(self.seed, TAG_HALTON, pass, dim);
                let out = &mut column[offset..offset + run];
                fill_column(self.scramble, base, key, local, out, &mut scratch);
            }
        }
        Ok(())
    }
}
