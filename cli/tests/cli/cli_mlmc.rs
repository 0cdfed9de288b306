//! The `mlmc` program: multilevel runs of GBM options agree with Black-Scholes, `--test`
//! prints Giles' survey with the published rates, `--json` has the fields the issue names,
//! `--plot` draws the decays, and bad input is a one-line error.

use crate::common::{assert_one_line_error, run, scratch_dir, stderr, stdout};
use serde_json::Value;

fn json_run(args: &[&str]) -> Value {
    let mut all = args.to_vec();
    all.push("--json");
    let out = run("mlmc", &all);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    serde_json::from_str(&stdout(&out)).expect("one JSON object")
}

fn number(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("{v} is not a number"))
}

/// The message of the one warning of `kind` in a report's `warnings` (objects with `kind` and
/// `message`, as `integrate --json` lists them).
fn warning<'a>(report: &'a Value, kind: &str) -> &'a str {
    let warnings = report["warnings"].as_array().expect("a warnings array");
    let of_kind: Vec<&str> = warnings
        .iter()
        .filter(|w| w["kind"] == kind)
        .map(|w| w["message"].as_str().expect("a message"))
        .collect();
    assert_eq!(of_kind.len(), 1, "one {kind} warning in {report}");
    of_kind[0]
}

#[test]
fn a_european_call_meets_its_target_and_reports_every_field() {
    let report = json_run(&["--eps", "0.05", "--seed", "3"]);
    let (estimate, exact) = (number(&report["estimate"]), number(&report["exact"]));
    assert!((exact - 10.450583572185565).abs() < 1e-9, "{exact}");
    // The run aims at an RMSE of 0.05: 4 of them is far in the tail.
    assert!((estimate - exact).abs() < 0.2, "{report}");
    assert_eq!(report["converged"], true);
    assert_eq!(report["stop"], "tolerance met");
    assert!(number(&report["cost"]) * 10.0 < number(&report["standard_mc_cost"]));
    for field in ["std_error", "bias", "alpha", "beta", "gamma"] {
        assert!(number(&report[field]) > 0.0, "{field}: {report}");
    }
    let levels = report["levels"].as_array().unwrap();
    assert!(levels.len() >= 3);
    for level in levels {
        assert!(level["n"].as_u64().unwrap() >= 16, "{level}");
        for field in ["mean", "variance", "cost"] {
            number(&level[field]);
        }
    }
    assert_eq!(levels[0]["check"], Value::Null);
}

#[test]
fn the_survey_shows_euler_and_milstein_rates() {
    for (scheme, beta) in [("euler", 1.0), ("milstein", 2.0)] {
        let report = json_run(&[
            "--scheme",
            scheme,
            "--test",
            "--test-levels",
            "6",
            "--test-samples",
            "40000",
            "--eps",
            "0.1",
        ]);
        let test = &report["test"];
        assert_eq!(test["levels"].as_array().unwrap().len(), 7);
        assert!(
            (number(&test["beta"]) - beta).abs() < 0.3,
            "{scheme}: {test}"
        );
    }
    let out = run(
        "mlmc",
        &[
            "--test",
            "--test-levels",
            "3",
            "--test-samples",
            "2000",
            "--eps",
            "0.2",
        ],
    );
    let text = stdout(&out);
    assert!(
        text.contains("Giles' mlmc_test survey") && text.contains("Black-Scholes"),
        "{text}"
    );
}

#[test]
fn other_payoffs_models_and_qmc_run() {
    let digital = json_run(&["--payoff", "digital", "--eps", "0.002", "--seed", "1"]);
    let error = number(&digital["estimate"]) - number(&digital["exact"]);
    assert!(error.abs() < 0.008, "{digital}");
    let qmc = json_run(&["--payoff", "asian", "--eps", "0.02", "--qmc"]);
    assert_eq!(qmc["exact"], Value::Null);
    assert!((number(&qmc["estimate"]) - 5.7631).abs() < 0.08, "{qmc}");
    let heston = json_run(&["--model", "heston", "--eps", "0.1"]);
    assert_eq!(heston["scheme"], "euler");
    assert_eq!(heston["converged"], true);
}

