//! `integrate_box`: every method of the library over a box, with a Python integrand, run on
//! a worker thread while the calling thread watches for Ctrl-C.

use std::sync::{Arc, mpsc};
use std::time::Duration;

use mcint::adaptive::{Miser, SobolG, TwoStage, Vegas, strata_per_axis_for};
use mcint::estimator::{BatchUniformEstimator, BatchVectorUniformEstimator};
use mcint::pdf::UniformBox;
use mcint::sampler::{PassKind, Sampler, SamplerKind};
use mcint::stats::{Derived, Tolerance};
use mcint::{CancelToken, Integrator, Method, Pdf, Run};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::to_py;
use crate::failure::Failure;
use crate::integrand::PyIntegrand;
use crate::measure::MeasureSpec;
use crate::result::RunResult;

/// Points per replicate of a plain or rqmc run given neither `n` nor a tolerance (as the
/// command line's `integrate`).
const DEFAULT_POINTS: u64 = 1 << 16;

/// Evaluations of a two-stage run without `n` (as the command line).
const DEFAULT_TWO_STAGE_EVALUATIONS: u64 = 1 << 16;

/// Iterations allowed to a VEGAS run to a tolerance: its evaluation limit stops it first.
const VEGAS_ITERATIONS_TO_TOLERANCE: u64 = 1 << 20;

/// Points per call of a Python integrand in plain and rqmc runs: each call costs some
/// microseconds of interpreter overhead, which larger calls spread (the sums, and so the bits,
/// do not depend on it).
const POINTS_PER_CALL: usize = 8192;

/// How often the calling thread looks for a pending signal (Ctrl-C) while a run goes on.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// What a run takes from `mcint.integrate`.
struct Settings {
    method: Method,
    domain: UniformBox,
    outputs: usize,
    sampler: Option<Box<dyn Sampler>>,
    n: Option<u64>,
    replicates: Option<u64>,
    tolerance: Option<Tolerance>,
    ratio: Option<(usize, usize)>,
    time_limit: Option<Duration>,
    seed: u64,
    threads: Option<usize>,
    cancel: CancelToken,
}

/// The settings every runner takes the same way.
macro_rules! common {
    ($runner:expr, $s:expr) => {{
        let mut runner = $runner.seed($s.seed).cancel_token($s.cancel.clone());
        if let Some(t) = $s.threads {
            runner = runner.threads(t);
        }
        if let Some(limit) = $s.time_limit {
            runner = runner.time_limit(limit);
        }
        runner
    }};
}

/// Integrates `f` (see [`PyIntegrand`]) over the box `[lower, upper)` by `method`, or, with
/// a `measure`, averages it over the measure (its canonical cube integrated).
#[pyfunction]
#[pyo3(signature = (
    f, lower, upper, outputs, method, *, n=None, replicates=None, rtol=None, atol=None,
    max_evals=None, time_limit=None, seed=0, threads=None, sampler=None, scramble=None,
    ratio=None, measure=None
))]
#[allow(
    clippy::too_many_arguments,
    reason = "the keyword arguments of mcint.integrate"
)]
pub fn integrate_box(
    py: Python<'_>,
    f: Py<PyAny>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    outputs: usize,
    method: &str,
    n: Option<u64>,
    replicates: Option<u64>,
    rtol: Option<f64>,
    atol: Option<f64>,
    max_evals: Option<u64>,
    time_limit: Option<f64>,
    seed: u64,
    threads: Option<usize>,
    sampler: Option<&str>,
    scramble: Option<&str>,
    ratio: Option<(usize, usize)>,
    measure: Option<PyRef<'_, MeasureSpec>>,
) -> PyResult<RunResult> {
    let method: Method = method.parse().map_err(to_py)?;
    let measure = measure.map(|m| Arc::clone(&m.measure));
    // An expectation integrates over the measure's canonical cube.
    let domain = match &measure {
        Some(_) if method.is_adaptive() => {
            return Err(PyValueError::new_err(format!(
                "an expectation over a measure takes method 'rqmc' or 'plain', not '{method}'"
            )));
        }
        Some(m) => UniformBox::unit(m.canonical_dims()),
        None => UniformBox::new(lower, upper),
    }
    .map_err(to_py)?;
    let tolerance = tolerance(rtol, atol, max_evals, "n points per replicate")?;
    let time_limit = time_limit.map(duration).transpose()?;
    if let Some((i, j)) = ratio
        && (i >= outputs || j >= outputs || i == j)
    {
        return Err(PyValueError::new_err(format!(
            "invalid ratio = ({i}, {j}): expected two different outputs below {outputs}"
        )));
    }
    let sampler = build_sampler(method, domain.dims(), n, sampler, scramble, seed)?;
    let cancel = CancelToken::new();
    let settings = Settings {
        method,
        domain,
        outputs,
        sampler,
        n,
        replicates,
        tolerance,
        ratio,
        time_limit,
        seed,
        threads,
        cancel: cancel.clone(),
    };
    let integrand = PyIntegrand::new(f, outputs, measure, cancel);
    let outcome = run_watching_signals(py, integrand.failure(), || {
        build(settings, &integrand).and_then(|run| run.run_vector().map_err(to_py))
    });
    if let Some(error) = integrand.failure().take() {
        return Err(error);
    }
    let run = outcome?;
    let ratio = match ratio {
        Some((i, j)) => Some((i, j, run.derived(&Derived::ratio(i, j)).map_err(to_py)?)),
        None => None,
    };
    Ok(RunResult::new(run, ratio))
}

