//! The README's first demonstration: a few integrals done several ways, with the true error
//! next to the reported standard error.
//!
//! ```text
//! cargo run --release -p mcint-demo
//! ```
//! It takes no flags. It is a crate of its own so that it builds with the library alone (no
//! dev-dependencies, no serde): the fewest crates a first build compiles.

use mcint::estimator::{ImportanceEstimator, UniformEstimator};
use mcint::pdf::{Exponential, Pdf1d, ProductPdf, TruncatedNormal, UniformBox};
use mcint::sampler::{Independent, Jittered, LatinHypercube, Lattice, Sampler, Scramble, Sobol};
use mcint::testfns::{Genz, GenzFamily, TestFunction};
use mcint::{Estimate, Estimator, Integrator, Result};
use std::time::Instant;

/// Writes a line to stdout; a closed pipe (`| head`) ends the program quietly, another write
/// error with one line and status 2, as the CLI programs do (`println!` panicked).
macro_rules! say {
    ($($arg:tt)*) => {
        write_line(format_args!($($arg)*))
    };
}

fn write_line(args: std::fmt::Arguments) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.write_all(b"\n")) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        fail(format!("cannot write the table: {e}"));
    }
}

/// Points per replicate and replicates: about a million samples per method.
const POINTS: u64 = 1 << 16;
const REPLICATES: u64 = 16;

fn main() {
    if let Some(flag) = std::env::args().nth(1) {
        if flag == "--help" || flag == "-h" {
            say!(
                "Integrates a few functions several ways (independent, stratified and \
                 quasi-random points, importance sampling) and prints each estimate with its \
                 standard error and true error.\n\nUsage: quickstart (it takes no flags)"
            );
            return;
        }
        fail(format!(
            "unexpected argument '{flag}' (quickstart takes no flags but --help)"
        ));
    }
    if let Err(e) = run() {
        fail(e);
    }
}

/// Prints `error: message` and exits with status 2.
fn fail(message: impl std::fmt::Display) -> ! {
    eprintln!("error: {message}");
    std::process::exit(2)
}

