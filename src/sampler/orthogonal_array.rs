//! Orthogonal-array sampling: every `t`-dimensional projection of a pass is jittered.
//!
//! An orthogonal array `OA(N, d, p, t)` is an `N x d` table of symbols `0..p` in which every
//! choice of `t` columns contains each of the `p^t` symbol tuples equally often (Rao 1947).
//! Read row `i` as a cell of the `p^d` grid: then every `t`-dimensional projection of the `N`
//! cells covers the `p^t` grid of that projection evenly, which is jittered sampling in every
//! `t`-dimensional face for only `N = p^t` points, whatever `d` is.
//!
//! Two classical constructions, both for a prime `p`:
//!
//! * Bose (1938): strength 2, `N = p^2`, up to `p + 1` columns. Row `(a, b)` has columns
//!   `a`, `b` and `a + k b mod p` for `k = 1 .. p - 1`.
//! * Bush (1952): strength `t`, `N = p^t`, up to `p` columns (`p + 1` when `t <= p`). The
//!   base-`p` digits of the row number are the coefficients of a polynomial of degree below
//!   `t`; column `j` holds its value at `x = j` mod `p`, and the extra column its leading
//!   coefficient. Any `t` columns see every tuple once, because a polynomial of degree below
//!   `t` is determined by `t` values (a Vandermonde system over the field `Z/p`).
//!
//! Owen (1992, "Orthogonal arrays for computer experiments, integration and visualization")
//! randomizes an array by permuting the symbols of each column independently (which keeps it
//! an orthogonal array) and jittering each point inside its cell. The estimate is then
//! unbiased and its variance is `(1/N) sum_{|u| > t} sigma_u^2 + o(1/N)`: the ANOVA effects of
//! up to `t` variables are removed to leading order. Tang (1993, "Orthogonal array-based Latin
//! hypercubes") places each point inside its cell so that every one-dimensional projection is
//! also a Latin hypercube of `N` strata; Jarosz, Enayet, Kensler, Kilpatrick & Christensen
//! (2019, "Orthogonal Array Sampling for Monte Carlo Rendering") call these offsets
//! multi-jittered and correlated multi-jittered, next to centered and plain jittered ones
//! ([`OaOffset`]).
//!
//! Each pass is an independent randomization: fresh symbol permutations per column, a fresh
//! order of the rows (so a prefix of a pass is a random subset of it) and fresh offsets. All of
//! them are hashed from `(seed, pass, ...)`, so any point is computed directly from its index.

use super::number_theory::{
    integer_root, is_prime, max_exponent, next_prime, polynomial_mod, previous_prime, prime_root,
};
use super::permutation::{Permutation, PermutationCache};
use super::simd::{BlockFill, dispatch_fill};
use super::{PassKind, Sampler, check_dims, check_point, pass_runs};
use crate::error::parse_name;
use crate::error::{Error, Result};
use crate::float::ONE_BELOW;
use crate::hash::{hash_absorb, hash_words, unit_f64};
use crate::points::Points;
use crate::simd::Kernel;
use std::fmt;
use std::str::FromStr;

/// Where a point sits inside its cell of the `p^d` grid (Jarosz et al. 2019, section 4).
///
/// ```
/// use mcint::sampler::{OaOffset, OrthogonalArray, Sampler};
/// let offset: OaOffset = "cmj".parse().unwrap();
/// assert_eq!(offset, OaOffset::CorrelatedMultiJittered);
/// assert_eq!(OaOffset::MultiJittered.to_string(), "multi-jittered");
/// assert!("random".parse::<OaOffset>().unwrap_err().to_string().contains("centered"));
/// let s = OrthogonalArray::bose(3, 5, offset, 1).unwrap();
/// assert_eq!(s.offset(), OaOffset::CorrelatedMultiJittered);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OaOffset {
    /// The centre of the cell. Only the symbol permutations are random, so the estimate is
    /// biased (a randomly relabelled midpoint rule); useful for visualization and comparison.
    Centered,
    /// Uniform in the cell, independently per point and dimension (Owen 1992). Unbiased.
    Jittered,
    /// Inside its cell the point is in a sub-stratum of width `1/N` chosen so that every
    /// one-dimensional projection has one point per `1/N` interval (Tang 1993); the choice is
    /// an independent random permutation for each column and symbol. Unbiased.
    MultiJittered,
    /// As [`MultiJittered`](Self::MultiJittered), but one permutation per column shared by all
    /// its symbols (Kensler's 2013 correlated multi-jittering, as Jarosz et al. 2019 apply it).
    /// Unbiased.
    CorrelatedMultiJittered,
}

