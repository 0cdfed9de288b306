//! Progressive multi-jittered (0,2) sequences: pmj02 (Christensen, Kensler & Kilpatrick 2018,
//! "Progressive Multi-Jittered Sample Sequences", Computer Graphics Forum 37(4)).
//!
//! A pmj02 sequence in two dimensions has every prefix of `2^m` points a `(0, m, 2)`-net in
//! base 2: each elementary interval `[a 2^-k, (a+1) 2^-k) x [b 2^-(m-k), (b+1) 2^-(m-k))` of
//! area `2^-m`, of every shape `k = 0..=m`, holds exactly one point. The shapes `k = 0` and
//! `k = m` make every prefix N-rooks (Latin hypercube) stratified, and for even `m` the square
//! shape makes it jittered.
//!
//! # Construction
//!
//! Christensen et al. build the sequence point by point, choosing each new point uniformly
//! among the positions allowed by all elementary intervals. Helmer, Christensen & Kensler
//! (2021, "Stochastic Generation of (t, s) Sample Sequences", EGSR) showed that this stochastic
//! generation is the same thing as Owen's nested uniform scrambling of a digital
//! `(0, 2)`-sequence: every digit of the new point that the net constraints leave free is a
//! fresh fair coin, and every forced digit is the complement dictated by an earlier point. This
//! module uses that second form, which needs no search and no stored table (the 2018 paper's
//! search-based generator, with its stratum bookkeeping, is not implemented; both give
//! sequences whose every power-of-two prefix is a `(0, m, 2)`-net, which the tests check):
//!
//! * the unscrambled sequence is the first two Sobol' dimensions: the van der Corput radical
//!   inverse (identity generator matrix) and the Pascal matrix mod 2, a `(0, 2)`-sequence in
//!   base 2;
//! * each coordinate gets a nested uniform scramble of its first `log2_max` digits: digit `d`
//!   is flipped by a hashed coin chosen independently for every value of the `d` digits above
//!   it (a true Owen scramble, one coin per tree node, not an approximation). Scrambling keeps
//!   every elementary interval's occupancy, so every prefix of `2^m` points (indeed every
//!   aligned block of `2^m` indices) of a pass stays a `(0, m, 2)`-net;
//! * below digit `log2_max` the `2^log2_max` points of a pass have pairwise different prefixes
//!   in both coordinates, so the remaining digits are independent fair coins hashed from the
//!   point's node (the jitter inside its finest elementary interval).
//!
//! Every point is therefore a pure function of `(seed, pass, index)`, computed in
//! `O(log2_max)` hashes: the sequential generation of the paper is not needed, and neither is a
//! cache of generated passes (no locks, no memory, and [`Sampler::point`] and
//! [`Sampler::fill`] share one code path). Each coordinate is uniform on `[0, 1)`, so every
//! estimate is unbiased; for smooth integrands the variance of a prefix of `N` points falls
//! like `N^-3 (log N)` (Owen 1997).
//!
//! # Higher dimensions
//!
//! Dimensions `(2p, 2p + 1)` are the pmj02 pair `p`: an independent scramble (seeds hashed
//! from `(seed, pass, p)`) of the same `(0, 2)`-sequence. Used with the same index, two
//! scrambles of one sequence would be strongly correlated (both first coordinates are
//! scrambles of the same radical inverse), so pair `p >= 1` reads its sequence at a hashed
//! index: bit `b` of the index is flipped by a coin that depends on the bits above `b` only.
//! That map sends every aligned block of `2^m` indices onto another aligned block of `2^m`
//! indices, so for pairs beyond the first too, every prefix of `2^m` points is a
//! `(0, m, 2)`-net (it is a different, randomly chosen block of the same sequence). What is
//! not controlled is the joint stratification of coordinates from different pairs (as with
//! pbrt's pmj02bn tables, pairs are padded randomly). An odd last dimension is the first
//! coordinate of one more independent pair: a progressive 1-D stratified sequence, whose every
//! prefix of `2^m` points has one point in each interval of width `2^-m`.

