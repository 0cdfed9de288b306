//! Multi-stage N-rooks sampling (after Wang & Sung 1999, "Multi-stage N-rooks sampling
//! method", Journal of Graphics Tools 4(1)).
//!
//! N-rooks (Latin hypercube) sampling puts one of its `N` points in each `1/N` slab of every
//! axis (Shirley 1990; McKay, Beckman & Conover 1979) but says nothing about smaller groups of
//! points. Wang & Sung apply N-rooks recursively, stage by stage, so that the pattern is
//! N-rooks at several scales at once. The paper's text was not available while this module was
//! written, so it implements the following construction, stated exactly:
//!
//! A pass has `N = n^k` points (`n >= 2` the base, `k >= 1` the number of stages). For every
//! stage `s = 0..=k`, the pass splits into `n^s` blocks of `n^(k-s)` consecutive indices
//! (aligned on multiples of `n^(k-s)` within the pass), and **each block is an N-rooks pattern
//! at resolution `n^(k-s)`**: on every axis it has exactly one point in each slab of width
//! `n^-(k-s)`. Stage 0 is the whole pass, a Latin hypercube of `N` points; stage `k - 1`
//! makes every run of `n` consecutive points a Latin hypercube of `n` points. Equivalently,
//! each slab of width `n^-(k-s)` of an axis is a sub-region in which the `n^s` points that fall
//! there (one from each stage-`s` block) are spread N-rooks-wise over its `n^s` finer slabs.
//!
//! On each axis the slab of local index `i` is the base-`n` radical inverse of `i` under a
//! nested random scramble (Owen 1995): its digit `t` (most significant first) is digit
//! `k - 1 - t` of `i` (least significant first) sent through a uniformly random permutation of
//! `0..n` that is chosen independently for every value of the digits of `i` already used. The
//! permutations are hashed from `(seed, pass, dim, node)`, so any point is computed directly
//! (random access in `O(k)` hashes) and axes are independent of each other. A uniform jitter
//! inside the slab completes the coordinate. Each coordinate is therefore uniform on `[0, 1)`
//! (estimates are unbiased), any pair of points of a pass lies in different slabs of the finest
//! scale, and additive integrands get the Latin hypercube's variance reduction at every stage:
//! a prefix or block of `n^(k-s)` points is as good as a Latin hypercube of that size.
//!
//! What the construction does not give: joint (multi-axis) stratification; for that use
//! jittered, multi-jittered or pmj02 samplers.

use super::number_theory::integer_root;
use super::permutation::Permutation;
use super::{PassKind, Sampler, check_block, check_dims, check_point, pass_runs};
use crate::error::{Error, Result};
use crate::float::ONE_BELOW;
use crate::hash::{hash_absorb, hash_words, unit_f64};
use crate::points::Points;

/// Largest pass size: slabs stay exactly representable in a double.
const MAX_POINTS: u64 = 1 << 53;
/// Most stages: base 2 and the largest pass.
const MAX_STAGES: usize = 53;
/// Salt for the permutation keys.
const PERMUTATION_SALT: u64 = 0x6d73_6e72_6b70;
/// Salt for the jitter.
const JITTER_SALT: u64 = 0x6d73_6e72_6b6a;
/// Bases up to this size draw a permutation from one 64-bit hash (12! < 2^29, so the bias of
/// the mixed-radix decoding is below 2^-35); larger bases use [`Permutation`].
const SMALL_BASE: u64 = 12;

/// Multi-stage N-rooks: `N = n^k` points per pass, every aligned block of `n^(k-s)`
/// consecutive points an N-rooks (Latin hypercube) pattern at resolution `n^(k-s)`, for every
/// stage `s`.
///
/// The exact construction and its guarantees are described at the top of its source file,
/// `src/sampler/multi_stage_n_rooks.rs`.
///
/// ```
/// use mcint::sampler::{MultiStageNRooks, Sampler};
/// let s = MultiStageNRooks::new(2, 16, 1).unwrap(); // 2^4: base 2, 4 stages
/// let mut p = [0.0; 2];
/// // Every aligned block of 4 points has one point in each quarter of each axis.
/// for block in 0..4 {
///     let mut quarters = [0; 4];
///     for i in 0..4 {
///         s.point(block * 4 + i, &mut p).unwrap();
///         quarters[(p[1] * 4.0) as usize] += 1;
///     }
///     assert_eq!(quarters, [1; 4]);
/// }
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MultiStageNRooks {
    dims: usize,
    base: u64,
    stages: u32,
    pass_size: u64,
    seed: u64,
}

