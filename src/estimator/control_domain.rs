//! [`ControlDomain`]: what [`FittedControlVariates`](super::FittedControlVariates) sample
//! from, a [`Pdf`] or a [`Measure`] (through [`OverMeasure`]).

use crate::measure::Measure;
use crate::pdf::Pdf;

/// The law fitted control variates sample their points from, and how a value at a point
/// becomes a contribution: divided by the density for a [`Pdf`], multiplied by the weight
/// for a [`Measure`] wrapped in [`OverMeasure`]. A zero value contributes zero either way (no
/// `0/0` where a density vanishes, no `0 * inf`).
///
/// ```
/// use mcint::estimator::{ControlDomain, OverMeasure};
/// use mcint::{measure::Gaussian, pdf::UniformBox};
/// let (box2, mut x) = (UniformBox::new(vec![0.0, 0.0], vec![2.0, 1.0]).unwrap(), [0.0; 2]);
/// let density = box2.place(&[0.5, 0.5], &mut x);
/// assert_eq!((x, box2.weigh(3.0, density)), ([1.0, 0.5], 6.0)); // 3 / (1/2)
/// let normal = OverMeasure(Gaussian::standard(1).unwrap());
/// let weight = normal.place(&[0.5], &mut x[..1]);
/// assert_eq!((x[0], normal.weigh(3.0, weight)), (0.0, 3.0));
/// ```
pub trait ControlDomain: Send + Sync {
    /// Number of canonical coordinates one point consumes.
    ///
    /// ```
    /// use mcint::estimator::ControlDomain;
    /// assert_eq!(mcint::pdf::UniformBox::unit(3).unwrap().canonical_dims(), 3);
    /// ```
    fn canonical_dims(&self) -> usize;

    /// Number of coordinates of a point.
    ///
    /// ```
    /// use mcint::estimator::{ControlDomain, OverMeasure};
    /// assert_eq!(OverMeasure(mcint::measure::Gaussian::standard(2).unwrap()).dims(), 2);
    /// ```
    fn dims(&self) -> usize;

    /// Maps the canonical point `u` to `x` and returns what [`weigh`](Self::weigh) combines
    /// values at `x` with: the density at `x`, or the measure's weight of `u`.
    ///
    /// ```
    /// use mcint::estimator::ControlDomain;
    /// let mut x = [0.0];
    /// assert_eq!(mcint::pdf::UniformBox::unit(1).unwrap().place(&[0.25], &mut x), 1.0);
    /// assert_eq!(x, [0.25]);
    /// ```
    fn place(&self, u: &[f64], x: &mut [f64]) -> f64;

    /// The contribution of `value` at a point whose [`place`](Self::place) returned `factor`.
    ///
    /// ```
    /// use mcint::estimator::ControlDomain;
    /// let unit = mcint::pdf::UniformBox::unit(1).unwrap();
    /// assert_eq!(unit.weigh(0.0, 0.0), 0.0); // not 0/0
    /// ```
    fn weigh(&self, value: f64, factor: f64) -> f64;
}

impl<P: Pdf> ControlDomain for P {
    fn canonical_dims(&self) -> usize {
        Pdf::canonical_dims(self)
    }

    fn dims(&self) -> usize {
        Pdf::dims(self)
    }

    #[inline]
    fn place(&self, u: &[f64], x: &mut [f64]) -> f64 {
        self.sample(u, x);
        self.pdf(x)
    }

    #[inline]
    fn weigh(&self, value: f64, density: f64) -> f64 {
        if value == 0.0 { 0.0 } else { value / density }
    }
}

/// A [`Measure`] as the domain of fitted control variates: values at its points are
/// multiplied by their weights, so the estimate is `E[f(X)]` under a probability law (see
/// [`Integrator::expectation_with_controls`](crate::Integrator::expectation_with_controls)).
///
/// ```
/// use mcint::estimator::{ControlDomain, OverMeasure};
/// let gaussian = OverMeasure(mcint::measure::Gaussian::standard(3).unwrap());
/// assert_eq!((gaussian.canonical_dims(), gaussian.dims()), (3, 3));
/// ```
#[derive(Debug, Clone)]
pub struct OverMeasure<M>(pub M);

impl<M: Measure> ControlDomain for OverMeasure<M> {
    fn canonical_dims(&self) -> usize {
        self.0.canonical_dims()
    }

    fn dims(&self) -> usize {
        self.0.dims()
    }

    #[inline]
    fn place(&self, u: &[f64], x: &mut [f64]) -> f64 {
        self.0.map(u, x)
    }

    #[inline]
    fn weigh(&self, value: f64, weight: f64) -> f64 {
        if value == 0.0 { 0.0 } else { value * weight }
    }
}
