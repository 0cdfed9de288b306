//! Control variates (Jarosz's A.26-A.29) checked against closed forms.
//!
//! - The known-`G` estimator is unbiased for every coefficient and its per-sample variance is
//!   `Var[f] - 2 beta Cov[f, g] + beta^2 Var[g]`, smallest at `beta* = Cov[f, g] / Var[g]`.
//! - Coefficients fitted on a pilot achieve the variance-reduction factor `1 - rho^2` (one
//!   control) or `1 - R^2` (two controls), within a tolerance from the delta method; the main
//!   run then has that per-sample variance, is unbiased at every size, and its 95% intervals
//!   cover, with independent points and with randomized QMC replicates.
//! - `CovarianceAccumulator` merges exactly (proptest) and agrees with a two-pass computation.
//! - Bad input (collinear or constant controls, wrong lengths, dependent samplers, non-finite
//!   values) gives errors, not panics.
//!
//! Statistical tolerances are 4.5 standard errors of the tested quantity (false alarms below
//! 1e-5 per check) with fixed seeds. Moments come from closed forms for `e^x` on `[0,1]`
//! (`int x^k e^x = e - k int x^(k-1) e^x`); fourth moments, needed only for tolerances, from
//! composite Simpson quadrature, accurate to about 1e-15 for these smooth integrands.

use crate::common::{config, integrate01};
use mcint::estimator::{Estimator, FittedControlVariates, FixedControlVariate};
use mcint::pdf::{Linear, UniformBox};
use mcint::sampler::{Independent, Jittered, Scramble, Sobol};
use mcint::stats::{Accumulator, CovarianceAccumulator, ErrorBasis};
use mcint::{Error, Integrator, Points};
use proptest::prelude::*;
use std::f64::consts::E;

/// `int_0^1 x^k e^x dx` by the recurrence `I_k = e - k I_{k-1}`, `I_0 = e - 1`.
fn moment_exp(k: u32) -> f64 {
    (1..=k).fold(E - 1.0, |acc, j| E - j as f64 * acc)
}

/// Exact moments of `f = e^x` with the controls `x` and `x^2` on [0, 1].
struct ExpMoments {
    mean: f64,
    var_f: f64,
    /// `Cov(e^x, x)`, `Cov(e^x, x^2)`.
    cov_f: [f64; 2],
    /// Covariance matrix of `(x, x^2)`: `[[1/12, 1/12], [1/12, 4/45]]`.
    var_g: [[f64; 2]; 2],
}

fn exp_moments() -> ExpMoments {
    let mean = moment_exp(0);
    ExpMoments {
        mean,
        var_f: (E * E - 1.0) / 2.0 - mean * mean,
        cov_f: [moment_exp(1) - mean / 2.0, moment_exp(2) - mean / 3.0],
        var_g: [[1.0 / 12.0, 1.0 / 12.0], [1.0 / 12.0, 4.0 / 45.0]],
    }
}

#[test]
fn closed_forms_match_scipy() {
    // python3 -c "import numpy as np; from scipy.integrate import quad; m=lambda h: quad(h,0,1,epsabs=1e-15,epsrel=1e-15)[0]; F=np.e-1; v=m(lambda x: np.exp(2*x))-F**2; c=m(lambda x: np.exp(x)*x)-F/2; print(v, c, 1-c*c*12/v)"
    // -> 0.24203560745276542 0.14085908577047745 0.016279517568082214
    let m = exp_moments();
    assert!((m.var_f - 0.24203560745276542).abs() < 1e-14);
    assert!((m.cov_f[0] - 0.14085908577047745).abs() < 1e-14);
    let one_minus_rho2 = 1.0 - m.cov_f[0] * m.cov_f[0] / (m.var_f * m.var_g[0][0]);
    assert!((one_minus_rho2 - 0.016279517568082214).abs() < 1e-12);
    // Two controls x, x^2:
    // python3 -c "import numpy as np; from scipy.integrate import quad; m=lambda h: quad(h,0,1,epsabs=1e-15,epsrel=1e-15)[0]; F=np.e-1; v=m(lambda x: np.exp(2*x))-F**2; c=np.array([m(lambda x: np.exp(x)*x)-F/2, m(lambda x: np.exp(x)*x*x)-F/3]); print(1-c@np.linalg.solve([[1/12,1/12],[1/12,4/45]],c)/v)"
    // -> 0.0001150055761582891
    assert!((one_minus_r2_two_controls(&m) - 0.0001150055761582891).abs() < 1e-12);
    // The quadrature agrees with the closed forms.
    assert!((integrate01(|x| x * x * x.exp()) - moment_exp(2)).abs() < 1e-14);
}

