//! First-order and total Sobol' sensitivity indices of a test model, from ONE vector-valued
//! randomized quasi-Monte Carlo run, with delta-method standard errors, next to the exact
//! values.
//!
//! ```text
//! cargo run --release --bin sensitivity -- --function ishigami|sobol-g [--dims D]
//!     [--n N] [--replicates R] [--seed S] [--time-limit SECONDS] [--json]
//! ```
//! `ishigami` is `sin x1 + 7 sin^2 x2 + 0.1 x3^4 sin x1` on `[-pi, pi]^3`; `sobol-g` is the
//! g-function on `[0, 1]^D` (default `D` = 6, at most 126) with the weights of Saltelli et al.
//! (2010), `a = (0, 0.5, 3, 9, 99, 99)` and 99 beyond. The run integrates the pick-freeze
//! design (`support/pick_freeze.rs`) over `--n` Owen-scrambled Sobol' points per replicate
//! (default 16384; powers of two keep the net balanced) in `--replicates` independent
//! scrambles (default 16, at least 2: the standard errors come from their spread).
//!
//! The integrator counts one evaluation per point for all outputs together; each point runs
//! the model `D + 2` times (`f(A)`, `f(B)` and `f(AB_i)` for every input), so the report gives
//! both: `evaluations` (points) and `model_evaluations` (`evaluations * (D + 2)`).
//!
//! `--json` prints one object: `function`, `dims`, `parameters`, `n` (points per replicate),
//! `replicates`, `seed`, `evaluations`, `model_evaluations`, `variance`, and `first_order`
//! and `total`, arrays with one `{"estimate", "std_error", "exact"}` object per input; and
//! `stop` (`budget`, or `time limit` when `--time-limit` stopped the run with the whole
//! replicates done by then) and `warnings`, as `integrate --json` has them. Warnings also go
//! to stderr.

use mcint::pdf::UniformBox;
use mcint::sampler::{Scramble, Sobol};
use mcint::stats::{Derived, StopReason, VectorEstimate, Warning};
use mcint::{Estimate, Integrator};
use mcint_cli::args as support;
use mcint_cli::pick_freeze;
use mcint_cli::sensitivity_models;
use mcint_cli::{note, say};
use pick_freeze::{MAX_INPUTS, PickFreeze};
use sensitivity_models::Model;
use support::Args;

const SPEC: support::Spec = &[
    ("function", true, "ishigami or sobol-g"),
    ("dims", true, "inputs of sobol-g"),
    (
        "n",
        true,
        "Owen-scrambled Sobol' points per replicate (default 16384)",
    ),
    support::REPLICATES,
    support::SEED,
    support::TIME_LIMIT,
    support::JSON,
];

/// What `--help` says before the list of flags.
fn usage() -> String {
    format!(
        "\
Sobol' sensitivity indices from one vector randomized-QMC run.

usage: sensitivity --function ishigami|sobol-g [--dims D] [--n N] [--replicates R]
                   [--seed S] [--json]

  --function     ishigami (3 inputs on [-pi, pi]^3, a = 7, b = 0.1) or
                 sobol-g (the g-function on [0, 1]^D, a = 0, 0.5, 3, 9, 99, 99, 99, ...)
  --dims D       inputs of sobol-g, 1 to {MAX_INPUTS} (default {DEFAULT_SOBOL_G_DIMS})
  --n N          Owen-scrambled Sobol' points per replicate (default {DEFAULT_POINTS}; use a
                 power of two)
  --replicates R independent scrambles, at least 2 (default {DEFAULT_REPLICATES})
  --seed S       seed of the scrambles (default 0)
  --json         one JSON object instead of the table
"
    )
}

const DEFAULT_POINTS: u64 = 1 << 14;
const DEFAULT_REPLICATES: u64 = 16;
const DEFAULT_SOBOL_G_DIMS: usize = 6;

fn main() {
    support::finish(run());
}

