//! Multi-sample and one-sample MIS, user weightings, mixtures and the product case are
//! unbiased.

use super::*;

// Unbiasedness

const UNBIASED_SAMPLES: usize = 100_000;

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
