//! `sobol_indices`: Sobol' indices of a Python model over one of the library's measures, by
//! the library's pick-freeze design with the model called on blocks of inputs.

use std::sync::Arc;

use mcint::measure::Measure;
use mcint::sensitivity::{Indices, SobolDesign};
use mcint::{CancelToken, Estimate};
use pyo3::exceptions::{PyFloatingPointError, PyIndexError, PyValueError};
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
    let outcome = run_watching_signals(py, model.failure(), || Ok(run.run()));
    if let Some(error) = model.failure().take() {
        return Err(error);
    }
    let estimate = match outcome? {
        Ok(estimate) => estimate,
        Err(error) => return Err(name_non_finite_run(&design, &model, outputs, error)),
    };
    let indices = design.indices(&estimate).map_err(to_py)?;
    Ok(SensitivityRun { indices })
}

/// The error of a run, a non-finite value named as the model run behind it (its input, its
/// output, which run of which design point), found by running the model again at the design
/// point the library's error names: that error speaks of the design's integrals and of a
/// point of twice the inputs' dimension.
fn name_non_finite_run(
    design: &SobolDesign<Shared>,
    model: &PyIntegrand,
    outputs: usize,
    error: mcint::Error,
) -> PyErr {
    let mcint::Error::NonFiniteContribution {
        count,
        first_index,
        first_replicate,
        first_point,
        ..
    } = &error
    else {
        return to_py(error);
    };
    let Ok(inputs) = design.model_inputs(first_point) else {
        return to_py(error);
    };
    let runs = inputs.len();
    let mut values = vec![f64::NAN; outputs * runs];
    model.batch(&inputs, &mut values);
    if let Some(raised) = model.failure().take() {
        return raised;
    }
    let factors = design.factors();
    for run in 0..runs {
        for output in 0..outputs {
            let value = values[output * runs + run];
            if value.is_finite() {
                continue;
            }
            let name = match run {
                0 => "A".to_string(),
                1 => "B".to_string(),
                r if r < 2 + factors => format!("AB_{}", r - 2),
                r => format!("BA_{}", r - 2 - factors),
            };
            let x: Vec<f64> = (0..inputs.dims()).map(|c| inputs.column(c)[run]).collect();
            let which = if outputs > 1 {
                format!(" (output {output})")
            } else {
                String::new()
            };
            return PyFloatingPointError::new_err(format!(
                "the model returned {value}{which} at x = {x:?}, run {name} of design point \
                 {first_index} of replicate {first_replicate} ({count} non-finite value(s) of \
                 the design's integrals in all): the model must be finite wherever the \
                 inputs' law puts weight"
            ));
        }
    }
    // Every run finite: the design's products overflowed, as the library's error says.
    to_py(error)
}
