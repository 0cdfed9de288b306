//! [`Warp3`]: a warp from the unit square to points of 3-D space (directions on a sphere,
//! points of a triangle) seen through glam's vector types, and [`Oriented`], such a warp
//! turned to any normal by an orthonormal frame.

use glam::{DVec2, DVec3};

use super::Pdf;
use crate::error::{Error, Result};

/// A [`Pdf`] from the unit square to points of 3-D space, with glam's vectors in and out:
/// what integrands over directions (or a triangle) are handed by
/// [`Integrator::over_warp`](crate::Integrator::over_warp).
///
/// ```
/// use mcint::glam::{DVec2, DVec3};
/// use mcint::pdf::{CosineHemisphere, Warp3};
/// let d = Warp3::sample_point(&CosineHemisphere, DVec2::splat(0.5));
/// assert_eq!(d, DVec3::Z);
/// ```
pub trait Warp3: Pdf {
    /// The point for the canonical point `u` in `[0, 1)^2`.
    fn sample_point(&self, u: DVec2) -> DVec3;

    /// The density at `x` (0 outside the domain).
    fn pdf_point(&self, x: DVec3) -> f64;

    /// The canonical point that [`sample_point`](Self::sample_point) maps to `x`.
    fn invert_point(&self, x: DVec3) -> DVec2;

    /// This warp turned so that its `+z` axis points along `normal` (any finite non-zero
    /// vector; it is normalized): a hemisphere or cap about a surface normal, in world
    /// coordinates.
    ///
    /// ```
    /// use mcint::glam::{DVec2, DVec3};
    /// use mcint::pdf::{CosineHemisphere, Warp3};
    /// let n = DVec3::new(1.0, 1.0, 0.0);
    /// let about = CosineHemisphere.about(n)?;
    /// let d = about.sample_point(DVec2::new(0.3, 0.8));
    /// // Cosine-distributed about n: the density is cos(d, n) / pi.
    /// let cos = d.dot(n.normalize());
    /// assert!((about.pdf_point(d) - cos / std::f64::consts::PI).abs() < 1e-15);
    /// assert!((about.invert_point(d) - DVec2::new(0.3, 0.8)).length() < 1e-12);
    /// assert!(CosineHemisphere.about(DVec3::ZERO).is_err());
    /// # Ok::<(), mcint::Error>(())
    /// ```
    fn about(self, normal: DVec3) -> Result<Oriented<Self>>
    where
        Self: Sized,
    {
        Ok(Oriented {
            warp: self,
            frame: Frame::from_normal(normal)?,
        })
    }
}

/// An orthonormal frame `(tangent, bitangent, normal)` built from its normal alone.
///
/// ```
/// use mcint::glam::DVec3;
/// use mcint::pdf::Frame;
/// let frame = Frame::from_normal(DVec3::new(0.0, 0.0, -2.0))?;
/// let v = DVec3::new(0.2, -0.3, 0.9);
/// assert!((frame.to_local(frame.to_world(v)) - v).length() < 1e-15);
/// assert!((frame.to_world(DVec3::Z) - DVec3::NEG_Z).length() < 1e-15);
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    tangent: DVec3,
    bitangent: DVec3,
    normal: DVec3,
}

impl Frame {
    /// The frame whose third axis is `normal` normalized (Duff et al. 2017, "Building an
    /// orthonormal basis, revisited", as glam's `any_orthonormal_pair`); `normal` must be
    /// finite and non-zero.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// assert!(mcint::pdf::Frame::from_normal(DVec3::new(f64::NAN, 0.0, 1.0)).is_err());
    /// ```
    pub fn from_normal(normal: DVec3) -> Result<Frame> {
        let length = normal.length();
        if !(length > 0.0 && length.is_finite()) {
            return Err(Error::invalid(
                "normal",
                normal,
                "a finite, non-zero vector",
            ));
        }
        let normal = normal / length;
        let (tangent, bitangent) = normal.any_orthonormal_pair();
        Ok(Frame {
            tangent,
            bitangent,
            normal,
        })
    }

    /// The normal (the frame's third axis), of unit length.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// let f = mcint::pdf::Frame::from_normal(DVec3::new(0.0, 3.0, 0.0)).unwrap();
    /// assert_eq!(f.normal(), DVec3::Y);
    /// ```
    pub fn normal(&self) -> DVec3 {
        self.normal
    }

