//! Jittered (stratified) sampling: one random point in each cell of a regular grid.
//!
//! The seed's equation A.30 in one dimension: `xi_i^N = (i + xi_i) / N`. In `d` dimensions the
//! unit cube is cut into `k^d` equal cells and each pass holds one uniform point per cell.
//! Jittered sampling never has more variance than independent sampling. Its RMSE falls as
//! about `N^(-1/2 - 1/d)` for smooth integrands and `N^(-1/2 - 1/(2d))` across discontinuities
//! (in 2D: `N^-1` and `N^-0.75`), not the "`sigma ∝ 1/N`" the seed states in general.

use super::number_theory::integer_root;
use super::{PassKind, Sampler, check_dims, check_point};
use crate::float::ONE_BELOW;
use crate::hash::{hash_words, unit_f64};

/// Leads every hash of this sampler, so that other samplers given the same seed (which hash
/// the same `(pass, index, dim)` words) draw unrelated jitters.
const SALT: u64 = 0x6a69_7474; // "jitt"
use crate::error::{Error, Result};

/// One uniform point in each of the `k^d` cells of a regular grid, per pass.
///
/// Point `i` of a pass lies in the cell whose coordinates are the base-`k` digits of `i`
/// (digit `j` for dimension `j`). Only whole passes are stratified, so integrators use
/// passes of `k^d` points as replicates.
///
/// ```
/// use mcint::sampler::{Jittered, Sampler};
/// let s = Jittered::new(2, 4, 1).unwrap(); // 16 points per pass
/// let mut p = [0.0; 2];
/// s.point(6, &mut p).unwrap(); // cell (6 % 4, 6 / 4) = (2, 1)
/// assert_eq!(((p[0] * 4.0) as u32, (p[1] * 4.0) as u32), (2, 1));
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Jittered {
    dims: usize,
    strata_per_axis: u64,
    pass_size: u64,
    seed: u64,
}

impl Jittered {
    /// The largest pass size `k^dims` (`k >= 1`) not above `n`: the most points a jittered
    /// pass of `dims` dimensions can have within a budget of `n` (1 when `n < 2^dims`).
    ///
    /// ```
    /// use mcint::sampler::Jittered;
    /// assert_eq!(Jittered::points_not_above(2, 1000), 961); // 31^2
    /// assert_eq!(Jittered::points_not_above(5, 65536), 59049); // 9^5
    /// assert_eq!(Jittered::points_not_above(30, 1000), 1);
    /// ```
    pub fn points_not_above(dims: usize, n: u64) -> u64 {
        let exponent = u32::try_from(dims).unwrap_or(u32::MAX);
        let mut k = 1u64;
        while (k + 1).checked_pow(exponent).is_some_and(|p| p <= n) {
            k += 1;
        }
        k.pow(exponent)
    }

    /// `strata_per_axis = k >= 1` cells along each of `dims >= 1` axes: `k^dims` points a
    /// pass, which must fit in a `u64`. With `dims = 1` this is A.30 with `N = k`.
    ///
    /// ```
    /// use mcint::sampler::{Jittered, PassKind, Sampler};
    /// assert_eq!(Jittered::new(3, 5, 0).unwrap().passes(), PassKind::Fixed { size: 125 });
    /// assert!(Jittered::new(2, 0, 0).is_err());
    /// ```
    pub fn new(dims: usize, strata_per_axis: u64, seed: u64) -> Result<Self> {
        check_dims(dims)?;
        if strata_per_axis == 0 {
            return Err(Error::invalid("strata_per_axis", 0, "at least 1"));
        }
        // 1^dims is 1 for every dims, also those beyond u32 that `checked_pow` cannot take.
        let pass_size = if strata_per_axis == 1 {
            Some(1)
        } else {
            u32::try_from(dims)
                .ok()
                .and_then(|d| strata_per_axis.checked_pow(d))
        }
        .ok_or_else(|| {
            Error::invalid(
                "strata_per_axis",
                strata_per_axis,
                format!("a value whose {dims}th power fits in 64 bits"),
            )
        })?;
        Ok(Jittered {
            dims,
            strata_per_axis,
            pass_size,
            seed,
        })
    }

