//! Jarosz's variance-reduction scenarios side by side: for each, every technique's estimate,
//! its standard error, the exact answer, and the variance per integrand evaluation (the
//! variance of the estimate times the evaluations it took), so techniques compare at equal
//! work.
//!
//! ```text
//! cargo run --release --bin variance_reduction [-- --n N] [--seed S] [--time-limit SECONDS]
//! ```
//! With `--time-limit` every run stops at that limit (counted from the start) with the
//! evaluations done, which its warning names; the rows not reached are left out and the
//! table says where it stopped.
//! 1. Importance sampling (A.19, Figure A.2, A.23-A.24): a Gaussian bump sampled uniformly,
//!    from a density of similar shape, from one of the wrong shape (more variance than
//!    uniform), and from the density proportional to it (zero variance).
//! 2. A product `f = g h` (A.25) and multiple importance sampling (Veach & Guibas 1995): a
//!    glossy reflection `g` (a sharp lobe plus a diffuse floor) times a broad light `h`.
//!    Sampling the lobe misses the floor, sampling the light misses the lobe, MIS combines
//!    both; sampling all of `g` exactly (A.25) is the ideal when `g` is fully known.
//! 3. Control variates (A.26-A.29): `e^x` with the control `1 + x`, with Jarosz's
//!    coefficient 1, with the least-squares coefficient, with two controls, and antithetic
//!    pairs for comparison.

use mcint::estimator::{
    Estimator, FixedControlVariate, ImportanceEstimator, MisHeuristic, MultiSampleMis,
    OneSampleMis, ProductImportanceEstimator, UniformEstimator,
};
use mcint::pdf::{Exponential, Linear, Mixture, Normal, Pdf, Pdf1d, TruncatedNormal, UniformBox};
use mcint::sampler::{Antithetic, Independent};
use mcint::{Estimate, Integrator};
use mcint_cli::args as support;
use mcint_cli::{note, say};
use support::Args;

/// What `--help` says the program does.
const ABOUT: &str = "Jarosz's variance-reduction scenarios: every technique's estimate, standard error and variance per evaluation.";

const SPEC: support::Spec = &[
    ("n", true, "evaluations per technique"),
    support::SEED,
    support::TIME_LIMIT,
];

fn main() {
    support::finish(run());
}

fn run() -> Result<(), String> {
    let args = Args::parse(ABOUT, SPEC)?;
    let n: u64 = args
        .get("n", "a whole, even number of samples >= 4")?
        .unwrap_or(1 << 16);
    if n < 4 || n % 2 == 1 {
        return Err(format!(
            "--n {n} is not allowed: use a whole, even number of samples >= 4"
        ));
    }
    let seed: u64 = args.get("seed", "a whole number")?.unwrap_or(1);
    let table = Table {
        n,
        seed,
        deadline: args.deadline()?,
    };
    let all = importance_sampling(&table)
        .and_then(|()| product_and_mis(&table))
        .and_then(|()| control_variates(&table));
    match all {
        Err(mcint::Error::Interrupted { stop, .. }) => {
            say!(
                "\nstopped ({}): the rows not shown were not reached",
                support::stop_name(stop)
            );
            Ok(())
        }
        other => other.map_err(support::flag_error),
    }
}

/// Prints rows of one scenario; every row uses `n` integrand evaluations and `seed`, and
/// stops by `deadline`.
struct Table {
    n: u64,
    seed: u64,
    deadline: Option<std::time::Instant>,
}

impl Table {
    fn header(&self, title: &str, exact: f64) {
        say!("\n{title}");
        say!(
            "exact integral {exact:.10}, {} evaluations per technique",
            self.n
        );
        say!(
            "{:<44} {:>14} {:>11} {:>12} {:>9}",
            "technique",
            "estimate",
            "std error",
            "var/eval",
            "vs first"
        );
    }

