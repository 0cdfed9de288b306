//! `mcint::multilevel`: Giles' multilevel Monte Carlo and multilevel QMC on SDE paths.
//!
//! References are closed forms (Black-Scholes call and digital; Goldman-Sosin-Gatto's
//! floating-strike lookback; Merton's and Reiner-Rubinstein's down-and-out call, all for a
//! continuously monitored path), computed here with `libm`'s `erfc`, and for the arithmetic
//! Asian call an RQMC integral over exact GBM paths. The RMSE bound `1.2 eps` over 50 seeds is
//! the issue's: the algorithm aims at `eps`, and the RMSE of 50 runs is itself uncertain by
//! about `1 / sqrt(100) = 10%`. The smallest targets here are `0.01` (the issue's `1e-3`
//! study takes hours of two cores; `docs/measurements.md` has it).

use mcint::measure::{Construction, GeometricBrownianMotion};
use mcint::multilevel::{Level, Multilevel, MultilevelEstimate, Payoff, Scheme, Sde, SdeLevels};
use mcint::sampler::{Sampler, Scramble, Sobol};
use mcint::stats::{StopReason, Warning};
use mcint::{CancelToken, Error, Integrator, Points};

const S0: f64 = 100.0;
const STRIKE: f64 = 100.0;
const RATE: f64 = 0.05;
const SIGMA: f64 = 0.2;
/// Black-Scholes, S0 = K = 100, r = 0.05, sigma = 0.2, T = 1.
const EUROPEAN: f64 = 10.450583572185565;
const SEEDS: u64 = 50;

fn normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / std::f64::consts::SQRT_2)
}

fn discount() -> f64 {
    (-RATE).exp()
}

/// `e^{-r} Phi(d2)`.
fn digital_exact() -> f64 {
    let d2 = (RATE - 0.5 * SIGMA * SIGMA) / SIGMA;
    discount() * normal_cdf(d2)
}

/// Goldman, Sosin and Gatto (1979), the floating-strike lookback call with the running
/// minimum at S0, as Hull's Options, Futures and Other Derivatives states it.
fn lookback_exact() -> f64 {
    let k = SIGMA * SIGMA / (2.0 * RATE);
    let a1 = (RATE + 0.5 * SIGMA * SIGMA) / SIGMA;
    let a2 = a1 - SIGMA;
    let a3 = (-RATE + 0.5 * SIGMA * SIGMA) / SIGMA;
    S0 * normal_cdf(a1)
        - S0 * k * normal_cdf(-a1)
        - S0 * discount() * (normal_cdf(a2) - k * normal_cdf(-a3))
}

/// The down-and-out call with barrier H below the strike: the call minus the down-and-in
/// (Reiner and Rubinstein 1991).
fn barrier_exact(h: f64) -> f64 {
    let lambda = (RATE + 0.5 * SIGMA * SIGMA) / (SIGMA * SIGMA);
    let y = (h * h / (S0 * STRIKE)).ln() / SIGMA + lambda * SIGMA;
    let down_in = S0 * (h / S0).powf(2.0 * lambda) * normal_cdf(y)
        - STRIKE * discount() * (h / S0).powf(2.0 * lambda - 2.0) * normal_cdf(y - SIGMA);
    EUROPEAN - down_in
}

/// The continuously averaged Asian call, another way: exact GBM prices on 512 dates, the
/// trapezoidal average (error O(h^2), about 1e-5 here), by RQMC with a Brownian bridge.
fn asian_reference() -> (f64, f64) {
    let n = 512;
    let times: Vec<f64> = (1..=n).map(|k| k as f64 / n as f64).collect();
    let gbm = GeometricBrownianMotion::new(S0, RATE, SIGMA, times, Construction::Bridge).unwrap();
    let payoff = move |s: &[f64]| {
        let inner: f64 = s[..n - 1].iter().sum();
        let average = (0.5 * (S0 + s[n - 1]) + inner) / n as f64;
        (-RATE).exp() * (average - STRIKE).max(0.0)
    };
    let e = Integrator::expectation(payoff, gbm)
        .sampler(Sobol::new(n, Scramble::Owen, 11).unwrap())
        .samples(1 << 13)
        .replicates(16)
        .run()
        .unwrap();
    (e.mean, e.std_error.unwrap())
}

fn gbm_levels(scheme: Scheme, payoff: Payoff) -> SdeLevels {
    SdeLevels::new(Sde::gbm(S0, RATE, SIGMA).unwrap(), scheme, payoff, 1.0)
        .unwrap()
        .discount(discount())
        .unwrap()
}

/// RMSE against `exact` and mean cost over the seeds.
fn study(levels: impl Fn() -> SdeLevels, eps: f64, qmc: bool, exact: f64) -> (f64, f64) {
    let (mut squares, mut cost) = (0.0, 0.0);
    for seed in 0..SEEDS {
        let run = Multilevel::new(levels())
            .rmse(eps)
            .qmc(qmc)
            .seed(seed)
            .run()
            .unwrap();
        assert!(run.converged, "seed {seed}: {run}");
        squares += (run.estimate - exact).powi(2);
        cost += run.cost;
    }
    ((squares / SEEDS as f64).sqrt(), cost / SEEDS as f64)
}

