//! Multi-jittered sampling (Chiu, Shirley & Wang 1994, "Multi-Jittered Sampling", Graphics
//! Gems IV), evaluated point by point as Kensler (2013, "Correlated Multi-Jittered Sampling",
//! Pixar Technical Memo 13-01, section 3) describes.
//!
//! A pass of `N = m * n` points in the unit square is at once *jittered* on an `m x n` grid
//! (one point in each of the `m` columns times `n` rows of cells) and *N-rooks* (one point in
//! each of the `N` vertical slabs of width `1/N` and each of the `N` horizontal ones). Cell
//! `(i, j)` (column `i`, row `j`) is cut into `n` sub-columns and `m` sub-rows; in the
//! canonical arrangement its point lies in sub-column `j` and sub-row `i`, which makes the
//! global `x` slab `i * n + j` and the global `y` slab `j * m + i`. Shuffling the sub-column
//! indices within each column (a permutation of `0..n` per column) and the sub-row indices
//! within each row (a permutation of `0..m` per row) keeps both properties; Chiu et al. do it
//! with random swaps, and Kensler replaces the stored shuffle with hashed random-access
//! permutations, so every point is a pure function of `(seed, pass, index)`. Here every column
//! and every row gets its own independent permutation (the "uncorrelated" case);
//! [`CorrelatedMultiJittered`](super::CorrelatedMultiJittered) uses one for all.
//!
//! More than two dimensions are taken in pairs `(0, 1), (2, 3), ...`: each pair is its own
//! multi-jittered pattern with independent seeds and its own random assignment of point
//! numbers to cells (a hashed permutation of `0..N`), so pairs are not correlated with each
//! other. An odd last dimension is a one-dimensional N-rooks (Latin) stratification.
//!
//! The shared machinery for both variants lives here.

use super::number_theory::squarest_divisor;
use super::permutation::{Permutation, PermutationCache};
use super::simd::{BlockFill, dispatch_fill};
use super::{PassKind, Sampler, check_dims, check_point, pass_runs};
use crate::error::{Error, Result};
use crate::float::ONE_BELOW;
use crate::hash::{hash_absorb, hash_words, unit_f64};
use crate::points::Points;
use crate::simd::Kernel;

/// Most points a pass may hold: `2^53`, beyond which the `1/N` slabs are no longer distinct
/// doubles in `[0, 1)` and the N-rooks property could not hold.
pub(super) const MAX_POINTS: u64 = 1 << 53;

/// Role tags hashed into permutation seeds, so that no two permutations share a seed.
const ROLE_CELL: u64 = 0x6365_6c6c; // point number -> cell
const ROLE_COLUMN: u64 = 0x636f_6c73; // sub-columns within a column
const ROLE_ROW: u64 = 0x726f_7773; // sub-rows within a row
const ROLE_LATIN: u64 = 0x6c61_7469; // the odd last dimension

/// The permutations one pair of dimensions uses in one pass. For the correlated variant the
/// column and row permutations are the same for every column (row) and are stored here; for
/// the uncorrelated one they depend on the column (row) and are built where they are used
/// (per point in `point`, once per run of a block in `fill`).
#[derive(Debug, Clone, Copy)]
pub(super) struct PairPermutations {
    /// Point number within the pass -> cell number (or slab, for the odd last dimension).
    cell: Permutation,
    /// Shared sub-column permutation of `0..n` (correlated variant only).
    column: Option<Permutation>,
    /// Shared sub-row permutation of `0..m` (correlated variant only).
    row: Option<Permutation>,
}

/// The pass structure and randomization shared by [`MultiJittered`] and
/// [`CorrelatedMultiJittered`](super::CorrelatedMultiJittered).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct MjCore {
    pub(super) dims: usize,
    m: u64,
    n: u64,
    pub(super) pass_size: u64,
    pub(super) seed: u64,
    correlated: bool,
}

