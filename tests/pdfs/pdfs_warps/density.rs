//! Each warp's density integrates to one, and samples follow it (chi-square goodness of fit).

use super::*;

// Integrates to one

#[test]
fn disk_densities_integrate_to_one() {
    // In polar coordinates around the centre, with the rim at a panel edge: pdf * r is linear
    // in r on each side of it, so the rule is exact and only rounding (~1e-15) remains. The
    // ring out to 2 r must hold nothing.
    for case in disk_cases() {
        let density = |r: f64, phi: f64| {
            let (sin, cos) = phi.sin_cos();
            case.disk.pdf_point(case.center + r * DVec2::new(cos, sin)) * r
        };
        let r = case.radius;
        let inside = integrate_2d(density, DVec2::ZERO, DVec2::new(r, TAU), 4);
        let ring = integrate_2d(density, DVec2::new(r, 0.0), DVec2::new(2.0 * r, TAU), 4);
        assert!(
            (inside - 1.0).abs() < 1e-13,
            "disk {} {r}: {inside}",
            case.center
        );
        assert_eq!(ring, 0.0, "disk {} {r}: mass outside", case.center);
        assert!((case.disk.area() - PI * r * r).abs() <= 4.0 * EPS * case.disk.area());
    }
}

#[test]
fn triangle_densities_integrate_to_one() {
    // Over the unit square of collapsed coordinates (s, t) with area element 2 A (1 - s): a
    // polynomial of degree 1, so exact. The relative error allowed is rounding plus the
    // pdf's 1/A computed from a cross product (a few eps).
    for case in triangle_cases() {
        let twice_area = 2.0 * case.area();
        let total = integrate_2d(
            |s, t| case.triangle.pdf_point(case.point(s, t)) * twice_area * (1.0 - s),
            DVec2::ZERO,
            DVec2::ONE,
            2,
        );
        assert!((total - 1.0).abs() < 1e-12, "{}: {total}", case.name());
        assert!(
            (case.triangle.area() / case.area() - 1.0).abs() < 1e-12,
            "{}: area {}",
            case.name(),
            case.triangle.area()
        );
    }
}

#[test]
fn triangle_density_vanishes_off_the_triangle() {
    for case in triangle_cases() {
        let t = &case.triangle;
        let density = 1.0 / case.area();
        let (scale, _) = case.scale_and_longest();
        let normal = (case.a - case.c).cross(case.b - case.c).normalize();
        let centroid = (case.a + case.b + case.c) / 3.0;
        assert!((t.pdf_point(centroid) / density - 1.0).abs() < 1e-12);
        // The documented tolerance is 32 eps S; 1e-9 S off the plane is far beyond it.
        assert_eq!(t.pdf_point(centroid + 1e-9 * scale * normal), 0.0);
        // Just beyond each edge (by 1e-6 of the opposite vertex's distance) and just inside.
        for (p, q, opposite) in [
            (case.a, case.b, case.c),
            (case.b, case.c, case.a),
            (case.c, case.a, case.b),
        ] {
            let mid = 0.5 * (p + q);
            assert_eq!(
                t.pdf_point(mid + 1e-6 * (mid - opposite)),
                0.0,
                "{}",
                case.name()
            );
            assert!(t.pdf_point(mid - 1e-6 * (mid - opposite)) > 0.0);
            // The vertices themselves are on the closed triangle.
            assert!(t.pdf_point(p) > 0.0, "{}: vertex {p}", case.name());
        }
    }
}

