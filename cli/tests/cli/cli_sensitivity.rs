//! The `sensitivity` example: Sobol' indices of Ishigami and the g-function from one vector
//! run agree with the analytic values within their standard errors, the table shows the
//! same numbers as the JSON, and bad input is a one-line error with exit code 2.

use crate::common::{assert_one_line_error, run, stderr, stdout};
use serde_json::Value;

/// Within this many standard errors of the exact value. The numerators are unbiased and the
/// indices are ratios of pooled means, whose O(1/N) bias is of the order of the squared
/// standard error: far below one standard error here, so no absolute allowance.
const SIGMAS: f64 = 5.0;

fn json_run(args: &[&str]) -> Value {
    let mut all = args.to_vec();
    all.push("--json");
    let out = run("sensitivity", &all);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    assert!(stderr(&out).is_empty(), "{args:?} warned: {}", stderr(&out));
    serde_json::from_str(&stdout(&out)).expect("one JSON object")
}

fn number(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("{v} is not a number"))
}

/// Every index of `kind` (`first_order` or `total`) within `SIGMAS` standard errors of the
/// exact value the example reports; returns the exact values.
fn assert_indices_agree(report: &Value, kind: &str) -> Vec<f64> {
    let rows = report[kind].as_array().expect("an array");
    assert_eq!(
        rows.len() as u64,
        report["dims"].as_u64().unwrap(),
        "{kind}"
    );
    rows.iter()
        .enumerate()
        .map(|(i, row)| {
            let (estimate, se, exact) = (
                number(&row["estimate"]),
                number(&row["std_error"]),
                number(&row["exact"]),
            );
            assert!(se > 0.0, "{kind}[{i}]: std_error {se}");
            assert!(
                (estimate - exact).abs() <= SIGMAS * se,
                "{} {kind}[{i}]: {estimate} vs exact {exact}, std error {se}",
                report["function"]
            );
            exact
        })
        .collect()
}

/// The run's size and cost: `n` points per replicate, one integrand evaluation per point and
/// `d + 2` model evaluations per point.
fn assert_counts(report: &Value, n: u64, replicates: u64, dims: u64) {
    assert_counts_with(report, n, replicates, dims, dims + 2);
}

fn assert_counts_with(report: &Value, n: u64, replicates: u64, dims: u64, runs_per_point: u64) {
    assert_eq!(report["dims"].as_u64(), Some(dims));
    assert_eq!(report["n"].as_u64(), Some(n));
    assert_eq!(report["replicates"].as_u64(), Some(replicates));
    assert_eq!(report["evaluations"].as_u64(), Some(n * replicates));
    assert_eq!(
        report["model_evaluations"].as_u64(),
        Some(n * replicates * runs_per_point)
    );
}

#[test]
fn ishigami_indices_agree_with_the_analytic_values() {
    let report = json_run(&["--function", "ishigami", "--seed", "0"]);
    assert_eq!(report["function"], "ishigami");
    assert_counts(&report, 1 << 13, 8, 3);
    let first = assert_indices_agree(&report, "first_order");
    let total = assert_indices_agree(&report, "total");
    // The published values for a = 7, b = 0.1 (Saltelli et al. 2008, The Primer), an
    // independent check of the analytic formulas.
    for (exact, published) in first.iter().zip([0.3139, 0.4424, 0.0]) {
        assert!((exact - published).abs() < 1e-4, "{exact} vs {published}");
    }
    for (exact, published) in total.iter().zip([0.5576, 0.4424, 0.2437]) {
        assert!((exact - published).abs() < 1e-4, "{exact} vs {published}");
    }
    let v = &report["variance"];
    assert!((number(&v["exact"]) - 13.8446).abs() < 1e-4, "{v}");
    assert!(
        (number(&v["estimate"]) - number(&v["exact"])).abs() <= SIGMAS * number(&v["std_error"])
    );
}

