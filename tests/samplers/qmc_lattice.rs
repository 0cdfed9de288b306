//! The rank-1 lattice sampler: reference values from QMCPy, block/point agreement, the lattice
//! structure of every power-of-two prefix, exact integration of trigonometric polynomials, and
//! the variance of the randomly shifted rule against its closed form.

use crate::common::SplitMix64;
use mcint::Points;
use mcint::sampler::{Lattice, PassKind, Sampler, Scramble};
use std::f64::consts::PI;

/// Points per pass of Kuo's vector.
const KUO_MAX: u64 = 1 << 20;

/// `x * n` as an integer, asserting that it is one (the coordinate lies on the `1/n` grid).
fn numerator(x: f64, n: u64) -> u64 {
    let y = x * n as f64;
    assert!(
        y.fract() == 0.0 && y >= 0.0 && y < n as f64,
        "{x} is not on the 1/{n} grid"
    );
    y as u64
}

/// `(a - b) mod 1` for two coordinates on the `2^-53` grid; exact in floating point.
fn wrap_difference(a: f64, b: f64) -> f64 {
    let d = a - b;
    if d < 0.0 { d + 1.0 } else { d }
}

fn point(s: &Lattice, index: u64) -> Vec<f64> {
    let mut p = vec![0.0; s.dims()];
    s.point(index, &mut p).unwrap();
    p
}

#[test]
fn matches_qmcpy_reference_points() {
    // tests/data/lattice_qmcpy_reference.txt: QMCPy 2.4, which ships the same Kuo vector,
    // Lattice(..., randomize=False, order='RADICAL INVERSE'); commands in the file's header.
    // Values k / 2^20 are exact doubles, so the comparison is bit for bit.
    let text = include_str!("../data/lattice_qmcpy_reference.txt");
    let rows: Vec<(u64, usize, f64)> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (
                f[0].parse().unwrap(),
                f[1].parse().unwrap(),
                f[2].parse().unwrap(),
            )
        })
        .collect();
    assert_eq!(rows.len(), 64 * 5 + 64 * 5 + 64 * 10);

    let all = Lattice::new(9125, Scramble::None, 0).unwrap();
    let mut cached: Option<(u64, Vec<f64>)> = None;
    for &(index, dim, value) in &rows {
        if cached.as_ref().is_none_or(|(i, _)| *i != index) {
            cached = Some((index, point(&all, index)));
        }
        let p = &cached.as_ref().unwrap().1;
        assert_eq!(
            p[dim - 1].to_bits(),
            value.to_bits(),
            "index {index}, dim {dim}"
        );
    }

    // The 5-dimensional sampler's block fill gives the same first 64 points.
    let five = Lattice::new(5, Scramble::None, 0).unwrap();
    let mut block = Points::new(5, 64).unwrap();
    five.fill(0, &mut block).unwrap();
    for &(index, dim, value) in rows.iter().take(64 * 5) {
        assert_eq!(
            block.get(index as usize, dim - 1).to_bits(),
            value.to_bits()
        );
    }
}

#[test]
fn fill_matches_point_bit_for_bit_across_pass_boundaries() {
    let samplers = [
        Lattice::new(7, Scramble::Shift, 11).unwrap(),
        Lattice::new(7, Scramble::None, 11).unwrap(),
        Lattice::with_generator(vec![1, 5, 7, 3], 4, Scramble::Shift, 3).unwrap(),
        // A pass exactly as long as the 256-index runs of the block kernel.
        Lattice::with_generator(vec![1, 77, 201], 8, Scramble::Shift, 5).unwrap(),
        Lattice::with_generator(vec![1, (1 << 52) - 3, 12345], 52, Scramble::Shift, 4).unwrap(),
    ];
    let mut rng = SplitMix64(2024);
    for s in &samplers {
        let PassKind::Extensible { max } = s.passes() else {
            panic!("a lattice is extensible");
        };
        for case in 0..40 {
            let len = rng.below(2500) as usize;
            let start = match case % 4 {
                // Straddling a pass boundary.
                0 | 1 => {
                    let boundary = (1 + rng.below(1000)) * max;
                    boundary - rng.below(len as u64 + 1).min(boundary)
                }
                // Anywhere.
                2 => rng.below(1 << 40),
                // At the very end of the index range.
                _ => u64::MAX - len.saturating_sub(1) as u64,
            };
            let mut block = Points::new(s.dims(), len).unwrap();
            s.fill(start, &mut block).unwrap();
            let mut p = vec![0.0; s.dims()];
            for i in 0..len {
                s.point(start + i as u64, &mut p).unwrap();
                for (dim, x) in p.iter().enumerate() {
                    assert_eq!(
                        x.to_bits(),
                        block.get(i, dim).to_bits(),
                        "{s:?}: index {}, dim {dim}",
                        start + i as u64
                    );
                }
            }
        }
    }
}

