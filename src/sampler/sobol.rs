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
//! as needed: the first 64 dimensions (30 µs), 1024 (0.5 ms) or all 21201 (12 ms; release build,
//! 2 GHz Xeon).
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
//!   the `(seed, pass, dim)` scramble ([`OwenScramble::tail_bits`]).
//!
//! A randomized coordinate is therefore exactly uniform on the `2^-53` grid of `[0, 1)`, and
//! below 1 by construction.
//!
//! The fill kernels work column by column over a block: for each dimension, the Gray-code
//! words of a chunk, then the scramble and the conversion in loops without loop-carried
//! dependencies, with the scramble dispatched once per column. Within an aligned group of 16
//! indices the words are the group's first word XOR a per-column table, so only one serial
//! Gray-code step is taken per group. The Owen column runs its Gray code on bit-reversed
//! direction words, since the hash works on reversed words, saving one bit reversal per value.
//! All of it is compiled once per instruction set and selected at run time
//! (`super::simd`), which turns these loops into 8- or 16-lane vector code.

use super::owen::{OwenScramble, dimension_seed, owen_scramble_u32};
use super::simd::{Kernel, dispatch};
use super::{PassKind, Sampler, Scramble, check_block, check_point, check_shape};
use crate::hash::{hash_words, mix64};
use crate::points_f32::{F32_BELOW_ONE, PointsF32};
use crate::{Error, Points, Result};
use std::fmt;
use std::ops::BitXorAssign;
use std::sync::OnceLock;

/// The Joe-Kuo table, one line per dimension 2..=21201 after a header line.
const JOE_KUO: &str = include_str!("../../data/sobol/new-joe-kuo-6.21201.txt");

/// Dimensions available: van der Corput plus the 21200 dimensions of the table.
const MAX_DIMS: usize = 21201;

/// Direction words of one dimension; bit `31 - k` is the leading bit of word `k`.
type Directions = [u32; 32];

/// Points per pass.
const PASS_BITS: u32 = 32;

/// Block length for the word buffers of the fill kernels (a power of two).
const CHUNK_BITS: u32 = 8;
const CHUNK: usize = 1 << CHUNK_BITS;
/// Below this many points of one aligned chunk, the shuffled kernel computes words directly
/// instead of generating the whole chunk by Gray code.
const SHUFFLE_DIRECT_BELOW: usize = 32;
/// Indices per aligned Gray-code group (a power of two dividing `CHUNK`): within an aligned
/// group the words are the group's first word XOR a per-column table, with no serial chain.
const GROUP: usize = 16;

/// Salts separating the hashes drawn from one pass seed.
const PASS_SALT: u64 = 0x736f_626f_6c5f_7073;
const XOR_SALT: u64 = 0x736f_626f_6c5f_786f;
const LMS_SALT: u64 = 0x736f_626f_6c5f_6c6d;
const SHUFFLE_SALT: u64 = 0x736f_626f_6c5f_7368;

/// Weyl increment (2^64 / golden ratio) for drawing several words from one hash.
const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;

/// Digits of a randomized coordinate (the precision of an `f64` in `[0, 1)`), and how many of
/// them lie below the sequence's 32.
const FULL_BITS: u32 = 53;
const EXTRA_BITS: u32 = FULL_BITS - 32;

/// Direction words of one dimension widened to 53 bits (the 32-bit word in bits 21..53), for
/// the digital shift and the linear matrix scramble.
type WideDirections = [u64; 32];

/// Table sizes parsed on demand: a sampler of `d` dimensions uses the smallest that covers `d`,
/// so low-dimensional use never parses the whole file.
const TIERS: [usize; 3] = [64, 1024, MAX_DIMS];

/// A parsed table, or why it could not be parsed (which the tests rule out).
type Parsed = std::result::Result<Vec<Directions>, String>;

/// The parsed tiers.
static TABLES: [OnceLock<Parsed>; 3] = [OnceLock::new(), OnceLock::new(), OnceLock::new()];

