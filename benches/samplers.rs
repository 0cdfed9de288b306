//! Sampler throughput, in values (coordinates) per second, for every named sampler against
//! `Independent` and a plain `rand_pcg` fill, measured in the same run.
//!
//! `cargo bench --bench samplers` (about 10 samples of 2 s per bench; pass criterion's
//! `--measurement-time` and `--warm-up-time` to change that).
//!
//! Groups:
//! - `fill_4d_4096`: one pass (or 4096 points) per fill, as a sampler is used per pass.
//! - `fill_{4,32}d_2^20_blocks`: 2^20 points in fills of 4096 points into one reused block
//!   (128 KiB at d = 4, 1 MiB at d = 32: the in-cache path the Integrator uses).
//! - `fill_{4,32}d_2^20_whole`: the same 2^20 points in one fill of a whole buffer (32 MiB at
//!   d = 4, 256 MiB at d = 32: bound by memory writes).
//! - `integrate_4d_2^16`: the Integrator against a hand-written loop.
//! - `owen_halton_vs_sobol`: Owen-scrambled Halton against Owen-scrambled Sobol', per value,
//!   in blocks of 4096 points at d = 10 and d = 30: the first 2^16 points of one pass after
//!   another, as replicates of an RQMC run use them.
//! - `owen_halton_block_vs_point`: what Owen-scrambled Halton's block kernel
//!   (`radical_inverse/owen_block.rs`, behind `fill`) buys over the one-coordinate path
//!   (`radical_inverse/owen.rs`, behind `point`), per value, on the first 2^16 points of a fresh
//!   pass at d = 4 and d = 32: one `fill` of all of them against `point` for each of them.
//!
//! The 2^20-point groups fill the first 2^20 points of a fresh pass per iteration (so samplers
//! that build tables per pass pay for them), of a pass size of at least 2^20: 2^20 itself where
//! the sampler allows it, otherwise the nearest valid size above (see [`pass_for`]). Two kinds
//! of sampler are measured on fewer points, and their rows say so:
//! - the blue-noise samplers build a whole pass at once (best candidate in O(N^2), Poisson
//!   disk in at most 3 dimensions): one pass of 1024 points, in 4 (best candidate) and 3
//!   (Poisson) dimensions;
//! - at d = 32, the samplers that fill about ten million values per second (multi-jittered,
//!   orthogonal arrays, multi-stage N-rooks: a 40-round hashed permutation per value), and
//!   CMJ, fill 2^16 points of their 2^20-point pass, so that ten samples take seconds rather
//!   than minutes.

use criterion::{Criterion, SamplingMode, Throughput, criterion_group, criterion_main};
use mcint::Integrator;
use mcint::Points;
use mcint::pdf::UniformBox;
use mcint::sampler::{Halton, PassKind, Sampler, SamplerKind, Scramble, Sobol};
use rand::Rng;
use rand_pcg::Pcg64;
use std::hint::black_box;
use std::time::Duration;

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

/// Points per large fill test.
const LARGE: u64 = 1 << 20;
/// Points per in-cache block of the blocked fills.
const IN_CACHE: u64 = 4096;

/// The sampler's build arguments `(dims, pass size, points filled)` for the 2^20-point groups
/// at `dims`, and the row name.
fn pass_for(kind: SamplerKind, dims: usize) -> (usize, u64, u64, String) {
    let name = kind.name().to_string();
    let slow = matches!(
        kind,
        SamplerKind::MultiJitter
            | SamplerKind::Cmj
            | SamplerKind::OaBose
            | SamplerKind::OaBush
            | SamplerKind::NRooksMultistage
    );
    let large = |pass: u64| {
        if slow && dims == 32 {
            (dims, pass, 1 << 16, format!("{name}_2^16"))
        } else {
            (dims, pass, LARGE, name.clone())
        }
    };
    match kind {
        // k^dims strata: 32^4 = 2^20; at d = 32, 2^32 (k = 2) is the smallest size >= 2^20.
        SamplerKind::Jittered if dims == 32 => large(1 << 32),
        // p^2 and p^3 for a prime p: 1031^2 and 103^3 are the first sizes above 2^20.
        SamplerKind::OaBose => large(1031 * 1031),
        SamplerKind::OaBush => large(103 * 103 * 103),
        // Built a pass at a time: one pass of 1024 points (Poisson disk in at most 3 dims).
        SamplerKind::Poisson => (3, 1024, 1024, format!("{name}_3d_1024")),
        SamplerKind::BestCandidate => (dims.min(4), 1024, 1024, format!("{name}_4d_1024")),
        _ => large(LARGE),
    }
}

