//! The README's demonstration prints its table, names its source, and takes no flags.

use std::process::Command;

fn quickstart(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_quickstart"))
        .args(args)
        .output()
        .expect("the quickstart binary runs")
}

#[test]
fn quickstart_prints_its_table() {
    let out = quickstart(&[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in [
        "uniform, independent",
        "importance",
        "jittered",
        "latin hypercube",
        "genz gaussian",
        // The source the equation numbers refer to.
        "W. Jarosz, \"Efficient Monte Carlo Methods for Light Transport in Scattering Media\"",
    ] {
        assert!(text.contains(needle), "missing {needle:?} in\n{text}");
    }
}

#[test]
fn quickstart_takes_no_flags() {
    for args in [&["--n", "5"][..], &["stray"]] {
        let out = quickstart(args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success());
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.contains("takes no flags"), "{stderr}");
        assert!(out.stdout.is_empty());
    }
    // --help says what it does, and runs nothing.
    for flag in ["--help", "-h"] {
        let out = quickstart(&[flag]);
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{out:?}");
        assert!(stdout.contains("Usage: quickstart"), "{stdout}");
        assert!(!stdout.contains("genz gaussian"), "{stdout}");
    }
}

/// A closed stdout (`quickstart | head -1`) ends the program quietly with success, and a full
/// disk with one line and status 2: `println!` panicked on both.
#[cfg(target_os = "linux")]
#[test]
fn quickstart_ends_quietly_on_a_closed_pipe_and_says_so_on_a_full_disk() {
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_quickstart"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The rows come after their runs: the read end is closed before most of them.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");

    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_quickstart"))
        .stdout(full)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("error: cannot write the table"),
        "{stderr}"
    );
}