#[test]
fn direction_densities_integrate_to_one() {
    // Over (s = 1 - cos theta, phi) with d omega = ds dphi, panels split at the support's edge
    // s = height: the densities are constant or linear in s there, so the rule is exact; the
    // rest of the sphere must hold nothing.
    for case in direction_cases() {
        let frame = test_frame(case.axis);
        let density = |s: f64, phi: f64| {
            case.pdf
                .pdf(&direction(case.axis, frame, s, phi).to_array())
        };
        let h = case.height;
        let inside = integrate_2d(density, DVec2::ZERO, DVec2::new(h, TAU), 2);
        assert!((inside - 1.0).abs() < 1e-12, "{}: {inside}", case.name);
        if h < 2.0 {
            let outside = integrate_2d(density, DVec2::new(h, 0.0), DVec2::new(2.0, TAU), 2);
            assert_eq!(outside, 0.0, "{}: mass off the support", case.name);
        }
        // The density is the documented one at a few points of the support.
        for s in [0.0, 0.3 * h, 0.9 * h] {
            let got = density(s, 1.0);
            assert!(
                (got - case.density(s)).abs() <= 1e-13 * case.density(s),
                "{}: pdf at s = {s}: {got}",
                case.name
            );
        }
    }
}

#[test]
fn direction_densities_vanish_off_the_support() {
    for case in direction_cases() {
        let frame = test_frame(case.axis);
        if case.height < 2.0 {
            // 1e-6 beyond the rim in 1 - cos (relative), and the opposite pole when it is not
            // on the support.
            let beyond = (case.height * (1.0 + 1e-6)).min(0.5 * (case.height + 2.0));
            let x = direction(case.axis, frame, beyond, 0.7);
            assert_eq!(case.pdf.pdf(&x.to_array()), 0.0, "{}: {x}", case.name);
            assert_eq!(case.pdf.pdf(&(-case.axis).to_array()), 0.0, "{}", case.name);
            let within = direction(case.axis, frame, case.height * (1.0 - 1e-6), 0.7);
            assert!(case.pdf.pdf(&within.to_array()) > 0.0, "{}", case.name);
        }
        assert!(case.pdf.pdf(&case.axis.to_array()) > 0.0);
        assert_eq!(case.pdf.pdf(&[f64::NAN, 0.0, 1.0]), 0.0, "{}", case.name);
    }
}

#[test]
fn tiny_caps_keep_their_precision() {
    // theta_max = 1e-10: cos(theta_max) rounds to 1, yet the cap is exact to rounding.
    let theta_max = 1e-10;
    let cap = SphericalCap::with_angle(theta_max).unwrap();
    assert_eq!(cap.cos_theta_max(), 1.0);
    // 1 - cos = 2 sin^2(theta/2) = theta^2/2 (1 - theta^2/12 + ...): 5e-21 to 1e-20 relative.
    assert!((cap.one_minus_cos_theta_max() / 5e-21 - 1.0).abs() < 8.0 * EPS);
    for u0 in [1e-12, 0.25, 0.5, 1.0 - 1e-9, ONE_BELOW] {
        let d = cap.sample_point(DVec2::new(u0, 0.3));
        // The angle from +z is asin(|(x, y)|); uniform in 1 - cos means theta = theta_max
        // sqrt(u0) up to a relative O(theta_max^2) = 1e-20. The sample's sin theta is a
        // product of square roots of rounded factors, and its x and y each add a rounding:
        // about 5 eps in all.
        let theta = d.x.hypot(d.y).asin();
        assert!(
            (theta / (theta_max * u0.sqrt()) - 1.0).abs() < 16.0 * EPS,
            "u0 = {u0}: theta = {theta}"
        );
        assert!((cap.invert_point(d).x / u0 - 1.0).abs() < 16.0 * EPS);
    }
    // The support's edge is resolved to rounding in the angle: 1e-12 of theta_max inside is
    // on the cap, 1e-12 outside is not.
    for (factor, inside) in [(1.0 - 1e-12, true), (1.0 + 1e-12, false)] {
        let theta = factor * theta_max;
        let d = DVec3::new(theta.sin(), 0.0, theta.cos());
        assert_eq!(cap.pdf_point(d) > 0.0, inside, "theta = {theta}");
    }
    // The smallest cap a cosine can describe agrees with the same cap given by its angle.
    let by_cos = SphericalCap::new(ONE_BELOW).unwrap();
    let theta = 2.0 * (0.5 * (1.0 - ONE_BELOW)).sqrt().asin();
    let by_angle = SphericalCap::with_angle(theta).unwrap();
    let ratio = by_cos.solid_angle() / by_angle.solid_angle();
    assert!((ratio - 1.0).abs() < 16.0 * EPS, "{ratio}");
    // Nearly full caps: the excluded cone around -z (half-angle pi - theta_max, exact in
    // floating point) is as sharp.
    let theta_max = PI - 1e-7;
    let excluded = PI - theta_max;
    let full = SphericalCap::with_angle(theta_max).unwrap();
    for (angle, inside) in [
        (excluded * (1.0 + 1e-9), true),
        (excluded * (1.0 - 1e-9), false),
    ] {
        let d = DVec3::new(angle.sin(), 0.0, -angle.cos());
        assert_eq!(full.pdf_point(d) > 0.0, inside, "{angle} from -z");
    }
}

