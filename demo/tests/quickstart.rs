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
