//! The prime bases of the radical inverses: each base with its scrambling depth and the
//! constants that let the kernels divide by it and round by it without a hardware division.

use super::rounding::{EXACT_F64, pow2, ratio_to_f64};
use super::{MAX_DIMS, PASS_SIZE};
use crate::sampler::number_theory::primes_below;
use std::sync::OnceLock;

/// The 10,000th prime is 104,729: sieving below this bound finds all the bases.
const SIEVE_BOUND: usize = 104_730;
/// The most digit positions a scramble permutes (base 2: `2^53`).
pub(super) const MAX_DEPTH: usize = 53;

/// A prime base with its scrambling depth.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Base {
    /// The prime `b`.
    pub(crate) base: u64,
    /// Digit positions a scramble permutes: the least `K` with `b^K >= 2^53`.
    pub(super) depth: usize,
    /// `b^K`, below `2^71`.
    pub(super) full: u128,
    /// Random digits cut from one 64-bit hash: the largest `m` with `b^m <= 2^32`.
    pub(super) per_word: u32,
    /// `1 / b` rounded, for [`Base::split`].
    pub(super) inverse: f64,
    /// `floor(2^(63 + D) / b^K)` with `D` the bit length of `b^K`, for [`Base::ratio`].
    pub(super) reciprocal: u64,
    /// `D`, the bit length of `b^K`.
    pub(super) full_bits: u32,
}

impl Base {
    pub(super) fn new(base: u64) -> Self {
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
    pub(super) fn ratio(&self, num: u128) -> f64 {
        debug_assert!(num < self.full);
        if self.base == 2 {
            // b^K = 2^53: exact.
            return num as u64 as i64 as f64 * pow2(-53);
        }
        if num == 0 {
            return 0.0;
        }
        let zeros = num.leading_zeros(); // A = 128 - zeros, at most 72
        self.round_top(((num << zeros) >> 64) as u64, 128 - zeros, num)
    }

    /// [`Base::ratio`] of a numerator below `2^64`, in 64-bit integers: `num` below 2^64 is
    /// its own top 64 bits, so the steps and the result are those of `ratio`.
    #[inline(always)]
    pub(super) fn ratio_narrow(&self, num: u64) -> f64 {
        debug_assert!(u128::from(num) < self.full);
        if self.base == 2 {
            return num as i64 as f64 * pow2(-53);
        }
        if num == 0 {
            return 0.0;
        }
        let zeros = num.leading_zeros();
        self.round_top(num << zeros, 64 - zeros, u128::from(num))
    }

    /// The rounding of [`Base::ratio`] from the top 64 bits `top` of the numerator `num`
    /// (truncated, leading bit set), whose bit length is `bits`.
    #[inline(always)]
    fn round_top(&self, top: u64, bits: u32, num: u128) -> f64 {
        let high = ((u128::from(top) * u128::from(self.reciprocal)) >> 64) as u64;
        // top >= 2^63 and the reciprocal > 2^63 (b^K is not a power of two): high >= 2^62, so
        // its leading zeros are 0 or 1, read from the top bit (no bit scan).
        let normal = 1 - (high >> 63) as u32;
        let high = high << normal;
        let low = high & 0x7ff;
        if (1024 - 10..=1024).contains(&low) || high >= u64::MAX - 32 {
            return ratio_to_f64(num, self.full);
        }
        // Round half up is safe here: the value is not within the error of the halfway point.
        let mantissa = (high >> 11) + u64::from(low > 1024);
        // The value is mantissa * 2^-(52 + D - A + normal); mantissa may have carried to 2^53,
        // which the addition into the exponent field absorbs.
        let exponent = 1022 + u64::from(bits) - u64::from(self.full_bits) - u64::from(normal);
        f64::from_bits((exponent << 52) + mantissa)
    }

    /// `(n / b, n % b)` for `n < 2^40`, without a hardware division (tens of cycles for a
    /// 64-bit divide on many x86 cores): the floating-point quotient is within `2^40 * 2^-52`
    /// of `n / b`, so truncating it is off by at most one, which the remainder reveals.
    #[inline]
    pub(super) fn split(&self, n: u64) -> (u64, u64) {
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
    fn narrow_ratio_equals_the_wide_one() {
        let mut h = 23u64;
        for base in bases()
            .iter()
            .take_while(|b| b.full <= u128::from(u64::MAX))
        {
            let full = base.full as u64;
            for case in 0..300u64 {
                h = mix64(h ^ case);
                for num in [h % full, full - 1 - case.min(full - 1), case % full] {
                    assert_eq!(
                        base.ratio_narrow(num).to_bits(),
                        base.ratio(u128::from(num)).to_bits(),
                        "{num} / {full}"
                    );
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
}
