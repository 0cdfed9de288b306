//! The example binaries, run as a user would: output formats, and one-line errors with a
//! non-zero exit on bad input. `cargo test` builds the examples before running these tests.

use crate::common::{assert_one_line_error, run, stderr, stdout};
use mcint::sampler::SamplerKind;

mod figures;
mod integrate;
mod points;
mod samplers;

/// A field of the one-line JSON object `integrate --json` prints, as text (strings unquoted).
fn json_field(json: &str, key: &str) -> String {
    let value: serde_json::Value =
        serde_json::from_str(json).unwrap_or_else(|e| panic!("not JSON ({e}): {json}"));
    match &value[key] {
        serde_json::Value::Null if value.get(key).is_none() => panic!("no {key} in {json}"),
        serde_json::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// The reported estimate of an `integrate --json` run with 8 replicates is within 10 of its
/// standard errors of the exact value: the Student-t quantile t_{0.99999, 7} is about 9.9, so
/// a larger error means a wrong estimate or a false error bar.
fn assert_within_ten_standard_errors(json: &str, context: &str) {
    let estimate: f64 = json_field(json, "estimate").parse().unwrap();
    let exact: f64 = json_field(json, "exact").parse().unwrap();
    let se: f64 = json_field(json, "std_error").parse().unwrap();
    assert!((estimate - exact).abs() < 10.0 * se, "{context}: {json}");
}
