//! Integration tests for the samplers: the `Sampler` contract (coordinates in `[0, 1)`,
//! `point` and `fill` bit-identical, determinism), the stratification each construction
//! promises (one point per jittered cell, one point per Latin-hypercube slab), unbiasedness
//! over passes, the variance reduction of stratification, and the error cases.
//!
//! Statistical thresholds are 1e-5 quantiles (or 4.5 standard errors, two-sided p about 7e-6)
//! with fixed seeds, so a correct sampler fails none of them in practice and a run is
//! reproducible bit for bit.

use crate::common::{bits, block, config};
use mcint::sampler::{
    Independent, Jittered, LatinHypercube, PassKind, Sampler, SamplerKind, build_sampler,
};
use mcint::{Error, Points};
use proptest::prelude::*;

/// Which sampler to build, with its pass parameter.
#[derive(Debug, Clone, Copy)]
enum Kind {
    Independent,
    /// Strata per axis `k`.
    Jittered(u64),
    /// Points per pass `N`.
    Latin(u64),
}

#[derive(Debug, Clone, Copy)]
struct Spec {
    kind: Kind,
    dims: usize,
    seed: u64,
}

impl Spec {
    fn build(self) -> Box<dyn Sampler> {
        match self.kind {
            Kind::Independent => Box::new(Independent::new(self.dims, self.seed).unwrap()),
            Kind::Jittered(k) => Box::new(Jittered::new(self.dims, k, self.seed).unwrap()),
            Kind::Latin(n) => Box::new(LatinHypercube::new(self.dims, n, self.seed).unwrap()),
        }
    }
}

/// Latin hypercube pass sizes: small ones, both sides of the switch from the swap-or-not
/// shuffle to the Feistel network at 2^16, and huge ones up to `u64::MAX`.
fn latin_sizes() -> impl Strategy<Value = u64> {
    prop_oneof![
        1u64..=100,
        65_530u64..=65_540,
        Just(1u64 << 40),
        1u64..=u64::MAX,
    ]
}

/// Strata per axis, kept small enough that a pass of `k^dims` points is cheap to check.
fn strata_for(dims: usize) -> u64 {
    match dims {
        1 => 64,
        2 => 16,
        3 | 4 => 5,
        _ => 3,
    }
}

/// Any of the three samplers in 1..=6 dimensions with any seed.
fn any_spec() -> impl Strategy<Value = Spec> {
    (1usize..=6, any::<u64>()).prop_flat_map(|(dims, seed)| {
        prop_oneof![
            Just(Kind::Independent),
            (1..=strata_for(dims)).prop_map(Kind::Jittered),
            latin_sizes().prop_map(Kind::Latin),
        ]
        .prop_map(move |kind| Spec { kind, dims, seed })
    })
}

/// Block starts: small, around `u64::MAX / 2`, and anywhere that leaves room for a block.
fn any_start() -> impl Strategy<Value = u64> {
    prop_oneof![
        0u64..1_000_000,
        (u64::MAX / 2 - 1_000_000)..=(u64::MAX / 2 + 1_000_000),
        0u64..=(u64::MAX - 10_000),
    ]
}

fn point(sampler: &dyn Sampler, index: u64) -> Vec<f64> {
    let mut p = vec![0.0; sampler.dims()];
    sampler.point(index, &mut p).unwrap();
    p
}

fn pass_size(sampler: &dyn Sampler) -> u64 {
    match sampler.passes() {
        PassKind::Fixed { size } | PassKind::Extensible { max: size } => size,
        PassKind::Independent => 1,
    }
}

/// The name of an `InvalidParameter` error (panics on any other error).
fn invalid_name(err: &Error) -> &'static str {
    match err {
        Error::InvalidParameter { name, .. } => name,
        other => panic!("expected InvalidParameter, got {other:?}"),
    }
}