/// Direction words of (at least) the first `dims` dimensions, parsed once per tier.
fn table(dims: usize) -> Result<&'static [Directions]> {
    let tier = TIERS
        .iter()
        .position(|&t| dims <= t)
        .unwrap_or(TIERS.len() - 1);
    match TABLES[tier].get_or_init(|| parse_joe_kuo(JOE_KUO, TIERS[tier])) {
        Ok(table) if table.len() >= dims => Ok(table),
        Ok(_) => Err(Error::invalid("dims", dims, format!("1 to {MAX_DIMS}"))),
        Err(message) => Err(Error::invalid(
            "sobol direction table",
            "the embedded Joe-Kuo file",
            format!("a well-formed table ({message})"),
        )),
    }
}

/// Parses the unsigned decimal numbers of one line (`None` on any other character, or on a
/// number above `u32::MAX`).
fn numbers(line: &[u8], out: &mut Vec<u32>) -> Option<()> {
    out.clear();
    let mut value = 0u64;
    let mut digits = 0u32;
    for &byte in line {
        if byte.is_ascii_digit() {
            value = value * 10 + u64::from(byte - b'0');
            digits += 1;
            if digits > 10 {
                return None;
            }
        } else if matches!(byte, b' ' | b'\t' | b'\r') {
            if digits > 0 {
                out.push(u32::try_from(value).ok()?);
            }
            value = 0;
            digits = 0;
        } else {
            return None;
        }
    }
    if digits > 0 {
        out.push(u32::try_from(value).ok()?);
    }
    Some(())
}

/// Parses the first `dims` dimensions of Joe & Kuo's format (`d s a m_1 .. m_s` per line after
/// a header) into 32 direction words each, with dimension 1 (van der Corput) first.
///
/// The initial values `m_1..m_s` (odd, `m_k < 2^k`) are extended by the recurrence of the
/// primitive polynomial `x^s + a_1 x^(s-1) + ... + a_(s-1) x + 1` (Bratley & Fox 1988):
/// `m_k = 2 a_1 m_(k-1) ^ 4 a_2 m_(k-2) ^ ... ^ 2^(s-1) a_(s-1) m_(k-s+1) ^ 2^s m_(k-s) ^
/// m_(k-s)`. In terms of the words `v_k = m_k 2^(32-k)` this reads
/// `v_k = v_(k-s) ^ (v_(k-s) >> s) ^ XOR_i a_i v_(k-i)`.
fn parse_joe_kuo(text: &str, dims: usize) -> Parsed {
    let mut table = Vec::with_capacity(dims);
    table.push(std::array::from_fn(|k| 1u32 << (31 - k)));
    let mut fields = Vec::with_capacity(24);
    for (line_number, line) in text.as_bytes().split(|&b| b == b'\n').enumerate().skip(1) {
        if table.len() == dims {
            break;
        }
        let bad = |what: &str| format!("line {}: {what}", line_number + 1);
        numbers(line, &mut fields).ok_or_else(|| bad("not a list of numbers"))?;
        let [dim, degree, coefficients, initial @ ..] = fields.as_slice() else {
            return Err(bad("fewer than four fields"));
        };
        let s = *degree as usize;
        if *dim as usize != table.len() + 1 {
            return Err(bad("dimensions out of order"));
        }
        if !(1..32).contains(&s) || coefficients >> (s - 1) != 0 || initial.len() != s {
            return Err(bad(
                "degree, coefficients or count of initial numbers out of range",
            ));
        }
        let mut v = [0u32; 32];
        for (k, (slot, &m)) in v.iter_mut().zip(initial).enumerate() {
            if m % 2 == 0 || m >> (k + 1) != 0 {
                return Err(bad("initial direction number not odd and below 2^k"));
            }
            *slot = m << (31 - k);
        }
        // Offsets i with a_i = 1 (bit s - 1 - i of the coefficients).
        let mut taps = [0usize; 32];
        let mut tap_count = 0;
        for i in 1..s {
            taps[tap_count] = i;
            tap_count += ((coefficients >> (s - 1 - i)) & 1) as usize;
        }
        for k in s..32 {
            let mut word = v[k - s] ^ (v[k - s] >> s);
            for &i in &taps[..tap_count] {
                word ^= v[k - i];
            }
            v[k] = word;
        }
        table.push(v);
    }
    if table.len() != dims {
        return Err(format!("{} dimensions instead of {dims}", table.len()));
    }
    Ok(table)
}

