//! [`Lebesgue`]: the Lebesgue measure on a box whose sides may be infinite, through
//! documented variable transforms whose Jacobian is the weight.

use super::Measure;
use super::normal_map::standard_normal;
use crate::error::{Error, Result};

/// How an infinite side of a [`Lebesgue`] box is reached from `[0, 1)`.
///
/// ```
/// use mcint::measure::UnboundedTransform;
/// assert_eq!(UnboundedTransform::default(), UnboundedTransform::Rational);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum UnboundedTransform {
    /// `x = a + u / (1 - u)` on `[a, inf)` (Jacobian `1 / (1 - u)^2`), its mirror on
    /// `(-inf, b]`, and `x = (u - 1/2) / (u (1 - u))` on the whole line (Jacobian
    /// `(u^2 - u + 1/2) / (u (1 - u))^2`): for integrands that decay like a power.
    #[default]
    Rational,
    /// `x = scale Phi^-1(u)` on the whole line and the half-normal map on half lines, with
    /// one over the normal density as the Jacobian: importance sampling by a normal of this
    /// scale, for integrands with Gaussian tails (the Keister integrand with `scale =
    /// 1/sqrt(2)` becomes `pi^{d/2} cos |x|`, as QMCPy integrates it).
    Normal {
        /// The standard deviation of the normal (finite, `> 0`).
        scale: f64,
    },
}

/// One axis of the box.
#[derive(Debug, Clone, Copy)]
enum Axis {
    Finite {
        lo: f64,
        width: f64,
    },
    /// `[lo, inf)`.
    Above {
        lo: f64,
    },
    /// `(-inf, hi]`.
    Below {
        hi: f64,
    },
    Whole,
}

/// The smallest `u` used where `u = 0` would map to an infinite point.
const SMALLEST: f64 = 1.0 / (1u64 << 54) as f64;

/// `1 / (sqrt(2 pi))`.
const INV_SQRT_2PI: f64 = 0.398_942_280_401_432_7;

/// The Lebesgue measure on the box `[lo_1, hi_1] x ... x [lo_d, hi_d]`, where a bound may be
/// infinite: `int f(x) dx = int_{[0,1)^d} f(T(u)) J(u) du`, the map `T` and its Jacobian `J`
/// axis by axis (an affine map on a finite side, [`UnboundedTransform`] on an infinite one).
///
/// ```
/// use mcint::{Integrator, measure::{Lebesgue, UnboundedTransform}};
/// // The integral of e^{-x^2} over the real line is sqrt(pi).
/// for transform in [UnboundedTransform::Rational, UnboundedTransform::Normal { scale: 1.0 }] {
///     let line = Lebesgue::new(vec![f64::NEG_INFINITY], vec![f64::INFINITY], transform).unwrap();
///     let e = Integrator::expectation(|x: &[f64]| (-x[0] * x[0]).exp(), line).samples(100_000).run().unwrap();
///     assert!((e.mean - std::f64::consts::PI.sqrt()).abs() < 5.0 * e.std_error.unwrap());
/// }
/// ```
#[derive(Debug, Clone)]
pub struct Lebesgue {
    axes: Vec<Axis>,
    transform: UnboundedTransform,
}