/// `--max-level` caps the levels: a run that needs deeper ones stops there, says so and
/// names the flag that allows more.
#[test]
fn max_level_stops_a_run_and_the_warning_names_the_flag() {
    let capped = json_run(&["--eps", "0.01", "--max-level", "3"]);
    assert_eq!(
        capped["levels"].as_array().map(Vec::len),
        Some(4),
        "{capped}"
    );
    assert_eq!(
        (&capped["stop"], &capped["converged"]),
        (&"max level".into(), &false.into())
    );
    let message = warning(&capped, "bias-above-target");
    assert!(message.contains("(--max-level)"), "{message}");
    let started = json_run(&["--eps", "0.1", "--min-level", "4"]);
    assert!(
        started["levels"].as_array().map_or(0, Vec::len) >= 5,
        "{started}"
    );
}

/// `--max-cost` bounds a run's work: a target that needs far more stops at the limit with
/// its estimate so far and says the tolerance was not met; a limit below the first samples'
/// cost, or not a positive number, is a one-line error naming the flag.
#[test]
fn max_cost_stops_a_run_at_its_limit() {
    let capped = json_run(&["--eps", "0.001", "--max-cost", "1e5"]);
    assert_eq!(
        (&capped["stop"], &capped["converged"]),
        (&"max evaluations".into(), &false.into()),
        "{capped}"
    );
    assert!(number(&capped["cost"]) <= 1e5, "{capped}");
    assert!(
        warning(&capped, "tolerance-not-met").contains("tolerance"),
        "{capped}"
    );
    for bad in ["0", "nan", "10"] {
        let out = run("mlmc", &["--max-cost", bad]);
        assert_one_line_error(&out, "--max-cost");
    }
}

/// A call far out of the money pays nothing on every sampled path: the run says so instead
/// of printing a NaN check.
#[test]
fn an_all_zero_run_warns() {
    let out = run("mlmc", &["--s0", "50", "--eps", "0.5", "--scheme", "euler"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stderr(&out).contains("exactly zero"), "{}", stderr(&out));
    assert!(!stdout(&out).contains("NaN"), "{}", stdout(&out));
}

#[test]
fn the_plot_is_drawn() {
    let dir = scratch_dir("mlmc-plot");
    let file = dir.join("levels.svg");
    let out = run("mlmc", &["--eps", "0.1", "--plot", file.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let svg = std::fs::read_to_string(&file).unwrap();
    assert!(
        svg.contains("<svg") && svg.contains("beta"),
        "{}",
        &svg[..200.min(svg.len())]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_input_is_one_line() {
    let cases: [(&[&str], &str); 10] = [
        // A flag of the other model is refused, not silently ignored.
        (
            &["--model", "heston", "--sigma", "0.3"],
            "--sigma does not apply to --model heston",
        ),
        (&["--rho", "0.3"], "--rho does not apply to --model gbm"),
        (&["--eps", "0"], "--eps"),
        (&["--model", "heston", "--scheme", "milstein"], "milstein"),
        (&["--payoff", "put"], "--payoff"),
        (&["--refinement", "1"], "invalid --refinement = 1"),
        (&["--test", "--test-levels", "30"], "--test-levels"),
        (
            &["--min-level", "5", "--max-level", "3"],
            "--min-level <= --max-level",
        ),
        (&["--max-level", "61"], "<= 60"),
        // exp(800) is no discount: the flags that gave it are named.
        (
            &["--rate", "-800"],
            "invalid --rate = -800 with --maturity = 1",
        ),
    ];
    for (args, needle) in cases {
        assert_one_line_error(&run("mlmc", args), needle);
    }
}

/// `--checkpoint` with a short `--time-limit`, run again until it converges, ends with the
/// bits of the uninterrupted run; a checkpoint of other flags is refused.
#[test]
fn a_checkpointed_run_resumes_to_the_uninterrupted_result() {
    let dir = scratch_dir("mlmc-checkpoint");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("run.json");
    let file = file.to_str().unwrap();
    let flags = ["--payoff", "asian", "--eps", "0.01", "--seed", "4"];
    let whole = json_run(&flags);
    let mut pieces = 0;
    let resumed = loop {
        pieces += 1;
        // A hang guard by count: every piece makes progress (at least one chunk).
        assert!(pieces <= 500, "no convergence after {pieces} pieces");
        let mut args = flags.to_vec();
        args.extend(["--checkpoint", file, "--time-limit", "0.05"]);
        let report = json_run(&args);
        if report["converged"] == true {
            break report;
        }
    };
    for field in ["estimate", "std_error", "cost", "levels"] {
        assert_eq!(
            resumed[field], whole[field],
            "{field} after {pieces} pieces"
        );
    }
    let mut other = flags.to_vec();
    other[3] = "0.02";
    other.extend(["--checkpoint", file]);
    assert_one_line_error(&run("mlmc", &other), "cannot continue with these flags");
    let _ = std::fs::remove_dir_all(&dir);
}
