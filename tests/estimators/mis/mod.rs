//! Multiple importance sampling, mixtures and the product case of importance sampling (the
//! seed's A.19, A.25 and its MIS section; Veach & Guibas 1995; Veach 1997, chapter 9):
//!
//! - the heuristics' weights lie in [0, 1] and sum to one (proptest);
//! - every estimator is unbiased: the mean of many contributions is within 4.5 standard errors
//!   of closed-form integrals (false-alarm probability about 7e-6 per check);
//! - the balance heuristic obeys Veach's Theorem 9.2, `V[F_balance] <= V[F_w] + (1/min n_i -
//!   1/sum n_i) F^2`, on variances computed exactly by quadrature (the quadrature is checked
//!   against the estimators' sample variances), and is optimal in the one-sample model;
//! - on a sharp lobe times a broad lobe, MIS beats both single techniques many times over;
//! - one-sample MIS with the balance heuristic is importance sampling from the mixture;
//! - mixtures integrate to one and pass chi-square goodness-of-fit tests (p > 1e-5);
//! - bad input gives errors naming the field; broken pdfs and weights that do not sum to one
//!   make the `Integrator` fail with the count and the first offending point.
//!
//! All randomness comes from fixed seeds.

use crate::common::{ONE_BELOW, config, integrate};
use mcint::estimator::{
    Estimator, ImportanceEstimator, MisHeuristic, MisWeighting, MultiSampleMis, OneSampleMis,
    ProductImportanceEstimator,
};
use mcint::pdf::{
    Exponential, Linear, Mixture, Pdf, Pdf1d, ProductPdf, TruncatedNormal, UniformBox,
    UniformInterval,
};
use mcint::sampler::{Independent, Sampler};
use mcint::stats::{Accumulator, chi_square_goodness_of_fit};
use mcint::{Error, Integrator, Points};
use proptest::prelude::*;

mod errors;
mod heuristic_weights;
mod mixture;
mod unbiasedness;
mod variance;

/// The heuristics under test, with Veach's power exponent and two others.
fn heuristics() -> Vec<MisHeuristic> {
    vec![
        MisHeuristic::Balance,
        MisHeuristic::power(2.0).unwrap(),
        MisHeuristic::power(0.5).unwrap(),
        MisHeuristic::Maximum,
        MisHeuristic::cutoff(0.2).unwrap(),
    ]
}

// ---------------------------------------------------------------------------------------------
// Quadrature (Gauss-Legendre, written here so that the reference does not share code with the
// library)

/// Tensor-product Gauss-Legendre over a rectangle, `panels` per axis.
fn integrate_2d(f: impl Fn(&[f64]) -> f64, lo: [f64; 2], hi: [f64; 2], panels: usize) -> f64 {
    integrate(
        |y| integrate(|x| f(&[x, y]), lo[0], hi[0], panels),
        lo[1],
        hi[1],
        panels,
    )
}

#[test]
fn quadrature_is_exact_where_theory_says() {
    assert!((integrate(|x| x.powi(23), 0.0, 1.0, 1) - 1.0 / 24.0).abs() < 1e-15);

    assert!((integrate(f64::exp, 0.0, 1.0, 4) - (1f64.exp() - 1.0)).abs() < 1e-15);
    let area = integrate_2d(|x| x[0] * x[1], [0.0, 0.0], [2.0, 3.0], 1);
    assert!((area - 9.0).abs() < 1e-13);
}

// ---------------------------------------------------------------------------------------------
// Sampling helpers

/// `n` contributions of an estimator from the independent sampler with a fixed seed.
fn contributions<E: Estimator>(estimator: &E, n: usize, seed: u64) -> Vec<f64> {
    let dims = estimator.canonical_dims();
    let sampler = Independent::new(dims, seed).unwrap();
    let block = 4096;
    let mut points = Points::new(dims, block).unwrap();
    let mut out = vec![0.0; n];
    for (b, chunk) in out.chunks_mut(block).enumerate() {
        points.set_len(chunk.len());
        sampler.fill((b * block) as u64, &mut points).unwrap();
        estimator.contributions(&points, chunk);
    }
    out
}

