//! Periodograms and radial power spectra of 2-D point sets, against direct evaluation and the
//! expected spectra of white noise and jittered sampling.

use crate::common::block;
use mcint::Points;
use mcint::quality::{
    Periodogram, RadialSpectrum, mean_periodogram, mean_periodogram_with_threads, periodogram,
    periodogram_with_threads,
};
use mcint::sampler::{BestCandidate, Independent, Jittered, Pmj02, PoissonDisk, Scramble, Sobol};
use std::f64::consts::{PI, TAU};

/// The frequencies of the half plane `ky > 0 or (ky = 0 and kx > 0)`: one of each pair
/// `{k, -k}`, whose periodogram values are equal.
fn half_plane(k: i64) -> Vec<(i64, i64)> {
    let mut out = Vec::new();
    for ky in 0..=k {
        for kx in -k..=k {
            if ky > 0 || kx > 0 {
                out.push((kx, ky));
            }
        }
    }
    out
}

/// `P(k)` by the definition, with a sine and cosine per term.
#[test]
fn matches_direct_evaluation() {
    for (n, k) in [(1usize, 3usize), (7, 5), (50, 7), (203, 12)] {
        let points = block(&Independent::new(2, n as u64).unwrap(), 0, n);
        let p = periodogram(&points, k).unwrap();
        let k = k as i64;
        for ky in -k..=k {
            for kx in -k..=k {
                let (mut re, mut im) = (0.0, 0.0);
                for i in 0..n {
                    let phase = TAU * (kx as f64 * points.get(i, 0) + ky as f64 * points.get(i, 1));
                    re += phase.cos();
                    im -= phase.sin();
                }
                let direct = (re * re + im * im) / n as f64;
                let got = p.get(kx, ky).unwrap();
                assert!(
                    (got - direct).abs() <= 1e-11 * n as f64,
                    "n {n} k ({kx}, {ky}): {got} vs {direct}"
                );
            }
        }
    }
    // Coordinates outside [0, 1) act modulo 1.
    let mut shifted = block(&Independent::new(2, 3).unwrap(), 0, 20);
    let base = periodogram(&shifted, 6).unwrap();
    shifted.column_mut(0).iter_mut().for_each(|x| *x += 3.0);
    shifted.column_mut(1).iter_mut().for_each(|y| *y -= 2.0);
    let moved = periodogram(&shifted, 6).unwrap();
    for (a, b) in base.values().iter().zip(moved.values()) {
        assert!((a - b).abs() < 1e-10, "{a} vs {b}");
    }
}

#[test]
fn zero_frequency_is_n_and_the_spectrum_is_symmetric() {
    for n in [1usize, 5, 64, 1000] {
        let points = block(&Sobol::new(2, Scramble::Owen, 2).unwrap(), 0, n);
        let p = periodogram(&points, 9).unwrap();
        assert_eq!(p.get(0, 0), Some(n as f64));
        assert_eq!((p.points(), p.passes(), p.size()), (n, 1, 19));
        for ky in -9..=9 {
            for kx in -9..=9 {
                assert_eq!(p.get(kx, ky), p.get(-kx, -ky));
            }
        }
    }
    let mean = mean_periodogram(&Independent::new(2, 0).unwrap(), 300, 3, 4).unwrap();
    assert_eq!(mean.get(0, 0), Some(300.0));
    assert_eq!(mean.passes(), 3);
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let points = block(&Independent::new(2, 8).unwrap(), 0, 333);
    let one = periodogram_with_threads(&points, 20, 1).unwrap();
    for threads in [2, 3, 5, 16, 64] {
        assert_eq!(periodogram_with_threads(&points, 20, threads).unwrap(), one);
    }
    let pmj = Pmj02::new(2, 4).unwrap();
    let one = mean_periodogram_with_threads(&pmj, 256, 5, 17, 1).unwrap();
    for threads in [2, 4, 7] {
        assert_eq!(
            mean_periodogram_with_threads(&pmj, 256, 5, 17, threads).unwrap(),
            one
        );
    }
    assert_eq!(mean_periodogram(&pmj, 256, 5, 17).unwrap(), one);
}

