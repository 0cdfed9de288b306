//! First-order, total and (with `--second-order`) second-order Sobol' sensitivity indices
//! of a test model by the library's `mcint::sensitivity` design, with their standard errors,
//! next to the exact values.
//!
//! ```text
//! cargo run --release --bin sensitivity -- --function ishigami [--a A] [--b B]
//! cargo run --release --bin sensitivity -- --function sobol-g [--weights W1,W2,...|--dims D]
//!     [--n N] [--replicates R] [--second-order] [--tol-abs T [--max-evals N]] [--seed S]
//!     [--threads T] [--time-limit SECONDS] [--json] [--mpi]
//! ```
//! `ishigami` is `sin x1 + a sin^2 x2 + b x3^4 sin x1` on `[-pi, pi]^3` (default `a = 7`,
//! `b = 0.1`); `sobol-g` is the g-function on `[0, 1]^D` with the given weights, or with those
//! of Saltelli et al. (2010), `a = (0, 0.5, 3, 9, 99, 99)` and 99 beyond, on `--dims` inputs
//! (default 6). The run integrates the pick-freeze design over `--replicates` independent
//! LMS-scrambled Sobol' sequences (default 8; 1 gives one sequence, more accurate, with no
//! error bar) of `--n` points each (default 8192; powers of two keep each net balanced);
//! `--tol-abs T` instead runs until every index's 95% half-width is at most `T`, or until
//! `--max-evals` points of the design (default 2^30).
//!
//! The report gives `evaluations` (points) and `model_evaluations` (`evaluations` times the
//! model runs per point: `D + 2`, or `2 D + 2` with second order).
//!
//! `--json` prints one object: `function`, `dims`, `parameters`, `n` (points per replicate
//! of the first stage), `replicates`, `seed`, `evaluations`, `model_evaluations`,
//! `variance`, and `first_order` and `total`, arrays with one `{"estimate", "std_error",
//! "exact"}` object per input; with `--second-order`, `second_order`, one such object per pair
//! with its `inputs` (`[i, j]`, from 0); `ranks` (of the MPI job, 1 without `--mpi`);
//! `converged` (null without `--tol-abs`), `stop`, and `warnings`, as `integrate --json` has
//! them. Warnings also go to stderr.
//!
//! `--mpi` (a build with `--features mpi`, launched as `mpirun -n N .../sensitivity --mpi
//! ...`) spreads the run's chunks over the ranks; rank 0 prints the one-process result, bit
//! for bit.

use mcint::estimator::MAX_OUTPUTS;
use mcint::sensitivity::{Indices, SobolDesign};
use mcint::stats::StopReason;
use mcint::{Estimate, Tolerance};
use mcint_cli::args as support;
use mcint_cli::ranks::{Ranks, Spread};
use mcint_cli::sensitivity_models;
use mcint_cli::{note, say};
use sensitivity_models::Model;
use support::Args;

/// The most inputs whose `4 + 2 D` integrals fit in one vector run.
const MAX_INPUTS: usize = (MAX_OUTPUTS - 4) / 2;
/// The most inputs whose `4 + 2 D + D (D - 1) / 2` integrals (with second order) fit in one
/// vector run.
const MAX_SECOND_ORDER_INPUTS: usize = max_second_order_inputs();
// `--help` spells both limits out.
const _: () = assert!(MAX_INPUTS == 126 && MAX_SECOND_ORDER_INPUTS == 21);

const fn max_second_order_inputs() -> usize {
    let mut d = 1;
    while 4 + 2 * (d + 1) + (d + 1) * d / 2 <= MAX_OUTPUTS {
        d += 1;
    }
    d
}

const SPEC: support::Spec = &[
    (
        "function",
        true,
        "ishigami (3 inputs on [-pi, pi]^3) or sobol-g (the g-function on [0, 1]^D)",
    ),
    ("a", true, "Ishigami's a, a finite number (default 7)"),
    ("b", true, "Ishigami's b, a finite number (default 0.1)"),
    (
        "weights",
        true,
        "the g-function's weights W1,W2,..., one per input (1 to 126 inputs, 1 to 21 with \
         --second-order), each >= 0",
    ),
    (
        "dims",
        true,
        "sobol-g on D inputs with Saltelli's weights 0, 0.5, 3, 9, 99, 99, ... (1 to 126, or \
         1 to 21 with --second-order; default 6)",
    ),
    (
        "n",
        true,
        "Sobol' points per replicate, >= 1 (default 8192; use a power of two)",
    ),
    (
        "replicates",
        true,
        "independent LMS scrambles, >= 1 (default 8; 1 is one sequence: more accurate, no \
         error bar)",
    ),
    (
        "second-order",
        false,
        "also the second-order index of every pair of inputs (of at most 21 inputs)",
    ),
    (
        "tol-abs",
        true,
        "run until every index's 95% half-width is at most this, > 0 (--n is then the first \
         stage; needs --replicates >= 2)",
    ),
    (
        "max-evals",
        true,
        "limit of a run to --tol-abs, in points of the design as `evaluations` counts them \
         (default 2^30)",
    ),
    support::SEED,
    support::THREADS,
    support::TIME_LIMIT,
    support::JSON,
    (
        "mpi",
        false,
        "spread the run over the ranks of the MPI job (mpirun -n N; a build with --features \
         mpi); rank 0 prints the one-process result",
    ),
];