/// `1 - R^2` of `e^x` on `(x, x^2)`: `1 - c^T S^-1 c / Var f`.
fn one_minus_r2_two_controls(m: &ExpMoments) -> f64 {
    let beta = optimal_two(m);
    1.0 - (beta[0] * m.cov_f[0] + beta[1] * m.cov_f[1]) / m.var_f
}

/// `beta* = S^-1 c` for the controls `(x, x^2)`, by Cramer's rule.
fn optimal_two(m: &ExpMoments) -> [f64; 2] {
    let s = m.var_g;
    let det = s[0][0] * s[1][1] - s[0][1] * s[1][0];
    [
        (s[1][1] * m.cov_f[0] - s[0][1] * m.cov_f[1]) / det,
        (s[0][0] * m.cov_f[1] - s[1][0] * m.cov_f[0]) / det,
    ]
}

// ---------------------------------------------------------------------------------------------
// Known G (A.27, A.29)

/// The known-`G` estimator with `f = e^x`, `g = 1 + x` (`G = 3/2`) on [0, 1].
fn exp_with_linear_control(beta: f64) -> impl Estimator {
    FixedControlVariate::new(
        |x: &[f64]| x[0].exp(),
        |x: &[f64]| 1.0 + x[0],
        1.5,
        UniformBox::unit(1).unwrap(),
    )
    .unwrap()
    .with_coefficient(beta)
    .unwrap()
}

/// Unbiased for every beta, and the per-sample variance is the closed form
/// `Var f - 2 beta Cov(f, g) + beta^2 Var g`; the sample variance's standard error is
/// `sqrt((mu_4 - sigma^4) / n)` with the fourth central moment by quadrature.
#[test]
fn known_g_estimator_is_unbiased_with_the_closed_form_variance() {
    let m = exp_moments();
    let optimal = m.cov_f[0] / m.var_g[0][0];
    // python3 -c "import numpy as np; print(12*(1-(np.e-1)/2))" -> 1.6903090292457295
    assert!((optimal - 1.6903090292457295).abs() < 1e-13);
    let n = 200_000u64;
    let mut variances = Vec::new();
    for (i, beta) in [0.0, 0.5, 1.0, optimal, 2.5].into_iter().enumerate() {
        let sigma2 = m.var_f - 2.0 * beta * m.cov_f[0] + beta * beta * m.var_g[0][0];
        // Y = e^x - beta x + beta/2 has mean e - 1, so Y - E[Y] = e^x - beta x - centre.
        let centre = m.mean - beta / 2.0;
        let mu4 = integrate01(|x| (x.exp() - beta * x - centre).powi(4));
        let e = Integrator::new(exp_with_linear_control(beta))
            .samples(n)
            .seed(100 + i as u64)
            .threads(2)
            .run()
            .unwrap();
        assert!(
            (e.mean - m.mean).abs() < 4.5 * (sigma2 / n as f64).sqrt(),
            "beta {beta}: mean {}, exact {}",
            e.mean,
            m.mean
        );
        let s2 = e.std_error.unwrap().powi(2) * n as f64;
        let tolerance = 4.5 * ((mu4 - sigma2 * sigma2) / n as f64).sqrt();
        assert!(
            (s2 - sigma2).abs() < tolerance,
            "beta {beta}: variance {s2}, closed form {sigma2}, tolerance {tolerance}"
        );
        variances.push(sigma2);
    }
    // beta* gives the smallest variance, (1 - rho^2) Var f.
    let best = variances[3];
    assert!(variances.iter().all(|&v| v >= best));
    let one_minus_rho2 = 1.0 - m.cov_f[0].powi(2) / (m.var_f * m.var_g[0][0]);
    assert!((best - one_minus_rho2 * m.var_f).abs() < 1e-15);
}