/// White noise: for independent uniform points and integer `k != 0`,
/// `S = sum_j z_j` with `z_j = exp(-2 pi i k . x_j)` independent, mean 0 and `E z_j^2 = 0`, so
/// `E P(k) = E|S|^2 / N = 1` and `E|S|^4 = 2N^2 - N` gives `Var P(k) = 1 - 1/N`. The same
/// fourth-moment count gives `Cov(P(k), P(k')) = 0` for `k' != +-k`. The mean of `M` passes
/// therefore has variance `(1 - 1/N) / M` at each `k`, uncorrelated across the half plane.
#[test]
fn white_noise_has_unit_power() {
    let (n, passes, k) = (256usize, 64usize, 16usize);
    let p = mean_periodogram(&Independent::new(2, 21).unwrap(), n, passes, k).unwrap();
    let variance = (1.0 - 1.0 / n as f64) / passes as f64;

    let freqs = half_plane(k as i64);
    let grand = freqs
        .iter()
        .map(|&(kx, ky)| p.get(kx, ky).unwrap())
        .sum::<f64>()
        / freqs.len() as f64;
    let se = (variance / freqs.len() as f64).sqrt();
    assert!(
        (grand - 1.0).abs() < 5.0 * se,
        "grand mean {grand}, se {se}"
    );

    // Each annulus holds counts/2 distinct pairs {k, -k}.
    let radial = p.radial_spectrum();
    assert_eq!(radial.frequencies.len(), k);
    assert_eq!(
        radial.counts.iter().sum::<usize>(),
        count_in_disc(k as f64 + 0.5) - 1
    );
    for (i, (&power, &count)) in radial.power.iter().zip(&radial.counts).enumerate() {
        let se = (variance / (count / 2) as f64).sqrt();
        assert!(
            (power - 1.0).abs() < 5.0 * se,
            "annulus {}: power {power}, se {se}",
            i + 1
        );
    }

    // Anisotropy: over an annulus of 2n values (n distinct, each with variance s2 =
    // (1 - 1/N)/M), the sample variance with divisor 2n - 1 has expectation
    // s2 * 2(n - 1)/(2n - 1). Each P is near a Gamma(M, 1/M) variable (kurtosis excess 6/M),
    // so the sample variance of n distinct values has relative variance about
    // (2 + 6/M)/(n - 1). Pool the annuli with weights n - 1.
    let (mut ratio_sum, mut weight) = (0.0, 0.0);
    for (&a, &count) in radial.anisotropy.iter().zip(&radial.counts) {
        let distinct = (count / 2) as f64;
        let expected = variance * 2.0 * (distinct - 1.0) / (2.0 * distinct - 1.0);
        ratio_sum += (distinct - 1.0) * a / expected;
        weight += distinct - 1.0;
    }
    let pooled = ratio_sum / weight;
    let se = ((2.0 + 6.0 / passes as f64) / weight).sqrt();
    println!(
        "white noise: grand mean {grand:.4}, pooled anisotropy / expected {pooled:.3} (se {se:.3})"
    );
    assert!((pooled - 1.0).abs() < 5.0 * se, "pooled {pooled}, se {se}");
}

/// Integer points with `0 < |k| < r`, plus the origin.
fn count_in_disc(r: f64) -> usize {
    let k = r.ceil() as i64;
    (-k..=k)
        .flat_map(|y| (-k..=k).map(move |x| (x, y)))
        .filter(|&(x, y)| ((x * x + y * y) as f64) < r * r)
        .count()
}

/// Jittered sampling, one uniform point in each cell of an `n x n` grid. With `c_j` the cell
/// corners and `u_j` the uniform offsets, `E z_j = exp(-2 pi i k . c_j) psi(k)` with
/// `|psi(k)|^2 = sinc^2(pi kx / n) sinc^2(pi ky / n)`, and `sum_j exp(-2 pi i k . c_j) = 0` unless
/// both components of `k` are multiples of `n`, where `psi(k) = 0` for `k != 0`. Hence
/// `E P(k) = 1 - |psi(k)|^2` exactly, which is `(pi |k| / n)^2 / 3` to first order: almost no
/// power at low frequencies. The test compares the mean ratio `P(k) / (1 - |psi(k)|^2)` over
/// the half plane with 1, using the spread of the per-pass means (independent passes) for
/// the standard error.
#[test]
fn jittered_power_matches_theory() {
    let (side, passes, k) = (32u64, 32usize, 16usize);
    let n = (side * side) as usize;
    let jittered = Jittered::new(2, side, 5).unwrap();
    let sinc = |x: f64| if x == 0.0 { 1.0 } else { x.sin() / x };
    let expected = |kx: i64, ky: i64| {
        let psi = sinc(PI * kx as f64 / side as f64) * sinc(PI * ky as f64 / side as f64);
        1.0 - psi * psi
    };
    let freqs = half_plane(k as i64);
    let mut pass_means = Vec::new();
    for pass in 0..passes as u64 {
        let p = periodogram(&block(&jittered, pass * n as u64, n), k).unwrap();
        let ratio: f64 = freqs
            .iter()
            .map(|&(kx, ky)| p.get(kx, ky).unwrap() / expected(kx, ky))
            .sum();
        pass_means.push(ratio / freqs.len() as f64);
    }
    let mean = pass_means.iter().sum::<f64>() / passes as f64;
    let var = pass_means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (passes - 1) as f64;
    let se = (var / passes as f64).sqrt();
    println!("jittered: mean P/E[P] = {mean:.4} (se {se:.4})");
    assert!((mean - 1.0).abs() < 5.0 * se, "mean {mean}, se {se}");

    // The averaged periodogram and its radial average show the low-frequency hole:
    // E P <= (pi * 4 / 32)^2 / 3 ~ 0.05 for |k| <= 4.
    let p = mean_periodogram(&jittered, n, passes, k).unwrap();
    let radial = p.radial_spectrum();
    for i in 0..4 {
        assert!(
            radial.power[i] < 0.1,
            "annulus {}: {}",
            i + 1,
            radial.power[i]
        );
    }
    assert!(p.get(1, 0).unwrap() < 0.02);
}

