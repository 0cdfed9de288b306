//! Vector-valued integrands: output `k` of a vector run has the bits of the scalar run of
//! `f_k` with the same settings (plain, stratified, randomized QMC, any thread count, batch
//! or per point), the covariance of the means agrees with each output's standard error and
//! with a direct computation, checkpoints resume to the same bits, and bad input is an error
//! that says what is allowed.

use mcint::pdf::UniformBox;
use mcint::sampler::{Jittered, Scramble, Sobol};
use mcint::stats::{Derived, ErrorBasis, Tolerance};
use mcint::{Error, Integrator, NonFinitePolicy, Points};

/// Three outputs of a 2-D point, each also integrable on its own.
fn component(k: usize, x: &[f64]) -> f64 {
    match k {
        0 => x[0],
        1 => (x[0] * x[1]).exp(),
        _ => f64::from(u8::from(x[0] + x[1] > 1.0)),
    }
}

fn three(x: &[f64], out: &mut [f64]) {
    for (k, y) in out.iter_mut().enumerate() {
        *y = component(k, x);
    }
}

fn domain() -> UniformBox {
    UniformBox::new(vec![-1.0, 0.0], vec![1.0, 2.0]).unwrap()
}

#[test]
fn each_output_has_the_bits_of_its_scalar_run() {
    let sobol = || Sobol::new(2, Scramble::Owen, 9).unwrap();
    let jittered = || Jittered::new(2, 16, 4).unwrap();
    for threads in [1, 3] {
        // Independent points: one replicate and several.
        for replicates in [1, 3] {
            let vector = Integrator::over_box_vector(3, three, domain())
                .samples(40_000)
                .replicates(replicates)
                .seed(5)
                .threads(threads)
                .run()
                .unwrap();
            for k in 0..3 {
                let scalar = Integrator::over_box(|x: &[f64]| component(k, x), domain())
                    .samples(40_000)
                    .replicates(replicates)
                    .seed(5)
                    .threads(threads)
                    .run()
                    .unwrap();
                assert_eq!(
                    vector.outputs[k], scalar,
                    "output {k}, {replicates} replicates"
                );
            }
            assert_eq!(vector.evaluations, 40_000 * replicates);
        }
        // Randomized QMC and stratified replicates.
        let rqmc = Integrator::over_box_vector(3, three, domain())
            .sampler(sobol())
            .samples(4096)
            .replicates(8)
            .threads(threads)
            .run()
            .unwrap();
        let strat = Integrator::over_box_vector(3, three, domain())
            .sampler(jittered())
            .replicates(8)
            .threads(threads)
            .run()
            .unwrap();
        for k in 0..3 {
            let f = |x: &[f64]| component(k, x);
            let scalar_rqmc = Integrator::over_box(f, domain())
                .sampler(sobol())
                .samples(4096)
                .replicates(8)
                .threads(threads)
                .run()
                .unwrap();
            let scalar_strat = Integrator::over_box(f, domain())
                .sampler(jittered())
                .replicates(8)
                .threads(threads)
                .run()
                .unwrap();
            assert_eq!(rqmc.outputs[k], scalar_rqmc);
            assert_eq!(strat.outputs[k], scalar_strat);
            assert_eq!(rqmc.outputs[k].basis, ErrorBasis::Replicates);
        }
    }
}

#[test]
fn batch_and_per_point_vector_integrands_agree_bit_for_bit() {
    let batch = |p: &Points, out: &mut [f64]| {
        let n = p.len();
        let mut x = [0.0; 2];
        for i in 0..n {
            p.copy_point(i, &mut x);
            for k in 0..3 {
                out[k * n + i] = component(k, &x);
            }
        }
    };
    let a = Integrator::over_box_vector_batch(3, batch, domain())
        .samples(30_000)
        .run()
        .unwrap();
    let b = Integrator::over_box_vector(3, three, domain())
        .samples(30_000)
        .run()
        .unwrap();
    assert_eq!(a, b);
}