fn summary(values: &[f64]) -> Accumulator {
    let mut acc = Accumulator::new();
    acc.extend(values);
    assert_eq!(acc.non_finite(), 0, "non-finite contributions");
    acc
}

/// Sample variance and its standard error, `sqrt((m4 - s^4) / n)` for large `n`.
fn variance_and_its_se(values: &[f64]) -> (f64, f64) {
    let acc = summary(values);
    let s2 = acc.variance();
    let m4 = values.iter().map(|v| (v - acc.mean()).powi(4)).sum::<f64>() / values.len() as f64;
    (s2, ((m4 - s2 * s2) / values.len() as f64).sqrt())
}

/// Asserts that the mean of `n` contributions is within 4.5 standard errors of `exact`.
fn assert_unbiased<E: Estimator>(name: &str, estimator: &E, exact: f64, n: usize, seed: u64) {
    let acc = summary(&contributions(estimator, n, seed));
    let se = (acc.variance() / n as f64).sqrt();
    assert!(
        (acc.mean() - exact).abs() <= 4.5 * se + 1e-13 * exact.abs(),
        "{name}: mean {} vs exact {exact} (se {se:e})",
        acc.mean()
    );
}

/// The field an error names: the parameter of `InvalidParameter`, the first word of a
/// `DimensionMismatch`'s `what`.
fn field(err: Error) -> String {
    match err {
        Error::InvalidParameter { name, .. } => name.to_string(),
        Error::DimensionMismatch { what, .. } => what.split(' ').next().unwrap().to_string(),
        Error::Unsupported { operation, .. } => operation.to_string(),
        other => panic!("unexpected error {other}"),
    }
}

// ---------------------------------------------------------------------------------------------
// Integrands with closed-form integrals, and their techniques

/// Rate of the sharp lobe, its floor and the broad lobe `h(x) = 0.1 + 1.9 x` on [0, 1].
const RATE: f64 = 10.0;
const FLOOR: f64 = 0.3;

fn sharp_lobe() -> Exponential {
    Exponential::new(RATE, 0.0, 1.0).unwrap()
}

fn broad_lobe() -> Linear {
    Linear::new(0.0, 1.0, 0.1, 2.0).unwrap()
}

fn h_broad(x: f64) -> f64 {
    0.1 + 1.9 * x
}

/// `f = g h` with `g` a sharp exponential lobe (rate 10, normalised) plus a floor of 0.3 (like a
/// glossy reflectance lobe on a diffuse base) and `h` the broad linear lobe.
fn sharp_times_broad(x: &[f64]) -> f64 {
    (sharp_lobe().pdf_1d(x[0]) + FLOOR) * h_broad(x[0])
}

/// `integral_0^1 (p_lobe + floor) h = 0.1 + 1.9 E_lobe[X] + floor (0.1 + 0.95)`, with the mean
/// of the truncated exponential `E[X] = 1/r - e^-r / (1 - e^-r)`.
fn sharp_times_broad_integral() -> f64 {
    let mean = 1.0 / RATE - (-RATE).exp() / -(-RATE).exp_m1();
    0.1 + 1.9 * mean + FLOOR * 1.05
}

fn sharp_techniques() -> Vec<Box<dyn Pdf>> {
    vec![Box::new(sharp_lobe()), Box::new(broad_lobe())]
}

/// `f(x) = 1 + x`, exactly proportional to the first technique (F = 1.5).
fn one_plus_x(x: &[f64]) -> f64 {
    1.0 + x[0]
}

fn perfect_techniques() -> Vec<Box<dyn Pdf>> {
    vec![
        Box::new(Linear::new(0.0, 1.0, 1.0, 2.0).unwrap()),
        Box::new(TruncatedNormal::new(0.8, 0.15, 0.0, 1.0).unwrap()),
    ]
}

/// `f(x) = e^{-3x} + 2 x^2` on [0, 1]: `(1 - e^-3) / 3 + 2/3`.
fn exp_plus_square(x: &[f64]) -> f64 {
    (-3.0 * x[0]).exp() + 2.0 * x[0] * x[0]
}