proptest! {
    #![proptest_config(config(256, 12345))]

    #[test]
    fn coordinates_lie_in_the_half_open_unit_interval(
        spec in any_spec(),
        start in any_start(),
        len in 0usize..300,
    ) {
        let sampler = spec.build();
        let points = block(sampler.as_ref(), start, len);
        for d in 0..spec.dims {
            for (i, &x) in points.column(d).iter().enumerate() {
                prop_assert!((0.0..1.0).contains(&x), "point {} dim {d}: {x}", start + i as u64);
            }
        }
    }

    #[test]
    fn point_and_fill_are_bit_identical(
        spec in any_spec(),
        start in any_start(),
        len in 0usize..300,
        split in 0usize..300,
    ) {
        let sampler = spec.build();
        let points = block(sampler.as_ref(), start, len);
        for i in 0..len {
            let p = point(sampler.as_ref(), start + i as u64);
            for (d, x) in p.iter().enumerate() {
                prop_assert_eq!(x.to_bits(), points.get(i, d).to_bits(), "point {} dim {}", i, d);
            }
        }
        // Any split of the range into two blocks (as threads do) gives the same bits.
        let split = split.min(len);
        let first = block(sampler.as_ref(), start, split);
        let second = block(sampler.as_ref(), start + split as u64, len - split);
        for d in 0..spec.dims {
            let joined: Vec<u64> = first.column(d).iter().chain(second.column(d))
                .map(|x| x.to_bits()).collect();
            let whole: Vec<u64> = points.column(d).iter().map(|x| x.to_bits()).collect();
            prop_assert_eq!(joined, whole);
        }
    }

    #[test]
    fn blocks_straddling_a_pass_boundary_match_points(
        dims in 1usize..=4,
        seed in any::<u64>(),
        jittered in any::<bool>(),
        size in 1u64..=200,
        pass in prop_oneof![1u64..10, 1u64..(1u64 << 50)],
        before in 0u64..=200,
        len in 1usize..=450,
    ) {
        let sampler: Box<dyn Sampler> = if jittered {
            let k = size.min(strata_for(dims));
            Box::new(Jittered::new(dims, k, seed).unwrap())
        } else {
            Box::new(LatinHypercube::new(dims, size, seed).unwrap())
        };
        let size = pass_size(sampler.as_ref());
        // Start up to `before` points ahead of the boundary of pass `pass`, so that the block
        // covers the end of one pass and the start of the next (and sometimes several passes).
        let start = (pass * size).saturating_sub(before.min(size));
        let points = block(sampler.as_ref(), start, len);
        for i in 0..len {
            let p = point(sampler.as_ref(), start + i as u64);
            for (d, x) in p.iter().enumerate() {
                prop_assert_eq!(x.to_bits(), points.get(i, d).to_bits());
            }
        }
    }

    #[test]
    fn same_seed_same_points_and_reseed_changes_them(
        spec in any_spec(),
        other in any::<u64>(),
        start in any_start(),
    ) {
        prop_assume!(other != spec.seed);
        let a = spec.build();
        let mut b = spec.build();
        prop_assert_eq!(a.seed(), spec.seed);
        let original = bits(&block(a.as_ref(), start, 16));
        prop_assert_eq!(&original, &bits(&block(b.as_ref(), start, 16)));

        b.reseed(other);
        prop_assert_eq!(b.seed(), other);
        prop_assert_eq!(b.dims(), a.dims());
        prop_assert_eq!(b.passes(), a.passes());
        let reseeded = bits(&block(b.as_ref(), start, 16));
        // 16 * dims independent 53-bit jitters: equal by chance with probability ~2^-53.
        prop_assert_ne!(&original, &reseeded);
        // A reseeded sampler is the sampler built with that seed ...
        let fresh = Spec { seed: other, ..spec }.build();
        prop_assert_eq!(&reseeded, &bits(&block(fresh.as_ref(), start, 16)));
        // ... and reseeding back restores the original points.
        b.reseed(spec.seed);
        prop_assert_eq!(&original, &bits(&block(b.as_ref(), start, 16)));
    }

    #[test]
    fn successive_passes_differ(
        dims in 1usize..=4,
        seed in any::<u64>(),
        size in 1u64..=64,
        pass in 0u64..1_000_000,
    ) {
        let samplers: [Box<dyn Sampler>; 2] = [
            Box::new(Jittered::new(dims, size.min(strata_for(dims)), seed).unwrap()),
            Box::new(LatinHypercube::new(dims, size, seed).unwrap()),
        ];
        for sampler in &samplers {
            let n = pass_size(sampler.as_ref());
            let this = bits(&block(sampler.as_ref(), pass * n, n as usize));
            let next = bits(&block(sampler.as_ref(), (pass + 1) * n, n as usize));
            prop_assert_ne!(this, next, "{} pass {}", sampler.name(), pass);
        }
    }

    #[test]
    fn jittered_puts_one_point_in_every_cell_of_every_pass(
        dims in 1usize..=4,
        k in 1u64..=6,
        seed in any::<u64>(),
        pass in prop_oneof![0u64..4, 0u64..(1u64 << 40)],
    ) {
        let sampler = Jittered::new(dims, k, seed).unwrap();
        let n = k.pow(dims as u32);
        prop_assert_eq!(sampler.passes(), PassKind::Fixed { size: n });
        prop_assert_eq!(sampler.strata_per_axis(), k);
        let points = block(&sampler, pass * n, n as usize);
        let mut hits = vec![0u32; n as usize];
        for i in 0..n as usize {
            // The cell's linear index, dimension 0 as the lowest base-k digit.
            let mut cell = 0u64;
            for d in (0..dims).rev() {
                let digit = (points.get(i, d) * k as f64).floor() as u64;
                prop_assert!(digit < k);
                cell = cell * k + digit;
            }
            // The documented layout: point i of a pass lies in the cell of i's digits.
            prop_assert_eq!(cell, i as u64);
            hits[cell as usize] += 1;
        }
        prop_assert!(hits.iter().all(|&h| h == 1));
    }

    #[test]
    fn latin_hypercube_puts_one_point_in_every_slab_of_every_axis(
        dims in 1usize..=5,
        // Small passes use the swap-or-not shuffle; larger ones (which cost about a
        // microsecond a coordinate to check) are in `latin_hypercube_slabs_for_large_passes`.
        n in 1u64..=300,
        seed in any::<u64>(),
        pass in prop_oneof![0u64..4, 0u64..(1u64 << 40)],
    ) {
        let sampler = LatinHypercube::new(dims, n, seed).unwrap();
        prop_assert_eq!(sampler.passes(), PassKind::Fixed { size: n });
        let points = block(&sampler, pass * n, n as usize);
        for d in 0..dims {
            let mut hits = vec![0u32; n as usize];
            for &x in points.column(d) {
                hits[(x * n as f64).floor() as usize] += 1;
            }
            prop_assert!(hits.iter().all(|&h| h == 1), "dim {}", d);
        }
    }

    #[test]
    fn jittered_with_points_names_the_nearest_valid_sizes(
        dims in 1usize..=5,
        points in 0u64..2_000_000,
    ) {
        // The largest r with r^dims <= points, by exact integer search.
        let mut root = 0u64;
        while (root + 1).pow(dims as u32) <= points {
            root += 1;
        }
        let result = Jittered::with_points(dims, points, 7);
        if root >= 1 && root.pow(dims as u32) == points {
            let sampler = result.unwrap();
            prop_assert_eq!(sampler.strata_per_axis(), root);
            prop_assert_eq!(sampler.passes(), PassKind::Fixed { size: points });
        } else {
            let err = result.unwrap_err();
            prop_assert_eq!(invalid_name(&err), "points");
            let above = (root + 1).pow(dims as u32);
            let nearest = if root >= 1 {
                format!("nearest valid: {} or {above})", root.pow(dims as u32))
            } else {
                format!("nearest valid: {above})")
            };
            let message = err.to_string();
            prop_assert!(message.contains(&nearest), "{} lacks {}", message, nearest);
        }
    }
}

