//! Integration tests for the normal, tent and table pdfs (`Normal`, `Tent`,
//! `PiecewiseConstant1d`, `PiecewiseConstant2d`, `PiecewiseLinear1d`) and the `AliasTable`:
//! each density integrates to one (quadrature written here, or exact sums over cells), samples
//! follow the density (the library's chi-square test against cell probabilities integrated
//! from `pdf`, never from `sample`), `invert` undoes `sample`, stratified `u` stay stratified
//! under the reference cdfs written here, densities vanish outside their supports and in
//! zero cells, and constructors reject bad input by name without panicking.
//!
//! Every statistical test uses a fixed seed and rejects at p < 1e-5, so a correct pdf fails
//! none of them in practice and every run is reproducible bit for bit.

use crate::common::{
    ONE_BELOW, P_REJECT, canonical, canonical_u, config, gauss_legendre, integrate, named,
};
use mcint::Error;
use mcint::pdf::{
    AliasTable, Normal, Pdf, Pdf1d, PiecewiseConstant1d, PiecewiseConstant2d, PiecewiseLinear1d,
    Tent, TruncatedNormal,
};
use mcint::stats::chi_square_goodness_of_fit;
use proptest::prelude::*;

const INF: f64 = f64::INFINITY;
const NAN: f64 = f64::NAN;
// ---------------------------------------------------------------------------------------------
// Quadrature

/// The integral of `f` over `[lo, hi]`, split at the `breaks` inside it (where `f` has a kink
/// or a jump) and into panels no wider than `max_panel` (`INF` for polynomial pieces).
fn integrate_pieces(
    f: &dyn Fn(f64) -> f64,
    lo: f64,
    hi: f64,
    breaks: &[f64],
    max_panel: f64,
) -> f64 {
    let mut points = vec![lo];
    points.extend(breaks.iter().copied().filter(|&x| lo < x && x < hi));
    points.push(hi);
    points
        .windows(2)
        .map(|piece| {
            let panels = ((piece[1] - piece[0]) / max_panel)
                .ceil()
                .clamp(1.0, 4000.0) as usize;
            integrate(f, piece[0], piece[1], panels)
        })
        .sum()
}

#[test]
fn quadrature_is_exact_where_theory_says() {
    let rule = gauss_legendre();
    assert!((rule.iter().map(|&(_, w)| w).sum::<f64>() - 2.0).abs() < 1e-14);
    assert!((integrate(|x: f64| x.powi(23), 0.0, 1.0, 1) - 1.0 / 24.0).abs() < 1e-15);
    // A step at 0.3 is integrated exactly once the break is given.
    let step = |x: f64| if x < 0.3 { 1.0 } else { 3.0 };
    let exact = 0.3 + 3.0 * 0.7;
    assert!((integrate_pieces(&step, 0.0, 1.0, &[0.3], INF) - exact).abs() < 1e-15);
    assert!((integrate_pieces(&step, 0.0, 1.0, &[], INF) - exact).abs() > 1e-3);
}

// ---------------------------------------------------------------------------------------------
// Reference distributions, written independently of the library

/// The standard normal density.
fn phi(z: f64) -> f64 {
    (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt()
}

/// The standard normal cdf by quadrature of `phi` from zero (absolute error near 1e-16:
/// panels of width 1/4 of a degree-23 rule).
fn reference_normal_cdf(z: f64) -> f64 {
    if z.is_nan() {
        return NAN;
    }
    let t = z.abs().min(40.0);
    let half = integrate(phi, 0.0, t, ((t / 0.25).ceil() as usize).max(1));
    if z < 0.0 { 0.5 - half } else { 0.5 + half }
}

/// The cdf of a step function with `weights` on equal cells of `[a, b)`.
fn reference_table_cdf(a: f64, b: f64, weights: &[f64], x: f64) -> f64 {
    let n = weights.len();
    let width = (b - a) / n as f64;
    if x < a {
        return 0.0;
    }
    if x >= b {
        return 1.0;
    }
    let sum: f64 = weights.iter().sum();
    let i = (((x - a) / width) as usize).min(n - 1);
    let before: f64 = weights[..i].iter().sum();
    let within = ((x - (a + i as f64 * width)) / width).clamp(0.0, 1.0);
    // Divide before multiplying: subnormal weights would lose their digits in the product.
    before / sum + weights[i] / sum * within
}

/// The cdf of the linear interpolant of `values` at `xs` (values rescaled by their largest, so
/// no product overflows).
fn reference_linear_cdf(xs: &[f64], values: &[f64], x: f64) -> f64 {
    let peak = values.iter().fold(0.0f64, |m, &v| m.max(v));
    let v: Vec<f64> = values.iter().map(|v| v / peak).collect();
    let segment_mass = |i: usize, tau: f64| {
        let d = xs[i + 1] - xs[i];
        v[i] * tau + (v[i + 1] - v[i]) * tau * (tau / (2.0 * d))
    };
    let n = xs.len();
    let total: f64 = (0..n - 1).map(|i| segment_mass(i, xs[i + 1] - xs[i])).sum();
    if x < xs[0] {
        return 0.0;
    }
    if x >= xs[n - 1] {
        return 1.0;
    }
    let i = (0..n - 1).rev().find(|&i| xs[i] <= x).unwrap();
    let before: f64 = (0..i).map(|j| segment_mass(j, xs[j + 1] - xs[j])).sum();
    (before + segment_mass(i, x - xs[i])) / total
}

/// The tent's cdf in closed form.
fn reference_tent_cdf(a: f64, c: f64, b: f64, x: f64) -> f64 {
    if x <= a {
        0.0
    } else if x >= b {
        1.0
    } else if x < c {
        ((x - a) / (c - a)).powi(2) * ((c - a) / (b - a))
    } else {
        1.0 - ((b - x) / (b - c)).powi(2) * ((b - c) / (b - a))
    }
}

/// The tent's density in closed form.
fn reference_tent_pdf(a: f64, c: f64, b: f64, x: f64) -> f64 {
    if !(a..=b).contains(&x) {
        0.0
    } else if x < c {
        2.0 / (b - a) * (x - a) / (c - a)
    } else if x > c {
        2.0 / (b - a) * (b - x) / (b - c)
    } else {
        2.0 / (b - a)
    }
}

// ---------------------------------------------------------------------------------------------
// The one-dimensional cases

/// A 1-D pdf with what the tests need to know about it.
struct Case {
    name: String,
    pdf: Box<dyn Pdf1d>,
    /// The same pdf through the `Pdf` trait.
    as_pdf: Box<dyn Pdf>,
    /// The cdf, computed here without the library.
    cdf: Box<dyn Fn(f64) -> f64>,
    /// The density, computed here without the library.
    density: Box<dyn Fn(f64) -> f64>,
    /// A finite window holding all but at most `1e-300` of the probability.
    window: (f64, f64),
    /// Where the density has kinks or jumps.
    breaks: Vec<f64>,
    /// Widest quadrature panel for this density (`INF` when it is piecewise polynomial).
    max_panel: f64,
    /// Histogram edges for the goodness-of-fit test, covering the support.
    bins: Vec<f64>,
    /// True when the support includes its upper end.
    closed: bool,
    /// Points inside the support where the density must be zero (zero cells).
    zeros: Vec<f64>,
}

/// `n` equal cells of `[lo, hi]`, as edges.
fn equal_edges(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..=n)
        .map(|i| {
            if i == n {
                hi
            } else {
                lo + i as f64 * ((hi - lo) / n as f64)
            }
        })
        .collect()
}

/// Each interval between consecutive `edges` split into `parts` equal bins.
fn refine(edges: &[f64], parts: usize) -> Vec<f64> {
    let mut bins = vec![edges[0]];
    for e in edges.windows(2) {
        for k in 1..=parts {
            bins.push(if k == parts {
                e[1]
            } else {
                e[0] + (e[1] - e[0]) * (k as f64 / parts as f64)
            });
        }
    }
    bins
}

fn normal(mean: f64, sd: f64) -> Case {
    let pdf = Normal::new(mean, sd).unwrap();
    // Beyond 40 sd the normal holds less than phi(40)/40 = 1e-349 (Mills' ratio).
    let window = (mean - 40.0 * sd, mean + 40.0 * sd);
    let mut bins = vec![-INF];
    bins.extend((0..=48).map(|k| mean + sd * (-6.0 + 12.0 * k as f64 / 48.0)));
    bins.push(INF);
    Case {
        name: format!("Normal({mean}, {sd})"),
        pdf: Box::new(pdf),
        as_pdf: Box::new(pdf),
        cdf: Box::new(move |x| reference_normal_cdf((x - mean) / sd)),
        density: Box::new(move |x| phi((x - mean) / sd) / sd),
        window,
        breaks: vec![],
        max_panel: sd / 4.0,
        bins,
        closed: true,
        zeros: vec![],
    }
}

