//! Runs of the `Integrator` to a tolerance: the reported 95% intervals cover the exact value
//! in at least 93% of 200 independent seeds for every Genz family in d = 2, 5 and 10, with
//! plain Monte Carlo (two-stage rule) and with randomized QMC (Owen-scrambled Sobol', 8
//! replicates to start, doubled or added to); the tolerance is met whenever it is reported as
//! met; limits stop runs with the right reason.
//!
//! Why 93%: with a true coverage of 95%, the count of covering runs out of 200 is binomial
//! with mean 190 and standard deviation 3.1, so 186 (93%) is 1.3 deviations below the mean; a
//! method whose true coverage were 90% would pass with probability below 1%. Across the 36
//! cases here an exactly-95% method would still fail one of them now and then; the methods
//! are designed to be a little conservative (the RQMC error bar is inflated by 1.2, the
//! plain pilot's deviation by 1.1). The seeds are fixed, so the outcome is reproducible.

use crate::common::{REQUIRED, SEEDS};
use mcint::Integrator;
use mcint::pdf::UniformBox;
use mcint::sampler::{Scramble, Sobol};
use mcint::stats::{StopReason, Tolerance};
use mcint::testfns::{Genz, GenzFamily, TestFunction};

/// Independent points a plain run needs to meet the tolerance: enough for the CLT, few
/// enough that 200 runs of each family in 10-D take well under a second.
const PLAIN_POINTS: f64 = 16384.0;
/// First points per replicate of the RQMC runs: small, so that runs double several times.
const RQMC_FIRST_STAGE: u64 = 128;

/// An absolute tolerance that a plain run meets with about `PLAIN_POINTS` points:
/// `1.96 sigma / sqrt(PLAIN_POINTS)`, with the integrand's standard deviation `sigma` taken
/// from a separate run (seed outside the tested range).
fn tolerance_for(f: &Genz) -> Tolerance {
    let dims = f.dims();
    let reference = Integrator::over_box(|x: &[f64]| f.eval(x), UniformBox::unit(dims).unwrap())
        .samples(1 << 16)
        .seed(1_000_000)
        .run()
        .unwrap();
    let sigma = reference.std_error.unwrap() * ((1u64 << 16) as f64).sqrt();
    Tolerance::absolute(1.96 * sigma / PLAIN_POINTS.sqrt())
        .unwrap()
        .max_evaluations(1 << 22)
        .unwrap()
}

/// The Genz function of a test case: the customary parameters, except that for the two
/// families whose integrand is heavy-tailed with them in high dimension, corner peak and
/// discontinuous, `a` is rescaled to sum 2.5 (its 2-D value) in every dimension, as Genz
/// normalises the difficulty. With the customary `a` (sum 32.5 in 10-D) the 10-D corner peak
/// has a relative standard deviation of 640 and a skewness near 1900, the discontinuous
/// family 48 and 200, and no CLT interval is honest below millions of samples (the skewness
/// of a mean of `n` samples is `skew / sqrt(n)`); rescaled, the skewness is at most 18 and 5.
fn test_function(family: GenzFamily, dims: usize) -> Genz {
    let customary = Genz::with_defaults(family, dims).unwrap();
    if !matches!(family, GenzFamily::CornerPeak | GenzFamily::Discontinuous) {
        return customary;
    }
    let sum: f64 = customary.a().iter().sum();
    let a = customary.a().iter().map(|a| a * 2.5 / sum).collect();
    Genz::new(family, a, customary.u().to_vec()).unwrap()
}

fn coverage(family: GenzFamily, dims: usize, rqmc: bool) -> (u64, u64) {
    let f = test_function(family, dims);
    let exact = f.exact();
    let tolerance = tolerance_for(&f);
    let (mut covered, mut met) = (0, 0);
    for seed in 0..SEEDS {
        let mut integrator =
            Integrator::over_box(|x: &[f64]| f.eval(x), UniformBox::unit(dims).unwrap())
                .tolerance(tolerance)
                .seed(seed)
                .threads(1);
        if rqmc {
            integrator = integrator
                .sampler(Sobol::new(dims, Scramble::Owen, seed).unwrap())
                .samples(RQMC_FIRST_STAGE);
        }
        let e = integrator.run().unwrap();
        let (lo, hi) = e.confidence_interval(0.95).unwrap().unwrap();
        if lo <= exact && exact <= hi {
            covered += 1;
        }
        if e.converged == Some(true) {
            met += 1;
            assert_eq!(e.stop, StopReason::ToleranceMet);
            assert!(e.half_width(0.95).unwrap().unwrap() <= tolerance.target(e.mean));
        }
    }
    (covered, met)
}

