//! Student's t distribution with any real number of degrees of freedom `ν > 0`: CDF and
//! quantile.
//!
//! The CDF uses the regularized incomplete beta function,
//! `P(T > s) = I_x(ν/2, 1/2) / 2` with `x = ν / (ν + s²)`, for `s ≥ 0`. Whichever of the
//! upper tail `P(T > s)` and the central part `P(0 < T ≤ s) = I_{1-x}(1/2, ν/2) / 2` is the
//! one the continued fraction converges for is computed directly and the other one by
//! subtraction from `1/2`, so both tails keep full relative precision. The incomplete beta
//! function is the classical continued fraction
//! `I_x(a, b) = x^a (1-x)^b / (a B(a, b)) · 1/(1 + d₁/(1 + d₂/(1 + …)))`
//! (Abramowitz & Stegun 26.5.8; Press et al., *Numerical Recipes*, §6.4), evaluated with
//! the modified Lentz method (Lentz 1976; Thompson & Barnett 1986). `ln B(a, b)` comes from
//! `libm::lgamma` when both arguments are small, and from a Stirling series for the ratio
//! `Γ(a + b) / Γ(a)` when one is large, so that no two huge log-gamma values cancel.
//!
//! `ν = 1` (Cauchy) and `ν = 2` have closed forms and use them. For `ν > 10¹⁰` the CDF is
//! the normal one plus the first three terms of its expansion in `1/ν` (exact to rounding
//! there), because the continued fraction eventually suffers from `ν` near the top of
//! the `f64` range. `ν = ∞` is the normal distribution.
//!
//! The quantile solves `P(T > s) = q` for the smaller tail `q = min(p, 1 - p)`. It starts
//! from the root of the power-law tail bound, `√ν (q ν B(ν/2, 1/2))^(-1/ν)`, when that is
//! far out compared with `√ν`, and otherwise from the Cornish–Fisher expansion around the
//! normal quantile (Abramowitz & Stegun 26.7.5). Newton's method then runs in `ln s` on
//! `ln P(T > s)` (near the centre on `ln P(0 < T ≤ s)`), both close to straight lines,
//! inside the bracket `[z, power-law root]` with geometric bisection as the fallback and
//! a hard iteration cap, so it always terminates.

use core::f64::consts::{FRAC_1_PI, FRAC_1_SQRT_2, PI, SQRT_2};

use super::normal::{normal_quantile, normal_sf};

/// `1 / √(2π)`, the normal density at 0.
const FRAC_1_SQRT_2PI: f64 = 0.398_942_280_401_432_7;

/// Above this many degrees of freedom the CDF switches from the continued fraction to the
/// large-`ν` expansion around the normal distribution. The continued fraction stays
/// accurate (about `1e-14`) well beyond this, to `ν ≈ 1e50`, and the expansion is exact to
/// rounding from here on, so the switch point is not delicate.
const ASYMPTOTIC_DOF: f64 = 1e10;

/// Smaller degrees of freedom are raised to this. Below it every result already is the
/// `ν → 0` limit to within rounding (`P(0 < T ≤ s) ≤ ν/2` for every finite `s`, so the
/// CDF is `1/2` and the quantile `±∞`), and `ν/2` could otherwise underflow to zero.
const MIN_DOF: f64 = 1e-300;

/// Arguments at or above this go through the Stirling series in [`ln_beta`].
const STIRLING_MIN: f64 = 10.0;

/// Student's t cumulative distribution function `P(T ≤ t)` for `dof` degrees of freedom.
///
/// `dof` may be any real number `> 0`; `dof = ∞` gives the standard normal CDF. Both
/// tails keep their relative precision (errors below about `5e-14` against 50-digit
/// references for `|t|` up to `1e50`), so a far tail such as `student_t_cdf(-40.0, 30.0)`
/// comes out with 13 or more correct digits instead of being lost to `1 - (1 - tiny)`.
///
/// Returns NaN when `t` or `dof` is NaN or `dof ≤ 0`; `t = ±∞` gives `1`/`0`.
// Only the tests call the cdf (to check the quantile against it); the runs need quantiles.
#[cfg(test)]
pub(crate) fn student_t_cdf(t: f64, dof: f64) -> f64 {
    if t.is_nan() || dof.is_nan() || dof <= 0.0 {
        return f64::NAN;
    }
    if dof == f64::INFINITY {
        return super::normal::normal_cdf(t);
    }
    if t == 0.0 {
        return 0.5;
    }
    let tails = Tails::at(t.abs(), dof.max(MIN_DOF));
    if t < 0.0 {
        tails.upper
    } else {
        0.5 + tails.central
    }
}

/// Student's t quantile function: the `t` with `P(T ≤ t) = p` for `dof` degrees of freedom.
///
/// `dof` may be any real number `> 0`; `dof = ∞` gives the standard normal quantile, and
/// `dof = 1` (Cauchy) and `dof = 2` use their closed forms. Otherwise the result is refined
/// by a safeguarded Newton iteration on the CDF with a fixed iteration cap, so it always
/// terminates; it agrees with high-precision references to about `1e-14` relative for `p`
/// in `[1e-12, 1 - 1e-12]` and `dof` from `0.5` to `1e7`.
///
/// For a two-sided confidence interval at level `c` use `p = (1 + c) / 2`.
///
/// Follows scipy's conventions at the edges: `p = 0` gives `-∞`, `p = 1` gives `+∞`, and
/// NaN, `p` outside `[0, 1]` or `dof ≤ 0` gives NaN.
pub(crate) fn student_t_quantile(p: f64, dof: f64) -> f64 {
    if p.is_nan() || !(0.0..=1.0).contains(&p) || dof.is_nan() || dof <= 0.0 {
        return f64::NAN;
    }
    if p == 0.0 {
        return f64::NEG_INFINITY;
    }
    if p == 1.0 {
        return f64::INFINITY;
    }
    if dof == f64::INFINITY {
        return normal_quantile(p);
    }
    // By symmetry solve for the smaller tail `q`; `1 - p` is exact for p ≥ 1/2.
    let (q, sign) = if p < 0.5 { (p, -1.0) } else { (1.0 - p, 1.0) };
    sign * student_t_upper_quantile(q, dof)
}

