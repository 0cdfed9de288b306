//! Poisson-disk (blue-noise) point sets on the unit torus: dart throwing (Cook 1986,
//! "Stochastic sampling in computer graphics") built with Bridson's algorithm (Bridson 2007,
//! "Fast Poisson disk sampling in arbitrary dimensions").
//!
//! A Poisson-disk set with radius `r` has no two points closer than `r`; it is *maximal* when
//! no further point fits, that is when the balls of radius `r` around its points cover the
//! whole domain. Bridson's algorithm grows such a set from one seed point: it keeps a list of
//! "active" points, and for a random active point tries `k = 30` random candidates in the
//! annulus `r <= |x - p| <= 2r`; the first candidate at least `r` from every point is accepted
//! and becomes active, and an active point whose `k` candidates all fail retires. A background
//! grid of cell size at most `r / sqrt(d)` holds at most one point per cell, so each distance
//! check looks at a fixed number of cells.
//!
//! Bridson's finite `k` leaves small holes, so the set it returns is only nearly maximal. To
//! make it truly maximal we finish with the cell-refinement dart throwing of Ebeida et al.
//! (2012, "A simple algorithm for maximal Poisson-disk sampling in high dimensions"): grid
//! cells not covered by the ball of a single point are kept as "active" cells, darts are
//! thrown uniformly into them, and then every active cell is split into `2^d` children of
//! which only the uncovered ones are kept. A cell inside one ball is certainly covered (a box
//! lies inside a ball when its farthest corner does), so the only thing lost is after
//! `MAX_REFINEMENTS` (30) halvings, when the cells left are smaller than `r * 2^-30` per side: a
//! volume far below anything a Monte Carlo estimate can see.
//!
//! Everything happens on the unit **torus**: distances are periodic (`min(|a - b|, 1 - |a - b|)`
//! per axis), so points near opposite faces repel each other and there is no boundary effect.
//! Finally the whole set is translated by one uniform random vector modulo 1 (a
//! Cranley-Patterson rotation), which preserves every toroidal distance, hence the minimum
//! distance and maximality. Because the translation is uniform and independent of the set,
//! *each point of the set is exactly uniform on `[0,1)^d`*, whatever the (grid-aligned)
//! construction did; a pass is `N` points of the set in a random order, so every point of a
//! pass is uniform too and the pass mean `(1/N) sum f(x_i)` is an unbiased estimate of the
//! integral. Different passes use independent generators, so pass means are independent and
//! their spread gives an honest error bar.
//!
//! The whole pass must be built before any of its points is known, so the samplers in this
//! module build a pass once, keep the last few built passes in a small cache (see
//! `PassCache`), and serve points from it by index.

use std::sync::{Arc, Mutex, OnceLock, PoisonError};

use rand_core::Rng;
use rand_pcg::Pcg64;

use super::{PassKind, Sampler, check_block, check_point};
use crate::hash::{ONE_BELOW, hash_words, unit_f64};
use crate::{Error, Points, Result};