#[test]
fn sobol_g_indices_agree_with_the_analytic_values() {
    for (dims, seed) in [("6", "0"), ("3", "7")] {
        let report = json_run(&[
            "--function",
            "sobol-g",
            "--dims",
            dims,
            "--seed",
            seed,
            "--n",
            "4096",
        ]);
        assert_eq!(report["function"], "sobol-g");
        let d: u64 = dims.parse().unwrap();
        assert_counts(&report, 4096, 8, d);
        let first = assert_indices_agree(&report, "first_order");
        let total = assert_indices_agree(&report, "total");
        // V_i = 1/(3 (1 + a_i)^2) with Saltelli et al.'s (2010) weights.
        let a = [0.0, 0.5, 3.0, 9.0, 99.0, 99.0];
        let partial: Vec<f64> = a[..first.len()]
            .iter()
            .map(|a| 1.0 / (3.0 * (1.0 + a) * (1.0 + a)))
            .collect();
        let v = partial.iter().map(|p| 1.0 + p).product::<f64>() - 1.0;
        for (i, p) in partial.iter().enumerate() {
            assert!((first[i] - p / v).abs() < 1e-12, "S_{i}");
            // The total of a product of factors: every subset that contains i.
            let others: f64 = (0..partial.len())
                .filter(|&j| j != i)
                .map(|j| 1.0 + partial[j])
                .product();
            assert!((total[i] - p * others / v).abs() < 1e-12, "ST_{i}");
            assert!(first[i] <= total[i]);
        }
    }
}

/// The numbers of one table row: `x<i>` then S_i, its std error, exact, ST_i, std error, exact.
fn table_row(table: &str, input: usize) -> Vec<f64> {
    let label = format!("x{input}");
    let line = table
        .lines()
        .find(|l| l.split_whitespace().next() == Some(label.as_str()))
        .unwrap_or_else(|| panic!("no row {label} in\n{table}"));
    line.split_whitespace()
        .skip(1)
        .map(|v| v.parse().unwrap_or_else(|_| panic!("{v} in {line}")))
        .collect()
}

#[test]
fn the_table_shows_every_index_as_the_json_has_it() {
    for function in ["ishigami", "sobol-g"] {
        let args = ["--function", function, "--n", "1024", "--seed", "3"];
        let report = json_run(&args);
        let out = run("sensitivity", &args);
        assert!(out.status.success(), "{}", stderr(&out));
        let table = stdout(&out);
        assert!(
            table.contains(&format!("model       {function}")),
            "{table}"
        );
        assert!(table.contains("model evaluations"), "{table}");
        let dims = report["dims"].as_u64().unwrap() as usize;
        for i in 0..dims {
            let row = table_row(&table, i + 1);
            assert_eq!(row.len(), 6, "row x{}: {row:?}", i + 1);
            for (k, kind) in ["first_order", "total"].into_iter().enumerate() {
                let entry = &report[kind][i];
                let (estimate, se, exact) = (row[3 * k], row[3 * k + 1], row[3 * k + 2]);
                // Six decimals for indices, three significant digits for standard errors.
                assert!(
                    (estimate - number(&entry["estimate"])).abs() <= 5e-7,
                    "{kind}[{i}]"
                );
                assert!(
                    (exact - number(&entry["exact"])).abs() <= 5e-7,
                    "{kind}[{i}]"
                );
                let json_se = number(&entry["std_error"]);
                assert!((se - json_se).abs() <= 5e-3 * json_se, "{kind}[{i}]");
            }
        }
    }
}

/// A one-line error that says what is allowed, with exit code 2 (not a panic).
fn assert_usage_error(args: &[&str], needle: &str) {
    let out = run("sensitivity", args);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
    assert_one_line_error(&out, needle);
    assert!(out.stdout.is_empty(), "{args:?} printed {}", stdout(&out));
}