/// The `s >= 0` with `P(T > s) = q` for `q` in `(0, 1/2]` and finite `dof > 0` (or
/// infinite: the normal's): what a two-sided interval at level `c` needs with `q = (1 - c)
/// / 2`, which keeps the tail that `(1 + c) / 2` would round away for `c` near 1.
pub(crate) fn student_t_upper_quantile(q: f64, dof: f64) -> f64 {
    if q.is_nan() || !(q > 0.0 && q <= 0.5) || dof.is_nan() || dof <= 0.0 {
        return f64::NAN;
    }
    if q == 0.5 {
        return 0.0;
    }
    if dof == f64::INFINITY {
        return -normal_quantile(q);
    }
    if dof == 1.0 {
        cauchy_upper_quantile(q)
    } else if dof == 2.0 {
        dof2_upper_quantile(q)
    } else {
        solve_upper_quantile(q, dof.max(MIN_DOF))
    }
}

/// `P(T > s)` and `P(0 < T ≤ s)` for some `s ≥ 0`; they add up to `1/2`.
#[derive(Clone, Copy, Debug)]
struct Tails {
    upper: f64,
    central: f64,
}

impl Tails {
    fn from_upper(upper: f64) -> Self {
        Self {
            upper,
            central: 0.5 - upper,
        }
    }

    fn from_central(central: f64) -> Self {
        Self {
            upper: 0.5 - central,
            central,
        }
    }

    /// Both parts at `s > 0` (possibly `+∞`) for finite `nu > 0`, the small one computed
    /// directly.
    fn at(s: f64, nu: f64) -> Self {
        if s == f64::INFINITY {
            return Self::from_upper(0.0);
        }
        if nu == 1.0 {
            cauchy_tails(s)
        } else if nu == 2.0 {
            dof2_tails(s)
        } else if nu > ASYMPTOTIC_DOF {
            large_dof_tails(s, nu)
        } else {
            beta_tails(s, nu)
        }
    }
}

/// Cauchy: `P(T > s) = atan(1/s)/π`, `P(0 < T ≤ s) = atan(s)/π`.
fn cauchy_tails(s: f64) -> Tails {
    if s <= 1.0 {
        Tails::from_central(libm::atan(s) * FRAC_1_PI)
    } else if s < 1e8 {
        Tails::from_upper(libm::atan(1.0 / s) * FRAC_1_PI)
    } else {
        // atan(u) = u (1 - u²/3 + …) and u² < 1e-16 here; `1/s` could go subnormal.
        Tails::from_upper(FRAC_1_PI / s)
    }
}

/// `ν = 2`: `P(0 < T ≤ s) = s / (2√(2 + s²))`, and the upper tail
/// `1/2 - s/(2r) = 1 / (r (r + s))` with `r = √(2 + s²)`, which does not cancel.
fn dof2_tails(s: f64) -> Tails {
    let r = libm::hypot(s, SQRT_2);
    if s <= 1.0 {
        Tails::from_central(0.5 * s / r)
    } else {
        Tails::from_upper((1.0 / r) / (r + s))
    }
}

/// Large `ν`: `P(T > s) = 1 - Φ(s) + φ(s) (g₁(s)/ν + g₂(s)/ν² + g₃(s)/ν³ + O(ν⁻⁴))`.
///
/// The polynomials come from expanding the density `f_ν / φ` in `1/ν` and integrating
/// term by term (done symbolically). The relative size of the `k`-th term is about
/// `(s⁴/4ν)^k / k!`, so for `ν > 1e10` the truncation error is below `1e-18` for all
/// `s < 40`.
fn large_dof_tails(s: f64, nu: f64) -> Tails {
    // Beyond this P(T > s) < 1e-340 for every ν > 1e10, i.e. zero in f64.
    if s >= 40.0 {
        return Tails::from_upper(0.0);
    }
    let s2 = s * s;
    let g1 = s * (s2 + 1.0) / 4.0;
    let g2 = s * (((3.0 * s2 - 7.0) * s2 - 5.0) * s2 - 3.0) / 96.0;
    let g3 = s * (((((s2 - 11.0) * s2 + 14.0) * s2 + 6.0) * s2 - 3.0) * s2 - 15.0) / 384.0;
    let inv = 1.0 / nu;
    let phi = FRAC_1_SQRT_2PI * libm::exp(-0.5 * s2);
    let correction = phi * inv * (g1 + inv * (g2 + inv * g3));
    if s <= 1.0 {
        Tails::from_central(0.5 * libm::erf(s * FRAC_1_SQRT_2) - correction)
    } else {
        Tails::from_upper(normal_sf(s) + correction)
    }
}

/// `x = ν/(ν + s²)` and `y = 1 - x = s²/(ν + s²)` with their logarithms, all formed
/// without cancellation, overflow of `s²` or underflow of `s²/ν`.
#[derive(Clone, Copy, Debug)]
struct BetaArgs {
    x: f64,
    y: f64,
    ln_x: f64,
    ln_y: f64,
}

impl BetaArgs {
    fn new(s: f64, nu: f64) -> Self {
        if s * s <= nu {
            let r = s * s / nu;
            let l1p = libm::log1p(r);
            let ln_r = if r >= f64::MIN_POSITIVE {
                libm::log(r)
            } else {
                2.0 * libm::log(s) - libm::log(nu)
            };
            Self {
                x: 1.0 / (1.0 + r),
                y: r / (1.0 + r),
                ln_x: -l1p,
                ln_y: ln_r - l1p,
            }
        } else {
            // Divide twice so `s²` never overflows.
            let rho = nu / s / s;
            let l1p = libm::log1p(rho);
            let ln_rho = if rho >= f64::MIN_POSITIVE {
                libm::log(rho)
            } else {
                libm::log(nu) - 2.0 * libm::log(s)
            };
            Self {
                x: rho / (1.0 + rho),
                y: 1.0 / (1.0 + rho),
                ln_x: ln_rho - l1p,
                ln_y: -l1p,
            }
        }
    }
}