// ---------------------------------------------------------------------------------------------
// Chi-square goodness of fit

/// Samples per goodness-of-fit test.
const GOF_SAMPLES: usize = 1_000_000;
/// Cells per axis of the grids: 256 cells of about 3,900 expected samples each (fewer near
/// the rim of the cosine hemisphere and the triangle's third vertex, still above 200), so a
/// density wrong by 1% over a few cells shows up at p < 1e-5.
const GRID: usize = 16;
fn assert_fits(name: &str, observed: &[u64], expected: &[f64]) {
    let total: f64 = expected.iter().sum();
    assert!(
        (total / GOF_SAMPLES as f64 - 1.0).abs() < 1e-10,
        "{name}: cells hold {total}"
    );
    let fit = chi_square_goodness_of_fit(observed, expected, 5.0).unwrap();
    assert!(
        fit.p_value >= P_REJECT,
        "{name}: chi2 = {} on {} dof, p = {}",
        fit.statistic,
        fit.dof,
        fit.p_value
    );
}

/// Cell index of a fraction in `[0, 1]` on `GRID` cells (1 itself goes in the last cell).
fn cell(fraction: f64) -> usize {
    ((fraction * GRID as f64) as usize).min(GRID - 1)
}

#[test]
fn disk_samples_follow_the_density() {
    // Cells: GRID rings of equal area (edges at r sqrt(i/GRID)) times GRID sectors, plus one
    // cell for anything beyond the rim (which must stay empty).
    for (k, case) in disk_cases().iter().enumerate() {
        let r = case.radius;
        let ring = |i: usize| r * (i as f64 / GRID as f64).sqrt();
        let mut expected = vec![0.0; GRID * GRID + 1];
        for i in 0..GRID {
            for j in 0..GRID {
                let phi = |j: usize| TAU * j as f64 / GRID as f64;
                expected[i * GRID + j] = GOF_SAMPLES as f64
                    * integrate_2d(
                        |rho, phi| {
                            let (sin, cos) = phi.sin_cos();
                            case.disk
                                .pdf_point(case.center + rho * DVec2::new(cos, sin))
                                * rho
                        },
                        DVec2::new(ring(i), phi(j)),
                        DVec2::new(ring(i + 1), phi(j + 1)),
                        1,
                    );
            }
        }
        let slack = 16.0 * EPS * (case.center.abs().max_element() + r);
        let mut observed = vec![0u64; GRID * GRID + 1];
        for_each_canonical(GOF_SAMPLES, 1000 + k as u64, |u| {
            let d = case.disk.sample_point(u) - case.center;
            let rho = d.length();
            let index = if rho <= r + slack {
                let turn = d.y.atan2(d.x) / TAU;
                let turn = if turn < 0.0 { turn + 1.0 } else { turn };
                cell((rho / r).powi(2)) * GRID + cell(turn)
            } else {
                GRID * GRID
            };
            observed[index] += 1;
        });
        assert_fits(
            &format!("UniformDisk({}, {r})", case.center),
            &observed,
            &expected,
        );
    }
}

