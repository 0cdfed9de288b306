//! What `integrate` prints of a run: one JSON object (`--json`, from the serializable
//! reports below) or text, for one output or several.

use mcint::stats::{Derived, Warning};
use mcint::testfns::TestFunction;
use mcint::{Estimate, Method, VectorEstimate};
use serde::Serialize;

use crate::args::stop_name;
use crate::integrands::Named;
use crate::{note, say};

/// What `integrate` ran, and what came of it.
pub struct Report<'a> {
    pub method: Method,
    pub functions: &'a [Named],
    pub sampler: &'static str,
    pub scramble: &'static str,
    /// The estimator's name and what it does (one output only).
    pub estimator: &'static str,
    pub estimator_description: String,
    /// Integrand evaluations per contribution of the estimator.
    pub evaluations_per_contribution: u64,
    /// `--ratio I,J`, if asked for.
    pub ratio: Option<(usize, usize)>,
    pub run: VectorEstimate,
    /// MPI ranks the run was spread over (1 without `--mpi`).
    pub ranks: usize,
    pub seconds: f64,
}

/// A warning as `--json` lists it.
#[derive(Serialize)]
struct WarningJson {
    kind: &'static str,
    message: String,
    /// The output it belongs to, in a run of several.
    #[serde(skip_serializing_if = "Option::is_none")]
    output: Option<usize>,
    /// The ratio `[I, J]` it belongs to: a tolerance on `--ratio` not met.
    #[serde(skip_serializing_if = "Option::is_none")]
    ratio: Option<[usize; 2]>,
}

/// What a warning belongs to.
#[derive(Clone, Copy)]
enum Owner {
    Run,
    Output(usize),
    /// The ratio of outputs `I / J`, the target of a run to a tolerance with `--ratio`.
    Ratio(usize, usize),
}

/// `--json` of a run of one output.
#[derive(Serialize)]
struct ScalarJson<'a> {
    method: &'static str,
    family: String,
    dims: usize,
    sampler: &'static str,
    scramble: &'static str,
    estimator: &'static str,
    estimate: Option<f64>,
    std_error: Option<f64>,
    error_bound: Option<f64>,
    variance_per_evaluation: Option<f64>,
    exact: Option<f64>,
    n: u64,
    replicates: u64,
    evaluations: u64,
    converged: Option<bool>,
    stop: &'static str,
    iterations: u64,
    chi2_dof: Option<f64>,
    rounding_error: Option<f64>,
    warnings: &'a [WarningJson],
    ranks: usize,
    seconds: Option<f64>,
}

/// `--json` of a vector run.
#[derive(Serialize)]
struct VectorJson<'a> {
    method: &'static str,
    families: Vec<String>,
    dims: usize,
    sampler: &'static str,
    scramble: &'static str,
    estimates: Vec<f64>,
    std_errors: Vec<Option<f64>>,
    exact: Vec<f64>,
    covariance: Option<Vec<Vec<f64>>>,
    n: u64,
    replicates: u64,
    evaluations: u64,
    converged: Option<bool>,
    stop: &'static str,
    iterations: u64,
    warnings: &'a [WarningJson],
    ranks: usize,
    seconds: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    ratio: Option<RatioJson>,
}

/// The ratio of two outputs in `--json`.
#[derive(Serialize)]
struct RatioJson {
    numerator: usize,
    denominator: usize,
    estimate: f64,
    std_error: Option<f64>,
    exact: f64,
}

/// A number JSON can hold: NaN and infinities become `null`.
fn number(v: Option<f64>) -> Option<f64> {
    v.filter(|v| v.is_finite())
}

