//! MISER and VEGAS runs to a tolerance: their reported 95% intervals cover the exact value in
//! at least 93% of 200 seeds on the 5-D Genz families they serve, as the Integrator's do
//! (`tests/runs/integrator_tolerance.rs`, which explains the 93%: 186 of 200 is 1.3 binomial
//! deviations below the 190 of an exact 95% interval).
//!
//! Both stop through the engine's one stopping rule. MISER's error bar comes from 16
//! independent replicates and is inflated by 1.2 against optional stopping, as the
//! Integrator's replicate intervals are; VEGAS's comes from the inverse-variance combination
//! of its iterations' per-sample variances.
//!
//! Families: all six for MISER, VEGAS and VEGAS+. Classic VEGAS once could not serve the
//! discontinuous family: its grid squeezed the jump into a sliver that most iterations
//! missed, so the per-iteration variances were underestimated and the combination drifted
//! (the Python `vegas` package does the same); it covered 185 of 200, one below the bound.
//! With the grid's density floor (`Vegas::density_floor`) and its grading it covers 191, and
//! VEGAS+ 192 (190 with the allocation exponent `beta` at 0.75). Corner peak and
//! discontinuous use `a` rescaled to sum 2.5, as in the Integrator's test, for the same reason
//! (heavy tails with the customary `a`).

use crate::common::{REQUIRED, SEEDS};
use mcint::adaptive::{Miser, Vegas};
use mcint::pdf::UniformBox;
use mcint::stats::{StopReason, Tolerance};
use mcint::testfns::{Genz, GenzFamily, TestFunction};
use mcint::{Estimate, Integrator};

const DIMS: usize = 5;
/// Independent points a plain run would need to meet the tolerance (see [`tolerance_for`]).
const PLAIN_POINTS: f64 = 8192.0;

/// The Genz function of a case (see the module documentation for the rescaled families).
fn test_function(family: GenzFamily) -> Genz {
    let customary = Genz::with_defaults(family, DIMS).unwrap();
    if !matches!(family, GenzFamily::CornerPeak | GenzFamily::Discontinuous) {
        return customary;
    }
    let sum: f64 = customary.a().iter().sum();
    let a = customary.a().iter().map(|a| a * 2.5 / sum).collect();
    Genz::new(family, a, customary.u().to_vec()).unwrap()
}

/// An absolute tolerance that plain Monte Carlo meets with about `PLAIN_POINTS` points,
/// `1.96 sigma / sqrt(PLAIN_POINTS)`, with `sigma` from a separate run; the adaptive methods,
/// which reduce the variance, need fewer.
fn tolerance_for(f: &Genz) -> Tolerance {
    let reference = Integrator::over_box(|x: &[f64]| f.eval(x), UniformBox::unit(DIMS).unwrap())
        .samples(1 << 16)
        .seed(1_000_000)
        .run()
        .unwrap();
    let sigma = reference.std_error.unwrap() * ((1u64 << 16) as f64).sqrt();
    Tolerance::absolute(1.96 * sigma / PLAIN_POINTS.sqrt())
        .unwrap()
        .max_evaluations(1 << 24)
        .unwrap()
}

/// Runs `run(seed)` for every seed; the number of runs whose interval covers the exact value,
/// checking that each run met the tolerance it reports as met.
fn coverage(f: &Genz, tolerance: Tolerance, run: impl Fn(u64) -> Estimate) -> u64 {
    let exact = f.exact();
    let mut covered = 0;
    for seed in 0..SEEDS {
        let e = run(seed);
        assert_eq!(e.stop, StopReason::ToleranceMet, "seed {seed}: {e:?}");
        assert!(e.half_width(0.95).unwrap().unwrap() <= tolerance.target(e.mean));
        let (lo, hi) = e.confidence_interval(0.95).unwrap().unwrap();
        covered += u64::from(lo <= exact && exact <= hi);
    }
    covered
}

fn miser_coverage(family: GenzFamily) {
    let f = test_function(family);
    let tolerance = tolerance_for(&f);
    let covered = coverage(&f, tolerance, |seed| {
        Miser::new(|x: &[f64]| f.eval(x), UniformBox::unit(DIMS).unwrap())
            .samples(256)
            .tolerance(tolerance)
            .seed(seed)
            .threads(1)
            .run()
            .unwrap()
    });
    eprintln!("MISER {family}: covered {covered} of {SEEDS}");
    assert!(
        covered >= REQUIRED,
        "MISER {family}: covered {covered} of {SEEDS}"
    );
}

fn vegas_coverage(family: GenzFamily, stratified: bool) {
    let f = test_function(family);
    let tolerance = tolerance_for(&f);
    let covered = coverage(&f, tolerance, |seed| {
        Vegas::new(|x: &[f64]| f.eval(x), UniformBox::unit(DIMS).unwrap())
            .stratified(stratified)
            .samples(2000)
            .warmup(3)
            .iterations(1000)
            .tolerance(tolerance)
            .seed(seed)
            .threads(1)
            .run()
            .unwrap()
    });
    let name = if stratified { "VEGAS+" } else { "VEGAS" };
    eprintln!("{name} {family}: covered {covered} of {SEEDS}");
    assert!(
        covered >= REQUIRED,
        "{name} {family}: covered {covered} of {SEEDS}"
    );
}

#[test]
fn miser_covers_on_every_family() {
    for family in GenzFamily::ALL {
        miser_coverage(family);
    }
}

#[test]
fn vegas_covers_on_every_family() {
    for family in GenzFamily::ALL {
        vegas_coverage(family, false);
    }
}

#[test]
fn vegas_plus_covers_on_every_family() {
    for family in GenzFamily::ALL {
        vegas_coverage(family, true);
    }
}
