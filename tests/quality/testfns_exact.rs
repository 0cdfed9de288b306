//! Checks every closed-form integral in `mcint::testfns` against independent numerics.
//!
//! The reference is a tensor-product composite Gauss-Legendre rule built here from scratch
//! (nodes by Newton's method on the Legendre recurrence). Panels are split at every kink or
//! jump (`x_i = u_i` for the Genz families, `x_i = 1/2` for Roos-Arnold and Sobol' g), and
//! panels are narrowed in proportion to the largest `a_i` so that peaks are resolved. On each
//! panel the integrand is then analytic with its nearest singularity several half-widths
//! away, so the rule converges geometrically and its error is at the level of rounding
//! (about 1e-14 relative). The closed forms are good to a few ulps. Requiring agreement to
//! 1e-10 therefore leaves four orders of magnitude for rounding in sums of up to ~10^7
//! terms, while any mistake in a formula (a wrong factor, sign, index or branch) shows up as
//! a discrepancy of order 1e-6 or far larger.
//!
//! The corner peak's exact value comes from a 1-D quadrature rather than a closed form, so it
//! is also checked at d = 8, 20 and up to 1000 against exact evaluations that do not share
//! that method (see `corner_peak_high_dimension_*`).

use crate::common::SplitMix64;
use mcint::testfns::{Genz, GenzFamily, Polynomial, RoosArnold, SobolGFunction, TestFunction};

/// Nodes and weights of the n-point Gauss-Legendre rule on [-1, 1].
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let nf = n as f64;
    (0..n)
        .map(|i| {
            // Tricomi's approximation to the i-th root is close enough for Newton to converge.
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
            let mut deriv = 1.0;
            for _ in 0..100 {
                // P_n(x) and P_{n-1}(x) by the three-term recurrence.
                let (mut p_prev, mut p) = (1.0, x);
                for k in 2..=n {
                    let kf = k as f64;
                    let next = ((2.0 * kf - 1.0) * x * p - (kf - 1.0) * p_prev) / kf;
                    p_prev = p;
                    p = next;
                }
                deriv = nf * (x * p - p_prev) / (x * x - 1.0);
                let step = p / deriv;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * deriv * deriv))
        })
        .collect()
}

/// A composite rule on [0, 1]: `panels` equal panels, further split at `cuts`, with an
/// `n`-point Gauss-Legendre rule on each.
fn composite_rule(panels: usize, cuts: &[f64], n: usize) -> Vec<(f64, f64)> {
    let mut breaks: Vec<f64> = (0..=panels).map(|k| k as f64 / panels as f64).collect();
    breaks.extend(cuts.iter().copied().filter(|c| *c > 0.0 && *c < 1.0));
    breaks.sort_by(f64::total_cmp);
    breaks.dedup();
    let base = gauss_legendre(n);
    let mut rule = Vec::new();
    for w in breaks.windows(2) {
        let (lo, hi) = (w[0], w[1]);
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        rule.extend(base.iter().map(|(x, wt)| (mid + half * x, half * wt)));
    }
    rule
}

/// The tensor product of the per-axis rules applied to `f` (nested sums keep rounding low).
fn cubature(f: &dyn Fn(&[f64]) -> f64, rules: &[Vec<(f64, f64)>]) -> f64 {
    fn recurse(f: &dyn Fn(&[f64]) -> f64, rules: &[Vec<(f64, f64)>], x: &mut Vec<f64>) -> f64 {
        let axis = x.len();
        if axis == rules.len() {
            return f(x);
        }
        let mut sum = 0.0;
        for &(xi, wi) in &rules[axis] {
            x.push(xi);
            sum += wi * recurse(f, rules, x);
            x.pop();
        }
        sum
    }
    recurse(f, rules, &mut Vec::with_capacity(rules.len()))
}

/// The reference integral of a Genz integrand, with panels split at each `u_i` and sized to
/// the largest `a_i`.
fn genz_reference(g: &Genz) -> f64 {
    let a_max = g.a().iter().copied().fold(0.0, f64::max);
    let panels = 8.max((2.0 * a_max).ceil() as usize);
    let rules: Vec<_> = g
        .u()
        .iter()
        .map(|&u| composite_rule(panels, &[u], 12))
        .collect();
    cubature(&|x| g.eval(x), &rules)
}

fn assert_close(what: &str, got: f64, want: f64, rel: f64) {
    let err = (got - want).abs();
    assert!(
        err <= rel * want.abs(),
        "{what}: {got:e} vs {want:e} (relative error {:e})",
        err / want.abs()
    );
}

