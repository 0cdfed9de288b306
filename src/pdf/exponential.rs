//! The (truncated) exponential density, sampled by its exact inverse cdf.

use super::{Pdf1d, check_interval};
use crate::error::{Error, Result};

/// Density proportional to `exp(-rate (x - a))` on `[a, b)`.
///
/// A positive rate decays away from `a` (and `b` may be `+inf`, the plain exponential shifted
/// to `a`); a negative rate grows toward `b`. Sampling measures the distance from the end
/// the density decays from, so both cases keep full precision near that end.
///
/// ```
/// use mcint::pdf::{Exponential, Pdf1d};
/// let p = Exponential::new(1.0, 0.0, 1.0).unwrap();
/// let z = 1.0 - (-1f64).exp();
/// assert!((p.pdf_1d(0.0) - 1.0 / z).abs() < 1e-14);
/// assert!((p.invert_1d(p.sample_1d(0.3)) - 0.3).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Exponential {
    a: f64,
    b: f64,
    /// `|rate|`, the decay rate measured from the peak end.
    decay: f64,
    /// Probability mass of the untruncated exponential within the interval, `1 - e^{-decay L}`
    /// (it may underflow for a tiny decay; `scale` keeps the precision).
    mass: f64,
    /// The normalisation `mass / decay`, the integral of `e^{-decay t}` over the interval.
    scale: f64,
    /// True when the density peaks at `a` (positive rate).
    peak_at_a: bool,
}

impl Exponential {
    /// Requires a finite non-zero `rate`, finite `a < b`; `b = +inf` is allowed when
    /// `rate > 0` (and `1 / rate` is finite), and the normalisation must stay finite.
    ///
    /// ```
    /// use mcint::pdf::{Exponential, Pdf1d};
    /// assert!(Exponential::new(0.0, 0.0, 1.0).is_err());
    /// assert!(Exponential::new(-1.0, 0.0, f64::INFINITY).is_err());
    /// // A subnormal rate is nearly uniform on a short interval, and too flat for a half-line.
    /// let flat = Exponential::new(5e-324, 0.0, 2.0).unwrap();
    /// assert_eq!((flat.pdf_1d(1.0), flat.sample_1d(0.25)), (0.5, 0.5));
    /// assert!(Exponential::new(5e-324, 0.0, f64::INFINITY).is_err());
    /// ```
    pub fn new(rate: f64, a: f64, b: f64) -> Result<Self> {
        if !rate.is_finite() || rate == 0.0 {
            return Err(Error::invalid(
                "rate",
                rate,
                "a finite non-zero rate (use UniformInterval for rate 0)",
            ));
        }
        check_interval(a, b, rate > 0.0)?;
        let decay = rate.abs();
        let width = b - a;
        let z = decay * width;
        // The integral of e^{-decay t} over the interval, (1 - e^{-z}) / decay, written as
        // width (1 - e^{-z}) / z so that a tiny or subnormal decay keeps its precision.
        let scale = if z.is_infinite() {
            1.0 / decay
        } else {
            width * one_minus_exp_over(z)
        };
        if !(scale > 0.0 && scale.is_finite() && (1.0 / scale).is_finite()) {
            return Err(Error::invalid(
                "rate",
                rate,
                format!(
                    "a rate whose normalisation (1 - e^(-|rate| (b - a))) / |rate| and its \
                     reciprocal are finite (it is {scale:e}; for b = +inf, 1 / |rate| must be \
                     finite)"
                ),
            ));
        }
        // The density peaks at one end, at 1 / scale.
        super::check_resolved("rate", rate, scale, if rate > 0.0 { a } else { b })?;
        Ok(Exponential {
            a,
            b,
            decay,
            // Computed directly, so that it never exceeds 1 (`distance` takes ln(1 - v mass)).
            mass: if z.is_infinite() { 1.0 } else { -(-z).exp_m1() },
            scale,
            peak_at_a: rate > 0.0,
        })
    }

    /// Distance from the peak end whose truncated cdf is `v`: `-ln(1 - v mass) / decay`,
    /// written as `v scale (-ln(1 - y) / y)` with `y = v mass`, which stays accurate when
    /// `v mass` underflows (a tiny decay, where the density is nearly uniform).
    fn distance(&self, v: f64) -> f64 {
        let y = v * self.mass;
        let log_ratio = if y > 0.0 { -(-y).ln_1p() / y } else { 1.0 };
        v * self.scale * log_ratio
    }

    /// Truncated cdf of the distance `t` from the peak end, `(1 - e^{-decay t}) / mass`; for a
    /// small `decay t` written as `(t / scale) (1 - e^{-decay t}) / (decay t)`, which keeps its
    /// precision when `mass` is tiny (then `decay t` is too).
    fn distance_cdf(&self, t: f64) -> f64 {
        let z = self.decay * t;
        if z < 1.0 {
            t / self.scale * one_minus_exp_over(z)
        } else {
            -(-z).exp_m1() / self.mass
        }
    }
}

/// `(1 - e^{-z}) / z` for `z >= 0` (1 at 0 and, to rounding, wherever `z` is tiny).
fn one_minus_exp_over(z: f64) -> f64 {
    if z > 0.0 { -(-z).exp_m1() / z } else { 1.0 }
}

impl Pdf1d for Exponential {
    fn sample_1d(&self, u: f64) -> f64 {
        let x = if self.peak_at_a {
            self.a + self.distance(u)
        } else {
            self.b - self.distance(1.0 - u)
        };
        x.clamp(self.a, self.b.next_down())
    }

    fn pdf_1d(&self, x: f64) -> f64 {
        if !(self.a..self.b).contains(&x) {
            return 0.0;
        }
        let t = if self.peak_at_a {
            x - self.a
        } else {
            self.b - x
        };
        (-self.decay * t).exp() / self.scale
    }

    fn invert_1d(&self, x: f64) -> f64 {
        let x = x.clamp(self.a, self.b);
        let u = if self.peak_at_a {
            self.distance_cdf(x - self.a)
        } else {
            1.0 - self.distance_cdf(self.b - x)
        };
        u.clamp(0.0, 1.0)
    }

    fn support(&self) -> (f64, f64) {
        (self.a, self.b)
    }
}
