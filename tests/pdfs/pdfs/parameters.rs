//! Supports and parameters: densities vanish outside the support, and bad parameters are
//! errors that name them.

use super::*;

// Support and parameters

#[test]
fn pdfs_vanish_outside_their_supports() {
    for case in all_cases() {
        let (a, b) = case.pdf.support();
        let mut outside = vec![f64::NAN];
        if a.is_finite() {
            outside.extend([a.next_down(), a - 1.0, a - 1e300, -INF]);
        }
        if b.is_finite() {
            outside.extend([b.next_up(), b + 1.0, b + 1e300, INF]);
            if !case.closed {
                outside.push(b);
            }
        }
        for x in outside {
            assert_eq!(case.pdf.pdf_1d(x), 0.0, "{}: pdf({x})", case.name);
        }
        // Inside, the density is positive (every case has positive density on the interior).
        for u in [0.01, 0.5, 0.99] {
            let x = case.pdf.sample_1d(u);
            assert!(case.pdf.pdf_1d(x) > 0.0, "{}: pdf({x}) = 0", case.name);
        }
    }

    let b = UniformBox::new(vec![-1.0, 2.0], vec![3.0, 2.5]).unwrap();
    // Volume 4 x 0.5 = 2; the lower faces belong to the box, the upper ones do not.
    assert_eq!(b.pdf(&[0.0, 2.25]), 0.5);
    assert_eq!(b.pdf(&[-1.0, 2.0]), 0.5);
    for x in [
        [3.0, 2.25],
        [0.0, 2.5],
        [(-1f64).next_down(), 2.25],
        [0.0, 1.9],
        [f64::NAN, 2.25],
        [0.0, INF],
    ] {
        assert_eq!(b.pdf(&x), 0.0, "box pdf({x:?})");
    }
    let p = product_2d();
    assert!(p.pdf(&[0.5, 0.0]) > 0.0);
    for x in [
        [1.0, 0.0],
        [-0.1, 0.0],
        [0.5, 2.1],
        [0.5, -1.5],
        [0.5, f64::NAN],
    ] {
        assert_eq!(p.pdf(&x), 0.0, "product pdf({x:?})");
    }
}

