//! `integrate --integrand F1,F2,...`: one vector-valued run of several integrands over the same
//! points, with the covariance of their estimates and, with `--ratio I,J`, the ratio of two
//! of them with a delta-method error bar.

use mcint::adaptive::Vegas;
use mcint::sampler::Sampler;
use mcint::stats::{Derived, Tolerance};
use mcint::testfns::TestFunction;
use mcint::{CancelToken, Integrator, VectorEstimate};

use crate::checkpoint;
use crate::integrands::Named;
use crate::methods::VEGAS_ITERATIONS_TO_TOLERANCE;
use crate::support::output::say;
use crate::support::stop_name;
use mcint::Method;

/// What a vector run needs from the command line.
pub struct VectorRunArgs<'a> {
    pub method: Method,
    pub functions: &'a [Named],
    pub sampler: Box<dyn Sampler>,
    pub samples: Option<u64>,
    /// `--replicates`, or the default of the sampler (plain and rqmc only).
    pub replicates: Option<u64>,
    pub default_replicates: u64,
    pub seed: u64,
    pub threads: Option<usize>,
    pub tolerance: Option<Tolerance>,
    /// `--ratio I,J`: output indices into the `--integrand` list.
    pub ratio: Option<(usize, usize)>,
    pub label: String,
    pub checkpoint: Option<checkpoint::Settings>,
    pub cancel: CancelToken,
    /// `--time-limit`: the instant the run stops by.
    pub deadline: Option<std::time::Instant>,
    /// `--mpi`: the ranks to spread the run over.
    pub spread: crate::ranks::Spread,
}

/// Runs the families as one vector integrand over the unit cube (plain, randomized QMC,
/// VEGAS or VEGAS+). With `--ratio`, a tolerance applies to the ratio (the quantity asked
/// for); otherwise to every output. `Ok(None)` when a checkpointed run stopped early on
/// purpose.
pub fn run(args: VectorRunArgs<'_>) -> Result<Option<VectorEstimate>, String> {
    if matches!(args.method, Method::Vegas | Method::VegasPlus) {
        return run_vegas(args).map(Some);
    }
    if matches!(
        args.method,
        Method::Miser | Method::TwoStage | Method::SobolG
    ) {
        return Err(format!(
            "--method {} integrates one output; several integrands or --ratio take \
                 --method plain, rqmc, vegas or vegas-plus",
            args.method
        ));
    }
    let functions = args.functions;
    let dims = functions[0].dims();
    let integrand = |x: &[f64], out: &mut [f64]| evaluate_all(functions, x, out);
    let cube = mcint::pdf::UniformBox::unit(dims).map_err(|e| e.to_string())?;
    let mut integrator = Integrator::over_box_vector(functions.len(), integrand, cube)
        .sampler(args.sampler)
        .seed(args.seed)
        .label(args.label)
        .cancel_token(args.cancel.clone());
    // With a tolerance the run picks its own replicates unless --replicates says otherwise.
    if args.tolerance.is_none() || args.replicates.is_some() {
        integrator = integrator.replicates(args.replicates.unwrap_or(args.default_replicates));
    }
    if let Some(n) = args.samples {
        integrator = integrator.samples(n);
    }
    if let Some(t) = args.threads {
        integrator = integrator.threads(t);
    }
    if let Some(deadline) = args.deadline {
        integrator = integrator.deadline(deadline);
    }
    match (args.tolerance, args.ratio) {
        (Some(t), Some((i, j))) => {
            integrator = integrator.derived_tolerance(Derived::ratio(i, j), t)
        }
        (Some(t), None) => integrator = integrator.tolerance(t),
        (None, _) => {}
    }
    let integrator = crate::ranks::spread!(integrator, args.spread);
    match args.checkpoint {
        None => integrator.run().map(Some).map_err(|e| e.to_string()),
        Some(settings) => checkpoint::run(
            &checkpoint::VectorCheckpoint(&integrator),
            &settings,
            &args.cancel,
        ),
    }
}

/// VEGAS or VEGAS+ over every output together (`--n` evaluations per iteration).
fn run_vegas(args: VectorRunArgs<'_>) -> Result<VectorEstimate, String> {
    if args.replicates.is_some() {
        return Err(format!(
            "--replicates does not apply to --method {} (its error bar combines iterations)",
            args.method.name()
        ));
    }
    if args.checkpoint.is_some() {
        return Err(format!(
            "--checkpoint applies to --method plain and rqmc, not {}",
            args.method.name()
        ));
    }
    let functions = args.functions;
    let integrand = |x: &[f64], out: &mut [f64]| evaluate_all(functions, x, out);
    let cube = mcint::pdf::UniformBox::unit(functions[0].dims()).map_err(|e| e.to_string())?;
    let mut vegas = Vegas::vector(functions.len(), integrand, cube)
        .sampler(args.sampler)
        .stratified(args.method == Method::VegasPlus)
        .seed(args.seed)
        .cancel_token(args.cancel);
    if let Some(n) = args.samples {
        vegas = vegas.samples(n);
    }
    if let Some(t) = args.threads {
        vegas = vegas.threads(t);
    }
    if let Some(deadline) = args.deadline {
        vegas = vegas.deadline(deadline);
    }
    match (args.tolerance, args.ratio) {
        (Some(t), Some((i, j))) => {
            vegas = vegas
                .derived_tolerance(Derived::ratio(i, j), t)
                .iterations(VEGAS_ITERATIONS_TO_TOLERANCE)
        }
        (Some(t), None) => vegas = vegas.tolerance(t).iterations(VEGAS_ITERATIONS_TO_TOLERANCE),
        (None, _) => {}
    }
    crate::ranks::spread!(vegas, args.spread)
        .run()
        .map_err(|e| e.to_string())
}

