//! A law of independent inputs, each given by its quantile function (inverse cdf).

use std::fmt;
use std::sync::Arc;

use super::Measure;
use crate::error::{Error, Result};

type Quantile = Arc<dyn Fn(f64) -> f64 + Send + Sync>;

/// Independent inputs `x_i = Q_i(u_i)`, each with its own quantile function `Q_i` (the
/// inverse of its cdf): any one-dimensional law a user can invert (triangular, Weibull,
/// truncated normal, an empirical table), one canonical coordinate per input, so stratified
/// and quasi-random points keep their structure. The law of the inputs of a sensitivity
/// analysis whose inputs are independent but not all uniform.
///
/// ```
/// use mcint::measure::{Independent, Measure};
/// // x1 uniform on [2, 4), x2 exponential with rate 1.
/// let law = Independent::new(vec![
///     Box::new(|u: f64| 2.0 + 2.0 * u),
///     Box::new(|u: f64| -(1.0 - u).ln()),
/// ])
/// .unwrap();
/// let mut x = [0.0; 2];
/// assert_eq!(law.map(&[0.5, 0.5], &mut x), 1.0);
/// assert_eq!(x[0], 3.0);
/// assert!((x[1] - 2f64.ln()).abs() < 1e-15);
/// ```
#[derive(Clone)]
pub struct Independent {
    quantiles: Vec<Quantile>,
}

impl Independent {
    /// The law with quantile functions `quantiles`, one per input (at least one). Each must
    /// map `[0, 1)` to finite values, non-decreasing; the constructor checks them at 1,025
    /// evenly spaced probabilities and refuses a non-finite or decreasing one.
    ///
    /// ```
    /// use mcint::measure::Independent;
    /// let err = Independent::new(vec![Box::new(|u: f64| 1.0 / u)]).err().unwrap();
    /// assert!(err.to_string().contains("finite"), "{err}");
    /// let err = Independent::new(vec![Box::new(|u: f64| -u)]).err().unwrap();
    /// assert!(err.to_string().contains("non-decreasing"), "{err}");
    /// let table = [1.0, 2.0, 3.0];
    /// let err = Independent::new(vec![Box::new(move |u: f64| table[(u * 4.0) as usize])]).err().unwrap();
    /// assert!(err.to_string().contains("panicked"), "{err}");
    /// ```
    pub fn new(quantiles: Vec<Box<dyn Fn(f64) -> f64 + Send + Sync>>) -> Result<Self> {
        if quantiles.is_empty() {
            return Err(Error::invalid(
                "quantiles",
                "[]",
                "at least one quantile function",
            ));
        }
        const PROBES: u32 = 1024;
        for (i, q) in quantiles.iter().enumerate() {
            let mut previous = f64::NEG_INFINITY;
            // u = 0 and the largest u below 1, and evenly spaced ones between.
            let largest = 1.0 - f64::EPSILON / 2.0;
            for k in 0..=PROBES {
                let u = (f64::from(k) / f64::from(PROBES)).min(largest);
                // A panicking quantile is the caller's bug, reported as an error, as a
                // panicking integrand is.
                let Ok(x) = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| q(u))) else {
                    return Err(Error::invalid(
                        "quantiles",
                        format!("quantile {i} panicked at u = {u}"),
                        "functions that return a value for every u in [0, 1)",
                    ));
                };
                if !x.is_finite() {
                    return Err(Error::invalid(
                        "quantiles",
                        format!("quantile {i} gives {x} at u = {u}"),
                        "finite values on [0, 1) (map u = 0 to the smallest value, e.g. by \
                         clamping u away from 0)",
                    ));
                }
                if x < previous {
                    return Err(Error::invalid(
                        "quantiles",
                        format!("quantile {i} falls from {previous} to {x} at u = {u}"),
                        "non-decreasing quantile functions (inverse cdfs)",
                    ));
                }
                previous = x;
            }
        }
        Ok(Independent {
            quantiles: quantiles.into_iter().map(Quantile::from).collect(),
        })
    }
}

impl fmt::Debug for Independent {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Independent {{ inputs: {} }}", self.quantiles.len())
    }
}

impl Measure for Independent {
    fn canonical_dims(&self) -> usize {
        self.quantiles.len()
    }

    fn dims(&self) -> usize {
        self.quantiles.len()
    }

    fn map(&self, u: &[f64], x: &mut [f64]) -> f64 {
        for ((x, u), q) in x.iter_mut().zip(u).zip(&self.quantiles) {
            *x = q(*u);
        }
        1.0
    }
}
