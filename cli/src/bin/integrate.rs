//! Integrates a Genz test family with a chosen sampler and reports the estimate, its honest
//! standard error and the exact value.
//!
//! ```text
//! cargo run --release --bin integrate -- --integrand NAME[,NAME..] --dims D [--ratio I,J]
//!     [--a a1,a2,..] [--u u1,u2,..]
//!     [--sampler NAME] [--scramble NAME] [--strength T] [--n N] [--replicates R] [--seed S]
//!     [--threads T] [--estimator uniform|importance|mis|control]
//!     [--method plain|rqmc|vegas|vegas-plus|miser|two-stage|sobol-g] [--tol-abs X] [--tol-rel X]
//!     [--max-evals N] [--checkpoint FILE [--save-every K] [--stop-after K]] [--json] [--mpi]
//! ```
//! NAME is `keister` (`cos|x| e^{-|x|^2}` over `R^D`, integrated after the normal transform to
//! the unit cube) or a Genz family: oscillatory, product-peak, corner-peak, gaussian,
//! continuous, discontinuous (`--genz` is a synonym of `--integrand`). Defaults: `a_i = 1 + 0.5 (i-1)`, `u_i = 0.2 + 0.6 (i-1)/(d-1)`, sampler
//! `independent`, `--n` (points per replicate) 65536 (for `jittered` the largest `k^d` not
//! above it), `--replicates` 1 for independent points or unscrambled sequences and 16
//! otherwise, `--scramble` the sampler's default (owen for sobol, permute for halton and
//! hammersley, shift for lattice). With `--scramble none` no standard error is reported.
//!
//! `--estimator` (default `uniform`) picks how points become contributions: `importance`
//! samples a product density shaped like the family (truncated normals for `gaussian`, exact;
//! piecewise-linear tables of the factors otherwise), `mis` combines one uniform point and
//! one proposal point with the balance heuristic, `control` subtracts the family's
//! least-squares linear part, fitted on a separate pilot run (A.27). The report gives the
//! variance per integrand evaluation, so the estimators can be compared at equal work.
//!
//! `--method` (default `plain`) picks the integrator: `plain` uses the sampler as given
//! (default `independent`); `rqmc` is randomized quasi-Monte Carlo, Owen-scrambled Sobol' by
//! default with 16 replicates (8 to start with in a run to a tolerance, which adds replicates
//! when that is cheaper than doubling their points); `vegas` and `vegas-plus` are VEGAS without and with adaptive
//! stratification (`--n` evaluations per iteration, default 10^4, after 5 warm-up
//! iterations; 10 iterations, or as many as a tolerance needs), `miser` is MISER (`--n`
//! evaluations per replicate, default 2^14, in `--replicates` independent runs, default 16),
//! `two-stage` is two-stage stratified sampling (`--n` evaluations in all, default 2^16, with as
//! many strata as 32 evaluations each afford; a fixed budget only). `sobol-g` doubles one
//! LMS-scrambled, digitally shifted Sobol' sequence (`--n` points first, default 1024, a power
//! of two) until a bound from the integrand's Walsh coefficients meets the tolerance (QMCPy's
//! `CubQMCSobolG`): its report has `error_bound` instead of a standard error. The other
//! adaptive methods take their uniform points from `--sampler` (default `independent`); all
//! accept only `--estimator uniform`. `--tol-abs` and/or `--tol-rel` make the run stop once the 95%
//! half-width is at most `max(tol-abs, tol-rel * |estimate|)` (then `--n` is the first stage:
//! the pilot for independent points, the first points per replicate otherwise), or at
//! `--max-evals` integrand evaluations (default 2^30). The report says whether the tolerance
//! was met and why the run stopped.
//!
//! `--checkpoint FILE` (plain and rqmc, fixed budget) saves the run's finished chunks of
//! 16384 points to FILE every `--save-every` chunks (default 16) and, when FILE exists,
//! resumes from it: however often it is stopped and restarted, the result has the same bits
//! as an uninterrupted run. `--stop-after K` stops after K chunks, as an interruption would.
//!
//! Several families (`--genz gaussian,oscillatory`) or `--ratio I,J` make one vector-valued run
//! over the same points (`--method plain`, `rqmc`, `vegas` or `vegas-plus`, `--estimator
//! uniform`): the report has every family's estimate and the covariance of the estimates, and
//! `--ratio` adds the ratio of outputs `I` and `J` (positions in the list, from 0) with its
//! delta-method error bar; a tolerance then applies to the ratio, otherwise to every output.
//!
//! `--mpi` (a build with `--features mpi`, launched as `mpirun -n N .../integrate --mpi ...`)
//! spreads the run over the job's ranks, each on its own `--threads`; the result has the same
//! bits as one process. Rank 0 prints it (`ranks` in the JSON) and writes the checkpoint,
//! which a job with another number of ranks resumes.
//!
//! Warnings about the estimate (points per replicate that break a net, a tolerance not met,
//! few replicates, skipped non-finite values, an error bar at the floating-point floor) go
//! to stderr, one `warning: ...` line each; `--json` also lists them in its `warnings` array
//! as `{"kind", "message"}` objects, empty when there are none.

