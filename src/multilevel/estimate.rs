//! [`MultilevelEstimate`] and [`LevelSummary`]: what a multilevel run reports.

use std::fmt;

use crate::stats::{HEAVY_TAIL_KURTOSIS, StopReason, Warning};

/// One level of a multilevel run: the samples it took and what they say.
///
/// ```
/// use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};
/// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
/// let levels = SdeLevels::new(gbm, Scheme::Euler, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
/// let run = Multilevel::new(levels).rmse(0.1).seed(1).run().unwrap();
/// let deepest = run.levels.last().unwrap();
/// assert!(deepest.variance < run.levels[0].variance);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct LevelSummary {
    /// The level `l`.
    pub level: usize,
    /// Samples `N_l` (over every replicate).
    pub samples: u64,
    /// The mean of `Y_l = P_l - P_{l-1}` (of `P_0` at level 0).
    pub mean: f64,
    /// The variance `V_l` of one sample of `Y_l`.
    pub variance: f64,
    /// The standard error of the level's mean (from the replicates' spread under QMC).
    pub std_error: f64,
    /// The cost `C_l` of one sample.
    pub cost: f64,
    /// The mean of `P_l`.
    pub fine_mean: f64,
    /// The variance of one sample of `P_l`.
    pub fine_variance: f64,
    /// The kurtosis of `Y_l` (Giles' `mlmc_test`: a large one makes `V_l` itself uncertain);
    /// `None` when `Y_l` does not vary, or when its fourth powers leave f64's range (values
    /// below about `1e-77` or above `1e77`).
    pub kurtosis: Option<f64>,
    /// Giles' consistency check, `|E[Y_l] - E[P_l] + E[P_{l-1}]|` over three standard errors
    /// of it (`None` at level 0, and where no sample varies): above 1 says the coarse path of
    /// level `l` does not have the law of the fine path of level `l - 1`, a coupling error.
    pub consistency: Option<f64>,
}

/// The result of a multilevel run (or a survey of its levels).
///
/// ```
/// use mcint::multilevel::{Multilevel, MultilevelEstimate, Payoff, Scheme, Sde, SdeLevels};
/// let gbm = Sde::gbm(100.0, 0.05, 0.2).unwrap();
/// let levels = SdeLevels::new(gbm, Scheme::Milstein, Payoff::european_call(100.0).unwrap(), 1.0).unwrap();
/// let run = Multilevel::new(levels).rmse(0.1).seed(3).run().unwrap();
/// assert!(run.converged && run.std_error <= 0.1 / 2f64.sqrt() && run.bias <= 0.1 / 2f64.sqrt());
/// assert!(run.cost < run.standard_mc_cost);
/// println!("{run}");
/// // The precision is the estimate's decimals; far from 1 they follow an exponent.
/// assert!(format!("{run:.2}").starts_with(&format!("{:.2} ± ", run.estimate)));
/// let huge = MultilevelEstimate { estimate: 1e140, ..run };
/// assert!(huge.to_string().starts_with("1.000000e140 ± "));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MultilevelEstimate {
    /// The estimate `sum_l mean(Y_l)`.
    pub estimate: f64,
    /// Its standard error (sampling error alone).
    pub std_error: f64,
    /// The estimated bias: `|E[Y_L]|` extrapolated geometrically past the deepest level
    /// `L` with the fitted `alpha`, `|E[Y_L]| / (M^alpha - 1)`, from the largest of the last
    /// three levels' extrapolations.
    pub bias: f64,
    /// `sqrt(std_error^2 + bias^2)`: the estimated root-mean-square error.
    pub rmse: f64,
    /// The target root-mean-square error (`None` for a survey).
    pub target: Option<f64>,
    /// The levels used, from 0.
    pub levels: Vec<LevelSummary>,
    /// The fitted weak rate: `|E[Y_l]|` falls like `M^(-alpha l)` (at least 0.5).
    pub alpha: f64,
    /// The fitted variance rate: `V_l` falls like `M^(-beta l)` (at least 0.5).
    pub beta: f64,
    /// The fitted cost rate: `C_l` grows like `M^(gamma l)` (at least 0.5).
    pub gamma: f64,
    /// The refinement factor `M` the rates are in.
    pub refinement: u32,
    /// The total cost `sum_l N_l C_l`.
    pub cost: f64,
    /// What standard Monte Carlo would spend for the same sampling error on the deepest
    /// level: `V[P_L] C_L / (eps^2 / 2)` with `C_L` the cost of the fine path alone (for a
    /// survey, `V[P_L] C_L / s^2` with `s` the survey's own standard error).
    pub standard_mc_cost: f64,
    /// Independent randomizations per level: 1 for Monte Carlo, `R` for multilevel QMC.
    pub replicates: u64,
    /// Why the run stopped.
    pub stop: StopReason,
    /// Whether the run met its target (sampling error and bias each within their share).
    pub converged: bool,
    /// What the caller should know about the result.
    pub warnings: Vec<Warning>,
}

