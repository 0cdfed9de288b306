//! The block kernel of Owen-scrambled radical inverses: the same integers as
//! [`owen_coordinate`](super::owen::owen_coordinate), computed once per node instead of once per
//! index where indices share nodes, and column by column in lanes of 32 indices.
//!
//! The scrambled numerator of `index` is `sum_k pi_(k, index mod b^k)(a_k) b^(K-1-k)` over the
//! positions `k < K`, where the image at position `k` depends on `index mod b^(k+1)` only
//! (the prefix and the digit). A pass meets each `(prefix, digit)` pair of a position with few
//! residues many times, in many blocks: the images of every position with at most 2^16
//! residues live in tables indexed by `index mod b^(k+1)`, and the nodes of the position above
//! them in a table indexed by the prefix, both kept by the filling thread for the whole pass
//! (`node_memo.rs`) and filled for the residues the blocks meet. The positions whose table a
//! block meets whole ("shallow") add up to one number per residue mod `b^shallow`. Deeper
//! positions have a different prefix for every index and are computed per index, and the zero
//! digits beyond the last digit of each index (the tail) word by word of its stream. The node
//! work runs in lanes through `crate::simd`: the hashes, the digits (by a floating-point
//! division) and the node permutations (Fisher-Yates from one hash up to base 13, in byte
//! lanes; an affine map above) vectorize. The sum is exact in integers whatever the order, and
//! rounded once as in `owen_coordinate`, so the values are bit-identical.
//!
//! It exists for speed alone: `cargo bench --bench samplers -- owen_halton_block_vs_point`
//! measures it against `owen_coordinate` value by value (`docs/measurements.md` keeps the
//! figures).

use super::base::{Base, MAX_DEPTH};
#[cfg(test)]
use super::digit_permutation::small_permutation;
use super::digit_permutation::{SMALL_BASE, TAG_RHO, affine_slope, rotate};
use super::node_memo::{ColumnTables, MEMO_RESIDUES, UNSEEN, admit, with_tables};
use crate::float::ONE_BELOW;
use crate::hash::{golden_step, hash_absorb, hash_absorb_scaled, hash_start};
use crate::sampler::permutation::below_narrow;
use crate::simd::{Kernel, dispatch};

/// Lanes of the node kernel.
const LANES: usize = 32;

/// Reusable buffers of the Owen block kernel.
#[derive(Default)]
pub(crate) struct OwenScratch {
    /// Digit images of one deep position for the indices of a run.
    images: Vec<u32>,
    /// `sum_k image_k b^(w-1-k)` over the deep positions `k` of each index.
    deep: Vec<u64>,
    /// The tail runs of each index, one array per word of the stream.
    tails: Vec<u64>,
    /// The shallow positions' part of the numerator, by residue mod `b^shallow`.
    lows: Vec<u64>,
}

/// The node permutations of a base, as the kernels evaluate them (see
/// [`owen_digit_image`](super::digit_permutation::owen_digit_image)).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RhoKind {
    /// Base 2: `pi(1) = 1 - pi(0)`.
    Two,
    /// `rho` by Fisher-Yates decoded from one hash (`small_permutation`), in lanes.
    Small,
    /// An affine map `pi(a) = (alpha a + pi(0)) mod b`, bases above 13.
    Affine,
}

/// What the kernels need of one (base, key).
#[derive(Debug, Clone, Copy)]
struct Nodes {
    b: u64,
    b_f64: f64,
    kind: RhoKind,
    /// [`hash_start`] of the key, and of the key of the `rho` hashes.
    words: u64,
    rhos: u64,
}