impl OaOffset {
    /// Every offset style, in the order listed in messages.
    ///
    /// ```
    /// use mcint::sampler::OaOffset;
    /// assert_eq!(OaOffset::ALL.len(), 4);
    /// assert_eq!(OaOffset::ALL[0], OaOffset::Centered);
    /// ```
    pub const ALL: [OaOffset; 4] = [
        OaOffset::Centered,
        OaOffset::Jittered,
        OaOffset::MultiJittered,
        OaOffset::CorrelatedMultiJittered,
    ];

    /// The name accepted by [`FromStr`]: `centered`, `jittered`, `multi-jittered` or `cmj`.
    ///
    /// ```
    /// use mcint::sampler::OaOffset;
    /// assert_eq!(OaOffset::CorrelatedMultiJittered.name(), "cmj");
    /// for offset in OaOffset::ALL {
    ///     assert_eq!(offset.name().parse::<OaOffset>().unwrap(), offset);
    /// }
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            OaOffset::Centered => "centered",
            OaOffset::Jittered => "jittered",
            OaOffset::MultiJittered => "multi-jittered",
            OaOffset::CorrelatedMultiJittered => "cmj",
        }
    }
}

impl fmt::Display for OaOffset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for OaOffset {
    type Err = Error;

    fn from_str(name: &str) -> Result<Self> {
        parse_name("offset", name, &OaOffset::ALL, OaOffset::name)
    }
}

/// Which classical construction built the array.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Construction {
    Bose,
    Bush,
}

/// Hash tags that keep the different random choices of a pass apart.
const TAG_ORDER: u64 = 0x6f61_6f72;
const TAG_SYMBOL: u64 = 0x6f61_7379;
const TAG_STRATUM: u64 = 0x6f61_7374;
const TAG_JITTER: u64 = 0x6f61_6a69;
/// A randomized orthogonal array of strength `t`: `N = p^t` points per pass, and in every
/// choice of `t` dimensions exactly one point of a pass in each cell of the `p^t` grid.
///
/// ```
/// use mcint::sampler::{OaOffset, OrthogonalArray, PassKind, Sampler};
/// // 49 points in 8 dimensions; every pair of dimensions is a 7 x 7 jittered grid.
/// let s = OrthogonalArray::bose(8, 7, OaOffset::MultiJittered, 3).unwrap();
/// assert_eq!(s.passes(), PassKind::Fixed { size: 49 });
/// let mut cells = vec![0; 49];
/// let mut p = [0.0; 8];
/// for i in 0..49 {
///     s.point(i, &mut p).unwrap();
///     cells[(p[2] * 7.0) as usize * 7 + (p[5] * 7.0) as usize] += 1;
/// }
/// assert!(cells.iter().all(|&c| c == 1));
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OrthogonalArray {
    construction: Construction,
    dims: usize,
    /// The prime number of symbols.
    p: u64,
    strength: u32,
    /// `p^(t-1)`: rows per symbol in each column, and sub-strata per cell.
    sub: u64,
    /// `N = p^t`.
    pass_size: u64,
    offset: OaOffset,
    seed: u64,
}

/// The random choices shared by all points of one pass.
struct PassKeys {
    pass: u64,
    order: Permutation,
    /// One symbol permutation per column.
    symbols: Vec<Permutation>,
    /// Sub-stratum permutations: per column (correlated), per column and symbol (uncorrelated,
    /// index `column * p + symbol`), or empty when built on demand or unused.
    strata: Vec<Permutation>,
}

