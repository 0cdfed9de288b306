//! `mlmc`: a multilevel Monte Carlo (or QMC) run of a Python model, its samples drawn a
//! block of canonical points at a time, or of the library's built-in SDE levels.

use std::sync::Arc;

use mcint::multilevel::{Level, Multilevel, MultilevelEstimate};
use mcint::{CancelToken, Points};
use pyo3::exceptions::PyFloatingPointError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::to_py_naming;
use crate::failure::Failure;
use crate::integrand::PyIntegrand;
use crate::result::warning_list;
use crate::run::{duration, run_watching_signals};
use crate::sde_levels::SdeModel;

/// The Python model as the library's [`Level`]: `f(l, u)` gives the fine and coarse values
/// of a block as an `(n, 2)` array (the package's wrapper checks the user's `(fine,
/// coarse)`), and the coordinates and costs of each level come as tables.
struct PyLevel {
    model: Arc<PyIntegrand>,
    dims: Vec<usize>,
    costs: Vec<f64>,
    refinement: u32,
    weak_order: Option<f64>,
}

impl PyLevel {
    /// Entry `level` of a table (the last one past its end: the tables reach the deepest
    /// level the run may sample, so only the checkpoint fingerprint's look beyond a shallow
    /// `max_level` gets it).
    fn entry<T: Copy>(table: &[T], level: usize) -> T {
        table[level.min(table.len() - 1)]
    }
}

impl Level for PyLevel {
    fn refinement(&self) -> u32 {
        self.refinement
    }

    fn dims(&self, level: usize) -> usize {
        PyLevel::entry(&self.dims, level)
    }

    fn cost(&self, level: usize) -> f64 {
        PyLevel::entry(&self.costs, level)
    }

    fn weak_order(&self) -> Option<f64> {
        self.weak_order
    }

    fn sample(&self, level: usize, u: &[f64], _: &mut Vec<f64>) -> (f64, f64) {
        let (mut fine, mut coarse) = ([0.0], [0.0]);
        match Points::from_rows(&[u]) {
            Ok(point) => self.sample_block(level, &point, &mut fine, &mut coarse, &mut Vec::new()),
            Err(_) => return (f64::NAN, f64::NAN),
        }
        (fine[0], coarse[0])
    }

    fn sample_block(
        &self,
        level: usize,
        points: &Points,
        fine: &mut [f64],
        coarse: &mut [f64],
        _: &mut Vec<f64>,
    ) {
        let n = points.len();
        let mut out = vec![0.0; 2 * n];
        self.model.level_batch(level, points, &mut out);
        fine[..n].copy_from_slice(&out[..n]);
        coarse[..n].copy_from_slice(&out[n..]);
    }
}

/// A finished multilevel run.
#[pyclass(module = "mcint._native", frozen)]
pub struct MultilevelRun {
    run: MultilevelEstimate,
}

#[pymethods]
impl MultilevelRun {
    /// Everything the run reports, with the keys of the command line's `mlmc --json`
    /// (`levels` as dicts of each level's statistics).
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let r = &self.run;
        let d = PyDict::new(py);
        d.set_item("estimate", r.estimate)?;
        d.set_item("std_error", r.std_error)?;
        d.set_item("bias", r.bias)?;
        d.set_item("rmse", r.rmse)?;
        d.set_item("target", r.target)?;
        let levels = PyList::empty(py);
        for l in &r.levels {
            let item = PyDict::new(py);
            item.set_item("level", l.level)?;
            item.set_item("n", l.samples)?;
            item.set_item("mean", l.mean)?;
            item.set_item("variance", l.variance)?;
            item.set_item("std_error", l.std_error)?;
            item.set_item("cost", l.cost)?;
            item.set_item("fine_mean", l.fine_mean)?;
            item.set_item("fine_variance", l.fine_variance)?;
            item.set_item("kurtosis", l.kurtosis)?;
            item.set_item("check", l.consistency)?;
            levels.append(item)?;
        }
        d.set_item("levels", levels)?;
        d.set_item("alpha", r.alpha)?;
        d.set_item("beta", r.beta)?;
        d.set_item("gamma", r.gamma)?;
        d.set_item("refinement", r.refinement)?;
        d.set_item("cost", r.cost)?;
        d.set_item("standard_mc_cost", r.standard_mc_cost)?;
        d.set_item("replicates", r.replicates)?;
        d.set_item("stop", r.stop.name())?;
        d.set_item("converged", r.converged)?;
        d.set_item("warnings", warning_list(py, &r.warnings)?)?;
        Ok(d)
    }
}

/// The settings of a run (or, with `survey = (levels, samples)`, of Giles' `mlmc_test`
/// survey of levels `0..=levels`) that the Python model and the built-in SDE levels share.
struct RunSettings {
    rmse: Option<f64>,
    survey: Option<(usize, u64)>,
    qmc: bool,
    replicates: Option<u64>,
    initial_samples: Option<u64>,
    min_level: Option<usize>,
    max_level: Option<usize>,
    max_cost: Option<f64>,
    time_limit: Option<f64>,
    seed: u64,
    threads: Option<usize>,
}

