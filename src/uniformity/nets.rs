//! Net quality: whether a point set is a `(t, m, d)`-net in base 2, and its smallest `t`.
//!
//! An *elementary interval* in base 2 (Niederreiter 1992, "Random Number Generation and
//! Quasi-Monte Carlo Methods", ch. 4) is a box
//! `prod_j [a_j 2^-e_j, (a_j + 1) 2^-e_j)` with integer exponents `e_j >= 0` and cells
//! `0 <= a_j < 2^e_j`; its volume is `2^-(e_1 + ... + e_d)`. A set of `N = 2^m` points in
//! `[0,1)^d` is a `(t, m, d)`-net in base 2 when every elementary interval of volume
//! `2^(t-m)` holds exactly `2^t` points, for every *shape* (split of the total exponent
//! `m - t` among the dimensions). A `(t, m, d)`-net is also a `(t', m, d)`-net for every
//! `t' >= t` (a coarser interval is a union of finer ones), so the *t-value* of a set is the
//! smallest such `t`; `t = 0` is perfect stratification, `t = m` says nothing.
//!
//! # Algorithm
//!
//! Each coordinate is turned once into its first `m` binary digits, the integer
//! `floor(x * 2^m)` (exact in floating point, since scaling by a power of two does not
//! round). The cell of a point in the interval shape `(e_1, ..., e_d)` is then the
//! concatenation of the top `e_j` digits of each coordinate, a `k = sum e_j`-bit integer, so
//! checking a shape is one counting pass over the points into `2^k` counters. The shapes of a
//! level `k` are enumerated depth first, dimension by dimension, so the partial cell indices
//! of the first dimensions are shared by all shapes that continue them: a level costs about
//! `N` operations per shape, and there are `C(k + d - 1, d - 1)` shapes at level `k`.
//! [`t_value`] checks the levels `k = 1, 2, ...` until one fails (at most `m` levels, and
//! `m - t + 1` of them), stopping at the first unbalanced cell. `2^16` points in two
//! dimensions are about 150 shapes of 65,536 points; the first `2^10` Sobol' points in eight
//! dimensions (`t = 5`) about 3,000 shapes of 1,024 points.
//! The number of shapes grows like `k^(d-1)`: sets with small t in many dimensions are
//! expensive (`d = 16`, `k = 8`: 490,314 shapes), while sets that fail early are cheap.

use crate::error::{Error, Result};
use crate::points::Points;
use std::fmt;

/// The most points a net check accepts: counters are 32-bit.
const MAX_POINTS: usize = 1 << 31;

/// An elementary interval that does not hold the number of points a net requires.
///
/// The interval's side along dimension `j` is `[cell[j] / 2^exponents[j], (cell[j] + 1) / 2^exponents[j])`.
///
/// ```
/// use mcint::{Points, quality::{shape_balanced, UnbalancedInterval}};
/// // Two points both in the left half of [0, 1)^1.
/// let mut points = Points::new(1, 2)?;
/// points.column_mut(0).copy_from_slice(&[0.1, 0.3]);
/// let bad: UnbalancedInterval = shape_balanced(&points, &[1])?.expect("halves are unequal");
/// assert_eq!((bad.exponents.clone(), bad.cell.clone()), (vec![1], vec![0]));
/// assert_eq!((bad.count, bad.expected), (2, 1));
/// assert_eq!(bad.bounds(), vec![(0.0, 0.5)]);
/// assert_eq!(
///     bad.to_string(),
///     "elementary interval [0/2, 1/2) (exponents [1]) holds 2 points, a net needs 1"
/// );
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnbalancedInterval {
    /// The exponent `e_j` of each dimension: side `2^-e_j`.
    pub exponents: Vec<u32>,
    /// The cell `a_j` of each dimension, `0 <= a_j < 2^e_j`.
    pub cell: Vec<u64>,
    /// How many points the interval holds.
    pub count: u64,
    /// How many it should hold: `N / 2^(sum of exponents)`.
    pub expected: u64,
}

impl UnbalancedInterval {
    /// The interval as one `(low, high)` pair per dimension.
    ///
    /// ```
    /// use mcint::quality::UnbalancedInterval;
    /// let bad = UnbalancedInterval { exponents: vec![2, 0], cell: vec![3, 0], count: 2, expected: 1 };
    /// assert_eq!(bad.bounds(), vec![(0.75, 1.0), (0.0, 1.0)]);
    /// ```
    pub fn bounds(&self) -> Vec<(f64, f64)> {
        self.exponents
            .iter()
            .zip(&self.cell)
            .map(|(&e, &a)| {
                let side = 0.5f64.powi(e as i32);
                (a as f64 * side, (a + 1) as f64 * side)
            })
            .collect()
    }
}

