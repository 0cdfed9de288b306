//! Values up to `f64::MAX`: the Accumulator works in units of a power of two beyond about
//! 1e144, so means stay within `[min, max]` and standard errors stay finite; every runner
//! either gives a finite, correct estimate for an integrand of magnitude 1e300 or refuses with
//! `Error::Overflow`, never NaN or infinity passed off as an estimate. Values all below about
//! 1e-145 are accumulated in small units likewise, so that their error bars do not underflow.

use mcint::adaptive::{Miser, TwoStage, Vegas};
use mcint::pdf::UniformBox;
use mcint::sampler::{Scramble, Sobol};
use mcint::stats::{Accumulator, Derived, Estimate};
use mcint::{Error, Integrator, Tolerance};
use std::sync::atomic::{AtomicU64, Ordering};

/// 2^1000: scaling by it is exact, so the statistics of `u * BIG` are those of `u` times it.
const BIG: f64 = 1.0715086071862673e301;

/// Deterministic values in [-1, 1): a fixed linear congruential stream, enough for moments.
fn values(n: usize) -> Vec<f64> {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    (0..n)
        .map(|_| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        })
        .collect()
}

/// Accumulators of `values` and of `values` times the power of two `factor`, checked to have
/// the same mean and standard error times `factor`, bit for bit: the same operations in units
/// of a power of two.
fn pushed_and_scaled(values: &[f64], factor: f64) -> (Accumulator, Accumulator) {
    let mut a = Accumulator::new();
    let mut b = Accumulator::new();
    for &u in values {
        a.push(u);
        b.push(u * factor);
    }
    assert_eq!(b.mean(), a.mean() * factor);
    let (ea, eb) = (a.estimate(), b.estimate());
    assert_eq!(eb.std_error.unwrap(), ea.std_error.unwrap() * factor);
    (a, b)
}

#[test]
fn huge_values_have_the_statistics_of_small_ones_scaled() {
    let small = values(1000);
    let (_, b) = pushed_and_scaled(&small, BIG);
    let eb = b.estimate();
    assert!(b.mean() >= b.min() && b.mean() <= b.max());
    // The squares overflow, and say so with an infinity rather than a negative number.
    assert_eq!(b.m2(), f64::INFINITY);
    // Slices and merges: the same to rounding.
    let mut c = Accumulator::new();
    c.extend(&small[..500].iter().map(|u| u * BIG).collect::<Vec<_>>());
    let mut d = Accumulator::new();
    d.extend(&small[500..].iter().map(|u| u * BIG).collect::<Vec<_>>());
    c.merge(&d);
    assert!((c.mean() - b.mean()).abs() <= 1e-12 * BIG);
    let se = c.estimate().std_error.unwrap();
    assert!((se / eb.std_error.unwrap() - 1.0).abs() < 1e-12, "{se}");
}

/// 2^-1000: values near it have squares far below the least double.
const TINY: f64 = 9.332636185032189e-302;

#[test]
fn tiny_values_have_the_statistics_of_ordinary_ones_scaled() {
    assert_eq!(TINY, 2f64.powi(-1000));
    let ordinary = values(1000);
    // Before the small units, the squares underflowed and the standard error came out 0.
    let (a, b) = pushed_and_scaled(&ordinary, TINY);
    // Slices, merges (with an all-zero part) and replicate means: the same to rounding.
    let mut c = Accumulator::new();
    c.extend(&[0.0; 10]);
    c.extend(&ordinary[..500].iter().map(|u| u * TINY).collect::<Vec<_>>());
    let mut d = Accumulator::new();
    d.extend(&ordinary[500..].iter().map(|u| u * TINY).collect::<Vec<_>>());
    c.merge(&d);
    let mut zeros = Accumulator::new();
    zeros.extend(&[0.0; 10]);
    let mut with_zeros = a;
    with_zeros.merge(&zeros);
    let se = c.estimate().std_error.unwrap();
    let expected = with_zeros.estimate().std_error.unwrap() * TINY;
    assert!(
        (se / expected - 1.0).abs() < 1e-12,
        "{se:e} vs {expected:e}"
    );
    let means: Vec<f64> = ordinary[..8].iter().map(|u| u * TINY).collect();
    let tiny = Estimate::from_replicates(&means, 1).unwrap();
    let plain = Estimate::from_replicates(&ordinary[..8], 1).unwrap();
    assert!((tiny.std_error.unwrap() / (plain.std_error.unwrap() * TINY) - 1.0).abs() < 1e-12);
    // The units survive a save; the least subnormal keeps normal units.
    let back: Accumulator = serde_json::from_str(&serde_json::to_string(&b).unwrap()).unwrap();
    assert_eq!(back, b);
    let mut least = Accumulator::new();
    least.extend(&[5e-324, 1e-323, 5e-324]);
    assert!(least.estimate().std_error.unwrap() > 0.0);
    assert!(serde_json::from_str::<Accumulator>(&serde_json::to_string(&least).unwrap()).is_ok());
}