fn check_family(family: GenzFamily) {
    for dims in [2, 5, 10] {
        for rqmc in [false, true] {
            let (covered, met) = coverage(family, dims, rqmc);
            eprintln!(
                "{family} d={dims} {}: covered {covered}/{SEEDS}, met {met}",
                if rqmc { "rqmc" } else { "plain" },
            );
            assert!(
                covered >= REQUIRED,
                "{family} d={dims} rqmc={rqmc}: covered {covered} of {SEEDS}"
            );
        }
    }
}

#[test]
fn coverage_oscillatory() {
    check_family(GenzFamily::Oscillatory);
}

#[test]
fn coverage_product_peak() {
    check_family(GenzFamily::ProductPeak);
}

#[test]
fn coverage_corner_peak() {
    check_family(GenzFamily::CornerPeak);
}

#[test]
fn coverage_gaussian() {
    check_family(GenzFamily::Gaussian);
}

#[test]
fn coverage_continuous() {
    check_family(GenzFamily::Continuous);
}

#[test]
fn coverage_discontinuous() {
    check_family(GenzFamily::Discontinuous);
}

fn quadratic() -> impl Fn(&[f64]) -> f64 + Send + Sync {
    |x: &[f64]| x.iter().map(|v| v * v).sum()
}

#[test]
fn evaluation_limit_stops_a_plain_run() {
    let tolerance = Tolerance::absolute(1e-6)
        .unwrap()
        .max_evaluations(50_000)
        .unwrap();
    let e = Integrator::over_box(quadratic(), UniformBox::unit(3).unwrap())
        .tolerance(tolerance)
        .seed(3)
        .run()
        .unwrap();
    assert_eq!(e.stop, StopReason::MaxEvaluations);
    assert_eq!(e.converged, Some(false));
    assert_eq!(e.evaluations, 50_000);
    // The estimate comes from the main stage alone, after the 4096-point pilot.
    assert_eq!(e.n, 50_000 - 4096);
    assert!((e.mean - 1.0).abs() < 5.0 * e.std_error.unwrap());
}

#[test]
fn evaluation_limit_stops_a_randomized_qmc_run() {
    let tolerance = Tolerance::absolute(1e-12)
        .unwrap()
        .max_evaluations(16 * 4096)
        .unwrap();
    let e = Integrator::over_box(quadratic(), UniformBox::unit(3).unwrap())
        .sampler(Sobol::new(3, Scramble::Owen, 5).unwrap())
        .samples(256)
        .tolerance(tolerance)
        .run()
        .unwrap();
    assert_eq!(e.stop, StopReason::MaxEvaluations);
    assert_eq!(e.converged, Some(false));
    // Stages of 256, 512, ..., 8192 points for each of the 8 replicates a run to a
    // tolerance starts with (the tolerance is far out of reach: no replicates are added).
    assert_eq!((e.iterations, e.replicates, e.n), (6, 8, 8 * 8192));
    assert!((e.mean - 1.0).abs() < 5.0 * e.std_error.unwrap());
}

/// Runs that end within reach of the tolerance add replicates instead of doubling: the
/// result is then that of a fixed-budget run of the same replicates and points per replicate
/// (the same points, folded in another order), and the tolerance is met.
#[test]
fn replicates_are_added_when_cheaper_than_doubling() {
    let f = Genz::with_defaults(GenzFamily::Gaussian, 5).unwrap();
    let integrand = |x: &[f64]| f.eval(x);
    let tolerance = Tolerance::absolute(1e-5).unwrap();
    let mut added = 0;
    for seed in 0..10 {
        let sobol = || Sobol::new(5, Scramble::Owen, seed).unwrap();
        let e = Integrator::over_box(integrand, UniformBox::unit(5).unwrap())
            .sampler(sobol())
            .tolerance(tolerance)
            .seed(seed)
            .run()
            .unwrap();
        assert_eq!(e.stop, StopReason::ToleranceMet);
        let per_replicate = e.n / e.replicates;
        assert_eq!(per_replicate * e.replicates, e.n);
        assert!(per_replicate.is_power_of_two() && per_replicate >= 1024);
        assert!(e.replicates >= 8, "{} replicates", e.replicates);
        if e.replicates > 8 {
            added += 1;
        }
        let fixed = Integrator::over_box(integrand, UniformBox::unit(5).unwrap())
            .sampler(sobol())
            .samples(per_replicate)
            .replicates(e.replicates)
            .seed(seed)
            .run()
            .unwrap();
        assert!((e.mean - fixed.mean).abs() <= 1e-13 * fixed.mean.abs());
        // The run reports the replicates' standard error inflated by 1.2.
        let se = fixed.std_error.unwrap() * 1.2;
        assert!((e.std_error.unwrap() - se).abs() <= 1e-9 * se);
    }
    assert!(added > 0, "no run added replicates");
}

