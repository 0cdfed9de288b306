//! The integrator: thread-count independence, honest error bars, and clear errors.

use mcint::estimator::ImportanceEstimator;
use mcint::pdf::{Pdf, UniformBox};
use mcint::sampler::{Independent, Jittered, LatinHypercube};
use mcint::{Error, Integrator};

fn smooth(x: &[f64]) -> f64 {
    x.iter()
        .enumerate()
        .map(|(i, v)| (1.0 + (i + 1) as f64 * v * v).ln())
        .sum::<f64>()
        .exp()
}

/// Runs on `threads` threads with chunks that do not divide the sample count evenly.
#[test]
fn result_is_identical_for_1_2_and_8_threads() {
    // (sampler, points per pass, points per replicate)
    for (name, pass, samples) in [
        ("independent", 0, 50_001),
        ("jittered", 4096, 8192),
        ("latin", 20_000, 40_000),
    ] {
        let run = |threads: usize| {
            Integrator::over_box(smooth, UniformBox::unit(2).unwrap())
                .sampler(mcint::sampler::build_sampler(name, 2, pass, 0).unwrap())
                .samples(samples)
                .replicates(3)
                .seed(11)
                .threads(threads)
                .run()
                .unwrap()
        };
        let one = run(1);
        assert_eq!(one, run(2), "{name}");
        assert_eq!(one, run(8), "{name}");
        assert_eq!(one.n, 3 * samples);
    }
}

#[test]
fn the_seed_selects_the_randomization() {
    let run = |seed| {
        Integrator::over_box(smooth, UniformBox::unit(3).unwrap())
            .sampler(LatinHypercube::new(3, 1000, 0).unwrap())
            .samples(1000)
            .replicates(4)
            .seed(seed)
            .run()
            .unwrap()
            .mean
    };
    assert_eq!(run(5), run(5));
    assert_ne!(run(5), run(6));
}

#[test]
fn dependent_points_get_error_bars_only_from_replicates() {
    let one = Integrator::over_box(smooth, UniformBox::unit(2).unwrap())
        .sampler(Jittered::new(2, 16, 0).unwrap())
        .samples(256)
        .run()
        .unwrap();
    assert_eq!(one.std_error, None);
    assert_eq!(one.confidence_interval(0.95).unwrap(), None);
    let many = Integrator::over_box(smooth, UniformBox::unit(2).unwrap())
        .sampler(Jittered::new(2, 16, 0).unwrap())
        .samples(256)
        .replicates(10)
        .run()
        .unwrap();
    assert_eq!(many.dof, Some(9.0));
    assert_eq!(many.basis, mcint::stats::ErrorBasis::Replicates);
}

/// Exact integral of `smooth` in 2D: prod_i int_0^1 (1 + i x^2) dx = (1 + 1/3)(1 + 2/3).
const SMOOTH_2D: f64 = (4.0 / 3.0) * (5.0 / 3.0);

/// The reported 95% intervals cover the exact value in about 95% of runs. With 400 seeds
/// the count of covering runs is Binomial(400, 0.95): mean 380, sd 4.36; we require at least
/// 360 (4.6 sd below the mean) and at most 399 (all 400 would suggest intervals too wide,
/// probability 0.95^400 ~ 1e-9).
#[test]
fn ninety_five_percent_intervals_cover_about_95_percent() {
    for (name, replicates, samples) in [
        ("independent", 1u64, 2000u64),
        ("latin", 8, 256),
        ("jittered", 6, 256),
    ] {
        let mut covered = 0;
        for seed in 0..400 {
            let sampler = mcint::sampler::build_sampler(name, 2, samples, 0).unwrap();
            let e = Integrator::over_box(smooth, UniformBox::unit(2).unwrap())
                .sampler(sampler)
                .samples(samples)
                .replicates(replicates)
                .seed(seed)
                .threads(1)
                .run()
                .unwrap();
            let (lo, hi) = e.confidence_interval(0.95).unwrap().unwrap();
            covered += u32::from(lo <= SMOOTH_2D && SMOOTH_2D <= hi);
        }
        assert!(
            (360..400).contains(&covered),
            "{name}: {covered} of 400 intervals covered"
        );
    }
}

