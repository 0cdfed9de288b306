//! Batch integrands (`Fn(&Points, &mut [f64])`): the same estimate bits as the per-point
//! integrand, any thread count, and unwritten or non-finite values caught by the run's policy.

use mcint::estimator::{BatchUniformEstimator, Estimator, UniformEstimator};
use mcint::pdf::UniformBox;
use mcint::sampler::{Independent, LatinHypercube, Scramble, Sobol};
use mcint::{Error, Integrator, NonFinitePolicy, Points};

/// The per-point integrand: a smooth function that uses every coordinate.
pub(super) fn f(x: &[f64]) -> f64 {
    x.iter()
        .enumerate()
        .map(|(i, &v)| (v * (i as f64 + 1.0)).cos())
        .sum::<f64>()
        .exp()
}

/// The same function over a block, column by column: per point it adds the same terms in the
/// same order, so each value has the same bits as `f`.
pub(super) fn f_batch(p: &Points, out: &mut [f64]) {
    out.fill(0.0);
    for d in 0..p.dims() {
        let scale = d as f64 + 1.0;
        for (y, &v) in out.iter_mut().zip(p.column(d)) {
            *y += (v * scale).cos();
        }
    }
    for y in out.iter_mut() {
        *y = y.exp();
    }
}

pub(super) fn boxes(dims: usize) -> Vec<UniformBox> {
    vec![
        UniformBox::unit(dims).unwrap(),
        UniformBox::new(
            (0..dims).map(|i| -1.5 + i as f64).collect(),
            (0..dims).map(|i| 0.25 + 2.0 * i as f64).collect(),
        )
        .unwrap(),
    ]
}

/// Builds a fresh sampler (a sampler is moved into the integrator).
type MakeSampler = fn() -> Box<dyn mcint::Sampler>;

#[test]
fn same_bits_as_the_per_point_integrand_for_every_sampler_and_box() {
    for domain in boxes(3) {
        // Sample counts that end mid-block (3000) and mid-chunk (20_000).
        let cases: [(MakeSampler, u64, u64); 4] = [
            (|| Box::new(Independent::new(3, 1).unwrap()), 3000, 1),
            (|| Box::new(Independent::new(3, 1).unwrap()), 20_000, 3),
            (
                || Box::new(Sobol::new(3, Scramble::Owen, 1).unwrap()),
                4096,
                8,
            ),
            (
                || Box::new(LatinHypercube::new(3, 1000, 1).unwrap()),
                1000,
                4,
            ),
        ];
        for (sampler, samples, replicates) in cases {
            let per_point = Integrator::over_box(f, domain.clone())
                .sampler(sampler())
                .samples(samples)
                .replicates(replicates)
                .seed(11)
                .threads(1)
                .run()
                .unwrap();
            let batch = Integrator::over_box_batch(f_batch, domain.clone())
                .sampler(sampler())
                .samples(samples)
                .replicates(replicates)
                .seed(11)
                .threads(1)
                .run()
                .unwrap();
            assert_eq!(batch, per_point, "{domain:?}, {samples} x {replicates}");
            assert_eq!(batch.mean.to_bits(), per_point.mean.to_bits());
        }
    }
}

#[test]
fn the_result_does_not_depend_on_the_thread_count() {
    for domain in boxes(4) {
        let run = |threads| {
            Integrator::over_box_batch(f_batch, domain.clone())
                .sampler(Sobol::new(4, Scramble::Owen, 0).unwrap())
                .samples(1 << 15)
                .replicates(6)
                .seed(5)
                .threads(threads)
                .run()
                .unwrap()
        };
        let one = run(1);
        assert_eq!(one, run(2));
        assert_eq!(one, run(5));
    }
}

