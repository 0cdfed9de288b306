//! Convergence rates measured by `mcint::quality::Convergence`, checked against theory.
//!
//! Every tolerance is derived, not tuned:
//!
//! * The fitted slope carries a standard error `SE` (the sampling error of the RMSEs
//!   propagated through the least-squares fit, inflated by the Birge ratio when the points
//!   scatter more than their errors allow), and each check allows `4 SE`.
//! * The asymptotic rates (`-1/2`, `-1`, `-3/2`, `-3/4`) are limits; over a finite range of `N`
//!   the RMSE also has lower-order terms (for scrambled nets on smooth integrands a
//!   `sqrt(log N)` factor, which raises the slope by up to `1/(2 ln N)`). Rather than guess an
//!   allowance for them, the tests compute the exact RMSE each sampler has at each `N`
//!   ([`theory`]), fit the same line through those exact values, and compare the measured slope
//!   with the *exact* slope over that range within `4 SE`. How far that exact slope is from the
//!   asymptotic rate is the modelling allowance; it is computed, printed and bounded too.
//! * The measured RMSE levels must match the exact ones too (the mean of `ln(measured /
//!   exact)` over the sizes within `4` of its standard errors), which checks the samplers
//!   themselves: the Owen-scrambled net variance below depends only on the net being a
//!   `(0, m, 2)`-net, and Sobol' and pmj02, two separate implementations, both match it.
//!
//! Seeds are fixed. The sizes run from `2^6` to `2^16` (jittered: `k^2` for `k = 8 .. 256`,
//! about evenly spaced in `log N`), with `R = 128` passes, so each slope has `SE ≈ 0.01`.

use mcint::quality::{Convergence, ConvergenceStudy};
use mcint::sampler::{Independent, Jittered, Pmj02, Sampler, Scramble, Sobol};
use mcint::testfns::{GraphicsIntegrand, TestFunction};
use mcint::{Error, Result};
use std::cell::Cell;

/// Exact variances of the estimators on the graphics integrands.
mod theory {
    use mcint::testfns::{GraphicsIntegrand, TestFunction};
    use std::f64::consts::PI;

    /// Nodes and weights of 5-point Gauss-Legendre on [-1, 1]: a cell mean of the Gaussian
    /// exact to rounding, without the cancellation of an erf difference on narrow cells.
    const GL_NODES: [f64; 5] = [
        0.0,
        -0.538_469_310_105_683_1,
        0.538_469_310_105_683_1,
        -0.906_179_845_938_664,
        0.906_179_845_938_664,
    ];
    const GL_WEIGHTS: [f64; 5] = [
        0.568_888_888_888_888_9,
        0.478_628_670_499_366_5,
        0.478_628_670_499_366_5,
        0.236_926_885_056_189_1,
        0.236_926_885_056_189_1,
    ];

    /// Mean of the factor `g(t)` of a product integrand over `[t0, t1]`.
    fn factor_mean(f: GraphicsIntegrand, t0: f64, t1: f64) -> f64 {
        match f {
            GraphicsIntegrand::Bilinear => 0.5 * (t0 + t1),
            GraphicsIntegrand::Gaussian => {
                let (mid, half) = (0.5 * (t0 + t1), 0.5 * (t1 - t0));
                GL_NODES
                    .iter()
                    .zip(GL_WEIGHTS)
                    .map(|(&x, w)| w * (-(mid + half * x).powi(2)).exp())
                    .sum::<f64>()
                    / 2.0
            }
            _ => unreachable!("{f} is not a product"),
        }
    }

    /// Mean and variance of the factor `g` over `[0, 1]`.
    fn factor_moments(f: GraphicsIntegrand) -> (f64, f64) {
        match f {
            GraphicsIntegrand::Bilinear => (0.5, 1.0 / 12.0),
            GraphicsIntegrand::Gaussian => {
                let mean = 0.5 * PI.sqrt() * libm::erf(1.0);
                // ∫ e^{-2t²} = √(π/8) erf(√2).
                let square = (PI / 8.0).sqrt() * libm::erf(2f64.sqrt());
                (mean, square - mean * mean)
            }
            _ => unreachable!("{f} is not a product"),
        }
    }

