//! `integrate --checkpoint` killed (SIGKILL) at 20 moments of its run: every checkpoint it
//! leaves is whole (saves are atomic: a temporary file, synced, renamed), and the run resumed
//! from it gives the bits of an uninterrupted run. The checkpoint file itself: saved through a
//! symbolic link, cleared of the temporary files of killed saves, locked against a second
//! process, and refused when it is no regular file.
#![cfg(unix)]

use crate::common::{
    assert_one_line_error, example, output_or_hang, run, scratch_dir, stderr, stdout,
};
use mcint::PartialRun;
use serde_json::Value;
use std::process::{Command, Stdio};

/// A run of 123 chunks of 16384 points on one thread, saved after every chunk.
const ARGS: &[&str] = &[
    "--genz",
    "gaussian",
    "--dims",
    "5",
    "--n",
    "2000000",
    "--threads",
    "1",
    "--json",
];

fn answer(json: &str) -> (String, String) {
    let v: Value = serde_json::from_str(json.trim()).expect("one JSON object");
    (v["estimate"].to_string(), v["std_error"].to_string())
}

#[test]
fn runs_killed_during_saves_resume_to_the_uninterrupted_bits() {
    let whole = run("integrate", ARGS);
    assert!(whole.status.success(), "{}", stderr(&whole));
    let whole = answer(&stdout(&whole));
    let dir = std::env::temp_dir().join(format!("mcint-kill-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut interrupted = 0;
    for trial in 0..20u64 {
        let path = dir.join(format!("trial-{trial}.json"));
        let path_arg = path.to_str().unwrap();
        let mut child = Command::new(example("integrate"))
            .args(ARGS)
            .args(["--checkpoint", path_arg, "--save-every", "1"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        // Kills spread over the run by its progress, not by the clock: trial t waits until
        // a checkpoint of at least 6t + 1 of the 123 chunks has been saved, then kills at
        // once, which lands during the next chunks or their saves.
        let target = 6 * trial + 1;
        while child.try_wait().unwrap().is_none() {
            let saved = std::fs::read_to_string(&path)
                .ok()
                .and_then(|text| serde_json::from_str::<PartialRun>(&text).ok())
                .map_or(0, |part| part.chunks_done());
            if saved >= target {
                break;
            }
            std::thread::yield_now();
        }
        let _ = child.kill();
        let status = child.wait().unwrap();
        interrupted += u64::from(!status.success());
        if path.exists() {
            let text = std::fs::read_to_string(&path).unwrap();
            serde_json::from_str::<PartialRun>(&text)
                .unwrap_or_else(|e| panic!("trial {trial}: a broken checkpoint ({e})"));
        }
        let resumed = run("integrate", &[ARGS, &["--checkpoint", path_arg]].concat());
        assert!(
            resumed.status.success(),
            "trial {trial}: {}",
            stderr(&resumed)
        );
        assert_eq!(answer(&stdout(&resumed)), whole, "trial {trial}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
    eprintln!("{interrupted} of 20 runs were interrupted");
    // Most kills must land during the run, or the test shows nothing.
    assert!(
        interrupted >= 10,
        "only {interrupted} of 20 runs were interrupted"
    );
}

/// A checkpoint named `*.partial` is saved through a temporary file too, two checkpoints whose
/// names differ only by extension run side by side without sharing one, neither leaves a
/// temporary or lock file, and a checkpoint larger than any (64 MiB) is refused after a
/// bounded read.
#[test]
fn checkpoint_names_never_collide_and_reads_are_bounded() {
    let dir = std::env::temp_dir().join(format!("mcint-names-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let with = |path: &std::path::Path| {
        Command::new(example("integrate"))
            .args(ARGS)
            .args(["--checkpoint", path.to_str().unwrap(), "--save-every", "1"])
            .output()
            .unwrap()
    };
    let partial = dir.join("run.partial");
    let out = with(&partial);
    assert!(out.status.success(), "{}", stderr(&out));
    serde_json::from_str::<PartialRun>(&std::fs::read_to_string(&partial).unwrap()).unwrap();
    let (a, b) = (dir.join("s.json"), dir.join("s.txt"));
    let (ta, tb) = (
        std::thread::spawn({
            let a = a.clone();
            move || with(&a)
        }),
        std::thread::spawn({
            let b = b.clone();
            move || with(&b)
        }),
    );
    for out in [ta.join().unwrap(), tb.join().unwrap()] {
        assert!(out.status.success(), "{}", stderr(&out));
    }
    for path in [&a, &b] {
        serde_json::from_str::<PartialRun>(&std::fs::read_to_string(path).unwrap()).unwrap();
    }
    // No temporary or lock file is left behind by a finished run.
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            name.ends_with(".tmp") || name.ends_with(".lock")
        })
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    // A regular file past the bound (sparse: it takes no room on disk).
    let huge = dir.join("huge.json");
    std::fs::File::create(&huge)
        .unwrap()
        .set_len((64 << 20) + 1)
        .unwrap();
    let out = run(
        "integrate",
        &[ARGS, &["--checkpoint", huge.to_str().unwrap()]].concat(),
    );
    assert!(!out.status.success());
    assert!(stderr(&out).contains("larger than"), "{}", stderr(&out));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A checkpoint path that exists and is no regular file is refused before the run, in one
/// line, instead of blocking on a read that never ends: `/dev/stdout` when stdout is a pipe,
/// a FIFO, a directory, a device.
#[test]
fn checkpoints_that_are_not_regular_files_are_refused() {
    let dir = scratch_dir("special");
    let fifo = dir.join("fifo");
    let made = Command::new("mkfifo").arg(&fifo).status();
    let mut cases = vec![
        ("/dev/stdout".to_string(), "is a pipe"),
        (dir.to_str().unwrap().to_string(), "is a directory"),
        ("/dev/null".to_string(), "is a device"),
    ];
    if made.is_ok_and(|s| s.success()) {
        cases.push((fifo.to_str().unwrap().to_string(), "is a pipe"));
    } else {
        eprintln!("no mkfifo: the FIFO case is skipped");
    }
    for (path, what) in cases {
        let args = [ARGS, &["--checkpoint", &path]].concat();
        // stdout is a pipe here, so /dev/stdout is one too.
        let out = output_or_hang(Command::new(example("integrate")).args(&args));
        assert_eq!(out.status.code(), Some(2), "{path}: {}", stderr(&out));
        assert_one_line_error(&out, what);
        assert!(
            stderr(&out).contains("takes a regular file"),
            "{}",
            stderr(&out)
        );
        assert!(stdout(&out).is_empty(), "{path}: {}", stdout(&out));
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The chunks saved in the checkpoint at `path`.
fn chunks_saved(path: &std::path::Path) -> u64 {
    let text = std::fs::read_to_string(path).unwrap();
    serde_json::from_str::<PartialRun>(&text)
        .unwrap()
        .chunks_done()
}

/// A checkpoint given as a symbolic link: every save updates the link's target (even one
/// that does not exist yet), and the link stays a link.
#[test]
fn a_checkpoint_through_a_symbolic_link_saves_to_its_target() {
    let dir = scratch_dir("symlink");
    std::fs::create_dir_all(dir.join("real")).unwrap();
    let (link, target) = (dir.join("link.json"), dir.join("real/run.json"));
    std::os::unix::fs::symlink("real/run.json", &link).unwrap();
    let link_arg = link.to_str().unwrap();
    let step = |stop_after: &str| {
        let args = ["--checkpoint", link_arg, "--save-every", "1"];
        run(
            "integrate",
            &[ARGS, &args, &["--stop-after", stop_after]].concat(),
        )
    };
    for (stop_after, saved) in [("2", 2), ("3", 5)] {
        let out = step(stop_after);
        assert!(out.status.success(), "{}", stderr(&out));
        let meta = std::fs::symlink_metadata(&link).unwrap();
        assert!(meta.file_type().is_symlink(), "the link was replaced");
        assert_eq!(chunks_saved(&target), saved);
        // --json says the run is saved, not finished (it printed nothing, exit status 0).
        let v: Value = serde_json::from_str(stdout(&out).trim()).expect("one JSON object");
        assert_eq!(v["finished"], false, "{v}");
        assert_eq!(v["stop"], "stop after", "{v}");
        assert_eq!(
            (v["chunks_done"].as_u64(), v["total_chunks"].as_u64()),
            (Some(saved), Some(123))
        );
    }
    let whole = run("integrate", ARGS);
    let resumed = run("integrate", &[ARGS, &["--checkpoint", link_arg]].concat());
    assert!(resumed.status.success(), "{}", stderr(&resumed));
    assert_eq!(answer(&stdout(&resumed)), answer(&stdout(&whole)));
    assert_eq!(chunks_saved(&target), 123);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The temporary files that SIGKILLed saves leave (`.NAME.tmp`, and `.NAME.PID.N.tmp` of
/// earlier versions, here of a process that no longer runs) are removed by the next run of
/// that checkpoint; the files of other checkpoints are not.
#[test]
fn temporary_files_of_killed_saves_are_removed_by_the_next_run() {
    let dir = scratch_dir("stale");
    let path = dir.join("run.json");
    let stale = [".run.json.tmp", ".run.json.4194304.7.tmp"];
    let others = [".other.json.tmp", ".run.json.x.tmp", "run.json.tmp"];
    for name in stale.iter().chain(&others) {
        std::fs::write(dir.join(name), "{\"half\": ").unwrap();
    }
    let args = ["--checkpoint", path.to_str().unwrap(), "--stop-after", "1"];
    let out = run("integrate", &[ARGS, &args].concat());
    assert!(out.status.success(), "{}", stderr(&out));
    let mut left: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    let mut expected: Vec<String> = others.iter().map(|s| s.to_string()).collect();
    expected.push("run.json".into());
    expected.sort();
    assert_eq!(left, expected);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A second process on a checkpoint that a running process holds is refused at once, in one
/// line with exit status 2, and leaves the checkpoint to the first; once the first is killed
/// (SIGKILL: its lock goes with it), the checkpoint runs again.
#[test]
fn a_second_process_on_a_checkpoint_in_use_is_refused() {
    let dir = scratch_dir("locked");
    let path = dir.join("run.json");
    let path_arg = path.to_str().unwrap();
    // 12208 chunks: far more than this test lets it run.
    let mut long: Vec<&str> = ARGS
        .iter()
        .map(|&a| if a == "2000000" { "200000000" } else { a })
        .collect();
    long.extend(["--checkpoint", path_arg, "--save-every", "1"]);
    let mut first = Command::new(example("integrate"))
        .args(&long)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // Started: its first save is done, so it holds the lock.
    while !path.exists() {
        assert!(first.try_wait().unwrap().is_none(), "the first run ended");
        std::thread::yield_now();
    }
    let second = [&long[..], &["--stop-after", "1"]].concat();
    let refused = output_or_hang(Command::new(example("integrate")).args(&second));
    assert_eq!(refused.status.code(), Some(2), "{}", stderr(&refused));
    assert_one_line_error(&refused, "is in use by another process");
    assert!(first.try_wait().unwrap().is_none(), "the first run ended");
    first.kill().unwrap();
    first.wait().unwrap();
    let after = run("integrate", &second);
    assert!(after.status.success(), "{}", stderr(&after));
    std::fs::remove_dir_all(&dir).unwrap();
}
