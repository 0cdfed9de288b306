//! L2 discrepancies of a point set in `[0,1]^d`, from their closed forms: the L2-star
//! discrepancy (Warnock 1972) and the centered and wrap-around discrepancies (Hickernell 1998),
//! and the mixture discrepancy (Zhou, Fang & Ning 2013).
//!
//! Each is the root mean square of a local discrepancy over a family of boxes, and each has the
//! same closed form: for points `x_1 .. x_N` in `d` dimensions,
//!
//! ```text
//! D^2 = C^d - (2 / N) sum_i prod_k g(x_ik) + (1 / N^2) sum_i sum_j prod_k K(x_ik, x_jk)
//! ```
//!
//! | discrepancy | `C` | `g(x)` | `K(x, y)` |
//! |---|---|---|---|
//! | L2-star `T_N` | `1/3` | `(1 - x^2) / 2` | `1 - max(x, y)` |
//! | centered `CD` | `13/12` | `1 + a/2 - a^2/2` | `1 + a/2 + b/2 - t/2` |
//! | wrap-around `WD` | `4/3` | `4/3` | `3/2 - t + t^2` |
//! | mixture `MD` | `19/12` | `5/3 - a/4 - a^2/4` | `15/8 - a/4 - b/4 - 3t/4 + t^2/2` |
//!
//! with `a = |x - 1/2|`, `b = |y - 1/2|`, `t = |x - y|` (Warnock 1972 for `T_N`; Hickernell
//! 1998 for `CD` and `WD`; Zhou, Fang & Ning 2013, eqs. 9, 10 and 18, for `CD`, `WD` and `MD`).
//! The L2-star discrepancy is anchored at the origin; the other three are invariant under
//! reflecting any coordinate (`x -> 1 - x`), and the wrap-around discrepancy also under shifting
//! all points modulo 1. [`Discrepancy`]'s documentation repeats what a user needs from this (the
//! module is private; it is re-exported from `mcint::quality`).
//!
//! # Roots, squares and scipy
//!
//! [`Discrepancy`] names the four; each gives the discrepancy itself
//! ([`root`](Discrepancy::root)), its square ([`squared`](Discrepancy::squared)), or what
//! `scipy.stats.qmc.discrepancy(sample, method=...)` returns ([`scipy`](Discrepancy::scipy): the
//! root of `'L2-star'`, the square of `'CD'`, `'WD'` and `'MD'`).
//!
//! # Cost and accuracy
//!
//! The sum over pairs uses its symmetry (`N (N + 1) / 2` kernel products) and two buffers of `N`
//! numbers, built one coordinate column at a time; no `N x N` matrix is formed.
//!
//! The result is a difference of terms of size `C^d` that, for a good point set, can be a
//! million times larger than it, so plain f64 arithmetic loses digits in proportion (scipy's
//! naive sums are off by up to `1e-6` relative on the test sets). Here the constant, the single
//! sum and the final combination are kept in double-double arithmetic; the final rounding of
//! each pair factor is recovered exactly (Fast2Sum) and carried to first order beside the
//! product; and the pair terms are added with compensated summation (Ogita, Rump & Oishi 2005,
//! Sum2) along each row and in double-double across rows. What is left is the rounding inside
//! each factor and product, a small fraction of `eps * C^d` in absolute terms: against exact
//! rational arithmetic the relative error on the test sets is at most `6e-13` (1024 Sobol'
//! points in 5 dimensions, `MD^2 = 1e-4`). See `tests/quality/quality_discrepancy.rs` and its
//! reference script `tests/data/discrepancy_scipy.py`.
//!
//! # High dimension
//!
//! The terms are products of `d` factors: `C^d`, and per point a diagonal pair term
//! `prod_k K(x_ik, x_ik)`, which is `1.5^d` for `WD`, between 1 and `1.5^d` for `CD`, between
//! `1.625^d` and `1.875^d` for `MD`, and at most 1 for `T_N` (whose `C^d` is `3^-d`). In a few
//! hundred to a few thousand dimensions they leave the range of f64 (plain arithmetic gave
//! inf, NaN, 0 or subnormals with few correct bits, and roots of NaN read as 0). So the
//! constant, the sums and each running product carry a power-of-two scale: a product is
//! rescaled once it passes `2^±300` (checked every few coordinates, so it cannot overflow in
//! between), a sum once a term is `2^600` times its scale, and the final combination is done
//! in the scale of its largest part. Below those thresholds nothing is rescaled and the
//! arithmetic is exactly the plain one, so results in low dimension are unchanged to the bit.
//!
//! The result is then exact up to the rounding described above, at any dimension, but it may
//! not be an f64: the squared forms return an error when the square is above `1.8e308` or below
//! `2.2e-308` (the smallest normal f64), the roots only when the root is. That happens from
//! about 1750 dimensions for `CD^2` and `WD^2` (3500 for their roots), 1130 for `MD^2` (2260),
//! and 645 for `T_N^2` (1290) in the worst case, later for typical point sets. A result no
//! larger than its rounding-error bound, `(d + 3) 2^-53` times the pair term (one rounding per
//! coordinate in each pair product), is an error too: every discrepancy of a finite set is
//! positive, and such a result has no known digit. See `tests/data/discrepancy_high_dim.py`.