impl MultiStageNRooks {
    /// `points = n^k` points per pass with `n >= 2` and `k >= 2` (4, 8, 9, 16, 25, 27, 32, ...);
    /// the smallest such base `n` is used, which gives the most stages (16 is `2^4`, not
    /// `4^2`). Other sizes are errors that name the nearest valid sizes.
    ///
    /// ```
    /// use mcint::sampler::{MultiStageNRooks, PassKind, Sampler};
    /// let s = MultiStageNRooks::new(3, 27, 0).unwrap();
    /// assert_eq!((s.base(), s.stages()), (3, 3));
    /// assert_eq!(s.passes(), PassKind::Fixed { size: 27 });
    /// let err = MultiStageNRooks::new(3, 20, 0).unwrap_err();
    /// assert!(err.to_string().contains("16 or 25"));
    /// ```
    pub fn new(dims: usize, points: u64, seed: u64) -> Result<Self> {
        check_dims(dims)?;
        // The most stages first: the first exact k-th root found is the smallest base.
        if (4..=MAX_POINTS).contains(&points) {
            for stages in (2..=63).rev() {
                let base = integer_root(points, stages);
                if base >= 2 && base.checked_pow(stages) == Some(points) {
                    return Self::with_stages(dims, base, stages, seed);
                }
            }
        }
        let nearest = match nearest_powers(points) {
            (Some(below), Some(above)) => format!("{below} or {above}"),
            (Some(one), None) | (None, Some(one)) => one.to_string(),
            (None, None) => "4".to_string(),
        };
        Err(Error::invalid(
            "points",
            points,
            format!(
                "a perfect power n^k with n >= 2 and k >= 2 stages, at most 2^53 \
                 (4, 8, 9, 16, 25, 27, 32, 36, ...); nearest valid: {nearest}"
            ),
        ))
    }

    /// `base^stages` points per pass with `base >= 2`, `stages >= 1` and
    /// `base^stages <= 2^53`. One stage is a plain Latin hypercube of `base` points.
    ///
    /// ```
    /// use mcint::sampler::{MultiStageNRooks, PassKind, Sampler};
    /// let s = MultiStageNRooks::with_stages(2, 4, 2, 0).unwrap(); // 4^2, unlike new(16)
    /// assert_eq!(s.passes(), PassKind::Fixed { size: 16 });
    /// assert!(MultiStageNRooks::with_stages(2, 1, 3, 0).is_err());
    /// assert!(MultiStageNRooks::with_stages(2, 10, 20, 0).is_err());
    /// ```
    pub fn with_stages(dims: usize, base: u64, stages: u32, seed: u64) -> Result<Self> {
        check_dims(dims)?;
        if base < 2 {
            return Err(Error::invalid("base", base, "at least 2"));
        }
        if stages == 0 {
            return Err(Error::invalid("stages", stages, "at least 1"));
        }
        let pass_size = base
            .checked_pow(stages)
            .filter(|&n| n <= MAX_POINTS)
            .ok_or_else(|| {
                Error::invalid(
                    "stages",
                    stages,
                    format!("base^stages at most 2^53 (base {base})"),
                )
            })?;
        Ok(MultiStageNRooks {
            dims,
            base,
            stages,
            pass_size,
            seed,
        })
    }

    /// The base `n` of the pass size `n^k`.
    ///
    /// ```
    /// use mcint::sampler::MultiStageNRooks;
    /// assert_eq!(MultiStageNRooks::new(1, 125, 0).unwrap().base(), 5);
    /// ```
    pub fn base(&self) -> u64 {
        self.base
    }

    /// The number of stages `k` of the pass size `n^k`.
    ///
    /// ```
    /// use mcint::sampler::MultiStageNRooks;
    /// assert_eq!(MultiStageNRooks::new(1, 64, 0).unwrap().stages(), 6);
    /// ```
    pub fn stages(&self) -> u32 {
        self.stages
    }

