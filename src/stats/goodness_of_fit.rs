//! Pearson's chi-square goodness-of-fit test: a test of sample quality.
//!
//! This is how pbrt and Mitsuba test their warps: histogram many samples on a grid, integrate
//! the claimed density over every cell for the expected counts, and ask whether the two
//! disagree by more than chance. Cells with small expected counts are pooled so that the
//! chi-square approximation holds (Cochran's rule of thumb: at least 5 expected per cell). The
//! p-value is the chi-square upper tail of the private `special` module.

use crate::error::{Error, Result};
use crate::special::chi_square_sf;

/// The outcome of [`chi_square_goodness_of_fit`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct GoodnessOfFit {
    /// Pearson's statistic `sum (observed - expected)^2 / expected` over the pooled cells
    /// (infinite when a cell of zero expected count was hit).
    pub statistic: f64,
    /// Degrees of freedom: pooled cells minus one.
    pub dof: usize,
    /// Probability of a statistic at least this large if the samples follow the expected
    /// distribution.
    pub p_value: f64,
    /// Number of cells after pooling.
    pub cells: usize,
}

/// How far apart, relatively, the observed and expected totals may be (scipy's `sqrt(eps)`).
const SUM_AGREEMENT: f64 = 1.5e-8;

/// Pearson's chi-square test of `observed` counts against `expected` counts (same length,
/// expected counts finite and `>= 0` with a positive total). Cells expecting fewer than
/// `min_expected` samples are pooled, smallest first, until each pooled cell reaches it; a
/// sample in a cell that expects none makes the p-value 0.
///
/// The expected counts must sum to the number of observations (within a relative 1.5e-8, as
/// scipy requires); a test with at least two pooled cells is returned, otherwise an error says
/// there were too few samples.
///
/// ```
/// use mcint::stats::chi_square_goodness_of_fit;
/// let fair = chi_square_goodness_of_fit(&[98, 105, 97], &[100.0; 3], 5.0).unwrap();
/// assert!(fair.p_value > 0.5);
/// let loaded = chi_square_goodness_of_fit(&[150, 75, 75], &[100.0; 3], 5.0).unwrap();
/// assert!(loaded.p_value < 1e-6);
/// // Probabilities in place of counts: an error, not a p-value of 0.
/// assert!(chi_square_goodness_of_fit(&[98, 105, 97], &[1.0 / 3.0; 3], 0.0).is_err());
/// ```
pub fn chi_square_goodness_of_fit(
    observed: &[u64],
    expected: &[f64],
    min_expected: f64,
) -> Result<GoodnessOfFit> {
    if observed.len() != expected.len() {
        return Err(Error::DimensionMismatch {
            what: "expected counts (one per observed cell)",
            expected: observed.len(),
            found: expected.len(),
        });
    }
    if let Some(bad) = expected.iter().find(|e| !e.is_finite() || **e < 0.0) {
        return Err(Error::invalid(
            "expected",
            bad,
            "finite expected counts >= 0",
        ));
    }
    if !(min_expected.is_finite() && min_expected >= 0.0) {
        return Err(Error::invalid(
            "min_expected",
            min_expected,
            "a finite count >= 0 (5 is the usual rule)",
        ));
    }
    // Expected counts that do not sum to the observations (probabilities, say) make every
    // cell look far off: refused, as scipy refuses sums apart by more than its sqrt(eps).
    let total_observed: f64 = observed.iter().map(|&o| o as f64).sum();
    let total_expected: f64 = expected.iter().sum();
    if (total_observed - total_expected).abs() > SUM_AGREEMENT * total_observed.max(total_expected)
    {
        return Err(Error::invalid(
            "expected",
            format!("counts summing to {total_expected}"),
            format!(
                "expected counts summing to the {total_observed} observations (within a \
                 relative 1.5e-8; scale probabilities by the number of observations)"
            ),
        ));
    }
    if observed
        .iter()
        .zip(expected)
        .any(|(&o, &e)| e == 0.0 && o > 0)
    {
        return Ok(GoodnessOfFit {
            statistic: f64::INFINITY,
            dof: observed.len().saturating_sub(1),
            p_value: 0.0,
            cells: observed.len(),
        });
    }
    let mut order: Vec<usize> = (0..expected.len()).filter(|&i| expected[i] > 0.0).collect();
    order.sort_by(|&i, &j| expected[i].total_cmp(&expected[j]));
    let mut statistic = 0.0;
    let mut cells = 0;
    let (mut pool_observed, mut pool_expected) = (0.0, 0.0);
    for &i in &order {
        pool_observed += observed[i] as f64;
        pool_expected += expected[i];
        if pool_expected >= min_expected {
            statistic += (pool_observed - pool_expected).powi(2) / pool_expected;
            cells += 1;
            (pool_observed, pool_expected) = (0.0, 0.0);
        }
    }
    if pool_expected > 0.0 {
        // Leftover small cells: too few to stand alone, so count them as one more cell.
        statistic += (pool_observed - pool_expected).powi(2) / pool_expected;
        cells += 1;
    }
    if cells < 2 {
        return Err(Error::invalid(
            "expected",
            format!("{cells} cell(s) after pooling"),
            format!("at least two cells expecting {min_expected} samples or more"),
        ));
    }
    let dof = cells - 1;
    Ok(GoodnessOfFit {
        statistic,
        dof,
        p_value: chi_square_sf(statistic, dof as f64),
        cells,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pooling_merges_small_cells() {
        let fit = chi_square_goodness_of_fit(&[1, 0, 2, 50, 47], &[1.0, 1.0, 1.0, 48.5, 48.5], 5.0)
            .unwrap();
        // The three cells expecting 1 join the first 48.5 cell: two cells remain.
        assert_eq!(fit.cells, 2);
        assert_eq!(fit.dof, 1);
    }
}
