//! The normal (Gaussian) density on the whole line, sampled by its inverse cdf.
//!
//! Inverse-cdf sampling (the warp behind Jarosz's A.13 and A.19) with Wichura's AS 241
//! quantile ([`normal_quantile`]; Wichura, *Applied Statistics* 37, 1988), rather than
//! Box-Muller or the ziggurat: the warp is monotone and uses one coordinate per sample, so
//! stratified and quasi-random `u` stay stratified (the reason Owen, *Monte Carlo theory,
//! methods and examples*, 2013, ch. 4, gives for preferring inversion with QMC).

use super::Pdf1d;
use crate::error::{Error, Result};
use crate::special::{normal_cdf, normal_quantile};

/// The normal density with `mean` and standard deviation `sd`,
/// `exp(-((x - mean)/sd)^2 / 2) / (sd sqrt(2 pi))`, sampled by `mean + sd Phi^-1(u)`.
///
/// `u = 0` (which unscrambled quasi-random sequences produce) would map to `-inf`; instead it
/// is treated as the smallest positive normal `f64`, `2.2e-308`, giving the finite point
/// `mean - 37.5 sd`. This is exactly what [`TruncatedNormal`](super::TruncatedNormal) does
/// with infinite bounds, and the two agree bit for bit for every `u`. The largest canonical
/// `u`, `1 - 2^-53`, gives `mean + 8.21 sd`: the upper tail is cut where `u` runs out of
/// resolution, at a probability of `1.1e-16`.
///
/// ```
/// use mcint::pdf::{Normal, Pdf1d};
/// let p = Normal::new(1.0, 2.0).unwrap();
/// assert_eq!(p.sample_1d(0.5), 1.0);
/// assert!((p.sample_1d(0.975) - (1.0 + 2.0 * 1.959963984540054)).abs() < 1e-14);
/// assert!((p.pdf_1d(1.0) - 1.0 / (2.0 * (2.0 * std::f64::consts::PI).sqrt())).abs() < 1e-16);
/// assert!(p.sample_1d(0.0).is_finite());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Normal {
    mean: f64,
    sd: f64,
}

/// Standard deviations from the mean that bound every sample (`Phi^-1(2.2e-308) = -37.52`,
/// `Phi^-1(1 - 2^-53) = 8.21`).
const SAMPLE_REACH: f64 = 40.0;

impl Normal {
    /// Requires a finite `mean` and a finite `sd > 0` with a finite peak density
    /// `1 / (sd sqrt(2 pi))` and `|mean| + 40 sd` finite (so every sample is finite). Errors
    /// name `mean` or `sd`.
    ///
    /// ```
    /// use mcint::pdf::Normal;
    /// assert!(Normal::new(0.0, 0.0).is_err());
    /// assert!(Normal::new(f64::NAN, 1.0).is_err());
    /// assert!(Normal::new(0.0, 1e307).is_err()); // samples could overflow
    /// assert!(Normal::new(-3.0, 1e-300).is_ok());
    /// ```
    pub fn new(mean: f64, sd: f64) -> Result<Self> {
        if !mean.is_finite() {
            return Err(Error::invalid("mean", mean, "a finite value"));
        }
        let usable = sd.is_finite()
            && sd > 0.0
            && (1.0 / (sd * (2.0 * std::f64::consts::PI).sqrt())).is_finite()
            && (mean.abs() + SAMPLE_REACH * sd).is_finite();
        if !usable {
            return Err(Error::invalid(
                "sd",
                sd,
                format!(
                    "a finite value > 0 with a finite peak density 1 / (sd sqrt(2 pi)) and \
                     |mean| + {SAMPLE_REACH} sd finite (mean = {mean})"
                ),
            ));
        }
        Ok(Normal { mean, sd })
    }

    /// The standard normal, mean 0 and sd 1.
    ///
    /// ```
    /// use mcint::pdf::{Normal, Pdf1d};
    /// assert_eq!(Normal::standard().invert_1d(0.0), 0.5);
    /// ```
    pub fn standard() -> Self {
        Normal { mean: 0.0, sd: 1.0 }
    }

    /// The mean.
    ///
    /// ```
    /// assert_eq!(mcint::pdf::Normal::new(2.0, 3.0).unwrap().mean(), 2.0);
    /// ```
    pub fn mean(&self) -> f64 {
        self.mean
    }

    /// The standard deviation.
    ///
    /// ```
    /// assert_eq!(mcint::pdf::Normal::new(2.0, 3.0).unwrap().sd(), 3.0);
    /// ```
    pub fn sd(&self) -> f64 {
        self.sd
    }
}

impl Pdf1d for Normal {
    fn sample_1d(&self, u: f64) -> f64 {
        // Same expression as TruncatedNormal on (-inf, inf), so the two agree to the bit.
        self.mean + self.sd * normal_quantile(u.max(f64::MIN_POSITIVE))
    }

    fn pdf_1d(&self, x: f64) -> f64 {
        let z = (x - self.mean) / self.sd;
        // exp(-inf) = 0 at the infinities; NaN stays out.
        if z.is_nan() {
            return 0.0;
        }
        (-0.5 * z * z).exp() / ((2.0 * std::f64::consts::PI).sqrt() * self.sd)
    }

    fn invert_1d(&self, x: f64) -> f64 {
        normal_cdf((x - self.mean) / self.sd).clamp(0.0, 1.0)
    }

    fn support(&self) -> (f64, f64) {
        (f64::NEG_INFINITY, f64::INFINITY)
    }
}
