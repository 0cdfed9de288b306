//! Integration tests for the geometric warps (disk, triangle, sphere, hemispheres, spherical
//! caps), in the way Mitsuba 3 tests its warps:
//!
//! - each density integrates to one over its domain, by Gauss-Legendre quadrature written here
//!   in coordinates where the support's boundary is a panel edge (polar coordinates for the
//!   disk, barycentric for the triangle, `(1 - cos theta, phi)` for directions), so the rule
//!   is exact up to rounding;
//! - samples follow the density: a chi-square test of 10^6 samples from the independent
//!   sampler on a grid, with expected counts from quadrature of `pdf` over each cell (never
//!   from `sample`), rejected at p < 1e-5 with fixed seeds;
//! - `invert(sample(u)) == u` to rounding (proptest), away from the seams each warp documents;
//!   samples are unit vectors or points of the domain, with the density the warp promises;
//! - the change of variables is right everywhere: `|det J| pdf = 1` by central differences
//!   (for a uniform warp that is area preservation), and jittered canonical points land one
//!   per region of equal measure, the image of their stratum, labelled by geometry computed
//!   here;
//! - bad parameters give errors naming the field, never a panic.

use crate::common::{ONE_BELOW, P_REJECT, config, gauss_legendre, integrate};
use glam::{DVec2, DVec3};
use mcint::pdf::{
    CosineHemisphere, Pdf, SphericalCap, UniformDisk, UniformHemisphere, UniformSphere,
    UniformTriangle,
};
use mcint::sampler::{Independent, Sampler};
use mcint::stats::chi_square_goodness_of_fit;
use mcint::{Error, Points};
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_4, PI, TAU};

const EPS: f64 = f64::EPSILON;
// ---------------------------------------------------------------------------------------------
// Quadrature

/// Tensor-product rule over `[lo0, hi0] x [lo1, hi1]`, `panels` panels per axis.
fn integrate_2d(f: impl Fn(f64, f64) -> f64, lo: DVec2, hi: DVec2, panels: usize) -> f64 {
    integrate(
        |x| integrate(|y| f(x, y), lo.y, hi.y, panels),
        lo.x,
        hi.x,
        panels,
    )
}

#[test]
fn quadrature_is_exact_where_theory_says() {
    let rule = gauss_legendre();
    assert!((rule.iter().map(|&(_, w)| w).sum::<f64>() - 2.0).abs() < 1e-14);
    assert!((integrate(|x| x.powi(23), 0.0, 1.0, 1) - 1.0 / 24.0).abs() < 1e-15);
    let area = integrate_2d(|x, y| x * y * y, DVec2::ZERO, DVec2::new(2.0, 3.0), 1);
    assert!((area - 2.0 * 9.0).abs() < 1e-13);
}

// ---------------------------------------------------------------------------------------------
// The cases

/// A disk with its parameters.
struct DiskCase {
    disk: UniformDisk,
    center: DVec2,
    radius: f64,
}

fn disk_cases() -> Vec<DiskCase> {
    [
        (DVec2::ZERO, 1.0),
        (DVec2::new(3.0, -2.0), 0.25),
        (DVec2::new(-1e3, 2e3), 7.5),
        (DVec2::new(-0.5, 0.25), 1e-3),
        (DVec2::new(1e4, -1e4), 1e-2),
        (DVec2::new(0.0, 1e-200), 1e150),
    ]
    .into_iter()
    .map(|(center, radius)| DiskCase {
        disk: UniformDisk::new(center, radius).unwrap(),
        center,
        radius,
    })
    .collect()
}

/// A triangle with its vertices.
struct TriangleCase {
    triangle: UniformTriangle,
    a: DVec3,
    b: DVec3,
    c: DVec3,
}

impl TriangleCase {
    fn name(&self) -> String {
        format!("UniformTriangle({}, {}, {})", self.a, self.b, self.c)
    }

    fn area(&self) -> f64 {
        0.5 * (self.a - self.c).cross(self.b - self.c).length()
    }

