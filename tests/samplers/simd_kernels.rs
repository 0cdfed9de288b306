//! The block fill kernels (Sobol' under every scramble, with and without the index shuffle,
//! `Independent`, Halton, lattices, multi-jittered, Latin hypercube, pmj02, multi-stage N-rooks
//! and orthogonal arrays) against the scalar `point` path, bit for bit: random starts and starts
//! near the ends of a pass (2^32) and of the index range (u64::MAX), ragged lengths around the
//! Gray-code group (16) and chunk (256) sizes, and several dimensions. Then the portable
//! kernels against the dispatched ones.
//!
//! `simd::force_portable` switches the whole process, so the tests that rely on the dispatched
//! path hold a shared lock and the one that switches holds it exclusively.

use crate::common::SplitMix64;
use mcint::Points;
use mcint::sampler::{
    CorrelatedMultiJittered, Halton, Independent, LatinHypercube, Lattice, MultiJittered,
    MultiStageNRooks, OaOffset, OrthogonalArray, Pmj02, Sampler, Scramble, Sobol, simd,
};
use std::sync::RwLock;

static PATH: RwLock<()> = RwLock::new(());

const PASS: u64 = 1 << 32;
const DIMS: [usize; 6] = [1, 2, 3, 4, 7, 32];
const LENGTHS: [usize; 16] = [
    0, 1, 7, 8, 9, 15, 16, 17, 31, 33, 255, 256, 257, 511, 1000, 1500,
];

/// Starts for a block of `len` points: aligned, misaligned, random, straddling or ending at
/// pass boundaries, and ending at the last index `u64::MAX`.
fn starts(len: usize, rng: &mut SplitMix64) -> Vec<u64> {
    let len = len as u64;
    let mut starts = vec![0, 1, 13, 16, 255, 4096 + 5];
    // Straddling the end of pass 0 (the index counter wraps at 2^32 inside the kernels).
    starts.push(PASS - len / 2 - 3);
    // Ending exactly at the end of a pass, and starting just after it.
    starts.push(7 * PASS - len);
    starts.push(PASS + 1);
    // The last indices of the whole range.
    starts.push(u64::MAX - len.saturating_sub(1));
    starts.push(u64::MAX - len.saturating_sub(1) - 9);
    for _ in 0..3 {
        starts.push(rng.next_u64() >> 1);
        // A random in-pass index in a random pass.
        starts.push((rng.next_u64() & !(PASS - 1)) | (rng.next_u64() >> 32));
    }
    starts
}

/// The lengths the other samplers are checked at (their `point` is slower than Sobol's).
const SHORT_LENGTHS: [usize; 12] = [0, 1, 7, 8, 9, 15, 16, 17, 255, 256, 257, 1000];

/// Starts for a sampler whose passes hold `pass` points: aligned and misaligned small ones,
/// straddling and ending at pass boundaries, the last indices of the range, and random ones.
fn starts_for_pass(len: usize, pass: u64, rng: &mut SplitMix64) -> Vec<u64> {
    let len = len as u64;
    let mut starts = vec![0, 1, 13, 4096 + 5];
    starts.push((3 * pass).saturating_sub(len / 2 + 3));
    starts.push((7 * pass).saturating_sub(len));
    starts.push(u64::MAX - len.saturating_sub(1));
    for _ in 0..2 {
        starts.push(rng.next_u64() >> 1);
    }
    starts
}

/// Fills a block and asserts every coordinate equals `point`'s, bit for bit.
fn assert_fill_matches_point(sampler: &dyn Sampler, start: u64, len: usize) {
    let dims = sampler.dims();
    let mut block = Points::new(dims, len).unwrap();
    sampler.fill(start, &mut block).unwrap();
    let mut p = vec![0.0; dims];
    for i in 0..len {
        let index = start + i as u64;
        sampler.point(index, &mut p).unwrap();
        for (dim, &x) in p.iter().enumerate() {
            let y = block.get(i, dim);
            assert_eq!(
                x.to_bits(),
                y.to_bits(),
                "{} {} ({dims} dims): start {start} len {len} point {index} dim {dim}: \
                 point {x} fill {y}",
                simd::active(),
                sampler.name()
            );
        }
    }
}

/// The Sobol' samplers under test: every scramble, and Owen with the index shuffle.
fn sobols(dims: usize, seed: u64) -> Vec<Sobol> {
    let mut all: Vec<Sobol> = [Scramble::None, Scramble::Xor, Scramble::Lms, Scramble::Owen]
        .into_iter()
        .map(|scramble| Sobol::new(dims, scramble, seed).unwrap())
        .collect();
    all.push(
        Sobol::new(dims, Scramble::Owen, seed)
            .unwrap()
            .with_index_shuffle(true),
    );
    all
}

