//! Polynomials on `[0,1]^d`, whose integral and mean square are exact rationals.
//!
//! Monomials are the classical baseline of Genz (1984) and of cubature design in general:
//! any rule that claims degree-`k` exactness must reproduce them, and
//! [`Polynomial::integral_of_square`] gives the exact variance `∫p² - (∫p)²` that a Monte
//! Carlo estimator's error bars can be checked against.

use super::TestFunction;
use crate::error::{Error, Result};

/// Largest exponent accepted for one variable of one term.
const MAX_EXPONENT: u32 = 64;

/// `p(x) = Σ_k c_k Π_i x_i^{e_{k,i}}` on `[0,1]^d`.
///
/// ```
/// use mcint::testfns::{Polynomial, TestFunction};
/// // 3 x y^2 - 2 z
/// let p = Polynomial::new(3, vec![(3.0, vec![1, 2, 0]), (-2.0, vec![0, 0, 1])]).unwrap();
/// assert_eq!(p.eval(&[1.0, 2.0, 0.5]), 11.0);
/// assert!((p.exact() - (3.0 / 6.0 - 2.0 / 2.0)).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Polynomial {
    dims: usize,
    coefficients: Vec<f64>,
    /// Row-major `terms × dims` exponents, flat so that `eval` walks memory linearly.
    exponents: Vec<u32>,
}

impl Polynomial {
    /// A polynomial in `dims >= 1` variables from `(coefficient, exponents)` terms.
    ///
    /// Each exponent vector must have length `dims` and entries `<= 64`, and each
    /// coefficient must be finite. Repeated monomials are allowed (they simply add) and an
    /// empty term list is the zero polynomial.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `dims` when it is 0, or `terms` for a
    /// non-finite coefficient, an exponent vector of the wrong length or an exponent above 64.
    ///
    /// ```
    /// use mcint::testfns::{Polynomial, TestFunction};
    /// let p = Polynomial::new(2, vec![(1.0, vec![2, 0]), (1.0, vec![0, 2])]).unwrap();
    /// assert!((p.exact() - 2.0 / 3.0).abs() < 1e-15);
    /// assert!(Polynomial::new(2, vec![(1.0, vec![1])]).is_err());
    /// assert!(Polynomial::new(0, vec![]).is_err());
    /// assert!(Polynomial::new(usize::MAX, vec![(1.0, vec![1])]).is_err());
    /// ```
    pub fn new(dims: usize, terms: Vec<(f64, Vec<u32>)>) -> Result<Self> {
        if dims == 0 {
            return Err(Error::invalid("dims", dims, "at least 1"));
        }
        let mut coefficients = Vec::with_capacity(terms.len());
        // The exponent vectors already exist, so their total length fits (terms.len() * dims
        // need not, when they do not all have length dims).
        let mut exponents = Vec::with_capacity(terms.iter().map(|(_, e)| e.len()).sum());
        for (k, (c, e)) in terms.into_iter().enumerate() {
            if !c.is_finite() {
                return Err(Error::invalid(
                    "terms",
                    format!("coefficient {c} in term {k}"),
                    "finite coefficients",
                ));
            }
            if e.len() != dims {
                return Err(Error::invalid(
                    "terms",
                    format!("{} exponents in term {k}", e.len()),
                    format!("exactly dims = {dims} exponents per term"),
                ));
            }
            if let Some(big) = e.iter().find(|&&p| p > MAX_EXPONENT) {
                return Err(Error::invalid(
                    "terms",
                    format!("exponent {big} in term {k}"),
                    format!("exponents <= {MAX_EXPONENT}"),
                ));
            }
            coefficients.push(c);
            exponents.extend_from_slice(&e);
        }
        Ok(Polynomial {
            dims,
            coefficients,
            exponents,
        })
    }

