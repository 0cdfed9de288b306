//! [`Estimate`]: an integral estimate with an honest error bar.

use super::accumulator::{Accumulator, scale_for};
use super::rounding::mean_of_means;
use super::warning::{DISAGREEMENT_Q, Warning};
use crate::error::{Error, Result};
use crate::special::{student_t_quantile, student_t_upper_quantile};
use crate::stop_reason::StopReason;

/// Where a standard error comes from.
///
/// ```
/// use mcint::stats::{Accumulator, ErrorBasis};
/// let mut acc = Accumulator::new();
/// acc.extend(&[1.0, 2.0]);
/// assert_eq!(acc.estimate().basis, ErrorBasis::PerSample);
/// ```
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorBasis {
    /// The per-sample variance of independent contributions, `s / sqrt(n)`.
    PerSample,
    /// The spread of independent replicate means, `s_R / sqrt(R)` with `R - 1` degrees of
    /// freedom: the only honest choice for stratified and quasi-Monte Carlo points, whose
    /// samples are not independent.
    Replicates,
    /// No honest standard error exists (for example a single replicate of stratified points).
    None,
    /// No standard error: [`Estimate::error_bound`] bounds the error from the decay of the
    /// discrete Walsh coefficients of one digital sequence (the cone-based rule of
    /// [`SobolG`](crate::adaptive::SobolG)), for integrands in the cone the rule assumes.
    WalshBound,
}

/// An estimate of an integral with its standard error and degrees of freedom. `{}` prints
/// it with its 95% interval, `{:.6}` with six decimals.
///
/// ```
/// use mcint::stats::{Estimate, ErrorBasis};
/// let e = Estimate::from_replicates(&[1.0, 1.2, 0.8, 1.0], 1000).unwrap();
/// assert_eq!(e.basis, ErrorBasis::Replicates);
/// let (lo, hi) = e.confidence_interval(0.95).unwrap().unwrap();
/// assert!(lo < 1.0 && 1.0 < hi);
/// println!("{e:.3}"); // 1.000 ± 2.6e-1 (95% CI [0.740, 1.260], 4000 evaluations)
/// ```
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Estimate {
    /// The estimate of the integral.
    pub mean: f64,
    /// Standard error of `mean`; `None` where none can be given honestly.
    pub std_error: Option<f64>,
    /// Degrees of freedom of the Student-t interval (`n - 1` or `R - 1`).
    pub dof: Option<f64>,
    /// Where the standard error comes from.
    pub basis: ErrorBasis,
    /// Total number of contributions (integrand evaluations) behind the estimate.
    pub n: u64,
    /// Integrand evaluations the run spent, including pilot stages and warm-up iterations
    /// whose samples are not in the estimate (equal to `n` for a single fixed run).
    pub evaluations: u64,
    /// Number of independent replicates.
    pub replicates: u64,
    /// Contributions that were NaN or infinite and were left out.
    pub non_finite: u64,
    /// Why the run that made this estimate stopped.
    pub stop: StopReason,
    /// Whether the requested tolerance was met (`None` when no tolerance was requested).
    pub converged: Option<bool>,
    /// Iterations (adaptive methods) or stages (a run that doubles its samples until a
    /// tolerance is met); 1 for a single fixed run.
    pub iterations: u64,
    /// `chi^2` per degree of freedom of the agreement between iterations, where an adaptive
    /// method combines iterations (VEGAS); values near 1 mean they agree.
    pub chi2_dof: Option<f64>,
    /// The probability of a `chi^2` at least as large as [`chi2_dof`](Self::chi2_dof) shows
    /// if the iterations agree (VEGAS's `Q`; small values warn of an unreliable estimate).
    pub q_value: Option<f64>,
    /// A bound on the floating-point error of `mean`: the rounding of every sum and merge
    /// behind it (tracked operation by operation, after Higham's bounds for summation), the
    /// combination of replicates or strata or iterations, and an allowance of 64 units in the
    /// last place of each contribution for its own evaluation (integrand, density, `f/pdf`).
    /// `std_error` is never reported below it (with a
    /// [`Warning::AtRoundingFloor`] when the statistics alone gave less): an estimate cannot
    /// claim more accuracy than its arithmetic has.
    #[cfg_attr(feature = "serde", serde(default))]
    pub rounding_error: f64,
    /// Conditions worth knowing about this estimate (see [`Warning`]); empty when there are
    /// none.
    #[cfg_attr(feature = "serde", serde(default))]
    pub warnings: Vec<Warning>,
    /// A bound on `|mean - integral|` where the basis is [`ErrorBasis::WalshBound`]: the
    /// interval `mean ± error_bound` has no confidence level, it holds for every integrand in
    /// the rule's cone. `None` for every other basis.
    #[cfg_attr(feature = "serde", serde(default))]
    pub error_bound: Option<f64>,
}