#[test]
fn block_and_point_paths_agree_on_edge_coordinates() {
    // Coordinates a sampler never produces (1.0, -0.0, NaN) still map as UniformBox maps them,
    // including over the unit cube, where the canonical block is otherwise passed unmapped.
    let raw = [0.0, -0.0, 0.5, 1.0, f64::NAN, 1.0f64.next_down()];
    for domain in boxes(2) {
        let batch = BatchUniformEstimator::new(f_batch, domain.clone());
        let per_point = UniformEstimator::new(f, domain.clone());
        let mut block = Points::new(2, raw.len()).unwrap();
        block.column_mut(0).copy_from_slice(&raw);
        block.column_mut(1).copy_from_slice(&[0.25; 6]);
        let mut out = [0.0; 6];
        batch.contributions(&block, &mut out);
        let mut x = [0.0; 2];
        for (i, &u0) in raw.iter().enumerate() {
            let expected = per_point.contribution(&[u0, 0.25], &mut x);
            assert_eq!(
                out[i].to_bits(),
                expected.to_bits(),
                "u0 = {u0:?}, {domain:?}"
            );
            // The one-point path of the batch estimator too.
            let single = batch.contribution(&[u0, 0.25], &mut x);
            assert_eq!(single.to_bits(), expected.to_bits(), "u0 = {u0:?}");
        }
    }
}

#[test]
fn the_integrand_sees_domain_points_in_blocks_of_at_most_1024() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let largest = AtomicUsize::new(0);
    let calls = AtomicUsize::new(0);
    let domain = UniformBox::new(vec![2.0, -3.0], vec![2.5, -1.0]).unwrap();
    let e = Integrator::over_box_batch(
        |p: &Points, out: &mut [f64]| {
            assert_eq!(out.len(), p.len());
            largest.fetch_max(p.len(), Ordering::Relaxed);
            calls.fetch_add(1, Ordering::Relaxed);
            assert!(p.column(0).iter().all(|x| (2.0..2.5).contains(x)));
            assert!(p.column(1).iter().all(|x| (-3.0..-1.0).contains(x)));
            out.fill(1.0);
        },
        domain,
    )
    .samples(5000)
    .threads(2)
    .run()
    .unwrap();
    // The integral of 1 is the volume, exactly.
    assert_eq!(e.mean, 1.0);
    assert_eq!(largest.load(Ordering::Relaxed), 1024);
    // 5000 = 4 * 1024 + 904: five calls.
    assert_eq!(calls.load(Ordering::Relaxed), 5);
}

#[test]
fn unwritten_values_are_non_finite_and_follow_the_policy() {
    // Writes only the first half of each block.
    let lazy = |_: &Points, out: &mut [f64]| {
        let half = out.len() / 2;
        out[..half].fill(2.0);
    };
    let err = Integrator::over_box_batch(lazy, UniformBox::unit(2).unwrap())
        .samples(2048)
        .run()
        .unwrap_err();
    match err {
        Error::NonFiniteContribution {
            count,
            first_index,
            first_value,
            ..
        } => {
            assert_eq!(count, 1024);
            assert_eq!(first_index, 512);
            assert!(first_value.is_nan());
        }
        other => panic!("expected a non-finite error, got {other}"),
    }
    let skipped = Integrator::over_box_batch(lazy, UniformBox::unit(2).unwrap())
        .samples(2048)
        .non_finite(NonFinitePolicy::Skip)
        .run()
        .unwrap();
    assert_eq!(
        (skipped.mean, skipped.n, skipped.non_finite),
        (2.0, 1024, 1024)
    );
}

