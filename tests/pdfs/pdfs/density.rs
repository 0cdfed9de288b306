//! Each 1-D density integrates to one, and samples follow it (chi-square goodness of fit
//! against cell probabilities integrated from the pdf).

use super::*;

// Integrates to one

#[test]
fn one_dimensional_pdfs_integrate_to_one() {
    // 400 panels of a degree-23 rule leave far less than 1e-13 of quadrature error on these
    // smooth densities (the sharpest, Exponential(50) and the z = 30 tail, change by about one
    // e-fold a panel); 1e-12 leaves room for rounding in the 4800-term sums.
    for case in all_cases() {
        assert!(
            case.tail < 1e-15,
            "{}: truncation tail {}",
            case.name,
            case.tail
        );
        let (lo, hi) = case.window;
        let total = integrate(|x| case.pdf.pdf_1d(x), lo, hi, 400);
        assert!(
            (total - 1.0).abs() <= 1e-12 + case.tail,
            "{}: integral {total}",
            case.name
        );
        // The Pdf trait's view of a 1-D pdf is the same density.
        let x = 0.5 * (lo + hi);
        assert_eq!(case.pdf.pdf_1d(x), case.as_pdf.pdf(&[x]));
        assert_eq!((case.as_pdf.dims(), case.as_pdf.canonical_dims()), (1, 1));
    }
}

#[test]
fn product_pdfs_and_boxes_integrate_to_one() {
    // Tensor Gauss-Legendre: 8 panels of 12 points per axis integrate these smooth factors to
    // well below 1e-12.
    let p = product_3d();
    assert_eq!((p.dims(), p.canonical_dims()), (3, 3));
    let total = integrate_nd(
        &|x| p.pdf(x),
        &[(0.0, 2.0, 8), (-1.0, 1.0, 8), (0.0, 1.0, 8)],
    );
    assert!((total - 1.0).abs() < 1e-12, "3-D product: {total}");

    // An infinite factor: the exponential keeps e^-45 of its mass beyond 45.
    let p = ProductPdf::new(vec![
        Box::new(Exponential::new(1.0, 0.0, INF).unwrap()),
        Box::new(UniformInterval::new(-1.0, 1.0).unwrap()),
    ])
    .unwrap();
    let total = integrate_nd(&|x| p.pdf(x), &[(0.0, 45.0, 200), (-1.0, 1.0, 1)]);
    assert!(
        (total - 1.0).abs() < 1e-12 + (-45f64).exp(),
        "exp x uniform: {total}"
    );

    // Boxes: a constant density, so one panel is exact up to rounding.
    for (lo, hi) in [
        (vec![-1.0, 2.0], vec![3.0, 2.5]),
        (vec![0.0, 0.0, 0.0], vec![1e-3, 10.0, 2.0]),
        (vec![0.0; 4], vec![1.0; 4]),
        (vec![-1e5], vec![1e5]),
    ] {
        let b = UniformBox::new(lo.clone(), hi.clone()).unwrap();
        assert_eq!((b.dims(), b.canonical_dims()), (lo.len(), lo.len()));
        let volume: f64 = lo.iter().zip(&hi).map(|(l, h)| h - l).product();
        assert!((b.volume() - volume).abs() <= 1e-15 * volume);
        let axes: Vec<_> = lo.iter().zip(&hi).map(|(&l, &h)| (l, h, 1)).collect();
        let total = integrate_nd(&|x| b.pdf(x), &axes);
        assert!((total - 1.0).abs() < 1e-13, "box {lo:?} {hi:?}: {total}");
    }
}

// ---------------------------------------------------------------------------------------------
// Chi-square goodness of fit

/// Upper 1e-5 quantiles of chi-square for 1..=70 degrees of freedom, from
/// `python3 -c "from scipy.stats import chi2; print([round(chi2.isf(1e-5, d), 2) for d in range(1, 71)])"`
/// (scipy 1.17.1).
const CHI2_ISF_1E5: [f64; 70] = [
    19.51, 23.03, 25.90, 28.47, 30.86, 33.11, 35.26, 37.33, 39.34, 41.30, //
    43.21, 45.08, 46.91, 48.72, 50.49, 52.24, 53.97, 55.68, 57.37, 59.04, //
    60.70, 62.34, 63.97, 65.58, 67.18, 68.77, 70.35, 71.92, 73.47, 75.02, //
    76.56, 78.09, 79.62, 81.13, 82.64, 84.14, 85.64, 87.12, 88.60, 90.08, //
    91.55, 93.01, 94.47, 95.92, 97.37, 98.81, 100.25, 101.69, 103.12, 104.54, //
    105.96, 107.38, 108.79, 110.20, 111.61, 113.01, 114.41, 115.80, 117.19, 118.58, //
    119.97, 121.35, 122.73, 124.10, 125.48, 126.85, 128.21, 129.58, 130.94, 132.30, //
];

