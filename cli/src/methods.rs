//! The one place where `integrate` chooses its method: every method of the library's
//! [`Method`], on one output or several, is built here as a [`Run`] (or, for a checkpointed
//! run, as a [`Checkpointed`] Integrator) from the command line's settings.

use std::time::Instant;

use mcint::adaptive::{Miser, SobolG, TwoStage, Vegas, strata_per_axis_for};
use mcint::estimator::Estimator;
use mcint::pdf::UniformBox;
use mcint::sampler::Sampler;
use mcint::stats::{Derived, Tolerance};
use mcint::testfns::TestFunction;
use mcint::{CancelToken, Integrator, Method, Run};

use crate::checkpoint::{Checkpointed, VectorCheckpoint};
use crate::integrands::Named;
use crate::ranks::Spread;

/// The names `--method` accepts (the library's [`Method`]s).
pub const METHOD_NAMES: &str = "plain, rqmc, vegas, vegas-plus, miser, two-stage or sobol-g";

/// Iterations allowed to a VEGAS run to a tolerance: its evaluation limit stops it first.
const VEGAS_ITERATIONS_TO_TOLERANCE: u64 = 1 << 20;

/// Evaluations of a two-stage run when `--n` is not given (pilot included).
const DEFAULT_TWO_STAGE_EVALUATIONS: u64 = 1 << 16;

/// `--method NAME`, with the flag's own message for an unknown name.
pub fn parse_method(name: &str) -> Result<Method, String> {
    name.parse()
        .map_err(|_| format!("unknown --method '{name}': expected {METHOD_NAMES}"))
}

/// What a run takes from the command line.
pub struct Setup<'a> {
    pub method: Method,
    /// The integrands: one, or several for one vector run over the same points.
    pub functions: &'a [Named],
    /// `--ratio I,J`: the tolerance of a vector run applies to this ratio of outputs.
    pub ratio: Option<(usize, usize)>,
    /// The estimator of a scalar plain or rqmc run.
    pub estimator: Option<Box<dyn Estimator>>,
    pub sampler: Box<dyn Sampler>,
    /// `--n`: points per replicate (plain, rqmc; of the first stage with a tolerance),
    /// evaluations per iteration (VEGAS), per replicate (MISER), in all (two-stage) or of the
    /// first stage (sobol-g).
    pub n: Option<u64>,
    /// Points per replicate of a plain or rqmc run without `--n`.
    pub default_n: u64,
    pub replicates: Option<u64>,
    pub default_replicates: u64,
    pub seed: u64,
    pub threads: Option<usize>,
    pub tolerance: Option<Tolerance>,
    /// The integrand's name in checkpoints.
    pub label: String,
    pub deadline: Option<Instant>,
    pub cancel: CancelToken,
    pub spread: Spread,
    /// A progress bar for a scalar plain or rqmc run.
    pub progress: Option<Box<dyn Fn(u64, u64) + Send + Sync>>,
}

/// The settings every runner takes the same way, applied to `$runner`.
macro_rules! common {
    ($runner:expr, $setup:expr) => {{
        let mut runner = $runner
            .sampler($setup.sampler)
            .seed($setup.seed)
            .cancel_token($setup.cancel.clone());
        if let Some(t) = $setup.threads {
            runner = runner.threads(t);
        }
        if let Some(deadline) = $setup.deadline {
            runner = runner.deadline(deadline);
        }
        crate::spread!(runner, $setup.spread)
    }};
}

/// The run `setup` asks for, any method, on one output or several.
pub fn build<'a>(setup: Setup<'a>) -> Result<Box<dyn Run + 'a>, String> {
    let vector = setup.functions.len() > 1 || setup.ratio.is_some();
    match setup.method {
        Method::Plain | Method::Rqmc if vector => Ok(Box::new(vector_integrator(setup)?)),
        Method::Plain | Method::Rqmc => Ok(Box::new(scalar_integrator(setup)?)),
        Method::Vegas | Method::VegasPlus => vegas(setup, vector),
        Method::Miser | Method::TwoStage | Method::SobolG if vector => Err(format!(
            "--method {} integrates one output; several integrands or --ratio take --method \
             plain, rqmc, vegas or vegas-plus",
            setup.method
        )),
        Method::Miser | Method::TwoStage | Method::SobolG => adaptive(setup),
    }
}

