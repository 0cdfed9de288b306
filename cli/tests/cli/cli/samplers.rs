//! The QMC and stratified samplers from the command line, in `points` and `integrate`.

use super::*;

#[test]
fn qmc_samplers_and_scrambles_from_the_command_line() {
    // Unscrambled Sobol' starts at the origin and has no honest error bar.
    let out = run(
        "points",
        &[
            "--sampler",
            "sobol",
            "--scramble",
            "none",
            "--dims",
            "3",
            "--n",
            "4",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(stdout(&out).lines().next(), Some("0.0,0.0,0.0"));
    let single = run(
        "integrate",
        &[
            "--genz",
            "gaussian",
            "--dims",
            "2",
            "--sampler",
            "sobol",
            "--scramble",
            "none",
            "--n",
            "1024",
            "--json",
        ],
    );
    assert!(single.status.success(), "{}", stderr(&single));
    assert_eq!(json_field(&stdout(&single), "std_error"), "null");
    assert_eq!(json_field(&stdout(&single), "scramble"), "none");
    // Randomized sequences give replicate error bars that cover the truth.
    for (sampler, scramble) in [
        ("sobol", "owen"),
        ("sobol", "lms"),
        ("sobol", "xor"),
        ("halton", "permute"),
        ("halton", "owen"),
        ("hammersley", "permute"),
        ("lattice", "shift"),
    ] {
        let out = run(
            "integrate",
            &[
                "--genz",
                "oscillatory",
                "--dims",
                "3",
                "--sampler",
                sampler,
                "--scramble",
                scramble,
                "--n",
                "1024",
                "--replicates",
                "8",
                "--json",
            ],
        );
        assert!(
            out.status.success(),
            "{sampler}/{scramble}: {}",
            stderr(&out)
        );
        let json = stdout(&out);
        assert_within_ten_standard_errors(&json, &format!("{sampler}/{scramble}"));
    }
    assert_one_line_error(
        &run(
            "integrate",
            &[
                "--genz",
                "gaussian",
                "--dims",
                "2",
                "--sampler",
                "sobol",
                "--scramble",
                "none",
                "--replicates",
                "4",
            ],
        ),
        "replicates",
    );
    assert_one_line_error(
        &run(
            "integrate",
            &[
                "--genz",
                "gaussian",
                "--dims",
                "2",
                "--sampler",
                "latin",
                "--scramble",
                "owen",
            ],
        ),
        "built in",
    );
    assert_one_line_error(
        &run(
            "points",
            &[
                "--sampler",
                "lattice",
                "--scramble",
                "xor",
                "--dims",
                "2",
                "--n",
                "4",
            ],
        ),
        "none, shift",
    );
    assert_one_line_error(
        &run(
            "points",
            &[
                "--sampler",
                "sobol",
                "--scramble",
                "twist",
                "--dims",
                "2",
                "--n",
                "4",
            ],
        ),
        "owen",
    );
    assert_one_line_error(
        &run(
            "points",
            &["--sampler", "sobol", "--dims", "21202", "--n", "4"],
        ),
        "21201",
    );
}

#[test]
fn stratified_family_from_the_command_line() {
    // One point per cell of the p^t grid in every t-dimensional projection: Bush, t = 3, p = 5.
    let out = run(
        "points",
        &[
            "--sampler",
            "oa-bush",
            "--strength",
            "3",
            "--dims",
            "3",
            "--n",
            "125",
            "--seed",
            "4",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let mut cells = std::collections::HashSet::new();
    for line in stdout(&out).lines() {
        let cell: Vec<usize> = line
            .split(',')
            .map(|v| (v.parse::<f64>().unwrap() * 5.0) as usize)
            .collect();
        assert!(cells.insert(cell), "two points in one cell");
    }
    assert_eq!(cells.len(), 125);
    for (sampler, n) in [
        ("multijitter", "64"),
        ("cmj", "64"),
        ("oa-bose", "49"),
        ("nrooks-multistage", "64"),
        ("poisson", "64"),
        ("best-candidate", "64"),
        ("pmj02", "64"),
    ] {
        let out = run(
            "integrate",
            &[
                "--genz",
                "gaussian",
                "--dims",
                "2",
                "--sampler",
                sampler,
                "--n",
                n,
                "--replicates",
                "8",
                "--json",
            ],
        );
        assert!(out.status.success(), "{sampler}: {}", stderr(&out));
        let json = stdout(&out);
        assert_within_ten_standard_errors(&json, sampler);
    }
    assert_one_line_error(
        &run(
            "points",
            &["--sampler", "oa-bose", "--dims", "2", "--n", "50"],
        ),
        "nearest valid: 49 or 121",
    );
    assert_one_line_error(
        &run(
            "points",
            &[
                "--sampler",
                "oa-bush",
                "--strength",
                "3",
                "--dims",
                "2",
                "--n",
                "100",
            ],
        ),
        "nearest valid",
    );
    assert_one_line_error(
        &run(
            "points",
            &[
                "--sampler",
                "latin",
                "--strength",
                "3",
                "--dims",
                "2",
                "--n",
                "100",
            ],
        ),
        "strength",
    );
    assert_one_line_error(
        &run(
            "points",
            &[
                "--sampler",
                "oa-bose",
                "--strength",
                "3",
                "--dims",
                "2",
                "--n",
                "49",
            ],
        ),
        "oa-bush",
    );
}
