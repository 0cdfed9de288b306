//! Correct rounding of the exact rationals the radical inverses are: `num / den` for wide
//! integers, to the nearest `f64` with ties to even, without software 128-bit division.

/// Every integer up to this is exact in an `f64`.
pub(super) const EXACT_F64: u64 = 1 << 53;

/// `2^exponent` for a normal exponent (`-1022 ..= 1023`).
#[inline]
pub(super) fn pow2(exponent: i32) -> f64 {
    f64::from_bits(((exponent + 1023) as u64) << 52)
}

/// `num / den` correctly rounded to the nearest `f64` (ties to even), for `num < den < 2^72`.
#[inline]
pub(super) fn ratio_to_f64(num: u128, den: u128) -> f64 {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash::mix64;
    use crate::sampler::radical_inverse::bases;

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
}
