//! Writes the points of a sampler, as CSV (exact round-trip text) or little-endian f64.
//!
//! ```text
//! cargo run --release --bin points -- --sampler latin --dims 2 --n 16 [--seed S] [--pass P]
//!     [--scramble none|xor|lms|owen|permute|shift] [--strength T] [--format csv|bin|sum|svg|png]
//!     [--pairs] [--out FILE] [--measure gaussian [--mean m1,m2,..] [--cov FILE]
//!     [--factorization cholesky|pca]]
//! ```
//! `--n` is the number of points written; for samplers with fixed passes it is also the pass
//! size (jittered needs `k^dims`, hammersley uses it as the set size). `--pass P` writes the
//! first `n` points of pass `P`, an independent randomization. `--scramble` applies to sobol
//! (default owen), halton and hammersley (default permute) and lattice (default shift);
//! `--strength` to oa-bush (default 3). Samplers: independent, jittered, latin, sobol, halton,
//! hammersley, lattice, multijitter, cmj, oa-bose, oa-bush, nrooks-multistage, poisson,
//! best-candidate, pmj02.
//!
//! `--format sum` generates the points through the same batch `fill` path and prints only the
//! sum of each coordinate (one line per dimension, `{:?}` of the f64 sum accumulated in index
//! order), so a whole-process run measures generation alone.
//!
//! `--measure gaussian` maps the points to the normal law with `--mean` (default 0) and the
//! covariance in `--cov FILE` (`d` rows of `d` numbers separated by commas or spaces; default
//! the identity), by inverse cdfs and the `--factorization` of the covariance (default
//! `cholesky`; `pca` orders the principal components first), as scipy's
//! `MultivariateNormalQMC` does with its inverse transform: quasi-random points stay
//! quasi-random.
//!
//! `--format svg` or `png` draws the first two dimensions (with `--pairs`, every pairwise
//! projection) into `--out FILE`, whose name must end in `.svg` or `.png` accordingly.

use mcint::Points;
use mcint::measure::{FACTOR_MAX_DIMS, Factorization, Gaussian, Measure};
use mcint::sampler::{PassKind, SamplerKind};
use mcint_cli::args as support;
use mcint_cli::note;
use mcint_cli::output;
use mcint_cli::plot;
use std::io::{BufWriter, Write};
use support::Args;

/// What `--help` says the program does.
const ABOUT: &str =
    "Writes the points of a sampler as CSV (exact round-trip text), binary f64, or their sum.";

const SPEC: support::Spec = &[
    support::SAMPLER,
    support::DIMS,
    (
        "n",
        true,
        "number of points written (the pass size for samplers with fixed passes)",
    ),
    support::SEED,
    (
        "pass",
        true,
        "write the first n points of this pass (an independent randomization)",
    ),
    support::SCRAMBLE,
    support::STRENGTH,
    (
        "format",
        true,
        "csv (default), bin (little-endian f64), sum (coordinate sums), svg or png",
    ),
    (
        "pairs",
        false,
        "with svg or png: draw every pairwise projection",
    ),
    ("out", true, "output file (svg and png need one)"),
    ("measure", true, "gaussian: map the points to a normal law"),
    (
        "mean",
        true,
        "mean vector m1,m2,.. of --measure gaussian (default 0)",
    ),
    (
        "cov",
        true,
        "file with the covariance matrix of --measure gaussian (default the identity)",
    ),
    ("factorization", true, "cholesky (default) or pca"),
];

/// The most dimensions whose pairwise projections `--pairs` draws (120 panels).
const MAX_PAIR_DIMS: usize = 16;

fn main() {
    support::finish(run());
}

