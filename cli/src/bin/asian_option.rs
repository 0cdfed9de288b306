//! Prices an Asian call on a Black-Scholes asset by (randomized quasi-) Monte Carlo: the path
//! construction decides how much QMC gains.
//!
//! ```text
//! cargo run --release --bin asian_option -- [--dates 64] [--s0 100 --strike 100 --rate 0.05
//!     --sigma 0.2 --maturity 1] [--payoff arithmetic|geometric] [--construction standard|bridge|pca]
//!     [--sampler sobol|independent|lattice|halton] [--control geometric|none] [--tol-rel X]
//!     [--max-evals N] [--n N --replicates R] [--seed S] [--threads T] [--time-limit SECONDS]
//!     [--json] [--table]
//! ```
//!
//! The price is `E[e^{-rT} max(A - K, 0)]` with `A` the arithmetic (or geometric) average of
//! the prices at `--dates` equally spaced dates, under geometric Brownian motion
//! ([`mcint::measure::GeometricBrownianMotion`]) built by the standard construction, the
//! Brownian bridge or principal components. `--control geometric` subtracts the geometric
//! payoff minus its closed-form price from the arithmetic one (Kemna & Vorst 1990, coefficient
//! 1: the two payoffs nearly agree path by path). With `--tol-rel` the run stops when the 95%
//! half-width is at most that fraction of the price (or at `--max-evals`, default 2^30);
//! otherwise it takes `--n` points per replicate (default 4096) and `--replicates` (default 16,
//! 1 for independent points). `--json` prints `price`, `std_error`, `evaluations`,
//! `converged`, `stop` and `exact` (the closed form for the geometric payoff, `null`
//! otherwise). `--time-limit` stops the run (every run of `--table`, counted from the start)
//! with the work done, and the report says so.
//!
//! `--table` prints, for every construction and sampler, with and without the control, the
//! evaluations a run needs to reach `--tol-rel` (default 1e-4), each limited to `--max-evals`
//! (default 2^24).

use asian::Contract;
use mcint::measure::{Construction, GeometricBrownianMotion};
use mcint::sampler::{SamplerKind, Scramble};
use mcint::stats::{StopReason, Tolerance};
use mcint::{Estimate, Integrator};
use mcint_cli::args as support;
use mcint_cli::asian;
use mcint_cli::output::decimals;
use mcint_cli::{note, say};
use std::time::Instant;
use support::Args;

/// What `--help` says the program does.
const ABOUT: &str =
    "Prices an Asian call on a Black-Scholes asset by (randomized quasi-) Monte Carlo.";

const SPEC: support::Spec = &[
    ("dates", true, "averaging dates (default 64)"),
    ("s0", true, "initial price (default 100)"),
    ("strike", true, "strike (default 100)"),
    ("rate", true, "interest rate (default 0.05)"),
    ("sigma", true, "volatility (default 0.2)"),
    ("maturity", true, "maturity in years (default 1)"),
    ("payoff", true, "arithmetic (default) or geometric average"),
    (
        "construction",
        true,
        "standard (default), bridge or pca paths",
    ),
    (
        "sampler",
        true,
        "sobol (default, Owen-scrambled), independent, lattice or halton",
    ),
    (
        "control",
        true,
        "geometric (the geometric option as control variate) or none (default)",
    ),
    support::TOL_REL,
    support::MAX_EVALS,
    support::TIME_LIMIT,
    ("n", true, "points per replicate (default 4096)"),
    (
        "replicates",
        true,
        "independent randomized replicates, their spread the error bar (default 16; 1 for \
         independent points, whose error bar is their own spread)",
    ),
    support::SEED,
    support::THREADS,
    support::JSON,
    (
        "table",
        false,
        "every construction and sampler to --tol-rel, with and without the control",
    ),
];

/// The most averaging dates (one canonical dimension each).
const MAX_DATES: usize = 4096;

fn main() {
    support::finish(run());
}

/// One pricing run's choices.
#[derive(Clone, Copy)]
struct Choice {
    arithmetic: bool,
    construction: Construction,
    sampler: SamplerKind,
    control: bool,
}

/// What the flags ask for beyond the contract and the choice.
#[derive(Clone, Copy)]
struct Budget {
    tolerance: Option<Tolerance>,
    n: Option<u64>,
    replicates: Option<u64>,
    seed: u64,
    threads: Option<usize>,
    deadline: Option<std::time::Instant>,
}

