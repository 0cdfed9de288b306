//! `sobol_indices`: Sobol' indices of a Python model over one of the library's measures, by
//! the library's pick-freeze design with the model called on blocks of inputs.

use std::sync::Arc;

use mcint::measure::Measure;
use mcint::sensitivity::{Indices, SobolDesign};
use mcint::{CancelToken, Estimate};
use pyo3::exceptions::{PyIndexError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::to_py;
use crate::integrand::PyIntegrand;
use crate::measure::MeasureSpec;
use crate::result::warning_list;
use crate::run::{duration, run_watching_signals, tolerance};

/// A shared measure as the design's input law.
struct Shared(Arc<dyn Measure>);

impl Measure for Shared {
    fn canonical_dims(&self) -> usize {
        self.0.canonical_dims()
    }

    fn dims(&self) -> usize {
        self.0.dims()
    }

    fn map(&self, u: &[f64], x: &mut [f64]) -> f64 {
        self.0.map(u, x)
    }
}

/// The indices of a finished design run.
#[pyclass(module = "mcint._native", frozen)]
pub struct SensitivityRun {
    indices: Indices,
}

/// An estimate as `(mean, std_error)`, the error `None` where there is none.
fn pair(e: &Estimate) -> (f64, Option<f64>) {
    (e.mean, e.std_error.filter(|s| s.is_finite()))
}

#[pymethods]
impl SensitivityRun {
    /// Everything the run reports: per output `variance`, `first_order`, `total` (lists of
    /// `(mean, std_error)`) and `second_order` (`(j, k, mean, std_error)`), the factors, the
    /// design points, the model evaluations, how the run stopped and its warnings.
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let ix = &self.indices;
        let d = PyDict::new(py);
        let outputs = PyList::empty(py);
        for o in &ix.outputs {
            let item = PyDict::new(py);
            item.set_item("variance", pair(&o.variance))?;
            item.set_item(
                "first_order",
                o.first_order.iter().map(pair).collect::<Vec<_>>(),
            )?;
            item.set_item("total", o.total.iter().map(pair).collect::<Vec<_>>())?;
            let second: Vec<_> = o
                .second_order
                .iter()
                .map(|s| (s.factors.0, s.factors.1, pair(&s.index)))
                .collect();
            item.set_item("second_order", second)?;
            outputs.append(item)?;
        }
        d.set_item("outputs", outputs)?;
        d.set_item("factors", ix.factors.clone())?;
        d.set_item("points", ix.points)?;
        d.set_item("model_evaluations", ix.model_evaluations)?;
        d.set_item("stop", ix.stop.name())?;
        d.set_item("converged", ix.converged)?;
        d.set_item("warnings", warning_list(py, &ix.warnings)?)?;
        Ok(d)
    }

    /// The confidence interval at `level` of index `j` of output `output`, of `kind`
    /// `"first_order"` or `"total"` (`j` a factor) or `"second_order"` (`j` a pair, in the
    /// order of the report's list); `None` without an error bar.
    fn interval(
        &self,
        kind: &str,
        output: usize,
        j: usize,
        level: f64,
    ) -> PyResult<Option<(f64, f64)>> {
        let o = self
            .indices
            .outputs
            .get(output)
            .ok_or_else(|| PyIndexError::new_err(format!("output {output} out of range")))?;
        let e = match kind {
            "first_order" => o.first_order.get(j),
            "total" => o.total.get(j),
            "second_order" => o.second_order.get(j).map(|s| &s.index),
            _ => {
                return Err(PyValueError::new_err(format!(
                    "invalid kind = '{kind}': expected 'first_order', 'total' or 'second_order'"
                )));
            }
        }
        .ok_or_else(|| PyIndexError::new_err(format!("index {j} out of range")))?;
        e.confidence_interval(level).map_err(to_py)
    }
}

/// Sobol' first-order and total (and second-order) indices of `f` over `measure`.
#[pyfunction]
#[pyo3(signature = (
    f, measure, outputs, *, groups=None, second_order=false, n=None, replicates=None,
    rtol=None, atol=None, max_evals=None, time_limit=None, seed=0, threads=None
))]
#[allow(
    clippy::too_many_arguments,
    reason = "the keyword arguments of mcint.sobol_indices"
)]
pub fn sobol_indices(
    py: Python<'_>,
    f: Py<PyAny>,
    measure: PyRef<'_, MeasureSpec>,
    outputs: usize,
    groups: Option<Vec<Vec<usize>>>,
    second_order: bool,
    n: Option<u64>,
    replicates: Option<u64>,
    rtol: Option<f64>,
    atol: Option<f64>,
    max_evals: Option<u64>,
    time_limit: Option<f64>,
    seed: u64,
    threads: Option<usize>,
) -> PyResult<SensitivityRun> {
    let mut design = SobolDesign::new(Shared(Arc::clone(&measure.measure)))
        .map_err(to_py)?
        .second_order(second_order);
    if let Some(groups) = groups {
        design = design.groups(groups).map_err(to_py)?;
    }
    if let Some(points) = n {
        design = design.points(points);
    }
    if let Some(r) = replicates {
        design = design.replicates(r);
    }
    if let Some(tolerance) = tolerance(rtol, atol, max_evals, "n design points")? {
        design = design.tolerance(tolerance);
    }
    let cancel = CancelToken::new();
    let model = Arc::new(PyIntegrand::new(f, outputs, None, cancel.clone()));
    let in_design = Arc::clone(&model);
    let mut run = design
        .integrator_batch(outputs, move |x: &mcint::Points, out: &mut [f64]| {
            in_design.batch(x, out)
        })
        .map_err(to_py)?
        .seed(seed)
        .cancel_token(cancel);
    if let Some(t) = threads {
        run = run.threads(t);
    }
    if let Some(seconds) = time_limit {
        run = run.time_limit(duration(seconds)?);
    }
    let outcome = run_watching_signals(py, model.failure(), || run.run().map_err(to_py));
    if let Some(error) = model.failure().take() {
        return Err(error);
    }
    let indices = design.indices(&outcome?).map_err(to_py)?;
    Ok(SensitivityRun { indices })
}