fn large_fill_benches(c: &mut Criterion) {
    for dims in [4usize, 32] {
        for whole in [false, true] {
            let mode = if whole { "whole" } else { "blocks" };
            let mut group = c.benchmark_group(format!("fill_{dims}d_2^20_{mode}"));
            group.sampling_mode(SamplingMode::Flat);
            if !whole {
                // Baseline: PCG-64 doubles written into the same in-cache block.
                let mut rng = Pcg64::new(0xcafe_f00d_d15e_a5e5, 0x0a02_bdbf_7bb3_c0a7);
                let mut block = Points::new(dims, IN_CACHE as usize).unwrap();
                group.throughput(Throughput::Elements(dims as u64 * LARGE));
                group.bench_function("rand_pcg_baseline", |b| {
                    b.iter(|| {
                        for _ in 0..LARGE / IN_CACHE {
                            for column in block.columns_mut() {
                                for x in column.iter_mut() {
                                    *x =
                                        (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
                                }
                            }
                            black_box(block.get(0, 0));
                        }
                    })
                });
            }
            for kind in SamplerKind::ALL {
                let (dims, pass, total, name) = pass_for(kind, dims);
                let sampler = kind.build(dims, pass, 1).unwrap();
                let block_len = if whole { total } else { total.min(IN_CACHE) };
                let mut block = Points::new(dims, block_len as usize).unwrap();
                group.throughput(Throughput::Elements(dims as u64 * total));
                // A fresh pass per iteration (a fresh stretch of 2^20 points for independent
                // points; extensible sequences start their next pass).
                let stride = match sampler.passes() {
                    PassKind::Independent => total,
                    PassKind::Fixed { size } => size,
                    PassKind::Extensible { max } => max,
                };
                let mut first = 0u64;
                group.bench_function(name, |b| {
                    b.iter(|| {
                        let mut done = 0;
                        while done < total {
                            sampler.fill(first + done, &mut block).unwrap();
                            black_box(block.get(0, 0));
                            done += block_len;
                        }
                        first += stride;
                    })
                });
            }
            group.finish();
        }
    }
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

fn owen_halton_vs_sobol(c: &mut Criterion) {
    let mut group = c.benchmark_group("owen_halton_vs_sobol");
    for dims in [10usize, 30] {
        let samplers: [(&str, Box<dyn Sampler>); 2] = [
            (
                "halton",
                Box::new(Halton::new(dims, Scramble::Owen, 1).unwrap()),
            ),
            (
                "sobol",
                Box::new(Sobol::new(dims, Scramble::Owen, 1).unwrap()),
            ),
        ];
        let mut block = Points::new(dims, POINTS).unwrap();
        group.throughput(Throughput::Elements((dims * POINTS) as u64));
        for (name, sampler) in &samplers {
            let PassKind::Extensible { max: stride } = sampler.passes() else {
                unreachable!("Halton and Sobol' passes are extensible")
            };
            let blocks_per_pass = (1u64 << 16) / POINTS as u64;
            let mut block_number = 0u64;
            group.bench_function(format!("{name}_{dims}d"), |b| {
                b.iter(|| {
                    let (pass, within) = (
                        block_number / blocks_per_pass,
                        block_number % blocks_per_pass,
                    );
                    let start = pass * stride + within * POINTS as u64;
                    sampler.fill(start, &mut block).unwrap();
                    block_number += 1;
                    black_box(block.get(0, 0))
                })
            });
        }
    }
    group.finish();
}

/// Owen-scrambled Halton: the block kernel (`fill`) against the one-coordinate path (`point`,
/// which recomputes every node of every index), both writing the first 2^16 points of a fresh
/// pass into one block, so that the kernel pays for its tables every iteration.
fn owen_halton_block_vs_point(c: &mut Criterion) {
    const N: usize = 1 << 16;
    let mut group = c.benchmark_group("owen_halton_block_vs_point");
    group.sampling_mode(SamplingMode::Flat);
    for dims in [4usize, 32] {
        let halton = Halton::new(dims, Scramble::Owen, 1).unwrap();
        let mut block = Points::new(dims, N).unwrap();
        group.throughput(Throughput::Elements((dims * N) as u64));
        let mut pass = 0u64;
        group.bench_function(format!("block_{dims}d_2^16"), |b| {
            b.iter(|| {
                halton.fill(pass * Halton::PASS_SIZE, &mut block).unwrap();
                pass += 1;
                black_box(block.get(0, 0))
            })
        });
        let mut point = vec![0.0; dims];
        group.bench_function(format!("point_{dims}d_2^16"), |b| {
            b.iter(|| {
                let first = pass * Halton::PASS_SIZE;
                for i in 0..N {
                    halton.point(first + i as u64, &mut point).unwrap();
                    for (column, &x) in block.columns_mut().zip(&point) {
                        column[i] = x;
                    }
                }
                pass += 1;
                black_box(block.get(0, 0))
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
    targets = fill_benches, large_fill_benches, integrate_benches, owen_halton_vs_sobol,
        owen_halton_block_vs_point
}
criterion_main!(benches);
