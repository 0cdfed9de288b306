//! The result of a sensitivity run: Sobol' indices with error bars, per model output.

use crate::stats::{Estimate, StopReason, Warning};

/// The Sobol' indices of one run of a [`SobolDesign`](super::SobolDesign).
///
/// ```
/// use mcint::{measure::Uniform, sensitivity::SobolDesign};
/// let design = SobolDesign::new(Uniform::unit(2).unwrap()).unwrap();
/// let run = design.integrator(|x: &[f64]| x[0] + x[1]).unwrap().run().unwrap();
/// let indices = design.indices(&run).unwrap();
/// assert_eq!(indices.model_evaluations, 4 * indices.points);
/// assert!((indices.first_order()[0].mean - 0.5).abs() < 1e-3);
/// ```
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Indices {
    /// The indices of each model output (one for a scalar model).
    pub outputs: Vec<OutputIndices>,
    /// The factors, as lists of the law's canonical coordinates (`[[0], [1], ...]` unless
    /// grouped).
    pub factors: Vec<Vec<usize>>,
    /// Points of the design the run integrated.
    pub points: u64,
    /// Model runs: `points` times the design's runs per point.
    pub model_evaluations: u64,
    /// Why the run stopped.
    pub stop: StopReason,
    /// Whether every index met the design's tolerance; `None` without one.
    pub converged: Option<bool>,
    /// The run's warnings, each once.
    pub warnings: Vec<Warning>,
}

impl Indices {
    /// The first-order indices of output 0 (of a scalar model), one per factor.
    ///
    /// ```
    /// use mcint::{measure::Uniform, sensitivity::SobolDesign};
    /// let design = SobolDesign::new(Uniform::unit(2).unwrap()).unwrap();
    /// let run = design.integrator(|x: &[f64]| x[0]).unwrap().run().unwrap();
    /// assert!(design.indices(&run).unwrap().first_order()[1].mean.abs() < 1e-6);
    /// ```
    pub fn first_order(&self) -> &[Estimate] {
        &self.outputs[0].first_order
    }

    /// The total indices of output 0 (of a scalar model), one per factor.
    ///
    /// ```
    /// use mcint::{measure::Uniform, sensitivity::SobolDesign};
    /// let design = SobolDesign::new(Uniform::unit(2).unwrap()).unwrap();
    /// let run = design.integrator(|x: &[f64]| x[0] * x[1]).unwrap().run().unwrap();
    /// // x0 x1 with uniform inputs: V = 7/144, V_T0 = V_0 + V_01 = 1/48 + 1/144.
    /// let total = design.indices(&run).unwrap().total()[0].mean;
    /// assert!((total - 4.0 / 7.0).abs() < 1e-3);
    /// ```
    pub fn total(&self) -> &[Estimate] {
        &self.outputs[0].total
    }
}

/// The indices of one model output.
///
/// ```
/// use mcint::{measure::Uniform, sensitivity::SobolDesign};
/// let design = SobolDesign::new(Uniform::unit(2).unwrap()).unwrap().second_order(true);
/// let run = design.integrator(|x: &[f64]| x[0] * x[1]).unwrap().seed(2).run().unwrap();
/// let output = &design.indices(&run).unwrap().outputs[0];
/// // x0 x1 with uniform inputs: V = 7/144, V_0 = V_1 = 1/48, V_01 = 1/144.
/// assert!((output.second_order[0].index.mean - 1.0 / 7.0).abs() < 1e-3);
/// assert_eq!(output.second_order[0].factors, (0, 1));
/// ```
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct OutputIndices {
    /// `Var Y`.
    pub variance: Estimate,
    /// `S_j = Var E[Y | X_j] / Var Y`, per factor.
    pub first_order: Vec<Estimate>,
    /// `ST_j = E Var[Y | X_~j] / Var Y`, per factor.
    pub total: Vec<Estimate>,
    /// `S_jk` for every pair `j < k` of factors, in the order `(0,1), (0,2), ..., (1,2), ...`;
    /// empty unless the design asked for them.
    pub second_order: Vec<SecondOrder>,
}

/// The second-order index of a pair of factors: the share of the variance that their
/// interaction alone explains.
///
/// ```
/// use mcint::{Estimate, sensitivity::SecondOrder};
/// let pair = SecondOrder { factors: (0, 2), index: Estimate::from_replicates(&[0.1, 0.12], 100).unwrap() };
/// assert_eq!(pair.factors.1, 2);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct SecondOrder {
    /// The two factors `(j, k)`, `j < k`.
    pub factors: (usize, usize),
    /// Its estimate.
    pub index: Estimate,
}

/// Exact Sobol' indices of a test model, to check estimates against.
///
/// ```
/// use mcint::testfns::Ishigami;
/// let exact = Ishigami::new(7.0, 0.1).unwrap().exact_indices();
/// assert!((exact.first_order.iter().sum::<f64>() - 1.0).abs() < 0.3);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ExactIndices {
    /// `Var Y`.
    pub variance: f64,
    /// First-order indices, one per input.
    pub first_order: Vec<f64>,
    /// Total indices, one per input.
    pub total: Vec<f64>,
}
