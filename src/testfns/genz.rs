//! The six Genz test families on `[0,1]^d`.
//!
//! A. Genz, "Testing multidimensional integration routines", in *Tools, Methods and Languages
//! for Scientific and Engineering Computation* (1984), pp. 81-94, introduced these families
//! to probe integration methods with oscillation, peaks, a corner singularity nearby, kinks
//! and discontinuities. The formulas follow the SFU Virtual Library of Simulation
//! Experiments (Surjanovic & Bingham). Parameters `a_i > 0` set the difficulty and
//! `u_i ∈ [0,1]` the location of the feature.
//!
//! Every exact integral is a closed form chosen to avoid cancellation, except the corner
//! peak, whose textbook `2^d`-term alternating sum loses all digits already for moderate `d`.
//! It is reduced instead to a one-dimensional integral of a positive, log-concave function:
//!
//! `∫ (1 + a·x)^{-(d+1)} dx = (1/(d! Π a_i)) ∫_0^∞ e^{-t} Π_i (1 - e^{-a_i t}) dt`,
//!
//! which follows from `s^{-(d+1)} = (1/d!) ∫_0^∞ t^d e^{-ts} dt` and integrating over `x`
//! first. That integral is evaluated by adaptive Gauss-Kronrod quadrature around its peak.
//!
//! At the ends of the range of `a`: quotients such as `sin(a/2)/(a/2)` and `(1 - e^{-a})/a`
//! are replaced by their limits below `a = 1e-100` (subnormal `a` made them 0, inf or
//! imprecise); products over the axes are kept as mantissa and exponent, so factors beyond f64
//! in opposite directions still give their product instead of `0 · inf`; and the oscillatory
//! phase `2π u_1 + Σ a_i/2` is a product of unit complex numbers once the sum passes 16, where
//! summing it would lose `2π u_1` (all of it for `a = 1e300`).

use std::f64::consts::PI;
use std::fmt;
use std::str::FromStr;

use super::TestFunction;
use super::genz_batch::Parameters;
use crate::error::parse_name;
use crate::error::{Error, Result};
use crate::points::Points;
use crate::quadrature::gauss_kronrod;

/// One of the six Genz (1984) integrand families.
///
/// ```
/// use mcint::testfns::GenzFamily;
/// let fam: GenzFamily = "corner-peak".parse().unwrap();
/// assert_eq!(fam, GenzFamily::CornerPeak);
/// assert_eq!(fam.name(), "corner-peak");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GenzFamily {
    /// `cos(2π u_1 + Σ a_i x_i)`.
    Oscillatory,
    /// `Π 1 / (a_i^{-2} + (x_i - u_i)^2)`.
    ProductPeak,
    /// `(1 + Σ a_i x_i)^{-(d+1)}`.
    CornerPeak,
    /// `exp(-Σ a_i^2 (x_i - u_i)^2)`.
    Gaussian,
    /// `exp(-Σ a_i |x_i - u_i|)`, with a kink at `u`.
    Continuous,
    /// `0` if `x_1 > u_1` or `x_2 > u_2` (the latter only when `d >= 2`), else `exp(Σ a_i x_i)`.
    Discontinuous,
}

impl GenzFamily {
    /// All six families, in the order Genz listed them.
    ///
    /// ```
    /// use mcint::testfns::GenzFamily;
    /// for fam in GenzFamily::ALL {
    ///     assert_eq!(fam.name().parse::<GenzFamily>().unwrap(), fam);
    /// }
    /// ```
    pub const ALL: [GenzFamily; 6] = [
        GenzFamily::Oscillatory,
        GenzFamily::ProductPeak,
        GenzFamily::CornerPeak,
        GenzFamily::Gaussian,
        GenzFamily::Continuous,
        GenzFamily::Discontinuous,
    ];

