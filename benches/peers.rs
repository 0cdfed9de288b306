//! The same work done by `mcint` and by peer crates, in one run: Owen-scrambled Sobol' points
//! against `sobol_burley` 0.5 (`sample` and `sample_4d`, which return f32; converting to f64
//! is part of the work), in 4 dimensions and, summing the values, in 256 and 1024
//! (`owen_sobol_highd`), and independent uniforms against a raw `rand_pcg` fill.
//!
//! `cargo bench --bench peers`; throughput is in values (coordinates) per second.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use mcint::Points;
use mcint::sampler::{Independent, Sampler, Scramble, Sobol, simd};
use rand::Rng;
use rand_pcg::Pcg64;
use std::hint::black_box;

const DIMS: usize = 4;
/// 4096 points x 4 dimensions of f64 = 128 KiB: an in-cache block.
const POINTS: usize = 4096;

fn owen_sobol(c: &mut Criterion) {
    let mut group = c.benchmark_group("owen_sobol_4d_4096");
    group.throughput(Throughput::Elements((DIMS * POINTS) as u64));
    let mut block = Points::new(DIMS, POINTS).unwrap();

    let sobol = Sobol::new(DIMS, Scramble::Owen, 7).unwrap();
    group.bench_function("mcint_fill", |b| {
        let mut start = 0u64;
        b.iter(|| {
            sobol.fill(start, &mut block).unwrap();
            start = (start + POINTS as u64) % (1 << 32);
            black_box(block.get(0, 0))
        })
    });

    // sobol_burley always shuffles the index (Burley 2020); this is the like-for-like variant.
    let shuffled = Sobol::new(DIMS, Scramble::Owen, 7)
        .unwrap()
        .with_index_shuffle(true);
    group.bench_function("mcint_fill_index_shuffle", |b| {
        let mut start = 0u64;
        b.iter(|| {
            shuffled.fill(start, &mut block).unwrap();
            start = (start + POINTS as u64) % (1 << 32);
            black_box(block.get(0, 0))
        })
    });

    // The same fill with the vector kernels turned off (the baseline build's code).
    group.bench_function("mcint_fill_portable", |b| {
        let mut start = 0u64;
        simd::force_portable(true);
        b.iter(|| {
            sobol.fill(start, &mut block).unwrap();
            start = (start + POINTS as u64) % (1 << 32);
            black_box(block.get(0, 0))
        });
        simd::force_portable(false);
    });

    group.bench_function("sobol_burley_sample_4d", |b| {
        let mut start = 0u32;
        b.iter(|| {
            let mut columns: Vec<&mut [f64]> = block.columns_mut().collect();
            for i in 0..POINTS {
                let p = sobol_burley::sample_4d(start.wrapping_add(i as u32), 0, 7);
                for (column, v) in columns.iter_mut().zip(p) {
                    column[i] = f64::from(v);
                }
            }
            start = start.wrapping_add(POINTS as u32);
            black_box(block.get(0, 0))
        })
    });

    group.bench_function("sobol_burley_sample", |b| {
        let mut start = 0u32;
        b.iter(|| {
            for (dim, column) in block.columns_mut().enumerate() {
                for (i, x) in column.iter_mut().enumerate() {
                    *x = f64::from(sobol_burley::sample(
                        start.wrapping_add(i as u32),
                        dim as u32,
                        7,
                    ));
                }
            }
            start = start.wrapping_add(POINTS as u32);
            black_box(block.get(0, 0))
        })
    });
    group.finish();
}

/// Values per block in high dimensions: 2 MiB of f64, which stays in L2 between the fill and
/// the sums (the block `points --format sum` uses).
const HIGHD_VALUES: usize = 1 << 18;