/// A.27 with `beta = 1` is exactly `(f - g)/pdf + G`, and the estimator stays unbiased with a
/// non-uniform pdf: `f = x^2`, `g = x` (`G = 1/2`) sampled from the density `2x` on [0, 1].
#[test]
fn known_g_estimator_with_a_pdf() {
    let pdf = Linear::new(0.0, 1.0, 0.0, 2.0).unwrap();
    let cv = FixedControlVariate::new(|x: &[f64]| x[0] * x[0], |x: &[f64]| x[0], 0.5, pdf).unwrap();
    let mut x = [0.0];
    for u in [0.04f64, 0.25, 0.81] {
        let sample = u.sqrt(); // inverse cdf of 2x
        let expected = (sample * sample - sample) / (2.0 * sample) + 0.5;
        assert!((cv.contribution(&[u], &mut x) - expected).abs() < 1e-15);
    }
    // Y = x/2 - 1/2 + 1/2 = x/2 under density 2x: mean 1/3, variance (1/2 - 4/9)/4 = 1/72.
    let n = 100_000u64;
    let e = Integrator::new(cv).samples(n).seed(7).run().unwrap();
    assert!((e.mean - 1.0 / 3.0).abs() < 4.5 * (1.0 / 72.0 / n as f64).sqrt());
}

/// A fixed coefficient keeps the estimator unbiased with stratified and quasi-random points
/// too, where the error bar comes from replicates.
#[test]
fn known_g_estimator_works_with_replicates() {
    let m = exp_moments();
    let e = Integrator::new(exp_with_linear_control(1.0))
        .sampler(Jittered::new(1, 256, 0).unwrap())
        .samples(256)
        .replicates(32)
        .seed(11)
        .run()
        .unwrap();
    assert_eq!(e.basis, ErrorBasis::Replicates);
    let (lo, hi) = e.confidence_interval(0.9999).unwrap().unwrap();
    assert!(lo < m.mean && m.mean < hi, "[{lo}, {hi}]");
}

#[test]
fn known_g_estimator_rejects_bad_input() {
    let make = |g: f64| {
        FixedControlVariate::new(
            |x: &[f64]| x[0],
            |x: &[f64]| x[0],
            g,
            UniformBox::unit(1).unwrap(),
        )
    };
    for bad in [f64::NAN, f64::INFINITY] {
        let err = make(bad).err().unwrap();
        assert!(matches!(
            err,
            Error::InvalidParameter {
                name: "control_integral",
                ..
            }
        ));
    }
    let err = make(0.5).unwrap().with_coefficient(f64::NAN).err().unwrap();
    assert!(err.to_string().contains("coefficient"), "{err}");
    // A pdf that is zero where f - beta g is not: the integrator reports it, no silent bias.
    let pdf = Linear::new(0.0, 1.0, 0.0, 2.0).unwrap(); // density 0 at x = 0
    let cv = FixedControlVariate::new(|_: &[f64]| 1.0, |x: &[f64]| x[0], 0.5, pdf).unwrap();
    let mut x = [0.0];
    assert!(!cv.contribution(&[0.0], &mut x).is_finite());
}

// ---------------------------------------------------------------------------------------------
// Coefficients fitted on a pilot (the Integrator's control-variate mode)

/// Standard deviation of the achieved `1 - R^2` by the delta method. With the population
/// residual `e = Y_c - beta*^T Z_c` (`Y_c`, `Z_c` centred) and `r = 1 - R^2`, the achieved
/// factor is `mean(e^2) / mean(Y_c^2) + O_p(1/n)`, so its variance is
/// `E[(e^2 - r Y_c^2)^2] / (n Var(Y)^2)`. The O(1/n) bias (relative size about `(k + 1)/n`)
/// is far below this standard deviation at the sizes used.
fn reduction_sd(
    residual: impl Fn(f64) -> f64,
    centred: impl Fn(f64) -> f64,
    r: f64,
    var_y: f64,
    n: u64,
) -> f64 {
    let m4 = integrate01(|x| (residual(x).powi(2) - r * centred(x).powi(2)).powi(2));
    (m4 / n as f64).sqrt() / var_y
}

