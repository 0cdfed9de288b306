//! The uniform density on a triangle in 3-D, sampled by Heitz's low-distortion map.
//!
//! The measure (Jarosz's A.18) is area on the triangle, so the density is `1 / area`; any
//! map from the square to the triangle with a constant Jacobian samples it. The classic one is
//! the square-root map `b_a = 1 - sqrt(u0)`, `b_b = u1 sqrt(u0)` (Turk, "Generating random
//! points in triangles", Graphics Gems, 1990), which squeezes strata near vertex `a`. This
//! warp uses E. Heitz, "A Low-Distortion Map Between Triangle and Square" (2019; pbrt-v4's
//! `SampleUniformTriangle`): the square's two halves on either side of its diagonal are sheared
//! linearly onto the triangle's two halves on either side of its median from `c`, so the map is
//! piecewise linear with Jacobian `1/2` (in barycentric coordinates), keeps strata compact,
//! and its inverse is piecewise linear too, exact, with no seam (it is continuous across the
//! diagonal).

use crate::error::{Error, Result};
use glam::{DVec2, DVec3};

/// Uniform density on the triangle `(a, b, c)` in 3-D space, with respect to area.
///
/// `u` maps to barycentric weights `(b_a, b_b)` of `a` and `b` by Heitz's map,
/// `(u0/2, u1 - u0/2)` when `u0 < u1` and `(u0 - u1/2, u1/2)` otherwise, and to the point
/// `c + b_a (a - c) + b_b (b - c)`. `invert` is its exact inverse (to rounding) for points on
/// the triangle; other points are first projected onto its plane, and the result is clamped to
/// `[0, 1]^2`.
///
/// The density is `1 / area` on the triangle and 0 off it. Sampled points carry rounding, so
/// "on the triangle" is tested with a tolerance `tau = 32 eps S`, where `S` is the largest
/// magnitude of a vertex coordinate: a point counts when it lies within `tau` of the
/// triangle's plane and at most `tau` outside each edge's line (in the plane). That keeps
/// every sample's density positive while points off the triangle by more than rounding get 0.
///
/// ```
/// use mcint::glam::{DVec2, DVec3};
/// use mcint::pdf::{Pdf, UniformTriangle};
/// let t = UniformTriangle::new(DVec3::X, DVec3::Y, DVec3::ZERO).unwrap();
/// assert_eq!(t.area(), 0.5);
/// // u0 < u1: weights (u0/2, u1 - u0/2) = (0.1, 0.5) of a and b.
/// let x = t.sample_point(DVec2::new(0.2, 0.6));
/// assert!((x - DVec3::new(0.1, 0.5, 0.0)).length() < 1e-15);
/// assert_eq!(t.pdf_point(x), 2.0);
/// assert_eq!(t.pdf_point(DVec3::new(0.1, 0.5, 0.1)), 0.0); // off the plane
/// assert!((t.invert_point(x) - DVec2::new(0.2, 0.6)).length() < 1e-15);
/// assert_eq!((t.canonical_dims(), t.dims()), (2, 3));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UniformTriangle {
    a: DVec3,
    b: DVec3,
    c: DVec3,
    /// `a - c` and `b - c`.
    edge_a: DVec3,
    edge_b: DVec3,
    /// Unit normal `edge_a x edge_b / |edge_a x edge_b|`.
    normal: DVec3,
    /// `|edge_a x edge_b|`, twice the area.
    twice_area: f64,
    density: f64,
    /// Distance from the triangle that still counts as on it.
    tolerance: f64,
    /// The lowest barycentric weight of `a`, `b`, `c` that counts as on the triangle: minus
    /// the tolerance divided by the height over the opposite edge.
    min_weight: DVec3,
}