impl fmt::Display for UnbalancedInterval {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "elementary interval ")?;
        for (j, (&e, &a)) in self.exponents.iter().zip(&self.cell).enumerate() {
            if j > 0 {
                write!(f, " x ")?;
            }
            let denominator = 1u128 << e;
            write!(f, "[{a}/{denominator}, {}/{denominator})", a + 1)?;
        }
        write!(
            f,
            " (exponents {:?}) holds {} points, a net needs {}",
            self.exponents, self.count, self.expected
        )
    }
}

/// The outcome of [`elementary_intervals_balanced`]: whether a set of `2^m` points is a
/// `(t, m, d)`-net in base 2, and if not, the first elementary interval that says so.
///
/// ```
/// use mcint::{Points, quality::elementary_intervals_balanced};
/// let mut points = Points::new(2, 4)?;
/// points.column_mut(0).copy_from_slice(&[0.0, 0.25, 0.5, 0.75]);
/// points.column_mut(1).copy_from_slice(&[0.0, 0.5, 0.25, 0.75]);
/// let check = elementary_intervals_balanced(&points, 0)?;
/// assert_eq!((check.m, check.t), (2, 0));
/// assert!(check.is_net() && check.first_unbalanced.is_none());
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NetCheck {
    /// `log2` of the number of points.
    pub m: u32,
    /// The `t` that was checked.
    pub t: u32,
    /// The first elementary interval of volume `2^(t-m)` that does not hold `2^t` points, in
    /// the order of shapes (exponent vectors, lexicographically increasing) and then of cells
    /// (row-major, the first dimension most significant); `None` for a net.
    pub first_unbalanced: Option<UnbalancedInterval>,
}

impl NetCheck {
    /// True when the set is a `(t, m, d)`-net.
    ///
    /// ```
    /// use mcint::{Points, quality::elementary_intervals_balanced};
    /// let mut points = Points::new(1, 2)?;
    /// points.column_mut(0).copy_from_slice(&[0.1, 0.2]);
    /// assert!(!elementary_intervals_balanced(&points, 0)?.is_net());
    /// assert!(elementary_intervals_balanced(&points, 1)?.is_net());
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn is_net(&self) -> bool {
        self.first_unbalanced.is_none()
    }
}

/// Checks whether `points` (`N = 2^m` of them) form a `(t, m, d)`-net in base 2: whether every
/// elementary interval of volume `2^(t-m)`, of every shape, holds exactly `2^t` points.
///
/// Errors: an empty set, `N` not a power of two (the message names the nearest powers),
/// `N > 2^31`, a coordinate outside `[0, 1)` (or NaN), `t > m`.
///
/// ```
/// use mcint::{Points, quality::elementary_intervals_balanced, sampler::{Sampler, Scramble, Sobol}};
/// let mut points = Points::new(2, 256)?;
/// Sobol::new(2, Scramble::Owen, 3)?.fill(0, &mut points)?;
/// assert!(elementary_intervals_balanced(&points, 0)?.is_net());
/// // Move one point: the 1 x 1/256 column it left is now empty.
/// points.column_mut(0)[0] = (points.get(0, 0) + 0.5) % 1.0;
/// let bad = elementary_intervals_balanced(&points, 0)?.first_unbalanced.unwrap();
/// assert_eq!(bad.exponents.iter().sum::<u32>(), 8);
/// assert!(bad.count != bad.expected);
/// # Ok::<(), mcint::Error>(())
/// ```
pub fn elementary_intervals_balanced(points: &Points, t: u32) -> Result<NetCheck> {
    let digits = Digits::new(points)?;
    if t > digits.m {
        return Err(Error::invalid(
            "t",
            t,
            format!(
                "at most m = {} (log2 of the {} points)",
                digits.m,
                points.len()
            ),
        ));
    }
    let level = digits.m - t;
    Ok(NetCheck {
        m: digits.m,
        t,
        first_unbalanced: digits.first_unbalanced_at_level(level),
    })
}