/// The general case through the incomplete beta function, `a = ν/2`, `b = 1/2`.
fn beta_tails(s: f64, nu: f64) -> Tails {
    let a = 0.5 * nu;
    let args = BetaArgs::new(s, nu);
    // x^a y^b / B(a, b), shared by I_x(a, b) and I_y(b, a).
    let front = libm::exp(a * args.ln_x + 0.5 * args.ln_y - ln_beta(a, 0.5));
    // The continued fraction for I_x(a, b) converges fast for x < (a+1)/(a+b+2), i.e.
    // y > 3/(ν+5); on the other side use the one for I_y(b, a) instead.
    if args.y * (nu + 5.0) > 3.0 {
        Tails::from_upper(0.5 * front / (a * beta_cf(a, 0.5, args.x, args.y)))
    } else {
        Tails::from_central(0.5 * front / (0.5 * beta_cf(0.5, a, args.y, args.x)))
    }
}

/// `cf` with `I_x(a, b) = x^a y^b / (a B(a, b)) / cf`, `y = 1 - x`, for
/// `x < (a+1)/(a+b+2)`.
///
/// The classical fraction is `cf = 1 + d₁/(1 + d₂/(1 + …))` with
/// `d₂ₘ₊₁ = -(a+m)(a+b+m) x / ((a+2m)(a+2m+1))` and `d₂ₘ = m(b-m) x / ((a+2m-1)(a+2m))`.
/// This evaluates its even contraction
/// `cf = β₀ + α₁/(β₁ + α₂/(β₂ + …))`, `βₘ = 1 + d₂ₘ + d₂ₘ₊₁` (`d₀ = 0`),
/// `αₘ = -d₂ₘ₋₁ d₂ₘ`, by the modified Lentz method. The point of the contraction is
/// `1 + d₂ₘ₊₁`: for large `a` and `x` near 1 it is a difference of nearly equal numbers,
/// which magnifies the rounding of `x` by about `a y`. Written as
/// `(a(2m+1-b) + m(3m+2-b) + (a+m)(a+b+m) y) / ((a+2m)(a+2m+1))` it has no cancellation
/// whenever the first two terms are not negative (always so for `b ≤ 1`), and it is
/// evaluated that way then.
///
/// With `b = 1/2` or `a = 1/2`, as used here, it takes at most about 60 steps for any
/// `ν` from `0.01` to `1e20` (measured over `s` from `1e-10` to `1e300`); the cap only
/// guarantees termination.
fn beta_cf(a: f64, b: f64, x: f64, y: f64) -> f64 {
    // Stands in for a zero denominator, which would otherwise stop Lentz's recurrence.
    const TINY: f64 = 1e-300;
    const MAX_STEPS: usize = 1000;
    // βₘ without its `d₂ₘ` part: 1 + d₂ₘ₊₁.
    // Every product below is formed as a product of ratios so nothing overflows even for
    // `a` near f64::MAX.
    let one_plus_odd = |m: f64| {
        let coefficient = (a + m) / (a + 2.0 * m) * ((a + b + m) / (a + 2.0 * m + 1.0));
        let rest = ((2.0 * m + 1.0 - b) * (a / (a + 2.0 * m))
            + m * (3.0 * m + 2.0 - b) / (a + 2.0 * m))
            / (a + 2.0 * m + 1.0);
        if rest >= 0.0 {
            rest + coefficient * y
        } else {
            1.0 - coefficient * x
        }
    };
    let tiny_guard = |v: f64| if v.abs() < TINY { TINY } else { v };
    let mut value = tiny_guard(one_plus_odd(0.0));
    let mut c = value;
    let mut d = 0.0;
    for step in 1..=MAX_STEPS {
        let m = step as f64;
        // The integer parts are grouped first so that a tiny `a` is not rounded away in
        // `(a + m - 1) / (a + 2m - 2)`, which is `a / a` at m = 1.
        let odd_before = -(a + (m - 1.0)) / (a + (2.0 * m - 2.0))
            * ((a + b + (m - 1.0)) / (a + (2.0 * m - 1.0)))
            * x;
        let even = m * (b - m) / (a + (2.0 * m - 1.0)) * (x / (a + 2.0 * m));
        let alpha = -odd_before * even;
        let beta = one_plus_odd(m) + even;
        d = 1.0 / tiny_guard(beta + alpha * d);
        c = tiny_guard(beta + alpha / c);
        let delta = c * d;
        value *= delta;
        if (delta - 1.0).abs() <= f64::EPSILON {
            break;
        }
    }
    value
}

/// `ln B(a, b) = ln Γ(a) + ln Γ(b) - ln Γ(a + b)` for `a, b > 0`.
///
/// When the larger argument is big, `ln Γ(a + b) - ln Γ(large)` is evaluated from the
/// Stirling series directly, so the result stays accurate in absolute terms even for
/// `ν = 10¹⁰`, where the individual log-gammas are near `10¹¹`.
fn ln_beta(a: f64, b: f64) -> f64 {
    let (small, large) = if a < b { (a, b) } else { (b, a) };
    if large < STIRLING_MIN {
        return libm::lgamma(a) + libm::lgamma(b) - libm::lgamma(a + b);
    }
    let sum = large + small;
    // ln Γ(L+S) - ln Γ(L) = (L - 1/2) ln(1 + S/L) + S (ln(L+S) - 1) + δ(L+S) - δ(L).
    let ln_ratio = (large - 0.5) * libm::log1p(small / large)
        + small * (libm::log(sum) - 1.0)
        + (stirling_remainder(sum) - stirling_remainder(large));
    libm::lgamma(small) - ln_ratio
}