fn tent(a: f64, c: f64, b: f64) -> Case {
    tent_case(Tent::new(a, c, b).unwrap(), format!("Tent({a}, {c}, {b})"))
}

fn symmetric_tent(center: f64, radius: f64) -> Case {
    tent_case(
        Tent::symmetric(center, radius).unwrap(),
        format!("Tent::symmetric({center}, {radius})"),
    )
}

fn tent_case(pdf: Tent, name: String) -> Case {
    let ((a, b), c) = (pdf.support(), pdf.mode());
    Case {
        name,
        pdf: Box::new(pdf),
        as_pdf: Box::new(pdf),
        cdf: Box::new(move |x| reference_tent_cdf(a, c, b, x)),
        density: Box::new(move |x| reference_tent_pdf(a, c, b, x)),
        window: (a, b),
        breaks: vec![c],
        max_panel: INF,
        bins: equal_edges(a, b, 40),
        closed: true,
        zeros: vec![],
    }
}

fn constant(a: f64, b: f64, weights: &[f64], parts: usize) -> Case {
    let pdf = PiecewiseConstant1d::new(a, b, weights).unwrap();
    let edges = equal_edges(a, b, weights.len());
    let w = weights.to_vec();
    let sum: f64 = w.iter().sum();
    let cell_width = (b - a) / w.len() as f64;
    let zeros = edges
        .windows(2)
        .zip(weights)
        .filter(|(_, w)| **w == 0.0)
        .map(|(e, _)| 0.5 * (e[0] + e[1]))
        .collect();
    let (w2, e2) = (w.clone(), edges.clone());
    Case {
        name: format!("PiecewiseConstant1d({a}, {b}, {} cells)", weights.len()),
        as_pdf: Box::new(pdf.clone()),
        pdf: Box::new(pdf),
        cdf: Box::new(move |x| reference_table_cdf(a, b, &w, x)),
        density: Box::new(move |x| {
            if !(a..b).contains(&x) {
                return 0.0;
            }
            let i = (((x - a) / cell_width) as usize).min(w2.len() - 1);
            // Samples are uniform between the cell's float edges, which rounding can make
            // unequal (by 1e-7 relative at 1e9 with cells of 1/3): that width is the density's.
            w2[i] / sum / (e2[i + 1] - e2[i])
        }),
        window: (a, b),
        breaks: edges.clone(),
        max_panel: INF,
        bins: refine(&edges, parts),
        closed: false,
        zeros,
    }
}

fn linear(xs: &[f64], values: &[f64], parts: usize) -> Case {
    let pdf = PiecewiseLinear1d::new(xs, values).unwrap();
    let (x, v) = (xs.to_vec(), values.to_vec());
    let (x2, v2) = (xs.to_vec(), values.to_vec());
    let zeros = xs
        .windows(2)
        .zip(values.windows(2))
        .filter(|(_, v)| v[0] == 0.0 && v[1] == 0.0)
        .map(|(x, _)| 0.5 * (x[0] + x[1]))
        .collect();
    let n = xs.len();
    Case {
        name: format!(
            "PiecewiseLinear1d({n} breakpoints on [{}, {}])",
            xs[0],
            xs[n - 1]
        ),
        as_pdf: Box::new(pdf.clone()),
        pdf: Box::new(pdf),
        cdf: Box::new(move |t| reference_linear_cdf(&x, &v, t)),
        density: Box::new(move |t| {
            // The derivative of the reference cdf: the interpolant over its integral.
            let n = x2.len();
            if !(x2[0]..x2[n - 1]).contains(&t) {
                return 0.0;
            }
            // Rescaled by the peak first, so subnormal values keep their digits.
            let peak = v2.iter().fold(0.0f64, |m, &v| m.max(v));
            let v: Vec<f64> = v2.iter().map(|v| v / peak).collect();
            let total: f64 = (0..n - 1)
                .map(|i| 0.5 * (v[i] + v[i + 1]) * (x2[i + 1] - x2[i]))
                .sum();
            let i = (0..n - 1).rev().find(|&i| x2[i] <= t).unwrap();
            let s = (t - x2[i]) / (x2[i + 1] - x2[i]);
            ((1.0 - s) * v[i] + s * v[i + 1]) / total
        }),
        window: (xs[0], xs[n - 1]),
        breaks: xs.to_vec(),
        max_panel: INF,
        bins: refine(xs, parts),
        closed: false,
        zeros,
    }
}

fn normal_cases() -> Vec<Case> {
    vec![
        normal(0.0, 1.0),
        normal(3.0, 0.25),
        normal(-1e5, 1e-3),
        normal(0.0, 1e-300),
        normal(1e300, 1e298),
        normal(0.0, 1e200),
    ]
}

fn tent_cases() -> Vec<Case> {
    vec![
        tent(0.0, 1.0, 4.0),
        tent(-1.0, -1.0, 1.0),
        tent(2.0, 5.0, 5.0),
        tent(0.0, 1e-9, 1.0),
        tent(0.0, 1.0 - 1e-9, 1.0),
        tent(-1e300, 0.0, 1e300),
        tent(1e-300, 2e-300, 4e-300),
        symmetric_tent(0.0, 1.0),
        symmetric_tent(1e6, 1e-3),
    ]
}

/// Weights from a fixed pseudo-random stream (the independent sampler), with every `zero_every`
/// -th one zero.
fn random_weights(n: usize, seed: u64, zero_every: usize) -> Vec<f64> {
    let u = canonical(1, n, seed);
    u.column(0)
        .iter()
        .enumerate()
        .map(|(i, &u)| if i % zero_every == 3 { 0.0 } else { u })
        .collect()
}

fn constant_cases() -> Vec<Case> {
    let geometric: Vec<f64> = (0..64).map(|i| 0.5f64.powi(i)).collect();
    vec![
        constant(0.0, 1.0, &[1.0, 2.0, 3.0, 4.0], 4),
        constant(-2.0, 4.0, &[0.0, 1.0, 0.0, 0.0, 5.0, 0.0], 4),
        constant(3.0, 5.0, &[7.0], 32),
        constant(0.0, 64.0, &geometric, 2),
        constant(0.0, 1.0, &[1e-300, 1e300, 0.0], 8),
        constant(1e-300, 3e-300, &[1.0, 3.0], 8),
        constant(-1e300, 1e300, &[1.0, 2.0, 3.0], 8),
        constant(0.0, 1.0, &[1e300, 1e300, 1e307], 8),
        constant(0.0, 1.0, &[1e-320, 3e-320], 8),
        constant(1e9, 1e9 + 1.0, &[2.0, 1.0, 2.0], 8),
        constant(-1.0, 1.0, &random_weights(1000, 77, 10), 2),
    ]
}

fn linear_cases() -> Vec<Case> {
    let wave_x: Vec<f64> = (0..200).map(|i| i as f64 * 0.05).collect();
    let wave_v: Vec<f64> = wave_x.iter().map(|x| x.sin().abs()).collect();
    vec![
        linear(&[0.0, 1.0, 2.0], &[0.0, 1.0, 0.0], 8),
        linear(&[0.0, 1.0], &[1.0, 1.0 + 1e-12], 16),
        linear(&[0.0, 1.0, 3.0, 3.5, 10.0], &[2.0, 0.0, 0.0, 5.0, 1.0], 8),
        linear(&[-1e-6, 0.0, 1e-6], &[1e-200, 1.0, 1e-200], 8),
        linear(&[0.0, 1e300], &[3.0, 1.0], 16),
        linear(&[0.0, 1.0, 2.0], &[1e300, 1e-300, 1e300], 8),
        linear(&[5.0, 5.5], &[0.0, 1e-310], 16),
        linear(&wave_x, &wave_v, 2),
    ]
}

fn all_cases() -> Vec<Case> {
    let mut cases = normal_cases();
    cases.extend(tent_cases());
    cases.extend(constant_cases());
    cases.extend(linear_cases());
    cases
}

// ---------------------------------------------------------------------------------------------
// Integrates to one, and is the density written here

/// Tolerance for a quadrature of a case's density to one. Each node `x_k` is rounded to a
/// float, by at most half an ulp, which changes `f(x_k)` by up to `|f'| ulp / 2`; summed with
/// the weights that is at most the density's total variation times `ulp / 2` (nodes never fall
/// on a jump). It matters only for narrow densities far from zero, such as `Normal(-1e5,
/// 1e-3)`, where x has an ulp of 1.5e-11 against an sd of 1e-3. The variation is measured on
/// a fine grid of the reference density (it over-counts jumps, which only loosens this a bit).
fn quadrature_tolerance(case: &Case) -> f64 {
    let (lo, hi) = case.window;
    let mut points: Vec<f64> = (0..=20_000)
        .map(|k| lo + (hi - lo) * (k as f64 / 20_000.0))
        .collect();
    points.extend(case.breaks.iter().copied());
    points.sort_by(f64::total_cmp);
    let variation: f64 = points
        .windows(2)
        .map(|p| ((case.density)(p[1]) - (case.density)(p[0])).abs())
        .sum();
    let ulp = f64::EPSILON * lo.abs().max(hi.abs());
    1e-12 + variation * ulp
}

