//! Integrand evaluations per second, one thread unless said, at a fixed budget of about 2^20
//! evaluations.
//!
//! `cargo bench --bench integrate` (10 samples of 2 s per bench; criterion's
//! `--measurement-time` and `--warm-up-time` change that).
//!
//! Groups:
//! - `genz_{family}_5d`: the six Genz families (d = 5, customary parameters) for each method:
//!   the plain [`Integrator`] with independent points, randomized QMC (Owen-scrambled Sobol',
//!   16 replicates of 2^16), VEGAS+ (stratified VEGAS, 3 warm-up and 5 measured iterations of
//!   2^17), and MISER (independent points). The throughput counts the evaluations each
//!   method actually made (counted once before timing), so the rows compare the overhead of
//!   the methods around the same integrand.
//! - `integrand_form_gaussian_5d`: the same integral with a per-point closure and with a batch
//!   integrand ([`Integrator::over_box_batch`]), over the unit cube (canonical blocks passed
//!   unmapped) and over a non-unit box (blocks mapped into a per-thread scratch block), and a
//!   batch estimator that allocates its mapped block per call, for comparison.
//! - `fused_vs_buffer_gaussian_5d`: the Integrator's fused path (blocks of 1024 points
//!   generated and evaluated while in cache) against generating all 2^20 points into one
//!   buffer (40 MiB, allocated once outside the timing) and then evaluating them; the same
//!   fusion by hand with a plain sum separates the cost of the memory round trip from the
//!   Integrator's accumulator (two passes per block of 1024 values, merged by Chan's formula).
//! - `threads_gaussian_5d_2e24`: 2^24-point plain and RQMC runs on one and two threads.

use criterion::{Criterion, SamplingMode, Throughput, criterion_group, criterion_main};
use mcint::adaptive::{Miser, Vegas};
use mcint::estimator::{BatchUniformEstimator, Estimator};
use mcint::pdf::UniformBox;
use mcint::sampler::{Independent, Sampler, Scramble, Sobol};
use mcint::testfns::{Genz, GenzFamily, TestFunction};
use mcint::{Accumulator, Integrator, Points};
use std::hint::black_box;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

const DIMS: usize = 5;
/// Evaluations per run.
const BUDGET: u64 = 1 << 20;

fn unit() -> UniformBox {
    UniformBox::unit(DIMS).unwrap()
}

/// One run of each method on `f`, returning the estimate.
type Method = fn(&(dyn Fn(&[f64]) -> f64 + Sync)) -> f64;

fn methods() -> [(&'static str, Method); 4] {
    [
        ("independent", |f| {
            Integrator::over_box(f, unit())
                .samples(BUDGET)
                .seed(1)
                .threads(1)
                .run()
                .unwrap()
                .mean
        }),
        ("rqmc_sobol_owen_16", |f| {
            Integrator::over_box(f, unit())
                .sampler(Sobol::new(DIMS, Scramble::Owen, 0).unwrap())
                .samples(BUDGET / 16)
                .replicates(16)
                .seed(1)
                .threads(1)
                .run()
                .unwrap()
                .mean
        }),
        ("vegas_plus", |f| {
            Vegas::new(f, unit())
                .stratified(true)
                .samples(BUDGET / 8)
                .warmup(3)
                .iterations(5)
                .seed(1)
                .threads(1)
                .run()
                .unwrap()
                .mean
        }),
        ("miser", |f| {
            Miser::new(f, unit())
                .samples(BUDGET / 16)
                .seed(1)
                .threads(1)
                .run()
                .unwrap()
                .mean
        }),
    ]
}

fn genz_methods(c: &mut Criterion) {
    for family in GenzFamily::ALL {
        let genz = Genz::with_defaults(family, DIMS).unwrap();
        let f = |x: &[f64]| genz.eval(x);
        let mut group = c.benchmark_group(format!("genz_{family}_5d"));
        group.sampling_mode(SamplingMode::Flat);
        for (name, method) in methods() {
            let count = AtomicU64::new(0);
            let counted = |x: &[f64]| {
                count.fetch_add(1, Ordering::Relaxed);
                f(x)
            };
            method(&counted);
            group.throughput(Throughput::Elements(count.load(Ordering::Relaxed)));
            group.bench_function(name, |b| b.iter(|| black_box(method(&f))));
        }
        group.finish();
    }
}

/// The Gaussian Genz integrand over a block: [`TestFunction::eval_batch`], a column at a time
/// with a vectorized `exp` (within an ulp of the per-point values).
fn gaussian_batch(genz: &Genz) -> impl Fn(&Points, &mut [f64]) + Sync + '_ {
    move |p: &Points, out: &mut [f64]| genz.eval_batch(p, out)
}

