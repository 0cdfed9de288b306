//! Principal-component factors `L = V sqrt(Lambda)` of a covariance, checked against it.
//!
//! A symmetric eigensolver is accurate to about `eps * |C|` in absolute terms, so a coordinate
//! whose variance is many decades below the largest loses its variance and correlations. The
//! factor is therefore checked in correlation units and refused, naming the remedy, where it
//! does not reproduce the covariance.

use nalgebra::{DMatrix, SymmetricEigen};

use crate::error::{Error, Result};

/// How far `L L'` may stray from the covariance, in units of `sqrt(c_ii c_jj)`: far above the
/// eigensolver's rounding on covariances whose variances span a few decades, far below an
/// error that changes the law.
const AGREEMENT: f64 = 1e-6;

/// `V sqrt(Lambda)` of `covariance` (positive semidefinite), row by row, with the eigenvalues
/// in decreasing order; a coordinate of variance 0 gets a row of zeros (it is its mean).
/// `what` names the parameter that gave the covariance in errors, and `instead` the remedy
/// when the factor cannot reproduce it (another factorization or construction).
pub(super) fn principal_components(
    covariance: &DMatrix<f64>,
    what: &'static str,
    instead: &str,
) -> Result<Vec<f64>> {
    let d = covariance.nrows();
    let scale = covariance.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    let eigen = SymmetricEigen::new(covariance.clone());
    let smallest = eigen
        .eigenvalues
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    // Rounding in the decomposition leaves eigenvalues of a semidefinite matrix a few ulps of
    // its scale below zero.
    if smallest < -1e-12 * d as f64 * scale {
        return Err(Error::invalid(
            what,
            format!("eigenvalue {smallest}"),
            "a positive semidefinite matrix (no negative eigenvalue)",
        ));
    }
    let mut order: Vec<usize> = (0..d).collect();
    order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
    let mut l = vec![0.0; d * d];
    for (column, &k) in order.iter().enumerate() {
        let root = eigen.eigenvalues[k].max(0.0).sqrt();
        for i in (0..d).filter(|&i| covariance[(i, i)] > 0.0) {
            l[i * d + column] = eigen.eigenvectors[(i, k)] * root;
        }
    }
    if let Some(bad) = l.iter().find(|v| !v.is_finite()) {
        return Err(Error::invalid(
            what,
            format!("largest entry {scale:e}"),
            format!("principal components within f64 (a factor entry is {bad}): {instead}"),
        ));
    }
    check_agreement(covariance, &l, what, instead)?;
    Ok(l)
}

/// Errs when `L L'` differs from `covariance` by more than [`AGREEMENT`] in correlation units
/// (rows scaled by `1 / sqrt(c_ii)`, so that no product overflows).
fn check_agreement(
    covariance: &DMatrix<f64>,
    l: &[f64],
    what: &'static str,
    instead: &str,
) -> Result<()> {
    let d = covariance.nrows();
    let sd: Vec<f64> = (0..d).map(|i| covariance[(i, i)].sqrt()).collect();
    let scaled = DMatrix::from_fn(d, d, |i, k| {
        if sd[i] > 0.0 {
            l[i * d + k] / sd[i]
        } else {
            0.0
        }
    });
    let product = &scaled * scaled.transpose();
    for i in (0..d).filter(|&i| sd[i] > 0.0) {
        for j in (0..=i).filter(|&j| sd[j] > 0.0) {
            let wanted = covariance[(i, j)] / sd[i] / sd[j];
            let off = (product[(i, j)] - wanted).abs();
            if off > AGREEMENT || off.is_nan() {
                let spread = sd
                    .iter()
                    .copied()
                    .filter(|&s| s > 0.0)
                    .fold((f64::INFINITY, 0.0f64), |(low, high), s| {
                        (low.min(s), high.max(s))
                    });
                return Err(Error::invalid(
                    what,
                    format!(
                        "standard deviations from {:.3e} to {:.3e}",
                        spread.0, spread.1
                    ),
                    format!(
                        "standard deviations close enough in scale for principal components \
                         in f64 (entry ({i},{j}) comes out {off:.1e} off in correlation \
                         units): {instead}"
                    ),
                ));
            }
        }
    }
    Ok(())
}
