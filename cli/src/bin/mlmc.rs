//! Multilevel Monte Carlo (and multilevel QMC) for an option on an SDE path, to a
//! root-mean-square error target, by the library's `mcint::multilevel`; with `--test`, Giles'
//! `mlmc_test` survey of the levels first.
//!
//! ```text
//! cargo run --release --bin mlmc -- [--model gbm|heston] [--payoff european|asian|lookback|digital|barrier]
//!     [--scheme euler|milstein] [--eps E] [--min-level L] [--max-level L] [--max-cost C] [--qmc] [--test]
//!     [--plot FILE] [--json] ...
//! ```
//! `gbm` is `dS = r S dt + sigma S dW` (`--s0`, `--rate`, `--sigma`); `heston` replaces
//! `sigma` by the root of the variance `dv = kappa (theta - v) dt + xi sqrt(v) dW_2` with
//! correlation `rho` (`--v0`, `--kappa`, `--theta`, `--xi`, `--rho`; Euler with full
//! truncation). A flag of the other model is refused. The payoff is
//! discounted by `exp(-r T)`; the barrier is a down-and-out call at `--barrier`.
//!
//! `--test` first samples `--test-samples` paths of every level up to `--test-levels` and
//! prints, per level, the means and variances of `P_l` and `P_l - P_{l-1}`, the cost, the
//! kurtosis and the consistency check, with the fitted `alpha`, `beta` and `gamma`.
//!
//! `--json` prints one object: `model`, `payoff`, `scheme`, `eps`, `qmc`, `seed`, `estimate`,
//! `std_error`, `bias`, `rmse`, `exact` (the Black-Scholes value where there is one, else
//! null), `levels` (objects with `level`, `n`, `mean`, `variance`, `cost`, `fine_mean`,
//! `fine_variance`, `kurtosis`, `check`), `alpha`, `beta`, `gamma`, `refinement`, `cost`,
//! `standard_mc_cost`, `converged`, `stop`, `warnings` (objects with `kind` and `message`, as
//! `integrate --json` lists them), `ranks`, and with `--test`, `test`
//! (the survey, as an object with `levels`, `alpha`, `beta`, `gamma`).
//!
//! `--checkpoint FILE` resumes the run saved in FILE (if it exists) and saves its state there
//! when it stops (down to the chunk of samples it stopped at): a run cut by `--time-limit` or
//! Ctrl-C continues when the same command is run again, and ends with the bits of an
//! uninterrupted run. A checkpoint of other flags, or an altered one, is refused.
//!
//! `--plot FILE` (`.svg` or `.png`) draws `log2 |mean|` and `log2 variance` of `P_l` and
//! `P_l - P_{l-1}` against the level (of the survey with `--test`, else of the run).

use std::path::PathBuf;

use mcint::multilevel::{Multilevel, MultilevelEstimate, Payoff, Scheme, Sde, SdeLevels};
use mcint_cli::args::{self as support, Args};
use mcint_cli::checkpoint;
use mcint_cli::output::decimals;
use mcint_cli::plot;
use mcint_cli::ranks::Ranks;
use mcint_cli::{note, say};

