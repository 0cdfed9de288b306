//! `exp` and `cos` over whole slices, vectorized: for batch integrands
//! ([`Integrator::over_box_batch`](crate::Integrator::over_box_batch)) whose time would
//! otherwise go to one scalar libm call per point.
//!
//! Both are written as branch-free lane functions (range reduction, a polynomial, a rescaling)
//! run through the crate's run-time dispatch, so the same loop is compiled for AVX-512, AVX2
//! and the baseline target and vectorized there with 8, 4 or 2 lanes. Only additions,
//! multiplications, comparisons and bit operations are used, which the compiler neither
//! reassociates nor contracts: every path gives the same bits on every x86-64 machine.
//!
//! Accuracy (measured in `tests/quality/vector_math.rs` against the standard library, itself within
//! an ulp of the truth): `exp` within 1 ulp, subnormal results included; `cos` within 1 ulp
//! for `|x| <= 100` and 2 ulps up to `1e6` (the reduced argument carries one more rounding),
//! or `1e-25` absolute next to the zeros of `cos`.
//! Arguments outside `[-1e6, 1e6]` and non-finite ones go to the standard library's `cos`.
//!
//! ```
//! let mut y = [0.0, 1.0, -2.5];
//! mcint::vector_math::exp_in_place(&mut y);
//! assert!((y[1] - std::f64::consts::E).abs() <= f64::EPSILON * y[1]);
//! ```

use crate::simd::{Kernel, dispatch};

/// `1.5 * 2^52`: adding it rounds an `f64` below `2^51` in magnitude to the nearest integer,
/// which then sits, in two's complement, in the low bits of the sum.
const ROUND: f64 = 6_755_399_441_055_744.0;

/// `ln 2` split so that `k * LN2_HI` is exact for `|k| < 2^21` (its low 21 bits are zero);
/// the bit patterns are fdlibm's.
const LN2_HI: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000);
const LN2_LO: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76);
/// Above this `exp` overflows to infinity (`ln f64::MAX`).
const EXP_OVERFLOW: f64 = 709.782_712_893_384;
/// Below this `exp` rounds to zero (`ln 2^-1075`).
const EXP_UNDERFLOW: f64 = -745.133_219_101_941_2;

/// `π/2` in three parts: the first two have 33 significant bits, so `j` times either is exact
/// for `|j| < 2^20`; the third carries the next 53 bits.
const PIO2_1: f64 = f64::from_bits(0x3FF9_21FB_5440_0000);
const PIO2_2: f64 = f64::from_bits(0x3DD0_B461_1A60_0000);
const PIO2_3: f64 = f64::from_bits(0x3BA3_198A_2E03_7073);
/// Largest `|x|` reduced by the three-part `π/2`: `|j| <= 636620 < 2^20`.
const COS_LIMIT: f64 = 1e6;

/// `e^x` for every value of `values`, in place.
///
/// ```
/// let mut y = vec![-1.0, 0.0, 700.0, 800.0, -800.0, f64::NAN];
/// mcint::vector_math::exp_in_place(&mut y);
/// assert_eq!(y[1], 1.0);
/// assert!((y[0] - (-1f64).exp()).abs() <= f64::EPSILON * y[0]);
/// assert_eq!((y[3], y[4]), (f64::INFINITY, 0.0));
/// assert!(y[5].is_nan());
/// ```
pub fn exp_in_place(values: &mut [f64]) {
    dispatch(ExpKernel(values));
}

/// `cos x` for every value of `values`, in place.
///
/// ```
/// let mut y = vec![0.0, 1.0, 3.0, 1e7, f64::INFINITY];
/// mcint::vector_math::cos_in_place(&mut y);
/// assert_eq!(y[0], 1.0);
/// assert!((y[1] - 1f64.cos()).abs() <= f64::EPSILON);
/// assert_eq!(y[3], 1e7f64.cos()); // beyond 1e6: the standard library's
/// assert!(y[4].is_nan());
/// ```
pub fn cos_in_place(values: &mut [f64]) {
    dispatch(CosKernel(values));
}

struct ExpKernel<'a>(&'a mut [f64]);

impl Kernel for ExpKernel<'_> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        for x in self.0.iter_mut() {
            *x = exp_lane(*x);
        }
    }
}

struct CosKernel<'a>(&'a mut [f64]);

