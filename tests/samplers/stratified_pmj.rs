//! Integration tests for the pmj02 and multi-stage N-rooks samplers: the stratification each
//! construction promises (every power-of-two prefix of pmj02 a (0, m, 2)-net; every stage of
//! multi-stage N-rooks a Latin hypercube), the `Sampler` contract (`point` and `fill`
//! bit-identical, coordinates in `[0, 1)`), unbiasedness over passes, variance reduction, and
//! the error cases.
//!
//! Statistical checks use 4.5 standard errors (two-sided p about 7e-6) with fixed seeds, so a
//! correct sampler fails none of them in practice and runs are reproducible.

use crate::common::{bits, block, config};
use mcint::sampler::{MultiStageNRooks, PassKind, Pmj02, Sampler};
use mcint::{Error, Points};
use proptest::prelude::*;

/// Whether `x, y` (of equal length 2^m) form a (0, m, 2)-net in base 2: for every shape
/// `2^-k x 2^-(m-k)` each elementary interval holds exactly one point.
fn is_net(x: &[f64], y: &[f64], m: u32) -> bool {
    assert_eq!(x.len(), 1 << m);
    (0..=m).all(|k| {
        let mut seen = vec![false; 1 << m];
        x.iter().zip(y).all(|(&a, &b)| {
            let cell = ((a * (1u64 << k) as f64) as usize) << (m - k)
                | (b * (1u64 << (m - k)) as f64) as usize;
            !std::mem::replace(&mut seen[cell], true)
        })
    })
}

/// Whether the values have exactly one in each of `slabs` equal slabs of `[0, 1)`.
fn one_per_slab(values: &[f64], slabs: u64) -> bool {
    let mut seen = vec![false; slabs as usize];
    values.len() as u64 == slabs
        && values.iter().all(|&v| {
            let s = (v * slabs as f64) as usize;
            s < seen.len() && !std::mem::replace(&mut seen[s], true)
        })
}

/// `prod_j exp(x_j)`, whose integral over `[0, 1)^d` is `(e - 1)^d`.
fn exp_product(point: &[f64]) -> f64 {
    point.iter().map(|x| x.exp()).product()
}

/// Per-pass means of `f` over `passes` passes of `size` points starting at pass 0.
fn pass_means(sampler: &dyn Sampler, size: usize, passes: u64, f: fn(&[f64]) -> f64) -> Vec<f64> {
    let stride = match sampler.passes() {
        PassKind::Fixed { size } | PassKind::Extensible { max: size } => size,
        PassKind::Independent => size as u64,
    };
    let mut p = vec![0.0; sampler.dims()];
    (0..passes)
        .map(|pass| {
            let points = block(sampler, pass * stride, size);
            (0..size)
                .map(|i| {
                    points.copy_point(i, &mut p);
                    f(&p)
                })
                .sum::<f64>()
                / size as f64
        })
        .collect()
}

/// Checks that the mean of the pass means is within 4.5 standard errors of `exact`.
fn assert_unbiased(means: &[f64], exact: f64) {
    let n = means.len() as f64;
    let mean = means.iter().sum::<f64>() / n;
    let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let se = (var / n).sqrt();
    assert!(se > 0.0, "passes do not differ");
    assert!(
        (mean - exact).abs() < 4.5 * se,
        "mean {mean}, exact {exact}, se {se}"
    );
}

/// Root mean square error of the pass means about `exact`.
fn rmse(means: &[f64], exact: f64) -> f64 {
    (means.iter().map(|m| (m - exact).powi(2)).sum::<f64>() / means.len() as f64).sqrt()
}

/// Standard deviation of `prod_j exp(x_j)` under uniform sampling in `d` dimensions.
fn exp_product_sd(d: i32) -> f64 {
    let e = std::f64::consts::E;
    (((e * e - 1.0) / 2.0).powi(d) - (e - 1.0).powi(2 * d)).sqrt()
}

