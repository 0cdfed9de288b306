//! The normal density truncated to an interval, sampled by its exact inverse cdf.

use super::Pdf1d;
use crate::float::ONE_BELOW;
use crate::quadrature::gauss_kronrod;
use crate::special::{normal_cdf, normal_quantile, normal_sf};
use crate::{Error, Result};
use std::f64::consts::PI;

/// The smallest positive double (subnormal): upper-tail probabilities go down to 1e-300 times
/// `1 - u`, below `f64::MIN_POSITIVE`.
const SMALLEST_POSITIVE: f64 = 5e-324;

/// The normal density with `mean` and `sd`, restricted to `[a, b]` and renormalised.
///
/// Sampling inverts the cdf, so stratified or quasi-random `u` stay stratified. When the whole
/// interval lies above the mean the computation runs on upper-tail probabilities instead, so
/// intervals far in either tail (down to probabilities near 1e-300) keep full precision, and
/// the mass of intervals narrow compared with the normal's scale is integrated directly. (In
/// such narrow intervals sampling resolves positions to about `1e-16 / mass` of the cdf.)
///
/// ```
/// use mcint::pdf::{Pdf1d, TruncatedNormal};
/// let p = TruncatedNormal::new(0.0, 1.0, 0.0, f64::INFINITY).unwrap(); // half-normal
/// assert!((p.sample_1d(0.5) - 0.674489750196082).abs() < 1e-13);
/// assert!((p.pdf_1d(0.0) - (2.0 / std::f64::consts::PI).sqrt()).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruncatedNormal {
    mean: f64,
    sd: f64,
    a: f64,
    b: f64,
    /// True when `a >= mean`: work with upper-tail probabilities.
    upper: bool,
    /// Tail probability at `a` (lower: `Phi(alpha)`; upper: `1 - Phi(alpha)`).
    at_a: f64,
    /// Normal probability of `[a, b]`.
    mass: f64,
    /// How the density is normalised.
    density: Density,
}

/// The normalisation of the density `exp(-z^2 / 2) / (sqrt(2 pi) sd mass)`.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Density {
    /// `sqrt(2 pi) sd mass`, when that is a normal float.
    Denominator(f64),
    /// Otherwise (a small sd and a small mass, whose product is subnormal and would lose
    /// digits, or an sd near `f64::MAX`) the density relative to its peak `peak` at `z0`, the
    /// point of the interval nearest the mean: `peak exp(-(z - z0)(z + z0) / 2)`.
    Peak { z0: f64, peak: f64 },
}

