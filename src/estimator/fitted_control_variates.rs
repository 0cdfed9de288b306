//! [`FittedControlVariates`]: several control variates whose coefficients are fitted by least
//! squares on a pilot stage, then held fixed for the main run.
//!
//! With controls `g_1..g_k` of known integrals `G_1..G_k` (Jarosz's A.26-A.29 with several
//! controls), write `Y = f(X)/pdf(X)` and `Z_j = g_j(X)/pdf(X)`, so that `E[Z_j] = G_j`. For any
//! fixed `beta`, `Y - beta^T (Z - G)` has mean `E[Y]`; its variance is smallest at
//! `beta* = Cov(Z)^-1 Cov(Z, Y)`, where it is `(1 - R^2) Var(Y)` with `R^2` the squared multiple
//! correlation of `Y` on `Z` (`rho^2` for one control) (Lavenberg & Welch 1981; Glasserman
//! 2004, section 4.1; Owen, *Monte Carlo theory, methods and examples*, section 8.9).
//!
//! The coefficients are the least-squares fit on a pilot of independent points, separate from
//! the main run. Fitting on the main run's own samples (the classical regression estimator)
//! makes the coefficients depend on the very samples they correct: a bias of order `1/n`, and
//! a standard error that needs the regression's own formula, which holds only for independent
//! points. With a pilot the main run uses a fixed estimator, so it is unbiased and its error
//! bar is the Integrator's usual one, for independent points and, through replicates, for
//! stratified and randomized quasi-Monte Carlo points alike; the price is the pilot's
//! evaluations and an excess variance of order `k / pilot` over `(1 - R^2) Var(Y)`.

use super::{ControlDomain, Estimator, PilotFit};
use crate::error::{Error, Result};
use crate::stats::CovarianceAccumulator;

/// Pilot points when the caller gives none.
const DEFAULT_PILOT: u64 = 4096;
/// A control whose residual variance, after regression on the controls before it, is below
/// this fraction of its own is collinear with them.
const COLLINEARITY_TOLERANCE: f64 = 1e-10;

/// Controls whose values are all below this magnitude (about `1e-140`) can have co-moments
/// that underflow to 0 (squares of values below about `1e-154`, summed), and then "constant"
/// cannot be told from "small". (A co-moment that kept a few bits still gives a coefficient:
/// a rough one costs variance, never the estimate's honesty.)
const SMALL_CONTROL: f64 = 1e-140;

type ControlFn<'a> = Box<dyn Fn(&[f64]) -> f64 + Send + Sync + 'a>;

/// `f` sampled from `pdf`, corrected by controls `g_j` with known integrals `G_j`, with
/// coefficients fitted on a pilot stage.
///
/// With `Y = f(X)/pdf(X)` and `Z_j = g_j(X)/pdf(X)` (so `E[Z_j] = G_j`), every fixed `beta`
/// makes `Y - beta^T (Z - G)` an unbiased contribution, of least variance
/// `(1 - R^2) Var(Y)` at `beta* = Cov(Z)^-1 Cov(Z, Y)`. The coefficients are the least-squares
/// fit on a pilot of independent points, separate from the main run, so the main run uses a
/// fixed estimator: unbiased, with the Integrator's usual error bar, for independent points
/// and, through replicates, for stratified and randomized QMC points alike. (Fitting on the
/// main run's own samples, the classical regression estimator, has a bias of order `1/n` and
/// an error bar that holds only for independent points.) The price is the pilot's
/// evaluations and an excess variance of order `k / pilot` over `(1 - R^2) Var(Y)`.
///
/// Outside an [`Integrator`](crate::Integrator) run (which fits the coefficients first), its
/// contributions are the plain `f/pdf`.
///
/// ```
/// use mcint::{Integrator, pdf::UniformBox};
/// // e^x on [0, 1] with the control x (integral 1/2): rho^2 = 0.98.
/// let e = Integrator::with_controls(|x: &[f64]| x[0].exp(), UniformBox::unit(1).unwrap())
///     .control(|x: &[f64]| x[0], 0.5)
///     .samples(20_000)
///     .run()
///     .unwrap();
/// let exact = std::f64::consts::E - 1.0;
/// assert!((e.mean - exact).abs() < 5.0 * e.std_error.unwrap());
/// assert!(e.std_error.unwrap() < 0.2 * (0.242f64 / 20_000.0).sqrt()); // plain: Var = 0.242
/// ```
pub struct FittedControlVariates<'a, F, P> {
    f: F,
    domain: P,
    controls: Vec<(ControlFn<'a>, f64)>,
    pilot: u64,
}