    /// Largest coordinate magnitude and longest edge.
    fn scale_and_longest(&self) -> (f64, f64) {
        let scale = self
            .a
            .abs()
            .max(self.b.abs())
            .max(self.c.abs())
            .max_element();
        let longest = (self.a - self.b)
            .length()
            .max((self.b - self.c).length())
            .max((self.c - self.a).length());
        (scale, longest)
    }

    /// `c + s (a - c) + t (1 - s) (b - c)`: the unit square onto the triangle (Duffy's
    /// collapsed coordinates), with area element `2 A (1 - s)`.
    fn point(&self, s: f64, t: f64) -> DVec3 {
        self.c + s * (self.a - self.c) + t * (1.0 - s) * (self.b - self.c)
    }

    /// Barycentric weights of `a` and `b` by the normal equations of
    /// `x - c = w_a (a - c) + w_b (b - c)` (a different route from the library's edge
    /// functions; they lose about `eps (L / h)^2`, under 1e-7 for these cases), and the
    /// distance of `x` from the plane along the normal `(a - c) x (b - c)` (exact for the
    /// sliver, whose vertices are dyadic numbers of few bits).
    fn weights(&self, x: DVec3) -> (f64, f64, f64) {
        let (e0, e1, d) = (self.a - self.c, self.b - self.c, x - self.c);
        let (g00, g01, g11) = (e0.dot(e0), e0.dot(e1), e1.dot(e1));
        let (r0, r1) = (e0.dot(d), e1.dot(d));
        let det = g00 * g11 - g01 * g01;
        let wa = (r0 * g11 - r1 * g01) / det;
        let wb = (g00 * r1 - g01 * r0) / det;
        let normal = e0.cross(e1);
        let off_plane = d.dot(normal).abs() / normal.length();
        (wa, wb, off_plane)
    }
}

fn triangle_cases() -> Vec<TriangleCase> {
    let v = DVec3::new;
    [
        (DVec3::X, DVec3::Y, DVec3::ZERO),
        (v(1.0, 2.0, 3.0), v(-2.0, 0.5, 1.0), v(0.3, -1.0, 2.0)),
        // A sliver, tilted in space: height 2^-14 sqrt(2) = 8.6e-5 over a base of sqrt(3).
        (
            v(0.0, 0.0, 1.0),
            v(1.0, 1.0, 0.0),
            v(0.5 + 2f64.powi(-14), 0.5 - 2f64.powi(-14), 0.5),
        ),
        // A needle: a short edge of 1e-3 opposite a far vertex.
        (v(0.0, 0.0, 0.0), v(1e-3, 0.0, 0.0), v(0.3, 1.0, 0.2)),
        // Obtuse and thin, far from the origin.
        (
            v(1e3, 1e3, -1e3),
            v(1e3 + 1.0, 1e3, -1e3),
            v(1e3 + 2.0, 1e3 + 0.01, -1e3 + 0.01),
        ),
    ]
    .into_iter()
    .map(|(a, b, c)| TriangleCase {
        triangle: UniformTriangle::new(a, b, c).unwrap(),
        a,
        b,
        c,
    })
    .collect()
}

/// A warp to directions: the support is the cap `1 - cos theta <= height` around `axis`.
struct DirectionCase {
    name: String,
    pdf: Box<dyn Pdf>,
    axis: DVec3,
    /// `1 - cos theta_max` (2 for the sphere, 1 for the hemispheres).
    height: f64,
    /// `1 + cos theta_max`, to full precision.
    complement: f64,
    /// The frame `(t, b)` in which the warp documents `u1` as the azimuth.
    frame: (DVec3, DVec3),
    /// Density `cos theta / pi` (else uniform on the support).
    cosine: bool,
    /// The frame is made of signed unit coordinate vectors, so a direction's coordinates in
    /// it carry only relative rounding.
    exact_coordinates: bool,
}

impl DirectionCase {
    /// The density this case should have at `s = 1 - cos theta` (on the support).
    fn density(&self, s: f64) -> f64 {
        if self.cosine {
            (1.0 - s) / PI
        } else {
            1.0 / (TAU * self.height)
        }
    }