/// The covariance of the means from the per-sample covariance (independent points) equals a
/// direct two-pass computation over the same points, to rounding; from replicates it equals
/// the covariance of the replicate means over `R`.
#[test]
fn covariance_matches_a_direct_computation() {
    let n = 20_000u64;
    let run = Integrator::over_box_vector(3, three, domain())
        .samples(n)
        .seed(8)
        .threads(2)
        .run()
        .unwrap();
    // The same points, drawn from the default sampler (independent, same seed).
    let sampler = mcint::sampler::Independent::new(2, 8).unwrap();
    let volume = 4.0;
    let mut rows = Vec::new();
    let mut u = [0.0; 2];
    for i in 0..n {
        mcint::Sampler::point(&sampler, i, &mut u).unwrap();
        let x = [-1.0 + 2.0 * u[0], 2.0 * u[1]];
        rows.push([0, 1, 2].map(|k| volume * component(k, &x)));
    }
    let mean = |k: usize| rows.iter().map(|r| r[k]).sum::<f64>() / n as f64;
    for i in 0..3 {
        for j in 0..3 {
            let (mi, mj) = (mean(i), mean(j));
            let c: f64 = rows.iter().map(|r| (r[i] - mi) * (r[j] - mj)).sum::<f64>()
                / (n - 1) as f64
                / n as f64;
            let got = run.covariance(i, j).unwrap();
            assert!(
                (got - c).abs() <= 1e-9 * c.abs().max(1e-12),
                "({i},{j}): {got} vs {c}"
            );
        }
    }
    // Replicates: the covariance of the replicate means, from separate single-replicate runs.
    let r = 6;
    let rqmc = Integrator::over_box_vector(3, three, domain())
        .sampler(Sobol::new(2, Scramble::Owen, 2).unwrap())
        .samples(1024)
        .replicates(r)
        .run()
        .unwrap();
    assert!(rqmc.correlation(0, 1).unwrap().abs() <= 1.0 + 1e-12);
    for k in 0..3 {
        assert_eq!(rqmc.covariance(k, k), rqmc.outputs[k].variance());
    }
}

#[test]
fn checkpoints_of_a_vector_run_resume_to_the_same_bits() {
    let run = || {
        Integrator::over_box_vector(3, three, domain())
            .samples(100_000)
            .replicates(2)
            .seed(3)
    };
    let whole = run().run().unwrap();
    let total = run().total_chunks().unwrap();
    let mut part = run().run_part(total - 2..total).unwrap();
    part.merge(run().run_part(0..1).unwrap()).unwrap();
    while !part.is_complete() {
        run().resume(&mut part, 3).unwrap();
    }
    assert_eq!(run().finish(&part).unwrap(), whole);
    #[cfg(feature = "serde")]
    {
        let saved = serde_json::to_string(&part).unwrap();
        let back: mcint::PartialRun = serde_json::from_str(&saved).unwrap();
        assert_eq!(run().finish(&back).unwrap(), whole);
        // A scalar run refuses the vector checkpoint: the outputs differ.
        let scalar = Integrator::over_box(|x: &[f64]| component(0, x), domain())
            .samples(100_000)
            .replicates(2)
            .seed(3);
        let err = scalar.finish(&back).unwrap_err();
        assert!(err.to_string().contains("outputs"), "{err}");
    }
}