#[test]
fn european_call_meets_its_rmse_at_eps_squared_cost() {
    for (scheme, targets) in [
        (Scheme::Milstein, &[0.1, 0.03, 0.01][..]),
        (Scheme::Euler, &[0.1, 0.03][..]),
    ] {
        let levels = || gbm_levels(scheme, Payoff::european_call(STRIKE).unwrap());
        let mut scaled = Vec::new();
        for &eps in targets {
            let (rmse, cost) = study(levels, eps, false, EUROPEAN);
            assert!(rmse <= 1.2 * eps, "{scheme:?} eps {eps}: RMSE {rmse}");
            scaled.push(cost * eps * eps);
        }
        // Cost ~ eps^-2 (Milstein, beta = 2 > gamma = 1), eps^-2 log^2 eps (Euler, beta =
        // gamma = 1): cost * eps^2 may grow by the log factor at most, with a margin of 1.5
        // for the randomness of N_l and of the number of levels.
        let (first, last) = (targets[0], targets[targets.len() - 1]);
        let allowed = match scheme {
            Scheme::Milstein => 1.5,
            Scheme::Euler => 1.5 * (last.ln() / first.ln()).powi(2),
        };
        let growth = scaled[scaled.len() - 1] / scaled[0];
        assert!(growth <= allowed, "{scheme:?}: cost * eps^2 {scaled:?}");
    }
}

#[test]
fn multilevel_costs_a_tenth_of_standard_monte_carlo() {
    let run = Multilevel::new(gbm_levels(
        Scheme::Milstein,
        Payoff::european_call(STRIKE).unwrap(),
    ))
    .rmse(0.01)
    .seed(3)
    .run()
    .unwrap();
    assert!(run.standard_mc_cost >= 10.0 * run.cost, "{run}");
}

#[test]
fn path_dependent_payoffs_meet_their_rmse() {
    let (asian, asian_se) = asian_reference();
    assert!(asian_se < 2e-3, "{asian_se}");
    let cases = [
        (
            Payoff::digital_call(STRIKE).unwrap(),
            digital_exact(),
            0.003,
        ),
        (Payoff::asian_call(STRIKE).unwrap(), asian, 0.03),
        (Payoff::lookback(), lookback_exact(), 0.03),
        (
            Payoff::down_and_out_call(STRIKE, 85.0).unwrap(),
            barrier_exact(85.0),
            0.03,
        ),
    ];
    for (payoff, exact, eps) in cases {
        let name = payoff.name();
        let levels = || gbm_levels(Scheme::Milstein, payoff.clone());
        let (rmse, _) = study(levels, eps, false, exact);
        assert!(
            rmse <= 1.2 * eps,
            "{name}: RMSE {rmse} at eps {eps} (exact {exact})"
        );
    }
}

/// Multilevel QMC meets the same targets, and spends a third of multilevel Monte Carlo or
/// less (mean cost over 10 seeds; the measured gap is far wider, see docs/measurements.md).
#[test]
fn multilevel_qmc_spends_a_third_of_multilevel_monte_carlo() {
    let (asian, _) = asian_reference();
    for (payoff, exact) in [
        (Payoff::european_call(STRIKE).unwrap(), EUROPEAN),
        (Payoff::asian_call(STRIKE).unwrap(), asian),
    ] {
        let name = payoff.name();
        let levels = || gbm_levels(Scheme::Milstein, payoff.clone());
        let (rmse, _) = study(levels, 0.03, true, exact);
        assert!(rmse <= 1.2 * 0.03, "{name}: QMC RMSE {rmse}");
        let mean_cost = |qmc: bool| {
            (0..10)
                .map(|seed| {
                    let run = Multilevel::new(levels()).rmse(0.01).qmc(qmc).seed(seed);
                    run.run().unwrap().cost
                })
                .sum::<f64>()
                / 10.0
        };
        let (mc, qmc) = (mean_cost(false), mean_cost(true));
        assert!(3.0 * qmc <= mc, "{name}: QMC {qmc:.3e}, MC {mc:.3e}");
    }
}

/// Giles' `mlmc_test` pattern for GBM: Euler's variance decays like `h` (beta = 1), Milstein's
/// like `h^2`, both with weak order 1, and every level's coarse path has the law of the
/// previous level's fine path.
#[test]
fn the_survey_shows_the_published_rates() {
    for (scheme, beta) in [(Scheme::Euler, 1.0), (Scheme::Milstein, 2.0)] {
        let levels = gbm_levels(scheme, Payoff::european_call(STRIKE).unwrap());
        let survey = Multilevel::new(levels).seed(1).survey(8, 100_000).unwrap();
        assert!((survey.beta - beta).abs() < 0.25, "{scheme:?}: {survey}");
        assert!((survey.alpha - 1.0).abs() < 0.4, "{scheme:?}: {survey}");
        assert!((survey.gamma - 1.0).abs() < 0.05, "{scheme:?}: {survey}");
        assert!(
            survey
                .levels
                .iter()
                .skip(1)
                .all(|l| l.consistency.unwrap() < 1.0),
            "{survey}"
        );
        assert_eq!(survey.levels.len(), 9);
    }
}

fn pinned_run(threads: usize, qmc: bool) -> MultilevelEstimate {
    Multilevel::new(gbm_levels(Scheme::Milstein, Payoff::lookback()))
        .rmse(0.05)
        .qmc(qmc)
        .seed(9)
        .threads(threads)
        .run()
        .unwrap()
}

#[test]
fn results_are_the_same_bits_on_any_thread_count() {
    for qmc in [false, true] {
        let one = pinned_run(1, qmc);
        for threads in [2, 3, 8] {
            assert_eq!(
                pinned_run(threads, qmc),
                one,
                "qmc {qmc}, {threads} threads"
            );
        }
    }
}

