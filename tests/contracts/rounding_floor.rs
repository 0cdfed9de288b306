//! Error bars at the floor of floating point: no reported standard error is smaller than the
//! rounding error of the arithmetic that produced the mean.
//!
//! - `Accumulator::rounding_error` bounds the distance between the computed mean and the exact
//!   mean of the values it was given, for values of any spread and sign, pushed one by one,
//!   summarized in slices, or merged from parts (the exact mean comes from a double-double
//!   sum, whose own error is about `u^2` relative).
//! - In zero-variance cases, where the statistical standard error vanishes (importance sampling
//!   with a density exactly proportional to the integrand, a constant integrand, a control
//!   variate equal to the integrand), every method reports a standard error at the floor and
//!   its 99% interval contains the exact value.

use crate::common::config;
use mcint::adaptive::{Miser, TwoStage, Vegas};
use mcint::estimator::FixedControlVariate;
use mcint::pdf::{Pdf1d, ProductPdf, TruncatedNormal, UniformBox};
use mcint::sampler::{Jittered, Scramble, Sobol};
use mcint::stats::{Accumulator, Tolerance, Warning};
use mcint::testfns::{Genz, GenzFamily, TestFunction};
use mcint::{Estimate, Integrator};
use proptest::prelude::*;

/// `a + b` as an unevaluated sum `(s, e)` with `s + e == a + b` exactly (Knuth's TwoSum).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let v = s - a;
    (s, (a - (s - v)) + (b - v))
}

/// The sum of `values` in double-double arithmetic: accurate to about `2^-104` of
/// `sum |x_i|`.
fn dd_sum(values: &[f64]) -> (f64, f64) {
    let (mut hi, mut lo) = (0.0, 0.0);
    for &x in values {
        let (s, e) = two_sum(hi, x);
        let (s2, e2) = two_sum(s, lo + e);
        hi = s2;
        lo = e2;
    }
    (hi, lo)
}

/// `|mean - sum(values) / n|`, computed as `|mean n - sum| / n` with the product exact (fused
/// multiply-add) and the sum in double-double.
fn error_of_mean(mean: f64, values: &[f64]) -> f64 {
    let n = values.len() as f64;
    let p = mean * n;
    let p_err = mean.mul_add(n, -p);
    let (hi, lo) = dd_sum(values);
    (((p - hi) + (p_err - lo)) / n).abs()
}

/// Values of one sign or both, with a common offset (cancellation) and a spread of many
/// orders of magnitude.
fn values() -> impl Strategy<Value = Vec<f64>> {
    (
        prop::collection::vec(-1.0f64..1.0, 1..3000),
        -12i32..12,
        prop_oneof![Just(0.0), -1e6f64..1e6],
    )
        .prop_map(|(raw, scale, offset)| {
            raw.iter()
                .map(|r| offset + r * 10f64.powi(scale) * r.abs().powi(4).recip().min(1e3))
                .collect()
        })
}

proptest! {
    #![proptest_config(config(300, 0x0f10_0a7e))]

    /// The bound holds whichever way the values arrive: pushed, in slices, or in merged parts.
    #[test]
    fn accumulator_bound_covers_the_rounding_error(values in values(), split in 0.0f64..1.0) {
        let mut pushed = Accumulator::new();
        values.iter().for_each(|&v| pushed.push(v));
        let mut sliced = Accumulator::new();
        values.chunks(1024).for_each(|c| sliced.extend(c));
        let cut = (split * values.len() as f64) as usize;
        let mut merged = Accumulator::new();
        merged.extend(&values[..cut]);
        let mut right = Accumulator::new();
        values[cut..].iter().for_each(|&v| right.push(v));
        merged.merge(&right);
        for acc in [pushed, sliced, merged] {
            let error = error_of_mean(acc.mean(), &values);
            prop_assert!(
                error <= acc.rounding_error(),
                "error {error:e} above the bound {:e} (mean {})",
                acc.rounding_error(),
                acc.mean()
            );
        }
    }
}

/// The bound is not vacuous: for a thousand equal values it is a few hundred units in the last
/// place of the mean, not orders of magnitude more.
#[test]
fn accumulator_bound_is_tight_enough_to_be_useful() {
    let mut acc = Accumulator::new();
    acc.extend(&[0.1; 1000]);
    let ulp = 0.1 * f64::EPSILON;
    assert!(acc.rounding_error() > 10.0 * ulp / 2.0);
    assert!(
        acc.rounding_error() < 500.0 * ulp,
        "{:e}",
        acc.rounding_error()
    );
}

/// The exact value lies inside the 99% interval, whose standard error is at least the floor.
fn assert_honest(name: &str, e: &Estimate, exact: f64) {
    let se = e
        .std_error
        .unwrap_or_else(|| panic!("{name}: no standard error"));
    assert!(e.rounding_error > 0.0, "{name}: no floor");
    assert!(
        se >= e.rounding_error,
        "{name}: se {se:e} below {:e}",
        e.rounding_error
    );
    let (lo, hi) = e.confidence_interval(0.99).unwrap().unwrap();
    assert!(
        lo <= exact && exact <= hi,
        "{name}: {} is {:e} from {exact}, 99% half-width {:e}",
        e.mean,
        (e.mean - exact).abs(),
        (hi - lo) / 2.0
    );
}