/// Largest supported dimension. The background grid has `(sqrt(d) / r)^d` cells and a
/// distance check visits a neighbourhood of cells that grows as `(2 sqrt(d) + 1)^d`; in 4-D
/// a pass of 4000 points took about 8 s to build (most of it filling Bridson's holes, which
/// grow with the dimension), against 0.4 s in 3-D, so 4-D is not offered.
const MAX_DIMS: usize = 3;
/// Room for coordinates in fixed-size arrays (shared with the best-candidate sampler).
pub(super) const MAX_ARRAY_DIMS: usize = 4;
/// Largest number of points per pass.
const MAX_POINTS: u64 = 1 << 20;
/// Largest number of background-grid cells (4 bytes each).
const MAX_CELLS: u64 = 1 << 22;
/// Bridson's number of candidates per active point.
const BRIDSON_K: usize = 30;
/// Halvings of the gap-filling cells before the residual holes are ignored.
const MAX_REFINEMENTS: u32 = 30;
/// Saturation (jamming) densities of random sequential adsorption of equal balls in 1 to 4
/// dimensions: the fraction of space covered by the disjoint balls of radius `r / 2` around
/// the points of a maximal set. Rényi's parking constant in 1-D; 2-D to 4-D from Torquato,
/// Uche & Stillinger (2006, "Random sequential addition of hard spheres in high Euclidean
/// dimensions"). Bridson's front-growing order gives sets of very nearly the same density
/// (the unit tests check the point counts).
const PACKING_DENSITY: [f64; MAX_DIMS] = [0.747_598, 0.547_07, 0.384_13];
/// Measured ratio of the size of our maximal sets to the packing estimate. Bridson's
/// algorithm grows the set from a front instead of adding points anywhere at random, which
/// packs worse in 1-D (each gap is drawn uniformly from `[r, 2r]`, and refilling the rare
/// gaps wider than `2r` does not make up for it) and almost identically in 2-D and 3-D; the
/// unit test `maximal_set_sizes_match_the_density_constants` checks these within 4%.
const BRIDSON_RATIO: [f64; MAX_DIMS] = [0.88, 0.985, 1.0];
/// Relative margin on the expected size of the maximal set.
const MARGIN_RELATIVE: f64 = 0.06;
/// Margin in units of `sqrt(N)`; the count of a saturated packing fluctuates much less than
/// a Poisson count (whose standard deviation is `sqrt(N)`), so this is many deviations.
const MARGIN_SQRT: f64 = 6.0;
/// Largest radius `new` picks (small `N`): well below the torus limit of one half.
const MAX_AUTO_RADIUS: f64 = 0.4;
/// Rebuilds at the same radius before the radius is shrunk (never seen to be needed).
const RETRIES_AT_RADIUS: u64 = 8;
/// Marks an empty grid cell.
const EMPTY: u32 = u32::MAX;
/// Salt of the generator of a Poisson-disk pass.
const TAG_POISSON: u64 = 0x706f_6973;

/// A maximal Poisson-disk set on the unit torus; a pass is `N` of its points in random order.
///
/// Every pass is a fresh maximal set (independent generator per pass), translated by a
/// uniform random vector, so each point is uniform on `[0,1)^d` and pass means are unbiased.
/// Points of one pass are at least [`radius`](Self::radius) apart (toroidal distance). The
/// `N` points of a pass are a random subset of the maximal set, so they keep the minimum
/// distance but are not themselves maximal; [`maximal_set`](Self::maximal_set) gives the
/// whole set.
///
/// A pass is built once (Bridson's algorithm, then gap filling) on first use and cached, so
/// [`point`](Sampler::point) and [`fill`](Sampler::fill) are cheap after the first call.
///
/// ```
/// use mcint::sampler::{PoissonDisk, Sampler};
/// let s = PoissonDisk::new(2, 256, 7).unwrap();
/// let mut a = [0.0; 2];
/// let mut b = [0.0; 2];
/// s.point(0, &mut a).unwrap();
/// s.point(1, &mut b).unwrap();
/// let gap = |x: f64, y: f64| (x - y).abs().min(1.0 - (x - y).abs());
/// assert!(gap(a[0], b[0]).hypot(gap(a[1], b[1])) >= s.radius());
/// ```
#[derive(Debug)]
pub struct PoissonDisk {
    dims: usize,
    pass_size: u64,
    radius: f64,
    seed: u64,
    cache: PassCache,
}

