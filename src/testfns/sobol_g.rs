//! The Sobol' g-function `Π (|4x_i - 2| + a_i)/(1 + a_i)` on `[0,1]^d`.
//!
//! I. M. Sobol', "On quasi-Monte Carlo integrations", *Mathematics and Computers in
//! Simulation* 47 (1998), and A. Saltelli and I. M. Sobol', "About the use of rank
//! transformation in sensitivity analysis of model output", *Reliability Engineering &
//! System Safety* 50 (1995): each factor has mean 1 and a kink at `x_i = 1/2`, and `a_i`
//! controls how much axis `i` matters (`a_i = 0`: most, large `a_i`: hardly at all). With
//! all `a_i = 0` it is the Roos-Arnold product; like it, it complements the smooth Genz
//! (1984) families.

use super::TestFunction;
use crate::error::{Error, Result};

/// `g(x) = Π_i (|4 x_i - 2| + a_i) / (1 + a_i)`, with integral 1 over `[0,1]^d`.
///
/// ```
/// use mcint::testfns::{SobolGFunction, TestFunction};
/// let g = SobolGFunction::new(vec![0.0, 1.0]).unwrap();
/// assert_eq!(g.eval(&[0.0, 0.5]), 2.0 * 0.5);
/// assert_eq!(g.exact(), 1.0);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct SobolGFunction {
    a: Vec<f64>,
    /// `1/(1 + a_i)`, so that `eval` multiplies instead of dividing.
    scale: Vec<f64>,
}

impl SobolGFunction {
    /// The g-function with weights `a` (one per dimension, each finite and `>= 0`).
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `a` if it is empty or a value is negative or not
    /// finite.
    ///
    /// ```
    /// use mcint::testfns::{SobolGFunction, TestFunction};
    /// assert_eq!(SobolGFunction::new(vec![0.0, 9.0, 99.0]).unwrap().dims(), 3);
    /// assert!(SobolGFunction::new(vec![-0.5]).is_err());
    /// assert!(SobolGFunction::new(vec![]).is_err());
    /// ```
    pub fn new(a: Vec<f64>) -> Result<Self> {
        if a.is_empty() {
            return Err(Error::invalid(
                "a",
                "an empty vector",
                "at least one value (d >= 1)",
            ));
        }
        if let Some((i, v)) = a
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
        {
            return Err(Error::invalid(
                "a",
                format!("{v} at index {i}"),
                "finite values >= 0",
            ));
        }
        let scale = a.iter().map(|ai| (1.0 + ai).recip()).collect();
        Ok(SobolGFunction { a, scale })
    }

    /// Saltelli's common choice `a_i = (i - 2)/2` for `i = 1..=d`, clipped below at 0 because
    /// negative weights are not allowed: `a = [0, 0, 0.5, 1, 1.5, ...]`. The first two axes
    /// are the most important and importance then decays slowly.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `d` when `d == 0` or too large to store.
    ///
    /// ```
    /// use mcint::testfns::SobolGFunction;
    /// assert_eq!(SobolGFunction::with_defaults(4).unwrap().a(), &[0.0, 0.0, 0.5, 1.0]);
    /// assert!(SobolGFunction::with_defaults(0).is_err());
    /// assert!(SobolGFunction::with_defaults(usize::MAX).is_err());
    /// ```
    pub fn with_defaults(d: usize) -> Result<Self> {
        if d == 0 {
            return Err(Error::invalid("d", d, "at least 1"));
        }
        crate::error::check_vec_len::<f64>("d", d)?;
        SobolGFunction::new((1..=d).map(|i| (0.5 * (i as f64 - 2.0)).max(0.0)).collect())
    }

    /// The weights `a_i`.
    ///
    /// ```
    /// use mcint::testfns::SobolGFunction;
    /// assert_eq!(SobolGFunction::new(vec![2.0]).unwrap().a(), &[2.0]);
    /// ```
    pub fn a(&self) -> &[f64] {
        &self.a
    }