impl Estimate {
    /// The estimate from independent replicate means, each of `n_per_replicate` samples: the
    /// mean of the means, with standard error `s_R / sqrt(R)` and `R - 1` degrees of freedom
    /// (as scipy's `qmc_quad` and QMCPy's `CubQMCRep` do). With one replicate there is no
    /// standard error.
    ///
    /// ```
    /// use mcint::stats::Estimate;
    /// let e = Estimate::from_replicates(&[2.0], 64).unwrap();
    /// assert_eq!((e.mean, e.std_error, e.n), (2.0, None, 64));
    /// assert!(Estimate::from_replicates(&[], 1).is_err());
    /// assert!(Estimate::from_replicates(&[f64::NAN, 1.0], 1).is_err());
    /// ```
    pub fn from_replicates(means: &[f64], n_per_replicate: u64) -> Result<Self> {
        Estimate::from_bounded_replicates(means, &vec![0.0; means.len()], n_per_replicate)
    }

    /// [`from_replicates`](Self::from_replicates) for means that carry rounding error bounds
    /// of their own.
    pub(crate) fn from_bounded_replicates(
        means: &[f64],
        bounds: &[f64],
        n_per_replicate: u64,
    ) -> Result<Self> {
        if means.is_empty() {
            return Err(Error::invalid(
                "replicate means",
                "[]",
                "at least one replicate",
            ));
        }
        if let Some(bad) = means.iter().find(|m| !m.is_finite()) {
            return Err(Error::invalid("replicate mean", bad, "finite values"));
        }
        let r = means.len() as u64;
        // In units of a power of two (1 unless the means are beyond about 1e144), so that
        // means up to f64::MAX keep a finite sum and sum of squares; exact scaling, so the
        // bits of ordinary results do not depend on it.
        let scale = scale_for(means.iter().fold(0.0f64, |m, v| m.max(v.abs())));
        let mean_s = means.iter().map(|m| m / scale).sum::<f64>() / r as f64;
        let mean = mean_s * scale;
        let honest = r >= 2;
        let std_error = honest.then(|| {
            let ss: f64 = means
                .iter()
                .map(|m| (m / scale - mean_s) * (m / scale - mean_s))
                .sum();
            (ss / ((r - 1) * r) as f64).sqrt() * scale
        });
        let mut estimate = Estimate {
            mean,
            std_error,
            dof: honest.then(|| (r - 1) as f64),
            basis: if honest {
                ErrorBasis::Replicates
            } else {
                ErrorBasis::None
            },
            n: r.saturating_mul(n_per_replicate),
            evaluations: r.saturating_mul(n_per_replicate),
            replicates: r,
            non_finite: 0,
            stop: StopReason::Budget,
            converged: None,
            iterations: 1,
            chi2_dof: None,
            q_value: None,
            rounding_error: mean_of_means(means, bounds),
            warnings: Vec::new(),
            error_bound: None,
        };
        estimate.finalize();
        Ok(estimate)
    }

    /// The estimate from independent replicates, each accumulated in full: as
    /// [`from_replicates`](Self::from_replicates) on their means, with `n` the finite
    /// contributions, `non_finite` those left out and `evaluations` all of them.
    ///
    /// ```
    /// use mcint::stats::{Accumulator, Estimate};
    /// let mut a = Accumulator::new();
    /// a.extend(&[1.0, 3.0, f64::NAN]);
    /// let mut b = Accumulator::new();
    /// b.extend(&[3.0, 5.0, 4.0]);
    /// let e = Estimate::from_replicate_accumulators(&[a, b]).unwrap();
    /// assert_eq!((e.mean, e.n, e.non_finite, e.evaluations), (3.0, 5, 1, 6));
    /// ```
    pub fn from_replicate_accumulators(replicates: &[Accumulator]) -> Result<Self> {
        let means: Vec<f64> = replicates.iter().map(Accumulator::mean).collect();
        let bounds: Vec<f64> = replicates.iter().map(Accumulator::rounding_error).collect();
        let mut estimate = Estimate::from_bounded_replicates(&means, &bounds, 0)?;
        estimate.n = replicates.iter().map(Accumulator::count).sum();
        estimate.non_finite = replicates.iter().map(Accumulator::non_finite).sum();
        estimate.evaluations = estimate.n + estimate.non_finite;
        if replicates.iter().all(Accumulator::all_zero) {
            estimate.warn(Warning::AllZero { count: estimate.n });
        }
        estimate.finalize();
        Ok(estimate)
    }

