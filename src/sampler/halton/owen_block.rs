//! The block kernel of Owen-scrambled Halton coordinates: the same integers as
//! [`owen_coordinate`](super::owen_coordinate), computed once per node instead of once per
//! index where a block shares nodes, and with the random permutations of large bases
//! evaluated sixteen at a time.
//!
//! The scrambled numerator of `index` is `sum_k pi_(k, index mod b^k)(a_k) b^(K-1-k)` over the
//! positions `k < K`, where the image at position `k` depends on `index mod b^(k+1)` only
//! (the prefix and the digit). In a block of consecutive indices, a position with
//! `b^(k+1)` not much above the block length sees each of its `(prefix, digit)` pairs many
//! times: those positions ("shallow") are memoized in a table indexed by `index mod b^(k+1)`.
//! Deeper positions have a different prefix for every index of the block and are computed
//! per index; the permutations of bases above 13 (a keyed swap-or-not shuffle of 40 hashed
//! rounds) are collected as jobs and run in lanes, which hides the rounds' latency and
//! vectorizes. The sum is exact in integers whatever the order, and rounded once as in
//! `owen_coordinate`, so the values are bit-identical.

use super::{Base, MAX_DEPTH, SMALL_BASE, TAG_RHO, below, rotate, small_permutation};
use crate::hash::{ONE_BELOW, hash_absorb, hash_start};
use crate::sampler::permutation::{LANES, Permutation, mod_reciprocal};
use crate::sampler::simd::{Kernel, dispatch};

/// Largest base whose digit permutation `rho` (on `b - 1` digits) is a swap-or-not shuffle,
/// which [`Permutation::apply_fresh_lanes`] evaluates in lanes; above it `rho` is a Feistel
/// network with a cycle walk, evaluated one by one.
const LANE_BASE_MAX: u64 = 1 << 16;
/// A memo slot not computed yet.
const UNSEEN: u32 = u32::MAX;
/// A memo slot whose image waits for its job.
const PENDING: u32 = u32::MAX - 1;

/// Where the image of a permutation job goes.
#[derive(Debug, Clone, Copy)]
enum Target {
    /// Slot of the memo table.
    Memo(usize),
    /// Added to the numerator of block offset `.0` with weight `b^(K-1-k)`, `k = .1`.
    Value(usize, usize),
}

/// Reusable buffers of the Owen block kernel.
#[derive(Default)]
pub(crate) struct OwenScratch {
    /// Memoized digit images of the shallow positions, one table after another.
    memo: Vec<u32>,
    /// The numerators of the block.
    nums: Vec<u128>,
    /// Permutation jobs: keys of `rho`, arguments (then images), pi(0) and targets.
    seeds: Vec<u64>,
    args: Vec<u64>,
    zeros: Vec<u64>,
    targets: Vec<Target>,
}

/// Digits and residues of consecutive indices, counted like an odometer.
struct Odometer {
    /// `digits[k]`: digit `k` of the index, least significant first.
    digits: [u64; MAX_DEPTH],
    /// `residues[j] = index mod b^j`.
    residues: [u64; MAX_DEPTH + 1],
    /// Digits of the index (0 for index 0).
    width: usize,
    index: u64,
}

impl Odometer {
    fn new(b: u64, index: u64, positions: usize) -> Self {
        let mut odometer = Odometer {
            digits: [0; MAX_DEPTH],
            residues: [0; MAX_DEPTH + 1],
            width: 0,
            index,
        };
        let (mut rest, mut power) = (index, 1u64);
        for k in 0..positions {
            odometer.digits[k] = rest % b;
            rest /= b;
            odometer.residues[k + 1] = odometer.residues[k] + odometer.digits[k] * power;
            power *= b;
        }
        // index mod b^j == index exactly from j = the number of digits on.
        odometer.width = (0..=positions)
            .find(|&j| odometer.residues[j] == index)
            .unwrap_or(positions);
        odometer
    }

