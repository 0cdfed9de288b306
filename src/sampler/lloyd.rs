//! [`lloyd`]: Lloyd-Max relaxation of any point set towards a centroidal Voronoi
//! tessellation of the unit cube, which spreads the points evenly (scipy's
//! `LatinHypercube(optimization="lloyd")`, for any sampler's points).

use super::nearest_point::NearestPoint;
use super::{Independent, Sampler};
use crate::error::{Error, Result};
use crate::points::Points;
use crate::uniformity::check_unit_cube;

/// How [`lloyd`] relaxes: scipy's 10 iterations, each cell's centroid estimated from 64 probe
/// points per point of the set on average.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Lloyd {
    /// Relaxation steps.
    pub iterations: u32,
    /// Uniform probe points per point of the set, which estimate the cells' centroids.
    pub probes_per_point: usize,
    /// The seed of the probe points.
    pub seed: u64,
}

impl Default for Lloyd {
    /// 10 iterations, 64 probes per point, seed 0.
    ///
    /// ```
    /// assert_eq!(mcint::sampler::Lloyd::default().iterations, 10);
    /// ```
    fn default() -> Self {
        Lloyd {
            iterations: 10,
            probes_per_point: 64,
            seed: 0,
        }
    }
}

/// Moves each point of `points` (in `[0, 1]^d`) to the centroid of its Voronoi cell in the
/// unit cube, `settings.iterations` times: Lloyd's algorithm, with each cell's centroid taken
/// over the uniform probe points nearest to it (one fixed set of probes, so every step lowers,
/// or keeps, the quantization energy: the mean squared distance from a probe to its nearest
/// point). A point whose cell holds no probe stays. The points lose any stratification they
/// had (a Latin hypercube is no longer one) and gain an even spread: larger minimum
/// distances, no clumps. Returns the energy before the first step and after each, never
/// increasing. Each step finds every probe's nearest point in a k-d tree of the points.
///
/// ```
/// use mcint::quality::{GeometricCriterion, geometric_discrepancy};
/// use mcint::sampler::{Independent, Lloyd, Sampler, lloyd};
/// let mut points = Independent::new(2, 3)?.random(64)?;
/// let spread = |p: &mcint::Points| geometric_discrepancy(p, GeometricCriterion::MinDistance);
/// let before = spread(&points)?;
/// let energies = lloyd(&mut points, Lloyd::default())?;
/// assert!(energies.windows(2).all(|w| w[1] <= w[0]));
/// assert!(spread(&points)? > before);
/// # Ok::<(), mcint::Error>(())
/// ```
pub fn lloyd(points: &mut Points, settings: Lloyd) -> Result<Vec<f64>> {
    check_unit_cube(points)?;
    if settings.probes_per_point == 0 {
        return Err(Error::invalid("probes_per_point", 0, "at least 1"));
    }
    let (n, d) = (points.len(), points.dims());
    let count = n
        .checked_mul(settings.probes_per_point)
        .ok_or(Error::IndexOutOfRange {
            what: "probe points",
            limit: usize::MAX as u64,
        })?;
    let probes = Independent::new(d, settings.seed)?.random(count)?;
    let mut nearest = vec![0usize; count];
    let mut energies = vec![assign(points, &probes, &mut nearest)];
    let mut sums = vec![0.0; n * d];
    let mut counts = vec![0u64; n];
    for _ in 0..settings.iterations {
        sums.fill(0.0);
        counts.fill(0);
        for &site in nearest.iter() {
            counts[site] += 1;
        }
        for k in 0..d {
            for (&site, &x) in nearest.iter().zip(probes.column(k)) {
                sums[site * d + k] += x;
            }
        }
        for k in 0..d {
            let column = points.column_mut(k);
            for (site, x) in column.iter_mut().enumerate() {
                if counts[site] > 0 {
                    *x = sums[site * d + k] / counts[site] as f64;
                }
            }
        }
        energies.push(assign(points, &probes, &mut nearest));
    }
    Ok(energies)
}

/// Assigns each probe to its nearest point (the lowest index among ties) and returns the
/// mean squared distance.
fn assign(points: &Points, probes: &Points, nearest: &mut [usize]) -> f64 {
    let tree = NearestPoint::new(points);
    let mut probe = vec![0.0; probes.dims()];
    let mut total = 0.0;
    for (p, slot) in nearest.iter_mut().enumerate() {
        for (k, x) in probe.iter_mut().enumerate() {
            *x = probes.column(k)[p];
        }
        let (site, distance) = tree.nearest(&probe).unwrap_or((0, f64::INFINITY));
        *slot = site;
        total += distance;
    }
    total / nearest.len().max(1) as f64
}