    /// The one-variable polynomial `c[0] + c[1] x + c[2] x^2 + ...` (at most 65
    /// coefficients, all finite).
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `coefficients` if there are more than 65 or one
    /// is not finite.
    ///
    /// ```
    /// use mcint::testfns::{Polynomial, TestFunction};
    /// let p = Polynomial::from_coefficients(&[1.0, 0.0, 3.0]).unwrap(); // 1 + 3x²
    /// assert_eq!(p.dims(), 1);
    /// assert_eq!(p.eval(&[2.0]), 13.0);
    /// assert!((p.exact() - 2.0).abs() < 1e-15);
    /// ```
    pub fn from_coefficients(c: &[f64]) -> Result<Self> {
        if c.len() > MAX_EXPONENT as usize + 1 {
            return Err(Error::invalid(
                "coefficients",
                format!("{} values", c.len()),
                format!(
                    "at most {} values (degree <= {MAX_EXPONENT})",
                    MAX_EXPONENT + 1
                ),
            ));
        }
        if let Some((i, v)) = c.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::invalid(
                "coefficients",
                format!("{v} at index {i}"),
                "finite values",
            ));
        }
        // The index is at most 64, so the cast is lossless.
        let terms = c
            .iter()
            .enumerate()
            .map(|(i, &ci)| (ci, vec![i as u32]))
            .collect();
        Polynomial::new(1, terms)
    }

    /// The number of terms, counting repeated monomials separately.
    ///
    /// ```
    /// use mcint::testfns::Polynomial;
    /// assert_eq!(Polynomial::from_coefficients(&[1.0, 2.0]).unwrap().num_terms(), 2);
    /// ```
    pub fn num_terms(&self) -> usize {
        self.coefficients.len()
    }

    /// The exact `∫_{[0,1]^d} p(x)^2 dx`, by expanding `p²` term by term.
    ///
    /// With [`TestFunction::exact`] this gives the exact variance of `p(X)` for `X` uniform.
    /// Cost is quadratic in the number of terms.
    ///
    /// ```
    /// use mcint::testfns::{Polynomial, TestFunction};
    /// let p = Polynomial::from_coefficients(&[0.0, 1.0]).unwrap(); // x
    /// let variance = p.integral_of_square() - p.exact().powi(2);
    /// assert!((variance - 1.0 / 12.0).abs() < 1e-15);
    /// ```
    pub fn integral_of_square(&self) -> f64 {
        let terms = || {
            self.coefficients
                .iter()
                .zip(self.exponents.chunks_exact(self.dims))
        };
        let mut total = 0.0;
        for (k, (ck, ek)) in terms().enumerate() {
            // Pairs (k, l) with l > k stand for both cross terms of p², hence the factor 2.
            for (j, (cl, el)) in terms().skip(k).enumerate() {
                let start = if j == 0 { ck * cl } else { 2.0 * ck * cl };
                // ∫_0^1 x^p x^q dx = 1/(p + q + 1) on each axis.
                total += ek
                    .iter()
                    .zip(el)
                    .fold(start, |v, (p, q)| v / f64::from(p + q + 1));
            }
        }
        total
    }
}

impl TestFunction for Polynomial {
    fn dims(&self) -> usize {
        self.dims
    }

    fn eval(&self, x: &[f64]) -> f64 {
        // dims >= 1, so chunks_exact yields exactly one chunk per term.
        self.coefficients
            .iter()
            .zip(self.exponents.chunks_exact(self.dims))
            .map(|(c, e)| {
                // Exponents are <= 64, so the casts to i32 are lossless.
                c * x
                    .iter()
                    .zip(e)
                    .map(|(xi, &p)| xi.powi(p as i32))
                    .product::<f64>()
            })
            .sum()
    }

    fn exact(&self) -> f64 {
        self.coefficients
            .iter()
            .zip(self.exponents.chunks_exact(self.dims))
            .map(|(c, e)| e.iter().fold(*c, |v, &p| v / f64::from(p + 1)))
            .sum()
    }

    fn name(&self) -> String {
        "polynomial".to_string()
    }
}
