//! Net quality: `(t, m, d)`-net checks and t-values in base 2, against a brute-force count
//! and the known net properties of the crate's samplers.

use crate::common::block;
use mcint::Points;
use mcint::quality::{elementary_intervals_balanced, shape_balanced, t_value};
use mcint::sampler::{Hammersley, Independent, Jittered, LatinHypercube, Pmj02, Scramble, Sobol};

/// The first `dims` columns of a block.
fn project(points: &Points, dims: usize) -> Points {
    let mut out = Points::new(dims, points.len()).unwrap();
    for dim in 0..dims {
        out.column_mut(dim).copy_from_slice(points.column(dim));
    }
    out
}

/// Every split of `total` into `parts` non-negative exponents.
fn compositions(total: u32, parts: usize) -> Vec<Vec<u32>> {
    if parts == 1 {
        return vec![vec![total]];
    }
    (0..=total)
        .flat_map(|e| {
            compositions(total - e, parts - 1)
                .into_iter()
                .map(move |mut rest| {
                    rest.insert(0, e);
                    rest
                })
        })
        .collect()
}

/// Brute force, independent of the library's digit arithmetic: for every shape and every
/// cell, count the points with `low <= x < high` in every dimension.
fn naive_is_net(points: &Points, m: u32, t: u32) -> bool {
    let dims = points.dims();
    compositions(m - t, dims).into_iter().all(|shape| {
        let cells: u64 = shape.iter().map(|&e| 1u64 << e).product();
        (0..cells).all(|mut flat| {
            let mut bounds = vec![(0.0, 0.0); dims];
            for j in (0..dims).rev() {
                let side = 1u64 << shape[j];
                let a = flat % side;
                flat /= side;
                bounds[j] = (a as f64 / side as f64, (a + 1) as f64 / side as f64);
            }
            let count = (0..points.len())
                .filter(|&i| {
                    bounds.iter().enumerate().all(|(j, &(lo, hi))| {
                        let x = points.get(i, j);
                        lo <= x && x < hi
                    })
                })
                .count();
            count == 1 << t
        })
    })
}

fn naive_t(points: &Points) -> u32 {
    let m = points.len().trailing_zeros();
    (0..=m).find(|&t| naive_is_net(points, m, t)).unwrap()
}

#[test]
fn sobol_prefixes_in_one_and_two_dimensions_are_0_nets() {
    for scramble in [Scramble::None, Scramble::Owen] {
        for seed in [0u64, 1, 2] {
            let sobol = Sobol::new(2, scramble, seed).unwrap();
            let all = block(&sobol, 0, 1 << 14);
            for m in 0..=14u32 {
                let n = 1usize << m;
                let prefix = block(&sobol, 0, n);
                assert_eq!(
                    t_value(&prefix).unwrap(),
                    0,
                    "{scramble:?} seed {seed} m {m}"
                );
                assert_eq!(t_value(&project(&prefix, 1)).unwrap(), 0);
                assert_eq!(prefix.column(0), &all.column(0)[..n]);
            }
            // An aligned block of 2^m points later in the pass is a net too.
            let later = block(&sobol, 3 << 10, 1 << 10);
            assert_eq!(t_value(&later).unwrap(), 0);
        }
    }
}

/// Sobol' dimensions 1 to 3 (primitive polynomials x, x + 1, x^2 + x + 1) form a
/// `(t, 3)`-sequence with `t = sum (degree - 1) = 1`, so every prefix of `2^m` points is a
/// `(t, m, 3)`-net with `t <= 1`. The exact t of each prefix comes from the brute-force count,
/// and scrambling (which maps elementary intervals onto elementary intervals of the same shape)
/// must not change it.
#[test]
fn sobol_in_three_dimensions_matches_brute_force() {
    let plain = Sobol::new(3, Scramble::None, 0).unwrap();
    let mut found = Vec::new();
    for m in 0..=9u32 {
        let points = block(&plain, 0, 1 << m);
        let t = t_value(&points).unwrap();
        assert_eq!(t, naive_t(&points), "m = {m}");
        assert!(t <= 1, "m = {m}: t = {t} exceeds the sequence's t = 1");
        found.push(t);
    }
    // Brute force above agrees with these; m = 1 is trivially a (0, 1, 3)-net.
    println!("t-values of the first 2^m 3-D Sobol' points, m = 0..=9: {found:?}");
    assert_eq!(found[0..2], [0, 0]);
    assert!(
        found.contains(&1),
        "some prefix must need t = 1 (no (0,3)-sequence in base 2)"
    );
    for m in 0..=12u32 {
        let t_plain = t_value(&block(&plain, 0, 1 << m)).unwrap();
        for seed in [4u64, 5] {
            let owen = Sobol::new(3, Scramble::Owen, seed).unwrap();
            assert_eq!(
                t_value(&block(&owen, 0, 1 << m)).unwrap(),
                t_plain,
                "m = {m}"
            );
        }
    }
}