impl Nodes {
    /// The images at position `k` (stream word `word`, `scale = b^(k % m)`, `power = b^k`)
    /// of the integers `r = first + j` (below 2^40), whose node has prefix `r mod b^k` and
    /// whose digit is `(r / b^k) mod b`, into `images[j]`.
    #[inline(always)]
    fn images(&self, k: usize, word: u64, scale: u64, power: u64, first: u64, images: &mut [u32]) {
        let Nodes {
            b,
            b_f64,
            kind,
            words,
            rhos,
        } = *self;
        let power_f64 = power as f64;
        for (chunk, out) in images.chunks_mut(LANES).enumerate() {
            let mut digits = [0u64; LANES];
            let mut zeros = [0u64; LANES];
            let mut keys = [0u64; LANES];
            for j in 0..LANES {
                let r = first + (chunk * LANES + j) as u64;
                let (high, prefix) = div_rem(r, power, power_f64);
                digits[j] = div_rem(high, b, b_f64).1;
                // pi(0): digit k of the node's stream; rho's key: a hash of the node (base 2
                // needs none).
                let word = hash_absorb(words, (prefix << 6) | word);
                zeros[j] = below_narrow(word.wrapping_mul(scale), b);
                if kind != RhoKind::Two {
                    keys[j] = hash_absorb(rhos, (prefix << 6) | k as u64);
                }
            }
            // rho(digit - 1) for the non-zero digits (0 stands in for the others).
            let mut rests = digits.map(|digit| digit.saturating_sub(1));
            if kind == RhoKind::Small {
                small_permutation_lanes(b - 1, &keys, &mut rests);
            }
            for (j, image) in out.iter_mut().enumerate() {
                let (zero, digit) = (zeros[j], digits[j]);
                // Digit images are below b < 2^17; alpha digit + zero < b^2 < 2^34.
                *image = match (kind, digit) {
                    (RhoKind::Two, _) => zero ^ digit,
                    (_, 0) => zero,
                    (RhoKind::Small, _) => rotate(b, zero, rests[j]),
                    (RhoKind::Affine, _) => {
                        div_rem(affine_slope(keys[j], b) * digit + zero, b, b_f64).1
                    }
                } as u32;
            }
        }
    }

    /// The nodes at position `k` (stream word `word`, `scale = b^(k % m)`) with prefixes
    /// `p = first + j`, each as one word `parts[j]` that [`Nodes::image`] reads: `pi(0)` in base
    /// 2; `pi(0) | alpha << 32` for the affine maps above base 13; the images `pi(0), ..,
    /// pi(b-1)` in 4-bit fields (b <= 13) otherwise. The same maps as [`Nodes::images`].
    #[inline(always)]
    fn parts(&self, k: usize, word: u64, scale: u64, first: u64, parts: &mut [u64]) {
        let Nodes {
            b,
            kind,
            words,
            rhos,
            ..
        } = *self;
        if kind == RhoKind::Small {
            // In lanes: the choices of each node's rho once, then where each digit goes.
            for (chunk, out) in parts.chunks_mut(LANES).enumerate() {
                let mut zeros = [0u64; LANES];
                let mut keys = [0u64; LANES];
                for j in 0..LANES {
                    let prefix = first + (chunk * LANES + j) as u64;
                    let word = hash_absorb(words, (prefix << 6) | word);
                    zeros[j] = below_narrow(word.wrapping_mul(scale), b);
                    keys[j] = hash_absorb(rhos, (prefix << 6) | k as u64);
                }
                let choices = small_choices(b - 1, &keys);
                let mut packed = zeros;
                for a in 1..b {
                    let mut rests = [a as u8 - 1; LANES];
                    small_follow(b - 1, &choices, &mut rests);
                    for ((packed, &zero), &rest) in packed.iter_mut().zip(&zeros).zip(&rests) {
                        *packed |= rotate(b, zero, u64::from(rest)) << (4 * a);
                    }
                }
                out.copy_from_slice(&packed[..out.len()]);
            }
            return;
        }
        for (part, prefix) in parts.iter_mut().zip(first..) {
            let zero = below_narrow(
                hash_absorb(words, (prefix << 6) | word).wrapping_mul(scale),
                b,
            );
            let key = || hash_absorb(rhos, (prefix << 6) | k as u64);
            *part = match kind {
                RhoKind::Two => zero,
                RhoKind::Affine => zero | affine_slope(key(), b) << 32,
                RhoKind::Small => unreachable!("computed in lanes above"),
            };
        }
    }

    /// `pi(digit)` of a node stored by [`Nodes::parts`].
    #[inline(always)]
    fn image(&self, part: u64, digit: u64) -> u64 {
        match self.kind {
            RhoKind::Two => part ^ digit,
            RhoKind::Affine => {
                div_rem(
                    (part >> 32) * digit + (part & 0xffff_ffff),
                    self.b,
                    self.b_f64,
                )
                .1
            }
            RhoKind::Small => (part >> (4 * digit)) & 0xf,
        }
    }
}

/// `small_permutation(keys[j], n, xs[j])` lane by lane (`n <= 12`), without the array
/// of items: Fisher-Yates swaps position `j` with the choice `c_j` for `j = n-1, .., 1`, so
/// the item that ends at position `x` started at `S_(n-1)(..(S_1(x)))`, with `S_j` the
/// transposition of `j` and `c_j`: the choices first, then the position followed through
/// the transpositions in reverse order, all by compares and selects.
#[inline(always)]
fn small_permutation_lanes(n: u64, keys: &[u64; LANES], xs: &mut [u64; LANES]) {
    let choices = small_choices(n, keys);
    let mut positions = xs.map(|x| x as u8);
    small_follow(n, &choices, &mut positions);
    *xs = positions.map(u64::from);
}

