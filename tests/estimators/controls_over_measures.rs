//! Control variates over a measure (`Integrator::expectation_with_controls`) and the
//! geometric-average call's closed form, checked against independent Monte Carlo and
//! Black-Scholes.

use mcint::measure::{Construction, Gaussian, GeometricBrownianMotion};
use mcint::sampler::{Scramble, Sobol};
use mcint::{Error, Integrator};

/// Black-Scholes call, from erfc: an independent check of the one-date case.
fn black_scholes(s0: f64, strike: f64, rate: f64, sigma: f64, t: f64) -> f64 {
    let cdf = |x: f64| 0.5 * libm::erfc(-x / std::f64::consts::SQRT_2);
    let d1 = ((s0 / strike).ln() + (rate + 0.5 * sigma * sigma) * t) / (sigma * t.sqrt());
    let d2 = d1 - sigma * t.sqrt();
    s0 * cdf(d1) - strike * (-rate * t).exp() * cdf(d2)
}

#[test]
fn one_date_is_black_scholes() {
    for (strike, sigma, t) in [(100.0, 0.2, 1.0), (80.0, 0.5, 0.25), (130.0, 0.1, 3.0)] {
        let gbm =
            GeometricBrownianMotion::new(100.0, 0.03, sigma, vec![t], Construction::Pca).unwrap();
        let exact = black_scholes(100.0, strike, 0.03, sigma, t);
        let ours = gbm.geometric_average_call(strike).unwrap();
        assert!((ours - exact).abs() <= 1e-12 * exact, "{ours} vs {exact}");
    }
}

#[test]
fn the_geometric_average_call_matches_monte_carlo() {
    let dates: Vec<f64> = (1..=8).map(|i| i as f64 / 8.0).collect();
    for (strike, sigma) in [(95.0, 0.3), (110.0, 0.2)] {
        let gbm =
            GeometricBrownianMotion::new(100.0, 0.05, sigma, dates.clone(), Construction::Bridge)
                .unwrap();
        let discount = (-0.05f64).exp();
        let payoff = move |s: &[f64]| {
            let log_mean = s.iter().map(|v| v.ln()).sum::<f64>() / s.len() as f64;
            discount * (log_mean.exp() - strike).max(0.0)
        };
        let exact = gbm.geometric_average_call(strike).unwrap();
        let e = Integrator::expectation(payoff, gbm)
            .sampler(Sobol::new(8, Scramble::Owen, 3).unwrap())
            .samples(1 << 14)
            .replicates(16)
            .run()
            .unwrap();
        let z = (e.mean - exact) / e.std_error.unwrap();
        assert!(
            z.abs() < 5.0,
            "strike {strike}: {} vs {exact}, z = {z}",
            e.mean
        );
    }
}

#[test]
fn without_volatility_the_average_is_certain() {
    let gbm =
        GeometricBrownianMotion::new(100.0, 0.05, 0.0, vec![0.5, 1.0], Construction::Standard)
            .unwrap();
    // ln G = ln 100 + 0.05 * 0.75, paid at t = 1.
    let expected = (-0.05f64).exp() * (100.0 * (0.05f64 * 0.75).exp() - 90.0);
    let ours = gbm.geometric_average_call(90.0).unwrap();
    assert!(
        (ours - expected).abs() < 1e-12 * expected,
        "{ours} vs {expected}"
    );
    assert_eq!(gbm.geometric_average_call(200.0).unwrap(), 0.0);
}

#[test]
fn bad_strikes_are_errors() {
    let gbm =
        GeometricBrownianMotion::new(100.0, 0.05, 0.2, vec![1.0], Construction::Standard).unwrap();
    for strike in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let err = gbm.geometric_average_call(strike).unwrap_err();
        assert!(matches!(err, Error::InvalidParameter { .. }), "{err}");
        assert!(err.to_string().contains("strike"), "{err}");
    }
}

#[test]
fn controls_over_a_gaussian_are_unbiased_and_cut_the_variance() {
    // f = exp(Z), Z = x0 + x1 / 2 ~ N(0, 1.25): E f = e^0.625. The control Z has mean 0 and
    // correlation rho^2 = 1.25 / (e^1.25 - 1) = 0.502 with f: the standard error falls to
    // sqrt(1 - rho^2) = 0.706 of the plain one.
    let f = |x: &[f64]| (x[0] + 0.5 * x[1]).exp();
    let control = |x: &[f64]| x[0] + 0.5 * x[1];
    let exact = 0.625f64.exp();
    let gaussian = || Gaussian::standard(2).unwrap();
    let n = 1 << 16;
    let with = Integrator::expectation_with_controls(f, gaussian())
        .control(control, 0.0)
        .samples(n)
        .seed(7)
        .run()
        .unwrap();
    let plain = Integrator::expectation(f, gaussian())
        .samples(n)
        .seed(7)
        .run()
        .unwrap();
    let z = (with.mean - exact) / with.std_error.unwrap();
    assert!(z.abs() < 5.0, "{} vs {exact}, z = {z}", with.mean);
    // The standard errors' own spread is about 3% each here (the lognormal's kurtosis, 264).
    let ratio = with.std_error.unwrap() / plain.std_error.unwrap();
    assert!((0.55..0.85).contains(&ratio), "ratio {ratio}");
    assert_eq!(with.evaluations, n + 4096); // the pilot's 4,096 points too
}

#[test]
fn a_control_over_a_measure_needs_a_finite_integral() {
    let err =
        Integrator::expectation_with_controls(|x: &[f64]| x[0], Gaussian::standard(1).unwrap())
            .control(|x: &[f64]| x[0], f64::NAN)
            .run()
            .unwrap_err();
    assert!(err.to_string().contains("control integral"), "{err}");
}
