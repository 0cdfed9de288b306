//! The block kernel of the Sobol' sampler: for each dimension, the Gray-code words of an
//! aligned chunk of consecutive indices (one XOR per word, Antonov & Saleev 1979), then the
//! scramble and the conversion in loops without loop-carried dependencies, compiled per
//! instruction set by `crate::simd`. The words and conversions are those of `Sobol::point`,
//! so the values are bit-identical.

use super::directions::Directions;
use super::randomizer::{Randomizer, WideDirections, linear, owen_parts, widen};
use super::unit::Unit;
use super::{PASS_BITS, Sobol};
use crate::points::PointBlock;
use crate::sampler::owen::OwenScramble;
use crate::sampler::pass_runs;
use crate::simd::{Kernel, dispatch};
use std::ops::BitXorAssign;

/// Block length for the word buffers of the fill kernels (a power of two).
const CHUNK_BITS: u32 = 8;
const CHUNK: usize = 1 << CHUNK_BITS;

/// Below this many points of one aligned chunk, the shuffled kernel computes words directly
/// instead of generating the whole chunk by Gray code.
const SHUFFLE_DIRECT_BELOW: usize = 32;

/// XOR of the direction words selected by the set bits of `bits` (the Gray code of an index).
#[inline]
pub(super) fn direct(directions: &Directions, mut bits: u32) -> u32 {
    let mut word = 0;
    while bits != 0 {
        word ^= directions[bits.trailing_zeros() as usize];
        bits &= bits - 1;
    }
    word
}

/// The direction words bit-reversed, which the Owen hash consumes. A loop rather than
/// `array::map`, which was compiled as a call outside the vector kernels.
#[inline(always)]
fn reversed(directions: &Directions) -> Directions {
    let mut reversed = *directions;
    for word in &mut reversed {
        *word = word.reverse_bits();
    }
    reversed
}

/// Gray code of an in-pass index.
#[inline]
pub(super) fn gray(i: u32) -> u32 {
    i ^ (i >> 1)
}

/// Scratch for [`owen_chunk`]: the scrambled words and their tails. Made once per fill, not
/// per chunk, whose zeroing of 2 KiB would cost a noticeable part of the fill.
type OwenParts = [[u32; CHUNK]; 2];

/// Owen-scrambles a chunk of bit-reversed words, each `base ^ reversed[j]`, and converts them:
/// the 32-bit hashing first (a loop of independent integer operations), then the conversion,
/// because one loop doing both is vectorized at the width of the `f64` results, half as many
/// lanes.
#[inline(always)]
fn owen_chunk<T: Unit>(
    scramble: &OwenScramble,
    base: u32,
    reversed: &[u32],
    out: &mut [T],
    [words, tails]: &mut OwenParts,
) {
    let (words, tails) = (&mut words[..reversed.len()], &mut tails[..reversed.len()]);
    for ((w, t), &v) in words.iter_mut().zip(tails.iter_mut()).zip(reversed) {
        (*w, *t) = owen_parts(scramble, base ^ v);
    }
    for ((x, &w), &t) in out.iter_mut().zip(words.iter()).zip(tails.iter()) {
        *x = T::join(w, t);
    }
}

impl Sobol {
    /// Fills a checked block of either precision, split at pass boundaries.
    pub(super) fn fill_block<T: Unit>(&self, start: u64, points: &mut PointBlock<T>) {
        for (done, pass, first, n) in pass_runs(start, points.len(), 1 << PASS_BITS) {
            dispatch(FillRun {
                sobol: self,
                pass,
                first: first as u32,
                out: points,
                offset: done,
                len: n,
            });
        }
    }

