//! Geometry of the unit torus `[0,1)^d` shared by the blue-noise constructions (Poisson-disk
//! and best-candidate sets): periodic distances, wrapping, and the random translation that
//! makes every point of a pass uniform without changing any distance.

use rand_pcg::Pcg64;

use super::pass_rng::uniform;
use crate::float::ONE_BELOW;

/// The most dimensions of the torus constructions: room for coordinates and cell indices in
/// fixed-size arrays.
pub(super) const MAX_TORUS_DIMS: usize = 8;

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
