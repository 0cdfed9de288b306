//! Integration tests for the pdfs (warps): each density integrates to one (by quadrature
//! written here), samples follow the density (chi-square goodness of fit against cell
//! probabilities integrated from the pdf, the way Mitsuba tests its warps), `invert` undoes
//! `sample`, sampling is monotone, far-tail truncated normals stay exact, densities vanish
//! outside their supports, and constructors reject bad parameters by name.
//!
//! Statistical thresholds are chi-square 1e-5 quantiles with fixed seeds, so a correct pdf
//! fails none of them in practice and a run is reproducible bit for bit.

use crate::common::{ONE_BELOW, canonical, canonical_u, config, gauss_legendre, integrate, named};
use mcint::pdf::{
    Exponential, Linear, Pdf, Pdf1d, ProductPdf, TruncatedNormal, UniformBox, UniformInterval,
};
use proptest::prelude::*;

const INF: f64 = f64::INFINITY;
// ---------------------------------------------------------------------------------------------
// Quadrature

/// Tensor-product composite Gauss-Legendre over a box, `(lo, hi, panels)` per dimension.
fn integrate_nd(f: &dyn Fn(&[f64]) -> f64, axes: &[(f64, f64, usize)]) -> f64 {
    fn nested(f: &dyn Fn(&[f64]) -> f64, axes: &[(f64, f64, usize)], prefix: &[f64]) -> f64 {
        match axes.split_first() {
            None => f(prefix),
            Some((&(lo, hi, panels), rest)) => integrate(
                |t| {
                    let mut x = prefix.to_vec();
                    x.push(t);
                    nested(f, rest, &x)
                },
                lo,
                hi,
                panels,
            ),
        }
    }
    nested(f, axes, &[])
}

#[test]
fn quadrature_is_exact_where_theory_says() {
    let rule = gauss_legendre();
    // Weights sum to the length of [-1, 1]; one panel integrates degree 23 exactly.
    assert!((rule.iter().map(|&(_, w)| w).sum::<f64>() - 2.0).abs() < 1e-14);
    assert!((integrate(|x| x.powi(23), 0.0, 1.0, 1) - 1.0 / 24.0).abs() < 1e-15);
    assert!((integrate(|x| x.powi(22), -1.0, 1.0, 1) - 2.0 / 23.0).abs() < 1e-15);
    assert!((integrate(f64::sin, 0.0, std::f64::consts::PI, 8) - 2.0).abs() < 1e-14);
    let volume = integrate_nd(
        &|x| x[0] * x[1] * x[2],
        &[(0.0, 1.0, 1), (0.0, 2.0, 1), (0.0, 3.0, 2)],
    );
    assert!((volume - 0.5 * 2.0 * 4.5).abs() < 1e-13);
}

// ---------------------------------------------------------------------------------------------
// The one-dimensional cases

/// A 1-D pdf with the ranges the tests use.
struct Case {
    name: String,
    pdf: Box<dyn Pdf1d>,
    /// The same pdf through the `Pdf` trait (which `dyn Pdf1d` itself does not implement).
    as_pdf: Box<dyn Pdf>,
    /// A finite window holding all but at most `tail` of the probability.
    window: (f64, f64),
    /// Bound on the probability outside `window`.
    tail: f64,
    /// Where the chi-square grid's equal cells go (the rest of the support gets open cells).
    grid: (f64, f64),
    /// True when the support includes its upper end (`[a, b]` rather than `[a, b)`).
    closed: bool,
}

fn uniform(a: f64, b: f64) -> Case {
    Case {
        name: format!("UniformInterval({a}, {b})"),
        pdf: Box::new(UniformInterval::new(a, b).unwrap()),
        as_pdf: Box::new(UniformInterval::new(a, b).unwrap()),
        window: (a, b),
        tail: 0.0,
        grid: (a, b),
        closed: false,
    }
}

fn linear(a: f64, b: f64, v0: f64, v1: f64) -> Case {
    Case {
        name: format!("Linear({a}, {b}, {v0}, {v1})"),
        pdf: Box::new(Linear::new(a, b, v0, v1).unwrap()),
        as_pdf: Box::new(Linear::new(a, b, v0, v1).unwrap()),
        window: (a, b),
        tail: 0.0,
        grid: (a, b),
        closed: false,
    }
}

fn exponential(rate: f64, a: f64, b: f64) -> Case {
    // Beyond 45 decay lengths the untruncated exponential (b = inf has mass 1) keeps e^-45 =
    // 2.9e-20 of its probability; the grid covers 10 decay lengths from the peak end.
    let decay = rate.abs();
    let (window, tail) = if b.is_finite() {
        ((a, b), 0.0)
    } else {
        ((a, a + 45.0 / decay), (-45f64).exp())
    };
    let grid = if rate > 0.0 {
        (a, b.min(a + 10.0 / decay))
    } else {
        (a.max(b - 10.0 / decay), b)
    };
    Case {
        name: format!("Exponential({rate}, {a}, {b})"),
        pdf: Box::new(Exponential::new(rate, a, b).unwrap()),
        as_pdf: Box::new(Exponential::new(rate, a, b).unwrap()),
        window,
        tail,
        grid,
        closed: false,
    }
}

