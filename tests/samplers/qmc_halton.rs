//! Tests of the Halton and Hammersley samplers: reference values from scipy and from exact
//! rational arithmetic, `fill` against `point`, the range `[0, 1)`, the stratification of
//! radical inverses (unscrambled and scrambled), uniformity of scrambled points across seeds,
//! unbiasedness and variance reduction of the randomized estimates, and the error cases.
//!
//! The scipy reference files in `tests/data/halton_*.txt` were made with scipy 1.17.1; the exact
//! command is in each file's header. For the full matrices it is
//!
//! ```text
//! python3 -c "from scipy.stats import qmc; x = qmc.Halton(d, scramble=False).random(1000); [print(i, *(repr(float(v)) for v in r)) for i, r in enumerate(x)]"
//! ```
//!
//! with `d` = 2, 10 and 100, and for selected rows and columns of `d` = 1000 and 10000 a short
//! program that sets `Halton.num_generated = i` before `random(1)` (scipy's `fast_forward`
//! draws all the skipped points).
//!
//! Statistical thresholds are 1e-5 tail quantiles (chi-square bounds from
//! `scipy.stats.chi2.isf(1e-5, df)`, means within 4.5 standard errors, two-sided p about 7e-6)
//! with fixed seeds, so a correct sampler fails none of them in practice and a run is
//! reproducible bit for bit.

use crate::common::SplitMix64;
use mcint::sampler::{Halton, Hammersley, PassKind, Sampler, Scramble};
use mcint::{Error, Points};

const SCRAMBLES: [Scramble; 3] = [Scramble::None, Scramble::Permute, Scramble::Owen];
const RANDOMIZED: [Scramble; 2] = [Scramble::Permute, Scramble::Owen];
const PASS: u64 = 1 << 40;

/// The first `n` primes, by trial division (independent of the sieve in the crate).
fn primes(n: usize) -> Vec<u64> {
    let mut found: Vec<u64> = Vec::with_capacity(n);
    let mut candidate = 2u64;
    while found.len() < n {
        if found
            .iter()
            .take_while(|&&p| p * p <= candidate)
            .all(|&p| !candidate.is_multiple_of(p))
        {
            found.push(candidate);
        }
        candidate += 1;
    }
    found
}

// ---------------------------------------------------------------------------------------------
// Exact arithmetic

/// The radical inverse of `i` in base `b` as an exact fraction `num / b^k`.
fn exact_radical_inverse(mut i: u64, b: u64) -> (u128, u128) {
    let (mut num, mut den) = (0u128, 1u128);
    while i > 0 {
        num = num * u128::from(b) + u128::from(i % b);
        den *= u128::from(b);
        i /= b;
    }
    (num, den)
}

/// Whether `x` is the double nearest to `num / den` (a tie may go either way), decided in
/// integers: with `x = m 2^-s` for a 53-bit `m`, `|x - num/den| <= 2^-s / 2` iff
/// `2 |m den - num 2^s| <= den`. Needs `m den` and `num 2^s` below `2^128`.
fn is_nearest(x: f64, num: u128, den: u128) -> bool {
    if num == 0 {
        return x == 0.0;
    }
    if !(x > 0.0 && x < 1.0) {
        return false;
    }
    let bits = x.to_bits();
    let exponent = ((bits >> 52) & 0x7ff) as u32;
    let m = u128::from((bits & ((1 << 52) - 1)) | (1 << 52));
    let s = 1075 - exponent;
    let (a, c) = (m * den, num << s);
    2 * a.abs_diff(c) <= den
}

/// scipy's own arithmetic for an unscrambled coordinate (`_cy_van_der_corput`): the terms
/// `digit * b2r` added in order, with `b2r` starting at `1 / b` and divided by `b` per digit.
fn scipy_sum(mut i: u64, b: u64) -> f64 {
    let (mut sum, mut b2r) = (0.0f64, 1.0 / b as f64);
    while i > 0 {
        sum += (i % b) as f64 * b2r;
        b2r /= b as f64;
        i /= b;
    }
    sum
}

/// Distance in units in the last place between two non-negative doubles.
fn ulps(a: f64, b: f64) -> u64 {
    a.to_bits().abs_diff(b.to_bits())
}

// ---------------------------------------------------------------------------------------------
// scipy reference files