    /// World coordinates of the frame-local vector `v`.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// let f = mcint::pdf::Frame::from_normal(DVec3::X).unwrap();
    /// assert!((f.to_world(DVec3::Z) - DVec3::X).length() < 1e-15);
    /// ```
    pub fn to_world(&self, v: DVec3) -> DVec3 {
        self.tangent * v.x + self.bitangent * v.y + self.normal * v.z
    }

    /// Frame-local coordinates of the world vector `v`.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// let f = mcint::pdf::Frame::from_normal(DVec3::X).unwrap();
    /// assert!((f.to_local(DVec3::X) - DVec3::Z).length() < 1e-15);
    /// ```
    pub fn to_local(&self, v: DVec3) -> DVec3 {
        DVec3::new(
            v.dot(self.tangent),
            v.dot(self.bitangent),
            v.dot(self.normal),
        )
    }
}

/// A [`Warp3`] turned by a [`Frame`]: its `+z` axis along the frame's normal (see
/// [`Warp3::about`]). Densities are unchanged by the rotation.
///
/// ```
/// use mcint::glam::DVec3;
/// use mcint::pdf::{Pdf, UniformHemisphere, Warp3};
/// let up = UniformHemisphere.about(DVec3::Y)?;
/// let mut x = [0.0; 3];
/// up.sample(&[0.4, 0.7], &mut x);
/// assert!(x[1] >= 0.0); // the upper half about +y
/// assert_eq!(up.pdf(&[0.0, -1.0, 0.0]), 0.0);
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Oriented<W> {
    warp: W,
    frame: Frame,
}

impl<W> Oriented<W> {
    /// The frame.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// use mcint::pdf::{CosineHemisphere, Warp3};
    /// assert_eq!(CosineHemisphere.about(DVec3::X)?.frame().normal(), DVec3::X);
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn frame(&self) -> &Frame {
        &self.frame
    }
}

/// The [`Pdf`] of the turned warp, as `warp_to_3d!` writes it for the plain warps.
impl<W: Warp3> Pdf for Oriented<W> {
    fn canonical_dims(&self) -> usize {
        2
    }

    fn dims(&self) -> usize {
        3
    }

    fn sample(&self, u: &[f64], x: &mut [f64]) {
        super::debug_assert_len!(self, sample, u, canonical_dims);
        super::debug_assert_len!(self, sample, x, dims);
        Warp3::sample_point(self, DVec2::new(u[0], u[1])).write_to_slice(&mut x[..3]);
    }

    fn pdf(&self, x: &[f64]) -> f64 {
        super::debug_assert_len!(self, pdf, x, dims);
        Warp3::pdf_point(self, DVec3::new(x[0], x[1], x[2]))
    }

    fn invert(&self, x: &[f64], u: &mut [f64]) -> Result<()> {
        super::debug_assert_len!(self, invert, x, dims);
        super::debug_assert_len!(self, invert, u, canonical_dims);
        let x = DVec3::new(x[0], x[1], x[2]);
        if !x.is_finite() {
            return Err(Error::invalid("x", x, "a finite point"));
        }
        Warp3::invert_point(self, x).write_to_slice(&mut u[..2]);
        Ok(())
    }
}

/// Rotate out of the frame to sample, into it to evaluate and invert.
impl<W: Warp3> Warp3 for Oriented<W> {
    fn sample_point(&self, u: DVec2) -> DVec3 {
        self.frame.to_world(self.warp.sample_point(u))
    }

    fn pdf_point(&self, x: DVec3) -> f64 {
        let local = self.frame.to_local(x);
        let density = self.warp.pdf_point(local);
        // A direction sampled on the equator may come back from the round trip through the
        // frame a rounding below it: read it at the equator, as sampled.
        if density == 0.0 && (-ROTATION_SLACK..0.0).contains(&local.z) {
            return self.warp.pdf_point(DVec3::new(local.x, local.y, 0.0));
        }
        density
    }

    fn invert_point(&self, x: DVec3) -> DVec2 {
        self.warp.invert_point(self.frame.to_local(x))
    }
}

/// How far below the equator the rotations into and out of a frame may move a unit direction
/// sampled on it: a few roundings of each of its coordinates.
const ROTATION_SLACK: f64 = 8.0 * f64::EPSILON;
