//! Halton sequences (Halton 1960) and their randomizations by digit permutations.
//!
//! Coordinate `j` of point `i` is the radical inverse of `i` in the `j`-th prime base
//! (van der Corput 1935 for one base, Halton 1960 for one prime per coordinate); Hammersley
//! (1960) point sets, in `hammersley.rs`, reuse this module's kernels. Two randomizations keep
//! each coordinate's stratification and make every point uniform: random digit permutations
//! (Braaten & Weller 1979 with fixed permutations; random ones as in Owen 2017 and scipy, and as
//! analysed by Faure & Tezuka 2002 and Matoušek 1998) and nested uniform scrambling in base `b`
//! (Owen 1995). The public [`Halton`] documents the index convention, the precision (correctly
//! rounded radical inverses), how the infinite tail of zero digits is handled, and the passes.
//!
//! Kernels: [`radical_inverse`] divides the digit-reversed integer by `b^k` once (an odometer
//! over a common denominator in [`fill_plain`]); scrambled coordinates accumulate permuted
//! digits as a `u128` numerator over `b^K` and round once ([`Base::ratio`]: a multiplication
//! by a per-base reciprocal, with the exact [`ratio_to_f64`] near halfway points). The block
//! kernels ([`fill_permuted`], and `owen_block.rs` for nested scrambling) share work between
//! the indices of a block and run the keyed permutations in lanes through `super::simd`. Every
//! path yields the same integers and the same single rounding, so `fill` and `point` agree bit
//! for bit.

use super::number_theory::primes_below;
use super::permutation::{LANES, Permutation};
use super::simd::{Kernel, dispatch};
use super::{PassKind, Sampler, Scramble, check_block, check_point};
use crate::float::ONE_BELOW;
use crate::hash::hash_words;
use crate::{Error, Points, Result};
use std::sync::OnceLock;

mod owen_block;

/// The most dimensions (prime bases) a Halton or Hammersley sampler may have.
pub(crate) const MAX_DIMS: usize = 10_000;
/// log2 of the points per pass of a Halton sequence.
const PASS_BITS: u32 = 40;
/// Points per pass of a Halton sequence, and the largest Hammersley point set.
pub(crate) const PASS_SIZE: u64 = 1 << PASS_BITS;
/// Every integer up to this is exact in an `f64`.
const EXACT_F64: u64 = 1 << 53;
/// The 10,000th prime is 104,729: sieving below this bound finds all the bases.
const SIEVE_BOUND: usize = 104_730;
/// Digit permutations of bases up to this are decoded from one hash by Fisher-Yates.
const SMALL_BASE: u64 = 13;
/// The most digit positions a scramble permutes (base 2: `2^53`).
const MAX_DEPTH: usize = 53;
/// Hash tags that keep the random streams of different purposes apart.
const TAG_HALTON: u64 = 0x6861_6c74;
const TAG_RHO: u64 = 0x0072_686f;

/// The randomizations the Halton-type samplers accept.
pub(crate) const SCRAMBLES: [Scramble; 3] = [Scramble::None, Scramble::Permute, Scramble::Owen];

/// A prime base with its scrambling depth.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Base {
    /// The prime `b`.
    pub(crate) base: u64,
    /// Digit positions a scramble permutes: the least `K` with `b^K >= 2^53`.
    depth: usize,
    /// `b^K`, below `2^71`.
    full: u128,
    /// Random digits cut from one 64-bit hash: the largest `m` with `b^m <= 2^32`.
    per_word: u32,
    /// `1 / b` rounded, for [`Base::split`].
    inverse: f64,
    /// `floor(2^(63 + D) / b^K)` with `D` the bit length of `b^K`, for [`Base::ratio`].
    reciprocal: u64,
    /// `D`, the bit length of `b^K`.
    full_bits: u32,
}

impl Base {
    fn new(base: u64) -> Self {
        let (mut depth, mut full) = (0, 1u128);
        while full < u128::from(EXACT_F64) {
            full *= u128::from(base);
            depth += 1;
        }
        let (mut per_word, mut power) = (0, 1u64);
        while power * base <= 1 << 32 {
            power *= base;
            per_word += 1;
        }
        // 2^(63 + D) may exceed 2^127: divide 2^127 first, then the remainder times the
        // rest (below 2^8, as D <= 72).
        let full_bits = 128 - full.leading_zeros();
        let reciprocal = if full_bits <= 64 {
            (1u128 << (63 + full_bits)) / full
        } else {
            let extra = full_bits - 64;
            (((1u128 << 127) / full) << extra) + ((((1u128 << 127) % full) << extra) / full)
        };
        Base {
            base,
            depth,
            full,
            per_word: per_word.max(1),
            inverse: 1.0 / base as f64,
            reciprocal: u64::try_from(reciprocal).unwrap_or(u64::MAX),
            full_bits,
        }
    }