/// The user-facing summary of the module documentation, shared by every public function.
macro_rules! cost_accuracy_errors {
    () => {
        "# Cost, accuracy and errors\n\n\
         The exact closed form in `O(N^2 d)` time and `O(N)` extra memory, on one thread: 4096 \
         points in 10 dimensions take about 0.1 s. The squared discrepancy is a difference of \
         terms of size `C^d` (`C` = 1/3, 13/12, 4/3 or 19/12) that can be a million times \
         larger than the result, so the sums are compensated and the constant and the final \
         combination kept in double-double arithmetic: against exact rational arithmetic the \
         relative error on the test sets is at most `6e-13`, where scipy's plain sums are off by \
         up to `1e-6`. The error grows as the discrepancy shrinks relative to `C^d`.\n\n\
         Returns [`Error::InvalidParameter`](crate::Error::InvalidParameter) for a set of no \
         points, or for a coordinate that is NaN or outside `[0, 1]` (the message names the \
         point and the dimension).\n\n\
         # High dimension\n\n\
         The terms are products of `d` factors, such as `C^d` and up to `1.5^d` (`CD`, `WD`) \
         or `1.875^d` (`MD`) per point, or `3^-d` for L2-star: they are computed with a \
         power-of-two scale, so no intermediate overflows or underflows and the accuracy \
         above holds in any dimension. The result itself must be a normal f64, though: the \
         squared forms return [`Error::InvalidParameter`](crate::Error::InvalidParameter) \
         (naming the point set, with the value's size) when the square is above `1.8e308` \
         or below `2.2e-308`, which can happen from about 1750 dimensions for `CD^2` and \
         `WD^2`, 1130 for `MD^2` and 645 for `T_N^2`; the roots then still work, up to about \
         twice those dimensions. The same error is returned, rather than a number with no \
         correct digit, if the result is within its rounding-error bound (`d + 3` roundings \
         of the pair terms; this needs far more points than `O(N^2 d)` time allows)."
    };
}

mod double_double;

use crate::error::{Error, Result};
use crate::points::Points;
use double_double::DoubleDouble;

/// Checks that `points` holds at least one point and that every coordinate is in `[0, 1]`.
pub(crate) fn check_unit_cube(points: &Points) -> Result<()> {
    if points.is_empty() {
        return Err(Error::invalid("number of points", 0, "at least 1"));
    }
    for dim in 0..points.dims() {
        for (index, &x) in points.column(dim).iter().enumerate() {
            if !(0.0..=1.0).contains(&x) {
                return Err(Error::invalid(
                    "coordinate",
                    format!("{x} (point {index}, dimension {dim})"),
                    "a number in [0, 1]",
                ));
            }
        }
    }
    Ok(())
}

/// One discrepancy of the closed form in the module documentation.
trait Kernel {
    /// The discrepancy's symbol and its variant of [`Discrepancy`], for error messages.
    const NAME: &'static str;
    const ROOT_FN: &'static str;
    /// How the result grows (or, for L2-star, shrinks) with the dimension, and from which
    /// dimension it can leave the normal range of f64 (worst case: one point at a corner, or
    /// the centre for `MD`), for error messages.
    const LIMIT: &'static str;
    /// The running products are checked for rescaling after every `CHECK_EVERY` coordinates:
    /// few enough that, starting within `2^±RESCALE_AT`, they cannot leave the normal range of
    /// f64 in between (the factors lie in `[2^-54, 1]`, or are 0, for L2-star, and in
    /// `[1, 15/8]` for the others).
    const CHECK_EVERY: usize;
    /// The constant `C` as `numerator / denominator`.
    const CONSTANT: (f64, f64);
    /// The one-point factor `g(x)`, in double-double.
    fn single(x: f64) -> DoubleDouble;
    /// The two-point factor is `K(x, y) = PAIR_BASE + pair_offset(x, y)` with
    /// `|pair_offset| <= PAIR_BASE`, so the rounding of the sum can be recovered exactly.
    const PAIR_BASE: f64;
    /// The varying part of `K(x, y)`.
    fn pair_offset(x: f64, y: f64) -> f64;
}

/// `|x - 1/2|` in double-double (the subtraction is inexact for `x < 1/4`).
fn distance_to_centre(x: f64) -> DoubleDouble {
    (DoubleDouble::from_f64(x) + -0.5).abs()
}

struct Star;
impl Kernel for Star {
    const NAME: &'static str = "T_N";
    const ROOT_FN: &'static str = "Discrepancy::L2Star.root";
    const LIMIT: &'static str = "T_N^2 shrinks with the dimension (its terms are products of d \
        factors of at most 1, such as 3^-d and prod_k (1 - x_ik)), and can fall below 2.2e-308 \
        from about 645 dimensions, T_N from about 1290";
    const CHECK_EVERY: usize = 8;
    const CONSTANT: (f64, f64) = (1.0, 3.0);
    fn single(x: f64) -> DoubleDouble {
        let x = DoubleDouble::from_f64(x);
        (DoubleDouble::ONE - x * x) * 0.5
    }
    const PAIR_BASE: f64 = 1.0;
    fn pair_offset(x: f64, y: f64) -> f64 {
        -x.max(y)
    }
}

