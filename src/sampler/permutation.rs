//! Random-access permutations of `0..n` selected by a seed.
//!
//! Latin hypercube and similar samplers need "the image of `i` under a random permutation of
//! `0..n`" without storing the permutation. As in Kensler (2013, "Correlated Multi-Jittered
//! Sampling") we build a bijection on the smallest even power-of-two range `0..2^w` covering
//! `n` and "cycle-walk": apply it again until the value lands below `n`. Because the map is a
//! bijection, the walk restricted to `0..n` is itself a bijection, and because `2^w < 4n`
//! fewer than four steps are needed on average.
//!
//! For `n` of 2^16 and more the bijection is a balanced Feistel network (Luby & Rackoff 1988)
//! whose round function is a full 64-bit hash. Small domains are where Feistel networks are
//! weak (halves of a few bits), so below 2^16 we use the swap-or-not shuffle (Hoang, Morris &
//! Rogaway 2012), which permutes `0..n` directly for any `n` and needs no cycle walk. Kensler's
//! cheaper multiply-xorshift mix was tried first: it left the image of a fixed index visibly
//! non-uniform across seeds for small `n` (chi-square 169 on 9 degrees of freedom for
//! `n = 10`), and so did a Feistel network for `n < 16`; both would bias Latin hypercube
//! estimates. The tests below check uniformity of single images and of pairs.

use crate::hash::{hash_words, mix64};

/// Feistel rounds; six leave no detectable structure in the tests below.
const FEISTEL_ROUNDS: usize = 6;
/// Below this size the swap-or-not shuffle is used.
const SMALL: u64 = 1 << 16;
/// Swap-or-not rounds for small domains (about 2.5 log2 of the largest small `n`).
const SWAP_ROUNDS: usize = 40;
/// The first word of every round key's hash.
const TAG_ROUND: u64 = 0x7065_726d;

/// A permutation of `0..n` that maps any index in O(1) expected time.
///
/// Different seeds give unrelated permutations; the same seed always gives the same one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Permutation {
    n: u64,
    half_bits: u32,
    half_mask: u64,
    /// One hashed key per round (Feistel uses the first `FEISTEL_ROUNDS`).
    keys: [u64; SWAP_ROUNDS],
    /// Swap-or-not pairing offsets, `(key >> 32) % n` per round, precomputed so that rounds
    /// need no division.
    offsets: [u64; SWAP_ROUNDS],
}

impl Permutation {
    /// The permutation of `0..n` selected by `seed` (any `n`, including 0 and 1).
    pub(crate) fn new(n: u64, seed: u64) -> Self {
        let (half_bits, half_mask) = feistel_halves(n);
        let mut keys = [0u64; SWAP_ROUNDS];
        for (k, key) in keys.iter_mut().enumerate() {
            *key = hash_words(seed, &[TAG_ROUND, k as u64]);
        }
        Permutation {
            n,
            half_bits,
            half_mask,
            keys,
            offsets: keys.map(|key| if n == 0 { 0 } else { (key >> 32) % n }),
        }
    }

    /// One application of the Feistel bijection on `0..2^(2 * half_bits)`.
    #[inline]
    fn scramble(&self, x: u64) -> u64 {
        let (mut left, mut right) = (x >> self.half_bits, x & self.half_mask);
        for &key in &self.keys[..FEISTEL_ROUNDS] {
            let mixed = left ^ (mix64(right ^ key) & self.half_mask);
            left = right;
            right = mixed;
        }
        (left << self.half_bits) | right
    }

    /// Swap-or-not: each round pairs `x` with `k - x (mod n)` and swaps the pair or not by a
    /// hashed bit of the pair; every round is an involution, so the whole is a bijection.
    fn swap_or_not(&self, mut x: u64) -> u64 {
        for (&key, &offset) in self.keys.iter().zip(&self.offsets) {
            x = swap_or_not_round(x, key, offset, self.n);
        }
        x
    }

    /// The image of `index` (which must be below `n`; larger values are reduced modulo `n`).
    #[inline]
    pub(crate) fn apply(&self, index: u64) -> u64 {
        if self.n <= 1 {
            return 0;
        }
        if self.n < SMALL {
            return self.swap_or_not(index % self.n);
        }
        let mut x = index % self.n;
        loop {
            x = self.scramble(x);
            if x < self.n {
                return x;
            }
        }
    }
}