const SPEC: support::Spec = &[
    ("model", true, "gbm or heston (default gbm)"),
    (
        "payoff",
        true,
        "european, asian (arithmetic average), lookback (floating strike), digital or \
         barrier (down-and-out call) (default european)",
    ),
    (
        "scheme",
        true,
        "euler or milstein (default milstein for gbm, euler for heston)",
    ),
    (
        "eps",
        true,
        "the root-mean-square error target, > 0 (default 0.01)",
    ),
    (
        "qmc",
        false,
        "multilevel QMC: 32 Owen-scrambled Sobol' sequences per level",
    ),
    (
        "refinement",
        true,
        "the refinement factor M between levels, 2 to 16 (default 2)",
    ),
    ("s0", true, "the initial price, > 0 (default 100)"),
    ("strike", true, "the strike (default 100)"),
    (
        "barrier",
        true,
        "the barrier of the down-and-out call (default 85)",
    ),
    ("rate", true, "the risk-free rate (default 0.05)"),
    ("sigma", true, "the volatility of gbm, >= 0 (default 0.2)"),
    ("maturity", true, "the maturity T in years, > 0 (default 1)"),
    ("v0", true, "heston's initial variance, >= 0 (default 0.04)"),
    ("kappa", true, "heston's mean reversion, >= 0 (default 2)"),
    (
        "theta",
        true,
        "heston's long-run variance, >= 0 (default 0.04)",
    ),
    (
        "xi",
        true,
        "heston's volatility of variance, >= 0 (default 0.3)",
    ),
    (
        "rho",
        true,
        "heston's correlation, in [-1, 1] (default -0.7)",
    ),
    (
        "min-level",
        true,
        "levels 0 to this are sampled from the start, Giles' Lmin, >= 1 (default 2)",
    ),
    (
        "max-level",
        true,
        "the deepest level allowed, Giles' Lmax, up to 60 (default 20)",
    ),
    (
        "max-cost",
        true,
        "the most a run may spend, in time steps of fine plus coarse paths (default 1e12); a \
         run stops before an iteration that would pass it, with its estimate so far",
    ),
    (
        "test",
        false,
        "first print Giles' mlmc_test survey of the levels",
    ),
    (
        "test-levels",
        true,
        "the deepest level of the survey, 1 to 20 (default 8)",
    ),
    (
        "test-samples",
        true,
        "samples per level of the survey, >= 2 (default 100000)",
    ),
    (
        "plot",
        true,
        "draw the level decays into this .svg or .png file",
    ),
    (
        "checkpoint",
        true,
        "save the run's state to this file when it stops, and resume from it if it exists \
         (with --time-limit: run the same command again to continue)",
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

const ABOUT: &str = "Multilevel Monte Carlo (Giles 2008) for an option on an SDE path, to a \
                     root-mean-square error target, by the library's mcint::multilevel.";

fn main() {
    support::finish(run());
}

/// The checked command line.
struct Settings {
    model: String,
    payoff: String,
    scheme: Scheme,
    eps: f64,
    s0: f64,
    strike: f64,
    rate: f64,
    sigma: f64,
    maturity: f64,
    seed: u64,
    test: Option<(usize, u64)>,
}

fn run() -> Result<(), String> {
    let args = Args::parse(ABOUT, SPEC)?;
    let text = |e| support::spec_error(SPEC, &[], e);
    let get = |name: &str, default: f64, what: &str| -> Result<f64, String> {
        Ok(args.get(name, what)?.unwrap_or(default))
    };
    let model: String = args.get("model", "gbm or heston")?.unwrap_or("gbm".into());
    let payoff_name: String = args
        .get("payoff", "european, asian, lookback, digital or barrier")?
        .unwrap_or("european".into());
    let default_scheme = if model == "heston" {
        "euler"
    } else {
        "milstein"
    };
    let scheme: Scheme = args
        .get::<String>("scheme", "euler or milstein")?
        .unwrap_or(default_scheme.into())
        .parse()
        .map_err(text)?;
    let eps = get("eps", 0.01, "a number > 0")?;
    if !(eps.is_finite() && eps > 0.0) {
        return Err(format!("invalid --eps = {eps}: expected a number > 0"));
    }
    let s0 = get("s0", 100.0, "a price > 0")?;
    let strike = get("strike", 100.0, "a finite price")?;
    let barrier = get("barrier", 85.0, "a finite price")?;
    let rate = get("rate", 0.05, "a finite rate")?;
    // A flag of the other model would be ignored: refused, so that no run silently prices
    // another model than the one the user described.
    let other_models_flags: &[&str] = match model.as_str() {
        "gbm" => &["v0", "kappa", "theta", "xi", "rho"],
        "heston" => &["sigma"],
        _ => &[],
    };
    if let Some(flag) = other_models_flags.iter().find(|f| args.given(f)) {
        return Err(format!(
            "--{flag} does not apply to --model {model}: gbm takes --sigma; heston takes --v0, \
             --kappa, --theta, --xi and --rho"
        ));
    }
    let sigma = get("sigma", 0.2, "a volatility >= 0")?;
    let maturity = get("maturity", 1.0, "a time > 0")?;
    let sde = match model.as_str() {
        "gbm" => Sde::gbm(s0, rate, sigma),
        "heston" => Sde::heston(
            s0,
            get("v0", 0.04, "a variance >= 0")?,
            rate,
            get("kappa", 2.0, "a rate >= 0")?,
            get("theta", 0.04, "a variance >= 0")?,
            get("xi", 0.3, "a number >= 0")?,
            get("rho", -0.7, "a correlation in [-1, 1]")?,
        ),
        other => {
            return Err(format!(
                "invalid --model = '{other}': expected gbm or heston"
            ));
        }
    }
    .map_err(text)?;
    let payoff = match payoff_name.as_str() {
        "european" => Payoff::european_call(strike),
        "asian" => Payoff::asian_call(strike),
        "lookback" => Ok(Payoff::lookback()),
        "digital" => Payoff::digital_call(strike),
        "barrier" => Payoff::down_and_out_call(strike, barrier),
        other => {
            return Err(format!(
                "invalid --payoff = '{other}': expected european, asian, lookback, digital or \
                 barrier"
            ));
        }
    }
    .map_err(text)?;
    let refinement: u32 = args
        .get("refinement", "a whole number 2 to 16")?
        .unwrap_or(2);
    let levels = SdeLevels::new(sde, scheme, payoff, maturity)
        .map_err(text)?
        .refinement_factor(refinement)
        .map_err(text)?
        .discount((-rate * maturity).exp())
        .map_err(|_| {
            format!(
                "invalid --rate = {rate} with --maturity = {maturity}: expected a finite \
                 discount exp(-rate * maturity)"
            )
        })?;
    let deepest: usize = args
        .get("test-levels", "a whole number 1 to 20")?
        .unwrap_or(8);
    if !(1..=20).contains(&deepest) {
        return Err(format!(
            "invalid --test-levels = {deepest}: expected 1 to 20"
        ));
    }
    let samples: u64 = args
        .get("test-samples", "a whole number >= 2")?
        .unwrap_or(100_000);
    if samples < 2 {
        return Err(format!(
            "invalid --test-samples = {samples}: expected a whole number >= 2"
        ));
    }
    let test = args.has("test").then_some((deepest, samples));
    let settings = Settings {
        model,
        payoff: payoff_name,
        scheme,
        eps,
        s0,
        strike,
        rate,
        sigma,
        maturity,
        seed: args.get("seed", "a whole number")?.unwrap_or(0),
        test,
    };
    let ranks = Ranks::new(args.has("mpi"))?;
    let mut runner = Multilevel::new(levels)
        .rmse(eps)
        .qmc(args.has("qmc"))
        .seed(settings.seed);
    if let Some(level) = args.get("min-level", "a whole number >= 1")? {
        runner = runner.min_level(level);
    }
    if let Some(level) = args.get("max-level", "a whole number up to 60")? {
        runner = runner.max_level(level);
    }
    if let Some(cost) = args.get("max-cost", "a cost > 0")? {
        runner = runner.max_cost(cost);
    }
    if let Some(threads) = args.get("threads", "a whole number of threads >= 1")? {
        runner = runner.threads(threads);
    }
    if let Some(deadline) = args.deadline()? {
        runner = runner.deadline(deadline);
    }
    // Ctrl-C (or SIGTERM) stops the run between chunks, with its estimate and checkpoint.
    let token = mcint::CancelToken::new();
    let stopper = token.clone();
    let _ = ctrlc::set_handler(move || stopper.cancel());
    let runner = runner.cancel_token(token);
    let runner = mcint_cli::spread!(runner, ranks.spread);
    let survey = match settings.test {
        Some((deepest, samples)) => {
            Some(Multilevel::survey(&runner, deepest, samples).map_err(text)?)
        }
        None => None,
    };
    let checkpoint: Option<PathBuf> = args.get("checkpoint", "a file name")?;
    let result = match &checkpoint {
        None => runner.run().map_err(text)?,
        Some(path) => {
            let mut state = match checkpoint::read_text(path)? {
                Some(saved) => serde_json::from_str(&saved)
                    .map_err(|e| format!("cannot read checkpoint '{}': {e}", path.display()))?,
                None => runner.checkpoint().map_err(text)?,
            };
            let result = runner.run_from(&mut state).map_err(|e| {
                format!(
                    "checkpoint '{}' cannot continue with these flags ({e}); delete it or repeat \
                     the flags of its run",
                    path.display()
                )
            })?;
            if ranks.spread.is_root() {
                let saved = serde_json::to_string(&state)
                    .map_err(|e| format!("cannot encode checkpoint: {e}"))?;
                checkpoint::write_text(path, &saved)?;
                if !result.converged {
                    note!(
                        "checkpoint: {}; saved in '{}'; run the same command again to continue",
                        support::stop_name(result.stop),
                        path.display()
                    );
                }
            }
            result
        }
    };
    if !ranks.spread.is_root() {
        return Ok(());
    }
    if let Some(path) = args.get::<PathBuf>("plot", "a file name")? {
        draw(&path, survey.as_ref().unwrap_or(&result))?;
    }
    // The library's settings named in a warning (`max_level`) are this program's flags.
    let warnings: Vec<(&str, String)> = result
        .warnings
        .iter()
        .map(|w| (w.kind(), w.to_string().replace("max_level", "--max-level")))
        .collect();
    for (_, warning) in &warnings {
        note!("warning: {warning}");
    }
    let exact = settings.exact();
    if args.has("json") {
        let mut report = serde_json::json!({
            "model": settings.model,
            "payoff": settings.payoff,
            "scheme": format!("{:?}", settings.scheme).to_lowercase(),
            "eps": settings.eps,
            "qmc": args.has("qmc"),
            "seed": settings.seed,
            "estimate": result.estimate,
            "std_error": result.std_error,
            "bias": result.bias,
            "rmse": result.rmse,
            "exact": exact,
            "levels": levels_json(&result),
            "alpha": result.alpha,
            "beta": result.beta,
            "gamma": result.gamma,
            "refinement": result.refinement,
            "cost": result.cost,
            "standard_mc_cost": result.standard_mc_cost,
            "converged": result.converged,
            "stop": support::stop_name(result.stop),
            "warnings": warnings
                .iter()
                .map(|(kind, message)| serde_json::json!({"kind": kind, "message": message}))
                .collect::<Vec<_>>(),
            "ranks": ranks.spread.size,
        });
        if let Some(survey) = &survey {
            report["test"] = serde_json::json!({
                "levels": levels_json(survey),
                "alpha": survey.alpha,
                "beta": survey.beta,
                "gamma": survey.gamma,
            });
        }
        say!("{report}");
        return Ok(());
    }
    if let Some(survey) = &survey {
        say!(
            "Giles' mlmc_test survey ({} samples per level):",
            survey.levels[0].samples
        );
        say!("{survey}");
    }
    say!("Multilevel run to RMSE {}:", decimals(settings.eps, None));
    say!("{result}");
    if let Some(exact) = exact {
        let error = result.estimate - exact;
        let ratio = error.abs() / settings.eps;
        let ratio = if ratio < 1e6 {
            format!("{ratio:.2}")
        } else {
            format!("{ratio:.2e}")
        };
        say!(
            "Black-Scholes {}: error {error:+.3e} ({ratio} target)",
            decimals(exact, Some(10))
        );
    }
    Ok(())
}

impl Settings {
    /// The Black-Scholes value of a European or digital call under GBM.
    fn exact(&self) -> Option<f64> {
        if self.model != "gbm" || self.sigma <= 0.0 {
            return None;
        }
        let root = self.sigma * self.maturity.sqrt();
        let d1 = ((self.s0 / self.strike).ln()
            + (self.rate + 0.5 * self.sigma * self.sigma) * self.maturity)
            / root;
        let d2 = d1 - root;
        let discount = (-self.rate * self.maturity).exp();
        match self.payoff.as_str() {
            "european" => Some(self.s0 * normal_cdf(d1) - self.strike * discount * normal_cdf(d2)),
            "digital" => Some(discount * normal_cdf(d2)),
            _ => None,
        }
    }
}

fn levels_json(run: &MultilevelEstimate) -> serde_json::Value {
    run.levels
        .iter()
        .map(|l| {
            serde_json::json!({
                "level": l.level,
                "n": l.samples,
                "mean": l.mean,
                "variance": l.variance,
                "cost": l.cost,
                "fine_mean": l.fine_mean,
                "fine_variance": l.fine_variance,
                "kurtosis": l.kurtosis,
                "check": l.consistency,
            })
        })
        .collect()
}

/// Giles' decay plot: `log2 |mean|` and `log2 variance` of `P_l` and `P_l - P_{l-1}`.
fn draw(path: &std::path::Path, run: &MultilevelEstimate) -> Result<(), String> {
    let series =
        |name: &str, value: &dyn Fn(&mcint::multilevel::LevelSummary) -> f64, from: usize| {
            plot::Series {
                name: name.to_string(),
                points: run
                    .levels
                    .iter()
                    .skip(from)
                    .filter(|l| value(l) > 0.0)
                    .map(|l| (l.level as f64, value(l).log2()))
                    .collect(),
            }
        };
    let lines = [
        series("log2 var(P_l)", &|l| l.fine_variance, 0),
        series("log2 var(P_l - P_l-1)", &|l| l.variance, 1),
        series("log2 |mean(P_l)|", &|l| l.fine_mean.abs(), 0),
        series("log2 |mean(P_l - P_l-1)|", &|l| l.mean.abs(), 1),
    ];
    let title = format!(
        "level decays: alpha {:.2}, beta {:.2}, gamma {:.2} (M = {})",
        run.alpha, run.beta, run.gamma, run.refinement
    );
    plot::line(path, &title, "level l", "log2", &lines, None)
}

/// The standard normal cdf, `erfc(-x / sqrt 2) / 2`.
fn normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / std::f64::consts::SQRT_2)
}
