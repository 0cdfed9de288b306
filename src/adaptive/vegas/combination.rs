//! The inverse-variance combination of VEGAS iterations, with their `chi^2` agreement.

use super::moments::pair;
use super::pass::Totals;
use crate::special::chi_square_sf;
use crate::stats::rounding::gamma;
use crate::stats::{DISAGREEMENT_Q, ErrorBasis, Estimate, StopReason, VectorEstimate};

/// Smallest iteration variance used as a weight, so that exact (zero-variance) iterations
/// do not divide by zero (the `TINY` of `vegas`).
const TINY_VARIANCE: f64 = 1e-250;

/// Inverse-variance weighted combination of the iterations after the warm-up.
#[derive(Default)]
pub(super) struct Combination {
    /// Each iteration's estimate and variance.
    results: Vec<(f64, f64)>,
    sum_weights: f64,
    sum_weighted: f64,
    /// The iterations' rounding bounds, weighted like their means.
    sum_weighted_rounding: f64,
    dof: f64,
}

impl Combination {
    pub(super) fn count(&self) -> u64 {
        self.results.len() as u64
    }

    /// Adds an iteration's estimate, its variance and degrees of freedom, and the bound on
    /// the rounding error of its estimate.
    pub(super) fn add(&mut self, mean: f64, variance: f64, dof: u64, rounding: f64) {
        let variance = variance.max(TINY_VARIANCE);
        self.results.push((mean, variance));
        self.sum_weights += 1.0 / variance;
        self.sum_weighted += mean / variance;
        self.sum_weighted_rounding += rounding / variance;
        self.dof += dof.max(1) as f64;
    }

    /// The combined estimate of `n` measured evaluations, out of `evaluations` spent.
    pub(super) fn estimate(&self, n: u64, evaluations: u64) -> Estimate {
        let mean = self.sum_weighted / self.sum_weights;
        let m = self.count();
        let (chi2_dof, q_value) = if m > 1 {
            let chi2: f64 = self
                .results
                .iter()
                .map(|(v, var)| (v - mean) * (v - mean) / var)
                .sum();
            let dof = (m - 1) as f64;
            (Some(chi2 / dof), Some(chi_square_sf(chi2, dof)))
        } else {
            (None, None)
        };
        // The weighted sums of m terms and their ratio: at most 2m + 2 roundings of the
        // largest iteration estimate.
        let largest = self.results.iter().fold(0.0f64, |l, (v, _)| l.max(v.abs()));
        let rounding =
            self.sum_weighted_rounding / self.sum_weights + gamma(2.0 * m as f64 + 2.0) * largest;
        let mut estimate = Estimate {
            mean,
            std_error: Some((1.0 / self.sum_weights).sqrt()),
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
            rounding_error: rounding,
            warnings: Vec::new(),
            error_bound: None,
        };
        estimate.finalize();
        estimate
    }
}

/// The iterations of several outputs: each output combined with its own inverse-variance
/// weights (as one output alone would be), and the covariance of the combined estimates,
/// `cov(I_j, I_k) = sum_i w_ij w_ik cov_i(j, k) / (W_j W_k)` over iterations `i`, with
/// `w_ij = 1 / var_ij` and `W_j = sum_i w_ij`.
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

    /// Adds an iteration's totals, whose variances have `dof` degrees of freedom.
    pub(super) fn add(&mut self, totals: &Totals, dof: u64) {
        for (k, combination) in self.outputs.iter_mut().enumerate() {
            let sums = &totals.sums.outputs[k];
            combination.add(sums.mean, sums.variance, dof, sums.rounding);
        }
        self.covariances.push(totals.sums.covariance.clone());
    }

    /// Whether the first iteration agrees with `other`, each output's estimate and variance
    /// in another iteration (true when `other` is empty): their `chi^2` on one degree of
    /// freedom has a `Q` of at least [`DISAGREEMENT_Q`] for every output.
    pub(super) fn first_agrees(&self, other: &[(f64, f64)]) -> bool {
        self.outputs
            .iter()
            .zip(other)
            .all(|(c, &(mean, variance))| {
                let (first, first_variance) = c.results[0];
                let chi2 = (first - mean).powi(2) / (first_variance + variance).max(TINY_VARIANCE);
                chi_square_sf(chi2, 1.0) >= DISAGREEMENT_Q
            })
    }

    /// The combined estimate of every output from `n` measured evaluations, `evaluations`
    /// spent in all.
    pub(super) fn estimate(&self, n: u64, evaluations: u64) -> VectorEstimate {
        let outputs: Vec<Estimate> = self
            .outputs
            .iter()
            .map(|c| c.estimate(n, evaluations))
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
                    .map(|(cov, ((_, var_j), (_, var_k)))| cov[pair(j, k)] / (var_j * var_k))
                    .sum();
                let c = sum / (a.sum_weights * b.sum_weights);
                matrix[j * m + k] = c;
                matrix[k * m + j] = c;
            }
        }
        VectorEstimate::assemble(outputs, Some(matrix))
    }
}