/// Checks one shape: whether every elementary interval with side `2^-exponents[j]` along
/// dimension `j` holds exactly `N / 2^(sum of exponents)` points. Returns the first cell
/// (row-major, the first dimension most significant) that does not, or `None`.
///
/// Errors as for [`elementary_intervals_balanced`], plus `exponents.len() != points.dims()`
/// and a sum of exponents above `m`.
///
/// ```
/// use mcint::{Points, quality::shape_balanced, sampler::{Jittered, Sampler}};
/// // A jittered 4 x 4 set is balanced in the square shape (2, 2) but not in (4, 0).
/// let mut points = Points::new(2, 16)?;
/// Jittered::new(2, 4, 7)?.fill(0, &mut points)?;
/// assert!(shape_balanced(&points, &[2, 2])?.is_none());
/// assert!(shape_balanced(&points, &[4, 0])?.is_some());
/// # Ok::<(), mcint::Error>(())
/// ```
pub fn shape_balanced(points: &Points, exponents: &[u32]) -> Result<Option<UnbalancedInterval>> {
    if exponents.len() != points.dims() {
        return Err(Error::DimensionMismatch {
            what: "exponents of an elementary interval",
            expected: points.dims(),
            found: exponents.len(),
        });
    }
    let digits = Digits::new(points)?;
    let total = exponents
        .iter()
        .try_fold(0u32, |sum, &e| sum.checked_add(e));
    match total {
        Some(k) if k <= digits.m => Ok(digits.first_unbalanced_in_shape(exponents)),
        _ => Err(Error::invalid(
            "exponents",
            format!("{exponents:?}"),
            format!(
                "exponents summing to at most m = {} (log2 of the {} points)",
                digits.m,
                points.len()
            ),
        )),
    }
}

/// The t-value of a set of `N = 2^m` points in base 2: the smallest `t` such that the set is a
/// `(t, m, d)`-net (every elementary interval of volume `2^(t-m)` holds `2^t` points).
///
/// `t = 0` for the first `2^m` points of a Sobol' sequence in one or two dimensions, for
/// Hammersley sets in two dimensions and for pmj02 prefixes; independent uniform points
/// have `t` close to `m`. The cost is about `N` counter increments per interval shape
/// checked: `C(k + d - 1, d - 1)` shapes at each level `k = 1 ..= m - t + 1` (see the module
/// source). To see *which* interval fails at `t - 1`, call
/// [`elementary_intervals_balanced`]`(points, t - 1)`.
///
/// Errors: an empty set, `N` not a power of two (the message names the nearest powers),
/// `N > 2^31`, a coordinate outside `[0, 1)` (or NaN).
///
/// ```
/// use mcint::{Points, quality::t_value, sampler::{Hammersley, Independent, Sampler, Scramble}};
/// let mut points = Points::new(2, 1024)?;
/// Hammersley::new(2, 1024, Scramble::None, 0)?.fill(0, &mut points)?;
/// assert_eq!(t_value(&points)?, 0);
/// Independent::new(2, 1)?.fill(0, &mut points)?;
/// assert!(t_value(&points)? >= 8);
/// let err = t_value(&Points::new(2, 1000)?).unwrap_err();
/// assert!(err.to_string().contains("512 or 1024"));
/// # Ok::<(), mcint::Error>(())
/// ```
pub fn t_value(points: &Points) -> Result<u32> {
    let digits = Digits::new(points)?;
    // Balance at level k implies balance at every coarser level, so the first failing
    // level k gives t = m - k + 1.
    for level in 1..=digits.m {
        if digits.first_unbalanced_at_level(level).is_some() {
            return Ok(digits.m - level + 1);
        }
    }
    Ok(0)
}

/// The first `m` binary digits of every coordinate, `floor(x * 2^m)`, column by column.
struct Digits {
    m: u32,
    dims: usize,
    len: usize,
    /// Column-major like [`Points`]: digits of coordinate `j` of point `i` at `j * len + i`.
    words: Vec<u64>,
}

impl Digits {
    fn new(points: &Points) -> Result<Self> {
        let len = points.len();
        if len == 0 {
            return Err(Error::invalid(
                "points",
                "an empty set",
                "N = 2^m points, m >= 0",
            ));
        }
        if len > MAX_POINTS {
            return Err(Error::IndexOutOfRange {
                what: "number of points of a net check",
                limit: MAX_POINTS as u64,
            });
        }
        if !len.is_power_of_two() {
            let below = 1usize << (usize::BITS - 1 - len.leading_zeros());
            return Err(Error::invalid(
                "number of points",
                len,
                format!(
                    "a power of two, N = 2^m (nearest: {below} or {})",
                    below * 2
                ),
            ));
        }
        let m = len.trailing_zeros();
        let scale = (1u64 << m) as f64;
        let dims = points.dims();
        let mut words = Vec::with_capacity(dims * len);
        for dim in 0..dims {
            for (i, &x) in points.column(dim).iter().enumerate() {
                if !(0.0..1.0).contains(&x) {
                    return Err(Error::invalid(
                        "points",
                        format!("coordinate {x} of point {i} in dimension {dim}"),
                        "every coordinate in [0, 1)",
                    ));
                }
                // Exact: scaling by a power of two does not round, and x < 1 keeps it below 2^m.
                words.push((x * scale) as u64);
            }
        }
        Ok(Digits {
            m,
            dims,
            len,
            words,
        })
    }