struct Centered;
impl Kernel for Centered {
    const NAME: &'static str = "CD";
    const ROOT_FN: &'static str = "Discrepancy::Centered.root";
    const LIMIT: &'static str = "CD^2 grows with the dimension (its terms are products of d \
        factors, up to 1.5^d per point: prod_k (1 + |x_ik - 1/2|)), and can pass 1.8e308 from \
        about 1750 dimensions, CD from about 3500";
    const CHECK_EVERY: usize = 256;
    const CONSTANT: (f64, f64) = (13.0, 12.0);
    fn single(x: f64) -> DoubleDouble {
        let a = distance_to_centre(x);
        DoubleDouble::ONE + (a - a * a) * 0.5
    }
    const PAIR_BASE: f64 = 1.0;
    fn pair_offset(x: f64, y: f64) -> f64 {
        0.5 * ((x - 0.5).abs() + (y - 0.5).abs() - (x - y).abs())
    }
}

struct WrapAround;
impl Kernel for WrapAround {
    const NAME: &'static str = "WD";
    const ROOT_FN: &'static str = "Discrepancy::WrapAround.root";
    const LIMIT: &'static str = "WD^2 grows with the dimension (its terms are products of d \
        factors, 1.5^d per point), and can pass 1.8e308 from about 1750 dimensions, WD from \
        about 3500";
    const CHECK_EVERY: usize = 256;
    const CONSTANT: (f64, f64) = (4.0, 3.0);
    fn single(_x: f64) -> DoubleDouble {
        // The integral of K(x, y) over y, the same for every x.
        DoubleDouble::ratio(4.0, 3.0)
    }
    const PAIR_BASE: f64 = 1.5;
    fn pair_offset(x: f64, y: f64) -> f64 {
        let t = (x - y).abs();
        -t * (1.0 - t)
    }
}

struct Mixture;
impl Kernel for Mixture {
    const NAME: &'static str = "MD";
    const ROOT_FN: &'static str = "Discrepancy::Mixture.root";
    const LIMIT: &'static str = "MD^2 grows with the dimension (its terms are products of d \
        factors, 1.625^d to 1.875^d per point: prod_k (15/8 - |x_ik - 1/2| / 2)), and can pass \
        1.8e308 from about 1130 dimensions, MD from about 2260";
    const CHECK_EVERY: usize = 256;
    const CONSTANT: (f64, f64) = (19.0, 12.0);
    fn single(x: f64) -> DoubleDouble {
        let a = distance_to_centre(x);
        DoubleDouble::ratio(5.0, 3.0) - (a + a * a) * 0.25
    }
    const PAIR_BASE: f64 = 1.875;
    fn pair_offset(x: f64, y: f64) -> f64 {
        let t = (x - y).abs();
        -(0.25 * ((x - 0.5).abs() + (y - 0.5).abs()) + t * (0.75 - 0.5 * t))
    }
}

/// `sum_j (products[j] + corrections[j])` as an unevaluated pair `(sum, error)`: the products
/// are added with their rounding errors recovered by TwoSum and accumulated, with the small
/// corrections, in a second sum (Ogita, Rump & Oishi 2005, Sum2), so the result is as accurate
/// as if summed in twice the working precision.
fn compensated_row_sum(products: &[f64], corrections: &[f64]) -> (f64, f64) {
    let (mut sum, mut error) = (0.0f64, 0.0f64);
    for (&p, &c) in products.iter().zip(corrections) {
        let next = sum + p;
        let p_part = next - sum;
        error += ((sum - (next - p_part)) + (p - p_part)) + c;
        sum = next;
    }
    (sum, error)
}

/// Running products are rescaled by a power of two once they pass `2^±RESCALE_AT`, far
/// inside f64's range (`2^±1022`), so that in high dimension they neither overflow nor
/// underflow. Below that no product is rescaled and the arithmetic is exactly the plain one.
const RESCALE_AT: i32 = 300;

/// Sums are rescaled once a term passes `2^SUM_HEADROOM` times their current scale.
const SUM_HEADROOM: i64 = 600;

/// The power of two to divide a running product by, if `largest` (its largest magnitude) has
/// left `[2^-RESCALE_AT, 2^RESCALE_AT]`.
fn rescale_shift(largest: f64) -> Option<i64> {
    let e = libm::ilogb(largest);
    (largest != 0.0 && !(-RESCALE_AT..=RESCALE_AT).contains(&e)).then_some(i64::from(e))
}

/// The binary exponent of a non-zero finite `x`: `2^e <= |x| < 2^(e+1)`.
fn exponent(x: f64) -> i64 {
    i64::from(libm::ilogb(x))
}

/// A sum of non-negative terms (up to tiny negative corrections) held as `dd * 2^exp`, so that
/// terms of size `2^±3000` neither overflow nor underflow. While every term stays within
/// `2^±SUM_HEADROOM` the scale stays 0 and the additions are exactly the plain double-double
/// ones.
#[derive(Clone, Copy)]
struct ScaledSum {
    dd: DoubleDouble,
    exp: i64,
}

impl ScaledSum {
    const ZERO: ScaledSum = ScaledSum {
        dd: DoubleDouble::ZERO,
        exp: 0,
    };

