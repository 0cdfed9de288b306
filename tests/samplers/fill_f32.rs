//! `Sampler::fill_f32`: every value is `to_unit_f32` of the `f64` coordinate `fill` gives (the
//! nearest `f32`, clamped below one), and in `[0, 1)`, for every sampler kind, Sobol's direct
//! word-to-`f32` path under every scramble, and the wrappers.

use mcint::Points;
use mcint::points_f32::{F32_BELOW_ONE, PointsF32, to_unit_f32};
use mcint::sampler::{Antithetic, Halton, Sampler, SamplerKind, Scramble, Sobol};

/// Fills `len` points from `start` in both precisions and compares them bit for bit.
fn assert_f32_matches_f64(sampler: &dyn Sampler, start: u64, len: usize) {
    let dims = sampler.dims();
    let mut wide = Points::new(dims, len).unwrap();
    let mut narrow = PointsF32::new(dims, len).unwrap();
    sampler.fill(start, &mut wide).unwrap();
    sampler.fill_f32(start, &mut narrow).unwrap();
    for dim in 0..dims {
        for (i, (&x, &y)) in wide.column(dim).iter().zip(narrow.column(dim)).enumerate() {
            assert!(
                (0.0..1.0).contains(&y),
                "{}: {y} not in [0, 1)",
                sampler.name()
            );
            assert_eq!(
                y.to_bits(),
                to_unit_f32(x).to_bits(),
                "{} dim {dim}: start {start} point {i}: f64 {x:e}, f32 {y:e}",
                sampler.name()
            );
        }
    }
}

#[test]
fn to_unit_f32_rounds_to_nearest_and_stays_below_one() {
    assert_eq!(F32_BELOW_ONE, 1.0 - 2f32.powi(-24));
    // Exactly representable values pass through.
    for x in [0.0, 0.5, 0.75, 1.0 - 2f64.powi(-24)] {
        assert_eq!(f64::from(to_unit_f32(x)), x);
    }
    // Just below the midpoint between F32_BELOW_ONE and 1 rounds down, at it (a tie, to the
    // even 1.0) and above it are clamped.
    let mid = 1.0 - 2f64.powi(-25);
    assert_eq!(to_unit_f32(mid - 2f64.powi(-53)), F32_BELOW_ONE);
    assert_eq!(to_unit_f32(mid), F32_BELOW_ONE);
    assert_eq!(to_unit_f32(1.0 - 2f64.powi(-53)), F32_BELOW_ONE);
    // Nearest, not truncation: 1/3 and 2/3 round in opposite directions.
    for x in [1.0 / 3.0, 2.0 / 3.0, 0.1, 1e-30] {
        let y = to_unit_f32(x);
        let (below, above) = (
            f32::from_bits(y.to_bits() - 1),
            f32::from_bits(y.to_bits() + 1),
        );
        let err = (f64::from(y) - x).abs();
        assert!(err <= (f64::from(below) - x).abs() && err <= (f64::from(above) - x).abs());
    }
}

#[test]
fn every_sampler_kind_fills_f32_as_its_f64_rounded() {
    for kind in SamplerKind::ALL {
        for dims in [1usize, 2, 3] {
            // 4096 = 4096^1 = 64^2 = 16^3 and a power of two suits every kind but the
            // orthogonal arrays, which need the square (Bose) or cube (Bush) of a prime.
            let points = match kind {
                SamplerKind::OaBose => 67 * 67,
                SamplerKind::OaBush => 17 * 17 * 17,
                _ => 4096,
            };
            let sampler = kind
                .build(dims, points, 11)
                .unwrap_or_else(|e| panic!("{kind:?} in {dims} dims: {e}"));
            for (start, len) in [(0u64, 0usize), (0, 1), (5, 1025), (points - 3, 600)] {
                assert_f32_matches_f64(sampler.as_ref(), start, len);
            }
        }
    }
    let antithetic = Antithetic::new(Halton::new(3, Scramble::Owen, 2).unwrap()).unwrap();
    assert_f32_matches_f64(&antithetic, 7, 300);
}

#[test]
fn sobol_direct_f32_path_equals_the_rounded_f64_for_every_scramble() {
    let pass = 1u64 << 32;
    for dims in [1usize, 3, 32] {
        for scramble in [Scramble::None, Scramble::Xor, Scramble::Lms, Scramble::Owen] {
            for shuffle in [false, true] {
                let s = Sobol::new(dims, scramble, 9)
                    .unwrap()
                    .with_index_shuffle(shuffle);
                for (start, len) in [
                    (0u64, 1000usize),
                    (13, 17),
                    (pass - 300, 700),
                    (u64::MAX - 256, 257),
                ] {
                    assert_f32_matches_f64(&s, start, len);
                }
            }
        }
    }
}

#[test]
fn values_next_to_one_are_clamped() {
    // Unscrambled Sobol' point 0xaaaaaaaa has Gray code 0xffffffff: its first coordinate is
    // 1 - 2^-32, which rounds to 1.0 in f32.
    let s = Sobol::new(1, Scramble::None, 0).unwrap();
    let mut block = PointsF32::new(1, 1).unwrap();
    s.fill_f32(0xaaaa_aaaa, &mut block).unwrap();
    assert_eq!(block.get(0, 0), F32_BELOW_ONE);
    // The last point of a Halton pass: 1 - 2^-40 in base 2.
    let h = Halton::new(1, Scramble::None, 0).unwrap();
    h.fill_f32(Halton::PASS_SIZE - 1, &mut block).unwrap();
    assert_eq!(block.get(0, 0), F32_BELOW_ONE);
}

#[test]
fn fill_f32_rejects_wrong_shapes() {
    let s = Sobol::new(2, Scramble::Owen, 1).unwrap();
    let mut block = PointsF32::new(3, 4).unwrap();
    assert!(s.fill_f32(0, &mut block).is_err());
    assert!(
        Halton::new(3, Scramble::None, 0)
            .unwrap()
            .fill_f32(u64::MAX - 2, &mut block)
            .is_err()
    );
    let mut ok = PointsF32::new(2, 4).unwrap();
    assert!(s.fill_f32(u64::MAX - 2, &mut ok).is_err());
    assert!(s.fill_f32(u64::MAX - 3, &mut ok).is_ok());
}
