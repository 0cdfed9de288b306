//! [`Gaussian`] and [`Lognormal`]: multivariate normal laws by inverse cdfs and a factor of
//! the covariance.

use std::cell::RefCell;

use nalgebra::{DMatrix, SymmetricEigen};

use super::geometric_brownian::LARGEST_LOG_PRICE;
use super::normal_map::{check_finite, largest_normal, standard_normal};
use super::principal_components::principal_components;
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
    check_symmetric(covariance, d)?;
    let matrix = DMatrix::from_row_slice(d, d, covariance);
    match factorization {
        Factorization::Cholesky => {
            let Some(cholesky) = nalgebra::Cholesky::new(matrix.clone()) else {
                let smallest = smallest_correlation_eigenvalue(&matrix);
                return Err(if smallest < -1e-12 * d as f64 {
                    not_semidefinite(smallest)
                } else {
                    Error::invalid(
                        "covariance",
                        format!("singular (smallest eigenvalue of its correlations {smallest})"),
                        "a positive definite matrix for the Cholesky factorization (the pca \
                         factorization takes a singular one)",
                    )
                });
            };
            let l = cholesky.l();
            Ok((0..d)
                .flat_map(|i| (0..d).map(move |j| (i, j)))
                .map(|(i, j)| l[(i, j)])
                .collect())
        }
        Factorization::Pca => principal_components(
            &matrix,
            "covariance",
            "use the cholesky factorization, or rescale the coordinates",
        )
        .map_err(|refused| {
            // An indefinite block of small variances hides below the rounding of the large
            // ones in the covariance's own eigenvalues; its correlations show it.
            let smallest = smallest_correlation_eigenvalue(&matrix);
            if smallest < -1e-12 * d as f64 {
                not_semidefinite(smallest)
            } else {
                refused
            }
        }),
    }
}

/// Errs unless `C` is symmetric (each pair within rounding of its own scale,
/// `sqrt(c_ii c_jj)`), its variances are at least 0, and a variance of 0 has covariances 0.
fn check_symmetric(covariance: &[f64], d: usize) -> Result<()> {
    let entry = |i: usize, j: usize| covariance[i * d + j];
    if let Some(i) = (0..d).find(|&i| entry(i, i) < 0.0) {
        return Err(Error::invalid(
            "covariance",
            format!("variance ({i},{i}) = {}", entry(i, i)),
            "a positive semidefinite matrix (variances of at least 0)",
        ));
    }
    for i in 0..d {
        for j in 0..i {
            let (a, b) = (entry(i, j), entry(j, i));
            let scale = (entry(i, i) * entry(j, j)).sqrt();
            if (a - b).abs() > 1e-12 * scale {
                return Err(Error::invalid(
                    "covariance",
                    format!("entries ({i},{j}) = {a} and ({j},{i}) = {b}"),
                    "a symmetric matrix",
                ));
            }
            if scale == 0.0 && a != 0.0 {
                return Err(Error::invalid(
                    "covariance",
                    format!("entry ({i},{j}) = {a} beside a variance of 0"),
                    "a positive semidefinite matrix (a coordinate of variance 0 has covariance 0 \
                     with every other)",
                ));
            }
        }
    }
    Ok(())
}

/// The smallest eigenvalue of the correlations `c_ij / sqrt(c_ii c_jj)` (coordinates of
/// variance 0 left out): whether `C` is semidefinite, whatever the scales of its variances.
fn smallest_correlation_eigenvalue(covariance: &DMatrix<f64>) -> f64 {
    let kept: Vec<usize> = (0..covariance.nrows())
        .filter(|&i| covariance[(i, i)] > 0.0)
        .collect();
    let sd: Vec<f64> = kept.iter().map(|&i| covariance[(i, i)].sqrt()).collect();
    let correlations = DMatrix::from_fn(kept.len(), kept.len(), |a, b| {
        covariance[(kept[a], kept[b])] / sd[a] / sd[b]
    });
    SymmetricEigen::new(correlations)
        .eigenvalues
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min)
}

fn not_semidefinite(smallest: f64) -> Error {
    Error::invalid(
        "covariance",
        format!("eigenvalue {smallest} of its correlations"),
        "a positive semidefinite matrix (no negative eigenvalue)",
    )
}

/// The lognormal law: `exp` of a [`Gaussian`] vector, coordinate by coordinate.
///
/// ```
/// use mcint::{Integrator, measure::{Gaussian, Lognormal}};
/// // E[e^Z] = e^{1/2} for a standard normal Z.
/// let lognormal = Lognormal::new(Gaussian::standard(1).unwrap()).unwrap();
/// let e = Integrator::expectation(|x: &[f64]| x[0], lognormal).samples(400_000).run().unwrap();
/// assert!((e.mean - 0.5f64.exp()).abs() < 5.0 * e.std_error.unwrap());
/// ```
#[derive(Debug, Clone)]
pub struct Lognormal {
    gaussian: Gaussian,
}

impl Lognormal {
    /// `exp(X)` for `X` distributed by `gaussian`, whose coordinates must stay below 709
    /// (`ln(f64::MAX / 2)`) at every canonical point, as geometric Brownian motion's
    /// log-prices do, so that every point is finite.
    ///
    /// ```
    /// use mcint::measure::{Factorization, Gaussian, Lognormal, Measure};
    /// let l = Lognormal::new(Gaussian::standard(1).unwrap()).unwrap();
    /// let mut x = [0.0];
    /// l.map(&[0.5], &mut x);
    /// assert_eq!(x, [1.0]); // the median, e^0
    /// // A mean of 800: e^800 is past f64::MAX.
    /// let far = Gaussian::new(vec![800.0], vec![1.0], Factorization::Cholesky).unwrap();
    /// assert!(Lognormal::new(far).unwrap_err().to_string().contains("709"));
    /// ```
    pub fn new(gaussian: Gaussian) -> Result<Self> {
        let d = gaussian.dims();
        for (i, row) in gaussian.factor.chunks_exact(d).enumerate() {
            // The largest |L_i z| over the normals of canonical points.
            let spread = largest_normal() * row.iter().map(|l| l.abs()).sum::<f64>();
            let reach = gaussian.mean[i] + spread;
            if reach > LARGEST_LOG_PRICE {
                return Err(Error::invalid(
                    "gaussian",
                    format!("coordinate {i} reaching {reach:.4e}"),
                    format!(
                        "coordinates below {LARGEST_LOG_PRICE} (ln(f64::MAX / 2)) at every \
                         canonical point, |normal| up to {:.2}, so that exp stays finite",
                        largest_normal()
                    ),
                ));
            }
        }
        Ok(Lognormal { gaussian })
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