/// `δ(x) = ln Γ(x) - ((x - 1/2) ln x - x + ln(2π)/2)` for `x ≥ 10`, from the Bernoulli
/// series; the first omitted term is below `3e-17` at `x = 10`.
fn stirling_remainder(x: f64) -> f64 {
    let inv = 1.0 / x;
    let inv2 = inv * inv;
    inv * (1.0 / 12.0
        - inv2
            * (1.0 / 360.0
                - inv2
                    * (1.0 / 1260.0
                        - inv2
                            * (1.0 / 1680.0
                                - inv2
                                    * (1.0 / 1188.0 - inv2 * (691.0 / 360_360.0 - inv2 / 156.0))))))
}

/// The logarithm of the Student t density at `s`, with `ln_b = ln B(ν/2, 1/2)`:
/// `ln((1 + s²/ν)^(-(ν+1)/2) / (√ν B(ν/2, 1/2)))`. Kept as a logarithm because far in a
/// heavy tail the density itself underflows long before the tail probability does.
fn ln_density(s: f64, nu: f64, ln_b: f64) -> f64 {
    let args = BetaArgs::new(s, nu);
    0.5 * (nu + 1.0) * args.ln_x - 0.5 * libm::log(nu) - ln_b
}

/// Cauchy: the `s > 0` with `atan(1/s)/π = q`, `0 < q < 1/2`.
fn cauchy_upper_quantile(q: f64) -> f64 {
    if q < 1e-8 {
        // 1/tan(πq) = 1/(πq) - πq/3 - …; avoids forming a subnormal `πq`.
        FRAC_1_PI / q - PI * q / 3.0
    } else if q < 0.25 {
        1.0 / libm::tan(PI * q)
    } else {
        // Exact difference (Sterbenz), and tan is well conditioned below π/4.
        libm::tan(PI * (0.5 - q))
    }
}

/// `ν = 2`: solving `1/(r(r+s)) = 2q` gives `s = (1 - 2q) / √(2q(1 - q))`.
fn dof2_upper_quantile(q: f64) -> f64 {
    (1.0 - 2.0 * q) / libm::sqrt(2.0 * q * (1.0 - q))
}

/// The `s > 0` with `P(T > s) = q` for `0 < q < 1/2` and finite `nu ∉ {1, 2}`.
fn solve_upper_quantile(q: f64, nu: f64) -> f64 {
    // Newton converges quadratically from the starting guess (measured: at most 6 steps
    // over ν in [0.01, 1e14] and q in [1e-300, 1/2)); the cap only matters if rounding
    // noise keeps the steps from getting small, and then bisection has long converged.
    const MAX_ITERATIONS: usize = 100;
    // A Newton step this small leaves an error of about its square: done.
    const STEP_TOLERANCE: f64 = 1e-12;

    let ln_b = ln_beta(0.5 * nu, 0.5);
    let z = -normal_quantile(q);
    // T = Z / U with U = √(χ²_ν / ν) independent of Z and E[U²] = 1. P(|Z| > s u) is
    // convex in u, so by Jensen P(|T| > s) ≥ P(|Z| > s E[U]) ≥ P(|Z| > s) (E[U] ≤ 1): the
    // root is at least `z`. The factor leaves room for rounding when ν is so large that
    // the two coincide.
    let mut lo = 0.999 * z;
    let power_law = power_law_quantile(q, nu, ln_b);
    // `power_law` solves an upper bound of the tail, so it bounds the root from above;
    // the factor 2 keeps it a bound after rounding.
    let mut hi = 2.0 * power_law;
    if !hi.is_finite() {
        // Possible for small ν: the quantile may be beyond the largest float.
        if Tails::at(f64::MAX, nu).upper >= q {
            return f64::INFINITY;
        }
        hi = f64::MAX;
    }
    let mut s = initial_guess(z, nu, power_law).max(lo).min(hi);
    for _ in 0..MAX_ITERATIONS {
        let tails = Tails::at(s, nu);
        // P(T > s) - q without cancellation: near q = 1/2 compare the central parts.
        let diff = if q >= 0.25 {
            (0.5 - q) - tails.central
        } else {
            tails.upper - q
        };
        if diff == 0.0 {
            return s;
        }
        if diff > 0.0 {
            lo = s;
        } else {
            hi = s;
        }
        // Newton in the variable ln s on the log of the part compared, where both ends are
        // nearly straight lines: ln P(T > s) in heavy (power-law) tails, ln P(0 < T ≤ s)
        // near the centre. d ln P / d ln s = ∓ s f(s) / P, formed in logs because far in a
        // heavy tail f(s) underflows before P does.
        let ln_s_f = libm::log(s) + ln_density(s, nu, ln_b);
        let step = if q >= 0.25 {
            let slope = libm::exp(ln_s_f - libm::log(tails.central));
            -libm::log1p(-diff / (0.5 - q)) / slope
        } else {
            let slope = libm::exp(ln_s_f - libm::log(tails.upper));
            libm::log1p(diff / q) / slope
        };
        let next = s * libm::exp(step);
        if step.abs() <= STEP_TOLERANCE {
            return next;
        }
        // Keep to the bracket; outside it (or on NaN) bisect in ln s, lo > 0 and hi finite.
        s = if next > lo && next < hi {
            next
        } else {
            libm::sqrt(lo) * libm::sqrt(hi)
        };
    }
    s
}

