//! The (truncated) exponential density, sampled by its exact inverse cdf.

use super::{Pdf1d, check_interval};
use crate::{Error, Result};

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
    /// Probability mass of the untruncated exponential within the interval, `1 - e^{-decay L}`.
    mass: f64,
    /// True when the density peaks at `a` (positive rate).
    peak_at_a: bool,
}

impl Exponential {
    /// Requires a finite non-zero `rate`, finite `a < b`; `b = +inf` is allowed when
    /// `rate > 0`.
    ///
    /// ```
    /// use mcint::pdf::Exponential;
    /// assert!(Exponential::new(0.0, 0.0, 1.0).is_err());
    /// assert!(Exponential::new(-1.0, 0.0, f64::INFINITY).is_err());
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
        let mass = -(-decay * (b - a)).exp_m1();
        if mass.is_nan() || mass <= 0.0 {
            return Err(Error::invalid(
                "rate",
                rate,
                "a rate with |rate| (b - a) above 1e-300",
            ));
        }
        Ok(Exponential {
            a,
            b,
            decay,
            mass,
            peak_at_a: rate > 0.0,
        })
    }

    /// Distance from the peak end whose truncated cdf is `v`.
    fn distance(&self, v: f64) -> f64 {
        -(-v * self.mass).ln_1p() / self.decay
    }

    /// Truncated cdf of the distance `t` from the peak end.
    fn distance_cdf(&self, t: f64) -> f64 {
        -(-self.decay * t).exp_m1() / self.mass
    }
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
        self.decay * (-self.decay * t).exp() / self.mass
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
