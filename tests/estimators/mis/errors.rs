//! Bad input gives errors naming the field; broken pdfs and weights are reported by the
//! integrator.

use super::*;

// Bad input

#[test]
fn bad_input_gives_errors_naming_the_field() {
    let unit = || -> Box<dyn Pdf> { Box::new(UniformInterval::new(0.0, 1.0).unwrap()) };
    let square = || -> Box<dyn Pdf> { Box::new(UniformBox::unit(2).unwrap()) };
    let f = |x: &[f64]| x[0];
    let nan = f64::NAN;
    let inf = f64::INFINITY;

    // Heuristic parameters.
    for beta in [0.0, -1.0, nan, inf] {
        assert_eq!(field(MisHeuristic::power(beta).unwrap_err()), "beta");
        assert_eq!(
            field(MisHeuristic::Power { beta }.check().unwrap_err()),
            "beta"
        );
    }
    for alpha in [-0.1, 1.1, nan, inf] {
        assert_eq!(field(MisHeuristic::cutoff(alpha).unwrap_err()), "alpha");
    }
    assert!(MisHeuristic::power(1e-300).is_ok() && MisHeuristic::power(1e300).is_ok());
    assert!(MisHeuristic::cutoff(0.0).is_ok() && MisHeuristic::cutoff(1.0).is_ok());

    // Mixture.
    assert_eq!(
        field(Mixture::new(vec![], vec![]).unwrap_err()),
        "components"
    );
    assert_eq!(
        field(Mixture::new(vec![unit()], vec![1.0, 2.0]).unwrap_err()),
        "weights"
    );
    assert_eq!(
        field(Mixture::new(vec![unit(), square()], vec![1.0, 1.0]).unwrap_err()),
        "components"
    );
    for bad in [
        vec![1.0, -1.0],
        vec![nan, 1.0],
        vec![inf, 1.0],
        vec![0.0, 0.0],
    ] {
        assert_eq!(
            field(Mixture::new(vec![unit(), unit()], bad).unwrap_err()),
            "weights"
        );
    }
    for alpha in [0.0, -0.5, 1.5, nan] {
        let err = Mixture::defensive(unit(), UniformBox::unit(1).unwrap(), alpha).unwrap_err();
        assert_eq!(field(err), "alpha");
    }
    let err = Mixture::defensive(square(), UniformBox::unit(1).unwrap(), 0.5).unwrap_err();
    assert_eq!(field(err), "proposal");

    // Multi-sample MIS.
    let balance = MisHeuristic::Balance;
    let err = |r: mcint::Result<MultiSampleMis<_, _>>| field(r.err().unwrap());
    assert_eq!(err(MultiSampleMis::new(f, vec![], balance)), "techniques");
    assert_eq!(
        err(MultiSampleMis::new(
            f,
            vec![(unit(), 1), (square(), 1)],
            balance
        )),
        "techniques"
    );
    assert_eq!(
        err(MultiSampleMis::new(
            f,
            vec![(unit(), 1), (unit(), 0)],
            balance
        )),
        "n_i"
    );
    assert_eq!(
        err(MultiSampleMis::new(
            f,
            vec![(unit(), usize::MAX), (unit(), 2)],
            balance
        )),
        "n_i"
    );
    assert_eq!(
        err(MultiSampleMis::new(
            f,
            vec![(unit(), 1)],
            MisHeuristic::Power { beta: 0.0 }
        )),
        "beta"
    );
    assert_eq!(
        err(MultiSampleMis::new(
            f,
            vec![(unit(), 1)],
            MisHeuristic::Cutoff { alpha: 2.0 }
        )),
        "alpha"
    );

    // One-sample MIS.
    let err = |r: mcint::Result<OneSampleMis<_, _>>| r.err().unwrap();
    assert_eq!(
        field(err(OneSampleMis::new(f, vec![], vec![], balance))),
        "techniques"
    );
    assert_eq!(
        field(err(OneSampleMis::new(
            f,
            vec![unit()],
            vec![0.5, 0.5],
            balance
        ))),
        "probabilities"
    );
    assert_eq!(
        field(err(OneSampleMis::new(
            f,
            vec![unit(), square()],
            vec![0.5, 0.5],
            balance
        ))),
        "techniques"
    );
    for bad in [
        vec![-0.5, 1.5],
        vec![nan, 1.0],
        vec![inf, 0.0],
        vec![0.5, 0.6],
        vec![0.5, 0.499999],
        vec![1.0, 1.0],
    ] {
        let e = err(OneSampleMis::new(
            f,
            vec![unit(), unit()],
            bad.clone(),
            balance,
        ));
        let message = e.to_string();
        assert_eq!(field(e), "probabilities", "{bad:?}");
        assert!(message.contains("sum to one"), "{message}");
    }
    // The message says what they summed to.
    let message = err(OneSampleMis::new(
        f,
        vec![unit(), unit()],
        vec![0.5, 0.6],
        balance,
    ))
    .to_string();
    assert!(message.contains("sum to 1.1"), "{message}");
    assert!(OneSampleMis::new(f, vec![unit(), unit()], vec![0.5, 0.5 + 1e-13], balance).is_ok());
    assert!(OneSampleMis::new(f, vec![unit(), unit()], vec![0.0, 1.0], balance).is_ok());
    assert_eq!(
        field(err(OneSampleMis::new(
            f,
            vec![unit()],
            vec![1.0],
            MisHeuristic::Power { beta: nan }
        ))),
        "beta"
    );

    // Product importance sampling.
    for bad in [0.0, -1.0, nan, inf] {
        let e = ProductImportanceEstimator::new(f, UniformInterval::new(0.0, 1.0).unwrap(), bad);
        assert_eq!(field(e.err().unwrap()), "g_integral");
        let e = ProductImportanceEstimator::from_normalization(
            f,
            UniformInterval::new(0.0, 1.0).unwrap(),
            bad,
        );
        assert_eq!(field(e.err().unwrap()), "c");
    }
    let e = ProductImportanceEstimator::from_normalization(
        f,
        UniformInterval::new(0.0, 1.0).unwrap(),
        1e-310,
    );
    assert_eq!(field(e.err().unwrap()), "c");
}