/// The lattice rule `{frac(k z / 2^m) : k < 2^m}` as sorted integer numerators.
fn lattice_set(z: &[u64], m: u32) -> Vec<Vec<u64>> {
    let n = 1u64 << m;
    let mut set: Vec<Vec<u64>> = (0..n)
        .map(|k| z.iter().map(|&zj| (k * (zj % n)) % n).collect())
        .collect();
    set.sort();
    set
}

#[test]
fn every_power_of_two_prefix_is_a_rank1_lattice_rule() {
    // Literal set comparison in 8 dimensions, unshifted and (after removing the shift, which
    // is point 0 of the pass) shifted, for a pass other than the first.
    let plain = Lattice::new(8, Scramble::None, 0).unwrap();
    let shifted = Lattice::new(8, Scramble::Shift, 5).unwrap();
    let z = plain.generator().to_vec();
    let pass_start = 3 * KUO_MAX;
    let origin = point(&shifted, pass_start);
    for m in 0..=10u32 {
        let n = 1u64 << m;
        let mut unshifted: Vec<Vec<u64>> = (0..n)
            .map(|i| point(&plain, i).iter().map(|&x| numerator(x, n)).collect())
            .collect();
        let mut unrotated: Vec<Vec<u64>> = (0..n)
            .map(|i| {
                let p = point(&shifted, pass_start + i);
                p.iter()
                    .zip(&origin)
                    .map(|(&x, &o)| numerator(wrap_difference(x, o), n))
                    .collect()
            })
            .collect();
        unshifted.sort();
        unrotated.sort();
        let expected = lattice_set(&z, m);
        assert_eq!(unshifted, expected, "unshifted, m = {m}");
        assert_eq!(unrotated, expected, "shifted, m = {m}");
    }

    // All 9125 dimensions: z_1 = 1, so point i is lattice point k = 2^m x_i1 and must equal
    // frac(k z / 2^m) in every coordinate, with k distinct over the prefix.
    for scramble in [Scramble::None, Scramble::Shift] {
        let s = Lattice::new(9125, scramble, 6).unwrap();
        let z = s.generator();
        assert_eq!(z[0], 1);
        let origin = point(&s, pass_start);
        for m in 0..=10u32 {
            let n = 1u64 << m;
            let mut seen = vec![false; n as usize];
            for i in 0..n {
                let p = point(&s, pass_start + i);
                let coord = |j: usize| numerator(wrap_difference(p[j], origin[j]), n);
                let k = coord(0);
                assert!(
                    !seen[k as usize],
                    "{scramble}: m = {m}: lattice point {k} twice"
                );
                seen[k as usize] = true;
                for (j, &zj) in z.iter().enumerate() {
                    assert_eq!(
                        coord(j),
                        k * zj % n,
                        "{scramble}: m = {m}, i = {i}, dim {j}"
                    );
                }
            }
        }
    }

    // A user vector with an even component: still the lattice set.
    let user = Lattice::with_generator(vec![3, 10, 7], 5, Scramble::None, 0).unwrap();
    for m in 0..=5u32 {
        let n = 1u64 << m;
        let mut set: Vec<Vec<u64>> = (0..n)
            .map(|i| point(&user, i).iter().map(|&x| numerator(x, n)).collect())
            .collect();
        set.sort();
        assert_eq!(set, lattice_set(&[3, 10, 7], m), "m = {m}");
    }
}

