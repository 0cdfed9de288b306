//! Control variates with a known integral (Jarosz's A.26-A.29).
//!
//! With a control `g` whose integral `G` over the domain is known exactly,
//! `F = int (f - g) + G` (A.26), and averaging `(f - g)/pdf` over samples from `pdf` and adding
//! `G` estimates `F` (A.27). Equivalently (A.29) the estimate is `<F^N> + G - <G^N>`: the plain
//! estimate corrected by the sampling error that the same points make on the known integral.
//! A coefficient `beta` generalises this to `<F^N> - beta (<G^N> - G)`, which is unbiased for
//! every fixed `beta` and has per-sample variance
//! `Var[f/pdf] - 2 beta Cov[f/pdf, g/pdf] + beta^2 Var[g/pdf]`, smallest at
//! `beta* = Cov[f/pdf, g/pdf] / Var[g/pdf]`, where it is `(1 - rho^2) Var[f/pdf]` (Lavenberg &
//! Welch 1981; Glasserman 2004, section 4.1; Owen, *Monte Carlo theory, methods and examples*,
//! section 8.9). Estimating `beta*` on a pilot, for one or several controls, is
//! [`FittedControlVariates`](super::FittedControlVariates).

use super::Estimator;
use crate::error::{Error, Result};
use crate::pdf::Pdf;

/// The control-variate contribution `f(X)/pdf(X) - beta g(X)/pdf(X) + beta G` with `X` drawn
/// from `pdf` (A.27 for `beta = 1`, the default; A.29 with a coefficient).
///
/// `G` must be the exact integral of `g` over the pdf's domain (for a [`UniformBox`], the box).
/// With `Y = f/pdf` and `Z = g/pdf`, the per-sample variance is
/// `Var[Y] - 2 beta Cov[Y, Z] + beta^2 Var[Z]`, smallest at `beta* = Cov[Y, Z] / Var[Z]`
/// where it is `(1 - rho^2) Var[Y]`; `beta = 1` (A.27) helps when `Var[Z] < 2 Cov[Y, Z]`.
/// Since `beta` is fixed, every contribution has expectation `F` and the estimator is unbiased
/// with any sampler; it works with [`Integrator`](crate::Integrator) as is, including
/// stratified and quasi-Monte Carlo samplers with replicates. A coefficient estimated from a
/// separate pilot run keeps that property (which is how
/// [`FittedControlVariates`](super::FittedControlVariates) fits its coefficients); one estimated from the
/// same samples does not.
///
/// The contribution is computed as `f/pdf - beta (g/pdf - G)`, so that a control with a large
/// constant part cancels against its own integral. Where `f` and `g` are both zero it is
/// `beta G` whatever the pdf (no `0/0`); where the pdf is zero but `f` or `g` is not, it is
/// infinite or NaN, which the integrator reports as an error.
///
/// [`UniformBox`]: crate::pdf::UniformBox
///
/// ```
/// use mcint::{Integrator, estimator::FixedControlVariate, pdf::UniformBox};
/// // int_0^1 e^x dx = e - 1 with the control g = 1 + x, G = 3/2 (A.27).
/// let cv = FixedControlVariate::new(|x: &[f64]| x[0].exp(), |x: &[f64]| 1.0 + x[0], 1.5, UniformBox::unit(1)?)?;
/// let e = Integrator::new(cv).samples(10_000).seed(1).run()?;
/// let exact = std::f64::consts::E - 1.0;
/// assert!((e.mean - exact).abs() < 4.5 * e.std_error.unwrap());
/// // Per sample, the sd is 0.21 with the control and 0.49 without (plain Monte Carlo).
/// assert!(e.std_error.unwrap() < 0.25 / 100.0);
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct FixedControlVariate<F, G, P> {
    f: F,
    control: G,
    control_integral: f64,
    coefficient: f64,
    pdf: P,
}

