//! [`VectorEstimate`]: the estimates of several integrals over the same points, with the
//! covariance of their means.

use super::accumulator::{Accumulator, scale_for};
use super::covariance::CovarianceAccumulator;
use super::derived::Derived;
use super::estimate::Estimate;
use super::warning::DISAGREEMENT_Q;
use crate::error::{Error, Result};
use crate::stop_reason::StopReason;

/// The result of a run of a vector-valued integrand: per output an [`Estimate`] (mean,
/// standard error, interval, warnings), and the covariance matrix of the `m` mean estimates.
///
/// The covariance comes from the per-sample covariance of the outputs divided by `n` for
/// independent points (the points where every output is finite), and from the sample
/// covariance of the replicate means divided by `R` for stratified and quasi-random points,
/// the same bases as each output's standard error; its diagonal is each output's
/// `std_error^2`, so the two always agree.
///
/// ```
/// use mcint::Integrator;
/// use mcint::pdf::UniformBox;
/// use mcint::sampler::{Scramble, Sobol};
/// // x and 2x + 1 over the same scrambled Sobol' points: perfectly correlated estimates.
/// let f = |x: &[f64], out: &mut [f64]| {
///     out[0] = x[0];
///     out[1] = 2.0 * x[0] + 1.0;
/// };
/// let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap())
///     .sampler(Sobol::new(1, Scramble::Owen, 3).unwrap())
///     .samples(256)
///     .replicates(16)
///     .run()
///     .unwrap();
/// assert!((run.correlation(0, 1).unwrap() - 1.0).abs() < 1e-9);
/// assert_eq!(run.covariance(1, 1), run.outputs[1].variance());
/// ```
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct VectorEstimate {
    /// The estimate of each output's integral.
    pub outputs: Vec<Estimate>,
    /// The covariance matrix of the output means, row by row (`m * m` entries); `None` where
    /// the outputs have no standard error (a single replicate of dependent points).
    pub covariance_matrix: Option<Vec<f64>>,
    /// Integrand evaluations the run spent: one per point for all outputs together.
    pub evaluations: u64,
    /// Why the run stopped.
    pub stop: StopReason,
    /// Whether every requested tolerance (per output and on derived quantities) was met;
    /// `None` without a tolerance.
    pub converged: Option<bool>,
    /// Stages of a run to a tolerance (1 for a single fixed run).
    pub iterations: u64,
}

impl VectorEstimate {
    /// Number of outputs `m`.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let f = |_: &[f64], out: &mut [f64]| out.fill(1.0);
    /// let run = Integrator::over_box_vector(3, f, UniformBox::unit(1).unwrap()).samples(8).run().unwrap();
    /// assert_eq!(run.len(), 3);
    /// assert!(!run.is_empty());
    /// ```
    pub fn len(&self) -> usize {
        self.outputs.len()
    }