use super::simd::{BlockFill, dispatch_fill};
use super::{PassKind, Sampler, check_dims, check_point, fill_pointwise, pass_runs};
use crate::error::{Error, Result};
use crate::hash::{hash_words, mix64};
use crate::points::Points;
use crate::simd::Kernel;

/// Largest accepted `log2_max`: passes of up to 2^20 points.
const MAX_LOG2: u32 = 20;
/// `log2_max` used by [`Pmj02::new`]: passes of 2^16 points.
const DEFAULT_LOG2: u32 = 16;
/// Weyl multiplier that spreads node numbers before they meet a key.
const SPREAD: u64 = 0x9e37_79b9_7f4a_7c15;
/// Salt separating this sampler's keys from other uses of the seed.
const SALT: u64 = 0x0070_6d6a_3032;

/// The Pascal matrix mod 2 (second Sobol' dimension), column `k` as a 32-bit word whose bit
/// `31 - r` is digit `r` (most significant first): digit `r` is `C(k, r) mod 2`, which by
/// Lucas' theorem is 1 exactly when the bits of `r` are a subset of those of `k`.
const PASCAL: [u32; 32] = pascal_columns();

const fn pascal_columns() -> [u32; 32] {
    let mut columns = [0u32; 32];
    let mut k = 0;
    while k < 32 {
        let mut r = 0;
        while r <= k {
            if r & k == r {
                columns[k] |= 1 << (31 - r);
            }
            r += 1;
        }
        k += 1;
    }
    columns
}

/// The hashed keys of one pair of dimensions in one pass.
#[derive(Debug, Clone, Copy)]
struct PairKeys {
    /// Scramble of the first coordinate.
    x: u64,
    /// Scramble of the second coordinate.
    y: u64,
    /// Index scramble (`None` for pair 0, which reads the sequence in order).
    index: Option<u64>,
}

/// Progressive multi-jittered (0,2) sample sequence (pmj02) in pairs of dimensions.
///
/// A pass holds up to `2^log2_max` points (`log2_max` in `0..=20`, default 16, so passes of
/// 65,536 points); index `i` is point `i mod 2^log2_max` of pass `i >> log2_max`, and each pass
/// is an independent randomization. Every prefix of `2^m` points of a pass is a
/// `(0, m, 2)`-net in dimensions `(0, 1)` (and in each later pair), which makes it both
/// jittered and N-rooks stratified. The construction is described at the top of
/// its source file, `src/sampler/pmj02.rs`.
///
/// ```
/// use mcint::sampler::{Pmj02, Sampler};
/// let s = Pmj02::new(2, 7).unwrap();
/// // The first 16 points have one point in each of the 4 x 4 cells and each of 16 columns.
/// let (mut cells, mut columns) = (vec![0; 16], vec![0; 16]);
/// let mut p = [0.0; 2];
/// for i in 0..16 {
///     s.point(i, &mut p).unwrap();
///     cells[(p[0] * 4.0) as usize * 4 + (p[1] * 4.0) as usize] += 1;
///     columns[(p[0] * 16.0) as usize] += 1;
/// }
/// assert!(cells.iter().chain(&columns).all(|&c| c == 1));
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Pmj02 {
    dims: usize,
    log2_max: u32,
    seed: u64,
}

impl Pmj02 {
    /// A pmj02 sampler in `dims >= 1` dimensions with passes of up to `2^16` points.
    ///
    /// ```
    /// use mcint::sampler::{PassKind, Pmj02, Sampler};
    /// let s = Pmj02::new(3, 1).unwrap();
    /// assert_eq!(s.passes(), PassKind::Extensible { max: 1 << 16 });
    /// assert!(Pmj02::new(0, 1).is_err());
    /// ```
    pub fn new(dims: usize, seed: u64) -> Result<Self> {
        Self::with_max_points(dims, DEFAULT_LOG2, seed)
    }

