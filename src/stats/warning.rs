//! [`Warning`]: what a user should know about an estimate that is not an error.

use std::fmt;

use crate::stop_reason::StopReason;

/// A condition worth knowing about an [`Estimate`](super::Estimate): the run succeeded, but
/// its answer is weaker than it looks, or was obtained differently than asked. Runs list
/// them in [`Estimate::warnings`](super::Estimate::warnings) (empty when there are none);
/// every example binary prints them to stderr, and `integrate --json` has a `warnings` array of
/// `{"kind", "message"}` objects.
///
/// ```
/// use mcint::{Integrator, pdf::UniformBox, sampler::{Scramble, Sobol}, stats::Warning};
/// // 1000 Owen-scrambled Sobol' points per replicate are not a net: a warning, not an error.
/// let e = Integrator::over_box(|x: &[f64]| x[0] * x[1], UniformBox::unit(2).unwrap())
///     .sampler(Sobol::new(2, Scramble::Owen, 0).unwrap())
///     .samples(1000)
///     .replicates(16)
///     .run()
///     .unwrap();
/// assert!(matches!(e.warnings[0], Warning::UnbalancedSampleSize { below: 512, above: 1024, .. }));
/// assert_eq!(e.warnings[0].kind(), "unbalanced-sample-size");
/// ```
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Warning {
    /// The points per replicate break the sampler's balance: its points keep their net or
    /// lattice structure (and their convergence rate) only in blocks of a whole power of
    /// `base` (scipy warns in the same case). A size of `below` or `above` keeps it.
    UnbalancedSampleSize {
        /// The sampler's name.
        sampler: String,
        /// The points per replicate that were used.
        samples: u64,
        /// The base of the balanced sizes (2 for Sobol', pmj02, Hammersley and lattices).
        base: u64,
        /// The nearest balanced size below `samples`.
        below: u64,
        /// The nearest balanced size above `samples`.
        above: u64,
    },
    /// A run to a tolerance stopped on a limit (or, VEGAS, on iterations that kept
    /// disagreeing) before meeting it.
    ToleranceNotMet {
        /// What stopped it.
        stop: StopReason,
    },
    /// Fewer than 8 independent replicates: the Student-t interval is wide, and the standard
    /// error itself is uncertain by about `1 / sqrt(2 (R - 1))` of its value.
    FewReplicates {
        /// The number of replicates.
        replicates: u64,
    },
    /// One replicate of dependent points (a net, a lattice, stratified points): their
    /// estimate has no honest standard error, so none is reported
    /// ([`Estimate::std_error`](super::Estimate::std_error) is `None`). Independent
    /// re-randomizations (`replicates(R)`, `R >= 8`, of a randomized sampler) give one from
    /// their spread.
    NoErrorBar {
        /// The sampler's name.
        sampler: String,
        /// Whether it is randomized (an unrandomized one gives the same points every
        /// replicate, so replicates alone do not help).
        randomized: bool,
    },
    /// NaN or infinite contributions were left out, as asked: the estimate is the mean over
    /// the finite ones, which is biased wherever the skipped points carry mass.
    NonFiniteSkipped {
        /// How many were left out.
        count: u64,
    },
    /// Every contribution was exactly zero (or underflowed to zero): the estimate 0 says only
    /// that the integrand was zero, or below the smallest `f64`, wherever the points fell; a
    /// peak between them, or a value that underflows at every point, is invisible to it.
    AllZero {
        /// The number of contributions.
        count: u64,
    },
    /// A fixed-budget run stopped early (its time limit, or a cancellation): the estimate uses
    /// the work done, which is less than was asked for.
    StoppedEarly {
        /// Why it stopped.
        stop: StopReason,
        /// Evaluations in the estimate.
        done: u64,
        /// Evaluations the run was to make.
        planned: u64,
    },
    /// The iterations an adaptive method combined (VEGAS) disagree beyond chance: a `chi^2` of
    /// their agreement this large or larger has probability `q_value`, below
    /// [`DISAGREEMENT_Q`], if their variances are right. Some iterations' variances are then
    /// underestimated, or their estimates drift (the grid still moving), and the combined
    /// estimate can sit many of those standard errors from the truth: the standard error
    /// reported is theirs times `sqrt(chi2_dof)`, the iterations' scatter, with Student-t
    /// quantiles of `iterations - 1` degrees of freedom. Causes seen: a discontinuity the
    /// grid squeezes into a sliver most iterations miss; a narrow peak that iterations of too
    /// few points find only now and then; a grid still adapting when the combined iterations
    /// began.
    IterationsDisagree {
        /// The number of iterations combined.
        iterations: u64,
        /// `chi^2` per degree of freedom.
        chi2_dof: f64,
        /// The probability of a `chi^2` at least as large if the iterations agree.
        q_value: f64,
    },
    /// The statistical standard error was below the bound on the rounding error of the mean
    /// (`Estimate::rounding_error`), and the floor is reported instead: the data hardly vary,
    /// and more points will not make the answer more accurate.
    AtRoundingFloor {
        /// The standard error the statistics alone gave.
        statistical: f64,
        /// The floor reported in its place.
        floor: f64,
    },
    /// A multilevel run's bias estimate (the decay of `E[P_l - P_{l-1}]` extrapolated past the
    /// deepest level) stayed above its share of the root-mean-square error target at the
    /// deepest level allowed: more levels (or a higher-order scheme) are needed.
    BiasAboveTarget {
        /// The deepest level used.
        level: usize,
        /// The bias estimate.
        bias: f64,
        /// Its share of the target, `eps / sqrt(2)`.
        target: f64,
    },
    /// A multilevel correction `Y_l = P_l - P_{l-1}` has a kurtosis above
    /// [`HEAVY_TAIL_KURTOSIS`] (the level with the largest is named): a few rare samples carry
    /// most of its variance, so that variance, the samples planned from it and the standard
    /// error are themselves uncertain. Giles' `mlmc_test` warns at the same bound; payoffs
    /// with a jump (digital, barrier) reach it on deep levels.
    HeavyTailedLevel {
        /// The level `l >= 1` with the largest kurtosis.
        level: usize,
        /// Its kurtosis.
        kurtosis: f64,
    },
    /// Giles' consistency check failed: at `level`, the mean of `P_l - P_{l-1}` differs from
    /// the mean of `P_l` minus the previous level's mean of its own `P_{l-1}` by more than
    /// three standard errors (`check` is that difference over three of them; the largest is
    /// named). The coarse sample of level `l` then does not have the law of the fine sample
    /// of level `l - 1`, a coupling error in the model, and the telescoping sum is biased.
    InconsistentLevels {
        /// The level `l >= 1` with the largest check.
        level: usize,
        /// Its check, above 1.
        check: f64,
    },
}