    /// Moves the scale for a term of binary exponent `magnitude` (absolute): up to it when the
    /// term would be too large, or to it when the sum is still 0 and the term far from the
    /// scale. Earlier terms far below a new scale vanish; they are negligible next to it
    /// because all terms are non-negative.
    fn make_room(&mut self, magnitude: i64) {
        if self.dd.hi() == 0.0 {
            if (magnitude - self.exp).abs() > SUM_HEADROOM {
                self.exp = magnitude;
            }
        } else if magnitude - self.exp > SUM_HEADROOM {
            self.dd = self.dd.scale(self.exp - magnitude);
            self.exp = magnitude;
        }
    }

    /// Adds `x * 2^exp`.
    fn add_f64(&mut self, x: f64, exp: i64) {
        if x != 0.0 {
            self.make_room(exp + exponent(x));
        }
        let shift = exp - self.exp;
        self.dd = self.dd
            + if shift == 0 {
                x
            } else {
                DoubleDouble::from_f64(x).scale(shift).to_f64()
            };
    }

    /// Adds `x * 2^exp`.
    fn add(&mut self, x: DoubleDouble, exp: i64) {
        if x.hi() != 0.0 {
            self.make_room(exp + exponent(x.hi()));
        }
        let shift = exp - self.exp;
        self.dd = self.dd + if shift == 0 { x } else { x.scale(shift) };
    }

    /// The binary exponent of the value, if it is not 0.
    fn magnitude(self) -> Option<i64> {
        (self.dd.hi() != 0.0).then(|| self.exp + exponent(self.dd.hi()))
    }

    /// The value divided by `2^exp`.
    fn at(self, exp: i64) -> DoubleDouble {
        if exp == self.exp {
            self.dd
        } else {
            self.dd.scale(self.exp - exp)
        }
    }
}

/// `C^d` as a [`ScaledSum`], by repeated squaring with the partial results kept near 1.
fn scaled_power(c: DoubleDouble, mut d: usize) -> ScaledSum {
    let (mut base, mut base_exp) = (c, 0i64);
    let (mut result, mut result_exp) = (DoubleDouble::ONE, 0i64);
    let rescale = |x: &mut DoubleDouble, exp: &mut i64| {
        if let Some(shift) = rescale_shift(x.hi()) {
            *x = x.scale(-shift);
            *exp += shift;
        }
    };
    while d > 0 {
        if d & 1 == 1 {
            result = result * base;
            result_exp += base_exp;
            rescale(&mut result, &mut result_exp);
        }
        base = base * base;
        base_exp *= 2;
        rescale(&mut base, &mut base_exp);
        d >>= 1;
    }
    ScaledSum {
        dd: result,
        exp: result_exp,
    }
}

/// A squared discrepancy as `value * 2^exp`, with a bound on its rounding error in the same
/// scale, so that values beyond f64's range can still give a representable root.
struct Squared {
    value: f64,
    exp: i64,
    error_bound: f64,
}

/// The squared discrepancy of kernel `K`: the closed form, with the compensations described in
/// the module documentation. The constant, the sums and the running products carry their own
/// power-of-two scale, so no intermediate overflows or underflows in high dimension.
fn squared<K: Kernel>(points: &Points) -> Result<Squared> {
    check_unit_cube(points)?;
    let n = points.len();
    let dims = points.dims();
    let columns: Vec<&[f64]> = (0..dims).map(|dim| points.column(dim)).collect();

    let constant = scaled_power(DoubleDouble::ratio(K::CONSTANT.0, K::CONSTANT.1), dims);

    let mut single_sum = ScaledSum::ZERO;
    for i in 0..n {
        let (mut product, mut exp) = (DoubleDouble::ONE, 0i64);
        for (k, column) in columns.iter().enumerate() {
            product = product * K::single(column[i]);
            if (k + 1) % K::CHECK_EVERY == 0
                && let Some(shift) = rescale_shift(product.hi())
            {
                product = product.scale(-shift);
                exp += shift;
            }
        }
        single_sum.add(product, exp);
    }

    // Row i holds the K-products of point i with points i.., built one column at a time so the
    // inner loop runs over contiguous memory. Each factor is rounded once, with its rounding
    // error recovered exactly (Fast2Sum), and carried to first order beside the product: the
    // term is products[j] + corrections[j], times 2^row_exp.
    let mut products = vec![1.0f64; n];
    let mut corrections = vec![0.0f64; n];
    let mut pair_sum = ScaledSum::ZERO;
    for i in 0..n {
        let products = &mut products[i..];
        let corrections = &mut corrections[i..];
        products.fill(1.0);
        corrections.fill(0.0);
        let mut row_exp = 0i64;
        for (k, column) in columns.iter().enumerate() {
            let x = column[i];
            for ((p, c), &y) in products
                .iter_mut()
                .zip(corrections.iter_mut())
                .zip(&column[i..])
            {
                let offset = K::pair_offset(x, y);
                let factor = K::PAIR_BASE + offset;
                let rounding = (K::PAIR_BASE - factor) + offset;
                *c = *c * factor + *p * rounding;
                *p *= factor;
            }
            if (k + 1) % K::CHECK_EVERY == 0 {
                let largest = products.iter().fold(0.0f64, |m, &p| m.max(p));
                if let Some(shift) = rescale_shift(largest) {
                    for v in products.iter_mut().chain(corrections.iter_mut()) {
                        *v = libm::scalbn(*v, -shift as i32);
                    }
                    row_exp += shift;
                }
            }
        }
        // The diagonal term once, the terms j > i twice (K is symmetric).
        let (sum, error) = compensated_row_sum(&products[1..], &corrections[1..]);
        for term in [products[0], corrections[0], 2.0 * sum, 2.0 * error] {
            pair_sum.add_f64(term, row_exp);
        }
    }

    // One scale for the final combination: the common one when the parts share it (always in
    // low dimension), else that of the largest part, so the largest is near 1.
    let parts = [constant, single_sum, pair_sum];
    let exp = if parts.iter().all(|p| p.exp == parts[0].exp) {
        parts[0].exp
    } else {
        parts
            .iter()
            .filter_map(|p| p.magnitude())
            .max()
            .unwrap_or(0)
    };
    let [constant, single_sum, pair_sum] = parts.map(|p| p.at(exp));
    let nf = n as f64;
    let single_term = (single_sum * 2.0).div_f64(nf);
    let pair_term = pair_sum.div_f64(nf).div_f64(nf);
    let result = constant - single_term + pair_term;
    // Each pair product carries up to one rounding per coordinate (relative 2^-53 each, the
    // rest of the arithmetic is double-double), so this bounds the error of the result.
    let half_eps = 0.5 * f64::EPSILON;
    let error_bound = (dims as f64 + 3.0) * half_eps * pair_term.to_f64()
        + (dims as f64 + 10.0) * half_eps * half_eps * (constant + single_term).to_f64();
    Ok(Squared {
        value: result.to_f64(),
        exp,
        error_bound,
    })
}