impl<F, G, P> FixedControlVariate<F, G, P>
where
    F: Fn(&[f64]) -> f64 + Send + Sync,
    G: Fn(&[f64]) -> f64 + Send + Sync,
    P: Pdf,
{
    /// The estimator of the integral of `f` over the pdf's domain with the control `control`,
    /// whose exact integral over that domain is `control_integral` (finite), coefficient 1.
    ///
    /// ```
    /// use mcint::estimator::FixedControlVariate;
    /// use mcint::pdf::UniformBox;
    /// let bad = FixedControlVariate::new(|_: &[f64]| 1.0, |_: &[f64]| 1.0, f64::NAN, UniformBox::unit(1).unwrap());
    /// assert!(bad.err().unwrap().to_string().contains("control_integral"));
    /// ```
    pub fn new(f: F, control: G, control_integral: f64, pdf: P) -> Result<Self> {
        if !control_integral.is_finite() {
            return Err(Error::invalid(
                "control_integral",
                control_integral,
                "the finite, exactly known integral of the control over the domain",
            ));
        }
        Ok(FixedControlVariate {
            f,
            control,
            control_integral,
            coefficient: 1.0,
            pdf,
        })
    }

    /// Sets the fixed coefficient `beta` (finite; 1 gives A.27, 0 plain importance sampling).
    ///
    /// ```
    /// use mcint::estimator::{FixedControlVariate, Estimator};
    /// use mcint::pdf::UniformBox;
    /// let cv = FixedControlVariate::new(|x: &[f64]| 2.0 * x[0], |x: &[f64]| x[0], 0.5, UniformBox::unit(1).unwrap())
    ///     .unwrap()
    ///     .with_coefficient(2.0)
    ///     .unwrap();
    /// let mut x = [0.0];
    /// assert_eq!(cv.contribution(&[0.3], &mut x), 1.0); // f - 2 g = 0: zero variance
    /// assert!(cv.with_coefficient(f64::INFINITY).is_err());
    /// // beta times the control's integral, part of every contribution, must be finite.
    /// let huge = FixedControlVariate::new(|x: &[f64]| x[0], |x: &[f64]| x[0], f64::MAX, UniformBox::unit(1).unwrap());
    /// assert!(huge.unwrap().with_coefficient(2.0).is_err());
    /// ```
    pub fn with_coefficient(self, coefficient: f64) -> Result<Self> {
        // Every contribution takes beta (g/pdf - G): where beta G overflows, so would it.
        if !(coefficient.is_finite() && (coefficient * self.control_integral).is_finite()) {
            return Err(Error::invalid(
                "coefficient",
                coefficient,
                format!(
                    "a finite control-variate coefficient beta with beta * control_integral \
                     finite (control_integral = {:e})",
                    self.control_integral
                ),
            ));
        }
        Ok(FixedControlVariate {
            coefficient,
            ..self
        })
    }

    /// The coefficient `beta`.
    ///
    /// ```
    /// use mcint::estimator::FixedControlVariate;
    /// let cv = FixedControlVariate::new(|_: &[f64]| 1.0, |_: &[f64]| 1.0, 1.0, mcint::pdf::UniformBox::unit(1).unwrap()).unwrap();
    /// assert_eq!(cv.coefficient(), 1.0);
    /// ```
    pub fn coefficient(&self) -> f64 {
        self.coefficient
    }

    /// The known integral `G` of the control.
    ///
    /// ```
    /// use mcint::estimator::FixedControlVariate;
    /// let cv = FixedControlVariate::new(|_: &[f64]| 1.0, |_: &[f64]| 1.0, 2.0, mcint::pdf::UniformBox::new(vec![0.0], vec![2.0]).unwrap()).unwrap();
    /// assert_eq!(cv.control_integral(), 2.0);
    /// ```
    pub fn control_integral(&self) -> f64 {
        self.control_integral
    }

    /// The sampling density.
    ///
    /// ```
    /// use mcint::{Pdf, estimator::FixedControlVariate};
    /// let cv = FixedControlVariate::new(|_: &[f64]| 1.0, |_: &[f64]| 1.0, 1.0, mcint::pdf::UniformBox::unit(3).unwrap()).unwrap();
    /// assert_eq!(cv.pdf().dims(), 3);
    /// ```
    pub fn pdf(&self) -> &P {
        &self.pdf
    }
}

impl<F, G, P> Estimator for FixedControlVariate<F, G, P>
where
    F: Fn(&[f64]) -> f64 + Send + Sync,
    G: Fn(&[f64]) -> f64 + Send + Sync,
    P: Pdf,
{
    fn canonical_dims(&self) -> usize {
        self.pdf.canonical_dims()
    }

    fn domain_dims(&self) -> usize {
        self.pdf.dims()
    }

    #[inline]
    fn contribution(&self, u: &[f64], x: &mut [f64]) -> f64 {
        self.pdf.sample(u, x);
        let (value, control) = ((self.f)(x), (self.control)(x));
        // `f/p - beta (g/p - G)`: the control's deviation from its integral is formed first,
        // so that a control with a large constant part cancels against its own integral, not
        // against f. A zero value needs no density (no 0/0 where the pdf is zero).
        let density = if value == 0.0 && control == 0.0 {
            1.0
        } else {
            self.pdf.pdf(x)
        };
        let over = |v: f64| if v == 0.0 { 0.0 } else { v / density };
        over(value) - self.coefficient * (over(control) - self.control_integral)
    }
}