proptest! {
    #![proptest_config(config(6, 0x706d_6a30))]

    #[test]
    fn pmj02_power_of_two_prefixes_are_0_m_2_nets(seed in any::<u64>()) {
        // Negative control: a diagonal is N-rooks but not a net.
    {
        let s = Pmj02::new(1, seed).unwrap();
        let x = block(&s, 0, 16);
        prop_assert!(!is_net(x.column(0), x.column(0), 4));
    }
    // Dims (0, 1) are the pmj02 pair, (2, 3) a second pair read at scrambled indices,
        // and dim 4 the odd last dimension.
        let s = Pmj02::new(5, seed).unwrap();
        for pass in [0u64, 2] {
            let points = block(&s, pass << 16, 1 << 12);
            for m in 0..=12u32 {
                let n = 1usize << m;
                let col = |d: usize| &points.column(d)[..n];
                prop_assert!(is_net(col(0), col(1), m), "pass {pass}, pair 0, m {m}");
                prop_assert!(is_net(col(2), col(3), m), "pass {pass}, pair 1, m {m}");
                prop_assert!(one_per_slab(col(4), n as u64), "pass {pass}, dim 4, m {m}");
            }
        }
    }

    #[test]
    fn pmj02_every_aligned_block_is_a_net(seed in any::<u64>(), log2 in 4u32..=10) {
        let s = Pmj02::with_max_points(2, log2, seed).unwrap();
        let points = block(&s, 0, 1 << log2);
        for m in 0..=log2 {
            let n = 1usize << m;
            for start in (0..points.len()).step_by(n) {
                let (x, y) = (points.column(0), points.column(1));
                prop_assert!(is_net(&x[start..start + n], &y[start..start + n], m));
            }
        }
    }

    #[test]
    fn pmj02_point_and_fill_are_bit_identical(
        seed in any::<u64>(),
        dims in 1usize..=5,
        log2 in 0u32..=5,
        pass in 0u64..1_000_000,
    ) {
        let s = Pmj02::with_max_points(dims, log2, seed).unwrap();
        // A block that starts before a pass boundary and spans two more.
        let size = 1u64 << log2;
        let start = (pass * size).saturating_sub(3);
        let len = (2 * size + 5) as usize;
        let points = block(&s, start, len);
        let mut p = vec![0.0; dims];
        for i in 0..len {
            s.point(start + i as u64, &mut p).unwrap();
            for (d, x) in p.iter().enumerate() {
                prop_assert_eq!(x.to_bits(), points.get(i, d).to_bits());
            }
        }
    }

    #[test]
    fn pmj02_coordinates_lie_in_the_half_open_unit_interval(
        seed in any::<u64>(),
        start in prop_oneof![Just(u64::MAX - 63), any::<u64>().prop_map(|s| s / 2)],
        log2 in 0u32..=20,
    ) {
        let s = Pmj02::with_max_points(3, log2, seed).unwrap();
        let points = block(&s, start, 64);
        for d in 0..3 {
            prop_assert!(points.column(d).iter().all(|x| (0.0..1.0).contains(x)));
        }
    }

    #[test]
    fn multistage_every_stage_is_n_rooks(
        seed in any::<u64>(),
        base in 2u64..=6,
        stages in 1u32..=4,
        dims in 1usize..=3,
        pass in 0u64..5,
    ) {
        let s = MultiStageNRooks::with_stages(dims, base, stages, seed).unwrap();
        let size = base.pow(stages);
        let points = block(&s, pass * size, size as usize);
        for stage in 0..=stages {
            let block_len = base.pow(stages - stage);
            for d in 0..dims {
                for chunk in points.column(d).chunks(block_len as usize) {
                    prop_assert!(
                        one_per_slab(chunk, block_len),
                        "base {base}, stages {stages}, stage {stage}, dim {d}"
                    );
                }
            }
        }
        for d in 0..dims {
            prop_assert!(points.column(d).iter().all(|x| (0.0..1.0).contains(x)));
        }
    }

    #[test]
    fn multistage_point_and_fill_are_bit_identical(
        seed in any::<u64>(),
        points in prop_oneof![Just(4u64), Just(8), Just(9), Just(27), Just(169)],
        dims in 1usize..=4,
        pass in 0u64..1_000_000,
    ) {
        let s = MultiStageNRooks::new(dims, points, seed).unwrap();
        let start = (pass * points).saturating_sub(2);
        let len = (2 * points + 3) as usize;
        let block = block(&s, start, len);
        let mut p = vec![0.0; dims];
        for i in 0..len {
            s.point(start + i as u64, &mut p).unwrap();
            for (d, x) in p.iter().enumerate() {
                prop_assert_eq!(x.to_bits(), block.get(i, d).to_bits());
            }
        }
    }
}