impl OrthogonalArray {
    /// Bose's strength-2 array: `p^2` points per pass for a prime `p`, in `1 <= dims <= p + 1`
    /// dimensions.
    ///
    /// ```
    /// use mcint::sampler::{OaOffset, OrthogonalArray, Sampler};
    /// let s = OrthogonalArray::bose(4, 3, OaOffset::Jittered, 0).unwrap();
    /// assert_eq!((s.name(), s.dims(), s.strength()), ("oa-bose", 4, 2));
    /// let err = OrthogonalArray::bose(5, 3, OaOffset::Jittered, 0).unwrap_err();
    /// assert!(err.to_string().contains("at most p + 1 = 4"), "{err}");
    /// assert!(OrthogonalArray::bose(2, 6, OaOffset::Jittered, 0).is_err());
    /// ```
    pub fn bose(dims: usize, p: u64, offset: OaOffset, seed: u64) -> Result<Self> {
        check_dims(dims)?;
        check_prime(p)?;
        if dims as u128 > u128::from(p) + 1 {
            return Err(Error::invalid(
                "dims",
                dims,
                format!(
                    "at most p + 1 = {} for the Bose construction with p = {p}",
                    u128::from(p) + 1
                ),
            ));
        }
        let pass_size = p.checked_mul(p).ok_or_else(|| {
            Error::invalid(
                "p",
                p,
                "a prime whose square fits in 64 bits (at most 4294967291)",
            )
        })?;
        Ok(OrthogonalArray {
            construction: Construction::Bose,
            dims,
            p,
            strength: 2,
            sub: p,
            pass_size,
            offset,
            seed,
        })
    }

    /// Bush's array of strength `t = strength >= 1`: `p^t` points per pass for a prime `p`, in
    /// `1 <= dims <= p` dimensions, or `p + 1` when `t <= p`. `p^t` must fit in a `u64`.
    /// With `dims < t` every projection is still balanced (each cell holds `p^(t - dims)`
    /// points).
    ///
    /// ```
    /// use mcint::sampler::{OaOffset, OrthogonalArray, PassKind, Sampler};
    /// let s = OrthogonalArray::bush(5, 5, 3, OaOffset::CorrelatedMultiJittered, 0).unwrap();
    /// assert_eq!(s.passes(), PassKind::Fixed { size: 125 });
    /// assert_eq!(s.name(), "oa-bush");
    /// assert!(OrthogonalArray::bush(4, 3, 4, OaOffset::Jittered, 0).is_err()); // dims > p
    /// assert!(OrthogonalArray::bush(2, 3, 41, OaOffset::Jittered, 0).is_err()); // 3^41 > 2^64
    /// ```
    pub fn bush(dims: usize, p: u64, strength: u32, offset: OaOffset, seed: u64) -> Result<Self> {
        check_dims(dims)?;
        check_prime(p)?;
        if strength == 0 {
            return Err(Error::invalid("strength", 0, "at least 1"));
        }
        let pass_size = p.checked_pow(strength).ok_or_else(|| {
            Error::invalid(
                "strength",
                strength,
                format!(
                    "at most {} for p = {p} (p^strength must fit in 64 bits)",
                    max_exponent(p)
                ),
            )
        })?;
        if !fits(dims, p, strength) {
            let limit = if u64::from(strength) <= p {
                format!("at most p + 1 = {}", u128::from(p) + 1)
            } else {
                format!("at most p = {p} (p + 1 only when strength <= p)")
            };
            return Err(Error::invalid(
                "dims",
                dims,
                format!("{limit} for the Bush construction with p = {p} and strength {strength}"),
            ));
        }
        Ok(OrthogonalArray {
            construction: Construction::Bush,
            dims,
            p,
            strength,
            sub: pass_size / p,
            pass_size,
            offset,
            seed,
        })
    }

