//! The basic Monte Carlo estimator over a box (Jarosz's A.14).

use super::Estimator;
use super::box_block::{is_unit, with_mapped};
use crate::pdf::{Pdf, UniformBox};
use crate::points::Points;

/// `<F^N> = V (1/N) sum f(X_i)` with `X_i` uniform in a box of volume `V`: equation A.14,
/// `(b - a) (1/N) sum_{i=0}^{N-1} f(a + xi_i (b - a))`, in any dimension.
///
/// (Jarosz's A.12 prints `1/(N-1)` and a sum to `N`; that is a typo, the estimator is A.14.)
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
        let f = |x: &[f64]| volume * (self.f)(x);
        with_mapped(&self.domain, self.unit, points, |mapped| {
            let columns: Vec<&[f64]> = (0..mapped.dims()).map(|d| mapped.column(d)).collect();
            let out = &mut out[..mapped.len()];
            match columns.len() {
                1 => gather_fixed::<1>(&columns, out, f),
                2 => gather_fixed::<2>(&columns, out, f),
                3 => gather_fixed::<3>(&columns, out, f),
                4 => gather_fixed::<4>(&columns, out, f),
                5 => gather_fixed::<5>(&columns, out, f),
                6 => gather_fixed::<6>(&columns, out, f),
                7 => gather_fixed::<7>(&columns, out, f),
                8 => gather_fixed::<8>(&columns, out, f),
                _ => gather(&columns, out, f),
            }
        });
    }
}

/// `out[i] = f(point i)` for the points whose coordinates are `columns`, each point gathered
/// into a buffer.
fn gather(columns: &[&[f64]], out: &mut [f64], f: impl Fn(&[f64]) -> f64) {
    let mut x = vec![0.0; columns.len()];
    for (i, y) in out.iter_mut().enumerate() {
        for (slot, column) in x.iter_mut().zip(columns) {
            *slot = column[i];
        }
        *y = f(&x);
    }
}

/// [`gather`] for `D` dimensions known at compile time: each point is built as an array value,
/// which the compiler keeps in registers when `f` is inlined, instead of a round trip through
/// a buffer written one coordinate at a time (several times slower for a cheap integrand).
fn gather_fixed<const D: usize>(columns: &[&[f64]], out: &mut [f64], f: impl Fn(&[f64]) -> f64) {
    let columns: [&[f64]; D] = std::array::from_fn(|d| &columns[d][..out.len()]);
    for (i, y) in out.iter_mut().enumerate() {
        let x: [f64; D] = std::array::from_fn(|d| columns[d][i]);
        *y = f(&x);
    }
}