    /// Whether there are no outputs (never, for a finished run).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let f = |_: &[f64], out: &mut [f64]| out.fill(1.0);
    /// assert!(!Integrator::over_box_vector(1, f, UniformBox::unit(1).unwrap()).samples(8).run().unwrap().is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.outputs.is_empty()
    }

    /// The mean estimate of every output.
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let f = |_: &[f64], out: &mut [f64]| { out[0] = 1.0; out[1] = 2.0; };
    /// let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap()).samples(8).run().unwrap();
    /// assert_eq!(run.means(), vec![1.0, 2.0]);
    /// ```
    pub fn means(&self) -> Vec<f64> {
        self.outputs.iter().map(|e| e.mean).collect()
    }

    /// The covariance of the mean estimates of outputs `i` and `j` (`None` without error
    /// bars or for an index out of range).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let f = |x: &[f64], out: &mut [f64]| { out[0] = x[0]; out[1] = -x[0]; };
    /// let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap()).samples(1000).run().unwrap();
    /// assert!(run.covariance(0, 1).unwrap() < 0.0);
    /// assert_eq!(run.covariance(0, 2), None);
    /// ```
    pub fn covariance(&self, i: usize, j: usize) -> Option<f64> {
        let m = self.len();
        if i >= m || j >= m {
            return None;
        }
        // A matrix of another shape (edited or read back by hand) has no such entry.
        self.covariance_matrix
            .as_ref()
            .and_then(|c| (c.len() == m * m).then(|| c[i * m + j]))
    }

    /// The correlation of the mean estimates of outputs `i` and `j` (`None` without error
    /// bars, out of range, or where a variance is zero).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox};
    /// let f = |x: &[f64], out: &mut [f64]| { out[0] = x[0]; out[1] = -3.0 * x[0]; };
    /// let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap()).samples(1000).run().unwrap();
    /// assert!((run.correlation(0, 1).unwrap() + 1.0).abs() < 1e-9);
    /// ```
    pub fn correlation(&self, i: usize, j: usize) -> Option<f64> {
        let (vi, vj) = (self.covariance(i, i)?, self.covariance(j, j)?);
        // Their product may overflow or underflow where each is fine.
        let product = vi * vj;
        let scale = if product.is_normal() {
            product.sqrt()
        } else {
            vi.sqrt() * vj.sqrt()
        };
        (scale > 0.0).then(|| self.covariance(i, j).map(|c| c / scale))?
    }

    /// The estimate of a function of the integrals (a ratio, or any smooth `g`), with a
    /// delta-method standard error from the covariance (see [`Derived`]).
    ///
    /// ```
    /// use mcint::{Integrator, pdf::UniformBox, stats::Derived};
    /// let f = |x: &[f64], out: &mut [f64]| { out[0] = x[0] * x[0]; out[1] = x[0]; };
    /// let run = Integrator::over_box_vector(2, f, UniformBox::unit(1).unwrap()).samples(100_000).run().unwrap();
    /// let ratio = run.derived(&Derived::ratio(0, 1)).unwrap(); // (1/3) / (1/2)
    /// assert!((ratio.mean - 2.0 / 3.0).abs() < 5.0 * ratio.std_error.unwrap());
    /// ```
    pub fn derived(&self, quantity: &Derived) -> Result<Estimate> {
        quantity.estimate(self)
    }

    /// The estimate of independent points: each output's merged accumulator, and the
    /// outputs' merged covariance accumulator (absent for a single output).
    pub(crate) fn independent(
        outputs: &[Accumulator],
        covariance: Option<&CovarianceAccumulator>,
        replicates: u64,
    ) -> VectorEstimate {
        // Each output's mean is over its own finite values (all, unless non-finite ones were
        // skipped).
        let counts: Vec<f64> = outputs.iter().map(|acc| acc.count() as f64).collect();
        let outputs: Vec<Estimate> = outputs
            .iter()
            .map(|acc| {
                let mut estimate = acc.estimate();
                estimate.replicates = replicates;
                estimate
            })
            .collect();
        let m = outputs.len();
        let matrix = outputs.iter().all(|e| e.std_error.is_some()).then(|| {
            let mut matrix = vec![0.0; m * m];
            if let Some(cov) = covariance.filter(|c| c.count() >= 2) {
                let n = cov.count() as f64;
                for i in 0..m {
                    for j in 0..i {
                        // The means of n_i and n_j values sharing the n rows where both are
                        // finite: Cov = C n / (n_i n_j), C / n when none was skipped.
                        let c = if counts[i] == n && counts[j] == n {
                            cov.covariance(i, j) / n
                        } else {
                            cov.covariance(i, j) * (n / counts[i]) / counts[j]
                        };
                        matrix[i * m + j] = c;
                        matrix[j * m + i] = c;
                    }
                }
            }
            matrix
        });
        VectorEstimate::assemble(outputs, matrix)
    }

    /// The estimate of `R` replicates of dependent points; `accumulators[r * m + k]` holds
    /// output `k` of replicate `r`.
    pub(crate) fn replicates(accumulators: &[Accumulator], m: usize) -> Result<VectorEstimate> {
        let r = accumulators.len() / m;
        let outputs = (0..m)
            .map(|k| {
                let column: Vec<Accumulator> =
                    (0..r).map(|rep| accumulators[rep * m + k]).collect();
                Estimate::from_replicate_accumulators(&column)
            })
            .collect::<Result<Vec<Estimate>>>()?;
        let matrix = (r >= 2).then(|| {
            // In units of a power of two per output, so that means up to f64::MAX keep
            // finite products (exact scaling: the bits of ordinary results do not change).
            let scales: Vec<f64> = (0..m)
                .map(|k| {
                    scale_for((0..r).fold(0.0f64, |a, rep| {
                        a.max(accumulators[rep * m + k].mean().abs())
                    }))
                })
                .collect();
            let centred = |rep: usize, k: usize| {
                accumulators[rep * m + k].mean() / scales[k] - outputs[k].mean / scales[k]
            };
            let mut matrix = vec![0.0; m * m];
            for i in 0..m {
                for j in 0..i {
                    let sum: f64 = (0..r).map(|rep| centred(rep, i) * centred(rep, j)).sum();
                    let c = sum / ((r - 1) * r) as f64 * scales[i] * scales[j];
                    matrix[i * m + j] = c;
                    matrix[j * m + i] = c;
                }
            }
            matrix
        });
        Ok(VectorEstimate::assemble(outputs, matrix))
    }

    /// The result with run-level fields from the first output, and each output's
    /// `std_error^2` on the diagonal of the covariance.
    pub(crate) fn assemble(outputs: Vec<Estimate>, matrix: Option<Vec<f64>>) -> VectorEstimate {
        let mut estimate = VectorEstimate {
            evaluations: outputs[0].evaluations,
            stop: outputs[0].stop,
            converged: outputs[0].converged,
            iterations: outputs[0].iterations,
            outputs,
            covariance_matrix: matrix,
        };
        estimate.sync_diagonal();
        estimate
    }

    /// Writes each output's `std_error^2` on the diagonal (after its rounding floor or an
    /// inflation changed it).
    pub(crate) fn sync_diagonal(&mut self) {
        let m = self.len();
        if let Some(matrix) = self.covariance_matrix.as_mut() {
            for (k, output) in self.outputs.iter().enumerate() {
                matrix[k * m + k] = output.variance().unwrap_or(0.0);
            }
        }
    }

    /// Measures the error of each output whose combined iterations disagree (`q_value` below
    /// [`DISAGREEMENT_Q`]) by their scatter rather than by their own variances, which the
    /// disagreement shows to be too small: its standard error times `sqrt(chi^2/dof)` (the
    /// Birge ratio), with the Student-t quantiles of the iterations' degrees of freedom. The
    /// covariance of the outputs follows. Outputs whose iterations agree are unchanged.
    pub(crate) fn widen_where_iterations_disagree(&mut self) {
        let factors: Vec<f64> = self
            .outputs
            .iter()
            .map(|e| match (e.chi2_dof, e.q_value) {
                (Some(chi2_dof), Some(q)) if q < DISAGREEMENT_Q && chi2_dof > 1.0 => {
                    chi2_dof.sqrt()
                }
                _ => 1.0,
            })
            .collect();
        if factors.iter().all(|&f| f == 1.0) {
            return;
        }
        for (output, &factor) in self.outputs.iter_mut().zip(&factors) {
            if factor > 1.0 {
                output.std_error = output.std_error.map(|s| s * factor);
                output.dof = Some(output.iterations.saturating_sub(1).max(1) as f64);
            }
        }
        let m = self.len();
        if let Some(matrix) = self.covariance_matrix.as_mut() {
            for (j, row) in matrix.chunks_exact_mut(m).enumerate() {
                for (c, factor) in row.iter_mut().zip(&factors) {
                    *c *= factors[j] * factor;
                }
            }
        }
        self.sync_diagonal();
    }

    /// Multiplies every standard error by `factor` (and the covariance by its square).
    pub(crate) fn inflate(&mut self, factor: f64) {
        for output in &mut self.outputs {
            output.std_error = output.std_error.map(|s| s * factor);
        }
        if let Some(matrix) = self.covariance_matrix.as_mut() {
            for c in matrix.iter_mut() {
                *c *= factor * factor;
            }
        }
        self.sync_diagonal();
    }

    /// Applies `change` to every output's estimate and copies the run-level fields of the
    /// first.
    pub(crate) fn for_each_output(&mut self, mut change: impl FnMut(usize, &mut Estimate)) {
        for (k, output) in self.outputs.iter_mut().enumerate() {
            change(k, output);
        }
        self.evaluations = self.outputs[0].evaluations;
        self.stop = self.outputs[0].stop;
        self.iterations = self.outputs[0].iterations;
        self.sync_diagonal();
    }

    /// The estimate, or [`Error::Overflow`] if a mean, standard error or (with several
    /// outputs) covariance is not finite. One output's matrix is its squared standard error
    /// alone, which overflows from about 1.3e154 while the run's results are finite: the
    /// run stands, as a scalar run's does.
    pub(crate) fn checked(self) -> Result<VectorEstimate> {
        for output in &self.outputs {
            output.clone().checked()?;
        }
        if self.outputs.len() == 1 {
            return Ok(self);
        }
        if let Some(bad) = self
            .covariance_matrix
            .iter()
            .flatten()
            .find(|c| !c.is_finite())
        {
            return Err(Error::Overflow {
                what: "covariance of the outputs",
                value: *bad,
            });
        }
        Ok(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_whose_iterations_disagree_get_the_scatter_of_their_iterations() {
        // Two outputs with standard errors 1 and 2 and covariance 0.5; the first's three
        // iterations disagree with chi^2/dof = 4 (a Birge ratio of 2).
        let mut first = Estimate::from_replicates(&[0.0, 2.0], 1).unwrap();
        let second = Estimate::from_replicates(&[0.0, 4.0], 1).unwrap();
        first.chi2_dof = Some(4.0);
        first.q_value = Some(DISAGREEMENT_Q / 2.0);
        first.iterations = 3;
        let mut run =
            VectorEstimate::assemble(vec![first, second.clone()], Some(vec![0.0, 0.5, 0.5, 0.0]));
        run.widen_where_iterations_disagree();
        assert_eq!(run.outputs[0].std_error, Some(2.0));
        assert_eq!(run.outputs[0].dof, Some(2.0));
        assert_eq!(run.outputs[1], second);
        assert_eq!(run.covariance_matrix, Some(vec![4.0, 1.0, 1.0, 4.0]));
        // Agreeing iterations (a larger Q) are left alone.
        let mut agreeing = run.clone();
        agreeing.outputs[0].q_value = Some(DISAGREEMENT_Q * 2.0);
        let before = agreeing.clone();
        agreeing.widen_where_iterations_disagree();
        assert_eq!(agreeing, before);
    }
}
