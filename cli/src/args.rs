//! Command-line plumbing shared by the programs: `--flag value` parsing (clap, with `--help`)
//! with one-line errors that say what is allowed, and output that never panics.

use crate::output;
pub use crate::output::{fail, launched_rank};

use mcint::sampler::{SamplerKind, Scramble};
use std::collections::HashMap;
use std::str::FromStr;

/// Parsed `--name value` and `--switch` arguments.
pub struct Args {
    values: HashMap<String, String>,
    switches: Vec<String>,
}

/// A flag: `(name, takes_value, what --help says of it)`.
pub type Flag = (&'static str, bool, &'static str);

/// The flags a program accepts.
pub type Spec = &'static [Flag];

// Flags several programs take, described once.
pub const SEED: Flag = ("seed", true, "seed of the randomization (default 0)");
pub const THREADS: Flag = (
    "threads",
    true,
    "worker threads (default: all cores; the result does not depend on it)",
);
pub const JSON: Flag = ("json", false, "print one JSON object instead of text");
pub const REPLICATES: Flag = (
    "replicates",
    true,
    "independent randomized replicates (their spread is the error bar)",
);
pub const DIMS: Flag = ("dims", true, "number of dimensions");
pub const SAMPLER: Flag = (
    "sampler",
    true,
    "point generator: independent, jittered, latin, sobol, halton, hammersley, lattice, multijitter, cmj, oa-bose, oa-bush, nrooks-multistage, poisson, best-candidate, pmj02",
);
pub const SCRAMBLE: Flag = (
    "scramble",
    true,
    "randomization: none, xor, lms, owen (sobol), permute (halton, hammersley), shift (lattice)",
);
pub const STRENGTH: Flag = (
    "strength",
    true,
    "strength of oa-bush orthogonal arrays (default 3)",
);
pub const PUBLICATION: Flag = ("publication", false, "larger figures with fonts for print");
pub const TOL_ABS: Flag = (
    "tol-abs",
    true,
    "run until the 95% half-width is at most this",
);
pub const TOL_REL: Flag = (
    "tol-rel",
    true,
    "run until the 95% half-width is at most this fraction of the estimate",
);
pub const TIME_LIMIT: Flag = (
    "time-limit",
    true,
    "stop after this many seconds with the work done so far (the report says so)",
);
pub const MAX_EVALS: Flag = (
    "max-evals",
    true,
    "evaluation limit of a run to a tolerance (default 2^30)",
);

/// The library's names of a run's settings as the programs' flags spell them.
pub const FLAG_NAMES: &[(&str, &str)] = &[
    ("samples", "--n"),
    ("points", "--n"),
    ("dims", "--dims"),
    ("d", "--dims"),
    ("a", "--a"),
    ("b", "--b"),
    ("u", "--u"),
    ("sampler", "--sampler"),
    ("scramble", "--scramble"),
    ("strength", "--strength"),
    ("replicates", "--replicates"),
    ("threads", "--threads"),
    ("seed", "--seed"),
    ("tol_abs", "--tol-abs"),
    ("tol_rel", "--tol-rel"),
    ("max_evals", "--max-evals"),
];

/// A library error as one line that names the flag behind a bad setting (`--n`, where the
/// library says `samples`).
pub fn flag_error(error: mcint::Error) -> String {
    error.message_with_names(FLAG_NAMES)
}

/// [`flag_error`] for a program whose flags are `spec`: names first as `own` spells them,
/// then as [`FLAG_NAMES`] does, and a setting the library spells like one of `spec`'s flags
/// (`s0` for `--s0`) by that flag.
pub fn spec_error(spec: Spec, own: &[(&str, &str)], error: mcint::Error) -> String {
    let alike: Vec<(String, String)> = spec
        .iter()
        .map(|&(flag, _, _)| (flag.replace('-', "_"), format!("--{flag}")))
        .collect();
    let names: Vec<(&str, &str)> = own
        .iter()
        .chain(FLAG_NAMES)
        .copied()
        .chain(
            alike
                .iter()
                .map(|(library, flag)| (&library[..], &flag[..])),
        )
        .collect();
    error.message_with_names(&names)
}