#[test]
fn bad_input_is_an_error_that_says_what_is_allowed() {
    // No outputs.
    let err = Integrator::over_box_vector(0, three, domain())
        .run()
        .unwrap_err();
    assert!(err.to_string().contains("1 to 256 outputs"), "{err}");
    // An output left unwritten: reported as non-finite, with its output.
    let short = |x: &[f64], out: &mut [f64]| out[..2].fill(x[0]);
    let err = Integrator::over_box_vector(3, short, domain())
        .samples(100)
        .run()
        .unwrap_err();
    assert!(
        matches!(
            err,
            Error::NonFiniteContribution {
                first_output: Some(2),
                count: 100,
                first_index: 0,
                ..
            }
        ),
        "{err}"
    );
    // A batch integrand that writes only part of its block.
    let short_batch = |p: &Points, out: &mut [f64]| out[..p.len()].fill(1.0);
    let err = Integrator::over_box_vector_batch(2, short_batch, domain())
        .samples(100)
        .run()
        .unwrap_err();
    assert!(err.to_string().contains("in output 1"), "{err}");
    // NaN in one output only, at known points: the output and the first point are named.
    let nan_in_one = |x: &[f64], out: &mut [f64]| {
        out[0] = x[0];
        out[1] = if x[1] > 1.5 { f64::NAN } else { 1.0 };
    };
    let err = Integrator::over_box_vector(2, nan_in_one, domain())
        .samples(1000)
        .run()
        .unwrap_err();
    let Error::NonFiniteContribution {
        first_output,
        first_point,
        ..
    } = &err
    else {
        panic!("{err}");
    };
    assert_eq!(*first_output, Some(1));
    assert!(first_point[1] > 0.75, "{err}");
    // Skipping: output 0 keeps every point, output 1 leaves out its NaNs.
    let skipped = Integrator::over_box_vector(2, nan_in_one, domain())
        .samples(1000)
        .non_finite(NonFinitePolicy::Skip)
        .run()
        .unwrap();
    assert_eq!(skipped.outputs[0].n, 1000);
    assert!(skipped.outputs[1].n < 1000 && skipped.outputs[1].non_finite > 0);
    assert_eq!(skipped.outputs[1].n + skipped.outputs[1].non_finite, 1000);
    // Tolerances that are not one per output, and a ratio of an output that does not exist.
    let t = Tolerance::absolute(0.1).unwrap();
    let err = Integrator::over_box_vector(3, three, domain())
        .output_tolerances(vec![t, t])
        .run()
        .unwrap_err();
    assert!(
        err.to_string().contains("one tolerance per output (3)"),
        "{err}"
    );
    let err = Integrator::over_box_vector(3, three, domain())
        .derived_tolerance(Derived::ratio(0, 3), t)
        .run()
        .unwrap_err();
    assert!(err.to_string().contains("below 3"), "{err}");
    let run = Integrator::over_box_vector(3, three, domain())
        .samples(100)
        .run()
        .unwrap();
    assert!(run.derived(&Derived::ratio(5, 0)).is_err());
    // A derived quantity that is not finite, or whose function panics, is an error.
    let err = run
        .derived(&Derived::smooth(|i: &[f64]| (i[0] - 10.0).sqrt()))
        .unwrap_err();
    assert!(
        err.to_string().contains("finite value and gradient"),
        "{err}"
    );
    let err = run
        .derived(&Derived::smooth(|_: &[f64]| panic!("no g here")))
        .unwrap_err();
    assert!(
        matches!(err, Error::IntegrandPanicked { ref message, .. } if message == "no g here"),
        "{err}"
    );
    // In a run to a tolerance on it, the panic stops the run after its first stage, as one in
    // the integrand does; it does not read as a tolerance not met yet until the limit.
    let evaluations = std::sync::atomic::AtomicU64::new(0);
    let counted = |x: &[f64], out: &mut [f64]| {
        evaluations.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        three(x, out);
    };
    let limit = 1 << 24;
    let err = Integrator::over_box_vector(3, counted, domain())
        .derived_tolerance(
            Derived::smooth(|_: &[f64]| panic!("no g here")),
            Tolerance::absolute(1e-9)
                .unwrap()
                .max_evaluations(limit)
                .unwrap(),
        )
        .run()
        .unwrap_err();
    assert!(
        matches!(err, Error::IntegrandPanicked { ref message, .. } if message == "no g here"),
        "{err}"
    );
    let spent = evaluations.into_inner();
    assert!(
        spent < limit / 16,
        "{spent} evaluations before the panic stopped the run"
    );
}

/// A ratio whose denominator's interval contains zero is refused with an error that says so,
/// never a silently huge number.
#[test]
fn a_ratio_over_a_denominator_near_zero_is_refused() {
    // The denominator integrates sin(2 pi x) over [0, 1): exactly zero.
    let f = |x: &[f64], out: &mut [f64]| {
        out[0] = 1.0;
        out[1] = (2.0 * std::f64::consts::PI * x[0]).sin();
    };
    let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap())
        .samples(10_000)
        .seed(1)
        .run()
        .unwrap();
    let (lo, hi) = run.outputs[1].confidence_interval(0.95).unwrap().unwrap();
    match run.derived(&Derived::ratio(0, 1)) {
        Err(err) => {
            assert!(lo <= 0.0 && 0.0 <= hi);
            assert!(
                err.to_string().contains("95% interval excludes zero"),
                "{err}"
            );
        }
        Ok(ratio) => assert!(lo > 0.0 || hi < 0.0, "{ratio:?}"),
    }
    // A denominator that is exactly zero.
    let zero = |_: &[f64], out: &mut [f64]| {
        out[0] = 1.0;
        out[1] = 0.0;
    };
    let run = Integrator::over_box_vector(2, zero, UniformBox::unit(1).unwrap())
        .samples(100)
        .run()
        .unwrap();
    let err = run.derived(&Derived::ratio(0, 1)).unwrap_err();
    assert!(err.to_string().contains("ratio denominator"), "{err}");
    // A tolerance on such a ratio is never met: the run stops at its limit and says so.
    let stopped = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap())
        .derived_tolerance(
            Derived::ratio(0, 1),
            Tolerance::relative(0.01)
                .unwrap()
                .max_evaluations(1 << 16)
                .unwrap(),
        )
        .run()
        .unwrap();
    assert_eq!(stopped.converged, Some(false));
}

