//! The Sobol' sampler: bit-identity with scipy, fill == point, the net property of every
//! scramble, uniformity of randomized points, the RQMC variance rate and input errors.
//!
//! Reference data (tests/data/sobol_scipy_*.txt) were made with scipy 1.17.1; each file's
//! header repeats its command:
//!
//! ```text
//! python3 -c 'import numpy as np; from scipy.stats.qmc import Sobol; np.savetxt("sobol_scipy_d2.txt", (Sobol(2, scramble=False, bits=32).random(1024) * 2**32).astype(np.uint64), fmt="%d")'
//! python3 -c 'import numpy as np; from scipy.stats.qmc import Sobol; np.savetxt("sobol_scipy_d10.txt", (Sobol(10, scramble=False, bits=32).random(1024) * 2**32).astype(np.uint64), fmt="%d")'
//! python3 -c 'import numpy as np; from scipy.stats.qmc import Sobol; np.savetxt("sobol_scipy_d100.txt", (Sobol(100, scramble=False, bits=32).random(256) * 2**32).astype(np.uint64), fmt="%d")'
//! python3 -c 'import numpy as np; from scipy.stats.qmc import Sobol; x = Sobol(21201, scramble=False, bits=32).random(16) * 2**32; np.savetxt("sobol_scipy_d21201_columns.txt", x[:, [c - 1 for c in [1, 2, 1000, 10000, 21200, 21201]]].astype(np.uint64), fmt="%d")'
//! python3 -c 'import numpy as np; from scipy.stats.qmc import Sobol; s = Sobol(3, scramble=False, bits=32); s.fast_forward(2**32 - 16); np.savetxt("sobol_scipy_d3_tail.txt", (s.random(16) * 2**32).astype(np.uint64), fmt="%d")'
//! ```
//!
//! and the checksums over all 21201 dimensions at indices `2^k` (which use every direction
//! word; scipy's `fast_forward` is linear in the index, so these points come from scipy's own
//! direction numbers `Sobol(21201, scramble=False, bits=32)._sv` by the Gray-code formula,
//! after checking that formula against scipy's `random(1024)` bit for bit):
//!
//! ```text
//! import numpy as np; from scipy.stats.qmc import Sobol
//! eng = Sobol(21201, scramble=False, bits=32); sv = eng._sv.astype(np.uint64)
//! def point(i):
//!     g = i ^ (i >> 1); x = np.zeros(21201, dtype=np.uint64)
//!     for k in range(32):
//!         if (g >> k) & 1: x ^= sv[:, k]
//!     return x
//! w = (eng.random(1024) * 2**32).astype(np.uint64)
//! assert all(np.array_equal(point(i), w[i]) for i in range(1024))
//! weights = 2 * np.arange(21201, dtype=np.uint64) + 1
//! for i in [2**k for k in range(32)] + [2**32 - 1, 3_000_000_007, 123_456_789]:
//!     print(i, int((point(i) * weights).sum(dtype=np.uint64)))
//! ```
//!
//! Chi-square thresholds: `scipy.stats.chi2.isf(1e-5, 63) = 122.727...` (8 x 8 cells, free
//! margins) and `chi2.isf(1e-5, 49) = 103.116...` (8 x 8 cells, both margins fixed).

use crate::common::SplitMix64;
use mcint::Points;
use mcint::sampler::{PassKind, Sampler, Scramble, Sobol};

const TWO_32: f64 = 4_294_967_296.0;
const PASS: u64 = 1 << 32;
const ALL: [Scramble; 4] = [Scramble::None, Scramble::Xor, Scramble::Lms, Scramble::Owen];

/// Rows of unsigned integers from a reference file, skipping `#` comments.
fn read_rows(name: &str) -> Vec<Vec<u64>> {
    let path = format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    text.lines()
        .filter(|line| !line.starts_with('#') && !line.trim().is_empty())
        .map(|line| {
            line.split_whitespace()
                .map(|field| {
                    field
                        .parse()
                        .unwrap_or_else(|e| panic!("{path}: {field}: {e}"))
                })
                .collect()
        })
        .collect()
}

