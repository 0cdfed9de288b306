//! MISER (recursive stratified sampling): accuracy on the Genz families, variance against
//! plain Monte Carlo, coverage of the replicate error bars, thread-count independence,
//! quasi-random points, the tolerance stop rule and parameter checking.

use std::time::Duration;

use mcint::adaptive::Miser;
use mcint::pdf::UniformBox;
use mcint::sampler::{Independent, Jittered, Pmj02, Scramble, Sobol};
use mcint::stats::{ErrorBasis, StopReason, Tolerance};
use mcint::testfns::{Genz, GenzFamily, TestFunction};

fn miser(g: &Genz) -> Miser<impl Fn(&[f64]) -> f64 + Sync + '_> {
    Miser::new(|x: &[f64]| g.eval(x), UniformBox::unit(g.dims()).unwrap())
}

#[test]
fn genz_families_in_2_and_5_dimensions_are_within_5_standard_errors() {
    for d in [2, 5] {
        for family in GenzFamily::ALL {
            let g = Genz::with_defaults(family, d).unwrap();
            let e = miser(&g).samples(1 << 14).seed(11).run().unwrap();
            let se = e.std_error.unwrap();
            let z = (e.mean - g.exact()) / se;
            assert!(z.abs() < 5.0, "{family} d={d}: z = {z:.2}, {e:?}");
            // 16 replicates of 2^14 evaluations: a Student-t error bar with 15 dof.
            assert_eq!(e.basis, ErrorBasis::Replicates);
            assert_eq!((e.replicates, e.dof, e.n), (16, Some(15.0), 1 << 18));
            assert_eq!(
                (e.stop, e.converged, e.iterations),
                (StopReason::Budget, None, 1)
            );
        }
    }
}

/// Exact variance of one uniform sample of `g` from the exact integrals of `g` and `g^2`
/// (for these families `g^2` is the same family with every `a_i` doubled, or times sqrt 2).
fn plain_variance(g: &Genz, squared: &Genz) -> f64 {
    squared.exact() - g.exact() * g.exact()
}

#[test]
fn beats_plain_monte_carlo_on_a_discontinuous_and_a_peaked_integrand() {
    // Discontinuous: exp(a.x) on [0, u1) x [0, u2), zero elsewhere; its square doubles a.
    let disc = Genz::with_defaults(GenzFamily::Discontinuous, 2).unwrap();
    let disc_sq = Genz::new(
        GenzFamily::Discontinuous,
        disc.a().iter().map(|a| 2.0 * a).collect(),
        disc.u().to_vec(),
    )
    .unwrap();
    // Peaked: exp(-400 |x - u|^2); its square has a times sqrt 2.
    let peak = Genz::new(GenzFamily::Gaussian, vec![20.0, 20.0], vec![0.7, 0.3]).unwrap();
    let peak_sq = Genz::new(
        GenzFamily::Gaussian,
        vec![20.0 * 2f64.sqrt(); 2],
        peak.u().to_vec(),
    )
    .unwrap();
    let n = 1u64 << 18;
    for (g, g_sq) in [(&disc, &disc_sq), (&peak, &peak_sq)] {
        let plain = plain_variance(g, g_sq) / n as f64;
        let e = miser(g).samples(n / 16).seed(5).run().unwrap();
        let ratio = plain / e.variance().unwrap();
        // Over 200 seeds MISER's variance at this budget is 69 (discontinuous) and 53 (peak)
        // times smaller than plain Monte Carlo's. The replicate variance is sigma^2 chi2_15/15,
        // which exceeds 2.84 sigma^2 with probability 1e-4, so the observed ratio is above
        // 53 / 2.84 = 18 but for a 1e-4 chance; 10 leaves room for the 10% uncertainty of
        // those measurements.
        assert!(ratio > 10.0, "{}: variance ratio {ratio:.1}", g.name());
        assert!(((e.mean - g.exact()) / e.std_error.unwrap()).abs() < 5.0);
    }
}

#[test]
fn replicate_intervals_cover_the_exact_integral() {
    // 200 independent runs on the discontinuous family, where MISER adapts the most. If the
    // intervals are honest, misses are Binomial(200, 0.05) at 95% (mean 10; P(>= 24) < 2e-5)
    // and Binomial(200, 0.01) at 99% (mean 2; P(>= 11) < 1e-5). So: at least 177/200 and
    // 190/200. (186/200 at 95% would fail 8% of honest runs: P(Bin(200, 0.05) >= 15) = 0.078.)
    let g = Genz::with_defaults(GenzFamily::Discontinuous, 2).unwrap();
    let (mut in95, mut in99) = (0, 0);
    for seed in 0..200 {
        let e = miser(&g).samples(1 << 12).seed(seed).run().unwrap();
        let (lo, hi) = e.confidence_interval(0.95).unwrap().unwrap();
        in95 += usize::from(lo <= g.exact() && g.exact() <= hi);
        let (lo, hi) = e.confidence_interval(0.99).unwrap().unwrap();
        in99 += usize::from(lo <= g.exact() && g.exact() <= hi);
    }
    assert!(in95 >= 177, "95% intervals covered {in95}/200");
    assert!(in99 >= 190, "99% intervals covered {in99}/200");
}

