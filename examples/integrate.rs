//! Integrates a Genz test family with a chosen sampler and reports the estimate, its honest
//! standard error and the exact value.
//!
//! ```text
//! cargo run --release --example integrate -- --genz FAMILY --dims D [--a a1,a2,..] [--u u1,u2,..]
//!     [--sampler NAME] [--scramble NAME] [--strength T] [--n N] [--replicates R] [--seed S]
//!     [--threads T] [--estimator uniform|importance|mis|control] [--json]
//! ```
//! FAMILY is one of oscillatory, product-peak, corner-peak, gaussian, continuous,
//! discontinuous. Defaults: `a_i = 1 + 0.5 (i-1)`, `u_i = 0.2 + 0.6 (i-1)/(d-1)`, sampler
//! `independent`, `--n` (points per replicate) 65536 (for `jittered` the largest `k^d` not
//! above it), `--replicates` 1 for independent points or unscrambled sequences and 16
//! otherwise, `--scramble` the sampler's default (owen for sobol, permute for halton and
//! hammersley, shift for lattice). With `--scramble none` no standard error is reported.
//!
//! `--estimator` (default `uniform`) picks how points become contributions: `importance`
//! samples a product density shaped like the family (truncated normals for `gaussian`, exact;
//! piecewise-linear tables of the factors otherwise), `mis` combines one uniform point and
//! one proposal point with the balance heuristic, `control` subtracts the family's
//! least-squares linear part, fitted on a separate pilot run (A.27). The report gives the variance per integrand evaluation, so the
//! estimators can be compared at equal work.

#[path = "support/genz_estimators.rs"]
mod genz_estimators;
#[path = "support/mod.rs"]
mod support;

use genz_estimators::EstimatorKind;
use mcint::estimator::Estimator;
use mcint::sampler::{PassKind, SamplerKind};
use mcint::testfns::{Genz, GenzFamily, TestFunction};
use mcint::{Estimate, Integrator};
use std::time::Instant;
use support::{Args, fail};

const SPEC: support::Spec = &[
    ("genz", true),
    ("dims", true),
    ("a", true),
    ("u", true),
    ("sampler", true),
    ("scramble", true),
    ("strength", true),
    ("n", true),
    ("replicates", true),
    ("seed", true),
    ("threads", true),
    ("estimator", true),
    ("json", false),
];

const DEFAULT_POINTS: u64 = 1 << 16;

fn main() {
    if let Err(message) = run() {
        fail(message);
    }
}

fn run() -> Result<(), String> {
    let args = Args::parse(SPEC)?;
    let family: GenzFamily = args
        .require::<String>("genz", "a Genz family name")?
        .parse()
        .map_err(|e: mcint::Error| e.to_string())?;
    let dims: usize = args.require("dims", "a whole number of dimensions >= 1")?;
    let f = match (args.list("a")?, args.list("u")?) {
        (None, None) => Genz::with_defaults(family, dims),
        (a, u) => {
            let defaults = Genz::with_defaults(family, dims).map_err(|e| e.to_string())?;
            Genz::new(
                family,
                a.unwrap_or_else(|| defaults.a().to_vec()),
                u.unwrap_or_else(|| defaults.u().to_vec()),
            )
        }
    }
    .map_err(|e| e.to_string())?;
    let estimator_kind: EstimatorKind = args
        .get::<String>("estimator", genz_estimators::ESTIMATOR_NAMES)?
        .map_or(Ok(EstimatorKind::Uniform), |name| name.parse())?;
    let seed: u64 = args.get("seed", "a whole number")?.unwrap_or(0);
    let built = genz_estimators::build(estimator_kind, &f, seed)?;
    // The sampler feeds the estimator's canonical points (two per dimension for mis).
    let canonical_dims = built.estimator.canonical_dims();
    let kind: SamplerKind = args
        .get::<String>("sampler", "a sampler name")?
        .unwrap_or_else(|| "independent".into())
        .parse()
        .map_err(|e: mcint::Error| e.to_string())?;
    let n = match args.get::<u64>("n", "a whole number of points >= 1")? {
        Some(n) => n,
        None if kind == SamplerKind::Jittered => {
            largest_power_not_above(DEFAULT_POINTS, canonical_dims)
        }
        None => DEFAULT_POINTS,
    };
    let scramble = args.scramble_for(kind)?;
    let strength: Option<u32> = args.get("strength", "a whole number >= 1 (oa-bush)")?;
    let sampler = kind
        .build_with(canonical_dims, n, scramble, strength, seed)
        .map_err(|e| e.to_string())?;
    let independent = sampler.passes() == PassKind::Independent;
    let default_replicates = if independent || !sampler.is_randomized() {
        1
    } else {
        16
    };
    let replicates: u64 = args
        .get("replicates", "a whole number >= 1")?
        .unwrap_or(default_replicates);
    let threads: Option<usize> = args.get("threads", "a whole number of threads >= 1")?;

    let mut integrator = Integrator::new(built.estimator)
        .sampler(sampler)
        .samples(n)
        .replicates(replicates)
        .seed(seed);
    if let Some(t) = threads {
        integrator = integrator.threads(t);
    }
    let started = Instant::now();
    let estimate = integrator.run().map_err(|e| e.to_string())?;
    let seconds = started.elapsed().as_secs_f64();
    let report = Report {
        family,
        dims,
        kind,
        scramble,
        estimator: estimator_kind,
        estimator_description: built.description,
        evaluations_per_contribution: built.evaluations_per_contribution,
        estimate,
        exact: f.exact(),
        seconds,
    };
    if args.has("json") {
        report.print_json()
    } else {
        report.print_text()
    }
    Ok(())
}

