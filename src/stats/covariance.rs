//! Streaming means and covariance matrix of vectors, with exact merging: the multivariate
//! form of Welford's update (Welford 1962) and of the pairwise formula of Chan, Golub &
//! LeVeque (1979), as in Pébay (2008), "Formulas for robust, one-pass parallel computation of
//! covariances and arbitrary-order statistical moments".
//!
//! The regression estimator of control variates (the coefficient-estimating form of Jarosz's
//! A.29) needs the means of `(f, g_1, ..., g_k)` and their covariance matrix from one pass over
//! the samples, split over threads; this accumulator gives both.

use crate::error::{Error, Result};

/// Count, means and co-moment matrix `C_ij = sum (x_i - mean_i)(x_j - mean_j)` of a stream of
/// vectors of a fixed length, plus a count of vectors with a non-finite entry (which are kept
/// out of the moments, as [`Accumulator`](super::Accumulator) does for scalars).
///
/// The update for one vector is Welford's, coordinate by coordinate, so the diagonal equals
/// what an [`Accumulator`](super::Accumulator) fed the same coordinate computes, bit for bit;
/// [`merge`](Self::merge) is Chan's pairwise formula, so parts accumulated on different threads
/// combine as if every vector had been pushed into one accumulator. Only the lower triangle is
/// stored: the matrix is symmetric by construction.
///
/// ```
/// use mcint::stats::CovarianceAccumulator;
/// let mut left = CovarianceAccumulator::new(2).unwrap();
/// let mut right = CovarianceAccumulator::new(2).unwrap();
/// left.push(&[1.0, 2.0]).unwrap();
/// left.push(&[2.0, 4.0]).unwrap();
/// right.push(&[3.0, 5.0]).unwrap();
/// right.push(&[f64::NAN, 0.0]).unwrap();
/// left.merge(&right).unwrap();
/// assert_eq!((left.count(), left.non_finite()), (3, 1));
/// assert_eq!(left.means(), &[2.0, 11.0 / 3.0]);
/// assert!((left.covariance(0, 1) - 1.5).abs() < 1e-15);
/// ```
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(try_from = "CovarianceState")
)]
#[derive(Debug, Clone, PartialEq)]
pub struct CovarianceAccumulator {
    count: u64,
    means: Vec<f64>,
    /// Lower triangle of the co-moment matrix, row by row: `(i, j)` with `j <= i` is at
    /// `i (i + 1) / 2 + j`.
    comoments: Vec<f64>,
    non_finite: u64,
}

/// The fields of a [`CovarianceAccumulator`] as read, before their shapes are checked (a
/// co-moment triangle shorter than the means made every read of it panic).
#[cfg(feature = "serde")]
#[derive(serde::Deserialize)]
struct CovarianceState {
    count: u64,
    means: Vec<f64>,
    comoments: Vec<f64>,
    non_finite: u64,
}

#[cfg(feature = "serde")]
impl TryFrom<CovarianceState> for CovarianceAccumulator {
    type Error = String;

    fn try_from(state: CovarianceState) -> std::result::Result<Self, String> {
        let d = state.means.len();
        let triangle = d
            .checked_add(1)
            .and_then(|t| t.checked_mul(d))
            .map(|t| t / 2);
        if d == 0 || triangle != Some(state.comoments.len()) {
            return Err(format!(
                "a covariance accumulator of {d} means and {} co-moments: expected at least one \
                 mean and d (d + 1) / 2 co-moments",
                state.comoments.len()
            ));
        }
        Ok(CovarianceAccumulator {
            count: state.count,
            means: state.means,
            comoments: state.comoments,
            non_finite: state.non_finite,
        })
    }
}

/// Position of `(i, j)`, `j <= i`, in the packed lower triangle.
#[inline]
fn packed(i: usize, j: usize) -> usize {
    i * (i + 1) / 2 + j
}