/// The tolerance of the keywords `rtol`, `atol` and `max_evals` (`None` without `rtol` and
/// `atol`, where `max_evals` is refused: a fixed run spends `fixed`).
pub fn tolerance(
    rtol: Option<f64>,
    atol: Option<f64>,
    max_evals: Option<u64>,
    fixed: &str,
) -> PyResult<Option<Tolerance>> {
    match (rtol.or(atol), max_evals) {
        (None, None) => Ok(None),
        (None, Some(_)) => Err(PyValueError::new_err(format!(
            "max_evals limits a run to a tolerance: give rtol or atol with it (a fixed run \
             spends {fixed})"
        ))),
        (Some(_), limit) => {
            let tolerance = Tolerance::new(atol, rtol).map_err(to_py)?;
            match limit {
                Some(m) => Ok(Some(tolerance.max_evaluations(m).map_err(to_py)?)),
                None => Ok(Some(tolerance)),
            }
        }
    }
}

/// `time_limit` seconds as a duration: finite and above 0 (a limit longer than a
/// `Duration` holds is none, a shorter one than a nanosecond is one nanosecond).
pub fn duration(seconds: f64) -> PyResult<Duration> {
    if !(seconds.is_finite() && seconds > 0.0) {
        return Err(PyValueError::new_err(format!(
            "invalid time_limit = {seconds:e}: expected a number of seconds above 0"
        )));
    }
    let limit = Duration::try_from_secs_f64(seconds).unwrap_or(Duration::MAX);
    Ok(limit.max(Duration::from_nanos(1)))
}

/// The sampler `sampler` and `scramble` name: for plain and rqmc runs always (the method's
/// default when not named), for the adaptive methods only when named (they draw their own
/// uniform points otherwise).
fn build_sampler(
    method: Method,
    dims: usize,
    n: Option<u64>,
    name: Option<&str>,
    scramble: Option<&str>,
    seed: u64,
) -> PyResult<Option<Box<dyn Sampler>>> {
    if method == Method::SobolG && (name.is_some() || scramble.is_some()) {
        return Err(PyValueError::new_err(
            "method 'sobol-g' draws its own LMS-scrambled, digitally shifted Sobol' sequence: \
             leave out sampler and scramble",
        ));
    }
    if method.is_adaptive() && name.is_none() {
        if scramble.is_some() {
            return Err(PyValueError::new_err(
                "scramble applies to a sampler: name one with sampler=...",
            ));
        }
        return Ok(None);
    }
    let kind: SamplerKind = match name {
        Some(name) => name.parse().map_err(to_py)?,
        None => method.default_sampler(),
    };
    let scramble = match scramble {
        Some(name) => name.parse().map_err(to_py)?,
        None => kind.default_scramble(),
    };
    let size = n.unwrap_or(DEFAULT_POINTS);
    let sampler = kind
        .build_scrambled(dims, size, scramble, seed)
        .map_err(to_py)?;
    let independent = sampler.passes() == PassKind::Independent;
    if method == Method::Rqmc && (independent || !sampler.is_randomized()) {
        return Err(PyValueError::new_err(format!(
            "method 'rqmc' needs a randomized quasi-Monte Carlo or stratified sampler, not {} \
             with scramble {} (for example sampler='sobol', scramble='owen')",
            kind.name(),
            scramble.name()
        )));
    }
    Ok(Some(sampler))
}

