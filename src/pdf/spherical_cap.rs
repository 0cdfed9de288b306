//! Uniformly distributed directions in a cone: the spherical cap within `theta_max` of an
//! axis.
//!
//! The solid angle (the measure of Jarosz's A.18) of the cap is `2 pi (1 - cos theta_max)`,
//! and it is uniform in `cos theta`, so `1 - cos theta = u0 (1 - cos theta_max)`,
//! `phi = 2 pi u1` samples it with density `1 / (2 pi (1 - cos theta_max))` (pbrt-v4
//! `SampleUniformCone`; Mitsuba 3's `square_to_uniform_cone`). Light sampling for spherical
//! lights and glossy lobes use it with cones from a few degrees down to the sun's 0.27 degrees
//! and below.
//!
//! Tiny cones are where the naive formulas fail: `cos theta` near 1 keeps almost none of the
//! angle's digits. This warp never forms `1 - cos` by subtraction: it stores the cap's height
//! `h = 1 - cos theta_max` and its complement `1 + cos theta_max`, each to full relative
//! precision ([`SphericalCap::with_angle`] computes them as `2 sin^2(theta_max / 2)` and
//! `2 sin^2((pi - theta_max) / 2)`), samples `sin theta` from them without cancellation, tests
//! membership by chord length, `|x - axis| = 2 sin(theta / 2)`, and inverts through
//! `1 - cos = sin^2 / (1 + cos)`. A frame around any axis comes from Duff et al., "Building an
//! Orthonormal Basis, Revisited" (Journal of Computer Graphics Techniques 6(1), 2017).

use super::uniform_sphere::{cap_canonical, cap_direction};
use crate::error::{Error, Result};
use core::f64::consts::{PI, TAU};
use glam::{DVec2, DVec3};

/// Directions uniformly distributed over the cap of directions within `theta_max` of an axis:
/// density `1 / (2 pi (1 - cos theta_max))` with respect to solid angle on the cap, 0 off it.
///
/// In the cap's frame `(t, b, axis)` (see [`frame`](Self::frame)), `u0` sets
/// `1 - cos theta = u0 (1 - cos theta_max)` (so `u0 = 0` is the axis and `u0 -> 1` the rim)
/// and `u1` the azimuth `phi = 2 pi u1` from `t` towards `b`; equal strata of `u` go to pieces
/// of equal solid angle. `pdf` assumes a unit vector. A direction counts as inside when its
/// chord distance from the axis is at most the rim's, `chord = 2 sin(theta_max / 2)`, plus a
/// slack for the rounding a sampled direction carries: `8 eps chord`, and `8 eps` more when
/// the axis is not a signed coordinate axis (then every coordinate carries absolute rounding).
/// For caps larger than a hemisphere the test is made the same way against the excluded cone
/// around `-axis`.
///
/// # Accuracy for tiny and nearly full caps
///
/// Around `+z` ([`new`](Self::new), [`with_angle`](Self::with_angle)), or any other signed
/// coordinate axis, the frame rotates without rounding and the angle from the axis lives in
/// the two other coordinates, which carry only relative rounding: sampling, the
/// support test and `invert` keep full relative precision for any cap whose height
/// `1 - cos theta_max` is a normal float (`theta_max` down to about `2e-154`). A cap given by
/// `cos_theta_max` can be no smaller than `1 - cos theta_max = 2^-53` (`theta_max` about
/// `1.5e-8`), the largest `f64` below 1; [`with_angle`](Self::with_angle) reaches the
/// smaller ones. Around other axes a direction's coordinates carry absolute rounding of
/// about `eps`, so the angle from the axis is known only to about `1e-16` radians: the
/// relative accuracy of the support test and of `invert` is about `eps / theta_max` there.
/// Nearly full caps are handled symmetrically: the excluded cone around `-axis` keeps the
/// same precision as a tiny cap would.
///
/// `invert` is exact to rounding except on seams of measure zero: at the axis (`u0 = 0`) every
/// `u1` gives the same direction and `invert` returns `u1 = 0`, and `u1 -> 1` meets `u1 = 0`
/// at `phi = 0`.
///
/// ```
/// use mcint::glam::{DVec2, DVec3};
/// use mcint::pdf::{Pdf, SphericalCap};
/// // The sun seen from the earth: a cone of half-angle 0.00465 rad.
/// let sun = SphericalCap::around_with_angle(DVec3::new(1.0, 1.0, 1.0), 0.00465).unwrap();
/// let d = sun.sample_point(DVec2::new(0.3, 0.8));
/// assert!((d.length() - 1.0).abs() < 1e-15);
/// assert!(d.angle_between(sun.axis()) < 0.00465);
/// let density = 1.0 / sun.solid_angle();
/// assert_eq!(sun.pdf_point(d), density);
/// assert_eq!(sun.pdf_point(-d), 0.0);
/// assert!((sun.invert_point(d) - DVec2::new(0.3, 0.8)).length() < 1e-10);
/// assert_eq!((sun.canonical_dims(), sun.dims()), (2, 3));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphericalCap {
    axis: DVec3,
    tangent: DVec3,
    bitangent: DVec3,
    /// `1 - cos theta_max`, to full relative precision.
    height: f64,
    /// `1 + cos theta_max`, to full relative precision.
    complement: f64,
    /// `sqrt(2 height)`: distance from the axis to the rim.
    chord: f64,
    /// `sqrt(2 complement)`: distance from `-axis` to the rim.
    complement_chord: f64,
    /// Rounding allowed in a chord distance beyond the rim (see the type's docs).
    slack: f64,
    density: f64,
}