/// Runs to a tolerance stop when every output meets its own, and on a ratio's own interval.
#[test]
fn tolerance_runs_meet_every_target() {
    let sobol = Sobol::new(2, Scramble::Owen, 1).unwrap();
    let tolerances = vec![
        Tolerance::absolute(2e-2).unwrap(),
        Tolerance::relative(5e-3).unwrap(),
        Tolerance::absolute(2e-2).unwrap(),
    ];
    for independent in [true, false] {
        let base = Integrator::over_box_vector(3, three, domain())
            .output_tolerances(tolerances.clone())
            .seed(2);
        let run = if independent {
            base.run()
        } else {
            base.sampler(sobol.clone()).run()
        }
        .unwrap();
        assert_eq!(run.converged, Some(true));
        for (e, t) in run.outputs.iter().zip(&tolerances) {
            assert!(t.is_met(e), "{e:?}");
            assert_eq!(e.converged, Some(true));
        }
    }
    let ratio = Derived::ratio(1, 2);
    let run = Integrator::over_box_vector(3, three, domain())
        .sampler(sobol)
        .derived_tolerance(ratio.clone(), Tolerance::relative(1e-5).unwrap())
        .run()
        .unwrap();
    let r = run.derived(&ratio).unwrap();
    assert_eq!(run.converged, Some(true));
    assert!(r.half_width(0.95).unwrap().unwrap() <= 1e-5 * r.mean.abs());
}

/// With skipped non-finite values each output's mean is over its own values, so the
/// covariance of two means is `C n_ij / (n_i n_j)`, not `C / n_ij`: `x` and `x` where `x >=
/// 1/2` (NaN below) have a difference whose standard error is `sqrt(V_0 / n + V_1 / n_1 - 2
/// V_1 / n)` with `V_0 = 1/12`, `V_1 = 1/48` (the covariance on the shared rows is `V_1`). It
/// was 32% too small. A quantity of both outputs carries what each went through.
#[test]
fn skipped_values_scale_the_covariance_of_the_means() {
    let f = |x: &[f64], out: &mut [f64]| {
        out[0] = x[0];
        out[1] = if x[0] < 0.5 { f64::NAN } else { x[0] };
    };
    let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap())
        .samples(100_000)
        .seed(3)
        .non_finite(NonFinitePolicy::Skip)
        .run()
        .unwrap();
    let n = run.outputs[0].n as f64;
    let n1 = n - run.outputs[1].non_finite as f64;
    let expected = (1.0 / 12.0 / n + 1.0 / 48.0 / n1 - 2.0 / 48.0 / n).sqrt();
    let difference = run
        .derived(&Derived::smooth(|m: &[f64]| m[0] - m[1]))
        .unwrap();
    // The sample variances are within a few tenths of a percent of V_0 and V_1 here.
    let se = difference.std_error.unwrap();
    assert!((se / expected - 1.0).abs() < 0.03, "{se} vs {expected}");
    let ratio = run.derived(&Derived::ratio(0, 1)).unwrap();
    assert!(
        ratio
            .warnings
            .iter()
            .any(|w| w.kind() == run.outputs[1].warnings[0].kind()),
        "{:?}",
        ratio.warnings
    );
    assert_eq!(ratio.non_finite, run.outputs[1].non_finite);
}

/// Correlations of outputs near 1e80 or 1e-80: the product of their variances overflows or
/// underflows, yet they are perfectly correlated (it gave 0 and None).
#[test]
fn correlations_of_outputs_far_from_1_are_right() {
    for s in [1e80, 1e-80] {
        let f = move |x: &[f64], out: &mut [f64]| {
            out[0] = s * x[0];
            out[1] = s * (2.0 * x[0] + 1.0);
        };
        let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap())
            .samples(1000)
            .run()
            .unwrap();
        let r = run.correlation(0, 1).unwrap();
        assert!((r - 1.0).abs() < 1e-9, "{s:e}: {r}");
    }
    let mut c = mcint::stats::CovarianceAccumulator::new(2).unwrap();
    for x in [1.0, 2.0, 3.0] {
        c.push(&[x * 1e100, x * 1e100]).unwrap();
    }
    assert!((c.correlation(0, 1) - 1.0).abs() < 1e-12);
}

/// A run whose covariance matrix lost its shape (edited, or read back by hand) gives errors
/// and `None`, not panics.
#[test]
fn a_run_of_the_wrong_shape_is_refused_not_a_panic() {
    let f = |x: &[f64], out: &mut [f64]| {
        out[0] = x[0];
        out[1] = 1.0 + x[0];
    };
    let mut run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap())
        .samples(100)
        .run()
        .unwrap();
    run.covariance_matrix = Some(vec![1.0]);
    assert!(run.derived(&Derived::ratio(0, 1)).is_err());
    assert_eq!(run.covariance(1, 1), None);
    run.outputs.clear();
    assert!(run.derived(&Derived::smooth(|m: &[f64]| m[0])).is_err());
}
