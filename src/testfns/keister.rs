//! The Keister integrand `cos(|x|) exp(-|x|^2)` over `R^d`.
//!
//! B. D. Keister, "Multidimensional quadrature algorithms", *Computers in Physics* 10 (1996),
//! the standard test of QMCPy. Its integral is radial: with `S_{d-1} = 2 pi^{d/2} / Gamma(d/2)`
//! the area of the unit sphere,
//!
//! `int cos(|x|) e^{-|x|^2} dx = S_{d-1} C_{d-1}`, `C_n = int_0^inf r^n cos(r) e^{-r^2} dr`,
//!
//! and, with `S_n = int_0^inf r^n sin(r) e^{-r^2} dr`, integrating by parts against
//! `d(e^{-r^2}) = -2 r e^{-r^2} dr` gives `C_{n+1} = (n C_{n-1} - S_n) / 2`,
//! `S_{n+1} = (n S_{n-1} + C_n) / 2` for `n >= 1`, `C_1 = (1 - S_0) / 2`, `S_1 = C_0 / 2`, from
//! `C_0 = sqrt(pi) e^{-1/4} / 2` and `S_0 = F(1/2)`, Dawson's integral.

use super::TestFunction;
use crate::error::{Error, Result};
use crate::special::normal_quantile;

/// The most dimensions (the recurrence for the exact value was checked against quadrature up
/// to here).
///
/// ```
/// use mcint::testfns::{KEISTER_MAX_DIMS, Keister};
/// assert!(Keister::new(KEISTER_MAX_DIMS).is_ok() && Keister::new(KEISTER_MAX_DIMS + 1).is_err());
/// ```
pub const KEISTER_MAX_DIMS: usize = 64;

/// The Keister integrand `cos(|x|) exp(-|x|^2)` over `R^d` (`integrand`), and, as a
/// [`TestFunction`] over the unit cube, the same integral after the normal transform
/// `x = Phi^-1(u) / sqrt(2)`: `eval(u) = pi^{d/2} cos(|x|)` (QMCPy's form).
///
/// ```
/// use mcint::testfns::{Keister, TestFunction};
/// let k = Keister::new(1).unwrap();
/// // In one dimension the integral is sqrt(pi) e^{-1/4}.
/// assert!((k.exact() - std::f64::consts::PI.sqrt() * (-0.25f64).exp()).abs() < 1e-15);
/// assert_eq!(k.integrand(&[0.0]), 1.0);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Keister {
    dims: usize,
    exact: f64,
}

impl Keister {
    /// The integrand in `dims` dimensions (1 to [`KEISTER_MAX_DIMS`]).
    ///
    /// ```
    /// use mcint::testfns::{Keister, TestFunction};
    /// // QMCPy's reference value in 3-D: pi^{3/2} e^{-1/4} / 2 = 2.16830...
    /// assert!((Keister::new(3).unwrap().exact() - 2.168_309_1).abs() < 1e-7);
    /// assert!(Keister::new(0).is_err());
    /// ```
    pub fn new(dims: usize) -> Result<Self> {
        if !(1..=KEISTER_MAX_DIMS).contains(&dims) {
            return Err(Error::invalid(
                "dims",
                dims,
                format!("1 to {KEISTER_MAX_DIMS} dimensions"),
            ));
        }
        Ok(Keister {
            dims,
            exact: exact_integral(dims),
        })
    }

    /// `cos(|x|) exp(-|x|^2)` at `x` in `R^d`.
    ///
    /// ```
    /// let k = mcint::testfns::Keister::new(2).unwrap();
    /// assert_eq!(k.integrand(&[3.0, 4.0]), 5.0f64.cos() * (-25.0f64).exp());
    /// ```
    pub fn integrand(&self, x: &[f64]) -> f64 {
        let r2: f64 = x.iter().map(|v| v * v).sum();
        r2.sqrt().cos() * (-r2).exp()
    }
}

impl TestFunction for Keister {
    fn dims(&self) -> usize {
        self.dims
    }

    fn eval(&self, u: &[f64]) -> f64 {
        // x = Phi^-1(u) / sqrt(2), whose density is pi^{-d/2} e^{-|x|^2}; u = 0 (only from
        // unrandomized points) is read as 2^-54.
        let r2: f64 = u
            .iter()
            .map(|&u| {
                let z = normal_quantile(u.max(1.0 / (1u64 << 54) as f64));
                0.5 * z * z
            })
            .sum();
        std::f64::consts::PI.powf(0.5 * self.dims as f64) * r2.sqrt().cos()
    }

    fn exact(&self) -> f64 {
        self.exact
    }

    fn name(&self) -> String {
        "keister".into()
    }
}

/// `S_{d-1} C_{d-1}` by the recurrence of the module documentation.
fn exact_integral(dims: usize) -> f64 {
    let pi = std::f64::consts::PI;
    let (mut c_prev, mut s_prev) = (0.5 * pi.sqrt() * (-0.25f64).exp(), dawson(0.5));
    // (C_n, S_n) for n = 1.
    let (mut c, mut s) = (0.5 * (1.0 - s_prev), 0.5 * c_prev);
    for n in 1..dims.saturating_sub(1) {
        let nf = n as f64;
        let next = (0.5 * (nf * c_prev - s), 0.5 * (nf * s_prev + c));
        (c_prev, s_prev) = (c, s);
        (c, s) = next;
    }
    let radial = if dims == 1 { c_prev } else { c };
    let sphere = 2.0 * pi.powf(0.5 * dims as f64) / libm::tgamma(0.5 * dims as f64);
    sphere * radial
}

/// Dawson's integral `F(x) = e^{-x^2} int_0^x e^{t^2} dt` for small `x`, by its series
/// `sum_k (-1)^k 2^k x^{2k+1} / (2k+1)!!`.
fn dawson(x: f64) -> f64 {
    let (mut term, mut sum) = (x, x);
    for k in 1..60 {
        term *= -2.0 * x * x / (2 * k + 1) as f64;
        sum += term;
    }
    sum
}
