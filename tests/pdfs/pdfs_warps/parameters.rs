//! Bad parameters are errors that name them.

use super::*;

// Bad parameters

/// Any float, with the troublesome ones often.
fn wild_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => prop::num::f64::ANY,
        3 => -3.0..3.0f64,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(0.0),
        1 => Just(-0.0),
        1 => Just(1.0),
        1 => Just(-1.0),
        1 => Just(5e-324),
        1 => Just(f64::MIN_POSITIVE),
        1 => Just(1e-160),
        1 => Just(f64::MAX),
        1 => Just(-f64::MAX),
    ]
}

fn wild_vec2() -> impl Strategy<Value = DVec2> {
    (wild_f64(), wild_f64()).prop_map(|(x, y)| DVec2::new(x, y))
}

fn wild_vec3() -> impl Strategy<Value = DVec3> {
    (wild_f64(), wild_f64(), wild_f64()).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

/// The name an `InvalidParameter` error gives (or a panic for any other error).
fn field(err: Error) -> &'static str {
    match err {
        Error::InvalidParameter { name, .. } => name,
        other => panic!("unexpected error {other}"),
    }
}

/// A warp that was accepted must sample finite points of positive, finite density and invert
/// them into the unit square.
fn assert_usable(name: &str, pdf: &dyn Pdf) -> Result<(), TestCaseError> {
    let dims = pdf.dims();
    for u in [
        [0.0, 0.0],
        [0.5, 0.5],
        [ONE_BELOW, ONE_BELOW],
        [0.3, 0.9],
        [1e-300, ONE_BELOW],
    ] {
        let mut x = [0.0; 3];
        pdf.sample(&u, &mut x[..dims]);
        prop_assert!(
            x.iter().all(|v| v.is_finite()),
            "{}: sample({:?}) = {:?}",
            name,
            u,
            x
        );
        let density = pdf.pdf(&x[..dims]);
        prop_assert!(
            density > 0.0 && density.is_finite(),
            "{}: pdf {}",
            name,
            density
        );
        let mut back = [0.0; 2];
        pdf.invert(&x[..dims], &mut back).unwrap();
        prop_assert!(
            back.iter().all(|v| (0.0..=1.0).contains(v)),
            "{}: {:?}",
            name,
            back
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(3000, 20_250_505))]

    #[test]
    fn disk_parameters_are_checked(center in wild_vec2(), radius in wild_f64()) {
        match UniformDisk::new(center, radius) {
            Ok(disk) => {
                prop_assert!(center.is_finite() && radius > 0.0 && radius.is_finite());
                assert_usable("disk", &disk)?;
            }
            Err(e) => {
                // Sensible disks are never refused.
                let sensible = center.is_finite()
                    && center.abs().max_element() < 1e300
                    && (1e-150..1e150).contains(&radius);
                prop_assert!(!sensible, "refused {} {}: {}", center, radius, e);
                let name = field(e);
                prop_assert!(name == "center" || name == "radius", "{}", name);
            }
        }
    }

    #[test]
    fn triangle_parameters_are_checked(a in wild_vec3(), b in wild_vec3(), c in wild_vec3(), t in wild_f64()) {
        match UniformTriangle::new(a, b, c) {
            Ok(triangle) => {
                prop_assert!(a.is_finite() && b.is_finite() && c.is_finite());
                assert_usable("triangle", &triangle)?;
            }
            Err(e) => {
                let name = field(e);
                prop_assert!(["a", "b", "c", "area"].contains(&name), "{}", name);
            }
        }
        // Collinear vertices (up to the rounding of placing c on the line) have no area.
        if a.is_finite() && b.is_finite() && t.is_finite() {
            let on_line = a + t * (b - a);
            if let Err(e) = UniformTriangle::new(a, b, on_line) {
                let name = field(e);
                prop_assert!(["c", "area"].contains(&name), "{}", name);
            } else {
                prop_assert!(false, "collinear {} {} {} accepted", a, b, on_line);
            }
        }
    }

    #[test]
    fn cap_parameters_are_checked(axis in wild_vec3(), cos_theta_max in wild_f64(), theta_max in wild_f64()) {
        let axis_ok = axis.is_finite() && axis != DVec3::ZERO;
        match SphericalCap::around(axis, cos_theta_max) {
            Ok(cap) => {
                prop_assert!(axis_ok && (-1.0..1.0).contains(&cos_theta_max));
                assert_usable("cap", &cap)?;
                prop_assert!((cap.axis().length() - 1.0).abs() <= 2.0 * EPS);
            }
            Err(e) => {
                prop_assert!(!(axis_ok && (-1.0..1.0).contains(&cos_theta_max)));
                let name = field(e);
                prop_assert!(name == "axis" || name == "cos_theta_max", "{}", name);
            }
        }
        match SphericalCap::around_with_angle(axis, theta_max) {
            Ok(cap) => {
                prop_assert!(axis_ok && theta_max > 0.0 && theta_max <= PI);
                assert_usable("cap by angle", &cap)?;
            }
            Err(e) => {
                prop_assert!(!(axis_ok && (1e-150..=PI).contains(&theta_max)));
                let name = field(e);
                prop_assert!(name == "axis" || name == "theta_max", "{}", name);
            }
        }
        match SphericalCap::new(cos_theta_max) {
            Ok(_) => prop_assert!((-1.0..1.0).contains(&cos_theta_max)),
            Err(e) => prop_assert_eq!(field(e), "cos_theta_max"),
        }
    }
}