/// Runs `job` on a worker thread; the calling thread waits with the interpreter's lock
/// released and, between waits, takes it to look for a signal: a `KeyboardInterrupt` is the
/// run's `failure` (it cancels the run, which stops within a chunk, and is raised by the
/// caller once the worker has finished).
///
/// A run started by an integrand (on a worker of the library's pools) runs on that worker,
/// with the lock released: its chunks then share the outer run's threads, as nested runs do
/// in Rust (on a thread of its own it would wait for pool threads that are all inside the
/// outer run's integrand, waiting for it). The outer run's caller watches the signals.
pub fn run_watching_signals<T: Send>(
    py: Python<'_>,
    failure: &Failure,
    job: impl FnOnce() -> PyResult<T> + Send,
) -> PyResult<T> {
    if rayon::current_thread_index().is_some() {
        return py.detach(job);
    }
    std::thread::scope(|scope| {
        let (done, finished) = mpsc::channel();
        // Waited on with the lock released, which needs a shareable receiver.
        let finished = std::sync::Mutex::new(finished);
        let worker = scope.spawn(move || {
            // The worker keeps a Python thread state for the whole run (released, so the
            // caller can take the lock): each call of f then only takes the lock, instead of
            // creating and destroying a thread state, which cost about 40 us a call.
            let result = Python::attach(|py| py.detach(job));
            // The receiver only goes away once this thread is joined.
            let _ = done.send(());
            result
        });
        loop {
            let waited = py.detach(|| {
                let finished = finished.lock().unwrap_or_else(|e| e.into_inner());
                finished.recv_timeout(SIGNAL_POLL)
            });
            if waited != Err(mpsc::RecvTimeoutError::Timeout) {
                break;
            }
            if let Err(interrupt) = py.check_signals() {
                failure.fail(interrupt);
            }
        }
        match py.detach(|| worker.join()) {
            Ok(result) => result,
            Err(panic) => std::panic::resume_unwind(panic),
        }
    })
}

