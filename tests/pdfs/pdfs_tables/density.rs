//! Each density integrates to one and is the density written here, and samples follow it.

use super::*;

// Integrates to one, and is the density written here

/// Tolerance for a quadrature of a case's density to one. Each node `x_k` is rounded to a
/// float, by at most half an ulp, which changes `f(x_k)` by up to `|f'| ulp / 2`; summed with
/// the weights that is at most the density's total variation times `ulp / 2` (nodes never fall
/// on a jump). It matters only for narrow densities far from zero, such as `Normal(-1e5,
/// 1e-3)`, where x has an ulp of 1.5e-11 against an sd of 1e-3. The variation is measured on
/// a fine grid of the reference density (it over-counts jumps, which only loosens this a bit).
fn quadrature_tolerance(case: &Case) -> f64 {
    let (lo, hi) = case.window;
    let mut points: Vec<f64> = (0..=20_000)
        .map(|k| lo + (hi - lo) * (k as f64 / 20_000.0))
        .collect();
    points.extend(case.breaks.iter().copied());
    points.sort_by(f64::total_cmp);
    let variation: f64 = points
        .windows(2)
        .map(|p| ((case.density)(p[1]) - (case.density)(p[0])).abs())
        .sum();
    let ulp = f64::EPSILON * lo.abs().max(hi.abs());
    1e-12 + variation * ulp
}

#[test]
fn one_dimensional_pdfs_integrate_to_one() {
    // Polynomial pieces are integrated exactly (to rounding in sums of up to 12,000 terms);
    // the normal with 320 panels of a quarter sd over +-40 sd, far below 1e-13 of error.
    for case in all_cases() {
        let (lo, hi) = case.window;
        let f = |x: f64| case.pdf.pdf_1d(x);
        let total = integrate_pieces(&f, lo, hi, &case.breaks, case.max_panel);
        let tolerance = quadrature_tolerance(&case);
        assert!(
            (total - 1.0).abs() < tolerance,
            "{}: integral {total} (tolerance {tolerance:e})",
            case.name
        );
        assert_eq!((case.as_pdf.dims(), case.as_pdf.canonical_dims()), (1, 1));
    }
}

#[test]
fn densities_match_the_formulas() {
    // At 2000 points across each window the library's density is the one written here, to
    // rounding: relative 1e-12, plus 1e-14 of the largest density seen, for points where the
    // interpolant nearly vanishes and the two formulas round differently. (The points avoid
    // cell edges, where the two might disagree about the cell by an ulp of x.)
    for case in all_cases() {
        let (lo, hi) = case.window;
        let points: Vec<f64> = (0..2000)
            .map(|k| lo + (hi - lo) * ((k as f64 + 0.3) / 2000.0))
            .collect();
        let scale = points.iter().fold(0.0f64, |m, &x| m.max((case.density)(x)));
        for &x in &points {
            let (got, want) = (case.pdf.pdf_1d(x), (case.density)(x));
            assert!(
                (got - want).abs() <= 1e-12 * want + 1e-14 * scale,
                "{}: pdf({x}) = {got}, expected {want}",
                case.name
            );
            assert_eq!(got.to_bits(), case.as_pdf.pdf(&[x]).to_bits());
        }
    }
}

#[test]
fn table_probabilities_sum_to_one_exactly() {
    // The tables' normalisation is an exact sum: probabilities are w_i / sum(w).
    for (a, b, weights) in [
        (0.0, 1.0, vec![1.0, 2.0, 3.0, 4.0]),
        (-2.0, 4.0, vec![0.0, 1.0, 0.0, 0.0, 5.0, 0.0]),
        (3.0, 5.0, vec![7.0]),
        (0.0, 1.0, random_weights(1000, 77, 10)),
    ] {
        let p = PiecewiseConstant1d::new(a, b, &weights).unwrap();
        let sum: f64 = weights.iter().sum();
        assert_eq!(p.cell_count(), weights.len());
        let total: f64 = p.probabilities().iter().sum();
        assert!((total - 1.0).abs() <= 1e-15 * weights.len() as f64);
        for (i, w) in weights.iter().enumerate() {
            assert_eq!(p.cell_probability(i), w / sum);
            let (lo, hi) = p.cell_bounds(i).unwrap();
            // Density times width is the cell's probability.
            let mid = 0.5 * (lo + hi);
            assert!((p.pdf_1d(mid) * (b - a) / weights.len() as f64 - w / sum).abs() < 1e-15);
            assert_eq!(p.cell_at(mid), Some(i));
        }
        assert_eq!(p.cell_probability(weights.len()), 0.0);
        assert_eq!(p.cell_bounds(weights.len()), None);
        assert!((p.integral() - sum * (b - a) / weights.len() as f64).abs() < 1e-14 * sum);
    }
    let p = PiecewiseLinear1d::new(&[0.0, 1.0, 3.0, 4.0], &[1.0, 3.0, 0.0, 0.0]).unwrap();
    // Trapezoids 2, 3, 0 of a total 5.
    let probabilities = p.segment_probabilities();
    assert_eq!(probabilities.len(), 3);
    for (got, want) in probabilities.iter().zip([0.4, 0.6, 0.0]) {
        assert!((got - want).abs() < 4e-16, "{got} vs {want}");
    }
    assert_eq!(p.breakpoints(), &[0.0, 1.0, 3.0, 4.0]);
}