/// Eight Sobol' dimensions, 2^10 points: t from the library equals the brute-force value at
/// the levels around it (checking all levels by brute force would take minutes).
#[test]
fn sobol_in_eight_dimensions() {
    let points = block(&Sobol::new(8, Scramble::None, 0).unwrap(), 0, 1 << 10);
    let t = t_value(&points).unwrap();
    assert!(t > 0 && t < 10);
    assert!(elementary_intervals_balanced(&points, t).unwrap().is_net());
    assert!(
        !elementary_intervals_balanced(&points, t - 1)
            .unwrap()
            .is_net()
    );
    // Owen scrambling keeps every elementary interval's count, so t too.
    let owen = block(&Sobol::new(8, Scramble::Owen, 3).unwrap(), 0, 1 << 10);
    assert_eq!(t_value(&owen).unwrap(), t);
}

#[test]
fn pmj02_prefixes_are_0_m_2_nets() {
    for seed in [0u64, 1, 2, 3] {
        let pmj = Pmj02::new(2, seed).unwrap();
        for m in 0..=12u32 {
            let prefix = block(&pmj, 0, 1 << m);
            assert_eq!(t_value(&prefix).unwrap(), 0, "seed {seed} m {m}");
        }
        // Second pass, and the second aligned block of 2^9 points of it.
        let max = 1u64 << pmj.log2_max();
        assert_eq!(t_value(&block(&pmj, max + 512, 512)).unwrap(), 0);
    }
}

#[test]
fn hammersley_in_two_dimensions_is_a_0_m_2_net() {
    for scramble in [Scramble::None, Scramble::Permute, Scramble::Owen] {
        for m in 0..=12u32 {
            let n = 1u64 << m;
            let hammersley = Hammersley::new(2, n, scramble, 7).unwrap();
            // First and third passes (different randomizations).
            for pass in [0u64, 2] {
                let points = block(&hammersley, pass * n, n as usize);
                assert_eq!(
                    t_value(&points).unwrap(),
                    0,
                    "{scramble:?} m {m} pass {pass}"
                );
            }
        }
    }
}

/// Independent points are almost never balanced even at level 1: the two halves along x
/// hold exactly `N / 2` points with probability `C(N, N/2) / 2^N ~ sqrt(2 / (pi N))`, and the
/// same for y, independently; t < m needs both, probability about `2 / (pi N)` (6e-4 for
/// N = 1024). Over 8 seeds in 2-D and 8-D the chance that any check fails is below 1%.
#[test]
fn independent_points_have_t_equal_to_m() {
    for seed in 0..8u64 {
        for dims in [2usize, 8] {
            let points = block(&Independent::new(dims, seed).unwrap(), 0, 1024);
            assert_eq!(t_value(&points).unwrap(), 10, "dims {dims} seed {seed}");
        }
    }
}

/// On small sets of several kinds (nets, stratified, random, perturbed nets) in one to four
/// dimensions, t_value equals the brute-force t, and the check at t' says "net" exactly when
/// t' >= t.
#[test]
fn t_value_matches_brute_force_on_small_sets() {
    let mut cases: Vec<(String, Points)> = Vec::new();
    for dims in 1..=4usize {
        for m in [0u32, 1, 3, 5, 6] {
            let n = 1usize << m;
            for seed in 0..3u64 {
                cases.push((
                    format!("independent d{dims} m{m} s{seed}"),
                    block(&Independent::new(dims, seed).unwrap(), 0, n),
                ));
                cases.push((
                    format!("latin d{dims} m{m} s{seed}"),
                    block(&LatinHypercube::new(dims, n as u64, seed).unwrap(), 0, n),
                ));
                let mut sobol = block(&Sobol::new(dims, Scramble::Owen, seed).unwrap(), 0, n);
                cases.push((format!("sobol d{dims} m{m} s{seed}"), sobol.clone()));
                // Swap one coordinate of two points: a slightly broken net.
                if n > 1 {
                    let col = sobol.column_mut(dims - 1);
                    col.swap(0, n / 2 + seed as usize % (n / 2));
                    cases.push((format!("swapped sobol d{dims} m{m} s{seed}"), sobol));
                }
            }
        }
        let side = [4u64, 4, 2, 2][dims - 1];
        let jittered = Jittered::new(dims, side, 1).unwrap();
        let n = side.pow(dims as u32) as usize;
        cases.push((format!("jittered d{dims}"), block(&jittered, 0, n)));
    }
    for (name, points) in &cases {
        let t = t_value(points).unwrap();
        assert_eq!(t, naive_t(points), "{name}");
        let m = points.len().trailing_zeros();
        for t_check in 0..=m {
            let check = elementary_intervals_balanced(points, t_check).unwrap();
            assert_eq!(check.is_net(), t_check >= t, "{name} at t' = {t_check}");
            assert_eq!((check.m, check.t), (m, t_check));
        }
    }
}