/// The Fisher-Yates choices `c_j` (`j = n-1, .., 1`) of [`small_permutation_lanes`] for each
/// key, as bytes (`c_j <= j < 12`).
#[inline(always)]
fn small_choices(n: u64, keys: &[u64; LANES]) -> [[u8; LANES]; SMALL_BASE as usize] {
    debug_assert!(n <= SMALL_BASE);
    let mut choices = [[0u8; LANES]; SMALL_BASE as usize];
    let mut hashes = *keys;
    for j in (1..n).rev() {
        for (choice, h) in choices[j as usize].iter_mut().zip(hashes.iter_mut()) {
            // The high and low words of h * (j + 1), from 32-bit halves (j + 1 <= 12).
            let high = ((*h >> 32) * (j + 1) + (((*h & 0xffff_ffff) * (j + 1)) >> 32)) >> 32;
            *choice = high as u8;
            *h = h.wrapping_mul(j + 1);
        }
    }
    choices
}

/// Follows positions `xs` through the transpositions of `choices` (from
/// [`small_choices`]), in byte lanes.
#[inline(always)]
fn small_follow(n: u64, choices: &[[u8; LANES]; SMALL_BASE as usize], xs: &mut [u8; LANES]) {
    for j in 1..n as u8 {
        for (x, &choice) in xs.iter_mut().zip(&choices[j as usize]) {
            *x = if *x == j {
                choice
            } else if *x == choice {
                j
            } else {
                *x
            };
        }
    }
}

/// `(c / m, c % m)` for `c < 2^52` and `1 <= m < 2^52`, without an integer division (which
/// does not vectorize): the correctly rounded quotient, rounded to an integer by adding
/// `2^52` (where doubles are integers) and read from its bits rather than converted (a
/// saturating conversion does not vectorize either), is within one of the true one, and the
/// remainder's sign and size say which way to correct.
#[inline(always)]
fn div_rem(c: u64, m: u64, m_f64: f64) -> (u64, u64) {
    const SHIFTER: f64 = (1u64 << 52) as f64;
    // c as a double by the same shifter (exact below 2^52; `as f64` does not vectorize
    // before AVX-512).
    let c_f64 = f64::from_bits(c | SHIFTER.to_bits()) - SHIFTER;
    let q = (c_f64 / m_f64 + SHIFTER).to_bits() - SHIFTER.to_bits();
    let r = c.wrapping_sub(q.wrapping_mul(m));
    let low = u64::from((r as i64) < 0);
    let high = u64::from((r as i64) >= 0 && r >= m);
    (
        q.wrapping_sub(low).wrapping_add(high),
        r.wrapping_add(m & low.wrapping_neg())
            .wrapping_sub(m & high.wrapping_neg()),
    )
}

/// The work of [`Nodes`] for one position over a run, compiled for each instruction set by
/// [`dispatch`]: the digit images of residues `first, first + 1, ..` (`power = b^k`), or the
/// nodes of prefixes `first, first + 1, ..`.
struct NodeRun<'a> {
    nodes: &'a Nodes,
    k: usize,
    word: u64,
    scale: u64,
    first: u64,
    output: NodeOutput<'a>,
}

/// What a [`NodeRun`] writes.
enum NodeOutput<'a> {
    Images { power: u64, images: &'a mut [u32] },
    Parts(&'a mut [u64]),
}

impl Kernel for NodeRun<'_> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let NodeRun {
            nodes,
            k,
            word,
            scale,
            first,
            output,
        } = self;
        match output {
            NodeOutput::Images { power, images } => {
                nodes.images(k, word, scale, power, first, images)
            }
            NodeOutput::Parts(parts) => nodes.parts(k, word, scale, first, parts),
        }
    }
}

/// The tail runs of the indices `first + j`: the digits `k .. k + count` of each index's own
/// stream (word `word`, `scale = b^(k % m)`, `range = b^count`), into `runs[j]`; compiled for
/// each instruction set by [`dispatch`].
struct TailRuns<'a> {
    words: u64,
    word: u64,
    scale: u64,
    range: u64,
    first: u64,
    runs: &'a mut [u64],
}

