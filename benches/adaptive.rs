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
//! Methods that need far longer are measured once from the command line instead (see
//! `docs/benchmarks.md`). The Python peers (scipy's `qmc_quad`, QMCPy's
//! `CubQMCSobolG`, vegas) are timed on
//! the same work by `benches/peers_python/adaptive_peers.py`.
//!
//! `cargo bench --bench adaptive -- two_threads`: VEGAS and VEGAS+ on the cheap 4-D Genz
//! Gaussian (about 60 ns per evaluation with the grid's mapping) on one and two threads, with
//! `10^6`, `10^7` (criterion) and `10^8` evaluations in 5 warm-up and 10 measured iterations,
//! and a run to a tolerance in the default iterations of `10^4` points; then the speedup of
//! two threads over one, from runs timed in alternating pairs (each timing repeats a short
//! run for about half a second), beside that of the Integrator's independent-point run of
//! `10^7` evaluations of the same integrand, as the machine allows it at that moment. Two
//! figures: the ratio of the fastest timings (a shared machine's other work only ever
//! slows a timing down) and the median of the pairs' ratios.

use criterion::{Criterion, criterion_group, criterion_main};
use mcint::adaptive::{Miser, SobolG, Vegas};
use mcint::estimator::Estimator;
use mcint::pdf::UniformBox;
use mcint::sampler::{Scramble, Sobol};
use mcint::stats::Tolerance;
use mcint::testfns::{Genz, GenzFamily, TestFunction};
use mcint::{Integrator, Points};
use std::hint::black_box;
use std::time::Instant;

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

/// Evaluations of the fixed-budget runs of `two_threads`, spent in 5 warm-up and 10
/// measured iterations of a fifteenth each.
const BUDGETS: [u64; 3] = [1_000_000, 10_000_000, 100_000_000];

/// The 4-D Genz Gaussian, cheap enough that the work between iterations shows.
fn cheap() -> Genz {
    Genz::with_defaults(GenzFamily::Gaussian, 4).unwrap()
}

/// A VEGAS (`stratified = false`) or VEGAS+ run on `threads` threads: `budget` evaluations
/// in fixed iterations, or with `budget = None` to a relative 95% half-width of `5e-6` in the
/// default iterations of `10^4` points. Returns its estimate.
fn vegas_run(f: &Genz, stratified: bool, budget: Option<u64>, threads: usize) -> f64 {
    let integrand = |x: &[f64]| f.eval(x);
    let vegas = Vegas::new(integrand, UniformBox::unit(4).unwrap())
        .stratified(stratified)
        .seed(1)
        .threads(threads);
    let e = match budget {
        Some(n) => vegas.samples(n / 15).warmup(5).iterations(10).run(),
        None => vegas
            .iterations(1 << 20)
            .tolerance(Tolerance::relative(5e-6).unwrap())
            .run(),
    };
    black_box(e.unwrap().mean)
}

fn two_threads(c: &mut Criterion) {
    let f = cheap();
    let mut group = c.benchmark_group("two_threads_vegas_gaussian_4d");
    group.sample_size(10);
    for (name, stratified) in [("vegas", false), ("vegas_plus", true)] {
        for budget in &BUDGETS[..2] {
            for threads in [1, 2] {
                let id = format!("{name}_{budget:e}_evals_{threads}_threads");
                group.bench_function(id, |b| {
                    b.iter(|| vegas_run(&f, stratified, Some(*budget), threads))
                });
            }
        }
    }
    group.finish();
    if asked_for("two_threads_vegas_gaussian_4d") {
        print_speedups(&f);
    }
}

/// Whether this is a `cargo bench` run (not `cargo test --benches`) whose name filter, if it
/// has one, matches `group`.
fn asked_for(group: &str) -> bool {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let benching = args.iter().any(|a| a == "--bench");
    let mut filters = args.iter().filter(|a| !a.starts_with('-'));
    benching && filters.all(|f| group.contains(f.as_str()))
}

/// Prints the speedup of two threads over one for each method and work size, from alternating
/// pairs of timings: the ratio of the fastest one-thread timing to the fastest two-thread one,
/// and the median of the pairs' ratios.
fn print_speedups(f: &Genz) {
    println!("two threads over one (fastest timings; median of paired ratios):");
    let integrator = |threads| {
        let integrand = |x: &[f64]| f.eval(x);
        let run = Integrator::over_box(integrand, UniformBox::unit(4).unwrap())
            .seed(1)
            .threads(threads)
            .samples(BUDGETS[1])
            .run();
        black_box(run.unwrap().mean);
    };
    print_speedup("Integrator", "1e7 evaluations", 7, integrator);
    for (name, stratified) in [("VEGAS", false), ("VEGAS+", true)] {
        let cases = BUDGETS
            .iter()
            .map(|&b| (Some(b), format!("{b:.0e} evaluations")))
            .chain([(None, "to 5e-6 in 10^4-point iterations".to_string())]);
        for (budget, what) in cases {
            let pairs = if budget == Some(BUDGETS[2]) { 3 } else { 7 };
            print_speedup(name, &what, pairs, |threads| {
                vegas_run(f, stratified, budget, threads);
            });
        }
    }
}

/// Prints the speedup of `run(2)` over `run(1)` from `pairs` alternating pairs of timings.
fn print_speedup(name: &str, what: &str, pairs: usize, run: impl Fn(usize)) {
    // Each timing covers `runs` runs back to back, enough for about half a second on one
    // thread, so that one scheduling hiccup of a shared machine does not decide a pair.
    let time = |threads, runs| {
        let start = Instant::now();
        for _ in 0..runs {
            run(threads);
        }
        start.elapsed().as_secs_f64()
    };
    let once = time(1, 1);
    let runs = (0.5 / once).ceil().max(1.0) as usize;
    let timings: Vec<(f64, f64)> = (0..pairs).map(|_| (time(1, runs), time(2, runs))).collect();
    let fastest = |pick: fn(&(f64, f64)) -> f64| timings.iter().map(pick).fold(f64::MAX, f64::min);
    let best = fastest(|t| t.0) / fastest(|t| t.1);
    let mut ratios: Vec<f64> = timings.iter().map(|(one, two)| one / two).collect();
    ratios.sort_by(f64::total_cmp);
    println!(
        "  {name:10} {what:34} {best:.2}x ({:.2}x)",
        ratios[pairs / 2]
    );
}

criterion_group!(benches, to_tolerance, two_threads);
criterion_main!(benches);