#[test]
fn bad_settings_are_errors_that_say_what_is_allowed() {
    let base = || Integrator::over_box(smooth, UniformBox::unit(2).unwrap());
    let message = |r: Result<mcint::Estimate, Error>| r.unwrap_err().to_string();
    assert!(message(base().samples(0).run()).contains("samples"));
    assert!(message(base().replicates(0).run()).contains("replicates"));
    assert!(message(base().threads(0).run()).contains("threads"));
    let wrong_dims = message(base().sampler(Independent::new(3, 0).unwrap()).run());
    assert!(
        wrong_dims.contains("3 dimensions, expected 2"),
        "{wrong_dims}"
    );
    let partial_pass = message(
        base()
            .sampler(Jittered::new(2, 4, 0).unwrap())
            .samples(20)
            .run(),
    );
    assert!(
        partial_pass.contains("multiple") && partial_pass.contains("16 or 32"),
        "{partial_pass}"
    );
    let overflow = base()
        .sampler(Independent::new(2, 0).unwrap())
        .samples(u64::MAX / 2)
        .replicates(3)
        .run();
    assert!(matches!(overflow, Err(Error::IndexOutOfRange { .. })));
}

#[test]
fn non_finite_integrand_values_are_reported_with_the_first_point() {
    let f = |x: &[f64]| if x[0] < 0.25 { f64::NAN } else { 1.0 };
    let err = Integrator::over_box(f, UniformBox::unit(1).unwrap())
        .samples(40_000)
        .seed(3)
        .run()
        .unwrap_err();
    let Error::NonFiniteContribution {
        count,
        first_point,
        first_value,
        first_replicate,
        ..
    } = err
    else {
        panic!("expected a non-finite error, got {err}");
    };
    // About a quarter of 40000: Binomial sd 87, so 10000 +- 450 is 5 sd.
    assert!(count.abs_diff(10_000) < 450, "{count}");
    assert!(first_point[0] < 0.25 && first_value.is_nan() && first_replicate == 0);
}

/// A pdf that claims zero density on half of where it samples: f/pdf is infinite there, and
/// the integrator refuses to average it into a silently wrong mean.
#[test]
fn zero_pdf_where_the_integrand_is_not_is_an_error() {
    struct Lying;
    impl Pdf for Lying {
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
            if x[0] < 0.5 { 0.0 } else { 1.0 }
        }
    }
    let estimator = ImportanceEstimator::new(|_: &[f64]| 1.0, Lying);
    let err = Integrator::new(estimator).samples(1000).run().unwrap_err();
    assert!(
        matches!(err, Error::NonFiniteContribution { first_value, .. } if first_value == f64::INFINITY)
    );
    // Where the integrand is zero too, the contribution is zero, not 0/0.
    let fine = Integrator::new(ImportanceEstimator::new(
        |x: &[f64]| if x[0] < 0.5 { 0.0 } else { 1.0 },
        Lying,
    ))
    .samples(1000)
    .run()
    .unwrap();
    assert!((fine.mean - 0.5).abs() < 5.0 * fine.std_error.unwrap());
}

/// An unscrambled sequence has no randomness to measure: no standard error, and several
/// replicates (identical copies) are refused. Scrambled, it gets replicate error bars.
#[test]
fn unrandomized_sequences_report_no_error_bar() {
    use mcint::sampler::{Scramble, Sobol};
    let base = || Integrator::over_box(smooth, UniformBox::unit(2).unwrap()).samples(1024);
    let plain = base()
        .sampler(Sobol::new(2, Scramble::None, 0).unwrap())
        .run()
        .unwrap();
    assert_eq!(
        (plain.std_error, plain.basis),
        (None, mcint::stats::ErrorBasis::None)
    );
    let refused = base()
        .sampler(Sobol::new(2, Scramble::None, 0).unwrap())
        .replicates(4)
        .run();
    assert!(
        refused
            .unwrap_err()
            .to_string()
            .contains("unrandomized sobol")
    );
    let scrambled = base()
        .sampler(Sobol::new(2, Scramble::Owen, 0).unwrap())
        .replicates(4)
        .run()
        .unwrap();
    assert_eq!(scrambled.basis, mcint::stats::ErrorBasis::Replicates);
    let too_many = base()
        .sampler(Sobol::new(2, Scramble::Owen, 0).unwrap())
        .samples((1 << 32) + 1)
        .run();
    assert!(
        too_many
            .unwrap_err()
            .to_string()
            .contains("at most 4294967296")
    );
}