    /// `num / b^K` correctly rounded (ties to even) for `num < b^K`: the same value as
    /// [`ratio_to_f64`]`(num, b^K)`, by one 64-bit multiplication in all but about 1 case in
    /// 100.
    ///
    /// With `A` the bit length of `num`, its top 64 bits `t` (truncated) times the
    /// precomputed reciprocal `r = floor(2^(63 + D) / b^K)` give, in their high 64 bits, the
    /// real `X = num / b^K * 2^(63 + D - A)`, which lies in `(2^62, 2^64)`, from below and
    /// within 5 units (two truncations of relative size `2^-63` and one of a unit). Shifted to
    /// 64 significant bits (within 10 units), the top 53 bits are the mantissa and the 11 below
    /// decide the rounding, unless they lie within the error of the halfway point (or the
    /// value may cross into the next binade): then the exact [`ratio_to_f64`] decides.
    #[inline(always)]
    fn ratio(&self, num: u128) -> f64 {
        debug_assert!(num < self.full);
        if self.base == 2 {
            // b^K = 2^53: exact.
            return num as u64 as i64 as f64 * pow2(-53);
        }
        if num == 0 {
            return 0.0;
        }
        let zeros = num.leading_zeros(); // A = 128 - zeros, at most 72
        let top = ((num << zeros) >> 64) as u64;
        let high = ((u128::from(top) * u128::from(self.reciprocal)) >> 64) as u64;
        let normal = high.leading_zeros(); // 0 or 1
        let high = high << normal;
        let low = high & 0x7ff;
        if (1024 - 10..=1024).contains(&low) || high >= u64::MAX - 32 {
            return ratio_to_f64(num, self.full);
        }
        // Round half up is safe here: the value is not within the error of the halfway point.
        let mantissa = (high >> 11) + u64::from(low > 1024);
        // The value is mantissa * 2^-(52 + D - A + normal); mantissa may have carried to 2^53,
        // which the addition into the exponent field absorbs.
        let exponent = 1022 + (128 - zeros) as u64 - u64::from(self.full_bits) - u64::from(normal);
        f64::from_bits((exponent << 52) + mantissa)
    }

    /// `(n / b, n % b)` for `n < 2^40`, without a hardware division (tens of cycles for a
    /// 64-bit divide on many x86 cores): the floating-point quotient is within `2^40 * 2^-52`
    /// of `n / b`, so truncating it is off by at most one, which the remainder reveals.
    #[inline]
    fn split(&self, n: u64) -> (u64, u64) {
        debug_assert!(n < PASS_SIZE);
        if self.base == 2 {
            return (n >> 1, n & 1);
        }
        // Through i64: n < 2^40, and signed conversions are single instructions on x86-64.
        let mut quotient = ((n as i64) as f64 * self.inverse) as i64 as u64;
        let mut remainder = n.wrapping_sub(quotient * self.base);
        if (remainder as i64) < 0 {
            quotient -= 1;
            remainder = remainder.wrapping_add(self.base);
        } else if remainder >= self.base {
            quotient += 1;
            remainder -= self.base;
        }
        (quotient, remainder)
    }
}

/// The first [`MAX_DIMS`] primes, found once by the sieve of Eratosthenes.
pub(crate) fn bases() -> &'static [Base] {
    static BASES: OnceLock<Vec<Base>> = OnceLock::new();
    BASES.get_or_init(|| {
        primes_below(SIEVE_BOUND)
            .into_iter()
            .take(MAX_DIMS)
            .map(Base::new)
            .collect()
    })
}

/// Validates the dimension of a Halton-type sampler.
pub(crate) fn check_halton_dims(dims: usize) -> Result<()> {
    if dims == 0 || dims > MAX_DIMS {
        return Err(Error::invalid(
            "dims",
            dims,
            format!("1 to {MAX_DIMS} (one prime base per dimension)"),
        ));
    }
    Ok(())
}

/// `x * n / 2^64` rounded down: a hash reduced to `0..n` (bias below `n / 2^64`).
#[inline]
fn below(x: u64, n: u64) -> u64 {
    ((u128::from(x) * u128::from(n)) >> 64) as u64
}

/// `2^exponent` for a normal exponent (`-1022 ..= 1023`).
#[inline]
fn pow2(exponent: i32) -> f64 {
    f64::from_bits(((exponent + 1023) as u64) << 52)
}

/// `num / den` correctly rounded to the nearest `f64` (ties to even), for `num < den < 2^72`.
#[inline]
pub(crate) fn ratio_to_f64(num: u128, den: u128) -> f64 {
    if den <= u128::from(EXACT_F64) {
        // Both are exact doubles, and IEEE division rounds correctly.
        return num as f64 / den as f64;
    }
    if num == 0 {
        return 0.0;
    }
    // Scale so that den <= num * 2^e < 2 den; then num * 2^(e+53) / den lies in [2^53, 2^54):
    // 53 bits of quotient and one rounding bit, with the remainder as the sticky bit.
    let mut e = num.leading_zeros() - den.leading_zeros();
    if num << e < den {
        e += 1;
    }
    let shift = e + 53;
    let scaled = num << shift; // below den * 2^54 < 2^126
    // The quotient estimated in floating point: three roundings of relative size 2^-53 on a
    // value below 2^54, so off by a few units, fixed with the exact remainder. The operands
    // are converted through exact halves (single instructions) and the quotient is scaled by
    // a power of two: no software 128-bit division or conversion.
    let estimate = wide_to_f64(num) / wide_to_f64(den) * pow2(shift as i32);
    // Through i64, whose conversions are single instructions: the values are below 2^55.
    let mut quotient = estimate as i64 as u64;
    let mut remainder = scaled.wrapping_sub(u128::from(quotient) * den) as i128;
    while remainder < 0 {
        quotient -= 1;
        remainder += den as i128;
    }
    while remainder >= den as i128 {
        quotient += 1;
        remainder -= den as i128;
    }
    let mut mantissa = quotient >> 1;
    if quotient & 1 == 1 && (remainder != 0 || mantissa & 1 == 1) {
        mantissa += 1;
    }
    mantissa as i64 as f64 * pow2(1 - shift as i32)
}

/// `x < 2^72` rounded once to an `f64`, from two halves that convert exactly.
#[inline(always)]
fn wide_to_f64(x: u128) -> f64 {
    let high = (x >> 32) as i64; // below 2^40
    let low = (x as u32) as i64;
    high as f64 * pow2(32) + low as f64
}