fn run() -> Result<()> {
    say!(
        "{:<26} {:<36} {:>15} {:>15} {:>9} {:>9} {:>8} {:>7}",
        "integrand",
        "method",
        "estimate",
        "exact",
        "|error|",
        "std err",
        "samples",
        "time"
    );

    // 1. The integral of x^2 e^-x over [0, 10]: exact 2 - 122 e^-10.
    let name = "x^2 e^-x on [0,10]";
    let exact = 2.0 - 122.0 * (-10f64).exp();
    let f = |x: &[f64]| x[0] * x[0] * (-x[0]).exp();
    let interval = UniformBox::new(vec![0.0], vec![10.0])?;
    let uniform = UniformEstimator::new(f, interval.clone());
    row(
        name,
        "uniform, independent (A.14)",
        exact,
        &uniform,
        Independent::new(1, 1)?,
    )?;
    row(
        name,
        "uniform, jittered 1D (A.30)",
        exact,
        &uniform,
        Jittered::new(1, POINTS, 1)?,
    )?;
    // Importance sampling helps only when the pdf has the integrand's shape (Figure A.2):
    // e^-x misses the x^2 factor and does worse than uniform; e^(-x/2) is closer and helps.
    let poor = ImportanceEstimator::new(f, Exponential::new(1.0, 0.0, 10.0)?);
    row(
        name,
        "importance e^-x (A.19), poor match",
        exact,
        &poor,
        Independent::new(1, 1)?,
    )?;
    let better = ImportanceEstimator::new(f, Exponential::new(0.5, 0.0, 10.0)?);
    row(
        name,
        "importance e^(-x/2), better match",
        exact,
        &better,
        Independent::new(1, 1)?,
    )?;
    row(
        name,
        "importance e^(-x/2), jittered",
        exact,
        &better,
        Jittered::new(1, POINTS, 1)?,
    )?;

    // 2. Genz Gaussian in 4 dimensions.
    let gaussian = Genz::with_defaults(GenzFamily::Gaussian, 4)?;
    let name = "genz gaussian, d = 4";
    let g = |x: &[f64]| gaussian.eval(x);
    let uniform = UniformEstimator::new(g, UniformBox::unit(4)?);
    row(
        name,
        "uniform, independent",
        gaussian.exact(),
        &uniform,
        Independent::new(4, 2)?,
    )?;
    row(
        name,
        "uniform, jittered 16^4",
        gaussian.exact(),
        &uniform,
        Jittered::new(4, 16, 2)?,
    )?;
    row(
        name,
        "uniform, latin hypercube",
        gaussian.exact(),
        &uniform,
        LatinHypercube::new(4, POINTS, 2)?,
    )?;
    row(
        name,
        "uniform, sobol owen-scrambled",
        gaussian.exact(),
        &uniform,
        Sobol::new(4, Scramble::Owen, 2)?,
    )?;
    row(
        name,
        "uniform, lattice shifted",
        gaussian.exact(),
        &uniform,
        Lattice::new(4, Scramble::Shift, 2)?,
    )?;
    // Each factor exp(-a^2 (x-u)^2) is a normal density with sd 1/(a sqrt 2); a proposal
    // 25% wider than that is close to, but not exactly, the integrand's shape.
    let proposal: Vec<Box<dyn Pdf1d>> = gaussian
        .a()
        .iter()
        .zip(gaussian.u())
        .map(|(&a, &u)| -> Result<Box<dyn Pdf1d>> {
            let sd = 1.25 / (a * std::f64::consts::SQRT_2);
            Ok(Box::new(TruncatedNormal::new(u, sd, 0.0, 1.0)?))
        })
        .collect::<Result<_>>()?;
    let importance = ImportanceEstimator::new(g, ProductPdf::new(proposal)?);
    row(
        name,
        "importance, truncated normals",
        gaussian.exact(),
        &importance,
        Independent::new(4, 2)?,
    )?;

    // 3. Genz oscillatory in 8 dimensions.
    let oscillatory = Genz::with_defaults(GenzFamily::Oscillatory, 8)?;
    let name = "genz oscillatory, d = 8";
    let h = |x: &[f64]| oscillatory.eval(x);
    let uniform = UniformEstimator::new(h, UniformBox::unit(8)?);
    row(
        name,
        "uniform, independent",
        oscillatory.exact(),
        &uniform,
        Independent::new(8, 3)?,
    )?;
    row(
        name,
        "uniform, jittered 4^8",
        oscillatory.exact(),
        &uniform,
        Jittered::new(8, 4, 3)?,
    )?;
    row(
        name,
        "uniform, latin hypercube",
        oscillatory.exact(),
        &uniform,
        LatinHypercube::new(8, POINTS, 3)?,
    )?;
    row(
        name,
        "uniform, sobol owen-scrambled",
        oscillatory.exact(),
        &uniform,
        Sobol::new(8, Scramble::Owen, 3)?,
    )?;
    row(
        name,
        "uniform, lattice shifted",
        oscillatory.exact(),
        &uniform,
        Lattice::new(8, Scramble::Shift, 3)?,
    )?;

    say!(
        "\nstd err: from the per-sample variance for independent points, and from the spread of \
         {REPLICATES} independently randomized replicates otherwise (their samples are not independent)."
    );
    say!(
        "A.x: equations of W. Jarosz, \"Efficient Monte Carlo Methods for Light Transport in \
         Scattering Media\", PhD dissertation, UC San Diego, 2008, Appendix A."
    );
    Ok(())
}

/// Integrates with `REPLICATES x POINTS` samples and prints one table row.
fn row<E: Estimator>(
    integrand: &str,
    method: &str,
    exact: f64,
    estimator: &E,
    sampler: impl Sampler + 'static,
) -> Result<()> {
    let started = Instant::now();
    let estimate: Estimate = Integrator::new(estimator)
        .sampler(sampler)
        .samples(POINTS)
        .replicates(REPLICATES)
        .seed(2024)
        .run()?;
    let seconds = started.elapsed().as_secs_f64();
    let std_error = estimate
        .std_error
        .map_or("none".to_string(), |s| format!("{s:.2e}"));
    say!(
        "{integrand:<26} {method:<36} {:>15.10} {exact:>15.10} {:>9.2e} {std_error:>9} {:>8} {:>6.3}s",
        estimate.mean,
        (estimate.mean - exact).abs(),
        estimate.n,
        seconds
    );
    for warning in &estimate.warnings {
        eprintln!("warning ({integrand}, {method}): {warning}");
    }
    Ok(())
}
