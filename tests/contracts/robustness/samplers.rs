use super::*;
use mcint::Points;
use mcint::sampler::{
    Antithetic, BestCandidate, CorrelatedMultiJittered, Halton, Hammersley, Independent, Jittered,
    LatinHypercube, Lattice, MultiJittered, MultiStageNRooks, OaOffset, OrthogonalArray, PassKind,
    Pmj02, PoissonDisk, Sampler, SamplerKind, Scramble, Sobol,
};

/// Above this many dimensions an accepted sampler is only constructed: its points would
/// need buffers of that size.
const MAX_PROBED_DIMS: usize = 25_000;

fn scramble() -> impl Strategy<Value = Scramble> {
    prop::sample::select(Scramble::ALL.to_vec())
}

fn offset() -> impl Strategy<Value = OaOffset> {
    prop::sample::select(OaOffset::ALL.to_vec())
}

/// Points of a pass, or the most of an extensible pass.
fn pass_size(passes: PassKind) -> u64 {
    match passes {
        PassKind::Independent => 1,
        PassKind::Fixed { size } => size,
        PassKind::Extensible { max } => max,
    }
}

/// Whether generating points would build large blue-noise passes (built whole, cached).
fn too_costly(s: &dyn Sampler) -> bool {
    let size = pass_size(s.passes());
    match s.name() {
        "poisson" => size > 32,
        "best-candidate" => size > 256,
        _ => false,
    }
}

/// Indices near the start of the range, around the first pass boundary, at the start of
/// the last pass and at the very end.
fn probe_indices(passes: PassKind, extra: u64) -> Vec<u64> {
    let size = pass_size(passes);
    let mut indices = vec![
        0,
        1,
        size - 1,
        size,
        size.saturating_mul(2) - 1,
        u64::MAX / size * size,
        u64::MAX - 1,
        u64::MAX,
        extra,
    ];
    indices.sort_unstable();
    indices.dedup();
    indices
}

/// Checks an accepted sampler: its dimension and pass size, points in the unit cube at
/// `probe_indices`, a block at the end of the index range equal to its points, and errors
/// for a block one point too long and for buffers of the wrong dimension.
fn exercise(s: &dyn Sampler, dims: usize, extra: u64) {
    let name = s.name();
    assert_eq!(s.dims(), dims, "{name}");
    assert!(pass_size(s.passes()) >= 1, "{name}: {:?}", s.passes());
    if dims > MAX_PROBED_DIMS || too_costly(s) {
        return;
    }
    let mut p = vec![0.0; dims];
    for index in probe_indices(s.passes(), extra) {
        s.point(index, &mut p)
            .unwrap_or_else(|e| panic!("{name}: point {index}: {e}"));
        assert!(
            p.iter().all(|x| (0.0..1.0).contains(x)),
            "{name}: point {index} = {p:?}"
        );
    }
    let mut block = Points::new(dims, 2).unwrap();
    s.fill(u64::MAX - 1, &mut block)
        .unwrap_or_else(|e| panic!("{name}: the last two points: {e}"));
    for (k, index) in [u64::MAX - 1, u64::MAX].into_iter().enumerate() {
        s.point(index, &mut p).unwrap();
        for (d, x) in p.iter().enumerate() {
            assert_eq!(
                block.get(k, d).to_bits(),
                x.to_bits(),
                "{name}: {index}, {d}"
            );
        }
    }
    let mut three = Points::new(dims, 3).unwrap();
    match s.fill(u64::MAX - 1, &mut three) {
        Err(e @ Error::IndexOutOfRange { .. }) => assert_clear(&e, &[]),
        other => panic!("{name}: a block past u64::MAX gave {other:?}"),
    }
    let mut empty = Points::new(dims, 0).unwrap();
    s.fill(u64::MAX, &mut empty).unwrap();
    let mut long = vec![0.0; dims + 1];
    assert!(
        matches!(s.point(0, &mut long), Err(Error::DimensionMismatch { .. })),
        "{name}"
    );
    let mut wide = Points::new(dims + 1, 1).unwrap();
    assert!(
        matches!(s.fill(0, &mut wide), Err(Error::DimensionMismatch { .. })),
        "{name}"
    );
}

/// A sampler result: exercised when `Ok`, which it must be when `valid`.
fn check_sampler<S: Sampler>(
    result: mcint::Result<S>,
    valid: bool,
    dims: usize,
    extra: u64,
    params: &[&str],
) {
    if valid {
        assert!(result.is_ok(), "valid input rejected: {:?}", result.err());
    }
    check(result, params, |s| exercise(&s, dims, extra));
}