    /// The family's name as accepted by [`FromStr`], in kebab case.
    ///
    /// ```
    /// use mcint::testfns::GenzFamily;
    /// assert_eq!(GenzFamily::ProductPeak.name(), "product-peak");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            GenzFamily::Oscillatory => "oscillatory",
            GenzFamily::ProductPeak => "product-peak",
            GenzFamily::CornerPeak => "corner-peak",
            GenzFamily::Gaussian => "gaussian",
            GenzFamily::Continuous => "continuous",
            GenzFamily::Discontinuous => "discontinuous",
        }
    }
}

impl fmt::Display for GenzFamily {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for GenzFamily {
    type Err = Error;

    /// Parses exactly one of the names returned by [`GenzFamily::name`].
    ///
    /// ```
    /// use mcint::testfns::GenzFamily;
    /// assert_eq!("gaussian".parse::<GenzFamily>().unwrap(), GenzFamily::Gaussian);
    /// assert!("Gauss".parse::<GenzFamily>().unwrap_err().to_string().contains("product-peak"));
    /// ```
    fn from_str(s: &str) -> Result<Self> {
        parse_name("family", s, &GenzFamily::ALL, GenzFamily::name)
    }
}

/// A Genz test integrand: a family with its parameters `a` (difficulty) and `u` (location).
///
/// The exact integral is computed once, at construction.
///
/// ```
/// use mcint::testfns::{Genz, GenzFamily, TestFunction};
/// let f = Genz::new(GenzFamily::Gaussian, vec![2.0, 3.0], vec![0.5, 0.25]).unwrap();
/// assert_eq!(f.dims(), 2);
/// assert_eq!(f.eval(&[0.5, 0.25]), 1.0);
/// assert!(f.exact() > 0.0 && f.exact() < 1.0);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Genz {
    family: GenzFamily,
    a: Vec<f64>,
    u: Vec<f64>,
    /// `a_i^{-2}`, used by the product peak so that `eval` needs one division per axis.
    inv_a_sq: Vec<f64>,
    exact: f64,
}

