//! [`Derived`]: a smooth function of several integrals (a ratio, a posterior mean, a
//! sensitivity index), estimated with a delta-method error bar.

use std::fmt;
use std::sync::Arc;

use super::estimate::Estimate;
use super::rounding::UNIT_ROUNDOFF;
use super::vector_estimate::VectorEstimate;
use super::warning::Warning;
use crate::error::{Error, Result};

/// An output weighs in a derived quantity's error bar when its standard error times the
/// gradient is at least this share (2^-26) of the largest such term: below, its variance adds
/// less than 2^-52 of the largest.
const WEIGHS: f64 = 1.0 / (1u64 << 26) as f64;

/// The least variance of an output that a derived quantity's error bar accepts, 2^-990 (about
/// `1e-298`): a normal number with room to spare, so that what the covariance loses to
/// subnormal rounding off its diagonal is below 2^-84 of what stands on it.
const SMALLEST_VARIANCE: f64 = f64::from_bits((1023 - 990) << 52);

type Value = Arc<dyn Fn(&[f64]) -> f64 + Send + Sync>;
type Gradient = Arc<dyn Fn(&[f64], &mut [f64]) + Send + Sync>;

/// A quantity `g(I_1, ..., I_m)` derived from the integrals of a vector run: a ratio
/// `I_i / I_j`, or any smooth `g` with a gradient given or taken by central differences.
///
/// Its estimate is `g` at the estimated integrals, with the delta-method standard error
/// `sqrt(grad g' S grad g)`, `S` the covariance of the estimated integrals
/// ([`VectorEstimate::covariance_matrix`]), and the degrees of freedom of the outputs it depends
/// on (the fewest): accurate to first order, once each integral is known to a few percent.
///
/// For replicate-based runs (randomized QMC, stratified points) the ratio is the **ratio of
/// the pooled means**, `mean(num) / mean(den)` over all replicates, not the mean of the `R`
/// replicate ratios: both are biased by `O(1/N)` for `N` points, but the bias of the mean of
/// ratios is that of one replicate (`R` times larger) and does not shrink as replicates are
/// added, while the ratio of means is as biased as one run of all `R N` points. Its standard
/// error comes from the replicates' covariance, as each output's does.
///
/// A ratio whose denominator's 95% interval contains zero is refused with an error that says
/// so: neither the ratio nor a first-order error bar means anything there. So is a quantity
/// of outputs whose standard errors are below about `1e-149` ([`Error::Unsupported`]): their
/// covariances underflow f64, and the integrand needs multiplying by a constant.
///
/// ```
/// use mcint::{Integrator, pdf::UniformBox, stats::Derived};
/// // The posterior mean of a uniform prior on [0, 1) with likelihood x^3: 4/5.
/// let f = |x: &[f64], out: &mut [f64]| {
///     let likelihood = x[0].powi(3);
///     out[0] = x[0] * likelihood;
///     out[1] = likelihood;
/// };
/// let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap())
///     .samples(200_000)
///     .run()
///     .unwrap();
/// let posterior_mean = run.derived(&Derived::ratio(0, 1)).unwrap();
/// assert!((posterior_mean.mean - 0.8).abs() < 5.0 * posterior_mean.std_error.unwrap());
/// // The same as a smooth function, with its gradient by central differences.
/// let smooth = run.derived(&Derived::smooth(|i: &[f64]| i[0] / i[1])).unwrap();
/// assert!((smooth.mean - posterior_mean.mean).abs() < 1e-15);
/// assert!((smooth.std_error.unwrap() / posterior_mean.std_error.unwrap() - 1.0).abs() < 1e-5);
/// ```
#[derive(Clone)]
pub struct Derived {
    kind: Kind,
}

#[derive(Clone)]
enum Kind {
    Ratio {
        numerator: usize,
        denominator: usize,
    },
    Smooth {
        value: Value,
        gradient: Option<Gradient>,
    },
}

impl fmt::Debug for Derived {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.kind {
            Kind::Ratio {
                numerator,
                denominator,
            } => write!(f, "Derived::ratio({numerator}, {denominator})"),
            Kind::Smooth { gradient, .. } => write!(
                f,
                "Derived::smooth(<function>, gradient: {})",
                if gradient.is_some() {
                    "given"
                } else {
                    "central differences"
                }
            ),
        }
    }
}

