//! The `quality` example binary, run as a user would: each measure prints the library's value
//! alone on one line, and malformed input gives a one-line error with a non-zero exit.
//! `cargo test` builds the examples before running this file.

use mcint::Points;
use mcint::quality;
use mcint::quality::Discrepancy;
use std::path::PathBuf;
use std::process::Output;

use crate::common::{assert_one_line_error, run, stderr, stdout};

/// A fresh directory under the system temp dir, unique to this process and `tag`.
fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mcint-cli-quality-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("create temp dir");
    dir
}

fn write(dir: &std::path::Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write point file");
    path.to_str().expect("utf-8 temp path").to_string()
}

/// Points of a small deterministic set, as rows and as CSV text in `points`' format.
fn sample(n: usize, dims: usize) -> (Points, String) {
    let mut points = Points::new(dims, n).unwrap();
    let mut state = 0x1234_5678_9abc_def0u64;
    let mut text = String::new();
    let mut rows = vec![vec![0.0; dims]; n];
    for row in &mut rows {
        for x in row.iter_mut() {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            *x = (state >> 11) as f64 * 2f64.powi(-53);
        }
    }
    for (dim, column) in points.columns_mut().enumerate() {
        for (x, row) in column.iter_mut().zip(&rows) {
            *x = row[dim];
        }
    }
    for row in &rows {
        let fields: Vec<String> = row.iter().map(|x| format!("{x:?}")).collect();
        text.push_str(&fields.join(","));
        text.push('\n');
    }
    (points, text)
}

fn printed_value(output: &Output) -> f64 {
    assert!(output.status.success(), "{}", stderr(output));
    let text = stdout(output);
    assert_eq!(text.lines().count(), 1, "not one line: {text:?}");
    text.trim().parse().expect("a number")
}