#[test]
fn one_dimensional_pdfs_integrate_to_one() {
    // Polynomial pieces are integrated exactly (to rounding in sums of up to 12,000 terms);
    // the normal with 320 panels of a quarter sd over +-40 sd, far below 1e-13 of error.
    for case in all_cases() {
        let (lo, hi) = case.window;
        let f = |x: f64| case.pdf.pdf_1d(x);
        let total = integrate_pieces(&f, lo, hi, &case.breaks, case.max_panel);
        let tolerance = quadrature_tolerance(&case);
        assert!(
            (total - 1.0).abs() < tolerance,
            "{}: integral {total} (tolerance {tolerance:e})",
            case.name
        );
        assert_eq!((case.as_pdf.dims(), case.as_pdf.canonical_dims()), (1, 1));
    }
}

#[test]
fn densities_match_the_formulas() {
    // At 2000 points across each window the library's density is the one written here, to
    // rounding: relative 1e-12, plus 1e-14 of the largest density seen, for points where the
    // interpolant nearly vanishes and the two formulas round differently. (The points avoid
    // cell edges, where the two might disagree about the cell by an ulp of x.)
    for case in all_cases() {
        let (lo, hi) = case.window;
        let points: Vec<f64> = (0..2000)
            .map(|k| lo + (hi - lo) * ((k as f64 + 0.3) / 2000.0))
            .collect();
        let scale = points.iter().fold(0.0f64, |m, &x| m.max((case.density)(x)));
        for &x in &points {
            let (got, want) = (case.pdf.pdf_1d(x), (case.density)(x));
            assert!(
                (got - want).abs() <= 1e-12 * want + 1e-14 * scale,
                "{}: pdf({x}) = {got}, expected {want}",
                case.name
            );
            assert_eq!(got.to_bits(), case.as_pdf.pdf(&[x]).to_bits());
        }
    }
}

#[test]
fn table_probabilities_sum_to_one_exactly() {
    // The tables' normalisation is an exact sum: probabilities are w_i / sum(w).
    for (a, b, weights) in [
        (0.0, 1.0, vec![1.0, 2.0, 3.0, 4.0]),
        (-2.0, 4.0, vec![0.0, 1.0, 0.0, 0.0, 5.0, 0.0]),
        (3.0, 5.0, vec![7.0]),
        (0.0, 1.0, random_weights(1000, 77, 10)),
    ] {
        let p = PiecewiseConstant1d::new(a, b, &weights).unwrap();
        let sum: f64 = weights.iter().sum();
        assert_eq!(p.cell_count(), weights.len());
        let total: f64 = p.probabilities().iter().sum();
        assert!((total - 1.0).abs() <= 1e-15 * weights.len() as f64);
        for (i, w) in weights.iter().enumerate() {
            assert_eq!(p.cell_probability(i), w / sum);
            let (lo, hi) = p.cell_bounds(i).unwrap();
            // Density times width is the cell's probability.
            let mid = 0.5 * (lo + hi);
            assert!((p.pdf_1d(mid) * (b - a) / weights.len() as f64 - w / sum).abs() < 1e-15);
            assert_eq!(p.cell_at(mid), Some(i));
        }
        assert_eq!(p.cell_probability(weights.len()), 0.0);
        assert_eq!(p.cell_bounds(weights.len()), None);
        assert!((p.integral() - sum * (b - a) / weights.len() as f64).abs() < 1e-14 * sum);
    }
    let p = PiecewiseLinear1d::new(&[0.0, 1.0, 3.0, 4.0], &[1.0, 3.0, 0.0, 0.0]).unwrap();
    // Trapezoids 2, 3, 0 of a total 5.
    let probabilities = p.segment_probabilities();
    assert_eq!(probabilities.len(), 3);
    for (got, want) in probabilities.iter().zip([0.4, 0.6, 0.0]) {
        assert!((got - want).abs() < 4e-16, "{got} vs {want}");
    }
    assert_eq!(p.breakpoints(), &[0.0, 1.0, 3.0, 4.0]);
}

// ---------------------------------------------------------------------------------------------
// Samples follow the density

fn assert_fits(name: &str, observed: &[u64], expected: &[f64]) {
    let fit = chi_square_goodness_of_fit(observed, expected, 5.0).unwrap();
    assert!(
        fit.p_value >= P_REJECT,
        "{name}: chi2 = {} on {} dof, p = {:e}",
        fit.statistic,
        fit.dof,
        fit.p_value
    );
}

/// Samples per 1-D case: a few hundred per bin for the 40-100 bins most cases have.
const SAMPLES_1D: usize = 200_000;

fn goodness_of_fit_1d(cases: &[Case], seed: u64) {
    for (c, case) in cases.iter().enumerate() {
        let bins = &case.bins;
        // Tables with many cells get more samples, so each bin still expects hundreds.
        let samples = SAMPLES_1D.max(250 * bins.len());
        let (w0, w1) = case.window;
        let f = |x: f64| case.pdf.pdf_1d(x);
        let expected: Vec<f64> = bins
            .windows(2)
            .map(|e| {
                let (lo, hi) = (e[0].max(w0), e[1].min(w1));
                if lo < hi {
                    samples as f64 * integrate_pieces(&f, lo, hi, &case.breaks, case.max_panel)
                } else {
                    0.0
                }
            })
            .collect();
        let total = expected.iter().sum::<f64>() / samples as f64;
        assert!(
            (total - 1.0).abs() < quadrature_tolerance(case),
            "{}: bins hold {total}",
            case.name
        );

        let (a, b) = case.pdf.support();
        let u = canonical(1, samples, seed + c as u64);
        let mut observed = vec![0u64; bins.len() - 1];
        for &u in u.column(0) {
            let x = case.pdf.sample_1d(u);
            let inside = x.is_finite()
                && if case.closed {
                    a <= x && x <= b
                } else {
                    a <= x && x < b
                };
            assert!(inside, "{}: sample({u}) = {x} outside", case.name);
            let bin = bins.partition_point(|&e| e <= x).clamp(1, bins.len() - 1) - 1;
            observed[bin] += 1;
        }
        assert_fits(&case.name, &observed, &expected);
    }
}

#[test]
fn normal_samples_follow_the_density() {
    goodness_of_fit_1d(&normal_cases(), 100);
}

#[test]
fn tent_samples_follow_the_density() {
    goodness_of_fit_1d(&tent_cases(), 200);
}

#[test]
fn piecewise_constant_samples_follow_the_density() {
    goodness_of_fit_1d(&constant_cases(), 300);
}

#[test]
fn piecewise_linear_samples_follow_the_density() {
    goodness_of_fit_1d(&linear_cases(), 400);
}

#[test]
fn goodness_of_fit_catches_a_wrong_density() {
    // The test has power: samples of one table judged against a table 3% different fail it.
    let samples = 200_000;
    let right = PiecewiseConstant1d::new(0.0, 1.0, &[1.0, 2.0, 3.0, 4.0]).unwrap();
    let wrong = PiecewiseConstant1d::new(0.0, 1.0, &[1.0, 2.0, 3.0, 4.3]).unwrap();
    let u = canonical(1, samples, 9);
    let mut observed = vec![0u64; 4];
    for &u in u.column(0) {
        observed[right.sample_cell(u).0] += 1;
    }
    let expected: Vec<f64> = wrong
        .probabilities()
        .iter()
        .map(|p| p * samples as f64)
        .collect();
    let fit = chi_square_goodness_of_fit(&observed, &expected, 5.0).unwrap();
    assert!(fit.p_value < P_REJECT, "p = {}", fit.p_value);
}

// ---------------------------------------------------------------------------------------------
// invert, stratification, support

/// Round-trip tolerance for `invert(sample(u)) = u`: the sample is a float, rounded by a few
/// ulps (clamps to half-open cells move it by one), which moves the cdf by `pdf(x)` per unit
/// of x; the cdf arithmetic adds a few ulps of u, well inside the 1e-12 floor.
fn round_trip_tolerance(density: f64, x: f64) -> f64 {
    1e-12 + 4.0 * density * (x.abs().next_up() - x.abs())
}

fn check_round_trip(name: &str, pdf: &dyn Pdf1d, u: f64) -> Result<(), TestCaseError> {
    let x = pdf.sample_1d(u);
    prop_assert!(x.is_finite(), "{}: sample({}) = {}", name, u, x);
    let back = pdf.invert_1d(x);
    let tolerance = round_trip_tolerance(pdf.pdf_1d(x), x);
    prop_assert!(
        (back - u).abs() <= tolerance,
        "{}: u = {}, x = {}, invert = {}, error {:e}",
        name,
        u,
        x,
        back,
        back - u
    );
    Ok(())
}

