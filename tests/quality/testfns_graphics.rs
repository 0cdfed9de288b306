//! Checks the graphics integrands' exact integrals against independent computations.
//!
//! * Each `eval` is integrated by an `M x M` midpoint rule and compared with `exact()`. A
//!   smooth integrand's midpoint error is `O(1/M²)` (below `1e-6` for `M = 2000` and these
//!   derivatives); an indicator's error comes only from the cells its boundary crosses, at
//!   most `2M` of the `M²` cells for a monotone boundary, each off by at most `1/M²`, so at
//!   most `2/M = 1e-3`.
//! * The closed forms are re-derived by other routes to rounding precision: the disk's area
//!   by quadrature in polar form, `erf(1)` by its Maclaurin series, and the Gaussian and
//!   bilinear integrals by a Gauss-Legendre tensor rule on the integrand itself.

use mcint::testfns::{GraphicsIntegrand, TestFunction};
use std::f64::consts::PI;

/// Midpoint rule with `m x m` cells.
fn midpoint(f: &dyn TestFunction, m: usize) -> f64 {
    let h = 1.0 / m as f64;
    let mut sum = 0.0;
    for i in 0..m {
        for j in 0..m {
            sum += f.eval(&[(i as f64 + 0.5) * h, (j as f64 + 0.5) * h]);
        }
    }
    sum * h * h
}

/// 5-point Gauss-Legendre on [0, 1] (exact for polynomials of degree 9), composite over
/// `panels` panels.
fn gauss_legendre_01(panels: usize) -> Vec<(f64, f64)> {
    let a = (5.0 - 2.0 * (10.0f64 / 7.0).sqrt()).sqrt() / 3.0;
    let b = (5.0 + 2.0 * (10.0f64 / 7.0).sqrt()).sqrt() / 3.0;
    let (wa, wb) = (
        (322.0 + 13.0 * 70f64.sqrt()) / 900.0,
        (322.0 - 13.0 * 70f64.sqrt()) / 900.0,
    );
    let rule = [(0.0, 128.0 / 225.0), (-a, wa), (a, wa), (-b, wb), (b, wb)];
    let h = 1.0 / panels as f64;
    (0..panels)
        .flat_map(|p| {
            let mid = (p as f64 + 0.5) * h;
            rule.map(|(x, w)| (mid + 0.5 * h * x, 0.5 * h * w))
        })
        .collect()
}

#[test]
fn midpoint_rule_agrees_with_every_exact_integral() {
    for f in GraphicsIntegrand::ALL {
        let error = (midpoint(&f, 2000) - f.exact()).abs();
        let bound = if f.is_smooth() { 1e-6 } else { 1e-3 };
        assert!(error < bound, "{f}: midpoint error {error}");
    }
}

#[test]
fn disk_of_radius_squared_two_over_pi_has_area_one_half() {
    // Area = ∫_0^r √(r² - x²) dx; with x = r sin θ it is ∫_0^{π/2} r² cos² θ dθ, a smooth
    // integrand that Gauss-Legendre integrates to rounding.
    let r2 = 2.0 / PI;
    let area: f64 = gauss_legendre_01(8)
        .iter()
        .map(|&(t, w)| {
            let theta = t * PI / 2.0;
            w * PI / 2.0 * r2 * theta.cos().powi(2)
        })
        .sum();
    assert!((area - 0.5).abs() < 1e-14, "{area}");
    assert_eq!(GraphicsIntegrand::Disk.exact(), 0.5);
    // Points just inside and outside the arc.
    let r = r2.sqrt();
    let f = GraphicsIntegrand::Disk;
    assert_eq!(f.eval(&[r * 0.6 - 1e-9, r * 0.8 - 1e-9]), 1.0);
    assert_eq!(f.eval(&[r * 0.6 + 1e-9, r * 0.8 + 1e-9]), 0.0);
}

#[test]
fn gaussian_integral_matches_series_and_quadrature() {
    // erf(1) = 2/√π Σ (-1)^n / (n! (2n + 1)); 25 terms leave less than 1e-25.
    let mut series = 0.0;
    let mut factorial = 1.0;
    for n in 0..25 {
        if n > 0 {
            factorial *= n as f64;
        }
        let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
        series += sign / (factorial * (2 * n + 1) as f64);
    }
    let erf1 = 2.0 / PI.sqrt() * series;
    let by_series = (0.5 * PI.sqrt() * erf1).powi(2);
    let f = GraphicsIntegrand::Gaussian;
    assert!(
        (f.exact() - by_series).abs() < 1e-15,
        "{} {by_series}",
        f.exact()
    );

    let nodes = gauss_legendre_01(4);
    let tensor: f64 = nodes
        .iter()
        .flat_map(|&(x, wx)| nodes.iter().map(move |&(y, wy)| wx * wy * f.eval(&[x, y])))
        .sum();
    assert!((f.exact() - tensor).abs() < 1e-14, "{tensor}");
}

#[test]
fn bilinear_step_and_triangle_integrals_are_exact() {
    // Gauss-Legendre is exact for x y.
    let nodes = gauss_legendre_01(1);
    let f = GraphicsIntegrand::Bilinear;
    let tensor: f64 = nodes
        .iter()
        .flat_map(|&(x, wx)| nodes.iter().map(move |&(y, wy)| wx * wy * f.eval(&[x, y])))
        .sum();
    assert!((tensor - 0.25).abs() < 1e-16);
    assert_eq!(f.exact(), 0.25);

    // The step is 1 on [0, 1/3): on a midpoint grid of 3j columns exactly j are inside.
    let step = GraphicsIntegrand::Step;
    assert!((midpoint(&step, 300) - 1.0 / 3.0).abs() < 1e-15);
    assert_eq!(step.exact(), 1.0 / 3.0);
    assert_eq!(
        (step.eval(&[0.333, 0.9]), step.eval(&[0.334, 0.1])),
        (1.0, 0.0)
    );

    // Of the m² midpoints, those strictly below the diagonal number m(m - 1)/2.
    let triangle = GraphicsIntegrand::Triangle;
    let m = 500;
    let expected = (m * (m - 1) / 2) as f64 / (m * m) as f64;
    assert!((midpoint(&triangle, m) - expected).abs() < 1e-15);
    assert_eq!(triangle.exact(), 0.5);
}

#[test]
fn names_round_trip_and_smoothness_is_reported() {
    let smooth: Vec<&str> = GraphicsIntegrand::ALL
        .into_iter()
        .filter(|f| f.is_smooth())
        .map(|f| f.name())
        .collect();
    assert_eq!(smooth, ["gaussian", "bilinear"]);
    for f in GraphicsIntegrand::ALL {
        assert_eq!(f.to_string().parse::<GraphicsIntegrand>().unwrap(), f);
        assert_eq!(TestFunction::name(&f), f.name());
        assert_eq!(f.dims(), 2);
    }
    assert!("Disk".parse::<GraphicsIntegrand>().is_err());
}