/// Largest `k^d <= n` with `k >= 1`.
fn largest_power_not_above(n: u64, d: usize) -> u64 {
    let exponent = u32::try_from(d).unwrap_or(u32::MAX);
    let mut k = 1u64;
    while (k + 1).checked_pow(exponent).is_some_and(|p| p <= n) {
        k += 1;
    }
    k.pow(exponent)
}

struct Report {
    family: GenzFamily,
    dims: usize,
    kind: SamplerKind,
    scramble: mcint::sampler::Scramble,
    estimator: EstimatorKind,
    estimator_description: String,
    evaluations_per_contribution: u64,
    estimate: Estimate,
    exact: f64,
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
        println!(
            "{{\"family\": \"{}\", \"dims\": {}, \"sampler\": \"{}\", \"scramble\": \"{}\", \"estimator\": \"{}\", \
             \"estimate\": {}, \"std_error\": {}, \"variance_per_evaluation\": {}, \
             \"exact\": {}, \"n\": {}, \"replicates\": {}, \"seconds\": {}}}",
            self.family.name(),
            self.dims,
            self.kind.name(),
            self.scramble.name(),
            self.estimator.name(),
            json_number(Some(e.mean)),
            json_number(e.std_error),
            json_number(self.variance_per_evaluation()),
            json_number(Some(self.exact)),
            e.n,
            e.replicates,
            json_number(Some(self.seconds)),
        );
    }

    fn print_text(&self) {
        let e = &self.estimate;
        let error = (e.mean - self.exact).abs();
        println!(
            "integrand   genz {} in {} dimensions",
            self.family.name(),
            self.dims
        );
        println!(
            "sampler     {}, scramble {} ({} replicates x {} points)",
            self.kind,
            self.scramble,
            e.replicates,
            e.n / e.replicates
        );
        println!(
            "estimator   {}: {}",
            self.estimator.name(),
            self.estimator_description
        );
        println!("estimate    {:.12e}", e.mean);
        println!("exact       {:.12e}", self.exact);
        match (e.std_error, e.confidence_interval(0.95)) {
            (Some(se), Ok(Some((lo, hi)))) => {
                println!("std error   {se:.3e} ({:?})", e.basis);
                if let Some(v) = self.variance_per_evaluation() {
                    println!("var/eval    {v:.3e} (variance x integrand evaluations)");
                }
                println!("95% CI      [{lo:.12e}, {hi:.12e}]");
                println!(
                    "|error|     {error:.3e} = {:.2} standard errors",
                    error / se
                );
            }
            _ => {
                println!(
                    "std error   none (one replicate of dependent points has no honest error bar)"
                );
                println!("|error|     {error:.3e}");
            }
        }
        println!("time        {:.3} s", self.seconds);
    }
}

/// A JSON number, or `null` for a missing or non-finite value.
fn json_number(value: Option<f64>) -> String {
    match value {
        Some(v) if v.is_finite() => format!("{v:?}"),
        _ => "null".into(),
    }
}