    /// Moves to the next index, which must stay below `b^positions`.
    #[inline]
    fn step(&mut self, b: u64, powers: &[u64], positions: usize) {
        self.index += 1;
        for k in 0..positions {
            let residue = self.residues[k + 1] + 1;
            self.residues[k + 1] = if residue == powers[k + 1] { 0 } else { residue };
        }
        for digit in &mut self.digits[..positions] {
            if *digit + 1 < b {
                *digit += 1;
                break;
            }
            *digit = 0;
        }
        if self.index == powers[self.width] {
            self.width += 1;
        }
    }
}

/// The runs of permutation jobs, compiled for each instruction set by [`dispatch`].
struct RhoJobs<'a> {
    n: u64,
    seeds: &'a [u64],
    args: &'a mut [u64],
}

impl Kernel for RhoJobs<'_> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let RhoJobs { n, seeds, args } = self;
        let reciprocal = mod_reciprocal(n);
        for (seeds, args) in seeds.chunks(LANES).zip(args.chunks_mut(LANES)) {
            let mut seed_lanes = [0u64; LANES];
            let mut arg_lanes = [0u64; LANES];
            seed_lanes[..seeds.len()].copy_from_slice(seeds);
            arg_lanes[..args.len()].copy_from_slice(args);
            Permutation::apply_fresh_lanes(n, reciprocal, &seed_lanes, &mut arg_lanes);
            args.copy_from_slice(&arg_lanes[..args.len()]);
        }
    }
}