/// Integrands of magnitude 2^-1000: the error bars of the Integrator and of two-stage
/// sampling are those of the same integrand at magnitude 1, scaled (they were 1e-14 of them,
/// the mean's rounding floor); MISER's allocation reads variances, whose squares may still
/// underflow, so its error bar can differ, but it stays an error bar.
#[test]
fn tiny_integrands_keep_their_error_bars() {
    let runs = |scale: f64| {
        let f = move |x: &[f64]| scale * (1.0 + x[0]);
        let unit = || UniformBox::unit(2).unwrap();
        let plain = Integrator::over_box(f, unit())
            .samples(4096)
            .seed(3)
            .run()
            .unwrap();
        let rqmc = Integrator::over_box(f, unit())
            .sampler(Sobol::new(2, Scramble::Owen, 3).unwrap())
            .samples(1024)
            .replicates(8)
            .run()
            .unwrap();
        let two_stage = TwoStage::new(f, unit(), 4).samples(4096).run().unwrap();
        let miser = Miser::new(f, unit()).samples(4096).seed(3).run().unwrap();
        [plain, rqmc, two_stage, miser].map(|e| (e.mean / scale, e.std_error.unwrap() / scale))
    };
    let (ordinary, tiny) = (runs(1.0), runs(TINY));
    for (method, (a, b)) in ["plain", "rqmc", "two-stage"]
        .iter()
        .zip(ordinary.iter().zip(&tiny))
    {
        assert!(
            (b.1 / a.1 - 1.0).abs() < 1e-9,
            "{method}: {b:?} vs {a:?} (relative)"
        );
    }
    let (mean, std_error) = tiny[3];
    assert!(std_error > 1e-6, "MISER: {std_error:e} (relative)");
    assert!(
        (mean - 1.5).abs() < 5.0 * std_error,
        "MISER: {mean} +- {std_error:e}"
    );
}

/// Two-stage sampling's Welch-Satterthwaite degrees of freedom are a ratio of squared
/// variances: at magnitudes near 1e-100 those squares underflowed (the pooled count was
/// given instead), near 1e100 they overflowed (NaN).
#[test]
fn two_stage_degrees_of_freedom_do_not_depend_on_the_scale() {
    let dof = |scale: f64| {
        let f = move |x: &[f64]| scale * (1.0 + x[0]) * (1.0 + x[1] * x[1]);
        let e = TwoStage::new(f, UniformBox::unit(2).unwrap(), 4)
            .samples(4096)
            .run()
            .unwrap();
        e.dof.unwrap()
    };
    let ordinary = dof(1.0);
    // Fewer than the pooled 4096 - 16: the strata's variances differ.
    assert!(ordinary < 4000.0, "{ordinary}");
    for exponent in [-1000, -330, 330, 1000] {
        let scaled = dof(2f64.powi(exponent));
        assert!(
            (scaled / ordinary - 1.0).abs() < 1e-9,
            "2^{exponent}: {scaled} against {ordinary}"
        );
    }
}

/// A ratio of two integrals of magnitude `scale`, from 4096 independent points and from 8
/// Owen-scrambled replicates.
fn ratios(scale: f64) -> [mcint::Result<Estimate>; 2] {
    let f = move |x: &[f64], out: &mut [f64]| {
        out[0] = scale * (1.0 + x[0]);
        out[1] = scale * (1.0 + x[0] * x[1]);
    };
    let unit = || UniformBox::unit(2).unwrap();
    let plain = Integrator::over_box_vector(2, f, unit())
        .samples(4096)
        .seed(1)
        .run()
        .unwrap();
    let rqmc = Integrator::over_box_vector(2, f, unit())
        .sampler(Sobol::new(2, Scramble::Owen, 1).unwrap())
        .samples(1024)
        .replicates(8)
        .run()
        .unwrap();
    [plain, rqmc].map(|run| run.derived(&Derived::ratio(0, 1)))
}

