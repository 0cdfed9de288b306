//! `points`: CSV and binary output against the library, and bad input.

use super::*;

#[test]
fn points_csv_round_trips_and_matches_the_library() {
    use mcint::sampler::{LatinHypercube, Sampler};
    let out = run(
        "points",
        &[
            "--sampler",
            "latin",
            "--dims",
            "3",
            "--n",
            "50",
            "--seed",
            "9",
            "--pass",
            "2",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    let rows: Vec<Vec<f64>> = text
        .lines()
        .map(|l| l.split(',').map(|v| v.parse().expect("number")).collect())
        .collect();
    assert_eq!(rows.len(), 50);
    let sampler = LatinHypercube::new(3, 50, 9).unwrap();
    let mut p = [0.0; 3];
    for (i, row) in rows.iter().enumerate() {
        sampler.point(100 + i as u64, &mut p).unwrap();
        assert_eq!(row.as_slice(), &p, "row {i} differs from point {}", 100 + i);
    }
}

#[test]
fn points_bin_is_little_endian_row_major() {
    let dir = std::env::temp_dir().join(format!("mcint-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("points.bin");
    let file_arg = file.to_str().unwrap();
    let out = run(
        "points",
        &[
            "--sampler",
            "jittered",
            "--dims",
            "2",
            "--n",
            "16",
            "--format",
            "bin",
            "--out",
            file_arg,
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let bytes = std::fs::read(&file).unwrap();
    assert_eq!(bytes.len(), 16 * 2 * 8);
    let values: Vec<f64> = bytes
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect();
    // Point i of a 4x4 jittered pass lies in cell (i % 4, i / 4).
    for (i, xy) in values.chunks_exact(2).enumerate() {
        assert_eq!(
            ((xy[0] * 4.0) as usize, (xy[1] * 4.0) as usize),
            (i % 4, i / 4)
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn points_rejects_bad_input_with_one_line() {
    assert_one_line_error(
        &run("points", &["--sampler", "sobel", "--dims", "2", "--n", "4"]),
        "independent, jittered, latin, sobol",
    );
    assert_one_line_error(
        &run(
            "points",
            &["--sampler", "jittered", "--dims", "2", "--n", "10"],
        ),
        "nearest valid: 9 or 16",
    );
    assert_one_line_error(
        &run("points", &["--sampler", "latin", "--dims", "0", "--n", "4"]),
        "dims",
    );
    assert_one_line_error(
        &run("points", &["--sampler", "latin", "--dims", "2", "--n", "0"]),
        "--n",
    );
    assert_one_line_error(
        &run("points", &["--sampler", "latin", "--dims", "x", "--n", "4"]),
        "--dims",
    );
    assert_one_line_error(
        &run("points", &["--sampler", "latin", "--dims", "2"]),
        "missing --n",
    );
    assert_one_line_error(
        &run(
            "points",
            &[
                "--sampler",
                "latin",
                "--dims",
                "2",
                "--n",
                "4",
                "--format",
                "xml",
            ],
        ),
        "csv, bin, svg or png",
    );
    assert_one_line_error(
        &run(
            "points",
            &[
                "--sampler",
                "latin",
                "--dims",
                "2",
                "--n",
                "4",
                "--bogus",
                "1",
            ],
        ),
        "unknown flag",
    );
    assert_one_line_error(&run("points", &["--sampler"]), "needs a value");
}