/// The 32-bit word of an unscrambled coordinate, checking that it is exactly `word * 2^-32`.
fn word(x: f64) -> u64 {
    let scaled = x * TWO_32;
    assert!(
        scaled == scaled.floor() && (0.0..TWO_32).contains(&scaled),
        "{x}"
    );
    scaled as u64
}

/// The samplers every property test runs on: each scramble, plus Owen with index shuffle.
fn variants(dims: usize, seed: u64) -> Vec<(String, Sobol)> {
    let mut out: Vec<(String, Sobol)> = ALL
        .iter()
        .map(|&s| (s.name().to_string(), Sobol::new(dims, s, seed).unwrap()))
        .collect();
    let shuffled = Sobol::new(dims, Scramble::Owen, seed)
        .unwrap()
        .with_index_shuffle(true);
    out.push(("owen+shuffle".to_string(), shuffled));
    out
}

fn block(sampler: &Sobol, start: u64, len: usize) -> Points {
    let mut points = Points::new(sampler.dims(), len).unwrap();
    sampler.fill(start, &mut points).unwrap();
    points
}

#[test]
fn unscrambled_points_equal_scipy_in_low_dimensions() {
    for (file, dims) in [
        ("sobol_scipy_d2.txt", 2),
        ("sobol_scipy_d10.txt", 10),
        ("sobol_scipy_d100.txt", 100),
    ] {
        let rows = read_rows(file);
        let sobol = Sobol::new(dims, Scramble::None, 0).unwrap();
        let points = block(&sobol, 0, rows.len());
        let mut p = vec![0.0; dims];
        for (i, row) in rows.iter().enumerate() {
            assert_eq!(row.len(), dims, "{file} row {i}");
            sobol.point(i as u64, &mut p).unwrap();
            for (d, &expected) in row.iter().enumerate() {
                assert_eq!(word(points.get(i, d)), expected, "{file} point {i} dim {d}");
                assert_eq!(word(p[d]), expected, "{file} point {i} dim {d} (point)");
            }
        }
    }
}

#[test]
fn unscrambled_points_equal_scipy_in_21201_dimensions() {
    let columns = [1, 2, 1000, 10000, 21200, 21201];
    let rows = read_rows("sobol_scipy_d21201_columns.txt");
    assert_eq!(rows.len(), 16);
    let sobol = Sobol::new(21201, Scramble::None, 0).unwrap();
    let points = block(&sobol, 0, 16);
    for (i, row) in rows.iter().enumerate() {
        for (&dim, &expected) in columns.iter().zip(row) {
            assert_eq!(
                word(points.get(i, dim - 1)),
                expected,
                "point {i} dim {dim}"
            );
        }
    }
}

#[test]
fn every_direction_word_of_every_dimension_equals_scipy() {
    // Points at 2^k are v_k ^ v_(k-1): the checksums cover all 21201 x 32 direction words.
    let rows = read_rows("sobol_scipy_checksums.txt");
    assert_eq!(rows.len(), 35);
    let sobol = Sobol::new(21201, Scramble::None, 0).unwrap();
    let mut p = vec![0.0; 21201];
    for row in &rows {
        let (index, expected) = (row[0], row[1]);
        sobol.point(index, &mut p).unwrap();
        let checksum = p.iter().enumerate().fold(0u64, |sum, (d, &x)| {
            sum.wrapping_add(word(x).wrapping_mul(2 * d as u64 + 1))
        });
        assert_eq!(checksum, expected, "index {index}");
    }
}