/// Heston with a frozen variance (kappa = xi = 0) is GBM with sigma = sqrt(v0): the general
/// noise path, stepped by Euler, prices the Black-Scholes call.
#[test]
fn heston_with_frozen_variance_prices_black_scholes() {
    let levels = || {
        let sde = Sde::heston(S0, SIGMA * SIGMA, RATE, 0.0, 0.04, 0.0, -0.5).unwrap();
        SdeLevels::new(
            sde,
            Scheme::Euler,
            Payoff::european_call(STRIKE).unwrap(),
            1.0,
        )
        .unwrap()
        .discount(discount())
        .unwrap()
    };
    let (rmse, _) = study(levels, 0.1, false, EUROPEAN);
    assert!(rmse <= 0.12, "{rmse}");
}

/// `dX = X (0.1 dW_1 + 0.2 dW_2)` is GBM with `sigma^2 = 0.05`; its noise commutes, so
/// Milstein with the `L^j b_k` terms has `beta = 2`. Two independent GBMs as a diagonal
/// system, read through a path closure, price the first one's call.
#[test]
fn general_and_diagonal_noise_step_as_scalar_gbm() {
    let s = [0.1, 0.2];
    let general = Sde::general(
        vec![S0],
        2,
        |_, x, a| a[0] = RATE * x[0],
        move |_, x, b| {
            b[0] = s[0] * x[0];
            b[1] = s[1] * x[0];
        },
    )
    .unwrap()
    .milstein_terms(move |_, x, l| {
        for j in 0..2 {
            for k in 0..2 {
                l[j * 2 + k] = s[j] * s[k] * x[0];
            }
        }
    })
    .unwrap();
    let levels = SdeLevels::new(
        general,
        Scheme::Milstein,
        Payoff::european_call(STRIKE).unwrap(),
        1.0,
    )
    .unwrap();
    let survey = Multilevel::new(levels).seed(2).survey(6, 50_000).unwrap();
    assert!((survey.beta - 2.0).abs() < 0.3, "{survey}");
    let sigma = 0.05f64.sqrt();
    let d1 = (RATE + 0.5 * sigma * sigma) / sigma;
    let exact = (S0 * normal_cdf(d1) - STRIKE * discount() * normal_cdf(d1 - sigma)) / discount();
    let last = survey.levels.last().unwrap();
    let sampled: f64 = survey.levels.iter().map(|l| l.mean).sum();
    let se = (last.fine_variance / last.samples as f64).sqrt();
    assert!(
        (sampled - exact).abs() < 5.0 * se + survey.bias,
        "{sampled} vs {exact}, bias estimate {}",
        survey.bias
    );

    let pair = Sde::diagonal(
        vec![S0, 50.0],
        |_, x, a| {
            a[0] = RATE * x[0];
            a[1] = RATE * x[1];
        },
        |_, x, b| {
            b[0] = SIGMA * x[0];
            b[1] = 0.3 * x[1];
        },
    )
    .unwrap()
    .diagonal_derivative(|_, _, d| {
        d[0] = SIGMA;
        d[1] = 0.3;
    })
    .unwrap();
    let first = Payoff::on_path(|p| (p.last()[0] - STRIKE).max(0.0));
    let levels = SdeLevels::new(pair, Scheme::Milstein, first, 1.0)
        .unwrap()
        .discount(discount())
        .unwrap();
    let run = Multilevel::new(levels).rmse(0.05).seed(4).run().unwrap();
    assert!((run.estimate - EUROPEAN).abs() < 5.0 * 0.05, "{run}");
    assert!(run.beta > 1.5, "{run}");
}

#[test]
fn refinement_factor_four_keeps_the_rates() {
    let levels = gbm_levels(Scheme::Euler, Payoff::european_call(STRIKE).unwrap())
        .refinement_factor(4)
        .unwrap();
    assert_eq!(levels.refinement(), 4);
    let survey = Multilevel::new(levels).seed(5).survey(4, 50_000).unwrap();
    // Rates are per level in base M: Euler's beta stays 1.
    assert!((survey.beta - 1.0).abs() < 0.25, "{survey}");
}

/// A model whose samples panic or turn non-finite at one level.
struct Faulty {
    nan: bool,
}

impl Level for Faulty {
    fn dims(&self, _: usize) -> usize {
        1
    }
    fn cost(&self, level: usize) -> f64 {
        (1u64 << level) as f64
    }
    fn sample(&self, level: usize, u: &[f64], _: &mut Vec<f64>) -> (f64, f64) {
        if level == 2 && u[0] < 0.01 {
            if self.nan {
                return (f64::NAN, 0.0);
            }
            panic!("level two broke");
        }
        (u[0], if level == 0 { 0.0 } else { u[0] })
    }
}

/// Differences near 1e90: their squares fit in f64, their fourth powers do not.
struct Huge;

impl Level for Huge {
    fn dims(&self, _: usize) -> usize {
        1
    }
    fn cost(&self, level: usize) -> f64 {
        (1u64 << level) as f64
    }
    fn sample(&self, level: usize, u: &[f64], _: &mut Vec<f64>) -> (f64, f64) {
        let fine = 1e90 * (u[0] + 1.0);
        (fine, if level == 0 { 0.0 } else { 0.5 * fine })
    }
}

#[test]
fn a_kurtosis_past_f64_is_left_out_not_nan() {
    let survey = Multilevel::new(Huge).seed(2).survey(2, 1000).unwrap();
    assert!(
        survey.levels.iter().all(|l| l.kurtosis.is_none()),
        "{survey}"
    );
    assert!(
        survey.levels.iter().all(|l| l.variance.is_finite()),
        "{survey}"
    );
    assert!(!survey.to_string().contains("NaN"), "{survey}");
}