/// `10^x` as text for `x * log10(2)` binary orders, for error messages.
fn power_of_ten(mantissa: f64, exp: i64) -> String {
    format!(
        "10^{:.1}",
        mantissa.abs().log10() + exp as f64 * std::f64::consts::LOG10_2
    )
}

/// The error for a squared discrepancy whose rounding error reaches its value.
fn cancelled<K: Kernel>(points: &Points, sq: &Squared) -> Error {
    Error::invalid(
        "point set",
        format!("{} points in {} dimensions", points.len(), points.dims()),
        format!(
            "a set whose {name}^2 exceeds the rounding error of its closed form: the terms \
             cancel to {value}, within their rounding error of {bound}, so no digit of {name} \
             is known",
            name = K::NAME,
            value = power_of_ten(sq.value, sq.exp),
            bound = power_of_ten(sq.error_bound, sq.exp),
        ),
    )
}

/// The error for a result (`what`, about `10^log10`) outside the normal range of f64.
fn out_of_range<K: Kernel>(points: &Points, what: &str, log10: f64, hint: &str) -> Error {
    Error::invalid(
        "point set",
        format!("{} points in {} dimensions", points.len(), points.dims()),
        format!(
            "a set whose {what} is a normal f64 (2.2e-308 to 1.8e308): it is about \
             10^{log10:.1}. {limit}{hint}",
            limit = K::LIMIT,
        ),
    )
}

/// `m * 2^e` if it is a normal f64 (`m` itself when `e` is 0 and `m` is normal: nothing was
/// rescaled).
fn in_range(m: f64, e: i64) -> Option<f64> {
    let magnitude = exponent(m) + e;
    (-1022..=1023)
        .contains(&magnitude)
        .then(|| libm::scalbn(m, e as i32))
}

/// Ok if the squared discrepancy exceeds its rounding error bound (it is positive for every
/// point set, so a value within the bound has no known digit).
fn check_digits<K: Kernel>(points: &Points, sq: &Squared) -> Result<()> {
    if sq.value > sq.error_bound {
        Ok(())
    } else {
        Err(cancelled::<K>(points, sq))
    }
}

/// The squared discrepancy of kernel `K` as an f64, or an error saying why it is not one.
fn squared_value<K: Kernel>(points: &Points) -> Result<f64> {
    let sq = squared::<K>(points)?;
    check_digits::<K>(points, &sq)?;
    if let Some(v) = in_range(sq.value, sq.exp) {
        return Ok(v);
    }
    let log10 = sq.value.log10() + sq.exp as f64 * std::f64::consts::LOG10_2;
    let hint = if (-2044..=2046).contains(&(exponent(sq.value) + sq.exp)) {
        format!(". Its root is a normal f64 here: use {}", K::ROOT_FN)
    } else {
        String::new()
    };
    Err(out_of_range::<K>(
        points,
        &format!("{}^2", K::NAME),
        log10,
        &hint,
    ))
}