/// Trial division, for the small primes the properties assert about.
fn is_small_prime(p: u64) -> bool {
    p >= 2
        && (2..p)
            .take_while(|d| d * d <= p)
            .all(|d| !p.is_multiple_of(d))
}

/// `base^exp` if it is at most `2^53`.
fn power_within_2_53(base: u64, exp: u32) -> Option<u64> {
    base.checked_pow(exp).filter(|&n| n <= 1 << 53)
}

proptest! {
    #![proptest_config(config(96, 0x5a3))]

    #[test]
    fn independent(dims in dims(), seed in any::<u64>(), extra in any::<u64>()) {
        check_sampler(Independent::new(dims, seed), dims >= 1, dims, extra, &["dims"]);
    }

    #[test]
    fn jittered(dims in dims(), k in count(), seed in any::<u64>(), extra in any::<u64>()) {
        // 1^dims fits for every dims; larger k while k^dims fits in 64 bits.
        let fits = k == 1 || u32::try_from(dims).ok().and_then(|d| k.checked_pow(d)).is_some();
        let valid = dims >= 1 && k >= 1 && fits;
        check_sampler(Jittered::new(dims, k, seed), valid, dims, extra, &["dims", "strata"]);
        check_sampler(
            Jittered::with_points(dims, k, seed),
            dims >= 1 && (k == 1 || (dims == 1 && k >= 1)),
            dims,
            extra,
            &["dims", "points"],
        );
    }

    #[test]
    fn latin_hypercube(dims in dims(), n in count(), seed in any::<u64>(), extra in any::<u64>()) {
        let valid = dims >= 1 && n >= 1;
        check_sampler(LatinHypercube::new(dims, n, seed), valid, dims, extra, &["dims", "points"]);
    }

    #[test]
    fn sobol(dims in dims(), scramble in scramble(), seed in any::<u64>(), shuffle: bool, extra in any::<u64>()) {
        let valid = (1..=21_201).contains(&dims)
            && matches!(scramble, Scramble::None | Scramble::Xor | Scramble::Lms | Scramble::Owen);
        let result = Sobol::new(dims, scramble, seed).map(|s| s.with_index_shuffle(shuffle));
        check_sampler(result, valid, dims, extra, &["dims", "scramble"]);
    }

    #[test]
    fn halton(dims in dims(), scramble in scramble(), seed in any::<u64>(), extra in any::<u64>()) {
        let valid = (1..=Halton::MAX_DIMS).contains(&dims)
            && matches!(scramble, Scramble::None | Scramble::Permute | Scramble::Owen);
        check_sampler(Halton::new(dims, scramble, seed), valid, dims, extra, &["dims", "scramble"]);
    }

    #[test]
    fn hammersley(dims in dims(), n in count(), scramble in scramble(), seed in any::<u64>(), extra in any::<u64>()) {
        let valid = (1..=Hammersley::MAX_DIMS).contains(&dims)
            && (1..=Hammersley::MAX_POINTS).contains(&n)
            && matches!(scramble, Scramble::None | Scramble::Permute | Scramble::Owen);
        check_sampler(
            Hammersley::new(dims, n, scramble, seed),
            valid,
            dims,
            extra,
            &["dims", "points", "scramble"],
        );
    }

    #[test]
    fn lattice(dims in dims(), scramble in scramble(), seed in any::<u64>(), extra in any::<u64>()) {
        let valid = (1..=Lattice::KUO_MAX_DIMS).contains(&dims)
            && matches!(scramble, Scramble::None | Scramble::Shift);
        check_sampler(Lattice::new(dims, scramble, seed), valid, dims, extra, &["dims", "scramble"]);
    }

    #[test]
    fn lattice_with_generator(
        z in prop_oneof![
            prop::collection::vec(count(), 0..5),
            (count(), prop::sample::select(vec![0usize, 1, 1000, 30_000])).prop_map(|(v, n)| vec![v; n]),
        ],
        m in prop_oneof![0..70u32, Just(u32::MAX)],
        scramble in scramble(),
        seed in any::<u64>(),
        extra in any::<u64>(),
    ) {
        let valid = !z.is_empty()
            && (1..=Lattice::MAX_LOG2_POINTS).contains(&m)
            && z.iter().all(|&v| v != 0 && v >> m == 0)
            && matches!(scramble, Scramble::None | Scramble::Shift);
        let dims = z.len();
        check_sampler(
            Lattice::with_generator(z, m, scramble, seed),
            valid,
            dims,
            extra,
            &["generating vector", "log2_max_points", "scramble"],
        );
    }

    #[test]
    fn multi_jittered(dims in dims(), m in count(), n in count(), seed in any::<u64>(), extra in any::<u64>()) {
        let valid = dims >= 1 && m >= 1 && n >= 1 && m.checked_mul(n).is_some_and(|p| p <= 1 << 53);
        check_sampler(MultiJittered::new(dims, m, n, seed), valid, dims, extra, &["dims", "m", "n"]);
        check_sampler(
            CorrelatedMultiJittered::new(dims, m, n, seed),
            valid,
            dims,
            extra,
            &["dims", "m", "n"],
        );
    }

    #[test]
    fn multi_jittered_with_points(
        dims in dims(),
        n in count(),
        seed in any::<u64>(),
        extra in any::<u64>(),
    ) {
        let valid = dims >= 1 && (1..=1 << 53).contains(&n);
        check_sampler(MultiJittered::with_points(dims, n, seed), valid, dims, extra, &["dims", "points"]);
        check_sampler(
            CorrelatedMultiJittered::with_points(dims, n, seed),
            valid,
            dims,
            extra,
            &["dims", "points"],
        );
    }

    #[test]
    fn orthogonal_array_bose(
        dims in dims(),
        p in prop_oneof![0..200u64, count()],
        offset in offset(),
        seed in any::<u64>(),
        extra in any::<u64>(),
    ) {
        let known = p < 1 << 20;
        let valid = known && dims >= 1 && is_small_prime(p) && dims as u128 <= u128::from(p) + 1;
        let result = OrthogonalArray::bose(dims, p, offset, seed);
        if known && !valid {
            prop_assert!(result.is_err());
        }
        check_sampler(result, valid, dims, extra, &["dims", "p"]);
    }

    #[test]
    fn orthogonal_array_bush(
        dims in dims(),
        p in prop_oneof![0..40u64, count()],
        t in prop_oneof![0..8u32, Just(63), Just(64), Just(u32::MAX)],
        offset in offset(),
        seed in any::<u64>(),
        extra in any::<u64>(),
    ) {
        let known = p < 1 << 20;
        let fits = dims as u128 <= u128::from(p) + u128::from(u64::from(t) <= p);
        let valid = known && dims >= 1 && t >= 1 && is_small_prime(p) && fits
            && p.checked_pow(t).is_some();
        let result = OrthogonalArray::bush(dims, p, t, offset, seed);
        if known && !valid {
            prop_assert!(result.is_err());
        }
        check_sampler(result, valid, dims, extra, &["dims", "p", "strength"]);
    }

    #[test]
    fn orthogonal_array_with_points(
        dims in dims(),
        n in count(),
        t in prop_oneof![0..6u32, Just(64), Just(u32::MAX)],
        offset in offset(),
        seed in any::<u64>(),
        extra in any::<u64>(),
    ) {
        check(
            OrthogonalArray::with_points(dims, n, t, offset, seed),
            &["dims", "points", "strength"],
            |s| {
                assert_eq!(pass_size(s.passes()), n);
                exercise(&s, dims, extra);
            },
        );
    }

    #[test]
    fn multi_stage_n_rooks(
        dims in dims(),
        n in count(),
        base in count(),
        stages in prop_oneof![0..60u32, Just(u32::MAX)],
        seed in any::<u64>(),
        extra in any::<u64>(),
    ) {
        let valid = dims >= 1 && base >= 2 && stages >= 1 && power_within_2_53(base, stages).is_some();
        check_sampler(
            MultiStageNRooks::with_stages(dims, base, stages, seed),
            valid,
            dims,
            extra,
            &["dims", "base", "stages"],
        );
        let perfect_power = (2..64u32).any(|k| {
            let root = (n as f64).powf(1.0 / f64::from(k)).round() as u64;
            (root.saturating_sub(1)..=root + 1)
                .any(|r| r >= 2 && power_within_2_53(r, k) == Some(n))
        });
        check_sampler(
            MultiStageNRooks::new(dims, n, seed),
            dims >= 1 && perfect_power,
            dims,
            extra,
            &["dims", "points"],
        );
    }

    #[test]
    fn pmj02(dims in dims(), log2 in prop_oneof![0..25u32, Just(32), Just(u32::MAX)], seed in any::<u64>(), extra in any::<u64>()) {
        check_sampler(Pmj02::new(dims, seed), dims >= 1, dims, extra, &["dims"]);
        check_sampler(
            Pmj02::with_max_points(dims, log2, seed),
            dims >= 1 && log2 <= 20,
            dims,
            extra,
            &["dims", "log2_max"],
        );
    }

    #[test]
    fn antithetic(
        dims in 1..4usize,
        n in count(),
        which in 0..4usize,
        seed in any::<u64>(),
        extra in any::<u64>(),
    ) {
        // Inner samplers with independent points, fixed passes of any size and
        // extensible passes; the doubled pass size must fit.
        let inner: mcint::Result<Box<dyn Sampler>> = match which {
            0 => Independent::new(dims, seed).map(|s| Box::new(s) as _),
            1 => LatinHypercube::new(dims, n, seed).map(|s| Box::new(s) as _),
            2 => Sobol::new(dims, Scramble::Owen, seed).map(|s| Box::new(s) as _),
            _ => Jittered::new(1, n, seed).map(|s| Box::new(s) as _),
        };
        let dims = if which == 3 { 1 } else { dims };
        if let Ok(inner) = inner {
            let size = pass_size(inner.passes());
            let valid = size.checked_mul(2).is_some();
            check_sampler(Antithetic::new(inner), valid, dims, extra, &["inner sampler"]);
        }
    }

    #[test]
    fn sampler_kind_build_with(
        kind in prop::sample::select(SamplerKind::ALL.to_vec()),
        dims in dims(),
        n in count().prop_map(|n| if n > 1 << 40 && n <= 1 << 53 { n >> 16 } else { n }),
        scramble in scramble(),
        strength in prop::option::of(prop_oneof![0..6u32, Just(64), Just(u32::MAX)]),
        seed in any::<u64>(),
        extra in any::<u64>(),
    ) {
        let params = ["dims", "points", "scramble", "strength", "m * n", "stages", "log2_max"];
        check(kind.build_with(dims, n, scramble, strength, seed), &params, |s| {
            assert_eq!(s.seed(), seed);
            if let PassKind::Fixed { size } = s.passes() {
                // Samplers with fixed passes take `points` as their pass size.
                assert_eq!(size, n, "{kind}");
            }
            exercise(&s, dims, extra);
        });
    }
}