impl fmt::Display for MultilevelEstimate {
    /// The estimate, its error budget, the rates and the costs, then a line per level; the
    /// precision (default 6 decimals, after the point of an exponent for magnitudes outside
    /// `1e-4` to `1e15`) applies to the estimate.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let digits = f.precision().unwrap_or(6);
        let x = self.estimate;
        let estimate = if x == 0.0 || (1e-4..1e15).contains(&x.abs()) {
            format!("{x:.digits$}")
        } else {
            format!("{x:.digits$e}")
        };
        writeln!(
            f,
            "{} ± {:.2e} (standard error), bias ≈ {:.2e}, RMSE ≈ {:.2e}{}; {} levels, alpha {:.2}, beta {:.2}, gamma {:.2} (M = {}); cost {:.3e}, standard MC \
             {:.3e}; stop: {:?}{}",
            estimate,
            self.std_error,
            self.bias,
            self.rmse,
            self.target
                .map_or(String::new(), |t| format!(" (target {t:.2e})")),
            self.levels.len(),
            self.alpha,
            self.beta,
            self.gamma,
            self.refinement,
            self.cost,
            self.standard_mc_cost,
            self.stop,
            if self.converged {
                ""
            } else {
                " (not converged)"
            }
        )?;
        writeln!(
            f,
            "level  samples       mean(Y_l)      var(Y_l)    cost(C_l)  mean(P_l)    var(P_l)  \
             kurtosis  check"
        )?;
        let optional = |x: Option<f64>, width: usize| {
            x.map_or(format!("{:>width$}", "-"), |x| format!("{x:>width$.2}"))
        };
        for l in &self.levels {
            writeln!(
                f,
                "{:>5}  {:>10}  {:>12.4e}  {:>12.4e}  {:>9.3e}  {:>10.4e}  {:>10.4e}  {:>8}  {:>5}",
                l.level,
                l.samples,
                l.mean,
                l.variance,
                l.cost,
                l.fine_mean,
                l.fine_variance,
                optional(l.kurtosis, 8),
                optional(l.consistency, 5)
            )?;
        }
        for w in &self.warnings {
            writeln!(f, "warning: {w}")?;
        }
        Ok(())
    }
}

/// Giles' two warnings of `mlmc_test` on the levels `l >= 1`: the largest kurtosis of a
/// correction above [`HEAVY_TAIL_KURTOSIS`], and the largest consistency check above 1.
pub(super) fn level_warnings(levels: &[LevelSummary]) -> Vec<Warning> {
    let largest = |value: fn(&LevelSummary) -> Option<f64>| {
        levels
            .iter()
            .skip(1)
            .filter_map(|l| Some((l.level, value(l)?)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
    };
    let mut warnings = Vec::new();
    if let Some((level, kurtosis)) = largest(|l| l.kurtosis)
        && kurtosis > HEAVY_TAIL_KURTOSIS
    {
        warnings.push(Warning::HeavyTailedLevel { level, kurtosis });
    }
    if let Some((level, check)) = largest(|l| l.consistency)
        && check > 1.0
    {
        warnings.push(Warning::InconsistentLevels { level, check });
    }
    warnings
}