    /// Whether `x` is on the support, by its chord distance from the axis (or, for caps larger
    /// than a hemisphere, from `-axis`) with a slack of `16 eps (1 + chord)` for the rounding of
    /// a sampled direction (at most a few eps in each coordinate).
    fn on_support(&self, x: DVec3) -> bool {
        if self.height <= 1.0 {
            let rim = (2.0 * self.height).sqrt();
            norm(x - self.axis) <= rim + 16.0 * EPS * (1.0 + rim)
        } else {
            let rim = (2.0 * self.complement).sqrt();
            norm(x + self.axis) >= rim - 16.0 * EPS * (1.0 + rim)
        }
    }

    /// `sin theta` of the sample of `u` for the uniform warps, from `1 - cos = u0 h` and
    /// `1 + cos = g + (1 - u0) h`.
    fn sin_theta(&self, u: DVec2) -> f64 {
        assert!(!self.cosine);
        (u.x * self.height * (self.complement + (1.0 - u.x) * self.height)).sqrt()
    }
}

/// A frame `(t, b)` around `axis` built here by Gram-Schmidt (independent of the library's).
fn test_frame(axis: DVec3) -> (DVec3, DVec3) {
    let helper = if axis.x.abs() < 0.6 {
        DVec3::X
    } else {
        DVec3::Y
    };
    let t = (helper - axis * helper.dot(axis)).normalize();
    (t, axis.cross(t))
}

/// The direction at `1 - cos theta = s` and azimuth `phi` around `axis`.
fn direction(axis: DVec3, frame: (DVec3, DVec3), s: f64, phi: f64) -> DVec3 {
    let sin_theta = (s * (2.0 - s)).max(0.0).sqrt();
    let (sin_phi, cos_phi) = phi.sin_cos();
    frame.0 * (sin_theta * cos_phi) + frame.1 * (sin_theta * sin_phi) + axis * (1.0 - s)
}

/// `1 - cos theta` of a unit direction from its chord distance to `axis`:
/// `|x - axis|^2 = 2 - 2 cos theta`, with no cancellation for small angles.
fn one_minus_cos(x: DVec3, axis: DVec3) -> f64 {
    let chord = norm(x - axis);
    0.5 * chord * chord
}

fn cap_case(name: String, cap: SphericalCap, exact_coordinates: bool) -> DirectionCase {
    let (t, b, axis) = cap.frame();
    let height = cap.one_minus_cos_theta_max();
    DirectionCase {
        name,
        axis,
        height,
        complement: 2.0 - height,
        frame: (t, b),
        cosine: false,
        exact_coordinates,
        pdf: Box::new(cap),
    }
}

fn direction_cases() -> Vec<DirectionCase> {
    let v = DVec3::new;
    let z_frame = (DVec3::X, DVec3::Y);
    let mut cases = vec![
        DirectionCase {
            name: "UniformSphere".into(),
            pdf: Box::new(UniformSphere),
            axis: DVec3::Z,
            height: 2.0,
            complement: 0.0,
            frame: z_frame,
            cosine: false,
            exact_coordinates: true,
        },
        DirectionCase {
            name: "UniformHemisphere".into(),
            pdf: Box::new(UniformHemisphere),
            axis: DVec3::Z,
            height: 1.0,
            complement: 1.0,
            frame: z_frame,
            cosine: false,
            exact_coordinates: true,
        },
        DirectionCase {
            name: "CosineHemisphere".into(),
            pdf: Box::new(CosineHemisphere),
            axis: DVec3::Z,
            height: 1.0,
            complement: 1.0,
            frame: z_frame,
            cosine: true,
            exact_coordinates: true,
        },
    ];
    let z_caps = [0.5, 0.0, -1.0, -1.0 + 1e-6, 0.999, 1.0 - EPS / 2.0];
    for c in z_caps {
        let mut case = cap_case(
            format!("SphericalCap::new({c})"),
            SphericalCap::new(c).unwrap(),
            true,
        );
        // 1 + c is exact for c <= -1/2 and rounded once otherwise: full precision.
        case.complement = 1.0 + c;
        cases.push(case);
    }
    for theta in [1e-9, 1e-150, PI - 1e-7] {
        let cap = SphericalCap::with_angle(theta).unwrap();
        let mut case = cap_case(format!("SphericalCap::with_angle({theta:e})"), cap, true);
        case.complement = 2.0 * (0.5 * (PI - theta)).sin().powi(2);
        cases.push(case);
    }
    for (axis, c) in [
        (v(1.0, 2.0, 3.0), 0.3),
        (v(-1.0, 0.5, -2.0), -0.5),
        (DVec3::NEG_Z, 0.9),
        (v(1e-9, 0.0, -1.0), 0.0),
        (v(0.0, -4.0, 0.0), 0.99),
    ] {
        let cap = SphericalCap::around(axis, c).unwrap();
        // A frame of signed coordinate axes rotates without rounding.
        let (t, b, n) = cap.frame();
        let exact = [t, b, n]
            .iter()
            .all(|w| w.to_array().iter().all(|&x| x == 0.0 || x.abs() == 1.0));
        let mut case = cap_case(format!("SphericalCap::around({axis}, {c})"), cap, exact);
        case.complement = 1.0 + c;
        cases.push(case);
    }
    for (axis, theta) in [(v(1.0, 2.0, 3.0), 1e-6), (v(0.3, -0.4, 0.5), PI - 1e-3)] {
        let cap = SphericalCap::around_with_angle(axis, theta).unwrap();
        let mut case = cap_case(
            format!("SphericalCap::around_with_angle({axis}, {theta:e})"),
            cap,
            false,
        );
        case.complement = 2.0 * (0.5 * (PI - theta)).sin().powi(2);
        cases.push(case);
    }
    cases
}

