//! Blue-noise samplers: Poisson disk (Cook 1986; Bridson 2007) and Mitchell's best
//! candidate (Mitchell 1991), both on the unit torus.

use mcint::Points;
use mcint::sampler::{BestCandidate, Independent, PassKind, PoissonDisk, Sampler};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use rand_core::Rng;

/// Squared periodic distance.
fn torus_dist2(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            let d = (x - y).abs();
            let g = d.min(1.0 - d);
            g * g
        })
        .sum()
}

/// Nearest-neighbour distance of every point (brute force).
fn nn_distances(points: &[Vec<f64>]) -> Vec<f64> {
    points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            points
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, q)| torus_dist2(p, q))
                .fold(f64::INFINITY, f64::min)
                .sqrt()
        })
        .collect()
}

/// The points of one pass, read one at a time.
fn pass(sampler: &dyn Sampler, pass: u64) -> Vec<Vec<f64>> {
    let PassKind::Fixed { size } = sampler.passes() else {
        panic!("blue-noise samplers have fixed passes");
    };
    (0..size)
        .map(|i| {
            let mut p = vec![0.0; sampler.dims()];
            sampler.point(pass * size + i, &mut p).unwrap();
            p
        })
        .collect()
}

fn min_distance(points: &[Vec<f64>]) -> f64 {
    nn_distances(points)
        .into_iter()
        .fold(f64::INFINITY, f64::min)
}