/// Parameter sets (a, u), truncated to the first d entries.
fn genz_parameter_sets() -> Vec<(&'static str, Vec<f64>, Vec<f64>)> {
    vec![
        ("a = 5, u = 0.3", vec![5.0; 3], vec![0.3; 3]),
        ("mixed", vec![0.7, 3.1, 9.5], vec![0.05, 0.95, 0.6]),
        (
            "u on the boundary",
            vec![2.5, 0.2, 1.0],
            vec![0.0, 1.0, 0.5],
        ),
    ]
}

#[test]
fn genz_defaults_match_cubature() {
    for family in GenzFamily::ALL {
        for d in 1..=3 {
            let g = Genz::with_defaults(family, d).unwrap();
            assert_close(
                &format!("{family:?} d={d} defaults"),
                g.exact(),
                genz_reference(&g),
                1e-10,
            );
        }
    }
}

#[test]
fn genz_other_parameters_match_cubature() {
    for family in GenzFamily::ALL {
        for (label, a, u) in genz_parameter_sets() {
            for d in 1..=3 {
                let g = Genz::new(family, a[..d].to_vec(), u[..d].to_vec()).unwrap();
                let reference = genz_reference(&g);
                assert_close(
                    &format!("{family:?} d={d} {label}"),
                    g.exact(),
                    reference,
                    1e-10,
                );
            }
        }
    }
}

#[test]
fn discontinuous_with_u1_zero_integrates_to_zero() {
    let g = Genz::new(GenzFamily::Discontinuous, vec![1.0, 2.0], vec![0.0, 0.7]).unwrap();
    assert_eq!(g.exact(), 0.0);
    assert_eq!(genz_reference(&g), 0.0);
}

/// The limits as every `a_k -> 0`, by hand from the definitions (`u = (0.3, 0.6, 0.9)`):
/// oscillatory `∫ cos(2π u_1) = cos(2π u_1)`; corner peak, Gaussian and continuous `∫ 1 = 1`;
/// discontinuous `u_1 u_2` (the cut box `[0, u_1] x [0, u_2] x [0, 1]`, or `u_1` when d = 1);
/// product peak `Π a_k^2 (1 - O(a_k^2))`, since `a (atan(a(1-u)) + atan(a u)) = a^2 (1 - O(a^2))`,
/// which is `(a^2)^d` rounded (0 for the subnormal `a`, whose `a^2 ≈ 1e-620` underflows).
/// The closed forms used to divide subnormals (`sin(a/2)/a`, `erf(a)/a`, `(e^{a u} - 1)/a`)
/// and gave 0, inf or 0.96 (corner peak) at `a = 5e-324`, and 1 + 5e-14 at `1e-310`.
#[test]
fn tiny_and_subnormal_a_give_the_limits_as_a_goes_to_zero() {
    let u = [0.3, 0.6, 0.9];
    for a in [1e-310, 5e-324, 1e-20] {
        for d in [1usize, 3] {
            for family in GenzFamily::ALL {
                let g = Genz::new(family, vec![a; d], u[..d].to_vec())
                    .unwrap_or_else(|e| panic!("{family} a = {a:e} d = {d}: {e}"));
                let limit = match family {
                    GenzFamily::Oscillatory => (2.0 * std::f64::consts::PI * u[0]).cos(),
                    GenzFamily::ProductPeak => (a * a).powi(d as i32),
                    GenzFamily::CornerPeak | GenzFamily::Gaussian | GenzFamily::Continuous => 1.0,
                    GenzFamily::Discontinuous => u[..d.min(2)].iter().product(),
                };
                // A few ulps: the corner peak's value comes from quadrature (1 ulp off here).
                assert!(
                    (g.exact() - limit).abs() <= 4.0 * f64::EPSILON * limit.abs(),
                    "{family} a = {a:e} d = {d}: {:e}, limit {limit:e}",
                    g.exact()
                );
            }
        }
    }
    // Tiny factors next to ordinary ones: the others' integrals, unchanged.
    for family in GenzFamily::ALL {
        let tiny = Genz::new(family, vec![5e-324, 2.0, 1e-310], vec![0.3, 0.6, 0.9]).unwrap();
        let one_axis = Genz::new(family, vec![1e-300, 2.0, 1e-300], vec![0.3, 0.6, 0.9]).unwrap();
        if family == GenzFamily::ProductPeak {
            // a_1^2 a_3^2 times the middle factor: below f64's range either way.
            assert_eq!((tiny.exact(), one_axis.exact()), (0.0, 0.0));
        } else {
            let (got, want) = (tiny.exact(), one_axis.exact());
            assert!(
                (got - want).abs() <= 4.0 * f64::EPSILON * want.abs(),
                "{family}: {got:e} vs {want:e} (a = 1e-300)"
            );
        }
    }
}

