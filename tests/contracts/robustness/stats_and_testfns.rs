use super::*;
use mcint::stats::{Estimate, Tolerance};
use mcint::testfns::{Genz, GenzFamily, Polynomial, RoosArnold, SobolGFunction, TestFunction};
use std::time::Duration;

fn family() -> impl Strategy<Value = GenzFamily> {
    prop::sample::select(GenzFamily::ALL.to_vec())
}

/// Sizes: ordinary ones, and ones no vector can hold.
fn length() -> impl Strategy<Value = usize> {
    prop_oneof![4 => 0..12usize, 1 => prop::sample::select(vec![1000, usize::MAX / 2, usize::MAX])]
}

proptest! {
    #![proptest_config(config(256, 0x701))]

    #[test]
    fn tolerance(abs in prop::option::of(real()), rel in prop::option::of(real()), n in count(), mean in real()) {
        let positive = |v: Option<f64>| v.is_none_or(|v| v.is_finite() && v > 0.0);
        // No error bar gets below the mean's rounding: a smaller relative one is refused.
        let relative = |v: Option<f64>| v.is_none_or(|v| v.is_finite() && v >= f64::EPSILON);
        let result = Tolerance::new(abs, rel);
        prop_assert_eq!(result.is_ok(), positive(abs) && relative(rel) && (abs.is_some() || rel.is_some()));
        check(result, &["tol_abs", "tol_rel", "tolerance"], |t| {
            let limited = t.max_evaluations(n);
            assert_eq!(limited.is_ok(), n >= 1);
            check(limited, &["max_evals"], |t| {
                assert_eq!(t.evaluation_limit(), n);
                let t = t.time_limit(Duration::ZERO);
                let target = t.target(mean);
                assert!(target >= 0.0, "target {target}");
                let e = Estimate::from_replicates(&[0.0, 1.0, 2.0], 10).unwrap();
                let _ = t.is_met(&e);
            });
        });
        for v in [abs.unwrap_or(1.0), rel.unwrap_or(1.0)] {
            prop_assert_eq!(Tolerance::absolute(v).is_ok(), positive(Some(v)));
            prop_assert_eq!(Tolerance::relative(v).is_ok(), relative(Some(v)));
        }
    }

    #[test]
    fn genz(
        family in family(),
        a in prop_oneof![
            prop::collection::vec(real(), 0..5),
            prop::collection::vec(1e-3..20.0f64, 0..8),
            (1e-2..10.0f64).prop_map(|a| vec![a; 200]),
        ],
        u in prop_oneof![prop::collection::vec(real(), 0..5), prop::collection::vec(0.0..=1.0f64, 0..8)],
        d in length(),
        x in prop::collection::vec(unit(), 1..5),
    ) {
        let valid = !a.is_empty()
            && a.len() == u.len()
            && a.iter().all(|v| v.is_finite() && *v > 0.0)
            && u.iter().all(|v| (0.0..=1.0).contains(v));
        // Small enough that no family's values or integral overflow (e^(20 * 8)).
        let moderate = a.iter().all(|v| (1e-3..=20.0).contains(v)) && a.len() <= 8;
        let result = Genz::new(family, a, u);
        if !valid || moderate {
            prop_assert_eq!(result.is_ok(), valid);
        }
        check(result, &["a", "u"], |f| {
            assert!(!f.exact().is_nan(), "{} exact = NaN", f.name());
            if moderate {
                assert!(f.exact().is_finite(), "{} exact = {}", f.name(), f.exact());
                let point: Vec<f64> = (0..f.dims()).map(|i| x[i % x.len()]).collect();
                assert!(f.eval(&point).is_finite());
            }
        });
        let result = Genz::with_defaults(family, d);
        prop_assert_eq!(result.is_ok(), (1..=1000).contains(&d));
        check(result, &["d"], |f| {
            assert_eq!(f.dims(), d);
            // The defaults grow with d (a_d = (d + 1) / 2): at d = 1000 the product peak
            // integral overflows, as documented; it is never NaN.
            assert!(!f.exact().is_nan());
            assert!(f.exact().is_finite() || d > 12, "{} exact = {}", f.name(), f.exact());
        });
    }

    #[test]
    fn other_test_functions(a in prop::collection::vec(real(), 0..5), d in length(), c in prop::collection::vec(real(), 0..4)) {
        let valid = !a.is_empty() && a.iter().all(|v| v.is_finite() && *v >= 0.0);
        let result = SobolGFunction::new(a);
        prop_assert_eq!(result.is_ok(), valid);
        check(result, &["a"], |f| assert!(f.exact().is_finite()));
        let result = SobolGFunction::with_defaults(d);
        prop_assert_eq!(result.is_ok(), (1..=1000).contains(&d));
        check(result, &["d"], |f| assert_eq!(f.dims(), d));
        check(RoosArnold::new(d), &["d"], |f| assert_eq!(f.dims(), d));
        let result = Polynomial::new(d, vec![(1.0, vec![1; d.min(3)])]);
        prop_assert_eq!(result.is_ok(), (1..=3).contains(&d));
        check(result, &["dims", "terms"], |p| assert!(p.exact().is_finite()));
        let valid = c.iter().all(|v| v.is_finite());
        let result = Polynomial::from_coefficients(&c);
        if !valid {
            prop_assert!(result.is_err());
        }
        // Coefficients near f64::MAX may overflow the integral, but never to NaN.
        check(result, &["c", "terms", "coefficients"], |p| assert!(!p.exact().is_nan()));
    }
}
