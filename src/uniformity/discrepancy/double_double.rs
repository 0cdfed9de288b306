//! Double-double numbers: an unevaluated sum `hi + lo` of two f64 with `|lo| <= ulp(hi) / 2`,
//! about 106 bits of precision (Dekker 1971; the algorithms of Hida, Li & Bailey's QD library).
//!
//! The L2 discrepancies are differences of terms of size `C^d` whose result can be a million
//! times smaller, so the constant, the `O(N d)` single sum and the final combination are kept in
//! double-double; the `O(N^2 d)` pair terms stay in f64 (their rounding errors are independent
//! and average out).

use std::ops::{Add, Mul, Neg, Sub};

/// `hi + lo`, normalized so that `hi` is `hi + lo` rounded to f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct DoubleDouble {
    hi: f64,
    lo: f64,
}

/// `a + b` exactly, as a normalized pair (Knuth's TwoSum).
fn two_sum(a: f64, b: f64) -> DoubleDouble {
    let s = a + b;
    let bb = s - a;
    let err = (a - (s - bb)) + (b - bb);
    DoubleDouble { hi: s, lo: err }
}

/// `a + b` exactly when `|a| >= |b|` (Dekker's FastTwoSum).
fn quick_two_sum(a: f64, b: f64) -> DoubleDouble {
    let s = a + b;
    DoubleDouble {
        hi: s,
        lo: b - (s - a),
    }
}

/// `a * b` exactly, with the fused multiply-add giving the rounding error.
fn two_prod(a: f64, b: f64) -> DoubleDouble {
    let p = a * b;
    DoubleDouble {
        hi: p,
        lo: a.mul_add(b, -p),
    }
}

impl DoubleDouble {
    pub(super) const ZERO: DoubleDouble = DoubleDouble { hi: 0.0, lo: 0.0 };
    pub(super) const ONE: DoubleDouble = DoubleDouble { hi: 1.0, lo: 0.0 };

    /// An f64, exactly.
    pub(super) fn from_f64(x: f64) -> Self {
        DoubleDouble { hi: x, lo: 0.0 }
    }

    /// `p / q` for integers small enough to be exact in f64, to double-double precision.
    pub(super) fn ratio(p: f64, q: f64) -> Self {
        let hi = p / q;
        // p - q * hi is exact (one fused operation on a residual smaller than ulp(p)).
        let residual = (-q).mul_add(hi, p);
        quick_two_sum(hi, residual / q)
    }

    /// The value rounded to f64.
    pub(super) fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    /// The leading part, `self` rounded to f64.
    pub(super) fn hi(self) -> f64 {
        self.hi
    }

    /// `self * 2^k`: exact unless the result leaves the normal range of f64.
    pub(super) fn scale(self, k: i64) -> Self {
        // Beyond ±5000 binary orders every f64 has overflowed or vanished.
        let k = k.clamp(-5000, 5000) as i32;
        DoubleDouble {
            hi: libm::scalbn(self.hi, k),
            lo: libm::scalbn(self.lo, k),
        }
    }

    /// The absolute value.
    pub(super) fn abs(self) -> Self {
        if self.hi < 0.0 { -self } else { self }
    }

    /// `self / b` for a finite non-zero f64.
    pub(super) fn div_f64(self, b: f64) -> Self {
        let q1 = self.hi / b;
        let remainder = self - two_prod(q1, b);
        let q2 = remainder.hi / b;
        let remainder = remainder - two_prod(q2, b);
        let q3 = remainder.hi / b;
        quick_two_sum(q1, q2) + DoubleDouble::from_f64(q3)
    }
}

impl Add for DoubleDouble {
    type Output = DoubleDouble;
    /// The accurate ("IEEE") double-double sum: relative error about `2^-104`.
    fn add(self, other: DoubleDouble) -> DoubleDouble {
        let s = two_sum(self.hi, other.hi);
        let t = two_sum(self.lo, other.lo);
        let s = quick_two_sum(s.hi, s.lo + t.hi);
        quick_two_sum(s.hi, s.lo + t.lo)
    }
}

impl Add<f64> for DoubleDouble {
    type Output = DoubleDouble;
    fn add(self, other: f64) -> DoubleDouble {
        let s = two_sum(self.hi, other);
        quick_two_sum(s.hi, s.lo + self.lo)
    }
}

impl Neg for DoubleDouble {
    type Output = DoubleDouble;
    fn neg(self) -> DoubleDouble {
        DoubleDouble {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Sub for DoubleDouble {
    type Output = DoubleDouble;
    fn sub(self, other: DoubleDouble) -> DoubleDouble {
        self + (-other)
    }
}

impl Mul for DoubleDouble {
    type Output = DoubleDouble;
    fn mul(self, other: DoubleDouble) -> DoubleDouble {
        let p = two_prod(self.hi, other.hi);
        let cross = self.hi.mul_add(other.lo, self.lo * other.hi);
        quick_two_sum(p.hi, p.lo + cross)
    }
}

impl Mul<f64> for DoubleDouble {
    type Output = DoubleDouble;
    fn mul(self, other: f64) -> DoubleDouble {
        let p = two_prod(self.hi, other);
        quick_two_sum(p.hi, self.lo.mul_add(other, p.lo))
    }
}

#[cfg(test)]
mod tests {
    use super::DoubleDouble;

    #[test]
    fn thirds_sum_to_one_beyond_f64_precision() {
        let third = DoubleDouble::ratio(1.0, 3.0);
        let one = third + third + third;
        // In f64, 1/3 is 1/3 - 2^-54 / 3; the double-double error is below 2^-104.
        assert!((one - DoubleDouble::ONE).abs().to_f64() < 1e-31, "{one:?}");
        assert_eq!((third * 3.0).to_f64(), 1.0);
    }

    #[test]
    fn products_and_division_keep_double_double_precision() {
        // (13/12)^12 * 12^12 = 13^12 exactly (an integer below 2^53).
        let c = (0..12).fold(DoubleDouble::ONE, |p, _| {
            p * DoubleDouble::ratio(13.0, 12.0)
        });
        let scaled = c * 12f64.powi(12);
        assert!(
            (scaled - DoubleDouble::from_f64(13f64.powi(12)))
                .abs()
                .to_f64()
                < 1e-15
        );
        // 1e16 + 1 is not an f64, but 1e16 + 1 - 1e16 is exact in double-double.
        let big = DoubleDouble::from_f64(1e16) + 1.0;
        assert_eq!((big - DoubleDouble::from_f64(1e16)).to_f64(), 1.0);
        let seventh = DoubleDouble::ONE.div_f64(7.0);
        assert!(((seventh * 7.0) - DoubleDouble::ONE).abs().to_f64() < 1e-31);
    }
}