/// Huge `a`: no NaN where the true value is a number, and a refusal nowhere.
///
/// References (mpmath; its working precision must exceed 300 digits for `2π u + a`):
/// `python3 -c "from mpmath import mp, mpf, sin, pi, expm1, atan; mp.dps = 400;
///  a, u = mpf(1e300), mpf(0.3); print(mp.nstr((sin(2*pi*u + a) - sin(2*pi*u)) / a, 20));
///  print(mp.nstr(mpf(1e-310)**2 * (mpf(1e300) * 2 * atan(mpf(1e300) / 2))**2, 20));
///  print(mp.nstr(expm1(mpf(1e-300)) * expm1(mpf(0.5)) * expm1(mpf(1000)) / 1000, 20))"`
#[test]
#[allow(clippy::excessive_precision, reason = "20 digits as printed by mpmath")]
fn huge_a_gives_numbers_not_nan() {
    let close = |got: f64, want: f64, what: &str| {
        assert!(
            (got - want).abs() <= 1e-14 * want.abs(),
            "{what}: {got:e}, want {want:e}"
        );
    };
    let one = |family, a: f64, u: f64| Genz::new(family, vec![a], vec![u]).unwrap().exact();
    // d = 1 closed forms: (sin(2πu + a) - sin(2πu))/a (the phase used to drop 2πu: the value
    // was -8.2e-301 for every u), π a, 1/(1 + a), √π/a, 2/a.
    close(
        one(GenzFamily::Oscillatory, 1e300, 0.3),
        -1.2455418172224204271e-300,
        "oscillatory",
    );
    close(
        one(GenzFamily::ProductPeak, 1e300, 0.3),
        std::f64::consts::PI * 1e300,
        "product peak",
    );
    close(
        one(GenzFamily::CornerPeak, 1e300, 0.3),
        1e-300,
        "corner peak",
    );
    close(
        one(GenzFamily::Gaussian, 1e300, 0.3),
        std::f64::consts::PI.sqrt() * 1e-300,
        "gaussian",
    );
    close(
        one(GenzFamily::Continuous, 1e300, 0.3),
        2e-300,
        "continuous",
    );
    // e^{3e299}/1e300 overflows: inf, as documented; the integral of e^{a x} over a cut at 0
    // is 0 whatever a is (it used to be 0 * inf = NaN, and the constructor refused it).
    assert_eq!(one(GenzFamily::Discontinuous, 1e300, 0.3), f64::INFINITY);
    let cut = Genz::new(
        GenzFamily::Discontinuous,
        vec![1.0, 1.0, 1e300],
        vec![0.0, 0.5, 0.5],
    );
    assert_eq!(cut.unwrap().exact(), 0.0);
    // Factors beyond f64 in both directions whose product is a plain number (both used to
    // be 0 * inf = NaN, refused by the constructor).
    let peak = Genz::new(
        GenzFamily::ProductPeak,
        vec![1e-310, 1e300, 1e300],
        vec![0.5; 3],
    );
    close(
        peak.unwrap().exact(),
        9.8696044010892993506e-20,
        "product peak, mixed",
    );
    let disc = Genz::new(
        GenzFamily::Discontinuous,
        vec![1.0, 1.0, 1000.0],
        vec![1e-300, 0.5, 0.5],
    );
    close(
        disc.unwrap().exact(),
        1.2780270364547557978e131,
        "discontinuous, mixed",
    );
    for family in GenzFamily::ALL {
        for a in [vec![1e300; 3], vec![1e300, 1.0, 1e-310], vec![f64::MAX; 2]] {
            let d = a.len();
            let g = Genz::new(family, a.clone(), vec![0.3; d])
                .unwrap_or_else(|e| panic!("{family} {a:?}: {e}"));
            assert!(!g.exact().is_nan(), "{family} {a:?}");
        }
    }
}