    /// The key of the random permutation of `0..base` at tree node (`depth`, `prefix`) of the
    /// axis whose words `[pass, dim]` are absorbed in `axis`: the hash of
    /// `(seed, pass, dim, depth, prefix)`.
    #[inline]
    fn node_key(axis: u64, depth: usize, prefix: u64) -> u64 {
        hash_absorb(
            hash_absorb(hash_absorb(axis, depth as u64), prefix),
            PERMUTATION_SALT,
        )
    }

    /// Image of `digit` under the permutation of `0..base` with `key`.
    #[inline]
    fn permute(&self, key: u64, digit: u64) -> u64 {
        if self.base <= SMALL_BASE {
            // Fisher-Yates driven by the mixed-radix digits of one hash; only the image of
            // `digit` is needed, but the shuffle is tiny.
            let mut slots = [0u8; SMALL_BASE as usize];
            for (v, slot) in slots.iter_mut().enumerate() {
                *slot = v as u8;
            }
            let mut h = key;
            for j in (1..self.base as usize).rev() {
                let r = (h % (j as u64 + 1)) as usize;
                h /= j as u64 + 1;
                slots.swap(j, r);
            }
            u64::from(slots[digit as usize])
        } else {
            Permutation::new(self.base, key).apply(digit)
        }
    }

    /// The slab (of `pass_size` per axis) of the local index whose base-`n` digits (least
    /// significant first, one per stage) are `digits`, on the axis whose words are absorbed in
    /// `axis` (see [`node_key`](Self::node_key)). `memo`, when given, holds the images of the
    /// nodes of its first depths (see [`NodeMemo`]).
    #[inline]
    fn slab(&self, axis: u64, digits: &[u64], mut memo: Option<&mut NodeMemo>) -> u64 {
        let base = self.base;
        // `used` holds the digits of the index consumed so far (its least significant `depth`).
        let mut used = 0u64;
        let mut place = 1u64;
        let mut slab = 0u64;
        for (depth, &digit) in digits.iter().enumerate() {
            let permute = || self.permute(Self::node_key(axis, depth, used), digit);
            let image = match memo.as_deref_mut() {
                Some(memo) if depth < memo.starts.len() => {
                    let slot =
                        &mut memo.images[memo.starts[depth] + (used * base + digit) as usize];
                    if *slot == u32::MAX {
                        // Images are below base <= u32::MAX (see NodeMemo::reset).
                        *slot = permute() as u32;
                    }
                    u64::from(*slot)
                }
                _ => permute(),
            };
            slab = slab * base + image;
            used += digit * place;
            place = place.saturating_mul(base);
        }
        slab
    }

    /// The base-`n` digits of `local`, least significant first, one per stage.
    fn digits(&self, mut local: u64, digits: &mut [u64; MAX_STAGES]) {
        for digit in digits[..self.stages as usize].iter_mut() {
            *digit = local % self.base;
            local /= self.base;
        }
    }

    /// Coordinate of point `index` on axis `dim` from its slab; `jitter_pass` has the seed and
    /// the pass absorbed.
    #[inline]
    fn coordinate(&self, slab: u64, jitter_pass: u64, index: u64, dim: usize) -> f64 {
        let jitter = unit_f64(hash_absorb(
            hash_absorb(hash_absorb(jitter_pass, index), dim as u64),
            JITTER_SALT,
        ));
        ((slab as f64 + jitter) / self.pass_size as f64).min(ONE_BELOW)
    }
}

/// Memoized permutation images of the shallow tree nodes of one axis and pass. A block of
/// consecutive indices meets every node of depth `d` (there are `base^d`) at up to `base`
/// digits, so when `base^(d+1)` is small next to the block each image is computed once
/// instead of once per point; deeper nodes are computed per point.
#[derive(Default)]
struct NodeMemo {
    /// Where the images of depth `d` start in `images`, for the memoized depths.
    starts: Vec<usize>,
    /// `images[starts[d] + prefix * base + digit]`, `u32::MAX` while not computed.
    images: Vec<u32>,
}

impl NodeMemo {
    /// Empties the memo for a run of `run` points with `base` and `stages`.
    fn reset(&mut self, base: u64, stages: u32, run: usize) {
        let limit = (4 * run as u64 + 1024).min(u64::from(u32::MAX));
        self.starts.clear();
        let (mut size, mut width) = (0u64, base);
        while self.starts.len() < stages as usize && width <= limit {
            self.starts.push(size as usize);
            size += width;
            width = width.saturating_mul(base);
        }
        self.images.clear();
        self.images.resize(size as usize, u32::MAX);
    }
}

