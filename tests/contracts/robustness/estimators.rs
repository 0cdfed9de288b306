use super::*;
use mcint::estimator::{
    ConsistentBiased, Estimator, FixedControlVariate, ImportanceEstimator, MisHeuristic,
    MultiSampleMis, OneSampleMis, ProductImportanceEstimator, UniformEstimator,
};
use mcint::pdf::{Exponential, Pdf, UniformBox, UniformInterval};
use mcint::sampler::{Independent, LatinHypercube};
use mcint::{Integrator, Points};

/// A pdf on the unit interval (consumes one canonical coordinate).
fn unit_pdf() -> Box<dyn Pdf> {
    Box::new(UniformInterval::new(0.0, 1.0).unwrap())
}

/// A point mass at 0.5 that consumes no canonical coordinates: a count of it adds to
/// the samples per contribution but not to the canonical dimension.
struct Fixed;

impl Pdf for Fixed {
    fn canonical_dims(&self) -> usize {
        0
    }
    fn dims(&self) -> usize {
        1
    }
    fn sample(&self, _u: &[f64], x: &mut [f64]) {
        x[0] = 0.5;
    }
    fn pdf(&self, _x: &[f64]) -> f64 {
        1.0
    }
}

/// Contributions at the probes are never NaN for an accepted estimator of a finite
/// integrand with positive pdfs, and finite when the parameters are `moderate` (with
/// coefficients near `f64::MAX` a sum of finite terms may overflow). Canonical
/// dimensions beyond 1000 are not probed.
fn exercise<E: Estimator>(e: &E, moderate: bool) {
    let k = e.canonical_dims();
    if k > 1000 {
        return;
    }
    let mut x = vec![0.0; e.domain_dims()];
    for v in [0.25, 0.5, 0.75] {
        let y = e.contribution(&vec![v; k], &mut x);
        assert!(!y.is_nan(), "contribution at {v} = {y}");
        assert!(y.is_finite() || !moderate, "contribution at {v} = {y}");
    }
}

fn heuristic() -> impl Strategy<Value = MisHeuristic> {
    prop_oneof![
        Just(MisHeuristic::Balance),
        Just(MisHeuristic::Maximum),
        real().prop_map(|beta| MisHeuristic::Power { beta }),
        real().prop_map(|alpha| MisHeuristic::Cutoff { alpha }),
    ]
}

proptest! {
    #![proptest_config(config(64, 0x1e5))]

    /// The infallible estimators: contributions of accepted boxes and pdfs are finite.
    #[test]
    fn uniform_and_importance(lo in -1e3..1e3f64, width in 1e-3..1e3f64, rate in prop_oneof![Just(-1.0), Just(1.0), 1e-3..1e3f64]) {
        let domain = UniformBox::new(vec![lo], vec![lo + width]).unwrap();
        exercise(&UniformEstimator::new(|x: &[f64]| x[0], domain), true);
        if let Ok(pdf) = Exponential::new(rate, lo, lo + width) {
            exercise(&ImportanceEstimator::new(|x: &[f64]| x[0], pdf), true);
        }
    }
}

fn technique_count() -> impl Strategy<Value = usize> {
    prop_oneof![3 => 0..4usize, 1 => prop::sample::select(vec![usize::MAX, usize::MAX / 2 + 1, 1 << 40])]
}