fn run() -> Result<(), String> {
    let args = Args::parse(ABOUT, SPEC)?;
    let contract = contract(&args)?;
    let choice = Choice {
        arithmetic: match args
            .get::<String>("payoff", "arithmetic or geometric")?
            .as_deref()
        {
            None | Some("arithmetic") => true,
            Some("geometric") => false,
            Some(other) => {
                return Err(format!(
                    "invalid --payoff = '{other}': expected arithmetic or geometric"
                ));
            }
        },
        construction: match args
            .get::<String>("construction", "standard, bridge or pca")?
            .as_deref()
        {
            None | Some("standard") => Construction::Standard,
            Some("bridge") => Construction::Bridge,
            Some("pca") => Construction::Pca,
            Some(other) => {
                return Err(format!(
                    "invalid --construction = '{other}': expected standard, bridge or pca"
                ));
            }
        },
        sampler: sampler_kind(args.get::<String>("sampler", "a sampler")?.as_deref())?,
        control: match args
            .get::<String>("control", "geometric or none")?
            .as_deref()
        {
            None | Some("none") => false,
            Some("geometric") => true,
            Some(other) => {
                return Err(format!(
                    "invalid --control = '{other}': expected geometric or none"
                ));
            }
        },
    };
    if choice.control && !choice.arithmetic {
        return Err("--control geometric applies to --payoff arithmetic (the geometric payoff has its closed form)".into());
    }
    let table = args.has("table");
    let tol_rel: Option<f64> = args.get("tol-rel", "a relative tolerance > 0")?;
    let max_evals: Option<u64> = args.get("max-evals", "a whole number of evaluations >= 1")?;
    let tolerance = match (tol_rel.or(table.then_some(1e-4)), max_evals) {
        (None, Some(_)) => {
            return Err("--max-evals limits a run to a tolerance: give --tol-rel too".into());
        }
        (None, None) => None,
        (Some(rel), limit) => {
            let t = Tolerance::relative(rel).map_err(flag_error)?;
            let limit = limit.or(table.then_some(1 << 24));
            Some(match limit {
                Some(n) => t.max_evaluations(n).map_err(flag_error)?,
                None => t,
            })
        }
    };
    let budget = Budget {
        tolerance,
        n: args.get("n", "a whole number of points >= 1")?,
        replicates: args.get("replicates", "a whole number >= 1")?,
        seed: args.get("seed", "a whole number")?.unwrap_or(0),
        threads: args.get("threads", "a whole number of threads >= 1")?,
        deadline: args.deadline()?,
    };
    if table {
        return print_table(&contract, &budget);
    }
    let started = Instant::now();
    let estimate = price(&contract, choice, &budget).map_err(flag_error)?;
    let seconds = started.elapsed().as_secs_f64();
    for warning in &estimate.warnings {
        note!("warning: {warning}");
    }
    let exact = if choice.arithmetic {
        None
    } else {
        Some(contract.geometric_price().map_err(flag_error)?)
    };
    if args.has("json") {
        let json = serde_json::json!({
            "price": estimate.mean,
            "std_error": estimate.std_error,
            "interval": estimate.confidence_interval(0.95).ok().flatten().map(|(lo, hi)| [lo, hi]),
            "evaluations": estimate.evaluations,
            "converged": estimate.converged,
            "stop": support::stop_name(estimate.stop),
            "exact": exact,
            "payoff": if choice.arithmetic { "arithmetic" } else { "geometric" },
            "construction": construction_name(choice.construction),
            "sampler": choice.sampler.name(),
            "control": if choice.control { "geometric" } else { "none" },
            "dates": contract.dates,
            "replicates": estimate.replicates,
            "seconds": seconds,
        });
        say!("{json}");
        return Ok(());
    }
    say!(
        "{} Asian call, {} dates, S0 {} K {} r {} sigma {} T {}",
        if choice.arithmetic {
            "arithmetic"
        } else {
            "geometric"
        },
        contract.dates,
        decimals(contract.s0, None),
        decimals(contract.strike, None),
        decimals(contract.rate, None),
        decimals(contract.sigma, None),
        decimals(contract.maturity, None)
    );
    say!(
        "paths       {} construction, {} points, control {}",
        construction_name(choice.construction),
        choice.sampler.name(),
        if choice.control { "geometric" } else { "none" }
    );
    say!("price       {}", decimals(estimate.mean, Some(10)));
    match (estimate.std_error, estimate.confidence_interval(0.95)) {
        (Some(se), Ok(Some((lo, hi)))) => {
            say!("std error   {se:.3e}");
            let (lo, hi) = (decimals(lo, Some(10)), decimals(hi, Some(10)));
            say!("95% CI      [{lo}, {hi}]");
        }
        _ => say!("std error   none"),
    }
    if let Some(exact) = exact {
        say!("exact       {} (closed form)", decimals(exact, Some(10)));
    }
    say!("evaluations {}", estimate.evaluations);
    if estimate.stop == StopReason::TimeLimit {
        say!("stopped     early (time limit)");
    }
    if let Some(converged) = estimate.converged {
        say!("tolerance   {}", if converged { "met" } else { "NOT met" });
    }
    say!("time        {seconds:.3} s");
    Ok(())
}