#[test]
fn bad_input_and_broken_models_are_errors() {
    let run = |f: Faulty| Multilevel::new(f).rmse(0.01).seed(1).run().unwrap_err();
    let nan = run(Faulty { nan: true }).to_string();
    assert!(nan.contains("level 2") && nan.contains("NaN"), "{nan}");
    assert!(
        matches!(
            run(Faulty { nan: false }),
            Error::IntegrandPanicked { ref message, .. } if message == "level two broke (in level 2)"
        ),
        "the panic names its level"
    );
    // A model that panics on every sample: the checkpoint's probe of the model does not
    // panic with it; the run from the checkpoint reports the panic.
    struct Panics;
    impl Level for Panics {
        fn dims(&self, _: usize) -> usize {
            1
        }
        fn cost(&self, level: usize) -> f64 {
            (1u64 << level) as f64
        }
        fn sample(&self, _: usize, _: &[f64], _: &mut Vec<f64>) -> (f64, f64) {
            panic!("every sample panics")
        }
    }
    let mut saved = Multilevel::new(Panics).rmse(0.01).checkpoint().unwrap();
    let resumed = Multilevel::new(Panics).rmse(0.01).run_from(&mut saved);
    assert!(matches!(resumed, Err(Error::IntegrandPanicked { .. })));
    let levels = || gbm_levels(Scheme::Euler, Payoff::european_call(STRIKE).unwrap());
    let err = |m: Multilevel<SdeLevels>| m.run().unwrap_err().to_string();
    assert!(err(Multilevel::new(levels())).contains("rmse"));
    assert!(err(Multilevel::new(levels()).rmse(f64::NAN)).contains("above 0"));
    for factor in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let call = SdeLevels::new(
            Sde::gbm(S0, RATE, SIGMA).unwrap(),
            Scheme::Euler,
            Payoff::european_call(STRIKE).unwrap(),
            1.0,
        );
        let refused = call.unwrap().discount(factor).err().map(|e| e.to_string());
        assert!(
            refused.as_ref().is_some_and(|e| e.contains("discount")),
            "{factor}: {refused:?}"
        );
    }
    assert!(
        err(Multilevel::new(levels()).rmse(0.1).qmc(true).replicates(1)).contains("at least 2")
    );
    assert!(
        err(Multilevel::new(levels())
            .rmse(0.1)
            .qmc(true)
            .initial_samples(6))
        .contains("power of 2")
    );
    assert!(
        err(Multilevel::new(levels())
            .rmse(0.1)
            .min_level(5)
            .max_level(3))
        .contains("min_level")
    );
    assert!(err(Multilevel::new(levels()).rmse(0.1).max_cost(10.0)).contains("max_cost"));
    assert!(err(Multilevel::new(levels()).rmse(0.1).threads(0)).contains("threads"));
    // Levels too deep for Sobol' points are refused up front.
    assert!(
        err(Multilevel::new(levels())
            .rmse(0.1)
            .qmc(true)
            .min_level(16)
            .max_level(20))
        .contains("fit the sampler")
    );
    assert!(Multilevel::new(levels()).survey(0, 100).is_err());
    assert!(Multilevel::new(levels()).survey(3, 1).is_err());
    // Under QMC a randomization is one Sobol' pass of 2^32 points.
    let past_a_pass = Multilevel::new(levels())
        .qmc(true)
        .survey(3, (1 << 32) + 1)
        .unwrap_err();
    assert!(
        past_a_pass.to_string().contains("2 to 2^32 with qmc"),
        "{past_a_pass}"
    );
    assert!(
        SdeLevels::new(
            Sde::gbm(S0, RATE, SIGMA).unwrap(),
            Scheme::Euler,
            Payoff::lookback(),
            0.0
        )
        .is_err()
    );
    assert!(
        gbm_levels(Scheme::Euler, Payoff::lookback())
            .refinement_factor(1)
            .is_err()
    );
}

#[test]
fn limits_stop_a_run_with_the_estimate_so_far() {
    let levels = || gbm_levels(Scheme::Euler, Payoff::european_call(STRIKE).unwrap());
    let capped = Multilevel::new(levels())
        .rmse(1e-3)
        .max_cost(2e6)
        .seed(1)
        .run()
        .unwrap();
    assert_eq!(capped.stop, StopReason::MaxEvaluations);
    assert!(!capped.converged && capped.cost <= 2e6 && !capped.warnings.is_empty());
    let token = CancelToken::new();
    token.cancel();
    let err = Multilevel::new(levels())
        .rmse(0.01)
        .cancel_token(token)
        .run()
        .unwrap_err();
    assert!(
        matches!(
            err,
            Error::Interrupted {
                stop: StopReason::Cancelled,
                ..
            }
        ),
        "{err}"
    );
    let deep = Multilevel::new(levels())
        .rmse(0.003)
        .min_level(1)
        .max_level(2)
        .seed(1)
        .run()
        .unwrap();
    assert_eq!(deep.stop, StopReason::MaxLevel);
    assert_eq!(deep.warnings[0].kind(), "bias-above-target");
    // One sentence, without the run of spaces a lost line continuation once left in it.
    let text = deep.warnings[0].to_string();
    assert!(text.contains("at level 2, the deepest allowed"), "{text}");
    assert!(!text.contains("  "), "{text}");
}