impl CovarianceAccumulator {
    /// An empty accumulator for vectors of `dims >= 1` entries.
    ///
    /// ```
    /// use mcint::stats::CovarianceAccumulator;
    /// assert_eq!(CovarianceAccumulator::new(3).unwrap().dims(), 3);
    /// assert!(CovarianceAccumulator::new(0).is_err());
    /// ```
    pub fn new(dims: usize) -> Result<Self> {
        if dims == 0 {
            return Err(Error::invalid("dims", dims, "at least 1"));
        }
        let triangle = dims
            .checked_add(1)
            .and_then(|d| d.checked_mul(dims))
            .map(|t| t / 2)
            .ok_or(Error::IndexOutOfRange {
                what: "size of the covariance matrix",
                limit: usize::MAX as u64,
            })?;
        crate::error::check_vec_len::<f64>("dims (its co-moment matrix)", triangle)?;
        Ok(CovarianceAccumulator {
            count: 0,
            means: vec![0.0; dims],
            comoments: vec![0.0; triangle],
            non_finite: 0,
        })
    }

    /// Number of entries of each vector.
    ///
    /// ```
    /// assert_eq!(mcint::stats::CovarianceAccumulator::new(2).unwrap().dims(), 2);
    /// ```
    pub fn dims(&self) -> usize {
        self.means.len()
    }

    /// Adds one vector (`values.len()` must equal [`dims`](Self::dims)). A vector with any NaN
    /// or infinite entry is counted in [`non_finite`](Self::non_finite) and otherwise ignored.
    ///
    /// ```
    /// use mcint::stats::CovarianceAccumulator;
    /// let mut acc = CovarianceAccumulator::new(2).unwrap();
    /// acc.push(&[1.0, f64::INFINITY]).unwrap();
    /// assert_eq!((acc.count(), acc.non_finite()), (0, 1));
    /// assert!(acc.push(&[1.0]).is_err());
    /// ```
    #[inline]
    pub fn push(&mut self, values: &[f64]) -> Result<()> {
        if values.len() != self.dims() {
            return Err(Error::DimensionMismatch {
                what: "vector pushed to a covariance accumulator",
                expected: self.dims(),
                found: values.len(),
            });
        }
        if values.iter().any(|v| !v.is_finite()) {
            self.non_finite += 1;
            return Ok(());
        }
        self.count += 1;
        let n = self.count as f64;
        // Row i of the triangle needs the new means of entries j <= i, which are updated
        // by then: C_ij += (x_i - old mean_i)(x_j - new mean_j), Welford's M2 on the diagonal.
        for i in 0..values.len() {
            let delta = values[i] - self.means[i];
            self.means[i] += delta / n;
            let row = &mut self.comoments[packed(i, 0)..=packed(i, i)];
            for ((c, &x), &mean) in row.iter_mut().zip(&values[..=i]).zip(&self.means[..=i]) {
                *c += delta * (x - mean);
            }
        }
        Ok(())
    }

    /// Adds a block of `len` vectors given as columns (entry `k` of vector `t` at
    /// `columns[k * len + t]`, `columns.len() == dims * len`): the block's means and
    /// co-moments by two passes, merged with Chan's formula. Vectors with a non-finite entry
    /// are counted and left out, as [`push`](Self::push) does.
    pub(crate) fn extend_columns(&mut self, columns: &[f64], len: usize) {
        let m = self.dims();
        if len == 0 {
            return;
        }
        let column = |k: usize| &columns[k * len..(k + 1) * len];
        let mut block = CovarianceAccumulator {
            count: 0,
            means: vec![0.0; m],
            comoments: vec![0.0; self.comoments.len()],
            non_finite: 0,
        };
        if columns[..m * len].iter().any(|v| !v.is_finite()) {
            // Rare: gather the vectors one by one, so that the bad ones are left out.
            let mut row = vec![0.0; m];
            for t in 0..len {
                for (k, slot) in row.iter_mut().enumerate() {
                    *slot = columns[k * len + t];
                }
                // The row has the accumulator's length, so push cannot fail.
                let _ = block.push(&row);
            }
        } else {
            block.count = len as u64;
            for (k, mean) in block.means.iter_mut().enumerate() {
                *mean = column(k).iter().sum::<f64>() / len as f64;
            }
            for i in 0..m {
                for j in 0..=i {
                    let (mi, mj) = (block.means[i], block.means[j]);
                    block.comoments[packed(i, j)] = column(i)
                        .iter()
                        .zip(column(j))
                        .map(|(&a, &b)| (a - mi) * (b - mj))
                        .sum();
                }
            }
        }
        // Same dimension by construction.
        let _ = self.merge(&block);
    }