/// The contract of the flags.
fn contract(args: &Args) -> Result<Contract, String> {
    let number = |name: &str, default: f64| -> Result<f64, String> {
        let value = args.get(name, "a number")?.unwrap_or(default);
        if value.is_finite() {
            Ok(value)
        } else {
            Err(format!(
                "invalid --{name} = {value}: expected a finite number"
            ))
        }
    };
    let dates: usize = args
        .get("dates", "a whole number of dates >= 1")?
        .unwrap_or(64);
    if !(1..=MAX_DATES).contains(&dates) {
        return Err(format!(
            "invalid --dates = {dates}: expected 1 to {MAX_DATES}"
        ));
    }
    let contract = Contract {
        s0: number("s0", 100.0)?,
        strike: number("strike", 100.0)?,
        rate: number("rate", 0.05)?,
        sigma: number("sigma", 0.2)?,
        maturity: number("maturity", 1.0)?,
        dates,
    };
    if contract.strike <= 0.0 {
        return Err(format!(
            "invalid --strike = {}: expected a price > 0",
            contract.strike
        ));
    }
    if contract.maturity <= 0.0 {
        return Err(format!(
            "invalid --maturity = {}: expected a time > 0",
            contract.maturity
        ));
    }
    // A negative rate discounts by e^(-rate T) > 1, which must stay finite (an infinite
    // one times a payoff of 0 is NaN).
    let exponent = -contract.rate * contract.maturity;
    if !exponent.exp().is_finite() {
        return Err(format!(
            "invalid --rate = {} with --maturity = {}: expected a discount factor \
             e^(-rate maturity) that f64 holds, -rate x maturity at most {:.2} (it is {exponent:e})",
            contract.rate,
            contract.maturity,
            f64::MAX.ln()
        ));
    }
    // The model checks s0 and sigma.
    contract.paths(Construction::Standard).map_err(flag_error)?;
    Ok(contract)
}

fn sampler_kind(name: Option<&str>) -> Result<SamplerKind, String> {
    match name {
        None | Some("sobol") => Ok(SamplerKind::Sobol),
        Some("independent") => Ok(SamplerKind::Independent),
        Some("lattice") => Ok(SamplerKind::Lattice),
        Some("halton") => Ok(SamplerKind::Halton),
        Some(other) => Err(format!(
            "invalid --sampler = '{other}': expected sobol, independent, lattice or halton"
        )),
    }
}

fn construction_name(c: Construction) -> &'static str {
    match c {
        Construction::Standard => "standard",
        Construction::Bridge => "bridge",
        Construction::Pca => "pca",
    }
}

/// A library error as one line naming the flags behind the bad setting.
fn flag_error(error: mcint::Error) -> String {
    let times = ("times", "monitoring times from --maturity and --dates");
    support::spec_error(SPEC, &[times], error)
}

/// The price by one run of the Integrator.
fn price(contract: &Contract, choice: Choice, budget: &Budget) -> mcint::Result<Estimate> {
    price_on(
        contract,
        contract.paths(choice.construction)?,
        choice,
        budget,
    )
}