/// The root of the power-law bound of the tail,
/// `P(T > s) ≤ ν^(ν/2 - 1) s^(-ν) / B(ν/2, 1/2)` (from `1 + s²/ν ≥ s²/ν` in the density):
/// `√ν (q ν B(ν/2, 1/2))^(-1/ν)`. Its relative error is about `(ν + 1) / (2 s²)`.
fn power_law_quantile(q: f64, nu: f64, ln_b: f64) -> f64 {
    let ln_nu = libm::log(nu);
    libm::exp(0.5 * ln_nu - (libm::log(q) + ln_nu + ln_b) / nu)
}

/// A starting point for [`solve_upper_quantile`] from the normal quantile `z > 0` and the
/// power-law root.
///
/// Far in the tail compared to `√ν` the power law is within 10%; otherwise the
/// Cornish–Fisher series around the normal quantile (Abramowitz & Stegun 26.7.5) is the
/// better guess, as long as it lands between the two bounds `z` and `power_law`.
fn initial_guess(z: f64, nu: f64, power_law: f64) -> f64 {
    if power_law * power_law >= 5.0 * (nu + 1.0) {
        return power_law;
    }
    let z2 = z * z;
    let g1 = z * (z2 + 1.0) / 4.0;
    let g2 = z * ((5.0 * z2 + 16.0) * z2 + 3.0) / 96.0;
    let g3 = z * (((3.0 * z2 + 19.0) * z2 + 17.0) * z2 - 15.0) / 384.0;
    let g4 = z * ((((79.0 * z2 + 776.0) * z2 + 1482.0) * z2 - 1920.0) * z2 - 945.0) / 92160.0;
    let inv = 1.0 / nu;
    let cornish_fisher = z + inv * (g1 + inv * (g2 + inv * (g3 + inv * g4)));
    if cornish_fisher > z && cornish_fisher < power_law {
        cornish_fisher
    } else {
        libm::sqrt(z) * libm::sqrt(power_law)
    }
}

#[cfg(test)]
mod tests {
    use super::super::normal::normal_cdf;
    use super::*;

    /// scipy 1.17.1's `t.ppf`/`t.cdf` agree with 50-digit mpmath to 1e-14 on this table,
    /// and so does this module; 1e-12 leaves room for both while a real defect (a lost
    /// tail, a wrong branch, a stalled iteration) shows up at 1e-8 or worse.
    const REL_TOL: f64 = 1e-12;

    fn rel_err(got: f64, want: f64) -> f64 {
        if got == want {
            0.0
        } else {
            ((got - want) / want).abs()
        }
    }

