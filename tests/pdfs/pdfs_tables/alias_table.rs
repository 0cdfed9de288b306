//! The alias table.

use super::*;

// The alias table

fn alias_weight_sets() -> Vec<(&'static str, Vec<f64>)> {
    vec![
        ("uniform 10", vec![1.0; 10]),
        ("geometric 40", (0..40).map(|i| 0.7f64.powi(i)).collect()),
        ("with zeros", vec![0.0, 3.0, 0.0, 1.0, 0.0, 0.0, 6.0, 0.0]),
        ("single", vec![2.5]),
        ("one heavy", {
            let mut w = vec![1e-3; 50];
            w[17] = 1e3;
            w
        }),
        ("random 1000", random_weights(1000, 88, 7)),
        ("extreme", vec![1e-300, 1e300, 5e299, 0.0, 1e299]),
    ]
}

#[test]
fn alias_probabilities_are_the_weights() {
    for (name, weights) in alias_weight_sets() {
        let t = AliasTable::new(&weights).unwrap();
        assert_eq!(t.len(), weights.len());
        assert!(!t.is_empty());
        let sum: f64 = weights.iter().sum();
        for (i, w) in weights.iter().enumerate() {
            assert_eq!(t.probability(i), w / sum, "{name}: {i}");
        }
        assert_eq!(t.probability(weights.len()), 0.0);
        assert_eq!(t.probabilities().len(), weights.len());
    }
}

#[test]
fn alias_samples_follow_the_probabilities() {
    const SAMPLES: usize = 1_000_000;
    for (k, (name, weights)) in alias_weight_sets().into_iter().enumerate() {
        if weights.len() < 2 {
            continue;
        }
        let t = AliasTable::new(&weights).unwrap();
        let u = canonical(1, SAMPLES, 800 + k as u64);
        let mut observed = vec![0u64; weights.len()];
        for &u in u.column(0) {
            observed[t.sample(u).0] += 1;
        }
        let expected: Vec<f64> = weights
            .iter()
            .map(|w| w / weights.iter().sum::<f64>() * SAMPLES as f64)
            .collect();
        for (i, w) in weights.iter().enumerate() {
            if *w == 0.0 {
                assert_eq!(observed[i], 0, "{name}: zero weight {i} sampled");
            }
        }
        assert_fits(name, &observed, &expected);
    }
}

#[test]
fn alias_remapped_u_is_uniform_and_independent_of_the_index() {
    // Joint histogram of (index, remapped u in 10 bins): if the remapped u is uniform and
    // independent of the index, each cell expects p_i / 10 of the samples.
    const SAMPLES: usize = 1_000_000;
    const BINS: usize = 10;
    for (k, (name, weights)) in alias_weight_sets().into_iter().enumerate() {
        if weights.len() > 100 {
            continue;
        }
        let t = AliasTable::new(&weights).unwrap();
        let u = canonical(1, SAMPLES, 900 + k as u64);
        let mut observed = vec![0u64; weights.len() * BINS];
        for &u in u.column(0) {
            let (i, v) = t.sample(u);
            assert!((0.0..1.0).contains(&v), "{name}: remapped {v}");
            observed[i * BINS + (v * BINS as f64) as usize] += 1;
        }
        let expected: Vec<f64> = (0..weights.len() * BINS)
            .map(|c| t.probability(c / BINS) * SAMPLES as f64 / BINS as f64)
            .collect();
        if weights.len() == 1 {
            // One outcome: the remapped u is u itself.
            assert_eq!(t.sample(0.3), (0, 0.3));
        }
        assert_fits(name, &observed, &expected);
    }
}

