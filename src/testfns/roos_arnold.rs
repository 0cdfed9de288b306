//! The Roos-Arnold product `Π |4x_i - 2|` on `[0,1]^d`.
//!
//! P. Roos and L. Arnold, "Numerische Experimente zur mehrdimensionalen Quadratur",
//! *Sitzungsberichte der Österreichischen Akademie der Wissenschaften* (1963), used this
//! product of tent-like factors as a test integrand; it appears alongside the Genz (1984)
//! families in comparisons of cubature and quasi-Monte Carlo rules. Each factor has mean 1
//! and a kink at `x_i = 1/2`, and its variance grows like `(4/3)^d`.

use super::TestFunction;
use crate::error::{Error, Result};

/// `f(x) = Π_i |4 x_i - 2|`, with integral 1 over `[0,1]^d`.
///
/// ```
/// use mcint::testfns::{RoosArnold, TestFunction};
/// let f = RoosArnold::new(2).unwrap();
/// assert_eq!(f.eval(&[0.0, 1.0]), 4.0);
/// assert_eq!(f.eval(&[0.5, 0.9]), 0.0);
/// assert_eq!(f.exact(), 1.0);
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RoosArnold {
    dims: usize,
}

impl RoosArnold {
    /// The product in `d >= 1` dimensions.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `d` when `d == 0`.
    ///
    /// ```
    /// use mcint::testfns::{RoosArnold, TestFunction};
    /// assert_eq!(RoosArnold::new(5).unwrap().dims(), 5);
    /// assert!(RoosArnold::new(0).is_err());
    /// ```
    pub fn new(d: usize) -> Result<Self> {
        if d == 0 {
            return Err(Error::invalid("d", d, "at least 1"));
        }
        Ok(RoosArnold { dims: d })
    }

    /// The exact `∫ f² = (4/3)^d`, so the variance of `f(X)` for uniform `X` is `(4/3)^d - 1`.
    ///
    /// ```
    /// use mcint::testfns::RoosArnold;
    /// assert!((RoosArnold::new(2).unwrap().integral_of_square() - 16.0 / 9.0).abs() < 1e-15);
    /// ```
    pub fn integral_of_square(&self) -> f64 {
        // ∫_0^1 (4x - 2)^2 dx = 4/3 on each axis; repeated multiplication saturates cleanly.
        (0..self.dims).fold(1.0, |v, _| v * (4.0 / 3.0))
    }
}

impl TestFunction for RoosArnold {
    fn dims(&self) -> usize {
        self.dims
    }

    fn eval(&self, x: &[f64]) -> f64 {
        x.iter().map(|xi| (4.0 * xi - 2.0).abs()).product()
    }

    fn exact(&self) -> f64 {
        1.0
    }

    fn name(&self) -> String {
        "roos-arnold".to_string()
    }
}