#[test]
fn last_points_of_a_pass_equal_scipy_and_unscrambled_passes_repeat() {
    let rows = read_rows("sobol_scipy_d3_tail.txt");
    assert_eq!(rows.len(), 16);
    let sobol = Sobol::new(3, Scramble::None, 5).unwrap();
    for pass in [0, 1, 1000] {
        let points = block(&sobol, pass * PASS + PASS - 16, 16);
        for (i, row) in rows.iter().enumerate() {
            for (d, &expected) in row.iter().enumerate() {
                assert_eq!(
                    word(points.get(i, d)),
                    expected,
                    "pass {pass} point {i} dim {d}"
                );
            }
        }
    }
}

#[test]
fn fill_equals_point_bit_for_bit() {
    let mut rng = SplitMix64(11);
    for dims in [1, 3, 7] {
        for (name, sobol) in variants(dims, 99) {
            let mut starts = vec![0, 1, PASS - 300, PASS - 1, 2 * PASS - 7, u64::MAX - 600];
            starts.extend((0..6).map(|_| rng.next_u64()));
            starts.extend((0..6).map(|_| rng.below(1 << 20)));
            let mut p = vec![0.0; dims];
            for start in starts {
                // Ragged lengths, below and across chunk boundaries and pass boundaries.
                let len = [0, 1, 2, 31, 33, 255, 257, 700][rng.below(8) as usize];
                let room = usize::try_from(u64::MAX - start).unwrap_or(usize::MAX);
                let len = len.min(room.saturating_add(1));
                let points = block(&sobol, start, len);
                for i in 0..len {
                    sobol.point(start + i as u64, &mut p).unwrap();
                    for (d, &x) in p.iter().enumerate() {
                        let y = points.get(i, d);
                        assert_eq!(x.to_bits(), y.to_bits(), "{name} start {start} i {i} d {d}");
                        assert!((0.0..1.0).contains(&x), "{name}: {x}");
                    }
                }
            }
        }
    }
}

#[test]
fn fill_equals_point_in_many_dimensions() {
    // 65 and 1025 dimensions use the larger parsed tables.
    for dims in [65, 1025] {
        for (name, sobol) in variants(dims, 5) {
            let start = PASS - 40;
            let points = block(&sobol, start, 80);
            let mut p = vec![0.0; dims];
            for i in 0..80 {
                sobol.point(start + i as u64, &mut p).unwrap();
                for (d, &x) in p.iter().enumerate() {
                    assert_eq!(
                        x.to_bits(),
                        points.get(i, d).to_bits(),
                        "{name} i {i} d {d}"
                    );
                }
            }
        }
    }
}

#[test]
fn randomized_coordinates_have_53_random_bits() {
    // Randomized coordinates are multiples of 2^-53, and each of the 21 digits below the
    // sequence's 32 is a fair coin across seeds: over 4096 seeds a frequency has sd
    // 0.5/64 = 0.0078; we allow 5 sd.
    const SEEDS: u64 = 4096;
    let tolerance = 5.0 * 0.5 / (SEEDS as f64).sqrt();
    for (name, sobol) in variants(2, 0) {
        if name == "none" {
            continue;
        }
        let mut ones = [0u32; 21];
        let mut s = sobol.clone();
        let mut p = [0.0; 2];
        for seed in 0..SEEDS {
            s.reseed(seed);
            s.point(PASS + 3, &mut p).unwrap();
            for &x in &p {
                let scaled = x * 9_007_199_254_740_992.0;
                assert_eq!(scaled, scaled.floor(), "{name}: {x}");
            }
            let bits = (p[1] * 9_007_199_254_740_992.0) as u64;
            for (b, count) in ones.iter_mut().enumerate() {
                *count += ((bits >> b) & 1) as u32;
            }
        }
        for (b, &count) in ones.iter().enumerate() {
            let f = f64::from(count) / SEEDS as f64;
            assert!((f - 0.5).abs() < tolerance, "{name} bit {b}: {f}");
        }
    }
}