/// [`price`] over `paths`, the contract's paths of `choice.construction` built already.
fn price_on(
    contract: &Contract,
    paths: GeometricBrownianMotion,
    choice: Choice,
    budget: &Budget,
) -> mcint::Result<Estimate> {
    let exact_geometric = contract.geometric_price()?;
    let c = *contract;
    let payoff = move |prices: &[f64]| {
        if !choice.arithmetic {
            c.geometric(prices)
        } else if choice.control {
            c.arithmetic(prices) - (c.geometric(prices) - exact_geometric)
        } else {
            c.arithmetic(prices)
        }
    };
    let scramble = match choice.sampler {
        SamplerKind::Sobol => Scramble::Owen,
        SamplerKind::Halton => Scramble::Permute,
        SamplerKind::Lattice => Scramble::Shift,
        _ => Scramble::None,
    };
    let n = budget.n.unwrap_or(4096);
    let sampler = choice
        .sampler
        .build_with(contract.dates, n, scramble, None, budget.seed)?;
    let default_replicates = mcint::Method::Rqmc.default_replicates(&*sampler);
    let mut integrator = Integrator::expectation(payoff, paths)
        .sampler(sampler)
        .seed(budget.seed);
    if budget.tolerance.is_none() || budget.n.is_some() {
        integrator = integrator.samples(n);
    }
    if budget.tolerance.is_none() || budget.replicates.is_some() {
        integrator = integrator.replicates(budget.replicates.unwrap_or(default_replicates));
    }
    if let Some(t) = budget.threads {
        integrator = integrator.threads(t);
    }
    if let Some(t) = budget.tolerance {
        integrator = integrator.tolerance(t);
    }
    if let Some(deadline) = budget.deadline {
        integrator = integrator.deadline(deadline);
    }
    integrator.run()
}

/// Evaluations to the tolerance for every construction and sampler, with and without the
/// control.
fn print_table(contract: &Contract, budget: &Budget) -> Result<(), String> {
    let Some(tolerance) = budget.tolerance else {
        return Err("--table needs a tolerance".into());
    };
    // The table's quasi-random rows are runs to a tolerance, whose error bar is the spread
    // of two replicates or more.
    if let Some(replicates @ 0..=1) = budget.replicates {
        return Err(format!(
            "invalid --replicates = {replicates}: expected at least 2 for --table (its runs \
             to a tolerance take their error bar from the replicates' spread)"
        ));
    }
    // Every row's settings are checked before any row is printed: each construction's paths
    // are built once (principal components have a dimension bound, and take seconds near
    // it), and each run started with a deadline already past, which checks its settings (an
    // evaluation limit below its first stage) and stops before its first evaluation.
    let paths = CONSTRUCTIONS
        .map(|construction| contract.paths(construction))
        .into_iter()
        .collect::<mcint::Result<Vec<_>>>()
        .map_err(flag_error)?;
    let paths_of = |choice: Choice| {
        // Always found: the rows are built from `CONSTRUCTIONS`.
        let at = CONSTRUCTIONS.iter().position(|&c| c == choice.construction);
        paths[at.unwrap_or(0)].clone()
    };
    let past = Budget {
        deadline: Some(std::time::Instant::now()),
        ..*budget
    };
    for choice in table_rows() {
        match price_on(contract, paths_of(choice), choice, &past) {
            Ok(_) | Err(mcint::Error::Interrupted { .. }) => {}
            Err(e) => return Err(flag_error(e)),
        }
    }
    say!(
        "arithmetic Asian call, {} dates: evaluations to a 95% half-width of {} x price (limit {})",
        contract.dates,
        tolerance.target(1.0),
        tolerance.evaluation_limit()
    );
    say!(
        "{:<10} {:<12} {:>14} {:>14}",
        "paths",
        "points",
        "no control",
        "geometric cv"
    );
    for pair in table_rows().collect::<Vec<_>>().chunks(2) {
        let mut cells = Vec::new();
        for &choice in pair {
            cells.push(match price_on(contract, paths_of(choice), choice, budget) {
                Ok(e) if e.converged == Some(true) => e.evaluations.to_string(),
                Ok(e) if e.stop == StopReason::TimeLimit => "time limit".to_string(),
                Ok(_) => format!("> {}", tolerance.evaluation_limit()),
                Err(mcint::Error::Interrupted { .. }) => "time limit".to_string(),
                Err(e) => return Err(flag_error(e)),
            });
        }
        say!(
            "{:<10} {:<12} {:>14} {:>14}",
            construction_name(pair[0].construction),
            pair[0].sampler.name(),
            cells[0],
            cells[1]
        );
    }
    Ok(())
}

/// The table's path constructions, in the order of its rows.
const CONSTRUCTIONS: [Construction; 3] = [
    Construction::Standard,
    Construction::Bridge,
    Construction::Pca,
];

/// The table's runs in the order printed: per sampler and construction, a row of two, without
/// and with the control.
fn table_rows() -> impl Iterator<Item = Choice> {
    let samplers = [
        SamplerKind::Independent,
        SamplerKind::Sobol,
        SamplerKind::Lattice,
        SamplerKind::Halton,
    ];
    samplers.into_iter().flat_map(move |sampler| {
        CONSTRUCTIONS.into_iter().flat_map(move |construction| {
            [false, true].map(|control| Choice {
                arithmetic: true,
                construction,
                sampler,
                control,
            })
        })
    })
}
