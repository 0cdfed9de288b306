//! Uniformly distributed directions on the hemisphere around `+z`.
//!
//! The solid-angle measure `d omega = d(cos theta) d phi` (the measure of Jarosz's A.18) is
//! uniform in `cos theta`, so `cos theta = 1 - u0`, `phi = 2 pi u1` samples the hemisphere
//! with density `1 / (2 pi)` (pbrt-v4 section A.5.2; Mitsuba 3's
//! `square_to_uniform_hemisphere`). It is the spherical cap of height `1 - cos theta_max = 1`
//! and shares that warp's numerically careful formulas.

use super::uniform_sphere::{cap_canonical, cap_direction};
use core::f64::consts::{PI, SQRT_2};
use glam::{DVec2, DVec3};

/// Directions uniformly distributed over the hemisphere `z >= 0`: density `1 / (2 pi)` with
/// respect to solid angle there, 0 below.
///
/// `u0` sets `z = cos theta = 1 - u0` (so `u0 = 0` is the pole and `u0 -> 1` the equator) and
/// `u1` the azimuth `phi = 2 pi u1` from `+x` towards `+y`. `x` is a unit vector (to
/// rounding) with `z > 0`. `pdf` assumes a unit vector and tests only the sign of its `z`.
///
/// `invert` is exact to rounding except on seams of measure zero: at the pole (`u0 = 0`)
/// every `u1` gives `+z` and `invert` returns `u1 = 0`, and `u1 -> 1` meets `u1 = 0` at
/// `phi = 0`, so a `u1` within rounding of 1 may come back within rounding of 0.
///
/// ```
/// use mcint::glam::{DVec2, DVec3};
/// use mcint::pdf::{Pdf, UniformHemisphere};
/// let d = UniformHemisphere.sample_point(DVec2::new(0.5, 0.5));
/// assert!((d.z - 0.5).abs() < 1e-15 && d.y.abs() < 1e-15 && d.x < 0.0);
/// assert_eq!(UniformHemisphere.pdf_point(d), 0.5 / std::f64::consts::PI);
/// assert_eq!(UniformHemisphere.pdf_point(DVec3::NEG_Z), 0.0);
/// assert!((UniformHemisphere.invert_point(d) - DVec2::new(0.5, 0.5)).length() < 1e-15);
/// assert_eq!(UniformHemisphere.dims(), 3);
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct UniformHemisphere;

impl UniformHemisphere {
    /// The direction for the canonical point `u` in `[0, 1)^2`.
    ///
    /// ```
    /// use mcint::glam::{DVec2, DVec3};
    /// assert_eq!(mcint::pdf::UniformHemisphere.sample_point(DVec2::ZERO), DVec3::Z);
    /// ```
    pub fn sample_point(&self, u: DVec2) -> DVec3 {
        cap_direction(u, 1.0, 1.0)
    }

    /// The density at a unit direction `d`: `1 / (2 pi)` for `z >= 0`, else 0 (and 0 for a
    /// `d` that is not finite).
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// let h = mcint::pdf::UniformHemisphere;
    /// assert_eq!(h.pdf_point(DVec3::X), 0.5 / std::f64::consts::PI);
    /// assert_eq!(h.pdf_point(DVec3::new(0.0, 0.6, -0.8)), 0.0);
    /// ```
    pub fn pdf_point(&self, d: DVec3) -> f64 {
        if d.z >= 0.0 && d.is_finite() {
            0.5 / PI
        } else {
            0.0
        }
    }

    /// The canonical point that [`sample_point`](Self::sample_point) maps to the unit
    /// direction `d` (see the type's docs for the seams; directions below the equator give
    /// `u0` clamped to 1).
    ///
    /// ```
    /// use mcint::glam::{DVec2, DVec3};
    /// let u = mcint::pdf::UniformHemisphere.invert_point(DVec3::new(0.0, 0.6, 0.8));
    /// assert!((u - DVec2::new(0.2, 0.25)).length() < 1e-15);
    /// ```
    pub fn invert_point(&self, d: DVec3) -> DVec2 {
        cap_canonical(d, 1.0, SQRT_2)
    }
}

super::warp_to_3d!(UniformHemisphere, "a finite unit direction");
