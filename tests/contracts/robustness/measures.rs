use super::*;
use mcint::measure::{BrownianMotion, Construction, GeometricBrownianMotion, Measure};

/// Dates: arbitrary values (mostly refused), or one to four increasing dates at a scale
/// from the subnormal 1e-310 to 1e308 / 16.
fn times() -> impl Strategy<Value = Vec<f64>> {
    let scale = prop_oneof![
        prop::sample::select(vec![1e-310, 1e-300, 1.0, 1e154, 1e300, 1e308 / 16.0]),
        (-300.0..300.0f64).prop_map(|e| 10f64.powf(e)),
    ];
    prop_oneof![
        1 => prop::collection::vec(real(), 0..4),
        3 => (prop::collection::vec(1.0..4.0f64, 1..5), scale).prop_map(|(steps, scale)| {
            let mut date = 0.0;
            steps
                .iter()
                .map(|step| {
                    date += step;
                    date * scale
                })
                .collect()
        }),
    ]
}

fn construction() -> impl Strategy<Value = Construction> {
    prop::sample::select(vec![
        Construction::Standard,
        Construction::Bridge,
        Construction::Pca,
    ])
}

/// Maps every corner of the canonical cube, `{0, 1 - 2^-53}^n` (where the normals are
/// largest, with every combination of signs), its centre and `random`, and asserts that
/// the points are finite.
fn assert_finite_paths(m: &dyn Measure, random: f64) {
    let n = m.dims();
    let mut inputs: Vec<Vec<f64>> = (0..1usize << n)
        .map(|corner| {
            (0..n)
                .map(|k| if corner >> k & 1 == 1 { ONE_BELOW } else { 0.0 })
                .collect()
        })
        .collect();
    inputs.push(vec![0.5; n]);
    inputs.push(vec![random; n]);
    let mut x = vec![0.0; n];
    for u in inputs {
        assert_eq!(m.map(&u, &mut x), 1.0);
        assert!(x.iter().all(|v| v.is_finite()), "{u:?} -> {x:?}");
    }
}

proptest! {
    #![proptest_config(config(512, 0xb40))]

    #[test]
    fn brownian_paths_are_finite_or_refused(
        times in times(),
        drift in real(),
        diffusion in real(),
        construction in construction(),
        r in unit(),
    ) {
        let result = BrownianMotion::new(times, drift, diffusion, construction);
        check(result, &["times", "drift", "diffusion"], |p| assert_finite_paths(&p, r));
    }

    #[test]
    fn geometric_prices_are_finite_or_refused(
        s0 in real(),
        rate in real(),
        sigma in real(),
        times in times(),
        construction in construction(),
        r in unit(),
    ) {
        let result = GeometricBrownianMotion::new(s0, rate, sigma, times, construction);
        check(result, &["s0", "rate", "sigma", "times"], |p| assert_finite_paths(&p, r));
    }
}