/// A batch estimator that maps every block into a freshly allocated block: what
/// [`BatchUniformEstimator`]'s per-thread scratch avoids.
struct AllocatingBatch<F> {
    f: F,
    domain: UniformBox,
}

impl<F: Fn(&Points, &mut [f64]) + Send + Sync> Estimator for AllocatingBatch<F> {
    fn canonical_dims(&self) -> usize {
        DIMS
    }

    fn domain_dims(&self) -> usize {
        DIMS
    }

    fn contribution(&self, _: &[f64], _: &mut [f64]) -> f64 {
        unreachable!("the Integrator calls contributions")
    }

    fn contributions(&self, points: &Points, out: &mut [f64]) {
        let mut x = Points::new(DIMS, points.len()).unwrap();
        for (d, column) in x.columns_mut().enumerate() {
            let (lo, hi) = (self.domain.lo()[d], self.domain.hi()[d]);
            for (x, &u) in column.iter_mut().zip(points.column(d)) {
                let v = lo + u * (hi - lo);
                *x = if v < hi { v } else { hi.next_down() };
            }
        }
        (self.f)(&x, out);
        for y in out.iter_mut() {
            *y *= self.domain.volume();
        }
    }
}

fn integrand_form(c: &mut Criterion) {
    let genz = Genz::with_defaults(GenzFamily::Gaussian, DIMS).unwrap();
    let f = |x: &[f64]| genz.eval(x);
    let batch = gaussian_batch(&genz);
    let shifted = UniformBox::new(vec![0.5; DIMS], vec![1.5; DIMS]).unwrap();
    let run = |e: &dyn Estimator| {
        Integrator::new(e)
            .samples(BUDGET)
            .seed(1)
            .threads(1)
            .run()
            .unwrap()
            .mean
    };
    let per_point = Integrator::over_box(f, unit())
        .samples(BUDGET)
        .seed(1)
        .threads(1);
    let batched = Integrator::over_box_batch(&batch, unit())
        .samples(BUDGET)
        .seed(1)
        .threads(1);
    // Same arithmetic per point: the same bits.
    assert_eq!(per_point.run().unwrap(), batched.run().unwrap());

    let mut group = c.benchmark_group("integrand_form_gaussian_5d");
    group.sampling_mode(SamplingMode::Flat);
    group.throughput(Throughput::Elements(BUDGET));
    group.bench_function("per_point_closure_unit", |b| {
        b.iter(|| black_box(per_point.run().unwrap().mean))
    });
    group.bench_function("batch_integrand_unit", |b| {
        b.iter(|| black_box(batched.run().unwrap().mean))
    });
    let per_point_box = mcint::estimator::UniformEstimator::new(f, shifted.clone());
    group.bench_function("per_point_closure_box", |b| {
        b.iter(|| black_box(run(&per_point_box)))
    });
    let batch_box = BatchUniformEstimator::new(&batch, shifted.clone());
    group.bench_function("batch_integrand_box_scratch", |b| {
        b.iter(|| black_box(run(&batch_box)))
    });
    let allocating = AllocatingBatch {
        f: &batch,
        domain: shifted,
    };
    group.bench_function("batch_integrand_box_alloc_per_block", |b| {
        b.iter(|| black_box(run(&allocating)))
    });
    group.finish();
}