/// No two points of a maximal set, or of a pass, are closer than the radius; and the set is
/// maximal: no uniform probe is farther than the radius from every point.
///
/// Why the probe check convinces: if the uncovered part of the torus (the points farther
/// than `r` from the set) had volume `a`, all `P = 200_000` independent probes would miss it
/// with probability `(1 - a)^P <= exp(-a P)`, below `e^-14` for `a >= 7e-5`. Bridson's
/// algorithm on its own leaves holes of a sizeable fraction of a ball (`r^d` is 4e-4 to 1e-2
/// here), so a missing gap-filling stage would be caught; a pass of the check shows that any
/// hole left has volume below about `1 / P`.
#[test]
fn poisson_disk_sets_are_separated_and_maximal() {
    let mut rng = rand_pcg::Pcg64::new(0x1234_5678_9abc, 0xdef);
    let probes = 200_000;
    for (dims, n) in [(1usize, 300u64), (2, 400), (3, 400), (4, 300)] {
        let sampler = PoissonDisk::new(dims, n, 11).unwrap();
        let r = sampler.radius();
        let set = sampler.maximal_set(2);
        assert!(set.len() as u64 >= n);
        let min_set = min_distance(&set);
        assert!(
            min_set >= r,
            "dims {dims}: set min distance {min_set} < {r}"
        );
        let min_pass = min_distance(&pass(&sampler, 2));
        assert!(
            min_pass >= r,
            "dims {dims}: pass min distance {min_pass} < {r}"
        );

        // Probes, bucketed in a coarse grid so that each looks only at nearby points.
        let m = ((1.0 / r).floor() as usize).max(1);
        let cell = |x: &[f64]| -> Vec<usize> {
            x.iter()
                .map(|&v| ((v * m as f64) as usize).min(m - 1))
                .collect()
        };
        let index = |c: &[usize]| c.iter().fold(0, |acc, &v| acc * m + v);
        let mut buckets = vec![Vec::new(); m.pow(dims as u32)];
        for (i, p) in set.iter().enumerate() {
            buckets[index(&cell(p))].push(i);
        }
        let r2 = r * r;
        let mut probe = vec![0.0; dims];
        for _ in 0..probes {
            for v in probe.iter_mut() {
                *v = (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
            }
            let base = cell(&probe);
            // Any point within r lies in a neighbouring cell (cell side >= r).
            let mut covered = false;
            for k in 0..3usize.pow(dims as u32) {
                let mut c = base.clone();
                let mut rest = k;
                for v in c.iter_mut() {
                    *v = (*v + m + rest % 3 - 1) % m;
                    rest /= 3;
                }
                if buckets[index(&c)]
                    .iter()
                    .any(|&i| torus_dist2(&set[i], &probe) <= r2)
                {
                    covered = true;
                    break;
                }
            }
            assert!(
                covered,
                "dims {dims}: probe {probe:?} is farther than {r} from the set"
            );
        }
    }
}

#[test]
fn poisson_disk_with_radius_keeps_the_radius() {
    let sampler = PoissonDisk::with_radius(2, 0.04, 5).unwrap();
    assert_eq!(sampler.radius(), 0.04);
    let points = pass(&sampler, 0);
    assert!(min_distance(&points) >= 0.04);
    assert!(sampler.maximal_set(0).len() >= points.len());
}

/// Best-candidate points are far better spread than independent ones.
///
/// For `N` independent uniform points in the unit square (torus) the nearest-neighbour
/// distance is close to that of a Poisson process of intensity `N`, whose mean is
/// `1 / (2 sqrt(N))` and standard deviation `sqrt((4 - pi) / (4 pi N)) = 0.26 / sqrt(N)`;
/// the mean over `N` points then has a standard error of order `0.26 / N`, so the sample
/// value is within a few percent of `0.5 / sqrt(N)`. A well-spread set approaches the
/// hexagonal spacing `1.07 / sqrt(N)`; best candidate reaches about `0.89 / sqrt(N)`, so
/// the bound `1.5 x 0.5 / sqrt(N)` separates the two by dozens of standard errors. The
/// minimum distance of independent points is of order `1 / N` (the closest of `N^2 / 2`
/// pairs), against about `0.77 / sqrt(N)` for best candidate; we require `0.4 / sqrt(N)`.
#[test]
fn best_candidate_is_well_spread() {
    let n = 1024u64;
    let expected_independent = 0.5 / (n as f64).sqrt();
    let best = BestCandidate::new(2, n, 3).unwrap();
    let independent = Independent::new(2, 3).unwrap();
    let indep: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            let mut p = vec![0.0; 2];
            independent.point(i, &mut p).unwrap();
            p
        })
        .collect();
    let indep_nn = nn_distances(&indep);
    let indep_mean = indep_nn.iter().sum::<f64>() / n as f64;
    assert!(
        (indep_mean / expected_independent - 1.0).abs() < 0.1,
        "{indep_mean}"
    );
    for p in 0..2 {
        let points = pass(&best, p);
        let nn = nn_distances(&points);
        let mean = nn.iter().sum::<f64>() / n as f64;
        let min = nn.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(mean > 1.5 * expected_independent, "mean NN {mean}");
        assert!(
            mean > 1.5 * indep_mean,
            "mean NN {mean} vs independent {indep_mean}"
        );
        assert!(min > 0.4 / (n as f64).sqrt(), "min NN {min}");
        let indep_min = indep_nn.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(
            min > 5.0 * indep_min,
            "min NN {min} vs independent {indep_min}"
        );
        // Progressive: the first quarter of the pass is well spread on its own.
        let prefix = &points[..(n / 4) as usize];
        let prefix_mean = nn_distances(prefix).iter().sum::<f64>() / prefix.len() as f64;
        assert!(prefix_mean > 1.5 * 0.5 / (prefix.len() as f64).sqrt());
    }
}

/// Both samplers, small enough to build many passes quickly.
fn samplers(seed: u64) -> Vec<Box<dyn Sampler>> {
    vec![
        Box::new(PoissonDisk::new(2, 50, seed).unwrap()),
        Box::new(PoissonDisk::new(1, 20, seed).unwrap()),
        Box::new(PoissonDisk::new(3, 30, seed).unwrap()),
        Box::new(BestCandidate::new(2, 50, seed).unwrap()),
        Box::new(BestCandidate::new(3, 30, seed).unwrap()),
        Box::new(BestCandidate::new(1, 20, seed).unwrap()),
    ]
}