impl Genz {
    /// A Genz integrand in `d = a.len()` dimensions.
    ///
    /// Requires `a` non-empty with every `a_i` finite and `> 0`, and `u` of the same length
    /// with every `u_i` in `[0, 1]`. Parameters that are valid but extreme can make values or
    /// the exact integral overflow to `inf` (for example the product peak grows like
    /// `Π π a_i`, the discontinuous one like `e^{Σ a_i}`) or underflow to 0 (rounded once,
    /// also when subnormal); factors beyond f64 in opposite directions still give their
    /// product. Tiny and subnormal `a_i` (down to `5e-324`) give the closed forms' limits as
    /// `a_i -> 0`, such as a factor of 1 for the oscillatory, Gaussian, continuous and corner
    /// peak families, `u_i` for a discontinuous cut, and `a_i^2` for the product peak.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `a` (empty, or a value not finite and positive, or
    /// values for which the exact integral would be NaN, which no valid parameters are known
    /// to give) or `u` (wrong length, or a value outside `[0, 1]`).
    ///
    /// ```
    /// use mcint::testfns::{Genz, GenzFamily, TestFunction};
    /// let f = Genz::new(GenzFamily::CornerPeak, vec![5.0; 3], vec![0.5; 3]).unwrap();
    /// // For equal a_i the corner peak integrates to Π_{k=1}^{d} 1 / (1 + k a).
    /// assert!((f.exact() - 1.0 / (6.0 * 11.0 * 16.0)).abs() < 1e-15);
    /// assert!(Genz::new(GenzFamily::CornerPeak, vec![-1.0], vec![0.5]).is_err());
    /// // A cut at u_1 = 0 leaves a region of volume 0: the integral is 0 even though
    /// // e^{1e300 x_3} overflows.
    /// let (a, u) = (vec![1.0, 1.0, 1e300], vec![0.0, 0.5, 0.5]);
    /// assert_eq!(Genz::new(GenzFamily::Discontinuous, a, u).unwrap().exact(), 0.0);
    /// // The smallest subnormal a is the limit a -> 0: the Gaussian integrates to 1.
    /// let g = Genz::new(GenzFamily::Gaussian, vec![5e-324], vec![0.3]).unwrap();
    /// assert_eq!(g.exact(), 1.0);
    /// ```
    pub fn new(family: GenzFamily, a: Vec<f64>, u: Vec<f64>) -> Result<Genz> {
        if a.is_empty() {
            return Err(Error::invalid(
                "a",
                "an empty vector",
                "at least one value (d >= 1)",
            ));
        }
        if u.len() != a.len() {
            return Err(Error::invalid(
                "u",
                format!("a vector of length {}", u.len()),
                format!("length {} to match a", a.len()),
            ));
        }
        if let Some((i, v)) = a
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && **v > 0.0))
        {
            return Err(Error::invalid(
                "a",
                format!("{v} at index {i}"),
                "finite values > 0",
            ));
        }
        if let Some((i, v)) = u
            .iter()
            .enumerate()
            .find(|(_, v)| !(0.0..=1.0).contains(*v))
        {
            return Err(Error::invalid(
                "u",
                format!("{v} at index {i}"),
                "values in [0, 1]",
            ));
        }
        let inv_a_sq = a.iter().map(|ai| (ai * ai).recip()).collect();
        let exact = exact_integral(family, &a, &u);
        // Extreme values may overflow the integral (documented above); a NaN would be a bug of
        // the closed forms, reported as an error rather than returned.
        if exact.is_nan() {
            return Err(Error::invalid(
                "a",
                format!("{a:?}"),
                format!(
                    "values whose exact {} integral is defined in floating point (it is NaN)",
                    family.name()
                ),
            ));
        }
        Ok(Genz {
            family,
            a,
            u,
            inv_a_sq,
            exact,
        })
    }

    /// The customary parameters `a_i = 1 + (i-1)/2` and `u_i` evenly spread over
    /// `[0.2, 0.8]` (`u_1 = 0.5` when `d = 1`), for `i = 1..=d`.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] naming `d` when `d == 0` or too large to store.
    ///
    /// ```
    /// use mcint::testfns::{Genz, GenzFamily};
    /// let f = Genz::with_defaults(GenzFamily::Continuous, 3).unwrap();
    /// assert_eq!(f.a(), &[1.0, 1.5, 2.0]);
    /// assert_eq!(f.u(), &[0.2, 0.5, 0.8]);
    /// assert!(Genz::with_defaults(GenzFamily::Continuous, 0).is_err());
    /// assert!(Genz::with_defaults(GenzFamily::Continuous, usize::MAX).is_err());
    /// ```
    pub fn with_defaults(family: GenzFamily, d: usize) -> Result<Genz> {
        if d == 0 {
            return Err(Error::invalid("d", d, "at least 1"));
        }
        crate::error::check_vec_len::<f64>("d", d)?;
        let a = (0..d).map(|k| 1.0 + 0.5 * k as f64).collect();
        let u = if d == 1 {
            vec![0.5]
        } else {
            (0..d)
                .map(|k| 0.2 + 0.6 * (k as f64 / (d - 1) as f64))
                .collect()
        };
        Genz::new(family, a, u)
    }

    /// The family.
    ///
    /// ```
    /// use mcint::testfns::{Genz, GenzFamily};
    /// let f = Genz::with_defaults(GenzFamily::Oscillatory, 2).unwrap();
    /// assert_eq!(f.family(), GenzFamily::Oscillatory);
    /// ```
    pub fn family(&self) -> GenzFamily {
        self.family
    }

    /// The difficulty parameters `a_i`.
    ///
    /// ```
    /// use mcint::testfns::{Genz, GenzFamily};
    /// let f = Genz::new(GenzFamily::Gaussian, vec![4.0], vec![0.1]).unwrap();
    /// assert_eq!(f.a(), &[4.0]);
    /// ```
    pub fn a(&self) -> &[f64] {
        &self.a
    }

    /// The location parameters `u_i`.
    ///
    /// ```
    /// use mcint::testfns::{Genz, GenzFamily};
    /// let f = Genz::new(GenzFamily::Gaussian, vec![4.0], vec![0.1]).unwrap();
    /// assert_eq!(f.u(), &[0.1]);
    /// ```
    pub fn u(&self) -> &[f64] {
        &self.u
    }
}