#[test]
fn bad_parameters_are_named() {
    let named = |r: Result<(), Error>| field(r.unwrap_err());
    let disk = |c: DVec2, r: f64| UniformDisk::new(c, r).map(|_| ());
    assert_eq!(named(disk(DVec2::new(f64::NAN, 0.0), 1.0)), "center");
    assert_eq!(named(disk(DVec2::new(0.0, f64::INFINITY), 1.0)), "center");
    for r in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-160, 1e160] {
        assert_eq!(named(disk(DVec2::ZERO, r)), "radius", "radius {r}");
    }
    assert_eq!(
        named(disk(DVec2::splat(f64::MAX), f64::MAX / 2.0)),
        "radius"
    );

    let tri = |a: DVec3, b: DVec3, c: DVec3| UniformTriangle::new(a, b, c).map(|_| ());
    let (o, x, y) = (DVec3::ZERO, DVec3::X, DVec3::Y);
    assert_eq!(named(tri(DVec3::NAN, x, y)), "a");
    assert_eq!(named(tri(o, DVec3::INFINITY, y)), "b");
    assert_eq!(named(tri(o, x, DVec3::NEG_INFINITY)), "c");
    assert_eq!(named(tri(o, x, o)), "area");
    assert_eq!(named(tri(o, x, 3.0 * x)), "area");
    assert_eq!(named(tri(o, 1e-160 * x, 1e-160 * y)), "area"); // area underflows
    assert_eq!(named(tri(o, 1e160 * x, 1e160 * y)), "area"); // area overflows
    // Thin but well above rounding: accepted.
    assert!(tri(o, x, DVec3::new(0.5, 1e-12, 0.0)).is_ok());

    for c in [1.0, 1.5, -1.0 - 1e-15, f64::NAN, f64::INFINITY] {
        assert_eq!(
            named(SphericalCap::new(c).map(|_| ())),
            "cos_theta_max",
            "{c}"
        );
    }
    for axis in [DVec3::ZERO, DVec3::NAN, DVec3::new(1.0, f64::INFINITY, 0.0)] {
        assert_eq!(
            named(SphericalCap::around(axis, 0.5).map(|_| ())),
            "axis",
            "{axis}"
        );
    }
    for theta in [0.0, -1.0, PI + 1e-9, f64::NAN, f64::INFINITY, 1e-160] {
        assert_eq!(
            named(SphericalCap::with_angle(theta).map(|_| ())),
            "theta_max",
            "{theta}"
        );
    }
    // Tiny and huge axes are normalised without overflow or underflow.
    let cap = SphericalCap::around(DVec3::new(1e-300, 0.0, 1e-300), 0.0).unwrap();
    assert!((cap.axis() - DVec3::new(1.0, 0.0, 1.0).normalize()).length() < 2.0 * EPS);
    let cap = SphericalCap::around(DVec3::splat(f64::MAX), 0.0).unwrap();
    assert!((cap.axis() - DVec3::ONE.normalize()).length() < 2.0 * EPS);
}