/// The runner of `s.method` over `integrand`.
fn build<'a>(mut s: Settings, integrand: &'a PyIntegrand) -> PyResult<Box<dyn Run + 'a>> {
    let domain = s.domain.clone();
    let vector = s.outputs > 1;
    let refuse = |what: &str| Err(PyValueError::new_err(what.to_string()));
    match s.method {
        Method::Plain | Method::Rqmc => {
            let (n, replicates) = match s.tolerance {
                None => (
                    Some(s.n.unwrap_or(DEFAULT_POINTS)),
                    s.replicates.or_else(|| {
                        let sampler = s.sampler.as_deref()?;
                        Some(s.method.default_replicates(sampler))
                    }),
                ),
                Some(_) => (s.n, s.replicates),
            };
            if vector {
                let f = move |p: &mcint::Points, out: &mut [f64]| integrand.batch(p, out);
                let estimator = BatchVectorUniformEstimator::new(s.outputs, f, domain)
                    .with_points_per_call(POINTS_PER_CALL)
                    .map_err(to_py)?;
                let mut run = common!(Integrator::new_vector(estimator), s);
                if let Some(sampler) = s.sampler.take() {
                    run = run.sampler(sampler);
                }
                run = budget(run, n, replicates);
                run = match (s.tolerance, s.ratio) {
                    (Some(t), Some((i, j))) => run.derived_tolerance(Derived::ratio(i, j), t),
                    (Some(t), None) => run.tolerance(t),
                    (None, _) => run,
                };
                Ok(Box::new(run))
            } else {
                let f = move |p: &mcint::Points, out: &mut [f64]| integrand.batch(p, out);
                let estimator = BatchUniformEstimator::new(f, domain)
                    .with_points_per_call(POINTS_PER_CALL)
                    .map_err(to_py)?;
                let mut run = common!(Integrator::new(estimator), s);
                if let Some(sampler) = s.sampler.take() {
                    run = run.sampler(sampler);
                }
                run = budget(run, n, replicates);
                if let Some(t) = s.tolerance {
                    run = run.tolerance(t);
                }
                Ok(Box::new(run))
            }
        }
        Method::Vegas | Method::VegasPlus => {
            if s.replicates.is_some() {
                return refuse(
                    "replicates does not apply to VEGAS (its error bar combines iterations)",
                );
            }
            // By blocks, one output or several: one Python call per block of points.
            let f = move |p: &mcint::Points, out: &mut [f64]| integrand.batch(p, out);
            let mut run = common!(Vegas::new_batch(s.outputs, f, domain), s)
                .stratified(s.method == Method::VegasPlus);
            if let Some(sampler) = s.sampler.take() {
                run = run.sampler(sampler);
            }
            if let Some(n) = s.n {
                run = run.samples(n);
            }
            run = match (s.tolerance, s.ratio) {
                (Some(t), Some((i, j))) => run.derived_tolerance(Derived::ratio(i, j), t),
                (Some(t), None) => run.tolerance(t),
                (None, _) => run,
            };
            if s.tolerance.is_some() {
                run = run.iterations(VEGAS_ITERATIONS_TO_TOLERANCE);
            }
            Ok(Box::new(run))
        }
        _ if vector || s.ratio.is_some() => refuse(&format!(
            "method '{}' integrates one output; several outputs or a ratio take method \
             'plain', 'rqmc', 'vegas' or 'vegas-plus'",
            s.method
        )),
        Method::Miser => {
            // By blocks: one Python call per exploration or leaf (up to 4,096 points).
            let f = move |p: &mcint::Points, out: &mut [f64]| integrand.batch(p, out);
            let mut run = common!(Miser::new_batch(f, domain), s);
            if let Some(sampler) = s.sampler.take() {
                run = run.sampler(sampler);
            }
            if let Some(n) = s.n {
                run = run.samples(n);
            }
            if let Some(r) = s.replicates {
                run = run.replicates(r);
            }
            if let Some(t) = s.tolerance {
                run = run.tolerance(t);
            }
            Ok(Box::new(run))
        }
        Method::TwoStage => {
            if s.replicates.is_some() || s.tolerance.is_some() {
                return refuse(
                    "method 'two-stage' takes a fixed budget (n evaluations), without \
                     replicates or a tolerance",
                );
            }
            let n = s.n.unwrap_or(DEFAULT_TWO_STAGE_EVALUATIONS);
            let strata = strata_per_axis_for(domain.dims(), n);
            // By blocks that gather many strata: one Python call per 4,096 points.
            let f = move |p: &mcint::Points, out: &mut [f64]| integrand.batch(p, out);
            let mut run = common!(TwoStage::new_batch(f, domain, strata).samples(n), s);
            if let Some(sampler) = s.sampler.take() {
                run = run.sampler(sampler);
            }
            Ok(Box::new(run))
        }
        _ => {
            if s.replicates.is_some() {
                return refuse(
                    "replicates does not apply to method 'sobol-g' (one sequence, its error \
                     bound from Walsh coefficients)",
                );
            }
            let f = move |p: &mcint::Points, out: &mut [f64]| integrand.batch(p, out);
            let mut run = common!(SobolG::new_batch(f, domain), s);
            if let Some(n) = s.n {
                run = run.samples(n);
            }
            if let Some(t) = s.tolerance {
                run = run.tolerance(t);
            }
            Ok(Box::new(run))
        }
    }
}

/// Points per replicate and replicates of an Integrator run, where given.
fn budget<E: mcint::Integration>(
    mut run: Integrator<E>,
    n: Option<u64>,
    replicates: Option<u64>,
) -> Integrator<E> {
    if let Some(n) = n {
        run = run.samples(n);
    }
    if let Some(r) = replicates {
        run = run.replicates(r);
    }
    run
}
