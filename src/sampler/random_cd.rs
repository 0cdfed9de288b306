//! [`random_cd`]: lower a design's centered discrepancy by swapping coordinates between
//! points, which keeps a Latin hypercube a Latin hypercube (scipy's
//! `LatinHypercube(optimization="random-cd")`).

use super::pass_rng::{below, pass_rng};
use crate::error::{Error, Result};
use crate::points::Points;
use crate::uniformity::Discrepancy;

/// Tags the random stream of the swaps.
const TAG: u64 = 0x7261_6e64_6f6d_6364; // "randomcd"

/// How long [`random_cd`] searches: scipy's defaults are 10 000 swaps tried, stopping after
/// 100 in a row that did not help.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RandomCd {
    /// The most swaps tried.
    pub max_tries: u64,
    /// Stop after this many tries in a row that did not lower the discrepancy.
    pub patience: u64,
}

impl Default for RandomCd {
    /// scipy's `n_iters = 10000`, `n_nochange = 100`.
    ///
    /// ```
    /// assert_eq!(mcint::sampler::RandomCd::default().max_tries, 10_000);
    /// ```
    fn default() -> Self {
        RandomCd {
            max_tries: 10_000,
            patience: 100,
        }
    }
}

/// Lowers the squared centered discrepancy `CD^2` of `points` in place by random swaps of one
/// coordinate between two points, each kept only if it lowers `CD^2` (Jin, Chen & Sudjianto
/// 2005; scipy's `random-cd`). A swap within a column keeps every one-dimensional projection,
/// so a Latin hypercube stays one. The swaps are drawn from `seed`, so the result is
/// reproducible. Returns `CD^2` after the search: below the one before, or equal when no swap
/// helped (a swap is kept only when it lowers `CD^2` by more than a rounding error). Each try
/// costs `O(N d)`.
///
/// ```
/// use mcint::quality::Discrepancy;
/// use mcint::sampler::{LatinHypercube, RandomCd, Sampler, random_cd};
/// let mut points = LatinHypercube::new(4, 64, 7)?.random(64)?;
/// let before = Discrepancy::Centered.squared(&points)?;
/// let after = random_cd(&mut points, RandomCd::default(), 1)?;
/// assert!(after < before);
/// assert!((Discrepancy::Centered.squared(&points)? - after).abs() < 1e-12);
/// # Ok::<(), mcint::Error>(())
/// ```
pub fn random_cd(points: &mut Points, search: RandomCd, seed: u64) -> Result<f64> {
    let initial = Discrepancy::Centered.squared(points)?;
    let (n, d) = (points.len(), points.dims());
    if n < 2 || d < 2 {
        // Permuting within columns cannot change a discrepancy of one point or one factor.
        return Ok(initial);
    }
    if search.patience == 0 {
        return Err(Error::invalid("patience", 0, "at least 1 try"));
    }
    // A change this small could be rounding (terms are up to (13/12)^d): not an improvement.
    let threshold = -4.0 * f64::EPSILON * (13.0f64 / 12.0).powi(d as i32);
    let mut rng = pass_rng(seed, 0, TAG);
    let mut idle = 0;
    for _ in 0..search.max_tries {
        if idle >= search.patience {
            break;
        }
        let (k, i, j) = (below(&mut rng, d), below(&mut rng, n), below(&mut rng, n));
        if swap_change(points, k, i, j) < threshold {
            points.column_mut(k).swap(i, j);
            idle = 0;
        } else {
            idle += 1;
        }
    }
    Discrepancy::Centered.squared(points)
}

/// The change of `CD^2` when points `i` and `j` swap coordinate `k`.
fn swap_change(points: &Points, k: usize, i: usize, j: usize) -> f64 {
    if i == j || points.get(i, k) == points.get(j, k) {
        return 0.0;
    }
    let (n, d) = (points.len(), points.dims());
    let centre = |x: f64| (x - 0.5).abs();
    let single = |x: f64| {
        let a = centre(x);
        1.0 + 0.5 * a - 0.5 * a * a
    };
    let kernel = |x: f64, y: f64| 1.0 + 0.5 * centre(x) + 0.5 * centre(y) - 0.5 * (x - y).abs();
    // Products over the coordinates other than k.
    let rest = |p: usize, q: usize| {
        (0..d)
            .filter(|&c| c != k)
            .map(|c| kernel(points.get(p, c), points.get(q, c)))
            .product::<f64>()
    };
    let rest_single = |p: usize| {
        (0..d)
            .filter(|&c| c != k)
            .map(|c| single(points.get(p, c)))
            .product::<f64>()
    };
    let (xi, xj) = (points.get(i, k), points.get(j, k));
    // The single sum: points i and j exchange their factor for coordinate k.
    let single_change = (rest_single(i) - rest_single(j)) * (single(xj) - single(xi));
    // The pair sum: the pairs (i, m) and (j, m) for every other m (twice, by symmetry), and
    // the diagonal terms (i, i) and (j, j); the pair (i, j) keeps its value.
    let mut pair_change = 0.0;
    for m in 0..n {
        if m == i || m == j {
            continue;
        }
        let xm = points.get(m, k);
        pair_change += 2.0
            * (rest(i, m) * (kernel(xj, xm) - kernel(xi, xm))
                + rest(j, m) * (kernel(xi, xm) - kernel(xj, xm)));
    }
    pair_change += rest(i, i) * (kernel(xj, xj) - kernel(xi, xi))
        + rest(j, j) * (kernel(xi, xi) - kernel(xj, xj));
    let n = n as f64;
    -2.0 / n * single_change + pair_change / (n * n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampler::{LatinHypercube, Sampler};

    #[test]
    fn the_change_of_a_swap_is_the_change_of_the_discrepancy() {
        let mut points = LatinHypercube::new(3, 20, 5).unwrap().random(20).unwrap();
        for (k, i, j) in [(0, 1, 7), (2, 19, 0), (1, 4, 5), (1, 6, 6)] {
            let before = Discrepancy::Centered.squared(&points).unwrap();
            let change = swap_change(&points, k, i, j);
            points.column_mut(k).swap(i, j);
            let after = Discrepancy::Centered.squared(&points).unwrap();
            assert!((after - before - change).abs() < 1e-15, "{k} {i} {j}");
        }
    }
}
