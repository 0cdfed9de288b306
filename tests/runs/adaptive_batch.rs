//! MISER and two-stage sampling over an integrand evaluated by blocks (`ScalarBatch`): the
//! bits of the per-point integrand on any thread count and sampler, blocks of at most 4,096
//! points that gather many small regions or strata, and non-finite values reported as for
//! a per-point integrand.

use super::batch_integrand::{boxes, f, f_batch};
use mcint::adaptive::{Miser, TwoStage};
use mcint::pdf::UniformBox;
use mcint::sampler::{Independent, Scramble, Sobol};
use mcint::stats::Tolerance;
use mcint::{Error, Points};
use std::sync::Mutex;

/// Builds a fresh sampler (a sampler is moved into the runner).
type MakeSampler = fn(usize) -> Box<dyn mcint::Sampler>;

fn samplers() -> [MakeSampler; 2] {
    [
        |d| Box::new(Independent::new(d, 11).unwrap()),
        |d| Box::new(Sobol::new(d, Scramble::Owen, 11).unwrap()),
    ]
}

#[test]
fn miser_by_blocks_has_the_bits_of_miser_by_points() {
    for domain in boxes(3) {
        for make in samplers() {
            let per_point = Miser::new(f, domain.clone())
                .sampler(make(3))
                .samples(20_000)
                .replicates(4)
                .threads(1)
                .run()
                .unwrap();
            for threads in [1, 3] {
                let by_blocks = Miser::new_batch(f_batch, domain.clone())
                    .sampler(make(3))
                    .samples(20_000)
                    .replicates(4)
                    .threads(threads)
                    .run()
                    .unwrap();
                assert_eq!(by_blocks, per_point, "{domain:?}, {threads} threads");
            }
        }
    }
}

#[test]
fn miser_by_blocks_to_a_tolerance_has_the_bits_of_miser_by_points() {
    let domain = UniformBox::unit(2).unwrap();
    let tolerance = Tolerance::relative(1e-3).unwrap();
    let per_point = Miser::new(f, domain.clone())
        .samples(2_000)
        .tolerance(tolerance)
        .seed(5)
        .run()
        .unwrap();
    let by_blocks = Miser::new_batch(f_batch, domain)
        .samples(2_000)
        .tolerance(tolerance)
        .seed(5)
        .run()
        .unwrap();
    assert!(per_point.iterations > 1, "{per_point:?}");
    assert_eq!(by_blocks, per_point);
}

#[test]
fn two_stage_by_blocks_has_the_bits_of_two_stage_by_points() {
    // Many small strata (gathered into shared blocks), and one large stratum (sampled in
    // pieces across chunks).
    for (strata_per_axis, samples) in [(6, 40_000), (1, 300_000)] {
        for domain in boxes(3) {
            for make in samplers() {
                let per_point = TwoStage::new(f, domain.clone(), strata_per_axis)
                    .sampler(make(3))
                    .samples(samples)
                    .threads(1)
                    .run()
                    .unwrap();
                for threads in [1, 3] {
                    let by_blocks = TwoStage::new_batch(f_batch, domain.clone(), strata_per_axis)
                        .sampler(make(3))
                        .samples(samples)
                        .threads(threads)
                        .run()
                        .unwrap();
                    assert_eq!(by_blocks, per_point, "{strata_per_axis}, {threads} threads");
                }
            }
        }
    }
}

/// The sizes of the blocks an integrand was called with, and the integrand that records them.
fn recording(sizes: &Mutex<Vec<usize>>) -> impl Fn(&Points, &mut [f64]) + Sync + '_ {
    move |p: &Points, out: &mut [f64]| {
        sizes.lock().unwrap().push(p.len());
        f_batch(p, out);
    }
}

#[test]
fn miser_calls_hold_whole_regions_of_at_most_4096_points() {
    let sizes = Mutex::new(Vec::new());
    let dims = 3;
    let run = Miser::new_batch(recording(&sizes), UniformBox::unit(dims).unwrap())
        .samples(100_000)
        .replicates(2)
        .threads(1)
        .run()
        .unwrap();
    let sizes = sizes.into_inner().unwrap();
    assert_eq!(sizes.iter().sum::<usize>() as u64, run.evaluations);
    assert!(sizes.iter().all(|&n| n <= 4096), "{sizes:?}");
    // Every exploration and leaf has at least min_points = 16 d points and takes
    // ceil(n / 4096) <= n / 48 calls: at most one call per 48 evaluations (per point, one
    // call per evaluation).
    let most = run.evaluations / (16 * dims as u64);
    assert!(
        sizes.len() as u64 <= most,
        "{} calls, at most {most}",
        sizes.len()
    );
}

#[test]
fn two_stage_calls_gather_many_strata() {
    let sizes = Mutex::new(Vec::new());
    let (per_axis, dims, samples) = (16, 3, 200_000u64);
    let run = TwoStage::new_batch(recording(&sizes), UniformBox::unit(dims).unwrap(), per_axis)
        .samples(samples)
        .threads(1)
        .run()
        .unwrap();
    let sizes = sizes.into_inner().unwrap();
    assert_eq!(sizes.iter().sum::<usize>() as u64, run.evaluations);
    assert!(sizes.iter().all(|&n| n <= 4096), "{sizes:?}");
    // 4,096 strata of about 49 points: per stratum that would be 8,192 calls. Gathered, a
    // chunk (at most 65,536 evaluations) needs at most one partial block: two stages of at most
    // four chunks each.
    assert!(
        sizes.len() as u64 <= samples / 4096 + 8,
        "{} calls",
        sizes.len()
    );
}

#[test]
fn values_left_unwritten_are_reported_where_the_per_point_integrand_fails() {
    // Per point: NaN beyond x0 = 0.7. By blocks: those values are left unwritten.
    let nan_beyond = |x: &[f64]| if x[0] > 0.7 { f64::NAN } else { x[0] };
    let unwritten_beyond = |p: &Points, out: &mut [f64]| {
        for (y, &x0) in out.iter_mut().zip(p.column(0)) {
            if x0 <= 0.7 {
                *y = x0;
            }
        }
    };
    let domain = UniformBox::unit(2).unwrap();
    let point_error = |e: Error| match e {
        Error::NonFiniteContribution {
            count,
            first_index,
            first_replicate,
            first_point,
            ..
        } => (count, first_index, first_replicate, first_point),
        other => panic!("{other}"),
    };
    let per_point = Miser::new(nan_beyond, domain.clone()).seed(2).run();
    let by_blocks = Miser::new_batch(unwritten_beyond, domain.clone())
        .seed(2)
        .run();
    let expected = point_error(per_point.unwrap_err());
    assert!(expected.3[0] > 0.7);
    assert_eq!(point_error(by_blocks.unwrap_err()), expected);
    let per_point = TwoStage::new(nan_beyond, domain.clone(), 8).seed(2).run();
    let by_blocks = TwoStage::new_batch(unwritten_beyond, domain, 8)
        .seed(2)
        .run();
    let expected = point_error(per_point.unwrap_err());
    assert!(expected.3[0] > 0.7);
    assert_eq!(point_error(by_blocks.unwrap_err()), expected);
}