/// Blue noise has little power at low frequencies. There is no closed form for Poisson-disk
/// or best-candidate sets, so this is the qualitative property only: the radially averaged
/// power up to a quarter of sqrt(N) (about a fifth of the principal frequency, near 1 / r) is
/// below 0.2, where white noise sits at 1, and the missing power piles up above 1 near the
/// principal frequency. For Poisson disk this holds for the maximal sets; the sampler's
/// passes are checked in `poisson_disk_passes_are_thinned_maximal_sets`.
#[test]
fn blue_noise_has_a_low_frequency_hole() {
    let (n, passes, k) = (1024usize, 8usize, 48usize);
    let low = (n as f64).sqrt() as usize / 4;
    let summary = |name: &str, radial: &RadialSpectrum| {
        let mean_low = radial.power[..low].iter().sum::<f64>() / low as f64;
        let peak = radial.power.iter().cloned().fold(0.0, f64::max);
        println!("{name}: mean power over |k| <= {low}: {mean_low:.4}, peak {peak:.2}");
        (mean_low, peak)
    };

    let best = BestCandidate::new(2, n as u64, 3).unwrap();
    let radial = mean_periodogram(&best, n, passes, k)
        .unwrap()
        .radial_spectrum();
    let (mean_low, peak) = summary("best candidate", &radial);
    assert!(mean_low < 0.2 && peak > 1.0);

    let poisson = PoissonDisk::new(2, n as u64, 3).unwrap();
    let mut power = vec![0.0; k];
    for pass in 0..passes as u64 {
        let radial = periodogram(&maximal_set(&poisson, pass), k)
            .unwrap()
            .radial_spectrum();
        power
            .iter_mut()
            .zip(&radial.power)
            .for_each(|(a, p)| *a += p);
    }
    power.iter_mut().for_each(|a| *a /= passes as f64);
    let radial = RadialSpectrum { power, ..radial };
    let (mean_low, peak) = summary("poisson disk maximal sets", &radial);
    assert!(mean_low < 0.2 && peak > 1.0);

    let white = mean_periodogram(&Independent::new(2, 3).unwrap(), n, passes, k)
        .unwrap()
        .radial_spectrum();
    let (white_low, _) = summary("independent", &white);
    // About 113 distinct pairs {k, -k} with |k| < 8.5, times 8 passes: a standard error near
    // 0.035 (white noise section above), so 0.8 is more than 5 of them below 1.
    assert!(
        white_low > 0.8,
        "white noise low-frequency power {white_low}"
    );
}

fn maximal_set(poisson: &PoissonDisk, pass: u64) -> Points {
    let set = poisson.maximal_set(pass);
    let mut points = Points::new(2, set.len()).unwrap();
    for (i, p) in set.iter().enumerate() {
        points.column_mut(0)[i] = p[0];
        points.column_mut(1)[i] = p[1];
    }
    points
}