    /// Runs `estimator` on independent points, `evaluations` integrand calls per contribution.
    fn run(
        &self,
        estimator: impl Estimator + 'static,
        evaluations: u64,
    ) -> mcint::Result<(Estimate, u64)> {
        let estimate = self
            .limited(Integrator::new(estimator))
            .samples(self.n / evaluations)
            .seed(self.seed)
            .run()?;
        Ok((estimate, evaluations))
    }

    /// `integrator`, stopping by the table's deadline.
    fn limited<E>(&self, integrator: Integrator<E>) -> Integrator<E> {
        match self.deadline {
            Some(deadline) => integrator.deadline(deadline),
            None => integrator,
        }
    }

    fn row(&self, name: &str, (estimate, evaluations): (Estimate, u64), first: &mut Option<f64>) {
        let se = estimate.std_error.unwrap_or(f64::NAN);
        let variance = se * se * (estimate.n * evaluations) as f64;
        let reference = *first.get_or_insert(variance);
        say!(
            "{name:<44} {:>14.10} {se:>11.3e} {variance:>12.4e} {:>9.3}",
            estimate.mean,
            variance / reference
        );
        for warning in &estimate.warnings {
            note!("warning ({name}): {warning}");
        }
    }
}

/// A Gaussian bump on [0, 1]: uniform, similar, wrong and proportional densities.
fn importance_sampling(t: &Table) -> mcint::Result<()> {
    let (centre, width) = (0.3, 0.1);
    let f = move |x: &[f64]| (-0.5 * ((x[0] - centre) / width).powi(2)).exp();
    // The bump's integral through the normal cdf (the inverse of the standard normal warp).
    let normal_cdf = |z: f64| Normal::new(0.0, 1.0).map(|n| n.invert_1d(z));
    let exact = width
        * (2.0 * std::f64::consts::PI).sqrt()
        * (normal_cdf((1.0 - centre) / width)? - normal_cdf(-centre / width)?);
    t.header("1. Importance sampling (A.19; Figure A.2; A.23)", exact);
    let mut first = None;
    let unit = UniformBox::unit(1)?;
    t.row(
        "uniform (A.14)",
        t.run(UniformEstimator::new(f, unit), 1)?,
        &mut first,
    );
    let similar = TruncatedNormal::new(centre, 1.5 * width, 0.0, 1.0)?;
    t.row(
        "similar shape: normal(0.3, 0.15)",
        t.run(ImportanceEstimator::new(f, similar), 1)?,
        &mut first,
    );
    let wrong = TruncatedNormal::new(0.85, 0.1, 0.0, 1.0)?;
    t.row(
        "wrong shape: normal(0.85, 0.1)",
        t.run(ImportanceEstimator::new(f, wrong), 1)?,
        &mut first,
    );
    let exact_pdf = TruncatedNormal::new(centre, width, 0.0, 1.0)?;
    t.row(
        "proportional to f (A.23): zero variance",
        t.run(ImportanceEstimator::new(f, exact_pdf), 1)?,
        &mut first,
    );
    Ok(())
}

