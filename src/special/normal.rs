//! The standard normal distribution: CDF `Φ`, survival function `1 - Φ` and quantile `Φ⁻¹`.
//!
//! The CDF and survival function are both written in terms of the complementary error
//! function (`libm::erfc`), `Φ(x) = erfc(-x/√2)/2` and `1 - Φ(x) = erfc(x/√2)/2`, so each
//! keeps full relative precision in its own small tail instead of computing `1 - (1 - tiny)`.
//! The rounding of the argument `x/√2` is corrected to first order, which matters far out
//! in the tail where `erfc` magnifies a relative argument error by `2z²`.
//!
//! The quantile is Wichura's algorithm AS 241 (PPND16): M. J. Wichura, "Algorithm AS 241:
//! The Percentage Points of the Normal Distribution", *Applied Statistics* 37(3), 477–484
//! (1988). It evaluates one of three rational approximations of degree 7/7 and is accurate
//! to about 1 part in 10¹⁶.

use core::f64::consts::{FRAC_1_SQRT_2, FRAC_2_SQRT_PI};

/// `1/√2 - FRAC_1_SQRT_2`: the rounding error of the `f64` constant, so that the product
/// `x/√2` can be formed to about 32 significant digits.
const FRAC_1_SQRT_2_LO: f64 = -4.833_646_656_726_457e-17;

/// `erfc(x/√2) / 2`, the upper tail `1 - Φ(x)`.
fn half_erfc_scaled(x: f64) -> f64 {
    if x.is_nan() {
        return f64::NAN;
    }
    if x.is_infinite() {
        return if x > 0.0 { 0.0 } else { 1.0 };
    }
    let z = x * FRAC_1_SQRT_2;
    // `z` is `x/√2` rounded; `dz` is what the rounding (and the constant's own error) lost.
    let dz = libm::fma(x, FRAC_1_SQRT_2, -z) + x * FRAC_1_SQRT_2_LO;
    // erfc(z + dz) ≈ erfc(z) - dz · 2/√π · exp(-z²): one Taylor term is plenty, `dz` is
    // below one ulp of `z`.
    let slope = FRAC_2_SQRT_PI * libm::exp(-z * z);
    0.5 * (libm::erfc(z) - dz * slope)
}

/// The standard normal cumulative distribution function `Φ(x) = P(Z ≤ x)`.
///
/// Computed as `erfc(-x/√2)/2`, so the lower tail keeps full relative precision
/// (`normal_cdf(-20.0)` is about `2.75e-89`, correct to the last few digits). Results
/// below about `2.2e-308` are subnormal and lose precision gradually; `x = ±∞` gives
/// `0`/`1` and NaN gives NaN.
pub(crate) fn normal_cdf(x: f64) -> f64 {
    half_erfc_scaled(-x)
}

/// The standard normal survival function `1 - Φ(x) = P(Z > x)`.
///
/// Computed as `erfc(x/√2)/2`, with full relative precision in the upper tail where
/// `1.0 - normal_cdf(x)` would cancel to zero.
pub(crate) fn normal_sf(x: f64) -> f64 {
    half_erfc_scaled(x)
}

// AS 241 (PPND16) coefficients, lowest degree first, as published by Wichura (1988).
// They carry more digits than an f64 holds; they are kept exactly as published so they
// can be checked against the paper.