/// Owen-scrambled Sobol' in 256 and 1024 dimensions, the values summed per dimension as
/// `points --format sum` does, against `sobol_burley`'s `sample_4d` producing and summing the
/// same number of values. sobol_burley has 256 dimensions; beyond them it takes a new seed for
/// each further 256 (the padding its documentation suggests). Its index is below 2^16.
fn owen_sobol_highd(c: &mut Criterion) {
    for dims in [256, 1024] {
        let points = HIGHD_VALUES / dims;
        let mut group = c.benchmark_group(format!("owen_sobol_highd_{dims}d_{points}"));
        group.throughput(Throughput::Elements((dims * points) as u64));
        let mut block = Points::new(dims, points).unwrap();
        let sobol = Sobol::new(dims, Scramble::Owen, 7).unwrap();
        let mut sums = vec![0.0f64; dims];

        group.bench_function("mcint_fill", |b| {
            let mut start = 0u64;
            b.iter(|| {
                sobol.fill(start, &mut block).unwrap();
                start = (start + points as u64) % (1 << 16);
                black_box(block.get(0, 0))
            })
        });

        group.bench_function("mcint_fill_sum", |b| {
            let mut start = 0u64;
            b.iter(|| {
                sobol.fill(start, &mut block).unwrap();
                add_columns(&mut sums, &block);
                start = (start + points as u64) % (1 << 16);
                black_box(sums[0])
            })
        });

        group.bench_function("sobol_burley_sample_4d_sum", |b| {
            let mut start = 0u32;
            b.iter(|| {
                for i in 0..points as u32 {
                    let index = (start + i) % (1 << 16);
                    for (seed, sums) in (7..).zip(sums.chunks_mut(256)) {
                        for (set, sums) in (0..).zip(sums.as_chunks_mut::<4>().0) {
                            let p = sobol_burley::sample_4d(index, set, seed);
                            for (sum, v) in sums.iter_mut().zip(p) {
                                *sum += f64::from(v);
                            }
                        }
                    }
                }
                start = (start + points as u32) % (1 << 16);
                black_box(sums[0])
            })
        });
        group.finish();
    }
}

/// Adds each column of `block` to its sum in index order, eight columns side by side (eight
/// independent chains of additions), as `points --format sum` does.
fn add_columns(sums: &mut [f64], block: &Points) {
    let len = block.len();
    for (group, sums) in sums.as_chunks_mut::<8>().0.iter_mut().enumerate() {
        let columns: [&[f64]; 8] = std::array::from_fn(|k| &block.column(8 * group + k)[..len]);
        for i in 0..len {
            for (sum, column) in sums.iter_mut().zip(&columns) {
                *sum += column[i];
            }
        }
    }
}

/// Sobol' fills under the other scrambles, which need no per-value hashing.
fn sobol_scrambles(c: &mut Criterion) {
    let mut group = c.benchmark_group("sobol_4d_4096");
    group.throughput(Throughput::Elements((DIMS * POINTS) as u64));
    let mut block = Points::new(DIMS, POINTS).unwrap();
    for (name, scramble) in [
        ("none", Scramble::None),
        ("xor", Scramble::Xor),
        ("lms", Scramble::Lms),
    ] {
        let sobol = Sobol::new(DIMS, scramble, 7).unwrap();
        group.bench_function(format!("mcint_fill_{name}"), |b| {
            let mut start = 0u64;
            b.iter(|| {
                sobol.fill(start, &mut block).unwrap();
                start = (start + POINTS as u64) % (1 << 32);
                black_box(block.get(0, 0))
            })
        });
    }
    group.finish();
}

fn independent(c: &mut Criterion) {
    // Both shapes are 128 KiB blocks: 4096 points in 4-D and 512 points in 32-D.
    for (dims, points) in [(DIMS, POINTS), (32, 512)] {
        let mut group = c.benchmark_group(format!("independent_{dims}d_{points}"));
        group.throughput(Throughput::Elements((dims * points) as u64));
        let mut block = Points::new(dims, points).unwrap();
        let sampler = Independent::new(dims, 1).unwrap();
        group.bench_function("mcint_fill", |b| {
            let mut start = 0u64;
            b.iter(|| {
                sampler.fill(start, &mut block).unwrap();
                start += points as u64;
                black_box(block.get(0, 0))
            })
        });
        let mut rng = Pcg64::new(0xcafe_f00d_d15e_a5e5, 0x0a02_bdbf_7bb3_c0a7);
        group.bench_function("rand_pcg_raw", |b| {
            b.iter(|| {
                for column in block.columns_mut() {
                    for x in column.iter_mut() {
                        *x = (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
                    }
                }
                black_box(block.get(0, 0))
            })
        });
        group.finish();
    }
}

criterion_group!(
    benches,
    owen_sobol,
    owen_sobol_highd,
    sobol_scrambles,
    independent
);
criterion_main!(benches);
