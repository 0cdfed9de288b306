//! Draws every sampler's 2-D points (with the strata or elementary intervals that define
//! them) and their Fourier spectrum, one image per sampler, plus an index page with the
//! measures of each set.
//!
//! ```text
//! cargo run --release --bin gallery -- --out DIR [--n 256] [--passes 16] [--frequency 32]
//!     [--format png|svg] [--seed S] [--publication]
//! ```
//! `--n` points per set (at most 65536: an image holds no more; samplers that cannot make exactly `n` use the nearest size they
//! can: 17^2 for `oa-bose` and `oa-bush`, the latter with strength 2); the spectrum is the periodogram averaged over
//! `--passes` independent passes up to frequency `--frequency`. `--publication` uses 1024
//! points, 64 passes and frequency 64 (a minute or so instead of seconds). The index,
//! `DIR/index.html`, lists each sampler's t-value (for power-of-two sizes), L2-star and
//! centered L2 discrepancies (of the drawn set), and low-frequency power; the spectra are
//! also written as data, `DIR/NAME-radial.csv` and `DIR/NAME-periodogram.csv`.

use indicatif::{ProgressBar, ProgressStyle};
use mcint::Points;
use mcint::quality::{Discrepancy, Periodogram, mean_periodogram, t_value};
use mcint::sampler::{Sampler, SamplerKind};
use mcint_cli::args as support;
use mcint_cli::plot;
use mcint_cli::say;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use support::Args;

/// What `--help` says the program does.
const ABOUT: &str = "Draws every sampler's 2-D points and Fourier spectrum, one image per sampler, with an index page.";

const SPEC: support::Spec = &[
    ("out", true, "directory for the images and index.html"),
    ("n", true, "points per image (default 256, at most 65536)"),
    (
        "passes",
        true,
        "passes averaged into each spectrum (default 16, at most 1024)",
    ),
    (
        "frequency",
        true,
        "highest frequency of the spectra (default 32, at most 256)",
    ),
    ("format", true, "png (default) or svg"),
    support::SEED,
    support::PUBLICATION,
];

/// The most points per image, passes per spectrum and highest frequency: an image shows no
/// more points, and the spectra cost `passes n (2 frequency + 1)^2` operations.
const MOST: [(&str, u64); 3] = [("n", 1 << 16), ("passes", 1 << 10), ("frequency", 1 << 8)];
/// The most operations the spectra of one sampler may take (about `2^34`: minutes).
const MAX_SPECTRUM_WORK: u64 = 1 << 34;

/// Sizes tried, in order, when a construction cannot make `--n` points.
const FALLBACK_SIZES: [u64; 4] = [289, 343, 243, 225];

fn main() {
    support::finish(run());
}

struct Settings {
    n: u64,
    passes: usize,
    frequency: usize,
    format: String,
    seed: u64,
}

fn run() -> Result<(), String> {
    let args = Args::parse(ABOUT, SPEC)?;
    let out: PathBuf = args.folder("out", "the folder to write the gallery into")?;
    let publication = args.has("publication");
    let settings = Settings {
        n: positive(&args, "n", if publication { 1024 } else { 256 })?,
        passes: usize::try_from(positive(
            &args,
            "passes",
            if publication { 64 } else { 16 },
        )?)
        .unwrap_or(usize::MAX),
        frequency: usize::try_from(positive(
            &args,
            "frequency",
            if publication { 64 } else { 32 },
        )?)
        .unwrap_or(usize::MAX),
        format: args
            .get::<String>("format", "png or svg")?
            .unwrap_or_else(|| "png".into()),
        seed: args.get("seed", "a whole number")?.unwrap_or(1),
    };
    for (name, most) in MOST {
        let value = match name {
            "n" => settings.n,
            "passes" => settings.passes as u64,
            _ => settings.frequency as u64,
        };
        if value > most {
            return Err(format!(
                "invalid --{name} = {value}: expected at most {most}"
            ));
        }
    }
    let side = 2 * settings.frequency as u64 + 1;
    // A sampler that cannot make --n points draws a fallback size, up to 343.
    let largest = FALLBACK_SIZES.into_iter().fold(settings.n, u64::max);
    let work = largest * settings.passes as u64 * side * side;
    if work > MAX_SPECTRUM_WORK {
        return Err(format!(
            "--n {} (or up to {largest} points, the fallback sizes of samplers that cannot make \
             --n) x --passes {} x (2 --frequency + 1)^2 = {work} operations per spectrum: \
             expected at most 2^34 = {MAX_SPECTRUM_WORK} (fewer points, passes or frequencies)",
            settings.n, settings.passes
        ));
    }
    if settings.format != "png" && settings.format != "svg" {
        return Err(format!(
            "invalid --format = '{}': expected png or svg",
            settings.format
        ));
    }
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create '{}': {e}", out.display()))?;
    let progress = ProgressBar::new(SamplerKind::ALL.len() as u64).with_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}").map_err(|e| e.to_string())?,
    );
    let mut rows = Vec::new();
    for kind in SamplerKind::ALL {
        progress.set_message(kind.name());
        rows.push(draw_sampler(kind, &settings, &out)?);
        progress.inc(1);
    }
    progress.finish_with_message("done");
    let index = out.join("index.html");
    std::fs::write(&index, index_page(&rows, &settings))
        .map_err(|e| format!("cannot write '{}': {e}", index.display()))?;
    say!("{}", index.display());
    Ok(())
}

