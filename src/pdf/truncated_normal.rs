//! The normal density truncated to an interval, sampled by its exact inverse cdf.

use super::Pdf1d;
use crate::error::{Error, Result};
use crate::float::ONE_BELOW;
use crate::special::{normal_cdf, normal_quantile, normal_sf};
use std::f64::consts::PI;

/// The smallest positive double (subnormal): upper-tail probabilities go down to 1e-300 times
/// `1 - u`, below `f64::MIN_POSITIVE`.
const SMALLEST_POSITIVE: f64 = 5e-324;

/// The largest `|k1| + k2` (the density's log-variation over the interval, see [`Local`]) for
/// which the interval is handled locally. Above it the interval's probability is at least
/// 0.03 of the tail probability it is the difference of, so that difference loses at most
/// 1.5 digits.
const LOCAL_VARIATION: f64 = 1.0 / 16.0;

/// Power-series terms of the local cdf: with `|k1| + k2 <= 1/16` the first one left out is
/// below 1e-18 of the total (Cauchy's estimate on a circle of radius `sqrt(m / 2 k2)` or
/// `m / |k1|`).
const LOCAL_TERMS: usize = 20;

/// The normal density with `mean` and `sd`, restricted to `[a, b]` and renormalised.
///
/// Sampling inverts the cdf, so stratified or quasi-random `u` stay stratified. When the whole
/// interval lies above the mean the computation runs on upper-tail probabilities instead, so
/// intervals far in either tail (down to probabilities near 1e-300) keep full precision. An
/// interval over which the density changes little (narrow compared with the normal's scale
/// there, or with a standard deviation that dwarfs it) is handled from its own left end,
/// without any normal cdf, so it keeps full precision too: there the difference of tail
/// probabilities would cancel.
///
/// ```
/// use mcint::pdf::{Pdf1d, TruncatedNormal};
/// let p = TruncatedNormal::new(0.0, 1.0, 0.0, f64::INFINITY).unwrap(); // half-normal
/// assert!((p.sample_1d(0.5) - 0.674489750196082).abs() < 1e-13);
/// assert!((p.pdf_1d(0.0) - (2.0 / std::f64::consts::PI).sqrt()).abs() < 1e-15);
/// ```
///
/// ```
/// use mcint::pdf::{Pdf1d, TruncatedNormal};
/// // The sd dwarfs [1, 2]: the law is uniform there to within 1e-200.
/// let wide = TruncatedNormal::new(0.0, 1e200, 1.0, 2.0).unwrap();
/// assert_eq!(wide.sample_1d(0.25), 1.25);
/// assert_eq!(wide.invert_1d(1.75), 0.75);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruncatedNormal {
    mean: f64,
    sd: f64,
    a: f64,
    b: f64,
    cdf: Cdf,
}

/// How the cdf is computed and inverted.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Cdf {
    /// As a difference of normal tail probabilities.
    Tails {
        /// True when `a >= mean`: work with upper-tail probabilities.
        upper: bool,
        /// Tail probability at `a` (lower: `Phi(alpha)`; upper: `1 - Phi(alpha)`).
        at_a: f64,
        /// Normal probability of `[a, b]`.
        mass: f64,
        /// How the density is normalised.
        density: Density,
    },
    /// From the left end, where the density varies little over the interval.
    Local(Local),
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

/// The density over `[a, b]` relative to its value at `a`, as a function of the position
/// `t = (x - a) / (b - a)` in `[0, 1]`: with `alpha = (a - mean) / sd` and
/// `w = (b - a) / sd`, `(z^2 - alpha^2) / 2 = k1 t + k2 t^2` where `k1 = alpha w` and
/// `k2 = w^2 / 2`, so the density is proportional to `exp(-(k1 t + k2 t^2))`. Nothing here
/// subtracts nearly equal numbers, and when `k1` and `k2` underflow it is exactly uniform.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Local {
    /// `b - a`.
    width: f64,
    k1: f64,
    k2: f64,
    /// `G(t) = int_0^t exp(-(k1 r + k2 r^2)) dr = t sum_m g[m] t^m`.
    g: [f64; LOCAL_TERMS],
    /// The number of terms of `g` above 1e-20 (the rest are dropped, below rounding).
    terms: usize,
    /// `G(1)`.
    total: f64,
}

