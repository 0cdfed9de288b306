//! Unscrambled radical inverses: the digit-reversed index over `b^k`, rounded once, point
//! by point and (an odometer over a common denominator) a block at a time.

use super::PASS_SIZE;
use super::base::Base;
use super::rounding::{EXACT_F64, pow2, ratio_to_f64};
use crate::float::ONE_BELOW;

/// The radical inverse of `index` (below `2^40`) in base `b`, correctly rounded.
pub(super) fn radical_inverse(digits: &Base, mut index: u64) -> f64 {
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
pub(super) fn fill_plain(digits_of: &Base, first: u64, out: &mut [f64]) {
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