/// XOR of the direction words selected by the set bits of `bits` (the Gray code of an index).
#[inline]
fn direct(directions: &Directions, mut bits: u32) -> u32 {
    let mut word = 0;
    while bits != 0 {
        word ^= directions[bits.trailing_zeros() as usize];
        bits &= bits - 1;
    }
    word
}

/// Gray code of an in-pass index.
#[inline]
fn gray(i: u32) -> u32 {
    i ^ (i >> 1)
}

/// A 32-bit word widened to 53 digits (zeros below).
#[inline(always)]
fn widen(word: u32) -> u64 {
    u64::from(word) << EXTRA_BITS
}

/// Applies the 53 x 32 binary matrix whose column for bit `b` of `word` is `columns[b]` (bit
/// `b + 21` plus random lower bits: lower triangular with unit diagonal in digit order).
#[inline]
fn linear(columns: &WideDirections, word: u32) -> u64 {
    let mut out = 0;
    for (b, &column) in columns.iter().enumerate() {
        out ^= column & 0u64.wrapping_sub(u64::from((word >> b) & 1));
    }
    out
}

/// An unscrambled word as a double: exactly `word * 2^-32`.
#[inline(always)]
fn unscrambled_f64(word: u32) -> f64 {
    f64::from(word) * (1.0 / 4_294_967_296.0)
}

/// A 53-digit randomized fraction (`bits < 2^53`) as a double: exact, on the `2^-53` grid,
/// below 1.
#[inline(always)]
fn wide_f64(bits: u64) -> f64 {
    let tail = (bits & ((1 << EXTRA_BITS) - 1)) as u32;
    join_f64((bits >> EXTRA_BITS) as u32, tail)
}

/// The Owen scramble of a bit-reversed word, followed by its hashed digits 33 to 53.
#[inline]
fn owen_f64(scramble: &OwenScramble, reversed: u32) -> f64 {
    let (word, tail) = owen_parts(scramble, reversed);
    join_f64(word, tail)
}

/// The scrambled word of a bit-reversed word, and its next 21 digits (right-aligned).
#[inline(always)]
fn owen_parts(scramble: &OwenScramble, reversed: u32) -> (u32, u32) {
    let word = scramble.apply_reversed(reversed);
    (word, scramble.tail_bits(word) >> (32 - EXTRA_BITS))
}

/// `(word * 2^21 + tail) * 2^-53` for `tail < 2^21`, as a sum of two exactly converted parts:
/// the sum is a multiple of `2^-53` below 1, so it is exact, and only 32-bit integers are
/// converted (which vectorizes, unlike 64-bit conversion before AVX-512).
#[inline(always)]
fn join_f64(word: u32, tail: u32) -> f64 {
    f64::from(word) * (1.0 / 4_294_967_296.0) + f64::from(tail) * (1.0 / 9_007_199_254_740_992.0)
}

/// Owen-scrambles a chunk of bit-reversed words and converts them: the 32-bit hashing first
/// (a loop of independent integer operations), then the conversion.
#[inline(always)]
fn owen_chunk<T: Unit>(scramble: &OwenScramble, reversed: &[u32], out: &mut [T]) {
    let mut words = [0u32; CHUNK];
    let mut tails = [0u32; CHUNK];
    let (words, tails) = (&mut words[..reversed.len()], &mut tails[..reversed.len()]);
    for ((w, t), &v) in words.iter_mut().zip(tails.iter_mut()).zip(reversed) {
        (*w, *t) = owen_parts(scramble, v);
    }
    for ((x, &w), &t) in out.iter_mut().zip(words.iter()).zip(tails.iter()) {
        *x = T::join(w, t);
    }
}

/// The randomization of one dimension in one pass.
// A short-lived stack value built once per column (or coordinate); boxing the matrix would
// cost an allocation per column for nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy)]
enum Randomizer {
    None,
    /// A 53-bit digital shift.
    Xor {
        shift: u64,
    },
    /// Columns of the 53 x 32 lower-triangular matrix, then a 53-bit digital shift.
    Lms {
        columns: WideDirections,
        shift: u64,
    },
    Owen {
        scramble: OwenScramble,
    },
}