#[path = "support/checkpoint.rs"]
mod checkpoint;
#[path = "support/genz_estimators.rs"]
mod genz_estimators;
#[path = "support/integrands.rs"]
mod integrands;
#[path = "support/methods.rs"]
mod methods;
#[path = "support/ranks.rs"]
mod ranks;
#[path = "support/mod.rs"]
mod support;
#[path = "support/vector_run.rs"]
mod vector_run;

use genz_estimators::EstimatorKind;
use integrands::{INTEGRAND_NAMES, Named};
use mcint::Method;
use mcint::estimator::Estimator;
use mcint::sampler::{Jittered, PassKind, SamplerKind, Scramble};
use mcint::stats::{StopReason, Tolerance};
use mcint::testfns::TestFunction;
use mcint::{CancelToken, Estimate, Integrator};
use methods::{AdaptiveRun, METHOD_NAMES, parse_method};
use std::io::IsTerminal;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;
use support::output::{note, say};
use support::{Args, stop_name};

/// Cancelled on SIGINT or SIGTERM: the run stops after its current chunks and reports what it
/// has (a checkpoint is saved first), and the process exits with status 130.
static CANCEL: OnceLock<CancelToken> = OnceLock::new();

/// Set on the ranks of an MPI job other than 0: they print nothing, not even the error that
/// rank 0 prints for all of them.
static QUIET: AtomicBool = AtomicBool::new(false);

/// What `--help` says the program does.
const ABOUT: &str = "Integrates Genz families or the Keister function with a chosen sampler and method; reports the estimate, its standard error and the exact value.";

const SPEC: support::Spec = &[
    (
        "integrand",
        true,
        "keister or Genz families (oscillatory, product-peak, corner-peak, gaussian, continuous, discontinuous), comma-separated for one vector run",
    ),
    ("genz", true, "synonym of --integrand"),
    support::DIMS,
    (
        "a",
        true,
        "Genz difficulty parameters a_1,a_2,.. (default 1 + 0.5 (i-1))",
    ),
    (
        "u",
        true,
        "Genz shift parameters u_1,u_2,.. (default 0.2 + 0.6 (i-1)/(d-1))",
    ),
    support::SAMPLER,
    support::SCRAMBLE,
    support::STRENGTH,
    (
        "n",
        true,
        "points per replicate (default 65536), evaluations per iteration (VEGAS), in all (two-stage) or of the first stage (sobol-g)",
    ),
    support::REPLICATES,
    support::SEED,
    support::THREADS,
    ("estimator", true, "uniform, importance, mis or control"),
    (
        "method",
        true,
        "plain, rqmc, vegas, vegas-plus, miser, two-stage or sobol-g",
    ),
    support::TOL_ABS,
    support::TOL_REL,
    support::MAX_EVALS,
    support::TIME_LIMIT,
    (
        "ratio",
        true,
        "I,J: also report the ratio of outputs I and J with a delta-method error bar",
    ),
    (
        "checkpoint",
        true,
        "save the run to FILE every few chunks and resume from it",
    ),
    (
        "save-every",
        true,
        "chunks between checkpoint saves (default 16)",
    ),
    (
        "stop-after",
        true,
        "stop after this many chunks, leaving the checkpoint",
    ),
    support::JSON,
    (
        "mpi",
        false,
        "spread the run over the ranks of the MPI job (mpirun; a build with --features mpi)",
    ),
];

const DEFAULT_POINTS: u64 = 1 << 16;

/// The most dimensions `--dims` takes: beyond, setting the test families up alone takes
/// seconds (the corner peak's exact value took 30 s in 10^7 dimensions).
const MAX_DIMS: usize = 1 << 17;