    /// An array of the given strength with `points = p^strength` per pass for a prime `p` that
    /// fits `dims` (Bose for strength 2, Bush otherwise); for any other count the error names
    /// the nearest valid sizes below and above.
    ///
    /// ```
    /// use mcint::sampler::{OaOffset, OrthogonalArray, Sampler};
    /// let s = OrthogonalArray::with_points(4, 121, 2, OaOffset::Jittered, 0).unwrap();
    /// assert_eq!((s.name(), s.prime()), ("oa-bose", 11));
    /// let err = OrthogonalArray::with_points(4, 50, 2, OaOffset::Jittered, 0).unwrap_err();
    /// assert_eq!(
    ///     err.to_string(),
    ///     "invalid points = 50: expected p^2 for a prime p >= 3 (nearest valid: 49 or 121)"
    /// );
    /// ```
    pub fn with_points(
        dims: usize,
        points: u64,
        strength: u32,
        offset: OaOffset,
        seed: u64,
    ) -> Result<Self> {
        check_dims(dims)?;
        if strength == 0 {
            return Err(Error::invalid("strength", 0, "at least 1"));
        }
        if let Some(p) = prime_root(points, strength)
            && fits(dims, p, strength)
        {
            return if strength == 2 {
                OrthogonalArray::bose(dims, p, offset, seed)
            } else {
                OrthogonalArray::bush(dims, p, strength, offset, seed)
            };
        }
        let root = integer_root(points, strength);
        let Some(smallest) = smallest_prime_fitting(dims, strength) else {
            return Err(Error::invalid(
                "points",
                points,
                format!("p^{strength} for a prime p, but none fits {dims} dimensions"),
            ));
        };
        // Largest valid size strictly below `points`, smallest strictly above.
        let below = previous_prime(root)
            .and_then(|q| {
                if q.checked_pow(strength).is_some_and(|n| n >= points) {
                    previous_prime(q - 1)
                } else {
                    Some(q)
                }
            })
            .filter(|&q| q >= smallest)
            .and_then(|q| q.checked_pow(strength));
        let above = root
            .checked_add(1)
            .map(|start| start.max(smallest))
            .and_then(next_prime)
            .and_then(|q| q.checked_pow(strength));
        let nearest: Vec<String> = [below, above]
            .into_iter()
            .flatten()
            .map(|n| n.to_string())
            .collect();
        let hint = if nearest.is_empty() {
            format!("no valid size fits in 64 bits (the smallest prime is {smallest})")
        } else {
            format!("nearest valid: {}", nearest.join(" or "))
        };
        Err(Error::invalid(
            "points",
            points,
            format!("p^{strength} for a prime p >= {smallest} ({hint})"),
        ))
    }

    /// The prime number of symbols `p` (cells along each axis).
    ///
    /// ```
    /// use mcint::sampler::{OaOffset, OrthogonalArray};
    /// assert_eq!(OrthogonalArray::bose(2, 5, OaOffset::Centered, 0).unwrap().prime(), 5);
    /// ```
    pub fn prime(&self) -> u64 {
        self.p
    }

    /// The strength `t`: every `t` dimensions are stratified into `p^t` cells.
    ///
    /// ```
    /// use mcint::sampler::{OaOffset, OrthogonalArray};
    /// let s = OrthogonalArray::bush(3, 3, 3, OaOffset::Jittered, 0).unwrap();
    /// assert_eq!(s.strength(), 3);
    /// ```
    pub fn strength(&self) -> u32 {
        self.strength
    }

    /// The offset style of the points inside their cells.
    ///
    /// ```
    /// use mcint::sampler::{OaOffset, OrthogonalArray};
    /// let s = OrthogonalArray::bose(2, 3, OaOffset::Centered, 0).unwrap();
    /// assert_eq!(s.offset(), OaOffset::Centered);
    /// ```
    pub fn offset(&self) -> OaOffset {
        self.offset
    }

    /// The evaluation point of column `column`: `Some(x)` for the polynomial's value at `x`,
    /// `None` for the extra column holding its leading coefficient.
    #[inline]
    fn evaluation_point(&self, column: usize) -> Option<u64> {
        let column = column as u64;
        match self.construction {
            // Bose's order: a (value at 0), b (the extra column), then a + k b.
            Construction::Bose => match column {
                0 => Some(0),
                1 => None,
                k => Some(k - 1),
            },
            Construction::Bush => (column < self.p).then_some(column),
        }
    }

    /// The seed salted with the construction, so that Bose and Bush arrays (and other
    /// samplers) given one seed draw unrelated permutations and jitters.
    #[inline]
    fn key(&self) -> u64 {
        self.seed
            ^ match self.construction {
                Construction::Bose => 0x626f_7365, // "bose"
                Construction::Bush => 0x6275_7368, // "bush"
            }
    }