impl TestFunction for Genz {
    fn dims(&self) -> usize {
        self.a.len()
    }

    fn eval(&self, x: &[f64]) -> f64 {
        let (a, u) = (&self.a, &self.u);
        match self.family {
            GenzFamily::Oscillatory => {
                let phase: f64 = a.iter().zip(x).map(|(ai, xi)| ai * xi).sum();
                (2.0 * PI * u[0] + phase).cos()
            }
            GenzFamily::ProductPeak => self
                .inv_a_sq
                .iter()
                .zip(u)
                .zip(x)
                .map(|((c, ui), xi)| 1.0 / (c + (xi - ui) * (xi - ui)))
                .product(),
            GenzFamily::CornerPeak => {
                let s = 1.0 + a.iter().zip(x).map(|(ai, xi)| ai * xi).sum::<f64>();
                // powi is accurate to about d ulps, no worse than the conditioning of s^-(d+1).
                match i32::try_from(a.len() + 1) {
                    Ok(n) => s.powi(-n),
                    Err(_) => s.powf(-((a.len() + 1) as f64)),
                }
            }
            GenzFamily::Gaussian => {
                let q: f64 = a
                    .iter()
                    .zip(u)
                    .zip(x)
                    .map(|((ai, ui), xi)| (ai * (xi - ui)).powi(2))
                    .sum();
                (-q).exp()
            }
            GenzFamily::Continuous => {
                let q: f64 = a
                    .iter()
                    .zip(u)
                    .zip(x)
                    .map(|((ai, ui), xi)| ai * (xi - ui).abs())
                    .sum();
                (-q).exp()
            }
            GenzFamily::Discontinuous => {
                // The cut is on the first two axes only; zip stops at d when d = 1.
                if x.iter().zip(u).take(2).any(|(xi, ui)| xi > ui) {
                    0.0
                } else {
                    a.iter().zip(x).map(|(ai, xi)| ai * xi).sum::<f64>().exp()
                }
            }
        }
    }

    fn exact(&self) -> f64 {
        self.exact
    }

    fn name(&self) -> String {
        self.family.name().to_string()
    }

    fn eval_batch(&self, points: &Points, out: &mut [f64]) {
        let parameters = Parameters {
            family: self.family,
            a: &self.a,
            u: &self.u,
            inv_a_sq: &self.inv_a_sq,
        };
        parameters.eval_batch(points, out);
    }
}

/// Below this value of `a` (or of `a` times the length it multiplies) the quotients of the
/// closed forms, such as `sin(a/2)/(a/2)`, `(1 - e^{-a})/a` and `erf(a)/a`, are replaced by
/// their limits as `a -> 0`: the next terms of their series are below `1e-100` relative, while
/// the quotients themselves lose digits to subnormal rounding near `a = 2^-1022`, and become
/// `0/0`, `0` or `inf` for the smallest subnormals.
const TINY_A: f64 = 1e-100;

/// From this sum of `a_k / 2` on, the oscillatory phase `2π u_1 + Σ a_k / 2` is no longer
/// summed: its rounding error, up to `d ulp(Σ a_k / 2)`, would exceed that of a product of
/// unit complex numbers (a few ulps per factor), and by `2^53` it loses every digit.
const PHASE_SUM_LIMIT: f64 = 16.0;

/// `(e^{a c} - 1) / a` for `a > 0`, `c` in `[0, 1]`: the integral of `e^{a x}` over `[0, c]`,
/// as a [`Scaled`] number so that `e^{a c}` beyond f64 (from `a c = 709.8`) is kept.
fn exp_integral(a: f64, c: f64) -> Scaled {
    let y = a * c;
    if y < TINY_A {
        // The limit c (the next term, a c^2 / 2, is below 1e-100 of it).
        return Scaled::one().mul(c);
    }
    if y <= 700.0 {
        return Scaled::one().mul(y.exp_m1() / a);
    }
    if y > 1e6 {
        // e^{1e6} = 10^434294: no product with the other factors (each at least 2^-1074)
        // comes back into range.
        return Scaled::one().mul(f64::INFINITY);
    }
    // e^y (1 - e^{-y}) / a, with e^y in factors of e^500 (at most 2000 of them).
    let mut value = Scaled::one().mul(-(-y).exp_m1() / a);
    let mut rest = y;
    while rest > 500.0 {
        value = value.mul(500f64.exp());
        rest -= 500.0;
    }
    value.mul(rest.exp())
}