/// Whether the floor was reported in place of a smaller statistical error.
fn at_floor(e: &Estimate) -> bool {
    e.warnings
        .iter()
        .any(|w| matches!(w, Warning::AtRoundingFloor { .. }))
}

/// The case of the issue that asked for the floor: the 5-D Genz Gaussian sampled from the
/// product of truncated normals proportional to it, so every `f/pdf` is the integral up to
/// rounding. Before the floor its standard error was 5e-21 against an error of 6e-18.
#[test]
fn perfect_importance_sampling_reports_the_floor() {
    let a = vec![4.0, 5.0, 6.0, 7.0, 8.0];
    let u = vec![0.3, 0.45, 0.5, 0.6, 0.7];
    let g = Genz::new(GenzFamily::Gaussian, a.clone(), u.clone()).unwrap();
    let factors: Vec<Box<dyn Pdf1d>> = a
        .iter()
        .zip(&u)
        .map(|(&ai, &ui)| {
            Box::new(TruncatedNormal::new(ui, 1.0 / (ai * 2f64.sqrt()), 0.0, 1.0).unwrap())
                as Box<dyn Pdf1d>
        })
        .collect();
    let pdf = ProductPdf::new(factors).unwrap();
    let e = Integrator::with_pdf(|x: &[f64]| g.eval(x), pdf)
        .samples(50_000)
        .seed(21)
        .run()
        .unwrap();
    assert_honest("importance", &e, g.exact());
    assert!(at_floor(&e), "{:?}", e.warnings);
    // The floor is small: a few hundred units in the last place of the integral.
    assert!(e.std_error.unwrap() < 1e-12 * g.exact());
}

const CONSTANT: f64 = 0.1;

fn constant(_: &[f64]) -> f64 {
    CONSTANT
}

fn unit(dims: usize) -> UniformBox {
    UniformBox::unit(dims).unwrap()
}

#[test]
fn a_constant_integrand_gets_an_honest_floor_from_every_method() {
    let tolerance = Tolerance::relative(1e-3).unwrap();
    let cases: Vec<(&str, Estimate)> = vec![
        (
            "plain",
            Integrator::over_box(constant, unit(3))
                .samples(100_000)
                .run()
                .unwrap(),
        ),
        (
            "rqmc",
            Integrator::over_box(constant, unit(3))
                .sampler(Sobol::new(3, Scramble::Owen, 1).unwrap())
                .samples(4096)
                .replicates(16)
                .run()
                .unwrap(),
        ),
        (
            "stratified",
            Integrator::over_box(constant, unit(3))
                .sampler(Jittered::new(3, 10, 1).unwrap())
                .replicates(16)
                .run()
                .unwrap(),
        ),
        (
            "plain to a tolerance",
            Integrator::over_box(constant, unit(3))
                .tolerance(tolerance)
                .run()
                .unwrap(),
        ),
        (
            "rqmc to a tolerance",
            Integrator::over_box(constant, unit(3))
                .sampler(Sobol::new(3, Scramble::Owen, 1).unwrap())
                .tolerance(tolerance)
                .run()
                .unwrap(),
        ),
        (
            "vegas",
            Vegas::new(constant, unit(3))
                .stratified(false)
                .run()
                .unwrap(),
        ),
        ("vegas+", Vegas::new(constant, unit(3)).run().unwrap()),
        ("miser", Miser::new(constant, unit(3)).run().unwrap()),
        (
            "miser to a tolerance",
            Miser::new(constant, unit(3))
                .tolerance(tolerance)
                .run()
                .unwrap(),
        ),
        (
            "two-stage",
            TwoStage::new(constant, unit(3), 4).run().unwrap(),
        ),
    ];
    for (name, e) in &cases {
        assert_honest(name, e, CONSTANT);
    }
    // Where the statistics give zero, the floor is what is reported (VEGAS keeps its own
    // larger roundoff floor on each hypercube's variance, as the Python package does).
    for (name, e) in cases.iter().filter(|(n, _)| !n.starts_with("vegas")) {
        assert!(at_floor(e), "{name}: {:?}", e.warnings);
    }
}

/// `f = e^x` with the control `g = f` (known integral `e - 1`): the corrected contribution is
/// the integral at every point, with the fixed coefficient 1 and with a fitted one.
#[test]
fn a_control_variate_equal_to_the_integrand_gets_an_honest_floor() {
    let exact = std::f64::consts::E - 1.0;
    let f = |x: &[f64]| x[0].exp();
    let fixed = FixedControlVariate::new(f, f, exact, unit(1)).unwrap();
    let e = Integrator::new(fixed).samples(10_000).run().unwrap();
    assert_honest("fixed coefficient", &e, exact);
    assert!(at_floor(&e));
    let fitted = Integrator::with_controls(f, unit(1))
        .control(f, exact)
        .samples(10_000)
        .run()
        .unwrap();
    assert_honest("fitted coefficient", &fitted, exact);
}