impl SphericalCap {
    /// The cap around `+z` of directions with `cos theta >= cos_theta_max`, for
    /// `cos_theta_max` in `[-1, 1)` (`-1` is the whole sphere).
    ///
    /// ```
    /// use mcint::pdf::SphericalCap;
    /// let cap = SphericalCap::new(0.5).unwrap(); // theta_max = 60 degrees
    /// assert!((cap.solid_angle() - std::f64::consts::PI).abs() < 1e-15);
    /// assert!(SphericalCap::new(1.0).is_err());
    /// assert!(SphericalCap::new(f64::NAN).is_err());
    /// ```
    pub fn new(cos_theta_max: f64) -> Result<Self> {
        SphericalCap::around(DVec3::Z, cos_theta_max)
    }

    /// The cap around `axis` (any finite non-zero vector; it is normalised) of directions with
    /// `cos theta >= cos_theta_max`, for `cos_theta_max` in `[-1, 1)`.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// use mcint::pdf::SphericalCap;
    /// let cap = SphericalCap::around(DVec3::new(0.0, -2.0, 0.0), 0.9).unwrap();
    /// assert_eq!(cap.axis(), DVec3::NEG_Y);
    /// assert!(SphericalCap::around(DVec3::ZERO, 0.9).is_err());
    /// ```
    pub fn around(axis: DVec3, cos_theta_max: f64) -> Result<Self> {
        if !(-1.0..1.0).contains(&cos_theta_max) {
            return Err(Error::invalid(
                "cos_theta_max",
                cos_theta_max,
                "a cosine in [-1, 1) (-1 is the whole sphere; 1 would be an empty cap)",
            ));
        }
        // Both are exact for cos_theta_max >= 1/2 and <= -1/2 respectively (Sterbenz), and
        // rounded once otherwise.
        SphericalCap::build(axis, 1.0 - cos_theta_max, 1.0 + cos_theta_max)
    }

    /// The cap around `+z` of directions within the angle `theta_max` (radians, in
    /// `(0, pi]`) of it. This is the constructor for tiny caps: it keeps their precision
    /// where `cos theta_max` would round to 1.
    ///
    /// ```
    /// use mcint::pdf::SphericalCap;
    /// let cap = SphericalCap::with_angle(1e-10).unwrap();
    /// // 2 pi (1 - cos 1e-10) = pi 1e-20 to rounding, though cos(1e-10) == 1 in f64.
    /// assert!((cap.solid_angle() / (std::f64::consts::PI * 1e-20) - 1.0).abs() < 1e-15);
    /// assert!(SphericalCap::with_angle(0.0).is_err());
    /// assert!(SphericalCap::with_angle(4.0).is_err());
    /// ```
    pub fn with_angle(theta_max: f64) -> Result<Self> {
        SphericalCap::around_with_angle(DVec3::Z, theta_max)
    }