#[test]
fn names_and_passes() {
    let p = PoissonDisk::new(2, 50, 0).unwrap();
    let b = BestCandidate::new(2, 50, 0).unwrap();
    assert_eq!((p.name(), b.name()), ("poisson", "best-candidate"));
    assert_eq!(p.passes(), PassKind::Fixed { size: 50 });
    assert_eq!(b.passes(), PassKind::Fixed { size: 50 });
    assert!(p.is_randomized() && b.is_randomized());
}

#[test]
fn coordinates_in_unit_interval_and_passes_differ() {
    for s in samplers(4) {
        let a = pass(s.as_ref(), 0);
        let b = pass(s.as_ref(), 1);
        assert!(
            a.iter()
                .chain(&b)
                .flatten()
                .all(|&x| (0.0..1.0).contains(&x)),
            "{}",
            s.name()
        );
        assert_ne!(a, b, "{}", s.name());
    }
}

#[test]
fn same_seed_same_points_and_reseed_changes_them() {
    for (mut s, t) in samplers(9).into_iter().zip(samplers(9)) {
        // Passes asked for in a different order still agree.
        let later = pass(t.as_ref(), 5);
        assert_eq!(pass(s.as_ref(), 5), later, "{}", s.name());
        assert_eq!(pass(s.as_ref(), 0), pass(t.as_ref(), 0));
        s.reseed(10);
        assert_eq!(s.seed(), 10);
        assert_ne!(pass(s.as_ref(), 5), later, "{}", s.name());
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 24,
        rng_seed: RngSeed::Fixed(0x626c_7565),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// `point` and `fill` agree bit for bit, also for blocks that span several passes.
    #[test]
    fn point_and_fill_agree(seed in 0u64..1000, start in 0u64..400, len in 0usize..160) {
        for s in samplers(seed) {
            let mut block = Points::new(s.dims(), len).unwrap();
            s.fill(start, &mut block).unwrap();
            let mut p = vec![0.0; s.dims()];
            for i in 0..len {
                s.point(start + i as u64, &mut p).unwrap();
                for (d, &x) in p.iter().enumerate() {
                    prop_assert_eq!(x.to_bits(), block.get(i, d).to_bits());
                }
            }
        }
    }
}

/// The mean over a pass of a smooth, non-periodic integrand is unbiased. Over `P`
/// independent passes the average of the pass means has standard error `sd / sqrt(P)`
/// (estimated from the passes); 4.5 standard errors is exceeded by chance with probability
/// about 7e-6 per check.
#[test]
fn pass_means_are_unbiased() {
    // f(x) = prod_j (x_j^2 + x_j): integral (1/3 + 1/2)^d.
    let f = |x: &[f64]| x.iter().map(|&v| v * v + v).product::<f64>();
    let passes = 300u64;
    for s in samplers(21) {
        let PassKind::Fixed { size } = s.passes() else {
            unreachable!()
        };
        let mut block = Points::new(s.dims(), size as usize).unwrap();
        let mut p = vec![0.0; s.dims()];
        let means: Vec<f64> = (0..passes)
            .map(|k| {
                s.fill(k * size, &mut block).unwrap();
                (0..size as usize)
                    .map(|i| {
                        block.copy_point(i, &mut p);
                        f(&p)
                    })
                    .sum::<f64>()
                    / size as f64
            })
            .collect();
        let mean = means.iter().sum::<f64>() / passes as f64;
        let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (passes - 1) as f64;
        let se = (var / passes as f64).sqrt();
        let exact = (5.0f64 / 6.0).powi(s.dims() as i32);
        assert!(
            (mean - exact).abs() < 4.5 * se,
            "{} in {} dims: {mean} vs {exact}, se {se}",
            s.name(),
            s.dims()
        );
    }
}

#[test]
fn errors_name_the_parameter_and_the_range() {
    let message = |e: mcint::Error| e.to_string();
    let e = message(PoissonDisk::new(0, 10, 0).unwrap_err());
    assert!(e.contains("dims") && e.contains("1 ..= 8"), "{e}");
    let e = message(PoissonDisk::new(9, 10, 0).unwrap_err());
    assert!(e.contains("dims") && e.contains("1 ..= 8"), "{e}");
    let e = message(PoissonDisk::new(1, 0, 0).unwrap_err());
    assert!(e.contains("points") && e.contains("1 ..= 1048576"), "{e}");
    let e = message(PoissonDisk::new(1, (1 << 20) + 1, 0).unwrap_err());
    assert!(e.contains("points") && e.contains("1 ..= 1048576"), "{e}");
    let most = PoissonDisk::max_points(2).unwrap();
    let e = message(PoissonDisk::new(2, most + 1, 0).unwrap_err());
    assert!(
        e.contains("points") && e.contains(&format!("1 ..= {most}")),
        "{e}"
    );
    for radius in [0.0, -0.1, 0.5, 0.7, f64::NAN] {
        let e = message(PoissonDisk::with_radius(2, radius, 0).unwrap_err());
        assert!(e.contains("radius") && e.contains("(0, 0.5)"), "{e}");
    }
    let e = message(PoissonDisk::with_radius(3, 1e-4, 0).unwrap_err());
    assert!(e.contains("radius") && e.contains("0.5)"), "{e}");
    let e = message(BestCandidate::new(0, 10, 0).unwrap_err());
    assert!(e.contains("dims") && e.contains("1 ..= 4"), "{e}");
    let e = message(BestCandidate::new(5, 10, 0).unwrap_err());
    assert!(e.contains("dims") && e.contains("1 ..= 4"), "{e}");
    let e = message(BestCandidate::new(2, 0, 0).unwrap_err());
    assert!(e.contains("points") && e.contains("16384"), "{e}");
    let e = message(BestCandidate::new(2, 1 << 15, 0).unwrap_err());
    assert!(e.contains("points") && e.contains("16384"), "{e}");

    // Buffers of the wrong dimension are errors, not panics.
    let s = PoissonDisk::new(2, 10, 0).unwrap();
    assert!(s.point(0, &mut [0.0; 3]).is_err());
    let b = BestCandidate::new(2, 10, 0).unwrap();
    assert!(b.fill(0, &mut Points::new(1, 4).unwrap()).is_err());
}

/// Poisson-disk passes in 5 to 8 dimensions (Bridson's sets, as scipy's): no two points of a
/// pass closer than the radius (toroidal distance), and every point uniform, so the mean of
/// the pass means of `x_0 + .. + x_{d-1}` over the passes is `d / 2` within 5 standard errors.
/// (Radii near the torus limit keep the sets small: an 8-D pass of 570 points takes 0.25 s.)
#[test]
fn poisson_disk_passes_in_five_to_eight_dimensions() {
    let gap = |a: f64, b: f64| {
        let t = (a - b).abs();
        t.min(1.0 - t)
    };
    for (dims, radius, passes) in [(5, 0.3, 32u64), (8, 0.45, 16)] {
        let s = PoissonDisk::with_radius(dims, radius, 11).unwrap();
        let mcint::sampler::PassKind::Fixed { size: points } = s.passes() else {
            unreachable!("Poisson-disk passes are fixed")
        };
        let r2 = s.radius() * s.radius();
        let mut means = Vec::new();
        for pass in 0..passes {
            let mut block = mcint::Points::new(dims, points as usize).unwrap();
            s.fill(pass * points, &mut block).unwrap();
            let rows = block.to_rows();
            for i in 0..rows.len() {
                for j in 0..i {
                    let d2: f64 = (0..dims).map(|k| gap(rows[i][k], rows[j][k]).powi(2)).sum();
                    assert!(d2 >= r2 * (1.0 - 1e-12), "{dims}-D pass {pass}: {i}, {j}");
                }
            }
            means.push(rows.iter().map(|r| r.iter().sum::<f64>()).sum::<f64>() / rows.len() as f64);
        }
        let mean = means.iter().sum::<f64>() / passes as f64;
        let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (passes as f64 - 1.0);
        let se = (var / passes as f64).sqrt();
        assert!(
            (mean - dims as f64 / 2.0).abs() < 5.0 * se,
            "{dims}-D: {mean} +- {se}"
        );
    }
}