/// A Poisson-disk pass is a uniformly random subset of `N` of the `M` points of a maximal set
/// (its first `N` after a shuffle). For such a subset of `z_1 .. z_M`, each pair is kept with
/// probability `N(N-1) / (M(M-1))`, so
/// `E[P_pass(k) | set] = 1 - c + c P_set(k)` with `c = (N - 1) / (M - 1)`: thinning adds a
/// white floor `1 - c` (about 0.2 here) under the set's own spectrum. The test checks this
/// identity over the half plane, pass by pass, with the spread of the per-pass means as the
/// standard error; it is why the sampler's passes have low-frequency power near 0.25 while
/// its maximal sets have about 0.06.
#[test]
fn poisson_disk_passes_are_thinned_maximal_sets() {
    let (n, passes, k) = (1024usize, 24u64, 16usize);
    let poisson = PoissonDisk::new(2, n as u64, 8).unwrap();
    let freqs = half_plane(k as i64);
    let mut deviations = Vec::new();
    let mut floors = Vec::new();
    for pass in 0..passes {
        let set = maximal_set(&poisson, pass);
        let c = (n - 1) as f64 / (set.len() - 1) as f64;
        let full = periodogram(&set, k).unwrap();
        let thinned = periodogram(&block(&poisson, pass * n as u64, n), k).unwrap();
        let sum: f64 = freqs
            .iter()
            .map(|&(kx, ky)| {
                thinned.get(kx, ky).unwrap() - (1.0 - c + c * full.get(kx, ky).unwrap())
            })
            .sum();
        deviations.push(sum / freqs.len() as f64);
        floors.push(1.0 - c);
    }
    let m = passes as f64;
    let mean = deviations.iter().sum::<f64>() / m;
    let var = deviations.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (m - 1.0);
    let se = (var / m).sqrt();
    let floor = floors.iter().sum::<f64>() / m;
    println!(
        "poisson disk passes: thinning floor 1 - c = {floor:.3}, mean deviation {mean:.4} (se {se:.4})"
    );
    assert!(mean.abs() < 5.0 * se, "mean deviation {mean}, se {se}");
}

#[test]
fn bad_input_is_an_error() {
    let points = block(&Independent::new(2, 0).unwrap(), 0, 16);
    let err = periodogram(&points, 0).unwrap_err().to_string();
    assert!(
        err.contains("max_frequency") && err.contains("1..=1024"),
        "{err}"
    );
    assert!(periodogram(&points, Periodogram::MAX_FREQUENCY + 1).is_err());
    assert!(periodogram(&points, Periodogram::MAX_FREQUENCY).is_ok());
    assert!(periodogram(&Points::new(2, 0).unwrap(), 4).is_err());
    let err = periodogram(&Points::new(3, 4).unwrap(), 4).unwrap_err();
    assert!(err.to_string().contains("expected 2"), "{err}");
    assert!(periodogram_with_threads(&points, 4, 0).is_err());
    for bad in [f64::NAN, f64::INFINITY] {
        let mut broken = points.clone();
        broken.column_mut(1)[3] = bad;
        let err = periodogram(&broken, 4).unwrap_err().to_string();
        assert!(err.contains("point 3 in dimension 1"), "{err}");
    }

    let independent = Independent::new(2, 0).unwrap();
    assert!(mean_periodogram(&independent, 16, 0, 4).is_err());
    assert!(mean_periodogram(&independent, 0, 4, 4).is_err());
    assert!(mean_periodogram(&Independent::new(3, 0).unwrap(), 16, 4, 4).is_err());
    let err = mean_periodogram(&independent, Periodogram::MAX_POINTS + 1, 1, 1).unwrap_err();
    assert!(
        err.to_string()
            .contains(&Periodogram::MAX_POINTS.to_string()),
        "{err}"
    );
    let err = mean_periodogram(&independent, 1 << 16, 1 << 10, 64).unwrap_err();
    assert!(err.to_string().contains("terms"), "{err}");
    let err = mean_periodogram(&Jittered::new(2, 8, 0).unwrap(), 32, 2, 4).unwrap_err();
    assert!(err.to_string().contains("pass size 64"), "{err}");
    let small = Pmj02::with_max_points(2, 4, 0).unwrap();
    let err = mean_periodogram(&small, 32, 2, 4).unwrap_err();
    assert!(err.to_string().contains("at most 16"), "{err}");
    assert!(mean_periodogram(&small, 16, 2, 4).is_ok());
}

/// The figure the brief asks for: N = 1024, K = 64, 16 passes, on one and two threads
/// (`cargo bench --bench quality` times it).
#[test]
fn a_typical_spectrum_has_the_same_bits_on_one_and_two_threads() {
    let sampler = Independent::new(2, 1).unwrap();
    let one = mean_periodogram_with_threads(&sampler, 1024, 16, 64, 1).unwrap();
    assert_eq!(one.size(), 129);
    assert_eq!(
        one,
        mean_periodogram_with_threads(&sampler, 1024, 16, 64, 2).unwrap()
    );
}