#[test]
fn bad_input_is_a_one_line_error_with_exit_code_2() {
    assert_usage_error(&["--function", "nope"], "expected ishigami or sobol-g");
    assert_usage_error(&[], "missing --function (ishigami or sobol-g)");
    assert_usage_error(
        &["--function", "ishigami", "--n", "0"],
        "points per replicate >= 1",
    );
    assert_usage_error(
        &["--function", "ishigami", "--n", "x"],
        "points per replicate >= 1",
    );
    assert_usage_error(&["--function", "ishigami", "--replicates", "0"], ">= 1");
    assert_usage_error(
        &[
            "--function",
            "ishigami",
            "--replicates",
            "1",
            "--tol-abs",
            "1e-3",
        ],
        "--replicates >= 2",
    );
    assert_usage_error(&["--function", "ishigami", "--tol-abs", "-1"], "> 0");
    assert_usage_error(
        &["--function", "ishigami", "--max-evals", "100000"],
        "give --tol-abs too",
    );
    let limited = ["--function", "ishigami", "--tol-abs", "1e-3", "--max-evals"];
    assert_usage_error(&[&limited[..], &["0"]].concat(), "invalid --max-evals = 0");
    assert_usage_error(
        &["--function", "ishigami", "--n", "18446744073709551615"],
        "--n x --replicates below 2^64",
    );
    assert_usage_error(
        &[&limited[..], &["1000"]].concat(),
        "at least 65536 evaluations (8 replicates of 8192 points)",
    );
    assert_usage_error(&["--function", "ishigami", "--weights", "1,2,3"], "sobol-g");
    assert_usage_error(&["--function", "sobol-g", "--b", "0.2"], "ishigami");
    assert_usage_error(&["--function", "sobol-g", "--weights", "1,-2"], ">= 0");
    // The weights were named after the library's `a`, which is Ishigami's --a here.
    for weights in ["1,-1", "1,nan"] {
        assert_usage_error(
            &["--function", "sobol-g", "--weights", weights],
            "invalid --weights = ",
        );
    }
    // With second order, at most 21 inputs (4 + 2 D + D (D - 1) / 2 integrals, at most 256);
    // 22 was refused as "factors", with the advice to group inputs, which the CLI cannot.
    let second = ["--function", "sobol-g", "--second-order"];
    assert_usage_error(
        &[&second[..], &["--dims", "22"]].concat(),
        "invalid --dims = 22 inputs: expected 1 to 21 with --second-order",
    );
    let weights = vec!["1"; 22].join(",");
    assert_usage_error(
        &[&second[..], &["--weights", &weights]].concat(),
        "invalid --weights = 22 inputs: expected 1 to 21 with --second-order",
    );
    assert_usage_error(
        &["--function", "sobol-g", "--weights", "1,2", "--dims", "2"],
        "not both",
    );
    assert_usage_error(&["--function", "ishigami", "--a", "inf"], "finite");
    assert_usage_error(&["--function", "ishigami", "--dims", "4"], "sobol-g");
    assert_usage_error(
        &["--function", "sobol-g", "--dims", "0"],
        "expected 1 to 126",
    );
    assert_usage_error(
        &["--function", "sobol-g", "--dims", "127"],
        "expected 1 to 126",
    );
    assert_usage_error(
        &["--function", "ishigami", "--bogus"],
        "unknown flag '--bogus'",
    );
}