impl Derived {
    /// The ratio `I_numerator / I_denominator` of two outputs (exact gradient).
    ///
    /// ```
    /// use mcint::stats::Derived;
    /// assert_eq!(format!("{:?}", Derived::ratio(0, 1)), "Derived::ratio(0, 1)");
    /// ```
    pub fn ratio(numerator: usize, denominator: usize) -> Derived {
        Derived {
            kind: Kind::Ratio {
                numerator,
                denominator,
            },
        }
    }

    /// A smooth function `g` of all the integrals (`g` gets the `m` estimates), whose
    /// gradient is taken by central differences with steps of `eps^(1/3)` relative to each
    /// integral (or its standard error, whichever is larger): a relative error near `1e-10`
    /// in the gradient for a `g` smooth at that scale.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox, stats::Derived};
    /// let f = |x: &[f64], out: &mut [f64]| { out[0] = x[0]; out[1] = x[0] * x[0]; };
    /// let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap()).samples(100_000).run().unwrap();
    /// // The variance of x, E[x^2] - E[x]^2 = 1/12.
    /// let variance = run.derived(&Derived::smooth(|i: &[f64]| i[1] - i[0] * i[0])).unwrap();
    /// assert!((variance.mean - 1.0 / 12.0).abs() < 5.0 * variance.std_error.unwrap());
    /// ```
    pub fn smooth(g: impl Fn(&[f64]) -> f64 + Send + Sync + 'static) -> Derived {
        Derived {
            kind: Kind::Smooth {
                value: Arc::new(g),
                gradient: None,
            },
        }
    }

    /// A smooth function `g` with its gradient: `gradient(integrals, out)` writes
    /// `dg/dI_k` to `out[k]`.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox, stats::Derived};
    /// let f = |x: &[f64], out: &mut [f64]| { out[0] = x[0]; out[1] = x[0] * x[0]; };
    /// let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap()).samples(100_000).run().unwrap();
    /// let g = |i: &[f64]| i[1] - i[0] * i[0];
    /// let gradient = |i: &[f64], out: &mut [f64]| { out[0] = -2.0 * i[0]; out[1] = 1.0; };
    /// let exact = run.derived(&Derived::smooth_with_gradient(g, gradient)).unwrap();
    /// let differences = run.derived(&Derived::smooth(g)).unwrap();
    /// assert!((exact.std_error.unwrap() / differences.std_error.unwrap() - 1.0).abs() < 1e-6);
    /// ```
    pub fn smooth_with_gradient(
        g: impl Fn(&[f64]) -> f64 + Send + Sync + 'static,
        gradient: impl Fn(&[f64], &mut [f64]) + Send + Sync + 'static,
    ) -> Derived {
        Derived {
            kind: Kind::Smooth {
                value: Arc::new(g),
                gradient: Some(Arc::new(gradient)),
            },
        }
    }