/// Numerator for `|p - 1/2| ≤ 0.425`, in `r = 0.180625 - (p - 1/2)²`.
#[allow(clippy::excessive_precision, reason = "published AS 241 coefficients")]
const A: [f64; 8] = [
    3.3871328727963666080e0,
    1.3314166789178437745e+2,
    1.9715909503065514427e+3,
    1.3731693765509461125e+4,
    4.5921953931549871457e+4,
    6.7265770927008700853e+4,
    3.3430575583588128105e+4,
    2.5090809287301226727e+3,
];
/// Denominator for `|p - 1/2| ≤ 0.425`.
#[allow(clippy::excessive_precision, reason = "published AS 241 coefficients")]
const B: [f64; 8] = [
    1.0,
    4.2313330701600911252e+1,
    6.8718700749205790830e+2,
    5.3941960214247511077e+3,
    2.1213794301586595867e+4,
    3.9307895800092710610e+4,
    2.8729085735721942674e+4,
    5.2264952788528545610e+3,
];
/// Numerator for the intermediate tail, in `r = √(-ln min(p, 1-p)) - 1.6`, `r + 1.6 ≤ 5`.
#[allow(clippy::excessive_precision, reason = "published AS 241 coefficients")]
const C: [f64; 8] = [
    1.42343711074968357734e0,
    4.63033784615654529590e0,
    5.76949722146069140550e0,
    3.64784832476320460504e0,
    1.27045825245236838258e0,
    2.41780725177450611770e-1,
    2.27238449892691845833e-2,
    7.74545014278341407640e-4,
];
/// Denominator for the intermediate tail.
#[allow(clippy::excessive_precision, reason = "published AS 241 coefficients")]
const D: [f64; 8] = [
    1.0,
    2.05319162663775882187e0,
    1.67638483018380384940e0,
    6.89767334985100004550e-1,
    1.48103976427480074590e-1,
    1.51986665636164571966e-2,
    5.47593808499534494600e-4,
    1.05075007164441684324e-9,
];
/// Numerator for the far tail, in `r = √(-ln min(p, 1-p)) - 5`.
#[allow(clippy::excessive_precision, reason = "published AS 241 coefficients")]
const E: [f64; 8] = [
    6.65790464350110377720e0,
    5.46378491116411436990e0,
    1.78482653991729133580e0,
    2.96560571828504891230e-1,
    2.65321895265761230930e-2,
    1.24266094738807843860e-3,
    2.71155556874348757815e-5,
    2.01033439929228813265e-7,
];
/// Denominator for the far tail.
#[allow(clippy::excessive_precision, reason = "published AS 241 coefficients")]
const F: [f64; 8] = [
    1.0,
    5.99832206555887937690e-1,
    1.36929880922735805310e-1,
    1.48753612908506148525e-2,
    7.86869131145613259100e-4,
    1.84631831751005468180e-5,
    1.42151175831644588870e-7,
    2.04426310338993978564e-15,
];

/// Horner evaluation of `c[0] + c[1] r + … + c[7] r⁷`.
fn poly7(c: &[f64; 8], r: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ci| acc * r + ci)
}