#[test]
fn genz_eval_matches_definitions() {
    let x = [0.1, 0.6, 0.9];
    let (a, u) = ([1.0, 1.5, 2.0], [0.2, 0.5, 0.8]);
    let sum_ax: f64 = a.iter().zip(&x).map(|(ai, xi)| ai * xi).sum();
    let cases = [
        (
            GenzFamily::Oscillatory,
            (2.0 * std::f64::consts::PI * u[0] + sum_ax).cos(),
        ),
        (
            GenzFamily::ProductPeak,
            (0..3)
                .map(|i| 1.0 / (a[i].powi(-2) + (x[i] - u[i]).powi(2)))
                .product(),
        ),
        (GenzFamily::CornerPeak, (1.0 + sum_ax).powi(-4)),
        (
            GenzFamily::Gaussian,
            (-(0..3).map(|i| (a[i] * (x[i] - u[i])).powi(2)).sum::<f64>()).exp(),
        ),
        (
            GenzFamily::Continuous,
            (-(0..3).map(|i| a[i] * (x[i] - u[i]).abs()).sum::<f64>()).exp(),
        ),
        // x_2 = 0.6 > u_2 = 0.5 puts the point in the zero region.
        (GenzFamily::Discontinuous, 0.0),
    ];
    for (family, want) in cases {
        let g = Genz::with_defaults(family, 3).unwrap();
        assert_close(&format!("{family:?} eval"), g.eval(&x), want, 1e-14);
        assert_eq!(g.name(), family.name());
    }
    let g = Genz::with_defaults(GenzFamily::Discontinuous, 3).unwrap();
    assert_close(
        "discontinuous inside",
        g.eval(&[0.1, 0.4, 0.9]),
        (0.1f64 + 0.6 + 1.8).exp(),
        1e-14,
    );
}

/// Double-double arithmetic: an unevaluated sum hi + lo with about 106 bits of precision.
#[derive(Clone, Copy)]
struct DoubleDouble {
    hi: f64,
    lo: f64,
}

impl DoubleDouble {
    /// 1/x for an exactly representable x: the fused residual 1 - r x is exact, so r + e/x is
    /// correct to about 2^-104 relative.
    fn recip(x: f64) -> DoubleDouble {
        let r = 1.0 / x;
        let residual = (-r).mul_add(x, 1.0);
        DoubleDouble {
            hi: r,
            lo: residual / x,
        }
    }

    /// Sum with Knuth's error-free two-sum on the high parts.
    fn add(self, other: DoubleDouble) -> DoubleDouble {
        let s = self.hi + other.hi;
        let v = s - self.hi;
        let err = (self.hi - (s - v)) + (other.hi - v);
        let lo = err + self.lo + other.lo;
        let hi = s + lo;
        DoubleDouble {
            hi,
            lo: lo - (hi - s),
        }
    }

