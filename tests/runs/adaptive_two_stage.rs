//! Two-stage adaptive stratified sampling (Kirk & Arvo 1991): unbiased where naive reuse of
//! the pilot is not, better than plain Monte Carlo where the variance is uneven, independent
//! of the thread count, and strict about its parameters.

use mcint::adaptive::TwoStage;
use mcint::pdf::UniformBox;
use mcint::sampler::{Independent, LatinHypercube, Scramble, Sobol};
use mcint::stats::ErrorBasis;
use mcint::testfns::{Genz, GenzFamily, TestFunction};

/// Mean and standard error of the mean of a list of estimates.
fn mean_and_sem(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// 1 on a fine lattice of small squares (side 0.15/32, one in every 1/32 x 1/32 cell), else
/// 0: every stratum of an 8 x 8 grid holds 16 squares, and a uniform point in it hits one
/// with probability q = 0.15^2 = 0.0225, which is also the exact integral.
fn sparse_spikes(x: &[f64]) -> f64 {
    let w = 0.15;
    if (32.0 * x[0]).fract() < w && (32.0 * x[1]).fract() < w {
        1.0
    } else {
        0.0
    }
}

#[test]
fn reusing_the_pilot_is_biased_and_the_two_stage_estimate_is_not() {
    // Pilot of 4 per stratum, 64 strata, 40 evaluations per stratum in all. A pilot sees no
    // spike with probability (1 - q)^4 = 0.91; its stratum then has sigma = 0 and gets only
    // the minimum of 2 second-stage points, while the ~6 strata whose pilot hit a spike share
    // the other ~2200. The naive estimate averages pilot and main samples: a spike-free pilot
    // keeps its four zeros at full weight, (0 + 2 main) / 6, with mean q/3, and a lucky
    // pilot's spike is diluted by ~390 fresh points, with mean ~q. So it expects about
    // 0.91 q/3 + 0.09 (q + 0.0026) = 0.40 q: biased by -60%. The two-stage estimate uses only
    // the fresh points, which are uniform in their stratum whatever the allocation, so its
    // mean is q exactly. Over 1000 seeds the naive mean is tens of standard errors below q;
    // the two-stage mean must be within 4.
    let exact = 0.15f64 * 0.15;
    let runs = |reuse: bool| -> Vec<f64> {
        (0..1000)
            .map(|seed| {
                TwoStage::new(sparse_spikes, UniformBox::unit(2).unwrap(), 8)
                    .pilot(4)
                    .samples(64 * 40)
                    .reuse_pilot(reuse)
                    .seed(seed)
                    .run()
                    .unwrap()
                    .mean
            })
            .collect()
    };
    let (naive, naive_sem) = mean_and_sem(&runs(true));
    let (fresh, fresh_sem) = mean_and_sem(&runs(false));
    let naive_z = (naive - exact) / naive_sem;
    let fresh_z = (fresh - exact) / fresh_sem;
    assert!(
        naive_z < -10.0,
        "naive: {naive} vs {exact}, z = {naive_z:.1}"
    );
    assert!(
        (naive / exact - 0.40).abs() < 0.05,
        "naive / exact = {:.3}, predicted 0.40",
        naive / exact
    );
    assert!(
        fresh_z.abs() < 4.0,
        "two-stage: {fresh} vs {exact}, z = {fresh_z:.2}"
    );
}

#[test]
fn neyman_allocation_beats_plain_monte_carlo_where_the_variance_is_uneven() {
    // A narrow peak, exp(-400 |x - (0.7, 0.3)|^2): nearly all the variance sits in a few of
    // the 16 x 16 strata. Plain Monte Carlo's variance at the same total budget is exact:
    // (integral of f^2 - (integral of f)^2) / N, with f^2 the same family at a sqrt 2.
    let peak = Genz::new(GenzFamily::Gaussian, vec![20.0; 2], vec![0.7, 0.3]).unwrap();
    let squared = Genz::new(
        GenzFamily::Gaussian,
        vec![20.0 * 2f64.sqrt(); 2],
        vec![0.7, 0.3],
    )
    .unwrap();
    let total = 1u64 << 14;
    let plain = (squared.exact() - peak.exact().powi(2)) / total as f64;
    let mut means = Vec::new();
    let mut reported = 0.0;
    for seed in 0..50 {
        let e = TwoStage::new(|x: &[f64]| peak.eval(x), UniformBox::unit(2).unwrap(), 16)
            .pilot(4)
            .samples(total)
            .seed(seed)
            .run()
            .unwrap();
        assert_eq!(
            (e.evaluations, e.basis, e.iterations),
            (total, ErrorBasis::PerSample, 2)
        );
        means.push(e.mean);
        reported += e.variance().unwrap() / 50.0;
    }
    let (mean, sem) = mean_and_sem(&means);
    let empirical = sem * sem * 50.0;
    // Over 100 seeds the two-stage variance is 101 times below plain Monte Carlo's. The
    // empirical variance of 50 runs is sigma^2 chi2_49/49, above 1.85 sigma^2 with
    // probability 1e-4, so the observed ratio exceeds 101 / 1.85 = 55 but for that chance;
    // 20 leaves room for the uncertainty of the 100-seed figure.
    let ratio = plain / empirical;
    assert!(ratio > 20.0, "variance ratio {ratio:.1}");
    assert!(((mean - peak.exact()) / sem).abs() < 4.0);
    // The reported variances are honest on average (the same chi2_49 bound both ways, plus
    // the spread of the reported values themselves).
    let honesty = reported / empirical;
    assert!(
        (0.5..2.0).contains(&honesty),
        "reported / empirical = {honesty:.2}"
    );
}

#[test]
fn results_are_bit_identical_for_any_thread_count_and_sampler_choices_work() {
    let g = Genz::with_defaults(GenzFamily::Continuous, 3).unwrap();
    let run = |threads, sobol: bool| {
        let t = TwoStage::new(|x: &[f64]| g.eval(x), UniformBox::unit(3).unwrap(), 12)
            .pilot(4)
            .samples(40_000)
            .threads(threads);
        let t = if sobol {
            t.sampler(Sobol::new(3, Scramble::Owen, 0).unwrap())
        } else {
            t
        };
        t.seed(17).run().unwrap()
    };
    for sobol in [false, true] {
        let one = run(1, sobol);
        assert_eq!(one, run(2, sobol));
        assert_eq!(one, run(3, sobol));
        let z = (one.mean - g.exact()) / one.std_error.unwrap();
        assert!(z.abs() < 5.0, "sobol = {sobol}: z = {z:.2}");
        assert_eq!(one.evaluations, 40_000);
    }
    // `seed` overrides the sampler's own seed.
    let with_sampler = TwoStage::new(|x: &[f64]| g.eval(x), UniformBox::unit(3).unwrap(), 12)
        .pilot(4)
        .samples(40_000)
        .sampler(Independent::new(3, 1234).unwrap())
        .seed(17)
        .run()
        .unwrap();
    assert_eq!(with_sampler, run(1, false));
}

#[test]
fn bad_parameters_are_errors_that_name_the_field() {
    let f = |x: &[f64]| x[0];
    let unit = || UniformBox::unit(2).unwrap();
    fn message<F: Fn(&[f64]) -> f64 + Sync>(t: TwoStage<F>) -> String {
        t.run().unwrap_err().to_string()
    }
    let cases = [
        (message(TwoStage::new(f, unit(), 0)), "strata_per_axis"),
        (message(TwoStage::new(f, unit(), 5000)), "strata_per_axis"),
        (message(TwoStage::new(f, unit(), 4).pilot(1)), "pilot"),
        (
            message(TwoStage::new(f, unit(), 4).pilot(2).samples(63)),
            "samples",
        ),
        (message(TwoStage::new(f, unit(), 4).threads(0)), "threads"),
        (
            message(TwoStage::new(f, unit(), 4).sampler(LatinHypercube::new(2, 8, 0).unwrap())),
            "sampler",
        ),
        (
            message(TwoStage::new(f, unit(), 4).sampler(Sobol::new(2, Scramble::None, 0).unwrap())),
            "sampler",
        ),
    ];
    for (message, field) in cases {
        assert!(
            message.starts_with(&format!("invalid {field} = ")),
            "{field}: {message}"
        );
    }
    let wrong_dims = TwoStage::new(f, unit(), 4).sampler(Independent::new(1, 0).unwrap());
    assert!(message(wrong_dims).contains("expected 2"));
    // The smallest total is accepted and used exactly: (pilot + 2) per stratum.
    assert_eq!(
        TwoStage::new(f, unit(), 4)
            .pilot(2)
            .samples(64)
            .run()
            .unwrap()
            .evaluations,
        64
    );
    let nan = TwoStage::new(|x: &[f64]| 1.0 / (x[0] - x[0]), unit(), 4)
        .run()
        .unwrap_err();
    assert!(nan.to_string().contains("non-finite"), "{nan}");
}