    /// A jittered sampler with `points` per pass, which must be a perfect `dims`-th power
    /// `k^dims`; otherwise the error names the nearest valid sizes.
    ///
    /// ```
    /// use mcint::sampler::Jittered;
    /// assert!(Jittered::with_points(2, 64, 0).is_ok());
    /// let err = Jittered::with_points(2, 50, 0).unwrap_err().to_string();
    /// assert!(err.contains("49") && err.contains("64"), "{err}");
    /// ```
    pub fn with_points(dims: usize, points: u64, seed: u64) -> Result<Self> {
        check_dims(dims)?;
        // Beyond u32 dimensions only k = 1 has a power that fits in 64 bits (2^dims does
        // not), so 1 is the only valid size.
        let powers = u32::try_from(dims).unwrap_or(u32::MAX);
        let root = integer_root(points, powers);
        if root > 0 && root.checked_pow(powers) == Some(points) {
            return Jittered::new(dims, root, seed);
        }
        let below = root.max(1).checked_pow(powers).filter(|&n| n <= points);
        let above = root
            .checked_add(1)
            .and_then(|next| next.checked_pow(powers));
        let nearest = [below, above]
            .into_iter()
            .flatten()
            .map(|n| n.to_string())
            .collect::<Vec<_>>()
            .join(" or ");
        Err(Error::invalid(
            "points",
            points,
            format!("k^{dims} points for an integer k >= 1 (nearest valid: {nearest})"),
        ))
    }

    /// Cells along each axis, `k`.
    ///
    /// ```
    /// assert_eq!(mcint::sampler::Jittered::new(2, 8, 0).unwrap().strata_per_axis(), 8);
    /// ```
    pub fn strata_per_axis(&self) -> u64 {
        self.strata_per_axis
    }
}

impl Sampler for Jittered {
    fn dims(&self) -> usize {
        self.dims
    }

    fn passes(&self) -> PassKind {
        PassKind::Fixed {
            size: self.pass_size,
        }
    }

    fn seed(&self) -> u64 {
        self.seed
    }

    fn reseed(&mut self, seed: u64) {
        self.seed = seed;
    }

    fn name(&self) -> &'static str {
        "jittered"
    }

    /// Point `index` (pass `index / k^d`); the trait's `fill` writes a block point by point.
    fn point(&self, index: u64, out: &mut [f64]) -> Result<()> {
        check_point(self.dims, out)?;
        let pass = index / self.pass_size;
        let mut cell = index % self.pass_size;
        let strata = self.strata_per_axis as f64;
        for (dim, x) in out.iter_mut().enumerate() {
            let digit = cell % self.strata_per_axis;
            cell /= self.strata_per_axis;
            let jitter = unit_f64(hash_words(self.seed, &[SALT, pass, index, dim as u64]));
            *x = ((digit as f64 + jitter) / strata).min(ONE_BELOW);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::Jittered;

    #[test]
    fn one_stratum_fits_any_dimension() {
        use crate::sampler::{PassKind, Sampler};
        for dims in [1usize << 32, (1 << 32) + 2, usize::MAX] {
            let s = Jittered::new(dims, 1, 0).unwrap();
            assert_eq!(s.passes(), PassKind::Fixed { size: 1 });
            assert!(Jittered::with_points(dims, 1, 0).is_ok());
            // 2^dims does not fit: 1 is the only valid size (not 4, as truncating dims to
            // 32 bits would claim).
            let err = Jittered::with_points(dims, 5, 0).unwrap_err().to_string();
            assert!(err.ends_with("(nearest valid: 1)"), "{err}");
            assert!(Jittered::new(dims, 2, 0).is_err());
        }
    }
}