    fn column(&self, dim: usize) -> &[u64] {
        &self.words[dim * self.len..(dim + 1) * self.len]
    }

    /// The first unbalanced interval among all shapes of total exponent `level`.
    fn first_unbalanced_at_level(&self, level: u32) -> Option<UnbalancedInterval> {
        let mut search = ShapeSearch {
            digits: self,
            exponents: vec![0; self.dims],
            partial: vec![vec![0; self.len]; self.dims],
            counts: vec![0; 1 << level],
        };
        search.visit(0, level)
    }

    fn first_unbalanced_in_shape(&self, exponents: &[u32]) -> Option<UnbalancedInterval> {
        let mut cells = vec![0u64; self.len];
        for (dim, &e) in exponents.iter().enumerate() {
            append_digits(&mut cells, self.column(dim), self.m, e);
        }
        let level: u32 = exponents.iter().sum();
        let mut counts = vec![0; 1 << level];
        first_unbalanced_cell(&cells, &mut counts, self.len >> level)
            .map(|(cell, count)| unbalanced(exponents, cell, count, (self.len >> level) as u64))
    }
}

/// Depth-first enumeration of the shapes of one level, sharing the partial cell indices of
/// the leading dimensions between shapes.
struct ShapeSearch<'a> {
    digits: &'a Digits,
    exponents: Vec<u32>,
    /// `partial[j]`: cell index of every point from the digits of dimensions `0..j`.
    partial: Vec<Vec<u64>>,
    counts: Vec<u32>,
}

impl ShapeSearch<'_> {
    /// Assigns exponents to dimensions `dim..` with `remaining` digits left to give.
    fn visit(&mut self, dim: usize, remaining: u32) -> Option<UnbalancedInterval> {
        let digits = self.digits;
        let last = digits.dims - 1;
        if dim == last {
            self.exponents[last] = remaining;
            let mut cells = std::mem::take(&mut self.partial[last]);
            append_digits(&mut cells, digits.column(last), digits.m, remaining);
            let level: u32 = self.exponents.iter().sum();
            let expected = digits.len >> level;
            let found = first_unbalanced_cell(&cells, &mut self.counts[..1 << level], expected);
            // The caller rewrites this buffer before the next shape (with one dimension there
            // is no caller and a single shape).
            self.partial[last] = cells;
            return found
                .map(|(cell, count)| unbalanced(&self.exponents, cell, count, expected as u64));
        }
        for e in 0..=remaining {
            self.exponents[dim] = e;
            let (head, tail) = self.partial.split_at_mut(dim + 1);
            tail[0].copy_from_slice(&head[dim]);
            append_digits(&mut tail[0], digits.column(dim), digits.m, e);
            if let Some(bad) = self.visit(dim + 1, remaining - e) {
                return Some(bad);
            }
        }
        None
    }
}

/// Appends the top `e` of the `m` digits of each coordinate to its cell index.
fn append_digits(cells: &mut [u64], words: &[u64], m: u32, e: u32) {
    if e == 0 {
        return;
    }
    let shift = m - e;
    for (cell, &w) in cells.iter_mut().zip(words) {
        *cell = (*cell << e) | (w >> shift);
    }
}

/// Counts the points of each cell (`counts.len()` cells) and returns the first cell whose
/// count is not `expected`, with its count.
fn first_unbalanced_cell(cells: &[u64], counts: &mut [u32], expected: usize) -> Option<(u64, u64)> {
    counts.fill(0);
    for &c in cells {
        counts[c as usize] += 1;
    }
    counts
        .iter()
        .position(|&c| c as usize != expected)
        .map(|i| (i as u64, u64::from(counts[i])))
}

/// Splits a row-major cell index of the given shape into per-dimension cells.
fn unbalanced(exponents: &[u32], cell: u64, count: u64, expected: u64) -> UnbalancedInterval {
    let mut rest = cell;
    let mut cells = vec![0; exponents.len()];
    for (slot, &e) in cells.iter_mut().zip(exponents).rev() {
        *slot = rest & ((1u64 << e) - 1);
        rest >>= e;
    }
    UnbalancedInterval {
        exponents: exponents.to_vec(),
        cell: cells,
        count,
        expected,
    }
}