    /// A pmj02 sampler whose passes hold up to `2^log2_max` points, `log2_max` in `0..=20`.
    ///
    /// Larger passes cost a little more per point (one hash per digit of `log2_max`).
    ///
    /// ```
    /// use mcint::sampler::{PassKind, Pmj02, Sampler};
    /// let s = Pmj02::with_max_points(2, 10, 5).unwrap();
    /// assert_eq!(s.passes(), PassKind::Extensible { max: 1024 });
    /// let err = Pmj02::with_max_points(2, 21, 5).unwrap_err();
    /// assert!(err.to_string().contains("0..=20"));
    /// ```
    pub fn with_max_points(dims: usize, log2_max: u32, seed: u64) -> Result<Self> {
        check_dims(dims)?;
        if log2_max > MAX_LOG2 {
            return Err(Error::invalid(
                "log2_max",
                log2_max,
                format!("log2 of the points per pass in 0..={MAX_LOG2}"),
            ));
        }
        Ok(Pmj02 {
            dims,
            log2_max,
            seed,
        })
    }

    /// Base-2 logarithm of the points per pass.
    ///
    /// ```
    /// use mcint::sampler::Pmj02;
    /// assert_eq!(Pmj02::new(2, 0).unwrap().log2_max(), 16);
    /// ```
    pub fn log2_max(&self) -> u32 {
        self.log2_max
    }

    /// The keys of pair `pair` in pass `pass`.
    fn keys(&self, pass: u64, pair: usize) -> PairKeys {
        let key = |role: u64| hash_words(self.seed, &[pass, pair as u64, role, SALT]);
        PairKeys {
            x: key(0),
            y: key(1),
            index: (pair > 0).then(|| key(2)),
        }
    }

    /// Coordinates `(x, y)` of the pair with keys `keys` at index `local` within its pass;
    /// `y` is skipped (returned as 0) when `want_y` is false.
    #[inline]
    fn pair_point(&self, keys: &PairKeys, local: u32, want_y: bool) -> (f64, f64) {
        let bits = self.log2_max;
        let index = match keys.index {
            Some(key) => scramble_index(local, bits, key),
            None => local,
        };
        if bits == 0 {
            let x = to_unit(0, 0, mix64(keys.x));
            let y = if want_y {
                to_unit(0, 0, mix64(keys.y))
            } else {
                0.0
            };
            return (x, y);
        }
        let radical = index.reverse_bits() >> (32 - bits);
        let x = owen_coordinate(radical, bits, keys.x);
        let y = if want_y {
            let mut word = 0u32;
            let mut rest = index;
            while rest != 0 {
                word ^= PASCAL[rest.trailing_zeros() as usize];
                rest &= rest - 1;
            }
            owen_coordinate(word >> (32 - bits), bits, keys.y)
        } else {
            0.0
        };
        (x, y)
    }

    /// Writes point `index` into `out`, given a function that supplies the keys of a pair.
    fn write_point(&self, index: u64, out: &mut [f64], keys: impl Fn(usize) -> PairKeys) {
        let local = (index & ((1u64 << self.log2_max) - 1)) as u32;
        for (pair, chunk) in out.chunks_mut(2).enumerate() {
            let (x, y) = self.pair_point(&keys(pair), local, chunk.len() == 2);
            chunk[0] = x;
            if let Some(slot) = chunk.get_mut(1) {
                *slot = y;
            }
        }
    }
}

/// The node coin of a tree node (`depth`, `prefix`) under `key`: a full 64-bit hash.
#[inline]
fn node_hash(key: u64, depth: u32, prefix: u32) -> u64 {
    let node = (u64::from(depth) << 32) | u64::from(prefix);
    mix64(key ^ node.wrapping_add(1).wrapping_mul(SPREAD))
}

/// Owen's nested uniform scramble of the `bits`-digit word `digits` (most significant digit
/// first), followed by `53 - bits` random digits hashed from the full word, as a double.
#[inline]
fn owen_coordinate(digits: u32, bits: u32, key: u64) -> f64 {
    let mut scrambled = digits;
    for depth in 0..bits {
        // The `depth` digits above digit `depth` (none for the first).
        let prefix = if depth == 0 {
            0
        } else {
            digits >> (bits - depth)
        };
        let coin = (node_hash(key, depth, prefix) >> 63) as u32;
        scrambled ^= coin << (bits - 1 - depth);
    }
    to_unit(scrambled, bits, node_hash(key, bits, digits))
}