#[test]
fn constructors_reject_bad_parameters_by_name() {
    let nan = f64::NAN;
    let uniform = |a, b| named(UniformInterval::new(a, b).unwrap_err());
    assert_eq!(uniform(1.0, 1.0), "b");
    assert_eq!(uniform(2.0, 1.0), "b");
    assert_eq!(uniform(nan, 1.0), "a");
    assert_eq!(uniform(0.0, nan), "b");
    assert_eq!(uniform(-INF, 1.0), "a");
    assert_eq!(uniform(0.0, INF), "b");

    let exponential = |r, a, b| named(Exponential::new(r, a, b).unwrap_err());
    assert_eq!(exponential(0.0, 0.0, 1.0), "rate");
    assert_eq!(exponential(-0.0, 0.0, 1.0), "rate");
    assert_eq!(exponential(nan, 0.0, 1.0), "rate");
    assert_eq!(exponential(INF, 0.0, 1.0), "rate");
    assert_eq!(exponential(1.0, 1.0, 1.0), "b");
    assert_eq!(exponential(1.0, nan, 1.0), "a");
    assert_eq!(exponential(1.0, -INF, 1.0), "a");
    assert_eq!(exponential(1.0, 0.0, nan), "b");
    // A growing exponential has no mass at +inf to normalise.
    assert_eq!(exponential(-1.0, 0.0, INF), "b");
    // |rate| (b - a) underflows: the density is uniform to rounding, and sampled as such.
    let flat = Exponential::new(1e-300, 0.0, 1e-300).unwrap();
    assert!((flat.pdf_1d(5e-301) * 1e-300 - 1.0).abs() < 1e-15);
    assert!((flat.sample_1d(0.25) / 2.5e-301 - 1.0).abs() < 1e-15);
    // A half-line needs 1 / rate finite.
    assert_eq!(exponential(5e-324, 0.0, INF), "rate");
    assert!(Exponential::new(1.0, 0.0, INF).is_ok());

    // Densities narrower than 2^20 floats where their mass lies are refused: their samples,
    // rounded to floats, would not follow their pdf (a truncated normal 4 floats wide gave
    // f/p 2.7 times its integral; an exponential of rate -1e17 on [0, 1] put every sample on
    // b's neighbour). The same shapes near 0 are fine.
    let (m, sd) = (1e10, 1e-6);
    let narrow = TruncatedNormal::new(m, sd, m - 3.0 * sd, m + 3.0 * sd).unwrap_err();
    assert_eq!(named(narrow.clone()), "mean, sd and [a, b]");
    assert!(narrow.to_string().contains("2^20 floats"), "{narrow}");
    assert!(TruncatedNormal::new(0.0, sd, -3.0 * sd, 3.0 * sd).is_ok());
    assert_eq!(exponential(-1e17, 0.0, 1.0), "rate");
    assert_eq!(exponential(-1e300, 0.0, 1.0), "rate");
    assert!(Exponential::new(1e17, 0.0, 1.0).is_ok());
    assert_eq!(
        named(mcint::pdf::Tent::new(1e15, 1e15 + 0.125, 1e15 + 1.0).unwrap_err()),
        "b"
    );
    assert!(mcint::pdf::Tent::new(0.0, 0.125, 1.0).is_ok());

    let linear = |a, b, v0, v1| named(Linear::new(a, b, v0, v1).unwrap_err());
    assert_eq!(linear(1.0, 0.0, 1.0, 1.0), "b");
    assert_eq!(linear(0.0, INF, 1.0, 1.0), "b");
    assert_eq!(linear(nan, 1.0, 1.0, 1.0), "a");
    assert_eq!(linear(0.0, 1.0, -1.0, 2.0), "v0");
    assert_eq!(linear(0.0, 1.0, 2.0, -1e-300), "v1");
    assert_eq!(linear(0.0, 1.0, nan, 1.0), "v0");
    assert_eq!(linear(0.0, 1.0, 1.0, INF), "v1");
    assert_eq!(linear(0.0, 1.0, 0.0, 0.0), "v0 + v1");
    assert!(Linear::new(0.0, 1.0, 0.0, 1.0).is_ok());

    let normal = |m, s, a, b| named(TruncatedNormal::new(m, s, a, b).unwrap_err());
    assert_eq!(normal(0.0, 0.0, -1.0, 1.0), "sd");
    assert_eq!(normal(0.0, -1.0, -1.0, 1.0), "sd");
    assert_eq!(normal(0.0, nan, -1.0, 1.0), "sd");
    assert_eq!(normal(0.0, INF, -1.0, 1.0), "sd");
    assert_eq!(normal(nan, 1.0, -1.0, 1.0), "mean");
    assert_eq!(normal(INF, 1.0, -1.0, 1.0), "mean");
    assert_eq!(normal(0.0, 1.0, 1.0, 1.0), "[a, b]");
    assert_eq!(normal(0.0, 1.0, 2.0, 1.0), "[a, b]");
    assert_eq!(normal(0.0, 1.0, nan, 1.0), "[a, b]");
    assert_eq!(normal(0.0, 1.0, 0.0, nan), "[a, b]");
    assert_eq!(normal(0.0, 1.0, INF, INF), "[a, b]");
    assert_eq!(normal(0.0, 1.0, -INF, -INF), "[a, b]");
    // No mass in f64 (the normal probability of [60, 61] is about 1e-784).
    assert_eq!(normal(0.0, 1.0, 60.0, 61.0), "[a, b]");
    assert_eq!(normal(0.0, 1.0, -61.0, -60.0), "[a, b]");
    assert_eq!(normal(0.0, 1.0, 45.0, INF), "[a, b]");
    // a - mean overflows (a is 4.5 sd below the mean): samples there would be -inf.
    assert_eq!(normal(9e307, 4e307, -9e307, -7e307), "[a, b]");
    let message = TruncatedNormal::new(0.0, 1.0, 60.0, 61.0)
        .unwrap_err()
        .to_string();
    assert!(message.contains("probability"), "{message}");

    assert_eq!(named(UniformBox::new(vec![], vec![]).unwrap_err()), "lo");
    assert_eq!(
        named(UniformBox::new(vec![0.0], vec![1.0, 2.0]).unwrap_err()),
        "hi"
    );
    assert_eq!(
        named(UniformBox::new(vec![0.0, 1.0], vec![1.0, 1.0]).unwrap_err()),
        "lo/hi"
    );
    assert_eq!(
        named(UniformBox::new(vec![0.0, nan], vec![1.0, 1.0]).unwrap_err()),
        "lo/hi"
    );
    assert_eq!(
        named(UniformBox::new(vec![0.0], vec![INF]).unwrap_err()),
        "lo/hi"
    );
    assert_eq!(
        named(UniformBox::new(vec![0.0, 0.0], vec![1e200, 1e200]).unwrap_err()),
        "box volume"
    );
    assert_eq!(
        named(UniformBox::new(vec![0.0, 0.0], vec![1e-200, 1e-200]).unwrap_err()),
        "box volume"
    );
    assert_eq!(named(UniformBox::unit(0).unwrap_err()), "dims");
    assert_eq!(named(ProductPdf::new(vec![]).unwrap_err()), "factors");

    // Messages name the parameter and what was allowed.
    assert_eq!(
        Linear::new(0.0, 1.0, -1.0, 2.0).unwrap_err().to_string(),
        "invalid v0 = -1: expected a finite value >= 0"
    );
    assert!(
        TruncatedNormal::new(0.0, -2.0, 0.0, 1.0)
            .unwrap_err()
            .to_string()
            .starts_with("invalid sd = -2")
    );
}

#[test]
fn intervals_whose_width_overflows_are_rejected_or_work() {
    let (a, b) = (-f64::MAX, f64::MAX);
    if let Ok(p) = UniformInterval::new(a, b) {
        assert!(p.pdf_1d(0.0) > 0.0, "pdf(0) = {}", p.pdf_1d(0.0));
        assert!(
            p.sample_1d(0.25) < 0.0,
            "sample(0.25) = {}",
            p.sample_1d(0.25)
        );
    }
    if let Ok(p) = Linear::new(a, b, 1.0, 1.0) {
        assert!(p.pdf_1d(0.0) > 0.0, "linear pdf(0) = {}", p.pdf_1d(0.0));
    }
}

#[test]
fn linear_sampling_is_scale_invariant() {
    // The density depends only on v1 / v0, so scaling both must not change the samples.
    for (v0, v1) in [(1.0, 1.0), (1.0, 3.0), (0.0, 1.0), (2.0, 0.5)] {
        let reference = Linear::new(0.0, 1.0, v0, v1).unwrap();
        for scale in [1e-200, 1e-160, 1e160, 1e200] {
            let scaled = Linear::new(0.0, 1.0, v0 * scale, v1 * scale).unwrap();
            for u in [0.1, 0.5, 0.9] {
                let (x, y) = (reference.sample_1d(u), scaled.sample_1d(u));
                assert!(
                    (x - y).abs() < 1e-12,
                    "v = ({v0}, {v1}) x {scale:e}: sample({u}) = {y}, expected {x}"
                );
                assert!((reference.pdf_1d(x) - scaled.pdf_1d(x)).abs() < 1e-12);
            }
        }
    }
}