impl Args {
    /// Parses the process arguments against `spec` with clap: `--help` prints the program's
    /// `about` line and its flags and exits; unknown flags, missing values, repeated flags and
    /// arguments that are not UTF-8 are one-line errors.
    pub fn parse(about: &str, spec: Spec) -> Result<Args, String> {
        let args = std::env::args_os()
            .skip(1)
            .map(|a| {
                a.into_string()
                    .map_err(|bad| format!("argument {bad:?} is not valid UTF-8"))
            })
            .collect::<Result<Vec<String>, String>>()?;
        let name = std::env::args()
            .next()
            .and_then(|path| {
                std::path::Path::new(&path)
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
            })
            .unwrap_or_else(|| "mcint".to_string());
        Args::parse_from(name, about, args, spec)
    }

    fn parse_from(
        name: String,
        about: &str,
        args: Vec<String>,
        spec: Spec,
    ) -> Result<Args, String> {
        let mut command = clap::Command::new(name)
            .about(about.to_string())
            .no_binary_name(true)
            .disable_version_flag(true);
        for &(flag, takes_value, help) in spec {
            let arg = clap::Arg::new(flag).long(flag).help(help);
            command = command.arg(if takes_value {
                arg.action(clap::ArgAction::Set)
                    .value_name("VALUE")
                    .allow_negative_numbers(true)
            } else {
                arg.action(clap::ArgAction::SetTrue)
            });
        }
        let matches = match command.try_get_matches_from(args) {
            Ok(matches) => matches,
            Err(e) if e.kind() == clap::error::ErrorKind::DisplayHelp => {
                if let Err(write) = e.print() {
                    output::exit_on_write_error(write);
                }
                output::flush();
                std::process::exit(0)
            }
            Err(e) => return Err(one_line(&e, spec)),
        };
        let mut values = HashMap::new();
        let mut switches = Vec::new();
        for &(flag, takes_value, _) in spec {
            if takes_value {
                if let Some(value) = matches.get_one::<String>(flag) {
                    values.insert(flag.to_string(), value.clone());
                }
            } else if matches.get_flag(flag) {
                switches.push(flag.to_string());
            }
        }
        Ok(Args { values, switches })
    }

    /// The value of `--name`, parsed; `None` when absent. A whole number may also be written
    /// in scientific notation (`--n 1e6`), as Python's peers accept it.
    pub fn get<T: FromStr>(&self, name: &str, what: &str) -> Result<Option<T>, String> {
        let Some(v) = self.values.get(name) else {
            return Ok(None);
        };
        v.parse()
            .ok()
            .or_else(|| whole_digits(v)?.parse().ok())
            .map(Some)
            .ok_or_else(|| format!("invalid --{name} = '{v}': expected {what}"))
    }

    /// The value of `--name`, which must be present.
    pub fn require<T: FromStr>(&self, name: &str, what: &str) -> Result<T, String> {
        self.get(name, what)?
            .ok_or_else(|| format!("missing --{name} ({what})"))
    }

    /// The folder `--name` names, which must be given and not blank (an empty path would
    /// write into the current directory).
    pub fn folder(&self, name: &str, what: &str) -> Result<std::path::PathBuf, String> {
        let path: String = self.require(name, what)?;
        if path.trim().is_empty() {
            return Err(format!(
                "invalid --{name} = '{path}': expected {what}, not a blank path"
            ));
        }
        Ok(path.into())
    }

