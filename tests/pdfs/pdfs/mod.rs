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

mod density;
mod invert;
mod parameters;
mod truncated_normal_tails;

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
// Helpers that more than one of the modules above use

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