/// A glossy reflection times a light: `g` is a sharp lobe plus a diffuse floor, `h` a
/// broad, brighter-to-the-right light. Sampling the lobe alone (as a BRDF sampler would)
/// misses the floor, sampling the light misses the lobe; MIS is good at both. Sampling all
/// of `g` exactly (A.25) is the ideal when `g` is fully known.
fn product_and_mis(t: &Table) -> mcint::Result<()> {
    let (rate, floor) = (10.0, 0.3);
    let lobe = Exponential::new(rate, 0.0, 1.0)?;
    let lobe_density = move |x: f64| rate * (-rate * x).exp() / (1.0 - (-rate).exp());
    let g = move |x: &[f64]| lobe_density(x[0]) + floor;
    let h = |x: &[f64]| 0.1 + 1.9 * x[0];
    let f = move |x: &[f64]| g(x) * h(x);
    // Mean of the truncated exponential on [0, 1]: 1/rate - e^-rate / (1 - e^-rate).
    let lobe_mean = 1.0 / rate - (-rate).exp() / (1.0 - (-rate).exp());
    let exact = (0.1 + 1.9 * lobe_mean) + floor * (0.1 + 1.9 / 2.0);
    t.header(
        "2. Product f = g h (A.25) and multiple importance sampling",
        exact,
    );
    let light = || Linear::new(0.0, 1.0, 0.1, 2.0);
    let techniques = || -> mcint::Result<Vec<(Box<dyn Pdf>, usize)>> {
        Ok(vec![(Box::new(lobe), 1), (Box::new(light()?), 1)])
    };
    let mut first = None;
    t.row(
        "uniform (A.14)",
        t.run(UniformEstimator::new(f, UniformBox::unit(1)?), 1)?,
        &mut first,
    );
    t.row(
        "sample the light h",
        t.run(ImportanceEstimator::new(f, light()?), 1)?,
        &mut first,
    );
    t.row(
        "sample the lobe of g only",
        t.run(ImportanceEstimator::new(f, lobe), 1)?,
        &mut first,
    );
    t.row(
        "MIS, one of each, balance heuristic",
        t.run(
            MultiSampleMis::new(f, techniques()?, MisHeuristic::Balance)?,
            2,
        )?,
        &mut first,
    );
    t.row(
        "MIS, one of each, power heuristic (2)",
        t.run(
            MultiSampleMis::new(f, techniques()?, MisHeuristic::power(2.0)?)?,
            2,
        )?,
        &mut first,
    );
    let one_sample = OneSampleMis::new(
        f,
        vec![Box::new(lobe), Box::new(light()?)],
        vec![0.5, 0.5],
        MisHeuristic::Balance,
    )?;
    t.row(
        "one-sample MIS, balance heuristic",
        t.run(one_sample, 1)?,
        &mut first,
    );
    // pdf_g: exactly proportional to g (lobe plus uniform floor), so f/pdf_g = G h.
    let pdf_g = Mixture::new(
        vec![Box::new(lobe), Box::new(UniformBox::unit(1)?)],
        vec![1.0, floor],
    )?;
    t.row(
        "sample all of g, average G h (A.25)",
        t.run(ProductImportanceEstimator::new(h, pdf_g, 1.0 + floor)?, 1)?,
        &mut first,
    );
    Ok(())
}

/// `e^x` on [0, 1] with the control `1 + x` (its first Taylor terms).
fn control_variates(t: &Table) -> mcint::Result<()> {
    let f = |x: &[f64]| x[0].exp();
    let g = |x: &[f64]| 1.0 + x[0];
    let exact = std::f64::consts::E - 1.0;
    t.header(
        "3. Control variates (A.26-A.29) and antithetic pairs",
        exact,
    );
    let unit = || UniformBox::unit(1);
    let mut first = None;
    t.row(
        "uniform (A.14)",
        t.run(UniformEstimator::new(f, unit()?), 1)?,
        &mut first,
    );
    t.row(
        "control 1 + x, coefficient 1 (A.27)",
        t.run(FixedControlVariate::new(f, g, 1.5, unit()?)?, 1)?,
        &mut first,
    );
    for (name, controls) in [
        ("control 1 + x, least-squares coefficient", 1),
        ("controls 1 + x and x^2, least squares", 2),
    ] {
        let mut runner = Integrator::with_controls(f, unit()?).control(g, 1.5);
        if controls == 2 {
            runner = runner.control(|x: &[f64]| x[0] * x[0], 1.0 / 3.0);
        }
        let estimate = t.limited(runner).samples(t.n).seed(t.seed).run()?;
        t.row(name, (estimate, 1), &mut first);
    }
    // Antithetic pairs are dependent: each pair is one replicate, so the error bar comes
    // from the spread of pair means.
    let antithetic = t
        .limited(Integrator::new(UniformEstimator::new(f, unit()?)))
        .sampler(Antithetic::new(Independent::new(1, t.seed)?)?)
        .samples(2)
        .replicates(t.n / 2)
        .seed(t.seed)
        .run()?;
    t.row("antithetic pairs (x, 1 - x)", (antithetic, 1), &mut first);
    Ok(())
}