/// The radical inverse of `index` (below `2^40`) in base `b`, correctly rounded.
pub(crate) fn radical_inverse(digits: &Base, mut index: u64) -> f64 {
    debug_assert!(index < PASS_SIZE);
    let base = digits.base;
    if base == 2 {
        // The bit reversal holds the exact value in its top 40 bits.
        return (index.reverse_bits() >> 11) as f64 * pow2(-53);
    }
    // num / den with den = b^k for the k digits of index: den <= index * b < 2^57.
    let (mut num, mut den) = (0u64, 1u64);
    while index > 0 {
        let (next, digit) = digits.split(index);
        num = num * base + digit;
        den *= base;
        index = next;
    }
    // For indices below 2^40 the value stays far from 1 (the largest, in base 2, is
    // 1 - 2^-40), so the cap never binds; it keeps the [0, 1) guarantee local.
    ratio_to_f64(u128::from(num), u128::from(den)).min(ONE_BELOW)
}

/// Writes the unscrambled radical inverses of `first, first + 1, ...` (all below `2^40`).
///
/// Consecutive indices are counted in base `b` like an odometer over a common denominator
/// `b^w`, so no division by `b` is needed per point. Every value is the correctly rounded
/// quotient of the same rational as in [`radical_inverse`], hence bit-identical to it.
fn fill_plain(digits_of: &Base, first: u64, out: &mut [f64]) {
    let Some(last_offset) = out.len().checked_sub(1) else {
        return;
    };
    let base = digits_of.base;
    let last = first + last_offset as u64;
    let (mut width, mut den) = (1usize, base);
    while den <= last {
        den *= base;
        width += 1;
    }
    if base == 2 || den > EXACT_F64 {
        for (x, index) in out.iter_mut().zip(first..) {
            *x = radical_inverse(digits_of, index);
        }
        return;
    }
    // digits[k] is digit k (least significant first) of the index; it carries weight
    // weights[k] = b^(width - 1 - k) in the numerator over den = b^width.
    let mut digits = [0u64; 64];
    let mut weights = [0u64; 64];
    let mut weight = 1u64;
    for w in weights[..width].iter_mut().rev() {
        *w = weight;
        weight *= base;
    }
    let (mut rest, mut num) = (first, 0u64);
    for (digit, w) in digits.iter_mut().zip(&weights[..width]) {
        *digit = rest % base;
        rest /= base;
        num += *digit * w;
    }
    let den = den as f64;
    for (n, x) in out.iter_mut().enumerate() {
        *x = (num as f64 / den).min(ONE_BELOW);
        if n == last_offset {
            break;
        }
        // Add one: the index stays at most `last < b^width`, so the carry stops below width.
        for (digit, w) in digits.iter_mut().zip(&weights[..width]) {
            if *digit + 1 < base {
                *digit += 1;
                num += w;
                break;
            }
            num -= *digit * w;
            *digit = 0;
        }
    }
}

/// Fisher-Yates decoded from one 64-bit hash: the image of `x` under a permutation of
/// `0..n` (`n <= 12`). The successive choices are the mixed-radix digits of
/// `floor(h * n! / 2^64)`, so each permutation has probability `floor` or `ceil` of
/// `2^64 / n!` over `2^64`.
fn small_permutation(mut h: u64, n: u64, x: u64) -> u64 {
    let mut items = [0u8; SMALL_BASE as usize];
    for (j, item) in items.iter_mut().enumerate() {
        *item = j as u8;
    }
    for j in (1..n as usize).rev() {
        let wide = u128::from(h) * (j as u128 + 1);
        items.swap(j, (wide >> 64) as usize);
        h = wide as u64;
    }
    u64::from(items[x as usize])
}

/// A uniformly random permutation `pi` of the digits `0..b`: `pi(0) = zero`, and
/// `pi(a) = (zero + 1 + rho(a - 1)) mod b` with `rho` selected by `rho_key` (see [`Halton`]).
#[derive(Debug, Clone, Copy)]
struct DigitPermutation {
    base: u64,
    zero: u64,
    rho_key: u64,
    /// The random-access permutation `rho` for bases above [`SMALL_BASE`].
    rho: Option<Permutation>,
}

impl DigitPermutation {
    fn new(base: u64, zero: u64, rho_key: u64) -> Self {
        let rho = (base > SMALL_BASE).then(|| Permutation::new(base - 1, rho_key));
        DigitPermutation {
            base,
            zero,
            rho_key,
            rho,
        }
    }

    /// `pi(digit)`; the same value as [`digit_image`] with the same parts.
    #[inline]
    fn apply(&self, digit: u64) -> u64 {
        if digit == 0 {
            return self.zero;
        }
        let rest = match &self.rho {
            Some(rho) => rho.apply(digit - 1),
            None => small_permutation(self.rho_key, self.base - 1, digit - 1),
        };
        rotate(self.base, self.zero, rest)
    }
}

/// `(zero + 1 + rest) mod b` for `zero < b` and `rest < b - 1`: `pi(a)` from `pi(0)` and
/// `rho(a - 1)`.
#[inline(always)]
fn rotate(base: u64, zero: u64, rest: u64) -> u64 {
    let image = zero + 1 + rest;
    if image >= base { image - base } else { image }
}

/// `pi(digit)` for the permutation with `pi(0) = zero` whose `rho` is keyed by `rho_key()`,
/// which is called (and `rho` built) only for a non-zero digit of a base above 2.
#[inline]
fn digit_image(base: u64, zero: u64, rho_key: impl FnOnce() -> u64, digit: u64) -> u64 {
    if base == 2 {
        // rho permutes the single digit left: pi(1) = 1 - pi(0). Branch-free, as the digits
        // of an index are unpredictable.
        return zero ^ digit;
    }
    match digit {
        0 => zero,
        _ => {
            let key = rho_key();
            let rest = if base <= SMALL_BASE {
                small_permutation(key, base - 1, digit - 1)
            } else {
                Permutation::new(base - 1, key).apply(digit - 1)
            };
            rotate(base, zero, rest)
        }
    }
}

