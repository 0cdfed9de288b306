//! The exact star discrepancy `D*_N` of a point set in one or two dimensions.
//!
//! `D*_N = sup_t |vol([0, t)) - #{x_i in [0, t)} / N|` over `t` in `[0, 1]^d`, taken over both
//! open boxes `[0, t)` and closed boxes `[0, t]` (the two suprema agree for points in
//! `[0, 1)^d`; the closed boxes also see points with a coordinate equal to 1).
//!
//! The supremum is attained, or approached, at a grid point: with `G_k` the distinct values of
//! coordinate `k` together with 1,
//!
//! ```text
//! D*_N = max over t in G_1 x ... x G_d of max( vol(t) - #{x < t} / N, #{x <= t} / N - vol(t) )
//! ```
//!
//! (Niederreiter 1972; the form of Gnewuch, Srivastav & Winzen 2009): between grid values the
//! counts are constant, so `vol - count` is largest at the upper end of a cell for open boxes
//! and `count - vol` at the lower end for closed ones. In two dimensions the grid has
//! `O(N^2)` points; sweeping `x` upward while keeping, for each distinct `y`, the number of
//! points already passed, one pass over the `y` values per column gives every count, for
//! `O(N^2)` time and `O(N)` memory. In one dimension it is a sort, `O(N log N)`. In higher
//! dimensions computing `D*_N` is NP-hard (Gnewuch, Srivastav & Winzen 2009), and this module
//! does not try.

use super::discrepancy::check_unit_cube;
use crate::error::{Error, Result};
use crate::points::Points;

/// The most points [`star_discrepancy`] accepts in two dimensions, `2^14 = 16384`: its sweep
/// costs about `N^2` steps, about a second at this size.
///
/// ```
/// assert_eq!(mcint::quality::STAR_DISCREPANCY_MAX_POINTS, 16384);
/// ```
pub const STAR_DISCREPANCY_MAX_POINTS: usize = 1 << 14;

/// The exact star discrepancy `D*_N` of a set of points in `[0, 1]` or `[0, 1]^2`:
///
/// ```text
/// D*_N = sup over t in [0, 1]^d of |vol([0, t)) - #{x_i in B_t} / N|
/// ```
///
/// over both open boxes `B_t = [0, t)` and closed boxes `B_t = [0, t]` (for points in
/// `[0, 1)^d` the two suprema agree, and this is the usual `D*_N`; the closed boxes also count
/// points with a coordinate equal to 1). It is the maximum over the grid of point coordinates
/// and 1 of `vol(t) - #{x < t} / N` and `#{x <= t} / N - vol(t)` (Niederreiter 1972), found by
/// a sweep in `O(N^2)` time and `O(N)` memory in two dimensions (about a second at
/// [`STAR_DISCREPANCY_MAX_POINTS`]) and by a sort in one. Rounding: one in each volume and one
/// in each difference, so the result is within a few `1e-16` of the exact value.
///
/// Errors ([`Error::InvalidParameter`](crate::Error::InvalidParameter)) for a dimension other
/// than 1 or 2 (in general the problem is NP-hard: Gnewuch, Srivastav & Winzen 2009), for
/// more than [`STAR_DISCREPANCY_MAX_POINTS`] points in two dimensions, for no points, and for
/// coordinates that are NaN or outside `[0, 1]`.
///
/// ```
/// use mcint::{Points, quality::star_discrepancy};
/// // The midpoints (2i - 1) / (2N) have D* = 1 / (2N) (Niederreiter 1992, Theorem 2.6).
/// let mut line = Points::new(1, 5)?;
/// line.column_mut(0).copy_from_slice(&[0.1, 0.3, 0.5, 0.7, 0.9]);
/// assert!((star_discrepancy(&line)? - 0.1).abs() < 1e-15);
/// // One point at (1/2, 1/2): the closed box [0, 1/2]^2 holds it and has volume 1/4.
/// let mut square = Points::new(2, 1)?;
/// square.column_mut(0)[0] = 0.5;
/// square.column_mut(1)[0] = 0.5;
/// assert_eq!(star_discrepancy(&square)?, 0.75);
/// assert!(star_discrepancy(&Points::new(3, 4)?).is_err());
/// # Ok::<(), mcint::Error>(())
/// ```
pub fn star_discrepancy(points: &Points) -> Result<f64> {
    match points.dims() {
        1 => {
            check_unit_cube(points)?;
            Ok(one_dimensional(points.column(0)))
        }
        2 => {
            if points.len() > STAR_DISCREPANCY_MAX_POINTS {
                return Err(Error::invalid(
                    "number of points",
                    points.len(),
                    format!(
                        "at most {STAR_DISCREPANCY_MAX_POINTS} for the exact star discrepancy \
                         in two dimensions (its cost grows as N^2)"
                    ),
                ));
            }
            check_unit_cube(points)?;
            Ok(two_dimensional(points.column(0), points.column(1)))
        }
        dims => Err(Error::invalid(
            "dims",
            dims,
            "1 or 2 for the exact star discrepancy (NP-hard in general)",
        )),
    }
}