#[test]
fn coordinates_lie_in_unit_interval() {
    let near_one = (1u64 << 52) - 1;
    let samplers = [
        Lattice::new(64, Scramble::Shift, 1).unwrap(),
        Lattice::new(64, Scramble::None, 1).unwrap(),
        Lattice::with_generator(vec![near_one, 1, near_one - 2], 52, Scramble::Shift, 2).unwrap(),
        Lattice::with_generator(vec![near_one, 1, near_one - 2], 52, Scramble::None, 2).unwrap(),
    ];
    let mut rng = SplitMix64(9);
    for s in &samplers {
        for seed in 0..8 {
            let mut s = s.clone();
            s.reseed(seed);
            for start in [0, rng.below(1 << 50), u64::MAX - 4095] {
                let mut block = Points::new(s.dims(), 4096).unwrap();
                s.fill(start, &mut block).unwrap();
                for dim in 0..s.dims() {
                    assert!(block.column(dim).iter().all(|x| (0.0..1.0).contains(x)));
                }
            }
        }
    }
}

#[test]
fn one_dimensional_projections_of_every_prefix_are_equally_spaced() {
    // For odd z_j, k -> k z_j mod 2^m permutes 0..2^m, so coordinate j of a 2^m prefix takes
    // each value k / 2^m once. Kuo's components are all odd.
    let s = Lattice::new(9125, Scramble::None, 0).unwrap();
    assert!(s.generator().iter().all(|&z| z % 2 == 1));
    // Point i belongs to every prefix of 2^m > i points; the strongest constraint is the
    // smallest such m, the bit length of i. Distinct values on the 1/2^m grid filling a
    // prefix of 2^m points are exactly the grid.
    // One 1024-bit set per dimension.
    let mut seen = vec![0u64; 9125 * 16];
    let mut p = vec![0.0; 9125];
    for i in 0..1024u64 {
        s.point(i, &mut p).unwrap();
        let m = 64 - i.leading_zeros();
        for (dim, &x) in p.iter().enumerate() {
            numerator(x, 1 << m);
            let k = numerator(x, 1024) as usize;
            let (word, bit) = (dim * 16 + k / 64, 1u64 << (k % 64));
            assert!(
                seen[word] & bit == 0,
                "dim {dim}: value {x} repeated by point {i}"
            );
            seen[word] |= bit;
        }
    }
}

/// Mean of `cos(2 pi h.x)` and `sin(2 pi h.x)` over the block.
fn trig_means(block: &Points, h: &[i64]) -> (f64, f64) {
    let (mut c, mut s) = (0.0, 0.0);
    for i in 0..block.len() {
        let t: f64 = h
            .iter()
            .enumerate()
            .map(|(j, &hj)| hj as f64 * block.get(i, j))
            .sum();
        c += (2.0 * PI * t).cos();
        s += (2.0 * PI * t).sin();
    }
    (c / block.len() as f64, s / block.len() as f64)
}

/// All integer vectors in `[-r, r]^d` except zero.
fn small_frequencies(d: usize, r: i64) -> Vec<Vec<i64>> {
    let mut all = vec![vec![]];
    for _ in 0..d {
        all = all
            .into_iter()
            .flat_map(|v: Vec<i64>| {
                (-r..=r).map(move |x| {
                    let mut w = v.clone();
                    w.push(x);
                    w
                })
            })
            .collect();
    }
    all.retain(|h| h.iter().any(|&x| x != 0));
    all
}

