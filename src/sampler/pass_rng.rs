//! The sequential generator of a pass that is built whole (Poisson-disk and best-candidate
//! sets): each pass draws from its own PCG-64 stream, hashed from `(seed, pass, tag)`, so
//! passes are independent and any pass can be built by any thread.

use rand_core::Rng;
use rand_pcg::Pcg64;

use crate::hash::{hash_words, unit_f64};

/// The generator of pass `pass` for purpose `tag`: PCG-64 with hashed state and stream.
pub(super) fn pass_rng(seed: u64, pass: u64, tag: u64) -> Pcg64 {
    let word = |w: u64| u128::from(hash_words(seed, &[pass, tag, w]));
    Pcg64::new((word(0) << 64) | word(1), (word(2) << 64) | word(3))
}

/// A uniform double in `[0, 1)`.
#[inline]
pub(super) fn uniform(rng: &mut Pcg64) -> f64 {
    unit_f64(rng.next_u64())
}

/// A uniform integer in `0..n` (`n >= 1`), by multiply-shift (bias below `n / 2^64`).
#[inline]
pub(super) fn below(rng: &mut Pcg64, n: usize) -> usize {
    ((u128::from(rng.next_u64()) * n as u128) >> 64) as usize
}