    /// Fills `out` with in-pass points `first..` of one pass (no index shuffle), column by
    /// column: Gray-code words into a buffer, then scramble and convert.
    #[inline(always)]
    fn fill_run<T: Unit>(
        &self,
        pass: u64,
        first: u32,
        out: &mut PointBlock<T>,
        offset: usize,
        len: usize,
    ) {
        let pass_seed = self.pass_seed(pass);
        let mut parts: OwenParts = [[0; CHUNK]; 2];
        for (dim, directions) in self.directions.iter().enumerate() {
            let column = &mut out.column_mut(dim)[offset..offset + len];
            // The word of the first index of the aligned chunk holding `first`.
            let start = direct(directions, gray(first & !(CHUNK as u32 - 1)));
            // Dispatch once per column. The shift and the matrix scramble are linear, so they
            // fold into 53-bit start and direction words; Owen runs the Gray code on
            // bit-reversed words, which is what its hash consumes.
            match self.randomizer(pass_seed, dim) {
                Randomizer::None => gray_column(directions, start, first, column, |b, w, x| {
                    convert(b, w, x, T::from_word)
                }),
                Randomizer::Xor { shift } => {
                    let wide: WideDirections = directions.map(widen);
                    gray_column(&wide, widen(start) ^ shift, first, column, |b, w, x| {
                        convert(b, w, x, T::from_wide)
                    })
                }
                Randomizer::Lms { columns, shift } => {
                    let wide: WideDirections = directions.map(|v| linear(&columns, v));
                    let start = linear(&columns, start) ^ shift;
                    gray_column(&wide, start, first, column, |b, w, x| {
                        convert(b, w, x, T::from_wide)
                    })
                }
                Randomizer::Owen { scramble } => {
                    let reversed = reversed(directions);
                    gray_column(&reversed, start.reverse_bits(), first, column, |b, v, x| {
                        owen_chunk(&scramble, b, v, x, &mut parts)
                    })
                }
            }
        }
    }

    /// Like [`fill_run`](Self::fill_run) with the index shuffle (Owen only).
    #[inline(always)]
    fn fill_shuffled_run<T: Unit>(
        &self,
        pass: u64,
        first: u32,
        out: &mut PointBlock<T>,
        offset: usize,
        len: usize,
    ) {
        let pass_seed = self.pass_seed(pass);
        let shuffle = OwenScramble::new(Self::shuffle_seed(pass_seed));
        let mut shuffled = [0u32; CHUNK];
        let mut words = [0u32; CHUNK];
        let mut gathered = [0u32; CHUNK];
        let mut parts: OwenParts = [[0; CHUNK]; 2];
        let mut done = 0;
        while done < len {
            // A chunk never crosses a multiple of CHUNK, so its shuffled indices share their
            // high bits: they all lie in one aligned chunk of the sequence.
            let i0 = first.wrapping_add(done as u32);
            let n = (CHUNK - (i0 as usize & (CHUNK - 1))).min(len - done);
            let shuffled = &mut shuffled[..n];
            for (j, s) in shuffled.iter_mut().enumerate() {
                *s = shuffle.apply(i0.wrapping_add(j as u32));
            }
            let base = shuffled[0] & !(CHUNK as u32 - 1);
            for (dim, directions) in self.directions.iter().enumerate() {
                let column = &mut out.column_mut(dim)[offset + done..offset + done + n];
                let Randomizer::Owen { scramble } = self.randomizer(pass_seed, dim) else {
                    // Only Owen shuffles (see `shuffles`).
                    continue;
                };
                let reversed = reversed(directions);
                let gathered = &mut gathered[..n];
                if n < SHUFFLE_DIRECT_BELOW {
                    for (g, &s) in gathered.iter_mut().zip(shuffled.iter()) {
                        *g = direct(&reversed, gray(s));
                    }
                } else {
                    // The whole aligned chunk of sequence points by Gray code, then gathered.
                    chunk_words(&reversed, direct(&reversed, gray(base)), &mut words);
                    for (g, &s) in gathered.iter_mut().zip(shuffled.iter()) {
                        *g = words[s as usize & (CHUNK - 1)];
                    }
                }
                owen_chunk(&scramble, 0, gathered, column, &mut parts);
            }
            done += n;
        }
    }
}

