//! `integrate` cancelled by SIGINT or SIGTERM: it stops after its current chunks, prints what
//! it has (the JSON says `"stop": "cancelled"`) and exits with status 130; with
//! `--checkpoint` it saves first, and the run resumed later gives the uninterrupted bits.
#![cfg(target_os = "linux")]

mod common;

use common::{example, run, stderr, stdout};
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
