//! Statistical properties of the estimators, checked against exact values:
//! unbiasedness (A.15, A.20), the variance law `sigma^2[Y] / N` (A.21), the `1/sqrt(N)` rate
//! (A.17, A.22), and the bias of the consistent-but-biased estimator (A.34, A.35).
//!
//! Tolerances are 4.5 to 5 standard errors of the tested quantity (false-alarm probability
//! below 1e-5 per check); all randomness comes from fixed seeds.

use crate::common::config;
use mcint::Points;
use mcint::estimator::{ConsistentBiased, Estimator, ImportanceEstimator, UniformEstimator};
use mcint::pdf::{Exponential, Linear, Pdf1d, TruncatedNormal, UniformBox};
use mcint::sampler::{Independent, Sampler};
use mcint::stats::Accumulator;
use proptest::prelude::*;

/// A polynomial `sum c_k x^k` on an interval, with exact moments.
#[derive(Debug, Clone)]
struct Poly {
    c: Vec<f64>,
}

impl Poly {
    fn eval(&self, x: f64) -> f64 {
        self.c.iter().rev().fold(0.0, |acc, &c| acc * x + c)
    }

    /// Exact integral over [a, b].
    fn integral(&self, a: f64, b: f64) -> f64 {
        let antiderivative = |x: f64| {
            self.c
                .iter()
                .enumerate()
                .map(|(k, c)| c * x.powi(k as i32 + 1) / (k + 1) as f64)
                .sum::<f64>()
        };
        antiderivative(b) - antiderivative(a)
    }

    fn square(&self) -> Poly {
        let mut c = vec![0.0; 2 * self.c.len() - 1];
        for (i, a) in self.c.iter().enumerate() {
            for (j, b) in self.c.iter().enumerate() {
                c[i + j] += a * b;
            }
        }
        Poly { c }
    }
}

/// `m` independent estimates, each the mean of `n` contributions, from disjoint index ranges
/// of one independent stream.
fn estimates<E: Estimator>(estimator: &E, n: usize, m: usize, seed: u64) -> Vec<f64> {
    let sampler = Independent::new(estimator.canonical_dims(), seed).unwrap();
    let mut points = Points::new(estimator.canonical_dims(), n).unwrap();
    let mut values = vec![0.0; n];
    (0..m)
        .map(|k| {
            sampler.fill((k * n) as u64, &mut points).unwrap();
            estimator.contributions(&points, &mut values);
            values.iter().sum::<f64>() / n as f64
        })
        .collect()
}

fn summary(values: &[f64]) -> Accumulator {
    let mut acc = Accumulator::new();
    acc.extend(values);
    acc
}

fn polynomial() -> impl Strategy<Value = Poly> {
    prop::collection::vec(-2.0..2.0f64, 1..6).prop_map(|c| Poly { c })
}

proptest! {
    #![proptest_config(config(24, 0xa15))]

    /// A.15: the uniform estimator's expectation is the integral. The standard error of the
    /// mean of M estimates of N samples is exactly sqrt(sigma^2[Y] / (N M)) with
    /// sigma^2[Y] = (b - a) int f^2 - F^2.
    #[test]
    fn uniform_estimator_is_unbiased(p in polynomial(), a in -2.0..1.0f64, len in 0.5..3.0f64, seed in 0u64..1000) {
        let b = a + len;
        let exact = p.integral(a, b);
        let sigma2 = len * p.square().integral(a, b) - exact * exact;
        let (n, m) = (64, 400);
        let q = p.clone();
        let estimator = UniformEstimator::new(move |x: &[f64]| q.eval(x[0]), UniformBox::new(vec![a], vec![b]).unwrap());
        let mean = summary(&estimates(&estimator, n, m, seed)).mean();
        let se = (sigma2.max(0.0) / (n * m) as f64).sqrt();
        prop_assert!((mean - exact).abs() <= 4.5 * se + 1e-12 * exact.abs().max(1.0),
            "mean {mean}, exact {exact}, se {se}");
    }

    /// A.20: the f/pdf estimator is unbiased for any pdf that is positive where f is not.
    /// Standard error from the spread of the M independent estimates.
    #[test]
    fn importance_estimator_is_unbiased(
        p in polynomial(), a in -2.0..1.0f64, len in 0.5..3.0f64, which in 0usize..3,
        shape in 0.2..2.0f64, other in 0.2..2.0f64, seed in 0u64..1000,
    ) {
        let b = a + len;
        let exact = p.integral(a, b);
        let pdf: Box<dyn Pdf1d> = match which {
            0 => Box::new(Linear::new(a, b, shape, other).unwrap()),
            1 => Box::new(Exponential::new((shape - 1.1) * 2.0, a, b).unwrap()),
            _ => Box::new(TruncatedNormal::new(a + len * (shape / 2.0), other, a, b).unwrap()),
        };
        let q = p.clone();
        let estimator = ImportanceEstimator::new(move |x: &[f64]| q.eval(x[0]), pdf);
        let acc = summary(&estimates(&estimator, 64, 400, seed));
        let se = (acc.variance() / 400.0).sqrt();
        prop_assert!((acc.mean() - exact).abs() <= 4.5 * se + 1e-12 * exact.abs().max(1.0),
            "mean {}, exact {exact}, se {se}", acc.mean());
    }
}