    /// Checks the output indices of a ratio against `m` outputs.
    pub(crate) fn check(&self, m: usize) -> Result<()> {
        if let Kind::Ratio {
            numerator,
            denominator,
        } = self.kind
        {
            for (what, index) in [
                ("ratio numerator", numerator),
                ("ratio denominator", denominator),
            ] {
                if index >= m {
                    return Err(Error::invalid(
                        what,
                        index,
                        format!("an output index below {m}"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The value and gradient of `g` at the estimated integrals.
    fn value_and_gradient(&self, run: &VectorEstimate) -> Result<(f64, Vec<f64>)> {
        let means = run.means();
        let m = means.len();
        self.check(m)?;
        let mut gradient = vec![0.0; m];
        match &self.kind {
            Kind::Ratio {
                numerator,
                denominator,
            } => {
                let (num, den) = (means[*numerator], &run.outputs[*denominator]);
                if let Some((lo, hi)) = den.confidence_interval(0.95)?
                    && lo <= 0.0
                    && 0.0 <= hi
                {
                    return Err(Error::invalid(
                        "ratio denominator",
                        format!(
                            "output {denominator} = {} (95% interval [{lo:e}, {hi:e}])",
                            den.mean
                        ),
                        "a denominator whose 95% interval excludes zero (the ratio and its error \
                         bar mean nothing there: integrate the denominator more accurately)",
                    ));
                }
                if den.mean == 0.0 {
                    return Err(Error::invalid(
                        "ratio denominator",
                        format!("output {denominator} = 0"),
                        "a nonzero denominator",
                    ));
                }
                gradient[*numerator] += 1.0 / den.mean;
                gradient[*denominator] -= num / (den.mean * den.mean);
                Ok((num / den.mean, gradient))
            }
            Kind::Smooth {
                value,
                gradient: given,
            } => {
                // A panic in the user's function is an error, as one in an integrand is.
                let at = crate::panics::guarded((0, 0), || {
                    let at = value(&means);
                    match given {
                        Some(g) => g(&means, &mut gradient),
                        None => central_differences(value, &means, run, &mut gradient),
                    }
                    Ok(at)
                })?;
                if !at.is_finite() || gradient.iter().any(|g| !g.is_finite()) {
                    return Err(Error::invalid(
                        "derived quantity",
                        format!("g = {at} with gradient {gradient:?} at the estimates {means:?}"),
                        "a function with a finite value and gradient at the estimated integrals",
                    ));
                }
                Ok((at, gradient))
            }
        }
    }

    /// Refuses a run whose covariance cannot carry this quantity's error bar: an output that
    /// weighs in it (its standard error times `|dg/dI_k|` at least 2^-26 of the largest such
    /// term, and at least 2^-495) with a standard error below about `1e-149`, whose square,
    /// on the covariance's diagonal, and the products off it leave the normal range of f64
    /// (the error bar of a ratio came out 2e-10 of the true one, or infinite, for integrands
    /// near `1e-160`). When the gradient itself cannot be formed (a smooth function's can
    /// overflow there), every output is checked. A panic in a smooth quantity's function is
    /// returned too: it stops a run to a tolerance at once, as a panic in the integrand does,
    /// where the other errors (a denominator near zero, a value not yet finite) may pass with
    /// more points.
    pub(crate) fn check_representable(&self, run: &VectorEstimate) -> Result<()> {
        match self.value_and_gradient(run) {
            Ok((_, gradient)) => self.underflow_error(run, Some(&gradient)),
            Err(panicked @ Error::IntegrandPanicked { .. }) => Err(panicked),
            Err(_) => self.underflow_error(run, None),
        }
    }

    /// The error of [`check_representable`](Self::check_representable), given the gradient
    /// when there is one; `Ok` without one for a ratio (whose own errors say more).
    fn underflow_error(&self, run: &VectorEstimate, gradient: Option<&[f64]>) -> Result<()> {
        let found = match gradient {
            Some(gradient) => {
                let term = |k: usize| gradient[k].abs() * run.outputs[k].std_error.unwrap_or(0.0);
                let largest = (0..gradient.len()).map(term).fold(0.0, f64::max);
                // A term below 2^-495 adds less than 2^-990 to the variance: an index that is
                // exactly zero (its output's standard error a subnormal rounding floor) has
                // no error bar to lose.
                let least = (largest * WEIGHS).max(SMALLEST_VARIANCE.sqrt());
                let weighs = (0..gradient.len()).filter(|&k| term(k) >= least);
                unrepresentable_output(run, weighs)
            }
            None if matches!(self.kind, Kind::Smooth { .. }) => {
                unrepresentable_output(run, 0..run.outputs.len())
            }
            None => None,
        };
        match found {
            Some((k, std_error)) => Err(Error::Unsupported {
                operation: "a derived quantity's error bar",
                reason: format!(
                    "output {k} has standard error {std_error:e}, whose square (its variance \
                     in the delta method) is below what f64 keeps to full precision (about \
                     1e-298): multiply the integrand by a constant that brings its outputs \
                     nearer 1 (a ratio or a Sobol' index does not change)"
                ),
            }),
            None => Ok(()),
        }
    }

    /// The estimate of this quantity from `run` (see [`VectorEstimate::derived`]).
    pub(crate) fn estimate(&self, run: &VectorEstimate) -> Result<Estimate> {
        // A run edited or read back by hand may have lost its shape.
        let m = run.outputs.len();
        if m == 0
            || run
                .covariance_matrix
                .as_ref()
                .is_some_and(|c| c.len() != m * m)
        {
            return Err(Error::invalid(
                "run",
                format!(
                    "{m} outputs and a covariance matrix of {} entries",
                    run.covariance_matrix.as_ref().map_or(0, Vec::len)
                ),
                "at least one output and, if any, an outputs x outputs covariance matrix",
            ));
        }
        let (value, gradient) = match self.value_and_gradient(run) {
            Ok(found) => found,
            Err(err) => {
                self.underflow_error(run, None)?;
                return Err(err);
            }
        };
        self.underflow_error(run, Some(&gradient))?;
        let used: Vec<usize> = (0..gradient.len())
            .filter(|&k| gradient[k] != 0.0)
            .collect();
        let first = used.first().copied().unwrap_or(0);
        let mut estimate = run.outputs[first].clone();
        estimate
            .warnings
            .retain(|w| !matches!(w, Warning::AtRoundingFloor { .. } | Warning::AllZero { .. }));
        // What the other outputs it uses went through (skipped values, a tolerance not met)
        // holds for it too.
        for &k in used.iter().skip(1) {
            let other = &run.outputs[k];
            for w in &other.warnings {
                if !matches!(w, Warning::AtRoundingFloor { .. } | Warning::AllZero { .. }) {
                    estimate.warn(w.clone());
                }
            }
            estimate.non_finite = estimate.non_finite.max(other.non_finite);
            estimate.n = estimate.n.min(other.n);
        }
        estimate.mean = value;
        estimate.converged = run.converged;
        estimate.evaluations = run.evaluations;
        estimate.std_error = run.covariance_matrix.as_ref().map(|matrix| {
            let m = gradient.len();
            let variance: f64 = (0..m)
                .flat_map(|i| (0..m).map(move |j| (i, j)))
                .map(|(i, j)| gradient[i] * gradient[j] * matrix[i * m + j])
                .sum();
            variance.max(0.0).sqrt()
        });
        estimate.dof = used
            .iter()
            .filter_map(|&k| run.outputs[k].dof)
            .reduce(f64::min)
            .or(estimate.dof);
        if estimate.std_error.is_none() {
            estimate.dof = None;
        }
        estimate.rounding_error = used
            .iter()
            .map(|&k| gradient[k].abs() * run.outputs[k].rounding_error)
            .sum::<f64>()
            + 4.0 * UNIT_ROUNDOFF * value.abs();
        estimate.finalize();
        estimate.checked()
    }
}

/// The first of the outputs `read` of `run` (with the standard error that disqualifies it)
/// whose variance is positive but below [`SMALLEST_VARIANCE`], where covariances lose
/// precision to underflow: no delta-method error bar can be built on it.
pub(crate) fn unrepresentable_output(
    run: &VectorEstimate,
    read: impl IntoIterator<Item = usize>,
) -> Option<(usize, f64)> {
    run.covariance_matrix.as_ref()?;
    read.into_iter().find_map(|k| {
        let std_error = run.outputs.get(k)?.std_error?;
        (std_error > 0.0 && std_error * std_error < SMALLEST_VARIANCE).then_some((k, std_error))
    })
}

/// `dg/dI_k` by central differences with steps of `eps^(1/3)` relative to each integral (or
/// its standard error, whichever is larger).
fn central_differences(value: &Value, means: &[f64], run: &VectorEstimate, gradient: &mut [f64]) {
    let mut shifted = means.to_vec();
    for (k, slot) in gradient.iter_mut().enumerate() {
        let scale = means[k].abs().max(run.outputs[k].std_error.unwrap_or(0.0));
        let h = f64::EPSILON.cbrt() * if scale > 0.0 { scale } else { 1.0 };
        shifted[k] = means[k] + h;
        let up = value(&shifted);
        shifted[k] = means[k] - h;
        let down = value(&shifted);
        shifted[k] = means[k];
        *slot = (up - down) / (2.0 * h);
    }
}