impl MjCore {
    /// Validates `dims >= 1`, `m, n >= 1` and `m * n <= 2^53`.
    pub(super) fn new(dims: usize, m: u64, n: u64, seed: u64, correlated: bool) -> Result<Self> {
        check_dims(dims)?;
        if m == 0 {
            return Err(Error::invalid("m", 0, "at least 1 column of cells"));
        }
        if n == 0 {
            return Err(Error::invalid("n", 0, "at least 1 row of cells"));
        }
        let pass_size = m
            .checked_mul(n)
            .filter(|&size| size <= MAX_POINTS)
            .ok_or_else(|| {
                Error::invalid(
                    "m * n",
                    format!("{m} * {n}"),
                    format!(
                        "at most 2^53 = {MAX_POINTS} points per pass (slabs of width 1/N must \
                         be distinct doubles)"
                    ),
                )
            })?;
        Ok(MjCore {
            dims,
            m,
            n,
            pass_size,
            seed,
            correlated,
        })
    }

    /// Chooses `m <= n` with `m * n = points` and `m` as close to `sqrt(points)` as possible.
    pub(super) fn with_points(
        dims: usize,
        points: u64,
        seed: u64,
        correlated: bool,
    ) -> Result<Self> {
        check_dims(dims)?;
        if points == 0 {
            return Err(Error::invalid(
                "points",
                0,
                format!("between 1 and 2^53 = {MAX_POINTS} points per pass (any count works)"),
            ));
        }
        if points > MAX_POINTS {
            return Err(Error::invalid(
                "points",
                points,
                format!(
                    "at most 2^53 = {MAX_POINTS} points per pass (slabs of width 1/N must be \
                     distinct doubles)"
                ),
            ));
        }
        let m = squarest_divisor(points);
        MjCore::new(dims, m, points / m, seed, correlated)
    }

    pub(super) fn m(&self) -> u64 {
        self.m
    }

    pub(super) fn n(&self) -> u64 {
        self.n
    }

    /// Seed of the permutation with `role` for pair `pair` of `pass` (`which` selects the
    /// column or row for the uncorrelated variant, and is 0 otherwise).
    #[inline]
    fn permutation_seed(&self, pass: u64, pair: usize, role: u64, which: u64) -> u64 {
        hash_words(self.seed, &[self.salt(), pass, pair as u64, role, which])
    }

    /// Leads every hash of this sampler: the two variants, and other samplers given the same
    /// seed (which hash the same `(pass, index, dim)` words for their jitter), draw unrelated
    /// numbers.
    #[inline]
    fn salt(&self) -> u64 {
        if self.correlated {
            0x0063_6d6a // "cmj"
        } else {
            0x0000_6d6a // "mj"
        }
    }

    /// The permutations pair `pair` (dimensions `2 pair` and `2 pair + 1`, or the odd last
    /// dimension when `2 pair + 1 == dims`) uses in `pass`.
    #[inline]
    fn pair_permutations(&self, pass: u64, pair: usize) -> PairPermutations {
        let single = 2 * pair + 1 == self.dims;
        let cell_role = if single { ROLE_LATIN } else { ROLE_CELL };
        let cell = Permutation::new(
            self.pass_size,
            self.permutation_seed(pass, pair, cell_role, 0),
        );
        let (column, row) = if self.correlated && !single {
            (
                Some(Permutation::new(
                    self.n,
                    self.permutation_seed(pass, pair, ROLE_COLUMN, 0),
                )),
                Some(Permutation::new(
                    self.m,
                    self.permutation_seed(pass, pair, ROLE_ROW, 0),
                )),
            )
        } else {
            (None, None)
        };
        PairPermutations { cell, column, row }
    }

    /// Coordinate `dim` from its slab in `0..N` and the point's hashed jitter.
    #[inline]
    fn coordinate(&self, slab: u64, pass: u64, index: u64, dim: usize) -> f64 {
        let jitter = unit_f64(hash_words(
            self.seed,
            &[self.salt(), pass, index, dim as u64],
        ));
        ((slab as f64 + jitter) / self.pass_size as f64).min(ONE_BELOW)
    }