fn exp_with_controls()
-> Integrator<FittedControlVariates<'static, impl Fn(&[f64]) -> f64 + Send + Sync, UniformBox>> {
    Integrator::with_controls(|x: &[f64]| x[0].exp(), UniformBox::unit(1).unwrap())
}

/// The pilot's fit achieves `1 - rho^2` and `beta*` within their sampling errors at the pilot's
/// size, and the main run's per-sample variance is the residual variance: `r Var f` times
/// `1 + 1/n_pilot` on average (the coefficient's own error, `E[(beta - beta*)^2] Var g =
/// r Var f / n_pilot`), within the sampling error of a variance at the main run's size.
#[test]
fn fitted_reduction_matches_one_minus_rho_squared() {
    let m = exp_moments();
    let beta = m.cov_f[0] / m.var_g[0][0];
    let r = 1.0 - m.cov_f[0].powi(2) / (m.var_f * m.var_g[0][0]);
    let residual = |x: f64| x.exp() - m.mean - beta * (x - 0.5);
    let (pilot, n) = (50_000, 200_000);
    let pilot_sd = reduction_sd(residual, |x| x.exp() - m.mean, r, m.var_f, pilot);
    let main_sd = reduction_sd(residual, |x| x.exp() - m.mean, r, m.var_f, n);
    for seed in [1, 2, 3] {
        let run = exp_with_controls()
            .control(|x: &[f64]| 1.0 + x[0], 1.5)
            .pilot(pilot)
            .samples(n)
            .seed(seed)
            .threads(2);
        let fit = run.fit().unwrap();
        assert!(
            (fit.variance_reduction - r).abs() < 4.5 * pilot_sd,
            "seed {seed}: achieved {}, 1 - rho^2 = {r}, sd {pilot_sd}",
            fit.variance_reduction
        );
        // The coefficient converges to beta* at rate sqrt(Var(e) / (n Var(g))).
        let beta_sd = (r * m.var_f / (pilot as f64 * m.var_g[0][0])).sqrt();
        assert!((fit.coefficients[0] - beta).abs() < 4.5 * beta_sd);
        let ratio = fit.residual_variance / fit.plain_variance;
        let dof_factor = (pilot - 1) as f64 / (pilot - 2) as f64;
        assert!((ratio - fit.variance_reduction * dof_factor).abs() < 1e-12);

        let e = run.run().unwrap();
        assert_eq!(
            (e.n, e.evaluations, e.basis),
            (n, n + pilot, ErrorBasis::PerSample)
        );
        assert!((e.mean - m.mean).abs() < 4.5 * e.std_error.unwrap());
        let achieved = e.variance().unwrap() * n as f64 / m.var_f;
        let expected = r * (1.0 + 1.0 / pilot as f64);
        assert!(
            (achieved - expected).abs() < 4.5 * main_sd + 4.5 * r / pilot as f64,
            "seed {seed}: main-run variance factor {achieved}, expected {expected}"
        );
    }
}

#[test]
fn fitted_reduction_with_two_controls_matches_one_minus_r_squared() {
    let m = exp_moments();
    let beta = optimal_two(&m);
    let r = one_minus_r2_two_controls(&m);
    let pilot = 50_000;
    let sd = reduction_sd(
        |x| x.exp() - m.mean - beta[0] * (x - 0.5) - beta[1] * (x * x - 1.0 / 3.0),
        |x| x.exp() - m.mean,
        r,
        m.var_f,
        pilot,
    );
    for seed in [4, 5, 6] {
        let run = exp_with_controls()
            .control(|x: &[f64]| x[0], 0.5)
            .control(|x: &[f64]| x[0] * x[0], 1.0 / 3.0)
            .pilot(pilot)
            .samples(20_000)
            .seed(seed);
        let fit = run.fit().unwrap();
        assert!(
            (fit.variance_reduction - r).abs() < 4.5 * sd,
            "seed {seed}: achieved {}, 1 - R^2 = {r}, sd {sd}",
            fit.variance_reduction
        );
        assert_eq!(fit.coefficients.len(), 2);
        let e = run.run().unwrap();
        assert_eq!(e.dof, Some((20_000 - 1) as f64));
        assert!((e.mean - m.mean).abs() < 4.5 * e.std_error.unwrap());
    }
}