    /// Applies the rounding floor to `std_error` and adds the warnings that the estimate's
    /// own fields call for (few replicates, skipped non-finite values); every run calls it
    /// on its final estimate, and calling it again changes nothing.
    pub(crate) fn finalize(&mut self) {
        if let Some(statistical) = self.std_error
            && statistical < self.rounding_error
        {
            self.std_error = Some(self.rounding_error);
            self.warn(Warning::AtRoundingFloor {
                statistical,
                floor: self.rounding_error,
            });
        }
        if self.basis == ErrorBasis::Replicates && self.replicates < 8 {
            self.warn(Warning::FewReplicates {
                replicates: self.replicates,
            });
        }
        if let (Some(chi2_dof), Some(q_value)) = (self.chi2_dof, self.q_value)
            && q_value < DISAGREEMENT_Q
        {
            self.warn(Warning::IterationsDisagree {
                iterations: self.iterations,
                chi2_dof,
                q_value,
            });
        }
        if self.non_finite > 0 {
            // Where it stands, with the count now known: finalizing twice changes nothing.
            let skipped = Warning::NonFiniteSkipped {
                count: self.non_finite,
            };
            match self
                .warnings
                .iter_mut()
                .find(|w| matches!(w, Warning::NonFiniteSkipped { .. }))
            {
                Some(earlier) => *earlier = skipped,
                None => self.warnings.push(skipped),
            }
        }
    }

    /// The estimate, or [`Error::Overflow`] if its mean or standard error is not finite:
    /// what every runner returns, so that no NaN or infinity passes for an estimate.
    pub(crate) fn checked(self) -> Result<Estimate> {
        if !self.mean.is_finite() {
            return Err(Error::Overflow {
                what: "estimate",
                value: self.mean,
            });
        }
        match self.std_error {
            Some(se) if !se.is_finite() => Err(Error::Overflow {
                what: "standard error",
                value: se,
            }),
            _ => Ok(self),
        }
    }

    /// Adds `warning` unless a warning of its kind is already there.
    pub(crate) fn warn(&mut self, warning: Warning) {
        if !self.warnings.iter().any(|w| w.kind() == warning.kind()) {
            self.warnings.push(warning);
        }
    }

    /// Variance of the estimate, `std_error^2`.
    ///
    /// ```
    /// let e = mcint::stats::Estimate::from_replicates(&[1.0, 3.0], 1).unwrap();
    /// assert_eq!(e.variance(), Some(1.0));
    /// ```
    pub fn variance(&self) -> Option<f64> {
        self.std_error.map(|s| s * s)
    }

    /// Relative standard error `std_error / |mean|` (`None` without a standard error; infinite
    /// for a zero mean).
    ///
    /// ```
    /// let e = mcint::stats::Estimate::from_replicates(&[1.0, 3.0], 1).unwrap();
    /// assert_eq!(e.relative_error(), Some(0.5));
    /// ```
    pub fn relative_error(&self) -> Option<f64> {
        self.std_error.map(|s| s / self.mean.abs())
    }

    /// Two-sided Student-t confidence interval at `level` in `(0, 1)`:
    /// `mean ± t_{(1+level)/2, dof} std_error`. `Ok(None)` when there is no standard error.
    ///
    /// ```
    /// let e = mcint::stats::Estimate::from_replicates(&[1.0, 3.0], 1).unwrap();
    /// let (lo, hi) = e.confidence_interval(0.95).unwrap().unwrap();
    /// assert!((hi - 2.0 - 12.706204736174706).abs() < 1e-9); // t_{0.975, 1} * 1
    /// assert!(e.confidence_interval(1.0).is_err());
    /// ```
    pub fn confidence_interval(&self, level: f64) -> Result<Option<(f64, f64)>> {
        let half = self.half_width(level)?;
        Ok(half.map(|h| (self.mean - h, self.mean + h)))
    }

    /// Half-width of the confidence interval at `level` (see
    /// [`confidence_interval`](Self::confidence_interval)); for an
    /// [`ErrorBasis::WalshBound`] estimate, its [`error_bound`](Self::error_bound) whatever
    /// the level.
    ///
    /// ```
    /// let e = mcint::stats::Estimate::from_replicates(&[1.0, 3.0], 1).unwrap();
    /// assert!(e.half_width(0.5).unwrap().unwrap() > 0.0);
    /// ```
    pub fn half_width(&self, level: f64) -> Result<Option<f64>> {
        if !(level > 0.0 && level < 1.0) {
            return Err(Error::invalid(
                "level",
                level,
                "a confidence level strictly between 0 and 1",
            ));
        }
        if self.basis == ErrorBasis::WalshBound {
            return Ok(self.error_bound);
        }
        Ok(match (self.std_error, self.dof) {
            (Some(_), Some(dof)) if dof.is_nan() || dof <= 0.0 => {
                return Err(Error::invalid(
                    "dof",
                    dof,
                    "degrees of freedom > 0 (an estimate edited or read back by hand?)",
                ));
            }
            // The tail (1 - level) / 2 directly (exact here): 0.5 + level / 2 rounds it away
            // near 1.
            (Some(se), Some(dof)) if level >= 0.5 => {
                Some(student_t_upper_quantile((1.0 - level) / 2.0, dof) * se)
            }
            (Some(se), Some(dof)) => Some(student_t_quantile(0.5 + level / 2.0, dof) * se),
            _ => None,
        })
    }
}
