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
// Heuristics

/// A density value anywhere in the f64 range, or exactly zero.
fn density() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        0.0..10.0f64,
        (-300.0..300.0f64).prop_map(|e| 10f64.powf(e)),
    ]
}

fn heuristic() -> impl Strategy<Value = MisHeuristic> {
    prop_oneof![
        Just(MisHeuristic::Balance),
        Just(MisHeuristic::Maximum),
        Just(MisHeuristic::Power { beta: 2.0 }),
        (0.01..50.0f64).prop_map(|beta| MisHeuristic::Power { beta }),
        (0.0..=1.0f64).prop_map(|alpha| MisHeuristic::Cutoff { alpha }),
        Just(MisHeuristic::Cutoff { alpha: 1.0 }),
    ]
}

proptest! {
    #![proptest_config(config(2000, 0x915))]

    /// Every heuristic gives weights in [0, 1] summing to one wherever some q_j > 0, also
    /// with ties (the repeated entry) and with densities across the whole f64 range.
    #[test]
    fn heuristic_weights_sum_to_one(
        mut q in prop::collection::vec(density(), 1..8),
        repeat in any::<prop::sample::Index>(),
        h in heuristic(),
    ) {
        let copy = q[repeat.index(q.len())];
        q.push(copy);
        prop_assume!(q.iter().any(|&v| v > 0.0));
        prop_assert!(h.check().is_ok());
        let mut w = vec![0.0; q.len()];
        h.weights(&q, &mut w);
        for (j, &wj) in w.iter().enumerate() {
            prop_assert!((0.0..=1.0).contains(&wj), "{:?}: w[{}] = {} for q = {:?}", h, j, wj, q);
            prop_assert_eq!(wj, h.weight(j, &q));
            // The trait method (used by the estimators) is the same function.
            prop_assert_eq!(wj, MisWeighting::weight(&h, j, &[0.5], &q));
        }
        let sum: f64 = w.iter().sum();
        prop_assert!((sum - 1.0).abs() <= 1e-14, "{:?}: weights {:?} sum to {} for q = {:?}", h, w, sum, q);
    }

    /// The weights depend on ratios of densities only, and the heuristics meet where the
    /// theory says: power 1 and cutoff 0 are the balance heuristic, cutoff 1 the maximum.
    #[test]
    fn heuristics_are_scale_free_and_nest(
        q in prop::collection::vec(0.01..100.0f64, 1..6),
        scale_exponent in -100.0..100.0f64,
        h in heuristic(),
    ) {
        let scale = 10f64.powf(scale_exponent);
        let scaled: Vec<f64> = q.iter().map(|v| v * scale).collect();
        for j in 0..q.len() {
            let (a, b) = (h.weight(j, &q), h.weight(j, &scaled));
            prop_assert!((a - b).abs() <= 1e-13, "{:?}: {} vs {} after scaling by {:e}", h, a, b, scale);
            let balance = MisHeuristic::Balance.weight(j, &q);
            let power_one = MisHeuristic::Power { beta: 1.0 }.weight(j, &q);
            let cutoff_zero = MisHeuristic::Cutoff { alpha: 0.0 }.weight(j, &q);
            prop_assert!((power_one - balance).abs() <= 1e-15, "power 1: {} vs {}", power_one, balance);
            prop_assert!((cutoff_zero - balance).abs() <= 1e-15, "cutoff 0: {} vs {}", cutoff_zero, balance);
            prop_assert_eq!(MisHeuristic::Cutoff { alpha: 1.0 }.weight(j, &q), MisHeuristic::Maximum.weight(j, &q));
        }
    }
}

