//! The randomizations of one Sobol' dimension in one pass, each keeping the net properties:
//! a digital shift, Matoušek's (1998) linear matrix scramble plus a shift, and Owen's (1995)
//! nested uniform scramble, hash-based (Laine & Karras 2011; Burley 2020). All act on 53
//! digits, as they would on a longer expansion whose digits beyond the 32nd are zero.

use super::unit::{EXTRA_BITS, FULL_BITS, join_f64, unscrambled_f64, wide_f64};
use crate::hash::{hash_words, mix64};
use crate::sampler::Scramble;
use crate::sampler::owen::{OwenScramble, dimension_seed};

/// Salts separating the hashes of the shift and of the matrix scramble, drawn from one pass
/// seed.
const XOR_SALT: u64 = 0x736f_626f_6c5f_786f;
const LMS_SALT: u64 = 0x736f_626f_6c5f_6c6d;

/// Weyl increment (2^64 / golden ratio) for drawing several words from one hash.
const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;

/// Direction words of one dimension widened to 53 bits (the 32-bit word in bits 21..53), for
/// the digital shift and the linear matrix scramble.
pub(super) type WideDirections = [u64; 32];

/// A 32-bit word widened to 53 digits (zeros below).
#[inline(always)]
pub(super) fn widen(word: u32) -> u64 {
    u64::from(word) << EXTRA_BITS
}

/// Applies the 53 x 32 binary matrix whose column for bit `b` of `word` is `columns[b]` (bit
/// `b + 21` plus random lower bits: lower triangular with unit diagonal in digit order).
#[inline]
pub(super) fn linear(columns: &WideDirections, word: u32) -> u64 {
    let mut out = 0;
    for (b, &column) in columns.iter().enumerate() {
        out ^= column & 0u64.wrapping_sub(u64::from((word >> b) & 1));
    }
    out
}

/// The Owen scramble of a bit-reversed word, followed by its hashed digits 33 to 53.
#[inline]
fn owen_f64(scramble: &OwenScramble, reversed: u32) -> f64 {
    let (word, tail) = owen_parts(scramble, reversed);
    join_f64(word, tail)
}

/// The scrambled word of a bit-reversed word, and its next 21 digits (right-aligned).
#[inline(always)]
pub(super) fn owen_parts(scramble: &OwenScramble, reversed: u32) -> (u32, u32) {
    let word = scramble.apply_reversed(reversed);
    (word, scramble.tail_bits(word) >> (32 - EXTRA_BITS))
}

/// The randomization of one dimension in one pass.
// A short-lived stack value built once per column (or coordinate); boxing the matrix would
// cost an allocation per column for nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy)]
pub(super) enum Randomizer {
    None,
    /// A 53-bit digital shift.
    Xor {
        shift: u64,
    },
    /// Columns of the 53 x 32 lower-triangular matrix, then a 53-bit digital shift.
    Lms {
        columns: WideDirections,
        shift: u64,
    },
    Owen {
        scramble: OwenScramble,
    },
}

impl Randomizer {
    /// Scrambles one unscrambled word and converts it.
    #[inline]
    pub(super) fn finish(&self, word: u32) -> f64 {
        match self {
            Randomizer::None => unscrambled_f64(word),
            Randomizer::Xor { shift } => wide_f64(widen(word) ^ shift),
            Randomizer::Lms { columns, shift } => wide_f64(linear(columns, word) ^ shift),
            Randomizer::Owen { scramble } => owen_f64(scramble, word.reverse_bits()),
        }
    }

    /// The randomization of dimension `dim` under `scramble` in the pass with seed
    /// `pass_seed`.
    pub(super) fn new(scramble: Scramble, pass_seed: u64, dim: usize) -> Self {
        let dim = dim as u64;
        let low53 = |h: u64| h >> (64 - FULL_BITS);
        match scramble {
            Scramble::Xor => Randomizer::Xor {
                shift: low53(hash_words(pass_seed, &[dim, XOR_SALT])),
            },
            Scramble::Lms => {
                let base = hash_words(pass_seed, &[dim, LMS_SALT]);
                // Column b keeps its diagonal bit b + 21 and random bits below it.
                let columns = std::array::from_fn(|b| {
                    let random = mix64(base.wrapping_add((b as u64 + 1).wrapping_mul(GOLDEN)));
                    let diagonal = 1u64 << (b as u32 + EXTRA_BITS);
                    diagonal | (random & (diagonal - 1))
                });
                Randomizer::Lms {
                    columns,
                    shift: low53(mix64(base)),
                }
            }
            Scramble::Owen => Randomizer::Owen {
                scramble: OwenScramble::new(dimension_seed(pass_seed, dim)),
            },
            // `new` admits no other scramble.
            _ => Randomizer::None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampler::Sobol;

    #[test]
    fn sobol_lms_columns_are_unit_lower_triangular_and_linear() {
        let s = Sobol::new(3, Scramble::Lms, 9).unwrap();
        let Randomizer::Lms { columns, .. } = s.randomizer(s.pass_seed(0), 2) else {
            panic!("expected an LMS randomizer");
        };
        // Column b: the diagonal bit b + 21, nothing above it, fair coins below it (1168
        // random bits in all: sd 17.1 around 584).
        let mut ones = 0;
        for (b, &c) in columns.iter().enumerate() {
            assert_eq!(c >> (b + 21), 1);
            ones += (c & ((1 << (b + 21)) - 1)).count_ones();
        }
        assert!(ones.abs_diff(584) < 86, "{ones}");
        assert_eq!(
            linear(&columns, 0x1234 ^ 0x8000_0001),
            linear(&columns, 0x1234) ^ linear(&columns, 0x8000_0001)
        );
    }
}