/// `bits` leading digits `head` followed by the top `53 - bits` bits of `tail`, as a double in
/// `[0, 1)` (exact: the word has 53 bits).
#[inline]
fn to_unit(head: u32, bits: u32, tail: u64) -> f64 {
    let low_bits = 53 - bits;
    let word = (u64::from(head) << low_bits) | (tail >> (64 - low_bits));
    word as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A bijection of `0..2^bits` that maps every aligned block of `2^m` indices onto an aligned
/// block of `2^m` indices: bit `b` is flipped by a coin depending on the bits above it only.
#[inline]
fn scramble_index(index: u32, bits: u32, key: u64) -> u32 {
    let mut out = index;
    for b in 0..bits {
        let coin = (node_hash(key, b, index >> (b + 1)) >> 63) as u32;
        out ^= coin << b;
    }
    out
}

impl Sampler for Pmj02 {
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
        "pmj02"
    }

    fn passes(&self) -> PassKind {
        PassKind::Extensible {
            max: 1 << self.log2_max,
        }
    }

    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        check_point(self.dims, out)?;
        let pass = index >> self.log2_max;
        self.write_point(index, out, |pair| self.keys(pass, pair));
        Ok(())
    }

    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        if self.log2_max == 0 {
            // One point per pass: nothing to vectorize.
            return fill_pointwise(self, start, points);
        }
        dispatch_fill(self, self.dims, start, points)
    }
}

/// Indices a step of the block fill kernel handles at once.
const LANES: usize = 16;

/// Owen's scramble of the `bits`-digit words `digits`, lane by lane, as `owen_coordinate`.
#[inline(always)]
fn owen_lanes(digits: &[u32; LANES], bits: u32, key: u64) -> [f64; LANES] {
    let mut scrambled = *digits;
    for depth in 0..bits {
        for (out, &word) in scrambled.iter_mut().zip(digits) {
            // The `depth` digits above digit `depth` (none for the first).
            let prefix = if depth == 0 {
                0
            } else {
                word >> (bits - depth)
            };
            let coin = (node_hash(key, depth, prefix) >> 63) as u32;
            *out ^= coin << (bits - 1 - depth);
        }
    }
    std::array::from_fn(|l| to_unit(scrambled[l], bits, node_hash(key, bits, digits[l])))
}

