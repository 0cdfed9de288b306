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

mod change_of_variables;
mod density;
mod invert;
mod parameters;

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
// Helpers that more than one of the modules above use

/// Length without overflow or underflow of the squares.
fn norm(v: DVec3) -> f64 {
    v.x.hypot(v.y).hypot(v.z)
}

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

/// The azimuth of `x` in `frame`, as a fraction of a turn in `[0, 1)`.
fn azimuth(x: DVec3, frame: (DVec3, DVec3)) -> f64 {
    let turn = x.dot(frame.1).atan2(x.dot(frame.0)) / TAU;
    if turn < 0.0 { turn + 1.0 } else { turn }
}