proptest! {
    // Blue noise builds whole passes; few cases, small passes (see `too_costly`).
    #![proptest_config(config(24, 0xb1e))]

    #[test]
    fn poisson_disk(dims in dims(), n in count(), seed in any::<u64>(), extra in any::<u64>()) {
        let valid = (1..=8).contains(&dims)
            && (1..=PoissonDisk::max_points(dims).unwrap()).contains(&n);
        let result = PoissonDisk::new(dims, n, seed);
        if dims > 4 {
            // Building 5-8-D passes takes seconds in debug builds: the constructor's
            // answer is checked here, the passes by tests/samplers/stratified_blue_noise.rs.
            prop_assert_eq!(result.is_ok(), valid);
            return Ok(());
        }
        check_sampler(result, valid, dims, extra, &["dims", "points"]);
    }

    #[test]
    fn poisson_disk_with_radius(
        dims in dims(),
        radius in prop_oneof![real(), 0.25..0.5f64],
        seed in any::<u64>(),
        extra in any::<u64>(),
    ) {
        let result = PoissonDisk::with_radius(dims, radius, seed);
        if !(radius > 0.0 && radius < 0.5 && (1..=8).contains(&dims)) {
            prop_assert!(result.is_err());
        }
        if dims > 4 {
            return Ok(()); // as above: the passes are checked elsewhere
        }
        check(result, &["dims", "radius"], |s| {
            exercise(&s, dims, extra);
            if !too_costly(&s) {
                assert_min_distance(&s, 0);
                assert_min_distance(&s, extra);
            }
        });
    }

    #[test]
    fn best_candidate(dims in dims(), n in count(), seed in any::<u64>(), extra in any::<u64>()) {
        let valid = (1..=4).contains(&dims) && (1..=1 << 14).contains(&n);
        check_sampler(BestCandidate::new(dims, n, seed), valid, dims, extra, &["dims", "points"]);
    }
}