/// A run cancelled midway (by its own progress callback, after about half its cost) and
/// resumed from its checkpoint, saved as JSON and read back, ends with the bits of the run
/// that was never stopped; an altered or foreign checkpoint is refused.
#[test]
fn checkpoints_resume_to_the_uninterrupted_run() {
    for qmc in [false, true] {
        let runner = || {
            Multilevel::new(gbm_levels(
                Scheme::Milstein,
                Payoff::asian_call(STRIKE).unwrap(),
            ))
            .rmse(0.02)
            .qmc(qmc)
            .seed(21)
        };
        let whole = runner().run().unwrap();
        let token = CancelToken::new();
        let stopper = token.clone();
        let half = whole.cost / 2.0;
        let mut state = runner().checkpoint().unwrap();
        let cut = runner()
            .cancel_token(token)
            .progress(move |done, _| {
                if done as f64 > half {
                    stopper.cancel();
                }
            })
            .run_from(&mut state)
            .unwrap();
        assert_eq!(cut.stop, StopReason::Cancelled, "qmc {qmc}");
        assert!(!cut.converged && cut.cost < whole.cost);
        let text = serde_json::to_string(&state).unwrap();
        let mut read: mcint::multilevel::MultilevelCheckpoint =
            serde_json::from_str(&text).unwrap();
        let resumed = runner().threads(3).run_from(&mut read).unwrap();
        assert_eq!(resumed, whole, "qmc {qmc}");
        // A finished checkpoint gives the same result again, at no cost.
        assert_eq!(runner().run_from(&mut read).unwrap(), whole);

        let altered = text.replacen("\"spent\":", "\"spent\":1", 1);
        let mut altered: mcint::multilevel::MultilevelCheckpoint =
            serde_json::from_str(&altered).unwrap();
        let err = runner().run_from(&mut altered).unwrap_err().to_string();
        assert!(err.contains("checksum"), "{err}");
        let err = runner()
            .rmse(0.03)
            .run_from(&mut state)
            .unwrap_err()
            .to_string();
        assert!(err.contains("fingerprint"), "{err}");
        // Another model with the same levels (dims and costs): another strike, or another
        // payoff, is refused too, not resumed into a mixture of both.
        for payoff in [
            Payoff::asian_call(STRIKE + 50.0).unwrap(),
            Payoff::european_call(STRIKE).unwrap(),
        ] {
            let other = Multilevel::new(gbm_levels(Scheme::Milstein, payoff))
                .rmse(0.02)
                .qmc(qmc)
                .seed(21);
            let err = other.run_from(&mut state).unwrap_err().to_string();
            assert!(err.contains("fingerprint"), "{err}");
        }
    }
}

/// A checkpoint is refused by a model that differs only in a parameter (the volatility, 5%
/// apart), for every payoff: the fingerprint's probe of the model once sampled one point at
/// which a call was out of the money under both volatilities, and `mlmc --sigma 0.3`
/// reported the finished run of `--sigma 0.2` as its own.
#[test]
fn checkpoints_of_another_volatility_are_refused() {
    let payoffs = [
        Payoff::european_call(STRIKE).unwrap(),
        Payoff::asian_call(STRIKE).unwrap(),
        Payoff::digital_call(STRIKE).unwrap(),
        Payoff::down_and_out_call(STRIKE, 85.0).unwrap(),
        Payoff::lookback(),
    ];
    for payoff in payoffs {
        let runner = |sigma: f64| {
            let levels = SdeLevels::new(
                Sde::gbm(S0, RATE, sigma).unwrap(),
                Scheme::Milstein,
                payoff.clone(),
                1.0,
            )
            .unwrap();
            Multilevel::new(levels).rmse(0.02).seed(21)
        };
        let mut state = runner(SIGMA).checkpoint().unwrap();
        let err = runner(SIGMA * 1.05)
            .run_from(&mut state)
            .unwrap_err()
            .to_string();
        assert!(err.contains("fingerprint"), "{payoff:?}: {err}");
    }
}

/// Prices scaled by 2^664 (about 1e200) or 2^-700 (about 1e-211): Giles' statistics are kept
/// in units of a power of two near the samples, so the run is the ordinary one scaled (GBM,
/// Milstein and the call are linear in S0 and K; the accumulators sum values that need units
/// one by one, so the last digits differ). Before, squares of prices near
/// 1e200 overflowed (the run ended in `Error::Overflow`), and near 1e-160 the variances
/// underflowed to 0: a standard error of 0 and a tolerance "met" on no evidence.
#[test]
fn prices_far_from_1_give_the_ordinary_run_scaled() {
    let european = |factor: f64| Payoff::european_call(STRIKE * factor).unwrap();
    let lookback = |_: f64| Payoff::lookback();
    let barrier = |factor: f64| Payoff::down_and_out_call(STRIKE * factor, 85.0 * factor).unwrap();
    let payoffs: [(&str, &dyn Fn(f64) -> Payoff); 3] = [
        ("european", &european),
        ("lookback", &lookback),
        ("barrier", &barrier),
    ];
    let levels = |factor: f64, payoff: &dyn Fn(f64) -> Payoff| {
        SdeLevels::new(
            Sde::gbm(S0 * factor, RATE, SIGMA).unwrap(),
            Scheme::Milstein,
            payoff(factor),
            1.0,
        )
        .unwrap()
        .discount(discount())
        .unwrap()
    };
    for (name, payoff) in payoffs {
        let run = |factor: f64| {
            Multilevel::new(levels(factor, payoff))
                .rmse(0.05 * factor)
                .seed(3)
                .run()
                .unwrap()
        };
        let ordinary = run(1.0);
        // 2^-262: the fourth powers of the differences are subnormal; the bridges of the
        // lookback and the barrier square prices, which leave f64's range at 2^+-664 unless
        // taken in units near the prices.
        for exponent in [664, -262, -700] {
            let factor = 2f64.powi(exponent);
            let scaled = run(factor);
            let what = format!("{name}, 2^{exponent}");
            let close = |a: f64, b: f64| (a / (b * factor) - 1.0).abs() < 1e-9;
            assert!(close(scaled.estimate, ordinary.estimate), "{what}");
            assert!(close(scaled.std_error, ordinary.std_error), "{what}");
            assert!(close(scaled.bias, ordinary.bias), "{what}");
            assert_eq!(scaled.cost, ordinary.cost, "{what}");
            assert_eq!(scaled.stop, ordinary.stop, "{what}");
            // The kurtosis is scale-free: the ordinary one, or none where the powers it needs
            // leave f64's range; never a number made of rounding.
            for (s, o) in scaled.levels.iter().zip(&ordinary.levels) {
                if let Some(k) = s.kurtosis {
                    let exact = o.kurtosis.unwrap();
                    assert!((k / exact - 1.0).abs() < 1e-9, "{what}: {k} for {exact}");
                }
            }
        }
    }
    // A target far below such prices' spread: its square underflows in the run's units. The
    // samples it wants are then more than any cost limit (before, they counted as none, and
    // the run added levels down to the deepest allowed).
    let far = Multilevel::new(levels(2f64.powi(664), &european))
        .rmse(0.05)
        .seed(3)
        .run()
        .unwrap();
    assert_eq!(far.stop, StopReason::MaxEvaluations);
    assert_eq!(far.levels.len(), 3, "{far}");
}