/// `count / n` for every count `0..=n`, each correctly rounded, so that the sweep multiplies
/// nothing by an inexact `1 / n`.
fn fractions(n: usize) -> Vec<f64> {
    (0..=n).map(|count| count as f64 / n as f64).collect()
}

/// The distinct values of `values` in increasing order, with 1 appended if absent.
/// `-0.0` and `0.0` are one value.
fn grid(values: &[f64]) -> Vec<f64> {
    let mut grid: Vec<f64> = values.iter().map(|&v| v + 0.0).collect();
    grid.sort_by(f64::total_cmp);
    grid.dedup();
    if grid.last() != Some(&1.0) {
        grid.push(1.0);
    }
    grid
}

fn one_dimensional(xs: &[f64]) -> f64 {
    let fraction = fractions(xs.len());
    let mut sorted: Vec<f64> = xs.iter().map(|&v| v + 0.0).collect();
    sorted.sort_by(f64::total_cmp);
    let mut best = 0.0f64;
    let mut below = 0; // points < a
    for a in grid(xs) {
        let mut at_or_below = below;
        while at_or_below < sorted.len() && sorted[at_or_below] <= a {
            at_or_below += 1;
        }
        best = best.max(a - fraction[below]).max(fraction[at_or_below] - a);
        below = at_or_below;
    }
    best
}

fn two_dimensional(xs: &[f64], ys: &[f64]) -> f64 {
    let n = xs.len();
    let fraction = fractions(n);
    let y_grid = grid(ys);
    // Points in increasing x, each with the rank of its y in the grid.
    let mut order: Vec<(f64, usize)> = xs
        .iter()
        .zip(ys)
        .map(|(&x, &y)| {
            let rank = y_grid.partition_point(|&g| g < y + 0.0);
            (x + 0.0, rank)
        })
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0));

    // passed[r]: points with x below the current column and y equal to y_grid[r], which is
    // also every point with x at most the previous column. One pass per column serves both the
    // open boxes [0, a) x [0, b) of this column (points with x < a and y < b) and the closed
    // boxes [0, a'] x [0, b] of the previous column a' (points with x <= a' and y <= b).
    let mut passed = vec![0u32; y_grid.len()];
    let (mut best_open, mut best_closed) = (0.0f64, 0.0f64);
    let mut previous = 0.0; // no closed box before the first column: its counts are all 0
    let mut next = 0;
    for a in grid(xs) {
        let mut count = 0usize;
        for (&b, &at_b) in y_grid.iter().zip(&passed) {
            best_open = best_open.max(a * b - fraction[count]);
            count += at_b as usize;
            best_closed = best_closed.max(fraction[count] - previous * b);
        }
        while next < n && order[next].0 == a {
            passed[order[next].1] += 1;
            next += 1;
        }
        previous = a;
    }
    // The closed boxes of the last column (a = 1), which hold every point with y <= b.
    let mut count = 0usize;
    for (&b, &at_b) in y_grid.iter().zip(&passed) {
        count += at_b as usize;
        best_closed = best_closed.max(fraction[count] - previous * b);
    }
    best_open.max(best_closed)
}
