//! The heuristics' weights: in [0, 1], summing to one, and the published formulas.

use super::*;

// Heuristics

/// A density value anywhere in the f64 range, or exactly zero.
fn density() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        0.0..10.0f64,
        (-300.0..300.0f64).prop_map(|e| 10f64.powf(e)),
    ]
}

fn heuristic() -> impl Strategy<Value = MisHeuristic> {
    prop_oneof![
        Just(MisHeuristic::Balance),
        Just(MisHeuristic::Maximum),
        Just(MisHeuristic::Power { beta: 2.0 }),
        (0.01..50.0f64).prop_map(|beta| MisHeuristic::Power { beta }),
        (0.0..=1.0f64).prop_map(|alpha| MisHeuristic::Cutoff { alpha }),
        Just(MisHeuristic::Cutoff { alpha: 1.0 }),
    ]
}

proptest! {
    #![proptest_config(config(2000, 0x915))]

    /// Every heuristic gives weights in [0, 1] summing to one wherever some q_j > 0, also
    /// with ties (the repeated entry) and with densities across the whole f64 range.
    #[test]
    fn heuristic_weights_sum_to_one(
        mut q in prop::collection::vec(density(), 1..8),
        repeat in any::<prop::sample::Index>(),
        h in heuristic(),
    ) {
        let copy = q[repeat.index(q.len())];
        q.push(copy);
        prop_assume!(q.iter().any(|&v| v > 0.0));
        prop_assert!(h.check().is_ok());
        let mut w = vec![0.0; q.len()];
        h.weights(&q, &mut w);
        for (j, &wj) in w.iter().enumerate() {
            prop_assert!((0.0..=1.0).contains(&wj), "{:?}: w[{}] = {} for q = {:?}", h, j, wj, q);
            prop_assert_eq!(wj, h.weight(j, &q));
            // The trait method (used by the estimators) is the same function.
            prop_assert_eq!(wj, MisWeighting::weight(&h, j, &[0.5], &q));
        }
        let sum: f64 = w.iter().sum();
        prop_assert!((sum - 1.0).abs() <= 1e-14, "{:?}: weights {:?} sum to {} for q = {:?}", h, w, sum, q);
    }

    /// The weights depend on ratios of densities only, and the heuristics meet where the
    /// theory says: power 1 and cutoff 0 are the balance heuristic, cutoff 1 the maximum.
    #[test]
    fn heuristics_are_scale_free_and_nest(
        q in prop::collection::vec(0.01..100.0f64, 1..6),
        scale_exponent in -100.0..100.0f64,
        h in heuristic(),
    ) {
        let scale = 10f64.powf(scale_exponent);
        let scaled: Vec<f64> = q.iter().map(|v| v * scale).collect();
        for j in 0..q.len() {
            let (a, b) = (h.weight(j, &q), h.weight(j, &scaled));
            prop_assert!((a - b).abs() <= 1e-13, "{:?}: {} vs {} after scaling by {:e}", h, a, b, scale);
            let balance = MisHeuristic::Balance.weight(j, &q);
            let power_one = MisHeuristic::Power { beta: 1.0 }.weight(j, &q);
            let cutoff_zero = MisHeuristic::Cutoff { alpha: 0.0 }.weight(j, &q);
            prop_assert!((power_one - balance).abs() <= 1e-15, "power 1: {} vs {}", power_one, balance);
            prop_assert!((cutoff_zero - balance).abs() <= 1e-15, "cutoff 0: {} vs {}", cutoff_zero, balance);
            prop_assert_eq!(MisHeuristic::Cutoff { alpha: 1.0 }.weight(j, &q), MisHeuristic::Maximum.weight(j, &q));
        }
    }
}

#[test]
fn heuristic_weights_are_the_published_formulas() {
    // q = (1, 2, 5): balance 1/8, 2/8, 5/8; power 2: 1/30, 4/30, 25/30; maximum 0, 0, 1;
    // cutoff 0.3 (threshold 1.5): 0, 2/7, 5/7.
    let q = [1.0, 2.0, 5.0];
    let cases: [(MisHeuristic, [f64; 3]); 4] = [
        (MisHeuristic::Balance, [1.0 / 8.0, 2.0 / 8.0, 5.0 / 8.0]),
        (
            MisHeuristic::Power { beta: 2.0 },
            [1.0 / 30.0, 4.0 / 30.0, 25.0 / 30.0],
        ),
        (MisHeuristic::Maximum, [0.0, 0.0, 1.0]),
        (
            MisHeuristic::Cutoff { alpha: 0.3 },
            [0.0, 2.0 / 7.0, 5.0 / 7.0],
        ),
    ];
    for (h, expected) in cases {
        for (j, e) in expected.iter().enumerate() {
            assert!(
                (h.weight(j, &q) - e).abs() < 1e-15,
                "{h:?} w[{j}] = {}",
                h.weight(j, &q)
            );
        }
    }
    // A large exponent approaches the maximum heuristic without overflow.
    let sharp = MisHeuristic::Power { beta: 1000.0 };
    assert!((sharp.weight(2, &[1e300, 1e300, 1.1e300]) - 1.0).abs() < 1e-15);
    // Undefined weights are NaN, never a silent value.
    for h in heuristics() {
        assert!(h.weight(0, &[0.0, 0.0]).is_nan(), "{h:?}");
        assert!(h.weight(0, &[1.0, f64::NAN]).is_nan(), "{h:?}");
        assert!(h.weight(0, &[1.0, -1.0]).is_nan(), "{h:?}");
        assert!(h.weight(0, &[1.0, f64::INFINITY]).is_nan(), "{h:?}");
    }
}