fn main() {
    let token = CANCEL.get_or_init(CancelToken::new).clone();
    // Without a handler (another already installed) a signal ends the process as usual.
    let _ = ctrlc::set_handler(move || token.cancel());
    let result = run();
    let cancelled = CANCEL.get().is_some_and(CancelToken::is_cancelled);
    if result.is_err() && QUIET.load(Ordering::Relaxed) {
        std::process::exit(2);
    }
    support::finish(result);
    if cancelled {
        std::process::exit(130);
    }
}

/// The run's cancellation token.
fn cancel_token() -> CancelToken {
    CANCEL.get_or_init(CancelToken::new).clone()
}

/// A progress bar on stderr when it is a terminal, told `(evaluations done, planned)`.
fn progress_bar() -> Option<impl Fn(u64, u64) + Send + Sync + 'static> {
    if !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} evaluations, {eta} left")
            .expect("a valid template"),
    );
    Some(move |done: u64, planned: u64| {
        if planned > 0 {
            bar.set_length(planned);
        }
        bar.set_position(done);
        if planned > 0 && done >= planned {
            bar.finish_and_clear();
        }
    })
}

fn run() -> Result<(), String> {
    let args = Args::parse(ABOUT, SPEC)?;
    let deadline = args.deadline()?;
    // Lives until the run ends: MPI stays up as long as it.
    let ranks = ranks::Ranks::new(args.has("mpi"))?;
    let spread = ranks.spread;
    QUIET.store(!spread.is_root(), Ordering::Relaxed);
    let names = match (
        args.get::<String>("integrand", INTEGRAND_NAMES)?,
        args.get::<String>("genz", INTEGRAND_NAMES)?,
    ) {
        (Some(_), Some(_)) => {
            return Err("--genz is a synonym of --integrand: give one of them".into());
        }
        (Some(names), None) | (None, Some(names)) => names,
        (None, None) => {
            return Err(format!(
                "missing --integrand: expected {INTEGRAND_NAMES}, or several separated by commas"
            ));
        }
    };
    let dims: usize = args.require("dims", "a whole number of dimensions >= 1")?;
    if dims > MAX_DIMS {
        return Err(format!(
            "invalid --dims {dims}: expected at most {MAX_DIMS} (the families' exact values take \
             O(d) work per quadrature node, and VEGAS keeps grids of d x 1000 increments per \
             chunk)"
        ));
    }
    let functions = Named::parse_list(&args, &names, dims)?;
    let ratio = args
        .get::<String>("ratio", "two output indices I,J")?
        .map(|text| vector_run::parse_ratio(&text, functions.len()))
        .transpose()?;
    let vector = functions.len() > 1 || ratio.is_some();
    let f = functions[0].clone();
    let estimator_kind: EstimatorKind = args
        .get::<String>("estimator", genz_estimators::ESTIMATOR_NAMES)?
        .map_or(Ok(EstimatorKind::Uniform), |name| name.parse())?;
    let seed: u64 = args.get("seed", "a whole number")?.unwrap_or(0);
    if vector && estimator_kind != EstimatorKind::Uniform {
        return Err(format!(
            "--estimator {} integrates one output; several integrands or --ratio take \
             --estimator uniform",
            estimator_kind.name()
        ));
    }
    let built = match f.genz() {
        Some(genz) => genz_estimators::build(estimator_kind, genz, seed)?,
        None if estimator_kind == EstimatorKind::Uniform => genz_estimators::uniform(&f)?,
        None => {
            return Err(format!(
                "--estimator {} is built for the Genz families; {} takes --estimator uniform",
                estimator_kind.name(),
                f.name()
            ));
        }
    };
    // The sampler feeds the estimator's canonical points (two per dimension for mis).
    let canonical_dims = built.estimator.canonical_dims();
    let method: Method = args
        .get::<String>("method", METHOD_NAMES)?
        .map_or(Ok(Method::Plain), |name| parse_method(&name))?;
    let kind: SamplerKind = match args.get::<String>("sampler", "a sampler name")? {
        Some(name) => name.parse().map_err(|e: mcint::Error| e.to_string())?,
        None => method.default_sampler(),
    };
    let tolerance = tolerance_from(&args)?;
    let n_flag = args.get::<u64>("n", "a whole number of points >= 1")?;
    let n = match n_flag {
        Some(n) => n,
        None if kind == SamplerKind::Jittered => {
            Jittered::points_not_above(canonical_dims, DEFAULT_POINTS)
        }
        None => DEFAULT_POINTS,
    };
    let scramble = if method == Method::SobolG {
        let given = |name| args.get::<String>(name, "").map(|value| value.is_some());
        if kind != SamplerKind::Sobol || given("scramble")? || given("strength")? {
            return Err(
                "--method sobol-g draws its own LMS-scrambled, digitally shifted Sobol' \
                 sequence: leave out --sampler (or give sobol), --scramble and --strength"
                    .into(),
            );
        }
        Scramble::Lms
    } else {
        args.scramble_for(kind)?
    };
    let strength: Option<u32> = args.get("strength", "a whole number >= 1 (oa-bush)")?;
    let sampler = kind
        .build_with(canonical_dims, n, scramble, strength, seed)
        .map_err(|e| match canonical_dims == dims {
            true => e.to_string(),
            false => format!(
                "{e} (the sampler draws {canonical_dims} coordinates a point for --dims {dims} \
                 with --estimator {})",
                estimator_kind.name()
            ),
        })?;
    let independent = sampler.passes() == PassKind::Independent;
    if method == Method::Rqmc && (independent || !sampler.is_randomized()) {
        return Err(format!(
            "--method rqmc needs a randomized quasi-Monte Carlo or stratified sampler, not {} \
             with scramble {scramble} (for example --sampler sobol --scramble owen)",
            kind.name()
        ));
    }
    let replicates_flag: Option<u64> = args.get("replicates", "a whole number >= 1")?;
    let threads: Option<usize> = args.get("threads", "a whole number of threads >= 1")?;
    let default_replicates = method.default_replicates(&*sampler);
    let checkpoint = checkpoint_settings(&args, tolerance.is_some(), spread, deadline)?;
    let started = Instant::now();
    if vector {
        let label = functions
            .iter()
            .map(Named::label)
            .collect::<Vec<_>>()
            .join("; ");
        let scramble_name = scramble.name().to_string();
        let Some(run) = vector_run::run(vector_run::VectorRunArgs {
            method,
            functions: &functions,
            sampler,
            samples: (tolerance.is_none() || n_flag.is_some()).then_some(n),
            replicates: replicates_flag,
            default_replicates,
            seed,
            threads,
            tolerance,
            ratio,
            label,
            checkpoint,
            cancel: cancel_token(),
            deadline,
            spread,
        })?
        else {
            return Ok(());
        };
        if !spread.is_root() {
            return Ok(());
        }
        let report = vector_run::VectorReport {
            method: method.name(),
            functions: &functions,
            sampler: kind.name().to_string(),
            scramble: scramble_name,
            run,
            ratio,
            ranks: spread.size,
            seconds: started.elapsed().as_secs_f64(),
        };
        for warning in report.warnings() {
            note!("warning: {warning}");
        }
        return if args.has("json") {
            report.print_json()
        } else {
            report.print_text()
        };
    }
    let estimate = if method.is_adaptive() {
        if checkpoint.is_some() {
            return Err(format!(
                "--checkpoint applies to --method plain and rqmc, not {}",
                method.name()
            ));
        }
        if estimator_kind != EstimatorKind::Uniform {
            return Err(format!(
                "--estimator {} applies to --method plain and rqmc; {} adapts its own \
                 density (use --estimator uniform)",
                estimator_kind.name(),
                method.name()
            ));
        }
        AdaptiveRun {
            method,
            f: &f,
            sampler,
            n: n_flag,
            replicates: replicates_flag,
            tolerance,
            seed,
            threads,
            cancel: cancel_token(),
            deadline,
            spread,
        }
        .run()?
    } else {
        // The integrand's name in checkpoints: another family, parameters or estimator is
        // refused on resume.
        let label = format!("{} estimator {}", f.label(), estimator_kind.name());
        let mut integrator = Integrator::new(built.estimator)
            .sampler(sampler)
            .seed(seed)
            .label(label)
            .cancel_token(cancel_token());
        if spread.is_root()
            && let Some(bar) = progress_bar()
        {
            integrator = integrator.progress(bar);
        }
        let mut integrator = ranks::spread!(integrator, spread);
        // With a tolerance the run picks its own first stage and replicates unless --n and
        // --replicates say otherwise.
        if tolerance.is_none() || n_flag.is_some() {
            integrator = integrator.samples(n);
        }
        if tolerance.is_none() || replicates_flag.is_some() {
            integrator = integrator.replicates(replicates_flag.unwrap_or(default_replicates));
        }
        if let Some(t) = threads {
            integrator = integrator.threads(t);
        }
        if let Some(tolerance) = tolerance {
            integrator = integrator.tolerance(tolerance);
        }
        if let Some(deadline) = deadline {
            integrator = integrator.deadline(deadline);
        }
        match checkpoint {
            None => integrator.run().map_err(|e| e.to_string())?,
            Some(settings) => match checkpoint::run(&integrator, &settings, &cancel_token())? {
                Some(estimate) => estimate,
                None => return Ok(()),
            },
        }
    };
    let seconds = started.elapsed().as_secs_f64();
    if !spread.is_root() {
        return Ok(());
    }
    let report = Report {
        method,
        family: f.name(),
        dims,
        kind,
        scramble,
        estimator: estimator_kind,
        estimator_description: built.description,
        evaluations_per_contribution: built.evaluations_per_contribution,
        estimate,
        exact: f.exact(),
        ranks: spread.size,
        seconds,
    };
    for warning in &report.estimate.warnings {
        note!("warning: {warning}");
    }
    if args.has("json") {
        report.print_json()
    } else {
        report.print_text()
    }
    Ok(())
}