/// Digits `from .. from + count` of the random base-`b` digit stream cut from `word`, as the
/// base-`b` integer they spell (first digit most significant); `from + count <= m`, the digits
/// per word. Digit `r` alone is `floor(frac(word b^r / 2^64) b)`: the mixed-radix expansion of
/// `word / 2^64`, so the `m` digits of a word are uniform within `b^m / 2^64 <= 2^-32`.
#[inline]
fn stream_digits(word: u64, base: u64, from: u32, count: u32) -> u64 {
    below(word.wrapping_mul(base.pow(from)), base.pow(count))
}

/// The random digit permutations of one (pass, dimension). Position `k` (0-based, the most
/// significant output digit first) has `pi_k(0) = t_k`, digit `k` of one random digit stream
/// (a hash per `m` digits), and `rho_k` keyed by a hash of `k`; the permutations of different
/// positions are independent.
struct PermuteColumn {
    base: Base,
    key: u64,
    /// `t_k = pi_k(0)`.
    zeros: [u64; MAX_DEPTH],
    /// `tails[w]`: the numerator (over `b^K`) of the permuted zero digits at positions `w..K`.
    tails: [u128; MAX_DEPTH + 1],
    /// `powers[j] = b^j`.
    powers: [u128; MAX_DEPTH + 1],
}

impl PermuteColumn {
    fn new(base: Base, key: u64) -> Self {
        let mut column = PermuteColumn {
            base,
            key,
            zeros: [0; MAX_DEPTH],
            tails: [0; MAX_DEPTH + 1],
            powers: [1; MAX_DEPTH + 1],
        };
        let (b, m) = (base.base, base.per_word as usize);
        for j in 1..=base.depth {
            column.powers[j] = column.powers[j - 1] * u128::from(b);
        }
        let mut word = 0;
        for k in 0..base.depth {
            if k % m == 0 {
                word = hash_words(key, &[(k / m) as u64]);
            }
            column.zeros[k] = stream_digits(word, b, (k % m) as u32, 1);
        }
        for k in (0..base.depth).rev() {
            column.tails[k] = column.tails[k + 1]
                + u128::from(column.zeros[k]) * column.powers[base.depth - 1 - k];
        }
        column
    }

    /// The key of `rho_k`.
    #[inline]
    fn rho_key(&self, k: usize) -> u64 {
        hash_words(self.key ^ TAG_RHO, &[k as u64])
    }

    /// The permutation of position `k`, with `rho` built.
    fn permutation(&self, k: usize) -> DigitPermutation {
        DigitPermutation::new(self.base.base, self.zeros[k], self.rho_key(k))
    }

    /// The permuted coordinate of `index`.
    fn point(&self, mut index: u64) -> f64 {
        let b = self.base.base;
        let (mut num, mut width) = (0u128, 0usize);
        while index > 0 {
            let (next, digit) = self.base.split(index);
            let zero = self.zeros[width];
            let image = digit_image(b, zero, || self.rho_key(width), digit);
            num = num * u128::from(b) + u128::from(image);
            width += 1;
            index = next;
        }
        let num = num * self.powers[self.base.depth - width] + self.tails[width];
        self.base.ratio(num).min(ONE_BELOW)
    }
}

/// The Owen-scrambled coordinate of `index` in `base`, for the (pass, dimension) `key`.
///
/// The node of digit position `k` (0-based) is identified by `k` and the integer
/// `prefix = index mod b^k` formed by the digits above it in the output. Its permutation has
/// `pi(0) = t`, digit `k` of a random digit stream of `prefix` (a hash of `(prefix, k / m)`
/// per `m` digits, see [`stream_digits`]), and `rho` keyed by a hash of `(prefix, k)`. Nodes
/// with different prefixes draw from different streams, and the nodes of one prefix from
/// different digits of its stream, so all nodes are independent, as nested uniform scrambling
/// requires. Every node has `prefix < b^k`, so the zero digits beyond the last digit of `index`
/// all read the stream of `prefix = index`: the tail costs one hash per `m` digits.
fn owen_coordinate(base: &Base, key: u64, index: u64) -> f64 {
    let (b, m) = (base.base, base.per_word as usize);
    // The digits of the index, least significant (first in the output) first.
    let mut digits = [0u64; MAX_DEPTH];
    let (mut rest, mut width) = (index, 0usize);
    while rest > 0 {
        let (next, digit) = base.split(rest);
        digits[width] = digit;
        width += 1;
        rest = next;
    }
    // The nodes above the last digit, each with its own prefix (so the hashes are independent
    // of each other and pipeline).
    let (mut num, mut prefix, mut weight) = (0u128, 0u64, 1u64);
    // Digit k of a stream is digit `within` (scale = b^within) of its word number k / m.
    let (mut word_number, mut within, mut scale) = (0u64, 0usize, 1u64);
    for (k, &digit) in digits[..width].iter().enumerate() {
        // prefix <= index < 2^40, k < 64: (prefix << 6) | k is unique per node.
        let node = (prefix << 6) | k as u64;
        let word = hash_words(key, &[(prefix << 6) | word_number]);
        let zero = below(word.wrapping_mul(scale), b);
        let image = digit_image(b, zero, || hash_words(key ^ TAG_RHO, &[node]), digit);
        num = num * u128::from(b) + u128::from(image);
        prefix += digit * weight;
        weight *= b;
        within += 1;
        scale *= b;
        if within == m {
            (word_number, within, scale) = (word_number + 1, 0, 1);
        }
    }
    // The tail of zero digits: whole runs of the stream of `index`.
    let mut k = width;
    while k < base.depth {
        let count = (m - within).min(base.depth - k);
        let word = hash_words(key, &[(index << 6) | word_number]);
        let run = stream_digits(word, b, within as u32, count as u32);
        num = num * u128::from(b.pow(count as u32)) + u128::from(run);
        k += count;
        (word_number, within) = (word_number + 1, 0);
    }
    base.ratio(num).min(ONE_BELOW)
}