fn exp_plus_square_integral() -> f64 {
    -(-3f64).exp_m1() / 3.0 + 2.0 / 3.0
}

fn three_techniques() -> Vec<Box<dyn Pdf>> {
    vec![
        Box::new(Exponential::new(3.0, 0.0, 1.0).unwrap()),
        Box::new(Linear::new(0.0, 1.0, 0.2, 1.0).unwrap()),
        Box::new(UniformInterval::new(0.0, 1.0).unwrap()),
    ]
}

/// `f(x, y) = e^{-x-y} (1 + x y)` on the unit square: `(1 - 1/e)^2 + (1 - 2/e)^2`.
fn exp_2d(x: &[f64]) -> f64 {
    (-x[0] - x[1]).exp() * (1.0 + x[0] * x[1])
}

fn exp_2d_integral() -> f64 {
    let e = 1f64.exp();
    (1.0 - 1.0 / e).powi(2) + (1.0 - 2.0 / e).powi(2)
}

fn techniques_2d() -> Vec<Box<dyn Pdf>> {
    let exponential = || -> Box<dyn Pdf1d> { Box::new(Exponential::new(1.0, 0.0, 1.0).unwrap()) };
    let linear = || -> Box<dyn Pdf1d> { Box::new(Linear::new(0.0, 1.0, 1.0, 2.0).unwrap()) };
    vec![
        Box::new(ProductPdf::new(vec![exponential(), exponential()]).unwrap()),
        Box::new(ProductPdf::new(vec![linear(), linear()]).unwrap()),
        // A defensive mixture as a technique: canonical dims 2, as the others.
        Box::new(
            Mixture::defensive(
                Box::new(ProductPdf::new(vec![exponential(), linear()]).unwrap()),
                UniformBox::unit(2).unwrap(),
                0.2,
            )
            .unwrap(),
        ),
    ]
}

type Integrand = fn(&[f64]) -> f64;

/// An integrand, its integral, and a factory for its techniques.
#[derive(Clone, Copy)]
struct Problem {
    name: &'static str,
    f: Integrand,
    exact: f64,
    techniques: fn() -> Vec<Box<dyn Pdf>>,
}

fn problems() -> Vec<Problem> {
    vec![
        Problem {
            name: "sharp x broad",
            f: sharp_times_broad,
            exact: sharp_times_broad_integral(),
            techniques: sharp_techniques,
        },
        Problem {
            name: "1 + x",
            f: one_plus_x,
            exact: 1.5,
            techniques: perfect_techniques,
        },
        Problem {
            name: "exp + square",
            f: exp_plus_square,
            exact: exp_plus_square_integral(),
            techniques: three_techniques,
        },
        Problem {
            name: "2-D exponential",
            f: exp_2d,
            exact: exp_2d_integral(),
            techniques: techniques_2d,
        },
    ]
}

#[test]
fn closed_forms_match_quadrature() {
    // Guards the reference integrals themselves.
    let sharp = integrate(|x| sharp_times_broad(&[x]), 0.0, 1.0, 200);
    assert!((sharp - sharp_times_broad_integral()).abs() < 1e-13);
    let eps = integrate(|x| exp_plus_square(&[x]), 0.0, 1.0, 50);
    assert!((eps - exp_plus_square_integral()).abs() < 1e-14);
    let e2 = integrate_2d(exp_2d, [0.0, 0.0], [1.0, 1.0], 10);
    assert!((e2 - exp_2d_integral()).abs() < 1e-14);
}

// ---------------------------------------------------------------------------------------------
// Helpers that more than one of the modules above use

/// Sample counts for `t` techniques: unequal, so that `n_i` enters the weights.
fn counts(t: usize) -> Vec<usize> {
    [1, 3, 2][..t].to_vec()
}

/// Selection probabilities for `t` techniques.
fn probabilities(t: usize) -> Vec<f64> {
    match t {
        2 => vec![0.3, 0.7],
        _ => vec![0.2, 0.5, 0.3],
    }
}