    /// Variance of the cell means of `g` over `cells` equal cells of `[0, 1]`.
    fn factor_cell_variance(f: GraphicsIntegrand, cells: u64) -> f64 {
        let (mean, _) = factor_moments(f);
        let h = 1.0 / cells as f64;
        (0..cells)
            .map(|i| (factor_mean(f, i as f64 * h, (i + 1) as f64 * h) - mean).powi(2))
            .sum::<f64>()
            / cells as f64
    }

    /// Area of `[x0, x1] x [y0, y1]` inside the quarter disk `x² + y² < 2/π`, from the
    /// antiderivative of `√(r² - x²)`.
    fn disk_area(x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
        let r2 = 2.0 / PI;
        let r = r2.sqrt();
        let below_arc = |x: f64| {
            let x = x.min(r);
            0.5 * (x * (r2 - x * x).max(0.0).sqrt() + r2 * (x / r).asin())
        };
        // The arc is above y1 for x < xa and above y0 for x < xb.
        let xa = (r2 - y1 * y1).max(0.0).sqrt();
        let xb = (r2 - y0 * y0).max(0.0).sqrt();
        let full = (x1.min(xa) - x0).max(0.0) * (y1 - y0);
        let (lo, hi) = (x0.max(xa), x1.min(xb));
        let partial = if hi > lo {
            below_arc(hi) - below_arc(lo) - y0 * (hi - lo)
        } else {
            0.0
        };
        full + partial
    }

    /// Variance of the integrand itself.
    pub fn variance(f: GraphicsIntegrand) -> f64 {
        match f {
            GraphicsIntegrand::Disk => 0.25,
            _ => {
                let (m, v) = factor_moments(f);
                2.0 * m * m * v + v * v
            }
        }
    }

    /// Variance of the cell means over an `nx` by `ny` grid of equal cells: `W(nx, ny)`.
    pub fn cell_mean_variance(f: GraphicsIntegrand, nx: u64, ny: u64) -> f64 {
        match f {
            GraphicsIntegrand::Disk => {
                let (hx, hy) = (1.0 / nx as f64, 1.0 / ny as f64);
                let mut sum = 0.0;
                for i in 0..nx {
                    for j in 0..ny {
                        let area = disk_area(
                            i as f64 * hx,
                            (i + 1) as f64 * hx,
                            j as f64 * hy,
                            (j + 1) as f64 * hy,
                        );
                        sum += (area / (hx * hy) - 0.5).powi(2);
                    }
                }
                sum / (nx * ny) as f64
            }
            _ => {
                // Means of a product are products of means: W = m² Vy + m² Vx + Vx Vy.
                let (m, _) = factor_moments(f);
                let (vx, vy) = (factor_cell_variance(f, nx), factor_cell_variance(f, ny));
                m * m * (vx + vy) + vx * vy
            }
        }
    }

    /// RMSE of the mean of `n` independent points: `σ / √n`.
    pub fn independent_rmse(f: GraphicsIntegrand, n: u64) -> f64 {
        (variance(f) / n as f64).sqrt()
    }

    /// RMSE of jittered sampling on a `k x k` grid: one uniform point per cell, so the
    /// variance is `(1/N²) Σ var_cell = (σ² - W(k, k)) / N`.
    pub fn jittered_rmse(f: GraphicsIntegrand, k: u64) -> f64 {
        let n = (k * k) as f64;
        ((variance(f) - cell_mean_variance(f, k, k)) / n).sqrt()
    }

