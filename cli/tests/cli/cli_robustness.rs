//! Every example binary is a well-behaved command-line program: a reader that closes the pipe
//! (`| head -1`) ends it quietly, an argument that is not UTF-8 is a one-line error, sizes
//! beyond memory are refused before anything is allocated, and a full disk is reported.

use crate::common::{self, assert_one_line_error, example, run, stderr};
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

/// Programs, with arguments that make them print more than one line to stdout.
const TALKATIVE: &[(&str, &[&str])] = &[
    (
        "points",
        &["--sampler", "sobol", "--dims", "2", "--n", "1048576"],
    ),
    ("variance_reduction", &["--n", "4096"]),
    (
        "integrate",
        &["--genz", "gaussian", "--dims", "3", "--n", "4096"],
    ),
    ("sensitivity", &["--function", "ishigami", "--n", "1024"]),
    ("asian_option", &["--dates", "8", "--n", "256"]),
    (
        "mlmc",
        &[
            "--eps",
            "0.1",
            "--test",
            "--test-levels",
            "3",
            "--test-samples",
            "1000",
        ],
    ),
];

/// A program that exited with success and printed no panic.
fn assert_quiet_success(name: &str, out: &std::process::Output) {
    assert!(
        out.status.success(),
        "{name}: {:?} {}",
        out.status,
        stderr(out)
    );
    assert!(!stderr(out).contains("panicked"), "{name}: {}", stderr(out));
}

#[test]
fn a_closed_stdout_ends_every_program_quietly() {
    for (name, args) in TALKATIVE {
        let mut child = Command::new(example(name))
            .args(*args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut first = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut first)
            .unwrap();
        // The read end is closed here, as `head -1` closes it.
        let out = child.wait_with_output().unwrap();
        assert!(!first.is_empty(), "{name} printed nothing");
        assert_quiet_success(name, &out);
    }
}

/// Every program with arguments that make it write to stdout, its input files in `dir`.
fn every_program(dir: &std::path::Path) -> Vec<(&'static str, Vec<String>)> {
    std::fs::create_dir_all(dir).unwrap();
    let points = dir.join("points.txt");
    let listed = run(
        "points",
        &["--sampler", "sobol", "--dims", "2", "--n", "64"],
    );
    std::fs::write(&points, &listed.stdout).unwrap();
    let (points, out_dir) = (
        points.to_str().unwrap().to_string(),
        dir.join("figures").to_str().unwrap().to_string(),
    );
    let owned = |args: &[&str]| args.iter().map(|a| a.to_string()).collect::<Vec<_>>();
    TALKATIVE
        .iter()
        .map(|(name, args)| (*name, owned(args)))
        .chain([
            (
                "quality",
                owned(&["--input", &points, "--measure", "centered"]),
            ),
            (
                "gallery",
                owned(&["--out", &out_dir, "--n", "64", "--passes", "2"]),
            ),
            (
                "convergence",
                owned(&["--out", &out_dir, "--max-log2", "8", "--passes", "8"]),
            ),
            ("integrate", owned(&["--help"])),
            (
                "integrate",
                owned(&[
                    "--genz",
                    "gaussian,oscillatory",
                    "--dims",
                    "3",
                    "--n",
                    "4096",
                    "--json",
                ]),
            ),
        ])
        .collect()
}

