//! Hemisphere and cap warps turned to any normal by an orthonormal frame, and integrands of
//! directions handed glam vectors (`Integrator::over_warp`). Statistical checks use fixed seeds
//! and 5 standard errors.

use mcint::Integrator;
use mcint::glam::{DVec2, DVec3};
use mcint::pdf::{
    CosineHemisphere, Pdf, SphericalCap, UniformHemisphere, UniformSphere, UniformTriangle, Warp3,
};

/// Normals in every octant, on the axes, and next to -z (where the frame's construction
/// changes branch).
fn normals() -> Vec<DVec3> {
    vec![
        DVec3::Z,
        DVec3::NEG_Z,
        DVec3::X,
        DVec3::new(1.0, -2.0, 3.0),
        DVec3::new(-0.3, 0.2, -5.0),
        DVec3::new(1e-9, -1e-9, -1.0),
        DVec3::new(-1.0, -1.0, 0.0),
    ]
}

fn warps(n: DVec3) -> Vec<(&'static str, Box<dyn Warp3>)> {
    vec![
        (
            "uniform hemisphere",
            Box::new(UniformHemisphere.about(n).unwrap()),
        ),
        (
            "cosine hemisphere",
            Box::new(CosineHemisphere.about(n).unwrap()),
        ),
        (
            "cap",
            Box::new(SphericalCap::new(0.6).unwrap().about(n).unwrap()),
        ),
    ]
}

#[test]
fn turned_warps_sample_about_their_normal_and_invert() {
    for n in normals() {
        let axis = n.normalize();
        for (name, warp) in warps(n) {
            for i in 0..64 {
                let u = DVec2::new(
                    (i as f64 + 0.5) / 64.0,
                    ((i * 37) % 64) as f64 / 64.0 + 0.007,
                );
                let d = warp.sample_point(u);
                assert!(
                    (d.length() - 1.0).abs() < 1e-12,
                    "{name} {n}: |d| = {}",
                    d.length()
                );
                assert!(d.dot(axis) >= -1e-12, "{name} {n}: {d} below the horizon");
                assert!(warp.pdf_point(d) > 0.0, "{name} {n}");
                let back = warp.invert_point(d);
                // Rounding of the rotation and the concentric map: measured below 1e-15.
                assert!(
                    (back - u).length() < 1e-13,
                    "{name} {n}: {u} -> {d} -> {back}"
                );
            }
        }
    }
}

#[test]
fn turned_densities_integrate_to_one_over_the_sphere() {
    for n in normals() {
        for (name, warp) in warps(n) {
            let density = move |d: DVec3| warp.pdf_point(d);
            let e = Integrator::over_warp(density, UniformSphere)
                .samples(200_000)
                .seed(5)
                .run()
                .unwrap();
            let se = e.std_error.unwrap();
            assert!(
                (e.mean - 1.0).abs() < 5.0 * se,
                "{name} {n}: {} +- {se}",
                e.mean
            );
        }
    }
}

#[test]
fn cosine_weighted_directions_average_two_thirds_of_the_normal() {
    // E[d] = (2/3) n for the density cos(theta) / pi about n.
    for n in normals() {
        let axis = n.normalize();
        let warp = CosineHemisphere.about(n).unwrap();
        for k in 0..3 {
            let component = move |d: DVec3| d[k];
            let e = Integrator::with_pdf(
                move |x: &[f64]| component(DVec3::from_slice(x)) * warp.pdf(x),
                warp,
            )
            .samples(100_000)
            .seed(k as u64)
            .run()
            .unwrap();
            let se = e.std_error.unwrap();
            let want = 2.0 / 3.0 * axis[k];
            assert!(
                (e.mean - want).abs() < 5.0 * se + 1e-15,
                "{n} [{k}]: {} vs {want}",
                e.mean
            );
        }
    }
}

#[test]
fn integrands_of_points_of_a_triangle_get_vectors() {
    let (a, b, c) = (
        DVec3::ZERO,
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(0.0, 3.0, 1.0),
    );
    let area = 0.5 * (b - a).cross(c - a).length();
    let triangle = UniformTriangle::new(a, b, c).unwrap();
    let e = Integrator::over_warp(|_: DVec3| 1.0, triangle)
        .samples(1000)
        .run()
        .unwrap();
    assert!((e.mean - area).abs() < 1e-12 * area);
    // The mean of x over the triangle is the centroid's x, times the area.
    let e = Integrator::over_warp(|p: DVec3| p.x, triangle)
        .samples(100_000)
        .seed(1)
        .run()
        .unwrap();
    let want = area * (a.x + b.x + c.x) / 3.0;
    assert!((e.mean - want).abs() < 5.0 * e.std_error.unwrap());
}

