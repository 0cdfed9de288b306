//! Estimators: one contribution `Y_i` from one canonical point.
//!
//! An estimator owns the integrand and whatever maps canonical points into its domain. The
//! integral estimate is the mean of the contributions, `<F^N> = (1/N) sum Y_i`, whose
//! variance is `sigma^2[Y] / N` for independent samples (Jarosz's A.21). The uniform
//! estimator is Jarosz's A.14, the importance-sampling estimator A.19; the biased but
//! consistent estimator of A.35 is kept as a teaching example ([`ConsistentBiased`]).
//! [`BatchUniformEstimator`] is the uniform estimator for an integrand that evaluates a whole
//! block of points per call (`Fn(&Points, &mut [f64])`), so users can vectorize it.
//!
//! Importance sampling and multiple importance sampling (Jarosz's A.3.1):
//! - [`ProductImportanceEstimator`]: importance sampling one known factor of `f = g h` (A.25).
//! - [`MultiSampleMis`] and [`OneSampleMis`]: multiple importance sampling (Veach & Guibas
//!   1995), weighted by a [`MisHeuristic`] (balance, power, maximum, cutoff) or any
//!   [`MisWeighting`].
//!
//! Integrands with several outputs, integrated over the same points, implement
//! [`VectorEstimator`]: [`VectorUniformEstimator`] (per point), [`BatchVectorUniformEstimator`]
//! (per block) and [`VectorImportanceEstimator`].
//!
//! Control variates (A.26-A.29) come with a known coefficient ([`FixedControlVariate`]) and with
//! least-squares coefficients fitted on a pilot stage that the
//! [`Integrator`](crate::Integrator) runs before the main one ([`FittedControlVariates`], through
//! [`PilotFit`]).

mod batch_uniform;
mod box_block;
mod consistent_biased;
mod control_domain;
mod expectation;
mod fitted_control_variates;
mod fixed_control_variate;
mod importance;
mod mis_heuristic;
mod mis_weighting;
mod multi_sample_mis;
mod one_sample_mis;
mod outputs;
mod pilot;
mod product_importance;
mod uniform;
mod vector;
mod vector_batch_uniform;
mod vector_importance;
mod vector_uniform;
mod warp_importance;

pub use batch_uniform::BatchUniformEstimator;

pub use consistent_biased::ConsistentBiased;
pub use control_domain::{ControlDomain, OverMeasure};
pub use expectation::{ExpectationEstimator, VectorExpectationEstimator};
pub use fitted_control_variates::{ControlFit, FittedControlVariates};
pub use fixed_control_variate::FixedControlVariate;
pub use importance::ImportanceEstimator;
pub use mis_heuristic::MisHeuristic;
pub use mis_weighting::MisWeighting;
pub use multi_sample_mis::MultiSampleMis;
pub use one_sample_mis::OneSampleMis;
pub use outputs::MAX_OUTPUTS;
pub(crate) use outputs::checked_outputs;
pub use pilot::PilotFit;
pub use product_importance::ProductImportanceEstimator;
pub use uniform::UniformEstimator;
pub(crate) use vector::SingleOutput;
pub use vector::VectorEstimator;
pub use vector_batch_uniform::BatchVectorUniformEstimator;
pub use vector_importance::VectorImportanceEstimator;
pub use vector_uniform::VectorUniformEstimator;
pub use warp_importance::WarpImportanceEstimator;

/// The points an estimator gets per call unless it asks for more (see
/// [`Estimator::points_per_call`]): also the block the Integrator sums at a time.
pub(crate) const DEFAULT_POINTS_PER_CALL: usize = 1024;

/// `points` per call if an estimator may ask for them: 1 to 2^20.
pub(crate) fn checked_points_per_call(points: usize) -> crate::error::Result<usize> {
    if (1..=1 << 20).contains(&points) {
        Ok(points)
    } else {
        Err(crate::error::Error::invalid(
            "points_per_call",
            points,
            "1 to 2^20",
        ))
    }
}

use crate::points::Points;

/// Turns canonical points into contributions `Y_i` whose mean estimates an integral.
///
/// Implementations are pure: the same `u` always gives the same `Y`, so blocks can be
/// evaluated on any thread. `contribution`'s `x` argument is scratch space of length
/// [`domain_dims`](Self::domain_dims) for the mapped point, so that the per-point path does not
/// allocate.
///
/// ```
/// use mcint::estimator::{Estimator, UniformEstimator};
/// use mcint::pdf::UniformBox;
/// let e = UniformEstimator::new(|x: &[f64]| x[0] * x[0], UniformBox::new(vec![0.0], vec![3.0]).unwrap());
/// let mut x = [0.0];
/// assert_eq!(e.contribution(&[0.5], &mut x), 3.0 * 1.5 * 1.5);
/// ```
pub trait Estimator: Send + Sync {
    /// Number of canonical coordinates each contribution consumes.
    fn canonical_dims(&self) -> usize;