#[test]
fn integrates_trigonometric_polynomials_as_theory_says() {
    // For N = 2^m points frac(k z / N + Delta), the mean of exp(2 pi i h.x) is
    // exp(2 pi i h.Delta) when h.z ≡ 0 (mod N) and exactly zero otherwise (a full sum of N-th
    // roots of unity). Rounding of h.x and cos leaves about 1e-14; the tolerance is 1e-12.
    let mut nonzero_cases = 0;
    let mut dual_cases = 0;
    for d in [2usize, 3] {
        for scramble in [Scramble::None, Scramble::Shift] {
            let s = Lattice::new(d, scramble, 21).unwrap();
            let z = s.generator().to_vec();
            for m in [2u32, 4, 7, 10] {
                let n = 1i64 << m;
                let start = 2 * KUO_MAX;
                let mut block = Points::new(d, n as usize).unwrap();
                s.fill(start, &mut block).unwrap();
                let mut frequencies = small_frequencies(d, 3);
                // Add a dual vector with h_2 = 1: h_1 = -z_2 mod N (z_1 = 1), centred.
                let mut h1 = (-(z[1] as i64)).rem_euclid(n);
                if h1 > n / 2 {
                    h1 -= n;
                }
                let mut dual = vec![h1, 1];
                dual.resize(d, 0);
                frequencies.push(dual);
                for h in &frequencies {
                    let hz: i64 = h.iter().zip(&z).map(|(&hj, &zj)| hj * zj as i64).sum();
                    let (c, sn) = trig_means(&block, h);
                    if hz.rem_euclid(n) != 0 {
                        nonzero_cases += 1;
                        assert!(
                            c.abs() < 1e-12 && sn.abs() < 1e-12,
                            "h = {h:?}, N = {n}: {c}, {sn}"
                        );
                    } else {
                        dual_cases += 1;
                        // Point 0 of the pass is the shift itself (the origin when unshifted).
                        let t: f64 = h
                            .iter()
                            .enumerate()
                            .map(|(j, &hj)| hj as f64 * block.get(0, j))
                            .sum();
                        let (ec, es) = ((2.0 * PI * t).cos(), (2.0 * PI * t).sin());
                        assert!(
                            (c - ec).abs() < 1e-12 && (sn - es).abs() < 1e-12,
                            "h = {h:?}, N = {n}"
                        );
                    }
                }
            }
        }
    }
    assert!(
        nonzero_cases > 500 && dual_cases >= 16,
        "{nonzero_cases} {dual_cases}"
    );
}

/// Bernoulli polynomial `B_2(x) = x^2 - x + 1/6`.
fn b2(x: f64) -> f64 {
    x * x - x + 1.0 / 6.0
}

/// Bernoulli polynomial `B_4(x) = x^4 - 2x^3 + x^2 - 1/30`.
fn b4(x: f64) -> f64 {
    x * x * (x * x - 2.0 * x + 1.0) - 1.0 / 30.0
}

/// The smooth periodic test integrand `f(x) = prod_j (1 + 2 pi^2 B_2(x_j))`, whose Fourier
/// coefficients are `f^(h) = prod_{h_j != 0} h_j^-2` (since `2 pi^2 B_2(x) =
/// sum_{h != 0} e^{2 pi i h x} / h^2`); its integral is `f^(0) = 1`.
fn korobov(x: &[f64]) -> f64 {
    x.iter().map(|&t| 1.0 + 2.0 * PI * PI * b2(t)).product()
}

/// `(1/N) sum_k prod_j g(frac(k z_j / N)) - 1`: by the character sum over the lattice this is
/// `sum over nonzero dual vectors h of prod_j c(h_j)` when `g(x) = sum_h c(h) e^{2 pi i h x}`.
fn dual_lattice_sum(z: &[u64], n: u64, g: impl Fn(f64) -> f64) -> f64 {
    let total: f64 = (0..n)
        .map(|k| {
            z.iter()
                .map(|&zj| g(((k * zj) % n) as f64 / n as f64))
                .product::<f64>()
        })
        .sum();
    total / n as f64 - 1.0
}

/// Estimates `Q_p` of the integral of `f` from the first `n` points of passes `0..passes`.
fn pass_estimates(s: &Lattice, n: usize, passes: u64, f: impl Fn(&[f64]) -> f64) -> Vec<f64> {
    let PassKind::Extensible { max } = s.passes() else {
        panic!("a lattice is extensible");
    };
    let mut block = Points::new(s.dims(), n).unwrap();
    let mut p = vec![0.0; s.dims()];
    (0..passes)
        .map(|pass| {
            s.fill(pass * max, &mut block).unwrap();
            (0..n)
                .map(|i| {
                    block.copy_point(i, &mut p);
                    f(&p)
                })
                .sum::<f64>()
                / n as f64
        })
        .collect()
}