impl Kernel for TailRuns<'_> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let TailRuns {
            words,
            word,
            scale,
            range,
            first,
            runs,
        } = self;
        // The words (index << 6) | word of consecutive indices are 64 apart: their products
        // with the hash's multiplier step by a constant.
        let step = golden_step(64);
        let mut scaled = golden_step((first << 6) | word);
        for run in runs.iter_mut() {
            let hash = hash_absorb_scaled(words, scaled);
            *run = below_narrow(hash.wrapping_mul(scale), range);
            scaled = scaled.wrapping_add(step);
        }
    }
}

/// Cuts `slots` into the straight runs of a cyclic range: slot `j` stands at `(from + j) mod
/// cycle`, and `f(run, at, turn)` gets each run with the cycle position of its first slot and
/// how many times the range has wrapped before it.
fn cyclic_runs(
    slots: &mut [u64],
    from: usize,
    cycle: usize,
    mut f: impl FnMut(&mut [u64], usize, usize),
) {
    let (mut rest, mut at, mut turn) = (slots, from, 0);
    while !rest.is_empty() {
        let (now, later) = rest.split_at_mut(rest.len().min(cycle - at));
        f(now, at, turn);
        (rest, at, turn) = (later, 0, turn + 1);
    }
}

/// The values of a run of indices in a base with `b^K` below `2^64`: the shallow part
/// `lows[r]` (residues `r` from `residue` on, cyclically), the deep part and the tail runs
/// summed in 64-bit integers and rounded once; compiled for each instruction set by
/// [`dispatch`] (where the bit scans of the rounding are single instructions).
struct NarrowValues<'a> {
    base: &'a Base,
    lows: &'a [u64],
    residue: usize,
    deep: &'a [u64],
    deep_scale: u64,
    head_weight: u64,
    /// One array of `deep.len()` runs per tail word.
    tails: &'a [u64],
    tail_weights: &'a [u64],
    out: &'a mut [f64],
}

impl Kernel for NarrowValues<'_> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let count = self.deep.len();
        let mut residue = self.residue;
        for (j, (x, &deep)) in self.out.iter_mut().zip(self.deep).enumerate() {
            let mut num = (self.lows[residue] * self.deep_scale + deep) * self.head_weight;
            for (t, &w) in self.tail_weights.iter().enumerate() {
                num += self.tails[t * count + j] * w;
            }
            *x = self.base.ratio_narrow(num).min(ONE_BELOW);
            residue += 1;
            if residue == self.lows.len() {
                residue = 0;
            }
        }
    }
}

/// Writes the Owen-scrambled coordinates of local indices `first, first + 1, ...` (one pass,
/// below `2^40`) in `base` for the (pass, dimension) `key`, bit-identical to
/// [`owen_coordinate`](super::owen::owen_coordinate).
pub(super) fn fill_owen(base: &Base, key: u64, first: u64, out: &mut [f64], s: &mut OwenScratch) {
    if out.is_empty() {
        return;
    }
    // Tables kept by the thread when it has room for them, else tables of this block only.
    let mut column = Column::new(base, key, first, out.len(), true);
    let kept = admit(base.base, key, column.slots());
    if !kept {
        column = Column::new(base, key, first, out.len(), false);
    }
    let starts = &column.table_start[..=column.memoized];
    let node_starts = &column.node_start[..=column.noded];
    with_tables(base.base, key, kept, starts, node_starts, |tables| {
        column.complete_tables(tables, first, out.len());
        column.shallow_parts(tables, &mut s.lows);
        // Runs of indices with the same number of digits w: positions shallow .. w, then the
        // tail of zero digits from max(shallow, w) on, read from each index's own stream.
        s.deep.clear();
        s.deep.resize(out.len(), 0);
        let mut done = 0usize;
        let mut width = (0..=column.positions)
            .find(|&j| column.powers[j] > first)
            .unwrap_or(column.positions);
        while done < out.len() {
            let start = first + done as u64;
            while column.powers[width] <= start {
                width += 1;
            }
            let end = if width < column.positions {
                (column.powers[width] - first).min(out.len() as u64) as usize
            } else {
                out.len()
            };
            let deep = &mut s.deep[done..end];
            for k in column.shallow..width {
                column.add_position(k, tables, start, deep, &mut s.images);
            }
            let top = width.max(column.shallow);
            let (tail_weights, tail_count) = column.tail_runs(start, end - done, top, &mut s.tails);
            let parts = Parts {
                lows: &s.lows,
                deep,
                tails: &s.tails,
                tail_weights: &tail_weights[..tail_count],
            };
            column.values(start, top, &parts, &mut out[done..end]);
            done = end;
        }
    });
}

