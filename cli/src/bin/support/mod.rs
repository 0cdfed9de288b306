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
    /// Parses the process arguments against `spec`; unknown flags, missing values and
    /// arguments that are not UTF-8 are errors. Every program calls it first, so it also makes
    /// a closed stdout (`| head -1`) end the program quietly instead of with a panic.
    pub fn parse(spec: Spec) -> Result<Args, String> {
        quiet_on_broken_pipe();
        let args = std::env::args_os()
            .skip(1)
            .map(|a| {
                a.into_string()
                    .map_err(|bad| format!("argument {bad:?} is not valid UTF-8"))
            })
            .collect::<Result<Vec<String>, String>>()?;
        Args::parse_from(args.into_iter(), spec)
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

/// Makes a write to a closed stdout or stderr end the program with status 0 and no message:
/// Rust ignores SIGPIPE, so `println!` to a pipe whose reader is gone panics instead, and the
/// panic hook turns exactly that panic into a quiet exit.
fn quiet_on_broken_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.starts_with("failed printing to std") && message.contains("Broken pipe") {
            std::process::exit(0);
        }
        default(info);
    }));
}

/// Prints `error: message` on one line and exits with status 2.
pub fn fail(message: impl std::fmt::Display) -> ! {
    eprintln!("error: {message}");
    std::process::exit(2)
}