impl PoissonDisk {
    /// `points` per pass (`1 ..= 2^20`) in `dims` dimensions (`1 ..= 3`).
    ///
    /// The radius is chosen so that a maximal set is expected to hold
    /// `1.06 N + 6 sqrt(N)` points: a maximal set of radius `r` holds about
    /// `phi_d / V_d(r / 2)` points, where `V_d` is the volume of a `d`-ball and `phi_d` the
    /// random-sequential-adsorption saturation density (0.748, 0.547, 0.384 in 1 to 3
    /// dimensions), times a measured correction for Bridson's growth order (0.88 in 1-D,
    /// 0.985 in 2-D, 1 in 3-D). The count of a saturated packing fluctuates far less than `sqrt(N)`, so
    /// the margin is many standard deviations; should a set still come out short it is
    /// rebuilt with a fresh generator (and, after 8 tries, a slightly smaller radius).
    ///
    /// ```
    /// use mcint::sampler::{PassKind, PoissonDisk, Sampler};
    /// let s = PoissonDisk::new(2, 1000, 1).unwrap();
    /// assert_eq!(s.passes(), PassKind::Fixed { size: 1000 });
    /// assert!(PoissonDisk::new(2, 0, 1).is_err());
    /// assert!(PoissonDisk::new(4, 10, 1).is_err());
    /// ```
    pub fn new(dims: usize, points: u64, seed: u64) -> Result<Self> {
        check_supported_dims(dims, MAX_DIMS)?;
        if points == 0 || points > MAX_POINTS {
            return Err(Error::invalid(
                "points",
                points,
                format!("1 ..= {MAX_POINTS} points per pass"),
            ));
        }
        let wanted = expected_needed(points as f64);
        let radius = radius_for_count(dims, wanted).min(MAX_AUTO_RADIUS);
        if grid_cells(dims, radius) > MAX_CELLS {
            return Err(Error::invalid(
                "points",
                points,
                format!(
                    "at most {} points per pass in {dims} dimensions (a background grid of at \
                     most {MAX_CELLS} cells)",
                    max_points_for(dims)
                ),
            ));
        }
        Ok(PoissonDisk {
            dims,
            pass_size: points,
            radius,
            seed,
            cache: PassCache::new(),
        })
    }

    /// Poisson-disk passes with a given minimum distance `radius` (in `(0, 0.5)`, and large
    /// enough that the background grid has at most 2^22 cells).
    ///
    /// The pass size is the largest `N` that [`new`](Self::new) would serve with this radius
    /// or a larger one (at least 1), so passes use almost all of each maximal set.
    ///
    /// ```
    /// use mcint::sampler::{PassKind, PoissonDisk, Sampler};
    /// let s = PoissonDisk::with_radius(2, 0.05, 3).unwrap();
    /// let PassKind::Fixed { size } = s.passes() else { unreachable!() };
    /// assert!(size > 150 && size < 275);
    /// assert!(PoissonDisk::with_radius(2, 0.5, 3).is_err());
    /// ```
    pub fn with_radius(dims: usize, radius: f64, seed: u64) -> Result<Self> {
        check_supported_dims(dims, MAX_DIMS)?;
        // Written so that NaN fails too.
        if !(radius > 0.0 && radius < 0.5) {
            return Err(Error::invalid("radius", radius, "a value in (0, 0.5)"));
        }
        if grid_cells(dims, radius) > MAX_CELLS {
            let smallest = dims_sqrt(dims) / ((MAX_CELLS as f64).powf(1.0 / dims as f64) - 1.0);
            return Err(Error::invalid(
                "radius",
                radius,
                format!(
                    "a value in ({smallest:.3e}, 0.5) in {dims} dimensions (a background grid \
                     of at most {MAX_CELLS} cells)"
                ),
            ));
        }
        let expected = density(dims) / ball_volume(dims, radius / 2.0);
        let points = count_for_expected(expected).clamp(1, MAX_POINTS);
        Ok(PoissonDisk {
            dims,
            pass_size: points,
            radius,
            seed,
            cache: PassCache::new(),
        })
    }

    /// The minimum toroidal distance between points of a pass.
    ///
    /// ```
    /// use mcint::sampler::PoissonDisk;
    /// assert_eq!(PoissonDisk::with_radius(1, 0.01, 0).unwrap().radius(), 0.01);
    /// ```
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The whole maximal set of pass `pass`, one `Vec` of `dims` coordinates per point, in
    /// the pass's order: its first `N` points are the pass.
    ///
    /// ```
    /// use mcint::sampler::{PoissonDisk, Sampler};
    /// let s = PoissonDisk::new(2, 100, 5).unwrap();
    /// let set = s.maximal_set(3);
    /// assert!(set.len() >= 100);
    /// let mut p = [0.0; 2];
    /// s.point(3 * 100 + 7, &mut p).unwrap();
    /// assert_eq!(p.to_vec(), set[7]);
    /// ```
    pub fn maximal_set(&self, pass: u64) -> Vec<Vec<f64>> {
        self.pass_points(pass)
            .chunks_exact(self.dims)
            .map(<[f64]>::to_vec)
            .collect()
    }

