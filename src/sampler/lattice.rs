//! Rank-1 lattice rules, embedded in base 2, with Cranley-Patterson random shifts.
//!
//! A rank-1 lattice rule with `N` points and generating vector `z` (Korobov 1959; Sloan & Joe
//! 1994) is the point set `x_k = frac(k z / N)`, `k = 0 .. N`. It integrates a trigonometric
//! polynomial `exp(2 pi i h.x)` exactly (to zero) unless `h` lies in the dual lattice
//! `h.z ≡ 0 (mod N)`, so for smooth periodic integrands, whose Fourier coefficients decay
//! fast, the error is far below Monte Carlo's.
//!
//! An *extensible* (embedded) lattice (Hickernell, Hong, L'Ecuyer & Lemieux 2000) lists the
//! points in radical-inverse order, `x_i = frac(phi_2(i) z)` where `phi_2` is the base-2
//! van der Corput radical inverse, so that every prefix of `2^m` points is itself the lattice
//! rule with `N = 2^m` and generating vector `z mod 2^m`. The default vector is F. Y. Kuo's
//! `lattice-33002-1024-1048576.9125`, built by the component-by-component construction of
//! Cools, Kuo & Nuyens (2006) to be good for every `N = 2^10 .. 2^20` (order-2 weights), in up
//! to 9125 dimensions (see `data/lattice/README.md`).
//!
//! Randomization is the Cranley & Patterson (1976) rotation: a uniform shift `Delta` added to
//! every point modulo one. Each point of the shifted rule is uniform on the cube, so the
//! estimate is unbiased, and independent shifts give independent replicates whose spread is an
//! honest error bar.
//!
//! Everything is exact integer arithmetic on 64-bit fixed point: with `M = 2^m` the most
//! points a pass holds and `i < M`, `i.reverse_bits()` is `phi_2(i) * 2^64`, and
//! `i.reverse_bits() * z_j mod 2^64` is `(rev_m(i) z_j mod M) * 2^(64-m)`, the unshifted
//! coordinate as a 64-bit fraction. The shift is a random 64-bit fraction added with wrapping
//! (which is "modulo one"), and only the final conversion keeps the top 53 bits, so every
//! coordinate lies in `[0, 1)` by construction and unshifted coordinates are exact.
//!
//! References:
//! - N. M. Korobov, "The approximate computation of multiple integrals", Dokl. Akad. Nauk SSSR
//!   124 (1959), 1207-1210.
//! - I. H. Sloan & S. Joe, *Lattice Methods for Multiple Integration*, Oxford University Press,
//!   1994.
//! - R. Cranley & T. N. L. Patterson, "Randomization of number theoretic methods for multiple
//!   integration", SIAM J. Numer. Anal. 13 (1976), 904-914.
//! - F. J. Hickernell, H. S. Hong, P. L'Ecuyer & C. Lemieux, "Extensible lattice sequences for
//!   quasi-Monte Carlo quadrature", SIAM J. Sci. Comput. 22 (2000), 1117-1138.
//! - R. Cools, F. Y. Kuo & D. Nuyens, "Constructing embedded lattice rules for multivariate
//!   integration", SIAM J. Sci. Comput. 28 (2006), 2162-2188.

use super::simd::{BlockFill, dispatch_fill};
use super::{PassKind, Sampler, Scramble, check_point};
use crate::error::{Error, Result};
use crate::hash::{hash_words, unit_f64};
use crate::points::Points;
use crate::simd::Kernel;
use std::borrow::Cow;
use std::fmt;
use std::sync::OnceLock;

/// Kuo's generating vector, one integer per line, dimension 1 first.
const KUO_TEXT: &str = include_str!("../../data/lattice/kuo-lattice-33002-1024-1048576.9125.txt");

/// Name of the embedded vector, as F. Y. Kuo publishes it.
const KUO_NAME: &str = "lattice-33002-1024-1048576.9125";

/// Word mixed into the shift hash so that lattice shifts are unrelated to other samplers'
/// random words drawn from the same seed ("latt").
const SHIFT_TAG: u64 = 0x6c61_7474;

/// The parsed embedded vector (or why it could not be parsed), built on first use.
fn kuo_vector() -> std::result::Result<&'static [u64], &'static str> {
    static KUO: OnceLock<std::result::Result<Vec<u64>, String>> = OnceLock::new();
    KUO.get_or_init(|| parse_kuo(KUO_TEXT))
        .as_ref()
        .map(Vec::as_slice)
        .map_err(String::as_str)
}

