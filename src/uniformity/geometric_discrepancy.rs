//! [`geometric_discrepancy`]: how far apart a set's points are, by the minimum distance
//! between two of them or the mean edge of their Euclidean minimum spanning tree (scipy's
//! `qmc.geometric_discrepancy`). Higher is better, unlike the L2 discrepancies.

use super::discrepancy::check_unit_cube;
use crate::error::{Error, Result};
use crate::points::Points;

/// What [`geometric_discrepancy`] measures (scipy's `method`).
///
/// ```
/// use mcint::quality::GeometricCriterion;
/// assert_eq!("mst".parse::<GeometricCriterion>()?, GeometricCriterion::MinimumSpanningTree);
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GeometricCriterion {
    /// The smallest Euclidean distance between two distinct points (`'mindist'`).
    MinDistance,
    /// The mean edge length of the Euclidean minimum spanning tree (`'mst'`; Franco et al.
    /// 2009).
    MinimumSpanningTree,
}

impl std::str::FromStr for GeometricCriterion {
    type Err = Error;

    /// scipy's names: `mindist` or `mst`.
    ///
    /// ```
    /// use mcint::quality::GeometricCriterion;
    /// assert!("mindist".parse::<GeometricCriterion>().is_ok());
    /// assert!("max".parse::<GeometricCriterion>().is_err());
    /// ```
    fn from_str(name: &str) -> Result<GeometricCriterion> {
        match name {
            "mindist" => Ok(GeometricCriterion::MinDistance),
            "mst" => Ok(GeometricCriterion::MinimumSpanningTree),
            other => Err(Error::invalid("criterion", other, "mindist or mst")),
        }
    }
}

/// The geometric discrepancy of `points` in `[0, 1]^d` (at least two distinct points): the
/// minimum distance between two points or the mean edge of the minimum spanning tree,
/// Euclidean, as scipy 1.17's `qmc.geometric_discrepancy` computes them. As there, points
/// that coincide are not joined by an edge of length 0: the minimum is over distinct points,
/// and the tree joins each copy to the others by its own edges. `O(N^2 d)` time (Prim's
/// algorithm on the complete graph), `O(N)` memory.
///
/// ```
/// use mcint::quality::{GeometricCriterion, geometric_discrepancy};
/// use mcint::sampler::{Independent, LatinHypercube, Sampler};
/// use mcint::Points;
/// let square = Points::from_rows(&[[0.0, 0.0], [0.0, 0.5], [0.5, 0.0], [0.5, 0.5]])?;
/// assert_eq!(geometric_discrepancy(&square, GeometricCriterion::MinDistance)?, 0.5);
/// assert_eq!(geometric_discrepancy(&square, GeometricCriterion::MinimumSpanningTree)?, 0.5);
/// assert!(geometric_discrepancy(&Points::from_rows(&[[0.5]])?, GeometricCriterion::MinDistance).is_err());
/// # Ok::<(), mcint::Error>(())
/// ```
pub fn geometric_discrepancy(points: &Points, criterion: GeometricCriterion) -> Result<f64> {
    check_unit_cube(points)?;
    let n = points.len();
    if n < 2 {
        return Err(Error::invalid(
            "number of points",
            n,
            "at least 2 (a distance needs two points)",
        ));
    }
    let distance = |i: usize, j: usize| {
        (0..points.dims())
            .map(|k| {
                let t = points.get(i, k) - points.get(j, k);
                t * t
            })
            .sum::<f64>()
            .sqrt()
    };
    let value = match criterion {
        GeometricCriterion::MinDistance => (0..n)
            .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
            .map(|(i, j)| distance(i, j))
            .filter(|&t| t > 0.0)
            .fold(f64::INFINITY, f64::min),
        GeometricCriterion::MinimumSpanningTree => mean_tree_edge(n, distance),
    };
    if !value.is_finite() {
        return Err(Error::invalid(
            "points",
            format!("{n} copies of one point"),
            "at least two distinct points",
        ));
    }
    Ok(value)
}

/// The mean edge length of the minimum spanning forest of the complete graph on `n` vertices
/// with edge lengths `distance`, zero-length edges left out (Prim's algorithm, `O(n^2)`);
/// infinite when there is no edge.
fn mean_tree_edge(n: usize, distance: impl Fn(usize, usize) -> f64) -> f64 {
    let mut in_tree = vec![false; n];
    // The shortest edge from each vertex outside the tree into it.
    let mut nearest = vec![f64::INFINITY; n];
    let (mut total, mut edges) = (0.0, 0u64);
    let mut next = Some(0);
    while let Some(v) = next {
        in_tree[v] = true;
        next = None;
        for u in 0..n {
            if in_tree[u] {
                continue;
            }
            let t = distance(u, v);
            if t > 0.0 && t < nearest[u] {
                nearest[u] = t;
            }
            if next.is_none_or(|w: usize| nearest[u] < nearest[w]) {
                next = Some(u);
            }
        }
        if let Some(u) = next
            && nearest[u].is_finite()
        {
            total += nearest[u];
            edges += 1;
        }
    }
    if edges == 0 {
        f64::INFINITY
    } else {
        total / edges as f64
    }
}