fn fused_vs_buffer(c: &mut Criterion) {
    let genz = Genz::with_defaults(GenzFamily::Gaussian, DIMS).unwrap();
    let f = |x: &[f64]| genz.eval(x);
    let batch = gaussian_batch(&genz);
    let sampler = Independent::new(DIMS, 1).unwrap();
    let mut group = c.benchmark_group("fused_vs_buffer_gaussian_5d");
    group.sampling_mode(SamplingMode::Flat);
    group.throughput(Throughput::Elements(BUDGET));

    let fused = Integrator::over_box(f, unit())
        .sampler(sampler.clone())
        .samples(BUDGET)
        .threads(1);
    group.bench_function("fused_integrator_per_point", |b| {
        b.iter(|| black_box(fused.run().unwrap().mean))
    });
    let fused_batch = Integrator::over_box_batch(&batch, unit())
        .sampler(sampler.clone())
        .samples(BUDGET)
        .threads(1);
    group.bench_function("fused_integrator_batch", |b| {
        b.iter(|| black_box(fused_batch.run().unwrap().mean))
    });

    // The same fusion by hand, with a plain sum instead of the Integrator's accumulator
    // (two passes per block and a merge): the cost of fusion alone.
    let mut block = Points::new(DIMS, 1024).unwrap();
    let mut block_values = vec![0.0; 1024];
    group.bench_function("fused_blocks_then_sum_per_point", |b| {
        b.iter(|| {
            let (mut x, mut sum) = ([0.0; DIMS], 0.0);
            for start in (0..BUDGET).step_by(1024) {
                sampler.fill(start, &mut block).unwrap();
                for i in 0..block.len() {
                    block.copy_point(i, &mut x);
                    sum += f(&x);
                }
            }
            black_box(sum / BUDGET as f64)
        })
    });
    group.bench_function("fused_blocks_then_sum_batch", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for start in (0..BUDGET).step_by(1024) {
                sampler.fill(start, &mut block).unwrap();
                batch(&block, &mut block_values);
                sum += block_values.iter().sum::<f64>();
            }
            black_box(sum / BUDGET as f64)
        })
    });

    // The whole buffer first, then the evaluation: the points make a round trip through
    // main memory (40 MiB, beyond the caches).
    let mut buffer = Points::new(DIMS, BUDGET as usize).unwrap();
    group.bench_function("buffer_then_sum_per_point", |b| {
        b.iter(|| {
            sampler.fill(0, &mut buffer).unwrap();
            let mut x = [0.0; DIMS];
            let mut sum = 0.0;
            for i in 0..buffer.len() {
                buffer.copy_point(i, &mut x);
                sum += f(&x);
            }
            black_box(sum / BUDGET as f64)
        })
    });
    let mut values = vec![0.0; BUDGET as usize];
    group.bench_function("buffer_then_sum_batch", |b| {
        b.iter(|| {
            sampler.fill(0, &mut buffer).unwrap();
            batch(&buffer, &mut values);
            black_box(values.iter().sum::<f64>() / BUDGET as f64)
        })
    });
    // With the Integrator's accumulator, to compare with the fused Integrator row.
    group.bench_function("buffer_then_accumulator_batch", |b| {
        b.iter(|| {
            sampler.fill(0, &mut buffer).unwrap();
            batch(&buffer, &mut values);
            let mut acc = Accumulator::new();
            acc.extend(&values);
            black_box(acc.mean())
        })
    });
    group.finish();
}

/// A 2^24-point plain run (independent points) and RQMC run (16 Owen-scrambled Sobol'
/// replicates of 2^20) of the 5-D Genz Gaussian batch integrand on one and on two threads:
/// the speed-up of the executor (the results have the same bits on any thread count).
fn thread_scaling(c: &mut Criterion) {
    const POINTS: u64 = 1 << 24;
    let genz = Genz::with_defaults(GenzFamily::Gaussian, DIMS).unwrap();
    let batch = gaussian_batch(&genz);
    let mut group = c.benchmark_group("threads_gaussian_5d_2e24");
    group.sampling_mode(SamplingMode::Flat);
    group.throughput(Throughput::Elements(POINTS));
    for threads in [1, 2] {
        let plain = Integrator::over_box_batch(&batch, unit())
            .samples(POINTS)
            .seed(1)
            .threads(threads);
        group.bench_function(format!("plain_{threads}_threads"), |b| {
            b.iter(|| black_box(plain.run().unwrap().mean))
        });
        let rqmc = Integrator::over_box_batch(&batch, unit())
            .sampler(Sobol::new(DIMS, Scramble::Owen, 0).unwrap())
            .samples(POINTS / 16)
            .replicates(16)
            .seed(1)
            .threads(threads);
        group.bench_function(format!("rqmc_{threads}_threads"), |b| {
            b.iter(|| black_box(rqmc.run().unwrap().mean))
        });
    }
    group.finish();
}

/// Short runs: 10 samples, 2 s of measurement after 1 s of warm-up per bench.
fn short() -> Criterion {
    Criterion::default()
        .sample_size(10)
        .measurement_time(Duration::from_secs(2))
        .warm_up_time(Duration::from_secs(1))
}

criterion_group! {
    name = benches;
    config = short();
    targets = genz_methods, integrand_form, fused_vs_buffer, thread_scaling
}
criterion_main!(benches);