proptest! {
    #![proptest_config(config(256, 0x4a3))]

    /// Names round-trip, and anything else is an error that names the parameter.
    #[test]
    fn names(name in prop_oneof!["[a-z-]{0,20}", ".{0,8}", prop::sample::select(vec!["sobol".to_string(), "oa-bush".into(), "cmj".into(), "owen".into()])], dims in 0..4usize, n in count()) {
        let parsed = (
            name.parse::<SamplerKind>(),
            name.parse::<Scramble>(),
            name.parse::<OaOffset>(),
        );
        check(parsed.0, &["sampler"], |k| assert_eq!(k.name(), name));
        check(parsed.1, &["scramble"], |k| assert_eq!(k.name(), name));
        check(parsed.2, &["offset"], |k| assert_eq!(k.name(), name));
        let params = ["sampler", "dims", "points", "m * n", "stages"];
        let n = if n > 1 << 40 && n <= 1 << 53 { n >> 16 } else { n };
        check(mcint::sampler::build_sampler(&name, dims, n, 1), &params, |s| {
            exercise(&s, dims, 0);
        });
    }
}

/// Every pair of points of a Poisson-disk pass is at least the radius apart on the torus.
fn assert_min_distance(s: &PoissonDisk, pass: u64) {
    let set = s.maximal_set(pass);
    let size = pass_size(s.passes()) as usize;
    assert!(
        set.len() >= size,
        "{} points for a pass of {size}",
        set.len()
    );
    let gap = |a: f64, b: f64| (a - b).abs().min(1.0 - (a - b).abs());
    for (i, a) in set.iter().enumerate() {
        for b in &set[..i] {
            let d = a
                .iter()
                .zip(b)
                .map(|(&x, &y)| gap(x, y).powi(2))
                .sum::<f64>();
            assert!(
                d.sqrt() >= s.radius() * (1.0 - 1e-12),
                "radius {} but two points {} apart",
                s.radius(),
                d.sqrt()
            );
        }
    }
}