/// What one fill of one column knows of its base, its nodes and its indices.
struct Column<'a> {
    base: &'a Base,
    nodes: Nodes,
    /// `powers[j] = b^j` for `j <= positions`, the digits of the block's last index
    /// (`b^positions <= last * b < 2^57`).
    powers: [u64; MAX_DEPTH + 2],
    positions: usize,
    /// `weights[k] = b^(K-1-k)`, the weight of position `k` in the numerator over `b^K`.
    weights: [u128; MAX_DEPTH],
    /// Digit `k` of a stream is digit `k % m` of its word number `k / m`: `floor(frac(word
    /// b^(k % m) / 2^64) b)` (see `stream_digits`); a run from digit `k` to the end of its word
    /// spells `floor(frac(word b^(k % m) / 2^64) b^run)`.
    word_of: [u64; MAX_DEPTH],
    scale_of: [u64; MAX_DEPTH],
    run_of: [usize; MAX_DEPTH],
    run_range: [u64; MAX_DEPTH],
    /// Positions `k < memoized` have image tables (`b^(k+1) <= MEMO_RESIDUES` when the tables
    /// are kept across the fills of the thread, see `node_memo`; at most the block length
    /// otherwise), position `k` at `table_start[k] .. table_start[k + 1]`; positions below
    /// `shallow` are met whole by the block (`b^(k+1)` at most its length), so their part of a
    /// value is one number per residue mod `b^shallow`.
    memoized: usize,
    shallow: usize,
    table_start: [usize; MAX_DEPTH + 1],
    /// The nodes of positions `k < noded` (`b^k <= MEMO_RESIDUES`, each serving `b` digits)
    /// have tables too, position `k`'s at `node_start[k] .. node_start[k + 1]`: those that fill
    /// the image tables, and, when the tables are kept, those of `node_position`, the position
    /// above them, whose `b^(k+1)` residues are too many for a table but whose `node_count =
    /// b^k` nodes are not (`usize::MAX` otherwise).
    noded: usize,
    node_start: [usize; MAX_DEPTH + 2],
    node_position: usize,
    node_count: u64,
}

/// The parts of the numerators of a run of indices, for [`Column::values`].
struct Parts<'a> {
    /// The shallow part, by residue mod `b^shallow`.
    lows: &'a [u64],
    /// The part of the positions from `shallow` to the index's digits.
    deep: &'a [u64],
    /// The tail runs, one array of `deep.len()` per stream word, and their weights.
    tails: &'a [u64],
    tail_weights: &'a [u128],
}

impl<'a> Column<'a> {
    /// The column's layout for the block of `len` indices from `first`, with tables kept by
    /// the thread (`kept`) or for this block only.
    fn new(base: &'a Base, key: u64, first: u64, len: usize, kept: bool) -> Self {
        let (b, m, depth) = (base.base, base.per_word as usize, base.depth);
        let last = first + len as u64 - 1;
        let mut powers = [1u64; MAX_DEPTH + 2];
        let mut positions = 0;
        while powers[positions] <= last {
            powers[positions + 1] = powers[positions] * b;
            positions += 1;
        }
        let mut weights = [0u128; MAX_DEPTH];
        let mut weight = 1u128;
        for w in weights[..depth].iter_mut().rev() {
            *w = weight;
            weight *= u128::from(b);
        }
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
        let limit = if kept { MEMO_RESIDUES } else { len as u64 };
        let mut memoized = 0;
        while memoized < positions && powers[memoized + 1] <= limit {
            memoized += 1;
        }
        let mut shallow = 0;
        while shallow < memoized && powers[shallow + 1] <= len as u64 {
            shallow += 1;
        }
        let mut table_start = [0usize; MAX_DEPTH + 1];
        for k in 0..memoized {
            table_start[k + 1] = table_start[k] + powers[k + 1] as usize;
        }
        let (mut node_position, mut node_count) = (0, 1u64);
        while node_count * b <= MEMO_RESIDUES {
            node_count *= b;
            node_position += 1;
        }
        if !kept {
            node_position = usize::MAX;
        }
        let noded = if kept {
            positions.min(node_position + 1)
        } else {
            memoized
        };
        let mut node_start = [0usize; MAX_DEPTH + 2];
        for k in 0..noded {
            node_start[k + 1] = node_start[k] + powers[k] as usize;
        }
        let nodes = Nodes {
            b,
            b_f64: b as f64,
            kind: match b {
                2 => RhoKind::Two,
                _ if b <= SMALL_BASE => RhoKind::Small,
                _ => RhoKind::Affine,
            },
            words: hash_start(key),
            rhos: hash_start(key ^ TAG_RHO),
        };
        Column {
            base,
            nodes,
            powers,
            positions,
            weights,
            word_of,
            scale_of,
            run_of,
            run_range,
            memoized,
            shallow,
            table_start,
            noded,
            node_start,
            node_position,
            node_count,
        }
    }