fn truncated_normal(mean: f64, sd: f64, a: f64, b: f64) -> Case {
    let pdf = TruncatedNormal::new(mean, sd, a, b).unwrap();
    let (alpha, beta) = ((a - mean) / sd, (b - mean) / sd);
    // Infinite ends are cut 12 sd beyond the mean or the finite end. For x beyond the mean the
    // Gaussian falls at least as fast as exp(-|z_c| (|z| - |z_c|)), so the probability beyond
    // a cut at z_c is at most pdf(c) sd / |z_c| (the Mills-ratio bound).
    let lo = if a.is_finite() {
        a
    } else {
        mean + sd * (beta.min(0.0) - 12.0)
    };
    let hi = if b.is_finite() {
        b
    } else {
        mean + sd * (alpha.max(0.0) + 12.0)
    };
    let mut tail = 0.0;
    for (end, cut) in [(a, lo), (b, hi)] {
        if !end.is_finite() {
            let z = (cut - mean) / sd;
            tail += pdf.pdf_1d(cut) * sd / z.abs();
        }
    }
    // The grid covers the bulk: 6 "decay lengths" from the end nearest the mean when the whole
    // interval is in one tail (the decay length there is about sd / |z|), else +-6 sd.
    let (zl, zh) = if alpha >= 0.0 {
        (alpha, beta.min(alpha + 6.0 / alpha.max(1.0)))
    } else if beta <= 0.0 {
        (alpha.max(beta - 6.0 / (-beta).max(1.0)), beta)
    } else {
        (alpha.max(-6.0), beta.min(6.0))
    };
    Case {
        name: format!("TruncatedNormal({mean}, {sd}, {a}, {b})"),
        pdf: Box::new(pdf),
        as_pdf: Box::new(pdf),
        window: (lo, hi),
        tail,
        grid: (mean + sd * zl, mean + sd * zh),
        closed: true,
    }
}

fn uniform_cases() -> Vec<Case> {
    vec![
        uniform(2.0, 6.0),
        uniform(-1e-3, 1e-3),
        uniform(-1e6, 3e6),
        uniform(1e9, 1e9 + 1.0),
    ]
}

fn exponential_cases() -> Vec<Case> {
    vec![
        exponential(2.0, 0.0, INF),
        exponential(3.0, 1e3, INF),
        exponential(1.0, 0.0, 1.0),
        exponential(-3.0, -1.0, 2.0),
        exponential(50.0, 0.0, 1.0),
        exponential(-0.5, 1.0, 10.0),
        exponential(1e-6, 0.0, 1.0),
        exponential(-40.0, -5.0, 5.0),
    ]
}

fn linear_cases() -> Vec<Case> {
    vec![
        linear(0.0, 1.0, 0.0, 2.0),
        linear(0.0, 2.0, 1.0, 3.0),
        linear(-1.0, 1.0, 3.0, 0.0),
        linear(5.0, 6.0, 1.0, 1.0),
        linear(-2.0, 3.0, 1e-3, 1.0),
        linear(10.0, 10.5, 7.0, 2.0),
    ]
}

fn central_normal_cases() -> Vec<Case> {
    vec![
        truncated_normal(0.0, 1.0, -INF, INF),
        truncated_normal(0.0, 1.0, 0.0, INF),
        truncated_normal(1.0, 2.0, -1.0, 0.5),
        truncated_normal(3.0, 0.5, -INF, 2.0),
        truncated_normal(0.0, 1.0, -2.0, 40.0),
        truncated_normal(0.0, 1.0, -1e-3, 2e-3),
    ]
}

/// Intervals many standard deviations from the mean.
fn tail_normal_cases() -> Vec<Case> {
    vec![
        truncated_normal(0.0, 1.0, 8.0, 9.0),
        truncated_normal(0.0, 1.0, -30.0, -29.0),
        truncated_normal(0.0, 1.0, 30.0, INF),
        truncated_normal(-5.0, 2.0, -INF, -20.0),
        truncated_normal(2.0, 3.0, 2.0 + 3.0 * 8.0, 2.0 + 3.0 * 9.0),
    ]
}

fn truncated_normal_cases() -> Vec<Case> {
    let mut cases = central_normal_cases();
    cases.extend(tail_normal_cases());
    cases
}

fn all_cases() -> Vec<Case> {
    let mut cases = uniform_cases();
    cases.extend(exponential_cases());
    cases.extend(linear_cases());
    cases.extend(truncated_normal_cases());
    cases
}

// ---------------------------------------------------------------------------------------------
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

fn product_3d() -> ProductPdf {
    ProductPdf::new(vec![
        Box::new(Linear::new(0.0, 2.0, 1.0, 3.0).unwrap()),
        Box::new(Exponential::new(-2.0, -1.0, 1.0).unwrap()),
        Box::new(TruncatedNormal::new(0.5, 0.3, 0.0, 1.0).unwrap()),
    ])
    .unwrap()
}

