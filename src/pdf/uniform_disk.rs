//! The uniform density on a disk, sampled by Shirley and Chiu's concentric map.
//!
//! The seed's f/pdf estimator (A.19) integrates over any measure (A.18); here the measure is
//! area in the plane, so the density is `1 / (pi r^2)`. Any map from the square with a
//! constant Jacobian samples it; the concentric map of Shirley & Chiu ("A Low Distortion Map
//! Between Disk and Square", Journal of Graphics Tools 2(3), 1997) is the one that also keeps
//! the shape of strata: it sends each square `max(|a|, |b|) = r` (in `[-1, 1]^2` coordinates)
//! to the circle of radius `r`, and each side of it linearly in angle to a quarter of that
//! circle, so its Jacobian is `pi/4` everywhere and cells stay compact (the polar map
//! `r = sqrt(u0)` squashes them). pbrt-v4 (section A.5.1) and Mitsuba 3
//! (`square_to_uniform_disk_concentric`) use the same map.
//!
//! The map is a homeomorphism of the closed square onto the closed disk (it is continuous
//! across the diagonals where its formula changes), so the inverse is single-valued
//! everywhere: there is no seam.

use super::{Pdf, debug_assert_len};
use crate::error::{Error, Result};
use core::f64::consts::{FRAC_PI_4, PI};
use glam::DVec2;

/// Maps `(a, b)` in `[-1, 1]^2` to the unit disk by the concentric map; also returns the
/// radius of the result, `max(|a|, |b|)`, exactly (callers that lift the disk to a hemisphere
/// need `1 - r^2` without the rounding of `x^2 + y^2`).
pub(super) fn concentric_square_to_disk(a: f64, b: f64) -> (f64, DVec2) {
    if a.abs() > b.abs() {
        // The wedges |y| <= |x|: radius |a|, angle pi/4 * b/a from the x axis.
        let (sin, cos) = (FRAC_PI_4 * (b / a)).sin_cos();
        (a.abs(), DVec2::new(a * cos, a * sin))
    } else if b != 0.0 {
        // The wedges |x| < |y|: radius |b|, angle pi/4 * a/b from the y axis.
        let (sin, cos) = (FRAC_PI_4 * (a / b)).sin_cos();
        (b.abs(), DVec2::new(b * sin, b * cos))
    } else {
        (0.0, DVec2::ZERO)
    }
}

/// The inverse of [`concentric_square_to_disk`]: the `(a, b)` in `[-1, 1]^2` of a point of
/// the unit disk (points outside give `max(|a|, |b|) = |p| > 1`).
pub(super) fn concentric_disk_to_square(p: DVec2) -> DVec2 {
    let radius = p.x.hypot(p.y);
    if p.x.abs() >= p.y.abs() {
        if p.x == 0.0 {
            return DVec2::ZERO;
        }
        let a = radius.copysign(p.x);
        DVec2::new(a, a * (p.y / p.x).atan() / FRAC_PI_4)
    } else {
        let b = radius.copysign(p.y);
        DVec2::new(b * (p.x / p.y).atan() / FRAC_PI_4, b)
    }
}

/// Uniform density on the closed disk of radius `r` around `center`, with respect to area.
///
/// `u = (u0, u1)` goes to `(a, b) = (2 u0 - 1, 2 u1 - 1)` and then through the concentric map
/// (see the module docs); `invert` is its exact inverse, to rounding. The density is
/// `1 / (pi r^2)` on the disk and 0 outside. A point counts as on the disk when its distance
/// from the centre is at most `r + 8 eps (max(|center.x|, |center.y|) + r)`: that slack is the
/// rounding a sampled point carries, so every sample has positive density.
///
/// ```
/// use mcint::glam::DVec2;
/// use mcint::pdf::{Pdf, UniformDisk};
/// let disk = UniformDisk::new(DVec2::new(1.0, 2.0), 0.5).unwrap();
/// let x = disk.sample_point(DVec2::new(0.9, 0.3));
/// assert!((x - DVec2::new(1.0, 2.0)).length() <= 0.5);
/// assert!((disk.pdf_point(x) - 1.0 / (std::f64::consts::PI * 0.25)).abs() < 1e-15);
/// assert!((disk.invert_point(x) - DVec2::new(0.9, 0.3)).abs().max_element() < 1e-14);
/// // Through the `Pdf` trait: x has two coordinates.
/// let mut y = [0.0; 2];
/// disk.sample(&[0.9, 0.3], &mut y);
/// assert_eq!(y, [x.x, x.y]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UniformDisk {
    center: DVec2,
    radius: f64,
    density: f64,
    /// Distance beyond the rim that still counts as on the disk (rounding of samples).
    slack: f64,
}