/// A table weight: zero, ordinary, tiny or huge.
fn weight() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        0.0..1.0f64,
        1e-200..1e-190f64,
        1e250..1e260f64,
        1.0..2.0f64,
    ]
}

/// A table of 1 to 40 weights, at least one positive.
fn weights() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(weight(), 1..40).prop_map(|mut w| {
        if w.iter().all(|&x| x == 0.0) {
            w[0] = 1.0;
        }
        w
    })
}

/// An interval `[a, a + width]` with a log-uniform width.
fn interval() -> impl Strategy<Value = (f64, f64)> {
    (-1e3..1e3f64, -6.0..6.0f64).prop_map(|(a, log_width)| (a, a + 10f64.powf(log_width)))
}

proptest! {
    #![proptest_config(config(400, 20240605))]

    #[test]
    fn listed_cases_invert_their_samples(case in 0usize..34, u in canonical_u()) {
        let cases = all_cases();
        prop_assert_eq!(cases.len(), 34);
        let case = &cases[case];
        check_round_trip(&case.name, case.pdf.as_ref(), u)?;
        // The Pdf trait forwards to the 1-D methods.
        let (mut x, mut back) = ([0.0], [0.0]);
        case.as_pdf.sample(&[u], &mut x);
        prop_assert_eq!(x[0].to_bits(), case.pdf.sample_1d(u).to_bits());
        case.as_pdf.invert(&x, &mut back).unwrap();
        prop_assert_eq!(back[0].to_bits(), case.pdf.invert_1d(x[0]).to_bits());
    }

    #[test]
    fn normals_invert_their_samples(
        mean in -1e6..1e6f64,
        log_sd in -6.0..6.0f64,
        u in canonical_u(),
    ) {
        let p = Normal::new(mean, 10f64.powf(log_sd)).unwrap();
        check_round_trip("Normal", &p, u)?;
    }

    #[test]
    fn tents_invert_their_samples(
        (a, b) in interval(),
        mode in prop_oneof![Just(0.0), Just(1.0), 0.0..1.0f64],
        u in canonical_u(),
    ) {
        let p = Tent::new(a, (a + mode * (b - a)).min(b), b).unwrap();
        check_round_trip("Tent", &p, u)?;
    }

    #[test]
    fn piecewise_constants_invert_their_samples(
        (a, b) in interval(),
        weights in weights(),
        u in canonical_u(),
    ) {
        let p = PiecewiseConstant1d::new(a, b, &weights).unwrap();
        check_round_trip("PiecewiseConstant1d", &p, u)?;
        // A sample never lands in a cell of zero weight.
        let x = p.sample_1d(u);
        let (cell, fraction) = p.sample_cell(u);
        prop_assert!(weights[cell] > 0.0 && p.pdf_1d(x) > 0.0);
        prop_assert_eq!(p.cell_at(x), Some(cell));
        prop_assert!((0.0..1.0).contains(&fraction));
    }

    #[test]
    fn piecewise_linears_invert_their_samples(
        a in -1e3..1e3f64,
        steps in prop::collection::vec(1e-3..10.0f64, 1..20),
        raw in prop::collection::vec(weight(), 20),
        u in canonical_u(),
    ) {
        let mut xs = vec![a];
        for s in &steps {
            xs.push(xs[xs.len() - 1] + s);
        }
        let mut values = raw[..xs.len()].to_vec();
        if values.iter().all(|&v| v == 0.0) {
            values[0] = 1.0;
        }
        let p = PiecewiseLinear1d::new(&xs, &values).unwrap();
        check_round_trip("PiecewiseLinear1d", &p, u)?;
        // Inside a segment of zero mass never; only on a zero breakpoint at its exact cdf.
        let x = p.sample_1d(u);
        let i = xs.partition_point(|&b| b <= x) - 1;
        prop_assert!(values[i] > 0.0 || values[i + 1] > 0.0, "segment {} is all zero", i);
    }
}

#[test]
fn stratified_canonical_points_stay_stratified() {
    // N jittered u, u_i = (i + xi_i) / N, must give exactly one sample in each of the N
    // equal-probability cells [F^-1(i/N), F^-1((i+1)/N)) of the pdf, where F is the reference
    // cdf written above (not the library's invert). A jitter within about 1e-12 of a stratum
    // edge could be misplaced by rounding; with these fixed seeds none is that close.
    const N: usize = 1000;
    for (c, case) in all_cases().iter().enumerate() {
        let jitter = canonical(1, N, 1000 + c as u64);
        let mut counts = vec![0u32; N];
        for (i, xi) in jitter.column(0).iter().enumerate() {
            let u = (i as f64 + xi) / N as f64;
            let x = case.pdf.sample_1d(u);
            let cell = ((case.cdf)(x) * N as f64).floor() as usize;
            assert_eq!(
                cell, i,
                "{}: u = {u} gave x = {x} in cell {cell}",
                case.name
            );
            counts[cell.min(N - 1)] += 1;
        }
        assert!(counts.iter().all(|&k| k == 1), "{}", case.name);
    }
}

#[test]
fn pdfs_vanish_outside_their_supports_and_in_zero_cells() {
    for case in all_cases() {
        let (a, b) = case.pdf.support();
        let mut outside = vec![NAN];
        // (a - 1 is a itself when a is huge.)
        if a.is_finite() {
            let below = [a.next_down(), a - 1.0, a - 1e300, -INF];
            outside.extend(below.into_iter().filter(|&x| x < a));
        }
        if b.is_finite() {
            let above = [b.next_up(), b + 1.0, b + 1e300, INF];
            outside.extend(above.into_iter().filter(|&x| x > b));
            if !case.closed {
                outside.push(b);
            }
        }
        for x in outside {
            assert_eq!(case.pdf.pdf_1d(x), 0.0, "{}: pdf({x})", case.name);
        }
        for &x in &case.zeros {
            assert_eq!(
                case.pdf.pdf_1d(x),
                0.0,
                "{}: pdf({x}) in a zero cell",
                case.name
            );
        }
        // invert is the cdf: 0 below the support, 1 above.
        if a.is_finite() {
            assert_eq!(case.pdf.invert_1d(a.next_down()), 0.0, "{}", case.name);
        }
        if b.is_finite() {
            assert_eq!(case.pdf.invert_1d(b.next_up()), 1.0, "{}", case.name);
        }
        assert_eq!(case.pdf.invert_1d(-INF), 0.0, "{}", case.name);
        assert_eq!(case.pdf.invert_1d(INF), 1.0, "{}", case.name);
    }
}

// ---------------------------------------------------------------------------------------------
// The normal

#[test]
fn normal_agrees_bit_for_bit_with_the_untruncated_truncated_normal() {
    for (mean, sd) in [(0.0, 1.0), (3.0, 0.25), (-1e5, 1e-3), (1e300, 1e298)] {
        let normal = Normal::new(mean, sd).unwrap();
        let truncated = TruncatedNormal::new(mean, sd, -INF, INF).unwrap();
        let mut us = vec![0.0, 5e-324, 1e-300, 1e-17, 0.5, ONE_BELOW, 1.0, NAN];
        us.extend((1..1000).map(|k| k as f64 / 1000.0));
        for u in us {
            let x = normal.sample_1d(u);
            assert_eq!(x.to_bits(), truncated.sample_1d(u).to_bits(), "u = {u}");
            assert_eq!(normal.pdf_1d(x).to_bits(), truncated.pdf_1d(x).to_bits());
            assert_eq!(
                normal.invert_1d(x).to_bits(),
                truncated.invert_1d(x).to_bits()
            );
        }
    }
}

#[test]
fn normal_at_u_zero_is_finite_and_as_documented() {
    // u = 0 is read as the smallest positive normal f64, where the quantile is
    // python3 -c "from scipy.stats import norm; import sys; print(norm.ppf(sys.float_info.min))"
    // = -37.5193793471445.
    let z0 = Normal::new(0.0, 1.0).unwrap().sample_1d(f64::MIN_POSITIVE);
    assert!((z0 + 37.5193793471445).abs() < 1e-12, "{z0}");
    for (mean, sd) in [(0.0, 1.0), (2.0, 3.0), (0.0, 1e-300), (1e300, 1e298)] {
        let p = Normal::new(mean, sd).unwrap();
        let x = p.sample_1d(0.0);
        assert!(x.is_finite());
        assert_eq!(x, mean + sd * z0);
        assert!(p.pdf_1d(x) >= 0.0);
        // The top of the canonical range, 1 - 2^-53, reaches 8.2095 sd
        // (python3 -c "from scipy.stats import norm; print(norm.ppf(1 - 2**-53))" gives
        // 8.209536151601387).
        let top = (p.sample_1d(ONE_BELOW) - mean) / sd;
        assert!((top - 8.209536151601387).abs() < 1e-9, "{top}");
    }
}

