//! `invert(sample(u)) == u`, and samples lie in the domain.

use super::*;

// invert(sample(u)) == u, and samples in the domain

/// Canonical coordinates: anywhere, very near 0, very near 1, and the two extremes.
fn canonical_u() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => 0.0..1.0f64,
        1 => 0.0..1e-9f64,
        1 => (1.0 - 1e-9)..1.0f64,
        1 => Just(0.0),
        1 => Just(ONE_BELOW),
        1 => Just(0.5),
    ]
}

fn canonical_point() -> impl Strategy<Value = DVec2> {
    (canonical_u(), canonical_u()).prop_map(|(a, b)| DVec2::new(a, b))
}

/// Distance between two azimuth fractions on the circle (0 and 1 are the same direction).
fn turn_distance(a: f64, b: f64) -> f64 {
    let d = (a - b).abs();
    d.min(1.0 - d)
}

proptest! {
    #![proptest_config(config(2000, 20_250_505))]

    #[test]
    fn disk_inverts_and_stays_inside(u in canonical_point()) {
        for case in disk_cases() {
            let x = case.disk.sample_point(u);
            // Through the trait too: the same point.
            let mut slice = [0.0; 2];
            case.disk.sample(&u.to_array(), &mut slice);
            prop_assert_eq!(DVec2::from_array(slice), x);
            // x carries rounding of about eps (|c| + r) per coordinate (the slack the pdf
            // documents), which moves u by that over r.
            let extent = case.center.abs().max_element() + case.radius;
            prop_assert!((x - case.center).length() <= case.radius + 8.0 * EPS * extent);
            prop_assert_eq!(case.disk.pdf_point(x), 1.0 / case.disk.area());
            let mut back = [0.0; 2];
            case.disk.invert(&slice, &mut back).unwrap();
            let tolerance = 1e-12 + 16.0 * EPS * extent / case.radius;
            prop_assert!(
                (DVec2::from_array(back) - u).abs().max_element() <= tolerance,
                "disk {} {}: {} -> {} -> {:?}", case.center, case.radius, u, x, back
            );
        }
    }

    #[test]
    fn triangle_inverts_and_stays_inside(u in canonical_point()) {
        for case in triangle_cases() {
            let x = case.triangle.sample_point(u);
            let mut slice = [0.0; 3];
            case.triangle.sample(&u.to_array(), &mut slice);
            prop_assert_eq!(DVec3::from_array(slice), x);
            prop_assert_eq!(case.triangle.pdf(&slice), 1.0 / case.triangle.area());
            // Inside by the normal equations, to their rounding (see the chi-square test).
            let (wa, wb, off_plane) = case.weights(x);
            let (scale, longest) = case.scale_and_longest();
            prop_assert!(wa >= -1e-6 && wb >= -1e-6 && 1.0 - wa - wb >= -1e-6);
            prop_assert!(off_plane <= 1e-9 * scale);
            // A point off by delta moves a weight by delta L / (2 A); a sample carries about
            // 10 eps S of rounding and the weights' edge functions add about as much.
            let mut back = [0.0; 2];
            case.triangle.invert(&slice, &mut back).unwrap();
            let tolerance = 1e-12 + 64.0 * EPS * scale * longest / (2.0 * case.area());
            prop_assert!(
                (DVec2::from_array(back) - u).abs().max_element() <= tolerance,
                "{}: {} -> {} -> {:?}", case.name(), u, x, back
            );
        }
    }

    #[test]
    fn directions_invert_and_stay_on_the_support(u in canonical_point()) {
        for case in direction_cases() {
            let mut x = [0.0; 3];
            case.pdf.sample(&u.to_array(), &mut x);
            let d = DVec3::from_array(x);
            // Unit length: the local direction's sin, cos and 1 - s carry a few eps, and the
            // rotation into a frame (itself orthonormal to a few eps) a few more.
            prop_assert!((d.length() - 1.0).abs() <= 16.0 * EPS, "{}: |{}| = {}", case.name, d, d.length());
            prop_assert!(case.on_support(d), "{}: {} off the support", case.name, d);
            let density = case.pdf.pdf(&x);
            if case.cosine {
                prop_assert!(d.z >= 0.0);
                prop_assert!((density - d.z / PI).abs() <= 2.0 * EPS * density);
            } else {
                prop_assert_eq!(density, 1.0 / (TAU * case.height));
            }

            let mut back = [0.0; 2];
            case.pdf.invert(&x, &mut back).unwrap();
            let back = DVec2::from_array(back);
            // Frames of coordinate axes keep every digit: 1e-12 covers the rounding of the
            // trigonometry. Skewed frames give each coordinate an absolute error of a few eps,
            // which moves u0 = (1 - cos) / h by about sqrt(2 u0 / h) times that and the
            // azimuth by that over 2 pi sin theta.
            let (tol0, tol1) = if case.exact_coordinates {
                (1e-12, 1e-12)
            } else {
                let sin_theta = case.sin_theta(u);
                (1e-12 + 16.0 * EPS / case.height.sqrt(), 1e-12 + 8.0 * EPS / (TAU * sin_theta))
            };
            if case.cosine {
                // The concentric map has no seam.
                prop_assert!((back - u).abs().max_element() <= 1e-12, "{}: {} -> {:?}", case.name, u, back);
            } else {
                prop_assert!((back.x - u.x).abs() <= tol0, "{}: {} -> {} -> {}", case.name, u, d, back);
                // At the pole (u0 = 0) the azimuth is undefined.
                if u.x > 0.0 {
                    prop_assert!(
                        turn_distance(back.y, u.y) <= tol1,
                        "{}: {} -> {} -> {}", case.name, u, d, back
                    );
                }
            }
            prop_assert!((0.0..=1.0).contains(&back.x) && (0.0..=1.0).contains(&back.y));
        }
    }
}