/// The bits and mask of each half of the Feistel network on `0..n`: the smallest even power
/// of two covering `n`.
#[inline]
fn feistel_halves(n: u64) -> (u32, u64) {
    let bits = 64 - n.saturating_sub(1).leading_zeros();
    let half_bits = bits.div_ceil(2).max(1);
    let half_mask = if half_bits == 32 {
        u64::from(u32::MAX)
    } else {
        (1u64 << half_bits) - 1
    };
    (half_bits, half_mask)
}

/// Lanes of one batch of [`Permutation::apply_lanes`]: 16 64-bit values, two AVX-512 or four
/// AVX2 registers, enough independent chains to hide the multiplies' latency.
pub(crate) const LANES: usize = 16;

impl Permutation {
    /// The images of 16 indices at once, each below `n`, equal to [`apply`](Self::apply) lane
    /// by lane. The rounds run outermost and the lanes innermost, so each round is a few
    /// vector instructions when compiled for a wide instruction set (see `crate::simd`).
    /// Feistel's cycle walk re-applies the network to the lanes not yet below `n`, keeping
    /// the others, until every lane has landed: the same walk as `apply`, lane by lane.
    #[inline(always)]
    pub(crate) fn apply_lanes(&self, xs: &mut [u64; LANES]) {
        if self.n <= 1 {
            *xs = [0; LANES];
            return;
        }
        debug_assert!(xs.iter().all(|&x| x < self.n));
        if self.n < SMALL {
            for (&key, &offset) in self.keys.iter().zip(&self.offsets) {
                for x in xs.iter_mut() {
                    *x = swap_or_not_round(*x, key, offset, self.n);
                }
            }
            return;
        }
        self.scramble_lanes(xs);
        while xs.iter().any(|&x| x >= self.n) {
            let mut again = *xs;
            self.scramble_lanes(&mut again);
            for (x, &y) in xs.iter_mut().zip(&again) {
                if *x >= self.n {
                    *x = y;
                }
            }
        }
    }

    /// The images of `inputs` (each below `n`) into `out` (as long as `inputs`), 16 lanes at
    /// a time by [`apply_lanes`](Self::apply_lanes).
    #[inline(always)]
    pub(crate) fn apply_into(&self, inputs: &[u64], out: &mut [u64]) {
        for (ins, outs) in inputs.chunks(LANES).zip(out.chunks_mut(LANES)) {
            let mut lanes = [0u64; LANES];
            lanes[..ins.len()].copy_from_slice(ins);
            self.apply_lanes(&mut lanes);
            outs.copy_from_slice(&lanes[..outs.len()]);
        }
    }

    /// The image of `xs[l]` under `perms[l]` for each of 16 lanes, equal to
    /// [`apply`](Self::apply) lane by lane: different permutations of one size, as the
    /// uncorrelated multi-jittered samplers use (one per column of cells). One swap-or-not
    /// application is a chain of 40 dependent hash rounds; stepping 16 of them in lockstep
    /// lets the CPU overlap the chains. Feistel-sized permutations are applied one by one.
    #[inline(always)]
    pub(crate) fn apply_each(perms: &[&Permutation; LANES], xs: &mut [u64; LANES]) {
        let n = perms[0].n;
        if n <= 1 || n >= SMALL || perms.iter().any(|p| p.n != n) {
            for (x, p) in xs.iter_mut().zip(perms) {
                *x = p.apply(*x);
            }
            return;
        }
        debug_assert!(xs.iter().all(|&x| x < n));
        for round in 0..SWAP_ROUNDS {
            for (x, p) in xs.iter_mut().zip(perms) {
                *x = swap_or_not_round(*x, p.keys[round], p.offsets[round], n);
            }
        }
    }

    /// [`scramble`](Self::scramble) of every lane, rounds outermost.
    #[inline(always)]
    fn scramble_lanes(&self, xs: &mut [u64; LANES]) {
        let mut left = xs.map(|x| x >> self.half_bits);
        let mut right = xs.map(|x| x & self.half_mask);
        for &key in &self.keys[..FEISTEL_ROUNDS] {
            for (l, r) in left.iter_mut().zip(right.iter_mut()) {
                let mixed = *l ^ (mix64(*r ^ key) & self.half_mask);
                *l = *r;
                *r = mixed;
            }
        }
        for ((x, &l), &r) in xs.iter_mut().zip(&left).zip(&right) {
            *x = (l << self.half_bits) | r;
        }
    }
}

