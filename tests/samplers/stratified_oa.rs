//! Orthogonal-array sampling (Owen 1992; Tang 1993; Jarosz et al. 2019): the stratification
//! every pass must have, exactly; unbiasedness and the variance reduction for integrands made
//! of main effects and two-factor interactions, statistically; and the error messages.
//!
//! Statistical tolerances are 4.5 standard errors or a 1 - 1e-5 chi-square quantile, so each
//! check has a false-alarm probability below about 1e-5; every seed is fixed.

use crate::common::config;
use mcint::Points;
use mcint::sampler::{OaOffset, OrthogonalArray, PassKind, Sampler};
use proptest::prelude::*;

fn pass_size(s: &impl Sampler) -> u64 {
    match s.passes() {
        PassKind::Fixed { size } => size,
        other => panic!("expected fixed passes, got {other:?}"),
    }
}

/// All points of pass `pass`, filled as one block.
fn whole_pass(s: &impl Sampler, pass: u64) -> Points {
    let n = pass_size(s);
    let mut block = Points::new(s.dims(), n as usize).unwrap();
    s.fill(pass * n, &mut block).unwrap();
    block
}

/// All subsets of `0..dims` with `t` elements, as sorted index lists.
fn subsets(dims: usize, t: usize) -> Vec<Vec<usize>> {
    (0..1u32 << dims)
        .filter(|m| m.count_ones() as usize == t)
        .map(|m| (0..dims).filter(|&c| m >> c & 1 == 1).collect())
        .collect()
}

/// A construction to test: Bose (`t = 2`) or Bush of strength `t`, prime `p`, and `dims`.
#[derive(Debug, Clone, Copy)]
struct Case {
    bose: bool,
    p: u64,
    t: u32,
    dims: usize,
}

impl Case {
    fn build(self, offset: OaOffset, seed: u64) -> OrthogonalArray {
        if self.bose {
            OrthogonalArray::bose(self.dims, self.p, offset, seed).unwrap()
        } else {
            OrthogonalArray::bush(self.dims, self.p, self.t, offset, seed).unwrap()
        }
    }
}

/// Bose for p = 2 .. 11 and Bush of strengths 2, 3, 4, with `t <= dims <=` the largest
/// number of columns the construction allows.
fn cases() -> impl Strategy<Value = Case> {
    let shapes: Vec<(bool, u64, u32)> = vec![
        (true, 2, 2),
        (true, 3, 2),
        (true, 5, 2),
        (true, 7, 2),
        (true, 11, 2),
        (false, 2, 2),
        (false, 5, 2),
        (false, 7, 2),
        (false, 3, 3),
        (false, 5, 3),
        (false, 7, 3),
        (false, 5, 4),
        (false, 7, 4),
    ];
    prop::sample::select(shapes).prop_flat_map(|(bose, p, t)| {
        // Bose allows p + 1 columns; Bush p + 1 when t <= p (true for every shape above).
        let most = p as usize + 1;
        (t as usize..=most).prop_map(move |dims| Case { bose, p, t, dims })
    })
}

fn offsets() -> impl Strategy<Value = OaOffset> {
    prop::sample::select(OaOffset::ALL.to_vec())
}

/// Cell of `x` among `cells` equal intervals of `[0, 1)`.
fn cell(x: f64, cells: u64) -> u64 {
    ((x * cells as f64) as u64).min(cells - 1)
}

proptest! {
    #![proptest_config(config(48, 0x0a5a_3971))]

    /// The defining property: in every t-dimensional projection of a pass each of the p^t
    /// cells holds exactly one point.
    #[test]
    fn every_t_projection_has_one_point_per_cell(
        case in cases(),
        offset in offsets(),
        seed in any::<u64>(),
        pass in prop::sample::select(vec![0u64, 3]),
    ) {
        let s = case.build(offset, seed);
        let n = pass_size(&s);
        prop_assert_eq!(n, case.p.pow(case.t));
        let block = whole_pass(&s, pass);
        for subset in subsets(case.dims, case.t as usize) {
            let mut counts = vec![0u32; n as usize];
            for i in 0..n as usize {
                let index = subset
                    .iter()
                    .fold(0u64, |acc, &d| acc * case.p + cell(block.get(i, d), case.p));
                counts[index as usize] += 1;
            }
            prop_assert!(counts.iter().all(|&c| c == 1), "{:?}: dims {:?}", case, subset);
        }
    }

    /// Multi-jittered offsets make every one-dimensional projection a Latin hypercube of N
    /// strata (Tang 1993); all offsets keep coordinates in [0, 1).
    #[test]
    fn multi_jittered_offsets_are_latin_and_all_points_lie_in_the_cube(
        case in cases(),
        offset in offsets(),
        seed in any::<u64>(),
        pass in prop::sample::select(vec![0u64, 3]),
    ) {
        let s = case.build(offset, seed);
        let n = pass_size(&s);
        let block = whole_pass(&s, pass);
        for d in 0..case.dims {
            prop_assert!(block.column(d).iter().all(|x| (0.0..1.0).contains(x)));
            if matches!(offset, OaOffset::MultiJittered | OaOffset::CorrelatedMultiJittered) {
                let mut counts = vec![0u32; n as usize];
                for &x in block.column(d) {
                    counts[cell(x, n) as usize] += 1;
                }
                prop_assert!(counts.iter().all(|&c| c == 1), "{:?}: dim {}", case, d);
            }
        }
    }

    /// `point` and `fill` agree to the bit, for blocks that may straddle passes.
    #[test]
    fn point_and_fill_are_bit_identical(
        case in cases(),
        offset in offsets(),
        seed in any::<u64>(),
        start in 0u64..5000,
        len in 0usize..300,
    ) {
        let s = case.build(offset, seed);
        let mut block = Points::new(case.dims, len).unwrap();
        s.fill(start, &mut block).unwrap();
        let mut p = vec![0.0; case.dims];
        for i in 0..len {
            s.point(start + i as u64, &mut p).unwrap();
            for (d, &x) in p.iter().enumerate() {
                prop_assert_eq!(x.to_bits(), block.get(i, d).to_bits());
            }
        }
    }
}

