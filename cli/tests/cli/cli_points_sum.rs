//! `points --format sum`: one line per dimension with the sum of that coordinate over the
//! points, equal to the sums of the CSV output and of the library's points; bad input is a
//! one-line error. `cargo test` builds the examples before running this file.

use crate::common::{assert_one_line_error, run, stderr, stdout};
use mcint::Points;
use mcint::sampler::SamplerKind;

/// Runs `points` with `args` plus `--format format` and returns its standard output.
fn points(args: &[&str], format: &str) -> String {
    let mut all = args.to_vec();
    all.extend(["--format", format]);
    let out = run("points", &all);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    stdout(&out)
}

/// The sums printed by `--format sum`, one per line.
fn parse_sums(text: &str) -> Vec<f64> {
    text.lines()
        .map(|l| l.parse().unwrap_or_else(|_| panic!("not a number: {l:?}")))
        .collect()
}

/// Column sums of CSV rows, adding rows in order.
fn csv_sums(text: &str, dims: usize) -> Vec<f64> {
    let mut sums = vec![0.0f64; dims];
    for line in text.lines() {
        let row: Vec<f64> = line.split(',').map(|v| v.parse().unwrap()).collect();
        assert_eq!(row.len(), dims);
        for (s, x) in sums.iter_mut().zip(row) {
            *s += x;
        }
    }
    sums
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn sums_equal_the_sums_of_the_csv_points() {
    // Sizes below, at and across the 4096-point block of the example (a ragged last block).
    let cases: [(&str, &str, &str, &[&str]); 5] = [
        ("sobol", "3", "10000", &["--scramble", "owen"]),
        ("halton", "5", "4096", &[]),
        ("independent", "1", "1", &[]),
        ("latin", "2", "5000", &["--pass", "3"]),
        ("lattice", "4", "8193", &["--seed", "7"]),
    ];
    for (sampler, dims, n, extra) in cases {
        let mut args = vec!["--sampler", sampler, "--dims", dims, "--n", n];
        args.extend_from_slice(extra);
        let sums = parse_sums(&points(&args, "sum"));
        let d: usize = dims.parse().unwrap();
        assert_eq!(sums.len(), d, "{args:?}: one line per dimension");
        let from_csv = csv_sums(&points(&args, "csv"), d);
        assert_eq!(bits(&sums), bits(&from_csv), "{args:?}");
    }
}

#[test]
fn sums_equal_the_library_sums_in_index_order() {
    let (dims, n, seed, pass) = (6usize, 20_000u64, 3u64, 1u64);
    let sampler = SamplerKind::Sobol.build(dims, n, seed).unwrap();
    // Sobol' is extensible: pass 1 starts at 2^32 (its pass length; see --pass).
    let max = match sampler.passes() {
        mcint::sampler::PassKind::Extensible { max } => max,
        other => panic!("unexpected passes {other:?}"),
    };
    let mut block = Points::new(dims, n as usize).unwrap();
    sampler.fill(pass * max, &mut block).unwrap();
    let expected: Vec<f64> = (0..dims)
        .map(|d| {
            let mut s = 0.0;
            for &x in block.column(d) {
                s += x;
            }
            s
        })
        .collect();
    let text = points(
        &[
            "--sampler",
            "sobol",
            "--dims",
            "6",
            "--n",
            "20000",
            "--seed",
            "3",
            "--pass",
            "1",
        ],
        "sum",
    );
    assert_eq!(bits(&parse_sums(&text)), bits(&expected));
    // A scrambled Sobol' coordinate sums to about n/2: each is uniform on [0, 1).
    for s in parse_sums(&text) {
        assert!((s / n as f64 - 0.5).abs() < 0.01, "{s}");
    }
}

#[test]
fn sums_can_be_written_to_a_file() {
    let dir = std::env::temp_dir().join(format!("mcint-points-sum-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("sums.txt");
    let args = ["--sampler", "cmj", "--dims", "2", "--n", "64"];
    let mut with_out = args.to_vec();
    with_out.extend(["--format", "sum", "--out", file.to_str().unwrap()]);
    let out = run("points", &with_out);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(out.stdout.is_empty());
    let written = std::fs::read_to_string(&file).unwrap();
    assert_eq!(written, points(&args, "sum"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_input_with_format_sum_is_one_line() {
    let base = |extra: &[&'static str]| {
        let mut args = vec!["--format", "sum"];
        args.extend_from_slice(extra);
        run("points", &args)
    };
    assert_one_line_error(
        &base(&["--sampler", "sobol", "--dims", "2", "--n", "0"]),
        "--n = 0",
    );
    assert_one_line_error(
        &base(&["--sampler", "sobol", "--dims", "0", "--n", "4"]),
        "dims",
    );
    assert_one_line_error(
        &base(&["--sampler", "sobel", "--dims", "2", "--n", "4"]),
        "sobol",
    );
    assert_one_line_error(
        &base(&["--sampler", "jittered", "--dims", "2", "--n", "10"]),
        "nearest valid: 9 or 16",
    );
    assert_one_line_error(
        &run(
            "points",
            &[
                "--sampler",
                "sobol",
                "--dims",
                "2",
                "--n",
                "4",
                "--format",
                "sums",
            ],
        ),
        "sum",
    );
}