    fn symbol_permutation(&self, pass: u64, column: usize) -> Permutation {
        Permutation::new(
            self.p,
            hash_words(self.key(), &[pass, column as u64, TAG_SYMBOL]),
        )
    }

    /// The sub-stratum permutation of `column` (and, uncorrelated, of `symbol`) in `pass`.
    fn stratum_permutation(&self, pass: u64, column: usize, symbol: u64) -> Permutation {
        let words = match self.offset {
            OaOffset::CorrelatedMultiJittered => [pass, column as u64, u64::MAX, TAG_STRATUM],
            _ => [pass, column as u64, symbol, TAG_STRATUM],
        };
        Permutation::new(self.sub, hash_words(self.key(), &words))
    }

    /// The random choices of `pass` (the uncorrelated multi-jittered permutations, one per
    /// column and symbol, are built where they are used).
    fn pass_keys(&self, pass: u64) -> PassKeys {
        let order = Permutation::new(self.pass_size, hash_words(self.key(), &[pass, TAG_ORDER]));
        let symbols = (0..self.dims)
            .map(|c| self.symbol_permutation(pass, c))
            .collect();
        let strata = match self.offset {
            OaOffset::CorrelatedMultiJittered => (0..self.dims)
                .map(|c| self.stratum_permutation(pass, c, 0))
                .collect(),
            _ => Vec::new(),
        };
        PassKeys {
            pass,
            order,
            symbols,
            strata,
        }
    }

    /// The array's entry in `row` (whose base-`p` digits, lowest first, are `coefficients`)
    /// and `column`, with the row's rank among the `p^(t-1)` rows holding that symbol in that
    /// column.
    #[inline]
    fn entry(&self, coefficients: &[u64], row: u64, column: usize) -> (u64, u64) {
        match self.evaluation_point(column) {
            Some(at) => {
                let value = polynomial_mod(coefficients, at, self.p);
                // Given the value, the higher digits determine the lowest one, so they rank
                // the row among those holding this symbol.
                (value, row / self.p)
            }
            // The leading coefficient; the lower digits rank the row.
            None => (coefficients[coefficients.len() - 1], row % self.sub),
        }
    }

    /// The coordinate (before the cap below one) of a point with `symbol` and, for the
    /// multi-jittered offsets, sub-stratum `stratum` in its column; `jitter` draws its jitter.
    #[inline(always)]
    fn coordinate(&self, symbol: u64, stratum: u64, jitter: impl FnOnce() -> f64) -> f64 {
        match self.offset {
            OaOffset::Centered => (symbol as f64 + 0.5) / self.p as f64,
            OaOffset::Jittered => (symbol as f64 + jitter()) / self.p as f64,
            OaOffset::CorrelatedMultiJittered | OaOffset::MultiJittered => {
                // symbol * p^(t-1) + stratum < p^t = N, so no overflow.
                let cell = symbol * self.sub + stratum;
                (cell as f64 + jitter()) / self.pass_size as f64
            }
        }
    }

    /// The sub-strata of a chunk of points of `column` with `symbols` and `ranks`, as
    /// `write_point` computes them, 16 lanes at a time (zeros for the other offsets); `own`
    /// keeps the column's per-symbol permutations of the uncorrelated offset.
    #[inline(always)]
    fn strata_into(
        &self,
        keys: &PassKeys,
        own: &mut PermutationCache,
        column: usize,
        symbols: &[u64],
        ranks: &[u64],
        out: &mut [u64],
    ) {
        match self.offset {
            OaOffset::Centered | OaOffset::Jittered => out.fill(0),
            OaOffset::CorrelatedMultiJittered => keys.strata[column].apply_into(ranks, out),
            OaOffset::MultiJittered => {
                let build = |symbol| self.stratum_permutation(keys.pass, column, symbol);
                own.apply_into(symbols, ranks, out, build);
            }
        }
    }

