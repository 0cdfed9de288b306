//! The triangular (tent) density on an interval, sampled by its exact inverse cdf.
//!
//! Inverse-cdf sampling (the warp behind Jarosz's A.13 and A.19): the cdf is quadratic on
//! each side of the mode, so its inverse is a square root there. The symmetric tent is pbrt's
//! tent filter (Pharr, Jakob & Humphreys, *Physically Based Rendering*, 4th ed., sec. A.4.1,
//! `SampleTent`), generalised to any mode; inversion itself is as in Devroye, *Non-Uniform
//! Random Variate Generation* (1986), ch. II.

use super::{Pdf1d, check_interval};
use crate::error::{Error, Result};

/// The triangular density on `[a, b]` with its mode at `c`: rising linearly from zero at `a`
/// to its peak `2 / (b - a)` at `c`, then falling linearly to zero at `b` (either side may be
/// empty, `c = a` or `c = b`).
///
/// The cdf is `F(x) = f_l ((x - a) / (c - a))^2` left of the mode and
/// `1 - f_r ((b - x) / (b - c))^2` right of it, where `f_l = (c - a) / (b - a)` and
/// `f_r = (b - c) / (b - a)` are the sides' probabilities; sampling inverts each side with a
/// square root measured from its own end, so both tails keep full precision.
///
/// `u = 0` maps to `a`, where the density is zero unless `c = a`.
///
/// ```
/// use mcint::pdf::{Pdf1d, Tent};
/// let p = Tent::new(0.0, 1.0, 4.0).unwrap();
/// assert_eq!(p.pdf_1d(1.0), 0.5); // the peak, 2 / (b - a)
/// assert_eq!(p.pdf_1d(2.5), 0.25);
/// assert_eq!(p.sample_1d(0.25), 1.0); // the left side holds 1/4 of the mass
/// assert!((p.invert_1d(p.sample_1d(0.9)) - 0.9).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tent {
    a: f64,
    c: f64,
    b: f64,
    /// Probability left of the mode, `(c - a) / (b - a)`.
    left: f64,
    /// Probability right of the mode, `(b - c) / (b - a)` (computed directly, not as
    /// `1 - left`, so that it keeps its relative precision when small).
    right: f64,
    /// The density at the mode, `2 / (b - a)`.
    peak: f64,
}

impl Tent {
    /// The triangular density on `[a, b]` with mode `c`.
    ///
    /// Requires finite `a < b` with `b - a` finite and a finite peak `2 / (b - a)`, and
    /// `a <= c <= b`. Errors name the parameter (`a`, `b` or `c`).
    ///
    /// ```
    /// use mcint::pdf::Tent;
    /// assert!(Tent::new(0.0, 2.0, 1.0).is_err()); // c above b
    /// assert!(Tent::new(1.0, 1.0, 1.0).is_err());
    /// assert!(Tent::new(0.0, 0.0, 1.0).is_ok()); // falling from a
    /// ```
    pub fn new(a: f64, c: f64, b: f64) -> Result<Self> {
        check_interval(a, b, false)?;
        let width = b - a;
        let peak = 2.0 / width;
        if !peak.is_finite() {
            return Err(Error::invalid(
                "b",
                b,
                format!(
                    "an interval wide enough that the peak 2 / (b - a) is finite (b - a = {width:e})"
                ),
            ));
        }
        if !(a..=b).contains(&c) {
            return Err(Error::invalid(
                "c",
                c,
                format!("a mode in [a, b] = [{a}, {b}]"),
            ));
        }
        super::check_resolved("b", b, 0.5 * width, c)?;
        Ok(Tent {
            a,
            c,
            b,
            left: (c - a) / width,
            right: (b - c) / width,
            peak,
        })
    }

    /// The symmetric tent `1 - |x - center| / radius` (normalised) on
    /// `[center - radius, center + radius]`: pbrt's tent filter.
    ///
    /// Requires a finite `center` and a finite `radius > 0` for which the interval's ends
    /// are finite, distinct and give a finite peak `1 / radius`. Errors name `center` or
    /// `radius`.
    ///
    /// ```
    /// use mcint::pdf::{Pdf1d, Tent};
    /// let p = Tent::symmetric(0.0, 2.0).unwrap();
    /// assert_eq!(p.support(), (-2.0, 2.0));
    /// assert_eq!(p.pdf_1d(0.0), 0.5);
    /// assert_eq!(p.sample_1d(0.5), 0.0);
    /// assert!(Tent::symmetric(0.0, -1.0).is_err());
    /// ```
    pub fn symmetric(center: f64, radius: f64) -> Result<Self> {
        if !center.is_finite() {
            return Err(Error::invalid("center", center, "a finite value"));
        }
        let (a, b) = (center - radius, center + radius);
        let usable = radius.is_finite()
            && radius > 0.0
            && a < center
            && center < b
            && (b - a).is_finite()
            && (2.0 / (b - a)).is_finite();
        if !usable {
            return Err(Error::invalid(
                "radius",
                radius,
                format!(
                    "a finite value > 0 with center - radius < center < center + radius \
                     finite and a finite peak 1 / radius (center = {center})"
                ),
            ));
        }
        super::check_resolved("radius", radius, 0.5 * (b - a), center)?;
        Tent::new(a, center, b)
    }

    /// The mode `c`.
    ///
    /// ```
    /// assert_eq!(mcint::pdf::Tent::new(0.0, 0.25, 1.0).unwrap().mode(), 0.25);
    /// ```
    pub fn mode(&self) -> f64 {
        self.c
    }
}

impl Pdf1d for Tent {
    fn sample_1d(&self, u: f64) -> f64 {
        // Each branch stays on its own side of the mode, so the warp is monotone across it.
        if u < self.left {
            let x = self.a + (self.c - self.a) * (u / self.left).sqrt();
            x.clamp(self.a, self.c)
        } else {
            let x = self.b - (self.b - self.c) * ((1.0 - u) / self.right).sqrt();
            x.clamp(self.c, self.b)
        }
    }

    fn pdf_1d(&self, x: f64) -> f64 {
        if !(self.a..=self.b).contains(&x) {
            0.0
        } else if x < self.c {
            self.peak * ((x - self.a) / (self.c - self.a))
        } else if x > self.c {
            self.peak * ((self.b - x) / (self.b - self.c))
        } else {
            self.peak
        }
    }

    fn invert_1d(&self, x: f64) -> f64 {
        if x.is_nan() {
            return f64::NAN;
        }
        let u = if x <= self.a {
            0.0
        } else if x >= self.b {
            1.0
        } else if x < self.c {
            let s = (x - self.a) / (self.c - self.a);
            self.left * s * s
        } else {
            let s = (self.b - x) / (self.b - self.c);
            1.0 - self.right * s * s
        };
        u.clamp(0.0, 1.0)
    }

    fn support(&self) -> (f64, f64) {
        (self.a, self.b)
    }
}