impl Randomizer {
    /// Scrambles one unscrambled word and converts it.
    #[inline]
    fn finish(&self, word: u32) -> f64 {
        match self {
            Randomizer::None => unscrambled_f64(word),
            Randomizer::Xor { shift } => wide_f64(widen(word) ^ shift),
            Randomizer::Lms { columns, shift } => wide_f64(linear(columns, word) ^ shift),
            Randomizer::Owen { scramble } => owen_f64(scramble, word.reverse_bits()),
        }
    }
}

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
        let dim = dim as u64;
        let low53 = |h: u64| h >> (64 - FULL_BITS);
        match self.scramble {
            Scramble::Xor => Randomizer::Xor {
                shift: low53(hash_words(pass_seed, &[dim, XOR_SALT])),
            },
            Scramble::Lms => {
                let base = hash_words(pass_seed, &[dim, LMS_SALT]);
                // Column b keeps its diagonal bit b + 21 and random bits below it.
                let columns = std::array::from_fn(|b| {
                    let random = mix64(base.wrapping_add((b as u64 + 1).wrapping_mul(GOLDEN)));
                    let diagonal = 1u64 << (b as u32 + EXTRA_BITS);
                    diagonal | (random & (diagonal - 1))
                });
                Randomizer::Lms {
                    columns,
                    shift: low53(mix64(base)),
                }
            }
            Scramble::Owen => Randomizer::Owen {
                scramble: OwenScramble::new(dimension_seed(pass_seed, dim)),
            },
            // `new` admits no other scramble.
            _ => Randomizer::None,
        }
    }

    /// Fills `out` with in-pass points `first..` of one pass (no index shuffle), column by
    /// column: Gray-code words into a buffer, then scramble and convert.
    #[inline(always)]
    fn fill_run<B: Block>(&self, pass: u64, first: u32, out: &mut B, offset: usize, len: usize) {
        let pass_seed = self.pass_seed(pass);
        for (dim, directions) in self.directions.iter().enumerate() {
            let column = &mut out.column_mut(dim)[offset..offset + len];
            let start = direct(directions, gray(first));
            // Dispatch once per column. The shift and the matrix scramble are linear, so they
            // fold into 53-bit start and direction words; Owen runs the Gray code on
            // bit-reversed words, which is what its hash consumes.
            match self.randomizer(pass_seed, dim) {
                Randomizer::None => gray_column(directions, start, first, column, |w, x| {
                    convert(w, x, B::Value::from_word)
                }),
                Randomizer::Xor { shift } => {
                    let wide: WideDirections = directions.map(widen);
                    gray_column(&wide, widen(start) ^ shift, first, column, |w, x| {
                        convert(w, x, B::Value::from_wide)
                    })
                }
                Randomizer::Lms { columns, shift } => {
                    let wide: WideDirections = directions.map(|v| linear(&columns, v));
                    let start = linear(&columns, start) ^ shift;
                    gray_column(&wide, start, first, column, |w, x| {
                        convert(w, x, B::Value::from_wide)
                    })
                }
                Randomizer::Owen { scramble } => {
                    let reversed: Directions = directions.map(u32::reverse_bits);
                    gray_column(&reversed, start.reverse_bits(), first, column, |v, x| {
                        owen_chunk(&scramble, v, x)
                    })
                }
            }
        }
    }

    /// Like [`fill_run`](Self::fill_run) with the index shuffle (Owen only).
    #[inline(always)]
    fn fill_shuffled_run<B: Block>(
        &self,
        pass: u64,
        first: u32,
        out: &mut B,
        offset: usize,
        len: usize,
    ) {
        let pass_seed = self.pass_seed(pass);
        let shuffle = OwenScramble::new(Self::shuffle_seed(pass_seed));
        let mut shuffled = [0u32; CHUNK];
        let mut words = [0u32; CHUNK];
        let mut gathered = [0u32; CHUNK];
        let mut done = 0;
        while done < len {
            // A chunk never crosses a multiple of CHUNK, so its shuffled indices share their
            // high bits: they all lie in one aligned chunk of the sequence.
            let i0 = first.wrapping_add(done as u32);
            let n = (CHUNK - (i0 as usize & (CHUNK - 1))).min(len - done);
            let shuffled = &mut shuffled[..n];
            for (j, s) in shuffled.iter_mut().enumerate() {
                *s = shuffle.apply(i0.wrapping_add(j as u32));
            }
            let base = shuffled[0] & !(CHUNK as u32 - 1);
            for (dim, directions) in self.directions.iter().enumerate() {
                let column = &mut out.column_mut(dim)[offset + done..offset + done + n];
                let Randomizer::Owen { scramble } = self.randomizer(pass_seed, dim) else {
                    // Only Owen shuffles (see `shuffles`).
                    continue;
                };
                let reversed: Directions = directions.map(u32::reverse_bits);
                let gathered = &mut gathered[..n];
                if n < SHUFFLE_DIRECT_BELOW {
                    for (g, &s) in gathered.iter_mut().zip(shuffled.iter()) {
                        *g = direct(&reversed, gray(s));
                    }
                } else {
                    // The whole aligned chunk of sequence points by Gray code, then gathered.
                    let offsets = group_offsets(&reversed);
                    let start = direct(&reversed, gray(base));
                    gray_words(&reversed, &offsets, start, base, &mut words);
                    for (g, &s) in gathered.iter_mut().zip(shuffled.iter()) {
                        *g = words[s as usize & (CHUNK - 1)];
                    }
                }
                owen_chunk(&scramble, gathered, column);
            }
            done += n;
        }
    }
}

