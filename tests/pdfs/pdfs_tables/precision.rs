//! The normal at its extremes, and numerically delicate tables.

use super::*;

// The normal

#[test]
fn normal_agrees_bit_for_bit_with_the_untruncated_truncated_normal() {
    for (mean, sd) in [(0.0, 1.0), (3.0, 0.25), (-1e5, 1e-3), (1e300, 1e298)] {
        let normal = Normal::new(mean, sd).unwrap();
        let truncated = TruncatedNormal::new(mean, sd, -INF, INF).unwrap();
        let mut us = vec![0.0, 5e-324, 1e-300, 1e-17, 0.5, ONE_BELOW, 1.0, NAN];
        us.extend((1..1000).map(|k| k as f64 / 1000.0));
        for u in us {
            let x = normal.sample_1d(u);
            assert_eq!(x.to_bits(), truncated.sample_1d(u).to_bits(), "u = {u}");
            assert_eq!(normal.pdf_1d(x).to_bits(), truncated.pdf_1d(x).to_bits());
            assert_eq!(
                normal.invert_1d(x).to_bits(),
                truncated.invert_1d(x).to_bits()
            );
        }
    }
}

#[test]
fn normal_at_u_zero_is_finite_and_as_documented() {
    // u = 0 is read as the smallest positive normal f64, where the quantile is
    // python3 -c "from scipy.stats import norm; import sys; print(norm.ppf(sys.float_info.min))"
    // = -37.5193793471445.
    let z0 = Normal::new(0.0, 1.0).unwrap().sample_1d(f64::MIN_POSITIVE);
    assert!((z0 + 37.5193793471445).abs() < 1e-12, "{z0}");
    for (mean, sd) in [(0.0, 1.0), (2.0, 3.0), (0.0, 1e-300), (1e300, 1e298)] {
        let p = Normal::new(mean, sd).unwrap();
        let x = p.sample_1d(0.0);
        assert!(x.is_finite());
        assert_eq!(x, mean + sd * z0);
        assert!(p.pdf_1d(x) >= 0.0);
        // The top of the canonical range, 1 - 2^-53, reaches 8.2095 sd
        // (python3 -c "from scipy.stats import norm; print(norm.ppf(1 - 2**-53))" gives
        // 8.209536151601387).
        let top = (p.sample_1d(ONE_BELOW) - mean) / sd;
        assert!((top - 8.209536151601387).abs() < 1e-9, "{top}");
    }
}

// ---------------------------------------------------------------------------------------------
// Numerically delicate tables

#[test]
fn nearly_flat_linear_segments_have_no_cancellation() {
    // With values 1 and 1 + s the cdf is t + s t^2 / 2 over (1 + s/2), so the inverse differs
    // from t = u by about s u (1 - u) / 2. A naive quadratic solve (-v0 + sqrt(v0^2 + ...)) /
    // (v1 - v0) divides a cancelled difference by s and loses everything at s = 1e-12; the
    // stable form keeps the error at rounding level.
    for s in [1e-6, 1e-12, 1e-15, 0.0] {
        let p = PiecewiseLinear1d::new(&[0.0, 1.0], &[1.0, 1.0 + s]).unwrap();
        for k in 0..=100 {
            let u = k as f64 / 100.0;
            let x = p.sample_1d(u);
            // The cdf of the density 1 + s t, normalised.
            let cdf = |t: f64| (t + s * t * t / 2.0) / (1.0 + s / 2.0);
            let error = cdf(x) - u;
            // A few ulps of u; the naive solve is off by about 1e-16 / s.
            assert!(
                error.abs() < 2e-15,
                "s = {s}: F(sample({u})) - u = {error:e}"
            );
        }
    }
}

#[test]
fn tiny_values_beside_large_ones_keep_their_shape() {
    // Values 1e-200 of the table's peak still make a linear density: the ratio across the
    // segment is that of its values ...
    let p = PiecewiseLinear1d::new(&[0.0, 1.0, 2.0], &[1e-200, 3e-200, 1.0]).unwrap();
    let ratio = p.pdf_1d(0.75) / p.pdf_1d(0.25);
    assert!((ratio - 2.5 / 1.5).abs() < 1e-14, "{ratio}");
    // ... and sampling within that segment (the first, so u below its probability, about
    // 4e-200, reaches it) follows its shape. Without rescaling each segment, the squares in
    // the quadratic underflow and every point lands at the segment's end.
    let mass = p.segment_probabilities()[0];
    assert!((mass / 4e-200 - 1.0).abs() < 1e-12, "{mass:e}");
    let shape = PiecewiseLinear1d::new(&[0.0, 1.0], &[1.0, 3.0]).unwrap();
    for k in 0..20 {
        let fraction = k as f64 / 20.0;
        let (x, y) = (p.sample_1d(fraction * mass), shape.sample_1d(fraction));
        assert!((x - y).abs() < 1e-14, "fraction {fraction}: {x} vs {y}");
        // Against the closed form t = (-1 + sqrt(1 + 8f)) / 2 of the density (1 + 2t) / 2.
        let exact = (-1.0 + (1.0 + 8.0 * fraction).sqrt()) / 2.0;
        assert!(
            (x - exact).abs() < 1e-14,
            "fraction {fraction}: {x}, exact {exact}"
        );
    }
}

#[test]
fn one_cell_tables_are_uniform() {
    let p = PiecewiseConstant1d::new(2.0, 6.0, &[3.5]).unwrap();
    let l = PiecewiseLinear1d::new(&[2.0, 6.0], &[3.5, 3.5]).unwrap();
    for k in 0..=64 {
        let u = (k as f64 / 64.0).min(ONE_BELOW);
        let x = 2.0 + 4.0 * u;
        assert_eq!(p.sample_1d(u), x.min(6f64.next_down()));
        assert!((l.sample_1d(u) - x).abs() < 1e-15 * 6.0);
        assert_eq!(p.pdf_1d(x.min(5.99)), 0.25);
        assert_eq!(p.sample_cell(u).0, 0);
    }
}

#[test]
fn out_of_range_u_stays_in_nonzero_cells() {
    // u is documented to be in [0, 1); values outside (or NaN) are clamped, never sent to a
    // zero cell at either end.
    let p = PiecewiseConstant1d::new(0.0, 1.0, &[0.0, 1.0, 2.0, 0.0]).unwrap();
    for u in [-1.0, 1.0, 2.0, NAN, INF, -INF] {
        let x = p.sample_1d(u);
        assert!(p.pdf_1d(x) > 0.0, "u = {u}: x = {x}");
    }
}