fn positive(args: &Args, name: &str, default: u64) -> Result<u64, String> {
    let value: u64 = args.get(name, "a whole number >= 1")?.unwrap_or(default);
    if value == 0 {
        return Err(format!("invalid --{name} = 0: expected at least 1"));
    }
    Ok(value)
}

/// What the index says of one sampler.
struct Row {
    name: &'static str,
    n: u64,
    image: String,
    t_value: Option<u32>,
    l2_star: f64,
    centered_l2: f64,
    low_frequency_power: f64,
}

/// Builds `kind` in 2-D with `n` points, or the first fallback size it accepts.
fn build(kind: SamplerKind, n: u64, seed: u64) -> Result<(Box<dyn Sampler>, u64), String> {
    let mut first_error = None;
    for size in std::iter::once(n).chain(FALLBACK_SIZES) {
        // Bush arrays of strength 2 in 2-D: every cell of the p x p grid holds one point.
        let strength = (kind == SamplerKind::OaBush).then_some(2);
        match kind.build_with(2, size, kind.default_scramble(), strength, seed) {
            Ok(sampler) => return Ok((sampler, size)),
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    Err(format!(
        "{}: {}",
        kind.name(),
        first_error.map_or_else(String::new, |e| e.to_string())
    ))
}

/// The strata that define a sampler's points, drawn behind them.
fn strata_of(kind: SamplerKind, n: u64) -> Option<plot::Strata> {
    let side = (n as f64).sqrt().round() as u32;
    let square = u64::from(side) * u64::from(side) == n;
    let power_of_two = n.is_power_of_two();
    match kind {
        SamplerKind::Jittered
        | SamplerKind::MultiJitter
        | SamplerKind::Cmj
        | SamplerKind::OaBose
        | SamplerKind::OaBush
            if square =>
        {
            Some(plot::Strata { x: side, y: side })
        }
        // A square elementary interval of a (0, m, 2)-net.
        SamplerKind::Sobol | SamplerKind::Pmj02 | SamplerKind::Hammersley if power_of_two => {
            let m = n.trailing_zeros();
            Some(plot::Strata {
                x: 1 << (m / 2),
                y: 1 << (m - m / 2),
            })
        }
        _ => None,
    }
}

fn draw_sampler(kind: SamplerKind, settings: &Settings, out: &Path) -> Result<Row, String> {
    let (sampler, n) = build(kind, settings.n, settings.seed)?;
    let mut points = Points::new(2, n as usize).map_err(support::flag_error)?;
    sampler.fill(0, &mut points).map_err(support::flag_error)?;
    let xy: Vec<(f64, f64)> = points
        .column(0)
        .iter()
        .copied()
        .zip(points.column(1).iter().copied())
        .collect();
    let passes = settings.passes;
    let spectrum: Periodogram = mean_periodogram(&*sampler, n as usize, passes, settings.frequency)
        .map_err(|e| format!("{}: {e}", kind.name()))?;
    let radial = spectrum.radial_spectrum();
    let radial_points: Vec<(f64, f64)> = radial
        .frequencies
        .iter()
        .copied()
        .zip(radial.power.iter().copied())
        .collect();
    // Low frequencies: the annuli up to a quarter of the way to the mean point spacing.
    let low_limit = ((n as f64).sqrt() / 4.0).max(1.0);
    let low: Vec<f64> = radial
        .frequencies
        .iter()
        .zip(&radial.power)
        .filter(|(f, _)| **f <= low_limit)
        .map(|(_, p)| *p)
        .collect();
    let low_frequency_power = low.iter().sum::<f64>() / low.len().max(1) as f64;
    write_spectrum_data(out, kind.name(), &spectrum)?;
    let image = format!("{}.{}", kind.name(), settings.format);
    let title = format!("{}: {n} points, spectrum over {passes} passes", kind.name());
    plot::card(
        &out.join(&image),
        &plot::Card {
            title: &title,
            points: &xy,
            strata: strata_of(kind, n),
            periodogram: spectrum.values(),
            size: spectrum.size(),
            lo: 0.01,
            hi: 4.0,
            radial: &radial_points,
        },
    )?;
    Ok(Row {
        name: kind.name(),
        n,
        image,
        t_value: if n.is_power_of_two() {
            t_value(&points).ok()
        } else {
            None
        },
        l2_star: Discrepancy::L2Star
            .root(&points)
            .map_err(support::flag_error)?,
        centered_l2: Discrepancy::Centered
            .root(&points)
            .map_err(support::flag_error)?,
        low_frequency_power,
    })
}

/// The spectrum as data: `NAME-radial.csv` (frequency, power, anisotropy, frequencies in the
/// annulus) and `NAME-periodogram.csv` (kx, ky, power).
fn write_spectrum_data(out: &Path, name: &str, spectrum: &Periodogram) -> Result<(), String> {
    let radial = spectrum.radial_spectrum();
    let mut text = String::from("frequency,power,anisotropy,count\n");
    for i in 0..radial.frequencies.len() {
        let _ = writeln!(
            text,
            "{:?},{:?},{:?},{}",
            radial.frequencies[i], radial.power[i], radial.anisotropy[i], radial.counts[i]
        );
    }
    let path = out.join(format!("{name}-radial.csv"));
    std::fs::write(&path, text).map_err(|e| format!("cannot write '{}': {e}", path.display()))?;
    let k = spectrum.max_frequency() as i64;
    let mut text = String::from("kx,ky,power\n");
    for ky in -k..=k {
        for kx in -k..=k {
            let p = spectrum.get(kx, ky).unwrap_or(f64::NAN);
            let _ = writeln!(text, "{kx},{ky},{p:?}");
        }
    }
    let path = out.join(format!("{name}-periodogram.csv"));
    std::fs::write(&path, text).map_err(|e| format!("cannot write '{}': {e}", path.display()))
}

fn index_page(rows: &[Row], settings: &Settings) -> String {
    let mut html = String::from(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>mcint sampler gallery</title>\
         <style>body{font-family:sans-serif} td,th{padding:4px 10px;text-align:right}\
         img{max-width:100%}</style></head><body>\n<h1>mcint sampler gallery</h1>\n",
    );
    let _ = writeln!(
        html,
        "<p>2-D point sets (seed {}); spectra averaged over {} passes up to frequency {}. \
         Low-frequency power: mean radial power for |k| up to a quarter of sqrt(N) \
         (1 for independent points, near 0 for blue noise and good nets).</p>",
        settings.seed, settings.passes, settings.frequency
    );
    html.push_str(
        "<table><tr><th>sampler</th><th>points</th><th>t-value</th><th>L2-star</th>\
         <th>centered L2</th><th>low-frequency power</th></tr>\n",
    );
    for row in rows {
        let _ = writeln!(
            html,
            "<tr><td><a href=\"#{0}\">{0}</a></td><td>{1}</td><td>{2}</td><td>{3:.3e}</td>\
             <td>{4:.3e}</td><td>{5:.3}</td></tr>",
            row.name,
            row.n,
            row.t_value.map_or("-".into(), |t| t.to_string()),
            row.l2_star,
            row.centered_l2,
            row.low_frequency_power
        );
    }
    html.push_str("</table>\n");
    for row in rows {
        let _ = writeln!(
            html,
            "<h2 id=\"{0}\">{0}</h2>\n<img src=\"{1}\" alt=\"{0} points and spectrum\">",
            row.name, row.image
        );
    }
    html.push_str("</body></html>\n");
    html
}