#[test]
fn pmj02_identity_and_passes() {
    let mut s = Pmj02::with_max_points(4, 10, 1).unwrap();
    assert_eq!(s.name(), "pmj02");
    assert_eq!(s.dims(), 4);
    assert_eq!(s.passes(), PassKind::Extensible { max: 1024 });
    assert!(s.is_randomized());
    let before = bits(&block(&s, 0, 16));
    assert_eq!(before, bits(&block(&s, 0, 16)), "same seed, same points");
    assert_ne!(before, bits(&block(&s, 1024, 16)), "passes differ");
    s.reseed(2);
    assert_eq!(s.seed(), 2);
    assert_ne!(before, bits(&block(&s, 0, 16)), "reseed changes the points");
}

#[test]
fn pmj02_rejects_log2_max_above_20_and_zero_dims() {
    let err = Pmj02::with_max_points(2, 21, 0).unwrap_err();
    assert!(matches!(
        err,
        Error::InvalidParameter {
            name: "log2_max",
            ..
        }
    ));
    assert!(err.to_string().contains("0..=20"), "{err}");
    assert!(Pmj02::with_max_points(2, 20, 0).is_ok());
    assert!(Pmj02::new(0, 0).is_err());
    let s = Pmj02::new(2, 0).unwrap();
    assert!(s.point(0, &mut [0.0; 3]).is_err());
    assert!(s.fill(0, &mut Points::new(3, 4).unwrap()).is_err());
}

#[test]
fn pmj02_is_unbiased_over_passes() {
    // 5 dimensions: both pairs and the odd dimension take part.
    let s = Pmj02::with_max_points(5, 12, 77).unwrap();
    let means = pass_means(&s, 64, 400, exp_product);
    assert_unbiased(&means, (std::f64::consts::E - 1.0).powi(5));
    // Prefixes that are not powers of two are unbiased too.
    let s = Pmj02::new(2, 78).unwrap();
    let means = pass_means(&s, 37, 400, exp_product);
    assert_unbiased(&means, (std::f64::consts::E - 1.0).powi(2));
}

#[test]
fn pmj02_rmse_is_far_below_independent_sampling() {
    // Independent sampling with N = 2^10 points has RMSE sd / sqrt(N). A scrambled (0, m, 2)
    // net has variance at most e * sd^2 / N for any integrand (Owen 1997), and O(N^-3 log N)
    // for smooth ones: relative to independent sampling the variance falls like N^-2 log N
    // (about 1e-5 at N = 2^10, up to a constant of order one for this integrand), so an RMSE
    // 30 times below independent sampling (variance ratio 1.1e-3) is a loose bound.
    let n = 1usize << 10;
    let s = Pmj02::new(2, 5).unwrap();
    let means = pass_means(&s, n, 64, exp_product);
    let error = rmse(&means, (std::f64::consts::E - 1.0).powi(2));
    let independent = exp_product_sd(2) / (n as f64).sqrt();
    eprintln!("pmj02 rmse {error:e}, independent {independent:e}");
    assert!(
        error < independent / 30.0,
        "pmj02 rmse {error}, independent {independent}"
    );
}