#[test]
fn reseeding_and_passes_give_different_points() {
    for offset in OaOffset::ALL {
        let mut s = OrthogonalArray::bush(4, 5, 3, offset, 1).unwrap();
        let first = whole_pass(&s, 0);
        assert_ne!(first, whole_pass(&s, 1), "{offset}: passes 0 and 1 agree");
        assert_eq!(first, whole_pass(&s, 0), "{offset}: not deterministic");
        s.reseed(2);
        assert_eq!(s.seed(), 2);
        assert_ne!(first, whole_pass(&s, 0), "{offset}: reseed changed nothing");
    }
}

#[test]
fn out_of_range_buffers_are_errors_not_panics() {
    let s = OrthogonalArray::bose(3, 5, OaOffset::Jittered, 0).unwrap();
    assert!(s.point(0, &mut [0.0; 2]).is_err());
    assert!(s.fill(0, &mut Points::new(2, 4).unwrap()).is_err());
    assert!(s.fill(u64::MAX, &mut Points::new(3, 2).unwrap()).is_err());
    let mut p = [0.0; 3];
    s.point(u64::MAX, &mut p).unwrap();
    assert!(p.iter().all(|x| (0.0..1.0).contains(x)));
}

/// Mean and sample variance of the pass means of `f` over `passes` passes.
fn pass_means(s: &impl Sampler, f: impl Fn(&[f64]) -> f64, passes: u64) -> (f64, f64) {
    let mut point = vec![0.0; s.dims()];
    let means: Vec<f64> = (0..passes)
        .map(|pass| {
            let block = whole_pass(s, pass);
            let sum: f64 = (0..block.len())
                .map(|i| {
                    block.copy_point(i, &mut point);
                    f(&point)
                })
                .sum();
            sum / block.len() as f64
        })
        .collect();
    let mean = means.iter().sum::<f64>() / passes as f64;
    let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (passes - 1) as f64;
    (mean, var)
}

/// Frequencies of the non-separable integrand `cos(a . x)`.
const FREQ: [f64; 4] = [1.0, 2.0, 3.0, 1.5];

/// Its exact integral over the unit cube: the real part of `prod_j (e^{i a_j} - 1) / (i a_j)`.
fn cosine_integral() -> f64 {
    let (mut re, mut im) = (1.0, 0.0);
    for a in FREQ {
        // (e^{ia} - 1) / (ia) = (sin a + i (1 - cos a)) / a.
        let (fr, fi) = (a.sin() / a, (1.0 - a.cos()) / a);
        (re, im) = (re * fr - im * fi, re * fi + im * fr);
    }
    re
}

#[test]
fn randomized_offsets_are_unbiased_for_a_non_separable_integrand() {
    // Each point is uniform on the cube (independent uniform symbol permutations per column,
    // uniform sub-strata and jitter), so the pass mean is unbiased. Centered offsets are not.
    let exact = cosine_integral();
    let f = |x: &[f64]| FREQ.iter().zip(x).map(|(a, x)| a * x).sum::<f64>().cos();
    let passes = 1000;
    for offset in [
        OaOffset::Jittered,
        OaOffset::MultiJittered,
        OaOffset::CorrelatedMultiJittered,
    ] {
        for s in [
            OrthogonalArray::bose(4, 7, offset, 11).unwrap(),
            OrthogonalArray::bush(4, 5, 3, offset, 12).unwrap(),
        ] {
            let (mean, var) = pass_means(&s, f, passes);
            let se = (var / passes as f64).sqrt();
            assert!(
                (mean - exact).abs() <= 4.5 * se,
                "{} {offset}: mean {mean}, exact {exact}, se {se}",
                s.name()
            );
        }
    }
}