    // (dof, p, t = t.ppf(p, dof), t.cdf(t, dof)) from
    // python3 -c "from scipy.stats import t; [print(f'({float(d)!r}, {p!r}, {float(t.ppf(p, d))!r}, {float(t.cdf(t.ppf(p, d), d))!r}),') for d in (1, 2, 3, 4, 5, 7, 10, 30, 100, 1e6, 0.5, 2.5) for p in (1e-10, 0.005, 0.025, 0.05, 0.5, 0.9, 0.95, 0.975, 0.995, 0.9995)]"
    const TABLE: [(f64, f64, f64, f64); 120] = [
        (1.0, 1e-10, -3183098861.8379064, 1e-10),
        (1.0, 0.005, -63.65674116287158, 0.005),
        (1.0, 0.025, -12.706204736174705, 0.025),
        (1.0, 0.05, -6.313751514675044, 0.04999999999999999),
        (1.0, 0.5, 0.0, 0.5),
        (1.0, 0.9, 3.0776835371752544, 0.9),
        (1.0, 0.95, 6.313751514675037, 0.95),
        (1.0, 0.975, 12.706204736174694, 0.975),
        (1.0, 0.995, 63.656741162871526, 0.995),
        (1.0, 0.9995, 636.6192487687897, 0.9995),
        (2.0, 1e-10, -70710.67810804816, 9.999999999999998e-11),
        (2.0, 0.005, -9.924843200918293, 0.005),
        (2.0, 0.025, -4.302652729749464, 0.025),
        (2.0, 0.05, -2.9199855803537256, 0.05000000000000001),
        (2.0, 0.5, 0.0, 0.5),
        (2.0, 0.9, 1.8856180831641272, 0.9),
        (2.0, 0.95, 2.9199855803537242, 0.95),
        (2.0, 0.975, 4.302652729749462, 0.975),
        (2.0, 0.995, 9.924843200918287, 0.995),
        (2.0, 0.9995, 31.599054576445365, 0.9995),
        (3.0, 1e-10, -2225.769284683093, 1.0000000000000002e-10),
        (3.0, 0.005, -5.840909309733357, 0.005000000000000002),
        (3.0, 0.025, -3.1824463052837086, 0.02500000000000001),
        (3.0, 0.05, -2.353363434801824, 0.04999999999999999),
        (3.0, 0.5, 0.0, 0.5),
        (3.0, 0.9, 1.637744353696209, 0.9),
        (3.0, 0.95, 2.3533634348018233, 0.95),
        (3.0, 0.975, 3.1824463052837078, 0.975),
        (3.0, 0.995, 5.840909309733355, 0.995),
        (3.0, 0.9995, 12.923978636687961, 0.9995),
        (4.0, 1e-10, -416.1751403296041, 9.999999999999998e-11),
        (4.0, 0.005, -4.604094871349993, 0.005000000000000001),
        (4.0, 0.025, -2.7764451051977943, 0.024999999999999988),
        (4.0, 0.05, -2.131846786326651, 0.04999999999999998),
        (4.0, 0.5, 0.0, 0.5),
        (4.0, 0.9, 1.533206274058944, 0.9),
        (4.0, 0.95, 2.1318467863266495, 0.95),
        (4.0, 0.975, 2.7764451051977934, 0.975),
        (4.0, 0.995, 4.604094871349992, 0.995),
        (4.0, 0.9995, 8.610301581379522, 0.9995),
        (5.0, 1e-10, -156.82559270889433, 9.999999999999995e-11),
        (5.0, 0.005, -4.032142983555229, 0.004999999999999996),
        (5.0, 0.025, -2.5705818356363155, 0.02499999999999999),
        (5.0, 0.05, -2.015048373333024, 0.050000000000000086),
        (5.0, 0.5, 0.0, 0.5),
        (5.0, 0.9, 1.4758840488244815, 0.9),
        (5.0, 0.95, 2.0150483733330233, 0.95),
        (5.0, 0.975, 2.5705818356363146, 0.975),
        (5.0, 0.995, 4.032142983555228, 0.995),
        (5.0, 0.9995, 6.868826625881276, 0.9995),
        (7.0, 1e-10, -53.83557948467374, 9.999999999999995e-11),
        (7.0, 0.005, -3.4994832973504932, 0.005),
        (7.0, 0.025, -2.3646242515927844, 0.025000000000000033),
        (7.0, 0.05, -1.8945786050900066, 0.05),
        (7.0, 0.5, 0.0, 0.5),
        (7.0, 0.9, 1.4149239276505086, 0.9),
        (7.0, 0.95, 1.8945786050900062, 0.95),
        (7.0, 0.975, 2.364624251592784, 0.975),
        (7.0, 0.995, 3.4994832973504924, 0.995),
        (7.0, 0.9995, 5.407882520861828, 0.9995),
        (10.0, 1e-10, -25.466008021697725, 1.0000000000000003e-10),
        (10.0, 0.005, -3.1692726726169504, 0.005000000000000014),
        (10.0, 0.025, -2.2281388519862753, 0.02499999999999996),
        (10.0, 0.05, -1.812461122811676, 0.050000000000000044),
        (10.0, 0.5, 0.0, 0.5),
        (10.0, 0.9, 1.372183641110336, 0.9),
        (10.0, 0.95, 1.8124611228116756, 0.95),
        (10.0, 0.975, 2.228138851986274, 0.975),
        (10.0, 0.995, 3.16927267261695, 0.995),
        (10.0, 0.9995, 4.586893858702708, 0.9995),
        (30.0, 1e-10, -9.377489780407144, 1e-10),
        (30.0, 0.005, -2.749995653567226, 0.004999999999999992),
        (30.0, 0.025, -2.042272456301238, 0.024999999999999988),
        (30.0, 0.05, -1.6972608865939574, 0.05000000000000005),
        (30.0, 0.5, 0.0, 0.5),
        (30.0, 0.9, 1.3104150253913955, 0.9),
        (30.0, 0.95, 1.697260886593957, 0.95),
        (30.0, 0.975, 2.0422724563012378, 0.975),
        (30.0, 0.995, 2.7499956535672254, 0.995),
        (30.0, 0.9995, 3.6459586350420627, 0.9995),
        (100.0, 1e-10, -7.083375481400722, 9.99999999999994e-11),
        (100.0, 0.005, -2.6258905214380173, 0.0050000000000000105),
        (100.0, 0.025, -1.983971518523552, 0.025000000000000012),
        (100.0, 0.05, -1.6602343260853396, 0.049999999999999996),
        (100.0, 0.5, 0.0, 0.5),
        (100.0, 0.9, 1.290074761346516, 0.9),
        (100.0, 0.95, 1.6602343260853392, 0.95),
        (100.0, 0.975, 1.9839715185235518, 0.975),
        (100.0, 0.995, 2.6258905214380173, 0.995),
        (100.0, 0.9995, 3.390491311164263, 0.9995),
        (1000000.0, 1e-10, -6.361406848876743, 1.0000000000000011e-10),
        (1000000.0, 0.005, -2.5758342201053344, 0.005000000000000003),
        (1000000.0, 0.025, -1.9599663568141072, 0.025000000000000005),
        (1000000.0, 0.05, -1.6448551507220406, 0.050000000000000044),
        (1000000.0, 0.5, 0.0, 0.5),
        (1000000.0, 0.9, 1.281552412129939, 0.9),
        (1000000.0, 0.95, 1.6448551507220404, 0.95),
        (1000000.0, 0.975, 1.959966356814107, 0.975),
        (1000000.0, 0.995, 2.5758342201053344, 0.995),
        (1000000.0, 0.9995, 3.2905364612487222, 0.9995),
        (0.5, 1e-10, -1.02849115631634e+19, 1e-10),
        (0.5, 0.005, -4113.964588804181, 0.004999999999999999),
        (0.5, 0.025, -164.55767348048846, 0.025000000000000005),
        (0.5, 0.05, -41.13600009287826, 0.05),
        (0.5, 0.5, 0.0, 0.5),
        (0.5, 0.9, 10.27032441023451, 0.9),
        (0.5, 0.95, 41.13600009287819, 0.95),
        (0.5, 0.975, 164.55767348048818, 0.975),
        (0.5, 0.995, 4113.964588804174, 0.995),
        (0.5, 0.9995, 411396.462526262, 0.9995),
        (2.5, 1e-10, -8765.437771364572, 9.999999999999999e-11),
        (2.5, 0.005, -7.163728138948786, 0.004999999999999999),
        (2.5, 0.025, -3.5746548420036834, 0.024999999999999998),
        (2.5, 0.05, -2.5582186141359364, 0.049999999999999996),
        (2.5, 0.5, 0.0, 0.5),
        (2.5, 0.9, 1.7302509288071766, 0.8999999999999999),
        (2.5, 0.95, 2.5582186141359355, 0.95),
        (2.5, 0.975, 3.5746548420036817, 0.975),
        (2.5, 0.995, 7.163728138948783, 0.995),
        (2.5, 0.9995, 18.277893528131457, 0.9995),
    ];