/// The least-squares fit of the controls on a pilot.
///
/// ```
/// use mcint::{Integrator, pdf::UniformBox};
/// let fit = Integrator::with_controls(|x: &[f64]| x[0].exp(), UniformBox::unit(1).unwrap())
///     .control(|x: &[f64]| x[0], 0.5)
///     .fit()
///     .unwrap();
/// assert!((fit.coefficients[0] - 1.69).abs() < 0.05); // beta* = Cov(e^x, x) / Var(x)
/// assert!(fit.variance_reduction < 0.05); // 1 - rho^2 = 0.016
/// ```
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct ControlFit {
    /// The coefficients `beta`, one per control.
    pub coefficients: Vec<f64>,
    /// The pilot's sample variance of `f/pdf`.
    pub plain_variance: f64,
    /// The pilot's residual variance of the regression (on `n - k - 1` degrees of freedom).
    pub residual_variance: f64,
    /// The pilot's `1 - R^2`: residual over total sum of squares, the fraction of the
    /// per-sample variance the controls leave.
    pub variance_reduction: f64,
}

impl<'a, F, P> FittedControlVariates<'a, F, P>
where
    F: Fn(&[f64]) -> f64 + Send + Sync,
    P: ControlDomain,
{
    /// `f` sampled from `domain`: a pdf (a [`UniformBox`](crate::pdf::UniformBox) for plain
    /// Monte Carlo) or a measure wrapped in [`OverMeasure`](super::OverMeasure); with no
    /// controls yet and a pilot of 4096 points.
    ///
    /// ```
    /// use mcint::{estimator::FittedControlVariates, pdf::UniformBox};
    /// let cv = FittedControlVariates::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap());
    /// assert_eq!(cv.controls(), 0);
    /// ```
    pub fn new(f: F, domain: P) -> Self {
        FittedControlVariates {
            f,
            domain,
            controls: Vec::new(),
            pilot: DEFAULT_PILOT,
        }
    }

    /// Adds a control `g` whose exact integral over the pdf's domain is `integral` (checked to
    /// be finite when the pilot is fitted).
    ///
    /// ```
    /// use mcint::{estimator::FittedControlVariates, pdf::UniformBox};
    /// let cv = FittedControlVariates::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap())
    ///     .control(|x: &[f64]| x[0], 0.5);
    /// assert_eq!(cv.controls(), 1);
    /// ```
    pub fn control(mut self, g: impl Fn(&[f64]) -> f64 + Send + Sync + 'a, integral: f64) -> Self {
        self.controls.push((Box::new(g), integral));
        self
    }

    /// Points of the pilot stage (more than the number of controls plus one; default 4096).
    ///
    /// ```
    /// use mcint::{estimator::{FittedControlVariates, Estimator}, pdf::UniformBox};
    /// let cv = FittedControlVariates::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).pilot_points(100);
    /// assert_eq!(cv.pilot().unwrap().points(), 100);
    /// ```
    pub fn pilot_points(mut self, n: u64) -> Self {
        self.pilot = n;
        self
    }

    /// Number of controls.
    ///
    /// ```
    /// use mcint::{estimator::FittedControlVariates, pdf::UniformBox};
    /// assert_eq!(FittedControlVariates::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap()).controls(), 0);
    /// ```
    pub fn controls(&self) -> usize {
        self.controls.len()
    }

    /// The least-squares fit of the controls to the pilot's rows `(f/pdf, g_1/pdf, ..)` (their
    /// count, means and co-moments, as [`PilotFit::row`] writes them).
    ///
    /// Errors when there is no control, an integral is not finite, the pilot has fewer than
    /// `k + 2` finite rows, a control is constant or collinear with the ones before it, or the
    /// correction `beta^T G` overflows.
    ///
    /// ```
    /// use mcint::{estimator::FittedControlVariates, pdf::UniformBox, stats::CovarianceAccumulator};
    /// let cv = FittedControlVariates::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap());
    /// let err = cv.fit(&CovarianceAccumulator::new(1)?).unwrap_err();
    /// assert!(err.to_string().contains("at least one control"));
    /// # Ok::<(), mcint::Error>(())
    /// ```
    pub fn fit(&self, pilot: &CovarianceAccumulator) -> Result<ControlFit> {
        let k = self.controls.len();
        if k == 0 {
            return Err(Error::invalid(
                "controls",
                0,
                "at least one control (add one with .control(g, integral))",
            ));
        }
        if let Some((j, (_, integral))) = self
            .controls
            .iter()
            .enumerate()
            .find(|(_, (_, g))| !g.is_finite())
        {
            return Err(Error::invalid(
                "control integral",
                format!("{integral} (integral of control {j})"),
                "the finite, exactly known integral of the control over the domain",
            ));
        }
        let least = k as u64 + 2;
        if pilot.count() < least {
            return Err(Error::invalid(
                "pilot points",
                pilot.count(),
                format!(
                    "at least {least} finite pilot rows (the number of controls plus two, for \
                     one degree of freedom in the residual variance)"
                ),
            ));
        }
        least_squares(pilot, k)
    }
}