#[test]
fn triangle_samples_follow_the_density() {
    // Cells: a GRID x GRID grid in the collapsed coordinates (s, t) = (w_a, w_b / (1 - w_a)),
    // computed here from the normal equations; one more cell for points off the triangle.
    for (k, case) in triangle_cases().iter().enumerate() {
        let twice_area = 2.0 * case.area();
        let edge = |i: usize| i as f64 / GRID as f64;
        let mut expected = vec![0.0; GRID * GRID + 1];
        for i in 0..GRID {
            for j in 0..GRID {
                expected[i * GRID + j] = GOF_SAMPLES as f64
                    * integrate_2d(
                        |s, t| case.triangle.pdf_point(case.point(s, t)) * twice_area * (1.0 - s),
                        DVec2::new(edge(i), edge(j)),
                        DVec2::new(edge(i + 1), edge(j + 1)),
                        1,
                    );
            }
        }
        // The normal equations lose up to (longest edge / smallest height)^2 eps, under 1e-7
        // for these triangles; 1e-6 of slack tells rounding from points off the triangle.
        let (scale, _) = case.scale_and_longest();
        let mut observed = vec![0u64; GRID * GRID + 1];
        for_each_canonical(GOF_SAMPLES, 2000 + k as u64, |u| {
            let (wa, wb, off_plane) = case.weights(case.triangle.sample_point(u));
            let inside =
                wa >= -1e-6 && wb >= -1e-6 && 1.0 - wa - wb >= -1e-6 && off_plane <= 1e-9 * scale;
            let index = if inside {
                let s = wa.clamp(0.0, 1.0);
                let t = if s < 1.0 {
                    (wb / (1.0 - s)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                cell(s) * GRID + cell(t)
            } else {
                GRID * GRID
            };
            observed[index] += 1;
        });
        assert_fits(&case.name(), &observed, &expected);
    }
}

#[test]
fn direction_samples_follow_the_density() {
    // Cells: GRID bands of equal width in s = 1 - cos theta across the support (equal solid
    // angle) times GRID sectors of azimuth in a frame built here, plus one cell for the rest
    // of the sphere, whose expected count is integrated from the pdf like the others.
    for (k, case) in direction_cases().iter().enumerate() {
        let frame = test_frame(case.axis);
        let h = case.height;
        let band = |i: usize| h * i as f64 / GRID as f64;
        let sector = |j: usize| TAU * j as f64 / GRID as f64;
        let density = |s: f64, phi: f64| {
            case.pdf
                .pdf(&direction(case.axis, frame, s, phi).to_array())
        };
        let mut expected = vec![0.0; GRID * GRID + 1];
        for i in 0..GRID {
            for j in 0..GRID {
                expected[i * GRID + j] = GOF_SAMPLES as f64
                    * integrate_2d(
                        density,
                        DVec2::new(band(i), sector(j)),
                        DVec2::new(band(i + 1), sector(j + 1)),
                        1,
                    );
            }
        }
        if h < 2.0 {
            expected[GRID * GRID] = GOF_SAMPLES as f64
                * integrate_2d(density, DVec2::new(h, 0.0), DVec2::new(2.0, TAU), 2);
        }
        let mut observed = vec![0u64; GRID * GRID + 1];
        let mut x = [0.0; 3];
        for_each_canonical(GOF_SAMPLES, 3000 + k as u64, |u| {
            case.pdf.sample(&u.to_array(), &mut x);
            let d = DVec3::from_array(x);
            let index = if case.on_support(d) {
                cell(one_minus_cos(d, case.axis) / h) * GRID + cell(azimuth(d, frame))
            } else {
                GRID * GRID
            };
            observed[index] += 1;
        });
        assert_fits(&case.name, &observed, &expected);
    }
}