/// Pearson's statistic of observed counts against expected counts, after pooling every cell
/// with an expected count below 5 into one cell (and, if that pool is itself below 5, into the
/// smallest remaining cell), in the manner of Mitsuba's chi-square test. Returns the statistic
/// and its degrees of freedom (cells after pooling, minus one). Panics if a sample fell in a
/// cell of zero probability.
fn pooled_chi2(name: &str, observed: &[f64], expected: &[f64]) -> (f64, usize) {
    let mut cells: Vec<(f64, f64)> = Vec::new();
    let (mut pool_obs, mut pool_exp) = (0.0, 0.0);
    for (&o, &e) in observed.iter().zip(expected) {
        assert!(e >= 0.0, "{name}: negative expected count {e}");
        assert!(
            e > 0.0 || o == 0.0,
            "{name}: {o} samples in a cell of zero probability"
        );
        if e < 5.0 {
            pool_obs += o;
            pool_exp += e;
        } else {
            cells.push((o, e));
        }
    }
    if pool_exp >= 5.0 {
        cells.push((pool_obs, pool_exp));
    } else if pool_exp > 0.0 || pool_obs > 0.0 {
        let smallest = cells
            .iter_mut()
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .expect("at least one cell with expected count >= 5");
        smallest.0 += pool_obs;
        smallest.1 += pool_exp;
    }
    let chi2 = cells.iter().map(|(o, e)| (o - e).powi(2) / e).sum();
    (chi2, cells.len() - 1)
}

fn assert_chi2_passes(name: &str, observed: &[f64], expected: &[f64]) {
    let (chi2, dof) = pooled_chi2(name, observed, expected);
    assert!(
        (1..=CHI2_ISF_1E5.len()).contains(&dof),
        "{name}: {dof} degrees of freedom"
    );
    let threshold = CHI2_ISF_1E5[dof - 1];
    assert!(
        chi2 < threshold,
        "{name}: chi2 = {chi2} on {dof} dof (threshold {threshold})"
    );
}

/// Samples per 1-D goodness-of-fit test. Against a smooth error in the density the statistic
/// grows by about `samples * sum (p_i - q_i)^2 / q_i`, so power comes from many samples and
/// few enough cells that the 1e-5 threshold sits close to the mean: with 200,000 samples
/// and 32 cells, sampling Linear(0, 2, 1, 3) but testing against Linear(0, 2, 1, 3.3) (a 2-3%
/// error in the density) gave a statistic of 138 against the threshold of 76.6 on 31 degrees
/// of freedom (a 2% error, v1 = 3.2, was just caught at 78).
const GOF_SAMPLES: usize = 200_000;
/// Equal cells across a case's grid range.
const GOF_CELLS: usize = 32;

fn goodness_of_fit_1d(cases: &[Case], samples: usize, seed: u64) {
    for (c, case) in cases.iter().enumerate() {
        let (a, b) = case.pdf.support();
        let (g0, g1) = case.grid;
        // Cell edges: open cells for the support outside the grid, equal cells across it.
        let mut edges = Vec::new();
        if a < g0 {
            edges.push(a);
        }
        edges.extend((0..=GOF_CELLS).map(|i| g0 + (g1 - g0) * i as f64 / GOF_CELLS as f64));
        if g1 < b {
            edges.push(b);
        }
        // Expected probabilities by quadrature of the pdf over each cell (clipped to the
        // finite window; the rest has probability below `tail` < 1e-15).
        let (w0, w1) = case.window;
        let expected: Vec<f64> = edges
            .windows(2)
            .map(|e| {
                let (lo, hi) = (e[0].max(w0), e[1].min(w1));
                // Grid cells are narrow (8 panels); the open cells can span many decay lengths.
                let panels = if e[1] - e[0] > 1.5 * (g1 - g0) / GOF_CELLS as f64 {
                    400
                } else {
                    8
                };
                if lo < hi {
                    samples as f64 * integrate(|x| case.pdf.pdf_1d(x), lo, hi, panels)
                } else {
                    0.0
                }
            })
            .collect();
        let total: f64 = expected.iter().sum::<f64>() / samples as f64;
        assert!(
            (total - 1.0).abs() < 1e-10,
            "{}: cells hold {total}",
            case.name
        );

        let u = canonical(1, samples, seed + c as u64);
        let mut observed = vec![0.0; edges.len() - 1];
        for &u in u.column(0) {
            let x = case.pdf.sample_1d(u);
            let inside = if case.closed {
                (a..=b).contains(&x)
            } else {
                (a..b).contains(&x)
            };
            assert!(
                inside,
                "{}: sample({u}) = {x} outside the support",
                case.name
            );
            // The cell [e_i, e_{i+1}) holding x; the upper end of a closed support goes in
            // the last cell.
            let cell = edges.partition_point(|&e| e <= x).clamp(1, edges.len() - 1) - 1;
            observed[cell] += 1.0;
        }
        assert_chi2_passes(&case.name, &observed, &expected);
    }
}

