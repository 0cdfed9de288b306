//! Integration tests for multi-jittered (Chiu, Shirley & Wang 1994) and correlated
//! multi-jittered (Kensler 2013) sampling: the stratification every pass promises (jittered on
//! the `m x n` grid and N-rooks in both coordinates of every pair, N-rooks in an odd last
//! dimension), the `Sampler` contract (`point` and `fill` bit-identical, determinism,
//! reseeding), unbiasedness and joint uniformity over passes, the variance reduction over
//! independent sampling, and the error messages.
//!
//! Statistical thresholds are 4.5 standard errors (two-sided p about 7e-6) or 1e-5 chi-square
//! quantiles, with fixed seeds, so a correct sampler fails none of them in practice and every
//! run is reproducible bit for bit.

use crate::common::{bits, block, config};
use mcint::sampler::{CorrelatedMultiJittered, MultiJittered, PassKind, Sampler};
use mcint::{Error, Points};
use proptest::prelude::*;

/// Builds the uncorrelated (`correlated = false`) or correlated sampler.
fn build(correlated: bool, dims: usize, m: u64, n: u64, seed: u64) -> Box<dyn Sampler> {
    if correlated {
        Box::new(CorrelatedMultiJittered::new(dims, m, n, seed).unwrap())
    } else {
        Box::new(MultiJittered::new(dims, m, n, seed).unwrap())
    }
}

fn pass_size(sampler: &dyn Sampler) -> u64 {
    match sampler.passes() {
        PassKind::Fixed { size } => size,
        other => panic!("expected fixed passes, got {other:?}"),
    }
}

/// Stratum of `x` among `k` equal slabs of `[0, 1)`.
fn slab(x: f64, k: u64) -> usize {
    (x * k as f64) as usize
}

/// Asserts that every count is exactly one.
fn all_once(counts: &[u32], what: &str) -> Result<(), TestCaseError> {
    prop_assert!(counts.iter().all(|&c| c == 1), "{what}: {counts:?}");
    Ok(())
}

/// Checks one whole pass: every pair jittered on `m x n` and N-rooks in both coordinates,
/// an odd last dimension N-rooks, every coordinate in `[0, 1)`.
///
/// For the correlated variant also checks Kensler's shared shuffle: the sub-column of a point
/// (its `x` slab modulo `n`) depends only on its row of cells, and its sub-row (`y` slab modulo
/// `m`) only on its column.
fn check_pass(points: &Points, m: u64, n: u64, correlated: bool) -> Result<(), TestCaseError> {
    let size = m * n;
    let dims = points.dims();
    for d in 0..dims {
        prop_assert!(
            points.column(d).iter().all(|&x| (0.0..1.0).contains(&x)),
            "dim {d} leaves [0, 1)"
        );
    }
    for dx in (0..dims).step_by(2) {
        let mut x_slabs = vec![0u32; size as usize];
        for &x in points.column(dx) {
            x_slabs[slab(x, size)] += 1;
        }
        all_once(&x_slabs, &format!("N-rooks in dim {dx}"))?;
        if dx + 1 == dims {
            continue;
        }
        let mut y_slabs = vec![0u32; size as usize];
        let mut cells = vec![0u32; size as usize];
        let mut sub_column_of_row = vec![None; n as usize];
        let mut sub_row_of_column = vec![None; m as usize];
        for (&x, &y) in points.column(dx).iter().zip(points.column(dx + 1)) {
            y_slabs[slab(y, size)] += 1;
            let (column, row) = (slab(x, m), slab(y, n));
            cells[column + m as usize * row] += 1;
            if correlated {
                let sub_column = slab(x, size) % n as usize;
                let sub_row = slab(y, size) % m as usize;
                prop_assert_eq!(
                    *sub_column_of_row[row].get_or_insert(sub_column),
                    sub_column
                );
                prop_assert_eq!(*sub_row_of_column[column].get_or_insert(sub_row), sub_row);
            }
        }
        all_once(&y_slabs, &format!("N-rooks in dim {}", dx + 1))?;
        all_once(
            &cells,
            &format!("{m} x {n} cells of dims ({dx}, {})", dx + 1),
        )?;
    }
    Ok(())
}

/// A sampler specification: variant, dims, m, n, seed.
fn any_spec() -> impl Strategy<Value = (bool, usize, u64, u64, u64)> {
    (any::<bool>(), 1usize..=5, 1u64..=7, 1u64..=7, any::<u64>())
}

