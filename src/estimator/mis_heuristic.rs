//! The weighting heuristics of multiple importance sampling (Veach & Guibas 1995; Veach 1997,
//! chapter 9): balance, power, maximum and cutoff.
//!
//! The seed's section on multiple importance sampling (after A.25) samples from several pdfs and
//! combines the samples. Each sample `X` of technique `i` is weighted by `w_i(X)`, and the
//! estimate is unbiased whenever the weights of all techniques sum to one wherever the integrand
//! is non-zero. A heuristic computes `w_i(x)` from the values `q_j = n_j p_j(x)` of every
//! technique `j` (the sample count times the density; the one-sample model uses the selection
//! probability `c_j` in place of `n_j`):
//!
//! | heuristic | `w_i(x)` |
//! |---|---|
//! | balance | `q_i / sum_j q_j` |
//! | power (exponent `beta`) | `q_i^beta / sum_j q_j^beta` |
//! | maximum | `1` if `q_i` is the largest (shared equally among ties), else `0` |
//! | cutoff (threshold `alpha`) | `0` if `q_i < alpha q_max`, else `q_i / sum_{q_j >= alpha q_max} q_j` |
//!
//! The balance heuristic's variance is within `(1/min_i n_i - 1/sum_i n_i) F^2` of the best
//! weighting's (Veach's Theorem 9.2), and in the one-sample model it is optimal. The power
//! heuristic with `beta = 2` is Veach's recommended choice: it sharpens the balance heuristic
//! where one technique is much better than the others, which is where the balance heuristic
//! loses most. `beta = 1` is the balance heuristic and `beta -> inf` the maximum heuristic;
//! the cutoff heuristic is the balance heuristic at `alpha = 0` and the maximum heuristic at
//! `alpha = 1`.

use super::MisWeighting;
use crate::error::{Error, Result};

/// A weighting heuristic of multiple importance sampling.
///
/// Every variant gives weights in `[0, 1]` that sum to one over the techniques at any point
/// where some `q_j > 0`. The fields are public, so a value built directly is checked by
/// [`check`](Self::check), which the MIS estimators call.
///
/// ```
/// use mcint::estimator::MisHeuristic;
/// let q = [1.0, 3.0]; // n_j p_j(x) of two techniques
/// assert_eq!(MisHeuristic::Balance.weight(1, &q), 0.75);
/// assert!((MisHeuristic::power(2.0).unwrap().weight(1, &q) - 0.9).abs() < 1e-15);
/// assert_eq!(MisHeuristic::Maximum.weight(0, &q), 0.0);
/// assert_eq!(MisHeuristic::cutoff(0.5).unwrap().weight(1, &q), 1.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MisHeuristic {
    /// `w_i = q_i / sum_j q_j` (Veach's equation 9.8): the sample is weighted as if drawn from
    /// the combined density `sum_j n_j p_j / sum_j n_j`.
    Balance,
    /// `w_i = q_i^beta / sum_j q_j^beta` for a finite `beta > 0` (`beta = 2` is Veach's choice).
    Power {
        /// The exponent, finite and `> 0`.
        beta: f64,
    },
    /// `w_i = 1` for the technique with the largest `q_i`, `0` for the others; when several
    /// share the maximum, each gets an equal share so that the weights still sum to one.
    Maximum,
    /// Techniques with `q_i < alpha q_max` get weight zero; the rest share by the balance
    /// heuristic. `alpha` is in `[0, 1]`.
    Cutoff {
        /// The threshold relative to the largest `q_j`, in `[0, 1]`.
        alpha: f64,
    },
}

impl MisHeuristic {
    /// The power heuristic with exponent `beta` (finite, `> 0`).
    ///
    /// ```
    /// use mcint::estimator::MisHeuristic;
    /// assert_eq!(MisHeuristic::power(2.0).unwrap(), MisHeuristic::Power { beta: 2.0 });
    /// assert!(MisHeuristic::power(0.0).is_err());
    /// assert!(MisHeuristic::power(f64::INFINITY).is_err());
    /// ```
    pub fn power(beta: f64) -> Result<Self> {
        let heuristic = MisHeuristic::Power { beta };
        heuristic.check()?;
        Ok(heuristic)
    }

    /// The cutoff heuristic with threshold `alpha` in `[0, 1]`.
    ///
    /// ```
    /// use mcint::estimator::MisHeuristic;
    /// assert_eq!(MisHeuristic::cutoff(0.1).unwrap(), MisHeuristic::Cutoff { alpha: 0.1 });
    /// assert!(MisHeuristic::cutoff(1.5).is_err());
    /// ```
    pub fn cutoff(alpha: f64) -> Result<Self> {
        let heuristic = MisHeuristic::Cutoff { alpha };
        heuristic.check()?;
        Ok(heuristic)
    }

