//! The radical-inverse engine of the Halton-type samplers ([`Halton`](super::Halton) and
//! [`Hammersley`](super::Hammersley)): the coordinate `phi_b(i)` of an index `i < 2^40` in one
//! of the first 10,000 prime bases, unscrambled, under random digit permutations or under
//! nested uniform scrambling, one point at a time or a block at a time.
//!
//! * `base.rs`: the prime bases, their scrambling depth and division-free arithmetic;
//! * `rounding.rs`: correctly rounded ratios of wide integers;
//! * `plain.rs`: unscrambled radical inverses;
//! * `digit_permutation.rs`: random digit permutations and the digit streams they come from;
//! * `permute.rs`: random digit permutation scrambling;
//! * `owen.rs` and `owen_block.rs`: nested uniform scrambling.
//!
//! Kernels: [`plain::radical_inverse`] divides the digit-reversed integer by `b^k` once (an
//! odometer over a common denominator in [`plain::fill_plain`]); scrambled coordinates
//! accumulate permuted digits as a `u128` numerator over `b^K` and round once
//! ([`Base::ratio`]: a multiplication by a per-base reciprocal, with the exact
//! [`rounding::ratio_to_f64`] near halfway points). The block kernels
//! ([`permute::fill_permuted`], and `owen_block.rs` for nested scrambling) share work between
//! the indices of a block and run the keyed permutations in lanes through `crate::simd`. Every
//! path yields the same integers and the same single rounding, so `fill` and `point` agree bit
//! for bit.

use super::Scramble;
use crate::error::{Error, Result};
use crate::hash::hash_words;

mod base;
mod digit_permutation;
mod node_memo;
mod owen;
mod owen_block;
mod permute;
mod plain;
mod rounding;

pub(crate) use base::{Base, bases};
use digit_permutation::DigitPermutation;
#[cfg(test)]
pub(crate) use node_memo::slots_held as thread_table_slots;
use owen::owen_coordinate;
use permute::{PermuteColumn, fill_permuted};
use plain::{fill_plain, radical_inverse};

/// The most dimensions (prime bases) a Halton or Hammersley sampler may have.
pub(crate) const MAX_DIMS: usize = 10_000;

/// log2 of the points per pass of a Halton sequence.
pub(crate) const PASS_BITS: u32 = 40;

/// Points per pass of a Halton sequence, and the largest Hammersley point set.
pub(crate) const PASS_SIZE: u64 = 1 << PASS_BITS;

/// The randomizations the Halton-type samplers accept.
pub(crate) const SCRAMBLES: [Scramble; 3] = [Scramble::None, Scramble::Permute, Scramble::Owen];

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
