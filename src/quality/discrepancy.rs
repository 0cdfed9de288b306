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
//! all points modulo 1. The public functions repeat what a user needs from this (the module is
//! private; they are re-exported from `mcint::quality`).
//!
//! # Which form each function returns, and scipy
//!
//! Every measure has a function for the discrepancy itself (the root) and one for its square:
//!
//! | function | returns | `scipy.stats.qmc.discrepancy(sample, method=...)` |
//! |---|---|---|
//! | [`l2_star`] | `T_N` | `'L2-star'` (scipy takes the root) |
//! | [`l2_star_squared`] | `T_N^2` | the square of `'L2-star'` |
//! | [`centered_l2`] | `CD` | the root of `'CD'` |
//! | [`centered_l2_squared`] | `CD^2` | `'CD'` (scipy returns the square) |
//! | [`wrap_around_l2`] | `WD` | the root of `'WD'` |
//! | [`wrap_around_l2_squared`] | `WD^2` | `'WD'` (scipy returns the square) |
//! | [`mixture_l2`] | `MD` | the root of `'MD'` |
//! | [`mixture_l2_squared`] | `MD^2` | `'MD'` (scipy returns the square) |
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
//! points in 5 dimensions, `MD^2 = 1e-4`). See `tests/quality_discrepancy.rs` and its reference
//! script `tests/data/discrepancy_scipy.py`.

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
         point and the dimension)."
    };
}

mod double_double;

use crate::{Error, Points, Result};
use double_double::DoubleDouble;

