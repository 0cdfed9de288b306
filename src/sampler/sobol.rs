//! The Sobol' sequence (Sobol' 1967) with the Joe & Kuo (2008) direction numbers, up to 21201
//! dimensions, unscrambled or randomized per pass by a digital shift, Matoušek's (1998) linear
//! matrix scramble or Owen's (1995) nested uniform scramble, hash-based after Laine & Karras
//! (2011) and Burley (2020), with Burley's optional index shuffle.
//!
//! Coordinate `j` of point `i` is the 32-bit binary fraction `x_j(i) = XOR_k g_k v_{j,k}`, where
//! `g_k` are the bits of the Gray code `g = i ^ (i >> 1)` of the index and `v_{j,k}` are the
//! direction words of dimension `j`. Consecutive Gray codes differ in one bit, bit
//! `ctz(i + 1)`, so a run of points costs one XOR per coordinate (Antonov & Saleev 1979). This
//! is the order of scipy's `scipy.stats.qmc.Sobol`, whose unscrambled points these equal bit
//! for bit (tested against `Sobol(d, scramble=False, bits=32).random(n)`). Dimension 1 is the
//! van der Corput sequence (`v_k = 2^(31 - k)`); dimensions 2 to 21201 come from Joe & Kuo's
//! `new-joe-kuo-6.21201` table (criterion D(6), chosen for good two-dimensional projections;
//! `data/sobol/README.md`), embedded with `include_str!` and parsed on first use, only as far
//! as needed, so that a sampler in a few dimensions does not pay for parsing all 21201.
//!
//! Every aligned block of `2^m` points of a pass (in particular every power-of-two prefix) is a
//! `(t, m, s)`-net in base 2: the first two dimensions form a `(0, m, 2)`-net and every single
//! coordinate a `(0, m, 1)`-net. All three randomizations keep these properties.
//!
//! Randomized coordinates have 53 random digits rather than 32, each randomization acting as it
//! would on a longer expansion whose digits beyond the 32nd are zero:
//!
//! * the digital shift is a random 53-bit word;
//! * the linear matrix scramble is a random 53 x 53 lower-triangular matrix with unit diagonal,
//!   whose rows 33 to 53 make the extra digits random linear functions of the first 32, plus a
//!   53-bit shift. Both are linear, so they fold into 53-bit start and direction words and a
//!   run of points still costs one XOR per coordinate;
//! * under a nested uniform scramble, digits 33 to 53 are a random function of the first 32
//!   input digits, that is of the scrambled 32-bit word: they are hashed from it with a key of
//!   the `(seed, pass, dim)` scramble
//!   ([`OwenScramble::tail_bits`](super::owen::OwenScramble::tail_bits)).
//!
//! A randomized coordinate is therefore exactly uniform on the `2^-53` grid of `[0, 1)`, and
//! below 1 by construction.
//!
//! The fill kernels work column by column over a block, in aligned chunks of 256 indices: the
//! scramble and the conversion of each chunk's Gray-code words run in loops without
//! loop-carried dependencies, with the scramble dispatched once per column. Within a chunk the
//! words are the chunk's first word XOR a per-column table of offsets (made once per column
//! by doubling, as `gray(2^k + j) = gray(2^k) ^ gray(j)` for `j < 2^k`), so only one serial
//! Gray-code step is taken per chunk. The Owen column runs its Gray code on bit-reversed
//! direction words, since the hash works on reversed words, saving one bit reversal per value.
//! All of it is compiled once per instruction set and selected at run time
//! (`crate::simd`), which turns these loops into 8- or 16-lane vector code.
//!
//! Files: `sobol/directions.rs` parses the direction numbers, `sobol/randomizer.rs` holds the
//! three randomizations, `sobol/unit.rs` the conversions of words to `f64` and `f32`, and
//! `sobol/kernel.rs` the Gray-code block kernel; this file the [`Sobol`] sampler.

mod directions;
mod kernel;
mod randomizer;
mod unit;

use super::owen::owen_scramble_u32;
use super::{PassKind, Sampler, Scramble, check_block, check_point, check_shape};
use crate::error::{Error, Result};
use crate::hash::hash_words;
use crate::points::Points;
use crate::points_f32::PointsF32;
use directions::{Directions, MAX_DIMS, table};
use kernel::{direct, gray};
use randomizer::Randomizer;
use std::fmt;

/// log2 of the points per pass.
const PASS_BITS: u32 = 32;

/// Salts separating the pass seed and the index shuffle's seed (the randomizations' own salts
/// are in `sobol/randomizer.rs`).
const PASS_SALT: u64 = 0x736f_626f_6c5f_7073;
const SHUFFLE_SALT: u64 = 0x736f_626f_6c5f_7368;