    /// Combines another accumulator of the same dimension into this one, as if its vectors had
    /// been pushed here (Chan, Golub & LeVeque's pairwise update).
    ///
    /// ```
    /// use mcint::stats::CovarianceAccumulator;
    /// let mut a = CovarianceAccumulator::new(1).unwrap();
    /// a.push(&[1.0]).unwrap();
    /// let mut b = CovarianceAccumulator::new(1).unwrap();
    /// b.push(&[5.0]).unwrap();
    /// a.merge(&b).unwrap();
    /// assert_eq!((a.mean(0), a.variance(0)), (3.0, 8.0));
    /// assert!(a.merge(&CovarianceAccumulator::new(2).unwrap()).is_err());
    /// ```
    pub fn merge(&mut self, other: &CovarianceAccumulator) -> Result<()> {
        if other.dims() != self.dims() {
            return Err(Error::DimensionMismatch {
                what: "covariance accumulator merged",
                expected: self.dims(),
                found: other.dims(),
            });
        }
        self.non_finite += other.non_finite;
        if other.count == 0 {
            return Ok(());
        }
        if self.count == 0 {
            self.count = other.count;
            self.means.copy_from_slice(&other.means);
            self.comoments.copy_from_slice(&other.comoments);
            return Ok(());
        }
        let (na, nb) = (self.count as f64, other.count as f64);
        let n = na + nb;
        let weight = na * nb / n;
        // The co-moments need the differences of the old means, so they go first.
        for i in 0..self.dims() {
            let delta_i = other.means[i] - self.means[i];
            let (start, end) = (packed(i, 0), packed(i, i));
            let row = self.comoments[start..=end]
                .iter_mut()
                .zip(&other.comoments[start..=end]);
            for (j, (c, &c_other)) in row.enumerate() {
                let delta_j = other.means[j] - self.means[j];
                *c += c_other + delta_i * delta_j * weight;
            }
        }
        for (mean, &other_mean) in self.means.iter_mut().zip(&other.means) {
            *mean += (other_mean - *mean) * (nb / n);
        }
        self.count += other.count;
        Ok(())
    }

    /// Number of vectors with all entries finite.
    ///
    /// ```
    /// assert_eq!(mcint::stats::CovarianceAccumulator::new(2).unwrap().count(), 0);
    /// ```
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Number of vectors left out because an entry was NaN or infinite.
    ///
    /// ```
    /// let mut acc = mcint::stats::CovarianceAccumulator::new(2).unwrap();
    /// acc.push(&[f64::NAN, 1.0]).unwrap();
    /// assert_eq!(acc.non_finite(), 1);
    /// ```
    pub fn non_finite(&self) -> u64 {
        self.non_finite
    }

    /// The means of every entry (zeros when empty).
    ///
    /// ```
    /// let mut acc = mcint::stats::CovarianceAccumulator::new(2).unwrap();
    /// acc.push(&[1.0, 2.0]).unwrap();
    /// acc.push(&[3.0, 6.0]).unwrap();
    /// assert_eq!(acc.means(), &[2.0, 4.0]);
    /// ```
    pub fn means(&self) -> &[f64] {
        &self.means
    }

    /// The mean of entry `i`. Panics when `i >= dims()`, like slice indexing.
    ///
    /// ```
    /// let mut acc = mcint::stats::CovarianceAccumulator::new(2).unwrap();
    /// acc.push(&[1.0, 2.0]).unwrap();
    /// assert_eq!(acc.mean(1), 2.0);
    /// ```
    pub fn mean(&self, i: usize) -> f64 {
        self.means[i]
    }