/// Checks that `points` holds at least one point and that every coordinate is in `[0, 1]`.
pub(super) fn check_unit_cube(points: &Points) -> Result<()> {
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

/// The squared discrepancy of kernel `K`: the closed form, with the compensations described in
/// the module documentation.
fn squared<K: Kernel>(points: &Points) -> Result<f64> {
    check_unit_cube(points)?;
    let n = points.len();
    let dims = points.dims();
    let columns: Vec<&[f64]> = (0..dims).map(|dim| points.column(dim)).collect();

    let constant = DoubleDouble::ratio(K::CONSTANT.0, K::CONSTANT.1).powi(dims);

    let mut single_sum = DoubleDouble::ZERO;
    for i in 0..n {
        let product = columns
            .iter()
            .fold(DoubleDouble::ONE, |p, column| p * K::single(column[i]));
        single_sum = single_sum + product;
    }

    // Row i holds the K-products of point i with points i.., built one column at a time so the
    // inner loop runs over contiguous memory. Each factor is rounded once, with its rounding
    // error recovered exactly (Fast2Sum), and carried to first order beside the product: the
    // term is products[j] + corrections[j].
    let mut products = vec![1.0f64; n];
    let mut corrections = vec![0.0f64; n];
    let mut pair_sum = DoubleDouble::ZERO;
    for i in 0..n {
        let products = &mut products[i..];
        let corrections = &mut corrections[i..];
        products.fill(1.0);
        corrections.fill(0.0);
        for column in &columns {
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
        }
        // The diagonal term once, the terms j > i twice (K is symmetric).
        let (sum, error) = compensated_row_sum(&products[1..], &corrections[1..]);
        pair_sum = pair_sum + products[0] + corrections[0] + 2.0 * sum + 2.0 * error;
    }

    let n = n as f64;
    let result = constant - (single_sum * 2.0).div_f64(n) + pair_sum.div_f64(n).div_f64(n);
    Ok(result.to_f64())
}

/// The root of a squared discrepancy; rounding can leave a tiny negative square, read as 0.
fn root(squared: f64) -> f64 {
    squared.max(0.0).sqrt()
}

/// The L2-star discrepancy `T_N` (Warnock 1972): the root mean square over `t` in `[0,1]^d` of
/// `vol([0, t)) - #{x_i in [0, t)} / N`, the root of [`l2_star_squared`]. The same quantity as
/// scipy's `qmc.discrepancy(sample, method='L2-star')`, which also returns the root.
///
/// ```
/// use mcint::{Points, quality::l2_star};
/// // The N midpoints (2i - 1) / (2N) of [0, 1] have T_N = 1 / (sqrt(12) N).
/// let mut points = Points::new(1, 4)?;
/// points.column_mut(0).copy_from_slice(&[0.125, 0.375, 0.625, 0.875]);
/// let t = l2_star(&points)?;
/// assert!((t - 1.0 / (12f64.sqrt() * 4.0)).abs() < 1e-15);
/// # Ok::<(), mcint::Error>(())
/// ```
///
#[doc = cost_accuracy_errors!()]
pub fn l2_star(points: &Points) -> Result<f64> {
    l2_star_squared(points).map(root)
}

/// The squared L2-star discrepancy `T_N^2`, by Warnock's (1972) closed form
///
/// ```text
/// T_N^2 = 3^-d - (2^(1-d) / N) sum_i prod_k (1 - x_ik^2)
///              + (1 / N^2) sum_i sum_j prod_k (1 - max(x_ik, x_jk))
/// ```
///
/// The square of scipy's `qmc.discrepancy(sample, method='L2-star')` (scipy returns the root).
///
/// ```
/// use mcint::{Points, quality::l2_star_squared};
/// // One point x in one dimension: T^2 = 1/3 - (1 - x^2) + (1 - x) = x^2 - x + 1/3.
/// let mut points = Points::new(1, 1)?;
/// points.column_mut(0)[0] = 0.25;
/// let t2 = l2_star_squared(&points)?;
/// assert!((t2 - (0.0625 - 0.25 + 1.0 / 3.0)).abs() < 1e-16);
/// // Coordinates must lie in [0, 1].
/// points.column_mut(0)[0] = 1.5;
/// assert!(l2_star_squared(&points).is_err());
/// # Ok::<(), mcint::Error>(())
/// ```
///
#[doc = cost_accuracy_errors!()]
pub fn l2_star_squared(points: &Points) -> Result<f64> {
    squared::<Star>(points)
}

/// The centered L2 discrepancy `CD` (Hickernell 1998), the root of [`centered_l2_squared`]:
/// the root mean square local discrepancy of the boxes spanned by a point `t` and the corner of
/// the unit cube nearest to `t`. The square root of scipy's
/// `qmc.discrepancy(sample, method='CD')`, which returns `CD^2`.
///
/// ```
/// use mcint::{Points, quality::centered_l2};
/// // One point at the centre of [0, 1]: CD^2 = 13/12 - 2 + 1 = 1/12.
/// let mut points = Points::new(1, 1)?;
/// points.column_mut(0)[0] = 0.5;
/// assert!((centered_l2(&points)? - (1.0f64 / 12.0).sqrt()).abs() < 1e-15);
/// # Ok::<(), mcint::Error>(())
/// ```
///
#[doc = cost_accuracy_errors!()]
pub fn centered_l2(points: &Points) -> Result<f64> {
    centered_l2_squared(points).map(root)
}

/// The squared centered L2 discrepancy `CD^2` (Hickernell 1998), with `a_ik = |x_ik - 1/2|`:
///
/// ```text
/// CD^2 = (13/12)^d - (2 / N) sum_i prod_k (1 + a_ik / 2 - a_ik^2 / 2)
///      + (1 / N^2) sum_i sum_j prod_k (1 + a_ik / 2 + a_jk / 2 - |x_ik - x_jk| / 2)
/// ```
///
/// The same quantity as scipy's `qmc.discrepancy(sample, method='CD')`, which returns the
/// square. Invariant under reflecting any coordinate, `x -> 1 - x`.
///
/// ```
/// use mcint::{Points, quality::centered_l2_squared};
/// // Reflecting a coordinate (x -> 1 - x) leaves CD unchanged.
/// let mut points = Points::new(2, 3)?;
/// points.column_mut(0).copy_from_slice(&[0.125, 0.5, 0.75]);
/// points.column_mut(1).copy_from_slice(&[0.25, 0.875, 0.5]);
/// let before = centered_l2_squared(&points)?;
/// for x in points.column_mut(1) {
///     *x = 1.0 - *x;
/// }
/// assert!((centered_l2_squared(&points)? - before).abs() < 1e-15);
/// # Ok::<(), mcint::Error>(())
/// ```
///
#[doc = cost_accuracy_errors!()]
pub fn centered_l2_squared(points: &Points) -> Result<f64> {
    squared::<Centered>(points)
}

/// The wrap-around L2 discrepancy `WD` (Hickernell 1998), the root of
/// [`wrap_around_l2_squared`]: the root mean square local discrepancy of boxes that may wrap
/// around the faces of the unit cube (boxes on the torus). The square root of scipy's
/// `qmc.discrepancy(sample, method='WD')`, which returns `WD^2`.
///
/// ```
/// use mcint::{Points, quality::wrap_around_l2};
/// // One point anywhere in [0, 1]: WD^2 = -4/3 + 3/2 = 1/6.
/// let mut points = Points::new(1, 1)?;
/// points.column_mut(0)[0] = 0.9;
/// assert!((wrap_around_l2(&points)? - (1.0f64 / 6.0).sqrt()).abs() < 1e-15);
/// # Ok::<(), mcint::Error>(())
/// ```
///
#[doc = cost_accuracy_errors!()]
pub fn wrap_around_l2(points: &Points) -> Result<f64> {
    wrap_around_l2_squared(points).map(root)
}

/// The squared wrap-around L2 discrepancy `WD^2` (Hickernell 1998), with
/// `t_ijk = |x_ik - x_jk|`:
///
/// ```text
/// WD^2 = -(4/3)^d + (1 / N^2) sum_i sum_j prod_k (3/2 - t_ijk + t_ijk^2)
/// ```
///
/// The same quantity as scipy's `qmc.discrepancy(sample, method='WD')`, which returns the
/// square. Invariant under reflecting any coordinate and under shifting all points modulo 1.
///
/// ```
/// use mcint::{Points, quality::wrap_around_l2_squared};
/// // Shifting every point by the same amount modulo 1 leaves WD unchanged.
/// let mut points = Points::new(1, 3)?;
/// points.column_mut(0).copy_from_slice(&[0.0, 0.25, 0.625]);
/// let before = wrap_around_l2_squared(&points)?;
/// points.column_mut(0).copy_from_slice(&[0.5, 0.75, 0.125]);
/// assert!((wrap_around_l2_squared(&points)? - before).abs() < 1e-15);
/// # Ok::<(), mcint::Error>(())
/// ```
///
#[doc = cost_accuracy_errors!()]
pub fn wrap_around_l2_squared(points: &Points) -> Result<f64> {
    squared::<WrapAround>(points)
}

/// The mixture L2 discrepancy `MD` (Zhou, Fang & Ning 2013), the root of
/// [`mixture_l2_squared`], which mixes the centered and wrap-around families of boxes. The
/// square root of scipy's `qmc.discrepancy(sample, method='MD')`, which returns `MD^2`.
///
/// ```
/// use mcint::{Points, quality::mixture_l2};
/// // One point at the centre of [0, 1]: MD^2 = 19/12 - 2 * 5/3 + 15/8 = 1/8.
/// let mut points = Points::new(1, 1)?;
/// points.column_mut(0)[0] = 0.5;
/// assert!((mixture_l2(&points)? - (0.125f64).sqrt()).abs() < 1e-15);
/// # Ok::<(), mcint::Error>(())
/// ```
///
#[doc = cost_accuracy_errors!()]
pub fn mixture_l2(points: &Points) -> Result<f64> {
    mixture_l2_squared(points).map(root)
}

/// The squared mixture L2 discrepancy `MD^2` (Zhou, Fang & Ning 2013, eq. 18), with
/// `a_ik = |x_ik - 1/2|` and `t_ijk = |x_ik - x_jk|`:
///
/// ```text
/// MD^2 = (19/12)^d - (2 / N) sum_i prod_k (5/3 - a_ik / 4 - a_ik^2 / 4)
///      + (1 / N^2) sum_i sum_j prod_k (15/8 - a_ik / 4 - a_jk / 4 - 3 t_ijk / 4 + t_ijk^2 / 2)
/// ```
///
/// The same quantity as scipy's `qmc.discrepancy(sample, method='MD')`, which returns the
/// square. Invariant under reflecting any coordinate.
///
/// ```
/// use mcint::{Points, quality::mixture_l2_squared};
/// // An empty set or a NaN coordinate is an error, not a panic.
/// assert!(mixture_l2_squared(&Points::new(3, 0)?).is_err());
/// let mut points = Points::new(2, 1)?;
/// points.column_mut(1)[0] = f64::NAN;
/// let err = mixture_l2_squared(&points).unwrap_err();
/// assert!(err.to_string().contains("point 0, dimension 1"));
/// # Ok::<(), mcint::Error>(())
/// ```
///
#[doc = cost_accuracy_errors!()]
pub fn mixture_l2_squared(points: &Points) -> Result<f64> {
    squared::<Mixture>(points)
}
