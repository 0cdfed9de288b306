//! Random digit permutation scrambling
//! ([`Scramble::Permute`](crate::sampler::Scramble::Permute)): digit position `k` of every
//! coordinate is replaced by `pi_k(a_k)`, one random permutation per position, point by point
//! and a block at a time.

use super::Scratch;
use super::base::{Base, MAX_DEPTH};
use super::digit_permutation::{DigitPermutation, TAG_RHO, digit_image, rotate, stream_digits};
use crate::float::ONE_BELOW;
use crate::hash::hash_words;
use crate::sampler::permutation::{LANES, Permutation};
use crate::simd::{Kernel, dispatch};

/// The random digit permutations of one (pass, dimension). Position `k` (0-based, the most
/// significant output digit first) has `pi_k(0) = t_k`, digit `k` of one random digit stream
/// (a hash per `m` digits), and `rho_k` keyed by a hash of `k`; the permutations of different
/// positions are independent.
pub(super) struct PermuteColumn {
    base: Base,
    key: u64,
    /// `t_k = pi_k(0)`.
    zeros: [u64; MAX_DEPTH],
    /// `tails[w]`: the numerator (over `b^K`) of the permuted zero digits at positions `w..K`.
    tails: [u128; MAX_DEPTH + 1],
    /// `powers[j] = b^j`.
    powers: [u128; MAX_DEPTH + 1],
}

impl PermuteColumn {
    pub(super) fn new(base: Base, key: u64) -> Self {
        let mut column = PermuteColumn {
            base,
            key,
            zeros: [0; MAX_DEPTH],
            tails: [0; MAX_DEPTH + 1],
            powers: [1; MAX_DEPTH + 1],
        };
        let (b, m) = (base.base, base.per_word as usize);
        for j in 1..=base.depth {
            column.powers[j] = column.powers[j - 1] * u128::from(b);
        }
        let mut word = 0;
        for k in 0..base.depth {
            if k % m == 0 {
                word = hash_words(key, &[(k / m) as u64]);
            }
            column.zeros[k] = stream_digits(word, b, (k % m) as u32, 1);
        }
        for k in (0..base.depth).rev() {
            column.tails[k] = column.tails[k + 1]
                + u128::from(column.zeros[k]) * column.powers[base.depth - 1 - k];
        }
        column
    }

    /// The key of `rho_k`.
    #[inline]
    fn rho_key(&self, k: usize) -> u64 {
        hash_words(self.key ^ TAG_RHO, &[k as u64])
    }

    /// The permutation of position `k`, with `rho` built.
    fn permutation(&self, k: usize) -> DigitPermutation {
        DigitPermutation::new(self.base.base, self.zeros[k], self.rho_key(k))
    }

    /// The permuted coordinate of `index`.
    pub(super) fn point(&self, mut index: u64) -> f64 {
        let b = self.base.base;
        let (mut num, mut width) = (0u128, 0usize);
        while index > 0 {
            let (next, digit) = self.base.split(index);
            let zero = self.zeros[width];
            let image = digit_image(b, zero, || self.rho_key(width), digit);
            num = num * u128::from(b) + u128::from(image);
            width += 1;
            index = next;
        }
        let num = num * self.powers[self.base.depth - width] + self.tails[width];
        self.base.ratio(num).min(ONE_BELOW)
    }
}

/// The images of the digits `from, from + 1, ..` (modulo `b`, one per slot of `images`) under
/// a digit permutation with a random-access `rho`, sixteen at a time; compiled for each
/// instruction set by [`dispatch`].
struct DigitImages<'a> {
    rho: &'a Permutation,
    base: u64,
    zero: u64,
    from: u64,
    images: &'a mut [u32],
}

impl Kernel for DigitImages<'_> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let DigitImages {
            rho,
            base,
            zero,
            from,
            images,
        } = self;
        for (chunk, out) in images.chunks_mut(LANES).enumerate() {
            let digits: [u64; LANES] = std::array::from_fn(|j| {
                let digit = from + (chunk * LANES + j) as u64;
                // from < b and at most b slots: one wrap at most (lanes past the end are 0).
                match digit {
                    _ if j >= out.len() => 0,
                    _ if digit >= base => digit - base,
                    _ => digit,
                }
            });
            // pi(0) = zero, pi(a) = rotate(rho(a - 1)) for a >= 1; digit 0 takes the in-range
            // argument 0, whose image is unused.
            let mut lanes = digits.map(|digit| digit.saturating_sub(1));
            rho.apply_lanes(&mut lanes);
            for ((image, &digit), &rest) in out.iter_mut().zip(&digits).zip(&lanes) {
                // Digit images are below b < 2^17.
                *image = match digit {
                    0 => zero,
                    _ => rotate(base, zero, rest),
                } as u32;
            }
        }
    }
}