/// Parses the embedded file and checks it is the table the constants describe.
fn parse_kuo(text: &str) -> std::result::Result<Vec<u64>, String> {
    let z = text
        .lines()
        .map(str::trim)
        .enumerate()
        .filter(|(_, line)| !line.is_empty())
        .map(|(n, line)| {
            line.parse::<u64>()
                .map_err(|e| format!("line {}: {line:?}: {e}", n + 1))
        })
        .collect::<std::result::Result<Vec<u64>, String>>()?;
    if z.len() != Lattice::KUO_MAX_DIMS {
        return Err(format!(
            "{} components, expected {}",
            z.len(),
            Lattice::KUO_MAX_DIMS
        ));
    }
    if let Some(bad) = z
        .iter()
        .position(|&v| v >> Lattice::KUO_LOG2_MAX_POINTS != 0)
    {
        return Err(format!("component {} is {} >= 2^20", bad + 1, z[bad]));
    }
    Ok(z)
}

/// Where the generating vector came from (for `Debug`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Source {
    Kuo,
    User,
}

/// An embedded (extensible) rank-1 lattice rule in base 2, unshifted or with independent
/// Cranley-Patterson shifts per pass.
///
/// Point `i` of a pass (`i < 2^m`, `2^m` = [`max`](PassKind::Extensible) points per pass) has
/// coordinates `x_ij = frac(phi_2(i) z_j + Delta_j)`, computed exactly in integers. Every
/// prefix of `2^k` points of a pass is a full lattice rule of `2^k` points, so the best results
/// come from power-of-two point counts; other counts are valid (any prefix is a fine point
/// set, and still unbiased when shifted) but are not a complete lattice and lose part of its
/// accuracy.
///
/// Sample index `p * 2^m + i` is point `i` of pass `p`. With [`Scramble::Shift`] each pass has
/// its own shift, hashed from `(seed, pass, dim)`, so passes are independent replicates. With
/// [`Scramble::None`] every pass is the same deterministic rule, its first point the origin;
/// [`is_randomized`](Sampler::is_randomized) is then false and no standard error can be
/// computed from passes.
///
/// ```
/// use mcint::sampler::{Lattice, Sampler, Scramble};
/// let s = Lattice::new(2, Scramble::None, 0).unwrap();
/// let mut p = [0.0; 2];
/// s.point(1, &mut p).unwrap();
/// assert_eq!(p, [0.5, 0.5]); // phi_2(1) = 1/2, and z_1, z_2 are odd
/// // The first 2^m points are a lattice: every coordinate is a multiple of 2^-m.
/// for i in 0..16 {
///     s.point(i, &mut p).unwrap();
///     assert!(p.iter().all(|&x| (x * 16.0).fract() == 0.0));
/// }
/// ```
#[derive(Clone, PartialEq, Eq)]
pub struct Lattice {
    z: Cow<'static, [u64]>,
    log2_max_points: u32,
    scramble: Scramble,
    seed: u64,
    source: Source,
}

impl Lattice {
    /// Dimensions of Kuo's embedded generating vector (the most [`new`](Self::new) accepts).
    ///
    /// ```
    /// use mcint::sampler::{Lattice, Scramble};
    /// assert!(Lattice::new(Lattice::KUO_MAX_DIMS, Scramble::Shift, 0).is_ok());
    /// assert!(Lattice::new(Lattice::KUO_MAX_DIMS + 1, Scramble::Shift, 0).is_err());
    /// ```
    pub const KUO_MAX_DIMS: usize = 9125;

    /// Kuo's vector holds up to `2^20` points per pass (and was optimized for `2^10 ..= 2^20`).
    ///
    /// ```
    /// use mcint::sampler::{Lattice, PassKind, Sampler, Scramble};
    /// let s = Lattice::new(3, Scramble::Shift, 0).unwrap();
    /// assert_eq!(s.passes(), PassKind::Extensible { max: 1 << Lattice::KUO_LOG2_MAX_POINTS });
    /// ```
    pub const KUO_LOG2_MAX_POINTS: u32 = 20;

