//! Hash-based Owen scrambling in base 2: the nested uniform scramble of a 32-bit word.
//!
//! Owen's (1995) nested uniform scramble flips digit `k` of a coordinate (counted from the most
//! significant) by a random bit chosen independently for every value of the digits above it.
//! It keeps every `(t, m, s)`-net a `(t, m, s)`-net, makes each point uniform on the cube, and
//! for smooth integrands gives a variance of `O(N^-3 (log N)^(s-1))`. Storing the random bits
//! takes a tree of size `N`; Laine & Karras (2011, "Stratified sampling for stochastic
//! transparency") observed that any map under which each output bit depends only on the same
//! input bit and the input bits *above* it is a nested scramble, and that such maps are built
//! from operations that only carry information upward in the bit-reversed word: adding a
//! constant, multiplying by an odd constant, and `v ^= v * even`. Burley (2020, "Practical
//! hash-based Owen scrambling") made the idea a practical scramble and also applied it to the
//! sample index to decorrelate differently seeded sequences.
//!
//! This module's scramble is written from that principle (not copied from either paper): on
//! the bit-reversed word it runs three rounds of `add, v ^= v * even, multiply by odd` (the
//! last round with a second `v ^= v * even` instead of the multiply), with every constant drawn
//! from a hash of the seed, so that different seeds give unrelated scrambles rather than
//! shifted copies of one. Each operation is a bijection of `u32` whose bit `b` is the input bit
//! `b` XOR a function of the lower bits, so the composition is too: the scramble is a
//! bijection for every seed and, in the original bit order, output bit `b` is input bit `b`
//! XOR a function of the higher input bits only (the net property). The tests check both, and
//! that the random flips behave like independent fair coins across seeds.
//!
//! Generators that can produce bit-reversed words directly (Sobol' from reversed direction
//! words) call [`OwenScramble::apply_reversed`] and save a reversal. A 32-digit input has zeros
//! beyond its 32nd digit, so the scramble's digits 33 and on are a random function of the first
//! 32 alone; [`OwenScramble::tail_bits`] supplies them, hashed from the scrambled word, for
//! coordinates that want double resolution. [`dimension_seed`] decorrelates the seeds of
//! different dimensions.

use crate::hash::{hash_words, mix64};

/// Salt that separates the scramble's constants from other uses of a seed's hash.
const CONSTANTS_SALT: u64 = 0x6f77_656e_5f6b_6579;
/// Salt for [`dimension_seed`].
const DIMENSION_SALT: u64 = 0x6f77_656e_5f64_696d;

/// The constants of one nested uniform scramble: a seeded bijection of `u32` that keeps the net
/// property. Build it once per seed (one column of a block) and [`apply`](Self::apply) it to
/// many words.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct OwenScramble {
    add: [u32; 3],
    odd: [u32; 2],
    even: [u32; 4],
    tail: u32,
}

impl OwenScramble {
    /// The scramble selected by `seed`; every seed gives a different set of constants.
    pub(crate) fn new(seed: u32) -> Self {
        let a = mix64(u64::from(seed) ^ CONSTANTS_SALT);
        let b = mix64(a ^ 0x0001);
        let c = mix64(b ^ 0x0002);
        let d = mix64(c ^ 0x0003);
        let e = mix64(d ^ 0x0004);
        let low = |h: u64| h as u32;
        let high = |h: u64| (h >> 32) as u32;
        // Even multipliers keep bit 1 set, so `v * even` feeds bit `b - 1` straight into bit
        // `b` (a multiplier with many trailing zeros would only mix bits far apart).
        let even = |w: u32| (w | 2) & !1;
        OwenScramble {
            add: [low(a), high(a), low(b)],
            odd: [high(b) | 1, low(c) | 1],
            even: [even(high(c)), even(low(d)), even(high(d)), even(low(e))],
            tail: high(e),
        }
    }

    /// Scrambles `x`: bit-reverse, mix upward, reverse back. Branch-free.
    #[inline(always)]
    pub(crate) fn apply(&self, x: u32) -> u32 {
        self.apply_reversed(x.reverse_bits())
    }

    /// Scrambles a word given bit-reversed (`v = x.reverse_bits()`) and returns the scrambled
    /// word in normal order: `apply_reversed(x.reverse_bits()) == apply(x)`. Generators that
    /// can produce reversed words directly (Sobol' with reversed direction words) save one
    /// reversal per value.
    #[inline(always)]
    pub(crate) fn apply_reversed(&self, mut v: u32) -> u32 {
        v = v.wrapping_add(self.add[0]);
        v ^= v.wrapping_mul(self.even[0]);
        v = v.wrapping_mul(self.odd[0]);
        v = v.wrapping_add(self.add[1]);
        v ^= v.wrapping_mul(self.even[1]);
        v = v.wrapping_mul(self.odd[1]);
        v = v.wrapping_add(self.add[2]);
        v ^= v.wrapping_mul(self.even[2]);
        v ^= v.wrapping_mul(self.even[3]);
        v.reverse_bits()
    }