    /// RMSE of `N = 2^m` points of any Owen-scrambled (nested uniform) `(0, m, 2)`-net in base
    /// 2: Owen-scrambled Sobol' and pmj02.
    ///
    /// For two distinct points whose unscrambled coordinates share exactly `k1` leading
    /// binary digits in `x` and `k2` in `y`, nested scrambling makes the pair uniform in a
    /// common box of `2^-k1 x 2^-k2`, in different halves of it along both axes, and
    /// independent below; so `E[f f'] - I² = 4W(k1,k2) - 2W(k1+1,k2) - 2W(k1,k2+1) +
    /// W(k1+1,k2+1)` with `W(a, b)` the variance of the means over boxes of `2^-a x 2^-b`. In a
    /// `(0, m, 2)`-net every box of volume `2^-(k1+k2) >= 2^-m` holds `2^(m-k1-k2)` points,
    /// so the ordered pairs sharing at least `(k1, k2)` digits number
    /// `P(k1, k2) = N (2^(m-k1-k2) - 1)` (zero once `k1 + k2 >= m`), the same for every such
    /// net, and those sharing exactly `(k1, k2)` follow by inclusion-exclusion. Then
    /// `N² Var = N σ² + Σ pairs (E[f f'] - I²)`.
    pub fn owen_net_rmse(f: GraphicsIntegrand, m: u32) -> f64 {
        let n = (1u64 << m) as f64;
        let pairs = |k1: u32, k2: u32| -> f64 {
            if k1 + k2 >= m {
                0.0
            } else {
                n * ((1u64 << (m - k1 - k2)) as f64 - 1.0)
            }
        };
        // W(a, b) for a + b <= m + 1.
        let w_table: Vec<Vec<f64>> = (0..=m + 1)
            .map(|a| {
                (0..=m + 1 - a)
                    .map(|b| cell_mean_variance(f, 1 << a, 1 << b))
                    .collect()
            })
            .collect();
        let w = |a: u32, b: u32| w_table[a as usize][b as usize];
        let mut sum = n * variance(f);
        for k1 in 0..m {
            for k2 in 0..m - k1 {
                let exactly =
                    pairs(k1, k2) - pairs(k1 + 1, k2) - pairs(k1, k2 + 1) + pairs(k1 + 1, k2 + 1);
                let covariance =
                    4.0 * w(k1, k2) - 2.0 * w(k1 + 1, k2) - 2.0 * w(k1, k2 + 1) + w(k1 + 1, k2 + 1);
                sum += exactly * covariance;
            }
        }
        (sum.max(0.0) / (n * n)).sqrt()
    }

    /// Checks the area formula against the integrand on a fine midpoint grid.
    pub fn check_disk_area() {
        let f = GraphicsIntegrand::Disk;
        let (x0, x1, y0, y1) = (0.55, 0.8, 0.3, 0.62);
        let steps = 1000;
        let mut inside = 0.0;
        for i in 0..steps {
            for j in 0..steps {
                let x = x0 + (i as f64 + 0.5) / steps as f64 * (x1 - x0);
                let y = y0 + (j as f64 + 0.5) / steps as f64 * (y1 - y0);
                inside += f.eval(&[x, y]);
            }
        }
        let midpoint = inside / (steps * steps) as f64 * (x1 - x0) * (y1 - y0);
        let exact = disk_area(x0, x1, y0, y1);
        // The midpoint count misses at most the cells the arc crosses: ~2 * 1000 of 10^6.
        assert!(
            (midpoint - exact).abs() < 2e-3 * (x1 - x0) * (y1 - y0),
            "{midpoint} {exact}"
        );
        assert!((disk_area(0.0, 1.0, 0.0, 1.0) - 0.5).abs() < 1e-15);
    }
}

const PASSES: u64 = 128;
const SEED: u64 = 2018;

/// Allowed distance in standard errors.
const Z: f64 = 4.0;

/// `N = 2^6 .. 2^16`, symmetric in `log N` about `2^11`, so an even/odd-`m` zigzag of a net's
/// RMSE cancels out of the fitted slope.
const LOG2_SIZES: std::ops::RangeInclusive<u32> = 6..=16;

/// Strata per axis of the jittered sizes: about evenly spaced in log N from 8^2 to 256^2.
const JITTER_STRATA: [u64; 11] = [8, 11, 16, 23, 32, 45, 64, 91, 128, 181, 256];

fn pow2_sizes() -> Vec<u64> {
    LOG2_SIZES.map(|m| 1u64 << m).collect()
}