// ---------------------------------------------------------------------------------------------
// Numerically delicate tables

#[test]
fn nearly_flat_linear_segments_have_no_cancellation() {
    // With values 1 and 1 + s the cdf is t + s t^2 / 2 over (1 + s/2), so the inverse differs
    // from t = u by about s u (1 - u) / 2. A naive quadratic solve (-v0 + sqrt(v0^2 + ...)) /
    // (v1 - v0) divides a cancelled difference by s and loses everything at s = 1e-12; the
    // stable form keeps the error at rounding level.
    for s in [1e-6, 1e-12, 1e-15, 0.0] {
        let p = PiecewiseLinear1d::new(&[0.0, 1.0], &[1.0, 1.0 + s]).unwrap();
        for k in 0..=100 {
            let u = k as f64 / 100.0;
            let x = p.sample_1d(u);
            // The cdf of the density 1 + s t, normalised.
            let cdf = |t: f64| (t + s * t * t / 2.0) / (1.0 + s / 2.0);
            let error = cdf(x) - u;
            // A few ulps of u; the naive solve is off by about 1e-16 / s.
            assert!(
                error.abs() < 2e-15,
                "s = {s}: F(sample({u})) - u = {error:e}"
            );
        }
    }
}

#[test]
fn tiny_values_beside_large_ones_keep_their_shape() {
    // Values 1e-200 of the table's peak still make a linear density: the ratio across the
    // segment is that of its values ...
    let p = PiecewiseLinear1d::new(&[0.0, 1.0, 2.0], &[1e-200, 3e-200, 1.0]).unwrap();
    let ratio = p.pdf_1d(0.75) / p.pdf_1d(0.25);
    assert!((ratio - 2.5 / 1.5).abs() < 1e-14, "{ratio}");
    // ... and sampling within that segment (the first, so u below its probability, about
    // 4e-200, reaches it) follows its shape. Without rescaling each segment, the squares in
    // the quadratic underflow and every point lands at the segment's end.
    let mass = p.segment_probabilities()[0];
    assert!((mass / 4e-200 - 1.0).abs() < 1e-12, "{mass:e}");
    let shape = PiecewiseLinear1d::new(&[0.0, 1.0], &[1.0, 3.0]).unwrap();
    for k in 0..20 {
        let fraction = k as f64 / 20.0;
        let (x, y) = (p.sample_1d(fraction * mass), shape.sample_1d(fraction));
        assert!((x - y).abs() < 1e-14, "fraction {fraction}: {x} vs {y}");
        // Against the closed form t = (-1 + sqrt(1 + 8f)) / 2 of the density (1 + 2t) / 2.
        let exact = (-1.0 + (1.0 + 8.0 * fraction).sqrt()) / 2.0;
        assert!(
            (x - exact).abs() < 1e-14,
            "fraction {fraction}: {x}, exact {exact}"
        );
    }
}

#[test]
fn one_cell_tables_are_uniform() {
    let p = PiecewiseConstant1d::new(2.0, 6.0, &[3.5]).unwrap();
    let l = PiecewiseLinear1d::new(&[2.0, 6.0], &[3.5, 3.5]).unwrap();
    for k in 0..=64 {
        let u = (k as f64 / 64.0).min(ONE_BELOW);
        let x = 2.0 + 4.0 * u;
        assert_eq!(p.sample_1d(u), x.min(6f64.next_down()));
        assert!((l.sample_1d(u) - x).abs() < 1e-15 * 6.0);
        assert_eq!(p.pdf_1d(x.min(5.99)), 0.25);
        assert_eq!(p.sample_cell(u).0, 0);
    }
}

#[test]
fn out_of_range_u_stays_in_nonzero_cells() {
    // u is documented to be in [0, 1); values outside (or NaN) are clamped, never sent to a
    // zero cell at either end.
    let p = PiecewiseConstant1d::new(0.0, 1.0, &[0.0, 1.0, 2.0, 0.0]).unwrap();
    for u in [-1.0, 1.0, 2.0, NAN, INF, -INF] {
        let x = p.sample_1d(u);
        assert!(p.pdf_1d(x) > 0.0, "u = {u}: x = {x}");
    }
}

// ---------------------------------------------------------------------------------------------
// The 2-D table

/// A 2-D case: the table and its box.
struct Case2d {
    name: &'static str,
    lo: [f64; 2],
    hi: [f64; 2],
    width: usize,
    height: usize,
    values: Vec<f64>,
}

impl Case2d {
    fn pdf(&self) -> PiecewiseConstant2d {
        PiecewiseConstant2d::new(self.lo, self.hi, self.width, self.height, &self.values).unwrap()
    }

    fn sum(&self) -> f64 {
        self.values.iter().sum()
    }

    fn cell_size(&self) -> (f64, f64) {
        (
            (self.hi[0] - self.lo[0]) / self.width as f64,
            (self.hi[1] - self.lo[1]) / self.height as f64,
        )
    }

    /// The centre of cell `(i, j)`.
    fn centre(&self, i: usize, j: usize) -> [f64; 2] {
        let (w, h) = self.cell_size();
        [
            self.lo[0] + (i as f64 + 0.5) * w,
            self.lo[1] + (j as f64 + 0.5) * h,
        ]
    }
}

fn cases_2d() -> Vec<Case2d> {
    // A bright spot on a dim background, 1e4 : 1, like an environment map's sun.
    let spot: Vec<f64> = (0..16 * 16)
        .map(|k| {
            let (i, j) = ((k % 16) as f64 - 11.5, (k / 16) as f64 - 4.5);
            1.0 + 1e4 * (-(i * i + j * j)).exp()
        })
        .collect();
    vec![
        Case2d {
            name: "4x3 with zeros and a zero row",
            lo: [0.0, 0.0],
            hi: [2.0, 1.0],
            width: 4,
            height: 3,
            values: vec![1.0, 0.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 4.0, 0.0, 0.0, 5.0],
        },
        Case2d {
            name: "16x16 bright spot",
            lo: [-1.0, -2.0],
            hi: [1.0, 2.0],
            width: 16,
            height: 16,
            values: spot,
        },
        Case2d {
            name: "1x1",
            lo: [3.0, 4.0],
            hi: [5.0, 4.5],
            width: 1,
            height: 1,
            values: vec![2.0],
        },
        Case2d {
            name: "5x1 strip",
            lo: [0.0, 0.0],
            hi: [1.0, 1.0],
            width: 5,
            height: 1,
            values: vec![1.0, 2.0, 0.0, 4.0, 8.0],
        },
        Case2d {
            name: "1x6 column, huge box",
            lo: [-1e150, 0.0],
            hi: [1e150, 1e150],
            width: 1,
            height: 6,
            values: vec![1.0, 0.0, 3.0, 1e-3, 1e3, 7.0],
        },
        Case2d {
            name: "3x2 tiny box, extreme values",
            lo: [1e-150, -1e-150],
            hi: [4e-150, 1e-150],
            width: 3,
            height: 2,
            values: vec![1e300, 1e-300, 0.0, 5e299, 1e300, 2e300],
        },
    ]
}

#[test]
fn the_2d_table_integrates_to_one_and_is_the_table() {
    for case in cases_2d() {
        let p = case.pdf();
        assert_eq!((p.dims(), p.canonical_dims()), (2, 2));
        assert_eq!((p.width(), p.height()), (case.width, case.height));
        let (w, h) = case.cell_size();
        let mut total = 0.0;
        for j in 0..case.height {
            for i in 0..case.width {
                let value = case.values[j * case.width + i];
                let probability = value / case.sum();
                let density = p.pdf(&case.centre(i, j));
                // Density times area is the cell's share of the table, to rounding.
                assert!(
                    (density * w * h - probability).abs() <= 1e-14 * probability + 1e-300,
                    "{}: cell ({i}, {j}) density {density}",
                    case.name
                );
                assert!((p.cell_probability(i, j) - probability).abs() <= 1e-14 * probability);
                total += density * w * h;
            }
        }
        assert!((total - 1.0).abs() < 1e-13, "{}: total {total}", case.name);
        // The marginal is the rows' shares; a row of zeros has no conditional.
        for j in 0..case.height {
            let row: f64 = case.values[j * case.width..(j + 1) * case.width]
                .iter()
                .sum();
            let share = p.marginal().cell_probability(j);
            assert!((share - row / case.sum()).abs() <= 1e-14 * share + 1e-300);
            assert_eq!(p.conditional(j).is_none(), row == 0.0, "{}", case.name);
        }
    }
}