/// With the coefficient fixed by an independent pilot, the main run is unbiased at every size
/// (the mean error over 400 seeds is within 4.5 of its standard errors of zero, even at
/// n = 64, where the same-sample regression estimator's `O(1/n)` bias showed), and its 95%
/// intervals cover as often as the binomial bound allows.
#[test]
fn pilot_fitted_estimate_is_unbiased_and_covers() {
    let m = exp_moments();
    let runs = 400u64;
    for n in [64u64, 1024, 16384] {
        let mut errors = Accumulator::new();
        let mut covered = 0;
        for seed in 0..runs {
            let e = exp_with_controls()
                .control(|x: &[f64]| x[0], 0.5)
                .pilot(256)
                .samples(n)
                .seed(1000 * n + seed)
                .threads(1)
                .run()
                .unwrap();
            errors.push(e.mean - m.mean);
            let (lo, hi) = e.confidence_interval(0.95).unwrap().unwrap();
            covered += u64::from(lo <= m.mean && m.mean <= hi);
        }
        let se_of_mean = (errors.variance() / runs as f64).sqrt();
        assert!(
            errors.mean().abs() < 4.5 * se_of_mean,
            "n = {n}: mean error {}, se {se_of_mean}",
            errors.mean()
        );
        // 95% intervals cover: binomial sd sqrt(0.95 * 0.05 / 400) = 0.011.
        let coverage = covered as f64 / runs as f64;
        assert!(
            (coverage - 0.95).abs() < 4.5 * (0.95 * 0.05 / runs as f64).sqrt(),
            "n = {n}: {coverage}"
        );
    }
}

/// The main run takes any sampler: with Owen-scrambled Sobol' replicates, the error bar comes
/// from their spread, and intervals cover (200 seeds, binomial bound at 4.5 sd).
#[test]
fn controls_work_with_randomized_qmc_replicates() {
    let exact = 1.317_902_151_454_404; // int_0^1 int_0^1 e^(xy) = sum_k 1/(k! (k+1)^2)
    let runs = 200u64;
    let mut covered = 0;
    for seed in 0..runs {
        let e = Integrator::with_controls(
            |x: &[f64]| (x[0] * x[1]).exp(),
            UniformBox::unit(2).unwrap(),
        )
        .control(|x: &[f64]| x[0] * x[1], 0.25)
        .pilot(512)
        .sampler(Sobol::new(2, Scramble::Owen, 0).unwrap())
        .samples(256)
        .replicates(8)
        .seed(seed)
        .threads(1)
        .run()
        .unwrap();
        assert_eq!(e.basis, ErrorBasis::Replicates);
        let (lo, hi) = e.confidence_interval(0.95).unwrap().unwrap();
        covered += u64::from(lo <= exact && exact <= hi);
    }
    let coverage = covered as f64 / runs as f64;
    assert!(
        coverage > 0.95 - 4.5 * (0.95 * 0.05 / runs as f64).sqrt(),
        "{coverage}"
    );
}

#[test]
fn fitted_result_does_not_depend_on_threads() {
    let run = |threads| {
        Integrator::with_controls(
            |x: &[f64]| (x[0] * x[1]).sin(),
            UniformBox::unit(2).unwrap(),
        )
        .control(|x: &[f64]| x[0] * x[1], 0.25)
        .control(|x: &[f64]| x[0], 0.5)
        .pilot(20_000) // several pilot chunks
        .samples(100_000) // several chunks
        .seed(9)
        .threads(threads)
        .run()
        .unwrap()
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(5));
}

#[test]
fn an_exact_fit_has_zero_error() {
    // f = 3 + 2x is exactly a linear function of the control x: the answer is exact.
    let run = Integrator::with_controls(|x: &[f64]| 3.0 + 2.0 * x[0], UniformBox::unit(1).unwrap())
        .control(|x: &[f64]| x[0], 0.5)
        .samples(1000);
    let e = run.run().unwrap();
    assert!((e.mean - 4.0).abs() < 1e-12);
    assert!(e.std_error.unwrap() < 1e-6);
    let fit = run.fit().unwrap();
    assert!((fit.coefficients[0] - 2.0).abs() < 1e-12);
    assert!(fit.variance_reduction < 1e-12);
}