fn run() -> Result<(), String> {
    let args = Args::parse(&usage(), SPEC)?;
    let settings = Settings::from_args(&args)?;
    let report = analyse(settings)?;
    for warning in &report.warnings {
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
    seed: u64,
    deadline: Option<std::time::Instant>,
}

impl Settings {
    fn from_args(args: &Args) -> Result<Settings, String> {
        let name: String = args.require("function", "ishigami or sobol-g")?;
        let dims: Option<usize> = args.get("dims", "a whole number of inputs >= 1")?;
        let model = match (name.as_str(), dims) {
            ("ishigami", None) => Model::ishigami(),
            ("ishigami", Some(_)) => {
                return Err(
                    "--dims applies to --function sobol-g (ishigami has 3 inputs)".to_string(),
                );
            }
            ("sobol-g", dims) => {
                let d = dims.unwrap_or(DEFAULT_SOBOL_G_DIMS);
                if !(1..=MAX_INPUTS).contains(&d) {
                    return Err(format!(
                        "invalid --dims {d}: expected 1 to {MAX_INPUTS} inputs (the design \
                         needs 4 + 2 D outputs of one vector run)"
                    ));
                }
                Model::sobol_g(d)?
            }
            (other, _) => {
                return Err(format!(
                    "invalid --function '{other}': expected ishigami or sobol-g"
                ));
            }
        };
        let n = args
            .get("n", "a whole number of points per replicate >= 1")?
            .unwrap_or(DEFAULT_POINTS);
        if n == 0 {
            return Err(
                "invalid --n 0: expected a whole number of points per replicate >= 1 \
                 (a power of two such as 16384 keeps the Sobol' net balanced)"
                    .to_string(),
            );
        }
        let replicates = args
            .get("replicates", "a whole number of replicates >= 2")?
            .unwrap_or(DEFAULT_REPLICATES);
        if replicates < 2 {
            return Err(format!(
                "invalid --replicates {replicates}: expected a whole number >= 2 (the \
                 standard errors come from the spread between replicates)"
            ));
        }
        let seed = args.get("seed", "a whole number")?.unwrap_or(0);
        Ok(Settings {
            model,
            n,
            replicates,
            seed,
            deadline: args.deadline()?,
        })
    }
}

/// One index (or the variance): the estimate, its standard error and the exact value.
struct Row {
    estimate: f64,
    std_error: Option<f64>,
    exact: f64,
}

struct Report {
    settings: Settings,
    design: PickFreeze,
    evaluations: u64,
    stop: StopReason,
    variance: Row,
    first_order: Vec<Row>,
    total: Vec<Row>,
    warnings: Vec<Warning>,
}

/// Integrates the pick-freeze design of the model once and derives every index from it.
fn analyse(settings: Settings) -> Result<Report, String> {
    let design = PickFreeze {
        inputs: settings.model.dims(),
    };
    let model = settings.model.clone();
    // Over the unit cube: each contribution is the integrand itself (no box volume), and the
    // model maps the point into its own input box.
    let mut integrator = Integrator::over_box_vector(
        design.outputs(),
        design.integrand(move |u: &[f64]| model.eval_unit(u)),
        UniformBox::unit(design.point_dims()).map_err(|e| e.to_string())?,
    )
    .sampler(
        Sobol::new(design.point_dims(), Scramble::Owen, settings.seed)
            .map_err(|e| e.to_string())?,
    )
    .samples(settings.n)
    .replicates(settings.replicates)
    .seed(settings.seed);
    if let Some(deadline) = settings.deadline {
        integrator = integrator.deadline(deadline);
    }
    let run = integrator.run().map_err(|e| e.to_string())?;
    let exact = settings.model.exact();
    let row = |quantity: Derived, exact: f64| -> Result<Row, String> {
        let e: Estimate = run.derived(&quantity).map_err(|e| e.to_string())?;
        Ok(Row {
            estimate: e.mean,
            std_error: e.std_error,
            exact,
        })
    };
    let inputs = 0..design.inputs;
    Ok(Report {
        variance: row(design.variance(), exact.variance)?,
        first_order: inputs
            .clone()
            .map(|i| row(design.first_order(i), exact.first_order[i]))
            .collect::<Result<_, _>>()?,
        total: inputs
            .map(|i| row(design.total(i), exact.total[i]))
            .collect::<Result<_, _>>()?,
        evaluations: run.evaluations,
        stop: run.stop,
        warnings: distinct_warnings(&run),
        settings,
        design,
    })
}

/// The warnings of every output, each once (most apply to the run, so all outputs share them).
fn distinct_warnings(run: &VectorEstimate) -> Vec<Warning> {
    let mut distinct: Vec<Warning> = Vec::new();
    for warning in run.outputs.iter().flat_map(|o| &o.warnings) {
        if !distinct.contains(warning) {
            distinct.push(warning.clone());
        }
    }
    distinct
}

impl Report {
    fn model_evaluations(&self) -> u64 {
        self.evaluations
            .saturating_mul(self.design.model_runs_per_point())
    }

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
        serde_json::json!({
            "function": s.model.name(),
            "dims": self.design.inputs,
            "parameters": parameters,
            "n": s.n,
            "replicates": s.replicates,
            "seed": s.seed,
            "evaluations": self.evaluations,
            "model_evaluations": self.model_evaluations(),
            "stop": support::stop_name(self.stop),
            "variance": row(&self.variance),
            "first_order": self.first_order.iter().map(row).collect::<Vec<_>>(),
            "total": self.total.iter().map(row).collect::<Vec<_>>(),
            "warnings": self.warnings.iter().map(|w| serde_json::json!({
                "kind": w.kind(),
                "message": w.to_string(),
            })).collect::<Vec<_>>(),
        })
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
            self.design.inputs,
            parameters.join(", ")
        );
        say!(
            "design      pick-freeze over Owen-scrambled Sobol' points in {} dimensions, {} \
             replicates x {} points",
            self.design.point_dims(),
            s.replicates,
            s.n
        );
        say!(
            "cost        {} integrand evaluations = {} model evaluations ({} per point: f(A), \
             f(B) and f(AB_i) for each input)",
            self.evaluations,
            self.model_evaluations(),
            self.design.model_runs_per_point()
        );
        if self.stop != StopReason::Budget {
            say!(
                "stopped     early ({}): the indices use the whole replicates done by then",
                support::stop_name(self.stop)
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