/// What `--help` says before the list of flags.
const ABOUT: &str = "Sobol' sensitivity indices of a test model next to their exact values, by \
                     the library's pick-freeze design (mcint::sensitivity).";

const ISHIGAMI_A: f64 = 7.0;
const ISHIGAMI_B: f64 = 0.1;
const DEFAULT_POINTS: u64 = 1 << 13;
const DEFAULT_REPLICATES: u64 = 8;
const DEFAULT_SOBOL_G_DIMS: usize = 6;

fn main() {
    support::finish(run());
}

fn run() -> Result<(), String> {
    let args = Args::parse(ABOUT, SPEC)?;
    let settings = Settings::from_args(&args)?;
    // Lives until the run ends: MPI stays up as long as it.
    let ranks = Ranks::new(args.has("mpi"))?;
    let report = analyse(settings, ranks.spread)?;
    if !ranks.spread.is_root() {
        return Ok(());
    }
    for warning in &report.indices.warnings {
        note!("warning: {warning}");
    }
    if args.has("json") {
        say!("{}", report.json());
    } else {
        report.print_table();
    }
    Ok(())
}

/// The command line, checked before any work is done.
struct Settings {
    model: Model,
    n: u64,
    replicates: u64,
    second_order: bool,
    tolerance: Option<f64>,
    max_evals: Option<u64>,
    seed: u64,
    threads: Option<usize>,
    deadline: Option<std::time::Instant>,
}

impl Settings {
    fn from_args(args: &Args) -> Result<Settings, String> {
        let name: String = args.require("function", "ishigami or sobol-g")?;
        let model = match name.as_str() {
            "ishigami" => ishigami(args)?,
            "sobol-g" => sobol_g(args)?,
            other => {
                return Err(format!(
                    "invalid --function = '{other}': expected ishigami or sobol-g"
                ));
            }
        };
        let n = args
            .get("n", "a whole number of points per replicate >= 1")?
            .unwrap_or(DEFAULT_POINTS);
        if n == 0 {
            return Err(
                "invalid --n = 0: expected a whole number of points per replicate >= 1 \
                 (a power of two such as 8192 keeps the Sobol' net balanced)"
                    .to_string(),
            );
        }
        let replicates = args
            .get("replicates", "a whole number of replicates >= 1")?
            .unwrap_or(DEFAULT_REPLICATES);
        if replicates == 0 {
            return Err(
                "invalid --replicates = 0: expected a whole number >= 1 (1 is one sequence \
                 with no error bar)"
                    .to_string(),
            );
        }
        let tolerance: Option<f64> = args.get("tol-abs", "a number > 0")?;
        if let Some(t) = tolerance {
            if !(t.is_finite() && t > 0.0) {
                return Err(format!("invalid --tol-abs = {t}: expected a number > 0"));
            }
            if replicates < 2 {
                return Err(
                    "--tol-abs needs --replicates >= 2: its stopping rule needs an error bar"
                        .to_string(),
                );
            }
        }
        let max_evals: Option<u64> = args.get("max-evals", "a whole number of points >= 1")?;
        if max_evals.is_some() && tolerance.is_none() {
            return Err("--max-evals limits a run to a tolerance: give --tol-abs too".into());
        }
        Ok(Settings {
            model,
            n,
            replicates,
            second_order: args.has("second-order"),
            tolerance,
            max_evals,
            seed: args.get("seed", "a whole number")?.unwrap_or(0),
            threads: args.get("threads", "a whole number of threads >= 1")?,
            deadline: args.deadline()?,
        })
    }
}

/// `--function ishigami` with `--a`, `--b`.
fn ishigami(args: &Args) -> Result<Model, String> {
    if args.given("weights") || args.given("dims") {
        return Err(
            "--dims and --weights apply to --function sobol-g (ishigami has 3 inputs and \
             parameters --a, --b)"
                .to_string(),
        );
    }
    let a: Option<f64> = args.get("a", "a finite number")?;
    let b: Option<f64> = args.get("b", "a finite number")?;
    Model::ishigami(a.unwrap_or(ISHIGAMI_A), b.unwrap_or(ISHIGAMI_B))
}