    /// The maximal set of a pass, shuffled and translated, point-major.
    fn pass_points(&self, pass: u64) -> Arc<[f64]> {
        self.cache.get_or_build(self.seed, pass, || {
            build_pass(
                self.dims,
                self.radius,
                self.pass_size as usize,
                self.seed,
                pass,
            )
        })
    }
}

impl Clone for PoissonDisk {
    /// A copy with the same parameters and an empty pass cache.
    fn clone(&self) -> Self {
        PoissonDisk {
            dims: self.dims,
            pass_size: self.pass_size,
            radius: self.radius,
            seed: self.seed,
            cache: PassCache::new(),
        }
    }
}

impl Sampler for PoissonDisk {
    fn name(&self) -> &'static str {
        "poisson"
    }

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
        self.cache.clear();
    }

    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        check_point(self.dims, out)?;
        let (pass, i) = (index / self.pass_size, (index % self.pass_size) as usize);
        let data = self.pass_points(pass);
        out.copy_from_slice(&data[i * self.dims..(i + 1) * self.dims]);
        Ok(())
    }

    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        check_block(self.dims, start, points)?;
        fill_from_passes(self.dims, self.pass_size, start, points, |pass| {
            self.pass_points(pass)
        });
        Ok(())
    }
}

/// Copies points `start ..` from cached passes (point-major) into a column-major block,
/// fetching each pass once per run of indices that share it.
pub(super) fn fill_from_passes(
    dims: usize,
    pass_size: u64,
    start: u64,
    points: &mut Points,
    mut pass_points: impl FnMut(u64) -> Arc<[f64]>,
) {
    let len = points.len();
    let mut columns: Vec<&mut [f64]> = points.columns_mut().collect();
    let mut i = 0;
    while i < len {
        let index = start + i as u64;
        let (pass, offset) = (index / pass_size, index % pass_size);
        let run = ((pass_size - offset) as usize).min(len - i);
        let data = pass_points(pass);
        let first = offset as usize;
        for (dim, column) in columns.iter_mut().enumerate() {
            for (k, x) in column[i..i + run].iter_mut().enumerate() {
                *x = data[(first + k) * dims + dim];
            }
        }
        i += run;
    }
}

/// Errors unless `1 <= dims <= max`.
pub(super) fn check_supported_dims(dims: usize, max: usize) -> Result<()> {
    if dims == 0 || dims > max {
        return Err(Error::invalid("dims", dims, format!("1 ..= {max}")));
    }
    Ok(())
}

/// Points per unit volume times `V_d(r / 2)` in our maximal sets.
fn density(dims: usize) -> f64 {
    PACKING_DENSITY[dims - 1] * BRIDSON_RATIO[dims - 1]
}

/// Expected size of the maximal set to ask for so that `n` points are there.
fn expected_needed(n: f64) -> f64 {
    (1.0 + MARGIN_RELATIVE) * n + MARGIN_SQRT * n.sqrt()
}

/// The largest `N` with `expected_needed(N) <= expected`, at least 1.
fn count_for_expected(expected: f64) -> u64 {
    let a = 1.0 + MARGIN_RELATIVE;
    let t = (-MARGIN_SQRT + (MARGIN_SQRT * MARGIN_SQRT + 4.0 * a * expected).sqrt()) / (2.0 * a);
    ((t * t).floor() as u64).max(1)
}

/// Volume of the `dims`-ball of radius `rho`.
fn ball_volume(dims: usize, rho: f64) -> f64 {
    use std::f64::consts::PI;
    let unit = match dims {
        1 => 2.0,
        2 => PI,
        3 => 4.0 / 3.0 * PI,
        _ => PI * PI / 2.0,
    };
    unit * rho.powi(dims as i32)
}

/// The radius whose maximal sets hold `expected` points on average.
fn radius_for_count(dims: usize, expected: f64) -> f64 {
    // expected = phi / V(r / 2)  =>  (r / 2)^d = phi / (V(1) expected).
    let half = (density(dims) / (ball_volume(dims, 1.0) * expected)).powf(1.0 / dims as f64);
    2.0 * half
}

fn dims_sqrt(dims: usize) -> f64 {
    (dims as f64).sqrt()
}