    /// The largest `log2_max_points` accepted by [`with_generator`](Self::with_generator).
    ///
    /// Unshifted coordinates are multiples of `2^-m`, and a double in `[0, 1)` holds every
    /// multiple of `2^-53` exactly, so `m <= 53` keeps them exact; sample indices
    /// `p * 2^m + i` are `u64`, so `m <= 52` still leaves `2^12` independent passes.
    /// `2^52` (4.5e15) points per pass is far beyond any practical run.
    ///
    /// ```
    /// use mcint::sampler::{Lattice, Scramble};
    /// let m = Lattice::MAX_LOG2_POINTS;
    /// assert!(Lattice::with_generator(vec![1], m, Scramble::None, 0).is_ok());
    /// assert!(Lattice::with_generator(vec![1], m + 1, Scramble::None, 0).is_err());
    /// ```
    pub const MAX_LOG2_POINTS: u32 = 52;

    /// The lattice in `dims` dimensions (`1 ..= 9125`) from F. Y. Kuo's generating vector
    /// `lattice-33002-1024-1048576.9125` (its first `dims` components), with `2^20` points per
    /// pass. `scramble` is [`Scramble::None`] or [`Scramble::Shift`].
    ///
    /// ```
    /// use mcint::sampler::{Lattice, Sampler, Scramble};
    /// let s = Lattice::new(4, Scramble::Shift, 7).unwrap();
    /// assert_eq!((s.dims(), s.name()), (4, "lattice"));
    /// assert!(Lattice::new(0, Scramble::Shift, 7).unwrap_err().to_string().contains("9125"));
    /// assert!(Lattice::new(4, Scramble::Owen, 7).is_err());
    /// ```
    pub fn new(dims: usize, scramble: Scramble, seed: u64) -> Result<Self> {
        if !(1..=Self::KUO_MAX_DIMS).contains(&dims) {
            return Err(Error::invalid(
                "dims",
                dims,
                format!(
                    "1 ..= {} (the dimensions of Kuo's {KUO_NAME} generating vector)",
                    Self::KUO_MAX_DIMS
                ),
            ));
        }
        scramble.check("lattice", &[Scramble::None, Scramble::Shift])?;
        let z = kuo_vector().map_err(|why| {
            Error::invalid(
                "embedded generating vector",
                KUO_NAME,
                format!("a readable table ({why})"),
            )
        })?;
        Ok(Lattice {
            z: Cow::Borrowed(&z[..dims]),
            log2_max_points: Self::KUO_LOG2_MAX_POINTS,
            scramble,
            seed,
            source: Source::Kuo,
        })
    }

    /// A lattice from a user's generating vector `z` (one component per dimension), with
    /// `2^log2_max_points` points per pass.
    ///
    /// Requires `z` non-empty, `1 <= log2_max_points <= 52` (see
    /// [`MAX_LOG2_POINTS`](Self::MAX_LOG2_POINTS)) and every `0 < z_j < 2^log2_max_points`
    /// (a `z_j` of 0 makes coordinate `j` one value, 0 before a shift).
    /// Components need not be odd, but an even `z_j` makes coordinate `j` of a `2^k`-point
    /// prefix take fewer than `2^k` distinct values, a worse rule.
    ///
    /// ```
    /// use mcint::sampler::{Lattice, Sampler, Scramble};
    /// // The 8-point Fibonacci-like lattice with z = (1, 3).
    /// let s = Lattice::with_generator(vec![1, 3], 3, Scramble::None, 0).unwrap();
    /// let mut p = [0.0; 2];
    /// s.point(4, &mut p).unwrap(); // phi_2(4) = 1/8
    /// assert_eq!(p, [0.125, 0.375]);
    /// assert!(Lattice::with_generator(vec![1, 9], 3, Scramble::None, 0).is_err());
    /// assert!(Lattice::with_generator(vec![1, 0], 3, Scramble::None, 0).is_err());
    /// ```
    pub fn with_generator(
        z: Vec<u64>,
        log2_max_points: u32,
        scramble: Scramble,
        seed: u64,
    ) -> Result<Self> {
        if z.is_empty() {
            return Err(Error::invalid(
                "generating vector length",
                0,
                "at least 1 component (one per dimension)",
            ));
        }
        if !(1..=Self::MAX_LOG2_POINTS).contains(&log2_max_points) {
            return Err(Error::invalid(
                "log2_max_points",
                log2_max_points,
                format!(
                    "1 ..= {} (points per pass are 2^log2_max_points; exact doubles and \
                     u64 sample indices bound it)",
                    Self::MAX_LOG2_POINTS
                ),
            ));
        }
        if let Some(dim) = z.iter().position(|&v| v == 0 || v >> log2_max_points != 0) {
            return Err(Error::invalid(
                "generating vector component",
                format!("{} (dimension {})", z[dim], dim + 1),
                format!(
                    "1 to 2^log2_max_points - 1 = {} (0 makes the coordinate constant)",
                    (1u64 << log2_max_points) - 1
                ),
            ));
        }
        scramble.check("lattice", &[Scramble::None, Scramble::Shift])?;
        Ok(Lattice {
            z: Cow::Owned(z),
            log2_max_points,
            scramble,
            seed,
            source: Source::User,
        })
    }

