//! The `f/pdf` estimator (Jarosz's A.19) for integrands of a geometric point, handed to them
//! as a glam vector (`DVec3` for directions and triangles, `DVec2` for the disk, or their `f32`
//! forms `Vec3` and `Vec2`), returning `f64` or `f32`.

use std::marker::PhantomData;

use glam::DVec2;

use super::Estimator;
use crate::pdf::{GeometricWarp, WarpPoint};

/// `<F^N> = (1/N) sum f(X_i) / pdf(X_i)` with `X_i` drawn from a [`GeometricWarp`]
/// (directions on a sphere, hemisphere or cap, points of a triangle or a disk), `f` taking the
/// point as a glam vector. The same conventions as
/// [`ImportanceEstimator`](super::ImportanceEstimator): a zero of `f` contributes 0 whatever
/// the pdf.
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
pub struct WarpImportanceEstimator<F, W, P, R = f64> {
    f: F,
    warp: W,
    point: PhantomData<fn() -> (P, R)>,
}

impl<F: Clone, W: Clone, P, R> Clone for WarpImportanceEstimator<F, W, P, R> {
    fn clone(&self) -> Self {
        WarpImportanceEstimator {
            f: self.f.clone(),
            warp: self.warp.clone(),
            point: PhantomData,
        }
    }
}

impl<F, W: std::fmt::Debug, P, R> std::fmt::Debug for WarpImportanceEstimator<F, W, P, R> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WarpImportanceEstimator")
            .field("warp", &self.warp)
            .finish_non_exhaustive()
    }
}

impl<P: WarpPoint, R: Into<f64>, F: Fn(P) -> R + Send + Sync, W: GeometricWarp<P>>
    WarpImportanceEstimator<F, W, P, R>
{
    /// Estimates the integral of `f` over the warp's domain, sampling from `warp`.
    ///
    /// ```
    /// use mcint::estimator::{Estimator, WarpImportanceEstimator};
    /// use mcint::glam::{DVec2, DVec3};
    /// use mcint::pdf::{UniformDisk, UniformSphere};
    /// let sphere = WarpImportanceEstimator::new(|d: DVec3| d.z * d.z, UniformSphere);
    /// assert_eq!((sphere.canonical_dims(), sphere.domain_dims()), (2, 3));
    /// let disk = WarpImportanceEstimator::new(|p: DVec2| p.length_squared(), UniformDisk::unit());
    /// assert_eq!(disk.domain_dims(), 2);
    /// ```
    pub fn new(f: F, warp: W) -> Self {
        WarpImportanceEstimator {
            f,
            warp,
            point: PhantomData,
        }
    }
}

impl<P: WarpPoint, R: Into<f64>, F: Fn(P) -> R + Send + Sync, W: GeometricWarp<P>> Estimator
    for WarpImportanceEstimator<F, W, P, R>
{
    fn canonical_dims(&self) -> usize {
        2
    }

    fn domain_dims(&self) -> usize {
        self.warp.dims()
    }

    #[inline]
    fn contribution(&self, u: &[f64], x: &mut [f64]) -> f64 {
        let (point, density) = self.warp.sample_with_density(DVec2::new(u[0], u[1]));
        point.write_to(x);
        let value: f64 = (self.f)(point).into();
        if value == 0.0 {
            // Zero integrand contributes zero even where the pdf is zero (no 0/0).
            return 0.0;
        }
        value / density
    }
}