#[test]
fn the_2d_table_samples_follow_the_density() {
    // 2x2 bins in every cell, expected counts from the pdf at the bins' Gauss points (it is
    // constant on them, so a 2-point tensor rule integrates it exactly).
    const SAMPLES: usize = 400_000;
    for (c, case) in cases_2d().iter().enumerate() {
        let p = case.pdf();
        let (bx, by) = (2 * case.width, 2 * case.height);
        let (w, h) = (
            (case.hi[0] - case.lo[0]) / bx as f64,
            (case.hi[1] - case.lo[1]) / by as f64,
        );
        let g = 0.5 / 3f64.sqrt();
        let mut expected = vec![0.0; bx * by];
        for j in 0..by {
            for i in 0..bx {
                let mut integral = 0.0;
                for (sx, sy) in [(-g, -g), (-g, g), (g, -g), (g, g)] {
                    let x = case.lo[0] + (i as f64 + 0.5 + sx) * w;
                    let y = case.lo[1] + (j as f64 + 0.5 + sy) * h;
                    integral += 0.25 * p.pdf(&[x, y]) * w * h;
                }
                expected[j * bx + i] = SAMPLES as f64 * integral;
            }
        }
        let total = expected.iter().sum::<f64>() / SAMPLES as f64;
        assert!(
            (total - 1.0).abs() < 1e-12,
            "{}: bins hold {total}",
            case.name
        );

        let u = canonical(2, SAMPLES, 600 + c as u64);
        let mut observed = vec![0u64; bx * by];
        let (mut uu, mut x) = ([0.0; 2], [0.0; 2]);
        for k in 0..SAMPLES {
            u.copy_point(k, &mut uu);
            p.sample(&uu, &mut x);
            let bin = |d: usize, n: usize| {
                let t = (x[d] - case.lo[d]) / (case.hi[d] - case.lo[d]) * n as f64;
                assert!(
                    x[d] >= case.lo[d] && x[d] < case.hi[d],
                    "{}: sample {x:?} outside",
                    case.name
                );
                (t as usize).min(n - 1)
            };
            let (i, j) = (bin(0, bx), bin(1, by));
            observed[j * bx + i] += 1;
            assert!(
                p.pdf(&x) > 0.0,
                "{}: sample {x:?} has zero density",
                case.name
            );
        }
        assert_fits(case.name, &observed, &expected);
    }
}

proptest! {
    #![proptest_config(config(400, 20240605))]

    #[test]
    fn the_2d_table_inverts_its_samples(
        width in 1usize..8,
        height in 1usize..8,
        raw in prop::collection::vec(weight(), 64),
        box_lo in prop::array::uniform2(-1e3..1e3f64),
        log_size in prop::array::uniform2(-3.0..3.0f64),
        u in prop::array::uniform2(canonical_u()),
    ) {
        let mut values = raw[..width * height].to_vec();
        if values.iter().all(|&v| v == 0.0) {
            values[0] = 1.0;
        }
        let hi = [box_lo[0] + 10f64.powf(log_size[0]), box_lo[1] + 10f64.powf(log_size[1])];
        let p = PiecewiseConstant2d::new(box_lo, hi, width, height, &values).unwrap();
        let (mut x, mut back) = ([0.0; 2], [0.0; 2]);
        p.sample(&u, &mut x);
        p.invert(&x, &mut back).unwrap();
        // Each coordinate is a 1-D warp (marginal, then the row's conditional), so each round
        // trip has the 1-D tolerance with that warp's density.
        let row = p.marginal().cell_at(x[1]).unwrap();
        let conditional = p.conditional(row).unwrap();
        let densities = [conditional.pdf_1d(x[0]), p.marginal().pdf_1d(x[1])];
        for d in 0..2 {
            let tolerance = round_trip_tolerance(densities[d], x[d]);
            prop_assert!(
                (back[d] - u[d]).abs() <= tolerance,
                "dim {}: {:?} -> {:?} -> {:?}",
                d,
                u,
                x,
                back
            );
        }
        // Samples land only in cells of positive value, and the density is the product.
        let column = conditional.cell_at(x[0]).unwrap();
        prop_assert!(values[row * width + column] > 0.0);
        prop_assert_eq!(p.pdf(&x), densities[0] * densities[1]);
    }
}

#[test]
fn the_2d_table_keeps_stratification() {
    // N x N jittered u: u[1]'s stratum j must be the marginal cdf stratum of y, and u[0]'s
    // stratum i the stratum of x under the conditional cdf of y's row, both by the reference
    // cdfs written here. So each of the N^2 (marginal, conditional) equal-probability cells
    // holds exactly one sample.
    const N: usize = 40;
    for (c, case) in cases_2d().iter().enumerate() {
        let p = case.pdf();
        let row_sums: Vec<f64> = case
            .values
            .chunks_exact(case.width)
            .map(|r| r.iter().sum())
            .collect();
        let jitter = canonical(2, N * N, 700 + c as u64);
        let mut counts = vec![0u32; N * N];
        let (mut xi, mut x) = ([0.0; 2], [0.0; 2]);
        for k in 0..N * N {
            jitter.copy_point(k, &mut xi);
            let (i, j) = (k % N, k / N);
            let u = [(i as f64 + xi[0]) / N as f64, (j as f64 + xi[1]) / N as f64];
            p.sample(&u, &mut x);
            let fy = reference_table_cdf(case.lo[1], case.hi[1], &row_sums, x[1]);
            let row = (((x[1] - case.lo[1]) / (case.hi[1] - case.lo[1]) * case.height as f64)
                as usize)
                .min(case.height - 1);
            let cells = &case.values[row * case.width..(row + 1) * case.width];
            let fx = reference_table_cdf(case.lo[0], case.hi[0], cells, x[0]);
            let (si, sj) = ((fx * N as f64) as usize, (fy * N as f64) as usize);
            assert_eq!((si, sj), (i, j), "{}: u = {u:?}, x = {x:?}", case.name);
            counts[sj * N + si] += 1;
        }
        assert!(counts.iter().all(|&k| k == 1), "{}", case.name);
    }
}

#[test]
fn the_2d_density_vanishes_outside_and_in_zero_cells() {
    let case = &cases_2d()[0];
    let p = case.pdf();
    for x in [
        [-0.1, 0.5],
        [2.0, 0.5],
        [1.0, -1e-300],
        [1.0, 1.0],
        [NAN, 0.5],
        [1.0, NAN],
        [INF, 0.5],
        [1.0, -INF],
    ] {
        assert_eq!(p.pdf(&x), 0.0, "pdf({x:?})");
    }
    for j in 0..case.height {
        for i in 0..case.width {
            if case.values[j * case.width + i] == 0.0 {
                assert_eq!(p.pdf(&case.centre(i, j)), 0.0, "cell ({i}, {j})");
            }
        }
    }
    // invert clamps points outside the box to the cdf's ends.
    let mut u = [0.5; 2];
    p.invert(&[-5.0, -5.0], &mut u).unwrap();
    assert_eq!(u, [0.0, 0.0]);
    p.invert(&[5.0, 5.0], &mut u).unwrap();
    assert_eq!(u, [1.0, 1.0]);
}

// ---------------------------------------------------------------------------------------------
// The alias table

fn alias_weight_sets() -> Vec<(&'static str, Vec<f64>)> {
    vec![
        ("uniform 10", vec![1.0; 10]),
        ("geometric 40", (0..40).map(|i| 0.7f64.powi(i)).collect()),
        ("with zeros", vec![0.0, 3.0, 0.0, 1.0, 0.0, 0.0, 6.0, 0.0]),
        ("single", vec![2.5]),
        ("one heavy", {
            let mut w = vec![1e-3; 50];
            w[17] = 1e3;
            w
        }),
        ("random 1000", random_weights(1000, 88, 7)),
        ("extreme", vec![1e-300, 1e300, 5e299, 0.0, 1e299]),
    ]
}

#[test]
fn alias_probabilities_are_the_weights() {
    for (name, weights) in alias_weight_sets() {
        let t = AliasTable::new(&weights).unwrap();
        assert_eq!(t.len(), weights.len());
        assert!(!t.is_empty());
        let sum: f64 = weights.iter().sum();
        for (i, w) in weights.iter().enumerate() {
            assert_eq!(t.probability(i), w / sum, "{name}: {i}");
        }
        assert_eq!(t.probability(weights.len()), 0.0);
        assert_eq!(t.probabilities().len(), weights.len());
    }
}

#[test]
fn alias_samples_follow_the_probabilities() {
    const SAMPLES: usize = 1_000_000;
    for (k, (name, weights)) in alias_weight_sets().into_iter().enumerate() {
        if weights.len() < 2 {
            continue;
        }
        let t = AliasTable::new(&weights).unwrap();
        let u = canonical(1, SAMPLES, 800 + k as u64);
        let mut observed = vec![0u64; weights.len()];
        for &u in u.column(0) {
            observed[t.sample(u).0] += 1;
        }
        let expected: Vec<f64> = weights
            .iter()
            .map(|w| w / weights.iter().sum::<f64>() * SAMPLES as f64)
            .collect();
        for (i, w) in weights.iter().enumerate() {
            if *w == 0.0 {
                assert_eq!(observed[i], 0, "{name}: zero weight {i} sampled");
            }
        }
        assert_fits(name, &observed, &expected);
    }
}

