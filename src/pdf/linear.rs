//! The linear density on an interval, sampled by its exact inverse cdf.

use super::{Pdf1d, check_interval};
use crate::error::{Error, Result};

/// Density proportional to the line through `(a, v0)` and `(b, v1)` on `[a, b)`, with
/// `v0, v1 >= 0` not both zero.
///
/// The inverse cdf is the root of a quadratic; it is evaluated in the form
/// `t = u (v0 + v1) / (v0 + sqrt((1-u) v0^2 + u v1^2))`, which has no cancellation for any
/// `v0, v1` (the same rearrangement pbrt-v4 uses).
///
/// ```
/// use mcint::pdf::{Linear, Pdf1d};
/// let p = Linear::new(0.0, 2.0, 1.0, 3.0).unwrap();
/// assert!((p.pdf_1d(0.0) - 0.25).abs() < 1e-15); // 2 * 1 / ((1 + 3) * 2)
/// assert!((p.invert_1d(p.sample_1d(0.7)) - 0.7).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linear {
    a: f64,
    b: f64,
    v0: f64,
    v1: f64,
}

impl Linear {
    /// Requires finite `a < b` with a finite peak `2 / (b - a)`, finite `v0, v1 >= 0` with
    /// `v0 + v1 > 0`.
    ///
    /// ```
    /// use mcint::pdf::Linear;
    /// assert!(Linear::new(0.0, 1.0, 0.0, 0.0).is_err());
    /// assert!(Linear::new(0.0, 1.0, -1.0, 2.0).is_err());
    /// // The peak 2 / (b - a) = 2.2e308 would overflow.
    /// assert!(Linear::new(1.3e-308, 2.2e-308, 1.0, 0.0).is_err());
    /// ```
    pub fn new(a: f64, b: f64, v0: f64, v1: f64) -> Result<Self> {
        check_interval(a, b, false)?;
        // The density reaches 2 / (b - a) when one end value is zero.
        if !(2.0 / (b - a)).is_finite() {
            return Err(Error::invalid(
                "b",
                b,
                format!("an interval wide enough that the peak 2 / (b - a) is finite (a = {a})"),
            ));
        }
        for (name, v) in [("v0", v0), ("v1", v1)] {
            if !v.is_finite() || v < 0.0 {
                return Err(Error::invalid(name, v, "a finite value >= 0"));
            }
        }
        if v0 + v1 <= 0.0 {
            return Err(Error::invalid(
                "v0 + v1",
                v0 + v1,
                "a positive sum (the density needs mass)",
            ));
        }
        // Only the ratio matters; normalizing keeps the squares in sample_1d from
        // underflowing or overflowing for values near 1e+-154.
        let scale = v0.max(v1);
        Ok(Linear {
            a,
            b,
            v0: v0 / scale,
            v1: v1 / scale,
        })
    }
}

impl Pdf1d for Linear {
    fn sample_1d(&self, u: f64) -> f64 {
        let (v0, v1) = (self.v0, self.v1);
        let denominator = v0 + ((1.0 - u) * v0 * v0 + u * v1 * v1).sqrt();
        let t = if denominator > 0.0 {
            u * (v0 + v1) / denominator
        } else {
            0.0
        };
        let x = self.a + t.min(1.0) * (self.b - self.a);
        x.min(self.b.next_down())
    }

    fn pdf_1d(&self, x: f64) -> f64 {
        if !(self.a..self.b).contains(&x) {
            return 0.0;
        }
        let t = (x - self.a) / (self.b - self.a);
        let numerator = 2.0 * ((1.0 - t) * self.v0 + t * self.v1);
        match (self.v0 + self.v1) * (self.b - self.a) {
            d if d.is_finite() => numerator / d,
            // (v0 + v1) (b - a) overflows when b - a is near f64::MAX: divide in two steps.
            _ => numerator / (self.v0 + self.v1) / (self.b - self.a),
        }
    }

    fn invert_1d(&self, x: f64) -> f64 {
        let t = ((x - self.a) / (self.b - self.a)).clamp(0.0, 1.0);
        (t * (2.0 * self.v0 + (self.v1 - self.v0) * t) / (self.v0 + self.v1)).clamp(0.0, 1.0)
    }

    fn support(&self) -> (f64, f64) {
        (self.a, self.b)
    }
}