/// The closed-form integral over `[0,1]^d`; `a` and `u` are validated and of equal length.
///
/// Products over the axes are kept as [`Scaled`] numbers, so a factor that underflows (a
/// product peak with a tiny `a`) or overflows (a discontinuous one with a huge `a`) only sets
/// the result's size instead of making `0 · inf = NaN`; where the product stays in range the
/// roundings are exactly those of the plain product.
fn exact_integral(family: GenzFamily, a: &[f64], u: &[f64]) -> f64 {
    let per_axis = a.iter().zip(u);
    match family {
        GenzFamily::Oscillatory => {
            // Re(e^{i(2πu_1)} Π (e^{i a_k} - 1)/(i a_k)), with each factor written as
            // e^{i a_k/2} · 2 sin(a_k/2)/a_k so no difference of nearby numbers appears.
            // The limit of 2 sin(a/2)/a as a -> 0 is 1.
            let amplitude = a.iter().fold(Scaled::one(), |p, &ak| {
                p.mul(if ak < TINY_A {
                    1.0
                } else {
                    2.0 * (0.5 * ak).sin() / ak
                })
            });
            let half_sum: f64 = a.iter().map(|ak| 0.5 * ak).sum();
            let cos_phase = if half_sum <= PHASE_SUM_LIMIT {
                (2.0 * PI * u[0] + half_sum).cos()
            } else {
                // cos(2πu_1 + Σ a_k/2) = Re(e^{i 2πu_1} Π e^{i a_k/2}): each angle is reduced
                // exactly by sin_cos, so a huge a_k keeps its phase (and u_1 its effect).
                let (sin, cos) = (2.0 * PI * u[0]).sin_cos();
                let (re, _) = a.iter().fold((cos, sin), |(re, im), ak| {
                    let (s, c) = (0.5 * ak).sin_cos();
                    (re * c - im * s, re * s + im * c)
                });
                re
            };
            amplitude.mul(cos_phase).to_f64()
        }
        GenzFamily::ProductPeak => per_axis
            .fold(Scaled::one(), |p, (&ak, &uk)| {
                if ak < TINY_A {
                    // a (atan(a(1-u)) + atan(a u)) = a^2 (1 - O(a^2)): the limit of the
                    // bracket over a is (1 - u) + u = 1, so the factor is a^2 (which alone
                    // underflows f64 below a = 1e-162).
                    p.mul(ak).mul(ak)
                } else if ak > 1e300 {
                    // a (atan + atan) <= π a would overflow f64 from a = 5.7e307.
                    p.mul(ak).mul((ak * (1.0 - uk)).atan() + (ak * uk).atan())
                } else {
                    p.mul(ak * ((ak * (1.0 - uk)).atan() + (ak * uk).atan()))
                }
            })
            .to_f64(),
        GenzFamily::CornerPeak => corner_peak_integral(a),
        GenzFamily::Gaussian => per_axis
            .fold(Scaled::one(), |p, (&ak, &uk)| {
                p.mul(if ak < TINY_A {
                    // (√π/2)/a (erf(a(1-u)) + erf(a u)) = 1 - a^2 ((1-u)^3 + u^3)/3 + ...:
                    // the limit is 1 (√π/(2a) alone overflows for a < 4.9e-309).
                    1.0
                } else {
                    0.5 * PI.sqrt() / ak * (libm::erf(ak * (1.0 - uk)) + libm::erf(ak * uk))
                })
            })
            .to_f64(),
        GenzFamily::Continuous => per_axis
            .fold(Scaled::one(), |p, (&ak, &uk)| {
                p.mul(if ak < TINY_A {
                    // (2 - e^{-a u} - e^{-a(1-u)})/a = 1 - a (u^2 + (1-u)^2)/2 + ...: limit 1.
                    1.0
                } else {
                    // 2 - e^{-a u} - e^{-a(1-u)} via expm1, exact in relative terms.
                    (-(-ak * uk).exp_m1() - (-ak * (1.0 - uk)).exp_m1()) / ak
                })
            })
            .to_f64(),
        GenzFamily::Discontinuous => {
            // The cut region x_1 <= u_1 (and x_2 <= u_2) has volume 0 when a cut is at 0,
            // and then so has the integral, however large e^{Σ a_k x_k} is elsewhere.
            if u.iter().take(2).any(|&uk| uk == 0.0) {
                return 0.0;
            }
            per_axis
                .enumerate()
                .fold(Scaled::one(), |p, (k, (&ak, &uk))| {
                    let c = if k < 2 { uk } else { 1.0 };
                    p.mul_scaled(exp_integral(ak, c))
                })
                .to_f64()
        }
    }
}

