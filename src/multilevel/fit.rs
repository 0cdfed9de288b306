//! The decay rates of a multilevel run, fitted as Giles' `mlmc` fits them.

/// The slope of the least-squares line through `(l, log_M y_l)` over `levels` (where every
/// `y_l` is positive and finite); `None` with fewer than two such points.
pub(super) fn log_slope(values: &[(usize, f64)], refinement: f64) -> Option<f64> {
    let points: Vec<(f64, f64)> = values
        .iter()
        .filter(|(_, y)| y.is_finite() && *y > 0.0)
        .map(|&(l, y)| (l as f64, y.ln() / refinement.ln()))
        .collect();
    if points.len() < 2 {
        return None;
    }
    let n = points.len() as f64;
    let mean_x = points.iter().map(|p| p.0).sum::<f64>() / n;
    let mean_y = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = points.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    let sxx: f64 = points.iter().map(|p| (p.0 - mean_x) * (p.0 - mean_x)).sum();
    Some(sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::log_slope;

    #[test]
    fn slopes_of_powers_of_the_refinement() {
        let halving: Vec<(usize, f64)> =
            (1..6).map(|l| (l, 3.0 * 4f64.powi(-(l as i32)))).collect();
        assert!((log_slope(&halving, 4.0).unwrap() + 1.0).abs() < 1e-12);
        assert!((log_slope(&halving, 2.0).unwrap() + 2.0).abs() < 1e-12);
        assert_eq!(log_slope(&[(1, 1.0), (2, 0.0)], 2.0), None);
    }
}
