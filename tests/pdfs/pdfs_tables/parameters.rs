//! Bad parameters are errors that name them.

use super::*;

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
