//! The two-dimensional integrands rendering papers use to compare samplers.
//!
//! Christensen, Kensler & Kilpatrick (2018, "Progressive Multi-Jittered Sample Sequences",
//! Computer Graphics Forum 37(4)) measure the error of each sampler on a handful of simple
//! functions of the unit square: a disk (a discontinuity along a curve, like a silhouette in
//! a pixel), a Gaussian (smooth, like a pixel filter), a bilinear ramp, a step (a
//! discontinuity along an axis-aligned edge) and a triangle (a discontinuity along the
//! diagonal). Pilleboue et al. (2015, "Variance Analysis for Monte Carlo Integration") and
//! Subr & Kautz (2013) explain the rates these show: smooth integrands expose a sampler's best
//! rate, while a discontinuity along a curve limits jittered and low-discrepancy samplers to
//! an RMSE of about `N^-3/4`.
//!
//! The parameters are fixed so that the integrals are simple closed forms:
//!
//! | integrand | `f(x, y)` | exact integral |
//! |-----------|-----------|----------------|
//! | disk | `1` if `x² + y² < 2/π` | `1/2` |
//! | gaussian | `exp(-x² - y²)` | `(√π/2 · erf 1)² ≈ 0.557746` |
//! | bilinear | `x y` | `1/4` |
//! | step | `1` if `x < 1/3` | `1/3` |
//! | triangle | `1` if `y < x` | `1/2` |
//!
//! The disk is the quarter disk of radius `√(2/π) ≈ 0.798` centred on the origin corner, as in
//! Christensen et al.: its area `π r²/4` is exactly one half, and its boundary is a curve that
//! crosses the strata of every grid at every angle from horizontal to vertical, so no
//! stratification lines up with it. The step sits at `x = 1/3`, which is not a dyadic
//! rational: it never falls on a stratum boundary of a power-of-two grid (or any grid of `k`
//! columns with `k` not a multiple of 3), so it exercises the one-dimensional stratification
//! of a sampler rather than a lucky alignment.

use std::f64::consts::PI;
use std::fmt;
use std::str::FromStr;

use super::TestFunction;
use crate::error::parse_name;
use crate::error::{Error, Result};

/// `r²` of the quarter disk: `2/π`, so that its area `π r² / 4` is one half.
const DISK_RADIUS_SQUARED: f64 = 2.0 / PI;
/// Position of the step's edge.
const STEP_EDGE: f64 = 1.0 / 3.0;

/// One of the graphics papers' two-dimensional test integrands on `[0,1)²`.
///
/// Each takes points of two coordinates; see the table in the module documentation for the
/// formulas and integrals.
///
/// ```
/// use mcint::testfns::{GraphicsIntegrand, TestFunction};
/// let disk = GraphicsIntegrand::Disk;
/// assert_eq!(disk.dims(), 2);
/// assert_eq!(disk.exact(), 0.5);
/// assert_eq!(disk.eval(&[0.1, 0.2]), 1.0);
/// assert_eq!(disk.eval(&[0.7, 0.7]), 0.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GraphicsIntegrand {
    /// `1` inside the quarter disk `x² + y² < 2/π`, else `0` (integral `1/2`).
    Disk,
    /// `exp(-x² - y²)` (integral `(√π/2 · erf 1)²`).
    Gaussian,
    /// `x y` (integral `1/4`).
    Bilinear,
    /// `1` where `x < 1/3`, else `0` (integral `1/3`).
    Step,
    /// `1` below the diagonal, `y < x`, else `0` (integral `1/2`).
    Triangle,
}

impl GraphicsIntegrand {
    /// All five, in the order of the module's table.
    ///
    /// ```
    /// use mcint::testfns::GraphicsIntegrand;
    /// for f in GraphicsIntegrand::ALL {
    ///     assert_eq!(f.name().parse::<GraphicsIntegrand>().unwrap(), f);
    /// }
    /// ```
    pub const ALL: [GraphicsIntegrand; 5] = [
        GraphicsIntegrand::Disk,
        GraphicsIntegrand::Gaussian,
        GraphicsIntegrand::Bilinear,
        GraphicsIntegrand::Step,
        GraphicsIntegrand::Triangle,
    ];