/// `--checkpoint FILE [--save-every K] [--stop-after K]`, if given (fixed budgets only).
fn checkpoint_settings(
    args: &Args,
    to_tolerance: bool,
    spread: ranks::Spread,
    deadline: Option<std::time::Instant>,
) -> Result<Option<checkpoint::Settings>, String> {
    let Some(path) = args.get::<String>("checkpoint", "a file path")? else {
        for flag in ["save-every", "stop-after"] {
            if args.get::<String>(flag, "")?.is_some() {
                return Err(format!(
                    "--{flag} applies to a run with --checkpoint FILE (give one, or leave out \
                     --{flag})"
                ));
            }
        }
        return Ok(None);
    };
    if to_tolerance {
        return Err("--checkpoint applies to fixed-budget runs, not to runs to a tolerance".into());
    }
    let save_every = args
        .get("save-every", "a whole number of chunks >= 1")?
        .unwrap_or(checkpoint::DEFAULT_SAVE_EVERY);
    if save_every == 0 {
        return Err("invalid --save-every 0: expected at least 1 chunk".into());
    }
    let stop_after = args.get("stop-after", "a whole number of chunks >= 1")?;
    if stop_after == Some(0) {
        return Err("invalid --stop-after 0: expected at least 1 chunk".into());
    }
    Ok(Some(checkpoint::Settings {
        path: path.into(),
        save_every,
        stop_after,
        deadline,
        spread,
    }))
}

