//! Convergence rates of randomized quasi-Monte Carlo on the Genz families, fitted and checked
//! against theory.
//!
//! At each N the RMSE over R independent randomizations is measured against the exact
//! integral; the slope of log RMSE against log N is fitted by least squares over 9 sizes
//! (N = 2^6 .. 2^14). With R = 64 replicates, log RMSE has a standard deviation of about
//! 1 / sqrt(2 R) = 0.088 (the log of a chi variable with R degrees of freedom), which gives
//! the slope a standard error of 0.088 / sqrt(Sxx) = 0.016 for these sizes. Each check allows
//! 4 such standard errors (or 4 fitted standard errors, whichever is larger) plus, where
//! stated, the known logarithmic factor of the theory.

use mcint::Points;
use mcint::sampler::{PassKind, Sampler, SamplerKind, Scramble};
use mcint::testfns::{Genz, GenzFamily, TestFunction};

const REPLICATES: u64 = 64;
const SIZES_LOG2: std::ops::RangeInclusive<u32> = 6..=14;

/// Root mean squared error of the `n`-point estimate over independent passes.
fn rmse(sampler: &dyn Sampler, f: &dyn TestFunction, n: u64) -> f64 {
    let stride = match sampler.passes() {
        PassKind::Independent => n,
        PassKind::Fixed { size } => size,
        PassKind::Extensible { max } => max,
    };
    let mut points = Points::new(f.dims(), n as usize).unwrap();
    let mut x = vec![0.0; f.dims()];
    let mut sum_squares = 0.0;
    for r in 0..REPLICATES {
        sampler.fill(r * stride, &mut points).unwrap();
        let mean = (0..points.len())
            .map(|i| {
                points.copy_point(i, &mut x);
                f.eval(&x)
            })
            .sum::<f64>()
            / n as f64;
        sum_squares += (mean - f.exact()).powi(2);
    }
    (sum_squares / REPLICATES as f64).sqrt()
}

/// Least-squares slope of log RMSE on log N and the standard error to test it with.
fn fitted_slope(kind: SamplerKind, scramble: Scramble, f: &dyn TestFunction) -> (f64, f64) {
    let sampler = kind.build_scrambled(f.dims(), 0, scramble, 2024).unwrap();
    let points: Vec<(f64, f64)> = SIZES_LOG2
        .map(|m| {
            let n = 1u64 << m;
            ((n as f64).ln(), rmse(sampler.as_ref(), f, n).ln())
        })
        .collect();
    let k = points.len() as f64;
    let mean_x = points.iter().map(|p| p.0).sum::<f64>() / k;
    let mean_y = points.iter().map(|p| p.1).sum::<f64>() / k;
    let sxx: f64 = points.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    let slope = sxy / sxx;
    let residual: f64 = points
        .iter()
        .map(|p| (p.1 - mean_y - slope * (p.0 - mean_x)).powi(2))
        .sum::<f64>()
        / (k - 2.0);
    let theory_sd = 1.0 / (2.0 * REPLICATES as f64).sqrt();
    let se = (residual / sxx).sqrt().max(theory_sd / sxx.sqrt());
    (slope, se)
}

/// Owen-scrambled Sobol' on a smooth integrand: RMSE ~ N^-1.5 (log N)^((d-1)/2) (Owen 1997).
/// In 2D the log factor raises the local slope by about 1 / (2 ln N) ~ 0.07 at these sizes.
#[test]
fn owen_sobol_reaches_n_to_the_minus_three_halves_on_smooth_integrands() {
    for family in [
        GenzFamily::Gaussian,
        GenzFamily::ProductPeak,
        GenzFamily::Oscillatory,
    ] {
        let f = Genz::with_defaults(family, 2).unwrap();
        let (slope, se) = fitted_slope(SamplerKind::Sobol, Scramble::Owen, &f);
        eprintln!("owen-sobol {}: slope {slope:.3} +- {se:.3}", family.name());
        assert!(
            slope > -1.5 - 4.0 * se && slope < -1.5 + 0.07 + 4.0 * se,
            "{}: slope {slope:.3} +- {se:.3}, theory -1.5 (+0.07 log factor)",
            family.name()
        );
    }
}

/// Every Genz family converges faster than plain Monte Carlo's N^-1/2 under every
/// randomized QMC generator, even the kinked and discontinuous ones (whose rates are about
/// N^-1 and N^-3/4 in 2D).
#[test]
fn randomized_qmc_beats_monte_carlo_on_every_genz_family() {
    let generators = [
        (SamplerKind::Sobol, Scramble::Owen),
        (SamplerKind::Sobol, Scramble::Lms),
        (SamplerKind::Sobol, Scramble::Xor),
        (SamplerKind::Halton, Scramble::Permute),
        (SamplerKind::Halton, Scramble::Owen),
        (SamplerKind::Lattice, Scramble::Shift),
    ];
    for family in GenzFamily::ALL {
        let f = Genz::with_defaults(family, 2).unwrap();
        for (kind, scramble) in generators {
            let (slope, se) = fitted_slope(kind, scramble, &f);
            eprintln!(
                "{kind}/{scramble} {}: slope {slope:.3} +- {se:.3}",
                family.name()
            );
            assert!(
                slope + 4.0 * se < -0.5,
                "{} with {kind}/{scramble}: slope {slope:.3} +- {se:.3} is not faster than -0.5",
                family.name()
            );
        }
    }
}

/// The fit itself is sound: plain Monte Carlo shows the N^-1/2 of A.22.
#[test]
fn independent_points_show_the_monte_carlo_rate() {
    let f = Genz::with_defaults(GenzFamily::Gaussian, 2).unwrap();
    let (slope, se) = fitted_slope(SamplerKind::Independent, Scramble::None, &f);
    eprintln!("independent gaussian: slope {slope:.3} +- {se:.3}");
    assert!(
        (slope + 0.5).abs() < 4.0 * se,
        "slope {slope:.3} +- {se:.3}"
    );
}
