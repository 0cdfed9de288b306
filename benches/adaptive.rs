//! Time to reach a 95% half-width of 1e-5 (so |error| <= 1e-5 in about 95% of runs) on the
//! 5-D Genz Gaussian, oscillatory, product-peak and continuous families (customary
//! parameters), one thread, for each method that gets there within a few seconds, side by
//! side in one run.
//!
//! `cargo bench --bench adaptive`. The default `rqmc` (Owen-scrambled Sobol', the
//! Integrator's rule to a tolerance) is timed with the batch integrand the `integrate` program
//! uses (`TestFunction::eval_batch`: vectorized `exp` and `cos`) and with a per-point closure;
//! `sobol_g` (QMCPy's `CubQMCSobolG` rule, one LMS-scrambled Sobol' sequence and a bound from
//! its Walsh coefficients) likewise, in both forms.
//! Methods that need far longer are measured once from the command line instead (see the
//! README). The Python peers (scipy's `qmc_quad`, QMCPy's `CubQMCSobolG`, vegas) are timed on
//! the same work by `benches/peers_python/adaptive_peers.py`.

use criterion::{Criterion, criterion_group, criterion_main};
use mcint::adaptive::{Miser, SobolG, Vegas};
use mcint::estimator::Estimator;
use mcint::pdf::UniformBox;
use mcint::sampler::{Scramble, Sobol};
use mcint::stats::Tolerance;
use mcint::testfns::{Genz, GenzFamily, TestFunction};
use mcint::{Integrator, Points};
use std::hint::black_box;

const DIMS: usize = 5;
const TARGET: f64 = 1e-5;

fn tolerance() -> Tolerance {
    Tolerance::absolute(TARGET).unwrap()
}

/// The default `rqmc` run of `integrator` (Owen-scrambled Sobol', the rule to a tolerance)
/// with `seed`, on one thread; its estimate.
fn rqmc<E: Estimator>(integrator: Integrator<E>, seed: u64) -> f64 {
    let e = integrator
        .sampler(Sobol::new(DIMS, Scramble::Owen, 0).unwrap())
        .tolerance(tolerance())
        .seed(seed)
        .threads(1)
        .run()
        .unwrap();
    assert_eq!(e.converged, Some(true));
    black_box(e.mean)
}

/// A `sobol_g` run of `rule` (QMCPy's `CubQMCSobolG` rule) with `seed`, on one thread; its
/// estimate.
fn sobol_g<E: Estimator>(rule: SobolG<E>, seed: u64) -> f64 {
    let e = rule
        .tolerance(tolerance())
        .seed(seed)
        .threads(1)
        .run()
        .unwrap();
    assert_eq!(e.converged, Some(true));
    black_box(e.mean)
}

fn to_tolerance(c: &mut Criterion) {
    for family in [
        GenzFamily::Gaussian,
        GenzFamily::Oscillatory,
        GenzFamily::ProductPeak,
        GenzFamily::Continuous,
    ] {
        let f = Genz::with_defaults(family, DIMS).unwrap();
        let integrand = |x: &[f64]| f.eval(x);
        let batch = |points: &Points, out: &mut [f64]| f.eval_batch(points, out);
        let unit = || UniformBox::unit(DIMS).unwrap();
        let sobol = || Sobol::new(DIMS, Scramble::Owen, 0).unwrap();
        let mut group = c.benchmark_group(format!("to_1e-5_{family}_5d"));
        group.sample_size(10);
        let mut seed = 0u64;
        let mut next_seed = || {
            seed += 1;
            seed
        };
        group.bench_function("rqmc_batch", |b| {
            b.iter(|| rqmc(Integrator::over_box_batch(batch, unit()), next_seed()))
        });
        group.bench_function("rqmc_per_point", |b| {
            b.iter(|| rqmc(Integrator::over_box(integrand, unit()), next_seed()))
        });
        group.bench_function("sobol_g_batch", |b| {
            b.iter(|| sobol_g(SobolG::new_batch(batch, unit()), next_seed()))
        });
        group.bench_function("sobol_g_per_point", |b| {
            b.iter(|| sobol_g(SobolG::new(integrand, unit()), next_seed()))
        });
        if family == GenzFamily::Gaussian {
            for (name, stratified) in [("vegas", false), ("vegas_plus", true)] {
                group.bench_function(name, |b| {
                    b.iter(|| {
                        let e = Vegas::new(integrand, unit())
                            .stratified(stratified)
                            .iterations(1 << 20)
                            .tolerance(tolerance())
                            .seed(next_seed())
                            .threads(1)
                            .run()
                            .unwrap();
                        assert_eq!(e.converged, Some(true));
                        black_box(e.mean)
                    })
                });
            }
        }
        if matches!(family, GenzFamily::Gaussian | GenzFamily::Oscillatory) {
            group.bench_function("miser_sobol_owen", |b| {
                b.iter(|| {
                    let e = Miser::new(integrand, unit())
                        .sampler(sobol())
                        .samples(1 << 12)
                        .tolerance(tolerance())
                        .seed(next_seed())
                        .threads(1)
                        .run()
                        .unwrap();
                    assert_eq!(e.converged, Some(true));
                    black_box(e.mean)
                })
            });
        }
        group.finish();
    }
}

criterion_group!(benches, to_tolerance);
criterion_main!(benches);
