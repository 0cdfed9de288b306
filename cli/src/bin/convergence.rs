//! RMSE against the number of points, on log-log axes, for several samplers on the test
//! integrands graphics papers use (disk, Gaussian, bilinear, step, triangle) and on two Genz
//! families, with the fitted slopes printed as a table.
//!
//! ```text
//! cargo run --release --bin convergence -- --out DIR [--passes R] [--max-log2 M]
//!     [--seed S] [--format png|svg] [--publication]
//! ```
//! Point counts run over powers of two from 2^4 to 2^M (default 12; jittered 2-D uses the
//! nearest squares `k^2`, with `k` never a multiple of 3), each with `R` independent passes (default 32). `--publication`
//! uses `M = 16` and `R = 128` (a few minutes instead of seconds). One plot per integrand
//! goes into DIR, with dashed reference slopes; the slope table is printed and written to
//! `DIR/slopes.md`.

use indicatif::{ProgressBar, ProgressStyle};
use mcint::quality::{Convergence, ConvergenceStudy};
use mcint::sampler::{Sampler, SamplerKind};
use mcint::testfns::{Genz, GenzFamily, GraphicsIntegrand, TestFunction};
use mcint_cli::args as support;
use mcint_cli::plot;
use mcint_cli::say;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use support::Args;

/// What `--help` says the program does.
const ABOUT: &str =
    "RMSE against the number of points, log-log, for several samplers on test integrands.";

const SPEC: support::Spec = &[
    ("out", true, "directory for the figures"),
    (
        "passes",
        true,
        "independent passes per point count (RMSE over them)",
    ),
    ("max-log2", true, "largest point count, as a power of two"),
    support::SEED,
    ("format", true, "png (default) or svg"),
    support::PUBLICATION,
];

/// Smallest point count: 2^4.
const MIN_LOG2: u32 = 4;
/// Dimension of the Genz cases.
const GENZ_DIMS: usize = 4;

fn main() {
    support::finish(run());
}

/// One integrand, the samplers compared on it and the slopes drawn for reference.
struct Case {
    name: String,
    function: Box<dyn TestFunction>,
    samplers: Vec<SamplerKind>,
    reference_slopes: Vec<f64>,
}

fn cases() -> Result<Vec<Case>, String> {
    let two_d = vec![
        SamplerKind::Independent,
        SamplerKind::Jittered,
        SamplerKind::Latin,
        SamplerKind::Sobol,
        SamplerKind::Pmj02,
        SamplerKind::Halton,
    ];
    let mut cases: Vec<Case> = GraphicsIntegrand::ALL
        .into_iter()
        .map(|g| Case {
            name: g.name().to_string(),
            function: Box::new(g),
            samplers: two_d.clone(),
            reference_slopes: if g.is_smooth() {
                vec![-0.5, -1.0, -1.5]
            } else {
                vec![-0.5, -0.75]
            },
        })
        .collect();
    for family in [GenzFamily::Gaussian, GenzFamily::Oscillatory] {
        cases.push(Case {
            name: format!("genz-{family}-{GENZ_DIMS}d"),
            function: Box::new(
                Genz::with_defaults(family, GENZ_DIMS).map_err(support::flag_error)?,
            ),
            samplers: vec![
                SamplerKind::Independent,
                SamplerKind::Latin,
                SamplerKind::Sobol,
                SamplerKind::Halton,
                SamplerKind::Lattice,
            ],
            reference_slopes: vec![-0.5, -1.0, -1.5],
        });
    }
    Ok(cases)
}

/// The point counts of a sampler: powers of two, or the nearest `k^d` for jittered points.
fn sizes(kind: SamplerKind, dims: usize, max_log2: u32) -> Vec<u64> {
    let mut sizes: Vec<u64> = (MIN_LOG2..=max_log2)
        .map(|m| {
            if kind == SamplerKind::Jittered {
                let k = 2f64.powf(f64::from(m) / dims as f64).round() as u64;
                // A multiple of 3 would put a stratum edge on the step at x = 1/3, and a
                // jittered estimate of it would be exact.
                let k = if k.is_multiple_of(3) { k + 1 } else { k };
                k.pow(dims as u32)
            } else {
                1 << m
            }
        })
        .collect();
    sizes.dedup();
    sizes
}