fn mean_and_variance(v: &[f64]) -> (f64, f64) {
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (v.len() - 1) as f64;
    (mean, var)
}

#[test]
fn randomly_shifted_rule_is_unbiased() {
    // Each point of a shifted rule is uniform on the cube, so E[Q] = integral = 1 even for a
    // small N = 16 in 3-D where the rule is coarse. 1000 independent shifts: the mean must
    // be within 4.5 standard errors (CLT; a false alarm has probability about 7e-6).
    let s = Lattice::new(3, Scramble::Shift, 77).unwrap();
    let q = pass_estimates(&s, 16, 1000, korobov);
    let (mean, var) = mean_and_variance(&q);
    let se = (var / q.len() as f64).sqrt();
    assert!(var > 0.0);
    assert!((mean - 1.0).abs() < 4.5 * se, "mean {mean}, se {se}");
}

#[test]
fn rqmc_variance_is_far_below_monte_carlo_and_matches_theory() {
    // For a randomly shifted lattice rule, Q(Delta) - I = sum over nonzero dual vectors h
    // (h.z ≡ 0 mod N) of f^(h) e^{2 pi i h.Delta}, so Var Q = V = sum over those h of
    // |f^(h)|^2 (Sloan & Joe 1994). For korobov() the coefficients are prod h_j^-2, and the
    // character sum gives V in closed form with 1 + sum_{h != 0} e^{2 pi i h x} / h^4 =
    // 1 - (2 pi^4 / 3) B_4(x). Monte Carlo with N points has variance sigma^2 / N with
    // sigma^2 = sum_{h != 0} |f^(h)|^2 = (1 + pi^4/45)^2 - 1. A good lattice has no short dual
    // vectors, so V is orders of magnitude smaller.
    let s = Lattice::new(2, Scramble::Shift, 2025).unwrap();
    let n = 1024u64;
    let z = s.generator();
    let v = dual_lattice_sum(z, n, |x| 1.0 - 2.0 * PI.powi(4) / 3.0 * b4(x));
    let sigma2 = (1.0 + PI.powi(4) / 45.0).powi(2) - 1.0;
    let mc = sigma2 / n as f64;
    assert!(
        v > 0.0 && v < 1e-5 * mc,
        "theory: V = {v:e}, sigma^2/N = {mc:e}"
    );

    // Tolerance for the sample variance s^2 of R shifts, distribution-free: all f^(h) are
    // positive, so |Q - I| <= B = sum over nonzero dual h of f^(h) (the same character sum
    // with 1 + 2 pi^2 B_2), hence E(Q - I)^4 <= B^2 V and Var s^2 <= B^2 V / R. Chebyshev
    // then bounds P(|s^2 - V| > V/2) by 4 B^2 / (V R); R = 16384 makes that below 1%.
    let b = dual_lattice_sum(z, n, |x| 1.0 + 2.0 * PI * PI * b2(x));
    let passes = 16384;
    let false_alarm = 4.0 * b * b / (v * passes as f64);
    assert!(false_alarm < 0.01, "Chebyshev bound {false_alarm}");

    let q = pass_estimates(&s, n as usize, passes, korobov);
    let (mean, var) = mean_and_variance(&q);
    assert!(
        (var - v).abs() < 0.5 * v,
        "sample variance {var:e}, theory {v:e}"
    );
    // By Markov's inequality, P(s^2 > 1e-3 sigma^2 / N) <= V / (1e-3 sigma^2 / N) < 1%.
    assert!(
        var < 1e-3 * mc,
        "sample variance {var:e} vs Monte Carlo {mc:e}"
    );
    // And the estimate is centred on the integral: |mean - 1| < 4.5 sqrt(V / R).
    assert!(
        (mean - 1.0).abs() < 4.5 * (v / passes as f64).sqrt(),
        "mean {mean}"
    );
}