/// Block kernel for [`Scramble::Permute`](crate::sampler::Scramble::Permute): the permutations
/// of the digit positions in use are built once, the images of the digits the block meets found
/// up front, and the indices counted like an odometer, updating the numerator
/// `sum_k pi_k(a_k) b^(K-1-k)` digit by digit (the lowest positions through a table of their
/// combined parts). The numerator is the same integer as in
/// [`PermuteColumn::point`] (zero digits map to `pi_k(0)` either way), so the values are
/// bit-identical.
pub(super) fn fill_permuted(
    base: &Base,
    key: u64,
    first: u64,
    out: &mut [f64],
    scratch: &mut Scratch,
) {
    let Some(last_offset) = out.len().checked_sub(1) else {
        return;
    };
    let column = PermuteColumn::new(*base, key);
    let b = base.base;
    let last = first + last_offset as u64;
    let (mut rest, mut width) = (last, 0usize);
    while rest > 0 {
        rest /= b;
        width += 1;
    }
    scratch.permutations.clear();
    scratch
        .permutations
        .extend((0..width).map(|k| column.permutation(k)));
    // The digits the block's indices take at position k are a window of consecutive ones
    // (cyclically, at most b and at most the block length): their images are found once, in
    // lanes (one permutation, many arguments) for the random-access permutations.
    let mut windows = [(0usize, 0u64); MAX_DEPTH]; // (offset in memo, first digit)
    scratch.memo.clear();
    let mut power = 1u64; // b^k
    for (k, permutation) in scratch.permutations.iter().enumerate() {
        let low = first / power;
        let (from, count) = (low % b, (last / power - low + 1).min(b));
        let at = scratch.memo.len();
        windows[k] = (at, from);
        scratch.memo.resize(at + count as usize, 0);
        let images = &mut scratch.memo[at..];
        match &permutation.rho {
            Some(rho) => dispatch(DigitImages {
                rho,
                base: b,
                zero: permutation.zero,
                from,
                images,
            }),
            None => {
                for (image, digit) in images.iter_mut().zip(from..) {
                    let digit = if digit >= b { digit - b } else { digit };
                    // Digit images are below b < 2^17.
                    *image = permutation.apply(digit) as u32;
                }
            }
        }
        power = power.saturating_mul(b);
    }
    let Scratch { memo, lows, .. } = scratch;
    let image = |k: usize, digit: u64| -> u64 {
        let (at, from) = windows[k];
        let j = if digit >= from {
            digit - from
        } else {
            digit + b - from
        };
        u64::from(memo[at + j as usize])
    };
    // digits[k]: digit k of the index (least significant first); images[k] = pi_k(digits[k]),
    // which carries weight b^(K-1-k) in the numerator over b^K.
    let mut digits = [0u64; MAX_DEPTH];
    let mut images = [0u64; MAX_DEPTH];
    let weights = &column.powers[base.depth - width..base.depth];
    let mut num = column.tails[width];
    let mut rest = first;
    for k in 0..width {
        digits[k] = rest % b;
        rest /= b;
        images[k] = image(k, digits[k]);
        num += u128::from(images[k]) * weights[width - 1 - k];
    }
    if width == 0 {
        // The block is index 0 alone.
        out[0] = base.ratio(num).min(ONE_BELOW);
        return;
    }
    // The lowest `low` positions form a number r < b^low that runs through its values before
    // a carry reaches the positions above, whose part of the numerator is then shared. With
    // b^low <= 256 small next to the block, the parts of all r are tabulated (built position
    // by position), else (low = 1) found digit by digit.
    let mut low = 1;
    while low < width && powers_u64(b, low + 1) <= 256.min(out.len() as u64) {
        low += 1;
    }
    let size = powers_u64(b, low);
    let tabulate = size <= out.len() as u64;
    lows.clear();
    if tabulate {
        lows.push(0);
        for k in 0..low {
            let span = lows.len();
            for digit in 1..b {
                let part = u128::from(image(k, digit)) * weights[width - 1 - k];
                for at in 0..span {
                    let value = lows[at] + part;
                    lows.push(value);
                }
            }
            // Digit 0 of position k: add pi_k(0)'s part to the existing entries.
            let zero = u128::from(image(k, 0)) * weights[width - 1 - k];
            for value in &mut lows[..span] {
                *value += zero;
            }
        }
    }
    // The part of positions below `low` of the index with these digits.
    let mut r = 0u64;
    let mut high = num;
    for k in (0..low).rev() {
        r = r * b + digits[k];
        high -= u128::from(images[k]) * weights[width - 1 - k];
    }
    let w0 = weights[width - 1];
    let mut done = 0;
    loop {
        let run = ((size - r) as usize).min(out.len() - done);
        let outs = &mut out[done..done + run];
        if tabulate {
            for (x, part) in outs.iter_mut().zip(&lows[r as usize..]) {
                *x = base.ratio(high + part).min(ONE_BELOW);
            }
        } else {
            for (x, digit) in outs.iter_mut().zip(r..) {
                *x = base
                    .ratio(high + u128::from(image(0, digit)) * w0)
                    .min(ONE_BELOW);
            }
        }
        done += run;
        if done == out.len() {
            break;
        }
        // Positions below `low` wrap to 0 and the carry adds one above; the index stays below
        // b^width, so the carry stops below width.
        r = 0;
        for k in low..width {
            let weight = weights[width - 1 - k];
            let (digit, carry) = if digits[k] + 1 < b {
                (digits[k] + 1, false)
            } else {
                (0, true)
            };
            let new = image(k, digit);
            high = high + u128::from(new) * weight - u128::from(images[k]) * weight;
            (digits[k], images[k]) = (digit, new);
            if !carry {
                break;
            }
        }
    }
}

/// `b^j` (small here).
fn powers_u64(b: u64, j: usize) -> u64 {
    b.saturating_pow(j as u32)
}