/// Permutations `0..count` of one family (one per column of cells, say), each built on first
/// use and kept for the rest of a run of points. Building a permutation costs 40 hashes and
/// 40 divisions, several times applying it, so a fill that meets the same member many times
/// reuses it; when `count` is large next to the run, nothing is kept and every use builds its
/// own, as the per-point path does.
#[derive(Default)]
pub(crate) struct PermutationCache {
    /// Where member `which` is in `built`, `u32::MAX` while it is not built.
    slots: Vec<u32>,
    built: Vec<Permutation>,
    keep: bool,
}

impl PermutationCache {
    /// Forgets every member, for a family of `count` members that a run of `uses` points will
    /// apply.
    pub(crate) fn reset(&mut self, count: u64, uses: usize) {
        self.built.clear();
        self.slots.clear();
        self.keep = count <= 4 * uses as u64 + 1024;
        if self.keep {
            self.slots.resize(count as usize, u32::MAX);
        }
    }

    /// Where member `which` is in `built`, building it by `build(which)` on first use (only
    /// while members are kept).
    #[inline(always)]
    fn slot(&mut self, which: u64, build: &impl Fn(u64) -> Permutation) -> usize {
        let slot = &mut self.slots[which as usize];
        if *slot == u32::MAX {
            *slot = self.built.len() as u32;
            self.built.push(build(which));
        }
        *slot as usize
    }

    /// `out[j]`: the image of `inputs[j]` under member `which[j]`, 16 lanes at a time in
    /// lockstep ([`Permutation::apply_each`]). Kept members are referred to where they are
    /// stored, not copied per use.
    #[inline(always)]
    pub(crate) fn apply_into(
        &mut self,
        which: &[u64],
        inputs: &[u64],
        out: &mut [u64],
        build: impl Fn(u64) -> Permutation,
    ) {
        let groups = which.chunks(LANES).zip(inputs.chunks(LANES));
        for ((which, inputs), out) in groups.zip(out.chunks_mut(LANES)) {
            // Short groups repeat their last lane.
            let last = which.len() - 1;
            let member = |l: usize| which[l.min(last)];
            let mut xs: [u64; LANES] = std::array::from_fn(|l| inputs[l.min(last)]);
            if self.keep {
                let slots: [usize; LANES] = std::array::from_fn(|l| self.slot(member(l), &build));
                let refs: [&Permutation; LANES] = std::array::from_fn(|l| &self.built[slots[l]]);
                Permutation::apply_each(&refs, &mut xs);
            } else {
                let perms: [Permutation; LANES] = std::array::from_fn(|l| build(member(l)));
                let refs: [&Permutation; LANES] = std::array::from_fn(|l| &perms[l]);
                Permutation::apply_each(&refs, &mut xs);
            }
            out.copy_from_slice(&xs[..out.len()]);
        }
    }
}

/// One round of the swap-or-not shuffle on `0..n`: `x` is paired with `(offset - x) mod n`
/// (`offset`, the key's high half reduced below `n`, and `x` both below `n`) and the pair is
/// swapped or not by a hashed bit of the pair salted by the whole key. Branch-free: the swap
/// bit is a coin flip, which a branch would mispredict half the time.
#[inline(always)]
pub(crate) fn swap_or_not_round(x: u64, key: u64, offset: u64, n: u64) -> u64 {
    let wrap = u64::from(offset < x).wrapping_neg() & n;
    let partner = offset.wrapping_sub(x).wrapping_add(wrap);
    let pair = x.max(partner);
    let swap = (mix64(pair ^ key) >> 63).wrapping_neg();
    x ^ ((x ^ partner) & swap)
}