    /// Writes point `index` (which must belong to `keys.pass`) into `out`.
    fn write_point(&self, keys: &PassKeys, index: u64, out: &mut [f64]) {
        let pass = keys.pass;
        let row = keys.order.apply(index % self.pass_size);
        // Base-p digits of the row, lowest first: the polynomial's coefficients.
        let mut digits = [0u64; 64];
        let mut rest = row;
        for digit in digits.iter_mut().take(self.strength as usize) {
            *digit = rest % self.p;
            rest /= self.p;
        }
        let coefficients = &digits[..self.strength as usize];
        for (column, x) in out.iter_mut().enumerate() {
            let (value, rank) = self.entry(coefficients, row, column);
            let symbol = keys.symbols[column].apply(value);
            let jitter = || {
                unit_f64(hash_words(
                    self.key(),
                    &[pass, index, column as u64, TAG_JITTER],
                ))
            };
            let stratum = match self.offset {
                OaOffset::Centered | OaOffset::Jittered => 0,
                OaOffset::CorrelatedMultiJittered => keys.strata[column].apply(rank),
                OaOffset::MultiJittered => {
                    self.stratum_permutation(pass, column, symbol).apply(rank)
                }
            };
            let coordinate = self.coordinate(symbol, stratum, jitter);
            *x = coordinate.min(ONE_BELOW);
        }
    }
}

impl Sampler for OrthogonalArray {
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
        match self.construction {
            Construction::Bose => "oa-bose",
            Construction::Bush => "oa-bush",
        }
    }

    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        check_point(self.dims, out)?;
        let keys = self.pass_keys(index / self.pass_size);
        self.write_point(&keys, index, out);
        Ok(())
    }

    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        dispatch_fill(self, self.dims, start, points)
    }
}

/// Indices per step of the block fill kernel (a multiple of the 16 permutation lanes).
const CHUNK: usize = 256;

/// The block fill, compiled for each instruction set by [`dispatch_fill`]. Per run of indices
/// within one pass (whose keys are built once): the rows of a chunk by the order permutation,
/// 16 indices at a time; then per column the entries, their symbols by the column's symbol
/// permutation over lanes, the sub-strata by the shared (correlated) permutation over lanes or
/// by 16 different per-symbol permutations stepped in lockstep, and the jitter hash with its
/// seed and pass absorbed once per run. The integers and the final `f64` expressions are those
/// of `write_point`, so the values are bit-identical to `point`.
impl Kernel for BlockFill<'_, OrthogonalArray> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let (array, start, points) = (self.sampler, self.start, self.points);
        let (size, p, t) = (array.pass_size, array.p, array.strength as usize);
        let len = points.len();
        let (mut rows, mut coefficients) = (Vec::new(), Vec::new());
        let mut values = [0u64; CHUNK];
        let mut ranks = [0u64; CHUNK];
        let mut symbols = [0u64; CHUNK];
        let mut strata = [0u64; CHUNK];
        let mut own = PermutationCache::default();
        for (done, pass, local, run) in pass_runs(start, len, size) {
            let index = start + done as u64;
            let keys = array.pass_keys(pass);
            // The rows of the run, and their base-p digits (lowest first): the polynomial's
            // coefficients.
            rows.clear();
            rows.extend(local..local + run as u64);
            for chunk in rows.chunks_mut(CHUNK) {
                values[..chunk.len()].copy_from_slice(chunk);
                keys.order.apply_into(&values[..chunk.len()], chunk);
            }
            coefficients.resize(run * t, 0);
            for (&row, digits) in rows.iter().zip(coefficients.chunks_exact_mut(t)) {
                let mut rest = row;
                for digit in digits.iter_mut() {
                    *digit = rest % p;
                    rest /= p;
                }
            }
            // hash_words(seed, [pass, index, column, TAG_JITTER]) with the seed and pass
            // absorbed.
            let pass_hash = hash_words(array.key(), &[pass]);
            for column in 0..array.dims {
                own.reset(p, run);
                for offset in (0..run).step_by(CHUNK) {
                    let c = CHUNK.min(run - offset);
                    let chunk_rows = &rows[offset..offset + c];
                    for (j, &row) in chunk_rows.iter().enumerate() {
                        let digits = &coefficients[(offset + j) * t..(offset + j + 1) * t];
                        (values[j], ranks[j]) = array.entry(digits, row, column);
                    }
                    keys.symbols[column].apply_into(&values[..c], &mut symbols[..c]);
                    let (symbols, ranks) = (&symbols[..c], &ranks[..c]);
                    array.strata_into(&keys, &mut own, column, symbols, ranks, &mut strata[..c]);
                    let first_index = index + offset as u64;
                    let at = done + offset;
                    let out = &mut points.column_mut(column)[at..at + c];
                    for (j, x) in out.iter_mut().enumerate() {
                        let jitter = || {
                            let h = hash_absorb(pass_hash, first_index + j as u64);
                            unit_f64(hash_absorb(hash_absorb(h, column as u64), TAG_JITTER))
                        };
                        *x = array
                            .coordinate(symbols[j], strata[j], jitter)
                            .min(ONE_BELOW);
                    }
                }
            }
        }
    }
}