/// `E[U^2]` on levels whose coarse sample is `scale` times `u^2` plus the previous level's
/// bias: with `scale = 1` it has the law of the previous fine sample; otherwise every coarse
/// mean is off by `(scale - 1) / 3`, a coupling error that no telescoping sum survives.
struct Coupled {
    scale: f64,
}

impl Level for Coupled {
    fn dims(&self, _: usize) -> usize {
        1
    }
    fn cost(&self, level: usize) -> f64 {
        (1u64 << level) as f64
    }
    fn sample(&self, level: usize, u: &[f64], _: &mut Vec<f64>) -> (f64, f64) {
        let fine = u[0] * u[0] + 0.5f64.powi(level as i32);
        let coarse = match level {
            0 => 0.0,
            _ => self.scale * u[0] * u[0] + 0.5f64.powi(level as i32 - 1),
        };
        (fine, coarse)
    }
}

/// A coupling error stops the run where it shows: `Coupled { scale: 1.1 }` has corrections of
/// mean about `-1/30` on every level, so the bias estimate never falls and the run would add
/// levels to the deepest allowed (20). Level 1's check is about `0.033 / (3 x 0.63 /
/// sqrt(N))` (give or take 0.25): 0.55 at the first 1000 samples, 2 at about 13,000. For
/// `eps = 0.001` the allocation gives level 1 (`V_1` about `9e-4`) about 17,000 samples with
/// three levels and 20,000 with four, so the run stops when about to add the fourth level, or
/// one or two later. The same levels rightly coupled meet the target.
#[test]
fn a_coupling_error_stops_the_run_before_the_deepest_level() {
    let run = |scale| {
        Multilevel::new(Coupled { scale })
            .rmse(0.001)
            .seed(11)
            .run()
            .unwrap()
    };
    let right = run(1.0);
    assert_eq!(right.stop, StopReason::ToleranceMet, "{right}");
    let wrong = run(1.1);
    assert_eq!(wrong.stop, StopReason::InconsistentLevels, "{wrong}");
    assert!(!wrong.converged);
    assert!(wrong.levels.len() <= 6, "{wrong}");
    let kinds: Vec<&str> = wrong.warnings.iter().map(|w| w.kind()).collect();
    assert!(kinds.contains(&"inconsistent-levels"), "{kinds:?}");
    assert!(kinds.contains(&"tolerance-not-met"), "{kinds:?}");
    assert_eq!(StopReason::InconsistentLevels.name(), "inconsistent levels");
}

/// Corrections that are zero but for a rare jump (probability `1e-3`): their kurtosis is
/// about 1000.
struct RareJumps;

impl Level for RareJumps {
    fn dims(&self, _: usize) -> usize {
        2
    }
    fn cost(&self, level: usize) -> f64 {
        (1u64 << level) as f64
    }
    fn sample(&self, level: usize, u: &[f64], _: &mut Vec<f64>) -> (f64, f64) {
        let jump = u[1] < 1e-3;
        let p = |l: usize| u[0] + if jump { 0.5f64.powi(l as i32) } else { 0.0 };
        (p(level), if level == 0 { 0.0 } else { p(level - 1) })
    }
}

fn level_warnings(run: &MultilevelEstimate) -> Vec<&Warning> {
    run.warnings
        .iter()
        .filter(|w| {
            matches!(
                w,
                Warning::HeavyTailedLevel { .. } | Warning::InconsistentLevels { .. }
            )
        })
        .collect()
}