    /// The cap around `axis` (finite, non-zero) of directions within `theta_max` (radians, in
    /// `(0, pi]`) of it.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// use mcint::pdf::SphericalCap;
    /// let cap = SphericalCap::around_with_angle(DVec3::X, std::f64::consts::PI).unwrap();
    /// assert!((cap.solid_angle() - 4.0 * std::f64::consts::PI).abs() < 1e-14);
    /// ```
    pub fn around_with_angle(axis: DVec3, theta_max: f64) -> Result<Self> {
        if !(theta_max > 0.0 && theta_max <= PI) {
            return Err(Error::invalid(
                "theta_max",
                theta_max,
                "an angle in (0, pi] radians",
            ));
        }
        let half = (0.5 * theta_max).sin();
        // pi - theta_max is exact (Sterbenz) for theta_max >= pi/2, where it matters.
        let complement_half = (0.5 * (PI - theta_max)).sin();
        let height = 2.0 * half * half;
        if height < f64::MIN_POSITIVE {
            return Err(Error::invalid(
                "theta_max",
                theta_max,
                "an angle in (0, pi] radians at least 2.1e-154, so that 1 - cos theta_max is a \
                 normal float",
            ));
        }
        SphericalCap::build(axis, height, 2.0 * complement_half * complement_half)
    }

    /// The cap around `axis` of the given `height = 1 - cos theta_max >= MIN_POSITIVE` and
    /// `complement = 1 + cos theta_max`.
    fn build(axis: DVec3, height: f64, complement: f64) -> Result<Self> {
        let scale = axis.abs().max_element();
        if !(axis.is_finite() && scale > 0.0) {
            return Err(Error::invalid("axis", axis, "a finite non-zero vector"));
        }
        // Scaling first keeps the length from overflowing or underflowing.
        let axis = (axis / scale).normalize();
        let (tangent, bitangent) = orthonormal_frame(axis);
        let chord = (2.0 * height).sqrt();
        let complement_chord = (2.0 * complement).sqrt();
        // Around a coordinate axis the frame is made of signed unit vectors and rotates without
        // rounding, so the small coordinates keep their relative precision.
        let coordinate_axis = axis.to_array().iter().all(|c| *c == 0.0 || c.abs() == 1.0);
        let absolute = if coordinate_axis {
            0.0
        } else {
            8.0 * f64::EPSILON
        };
        let nearest_chord = if height <= 1.0 {
            chord
        } else {
            complement_chord
        };
        Ok(SphericalCap {
            axis,
            tangent,
            bitangent,
            height,
            complement,
            chord,
            complement_chord,
            slack: 8.0 * f64::EPSILON * nearest_chord + absolute,
            density: 1.0 / (TAU * height),
        })
    }

    /// The cap's axis (unit length).
    ///
    /// ```
    /// assert_eq!(mcint::pdf::SphericalCap::new(0.0).unwrap().axis(), mcint::glam::DVec3::Z);
    /// ```
    pub fn axis(&self) -> DVec3 {
        self.axis
    }

    /// The right-handed orthonormal frame `(t, b, axis)` in which `u1` measures the azimuth
    /// (from `t` towards `b`); around `+z` it is `(+x, +y, +z)`.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// use mcint::pdf::SphericalCap;
    /// let (t, b, n) = SphericalCap::around(DVec3::new(1.0, 2.0, -2.0), 0.0).unwrap().frame();
    /// assert!(t.dot(b).abs() < 1e-15 && t.dot(n).abs() < 1e-15);
    /// assert!((t.cross(b) - n).length() < 1e-15);
    /// let (x, y, _) = SphericalCap::new(0.0).unwrap().frame();
    /// assert_eq!((x, y), (DVec3::X, DVec3::Y));
    /// ```
    pub fn frame(&self) -> (DVec3, DVec3, DVec3) {
        (self.tangent, self.bitangent, self.axis)
    }