    /// Number of coordinates of the domain point (length of the scratch buffer).
    fn domain_dims(&self) -> usize;

    /// The contribution `Y` of the canonical point `u`; `x` is scratch of length
    /// [`domain_dims`](Self::domain_dims).
    fn contribution(&self, u: &[f64], x: &mut [f64]) -> f64;

    /// Contributions of every point of a block (`out.len() == points.len()`). The default
    /// calls [`contribution`](Self::contribution) per point with one scratch allocation.
    fn contributions(&self, points: &Points, out: &mut [f64]) {
        let mut u = vec![0.0; points.dims()];
        let mut x = vec![0.0; self.domain_dims()];
        for (i, y) in out.iter_mut().enumerate().take(points.len()) {
            points.copy_point(i, &mut u);
            *y = self.contribution(&u, &mut x);
        }
    }

    /// How many points [`contributions`](Self::contributions) would like in one call: 1024
    /// by default (a block that stays in cache); more for an integrand that pays a cost per
    /// call (see [`BatchUniformEstimator::with_points_per_call`]). The Integrator calls with
    /// whole blocks of 1024 points, as many as fit (at least one), and sums contributions
    /// 1024 at a time whatever the call size, so the hint never changes a result's bits.
    ///
    /// ```
    /// use mcint::estimator::{Estimator, UniformEstimator};
    /// use mcint::pdf::UniformBox;
    /// let e = UniformEstimator::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap());
    /// assert_eq!(e.points_per_call(), 1024);
    /// ```
    fn points_per_call(&self) -> usize {
        DEFAULT_POINTS_PER_CALL
    }

    /// Integrand evaluations one contribution costs (default 1; a multi-sample MIS
    /// contribution evaluates the integrand once per sample of every technique), so that runs
    /// report, and limit, true evaluation counts.
    ///
    /// ```
    /// use mcint::estimator::{Estimator, UniformEstimator};
    /// use mcint::pdf::UniformBox;
    /// let e = UniformEstimator::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap());
    /// assert_eq!(e.evaluations_per_contribution(), 1);
    /// ```
    fn evaluations_per_contribution(&self) -> u64 {
        1
    }

    /// The pilot stage this estimator fits itself to before the main run, if any (default
    /// none): the [`Integrator`](crate::Integrator) runs it first and integrates with the
    /// fitted estimator it returns.
    ///
    /// ```
    /// use mcint::estimator::{FittedControlVariates, Estimator, UniformEstimator};
    /// use mcint::pdf::UniformBox;
    /// let plain = UniformEstimator::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap());
    /// assert!(plain.pilot().is_none());
    /// let cv = FittedControlVariates::new(|x: &[f64]| x[0].exp(), UniformBox::unit(1).unwrap())
    ///     .control(|x: &[f64]| x[0], 0.5);
    /// assert!(cv.pilot().is_some());
    /// ```
    fn pilot(&self) -> Option<&dyn PilotFit> {
        None
    }
}

/// Forwards every method of [`Estimator`] through a pointer type, so that references and
/// boxes (`Box<dyn Estimator>`) are estimators too.
macro_rules! forward_estimator {
    ($($pointer:ty),+) => {$(
        impl<E: Estimator + ?Sized> Estimator for $pointer {
            fn canonical_dims(&self) -> usize {
                (**self).canonical_dims()
            }

            fn domain_dims(&self) -> usize {
                (**self).domain_dims()
            }

            fn contribution(&self, u: &[f64], x: &mut [f64]) -> f64 {
                (**self).contribution(u, x)
            }

            fn contributions(&self, points: &Points, out: &mut [f64]) {
                (**self).contributions(points, out)
            }

            fn evaluations_per_contribution(&self) -> u64 {
                (**self).evaluations_per_contribution()
            }

            fn points_per_call(&self) -> usize {
                (**self).points_per_call()
            }

            fn pilot(&self) -> Option<&dyn PilotFit> {
                (**self).pilot()
            }
        }
    )+};
}

forward_estimator!(&E, Box<E>);