    /// Table slots of the layout (a node counts two).
    fn slots(&self) -> usize {
        self.table_start[self.memoized] + 2 * self.node_start[self.noded]
    }

    /// The node work at position `k` over a run from `first` (see [`NodeRun`]).
    fn run_nodes(&self, k: usize, first: u64, output: NodeOutput<'_>) {
        dispatch(NodeRun {
            nodes: &self.nodes,
            k,
            word: self.word_of[k],
            scale: self.scale_of[k],
            first,
            output,
        });
    }

    /// Computes the table slots the block of `len` indices from `first` meets and the thread
    /// has not computed yet (the residues from `first mod b^(k+1)` on, cyclically), from the
    /// nodes of their prefixes, each computed once per pass for its `b` digits.
    fn complete_tables(&self, tables: &mut ColumnTables<'_>, first: u64, len: usize) {
        for k in 0..self.memoized {
            if tables.is_complete(k) {
                continue;
            }
            self.complete_nodes(k, tables, first, len);
            let (size, prefixes) = (self.powers[k + 1], self.powers[k]);
            let compute = |nodes: &[u64], first: u64, images: &mut [u32]| {
                // Residue r = prefix + digit b^k, the prefix advancing and the digit with
                // each cycle of prefixes.
                let (mut prefix, mut digit) = ((first % prefixes) as usize, first / prefixes);
                for image in images.iter_mut() {
                    *image = self.nodes.image(nodes[prefix], digit) as u32;
                    prefix += 1;
                    if prefix == nodes.len() {
                        (prefix, digit) = (0, digit + 1);
                    }
                }
            };
            let from = first % size;
            let count = (len as u64).min(size);
            let straight = count.min(size - from);
            tables.complete(k, from as usize, straight as usize, compute);
            tables.complete(k, 0, (count - straight) as usize, compute);
        }
    }

    /// Computes the nodes at position `k` of the prefixes that the block of `len` indices from
    /// `first` meets and the thread has not computed yet: `first mod b^k` on, cyclically.
    fn complete_nodes(&self, k: usize, tables: &mut ColumnTables<'_>, first: u64, len: usize) {
        let prefixes = self.powers[k];
        let from = first % prefixes;
        let count = (len as u64).min(prefixes);
        let straight = count.min(prefixes - from);
        let compute =
            |first: u64, parts: &mut [u64]| self.run_nodes(k, first, NodeOutput::Parts(parts));
        tables.complete_nodes(k, from as usize, straight as usize, compute);
        tables.complete_nodes(k, 0, (count - straight) as usize, compute);
    }

    /// `lows[r] = sum_(k < shallow) image_k(r mod b^(k+1)) b^(shallow-1-k)` for `r <
    /// b^shallow`, built position by position in place, each level from the one before.
    fn shallow_parts(&self, tables: &ColumnTables<'_>, lows: &mut Vec<u64>) {
        let b = self.nodes.b;
        lows.clear();
        lows.resize(self.powers[self.shallow] as usize, 0);
        for (k, &below) in self.powers[..self.shallow].iter().enumerate() {
            let below = below as usize;
            let table = tables.table(k);
            // Level k+1 at q b^k + r from level k at r: the block q = 0, which the others
            // read, last.
            for q in (0..b as usize).rev() {
                for r in 0..below {
                    let image = table[q * below + r];
                    debug_assert!(image != UNSEEN);
                    lows[q * below + r] = lows[r] * b + u64::from(image);
                }
            }
        }
    }

