//! The measure-based command lines: `asian_option` (prices and their closed form, the
//! control variate, bad input), `points --measure gaussian` (moments of the written points,
//! bad covariance files) and `integrate --integrand keister`.

use crate::common::{self, assert_one_line_error, run, stdout};
use serde_json::Value;

fn json(name: &str, args: &[&str]) -> Value {
    let out = run(name, args);
    assert!(
        out.status.success(),
        "{name} {args:?}: {}",
        common::stderr(&out)
    );
    serde_json::from_str(&stdout(&out)).expect("one JSON object")
}

fn number(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

#[test]
fn asian_option_prices_cover_the_closed_form_and_the_control_helps() {
    for construction in ["standard", "bridge", "pca"] {
        let v = json(
            "asian_option",
            &[
                "--payoff",
                "geometric",
                "--construction",
                construction,
                "--dates",
                "32",
                "--json",
            ],
        );
        let (price, se, exact) = (
            number(&v, "price"),
            number(&v, "std_error"),
            number(&v, "exact"),
        );
        assert!(
            (price - exact).abs() < 5.0 * se,
            "{construction}: {price} vs {exact}"
        );
        assert_eq!(v["evaluations"].as_u64(), Some(16 * 4096));
        assert!(v["converged"].is_null());
    }
    let plain = json(
        "asian_option",
        &[
            "--dates",
            "32",
            "--sampler",
            "independent",
            "--n",
            "20000",
            "--json",
        ],
    );
    let control = json(
        "asian_option",
        &[
            "--dates",
            "32",
            "--sampler",
            "independent",
            "--n",
            "20000",
            "--control",
            "geometric",
            "--json",
        ],
    );
    assert!(plain["exact"].is_null());
    // The two estimate the same price; the control cuts the error bar several times over.
    let (a, b) = (number(&plain, "price"), number(&control, "price"));
    let (sa, sb) = (number(&plain, "std_error"), number(&control, "std_error"));
    assert!(
        (a - b).abs() < 5.0 * (sa * sa + sb * sb).sqrt(),
        "{a} vs {b}"
    );
    assert!(sb < sa / 4.0, "control {sb} vs plain {sa}");
    let tol = json(
        "asian_option",
        &["--construction", "bridge", "--tol-rel", "1e-3", "--json"],
    );
    assert_eq!(tol["converged"], Value::Bool(true));
    // Met: t_{15, 0.975} times the (inflated) standard error is within the tolerance, so
    // 1.96 times it is too.
    let half = 1.96 * number(&tol, "std_error");
    assert!(half <= 1e-3 * number(&tol, "price"), "{tol}");
}

/// `--help` states the default of every choice, and they are the ones a run without flags
/// uses (issue 38 found the choices listed without their defaults).
#[test]
fn asian_option_help_states_the_defaults_a_plain_run_uses() {
    let out = run("asian_option", &["--help"]);
    assert!(out.status.success());
    let help = stdout(&out);
    let report = json("asian_option", &["--n", "256", "--json"]);
    for (flag, key, value) in [
        ("--construction", "construction", "standard"),
        ("--sampler", "sampler", "sobol"),
        ("--control", "control", "none"),
        ("--payoff", "payoff", "arithmetic"),
    ] {
        let line = help
            .lines()
            .find(|l| l.trim_start().starts_with(flag))
            .unwrap_or_else(|| panic!("{flag} missing from\n{help}"));
        assert!(line.contains(&format!("{value} (default")), "{line}");
        assert_eq!(report[key], value, "{key}");
    }
    let replicates = help.lines().find(|l| l.contains("--replicates")).unwrap();
    assert!(replicates.contains("default 16"), "{replicates}");
    assert_eq!(report["replicates"], 16);
}

/// Prices far from 1 keep a readable form: `--s0 1e200` printed a 201-digit price and
/// interval with ten decimals each.
#[test]
fn asian_option_prints_extreme_prices_with_an_exponent() {
    let out = run(
        "asian_option",
        &["--s0", "1e200", "--strike", "1e200", "--n", "1024"],
    );
    assert!(out.status.success(), "{}", common::stderr(&out));
    let text = stdout(&out);
    let price = text
        .lines()
        .find_map(|l| l.strip_prefix("price       "))
        .unwrap_or_else(|| panic!("a price line in {text}"));
    // An at-the-money Asian call with these settings is worth a few percent of S0.
    let value: f64 = price.parse().unwrap_or_else(|_| panic!("{text}"));
    assert!(
        price.contains('e') && (1e198..1e199).contains(&value),
        "{text}"
    );
    assert!(text.contains("S0 1e200 K 1e200 "), "{text}");
    assert!(text.lines().all(|l| l.len() < 80), "{text}");
    // The closed form of the geometric payoff scales too.
    let out = run(
        "asian_option",
        &[
            "--payoff",
            "geometric",
            "--s0",
            "1e-200",
            "--strike",
            "1e-200",
            "--n",
            "1024",
        ],
    );
    let text = stdout(&out);
    let exact = text
        .lines()
        .find_map(|l| {
            l.strip_suffix(" (closed form)")?
                .strip_prefix("exact       ")
        })
        .unwrap_or_else(|| panic!("an exact line in {text}"));
    let value: f64 = exact.parse().unwrap_or_else(|_| panic!("{text}"));
    assert!(
        exact.contains('e') && (1e-202..1e-201).contains(&value),
        "{text}"
    );
}

#[test]
fn asian_option_refuses_bad_input() {
    let bad =
        |args: &[&str], needle: &str| assert_one_line_error(&run("asian_option", args), needle);
    bad(&["--construction", "nope"], "standard, bridge or pca");
    bad(
        &["--sampler", "latin"],
        "sobol, independent, lattice or halton",
    );
    bad(
        &["--payoff", "geometric", "--control", "geometric"],
        "applies to --payoff arithmetic",
    );
    bad(&["--sigma", "-0.2"], "sigma");
    bad(&["--s0", "NaN"], "finite");
    bad(&["--dates", "0"], "1 to 4096");
    // e^(rate T) overflows f64: refused by the model, not priced as inf.
    bad(&["--rate", "1000"], "709");
    // e^(-rate T) overflows: refused, naming the flags (it was a NaN payoff, inf x 0, at
    // every sample: an error that named no flag).
    bad(
        &["--rate", "-800"],
        "invalid --rate = -800 with --maturity = 1",
    );
    bad(&["--rate", "-8", "--maturity", "100"], "at most 709.78");
    // Principal components of 2000 dates: beyond the factorization's dimension bound, also
    // before a table prints its first row.
    let limit = format!("at most {}", mcint::measure::FACTOR_MAX_DIMS);
    bad(&["--dates", "2000", "--construction", "pca"], &limit);
    let table = run("asian_option", &["--dates", "2000", "--table"]);
    assert_one_line_error(&table, &limit);
    assert!(stdout(&table).is_empty(), "{}", stdout(&table));
    // The table's quasi-random rows need two replicates: refused before the first row.
    let table = run("asian_option", &["--table", "--replicates", "1"]);
    assert_one_line_error(&table, "invalid --replicates = 1: expected at least 2");
    assert!(stdout(&table).is_empty(), "{}", stdout(&table));
    // An evaluation limit below a row's first stage: the independent rows' pilot, then the
    // quasi-random rows' first stage of replicates (the header was printed before either).
    for (limit, needle) in [("1000", "the pilot's 4096"), ("5000", "8 replicates")] {
        let table = run("asian_option", &["--table", "--max-evals", limit]);
        assert_one_line_error(&table, needle);
        assert!(stdout(&table).is_empty(), "{}", stdout(&table));
    }
    // The same checks pass a table that can run: a header and twelve rows.
    let table = run(
        "asian_option",
        &["--table", "--tol-rel", "1e-2", "--dates", "16"],
    );
    assert!(table.status.success(), "{}", stdout(&table));
    assert_eq!(stdout(&table).lines().count(), 14, "{}", stdout(&table));
    bad(&["--max-evals", "100"], "give --tol-rel too");
    bad(&["--tol-rel", "0"], "tolerance");
}

#[test]
fn points_with_a_gaussian_measure_have_its_mean_and_covariance() {
    let dir = common::scratch_dir("cli-measures");
    let cov = dir.join("cov.txt");
    std::fs::write(&cov, "2, 0.6\n0.6 1\n").unwrap();
    let n = 1 << 14;
    for factorization in ["cholesky", "pca"] {
        let out = run(
            "points",
            &[
                "--sampler",
                "independent",
                "--dims",
                "2",
                "--n",
                &n.to_string(),
                "--measure",
                "gaussian",
                "--mean",
                "1,-1",
                "--cov",
                cov.to_str().unwrap(),
                "--factorization",
                factorization,
            ],
        );
        assert!(out.status.success(), "{}", common::stderr(&out));
        let rows: Vec<[f64; 2]> = stdout(&out)
            .lines()
            .map(|l| {
                let (a, b) = l.split_once(',').unwrap();
                [a.parse().unwrap(), b.parse().unwrap()]
            })
            .collect();
        assert_eq!(rows.len(), n);
        let mean = |k: usize| rows.iter().map(|r| r[k]).sum::<f64>() / n as f64;
        let (m0, m1) = (mean(0), mean(1));
        assert!((m0 - 1.0).abs() < 5.0 * (2.0 / n as f64).sqrt(), "{m0}");
        assert!((m1 + 1.0).abs() < 5.0 * (1.0 / n as f64).sqrt(), "{m1}");
        let c01 = rows.iter().map(|r| (r[0] - m0) * (r[1] - m1)).sum::<f64>() / (n - 1) as f64;
        // The variance of a normal sample covariance: (C_00 C_11 + C_01^2) / n.
        assert!(
            (c01 - 0.6).abs() < 5.0 * ((2.0 + 0.36) / n as f64).sqrt(),
            "{c01}"
        );
    }
    std::fs::write(&cov, "1, 2\n2, 1\n").unwrap();
    let base = [
        "--sampler",
        "sobol",
        "--dims",
        "2",
        "--n",
        "4",
        "--measure",
        "gaussian",
    ];
    let with = |extra: &[&str]| run("points", &[&base[..], extra].concat());
    assert_one_line_error(&with(&["--cov", cov.to_str().unwrap()]), "eigenvalue");
    std::fs::write(&cov, "1, 0\n").unwrap();
    assert_one_line_error(&with(&["--cov", cov.to_str().unwrap()]), "expected 2");
    assert_one_line_error(&with(&["--mean", "1,2,3"]), "one per dimension");
    assert_one_line_error(
        &with(&["--format", "svg", "--out", "x.svg"]),
        "csv, bin or sum",
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
                "--measure",
                "cauchy",
            ],
        ),
        "expected gaussian",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn points_refuses_a_gaussian_too_large_to_factor() {
    // 20,000 dimensions took 5.9 GB and an unbounded O(d^3) factorization: now one line,
    // before the covariance is built.
    for factorization in ["pca", "cholesky"] {
        let out = run(
            "points",
            &[
                "--sampler",
                "independent",
                "--dims",
                "20000",
                "--n",
                "1",
                "--measure",
                "gaussian",
                "--factorization",
                factorization,
            ],
        );
        assert_eq!(out.status.code(), Some(2), "{}", common::stderr(&out));
        assert_one_line_error(
            &out,
            &format!("at most {}", mcint::measure::FACTOR_MAX_DIMS),
        );
    }
}

#[test]
fn integrate_takes_keister_and_keeps_genz_as_a_synonym() {
    for dims in ["1", "3", "8"] {
        let v = json(
            "integrate",
            &[
                "--integrand",
                "keister",
                "--dims",
                dims,
                "--method",
                "rqmc",
                "--json",
            ],
        );
        let exact = number(&v, "exact");
        let keister = mcint::testfns::Keister::new(dims.parse().unwrap()).unwrap();
        assert_eq!(exact, mcint::testfns::TestFunction::exact(&keister));
        assert!(
            (number(&v, "estimate") - exact).abs() < 5.0 * number(&v, "std_error"),
            "{v}"
        );
        assert_eq!(v["family"], "keister");
    }
    let a = json(
        "integrate",
        &["--genz", "gaussian", "--dims", "3", "--json"],
    );
    let b = json(
        "integrate",
        &["--integrand", "gaussian", "--dims", "3", "--json"],
    );
    assert_eq!(a["estimate"], b["estimate"]);
    assert_one_line_error(
        &run(
            "integrate",
            &[
                "--integrand",
                "keister",
                "--dims",
                "3",
                "--estimator",
                "control",
            ],
        ),
        "--estimator uniform",
    );
    assert_one_line_error(
        &run("integrate", &["--integrand", "nope", "--dims", "3"]),
        "keister or a Genz family",
    );
    assert_one_line_error(&run("integrate", &["--dims", "3"]), "missing --integrand");
}