/// OLS slope of ln RMSE on ln N through exact values (the same fit the study makes).
fn exact_slope(sizes: &[u64], rmse: &[f64]) -> f64 {
    let k = sizes.len() as f64;
    let xs: Vec<f64> = sizes.iter().map(|&n| (n as f64).ln()).collect();
    let ys: Vec<f64> = rmse.iter().map(|r| r.ln()).collect();
    let (mx, my) = (xs.iter().sum::<f64>() / k, ys.iter().sum::<f64>() / k);
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    sxy / sxx
}

/// Checks a study against the exact RMSEs at its sizes and returns the exact slope.
///
/// * The measured slope is within `Z` standard errors of the exact slope.
/// * The measured RMSEs agree with the exact ones on average: the mean of
///   `ln(measured / exact)` over the sizes has standard error `√(Σ σ_k²) / K` (the sizes are
///   independent), and its bias, `-1/(2R)` for normal errors (`ln` of a chi-square mean),
///   is removed. This checks the samplers' error levels, not just their rates.
fn check_against_exact(label: &str, study: &ConvergenceStudy, exact_rmse: &[f64]) -> f64 {
    let sizes: Vec<u64> = study.points.iter().map(|p| p.n).collect();
    let exact = exact_slope(&sizes, exact_rmse);
    let k = sizes.len() as f64;
    let log_ratio = study
        .points
        .iter()
        .zip(exact_rmse)
        .map(|(p, e)| (p.rmse / e).ln())
        .sum::<f64>()
        / k
        + 1.0 / (2.0 * study.passes as f64);
    let log_ratio_se = study
        .points
        .iter()
        .map(|p| (p.rmse_std_error / p.rmse).powi(2))
        .sum::<f64>()
        .sqrt()
        / k;
    eprintln!(
        "{label}: slope {:+.4} ± {:.4} (chi2/dof {:.2}), exact {exact:+.4}; \
         mean ln(rmse/exact) {log_ratio:+.4} ± {log_ratio_se:.4}",
        study.slope,
        study.slope_std_error,
        study.chi2_per_dof.unwrap_or(f64::NAN),
    );
    assert!(
        (study.slope - exact).abs() < Z * study.slope_std_error,
        "{label}: slope {} is not within {Z} x {} of the exact {exact}",
        study.slope,
        study.slope_std_error
    );
    assert!(
        log_ratio.abs() < Z * log_ratio_se,
        "{label}: RMSE level off by {log_ratio} (se {log_ratio_se})"
    );
    exact
}

fn study<S: Sampler>(
    f: GraphicsIntegrand,
    sizes: &[u64],
    sampler: impl Fn(u64, u64) -> Result<S> + Sync,
) -> ConvergenceStudy {
    Convergence::new(&f, sizes)
        .passes(PASSES)
        .seed(SEED)
        .run(sampler)
        .unwrap()
}

/// The rate that a pure `√(log N)` factor adds to a power law over the test's sizes: the OLS
/// slope of `½ ln ln N` on `ln N`. An Owen-scrambled net's variance on a smooth 2-D integrand
/// is `N^-3 (A + B log N)` with `A, B >= 0` asymptotically (Owen 1997), and the OLS slope is
/// a positively weighted average of local slopes, each at most that of `B log N` alone, so
/// the fitted slope lies in `[-3/2, -3/2 + this]`.
fn log_factor_allowance(sizes: &[u64]) -> f64 {
    // `exact_slope` takes logs: ln √(ln N) = ½ ln ln N.
    let sqrt_log: Vec<f64> = sizes.iter().map(|&n| (n as f64).ln().sqrt()).collect();
    exact_slope(sizes, &sqrt_log)
}

#[test]
fn exact_disk_areas_agree_with_a_midpoint_count() {
    theory::check_disk_area();
}

/// Independent points: RMSE = σ / √N exactly, so the exact slope is -1/2 with no allowance.
#[test]
fn independent_points_converge_at_minus_one_half() {
    let sizes = pow2_sizes();
    for f in [GraphicsIntegrand::Disk, GraphicsIntegrand::Gaussian] {
        let s = study(f, &sizes, |_, seed| Independent::new(2, seed));
        let exact: Vec<f64> = sizes
            .iter()
            .map(|&n| theory::independent_rmse(f, n))
            .collect();
        let slope = check_against_exact(&format!("independent {f}"), &s, &exact);
        assert!((slope + 0.5).abs() < 1e-12);
    }
}