#[test]
fn sobol_fill_equals_point_for_every_scramble_start_length_and_dimension() {
    let _shared = PATH.read().unwrap();
    let mut rng = SplitMix64(1);
    for dims in DIMS {
        for sobol in sobols(dims, dims as u64 * 31 + 5) {
            for len in LENGTHS {
                for start in starts(len, &mut rng) {
                    assert_fill_matches_point(&sobol, start, len);
                }
            }
        }
    }
}

#[test]
fn sobol_long_fill_over_a_pass_boundary_equals_point() {
    // Several chunks, unaligned, crossing from pass 4 into pass 5.
    let _shared = PATH.read().unwrap();
    for sobol in sobols(3, 77) {
        assert_fill_matches_point(&sobol, 5 * PASS - 2500 - 3, 5000);
    }
}

#[test]
fn independent_fill_equals_point_for_every_start_length_and_dimension() {
    let _shared = PATH.read().unwrap();
    let mut rng = SplitMix64(2);
    for dims in DIMS {
        let sampler = Independent::new(dims, dims as u64 + 11).unwrap();
        for len in LENGTHS {
            for start in starts(len, &mut rng) {
                assert_fill_matches_point(&sampler, start, len);
            }
        }
    }
}

/// Halton under every scramble, lattices unshifted and shifted (Kuo's vector, and a user's with the
/// most points per pass), multi-jittered patterns (correlated or not), Latin hypercubes, pmj02,
/// multi-stage N-rooks patterns and orthogonal arrays of several sizes: the samplers checked here,
/// with how many points their passes hold.
fn other_samplers(dims: usize, seed: u64) -> Vec<(Box<dyn Sampler>, u64)> {
    let mut all: Vec<(Box<dyn Sampler>, u64)> = Vec::new();
    for scramble in [Scramble::None, Scramble::Permute, Scramble::Owen] {
        let halton = Halton::new(dims, scramble, seed).unwrap();
        all.push((Box::new(halton), Halton::PASS_SIZE));
    }
    for scramble in [Scramble::None, Scramble::Shift] {
        all.push((
            Box::new(Lattice::new(dims, scramble, seed).unwrap()),
            1 << 20,
        ));
        let z = (0..dims as u64)
            .map(|j| (j * 0x9e37_79b9 + 1) | 1)
            .collect();
        let wide = Lattice::with_generator(z, 52, scramble, seed).unwrap();
        all.push((Box::new(wide), 1 << 52));
    }
    // Square and 1 x N grids, swap-or-not (below 2^16 points) and Feistel permutations.
    for points in [1u64, 100, 101, 1 << 16, (1 << 20) + 7, 1 << 53] {
        let cmj = CorrelatedMultiJittered::with_points(dims, points, seed).unwrap();
        all.push((Box::new(cmj), points));
        let latin = LatinHypercube::new(dims, points, seed).unwrap();
        all.push((Box::new(latin), points));
        let multi_jittered = MultiJittered::with_points(dims, points, seed).unwrap();
        all.push((Box::new(multi_jittered), points));
    }
    // pmj02 with passes of one point (scalar), two, 32, the default 2^16 and the largest.
    for log2 in [0u32, 1, 5, 16, 20] {
        let pmj = Pmj02::with_max_points(dims, log2, seed).unwrap();
        all.push((Box::new(pmj), 1 << log2));
    }
    // Multi-stage N-rooks: small bases (one-hash shuffles), a large one (hashed permutations),
    // and the largest pass.
    for (base, stages) in [(2u64, 10u32), (3, 5), (13, 2), (2, 53)] {
        let nrooks = MultiStageNRooks::with_stages(dims, base, stages, seed).unwrap();
        all.push((Box::new(nrooks), base.pow(stages)));
    }
    // Orthogonal arrays under every offset, strengths 2 and 3; with multi-jittered offsets a
    // large prime too (per-symbol permutations built per point, of Feistel size).
    for offset in OaOffset::ALL {
        let primes: &[u64] = match offset {
            OaOffset::MultiJittered => &[37, 65_537],
            _ => &[37],
        };
        for &p in primes {
            let bose = OrthogonalArray::bose(dims, p, offset, seed).unwrap();
            all.push((Box::new(bose), p * p));
        }
        if dims <= 6 {
            let bush = OrthogonalArray::bush(dims, 5, 3, offset, seed).unwrap();
            all.push((Box::new(bush), 125));
        }
    }
    all
}