/// Outputs near 1e-160 have covariances below the normal doubles: a ratio's delta-method
/// error bar came out 2e-10 of the true one (and infinite near 1e-200). It is refused with an
/// error that says what to do; at 2^-300 (about 5e-91) it is the ordinary one.
#[test]
fn derived_quantities_of_tiny_outputs_are_refused_not_shrunk() {
    let ordinary = ratios(1.0).map(|r| r.unwrap());
    let small = ratios(2f64.powi(-300)).map(|r| r.unwrap());
    for (a, b) in ordinary.iter().zip(&small) {
        assert!((b.std_error.unwrap() / a.std_error.unwrap() - 1.0).abs() < 1e-9);
        assert!((b.mean / a.mean - 1.0).abs() < 1e-12);
    }
    for exponent in [-540, -700, -1000] {
        for result in ratios(2f64.powi(exponent)) {
            match result {
                Err(err @ Error::Unsupported { .. }) => {
                    assert!(err.to_string().contains("multiply the integrand"), "{err}");
                }
                other => panic!("2^{exponent}: expected Error::Unsupported, got {other:?}"),
            }
        }
    }
}

/// A run to a tolerance on such a ratio stops at its first estimate with that error instead
/// of running to its evaluation limit (2^24 evaluations here) on error bars it cannot form.
#[test]
fn a_tolerance_on_a_tiny_ratio_stops_at_once() {
    let calls = AtomicU64::new(0);
    let tiny = 2f64.powi(-540);
    let f = |x: &[f64], out: &mut [f64]| {
        calls.fetch_add(1, Ordering::Relaxed);
        out[0] = tiny * (1.0 + x[0]);
        out[1] = tiny * (1.0 + x[0] * x[1]);
    };
    let tolerance = Tolerance::relative(1e-6)
        .unwrap()
        .max_evaluations(1 << 24)
        .unwrap();
    let result = Integrator::over_box_vector(2, f, UniformBox::unit(2).unwrap())
        .derived_tolerance(Derived::ratio(0, 1), tolerance)
        .run();
    assert!(
        matches!(result, Err(Error::Unsupported { .. })),
        "{result:?}"
    );
    let spent = calls.load(Ordering::Relaxed);
    assert!(spent < 1 << 20, "{spent} evaluations");
}

#[test]
fn values_at_the_largest_double_keep_a_finite_error_bar() {
    let mut acc = Accumulator::new();
    for i in 0..1000 {
        acc.push(if i % 2 == 0 { f64::MAX } else { -f64::MAX });
    }
    // Alternating +-a: mean 0, standard error a / sqrt(n - 1).
    let e = acc.estimate();
    assert_eq!(acc.mean(), 0.0);
    let expected = f64::MAX / 999f64.sqrt();
    assert!((e.std_error.unwrap() / expected - 1.0).abs() < 1e-12);
    assert!(e.rounding_error.is_finite());
}

#[test]
fn a_scaled_accumulator_survives_a_save() {
    let mut acc = Accumulator::new();
    for u in values(100) {
        acc.push(u * BIG);
    }
    let text = serde_json::to_string(&acc).unwrap();
    assert!(text.contains("scale"), "{text}");
    let back: Accumulator = serde_json::from_str(&text).unwrap();
    assert_eq!(back, acc);
    // An ordinary one keeps its old form, without a scale.
    let mut small = Accumulator::new();
    small.extend(&values(100));
    assert!(!serde_json::to_string(&small).unwrap().contains("scale"));
    // A scale that is not a power of two is refused.
    let bad = text.replace("\"scale\":", "\"scale\":3.0,\"x\":");
    assert!(serde_json::from_str::<Accumulator>(&bad).is_err());
}

#[test]
fn replicate_means_near_the_largest_double_combine() {
    let means = [f64::MAX, -f64::MAX, f64::MAX, -f64::MAX];
    let e = Estimate::from_replicates(&means, 1).unwrap();
    assert_eq!(e.mean, 0.0);
    // sqrt(sum (m - 0)^2 / (r (r - 1))) = a * sqrt(4 / 12).
    let expected = f64::MAX * (4.0f64 / 12.0).sqrt();
    assert!((e.std_error.unwrap() / expected - 1.0).abs() < 1e-12);
}