/// Cells per axis of the background grid: side `1/m < r / sqrt(d)`, so a cell's diagonal is
/// shorter than `r` and two points of the set never share a cell.
fn cells_per_axis(dims: usize, radius: f64) -> f64 {
    (dims_sqrt(dims) / radius).floor() + 1.0
}

/// Number of background-grid cells (saturating).
fn grid_cells(dims: usize, radius: f64) -> u64 {
    let m = cells_per_axis(dims, radius);
    let total = m.powi(dims as i32);
    if total >= u64::MAX as f64 {
        u64::MAX
    } else {
        total as u64
    }
}

/// Largest `points` that `new` accepts in `dims` dimensions.
fn max_points_for(dims: usize) -> u64 {
    let (mut lo, mut hi) = (1u64, MAX_POINTS);
    while lo < hi {
        let mid = lo + (hi - lo).div_ceil(2);
        let r = radius_for_count(dims, expected_needed(mid as f64)).min(MAX_AUTO_RADIUS);
        if grid_cells(dims, r) <= MAX_CELLS {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    lo
}

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

/// Periodic distance between two coordinates in `[0, 1)`.
#[inline]
pub(super) fn torus_gap(a: f64, b: f64) -> f64 {
    let d = (a - b).abs();
    d.min(1.0 - d)
}

/// Squared toroidal distance between two points.
#[inline]
pub(super) fn torus_dist2(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(&x, &y)| {
            let g = torus_gap(x, y);
            g * g
        })
        .sum()
}

/// `x` modulo 1, in `[0, 1)`.
#[inline]
pub(super) fn wrap(x: f64) -> f64 {
    let y = x - x.floor();
    if y < 1.0 { y } else { 0.0 }
}

/// Translates every point (point-major) by one uniform random vector, modulo 1.
pub(super) fn random_shift(dims: usize, points: &mut [f64], rng: &mut Pcg64) {
    let shift: Vec<f64> = (0..dims).map(|_| uniform(rng)).collect();
    for point in points.chunks_exact_mut(dims) {
        for (x, s) in point.iter_mut().zip(&shift) {
            *x = wrap(*x + s).min(ONE_BELOW);
        }
    }
}

/// The background grid: at most one point per cell, periodic neighbourhoods.
struct Grid {
    dims: usize,
    m: usize,
    radius2: f64,
    cells: Vec<u32>,
    /// Cell offsets whose cells can hold a point within `r` of a point of the centre cell.
    offsets: Vec<[i64; MAX_ARRAY_DIMS]>,
    /// The points, point-major.
    points: Vec<f64>,
}

impl Grid {
    fn new(dims: usize, radius: f64) -> Grid {
        let m = cells_per_axis(dims, radius) as usize;
        let side = 1.0 / m as f64;
        let reach = (radius * m as f64).ceil() as i64;
        let width = (2 * reach + 1) as usize;
        let mut offsets = Vec::new();
        for k in 0..width.pow(dims as u32) {
            let mut o = [0i64; MAX_ARRAY_DIMS];
            let mut rest = k;
            let mut gap2 = 0.0;
            for slot in o.iter_mut().take(dims) {
                *slot = (rest % width) as i64 - reach;
                rest /= width;
                let gap = (slot.abs() - 1).max(0) as f64 * side;
                gap2 += gap * gap;
            }
            // Two points in cells this far apart are at least sqrt(gap2) apart.
            if gap2 <= radius * radius {
                offsets.push(o);
            }
        }
        Grid {
            dims,
            m,
            radius2: radius * radius,
            cells: vec![EMPTY; m.pow(dims as u32)],
            offsets,
            points: Vec::new(),
        }
    }

    fn len(&self) -> usize {
        self.points.len() / self.dims
    }

    fn point(&self, i: usize) -> &[f64] {
        &self.points[i * self.dims..(i + 1) * self.dims]
    }

    fn cell_coords(&self, x: &[f64]) -> [i64; MAX_ARRAY_DIMS] {
        let mut c = [0i64; MAX_ARRAY_DIMS];
        for (slot, &v) in c.iter_mut().zip(x) {
            *slot = ((v * self.m as f64) as i64).clamp(0, self.m as i64 - 1);
        }
        c
    }

    fn cell_index(&self, c: &[i64; MAX_ARRAY_DIMS]) -> usize {
        let m = self.m as i64;
        c[..self.dims]
            .iter()
            .rev()
            .fold(0usize, |acc, &v| acc * self.m + v.rem_euclid(m) as usize)
    }

    /// Whether some point near `x` (within the offset neighbourhood) satisfies `pred`.
    fn any_near(&self, x: &[f64], mut pred: impl FnMut(&[f64]) -> bool) -> bool {
        let base = self.cell_coords(x);
        for o in &self.offsets {
            let mut c = base;
            for (v, d) in c.iter_mut().zip(o) {
                *v += d;
            }
            let slot = self.cells[self.cell_index(&c)];
            if slot != EMPTY && pred(self.point(slot as usize)) {
                return true;
            }
        }
        false
    }

    /// Adds `x` if it is at least `r` from every point (and its cell is free).
    fn try_insert(&mut self, x: &[f64]) -> bool {
        let r2 = self.radius2;
        if self.any_near(x, |p| torus_dist2(p, x) < r2) {
            return false;
        }
        self.insert_unchecked(x)
    }

    /// Indices of the points that can lie within `r` of a point of base cell `base`.
    fn gather(&self, base: &[i64; MAX_ARRAY_DIMS], out: &mut Vec<u32>) {
        out.clear();
        for o in &self.offsets {
            let mut c = *base;
            for (v, d) in c.iter_mut().zip(o) {
                *v += d;
            }
            let slot = self.cells[self.cell_index(&c)];
            if slot != EMPTY {
                out.push(slot);
            }
        }
    }

    /// Adds `x` if it is at least `r` from every point of `near` (which must hold every point
    /// that can be within `r` of `x`); returns its index.
    fn insert_if_clear(&mut self, x: &[f64], near: &[u32]) -> Option<u32> {
        let r2 = self.radius2;
        if near
            .iter()
            .any(|&i| torus_dist2(self.point(i as usize), x) < r2)
        {
            return None;
        }
        let index = self.len() as u32;
        self.insert_unchecked(x).then_some(index)
    }

    /// Adds `x` without a distance check, unless its cell is taken.
    fn insert_unchecked(&mut self, x: &[f64]) -> bool {
        let cell = self.cell_index(&self.cell_coords(x));
        if self.cells[cell] != EMPTY {
            // Only possible through rounding at distance exactly r; keep one point per cell.
            return false;
        }
        self.cells[cell] = self.len() as u32;
        self.points.extend_from_slice(x);
        true
    }

    /// Whether the box with centre `centre` and half side `half` lies inside the ball of one
    /// point of `near`.
    fn box_covered(&self, centre: &[f64], half: f64, near: &[u32]) -> bool {
        let r2 = self.radius2;
        near.iter().any(|&i| {
            let p = self.point(i as usize);
            let far2: f64 = p
                .iter()
                .zip(centre)
                .map(|(&a, &b)| {
                    let g = torus_gap(a, b) + half;
                    g * g
                })
                .sum();
            far2 <= r2
        })
    }
}

/// The centre of the cell with integer coordinates `c` and side `side`.
fn centre_of(c: &[u64; MAX_ARRAY_DIMS], side: f64, centre: &mut [f64; MAX_ARRAY_DIMS]) {
    for (x, &v) in centre.iter_mut().zip(c) {
        *x = (v as f64 + 0.5) * side;
    }
}

/// One maximal set: Bridson's algorithm, then gap filling; point-major, not yet shuffled.
fn maximal_set(dims: usize, radius: f64, rng: &mut Pcg64) -> Vec<f64> {
    let mut grid = Grid::new(dims, radius);
    let mut x = [0.0; MAX_ARRAY_DIMS];
    let x = &mut x[..dims];

    // Bridson (2007): grow from one uniform seed point.
    for v in x.iter_mut() {
        *v = uniform(rng);
    }
    grid.try_insert(x);
    let mut active: Vec<u32> = vec![0];
    while !active.is_empty() {
        let slot = below(rng, active.len());
        let centre = grid.point(active[slot] as usize).to_vec();
        let mut placed = false;
        for _ in 0..BRIDSON_K {
            // Uniform in the annulus r <= |v| <= 2r: rejection from the cube [-2r, 2r]^d.
            loop {
                let mut norm2 = 0.0;
                for v in x.iter_mut() {
                    *v = (2.0 * uniform(rng) - 1.0) * 2.0 * radius;
                    norm2 += *v * *v;
                }
                let r2 = radius * radius;
                if (r2..=4.0 * r2).contains(&norm2) {
                    break;
                }
            }
            for (v, c) in x.iter_mut().zip(&centre) {
                *v = wrap(*v + c);
            }
            if grid.try_insert(x) {
                active.push(grid.len() as u32 - 1);
                placed = true;
                break;
            }
        }
        if !placed {
            active.swap_remove(slot);
        }
    }

    // Gap filling (Ebeida et al. 2012). A cell is integer coordinates at a level whose side
    // is 1 / (m 2^level); cells stay sorted by the base-grid cell that contains them, so the
    // points that matter to a cell (those within r of its base cell) are gathered once per
    // base cell and shared by all its sub-cells.
    let m = grid.m as u64;
    let mut cells: Vec<[u64; MAX_ARRAY_DIMS]> = (0..m.pow(dims as u32))
        .map(|k| {
            let mut c = [0u64; MAX_ARRAY_DIMS];
            let mut rest = k;
            for v in c.iter_mut().take(dims) {
                *v = rest % m;
                rest /= m;
            }
            c
        })
        .collect();
    let mut side = 1.0 / m as f64;
    let mut level = 0;
    let mut near: Vec<u32> = Vec::new();
    let mut centre = [0.0; MAX_ARRAY_DIMS];
    // Level 0 has no darts: Bridson's set is already nearly maximal, so only uncovered
    // base cells are kept before the first round of darts.
    let mut darts = false;
    while !cells.is_empty() && level <= MAX_REFINEMENTS {
        let child_side = side / 2.0;
        let mut children = Vec::new();
        let mut last_base = usize::MAX;
        for c in &cells {
            let mut base = [0i64; MAX_ARRAY_DIMS];
            for (b, &v) in base.iter_mut().zip(c) {
                *b = (v >> level) as i64;
            }
            let base_index = grid.cell_index(&base);
            if base_index != last_base {
                grid.gather(&base, &mut near);
                last_base = base_index;
            }
            if darts {
                for (v, &k) in x.iter_mut().zip(c) {
                    *v = ((k as f64 + uniform(rng)) * side).min(ONE_BELOW);
                }
                if let Some(added) = grid.insert_if_clear(x, &near) {
                    near.push(added);
                }
            }
            if level == MAX_REFINEMENTS {
                continue;
            }
            centre_of(c, side, &mut centre);
            if grid.box_covered(&centre[..dims], side / 2.0, &near) {
                continue;
            }
            if !darts {
                // Level 0 without darts: keep the uncovered base cell itself.
                children.push(*c);
                continue;
            }
            for k in 0..1u64 << dims {
                let mut child = [0u64; MAX_ARRAY_DIMS];
                for (j, v) in child.iter_mut().enumerate().take(dims) {
                    *v = 2 * c[j] + ((k >> j) & 1);
                }
                centre_of(&child, child_side, &mut centre);
                if !grid.box_covered(&centre[..dims], child_side / 2.0, &near) {
                    children.push(child);
                }
            }
        }
        cells = children;
        if darts {
            side = child_side;
            level += 1;
        }
        darts = true;
    }
    grid.points
}

/// Builds pass `pass`: a maximal set with at least `needed` points, shuffled, translated.
fn build_pass(dims: usize, radius: f64, needed: usize, seed: u64, pass: u64) -> Vec<f64> {
    let mut attempt = 0u64;
    let mut r = radius;
    loop {
        let mut rng = pass_rng(seed, pass, hash_words(TAG_POISSON, &[attempt]));
        let mut points = maximal_set(dims, r, &mut rng);
        let n = points.len() / dims;
        if n >= needed {
            // Fisher-Yates shuffle of whole points, then the uniform translation.
            for i in (1..n).rev() {
                let j = below(&mut rng, i + 1);
                for d in 0..dims {
                    points.swap(i * dims + d, j * dims + d);
                }
            }
            random_shift(dims, &mut points, &mut rng);
            return points;
        }
        attempt += 1;
        if attempt >= RETRIES_AT_RADIUS {
            r *= 0.95;
        }
    }
}

/// A slot that one thread builds and every thread then shares.
type Slot = Arc<OnceLock<Arc<[f64]>>>;

/// The last few built passes, keyed by `(seed, pass)`, least recently used first.
///
/// Lookups hold the lock only to find or create a slot; the build itself runs in
/// [`OnceLock::get_or_init`] outside the lock, so threads building different passes run in
/// parallel while threads wanting the same pass wait for one build. The capacity is the
/// number of available threads (at least 2, at most 8), so that workers on different passes
/// do not evict each other's passes. A poisoned lock (a panic elsewhere while it was held)
/// is recovered: the list is always in a valid state.
pub(super) struct PassCache {
    capacity: usize,
    entries: Mutex<Vec<(u64, u64, Slot)>>,
}

impl PassCache {
    pub(super) fn new() -> Self {
        let capacity = std::thread::available_parallelism()
            .map_or(2, |n| n.get())
            .clamp(2, 8);
        PassCache {
            capacity,
            entries: Mutex::new(Vec::new()),
        }
    }

    /// The pass `(seed, pass)`, built by `build` if it is not cached.
    pub(super) fn get_or_build(
        &self,
        seed: u64,
        pass: u64,
        build: impl FnOnce() -> Vec<f64>,
    ) -> Arc<[f64]> {
        let slot = {
            let mut entries = self.entries.lock().unwrap_or_else(PoisonError::into_inner);
            match entries.iter().position(|e| e.0 == seed && e.1 == pass) {
                Some(at) => {
                    let entry = entries.remove(at);
                    let slot = Arc::clone(&entry.2);
                    entries.push(entry);
                    slot
                }
                None => {
                    if entries.len() >= self.capacity {
                        entries.remove(0);
                    }
                    let slot = Slot::default();
                    entries.push((seed, pass, Arc::clone(&slot)));
                    slot
                }
            }
        };
        Arc::clone(slot.get_or_init(|| Arc::from(build())))
    }

    /// Drops every cached pass.
    pub(super) fn clear(&mut self) {
        self.entries
            .get_mut()
            .unwrap_or_else(PoisonError::into_inner)
            .clear();
    }
}

impl std::fmt::Debug for PassCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PassCache")
            .field("capacity", &self.capacity)
            .finish_non_exhaustive()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Maximal sets hold the number of points the radius rule assumes: within 4% of
    /// `density_d / V_d(r / 2)` (the count of a saturated packing fluctuates by well under 1%
    /// at these sizes, so 4% leaves room only for a wrong density constant).
    #[test]
    fn maximal_set_sizes_match_the_density_constants() {
        for dims in 1..=MAX_DIMS {
            let radius = [0.002, 0.02, 0.06][dims - 1];
            let expected = density(dims) / ball_volume(dims, radius / 2.0);
            for seed in 0..2 {
                let mut rng = pass_rng(seed, 0, 1);
                let n = (maximal_set(dims, radius, &mut rng).len() / dims) as f64;
                let ratio = n / expected;
                assert!(
                    (0.96..1.04).contains(&ratio),
                    "dims {dims}: {n} vs {expected}"
                );
            }
        }
    }

    #[test]
    fn count_rule_inverts_the_margin() {
        for n in [1u64, 2, 10, 1000, 123_456] {
            assert_eq!(count_for_expected(expected_needed(n as f64) + 1e-9), n);
        }
    }

    #[test]
    fn cache_recovers_from_a_poisoned_lock() {
        let cache = PassCache::new();
        let _ = std::thread::scope(|s| {
            s.spawn(|| {
                let _guard = cache.entries.lock();
                panic!("poison the lock");
            })
            .join()
        });
        assert!(cache.entries.is_poisoned());
        assert_eq!(&*cache.get_or_build(1, 2, || vec![0.5]), &[0.5]);
        assert_eq!(&*cache.get_or_build(1, 2, || vec![0.25]), &[0.5]);
    }
}
