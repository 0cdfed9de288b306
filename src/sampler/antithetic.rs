//! Antithetic variates (Hammersley & Morton 1956): every point of a sampler followed by its
//! reflection through the centre of the unit cube.
//!
//! For a function `f` monotone in each coordinate, `f(u)` and `f(1 - u)` are negatively
//! correlated, so the pair mean `(f(u) + f(1 - u)) / 2` has variance
//! `(Var f + Cov(f(u), f(1 - u))) / 2`, below the `Var f / 2` of two independent points; for a
//! function symmetric about the centre (`f(u) = f(1 - u)`) the covariance is `+Var f` and
//! antithetic pairs are twice as bad. The seed's appendix gives variance-reduction techniques in
//! section A.3 (A.19-A.29); antithetic sampling is the classical companion of its control
//! variates (Glasserman 2004, section 4.2; Owen, *Monte Carlo theory, methods and examples*,
//! section 8.2).

use super::{PassKind, Sampler, check_block, check_point};
use crate::error::{Error, Result};
use crate::float::ONE_BELOW;
use crate::points::Points;

/// The reflection `u -> (1 - 2^-53) - u` used by [`Antithetic`].
///
/// Samplers give coordinates in `[0, 1)`, where the exact `1 - u` would map 0 to 1. On the
/// grid of multiples of `2^-53` (what independent and digital samplers produce), this map
/// complements the 53-bit fixed-point value `k -> 2^53 - 1 - k`: it is exact, an involution,
/// and maps the uniform distribution on the grid to itself, so it is exactly as unbiased as
/// `1 - u`. Off the grid (for example jittered coordinates) it is `1 - u` shifted by `2^-53`
/// and rounded to nearest, which never leaves `[0, 1)`.
///
/// ```
/// use mcint::sampler::reflect;
/// assert_eq!(reflect(0.0), 1.0 - f64::EPSILON / 2.0);
/// assert_eq!(reflect(1.0 - f64::EPSILON / 2.0), 0.0);
/// assert_eq!(reflect(0.25) + 0.25, 1.0 - f64::EPSILON / 2.0);
/// ```
#[inline]
pub fn reflect(u: f64) -> f64 {
    ONE_BELOW - u
}

/// Antithetic pairs from any sampler: point `2i` is point `i` of the inner sampler and point
/// `2i + 1` is its reflection `reflect(u)` (about `1 - u`, see [`reflect`]) in every
/// coordinate (Hammersley & Morton 1956).
///
/// The mean of a pair, `(f(u) + f(1 - u)) / 2`, has variance `(Var f + Cov(f(u), f(1 - u))) / 2`
/// against `Var f / 2` for two independent points: a gain when `f` is monotone in each
/// coordinate (the covariance is then negative), a loss of up to a factor 2 when `f` is
/// symmetric about the centre (`f(u) = f(1 - u)`, covariance `+Var f`).
///
/// The two points of a pair are dependent by design, so the pair, not the point, is the unit of
/// independence, and [`passes`](Sampler::passes) says so:
/// - an inner sampler of independent points gives `PassKind::Fixed { size: 2 }`: every pair is
///   an independent pass;
/// - an inner sampler with fixed passes of `N` points gives `Fixed { size: 2N }`: pass `p` is
///   inner pass `p` with every point followed by its reflection;
/// - an extensible inner sequence (passes of up to `M` points, any prefix valid) gives
///   `Extensible { max: 2M }`: pass `p` holds the pairs of inner pass `p` in order, so a prefix
///   of even length is the antithetic version of an inner prefix. Use an even number of
///   samples. For digital nets on the `2^-53` grid the reflection complements every bit, a
///   digital shift, so the reflected points form a net of the same quality.
///
/// # Error bars
///
/// Because passes are fixed, the [`Integrator`](crate::Integrator) computes the standard error
/// from the spread of independent replicates, never from the dependent per-point variance. With
/// an independent inner sampler, `.samples(2 * m).replicates(r)` averages `m` pairs per
/// replicate and gives a Student-t error bar on `r - 1` degrees of freedom; `.samples(2)` with
/// many replicates makes each pair a replicate, whose spread is the per-pair variance itself.
///
/// ```
/// use mcint::{Integrator, pdf::UniformBox, sampler::{Antithetic, Independent, PassKind, Sampler}};
/// let pairs = Antithetic::new(Independent::new(1, 0)?)?;
/// assert_eq!(pairs.passes(), PassKind::Fixed { size: 2 });
/// // int_0^1 e^x dx = e - 1: e^x is monotone, so the pairs cancel most of the variance.
/// let e = Integrator::over_box(|x: &[f64]| x[0].exp(), UniformBox::unit(1)?)
///     .sampler(pairs)
///     .samples(2 * 512)
///     .replicates(32)
///     .seed(5)
///     .run()?;
/// let exact = std::f64::consts::E - 1.0;
/// assert!((e.mean - exact).abs() < 4.5 * e.std_error.unwrap());
/// # Ok::<(), mcint::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Antithetic<S> {
    inner: S,
}