/// A positive number held as `mantissa · 2^exponent`, so that long products such as
/// `d! Π a_i` neither overflow nor underflow before the final result.
#[derive(Debug, Clone, Copy)]
struct Scaled {
    mantissa: f64,
    exponent: i64,
}

impl Scaled {
    fn one() -> Scaled {
        Scaled {
            mantissa: 1.0,
            exponent: 0,
        }
    }

    fn mul(self, factor: f64) -> Scaled {
        // The factor is normalized first, so a subnormal one keeps all its bits.
        let (f, fe) = libm::frexp(factor);
        let (m, e) = libm::frexp(self.mantissa * f);
        Scaled {
            mantissa: m,
            exponent: self.exponent + i64::from(e) + i64::from(fe),
        }
    }

    fn mul_scaled(self, other: Scaled) -> Scaled {
        let product = self.mul(other.mantissa);
        Scaled {
            exponent: product.exponent + other.exponent,
            ..product
        }
    }

    fn to_f64(self) -> f64 {
        // Clamping keeps the i32 conversion lossless; beyond ±4000 the result is 0 or ∞ anyway.
        // scalbn rounds once, also when the result is subnormal.
        libm::scalbn(self.mantissa, self.exponent.clamp(-4000, 4000) as i32)
    }
}

/// `(1 - e^{-a t}) / a`, with the limit `t` (relative error `a t / 2`) where `a t` is tiny.
fn saturation(a: f64, t: f64) -> f64 {
    if a * t < TINY_A {
        t
    } else {
        -(-a * t).exp_m1() / a
    }
}

/// `d/dt log g(t)` for `g(t) = e^{-t} Π (1 - e^{-a_i t})`: strictly decreasing from `+∞`
/// to `-1`, because each `log(1 - e^{-a t})` is concave.
fn log_g_slope(a: &[f64], t: f64) -> f64 {
    // a / (e^{a t} - 1) has the limit 1/t as a t -> 0 (the quotient of subnormals would not).
    -1.0 + a
        .iter()
        .map(|ai| {
            if ai * t < TINY_A {
                t.recip()
            } else {
                ai / (ai * t).exp_m1()
            }
        })
        .sum::<f64>()
}

/// `-(d²/dt²) log g(t) = Σ (a_i / (2 sinh(a_i t / 2)))²`, always positive.
fn log_g_curvature(a: &[f64], t: f64) -> f64 {
    a.iter()
        .map(|ai| {
            if ai * t < TINY_A {
                t.powi(-2)
            } else {
                (ai / (2.0 * (0.5 * ai * t).sinh())).powi(2)
            }
        })
        .sum()
}

