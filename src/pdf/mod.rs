//! Pdfs (warps): maps from canonical points `u` in `[0,1)^k` to points `x` of a domain, with
//! the density of the result.
//!
//! This is Jarosz's warping step (equation A.13, `X_i = a + xi_i (b - a)`) generalised to
//! inverse-cdf sampling of any density, which the `f/pdf` estimator (A.19) needs. As in pbrt and
//! Mitsuba, each pdf keeps `sample`, `pdf` and (where it exists) `invert` side by side. The
//! one-dimensional densities implement [`Pdf1d`] and get [`Pdf`] for free; they sample by the
//! exact inverse cdf, so they are monotone and keep stratified or low-discrepancy `u`
//! stratified.
//!
//! - One-dimensional: [`UniformInterval`], [`Exponential`], [`Linear`], [`Tent`], [`Normal`],
//!   [`TruncatedNormal`], and densities from tables: [`PiecewiseConstant1d`] (a step function)
//!   and [`PiecewiseLinear1d`] (an interpolant).
//! - Several dimensions: [`UniformBox`], [`ProductPdf`] of independent 1-D densities, and
//!   [`PiecewiseConstant2d`] (an image-like table, sampled by marginal and conditional).
//! - Discrete: [`AliasTable`], `O(1)` sampling of an index (a density for counting measure).
//! - Combinations: [`Mixture`] (defensive importance sampling, and the combined density of
//!   multiple importance sampling).
//!
//! The geometric warps take two canonical coordinates to a point of a disk
//! ([`UniformDisk`]), a triangle in space ([`UniformTriangle`]) or the unit sphere of
//! directions ([`UniformSphere`], [`UniformHemisphere`], [`CosineHemisphere`],
//! [`SphericalCap`]), with densities with respect to area or solid angle (the measure of the
//! seed's A.18). Besides the slice-based [`Pdf`] trait they offer typed `sample_point`,
//! `pdf_point` and `invert_point` methods on `glam`'s `DVec2` and `DVec3`. Their maps are the
//! low-distortion ones of pbrt-v4 and Mitsuba 3 (Shirley and Chiu's concentric disk, Heitz's
//! triangle map, `z` linear in `u` on the sphere), with exact inverses; `invert` reports a
//! point that is not finite as an error. Densities of directions assume unit vectors.

mod alias_table;
mod cosine_hemisphere;
mod exponential;
mod geometric_warp;
mod linear;
mod mixture;
mod normal;
mod piecewise_constant;
mod piecewise_constant_2d;
mod piecewise_linear;
mod product;
mod spherical_cap;
mod tent;
mod truncated_normal;
mod uniform;
mod uniform_box;
mod uniform_disk;
mod uniform_hemisphere;
mod uniform_sphere;
mod uniform_triangle;
mod warp3;
mod warp_to_3d;

use warp_to_3d::warp_to_3d;

/// Checks, only in builds with debug assertions, that a slice given to a [`Pdf`] method has the
/// length the pdf takes: `debug_assert_len!(self, sample, u, canonical_dims)` asserts
/// `u.len() == self.canonical_dims()`, and its panic names the pdf type, the method, the slice
/// and both lengths. Everything is inside `debug_assert_eq!`, so release builds evaluate
/// nothing (not even `dims()`) on these hot paths. Use it in a method of an `impl` (it names
/// `Self`).
macro_rules! debug_assert_len {
    ($pdf:expr, $method:ident, $slice:ident, $dims:ident) => {
        debug_assert_eq!(
            $slice.len(),
            $crate::pdf::Pdf::$dims($pdf),
            "{}::{}: {}.len() must equal {}() = {}, but is {}",
            ::std::any::type_name::<Self>(),
            stringify!($method),
            stringify!($slice),
            stringify!($dims),
            $crate::pdf::Pdf::$dims($pdf),
            $slice.len(),
        )
    };
}

pub(crate) use debug_assert_len;

pub use alias_table::AliasTable;
pub use cosine_hemisphere::CosineHemisphere;
pub use exponential::Exponential;
pub use geometric_warp::{GeometricWarp, WarpPoint};
pub use linear::Linear;
pub use mixture::Mixture;
pub use normal::Normal;
pub use piecewise_constant::PiecewiseConstant1d;
pub use piecewise_constant_2d::PiecewiseConstant2d;
pub use piecewise_linear::PiecewiseLinear1d;
pub use product::ProductPdf;
pub use spherical_cap::SphericalCap;
pub use tent::Tent;
pub use truncated_normal::TruncatedNormal;
pub use uniform::UniformInterval;
pub use uniform_box::UniformBox;
pub use uniform_disk::UniformDisk;
pub use uniform_hemisphere::UniformHemisphere;
pub use uniform_sphere::UniformSphere;
pub use uniform_triangle::UniformTriangle;
pub use warp3::{Frame, Oriented, Warp3};

use crate::error::{Error, Result};