/// A fill of one pass's run of points, compiled for each instruction set by [`dispatch`].
struct FillRun<'a, B> {
    sobol: &'a Sobol,
    pass: u64,
    first: u32,
    out: &'a mut B,
    offset: usize,
    len: usize,
}

impl<B: Block> Kernel for FillRun<'_, B> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let FillRun {
            sobol,
            pass,
            first,
            out,
            offset,
            len,
        } = self;
        if sobol.shuffles() {
            sobol.fill_shuffled_run(pass, first, out, offset, len);
        } else {
            sobol.fill_run(pass, first, out, offset, len);
        }
    }
}

/// The words of in-group offsets `0..GROUP` relative to the group's first word: entry `j` is
/// the XOR of the direction words selected by `gray(j)`. For an aligned index `a` (a multiple
/// of `GROUP`) and `j < GROUP`, `gray(a + j) = gray(a) ^ gray(j)`, so the word of `a + j` is
/// the word of `a` XOR entry `j`.
#[inline(always)]
fn group_offsets<W: Copy + Default + BitXorAssign>(directions: &[W; 32]) -> [W; GROUP] {
    let mut offsets = [W::default(); GROUP];
    let mut word = W::default();
    for (j, slot) in offsets.iter_mut().enumerate().skip(1) {
        word ^= directions[j.trailing_zeros() as usize];
        *slot = word;
    }
    offsets
}

/// Writes the words of in-pass indices `first, first + 1, ...` into `words`, starting from
/// `start` (the word of `first`, possibly scrambled or widened). Returns the word of the
/// index after the last. Consecutive Gray codes differ in bit `ctz(i + 1)`; the indices
/// before the first multiple of `GROUP` and after the last step one at a time, the aligned
/// groups in between are filled from `offsets` ([`group_offsets`]), with one serial step per
/// group.
#[inline(always)]
fn gray_words<W: Copy + BitXorAssign>(
    directions: &[W; 32],
    offsets: &[W; GROUP],
    start: W,
    first: u32,
    words: &mut [W],
) -> W {
    // ctz(0) = 32 only past the end of a pass, where the update is never used.
    let step = |i: u32| directions[(i.trailing_zeros() & 31) as usize];
    let mut word = start;
    let mut i = first;
    let head = ((GROUP as u32).wrapping_sub(first) as usize & (GROUP - 1)).min(words.len());
    let (head, rest) = words.split_at_mut(head);
    for slot in head {
        *slot = word;
        i = i.wrapping_add(1);
        word ^= step(i);
    }
    let mut groups = rest.chunks_exact_mut(GROUP);
    for group in &mut groups {
        for (slot, &offset) in group.iter_mut().zip(offsets) {
            let mut w = word;
            w ^= offset;
            *slot = w;
        }
        // The group's last word, then one step into the next group.
        word ^= offsets[GROUP - 1];
        i = i.wrapping_add(GROUP as u32);
        word ^= step(i);
    }
    for slot in groups.into_remainder() {
        *slot = word;
        i = i.wrapping_add(1);
        word ^= step(i);
    }
    word
}