fn run() -> Result<(), String> {
    let args = Args::parse(ABOUT, SPEC)?;
    let name: String = args.require(
        "sampler",
        "a sampler name such as independent, jittered, latin",
    )?;
    let dims: usize = args.require("dims", "a whole number of dimensions >= 1")?;
    let n: u64 = args.require("n", "a whole number of points >= 1")?;
    let seed: u64 = args.get("seed", "a whole number")?.unwrap_or(0);
    let pass: u64 = args.get("pass", "a whole number")?.unwrap_or(0);
    let format: String = args
        .get("format", "csv, bin, svg or png, or sum")?
        .unwrap_or_else(|| "csv".into());
    if !["csv", "bin", "sum", "svg", "png"].contains(&format.as_str()) {
        return Err(format!(
            "invalid --format = '{format}': expected csv, bin, svg or png, or sum (coordinate sums)"
        ));
    }
    let image = format == "svg" || format == "png";
    if image && n > MAX_DRAWN_POINTS {
        return Err(format!(
            "invalid --n = {n}: at most {MAX_DRAWN_POINTS} points can be drawn"
        ));
    }
    if image && args.has("pairs") && dims > MAX_PAIR_DIMS {
        return Err(format!(
            "invalid --dims = {dims} with --pairs: at most {MAX_PAIR_DIMS} dimensions \
             ({} projections) can be drawn",
            MAX_PAIR_DIMS * (MAX_PAIR_DIMS - 1) / 2
        ));
    }
    if image && dims < 2 && !args.has("pairs") {
        return Err(
            "--format svg or png draws dimensions 0 and 1: needs --dims 2 or more \
                    (or --pairs)"
                .into(),
        );
    }
    if n == 0 {
        return Err("invalid --n = 0: expected at least 1 point".into());
    }
    let gaussian = gaussian(&args, dims)?;
    if gaussian.is_some() && image {
        return Err("--measure writes numbers: use --format csv, bin or sum".into());
    }
    let kind: SamplerKind = name.parse().map_err(support::flag_error)?;
    let scramble = args.scramble_for(kind)?;
    let strength: Option<u32> = args.get("strength", "a whole number >= 1 (oa-bush)")?;
    let sampler = kind
        .build_with(dims, n, scramble, strength, seed)
        .map_err(support::flag_error)?;
    let pass_length = match sampler.passes() {
        PassKind::Independent => n,
        PassKind::Fixed { size } => size,
        PassKind::Extensible { max } => {
            if n > max {
                return Err(format!(
                    "invalid --n = {n}: at most {max} points per pass for {name}"
                ));
            }
            max
        }
    };
    // As scipy does: a count that breaks the points' balance is written, with a warning.
    if let Some(base) = sampler.unbalanced_by(n) {
        note!(
            "warning: {n} points break the balance of the {name} sampler, whose points are \
             nets only in blocks of a whole power of {base}"
        );
    }
    let start = pass
        .checked_mul(pass_length)
        .ok_or("--pass is too large: the first index overflows 64 bits")?;
    if image {
        let path: String = args.require("out", "the image file to write")?;
        if !path.ends_with(&format!(".{format}")) {
            return Err(format!(
                "invalid --out = '{path}': a --format {format} image needs a name ending in .{format}"
            ));
        }
        let columns = collect_columns(&*sampler, start, n, dims)?;
        let title = format!("{name}, {n} points, seed {seed}, pass {pass}");
        let path = std::path::Path::new(&path);
        return if args.has("pairs") {
            plot::pairs(path, &title, &columns)
        } else {
            let xy: Vec<(f64, f64)> = columns[0]
                .iter()
                .copied()
                .zip(columns[1].iter().copied())
                .collect();
            plot::scatter(path, &title, &xy, None)
        };
    }
    let out: Box<dyn Write> = match args.get::<String>("out", "a file path")? {
        Some(path) => Box::new(
            std::fs::File::create(&path).map_err(|e| format!("cannot create '{path}': {e}"))?,
        ),
        None => Box::new(std::io::stdout().lock()),
    };
    let mut out = BufWriter::new(out);
    // Generate in blocks through the batch path, and write row by row. A block of about 2^18
    // values (2 MiB) stays in a core's L2 cache between the fill and the sums; 4096 points
    // at 256 dimensions (8 MiB) do not (the whole `--format sum` run took 27 ms, not 20).
    let block_len = (BLOCK_VALUES / dims as u64).clamp(256, 4096);
    // A whole block is allocated up front: a dimension beyond what memory holds is refused
    // here, before anything is written.
    let mut block = Points::new(dims, (n.min(block_len)) as usize).map_err(support::flag_error)?;
    let mut sums = vec![0.0f64; dims];
    let mut written = 0u64;
    while written < n {
        let len = (n - written).min(block_len);
        block.set_len(len as usize);
        sampler
            .fill(start + written, &mut block)
            .map_err(support::flag_error)?;
        if let Some(g) = &gaussian {
            map_block(g, &mut block);
        }
        if format == "sum" {
            add_columns(&mut sums, &block);
        } else {
            write_block(&mut out, &block, &format)
                .unwrap_or_else(|e| output::exit_on_write_error(e));
        }
        written += len;
    }
    if format == "sum" {
        for sum in &sums {
            writeln!(out, "{sum:?}").unwrap_or_else(|e| output::exit_on_write_error(e));
        }
    }
    out.flush()
        .unwrap_or_else(|e| output::exit_on_write_error(e));
    Ok(())
}