/// The corner-peak integral `(1/(d! Π a_i)) ∫_0^∞ g(t) dt`, `g(t) = e^{-t} Π (1 - e^{-a_i t})`.
///
/// `g` is log-concave with a single maximum at `t*`; the integrand is scaled by `g(t*)` so
/// that its peak is 1, and the half-line is split into panels that double in width away
/// from `t*`, so that adaptive quadrature sees every scale on which `g` changes (the peak
/// width `σ` from the curvature of `log g`, each `1/a_i`, and 1); the last panel maps the
/// remaining half-line to a finite interval with `t = t_0 + L s/(1-s)`. The constant
/// `g(t*)/(d! Π a_i)` is accumulated as a [`Scaled`] product.
fn corner_peak_integral(a: &[f64]) -> f64 {
    let d = a.len() as f64;
    // log g has slope >= d/t - 1 - Σa/2 and <= d/t - 1, so the peak lies in [lo, hi].
    let (mut lo, mut hi) = (
        (d / (1.0 + 0.5 * a.iter().sum::<f64>())).max(f64::MIN_POSITIVE),
        d,
    );
    // Bisection on a log scale: the bracket can span hundreds of binary orders of magnitude
    // and t* need only be approximate.
    for _ in 0..200 {
        let mid = (lo * hi).sqrt();
        if !(lo < mid && mid < hi) || hi - lo <= 1e-12 * hi {
            break;
        }
        if log_g_slope(a, mid) > 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    let peak = 0.5 * (lo + hi);
    let sigma = log_g_curvature(a, peak).sqrt().recip();
    let sigma = if sigma > 0.0 && sigma.is_finite() {
        sigma
    } else {
        peak
    };

    let at_peak: Vec<f64> = a.iter().map(|ai| -(-ai * peak).exp_m1()).collect();
    // (1 - e^{-a t}) / (1 - e^{-a t*}), whose limit as a -> 0 is t / t*: used where a t or
    // a t* is tiny, as the quotient of (sub)normal numbers near 2^-1074 has few digits left.
    let ratio = |ai: f64, fp: f64, t: f64| -> f64 {
        if ai * t < TINY_A || ai * peak < TINY_A {
            saturation(ai, t) / saturation(ai, peak)
        } else {
            -(-ai * t).exp_m1() / fp
        }
    };
    // g(t)/g(t*) in logs: each ratio is near 1 around the peak, so its log is accurate.
    let scaled_g = |t: f64| -> f64 {
        let log_ratio: f64 = a
            .iter()
            .zip(&at_peak)
            .map(|(&ai, &fp)| ratio(ai, fp, t).ln())
            .sum();
        (peak - t + log_ratio).exp()
    };

    // Panels double in width away from the peak: from below the finest scale that can matter
    // there (σ, or 1/a_i for a factor not yet saturated at t*, which is >= t*/40) to beyond
    // the coarsest (σ, t* and the unit scale of e^{-t}). Loop caps guard against NaN scales.
    let fine = (sigma.min(peak) / 64.0).max(peak * 1e-12);
    let coarse = 64.0 * sigma.max(peak).max(1.0);
    let mut breaks = vec![peak];
    let mut width = fine;
    for _ in 0..2200 {
        if width >= peak {
            break;
        }
        breaks.push(peak - width);
        width *= 2.0;
    }
    // A factor with a large a_i is saturated at t* but still bends g near t = 0 on the scale
    // 1/a_i, so the panels also halve towards 0. g increases on [0, t*], so ∫_0^b g <= b g(b)
    // and Q >= (t*/2) g(t*/2): stop once the rest is below 1e-18 of the integral.
    let negligible = 1e-18 * 0.5 * peak * scaled_g(0.5 * peak);
    let mut b = breaks.last().copied().unwrap_or(peak);
    for _ in 0..2200 {
        b *= 0.5;
        if !(b > 0.0 && b * scaled_g(b) > negligible) {
            break;
        }
        breaks.push(b);
    }
    breaks.push(0.0);
    breaks.reverse();
    let mut width = fine;
    for _ in 0..2200 {
        breaks.push(peak + width);
        if width >= coarse {
            break;
        }
        width *= 2.0;
    }
    // Beyond `last`, t = last + L s/(1-s) maps s ∈ [0, 1) onto the rest of the half-line. It
    // is integrated over w = s - 1 ∈ [-1, 0), which makes 1 - s = -w exact near t = ∞.
    let last = peak + width;
    breaks.insert(0, -1.0);
    let integrand = |w: f64| -> f64 {
        if w >= 0.0 {
            return scaled_g(w);
        }
        let gap = -w;
        let value = scaled_g(last + width * (1.0 + w) / gap);
        if value == 0.0 {
            0.0
        } else {
            value * width / (gap * gap)
        }
    };
    // The integrand carries rounding noise of order d ulps from its sum of d logarithms.
    let rel_tol = 1e-15 + d * f64::EPSILON;
    let total = gauss_kronrod(integrand, &breaks, rel_tol, 0.0, breaks.len() + 2000).value;

    // g(t*)/(d! Π a_i) = e^{-t*} Π (1 - e^{-a_i t*}) / (i a_i), kept as mantissa and exponent.
    let mut constant = Scaled::one();
    let mut rest = peak;
    while rest > 500.0 {
        constant = constant.mul((-500.0f64).exp());
        rest -= 500.0;
    }
    constant = constant.mul((-rest).exp());
    for (i, (ai, fp)) in a.iter().zip(&at_peak).enumerate() {
        let factor = if ai * peak < TINY_A {
            saturation(*ai, peak)
        } else {
            fp / ai
        };
        constant = constant.mul(factor / (i + 1) as f64);
    }
    constant.mul(total).to_f64()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// For equal a_i the corner-peak integral is Π_{k=1}^{d} 1/(1 + k a).
    fn equal_a_corner(a: f64, d: usize) -> f64 {
        (1..=d).map(|k| 1.0 / (1.0 + k as f64 * a)).product()
    }

    #[test]
    fn corner_peak_matches_equal_a_product_formula() {
        // The integrand's rounding noise is about d ulps (a sum of d logarithms), so that is
        // the accuracy to expect; below d = 10 it is a few ulps.
        for &a in &[1e-300, 1e-6, 1e-3, 0.1, 1.0, 5.0, 100.0, 1e6, 1e100, 1e300] {
            for &d in &[1usize, 2, 3, 8, 20, 100, 1000] {
                let got = corner_peak_integral(&vec![a; d]);
                let want = equal_a_corner(a, d);
                let tol = 2e-15 + 4.0 * d as f64 * f64::EPSILON;
                let err = (got - want).abs();
                // Results below ~1e-290 lose relative precision to subnormal rounding.
                assert!(
                    err <= tol * want || (want < 1e-290 && err < 1e-300),
                    "a = {a}, d = {d}: {got:e} vs {want:e}"
                );
            }
        }
    }

    #[test]
    fn corner_peak_d1_mixed_scales() {
        // d = 1: 1/(1 + a); d = 2 with distinct a: closed form from the alternating sum.
        for &a in &[1e-300, 1e-8, 0.5, 3.0, 1e8, 1e300] {
            let got = corner_peak_integral(&[a]);
            assert!((got * (1.0 + a) - 1.0).abs() < 1e-14, "a = {a}: {got:e}");
        }
        for &(p, q) in &[(1e-3, 1e3), (0.5, 2.0), (1e-8, 1.0), (7.0, 1e6)] {
            let got = corner_peak_integral(&[p, q]);
            // (1 - 1/(1+p) - 1/(1+q) + 1/(1+p+q)) / (2pq) = 1/((1+p)(1+q)(1+p+q)) · (2+p+q)/2.
            let want = (2.0 + p + q) / (2.0 * (1.0 + p) * (1.0 + q) * (1.0 + p + q));
            assert!(
                ((got - want) / want).abs() < 1e-14,
                "({p}, {q}): {got:e} vs {want:e}"
            );
        }
    }

    #[test]
    fn defaults_support_large_d() {
        for fam in GenzFamily::ALL {
            let f = Genz::with_defaults(fam, 1000).unwrap();
            let x = vec![0.3; 1000];
            assert!(!f.eval(&x).is_nan(), "{fam}");
            assert!(!f.exact().is_nan(), "{fam}");
        }
        let f = Genz::with_defaults(GenzFamily::CornerPeak, 1000).unwrap();
        assert!(f.exact() >= 0.0 && f.exact().is_finite());
    }
}
