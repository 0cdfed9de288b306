//! Cosine-weighted directions on the hemisphere around `+z`, by Malley's method.
//!
//! Importance sampling (Jarosz's A.19 with a pdf close to the integrand, A.23-A.24) of the
//! ubiquitous `cos theta` factor of rendering integrals. Malley's method (T. Malley, "A
//! shading method for computer generated images", MSc thesis, University of Utah, 1988)
//! samples the unit disk uniformly and lifts the point straight up to the hemisphere: the
//! projection of solid angle onto the disk is `dA = cos theta d omega`, so the density becomes
//! `(1 / pi) cos theta` with respect to solid angle. The disk is sampled by Shirley and Chiu's
//! concentric map, as in pbrt-v4 (section A.5.3) and Mitsuba 3
//! (`square_to_cosine_hemisphere`), and inverted through it.

use super::uniform_disk::{concentric_disk_to_square, concentric_square_to_disk};
use core::f64::consts::FRAC_1_PI;
use glam::{DVec2, DVec3};

/// Directions on the hemisphere `z >= 0` with density `cos theta / pi = z / pi` with respect
/// to solid angle (0 below the equator).
///
/// `u` goes through the concentric map to a point `(x, y)` of the unit disk and then to
/// `(x, y, sqrt(1 - x^2 - y^2))`, with `1 - r^2` formed as `(1 - r)(1 + r)` from the exact
/// concentric radius `r` so that directions near the equator stay unit vectors. `pdf`
/// assumes a unit vector and reads `cos theta` from its `z`.
///
/// `invert` projects back to the disk and inverts the concentric map: the map is a
/// homeomorphism of the closed square onto the closed hemisphere, so it has no seam.
/// Directions below the equator invert to the `u` of their mirror image above it.
///
/// ```
/// use mcint::glam::{DVec2, DVec3};
/// use mcint::pdf::{CosineHemisphere, Pdf};
/// let d = CosineHemisphere.sample_point(DVec2::new(0.75, 0.5));
/// // The middle of the square's right half goes to (1/2, 0) on the disk.
/// assert!((d - DVec3::new(0.5, 0.0, 0.75f64.sqrt())).length() < 1e-15);
/// assert!((CosineHemisphere.pdf_point(d) - d.z / std::f64::consts::PI).abs() < 1e-16);
/// assert!((CosineHemisphere.invert_point(d) - DVec2::new(0.75, 0.5)).length() < 1e-15);
/// assert_eq!(CosineHemisphere.canonical_dims(), 2);
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CosineHemisphere;

impl CosineHemisphere {
    /// The direction for the canonical point `u` in `[0, 1)^2`.
    ///
    /// ```
    /// use mcint::glam::{DVec2, DVec3};
    /// assert_eq!(mcint::pdf::CosineHemisphere.sample_point(DVec2::splat(0.5)), DVec3::Z);
    /// ```
    pub fn sample_point(&self, u: DVec2) -> DVec3 {
        let (r, p) = concentric_square_to_disk(2.0 * u.x - 1.0, 2.0 * u.y - 1.0);
        let z = ((1.0 - r) * (1.0 + r)).sqrt();
        DVec3::new(p.x, p.y, z)
    }

    /// The density `z / pi` at a unit direction `d` with `z >= 0`, else 0 (and 0 for a `d`
    /// that is not finite).
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// let c = mcint::pdf::CosineHemisphere;
    /// assert_eq!(c.pdf_point(DVec3::Z), 1.0 / std::f64::consts::PI);
    /// assert_eq!(c.pdf_point(DVec3::X), 0.0);
    /// assert_eq!(c.pdf_point(DVec3::NEG_Z), 0.0);
    /// ```
    pub fn pdf_point(&self, d: DVec3) -> f64 {
        if d.z >= 0.0 && d.is_finite() {
            d.z * FRAC_1_PI
        } else {
            0.0
        }
    }

    /// The canonical point that [`sample_point`](Self::sample_point) maps to the unit
    /// direction `d`.
    ///
    /// ```
    /// use mcint::glam::{DVec2, DVec3};
    /// let u = mcint::pdf::CosineHemisphere.invert_point(DVec3::new(0.0, -0.6, 0.8));
    /// assert!((u - DVec2::new(0.5, 0.2)).length() < 1e-15);
    /// ```
    pub fn invert_point(&self, d: DVec3) -> DVec2 {
        let ab = concentric_disk_to_square(DVec2::new(d.x, d.y));
        (0.5 * (ab + 1.0)).clamp(DVec2::ZERO, DVec2::ONE)
    }
}

super::warp_to_3d!(CosineHemisphere, "a finite unit direction");