// ---------------------------------------------------------------------------------------------
// Broken pdfs and weights: the integrator reports them

/// Samples uniformly on [0, 1) but claims a density of `claim` on [0.5, 1): zero or NaN there
/// is a pdf inconsistent with its own samples.
struct BrokenPdf {
    claim: f64,
}

impl Pdf for BrokenPdf {
    fn canonical_dims(&self) -> usize {
        1
    }
    fn dims(&self) -> usize {
        1
    }
    fn sample(&self, u: &[f64], x: &mut [f64]) {
        x[0] = u[0];
    }
    fn pdf(&self, x: &[f64]) -> f64 {
        if x[0] < 0.5 { 1.0 } else { self.claim }
    }
}

fn broken(claim: f64) -> Box<dyn Pdf> {
    Box::new(BrokenPdf { claim })
}

fn uniform() -> Box<dyn Pdf> {
    Box::new(UniformInterval::new(0.0, 1.0).unwrap())
}

/// Runs the integrator and returns the non-finite count and the first offending point,
/// checking the count against its binomial expectation (4.5 standard deviations).
fn expect_non_finite<E: Estimator>(estimator: E, samples: u64, probability: f64) -> Vec<f64> {
    match Integrator::new(estimator).samples(samples).seed(11).run() {
        Err(Error::NonFiniteContribution {
            count,
            first_point,
            first_value,
            ..
        }) => {
            assert!(!first_value.is_finite());
            let mean = samples as f64 * probability;
            let sd = (samples as f64 * probability * (1.0 - probability)).sqrt();
            assert!(
                (count as f64 - mean).abs() <= 4.5 * sd + 1e-9,
                "count {count}, expected {mean} +- {sd}"
            );
            first_point
        }
        other => panic!("expected a non-finite contribution error, got {other:?}"),
    }
}

#[test]
fn pdfs_zero_or_nan_where_f_is_not_are_reported() {
    let f = |_: &[f64]| 1.0;
    let samples = 10_000;
    // Multi-sample: the broken technique's own sample lands in [0.5, 1) in half of the groups.
    // With a zero claim only that technique's samples fail (the uniform technique's samples
    // there have weight one); with a NaN claim every sample in [0.5, 1) fails (3/4 of groups).
    let mis = MultiSampleMis::new(
        f,
        vec![(broken(0.0), 1), (uniform(), 1)],
        MisHeuristic::Balance,
    )
    .unwrap();
    let point = expect_non_finite(mis, samples, 0.5);
    assert!(point[0] >= 0.5, "{point:?}");
    let mis = MultiSampleMis::new(
        f,
        vec![(broken(f64::NAN), 1), (uniform(), 1)],
        MisHeuristic::power(2.0).unwrap(),
    )
    .unwrap();
    let point = expect_non_finite(mis, samples, 0.75);
    assert!(point.iter().any(|&u| u >= 0.5), "{point:?}");

    // One-sample: the broken technique is chosen with probability 0.4 and its sample falls in
    // [0.5, 1) half the time. u[0] < 0.4 chooses it, with remapped u = u[0] / 0.4.
    let mis = OneSampleMis::new(
        f,
        vec![broken(0.0), uniform()],
        vec![0.4, 0.6],
        MisHeuristic::Maximum,
    )
    .unwrap();
    let point = expect_non_finite(mis, samples, 0.2);
    assert!((0.2..0.4).contains(&point[0]), "{point:?}");

    // A mixture with a NaN component: every point in [0.5, 1) has a NaN density.
    let mixture = Mixture::new(vec![broken(f64::NAN), uniform()], vec![1.0, 1.0]).unwrap();
    expect_non_finite(ImportanceEstimator::new(f, mixture), samples, 0.5);

    // Where f = 0 the broken density is never consulted: the estimate is fine and unbiased.
    let half = |x: &[f64]| if x[0] < 0.5 { 1.0 } else { 0.0 };
    let mis = MultiSampleMis::new(
        half,
        vec![(broken(f64::NAN), 1), (uniform(), 2)],
        MisHeuristic::Balance,
    )
    .unwrap();
    let e = Integrator::new(mis)
        .samples(samples)
        .seed(12)
        .run()
        .unwrap();
    assert!((e.mean - 0.5).abs() <= 4.5 * e.std_error.unwrap(), "{e:?}");
}