impl UniformTriangle {
    /// The triangle with vertices `a`, `b`, `c`: finite coordinates, edges shorter than
    /// `1e154`, an area that is a normal float, and not degenerate at the precision of its
    /// coordinates: twice the area must exceed
    /// `64 eps S L` (`S` the largest coordinate magnitude, `L` the longest edge), that is its
    /// smallest height must be above `64 eps S`; below that, rounding decides the area.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// use mcint::pdf::UniformTriangle;
    /// // Collinear vertices have no area.
    /// let e = UniformTriangle::new(DVec3::ZERO, DVec3::X, 2.0 * DVec3::X).unwrap_err();
    /// assert!(e.to_string().contains("area"));
    /// assert!(UniformTriangle::new(DVec3::ZERO, DVec3::X, DVec3::splat(f64::NAN)).is_err());
    /// ```
    pub fn new(a: DVec3, b: DVec3, c: DVec3) -> Result<Self> {
        for (name, v) in [("a", a), ("b", b), ("c", c)] {
            if !v.is_finite() {
                return Err(Error::invalid(name, v, "a finite vertex"));
            }
        }
        let (edge_a, edge_b) = (a - c, b - c);
        let cross = accurate_cross(edge_a, edge_b);
        let twice_area = length(cross);
        let edge_lengths = DVec3::new(length(b - c), length(a - c), length(a - b));
        let longest = edge_lengths.max_element();
        let scale = a.abs().max(b.abs()).max(c.abs()).max_element();
        let area = 0.5 * twice_area;
        // Edge functions multiply two edge-sized vectors, so the longest edge squared must
        // stay finite too.
        if !(area.is_finite() && area >= f64::MIN_POSITIVE && (longest * longest).is_finite()) {
            return Err(Error::invalid(
                "area",
                area,
                "a triangle whose area is a positive normal float and whose edges are shorter \
                 than 1e154",
            ));
        }
        if twice_area <= 64.0 * f64::EPSILON * scale * longest {
            return Err(Error::invalid(
                "area",
                area,
                format!(
                    "a triangle that is not degenerate at the precision of its coordinates \
                     (twice the area above 64 eps max|coordinate| longest edge = {})",
                    64.0 * f64::EPSILON * scale * longest
                ),
            ));
        }
        let tolerance = 32.0 * f64::EPSILON * scale;
        Ok(UniformTriangle {
            a,
            b,
            c,
            edge_a,
            edge_b,
            normal: cross / twice_area,
            twice_area,
            density: 1.0 / area,
            tolerance,
            // The weight of a vertex is the distance from the opposite edge over the height,
            // and the height is twice the area over that edge's length.
            min_weight: -tolerance * edge_lengths / twice_area,
        })
    }

    /// The vertices `(a, b, c)`.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// let t = mcint::pdf::UniformTriangle::new(DVec3::ZERO, DVec3::X, DVec3::Z).unwrap();
    /// assert_eq!(t.vertices(), (DVec3::ZERO, DVec3::X, DVec3::Z));
    /// ```
    pub fn vertices(&self) -> (DVec3, DVec3, DVec3) {
        (self.a, self.b, self.c)
    }

    /// The area, whose reciprocal is the density.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// let t = mcint::pdf::UniformTriangle::new(DVec3::ZERO, 2.0 * DVec3::X, 3.0 * DVec3::Y)
    ///     .unwrap();
    /// assert_eq!(t.area(), 3.0);
    /// ```
    pub fn area(&self) -> f64 {
        0.5 * self.twice_area
    }

    /// The unit normal `(a - c) x (b - c) / |(a - c) x (b - c)|`.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// let t = mcint::pdf::UniformTriangle::new(DVec3::X, DVec3::Y, DVec3::ZERO).unwrap();
    /// assert_eq!(t.normal(), DVec3::Z);
    /// ```
    pub fn normal(&self) -> DVec3 {
        self.normal
    }

    /// The point of the triangle for the canonical point `u` in `[0, 1)^2`.
    ///
    /// ```
    /// use mcint::glam::{DVec2, DVec3};
    /// let t = mcint::pdf::UniformTriangle::new(DVec3::X, DVec3::Y, DVec3::Z).unwrap();
    /// assert_eq!(t.sample_point(DVec2::ZERO), DVec3::Z); // u = 0 is vertex c
    /// ```
    pub fn sample_point(&self, u: DVec2) -> DVec3 {
        let (weight_a, weight_b) = if u.x < u.y {
            (0.5 * u.x, u.y - 0.5 * u.x)
        } else {
            (u.x - 0.5 * u.y, 0.5 * u.y)
        };
        self.c + (weight_a * self.edge_a + weight_b * self.edge_b)
    }