impl<F, P> Estimator for FittedControlVariates<'_, F, P>
where
    F: Fn(&[f64]) -> f64 + Send + Sync,
    P: ControlDomain,
{
    fn canonical_dims(&self) -> usize {
        self.domain.canonical_dims()
    }

    fn domain_dims(&self) -> usize {
        self.domain.dims()
    }

    fn contribution(&self, u: &[f64], x: &mut [f64]) -> f64 {
        let factor = self.domain.place(u, x);
        self.domain.weigh((self.f)(x), factor)
    }

    fn pilot(&self) -> Option<&dyn PilotFit> {
        Some(self)
    }
}

impl<F, P> PilotFit for FittedControlVariates<'_, F, P>
where
    F: Fn(&[f64]) -> f64 + Send + Sync,
    P: ControlDomain,
{
    fn points(&self) -> u64 {
        self.pilot
    }

    fn values(&self) -> usize {
        1 + self.controls.len()
    }

    fn row(&self, u: &[f64], x: &mut [f64], row: &mut [f64]) {
        let factor = self.domain.place(u, x);
        row[0] = self.domain.weigh((self.f)(x), factor);
        for (slot, (g, _)) in row[1..].iter_mut().zip(&self.controls) {
            *slot = self.domain.weigh(g(x), factor);
        }
    }

    fn fitted(&self, pilot: &CovarianceAccumulator) -> Result<Box<dyn Estimator + '_>> {
        let fit = self.fit(pilot)?;
        let shift: f64 = fit
            .coefficients
            .iter()
            .zip(&self.controls)
            .map(|(b, (_, integral))| b * integral)
            .sum();
        if !shift.is_finite() {
            return Err(Error::invalid(
                "control integral",
                format!(
                    "{:?}",
                    self.controls.iter().map(|c| c.1).collect::<Vec<_>>()
                ),
                format!(
                    "integrals whose correction beta^T G stays finite (beta = {:?})",
                    fit.coefficients
                ),
            ));
        }
        Ok(Box::new(Fitted {
            cv: self,
            coefficients: fit.coefficients,
        }))
    }
}

/// The main run's estimator: `f/pdf - beta^T (g/pdf - G)` with the fitted `beta`.
struct Fitted<'c, 'a, F, P> {
    cv: &'c FittedControlVariates<'a, F, P>,
    coefficients: Vec<f64>,
}

impl<F, P> Estimator for Fitted<'_, '_, F, P>
where
    F: Fn(&[f64]) -> f64 + Send + Sync,
    P: ControlDomain,
{
    fn canonical_dims(&self) -> usize {
        self.cv.canonical_dims()
    }

    fn domain_dims(&self) -> usize {
        self.cv.domain_dims()
    }

    fn contribution(&self, u: &[f64], x: &mut [f64]) -> f64 {
        let factor = self.cv.domain.place(u, x);
        // Each control's deviation from its integral is formed first: a control with a large
        // constant part then cancels against its own integral, exactly, not against f.
        let corrections: f64 = self
            .coefficients
            .iter()
            .zip(&self.cv.controls)
            .map(|(b, (g, integral))| b * (self.cv.domain.weigh(g(x), factor) - integral))
            .sum();
        self.cv.domain.weigh((self.cv.f)(x), factor) - corrections
    }
}