#[test]
fn halton_lattice_stratified_and_orthogonal_array_fill_equals_point() {
    let _shared = PATH.read().unwrap();
    let mut rng = SplitMix64(4);
    for dims in [1, 2, 3, 7, 32] {
        for (sampler, pass) in other_samplers(dims, dims as u64 * 17 + 1) {
            // Owen-scrambled Halton points cost microseconds each in 32 bases.
            let lengths: &[usize] = if dims == 32 {
                &[0, 1, 9, 17, 257]
            } else {
                &SHORT_LENGTHS
            };
            for &len in lengths {
                for start in starts_for_pass(len, pass, &mut rng) {
                    assert_fill_matches_point(sampler.as_ref(), start, len);
                }
            }
        }
    }
}

#[test]
fn portable_kernels_equal_the_dispatched_ones() {
    let _exclusive = PATH.write().unwrap();
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("lzcnt") {
        assert_ne!(simd::active(), "portable", "avx2 is present but not used");
    }
    let mut samplers: Vec<Box<dyn Sampler>> = Vec::new();
    for dims in [1, 4, 7] {
        for sobol in sobols(dims, 3) {
            samplers.push(Box::new(sobol));
        }
        samplers.push(Box::new(Independent::new(dims, 3).unwrap()));
        samplers.extend(other_samplers(dims, 3).into_iter().map(|(s, _)| s));
    }
    let mut rng = SplitMix64(3);
    for sampler in &samplers {
        for len in [1, 17, 256, 1000, 3000] {
            for start in starts(len, &mut rng) {
                let mut dispatched = Points::new(sampler.dims(), len).unwrap();
                let mut portable = dispatched.clone();
                sampler.fill(start, &mut dispatched).unwrap();
                simd::force_portable(true);
                assert_eq!(simd::active(), "portable");
                let result = sampler.fill(start, &mut portable);
                simd::force_portable(false);
                result.unwrap();
                assert_eq!(
                    dispatched,
                    portable,
                    "{} ({} dims): start {start} len {len}",
                    sampler.name(),
                    sampler.dims()
                );
                // Equal as numbers is not enough: compare the bits (signs of zero, NaNs).
                for dim in 0..sampler.dims() {
                    let bits = |p: &Points| -> Vec<u64> {
                        p.column(dim).iter().map(|x| x.to_bits()).collect()
                    };
                    assert_eq!(bits(&dispatched), bits(&portable));
                }
            }
        }
    }
}

/// Small enough for Miri (`cargo +nightly miri test --test samplers -- simd_kernels::small`),
/// which checks
/// the dispatch's unsafe call: a few ragged fills of every scramble equal `point()`.
#[test]
fn small_fills_equal_point() {
    for scramble in [Scramble::None, Scramble::Xor, Scramble::Lms, Scramble::Owen] {
        let sobol = Sobol::new(3, scramble, 9).unwrap();
        for (start, len) in [(0u64, 17usize), (5, 3), ((1 << 32) - 2, 4)] {
            let mut block = Points::new(3, len).unwrap();
            sobol.fill(start, &mut block).unwrap();
            let mut p = [0.0; 3];
            for i in 0..len {
                sobol.point(start + i as u64, &mut p).unwrap();
                for (d, x) in p.iter().enumerate() {
                    assert_eq!(x.to_bits(), block.get(i, d).to_bits(), "{scramble:?}");
                }
            }
        }
    }
    let independent = Independent::new(2, 4).unwrap();
    let mut block = Points::new(2, 9).unwrap();
    independent.fill(3, &mut block).unwrap();
    let mut p = [0.0; 2];
    for i in 0..9 {
        independent.point(3 + i as u64, &mut p).unwrap();
        assert_eq!(p[1].to_bits(), block.get(i, 1).to_bits());
    }
}

#[test]
fn halton_kernels_in_every_base_range_equal_the_portable_ones() {
    // The Halton block kernels run node permutations in lanes: Fisher-Yates (bases up to 13),
    // swap-or-not (up to 65,521) and Feistel (above 65,536, from dimension 6,543 on).
    let _exclusive = PATH.write().unwrap();
    for scramble in [Scramble::Permute, Scramble::Owen] {
        for (dims, start, len) in [(40, 1_000_003, 3000), (10_000, 200_000, 40)] {
            let halton = Halton::new(dims, scramble, 5).unwrap();
            let mut dispatched = Points::new(dims, len).unwrap();
            let mut portable = dispatched.clone();
            halton.fill(start, &mut dispatched).unwrap();
            simd::force_portable(true);
            let result = halton.fill(start, &mut portable);
            simd::force_portable(false);
            result.unwrap();
            for dim in 0..dims {
                let bits = |p: &Points| -> Vec<u64> {
                    p.column(dim).iter().map(|x| x.to_bits()).collect()
                };
                assert_eq!(
                    bits(&dispatched),
                    bits(&portable),
                    "{scramble} d{dims} dim {dim}"
                );
            }
        }
    }
}