    /// The co-moment `C_ij = sum_n (x_ni - mean_i)(x_nj - mean_j)` (the multivariate `M2`).
    /// Panics when an index is `>= dims()`, like slice indexing.
    ///
    /// ```
    /// let mut acc = mcint::stats::CovarianceAccumulator::new(2).unwrap();
    /// acc.push(&[1.0, 1.0]).unwrap();
    /// acc.push(&[3.0, -1.0]).unwrap();
    /// assert_eq!(acc.comoment(0, 1), -2.0);
    /// assert_eq!(acc.comoment(1, 0), -2.0);
    /// ```
    pub fn comoment(&self, i: usize, j: usize) -> f64 {
        assert!(
            i < self.dims() && j < self.dims(),
            "index ({i}, {j}) out of range for {} dimensions",
            self.dims()
        );
        let (row, column) = if j <= i { (i, j) } else { (j, i) };
        self.comoments[packed(row, column)]
    }

    /// The unbiased sample covariance `C_ij / (n - 1)` (NaN with fewer than two vectors).
    /// Panics when an index is `>= dims()`, like slice indexing.
    ///
    /// ```
    /// let mut acc = mcint::stats::CovarianceAccumulator::new(2).unwrap();
    /// acc.push(&[1.0, 1.0]).unwrap();
    /// assert!(acc.covariance(0, 1).is_nan());
    /// acc.push(&[3.0, -1.0]).unwrap();
    /// assert_eq!(acc.covariance(0, 1), -2.0);
    /// ```
    pub fn covariance(&self, i: usize, j: usize) -> f64 {
        if self.count < 2 {
            // Still check the indices, so that bad ones fail the same way at every count.
            let _ = self.comoment(i, j);
            return f64::NAN;
        }
        self.comoment(i, j) / (self.count - 1) as f64
    }

    /// The unbiased sample variance of entry `i`, `C_ii / (n - 1)`.
    ///
    /// ```
    /// let mut acc = mcint::stats::CovarianceAccumulator::new(1).unwrap();
    /// acc.push(&[2.0]).unwrap();
    /// acc.push(&[4.0]).unwrap();
    /// assert_eq!(acc.variance(0), 2.0);
    /// ```
    pub fn variance(&self, i: usize) -> f64 {
        self.covariance(i, i)
    }

    /// The sample correlation `C_ij / sqrt(C_ii C_jj)` (NaN when either entry is constant or
    /// fewer than two vectors were pushed).
    ///
    /// ```
    /// let mut acc = mcint::stats::CovarianceAccumulator::new(2).unwrap();
    /// for x in [0.0, 1.0, 2.0] {
    ///     acc.push(&[x, 3.0 - 2.0 * x]).unwrap();
    /// }
    /// assert!((acc.correlation(0, 1) + 1.0).abs() < 1e-15);
    /// ```
    pub fn correlation(&self, i: usize, j: usize) -> f64 {
        let (mi, mj) = (self.comoment(i, i), self.comoment(j, j));
        // Their product may overflow or underflow where each is fine.
        let product = mi * mj;
        let scale = if product.is_normal() {
            product.sqrt()
        } else {
            mi.sqrt() * mj.sqrt()
        };
        if self.count < 2 || scale == 0.0 {
            return f64::NAN;
        }
        self.comoment(i, j) / scale
    }

    /// The full sample covariance matrix, row-major, `dims() x dims()` (NaN entries with fewer
    /// than two vectors).
    ///
    /// ```
    /// let mut acc = mcint::stats::CovarianceAccumulator::new(2).unwrap();
    /// acc.push(&[0.0, 0.0]).unwrap();
    /// acc.push(&[2.0, 1.0]).unwrap();
    /// assert_eq!(acc.covariance_matrix(), vec![2.0, 1.0, 1.0, 0.5]);
    /// ```
    pub fn covariance_matrix(&self) -> Vec<f64> {
        let d = self.dims();
        let mut matrix = vec![0.0; d * d];
        for i in 0..d {
            for j in 0..d {
                matrix[i * d + j] = self.covariance(i, j);
            }
        }
        matrix
    }
}