impl UniformDisk {
    /// The disk of `radius` around `center`: a finite centre, a finite `radius > 0` whose
    /// area `pi r^2` is a normal float (so the density is finite), and coordinates of the
    /// disk that stay finite.
    ///
    /// ```
    /// use mcint::glam::DVec2;
    /// use mcint::pdf::UniformDisk;
    /// assert!(UniformDisk::new(DVec2::ZERO, 0.0).is_err());
    /// assert!(UniformDisk::new(DVec2::new(f64::NAN, 0.0), 1.0).is_err());
    /// assert_eq!(UniformDisk::new(DVec2::ONE, 2.0).unwrap().radius(), 2.0);
    /// ```
    pub fn new(center: DVec2, radius: f64) -> Result<Self> {
        if !center.is_finite() {
            return Err(Error::invalid("center", center, "a finite point"));
        }
        let area = PI * radius * radius;
        if !(radius > 0.0 && area.is_finite() && area >= f64::MIN_POSITIVE) {
            return Err(Error::invalid(
                "radius",
                radius,
                "a finite radius > 0 whose area pi r^2 is a finite normal float",
            ));
        }
        let extent = center.abs().max_element() + radius;
        if !extent.is_finite() {
            return Err(Error::invalid(
                "radius",
                radius,
                format!("a radius that keeps the disk around {center} finite"),
            ));
        }
        Ok(UniformDisk {
            center,
            radius,
            density: 1.0 / area,
            slack: 8.0 * f64::EPSILON * extent,
        })
    }

    /// The unit disk around the origin.
    ///
    /// ```
    /// let disk = mcint::pdf::UniformDisk::unit();
    /// assert_eq!(disk.area(), std::f64::consts::PI);
    /// ```
    pub fn unit() -> Self {
        UniformDisk {
            center: DVec2::ZERO,
            radius: 1.0,
            density: 1.0 / PI,
            slack: 8.0 * f64::EPSILON,
        }
    }

    /// The centre.
    ///
    /// ```
    /// use mcint::glam::DVec2;
    /// let disk = mcint::pdf::UniformDisk::new(DVec2::new(3.0, 4.0), 1.0).unwrap();
    /// assert_eq!(disk.center(), DVec2::new(3.0, 4.0));
    /// ```
    pub fn center(&self) -> DVec2 {
        self.center
    }

    /// The radius.
    ///
    /// ```
    /// assert_eq!(mcint::pdf::UniformDisk::unit().radius(), 1.0);
    /// ```
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The area `pi r^2`, whose reciprocal is the density.
    ///
    /// ```
    /// use mcint::glam::DVec2;
    /// let disk = mcint::pdf::UniformDisk::new(DVec2::ZERO, 2.0).unwrap();
    /// assert_eq!(disk.area(), 4.0 * std::f64::consts::PI);
    /// ```
    pub fn area(&self) -> f64 {
        PI * self.radius * self.radius
    }

    /// The point of the disk for the canonical point `u` in `[0, 1)^2`.
    ///
    /// ```
    /// use mcint::glam::DVec2;
    /// let disk = mcint::pdf::UniformDisk::unit();
    /// // The centre of the square goes to the centre, the middle of its right side to (1, 0).
    /// assert_eq!(disk.sample_point(DVec2::new(0.5, 0.5)), DVec2::ZERO);
    /// assert_eq!(disk.sample_point(DVec2::new(1.0, 0.5)), DVec2::new(1.0, 0.0));
    /// ```
    pub fn sample_point(&self, u: DVec2) -> DVec2 {
        let (_, p) = concentric_square_to_disk(2.0 * u.x - 1.0, 2.0 * u.y - 1.0);
        self.center + self.radius * p
    }

    /// The density at `x`: `1 / area` on the disk, 0 off it.
    ///
    /// ```
    /// use mcint::glam::DVec2;
    /// let disk = mcint::pdf::UniformDisk::unit();
    /// assert_eq!(disk.pdf_point(DVec2::new(0.6, 0.8)), 1.0 / std::f64::consts::PI);
    /// assert_eq!(disk.pdf_point(DVec2::new(0.8, 0.8)), 0.0);
    /// ```
    pub fn pdf_point(&self, x: DVec2) -> f64 {
        let d = x - self.center;
        if d.x.hypot(d.y) <= self.radius + self.slack {
            self.density
        } else {
            0.0
        }
    }

    /// The canonical point that [`sample_point`](Self::sample_point) maps to `x` (for `x`
    /// off the disk, the result is clamped to `[0, 1]^2`).
    ///
    /// ```
    /// use mcint::glam::DVec2;
    /// let disk = mcint::pdf::UniformDisk::unit();
    /// assert_eq!(disk.invert_point(DVec2::new(0.0, 0.5)), DVec2::new(0.5, 0.75));
    /// ```
    pub fn invert_point(&self, x: DVec2) -> DVec2 {
        let ab = concentric_disk_to_square((x - self.center) / self.radius);
        (0.5 * (ab + 1.0)).clamp(DVec2::ZERO, DVec2::ONE)
    }
}

impl Pdf for UniformDisk {
    fn canonical_dims(&self) -> usize {
        2
    }

    fn dims(&self) -> usize {
        2
    }

    fn sample(&self, u: &[f64], x: &mut [f64]) {
        debug_assert_len!(self, sample, u, canonical_dims);
        debug_assert_len!(self, sample, x, dims);
        self.sample_point(DVec2::new(u[0], u[1]))
            .write_to_slice(&mut x[..2]);
    }

    fn pdf(&self, x: &[f64]) -> f64 {
        debug_assert_len!(self, pdf, x, dims);
        self.pdf_point(DVec2::new(x[0], x[1]))
    }

    fn invert(&self, x: &[f64], u: &mut [f64]) -> Result<()> {
        debug_assert_len!(self, invert, x, dims);
        debug_assert_len!(self, invert, u, canonical_dims);
        let x = DVec2::new(x[0], x[1]);
        if !x.is_finite() {
            return Err(Error::invalid("x", x, "a finite point"));
        }
        self.invert_point(x).write_to_slice(&mut u[..2]);
        Ok(())
    }
}