/// `1e300 (1 + x0)` over the unit square: the integral is 1.5e300.
fn huge(x: &[f64]) -> f64 {
    1e300 * (1.0 + x[0])
}

/// A finite estimate within 5 standard errors of 1.5e300, with a finite positive error bar.
fn assert_right(result: mcint::Result<Estimate>, method: &str) {
    let e = result.unwrap_or_else(|err| panic!("{method}: {err}"));
    let se = e.std_error.unwrap();
    assert!(se.is_finite() && se > 0.0, "{method}: {e:?}");
    assert!(
        (e.mean - 1.5e300).abs() <= 5.0 * se,
        "{method}: {} +- {se}",
        e.mean
    );
}

#[test]
fn every_runner_is_honest_about_integrands_near_1e300() {
    let unit = || UniformBox::unit(2).unwrap();
    // The Integrator (plain and replicated) and MISER accumulate in scaled units.
    assert_right(
        Integrator::over_box(huge, unit()).samples(10_000).run(),
        "plain",
    );
    let rqmc = Integrator::over_box(huge, unit())
        .sampler(Sobol::new(2, Scramble::Owen, 3).unwrap())
        .samples(1024)
        .replicates(16)
        .run();
    assert_right(rqmc, "rqmc");
    assert_right(Miser::new(huge, unit()).run(), "miser");
    // Two-stage sampling sums its strata's variances in the strata's units (it gave an
    // infinite standard error, then an overflow error).
    assert_right(TwoStage::new(huge, unit(), 4).run(), "two-stage");
    // VEGAS sums in units near the values (it returned NaN, then refused with an overflow
    // error beyond about 1e150).
    assert_right(Vegas::new(huge, unit()).run(), "vegas+");
    assert_right(Vegas::new(huge, unit()).stratified(false).run(), "vegas");
}

/// `f64::MAX (1/2 + x0 / 4)`: every value is finite and so is the integral, 0.625 f64::MAX,
/// but any sum of two values overflows.
fn near_max(x: &[f64]) -> f64 {
    f64::MAX * (0.5 + 0.25 * x[0])
}

/// `f64::MAX (3/2) (x0 - 1/2)`: values of both signs near the largest double, whose
/// differences overflow; the integral is 0.
fn near_max_both_signs(x: &[f64]) -> f64 {
    f64::MAX * (1.5 * (x[0] - 0.5))
}

/// Every runner integrates values near the largest double as the Integrator does. MISER's
/// leaves summed the values unscaled: the sum overflowed and the run ended in "invalid
/// replicate mean = inf".
#[test]
fn every_runner_integrates_values_near_the_largest_double() {
    let unit = || UniformBox::unit(2).unwrap();
    for (f, exact) in [
        (near_max as fn(&[f64]) -> f64, 0.625 * f64::MAX),
        (near_max_both_signs, 0.0),
    ] {
        let check = |result: mcint::Result<Estimate>, method: &str| {
            let e = result.unwrap_or_else(|err| panic!("{method} ({exact:e}): {err}"));
            let se = e.std_error.unwrap();
            assert!(se.is_finite() && se > 0.0, "{method}: {e:?}");
            assert!((e.mean - exact).abs() <= 5.0 * se, "{method}: {e:?}");
        };
        check(
            Integrator::over_box(f, unit()).samples(10_000).run(),
            "plain",
        );
        check(Miser::new(f, unit()).seed(1).run(), "miser");
        check(TwoStage::new(f, unit(), 4).run(), "two-stage");
        check(Vegas::new(f, unit()).seed(1).run(), "vegas+");
        check(
            Vegas::new(f, unit()).stratified(false).seed(1).run(),
            "vegas",
        );
    }
}

/// A Gaussian peak of height `scale` over the unit square.
fn peak(scale: f64) -> impl Fn(&[f64]) -> f64 + Sync + Copy {
    move |x: &[f64]| scale * (-50.0 * ((x[0] - 0.3).powi(2) + (x[1] - 0.6).powi(2))).exp()
}

