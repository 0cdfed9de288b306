//! Command-line plumbing shared by the example binaries: `--flag value` parsing with one-line
#![allow(dead_code)] // each example binary uses a different subset of these helpers
//! errors that say what is allowed.

use mcint::sampler::{SamplerKind, Scramble};
use std::collections::HashMap;
use std::str::FromStr;

/// Parsed `--name value` and `--switch` arguments.
pub struct Args {
    values: HashMap<String, String>,
    switches: Vec<String>,
}

/// The flags a program accepts: `(name, takes_value)`.
pub type Spec = &'static [(&'static str, bool)];

impl Args {
    /// Parses the process arguments against `spec`; unknown flags and missing values are errors.
    pub fn parse(spec: Spec) -> Result<Args, String> {
        Args::parse_from(std::env::args().skip(1), spec)
    }

    fn parse_from(args: impl Iterator<Item = String>, spec: Spec) -> Result<Args, String> {
        let mut values = HashMap::new();
        let mut switches = Vec::new();
        let mut args = args.peekable();
        let known = || {
            if spec.is_empty() {
                return "none".to_string();
            }
            spec.iter()
                .map(|(n, _)| format!("--{n}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        while let Some(arg) = args.next() {
            let Some(name) = arg.strip_prefix("--") else {
                return Err(format!(
                    "unexpected argument '{arg}' (flags are: {})",
                    known()
                ));
            };
            let Some(&(_, takes_value)) = spec.iter().find(|(n, _)| *n == name) else {
                return Err(format!("unknown flag '{arg}' (flags are: {})", known()));
            };
            if takes_value {
                match args.next() {
                    Some(v) if !v.starts_with("--") => {
                        if values.insert(name.to_string(), v).is_some() {
                            return Err(format!("flag '{arg}' given twice"));
                        }
                    }
                    _ => return Err(format!("flag '{arg}' needs a value")),
                }
            } else {
                switches.push(name.to_string());
            }
        }
        Ok(Args { values, switches })
    }

    /// The value of `--name`, parsed; `None` when absent.
    pub fn get<T: FromStr>(&self, name: &str, what: &str) -> Result<Option<T>, String> {
        match self.values.get(name) {
            None => Ok(None),
            Some(v) => v
                .parse()
                .map(Some)
                .map_err(|_| format!("invalid --{name} '{v}': expected {what}")),
        }
    }

    /// The value of `--name`, which must be present.
    pub fn require<T: FromStr>(&self, name: &str, what: &str) -> Result<T, String> {
        self.get(name, what)?
            .ok_or_else(|| format!("missing --{name} ({what})"))
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
            Some(text) => text.parse::<Scramble>().map_err(|e| e.to_string()),
            None => Ok(kind.default_scramble()),
        }
    }

    /// Whether `--name` (a switch) was given.
    pub fn has(&self, name: &str) -> bool {
        self.switches.iter().any(|s| s == name)
    }
}

/// Prints `error: message` on one line and exits with status 2.
pub fn fail(message: impl std::fmt::Display) -> ! {
    eprintln!("error: {message}");
    std::process::exit(2)
}