#[test]
fn help_lists_every_flag() {
    let out = run("sensitivity", &["--help"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("1 to 21 with --second-order"), "{text}");
    for flag in [
        "--function",
        "--dims",
        "--n",
        "--replicates",
        "--seed",
        "--json",
        "--a",
        "--b",
        "--weights",
        "--second-order",
        "--tol-abs",
        "--max-evals",
        "--threads",
        "--mpi",
    ] {
        assert!(text.contains(flag), "{flag} missing from\n{text}");
    }
    assert_eq!(
        text.matches("Usage:").count(),
        1,
        "one usage block:\n{text}"
    );
    // The defaults the help states are those a run without flags uses.
    let report = json_run(&["--function", "ishigami"]);
    for (key, stated) in [("n", "default 8192"), ("replicates", "default 8;")] {
        assert!(text.contains(stated), "{stated} missing from\n{text}");
        assert!(
            stated.contains(&report[key].to_string()),
            "{key}: {}",
            report[key]
        );
    }
    assert_eq!(report["parameters"]["a"][0], 7.0);
    assert!(
        text.contains("(default 7)") && text.contains("(default 0.1)"),
        "{text}"
    );
}

/// Ishigami's parameters and the g-function's weights reach the model: the exact values
/// the report gives are those of the parameters asked for, and the estimates agree.
#[test]
fn parameters_and_weights_reach_the_model() {
    let report = json_run(&[
        "--function",
        "ishigami",
        "--a",
        "5",
        "--b",
        "0.2",
        "--seed",
        "1",
    ]);
    assert_eq!(report["parameters"]["a"][0], 5.0);
    let total = assert_indices_agree(&report, "total");
    // V13 / V with a = 5, b = 0.2: V = a^2/8 + b pi^4/5 + b^2 pi^8/18 + 1/2.
    let pi = std::f64::consts::PI;
    let v = 25.0 / 8.0 + 0.2 * pi.powi(4) / 5.0 + 0.04 * pi.powi(8) / 18.0 + 0.5;
    let v13 = 0.04 * pi.powi(8) * (1.0 / 18.0 - 1.0 / 50.0);
    assert!((total[2] - v13 / v).abs() < 1e-12, "{}", total[2]);
    let report = json_run(&[
        "--function",
        "sobol-g",
        "--weights",
        "0,1,4.5",
        "--seed",
        "2",
    ]);
    assert_eq!(report["dims"], 3);
    let first = assert_indices_agree(&report, "first_order");
    let partial = [1.0 / 3.0, 1.0 / 12.0, 1.0 / (3.0 * 5.5 * 5.5)];
    let v = partial.iter().map(|p| 1.0 + p).product::<f64>() - 1.0;
    for (s, p) in first.iter().zip(partial) {
        assert!((s - p / v).abs() < 1e-12);
    }
}

/// `--second-order` adds `second_order`, one entry per pair with its inputs, within its
/// standard errors of the exact `S_ij = V_i V_j / V` of the g-function, at `2 D + 2` model
/// runs per point.
#[test]
fn second_order_indices_are_reported_per_pair() {
    let report = json_run(&[
        "--function",
        "sobol-g",
        "--weights",
        "0,1,4.5",
        "--second-order",
    ]);
    assert_counts_with(&report, 1 << 13, 8, 3, 8);
    let pairs = report["second_order"].as_array().expect("second_order");
    assert_eq!(pairs.len(), 3);
    for (pair, inputs) in pairs.iter().zip([[0, 1], [0, 2], [1, 2]]) {
        assert_eq!(pair["inputs"], serde_json::json!(inputs));
        let (estimate, se, exact) = (
            number(&pair["estimate"]),
            number(&pair["std_error"]),
            number(&pair["exact"]),
        );
        assert!(exact > 0.0);
        assert!((estimate - exact).abs() <= SIGMAS * se, "{pair}");
    }
    let without = json_run(&["--function", "sobol-g", "--weights", "0,1,4.5"]);
    assert!(without.get("second_order").is_none());
}

/// `--tol-abs` runs until every index's half-width meets it, and says so.
#[test]
fn a_tolerance_run_meets_it_on_every_index() {
    let report = json_run(&["--function", "ishigami", "--tol-abs", "2e-3", "--n", "1024"]);
    assert_eq!(report["converged"], true);
    for kind in ["first_order", "total"] {
        assert_indices_agree(&report, kind);
        for row in report[kind].as_array().unwrap() {
            // 95% half-width of 8 replicates: t_7 = 2.3646 standard errors.
            assert!(2.3646 * number(&row["std_error"]) <= 2e-3 * 1.0001, "{row}");
        }
    }
    let json_free = json_run(&["--function", "ishigami"]);
    assert!(json_free["converged"].is_null());
}

/// `--max-evals` ends a run to an unreachable tolerance at that many points, and says so.
#[test]
fn a_tolerance_run_stops_at_max_evals() {
    let args = [
        "--function",
        "ishigami",
        "--tol-abs",
        "1e-9",
        "--n",
        "1024",
        "--max-evals",
        "40000",
        "--json",
    ];
    let out = run("sensitivity", &args);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("before meeting the tolerance"),
        "{}",
        stderr(&out)
    );
    let report: Value = serde_json::from_str(&stdout(&out)).expect("one JSON object");
    assert_eq!(report["converged"], false);
    assert_eq!(report["stop"], "max evaluations");
    let evaluations = report["evaluations"].as_u64().unwrap();
    assert!((8192..=40000).contains(&evaluations), "{evaluations}");
    assert_eq!(report["model_evaluations"].as_u64(), Some(5 * evaluations));
    let warnings = report["warnings"].as_array().unwrap();
    assert!(
        warnings.iter().any(|w| w["kind"] == "tolerance-not-met"),
        "{warnings:?}"
    );
}