impl Local {
    fn new(width: f64, k1: f64, k2: f64) -> Self {
        // The density's Taylor coefficients c[m] follow from f' = -(k1 + 2 k2 t) f:
        // (m + 1) c[m+1] = -k1 c[m] - 2 k2 c[m-1], c[0] = 1; then g[m] = c[m] / (m + 1).
        let mut g = [0.0; LOCAL_TERMS];
        let (mut before, mut c) = (0.0, 1.0);
        for (m, slot) in g.iter_mut().enumerate() {
            *slot = c / (m + 1) as f64;
            let next = (-k1 * c - 2.0 * k2 * before) / (m + 1) as f64;
            (before, c) = (c, next);
        }
        let terms = 1 + g.iter().rposition(|c| c.abs() > 1e-20).unwrap_or(0);
        let mut local = Local {
            width,
            k1,
            k2,
            g,
            terms,
            total: 1.0,
        };
        local.total = local.integral(1.0);
        local
    }

    /// `exp(-(k1 t + k2 t^2))`.
    fn density(&self, t: f64) -> f64 {
        (-(self.k1 + self.k2 * t) * t).exp()
    }

    /// `G(t)`.
    fn integral(&self, t: f64) -> f64 {
        t * self.g[..self.terms]
            .iter()
            .rev()
            .fold(0.0, |sum, &g| sum * t + g)
    }

    /// The `t` with `G(t) = u G(1)`, by Newton's method from the inverse to first order in
    /// `k1` and `k2`, `t = u - k1 u (1 - u) / 2 - k2 u (1 - u^2) / 3`, which is within about
    /// `(|k1| + k2)^2` of it: the density stays within a factor `e^(1/16)` of 1, so each step
    /// squares the error (times at most 1/16), and three steps reach rounding.
    fn position(&self, u: f64) -> f64 {
        let target = u * self.total;
        let mut t =
            (u - u * (1.0 - u) * (self.k1 / 2.0 + self.k2 * (1.0 + u) / 3.0)).clamp(0.0, 1.0);
        for _ in 0..6 {
            let step = (self.integral(t) - target) / self.density(t);
            t = (t - step).clamp(0.0, 1.0);
            // Rounding leaves steps of a few ulps; after a step that small the next would be
            // far below one.
            if step.abs() <= 8.0 * f64::EPSILON * t {
                break;
            }
        }
        t
    }
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
        let width = b - a;
        let w = width / sd;
        let (k1, k2) = (alpha * w, 0.5 * w * w);
        let (mass, peak, cdf) = if width.is_finite() && k1.abs() + k2 <= LOCAL_VARIATION {
            let local = Local::new(width, k1, k2);
            let phi = (-0.5 * alpha * alpha).exp() / (2.0 * PI).sqrt();
            let peak = local.density(0.0).max(local.density(1.0)) / (width * local.total);
            (phi * w * local.total, peak, Cdf::Local(local))
        } else {
            // Here the interval's probability is at least 0.03 of the larger tail probability
            // (see LOCAL_VARIATION).
            let upper = alpha >= 0.0;
            let (at_a, at_b) = if upper {
                (normal_sf(alpha), normal_sf(beta))
            } else {
                (normal_cdf(alpha), normal_cdf(beta))
            };
            let mass = (at_a - at_b).abs();
            // The density is largest at the point of [a, b] nearest the mean.
            let z0 = (mean.clamp(a, b) - mean) / sd;
            let top = (-0.5 * z0 * z0).exp();
            let (density, peak) = match (2.0 * PI).sqrt() * sd * mass {
                d if d.is_finite() && d >= f64::MIN_POSITIVE => (Density::Denominator(d), top / d),
                _ => {
                    // top / mass lies in [1, 1e300]: the mass is at most the normal tail
                    // beyond z0, below top / 2 (or 1 when z0 = 0), and above 1e-300.
                    let peak = top / mass / sd / (2.0 * PI).sqrt();
                    (Density::Peak { z0, peak }, peak)
                }
            };
            let cdf = Cdf::Tails {
                upper,
                at_a,
                mass,
                density,
            };
            (mass, peak, cdf)
        };
        if mass.is_nan() || mass <= 1e-300 {
            return Err(Error::invalid(
                "[a, b]",
                format!("[{a}, {b}]"),
                format!("an interval with normal probability above 1e-300 (it has {mass:e})"),
            ));
        }
        // The peak density must be a finite normal float (a subnormal sd would make it
        // infinite).
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
        // One over the peak density is how far the mass spreads from the peak.
        super::check_resolved(
            "mean, sd and [a, b]",
            format!("{mean}, {sd} and [{a}, {b}]"),
            1.0 / peak,
            mean.clamp(a, b),
        )?;
        Ok(TruncatedNormal {
            mean,
            sd,
            a,
            b,
            cdf,
        })
    }
}