#[test]
fn integrands_of_points_of_a_disk_get_two_vectors() {
    use mcint::pdf::UniformDisk;
    let (centre, radius) = (DVec2::new(1.0, 2.0), 0.5);
    let disk = UniformDisk::new(centre, radius).unwrap();
    let area = std::f64::consts::PI * radius * radius;
    let e = Integrator::over_warp(|_: DVec2| 1.0, disk)
        .samples(1000)
        .run()
        .unwrap();
    assert!((e.mean - area).abs() < 1e-12 * area);
    // The integral of x over the disk is the centre's x times the area; of |p - c|^2 it is
    // pi R^4 / 2.
    let e = Integrator::over_warp(|p: DVec2| p.x, disk)
        .samples(100_000)
        .seed(2)
        .run()
        .unwrap();
    assert!((e.mean - area * centre.x).abs() < 5.0 * e.std_error.unwrap());
    let second = move |p: DVec2| (p - centre).length_squared();
    let e = Integrator::over_warp(second, disk)
        .samples(100_000)
        .seed(3)
        .run()
        .unwrap();
    let want = std::f64::consts::PI * radius.powi(4) / 2.0;
    assert!((e.mean - want).abs() < 5.0 * e.std_error.unwrap());
}

/// The integral of a cosine lobe about `n` over `warp`'s directions, with `f64` and with
/// `f32` vectors and values: the f32 points are the f64 ones rounded, with the density of the
/// unrounded point, so the estimates differ by f32 rounding only.
fn f32_matches_f64<W: Warp3 + Clone + 'static>(name: &str, warp: W, n: DVec3) {
    use mcint::glam::Vec3;
    let lobe = move |d: DVec3| d.dot(n).max(0.0).powi(8);
    let n32 = n.as_vec3();
    let lobe32 = move |d: Vec3| d.dot(n32).max(0.0).powi(8);
    let run64 = Integrator::over_warp(lobe, warp.clone())
        .samples(20_000)
        .seed(4)
        .run()
        .unwrap();
    let run32 = Integrator::over_warp(lobe32, warp)
        .samples(20_000)
        .seed(4)
        .run()
        .unwrap();
    let gap = (run64.mean - run32.mean).abs();
    assert!(
        gap <= 1e-5 * run64.mean.abs(),
        "{name}: {run64:?} vs {run32:?}"
    );
}

#[test]
fn renderers_f32_vectors_and_values_get_the_f64_runs_estimate() {
    use mcint::glam::Vec2;
    use mcint::pdf::UniformDisk;
    let n = DVec3::new(0.3, -1.0, 0.4).normalize();
    f32_matches_f64("uniform hemisphere", UniformHemisphere.about(n).unwrap(), n);
    f32_matches_f64("cosine hemisphere", CosineHemisphere.about(n).unwrap(), n);
    f32_matches_f64("cap", SphericalCap::new(0.6).unwrap().about(n).unwrap(), n);
    f32_matches_f64("sphere", UniformSphere, n);
    let disk = UniformDisk::new(DVec2::new(1.0, 2.0), 0.5).unwrap();
    let run64 = Integrator::over_warp(|p: DVec2| p.x * p.y, disk)
        .seed(1)
        .run()
        .unwrap();
    let run32 = Integrator::over_warp(|p: Vec2| p.x * p.y, disk)
        .seed(1)
        .run()
        .unwrap();
    assert!((run64.mean - run32.mean).abs() <= 1e-6 * run64.mean.abs());
}

#[test]
fn a_point_rounded_across_a_caps_edge_keeps_its_density() {
    use mcint::glam::Vec3;
    // A cap 1e-4 rad wide: its directions are within f32 rounding of its edge, where the f32
    // point's own density could be zero. Every value must stay finite: f = 1 integrates to the
    // cap's solid angle exactly.
    let cap = SphericalCap::around_with_angle(DVec3::new(1.0, 2.0, 3.0), 1e-4).unwrap();
    let e = Integrator::over_warp(|_: Vec3| 1.0f32, cap)
        .samples(10_000)
        .run()
        .unwrap();
    // 2 pi (1 - cos theta), written without the cancellation of 1 - cos.
    let solid_angle = 4.0 * std::f64::consts::PI * (0.5e-4f64).sin().powi(2);
    assert!((e.mean - solid_angle).abs() <= 1e-9 * solid_angle, "{e:?}");
}

/// A uniform hemisphere turned about an oblique normal has a positive density at its own
/// samples on the equator: the round trip through the frame left one a rounding below it
/// (local z = -5.6e-17), where the density was 0.
#[test]
fn turned_hemispheres_keep_their_density_on_the_equator() {
    let turned = UniformHemisphere.about(DVec3::new(1.0, 2.0, 3.0)).unwrap();
    let mut below = 0;
    for i in 0..1000 {
        let u = DVec2::new(1.0 - f64::EPSILON / 2.0, (i as f64 + 0.5) / 1000.0);
        let d = turned.sample_point(u);
        below += usize::from(turned.frame().to_local(d).z < 0.0);
        assert_eq!(turned.pdf_point(d), 0.5 / std::f64::consts::PI, "{u:?}");
    }
    // The case arises: some equator samples do come back below it.
    assert!(below > 0);
    // Well below the equator the density is still 0.
    assert_eq!(turned.pdf_point(-turned.frame().normal()), 0.0);
}
