//! [`NonFinitePolicy`]: what a run does with NaN or infinite contributions.
//!
//! The engine's run configuration holds it and every runner above reads it, so it sits below
//! both; users reach it as `mcint::NonFinitePolicy`.

/// What the [`Integrator`](crate::Integrator) does when a contribution `Y_i` is NaN or
/// infinite (the integrand returned one, or a pdf was zero where the integrand was not).
///
/// The default, [`Fail`](Self::Fail), stops the run with an error giving the count and the
/// first offending point: a mean with such values in it, or silently without them, would be
/// wrong. [`Skip`](Self::Skip) leaves them out and counts them in
/// [`Estimate::non_finite`](crate::Estimate::non_finite); the estimate is then the mean over
/// the finite contributions only, which is biased wherever the skipped points carry mass
/// (a renderer's choice for rare NaN samples, not a cure for a singular integrand).
///
/// ```
/// use mcint::{Integrator, NonFinitePolicy, pdf::UniformBox};
/// // NaN on a tenth of the cube.
/// let f = |x: &[f64]| if x[0] < 0.1 { f64::NAN } else { 1.0 };
/// let strict = Integrator::over_box(f, UniformBox::unit(1).unwrap()).samples(1000).run();
/// assert!(strict.is_err());
/// let e = Integrator::over_box(f, UniformBox::unit(1).unwrap())
///     .samples(1000)
///     .non_finite(NonFinitePolicy::Skip)
///     .run()
///     .unwrap();
/// assert_eq!(e.mean, 1.0);
/// assert!(e.non_finite > 50 && e.n + e.non_finite == 1000);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum NonFinitePolicy {
    /// Fail with [`Error::NonFiniteContribution`](crate::Error::NonFiniteContribution).
    #[default]
    Fail,
    /// Leave them out of the estimate and count them.
    Skip,
}
