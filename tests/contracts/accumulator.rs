//! The accumulator: Welford's update, the two-pass `extend` and Chan's merge agree with the
//! sequential result for any split of a stream, and stay accurate where the naive `E[Y^2] - E[Y]^2`
//! cancels.

use crate::common::config;
use mcint::stats::Accumulator;
use proptest::prelude::*;

fn sequential(values: &[f64]) -> Accumulator {
    let mut acc = Accumulator::new();
    acc.extend(values);
    acc
}

fn pushed(values: &[f64]) -> Accumulator {
    let mut acc = Accumulator::new();
    values.iter().for_each(|&y| acc.push(y));
    acc
}

/// Relative agreement "to rounding": a few hundred ulps of the data's scale, since the two
/// paths round in different orders.
fn agree(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-13 * scale.max(f64::MIN_POSITIVE) + 1e-300
}

proptest! {
    #![proptest_config(config(256, 0xacc))]

    #[test]
    fn any_split_merges_to_the_sequential_result(
        values in prop::collection::vec(-1e3..1e3f64, 0..400),
        cuts in prop::collection::vec(0.0..1.0f64, 0..8),
        offset in -1e6..1e6f64,
    ) {
        let values: Vec<f64> = values.iter().map(|v| v + offset).collect();
        let whole = sequential(&values);
        let mut bounds: Vec<usize> = cuts.iter().map(|c| (c * values.len() as f64) as usize).collect();
        bounds.push(0);
        bounds.push(values.len());
        bounds.sort_unstable();
        let mut merged = Accumulator::new();
        for pair in bounds.windows(2) {
            merged.merge(&sequential(&values[pair[0]..pair[1]]));
        }
        prop_assert_eq!(merged.count(), whole.count());
        prop_assert_eq!(merged.min(), whole.min());
        prop_assert_eq!(merged.max(), whole.max());
        let scale = offset.abs() + 1e3;
        prop_assert!(agree(merged.mean(), whole.mean(), scale), "{} vs {}", merged.mean(), whole.mean());
        // M2 is a sum of n squared deviations of size up to 1e3: scale n * 1e6.
        prop_assert!(agree(merged.m2(), whole.m2(), values.len() as f64 * 1e6 * 1e2),
            "{} vs {}", merged.m2(), whole.m2());
    }

    #[test]
    fn non_finite_values_are_counted_and_excluded(
        values in prop::collection::vec(prop_oneof![
            4 => -1.0..1.0f64,
            1 => Just(f64::NAN),
            1 => Just(f64::INFINITY),
            1 => Just(f64::NEG_INFINITY),
        ], 0..100),
    ) {
        let acc = sequential(&values);
        let finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
        prop_assert_eq!(acc.non_finite() as usize, values.len() - finite.len());
        // The same statistics as the finite values alone, pushed one by one.
        let clean = pushed(&finite);
        prop_assert_eq!(acc.count(), clean.count());
        prop_assert_eq!(acc.min(), clean.min());
        prop_assert_eq!(acc.max(), clean.max());
        prop_assert!(agree(acc.mean(), clean.mean(), 1.0), "{} vs {}", acc.mean(), clean.mean());
        prop_assert!(agree(acc.m2(), clean.m2(), 1e2), "{} vs {}", acc.m2(), clean.m2());
    }

    #[test]
    fn extend_agrees_with_pushing_value_by_value(
        values in prop::collection::vec(-1e3..1e3f64, 0..3000),
        offset in -1e6..1e6f64,
    ) {
        let values: Vec<f64> = values.iter().map(|v| v + offset).collect();
        let (fast, slow) = (sequential(&values), pushed(&values));
        prop_assert_eq!(fast.count(), slow.count());
        prop_assert_eq!(fast.min(), slow.min());
        prop_assert_eq!(fast.max(), slow.max());
        let scale = offset.abs() + 1e3;
        prop_assert!(agree(fast.mean(), slow.mean(), scale), "{} vs {}", fast.mean(), slow.mean());
        prop_assert!(agree(fast.m2(), slow.m2(), values.len() as f64 * 1e6 * 1e2),
            "{} vs {}", fast.m2(), slow.m2());
    }
}