/// A run to a budget and one to `Tolerance::relative(1e-3)` (which the unscaled run meets), as
/// `runs(scale, tolerance)` builds them for an integrand of magnitude `scale`, checked to be
/// the unscaled runs with mean and standard error times `2^k`, bit for bit (scaling by a power
/// of two is exact), for each `k` of `exponents`, and to spend at most `extra` more
/// evaluations.
fn check_scaled<R>(runs: R, exponents: &[i32], extra: u64)
where
    R: Fn(f64, Option<Tolerance>) -> Estimate,
{
    let tolerance = Tolerance::relative(1e-3)
        .unwrap()
        .max_evaluations(1 << 24)
        .unwrap();
    let both = |scale: f64| [runs(scale, None), runs(scale, Some(tolerance))];
    let ordinary = both(1.0);
    assert_eq!(ordinary[1].converged, Some(true));
    for &exponent in exponents {
        let scale = 2f64.powi(exponent);
        for (scaled, plain) in both(scale).iter().zip(&ordinary) {
            let at = format!("{:?} at 2^{exponent}", plain.stop);
            assert_eq!(scaled.mean / scale, plain.mean, "{at}");
            let se = |e: &Estimate| e.std_error.unwrap();
            assert_eq!(se(scaled) / scale, se(plain), "{at}");
            assert_eq!(scaled.converged, plain.converged, "{at}");
            let more = scaled.evaluations - plain.evaluations;
            assert!(more <= extra, "{at}: {more} more evaluations");
        }
    }
}

/// VEGAS sums values far from 1 in units of a power of two near them, chosen by its first
/// iteration, which is then run again on the same points: a run of `2^k f` is the run of `f`
/// with its results times `2^k`, and one iteration more spent. Before, beyond about 1e150 it
/// refused with an overflow error, and below about 1e-125 the floor on an iteration's
/// variance (1e-250) made its error bars up to 1e85 times too wide, so runs to a tolerance
/// went to the evaluation limit.
#[test]
fn vegas_runs_far_from_1_are_the_ordinary_run_scaled() {
    const SAMPLES: u64 = 5000;
    for stratified in [true, false] {
        let runs = |scale: f64, tolerance: Option<Tolerance>| {
            let vegas = Vegas::new(peak(scale), UniformBox::unit(2).unwrap())
                .stratified(stratified)
                .samples(SAMPLES)
                .seed(1);
            match tolerance {
                Some(t) => vegas.tolerance(t).run().unwrap(),
                None => vegas.run().unwrap(),
            }
        };
        check_scaled(runs, &[300, 900, -300, -900], SAMPLES);
    }
}

/// MISER's exploration sums the squares of its deviations in units of a power of two near
/// them: a run of `2^k f`, to a budget or to a tolerance, is the run of `f` scaled, bit for
/// bit, with the same evaluations. Before, their squares overflowed (beyond about 1e154) or
/// underflowed (below about 1e-154), every bisection fell back to splitting the points by
/// volume, and on a 2-D Gaussian peak the standard error was 3.8 times the ordinary run's and
/// a run to `Tolerance::relative(1e-3)` spent its 2^24 evaluations (3.9 x 10^6 at magnitude 1).
#[test]
fn miser_runs_far_from_1_are_the_ordinary_run_scaled() {
    let runs = |scale: f64, tolerance: Option<Tolerance>| {
        let miser = Miser::new(peak(scale), UniformBox::unit(2).unwrap()).seed(1);
        match tolerance {
            Some(t) => miser.tolerance(t).run().unwrap(),
            None => miser.run().unwrap(),
        }
    };
    check_scaled(runs, &[500, 900, -500, -900], 0);
}

/// Values of both signs up to 1.95 x 2^1023: the differences MISER's exploration takes
/// overflow, yet its run is the ordinary run scaled, bit for bit (it took differences of
/// `inf`, every bisection fell back to splitting the points by volume, and before that its
/// leaves' sums overflowed).
#[test]
fn miser_runs_of_both_signs_near_the_largest_double_are_the_ordinary_run_scaled() {
    let run = |scale: f64| {
        let f = move |x: &[f64]| {
            let bump = (-50.0 * ((x[0] - 0.3).powi(2) + (x[1] - 0.6).powi(2))).exp();
            scale * (3.6 * (x[0] - 0.5) + 0.15 * bump)
        };
        Miser::new(f, UniformBox::unit(2).unwrap())
            .seed(1)
            .run()
            .unwrap()
    };
    let (ordinary, scale) = (run(1.0), 2f64.powi(1023));
    let scaled = run(scale);
    assert_eq!(scaled.mean / scale, ordinary.mean);
    assert_eq!(
        scaled.std_error.unwrap() / scale,
        ordinary.std_error.unwrap()
    );
}