struct Reference {
    /// The dimensions each row lists.
    columns: Vec<usize>,
    /// (index, values of the listed columns)
    rows: Vec<(u64, Vec<f64>)>,
}

fn load(name: &str) -> Reference {
    let path = format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut columns = None;
    let mut rows = Vec::new();
    for line in text.lines() {
        if let Some(listed) = line.strip_prefix("# columns:") {
            columns = Some(
                listed
                    .split_whitespace()
                    .map(|c| c.parse().unwrap())
                    .collect(),
            );
        } else if !line.starts_with('#') && !line.trim().is_empty() {
            let mut fields = line.split_whitespace();
            let index: u64 = fields.next().unwrap().parse().unwrap();
            let values: Vec<f64> = fields.map(|v| v.parse().unwrap()).collect();
            rows.push((index, values));
        }
    }
    let width = rows[0].1.len();
    Reference {
        columns: columns.unwrap_or_else(|| (0..width).collect()),
        rows,
    }
}

/// Compares an unscrambled Halton sampler with a scipy file: within 2 ulps of scipy, exactly
/// the correctly rounded radical inverse, and scipy's file reproduced bit for bit by its
/// term-by-term summation (so every difference is scipy's rounding). Returns (coordinates,
/// bit-equal ones).
fn check_against_scipy(dims: usize, file: &str) -> (usize, usize) {
    let reference = load(file);
    let bases = primes(dims);
    let halton = Halton::new(dims, Scramble::None, 0).unwrap();
    let mut point = vec![0.0; dims];
    let (mut total, mut equal) = (0, 0);
    for (index, values) in &reference.rows {
        halton.point(*index, &mut point).unwrap();
        for (&dim, &expected) in reference.columns.iter().zip(values) {
            let (x, b) = (point[dim], bases[dim]);
            let (num, den) = exact_radical_inverse(*index, b);
            assert!(
                is_nearest(x, num, den),
                "{file}: index {index}, dim {dim}: {x:e} is not {num}/{den} rounded"
            );
            assert_eq!(
                scipy_sum(*index, b).to_bits(),
                expected.to_bits(),
                "{file}: index {index}, dim {dim}: scipy's summation does not give the file value"
            );
            assert!(
                ulps(x, expected) <= 2,
                "{file}: index {index}, dim {dim}: {x:e} vs scipy {expected:e}"
            );
            total += 1;
            equal += usize::from(x.to_bits() == expected.to_bits());
        }
    }
    (total, equal)
}

#[test]
fn unscrambled_halton_matches_scipy() {
    // scipy accumulates sum(a_k * b^-k) in floating point, a few roundings per term, and so
    // lands up to 2 ulps from the exact value, which we return correctly rounded: 2 ulps is
    // the tolerance, and `check_against_scipy` shows where every difference comes from.
    for (dims, file, rows) in [
        (2, "halton_d2_n1000.txt", 1000),
        (10, "halton_d10_n1000.txt", 1000),
        (100, "halton_d100_n1000.txt", 1000),
        (1000, "halton_d1000_selected.txt", 15),
        (10_000, "halton_d10000_selected.txt", 15),
    ] {
        let (total, equal) = check_against_scipy(dims, file);
        let expected_total = rows * load(file).columns.len();
        assert_eq!(total, expected_total, "{file}");
        // Most coordinates agree bit for bit (all of base 2, which is exact either way).
        assert!(equal * 2 > total, "{file}: only {equal} of {total} equal");
    }
}

#[test]
fn unscrambled_fill_matches_scipy_block() {
    let reference = load("halton_d100_n1000.txt");
    let halton = Halton::new(100, Scramble::None, 3).unwrap();
    let mut block = Points::new(100, 1000).unwrap();
    halton.fill(0, &mut block).unwrap();
    for (index, values) in &reference.rows {
        for (dim, &expected) in values.iter().enumerate() {
            let x = block.get(*index as usize, dim);
            assert!(ulps(x, expected) <= 2, "index {index}, dim {dim}");
        }
    }
    // The first point is the origin, as in scipy.
    assert!(block.column(0)[0] == 0.0 && block.column(99)[0] == 0.0);
}