#[test]
fn typed_methods_agree_with_the_trait() {
    let u = DVec2::new(0.3, 0.8);
    let mut x = [0.0; 3];
    UniformSphere.sample(&u.to_array(), &mut x);
    assert_eq!(DVec3::from_array(x), UniformSphere.sample_point(u));
    UniformHemisphere.sample(&u.to_array(), &mut x);
    assert_eq!(DVec3::from_array(x), UniformHemisphere.sample_point(u));
    assert_eq!(
        UniformHemisphere.pdf(&x),
        UniformHemisphere.pdf_point(DVec3::from_array(x))
    );
    CosineHemisphere.sample(&u.to_array(), &mut x);
    assert_eq!(DVec3::from_array(x), CosineHemisphere.sample_point(u));
    let mut back = [0.0; 2];
    CosineHemisphere.invert(&x, &mut back).unwrap();
    assert_eq!(
        DVec2::from_array(back),
        CosineHemisphere.invert_point(DVec3::from_array(x))
    );
    let cap = SphericalCap::around(DVec3::new(1.0, -1.0, 0.5), 0.2).unwrap();
    cap.sample(&u.to_array(), &mut x);
    assert_eq!(DVec3::from_array(x), cap.sample_point(u));
    assert_eq!(cap.pdf(&x), cap.pdf_point(DVec3::from_array(x)));
    let triangle = UniformTriangle::new(DVec3::X, DVec3::Y, DVec3::Z).unwrap();
    let pdfs: [&dyn Pdf; 5] = [
        &UniformSphere,
        &UniformHemisphere,
        &CosineHemisphere,
        &cap,
        &triangle,
    ];
    for pdf in pdfs {
        assert_eq!((pdf.canonical_dims(), pdf.dims()), (2, 3));
        // invert reports points it cannot place instead of returning NaN.
        let err = pdf.invert(&[f64::NAN, 0.0, 1.0], &mut back).unwrap_err();
        assert!(
            matches!(err, Error::InvalidParameter { name: "x", .. }),
            "{err}"
        );
    }
    let disk = UniformDisk::unit();
    assert_eq!((disk.canonical_dims(), disk.dims()), (2, 2));
    let err = disk.invert(&[f64::INFINITY, 0.0], &mut back).unwrap_err();
    assert!(
        matches!(err, Error::InvalidParameter { name: "x", .. }),
        "{err}"
    );
}