#[test]
fn fill_splits_anywhere_with_identical_bits() {
    // A block filled at once equals the same block filled in arbitrary pieces.
    let mut rng = SplitMix64(12);
    for (name, sobol) in variants(4, 3) {
        let start = PASS - 1000;
        let whole = block(&sobol, start, 3000);
        let mut at = 0;
        while at < 3000 {
            let len = (1 + rng.below(400) as usize).min(3000 - at);
            let piece = block(&sobol, start + at as u64, len);
            for d in 0..4 {
                assert_eq!(piece.column(d), &whole.column(d)[at..at + len], "{name}");
            }
            at += len;
        }
    }
}

/// Whether `n = 2^m` points of two coordinates (as 32-bit words) form a (0, m, 2)-net: every
/// elementary interval of volume 2^-m holds exactly one point.
fn is_02_net(xs: &[u32], ys: &[u32], m: u32) -> bool {
    (0..=m).all(|k| {
        let mut seen = vec![false; 1 << m];
        xs.iter().zip(ys).all(|(&x, &y)| {
            let a = if k == 0 { 0 } else { (x >> (32 - k)) as usize };
            let b = if k == m {
                0
            } else {
                (y >> (32 - (m - k))) as usize
            };
            let cell = (a << (m - k)) | b;
            !std::mem::replace(&mut seen[cell], true)
        })
    })
}

/// Whether 2^m coordinates form a (0, m, 1)-net: one point in each interval of length 2^-m.
fn is_01_net(xs: &[u32], m: u32) -> bool {
    let mut seen = vec![false; 1 << m];
    xs.iter().all(|&x| {
        let cell = if m == 0 { 0 } else { (x >> (32 - m)) as usize };
        !std::mem::replace(&mut seen[cell], true)
    })
}

/// The leading 32 bits of each coordinate of a column: exact for every scramble, since
/// randomized coordinates are the scrambled word followed by 21 more bits.
fn words(column: &[f64]) -> Vec<u32> {
    column
        .iter()
        .map(|&x| (x * TWO_32).floor() as u32)
        .collect()
}

#[test]
fn first_two_dimensions_are_02_nets_at_every_power_of_two() {
    for seed in [0, 17] {
        for (name, sobol) in variants(2, seed) {
            // Pass 0 and pass 5: every pass is an independently randomized (0, 2)-sequence.
            for pass in [0, 5] {
                let points = block(&sobol, pass * PASS, 1 << 12);
                let (xs, ys) = (words(points.column(0)), words(points.column(1)));
                for m in 0..=12 {
                    let n = 1 << m;
                    assert!(
                        is_02_net(&xs[..n], &ys[..n], m),
                        "{name} seed {seed} pass {pass} m {m}"
                    );
                }
            }
        }
    }
}

#[test]
fn higher_dimensions_are_01_nets_at_every_power_of_two() {
    // Pairs of higher dimensions have t > 0, but every single coordinate is a (0, 1)-sequence.
    let pairs = [2, 9, 99, 999, 21199];
    for (name, sobol) in variants(21201, 4) {
        let points = block(&sobol, 3 * PASS, 1 << 10);
        for j in pairs {
            for d in [j, j + 1] {
                let xs = words(points.column(d));
                for m in 0..=10 {
                    assert!(is_01_net(&xs[..1 << m], m), "{name} dim {d} m {m}");
                }
            }
        }
    }
}

/// Pearson chi-square of counts against equal expected counts.
fn chi_square(counts: &[u64]) -> f64 {
    let total: u64 = counts.iter().sum();
    let expected = total as f64 / counts.len() as f64;
    counts
        .iter()
        .map(|&c| (c as f64 - expected).powi(2) / expected)
        .sum()
}

