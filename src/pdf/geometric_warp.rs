//! [`GeometricWarp`]: a warp from the unit square seen through the glam vector type of its
//! points, `DVec3` for directions and triangles, `DVec2` for the disk, so that integrands of
//! those points take the vector itself (see [`Integrator::over_warp`](crate::Integrator::over_warp)).

use glam::{DVec2, DVec3, Vec2, Vec3};

use super::{Pdf, UniformDisk, Warp3};

/// The glam vectors geometric warps produce: `DVec2` and `DVec3`, and for renderers that work
/// in `f32`, `Vec2` and `Vec3` (the `f64` point rounded; see [`GeometricWarp`]).
///
/// ```
/// use mcint::glam::DVec2;
/// use mcint::pdf::WarpPoint;
/// let mut x = [0.0; 2];
/// DVec2::new(0.5, 0.25).write_to(&mut x);
/// assert_eq!(x, [0.5, 0.25]);
/// ```
pub trait WarpPoint: Copy + Send + Sync + 'static {
    /// Writes the coordinates into the first slots of `out`.
    fn write_to(self, out: &mut [f64]);
}

impl WarpPoint for DVec2 {
    fn write_to(self, out: &mut [f64]) {
        self.write_to_slice(&mut out[..2]);
    }
}

impl WarpPoint for DVec3 {
    fn write_to(self, out: &mut [f64]) {
        self.write_to_slice(&mut out[..3]);
    }
}

impl WarpPoint for Vec2 {
    fn write_to(self, out: &mut [f64]) {
        self.as_dvec2().write_to_slice(&mut out[..2]);
    }
}

impl WarpPoint for Vec3 {
    fn write_to(self, out: &mut [f64]) {
        self.as_dvec3().write_to_slice(&mut out[..3]);
    }
}

/// A [`Pdf`] from the unit square whose points are glam vectors of type `P`: every
/// [`Warp3`] (sphere, hemispheres, cap, triangle, turned or not) with `DVec3`, and
/// [`UniformDisk`] with `DVec2`; and the same with `f32` points, `Vec3` and `Vec2`: the warp
/// samples in `f64`, the integrand gets the point rounded to `f32`, and the density is the
/// one at the unrounded point (so a point that rounds across the edge of a cap or a
/// hemisphere keeps its density, never a zero).
///
/// ```
/// use mcint::glam::{DVec2, DVec3};
/// use mcint::pdf::{GeometricWarp, UniformDisk, UniformSphere};
/// let d: DVec3 = UniformSphere.sample_vector(DVec2::new(0.5, 0.5));
/// assert!((d.length() - 1.0).abs() < 1e-15);
/// let p: DVec2 = UniformDisk::unit().sample_vector(DVec2::splat(0.5));
/// assert_eq!(p, DVec2::ZERO);
/// let d32: mcint::glam::Vec3 = UniformSphere.sample_vector(DVec2::new(0.5, 0.5));
/// assert_eq!(d32, d.as_vec3());
/// ```
pub trait GeometricWarp<P: WarpPoint>: Pdf {
    /// The point for the canonical point `u` in `[0, 1)^2`.
    fn sample_vector(&self, u: DVec2) -> P;

    /// The density at `x` (0 outside the domain).
    fn density_at(&self, x: P) -> f64;

    /// The point for `u` and the density there, as the `f/pdf` estimator uses them (for `f32`
    /// points, the density at the point before rounding).
    ///
    /// ```
    /// use mcint::glam::{DVec2, DVec3, Vec3};
    /// use mcint::pdf::{CosineHemisphere, GeometricWarp};
    /// let (d, density): (Vec3, f64) = CosineHemisphere.sample_with_density(DVec2::new(0.3, 0.7));
    /// let exact: DVec3 = CosineHemisphere.sample_vector(DVec2::new(0.3, 0.7));
    /// assert_eq!((d, density), (exact.as_vec3(), CosineHemisphere.density_at(exact)));
    /// ```
    fn sample_with_density(&self, u: DVec2) -> (P, f64) {
        let point = self.sample_vector(u);
        (point, self.density_at(point))
    }
}

impl<W: Warp3> GeometricWarp<Vec3> for W {
    fn sample_vector(&self, u: DVec2) -> Vec3 {
        self.sample_point(u).as_vec3()
    }

    fn density_at(&self, x: Vec3) -> f64 {
        self.pdf_point(x.as_dvec3())
    }

    fn sample_with_density(&self, u: DVec2) -> (Vec3, f64) {
        let point = self.sample_point(u);
        (point.as_vec3(), self.pdf_point(point))
    }
}

impl GeometricWarp<Vec2> for UniformDisk {
    fn sample_vector(&self, u: DVec2) -> Vec2 {
        self.sample_point(u).as_vec2()
    }

    fn density_at(&self, x: Vec2) -> f64 {
        self.pdf_point(x.as_dvec2())
    }

    fn sample_with_density(&self, u: DVec2) -> (Vec2, f64) {
        let point = self.sample_point(u);
        (point.as_vec2(), self.pdf_point(point))
    }
}

impl<W: Warp3> GeometricWarp<DVec3> for W {
    fn sample_vector(&self, u: DVec2) -> DVec3 {
        self.sample_point(u)
    }

    fn density_at(&self, x: DVec3) -> f64 {
        self.pdf_point(x)
    }
}

impl GeometricWarp<DVec2> for UniformDisk {
    fn sample_vector(&self, u: DVec2) -> DVec2 {
        self.sample_point(u)
    }

    fn density_at(&self, x: DVec2) -> f64 {
        self.pdf_point(x)
    }
}