    /// The generating vector `z`, one component per dimension.
    ///
    /// ```
    /// use mcint::sampler::{Lattice, Scramble};
    /// let s = Lattice::new(3, Scramble::None, 0).unwrap();
    /// assert_eq!(s.generator()[0], 1);
    /// assert!(s.generator().iter().all(|&z| z % 2 == 1));
    /// ```
    pub fn generator(&self) -> &[u64] {
        &self.z
    }

    /// `m`, where a pass holds `2^m` points.
    ///
    /// ```
    /// use mcint::sampler::{Lattice, Scramble};
    /// assert_eq!(Lattice::new(3, Scramble::None, 0).unwrap().log2_max_points(), 20);
    /// ```
    pub fn log2_max_points(&self) -> u32 {
        self.log2_max_points
    }

    /// The randomization: [`Scramble::None`] or [`Scramble::Shift`].
    ///
    /// ```
    /// use mcint::sampler::{Lattice, Scramble};
    /// let s = Lattice::new(3, Scramble::Shift, 0).unwrap();
    /// assert_eq!(s.scramble(), Scramble::Shift);
    /// ```
    pub fn scramble(&self) -> Scramble {
        self.scramble
    }

    /// `2^m - 1`: the index within a pass is `index & mask`.
    #[inline]
    fn mask(&self) -> u64 {
        (1u64 << self.log2_max_points) - 1
    }

    /// The shift of `dim` in `pass`, as a 64-bit fraction of one (zero when unshifted).
    #[inline]
    fn shift(&self, pass: u64, dim: usize) -> u64 {
        match self.scramble {
            Scramble::Shift => hash_words(self.seed, &[pass, dim as u64, SHIFT_TAG]),
            _ => 0,
        }
    }
}

/// Bit reversals of the bytes 0..256 as 64-bit words: `REV8[j] = j.reverse_bits()`. Block
/// fills look up the low 8 bits of the index here instead of reversing every index.
const REV8: [u64; 256] = {
    let mut table = [0u64; 256];
    let mut j = 0;
    while j < table.len() {
        table[j] = (j as u64).reverse_bits();
        j += 1;
    }
    table
};

/// The index bits looked up in [`REV8`].
const LOW_MASK: u64 = 0xff;

/// `(reversed * z + offset) mod 2^64` read as a fraction of one, its top 53 bits as a double.
/// With `reversed = (i & mask).reverse_bits()` (that is, `phi_2(i) * 2^64`) and `offset` the
/// shift, this is `frac(phi_2(i) z + shift)` in fixed point.
#[inline(always)]
fn coordinate(reversed: u64, z: u64, shift: u64) -> f64 {
    unit_f64(reversed.wrapping_mul(z).wrapping_add(shift))
}

impl fmt::Debug for Lattice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let generator = match self.source {
            Source::Kuo => KUO_NAME,
            Source::User => "user",
        };
        f.debug_struct("Lattice")
            .field("dims", &self.z.len())
            .field("generator", &generator)
            .field("log2_max_points", &self.log2_max_points)
            .field("scramble", &self.scramble)
            .field("seed", &self.seed)
            .finish()
    }
}

impl Sampler for Lattice {
    fn unbalanced_by(&self, n: u64) -> Option<u64> {
        (!n.is_power_of_two()).then_some(2)
    }