#[test]
fn randomized_points_are_uniform_across_seeds() {
    // A randomized point is uniform on [0,1)^d whatever its index. Over S seeds the mean of a
    // coordinate has sd 1/sqrt(12 S); we allow 4.5 sd. The first two coordinates binned in 8 x 8
    // cells must pass a chi-square test at p = 1e-5 (63 degrees of freedom: 122.727).
    const SEEDS: u64 = 20_000;
    const DIMS: usize = 4;
    let tolerance = 4.5 / (12.0 * SEEDS as f64).sqrt();
    for (name, sobol) in variants(DIMS, 0) {
        if name == "none" {
            continue;
        }
        for index in [0, PASS + 12_345] {
            let mut sums = [0.0; DIMS];
            let mut cells = [0u64; 64];
            let mut p = [0.0; DIMS];
            let mut s = sobol.clone();
            for seed in 0..SEEDS {
                s.reseed(seed);
                s.point(index, &mut p).unwrap();
                for (sum, &x) in sums.iter_mut().zip(&p) {
                    *sum += x;
                }
                cells[(p[0] * 8.0) as usize * 8 + (p[1] * 8.0) as usize] += 1;
            }
            for (d, sum) in sums.iter().enumerate() {
                let mean = sum / SEEDS as f64;
                assert!(
                    (mean - 0.5).abs() < tolerance,
                    "{name} index {index} dim {d}: {mean}"
                );
            }
            let chi2 = chi_square(&cells);
            assert!(chi2 < 122.727, "{name} index {index}: chi-square {chi2}");
        }
    }
}

#[test]
fn index_shuffle_decorrelates_differently_seeded_streams() {
    // Dimension 0 of two seeds, paired by index, in 8 x 8 cells over 4096 points. Without the
    // shuffle both are nested scrambles of the same van der Corput point, so the pair's cells
    // are a function of its top three bits: only 8 of the 64 cells are used. With the shuffle
    // each aligned block of 8 indices pairs the cells by an unrelated random permutation, so
    // every cell expects 64 points; both margins are exactly uniform (one point per cell per
    // block), so the statistic has 49 degrees of freedom: threshold chi2.isf(1e-5, 49) = 103.1.
    let cells = |shuffle: bool| {
        let a = Sobol::new(1, Scramble::Owen, 1)
            .unwrap()
            .with_index_shuffle(shuffle);
        let b = Sobol::new(1, Scramble::Owen, 2)
            .unwrap()
            .with_index_shuffle(shuffle);
        let (pa, pb) = (block(&a, 0, 4096), block(&b, 0, 4096));
        let mut cells = [0u64; 64];
        for (&x, &y) in pa.column(0).iter().zip(pb.column(0)) {
            cells[(x * 8.0) as usize * 8 + (y * 8.0) as usize] += 1;
        }
        cells
    };
    let plain = cells(false);
    assert_eq!(plain.iter().filter(|&&c| c > 0).count(), 8);
    let chi2 = chi_square(&cells(true));
    assert!(chi2 < 103.116, "chi-square {chi2}");
}

#[test]
fn index_shuffle_only_affects_owen() {
    for scramble in [Scramble::None, Scramble::Xor, Scramble::Lms] {
        let plain = Sobol::new(3, scramble, 8).unwrap();
        let shuffled = plain.clone().with_index_shuffle(true);
        assert_eq!(
            block(&plain, 77, 100),
            block(&shuffled, 77, 100),
            "{scramble}"
        );
    }
    let plain = Sobol::new(3, Scramble::Owen, 8).unwrap();
    let shuffled = plain.clone().with_index_shuffle(true);
    assert_ne!(block(&plain, 0, 100), block(&shuffled, 0, 100));
}