/// The Integrator of a plain or rqmc run, to run from a checkpoint.
pub fn build_checkpointed<'a>(setup: Setup<'a>) -> Result<Box<dyn Checkpointed + 'a>, String> {
    if setup.method.is_adaptive() {
        return Err(format!(
            "--checkpoint applies to --method plain and rqmc, not {}",
            setup.method.name()
        ));
    }
    if setup.functions.len() > 1 || setup.ratio.is_some() {
        Ok(Box::new(VectorCheckpoint(vector_integrator(setup)?)))
    } else {
        Ok(Box::new(scalar_integrator(setup)?))
    }
}

/// The Integrator of one output, with the estimator `--estimator` chose.
fn scalar_integrator(mut setup: Setup<'_>) -> Result<Integrator<Box<dyn Estimator>>, String> {
    let estimator = setup
        .estimator
        .take()
        .ok_or("a scalar plain or rqmc run needs its estimator")?;
    let (n, replicates, tolerance) = integrator_budget(&setup);
    let mut integrator = Integrator::new(estimator).label(setup.label.clone());
    if let Some(bar) = setup.progress.take() {
        integrator = integrator.progress(bar);
    }
    let mut integrator = common!(integrator, setup);
    if let Some(n) = n {
        integrator = integrator.samples(n);
    }
    if let Some(r) = replicates {
        integrator = integrator.replicates(r);
    }
    if let Some(t) = tolerance {
        integrator = integrator.tolerance(t);
    }
    Ok(integrator)
}

/// The Integrator of every output together, over the same points; with `--ratio`, a
/// tolerance applies to the ratio (the quantity asked for), otherwise to every output.
fn vector_integrator<'a>(
    setup: Setup<'a>,
) -> Result<Integrator<mcint::VectorRun<impl mcint::estimator::VectorEstimator + 'a>>, String> {
    let functions = setup.functions;
    let (n, replicates, tolerance) = integrator_budget(&setup);
    let integrand = move |x: &[f64], out: &mut [f64]| evaluate_all(functions, x, out);
    let cube = UniformBox::unit(functions[0].dims()).map_err(crate::args::flag_error)?;
    let integrator =
        Integrator::over_box_vector(functions.len(), integrand, cube).label(setup.label.clone());
    let ratio = setup.ratio;
    let mut integrator = common!(integrator, setup);
    if let Some(n) = n {
        integrator = integrator.samples(n);
    }
    if let Some(r) = replicates {
        integrator = integrator.replicates(r);
    }
    match (tolerance, ratio) {
        (Some(t), Some((i, j))) => {
            integrator = integrator.derived_tolerance(Derived::ratio(i, j), t)
        }
        (Some(t), None) => integrator = integrator.tolerance(t),
        (None, _) => {}
    }
    Ok(integrator)
}

/// Points per replicate, replicates and tolerance of an Integrator run: with a tolerance the
/// run picks its own first stage and replicates unless `--n` and `--replicates` say
/// otherwise.
fn integrator_budget(setup: &Setup<'_>) -> (Option<u64>, Option<u64>, Option<Tolerance>) {
    let fixed = setup.tolerance.is_none();
    let n = setup.n.or(fixed.then_some(setup.default_n));
    let replicates = setup
        .replicates
        .or(fixed.then_some(setup.default_replicates));
    (n, replicates, setup.tolerance)
}