/// The normal law of `--measure gaussian`, `--mean`, `--cov` and `--factorization`, if asked
/// for.
fn gaussian(args: &Args, dims: usize) -> Result<Option<Gaussian>, String> {
    let measure: Option<String> = args.get("measure", "gaussian")?;
    let given = ["mean", "cov", "factorization"]
        .into_iter()
        .find(|name| args.get::<String>(name, "").ok().flatten().is_some());
    match measure.as_deref() {
        None => {
            return match given {
                Some(name) => Err(format!("--{name} applies to --measure gaussian")),
                None => Ok(None),
            };
        }
        Some("gaussian") => {}
        Some(other) => return Err(format!("invalid --measure = '{other}': expected gaussian")),
    }
    // Before the dims x dims covariance is built (20,000 dimensions would take 3.2 GB).
    if dims > FACTOR_MAX_DIMS {
        return Err(format!(
            "invalid --dims = {dims} with --measure gaussian: at most {FACTOR_MAX_DIMS} (factoring \
             the covariance keeps dims x dims matrices and takes O(dims^3) time)"
        ));
    }
    let mean = args.list("mean")?.unwrap_or_else(|| vec![0.0; dims]);
    if mean.len() != dims {
        return Err(format!(
            "invalid --mean: {} values for --dims {dims} (one per dimension)",
            mean.len()
        ));
    }
    let covariance = match args.get::<String>("cov", "a file path")? {
        None => (0..dims * dims)
            .map(|k| if k / dims == k % dims { 1.0 } else { 0.0 })
            .collect(),
        Some(path) => read_matrix(&path, dims)?,
    };
    let factorization = match args
        .get::<String>("factorization", "cholesky or pca")?
        .as_deref()
    {
        None | Some("cholesky") => Factorization::Cholesky,
        Some("pca") => Factorization::Pca,
        Some(other) => {
            return Err(format!(
                "invalid --factorization = '{other}': expected cholesky or pca"
            ));
        }
    };
    Gaussian::new(mean, covariance, factorization)
        .map(Some)
        .map_err(support::flag_error)
}

/// A `dims x dims` matrix from a text file: rows of numbers separated by commas or spaces.
fn read_matrix(path: &str, dims: usize) -> Result<Vec<f64>, String> {
    let text = mcint_cli::input::read_text(path, "cov")?;
    let rows: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    if rows.len() != dims {
        return Err(format!(
            "--cov '{path}' has {} rows: expected {dims} (one per dimension)",
            rows.len()
        ));
    }
    let mut values = Vec::with_capacity(dims * dims);
    for (i, row) in rows.iter().enumerate() {
        let entries: Vec<&str> = row
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|e| !e.is_empty())
            .collect();
        if entries.len() != dims {
            return Err(format!(
                "--cov '{path}' row {} has {} entries: expected {dims}",
                i + 1,
                entries.len()
            ));
        }
        for entry in entries {
            values.push(
                entry.parse::<f64>().map_err(|_| {
                    format!("--cov '{path}' row {}: '{entry}' is not a number", i + 1)
                })?,
            );
        }
    }
    Ok(values)
}

/// Maps every point of `block` through the normal law, in place.
fn map_block(gaussian: &Gaussian, block: &mut Points) {
    let dims = block.dims();
    let (mut u, mut x) = (vec![0.0; dims], vec![0.0; dims]);
    for i in 0..block.len() {
        block.copy_point(i, &mut u);
        gaussian.map(&u, &mut x);
        for (d, &v) in x.iter().enumerate() {
            block.column_mut(d)[i] = v;
        }
    }
}

/// Values (points x dimensions) per generated block, unless that leaves fewer than 256 points.
const BLOCK_VALUES: u64 = 1 << 18;

/// Largest point set `--format svg|png` draws.
const MAX_DRAWN_POINTS: u64 = 1 << 20;

/// Points `start .. start + n` of `sampler`, one vector per dimension.
fn collect_columns(
    sampler: &dyn mcint::Sampler,
    start: u64,
    n: u64,
    dims: usize,
) -> Result<Vec<Vec<f64>>, String> {
    let mut block = Points::new(dims, n as usize).map_err(support::flag_error)?;
    sampler
        .fill(start, &mut block)
        .map_err(support::flag_error)?;
    Ok((0..dims).map(|d| block.column(d).to_vec()).collect())
}

/// Adds each column of `block` to its running sum, in index order.
///
/// A column's sum is one chain of dependent additions, so summing a column at a time waits
/// on the adder's latency for every value; eight columns side by side keep eight independent
/// chains in flight, each still in index order (the same sums, several times faster).
fn add_columns(sums: &mut [f64], block: &Points) {
    const LANES: usize = 8;
    let len = block.len();
    let (groups, rest) = sums.as_chunks_mut::<LANES>();
    for (group, sums) in groups.iter_mut().enumerate() {
        let columns: [&[f64]; LANES] =
            std::array::from_fn(|k| &block.column(LANES * group + k)[..len]);
        for i in 0..len {
            for (sum, column) in sums.iter_mut().zip(&columns) {
                *sum += column[i];
            }
        }
    }
    let first = groups.len() * LANES;
    for (k, sum) in rest.iter_mut().enumerate() {
        *sum = block.column(first + k).iter().fold(*sum, |s, &x| s + x);
    }
}

fn write_block(out: &mut impl Write, block: &Points, format: &str) -> std::io::Result<()> {
    for i in 0..block.len() {
        for dim in 0..block.dims() {
            let x = block.get(i, dim);
            if format == "bin" {
                out.write_all(&x.to_le_bytes())?;
            } else {
                // `{:?}` prints the shortest text that parses back to the same f64.
                let sep = if dim + 1 == block.dims() { "\n" } else { "," };
                write!(out, "{x:?}{sep}")?;
            }
        }
    }
    Ok(())
}
