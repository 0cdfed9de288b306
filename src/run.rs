//! [`Run`]: what every runner is to a program that chooses its method at run time.

use crate::adaptive::{Miser, ScalarBatch, SobolG, TwoStage, Vegas, VegasBatch, VegasOutputs};
use crate::error::Result;
use crate::estimator::Estimator;
use crate::integrate::{Integration, Integrator};
use crate::points::Points;
use crate::stats::{Estimate, VectorEstimate};

/// A configured run of any method: the [`Integrator`] (scalar or vector), [`Vegas`] (scalar
/// or vector), [`Miser`], [`TwoStage`] and [`SobolG`].
///
/// Each runner's own `run` gives its natural result (an [`Estimate`] for one output, a
/// [`VectorEstimate`] for several); through this trait every one gives a `VectorEstimate`
/// (one output for a scalar integrand), with the same stop reasons, convergence flag and
/// warnings whichever method ran, so that a program (a command line, a binding) can hold a
/// `Box<dyn Run>` and dispatch its method in one place.
///
/// ```
/// use mcint::{Integrator, Run, adaptive::{Miser, Vegas}, pdf::UniformBox};
/// let f = |x: &[f64]| x[0] * x[1];
/// let square = || UniformBox::unit(2).unwrap();
/// let runs: Vec<Box<dyn Run>> = vec![
///     Box::new(Integrator::over_box(f, square()).samples(4096)),
///     Box::new(Vegas::new(f, square()).samples(1000)),
///     Box::new(Miser::new(f, square()).samples(1024)),
/// ];
/// for run in &runs {
///     let result = run.run_vector().unwrap();
///     let e = &result.outputs[0];
///     assert!((e.mean - 0.25).abs() < 5.0 * e.std_error.unwrap());
/// }
/// ```
pub trait Run {
    /// Runs it: every output's estimate (one for a scalar integrand), how the run ended and
    /// its warnings.
    ///
    /// ```
    /// use mcint::{Run, adaptive::TwoStage, pdf::UniformBox};
    /// let run = TwoStage::new(|x: &[f64]| x[0], UniformBox::unit(1).unwrap(), 8);
    /// assert_eq!(run.run_vector().unwrap().outputs[0], run.run().unwrap());
    /// ```
    fn run_vector(&self) -> Result<VectorEstimate>;
}

impl From<Estimate> for VectorEstimate {
    /// The estimate of one output as a vector of one, its variance the covariance matrix.
    ///
    /// ```
    /// use mcint::{Estimate, VectorEstimate};
    /// let e = Estimate::from_replicates(&[1.0, 3.0], 10).unwrap();
    /// let v = VectorEstimate::from(e.clone());
    /// assert_eq!((v.outputs[0].clone(), v.covariance(0, 0)), (e, Some(1.0)));
    /// ```
    fn from(estimate: Estimate) -> VectorEstimate {
        let matrix = estimate.variance().map(|v| vec![v]);
        VectorEstimate::assemble(vec![estimate], matrix)
    }
}

impl<E: Integration> Run for Integrator<E> {
    fn run_vector(&self) -> Result<VectorEstimate> {
        self.run().map(Into::into)
    }
}

impl<F: Fn(&[f64]) -> f64 + Sync> Run for Vegas<F> {
    fn run_vector(&self) -> Result<VectorEstimate> {
        self.run().map(VectorEstimate::from)
    }
}

impl<G: Fn(&[f64], &mut [f64]) + Sync> Run for Vegas<VegasOutputs<G>> {
    fn run_vector(&self) -> Result<VectorEstimate> {
        self.run()
    }
}

impl<G: Fn(&Points, &mut [f64]) + Sync> Run for Vegas<VegasOutputs<VegasBatch<G>>> {
    fn run_vector(&self) -> Result<VectorEstimate> {
        self.run()
    }
}

impl<F: Fn(&[f64]) -> f64 + Sync> Run for Miser<F> {
    fn run_vector(&self) -> Result<VectorEstimate> {
        self.run().map(VectorEstimate::from)
    }
}

impl<G: Fn(&Points, &mut [f64]) + Sync> Run for Miser<ScalarBatch<G>> {
    fn run_vector(&self) -> Result<VectorEstimate> {
        self.run().map(VectorEstimate::from)
    }
}

impl<F: Fn(&[f64]) -> f64 + Sync> Run for TwoStage<F> {
    fn run_vector(&self) -> Result<VectorEstimate> {
        self.run().map(VectorEstimate::from)
    }
}

impl<G: Fn(&Points, &mut [f64]) + Sync> Run for TwoStage<ScalarBatch<G>> {
    fn run_vector(&self) -> Result<VectorEstimate> {
        self.run().map(VectorEstimate::from)
    }
}

impl<E: Estimator> Run for SobolG<E> {
    fn run_vector(&self) -> Result<VectorEstimate> {
        self.run().map(VectorEstimate::from)
    }
}