impl Pdf1d for TruncatedNormal {
    fn sample_1d(&self, u: f64) -> f64 {
        let x = match self.cdf {
            Cdf::Local(ref local) => self.a + local.position(u) * local.width,
            Cdf::Tails {
                upper, at_a, mass, ..
            } => {
                let z = if upper {
                    // Keep p above zero: with b = +inf, at_a - u mass can round to 0 for u
                    // near 1.
                    -normal_quantile((at_a - u * mass).max(SMALLEST_POSITIVE))
                } else {
                    // Keep p above zero so u = 0 with a = -inf gives a finite point, and below
                    // one for canonical u < 1 (with b = +inf, at_a + u mass can round to 1).
                    // Other u are treated as Normal treats them, so that the two agree bit for
                    // bit on (-inf, inf).
                    let p = (at_a + u * mass).max(f64::MIN_POSITIVE);
                    normal_quantile(if u < 1.0 { p.min(ONE_BELOW) } else { p })
                };
                self.mean + self.sd * z
            }
        };
        x.clamp(self.a, self.b)
    }

    fn pdf_1d(&self, x: f64) -> f64 {
        if !(x >= self.a && x <= self.b) {
            return 0.0;
        }
        match self.cdf {
            Cdf::Local(ref local) => {
                let t = (x - self.a) / local.width;
                local.density(t) / (local.width * local.total)
            }
            Cdf::Tails { density, .. } => {
                let z = (x - self.mean) / self.sd;
                match density {
                    Density::Denominator(d) => (-0.5 * z * z).exp() / d,
                    Density::Peak { z0, peak } => peak * (-0.5 * (z - z0) * (z + z0)).exp(),
                }
            }
        }
    }

    fn invert_1d(&self, x: f64) -> f64 {
        let x = x.clamp(self.a, self.b);
        let u = match self.cdf {
            Cdf::Local(ref local) => {
                let t = ((x - self.a) / local.width).min(1.0);
                local.integral(t) / local.total
            }
            Cdf::Tails {
                upper, at_a, mass, ..
            } => {
                let z = (x - self.mean) / self.sd;
                if upper {
                    (at_a - normal_sf(z)) / mass
                } else {
                    (normal_cdf(z) - at_a) / mass
                }
            }
        };
        u.clamp(0.0, 1.0)
    }

    fn support(&self) -> (f64, f64) {
        (self.a, self.b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quadrature::gauss_kronrod;

    #[test]
    fn the_local_series_matches_quadrature_up_to_the_largest_variation() {
        let limit = LOCAL_VARIATION;
        for (k1, k2) in [
            (limit, 0.0),
            (-limit, 0.0),
            (0.0, limit),
            (limit / 2.0, limit / 2.0),
            (-limit / 2.0, limit / 2.0),
            (1e-300, 0.0),
            (0.0, 0.0),
        ] {
            let local = Local::new(1.0, k1, k2);
            for t in [1e-300, 0.1, 0.5, 0.9, 1.0] {
                let exact = gauss_kronrod(|r| local.density(r), &[0.0, t], 1e-16, 0.0, 64).value;
                let series = local.integral(t);
                assert!(
                    (series - exact).abs() <= 4.0 * f64::EPSILON * exact,
                    "k1 {k1}, k2 {k2}: G({t}) = {series} vs {exact}"
                );
            }
            for u in [0.0, 1e-300, 0.001, 0.25, 0.5, 0.75, 0.999, ONE_BELOW, 1.0] {
                let t = local.position(u);
                let back = local.integral(t) / local.total;
                assert!(
                    (back - u).abs() <= 4.0 * f64::EPSILON * u.max(1e-300),
                    "k1 {k1}, k2 {k2}: position({u}) = {t} gives back {back}"
                );
            }
        }
    }
}