impl<S: Sampler> Antithetic<S> {
    /// Pairs every point of `inner` with its reflection. Fails when the doubled pass size
    /// does not fit in `u64`.
    ///
    /// ```
    /// use mcint::sampler::{Antithetic, LatinHypercube, PassKind, Sampler};
    /// let s = Antithetic::new(LatinHypercube::new(2, 16, 0).unwrap()).unwrap();
    /// assert_eq!(s.passes(), PassKind::Fixed { size: 32 });
    /// ```
    pub fn new(inner: S) -> Result<Self> {
        let size = match inner.passes() {
            PassKind::Independent => 1,
            PassKind::Fixed { size } => size,
            PassKind::Extensible { max } => max,
        };
        if size.checked_mul(2).is_none() {
            return Err(Error::invalid(
                "inner sampler pass size",
                size,
                format!(
                    "at most {} points per pass, so that pairs fit",
                    u64::MAX / 2
                ),
            ));
        }
        Ok(Antithetic { inner })
    }

    /// The wrapped sampler.
    ///
    /// ```
    /// use mcint::sampler::{Antithetic, Independent, Sampler};
    /// let s = Antithetic::new(Independent::new(3, 9).unwrap()).unwrap();
    /// assert_eq!(s.inner().name(), "independent");
    /// ```
    pub fn inner(&self) -> &S {
        &self.inner
    }

    /// Unwraps the inner sampler.
    ///
    /// ```
    /// use mcint::sampler::{Antithetic, Independent, Sampler};
    /// let s = Antithetic::new(Independent::new(3, 9).unwrap()).unwrap();
    /// assert_eq!(s.into_inner().seed(), 9);
    /// ```
    pub fn into_inner(self) -> S {
        self.inner
    }
}

impl<S: Sampler> Sampler for Antithetic<S> {
    fn name(&self) -> &'static str {
        "antithetic"
    }

    fn dims(&self) -> usize {
        self.inner.dims()
    }

    fn passes(&self) -> PassKind {
        // `new` checked that doubling fits.
        match self.inner.passes() {
            PassKind::Independent => PassKind::Fixed { size: 2 },
            PassKind::Fixed { size } => PassKind::Fixed { size: 2 * size },
            PassKind::Extensible { max } => PassKind::Extensible { max: 2 * max },
        }
    }

    fn seed(&self) -> u64 {
        self.inner.seed()
    }

    fn reseed(&mut self, seed: u64) {
        self.inner.reseed(seed);
    }

    fn is_randomized(&self) -> bool {
        self.inner.is_randomized()
    }

    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        check_point(self.dims(), out)?;
        self.inner.point(index / 2, out)?;
        if index % 2 == 1 {
            for u in out.iter_mut() {
                *u = reflect(*u);
            }
        }
        Ok(())
    }

    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        check_block(self.dims(), start, points)?;
        let len = points.len();
        if len == 0 {
            return Ok(());
        }
        // The inner points behind indices start .. start + len: one per pair touched.
        let first = start / 2;
        let last = (start + (len as u64 - 1)) / 2;
        let mut inner = Points::new(self.dims(), (last - first + 1) as usize)?;
        self.inner.fill(first, &mut inner)?;
        let parity = (start % 2) as usize;
        for (dim, column) in points.columns_mut().enumerate() {
            let source = inner.column(dim);
            for (i, u) in column.iter_mut().enumerate() {
                let k = i + parity;
                let v = source[k / 2];
                *u = if k % 2 == 1 { reflect(v) } else { v };
            }
        }
        Ok(())
    }
}