/// Mean and fourth central moment of a sample, for the standard error of its variance:
/// `Var(s^2) ~ (m4 - s^4) / M` for large M.
fn variance_and_its_se(values: &[f64]) -> (f64, f64) {
    let acc = summary(values);
    let s2 = acc.variance();
    let m4 = values.iter().map(|v| (v - acc.mean()).powi(4)).sum::<f64>() / values.len() as f64;
    (s2, ((m4 - s2 * s2) / values.len() as f64).sqrt())
}

fn cubic() -> (
    UniformEstimator<impl Fn(&[f64]) -> f64 + Send + Sync>,
    f64,
    f64,
) {
    let p = Poly {
        c: vec![0.5, -1.0, 0.0, 3.0],
    };
    let (a, b) = (0.0, 2.0);
    let exact = p.integral(a, b);
    let sigma2 = (b - a) * p.square().integral(a, b) - exact * exact;
    let q = p.clone();
    let estimator = UniformEstimator::new(
        move |x: &[f64]| q.eval(x[0]),
        UniformBox::new(vec![a], vec![b]).unwrap(),
    );
    (estimator, exact, sigma2)
}

/// A.21: the variance of the N-sample estimator is sigma^2[Y] / N.
#[test]
fn estimator_variance_is_sigma2_over_n() {
    let (estimator, _, sigma2) = cubic();
    for (n, seed) in [(16, 1), (256, 2)] {
        let (s2, se) = variance_and_its_se(&estimates(&estimator, n, 4000, seed));
        let expected = sigma2 / n as f64;
        assert!(
            (s2 - expected).abs() <= 5.0 * se,
            "N = {n}: variance {s2}, expected {expected}, se {se}"
        );
    }
}

/// A.17/A.22: quadrupling N halves the standard deviation (not Jarosz's "O(sqrt N)").
/// The ratio of sample standard deviations has relative standard error
/// sqrt(Var(s1^2)/(4 s1^4) + Var(s2^2)/(4 s2^4)) by the delta method.
#[test]
fn standard_deviation_halves_when_n_quadruples() {
    let (estimator, _, _) = cubic();
    let (v1, se1) = variance_and_its_se(&estimates(&estimator, 64, 4000, 3));
    let (v2, se2) = variance_and_its_se(&estimates(&estimator, 256, 4000, 4));
    let ratio = (v1 / v2).sqrt();
    let rel_se = ((se1 / v1).powi(2) / 4.0 + (se2 / v2).powi(2) / 4.0).sqrt();
    assert!(
        (ratio - 2.0).abs() <= 5.0 * rel_se * ratio,
        "ratio {ratio}, relative se {rel_se}"
    );
}

/// A.23: a pdf exactly proportional to f gives zero variance.
#[test]
fn perfect_importance_sampling_has_zero_variance() {
    let pdf = Linear::new(1.0, 3.0, 1.0, 3.0).unwrap(); // proportional to x on [1, 3]
    let estimator = ImportanceEstimator::new(|x: &[f64]| x[0], pdf);
    let acc = summary(&estimates(&estimator, 100, 10, 5));
    assert!((acc.mean() - 4.0).abs() < 1e-13);
    assert!(acc.variance() < 1e-26, "{}", acc.variance());
}

/// A.34/A.35: the 1/(N+1) estimator has expectation N F / (N + 1), so its bias is -F/(N+1),
/// and its mean squared error is (N sigma^2 + F^2) / (N+1)^2; the bias vanishes as N grows.
#[test]
fn consistent_biased_estimator_has_the_predicted_bias() {
    let (estimator, exact, sigma2) = cubic();
    let biased = ConsistentBiased::new(&estimator);
    let sampler = Independent::new(1, 6).unwrap();
    for n in [4usize, 64] {
        let m = 20_000;
        let mut points = Points::new(1, n).unwrap();
        let mut values = Vec::with_capacity(m);
        let mut squared_error = Accumulator::new();
        for k in 0..m {
            sampler.fill((k * n) as u64, &mut points).unwrap();
            let v = biased.estimate(&points).unwrap();
            values.push(v);
            squared_error.push((v - exact) * (v - exact));
        }
        let acc = summary(&values);
        let se = (acc.variance() / m as f64).sqrt();
        let predicted_bias = ConsistentBiased::<()>::bias(exact, n as u64);
        let measured_bias = acc.mean() - exact;
        assert!(
            (measured_bias - predicted_bias).abs() <= 4.5 * se,
            "N = {n}: bias {measured_bias} vs {predicted_bias}"
        );
        // The bias is real: many standard errors away from zero.
        assert!(
            measured_bias.abs() > 10.0 * se,
            "N = {n}: bias {measured_bias} not distinguishable, se {se}"
        );
        let mse = ConsistentBiased::<()>::mse(exact, n as u64, sigma2);
        let mse_se = (squared_error.variance() / m as f64).sqrt();
        assert!(
            (squared_error.mean() - mse).abs() <= 5.0 * mse_se,
            "N = {n}: mse {} vs {mse}",
            squared_error.mean()
        );
    }
}