/// One column of a run of consecutive in-pass indices starting at `first`, whose word is
/// `start`: Gray-code words into a chunk buffer, then `finish` scrambles and converts the
/// chunk (loops free of loop-carried dependencies). Monomorphized per scramble, so the inner
/// loops do not branch on it. Chunks after the first start at multiples of `CHUNK`, so only
/// the first and last can have unaligned groups.
#[inline(always)]
fn gray_column<W: Copy + Default + BitXorAssign, T, F: FnMut(&[W], &mut [T])>(
    directions: &[W; 32],
    start: W,
    first: u32,
    column: &mut [T],
    mut finish: F,
) {
    let offsets = group_offsets(directions);
    let mut words = [W::default(); CHUNK];
    let mut word = start;
    let mut i = first;
    let mut rest = column;
    while !rest.is_empty() {
        let n = (CHUNK - (i as usize & (CHUNK - 1))).min(rest.len());
        let (out, tail) = rest.split_at_mut(n);
        let words = &mut words[..n];
        word = gray_words(directions, &offsets, word, i, words);
        i = i.wrapping_add(n as u32);
        finish(words, out);
        rest = tail;
    }
}

/// Converts a chunk of words one by one.
#[inline(always)]
fn convert<W: Copy, T>(words: &[W], out: &mut [T], to_unit: impl Fn(W) -> T) {
    for (x, &w) in out.iter_mut().zip(words) {
        *x = to_unit(w);
    }
}

/// An output precision: how a 32-bit word, a 53-bit fraction or a word with its 21 tail
/// digits becomes a coordinate. Each is the exact value, rounded once (for `f32`).
trait Unit: Copy {
    /// `word * 2^-32`.
    fn from_word(word: u32) -> Self;
    /// `bits * 2^-53`, for `bits < 2^53`.
    fn from_wide(bits: u64) -> Self;
    /// `(word * 2^21 + tail) * 2^-53`, for `tail < 2^21`.
    fn join(word: u32, tail: u32) -> Self;
}

impl Unit for f64 {
    #[inline(always)]
    fn from_word(word: u32) -> f64 {
        unscrambled_f64(word)
    }
    #[inline(always)]
    fn from_wide(bits: u64) -> f64 {
        wide_f64(bits)
    }
    #[inline(always)]
    fn join(word: u32, tail: u32) -> f64 {
        join_f64(word, tail)
    }
}

/// The integer conversion rounds to nearest, ties to even, and the power-of-two scaling is
/// exact; values that would round to 1.0 are clamped as `to_unit_f32` does.
impl Unit for f32 {
    #[inline(always)]
    fn from_word(word: u32) -> f32 {
        (word as f32 * (1.0 / 4_294_967_296.0)).min(F32_BELOW_ONE)
    }
    #[inline(always)]
    fn from_wide(bits: u64) -> f32 {
        (bits as f32 * (1.0 / 9_007_199_254_740_992.0)).min(F32_BELOW_ONE)
    }
    #[inline(always)]
    fn join(word: u32, tail: u32) -> f32 {
        Self::from_wide(u64::from(word) << EXTRA_BITS | u64::from(tail))
    }
}

/// A block of points of either precision.
trait Block {
    /// The coordinate type.
    type Value: Unit;
    /// Points in the block.
    fn len(&self) -> usize;
    /// Column `dim`.
    fn column_mut(&mut self, dim: usize) -> &mut [Self::Value];
}

impl Block for Points {
    type Value = f64;
    fn len(&self) -> usize {
        Points::len(self)
    }
    fn column_mut(&mut self, dim: usize) -> &mut [f64] {
        Points::column_mut(self, dim)
    }
}