/// The key of one (pass, dimension) randomization of a Halton-type sampler.
pub(crate) fn column_key(seed: u64, tag: u64, pass: u64, dim: usize) -> u64 {
    hash_words(seed, &[tag, pass, dim as u64])
}

/// Coordinate for local index `index` (below `2^40`) in `base` under `scramble`.
pub(crate) fn coordinate(scramble: Scramble, base: &Base, key: u64, index: u64) -> f64 {
    match scramble {
        Scramble::Permute => PermuteColumn::new(*base, key).point(index),
        Scramble::Owen => owen_coordinate(base, key, index),
        _ => radical_inverse(base, index),
    }
}

/// Scratch space reused over the columns of one block.
#[derive(Default)]
pub(crate) struct Scratch {
    /// The digit images a block meets, one window of digits per position.
    memo: Vec<u32>,
    /// One digit permutation per position that the block's indices use.
    permutations: Vec<DigitPermutation>,
    /// The numerator parts of the lowest digit positions, by their value.
    lows: Vec<u128>,
    /// Buffers of the Owen kernel.
    owen: owen_block::OwenScratch,
}

/// Writes the coordinates of local indices `first, first + 1, ...` (one pass, all below
/// `2^40`), bit-identical to [`coordinate`].
pub(crate) fn fill_column(
    scramble: Scramble,
    base: &Base,
    key: u64,
    first: u64,
    out: &mut [f64],
    scratch: &mut Scratch,
) {
    match scramble {
        Scramble::Permute => fill_permuted(base, key, first, out, scratch),
        Scramble::Owen => owen_block::fill_owen(base, key, first, out, &mut scratch.owen),
        _ => fill_plain(base, first, out),
    }
}

/// The images of the digits `from, from + 1, ..` (modulo `b`, one per slot of `images`) under
/// a digit permutation with a random-access `rho`, sixteen at a time; compiled for each
/// instruction set by [`dispatch`].
struct DigitImages<'a> {
    rho: &'a Permutation,
    base: u64,
    zero: u64,
    from: u64,
    images: &'a mut [u32],
}

impl Kernel for DigitImages<'_> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let DigitImages {
            rho,
            base,
            zero,
            from,
            images,
        } = self;
        for (chunk, out) in images.chunks_mut(LANES).enumerate() {
            let digits: [u64; LANES] = std::array::from_fn(|j| {
                let digit = from + (chunk * LANES + j) as u64;
                // from < b and at most b slots: one wrap at most (lanes past the end are 0).
                match digit {
                    _ if j >= out.len() => 0,
                    _ if digit >= base => digit - base,
                    _ => digit,
                }
            });
            // pi(0) = zero, pi(a) = rotate(rho(a - 1)) for a >= 1; digit 0 takes the in-range
            // argument 0, whose image is unused.
            let mut lanes = digits.map(|digit| digit.saturating_sub(1));
            rho.apply_lanes(&mut lanes);
            for ((image, &digit), &rest) in out.iter_mut().zip(&digits).zip(&lanes) {
                // Digit images are below b < 2^17.
                *image = match digit {
                    0 => zero,
                    _ => rotate(base, zero, rest),
                } as u32;
            }
        }
    }
}