/// The tolerance of `--tol-abs`, `--tol-rel` and `--max-evals`, if one was asked for.
fn tolerance_from(args: &Args) -> Result<Option<Tolerance>, String> {
    let abs: Option<f64> = args.get("tol-abs", "a positive number")?;
    let rel: Option<f64> = args.get("tol-rel", "a positive number")?;
    let max_evals: Option<u64> = args.get("max-evals", "a whole number of evaluations")?;
    if abs.is_none() && rel.is_none() {
        return match max_evals {
            Some(_) => Err(
                "--max-evals limits a run to a tolerance: give --tol-abs or \
                            --tol-rel too (or --n for a fixed number of points)"
                    .into(),
            ),
            None => Ok(None),
        };
    }
    let mut tolerance = Tolerance::new(abs, rel).map_err(|e| e.to_string())?;
    if let Some(limit) = max_evals {
        tolerance = tolerance
            .max_evaluations(limit)
            .map_err(|e| e.to_string())?;
    }
    Ok(Some(tolerance))
}

struct Report {
    method: Method,
    family: String,
    dims: usize,
    kind: SamplerKind,
    scramble: mcint::sampler::Scramble,
    estimator: EstimatorKind,
    estimator_description: String,
    evaluations_per_contribution: u64,
    estimate: Estimate,
    exact: f64,
    /// MPI ranks the run was spread over (1 without `--mpi`).
    ranks: usize,
    seconds: f64,
}

impl Report {
    /// The variance of the estimate times the number of integrand evaluations it took: the
    /// variance of a one-evaluation estimate, comparable across estimators at equal work.
    fn variance_per_evaluation(&self) -> Option<f64> {
        let e = &self.estimate;
        e.std_error
            .map(|se| se * se * (e.n * self.evaluations_per_contribution) as f64)
    }