proptest! {
    #![proptest_config(config(192, 20130101))]

    #[test]
    fn every_pass_is_jittered_and_n_rooks(
        (correlated, dims, m, n, seed) in any_spec(),
        pass_choice in 0u64..4,
    ) {
        let sampler = build(correlated, dims, m, n, seed);
        let size = pass_size(&*sampler);
        prop_assert_eq!(size, m * n);
        // Passes 0, 1, 2 and the last whole pass of the u64 index range.
        let pass = if pass_choice == 3 { u64::MAX / size - 1 } else { pass_choice };
        check_pass(&block(&*sampler, pass * size, size as usize), m, n, correlated)?;
    }

    #[test]
    fn point_and_fill_are_bit_identical(
        (correlated, dims, m, n, seed) in any_spec(),
        start in prop_oneof![0u64..200, (u64::MAX - 300)..=(u64::MAX - 100)],
        len in 0usize..100,
    ) {
        // Blocks of up to 100 points with passes of at most 49 cross pass boundaries.
        let sampler = build(correlated, dims, m, n, seed);
        let points = block(&*sampler, start, len);
        let mut p = vec![0.0; dims];
        for i in 0..len {
            sampler.point(start + i as u64, &mut p).unwrap();
            for (d, x) in p.iter().enumerate() {
                prop_assert_eq!(x.to_bits(), points.get(i, d).to_bits(), "point {} dim {}", i, d);
            }
        }
    }

    #[test]
    fn same_seed_same_points_reseed_and_passes_differ(
        (correlated, dims, m, n, seed) in any_spec(),
    ) {
        let mut sampler = build(correlated, dims, m, n, seed);
        let size = pass_size(&*sampler) as usize;
        let first = bits(&block(&*sampler, 0, size));
        prop_assert_eq!(&first, &bits(&block(&*build(correlated, dims, m, n, seed), 0, size)));
        prop_assert_ne!(&first, &bits(&block(&*sampler, size as u64, size)));
        sampler.reseed(seed ^ 1);
        prop_assert_eq!(sampler.seed(), seed ^ 1);
        prop_assert_ne!(&first, &bits(&block(&*sampler, 0, size)));
        prop_assert!(sampler.is_randomized());
    }
}

#[test]
fn names_and_pass_sizes() {
    let mj = MultiJittered::new(3, 4, 5, 1).unwrap();
    let cmj = CorrelatedMultiJittered::new(3, 4, 5, 1).unwrap();
    assert_eq!((mj.name(), cmj.name()), ("multijitter", "cmj"));
    assert_eq!(mj.passes(), PassKind::Fixed { size: 20 });
    assert_eq!(cmj.passes(), PassKind::Fixed { size: 20 });
    assert_eq!((mj.dims(), mj.m(), mj.n()), (3, 4, 5));
    assert_eq!((cmj.dims(), cmj.m(), cmj.n()), (3, 4, 5));
}

#[test]
fn with_points_chooses_the_squarest_grid() {
    for (points, m, n) in [
        (1, 1, 1),
        (7, 1, 7),
        (12, 3, 4),
        (16, 4, 4),
        (18, 3, 6),
        (97, 1, 97),
        (1000, 25, 40),
    ] {
        let mj = MultiJittered::with_points(2, points, 0).unwrap();
        let cmj = CorrelatedMultiJittered::with_points(2, points, 0).unwrap();
        assert_eq!((mj.m(), mj.n()), (m, n), "points = {points}");
        assert_eq!((cmj.m(), cmj.n()), (m, n), "points = {points}");
        assert_eq!(mj.passes(), PassKind::Fixed { size: points });
    }
}

/// Name and allowed-values text of an `InvalidParameter` error.
fn invalid(err: Error) -> (&'static str, String) {
    match err {
        Error::InvalidParameter { name, allowed, .. } => (name, allowed),
        other => panic!("expected InvalidParameter, got {other:?}"),
    }
}