    /// A comma-separated list of numbers.
    pub fn list(&self, name: &str) -> Result<Option<Vec<f64>>, String> {
        let Some(text) = self.values.get(name) else {
            return Ok(None);
        };
        text.split(',')
            .map(|item| {
                item.trim().parse::<f64>().map_err(|_| {
                    format!("invalid --{name} item '{item}': expected comma-separated numbers")
                })
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Some)
    }

    /// The `--scramble` choice, or the sampler kind's default randomization.
    pub fn scramble_for(&self, kind: SamplerKind) -> Result<Scramble, String> {
        match self.values.get("scramble") {
            Some(text) => text.parse::<Scramble>().map_err(flag_error),
            None => Ok(kind.default_scramble()),
        }
    }

    /// The instant `--time-limit SECONDS` (from now) ends the run by, if given: a positive
    /// number of seconds, fractions allowed; one past what the clock can represent (`inf`)
    /// is no limit.
    pub fn deadline(&self) -> Result<Option<std::time::Instant>, String> {
        let Some(seconds) = self.get::<f64>("time-limit", "a number of seconds > 0")? else {
            return Ok(None);
        };
        if seconds.is_nan() || seconds <= 0.0 {
            return Err(format!(
                "invalid --time-limit = {seconds}: expected a number of seconds > 0"
            ));
        }
        let limit =
            std::time::Duration::try_from_secs_f64(seconds).unwrap_or(std::time::Duration::MAX);
        Ok(std::time::Instant::now().checked_add(limit))
    }

    /// Whether `--name` (a switch) was given.
    pub fn has(&self, name: &str) -> bool {
        self.switches.iter().any(|s| s == name)
    }

    /// Whether `--name` was given, with a value or as a switch.
    pub fn given(&self, name: &str) -> bool {
        self.values.contains_key(name) || self.has(name)
    }
}

/// The digits of the whole number that `text` writes in scientific notation (`1e6`, `2.5E3`,
/// `-1.5e1`), read exactly, in decimal, so that no digit is lost to a rounding through `f64`;
/// `None` when it is not one, or not whole (`1.5`, `1e-3`).
fn whole_digits(text: &str) -> Option<String> {
    let (mantissa, exponent) = text.split_once(['e', 'E'])?;
    let exponent: i64 = exponent.parse().ok()?;
    let (sign, mantissa) = match mantissa.strip_prefix('-') {
        Some(rest) => ("-", rest),
        None => ("", mantissa.strip_prefix('+').unwrap_or(mantissa)),
    };
    let (int, frac) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let digits = format!("{int}{frac}");
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    // Where the decimal point falls in `digits`; every digit after it must be zero.
    let point = int.len() as i64 + exponent;
    let (whole, rest) = match usize::try_from(point) {
        Ok(p) if p <= digits.len() => digits.split_at(p),
        // Past the digits: zeros follow (at most 40, more than any count holds).
        Ok(p) if p <= 40 => return Some(format!("{sign}{digits}{}", "0".repeat(p - digits.len()))),
        Ok(_) => return None,
        Err(_) => ("", digits.as_str()),
    };
    rest.bytes()
        .all(|b| b == b'0')
        .then(|| format!("{sign}0{whole}"))
}

/// clap's error as one line that names the flag and what is allowed.
fn one_line(error: &clap::Error, spec: Spec) -> String {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    let known = || {
        if spec.is_empty() {
            return "none".to_string();
        }
        spec.iter()
            .map(|(n, _, _)| format!("--{n}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    // The flag as the user wrote it, without clap's `<VALUE>`.
    let arg = match error.get(ContextKind::InvalidArg) {
        Some(ContextValue::String(a)) => a.split_whitespace().next().unwrap_or("").to_string(),
        _ => String::new(),
    };
    match error.kind() {
        ErrorKind::UnknownArgument if arg.starts_with("--") => {
            format!("unknown flag '{arg}' (flags are: {})", known())
        }
        ErrorKind::UnknownArgument if arg.starts_with('-') => format!(
            "unexpected argument '{arg}': a value that starts with '-' is given after '=' \
             (--a=-1,2), or it is read as a flag (flags are: {})",
            known()
        ),
        ErrorKind::UnknownArgument => {
            format!("unexpected argument '{arg}' (flags are: {})", known())
        }
        ErrorKind::ArgumentConflict => format!("flag '{arg}' given twice"),
        ErrorKind::InvalidValue | ErrorKind::NoEquals => format!("flag '{arg}' needs a value"),
        _ => error
            .to_string()
            .lines()
            .next()
            .unwrap_or("invalid arguments")
            .trim_start_matches("error: ")
            .to_string(),
    }
}

/// How a run ended, in words.
pub fn stop_name(stop: mcint::stats::StopReason) -> &'static str {
    stop.name()
}

/// Ends a program with the result of its work: stdout flushed (a failed write is one line and
/// status 2), then for an error one `error:` line and status 2.
pub fn finish(result: Result<(), String>) {
    output::flush();
    if let Err(message) = result {
        fail(message);
    }
}