/// A probability density on a domain, with a way to sample it from canonical points.
///
/// `sample` maps `u` (length [`canonical_dims`](Self::canonical_dims)) to `x` (length
/// [`dims`](Self::dims)); `pdf(x)` is the density of `sample`'s output with respect to the
/// domain's measure (Lebesgue measure for boxes).
///
/// Every slice must have exactly its length: `u.len() == canonical_dims()` and
/// `x.len() == dims()`. These are hot-path methods, so only builds with debug assertions check
/// this, panicking on any mismatch; release builds still panic on a slice that is too short
/// (as slice indexing does) but give unspecified, memory-safe results for one that is too long.
/// The `# Panics` section of each method says which slice is which.
///
/// ```
/// use mcint::pdf::{Exponential, Pdf};
/// let p = Exponential::new(2.0, 0.0, f64::INFINITY).unwrap();
/// let mut x = [0.0];
/// p.sample(&[0.5], &mut x);
/// assert!((x[0] - 2f64.ln() / 2.0).abs() < 1e-15);
/// assert!((p.pdf(&x) - 1.0).abs() < 1e-15); // 2 exp(-2 x) at the median
/// ```
pub trait Pdf: Send + Sync {
    /// Number of canonical coordinates one sample consumes.
    fn canonical_dims(&self) -> usize;

    /// Number of coordinates of a sampled point `x`.
    fn dims(&self) -> usize;

    /// Maps a canonical point `u` to a point `x` of the domain.
    ///
    /// # Panics
    ///
    /// `u.len()` must equal [`canonical_dims`](Self::canonical_dims) and `x.len()` must equal
    /// [`dims`](Self::dims). With debug assertions a mismatch panics, with a message naming
    /// the pdf, the slice and both lengths. Release builds do not check: a slice that is too
    /// short panics as slice indexing does, one that is too long gives unspecified (but
    /// memory-safe) results.
    ///
    /// ```
    /// use mcint::pdf::{Pdf, UniformBox};
    /// let square = UniformBox::new(vec![0.0, 0.0], vec![2.0, 4.0])?;
    /// let mut x = [0.0; 2]; // dims() = 2
    /// square.sample(&[0.5, 0.25], &mut x); // canonical_dims() = 2
    /// assert_eq!(x, [1.0, 1.0]);
    /// let short = std::panic::catch_unwind(|| square.sample(&[0.5], &mut [0.0; 2]));
    /// assert!(short.is_err()); // in every build
    /// # Ok::<(), mcint::Error>(())
    /// ```
    fn sample(&self, u: &[f64], x: &mut [f64]);

    /// The density at `x` (zero outside the support).
    ///
    /// # Panics
    ///
    /// `x.len()` must equal [`dims`](Self::dims). With debug assertions a mismatch panics,
    /// with a message naming the pdf, the slice and both lengths. Release builds do not
    /// check: a slice that is too short panics as slice indexing does, one that is too long
    /// gives an unspecified (but memory-safe) result.
    ///
    /// ```
    /// use mcint::pdf::{Pdf, UniformBox};
    /// let square = UniformBox::new(vec![0.0, 0.0], vec![2.0, 2.0])?;
    /// assert_eq!(square.pdf(&[1.0, 1.0]), 0.25);
    /// assert!(std::panic::catch_unwind(|| square.pdf(&[1.0])).is_err()); // in every build
    /// # Ok::<(), mcint::Error>(())
    /// ```
    fn pdf(&self, x: &[f64]) -> f64;

    /// Maps `x` back to the canonical point `u` with `sample(u) == x`, where the warp has an
    /// inverse; the default reports that it does not.
    ///
    /// # Panics
    ///
    /// `x.len()` must equal [`dims`](Self::dims) and `u.len()` must equal
    /// [`canonical_dims`](Self::canonical_dims), as for [`sample`](Self::sample), also for
    /// pdfs without an inverse: with debug assertions a mismatch panics, naming the pdf, the
    /// slice and both lengths; release builds panic on a slice that is too short and give
    /// unspecified (but memory-safe) results for one that is too long.
    ///
    /// ```
    /// use mcint::pdf::{Exponential, Pdf};
    /// let p = Exponential::new(1.0, 0.0, f64::INFINITY)?;
    /// let mut u = [0.0];
    /// p.invert(&[2f64.ln()], &mut u)?;
    /// assert!((u[0] - 0.5).abs() < 1e-15);
    /// assert!(std::panic::catch_unwind(|| p.invert(&[1.0], &mut [])).is_err()); // in every build
    /// # Ok::<(), mcint::Error>(())
    /// ```
    fn invert(&self, x: &[f64], u: &mut [f64]) -> Result<()> {
        debug_assert_len!(self, invert, x, dims);
        debug_assert_len!(self, invert, u, canonical_dims);
        // Nothing is read, but a too-short slice panics here as it would in a pdf that inverts.
        assert!(
            x.len() >= self.dims() && u.len() >= self.canonical_dims(),
            "{}::invert: x.len() = {} must be at least dims() = {} and u.len() = {} at least \
             canonical_dims() = {}",
            std::any::type_name::<Self>(),
            x.len(),
            self.dims(),
            u.len(),
            self.canonical_dims()
        );
        Err(Error::Unsupported {
            operation: "invert",
            reason: format!(
                "the warp of {} has no inverse (a pdf that maps canonical points one to one \
                 does: the 1-D, product, disk, sphere and table pdfs)",
                std::any::type_name::<Self>()
            ),
        })
    }
}