/// Every program, its stdout closed before it writes anything (a reader that exits at once):
/// the first write fails, and the program ends quietly with success instead of panicking.
#[test]
fn a_stdout_closed_from_the_start_ends_every_program_quietly() {
    let dir = std::env::temp_dir().join(format!("mcint-closed-{}", std::process::id()));
    for (name, args) in every_program(&dir) {
        let mut child = Command::new(example(name))
            .args(&args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take()); // the read end closes before anything is written
        let out = child.wait_with_output().unwrap();
        assert_quiet_success(name, &out);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every program, its stdout on a full device: one line naming the error, status 2 (they
/// panicked with status 101, all but `points`).
#[cfg(target_os = "linux")]
#[test]
fn a_full_stdout_is_a_one_line_error_in_every_program() {
    let dir = std::env::temp_dir().join(format!("mcint-full-stdout-{}", std::process::id()));
    for (name, args) in every_program(&dir) {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = Command::new(example(name))
            .args(&args)
            .stdout(full)
            .output()
            .unwrap();
        assert_eq!(
            out.status.code(),
            Some(2),
            "{name} {args:?}: {}",
            stderr(&out)
        );
        let err = stderr(&out);
        let errors: Vec<&str> = err.lines().filter(|l| !l.starts_with("warning:")).collect();
        assert_eq!(
            errors,
            ["error: cannot write the output: No space left on device (os error 28)"],
            "{name} {args:?}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[cfg(unix)]
#[test]
fn an_argument_that_is_not_utf8_is_a_one_line_error() {
    use std::ffi::OsStr;
    use std::os::unix::ffi::OsStrExt;
    let bad = OsStr::from_bytes(b"--sampler\xff");
    for name in [
        "points",
        "integrate",
        "quality",
        "gallery",
        "convergence",
        "variance_reduction",
        "sensitivity",
        "asian_option",
        "mlmc",
    ] {
        let out = Command::new(example(name)).arg(bad).output().unwrap();
        assert_one_line_error(&out, "not valid UTF-8");
    }
}

#[test]
fn sizes_beyond_memory_are_refused_before_anything_is_allocated() {
    let out = run(
        "points",
        &[
            "--sampler",
            "independent",
            "--dims",
            "100000000000",
            "--n",
            "16",
        ],
    );
    assert_one_line_error(&out, "8 GiB");
    let out = run(
        "points",
        &[
            "--sampler",
            "independent",
            "--dims",
            "1000",
            "--n",
            "16",
            "--format",
            "png",
            "--pairs",
            "--out",
            "never.png",
        ],
    );
    assert_one_line_error(&out, "at most 16 dimensions");
    let out = run("integrate", &["--genz", "gaussian", "--dims", "10000000"]);
    assert_one_line_error(&out, "at most 131072");
    // An image of 10^7 points took 1.3 GB; the spectra's work is bounded too.
    let out = run(
        "gallery",
        &["--out", "/tmp/mcint-never-written", "--n", "1e7"],
    );
    assert_one_line_error(&out, "at most 65536");
    let out = run(
        "gallery",
        &[
            "--out",
            "/tmp/mcint-never-written",
            "--n",
            "65536",
            "--passes",
            "1024",
        ],
    );
    assert_one_line_error(&out, "at most 2^34");
    // Two points are too few for the stratified samplers, which draw 289 or 343 instead: the
    // bound counts those (it let 4.5 times its work through).
    let out = run(
        "gallery",
        &[
            "--out",
            "/tmp/mcint-never-written",
            "--n",
            "2",
            "--passes",
            "1024",
            "--frequency",
            "256",
        ],
    );
    assert_one_line_error(&out, "up to 343 points");
}

/// Input files are read only when they are regular files, and at most 64 MiB of them:
/// `quality --input /dev/zero` read 8 GiB before failing, and a pipe (`/dev/stdout` with
/// stdout a pipe) blocked forever.
#[cfg(target_os = "linux")]
#[test]
fn input_files_must_be_regular_and_bounded() {
    use crate::common::output_or_hang;
    let dir = common::scratch_dir("inputs");
    let big = dir.join("big.csv");
    std::fs::File::create(&big)
        .unwrap()
        .set_len((64 << 20) + 1)
        .unwrap();
    let big = big.to_str().unwrap();
    let dir_path = dir.to_str().unwrap();
    let cases: [(&str, Vec<&str>, &str); 6] = [
        (
            "quality",
            vec!["--input", "/dev/zero", "--measure", "star"],
            "a device",
        ),
        (
            "quality",
            vec!["--input", "/dev/stdout", "--measure", "star"],
            "a pipe",
        ),
        (
            "quality",
            vec!["--input", dir_path, "--measure", "star"],
            "a directory",
        ),
        (
            "quality",
            vec!["--input", big, "--measure", "star"],
            "larger than 67108864 bytes",
        ),
        (
            "points",
            vec![
                "--sampler",
                "sobol",
                "--dims",
                "2",
                "--n",
                "4",
                "--measure",
                "gaussian",
                "--cov",
                "/dev/zero",
            ],
            "a device",
        ),
        (
            "points",
            vec![
                "--sampler",
                "sobol",
                "--dims",
                "2",
                "--n",
                "4",
                "--measure",
                "gaussian",
                "--cov",
                big,
            ],
            "larger than",
        ),
    ];
    for (name, args, needle) in cases {
        // stdout a pipe, kept open: /dev/stdout is that pipe.
        let out = output_or_hang(Command::new(example(name)).args(&args));
        assert_one_line_error(&out, needle);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_is_an_error_not_a_silent_success() {
    let dir = std::env::temp_dir().join(format!("mcint-full-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for format in ["svg", "png"] {
        let path = dir.join(format!("full.{format}"));
        std::os::unix::fs::symlink("/dev/full", &path).unwrap();
        let out = run(
            "points",
            &[
                "--sampler",
                "sobol",
                "--dims",
                "2",
                "--n",
                "64",
                "--format",
                format,
                "--out",
                path.to_str().unwrap(),
            ],
        );
        assert_one_line_error(&out, "No space left on device");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `convergence` checks `--passes` before it makes the output folder, and the library's
/// refusals name the flag (they said `passes`, and left an empty folder behind).
#[test]
fn convergence_checks_its_flags_before_making_the_folder() {
    let dir = common::scratch_dir("convergence-flags");
    let out = dir.join("plots");
    let out = out.to_str().unwrap();
    let refused = run("convergence", &["--out", out, "--passes", "1"]);
    assert_one_line_error(&refused, "invalid --passes = 1: expected 2 to 2^20");
    assert!(!std::path::Path::new(out).exists());
    std::fs::remove_dir_all(&dir).ok();
}