impl Report<'_> {
    /// Whether the run estimated several outputs.
    fn vector(&self) -> bool {
        self.functions.len() > 1 || self.ratio.is_some()
    }

    /// The warnings on stderr, one line each, then the report on stdout.
    pub fn print(&self, json: bool) -> Result<(), String> {
        for (owner, warning) in self.warnings() {
            match owner {
                Owner::Output(k) => note!("warning: output {k}: {warning}"),
                Owner::Ratio(i, j) => note!("warning: ratio {i}/{j}: {warning}"),
                Owner::Run => note!("warning: {warning}"),
            }
        }
        match (json, self.vector()) {
            (true, false) => self.scalar_json(),
            (true, true) => self.vector_json()?,
            (false, false) => self.scalar_text(),
            (false, true) => self.vector_text()?,
        }
        Ok(())
    }

    /// Every output's warnings, with the output they belong to in a vector run. With
    /// `--ratio` the tolerance is the ratio's alone, so a tolerance not met is the ratio's,
    /// said once, not each output's.
    fn warnings(&self) -> Vec<(Owner, &Warning)> {
        let vector = self.vector();
        let mut warnings: Vec<(Owner, &Warning)> = Vec::new();
        for (k, e) in self.run.outputs.iter().enumerate() {
            for w in &e.warnings {
                let owner = match (self.ratio, w) {
                    (Some((i, j)), Warning::ToleranceNotMet { .. }) => Owner::Ratio(i, j),
                    _ if vector => Owner::Output(k),
                    _ => Owner::Run,
                };
                // Every output carries the ratio's one warning: said once.
                let said = matches!(owner, Owner::Ratio(..))
                    && warnings.iter().any(|(o, _)| matches!(o, Owner::Ratio(..)));
                if !said {
                    warnings.push((owner, w));
                }
            }
        }
        warnings
    }

    fn warnings_json(&self) -> Vec<WarningJson> {
        self.warnings()
            .into_iter()
            .map(|(owner, w)| WarningJson {
                kind: w.kind(),
                message: w.to_string(),
                output: match owner {
                    Owner::Output(k) => Some(k),
                    _ => None,
                },
                ratio: match owner {
                    Owner::Ratio(i, j) => Some([i, j]),
                    _ => None,
                },
            })
            .collect()
    }

    /// The estimate of the one output.
    fn estimate(&self) -> &Estimate {
        &self.run.outputs[0]
    }

    /// The variance of the estimate times the number of integrand evaluations it took: the
    /// variance of a one-evaluation estimate, comparable across estimators at equal work.
    fn variance_per_evaluation(&self) -> Option<f64> {
        let e = self.estimate();
        e.std_error
            .map(|se| se * se * (e.n * self.evaluations_per_contribution) as f64)
    }

    /// The ratio's estimate and exact value, if one was asked for.
    fn ratio(&self) -> Option<Result<(Estimate, f64), String>> {
        self.ratio.map(|(i, j)| {
            let exact = self.functions[i].exact() / self.functions[j].exact();
            let estimate = self.run.derived(&Derived::ratio(i, j));
            estimate
                .map(|e| (e, exact))
                .map_err(crate::args::flag_error)
        })
    }

    fn scalar_json(&self) {
        let e = self.estimate();
        let f = &self.functions[0];
        let warnings = self.warnings_json();
        let json = ScalarJson {
            method: self.method.name(),
            family: f.name(),
            dims: f.dims(),
            sampler: self.sampler,
            scramble: self.scramble,
            estimator: self.estimator,
            estimate: number(Some(e.mean)),
            std_error: number(e.std_error),
            error_bound: number(e.error_bound),
            variance_per_evaluation: number(self.variance_per_evaluation()),
            exact: number(Some(f.exact())),
            n: e.n,
            replicates: e.replicates,
            evaluations: e.evaluations,
            converged: e.converged,
            stop: stop_name(e.stop),
            iterations: e.iterations,
            chi2_dof: number(e.chi2_dof),
            rounding_error: number(Some(e.rounding_error)),
            warnings: &warnings,
            ranks: self.ranks,
            seconds: number(Some(self.seconds)),
        };
        say!("{}", serde_json::to_string(&json).unwrap_or_default());
    }

    fn vector_json(&self) -> Result<(), String> {
        let run = &self.run;
        let m = run.len();
        let warnings = self.warnings_json();
        let ratio = match (self.ratio, self.ratio()) {
            (Some((numerator, denominator)), Some(result)) => {
                let (estimate, exact) = result?;
                Some(RatioJson {
                    numerator,
                    denominator,
                    estimate: estimate.mean,
                    std_error: number(estimate.std_error),
                    exact,
                })
            }
            _ => None,
        };
        let json = VectorJson {
            method: self.method.name(),
            families: self.functions.iter().map(TestFunction::name).collect(),
            dims: self.functions[0].dims(),
            sampler: self.sampler,
            scramble: self.scramble,
            estimates: run.outputs.iter().map(|e| e.mean).collect(),
            std_errors: run.outputs.iter().map(|e| number(e.std_error)).collect(),
            exact: self.functions.iter().map(|f| f.exact()).collect(),
            covariance: run
                .covariance_matrix
                .as_ref()
                .map(|c| c.chunks(m).map(<[f64]>::to_vec).collect()),
            n: run.outputs[0].n,
            replicates: run.outputs[0].replicates,
            evaluations: run.evaluations,
            converged: run.converged,
            stop: stop_name(run.stop),
            iterations: run.iterations,
            warnings: &warnings,
            ranks: self.ranks,
            seconds: self.seconds,
            ratio,
        };
        say!("{}", serde_json::to_string(&json).unwrap_or_default());
        Ok(())
    }

    fn scalar_text(&self) {
        let e = self.estimate();
        let f = &self.functions[0];
        let (family, exact) = (f.name(), f.exact());
        let error = (e.mean - exact).abs();
        let genz = if family == "keister" { "" } else { "genz " };
        say!("integrand   {genz}{family} in {} dimensions", f.dims());
        say!("method      {}", self.method.name());
        let layout = if matches!(self.method, Method::Vegas | Method::VegasPlus) {
            format!("{} iterations combined, {} points", e.iterations, e.n)
        } else if self.method == Method::SobolG {
            format!(
                "one sequence, {} points in {} stage{}",
                e.n,
                e.iterations,
                plural(e.iterations)
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
            self.sampler,
            self.scramble
        );
        say!(
            "estimator   {}: {}",
            self.estimator,
            self.estimator_description
        );
        say!("estimate    {:.12e}", e.mean);
        say!("exact       {exact:.12e}");
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
        self.how_it_ended("  ");
        if let Some(chi2) = e.chi2_dof {
            let q = e.q_value.map_or("-".to_string(), |q| format!("{q:.2}"));
            say!(
                "chi2/dof    {chi2:.2} over {} iterations (Q = {q})",
                e.iterations
            );
        }
        if self.ranks > 1 {
            say!("ranks       {} MPI processes", self.ranks);
        }
        say!("time        {:.3} s", self.seconds);
    }

    fn vector_text(&self) -> Result<(), String> {
        let run = &self.run;
        let names: Vec<String> = self.functions.iter().map(TestFunction::name).collect();
        say!(
            "{} outputs over the same points: {} in {} dimensions",
            run.len(),
            names.join(", "),
            self.functions[0].dims()
        );
        let combined = if self.method.name().starts_with("vegas") {
            "iterations combined"
        } else {
            "replicates"
        };
        say!(
            "method {}, sampler {}, scramble {}, {} {combined}, {} evaluations",
            self.method.name(),
            self.sampler,
            self.scramble,
            run.outputs[0].replicates,
            run.evaluations
        );
        say!(
            "{:>3}  {:<14} {:>20} {:>20} {:>10} {:>8}",
            "k",
            "family",
            "estimate",
            "exact",
            "std err",
            "|err|/se"
        );
        for (k, (e, f)) in run.outputs.iter().zip(self.functions).enumerate() {
            let se = e.std_error.map_or("none".into(), |s| format!("{s:.3e}"));
            let z = e.std_error.map_or("-".into(), |s| {
                format!("{:.2}", (e.mean - f.exact()).abs() / s)
            });
            say!(
                "{k:>3}  {:<14} {:>20.12e} {:>20.12e} {se:>10} {z:>8}",
                f.name(),
                e.mean,
                f.exact()
            );
        }
        if let (Some((i, j)), Some(result)) = (self.ratio, self.ratio()) {
            let (estimate, exact) = result?;
            let se = estimate
                .std_error
                .map_or("none".into(), |s| format!("{s:.3e}"));
            say!(
                "ratio {i}/{j}  {:>20.12e} {exact:>20.12e} {se:>10} (delta method)",
                estimate.mean
            );
        }
        self.how_it_ended("");
        say!("time {:.3} s", self.seconds);
        Ok(())
    }

    /// The line that says how the run ended, when it did not simply spend its budget: a
    /// tolerance met or not, or a stop on a limit (`gap` after the first word).
    fn how_it_ended(&self, gap: &str) {
        let run = &self.run;
        let e = self.estimate();
        let in_all = if self.vector() {
            String::new()
        } else {
            format!(", {} evaluations in all", run.evaluations)
        };
        if let Some(converged) = run.converged {
            say!(
                "tolerance{gap} {} ({}, {} stage{}{in_all})",
                if converged { "met" } else { "NOT met" },
                stop_name(run.stop),
                run.iterations,
                plural(run.iterations)
            );
        } else if matches!(
            run.stop,
            mcint::StopReason::TimeLimit | mcint::StopReason::Cancelled
        ) {
            say!(
                "stopped{gap}   early ({}) after {} evaluations",
                stop_name(run.stop),
                e.evaluations
            );
        }
    }
}

/// `"s"` unless there is one.
fn plural(n: u64) -> &'static str {
    if n == 1 { "" } else { "s" }
}