/// Block kernel for [`Scramble::Permute`]: the permutations of the digit positions in use are built
/// once, the images of the digits the block meets found up front, and the indices counted like an
/// odometer, updating the numerator `sum_k pi_k(a_k) b^(K-1-k)` digit by digit (the lowest
/// positions through a table of their combined parts). The numerator is the same integer as in
/// [`PermuteColumn::point`] (zero digits map to `pi_k(0)` either way), so the values are
/// bit-identical.
fn fill_permuted(base: &Base, key: u64, first: u64, out: &mut [f64], scratch: &mut Scratch) {
    let Some(last_offset) = out.len().checked_sub(1) else {
        return;
    };
    let column = PermuteColumn::new(*base, key);
    let b = base.base;
    let last = first + last_offset as u64;
    let (mut rest, mut width) = (last, 0usize);
    while rest > 0 {
        rest /= b;
        width += 1;
    }
    scratch.permutations.clear();
    scratch
        .permutations
        .extend((0..width).map(|k| column.permutation(k)));
    // The digits the block's indices take at position k are a window of consecutive ones
    // (cyclically, at most b and at most the block length): their images are found once, in
    // lanes (one permutation, many arguments) for the random-access permutations.
    let mut windows = [(0usize, 0u64); MAX_DEPTH]; // (offset in memo, first digit)
    scratch.memo.clear();
    let mut power = 1u64; // b^k
    for (k, permutation) in scratch.permutations.iter().enumerate() {
        let low = first / power;
        let (from, count) = (low % b, (last / power - low + 1).min(b));
        let at = scratch.memo.len();
        windows[k] = (at, from);
        scratch.memo.resize(at + count as usize, 0);
        let images = &mut scratch.memo[at..];
        match &permutation.rho {
            Some(rho) => dispatch(DigitImages {
                rho,
                base: b,
                zero: permutation.zero,
                from,
                images,
            }),
            None => {
                for (image, digit) in images.iter_mut().zip(from..) {
                    let digit = if digit >= b { digit - b } else { digit };
                    // Digit images are below b < 2^17.
                    *image = permutation.apply(digit) as u32;
                }
            }
        }
        power = power.saturating_mul(b);
    }
    let Scratch { memo, lows, .. } = scratch;
    let image = |k: usize, digit: u64| -> u64 {
        let (at, from) = windows[k];
        let j = if digit >= from {
            digit - from
        } else {
            digit + b - from
        };
        u64::from(memo[at + j as usize])
    };
    // digits[k]: digit k of the index (least significant first); images[k] = pi_k(digits[k]),
    // which carries weight b^(K-1-k) in the numerator over b^K.
    let mut digits = [0u64; MAX_DEPTH];
    let mut images = [0u64; MAX_DEPTH];
    let weights = &column.powers[base.depth - width..base.depth];
    let mut num = column.tails[width];
    let mut rest = first;
    for k in 0..width {
        digits[k] = rest % b;
        rest /= b;
        images[k] = image(k, digits[k]);
        num += u128::from(images[k]) * weights[width - 1 - k];
    }
    if width == 0 {
        // The block is index 0 alone.
        out[0] = base.ratio(num).min(ONE_BELOW);
        return;
    }
    // The lowest `low` positions form a number r < b^low that runs through its values before
    // a carry reaches the positions above, whose part of the numerator is then shared. With
    // b^low <= 256 small next to the block, the parts of all r are tabulated (built position
    // by position), else (low = 1) found digit by digit.
    let mut low = 1;
    while low < width && powers_u64(b, low + 1) <= 256.min(out.len() as u64) {
        low += 1;
    }
    let size = powers_u64(b, low);
    let tabulate = size <= out.len() as u64;
    lows.clear();
    if tabulate {
        lows.push(0);
        for k in 0..low {
            let span = lows.len();
            for digit in 1..b {
                let part = u128::from(image(k, digit)) * weights[width - 1 - k];
                for at in 0..span {
                    let value = lows[at] + part;
                    lows.push(value);
                }
            }
            // Digit 0 of position k: add pi_k(0)'s part to the existing entries.
            let zero = u128::from(image(k, 0)) * weights[width - 1 - k];
            for value in &mut lows[..span] {
                *value += zero;
            }
        }
    }
    // The part of positions below `low` of the index with these digits.
    let mut r = 0u64;
    let mut high = num;
    for k in (0..low).rev() {
        r = r * b + digits[k];
        high -= u128::from(images[k]) * weights[width - 1 - k];
    }
    let w0 = weights[width - 1];
    let mut done = 0;
    loop {
        let run = ((size - r) as usize).min(out.len() - done);
        let outs = &mut out[done..done + run];
        if tabulate {
            for (x, part) in outs.iter_mut().zip(&lows[r as usize..]) {
                *x = base.ratio(high + part).min(ONE_BELOW);
            }
        } else {
            for (x, digit) in outs.iter_mut().zip(r..) {
                *x = base
                    .ratio(high + u128::from(image(0, digit)) * w0)
                    .min(ONE_BELOW);
            }
        }
        done += run;
        if done == out.len() {
            break;
        }
        // Positions below `low` wrap to 0 and the carry adds one above; the index stays below
        // b^width, so the carry stops below width.
        r = 0;
        for k in low..width {
            let weight = weights[width - 1 - k];
            let (digit, carry) = if digits[k] + 1 < b {
                (digits[k] + 1, false)
            } else {
                (0, true)
            };
            let new = image(k, digit);
            high = high + u128::from(new) * weight - u128::from(images[k]) * weight;
            (digits[k], images[k]) = (digit, new);
            if !carry {
                break;
            }
        }
    }
}