/// `--function sobol-g` with `--weights` or `--dims`.
fn sobol_g(args: &Args) -> Result<Model, String> {
    if args.given("a") || args.given("b") {
        return Err(
            "--a and --b apply to --function ishigami (sobol-g takes --weights)".to_string(),
        );
    }
    let dims: Option<usize> = args.get("dims", "a whole number of inputs >= 1")?;
    let model = match (args.list("weights")?, dims) {
        (Some(_), Some(_)) => {
            return Err(
                "give --weights or --dims, not both (--weights sets one weight per input)"
                    .to_string(),
            );
        }
        (Some(weights), None) => Model::sobol_g(weights)?,
        (None, dims) => {
            let d = dims.unwrap_or(DEFAULT_SOBOL_G_DIMS);
            if d == 0 {
                return Err(format!(
                    "invalid --dims = 0: expected 1 to {MAX_INPUTS} inputs"
                ));
            }
            Model::sobol_g_saltelli(d.min(MAX_INPUTS + 1))?
        }
    };
    let flag = if dims.is_some() {
        "--dims"
    } else {
        "--weights"
    };
    if model.dims() > MAX_INPUTS {
        return Err(format!(
            "invalid {flag} = {} inputs: expected 1 to {MAX_INPUTS} (the design needs 4 + 2 D \
             integrals of one vector run)",
            dims.unwrap_or(model.dims())
        ));
    }
    if args.has("second-order") && model.dims() > MAX_SECOND_ORDER_INPUTS {
        return Err(format!(
            "invalid {flag} = {} inputs: expected 1 to {MAX_SECOND_ORDER_INPUTS} with \
             --second-order (the design needs 4 + 2 D + D (D - 1) / 2 integrals of one vector \
             run, at most {MAX_OUTPUTS})",
            model.dims()
        ));
    }
    Ok(model)
}

/// One index (or the variance): the estimate, its standard error and the exact value.
struct Row {
    estimate: f64,
    std_error: Option<f64>,
    exact: f64,
}

struct Report {
    settings: Settings,
    /// Ranks of the MPI job the run was spread over (1 without `--mpi`).
    ranks: usize,
    runs_per_point: u64,
    indices: Indices,
    variance: Row,
    first_order: Vec<Row>,
    total: Vec<Row>,
    /// `(i, j, row)` for every pair, with `--second-order`.
    second_order: Vec<(usize, usize, Row)>,
}

/// Runs the library's design on the model and pairs every index with its exact value.
fn analyse(settings: Settings, spread: Spread) -> Result<Report, String> {
    // The design's points are `--n` per replicate times `--replicates`.
    let text = |e| support::spec_error(SPEC, &[("points", "--n x --replicates")], e);
    let mut design = SobolDesign::new(settings.model.inputs())
        .map_err(text)?
        .points(settings.n.checked_mul(settings.replicates).ok_or_else(|| {
            format!(
                "invalid --n = {}: expected --n x --replicates below 2^64 points",
                settings.n
            )
        })?)
        .replicates(settings.replicates)
        .second_order(settings.second_order);
    if let Some(t) = settings.tolerance {
        let mut tolerance = Tolerance::absolute(t).map_err(text)?;
        if let Some(limit) = settings.max_evals {
            tolerance = tolerance.max_evaluations(limit).map_err(text)?;
        }
        design = design.tolerance(tolerance);
    }
    let model = settings.model.clone();
    let mut integrator = design
        .integrator(move |x: &[f64]| model.eval(x))
        .map_err(text)?
        .seed(settings.seed);
    if let Some(deadline) = settings.deadline {
        integrator = integrator.deadline(deadline);
    }
    if let Some(threads) = settings.threads {
        integrator = integrator.threads(threads);
    }
    let run = mcint_cli::spread!(integrator, spread).run().map_err(text)?;
    let indices = design.indices(&run).map_err(text)?;
    let exact = settings.model.exact();
    let row = |e: &Estimate, exact: f64| Row {
        estimate: e.mean,
        std_error: e.std_error,
        exact,
    };
    let rows = |estimates: &[Estimate], exact: &[f64]| -> Vec<Row> {
        estimates
            .iter()
            .zip(exact)
            .map(|(e, x)| row(e, *x))
            .collect()
    };
    let output = &indices.outputs[0];
    Ok(Report {
        variance: row(&output.variance, exact.variance),
        first_order: rows(&output.first_order, &exact.first_order),
        total: rows(&output.total, &exact.total),
        second_order: output
            .second_order
            .iter()
            .map(|pair| {
                let (i, j) = pair.factors;
                let exact = settings.model.exact_second_order(i, j);
                (i, j, row(&pair.index, exact))
            })
            .collect(),
        runs_per_point: design.model_runs_per_point(),
        ranks: spread.size,
        indices,
        settings,
    })
}