/// Giles' consistency check finds a coupling error: the check at each level is the gap over
/// three standard errors, about `(1.1 - 1) / 3 / (3 x 0.63 / sqrt(40000)) = 3.5` here, and
/// under a right coupling it exceeds 1 with probability below `P(|Z| > 3)` per level.
#[test]
fn a_coupling_error_is_a_warning() {
    let survey = |scale| {
        Multilevel::new(Coupled { scale })
            .seed(7)
            .survey(3, 40_000)
            .unwrap()
    };
    let right = survey(1.0);
    assert!(level_warnings(&right).is_empty(), "{right}");
    let wrong = survey(1.1);
    let found = level_warnings(&wrong);
    assert!(
        matches!(found[..], [Warning::InconsistentLevels { level: 1..=3, check }] if *check > 1.0),
        "{wrong}"
    );
    assert_eq!(found[0].kind(), "inconsistent-levels");
    assert!(found[0].to_string().contains("coupling error"), "{wrong}");
}

/// A correction that is a rare jump has a kurtosis near `1 / p = 1000` (about 40 jumps in
/// 40,000 samples, so the estimate is within a factor 2 of it with overwhelming probability),
/// while the GBM levels' corrections stay near 10 (Giles' survey shows 5 to 30).
#[test]
fn a_heavy_tailed_correction_is_a_warning() {
    let jumps = Multilevel::new(RareJumps)
        .seed(3)
        .survey(3, 40_000)
        .unwrap();
    let found = level_warnings(&jumps);
    assert!(
        matches!(found[..], [Warning::HeavyTailedLevel { level: 1..=3, kurtosis }] if *kurtosis > 100.0),
        "{jumps}"
    );
    assert!(found[0].to_string().contains("rare samples"), "{jumps}");
    let gbm = gbm_levels(Scheme::Milstein, Payoff::european_call(STRIKE).unwrap());
    let survey = Multilevel::new(gbm).seed(3).survey(6, 20_000).unwrap();
    assert!(level_warnings(&survey).is_empty(), "{survey}");
}

/// A run draws its samples a block at a time (`sample_block`, which sets a level up once and
/// draws the block's normals in one pass); each must have the bits of `sample` on its own
/// point, for every kind of noise and payoff, Euler and Milstein, at the first levels and
/// past them, with `M = 2` and `4`. (A diagonal system's coefficients fill one value per
/// state: slices of that length.)
#[test]
fn blocks_of_samples_have_the_bits_of_single_samples() {
    let heston = || Sde::heston(S0, 0.04, RATE, 2.0, 0.04, 0.3, -0.7).unwrap();
    let pair = || {
        Sde::diagonal(
            vec![S0, 50.0],
            |_, x, a| a.copy_from_slice(&[RATE * x[0], RATE * x[1]]),
            |_, x, b| b.copy_from_slice(&[SIGMA * x[0], 0.3 * x[1]]),
        )
        .unwrap()
        .diagonal_derivative(|_, _, d| d.copy_from_slice(&[SIGMA, 0.3]))
        .unwrap()
    };
    let gbm = || Sde::gbm(S0, RATE, SIGMA).unwrap();
    let cases = [
        (
            gbm(),
            Scheme::Milstein,
            Payoff::european_call(STRIKE).unwrap(),
            2,
        ),
        (gbm(), Scheme::Euler, Payoff::asian_call(STRIKE).unwrap(), 2),
        (gbm(), Scheme::Milstein, Payoff::lookback(), 4),
        (
            gbm(),
            Scheme::Euler,
            Payoff::digital_call(STRIKE).unwrap(),
            2,
        ),
        (
            heston(),
            Scheme::Euler,
            Payoff::down_and_out_call(STRIKE, 85.0).unwrap(),
            4,
        ),
        (
            pair(),
            Scheme::Milstein,
            Payoff::on_path(|p| p.last()[1]),
            2,
        ),
    ];
    for (sde, scheme, payoff, m) in cases {
        let name = format!("{sde:?} {scheme:?} {payoff:?} M = {m}");
        let levels = SdeLevels::new(sde, scheme, payoff, 1.0)
            .unwrap()
            .refinement_factor(m)
            .unwrap()
            .discount(discount())
            .unwrap();
        for level in [0, 1, 3] {
            let dims = levels.dims(level);
            let mut points = Points::new(dims, 37).unwrap();
            let sobol = Sobol::new(dims, Scramble::Owen, 9).unwrap();
            sobol.fill(0, &mut points).unwrap();
            let (mut fine, mut coarse) = (vec![0.0; 37], vec![0.0; 37]);
            let mut scratch = Vec::new();
            levels.sample_block(level, &points, &mut fine, &mut coarse, &mut scratch);
            for i in 0..37 {
                let u = points.row(i).unwrap();
                let (f, c) = levels.sample(level, &u, &mut Vec::new());
                assert_eq!(
                    (fine[i].to_bits(), coarse[i].to_bits()),
                    (f.to_bits(), c.to_bits()),
                    "{name}, level {level}, sample {i}"
                );
            }
        }
    }
}

/// A path whose state leaves the reals (here a square root of a negative variance, the
/// classic slip in a CIR model) is an error naming the level and sample, for every payoff:
/// the payoffs' comparisons would read a NaN as out of the money and price it at 0.
#[test]
fn a_path_that_leaves_the_reals_is_an_error() {
    let payoffs = [
        Payoff::european_call(0.03).unwrap(),
        Payoff::asian_call(0.03).unwrap(),
        Payoff::digital_call(0.03).unwrap(),
        Payoff::lookback(),
        Payoff::down_and_out_call(0.03, 0.01).unwrap(),
    ];
    for payoff in payoffs {
        let cir = Sde::scalar(0.04, |_, x| 2.0 * (0.04 - x), |_, x| 0.8 * x.sqrt()).unwrap();
        let name = format!("{payoff:?}");
        let levels = SdeLevels::new(cir, Scheme::Euler, payoff, 1.0).unwrap();
        let err = Multilevel::new(levels)
            .rmse(1e-3)
            .seed(1)
            .run()
            .unwrap_err();
        let message = err.to_string();
        assert!(
            message.contains("level sample") && message.contains("NaN"),
            "{name}: {message}"
        );
    }
    // At a deep level the message shows the point's first coordinates, not all of them.
    let nan_when_fine = Payoff::on_path(|p| if p.len() > 1000 { f64::NAN } else { 1.0 });
    let gbm = Sde::gbm(S0, RATE, SIGMA).unwrap();
    let levels = SdeLevels::new(gbm, Scheme::Euler, nan_when_fine, 1.0).unwrap();
    let message = Multilevel::new(levels)
        .survey(10, 10)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("level 10") && message.contains("(1024 coordinates)]"),
        "{message}"
    );
    assert!(message.len() < 1000, "{message}");
}