/// Whether `dims` columns fit an array of strength `t` over `p` symbols: at most `p`, or
/// `p + 1` when `t <= p` (Bose's `p + 1` for `t = 2` is the same rule).
fn fits(dims: usize, p: u64, t: u32) -> bool {
    dims as u128 <= u128::from(p) + u128::from(u64::from(t) <= p)
}

/// The smallest prime `p` for which `dims` columns fit strength `t`.
fn smallest_prime_fitting(dims: usize, t: u32) -> Option<u64> {
    let start = u64::try_from(dims.saturating_sub(1)).ok()?.max(2);
    let mut p = next_prime(start)?;
    while !fits(dims, p, t) {
        p = next_prime(p.checked_add(1)?)?;
    }
    Some(p)
}

/// Ok for a prime `p`, otherwise an error naming the nearest primes.
fn check_prime(p: u64) -> Result<()> {
    if is_prime(p) {
        return Ok(());
    }
    let nearest: Vec<String> = [
        p.checked_sub(1).and_then(previous_prime),
        p.checked_add(1).and_then(next_prime),
    ]
    .into_iter()
    .flatten()
    .map(|q| q.to_string())
    .collect();
    Err(Error::invalid(
        "p",
        p,
        format!("a prime >= 2 (nearest primes: {})", nearest.join(" or ")),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every pair (Bose) or triple (Bush, t = 3) of columns holds each tuple once, and
    /// (value, rank) identifies the row in every column.
    #[test]
    fn entries_form_orthogonal_arrays_with_ranks() {
        for (s, t) in [
            (
                OrthogonalArray::bose(6, 5, OaOffset::Centered, 0).unwrap(),
                2usize,
            ),
            (
                OrthogonalArray::bush(4, 3, 3, OaOffset::Centered, 0).unwrap(),
                3,
            ),
        ] {
            let (p, n) = (s.p, s.pass_size);
            let table: Vec<Vec<(u64, u64)>> = (0..n)
                .map(|row| {
                    let digits: Vec<u64> = (0..t as u32).map(|k| row / p.pow(k) % p).collect();
                    (0..s.dims).map(|c| s.entry(&digits, row, c)).collect()
                })
                .collect();
            for c in 0..s.dims {
                let mut seen: Vec<(u64, u64)> = table.iter().map(|r| r[c]).collect();
                seen.sort_unstable();
                seen.dedup();
                assert_eq!(seen.len() as u64, n, "column {c}: (value, rank) not unique");
            }
            let subsets: Vec<Vec<usize>> = (0..1usize << s.dims)
                .filter(|m| m.count_ones() as usize == t)
                .map(|m| (0..s.dims).filter(|c| m >> c & 1 == 1).collect())
                .collect();
            for subset in subsets {
                let mut seen: Vec<Vec<u64>> = table
                    .iter()
                    .map(|r| subset.iter().map(|&c| r[c].0).collect())
                    .collect();
                seen.sort_unstable();
                seen.dedup();
                assert_eq!(seen.len() as u64, n, "columns {subset:?}");
            }
        }
    }

    #[test]
    fn large_primes_give_points_in_the_unit_cube() {
        let p = 4_294_967_291;
        let s = OrthogonalArray::bose(3, p, OaOffset::MultiJittered, 1).unwrap();
        let mut x = [0.0; 3];
        s.point(u64::MAX, &mut x).unwrap();
        assert!(x.iter().all(|&v| (0.0..1.0).contains(&v)));
        assert!(OrthogonalArray::bose(2, 4_294_967_311, OaOffset::Jittered, 0).is_err());
    }
}