/// A fill of one pass's run of points, compiled for each instruction set by [`dispatch`].
struct FillRun<'a, T> {
    sobol: &'a Sobol,
    pass: u64,
    first: u32,
    out: &'a mut PointBlock<T>,
    offset: usize,
    len: usize,
}

impl<T: Unit> Kernel for FillRun<'_, T> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let FillRun {
            sobol,
            pass,
            first,
            out,
            offset,
            len,
        } = self;
        if sobol.shuffles() {
            sobol.fill_shuffled_run(pass, first, out, offset, len);
        } else {
            sobol.fill_run(pass, first, out, offset, len);
        }
    }
}

/// Writes the words of the first `words.len()` indices of an aligned chunk (its first index a
/// multiple of `CHUNK`), given the word of its first index. For `j < 2^k`, `gray(2^k + j) =
/// gray(2^k) ^ gray(j)`, so the words of offsets `2^k..2^(k+1)` are those of `0..2^k` XOR one
/// word: each doubling is a loop of independent XORs (vectorized), where stepping index by
/// index would be a serial chain.
#[inline(always)]
fn chunk_words<W: Copy + Default + BitXorAssign>(directions: &[W; 32], first: W, words: &mut [W]) {
    let Some((head, _)) = words.split_first_mut() else {
        return;
    };
    *head = first;
    let mut done = 1;
    // The word of gray(2^k) = 2^k ^ 2^(k - 1) relative to offset 0.
    let mut step = directions[0];
    for k in 1.. {
        let (known, rest) = words.split_at_mut(done);
        let n = rest.len().min(done);
        for (w, &v) in rest[..n].iter_mut().zip(known.iter()) {
            *w = v;
            *w ^= step;
        }
        done += n;
        if done == words.len() {
            break;
        }
        step = directions[k];
        step ^= directions[k - 1];
    }
}

/// One column of a run of consecutive in-pass indices starting at `first`, given `start`, the
/// word of the first index of the aligned chunk holding `first`. The words of a chunk's
/// offsets relative to its first word are the same for every chunk of the column: they are
/// made once ([`chunk_words`]), and `finish(base, offsets, out)` scrambles and converts
/// `base ^ offsets[j]` for the chunk's part of the column, in loops free of loop-carried
/// dependencies (made per chunk, the small first doublings' stores stalled the wide loads of
/// the next, 16% of the fill). Monomorphized per scramble, so the inner loops do not branch on
/// it.
#[inline(always)]
fn gray_column<W: Copy + Default + BitXorAssign, T, F: FnMut(W, &[W], &mut [T])>(
    directions: &[W; 32],
    start: W,
    first: u32,
    column: &mut [T],
    mut finish: F,
) {
    let mut skip = first as usize & (CHUNK - 1);
    let mut offsets = [W::default(); CHUNK];
    let made = (skip + column.len()).min(CHUNK);
    chunk_words(directions, W::default(), &mut offsets[..made]);
    let mut word = start;
    let mut base = first & !(CHUNK as u32 - 1);
    let mut rest = column;
    while !rest.is_empty() {
        let end = (skip + rest.len()).min(CHUNK);
        let (out, tail) = rest.split_at_mut(end - skip);
        finish(word, &offsets[skip..end], out);
        rest = tail;
        skip = 0;
        // The next chunk's first word: consecutive Gray codes differ in bit ctz(i) of the later
        // index i (ctz(0) = 32 only past the end of a pass, where the word is never used).
        base = base.wrapping_add(CHUNK as u32);
        word ^= offsets[CHUNK - 1];
        word ^= directions[(base.trailing_zeros() & 31) as usize];
    }
}

/// Converts the words `base ^ offsets[j]` of a chunk one by one.
#[inline(always)]
fn convert<W: Copy + BitXorAssign, T>(
    base: W,
    offsets: &[W],
    out: &mut [T],
    to_unit: impl Fn(W) -> T,
) {
    for (x, &offset) in out.iter_mut().zip(offsets) {
        let mut w = base;
        w ^= offset;
        *x = to_unit(w);
    }
}
