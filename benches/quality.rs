//! Speed of the point-set measures whose tests used to time themselves: the t-value of 2^16
//! points in 2-D and the mean periodogram of the spectrum figures, each against a baseline in
//! the same run.
//!
//! `cargo bench --bench quality`. Groups:
//! - `t_value_2d_2^16`: an Owen-scrambled Sobol' (0, 16, 2)-net against independent points
//!   (whose t is found at the first level it tries), and against the cost of making the
//!   points (`fill_baseline`).
//! - `mean_periodogram_1024_K64_16_passes`: independent points on one and two threads; the
//!   ratio is the parallel speed-up.

use criterion::{Criterion, criterion_group, criterion_main};
use mcint::Points;
use mcint::quality::{mean_periodogram_with_threads, t_value};
use mcint::sampler::{Independent, Sampler, Scramble, Sobol};
use std::hint::black_box;
use std::time::Duration;

const POINTS: usize = 1 << 16;

fn filled(sampler: &dyn Sampler) -> Points {
    let mut points = Points::new(2, POINTS).expect("a 2-D block");
    sampler.fill(0, &mut points).expect("a valid fill");
    points
}

fn t_value_benches(c: &mut Criterion) {
    let mut group = c.benchmark_group("t_value_2d_2^16");
    let sobol = Sobol::new(2, Scramble::Owen, 1).expect("a 2-D Sobol' sampler");
    let independent = Independent::new(2, 1).expect("a 2-D independent sampler");
    group.bench_function("fill_baseline", |b| b.iter(|| black_box(filled(&sobol))));
    let net = filled(&sobol);
    group.bench_function("sobol_owen", |b| {
        b.iter(|| black_box(t_value(&net).expect("a t-value")))
    });
    let random = filled(&independent);
    group.bench_function("independent", |b| {
        b.iter(|| black_box(t_value(&random).expect("a t-value")))
    });
    group.finish();
}

fn periodogram_benches(c: &mut Criterion) {
    let mut group = c.benchmark_group("mean_periodogram_1024_K64_16_passes");
    let sampler = Independent::new(2, 1).expect("a 2-D independent sampler");
    for threads in [1, 2] {
        group.bench_function(format!("{threads}_threads"), |b| {
            b.iter(|| {
                black_box(
                    mean_periodogram_with_threads(&sampler, 1024, 16, 64, threads)
                        .expect("a periodogram"),
                )
            })
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
    targets = t_value_benches, periodogram_benches
}
criterion_main!(benches);
