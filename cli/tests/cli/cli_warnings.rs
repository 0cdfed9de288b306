//! Warnings and the rounding floor from the command line: `integrate` prints each warning to
//! stderr and lists them in `--json`'s `warnings` array (empty when there are none), `points`
//! warns about counts that break a net, and the run of the issue that asked for the floor
//! now reports an error bar its error fits in.

use crate::common::{run, stderr, stdout};
use serde_json::Value;

fn integrate_json(args: &[&str]) -> (Value, String) {
    let mut all = args.to_vec();
    all.push("--json");
    let out = run("integrate", &all);
    assert!(out.status.success(), "{}", stderr(&out));
    let json: Value = serde_json::from_str(stdout(&out).trim()).expect("one JSON object");
    (json, stderr(&out))
}

fn kinds(json: &Value) -> Vec<String> {
    json["warnings"]
        .as_array()
        .expect("a warnings array")
        .iter()
        .map(|w| w["kind"].as_str().expect("a kind").to_string())
        .collect()
}

/// Perfect importance sampling of the 5-D Genz Gaussian: the estimate was 6e-18 from the
/// exact value with a standard error of 4.9e-21 ("1200 standard errors"); now the error bar
/// is the floating-point floor and the exact value is inside the 99% interval
/// (t_{0.995, 49999} = 2.576).
#[test]
fn perfect_importance_sampling_reports_the_rounding_floor() {
    let (json, err) = integrate_json(&[
        "--genz",
        "gaussian",
        "--dims",
        "5",
        "--a",
        "4,5,6,7,8",
        "--estimator",
        "importance",
        "--n",
        "50000",
        "--seed",
        "21",
    ]);
    let estimate = json["estimate"].as_f64().unwrap();
    let exact = json["exact"].as_f64().unwrap();
    let se = json["std_error"].as_f64().unwrap();
    assert!(se >= json["rounding_error"].as_f64().unwrap());
    assert!((estimate - exact).abs() <= 2.576 * se, "{json}");
    assert_eq!(kinds(&json), ["at-rounding-floor"]);
    assert!(
        err.contains("warning: the statistical standard error"),
        "{err}"
    );
}

/// 1000 Owen-scrambled Sobol' points per replicate are not a net: the run goes ahead and
/// says so, with the sizes that would be; 1024 are, and no warning is given.
#[test]
fn a_sample_size_that_breaks_a_net_is_warned_about() {
    let args = |n: &'static str| {
        vec![
            "--genz",
            "oscillatory",
            "--dims",
            "3",
            "--method",
            "rqmc",
            "--n",
            n,
        ]
    };
    let (json, err) = integrate_json(&args("1000"));
    assert_eq!(kinds(&json), ["unbalanced-sample-size"]);
    let message = json["warnings"][0]["message"].as_str().unwrap();
    assert!(message.contains("512 or 1024"), "{message}");
    assert!(err.contains("warning: 1000 points per replicate"), "{err}");
    let (json, err) = integrate_json(&args("1024"));
    assert_eq!(json["warnings"], Value::Array(vec![]));
    assert!(!err.contains("warning"), "{err}");
}

/// Few replicates and a tolerance that is not met are warnings too.
#[test]
fn few_replicates_and_an_unmet_tolerance_are_warned_about() {
    let (json, _) = integrate_json(&[
        "--genz",
        "gaussian",
        "--dims",
        "2",
        "--method",
        "rqmc",
        "--replicates",
        "4",
    ]);
    assert_eq!(kinds(&json), ["few-replicates"]);
    let (json, err) = integrate_json(&[
        "--genz",
        "oscillatory",
        "--dims",
        "4",
        "--tol-abs",
        "1e-9",
        "--max-evals",
        "100000",
    ]);
    assert_eq!(json["converged"], Value::Bool(false));
    assert_eq!(kinds(&json), ["tolerance-not-met"]);
    assert!(err.contains("before meeting the tolerance"), "{err}");
}

#[test]
fn points_warns_about_a_count_that_breaks_a_net() {
    let out = run(
        "points",
        &["--sampler", "sobol", "--dims", "2", "--n", "100"],
    );
    assert!(out.status.success());
    assert!(stderr(&out).contains("warning: 100 points break the balance"));
    assert_eq!(stdout(&out).lines().count(), 100);
    let out = run(
        "points",
        &["--sampler", "sobol", "--dims", "2", "--n", "128"],
    );
    assert!(stderr(&out).is_empty(), "{}", stderr(&out));
}

/// A vector run lists its warnings in `--json` as a scalar run does, `{"kind", "message"}`
/// objects (it gave plain strings), with the output each belongs to.
#[test]
fn vector_runs_list_warnings_as_objects() {
    let (json, err) = integrate_json(&[
        "--genz",
        "gaussian,oscillatory",
        "--dims",
        "3",
        "--method",
        "rqmc",
        "--replicates",
        "4",
    ]);
    let warnings = json["warnings"].as_array().expect("a warnings array");
    assert_eq!(warnings.len(), 2, "{json}");
    for (k, w) in warnings.iter().enumerate() {
        assert_eq!(w["kind"], "few-replicates", "{w}");
        assert_eq!(w["output"], k, "{w}");
        assert!(
            w["message"].as_str().unwrap().contains("only 4 replicates"),
            "{w}"
        );
    }
    assert!(
        err.contains("warning: output 1: only 4 replicates"),
        "{err}"
    );
}

/// One replicate of dependent points: no standard error, and a warning that says how to get
/// one.
#[test]
fn one_replicate_of_dependent_points_is_warned_about() {
    let (json, err) = integrate_json(&[
        "--genz",
        "gaussian",
        "--dims",
        "3",
        "--sampler",
        "sobol",
        "--replicates",
        "1",
    ]);
    assert_eq!(json["std_error"], Value::Null);
    assert_eq!(kinds(&json), ["no-error-bar"]);
    assert!(err.contains("8 or more replicates"), "{err}");
}
