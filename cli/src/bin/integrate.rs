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
//! A run that stops before its last chunk prints, with `--json`, `{"finished": false, "stop",
//! "chunks_done", "total_chunks"}` (`stop` is "stop after", "time limit" or "cancelled").
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
//! as `{"kind", "message"}` objects, empty when there are none, with the `output` they belong
//! to in a vector run (a tolerance not met with `--ratio I,J` is the ratio's: `"ratio": [I,
//! J]`, once).

use mcint::CancelToken;
use mcint::Method;
use mcint::estimator::Estimator;
use mcint::sampler::{Jittered, PassKind, SamplerKind, Scramble};
use mcint::stats::Tolerance;
use mcint::testfns::TestFunction;
use mcint_cli::args::{self as support, Args};
use mcint_cli::estimators::{self as genz_estimators, EstimatorKind};
use mcint_cli::integrands::{self, INTEGRAND_NAMES, Named};
use mcint_cli::methods::{self, METHOD_NAMES, Setup, parse_method};
use mcint_cli::report::Report;
use mcint_cli::{checkpoint, ranks};
use std::io::IsTerminal;
use std::sync::OnceLock;
use std::time::Instant;

/// Cancelled on SIGINT or SIGTERM: the run stops after its current chunks and reports what it
/// has (a checkpoint is saved first), and the process exits with status 130.
static CANCEL: OnceLock<CancelToken> = OnceLock::new();

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
            "invalid --dims = {dims}: expected at most {MAX_DIMS} (the families' exact values take \
             O(d) work per quadrature node, and VEGAS keeps grids of d x 1000 increments per \
             chunk)"
        ));
    }
    let functions = Named::parse_list(&args, &names, dims)?;
    let ratio = args
        .get::<String>("ratio", "two output indices I,J")?
        .map(|text| integrands::parse_ratio(&text, functions.len()))
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
        Some(name) => name.parse().map_err(support::flag_error)?,
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
            true => support::flag_error(e),
            false => format!(
                "{} (the sampler draws {canonical_dims} coordinates a point for --dims {dims} \
                 with --estimator {})",
                support::flag_error(e),
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
    let replicates: Option<u64> = args.get("replicates", "a whole number >= 1")?;
    let threads: Option<usize> = args.get("threads", "a whole number of threads >= 1")?;
    let default_replicates = method.default_replicates(&*sampler);
    let checkpoint = checkpoint_settings(&args, tolerance.is_some(), spread, deadline)?;
    if method.is_adaptive() && !vector && estimator_kind != EstimatorKind::Uniform {
        return Err(format!(
            "--estimator {} applies to --method plain and rqmc; {} adapts its own density (use \
             --estimator uniform)",
            estimator_kind.name(),
            method.name()
        ));
    }
    // The integrand's name in checkpoints: another family, parameters or estimator is
    // refused on resume.
    let label = if vector {
        let labels: Vec<String> = functions.iter().map(Named::label).collect();
        labels.join("; ")
    } else {
        format!("{} estimator {}", f.label(), estimator_kind.name())
    };
    let progress = progress_bar().filter(|_| spread.is_root() && !vector);
    let setup = Setup {
        method,
        functions: &functions,
        ratio,
        estimator: Some(built.estimator),
        sampler,
        n: n_flag,
        default_n: n,
        replicates,
        default_replicates,
        seed,
        threads,
        tolerance,
        label,
        deadline,
        cancel: cancel_token(),
        spread,
        progress: progress.map(|bar| Box::new(bar) as Box<dyn Fn(u64, u64) + Send + Sync>),
    };
    let started = Instant::now();
    let run = match checkpoint {
        None => methods::build(setup)?
            .run_vector()
            .map_err(support::flag_error)?,
        Some(settings) => {
            let integrator = methods::build_checkpointed(setup)?;
            match checkpoint::run(&*integrator, &settings, &cancel_token())? {
                Ok(run) => run,
                Err(unfinished) => {
                    // A script reading --json can tell a saved, unfinished run from a result.
                    if args.has("json") && spread.is_root() {
                        let json = serde_json::to_string(&unfinished).map_err(|e| e.to_string())?;
                        println!("{json}");
                    }
                    return Ok(());
                }
            }
        }
    };
    if !spread.is_root() {
        return Ok(());
    }
    Report {
        method,
        functions: &functions,
        sampler: kind.name(),
        scramble: scramble.name(),
        estimator: estimator_kind.name(),
        estimator_description: built.description,
        evaluations_per_contribution: built.evaluations_per_contribution,
        ratio,
        run,
        ranks: spread.size,
        seconds: started.elapsed().as_secs_f64(),
    }
    .print(args.has("json"))
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
            if args.given(flag) {
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
        return Err("invalid --save-every = 0: expected at least 1 chunk".into());
    }
    let stop_after = args.get("stop-after", "a whole number of chunks >= 1")?;
    if stop_after == Some(0) {
        return Err("invalid --stop-after = 0: expected at least 1 chunk".into());
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
    let mut tolerance = Tolerance::new(abs, rel).map_err(support::flag_error)?;
    if let Some(limit) = max_evals {
        tolerance = tolerance
            .max_evaluations(limit)
            .map_err(support::flag_error)?;
    }
    Ok(Some(tolerance))
}
