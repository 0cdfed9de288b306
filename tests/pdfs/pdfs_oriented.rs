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