/// Writes the Owen-scrambled coordinates of local indices `first, first + 1, ...` (one pass,
/// below `2^40`) in `base` for the (pass, dimension) `key`, bit-identical to
/// [`owen_coordinate`](super::owen_coordinate).
pub(super) fn fill_owen(base: &Base, key: u64, first: u64, out: &mut [f64], s: &mut OwenScratch) {
    let Some(last_offset) = out.len().checked_sub(1) else {
        return;
    };
    let (b, m, depth) = (base.base, base.per_word as usize, base.depth);
    let last = first + last_offset as u64;
    // powers[j] = b^j for j <= positions, the digits of `last` (b^positions <= last * b < 2^57).
    let mut powers = [1u64; MAX_DEPTH + 2];
    let mut positions = 0;
    while powers[positions] <= last {
        powers[positions + 1] = powers[positions] * b;
        positions += 1;
    }
    powers[positions + 1] = powers[positions].saturating_mul(b);
    // weights[k] = b^(K-1-k), the weight of position k in the numerator over b^K.
    let mut weights = [0u128; MAX_DEPTH];
    let mut weight = 1u128;
    for w in weights[..depth].iter_mut().rev() {
        *w = weight;
        weight *= u128::from(b);
    }
    // Shallow positions: tables of b^(k+1) slots, small next to the block.
    let limit = 4 * out.len() as u64 + 1024;
    let mut shallow = 0;
    while shallow < positions && powers[shallow + 1] <= limit {
        shallow += 1;
    }
    let table_start: Vec<usize> = (0..=shallow)
        .scan(0usize, |at, k| {
            let start = *at;
            *at += powers[k + 1] as usize;
            Some(start)
        })
        .collect();
    s.memo.clear();
    s.memo.resize(table_start[shallow], UNSEEN);
    s.nums.clear();
    s.nums.resize(out.len(), 0);
    s.seeds.clear();
    s.args.clear();
    s.zeros.clear();
    s.targets.clear();

    // Digit k of a stream is digit k % m of its word number k / m: floor(frac(word b^(k % m)
    // / 2^64) b) (see `stream_digits`); a run from digit k to the end of its word spells
    // floor(frac(word b^(k % m) / 2^64) b^run).
    let mut word_of = [0u64; MAX_DEPTH];
    let mut scale_of = [0u64; MAX_DEPTH];
    let mut run_of = [0usize; MAX_DEPTH];
    let mut run_range = [0u64; MAX_DEPTH];
    for k in 0..depth {
        let within = k % m;
        word_of[k] = (k / m) as u64;
        scale_of[k] = b.pow(within as u32);
        run_of[k] = (m - within).min(depth - k);
        run_range[k] = b.pow(run_of[k] as u32);
    }
    let words = hash_start(key);
    let rhos = hash_start(key ^ TAG_RHO);
    // pi(0) of node (k, prefix): digit k of the node's stream.
    let zero_of = |k: usize, prefix: u64| -> u64 {
        let word = hash_absorb(words, (prefix << 6) | word_of[k]);
        below(word.wrapping_mul(scale_of[k]), b)
    };
    // The image of a non-zero digit: now for small bases, else as a job (None).
    let mut image_of = |k: usize, prefix: u64, digit: u64, zero: u64, target: Target| {
        if b == 2 {
            return Some(zero ^ digit);
        }
        let rho_key = hash_absorb(rhos, (prefix << 6) | k as u64);
        if b <= SMALL_BASE {
            return Some(rotate(
                b,
                zero,
                small_permutation(rho_key, b - 1, digit - 1),
            ));
        }
        if b > LANE_BASE_MAX {
            let rest = Permutation::new(b - 1, rho_key).apply(digit - 1);
            return Some(rotate(b, zero, rest));
        }
        s.seeds.push(rho_key);
        s.args.push(digit - 1);
        s.zeros.push(zero);
        s.targets.push(target);
        None
    };

    // Pass 1: every position but the shallow ones, and the shallow slots the block needs.
    let mut odometer = Odometer::new(b, first, positions);
    for (offset, num) in s.nums.iter_mut().enumerate() {
        if offset > 0 {
            odometer.step(b, &powers, positions);
        }
        let Odometer {
            digits,
            residues,
            width,
            index,
        } = &odometer;
        for k in 0..shallow {
            let slot = table_start[k] + residues[k + 1] as usize;
            if s.memo[slot] == UNSEEN {
                let zero = zero_of(k, residues[k]);
                s.memo[slot] = match digits[k] {
                    0 => zero as u32,
                    digit => match image_of(k, residues[k], digit, zero, Target::Memo(slot)) {
                        Some(image) => image as u32,
                        None => PENDING,
                    },
                };
            }
        }
        // Deep positions: a node of its own for every index.
        for k in shallow..*width {
            let zero = zero_of(k, residues[k]);
            let image = match digits[k] {
                0 => Some(zero),
                digit => image_of(k, residues[k], digit, zero, Target::Value(offset, k)),
            };
            if let Some(image) = image {
                *num += u128::from(image) * weights[k];
            }
        }
        // The tail of zero digits: runs of the stream of `index` itself.
        let mut k = shallow.max(*width);
        while k < depth {
            let word = hash_absorb(words, (index << 6) | word_of[k]);
            let run = below(word.wrapping_mul(scale_of[k]), run_range[k]);
            *num += u128::from(run) * weights[k + run_of[k] - 1];
            k += run_of[k];
        }
    }

    // The permutation jobs, sixteen at a time.
    if !s.seeds.is_empty() {
        dispatch(RhoJobs {
            n: b - 1,
            seeds: &s.seeds,
            args: &mut s.args,
        });
        for ((&rest, &zero), &target) in s.args.iter().zip(&s.zeros).zip(&s.targets) {
            let image = rotate(b, zero, rest);
            match target {
                Target::Memo(slot) => s.memo[slot] = image as u32,
                Target::Value(offset, k) => s.nums[offset] += u128::from(image) * weights[k],
            }
        }
    }

    // Pass 2: the shallow positions from the tables, then the single rounding.
    let mut odometer = Odometer::new(b, first, positions);
    let low_weight = if shallow == 0 {
        0
    } else {
        weights[shallow - 1]
    };
    for (offset, (x, &num)) in out.iter_mut().zip(&s.nums).enumerate() {
        if offset > 0 {
            odometer.step(b, &powers, positions);
        }
        // sum_(k < shallow) image_k b^(shallow-1-k), below b^shallow: one u64 Horner sum.
        let mut low = 0u64;
        for k in 0..shallow {
            let image = s.memo[table_start[k] + odometer.residues[k + 1] as usize];
            debug_assert!(image < PENDING);
            low = low * b + u64::from(image);
        }
        let num = num + u128::from(low) * low_weight;
        *x = base.to_f64(num).min(ONE_BELOW);
    }
}