#[test]
fn the_cases_are_what_they_claim() {
    // The frames documented for u1 are orthonormal and right-handed around each axis.
    for case in direction_cases() {
        let (t, b) = case.frame;
        let n = case.axis;
        for (x, y) in [(t, b), (t, n), (b, n)] {
            assert!(x.dot(y).abs() < 4.0 * EPS, "{}: frame", case.name);
        }
        assert!(
            (t.cross(b) - n).length() < 4.0 * EPS,
            "{}: frame",
            case.name
        );
        assert!(case.height > 0.0 && case.height <= 2.0);
        assert!((case.height + case.complement - 2.0).abs() <= 2.0 * EPS);
    }
    // Caps around signed coordinate axes get frames of signed coordinate axes (which the
    // cap's accuracy notes rely on); skewed axes do not.
    for case in direction_cases() {
        let coordinate_axis = ["[0, 0, -1]", "[0, -4, 0]", "::new(", "::with_angle("]
            .iter()
            .any(|tag| case.name.contains(tag));
        if case.name.starts_with("SphericalCap") {
            assert_eq!(case.exact_coordinates, coordinate_axis, "{}", case.name);
        }
    }
}

// ---------------------------------------------------------------------------------------------
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
/// Calls `f` with `count` canonical points from the independent sampler with `seed`.
fn for_each_canonical(count: usize, seed: u64, mut f: impl FnMut(DVec2)) {
    const BLOCK: usize = 1 << 16;
    let sampler = Independent::new(2, seed).unwrap();
    let mut points = Points::new(2, BLOCK).unwrap();
    let mut start = 0;
    while start < count {
        let len = BLOCK.min(count - start);
        points.set_len(len);
        sampler.fill(start as u64, &mut points).unwrap();
        for (&u0, &u1) in points.column(0).iter().zip(points.column(1)) {
            f(DVec2::new(u0, u1));
        }
        start += len;
    }
}

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

/// The azimuth of `x` in `frame`, as a fraction of a turn in `[0, 1)`.
fn azimuth(x: DVec3, frame: (DVec3, DVec3)) -> f64 {
    let turn = x.dot(frame.1).atan2(x.dot(frame.0)) / TAU;
    if turn < 0.0 { turn + 1.0 } else { turn }
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

// ---------------------------------------------------------------------------------------------
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

// ---------------------------------------------------------------------------------------------
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

/// Length without overflow or underflow of the squares.
fn norm(v: DVec3) -> f64 {
    v.x.hypot(v.y).hypot(v.z)
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

// ---------------------------------------------------------------------------------------------
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