#[test]
fn every_named_kind_builds_a_sampler_honouring_the_contract() {
    assert_eq!(
        SamplerKind::ALL.map(SamplerKind::name),
        [
            "independent",
            "jittered",
            "latin",
            "sobol",
            "halton",
            "hammersley",
            "lattice",
            "multijitter",
            "cmj",
            "oa-bose",
            "oa-bush",
            "nrooks-multistage",
            "poisson",
            "best-candidate",
            "pmj02"
        ]
    );
    for kind in SamplerKind::ALL {
        assert_eq!(kind.to_string().parse::<SamplerKind>().unwrap(), kind);
        // 64 is a perfect square, cube, power of two and product, so most kinds accept it;
        // orthogonal arrays need a prime power: 7^2 for Bose, 5^3 for Bush (strength 3).
        let points = match kind {
            SamplerKind::OaBose => 49,
            SamplerKind::OaBush => 125,
            _ => 64,
        };
        for dims in 1..=3 {
            let sampler = build_sampler(kind.name(), dims, points, 99).unwrap();
            assert_eq!(sampler.name(), kind.name());
            assert_eq!(sampler.dims(), dims);
            assert_eq!(sampler.seed(), 99);
            let expected = match kind {
                SamplerKind::Independent => PassKind::Independent,
                SamplerKind::Sobol => PassKind::Extensible { max: 1 << 32 },
                SamplerKind::Halton => PassKind::Extensible { max: 1 << 40 },
                SamplerKind::Lattice => PassKind::Extensible { max: 1 << 20 },
                SamplerKind::Pmj02 => PassKind::Extensible { max: 1 << 16 },
                _ => PassKind::Fixed { size: points },
            };
            assert_eq!(sampler.passes(), expected);
            assert_eq!(kind.build(dims, points, 99).unwrap().passes(), expected);
            for start in [0, 60, u64::MAX / 2 - 3, u64::MAX - 200] {
                let points = block(sampler.as_ref(), start, 100);
                for i in 0..100 {
                    let p = point(sampler.as_ref(), start + i as u64);
                    for (d, x) in p.iter().enumerate() {
                        assert!((0.0..1.0).contains(x));
                        assert_eq!(x.to_bits(), points.get(i, d).to_bits());
                    }
                }
            }
            // The very last index is reachable by `point`.
            assert!(
                point(sampler.as_ref(), u64::MAX)
                    .iter()
                    .all(|x| (0.0..1.0).contains(x))
            );
        }
    }
}