/// The standard normal quantile function `Φ⁻¹(p)`: the `x` with `P(Z ≤ x) = p`.
///
/// Wichura's AS 241 (PPND16), relative accuracy about `1e-16` for every representable
/// `p` in `(0, 1)`, including `p` far into the tails (`normal_quantile(1e-300)` is about
/// `-37.05`). Near `p = 1` the answer can only be as precise as `1 - p` is, which is the
/// rounding of `p` itself.
///
/// Follows scipy's conventions at the edges: `p = 0` gives `-∞`, `p = 1` gives `+∞`, and
/// `p` outside `[0, 1]` or NaN gives NaN.
pub(crate) fn normal_quantile(p: f64) -> f64 {
    if p.is_nan() || !(0.0..=1.0).contains(&p) {
        return f64::NAN;
    }
    if p == 0.0 {
        return f64::NEG_INFINITY;
    }
    if p == 1.0 {
        return f64::INFINITY;
    }
    // Exact (Sterbenz) for p in [0.25, 1]; below that the relative error of q is harmless
    // because the central branch then is not used.
    let q = p - 0.5;
    if q.abs() <= 0.425 {
        let r = 0.180625 - q * q;
        return q * poly7(&A, r) / poly7(&B, r);
    }
    // Work with the smaller tail probability; `1 - p` is exact for p ≥ 1/2.
    let tail = if q < 0.0 { p } else { 1.0 - p };
    let r = libm::sqrt(-libm::log(tail));
    let magnitude = if r <= 5.0 {
        let r = r - 1.6;
        poly7(&C, r) / poly7(&D, r)
    } else {
        let r = r - 5.0;
        poly7(&E, r) / poly7(&F, r)
    };
    if q < 0.0 { -magnitude } else { magnitude }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference values come from scipy 1.17.1, whose `ndtr`/`ndtri` are themselves good
    /// to a few ulps (checked against 50-digit mpmath: at most 3e-14 off, at x = -20,
    /// where this module is within 1e-16). 1e-12 leaves room for both while any real
    /// defect (wrong coefficient, wrong branch, lost tail precision) shows up at 1e-8 or
    /// worse.
    const REL_TOL: f64 = 1e-12;

    fn rel_err(got: f64, want: f64) -> f64 {
        if got == want {
            0.0
        } else {
            ((got - want) / want).abs()
        }
    }

    // (x, Φ(x), 1 - Φ(x)) from
    // python3 -c "from scipy.stats import norm; [print(f'({x!r}, {float(norm.cdf(x))!r}, {float(norm.sf(x))!r}),') for x in (-20.0, -8.0, -1.0, 0.0, 0.5, 3.0, 8.0)]"
    const CDF_TABLE: [(f64, f64, f64); 7] = [
        (-20.0, 2.7536241186061556e-89, 1.0),
        (-8.0, 6.22096057427174e-16, 0.9999999999999993),
        (-1.0, 0.15865525393145707, 0.8413447460685429),
        (0.0, 0.5, 0.5),
        (0.5, 0.6914624612740131, 0.3085375387259869),
        (3.0, 0.9986501019683699, 0.0013498980316300933),
        (8.0, 0.9999999999999993, 6.22096057427174e-16),
    ];

    // (p, Φ⁻¹(p)) from
    // python3 -c "from scipy.stats import norm; [print(f'({p!r}, {float(norm.ppf(p))!r}),') for p in (1e-300, 1e-20, 1e-10, 0.001, 0.025, 0.3, 0.5, 0.7, 0.975, 0.999, 1 - 1e-10)]"
    const QUANTILE_TABLE: [(f64, f64); 11] = [
        (1e-300, -37.0470962993612),
        (1e-20, -9.262340089798409),
        (1e-10, -6.361340902404056),
        (0.001, -3.090232306167813),
        (0.025, -1.9599639845400545),
        (0.3, -0.5244005127080409),
        (0.5, 0.0),
        (0.7, 0.5244005127080407),
        (0.975, 1.959963984540054),
        (0.999, 3.090232306167813),
        (0.9999999999, 6.361340889697422),
    ];

    #[test]
    fn cdf_and_sf_match_scipy() {
        for (x, cdf, sf) in CDF_TABLE {
            let (got_cdf, got_sf) = (normal_cdf(x), normal_sf(x));
            assert!(
                rel_err(got_cdf, cdf) <= REL_TOL,
                "cdf({x}) = {got_cdf:e}, want {cdf:e}"
            );
            assert!(
                rel_err(got_sf, sf) <= REL_TOL,
                "sf({x}) = {got_sf:e}, want {sf:e}"
            );
        }
    }

    #[test]
    fn deep_lower_tail_is_not_rounded_to_zero() {
        // scipy's norm.cdf(-38.0) underflows to 0, so the reference is its log form:
        // python3 -c "import math; from scipy.special import log_ndtr; print(repr(math.exp(log_ndtr(-38.0))))"
        let want = 2.88542835e-316;
        let got = normal_cdf(-38.0);
        // The value is subnormal (below 2.2e-308) and carries only about 7 significant
        // digits there (an ulp is 4.9e-324), so relative precision 1e-12 is not possible.
        assert!(
            rel_err(got, want) <= 1e-7,
            "cdf(-38) = {got:e}, want {want:e}"
        );
        assert_eq!(normal_sf(-38.0), 1.0);
        assert_eq!(normal_sf(38.0), got);
    }

    #[test]
    fn quantile_matches_scipy() {
        for (p, want) in QUANTILE_TABLE {
            let got = normal_quantile(p);
            assert!(
                rel_err(got, want) <= REL_TOL,
                "quantile({p}) = {got:e}, want {want:e}"
            );
        }
    }

    #[test]
    fn quantile_inverts_cdf() {
        // Lower tail: p = Φ(x) keeps full precision there, so x comes back to ~1e-15.
        let mut x = -37.0;
        while x <= 0.0 {
            let back = normal_quantile(normal_cdf(x));
            assert!(
                (back - x).abs() <= 1e-13 * x.abs().max(1.0),
                "x = {x}, back = {back}"
            );
            x += 0.37;
        }
        // Upper tail through the survival function and symmetry.
        let mut x = 0.5;
        while x <= 37.0 {
            let back = -normal_quantile(normal_sf(x));
            assert!((back - x).abs() <= 1e-13 * x, "x = {x}, back = {back}");
            x += 0.37;
        }
    }

    #[test]
    fn cdf_and_sf_are_mirror_images() {
        for i in -200..=200 {
            let x = f64::from(i) * 0.1;
            assert_eq!(normal_cdf(x), normal_sf(-x));
            let sum = normal_cdf(x) + normal_sf(x);
            assert!(
                (sum - 1.0).abs() <= 2.0 * f64::EPSILON,
                "x = {x}: sum {sum}"
            );
        }
    }

    #[test]
    fn quantile_is_odd_about_one_half() {
        // Dyadic p make 1 - p exact, so both sides take mirrored paths.
        for k in 1..1024 {
            let p = f64::from(k) / 1024.0;
            assert_eq!(normal_quantile(1.0 - p), -normal_quantile(p), "p = {p}");
        }
    }

    #[test]
    fn quantile_edges_follow_scipy() {
        assert_eq!(normal_quantile(0.0), f64::NEG_INFINITY);
        assert_eq!(normal_quantile(1.0), f64::INFINITY);
        assert_eq!(normal_quantile(0.5), 0.0);
        for p in [f64::NAN, -5e-324, -1.0, 1.0 + f64::EPSILON, f64::INFINITY] {
            assert!(normal_quantile(p).is_nan(), "p = {p}");
        }
        // Subnormal p still gives a finite, sensible answer.
        let x = normal_quantile(5e-324);
        assert!(x.is_finite() && x < -38.0, "{x}");
    }

    #[test]
    fn cdf_edges() {
        assert!(normal_cdf(f64::NAN).is_nan());
        assert!(normal_sf(f64::NAN).is_nan());
        assert_eq!(normal_cdf(f64::NEG_INFINITY), 0.0);
        assert_eq!(normal_cdf(f64::INFINITY), 1.0);
        assert_eq!(normal_sf(f64::INFINITY), 0.0);
        assert_eq!(normal_sf(f64::NEG_INFINITY), 1.0);
        assert_eq!(normal_cdf(-40.0), 0.0);
        assert_eq!(normal_cdf(f64::MAX), 1.0);
        assert_eq!(normal_cdf(f64::MIN), 0.0);
    }

    /// The values quoted in the function's documentation.
    #[test]
    fn normal_cdf_examples_hold() {
        assert_eq!(normal_cdf(0.0), 0.5);
        assert!((normal_cdf(1.959963984540054) - 0.975).abs() < 1e-15);
        // The lower tail is not rounded away to zero.
        let tail = normal_cdf(-10.0);
        assert!((tail / 7.619853024160527e-24 - 1.0).abs() < 1e-14);
    }

    /// The values quoted in the function's documentation.
    #[test]
    fn normal_sf_examples_hold() {
        assert_eq!(normal_sf(0.0), 0.5);
        let tail = normal_sf(10.0);
        assert!((tail / 7.619853024160527e-24 - 1.0).abs() < 1e-14);
    }

    /// The values quoted in the function's documentation.
    #[test]
    fn normal_quantile_examples_hold() {
        assert_eq!(normal_quantile(0.5), 0.0);
        assert!((normal_quantile(0.975) - 1.959963984540054).abs() < 1e-15);
        assert!((normal_quantile(0.025) + 1.959963984540054).abs() < 1e-15);
        assert_eq!(normal_quantile(0.0), f64::NEG_INFINITY);
        assert!(normal_quantile(1.5).is_nan());
    }
}
