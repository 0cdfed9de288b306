//! Sampler throughput, in values (coordinates) per second, for every named sampler against
//! `Independent` and a plain `rand_pcg` fill, measured in the same run.
//!
//! `cargo bench --bench samplers`

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use mcint::Integrator;
use mcint::Points;
use mcint::pdf::UniformBox;
use mcint::sampler::SamplerKind;
use rand::Rng;
use rand_pcg::Pcg64;
use std::hint::black_box;

const DIMS: usize = 4;
/// Points per block: 4096 x 4 doubles = 128 KiB, an L2-sized block.
const POINTS: usize = 4096;

fn fill_benches(c: &mut Criterion) {
    let mut group = c.benchmark_group("fill_4d_4096");
    group.throughput(Throughput::Elements((DIMS * POINTS) as u64));
    let mut block = Points::new(DIMS, POINTS).unwrap();

    // Baseline: the raw PCG-64 stream converted to doubles, written column-major.
    let mut rng = Pcg64::new(0xcafe_f00d_d15e_a5e5, 0x0a02_bdbf_7bb3_c0a7);
    group.bench_function("rand_pcg_baseline", |b| {
        b.iter(|| {
            for column in block.columns_mut() {
                for x in column.iter_mut() {
                    *x = (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
                }
            }
            black_box(block.get(0, 0))
        })
    });

    // Every named sampler, one pass (or 4096 points) per iteration. Orthogonal arrays need a
    // prime power, so they fill 61^2 (Bose) and 13^3 (Bush) points; the blue-noise sets are
    // built per pass (best candidate in O(N^2)), so they use 1024 points, and Poisson disk
    // supports at most 3 dimensions.
    for kind in SamplerKind::ALL {
        let (dims, points) = match kind {
            SamplerKind::OaBose => (DIMS, 61 * 61),
            SamplerKind::OaBush => (DIMS, 13 * 13 * 13),
            SamplerKind::Poisson => (3, 1024),
            SamplerKind::BestCandidate => (DIMS, 1024),
            _ => (DIMS, POINTS as u64),
        };
        let sampler = kind.build(dims, points, 1).unwrap();
        let mut block = Points::new(dims, points as usize).unwrap();
        group.throughput(Throughput::Elements(dims as u64 * points));
        let mut start = 0u64;
        group.bench_function(kind.name(), |b| {
            b.iter(|| {
                sampler.fill(start, &mut block).unwrap();
                start += points;
                black_box(block.get(0, 0))
            })
        });
    }
    group.finish();
}

fn integrate_benches(c: &mut Criterion) {
    let mut group = c.benchmark_group("integrate_4d_2^16");
    group.throughput(Throughput::Elements(1 << 16));
    let f = |x: &[f64]| (-(x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + x[3] * x[3])).exp();
    // Hand-written loop over the same PCG stream: the cost floor of plain Monte Carlo.
    group.bench_function("hand_loop_baseline", |b| {
        let mut rng = Pcg64::new(1, 3);
        b.iter(|| {
            let mut sum = 0.0;
            let mut x = [0.0; DIMS];
            for _ in 0..1 << 16 {
                for v in x.iter_mut() {
                    *v = (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
                }
                sum += f(&x);
            }
            black_box(sum)
        })
    });
    group.bench_function("integrator_independent_1_thread", |b| {
        let integrator = Integrator::over_box(f, UniformBox::unit(DIMS).unwrap())
            .samples(1 << 16)
            .threads(1);
        b.iter(|| black_box(integrator.run().unwrap().mean))
    });
    group.finish();
}

criterion_group!(benches, fill_benches, integrate_benches);
criterion_main!(benches);
