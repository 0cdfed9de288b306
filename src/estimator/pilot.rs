//! [`PilotFit`]: an estimator that fits itself to a pilot stage before the main run.

use super::Estimator;
use crate::error::Result;
use crate::stats::CovarianceAccumulator;

/// What an estimator learns from a pilot stage, and the estimator it then becomes.
///
/// The [`Integrator`](crate::Integrator) evaluates [`row`](Self::row) on
/// [`points`](Self::points) independent pilot points (independent of the main run's, whatever
/// its sampler), accumulates the rows' means and co-moments, and integrates with
/// [`fitted`](Self::fitted). Because the fit depends on the pilot alone, the main run's
/// estimate and error bar are those of a fixed estimator: unbiased, with an honest interval.
///
/// ```
/// use mcint::estimator::{FittedControlVariates, Estimator, PilotFit};
/// use mcint::pdf::UniformBox;
/// let cv = FittedControlVariates::new(|x: &[f64]| x[0].exp(), UniformBox::unit(1).unwrap())
///     .control(|x: &[f64]| x[0], 0.5);
/// let pilot = cv.pilot().unwrap();
/// assert_eq!(pilot.values(), 2); // f/pdf and one control
/// ```
pub trait PilotFit: Send + Sync {
    /// Points of the pilot stage.
    ///
    /// ```
    /// use mcint::estimator::{FittedControlVariates, Estimator};
    /// use mcint::pdf::UniformBox;
    /// let cv = FittedControlVariates::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).pilot_points(500);
    /// assert_eq!(cv.pilot().unwrap().points(), 500);
    /// ```
    fn points(&self) -> u64;

    /// Values recorded per pilot point.
    ///
    /// ```
    /// use mcint::estimator::{FittedControlVariates, Estimator};
    /// use mcint::pdf::UniformBox;
    /// let cv = FittedControlVariates::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap());
    /// assert_eq!(cv.pilot().unwrap().values(), 1);
    /// ```
    fn values(&self) -> usize;

    /// Writes the pilot values at the canonical point `u` to `row` (`x` is scratch of the
    /// estimator's [`domain_dims`](Estimator::domain_dims)).
    ///
    /// ```
    /// use mcint::estimator::{FittedControlVariates, Estimator};
    /// use mcint::pdf::UniformBox;
    /// let cv = FittedControlVariates::new(|x: &[f64]| 2.0 * x[0], UniformBox::unit(1).unwrap())
    ///     .control(|x: &[f64]| x[0], 0.5);
    /// let mut row = [0.0; 2];
    /// cv.pilot().unwrap().row(&[0.25], &mut [0.0], &mut row);
    /// assert_eq!(row, [0.5, 0.25]);
    /// ```
    fn row(&self, u: &[f64], x: &mut [f64], row: &mut [f64]);

    /// The estimator of the main run, fitted to the pilot rows' count, means and co-moments.
    ///
    /// ```
    /// use mcint::estimator::{FittedControlVariates, Estimator};
    /// use mcint::pdf::UniformBox;
    /// use mcint::stats::CovarianceAccumulator;
    /// let cv = FittedControlVariates::new(|x: &[f64]| 3.0 + 2.0 * x[0], UniformBox::unit(1).unwrap())
    ///     .control(|x: &[f64]| x[0], 0.5);
    /// let pilot = cv.pilot().unwrap();
    /// let mut summary = CovarianceAccumulator::new(2)?;
    /// for u in [0.1, 0.4, 0.7, 0.9] {
    ///     let mut row = [0.0; 2];
    ///     pilot.row(&[u], &mut [0.0], &mut row);
    ///     summary.push(&row)?;
    /// }
    /// let fitted = pilot.fitted(&summary)?;
    /// // f is 3 + 2 g exactly: every fitted contribution is the integral, 4.
    /// assert!((fitted.contribution(&[0.3], &mut [0.0]) - 4.0).abs() < 1e-12);
    /// # Ok::<(), mcint::Error>(())
    /// ```
    fn fitted(&self, pilot: &CovarianceAccumulator) -> Result<Box<dyn Estimator + '_>>;
}