/// A multilevel correction whose kurtosis is above this is heavy-tailed
/// ([`Warning::HeavyTailedLevel`]); Giles' `mlmc_test` uses the same bound.
///
/// ```
/// assert_eq!(mcint::stats::HEAVY_TAIL_KURTOSIS, 100.0);
/// ```
pub const HEAVY_TAIL_KURTOSIS: f64 = 100.0;

/// A `Q` below this warns that combined iterations disagree ([`Warning::IterationsDisagree`]):
/// iterations with honest variances give it in 1% of runs.
///
/// ```
/// assert_eq!(mcint::stats::DISAGREEMENT_Q, 0.01);
/// ```
pub const DISAGREEMENT_Q: f64 = 0.01;

impl Warning {
    /// A short stable name of the warning's kind, for machine-readable output.
    ///
    /// ```
    /// use mcint::stats::Warning;
    /// assert_eq!(Warning::FewReplicates { replicates: 4 }.kind(), "few-replicates");
    /// ```
    pub fn kind(&self) -> &'static str {
        match self {
            Warning::UnbalancedSampleSize { .. } => "unbalanced-sample-size",
            Warning::ToleranceNotMet { .. } => "tolerance-not-met",
            Warning::FewReplicates { .. } => "few-replicates",
            Warning::NoErrorBar { .. } => "no-error-bar",
            Warning::NonFiniteSkipped { .. } => "non-finite-skipped",
            Warning::AtRoundingFloor { .. } => "at-rounding-floor",
            Warning::StoppedEarly { .. } => "stopped-early",
            Warning::AllZero { .. } => "all-zero",
            Warning::IterationsDisagree { .. } => "iterations-disagree",
            Warning::BiasAboveTarget { .. } => "bias-above-target",
            Warning::HeavyTailedLevel { .. } => "heavy-tailed-level",
            Warning::InconsistentLevels { .. } => "inconsistent-levels",
        }
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::UnbalancedSampleSize {
                sampler,
                samples,
                base,
                below,
                above,
            } => write!(
                f,
                "{samples} points per replicate break the balance of the {sampler} sampler, \
                 whose points are nets only in blocks of powers of {base}; {below} or {above} \
                 points keep it (and its convergence rate)"
            ),
            Warning::ToleranceNotMet { stop } => write!(
                f,
                "the run stopped ({}) before meeting the tolerance: the interval is wider \
                 than asked, or its iterations disagree",
                stop_words(*stop)
            ),
            Warning::AllZero { count } => write!(
                f,
                "all {count} contributions were exactly zero (or underflowed): the integrand may \
                 be nonzero where no point fell; sample where it is (importance sampling) or \
                 rescale it"
            ),
            Warning::StoppedEarly {
                stop,
                done,
                planned,
            } => write!(
                f,
                "the run stopped ({}) after {done} of its {planned} evaluations; the estimate \
                 uses those",
                stop_words(*stop)
            ),
            Warning::FewReplicates { replicates } => write!(
                f,
                "only {replicates} replicates: the interval is wide and its standard error \
                 uncertain; use at least 8"
            ),
            Warning::NoErrorBar {
                sampler,
                randomized: true,
            } => write!(
                f,
                "one replicate of {sampler} points has no error bar (its points are dependent): \
                 run 8 or more replicates for one from their spread"
            ),
            Warning::NoErrorBar {
                sampler,
                randomized: false,
            } => write!(
                f,
                "one replicate of {sampler} points has no error bar (its points are dependent), \
                 and unrandomized points give none with more replicates: randomize them (a \
                 scramble or a shift) and run 8 or more replicates"
            ),
            Warning::NonFiniteSkipped { count } => write!(
                f,
                "{count} NaN or infinite contributions were left out: the estimate is the \
                 mean of the finite ones"
            ),
            Warning::IterationsDisagree {
                iterations,
                chi2_dof,
                q_value,
            } => write!(
                f,
                "the {iterations} combined iterations disagree (chi2/dof {chi2_dof:.2}, \
                 Q = {q_value:.1e}): their variances are too small or their estimates drift, so \
                 the error bar given is their scatter, sqrt(chi2/dof) times wider; possible \
                 causes: a discontinuity or a narrow peak \
                 that most iterations of this size miss (more evaluations per iteration, or \
                 MISER or randomized QMC, which need no grid), or a grid still adapting (more \
                 warm-up iterations)"
            ),
            Warning::AtRoundingFloor { statistical, floor } => write!(
                f,
                "the statistical standard error {statistical:.3e} is below the rounding error \
                 bound of the mean, {floor:.3e}, which is reported instead"
            ),
            Warning::BiasAboveTarget {
                level,
                bias,
                target,
            } => write!(
                f,
                "the bias estimate {bias:.3e} is above its target {target:.3e} at level \
                 {level}, the deepest allowed: allow more levels (max_level) or use a scheme of \
                 higher weak order"
            ),
            Warning::HeavyTailedLevel { level, kurtosis } => write!(
                f,
                "the correction P_l - P_(l-1) at level {level} has kurtosis {kurtosis:.0}, above \
                 {HEAVY_TAIL_KURTOSIS}: a few rare samples carry most of its variance, so that \
                 variance, the samples planned from it and the standard error are uncertain; a \
                 smoother payoff (a conditional expectation over the last step) or more \
                 samples on that level help"
            ),
            Warning::InconsistentLevels { level, check } => write!(
                f,
                "at level {level}, the mean of P_l - P_(l-1) differs from mean(P_l) - \
                 mean(P_(l-1)) by {check:.2} times three standard errors: the coarse sample of \
                 level {level} does not seem to have the law of the fine sample of level {}, \
                 a coupling error in the model that biases the estimate",
                level.saturating_sub(1)
            ),
        }
    }
}

/// A stop reason in words.
fn stop_words(stop: StopReason) -> &'static str {
    match stop {
        StopReason::Budget => "its budget spent",
        StopReason::ToleranceMet => "tolerance met",
        StopReason::MaxEvaluations => "evaluation limit",
        StopReason::TimeLimit => "time limit",
        StopReason::Cancelled => "cancelled",
        StopReason::SamplerExhausted => "the sampler ran out of points",
        StopReason::IterationsDisagree => "iterations that disagree",
        StopReason::MaxLevel => "the deepest level allowed",
        StopReason::InconsistentLevels => "levels that fail the consistency check",
    }
}