/// The reported interval really holds the reported count, which differs from the expected
/// one, and every shape before it (in lexicographic order of exponents) is balanced.
#[test]
fn the_first_unbalanced_interval_is_reported_exactly() {
    for seed in 0..6u64 {
        let points = block(&Independent::new(3, seed).unwrap(), 0, 64);
        for t in 0..4u32 {
            let check = elementary_intervals_balanced(&points, t).unwrap();
            let bad = check
                .first_unbalanced
                .expect("64 random points are not a net");
            assert_eq!(bad.exponents.iter().sum::<u32>(), 6 - t);
            assert_eq!(bad.expected, 1 << t);
            let bounds = bad.bounds();
            let inside = (0..64)
                .filter(|&i| {
                    bounds.iter().enumerate().all(|(j, &(lo, hi))| {
                        let x = points.get(i, j);
                        lo <= x && x < hi
                    })
                })
                .count() as u64;
            assert_eq!(inside, bad.count);
            assert_ne!(bad.count, bad.expected);
            assert_eq!(
                shape_balanced(&points, &bad.exponents).unwrap(),
                Some(bad.clone())
            );
            for shape in compositions(6 - t, 3) {
                if shape == bad.exponents {
                    break;
                }
                assert_eq!(shape_balanced(&points, &shape).unwrap(), None, "{shape:?}");
            }
        }
    }
    // A hand-made case: 4 points of a (0, 2, 2)-net with one point moved from cell
    // [1/2, 3/4) x [1/4, 1/2) to the first row.
    let mut points = Points::new(2, 4).unwrap();
    points
        .column_mut(0)
        .copy_from_slice(&[0.1, 0.35, 0.6, 0.85]);
    points.column_mut(1).copy_from_slice(&[0.1, 0.6, 0.1, 0.85]);
    let bad = elementary_intervals_balanced(&points, 0)
        .unwrap()
        .first_unbalanced
        .unwrap();
    // Shape (0, 2): rows of height 1/4; row 0 holds two points.
    assert_eq!(bad.exponents, vec![0, 2]);
    assert_eq!(bad.cell, vec![0, 0]);
    assert_eq!((bad.count, bad.expected), (2, 1));
    assert_eq!(
        bad.to_string(),
        "elementary interval [0/1, 1/1) x [0/4, 1/4) (exponents [0, 2]) holds 2 points, \
         a net needs 1"
    );
    assert_eq!(t_value(&points).unwrap(), 1);
}

#[test]
fn bad_input_is_an_error() {
    let empty = Points::new(2, 0).unwrap();
    assert!(t_value(&empty).unwrap_err().to_string().contains("empty"));
    let err = t_value(&Points::new(2, 1000).unwrap()).unwrap_err();
    assert!(err.to_string().contains("nearest: 512 or 1024"), "{err}");
    // 50,000 points once overflowed the stack and aborted the process: now an error.
    let err = t_value(&Points::new(2, 50_000).unwrap()).unwrap_err();
    assert!(err.to_string().contains("nearest: 32768 or 65536"), "{err}");
    let err = t_value(&Points::new(1, 3).unwrap()).unwrap_err();
    assert!(err.to_string().contains("nearest: 2 or 4"), "{err}");
    for bad in [1.0, -0.25, f64::NAN, f64::INFINITY] {
        let mut points = Points::new(2, 4).unwrap();
        points.column_mut(1)[2] = bad;
        let err = t_value(&points).unwrap_err().to_string();
        assert!(
            err.contains("point 2 in dimension 1") && err.contains("[0, 1)"),
            "{err}"
        );
        assert!(elementary_intervals_balanced(&points, 0).is_err());
        assert!(shape_balanced(&points, &[1, 1]).is_err());
    }
    let points = block(&Sobol::new(2, Scramble::None, 0).unwrap(), 0, 16);
    let err = elementary_intervals_balanced(&points, 5).unwrap_err();
    assert!(err.to_string().contains("at most m = 4"), "{err}");
    assert!(shape_balanced(&points, &[1, 1, 1]).is_err());
    assert!(shape_balanced(&points, &[3, 2]).is_err());
    assert!(shape_balanced(&points, &[u32::MAX, 2]).is_err());
    assert_eq!(shape_balanced(&points, &[2, 2]).unwrap(), None);
    // One point is a (0, 0, d)-net.
    assert_eq!(t_value(&Points::new(5, 1).unwrap()).unwrap(), 0);
}

/// The largest sizes the brief asks for, 2^16 points in 2-D: a (0, 16, 2)-net and random
/// points, which are no better than a (16, 16, 2)-net. `cargo bench --bench quality` times
/// them. They run on a test thread's 2 MiB stack: the search is not recursive in `m`.
#[test]
fn t_value_of_2_16_points_in_2d() {
    let points = block(&Sobol::new(2, Scramble::Owen, 1).unwrap(), 0, 1 << 16);
    assert_eq!(t_value(&points).unwrap(), 0);
    let random = block(&Independent::new(2, 1).unwrap(), 0, 1 << 16);
    assert_eq!(t_value(&random).unwrap(), 16);
}
