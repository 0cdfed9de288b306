//! The combination of VEGAS iterations, with their `chi^2` agreement.
//!
//! Each iteration is weighted by the inverse of the variance that the iteration before it
//! measured (the last warm-up iteration's for the first), not by its own. An iteration's
//! estimate and its own variance come from the same points and are correlated (points that
//! happen to hold large values raise both), so weights of their own variance pull the
//! combination towards the iterations that undershot, or overshot, by about the skewness times
//! `sqrt(m / n)` standard errors for `m` iterations of `n` points: negligible over ten
//! iterations, not over the thousands a tight tolerance takes (docs/measurements.md has the
//! measurement). A weight fixed before an iteration's points are drawn
//! leaves each term unbiased; the variance of the combination, `sum w_i^2 var_i / (sum w_i)^2`,
//! takes the iterations' own variances.

use super::moments::pair;
use super::pass::Totals;
use super::units::Units;
use crate::special::chi_square_sf;
use crate::stats::rounding::{contribution_allowance, gamma};
use crate::stats::{DISAGREEMENT_Q, ErrorBasis, Estimate, StopReason, VectorEstimate, Warning};

/// Smallest iteration variance used, so that exact (zero-variance) iterations do not divide
/// by zero (the `TINY` of `vegas`).
const TINY_VARIANCE: f64 = 1e-250;

/// One combined iteration: its estimate, its variance and its weight.
#[derive(Clone, Copy)]
struct Iteration {
    mean: f64,
    variance: f64,
    weight: f64,
}

/// The weighted combination of the iterations after the warm-up.
#[derive(Default)]
pub(super) struct Combination {
    results: Vec<Iteration>,
    /// The warm-up iterations' estimates and variances.
    warmups: Vec<(f64, f64)>,
    /// The largest weight so far: the sums below hold weights divided by it, which are at
    /// most 1 (weights themselves reach `1 / TINY_VARIANCE`, and their squares would overflow).
    scale: f64,
    sum_weights: f64,
    sum_weighted: f64,
    /// `sum w_i^2 var_i`, the variance of the weighted sum.
    sum_weighted_variance: f64,
    /// The iterations' rounding bounds, weighted like their means.
    sum_weighted_rounding: f64,
    dof: f64,
    /// The iterations' means weighted by the inverse of their own variances: the sum of those
    /// weights, the weighted mean, and the weighted sum of squared deviations from it (West's
    /// update), from which `chi^2` follows without a pass over every iteration.
    own_weights: f64,
    own_mean: f64,
    own_squares: f64,
    /// The largest iteration estimate in magnitude.
    largest: f64,
    /// The size of the previous iteration over the next one's, when they differ.
    size_ratio: Option<f64>,
    /// The variance of the last iteration set aside by a restart, which weights the next
    /// (`None` while none was).
    set_aside: Option<f64>,
    /// Whether a combined iteration had a value other than zero: without one, every
    /// contribution was zero, and the floor on the variances is no error bar.
    any_nonzero: bool,
}

impl Combination {
    pub(super) fn count(&self) -> u64 {
        self.results.len() as u64
    }

    /// Notes a warm-up iteration's estimate and variance: the first combined iteration is
    /// weighted by the last one's variance and checked against every one's estimate.
    pub(super) fn warm_up(&mut self, mean: f64, variance: f64) {
        self.warmups.push((mean, variance.max(TINY_VARIANCE)));
    }

    /// Adds an iteration's estimate, its variance and degrees of freedom, and the bound on
    /// the rounding error of its estimate.
    pub(super) fn add(&mut self, mean: f64, variance: f64, dof: u64, rounding: f64) {
        self.any_nonzero |= mean != 0.0 || variance != 0.0;
        let variance = variance.max(TINY_VARIANCE);
        // The variance of the iteration before: the last combined one, or the last warm-up.
        let previous = self.results.last().map(|r| r.variance).or(self.set_aside);
        let last_warmup = self.warmups.last().map(|&(_, v)| v);
        // An iteration `1 / ratio` times larger has about `ratio` times the variance.
        let ratio = self.size_ratio.take().unwrap_or(1.0);
        let weight = 1.0 / (ratio * previous.or(last_warmup).unwrap_or(variance));
        self.results.push(Iteration {
            mean,
            variance,
            weight,
        });
        if weight > self.scale {
            let shrink = self.scale / weight;
            self.sum_weights *= shrink;
            self.sum_weighted *= shrink;
            self.sum_weighted_variance *= shrink * shrink;
            self.sum_weighted_rounding *= shrink;
            self.scale = weight;
        }
        let relative = weight / self.scale;
        self.sum_weights += relative;
        self.sum_weighted += relative * mean;
        self.sum_weighted_variance += relative * relative * variance;
        self.sum_weighted_rounding += relative * rounding;
        self.dof += dof.max(1) as f64;
        let own = 1.0 / variance;
        self.own_weights += own;
        let deviation = mean - self.own_mean;
        self.own_mean += own / self.own_weights * deviation;
        self.own_squares += own * deviation * (mean - self.own_mean);
        self.largest = self.largest.max(mean.abs());
    }