/// The discrepancy of kernel `K` (the root of its square), or an error saying why it is not
/// representable.
fn root_value<K: Kernel>(points: &Points) -> Result<f64> {
    let sq = squared::<K>(points)?;
    check_digits::<K>(points, &sq)?;
    // sqrt(v 2^e) = sqrt(v 2^(e mod 2)) 2^(e div 2), exact in the scaling.
    let (odd, half) = (sq.exp.rem_euclid(2), sq.exp.div_euclid(2));
    let root = (sq.value * if odd == 1 { 2.0 } else { 1.0 }).sqrt();
    if let Some(v) = in_range(root, half) {
        return Ok(v);
    }
    let log10 = root.log10() + half as f64 * std::f64::consts::LOG10_2;
    Err(out_of_range::<K>(points, K::NAME, log10, ""))
}

/// An L2 discrepancy of a point set in `[0, 1]^d` (scipy's `qmc.discrepancy` methods), each
/// as a root ([`root`](Self::root)) or a square ([`squared`](Self::squared)); see the module
/// documentation for the closed forms.
///
/// | variant | scipy `method` | [`scipy`](Self::scipy) returns, as scipy does |
/// |---|---|---|
/// | [`L2Star`](Self::L2Star) `T_N` | `'L2-star'` | the root |
/// | [`Centered`](Self::Centered) `CD` | `'CD'` | the square |
/// | [`WrapAround`](Self::WrapAround) `WD` | `'WD'` | the square |
/// | [`Mixture`](Self::Mixture) `MD` | `'MD'` | the square |
///
#[doc = cost_accuracy_errors!()]
///
/// ```
/// use mcint::quality::Discrepancy;
/// use mcint::sampler::{Independent, Sampler, Scramble, Sobol};
/// let sobol = Sobol::new(3, Scramble::Owen, 1)?.random(256)?;
/// let random = Independent::new(3, 1)?.random(256)?;
/// for kind in Discrepancy::ALL {
///     assert!(kind.root(&sobol)? < kind.root(&random)?, "{}", kind.name());
/// }
/// assert_eq!("CD".parse::<Discrepancy>()?, Discrepancy::Centered);
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Discrepancy {
    /// The L2-star discrepancy `T_N` (Warnock 1972): the root mean square over `t` in
    /// `[0,1]^d` of `vol([0, t)) - #{x_i in [0, t)} / N`, by Warnock's closed form
    ///
    /// ```text
    /// T_N^2 = 3^-d - (2^(1-d) / N) sum_i prod_k (1 - x_ik^2)
    ///              + (1 / N^2) sum_i sum_j prod_k (1 - max(x_ik, x_jk))
    /// ```
    ///
    /// ```
    /// use mcint::{Points, quality::Discrepancy};
    /// // The N midpoints (2i - 1) / (2N) of [0, 1] have T_N = 1 / (sqrt(12) N).
    /// let points = Points::from_rows(&[[0.125], [0.375], [0.625], [0.875]])?;
    /// let t = Discrepancy::L2Star.root(&points)?;
    /// assert!((t - 1.0 / (12f64.sqrt() * 4.0)).abs() < 1e-15);
    /// // One point x in one dimension: T^2 = 1/3 - (1 - x^2) + (1 - x) = x^2 - x + 1/3.
    /// let one = Points::from_rows(&[[0.25]])?;
    /// let t2 = Discrepancy::L2Star.squared(&one)?;
    /// assert!((t2 - (0.0625 - 0.25 + 1.0 / 3.0)).abs() < 1e-16);
    /// // Coordinates must lie in [0, 1].
    /// assert!(Discrepancy::L2Star.squared(&Points::from_rows(&[[1.5]])?).is_err());
    /// # Ok::<(), mcint::Error>(())
    /// ```
    L2Star,
    /// The centered L2 discrepancy `CD` (Hickernell 1998): the root mean square local
    /// discrepancy of the boxes spanned by a point `t` and the corner of the unit cube nearest
    /// to `t`. With `a_ik = |x_ik - 1/2|`:
    ///
    /// ```text
    /// CD^2 = (13/12)^d - (2 / N) sum_i prod_k (1 + a_ik / 2 - a_ik^2 / 2)
    ///      + (1 / N^2) sum_i sum_j prod_k (1 + a_ik / 2 + a_jk / 2 - |x_ik - x_jk| / 2)
    /// ```
    ///
    /// Invariant under reflecting any coordinate, `x -> 1 - x`.
    ///
    /// ```
    /// use mcint::{Points, quality::Discrepancy};
    /// // One point at the centre of [0, 1]: CD^2 = 13/12 - 2 + 1 = 1/12.
    /// let centre = Points::from_rows(&[[0.5]])?;
    /// assert!((Discrepancy::Centered.root(&centre)? - (1.0f64 / 12.0).sqrt()).abs() < 1e-15);
    /// // Reflecting a coordinate leaves CD unchanged.
    /// let mut points = Points::from_rows(&[[0.125, 0.25], [0.5, 0.875], [0.75, 0.5]])?;
    /// let before = Discrepancy::Centered.squared(&points)?;
    /// for x in points.column_mut(1) {
    ///     *x = 1.0 - *x;
    /// }
    /// assert!((Discrepancy::Centered.squared(&points)? - before).abs() < 1e-15);
    /// # Ok::<(), mcint::Error>(())
    /// ```
    Centered,
    /// The wrap-around L2 discrepancy `WD` (Hickernell 1998): the root mean square local
    /// discrepancy of boxes that may wrap around the faces of the unit cube (boxes on the
    /// torus). With `t_ijk = |x_ik - x_jk|`:
    ///
    /// ```text
    /// WD^2 = -(4/3)^d + (1 / N^2) sum_i sum_j prod_k (3/2 - t_ijk + t_ijk^2)
    /// ```
    ///
    /// Invariant under reflecting any coordinate and under shifting all points modulo 1.
    ///
    /// ```
    /// use mcint::{Points, quality::Discrepancy};
    /// // One point anywhere in [0, 1]: WD^2 = -4/3 + 3/2 = 1/6.
    /// let one = Points::from_rows(&[[0.9]])?;
    /// assert!((Discrepancy::WrapAround.root(&one)? - (1.0f64 / 6.0).sqrt()).abs() < 1e-15);
    /// // Shifting every point by the same amount modulo 1 leaves WD unchanged.
    /// let before = Discrepancy::WrapAround.squared(&Points::from_rows(&[[0.0], [0.25], [0.625]])?)?;
    /// let after = Discrepancy::WrapAround.squared(&Points::from_rows(&[[0.5], [0.75], [0.125]])?)?;
    /// assert!((after - before).abs() < 1e-15);
    /// // One point in 2000 dimensions: WD^2 = 1.5^2000 - (4/3)^2000, about 10^352, is beyond
    /// // f64, but its root, about 1.5^1000 = 1.2e176, is returned.
    /// let far = Points::new(2000, 1)?;
    /// let err = Discrepancy::WrapAround.squared(&far).unwrap_err();
    /// assert!(err.to_string().contains("1.8e308"));
    /// let wd = Discrepancy::WrapAround.root(&far)?;
    /// assert!((wd / 1.5f64.powi(1000) - 1.0).abs() < 1e-12);
    /// # Ok::<(), mcint::Error>(())
    /// ```
    WrapAround,
    /// The mixture L2 discrepancy `MD` (Zhou, Fang & Ning 2013, eq. 18), which mixes the
    /// centered and wrap-around families of boxes. With `a_ik = |x_ik - 1/2|` and
    /// `t_ijk = |x_ik - x_jk|`:
    ///
    /// ```text
    /// MD^2 = (19/12)^d - (2 / N) sum_i prod_k (5/3 - a_ik / 4 - a_ik^2 / 4)
    ///      + (1 / N^2) sum_i sum_j prod_k (15/8 - a_ik / 4 - a_jk / 4 - 3 t_ijk / 4 + t_ijk^2 / 2)
    /// ```
    ///
    /// Invariant under reflecting any coordinate.
    ///
    /// ```
    /// use mcint::{Points, quality::Discrepancy};
    /// // One point at the centre of [0, 1]: MD^2 = 19/12 - 2 * 5/3 + 15/8 = 1/8.
    /// let centre = Points::from_rows(&[[0.5]])?;
    /// assert!((Discrepancy::Mixture.root(&centre)? - 0.125f64.sqrt()).abs() < 1e-15);
    /// // An empty set or a NaN coordinate is an error, not a panic.
    /// assert!(Discrepancy::Mixture.squared(&Points::new(3, 0)?).is_err());
    /// let err = Discrepancy::Mixture.squared(&Points::from_rows(&[[0.0, f64::NAN]])?).unwrap_err();
    /// assert!(err.to_string().contains("point 0, dimension 1"));
    /// # Ok::<(), mcint::Error>(())
    /// ```
    Mixture,
}