    /// `cos theta_max` (rounded: for tiny caps it is 1).
    ///
    /// ```
    /// assert_eq!(mcint::pdf::SphericalCap::new(0.25).unwrap().cos_theta_max(), 0.25);
    /// ```
    pub fn cos_theta_max(&self) -> f64 {
        1.0 - self.height
    }

    /// The cap's height `1 - cos theta_max`, to full relative precision.
    ///
    /// ```
    /// let cap = mcint::pdf::SphericalCap::with_angle(2e-9).unwrap();
    /// assert!((cap.one_minus_cos_theta_max() / 2e-18 - 1.0).abs() < 1e-15);
    /// ```
    pub fn one_minus_cos_theta_max(&self) -> f64 {
        self.height
    }

    /// The solid angle `2 pi (1 - cos theta_max)`, whose reciprocal is the density.
    ///
    /// ```
    /// let cap = mcint::pdf::SphericalCap::new(-1.0).unwrap();
    /// assert_eq!(cap.solid_angle(), 4.0 * std::f64::consts::PI);
    /// ```
    pub fn solid_angle(&self) -> f64 {
        TAU * self.height
    }

    /// The direction for the canonical point `u` in `[0, 1)^2`.
    ///
    /// ```
    /// use mcint::glam::{DVec2, DVec3};
    /// let cap = mcint::pdf::SphericalCap::new(0.0).unwrap();
    /// assert_eq!(cap.sample_point(DVec2::ZERO), DVec3::Z);
    /// ```
    pub fn sample_point(&self, u: DVec2) -> DVec3 {
        let local = cap_direction(u, self.height, self.complement);
        self.tangent * local.x + self.bitangent * local.y + self.axis * local.z
    }

    /// The density at a unit direction `d`: `1 / solid_angle` on the cap, 0 off it.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// let cap = mcint::pdf::SphericalCap::new(0.8).unwrap();
    /// let inside = DVec3::new(0.6, 0.0, 0.8);
    /// assert_eq!(cap.pdf_point(inside), 1.0 / cap.solid_angle());
    /// assert_eq!(cap.pdf_point(DVec3::new(0.8, 0.0, 0.6)), 0.0);
    /// ```
    pub fn pdf_point(&self, d: DVec3) -> f64 {
        let inside = if self.height <= 1.0 {
            chord_length(d - self.axis) <= self.chord + self.slack
        } else {
            chord_length(d + self.axis) >= self.complement_chord - self.slack
        };
        if inside { self.density } else { 0.0 }
    }

    /// The canonical point that [`sample_point`](Self::sample_point) maps to the unit
    /// direction `d` (see the type's docs for the seams; directions off the cap give `u0`
    /// clamped to 1).
    ///
    /// ```
    /// use mcint::glam::{DVec2, DVec3};
    /// let cap = mcint::pdf::SphericalCap::new(0.5).unwrap();
    /// let u = cap.invert_point(DVec3::new(0.0, 0.6, 0.8));
    /// assert!((u - DVec2::new(0.4, 0.25)).length() < 1e-15);
    /// ```
    pub fn invert_point(&self, d: DVec3) -> DVec2 {
        let local = DVec3::new(d.dot(self.tangent), d.dot(self.bitangent), d.dot(self.axis));
        cap_canonical(local, self.height, self.chord)
    }
}

/// Length of `v` without overflow or underflow of the squares.
fn chord_length(v: DVec3) -> f64 {
    v.x.hypot(v.y).hypot(v.z)
}

/// Two unit vectors `(t, b)` with `(t, b, n)` a right-handed orthonormal frame, for a unit
/// `n`, by the branch-free construction of Duff et al. (2017) that stays accurate for every
/// `n`, including near `-z`.
fn orthonormal_frame(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        DVec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

super::warp_to_3d!(SphericalCap, "a finite unit direction");