    /// Checks the parameter of a heuristic built directly: `beta` finite and `> 0`, `alpha` in
    /// `[0, 1]`.
    ///
    /// ```
    /// use mcint::estimator::MisHeuristic;
    /// let err = MisHeuristic::Power { beta: -1.0 }.check().unwrap_err();
    /// assert_eq!(err.to_string(), "invalid beta = -1: expected a finite exponent > 0 (2 is Veach's choice)");
    /// assert!(MisHeuristic::Cutoff { alpha: f64::NAN }.check().is_err());
    /// assert!(MisHeuristic::Balance.check().is_ok());
    /// ```
    pub fn check(&self) -> Result<()> {
        match *self {
            MisHeuristic::Power { beta } if !(beta.is_finite() && beta > 0.0) => Err(
                Error::invalid("beta", beta, "a finite exponent > 0 (2 is Veach's choice)"),
            ),
            MisHeuristic::Cutoff { alpha } if !(0.0..=1.0).contains(&alpha) => {
                Err(Error::invalid("alpha", alpha, "a threshold in [0, 1]"))
            }
            _ => Ok(()),
        }
    }

    /// The weight of technique `technique` at a point where the techniques have
    /// `densities[j] = n_j p_j(x)`.
    ///
    /// The result is in `[0, 1]`, and the weights of all techniques sum to one (to rounding)
    /// when every `densities[j]` is finite and `>= 0` and at least one is positive. Otherwise
    /// the weights are undefined and the result is NaN, so that a pdf which is NaN, infinite,
    /// negative or zero for every technique cannot bias an estimate silently. The computation
    /// divides by the largest density first, so densities anywhere in the `f64` range neither
    /// overflow nor underflow. `technique` must index `densities` (it panics otherwise, like
    /// slice indexing).
    ///
    /// ```
    /// use mcint::estimator::MisHeuristic;
    /// let q = [2.0, 2.0, 1.0];
    /// assert_eq!(MisHeuristic::Maximum.weight(0, &q), 0.5); // a tie shares the weight
    /// assert_eq!(MisHeuristic::Balance.weight(2, &q), 0.2);
    /// assert!(MisHeuristic::Balance.weight(0, &[0.0, 0.0]).is_nan());
    /// assert!(MisHeuristic::Balance.weight(0, &[1.0, f64::NAN]).is_nan());
    /// assert_eq!(MisHeuristic::Balance.weight(0, &[1e300, 1e300]), 0.5);
    /// ```
    pub fn weight(&self, technique: usize, densities: &[f64]) -> f64 {
        let own = densities[technique];
        let mut max = 0.0f64;
        for &q in densities {
            if !(q.is_finite() && q >= 0.0) {
                return f64::NAN;
            }
            max = max.max(q);
        }
        if max == 0.0 {
            // No technique can produce this point: the weights are undefined.
            return f64::NAN;
        }
        let own = own / max;
        let scaled = densities.iter().map(|&q| q / max);
        match *self {
            MisHeuristic::Balance => own / scaled.sum::<f64>(),
            MisHeuristic::Power { beta } => {
                let power = |t: f64| if beta == 2.0 { t * t } else { t.powf(beta) };
                // The largest term is 1, so the denominator is at least 1.
                power(own) / scaled.map(power).sum::<f64>()
            }
            MisHeuristic::Maximum => {
                if own == 1.0 {
                    1.0 / scaled.filter(|&t| t == 1.0).count() as f64
                } else {
                    0.0
                }
            }
            MisHeuristic::Cutoff { alpha } => {
                if own < alpha {
                    0.0
                } else {
                    own / scaled.filter(|&t| t >= alpha).sum::<f64>()
                }
            }
        }
    }

    /// The weights of all techniques at once: `out[j] = weight(j, densities)`
    /// (`out.len() == densities.len()`).
    ///
    /// ```
    /// use mcint::estimator::MisHeuristic;
    /// let mut w = [0.0; 3];
    /// MisHeuristic::Cutoff { alpha: 0.3 }.weights(&[1.0, 4.0, 3.0], &mut w); // 1 < 0.3 * 4
    /// assert_eq!(w[0], 0.0);
    /// assert!((w[1] - 4.0 / 7.0).abs() < 1e-15 && (w[2] - 3.0 / 7.0).abs() < 1e-15);
    /// ```
    pub fn weights(&self, densities: &[f64], out: &mut [f64]) {
        for (j, w) in out.iter_mut().enumerate() {
            *w = self.weight(j, densities);
        }
    }
}

impl MisWeighting for MisHeuristic {
    fn weight(&self, technique: usize, _x: &[f64], densities: &[f64]) -> f64 {
        MisHeuristic::weight(self, technique, densities)
    }

    fn check(&self) -> Result<()> {
        MisHeuristic::check(self)
    }

    fn is_partition_of_unity(&self) -> bool {
        true
    }
}
