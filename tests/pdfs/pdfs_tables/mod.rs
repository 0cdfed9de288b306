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

mod alias_table;
mod density;
mod invert;
mod parameters;
mod precision;
mod table_2d;

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
// Helpers that more than one of the modules above use

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

/// Round-trip tolerance for `invert(sample(u)) = u`: the sample is a float, rounded by a few
/// ulps (clamps to half-open cells move it by one), which moves the cdf by `pdf(x)` per unit
/// of x; the cdf arithmetic adds a few ulps of u, well inside the 1e-12 floor.
fn round_trip_tolerance(density: f64, x: f64) -> f64 {
    1e-12 + 4.0 * density * (x.abs().next_up() - x.abs())
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
