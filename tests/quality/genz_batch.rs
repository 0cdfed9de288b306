//! `TestFunction::eval_batch` against `eval`: the Genz families' block evaluation forms the
//! same sums and products as `eval`, so product and corner peaks give the same bits and the
//! families ending in `exp` or `cos` are within 1 ulp of `eval` (the accuracy of
//! `vector_math`'s `exp`, and of its `cos` for arguments up to 100); other test functions
//! use the per-point default, which gives the same bits.

use mcint::Points;
use mcint::sampler::{Independent, Sampler};
use mcint::testfns::{Genz, GenzFamily, Keister, TestFunction};

fn block(dims: usize, seed: u64) -> Points {
    let mut points = Points::new(dims, 1000).unwrap();
    Independent::new(dims, seed)
        .unwrap()
        .fill(0, &mut points)
        .unwrap();
    points
}

/// The largest distance of `eval_batch` from `eval` over a block, in ulps of `eval`.
fn worst_ulps(f: &dyn TestFunction, points: &Points) -> f64 {
    let mut out = vec![f64::NAN; points.len()];
    f.eval_batch(points, &mut out);
    let mut worst = 0.0f64;
    for (i, y) in out.iter().enumerate() {
        let x: Vec<f64> = (0..points.dims()).map(|k| points.column(k)[i]).collect();
        let expected = f.eval(&x);
        if *y != expected {
            let e = expected.abs();
            let ulp = f64::from_bits(e.to_bits() + 1) - e;
            worst = worst.max((y - expected).abs() / ulp);
        }
    }
    worst
}

#[test]
fn genz_blocks_match_point_evaluation() {
    for family in GenzFamily::ALL {
        for dims in 1..=10 {
            let points = block(dims, dims as u64);
            let customary = Genz::with_defaults(family, dims).unwrap();
            // Sharper and shifted parameters too.
            let a = customary.a().iter().map(|a| 3.0 * a).collect();
            let u = customary.u().iter().map(|u| 1.0 - u).collect();
            let sharper = Genz::new(family, a, u).unwrap();
            for f in [customary, sharper] {
                let worst = worst_ulps(&f, &points);
                let allowed = match family {
                    GenzFamily::ProductPeak | GenzFamily::CornerPeak => 0.0,
                    _ => 1.0,
                };
                assert!(worst <= allowed, "{family} d={dims}: {worst} ulps");
            }
        }
    }
}

#[test]
fn the_default_block_evaluation_is_the_point_one() {
    let f = Keister::new(3).unwrap();
    assert_eq!(worst_ulps(&f, &block(3, 9)), 0.0);
}

#[test]
fn a_batch_integrand_gives_the_estimate_of_the_point_one() {
    use mcint::Integrator;
    use mcint::pdf::UniformBox;
    use mcint::sampler::{Scramble, Sobol};
    let f = Genz::with_defaults(GenzFamily::Oscillatory, 5).unwrap();
    let run = |batch: bool| {
        let sobol = Sobol::new(5, Scramble::Owen, 3).unwrap();
        let unit = UniformBox::unit(5).unwrap();
        if batch {
            Integrator::over_box_batch(|p: &Points, out: &mut [f64]| f.eval_batch(p, out), unit)
                .sampler(sobol)
                .samples(1 << 14)
                .replicates(4)
                .run()
                .unwrap()
        } else {
            Integrator::over_box(|x: &[f64]| f.eval(x), unit)
                .sampler(sobol)
                .samples(1 << 14)
                .replicates(4)
                .run()
                .unwrap()
        }
    };
    let (batch, point) = (run(true), run(false));
    // Values within an ulp of each other: means within a few ulps.
    assert!((batch.mean - point.mean).abs() <= 1e-14);
    assert!((batch.mean - f.exact()).abs() <= 5.0 * batch.std_error.unwrap());
}