/// Upper 1 - 1e-5 quantile of chi-square with `k` degrees of freedom divided by `k`
/// (Wilson-Hilferty; z = 4.265 is the standard normal 1 - 1e-5 quantile).
fn chi2_upper_ratio(k: f64) -> f64 {
    let c = 2.0 / (9.0 * k);
    (1.0 - c + 4.265 * c.sqrt()).powi(3)
}

/// `f = sum_j x_j + sum_{j<k} (x_j - 1/2)(x_k - 1/2)` in 4 dimensions: main effects and
/// two-factor interactions only, integral 2.
fn additive_plus_pairwise(x: &[f64]) -> f64 {
    let mut f = 0.0;
    for j in 0..x.len() {
        f += x[j];
        for k in j + 1..x.len() {
            f += (x[j] - 0.5) * (x[k] - 0.5);
        }
    }
    f
}

#[test]
fn strength_two_removes_main_effects_and_two_factor_interactions() {
    // Reasoning (jittered offsets, Owen 1992). Given the symbol permutations, each point is
    // uniform in its own cell of side 1/p, independently of the others. The conditional mean
    // of the pass mean is the average of the cell means; since each column is balanced
    // (every 1/p slab holds N/p points) and each pair of columns is a full p x p grid, the
    // cell means of every main effect and two-factor interaction average to their exact
    // integrals, so that conditional mean is the integral for every permutation. Hence
    // Var(mean) = E[Var(mean | permutations)] = (1/N^2) sum_i Var(f on cell i), and by the
    // Efron-Stein inequality with Var(h(U)) <= L^2 w^2 / 12 for an L-Lipschitz h of a uniform
    // on an interval of width w, Var(f on a cell) <= sum_d L_d^2 / (12 p^2). Here
    // |df/dx_d| <= 1 + 3/2 = L_d, so Var(mean) <= 4 L_d^2 / (12 p^2 N) = O(N^-2), while
    // independent sampling has sigma^2 / N with sigma^2 = 4/12 + 6/144 (orthogonal ANOVA terms).
    //
    // Multi-jittered offsets only move each point to a random 1/N sub-slab of the same cell,
    // uniformly given the permutations, so the same conditional-mean argument holds; their
    // within-cell placement is sampling without replacement of sub-slabs, which Tang (1993)
    // shows leaves the leading-order variance unchanged while stratifying main effects
    // further. We test them against the same bound (no proof of it for them is claimed).
    let (p, dims) = (11u64, 4usize);
    let n = (p * p) as f64;
    let lipschitz: f64 = 1.0 + (dims - 1) as f64 / 2.0;
    let bound = dims as f64 * lipschitz.powi(2) / (12.0 * (p * p) as f64 * n);
    let sigma2 = dims as f64 / 12.0 + (dims * (dims - 1) / 2) as f64 / 144.0;
    assert!(
        bound < sigma2 / n / 20.0,
        "bound {bound} vs sigma^2/N {}",
        sigma2 / n
    );
    let passes = 1000u64;
    let tolerance = bound * chi2_upper_ratio((passes - 1) as f64);
    for offset in [
        OaOffset::Jittered,
        OaOffset::MultiJittered,
        OaOffset::CorrelatedMultiJittered,
    ] {
        let s = OrthogonalArray::bose(dims, p, offset, 21).unwrap();
        let (_, var) = pass_means(&s, additive_plus_pairwise, passes);
        assert!(
            var <= tolerance,
            "{offset}: variance of pass mean {var} above {tolerance} (sigma^2/N = {})",
            sigma2 / n
        );
    }
    // Centered offsets put every pair of coordinates on the p x p midpoint grid whatever the
    // permutations, so the pass mean is the same in every pass: here exactly the integral,
    // since the midpoint rule integrates these (bi)linear terms exactly.
    let s = OrthogonalArray::bose(dims, p, OaOffset::Centered, 21).unwrap();
    let (mean, var) = pass_means(&s, additive_plus_pairwise, 50);
    assert!((mean - 2.0).abs() < 1e-12 && var < 1e-24, "{mean} {var}");
}

fn message(result: mcint::Result<OrthogonalArray>) -> String {
    result.unwrap_err().to_string()
}