/// Values whose sum overflows: `extend` falls back to pushing one by one and keeps a finite
/// mean and the exact count.
#[test]
fn extend_survives_a_sum_that_overflows() {
    let values = vec![f64::MAX / 2.0; 1000];
    let acc = sequential(&values);
    assert_eq!(acc.count(), 1000);
    assert_eq!(acc.mean(), f64::MAX / 2.0);
    assert_eq!(acc.m2(), 0.0);
}

/// Data with a huge mean and a small spread: the naive formula loses every digit of the
/// variance, Welford's update and the two-pass `extend` keep them.
#[test]
fn welford_survives_a_large_offset() {
    let values: Vec<f64> = (0..4000).map(|i| 1e9 + (i % 4) as f64).collect();
    let acc = sequential(&values);
    assert!((pushed(&values).variance() - 5000.0 / 3999.0).abs() < 1e-6);
    // Exact sample variance of 1000 copies each of {0,1,2,3}: sum of squares 5000, n - 1 = 3999.
    assert!(
        (acc.variance() - 5000.0 / 3999.0).abs() < 1e-6,
        "{}",
        acc.variance()
    );
    let naive = values.iter().map(|v| v * v).sum::<f64>() / 4000.0 - acc.mean() * acc.mean();
    assert!(
        (naive - 1.25).abs() > 0.1 || naive.is_nan(),
        "naive formula unexpectedly accurate: {naive}"
    );
}

#[test]
fn estimate_uses_n_minus_one_degrees_of_freedom() {
    let acc = sequential(&[1.0, 2.0, 4.0]);
    let e = acc.estimate();
    assert_eq!(e.dof, Some(2.0));
    assert_eq!(e.n, 3);
    let var = acc.variance();
    assert!((e.std_error.unwrap() - (var / 3.0).sqrt()).abs() < 1e-15);
    assert_eq!(sequential(&[1.0]).estimate().std_error, None);
}

/// Intervals at levels near 1 keep their tail: `0.5 + level / 2` rounded it away (a level of
/// `1 - 1e-15` with one degree of freedom gave a half-width 12.5% too wide, `1 - 2^-53` with
/// two an infinite one). The Cauchy quantile is `1 / tan(pi q)`, the two-dof one
/// `(1 - 2q) / sqrt(2 q (1 - q))`, for the tail `q = (1 - level) / 2`. Degrees of freedom that
/// are not positive (an estimate edited by hand) are an error, not a NaN interval.
#[test]
fn intervals_near_level_1_keep_their_tail() {
    let unit = |dof: f64| {
        let mut e = mcint::stats::Estimate::from_replicates(&[-1.0, 1.0], 1).unwrap();
        e.dof = Some(dof);
        e
    };
    let se = unit(1.0).std_error.unwrap();
    let level = 1.0 - 1e-15;
    let q = (1.0 - level) / 2.0;
    let cauchy = 1.0 / (std::f64::consts::PI * q).tan();
    let half = unit(1.0).half_width(level).unwrap().unwrap() / se;
    assert!((half / cauchy - 1.0).abs() < 1e-9, "{half} vs {cauchy}");
    let level = 1.0 - f64::EPSILON / 2.0;
    let q = (1.0 - level) / 2.0;
    let two = (1.0 - 2.0 * q) / (2.0 * q * (1.0 - q)).sqrt();
    let half = unit(2.0).half_width(level).unwrap().unwrap() / se;
    assert!((half / two - 1.0).abs() < 1e-9, "{half} vs {two}");
    for dof in [0.0, -3.0, f64::NAN] {
        assert!(unit(dof).confidence_interval(0.95).is_err(), "{dof}");
    }
}