#[test]
fn results_are_bit_identical_for_any_thread_count() {
    // With 2 replicates of 2^19 and 3 threads, a spare thread takes large subregions, so the
    // split of the tree between threads differs from run to run of the thread count.
    let g = Genz::with_defaults(GenzFamily::Oscillatory, 3).unwrap();
    for replicates in [2, 5] {
        let run = |threads| {
            miser(&g)
                .samples((1 << 20) / replicates)
                .replicates(replicates)
                .dither(0.1)
                .seed(3)
                .threads(threads)
                .run()
                .unwrap()
        };
        let one = run(1);
        assert_eq!(one, run(2));
        assert_eq!(one, run(3));
    }
    // The seed matters, and the sampler's seed is overridden by `seed`.
    let a = miser(&g).samples(1 << 10).seed(1).run().unwrap();
    let b = miser(&g)
        .sampler(Independent::new(3, 99).unwrap())
        .samples(1 << 10)
        .seed(1)
        .run()
        .unwrap();
    let c = miser(&g).samples(1 << 10).seed(2).run().unwrap();
    assert_eq!(a, b);
    assert_ne!(a.mean, c.mean);
}

#[test]
fn owen_scrambled_sobol_points_are_accepted_and_accurate() {
    for family in [GenzFamily::Gaussian, GenzFamily::Discontinuous] {
        let g = Genz::with_defaults(family, 5).unwrap();
        let run = |threads| {
            miser(&g)
                .sampler(Sobol::new(5, Scramble::Owen, 0).unwrap())
                .samples(1 << 14)
                .seed(21)
                .threads(threads)
                .run()
                .unwrap()
        };
        let e = run(2);
        let z = (e.mean - g.exact()) / e.std_error.unwrap();
        assert!(z.abs() < 5.0, "{family}: z = {z:.2}");
        assert_eq!(e, run(1));
    }
    // Passes of 16 points: leaves and explorations spill over several passes.
    let g = Genz::with_defaults(GenzFamily::ProductPeak, 2).unwrap();
    let e = miser(&g)
        .sampler(Pmj02::with_max_points(2, 4, 0).unwrap())
        .samples(1 << 12)
        .seed(2)
        .run()
        .unwrap();
    assert!(((e.mean - g.exact()) / e.std_error.unwrap()).abs() < 5.0);
    // An unscrambled sequence has no randomness for replicates; fixed passes cannot be cut
    // into batches of any size; the dimension must match the domain.
    let g = Genz::with_defaults(GenzFamily::Gaussian, 2).unwrap();
    let err = |e: mcint::Error| e.to_string();
    let unscrambled = miser(&g).sampler(Sobol::new(2, Scramble::None, 0).unwrap());
    assert!(err(unscrambled.run().unwrap_err()).contains("randomized"));
    let fixed = miser(&g).sampler(Jittered::new(2, 4, 0).unwrap());
    assert!(err(fixed.run().unwrap_err()).contains("fixed passes"));
    let wrong = miser(&g).sampler(Independent::new(3, 0).unwrap());
    assert!(err(wrong.run().unwrap_err()).contains("expected 2"));
}