/// A one-dimensional density sampled by its exact inverse cdf.
///
/// ```
/// use mcint::pdf::{Linear, Pdf1d};
/// let p = Linear::new(0.0, 1.0, 0.0, 2.0).unwrap(); // density 2x on [0,1]
/// let x = p.sample_1d(0.25);
/// assert!((x - 0.5).abs() < 1e-15);
/// assert!((p.invert_1d(x) - 0.25).abs() < 1e-15);
/// assert_eq!(p.support(), (0.0, 1.0));
/// ```
pub trait Pdf1d: Send + Sync {
    /// Maps `u` in `[0,1)` to `x` by the inverse cdf.
    fn sample_1d(&self, u: f64) -> f64;
    /// The density at `x` (zero outside the support).
    fn pdf_1d(&self, x: f64) -> f64;
    /// The cdf at `x`, which inverts [`sample_1d`](Self::sample_1d).
    fn invert_1d(&self, x: f64) -> f64;
    /// The interval `(lo, hi)` that holds all the probability (`hi` may be infinite).
    fn support(&self) -> (f64, f64);
}

impl<P: Pdf1d + ?Sized> Pdf1d for Box<P> {
    fn sample_1d(&self, u: f64) -> f64 {
        (**self).sample_1d(u)
    }

    fn pdf_1d(&self, x: f64) -> f64 {
        (**self).pdf_1d(x)
    }

    fn invert_1d(&self, x: f64) -> f64 {
        (**self).invert_1d(x)
    }

    fn support(&self) -> (f64, f64) {
        (**self).support()
    }
}

impl<T: Pdf1d> Pdf for T {
    fn canonical_dims(&self) -> usize {
        1
    }

    fn dims(&self) -> usize {
        1
    }

    fn sample(&self, u: &[f64], x: &mut [f64]) {
        debug_assert_len!(self, sample, u, canonical_dims);
        debug_assert_len!(self, sample, x, dims);
        x[0] = self.sample_1d(u[0]);
    }

    fn pdf(&self, x: &[f64]) -> f64 {
        debug_assert_len!(self, pdf, x, dims);
        self.pdf_1d(x[0])
    }

    fn invert(&self, x: &[f64], u: &mut [f64]) -> Result<()> {
        debug_assert_len!(self, invert, x, dims);
        debug_assert_len!(self, invert, u, canonical_dims);
        u[0] = self.invert_1d(x[0]);
        Ok(())
    }
}

/// The fewest floats the spread of a 1-D density must hold. Its samples are rounded to
/// floats, which moves the law they follow from its pdf by about one float spacing over the
/// spread: at this count, a relative error of about 2^-20, below what runs resolve.
const MIN_FLOATS_PER_SPREAD: f64 = (1u64 << 20) as f64;

/// Refuses a 1-D density whose mass lies within `spread` of `at` when the floats there are
/// too coarse to sample it ([`MIN_FLOATS_PER_SPREAD`]); `name` and `value` name the
/// parameter that makes it so narrow.
pub(crate) fn check_resolved(
    name: &'static str,
    value: impl std::fmt::Display,
    spread: f64,
    at: f64,
) -> Result<()> {
    let m = at.abs();
    let spacing = m.next_up() - m;
    if spread >= MIN_FLOATS_PER_SPREAD * spacing {
        return Ok(());
    }
    Err(Error::invalid(
        name,
        value,
        format!(
            "a density spread over at least 2^20 floats: its mass lies within {spread:e} of \
             {at:e}, where floats are {spacing:e} apart, so its samples would not follow its \
             pdf (shift the variable so that the mass lies near 0, or widen it)"
        ),
    ))
}

/// Validates an interval `lo < hi` with a finite width whose reciprocal is a finite normal
/// float, so that a density of order `1 / (hi - lo)` is representable (`hi` may be `+inf` when
/// `hi_may_be_infinite`).
pub(crate) fn check_interval(lo: f64, hi: f64, hi_may_be_infinite: bool) -> Result<()> {
    if !lo.is_finite() {
        return Err(Error::invalid("a", lo, "a finite lower bound"));
    }
    let density = 1.0 / (hi - lo);
    let hi_ok = (hi.is_finite() && density.is_finite() && density >= f64::MIN_POSITIVE)
        || (hi_may_be_infinite && hi == f64::INFINITY);
    if !hi_ok || hi.is_nan() || hi <= lo {
        let allowed = if hi_may_be_infinite {
            format!("an upper bound above a = {lo}, +inf or with 1 / (b - a) a finite normal float")
        } else {
            format!("a finite upper bound above a = {lo} with 1 / (b - a) a finite normal float")
        };
        return Err(Error::invalid("b", hi, allowed));
    }
    Ok(())
}
