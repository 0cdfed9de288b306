//! Extreme sizes and counts: refused with an error that says how much was asked for, or run
//! within bounds; never a panic, an abort or a hang.

use super::*;
use mcint::adaptive::TwoStage;
use mcint::pdf::UniformBox;
use mcint::stats::{CovarianceAccumulator, Warning};
use mcint::testfns::{Genz, GenzFamily, TestFunction};
use mcint::{Integrator, Points};

#[test]
fn buffers_beyond_eight_gib_are_refused() {
    assert!(Points::new(1, 1 << 40).is_err());
    let e = Genz::with_defaults(GenzFamily::Gaussian, 1 << 40).unwrap_err();
    assert!(e.to_string().contains("bytes were asked for"), "{e}");
    let e = CovarianceAccumulator::new(1 << 20).unwrap_err();
    assert!(e.to_string().contains("bytes were asked for"), "{e}");
}

#[test]
fn huge_counts_are_refused_and_huge_thread_counts_capped() {
    let f = |x: &[f64]| x[0];
    let e = Integrator::over_box(f, UniformBox::unit(1).unwrap())
        .samples(1)
        .replicates(u64::MAX)
        .run()
        .unwrap_err();
    assert_clear(&e, &["replicates"]);
    let e = TwoStage::new(f, UniformBox::unit(1).unwrap(), 4)
        .pilot(u64::MAX)
        .run()
        .unwrap_err();
    assert_clear(&e, &["pilot"]);
    let e = Integrator::over_box(f, UniformBox::unit(1).unwrap())
        .samples(100_000)
        .threads(100_000)
        .run()
        .unwrap();
    assert!((e.mean - 0.5).abs() < 5.0 * e.std_error.unwrap());
}

/// A 100-D Gaussian peak so narrow that the integrand underflows to zero at every sampled
/// point, while its integral (about 1e-123) does not: the estimate is 0, but it says that
/// every contribution was zero, and its error bar is not zero.
#[test]
fn an_integrand_that_underflows_everywhere_is_flagged() {
    let g = Genz::new(GenzFamily::Gaussian, vec![30.0; 100], vec![0.5; 100]).unwrap();
    assert!(g.exact() > 0.0);
    let e = Integrator::over_box(|x: &[f64]| g.eval(x), UniformBox::unit(100).unwrap())
        .samples(10_000)
        .run()
        .unwrap();
    assert_eq!(e.mean, 0.0);
    assert!(e.std_error.unwrap() > 0.0);
    assert!(
        e.warnings.contains(&Warning::AllZero { count: 10_000 }),
        "{:?}",
        e.warnings
    );
}

/// VEGAS and VEGAS+ on a spike their points never hit: every value zero. They reported
/// 0 +- 3e-126 (the floor on iteration variances) and no warning; now 0 +- the rounding floor,
/// and the warning the other runners give.
#[test]
fn vegas_that_sees_only_zeros_says_so() {
    use mcint::adaptive::Vegas;
    let spike = |x: &[f64]| if x[0] > 1.0 - 1e-9 { 1e6 } else { 0.0 };
    for stratified in [false, true] {
        let e = Vegas::new(spike, UniformBox::unit(2).unwrap())
            .stratified(stratified)
            .samples(10_000)
            .seed(1)
            .run()
            .unwrap();
        assert_eq!(e.mean, 0.0, "{e:?}");
        assert!(e.std_error.unwrap() < 1e-300, "{e:?}");
        assert!(
            e.warnings
                .iter()
                .any(|w| matches!(w, Warning::AllZero { count } if *count == e.n)),
            "stratified {stratified}: {:?}",
            e.warnings
        );
    }
    // One value that is not zero is no such warning.
    let e = Vegas::new(|x: &[f64]| x[0], UniformBox::unit(2).unwrap())
        .samples(10_000)
        .seed(1)
        .run()
        .unwrap();
    assert!(
        !e.warnings
            .iter()
            .any(|w| matches!(w, Warning::AllZero { .. }))
    );
}

/// A NaN of a stratified VEGAS+ run is reported at its own canonical point: in its hypercube,
/// where the first iteration's uniform grid maps it to the point where the integrand failed
/// (a square of side 0.02). The sampler's point in the whole cube was reported instead.
#[test]
fn vegas_plus_names_the_point_of_a_nan() {
    use mcint::Error;
    use mcint::adaptive::Vegas;
    let corner = |x: &[f64]| x.iter().all(|&c| (0.5..0.52).contains(&c));
    let f = move |x: &[f64]| if corner(x) { f64::NAN } else { x[0] };
    for threads in [1, 2] {
        let err = Vegas::new(f, UniformBox::unit(2).unwrap())
            .samples(1_000_000)
            .seed(2)
            .threads(threads)
            .run()
            .unwrap_err();
        let Error::NonFiniteContribution { first_point, .. } = &err else {
            panic!("{err}");
        };
        assert!(corner(first_point), "{err}");
    }
}

/// Too many iterations for 64-bit sample indices: the iterations are named. With 2^60
/// iterations the samples were blamed ("at most 15 per iteration", below VEGAS's least of 50),
/// and a warm-up of u64::MAX gave an index error naming no setting.
#[test]
fn vegas_names_the_iterations_when_their_indices_overflow() {
    use mcint::adaptive::Vegas;
    let vegas = || Vegas::new(|x: &[f64]| x[0], UniformBox::unit(2).unwrap()).samples(1000);
    for err in [
        vegas().iterations(1 << 60).run().unwrap_err(),
        vegas().warmup(u64::MAX).run().unwrap_err(),
    ] {
        assert!(
            err.to_string().starts_with("invalid warmup + iterations"),
            "{err}"
        );
    }
}

/// Subnormal values: VEGAS summed them in units near their size and reported a rounding
/// error of 0 (and a standard error of 0 at 1e-320); the values were rounded at the bottom of
/// the subnormal range before any units, which the other runners' floor of 64 x 2^-1074
/// carries.
#[test]
fn vegas_keeps_the_subnormal_rounding_floor() {
    use mcint::adaptive::Vegas;
    for tiny in [1e-320, 1e-318] {
        let e = Vegas::new(move |x: &[f64]| x[0] * tiny, UniformBox::unit(2).unwrap())
            .samples(10_000)
            .seed(1)
            .run()
            .unwrap();
        assert!(e.rounding_error >= 64.0 * 5e-324, "{e:?}");
        assert!(e.std_error.unwrap() >= e.rounding_error, "{e:?}");
    }
}