#[test]
fn with_points_builds_the_matching_construction() {
    let s = OrthogonalArray::with_points(4, 121, 2, OaOffset::Jittered, 0).unwrap();
    assert_eq!((s.name(), s.prime(), s.strength()), ("oa-bose", 11, 2));
    let s = OrthogonalArray::with_points(6, 125, 3, OaOffset::Jittered, 0).unwrap();
    assert_eq!((s.name(), s.prime(), s.strength()), ("oa-bush", 5, 3));
    let s = OrthogonalArray::with_points(3, 3, 2, OaOffset::Jittered, 0);
    assert!(s.is_err());
    let s = OrthogonalArray::with_points(3, 7, 1, OaOffset::MultiJittered, 0).unwrap();
    assert_eq!(pass_size(&s), 7);
}

#[test]
fn with_points_errors_name_the_nearest_valid_sizes() {
    let m = |dims, points, t| {
        message(OrthogonalArray::with_points(
            dims,
            points,
            t,
            OaOffset::Jittered,
            0,
        ))
    };
    assert_eq!(
        m(4, 50, 2),
        "invalid points = 50: expected p^2 for a prime p >= 3 (nearest valid: 49 or 121)"
    );
    // 36 = 6^2 is a square, but 6 is not prime.
    assert_eq!(
        m(2, 36, 2),
        "invalid points = 36: expected p^2 for a prime p >= 2 (nearest valid: 25 or 49)"
    );
    assert_eq!(
        m(3, 100, 3),
        "invalid points = 100: expected p^3 for a prime p >= 3 (nearest valid: 27 or 125)"
    );
    // 8 dims need p + 1 >= 8; nothing below.
    assert_eq!(
        m(8, 9, 2),
        "invalid points = 9: expected p^2 for a prime p >= 7 (nearest valid: 49)"
    );
    // 8 = 2^3, but strength 3 > p = 2 allows only 2 columns.
    assert_eq!(
        m(3, 8, 3),
        "invalid points = 8: expected p^3 for a prime p >= 3 (nearest valid: 27)"
    );
    // 125 = 5^3 fits 6 dims but not 7.
    assert_eq!(
        m(7, 125, 3),
        "invalid points = 125: expected p^3 for a prime p >= 7 (nearest valid: 343)"
    );
    // Nothing valid above 2^64 for strength 2: only the size below is named.
    assert_eq!(
        m(2, u64::MAX, 2),
        format!(
            "invalid points = {}: expected p^2 for a prime p >= 2 (nearest valid: {})",
            u64::MAX,
            4_294_967_291u64 * 4_294_967_291
        )
    );
    assert!(m(2, 49, 0).contains("strength = 0"));
    assert!(m(0, 49, 2).contains("dims = 0"));
}

#[test]
fn bad_primes_and_too_many_dims_name_the_limit() {
    let j = OaOffset::Jittered;
    assert_eq!(
        message(OrthogonalArray::bose(2, 6, j, 0)),
        "invalid p = 6: expected a prime >= 2 (nearest primes: 5 or 7)"
    );
    assert_eq!(
        message(OrthogonalArray::bush(2, 1, 2, j, 0)),
        "invalid p = 1: expected a prime >= 2 (nearest primes: 2)"
    );
    assert!(message(OrthogonalArray::bose(2, 0, j, 0)).contains("p = 0"));
    assert_eq!(
        message(OrthogonalArray::bose(7, 5, j, 0)),
        "invalid dims = 7: expected at most p + 1 = 6 for the Bose construction with p = 5"
    );
    assert_eq!(
        message(OrthogonalArray::bush(5, 3, 3, j, 0)),
        "invalid dims = 5: expected at most p + 1 = 4 for the Bush construction with p = 3 \
         and strength 3"
    );
    assert_eq!(
        message(OrthogonalArray::bush(4, 3, 4, j, 0)),
        "invalid dims = 4: expected at most p = 3 (p + 1 only when strength <= p) for the \
         Bush construction with p = 3 and strength 4"
    );
    assert_eq!(
        message(OrthogonalArray::bush(2, 3, 41, j, 0)),
        "invalid strength = 41: expected at most 40 for p = 3 (p^strength must fit in 64 bits)"
    );
    assert!(message(OrthogonalArray::bush(2, 3, 0, j, 0)).contains("strength = 0"));
    assert!(message(OrthogonalArray::bose(0, 3, j, 0)).contains("dims = 0"));
    assert!(message(OrthogonalArray::bose(2, 4_294_967_311, j, 0)).contains("square"));
}

#[test]
fn offset_names_round_trip() {
    for offset in OaOffset::ALL {
        assert_eq!(offset.name().parse::<OaOffset>().unwrap(), offset);
        assert_eq!(offset.to_string(), offset.name());
    }
    let names: Vec<&str> = OaOffset::ALL.iter().map(|o| o.name()).collect();
    assert_eq!(names, ["centered", "jittered", "multi-jittered", "cmj"]);
    assert!(
        "mj".parse::<OaOffset>()
            .unwrap_err()
            .to_string()
            .contains("centered, jittered, multi-jittered, cmj")
    );
}
