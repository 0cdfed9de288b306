//! Nested scrambling in base `b` (Owen 1995;
//! [`Scramble::Owen`](crate::sampler::Scramble::Owen)), one coordinate at a time;
//! `owen_block.rs` computes the same integers a block at a time.

use super::base::{Base, MAX_DEPTH};
use super::digit_permutation::{TAG_RHO, below, owen_digit_image, stream_digits};
use crate::float::ONE_BELOW;
use crate::hash::hash_words;

/// The Owen-scrambled coordinate of `index` in `base`, for the (pass, dimension) `key`.
///
/// The node of digit position `k` (0-based) is identified by `k` and the integer
/// `prefix = index mod b^k` formed by the digits above it in the output. Its permutation has
/// `pi(0) = t`, digit `k` of a random digit stream of `prefix` (a hash of `(prefix, k / m)`
/// per `m` digits, see [`stream_digits`]), and the rest of it (`rho`, or in bases above 13 the
/// slope of an affine map, see [`owen_digit_image`]) keyed by a hash of `(prefix, k)`. Nodes
/// with different prefixes draw from different streams, and the nodes of one prefix from
/// different digits of its stream, so all nodes are independent, as nested scrambling
/// requires. Every node has `prefix < b^k`, so the zero digits beyond the last digit of
/// `index` all read the stream of `prefix = index`: the tail costs one hash per `m` digits.
pub(super) fn owen_coordinate(base: &Base, key: u64, index: u64) -> f64 {
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
        let image = owen_digit_image(b, zero, || hash_words(key ^ TAG_RHO, &[node]), digit);
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