/// Jittered points on smooth integrands: each cell's variance is `h² |∇f|² / 12 + O(h⁴)`, so
/// the RMSE is `c / N · (1 + O(1/N))` and the exact slope is -1 to within 0.002 here.
#[test]
fn jittered_points_converge_at_minus_one_on_smooth_integrands() {
    let sizes: Vec<u64> = JITTER_STRATA.iter().map(|k| k * k).collect();
    for f in [GraphicsIntegrand::Gaussian, GraphicsIntegrand::Bilinear] {
        let s = study(f, &sizes, |n, seed| Jittered::with_points(2, n, seed));
        let exact: Vec<f64> = JITTER_STRATA
            .iter()
            .map(|&k| theory::jittered_rmse(f, k))
            .collect();
        let slope = check_against_exact(&format!("jittered {f}"), &s, &exact);
        assert!((slope + 1.0).abs() < 0.002, "exact jittered slope {slope}");
    }
}

/// Jittered points on the disk: only the ~√N cells the arc crosses have variance, each
/// `p (1 - p) / N²`, so the RMSE is ~ N^-3/4; how `p` is spread over those cells wobbles with
/// the grid, which moves the exact slope over these sizes by less than 0.01.
#[test]
fn jittered_points_converge_at_minus_three_quarters_on_the_disk() {
    let f = GraphicsIntegrand::Disk;
    let sizes: Vec<u64> = JITTER_STRATA.iter().map(|k| k * k).collect();
    let s = study(f, &sizes, |n, seed| Jittered::with_points(2, n, seed));
    let exact: Vec<f64> = JITTER_STRATA
        .iter()
        .map(|&k| theory::jittered_rmse(f, k))
        .collect();
    let slope = check_against_exact("jittered disk", &s, &exact);
    assert!((slope + 0.75).abs() < 0.01, "exact jittered slope {slope}");
}

/// Checks an Owen-scrambled (0,2) sampler on the smooth integrands and on the disk.
fn check_owen_net<S: Sampler>(name: &str, sampler: impl Fn(u64, u64) -> Result<S> + Sync) {
    let sizes = pow2_sizes();
    let allowance = log_factor_allowance(&sizes);
    for f in [
        GraphicsIntegrand::Gaussian,
        GraphicsIntegrand::Bilinear,
        GraphicsIntegrand::Disk,
    ] {
        let s = study(f, &sizes, &sampler);
        let exact: Vec<f64> = LOG2_SIZES.map(|m| theory::owen_net_rmse(f, m)).collect();
        let slope = check_against_exact(&format!("{name} {f}"), &s, &exact);
        if f.is_smooth() {
            // The exact slope shows the sqrt(log N) factor, within its bound.
            eprintln!("  log-factor bound: [-1.5, {:.4}]", -1.5 + allowance);
            assert!(
                slope > -1.5 && slope < -1.5 + allowance,
                "exact slope {slope} outside [-1.5, -1.5 + {allowance}]"
            );
        } else {
            assert!((slope + 0.75).abs() < 0.01, "exact disk slope {slope}");
        }
    }
}

/// Owen-scrambled Sobol': N^-3/2 (times √log N) on smooth integrands, N^-3/4 on the disk.
#[test]
fn owen_sobol_converges_at_minus_three_halves_smooth_and_minus_three_quarters_on_the_disk() {
    check_owen_net("sobol-owen", |_, seed| Sobol::new(2, Scramble::Owen, seed));
}

/// pmj02 is an Owen-scrambled (0,2) sequence: the same exact variances as Sobol'.
#[test]
fn pmj02_converges_at_minus_three_halves_smooth_and_minus_three_quarters_on_the_disk() {
    check_owen_net("pmj02", |_, seed| Pmj02::new(2, seed));
}