/// VEGAS or VEGAS+, on one output or several (`--n` evaluations per iteration).
fn vegas<'a>(setup: Setup<'a>, vector: bool) -> Result<Box<dyn Run + 'a>, String> {
    if setup.replicates.is_some() {
        return Err(format!(
            "--replicates does not apply to --method {} (its error bar combines iterations)",
            setup.method.name()
        ));
    }
    let functions = setup.functions;
    let cube = UniformBox::unit(functions[0].dims()).map_err(crate::args::flag_error)?;
    let stratified = setup.method == Method::VegasPlus;
    let (n, tolerance, ratio) = (setup.n, setup.tolerance, setup.ratio);
    if vector {
        let integrand = move |x: &[f64], out: &mut [f64]| evaluate_all(functions, x, out);
        let vegas = Vegas::new_vector(functions.len(), integrand, cube).stratified(stratified);
        let mut vegas = common!(vegas, setup);
        if let Some(n) = n {
            vegas = vegas.samples(n);
        }
        vegas = match (tolerance, ratio) {
            (Some(t), Some((i, j))) => vegas.derived_tolerance(Derived::ratio(i, j), t),
            (Some(t), None) => vegas.tolerance(t),
            (None, _) => vegas,
        };
        if tolerance.is_some() {
            vegas = vegas.iterations(VEGAS_ITERATIONS_TO_TOLERANCE);
        }
        return Ok(Box::new(vegas));
    }
    let f = &functions[0];
    let vegas = Vegas::new(move |x: &[f64]| f.eval(x), cube).stratified(stratified);
    let mut vegas = common!(vegas, setup);
    if let Some(n) = n {
        vegas = vegas.samples(n);
    }
    if let Some(t) = tolerance {
        vegas = vegas.tolerance(t).iterations(VEGAS_ITERATIONS_TO_TOLERANCE);
    }
    Ok(Box::new(vegas))
}

/// MISER, two-stage sampling or sobol-g, on one output.
fn adaptive<'a>(setup: Setup<'a>) -> Result<Box<dyn Run + 'a>, String> {
    let f = &setup.functions[0];
    let integrand = move |x: &[f64]| f.eval(x);
    let domain = UniformBox::unit(f.dims()).map_err(crate::args::flag_error)?;
    let (n, replicates, tolerance) = (setup.n, setup.replicates, setup.tolerance);
    match setup.method {
        Method::Miser => {
            let mut miser = common!(Miser::new(integrand, domain), setup);
            if let Some(n) = n {
                miser = miser.samples(n);
            }
            if let Some(r) = replicates {
                miser = miser.replicates(r);
            }
            if let Some(t) = tolerance {
                miser = miser.tolerance(t);
            }
            Ok(Box::new(miser))
        }
        Method::TwoStage => {
            if replicates.is_some() || tolerance.is_some() {
                return Err(
                    "--method two-stage takes a fixed budget (--n evaluations), without \
                     --replicates or a tolerance"
                        .into(),
                );
            }
            let n = n.unwrap_or(DEFAULT_TWO_STAGE_EVALUATIONS);
            let strata = strata_per_axis_for(f.dims(), n);
            let two_stage = TwoStage::new(integrand, domain, strata).samples(n);
            Ok(Box::new(common!(two_stage, setup)))
        }
        _ => {
            if replicates.is_some() {
                return Err(
                    "--replicates does not apply to --method sobol-g (one sequence, its error \
                     bound from Walsh coefficients)"
                        .into(),
                );
            }
            // The batch form: Genz families evaluate blocks with vectorized exp and cos.
            let batch = move |points: &mcint::Points, out: &mut [f64]| f.eval_batch(points, out);
            // SobolG draws its own sequence: the command line refuses another sampler.
            let mut sobol_g = SobolG::new_batch(batch, domain)
                .seed(setup.seed)
                .cancel_token(setup.cancel.clone());
            if let Some(t) = setup.threads {
                sobol_g = sobol_g.threads(t);
            }
            if let Some(deadline) = setup.deadline {
                sobol_g = sobol_g.deadline(deadline);
            }
            let mut sobol_g = crate::spread!(sobol_g, setup.spread);
            if let Some(n) = n {
                sobol_g = sobol_g.samples(n);
            }
            if let Some(t) = tolerance {
                sobol_g = sobol_g.tolerance(t);
            }
            Ok(Box::new(sobol_g))
        }
    }
}

/// Every function at `x`, output `k` from function `k`.
fn evaluate_all(functions: &[Named], x: &[f64], out: &mut [f64]) {
    for (y, f) in out.iter_mut().zip(functions) {
        *y = f.eval(x);
    }
}
