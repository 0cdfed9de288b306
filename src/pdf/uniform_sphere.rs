//! Uniformly distributed directions: the unit sphere with its solid-angle measure.
//!
//! The seed's f/pdf estimator (A.19) works over any measure (A.18); for directions the
//! measure is solid angle, `d omega = d(cos theta) d phi`, so equal steps in `cos theta` and in
//! `phi` cut the sphere into pieces of equal area (Archimedes' hat-box theorem). The warp is
//! therefore `z = cos theta = 1 - 2 u0`, `phi = 2 pi u1` (pbrt-v4 section A.5.2, Mitsuba 3's
//! `square_to_uniform_sphere`), with density `1 / (4 pi)`.
//!
//! The helpers here serve every warp to a spherical cap around `+z` (a cap of height
//! `h = 1 - cos theta_max`: the sphere is `h = 2`, the hemisphere `h = 1`): `u0` sets
//! `1 - cos theta = u0 h`, `u1` the azimuth. They are written so that directions near either
//! pole keep full relative precision: `sin theta` comes from `(1 - cos theta)(1 + cos theta)`
//! with both factors formed without cancellation, and the inverse reads `1 - cos theta` from
//! `x` and `y` near `+z` instead of from `1 - z`.

use crate::float::ONE_BELOW;
use core::f64::consts::{PI, TAU};
use glam::{DVec2, DVec3};

/// The direction, in the cap's own frame (axis `+z`), of the canonical point `u` for a cap of
/// height `h = 1 - cos theta_max` whose complement has height `g = 1 + cos theta_max`.
pub(super) fn cap_direction(u: DVec2, h: f64, g: f64) -> DVec3 {
    let one_minus_cos = u.x * h;
    // 1 + cos theta = 2 - u0 h, formed as g + (1 - u0) h so that it keeps its precision
    // near the -z pole, where it is small.
    let one_plus_cos = g + (1.0 - u.x) * h;
    // sin^2 = (1 - cos)(1 + cos) = u0 * h (1 + cos); the square roots are taken apart so that
    // a tiny u0 times a tiny h does not underflow.
    let sin_theta = u.x.sqrt() * (h * one_plus_cos).sqrt();
    let (sin_phi, cos_phi) = (TAU * u.y).sin_cos();
    DVec3::new(
        sin_theta * cos_phi,
        sin_theta * sin_phi,
        1.0 - one_minus_cos,
    )
}

/// The inverse of [`cap_direction`] for a unit direction `d` in the cap's frame, where
/// `chord = sqrt(2 h)` is the distance from the axis to the cap's rim. `u0` is clamped to
/// `[0, 1]` and `u1` lies in `[0, 1)` (0 at the poles, where the azimuth is undefined).
pub(super) fn cap_canonical(d: DVec3, h: f64, chord: f64) -> DVec2 {
    let u0 = if d.z > 0.0 {
        // 1 - cos = sin^2 / (1 + cos), and sin^2 / h = 2 (sin / chord)^2: no cancellation and
        // no underflow, however small the angle or the cap.
        let ratio = d.x.hypot(d.y) / chord;
        2.0 * ratio * ratio / (1.0 + d.z)
    } else {
        (1.0 - d.z) / h
    };
    let phi = d.y.atan2(d.x);
    let u1 = if phi < 0.0 {
        phi / TAU + 1.0
    } else {
        phi / TAU
    };
    DVec2::new(u0.clamp(0.0, 1.0), u1.clamp(0.0, ONE_BELOW))
}

/// Directions uniformly distributed over the unit sphere: density `1 / (4 pi)` with respect
/// to solid angle.
///
/// `u0` sets the height `z = 1 - 2 u0` and `u1` the azimuth `phi = 2 pi u1` measured from `+x`
/// towards `+y`, so equal strata of `u` go to pieces of the sphere of equal area. `x` has
/// three coordinates, a unit vector (to rounding). `pdf` assumes its argument is a unit
/// vector and returns `1 / (4 pi)` for any finite one.
///
/// `invert` is exact to rounding except on two seams of measure zero: at the poles
/// (`u0 = 0`, and `u0 = 1` which `[0, 1)` never reaches) every `u1` gives the same direction
/// and `invert` returns `u1 = 0`; and `u1 = 0` and `u1 -> 1` meet at the meridian `phi = 0`,
/// so a `u1` within rounding of 1 may come back as a value within rounding of 0 (they are the
/// same direction).
///
/// ```
/// use mcint::glam::{DVec2, DVec3};
/// use mcint::pdf::{Pdf, UniformSphere};
/// let d = UniformSphere.sample_point(DVec2::new(0.5, 0.25));
/// assert!((d - DVec3::Y).length() < 1e-15); // the equator, a quarter turn from +x
/// assert_eq!(UniformSphere.pdf_point(d), 1.0 / (4.0 * std::f64::consts::PI));
/// assert!((UniformSphere.invert_point(d) - DVec2::new(0.5, 0.25)).length() < 1e-15);
/// assert_eq!((UniformSphere.canonical_dims(), UniformSphere.dims()), (2, 3));
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct UniformSphere;

impl UniformSphere {
    /// The direction for the canonical point `u` in `[0, 1)^2`.
    ///
    /// ```
    /// use mcint::glam::{DVec2, DVec3};
    /// assert_eq!(mcint::pdf::UniformSphere.sample_point(DVec2::ZERO), DVec3::Z);
    /// ```
    pub fn sample_point(&self, u: DVec2) -> DVec3 {
        cap_direction(u, 2.0, 0.0)
    }

    /// The density `1 / (4 pi)` at a unit direction `d` (0 if `d` is not finite).
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// let p = mcint::pdf::UniformSphere.pdf_point(DVec3::NEG_Z);
    /// assert_eq!(p, 0.25 / std::f64::consts::PI);
    /// ```
    pub fn pdf_point(&self, d: DVec3) -> f64 {
        if d.is_finite() { 0.25 / PI } else { 0.0 }
    }

    /// The canonical point that [`sample_point`](Self::sample_point) maps to the unit
    /// direction `d` (see the type's docs for the seams).
    ///
    /// ```
    /// use mcint::glam::{DVec2, DVec3};
    /// let u = mcint::pdf::UniformSphere.invert_point(DVec3::NEG_X);
    /// assert!((u - DVec2::new(0.5, 0.5)).length() < 1e-15);
    /// ```
    pub fn invert_point(&self, d: DVec3) -> DVec2 {
        cap_canonical(d, 2.0, 2.0)
    }
}

super::warp_to_3d!(UniformSphere, "a finite unit direction");