#[test]
fn owen_scrambled_variance_is_far_below_monte_carlo() {
    // f(x, y) = e^x sin(pi y): smooth, mean 2(e - 1)/pi, variance
    // sigma^2 = (e^2 - 1)/4 - 4 (e - 1)^2 / pi^2 = 0.4010. Independent sampling with N = 2^10
    // has variance sigma^2 / N. For smooth integrands the scrambled-net variance is
    // O(N^-3 (log N)^(s-1)) (Owen 1997), here a ratio of order N^-2 log N ~ 1e-5 to the
    // Monte Carlo variance; we require 0.01, which a sample variance over 64 seeds (63 degrees
    // of freedom, within a factor 2 of the truth with probability above 1 - 1e-6) cannot miss
    // unless the rate is lost. The sample variance of the replicate means also checks they
    // centre on the true value.
    use std::f64::consts::{E, PI};
    const N: usize = 1 << 10;
    const SEEDS: u64 = 64;
    let truth = 2.0 * (E - 1.0) / PI;
    let sigma2 = (E * E - 1.0) / 4.0 - 4.0 * (E - 1.0).powi(2) / (PI * PI);
    for shuffle in [false, true] {
        let means: Vec<f64> = (0..SEEDS)
            .map(|seed| {
                let s = Sobol::new(2, Scramble::Owen, seed)
                    .unwrap()
                    .with_index_shuffle(shuffle);
                let p = block(&s, 0, N);
                let sum: f64 = p
                    .column(0)
                    .iter()
                    .zip(p.column(1))
                    .map(|(&x, &y)| x.exp() * (PI * y).sin())
                    .sum();
                sum / N as f64
            })
            .collect();
        let mean = means.iter().sum::<f64>() / SEEDS as f64;
        let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (SEEDS - 1) as f64;
        let ratio = var / (sigma2 / N as f64);
        assert!(ratio < 0.01, "shuffle {shuffle}: variance ratio {ratio}");
        // The mean over seeds is within 5 of its own standard errors of the truth (plus
        // rounding).
        let se = (var / SEEDS as f64).sqrt();
        assert!(
            (mean - truth).abs() < 5.0 * se + 1e-12,
            "shuffle {shuffle}: {mean} vs {truth}"
        );
    }
}

#[test]
fn bad_input_gives_errors_naming_the_allowed_values() {
    for dims in [0, 21202] {
        let err = Sobol::new(dims, Scramble::None, 0).unwrap_err().to_string();
        assert!(err.contains("1 to 21201"), "{err}");
    }
    for scramble in [Scramble::Permute, Scramble::Shift] {
        let err = Sobol::new(2, scramble, 0).unwrap_err().to_string();
        assert!(err.contains("none, xor, lms, owen"), "{err}");
    }
    let sobol = Sobol::new(3, Scramble::Owen, 0).unwrap();
    assert!(sobol.point(0, &mut [0.0; 2]).is_err());
    assert!(sobol.fill(0, &mut Points::new(2, 4).unwrap()).is_err());
    // A block whose last index would overflow u64.
    assert!(
        sobol
            .fill(u64::MAX - 1, &mut Points::new(3, 4).unwrap())
            .is_err()
    );
    assert!(Sobol::new(21201, Scramble::Lms, 0).is_ok());
}

#[test]
fn sampler_metadata() {
    let mut sobol = Sobol::new(5, Scramble::Lms, 3).unwrap();
    assert_eq!(sobol.name(), "sobol");
    assert_eq!(sobol.dims(), 5);
    assert_eq!(sobol.passes(), PassKind::Extensible { max: 1 << 32 });
    assert_eq!(sobol.scramble(), Scramble::Lms);
    assert!(sobol.is_randomized());
    assert!(!Sobol::new(5, Scramble::None, 3).unwrap().is_randomized());
    let before = block(&sobol, 0, 8);
    sobol.reseed(4);
    assert_eq!(sobol.seed(), 4);
    assert_ne!(before, block(&sobol, 0, 8));
    // Randomized passes differ; unscrambled passes repeat.
    assert_ne!(block(&sobol, 0, 8), block(&sobol, PASS, 8));
    let plain = Sobol::new(5, Scramble::None, 3).unwrap();
    assert_eq!(block(&plain, 0, 8), block(&plain, 7 * PASS, 8));
    // Boxed, as the integrator uses it.
    let boxed: Box<dyn Sampler> = Box::new(plain.clone());
    assert_eq!(boxed.name(), "sobol");
    assert!(format!("{plain:?}").contains("Sobol"));
}