impl Report {
    fn json(&self) -> serde_json::Value {
        let row = |r: &Row| {
            serde_json::json!({
                "estimate": r.estimate,
                "std_error": r.std_error,
                "exact": r.exact,
            })
        };
        let s = &self.settings;
        let parameters: serde_json::Map<String, serde_json::Value> = s
            .model
            .parameters()
            .into_iter()
            .map(|(name, values)| (name.to_string(), serde_json::json!(values)))
            .collect();
        let mut report = serde_json::json!({
            "function": s.model.name(),
            "dims": s.model.dims(),
            "parameters": parameters,
            "n": s.n,
            "replicates": s.replicates,
            "seed": s.seed,
            "ranks": self.ranks,
            "evaluations": self.indices.points,
            "model_evaluations": self.indices.model_evaluations,
            "converged": self.indices.converged,
            "stop": support::stop_name(self.indices.stop),
            "variance": row(&self.variance),
            "first_order": self.first_order.iter().map(row).collect::<Vec<_>>(),
            "total": self.total.iter().map(row).collect::<Vec<_>>(),
            "warnings": self.indices.warnings.iter().map(|w| serde_json::json!({
                "kind": w.kind(),
                "message": w.to_string(),
            })).collect::<Vec<_>>(),
        });
        if s.second_order {
            report["second_order"] = self
                .second_order
                .iter()
                .map(|(i, j, r)| {
                    let mut entry = row(r);
                    entry["inputs"] = serde_json::json!([i, j]);
                    entry
                })
                .collect::<Vec<_>>()
                .into();
        }
        report
    }

    fn print_table(&self) {
        let s = &self.settings;
        let parameters: Vec<String> = s
            .model
            .parameters()
            .into_iter()
            .map(|(name, values)| format!("{name} = {}", list(&values)))
            .collect();
        say!(
            "model       {} with {} inputs, {}",
            s.model.name(),
            s.model.dims(),
            parameters.join(", ")
        );
        say!(
            "design      pick-freeze over LMS-scrambled Sobol' points in {} dimensions, {} \
             replicates x {} points{}",
            2 * s.model.dims(),
            s.replicates,
            s.n,
            if s.tolerance.is_some() {
                " in the first stage"
            } else {
                ""
            }
        );
        say!(
            "cost        {} integrand evaluations = {} model evaluations ({} per point: f(A), \
             f(B) and the mixed inputs)",
            self.indices.points,
            self.indices.model_evaluations,
            self.runs_per_point
        );
        let stop = self.indices.stop;
        if let Some(t) = s.tolerance {
            if self.indices.converged == Some(true) {
                say!("tolerance   met: every index's 95% half-width is at most {t}");
            } else {
                say!(
                    "tolerance   {t} not met (stop: {})",
                    support::stop_name(stop)
                );
            }
        } else if stop != StopReason::Budget {
            say!(
                "stopped     early ({}): the indices use the whole replicates done by then",
                support::stop_name(stop)
            );
        }
        let v = &self.variance;
        say!(
            "variance    {:.6} (std error {}, exact {:.6})",
            v.estimate,
            std_error(v.std_error),
            v.exact
        );
        say!();
        say!(
            "{:<6} {:>10} {:>9} {:>10} {:>10} {:>9} {:>10}",
            "input",
            "S_i",
            "std err",
            "exact",
            "ST_i",
            "std err",
            "exact"
        );
        for (i, (first, total)) in self.first_order.iter().zip(&self.total).enumerate() {
            say!(
                "{:<6} {:>10.6} {:>9} {:>10.6} {:>10.6} {:>9} {:>10.6}",
                format!("x{}", i + 1),
                first.estimate,
                std_error(first.std_error),
                first.exact,
                total.estimate,
                std_error(total.std_error),
                total.exact
            );
        }
        if !self.second_order.is_empty() {
            say!();
            say!(
                "{:<6} {:>10} {:>9} {:>10}",
                "pair",
                "S_ij",
                "std err",
                "exact"
            );
            for (i, j, r) in &self.second_order {
                say!(
                    "{:<6} {:>10.6} {:>9} {:>10.6}",
                    format!("x{}x{}", i + 1, j + 1),
                    r.estimate,
                    std_error(r.std_error),
                    r.exact
                );
            }
        }
    }
}

/// A standard error in a table cell, `-` when there is none.
fn std_error(value: Option<f64>) -> String {
    value.map_or("-".to_string(), |se| format!("{se:.2e}"))
}

/// `7` or `(0, 0.5, 3)`.
fn list(values: &[f64]) -> String {
    let items: Vec<String> = values.iter().map(f64::to_string).collect();
    match items.as_slice() {
        [one] => one.clone(),
        _ => format!("({})", items.join(", ")),
    }
}