#[test]
fn results_do_not_depend_on_threads_or_on_the_other_sizes() {
    let f = GraphicsIntegrand::Disk;
    let run = |sizes: &[u64], threads| {
        Convergence::new(&f, sizes)
            .passes(8)
            .seed(3)
            .threads(threads)
            .run(|_, seed| Sobol::new(2, Scramble::Owen, seed))
            .unwrap()
    };
    let one = run(&[16, 64, 256, 1024], 1);
    assert_eq!(one, run(&[16, 64, 256, 1024], 2));
    assert_eq!(one, run(&[16, 64, 256, 1024], 5));
    // The estimate at each size depends only on (seed, size, pass).
    let subset = run(&[64, 1024], 2);
    assert_eq!(subset.points[0], one.points[1]);
    assert_eq!(subset.points[1], one.points[3]);
    assert_eq!(
        (one.sampler.as_str(), one.integrand.as_str()),
        ("sobol", "disk")
    );
}

#[test]
fn progress_counts_every_point_once_and_ends_at_the_total() {
    let f = GraphicsIntegrand::Bilinear;
    let (calls, last, monotone) = (Cell::new(0u64), Cell::new((0u64, 0u64)), Cell::new(true));
    let report = |done: u64, total: u64| {
        calls.set(calls.get() + 1);
        monotone.set(monotone.get() && done > last.get().0 && done <= total);
        last.set((done, total));
    };
    Convergence::new(&f, &[16, 64, 256])
        .passes(5)
        .threads(2)
        .progress(&report)
        .run(|_, seed| Independent::new(2, seed))
        .unwrap();
    assert_eq!(calls.get(), 15);
    assert!(monotone.get());
    assert_eq!(last.get(), (5 * (16 + 64 + 256), 5 * (16 + 64 + 256)));
}

/// An integrand that is NaN on part of the square.
struct NanCorner;

impl TestFunction for NanCorner {
    fn dims(&self) -> usize {
        2
    }
    fn eval(&self, x: &[f64]) -> f64 {
        if x[0] > 0.9 && x[1] > 0.9 {
            f64::NAN
        } else {
            1.0
        }
    }
    fn exact(&self) -> f64 {
        1.0
    }
    fn name(&self) -> String {
        "nan-corner".into()
    }
}

#[test]
fn bad_settings_and_unfit_samplers_are_errors_not_panics() {
    let f = GraphicsIntegrand::Gaussian;
    let independent = |_: u64, seed: u64| Independent::new(2, seed);
    let message = |e: Error| e.to_string();

    let few = Convergence::new(&f, &[64]).run(independent).unwrap_err();
    assert!(message(few).contains("at least two"));
    for sizes in [&[64u64, 64][..], &[256, 64], &[0, 64]] {
        let e = Convergence::new(&f, sizes).run(independent).unwrap_err();
        assert!(message(e).contains("strictly increasing"));
    }
    let e = Convergence::new(&f, &[16, 64])
        .passes(1)
        .run(independent)
        .unwrap_err();
    assert!(message(e).contains("passes"));
    let e = Convergence::new(&f, &[16, 64])
        .threads(0)
        .run(independent)
        .unwrap_err();
    assert!(message(e).contains("threads"));

    // The sampler's own error for a size it cannot make passes through.
    let e = Convergence::new(&f, &[16, 64, 100, 200])
        .run(|n, seed| Jittered::with_points(2, n, seed))
        .unwrap_err();
    assert_eq!(e, Jittered::with_points(2, 200, 0).unwrap_err());
    // A fixed-size sampler built for another size.
    let e = Convergence::new(&f, &[16, 64])
        .run(|_, seed| Jittered::new(2, 4, seed))
        .unwrap_err();
    assert!(message(e).contains("pass size"));
    // More points than a pass of the sequence holds.
    let e = Convergence::new(&f, &[16, 32])
        .run(|_, seed| Pmj02::with_max_points(2, 4, seed))
        .unwrap_err();
    assert!(message(e).contains("at most 16"));
    // Unrandomized points repeat every pass.
    let e = Convergence::new(&f, &[16, 32])
        .run(|_, seed| Sobol::new(2, Scramble::None, seed))
        .unwrap_err();
    assert!(message(e).contains("randomized"));
    // Wrong dimension.
    let e = Convergence::new(&f, &[16, 32])
        .run(|_, seed| Independent::new(3, seed))
        .unwrap_err();
    assert!(matches!(
        e,
        Error::DimensionMismatch {
            expected: 2,
            found: 3,
            ..
        }
    ));
    // Non-finite integrand values.
    let e = Convergence::new(&NanCorner, &[64, 256])
        .threads(2)
        .run(independent)
        .unwrap_err();
    assert!(matches!(e, Error::NonFiniteContribution { .. }), "{e}");
    // Exact at some size: 9 columns put the step's edge x = 1/3 on a stratum boundary.
    let e = Convergence::new(&GraphicsIntegrand::Step, &[16, 81])
        .run(|n, seed| Jittered::with_points(2, n, seed))
        .unwrap_err();
    assert!(message(e).contains("N = 81"));
}

