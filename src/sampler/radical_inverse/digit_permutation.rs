//! Random digit permutations of a base and the random digit streams they are drawn from.
//!
//! A uniformly random permutation `pi` of the digits `0..b` is drawn as `pi(0) = t` with `t`
//! uniform and `pi(a) = (t + 1 + rho(a - 1)) mod b` for `a >= 1`, with `rho` a uniformly random
//! permutation of `0..b-1` independent of `t`; the zero digits, the bulk of a coordinate's
//! tail, need only `t` (see [`Halton`](crate::sampler::Halton) for the whole construction).

use crate::sampler::permutation::{Permutation, below_narrow};

/// Digit permutations of bases up to this are decoded from one hash by Fisher-Yates.
pub(super) const SMALL_BASE: u64 = 13;
/// Hash tag of the keys of the permutations `rho`.
pub(super) const TAG_RHO: u64 = 0x0072_686f;

/// `x * n / 2^64` rounded down: a hash reduced to `0..n` (bias below `n / 2^64`).
#[inline]
pub(super) fn below(x: u64, n: u64) -> u64 {
    ((u128::from(x) * u128::from(n)) >> 64) as u64
}

/// Fisher-Yates decoded from one 64-bit hash: the image of `x` under a permutation of
/// `0..n` (`n <= 12`). The successive choices are the mixed-radix digits of
/// `floor(h * n! / 2^64)`, so each permutation has probability `floor` or `ceil` of
/// `2^64 / n!` over `2^64`.
pub(super) fn small_permutation(mut h: u64, n: u64, x: u64) -> u64 {
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
/// `pi(a) = (zero + 1 + rho(a - 1)) mod b` with `rho` selected by `rho_key` (see
/// [`Halton`](crate::sampler::Halton)).
#[derive(Debug, Clone, Copy)]
pub(super) struct DigitPermutation {
    base: u64,
    pub(super) zero: u64,
    rho_key: u64,
    /// The random-access permutation `rho` for bases above [`SMALL_BASE`].
    pub(super) rho: Option<Permutation>,
}

impl DigitPermutation {
    pub(super) fn new(base: u64, zero: u64, rho_key: u64) -> Self {
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
    pub(super) fn apply(&self, digit: u64) -> u64 {
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
pub(super) fn rotate(base: u64, zero: u64, rest: u64) -> u64 {
    let image = zero + 1 + rest;
    if image >= base { image - base } else { image }
}

/// `pi(digit)` for the permutation with `pi(0) = zero` whose `rho` is keyed by `rho_key()`,
/// which is called (and `rho` built) only for a non-zero digit of a base above 2.
#[inline]
pub(super) fn digit_image(base: u64, zero: u64, rho_key: impl FnOnce() -> u64, digit: u64) -> u64 {
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

/// `pi(digit)` for the node permutation of [`Scramble::Owen`](crate::sampler::Scramble::Owen):
/// the uniformly random permutation of [`digit_image`] in bases up to [`SMALL_BASE`], and above
/// them the random affine map `pi(a) = (alpha a + zero) mod b` with `alpha = 1 + (key mod
/// (b - 1))` read from `node_key()` (called for a non-zero digit only). The affine maps of a
/// prime base are sharply 2-transitive: two distinct digits go to a uniformly random pair of
/// distinct digits, as under a uniform permutation, and the variance of a scrambled estimate
/// depends on the points two at a time only (see [`Halton`](crate::sampler::Halton)).
#[inline]
pub(super) fn owen_digit_image(
    base: u64,
    zero: u64,
    node_key: impl FnOnce() -> u64,
    digit: u64,
) -> u64 {
    if base <= SMALL_BASE || digit == 0 {
        return digit_image(base, zero, node_key, digit);
    }
    (affine_slope(node_key(), base) * digit + zero) % base
}

/// The slope `alpha` in `1..b` of an affine node permutation in base `b`, from its key (by
/// the vectorizable form of [`below`], equal to it for `b <= 2^32`).
#[inline(always)]
pub(super) fn affine_slope(key: u64, base: u64) -> u64 {
    1 + below_narrow(key, base - 1)
}

/// Digits `from .. from + count` of the random base-`b` digit stream cut from `word`, as the
/// base-`b` integer they spell (first digit most significant); `from + count <= m`, the digits
/// per word. Digit `r` alone is `floor(frac(word b^r / 2^64) b)`: the mixed-radix expansion of
/// `word / 2^64`, so the `m` digits of a word are uniform within `b^m / 2^64 <= 2^-32`.
#[inline]
pub(super) fn stream_digits(word: u64, base: u64, from: u32, count: u32) -> u64 {
    below(word.wrapping_mul(base.pow(from)), base.pow(count))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hash::mix64;
    use crate::sampler::radical_inverse::base::Base;

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
