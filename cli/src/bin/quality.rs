//! Measures the quality of a point set read from a CSV file and prints the value alone on one
//! line.
//!
//! ```text
//! cargo run --release --bin quality -- --input FILE
//!     --measure l2-star|centered|wrap-around|mixture|star|t-value [--squared]
//! ```
//! FILE holds one point per line, coordinates in `[0, 1]` separated by commas, as the `points`
//! example writes it (`--format csv`). The L2 measures print the discrepancy itself (the root;
//! see `mcint::quality`); `--squared` prints its square instead, which for `centered`,
//! `wrap-around` and `mixture` is what `scipy.stats.qmc.discrepancy` returns for `CD`, `WD`
//! and `MD`. `star` is the exact star discrepancy, for one- or two-dimensional sets.
//! `t-value` is the quality parameter `t` of a base-2 net. The L2 measures are exact and cost
//! `N^2 d`: sets beyond `2^36` such terms (about a minute) are refused. Malformed input (a missing or
//! empty file, ragged rows, something that is not a number, a coordinate outside `[0, 1]`)
//! gives a one-line error on stderr and exit status 2.
//!
//! ```text
//! cargo run --release --bin points -- --sampler sobol --dims 2 --n 1024 --out sobol.csv
//! cargo run --release --bin quality -- --input sobol.csv --measure star
//! ```

use mcint::Points;
use mcint::quality;
use mcint_cli::args as support;
use mcint_cli::say;
use support::Args;

/// What `--help` says the program does.
const ABOUT: &str =
    "Measures the quality of a point set read from a CSV file; prints the value alone.";

const SPEC: support::Spec = &[
    (
        "input",
        true,
        "CSV file of points in [0, 1]^d, one per line",
    ),
    (
        "measure",
        true,
        "l2-star, centered, wrap-around, mixture, star or t-value",
    ),
    ("squared", false, "print the square of an L2 discrepancy"),
];

/// What `--measure` asked for.
enum Choice {
    /// An L2 discrepancy (its root or, with `--squared`, its square).
    L2(mcint::quality::Discrepancy),
    Star,
    TValue,
}

const MEASURES: &str = "l2-star, centered, wrap-around, mixture, star or t-value";

fn main() {
    support::finish(run().map(|value| say!("{value}")));
}

/// The measured value, formatted for printing (`{:?}` of an f64 reads back to the same f64).
fn run() -> Result<String, String> {
    let args = Args::parse(ABOUT, SPEC)?;
    let path: String = args.require("input", "a CSV file of points, one per line")?;
    let measure: String = args.require("measure", MEASURES)?;
    let squared = args.has("squared");
    // Check the flags before reading a possibly large file.
    let choice = match measure.as_str() {
        "l2-star" | "centered" | "wrap-around" | "mixture" => {
            Choice::L2(measure.parse().map_err(|e: mcint::Error| e.to_string())?)
        }
        "star" => Choice::Star,
        "t-value" => Choice::TValue,
        other => {
            return Err(format!(
                "invalid --measure = '{other}': expected {MEASURES}"
            ));
        }
    };
    if squared && !matches!(choice, Choice::L2(..)) {
        return Err(format!(
            "--squared applies to the L2 measures only, not to --measure {measure}"
        ));
    }
    let points = read_points(&path)?;
    let value = match choice {
        Choice::L2(kind) => {
            check_l2_cost(&points)?;
            if squared {
                kind.squared(&points)
            } else {
                kind.root(&points)
            }
        }
        Choice::Star => quality::star_discrepancy(&points),
        Choice::TValue => return t_value(&points),
    };
    value.map(|v| format!("{v:?}")).map_err(about_input)
}

/// The most pair-coordinate terms, `N^2 d`, an L2 discrepancy may take: 2^36, about a
/// minute on one thread.
const MAX_L2_TERMS: f64 = (1u64 << 36) as f64;

/// Refuses a set whose L2 discrepancy would take hours: the exact form costs `N^2 d`.
fn check_l2_cost(points: &Points) -> Result<(), String> {
    let (n, d) = (points.len() as f64, points.dims() as f64);
    let terms = n * n * d;
    if terms > MAX_L2_TERMS {
        return Err(format!(
            "invalid --input: {} points in {} dimensions cost N^2 d = {terms:.3e} terms for \
             an L2 discrepancy (exact, one thread): expected at most 2^36 = {MAX_L2_TERMS:.3e} \
             (about a minute), so at most {} points in {} dimensions; measure a subset",
            points.len(),
            points.dims(),
            (MAX_L2_TERMS / d).sqrt().floor(),
            points.dims()
        ));
    }
    Ok(())
}

/// A library error about the points as one line that says they come from `--input`.
fn about_input(error: mcint::Error) -> String {
    error.message_with_names(&[("dims", "dimension of the --input points")])
}

/// The t-value of a base-2 net (the smallest `t` for which the set is a `(t, m, d)`-net).
fn t_value(points: &Points) -> Result<String, String> {
    quality::t_value(points)
        .map(|t| t.to_string())
        .map_err(about_input)
}

/// Reads a CSV file of points (one per line, comma-separated coordinates in `[0, 1]`).
fn read_points(path: &str) -> Result<Points, String> {
    let text = mcint_cli::input::read_text(path, "input")?;
    // A final newline (or several) is not an empty point.
    let body = text.trim_end();
    if body.is_empty() {
        return Err(format!("'{path}' holds no points"));
    }
    let mut dims = 0;
    let mut rows = 0;
    let mut values = Vec::new(); // row-major
    for (index, line) in body.lines().enumerate() {
        let line_number = index + 1;
        let mut count = 0;
        for (column, field) in line.split(',').enumerate() {
            let field = field.trim();
            let x: f64 = field.parse().map_err(|_| {
                format!(
                    "{path}, line {line_number}, column {}: '{field}' is not a number",
                    column + 1
                )
            })?;
            if !(0.0..=1.0).contains(&x) {
                return Err(format!(
                    "{path}, line {line_number}, column {}: {x} is outside [0, 1]",
                    column + 1
                ));
            }
            values.push(x);
            count += 1;
        }
        if index == 0 {
            dims = count;
        } else if count != dims {
            return Err(format!(
                "{path}, line {line_number}: {count} coordinates, but line 1 has {dims}"
            ));
        }
        rows += 1;
    }
    let mut points = Points::new(dims, rows).map_err(|e| e.to_string())?;
    for (dim, column) in points.columns_mut().enumerate() {
        for (i, x) in column.iter_mut().enumerate() {
            *x = values[i * dims + dim];
        }
    }
    Ok(points)
}