    fn print_json(&self) {
        let e = &self.estimate;
        let number = |v: Option<f64>| v.filter(|v| v.is_finite());
        let json = serde_json::json!({
            "method": self.method.name(),
            "family": self.family,
            "dims": self.dims,
            "sampler": self.kind.name(),
            "scramble": self.scramble.name(),
            "estimator": self.estimator.name(),
            "estimate": number(Some(e.mean)),
            "std_error": number(e.std_error),
            "error_bound": number(e.error_bound),
            "variance_per_evaluation": number(self.variance_per_evaluation()),
            "exact": number(Some(self.exact)),
            "n": e.n,
            "replicates": e.replicates,
            "evaluations": e.evaluations,
            "converged": e.converged,
            "stop": stop_name(e.stop),
            "iterations": e.iterations,
            "chi2_dof": number(e.chi2_dof),
            "rounding_error": number(Some(e.rounding_error)),
            "warnings": e.warnings.iter().map(|w| serde_json::json!({
                "kind": w.kind(),
                "message": w.to_string(),
            })).collect::<Vec<_>>(),
            "ranks": self.ranks,
            "seconds": number(Some(self.seconds)),
        });
        say!("{json}");
    }

    fn print_text(&self) {
        let e = &self.estimate;
        let error = (e.mean - self.exact).abs();
        say!(
            "integrand   {}{} in {} dimensions",
            if self.family == "keister" {
                ""
            } else {
                "genz "
            },
            self.family,
            self.dims
        );
        say!("method      {}", self.method.name());
        let layout = if matches!(self.method, Method::Vegas | Method::VegasPlus) {
            format!("{} iterations combined, {} points", e.iterations, e.n)
        } else if self.method == Method::SobolG {
            let plural = if e.iterations == 1 { "" } else { "s" };
            format!(
                "one sequence, {} points in {} stage{plural}",
                e.n, e.iterations
            )
        } else {
            format!(
                "{} replicates x {} points",
                e.replicates,
                e.n / e.replicates
            )
        };
        say!(
            "sampler     {}, scramble {} ({layout})",
            self.kind,
            self.scramble
        );
        say!(
            "estimator   {}: {}",
            self.estimator.name(),
            self.estimator_description
        );
        say!("estimate    {:.12e}", e.mean);
        say!("exact       {:.12e}", self.exact);
        if let Some(bound) = e.error_bound {
            say!("error bound {bound:.3e} (from the Walsh coefficients; no confidence level)");
            say!("|error|     {error:.3e}");
        }
        match (e.std_error, e.confidence_interval(0.95)) {
            (Some(se), Ok(Some((lo, hi)))) => {
                say!("std error   {se:.3e} ({:?})", e.basis);
                if let Some(v) = self.variance_per_evaluation() {
                    say!("var/eval    {v:.3e} (variance x integrand evaluations)");
                }
                say!("95% CI      [{lo:.12e}, {hi:.12e}]");
                say!(
                    "|error|     {error:.3e} = {:.2} standard errors",
                    error / se
                );
            }
            _ if e.error_bound.is_some() => {}
            _ => {
                say!(
                    "std error   none (a single point, or one replicate of dependent points, has \
                     no honest error bar)"
                );
                say!("|error|     {error:.3e}");
            }
        }
        if e.converged.is_none() && matches!(e.stop, StopReason::TimeLimit | StopReason::Cancelled)
        {
            say!(
                "stopped     early ({}) after {} evaluations",
                stop_name(e.stop),
                e.evaluations
            );
        }
        if let Some(converged) = e.converged {
            say!(
                "tolerance   {} ({}, {} stage{}, {} evaluations in all)",
                if converged { "met" } else { "NOT met" },
                stop_name(e.stop),
                e.iterations,
                if e.iterations == 1 { "" } else { "s" },
                e.evaluations
            );
        }
        if let Some(chi2) = e.chi2_dof {
            say!(
                "chi2/dof    {chi2:.2} over {} iterations (Q = {:.2})",
                e.iterations,
                e.q_value.unwrap_or(f64::NAN)
            );
        }
        if self.ranks > 1 {
            say!("ranks       {} MPI processes", self.ranks);
        }
        say!("time        {:.3} s", self.seconds);
    }
}