#[test]
fn user_weights_that_do_not_sum_to_one_are_reported() {
    let f = |x: &[f64]| 1.0 + x[0];
    let samples = 10_000;
    // Shares that sum to 1.2 on [0.5, 1): a bias the estimator cannot see by itself.
    let wrong = |i: usize, x: &[f64], _: &[f64]| {
        if x[0] < 0.5 || i == 0 { 0.5 } else { 0.7 }
    };
    // Every sample of both techniques is checked: a group fails when either lands in [0.5, 1).
    let mis = MultiSampleMis::new(f, vec![(uniform(), 1), (uniform(), 1)], wrong).unwrap();
    let point = expect_non_finite(mis, samples, 0.75);
    assert!(point.iter().any(|&u| u >= 0.5), "{point:?}");
    let mis = OneSampleMis::new(f, vec![uniform(), uniform()], vec![0.5, 0.5], wrong).unwrap();
    expect_non_finite(mis, samples, 0.5);

    // A fixed split is wrong where one technique cannot produce the point: its half of the
    // weight was lost (0.249 for 0.5, 0.312 for 0.375, with error bars that hid it). The
    // sum is taken over the techniques of positive density, so those points are reported.
    let half = |_: usize, _: &[f64], _: &[f64]| 0.5;
    let narrow = || -> Box<dyn Pdf> { Box::new(UniformInterval::new(0.0, 0.5).unwrap()) };
    let never_chosen =
        OneSampleMis::new(f, vec![uniform(), uniform()], vec![1.0, 0.0], half).unwrap();
    expect_non_finite(never_chosen, samples, 1.0);
    let mis = MultiSampleMis::new(f, vec![(uniform(), 1), (narrow(), 1)], half).unwrap();
    // A group fails when the uniform technique's sample lands in [0.5, 1).
    let point = expect_non_finite(mis, samples, 0.5);
    assert!(point[0] >= 0.5, "{point:?}");
    let mis = OneSampleMis::new(f, vec![uniform(), narrow()], vec![0.5, 0.5], half).unwrap();
    // The uniform technique is chosen (u[0] < 0.5) and its sample lands in [0.5, 1).
    expect_non_finite(mis, samples, 0.25);
    // Where both cover the point, the same split is valid.
    let mis = MultiSampleMis::new(f, vec![(uniform(), 1), (uniform(), 3)], half).unwrap();
    let e = Integrator::new(mis)
        .samples(samples)
        .seed(14)
        .run()
        .unwrap();
    assert!((e.mean - 1.5).abs() <= 4.5 * e.std_error.unwrap(), "{e:?}");

    // A slightly wrong sum is caught too (1e-6 is far above rounding).
    let almost = |i: usize, _: &[f64], _: &[f64]| if i == 0 { 0.5 } else { 0.5 + 1e-6 };
    let mis = MultiSampleMis::new(f, vec![(uniform(), 1), (uniform(), 1)], almost).unwrap();
    expect_non_finite(mis, samples, 1.0);

    // The same weighting within the 1e-9 tolerance runs.
    let rounding = |i: usize, _: &[f64], _: &[f64]| if i == 0 { 0.5 } else { 0.5 + 1e-12 };
    let mis = MultiSampleMis::new(f, vec![(uniform(), 1), (uniform(), 1)], rounding).unwrap();
    let e = Integrator::new(mis)
        .samples(samples)
        .seed(13)
        .run()
        .unwrap();
    assert!((e.mean - 1.5).abs() <= 4.5 * e.std_error.unwrap(), "{e:?}");
}