    // (a, ln B(a, 1/2)) from
    // python3 -c "from scipy.special import betaln; [print(f'({a!r}, {float(betaln(a, 0.5))!r}),') for a in (0.25, 1.5, 5.0, 9.999, 10.0, 50.0, 5e9)]"
    // (a = 5e5 is left out: there scipy's betaln itself is only good to 3.5e-11.)
    const LN_BETA_TABLE: [(f64, f64); 7] = [
        (0.25, 1.6571065161914822),
        (1.5, 0.4515827052894547),
        (5.0, -0.20739519434607073),
        (9.999, -0.5663815453274939),
        (10.0, -0.566432796397594),
        (50.0, -1.381146601451041),
        (5000000000.0, -10.593986931740554),
    ];

    const DOFS: [f64; 16] = [
        0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 7.0, 10.0, 29.0, 30.0, 100.0, 1e6, 1e7,
    ];

    #[test]
    fn quantile_matches_scipy() {
        for (dof, p, t, _) in TABLE {
            let got = student_t_quantile(p, dof);
            assert!(
                rel_err(got, t) <= REL_TOL,
                "quantile({p}, {dof}) = {got:e}, want {t:e}"
            );
        }
    }

    #[test]
    fn cdf_matches_scipy() {
        for (dof, _, t, cdf) in TABLE {
            let got = student_t_cdf(t, dof);
            assert!(
                rel_err(got, cdf) <= REL_TOL,
                "cdf({t}, {dof}) = {got:e}, want {cdf:e}"
            );
        }
    }

    #[test]
    fn ln_beta_matches_scipy() {
        for (a, want) in LN_BETA_TABLE {
            let got = ln_beta(a, 0.5);
            assert!(
                rel_err(got, want) <= REL_TOL,
                "ln B({a}, 1/2) = {got}, want {want}"
            );
            assert_eq!(ln_beta(0.5, a), got);
        }
    }

    #[test]
    fn cdf_inverts_quantile() {
        let mut ps = vec![
            1e-12, 1e-10, 1e-6, 1e-3, 0.005, 0.025, 0.05, 0.1, 0.25, 0.3, 0.45,
        ];
        ps.extend([0.499, 0.4999999, 0.5 - 1e-12]);
        for dof in DOFS {
            for p in ps.iter().flat_map(|&p| [p, 1.0 - p]) {
                let t = student_t_quantile(p, dof);
                // Compare the small tail, P(T ≤ -|t|), against min(p, 1 - p): exact for
                // p > 1/2, and the quantity that is known to full relative precision.
                let tail = student_t_cdf(-t.abs(), dof);
                let want = p.min(1.0 - p);
                assert!(
                    rel_err(tail, want) <= REL_TOL,
                    "dof {dof}, p {p}: t = {t:e}, tail {tail:e}"
                );
                assert_eq!(t < 0.0, p < 0.5);
            }
        }
    }

    #[test]
    fn quantile_is_increasing_and_odd() {
        for dof in DOFS {
            let mut previous = f64::NEG_INFINITY;
            for k in 1..1024 {
                let p = f64::from(k) / 1024.0;
                let t = student_t_quantile(p, dof);
                assert!(t > previous, "dof {dof}, p {p}: {t} after {previous}");
                // Dyadic p: 1 - p is exact, so the two sides take mirrored paths.
                assert_eq!(student_t_quantile(1.0 - p, dof), -t, "dof {dof}, p {p}");
                previous = t;
            }
        }
    }

    #[test]
    fn cdf_halves_add_up() {
        for dof in DOFS {
            for i in 0..=400 {
                let t = f64::from(i) * 0.05;
                let sum = student_t_cdf(t, dof) + student_t_cdf(-t, dof);
                assert!(
                    (sum - 1.0).abs() <= 4.0 * f64::EPSILON,
                    "dof {dof}, t {t}: {sum}"
                );
            }
        }
    }

    #[test]
    fn closed_forms_agree_with_the_general_method() {
        // dof = 1 and 2 take closed forms; a dof a hair away takes the incomplete beta
        // function and the Newton iteration. The true difference is below 1e-10.
        for dof in [1.0, 2.0] {
            let nearby = dof * (1.0 + 1e-12);
            for p in [1e-10, 1e-4, 0.025, 0.2, 0.3, 0.45, 0.55, 0.975] {
                let (exact, general) = (student_t_quantile(p, dof), student_t_quantile(p, nearby));
                assert!(rel_err(general, exact) <= 1e-9, "dof {dof}, p {p}");
            }
            for t in [-1e8, -1e3, -5.0, -1.5, -0.3, 0.2, 1.0, 4.0] {
                let (exact, general) = (student_t_cdf(t, dof), student_t_cdf(t, nearby));
                assert!(rel_err(general, exact) <= 1e-9, "dof {dof}, t {t}");
            }
        }
        // Cauchy quantile in closed form: tan(π(p - 1/2)).
        assert!((student_t_quantile(0.75, 1.0) - 1.0).abs() <= 2.0 * f64::EPSILON);
        // dof = 2: t = (2p - 1) / √(2p(1 - p)); at p = 0.9 that is 0.8 / √0.18.
        let want = 0.8 / 0.18_f64.sqrt();
        assert!(rel_err(student_t_quantile(0.9, 2.0), want) <= 4.0 * f64::EPSILON);
    }

    #[test]
    fn large_dof_switch_is_continuous() {
        // Just below ASYMPTOTIC_DOF the continued fraction, just above it the series.
        let below = ASYMPTOTIC_DOF;
        let above = ASYMPTOTIC_DOF.next_up();
        for t in [-37.0, -20.0, -8.0, -3.0, -1.7, -1.0, -0.5, -1e-3, 0.3, 2.0] {
            let (a, b) = (student_t_cdf(t, below), student_t_cdf(t, above));
            assert!(rel_err(b, a) <= 1e-13, "t {t}: {a:e} vs {b:e}");
        }
        let (a, b) = (
            student_t_quantile(1e-10, below),
            student_t_quantile(1e-10, above),
        );
        assert!(rel_err(b, a) <= 1e-13, "{a} vs {b}");
    }