    /// Adds position `k` to the numerators `deep` of the indices `start, start + 1, ..`
    /// (`deep = deep * b + image`): from its table, from the kept nodes, or node by node.
    fn add_position(
        &self,
        k: usize,
        tables: &mut ColumnTables<'_>,
        start: u64,
        deep: &mut [u64],
        images: &mut Vec<u32>,
    ) {
        let b = self.nodes.b;
        if k < self.memoized {
            // The residues from start mod b^(k+1) on, cyclically.
            let table = tables.table(k);
            let from = (start % self.powers[k + 1]) as usize;
            cyclic_runs(deep, from, table.len(), |now, at, _| {
                for (acc, &image) in now.iter_mut().zip(&table[at..]) {
                    *acc = *acc * b + u64::from(image);
                }
            });
        } else if k == self.node_position {
            // The nodes of prefixes start mod b^k on, cyclically, the digit advancing with each
            // cycle.
            self.complete_nodes(k, tables, start, deep.len());
            let nodes = tables.nodes(k);
            let from = (start % self.node_count) as usize;
            let digit = (start / self.node_count) % b;
            cyclic_runs(deep, from, nodes.len(), |now, at, turn| {
                let digit = (digit + turn as u64) % b;
                for (acc, &part) in now.iter_mut().zip(&nodes[at..]) {
                    *acc = *acc * b + self.nodes.image(part, digit);
                }
            });
        } else {
            images.clear();
            images.resize(deep.len(), 0);
            // Residue index mod b^(k+1) or the index itself: the same prefix and digit.
            let power = self.powers[k];
            self.run_nodes(k, start, NodeOutput::Images { power, images });
            for (acc, &image) in deep.iter_mut().zip(images.iter()) {
                *acc = *acc * b + u64::from(image);
            }
        }
    }

    /// The tail runs of `count` indices from `start`, from position `top` on, one array per
    /// stream word in `tails`; returns their weights and how many there are.
    fn tail_runs(
        &self,
        start: u64,
        count: usize,
        top: usize,
        tails: &mut Vec<u64>,
    ) -> ([u128; MAX_DEPTH], usize) {
        let mut weights = [0u128; MAX_DEPTH];
        let mut words = 0;
        let mut k = top;
        tails.clear();
        while k < self.base.depth {
            let at = tails.len();
            tails.resize(at + count, 0);
            dispatch(TailRuns {
                words: self.nodes.words,
                word: self.word_of[k],
                scale: self.scale_of[k],
                range: self.run_range[k],
                first: start,
                runs: &mut tails[at..],
            });
            weights[words] = self.weights[k + self.run_of[k] - 1];
            words += 1;
            k += self.run_of[k];
        }
        (weights, words)
    }

