//! `vector_math::exp_in_place` and `cos_in_place` against the standard library's `exp` and
//! `cos` (themselves within an ulp of the true values), at random arguments over their whole
//! ranges, next to the zeros of `cos` and at special values: `exp` within 1 ulp of them,
//! `cos` within 1 ulp for `|x| <= 100` and 2 beyond (or 1e-25 absolute); the dispatched and
//! portable paths give the same bits.

use mcint::sampler::simd;
use mcint::vector_math::{cos_in_place, exp_in_place};
use rand_core::Rng;
use rand_pcg::Pcg64;

/// Distance in units in the last place of `expected`, for finite values.
fn ulps(got: f64, expected: f64) -> f64 {
    if got == expected {
        return 0.0;
    }
    let spacing = if expected == 0.0 {
        f64::from_bits(1)
    } else {
        let e = expected.abs();
        // ulp(e): the gap to the next float up (subnormal gaps are 2^-1074).
        f64::from_bits(e.to_bits() + 1) - e
    };
    (got - expected).abs() / spacing
}

fn random_arguments(low: f64, high: f64, count: usize, seed: u64) -> Vec<f64> {
    let mut rng = Pcg64::new(0x5eed, u128::from(seed));
    (0..count)
        .map(|_| low + (high - low) * ((rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64))
        .collect()
}

#[test]
fn exp_is_within_one_ulp_of_the_standard_library() {
    let mut xs = random_arguments(-745.5, 710.0, 400_000, 1);
    xs.extend(random_arguments(-1.0, 1.0, 200_000, 2));
    xs.extend(random_arguments(-30.0, 0.0, 200_000, 3));
    // Around the overflow and underflow thresholds and the subnormal range.
    xs.extend(random_arguments(-745.2, -708.0, 100_000, 4));
    xs.extend([
        0.0,
        -0.0,
        1.0,
        -1.0,
        709.78,
        709.7827128933839,
        -745.13,
        -744.4,
        -708.4,
    ]);
    let mut ys = xs.clone();
    exp_in_place(&mut ys);
    let worst = xs
        .iter()
        .zip(&ys)
        .map(|(x, y)| ulps(*y, x.exp()))
        .fold(0.0, f64::max);
    eprintln!("exp: worst {worst} ulps");
    assert!(worst <= 1.0, "exp: {worst} ulps");
}

#[test]
fn exp_special_values() {
    let mut ys = [
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
        710.0,
        -746.0,
        1e300,
        -1e300,
    ];
    exp_in_place(&mut ys);
    assert_eq!(ys[0], f64::INFINITY);
    assert_eq!(ys[1], 0.0);
    assert!(ys[2].is_nan());
    assert_eq!(&ys[3..], &[f64::INFINITY, 0.0, f64::INFINITY, 0.0]);
}

#[test]
fn cos_is_within_one_ulp_of_the_standard_library() {
    let mut xs = random_arguments(-1e6, 1e6, 400_000, 5);
    xs.extend(random_arguments(-10.0, 10.0, 400_000, 6));
    xs.extend(random_arguments(-1e-3, 1e-3, 50_000, 7));
    // Next to the zeros and extremes of cos, where the reduction cancels most.
    for j in (-2000i32..2000).chain([636_619, -636_619]) {
        let at = f64::from(j) * std::f64::consts::FRAC_PI_2;
        let mut x = at;
        for _ in 0..8 {
            xs.push(x);
            x = f64::from_bits(x.to_bits() + 1);
        }
    }
    let mut ys = xs.clone();
    cos_in_place(&mut ys);
    // The worst error in ulps of the standard library's value, where that is above 1e-25,
    // over |x| <= 100 and over the rest.
    let (mut near, mut far) = (0.0f64, 0.0f64);
    for (x, y) in xs.iter().zip(&ys) {
        let expected = x.cos();
        if (y - expected).abs() > 1e-25 {
            let worst = if x.abs() <= 100.0 {
                &mut near
            } else {
                &mut far
            };
            *worst = worst.max(ulps(*y, expected));
        }
    }
    eprintln!("cos: worst {near} ulps for |x| <= 100, {far} beyond");
    assert!(near <= 1.0 && far <= 2.0, "cos: {near} and {far} ulps");
}

#[test]
fn cos_beyond_the_reduction_and_special_values() {
    let xs = [
        1e6,
        -1e6,
        1.5e6,
        1e300,
        -7e9,
        f64::INFINITY,
        f64::NAN,
        0.0,
        -0.0,
    ];
    let mut ys = xs;
    cos_in_place(&mut ys);
    for (x, y) in xs.iter().zip(&ys).skip(2).take(3) {
        assert_eq!(*y, x.cos());
    }
    assert!(ys[5].is_nan() && ys[6].is_nan());
    assert_eq!(&ys[7..], &[1.0, 1.0]);
}

#[test]
fn every_instruction_set_gives_the_same_bits() {
    let xs = random_arguments(-700.0, 700.0, 10_000, 8);
    let run = |portable: bool| {
        simd::force_portable(portable);
        let (mut e, mut c) = (xs.clone(), xs.clone());
        exp_in_place(&mut e);
        cos_in_place(&mut c);
        simd::force_portable(false);
        (e, c)
    };
    let dispatched = run(false);
    let portable = run(true);
    assert_eq!(dispatched, portable, "{}", simd::active());
}