/// `b^j` (small here).
fn powers_u64(b: u64, j: usize) -> u64 {
    b.saturating_pow(j as u32)
}

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
/// * [`Scramble::Owen`]: nested uniform scrambling in base `b` (Owen 1995): the permutation
///   applied to digit `k` is chosen afresh for every value of the higher digits of the output,
///   that is, for every prefix `(a_1, .., a_{k-1})`, by hashing the prefix with the pass and the
///   dimension (hash-based, like pbrt-v4's Owen-scrambled radical inverse).
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
/// larger bases.
///
/// **Cost.** Measured on blocks of 4096 points (one x86-64 core with AVX-512, the first 10^6
/// points): unscrambled blocks cost about 2 ns per value (an odometer over the digits, no
/// division). `Permute` blocks find the images of the digits each position meets once per block,
/// sixteen at a time, and round each value by one multiplication: about 5 ns per value at d = 4 or
/// 32 (and 40 ns at d = 10,000, where bases above the block length give every index a lowest digit
/// of its own to permute). `Owen` blocks memoize the digit positions that the block's indices
/// share; every deeper digit has a node of its own per index, so it costs hashes and, in bases
/// above 13, a keyed 40-round permutation (about 20 ns, run in lanes of 32): about 40 ns per value
/// at d = 4, 60 ns at d = 32 and 45 ns at d = 10,000, growing with the digits an index has beyond
/// those of the block length. [`point`](Sampler::point) recomputes everything per call (about a
/// microsecond per `Owen` value in large bases): use [`fill`](Sampler::fill) for throughput.
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
    fn name(&self) -> &'static str {
        "halton"
    }

    fn dims(&self) -> usize {
        self.dims
    }

    fn passes(&self) -> PassKind {
        PassKind::Extensible { max: PASS_SIZE }
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
            // Split the block into runs of indices that share a pass.
            let mut offset = 0usize;
            while offset < column.len() {
                let index = start + offset as u64;
                let (pass, local) = (index >> PASS_BITS, index & (PASS_SIZE - 1));
                let run = ((PASS_SIZE - local).min((column.len() - offset) as u64)) as usize;
                let key = column_key(self.seed, TAG_HALTON, pass, dim);
                let out = &mut column[offset..offset + run];
                fill_column(self.scramble, base, key, local, out, &mut scratch);
                offset += run;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash::mix64;

    #[test]
    fn bases_are_the_first_ten_thousand_primes() {
        let b = bases();
        assert_eq!(b.len(), MAX_DIMS);
        let first: Vec<u64> = b[..10].iter().map(|p| p.base).collect();
        assert_eq!(first, [2, 3, 5, 7, 11, 13, 17, 19, 23, 29]);
        assert_eq!(b[999].base, 7919);
        assert_eq!(b[MAX_DIMS - 1].base, 104_729);
        // Depth: least K with b^K >= 2^53.
        assert_eq!((b[0].depth, b[1].depth, b[2].depth), (53, 34, 23));
        for p in b {
            assert!(p.full >= 1 << 53 && p.full / u128::from(p.base) < 1 << 53);
            assert!(p.full < 1 << 71);
        }
    }

    /// Whether `x` is the double nearest `num / den` (ties either way), checked in integers.
    fn is_nearest(x: f64, num: u128, den: u128) -> bool {
        if num == 0 {
            return x == 0.0;
        }
        // x = m * 2^-s with a 53-bit m; |x - num/den| <= 2^-s / 2  <=>  2 |m den - num 2^s| <= den.
        let bits = x.to_bits();
        let exponent = ((bits >> 52) & 0x7ff) as i32;
        let m = u128::from((bits & ((1 << 52) - 1)) | (1 << 52));
        let s = (1075 - exponent) as u32;
        let (a, c) = (m * den, num << s);
        2 * a.abs_diff(c) <= den
    }

    #[test]
    fn ratio_to_f64_rounds_correctly() {
        let mut h = 1u64;
        for case in 0..20_000u64 {
            h = mix64(h.wrapping_add(case));
            let den_bits = 54 + (h % 17) as u32; // 2^53 < den < 2^71
            let den =
                (u128::from(mix64(h ^ 1)) << 64 | u128::from(mix64(h ^ 2))) >> (128 - den_bits);
            let den = den | (1 << (den_bits - 1));
            let num = match case % 3 {
                0 => (u128::from(mix64(h ^ 3)) << 64 | u128::from(mix64(h ^ 4))) % den,
                1 => u128::from(mix64(h ^ 5) >> (case % 64)) % den,
                _ => den - 1 - u128::from(mix64(h ^ 6) % 1000).min(den - 1),
            };
            let x = ratio_to_f64(num, den);
            assert!(is_nearest(x, num, den), "{num} / {den} gave {x:e}");
        }
        // Exact halfway cases round to even.
        // (2^53 + 1) / 2^61 is 2^-8 plus half an ulp: down to the even 2^-8; (2^53 + 3) / 2^61
        // is an odd mantissa plus half an ulp: up.
        let den = 1u128 << 61;
        assert_eq!(ratio_to_f64((1 << 53) + 1, den), 2f64.powi(-8));
        assert_eq!(
            ratio_to_f64((1 << 53) + 3, den),
            2f64.powi(-8) + 2f64.powi(-59)
        );
        assert_eq!(ratio_to_f64(3, 4), 0.75);
        assert_eq!(ratio_to_f64(0, den), 0.0);
    }

    #[test]
    fn ratio_to_f64_is_nearest_near_rounding_boundaries() {
        let mut h = 11u64;
        let mut next = || {
            h = mix64(h.wrapping_add(0x9e37));
            h
        };
        let mut dens: Vec<u128> = bases().iter().step_by(97).map(|b| b.full).collect();
        dens.extend([(1u128 << 53) + 1, 1 << 60, 1 << 71, (1 << 72) - 1]);
        for _ in 0..40 {
            let bits = 54 + (next() % 18) as u32;
            let den = (u128::from(next()) << 64 | u128::from(next())) >> (128 - bits);
            dens.push(den | 1 << (bits - 1));
        }
        for &den in &dens {
            for case in 0..3000u32 {
                let r = next();
                let num = match case % 6 {
                    0 => (u128::from(r) << 64 | u128::from(next())) % den,
                    1 => u128::from(r >> (case % 64)) % den,
                    2 => den - 1 - u128::from(r % 1000).min(den - 1),
                    // Close to a rounding boundary: num / den near (m + 1/2) 2^-s, and near
                    // powers of two, where the spacing of doubles changes.
                    3 | 4 => {
                        let s = 54 + (r % 60) as u32;
                        let m = if case % 6 == 3 {
                            u128::from(next() >> 11 | 1 << 52)
                        } else {
                            1 << 53
                        };
                        let target = ((2 * m + 1) * den) >> (s + 1);
                        (target + u128::from(r >> 62)).saturating_sub(2) % den
                    }
                    _ => u128::from(r % 64) % den,
                };
                let x = ratio_to_f64(num, den);
                assert!(is_nearest(x, num, den), "{num} / {den} gave {x:e}");
            }
        }
        // Exact halfway cases, den a power of two above 2^53: num / den = (m + 1/2) 2^-53
        // rounds to the even neighbour (m = 2^53 - 1 rounds up to 1.0).
        for s in 54..72u32 {
            for m in [1u128 << 52, (1 << 53) - 1, 0x1a_bcde_f012_3457] {
                let den = 1u128 << s;
                let num = (2 * m + 1) << (s - 54);
                let even = if m % 2 == 0 { m } else { m + 1 };
                assert_eq!(
                    ratio_to_f64(num, den),
                    even as f64 * 2f64.powi(-53),
                    "{m} {s}"
                );
            }
        }
    }

    #[test]
    fn reciprocal_rounding_equals_the_exact_division() {
        let mut h = 17u64;
        let mut next = || {
            h = mix64(h.wrapping_add(0x51ed));
            h
        };
        let (mut slow, mut total) = (0usize, 0usize);
        for base in bases().iter().step_by(13).chain(&bases()[..40]) {
            let full = base.full;
            for case in 0..2000u32 {
                let r = next();
                let num = match case % 5 {
                    0 => (u128::from(r) << 64 | u128::from(next())) % full,
                    1 => u128::from(r >> (case % 64)) % full,
                    2 => full - 1 - u128::from(r % 1000).min(full - 1),
                    // Near a halfway point between doubles: num / b^K = (m + 1/2) 2^-s.
                    _ => {
                        let s = 54 + (r % 40) as u32;
                        let m = u128::from(next() >> 11 | 1 << 52);
                        let target = ((2 * m + 1) * full) >> (s + 1);
                        (target + u128::from(r >> 61)).saturating_sub(4) % full
                    }
                };
                let exact = ratio_to_f64(num, full);
                assert_eq!(base.ratio(num).to_bits(), exact.to_bits(), "{num} / {full}");
                total += 1;
                if num == 0 {
                    continue;
                }
                let x = num << num.leading_zeros() >> 64;
                let high = ((x * u128::from(base.reciprocal)) >> 64) as u64;
                let high = high << high.leading_zeros();
                slow += usize::from((1014..=1024).contains(&(high & 0x7ff)));
            }
        }
        // The near-halfway cases are two in five; the others take the fast path but for
        // about 11 in 2048.
        assert!(slow < total / 2, "{slow} of {total} on the slow path");
    }

    #[test]
    fn radical_inverse_is_exact_and_odometer_matches_it() {
        let (two, three) = (Base::new(2), Base::new(3));
        assert_eq!(radical_inverse(&two, 0), 0.0);
        assert_eq!(radical_inverse(&two, 6), 0.375);
        assert_eq!(radical_inverse(&three, 5), 7.0 / 9.0);
        assert_eq!(radical_inverse(&two, PASS_SIZE - 1), 1.0 - 0.5f64.powi(40));
        for b in [2u64, 3, 5, 7919, 104_729] {
            let base = Base::new(b);
            for first in [0u64, 1, 7, b - 1, b * b - 3, PASS_SIZE - 40] {
                let mut out = [0.0; 37];
                fill_plain(&base, first, &mut out);
                for (x, index) in out.iter().zip(first..) {
                    assert_eq!(x.to_bits(), radical_inverse(&base, index).to_bits());
                }
            }
        }
    }

    #[test]
    fn split_matches_integer_division() {
        let mut h = 5u64;
        for base in bases().iter().step_by(37).chain(bases().last()) {
            let b = base.base;
            for k in 0..2000u64 {
                h = mix64(h ^ k);
                // Around multiples of b (where the estimate may be off by one), and anywhere.
                let near = ((h >> 24) / b * b).saturating_add(k % 3).saturating_sub(1);
                for n in [near, h >> 24, PASS_SIZE - 1 - k, k] {
                    assert_eq!(base.split(n), (n / b, n % b), "{n} / {b}");
                }
            }
        }
    }

    #[test]
    fn small_permutations_are_uniform() {
        // All 24 permutations of 0..4 from 48,000 keys: chi-square on 23 degrees of freedom,
        // bound 0.99999 quantile 63.9 (scipy.stats.chi2.isf(1e-5, 23)).
        let mut counts = [0f64; 256];
        let draws = 48_000u64;
        for key in 0..draws {
            let h = mix64(key);
            let code: usize = (0..4)
                .map(|x| (small_permutation(h, 4, x) as usize) << (2 * x))
                .sum();
            counts[code] += 1.0;
        }
        let expected = draws as f64 / 24.0;
        let used = counts.iter().filter(|&&c| c > 0.0).count();
        assert_eq!(used, 24);
        let chi2: f64 = counts
            .iter()
            .filter(|&&c| c > 0.0)
            .map(|c| (c - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 63.9, "chi2 = {chi2}");
    }

    #[test]
    fn digit_permutations_are_permutations_with_uniform_images() {
        let parts = |base: u64, key: u64| (below(mix64(key), base), mix64(key ^ 7));
        for base in [2u64, 3, 5, 13, 17, 31, 7919] {
            for key in 0..5u64 {
                let (zero, rho_key) = parts(base, key);
                let p = DigitPermutation::new(base, zero, rho_key);
                let mut seen = vec![false; base as usize];
                for a in 0..base {
                    let image = p.apply(a);
                    assert_eq!(image, digit_image(base, zero, || rho_key, a));
                    assert!(!seen[image as usize]);
                    seen[image as usize] = true;
                }
            }
        }
        // Where digit 3 of base 7 lands, over 14,000 keys: 6 degrees of freedom, bound
        // scipy.stats.chi2.isf(1e-5, 6) = 33.1; the same for base 17 (16 df: 52.0).
        for (base, bound) in [(7u64, 33.1), (17, 52.0)] {
            let draws = 14_000u64;
            let mut counts = vec![0f64; base as usize];
            for key in 0..draws {
                let (zero, rho_key) = parts(base, key ^ 99);
                counts[digit_image(base, zero, || rho_key, 3) as usize] += 1.0;
            }
            let expected = draws as f64 / base as f64;
            let chi2: f64 = counts
                .iter()
                .map(|c| (c - expected).powi(2) / expected)
                .sum();
            assert!(chi2 < bound, "base {base}: chi2 = {chi2}");
        }
    }

    #[test]
    fn stream_digits_in_runs_equal_digits_one_by_one() {
        for b in [2u64, 3, 13, 101, 65_537, 104_729] {
            let m = Base::new(b).per_word;
            for key in 0..50u64 {
                let word = mix64(key);
                let mut whole = 0u64;
                for r in 0..m {
                    whole = whole * b + stream_digits(word, b, r, 1);
                }
                assert_eq!(whole, stream_digits(word, b, 0, m));
                let tail = stream_digits(word, b, m / 2, m - m / 2);
                assert_eq!(tail, whole % b.pow(m - m / 2));
            }
        }
    }
}