#[test]
fn each_measure_prints_the_library_value() {
    let dir = temp_dir("values");
    let (points2, text2) = sample(300, 2);
    let (points5, text5) = sample(200, 5);
    let file2 = write(&dir, "two.csv", &text2);
    let file5 = write(&dir, "five.csv", &text5);
    type Measure = fn(&Points) -> mcint::Result<f64>;
    let cases: [(&str, bool, Measure); 8] = [
        ("l2-star", false, |p: &Points| Discrepancy::L2Star.root(p)),
        ("l2-star", true, |p: &Points| Discrepancy::L2Star.squared(p)),
        ("centered", false, |p: &Points| {
            Discrepancy::Centered.root(p)
        }),
        ("centered", true, |p: &Points| {
            Discrepancy::Centered.squared(p)
        }),
        ("wrap-around", false, |p: &Points| {
            Discrepancy::WrapAround.root(p)
        }),
        ("wrap-around", true, |p: &Points| {
            Discrepancy::WrapAround.squared(p)
        }),
        ("mixture", false, |p: &Points| Discrepancy::Mixture.root(p)),
        ("mixture", true, |p: &Points| {
            Discrepancy::Mixture.squared(p)
        }),
    ];
    for (measure, squared, f) in cases {
        for (file, points) in [(&file2, &points2), (&file5, &points5)] {
            let mut args = vec!["--input", file.as_str(), "--measure", measure];
            if squared {
                args.push("--squared");
            }
            let printed = printed_value(&run("quality", &args));
            // The CSV text and the printed value both round-trip f64 exactly.
            assert_eq!(printed, f(points).unwrap(), "{measure} squared={squared}");
        }
    }
    let printed = printed_value(&run("quality", &["--input", &file2, "--measure", "star"]));
    assert_eq!(printed, quality::star_discrepancy(&points2).unwrap());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn reads_what_the_points_example_writes() {
    let dir = temp_dir("points");
    let file = dir.join("sobol.csv");
    let file = file.to_str().unwrap();
    let out = run(
        "points",
        &[
            "--sampler",
            "sobol",
            "--dims",
            "2",
            "--n",
            "64",
            "--scramble",
            "none",
            "--out",
            file,
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(file).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let mut points = Points::new(2, rows.len()).unwrap();
    for (dim, column) in points.columns_mut().enumerate() {
        for (x, row) in column.iter_mut().zip(&rows) {
            *x = row[dim];
        }
    }
    let d = printed_value(&run("quality", &["--input", file, "--measure", "star"]));
    assert_eq!(d, quality::star_discrepancy(&points).unwrap());
    // 64 unscrambled Sobol' points form a digital (0, 6, 2)-net in base 2: 1/(2N) <= D* (the
    // projection on one axis alone) and N D* <= m/2 + 3/2 (Niederreiter 1987, as quoted by
    // Larcher & Pillichshammer 2003).
    assert!(d >= 1.0 / 128.0 && 64.0 * d <= 4.5, "D* = {d}");
    // ... and its t-value is 0; the first 48 points are not a net at all.
    let t = run("quality", &["--input", file, "--measure", "t-value"]);
    assert!(t.status.success(), "{}", stderr(&t));
    assert_eq!(stdout(&t), "0\n");
    let first_48: String = text.lines().take(48).map(|l| format!("{l}\n")).collect();
    let partial = write(&dir, "first48.csv", &first_48);
    assert_one_line_error(
        &run("quality", &["--input", &partial, "--measure", "t-value"]),
        "32 or 64",
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn malformed_input_gives_one_line_errors() {
    let dir = temp_dir("errors");
    let ragged = write(&dir, "ragged.csv", "0.1,0.2\n0.3\n");
    let outside = write(&dir, "outside.csv", "0.1,0.2\n0.3,1.5\n");
    let negative = write(&dir, "negative.csv", "0.1,-0.2\n");
    let nan = write(&dir, "nan.csv", "0.1,NaN\n");
    let word = write(&dir, "word.csv", "0.1,0.2\n0.3,abc\n");
    let blank_line = write(&dir, "blank.csv", "0.1,0.2\n\n0.3,0.4\n");
    let empty = write(&dir, "empty.csv", "");
    let only_newlines = write(&dir, "newlines.csv", "\n\n");
    let three_d = write(&dir, "three.csv", "0.1,0.2,0.3\n0.4,0.5,0.6\n");
    let good = write(&dir, "good.csv", "0.1,0.2\n0.3,0.4\n");
    let missing = dir.join("no-such-file.csv");
    let missing = missing.to_str().unwrap();

    let cases: [(&[&str], &str); 14] = [
        (
            &["--input", &ragged, "--measure", "l2-star"],
            "line 2: 1 coordinates",
        ),
        (
            &["--input", &outside, "--measure", "centered"],
            "outside [0, 1]",
        ),
        (
            &["--input", &negative, "--measure", "mixture"],
            "line 1, column 2",
        ),
        (&["--input", &nan, "--measure", "star"], "outside [0, 1]"),
        (
            &["--input", &word, "--measure", "wrap-around"],
            "'abc' is not a number",
        ),
        (
            &["--input", &blank_line, "--measure", "star"],
            "line 2, column 1",
        ),
        (&["--input", &empty, "--measure", "l2-star"], "no points"),
        (
            &["--input", &only_newlines, "--measure", "l2-star"],
            "no points",
        ),
        (&["--input", missing, "--measure", "l2-star"], "cannot read"),
        (&["--input", &three_d, "--measure", "star"], "1 or 2"),
        (
            &["--input", &good, "--measure", "volume"],
            "invalid --measure = 'volume'",
        ),
        (
            &["--input", &good, "--measure", "star", "--squared"],
            "--squared",
        ),
        (&["--measure", "star"], "missing --input"),
        (&["--input", &good], "missing --measure"),
    ];
    for (args, needle) in cases {
        assert_one_line_error(&run("quality", args), needle);
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The exact L2 discrepancies cost `N^2 d`: 2^18 + 1 points in one dimension (2^36 + 2^19 + 1
/// terms) are refused, with the largest size allowed, rather than measured for minutes; 80,000
/// points took 6 s, and the 64 MiB input limit allows sets that would take hours.
#[test]
fn l2_discrepancies_of_sets_too_large_to_measure_are_refused() {
    let dir = temp_dir("l2-cost");
    let many = write(&dir, "many.csv", &"0.5\n".repeat((1 << 18) + 1));
    for measure in ["l2-star", "centered", "wrap-around", "mixture"] {
        assert_one_line_error(
            &run("quality", &["--input", &many, "--measure", measure]),
            "at most 262144 points in 1 dimensions",
        );
    }
    // The t-value is not an L2 measure: measured.
    let t = run("quality", &["--input", &many, "--measure", "t-value"]);
    assert!(!String::from_utf8_lossy(&t.stderr).contains("2^36"));
    std::fs::remove_dir_all(&dir).ok();
}
