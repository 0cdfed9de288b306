//! The basic Monte Carlo estimator over a box (the seed's A.14).

use super::Estimator;
use super::box_block::{is_unit, with_mapped};
use crate::Points;
use crate::pdf::{Pdf, UniformBox};

/// `<F^N> = V (1/N) sum f(X_i)` with `X_i` uniform in a box of volume `V`: equation A.14,
/// `(b - a) (1/N) sum_{i=0}^{N-1} f(a + xi_i (b - a))`, in any dimension.
///
/// (The seed's A.12 prints `1/(N-1)` and a sum to `N`; that is a typo, the estimator is A.14.)
///
/// ```
/// use mcint::estimator::{Estimator, UniformEstimator};
/// use mcint::pdf::UniformBox;
/// let e = UniformEstimator::new(|x: &[f64]| x[0] + x[1], UniformBox::unit(2).unwrap());
/// let mut x = [0.0; 2];
/// assert_eq!(e.contribution(&[0.25, 0.5], &mut x), 0.75);
/// ```
#[derive(Debug, Clone)]
pub struct UniformEstimator<F> {
    f: F,
    domain: UniformBox,
    /// The domain is `[0,1)^d`: canonical points need no mapping.
    unit: bool,
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync> UniformEstimator<F> {
    /// Estimates the integral of `f` over `domain`.
    ///
    /// ```
    /// let e = mcint::estimator::UniformEstimator::new(|x: &[f64]| x[0], mcint::pdf::UniformBox::unit(1).unwrap());
    /// assert_eq!(e.domain().volume(), 1.0);
    /// ```
    pub fn new(f: F, domain: UniformBox) -> Self {
        let unit = is_unit(&domain);
        UniformEstimator { f, domain, unit }
    }

    /// The integration domain.
    ///
    /// ```
    /// let e = mcint::estimator::UniformEstimator::new(|_: &[f64]| 1.0, mcint::pdf::UniformBox::unit(3).unwrap());
    /// assert_eq!(e.domain().lo().len(), 3);
    /// ```
    pub fn domain(&self) -> &UniformBox {
        &self.domain
    }
}

impl<F: Fn(&[f64]) -> f64 + Send + Sync> Estimator for UniformEstimator<F> {
    fn canonical_dims(&self) -> usize {
        self.domain.dims()
    }

    fn domain_dims(&self) -> usize {
        self.domain.dims()
    }

    #[inline]
    fn contribution(&self, u: &[f64], x: &mut [f64]) -> f64 {
        self.domain.sample(u, x);
        self.domain.volume() * (self.f)(x)
    }

    /// The block is mapped into the box column by column (vectorized, and skipped over the
    /// unit cube), then `f` is called per point; the values have the bits of
    /// [`contribution`](Self::contribution).
    fn contributions(&self, points: &Points, out: &mut [f64]) {
        let volume = self.domain.volume();
        with_mapped(&self.domain, self.unit, points, |mapped| {
            let columns: Vec<&[f64]> = (0..mapped.dims()).map(|d| mapped.column(d)).collect();
            let mut x = vec![0.0; columns.len()];
            for (i, y) in out.iter_mut().enumerate().take(mapped.len()) {
                for (slot, column) in x.iter_mut().zip(&columns) {
                    *slot = column[i];
                }
                *y = volume * (self.f)(&x);
            }
        });
    }
}