fn run() -> Result<(), String> {
    let args = Args::parse(ABOUT, SPEC)?;
    let out: PathBuf = args.folder("out", "the folder to write the plots into")?;
    let publication = args.has("publication");
    let passes: u64 = args
        .get("passes", "a whole number from 2 to 2^20")?
        .unwrap_or(if publication { 128 } else { 32 });
    // The library's bound, checked before the folder is made.
    if !(2..=1 << 20).contains(&passes) {
        return Err(format!(
            "invalid --passes = {passes}: expected 2 to 2^20 independent passes per point count"
        ));
    }
    let max_log2: u32 = args
        .get("max-log2", "a whole number from 6 to 24")?
        .unwrap_or(if publication { 16 } else { 12 });
    if !(6..=24).contains(&max_log2) {
        return Err(format!("invalid --max-log2 = {max_log2}: expected 6 to 24"));
    }
    let seed: u64 = args.get("seed", "a whole number")?.unwrap_or(2018);
    let format: String = args
        .get::<String>("format", "png or svg")?
        .unwrap_or_else(|| "png".into());
    if format != "png" && format != "svg" {
        return Err(format!(
            "invalid --format = '{format}': expected png or svg"
        ));
    }
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create '{}': {e}", out.display()))?;

    let cases = cases()?;
    let studies_total: u64 = cases.iter().map(|c| c.samplers.len() as u64).sum();
    let progress = ProgressBar::new(studies_total * 1000).with_style(
        ProgressStyle::with_template("{bar:30} {percent}% {msg}").map_err(|e| e.to_string())?,
    );
    let mut table = String::from("| integrand |");
    let samplers_in_table = [
        SamplerKind::Independent,
        SamplerKind::Jittered,
        SamplerKind::Latin,
        SamplerKind::Sobol,
        SamplerKind::Pmj02,
        SamplerKind::Halton,
        SamplerKind::Lattice,
    ];
    for kind in samplers_in_table {
        let _ = write!(table, " {} |", kind.name());
    }
    table.push_str("\n|---|");
    table.push_str(&"---|".repeat(samplers_in_table.len()));
    table.push('\n');
    let mut done = 0u64;
    for case in &cases {
        let mut studies = Vec::new();
        for &kind in &case.samplers {
            progress.set_message(format!("{} / {}", case.name, kind.name()));
            let study = study(case, kind, passes, max_log2, seed, &progress, done)?;
            done += 1;
            progress.set_position(done * 1000);
            studies.push((kind, study));
        }
        let _ = write!(table, "| {} |", case.name);
        for kind in samplers_in_table {
            match studies.iter().find(|(k, _)| *k == kind) {
                Some((_, s)) => {
                    let _ = write!(table, " {:.2} ± {:.2} |", s.slope, s.slope_std_error);
                }
                None => table.push_str(" |"),
            }
        }
        table.push('\n');
        draw(case, &studies, &out.join(format!("{}.{format}", case.name)))?;
    }
    progress.finish_and_clear();
    let caption = format!(
        "Fitted log-log slopes of the RMSE (± standard error), {passes} passes, N = 2^{MIN_LOG2} \
         to 2^{max_log2}, seed {seed}.\n\n"
    );
    let path = out.join("slopes.md");
    std::fs::write(&path, format!("{caption}{table}"))
        .map_err(|e| format!("cannot write '{}': {e}", path.display()))?;
    say!("{caption}{}", table.trim_end_matches('\n'));
    Ok(())
}

fn study(
    case: &Case,
    kind: SamplerKind,
    passes: u64,
    max_log2: u32,
    seed: u64,
    progress: &ProgressBar,
    done: u64,
) -> Result<ConvergenceStudy, String> {
    let dims = case.function.dims();
    let report = |points: u64, total: u64| {
        progress.set_position(done * 1000 + points * 1000 / total.max(1));
    };
    Convergence::new(&*case.function, &sizes(kind, dims, max_log2))
        .passes(passes)
        .seed(seed)
        .progress(&report)
        .run(|n, s| -> mcint::Result<Box<dyn Sampler>> {
            kind.build_with(dims, n, kind.default_scramble(), None, s)
        })
        .map_err(|e| {
            let e = support::spec_error(SPEC, &[], e);
            format!("{} with {}: {e}", case.name, kind.name())
        })
}

fn draw(
    case: &Case,
    studies: &[(SamplerKind, ConvergenceStudy)],
    path: &Path,
) -> Result<(), String> {
    let series: Vec<plot::Series> = studies
        .iter()
        .map(|(kind, s)| plot::Series {
            name: format!("{} ({:.2})", kind.name(), s.slope),
            points: s.points.iter().map(|p| (p.n as f64, p.rmse)).collect(),
        })
        .collect();
    plot::loglog(
        path,
        &format!("RMSE of the estimate: {}", case.name),
        "points N",
        "RMSE",
        &series,
        &case.reference_slopes,
    )
}