/// Every function at `x`, output `k` from function `k`.
fn evaluate_all(functions: &[Named], x: &[f64], out: &mut [f64]) {
    for (y, f) in out.iter_mut().zip(functions) {
        *y = f.eval(x);
    }
}

/// Parses `--ratio I,J` against `m` outputs.
pub fn parse_ratio(text: &str, m: usize) -> Result<(usize, usize), String> {
    let bad = || {
        format!(
            "invalid --ratio '{text}': expected two output indices I,J below {m} (positions in \
             the --integrand list, from 0), I != J"
        )
    };
    let (i, j) = text.split_once(',').ok_or_else(bad)?;
    let (i, j): (usize, usize) = (
        i.trim().parse().map_err(|_| bad())?,
        j.trim().parse().map_err(|_| bad())?,
    );
    if i >= m || j >= m || i == j {
        return Err(bad());
    }
    Ok((i, j))
}

/// The report of a vector run.
pub struct VectorReport<'a> {
    pub method: &'a str,
    pub functions: &'a [Named],
    pub sampler: String,
    pub scramble: String,
    pub run: VectorEstimate,
    pub ratio: Option<(usize, usize)>,
    /// MPI ranks the run was spread over (1 without `--mpi`).
    pub ranks: usize,
    pub seconds: f64,
}

impl VectorReport<'_> {
    /// The ratio's estimate and exact value, if one was asked for.
    fn ratio(&self) -> Option<(mcint::Result<mcint::Estimate>, f64)> {
        self.ratio.map(|(i, j)| {
            let exact = self.functions[i].exact() / self.functions[j].exact();
            (self.run.derived(&Derived::ratio(i, j)), exact)
        })
    }

    /// Every output's warnings, with the output they belong to.
    fn output_warnings(&self) -> impl Iterator<Item = (usize, &mcint::stats::Warning)> {
        let outputs = self.run.outputs.iter().enumerate();
        outputs.flat_map(|(k, e)| e.warnings.iter().map(move |w| (k, w)))
    }

    /// The warnings as lines for stderr.
    pub fn warnings(&self) -> Vec<String> {
        self.output_warnings()
            .map(|(k, w)| format!("output {k}: {w}"))
            .collect()
    }

    pub fn print_json(&self) -> Result<(), String> {
        let run = &self.run;
        let m = run.len();
        let number = |v: Option<f64>| v.filter(|v| v.is_finite());
        let covariance: Option<Vec<Vec<f64>>> = run
            .covariance_matrix
            .as_ref()
            .map(|c| c.chunks(m).map(<[f64]>::to_vec).collect());
        let mut json = serde_json::json!({
            "method": self.method,
            "families": self.functions.iter().map(TestFunction::name).collect::<Vec<_>>(),
            "dims": self.functions[0].dims(),
            "sampler": self.sampler,
            "scramble": self.scramble,
            "estimates": run.outputs.iter().map(|e| e.mean).collect::<Vec<_>>(),
            "std_errors": run.outputs.iter().map(|e| number(e.std_error)).collect::<Vec<_>>(),
            "exact": self.functions.iter().map(|f| f.exact()).collect::<Vec<_>>(),
            "covariance": covariance,
            "n": run.outputs[0].n,
            "replicates": run.outputs[0].replicates,
            "evaluations": run.evaluations,
            "converged": run.converged,
            "stop": stop_name(run.stop),
            "iterations": run.iterations,
            // As a scalar run has them, with the output each belongs to.
            "warnings": self.output_warnings().map(|(k, w)| serde_json::json!({
                "kind": w.kind(),
                "message": w.to_string(),
                "output": k,
            })).collect::<Vec<_>>(),
            "ranks": self.ranks,
            "seconds": self.seconds,
        });
        if let Some((estimate, exact)) = self.ratio() {
            let estimate = estimate.map_err(|e| e.to_string())?;
            json["ratio"] = serde_json::json!({
                "numerator": self.ratio.map(|r| r.0),
                "denominator": self.ratio.map(|r| r.1),
                "estimate": estimate.mean,
                "std_error": number(estimate.std_error),
                "exact": exact,
            });
        }
        say!("{json}");
        Ok(())
    }

    pub fn print_text(&self) -> Result<(), String> {
        let run = &self.run;
        say!(
            "{} outputs over the same points: {} in {} dimensions",
            run.len(),
            self.functions
                .iter()
                .map(TestFunction::name)
                .collect::<Vec<_>>()
                .join(", "),
            self.functions[0].dims()
        );
        say!(
            "method {}, sampler {}, scramble {}, {} {}, {} evaluations",
            self.method,
            self.sampler,
            self.scramble,
            run.outputs[0].replicates,
            if self.method.starts_with("vegas") {
                "iterations combined"
            } else {
                "replicates"
            },
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
        if let Some((estimate, exact)) = self.ratio() {
            let (i, j) = self.ratio.unwrap_or_default();
            let estimate = estimate.map_err(|e| e.to_string())?;
            let se = estimate
                .std_error
                .map_or("none".into(), |s| format!("{s:.3e}"));
            say!(
                "ratio {i}/{j}  {:>20.12e} {exact:>20.12e} {se:>10} (delta method)",
                estimate.mean
            );
        }
        if let Some(converged) = run.converged {
            say!(
                "tolerance {} ({}, {} stage{})",
                if converged { "met" } else { "NOT met" },
                stop_name(run.stop),
                run.iterations,
                if run.iterations == 1 { "" } else { "s" }
            );
        }
        say!("time {:.3} s", self.seconds);
        Ok(())
    }
}
