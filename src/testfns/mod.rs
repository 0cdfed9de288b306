//! Test integrands on the unit cube `[0,1)^d` with known integrals.
//!
//! These are the functions numerical-integration papers use to compare methods: the six
//! Genz (1984) families, polynomials, the Roos-Arnold product, the Sobol' g-function and the
//! two-dimensional integrands of rendering papers ([`GraphicsIntegrand`]). Each
//! implements [`TestFunction`], which pairs the integrand with its exact integral over the
//! unit cube, so that examples, tests and benches can report true errors.

mod genz;
mod genz_batch;
mod graphics;
mod ishigami;
mod keister;
mod polynomial;
mod roos_arnold;
mod sobol_g;

pub use genz::{Genz, GenzFamily};
pub use graphics::GraphicsIntegrand;
pub use ishigami::Ishigami;
pub use keister::{KEISTER_MAX_DIMS, Keister};
pub use polynomial::Polynomial;
pub use roos_arnold::RoosArnold;
pub use sobol_g::SobolGFunction;

use crate::points::Points;

/// An integrand on the unit cube with a known integral.
///
/// ```
/// use mcint::testfns::{Genz, GenzFamily, TestFunction};
/// let f = Genz::with_defaults(GenzFamily::Gaussian, 3).unwrap();
/// assert_eq!(f.dims(), 3);
/// assert!(f.exact() > 0.0 && f.eval(&[0.5, 0.5, 0.5]) > 0.0);
/// ```
pub trait TestFunction: Send + Sync {
    /// Number of dimensions `d` of the domain `[0,1)^d`.
    fn dims(&self) -> usize;
    /// The integrand at `x` (`x.len() == self.dims()`).
    fn eval(&self, x: &[f64]) -> f64;
    /// The exact integral over `[0,1)^d`.
    fn exact(&self) -> f64;
    /// A short name for tables (for example `"gaussian"`).
    fn name(&self) -> String;

    /// The integrand at every point of a block (one column per coordinate): `out[i]` is the
    /// value at point `i` (`out.len() == points.len()`, `points.dims() == self.dims()`).
    /// This default calls [`eval`](TestFunction::eval) point by point; the Genz families
    /// evaluate column by column with [`vector_math`](crate::vector_math)'s `exp` and `cos`,
    /// within an ulp or two of `eval`. It is the form
    /// [`Integrator::over_box_batch`](crate::Integrator::over_box_batch) takes.
    ///
    /// ```
    /// use mcint::Points;
    /// use mcint::testfns::{Genz, GenzFamily, TestFunction};
    /// let f = Genz::with_defaults(GenzFamily::Oscillatory, 2).unwrap();
    /// let points = Points::from_rows(&[[0.1, 0.2], [0.7, 0.4]]).unwrap();
    /// let mut out = [0.0; 2];
    /// f.eval_batch(&points, &mut out);
    /// assert!((out[1] - f.eval(&[0.7, 0.4])).abs() <= 2.0 * f64::EPSILON);
    /// ```
    fn eval_batch(&self, points: &Points, out: &mut [f64]) {
        let mut x = vec![0.0; points.dims()];
        for (i, y) in out.iter_mut().enumerate().take(points.len()) {
            for (k, xk) in x.iter_mut().enumerate() {
                *xk = points.column(k)[i];
            }
            *y = self.eval(&x);
        }
    }
}
