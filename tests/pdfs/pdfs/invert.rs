//! `invert` undoes `sample`, and sampling is monotone.

use super::*;

// invert and monotonicity

/// Round-trip tolerance for `invert(sample(u)) = u`. The sample x is a float, so it carries
/// up to a few ulps of rounding (a clamp to the half-open support moves it by one ulp), and
/// that moves u by `pdf(x)` per unit of x: 4 pdf(x) ulp(x). The cdf arithmetic itself adds a
/// few ulps of u, well inside the 1e-12 floor. (For most cases the first term is ~1e-15; it
/// matters for narrow intervals far from zero such as `[1e9, 1e9 + 1]`, where x only has 27
/// bits below the unit, and for the z = 30 normal tail, where pdf(x) is about 30.)
fn round_trip_tolerance(density: f64, x: f64) -> f64 {
    if x.is_finite() {
        1e-12 + 4.0 * density * (x.abs().next_up() - x.abs())
    } else {
        // u = 0 may map to -inf for a support unbounded below, where the density is zero.
        1e-12
    }
}

proptest! {
    #![proptest_config(config(512, 12345))]

    #[test]
    fn invert_undoes_sample(case in 0usize..29, u in canonical_u()) {
        let cases = all_cases();
        prop_assert_eq!(cases.len(), 29);
        let case = &cases[case];
        let x = case.pdf.sample_1d(u);
        let back = case.pdf.invert_1d(x);
        let tolerance = round_trip_tolerance(case.pdf.pdf_1d(x), x);
        prop_assert!(
            (back - u).abs() <= tolerance,
            "{}: u = {}, x = {}, invert = {}, error {:e}",
            case.name,
            u,
            x,
            back,
            back - u
        );
        // The Pdf trait forwards to the 1-D methods.
        let mut xs = [0.0];
        case.as_pdf.sample(&[u], &mut xs);
        prop_assert_eq!(xs[0].to_bits(), x.to_bits());
        let mut us = [0.0];
        case.as_pdf.invert(&[x], &mut us).unwrap();
        prop_assert_eq!(us[0].to_bits(), back.to_bits());
    }

    #[test]
    fn sampling_is_monotone(
        case in 0usize..29,
        u in canonical_u(),
        ulps in 1u32..=4,
        step in 0.0..1.0f64,
    ) {
        let cases = all_cases();
        let case = &cases[case];
        // Neighbouring floats, where rounding could reverse the order ...
        let mut v = u;
        for _ in 0..ulps {
            v = v.next_up().min(ONE_BELOW);
        }
        // ... and a larger step toward one.
        let w = (u + step * (1.0 - u)).min(ONE_BELOW);
        let (xu, xv, xw) = (case.pdf.sample_1d(u), case.pdf.sample_1d(v), case.pdf.sample_1d(w));
        // Inverse cdfs built on a normal quantile accurate to about one ulp (AS241) can
        // reverse the order of two neighbouring inputs by rounding; allow two ulps of x, far
        // below any stratum width, and nothing more.
        let slack = 2.0 * (xu.abs().next_up() - xu.abs());
        prop_assert!(xu <= xv + slack, "{}: sample({}) = {} > sample({}) = {}", case.name, u, xu, v, xv);
        prop_assert!(xu <= xw, "{}: sample({}) = {} > sample({}) = {}", case.name, u, xu, w, xw);
    }

    #[test]
    fn multidimensional_invert_undoes_sample(u in prop::collection::vec(canonical_u(), 3)) {
        let p = product_3d();
        let (mut x, mut back) = ([0.0; 3], [0.0; 3]);
        p.sample(&u, &mut x);
        p.invert(&x, &mut back).unwrap();
        // Each coordinate is its factor's 1-D warp, so each round trip has the 1-D tolerance
        // with that factor's density, and the density is the product of the factors'.
        let marginals: [Box<dyn Pdf1d>; 3] = [
            Box::new(Linear::new(0.0, 2.0, 1.0, 3.0).unwrap()),
            Box::new(Exponential::new(-2.0, -1.0, 1.0).unwrap()),
            Box::new(TruncatedNormal::new(0.5, 0.3, 0.0, 1.0).unwrap()),
        ];
        for d in 0..3 {
            prop_assert_eq!(x[d].to_bits(), marginals[d].sample_1d(u[d]).to_bits());
            let tolerance = round_trip_tolerance(marginals[d].pdf_1d(x[d]), x[d]);
            prop_assert!(
                (back[d] - u[d]).abs() <= tolerance,
                "product dim {}: {:?} -> {:?}",
                d,
                u,
                back
            );
        }
        let density: f64 = (0..3).map(|d| marginals[d].pdf_1d(x[d])).product();
        prop_assert!(density > 0.0);
        prop_assert!((p.pdf(&x) - density).abs() <= 1e-15 * density);

        // The third axis is 1e-3 wide at 1e6, where x has an ulp of 1.2e-10: the round trip is
        // exact only up to 4 * 1.2e-10 / 1e-3, which the tolerance's density term allows.
        let b = UniformBox::new(vec![-1.0, 2.0, 1e6], vec![3.0, 2.5, 1e6 + 1e-3]).unwrap();
        b.sample(&u, &mut x);
        b.invert(&x, &mut back).unwrap();
        for d in 0..3 {
            let (lo, hi) = (b.lo()[d], b.hi()[d]);
            prop_assert!(x[d] >= lo && x[d] < hi);
            let tolerance = round_trip_tolerance(1.0 / (hi - lo), x[d]);
            prop_assert!(
                (back[d] - u[d]).abs() <= tolerance,
                "box dim {}: {:?} -> {:?}",
                d,
                u,
                back
            );
        }
        prop_assert_eq!(b.pdf(&x), 1.0 / b.volume());
    }
}

#[test]
fn stratified_canonical_points_stay_stratified() {
    // A sweep of sorted u (strata edges of a 1-D jittered pattern) maps to sorted x, so each
    // stratum of u lands in its own interval of x.
    for case in all_cases() {
        let mut last = f64::NEG_INFINITY;
        for i in 0..=2_000 {
            let u = (i as f64 / 2_000.0).min(ONE_BELOW);
            let x = case.pdf.sample_1d(u);
            assert!(x >= last, "{}: not monotone at u = {u}", case.name);
            last = x;
        }
    }
}