/// The Sobol' sequence (Sobol' 1967) in up to 21201 dimensions with the Joe & Kuo (2008)
/// direction numbers, optionally randomized per pass.
///
/// Point `i` is generated in Gray-code order, as scipy does: the unscrambled points equal
/// `scipy.stats.qmc.Sobol(d, scramble=False, bits=32).random(n)` bit for bit, starting with the
/// origin at index 0. Unscrambled coordinates are 32-bit fractions, `word * 2^-32` exactly.
///
/// Passes hold `2^32` points: index `p * 2^32 + i` is point `i` of pass `p`, and any prefix of
/// a pass is a valid point set, best at powers of two, where the first two coordinates form a
/// `(0, m, 2)`-net and every coordinate a `(0, m, 1)`-net. Each pass is randomized
/// independently with constants hashed from `(seed, pass, dim)`:
///
/// * [`Scramble::None`]: no randomization; every pass repeats the same deterministic sequence,
///   and [`is_randomized`](Sampler::is_randomized) is false.
/// * [`Scramble::Xor`]: a random digital shift per dimension.
/// * [`Scramble::Lms`]: Matoušek's (1998) linear matrix scramble (a random lower-triangular
///   binary matrix with unit diagonal) plus a digital shift, what scipy calls `scramble=True`.
/// * [`Scramble::Owen`]: Owen's (1995) nested uniform scramble, hash-based (Laine & Karras
///   2011; Burley 2020); for smooth integrands its variance falls as `O(N^-3 (log N)^(d-1))`.
///   [`with_index_shuffle`](Self::with_index_shuffle) adds Burley's index scramble.
///
/// Each randomization keeps the net properties and makes every point uniform on `[0, 1)^d`, at
/// double resolution: after the 32 scrambled digits come 21 more, randomized as the same
/// scramble would randomize a longer expansion (a 53-bit shift, a 53 x 53 matrix, or digits
/// hashed from the scrambled word for Owen), so randomized coordinates are exact multiples of
/// `2^-53`, below 1.
///
/// ```
/// use mcint::sampler::{Sampler, Scramble, Sobol};
/// let s = Sobol::new(2, Scramble::None, 0).unwrap();
/// let mut p = [0.0; 2];
/// s.point(1, &mut p).unwrap();
/// assert_eq!(p, [0.5, 0.5]);
/// s.point(2, &mut p).unwrap();
/// assert_eq!(p, [0.75, 0.25]);
/// // Randomized: every pass is an independent scramble of the same net.
/// let owen = Sobol::new(2, Scramble::Owen, 42).unwrap();
/// let mut block = mcint::Points::new(2, 4).unwrap();
/// owen.fill(1 << 32, &mut block).unwrap(); // the first 4 points of pass 1
/// let mut rows: Vec<usize> = (0..4).map(|i| (block.get(i, 1) * 4.0) as usize).collect();
/// rows.sort();
/// assert_eq!(rows, [0, 1, 2, 3]);
/// ```
#[derive(Clone)]
pub struct Sobol {
    dims: usize,
    scramble: Scramble,
    seed: u64,
    shuffle: bool,
    /// Direction words of dimensions `0..dims`.
    directions: &'static [Directions],
}

impl Sobol {
    /// The scrambles this generator accepts.
    const SCRAMBLES: [Scramble; 4] = [Scramble::None, Scramble::Xor, Scramble::Lms, Scramble::Owen];

    /// Sobol' points in `dims` dimensions (1 to 21201) with the given randomization (`None`,
    /// `Xor`, `Lms` or `Owen`) selected by `seed`.
    ///
    /// ```
    /// use mcint::sampler::{Sampler, Scramble, Sobol};
    /// let s = Sobol::new(3, Scramble::Owen, 7).unwrap();
    /// assert_eq!(s.dims(), 3);
    /// assert!(Sobol::new(21202, Scramble::None, 0).is_err());
    /// assert!(Sobol::new(3, Scramble::Shift, 0).is_err());
    /// ```
    pub fn new(dims: usize, scramble: Scramble, seed: u64) -> Result<Self> {
        if !(1..=MAX_DIMS).contains(&dims) {
            return Err(Error::invalid(
                "dims",
                dims,
                format!("1 to {MAX_DIMS} (the dimensions of the Joe-Kuo table) for sobol"),
            ));
        }
        scramble.check("sobol", &Self::SCRAMBLES)?;
        let directions = &table(dims)?[..dims];
        Ok(Sobol {
            dims,
            scramble,
            seed,
            shuffle: false,
            directions,
        })
    }