/// Passes beyond memory are refused before anything is allocated (2^64 - 1 passes asked for
/// a vector that large and aborted), and a point whose passes all have the same squared
/// error, so that the slope's error bar is undefined, is an error naming the passes (the
/// study reported a slope "± inf"; the same for passes that were all exact, which blamed the
/// integrand).
#[test]
fn passes_beyond_memory_or_too_few_to_measure_a_spread_are_refused() {
    let independent = |_: u64, seed: u64| Independent::new(2, seed);
    for passes in [u64::MAX, 1 << 21] {
        let e = Convergence::new(&GraphicsIntegrand::Disk, &[16, 64])
            .passes(passes)
            .run(independent)
            .unwrap_err();
        assert!(e.to_string().contains("2 to 2^20"), "{e}");
    }
    // Owen-scrambled Sobol' points count the disk's 32-point net the same way in 3 passes.
    let sobol = |_: u64, seed: u64| Sobol::new(2, Scramble::Owen, seed);
    let e = Convergence::new(&GraphicsIntegrand::Disk, &[16, 32, 64])
        .passes(3)
        .seed(2018)
        .run(sobol)
        .unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("invalid passes = 3") && text.contains("undefined"),
        "{text}"
    );
}

/// `s x` over the unit square, whose errors scale with `s`.
struct Scaled(f64);

impl TestFunction for Scaled {
    fn dims(&self) -> usize {
        2
    }
    fn eval(&self, x: &[f64]) -> f64 {
        self.0 * x[0]
    }
    fn exact(&self) -> f64 {
        self.0 / 2.0
    }
    fn name(&self) -> String {
        "scaled".into()
    }
}

/// A study of `2^k x` is the study of `x` with RMSEs times `2^k`, bit for bit, and the same
/// slope to rounding: the
/// spread of the squared errors took fourth powers, which overflowed at 1e160 (slope NaN, RMSE
/// inf, returned as Ok) and vanished at 1e-160 (refused as "every estimate was exact").
#[test]
fn studies_far_from_1_are_the_ordinary_study_scaled() {
    let study = |scale: f64| {
        Convergence::new(&Scaled(scale), &[64, 256, 1024, 4096])
            .passes(32)
            .seed(5)
            .run(|_, seed| Independent::new(2, seed))
            .unwrap()
    };
    let ordinary = study(1.0);
    for k in [500, 540, -500, -540] {
        let scale = 2f64.powi(k);
        let scaled = study(scale);
        // ln RMSE shifts by k ln 2, rounded: the fit agrees to rounding.
        assert!((scaled.slope - ordinary.slope).abs() < 1e-12, "2^{k}");
        let relative = scaled.slope_std_error / ordinary.slope_std_error - 1.0;
        assert!(relative.abs() < 1e-9, "2^{k}");
        for (a, b) in scaled.points.iter().zip(&ordinary.points) {
            assert_eq!(a.rmse / scale, b.rmse, "2^{k}");
            assert_eq!(a.rmse_std_error / scale, b.rmse_std_error, "2^{k}");
        }
    }
}