    /// The values of the indices from `start`, whose positions below `top = max(w, shallow)`
    /// form one integer below `b^top < 2^57`: the shallow part times `b^(top - shallow)` plus
    /// the deep part, of weight `b^(K - top)`, then the tail; summed exactly and rounded once.
    fn values(&self, start: u64, top: usize, parts: &Parts<'_>, out: &mut [f64]) {
        let deep_scale = self.powers[top - self.shallow];
        let head_weight = self.weights[top.max(1) - 1];
        let residue = (start % self.powers[self.shallow]) as usize;
        if u64::try_from(self.base.full).is_ok() {
            // b^K below 2^64 (bases below 2^11): the same sums in 64-bit integers.
            let mut tail_weights = [0u64; MAX_DEPTH];
            for (narrow, &w) in tail_weights.iter_mut().zip(parts.tail_weights) {
                *narrow = w as u64;
            }
            dispatch(NarrowValues {
                base: self.base,
                lows: parts.lows,
                residue,
                deep: parts.deep,
                deep_scale,
                head_weight: head_weight as u64,
                tails: parts.tails,
                tail_weights: &tail_weights[..parts.tail_weights.len()],
                out,
            });
            return;
        }
        let (count, mut residue) = (parts.deep.len(), residue);
        for (j, (x, &deep)) in out.iter_mut().zip(parts.deep).enumerate() {
            let mut num = u128::from(parts.lows[residue] * deep_scale + deep) * head_weight;
            for (t, &w) in parts.tail_weights.iter().enumerate() {
                num += u128::from(parts.tails[t * count + j]) * w;
            }
            *x = self.base.ratio(num).min(ONE_BELOW);
            residue += 1;
            if residue == parts.lows.len() {
                residue = 0;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::owen::owen_coordinate;
    use super::*;
    use crate::hash::mix64;

    #[test]
    fn small_permutations_in_lanes_equal_fisher_yates() {
        for n in 1..=12u64 {
            for round in 0..200u64 {
                let keys: [u64; LANES] = std::array::from_fn(|j| mix64(round * 64 + j as u64));
                let mut xs: [u64; LANES] = std::array::from_fn(|j| j as u64 % n);
                let expected: [u64; LANES] =
                    std::array::from_fn(|j| small_permutation(keys[j], n, xs[j]));
                small_permutation_lanes(n, &keys, &mut xs);
                assert_eq!(xs, expected, "n {n}");
            }
        }
    }

    #[test]
    fn blocks_with_shared_nodes_equal_single_coordinates() {
        // Bases where a block of 4096 meets each node of its first deep position 2 to 61 times
        // (17 and 67) or once (61, 127), and one where the shared path's last lanes pass the
        // last node (113 = 3 * 32 + 17); runs starting mid-node and near the end of a pass.
        let mut s = OwenScratch::default();
        for b in [17u64, 61, 67, 113, 127] {
            let base = Base::new(b);
            for (first, len) in [(0u64, 4096usize), (12_345, 4096), ((1 << 40) - 5000, 5000)] {
                let key = mix64(b ^ first);
                let mut out = vec![0.0; len];
                fill_owen(&base, key, first, &mut out, &mut s);
                for (j, &x) in out.iter().enumerate() {
                    let expected = owen_coordinate(&base, key, first + j as u64);
                    assert_eq!(
                        x.to_bits(),
                        expected.to_bits(),
                        "base {b}, index {}",
                        first + j as u64
                    );
                }
            }
        }
    }

    #[test]
    fn blocks_in_any_order_equal_single_coordinates_whatever_the_memo_holds() {
        // Blocks of two columns of one base, interleaved (each switch resets the thread's
        // tables), of varying lengths, overlapping and out of order, so the memo holds a
        // different mix of computed and unseen slots at every fill. Indices up to 73,000 reach
        // the kept nodes of every kind (digit position 16 in base 2, 10 in base 3, 6 in base
        // 5, 4 in base 13, 3 in base 29).
        let mut s = OwenScratch::default();
        let mut h = 3u64;
        for b in [2u64, 3, 5, 13, 29] {
            let base = Base::new(b);
            let keys = [mix64(b), mix64(b + 1)];
            for round in 0..24u64 {
                h = mix64(h ^ round);
                let key = keys[usize::from(round % 5 == 4)];
                let first = h % 70_000;
                let len = 1 + (h >> 20) as usize % 3000;
                let mut out = vec![0.0; len];
                fill_owen(&base, key, first, &mut out, &mut s);
                for (j, &x) in out.iter().enumerate().step_by(7) {
                    let expected = owen_coordinate(&base, key, first + j as u64);
                    assert_eq!(x.to_bits(), expected.to_bits(), "base {b}, round {round}");
                }
            }
        }
    }

    #[test]
    fn blocks_without_kept_tables_equal_single_coordinates() {
        // A thread whose memo is full fills new columns with tables of the block only.
        let hog = super::super::node_memo::BUDGET;
        assert!(admit(2, 0, hog));
        with_tables(2, 0, true, &[0, hog], &[], |_| ());
        let mut s = OwenScratch::default();
        for b in [3u64, 13, 29, 113] {
            let base = Base::new(b);
            let key = mix64(b);
            for (first, len) in [(0u64, 1024usize), (40_000, 3000), ((1 << 40) - 700, 700)] {
                // The full column stays in use (an idle one would be forgotten).
                assert!(admit(2, 0, hog));
                let column = Column::new(&base, key, first, len, true);
                assert!(!admit(b, key, column.slots()), "base {b} was admitted");
                let mut out = vec![0.0; len];
                fill_owen(&base, key, first, &mut out, &mut s);
                for (j, &x) in out.iter().enumerate().step_by(3) {
                    let expected = owen_coordinate(&base, key, first + j as u64);
                    assert_eq!(
                        x.to_bits(),
                        expected.to_bits(),
                        "base {b}, index {first} + {j}"
                    );
                }
            }
        }
    }

    #[test]
    fn division_free_helpers_are_exact() {
        let mut h = 1u64;
        for m in [
            1u64,
            2,
            3,
            7,
            131,
            65_521,
            104_729,
            3u64.pow(25),
            (1 << 40) - 3,
        ] {
            for k in 0..3000u64 {
                h = mix64(h ^ k);
                let near = ((h >> 24) / m * m).saturating_add(k % 3).saturating_sub(1);
                for c in [h >> 24, near, k, (1 << 40) - 1 - k] {
                    assert_eq!(div_rem(c, m, m as f64), (c / m, c % m), "{c} / {m}");
                }
            }
        }
        for n in [2u64, 3, 131, 65_537, 104_729, 3u64.pow(20), 1 << 32] {
            for k in 0..3000u64 {
                h = mix64(h ^ k);
                for x in [h, u64::MAX - k, k] {
                    assert_eq!(
                        below_narrow(x, n),
                        super::super::digit_permutation::below(x, n),
                        "{x} {n}"
                    );
                }
            }
        }
    }
}