    fn neg(self) -> DoubleDouble {
        DoubleDouble {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

/// The corner-peak integral by the inclusion-exclusion sum
/// `(1/(d! Π a_i)) Σ_S (-1)^{|S|} / (1 + Σ_{i∈S} a_i)`, in double-double.
///
/// Why this is still accurate at d = 20: the a_i used are multiples of 1/4 with few
/// significant bits, so every subset sum 1 + a_S (formed incrementally in Gray-code order)
/// is exact in f64. Each reciprocal is then correct to about u² = 2^-104 relative, and each
/// of the N = 2^d double-double additions errs by at most ~u² times a partial sum, which is
/// at most Σ|t|. So the sum's relative error is below ~N u² (Σ|t| / |Σ t|); the function
/// returns that cancellation ratio and the caller checks it (N u² = 5e-26 at d = 20). The
/// final division by d! Π a_i in f64 adds at most ~2d ulps.
fn corner_peak_inclusion_exclusion(a: &[f64]) -> (f64, f64) {
    let d = a.len();
    let mut sum = DoubleDouble { hi: 1.0, lo: 0.0 }; // the empty set
    let mut abs_sum = 1.0;
    let mut subset_sum = 0.0;
    let mut members = 0usize;
    let mut in_set = vec![false; d];
    for k in 1u64..(1u64 << d) {
        // Gray code: step k flips the bit at the position of k's lowest set bit.
        let bit = k.trailing_zeros() as usize;
        in_set[bit] = !in_set[bit];
        if in_set[bit] {
            subset_sum += a[bit];
            members += 1;
        } else {
            subset_sum -= a[bit];
            members -= 1;
        }
        let term = DoubleDouble::recip(1.0 + subset_sum);
        abs_sum += term.hi;
        sum = sum.add(if members % 2 == 1 { term.neg() } else { term });
    }
    let mut scale = 1.0;
    for (i, ai) in a.iter().enumerate() {
        scale *= (i + 1) as f64 * ai;
    }
    ((sum.hi + sum.lo) / scale, abs_sum / sum.hi.abs())
}

#[test]
fn corner_peak_high_dimension_matches_inclusion_exclusion() {
    let dyadic = [0.25, 3.0, 0.5, 7.5, 1.25, 2.0, 0.75, 5.0, 1.5, 0.25];
    for d in [8, 20] {
        let defaults = Genz::with_defaults(GenzFamily::CornerPeak, d).unwrap();
        let others: Vec<f64> = (0..d).map(|i| dyadic[i % dyadic.len()]).collect();
        let custom = Genz::new(GenzFamily::CornerPeak, others, vec![0.5; d]).unwrap();
        for g in [defaults, custom] {
            let (want, cancellation) = corner_peak_inclusion_exclusion(g.a());
            // Keeps the double-double sum good to ~5e-26 * 1e10 = 5e-16 relative.
            assert!(
                cancellation < 1e10,
                "d={d}: cancellation ratio {cancellation:e}"
            );
            // The quadrature is accurate to about d ulps; 1e-13 also covers the reference.
            assert_close(
                &format!("corner peak d={d} a={:?}", g.a()),
                g.exact(),
                want,
                1e-13,
            );
        }
    }
}

#[test]
fn corner_peak_high_dimension_matches_equal_a_product() {
    // With all a_i = a the inclusion-exclusion sum telescopes to Π_{k=1}^{d} 1/(1 + k a): a
    // product of d correctly rounded factors, itself good to d ulps.
    for a in [1e-4, 0.01, 0.5, 5.0, 200.0] {
        for d in [8, 20, 100, 1000] {
            let g = Genz::new(GenzFamily::CornerPeak, vec![a; d], vec![0.5; d]).unwrap();
            let want: f64 = (1..=d).map(|k| 1.0 / (1.0 + k as f64 * a)).product();
            if want < 1e-290 {
                // Deep in the subnormal range relative precision is gone; just require tiny.
                assert!(g.exact() < 1e-280, "a={a} d={d}: {:e}", g.exact());
                continue;
            }
            // Both sides carry rounding of order d ulps (the quadrature sums d logarithms).
            let tol = 1e-14 + 8.0 * d as f64 * f64::EPSILON;
            assert_close(&format!("corner peak a={a} d={d}"), g.exact(), want, tol);
        }
    }
}

#[test]
fn polynomials_match_cubature() {
    let mut rng = SplitMix64(2024);
    for trial in 0..60 {
        let d = 1 + trial % 3;
        let n_terms = 1 + (rng.next_u64() % 6) as usize;
        let terms: Vec<(f64, Vec<u32>)> = (0..n_terms)
            .map(|_| {
                let c = 4.0 * rng.uniform() - 2.0;
                (c, (0..d).map(|_| (rng.next_u64() % 9) as u32).collect())
            })
            .collect();
        let scale: f64 = terms.iter().map(|(c, _)| c.abs()).sum();
        let p = Polynomial::new(d, terms).unwrap();
        // 10 nodes integrate degree 19 exactly; p² has degree <= 16 per axis.
        let rules = vec![composite_rule(1, &[], 10); d];
        let mean = cubature(&|x| p.eval(x), &rules);
        let square = cubature(&|x| p.eval(x).powi(2), &rules);
        // Absolute tolerances scaled by Σ|c_k|, since the integral itself may cancel to ~0.
        assert!(
            (p.exact() - mean).abs() <= 1e-13 * scale,
            "trial {trial}: {} vs {mean}",
            p.exact()
        );
        assert!(
            (p.integral_of_square() - square).abs() <= 1e-13 * scale * scale,
            "trial {trial}: {} vs {square}",
            p.integral_of_square()
        );
    }
}

#[test]
fn polynomial_from_coefficients() {
    let p = Polynomial::from_coefficients(&[1.0, -2.0, 0.0, 4.0]).unwrap();
    assert_eq!(p.dims(), 1);
    assert_eq!(p.eval(&[0.5]), 1.0 - 1.0 + 0.5);
    assert_close("1d polynomial", p.exact(), 1.0 - 1.0 + 1.0, 1e-15);
    let rule = vec![composite_rule(1, &[], 10)];
    assert_close(
        "1d square",
        p.integral_of_square(),
        cubature(&|x| p.eval(x).powi(2), &rule),
        1e-13,
    );
    assert_eq!(p.name(), "polynomial");
}

#[test]
fn roos_arnold_and_sobol_g_match_cubature() {
    for d in 1..=3 {
        // Piecewise multilinear with the kink at 1/2: two panels of 4 nodes are exact.
        let rules = vec![composite_rule(2, &[], 4); d];
        let ra = RoosArnold::new(d).unwrap();
        assert_close(
            &format!("roos-arnold d={d}"),
            ra.exact(),
            cubature(&|x| ra.eval(x), &rules),
            1e-13,
        );
        assert_close(
            &format!("roos-arnold square d={d}"),
            ra.integral_of_square(),
            cubature(&|x| ra.eval(x).powi(2), &rules),
            1e-13,
        );
        let custom = SobolGFunction::new([0.0, 1.0, 4.5][..d].to_vec()).unwrap();
        for g in [SobolGFunction::with_defaults(d).unwrap(), custom] {
            let what = format!("sobol-g d={d} a={:?}", g.a());
            assert_close(&what, g.exact(), cubature(&|x| g.eval(x), &rules), 1e-13);
            assert_close(
                &what,
                g.integral_of_square(),
                cubature(&|x| g.eval(x).powi(2), &rules),
                1e-13,
            );
        }
    }
    assert_eq!(
        SobolGFunction::with_defaults(5).unwrap().a(),
        &[0.0, 0.0, 0.5, 1.0, 1.5]
    );
}

/// The message of a rejected constructor call, checked to name the parameter.
fn assert_rejects<T: std::fmt::Debug>(result: mcint::Result<T>, parameter: &str) {
    let message = result.expect_err("invalid input was accepted").to_string();
    assert!(!message.is_empty());
    assert!(
        message.contains(&format!("invalid {parameter} ")),
        "message {message:?} does not name {parameter}"
    );
}

#[test]
fn bad_parameters_are_rejected_with_named_errors() {
    let fam = GenzFamily::Gaussian;
    assert_rejects(Genz::new(fam, vec![1.0, 0.0], vec![0.5, 0.5]), "a");
    assert_rejects(Genz::new(fam, vec![-1.0], vec![0.5]), "a");
    assert_rejects(Genz::new(fam, vec![f64::NAN], vec![0.5]), "a");
    assert_rejects(Genz::new(fam, vec![f64::INFINITY], vec![0.5]), "a");
    assert_rejects(Genz::new(fam, vec![1.0], vec![f64::NAN]), "u");
    assert_rejects(Genz::new(fam, vec![1.0], vec![1.5]), "u");
    assert_rejects(Genz::new(fam, vec![1.0], vec![-0.1]), "u");
    assert_rejects(Genz::new(fam, vec![1.0, 2.0], vec![0.5]), "u");
    assert_rejects(Genz::new(fam, vec![], vec![]), "a");
    assert_rejects(Genz::with_defaults(fam, 0), "d");
    assert_rejects("gauss".parse::<GenzFamily>(), "family");
    assert_rejects("Gaussian".parse::<GenzFamily>(), "family");
    let message = "".parse::<GenzFamily>().unwrap_err().to_string();
    for family in GenzFamily::ALL {
        assert!(
            message.contains(family.name()),
            "{message:?} does not list {}",
            family.name()
        );
    }

    assert_rejects(Polynomial::new(0, vec![]), "dims");
    assert_rejects(Polynomial::new(2, vec![(1.0, vec![1])]), "terms");
    assert_rejects(Polynomial::new(1, vec![(f64::NAN, vec![1])]), "terms");
    assert_rejects(Polynomial::new(1, vec![(1.0, vec![65])]), "terms");
    assert_rejects(
        Polynomial::from_coefficients(&[1.0, f64::INFINITY]),
        "coefficients",
    );
    assert_rejects(Polynomial::from_coefficients(&[1.0; 66]), "coefficients");

    assert_rejects(RoosArnold::new(0), "d");
    assert_rejects(SobolGFunction::new(vec![0.0, -0.5]), "a");
    assert_rejects(SobolGFunction::new(vec![f64::NAN]), "a");
    assert_rejects(SobolGFunction::new(vec![]), "a");
    assert_rejects(SobolGFunction::with_defaults(0), "d");
}

#[test]
fn family_names_round_trip() {
    let names: Vec<&str> = GenzFamily::ALL.iter().map(|f| f.name()).collect();
    assert_eq!(
        names,
        [
            "oscillatory",
            "product-peak",
            "corner-peak",
            "gaussian",
            "continuous",
            "discontinuous"
        ]
    );
    for family in GenzFamily::ALL {
        assert_eq!(family.name().parse::<GenzFamily>().unwrap(), family);
    }
}