#[test]
fn multistage_identity_and_sizes() {
    let s = MultiStageNRooks::new(3, 16, 4).unwrap();
    assert_eq!(s.name(), "nrooks-multistage");
    assert_eq!((s.base(), s.stages()), (2, 4));
    assert_eq!(s.passes(), PassKind::Fixed { size: 16 });
    assert!(s.is_randomized());
    let s = MultiStageNRooks::new(1, 3u64.pow(10), 4).unwrap();
    assert_eq!((s.base(), s.stages()), (3, 10));
    let s = MultiStageNRooks::new(1, 36, 4).unwrap();
    assert_eq!((s.base(), s.stages()), (6, 2));
    let s = MultiStageNRooks::with_stages(1, 13, 1, 4).unwrap();
    assert_eq!(s.passes(), PassKind::Fixed { size: 13 });
    // Bases above 12 use the general permutation.
    let s = MultiStageNRooks::new(2, 169, 1).unwrap();
    let points = block(&s, 169, 169);
    for d in 0..2 {
        assert!(one_per_slab(points.column(d), 169));
        for chunk in points.column(d).chunks(13) {
            assert!(one_per_slab(chunk, 13));
        }
    }
}

#[test]
fn multistage_errors_name_the_valid_sizes() {
    let message = |points| {
        let err = MultiStageNRooks::new(2, points, 0).unwrap_err();
        assert!(matches!(
            err,
            Error::InvalidParameter { name: "points", .. }
        ));
        err.to_string()
    };
    assert!(
        message(20).contains("nearest valid: 16 or 25"),
        "{}",
        message(20)
    );
    assert!(message(0).contains("nearest valid: 4"), "{}", message(0));
    assert!(message(3).contains("nearest valid: 4"), "{}", message(3));
    assert!(
        message(33).contains("nearest valid: 32 or 36"),
        "{}",
        message(33)
    );
    assert!(message(u64::MAX).contains("2^53"), "{}", message(u64::MAX));
    assert!(MultiStageNRooks::new(0, 16, 0).is_err());
    for (base, stages) in [(0, 2), (1, 2), (2, 0), (2, 54), (u64::MAX, 2)] {
        assert!(MultiStageNRooks::with_stages(2, base, stages, 0).is_err());
    }
    let s = MultiStageNRooks::new(2, 16, 0).unwrap();
    assert!(s.point(0, &mut [0.0; 1]).is_err());
}

#[test]
fn multistage_is_unbiased_over_passes() {
    let s = MultiStageNRooks::new(3, 27, 11).unwrap();
    let means = pass_means(&s, 27, 2000, exp_product);
    assert_unbiased(&means, (std::f64::consts::E - 1.0).powi(3));
}

#[test]
fn multistage_reduces_variance_of_additive_integrands() {
    // For an additive integrand a Latin hypercube of N points removes all but O(N^-3) of the
    // variance (the within-slab part of each smooth term); independent sampling leaves sd^2 / N.
    // sum_j exp(x_j) in 3 dimensions: sd^2 = 3 ((e^2 - 1) / 2 - (e - 1)^2).
    let e = std::f64::consts::E;
    let n = 64usize;
    let f: fn(&[f64]) -> f64 = |p| p.iter().map(|x| x.exp()).sum();
    let s = MultiStageNRooks::new(3, n as u64, 3).unwrap();
    let means = pass_means(&s, n, 200, f);
    let error = rmse(&means, 3.0 * (e - 1.0));
    let independent = (3.0 * ((e * e - 1.0) / 2.0 - (e - 1.0).powi(2)) / n as f64).sqrt();
    eprintln!("multi-stage rmse {error:e}, independent {independent:e}");
    assert!(
        error < independent / 10.0,
        "multi-stage rmse {error}, independent {independent}"
    );
}