/// Many Brownian motions: Euler keeps `d * m` diffusion values a step (not the `d * m * m`
/// Milstein terms it does not use: with 131,072 motions those were 137 GB, and the process
/// aborted), and a system whose step would hold more than 2^24 values is refused up front.
#[test]
fn many_brownian_motions_are_affordable_or_refused() {
    let m = 1 << 17;
    let general = |m: usize| {
        let scale = 1.0 / (m as f64).sqrt();
        Sde::general(
            vec![0.0],
            m,
            |_, _, a| a[0] = 0.0,
            move |_, _, b| b.fill(scale),
        )
        .unwrap()
    };
    let call = || Payoff::european_call(0.0).unwrap();
    let levels = SdeLevels::new(general(m), Scheme::Euler, call(), 1.0).unwrap();
    let u = vec![0.5; levels.dims(0)];
    assert_eq!(levels.sample(0, &u, &mut Vec::new()), (0.0, 0.0));

    let terms = general(5000).milstein_terms(|_, _, l| l.fill(0.0)).unwrap();
    let err = SdeLevels::new(terms, Scheme::Milstein, call(), 1.0).unwrap_err();
    assert!(err.to_string().contains("2^24"), "{err}");
}

/// Levels 0-2 of one coordinate, then more than any sampler has: a survey to level 5 is
/// refused before it samples anything (it drew every sample of levels 0-2 first).
#[test]
fn a_survey_past_the_sampleable_levels_is_refused_before_sampling() {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicU64, Ordering};
    struct Wide(Arc<AtomicU64>);
    impl Level for Wide {
        fn dims(&self, level: usize) -> usize {
            if level < 3 { 1 } else { 1 << 40 }
        }
        fn cost(&self, level: usize) -> f64 {
            (1u64 << level) as f64
        }
        fn sample(&self, _: usize, u: &[f64], _: &mut Vec<f64>) -> (f64, f64) {
            self.0.fetch_add(1, Ordering::Relaxed);
            (u[0], 0.0)
        }
    }
    let drawn = Arc::new(AtomicU64::new(0));
    let err = Multilevel::new(Wide(drawn.clone()))
        .survey(5, 1000)
        .unwrap_err();
    assert!(
        err.to_string()
            .contains("(level 3 takes 1099511627776; 1 to 16777216 coordinates"),
        "{err}"
    );
    assert_eq!(drawn.load(Ordering::Relaxed), 0);
    // Too wide from level 0: no setting helps, so the error names the model's dimensions.
    struct Wider;
    impl Level for Wider {
        fn dims(&self, _: usize) -> usize {
            1 << 30
        }
        fn cost(&self, level: usize) -> f64 {
            (1u64 << level) as f64
        }
        fn sample(&self, _: usize, u: &[f64], _: &mut Vec<f64>) -> (f64, f64) {
            (u[0], 0.0)
        }
    }
    let run = Multilevel::new(Wider)
        .rmse(0.1)
        .run()
        .unwrap_err()
        .to_string();
    let survey = Multilevel::new(Wider)
        .qmc(true)
        .survey(2, 64)
        .unwrap_err()
        .to_string();
    assert!(
        run.starts_with("invalid level dims = 1073741824 at level 0")
            && run.contains("1 to 16777216 coordinates per sample (independent points)"),
        "{run}"
    );
    assert!(
        survey.contains("1 to 21201 coordinates per sample (Sobol' points)"),
        "{survey}"
    );
}

/// The shortest maturity allowed has distinct dates on every grid a level can be sampled
/// on: deep levels (here 2^20 steps) give finite samples, not NaN from a bridge that
/// could not be built; a shorter one is refused by name.
#[test]
fn the_shortest_maturity_samples_deep_levels() {
    let t = SdeLevels::SHORTEST_MATURITY;
    for payoff in [Payoff::lookback(), Payoff::asian_call(S0).unwrap()] {
        let levels =
            SdeLevels::new(Sde::gbm(S0, RATE, SIGMA).unwrap(), Scheme::Euler, payoff, t).unwrap();
        for level in [0, 1, 12, 20] {
            let u = vec![0.3; levels.dims(level)];
            let (fine, coarse) = levels.sample(level, &u, &mut Vec::new());
            assert!(
                fine.is_finite() && coarse.is_finite(),
                "level {level}: {fine}, {coarse}"
            );
        }
    }
    for short in [t / 2.0, 1e-320, f64::MIN_POSITIVE] {
        let refused = SdeLevels::new(
            Sde::gbm(S0, RATE, SIGMA).unwrap(),
            Scheme::Euler,
            Payoff::lookback(),
            short,
        );
        assert!(
            refused.is_err_and(|e| e.to_string().contains("maturity")),
            "{short:e}"
        );
    }
}