impl Kernel for CosKernel<'_> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        // Rare arguments the reduction does not cover (NaN among them) take the scalar path,
        // value by value. The check is an AND of comparisons, so it vectorizes too.
        let all_covered = self
            .0
            .iter()
            .fold(true, |all, x| all & (x.abs() <= COS_LIMIT));
        if all_covered {
            for x in self.0.iter_mut() {
                *x = cos_lane(*x);
            }
        } else {
            for x in self.0.iter_mut() {
                *x = if x.abs() <= COS_LIMIT {
                    cos_lane(*x)
                } else {
                    x.cos()
                };
            }
        }
    }
}

/// `x` rounded to the nearest integer (ties to even), as an `f64` and as an `i64`; `|x|` must
/// be below `2^51`.
#[inline(always)]
fn round_to_integer(x: f64) -> (f64, i64) {
    let sum = x + ROUND;
    let integer = (sum.to_bits() as i64).wrapping_sub(ROUND.to_bits() as i64);
    (sum - ROUND, integer)
}

/// `2^k` for `-1022 <= k <= 1023`.
#[inline(always)]
fn power_of_two(k: i64) -> f64 {
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// `e^x`: `x = k ln 2 + r` with `|r| <= ln 2 / 2`, `e^r` by its Taylor polynomial to `r^13`
/// (the remainder is below `2^-57`), times `2^k` in two exact factors so that subnormal
/// results are rounded once.
#[inline(always)]
fn exp_lane(x: f64) -> f64 {
    let clamped = x.clamp(-746.0, 710.0);
    let (k, ki) = round_to_integer(clamped * std::f64::consts::LOG2_E);
    let r = (clamped - k * LN2_HI) - k * LN2_LO;
    let mut p = 1.0 / 6_227_020_800.0; // 1/13!
    for inverse_factorial in [
        1.0 / 479_001_600.0,
        1.0 / 39_916_800.0,
        1.0 / 3_628_800.0,
        1.0 / 362_880.0,
        1.0 / 40_320.0,
        1.0 / 5_040.0,
        1.0 / 720.0,
        1.0 / 120.0,
        1.0 / 24.0,
        1.0 / 6.0,
        0.5,
        1.0,
        1.0,
    ] {
        p = p * r + inverse_factorial;
    }
    let half = ki >> 1;
    let y = p * power_of_two(half) * power_of_two(ki - half);
    if x > EXP_OVERFLOW {
        f64::INFINITY
    } else if x < EXP_UNDERFLOW {
        0.0
    } else if x.is_nan() {
        x
    } else {
        y
    }
}

/// `cos x` for `|x| <= COS_LIMIT`: `x = j π/2 + r` with `|r| <= π/4`, then `±cos r` or
/// `±sin r` by the quadrant `j mod 4`, each from its Taylor polynomial (to `r^18` and `r^17`;
/// remainders below `2^-60`).
#[inline(always)]
fn cos_lane(x: f64) -> f64 {
    let (j, ji) = round_to_integer(x * std::f64::consts::FRAC_2_PI);
    let r = ((x - j * PIO2_1) - j * PIO2_2) - j * PIO2_3;
    let z = r * r;
    // sin r = r - r^3 (1/3! - z (1/5! - z (1/7! - ...))).
    let mut s = -1.0 / 355_687_428_096_000.0; // -1/17!
    for inverse_factorial in [
        1.0 / 1_307_674_368_000.0,
        -1.0 / 6_227_020_800.0,
        1.0 / 39_916_800.0,
        -1.0 / 362_880.0,
        1.0 / 5_040.0,
        -1.0 / 120.0,
        1.0 / 6.0,
    ] {
        s = s * z + inverse_factorial;
    }
    let sin = r - r * z * s;
    // cos r = 1 - z/2 + z^2 (1/4! - z (1/6! - ...)) = 1 - z/2 - z^2 q, with the rounding of
    // 1 - z/2 recovered.
    let mut q = 1.0 / 6_402_373_705_728_000.0; // 1/18!
    for inverse_factorial in [
        -1.0 / 20_922_789_888_000.0,
        1.0 / 87_178_291_200.0,
        -1.0 / 479_001_600.0,
        1.0 / 3_628_800.0,
        -1.0 / 40_320.0,
        1.0 / 720.0,
        -1.0 / 24.0,
    ] {
        q = q * z + inverse_factorial;
    }
    let half_z = 0.5 * z;
    let w = 1.0 - half_z;
    let cos = w + (((1.0 - w) - half_z) - z * z * q);
    let quadrant = ji & 3;
    let v = if quadrant & 1 == 0 { cos } else { sin };
    if (quadrant + 1) & 2 != 0 { -v } else { v }
}
