//! The `f/pdf` estimator (Jarosz's A.19) for integrands of a 3-D point or direction, handed
//! to them as a glam `DVec3`.

use glam::{DVec2, DVec3};

use super::Estimator;
use crate::pdf::Warp3;

/// `<F^N> = (1/N) sum f(X_i) / pdf(X_i)` with `X_i` drawn from a [`Warp3`] (directions on a
/// sphere, hemisphere or cap, points of a triangle), `f` taking the point as a `DVec3`. The
/// same conventions as [`ImportanceEstimator`](super::ImportanceEstimator): a zero of `f`
/// contributes 0 whatever the pdf.
///
/// ```
/// use mcint::estimator::{Estimator, WarpImportanceEstimator};
/// use mcint::glam::DVec3;
/// use mcint::pdf::{CosineHemisphere, Warp3};
/// // cos(theta) about n, sampled by its own density: every contribution is pi.
/// let n = DVec3::new(0.0, 1.0, 1.0).normalize();
/// let f = move |d: DVec3| d.dot(n).max(0.0);
/// let e = WarpImportanceEstimator::new(f, CosineHemisphere.about(n)?);
/// let mut x = [0.0; 3];
/// assert!((e.contribution(&[0.3, 0.6], &mut x) - std::f64::consts::PI).abs() < 1e-12);
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct WarpImportanceEstimator<F, W> {
    f: F,
    warp: W,
}

impl<F: Fn(DVec3) -> f64 + Send + Sync, W: Warp3> WarpImportanceEstimator<F, W> {
    /// Estimates the integral of `f` over the warp's domain, sampling from `warp`.
    ///
    /// ```
    /// use mcint::estimator::{Estimator, WarpImportanceEstimator};
    /// use mcint::pdf::UniformSphere;
    /// let e = WarpImportanceEstimator::new(|d: mcint::glam::DVec3| d.z * d.z, UniformSphere);
    /// assert_eq!((e.canonical_dims(), e.domain_dims()), (2, 3));
    /// ```
    pub fn new(f: F, warp: W) -> Self {
        WarpImportanceEstimator { f, warp }
    }
}

impl<F: Fn(DVec3) -> f64 + Send + Sync, W: Warp3> Estimator for WarpImportanceEstimator<F, W> {
    fn canonical_dims(&self) -> usize {
        2
    }

    fn domain_dims(&self) -> usize {
        3
    }

    #[inline]
    fn contribution(&self, u: &[f64], x: &mut [f64]) -> f64 {
        let point = self.warp.sample_point(DVec2::new(u[0], u[1]));
        point.write_to_slice(&mut x[..3]);
        let value = (self.f)(point);
        if value == 0.0 {
            // Zero integrand contributes zero even where the pdf is zero (no 0/0).
            return 0.0;
        }
        value / self.warp.pdf_point(point)
    }
}