    /// Turns Burley's (2020) index shuffling on or off (off by default). Before a point is
    /// generated, its in-pass index is Owen-scrambled as a 32-bit integer (nested from the top
    /// bit) with a per-pass seed, so the first `2^m` points of a pass are a randomly chosen
    /// aligned block of `2^m` Sobol' points in a random order: still a net, but no longer in
    /// the same order for every seed. Without it, the same dimension of two differently seeded
    /// samplers holds nested scrambles of the same point at each index, which is strongly
    /// dependent when their points are combined index by index (as when padding dimensions
    /// from separate samplers); with it they are unrelated. Only meaningful with
    /// [`Scramble::Owen`]; with any other scramble it has no effect.
    ///
    /// ```
    /// use mcint::sampler::{Sampler, Scramble, Sobol};
    /// let s = Sobol::new(2, Scramble::Owen, 1).unwrap().with_index_shuffle(true);
    /// let mut p = [0.0; 2];
    /// s.point(0, &mut p).unwrap();
    /// assert!(p.iter().all(|&x| (0.0..1.0).contains(&x)));
    /// ```
    pub fn with_index_shuffle(mut self, on: bool) -> Self {
        self.shuffle = on;
        self
    }

    /// The randomization applied to each pass.
    ///
    /// ```
    /// use mcint::sampler::{Scramble, Sobol};
    /// assert_eq!(Sobol::new(1, Scramble::Lms, 0).unwrap().scramble(), Scramble::Lms);
    /// ```
    pub fn scramble(&self) -> Scramble {
        self.scramble
    }

    /// Whether the index is shuffled (set, and the scramble is Owen).
    fn shuffles(&self) -> bool {
        self.shuffle && self.scramble == Scramble::Owen
    }

    /// The seed of pass `pass`, from which every constant of that pass is hashed.
    fn pass_seed(&self, pass: u64) -> u64 {
        hash_words(self.seed, &[pass, PASS_SALT])
    }

    /// Seed of the index shuffle of a pass.
    fn shuffle_seed(pass_seed: u64) -> u32 {
        (hash_words(pass_seed, &[SHUFFLE_SALT]) >> 32) as u32
    }

    /// The randomization of dimension `dim` in the pass with seed `pass_seed`.
    fn randomizer(&self, pass_seed: u64, dim: usize) -> Randomizer {
        Randomizer::new(self.scramble, pass_seed, dim)
    }
}

impl fmt::Debug for Sobol {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Sobol")
            .field("dims", &self.dims)
            .field("scramble", &self.scramble)
            .field("seed", &self.seed)
            .field("index_shuffle", &self.shuffle)
            .finish_non_exhaustive()
    }
}

impl PartialEq for Sobol {
    fn eq(&self, other: &Self) -> bool {
        // The direction words are a function of the dimension.
        (self.dims, self.scramble, self.seed, self.shuffle)
            == (other.dims, other.scramble, other.seed, other.shuffle)
    }
}

impl Eq for Sobol {}

impl Sampler for Sobol {
    fn dims(&self) -> usize {
        self.dims
    }

    fn seed(&self) -> u64 {
        self.seed
    }

    fn reseed(&mut self, seed: u64) {
        self.seed = seed;
    }

    fn unbalanced_by(&self, n: u64) -> Option<u64> {
        (!n.is_power_of_two()).then_some(2)
    }

    fn name(&self) -> &'static str {
        "sobol"
    }

    fn passes(&self) -> PassKind {
        PassKind::Extensible {
            max: 1 << PASS_BITS,
        }
    }

    fn is_randomized(&self) -> bool {
        self.scramble != Scramble::None
    }

    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        check_point(self.dims, out)?;
        let pass = index >> PASS_BITS;
        let i = index as u32;
        let pass_seed = self.pass_seed(pass);
        let position = if self.shuffles() {
            owen_scramble_u32(i, Self::shuffle_seed(pass_seed))
        } else {
            i
        };
        let g = gray(position);
        for (dim, (x, directions)) in out.iter_mut().zip(self.directions).enumerate() {
            let word = direct(directions, g);
            *x = self.randomizer(pass_seed, dim).finish(word);
        }
        Ok(())
    }

    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        check_block(self.dims, start, points)?;
        self.fill_block(start, points);
        Ok(())
    }

    /// Converts the 32-bit words (unscrambled) or 53-bit fractions (randomized) straight to
    /// `f32`: one rounding of the exact value, which is what converting the exact `f64`
    /// coordinate gives, so the values equal the default's.
    fn fill_f32(&self, start: u64, points: &mut PointsF32) -> Result<()> {
        check_shape(self.dims, start, points.dims(), points.len())?;
        self.fill_block(start, points);
        Ok(())
    }
}