#[test]
fn uniform_samples_follow_the_density() {
    goodness_of_fit_1d(&uniform_cases(), GOF_SAMPLES, 100);
}

#[test]
fn exponential_samples_follow_the_density() {
    goodness_of_fit_1d(&exponential_cases(), GOF_SAMPLES, 200);
}

#[test]
fn linear_samples_follow_the_density() {
    goodness_of_fit_1d(&linear_cases(), GOF_SAMPLES, 300);
}

/// Truncated-normal sampling inverts the normal cdf by a root search (or series), which costs
/// far more than the other warps: fewer samples (still about 900 per grid cell), and the
/// cases split over two tests so they run in parallel.
const NORMAL_GOF_SAMPLES: usize = 30_000;

#[test]
fn truncated_normal_samples_follow_the_density() {
    goodness_of_fit_1d(&central_normal_cases(), NORMAL_GOF_SAMPLES, 400);
}

#[test]
fn far_tail_truncated_normal_samples_follow_the_density() {
    goodness_of_fit_1d(&tail_normal_cases(), NORMAL_GOF_SAMPLES, 450);
}

/// Samples per 2-D goodness-of-fit test: about 940 per cell of the 8x8 grid.
const SAMPLES_2D: usize = 60_000;

/// Chi-square of samples of a 2-D pdf on an 8x8 grid over `[lo, hi]`, with cell probabilities
/// by tensor Gauss-Legendre quadrature of the pdf over each cell.
fn goodness_of_fit_2d(name: &str, pdf: &dyn Pdf, lo: [f64; 2], hi: [f64; 2], seed: u64) {
    const GRID: usize = 8;
    let edge = |d: usize, i: usize| lo[d] + (hi[d] - lo[d]) * i as f64 / GRID as f64;
    let mut expected = vec![0.0; GRID * GRID];
    for iy in 0..GRID {
        for ix in 0..GRID {
            let p = integrate_nd(
                &|x| pdf.pdf(x),
                &[
                    (edge(0, ix), edge(0, ix + 1), 1),
                    (edge(1, iy), edge(1, iy + 1), 1),
                ],
            );
            expected[ix + GRID * iy] = SAMPLES_2D as f64 * p;
        }
    }
    let total: f64 = expected.iter().sum::<f64>() / SAMPLES_2D as f64;
    assert!((total - 1.0).abs() < 1e-10, "{name}: cells hold {total}");

    let u = canonical(2, SAMPLES_2D, seed);
    let mut observed = vec![0.0; GRID * GRID];
    let (mut uu, mut x) = ([0.0; 2], [0.0; 2]);
    for i in 0..SAMPLES_2D {
        u.copy_point(i, &mut uu);
        pdf.sample(&uu, &mut x);
        let cell = |d: usize| {
            let t = (x[d] - lo[d]) / (hi[d] - lo[d]) * GRID as f64;
            assert!(
                (0.0..GRID as f64).contains(&t),
                "{name}: sample {x:?} outside"
            );
            t as usize
        };
        observed[cell(0) + GRID * cell(1)] += 1.0;
    }
    assert_chi2_passes(name, &observed, &expected);
}

#[test]
fn product_and_box_samples_follow_the_density() {
    goodness_of_fit_2d(
        "ProductPdf(Linear, TruncatedNormal)",
        &product_2d(),
        [0.0, -1.0],
        [1.0, 2.0],
        500,
    );
    let p = ProductPdf::new(vec![
        Box::new(Exponential::new(-2.0, 0.0, 1.0).unwrap()),
        Box::new(UniformInterval::new(3.0, 4.0).unwrap()),
    ])
    .unwrap();
    goodness_of_fit_2d(
        "ProductPdf(Exponential, Uniform)",
        &p,
        [0.0, 3.0],
        [1.0, 4.0],
        501,
    );
    let b = UniformBox::new(vec![-1.0, 2.0], vec![3.0, 2.5]).unwrap();
    goodness_of_fit_2d("UniformBox", &b, [-1.0, 2.0], [3.0, 2.5], 502);
}