    /// The exact `∫ g² = Π (1 + 1/(3 (1 + a_i)²))`, so the variance of `g(X)` for uniform `X`
    /// is this minus 1.
    ///
    /// ```
    /// use mcint::testfns::SobolGFunction;
    /// let g = SobolGFunction::new(vec![0.0]).unwrap();
    /// assert!((g.integral_of_square() - 4.0 / 3.0).abs() < 1e-15);
    /// ```
    pub fn integral_of_square(&self) -> f64 {
        // Per axis: mean 1 and variance ∫(|4x-2| - 1)² / (1+a)² = 1/(3 (1+a)²).
        self.scale.iter().map(|s| 1.0 + s * s / 3.0).product()
    }

    /// The exact Sobol' indices for inputs uniform on `[0,1)^d` (Saltelli & Sobol' 1995): each
    /// factor has mean 1 and variance `V_i = 1/(3 (1 + a_i)^2)`, a product of independent
    /// factors has `V = prod (1 + V_i) - 1`, and the terms that contain `i` add up to
    /// `V_i prod_{j != i} (1 + V_j)`.
    ///
    /// ```
    /// use mcint::testfns::SobolGFunction;
    /// let exact = SobolGFunction::new(vec![0.0, 0.0]).unwrap().exact_indices();
    /// // V_i = 1/3 each, V = 16/9 - 1 = 7/9: S_i = 3/7, ST_i = (1/3)(4/3)/(7/9) = 4/7.
    /// assert!((exact.first_order[0] - 3.0 / 7.0).abs() < 1e-15);
    /// assert!((exact.total[1] - 4.0 / 7.0).abs() < 1e-15);
    /// ```
    pub fn exact_indices(&self) -> crate::sensitivity::ExactIndices {
        let partial: Vec<f64> = self.scale.iter().map(|s| s * s / 3.0).collect();
        let product: f64 = partial.iter().map(|v| 1.0 + v).product();
        // `prod (1 + V_i) - 1` as `expm1(sum ln(1 + V_i))`: the subtraction cancelled for
        // large weights (tiny `V_i`), and gave first-order indices above 1/2 for two inputs.
        let variance = libm::expm1(partial.iter().map(|&v| libm::log1p(v)).sum());
        crate::sensitivity::ExactIndices {
            variance,
            first_order: partial.iter().map(|v| v / variance).collect(),
            total: partial
                .iter()
                .map(|v| v * product / (1.0 + v) / variance)
                .collect(),
        }
    }
}

impl TestFunction for SobolGFunction {
    fn dims(&self) -> usize {
        self.a.len()
    }

    fn eval(&self, x: &[f64]) -> f64 {
        x.iter()
            .zip(&self.a)
            .zip(&self.scale)
            .map(|((xi, ai), si)| ((4.0 * xi - 2.0).abs() + ai) * si)
            .product()
    }

    fn exact(&self) -> f64 {
        1.0
    }

    fn name(&self) -> String {
        "sobol-g".to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Weights 1e6, 1e6: `V_i = 1 / (3 (1 + 1e6)^2)` each and `V = 2 V_i + V_i^2`, so
    /// `S_i = 1 / (2 + V_i)`, just below 1/2; `product - 1` gave 0.500066.
    #[test]
    fn exact_indices_of_large_weights_do_not_cancel() {
        let exact = SobolGFunction::new(vec![1e6, 1e6]).unwrap().exact_indices();
        let v = 1.0 / (3.0 * (1.0 + 1e6_f64).powi(2));
        for s in &exact.first_order {
            assert!(*s <= 0.5, "{s}");
            assert!((s - 1.0 / (2.0 + v)).abs() < 1e-14, "{s}");
        }
        assert!((exact.variance / (2.0 * v + v * v) - 1.0).abs() < 1e-14);
    }
}
