//! Figures: `points --format svg/png`, `gallery` and `convergence`.

use super::*;

/// `points --format svg|png` draws the points: the SVG has one circle per point (and per
/// pairwise panel with `--pairs`), the PNG is a PNG; bad combinations are one-line errors.
#[test]
fn points_draws_svg_and_png_images() {
    let dir = std::env::temp_dir().join(format!("mcint-points-images-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let svg = dir.join("cmj.svg");
    let out = run(
        "points",
        &[
            "--sampler",
            "cmj",
            "--dims",
            "2",
            "--n",
            "64",
            "--format",
            "svg",
            "--out",
            svg.to_str().unwrap(),
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg"), "{}", &text[..40.min(text.len())]);
    assert_eq!(text.matches("<circle").count(), 64);

    let pairs = dir.join("pairs.svg");
    let out = run(
        "points",
        &[
            "--sampler",
            "sobol",
            "--dims",
            "3",
            "--n",
            "32",
            "--format",
            "svg",
            "--pairs",
            "--out",
            pairs.to_str().unwrap(),
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    // Six off-diagonal panels of 32 points each.
    let text = std::fs::read_to_string(&pairs).unwrap();
    assert_eq!(text.matches("<circle").count(), 6 * 32);

    let png = dir.join("halton.png");
    let out = run(
        "points",
        &[
            "--sampler",
            "halton",
            "--dims",
            "2",
            "--n",
            "100",
            "--format",
            "png",
            "--out",
            png.to_str().unwrap(),
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");

    let wrong = dir.join("wrong.svg");
    assert_one_line_error(
        &run(
            "points",
            &[
                "--sampler",
                "sobol",
                "--dims",
                "2",
                "--n",
                "8",
                "--format",
                "png",
                "--out",
                wrong.to_str().unwrap(),
            ],
        ),
        "ending in .png",
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
                "8",
                "--format",
                "svg",
            ],
        ),
        "missing --out",
    );
    assert_one_line_error(
        &run(
            "points",
            &[
                "--sampler",
                "sobol",
                "--dims",
                "1",
                "--n",
                "8",
                "--format",
                "svg",
                "--out",
                wrong.to_str().unwrap(),
            ],
        ),
        "--dims 2",
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
                "8",
                "--format",
                "jpeg",
            ],
        ),
        "csv, bin, svg or png",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `gallery --out DIR` writes one image per sampler and an index naming every one of them,
/// with the t-value of the power-of-two sets (0 for Sobol' and PMJ02 as 2-D nets).
#[test]
fn gallery_draws_every_sampler_and_an_index() {
    let dir = std::env::temp_dir().join(format!("mcint-gallery-{}", std::process::id()));
    let out = run(
        "gallery",
        &[
            "--out",
            dir.to_str().unwrap(),
            "--n",
            "64",
            "--passes",
            "2",
            "--frequency",
            "8",
            "--format",
            "svg",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let index = std::fs::read_to_string(dir.join("index.html")).unwrap();
    // Every named sampler, so a sampler added to the crate is checked here too.
    for name in SamplerKind::ALL.map(SamplerKind::name) {
        let image = std::fs::read_to_string(dir.join(format!("{name}.svg"))).unwrap();
        assert!(image.starts_with("<svg"), "{name}");
        assert!(
            index.contains(&format!("<img src=\"{name}.svg\"")),
            "{name}"
        );
        // Frequencies 1 ..= 8 of the radial spectrum, and the (2*8+1)^2 periodogram.
        let radial = std::fs::read_to_string(dir.join(format!("{name}-radial.csv"))).unwrap();
        assert_eq!(radial.lines().count(), 1 + 8, "{name}");
        let grid = std::fs::read_to_string(dir.join(format!("{name}-periodogram.csv"))).unwrap();
        assert_eq!(grid.lines().count(), 1 + 17 * 17, "{name}");
    }
    for net in ["sobol", "pmj02"] {
        let row = format!("<a href=\"#{net}\">{net}</a></td><td>64</td><td>0</td>");
        assert!(index.contains(&row), "{net}: {index}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
    assert_one_line_error(&run("gallery", &[]), "missing --out");
    assert_one_line_error(
        &run("gallery", &["--out", "/tmp/x", "--format", "gif"]),
        "png or svg",
    );
    assert_one_line_error(&run("gallery", &["--out", "/tmp/x", "--n", "0"]), "--n");
}

/// `convergence --out DIR` draws one log-log plot per integrand and writes the slope table;
/// even a tiny run orders the samplers as theory says on the smooth Gaussian.
#[test]
fn convergence_draws_plots_and_a_slope_table() {
    let dir = std::env::temp_dir().join(format!("mcint-convergence-{}", std::process::id()));
    let out = run(
        "convergence",
        &[
            "--out",
            dir.to_str().unwrap(),
            "--max-log2",
            "10",
            "--passes",
            "16",
            "--format",
            "svg",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let table = std::fs::read_to_string(dir.join("slopes.md")).unwrap();
    assert_eq!(stdout(&out), table);
    for name in [
        "disk",
        "gaussian",
        "bilinear",
        "step",
        "triangle",
        "genz-gaussian-4d",
        "genz-oscillatory-4d",
    ] {
        let svg = std::fs::read_to_string(dir.join(format!("{name}.svg"))).unwrap();
        assert!(svg.starts_with("<svg"), "{name}");
        assert!(table.contains(&format!("| {name} |")), "{name}");
    }
    // Slopes on the 2-D Gaussian: independent near -0.5, Sobol' far steeper (each slope's
    // standard error here is about 0.05, so 0.25 is about 5 of them).
    let row = table
        .lines()
        .find(|l| l.starts_with("| gaussian |"))
        .unwrap();
    let slopes: Vec<f64> = row
        .split('|')
        .filter_map(|cell| cell.split('±').next()?.trim().parse().ok())
        .collect();
    let (independent, sobol) = (slopes[0], slopes[3]);
    assert!((independent + 0.5).abs() < 0.25, "{row}");
    assert!(sobol < -1.2, "{row}");
    std::fs::remove_dir_all(&dir).unwrap();
    assert_one_line_error(&run("convergence", &[]), "missing --out");
    assert_one_line_error(
        &run("convergence", &["--out", "/tmp/x", "--max-log2", "40"]),
        "--max-log2",
    );
    // Passes beyond memory panicked (1e19) or aborted (1e15).
    for passes in ["1e15", "1e19"] {
        assert_one_line_error(
            &run("convergence", &["--out", "/tmp/x", "--passes", passes]),
            "2 to 2^20 independent passes",
        );
    }
}
