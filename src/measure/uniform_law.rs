//! The uniform law on a box, as a [`Measure`]: `E[f(X)]` for `X` uniform on the box.

use super::Measure;
use crate::error::Result;
use crate::pdf::{Pdf, UniformBox};

/// The uniform probability law on a box: `u` maps affinely to the box with weight 1, so
/// [`Integrator::expectation`](crate::Integrator::expectation) gives the mean of `f` over the
/// box (where [`Integrator::over_box`](crate::Integrator::over_box) gives its integral, the
/// mean times the volume). The law of the inputs of a sensitivity analysis on a box.
///
/// ```
/// use mcint::{Integrator, measure::{Measure, Uniform}};
/// let square = Uniform::new(vec![0.0, 0.0], vec![2.0, 2.0]).unwrap();
/// let mut x = [0.0; 2];
/// assert_eq!(square.map(&[0.5, 0.25], &mut x), 1.0);
/// assert_eq!(x, [1.0, 0.5]);
/// let mean = Integrator::expectation(|x: &[f64]| x[0], square).samples(1 << 12).run().unwrap();
/// assert!((mean.mean - 1.0).abs() < 5.0 * mean.std_error.unwrap());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Uniform {
    domain: UniformBox,
}

impl Uniform {
    /// The uniform law on the box with corners `lo` and `hi` (as [`UniformBox::new`] checks
    /// them).
    ///
    /// ```
    /// use mcint::measure::Uniform;
    /// assert!(Uniform::new(vec![1.0], vec![0.0]).is_err());
    /// ```
    pub fn new(lo: Vec<f64>, hi: Vec<f64>) -> Result<Self> {
        Ok(Uniform::from(UniformBox::new(lo, hi)?))
    }

    /// The uniform law on the unit cube `[0,1)^dims`.
    ///
    /// ```
    /// use mcint::measure::{Measure, Uniform};
    /// assert_eq!(Uniform::unit(4).unwrap().dims(), 4);
    /// assert!(Uniform::unit(0).is_err());
    /// ```
    pub fn unit(dims: usize) -> Result<Self> {
        Ok(Uniform::from(UniformBox::unit(dims)?))
    }

    /// The box.
    ///
    /// ```
    /// use mcint::measure::Uniform;
    /// assert_eq!(Uniform::new(vec![0.0], vec![2.0]).unwrap().domain().hi(), &[2.0]);
    /// ```
    pub fn domain(&self) -> &UniformBox {
        &self.domain
    }
}

/// ```
/// use mcint::{measure::{Measure, Uniform}, pdf::UniformBox};
/// assert_eq!(Uniform::from(UniformBox::unit(3).unwrap()).dims(), 3);
/// ```
impl From<UniformBox> for Uniform {
    fn from(domain: UniformBox) -> Self {
        Uniform { domain }
    }
}

impl Measure for Uniform {
    fn canonical_dims(&self) -> usize {
        self.domain.dims()
    }

    fn dims(&self) -> usize {
        self.domain.dims()
    }

    fn map(&self, u: &[f64], x: &mut [f64]) -> f64 {
        self.domain.sample(u, x);
        1.0
    }
}