#[test]
fn unscrambled_hammersley_is_exact() {
    // Reference by exact rational arithmetic: x_0 = i / N and x_j = phi_{p_j}(i), each the
    // correctly rounded double; and the Halton columns agree with the scipy Halton file.
    let scipy = load("halton_d10_n1000.txt");
    let bases = primes(10);
    for n in [1u64, 2, 7, 64, 1000, 1 << 40] {
        let s = Hammersley::new(11, n, Scramble::None, 9).unwrap();
        assert!(!s.is_randomized());
        let mut p = [0.0; 11];
        let indices: Vec<u64> = (0..n.min(1000)).chain([n - 1, n / 3]).collect();
        for &i in &indices {
            s.point(i, &mut p).unwrap();
            assert!(
                is_nearest(p[0], u128::from(i), u128::from(n)),
                "N {n}, i {i}"
            );
            for (j, &b) in bases.iter().enumerate() {
                let (num, den) = exact_radical_inverse(i, b);
                assert!(
                    is_nearest(p[j + 1], num, den),
                    "N {n}, i {i}, dim {}",
                    j + 1
                );
                if i < 1000 {
                    let expected = scipy.rows[i as usize].1[j];
                    assert!(ulps(p[j + 1], expected) <= 2);
                }
            }
            // Passes repeat without scrambling.
            let mut q = [0.0; 11];
            s.point(5 * n + i, &mut q).unwrap();
            assert_eq!(p, q);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The sampler contract: fill == point, [0, 1), determinism

/// Every combination exercised by the contract tests.
fn samplers(dims: usize, seed: u64) -> Vec<(String, Box<dyn Sampler>)> {
    let mut all: Vec<(String, Box<dyn Sampler>)> = Vec::new();
    for scramble in SCRAMBLES {
        all.push((
            format!("halton {scramble} d{dims}"),
            Box::new(Halton::new(dims, scramble, seed).unwrap()),
        ));
        for n in [1u64, 5, 64, 1000, 1 << 40] {
            all.push((
                format!("hammersley {scramble} N{n} d{dims}"),
                Box::new(Hammersley::new(dims, n, scramble, seed).unwrap()),
            ));
        }
    }
    all
}

/// Start indices that cross pass boundaries and reach the end of the index space.
fn interesting_start(rng: &mut SplitMix64, pass: u64, len: u64) -> u64 {
    match rng.below(5) {
        0 => rng.below(5000),
        1 => (1 + rng.below(5)) * pass - rng.below(len + 1).min(pass),
        2 => u64::MAX - len + 1 - rng.below(3).min(u64::MAX - len + 1),
        3 => (1 + rng.below(1000)) * PASS - rng.below(len + 1),
        _ => rng.next_u64() >> rng.below(64),
    }
}

fn check_fill_matches_point(sampler: &dyn Sampler, name: &str, start: u64, len: usize) {
    let dims = sampler.dims();
    let mut block = Points::new(dims, len).unwrap();
    sampler.fill(start, &mut block).unwrap();
    let mut p = vec![0.0; dims];
    for i in 0..len {
        sampler.point(start + i as u64, &mut p).unwrap();
        for (dim, &x) in p.iter().enumerate() {
            let y = block.get(i, dim);
            assert_eq!(
                x.to_bits(),
                y.to_bits(),
                "{name}: index {}, dim {dim}: point {x:e} vs fill {y:e}",
                start + i as u64
            );
            assert!(
                (0.0..1.0).contains(&x),
                "{name}: {x} at index {}",
                start + i as u64
            );
        }
    }
}

#[test]
fn fill_equals_point_bit_for_bit() {
    let mut rng = SplitMix64(2024);
    for dims in [1usize, 2, 7, 40] {
        for (name, sampler) in samplers(dims, rng.next_u64()) {
            let pass = match sampler.passes() {
                PassKind::Fixed { size } => size,
                PassKind::Extensible { max } => max,
                PassKind::Independent => unreachable!(),
            };
            for _ in 0..8 {
                let len = rng.below(if dims > 10 { 80 } else { 300 }) as usize;
                let start = interesting_start(&mut rng, pass, len as u64);
                check_fill_matches_point(sampler.as_ref(), &name, start, len);
            }
        }
    }
    // Many dimensions, including the largest bases.
    for scramble in SCRAMBLES {
        let halton = Halton::new(10_000, scramble, 77).unwrap();
        for start in [0, 7919 * 7919 - 2, 3 * PASS - 2] {
            check_fill_matches_point(&halton, &format!("halton {scramble} d10000"), start, 4);
        }
        let hammersley = Hammersley::new(1000, 100_000, scramble, 78).unwrap();
        check_fill_matches_point(&hammersley, &format!("hammersley {scramble}"), 99_998, 4);
    }
}

#[test]
fn scrambled_block_kernels_fill_like_points() {
    // The block kernels memoize the digit positions whose tables are small next to the
    // block (so the split moves with the length), compute the others per index in lanes of
    // sixteen, split blocks where the number of digits of the index grows and where a pass
    // ends, and evaluate the digit permutations of bases 2, 3 to 13, 17 to 65,521 and above
    // 65,536 in four different ways. Ragged lengths around the lane count and the table
    // sizes, at starts where the digit count changes, near the end of a pass and in later
    // passes, all bit for bit against `point`.
    for scramble in RANDOMIZED {
        let halton = Halton::new(40, scramble, 91).unwrap();
        for (start, len) in [
            (0u64, 1usize),
            (0, 2),
            (1, 15),
            (3u64.pow(10) - 7, 16),
            (5u64.pow(8) - 9, 17),
            (173 * 173 - 20, 33),
            (PASS - 9, 40),
            (2 * PASS + 13, 257),
            (1_000_003, 1100),
            (2u64.pow(20) - 2000, 5000),
        ] {
            let name = format!("halton {scramble} start {start} len {len}");
            check_fill_matches_point(&halton, &name, start, len);
        }
        let hammersley = Hammersley::new(24, 3u64.pow(9), scramble, 92).unwrap();
        check_fill_matches_point(&hammersley, "hammersley", 3u64.pow(9) - 100, 300);
        // The largest bases (above 65,536 from dimension 6,543 on), where permutations are
        // Feistel networks, and where a block of 40 memoizes nothing.
        let many = Halton::new(10_000, scramble, 93).unwrap();
        for start in [65_536 * 2 - 20, PASS - 20] {
            check_fill_matches_point(&many, "halton d10000", start, 40);
        }
    }
}

#[test]
fn large_blocks_fill_like_points() {
    // Blocks long enough for the memoized permutation tables and the odometer.
    for scramble in SCRAMBLES {
        let halton = Halton::new(30, scramble, 5).unwrap();
        check_fill_matches_point(&halton, "halton", PASS - 1500, 3000);
        let hammersley = Hammersley::new(30, 2000, scramble, 5).unwrap();
        check_fill_matches_point(&hammersley, "hammersley", 1000, 3000);
    }
}

#[test]
fn coordinates_stay_in_the_unit_interval_at_extreme_indices() {
    let indices = [0, 1, PASS - 1, PASS, 5 * PASS - 1, u64::MAX - 1, u64::MAX];
    for scramble in SCRAMBLES {
        for seed in [0u64, 1, u64::MAX] {
            let halton = Halton::new(10_000, scramble, seed).unwrap();
            let mut p = vec![0.0; 10_000];
            for index in indices {
                halton.point(index, &mut p).unwrap();
                assert!(
                    p.iter().all(|x| (0.0..1.0).contains(x)),
                    "{scramble} {index}"
                );
            }
            for n in [1u64, 3, 1 << 40] {
                let hammersley = Hammersley::new(50, n, scramble, seed).unwrap();
                let mut block = Points::new(50, 200).unwrap();
                hammersley.fill(u64::MAX - 199, &mut block).unwrap();
                for dim in 0..50 {
                    assert!(block.column(dim).iter().all(|x| (0.0..1.0).contains(x)));
                }
            }
        }
    }
    // The last point of a Halton pass is as close to 1 as its digits allow.
    let halton = Halton::new(1, Scramble::None, 0).unwrap();
    let mut p = [0.0];
    halton.point(PASS - 1, &mut p).unwrap();
    assert_eq!(p[0], 1.0 - 2f64.powi(-40));
}

#[test]
fn same_seed_same_points_and_passes_differ_only_when_scrambled() {
    for scramble in SCRAMBLES {
        let a = Halton::new(4, scramble, 11).unwrap();
        let mut b = a.clone();
        let (mut p, mut q) = ([0.0; 4], [0.0; 4]);
        a.point(123, &mut p).unwrap();
        b.point(123, &mut q).unwrap();
        assert_eq!(p, q);
        b.point(PASS + 123, &mut q).unwrap();
        assert_eq!(
            p == q,
            scramble == Scramble::None,
            "{scramble}: pass 1 vs pass 0"
        );
        b.reseed(12);
        assert_eq!(b.seed(), 12);
        b.point(123, &mut q).unwrap();
        assert_eq!(p == q, scramble == Scramble::None, "{scramble}: reseeded");
        assert_eq!(a.is_randomized(), scramble != Scramble::None);
        assert_eq!(a.name(), "halton");
        assert_eq!(a.passes(), PassKind::Extensible { max: PASS });
        assert_eq!(a.scramble(), scramble);

        let h = Hammersley::new(3, 100, scramble, 11).unwrap();
        assert_eq!(h.name(), "hammersley");
        assert_eq!(h.passes(), PassKind::Fixed { size: 100 });
        assert_eq!(h.is_randomized(), scramble != Scramble::None);
        let (mut p, mut q) = ([0.0; 3], [0.0; 3]);
        h.point(7, &mut p).unwrap();
        h.point(107, &mut q).unwrap();
        assert_eq!(
            p == q,
            scramble == Scramble::None,
            "{scramble}: hammersley passes"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Stratification

/// The stratum `floor(x * size)` of `x` among `size` equal slabs, robust to rounding: an
/// unscrambled coordinate may be exactly `a / size`, and its nearest double (and the product
/// with `size`, for `size <= 2^13`) can fall up to `2^-40` slab widths below the boundary, so we
/// add `2^-38`. A scrambled point (uniform within its slab) is misplaced by this with
/// probability `2^-38` only.
fn stratum(x: f64, size: u64) -> usize {
    (x * size as f64 + 2f64.powi(-38)) as usize
}

/// Checks that every aligned run of `b^k` indices `[r b^k, (r + 1) b^k)` inside the block
/// (column of local indices `first ..`) puts exactly one point in each `[a / b^k, (a+1) / b^k)`.
fn check_strata(column: &[f64], first: u64, b: u64, what: &str) {
    let mut size = b;
    while size <= column.len() as u64 {
        let mut r = first.div_ceil(size) * size;
        while r + size <= first + column.len() as u64 {
            let offset = (r - first) as usize;
            let mut seen = vec![false; size as usize];
            for &x in &column[offset..offset + size as usize] {
                let stratum = stratum(x, size);
                assert!(
                    stratum < seen.len() && !seen[stratum],
                    "{what}: base {b}, {size} points from {r}: stratum {stratum} twice"
                );
                seen[stratum] = true;
            }
            r += size;
        }
        size *= b;
    }
}

#[test]
fn each_halton_coordinate_is_a_01_sequence() {
    // Radical inverses in base b are (0,1)-sequences: any b^k consecutive indices starting at
    // a multiple of b^k have distinct lowest k digits, hence distinct first k output digits.
    // Digit permutations and nested scrambles are bijections on those digits, so they keep it.
    let dims = 12;
    let bases = primes(dims);
    for scramble in SCRAMBLES {
        for pass in [0u64, 3] {
            for first in [0u64, 1_000_003] {
                let halton = Halton::new(dims, scramble, 99).unwrap();
                let mut block = Points::new(dims, 8192).unwrap();
                halton.fill(pass * PASS + first, &mut block).unwrap();
                for (dim, &b) in bases.iter().enumerate() {
                    let what = format!("halton {scramble} pass {pass} dim {dim}");
                    check_strata(block.column(dim), first, b, &what);
                }
            }
        }
    }
}

#[test]
fn hammersley_in_base_two_is_a_0_m_2_net() {
    // N = 2^m points of (x_0, phi_2): every elementary box of area 1/N holds one point, also
    // after scrambling phi_2 and rotating x_0 (see the module docs of `hammersley`).
    for m in [4u32, 7, 10] {
        let n = 1u64 << m;
        for scramble in SCRAMBLES {
            let s = Hammersley::new(3, n, scramble, 1234).unwrap();
            for pass in [0u64, 1, 2] {
                let mut block = Points::new(3, n as usize).unwrap();
                s.fill(pass * n, &mut block).unwrap();
                for j in 0..=m {
                    let (cols, rows) = (1u64 << j, 1u64 << (m - j));
                    let mut seen = vec![false; n as usize];
                    for i in 0..n as usize {
                        let a = stratum(block.get(i, 0), cols) as u64;
                        let c = stratum(block.get(i, 1), rows) as u64;
                        let cell = (a * rows + c) as usize;
                        assert!(!seen[cell], "{scramble} m {m} pass {pass} j {j}: box twice");
                        seen[cell] = true;
                    }
                }
                // The first coordinate keeps its equal spacing: one point per 1/N slab. The
                // base-3 coordinate of N points is stratified like any Halton coordinate.
                check_strata(block.column(0), 0, n, "hammersley x_0");
                check_strata(block.column(2), 0, 3, "hammersley base 3");
            }
        }
    }
    // Any N: one point per slab of the first coordinate.
    for scramble in SCRAMBLES {
        let s = Hammersley::new(2, 1000, scramble, 8).unwrap();
        let mut block = Points::new(2, 1000).unwrap();
        s.fill(7000, &mut block).unwrap();
        check_strata(block.column(0), 0, 1000, "hammersley N = 1000");
    }
}

// ---------------------------------------------------------------------------------------------
// Statistics over seeds

/// Chi-square statistic of counts against a uniform expectation.
fn chi_square(counts: &[f64]) -> f64 {
    let expected = counts.iter().sum::<f64>() / counts.len() as f64;
    counts
        .iter()
        .map(|c| (c - expected).powi(2) / expected)
        .sum()
}

/// For `seeds` samplers built by `make(seed)`, point `index`: each listed coordinate has mean
/// 1/2 within 4.5 standard errors and 20 equal bins with chi-square below
/// `chi2.isf(1e-5, 19) = 46.86`, and the pair of the first two listed coordinates is uniform on
/// a 10 x 10 grid: chi-square below `chi2.isf(1e-5, 99) = 170.80`.
fn check_uniform_over_seeds(
    make: impl Fn(u64) -> Box<dyn Sampler>,
    index: u64,
    coords: &[usize],
    what: &str,
) {
    let seeds = 10_000u64;
    let dims = make(0).dims();
    let mut p = vec![0.0; dims];
    let mut sums = vec![0.0; coords.len()];
    let mut bins = vec![vec![0.0; 20]; coords.len()];
    let mut grid = vec![0.0; 100];
    for seed in 0..seeds {
        make(seed).point(index, &mut p).unwrap();
        for (c, &dim) in coords.iter().enumerate() {
            sums[c] += p[dim];
            bins[c][(p[dim] * 20.0) as usize] += 1.0;
        }
        let (x, y) = (p[coords[0]], p[coords[1]]);
        grid[(x * 10.0) as usize * 10 + (y * 10.0) as usize] += 1.0;
    }
    let se = (1.0 / 12.0 / seeds as f64).sqrt();
    for (c, &dim) in coords.iter().enumerate() {
        let mean = sums[c] / seeds as f64;
        assert!(
            (mean - 0.5).abs() < 4.5 * se,
            "{what}: dim {dim} mean {mean}"
        );
        let chi2 = chi_square(&bins[c]);
        assert!(chi2 < 46.86, "{what}: dim {dim} chi2 {chi2}");
    }
    let chi2 = chi_square(&grid);
    assert!(chi2 < 170.80, "{what}: 2-D chi2 {chi2}");
}

#[test]
fn scrambled_halton_points_are_uniform_over_seeds() {
    // Bases 2, 3, 13, 17 (the first above the small-permutation cut-off) and 73.
    let coords = [0usize, 1, 5, 6, 20];
    for scramble in RANDOMIZED {
        // Index 0 has only zero digits (the permuted tail alone); the other is in pass 1.
        for index in [0u64, PASS + 1_234_567] {
            let what = format!("halton {scramble} index {index}");
            check_uniform_over_seeds(
                |seed| Box::new(Halton::new(21, scramble, seed).unwrap()),
                index,
                &coords,
                &what,
            );
        }
    }
}

#[test]
fn scrambled_hammersley_points_are_uniform_over_seeds() {
    // The rotation makes each point's first coordinate uniform, not only the set's.
    for scramble in RANDOMIZED {
        for index in [5u64, 2 * 1000 + 999] {
            let what = format!("hammersley {scramble} index {index}");
            check_uniform_over_seeds(
                |seed| Box::new(Hammersley::new(4, 1000, scramble, seed).unwrap()),
                index,
                &[0, 1, 3],
                &what,
            );
        }
    }
}

/// Builds a sampler from a seed.
type Maker = Box<dyn Fn(u64) -> Box<dyn Sampler>>;

#[test]
fn owen_scrambling_is_nested_and_permute_is_not() {
    // Indices 0 and 1 share every digit but the first. Digit permutations that depend only on
    // the position map the shared digits alike, so in base 2 the two points differ by exactly
    // 1/2; nested scrambling draws the later digits of the two from different nodes, so their
    // second output digits agree with probability 1/2 (independent fair bits): over 4000
    // seeds within 4.5 standard errors, 4.5 * sqrt(0.25 / 4000) = 0.036.
    let seeds = 4000u64;
    let mut agree = 0u64;
    let (mut p, mut q) = ([0.0], [0.0]);
    for seed in 0..seeds {
        let permute = Halton::new(1, Scramble::Permute, seed).unwrap();
        permute.point(0, &mut p).unwrap();
        permute.point(1, &mut q).unwrap();
        assert_eq!((p[0] - q[0]).abs(), 0.5, "seed {seed}");
        let owen = Halton::new(1, Scramble::Owen, seed).unwrap();
        owen.point(0, &mut p).unwrap();
        owen.point(1, &mut q).unwrap();
        assert_ne!(
            stratum(p[0], 2),
            stratum(q[0], 2),
            "first digits must differ"
        );
        agree += u64::from(stratum(p[0], 4) % 2 == stratum(q[0], 4) % 2);
    }
    let fraction = agree as f64 / seeds as f64;
    assert!(
        (fraction - 0.5).abs() < 0.036,
        "second digits agree {fraction}"
    );
}

#[test]
fn owen_nodes_send_two_digits_to_a_uniform_distinct_pair() {
    // In bases above 13 an Owen node permutes its digits by a random affine map, which keeps
    // the one property the variance of a scrambled estimate depends on: two distinct digits
    // of one node go to a uniformly random pair of distinct digits, as under a uniform
    // permutation. Indices 1 and 2 share the root node with first digits 1 and 2; their first
    // output digits must differ and be uniform over the b (b - 1) ordered pairs: chi-square
    // below chi2.isf(1e-5, df) (df = 271 for base 17, 811 for base 29; scipy 1.17).
    for (dims, base, limit) in [(7usize, 17usize, 381.96), (10, 29, 994.35)] {
        let seeds = 60 * base * (base - 1);
        let mut counts = vec![0.0; base * base];
        let (mut p, mut q) = (vec![0.0; dims], vec![0.0; dims]);
        for seed in 0..seeds as u64 {
            let owen = Halton::new(dims, Scramble::Owen, seed).unwrap();
            owen.point(1, &mut p).unwrap();
            owen.point(2, &mut q).unwrap();
            let (a, b) = (
                stratum(p[dims - 1], base as u64),
                stratum(q[dims - 1], base as u64),
            );
            assert_ne!(a, b, "base {base} seed {seed}: distinct digits collide");
            counts[a * base + b] += 1.0;
        }
        let pairs: Vec<f64> = (0..base * base)
            .filter(|cell| cell / base != cell % base)
            .map(|cell| counts[cell])
            .collect();
        let chi2 = chi_square(&pairs);
        assert!(chi2 < limit, "base {base}: pair chi2 {chi2}");
    }
}

/// `f(x, y) = x e^(xy)` on the unit square: smooth, not separable.
fn integrand(x: f64, y: f64) -> f64 {
    x * (x * y).exp()
}

#[test]
fn randomized_estimates_are_unbiased_and_beat_monte_carlo() {
    // Exact: int_0^1 int_0^1 x e^(xy) dy dx = int_0^1 (e^x - 1) dx = e - 2, and
    // E f^2 = int_0^1 x (e^(2x) - 1) / 2 dx = (e^2 - 1) / 8, so the Monte Carlo variance of one
    // sample is sigma^2 = (e^2 - 1) / 8 - (e - 2)^2 = 0.2827.
    let e = std::f64::consts::E;
    let exact = e - 2.0;
    let sigma2 = (e * e - 1.0) / 8.0 - (e - 2.0).powi(2);
    let (n, replicates) = (1000u64, 200u64);
    for scramble in RANDOMIZED {
        let makers: [(&str, Maker); 2] = [
            (
                "halton",
                Box::new(move |seed| Box::new(Halton::new(2, scramble, seed).unwrap())),
            ),
            (
                "hammersley",
                Box::new(move |seed| Box::new(Hammersley::new(2, n, scramble, seed).unwrap())),
            ),
        ];
        for (name, make) in makers {
            let mut estimates = Vec::new();
            let mut block = Points::new(2, n as usize).unwrap();
            for seed in 0..replicates {
                // Pass 0 of the sampler with this seed: one randomized point set of N points.
                make(seed + 1000).fill(0, &mut block).unwrap();
                let sum: f64 = (0..n as usize)
                    .map(|i| integrand(block.get(i, 0), block.get(i, 1)))
                    .sum();
                estimates.push(sum / n as f64);
            }
            let r = replicates as f64;
            let mean = estimates.iter().sum::<f64>() / r;
            let var = estimates.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (r - 1.0);
            let se = (var / r).sqrt();
            assert!(
                (mean - exact).abs() < 4.5 * se,
                "{name} {scramble}: mean {mean} vs {exact}, se {se:e}"
            );
            // Variance: the 1e-5 upper confidence bound var * 199 / chi2.ppf(1e-5, 199), with
            // chi2.ppf(1e-5, 199) = 125.08, must lie below a tenth of the Monte Carlo variance
            // sigma^2 / N. Theory predicts far more: for smooth f, randomized Halton and
            // Hammersley errors are O(log^2 N / N) (Koksma-Hlawka with their discrepancy), and
            // scrambled nets reach variance O(N^-3 log N) (Owen 1997), against sigma^2 / N.
            let upper = var * 199.0 / 125.08;
            eprintln!(
                "{name} {scramble}: mean {mean:.6} (exact {exact:.6}), variance {var:.3e}, \
                 Monte Carlo {:.3e}",
                sigma2 / n as f64
            );
            assert!(
                upper < sigma2 / n as f64 / 10.0,
                "{name} {scramble}: variance {var:e} vs Monte Carlo {:e}",
                sigma2 / n as f64
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Errors

fn invalid(err: Error, name: &str, mentions: &str) {
    let text = err.to_string();
    match err {
        Error::InvalidParameter { name: n, .. } => assert_eq!(n, name, "{text}"),
        other => panic!("expected an invalid {name}, got {other:?}"),
    }
    assert!(text.contains(mentions), "{text}");
}

#[test]
fn bad_parameters_are_errors_naming_the_allowed_values() {
    invalid(
        Halton::new(0, Scramble::None, 0).unwrap_err(),
        "dims",
        "1 to 10000",
    );
    invalid(
        Halton::new(10_001, Scramble::Owen, 0).unwrap_err(),
        "dims",
        "1 to 10000",
    );
    invalid(
        Hammersley::new(0, 8, Scramble::None, 0).unwrap_err(),
        "dims",
        "1 to 10000",
    );
    invalid(
        Hammersley::new(10_001, 8, Scramble::None, 0).unwrap_err(),
        "dims",
        "1 to 10000",
    );
    invalid(
        Hammersley::new(2, 0, Scramble::None, 0).unwrap_err(),
        "points",
        "1 to 2^40",
    );
    invalid(
        Hammersley::new(2, PASS + 1, Scramble::None, 0).unwrap_err(),
        "points",
        "1 to 2^40",
    );
    for scramble in [Scramble::Xor, Scramble::Lms, Scramble::Shift] {
        let err = Halton::new(2, scramble, 0).unwrap_err();
        invalid(err, "scramble", "one of none, permute, owen for halton");
        let err = Hammersley::new(2, 8, scramble, 0).unwrap_err();
        invalid(err, "scramble", "one of none, permute, owen for hammersley");
    }
    let halton = Halton::new(3, Scramble::Owen, 0).unwrap();
    assert!(matches!(
        halton.point(0, &mut [0.0; 2]),
        Err(Error::DimensionMismatch { .. })
    ));
    assert!(matches!(
        halton.fill(0, &mut Points::new(2, 4).unwrap()),
        Err(Error::DimensionMismatch { .. })
    ));
    assert!(matches!(
        halton.fill(u64::MAX, &mut Points::new(3, 2).unwrap()),
        Err(Error::IndexOutOfRange { .. })
    ));
    let hammersley = Hammersley::new(3, 10, Scramble::Permute, 0).unwrap();
    assert!(matches!(
        hammersley.point(0, &mut [0.0; 4]),
        Err(Error::DimensionMismatch { .. })
    ));
    // Empty blocks are fine anywhere.
    assert!(
        hammersley
            .fill(u64::MAX, &mut Points::new(3, 0).unwrap())
            .is_ok()
    );
}