impl Block for PointsF32 {
    type Value = f32;
    fn len(&self) -> usize {
        PointsF32::len(self)
    }
    fn column_mut(&mut self, dim: usize) -> &mut [f32] {
        PointsF32::column_mut(self, dim)
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
    fn name(&self) -> &'static str {
        "sobol"
    }

    fn dims(&self) -> usize {
        self.dims
    }

    fn passes(&self) -> PassKind {
        PassKind::Extensible {
            max: 1 << PASS_BITS,
        }
    }

    fn seed(&self) -> u64 {
        self.seed
    }

    fn reseed(&mut self, seed: u64) {
        self.seed = seed;
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

impl Sobol {
    /// Fills a checked block of either precision, split at pass boundaries.
    fn fill_block<B: Block>(&self, start: u64, points: &mut B) {
        let len = points.len();
        let mut done = 0;
        // Split the block at pass boundaries; each run lies within one pass.
        while done < len {
            let index = start + done as u64;
            let pass = index >> PASS_BITS;
            let first = index as u32;
            let room = (1u64 << PASS_BITS) - u64::from(first);
            let n = (len - done).min(usize::try_from(room).unwrap_or(usize::MAX));
            dispatch(FillRun {
                sobol: self,
                pass,
                first,
                out: points,
                offset: done,
                len: n,
            });
            done += n;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sobol_table_parses_and_first_dimensions_match_the_definition() {
        let t = table(MAX_DIMS).unwrap();
        assert_eq!(t.len(), MAX_DIMS);
        // Dimension 2: s = 1, m_1 = 1, polynomial x + 1: m_k = 2 m_(k-1) ^ m_(k-1), so the
        // words are 2^31, 2^31 + 2^30, ... (Pascal's triangle mod 2).
        assert_eq!(t[1][0], 1 << 31);
        assert_eq!(t[1][1], 0xc000_0000);
        assert_eq!(t[1][2], 0xa000_0000);
        assert_eq!(t[1][3], 0xf000_0000);
        // m_k is odd, so word k's lowest set bit is bit 31 - k: the generator matrices have a
        // unit diagonal and every coordinate is a (0, 1)-sequence.
        for dirs in t {
            for (k, &v) in dirs.iter().enumerate() {
                assert_eq!(v.trailing_zeros() as usize, 31 - k);
            }
        }
    }

    #[test]
    fn sobol_parser_rejects_malformed_lines() {
        assert!(parse_joe_kuo("header\n2 1 0 2\n", 2).is_err());
        assert!(parse_joe_kuo("header\n3 1 0 1\n", 2).is_err());
        assert!(parse_joe_kuo("header\n2 1 0 1 1\n", 2).is_err());
        assert!(parse_joe_kuo("header\n2 1 0\n", 2).is_err());
        // Well formed but short.
        assert!(parse_joe_kuo("header\n2 1 0 1\n", 3).is_err());
        assert_eq!(parse_joe_kuo("header\n2 1 0 1\n", 2).unwrap().len(), 2);
        assert!(parse_joe_kuo("header\n2 1 0 x\n", 2).is_err());
    }

    #[test]
    fn sobol_lms_columns_are_unit_lower_triangular_and_linear() {
        let s = Sobol::new(3, Scramble::Lms, 9).unwrap();
        let Randomizer::Lms { columns, .. } = s.randomizer(s.pass_seed(0), 2) else {
            panic!("expected an LMS randomizer");
        };
        // Column b: the diagonal bit b + 21, nothing above it, fair coins below it (1168
        // random bits in all: sd 17.1 around 584).
        let mut ones = 0;
        for (b, &c) in columns.iter().enumerate() {
            assert_eq!(c >> (b + 21), 1);
            ones += (c & ((1 << (b + 21)) - 1)).count_ones();
        }
        assert!(ones.abs_diff(584) < 86, "{ones}");
        assert_eq!(
            linear(&columns, 0x1234 ^ 0x8000_0001),
            linear(&columns, 0x1234) ^ linear(&columns, 0x8000_0001)
        );
    }
}