impl TruncatedNormal {
    /// Requires finite `mean`, finite `sd > 0`, and `a < b` (either may be infinite, a finite
    /// end within `f64::MAX` of the mean) with a normal probability of the interval above
    /// 1e-300 and a peak density that is a finite normal float.
    ///
    /// ```
    /// use mcint::pdf::TruncatedNormal;
    /// assert!(TruncatedNormal::new(0.0, 0.0, -1.0, 1.0).is_err());
    /// assert!(TruncatedNormal::new(0.0, 1.0, 60.0, 61.0).is_err()); // no mass in f64
    /// // A subnormal sd has an infinite peak 1 / (sd sqrt(2 pi)), the largest a subnormal one.
    /// assert!(TruncatedNormal::new(0.0, 1e-310, -1.0, 1.0).is_err());
    /// assert!(TruncatedNormal::new(0.0, f64::MAX, -f64::MAX, 0.0).is_err());
    /// // b - mean overflows.
    /// assert!(TruncatedNormal::new(-1e308, 1e308, 0.0, 1e308).is_err());
    /// // Samples 38 sd below the mean would overflow on (-inf, 0].
    /// assert!(TruncatedNormal::new(0.0, 1e307, f64::NEG_INFINITY, 0.0).is_err());
    /// // Samples are finite, also for u near 1 on a half-line.
    /// use mcint::pdf::Pdf1d;
    /// let half_line = TruncatedNormal::new(0.5, 1e160, 0.0, f64::INFINITY).unwrap();
    /// assert!(half_line.sample_1d(1.0 - f64::EPSILON / 2.0).is_finite());
    /// ```
    pub fn new(mean: f64, sd: f64, a: f64, b: f64) -> Result<Self> {
        if !mean.is_finite() {
            return Err(Error::invalid("mean", mean, "a finite value"));
        }
        if !sd.is_finite() || sd <= 0.0 {
            return Err(Error::invalid("sd", sd, "a finite value > 0"));
        }
        if a.is_nan() || b.is_nan() || a >= b {
            return Err(Error::invalid(
                "[a, b]",
                format!("[{a}, {b}]"),
                "a < b (either may be infinite)",
            ));
        }
        // Samples reach about 38.5 sd from the mean (the quantile of the smallest double);
        // on a half-line nothing clamps them, so that reach must stay finite (as for Normal).
        let reach = mean.abs() + 40.0 * sd;
        if (a.is_infinite() || b.is_infinite()) && !reach.is_finite() {
            return Err(Error::invalid(
                "sd",
                sd,
                format!(
                    "a value with |mean| + 40 sd finite when an end is infinite (mean = {mean})"
                ),
            ));
        }
        // Standardised ends; the distance of a finite end from the mean must be finite.
        let (alpha, beta) = ((a - mean) / sd, (b - mean) / sd);
        if (a.is_finite() && !(a - mean).is_finite()) || (b.is_finite() && !(b - mean).is_finite())
        {
            return Err(Error::invalid(
                "[a, b]",
                format!("[{a}, {b}]"),
                format!("ends whose distance from the mean ({mean}) is finite (below 1.8e308)"),
            ));
        }
        let upper = alpha >= 0.0;
        let (at_a, at_b) = if upper {
            (normal_sf(alpha), normal_sf(beta))
        } else {
            (normal_cdf(alpha), normal_cdf(beta))
        };
        let mut mass = (at_a - at_b).abs();
        if mass < 1e-3 * at_a {
            // The difference of tail probabilities has cancelled (an interval narrow
            // compared with the normal's scale there): integrate the density directly.
            mass = standard_normal_mass(alpha, beta);
        }
        if mass.is_nan() || mass <= 1e-300 {
            return Err(Error::invalid(
                "[a, b]",
                format!("[{a}, {b}]"),
                format!("an interval with normal probability above 1e-300 (it has {mass:e})"),
            ));
        }
        // The density is largest at the point of [a, b] nearest the mean, and that peak must
        // be a finite normal float (a subnormal sd would make it infinite).
        let z0 = (mean.clamp(a, b) - mean) / sd;
        let top = (-0.5 * z0 * z0).exp();
        let (density, peak) = match (2.0 * PI).sqrt() * sd * mass {
            d if d.is_finite() && d >= f64::MIN_POSITIVE => (Density::Denominator(d), top / d),
            _ => {
                // top / mass lies in [1, 1e300]: the mass is at most the normal tail beyond
                // z0, below top / 2 (or 1 when z0 = 0), and above 1e-300.
                let peak = top / mass / sd / (2.0 * PI).sqrt();
                (Density::Peak { z0, peak }, peak)
            }
        };
        if !(peak.is_finite() && peak >= f64::MIN_POSITIVE) {
            return Err(Error::invalid(
                "sd",
                sd,
                format!(
                    "a value > 0 whose peak density is a finite normal float (it is {peak:e} \
                     on [{a}, {b}])"
                ),
            ));
        }
        Ok(TruncatedNormal {
            mean,
            sd,
            a,
            b,
            upper,
            at_a,
            mass,
            density,
        })
    }
}

/// `Phi(beta) - Phi(alpha)` for a finite interval, by adaptive Gauss-Kronrod quadrature of the
/// density (which is smooth, so this reaches full relative precision).
fn standard_normal_mass(alpha: f64, beta: f64) -> f64 {
    let density = |z: f64| (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt();
    gauss_kronrod(density, &[alpha, beta], 1e-15, 0.0, 64).value
}

impl Pdf1d for TruncatedNormal {
    fn sample_1d(&self, u: f64) -> f64 {
        let z = if self.upper {
            // Keep p above zero: with b = +inf, at_a - u mass can round to 0 for u near 1.
            -normal_quantile((self.at_a - u * self.mass).max(SMALLEST_POSITIVE))
        } else {
            // Keep p above zero so u = 0 with a = -inf gives a finite point, and below one for
            // canonical u < 1 (with b = +inf, at_a + u mass can round to 1). Other u are
            // treated as Normal treats them, so that the two agree bit for bit on (-inf, inf).
            let p = (self.at_a + u * self.mass).max(f64::MIN_POSITIVE);
            normal_quantile(if u < 1.0 { p.min(ONE_BELOW) } else { p })
        };
        (self.mean + self.sd * z).clamp(self.a, self.b)
    }

    fn pdf_1d(&self, x: f64) -> f64 {
        if !(x >= self.a && x <= self.b) {
            return 0.0;
        }
        let z = (x - self.mean) / self.sd;
        match self.density {
            Density::Denominator(d) => (-0.5 * z * z).exp() / d,
            Density::Peak { z0, peak } => peak * (-0.5 * (z - z0) * (z + z0)).exp(),
        }
    }

    fn invert_1d(&self, x: f64) -> f64 {
        let z = (x.clamp(self.a, self.b) - self.mean) / self.sd;
        let u = if self.upper {
            (self.at_a - normal_sf(z)) / self.mass
        } else {
            (normal_cdf(z) - self.at_a) / self.mass
        };
        u.clamp(0.0, 1.0)
    }

    fn support(&self) -> (f64, f64) {
        (self.a, self.b)
    }
}