#[test]
fn errors_name_the_parameter_and_what_is_allowed() {
    for correlated in [false, true] {
        let new = |dims, m, n| {
            if correlated {
                CorrelatedMultiJittered::new(dims, m, n, 0).map(|_| ())
            } else {
                MultiJittered::new(dims, m, n, 0).map(|_| ())
            }
        };
        let with_points = |dims, points| {
            if correlated {
                CorrelatedMultiJittered::with_points(dims, points, 0).map(|_| ())
            } else {
                MultiJittered::with_points(dims, points, 0).map(|_| ())
            }
        };
        assert_eq!(invalid(new(0, 2, 2).unwrap_err()).0, "dims");
        assert_eq!(invalid(with_points(0, 4).unwrap_err()).0, "dims");
        assert_eq!(invalid(new(2, 0, 2).unwrap_err()).0, "m");
        assert_eq!(invalid(new(2, 2, 0).unwrap_err()).0, "n");
        for (m, n) in [(u64::MAX, 2), (1 << 27, 1 << 27)] {
            let (name, allowed) = invalid(new(2, m, n).unwrap_err());
            assert_eq!(name, "m * n");
            assert!(allowed.contains("at most 2^53"), "{allowed}");
        }
        let (name, allowed) = invalid(with_points(2, 0).unwrap_err());
        assert_eq!(name, "points");
        assert!(allowed.contains("between 1 and 2^53"), "{allowed}");
        let (name, allowed) = invalid(with_points(2, u64::MAX).unwrap_err());
        assert_eq!(name, "points");
        assert!(allowed.contains("at most 2^53"), "{allowed}");
        // The largest allowed sizes are accepted (2^53 = 2^26 x 2^27).
        assert!(new(2, 1 << 26, 1 << 27).is_ok());
        assert!(with_points(2, 1 << 53).is_ok());
    }
    let s = MultiJittered::new(3, 2, 2, 0).unwrap();
    assert!(matches!(
        s.point(0, &mut [0.0; 2]),
        Err(Error::DimensionMismatch { .. })
    ));
    assert!(s.fill(0, &mut Points::new(2, 4).unwrap()).is_err());
}

/// `exp(x y)` over the unit square: the sum of `1 / (k! (k + 1)^2)`. With `scale = 2` this is
/// `E[exp(2 x y)]`, the second moment: the sum of `2^k / (k! (k + 1)^2)`.
fn exp_xy_moment(scale: f64) -> f64 {
    let mut term = 1.0; // scale^k / k!
    let mut sum = 0.0;
    for k in 0..40 {
        let kp1 = (k + 1) as f64;
        sum += term / (kp1 * kp1);
        term *= scale / kp1;
    }
    sum
}

/// Means over `passes` passes of the pass means of `f`, and the standard error of that mean
/// computed from the spread of the pass means.
fn pass_mean_stats(sampler: &dyn Sampler, passes: u64, f: impl Fn(&[f64]) -> f64) -> (f64, f64) {
    let size = pass_size(sampler);
    let mut points = Points::new(sampler.dims(), size as usize).unwrap();
    let mut p = vec![0.0; sampler.dims()];
    let (mut sum, mut sum_sq) = (0.0, 0.0);
    for pass in 0..passes {
        sampler.fill(pass * size, &mut points).unwrap();
        let mut total = 0.0;
        for i in 0..size as usize {
            points.copy_point(i, &mut p);
            total += f(&p);
        }
        let mean = total / size as f64;
        sum += mean;
        sum_sq += mean * mean;
    }
    let k = passes as f64;
    let mean = sum / k;
    let var = (sum_sq - k * mean * mean) / (k - 1.0);
    (mean, (var / k).sqrt())
}

#[test]
fn pass_means_are_unbiased_for_a_non_separable_integrand() {
    let exact = exp_xy_moment(1.0);
    // 1.3179021514544038... (the series converges to machine precision in 20 terms).
    assert!((exact - 1.317_902_151_454_404).abs() < 1e-14);
    for correlated in [false, true] {
        for (dims, m, n, seed) in [(2, 3, 5, 11), (2, 4, 4, 12), (5, 2, 3, 13)] {
            let sampler = build(correlated, dims, m, n, seed);
            // exp(x_a x_b) for each pair (a, b): within the first pair; for 5 dims also within
            // the second pair, across pairs, and the odd dimension with a pair.
            let pairs: &[(usize, usize)] = if dims == 5 {
                &[(0, 1), (2, 3), (1, 2), (4, 0)]
            } else {
                &[(0, 1)]
            };
            for &(a, b) in pairs {
                let (mean, se) = pass_mean_stats(&*sampler, 4000, |p| (p[a] * p[b]).exp());
                assert!(
                    (mean - exact).abs() < 4.5 * se,
                    "{} {m}x{n} dims {dims} exp(x{a} x{b}): mean {mean}, exact {exact}, se {se}",
                    sampler.name()
                );
            }
        }
    }
}