#[test]
fn tolerance_stops_the_run_for_the_right_reason() {
    let g = Genz::with_defaults(GenzFamily::Continuous, 2).unwrap();
    // Met: the 95% half-width is within the tolerance, after doubling from 2^12.
    let tol = Tolerance::absolute(2e-4).unwrap();
    let e = miser(&g)
        .tolerance(tol)
        .samples(1 << 8)
        .seed(4)
        .run()
        .unwrap();
    assert_eq!(
        (e.stop, e.converged),
        (StopReason::ToleranceMet, Some(true))
    );
    assert!(e.half_width(0.95).unwrap().unwrap() <= 2e-4);
    assert!(e.iterations > 1, "2^12 evaluations cannot reach 2e-4");
    // Stages of 2^12, 2^13, ...: n counts all of them.
    assert_eq!(e.evaluations, (1 << 12) * ((1 << e.iterations) - 1));
    assert!(((e.mean - g.exact()) / e.std_error.unwrap()).abs() < 5.0);

    // Out of evaluations: stages of 4096, 8192, 16384 fit in 28672, the next does not.
    let tight = Tolerance::absolute(1e-12)
        .unwrap()
        .max_evaluations(28_672)
        .unwrap();
    let e = miser(&g)
        .tolerance(tight)
        .samples(256)
        .seed(4)
        .run()
        .unwrap();
    assert_eq!(
        (e.stop, e.converged),
        (StopReason::MaxEvaluations, Some(false))
    );
    assert_eq!((e.iterations, e.evaluations), (3, 28_672));

    // Out of time before the first stage finished: no estimate, and an error that says so.
    let timed = Tolerance::absolute(1e-12)
        .unwrap()
        .time_limit(Duration::ZERO);
    let err = miser(&g).tolerance(timed).seed(4).run().unwrap_err();
    assert!(
        matches!(
            err,
            mcint::Error::Interrupted {
                stop: StopReason::TimeLimit,
                ..
            }
        ),
        "{err}"
    );

    // Relative tolerances work the same way.
    let rel = Tolerance::relative(1e-3).unwrap();
    let e = miser(&g).tolerance(rel).seed(4).run().unwrap();
    assert_eq!(e.stop, StopReason::ToleranceMet);
    assert!(e.half_width(0.95).unwrap().unwrap() <= 1e-3 * e.mean.abs());
}

#[test]
fn bad_parameters_are_errors_that_name_the_field() {
    let g = Genz::with_defaults(GenzFamily::Gaussian, 2).unwrap();
    fn message<F: Fn(&[f64]) -> f64 + Sync>(m: Miser<F>) -> String {
        m.run().unwrap_err().to_string()
    }
    let cases: Vec<(String, &str)> = vec![
        (message(miser(&g).samples(0)), "samples"),
        (message(miser(&g).replicates(0)), "replicates"),
        (message(miser(&g).replicates(1 << 21)), "replicates"),
        (
            message(
                miser(&g)
                    .replicates(1)
                    .tolerance(Tolerance::absolute(1.0).unwrap()),
            ),
            "replicates",
        ),
        (
            message(
                miser(&g).tolerance(
                    Tolerance::absolute(1.0)
                        .unwrap()
                        .max_evaluations(8)
                        .unwrap(),
                ),
            ),
            "max_evals",
        ),
        (message(miser(&g).explore_fraction(0.0)), "explore_fraction"),
        (message(miser(&g).explore_fraction(1.0)), "explore_fraction"),
        (
            message(miser(&g).explore_fraction(f64::NAN)),
            "explore_fraction",
        ),
        (message(miser(&g).min_points(1)), "min_points"),
        (
            message(miser(&g).min_points(10).min_points_per_bisection(29)),
            "min_points_per_bisection",
        ),
        (message(miser(&g).dither(-0.1)), "dither"),
        (message(miser(&g).dither(0.5)), "dither"),
        (message(miser(&g).alpha(-0.5)), "alpha"),
        (message(miser(&g).alpha(f64::INFINITY)), "alpha"),
        (message(miser(&g).threads(0)), "threads"),
    ];
    for (message, field) in cases {
        assert!(
            message.starts_with(&format!("invalid {field} = ")),
            "{field}: {message}"
        );
    }
    // A NaN from the integrand is reported with its count and where it happened.
    let nan = Miser::new(
        |x: &[f64]| if x[0] < 0.5 { f64::NAN } else { 1.0 },
        UniformBox::unit(2).unwrap(),
    )
    .samples(1 << 8)
    .run()
    .unwrap_err()
    .to_string();
    assert!(nan.contains("non-finite"), "{nan}");
}

#[test]
fn boundary_settings_still_give_correct_answers() {
    // Tiny budgets (a single leaf per replicate), alpha = 0 and a large dither all keep the
    // estimate unbiased; only its variance changes.
    let g = Genz::with_defaults(GenzFamily::ProductPeak, 3).unwrap();
    let settings: Vec<Miser<_>> = vec![
        miser(&g).samples(3),
        miser(&g).alpha(0.0).samples(1 << 12),
        miser(&g).dither(0.4).samples(1 << 12),
        miser(&g)
            .explore_fraction(0.9)
            .min_points(2)
            .samples(1 << 12),
        miser(&g)
            .min_points(2)
            .min_points_per_bisection(6)
            .samples(1 << 10),
    ];
    for (i, m) in settings.into_iter().enumerate() {
        let e = m.seed(8).run().unwrap();
        let z = (e.mean - g.exact()) / e.std_error.unwrap();
        assert!(z.abs() < 5.0, "setting {i}: z = {z:.2}");
    }
}