#[test]
fn passes_repeat_without_shift_and_differ_with_it() {
    let plain = Lattice::new(4, Scramble::None, 1).unwrap();
    assert!(!plain.is_randomized());
    assert_eq!(plain.passes(), PassKind::Extensible { max: KUO_MAX });
    assert_eq!(point(&plain, 0), vec![0.0; 4]);
    for i in [0, 1, 77, KUO_MAX - 1] {
        assert_eq!(point(&plain, i), point(&plain, 5 * KUO_MAX + i));
    }

    let mut shifted = Lattice::new(4, Scramble::Shift, 1).unwrap();
    assert!(shifted.is_randomized());
    assert_eq!(shifted.name(), "lattice");
    let first = point(&shifted, 3);
    assert_ne!(first, point(&shifted, KUO_MAX + 3));
    shifted.reseed(2);
    assert_eq!(shifted.seed(), 2);
    assert_ne!(first, point(&shifted, 3));
    // Same seed, same points.
    assert_eq!(
        point(&Lattice::new(4, Scramble::Shift, 9).unwrap(), 1234),
        point(&Lattice::new(4, Scramble::Shift, 9).unwrap(), 1234)
    );

    let user = Lattice::with_generator(vec![1, 3], 3, Scramble::None, 0).unwrap();
    assert_eq!(user.passes(), PassKind::Extensible { max: 8 });
    assert_eq!(user.log2_max_points(), 3);
    // Debug names the vector instead of printing all 9125 components.
    let debug = format!("{:?}", Lattice::new(9125, Scramble::Shift, 0).unwrap());
    assert!(debug.contains("lattice-33002-1024-1048576.9125") && debug.len() < 200);
}

#[test]
fn rejects_bad_input() {
    for dims in [0, 9126, usize::MAX] {
        let err = Lattice::new(dims, Scramble::Shift, 0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("1 ..= 9125"), "{err}");
    }
    for scramble in [
        Scramble::Xor,
        Scramble::Lms,
        Scramble::Owen,
        Scramble::Permute,
    ] {
        let err = Lattice::new(3, scramble, 0).unwrap_err().to_string();
        assert!(err.contains("none, shift"), "{err}");
        let err = Lattice::with_generator(vec![1], 4, scramble, 0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("none, shift"), "{err}");
    }
    assert!(Lattice::with_generator(vec![], 4, Scramble::None, 0).is_err());
    // A component of 0 makes its coordinate one value for every point.
    let zero = Lattice::with_generator(vec![1, 0], 4, Scramble::None, 0).unwrap_err();
    assert!(zero.to_string().contains("constant"), "{zero}");
    for log2 in [0, 53, 64, u32::MAX] {
        let err = Lattice::with_generator(vec![1], log2, Scramble::None, 0).unwrap_err();
        assert!(err.to_string().contains("1 ..= 52"), "{err}");
    }
    let err = Lattice::with_generator(vec![1, 16], 4, Scramble::None, 0).unwrap_err();
    assert!(err.to_string().contains("dimension 2"), "{err}");
    assert!(Lattice::with_generator(vec![u64::MAX], 52, Scramble::None, 0).is_err());
    // Components need not be odd, and 2^m - 1 is the largest allowed (0 is refused above).
    assert!(Lattice::with_generator(vec![1, 2, 15], 4, Scramble::Shift, 0).is_ok());

    let s = Lattice::new(3, Scramble::Shift, 0).unwrap();
    assert!(s.point(0, &mut [0.0; 2]).is_err());
    assert!(s.fill(0, &mut Points::new(4, 8).unwrap()).is_err());
    assert!(
        s.fill(u64::MAX - 2, &mut Points::new(3, 8).unwrap())
            .is_err()
    );
    // The last representable indices are fine.
    assert!(
        s.fill(u64::MAX - 7, &mut Points::new(3, 8).unwrap())
            .is_ok()
    );
}