/// A box of side `2^k` with the peak stretched over it and scaled by `2^-2k`: the integral is
/// the unit square's. Two-stage sampling summed `V_h^2 s_h^2 / n_h` with the squared stratum
/// volume `V_h^2` as it was: in a box of volume 2^900 it overflowed (an overflow error), in one
/// of 2^-900 it underflowed to 0 and the standard error reported was the rounding floor,
/// 1.1e-15 for an actual 3.2e-3. The volume is now split into a power of two and a factor,
/// and every runner gives the unit square's mean and standard error, bit for bit.
#[test]
fn boxes_far_from_volume_1_give_the_unit_square_run() {
    let run = |k: i32, method: &str| {
        let side = 2f64.powi(k);
        let height = 2f64.powi(-2 * k);
        let f = move |x: &[f64]| peak(height)(&[x[0] / side, x[1] / side]);
        let domain = UniformBox::new(vec![0.0, 0.0], vec![side, side]).unwrap();
        match method {
            "two-stage" => TwoStage::new(f, domain, 4).seed(1).run(),
            "miser" => Miser::new(f, domain).seed(1).run(),
            "vegas" => Vegas::new(f, domain).samples(5000).seed(1).run(),
            _ => Integrator::over_box(f, domain)
                .samples(10_000)
                .seed(1)
                .run(),
        }
        .unwrap()
    };
    for method in ["two-stage", "miser", "vegas", "plain"] {
        let unit = run(0, method);
        for k in [450, -450] {
            let e = run(k, method);
            assert_eq!(e.mean, unit.mean, "{method}, side 2^{k}");
            assert_eq!(e.std_error, unit.std_error, "{method}, side 2^{k}");
        }
    }
}

/// Each output of a vector VEGAS run gets its own units: outputs near 2^-400 and 2^400 in one
/// run give the ordinary run's means and standard errors scaled, and their covariance too.
/// (Far beyond, the squares of the standard errors on the covariance matrix's diagonal leave
/// f64 themselves.)
/// A vector run of one output near the largest double stands, as the scalar run does: its
/// covariance matrix is its squared standard error alone, which overflows. VEGAS refused it
/// ("the covariance of the outputs is inf ... a vector run"), and the Python package runs
/// every VEGAS integrand as a vector run.
#[test]
fn one_output_vector_runs_near_the_largest_double_stand() {
    let f = |x: &[f64], out: &mut [f64]| out[0] = near_max(x);
    for stratified in [true, false] {
        let vector = Vegas::new_vector(1, f, UniformBox::unit(2).unwrap())
            .stratified(stratified)
            .seed(1)
            .run()
            .unwrap();
        let scalar = Vegas::new(near_max, UniformBox::unit(2).unwrap())
            .stratified(stratified)
            .seed(1)
            .run()
            .unwrap();
        assert_eq!(vector.outputs[0].mean, scalar.mean);
        assert_eq!(vector.outputs[0].std_error, scalar.std_error);
    }
    let f = |x: &[f64], out: &mut [f64]| out[0] = near_max(x);
    let plain = Integrator::over_box_vector(1, f, UniformBox::unit(2).unwrap())
        .samples(4096)
        .run();
    assert!(plain.is_ok(), "{plain:?}");
}

#[test]
fn vector_vegas_outputs_far_apart_in_magnitude_each_keep_their_statistics() {
    let run = |small: f64, large: f64| {
        let f = move |x: &[f64], out: &mut [f64]| {
            out[0] = peak(small)(x);
            out[1] = large * x[0];
        };
        Vegas::new_vector(2, f, UniformBox::unit(2).unwrap())
            .samples(5000)
            .seed(2)
            .run()
            .unwrap()
    };
    let plain = run(1.0, 1.0);
    let (small, large) = (2f64.powi(-400), 2f64.powi(400));
    let scaled = run(small, large);
    for (k, unit) in [small, large].into_iter().enumerate() {
        let (a, b) = (&scaled.outputs[k], &plain.outputs[k]);
        assert_eq!(a.mean / unit, b.mean, "output {k}");
        assert_eq!(
            a.std_error.unwrap() / unit,
            b.std_error.unwrap(),
            "output {k}"
        );
    }
    let plain_covariance = plain.covariance(0, 1).unwrap();
    assert!(plain_covariance != 0.0);
    assert_eq!(
        scaled.covariance(0, 1).unwrap() / small / large,
        plain_covariance
    );
}

