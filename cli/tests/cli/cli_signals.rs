//! `integrate` cancelled by SIGINT or SIGTERM: it stops after its current chunks, prints what
//! it has (the JSON says `"stop": "cancelled"`) and exits with status 130; with
//! `--checkpoint` it saves first, and the run resumed later gives the uninterrupted bits.
//! `--time-limit` stops every program that integrates the same way, with status 0.
#![cfg(target_os = "linux")]

use crate::common::{self, example, output_or_hang, run, stderr, stdout};
use mcint::PartialRun;
use serde_json::Value;
use std::process::{Child, Command, Stdio};

/// Waits until `child` has installed its handler for SIGINT (bit 2 of `SigCgt` in
/// `/proc/PID/status`), so the signal is not delivered to a process that cannot catch it yet.
fn wait_for_handler(child: &Child) {
    let status = format!("/proc/{}/status", child.id());
    for _ in 0..100_000 {
        let text = std::fs::read_to_string(&status).unwrap_or_default();
        let caught = text
            .lines()
            .find_map(|l| l.strip_prefix("SigCgt:"))
            .and_then(|mask| u64::from_str_radix(mask.trim(), 16).ok());
        if caught.is_some_and(|mask| mask & (1 << 1) != 0) {
            return;
        }
        std::thread::yield_now();
    }
    panic!("the process never installed its signal handler");
}