/// `NonFinitePolicy::Skip` leaves NaN contributions out and counts them: the estimate is the
/// mean over the finite region (here x on [0.1, 1), mean 0.55), for independent points and
/// for replicates of stratified points; a replicate with nothing finite is still an error.
#[test]
fn skipped_non_finite_contributions_are_counted_and_left_out() {
    use mcint::NonFinitePolicy;
    use mcint::sampler::{Scramble, Sobol};
    let f = |x: &[f64]| if x[0] < 0.1 { f64::NAN } else { x[0] };
    let unit = || UniformBox::unit(1).unwrap();
    let plain = Integrator::over_box(f, unit())
        .samples(100_000)
        .seed(3)
        .non_finite(NonFinitePolicy::Skip)
        .run()
        .unwrap();
    // Binomial(100000, 0.1) skipped: within 5 standard deviations (sd 94.9) of 10000.
    assert!(
        (plain.non_finite as f64 - 10_000.0).abs() < 5.0 * 94.9,
        "{plain:?}"
    );
    assert_eq!(plain.n + plain.non_finite, 100_000);
    assert_eq!(plain.evaluations, 100_000);
    assert!(
        (plain.mean - 0.55).abs() < 5.0 * plain.std_error.unwrap(),
        "{plain:?}"
    );

    let rqmc = Integrator::over_box(f, unit())
        .sampler(Sobol::new(1, Scramble::Owen, 4).unwrap())
        .samples(1024)
        .replicates(8)
        .non_finite(NonFinitePolicy::Skip)
        .run()
        .unwrap();
    assert!(rqmc.non_finite > 0 && rqmc.n + rqmc.non_finite == 8 * 1024);
    assert!((rqmc.mean - 0.55).abs() < 1e-3, "{rqmc:?}");

    let all_nan = Integrator::over_box(|_: &[f64]| f64::NAN, unit())
        .samples(10)
        .non_finite(NonFinitePolicy::Skip)
        .run()
        .unwrap_err()
        .to_string();
    assert!(all_nan.contains("at least one finite"), "{all_nan}");
    // The default still fails, naming the count.
    let strict = Integrator::over_box(f, unit())
        .samples(1000)
        .seed(3)
        .run()
        .unwrap_err();
    assert!(matches!(strict, mcint::Error::NonFiniteContribution { .. }));
}

/// One replicate of dependent points has no standard error, and the estimate says why (it
/// said nothing: `std_error.unwrap()` panicked in a user's program without a hint).
#[test]
fn one_replicate_of_dependent_points_warns_that_it_has_no_error_bar() {
    use mcint::sampler::{Scramble, Sobol};
    use mcint::stats::Warning;
    let f = |x: &[f64]| x[0] * x[1];
    let square = || UniformBox::unit(2).unwrap();
    let owen = || Sobol::new(2, Scramble::Owen, 3).unwrap();
    let e = Integrator::over_box(f, square())
        .sampler(owen())
        .samples(1024)
        .run()
        .unwrap();
    assert_eq!(e.std_error, None);
    let expected = Warning::NoErrorBar {
        sampler: "sobol".into(),
        randomized: true,
    };
    assert!(e.warnings.contains(&expected), "{:?}", e.warnings);
    assert_eq!(expected.kind(), "no-error-bar");
    for sampler in [
        Box::new(Jittered::new(2, 32, 3).unwrap()) as Box<dyn mcint::Sampler>,
        Box::new(Sobol::new(2, Scramble::None, 3).unwrap()),
    ] {
        let randomized = sampler.is_randomized();
        let e = Integrator::over_box(f, square())
            .sampler(sampler)
            .samples(1024)
            .run()
            .unwrap();
        assert!(
            e.warnings.iter().any(
                |w| matches!(w, Warning::NoErrorBar { randomized: r, .. } if *r == randomized)
            ),
            "{:?}",
            e.warnings
        );
    }
    // With replicates there is an error bar, and no such warning.
    let e = Integrator::over_box(f, square())
        .sampler(owen())
        .samples(1024)
        .replicates(16)
        .run()
        .unwrap();
    assert!(e.std_error.is_some());
    assert!(
        e.warnings.iter().all(|w| w.kind() != "no-error-bar"),
        "{:?}",
        e.warnings
    );
    // Independent points have a per-sample error bar.
    let e = Integrator::over_box(f, square())
        .sampler(Independent::new(2, 3).unwrap())
        .samples(1024)
        .run()
        .unwrap();
    assert!(
        e.std_error.is_some() && e.warnings.is_empty(),
        "{:?}",
        e.warnings
    );
}