// ---------------------------------------------------------------------------------------------
// Samples follow the density

/// Samples per 1-D case: a few hundred per bin for the 40-100 bins most cases have.
const SAMPLES_1D: usize = 200_000;

fn goodness_of_fit_1d(cases: &[Case], seed: u64) {
    for (c, case) in cases.iter().enumerate() {
        let bins = &case.bins;
        // Tables with many cells get more samples, so each bin still expects hundreds.
        let samples = SAMPLES_1D.max(250 * bins.len());
        let (w0, w1) = case.window;
        let f = |x: f64| case.pdf.pdf_1d(x);
        let expected: Vec<f64> = bins
            .windows(2)
            .map(|e| {
                let (lo, hi) = (e[0].max(w0), e[1].min(w1));
                if lo < hi {
                    samples as f64 * integrate_pieces(&f, lo, hi, &case.breaks, case.max_panel)
                } else {
                    0.0
                }
            })
            .collect();
        let total = expected.iter().sum::<f64>() / samples as f64;
        assert!(
            (total - 1.0).abs() < quadrature_tolerance(case),
            "{}: bins hold {total}",
            case.name
        );

        let (a, b) = case.pdf.support();
        let u = canonical(1, samples, seed + c as u64);
        let mut observed = vec![0u64; bins.len() - 1];
        for &u in u.column(0) {
            let x = case.pdf.sample_1d(u);
            let inside = x.is_finite()
                && if case.closed {
                    a <= x && x <= b
                } else {
                    a <= x && x < b
                };
            assert!(inside, "{}: sample({u}) = {x} outside", case.name);
            let bin = bins.partition_point(|&e| e <= x).clamp(1, bins.len() - 1) - 1;
            observed[bin] += 1;
        }
        assert_fits(&case.name, &observed, &expected);
    }
}

#[test]
fn normal_samples_follow_the_density() {
    goodness_of_fit_1d(&normal_cases(), 100);
}

#[test]
fn tent_samples_follow_the_density() {
    goodness_of_fit_1d(&tent_cases(), 200);
}

#[test]
fn piecewise_constant_samples_follow_the_density() {
    goodness_of_fit_1d(&constant_cases(), 300);
}

#[test]
fn piecewise_linear_samples_follow_the_density() {
    goodness_of_fit_1d(&linear_cases(), 400);
}

#[test]
fn goodness_of_fit_catches_a_wrong_density() {
    // The test has power: samples of one table judged against a table 3% different fail it.
    let samples = 200_000;
    let right = PiecewiseConstant1d::new(0.0, 1.0, &[1.0, 2.0, 3.0, 4.0]).unwrap();
    let wrong = PiecewiseConstant1d::new(0.0, 1.0, &[1.0, 2.0, 3.0, 4.3]).unwrap();
    let u = canonical(1, samples, 9);
    let mut observed = vec![0u64; 4];
    for &u in u.column(0) {
        observed[right.sample_cell(u).0] += 1;
    }
    let expected: Vec<f64> = wrong
        .probabilities()
        .iter()
        .map(|p| p * samples as f64)
        .collect();
    let fit = chi_square_goodness_of_fit(&observed, &expected, 5.0).unwrap();
    assert!(fit.p_value < P_REJECT, "p = {}", fit.p_value);
}