    /// Whether the first iteration agrees with the warm-up iterations (true without a
    /// warm-up): each is an unbiased estimate with its own variance, so, if those are right,
    /// the `chi^2` of all of them about their weighted mean has a `Q` of at least
    /// [`DISAGREEMENT_Q`] but by chance. A single earlier iteration is a weak check: one whose
    /// variance is honest, and so large, agrees with anything.
    ///
    /// The first warm-up iteration is left out when there are others: drawn before the grid
    /// adapted, it is plain Monte Carlo on the raw integrand, whose variance a sharp peak
    /// makes the least trustworthy of all; a disagreement with it alone would double the
    /// iterations for nothing (docs/measurements.md).
    fn first_agrees(&self) -> bool {
        let Some(first) = self.results.first() else {
            return true;
        };
        if self.warmups.is_empty() {
            return true;
        }
        let trusted = &self.warmups[usize::from(self.warmups.len() > 1)..];
        let all = || std::iter::once((first.mean, first.variance)).chain(trusted.iter().copied());
        let (weights, weighted) = all().fold((0.0, 0.0), |(w, s), (m, v)| (w + 1.0 / v, s + m / v));
        let mean = weighted / weights;
        let chi2: f64 = all().map(|(m, v)| (m - mean).powi(2) / v).sum();
        chi_square_sf(chi2, trusted.len() as f64) >= DISAGREEMENT_Q
    }

    /// The combined estimate of `n` measured evaluations, out of `evaluations` spent, of
    /// iterations summed in units of `unit`.
    pub(super) fn estimate(&self, n: u64, evaluations: u64, unit: f64) -> Estimate {
        let mean = self.sum_weighted / self.sum_weights;
        let m = self.count();
        let (chi2_dof, q_value) = if m > 1 {
            // sum_i (m_i - mean)^2 / var_i, about the own-weighted mean and shifted to `mean`.
            let shift = self.own_mean - mean;
            let chi2 = self.own_squares + self.own_weights * shift * shift;
            let dof = (m - 1) as f64;
            (Some(chi2 / dof), Some(chi_square_sf(chi2, dof)))
        } else {
            (None, None)
        };
        // The weighted sums of m terms and their ratio: at most 2m + 2 roundings of the
        // largest iteration estimate.
        let rounding = self.sum_weighted_rounding / self.sum_weights
            + gamma(2.0 * m as f64 + 2.0) * self.largest;
        let all_zero = m > 0 && !self.any_nonzero;
        let std_error = if all_zero {
            0.0
        } else {
            self.sum_weighted_variance.sqrt() / self.sum_weights * unit
        };
        let mut estimate = Estimate {
            mean: mean * unit,
            std_error: Some(std_error),
            dof: Some(self.dof),
            basis: ErrorBasis::PerSample,
            n,
            evaluations,
            replicates: m,
            non_finite: 0,
            stop: StopReason::Budget,
            converged: None,
            iterations: m,
            chi2_dof,
            q_value,
            // Values were rounded in the integrand's own units, where one that underflowed
            // carries an absolute error the sums' units scale away.
            rounding_error: rounding * unit + contribution_allowance(0.0),
            warnings: Vec::new(),
            error_bound: None,
        };
        if all_zero {
            // As the other runners say it: 0 +- 0 only says that no point hit a value.
            estimate.warn(Warning::AllZero { count: n });
        }
        estimate.finalize();
        estimate
    }
}

/// The iterations of several outputs: each output combined with its own weights (as one
/// output alone would be), and the covariance of the combined estimates,
/// `cov(I_j, I_k) = sum_i w_ij w_ik cov_i(j, k) / (W_j W_k)` over iterations `i`, with `w_ij`
/// the weight of output `j` in iteration `i` and `W_j = sum_i w_ij`.
pub(super) struct VectorCombination {
    outputs: Vec<Combination>,
    /// Each iteration's covariance of each pair of outputs, as `Totals` lays them out.
    covariances: Vec<Vec<f64>>,
}

impl VectorCombination {
    pub(super) fn new(m: usize) -> VectorCombination {
        VectorCombination {
            outputs: (0..m).map(|_| Combination::default()).collect(),
            covariances: Vec::new(),
        }
    }

    pub(super) fn count(&self) -> u64 {
        self.outputs[0].count()
    }

    /// The variance of the last combined iteration's first output (NaN before one).
    pub(super) fn last_variance(&self) -> f64 {
        self.outputs[0]
            .results
            .last()
            .map_or(f64::NAN, |r| r.variance)
    }

    /// Adds an iteration's totals, whose variances have `dof` degrees of freedom.
    pub(super) fn add(&mut self, totals: &Totals, dof: u64) {
        for (k, combination) in self.outputs.iter_mut().enumerate() {
            let sums = &totals.sums.outputs[k];
            combination.add(sums.mean, sums.variance, dof, sums.rounding);
        }
        self.covariances.push(totals.sums.covariance.clone());
    }