fn message(result: mcint::Result<impl std::fmt::Debug>) -> String {
    result.expect_err("an error").to_string()
}

#[test]
fn fitting_rejects_bad_input_with_clear_errors() {
    let base = || exp_with_controls().pilot(100).samples(100);
    // Constant control (collinear with the intercept).
    let err = message(base().control(|_: &[f64]| 2.0, 2.0).run());
    assert!(err.contains("constant"), "{err}");
    // Two collinear controls, and a duplicated one.
    let err = message(
        base()
            .control(|x: &[f64]| x[0], 0.5)
            .control(|x: &[f64]| 3.0 * x[0] - 1.0, 0.5)
            .run(),
    );
    assert!(err.contains("control = 1 (over the 100 pilot points, a linear combination of the controls before it, 0 to 0"), "{err}");
    let err = message(
        base()
            .control(|x: &[f64]| x[0] * x[0], 1.0 / 3.0)
            .control(|x: &[f64]| x[0], 0.5)
            .control(|x: &[f64]| x[0] * x[0], 1.0 / 3.0)
            .run(),
    );
    assert!(err.contains("control = 2"), "{err}");
    // No control, non-finite integral, too small a pilot.
    assert!(message(base().run()).contains("at least one control"));
    assert!(message(base().control(|x: &[f64]| x[0], f64::INFINITY).run()).contains("control 0"));
    let err = message(base().control(|x: &[f64]| x[0], 0.5).pilot(2).run());
    assert!(err.contains("at least 3"), "{err}");
    assert!(message(base().control(|x: &[f64]| x[0], 0.5).pilot(0).run()).contains("pilot"));
    // The pilot is held to the run's limits before it starts: 2^60 points without a time
    // limit ran for hours, and 2^22 spent 42 times a tolerance's evaluation limit.
    let err = message(base().control(|x: &[f64]| x[0], 0.5).pilot(1 << 60).run());
    assert!(
        err.contains("invalid pilot points") && err.contains("2^52"),
        "{err}"
    );
    let tolerance = mcint::Tolerance::absolute(1e-3)
        .unwrap()
        .max_evaluations(100_000)
        .unwrap();
    let err = message(
        base()
            .control(|x: &[f64]| x[0], 0.5)
            .pilot(1 << 22)
            .tolerance(tolerance)
            .run(),
    );
    assert!(err.contains("evaluation limit, 100000"), "{err}");
    assert!(message(base().control(|x: &[f64]| x[0], 0.5).threads(0).run()).contains("threads"));
    // A sampler of the wrong dimension.
    let err = base()
        .control(|x: &[f64]| x[0], 0.5)
        .sampler(Independent::new(2, 0).unwrap())
        .run()
        .err()
        .unwrap();
    assert!(matches!(
        err,
        Error::DimensionMismatch {
            expected: 1,
            found: 2,
            ..
        }
    ));
    // Non-finite values of f/pdf or g/pdf in the pilot: counted, and refused.
    let err = message(
        Integrator::with_controls(
            |x: &[f64]| 1.0 / (x[0] - x[0]),
            UniformBox::unit(1).unwrap(),
        )
        .control(|x: &[f64]| x[0], 0.5)
        .pilot(50)
        .run(),
    );
    assert!(err.contains("50 non-finite"), "{err}");
    let err = message(
        Integrator::with_controls(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
            .control(|x: &[f64]| if x[0] < 0.5 { f64::NAN } else { x[0] }, 0.5)
            .pilot(1000)
            .run(),
    );
    assert!(err.contains("non-finite"), "{err}");
}

// ---------------------------------------------------------------------------------------------
// CovarianceAccumulator

/// Vectors of `dims` entries with a common offset and scale, so cancellation is exercised.
fn vectors() -> impl Strategy<Value = (usize, Vec<Vec<f64>>)> {
    // An offset up to 50 spreads keeps the condition number (offset / spread) at most 50, so
    // rounding differences stay near 50 * n * 1e-16, inside the 1e-12 tolerance.
    (1usize..5, 0usize..120, -50.0..50.0f64, 1e-3..1e3f64).prop_flat_map(
        |(dims, len, offset, scale)| {
            let row = prop::collection::vec(-1.0..1.0f64, dims).prop_map(move |r| {
                r.into_iter()
                    .map(|v| scale * (offset + v))
                    .collect::<Vec<f64>>()
            });
            (Just(dims), prop::collection::vec(row, len))
        },
    )
}

fn accumulate(dims: usize, rows: &[Vec<f64>]) -> CovarianceAccumulator {
    let mut acc = CovarianceAccumulator::new(dims).unwrap();
    for row in rows {
        acc.push(row).unwrap();
    }
    acc
}

/// Agreement to relative 1e-12 of the natural scales: `|mean_i|` plus the spread for means,
/// `sqrt(C_ii C_jj)` for co-moments (an off-diagonal co-moment may be near zero).
fn assert_close(
    a: &CovarianceAccumulator,
    means: &[f64],
    comoments: &[Vec<f64>],
) -> Result<(), TestCaseError> {
    let d = a.dims();
    let n = a.count().max(1) as f64;
    for i in 0..d {
        let scale = means[i].abs() + (comoments[i][i] / n).sqrt();
        prop_assert!(
            (a.mean(i) - means[i]).abs() <= 1e-12 * scale,
            "mean {i}: {} vs {}",
            a.mean(i),
            means[i]
        );
        for j in 0..d {
            let scale = (comoments[i][i] * comoments[j][j]).sqrt();
            prop_assert!(
                (a.comoment(i, j) - comoments[i][j]).abs() <= 1e-12 * scale,
                "C[{i}][{j}]: {} vs {}",
                a.comoment(i, j),
                comoments[i][j]
            );
        }
    }
    Ok(())
}

fn moments_of(acc: &CovarianceAccumulator) -> (Vec<f64>, Vec<Vec<f64>>) {
    let d = acc.dims();
    let comoments = (0..d)
        .map(|i| (0..d).map(|j| acc.comoment(i, j)).collect())
        .collect();
    (acc.means().to_vec(), comoments)
}

proptest! {
    #![proptest_config(config(256, 0xc0a))]

    /// Merging the parts of any split gives the one-pass accumulator.
    #[test]
    fn merge_equals_one_pass((dims, rows) in vectors(), cuts in prop::collection::vec(0.0..1.0f64, 0..4)) {
        let whole = accumulate(dims, &rows);
        let mut bounds: Vec<usize> = cuts.iter().map(|c| (c * rows.len() as f64) as usize).collect();
        bounds.push(0);
        bounds.push(rows.len());
        bounds.sort_unstable();
        let mut merged = CovarianceAccumulator::new(dims).unwrap();
        for w in bounds.windows(2) {
            merged.merge(&accumulate(dims, &rows[w[0]..w[1]])).unwrap();
        }
        prop_assert_eq!(merged.count(), whole.count());
        let (means, comoments) = moments_of(&whole);
        assert_close(&merged, &means, &comoments)?;
    }

    /// One pass agrees with the two-pass textbook computation, and its diagonal is exactly
    /// what the scalar Accumulator computes.
    #[test]
    fn one_pass_matches_two_pass((dims, rows) in vectors()) {
        let acc = accumulate(dims, &rows);
        let n = rows.len();
        let means: Vec<f64> = (0..dims)
            .map(|i| if n == 0 { 0.0 } else { rows.iter().map(|r| r[i]).sum::<f64>() / n as f64 })
            .collect();
        let comoments: Vec<Vec<f64>> = (0..dims)
            .map(|i| (0..dims).map(|j| rows.iter().map(|r| (r[i] - means[i]) * (r[j] - means[j])).sum()).collect())
            .collect();
        assert_close(&acc, &means, &comoments)?;
        for i in 0..dims {
            let mut scalar = Accumulator::new();
            for r in &rows {
                scalar.push(r[i]);
            }
            prop_assert_eq!(scalar.mean(), acc.mean(i));
            prop_assert_eq!(scalar.m2(), acc.comoment(i, i));
            if n >= 2 {
                prop_assert_eq!(scalar.variance(), acc.variance(i));
                let expected = acc.comoment(i, 0) / (n - 1) as f64;
                prop_assert_eq!(acc.covariance(i, 0), expected);
                prop_assert_eq!(acc.covariance_matrix()[i * dims], expected);
            }
        }
    }
}

#[test]
fn covariance_accumulator_counts_non_finite_and_rejects_wrong_lengths() {
    let mut acc = CovarianceAccumulator::new(3).unwrap();
    acc.push(&[1.0, 2.0, 3.0]).unwrap();
    acc.push(&[1.0, f64::NAN, 3.0]).unwrap();
    acc.push(&[f64::NEG_INFINITY, 0.0, 0.0]).unwrap();
    acc.push(&[2.0, 2.0, 5.0]).unwrap();
    assert_eq!((acc.count(), acc.non_finite()), (2, 2));
    assert_eq!(acc.means(), &[1.5, 2.0, 4.0]);
    assert_eq!(acc.covariance(0, 2), 1.0);
    assert!(acc.correlation(0, 1).is_nan()); // entry 1 is constant
    assert!(matches!(
        acc.push(&[1.0, 2.0]),
        Err(Error::DimensionMismatch {
            expected: 3,
            found: 2,
            ..
        })
    ));
    let mut other = CovarianceAccumulator::new(2).unwrap();
    assert!(other.merge(&acc).is_err());
    // Merging keeps non-finite counts, also into an empty accumulator.
    let mut empty = CovarianceAccumulator::new(3).unwrap();
    empty.merge(&acc).unwrap();
    assert_eq!(empty, acc);
    assert!(CovarianceAccumulator::new(0).is_err());
}

/// The regression estimator's inputs are exactly what a block of contributions gives: check the
/// accumulator against the estimator interface on a block (f and g evaluated together).
#[test]
fn covariance_of_f_and_control_matches_the_closed_form() {
    let m = exp_moments();
    let sampler = Independent::new(1, 21).unwrap();
    let n = 200_000;
    let mut points = Points::new(1, n).unwrap();
    mcint::Sampler::fill(&sampler, 0, &mut points).unwrap();
    let mut acc = CovarianceAccumulator::new(2).unwrap();
    for &x in points.column(0) {
        acc.push(&[x.exp(), x]).unwrap();
    }
    // Var of the sample covariance of (Y, Z) ~ Var[(Y - EY)(Z - EZ)] / n.
    let mu22 = integrate01(|x| ((x.exp() - m.mean) * (x - 0.5)).powi(2));
    let tolerance = 4.5 * ((mu22 - m.cov_f[0].powi(2)) / n as f64).sqrt();
    assert!((acc.covariance(0, 1) - m.cov_f[0]).abs() < tolerance);
}

/// A control with a large constant part, `1e15 + x` with integral `1e15 + 1/2`, is as good as
/// `x`: its deviation from its integral is formed first. The estimators formed `f - beta g`
/// near 1.7e15, keeping f to a quarter: 1.607 +- 0.0004 for e - 1 = 1.718 (fitted, 277
/// standard errors off) and 1.670 (fixed, beta = 1.69, 131 off).
#[test]
fn controls_with_a_large_constant_part_keep_the_estimate() {
    let exact = E - 1.0;
    for offset in [1e13, 1e14, 1e15] {
        let fitted =
            Integrator::with_controls(|x: &[f64]| x[0].exp(), UniformBox::unit(1).unwrap())
                .control(move |x: &[f64]| offset + x[0], offset + 0.5)
                .samples(100_000)
                .seed(7)
                .run()
                .unwrap();
        let se = fitted.std_error.unwrap();
        assert!(
            (fitted.mean - exact).abs() <= 5.0 * se,
            "{offset:e}: {fitted:?}"
        );
        let fixed = FixedControlVariate::new(
            |x: &[f64]| x[0].exp(),
            move |x: &[f64]| offset + x[0],
            offset + 0.5,
            UniformBox::unit(1).unwrap(),
        )
        .unwrap()
        .with_coefficient(1.69)
        .unwrap();
        let fixed = Integrator::new(fixed)
            .samples(100_000)
            .seed(7)
            .run()
            .unwrap();
        let se = fixed.std_error.unwrap();
        assert!(
            (fixed.mean - exact).abs() <= 5.0 * se,
            "{offset:e}: {fixed:?}"
        );
    }
}
