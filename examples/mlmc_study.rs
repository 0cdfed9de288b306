//! The multilevel study behind `docs/measurements.md` ("Multilevel Monte Carlo"): a GBM
//! option (S0 = K = 100, r = 0.05, sigma = 0.2, T = 1) priced by `mcint::multilevel` to a
//! root-mean-square error target over many seeds, against its exact value.
//!
//! ```text
//! cargo build --release --example mlmc_study
//! target/release/examples/mlmc_study SCHEME PAYOFF EPS SEEDS [mc|qmc] [THREADS] [EXACT]
//! ```
//! `SEEDS` is a count `N` (seeds `0..N`) or a range `A..B`, so that a long study can run in
//! pieces and be pooled (mean squares and mean costs weighted by seed counts). `SCHEME` is euler or milstein, `PAYOFF` european, asian, lookback, digital or barrier (at
//! strike 100, barrier 85); `EXACT` is the value to measure errors against (default: the
//! Black-Scholes call, or the digital's closed form for `digital`). Prints one line: the RMSE
//! over the seeds in units of `EPS`, the mean cost, the mean cost times `EPS^2`, the mean
//! standard MC cost and its ratio to the cost, the mean number of levels, and how many runs
//! did not converge.

use mcint::multilevel::{Multilevel, Payoff, Scheme, Sde, SdeLevels};

const USAGE: &str = "usage: mlmc_study SCHEME PAYOFF EPS SEEDS [mc|qmc] [THREADS] [EXACT]";

fn main() {
    if let Err(message) = run() {
        eprintln!("error: {message}\n{USAGE}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize| args.get(i).ok_or_else(|| USAGE.to_string());
    let text = |e: mcint::Error| e.to_string();
    let number = |i: usize| -> Result<f64, String> {
        arg(i)?
            .parse()
            .map_err(|_| format!("not a number: {}", args[i]))
    };
    let scheme: Scheme = arg(0)?.parse().map_err(text)?;
    let payoff: Payoff = arg(1)?.parse().map_err(text)?;
    let eps = number(2)?;
    let seeds = seed_range(arg(3)?)?;
    let qmc = args.get(4).is_some_and(|m| m == "qmc");
    let threads = args.get(5).map_or(Ok(0.0), |_| number(5))? as usize;
    let discount = (-0.05f64).exp();
    let exact = match (args.get(6), payoff.name()) {
        (Some(_), _) => number(6)?,
        (None, "digital") => discount * 0.5 * libm::erfc(-0.15 / std::f64::consts::SQRT_2),
        (None, _) => 10.450583572185565,
    };
    let (mut squares, mut cost, mut standard, mut levels, mut unconverged) = (0.0, 0.0, 0.0, 0, 0);
    for seed in seeds.clone() {
        let sde = Sde::gbm(100.0, 0.05, 0.2).map_err(text)?;
        let model = SdeLevels::new(sde, scheme, payoff.clone(), 1.0)
            .map_err(text)?
            .discount(discount)
            .map_err(text)?;
        let mut runner = Multilevel::new(model).rmse(eps).qmc(qmc).seed(seed);
        if threads > 0 {
            runner = runner.threads(threads);
        }
        let run = runner.run().map_err(text)?;
        squares += (run.estimate - exact).powi(2);
        cost += run.cost;
        standard += run.standard_mc_cost;
        levels += run.levels.len();
        unconverged += usize::from(!run.converged);
    }
    let n = seeds.clone().count() as f64;
    println!(
        "{scheme:?} {} eps {eps:e} {} seeds {seeds:?}: RMSE/eps {:.3}, cost {:.3e}, cost*eps^2 \
         {:.1}, standard MC {:.3e} ({:.1}x), levels {:.1}, not converged {unconverged}",
        payoff.name(),
        if qmc { "MLQMC" } else { "MLMC" },
        (squares / n).sqrt() / eps,
        cost / n,
        cost / n * eps * eps,
        standard / n,
        standard / cost,
        levels as f64 / n,
    );
    Ok(())
}

/// Seeds `0..N` from `N`, or `A..B` from `A..B`.
fn seed_range(text: &str) -> Result<std::ops::Range<u64>, String> {
    let bad = || format!("SEEDS must be a count N or a range A..B, not {text}");
    let parse = |t: &str| t.parse::<u64>().map_err(|_| bad());
    match text.split_once("..") {
        Some((a, b)) if parse(a)? < parse(b)? => Ok(parse(a)?..parse(b)?),
        Some(_) => Err(bad()),
        None if parse(text)? > 0 => Ok(0..parse(text)?),
        None => Err(bad()),
    }
}