proptest! {
    #![proptest_config(config(256, 0xe57))]

    #[test]
    fn control_variate(integral in real(), beta in real()) {
        let f = |x: &[f64]| x[0];
        let result = FixedControlVariate::new(f, f, integral, UniformInterval::new(0.0, 1.0).unwrap());
        prop_assert_eq!(result.is_ok(), integral.is_finite());
        let moderate = |v: f64| v.abs() <= 1e300;
        check(result, &["control_integral"], |cv| {
            exercise(&cv, moderate(integral));
            let with = cv.with_coefficient(beta);
            assert_eq!(with.is_ok(), beta.is_finite() && (beta * integral).is_finite());
            check(with, &["coefficient"], |cv| exercise(&cv, moderate(integral) && moderate(beta)));
        });
    }

    #[test]
    fn mis_heuristics(h in heuristic(), densities in prop::collection::vec(real(), 1..5)) {
        let checked = match h {
            MisHeuristic::Power { beta } => MisHeuristic::power(beta),
            MisHeuristic::Cutoff { alpha } => MisHeuristic::cutoff(alpha),
            other => Ok(other),
        };
        let valid = match h {
            MisHeuristic::Power { beta } => beta.is_finite() && beta > 0.0,
            MisHeuristic::Cutoff { alpha } => (0.0..=1.0).contains(&alpha),
            _ => true,
        };
        prop_assert_eq!(checked.is_ok(), valid);
        check(checked, &["beta", "alpha"], |h| {
            // Valid densities (finite, >= 0, one positive) give weights in [0, 1] that sum
            // to one; anything else gives NaN, never a plausible number.
            let usable = densities.iter().all(|q| q.is_finite() && *q >= 0.0)
                && densities.iter().any(|q| *q > 0.0);
            let mut w = vec![0.0; densities.len()];
            h.weights(&densities, &mut w);
            if usable {
                assert!(w.iter().all(|v| (0.0..=1.0).contains(v)), "{w:?}");
                assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{w:?}");
            } else {
                assert!(w.iter().all(|v| v.is_nan()), "{densities:?} gave {w:?}");
            }
        });
    }

    #[test]
    fn multi_sample_mis(
        counts in prop::collection::vec(technique_count(), 0..4),
        fixed_count in technique_count(),
        wrong_dims: bool,
        h in heuristic(),
    ) {
        let f = |x: &[f64]| x[0] + 1.0;
        let mut techniques: Vec<(Box<dyn Pdf>, usize)> =
            counts.iter().map(|&n| (unit_pdf(), n)).collect();
        techniques.push((Box::new(Fixed), fixed_count));
        if wrong_dims {
            techniques.push((Box::new(UniformBox::unit(2).unwrap()), 1));
        }
        let total = counts.iter().chain([&fixed_count]).try_fold(0usize, |t, &n| t.checked_add(n));
        let result = MultiSampleMis::new(f, techniques, h);
        if total.is_none() || wrong_dims || counts.contains(&0) || fixed_count == 0 {
            prop_assert!(result.is_err());
        }
        check(result, &["n_i", "techniques", "beta", "alpha"], |e| {
            assert_eq!(Some(e.samples_per_contribution()), total);
            if total.is_some_and(|t| t <= 1000) {
                exercise(&e, true);
            }
        });
    }

    #[test]
    fn one_sample_mis(probabilities in prop::collection::vec(prop_oneof![real(), Just(0.5), Just(0.25)], 0..4), h in heuristic()) {
        let f = |x: &[f64]| x[0] + 1.0;
        let techniques: Vec<Box<dyn Pdf>> = (0..2).map(|_| unit_pdf()).collect();
        let sum: f64 = probabilities.iter().sum();
        let valid = probabilities.len() == 2
            && probabilities.iter().all(|c| c.is_finite() && *c >= 0.0)
            && (sum - 1.0).abs() <= 1e-12
            && MisWeighting::check(&h).is_ok();
        let result = OneSampleMis::new(f, techniques, probabilities, h);
        prop_assert_eq!(result.is_ok(), valid);
        check(result, &["probabilities", "techniques", "beta", "alpha"], |e| exercise(&e, true));
    }

    #[test]
    fn product_importance(g in real(), c in real()) {
        // |h| <= 1, so that only the parameters can overflow a contribution.
        let h = |x: &[f64]| 1.0 / (1.0 + x[0]);
        let pdf = || Exponential::new(1.0, 0.0, f64::INFINITY).unwrap();
        let result = ProductImportanceEstimator::new(h, pdf(), g);
        prop_assert_eq!(result.is_ok(), g.is_finite() && g > 0.0);
        check(result, &["g_integral"], |e| exercise(&e, true));
        let result = ProductImportanceEstimator::from_normalization(h, pdf(), c);
        prop_assert_eq!(result.is_ok(), c.is_finite() && c > 0.0 && (1.0 / c).is_finite());
        check(result, &["c"], |e| exercise(&e, true));
    }

    #[test]
    fn consistent_biased(dims in 1..4usize, len in prop_oneof![Just(0usize), 1..50usize]) {
        let e = ConsistentBiased::new(UniformEstimator::new(|x: &[f64]| x[0], UniformBox::unit(2).unwrap()));
        let points = Points::new(dims, len).unwrap();
        let result = e.estimate(&points);
        prop_assert_eq!(result.is_ok(), dims == 2);
        check(result, &[], |mean| assert!(mean.is_finite()));
    }
}

use mcint::estimator::MisWeighting;

proptest! {
    #![proptest_config(config(48, 0x7e9))]

    #[test]
    fn control_variates_fitted_on_a_pilot(
        pilot in prop::sample::select(vec![0u64, 1, 2, 3, 4, 5, 100, 5000]),
        samples in prop::sample::select(vec![0u64, 1, 16, 1000]),
        threads in prop::option::of(prop::sample::select(vec![0usize, 1, 2, usize::MAX])),
        integrals in prop::collection::vec(prop_oneof![Just(0.5), real()], 0..3),
        sampler in 0..3usize,
        seed in any::<u64>(),
    ) {
        let k = integrals.len();
        let mut run = Integrator::with_controls(|x: &[f64]| x[0] * x[0], UniformBox::unit(1).unwrap())
            .pilot(pilot)
            .samples(samples)
            .seed(seed);
        for (j, &integral) in integrals.iter().enumerate() {
            let power = j as i32 + 1;
            run = run.control(move |x: &[f64]| x[0].powi(power), integral);
        }
        if let Some(t) = threads {
            run = run.threads(t);
        }
        run = match sampler {
            0 => run,
            1 => run.sampler(Independent::new(2, 0).unwrap()),
            _ => run.sampler(LatinHypercube::new(1, 16, 0).unwrap()),
        };
        let valid = k >= 1
            && integrals.iter().all(|g| g.is_finite())
            && sampler != 1
            && pilot >= k as u64 + 2
            && samples >= 1
            && (sampler != 2 || samples % 16 == 0)
            && threads != Some(0);
        let result = run.run();
        if !valid {
            prop_assert!(result.is_err());
        } else if integrals.iter().all(|g| g.abs() <= 1e300) {
            prop_assert!(result.is_ok(), "{:?}", result.as_ref().err());
        }
        check(result, &["controls", "control integral", "sampler", "samples", "pilot points", "threads"], |e| {
            assert!(e.mean.is_finite());
            assert_eq!(e.evaluations, e.n + pilot);
        });
    }
}