    fn name(&self) -> &'static str {
        "lattice"
    }

    fn dims(&self) -> usize {
        self.z.len()
    }

    fn passes(&self) -> PassKind {
        PassKind::Extensible {
            max: 1u64 << self.log2_max_points,
        }
    }

    fn seed(&self) -> u64 {
        self.seed
    }

    fn reseed(&mut self, seed: u64) {
        self.seed = seed;
    }

    fn is_randomized(&self) -> bool {
        self.scramble == Scramble::Shift
    }

    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        check_point(self.z.len(), out)?;
        let pass = index >> self.log2_max_points;
        let reversed = (index & self.mask()).reverse_bits();
        for (dim, (x, &z)) in out.iter_mut().zip(self.z.iter()).enumerate() {
            *x = coordinate(reversed, z, self.shift(pass, dim));
        }
        Ok(())
    }

    fn fill(&self, start: u64, points: &mut Points) -> Result<()> {
        dispatch_fill(self, self.z.len(), start, points)
    }
}

/// A block fill, compiled for each instruction set by [`dispatch_fill`]: the inner loop is one
/// 64-bit multiply-add and conversion per value, which AVX-512 does in 8 lanes.
impl Kernel for BlockFill<'_, Lattice> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let (lattice, start, points) = (self.sampler, self.start, self.points);
        let len = points.len();
        let mask = lattice.mask();
        for (dim, column) in points.columns_mut().enumerate() {
            let z = lattice.z[dim];
            let mut shift_of_pass: Option<(u64, u64)> = None;
            // Runs of indices that share a pass and all but the low 8 bits of the in-pass
            // index: rev(i) = rev(high bits) + REV8[low bits] (disjoint bits), so
            // rev(i) z + shift = REV8[low] z + (rev(high) z + shift) modulo 2^64, the same
            // integer point() computes. check_block guarantees start + len - 1 fits.
            let mut done = 0;
            while done < len {
                let index = start + done as u64;
                let pass = index >> lattice.log2_max_points;
                let offset = index & mask;
                let low = (offset & LOW_MASK) as usize;
                let left_in_pass = usize::try_from(mask - offset).unwrap_or(usize::MAX);
                let run = (len - done)
                    .min(REV8.len() - low)
                    .min(left_in_pass.saturating_add(1));
                let shift = match shift_of_pass {
                    Some((p, shift)) if p == pass => shift,
                    _ => {
                        let shift = lattice.shift(pass, dim);
                        shift_of_pass = Some((pass, shift));
                        shift
                    }
                };
                let base = (offset & !LOW_MASK)
                    .reverse_bits()
                    .wrapping_mul(z)
                    .wrapping_add(shift);
                for (x, &reversed_low) in column[done..done + run]
                    .iter_mut()
                    .zip(&REV8[low..low + run])
                {
                    *x = coordinate(reversed_low, z, base);
                }
                done += run;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_kuo_vector_is_complete_odd_and_below_2_pow_20() {
        let z = kuo_vector().unwrap();
        assert_eq!(z.len(), 9125);
        assert_eq!(z[0], 1);
        assert!(z.iter().all(|&v| v % 2 == 1 && v < 1 << 20));
        // Spot values straight from the published file.
        assert_eq!(&z[..4], &[1, 182667, 213731, 255351]);
        assert_eq!(z[9124], 256517);
    }

    #[test]
    fn parse_kuo_rejects_damaged_tables() {
        assert!(parse_kuo("1\n3\nx\n").unwrap_err().contains("line 3"));
        assert!(parse_kuo("1\n3\n").unwrap_err().contains("2 components"));
    }

    #[test]
    fn byte_table_splits_the_bit_reversal() {
        for i in [0u64, 1, 255, 256, 1000, 0xdead_beef, (1 << 52) - 1] {
            let split = (i & !LOW_MASK).reverse_bits() | REV8[(i & LOW_MASK) as usize];
            assert_eq!(split, i.reverse_bits());
        }
    }

    #[test]
    fn fixed_point_product_is_the_exact_lattice_coordinate() {
        // reverse_bits(i) * z mod 2^64 == (rev_m(i) * z mod 2^m) << (64 - m) for i < 2^m.
        for m in [1u32, 5, 20, 33, 52] {
            for (i, z) in [
                (1u64, 1u64),
                (3, 5),
                (12345, 987654321),
                (u64::MAX, u64::MAX),
            ] {
                let (i, z) = (i & ((1 << m) - 1), z & ((1 << m) - 1));
                let rev_m = i.reverse_bits() >> (64 - m);
                let exact = ((rev_m as u128 * z as u128) % (1u128 << m)) as u64;
                assert_eq!(i.reverse_bits().wrapping_mul(z), exact << (64 - m));
                assert_eq!(
                    coordinate(i.reverse_bits(), z, 0),
                    exact as f64 / (1u64 << m) as f64
                );
            }
        }
    }
}