/// The least-squares coefficients of `Y` (entry 0) on `Z_1..Z_k` (entries `1..=k`) from their
/// merged moments, with the fit's variances.
fn least_squares(total: &CovarianceAccumulator, k: usize) -> Result<ControlFit> {
    let n = total.count();
    let l = cholesky(total, k)?;
    // beta = S_ZZ^-1 S_ZY, through L w = S_ZY and L^T beta = w.
    let mut beta: Vec<f64> = (0..k).map(|j| total.comoment(1 + j, 0)).collect();
    forward(&l, k, &mut beta);
    // With w = L^-1 S_ZY, the explained sum of squares is S_YZ S_ZZ^-1 S_ZY = |w|^2.
    let explained: f64 = beta.iter().map(|w| w * w).sum();
    backward(&l, k, &mut beta);
    let total_ss = total.comoment(0, 0);
    // Rounding can leave a tiny negative residual when f is (nearly) a combination of controls.
    let residual_ss = (total_ss - explained).max(0.0);
    Ok(ControlFit {
        coefficients: beta,
        plain_variance: total_ss / (n - 1) as f64,
        residual_variance: residual_ss / (n - k as u64 - 1) as f64,
        variance_reduction: if total_ss > 0.0 {
            residual_ss / total_ss
        } else {
            1.0
        },
    })
}

/// The Cholesky factor `L` (row-major, lower triangle) of the controls' co-moment matrix,
/// which is entry `(1 + i, 1 + j)` of the accumulator; fails when a control is constant or a
/// linear combination of the controls before it.
fn cholesky(total: &CovarianceAccumulator, k: usize) -> Result<Vec<f64>> {
    let mut l = vec![0.0; k * k];
    for j in 0..k {
        let diagonal = total.comoment(1 + j, 1 + j);
        let mean = total.mean(1 + j);
        let too_small = diagonal == 0.0 && mean != 0.0 && mean.abs() < SMALL_CONTROL;
        if too_small || !diagonal.is_finite() {
            return Err(Error::invalid(
                "control",
                format!(
                    "{j} (mean {mean:e} over the pilot, sum of squared deviations {diagonal:e})"
                ),
                "controls whose squares f64 can hold (values from about 1e-160 to 1e150): \
                 multiply the control and its integral by a constant (the coefficient scales \
                 with it; the estimate does not change)",
            ));
        }
        if diagonal <= 0.0 {
            return Err(Error::invalid(
                "control",
                format!("{j} (constant over the {} pilot points)", total.count()),
                "controls that vary over the domain (a constant control is collinear with the \
                 intercept, and its coefficient is not determined)",
            ));
        }
        let pivot = diagonal - (0..j).map(|m| l[j * k + m] * l[j * k + m]).sum::<f64>();
        if pivot.is_nan() || pivot <= COLLINEARITY_TOLERANCE * diagonal {
            return Err(Error::invalid(
                "control",
                format!(
                    "{j} (over the {} pilot points, a linear combination of the controls \
                     before it, 0 to {}, up to a relative residual variance {:.1e})",
                    total.count(),
                    j.saturating_sub(1),
                    pivot / diagonal
                ),
                format!(
                    "controls that are not collinear (relative residual variance above \
                     {COLLINEARITY_TOLERANCE:e}): drop the redundant control"
                ),
            ));
        }
        let root = pivot.sqrt();
        l[j * k + j] = root;
        for i in j + 1..k {
            let s = total.comoment(1 + i, 1 + j)
                - (0..j).map(|m| l[i * k + m] * l[j * k + m]).sum::<f64>();
            l[i * k + j] = s / root;
        }
    }
    Ok(l)
}

/// Solves `L w = b` (forward substitution) in place.
fn forward(l: &[f64], k: usize, b: &mut [f64]) {
    for i in 0..k {
        let s: f64 = (0..i).map(|m| l[i * k + m] * b[m]).sum();
        b[i] = (b[i] - s) / l[i * k + i];
    }
}

/// Solves `L^T x = b` (back substitution) in place.
fn backward(l: &[f64], k: usize, b: &mut [f64]) {
    for i in (0..k).rev() {
        let s: f64 = (i + 1..k).map(|m| l[m * k + i] * b[m]).sum();
        b[i] = (b[i] - s) / l[i * k + i];
    }
}