#[test]
fn alias_remapped_u_is_uniform_and_independent_of_the_index() {
    // Joint histogram of (index, remapped u in 10 bins): if the remapped u is uniform and
    // independent of the index, each cell expects p_i / 10 of the samples.
    const SAMPLES: usize = 1_000_000;
    const BINS: usize = 10;
    for (k, (name, weights)) in alias_weight_sets().into_iter().enumerate() {
        if weights.len() > 100 {
            continue;
        }
        let t = AliasTable::new(&weights).unwrap();
        let u = canonical(1, SAMPLES, 900 + k as u64);
        let mut observed = vec![0u64; weights.len() * BINS];
        for &u in u.column(0) {
            let (i, v) = t.sample(u);
            assert!((0.0..1.0).contains(&v), "{name}: remapped {v}");
            observed[i * BINS + (v * BINS as f64) as usize] += 1;
        }
        let expected: Vec<f64> = (0..weights.len() * BINS)
            .map(|c| t.probability(c / BINS) * SAMPLES as f64 / BINS as f64)
            .collect();
        if weights.len() == 1 {
            // One outcome: the remapped u is u itself.
            assert_eq!(t.sample(0.3), (0, 0.3));
        }
        assert_fits(name, &observed, &expected);
    }
}

#[test]
fn alias_with_evenly_spaced_u_is_balanced_to_the_derived_bound() {
    // With u_j = (j + 1/2) / (N K), j < N K, bin b = floor(u N) receives exactly K points, at
    // fractions f_m = (m + 1/2) / K, m < K. The bin gives its own index to the c of them with
    // f_m < q_b and the alias to the other K - c, and c = #{m : m + 1/2 < q_b K} lies within
    // 1/2 of q_b K (likewise K - c of (1 - q_b) K). The expected count of index i, N K p_i, is
    // K times i's shares summed over the bins where it has one, so
    //     |count_i - N K p_i| <= m_i / 2 <= N / 2,
    // where m_i is the number of bins in which i has a share (at most N), and, since each bin
    // contributes two errors of opposite sign and size at most 1/2,
    //     sum_i |count_i - N K p_i| <= N.
    // With K >= N / 2 every count is therefore within K of its expectation. Rounding (of u_j,
    // of u N, and of the table's thresholds, each ~N * 1e-16 relative) adds at most 1e-6 here.
    // Each bin's K points also form at most two runs: own index first, then its alias.
    for (name, weights) in alias_weight_sets() {
        let n = weights.len();
        let t = AliasTable::new(&weights).unwrap();
        let k_per_bin = n.div_ceil(2).max(64);
        let total = n * k_per_bin;
        let mut counts = vec![0u64; n];
        for b in 0..n {
            let mut runs: Vec<usize> = Vec::new();
            for m in 0..k_per_bin {
                let j = b * k_per_bin + m;
                let (i, _) = t.sample((j as f64 + 0.5) / total as f64);
                counts[i] += 1;
                if runs.last() != Some(&i) {
                    runs.push(i);
                }
            }
            assert!(runs.len() <= 2, "{name}: bin {b} gave indices {runs:?}");
        }
        let mut sum_abs = 0.0;
        for (i, &count) in counts.iter().enumerate() {
            let expected = total as f64 * t.probability(i);
            let error = (count as f64 - expected).abs();
            assert!(
                error <= n as f64 / 2.0 + 1e-6,
                "{name}: index {i} count {count} expected {expected}"
            );
            assert!(error <= k_per_bin as f64 + 1e-6);
            sum_abs += error;
        }
        assert!(sum_abs <= n as f64 + 1e-6, "{name}: total error {sum_abs}");
    }
}

#[test]
fn alias_table_as_a_pdf_uses_counting_measure() {
    let weights = [0.0, 3.0, 0.0, 1.0];
    let t = AliasTable::new(&weights).unwrap();
    assert_eq!((t.dims(), t.canonical_dims()), (1, 1));
    let mut x = [0.0];
    for k in 0..100 {
        let u = k as f64 / 100.0;
        Pdf::sample(&t, &[u], &mut x);
        assert_eq!(x[0], t.sample(u).0 as f64);
        assert_eq!(t.pdf(&x), t.probability(x[0] as usize));
        assert!(t.pdf(&x) > 0.0);
    }
    // The density sums to one over the integers, and is zero elsewhere.
    let total: f64 = (0..4).map(|i| t.pdf(&[i as f64])).sum();
    assert_eq!(total, 1.0);
    for x in [
        0.5,
        -1.0,
        4.0,
        1e300,
        -0.0 - 1e-300,
        NAN,
        INF,
        -INF,
        1.0 + 1e-15,
    ] {
        assert_eq!(t.pdf(&[x]), 0.0, "pdf({x})");
    }
    // The warp has no inverse: invert keeps the trait's error.
    let mut u = [0.0];
    match t.invert(&[1.0], &mut u) {
        Err(Error::Unsupported { operation, .. }) => assert_eq!(operation, "invert"),
        other => panic!("expected the default invert error, got {other:?}"),
    }
    // The estimator f(x) / pdf(x) of sum_i f(i) is exact for f proportional to the weights.
    let f = |i: f64| 2.0 * weights[i as usize];
    for k in 0..10 {
        Pdf::sample(&t, &[k as f64 / 10.0], &mut x);
        assert!((f(x[0]) / t.pdf(&x) - 8.0).abs() < 1e-14);
    }
}

#[test]
fn alias_handles_out_of_range_u() {
    let t = AliasTable::new(&[0.0, 1.0, 0.0, 2.0, 0.0]).unwrap();
    for u in [0.0, ONE_BELOW, 1.0, 2.0, -1.0, NAN, INF, -INF] {
        let (i, v) = t.sample(u);
        assert!(t.probability(i) > 0.0, "u = {u}: index {i}");
        assert!((0.0..1.0).contains(&v), "u = {u}: remapped {v}");
    }
}

// ---------------------------------------------------------------------------------------------
// Parameters