#[test]
fn single_points_are_jointly_uniform_over_passes() {
    // One point per pass (a fixed number within the pass) binned on a 4 x 4 grid: passes are
    // independent, so the counts are multinomial and the chi-square statistic has 15 degrees
    // of freedom. Bound: scipy.stats.chi2.isf(1e-5, 15) = 50.49.
    const BOUND: f64 = 50.49;
    let passes = 16_000u64;
    for correlated in [false, true] {
        for (dims, m, n, local, pair) in [(2, 3, 5, 0, 0), (2, 4, 4, 9, 0), (5, 2, 6, 5, 1)] {
            let sampler = build(correlated, dims, m, n, 77);
            let size = pass_size(&*sampler);
            let mut counts = [0f64; 16];
            let mut p = vec![0.0; dims];
            for pass in 0..passes {
                sampler.point(pass * size + local, &mut p).unwrap();
                let (x, y) = (p[2 * pair], p[2 * pair + 1]);
                counts[slab(x, 4) + 4 * slab(y, 4)] += 1.0;
            }
            let expected = passes as f64 / 16.0;
            let chi2: f64 = counts
                .iter()
                .map(|c| (c - expected).powi(2) / expected)
                .sum();
            assert!(
                chi2 < BOUND,
                "{} {m}x{n} point {local} pair {pair}: chi2 = {chi2}",
                sampler.name()
            );
        }
    }
}

#[test]
fn pass_mean_variance_is_far_below_independent_sampling() {
    // Independent sampling of f = exp(x y) with N points has Var(mean) = sigma^2 / N, with
    // sigma^2 = E[exp(2 x y)] - I^2 = 0.1051 from the series; here m = n = 8, N = 64.
    //
    // Multi-jittered: with independent positions inside the cells, stratification on the
    // m x n grid leaves Var(mean) ~ (1/N) E[f_x^2 / m^2 + f_y^2 / n^2] / 12 for a smooth f (a
    // linear function over a uniform cell); E[f_x^2] = E[y^2 exp(2 x y)] =
    // sum 2^k / (k! (k + 1) (k + 3)) = 0.799, so 1.597 / (768 * 0.1051) = 2.0% of sigma^2 / N.
    // MJ's sub-column (sub-row) indices form a permutation within each column (row), which
    // cancels the linear term further, so it sits below that.
    //
    // Correlated multi-jittered shares one sub-column offset across the m cells of each row
    // (and one sub-row offset across each column), so the linear term cancels only up to the
    // variation of h(y) = integral of f_x over x = e^y - 1 between rows. Linearizing, with a
    // random permutation of the offsets a_k = (k + 1/2 - n/2) / N, k < n, the x part has
    // variance (n + 1) Var(e^y) / (12 N^2): with Var(e^y) = (e^2 - 1)/2 - (e - 1)^2 = 0.242
    // and the same for y, 2 * 9 * 0.242 / (768 * 0.1051) = 5.4% of sigma^2 / N.
    //
    // Asserting below 10% for both leaves a margin of 1.85x over the larger prediction, which
    // covers the neglected second-order terms (relative size about 1/m) and the sampling error
    // of the variance estimate (relative SE sqrt(2 / 2000) = 3%, so 4.5 SE is 14%).
    let exact = exp_xy_moment(1.0);
    let sigma2 = exp_xy_moment(2.0) - exact * exact;
    let (m, n) = (8u64, 8u64);
    let passes = 2000u64;
    let independent_var = sigma2 / (m * n) as f64;
    for correlated in [false, true] {
        let sampler = build(correlated, 2, m, n, 5);
        let (_, se) = pass_mean_stats(&*sampler, passes, |p| (p[0] * p[1]).exp());
        let var = se * se * passes as f64;
        let ratio = var / independent_var;
        assert!(
            ratio < 0.1,
            "{}: Var(pass mean) = {var:e} is {ratio:.4} of sigma^2/N = {independent_var:e}",
            sampler.name()
        );
    }
}