    /// Writes the coordinates of pair `pair` of point `index` into `out` (`out[2 pair]`, and
    /// `out[2 pair + 1]` unless it is the odd last dimension).
    #[inline]
    fn write_pair(
        &self,
        perms: &PairPermutations,
        pass: u64,
        index: u64,
        pair: usize,
        out: &mut [f64],
    ) {
        let local = index % self.pass_size;
        let cell = perms.cell.apply(local);
        let dx = 2 * pair;
        if dx + 1 == self.dims {
            out[dx] = self.coordinate(cell, pass, index, dx);
            return;
        }
        let (column, row) = (cell % self.m, cell / self.m);
        // Sub-column of the point within its column, sub-row within its row.
        let sub_column = match &perms.column {
            Some(p) => p.apply(row),
            None => Permutation::new(
                self.n,
                self.permutation_seed(pass, pair, ROLE_COLUMN, column),
            )
            .apply(row),
        };
        let sub_row = match &perms.row {
            Some(p) => p.apply(column),
            None => Permutation::new(self.m, self.permutation_seed(pass, pair, ROLE_ROW, row))
                .apply(column),
        };
        // column * n + sub_column <= (m - 1) n + n - 1 = N - 1: no overflow.
        out[dx] = self.coordinate(column * self.n + sub_column, pass, index, dx);
        out[dx + 1] = self.coordinate(row * self.m + sub_row, pass, index, dx + 1);
    }

    /// Number of pairs, counting an odd last dimension as one.
    fn pairs(&self) -> usize {
        self.dims.div_ceil(2)
    }

    pub(super) fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        check_point(self.dims, out)?;
        let pass = index / self.pass_size;
        for pair in 0..self.pairs() {
            let perms = self.pair_permutations(pass, pair);
            self.write_pair(&perms, pass, index, pair, out);
        }
        Ok(())
    }

    pub(super) fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        dispatch_fill(self, self.dims, start, points)
    }
}

/// Values per chunk of the fill kernel (a multiple of the 16 permutation lanes).
const CHUNK: usize = 256;

/// `(c / m, c % m)` for `c < 2^53`, `m >= 1`, without an integer division (which does not
/// vectorize): the correctly rounded `f64` quotient truncates to within one of the true
/// one, and the remainder's sign and size say which way to correct.
#[inline(always)]
pub(super) fn div_rem(c: u64, m: u64, m_f64: f64) -> (u64, u64) {
    let q = (c as f64 / m_f64) as u64;
    let r = c.wrapping_sub(q.wrapping_mul(m));
    let low = u64::from((r as i64) < 0);
    let high = u64::from((r as i64) >= 0 && r >= m);
    (
        q.wrapping_sub(low).wrapping_add(high),
        r.wrapping_add(low.wrapping_neg() & m)
            .wrapping_sub(high.wrapping_neg() & m),
    )
}