#[test]
fn index_limits_are_pass_boundaries_not_wraps() {
    // An unscrambled sequence repeats itself pass after pass (documented); the point after
    // the last of a pass starts the next pass, and the last index of u64 still works.
    let mut a = [0.0; 2];
    let mut b = [0.0; 2];
    let sobol = Sobol::new(2, Scramble::None, 0).unwrap();
    sobol.point((1 << 32) - 1, &mut a).unwrap();
    assert!(a.iter().all(|x| (0.0..1.0).contains(x)) && a != [0.0, 0.0]);
    sobol.point(1 << 32, &mut b).unwrap();
    assert_eq!(b, [0.0, 0.0]);
    sobol.point(u64::MAX, &mut b).unwrap();
    assert_eq!(a, b);
    let lattice = Lattice::new(2, Scramble::None, 0).unwrap();
    lattice.point((1 << 20) - 1, &mut a).unwrap();
    lattice.point(((1 << 20) - 1) | (5 << 20), &mut b).unwrap();
    assert_eq!(a, b);
    let lattice = Lattice::new(Lattice::KUO_MAX_DIMS, Scramble::Shift, 0).unwrap();
    let mut p = vec![0.0; Lattice::KUO_MAX_DIMS];
    lattice.point(u64::MAX, &mut p).unwrap();
    assert!(p.iter().all(|x| (0.0..1.0).contains(x)));
    let halton = Halton::new(3, Scramble::None, 0).unwrap();
    halton.point(Halton::PASS_SIZE - 1, &mut p[..3]).unwrap();
    assert!(p[..3].iter().all(|x| (0.0..1.0).contains(x)));
    // Owen-scrambled Sobol' with the index shuffle at the top of the range.
    let shuffled = Sobol::new(2, Scramble::Owen, 3)
        .unwrap()
        .with_index_shuffle(true);
    let mut block = Points::new(2, 300).unwrap();
    shuffled.fill(u64::MAX - 299, &mut block).unwrap();
    for i in 0..300 {
        shuffled.point(u64::MAX - 299 + i as u64, &mut a).unwrap();
        assert_eq!([block.get(i, 0), block.get(i, 1)], a);
    }
}

#[test]
fn multi_jittered_with_points_near_2_53_finishes() {
    // The largest prime below 2^53 (a walk down from its root would try 9.5e7 divisors).
    let s = MultiJittered::with_points(2, (1 << 53) - 111, 0).unwrap();
    assert_eq!(s.m(), 1);
}
