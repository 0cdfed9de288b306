//! The Ishigami function, the classic test model of variance-based sensitivity analysis.

use std::f64::consts::PI;

use crate::error::{Error, Result};
use crate::measure::Uniform;
use crate::sensitivity::ExactIndices;

/// `f(x) = sin x1 + a sin^2 x2 + b x3^4 sin x1` with independent inputs uniform on
/// `[-pi, pi]` (T. Ishigami and T. Homma, "An importance quantification technique in
/// uncertainty analysis for computer models", ISUMA 1990), with its exact Sobol' indices.
///
/// ```
/// use mcint::testfns::Ishigami;
/// let f = Ishigami::new(7.0, 0.1).unwrap();
/// assert_eq!(f.eval(&[0.0, 0.0, 1.0]), 0.0);
/// assert!((f.eval(&[std::f64::consts::FRAC_PI_2, 0.0, 1.0]) - 1.1).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ishigami {
    a: f64,
    b: f64,
}

impl Ishigami {
    /// The function with parameters `a` and `b` (finite; the usual values are 7 and 0.1).
    ///
    /// ```
    /// use mcint::testfns::Ishigami;
    /// assert!(Ishigami::new(7.0, f64::NAN).is_err());
    /// ```
    pub fn new(a: f64, b: f64) -> Result<Self> {
        for (name, value) in [("a", a), ("b", b)] {
            if !value.is_finite() {
                return Err(Error::invalid(name, value, "a finite number"));
            }
        }
        Ok(Ishigami { a, b })
    }

    /// `f` at `x` (three values).
    ///
    /// ```
    /// use mcint::testfns::Ishigami;
    /// assert_eq!(Ishigami::new(2.0, 0.0).unwrap().eval(&[0.0, std::f64::consts::FRAC_PI_2, 0.0]), 2.0);
    /// ```
    pub fn eval(&self, x: &[f64]) -> f64 {
        let s2 = x[1].sin();
        x[0].sin() * (1.0 + self.b * x[2].powi(4)) + self.a * s2 * s2
    }

    /// The inputs' law: uniform on `[-pi, pi]^3`.
    ///
    /// ```
    /// use mcint::testfns::Ishigami;
    /// assert_eq!(Ishigami::new(7.0, 0.1).unwrap().inputs().domain().lo(), &[-std::f64::consts::PI; 3]);
    /// ```
    pub fn inputs(&self) -> Uniform {
        Uniform::new(vec![-PI; 3], vec![PI; 3]).expect("a finite box")
    }

    /// The exact variance and indices (Sobol' & Levitan 1999; Saltelli et al. 2008, "Global
    /// Sensitivity Analysis: The Primer"). With `x` uniform on `[-pi, pi]`: `Var sin x = 1/2`,
    /// `E sin^4 x = 3/8`, `E x^4 = pi^4/5`, `E x^8 = pi^8/9`, so `V1 = (1 + b pi^4/5)^2 / 2`,
    /// `V2 = a^2/8`, `V3 = 0`, and the one interaction `V13 = b^2 pi^8 (1/18 - 1/50)`.
    ///
    /// ```
    /// use mcint::testfns::Ishigami;
    /// let exact = Ishigami::new(7.0, 0.1).unwrap().exact_indices();
    /// assert!((exact.first_order[0] - 0.3139).abs() < 1e-4);
    /// assert_eq!(exact.first_order[2], 0.0);
    /// ```
    pub fn exact_indices(&self) -> ExactIndices {
        let (a, b) = (self.a, self.b);
        let pi4 = PI.powi(4);
        let v1 = 0.5 * (1.0 + b * pi4 / 5.0).powi(2);
        let v2 = a * a / 8.0;
        let v13 = b * b * pi4 * pi4 * (1.0 / 18.0 - 1.0 / 50.0);
        let variance = v1 + v2 + v13;
        ExactIndices {
            variance,
            first_order: vec![v1 / variance, v2 / variance, 0.0],
            total: vec![(v1 + v13) / variance, v2 / variance, v13 / variance],
        }
    }
}