#[test]
fn a_contribution_beyond_the_largest_double_is_an_error_that_says_so() {
    // Half of f64::MAX over a box of volume 4: every value is finite, volume times value is
    // not; the error names that cause.
    let domain = UniformBox::new(vec![0.0, 0.0], vec![2.0, 2.0]).unwrap();
    let err = Integrator::over_box(|_: &[f64]| f64::MAX / 2.0, domain)
        .samples(1000)
        .run()
        .unwrap_err();
    assert!(
        matches!(err, Error::NonFiniteContribution { count: 1000, .. }),
        "{err:?}"
    );
    assert!(err.to_string().contains("times the volume"), "{err}");
}

/// A control of magnitude `scale` on `e^x` of the same magnitude over [0, 1].
fn with_scaled_control(scale: f64) -> mcint::Result<Estimate> {
    Integrator::with_controls(
        move |x: &[f64]| scale * x[0].exp(),
        UniformBox::unit(1).unwrap(),
    )
    .control(move |x: &[f64]| scale * x[0], 0.5 * scale)
    .samples(20_000)
    .run()
}

/// A control whose squares underflow to 0 (values near 1e-200) was called "constant over the
/// pilot", and one whose squares overflow (near 1e160) "a linear combination of the controls
/// before it": both false. Each is now an error that says the magnitude is the cause. Near
/// 1e-120 and 1e100 the run is the ordinary one scaled; near 1e-160 the pilot's subnormal
/// sums give a rougher coefficient, which still gives an honest estimate.
#[test]
fn controls_far_from_1_are_fitted_or_refused_for_their_magnitude() {
    let ordinary = with_scaled_control(1.0).unwrap();
    for scale in [2f64.powi(-400), 2f64.powi(330)] {
        let e = with_scaled_control(scale).unwrap();
        let mean = e.mean / scale / ordinary.mean;
        assert!((mean - 1.0).abs() < 1e-12, "{scale:e}: {mean}");
        let ratio = e.std_error.unwrap() / scale / ordinary.std_error.unwrap();
        assert!((ratio - 1.0).abs() < 1e-6, "{scale:e}: {ratio}");
    }
    let scale = 2f64.powi(-530);
    let e = with_scaled_control(scale).unwrap();
    let exact = std::f64::consts::E - 1.0;
    assert!((e.mean / scale - exact).abs() < 5.0 * e.std_error.unwrap() / scale);
    for scale in [2f64.powi(-660), 2f64.powi(530), 2f64.powi(1000)] {
        let err = with_scaled_control(scale).unwrap_err().to_string();
        assert!(
            err.contains("squares f64 can hold") && !err.contains("constant over"),
            "{scale:e}: {err}"
        );
    }
}

/// A run to a relative tolerance plans its points from the per-sample spread: at 2^1000 that
/// spread, read as `variance().sqrt()`, was infinite and the run went to its evaluation limit
/// (2^30 points for a tolerance met at 1.5 x 10^5). It now plans as at magnitude 1.
#[test]
fn a_tolerance_run_plans_the_same_points_at_any_magnitude() {
    let run = |scale: f64| {
        let f = move |x: &[f64]| scale * (1.0 + x[0] * x[1]);
        let tolerance = Tolerance::relative(1e-3)
            .unwrap()
            .max_evaluations(1 << 26)
            .unwrap();
        Integrator::over_box(f, UniformBox::unit(2).unwrap())
            .tolerance(tolerance)
            .seed(1)
            .run()
            .unwrap()
    };
    let ordinary = run(1.0);
    assert!(ordinary.evaluations < 1 << 20, "{ordinary:?}");
    for exponent in [1000, -1000] {
        let scaled = run(2f64.powi(exponent));
        assert_eq!(scaled.evaluations, ordinary.evaluations, "2^{exponent}");
        assert_eq!(scaled.converged, Some(true), "2^{exponent}");
    }
}