impl Lebesgue {
    /// The box with corners `lo` and `hi` (the same length, `lo < hi` on every axis, either
    /// bound possibly infinite, neither NaN), infinite sides reached by `transform`.
    ///
    /// ```
    /// use mcint::measure::{Lebesgue, UnboundedTransform};
    /// let t = UnboundedTransform::Rational;
    /// assert!(Lebesgue::new(vec![1.0], vec![0.0], t).is_err());
    /// assert!(Lebesgue::new(vec![0.0, 0.0], vec![1.0], t).is_err());
    /// assert!(Lebesgue::new(vec![0.0], vec![1.0], UnboundedTransform::Normal { scale: 0.0 }).is_err());
    /// ```
    pub fn new(lo: Vec<f64>, hi: Vec<f64>, transform: UnboundedTransform) -> Result<Self> {
        if lo.len() != hi.len() {
            return Err(Error::DimensionMismatch {
                what: "upper corner of the box",
                expected: lo.len(),
                found: hi.len(),
            });
        }
        if lo.is_empty() {
            return Err(Error::invalid("lo", "[]", "at least one dimension"));
        }
        if let UnboundedTransform::Normal { scale } = transform
            && !(scale.is_finite() && scale > 0.0)
        {
            return Err(Error::invalid(
                "scale",
                scale,
                "a finite standard deviation > 0",
            ));
        }
        let axes = lo
            .iter()
            .zip(&hi)
            .enumerate()
            .map(|(d, (&lo, &hi))| {
                if lo.is_nan()
                    || hi.is_nan()
                    || lo >= hi
                    || lo == f64::INFINITY
                    || hi == f64::NEG_INFINITY
                {
                    return Err(Error::invalid(
                        "box",
                        format!("[{lo}, {hi}] on axis {d}"),
                        "lo < hi on every axis (either may be infinite, neither NaN)",
                    ));
                }
                Ok(match (lo.is_finite(), hi.is_finite()) {
                    (true, true) => {
                        let width = hi - lo;
                        if !width.is_finite() {
                            return Err(Error::invalid(
                                "box",
                                format!("[{lo}, {hi}] on axis {d}"),
                                "a width below f64::MAX",
                            ));
                        }
                        Axis::Finite { lo, width }
                    }
                    (true, false) => Axis::Above { lo },
                    (false, true) => Axis::Below { hi },
                    (false, false) => Axis::Whole,
                })
            })
            .collect::<Result<Vec<Axis>>>()?;
        Ok(Lebesgue { axes, transform })
    }

    /// The whole space `R^dims` by `transform`.
    ///
    /// ```
    /// use mcint::measure::{Lebesgue, Measure, UnboundedTransform};
    /// assert_eq!(Lebesgue::whole_space(3, UnboundedTransform::Rational).unwrap().dims(), 3);
    /// ```
    pub fn whole_space(dims: usize, transform: UnboundedTransform) -> Result<Self> {
        Lebesgue::new(
            vec![f64::NEG_INFINITY; dims],
            vec![f64::INFINITY; dims],
            transform,
        )
    }

    /// `(x, Jacobian)` of a half line `[0, inf)` at `u`.
    fn half_line(&self, u: f64) -> (f64, f64) {
        match self.transform {
            UnboundedTransform::Rational => {
                let rest = 1.0 - u;
                (u / rest, 1.0 / (rest * rest))
            }
            UnboundedTransform::Normal { scale } => {
                // The half-normal: |N(0, scale^2)| has density 2 phi(x / scale) / scale. Its
                // quantile from the upper tail, 0.5 (1 - u), which is exact for u >= 1/2 and
                // never 0: 0.5 + 0.5 u rounds to 1 (an infinite x) below 1.
                let y = -standard_normal(0.5 * (1.0 - u));
                let density = 2.0 * INV_SQRT_2PI * (-0.5 * y * y).exp() / scale;
                (scale * y, 1.0 / density)
            }
        }
    }

    /// `(x, Jacobian)` of the whole line at `u`.
    fn whole_line(&self, u: f64) -> (f64, f64) {
        let u = u.max(SMALLEST);
        match self.transform {
            UnboundedTransform::Rational => {
                let product = u * (1.0 - u);
                ((u - 0.5) / product, (u * u - u + 0.5) / (product * product))
            }
            UnboundedTransform::Normal { scale } => {
                let y = standard_normal(u);
                let density = INV_SQRT_2PI * (-0.5 * y * y).exp() / scale;
                (scale * y, 1.0 / density)
            }
        }
    }
}

impl Measure for Lebesgue {
    fn canonical_dims(&self) -> usize {
        self.axes.len()
    }

    fn dims(&self) -> usize {
        self.axes.len()
    }

    fn map(&self, u: &[f64], x: &mut [f64]) -> f64 {
        let mut weight = 1.0;
        for ((axis, &u), x) in self.axes.iter().zip(u).zip(x.iter_mut()) {
            let (value, jacobian) = match *axis {
                Axis::Finite { lo, width } => (lo + width * u, width),
                Axis::Above { lo } => {
                    let (y, j) = self.half_line(u);
                    (lo + y, j)
                }
                Axis::Below { hi } => {
                    let (y, j) = self.half_line(u);
                    (hi - y, j)
                }
                Axis::Whole => self.whole_line(u),
            };
            *x = value;
            weight *= jacobian;
        }
        weight
    }
}