/// The largest valid size `n^k <= points` and the smallest one `>= points`, if any, where
/// valid means `n >= 2`, `k >= 2` and at most 2^53.
fn nearest_powers(points: u64) -> (Option<u64>, Option<u64>) {
    let capped = points.min(MAX_POINTS);
    let mut below = None::<u64>;
    let mut above = None::<u64>;
    for k in 2..=53u32 {
        let r = integer_root(capped, k);
        if r >= 2 {
            let p = r.pow(k);
            below = Some(below.map_or(p, |b| b.max(p)));
        }
        if let Some(p) = (r + 1).max(2).checked_pow(k)
            && (points..=MAX_POINTS).contains(&p)
        {
            above = Some(above.map_or(p, |a| a.min(p)));
        }
    }
    (below, above)
}

impl Sampler for MultiStageNRooks {
    fn dims(&self) -> usize {
        self.dims
    }

    fn passes(&self) -> PassKind {
        PassKind::Fixed {
            size: self.pass_size,
        }
    }

    fn seed(&self) -> u64 {
        self.seed
    }

    fn reseed(&mut self, seed: u64) {
        self.seed = seed;
    }

    fn name(&self) -> &'static str {
        "nrooks-multistage"
    }

    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        check_point(self.dims, out)?;
        let pass = index / self.pass_size;
        let local = index % self.pass_size;
        let jitter_pass = hash_words(self.seed, &[pass]);
        let mut digits = [0; MAX_STAGES];
        self.digits(local, &mut digits);
        for (dim, x) in out.iter_mut().enumerate() {
            let axis = hash_words(self.seed, &[pass, dim as u64]);
            let slab = self.slab(axis, &digits[..self.stages as usize], None);
            *x = self.coordinate(slab, jitter_pass, index, dim);
        }
        Ok(())
    }

    /// Per column and per run of indices within one pass: the shallow nodes' images memoized
    /// (a `NodeMemo`), the hash words of seed, pass and axis absorbed once. The same integers
    /// as `point`, so the same bits.
    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        check_block(self.dims, start, points)?;
        let len = points.len();
        let mut memo = NodeMemo::default();
        for (done, pass, local, run) in pass_runs(start, len, self.pass_size) {
            let index = start + done as u64;
            let jitter_pass = hash_words(self.seed, &[pass]);
            for dim in 0..self.dims {
                memo.reset(self.base, self.stages, run);
                let axis = hash_words(self.seed, &[pass, dim as u64]);
                let column = &mut points.column_mut(dim)[done..done + run];
                // The digits of consecutive indices, counted like an odometer (no division).
                let mut digits = [0; MAX_STAGES];
                self.digits(local, &mut digits);
                let digits = &mut digits[..self.stages as usize];
                for (j, x) in column.iter_mut().enumerate() {
                    let slab = self.slab(axis, digits, Some(&mut memo));
                    *x = self.coordinate(slab, jitter_pass, index + j as u64, dim);
                    // The last index of a pass carries out of every digit: the run ends there.
                    for digit in digits.iter_mut() {
                        *digit += 1;
                        if *digit < self.base {
                            break;
                        }
                        *digit = 0;
                    }
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_powers_bracket_the_request() {
        assert_eq!(nearest_powers(20), (Some(16), Some(25)));
        assert_eq!(nearest_powers(1), (None, Some(4)));
        assert_eq!(nearest_powers(30), (Some(27), Some(32)));
        assert_eq!(nearest_powers(u64::MAX), (Some(MAX_POINTS), None));
    }

    #[test]
    fn small_base_permutations_are_bijections() {
        let s = MultiStageNRooks::with_stages(1, 7, 2, 3).unwrap();
        let axis = hash_words(3, &[0, 0]);
        for prefix in 0..7 {
            let key = MultiStageNRooks::node_key(axis, 1, prefix);
            let mut image: Vec<u64> = (0..7).map(|d| s.permute(key, d)).collect();
            image.sort_unstable();
            assert_eq!(image, (0..7).collect::<Vec<_>>());
        }
    }
}
