//! Two samplers of different kinds given the same seed draw unrelated numbers: every sampler
//! salts its hashes with its kind. Before, `LatinHypercube`, `Jittered`, `MultiJittered` and
//! `CorrelatedMultiJittered` hashed the same `(seed, pass, index, dim)` words for their
//! in-cell jitter, so at one seed their offsets were identical (correlation 1 across seeds).

use mcint::Points;
use mcint::sampler::{Sampler, SamplerKind};

/// Seeds per correlation.
const SEEDS: u64 = 400;
/// Leading points and dimensions whose coordinates are compared.
const POINTS: usize = 4;
const DIMS: usize = 2;

/// A pass size each kind accepts in 2-D, near 64 (some need squares, prime powers or cubes).
fn build(kind: SamplerKind, seed: u64) -> Option<(Box<dyn Sampler>, u64)> {
    [64, 49, 27, 125, 81]
        .into_iter()
        .find_map(|n| kind.build(DIMS, n, seed).ok().map(|s| (s, n)))
}

/// Per seed, the leading coordinates seen at three scales: `x`, and its fractional part
/// within a stratum of width `1 / sqrt(N)` and `1 / N` (where stratified samplers place their
/// jitter). Indexed `[feature][seed]`, features ordered by (point, dim, scale).
fn features(kind: SamplerKind) -> Option<Vec<Vec<f64>>> {
    let (probe, n) = build(kind, 0)?;
    if !probe.is_randomized() {
        return None;
    }
    let scales = [1.0, (n as f64).sqrt().round(), n as f64];
    let mut out = vec![Vec::new(); POINTS * DIMS * scales.len()];
    for seed in 0..SEEDS {
        let (sampler, _) = build(kind, seed).unwrap();
        let mut block = Points::new(DIMS, POINTS).unwrap();
        sampler.fill(0, &mut block).unwrap();
        for i in 0..POINTS {
            for d in 0..DIMS {
                for (s, scale) in scales.iter().enumerate() {
                    let v = block.get(i, d) * scale;
                    out[(i * DIMS + d) * scales.len() + s].push(v - v.floor());
                }
            }
        }
    }
    Some(out)
}

/// Pearson's correlation; `None` when either side does not vary.
fn correlation(a: &[f64], b: &[f64]) -> Option<f64> {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    (saa > 0.0 && sbb > 0.0).then(|| sab / (saa * sbb).sqrt())
}

#[test]
fn samplers_of_different_kinds_given_one_seed_are_independent() {
    let kinds: Vec<(SamplerKind, Vec<Vec<f64>>)> = SamplerKind::ALL
        .into_iter()
        .filter_map(|k| features(k).map(|f| (k, f)))
        .collect();
    // Every kind that is randomized by default takes part: 13 or more of the 15.
    assert!(kinds.len() >= 13, "only {} kinds built", kinds.len());
    // Under independence r is about normal with standard deviation 1 / sqrt(SEEDS - 1) = 0.05;
    // 0.3 is 6 of them, so the ~7,000 correlations below all stay under it except with
    // probability about 7e3 * 2e-9 (Bonferroni), while identical offsets give r = 1.
    let limit = 6.0 / ((SEEDS - 1) as f64).sqrt();
    let per_point = 3;
    let mut worst = (0.0f64, String::new());
    for (a, (kind_a, fa)) in kinds.iter().enumerate() {
        for (kind_b, fb) in &kinds[a + 1..] {
            for point_dim in 0..POINTS * DIMS {
                for sa in 0..per_point {
                    for sb in 0..per_point {
                        let (x, y) = (
                            &fa[point_dim * per_point + sa],
                            &fb[point_dim * per_point + sb],
                        );
                        if let Some(r) = correlation(x, y)
                            && r.abs() > worst.0
                        {
                            worst = (
                                r.abs(),
                                format!(
                                    "{} vs {}: point/dim {point_dim}, scales {sa}/{sb}",
                                    kind_a.name(),
                                    kind_b.name()
                                ),
                            );
                        }
                    }
                }
            }
        }
    }
    assert!(worst.0 < limit, "correlation {:.3} ({})", worst.0, worst.1);
}