#[test]
fn stale_values_of_an_earlier_block_do_not_leak_into_a_later_one() {
    // The first call writes everything, later calls nothing: the later values must be NaN,
    // not the first block's values left in a reused buffer.
    use std::sync::atomic::{AtomicBool, Ordering};
    let first = AtomicBool::new(true);
    let err = Integrator::over_box_batch(
        |_: &Points, out: &mut [f64]| {
            if first.swap(false, Ordering::Relaxed) {
                out.fill(1.0);
            }
        },
        UniformBox::new(vec![0.0], vec![3.0]).unwrap(),
    )
    .samples(4096)
    .threads(1)
    .run()
    .unwrap_err();
    assert!(
        matches!(
            err,
            Error::NonFiniteContribution {
                count: 3072,
                first_index: 1024,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn infinite_values_are_reported_with_their_point() {
    let err = Integrator::over_box_batch(
        |p: &Points, out: &mut [f64]| {
            for (y, &x) in out.iter_mut().zip(p.column(0)) {
                *y = 1.0 / (x - 0.5).max(0.0);
            }
        },
        UniformBox::unit(1).unwrap(),
    )
    .samples(1000)
    .run()
    .unwrap_err();
    match err {
        Error::NonFiniteContribution {
            first_value,
            first_point,
            ..
        } => {
            assert_eq!(first_value, f64::INFINITY);
            assert!(first_point[0] <= 0.5, "{first_point:?}");
        }
        other => panic!("expected a non-finite error, got {other}"),
    }
}

#[test]
fn a_batch_integrand_may_run_a_nested_batch_integration() {
    // The inner run on the same thread must not share the outer run's scratch block: nested
    // batch runs over non-unit boxes give the bits of nested per-point runs.
    let inner_domain = UniformBox::new(vec![1.0, 1.0], vec![2.0, 4.0]).unwrap();
    let outer_domain = UniformBox::new(vec![0.0, 0.0], vec![1.0, 2.0]).unwrap();
    let inner_batch = |x: f64| {
        Integrator::over_box_batch(
            |q: &Points, o: &mut [f64]| {
                for (v, (&a, &b)) in o.iter_mut().zip(q.column(0).iter().zip(q.column(1))) {
                    *v = a * b * x;
                }
            },
            inner_domain.clone(),
        )
        .samples(1500)
        .threads(1)
        .run()
        .unwrap()
        .mean
    };
    let inner_point = |x: f64| {
        Integrator::over_box(|q: &[f64]| q[0] * q[1] * x, inner_domain.clone())
            .samples(1500)
            .threads(1)
            .run()
            .unwrap()
            .mean
    };
    let batch = Integrator::over_box_batch(
        |p: &Points, out: &mut [f64]| {
            for (y, (&x, &z)) in out.iter_mut().zip(p.column(0).iter().zip(p.column(1))) {
                *y = inner_batch(x) + z;
            }
        },
        outer_domain.clone(),
    )
    .samples(1100)
    .threads(1)
    .run()
    .unwrap();
    let per_point = Integrator::over_box(|p: &[f64]| inner_point(p[0]) + p[1], outer_domain)
        .samples(1100)
        .threads(1)
        .run()
        .unwrap();
    assert_eq!(batch, per_point);
}

#[test]
fn a_sampler_of_the_wrong_dimension_is_an_error() {
    let err = Integrator::over_box_batch(
        |_: &Points, out: &mut [f64]| out.fill(0.0),
        UniformBox::unit(3).unwrap(),
    )
    .sampler(Independent::new(2, 0).unwrap())
    .run()
    .unwrap_err();
    assert!(
        matches!(
            err,
            Error::DimensionMismatch {
                expected: 3,
                found: 2,
                ..
            }
        ),
        "{err}"
    );
}

/// Two outputs per point, `f` and `x0 f`, as the per-point vector form writes them.
fn two_outputs(x: &[f64], out: &mut [f64]) {
    out[0] = f(x);
    out[1] = x[0] * out[0];
}

/// The same two outputs over a block, output-major (`out[k * n + i]`).
fn two_outputs_batch(p: &Points, out: &mut [f64]) {
    let n = p.len();
    let (first, second) = out.split_at_mut(n);
    f_batch(p, first);
    for ((y, &value), &x0) in second.iter_mut().zip(first.iter()).zip(p.column(0)) {
        *y = x0 * value;
    }
}

#[test]
fn vegas_by_blocks_has_the_bits_of_vegas_by_points_on_any_thread_count() {
    use mcint::adaptive::Vegas;
    use mcint::stats::{StopReason, Tolerance};
    for domain in boxes(3) {
        for stratified in [false, true] {
            // A run of several iterations that ends on the tolerance (checked below): its
            // bits are what must not depend on blocks or threads, not its length.
            let tolerance = Tolerance::relative(5e-4).unwrap();
            let per_point = Vegas::new_vector(2, two_outputs, domain.clone())
                .stratified(stratified)
                .samples(3000)
                .tolerance(tolerance)
                .iterations(200)
                .seed(7)
                .threads(1)
                .run()
                .unwrap();
            assert_eq!(per_point.stop, StopReason::ToleranceMet, "{domain:?}");
            assert!(per_point.iterations >= 3, "{}", per_point.iterations);
            for threads in [1, 3] {
                let batch = Vegas::new_batch(2, two_outputs_batch, domain.clone())
                    .stratified(stratified)
                    .samples(3000)
                    .tolerance(tolerance)
                    .iterations(200)
                    .seed(7)
                    .threads(threads)
                    .run()
                    .unwrap();
                assert_eq!(batch, per_point, "{domain:?}, stratified {stratified}");
            }
        }
    }
}

#[test]
fn vegas_by_blocks_reports_unwritten_outputs_as_non_finite() {
    use mcint::adaptive::Vegas;
    // Writes output 0 only: output 1 stays NaN, which the run names.
    let half = |p: &Points, out: &mut [f64]| {
        let n = p.len();
        out[..n].copy_from_slice(p.column(0));
    };
    let err = Vegas::new_batch(2, half, UniformBox::unit(2).unwrap())
        .run()
        .unwrap_err();
    assert!(matches!(err, Error::NonFiniteContribution { .. }), "{err}");
    assert!(err.to_string().contains("output 1"), "{err}");
}

#[test]
fn larger_calls_change_no_bit_of_a_vector_run() {
    use mcint::estimator::BatchVectorUniformEstimator;
    use mcint::stats::Tolerance;
    let domain = || UniformBox::unit(3).unwrap();
    let run = |per_call: Option<usize>, threads| {
        let mut e = BatchVectorUniformEstimator::new(2, two_outputs_batch, domain());
        if let Some(points) = per_call {
            e = e.with_points_per_call(points).unwrap();
        }
        Integrator::new_vector(e)
            .sampler(Sobol::new(3, Scramble::Owen, 3).unwrap())
            .tolerance(Tolerance::relative(1e-6).unwrap())
            .seed(3)
            .threads(threads)
            .run()
            .unwrap()
    };
    let reference = run(None, 1);
    assert!(reference.covariance_matrix.is_some());
    // 5000 is not a whole number of summation blocks: calls of 4096 points (1: of 1024).
    for per_call in [Some(5000), Some(1 << 14), Some(1)] {
        for threads in [1, 3] {
            assert_eq!(
                run(per_call, threads),
                reference,
                "{per_call:?} x {threads}"
            );
        }
    }
}

#[test]
fn larger_calls_report_the_same_non_finite_point() {
    use mcint::estimator::BatchUniformEstimator;
    // NaN wherever x0 is in a thin slab: the first such point is the same for any call size.
    let slab = |p: &Points, out: &mut [f64]| {
        for (y, &x) in out.iter_mut().zip(p.column(0)) {
            *y = if (0.3..0.3001).contains(&x) {
                f64::NAN
            } else {
                x
            };
        }
    };
    let error = |per_call: usize| {
        let e = BatchUniformEstimator::new(slab, UniformBox::unit(2).unwrap())
            .with_points_per_call(per_call)
            .unwrap();
        Integrator::new(e)
            .samples(50_000)
            .seed(1)
            .run()
            .unwrap_err()
            .to_string()
    };
    let reference = error(1024);
    assert!(reference.contains("non-finite"), "{reference}");
    assert_eq!(error(8192), reference);
}
