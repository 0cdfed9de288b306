//! The change of variables, and stratification.

use super::*;

// The change of variables, and stratification

/// How the area element of a warp is measured from its differences.
enum Measure {
    /// `|du0 x du1|`: the plane (with z = 0) or a surface in space, where each coordinate of
    /// a sample carries absolute rounding up to `rounding`.
    Surface { rounding: f64 },
    /// Directions within a hemisphere around a coordinate axis: the area element on the sphere
    /// is that of the projection onto the frame's plane `(t, b)` over `cos theta`. Those
    /// coordinates carry only relative rounding, so tiny caps are measured as precisely as
    /// large ones.
    Projected { t: DVec3, b: DVec3, axis: DVec3 },
}

/// Checks `|det J(u)| pdf(sample(u)) = 1` on a 16 x 16 grid of u, by central differences of
/// step `step`, and returns whether the check was precise enough to run. The grid is offset by
/// (0.3, 0.45) of a cell so no point is within 0.009 of the kinks of the concentric map
/// (|a| = |b|) or of Heitz's map (u0 = u1), nor of the square's edges. For smooth maps and a
/// step of 1e-6 the truncation error is about step^2 times the map's third derivative over its
/// first (at most ~3e3 near a pole, at u0 = 0.019: 1e-9); Heitz's map is linear on each side
/// of its kink, so any step below 0.009 has none. Rounding moves each difference quotient by
/// up to `sqrt(3) rounding / step` (relative rounding for `Projected`), which is bounded here
/// for every point and added to the 1e-6 allowed. A bound above 1e-4 means the differences
/// cannot resolve the map: the case is skipped.
fn check_jacobian(name: &str, pdf: &dyn Pdf, measure: &Measure, step: f64) -> bool {
    let dims = pdf.dims();
    let sample = |u: DVec2| {
        let mut x = [0.0; 3];
        pdf.sample(&u.to_array(), &mut x[..dims]);
        DVec3::from_array(x)
    };
    let mut checks = Vec::new();
    for i in 0..16 {
        for j in 0..16 {
            let u = DVec2::new((i as f64 + 0.3) / 16.0, (j as f64 + 0.45) / 16.0);
            let x = sample(u);
            let (plus0, minus0) = (sample(u + DVec2::X * step), sample(u - DVec2::X * step));
            let (plus1, minus1) = (sample(u + DVec2::Y * step), sample(u - DVec2::Y * step));
            let (area, bound) = match *measure {
                Measure::Surface { rounding } => {
                    let du0 = (plus0 - minus0) / (2.0 * step);
                    let du1 = (plus1 - minus1) / (2.0 * step);
                    let area = norm(du0.cross(du1));
                    let error = 3f64.sqrt() * rounding / step;
                    (area, error * (norm(du0) + norm(du1)) / area)
                }
                Measure::Projected { t, b, axis } => {
                    let project = |y: DVec3| DVec2::new(y.dot(t), y.dot(b));
                    let du0 = (project(plus0) - project(minus0)) / (2.0 * step);
                    let du1 = (project(plus1) - project(minus1)) / (2.0 * step);
                    let area = du0.perp_dot(du1).abs() / x.dot(axis);
                    let p = project(x);
                    let error = 2.0 * EPS * p.x.hypot(p.y) / step;
                    (
                        area,
                        error * (du0.length() + du1.length()) / du0.perp_dot(du1).abs(),
                    )
                }
            };
            let density = pdf.pdf(&x.to_array()[..dims]);
            checks.push((u, area * density, bound));
        }
    }
    if checks.iter().any(|&(_, _, bound)| bound > 1e-4) {
        return false;
    }
    for (u, product, bound) in checks {
        assert!(
            (product - 1.0).abs() < 1e-6 + bound,
            "{name}: at u = {u}, |det J| pdf = {product} (rounding bound {bound})"
        );
    }
    true
}

/// Central-difference step for the smooth maps (see `check_jacobian`).
const SMOOTH_STEP: f64 = 1e-6;

#[test]
fn jacobians_match_the_densities() {
    let mut skipped = Vec::new();
    for case in disk_cases() {
        let rounding = 2.0 * EPS * (case.center.abs().max_element() + case.radius);
        let name = format!("disk {} {}", case.center, case.radius);
        if !check_jacobian(
            &name,
            &case.disk,
            &Measure::Surface { rounding },
            SMOOTH_STEP,
        ) {
            skipped.push(name);
        }
    }
    for case in triangle_cases() {
        let (scale, longest) = case.scale_and_longest();
        let rounding = 3.0 * EPS * (scale + longest);
        let measure = Measure::Surface { rounding };
        // Heitz's map is piecewise linear: a long step loses nothing and resolves the
        // triangle far from the origin.
        if !check_jacobian(&case.name(), &case.triangle, &measure, 1e-3) {
            skipped.push(case.name());
        }
    }
    for case in direction_cases() {
        let measure = if case.exact_coordinates && case.height <= 0.5 {
            let (t, b) = case.frame;
            Measure::Projected {
                t,
                b,
                axis: case.axis,
            }
        } else {
            // Unit vectors: a few roundings of numbers at most 1 in each coordinate.
            Measure::Surface {
                rounding: 4.0 * EPS,
            }
        };
        if !check_jacobian(&case.name, case.pdf.as_ref(), &measure, SMOOTH_STEP) {
            skipped.push(case.name);
        }
    }
    // Only two cases are beyond what differences can resolve: the disk of radius 1e-2 at
    // 1e4 from the origin (its points carry rounding of 2e-12, 1e-10 of its radius) and the
    // cap of angle 1e-6 around a skewed axis.
    assert_eq!(
        skipped,
        [
            "disk [10000, -10000] 0.01",
            "SphericalCap::around_with_angle([1, 2, 3], 1e-6)"
        ]
    );
}

