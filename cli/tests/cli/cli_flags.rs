//! Every example binary answers a bad command line (unknown flag, flag without its value,
//! malformed number, stray argument) with one line on stderr and a non-zero exit, before
//! doing any work.

use crate::common::run;

fn assert_one_line_error(name: &str, args: &[&str], needle: &str) {
    let out = run(name, args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{name} {args:?} succeeded");
    assert_eq!(stderr.lines().count(), 1, "{name} {args:?}: {stderr}");
    assert!(stderr.starts_with("error: "), "{name} {args:?}: {stderr}");
    assert!(
        stderr.contains(needle),
        "{name} {args:?}: {stderr} lacks {needle}"
    );
    assert!(out.stdout.is_empty(), "{name} {args:?} printed to stdout");
}

/// A flag each binary takes with a value, and valid values of its required flags.
const BINARIES: [(&str, &str, &[&str]); 9] = [
    ("points", "--n", &["--sampler", "sobol", "--dims", "2"]),
    ("integrate", "--n", &["--genz", "gaussian", "--dims", "2"]),
    ("variance_reduction", "--n", &[]),
    ("gallery", "--n", &["--out", "/tmp/mcint-never-written"]),
    (
        "convergence",
        "--passes",
        &["--out", "/tmp/mcint-never-written"],
    ),
    ("quality", "--input", &["--measure", "star"]),
    ("sensitivity", "--n", &["--function", "ishigami"]),
    ("asian_option", "--n", &[]),
    ("mlmc", "--eps", &[]),
];

#[test]
fn unknown_flags_are_refused_with_the_list_of_known_ones() {
    for (name, _, required) in BINARIES {
        let mut args = required.to_vec();
        args.push("--bogus");
        assert_one_line_error(name, &args, "unknown flag '--bogus'");
    }
}

#[test]
fn flags_without_values_are_refused() {
    for (name, flag, required) in BINARIES {
        let mut args = required.to_vec();
        args.push(flag);
        assert_one_line_error(name, &args, "needs a value");
    }
}

#[test]
fn malformed_numbers_are_refused() {
    for (name, flag, required) in BINARIES {
        if flag == "--input" {
            continue;
        }
        for bad in ["12x", "-3", "1e99999", "0x10", ""] {
            let mut args = required.to_vec();
            args.extend([flag, bad]);
            assert_one_line_error(name, &args, flag);
        }
    }
}

#[test]
fn stray_arguments_are_refused() {
    for (name, _, required) in BINARIES {
        let mut args = required.to_vec();
        args.push("stray");
        assert_one_line_error(name, &args, "unexpected argument 'stray'");
    }
}

#[test]
fn every_program_answers_help_with_its_flags() {
    for (name, flag, _) in BINARIES {
        let out = run(name, &["--help"]);
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{name} --help failed");
        assert!(text.contains(&format!("Usage: {name}")), "{name}: {text}");
        assert!(
            text.contains(flag),
            "{name} --help does not list {flag}: {text}"
        );
    }
}

#[test]
fn whole_numbers_may_be_written_in_scientific_notation() {
    let out = run(
        "integrate",
        &["--genz", "gaussian", "--dims", "2", "--n", "1e3", "--json"],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{out:?}");
    assert!(text.contains("\"evaluations\":1000"), "{text}");
    // Read exactly in decimal: a seed of 20 digits is the same seed either way (through an
    // f64 it would lose its last four digits and give another estimate).
    let estimate = |seed: &str| {
        let args = [
            "--genz", "gaussian", "--dims", "2", "--n", "64", "--seed", seed, "--json",
        ];
        let out = run("integrate", &args);
        assert!(out.status.success(), "{out:?}");
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        text.split("\"estimate\":")
            .nth(1)
            .unwrap()
            .split(',')
            .next()
            .unwrap()
            .to_string()
    };
    assert_eq!(
        estimate("1.2345678901234567891e19"),
        estimate("12345678901234567891")
    );
    assert_ne!(
        estimate("1.2345678901234567891e19"),
        estimate("12345678901234567890")
    );
    // Not a whole number, or too large for one: refused as before.
    for bad in ["1.5", "1e30", "1.0001e3", "2e-3"] {
        let args = ["--genz", "gaussian", "--dims", "2", "--n", bad];
        assert_one_line_error("integrate", &args, "expected a whole number");
    }
}

#[test]
fn a_value_that_starts_with_a_minus_sign_is_shown_how_to_pass() {
    let args = ["--genz", "gaussian", "--dims", "2", "--a", "-1,1"];
    assert_one_line_error("integrate", &args, "given after '='");
    // Given after '=', it reaches the check of its range.
    let args = ["--genz", "gaussian", "--dims", "2", "--a=-1,1"];
    assert_one_line_error("integrate", &args, "expected finite values > 0");
}

#[test]
fn sampler_errors_name_the_coordinates_an_estimator_draws() {
    let args = [
        "--genz",
        "gaussian",
        "--dims",
        "6",
        "--sampler",
        "best-candidate",
        "--estimator",
        "mis",
    ];
    assert_one_line_error("integrate", &args, "12 coordinates a point for --dims 6");
}

/// `--time-limit` takes a positive number of seconds; the checkpoint's step flags need
/// `--checkpoint` (they were silently ignored without it).
#[test]
fn time_limits_and_checkpoint_steps_are_checked() {
    let integrate = ["--genz", "gaussian", "--dims", "2"];
    for bad in ["0", "-1", "nan", "soon"] {
        assert_one_line_error(
            "integrate",
            &[&integrate[..], &["--time-limit", bad]].concat(),
            "--time-limit",
        );
    }
    for flag in ["--save-every", "--stop-after"] {
        assert_one_line_error(
            "integrate",
            &[&integrate[..], &[flag, "4"]].concat(),
            "applies to a run with --checkpoint",
        );
    }
    // A limit too long for the clock is no limit.
    let out = run(
        "integrate",
        &[&integrate[..], &["--n", "64", "--time-limit", "1e300"]].concat(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