#[test]
fn latin_hypercube_slabs_for_large_passes() {
    // The largest swap-or-not size (2^16 - 1), then sizes where the permutation is a
    // cycle-walking Feistel network (n >= 2^16), including a non-power of two that needs walks
    // and one just above a power of four.
    for (n, dims) in [
        (65_535u64, 1usize),
        (65_536, 2),
        (70_001, 2),
        ((1 << 20) + 1, 1),
    ] {
        let sampler = LatinHypercube::new(dims, n, 5).unwrap();
        for pass in [0u64, 12_345] {
            let points = block(&sampler, pass * n, n as usize);
            for d in 0..dims {
                let mut hits = vec![false; n as usize];
                for &x in points.column(d) {
                    let slab = (x * n as f64).floor() as usize;
                    assert!(
                        !hits[slab],
                        "n = {n}, pass {pass}, dim {d}: slab {slab} twice"
                    );
                    hits[slab] = true;
                }
            }
        }
    }
}

#[test]
fn latin_hypercube_passes_use_fresh_permutations() {
    // With N = 100 two passes share a slab order by chance with probability 1/100!.
    let n = 100u64;
    let sampler = LatinHypercube::new(2, n, 3).unwrap();
    let slabs = |pass: u64, d: usize| -> Vec<u64> {
        block(&sampler, pass * n, n as usize)
            .column(d)
            .iter()
            .map(|x| (x * n as f64).floor() as u64)
            .collect()
    };
    assert_ne!(slabs(0, 0), slabs(1, 0));
    assert_ne!(slabs(0, 1), slabs(1, 1));
    // The two dimensions of one pass are permuted independently too.
    assert_ne!(slabs(0, 0), slabs(0, 1));
}