/// Strata per axis in the stratification tests (1024 jittered points).
const STRATA: usize = 32;

/// One jittered point per stratum of a `STRATA x STRATA` grid, with its stratum.
fn jittered(seed: u64) -> Vec<(DVec2, (usize, usize))> {
    let mut jitter = Vec::new();
    for_each_canonical(STRATA * STRATA, seed, |u| jitter.push(u));
    let n = STRATA as f64;
    (0..STRATA * STRATA)
        .map(|k| {
            let (i, j) = (k / STRATA, k % STRATA);
            let u = (DVec2::new(i as f64, j as f64) + jitter[k]) / n;
            (u, (i, j))
        })
        .collect()
}

/// The stratum of a fraction in `[0, 1]`.
fn stratum(fraction: f64) -> usize {
    ((fraction * STRATA as f64) as usize).min(STRATA - 1)
}

/// The concentric map's square coordinates `(a, b)` of a point `p` of the unit disk, derived
/// here as a walk: the map sends the boundary of the square `max(|a|, |b|) = r` to the circle
/// of radius `r` at constant speed, from `(r, 0)` at angle 0 counterclockwise, so angle
/// `theta` is arc length `t = 4 r theta / pi` along the square's perimeter `8 r`.
fn concentric_coordinates(p: DVec2) -> DVec2 {
    let r = p.length();
    let mut theta = p.y.atan2(p.x);
    if theta < 0.0 {
        theta += TAU;
    }
    let t = theta / FRAC_PI_4 * r;
    if t < r {
        DVec2::new(r, t)
    } else if t < 3.0 * r {
        DVec2::new(2.0 * r - t, r)
    } else if t < 5.0 * r {
        DVec2::new(-r, 4.0 * r - t)
    } else if t < 7.0 * r {
        DVec2::new(t - 6.0 * r, -r)
    } else {
        DVec2::new(r, t - 8.0 * r)
    }
}

#[test]
fn concentric_strata_stay_stratified() {
    // Each stratum [a0, a1] x [b0, b1] of the square within one wedge (|b| <= a, say) goes to
    // {r in [a0, a1], theta in [pi/4 b0 / r, pi/4 b1 / r]}, of area integral r pi/4 (b1 - b0)
    // / r dr = pi/4 (a1 - a0)(b1 - b0): every stratum's image has the same area, pi / N (the
    // Jacobian check shows the same everywhere). Jittered points must land one per image.
    for (k, case) in disk_cases().iter().enumerate() {
        for (u, (i, j)) in jittered(4000 + k as u64) {
            let x = case.disk.sample_point(u);
            let ab = concentric_coordinates((x - case.center) / case.radius);
            let label = (stratum(0.5 * (ab.x + 1.0)), stratum(0.5 * (ab.y + 1.0)));
            assert_eq!(label, (i, j), "disk {}: u = {u}, x = {x}", case.center);
        }
    }
    // Malley's method keeps the disk's strata: projected onto the disk the cosine-weighted
    // directions land one per image, regions of equal projected solid angle.
    for (u, (i, j)) in jittered(4100) {
        let d = CosineHemisphere.sample_point(u);
        let ab = concentric_coordinates(DVec2::new(d.x, d.y));
        let label = (stratum(0.5 * (ab.x + 1.0)), stratum(0.5 * (ab.y + 1.0)));
        assert_eq!(label, (i, j), "cosine hemisphere: u = {u}, d = {d}");
    }
}

#[test]
fn spherical_strata_stay_stratified() {
    // Archimedes: the zone between 1 - cos theta = s and s + ds has area 2 pi ds, so GRID bands
    // of equal width in s times sectors of equal azimuth are regions of equal solid angle, and
    // the warps send the stratum (i, j) to band i, sector j (azimuth in the documented frame).
    for (k, case) in direction_cases().iter().enumerate() {
        // A skewed frame resolves 1 - cos to about eps / sqrt(h) relative: stay where that is
        // far below the chance of a jittered point within it of a band's edge.
        if case.cosine || !(case.exact_coordinates || case.height >= 1e-4) {
            continue;
        }
        let mut x = [0.0; 3];
        for (u, (i, j)) in jittered(5000 + k as u64) {
            case.pdf.sample(&u.to_array(), &mut x);
            let d = DVec3::from_array(x);
            let s = if case.height <= 1.0 {
                one_minus_cos(d, case.axis)
            } else {
                // Near -axis, 1 - cos = 2 - (1 + cos) keeps its digits through the chord to
                // -axis.
                2.0 - one_minus_cos(d, -case.axis)
            };
            let label = (stratum(s / case.height), stratum(azimuth(d, case.frame)));
            assert_eq!(label, (i, j), "{}: u = {u}, d = {d}", case.name);
        }
    }
}
