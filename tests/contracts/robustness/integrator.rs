use super::*;
use mcint::pdf::UniformBox;
use mcint::sampler::{Independent, Jittered, LatinHypercube, Sampler, Scramble, Sobol};
use mcint::stats::Tolerance;
use mcint::{Integrator, NonFinitePolicy, Points};
use std::sync::atomic::{AtomicU64, Ordering};

fn sampler(which: usize, n: u64) -> Option<Box<dyn Sampler>> {
    match which {
        0 => None,
        1 => Some(Box::new(Independent::new(2, 0).unwrap())),
        2 => LatinHypercube::new(2, n.max(1), 0)
            .ok()
            .map(|s| Box::new(s) as _),
        3 => Some(Box::new(Sobol::new(2, Scramble::Owen, 0).unwrap())),
        4 => Some(Box::new(Sobol::new(2, Scramble::None, 0).unwrap())),
        5 => Some(Box::new(Jittered::new(2, 4, 0).unwrap())),
        // The wrong dimension.
        _ => Some(Box::new(Independent::new(3, 0).unwrap())),
    }
}

fn size() -> impl Strategy<Value = u64> {
    prop::sample::select(vec![
        0,
        1,
        2,
        16,
        100,
        1 << 14,
        (1 << 14) + 1,
        1 << 32,
        (1 << 32) + 1,
        1 << 40,
        u64::MAX / 2,
        u64::MAX,
    ])
}

proptest! {
    #![proptest_config(config(128, 0x1a7))]

    /// Settings are checked before any work; accepted runs small enough to do are done
    /// (the rest are only planned: `total_chunks` validates the same plan).
    #[test]
    fn settings(
        samples in prop::option::of(size()),
        replicates in prop::option::of(size()),
        threads in prop::option::of(prop::sample::select(vec![0usize, 1, 2, usize::MAX])),
        which in 0..7usize,
        pass in prop::sample::select(vec![1u64, 16, 1 << 14, 1 << 40]),
        seed in any::<u64>(),
    ) {
        let mut integrator = Integrator::over_box(|x: &[f64]| x[0] * x[1], UniformBox::unit(2).unwrap()).seed(seed);
        let randomized = which != 4;
        if let Some(s) = sampler(which, pass) {
            integrator = integrator.sampler(s);
        }
        if let Some(n) = samples {
            integrator = integrator.samples(n);
        }
        if let Some(r) = replicates {
            integrator = integrator.replicates(r);
        }
        if let Some(t) = threads {
            integrator = integrator.threads(t);
        }
        let pass_size = match which {
            2 => Some(pass),
            5 => Some(16),
            _ => None,
        };
        let n = samples.unwrap_or(pass_size.unwrap_or(1 << 16));
        let r = replicates.unwrap_or(1);
        let params = ["samples", "replicates", "threads", "sampler"];
        // The same checks as run, without running.
        let planned = integrator.total_chunks();
        if n == 0 || r == 0 || threads == Some(0) || which == 6 || (r > 1 && !randomized) {
            prop_assert!(planned.is_err());
        }
        check(planned, &params, |chunks| assert!(chunks >= 1));
        if n.checked_mul(r).is_some_and(|work| work <= 1 << 16) {
            let result = integrator.run();
            check(result, &params, |e| {
                assert!(e.mean.is_finite());
                assert_eq!(e.n, n * r);
            });
        }
    }

    /// A run to a tolerance stops at its evaluation limit, however unreachable the target.
    #[test]
    fn tolerance_runs_stop(
        tol in prop::sample::select(vec![1e-300, 1e-3, 1e300]),
        limit in prop::sample::select(vec![1u64, 100, 5000]),
        which in 0..7usize,
        replicates in prop::option::of(prop::sample::select(vec![0u64, 1, 2, 8])),
    ) {
        let tolerance = Tolerance::absolute(tol).unwrap().max_evaluations(limit).unwrap();
        let mut integrator = Integrator::over_box(|x: &[f64]| x[0] * x[1], UniformBox::unit(2).unwrap())
            .tolerance(tolerance)
            .threads(2);
        if let Some(s) = sampler(which, 16) {
            integrator = integrator.sampler(s);
        }
        if let Some(r) = replicates {
            integrator = integrator.replicates(r);
        }
        let result = integrator.run();
        check(result, &["samples", "replicates", "tolerance", "sampler", "max_evals"], |e| {
            assert!(e.mean.is_finite());
        });
    }
}

#[test]
fn parts_of_huge_runs_are_checked() {
    let integrator = || {
        Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
            .samples(1 << 40)
            .replicates(1 << 20)
    };
    let total = integrator().total_chunks().unwrap();
    assert!(total > 1 << 40);
    // Empty, reversed, past the end, and too long.
    let (five, three) = (5, 3);
    for range in [0..0, five..three, total..total + 1, 0..total + 1] {
        let err = integrator().run_part(range).unwrap_err();
        assert_clear(&err, &["chunk range"]);
    }
    let overflowing = Integrator::over_box(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
        .samples(u64::MAX / 2)
        .replicates(3);
    assert!(matches!(
        overflowing.total_chunks(),
        Err(Error::IndexOutOfRange { .. })
    ));
    let mut partial = integrator().run_part(0..1).unwrap();
    assert!(integrator().resume(&mut partial, 0).is_err());
    assert_clear(
        &integrator().finish(&partial).unwrap_err(),
        &["partial run"],
    );
}

/// The last chunk of a replicate whose local indices reach `u64::MAX` is evaluated (its
/// end was once computed as `first + CHUNK`, which overflowed: release builds evaluated
/// no point of it, debug builds panicked in the worker).
#[test]
fn last_chunk_near_the_end_of_the_index_range_is_evaluated() {
    let calls = AtomicU64::new(0);
    let integrator = Integrator::over_box(
        |x: &[f64]| {
            calls.fetch_add(1, Ordering::Relaxed);
            x[0]
        },
        UniformBox::unit(1).unwrap(),
    )
    .samples(u64::MAX)
    .threads(1);
    let total = integrator.total_chunks().unwrap();
    integrator.run_part(total - 1..total).unwrap();
    assert!(calls.load(Ordering::Relaxed) > 0);
}

#[test]
fn skipping_non_finite_values_still_needs_one_finite_value() {
    let e = Integrator::over_box(|_: &[f64]| f64::NAN, UniformBox::unit(1).unwrap())
        .samples(10)
        .non_finite(NonFinitePolicy::Skip)
        .run()
        .unwrap_err();
    assert_clear(&e, &["integrand"]);
}

#[test]
fn point_blocks_beyond_memory_are_errors() {
    for (dims, len) in [
        (0, 1),
        (usize::MAX, 2),
        (1, usize::MAX / 4),
        (1 << 33, 1 << 31),
    ] {
        match Points::new(dims, len) {
            Err(e) => assert_clear(&e, &["dims"]),
            Ok(_) => panic!("Points::new({dims}, {len}) was accepted"),
        }
    }
    assert!(Points::new(3, 0).is_ok());
}