#[test]
fn alias_with_evenly_spaced_u_is_balanced_to_the_derived_bound() {
    // With u_j = (j + 1/2) / (N K), j < N K, bin b = floor(u N) receives exactly K points, at
    // fractions f_m = (m + 1/2) / K, m < K. The bin gives its own index to the c of them with
    // f_m < q_b and the alias to the other K - c, and c = #{m : m + 1/2 < q_b K} lies within
    // 1/2 of q_b K (likewise K - c of (1 - q_b) K). The expected count of index i, N K p_i, is
    // K times i's shares summed over the bins where it has one, so
    //     |count_i - N K p_i| <= m_i / 2 <= N / 2,
    // where m_i is the number of bins in which i has a share (at most N), and, since each bin
    // contributes two errors of opposite sign and size at most 1/2,
    //     sum_i |count_i - N K p_i| <= N.
    // With K >= N / 2 every count is therefore within K of its expectation. Rounding (of u_j,
    // of u N, and of the table's thresholds, each ~N * 1e-16 relative) adds at most 1e-6 here.
    // Each bin's K points also form at most two runs: own index first, then its alias.
    for (name, weights) in alias_weight_sets() {
        let n = weights.len();
        let t = AliasTable::new(&weights).unwrap();
        let k_per_bin = n.div_ceil(2).max(64);
        let total = n * k_per_bin;
        let mut counts = vec![0u64; n];
        for b in 0..n {
            let mut runs: Vec<usize> = Vec::new();
            for m in 0..k_per_bin {
                let j = b * k_per_bin + m;
                let (i, _) = t.sample((j as f64 + 0.5) / total as f64);
                counts[i] += 1;
                if runs.last() != Some(&i) {
                    runs.push(i);
                }
            }
            assert!(runs.len() <= 2, "{name}: bin {b} gave indices {runs:?}");
        }
        let mut sum_abs = 0.0;
        for (i, &count) in counts.iter().enumerate() {
            let expected = total as f64 * t.probability(i);
            let error = (count as f64 - expected).abs();
            assert!(
                error <= n as f64 / 2.0 + 1e-6,
                "{name}: index {i} count {count} expected {expected}"
            );
            assert!(error <= k_per_bin as f64 + 1e-6);
            sum_abs += error;
        }
        assert!(sum_abs <= n as f64 + 1e-6, "{name}: total error {sum_abs}");
    }
}

#[test]
fn alias_table_as_a_pdf_uses_counting_measure() {
    let weights = [0.0, 3.0, 0.0, 1.0];
    let t = AliasTable::new(&weights).unwrap();
    assert_eq!((t.dims(), t.canonical_dims()), (1, 1));
    let mut x = [0.0];
    for k in 0..100 {
        let u = k as f64 / 100.0;
        Pdf::sample(&t, &[u], &mut x);
        assert_eq!(x[0], t.sample(u).0 as f64);
        assert_eq!(t.pdf(&x), t.probability(x[0] as usize));
        assert!(t.pdf(&x) > 0.0);
    }
    // The density sums to one over the integers, and is zero elsewhere.
    let total: f64 = (0..4).map(|i| t.pdf(&[i as f64])).sum();
    assert_eq!(total, 1.0);
    for x in [
        0.5,
        -1.0,
        4.0,
        1e300,
        -0.0 - 1e-300,
        NAN,
        INF,
        -INF,
        1.0 + 1e-15,
    ] {
        assert_eq!(t.pdf(&[x]), 0.0, "pdf({x})");
    }
    // The warp has no inverse: invert keeps the trait's error.
    let mut u = [0.0];
    match t.invert(&[1.0], &mut u) {
        Err(Error::Unsupported { operation, .. }) => assert_eq!(operation, "invert"),
        other => panic!("expected the default invert error, got {other:?}"),
    }
    // The estimator f(x) / pdf(x) of sum_i f(i) is exact for f proportional to the weights.
    let f = |i: f64| 2.0 * weights[i as usize];
    for k in 0..10 {
        Pdf::sample(&t, &[k as f64 / 10.0], &mut x);
        assert!((f(x[0]) / t.pdf(&x) - 8.0).abs() < 1e-14);
    }
}

#[test]
fn alias_handles_out_of_range_u() {
    let t = AliasTable::new(&[0.0, 1.0, 0.0, 2.0, 0.0]).unwrap();
    for u in [0.0, ONE_BELOW, 1.0, 2.0, -1.0, NAN, INF, -INF] {
        let (i, v) = t.sample(u);
        assert!(t.probability(i) > 0.0, "u = {u}: index {i}");
        assert!((0.0..1.0).contains(&v), "u = {u}: remapped {v}");
    }
}
