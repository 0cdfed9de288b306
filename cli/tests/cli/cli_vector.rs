//! `integrate --genz F1,F2,...` and `--ratio I,J`: one vector run whose JSON has every
//! family's estimate, standard error, exact value and the covariance matrix, agreeing with the
//! library's vector run and with the scalar runs of each family; the ratio within 5 standard
//! errors of its exact value; checkpoints resuming to the same numbers; bad input refused with
//! what is allowed.

use crate::common::{self, assert_one_line_error, run, stdout};
use mcint::pdf::UniformBox;
use mcint::sampler::{Scramble, Sobol};
use mcint::testfns::{Genz, GenzFamily, TestFunction};
use serde_json::Value;

fn json(args: &[&str]) -> Value {
    let output = run("integrate", args);
    assert!(output.status.success(), "{}", common::stderr(&output));
    serde_json::from_str(&stdout(&output)).expect("one JSON object")
}

fn numbers(value: &Value) -> Vec<f64> {
    value
        .as_array()
        .expect("an array")
        .iter()
        .map(|v| v.as_f64().expect("a number"))
        .collect()
}

#[test]
fn json_has_every_output_the_covariance_and_the_ratio() {
    for method in ["plain", "rqmc", "vegas", "vegas-plus"] {
        let v = json(&[
            "--genz",
            "gaussian,oscillatory,product-peak",
            "--dims",
            "4",
            "--method",
            method,
            "--ratio",
            "1,0",
            "--seed",
            "3",
            "--json",
        ]);
        let (estimates, errors, exact) = (
            numbers(&v["estimates"]),
            numbers(&v["std_errors"]),
            numbers(&v["exact"]),
        );
        assert_eq!((estimates.len(), errors.len(), exact.len()), (3, 3, 3));
        let covariance: Vec<Vec<f64>> = v["covariance"]
            .as_array()
            .unwrap()
            .iter()
            .map(numbers)
            .collect();
        assert_eq!(covariance.len(), 3);
        for (k, family) in [
            GenzFamily::Gaussian,
            GenzFamily::Oscillatory,
            GenzFamily::ProductPeak,
        ]
        .into_iter()
        .enumerate()
        {
            let f = Genz::with_defaults(family, 4).unwrap();
            assert_eq!(exact[k], f.exact());
            assert!(
                (estimates[k] - exact[k]).abs() < 5.0 * errors[k],
                "{method} output {k}: {} vs {}",
                estimates[k],
                exact[k]
            );
            assert_eq!(covariance[k].len(), 3);
            assert!((covariance[k][k] - errors[k] * errors[k]).abs() <= 1e-12 * covariance[k][k]);
            for (j, row) in covariance.iter().enumerate() {
                assert_eq!(covariance[k][j], row[k]);
            }
        }
        let ratio = &v["ratio"];
        let (r, se, r_exact) = (
            ratio["estimate"].as_f64().unwrap(),
            ratio["std_error"].as_f64().unwrap(),
            ratio["exact"].as_f64().unwrap(),
        );
        assert_eq!(r_exact, exact[1] / exact[0]);
        assert!(
            (r - r_exact).abs() < 5.0 * se,
            "{method}: ratio {r} vs {r_exact}"
        );
        // One evaluation per point for all three outputs.
        if !method.starts_with("vegas") {
            assert_eq!(v["evaluations"], v["n"]);
        }
    }
}

/// The command line's vector run is the library's, and each output is the scalar run's.
#[test]
fn outputs_match_the_library_and_the_scalar_runs() {
    let v = json(&[
        "--genz",
        "gaussian,continuous",
        "--dims",
        "3",
        "--method",
        "rqmc",
        "--n",
        "4096",
        "--seed",
        "5",
        "--json",
    ]);
    let functions = [
        Genz::with_defaults(GenzFamily::Gaussian, 3).unwrap(),
        Genz::with_defaults(GenzFamily::Continuous, 3).unwrap(),
    ];
    let sobol = || Sobol::new(3, Scramble::Owen, 5).unwrap();
    let estimates = numbers(&v["estimates"]);
    for (k, f) in functions.iter().enumerate() {
        let scalar =
            mcint::Integrator::over_box(|x: &[f64]| f.eval(x), UniformBox::unit(3).unwrap())
                .sampler(sobol())
                .samples(4096)
                .replicates(16)
                .seed(5)
                .run()
                .unwrap();
        assert_eq!(estimates[k], scalar.mean, "output {k}");
    }
}

#[test]
fn a_checkpointed_vector_run_resumes_to_the_same_numbers() {
    let dir = common::scratch_dir("cli-vector");
    let file = dir.join("run.json");
    let path = file.to_str().unwrap();
    let args = [
        "--genz",
        "gaussian,oscillatory",
        "--dims",
        "3",
        "--n",
        "100000",
    ];
    let whole = json(&[&args[..], &["--json"]].concat());
    let first = run(
        "integrate",
        &[&args[..], &["--checkpoint", path, "--stop-after", "2"]].concat(),
    );
    assert!(first.status.success());
    let resumed = json(&[&args[..], &["--checkpoint", path, "--json"]].concat());
    assert_eq!(resumed["estimates"], whole["estimates"]);
    assert_eq!(resumed["covariance"], whole["covariance"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_input_is_refused_with_what_is_allowed() {
    let base = ["--genz", "gaussian,oscillatory", "--dims", "3"];
    let with = |extra: &[&str]| run("integrate", &[&base[..], extra].concat());
    assert_one_line_error(&with(&["--ratio", "0,0"]), "I != J");
    assert_one_line_error(&with(&["--ratio", "0,2"]), "below 2");
    assert_one_line_error(&with(&["--ratio", "x"]), "two output indices");
    assert_one_line_error(&with(&["--method", "miser"]), "integrates one output");
    assert_one_line_error(&with(&["--estimator", "mis"]), "--estimator uniform");
    assert_one_line_error(
        &with(&["--method", "vegas", "--replicates", "4"]),
        "--replicates",
    );
    assert_one_line_error(
        &run("integrate", &["--genz", "gaussian,nope", "--dims", "3"]),
        "keister or a Genz family",
    );
    assert_one_line_error(
        &run(
            "integrate",
            &[
                "--genz",
                "gaussian",
                "--dims",
                "3",
                "--method",
                "vegas",
                "--checkpoint",
                "x",
            ],
        ),
        "--checkpoint applies to --method plain and rqmc",
    );
}

/// With `--ratio` the tolerance is the ratio's: a tolerance not met is said once, of the
/// ratio (it was said of each output, which had no tolerance of its own).
#[test]
fn a_ratio_tolerance_not_met_is_the_ratios_warning() {
    let args = [
        "--genz",
        "gaussian,product-peak",
        "--dims",
        "3",
        "--ratio",
        "0,1",
        "--tol-rel",
        "1e-7",
        "--max-evals",
        "100000",
    ];
    let text = run("integrate", &args);
    let lines: Vec<&str> = std::str::from_utf8(&text.stderr)
        .unwrap()
        .lines()
        .filter(|l| l.starts_with("warning:"))
        .collect();
    assert_eq!(lines.len(), 1, "{lines:?}");
    assert!(
        lines[0].starts_with("warning: ratio 0/1: the run stopped"),
        "{lines:?}"
    );
    let mut with_json = args.to_vec();
    with_json.push("--json");
    let v = json(&with_json);
    let warnings = v["warnings"].as_array().unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_eq!(warnings[0]["kind"], "tolerance-not-met");
    assert_eq!(warnings[0]["ratio"], serde_json::json!([0, 1]));
    assert!(warnings[0].get("output").is_none(), "{warnings:?}");
}
