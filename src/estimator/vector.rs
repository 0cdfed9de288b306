//! [`VectorEstimator`]: several contributions from one canonical point, for integrands with
//! several outputs integrated over the same points.

use super::Estimator;
use crate::points::Points;

/// Turns canonical points into `m` contributions each, one per output of a vector-valued
/// integrand, whose means estimate `m` integrals over the same points.
///
/// Evaluating all outputs at once costs one integrand evaluation per point, whatever `m` is,
/// and gives the covariance of the `m` estimates, which functions of them (ratios, posterior
/// means, sensitivity indices) need for honest error bars. Implementations are pure, like
/// [`Estimator`]s: the same `u` always gives the same values.
///
/// ```
/// use mcint::estimator::{VectorEstimator, VectorUniformEstimator};
/// use mcint::pdf::UniformBox;
/// let e = VectorUniformEstimator::new(2, |x: &[f64], out: &mut [f64]| {
///     out[0] = x[0];
///     out[1] = x[0] * x[0];
/// }, UniformBox::new(vec![0.0], vec![2.0]).unwrap());
/// let (mut x, mut out) = ([0.0], [0.0; 2]);
/// e.contribution(&[0.5], &mut x, &mut out);
/// assert_eq!(out, [2.0 * 1.0, 2.0 * 1.0]); // volume 2 times f(1)
/// assert_eq!(e.outputs(), 2);
/// ```
pub trait VectorEstimator: Send + Sync {
    /// Number of outputs `m` (at least 1).
    fn outputs(&self) -> usize;

    /// Number of canonical coordinates each point consumes.
    fn canonical_dims(&self) -> usize;

    /// Number of coordinates of the domain point (length of the scratch buffer).
    fn domain_dims(&self) -> usize;

    /// The `m` contributions of the canonical point `u` into `out` (`out.len() ==
    /// outputs()`); `x` is scratch of length [`domain_dims`](Self::domain_dims).
    fn contribution(&self, u: &[f64], x: &mut [f64], out: &mut [f64]);

    /// Contributions of every point of a block, one column per output: output `k` of point
    /// `i` goes to `out[k * points.len() + i]` (`out.len() == outputs() * points.len()`). The
    /// default calls [`contribution`](Self::contribution) per point.
    fn contributions(&self, points: &Points, out: &mut [f64]) {
        let (len, m) = (points.len(), self.outputs());
        let mut u = vec![0.0; points.dims()];
        let mut x = vec![0.0; self.domain_dims()];
        let mut row = vec![0.0; m];
        for i in 0..len {
            points.copy_point(i, &mut u);
            self.contribution(&u, &mut x, &mut row);
            for (k, &y) in row.iter().enumerate() {
                out[k * len + i] = y;
            }
        }
    }

    /// How many points [`contributions`](Self::contributions) would like in one call (see
    /// [`Estimator::points_per_call`]; default 1024).
    ///
    /// ```
    /// use mcint::estimator::{VectorEstimator, VectorUniformEstimator};
    /// use mcint::pdf::UniformBox;
    /// let e = VectorUniformEstimator::new(2, |x: &[f64], o: &mut [f64]| o.fill(x[0]), UniformBox::unit(1).unwrap());
    /// assert_eq!(e.points_per_call(), 1024);
    /// ```
    fn points_per_call(&self) -> usize {
        super::DEFAULT_POINTS_PER_CALL
    }

    /// Integrand evaluations one point costs (default 1, for all `m` outputs together).
    ///
    /// ```
    /// use mcint::estimator::{VectorEstimator, VectorUniformEstimator};
    /// use mcint::pdf::UniformBox;
    /// let f = |x: &[f64], out: &mut [f64]| out.fill(x[0]);
    /// let e = VectorUniformEstimator::new(3, f, UniformBox::unit(1).unwrap());
    /// assert_eq!(e.evaluations_per_contribution(), 1);
    /// ```
    fn evaluations_per_contribution(&self) -> u64 {
        1
    }
}

/// A scalar [`Estimator`] seen as a vector estimator of one output: the same contributions,
/// bit for bit, so that scalar runs go through the same engine as vector ones.
pub(crate) struct SingleOutput<'a>(pub(crate) &'a dyn Estimator);

impl VectorEstimator for SingleOutput<'_> {
    fn outputs(&self) -> usize {
        1
    }

    fn canonical_dims(&self) -> usize {
        self.0.canonical_dims()
    }

    fn domain_dims(&self) -> usize {
        self.0.domain_dims()
    }

    fn contribution(&self, u: &[f64], x: &mut [f64], out: &mut [f64]) {
        out[0] = self.0.contribution(u, x);
    }

    fn contributions(&self, points: &Points, out: &mut [f64]) {
        self.0.contributions(points, out);
    }

    fn evaluations_per_contribution(&self) -> u64 {
        self.0.evaluations_per_contribution()
    }

    fn points_per_call(&self) -> usize {
        self.0.points_per_call()
    }
}