impl Discrepancy {
    /// Every discrepancy, in the order of the table above.
    ///
    /// ```
    /// assert_eq!(mcint::quality::Discrepancy::ALL.len(), 4);
    /// ```
    pub const ALL: [Discrepancy; 4] = [
        Discrepancy::L2Star,
        Discrepancy::Centered,
        Discrepancy::WrapAround,
        Discrepancy::Mixture,
    ];

    /// The discrepancy itself: `T_N`, `CD`, `WD` or `MD`.
    ///
    /// ```
    /// use mcint::{Points, quality::Discrepancy};
    /// let p = Points::from_rows(&[[0.2, 0.7], [0.6, 0.1]])?;
    /// let (root, square) = (Discrepancy::Centered.root(&p)?, Discrepancy::Centered.squared(&p)?);
    /// assert!((root * root - square).abs() < 1e-15);
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn root(self, points: &Points) -> Result<f64> {
        match self {
            Discrepancy::L2Star => root_value::<Star>(points),
            Discrepancy::Centered => root_value::<Centered>(points),
            Discrepancy::WrapAround => root_value::<WrapAround>(points),
            Discrepancy::Mixture => root_value::<Mixture>(points),
        }
    }

    /// The square of the discrepancy: `T_N^2`, `CD^2`, `WD^2` or `MD^2`.
    ///
    /// ```
    /// use mcint::{Points, quality::Discrepancy};
    /// let one = Points::from_rows(&[[0.5]])?;
    /// assert!((Discrepancy::Centered.squared(&one)? - 1.0 / 12.0).abs() < 1e-15);
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn squared(self, points: &Points) -> Result<f64> {
        match self {
            Discrepancy::L2Star => squared_value::<Star>(points),
            Discrepancy::Centered => squared_value::<Centered>(points),
            Discrepancy::WrapAround => squared_value::<WrapAround>(points),
            Discrepancy::Mixture => squared_value::<Mixture>(points),
        }
    }