#[test]
fn jittered_strata_overflow_is_an_error() {
    // 2^63 fits in a u64, 2^64 does not; (2^32 - 1)^2 fits, (2^32)^2 does not.
    assert_eq!(
        Jittered::new(63, 2, 0).unwrap().passes(),
        PassKind::Fixed { size: 1 << 63 }
    );
    let max_square = (u64::from(u32::MAX)).pow(2);
    assert_eq!(
        Jittered::new(2, u64::from(u32::MAX), 0).unwrap().passes(),
        PassKind::Fixed { size: max_square }
    );
    for (dims, k) in [(64usize, 2u64), (2, 1 << 32), (3, 3_000_000), (1000, 2)] {
        let err = Jittered::new(dims, k, 0).unwrap_err();
        assert_eq!(invalid_name(&err), "strata_per_axis", "{err}");
        assert!(err.to_string().contains("fits in 64 bits"), "{err}");
    }
    // The largest square below u64::MAX is the only valid neighbour of u64::MAX in 2D.
    let err = Jittered::with_points(2, u64::MAX, 0)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains(&format!("nearest valid: {max_square})")),
        "{err}"
    );
    assert!(Jittered::with_points(2, max_square, 0).is_ok());
    assert!(Jittered::with_points(1, u64::MAX, 0).is_ok());
}

#[test]
fn constructors_reject_zero_dims_and_empty_passes() {
    let errors = [
        ("dims", Independent::new(0, 1).unwrap_err()),
        ("dims", Jittered::new(0, 2, 1).unwrap_err()),
        ("dims", Jittered::with_points(0, 4, 1).unwrap_err()),
        ("dims", LatinHypercube::new(0, 4, 1).unwrap_err()),
        ("strata_per_axis", Jittered::new(2, 0, 1).unwrap_err()),
        ("points", Jittered::with_points(2, 0, 1).unwrap_err()),
        ("points", LatinHypercube::new(2, 0, 1).unwrap_err()),
    ];
    for (name, err) in &errors {
        assert_eq!(invalid_name(err), *name, "{err}");
    }
    for kind in SamplerKind::ALL {
        assert_eq!(invalid_name(&kind.build(0, 16, 1).err().unwrap()), "dims");
    }
    // Independent points come in no passes, so it ignores the point count.
    assert!(build_sampler("independent", 2, 0, 1).is_ok());
    assert_eq!(
        invalid_name(&build_sampler("jittered", 2, 0, 1).err().unwrap()),
        "points"
    );
    assert_eq!(
        invalid_name(&build_sampler("latin", 2, 0, 1).err().unwrap()),
        "points"
    );
}

#[test]
fn unknown_sampler_name_lists_the_valid_names() {
    for name in ["sobel", "", "Latin", "independent "] {
        let err = build_sampler(name, 2, 16, 0).err().unwrap();
        assert_eq!(invalid_name(&err), "sampler");
        assert_eq!(
            err.to_string(),
            format!(
                "invalid sampler = {name:?}: expected one of independent, jittered, latin, sobol, \
                 halton, hammersley, lattice, multijitter, cmj, oa-bose, oa-bush, \
                 nrooks-multistage, poisson, best-candidate, pmj02"
            )
        );
        assert!(name.parse::<SamplerKind>().is_err());
    }
}