/// Waits until `child` has run for `ticks` clock ticks of CPU time (user plus system, fields
/// 14 and 15 of `/proc/PID/stat`), so that it has done some work when it is signalled: a
/// signal before its first chunk leaves it nothing to report. This measures the work done,
/// not the time passed; the loop is bounded by a count in case the process never runs.
fn wait_for_work(child: &Child, ticks: u64) {
    let stat = format!("/proc/{}/stat", child.id());
    for _ in 0..1_000_000 {
        let text = std::fs::read_to_string(&stat).unwrap_or_default();
        let state = text
            .rsplit_once(')')
            .and_then(|(_, r)| r.split_whitespace().next());
        if state.is_none_or(|s| s == "Z") {
            return; // it has ended: the caller's assertions say how
        }
        // The command name (field 2) is in parentheses and may hold spaces: count after it.
        let used: u64 = text
            .rsplit_once(')')
            .map(|(_, rest)| {
                rest.split_whitespace()
                    .skip(11)
                    .take(2)
                    .filter_map(|t| t.parse::<u64>().ok())
                    .sum()
            })
            .unwrap_or(0);
        if used >= ticks {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    panic!("the process never did {ticks} ticks of work");
}

fn signal(child: &Child, name: &str) {
    let status = Command::new("kill")
        .args([&format!("-{name}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
}

#[test]
fn sigint_stops_a_run_which_reports_what_it_has() {
    let mut child = Command::new(example("integrate"))
        .args([
            "--genz",
            "gaussian",
            "--dims",
            "5",
            "--n",
            "1073741824",
            "--threads",
            "1",
            "--json",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_handler(&child);
    // A tenth of a second of work: many chunks of 16384 points, far from the 2^30 planned.
    wait_for_work(&child, 10);
    signal(&child, "INT");
    let status = child.wait().unwrap();
    let out = child.wait_with_output().unwrap();
    assert_eq!(status.code(), Some(130), "{}", stderr(&out));
    let json: Value = serde_json::from_str(stdout(&out).trim()).expect("the partial result");
    assert_eq!(json["stop"], "cancelled");
    assert!(json["n"].as_u64().unwrap() < 1 << 30);
    assert!(
        stderr(&out).contains("warning: the run stopped (cancelled)"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn sigterm_saves_the_checkpoint_which_resumes_to_the_uninterrupted_bits() {
    let dir = std::env::temp_dir().join(format!("mcint-signal-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run.json");
    let args = [
        "--genz",
        "gaussian",
        "--dims",
        "5",
        "--n",
        "16777216",
        "--threads",
        "1",
        "--json",
        "--checkpoint",
        path.to_str().unwrap(),
        "--save-every",
        "1",
    ];
    let mut child = Command::new(example("integrate"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_handler(&child);
    wait_for_work(&child, 5);
    signal(&child, "TERM");
    let status = child.wait().unwrap();
    let out = child.wait_with_output().unwrap();
    if status.code() == Some(130) {
        assert!(
            stderr(&out).contains("checkpoint: cancelled"),
            "{}",
            stderr(&out)
        );
        let part: PartialRun =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        assert!(!part.is_complete());
    } else {
        // The run finished before the signal arrived: nothing to test but the answer.
        assert!(status.success(), "{}", stderr(&out));
    }
    let resumed = run("integrate", &args);
    assert!(resumed.status.success(), "{}", stderr(&resumed));
    std::fs::remove_dir_all(&dir).unwrap();
    let whole = run("integrate", &args[..9]);
    let answer = |text: &str| -> (Value, Value) {
        let v: Value = serde_json::from_str(text.trim()).unwrap();
        (v["estimate"].clone(), v["std_error"].clone())
    };
    assert_eq!(answer(&stdout(&resumed)), answer(&stdout(&whole)));
}

/// `integrate METHOD` with an unreachable tolerance (or a budget of days) and `--time-limit`.
fn timed(method: &str, extra: &[&str]) -> std::process::Output {
    let mut command = Command::new(example("integrate"));
    command.args(["--integrand", "gaussian", "--dims", "3", "--method", method]);
    command.args(extra).args(["--time-limit", "0.5"]);
    output_or_hang(&mut command)
}

/// Every method stops at `--time-limit` with its last whole stage, and says so in JSON
/// (`"stop": "time limit"`) and in text; a run that had no whole stage by then is a one-line
/// error naming the limit. Either way the process ends (the hang guard kills it otherwise:
/// these runs would take days).
#[test]
fn time_limit_stops_every_method_and_the_report_says_so() {
    let tolerance = ["--tol-rel", "1e-15", "--max-evals", "1e15"];
    let cases: [(&str, Vec<&str>); 7] = [
        ("plain", vec!["--n", "1e15"]),
        ("rqmc", tolerance.to_vec()),
        ("vegas", [&tolerance[..], &["--n", "1000"]].concat()),
        ("vegas-plus", [&tolerance[..], &["--n", "1000"]].concat()),
        ("miser", [&tolerance[..], &["--n", "1024"]].concat()),
        ("two-stage", vec!["--n", "1e14"]),
        ("sobol-g", tolerance.to_vec()),
    ];
    for (method, args) in cases {
        let json = timed(method, &[&args[..], &["--json"]].concat());
        let text = timed(method, &args);
        for out in [&json, &text] {
            if out.status.code() == Some(2) {
                // A busy machine gave the first stage no time.
                assert!(
                    stderr(out).contains("stopped (TimeLimit)"),
                    "{method}: {}",
                    stderr(out)
                );
                continue;
            }
            assert!(out.status.success(), "{method}: {}", stderr(out));
            assert!(
                stderr(out).contains("time limit"),
                "{method}: {}",
                stderr(out)
            );
        }
        if json.status.success() {
            let v: Value = serde_json::from_str(&stdout(&json)).unwrap();
            assert_eq!(v["stop"], "time limit", "{method}: {v}");
            assert!(v["estimate"].as_f64().unwrap().is_finite(), "{method}: {v}");
        }
        if text.status.success() {
            let report = stdout(&text);
            assert!(
                report.contains("time limit"),
                "{method} does not say why it stopped: {report}"
            );
        }
    }
}

/// A checkpointed run stopped by `--time-limit` saves its chunks and says so; run again
/// (without the limit) it finishes with the bits of an uninterrupted run.
#[test]
fn time_limit_leaves_a_checkpoint_that_resumes_to_the_uninterrupted_bits() {
    let dir = common::scratch_dir("time-limit-checkpoint");
    let path = dir.join("run.json");
    let path = path.to_str().unwrap();
    let args = [
        "--integrand",
        "oscillatory",
        "--dims",
        "4",
        "--n",
        "4e7",
        "--json",
    ];
    let limited = output_or_hang(Command::new(example("integrate")).args(args).args([
        "--checkpoint",
        path,
        "--save-every",
        "4",
        "--time-limit",
        "0.3",
    ]));
    assert!(limited.status.success(), "{}", stderr(&limited));
    assert!(
        stderr(&limited).contains("time limit reached"),
        "{}",
        stderr(&limited)
    );
    let saved: PartialRun = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert!(!saved.is_complete());
    let resumed = run("integrate", &[&args[..], &["--checkpoint", path]].concat());
    let whole = run("integrate", &args);
    let estimate = |out: &std::process::Output| {
        let v: Value = serde_json::from_str(&stdout(out)).unwrap();
        (
            v["estimate"].clone(),
            v["std_error"].clone(),
            v["evaluations"].clone(),
        )
    };
    assert_eq!(estimate(&resumed), estimate(&whole));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The other programs that integrate take `--time-limit` too, and say the stop.
#[test]
fn time_limit_stops_the_other_programs() {
    let cases: [(&str, &[&str], &str); 3] = [
        (
            "asian_option",
            &[
                "--tol-rel",
                "1e-9",
                "--max-evals",
                "1e15",
                "--n",
                "256",
                "--json",
            ],
            "\"stop\":\"time limit\"",
        ),
        (
            "sensitivity",
            &[
                "--function",
                "ishigami",
                "--n",
                "4294967296",
                "--replicates",
                "2",
                "--json",
            ],
            "error: the run stopped (TimeLimit)",
        ),
        (
            "variance_reduction",
            &["--n", "1e13"],
            "stopped (time limit)",
        ),
    ];
    for (name, args, needle) in cases {
        let out = output_or_hang(
            Command::new(example(name))
                .args(args)
                .args(["--time-limit", "0.5"]),
        );
        let all = format!("{}{}", stdout(&out), stderr(&out));
        assert!(all.contains(needle), "{name}: {all}");
    }
}