/// The block fill, compiled for each instruction set by [`dispatch_fill`]. Per run of one pass and per
/// pair of dimensions: the cells of a chunk of points by the cell permutation over 16 indices at a
/// time; column and row by a division done in `f64` and corrected exactly; for the correlated
/// variant the shared sub-column and sub-row permutations from tables of their `n + m` images when
/// the run is at least that long, else over lanes; for the uncorrelated one each column's and row's
/// own permutation, built once per run and pair and stepped 16 at a time in lockstep (a
/// `PermutationCache`); and the jitter hash with its seed and pass words absorbed once per run.
/// Every step computes the integers `write_pair` does and the same final `f64` expression, so the
/// values are bit-identical.
impl Kernel for BlockFill<'_, MjCore> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let (core, start, points) = (self.sampler, self.start, self.points);
        let len = points.len();
        let size = core.pass_size;
        let size_f64 = size as f64;
        let m_f64 = core.m as f64;
        let mut inputs = [0u64; CHUNK];
        let mut cells = [0u64; CHUNK];
        let mut columns = [0u64; CHUNK];
        let mut rows = [0u64; CHUNK];
        let mut sub_columns = [0u64; CHUNK];
        let mut sub_rows = [0u64; CHUNK];
        let (mut column_table, mut row_table) = (Vec::new(), Vec::new());
        let (mut own_columns, mut own_rows) = <(PermutationCache, PermutationCache)>::default();
        for (done, pass, local, run) in pass_runs(start, len, size) {
            // hash_words(seed, [salt, pass, index, dim]) with the first three words absorbed.
            let pass_hash = hash_words(core.seed, &[core.salt(), pass]);
            let coordinate = |slab: u64, index: u64, dim: u64| {
                let h = hash_absorb(hash_absorb(pass_hash, index), dim);
                ((slab as f64 + unit_f64(h)) / size_f64).min(ONE_BELOW)
            };
            for pair in 0..core.pairs() {
                let perms = core.pair_permutations(pass, pair);
                let dx = 2 * pair;
                let single = dx + 1 == core.dims;
                let tabulate = !single && (core.m + core.n) as usize <= run;
                if !core.correlated && !single {
                    own_columns.reset(core.m, run);
                    own_rows.reset(core.n, run);
                }
                if let (true, Some(column), Some(row)) = (tabulate, &perms.column, &perms.row) {
                    let identity: Vec<u64> = (0..core.n.max(core.m)).collect();
                    column_table.resize(core.n as usize, 0);
                    row_table.resize(core.m as usize, 0);
                    column.apply_into(&identity[..core.n as usize], &mut column_table);
                    row.apply_into(&identity[..core.m as usize], &mut row_table);
                }
                let mut offset = 0;
                while offset < run {
                    let c = CHUNK.min(run - offset);
                    let first = local + offset as u64;
                    for (j, input) in inputs[..c].iter_mut().enumerate() {
                        *input = first + j as u64;
                    }
                    perms.cell.apply_into(&inputs[..c], &mut cells[..c]);
                    let at = done + offset;
                    let first_index = start + at as u64;
                    if single {
                        let out = &mut points.column_mut(dx)[at..at + c];
                        for (j, (x, &cell)) in out.iter_mut().zip(&cells[..c]).enumerate() {
                            *x = coordinate(cell, first_index + j as u64, dx as u64);
                        }
                        offset += c;
                        continue;
                    }
                    for ((&cell, column), row) in
                        cells[..c].iter().zip(&mut columns[..c]).zip(&mut rows[..c])
                    {
                        (*row, *column) = div_rem(cell, core.m, m_f64);
                    }
                    match (&perms.column, &perms.row) {
                        (Some(_), Some(_)) if tabulate => {
                            for (s, &row) in sub_columns[..c].iter_mut().zip(&rows[..c]) {
                                *s = column_table[row as usize];
                            }
                            for (s, &column) in sub_rows[..c].iter_mut().zip(&columns[..c]) {
                                *s = row_table[column as usize];
                            }
                        }
                        (Some(column_perm), Some(row_perm)) => {
                            column_perm.apply_into(&rows[..c], &mut sub_columns[..c]);
                            row_perm.apply_into(&columns[..c], &mut sub_rows[..c]);
                        }
                        // Uncorrelated: every column and row has its own permutation.
                        _ => {
                            let own = |role, size| {
                                move |which| {
                                    let seed = core.permutation_seed(pass, pair, role, which);
                                    Permutation::new(size, seed)
                                }
                            };
                            let (cs, rs) = (&columns[..c], &rows[..c]);
                            let column_own = own(ROLE_COLUMN, core.n);
                            own_columns.apply_into(cs, rs, &mut sub_columns[..c], column_own);
                            own_rows.apply_into(rs, cs, &mut sub_rows[..c], own(ROLE_ROW, core.m));
                        }
                    }
                    let out = &mut points.column_mut(dx)[at..at + c];
                    for (j, x) in out.iter_mut().enumerate() {
                        let slab = columns[j] * core.n + sub_columns[j];
                        *x = coordinate(slab, first_index + j as u64, dx as u64);
                    }
                    let out = &mut points.column_mut(dx + 1)[at..at + c];
                    for (j, x) in out.iter_mut().enumerate() {
                        let slab = rows[j] * core.m + sub_rows[j];
                        *x = coordinate(slab, first_index + j as u64, dx as u64 + 1);
                    }
                    offset += c;
                }
            }
        }
    }
}

