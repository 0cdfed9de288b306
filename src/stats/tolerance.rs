//! [`Tolerance`]: when a run that adapts its number of samples may stop.

use std::time::Duration;

use super::estimate::Estimate;
use super::warning::DISAGREEMENT_Q;
use crate::error::{Error, Result};

/// The accuracy a run should reach and the limits on what it may spend.
///
/// The tolerance is met when the half-width of the 95% confidence interval is at most
/// `max(abs, rel * |mean|)` (QMCPy's convention for absolute and relative tolerances; give
/// either or both). A run stops as soon as the tolerance is met, or when the next stage would
/// exceed `max_evaluations` integrand evaluations, or once `time_limit` has passed; the
/// [`Estimate`] then says why (`stop`) and whether the tolerance was met (`converged`).
///
/// ```
/// use mcint::stats::{Estimate, Tolerance};
/// let t = Tolerance::absolute(0.01).unwrap();
/// let e = Estimate::from_replicates(&[1.0, 1.001, 0.999, 1.0], 100).unwrap();
/// assert!(t.is_met(&e));
/// assert!(Tolerance::absolute(-1.0).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    abs: Option<f64>,
    rel: Option<f64>,
    max_evaluations: u64,
    time_limit: Option<Duration>,
}

/// Evaluations allowed when the caller sets no limit.
const DEFAULT_MAX_EVALUATIONS: u64 = 1 << 30;

impl Tolerance {
    /// Stop when the 95% half-width is at most `abs` (finite, `> 0`).
    ///
    /// ```
    /// assert!(mcint::stats::Tolerance::absolute(1e-6).is_ok());
    /// ```
    pub fn absolute(abs: f64) -> Result<Self> {
        Self::new(Some(abs), None)
    }

    /// Stop when the 95% half-width is at most `rel * |mean|` (`rel` finite and at least
    /// `f64::EPSILON`: no error bar, which never falls below the bound on the mean's rounding
    /// error, gets smaller than that, so a smaller `rel` would only spend the whole budget).
    ///
    /// ```
    /// use mcint::stats::Tolerance;
    /// assert!(Tolerance::relative(0.0).is_err());
    /// assert!(Tolerance::relative(1e-20).is_err());
    /// assert!(Tolerance::relative(1e-15).is_ok());
    /// ```
    pub fn relative(rel: f64) -> Result<Self> {
        Self::new(None, Some(rel))
    }

    /// Absolute and/or relative tolerance: met when the half-width is at most the larger of
    /// `abs` and `rel * |mean|`. At least one must be given.
    ///
    /// ```
    /// use mcint::stats::Tolerance;
    /// assert!(Tolerance::new(Some(1e-3), Some(1e-2)).is_ok());
    /// assert!(Tolerance::new(None, None).is_err());
    /// ```
    pub fn new(abs: Option<f64>, rel: Option<f64>) -> Result<Self> {
        for (name, value) in [("tol_abs", abs), ("tol_rel", rel)] {
            if let Some(v) = value
                && !(v.is_finite() && v > 0.0)
            {
                return Err(Error::invalid(name, v, "a finite tolerance > 0"));
            }
        }
        if let Some(v) = rel
            && v < f64::EPSILON
        {
            return Err(Error::invalid(
                "tol_rel",
                format!("{v:e}"),
                "a relative tolerance of at least 2.2e-16 (f64::EPSILON): no error bar gets \
                 smaller than the mean's rounding",
            ));
        }
        if abs.is_none() && rel.is_none() {
            return Err(Error::invalid(
                "tolerance",
                "none",
                "an absolute or a relative tolerance (or both)",
            ));
        }
        Ok(Tolerance {
            abs,
            rel,
            max_evaluations: DEFAULT_MAX_EVALUATIONS,
            time_limit: None,
        })
    }

    /// At most `n` integrand evaluations (`n >= 1`; default `2^30`).
    ///
    /// ```
    /// use mcint::stats::Tolerance;
    /// let t = Tolerance::absolute(1e-3).unwrap().max_evaluations(1000).unwrap();
    /// assert_eq!(t.evaluation_limit(), 1000);
    /// ```
    pub fn max_evaluations(mut self, n: u64) -> Result<Self> {
        if n == 0 {
            return Err(Error::invalid("max_evals", 0, "at least 1 evaluation"));
        }
        self.max_evaluations = n;
        Ok(self)
    }

    /// Stop once `limit` has passed: checked before every chunk of work, so a run exceeds it
    /// by at most a chunk's work and returns its last whole stage (as the runners'
    /// `time_limit` setting does; with both, the shorter applies).
    ///
    /// ```
    /// use std::time::Duration;
    /// let t = mcint::stats::Tolerance::relative(1e-3).unwrap().time_limit(Duration::from_secs(2));
    /// assert_eq!(t.time(), Some(Duration::from_secs(2)));
    /// ```
    pub fn time_limit(mut self, limit: Duration) -> Self {
        self.time_limit = Some(limit);
        self
    }

    /// The most integrand evaluations a run may use.
    ///
    /// ```
    /// assert_eq!(mcint::stats::Tolerance::absolute(1.0).unwrap().evaluation_limit(), 1 << 30);
    /// ```
    pub fn evaluation_limit(&self) -> u64 {
        self.max_evaluations
    }

    /// The time limit, if any.
    ///
    /// ```
    /// assert_eq!(mcint::stats::Tolerance::absolute(1.0).unwrap().time(), None);
    /// ```
    pub fn time(&self) -> Option<std::time::Duration> {
        self.time_limit
    }

    /// The half-width the 95% interval must reach for an estimate with this `mean`.
    ///
    /// ```
    /// let t = mcint::stats::Tolerance::new(Some(0.1), Some(0.01)).unwrap();
    /// assert_eq!(t.target(100.0), 1.0);
    /// assert_eq!(t.target(1.0), 0.1);
    /// ```
    pub fn target(&self, mean: f64) -> f64 {
        let abs = self.abs.unwrap_or(0.0);
        let rel = self.rel.map_or(0.0, |r| r * mean.abs());
        abs.max(rel)
    }

    /// Whether `estimate`'s 95% interval is narrow enough (false without a standard error, and
    /// false when its combined iterations disagree, `q_value` below [`DISAGREEMENT_Q`]: their
    /// error bar is then too small, see
    /// [`Warning::IterationsDisagree`](super::Warning::IterationsDisagree)).
    ///
    /// ```
    /// use mcint::stats::{Estimate, Tolerance};
    /// let single = Estimate::from_replicates(&[1.0], 100).unwrap(); // no error bar
    /// assert!(!Tolerance::absolute(1.0).unwrap().is_met(&single));
    /// let mut pair = Estimate::from_replicates(&[1.0, 1.1], 100).unwrap();
    /// assert!(Tolerance::absolute(1.0).unwrap().is_met(&pair));
    /// pair.q_value = Some(1e-6);
    /// assert!(!Tolerance::absolute(1.0).unwrap().is_met(&pair));
    /// ```
    pub fn is_met(&self, estimate: &Estimate) -> bool {
        if estimate.q_value.is_some_and(|q| q < DISAGREEMENT_Q) {
            return false;
        }
        match estimate.half_width(0.95) {
            Ok(Some(h)) => h <= self.target(estimate.mean),
            _ => false,
        }
    }
}