    #[test]
    fn infinite_dof_is_the_normal_distribution() {
        for t in [-38.0, -8.0, -1.0, 0.0, 0.5, 3.0, 8.0] {
            assert_eq!(student_t_cdf(t, f64::INFINITY), normal_cdf(t));
        }
        for p in [1e-300, 1e-10, 0.025, 0.5, 0.975, 1.0 - 1e-10] {
            assert_eq!(student_t_quantile(p, f64::INFINITY), normal_quantile(p));
        }
        // And huge finite dof get there continuously (the leading difference is about
        // t⁴/(4 dof) relative, 4e-15 at t = -20 for dof = 1e20).
        for dof in [1e20, 1e100, f64::MAX] {
            for t in [-20.0, -1.0, 0.5, 3.0] {
                let (got, want) = (student_t_cdf(t, dof), normal_cdf(t));
                assert!(rel_err(got, want) <= 1e-10, "dof {dof}, t {t}");
            }
            let (got, want) = (student_t_quantile(0.025, dof), normal_quantile(0.025));
            assert!(rel_err(got, want) <= 1e-10, "dof {dof}");
        }
    }

    #[test]
    fn invalid_input_gives_nan() {
        for dof in [0.0, -1.0, -0.0, f64::NEG_INFINITY, f64::NAN] {
            assert!(student_t_cdf(1.0, dof).is_nan(), "dof {dof}");
            assert!(student_t_quantile(0.3, dof).is_nan(), "dof {dof}");
        }
        assert!(student_t_cdf(f64::NAN, 3.0).is_nan());
        for p in [
            f64::NAN,
            -5e-324,
            -0.5,
            1.0 + f64::EPSILON,
            2.0,
            f64::INFINITY,
        ] {
            assert!(student_t_quantile(p, 3.0).is_nan(), "p {p}");
            assert!(student_t_quantile(p, 1.0).is_nan(), "p {p}");
        }
    }

    #[test]
    fn edges_give_infinities_and_limits() {
        for dof in [0.5, 1.0, 2.0, 3.0, 1e20, f64::INFINITY] {
            assert_eq!(student_t_quantile(0.0, dof), f64::NEG_INFINITY);
            assert_eq!(student_t_quantile(1.0, dof), f64::INFINITY);
            assert_eq!(student_t_quantile(0.5, dof), 0.0);
            assert_eq!(student_t_cdf(f64::NEG_INFINITY, dof), 0.0);
            assert_eq!(student_t_cdf(f64::INFINITY, dof), 1.0);
            assert_eq!(student_t_cdf(0.0, dof), 0.5);
        }
    }

    #[test]
    fn extreme_arguments_stay_finite_and_terminate() {
        // A quantile beyond the largest float: P(T ≤ -f64::MAX) is still about 4e-4 for
        // dof = 0.01.
        assert_eq!(student_t_quantile(1e-5, 0.01), f64::NEG_INFINITY);
        assert_eq!(student_t_quantile(1.0 - 1e-5, 0.01), f64::INFINITY);
        // Far tails with heavy tails: t near 1e81, density far below f64::MIN_POSITIVE.
        let t = student_t_quantile(1e-244, 3.0);
        assert!(t.is_finite() && t < -1e80, "{t}");
        assert!(rel_err(student_t_cdf(t, 3.0), 1e-244) <= 1e-12);
        // Subnormal p and tiny dof do not hang or panic.
        for (p, dof) in [(5e-324, 3.0), (5e-324, 1e6), (1e-300, 0.5), (0.3, 1e-300)] {
            let t = student_t_quantile(p, dof);
            assert!(t < 0.0, "p {p}, dof {dof}: {t}");
        }
        assert!(student_t_cdf(-1e300, 0.5) > 0.0);
        assert!(student_t_cdf(-f64::MAX, 1e-3) > 0.0);
        assert_eq!(student_t_cdf(1e-300, 5.0), 0.5);
    }

    #[test]
    fn confidence_interval_critical_values() {
        // The use in this crate: two-sided intervals from n replicates, dof = n - 1.
        // Textbook table values (rounded to 3 decimals) as a sanity check on top of scipy.
        let cases = [
            (1.0, 0.95, 12.706),
            (2.0, 0.95, 4.303),
            (4.0, 0.99, 4.604),
            (9.0, 0.95, 2.262),
            (19.0, 0.90, 1.729),
            (29.0, 0.999, 3.659),
        ];
        for (dof, level, want) in cases {
            let t = student_t_quantile((1.0 + level) / 2.0, dof);
            assert!((t - want).abs() < 5e-4, "dof {dof}, level {level}: {t}");
        }
    }

    /// The values quoted in the function's documentation.
    #[test]
    fn student_t_cdf_examples_hold() {
        assert_eq!(student_t_cdf(0.0, 4.0), 0.5);
        // The two-sided 95% critical value for 3 degrees of freedom.
        assert!((student_t_cdf(3.1824463052837078, 3.0) - 0.975).abs() < 1e-14);
        // Cauchy: P(T ≤ -1) = 1/4.
        assert!((student_t_cdf(-1.0, 1.0) - 0.25).abs() < 1e-16);
        assert!(student_t_cdf(1.0, -2.0).is_nan());
    }

    /// The values quoted in the function's documentation.
    #[test]
    fn student_t_quantile_examples_hold() {
        // 95% two-sided interval from 4 replicates: dof = 3.
        let t = student_t_quantile(0.975, 3.0);
        assert!((t - 3.1824463052837078).abs() < 1e-13);
        // Cauchy closed form: the 3/4 quantile is tan(π/4) = 1.
        assert!((student_t_quantile(0.75, 1.0) - 1.0).abs() < 1e-15);
        assert_eq!(student_t_quantile(0.5, 7.5), 0.0);
        assert_eq!(student_t_quantile(1.0, 7.5), f64::INFINITY);
        assert!(student_t_quantile(0.5, 0.0).is_nan());
    }
}