/// `preferred` points per pass, except for orthogonal arrays, which need a prime power:
/// 5^2 for Bose, 3^3 for Bush (strength 3).
fn prime_power_for(kind: SamplerKind, preferred: u64) -> u64 {
    match kind {
        SamplerKind::OaBose => 25,
        SamplerKind::OaBush => 27,
        _ => preferred,
    }
}

#[test]
fn mismatched_buffers_are_errors_not_panics() {
    for kind in SamplerKind::ALL {
        let sampler = kind.build(3, prime_power_for(kind, 27), 4).unwrap();
        for wrong in [0usize, 2, 4] {
            let mut out = vec![0.5; wrong];
            let err = sampler.point(5, &mut out).unwrap_err();
            assert_eq!(
                err,
                Error::DimensionMismatch {
                    what: "point buffer",
                    expected: 3,
                    found: wrong
                }
            );
            assert!(out.iter().all(|&x| x == 0.5), "buffer written on error");
        }
        for wrong in [1usize, 2, 4] {
            let mut points = Points::new(wrong, 10).unwrap();
            let err = sampler.fill(0, &mut points).unwrap_err();
            assert_eq!(
                err,
                Error::DimensionMismatch {
                    what: "point block",
                    expected: 3,
                    found: wrong
                }
            );
        }
        // An empty block is fine anywhere, even at the very end of the index range.
        let mut empty = Points::new(3, 0).unwrap();
        sampler.fill(0, &mut empty).unwrap();
        sampler.fill(u64::MAX, &mut empty).unwrap();
        // A block running past the last index is an error.
        let mut points = Points::new(3, 10).unwrap();
        assert!(matches!(
            sampler.fill(u64::MAX - 5, &mut points),
            Err(Error::IndexOutOfRange { .. })
        ));
    }
}

#[test]
fn a_block_may_end_at_the_last_index() {
    for kind in SamplerKind::ALL {
        let sampler = kind.build(2, prime_power_for(kind, 16), 4).unwrap();
        let mut points = Points::new(2, 4).unwrap();
        sampler.fill(u64::MAX - 3, &mut points).unwrap();
        let mut p = [0.0; 2];
        sampler.point(u64::MAX, &mut p).unwrap();
        assert_eq!(p, [points.get(3, 0), points.get(3, 1)]);
    }
}

/// Mean and standard error (sd of the pass means over sqrt(passes)) of the pass means.
fn pass_mean_stats(
    sampler: &dyn Sampler,
    passes: u64,
    f: impl Fn(&[f64]) -> f64,
) -> (f64, f64, f64) {
    let n = pass_size(sampler);
    let dims = sampler.dims();
    let mut points = Points::new(dims, n as usize).unwrap();
    let mut x = vec![0.0; dims];
    let means: Vec<f64> = (0..passes)
        .map(|p| {
            sampler.fill(p * n, &mut points).unwrap();
            let sum: f64 = (0..n as usize)
                .map(|i| {
                    points.copy_point(i, &mut x);
                    f(&x)
                })
                .sum();
            sum / n as f64
        })
        .collect();
    let mean = means.iter().sum::<f64>() / passes as f64;
    let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (passes - 1) as f64;
    (mean, (var / passes as f64).sqrt(), var)
}

/// `int_0^1 int_0^1 exp(x y) dx dy = sum_n 1 / ((n + 1)^2 n!)`, by expanding the exponential;
/// the terms fall below 1e-30 by n = 25.
fn exp_xy_integral() -> f64 {
    let mut factorial = 1.0;
    let mut sum = 0.0;
    for n in 0..30 {
        if n > 0 {
            factorial *= n as f64;
        }
        sum += 1.0 / ((n + 1) as f64).powi(2) / factorial;
    }
    sum
}