/// `floor(x n / 2^64)` for `n <= 2^32` (a 64-bit fraction `x / 2^64` scaled to `0..n`), from
/// 32-bit halves whose products fit in 64 bits (and which vector units multiply):
/// `floor((xh n 2^32 + xl n) / 2^64)` is `floor((xh n + floor(xl n / 2^32)) / 2^32)`.
#[inline(always)]
pub(crate) fn below_narrow(x: u64, n: u64) -> u64 {
    ((x >> 32) * n + (((x & 0xffff_ffff) * n) >> 32)) >> 32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_equal_single_applications() {
        for n in [2u64, 3, 17, 1000, 65_535, 65_536, 100_003, 1 << 40] {
            for seed in 0..4u64 {
                let p = Permutation::new(n, seed);
                let mut xs: [u64; LANES] = std::array::from_fn(|j| (j as u64 * 7919 + seed) % n);
                let expected = xs.map(|x| p.apply(x));
                p.apply_lanes(&mut xs);
                assert_eq!(xs, expected, "n {n} seed {seed}");
            }
        }
    }

    #[test]
    fn lanes_of_different_permutations_equal_single_applications() {
        for n in [1u64, 2, 3, 17, 1000, 65_535, 65_536, 100_003] {
            let perms: Vec<Permutation> =
                (0..LANES as u64).map(|s| Permutation::new(n, s)).collect();
            let refs: [&Permutation; LANES] = std::array::from_fn(|l| &perms[l]);
            let mut xs: [u64; LANES] = std::array::from_fn(|l| (l as u64 * 7919) % n.max(1));
            let expected: [u64; LANES] = std::array::from_fn(|l| perms[l].apply(xs[l]));
            Permutation::apply_each(&refs, &mut xs);
            assert_eq!(xs, expected, "n {n}");
        }
    }

    #[test]
    fn is_a_permutation_for_many_sizes() {
        for n in [1u64, 2, 3, 5, 8, 17, 100, 255, 256, 257, 1000] {
            for seed in 0..4 {
                let p = Permutation::new(n, seed);
                let mut seen = vec![false; n as usize];
                for i in 0..n {
                    let j = p.apply(i) as usize;
                    assert!(!seen[j], "n = {n}, seed = {seed}: {j} hit twice");
                    seen[j] = true;
                }
            }
        }
    }

    #[test]
    fn seeds_give_different_permutations() {
        let a: Vec<u64> = (0..64).map(|i| Permutation::new(64, 1).apply(i)).collect();
        let b: Vec<u64> = (0..64).map(|i| Permutation::new(64, 2).apply(i)).collect();
        assert_ne!(a, b);
    }

    /// Chi-square statistic of where `index` lands in `0..n` over `draws` seeds.
    fn landing_chi2(n: u64, index: u64, draws: u64) -> f64 {
        let mut counts = vec![0f64; n as usize];
        for seed in 0..draws {
            counts[Permutation::new(n, seed).apply(index) as usize] += 1.0;
        }
        let expected = draws as f64 / n as f64;
        counts
            .iter()
            .map(|c| (c - expected).powi(2) / expected)
            .sum()
    }

    #[test]
    fn image_of_a_fixed_index_is_uniform_across_seeds() {
        // Chi-square with n - 1 degrees of freedom; bounds are the 0.99999 quantiles
        // (scipy.stats.chi2.ppf(0.99999, df)): df 1: 19.5, 2: 23.0, 4: 28.5, 9: 37.3, 15: 46.1.
        for (n, bound) in [(2u64, 19.5), (3, 23.0), (5, 28.5), (10, 37.3), (16, 46.1)] {
            for index in [0, n / 2, n - 1] {
                let chi2 = landing_chi2(n, index, 20_000);
                assert!(chi2 < bound, "n = {n}, index = {index}: chi2 = {chi2}");
            }
        }
    }

    #[test]
    fn pairs_of_images_are_uniform_across_seeds() {
        // Where indices 0 and 1 land jointly, over the n (n - 1) possible ordered pairs, n = 6:
        // 29 degrees of freedom, 0.99999 quantile 66.6.
        let n = 6u64;
        let draws = 30_000u64;
        let mut counts = vec![0f64; (n * n) as usize];
        for seed in 0..draws {
            let p = Permutation::new(n, seed);
            counts[(p.apply(0) * n + p.apply(1)) as usize] += 1.0;
        }
        let expected = draws as f64 / (n * (n - 1)) as f64;
        let chi2: f64 = (0..n * n)
            .filter(|k| k / n != k % n)
            .map(|k| (counts[k as usize] - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 66.6, "chi2 = {chi2}");
    }

    #[test]
    fn works_at_the_top_of_the_u64_range() {
        let p = Permutation::new(u64::MAX, 9);
        assert!(p.apply(u64::MAX - 1) < u64::MAX);
    }
}