    /// The value scipy's `qmc.discrepancy(sample, method=...)` returns: the root of L2-star,
    /// the square of the others.
    ///
    /// ```
    /// use mcint::{Points, quality::Discrepancy};
    /// let p = Points::from_rows(&[[0.2, 0.7], [0.6, 0.1]])?;
    /// assert_eq!(Discrepancy::L2Star.scipy(&p)?, Discrepancy::L2Star.root(&p)?);
    /// assert_eq!(Discrepancy::Mixture.scipy(&p)?, Discrepancy::Mixture.squared(&p)?);
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn scipy(self, points: &Points) -> Result<f64> {
        match self {
            Discrepancy::L2Star => self.root(points),
            _ => self.squared(points),
        }
    }

    /// The name the `quality` binary takes: `l2-star`, `centered`, `wrap-around`, `mixture`.
    ///
    /// ```
    /// assert_eq!(mcint::quality::Discrepancy::WrapAround.name(), "wrap-around");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            Discrepancy::L2Star => "l2-star",
            Discrepancy::Centered => "centered",
            Discrepancy::WrapAround => "wrap-around",
            Discrepancy::Mixture => "mixture",
        }
    }

    /// scipy's name of the method: `L2-star`, `CD`, `WD`, `MD`.
    ///
    /// ```
    /// assert_eq!(mcint::quality::Discrepancy::Centered.scipy_name(), "CD");
    /// ```
    pub fn scipy_name(self) -> &'static str {
        match self {
            Discrepancy::L2Star => "L2-star",
            Discrepancy::Centered => "CD",
            Discrepancy::WrapAround => "WD",
            Discrepancy::Mixture => "MD",
        }
    }
}

impl std::str::FromStr for Discrepancy {
    type Err = Error;

    /// A discrepancy by its name or scipy's (`centered` or `CD`, ...).
    ///
    /// ```
    /// use mcint::quality::Discrepancy;
    /// assert_eq!("mixture".parse::<Discrepancy>()?, Discrepancy::Mixture);
    /// assert!("star".parse::<Discrepancy>().is_err());
    /// # Ok::<(), mcint::Error>(())
    /// ```
    fn from_str(name: &str) -> Result<Discrepancy> {
        Discrepancy::ALL
            .into_iter()
            .find(|d| name == d.name() || name == d.scipy_name())
            .ok_or_else(|| {
                Error::invalid(
                    "discrepancy",
                    name,
                    "one of l2-star, centered, wrap-around, mixture (or scipy's L2-star, CD, \
                     WD, MD)",
                )
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `log2` of `dd * 2^exp`.
    fn log2(s: ScaledSum) -> f64 {
        s.exp as f64 + s.dd.to_f64().log2()
    }

    #[test]
    fn scaled_powers_go_beyond_f64() {
        assert_eq!(
            scaled_power(DoubleDouble::ratio(19.0, 12.0), 0).dd.to_f64(),
            1.0
        );
        for (p, q, d) in [(19.0, 12.0, 3000), (4.0, 3.0, 100_000), (1.0, 3.0, 5000)] {
            let power = scaled_power(DoubleDouble::ratio(p, q), d);
            let want = d as f64 * (p / q).log2();
            assert!(
                (log2(power) - want).abs() <= 1e-12 * want.abs(),
                "({p}/{q})^{d}: 2^{} vs 2^{want}",
                log2(power)
            );
        }
        // In range the scale is 0 and the value the plain product's.
        let power = scaled_power(DoubleDouble::ratio(13.0, 12.0), 12);
        assert_eq!(power.exp, 0);
        assert!((power.dd.to_f64() * 12f64.powi(12) - 13f64.powi(12)).abs() < 1e-2);
    }

    #[test]
    fn sums_keep_terms_far_outside_f64() {
        let mut sum = ScaledSum::ZERO;
        sum.add_f64(1.5, -3000);
        sum.add_f64(0.5, -3000);
        assert_eq!(log2(sum), -2999.0);
        // A term 2^4000 times larger moves the scale; the earlier ones are negligible.
        sum.add_f64(3.0, 1000);
        assert_eq!(log2(sum), 1000.0 + 3f64.log2());
        // Ordinary terms leave the scale at 0 (the plain arithmetic).
        let mut sum = ScaledSum::ZERO;
        sum.add_f64(1e100, 0);
        sum.add(DoubleDouble::from_f64(1e-100), 0);
        assert_eq!((sum.dd.to_f64(), sum.exp), (1e100, 0));
    }

    #[test]
    fn a_result_within_its_rounding_error_is_an_error() {
        let points = Points::new(2, 1).unwrap();
        let sq = Squared {
            value: 1e-30,
            exp: 0,
            error_bound: 1e-20,
        };
        let err = check_digits::<Centered>(&points, &sq)
            .unwrap_err()
            .to_string();
        assert!(err.contains("no digit of CD is known"), "{err}");
        assert!(err.contains("1 points in 2 dimensions"), "{err}");
        let sq = Squared { value: 1e-19, ..sq };
        assert!(check_digits::<Centered>(&points, &sq).is_ok());
    }
}