impl RunSettings {
    /// The runner of `levels` with these settings, cancelled through `cancel`.
    fn runner<L: Level>(&self, levels: L, cancel: CancelToken) -> PyResult<Multilevel<L>> {
        let mut run = Multilevel::new(levels)
            .qmc(self.qmc)
            .seed(self.seed)
            .cancel_token(cancel);
        if let Some(eps) = self.rmse {
            run = run.rmse(eps);
        }
        if let Some(r) = self.replicates {
            run = run.replicates(r);
        }
        if let Some(n) = self.initial_samples {
            run = run.initial_samples(n);
        }
        if let Some(l) = self.min_level {
            run = run.min_level(l);
        }
        if let Some(l) = self.max_level {
            run = run.max_level(l);
        }
        if let Some(c) = self.max_cost {
            run = run.max_cost(c);
        }
        if let Some(t) = self.threads {
            run = run.threads(t);
        }
        if let Some(seconds) = self.time_limit {
            run = run.time_limit(duration(seconds)?);
        }
        Ok(run)
    }

    /// The run, or the survey, of `run`.
    fn outcome<L: Level>(&self, run: &Multilevel<L>) -> PyResult<MultilevelEstimate> {
        match self.survey {
            Some((levels, samples)) => run.survey(levels, samples),
            None => run.run(),
        }
        .map_err(non_finite_sample)
    }
}

/// Giles' multilevel algorithm on the Python model `level` to the RMSE target `rmse`, or,
/// with `survey = (levels, samples)`, his `mlmc_test` survey of levels `0..=levels`.
#[pyfunction]
#[pyo3(signature = (
    level, rmse, dims, costs, refinement, *, survey=None, weak_order=None, qmc=false,
    replicates=None, initial_samples=None, min_level=None, max_level=None, max_cost=None,
    time_limit=None, seed=0, threads=None
))]
#[allow(
    clippy::too_many_arguments,
    reason = "the keyword arguments of mcint.mlmc"
)]
pub fn mlmc(
    py: Python<'_>,
    level: Py<PyAny>,
    rmse: Option<f64>,
    dims: Vec<usize>,
    costs: Vec<f64>,
    refinement: u32,
    survey: Option<(usize, u64)>,
    weak_order: Option<f64>,
    qmc: bool,
    replicates: Option<u64>,
    initial_samples: Option<u64>,
    min_level: Option<usize>,
    max_level: Option<usize>,
    max_cost: Option<f64>,
    time_limit: Option<f64>,
    seed: u64,
    threads: Option<usize>,
) -> PyResult<MultilevelRun> {
    if dims.is_empty() || dims.len() != costs.len() {
        return Err(pyo3::exceptions::PyValueError::new_err(
            "dims and costs: expected one entry per level, from level 0",
        ));
    }
    let settings = RunSettings {
        rmse,
        survey,
        qmc,
        replicates,
        initial_samples,
        min_level,
        max_level,
        max_cost,
        time_limit,
        seed,
        threads,
    };
    let cancel = CancelToken::new();
    let model = Arc::new(PyIntegrand::new(level, 2, None, cancel.clone()));
    let levels = PyLevel {
        model: Arc::clone(&model),
        dims,
        costs,
        refinement,
        weak_order,
    };
    let run = settings.runner(levels, cancel)?;
    let outcome = run_watching_signals(py, model.failure(), || settings.outcome(&run));
    if let Some(error) = model.failure().take() {
        return Err(error);
    }
    Ok(MultilevelRun { run: outcome? })
}

/// [`mlmc`] on the library's built-in SDE levels: no call reaches Python.
#[pyfunction]
#[pyo3(signature = (
    levels, rmse, *, survey=None, qmc=false, replicates=None, initial_samples=None,
    min_level=None, max_level=None, max_cost=None, time_limit=None, seed=0, threads=None
))]
#[allow(
    clippy::too_many_arguments,
    reason = "the keyword arguments of mcint.mlmc"
)]
pub fn mlmc_sde(
    py: Python<'_>,
    levels: &SdeModel,
    rmse: Option<f64>,
    survey: Option<(usize, u64)>,
    qmc: bool,
    replicates: Option<u64>,
    initial_samples: Option<u64>,
    min_level: Option<usize>,
    max_level: Option<usize>,
    max_cost: Option<f64>,
    time_limit: Option<f64>,
    seed: u64,
    threads: Option<usize>,
) -> PyResult<MultilevelRun> {
    let settings = RunSettings {
        rmse,
        survey,
        qmc,
        replicates,
        initial_samples,
        min_level,
        max_level,
        max_cost,
        time_limit,
        seed,
        threads,
    };
    let cancel = CancelToken::new();
    let run = settings.runner(levels.levels()?, cancel.clone())?;
    let failure = Failure::new(cancel);
    let outcome = run_watching_signals(py, &failure, || settings.outcome(&run));
    if let Some(error) = failure.take() {
        return Err(error);
    }
    Ok(MultilevelRun { run: outcome? })
}

/// The library's error, with a non-finite sample a `FloatingPointError` as a non-finite
/// integrand value is for `integrate`; `samples` is a keyword of its own here (the survey's),
/// not the `n` of the point sets.
fn non_finite_sample(error: mcint::Error) -> PyErr {
    match &error {
        mcint::Error::InvalidParameter { name, .. } if *name == "level sample" => {
            PyFloatingPointError::new_err(error.to_string())
        }
        _ => to_py_naming(error, &[("samples", "samples")]),
    }
}