#[test]
fn a_passed_time_limit_stops_the_run_before_its_first_stage() {
    let tolerance = Tolerance::relative(1e-9)
        .unwrap()
        .time_limit(std::time::Duration::ZERO);
    for rqmc in [false, true] {
        let mut integrator = Integrator::over_box(quadratic(), UniformBox::unit(2).unwrap())
            .tolerance(tolerance)
            .seed(8);
        if rqmc {
            integrator = integrator.sampler(Sobol::new(2, Scramble::Owen, 8).unwrap());
        }
        let err = integrator.run().unwrap_err();
        assert!(
            matches!(
                err,
                mcint::Error::Interrupted {
                    stop: StopReason::TimeLimit,
                    evaluations: 0
                }
            ),
            "rqmc = {rqmc}: {err}"
        );
    }
}

/// A tolerance that the pilot already meets: the pilot's estimate stands (one stage, its 4096
/// points), and covers as often as any fixed-size run (3797 of 4000 seeds for this case). The
/// rule used to size a main stage from it anyway, here a score of points whose own spread was
/// the error bar.
#[test]
fn a_pilot_that_meets_the_tolerance_stands() {
    let f = test_function(GenzFamily::Discontinuous, 5);
    let exact = f.exact();
    let reference = tolerance_for(&f).target(0.0) / 1.96 * PLAIN_POINTS.sqrt();
    // Met by about 16 points: the 4096 of the pilot meet it with a wide margin.
    let tolerance = Tolerance::absolute(1.96 * reference / 4.0).unwrap();
    let mut covered = 0;
    for seed in 0..SEEDS {
        let e = Integrator::over_box(|x: &[f64]| f.eval(x), UniformBox::unit(5).unwrap())
            .tolerance(tolerance)
            .seed(seed)
            .threads(1)
            .run()
            .unwrap();
        assert_eq!(
            (e.stop, e.iterations, e.n, e.evaluations),
            (StopReason::ToleranceMet, 1, 4096, 4096)
        );
        let (lo, hi) = e.confidence_interval(0.95).unwrap().unwrap();
        covered += u64::from(lo <= exact && exact <= hi);
    }
    eprintln!("pilot that meets: covered {covered} of {SEEDS}");
    assert!(covered >= REQUIRED, "covered {covered} of {SEEDS}");
}

#[test]
fn a_met_tolerance_is_met_and_counts_every_evaluation() {
    let tolerance = Tolerance::new(Some(1e-3), Some(1e-3)).unwrap();
    let plain = Integrator::over_box(quadratic(), UniformBox::unit(4).unwrap())
        .tolerance(tolerance)
        .seed(11)
        .run()
        .unwrap();
    assert_eq!(
        (plain.stop, plain.converged),
        (StopReason::ToleranceMet, Some(true))
    );
    assert!(plain.half_width(0.95).unwrap().unwrap() <= tolerance.target(plain.mean));
    assert_eq!(plain.evaluations, plain.n + 4096);
    let rqmc = Integrator::over_box(quadratic(), UniformBox::unit(4).unwrap())
        .sampler(Sobol::new(4, Scramble::Owen, 11).unwrap())
        .tolerance(tolerance)
        .run()
        .unwrap();
    assert_eq!(
        (rqmc.stop, rqmc.converged),
        (StopReason::ToleranceMet, Some(true))
    );
    assert_eq!(rqmc.evaluations, rqmc.n);
    assert!((rqmc.mean - 4.0 / 3.0).abs() <= 2.0 * tolerance.target(rqmc.mean));
    // Randomized QMC reaches it with far fewer points than plain Monte Carlo.
    assert!(rqmc.evaluations * 2 < plain.evaluations);
}

#[test]
fn runs_that_cannot_give_an_error_bar_are_refused() {
    let tolerance = Tolerance::absolute(1e-3).unwrap();
    let unrandomized = Integrator::over_box(quadratic(), UniformBox::unit(2).unwrap())
        .sampler(Sobol::new(2, Scramble::None, 0).unwrap())
        .tolerance(tolerance)
        .run()
        .unwrap_err()
        .to_string();
    assert!(
        unrandomized.contains("randomized sampler"),
        "{unrandomized}"
    );
    let one_replicate = Integrator::over_box(quadratic(), UniformBox::unit(2).unwrap())
        .sampler(Sobol::new(2, Scramble::Owen, 0).unwrap())
        .replicates(1)
        .tolerance(tolerance)
        .run()
        .unwrap_err()
        .to_string();
    assert!(one_replicate.contains("at least 2"), "{one_replicate}");
    let tiny_budget = Integrator::over_box(quadratic(), UniformBox::unit(2).unwrap())
        .tolerance(tolerance.max_evaluations(100).unwrap())
        .run()
        .unwrap_err()
        .to_string();
    assert!(tiny_budget.contains("max_evals"), "{tiny_budget}");
}
