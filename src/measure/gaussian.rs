//! [`Gaussian`] and [`Lognormal`]: multivariate normal laws by inverse cdfs and a factor of
//! the covariance.

use std::cell::RefCell;

use nalgebra::{DMatrix, SymmetricEigen};

use super::normal_map::{check_finite, standard_normal};
use super::{Measure, check_factor_dims};
use crate::error::{Error, Result};

/// How a covariance `C` is factored as `C = L L'` to map independent normals `z` to `L z`.
///
/// ```
/// use mcint::measure::Factorization;
/// assert_ne!(Factorization::Cholesky, Factorization::Pca);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Factorization {
    /// The lower-triangular Cholesky factor (needs a positive definite `C`): coordinate `i`
    /// depends on the first `i + 1` normals only.
    Cholesky,
    /// Principal components, `L = V sqrt(Lambda)` with the eigenvalues in decreasing order:
    /// the first canonical coordinates carry the most variance, which lowers the effective
    /// dimension for quasi-Monte Carlo; accepts a singular (positive semidefinite) `C`.
    Pca,
}

thread_local! {
    /// Independent normals of one point, for factors that cannot be applied in place.
    static NORMALS: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

/// The normal law `N(mean, C)` on `R^d`: `x = mean + L z` with `z_j = Phi^-1(u_j)`.
///
/// The covariance is checked: finite, symmetric, and positive semidefinite (a negative
/// eigenvalue is refused with its value); the Cholesky factorization also needs it positive
/// definite. A canonical coordinate `u = 0` is read as `2^-54` so every point is finite.
///
/// ```
/// use mcint::{Integrator, measure::{Factorization, Gaussian}};
/// // E[x0 x1] under a correlated normal is the covariance, 0.6.
/// let gaussian = Gaussian::new(vec![0.0, 0.0], vec![1.0, 0.6, 0.6, 2.0], Factorization::Cholesky).unwrap();
/// let e = Integrator::expectation(|x: &[f64]| x[0] * x[1], gaussian).samples(200_000).run().unwrap();
/// assert!((e.mean - 0.6).abs() < 5.0 * e.std_error.unwrap());
/// ```
#[derive(Debug, Clone)]
pub struct Gaussian {
    mean: Vec<f64>,
    covariance: Vec<f64>,
    /// `L`, row by row (`d x d`).
    factor: Vec<f64>,
    factorization: Factorization,
}

impl Gaussian {
    /// The standard normal law on `R^dims`, `1 <= dims <=`
    /// [`FACTOR_MAX_DIMS`](super::FACTOR_MAX_DIMS): `x_j = Phi^-1(u_j)`.
    ///
    /// ```
    /// use mcint::measure::{Gaussian, Measure};
    /// let g = Gaussian::standard(3).unwrap();
    /// assert_eq!((g.dims(), g.canonical_dims()), (3, 3));
    /// assert!(Gaussian::standard(0).is_err());
    /// ```
    pub fn standard(dims: usize) -> Result<Self> {
        if dims == 0 {
            return Err(Error::invalid("dims", 0, "at least 1"));
        }
        // Before the identity's d x d entries are allocated.
        check_factor_dims("dims", dims, "dimensions", "")?;
        let mut identity = vec![0.0; dims * dims];
        for i in 0..dims {
            identity[i * dims + i] = 1.0;
        }
        Gaussian::new(vec![0.0; dims], identity, Factorization::Cholesky)
    }

    /// The normal law with `mean` (length `d`, at most
    /// [`FACTOR_MAX_DIMS`](super::FACTOR_MAX_DIMS)) and `covariance` (`d x d`, row by row),
    /// factored by `factorization`.
    ///
    /// ```
    /// use mcint::measure::{Factorization, Gaussian};
    /// // Not positive semidefinite: eigenvalues 3 and -1.
    /// let err = Gaussian::new(vec![0.0; 2], vec![1.0, 2.0, 2.0, 1.0], Factorization::Pca).unwrap_err();
    /// assert!(err.to_string().contains("eigenvalue -1"), "{err}");
    /// // Singular: fine for principal components, not for Cholesky.
    /// let singular = vec![1.0, 1.0, 1.0, 1.0];
    /// assert!(Gaussian::new(vec![0.0; 2], singular.clone(), Factorization::Pca).is_ok());
    /// assert!(Gaussian::new(vec![0.0; 2], singular, Factorization::Cholesky).is_err());
    /// ```
    pub fn new(mean: Vec<f64>, covariance: Vec<f64>, factorization: Factorization) -> Result<Self> {
        let d = mean.len();
        if d == 0 {
            return Err(Error::invalid("mean", "[]", "at least one dimension"));
        }
        check_factor_dims("mean", d, "dimensions", "")?;
        if covariance.len() != d.saturating_mul(d) {
            return Err(Error::DimensionMismatch {
                what: "covariance entries (d x d for a mean of d)",
                expected: d.saturating_mul(d),
                found: covariance.len(),
            });
        }
        check_finite("mean", &mean)?;
        check_finite("covariance", &covariance)?;
        let factor = factor(&covariance, d, factorization)?;
        Ok(Gaussian {
            mean,
            covariance,
            factor,
            factorization,
        })
    }

    /// The mean.
    ///
    /// ```
    /// assert_eq!(mcint::measure::Gaussian::standard(2).unwrap().mean(), &[0.0, 0.0]);
    /// ```
    pub fn mean(&self) -> &[f64] {
        &self.mean
    }

    /// The covariance, row by row.
    ///
    /// ```
    /// assert_eq!(mcint::measure::Gaussian::standard(1).unwrap().covariance(), &[1.0]);
    /// ```
    pub fn covariance(&self) -> &[f64] {
        &self.covariance
    }

    /// The factor `L` (`C = L L'`), row by row.
    ///
    /// ```
    /// use mcint::measure::{Factorization, Gaussian};
    /// let g = Gaussian::new(vec![0.0; 2], vec![4.0, 2.0, 2.0, 2.0], Factorization::Cholesky).unwrap();
    /// assert_eq!(g.factor(), &[2.0, 0.0, 1.0, 1.0]);
    /// ```
    pub fn factor(&self) -> &[f64] {
        &self.factor
    }
}

impl Measure for Gaussian {
    fn canonical_dims(&self) -> usize {
        self.mean.len()
    }

    fn dims(&self) -> usize {
        self.mean.len()
    }

    fn map(&self, u: &[f64], x: &mut [f64]) -> f64 {
        let d = self.mean.len();
        let (u, x) = (&u[..d], &mut x[..d]);
        match self.factorization {
            Factorization::Cholesky => {
                // In place from the last row up: row i needs z_0..z_i, not yet overwritten.
                for (slot, &v) in x.iter_mut().zip(u) {
                    *slot = standard_normal(v);
                }
                for i in (0..d).rev() {
                    let row = &self.factor[i * d..i * d + i + 1];
                    let value: f64 = row.iter().zip(&x[..=i]).map(|(l, z)| l * z).sum();
                    x[i] = self.mean[i] + value;
                }
            }
            Factorization::Pca => NORMALS.with_borrow_mut(|z| {
                z.clear();
                z.extend(u.iter().map(|&v| standard_normal(v)));
                for (i, slot) in x.iter_mut().enumerate() {
                    let row = &self.factor[i * d..(i + 1) * d];
                    *slot =
                        self.mean[i] + row.iter().zip(z.iter()).map(|(l, z)| l * z).sum::<f64>();
                }
            }),
        }
        1.0
    }
}

/// `L` with `C = L L'`, after checking that `C` is symmetric and positive semidefinite.
fn factor(covariance: &[f64], d: usize, factorization: Factorization) -> Result<Vec<f64>> {
    let scale = covariance.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    for i in 0..d {
        for j in 0..i {
            let (a, b) = (covariance[i * d + j], covariance[j * d + i]);
            if (a - b).abs() > 1e-12 * scale {
                return Err(Error::invalid(
                    "covariance",
                    format!("entries ({i},{j}) = {a} and ({j},{i}) = {b}"),
                    "a symmetric matrix",
                ));
            }
        }
    }
    let matrix = DMatrix::from_row_slice(d, d, covariance);
    let eigen = SymmetricEigen::new(matrix.clone());
    let smallest = eigen
        .eigenvalues
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    // Rounding in the decomposition leaves eigenvalues of a semidefinite matrix a few ulps of
    // its scale below zero.
    let tolerance = 1e-12 * d as f64 * scale;
    if smallest < -tolerance {
        return Err(Error::invalid(
            "covariance",
            format!("eigenvalue {smallest}"),
            "a positive semidefinite matrix (no negative eigenvalue)",
        ));
    }
    match factorization {
        Factorization::Cholesky => {
            let cholesky = nalgebra::Cholesky::new(matrix).ok_or_else(|| {
                Error::invalid(
                    "covariance",
                    format!("singular (smallest eigenvalue {smallest})"),
                    "a positive definite matrix for the Cholesky factorization (the pca \
                     factorization takes a singular one)",
                )
            })?;
            let l = cholesky.l();
            Ok((0..d)
                .flat_map(|i| (0..d).map(move |j| (i, j)))
                .map(|(i, j)| l[(i, j)])
                .collect())
        }
        Factorization::Pca => {
            let mut order: Vec<usize> = (0..d).collect();
            order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
            let mut l = vec![0.0; d * d];
            for (column, &k) in order.iter().enumerate() {
                let root = eigen.eigenvalues[k].max(0.0).sqrt();
                for i in 0..d {
                    l[i * d + column] = eigen.eigenvectors[(i, k)] * root;
                }
            }
            Ok(l)
        }
    }
}

/// The lognormal law: `exp` of a [`Gaussian`] vector, coordinate by coordinate.
///
/// ```
/// use mcint::{Integrator, measure::{Gaussian, Lognormal}};
/// // E[e^Z] = e^{1/2} for a standard normal Z.
/// let lognormal = Lognormal::new(Gaussian::standard(1).unwrap());
/// let e = Integrator::expectation(|x: &[f64]| x[0], lognormal).samples(400_000).run().unwrap();
/// assert!((e.mean - 0.5f64.exp()).abs() < 5.0 * e.std_error.unwrap());
/// ```
#[derive(Debug, Clone)]
pub struct Lognormal {
    gaussian: Gaussian,
}

impl Lognormal {
    /// `exp(X)` for `X` distributed by `gaussian`.
    ///
    /// ```
    /// use mcint::measure::{Gaussian, Lognormal, Measure};
    /// let l = Lognormal::new(Gaussian::standard(1).unwrap());
    /// let mut x = [0.0];
    /// l.map(&[0.5], &mut x);
    /// assert_eq!(x, [1.0]); // the median, e^0
    /// ```
    pub fn new(gaussian: Gaussian) -> Self {
        Lognormal { gaussian }
    }
}

impl Measure for Lognormal {
    fn canonical_dims(&self) -> usize {
        self.gaussian.canonical_dims()
    }

    fn dims(&self) -> usize {
        self.gaussian.dims()
    }

    fn map(&self, u: &[f64], x: &mut [f64]) -> f64 {
        let weight = self.gaussian.map(u, x);
        for v in x.iter_mut().take(self.gaussian.dims()) {
            *v = v.exp();
        }
        weight
    }
}