/// The block fill for passes of at least two points, compiled for each instruction set by
/// [`dispatch_fill`]. Per run of indices within one pass and per pair of dimensions, 16 indices
/// at a time: the index scramble, the radical inverse and the Pascal-matrix word (XOR of the
/// rows of the set bits, masked instead of branched), and both Owen scrambles, each with the
/// digit positions outermost and the lanes innermost, so every step is a few vector
/// instructions. The integers are those of `pair_point`, so the values are bit-identical.
impl Kernel for BlockFill<'_, Pmj02> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let (sampler, start, points) = (self.sampler, self.start, self.points);
        let bits = sampler.log2_max;
        let len = points.len();
        for (done, pass, local, run) in pass_runs(start, len, 1 << bits) {
            let local = local as u32;
            for pair in 0..sampler.dims.div_ceil(2) {
                let keys = sampler.keys(pass, pair);
                let dx = 2 * pair;
                for offset in (0..run).step_by(LANES) {
                    let n = LANES.min(run - offset);
                    // Short groups repeat their last index.
                    let first = local + offset as u32;
                    let plain: [u32; LANES] = std::array::from_fn(|l| first + l.min(n - 1) as u32);
                    let mut indices = plain;
                    if let Some(key) = keys.index {
                        for b in 0..bits {
                            for (out, &i) in indices.iter_mut().zip(&plain) {
                                let coin = (node_hash(key, b, i >> (b + 1)) >> 63) as u32;
                                *out ^= coin << b;
                            }
                        }
                    }
                    let radical = indices.map(|i| i.reverse_bits() >> (32 - bits));
                    let xs = owen_lanes(&radical, bits, keys.x);
                    let at = done + offset;
                    points.column_mut(dx)[at..at + n].copy_from_slice(&xs[..n]);
                    if dx + 1 == sampler.dims {
                        continue;
                    }
                    let mut words = [0u32; LANES];
                    for (bit, &row) in PASCAL.iter().enumerate().take(bits as usize) {
                        for (word, &i) in words.iter_mut().zip(&indices) {
                            *word ^= row & 0u32.wrapping_sub((i >> bit) & 1);
                        }
                    }
                    let ys = owen_lanes(&words.map(|w| w >> (32 - bits)), bits, keys.y);
                    points.column_mut(dx + 1)[at..at + n].copy_from_slice(&ys[..n]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether the points are a (0, m, 2)-net: every elementary interval of area 2^-m holds
    /// exactly one of the 2^m points.
    fn is_net(points: &[(f64, f64)], m: u32) -> bool {
        let n = 1usize << m;
        (0..=m).all(|k| {
            let mut seen = vec![false; n];
            points.iter().all(|&(x, y)| {
                let cell = ((x * (1u64 << k) as f64) as usize) << (m - k)
                    | (y * (1u64 << (m - k)) as f64) as usize;
                !std::mem::replace(&mut seen[cell], true)
            })
        })
    }

    #[test]
    fn pmj02_pascal_columns_are_lucas() {
        assert_eq!(PASCAL[0], 1 << 31);
        assert_eq!(PASCAL[1], 0b11 << 30);
        assert_eq!(PASCAL[2], 0b101 << 29);
        assert_eq!(PASCAL[3], 0b1111 << 28);
    }

    #[test]
    fn pmj02_unscrambled_sequence_is_a_0_2_sequence() {
        // All 2^12 prefixes of every power of two, for the digits alone (no scramble).
        let bits = 12;
        let points: Vec<(f64, f64)> = (0u32..1 << bits)
            .map(|i| {
                let x = i.reverse_bits() >> (32 - bits);
                let mut y = 0;
                let mut rest = i;
                while rest != 0 {
                    y ^= PASCAL[rest.trailing_zeros() as usize];
                    rest &= rest - 1;
                }
                let scale = 1.0 / (1u64 << bits) as f64;
                (f64::from(x) * scale, f64::from(y >> (32 - bits)) * scale)
            })
            .collect();
        for m in 0..=bits {
            assert!(is_net(&points[..1 << m], m), "m = {m}");
        }
    }

    #[test]
    fn pmj02_index_scramble_maps_aligned_blocks_to_aligned_blocks() {
        let bits = 10;
        for key in [1u64, 99, 12345] {
            let image: Vec<u32> = (0..1 << bits)
                .map(|i| scramble_index(i, bits, key))
                .collect();
            let mut sorted = image.clone();
            sorted.sort_unstable();
            assert!(sorted.iter().enumerate().all(|(i, &v)| v == i as u32));
            for m in 0..=bits {
                for block in image.chunks(1 << m) {
                    assert!(block.iter().all(|&v| v >> m == block[0] >> m), "m = {m}");
                }
            }
        }
    }

    #[test]
    fn pmj02_full_pass_of_2_16_points_is_a_net() {
        let s = Pmj02::new(2, 3).unwrap();
        let mut block = Points::new(2, 1 << 16).unwrap();
        s.fill(1 << 16, &mut block).unwrap();
        let points: Vec<(f64, f64)> = (0..block.len())
            .map(|i| (block.get(i, 0), block.get(i, 1)))
            .collect();
        assert!(is_net(&points, 16));
        assert!(is_net(&points[..1 << 15], 15));
    }

    #[test]
    fn pmj02_zero_log2_max_gives_one_point_passes() {
        let s = Pmj02::with_max_points(3, 0, 4).unwrap();
        let (mut a, mut b) = ([0.0; 3], [0.0; 3]);
        s.point(0, &mut a).unwrap();
        s.point(1, &mut b).unwrap();
        assert!(a.iter().chain(&b).all(|&x| (0.0..1.0).contains(&x)));
        assert_ne!(a, b);
    }
}