#[test]
fn constructors_reject_bad_parameters_by_name() {
    let normal = |m, s| named(Normal::new(m, s).unwrap_err());
    assert_eq!(normal(NAN, 1.0), "mean");
    assert_eq!(normal(INF, 1.0), "mean");
    assert_eq!(normal(0.0, 0.0), "sd");
    assert_eq!(normal(0.0, -1.0), "sd");
    assert_eq!(normal(0.0, NAN), "sd");
    assert_eq!(normal(0.0, INF), "sd");
    assert_eq!(normal(0.0, 1e-310), "sd"); // peak density overflows
    assert_eq!(normal(1e308, 1e307), "sd"); // samples would overflow
    assert!(Normal::new(1e300, 1e298).is_ok());

    let tent = |a, c, b| named(Tent::new(a, c, b).unwrap_err());
    assert_eq!(tent(NAN, 0.0, 1.0), "a");
    assert_eq!(tent(-INF, 0.0, 1.0), "a");
    assert_eq!(tent(0.0, 0.0, 0.0), "b");
    assert_eq!(tent(1.0, 0.5, 0.0), "b");
    assert_eq!(tent(0.0, 0.5, INF), "b");
    assert_eq!(tent(-f64::MAX, 0.0, f64::MAX), "b"); // b - a overflows
    assert_eq!(tent(0.0, 0.0, 1e-310), "b"); // the peak overflows
    assert_eq!(tent(0.0, 2.0, 1.0), "c");
    assert_eq!(tent(0.0, -1.0, 1.0), "c");
    assert_eq!(tent(0.0, NAN, 1.0), "c");
    let symmetric = |c, r| named(Tent::symmetric(c, r).unwrap_err());
    assert_eq!(symmetric(NAN, 1.0), "center");
    assert_eq!(symmetric(INF, 1.0), "center");
    assert_eq!(symmetric(0.0, 0.0), "radius");
    assert_eq!(symmetric(0.0, -1.0), "radius");
    assert_eq!(symmetric(0.0, NAN), "radius");
    assert_eq!(symmetric(0.0, INF), "radius");
    assert_eq!(symmetric(1e9, 1e-9), "radius"); // center +- radius round to center
    assert_eq!(symmetric(f64::MAX, f64::MAX / 2.0), "radius");

    let constant = |a, b, w: &[f64]| named(PiecewiseConstant1d::new(a, b, w).unwrap_err());
    assert_eq!(constant(0.0, 1.0, &[]), "weights");
    assert_eq!(constant(0.0, 1.0, &[0.0, 0.0]), "weights");
    assert_eq!(constant(0.0, 1.0, &[1.0, -1.0]), "weights");
    assert_eq!(constant(0.0, 1.0, &[1.0, -0.0 - 1e-300]), "weights");
    assert_eq!(constant(0.0, 1.0, &[NAN]), "weights");
    assert_eq!(constant(0.0, 1.0, &[1.0, INF]), "weights");
    assert_eq!(constant(0.0, 1.0, &[f64::MAX, f64::MAX]), "weights");
    assert_eq!(constant(1.0, 1.0, &[1.0]), "b");
    assert_eq!(constant(NAN, 1.0, &[1.0]), "a");
    assert_eq!(constant(0.0, INF, &[1.0]), "b");
    // More cells than floats in the interval.
    assert_eq!(constant(1.0, 1.0 + 4.0 * f64::EPSILON, &[1.0; 16]), "b");
    // -0.0 is a weight of zero, which is allowed.
    assert!(PiecewiseConstant1d::new(0.0, 1.0, &[-0.0, 1.0]).is_ok());

    let linear = |x: &[f64], v: &[f64]| named(PiecewiseLinear1d::new(x, v).unwrap_err());
    assert_eq!(linear(&[], &[]), "xs");
    assert_eq!(linear(&[0.0], &[1.0]), "xs");
    assert_eq!(linear(&[0.0, 0.0], &[1.0, 1.0]), "xs");
    assert_eq!(linear(&[1.0, 0.0], &[1.0, 1.0]), "xs");
    assert_eq!(linear(&[0.0, NAN], &[1.0, 1.0]), "xs");
    assert_eq!(linear(&[0.0, INF], &[1.0, 1.0]), "xs");
    assert_eq!(linear(&[-f64::MAX, f64::MAX], &[1.0, 1.0]), "xs");
    assert_eq!(linear(&[0.0, 5e-324], &[1.0, 1.0]), "xs"); // the density overflows
    assert_eq!(linear(&[0.0, 1.0], &[1.0]), "values");
    assert_eq!(linear(&[0.0, 1.0], &[1.0, 2.0, 3.0]), "values");
    assert_eq!(linear(&[0.0, 1.0], &[1.0, -2.0]), "values");
    assert_eq!(linear(&[0.0, 1.0], &[NAN, 2.0]), "values");
    assert_eq!(linear(&[0.0, 1.0], &[INF, 2.0]), "values");
    assert_eq!(linear(&[0.0, 1.0], &[0.0, 0.0]), "values");

    let table =
        |lo, hi, w, h, v: &[f64]| named(PiecewiseConstant2d::new(lo, hi, w, h, v).unwrap_err());
    let (lo, hi) = ([0.0, 0.0], [1.0, 1.0]);
    assert_eq!(table(lo, hi, 0, 1, &[]), "width");
    assert_eq!(table(lo, hi, 1, 0, &[]), "height");
    assert_eq!(table(lo, hi, 2, 2, &[1.0; 3]), "values");
    assert_eq!(table(lo, hi, usize::MAX, 2, &[1.0; 2]), "values");
    assert_eq!(table(lo, hi, 2, 1, &[0.0, 0.0]), "values");
    assert_eq!(table(lo, hi, 2, 1, &[1.0, NAN]), "values");
    assert_eq!(table(lo, hi, 2, 1, &[1.0, -1.0]), "values");
    assert_eq!(table(lo, hi, 1, 2, &[f64::MAX, f64::MAX]), "values");
    assert_eq!(table([0.0, 1.0], [1.0, 1.0], 1, 1, &[1.0]), "y range");
    assert_eq!(table([0.0, NAN], [1.0, 1.0], 1, 1, &[1.0]), "y range");
    assert_eq!(table([2.0, 0.0], [1.0, 1.0], 1, 1, &[1.0]), "x range");
    assert_eq!(table([0.0, 0.0], [INF, 1.0], 1, 1, &[1.0]), "x range");
    // Each side's cells have a finite density, their product does not.
    assert_eq!(table([0.0, 0.0], [1e-200, 1e-200], 1, 1, &[1.0]), "box");

    let alias = |w: &[f64]| named(AliasTable::new(w).unwrap_err());
    assert_eq!(alias(&[]), "weights");
    assert_eq!(alias(&[0.0]), "weights");
    assert_eq!(alias(&[1.0, -2.0]), "weights");
    assert_eq!(alias(&[NAN]), "weights");
    assert_eq!(alias(&[-INF, 1.0]), "weights");
    assert_eq!(alias(&[f64::MAX, f64::MAX]), "weights");

    // Messages say what was wrong and what is allowed.
    let message = PiecewiseConstant1d::new(0.0, 1.0, &[1.0, -2.0])
        .unwrap_err()
        .to_string();
    assert_eq!(
        message,
        "invalid weights = -2 at index 1: expected finite weights >= 0"
    );
    let message = AliasTable::new(&[0.0, 0.0]).unwrap_err().to_string();
    assert!(
        message.contains("at least one positive weight"),
        "{message}"
    );
    let message = AliasTable::new(&[]).unwrap_err().to_string();
    assert!(message.contains("non-empty"), "{message}");
    let message = AliasTable::new(&[f64::MAX, f64::MAX])
        .unwrap_err()
        .to_string();
    assert!(message.contains("finite sum"), "{message}");
    let message = Tent::new(0.0, 2.0, 1.0).unwrap_err().to_string();
    assert!(message.starts_with("invalid c = 2"), "{message}");
}

/// Any f64, weighted toward the troublesome ones.
fn absurd() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(NAN),
        Just(INF),
        Just(-INF),
        Just(0.0),
        Just(-0.0),
        Just(f64::MAX),
        Just(-f64::MAX),
        Just(f64::MIN_POSITIVE),
        Just(5e-324),
        Just(1.0),
        -10.0..10.0f64,
        any::<f64>(),
    ]
}

fn absurd_vec() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(absurd(), 0..6)
}

/// An `Err` must name one of `allowed`.
fn check_error<T>(result: &Result<T, Error>, allowed: &[&str]) -> Result<(), TestCaseError> {
    if let Err(e) = result {
        let name = named(e.clone());
        prop_assert!(allowed.contains(&name), "error names {}: {}", name, e);
    }
    Ok(())
}

/// A 1-D pdf that was accepted samples finite points of its support with finite densities, and
/// inverts to `[0, 1]`.
fn check_usable(pdf: &dyn Pdf1d) -> Result<(), TestCaseError> {
    let (a, b) = pdf.support();
    for u in [0.0, 0.3, 0.5, ONE_BELOW] {
        let x = pdf.sample_1d(u);
        prop_assert!(x.is_finite() && a <= x && x <= b, "sample({}) = {}", u, x);
        let density = pdf.pdf_1d(x);
        prop_assert!(
            density.is_finite() && density >= 0.0,
            "pdf({}) = {}",
            x,
            density
        );
        let back = pdf.invert_1d(x);
        prop_assert!((0.0..=1.0).contains(&back), "invert({}) = {}", x, back);
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(2000, 20240605))]

    #[test]
    fn constructors_never_panic_on_absurd_input(
        p in prop::array::uniform4(absurd()),
        v in absurd_vec(),
        w in absurd_vec(),
        dims in prop::array::uniform2(0usize..4),
    ) {
        let normal = Normal::new(p[0], p[1]);
        check_error(&normal, &["mean", "sd"])?;
        if let Ok(n) = &normal {
            check_usable(n)?;
        }
        let tent = Tent::new(p[0], p[1], p[2]);
        check_error(&tent, &["a", "b", "c"])?;
        if let Ok(t) = &tent {
            check_usable(t)?;
        }
        let symmetric = Tent::symmetric(p[2], p[3]);
        check_error(&symmetric, &["center", "radius"])?;
        if let Ok(t) = &symmetric {
            check_usable(t)?;
        }
        let constant = PiecewiseConstant1d::new(p[0], p[1], &v);
        check_error(&constant, &["a", "b", "weights"])?;
        if let Ok(c) = &constant {
            check_usable(c)?;
            prop_assert!(c.pdf_1d(c.sample_1d(0.5)) > 0.0);
        }
        let linear = PiecewiseLinear1d::new(&v, &w);
        check_error(&linear, &["xs", "values"])?;
        if let Ok(l) = &linear {
            check_usable(l)?;
        }
        let (width, height) = (dims[0], dims[1]);
        let table = PiecewiseConstant2d::new([p[0], p[1]], [p[2], p[3]], width, height, &v);
        check_error(&table, &["width", "height", "values", "x range", "y range", "box"])?;
        if let Ok(t) = &table {
            let mut x = [0.0; 2];
            t.sample(&[0.5, 0.5], &mut x);
            prop_assert!(x[0] >= p[0] && x[0] < p[2] && x[1] >= p[1] && x[1] < p[3]);
            let density = t.pdf(&x);
            prop_assert!(density.is_finite() && density >= 0.0);
        }
        let alias = AliasTable::new(&v);
        check_error(&alias, &["weights"])?;
        if let Ok(a) = &alias {
            for u in [0.0, 0.5, ONE_BELOW] {
                let (i, r) = a.sample(u);
                prop_assert!(a.probability(i) > 0.0 && (0.0..1.0).contains(&r));
            }
        }
    }
}