    /// The name accepted by [`FromStr`]. (Called on a reference, `f.name()` resolves to
    /// [`TestFunction::name`], which returns the same text as a `String`.)
    ///
    /// ```
    /// assert_eq!(mcint::testfns::GraphicsIntegrand::Step.name(), "step");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            GraphicsIntegrand::Disk => "disk",
            GraphicsIntegrand::Gaussian => "gaussian",
            GraphicsIntegrand::Bilinear => "bilinear",
            GraphicsIntegrand::Step => "step",
            GraphicsIntegrand::Triangle => "triangle",
        }
    }

    /// Whether the integrand is smooth (infinitely differentiable on the square), as opposed
    /// to an indicator with a discontinuity; the two kinds converge at different rates.
    ///
    /// ```
    /// use mcint::testfns::GraphicsIntegrand;
    /// assert!(GraphicsIntegrand::Gaussian.is_smooth());
    /// assert!(!GraphicsIntegrand::Disk.is_smooth());
    /// ```
    pub fn is_smooth(self) -> bool {
        matches!(
            self,
            GraphicsIntegrand::Gaussian | GraphicsIntegrand::Bilinear
        )
    }
}

impl fmt::Display for GraphicsIntegrand {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(GraphicsIntegrand::name(*self))
    }
}

impl FromStr for GraphicsIntegrand {
    type Err = Error;

    /// Parses exactly one of the names returned by [`GraphicsIntegrand::name`].
    ///
    /// ```
    /// use mcint::testfns::GraphicsIntegrand;
    /// assert_eq!("disk".parse::<GraphicsIntegrand>().unwrap(), GraphicsIntegrand::Disk);
    /// assert!("disc".parse::<GraphicsIntegrand>().unwrap_err().to_string().contains("triangle"));
    /// ```
    fn from_str(name: &str) -> Result<Self> {
        parse_name(
            "integrand",
            name,
            &GraphicsIntegrand::ALL,
            GraphicsIntegrand::name,
        )
    }
}

impl TestFunction for GraphicsIntegrand {
    /// Always 2.
    ///
    /// ```
    /// use mcint::testfns::{GraphicsIntegrand, TestFunction};
    /// assert!(GraphicsIntegrand::ALL.iter().all(|f| f.dims() == 2));
    /// ```
    fn dims(&self) -> usize {
        2
    }

    /// The integrand at `x = [x, y]` (only the first two coordinates are read).
    ///
    /// ```
    /// use mcint::testfns::{GraphicsIntegrand, TestFunction};
    /// assert_eq!(GraphicsIntegrand::Bilinear.eval(&[0.5, 0.25]), 0.125);
    /// assert_eq!(GraphicsIntegrand::Triangle.eval(&[0.5, 0.25]), 1.0);
    /// assert_eq!(GraphicsIntegrand::Step.eval(&[0.5, 0.25]), 0.0);
    /// ```
    fn eval(&self, x: &[f64]) -> f64 {
        let (u, v) = (x[0], x[1]);
        let indicator = |inside: bool| if inside { 1.0 } else { 0.0 };
        match self {
            GraphicsIntegrand::Disk => indicator(u * u + v * v < DISK_RADIUS_SQUARED),
            GraphicsIntegrand::Gaussian => (-u * u - v * v).exp(),
            GraphicsIntegrand::Bilinear => u * v,
            GraphicsIntegrand::Step => indicator(u < STEP_EDGE),
            GraphicsIntegrand::Triangle => indicator(v < u),
        }
    }

    /// The exact integral over `[0,1)²`.
    ///
    /// ```
    /// use mcint::testfns::{GraphicsIntegrand, TestFunction};
    /// assert_eq!(GraphicsIntegrand::Bilinear.exact(), 0.25);
    /// assert!((GraphicsIntegrand::Gaussian.exact() - 0.557746).abs() < 1e-6);
    /// ```
    fn exact(&self) -> f64 {
        match self {
            GraphicsIntegrand::Disk | GraphicsIntegrand::Triangle => 0.5,
            // The Gaussian separates: (∫_0^1 e^{-t²} dt)² with ∫_0^1 e^{-t²} dt = √π/2 erf(1).
            GraphicsIntegrand::Gaussian => (0.5 * PI.sqrt() * libm::erf(1.0)).powi(2),
            GraphicsIntegrand::Bilinear => 0.25,
            GraphicsIntegrand::Step => STEP_EDGE,
        }
    }

    /// The name, as [`GraphicsIntegrand::name`].
    ///
    /// ```
    /// use mcint::testfns::{GraphicsIntegrand, TestFunction};
    /// assert_eq!(TestFunction::name(&GraphicsIntegrand::Disk), "disk");
    /// ```
    fn name(&self) -> String {
        GraphicsIntegrand::name(*self).to_string()
    }
}