    /// Notes a warm-up iteration's totals (see [`Combination::warm_up`]).
    pub(super) fn warm_up(&mut self, totals: &Totals) {
        for (combination, sums) in self.outputs.iter_mut().zip(&totals.sums.outputs) {
            combination.warm_up(sums.mean, sums.variance);
        }
    }

    /// Starts the combination again after the iterations grew by `1 / ratio`: the earlier
    /// ones, which disagreed, are set aside, and the last one's variance (times `ratio`)
    /// weights the next. The first new iteration is then not checked against the warm-up
    /// (whose small iterations may be what disagreed): it needs a second (see
    /// [`VectorCombination::first_agrees`]).
    pub(super) fn restart(&mut self, ratio: f64) {
        for combination in &mut self.outputs {
            let set_aside = combination.results.last().map(|r| r.variance);
            let warmups = std::mem::take(&mut combination.warmups);
            *combination = Combination {
                warmups,
                set_aside,
                size_ratio: Some(ratio),
                ..Combination::default()
            };
        }
        self.covariances.clear();
    }

    /// Tells the combination that the next iteration is `1 / ratio` times larger than the
    /// last one, whose variance, times `ratio`, then weights it.
    pub(super) fn scale_next(&mut self, ratio: f64) {
        for combination in &mut self.outputs {
            combination.size_ratio = Some(ratio);
        }
    }

    /// Whether every output's first iteration agrees with its warm-up iterations (true
    /// without a warm-up; see [`Combination::first_agrees`]); `None` for the first iteration
    /// after iterations were set aside, which has nothing to be checked against.
    pub(super) fn first_agrees(&self) -> Option<bool> {
        if self.outputs[0].set_aside.is_some() {
            return None;
        }
        Some(self.outputs.iter().all(Combination::first_agrees))
    }

    /// The combined estimate of every output from `n` measured evaluations, `evaluations`
    /// spent in all, of iterations summed in `units`.
    pub(super) fn estimate(&self, n: u64, evaluations: u64, units: &Units) -> VectorEstimate {
        let outputs: Vec<Estimate> = self
            .outputs
            .iter()
            .enumerate()
            .map(|(k, c)| c.estimate(n, evaluations, units.of(k)))
            .collect();
        let m = outputs.len();
        let mut matrix = vec![0.0; m * m];
        for k in 1..m {
            for j in 0..k {
                let (a, b) = (&self.outputs[j], &self.outputs[k]);
                let sum: f64 = self
                    .covariances
                    .iter()
                    .zip(a.results.iter().zip(&b.results))
                    .map(|(cov, (r_j, r_k))| {
                        cov[pair(j, k)] * (r_j.weight / a.scale) * (r_k.weight / b.scale)
                    })
                    .sum();
                let c = sum / (a.sum_weights * b.sum_weights) * units.of(j) * units.of(k);
                matrix[j * m + k] = c;
                matrix[k * m + j] = c;
            }
        }
        VectorEstimate::assemble(outputs, Some(matrix))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn first_after(warmups: &[(f64, f64)]) -> bool {
        let mut c = Combination::default();
        for &(mean, variance) in warmups {
            c.warm_up(mean, variance);
        }
        c.add(1.0, 0.01, 100, 0.0);
        c.first_agrees()
    }

    /// A warm-up iteration 1000 of its standard errors off counts against the first
    /// iteration, unless it is the first of several (drawn before the grid adapted).
    #[test]
    fn the_first_of_several_warm_up_iterations_is_not_checked() {
        let off = (0.0, 1e-6);
        let honest = (1.0, 0.01);
        assert!(first_after(&[honest]));
        assert!(!first_after(&[off]));
        assert!(first_after(&[off, honest, honest]));
        assert!(!first_after(&[honest, off, honest]));
    }

    /// The running chi^2 (West's update, shifted to the combined mean) equals the direct sum
    /// `sum_i (m_i - mean)^2 / var_i` over the iterations, for means far from zero and
    /// variances spread over orders of magnitude.
    #[test]
    fn running_chi2_matches_the_direct_sum() {
        let mut c = Combination::default();
        let iterations: Vec<(f64, f64)> = (0..40)
            .map(|i| {
                let i = f64::from(i);
                (
                    1e6 + (i * 0.7).sin() * 3.0,
                    10f64.powf((i * 1.3).cos() * 2.0),
                )
            })
            .collect();
        for &(mean, variance) in &iterations {
            c.add(mean, variance, 100, 0.0);
        }
        let e = c.estimate(4000, 4000, 1.0);
        let direct: f64 = iterations
            .iter()
            .map(|(m, v)| (m - e.mean).powi(2) / v)
            .sum();
        let running = e.chi2_dof.unwrap() * 39.0;
        assert!(
            (running - direct).abs() <= 1e-9 * direct,
            "{running} vs {direct}"
        );
    }
}
