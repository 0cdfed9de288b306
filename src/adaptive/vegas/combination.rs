//! The inverse-variance combination of VEGAS iterations, with their `chi^2` agreement.

use crate::special::chi_square_sf;
use crate::stats::rounding::gamma;
use crate::stats::{ErrorBasis, Estimate, StopReason};

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
        };
        estimate.finalize();
        estimate
    }
}