    /// Random digits to follow a scrambled 32-digit word, as the nested scramble of a longer
    /// expansion would give them. A 32-digit input has zeros beyond digit 32, so under a nested
    /// uniform scramble the output digits 33, 34, ... are a random function of the first 32
    /// input digits alone, equivalently (the scramble being a bijection) of the scrambled word
    /// `scrambled`. This hashes it with a per-seed key (the "lowbias32" mixer of Wellons'
    /// hash-prospector, a bijection of `u32` with low bias); use the top bits.
    #[inline(always)]
    pub(crate) fn tail_bits(&self, scrambled: u32) -> u32 {
        let mut h = scrambled ^ self.tail;
        h ^= h >> 16;
        h = h.wrapping_mul(0x7feb_352d);
        h ^= h >> 15;
        h = h.wrapping_mul(0x846c_a68b);
        h ^ (h >> 16)
    }
}

/// Owen-scrambles the 32-bit fixed-point digits `x` (most significant bit first) with `seed`.
///
/// A bijection of `u32` for every seed, in which output bit `b` depends only on input bit `b`
/// and the input bits above it. To scramble many words with one seed, build an
/// [`OwenScramble`] once instead.
#[inline]
pub(crate) fn owen_scramble_u32(x: u32, seed: u32) -> u32 {
    OwenScramble::new(seed).apply(x)
}

/// The scramble seed for dimension `dim` under the randomization `seed`: a hash of both, so
/// that neighbouring dimensions (and neighbouring seeds) get unrelated scrambles. Never use
/// `seed + dim`, which makes dimension `d` of seed `s` repeat dimension `d - 1` of `s + 1`.
#[inline]
pub(crate) fn dimension_seed(seed: u64, dim: u64) -> u32 {
    (hash_words(seed, &[dim, DIMENSION_SALT]) >> 32) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small SplitMix64 stream for drawing test inputs.
    fn draws(seed: u64) -> impl Iterator<Item = u64> {
        (0u64..).map(move |i| mix64(seed.wrapping_add(i.wrapping_mul(0x9e37_79b9_7f4a_7c15))))
    }

    #[test]
    fn bit_b_is_input_bit_b_xor_a_function_of_higher_bits() {
        // Flipping input bit b must flip output bit b and leave every higher output bit
        // unchanged; this is the net property, and (by induction from the top bit) it makes the
        // map a bijection.
        let mut rng = draws(1);
        for _ in 0..20_000 {
            let r = rng.next().unwrap_or(0);
            let x = r as u32;
            let seed = (r >> 32) as u32;
            let b = (rng.next().unwrap_or(0) % 32) as u32;
            let s = OwenScramble::new(seed);
            let (y, z) = (s.apply(x), s.apply(x ^ (1 << b)));
            let differ = y ^ z;
            assert_eq!(differ >> b, 1, "x {x:#x} bit {b} seed {seed:#x}");
            assert_eq!(owen_scramble_u32(x, seed), y);
        }
    }

    #[test]
    fn permutes_every_top_16_bit_prefix() {
        // Output bits 16..32 depend only on input bits 16..32, so the map restricted to those
        // bits must be a permutation of 2^16 values.
        for seed in [0u32, 1, 0xdead_beef, u32::MAX] {
            let s = OwenScramble::new(seed);
            let mut seen = vec![false; 1 << 16];
            for h in 0u32..1 << 16 {
                let top = (s.apply(h << 16) >> 16) as usize;
                assert!(!seen[top], "seed {seed:#x}: collision at {h:#x}");
                seen[top] = true;
            }
        }
    }

    #[test]
    fn flips_are_fair_and_independent_across_seeds() {
        // In a nested uniform scramble, for two inputs whose first difference is at bit p,
        // every output bit below p is flipped independently for each: each output bit is a fair
        // coin, and so is "the two outputs agree in bit q" for q < p. Over S seeds each such
        // frequency has sd 0.5/sqrt(S); we allow 5 sd.
        const SEEDS: u32 = 20_000;
        let tolerance = 5.0 * 0.5 / f64::from(SEEDS).sqrt();
        let mut rng = draws(2);
        for _case in 0..24 {
            let r = rng.next().unwrap_or(0);
            let x = r as u32;
            let p = 1 + (r >> 32) as u32 % 31;
            // y shares x's bits above p, differs at p, and has random bits below.
            let low_mask = (1u32 << p) - 1;
            let y = (x & !low_mask & !(1 << p))
                | (!x & (1 << p))
                | ((rng.next().unwrap_or(0) as u32) & low_mask);
            let mut ones = [0u32; 32];
            let mut agree = [0u32; 32];
            for seed in 0..SEEDS {
                let s = OwenScramble::new(dimension_seed(7, u64::from(seed)));
                let (a, b) = (s.apply(x), s.apply(y));
                for q in 0..32 {
                    ones[q as usize] += (a >> q) & 1;
                    agree[q as usize] += !(a ^ b) >> q & 1;
                }
            }
            for q in 0..32 {
                let f = f64::from(ones[q as usize]) / f64::from(SEEDS);
                assert!((f - 0.5).abs() < tolerance, "x {x:#x} bit {q}: {f}");
                if q < p {
                    let g = f64::from(agree[q as usize]) / f64::from(SEEDS);
                    assert!(
                        (g - 0.5).abs() < tolerance,
                        "x {x:#x} y {y:#x} bit {q}: {g}"
                    );
                }
            }
        }
    }

    #[test]
    fn dimension_seeds_differ() {
        let seeds: Vec<u32> = (0..1000).map(|d| dimension_seed(5, d)).collect();
        let mut sorted = seeds.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), seeds.len());
        assert_ne!(dimension_seed(5, 1), dimension_seed(6, 0));
    }
}