fn product_2d() -> ProductPdf {
    ProductPdf::new(vec![
        Box::new(Linear::new(0.0, 1.0, 1.0, 3.0).unwrap()),
        Box::new(TruncatedNormal::new(0.0, 1.0, -1.0, 2.0).unwrap()),
    ])
    .unwrap()
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

// ---------------------------------------------------------------------------------------------
// invert and monotonicity

/// Round-trip tolerance for `invert(sample(u)) = u`. The sample x is a float, so it carries
/// up to a few ulps of rounding (a clamp to the half-open support moves it by one ulp), and
/// that moves u by `pdf(x)` per unit of x: 4 pdf(x) ulp(x). The cdf arithmetic itself adds a
/// few ulps of u, well inside the 1e-12 floor. (For most cases the first term is ~1e-15; it
/// matters for narrow intervals far from zero such as `[1e9, 1e9 + 1]`, where x only has 27
/// bits below the unit, and for the z = 30 normal tail, where pdf(x) is about 30.)
fn round_trip_tolerance(density: f64, x: f64) -> f64 {
    if x.is_finite() {
        1e-12 + 4.0 * density * (x.abs().next_up() - x.abs())
    } else {
        // u = 0 may map to -inf for a support unbounded below, where the density is zero.
        1e-12
    }
}

proptest! {
    #![proptest_config(config(512, 12345))]

    #[test]
    fn invert_undoes_sample(case in 0usize..29, u in canonical_u()) {
        let cases = all_cases();
        prop_assert_eq!(cases.len(), 29);
        let case = &cases[case];
        let x = case.pdf.sample_1d(u);
        let back = case.pdf.invert_1d(x);
        let tolerance = round_trip_tolerance(case.pdf.pdf_1d(x), x);
        prop_assert!(
            (back - u).abs() <= tolerance,
            "{}: u = {}, x = {}, invert = {}, error {:e}",
            case.name,
            u,
            x,
            back,
            back - u
        );
        // The Pdf trait forwards to the 1-D methods.
        let mut xs = [0.0];
        case.as_pdf.sample(&[u], &mut xs);
        prop_assert_eq!(xs[0].to_bits(), x.to_bits());
        let mut us = [0.0];
        case.as_pdf.invert(&[x], &mut us).unwrap();
        prop_assert_eq!(us[0].to_bits(), back.to_bits());
    }

    #[test]
    fn sampling_is_monotone(
        case in 0usize..29,
        u in canonical_u(),
        ulps in 1u32..=4,
        step in 0.0..1.0f64,
    ) {
        let cases = all_cases();
        let case = &cases[case];
        // Neighbouring floats, where rounding could reverse the order ...
        let mut v = u;
        for _ in 0..ulps {
            v = v.next_up().min(ONE_BELOW);
        }
        // ... and a larger step toward one.
        let w = (u + step * (1.0 - u)).min(ONE_BELOW);
        let (xu, xv, xw) = (case.pdf.sample_1d(u), case.pdf.sample_1d(v), case.pdf.sample_1d(w));
        // Inverse cdfs built on a normal quantile accurate to about one ulp (AS241) can
        // reverse the order of two neighbouring inputs by rounding; allow two ulps of x, far
        // below any stratum width, and nothing more.
        let slack = 2.0 * (xu.abs().next_up() - xu.abs());
        prop_assert!(xu <= xv + slack, "{}: sample({}) = {} > sample({}) = {}", case.name, u, xu, v, xv);
        prop_assert!(xu <= xw, "{}: sample({}) = {} > sample({}) = {}", case.name, u, xu, w, xw);
    }

    #[test]
    fn multidimensional_invert_undoes_sample(u in prop::collection::vec(canonical_u(), 3)) {
        let p = product_3d();
        let (mut x, mut back) = ([0.0; 3], [0.0; 3]);
        p.sample(&u, &mut x);
        p.invert(&x, &mut back).unwrap();
        // Each coordinate is its factor's 1-D warp, so each round trip has the 1-D tolerance
        // with that factor's density, and the density is the product of the factors'.
        let marginals: [Box<dyn Pdf1d>; 3] = [
            Box::new(Linear::new(0.0, 2.0, 1.0, 3.0).unwrap()),
            Box::new(Exponential::new(-2.0, -1.0, 1.0).unwrap()),
            Box::new(TruncatedNormal::new(0.5, 0.3, 0.0, 1.0).unwrap()),
        ];
        for d in 0..3 {
            prop_assert_eq!(x[d].to_bits(), marginals[d].sample_1d(u[d]).to_bits());
            let tolerance = round_trip_tolerance(marginals[d].pdf_1d(x[d]), x[d]);
            prop_assert!(
                (back[d] - u[d]).abs() <= tolerance,
                "product dim {}: {:?} -> {:?}",
                d,
                u,
                back
            );
        }
        let density: f64 = (0..3).map(|d| marginals[d].pdf_1d(x[d])).product();
        prop_assert!(density > 0.0);
        prop_assert!((p.pdf(&x) - density).abs() <= 1e-15 * density);

        // The third axis is 1e-3 wide at 1e6, where x has an ulp of 1.2e-10: the round trip is
        // exact only up to 4 * 1.2e-10 / 1e-3, which the tolerance's density term allows.
        let b = UniformBox::new(vec![-1.0, 2.0, 1e6], vec![3.0, 2.5, 1e6 + 1e-3]).unwrap();
        b.sample(&u, &mut x);
        b.invert(&x, &mut back).unwrap();
        for d in 0..3 {
            let (lo, hi) = (b.lo()[d], b.hi()[d]);
            prop_assert!(x[d] >= lo && x[d] < hi);
            let tolerance = round_trip_tolerance(1.0 / (hi - lo), x[d]);
            prop_assert!(
                (back[d] - u[d]).abs() <= tolerance,
                "box dim {}: {:?} -> {:?}",
                d,
                u,
                back
            );
        }
        prop_assert_eq!(b.pdf(&x), 1.0 / b.volume());
    }
}

#[test]
fn stratified_canonical_points_stay_stratified() {
    // A sweep of sorted u (strata edges of a 1-D jittered pattern) maps to sorted x, so each
    // stratum of u lands in its own interval of x.
    for case in all_cases() {
        let mut last = f64::NEG_INFINITY;
        for i in 0..=2_000 {
            let u = (i as f64 / 2_000.0).min(ONE_BELOW);
            let x = case.pdf.sample_1d(u);
            assert!(x >= last, "{}: not monotone at u = {u}", case.name);
            last = x;
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Far tails of the truncated normal

/// Reference truncated-normal cdf and density, computed without any normal cdf: Gauss-Legendre
/// on the Gaussian scaled by its value at the interval end nearest the mean, so nothing
/// underflows even at z = 30.
struct TailReference {
    mean: f64,
    sd: f64,
    /// Standardised interval, with the infinite end cut where the scaled density is e^-60.
    za: f64,
    zb: f64,
    /// The end nearest the mean (the density's largest value in the interval).
    z0: f64,
    total: f64,
}

impl TailReference {
    fn new(mean: f64, sd: f64, a: f64, b: f64) -> Self {
        let (za, zb) = ((a - mean) / sd, (b - mean) / sd);
        let z0 = if za >= 0.0 { za } else { zb };
        // exp(-(z^2 - z0^2)/2) <= exp(-|z0| (|z| - |z0|)): 60 / |z0| beyond z0 leaves e^-60.
        let zb = if zb.is_finite() {
            zb
        } else {
            za + 60.0 / za.abs()
        };
        let za = if za.is_finite() {
            za
        } else {
            zb - 60.0 / zb.abs()
        };
        let mut r = TailReference {
            mean,
            sd,
            za,
            zb,
            z0,
            total: 1.0,
        };
        r.total = r.mass(za, zb);
        r
    }

    fn scaled(&self, z: f64) -> f64 {
        (-0.5 * (z - self.z0) * (z + self.z0)).exp()
    }

    fn mass(&self, from: f64, to: f64) -> f64 {
        integrate(|z| self.scaled(z), from, to, 64)
    }

    fn cdf(&self, x: f64) -> f64 {
        let z = ((x - self.mean) / self.sd).clamp(self.za, self.zb);
        self.mass(self.za, z) / self.total
    }

    fn pdf(&self, x: f64) -> f64 {
        self.scaled((x - self.mean) / self.sd) / (self.sd * self.total)
    }
}

#[test]
fn far_tail_truncated_normals_sample_inside_with_the_right_cdf() {
    // The reference cdf is accurate to ~1e-15; x carries a few ulps of rounding, worth at most
    // pdf(x) * ulp(x) ~ 30 * 3.6e-15 = 1e-13 of probability at z = 30. So 1e-11 is generous
    // and still catches any loss of the tail (a naive 1 - Phi(x) would be off by O(1)).
    for (mean, sd, a, b) in [
        (0.0, 1.0, 8.0, 9.0),
        (0.0, 1.0, -30.0, -29.0),
        (0.0, 1.0, 30.0, INF),
        (0.0, 1.0, -INF, -30.0),
        (1.0, 0.5, 16.0, 17.0),
        (-2.0, 4.0, -150.0, -110.0),
        (0.0, 1.0, 37.0, 37.5),
    ] {
        let p = TruncatedNormal::new(mean, sd, a, b).unwrap();
        let reference = TailReference::new(mean, sd, a, b);
        for i in 0..=1000 {
            let u = (i as f64 / 1000.0).min(ONE_BELOW);
            let x = p.sample_1d(u);
            assert!(a <= x && x <= b, "[{a}, {b}]: sample({u}) = {x} outside");
            let cdf = reference.cdf(x);
            assert!(
                (cdf - u).abs() < 1e-11,
                "N({mean}, {sd}) on [{a}, {b}]: sample({u}) = {x} has cdf {cdf}"
            );
            assert!(
                (p.invert_1d(x) - cdf).abs() < 1e-11,
                "[{a}, {b}]: invert({x}) = {} vs cdf {cdf}",
                p.invert_1d(x)
            );
            // The density, normalised by a mass near 1e-200, keeps full relative precision.
            // (Not at u = 0 with an infinite end: the quantile there is -inf or the end of a
            // root search, where exp(-z^2/2) underflows although the truncated density does
            // not; that far out it is below e^-290 of its peak, so no sample lands there.)
            if i == 0 && !(a.is_finite() && b.is_finite()) {
                continue;
            }
            let density = reference.pdf(x);
            assert!(
                (p.pdf_1d(x) / density - 1.0).abs() < 1e-10,
                "[{a}, {b}]: pdf({x}) = {} vs {density}",
                p.pdf_1d(x)
            );
        }
    }
}

#[test]
fn narrow_truncated_normals_keep_precision() {
    for width in [1e-6, 1e-9, 1e-12] {
        let p = TruncatedNormal::new(0.0, 1.0, 0.0, width).unwrap();
        // Exact: pdf(0) = phi(0) / (Phi(w) - Phi(0)) = 1 / (w - w^3/6 + O(w^5)).
        let exact = 1.0 / (width - width.powi(3) / 6.0);
        let relative = p.pdf_1d(0.0) / exact - 1.0;
        assert!(
            relative.abs() < 1e-12,
            "width {width}: relative error {relative:e}"
        );
        let total = integrate(|x| p.pdf_1d(x), 0.0, width, 4);
        assert!(
            (total - 1.0).abs() < 1e-12,
            "width {width}: integral {total}"
        );
    }
}

/// A truncated normal's shape on its own interval, for reference: with `t = (x - a) / (b - a)`
/// in `[0, 1]` and `z = (x - mean) / sd`, the density is proportional to
/// `exp(-(z - z0)(z + z0) / 2)`, `z0` the point of the interval nearest the mean, where
/// `z - z0 = (t - t0) w` and `w = (b - a) / sd`. Nothing in it cancels, however narrow the
/// interval, far its tail or large the sd.
struct Shape {
    w: f64,
    t0: f64,
    z0: f64,
    total: f64,
}

/// Quadrature panels on `[0, 1]`: the steepest shape tested falls by about `z0 w` = 500
/// e-folds across it, 8 per panel, which the 12-point rule integrates to far below 1e-15.
const SHAPE_PANELS: usize = 64;

impl Shape {
    fn new(mean: f64, sd: f64, a: f64, b: f64) -> Self {
        let w = (b - a) / sd;
        let (alpha, beta) = ((a - mean) / sd, (b - mean) / sd);
        let (t0, z0) = if alpha >= 0.0 {
            (0.0, alpha)
        } else if beta <= 0.0 {
            (1.0, beta)
        } else {
            ((mean - a) / (b - a), 0.0)
        };
        let mut shape = Shape {
            w,
            t0,
            z0,
            total: 1.0,
        };
        shape.total = shape.integral(1.0);
        shape
    }

    fn scaled(&self, t: f64) -> f64 {
        let d = (t - self.t0) * self.w;
        (-0.5 * d * (2.0 * self.z0 + d)).exp()
    }

    fn integral(&self, t: f64) -> f64 {
        integrate(|s| self.scaled(s), 0.0, t, SHAPE_PANELS)
    }

    fn cdf(&self, t: f64) -> f64 {
        self.integral(t) / self.total
    }
}

/// Truncated normals with the interval placed by what it does to the cdf: tiny compared with
/// an enormous sd (the cdf difference cancels completely), narrow in a far tail, straddling
/// the mean, and ordinary. `(mean, sd, a, b)`; fixed draws, so a run is reproducible.
fn truncated_normal_regimes() -> Vec<(f64, f64, f64, f64)> {
    let mut cases = vec![
        // The two of issue 32: every u gave one end, and invert gave 0.
        (1e-300, 1e308, -2.5e14, -3.3e9),
        (0.0, 1e200, 1.0, 2.0),
        (0.0, 1e3, 0.0, 1.0),
        (0.0, 30.0, 0.0, 1.0),
        (0.0, 1.0, -1e-9, 1e-9),
        (0.0, 1.0, 30.0, 30.0 + 1e-4),
        (0.0, 1.0, 30.0, 30.0 + 1e-3),
        (0.0, 1.0, -30.001, -30.0),
        (5.0, 1.0, 40.0, 40.002),
        (1e6, 1e-3, 1e6 + 0.02, 1e6 + 0.020001),
    ];
    let draws = canonical(7, 600, 0x7e57);
    let mut v = [0.0; 7];
    for i in 0..draws.len() {
        draws.copy_point(i, &mut v);
        let sd = 10f64.powf(-300.0 + 600.0 * v[0]);
        // Widths in sd: from 1e-300, 1e-6 or 0.1 to 10, a third of the draws each.
        let log_w = match (v[6] * 3.0) as usize {
            0 => -300.0 + 301.0 * v[1],
            1 => -6.0 + 7.0 * v[1],
            _ => -1.0 + 2.0 * v[1],
        };
        let w = 10f64.powf(log_w);
        // Where the interval starts, in sd from the mean: central, upper tail, lower tail
        // (placed by its upper end), or within 1e-300..1 of the mean.
        let side = if v[4] < 0.5 { -1.0 } else { 1.0 };
        let alpha = match (v[2] * 4.0) as usize {
            0 => -4.0 + 8.0 * v[3],
            1 => 4.0 + 33.0 * v[3],
            2 => -(4.0 + 33.0 * v[3]) - w,
            _ => side * 10f64.powf(-300.0 + 300.0 * v[3]),
        };
        // The interval's position: at 0, or up to 1e9 widths from it on either side (so that
        // it holds at least 2^20 floats).
        let width = w * sd;
        let a = match (v[4] * 8.0) as usize % 4 {
            0 => 0.0,
            _ => side * width * 10f64.powf(-3.0 + 12.0 * v[5]),
        };
        let b = a + width;
        let mean = a - alpha * sd;
        let floats = (b - a) / (a.abs().max(b.abs()) * f64::EPSILON);
        if mean.is_finite() && b.is_finite() && a < b && floats >= (1u64 << 20) as f64 {
            cases.push((mean, sd, a, b));
        }
    }
    cases
}

#[test]
fn truncated_normals_sample_and_invert_exactly_in_every_regime() {
    // u on a stratified grid: sample(u_i) is the u_i quantile, so the fraction of samples
    // at or below any x is the cdf there to within 1/(2N), plus the samples whose u is
    // within the round-trip error of the cdf.
    const N: usize = 1000;
    let (mut tested, mut refused) = (0, 0);
    for (mean, sd, a, b) in truncated_normal_regimes() {
        let name = format!("N({mean:e}, {sd:e}) on [{a:e}, {b:e}]");
        let Ok(p) = TruncatedNormal::new(mean, sd, a, b) else {
            refused += 1;
            continue;
        };
        tested += 1;
        let shape = Shape::new(mean, sd, a, b);
        let t_of = |x: f64| ((x - a) / (b - a)).clamp(0.0, 1.0);
        let xs: Vec<f64> = (0..N)
            .map(|i| p.sample_1d((i as f64 + 0.5) / N as f64))
            .collect();
        let mut previous = a;
        for (i, &x) in xs.iter().enumerate() {
            let u = (i as f64 + 0.5) / N as f64;
            assert!(
                previous <= x && x <= b,
                "{name}: sample({u}) = {x:e} after {previous:e}"
            );
            previous = x;
            // The round trip: x is a float of relative precision EPSILON, and its position
            // relative to the mean carries the quantile's relative error (7e-16); both move u
            // by the density times that much x. The cdf arithmetic adds a few ulps of u,
            // magnified by at most 1/0.03 where the interval's probability is a difference of
            // tail probabilities.
            let density = p.pdf_1d(x);
            let tolerance = 1e-12 + 8.0 * density * f64::EPSILON * (x.abs() + (x - mean).abs());
            let back = p.invert_1d(x);
            assert!(
                (back - u).abs() <= tolerance,
                "{name}: invert(sample({u}) = {x:e}) = {back}"
            );
            // The density against the shape: exp(-z^2 / 2) carries a relative error of about
            // EPSILON z^2, the normalisation a few ulps.
            let z = (x - mean) / sd;
            let reference = shape.scaled(t_of(x)) / (shape.total * (b - a));
            assert!(
                (density / reference - 1.0).abs() <= 1e-12 + 4.0 * f64::EPSILON * z * z,
                "{name}: pdf({x:e}) = {density:e}, shape says {reference:e}"
            );
        }
        assert!(xs[0] < xs[N - 1], "{name}: every sample is {:e}", xs[0]);
        for j in 1..8 {
            let x = a + (b - a) * j as f64 / 8.0;
            let below = xs.partition_point(|&s| s <= x) as f64 / N as f64;
            let cdf = shape.cdf(t_of(x));
            assert!(
                (below - cdf).abs() <= 1.0 / N as f64 + 1e-9,
                "{name}: {below} of the samples are <= {x:e}, where the cdf is {cdf}"
            );
        }
    }
    // Only intervals without probability in f64 (far tails) are refused.
    assert!(tested >= 300, "{tested} tested, {refused} refused");
}

#[test]
fn truncated_normals_are_scale_invariant() {
    // N(0, s) on [20 s, 21 s] is N(0, 1) on [20, 21] in units of s: samples times s, density
    // over s. At s = 1e-230 the normalisation sd * mass is 2.8e-319, a subnormal with five
    // significant digits, which the density must not divide by. The tolerance allows the
    // rounding of x * s, magnified by z^2 = 441 in exp(-z^2 / 2).
    let unit = TruncatedNormal::new(0.0, 1.0, 20.0, 21.0).unwrap();
    for scale in [1e-230, 1e-200, 1e200] {
        let p = TruncatedNormal::new(0.0, scale, 20.0 * scale, 21.0 * scale).unwrap();
        for u in [0.0, 0.1, 0.5, 0.9, ONE_BELOW] {
            let x = unit.sample_1d(u);
            let sample = p.sample_1d(u) / scale;
            assert!(
                (sample / x - 1.0).abs() < 1e-14,
                "s = {scale:e}: {sample} vs {x}"
            );
            let density = p.pdf_1d(x * scale) * scale;
            assert!(
                (density / unit.pdf_1d(x) - 1.0).abs() < 1e-12,
                "s = {scale:e}: pdf {density} vs {}",
                unit.pdf_1d(x)
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Support and parameters

#[test]
fn pdfs_vanish_outside_their_supports() {
    for case in all_cases() {
        let (a, b) = case.pdf.support();
        let mut outside = vec![f64::NAN];
        if a.is_finite() {
            outside.extend([a.next_down(), a - 1.0, a - 1e300, -INF]);
        }
        if b.is_finite() {
            outside.extend([b.next_up(), b + 1.0, b + 1e300, INF]);
            if !case.closed {
                outside.push(b);
            }
        }
        for x in outside {
            assert_eq!(case.pdf.pdf_1d(x), 0.0, "{}: pdf({x})", case.name);
        }
        // Inside, the density is positive (every case has positive density on the interior).
        for u in [0.01, 0.5, 0.99] {
            let x = case.pdf.sample_1d(u);
            assert!(case.pdf.pdf_1d(x) > 0.0, "{}: pdf({x}) = 0", case.name);
        }
    }

    let b = UniformBox::new(vec![-1.0, 2.0], vec![3.0, 2.5]).unwrap();
    // Volume 4 x 0.5 = 2; the lower faces belong to the box, the upper ones do not.
    assert_eq!(b.pdf(&[0.0, 2.25]), 0.5);
    assert_eq!(b.pdf(&[-1.0, 2.0]), 0.5);
    for x in [
        [3.0, 2.25],
        [0.0, 2.5],
        [(-1f64).next_down(), 2.25],
        [0.0, 1.9],
        [f64::NAN, 2.25],
        [0.0, INF],
    ] {
        assert_eq!(b.pdf(&x), 0.0, "box pdf({x:?})");
    }
    let p = product_2d();
    assert!(p.pdf(&[0.5, 0.0]) > 0.0);
    for x in [
        [1.0, 0.0],
        [-0.1, 0.0],
        [0.5, 2.1],
        [0.5, -1.5],
        [0.5, f64::NAN],
    ] {
        assert_eq!(p.pdf(&x), 0.0, "product pdf({x:?})");
    }
}

#[test]
fn constructors_reject_bad_parameters_by_name() {
    let nan = f64::NAN;
    let uniform = |a, b| named(UniformInterval::new(a, b).unwrap_err());
    assert_eq!(uniform(1.0, 1.0), "b");
    assert_eq!(uniform(2.0, 1.0), "b");
    assert_eq!(uniform(nan, 1.0), "a");
    assert_eq!(uniform(0.0, nan), "b");
    assert_eq!(uniform(-INF, 1.0), "a");
    assert_eq!(uniform(0.0, INF), "b");

    let exponential = |r, a, b| named(Exponential::new(r, a, b).unwrap_err());
    assert_eq!(exponential(0.0, 0.0, 1.0), "rate");
    assert_eq!(exponential(-0.0, 0.0, 1.0), "rate");
    assert_eq!(exponential(nan, 0.0, 1.0), "rate");
    assert_eq!(exponential(INF, 0.0, 1.0), "rate");
    assert_eq!(exponential(1.0, 1.0, 1.0), "b");
    assert_eq!(exponential(1.0, nan, 1.0), "a");
    assert_eq!(exponential(1.0, -INF, 1.0), "a");
    assert_eq!(exponential(1.0, 0.0, nan), "b");
    // A growing exponential has no mass at +inf to normalise.
    assert_eq!(exponential(-1.0, 0.0, INF), "b");
    // |rate| (b - a) underflows: the density is uniform to rounding, and sampled as such.
    let flat = Exponential::new(1e-300, 0.0, 1e-300).unwrap();
    assert!((flat.pdf_1d(5e-301) * 1e-300 - 1.0).abs() < 1e-15);
    assert!((flat.sample_1d(0.25) / 2.5e-301 - 1.0).abs() < 1e-15);
    // A half-line needs 1 / rate finite.
    assert_eq!(exponential(5e-324, 0.0, INF), "rate");
    assert!(Exponential::new(1.0, 0.0, INF).is_ok());

    let linear = |a, b, v0, v1| named(Linear::new(a, b, v0, v1).unwrap_err());
    assert_eq!(linear(1.0, 0.0, 1.0, 1.0), "b");
    assert_eq!(linear(0.0, INF, 1.0, 1.0), "b");
    assert_eq!(linear(nan, 1.0, 1.0, 1.0), "a");
    assert_eq!(linear(0.0, 1.0, -1.0, 2.0), "v0");
    assert_eq!(linear(0.0, 1.0, 2.0, -1e-300), "v1");
    assert_eq!(linear(0.0, 1.0, nan, 1.0), "v0");
    assert_eq!(linear(0.0, 1.0, 1.0, INF), "v1");
    assert_eq!(linear(0.0, 1.0, 0.0, 0.0), "v0 + v1");
    assert!(Linear::new(0.0, 1.0, 0.0, 1.0).is_ok());

    let normal = |m, s, a, b| named(TruncatedNormal::new(m, s, a, b).unwrap_err());
    assert_eq!(normal(0.0, 0.0, -1.0, 1.0), "sd");
    assert_eq!(normal(0.0, -1.0, -1.0, 1.0), "sd");
    assert_eq!(normal(0.0, nan, -1.0, 1.0), "sd");
    assert_eq!(normal(0.0, INF, -1.0, 1.0), "sd");
    assert_eq!(normal(nan, 1.0, -1.0, 1.0), "mean");
    assert_eq!(normal(INF, 1.0, -1.0, 1.0), "mean");
    assert_eq!(normal(0.0, 1.0, 1.0, 1.0), "[a, b]");
    assert_eq!(normal(0.0, 1.0, 2.0, 1.0), "[a, b]");
    assert_eq!(normal(0.0, 1.0, nan, 1.0), "[a, b]");
    assert_eq!(normal(0.0, 1.0, 0.0, nan), "[a, b]");
    assert_eq!(normal(0.0, 1.0, INF, INF), "[a, b]");
    assert_eq!(normal(0.0, 1.0, -INF, -INF), "[a, b]");
    // No mass in f64 (the normal probability of [60, 61] is about 1e-784).
    assert_eq!(normal(0.0, 1.0, 60.0, 61.0), "[a, b]");
    assert_eq!(normal(0.0, 1.0, -61.0, -60.0), "[a, b]");
    assert_eq!(normal(0.0, 1.0, 45.0, INF), "[a, b]");
    // a - mean overflows (a is 4.5 sd below the mean): samples there would be -inf.
    assert_eq!(normal(9e307, 4e307, -9e307, -7e307), "[a, b]");
    let message = TruncatedNormal::new(0.0, 1.0, 60.0, 61.0)
        .unwrap_err()
        .to_string();
    assert!(message.contains("probability"), "{message}");

    assert_eq!(named(UniformBox::new(vec![], vec![]).unwrap_err()), "lo");
    assert_eq!(
        named(UniformBox::new(vec![0.0], vec![1.0, 2.0]).unwrap_err()),
        "hi"
    );
    assert_eq!(
        named(UniformBox::new(vec![0.0, 1.0], vec![1.0, 1.0]).unwrap_err()),
        "lo/hi"
    );
    assert_eq!(
        named(UniformBox::new(vec![0.0, nan], vec![1.0, 1.0]).unwrap_err()),
        "lo/hi"
    );
    assert_eq!(
        named(UniformBox::new(vec![0.0], vec![INF]).unwrap_err()),
        "lo/hi"
    );
    assert_eq!(
        named(UniformBox::new(vec![0.0, 0.0], vec![1e200, 1e200]).unwrap_err()),
        "box volume"
    );
    assert_eq!(
        named(UniformBox::new(vec![0.0, 0.0], vec![1e-200, 1e-200]).unwrap_err()),
        "box volume"
    );
    assert_eq!(named(UniformBox::unit(0).unwrap_err()), "dims");
    assert_eq!(named(ProductPdf::new(vec![]).unwrap_err()), "factors");

    // Messages name the parameter and what was allowed.
    assert_eq!(
        Linear::new(0.0, 1.0, -1.0, 2.0).unwrap_err().to_string(),
        "invalid v0 = -1: expected a finite value >= 0"
    );
    assert!(
        TruncatedNormal::new(0.0, -2.0, 0.0, 1.0)
            .unwrap_err()
            .to_string()
            .starts_with("invalid sd = -2")
    );
}

#[test]
fn intervals_whose_width_overflows_are_rejected_or_work() {
    let (a, b) = (-f64::MAX, f64::MAX);
    if let Ok(p) = UniformInterval::new(a, b) {
        assert!(p.pdf_1d(0.0) > 0.0, "pdf(0) = {}", p.pdf_1d(0.0));
        assert!(
            p.sample_1d(0.25) < 0.0,
            "sample(0.25) = {}",
            p.sample_1d(0.25)
        );
    }
    if let Ok(p) = Linear::new(a, b, 1.0, 1.0) {
        assert!(p.pdf_1d(0.0) > 0.0, "linear pdf(0) = {}", p.pdf_1d(0.0));
    }
}

#[test]
fn linear_sampling_is_scale_invariant() {
    // The density depends only on v1 / v0, so scaling both must not change the samples.
    for (v0, v1) in [(1.0, 1.0), (1.0, 3.0), (0.0, 1.0), (2.0, 0.5)] {
        let reference = Linear::new(0.0, 1.0, v0, v1).unwrap();
        for scale in [1e-200, 1e-160, 1e160, 1e200] {
            let scaled = Linear::new(0.0, 1.0, v0 * scale, v1 * scale).unwrap();
            for u in [0.1, 0.5, 0.9] {
                let (x, y) = (reference.sample_1d(u), scaled.sample_1d(u));
                assert!(
                    (x - y).abs() < 1e-12,
                    "v = ({v0}, {v1}) x {scale:e}: sample({u}) = {y}, expected {x}"
                );
                assert!((reference.pdf_1d(x) - scaled.pdf_1d(x)).abs() < 1e-12);
            }
        }
    }
}
