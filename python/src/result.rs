//! `RunResult`: a finished run, as the Python result type reads it.

use mcint::stats::Warning;
use mcint::{Estimate, VectorEstimate};
use pyo3::exceptions::PyIndexError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::to_py;

/// Every output's estimate, how the run ended, and the ratio's estimate if one was asked for.
#[pyclass(module = "mcint._native", frozen)]
pub struct RunResult {
    run: VectorEstimate,
    ratio: Option<(usize, usize, Estimate)>,
}

impl RunResult {
    pub fn new(run: VectorEstimate, ratio: Option<(usize, usize, Estimate)>) -> Self {
        RunResult { run, ratio }
    }

    /// Output `k`'s estimate, or the ratio's for `None`.
    fn estimate(&self, output: Option<usize>) -> PyResult<&Estimate> {
        match output {
            Some(k) => self.run.outputs.get(k).ok_or_else(|| {
                PyIndexError::new_err(format!(
                    "output {k} out of range: the run has {} outputs",
                    self.run.outputs.len()
                ))
            }),
            None => self
                .ratio
                .as_ref()
                .map(|(_, _, e)| e)
                .ok_or_else(|| PyIndexError::new_err("the run estimated no ratio")),
        }
    }
}

/// A number JSON can hold: NaN and infinities become `None`.
fn finite(v: Option<f64>) -> Option<f64> {
    v.filter(|v| v.is_finite())
}

#[pymethods]
impl RunResult {
    /// The confidence interval of output `output` (`None`: the ratio) at `level`, or
    /// `None` without an error bar.
    #[pyo3(signature = (output, level))]
    fn interval(&self, output: Option<usize>, level: f64) -> PyResult<Option<(f64, f64)>> {
        self.estimate(output)?
            .confidence_interval(level)
            .map_err(to_py)
    }

    /// Everything the run reports, as a dict with the keys of the command line's
    /// `integrate --json` (vector form: `estimates`, `std_errors`, `covariance`, ...), plus
    /// per-output `dofs`, `error_bounds` and `rounding_errors`.
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let run = &self.run;
        let outputs = &run.outputs;
        let d = PyDict::new(py);
        d.set_item(
            "estimates",
            outputs.iter().map(|e| e.mean).collect::<Vec<_>>(),
        )?;
        let errors: Vec<_> = outputs.iter().map(|e| finite(e.std_error)).collect();
        d.set_item("std_errors", errors)?;
        d.set_item("dofs", outputs.iter().map(|e| e.dof).collect::<Vec<_>>())?;
        let bounds: Vec<_> = outputs.iter().map(|e| e.error_bound).collect();
        d.set_item("error_bounds", bounds)?;
        let rounding: Vec<_> = outputs.iter().map(|e| e.rounding_error).collect();
        d.set_item("rounding_errors", rounding)?;
        let m = outputs.len();
        let covariance = run.covariance_matrix.as_ref().map(|c| {
            (0..m)
                .map(|i| c[i * m..(i + 1) * m].to_vec())
                .collect::<Vec<_>>()
        });
        d.set_item("covariance", covariance)?;
        let first = outputs.first();
        d.set_item("n", first.map_or(0, |e| e.n))?;
        d.set_item("replicates", first.map_or(0, |e| e.replicates))?;
        d.set_item("evaluations", run.evaluations)?;
        d.set_item("converged", run.converged)?;
        d.set_item("stop", run.stop.name())?;
        d.set_item("iterations", run.iterations)?;
        let warnings = PyList::empty(py);
        for (k, e) in outputs.iter().enumerate() {
            for w in &e.warnings {
                let item = warning_dict(py, w)?;
                if m > 1 {
                    item.set_item("output", k)?;
                }
                warnings.append(item)?;
            }
        }
        d.set_item("warnings", warnings)?;
        if let Some((i, j, e)) = &self.ratio {
            let ratio = PyDict::new(py);
            ratio.set_item("numerator", i)?;
            ratio.set_item("denominator", j)?;
            ratio.set_item("estimate", e.mean)?;
            ratio.set_item("std_error", finite(e.std_error))?;
            d.set_item("ratio", ratio)?;
        }
        Ok(d)
    }
}

/// A warning as the package's `RunWarning` is built from: its `kind` and `message`.
pub fn warning_dict<'py>(py: Python<'py>, warning: &Warning) -> PyResult<Bound<'py, PyDict>> {
    let item = PyDict::new(py);
    item.set_item("kind", warning.kind())?;
    item.set_item("message", warning.to_string())?;
    Ok(item)
}

/// Every warning of a run, as [`warning_dict`]s.
pub fn warning_list<'py>(py: Python<'py>, warnings: &[Warning]) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for w in warnings {
        list.append(warning_dict(py, w)?)?;
    }
    Ok(list)
}
