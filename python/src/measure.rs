//! `MeasureSpec`: one of the library's measures (Gaussian, lognormal, Brownian paths,
//! geometric Brownian motion, uniform), built from Python parameters.

use std::sync::Arc;

use mcint::measure::{
    BrownianMotion, Construction, Factorization, Gaussian, GeometricBrownianMotion, Lognormal,
    Measure, Uniform,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::{to_py, to_py_naming};

/// A measure of the library: what `mcint.expectation` averages over.
#[pyclass(module = "mcint._native", frozen)]
pub struct MeasureSpec {
    pub measure: Arc<dyn Measure>,
}

fn factorization(name: &str) -> PyResult<Factorization> {
    match name {
        "cholesky" => Ok(Factorization::Cholesky),
        "pca" => Ok(Factorization::Pca),
        _ => Err(PyValueError::new_err(format!(
            "invalid factorization = '{name}': expected 'cholesky' or 'pca'"
        ))),
    }
}

fn construction(name: &str) -> PyResult<Construction> {
    match name {
        "standard" => Ok(Construction::Standard),
        "bridge" => Ok(Construction::Bridge),
        "pca" => Ok(Construction::Pca),
        _ => Err(PyValueError::new_err(format!(
            "invalid construction = '{name}': expected 'standard', 'bridge' or 'pca'"
        ))),
    }
}

fn gaussian(mean: Vec<f64>, covariance: Vec<f64>, how: &str) -> PyResult<Gaussian> {
    Gaussian::new(mean, covariance, factorization(how)?)
        .map_err(|e| to_py_naming(e, &[("covariance", "cov")]))
}

fn spec(measure: impl Measure + 'static) -> MeasureSpec {
    MeasureSpec {
        measure: Arc::new(measure),
    }
}

#[pymethods]
impl MeasureSpec {
    /// The normal law with `mean` and the row-major `covariance` (d x d).
    #[staticmethod]
    fn gaussian(mean: Vec<f64>, covariance: Vec<f64>, factorization: &str) -> PyResult<Self> {
        Ok(spec(gaussian(mean, covariance, factorization)?))
    }

    /// `exp` of the normal law with `mean` and `covariance`, coordinate by coordinate.
    #[staticmethod]
    fn lognormal(mean: Vec<f64>, covariance: Vec<f64>, factorization: &str) -> PyResult<Self> {
        let law = Lognormal::new(gaussian(mean, covariance, factorization)?);
        Ok(spec(law.map_err(|e| {
            to_py_naming(e, &[("gaussian", "mean and cov")])
        })?))
    }

    /// `mu t + sigma W(t)` on the dates `times`.
    #[staticmethod]
    fn brownian(times: Vec<f64>, drift: f64, diffusion: f64, how: &str) -> PyResult<Self> {
        let path = BrownianMotion::new(times, drift, diffusion, construction(how)?);
        Ok(spec(path.map_err(to_py)?))
    }

    /// Geometric Brownian motion from `s0` with `rate` and `sigma` on the dates `times`.
    #[staticmethod]
    fn geometric_brownian(
        s0: f64,
        rate: f64,
        sigma: f64,
        times: Vec<f64>,
        how: &str,
    ) -> PyResult<Self> {
        let path = GeometricBrownianMotion::new(s0, rate, sigma, times, construction(how)?);
        Ok(spec(path.map_err(to_py)?))
    }

    /// The uniform law on the box `[lower, upper)`.
    #[staticmethod]
    fn uniform(lower: Vec<f64>, upper: Vec<f64>) -> PyResult<Self> {
        Ok(spec(Uniform::new(lower, upper).map_err(to_py)?))
    }

    /// The dimension of the measure's points.
    #[getter]
    fn d(&self) -> usize {
        self.measure.dims()
    }

    /// The image of the canonical point `(1/2, ..., 1/2)` (the median of each coordinate of
    /// a Gaussian): where `mcint.expectation` probes `f` for its number of outputs.
    fn middle(&self) -> Vec<f64> {
        let u = vec![0.5; self.measure.canonical_dims()];
        let mut x = vec![0.0; self.measure.dims()];
        self.measure.map(&u, &mut x);
        x
    }

    /// The canonical coordinates one point takes.
    #[getter]
    fn canonical_dims(&self) -> usize {
        self.measure.canonical_dims()
    }
}