#[test]
fn exp_xy_series_matches_quadrature() {
    // Cross-check the series with a 2-D midpoint rule (error O(h^2) ~ 1e-7 for h = 1/1000).
    let m = 1000;
    let h = 1.0 / m as f64;
    let mut sum = 0.0;
    for i in 0..m {
        for j in 0..m {
            sum += ((i as f64 + 0.5) * h * (j as f64 + 0.5) * h).exp();
        }
    }
    assert!((sum * h * h - exp_xy_integral()).abs() < 1e-6);
    assert!((exp_xy_integral() - 1.317_902_151_454_404).abs() < 1e-14);
}

#[test]
fn stratified_pass_means_are_unbiased() {
    // The mean of many independent pass means is within 4.5 standard errors (from their
    // spread) of the exact integral: a two-sided normal tail of 7e-6 per check. Pass means
    // are sums of many independent terms, so the normal approximation is good.
    let product = |x: &[f64]| x.iter().map(|&t| (1.0 + t) / 1.5).product::<f64>();
    let exp_xy = |x: &[f64]| (x[0] * x[1]).exp();
    let cases: Vec<(Box<dyn Sampler>, u64)> = vec![
        (Box::new(Jittered::new(1, 16, 11).unwrap()), 4000),
        (Box::new(Jittered::new(2, 8, 12).unwrap()), 4000),
        (Box::new(Jittered::new(3, 4, 13).unwrap()), 4000),
        (Box::new(Jittered::new(5, 2, 14).unwrap()), 4000),
        (Box::new(LatinHypercube::new(1, 16, 15).unwrap()), 4000),
        (Box::new(LatinHypercube::new(2, 7, 16).unwrap()), 8000),
        (Box::new(LatinHypercube::new(3, 64, 17).unwrap()), 4000),
        (Box::new(LatinHypercube::new(5, 10, 18).unwrap()), 4000),
    ];
    for (sampler, passes) in &cases {
        let (mean, se, _) = pass_mean_stats(sampler.as_ref(), *passes, product);
        assert!(se > 0.0);
        assert!(
            (mean - 1.0).abs() < 4.5 * se,
            "{} in {}D, product: mean {mean}, se {se}",
            sampler.name(),
            sampler.dims()
        );
        if sampler.dims() == 2 {
            let exact = exp_xy_integral();
            let (mean, se, _) = pass_mean_stats(sampler.as_ref(), *passes, exp_xy);
            assert!(se > 0.0);
            assert!(
                (mean - exact).abs() < 4.5 * se,
                "{} exp(xy): mean {mean}, exact {exact}, se {se}",
                sampler.name()
            );
        }
    }
}

/// Upper 1e-5 quantile of chi-square with 15 degrees of freedom:
/// `python3 -c "from scipy.stats import chi2; print(chi2.isf(1e-5, 15))"` -> 50.493.
const CHI2_15_ISF_1E5: f64 = 50.49;

#[test]
fn latin_hypercube_points_are_jointly_uniform() {
    // One point from each of many independent passes (point p mod N of pass p, so every index
    // of the pass is used), binned on a 4x4 grid: independent draws, so the counts are exactly
    // multinomial and Pearson's statistic is chi-square with 15 degrees of freedom. This is
    // what unbiasedness for non-separable integrands needs: each point uniform on the square,
    // that is, the two coordinates' hashed permutations independent and uniform. N = 4 lines
    // the slabs up with the grid, so any coupling of the two permutations shows at full size.
    let passes = 16_000u64;
    for n in [4u64, 5, 16, 70_000] {
        let sampler = LatinHypercube::new(2, n, 2024).unwrap();
        let mut counts = [0f64; 16];
        let mut x = [0.0; 2];
        for p in 0..passes {
            sampler.point(p * n + p % n, &mut x).unwrap();
            let cell = (x[0] * 4.0) as usize + 4 * (x[1] * 4.0) as usize;
            counts[cell] += 1.0;
        }
        let expected = passes as f64 / 16.0;
        let chi2: f64 = counts
            .iter()
            .map(|c| (c - expected).powi(2) / expected)
            .sum();
        assert!(
            chi2 < CHI2_15_ISF_1E5,
            "N = {n}: chi2 = {chi2}, counts {counts:?}"
        );
    }
}

