//! Measures: expectations `E[f(X)]` under Gaussian, lognormal and Brownian-motion laws, and
//! integrals over unbounded domains, as integrals over the unit cube.
//!
//! A [`Measure`] maps a canonical point `u` in `[0,1)^k` to a point `x` of its space and gives
//! the weight of that point, so that `int f dmu = int_{[0,1)^k} f(T(u)) w(u) du`: the weight is
//! 1 for a probability law (`x` is then distributed by it when `u` is uniform) and the
//! Jacobian of the transform for the Lebesgue measure of an unbounded domain. Every map is a
//! composition of inverse cdfs and linear maps, never rejection or Box-Muller, so the
//! structure of stratified and quasi-random points survives: one coordinate of `u` per
//! independent normal, in the order that carries the most variance first where the
//! construction allows (principal components, Brownian bridge), which is what makes QMC pay
//! off (the integrand's effective dimension is low).
//!
//! [`Integrator::expectation`](crate::Integrator::expectation) integrates `f` against any
//! measure.
//!
//! Linear algebra (Cholesky and symmetric eigendecompositions) comes from `nalgebra`: mature,
//! with both factorizations for the small dense matrices here (a covariance of a few hundred
//! dimensions at most), and lighter to build than `faer`, whose speed matters only for large
//! matrices.

mod brownian;
mod gaussian;
mod geometric_brownian;
mod independent;
mod lebesgue;
mod normal_map;
mod principal_components;
mod uniform_law;

pub use brownian::{BrownianMotion, Construction};
pub use gaussian::{Factorization, Gaussian, Lognormal};
pub use geometric_brownian::GeometricBrownianMotion;
pub use independent::Independent;
pub use lebesgue::{Lebesgue, UnboundedTransform};
pub use uniform_law::Uniform;

pub(crate) use normal_map::standard_normal;

/// The most dimensions of a [`Gaussian`] (either [`Factorization`]) and of a
/// [`BrownianMotion`] built by [`Construction::Pca`]: factoring their covariance keeps
/// `d x d` matrices and takes `O(d^3)` time, so larger ones are refused with an error instead
/// of running for minutes with gigabytes. (The standard and bridge constructions of Brownian
/// paths take `O(d)` and have no such bound.)
///
/// ```
/// use mcint::measure::{BrownianMotion, Construction, FACTOR_MAX_DIMS, Gaussian};
/// let err = Gaussian::standard(FACTOR_MAX_DIMS + 1).unwrap_err();
/// assert!(err.to_string().contains("O(d^3)"), "{err}");
/// let times: Vec<f64> = (1..=2000).map(f64::from).collect();
/// assert!(BrownianMotion::new(times.clone(), 0.0, 1.0, Construction::Pca).is_err());
/// assert!(BrownianMotion::new(times, 0.0, 1.0, Construction::Bridge).is_ok());
/// ```
pub const FACTOR_MAX_DIMS: usize = 1024;

/// Ok when `d` dimensions (`what`: the parameter that sets them, counted in `unit`) can be
/// factored; `hint` ends the message.
fn check_factor_dims(
    what: &'static str,
    d: usize,
    unit: &str,
    hint: &str,
) -> crate::error::Result<()> {
    if d > FACTOR_MAX_DIMS {
        return Err(crate::error::Error::invalid(
            what,
            format!("{d} {unit}"),
            format!(
                "at most {FACTOR_MAX_DIMS} (FACTOR_MAX_DIMS): factoring the covariance keeps d x d \
                 matrices and takes O(d^3) time{hint}"
            ),
        ));
    }
    Ok(())
}

/// A measure over `R^d` seen from the unit cube: canonical points `u` in `[0,1)^k` map to
/// points `x` with weights, so that `int f dmu = int f(T(u)) w(u) du`.
///
/// ```
/// use mcint::measure::{Gaussian, Measure};
/// let standard = Gaussian::standard(2).unwrap();
/// let mut x = [0.0; 2];
/// assert_eq!(standard.map(&[0.5, 0.5], &mut x), 1.0); // a probability law: weight 1
/// assert_eq!(x, [0.0, 0.0]); // the medians
/// ```
pub trait Measure: Send + Sync {
    /// Number of canonical coordinates `k` one point consumes.
    fn canonical_dims(&self) -> usize;

    /// Number of coordinates `d` of a point of the measure's space.
    fn dims(&self) -> usize;

    /// Maps `u` (`u.len() == canonical_dims()`) to `x` (`x.len() == dims()`) and returns the
    /// point's weight `w(u)` (1 for a probability law).
    ///
    /// # Panics
    ///
    /// May panic when a slice is shorter than its dimension.
    fn map(&self, u: &[f64], x: &mut [f64]) -> f64;
}

impl<M: Measure + ?Sized> Measure for &M {
    fn canonical_dims(&self) -> usize {
        (**self).canonical_dims()
    }

    fn dims(&self) -> usize {
        (**self).dims()
    }

    fn map(&self, u: &[f64], x: &mut [f64]) -> f64 {
        (**self).map(u, x)
    }
}
