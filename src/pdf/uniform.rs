//! The uniform density on an interval: the warp of Jarosz's equation A.13.

use super::{Pdf1d, check_interval};
use crate::error::Result;

/// Uniform density `1/(b-a)` on `[a, b)`, sampled by `x = a + u (b - a)` (A.13).
///
/// ```
/// use mcint::pdf::{Pdf1d, UniformInterval};
/// let p = UniformInterval::new(2.0, 6.0).unwrap();
/// assert_eq!(p.sample_1d(0.5), 4.0);
/// assert_eq!(p.pdf_1d(3.0), 0.25);
/// assert_eq!(p.pdf_1d(7.0), 0.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UniformInterval {
    a: f64,
    b: f64,
}

impl UniformInterval {
    /// The uniform density on `[a, b)`; requires finite `a < b` with a finite density
    /// `1 / (b - a)`.
    ///
    /// ```
    /// assert!(mcint::pdf::UniformInterval::new(1.0, 1.0).is_err());
    /// // A subnormal width would make the density infinite.
    /// let err = mcint::pdf::UniformInterval::new(0.0, 5e-324).unwrap_err();
    /// assert!(err.to_string().starts_with("invalid b = "), "{err}");
    /// ```
    pub fn new(a: f64, b: f64) -> Result<Self> {
        check_interval(a, b, false)?;
        Ok(UniformInterval { a, b })
    }

    /// Length of the interval, `b - a`.
    ///
    /// ```
    /// assert_eq!(mcint::pdf::UniformInterval::new(-1.0, 2.0).unwrap().length(), 3.0);
    /// ```
    pub fn length(&self) -> f64 {
        self.b - self.a
    }
}

impl Pdf1d for UniformInterval {
    fn sample_1d(&self, u: f64) -> f64 {
        // Rounding can reach b when u is just below one; keep the half-open interval.
        let x = self.a + u * (self.b - self.a);
        if x < self.b { x } else { self.b.next_down() }
    }

    fn pdf_1d(&self, x: f64) -> f64 {
        if (self.a..self.b).contains(&x) {
            1.0 / (self.b - self.a)
        } else {
            0.0
        }
    }

    fn invert_1d(&self, x: f64) -> f64 {
        ((x - self.a) / (self.b - self.a)).clamp(0.0, 1.0)
    }

    fn support(&self) -> (f64, f64) {
        (self.a, self.b)
    }
}