#[test]
fn stratification_reduces_variance_by_orders_of_magnitude() {
    // f(x) = x0 + x1 is monotone and additive, so the variances of the pass means (N = 256)
    // are known exactly (sigma^2 = Var f(U) = 1/6):
    //   independent:               sigma^2 / N
    //   jittered, k = 16 per axis: each point varies only within its cell, 2/(12 k^2) each,
    //                              so sigma^2 / (k^2 N), k^2 = 256 times less;
    //   Latin hypercube:           each coordinate's sum varies only by its N jitters,
    //                              so 2 N / (12 N^2) / N^2 = sigma^2 / N^3, N^2 times less.
    // Pass means are sums of 512 independent uniforms (near normal), so with P = 400 passes
    // (P - 1) s^2 / var lies within chi-square(399) 1e-5 quantiles:
    //   `python3 -c "from scipy.stats import chi2; print(chi2.ppf(1e-5, 399), chi2.isf(1e-5, 399))"`
    //   -> 289.78, 531.11.
    // Checking each variance against its theory checks the ordering; on top, the ratio of
    // sample variances is (true ratio) times an F(399, 399) variate whose 1e-5 quantile is
    // 0.651 (`scipy.stats.f.ppf(1e-5, 399, 399)`), so independent / jittered > 256 * 0.651 =
    // 166; we assert the two orders of magnitude the theory promises, ratio > 100.
    let n = 256u64;
    let passes = 400u64;
    let sigma2 = 1.0 / 6.0;
    let f = |x: &[f64]| x[0] + x[1];
    let (lo, hi) = (289.78 / 399.0, 531.11 / 399.0);
    let within = |name: &str, s2: f64, var: f64| {
        let ratio = s2 / var;
        assert!(
            (lo..hi).contains(&ratio),
            "{name}: sample variance {s2:e} is {ratio} times the theory {var:e}"
        );
    };

    // Independent points have no passes: take consecutive blocks of N as "passes".
    struct Blocks(Independent, u64);
    impl Sampler for Blocks {
        fn name(&self) -> &'static str {
            "independent blocks"
        }
        fn dims(&self) -> usize {
            self.0.dims()
        }
        fn passes(&self) -> PassKind {
            PassKind::Fixed { size: self.1 }
        }
        fn seed(&self) -> u64 {
            self.0.seed()
        }
        fn reseed(&mut self, seed: u64) {
            self.0.reseed(seed)
        }
        fn point(&self, index: u64, out: &mut [f64]) -> mcint::Result<()> {
            self.0.point(index, out)
        }
        fn fill(&self, start: u64, points: &mut Points) -> mcint::Result<()> {
            self.0.fill(start, points)
        }
    }
    let independent = Blocks(Independent::new(2, 77).unwrap(), n);
    let jittered = Jittered::with_points(2, n, 77).unwrap();
    let latin = LatinHypercube::new(2, n, 77).unwrap();

    let (_, _, var_ind) = pass_mean_stats(&independent, passes, f);
    let (_, _, var_jit) = pass_mean_stats(&jittered, passes, f);
    let (_, _, var_lhs) = pass_mean_stats(&latin, passes, f);
    within("independent", var_ind, sigma2 / n as f64);
    within("jittered", var_jit, sigma2 / (16.0 * 16.0 * n as f64));
    within("latin", var_lhs, sigma2 / (n as f64).powi(3));
    assert!(
        var_ind / var_jit > 100.0,
        "independent {var_ind:e} vs jittered {var_jit:e}"
    );
    assert!(
        var_ind / var_lhs > 100.0,
        "independent {var_ind:e} vs latin {var_lhs:e}"
    );
}