/// Multi-jittered sampling: `N = m * n` points per pass, jittered on the `m x n` grid and
/// N-rooks in both coordinates of every pair of dimensions.
///
/// Every column and row of cells has its own random sub-cell shuffle (Chiu, Shirley & Wang
/// 1994), evaluated by hashed permutations (Kensler 2013) so any point is computed directly.
/// Only whole passes are stratified: integrators use passes of `N` points as replicates.
///
/// ```
/// use mcint::sampler::{MultiJittered, Sampler};
/// let s = MultiJittered::new(2, 3, 4, 7).unwrap(); // 12 points per pass
/// let (mut cells, mut x_slabs, mut y_slabs) = (vec![0; 12], vec![0; 12], vec![0; 12]);
/// let mut p = [0.0; 2];
/// for i in 0..12 {
///     s.point(i, &mut p).unwrap();
///     cells[(p[0] * 3.0) as usize + 3 * (p[1] * 4.0) as usize] += 1;
///     x_slabs[(p[0] * 12.0) as usize] += 1;
///     y_slabs[(p[1] * 12.0) as usize] += 1;
/// }
/// assert!(cells.iter().chain(&x_slabs).chain(&y_slabs).all(|&c| c == 1));
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MultiJittered {
    core: MjCore,
}

impl MultiJittered {
    /// `m >= 1` columns by `n >= 1` rows of cells, `N = m * n <= 2^53` points per pass, in
    /// `dims >= 1` dimensions.
    ///
    /// ```
    /// use mcint::sampler::{MultiJittered, PassKind, Sampler};
    /// let s = MultiJittered::new(3, 4, 8, 0).unwrap();
    /// assert_eq!(s.passes(), PassKind::Fixed { size: 32 });
    /// assert!(MultiJittered::new(2, 0, 8, 0).is_err());
    /// assert!(MultiJittered::new(2, u64::MAX, 2, 0).is_err());
    /// ```
    pub fn new(dims: usize, m: u64, n: u64, seed: u64) -> Result<Self> {
        Ok(MultiJittered {
            core: MjCore::new(dims, m, n, seed, false)?,
        })
    }

    /// `points` per pass (`1 <= points <= 2^53`), with `m <= n`, `m * n = points` and `m` as
    /// close to `sqrt(points)` as possible. A prime count gives a `1 x N` grid, which is
    /// still N-rooks but only one-dimensionally jittered.
    /// The grid comes from the prime factors of `points` (by Pollard's rho), so any count is
    /// quick.
    ///
    /// ```
    /// use mcint::sampler::MultiJittered;
    /// let s = MultiJittered::with_points(2, 24, 0).unwrap();
    /// assert_eq!((s.m(), s.n()), (4, 6));
    /// let prime = MultiJittered::with_points(2, 13, 0).unwrap();
    /// assert_eq!((prime.m(), prime.n()), (1, 13));
    /// assert!(MultiJittered::with_points(2, 0, 0).is_err());
    /// ```
    pub fn with_points(dims: usize, points: u64, seed: u64) -> Result<Self> {
        Ok(MultiJittered {
            core: MjCore::with_points(dims, points, seed, false)?,
        })
    }

    /// Columns of cells, `m`.
    ///
    /// ```
    /// assert_eq!(mcint::sampler::MultiJittered::new(2, 3, 5, 0).unwrap().m(), 3);
    /// ```
    pub fn m(&self) -> u64 {
        self.core.m()
    }

    /// Rows of cells, `n`.
    ///
    /// ```
    /// assert_eq!(mcint::sampler::MultiJittered::new(2, 3, 5, 0).unwrap().n(), 5);
    /// ```
    pub fn n(&self) -> u64 {
        self.core.n()
    }
}

impl Sampler for MultiJittered {
    fn name(&self) -> &'static str {
        "multijitter"
    }

    fn dims(&self) -> usize {
        self.core.dims
    }

    fn passes(&self) -> PassKind {
        PassKind::Fixed {
            size: self.core.pass_size,
        }
    }

    fn seed(&self) -> u64 {
        self.core.seed
    }

    fn reseed(&mut self, seed: u64) {
        self.core.seed = seed;
    }

    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        self.core.point(index, out)
    }

    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        self.core.fill(start, points)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multi_jittered_squarest_divisor_is_closest_to_the_root() {
        for (points, m) in [
            (1, 1),
            (2, 1),
            (4, 2),
            (12, 3),
            (13, 1),
            (36, 6),
            (48, 6),
            (1 << 53, 1 << 26),
        ] {
            assert_eq!(squarest_divisor(points), m, "points = {points}");
        }
        // A large prime walks all the way down.
        assert_eq!(squarest_divisor(1_000_003), 1);
    }
}