    /// The density at `x`: `1 / area` on the triangle (within the tolerance described on
    /// the type), 0 off it.
    ///
    /// ```
    /// use mcint::glam::DVec3;
    /// let t = mcint::pdf::UniformTriangle::new(DVec3::ZERO, DVec3::X, DVec3::Y).unwrap();
    /// assert_eq!(t.pdf_point(DVec3::new(0.5, 0.5, 0.0)), 2.0); // on the hypotenuse
    /// assert_eq!(t.pdf_point(DVec3::new(0.5, 0.51, 0.0)), 0.0);
    /// ```
    pub fn pdf_point(&self, x: DVec3) -> f64 {
        let off_plane = (x - self.c).dot(self.normal).abs();
        let weights = self.barycentric(x);
        if off_plane <= self.tolerance && weights.cmpge(self.min_weight).all() {
            self.density
        } else {
            0.0
        }
    }

    /// The canonical point that [`sample_point`](Self::sample_point) maps to `x` (see the
    /// type's docs for points off the triangle).
    ///
    /// ```
    /// use mcint::glam::{DVec2, DVec3};
    /// let t = mcint::pdf::UniformTriangle::new(DVec3::X, DVec3::Y, DVec3::Z).unwrap();
    /// // Vertex a comes from u = (1, 0), b from (0, 1), c from (0, 0).
    /// assert!((t.invert_point(DVec3::X) - DVec2::new(1.0, 0.0)).length() < 1e-15);
    /// assert!((t.invert_point(DVec3::Y) - DVec2::new(0.0, 1.0)).length() < 1e-15);
    /// ```
    pub fn invert_point(&self, x: DVec3) -> DVec2 {
        let weights = self.barycentric(x);
        let (weight_a, weight_b) = (weights.x, weights.y);
        let u = if weight_b > weight_a {
            DVec2::new(2.0 * weight_a, weight_a + weight_b)
        } else {
            DVec2::new(weight_a + weight_b, 2.0 * weight_b)
        };
        u.clamp(DVec2::ZERO, DVec2::ONE)
    }

    /// Barycentric weights of `a`, `b`, `c` for the projection of `x` onto the plane. Each
    /// is the edge function of the opposite edge, `((q - p) x (x - p)) . n / |n|` for the
    /// edge from `p` to `q`, over twice the area, so its rounding is relative to that edge and
    /// to `x`'s distance from it (`1 - w_a - w_b` would carry the rounding of the other two,
    /// which for a thin triangle can far exceed the tolerance of its short edge).
    fn barycentric(&self, x: DVec3) -> DVec3 {
        let edge_function = |p: DVec3, q: DVec3| (q - p).cross(x - p).dot(self.normal);
        DVec3::new(
            edge_function(self.b, self.c),
            edge_function(self.c, self.a),
            edge_function(self.a, self.b),
        ) / self.twice_area
    }
}

/// `u x v` with each component correct to about one rounding, by Kahan's fused
/// multiply-add evaluation of `p q - r s`. The plain cross product of two nearly parallel
/// edges (a thin triangle) cancels, and its error would tilt the normal by `eps L / h`, which
/// would put the triangle's own far corners off its plane.
fn accurate_cross(u: DVec3, v: DVec3) -> DVec3 {
    let difference_of_products = |p: f64, q: f64, r: f64, s: f64| {
        let rs = r * s;
        let rounding_of_rs = (-r).mul_add(s, rs);
        p.mul_add(q, -rs) + rounding_of_rs
    };
    DVec3::new(
        difference_of_products(u.y, v.z, u.z, v.y),
        difference_of_products(u.z, v.x, u.x, v.z),
        difference_of_products(u.x, v.y, u.y, v.x),
    )
}

/// Length of `v` without overflow or underflow of the squares.
fn length(v: DVec3) -> f64 {
    v.x.hypot(v.y).hypot(v.z)
}

super::warp_to_3d!(UniformTriangle, "a finite point");
