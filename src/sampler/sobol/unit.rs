//! Output precisions: how a Sobol' word becomes a coordinate. An unscrambled word is the
//! 32-bit fraction `word * 2^-32`; a randomized coordinate has 53 digits, the scrambled word
//! and 21 more. Each conversion is exact in `f64` and rounded once in `f32`.

use crate::points_f32::F32_BELOW_ONE;

/// Digits of a randomized coordinate (the precision of an `f64` in `[0, 1)`), and how many of
/// them lie below the sequence's 32.
pub(super) const FULL_BITS: u32 = 53;

pub(super) const EXTRA_BITS: u32 = FULL_BITS - 32;

/// An unscrambled word as a double: exactly `word * 2^-32`.
#[inline(always)]
pub(super) fn unscrambled_f64(word: u32) -> f64 {
    f64::from(word) * (1.0 / 4_294_967_296.0)
}

/// A 53-digit randomized fraction (`bits < 2^53`) as a double: exact, on the `2^-53` grid,
/// below 1.
#[inline(always)]
pub(super) fn wide_f64(bits: u64) -> f64 {
    let tail = (bits & ((1 << EXTRA_BITS) - 1)) as u32;
    join_f64((bits >> EXTRA_BITS) as u32, tail)
}

/// `(word * 2^21 + tail) * 2^-53` for `tail < 2^21`, as a sum of two exactly converted parts:
/// the sum is a multiple of `2^-53` below 1, so it is exact, and only 32-bit integers are
/// converted (which vectorizes, unlike 64-bit conversion before AVX-512).
#[inline(always)]
pub(super) fn join_f64(word: u32, tail: u32) -> f64 {
    f64::from(word) * (1.0 / 4_294_967_296.0) + f64::from(tail) * (1.0 / 9_007_199_254_740_992.0)
}

/// An output precision: how a 32-bit word, a 53-bit fraction or a word with its 21 tail
/// digits becomes a coordinate. Each is the exact value, rounded once (for `f32`).
pub(super) trait Unit: Copy + Default {
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