#[test]
fn heuristic_weights_are_the_published_formulas() {
    // q = (1, 2, 5): balance 1/8, 2/8, 5/8; power 2: 1/30, 4/30, 25/30; maximum 0, 0, 1;
    // cutoff 0.3 (threshold 1.5): 0, 2/7, 5/7.
    let q = [1.0, 2.0, 5.0];
    let cases: [(MisHeuristic, [f64; 3]); 4] = [
        (MisHeuristic::Balance, [1.0 / 8.0, 2.0 / 8.0, 5.0 / 8.0]),
        (
            MisHeuristic::Power { beta: 2.0 },
            [1.0 / 30.0, 4.0 / 30.0, 25.0 / 30.0],
        ),
        (MisHeuristic::Maximum, [0.0, 0.0, 1.0]),
        (
            MisHeuristic::Cutoff { alpha: 0.3 },
            [0.0, 2.0 / 7.0, 5.0 / 7.0],
        ),
    ];
    for (h, expected) in cases {
        for (j, e) in expected.iter().enumerate() {
            assert!(
                (h.weight(j, &q) - e).abs() < 1e-15,
                "{h:?} w[{j}] = {}",
                h.weight(j, &q)
            );
        }
    }
    // A large exponent approaches the maximum heuristic without overflow.
    let sharp = MisHeuristic::Power { beta: 1000.0 };
    assert!((sharp.weight(2, &[1e300, 1e300, 1.1e300]) - 1.0).abs() < 1e-15);
    // Undefined weights are NaN, never a silent value.
    for h in heuristics() {
        assert!(h.weight(0, &[0.0, 0.0]).is_nan(), "{h:?}");
        assert!(h.weight(0, &[1.0, f64::NAN]).is_nan(), "{h:?}");
        assert!(h.weight(0, &[1.0, -1.0]).is_nan(), "{h:?}");
        assert!(h.weight(0, &[1.0, f64::INFINITY]).is_nan(), "{h:?}");
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
// Unbiasedness

const UNBIASED_SAMPLES: usize = 100_000;

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

#[test]
fn multi_sample_mis_is_unbiased() {
    for (p, problem) in problems().iter().enumerate() {
        for (k, h) in heuristics().into_iter().enumerate() {
            let techniques = (problem.techniques)();
            let n = counts(techniques.len());
            let mis =
                MultiSampleMis::new(problem.f, techniques.into_iter().zip(n).collect(), h).unwrap();
            let name = format!("{} multi-sample {h:?}", problem.name);
            assert_unbiased(
                &name,
                &mis,
                problem.exact,
                UNBIASED_SAMPLES,
                (100 * p + k) as u64,
            );
        }
    }
}

#[test]
fn one_sample_mis_is_unbiased() {
    for (p, problem) in problems().iter().enumerate() {
        for (k, h) in heuristics().into_iter().enumerate() {
            let techniques = (problem.techniques)();
            let c = probabilities(techniques.len());
            let mis = OneSampleMis::new(problem.f, techniques, c, h).unwrap();
            let name = format!("{} one-sample {h:?}", problem.name);
            assert_unbiased(
                &name,
                &mis,
                problem.exact,
                UNBIASED_SAMPLES,
                (1000 + 100 * p + k) as u64,
            );
        }
    }
}

#[test]
fn user_weightings_that_sum_to_one_are_unbiased() {
    for (p, problem) in problems().iter().enumerate() {
        let t = (problem.techniques)().len();
        // Fixed shares (valid since every technique here is positive wherever f is), and a
        // share that moves with x.
        let fixed = move |_i: usize, _x: &[f64], _q: &[f64]| 1.0 / t as f64;
        let moving = move |i: usize, x: &[f64], _q: &[f64]| {
            let first = 0.2 + 0.6 * x[0];
            if i == 0 {
                first
            } else {
                (1.0 - first) / (t - 1) as f64
            }
        };
        let n = counts(t);
        let mis = MultiSampleMis::new(
            problem.f,
            (problem.techniques)().into_iter().zip(n.clone()).collect(),
            fixed,
        )
        .unwrap();
        let name = format!("{} multi-sample fixed shares", problem.name);
        assert_unbiased(
            &name,
            &mis,
            problem.exact,
            UNBIASED_SAMPLES,
            2000 + p as u64,
        );
        let mis = MultiSampleMis::new(
            problem.f,
            (problem.techniques)().into_iter().zip(n).collect(),
            moving,
        )
        .unwrap();
        let name = format!("{} multi-sample moving shares", problem.name);
        assert_unbiased(
            &name,
            &mis,
            problem.exact,
            UNBIASED_SAMPLES,
            2100 + p as u64,
        );
        let mis =
            OneSampleMis::new(problem.f, (problem.techniques)(), probabilities(t), moving).unwrap();
        let name = format!("{} one-sample moving shares", problem.name);
        assert_unbiased(
            &name,
            &mis,
            problem.exact,
            UNBIASED_SAMPLES,
            2200 + p as u64,
        );
    }
}

#[test]
fn importance_sampling_a_mixture_is_unbiased() {
    for (p, problem) in problems().iter().enumerate() {
        let techniques = (problem.techniques)();
        let weights = vec![1.0; techniques.len()];
        let mixture = Mixture::new(techniques, weights).unwrap();
        let estimator = ImportanceEstimator::new(problem.f, mixture);
        let name = format!("{} mixture", problem.name);
        assert_unbiased(
            &name,
            &estimator,
            problem.exact,
            UNBIASED_SAMPLES,
            3000 + p as u64,
        );
    }
}

/// `g(x, y) = (1 + x)(1 + y)` on the unit square (`G = 9/4`), sampled exactly by a product of
/// linear densities, and `h = x y`: `integral g h = (1/2 + 1/3)^2 = 25/36`.
fn product_case() -> (ProductPdf, f64, f64) {
    let linear = || -> Box<dyn Pdf1d> { Box::new(Linear::new(0.0, 1.0, 1.0, 2.0).unwrap()) };
    let pdf_g = ProductPdf::new(vec![linear(), linear()]).unwrap();
    (pdf_g, 2.25, 25.0 / 36.0)
}

#[test]
fn product_importance_sampling_is_unbiased_and_is_a25() {
    let h = |x: &[f64]| x[0] * x[1];
    let (pdf_g, g_integral, exact) = product_case();
    let estimator = ProductImportanceEstimator::new(h, pdf_g, g_integral).unwrap();
    assert_unbiased("A.25 with G", &estimator, exact, UNBIASED_SAMPLES, 4000);
    let (pdf_g, g_integral, _) = product_case();
    let seed_notation =
        ProductImportanceEstimator::from_normalization(h, pdf_g, 1.0 / g_integral).unwrap();
    assert_unbiased("A.25 with c", &seed_notation, exact, UNBIASED_SAMPLES, 4001);

    // A.25 is A.19 with pdf_g = c g: the contributions h / c equal f / pdf_g to rounding.
    let (pdf_g, _, _) = product_case();
    let f = |x: &[f64]| (1.0 + x[0]) * (1.0 + x[1]) * x[0] * x[1];
    let general = ImportanceEstimator::new(f, pdf_g);
    let a = contributions(&estimator, 10_000, 4002);
    let b = contributions(&general, 10_000, 4002);
    for (ya, yb) in a.iter().zip(&b) {
        assert!(
            (ya - yb).abs() <= 1e-13 * yb.abs().max(1e-300),
            "{ya} vs {yb}"
        );
    }
    // Only h is evaluated: its variance is G^2 Var[h(X)], below that of uniform sampling of f.
    let uniform = mcint::estimator::UniformEstimator::new(f, UniformBox::unit(2).unwrap());
    let (v_product, se_product) = variance_and_its_se(&a);
    let (v_uniform, se_uniform) = variance_and_its_se(&contributions(&uniform, 10_000, 4003));
    assert!(
        v_product + 5.0 * se_product < v_uniform - 5.0 * se_uniform,
        "product {v_product} vs uniform {v_uniform}"
    );
}

// ---------------------------------------------------------------------------------------------
// Exact variances by quadrature (1-D problems on [0, 1])

/// Panels for the variance quadrature; a second pass with twice as many gives the tolerance
/// (the maximum and cutoff weights jump where two densities cross, which the panels do not
/// resolve exactly).
const VARIANCE_PANELS: usize = 2000;

/// A weighting as a function of the technique, `x` and the `q_j`.
type Weight<'a> = &'a dyn Fn(usize, f64, &[f64]) -> f64;
type OwnedWeight = Box<dyn Fn(usize, f64, &[f64]) -> f64>;

/// `q_j(x) = scale_j p_j(x)` for every technique.
fn densities(pdfs: &[Box<dyn Pdf>], scales: &[f64], x: f64) -> Vec<f64> {
    pdfs.iter()
        .zip(scales)
        .map(|(p, s)| s * p.pdf(&[x]))
        .collect()
}

/// `(value, tolerance)` of the quadrature of `term` on [0, 1], from two resolutions.
fn quadrature_with_tolerance(term: impl Fn(f64) -> f64) -> (f64, f64) {
    let coarse = integrate(&term, 0.0, 1.0, VARIANCE_PANELS);
    let fine = integrate(&term, 0.0, 1.0, 2 * VARIANCE_PANELS);
    (fine, 2.0 * (fine - coarse).abs() + 1e-13 * fine.abs())
}

/// Exact variance of Veach's multi-sample estimator (one contribution = one group):
/// `V = sum_i [ integral w_i^2 f^2 / (n_i p_i) - (integral w_i f)^2 / n_i ]`, and its tolerance.
fn multi_sample_variance(
    f: Integrand,
    pdfs: &[Box<dyn Pdf>],
    n: &[usize],
    weight: Weight,
) -> (f64, f64) {
    let scales: Vec<f64> = n.iter().map(|&k| k as f64).collect();
    let (mut variance, mut tolerance) = (0.0, 0.0);
    for (i, &ni) in scales.iter().enumerate() {
        let (second, e2) = quadrature_with_tolerance(|x| {
            let q = densities(pdfs, &scales, x);
            let w = weight(i, x, &q);
            if w == 0.0 {
                0.0
            } else {
                w * w * f(&[x]).powi(2) / q[i]
            }
        });
        let (first, e1) = quadrature_with_tolerance(|x| {
            let q = densities(pdfs, &scales, x);
            weight(i, x, &q) * f(&[x])
        });
        variance += second - first * first / ni;
        tolerance += e2 + 2.0 * first.abs() * e1 / ni;
    }
    (variance, tolerance)
}

/// Exact variance of the one-sample estimator: `sum_i integral w_i^2 f^2 / (c_i p_i) - F^2`.
fn one_sample_variance(
    f: Integrand,
    pdfs: &[Box<dyn Pdf>],
    c: &[f64],
    exact: f64,
    weight: Weight,
) -> (f64, f64) {
    let (mut second, mut tolerance) = (0.0, 0.0);
    for i in 0..pdfs.len() {
        let (value, e) = quadrature_with_tolerance(|x| {
            let q = densities(pdfs, c, x);
            let w = weight(i, x, &q);
            if w == 0.0 {
                0.0
            } else {
                w * w * f(&[x]).powi(2) / q[i]
            }
        });
        second += value;
        tolerance += e;
    }
    (second - exact * exact, tolerance)
}

/// Named weightings for the variance comparisons: the heuristics (through the library), fixed
/// shares, every technique alone, and a share that moves with x.
fn weightings(t: usize) -> Vec<(String, OwnedWeight)> {
    let mut list: Vec<(String, OwnedWeight)> = Vec::new();
    for h in heuristics() {
        list.push((
            format!("{h:?}"),
            Box::new(move |i: usize, _: f64, q: &[f64]| h.weight(i, q)),
        ));
    }
    list.push((
        "fixed shares".into(),
        Box::new(move |_: usize, _: f64, _: &[f64]| 1.0 / t as f64),
    ));
    for k in 0..t {
        list.push((
            format!("technique {k} alone"),
            Box::new(move |i: usize, _: f64, _: &[f64]| if i == k { 1.0 } else { 0.0 }),
        ));
    }
    list.push((
        "moving share".into(),
        Box::new(move |i: usize, x: f64, _: &[f64]| {
            let first = 0.1 + 0.8 * x;
            if i == 0 {
                first
            } else {
                (1.0 - first) / (t - 1) as f64
            }
        }),
    ));
    list
}

/// Veach's Theorem 9.2: for any weighting w,
/// `V[F_balance] <= V[F_w] + (1/min_i n_i - 1/sum_i n_i) F^2`, here on exact variances.
#[test]
fn balance_heuristic_obeys_veachs_bound() {
    let mut cases: Vec<(Problem, Vec<usize>)> = Vec::new();
    for problem in problems()
        .into_iter()
        .filter(|p| p.name != "2-D exponential")
    {
        let shapes: Vec<Vec<usize>> = if (problem.techniques)().len() == 2 {
            vec![vec![1, 1], vec![1, 3], vec![4, 2]]
        } else {
            vec![vec![1, 1, 1], vec![2, 1, 3]]
        };
        cases.extend(shapes.into_iter().map(|n| (problem, n)));
    }
    let mut balance_loses_somewhere = false;
    for (problem, n) in &cases {
        let pdfs = (problem.techniques)();
        let balance = |i: usize, _: f64, q: &[f64]| MisHeuristic::Balance.weight(i, q);
        let (v_balance, tol_balance) = multi_sample_variance(problem.f, &pdfs, n, &balance);
        let min_n = *n.iter().min().unwrap() as f64;
        let total_n: f64 = n.iter().sum::<usize>() as f64;
        let slack = (1.0 / min_n - 1.0 / total_n) * problem.exact * problem.exact;
        for (name, w) in weightings(pdfs.len()) {
            let (v, tol) = multi_sample_variance(problem.f, &pdfs, n, w.as_ref());
            assert!(
                v_balance <= v + slack + tol + tol_balance,
                "{} n = {n:?}: balance {v_balance} > {name} {v} + slack {slack}",
                problem.name
            );
            balance_loses_somewhere |= v_balance > v + tol + tol_balance;
        }
    }
    // The slack term is needed: where one technique is perfect (f = 1.5 p_0), that technique
    // alone has zero variance and the balance heuristic does not.
    assert!(balance_loses_somewhere);
}

/// The quadrature variances are the variances of the library's estimators: sample variances
/// of 200,000 contributions agree within 5 standard errors.
#[test]
fn exact_variances_match_the_estimators() {
    for problem in problems()
        .into_iter()
        .filter(|p| p.name != "2-D exponential")
    {
        let t = (problem.techniques)().len();
        let n = counts(t);
        let c = probabilities(t);
        for (k, h) in heuristics().into_iter().enumerate() {
            let w = move |i: usize, _: f64, q: &[f64]| h.weight(i, q);
            let pdfs = (problem.techniques)();
            let (exact, tol) = multi_sample_variance(problem.f, &pdfs, &n, &w);
            let mis = MultiSampleMis::new(problem.f, pdfs.into_iter().zip(n.clone()).collect(), h)
                .unwrap();
            let (s2, se) = variance_and_its_se(&contributions(&mis, 200_000, 5000 + k as u64));
            assert!(
                (s2 - exact).abs() <= 5.0 * se + tol,
                "{} multi-sample {h:?}: sample variance {s2} vs exact {exact} (se {se:e})",
                problem.name
            );
            let pdfs = (problem.techniques)();
            let (exact, tol) = one_sample_variance(problem.f, &pdfs, &c, problem.exact, &w);
            let mis = OneSampleMis::new(problem.f, pdfs, c.clone(), h).unwrap();
            let (s2, se) = variance_and_its_se(&contributions(&mis, 200_000, 5100 + k as u64));
            assert!(
                (s2 - exact).abs() <= 5.0 * se + tol,
                "{} one-sample {h:?}: sample variance {s2} vs exact {exact} (se {se:e})",
                problem.name
            );
        }
    }
}

/// In the one-sample model the balance heuristic is optimal: `E[F^2] = sum_i integral w_i^2 f^2
/// / q_i` is minimised pointwise by `w_i = q_i / sum_j q_j` (Veach 1997, chapter 9).
#[test]
fn balance_heuristic_is_optimal_for_one_sample_mis() {
    for problem in problems()
        .into_iter()
        .filter(|p| p.name != "2-D exponential")
    {
        let pdfs = (problem.techniques)();
        let c = probabilities(pdfs.len());
        let balance = |i: usize, _: f64, q: &[f64]| MisHeuristic::Balance.weight(i, q);
        let (v_balance, tol_balance) =
            one_sample_variance(problem.f, &pdfs, &c, problem.exact, &balance);
        for (name, w) in weightings(pdfs.len()) {
            let (v, tol) = one_sample_variance(problem.f, &pdfs, &c, problem.exact, w.as_ref());
            assert!(
                v_balance <= v + tol + tol_balance,
                "{}: one-sample balance {v_balance} > {name} {v}",
                problem.name
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The classic case: a sharp lobe times a broad lobe

/// f = g h with g a sharp lobe (rate 10) on a floor and h a broad linear lobe; technique 0
/// samples the lobe of g, technique 1 samples h. Sampling the lobe alone meets the floor's
/// contribution far from the lobe, where its density is e^-10 of its peak (rare, huge
/// contributions); sampling h alone rarely lands in the lobe. MIS with one sample of each gets
/// the best of both. Variances are per group of two samples (each single technique gets two).
#[test]
fn mis_beats_both_techniques_on_sharp_times_broad() {
    let pdfs = sharp_techniques();
    let exact_f = sharp_times_broad_integral();
    let variance = |w: Weight, n: &[usize]| multi_sample_variance(sharp_times_broad, &pdfs, n, w);
    let lobe_alone = |i: usize, _: f64, _: &[f64]| if i == 0 { 1.0 } else { 0.0 };
    let broad_alone = |i: usize, _: f64, _: &[f64]| if i == 1 { 1.0 } else { 0.0 };
    let (v_lobe, _) = variance(&lobe_alone, &[2, 1]);
    let (v_broad, _) = variance(&broad_alone, &[1, 2]);
    for h in [MisHeuristic::Balance, MisHeuristic::power(2.0).unwrap()] {
        let (v_mis, tol) = variance(&move |i: usize, _: f64, q: &[f64]| h.weight(i, q), &[1, 1]);
        // A margin of 10 in variance: both single techniques need ten times the samples.
        assert!(
            10.0 * (v_mis + tol) < v_broad.min(v_lobe),
            "{h:?}: MIS {v_mis} vs lobe {v_lobe}, broad {v_broad}"
        );
        // The estimator realises that variance (its contributions are bounded, so the sample
        // variance is reliable) ...
        let mis = MultiSampleMis::new(
            sharp_times_broad,
            sharp_techniques().into_iter().zip([1, 1]).collect(),
            h,
        )
        .unwrap();
        let values = contributions(&mis, 1 << 18, 6000);
        let (s2, se) = variance_and_its_se(&values);
        assert!(
            (s2 - v_mis).abs() <= 5.0 * se + tol,
            "{h:?}: {s2} vs {v_mis}"
        );
        assert!(
            (summary(&values).mean() - exact_f).abs() <= 4.5 * (s2 / values.len() as f64).sqrt()
        );
        // ... and beats the broad technique's measured variance far beyond sampling noise.
        // (The lobe technique's variance comes from contributions of probability about e^-10
        // and size about e^10, so its sample variance is unreliable; its exact value is above.)
        let broad = MultiSampleMis::new(
            sharp_times_broad,
            vec![(Box::new(broad_lobe()) as Box<dyn Pdf>, 2)],
            MisHeuristic::Balance,
        )
        .unwrap();
        let (s2_broad, se_broad) = variance_and_its_se(&contributions(&broad, 1 << 18, 6001));
        assert!(
            (s2_broad - v_broad).abs() <= 5.0 * se_broad,
            "{s2_broad} vs {v_broad}"
        );
        assert!(
            s2_broad - 5.0 * se_broad > 10.0 * (s2 + 5.0 * se),
            "{h:?}: broad {s2_broad} +- {se_broad} vs MIS {s2} +- {se}"
        );
    }
    // The lobe technique's variance is enormous relative to the integral (F^2 is about 0.37).
    assert!(v_lobe > 50.0 * exact_f * exact_f, "{v_lobe}");
}

// ---------------------------------------------------------------------------------------------
// One-sample MIS with the balance heuristic is sampling the mixture

#[test]
fn one_sample_balance_is_importance_sampling_the_mixture() {
    for (p, problem) in problems().iter().enumerate() {
        let t = (problem.techniques)().len();
        let c = probabilities(t);
        let mis = OneSampleMis::new(
            problem.f,
            (problem.techniques)(),
            c.clone(),
            MisHeuristic::Balance,
        )
        .unwrap();
        let mixture = Mixture::new((problem.techniques)(), c).unwrap();
        let importance = ImportanceEstimator::new(problem.f, mixture);
        assert_eq!(mis.canonical_dims(), importance.canonical_dims());
        let a = contributions(&mis, 20_000, 7000 + p as u64);
        let b = contributions(&importance, 20_000, 7000 + p as u64);
        for (ya, yb) in a.iter().zip(&b) {
            assert!(
                (ya - yb).abs() <= 1e-13 * yb.abs(),
                "{}: one-sample {ya} vs mixture {yb}",
                problem.name
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Mixture

/// A test density with more canonical dimensions than dimensions: `x = u_0 + u_1`, the
/// triangular density on [0, 2).
struct SumOfTwoUniforms;

impl Pdf for SumOfTwoUniforms {
    fn canonical_dims(&self) -> usize {
        2
    }
    fn dims(&self) -> usize {
        1
    }
    fn sample(&self, u: &[f64], x: &mut [f64]) {
        x[0] = u[0] + u[1];
    }
    fn pdf(&self, x: &[f64]) -> f64 {
        match x[0] {
            t if (0.0..1.0).contains(&t) => t,
            t if (1.0..2.0).contains(&t) => 2.0 - t,
            _ => 0.0,
        }
    }
}

fn triangle_cdf(x: f64) -> f64 {
    let x = x.clamp(0.0, 2.0);
    if x < 1.0 {
        0.5 * x * x
    } else {
        1.0 - 0.5 * (2.0 - x) * (2.0 - x)
    }
}

/// A 1-D mixture on [0, 2) with exact cdf: components with unnormalised weights 3, 5, 2, 1.
fn mixture_1d() -> (Mixture, impl Fn(f64) -> f64) {
    let exponential = Exponential::new(5.0, 0.0, 2.0).unwrap();
    let normal = TruncatedNormal::new(1.2, 0.1, 0.0, 2.0).unwrap();
    let linear = Linear::new(0.0, 2.0, 1.0, 0.0).unwrap();
    let mixture = Mixture::new(
        vec![
            Box::new(exponential),
            Box::new(normal),
            Box::new(linear),
            Box::new(SumOfTwoUniforms),
        ],
        vec![3.0, 5.0, 2.0, 1.0],
    )
    .unwrap();
    let cdf = move |x: f64| {
        (3.0 * exponential.invert_1d(x)
            + 5.0 * normal.invert_1d(x)
            + 2.0 * linear.invert_1d(x)
            + triangle_cdf(x))
            / 11.0
    };
    (mixture, cdf)
}

#[test]
fn mixtures_integrate_to_one() {
    let (mixture, _) = mixture_1d();
    assert_eq!((mixture.dims(), mixture.canonical_dims()), (1, 2));
    let weights = mixture.weights();
    let expected = [3.0 / 11.0, 5.0 / 11.0, 2.0 / 11.0, 1.0 / 11.0];
    for (w, e) in weights.iter().zip(expected) {
        assert!((w - e).abs() < 1e-16);
    }
    // Panels are 1/200 wide, so the kink of the triangle at 1 is a panel edge.
    let total = integrate(|x| mixture.pdf(&[x]), 0.0, 2.0, 400);
    assert!((total - 1.0).abs() < 1e-12, "1-D mixture: {total}");

    let (mixture_2d, lo, hi) = mixture_2d();
    let total = integrate_2d(|x| mixture_2d.pdf(x), lo, hi, 24);
    assert!((total - 1.0).abs() < 1e-12, "2-D mixture: {total}");

    let defensive = Mixture::defensive(
        Box::new(TruncatedNormal::new(0.3, 0.05, -1.0, 3.0).unwrap()),
        UniformBox::new(vec![-1.0], vec![3.0]).unwrap(),
        0.1,
    )
    .unwrap();
    let total = integrate(|x| defensive.pdf(&[x]), -1.0, 3.0, 400);
    assert!((total - 1.0).abs() < 1e-12, "defensive: {total}");
}

/// Chi-square test of 1-D samples against exact cell probabilities from a cdf.
fn chi_square_1d(pdf: &dyn Pdf, cdf: &dyn Fn(f64) -> f64, lo: f64, hi: f64, seed: u64) -> f64 {
    const SAMPLES: usize = 200_000;
    const CELLS: usize = 40;
    let edge = |k: usize| lo + (hi - lo) * k as f64 / CELLS as f64;
    let expected: Vec<f64> = (0..CELLS)
        .map(|k| SAMPLES as f64 * (cdf(edge(k + 1)) - cdf(edge(k))))
        .collect();
    let dims = pdf.canonical_dims();
    let sampler = Independent::new(dims, seed).unwrap();
    let mut points = Points::new(dims, SAMPLES).unwrap();
    sampler.fill(0, &mut points).unwrap();
    let mut observed = vec![0u64; CELLS];
    let (mut u, mut x) = (vec![0.0; dims], [0.0]);
    for i in 0..SAMPLES {
        points.copy_point(i, &mut u);
        pdf.sample(&u, &mut x);
        assert!(pdf.pdf(&x) > 0.0, "sample {x:?} where the pdf is zero");
        let cell = ((x[0] - lo) / (hi - lo) * CELLS as f64) as usize;
        observed[cell.min(CELLS - 1)] += 1;
    }
    chi_square_goodness_of_fit(&observed, &expected, 5.0)
        .unwrap()
        .p_value
}

/// A 2-D mixture on [0, 1] x [-1, 2) of a product density and the uniform box.
fn mixture_2d() -> (Mixture, [f64; 2], [f64; 2]) {
    let product = ProductPdf::new(vec![
        Box::new(Linear::new(0.0, 1.0, 1.0, 3.0).unwrap()),
        Box::new(TruncatedNormal::new(0.0, 0.5, -1.0, 2.0).unwrap()),
    ])
    .unwrap();
    let uniform = UniformBox::new(vec![0.0, -1.0], vec![1.0, 2.0]).unwrap();
    let mixture = Mixture::new(vec![Box::new(product), Box::new(uniform)], vec![0.7, 0.3]).unwrap();
    (mixture, [0.0, -1.0], [1.0, 2.0])
}

#[test]
fn mixture_samples_follow_the_density() {
    let (mixture, cdf) = mixture_1d();
    let p = chi_square_1d(&mixture, &cdf, 0.0, 2.0, 8000);
    assert!(p > 1e-5, "1-D mixture: p = {p}");

    let proposal = Exponential::new(-20.0, 0.0, 1.0).unwrap();
    let defensive =
        Mixture::defensive(Box::new(proposal), UniformBox::unit(1).unwrap(), 0.25).unwrap();
    let cdf = |x: f64| 0.25 * x.clamp(0.0, 1.0) + 0.75 * proposal.invert_1d(x);
    let p = chi_square_1d(&defensive, &cdf, 0.0, 1.0, 8001);
    assert!(p > 1e-5, "defensive mixture: p = {p}");

    // 2-D: 8 x 8 cells, probabilities from the factors' cdfs.
    const SAMPLES: usize = 100_000;
    const GRID: usize = 8;
    let (mixture, lo, hi) = mixture_2d();
    let linear = Linear::new(0.0, 1.0, 1.0, 3.0).unwrap();
    let normal = TruncatedNormal::new(0.0, 0.5, -1.0, 2.0).unwrap();
    let edge = |d: usize, k: usize| lo[d] + (hi[d] - lo[d]) * k as f64 / GRID as f64;
    let mut expected = vec![0.0; GRID * GRID];
    for iy in 0..GRID {
        for ix in 0..GRID {
            let px = linear.invert_1d(edge(0, ix + 1)) - linear.invert_1d(edge(0, ix));
            let py = normal.invert_1d(edge(1, iy + 1)) - normal.invert_1d(edge(1, iy));
            let cell_area = 1.0 / (GRID * GRID) as f64;
            expected[ix + GRID * iy] = SAMPLES as f64 * (0.7 * px * py + 0.3 * cell_area);
        }
    }
    let sampler = Independent::new(2, 8002).unwrap();
    let mut points = Points::new(2, SAMPLES).unwrap();
    sampler.fill(0, &mut points).unwrap();
    let mut observed = vec![0u64; GRID * GRID];
    let (mut u, mut x) = ([0.0; 2], [0.0; 2]);
    for i in 0..SAMPLES {
        points.copy_point(i, &mut u);
        mixture.sample(&u, &mut x);
        let cell = |d: usize| {
            let t = ((x[d] - lo[d]) / (hi[d] - lo[d]) * GRID as f64) as usize;
            t.min(GRID - 1)
        };
        observed[cell(0) + GRID * cell(1)] += 1;
    }
    let fit = chi_square_goodness_of_fit(&observed, &expected, 5.0).unwrap();
    assert!(fit.p_value > 1e-5, "2-D mixture: {fit:?}");
}

#[test]
fn mixture_component_choice_is_exact_at_the_edges() {
    let interval = |a: f64| -> Box<dyn Pdf> { Box::new(UniformInterval::new(a, a + 1.0).unwrap()) };
    // Zero weights first, between and last: never chosen, and their pdf never read.
    let mixture = Mixture::new(
        vec![
            interval(0.0),
            interval(10.0),
            interval(20.0),
            interval(30.0),
            interval(40.0),
        ],
        vec![0.0, 1.0, 0.0, 3.0, 0.0],
    )
    .unwrap();
    let mut x = [0.0];
    for (u0, component, expected_x) in [
        (0.0, 1, 10.0),
        (0.125, 1, 10.5),
        (0.25 - f64::EPSILON / 8.0, 1, 11.0),
        (0.25, 3, 30.0),
        (0.625, 3, 30.5),
        (ONE_BELOW, 3, 31.0),
    ] {
        assert_eq!(
            mixture.sample_with_component(&[u0], &mut x),
            component,
            "u0 = {u0}"
        );
        assert!((x[0] - expected_x).abs() < 1e-14, "u0 = {u0}: x = {}", x[0]);
        // Inside the component's half-open interval [10 k, 10 k + 1).
        let start = 10.0 * component as f64;
        assert!(
            (start..start + 1.0).contains(&x[0]),
            "u0 = {u0}: x = {} outside",
            x[0]
        );
    }
    assert_eq!(mixture.pdf(&[20.5]), 0.0);
    assert_eq!(mixture.pdf(&[30.5]), 0.75);
    // invert does not exist for a mixture.
    assert_eq!(
        field(mixture.invert(&[10.5], &mut [0.0]).unwrap_err()),
        "invert"
    );
    // Weights near the top of the f64 range normalise without overflow.
    let huge = Mixture::new(vec![interval(0.0), interval(1.0)], vec![f64::MAX, f64::MAX]).unwrap();
    assert_eq!(huge.weights(), &[0.5, 0.5]);
}

/// Hesterberg's bound: importance sampling from `alpha * uniform + (1 - alpha) * proposal` has
/// variance at most `sigma_uniform^2 / alpha + (1/alpha - 1) F^2`, however bad the proposal;
/// here the proposal alone (a rate-30 exponential, whose density falls to e^-30 of its peak
/// where f is largest) is far above that bound. Exact variances by quadrature.
#[test]
fn defensive_mixture_obeys_hesterbergs_bound() {
    let proposal = || Exponential::new(30.0, 0.0, 1.0).unwrap();
    let f = |x: f64| sharp_times_broad(&[x]);
    let exact = sharp_times_broad_integral();
    let second_moment = |pdf: &dyn Pdf| integrate(|x| f(x).powi(2) / pdf.pdf(&[x]), 0.0, 1.0, 400);
    let v_uniform = second_moment(&UniformInterval::new(0.0, 1.0).unwrap()) - exact * exact;
    let v_proposal = second_moment(&proposal()) - exact * exact;
    for alpha in [0.05, 0.2, 0.5, 1.0] {
        let defensive =
            Mixture::defensive(Box::new(proposal()), UniformBox::unit(1).unwrap(), alpha).unwrap();
        let v = second_moment(&defensive) - exact * exact;
        let bound = v_uniform / alpha + (1.0 / alpha - 1.0) * exact * exact;
        assert!(v <= bound * (1.0 + 1e-12), "alpha {alpha}: {v} > {bound}");
        assert!(
            v_proposal > 1e3 * bound,
            "alpha {alpha}: proposal {v_proposal}"
        );
    }
    // The defensive estimator realises that variance.
    let defensive =
        Mixture::defensive(Box::new(proposal()), UniformBox::unit(1).unwrap(), 0.2).unwrap();
    let v = second_moment(&defensive) - exact * exact;
    let estimator = ImportanceEstimator::new(sharp_times_broad, defensive);
    let (s2, se) = variance_and_its_se(&contributions(&estimator, 200_000, 8100));
    assert!(
        (s2 - v).abs() <= 5.0 * se,
        "sample variance {s2} vs exact {v}"
    );
}

proptest! {
    #![proptest_config(config(512, 0x313))]

    /// Defensive mixtures keep at least alpha / volume of density everywhere on the domain,
    /// and every sample of a mixture lands where its density is positive.
    #[test]
    fn defensive_mixtures_are_bounded_below(
        alpha in 0.01..=1.0f64,
        x in 0.0..1.0f64,
        y in 0.0..2.0f64,
        u in prop::array::uniform2(0.0..1.0f64),
    ) {
        let proposal = ProductPdf::new(vec![
            Box::new(Exponential::new(40.0, 0.0, 1.0).unwrap()),
            Box::new(TruncatedNormal::new(0.1, 0.02, 0.0, 2.0).unwrap()),
        ])
        .unwrap();
        let domain = UniformBox::new(vec![0.0, 0.0], vec![1.0, 2.0]).unwrap();
        let p = Mixture::defensive(Box::new(proposal), domain, alpha).unwrap();
        prop_assert!(p.pdf(&[x, y]) >= alpha / 2.0 * (1.0 - 1e-15));
        let mut s = [0.0; 2];
        p.sample(&u, &mut s);
        prop_assert!(p.pdf(&s) > 0.0, "sample {:?} of u = {:?}", s, u);
    }
}

// ---------------------------------------------------------------------------------------------
// Bad input

#[test]
fn bad_input_gives_errors_naming_the_field() {
    let unit = || -> Box<dyn Pdf> { Box::new(UniformInterval::new(0.0, 1.0).unwrap()) };
    let square = || -> Box<dyn Pdf> { Box::new(UniformBox::unit(2).unwrap()) };
    let f = |x: &[f64]| x[0];
    let nan = f64::NAN;
    let inf = f64::INFINITY;

    // Heuristic parameters.
    for beta in [0.0, -1.0, nan, inf] {
        assert_eq!(field(MisHeuristic::power(beta).unwrap_err()), "beta");
        assert_eq!(
            field(MisHeuristic::Power { beta }.check().unwrap_err()),
            "beta"
        );
    }
    for alpha in [-0.1, 1.1, nan, inf] {
        assert_eq!(field(MisHeuristic::cutoff(alpha).unwrap_err()), "alpha");
    }
    assert!(MisHeuristic::power(1e-300).is_ok() && MisHeuristic::power(1e300).is_ok());
    assert!(MisHeuristic::cutoff(0.0).is_ok() && MisHeuristic::cutoff(1.0).is_ok());

    // Mixture.
    assert_eq!(
        field(Mixture::new(vec![], vec![]).unwrap_err()),
        "components"
    );
    assert_eq!(
        field(Mixture::new(vec![unit()], vec![1.0, 2.0]).unwrap_err()),
        "weights"
    );
    assert_eq!(
        field(Mixture::new(vec![unit(), square()], vec![1.0, 1.0]).unwrap_err()),
        "components"
    );
    for bad in [
        vec![1.0, -1.0],
        vec![nan, 1.0],
        vec![inf, 1.0],
        vec![0.0, 0.0],
    ] {
        assert_eq!(
            field(Mixture::new(vec![unit(), unit()], bad).unwrap_err()),
            "weights"
        );
    }
    for alpha in [0.0, -0.5, 1.5, nan] {
        let err = Mixture::defensive(unit(), UniformBox::unit(1).unwrap(), alpha).unwrap_err();
        assert_eq!(field(err), "alpha");
    }
    let err = Mixture::defensive(square(), UniformBox::unit(1).unwrap(), 0.5).unwrap_err();
    assert_eq!(field(err), "proposal");

    // Multi-sample MIS.
    let balance = MisHeuristic::Balance;
    let err = |r: mcint::Result<MultiSampleMis<_, _>>| field(r.err().unwrap());
    assert_eq!(err(MultiSampleMis::new(f, vec![], balance)), "techniques");
    assert_eq!(
        err(MultiSampleMis::new(
            f,
            vec![(unit(), 1), (square(), 1)],
            balance
        )),
        "techniques"
    );
    assert_eq!(
        err(MultiSampleMis::new(
            f,
            vec![(unit(), 1), (unit(), 0)],
            balance
        )),
        "n_i"
    );
    assert_eq!(
        err(MultiSampleMis::new(
            f,
            vec![(unit(), usize::MAX), (unit(), 2)],
            balance
        )),
        "n_i"
    );
    assert_eq!(
        err(MultiSampleMis::new(
            f,
            vec![(unit(), 1)],
            MisHeuristic::Power { beta: 0.0 }
        )),
        "beta"
    );
    assert_eq!(
        err(MultiSampleMis::new(
            f,
            vec![(unit(), 1)],
            MisHeuristic::Cutoff { alpha: 2.0 }
        )),
        "alpha"
    );

    // One-sample MIS.
    let err = |r: mcint::Result<OneSampleMis<_, _>>| r.err().unwrap();
    assert_eq!(
        field(err(OneSampleMis::new(f, vec![], vec![], balance))),
        "techniques"
    );
    assert_eq!(
        field(err(OneSampleMis::new(
            f,
            vec![unit()],
            vec![0.5, 0.5],
            balance
        ))),
        "probabilities"
    );
    assert_eq!(
        field(err(OneSampleMis::new(
            f,
            vec![unit(), square()],
            vec![0.5, 0.5],
            balance
        ))),
        "techniques"
    );
    for bad in [
        vec![-0.5, 1.5],
        vec![nan, 1.0],
        vec![inf, 0.0],
        vec![0.5, 0.6],
        vec![0.5, 0.499999],
        vec![1.0, 1.0],
    ] {
        let e = err(OneSampleMis::new(
            f,
            vec![unit(), unit()],
            bad.clone(),
            balance,
        ));
        let message = e.to_string();
        assert_eq!(field(e), "probabilities", "{bad:?}");
        assert!(message.contains("sum to one"), "{message}");
    }
    // The message says what they summed to.
    let message = err(OneSampleMis::new(
        f,
        vec![unit(), unit()],
        vec![0.5, 0.6],
        balance,
    ))
    .to_string();
    assert!(message.contains("sum to 1.1"), "{message}");
    assert!(OneSampleMis::new(f, vec![unit(), unit()], vec![0.5, 0.5 + 1e-13], balance).is_ok());
    assert!(OneSampleMis::new(f, vec![unit(), unit()], vec![0.0, 1.0], balance).is_ok());
    assert_eq!(
        field(err(OneSampleMis::new(
            f,
            vec![unit()],
            vec![1.0],
            MisHeuristic::Power { beta: nan }
        ))),
        "beta"
    );

    // Product importance sampling.
    for bad in [0.0, -1.0, nan, inf] {
        let e = ProductImportanceEstimator::new(f, UniformInterval::new(0.0, 1.0).unwrap(), bad);
        assert_eq!(field(e.err().unwrap()), "g_integral");
        let e = ProductImportanceEstimator::from_normalization(
            f,
            UniformInterval::new(0.0, 1.0).unwrap(),
            bad,
        );
        assert_eq!(field(e.err().unwrap()), "c");
    }
    let e = ProductImportanceEstimator::from_normalization(
        f,
        UniformInterval::new(0.0, 1.0).unwrap(),
        1e-310,
    );
    assert_eq!(field(e.err().unwrap()), "c");
}

// ---------------------------------------------------------------------------------------------
// Broken pdfs and weights: the integrator reports them

/// Samples uniformly on [0, 1) but claims a density of `claim` on [0.5, 1): zero or NaN there
/// is a pdf inconsistent with its own samples.
struct BrokenPdf {
    claim: f64,
}

impl Pdf for BrokenPdf {
    fn canonical_dims(&self) -> usize {
        1
    }
    fn dims(&self) -> usize {
        1
    }
    fn sample(&self, u: &[f64], x: &mut [f64]) {
        x[0] = u[0];
    }
    fn pdf(&self, x: &[f64]) -> f64 {
        if x[0] < 0.5 { 1.0 } else { self.claim }
    }
}

fn broken(claim: f64) -> Box<dyn Pdf> {
    Box::new(BrokenPdf { claim })
}

fn uniform() -> Box<dyn Pdf> {
    Box::new(UniformInterval::new(0.0, 1.0).unwrap())
}

/// Runs the integrator and returns the non-finite count and the first offending point,
/// checking the count against its binomial expectation (4.5 standard deviations).
fn expect_non_finite<E: Estimator>(estimator: E, samples: u64, probability: f64) -> Vec<f64> {
    match Integrator::new(estimator).samples(samples).seed(11).run() {
        Err(Error::NonFiniteContribution {
            count,
            first_point,
            first_value,
            ..
        }) => {
            assert!(!first_value.is_finite());
            let mean = samples as f64 * probability;
            let sd = (samples as f64 * probability * (1.0 - probability)).sqrt();
            assert!(
                (count as f64 - mean).abs() <= 4.5 * sd + 1e-9,
                "count {count}, expected {mean} +- {sd}"
            );
            first_point
        }
        other => panic!("expected a non-finite contribution error, got {other:?}"),
    }
}

#[test]
fn pdfs_zero_or_nan_where_f_is_not_are_reported() {
    let f = |_: &[f64]| 1.0;
    let samples = 10_000;
    // Multi-sample: the broken technique's own sample lands in [0.5, 1) in half of the groups.
    // With a zero claim only that technique's samples fail (the uniform technique's samples
    // there have weight one); with a NaN claim every sample in [0.5, 1) fails (3/4 of groups).
    let mis = MultiSampleMis::new(
        f,
        vec![(broken(0.0), 1), (uniform(), 1)],
        MisHeuristic::Balance,
    )
    .unwrap();
    let point = expect_non_finite(mis, samples, 0.5);
    assert!(point[0] >= 0.5, "{point:?}");
    let mis = MultiSampleMis::new(
        f,
        vec![(broken(f64::NAN), 1), (uniform(), 1)],
        MisHeuristic::power(2.0).unwrap(),
    )
    .unwrap();
    let point = expect_non_finite(mis, samples, 0.75);
    assert!(point.iter().any(|&u| u >= 0.5), "{point:?}");

    // One-sample: the broken technique is chosen with probability 0.4 and its sample falls in
    // [0.5, 1) half the time. u[0] < 0.4 chooses it, with remapped u = u[0] / 0.4.
    let mis = OneSampleMis::new(
        f,
        vec![broken(0.0), uniform()],
        vec![0.4, 0.6],
        MisHeuristic::Maximum,
    )
    .unwrap();
    let point = expect_non_finite(mis, samples, 0.2);
    assert!((0.2..0.4).contains(&point[0]), "{point:?}");

    // A mixture with a NaN component: every point in [0.5, 1) has a NaN density.
    let mixture = Mixture::new(vec![broken(f64::NAN), uniform()], vec![1.0, 1.0]).unwrap();
    expect_non_finite(ImportanceEstimator::new(f, mixture), samples, 0.5);

    // Where f = 0 the broken density is never consulted: the estimate is fine and unbiased.
    let half = |x: &[f64]| if x[0] < 0.5 { 1.0 } else { 0.0 };
    let mis = MultiSampleMis::new(
        half,
        vec![(broken(f64::NAN), 1), (uniform(), 2)],
        MisHeuristic::Balance,
    )
    .unwrap();
    let e = Integrator::new(mis)
        .samples(samples)
        .seed(12)
        .run()
        .unwrap();
    assert!((e.mean - 0.5).abs() <= 4.5 * e.std_error.unwrap(), "{e:?}");
}

#[test]
fn user_weights_that_do_not_sum_to_one_are_reported() {
    let f = |x: &[f64]| 1.0 + x[0];
    let samples = 10_000;
    // Shares that sum to 1.2 on [0.5, 1): a bias the estimator cannot see by itself.
    let wrong = |i: usize, x: &[f64], _: &[f64]| {
        if x[0] < 0.5 || i == 0 { 0.5 } else { 0.7 }
    };
    // Every sample of both techniques is checked: a group fails when either lands in [0.5, 1).
    let mis = MultiSampleMis::new(f, vec![(uniform(), 1), (uniform(), 1)], wrong).unwrap();
    let point = expect_non_finite(mis, samples, 0.75);
    assert!(point.iter().any(|&u| u >= 0.5), "{point:?}");
    let mis = OneSampleMis::new(f, vec![uniform(), uniform()], vec![0.5, 0.5], wrong).unwrap();
    expect_non_finite(mis, samples, 0.5);

    // A slightly wrong sum is caught too (1e-6 is far above rounding).
    let almost = |i: usize, _: &[f64], _: &[f64]| if i == 0 { 0.5 } else { 0.5 + 1e-6 };
    let mis = MultiSampleMis::new(f, vec![(uniform(), 1), (uniform(), 1)], almost).unwrap();
    expect_non_finite(mis, samples, 1.0);

    // The same weighting within the 1e-9 tolerance runs.
    let rounding = |i: usize, _: &[f64], _: &[f64]| if i == 0 { 0.5 } else { 0.5 + 1e-12 };
    let mis = MultiSampleMis::new(f, vec![(uniform(), 1), (uniform(), 1)], rounding).unwrap();
    let e = Integrator::new(mis)
        .samples(samples)
        .seed(13)
        .run()
        .unwrap();
    assert!((e.mean - 1.5).abs() <= 4.5 * e.std_error.unwrap(), "{e:?}");
}
