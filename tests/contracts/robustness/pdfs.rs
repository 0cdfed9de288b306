use super::*;
use glam::{DVec2, DVec3};
use mcint::pdf::{
    AliasTable, CosineHemisphere, Exponential, Linear, Mixture, Normal, Pdf, Pdf1d,
    PiecewiseConstant1d, PiecewiseConstant2d, PiecewiseLinear1d, ProductPdf, SphericalCap, Tent,
    TruncatedNormal, UniformBox, UniformDisk, UniformHemisphere, UniformInterval, UniformSphere,
    UniformTriangle,
};

/// Canonical coordinates every accepted pdf is sampled at (each used for all coordinates).
const PROBES: [f64; 7] = [0.0, 5e-324, f64::EPSILON / 2.0, 0.25, 0.5, 0.75, ONE_BELOW];

/// Checks an accepted pdf: samples at the probes and at `random` (cycled over the
/// canonical coordinates) are finite and `inside` the domain with a finite density, which
/// is positive when every coordinate is in `[1/4, 3/4]` (if `positive`); `invert`, where
/// it exists, gives canonical coordinates in `[0, 1]`.
fn exercise(p: &dyn Pdf, inside: &dyn Fn(&[f64]) -> bool, random: &[f64], positive: bool) {
    let (k, d) = (p.canonical_dims(), p.dims());
    assert!(k >= 1 && d >= 1, "canonical_dims {k}, dims {d}");
    let mut inputs: Vec<Vec<f64>> = PROBES.iter().map(|&v| vec![v; k]).collect();
    inputs.push((0..k).map(|i| random[i % random.len()]).collect());
    let (mut x, mut back) = (vec![0.0; d], vec![0.0; k]);
    for u in &inputs {
        p.sample(u, &mut x);
        let shown = |v: &[f64]| format!("{:?}", &v[..v.len().min(4)]);
        assert!(
            x.iter().all(|v| v.is_finite()),
            "sample({}) = {}",
            shown(u),
            shown(&x)
        );
        assert!(
            inside(&x),
            "sample({}) = {} is outside",
            shown(u),
            shown(&x)
        );
        let density = p.pdf(&x);
        assert!(
            density.is_finite() && density >= 0.0,
            "pdf({}) = {density}",
            shown(&x)
        );
        if positive && u.iter().all(|v| (0.25..=0.75).contains(v)) {
            assert!(density > 0.0, "pdf(sample({})) = 0", shown(u));
        }
        if p.invert(&x, &mut back).is_ok() {
            assert!(
                back.iter().all(|v| (0.0..=1.0).contains(v)),
                "invert({}) = {}",
                shown(&x),
                shown(&back)
            );
        }
    }
}

/// Whether the quartiles of a one-dimensional density are distinct floats. When they are
/// not, the density is narrower than the spacing of floats where it lives (an exponential
/// of rate 5 ending at 1e161), no float carries its shape, and a sample may sit where the
/// computed density is 0; only then is a zero density at an interior sample allowed.
fn resolvable<P: Pdf1d + ?Sized>(p: &P) -> bool {
    let q = [0.25, 0.5, 0.75].map(|u| p.sample_1d(u));
    q[0] < q[1] && q[1] < q[2]
}

/// [`exercise`] for a one-dimensional density, whose domain is its closed support.
fn exercise_1d<P: Pdf1d>(p: P, random: f64) {
    let (lo, hi) = p.support();
    assert!(
        lo < hi && !lo.is_nan() && !hi.is_nan(),
        "support ({lo}, {hi})"
    );
    let positive = resolvable(&p);
    exercise(&p, &|x| lo <= x[0] && x[0] <= hi, &[random], positive);
}

/// Whether `a < b` with a density `1 / (b - a)` that is a finite normal float.
fn good_interval(a: f64, b: f64) -> bool {
    let density = 1.0 / (b - a);
    a.is_finite() && b.is_finite() && a < b && density.is_finite() && density >= f64::MIN_POSITIVE
}

/// A vector of weights: short and arbitrary, or long and constant.
fn weights() -> impl Strategy<Value = Vec<f64>> {
    prop_oneof![
        3 => prop::collection::vec(real(), 0..7),
        1 => prop::collection::vec(prop_oneof![Just(0.0), 0.0..1e3f64, Just(1e-320), Just(1e300)], 0..40),
        1 => (real(), prop::sample::select(vec![1usize, 1000, 1 << 17]))
            .prop_map(|(w, n)| vec![w; n]),
    ]
}

/// A valid one-dimensional density of every kind with ordinary parameters (for products
/// and mixtures): a kind, a left end, a width and two shape values in `[0, 1)`.
#[derive(Debug, Clone, Copy)]
struct Spec1d(usize, f64, f64, f64, f64);

impl Spec1d {
    fn build(self) -> Box<dyn Pdf1d> {
        let Spec1d(kind, a, width, s, t) = self;
        let b = a + width;
        match kind {
            0 => Box::new(UniformInterval::new(a, b).unwrap()),
            1 => Box::new(
                Exponential::new(s - 0.5, a, b)
                    .unwrap_or_else(|_| Exponential::new(1.0, a, f64::INFINITY).unwrap()),
            ),
            2 => Box::new(Linear::new(a, b, s, t + 0.01).unwrap()),
            3 => Box::new(Tent::new(a, a + s * width, b).unwrap()),
            4 => Box::new(Normal::new(a, width).unwrap()),
            5 => Box::new(TruncatedNormal::new(a, width, a - s, a + t + 0.1).unwrap()),
            6 => Box::new(PiecewiseConstant1d::new(a, b, &[s, 1.0, t]).unwrap()),
            _ => Box::new(PiecewiseLinear1d::new(&[a, a + width / 2.0, b], &[s, 1.0, t]).unwrap()),
        }
    }
}

fn spec_1d() -> impl Strategy<Value = Spec1d> {
    (
        0..8usize,
        -10.0..10.0f64,
        1e-3..10.0f64,
        0.0..1.0f64,
        0.0..1.0f64,
    )
        .prop_map(|(kind, a, width, s, t)| Spec1d(kind, a, width, s, t))
}

proptest! {
    #![proptest_config(config(256, 0x9df))]

    #[test]
    fn uniform_interval(a in real(), b in real(), r in unit()) {
        let result = UniformInterval::new(a, b);
        prop_assert_eq!(result.is_ok(), good_interval(a, b), "{:?}", result);
        check(result, &["a", "b"], |p| exercise_1d(p, r));
    }

    #[test]
    fn exponential(rate in real(), a in real(), b in prop_oneof![real(), Just(f64::INFINITY)], r in unit()) {
        let result = Exponential::new(rate, a, b);
        if !(rate.is_finite() && rate != 0.0 && a.is_finite() && a < b) {
            prop_assert!(result.is_err());
        }
        check(result, &["rate", "a", "b"], |p| exercise_1d(p, r));
    }

    #[test]
    fn linear(a in real(), b in real(), v0 in real(), v1 in real(), r in unit()) {
        let result = Linear::new(a, b, v0, v1);
        let values = v0 >= 0.0 && v1 >= 0.0 && v0.is_finite() && v1.is_finite() && v0 + v1 > 0.0;
        // The peak 2 / (b - a) must be finite too.
        let valid = good_interval(a, b) && (2.0 / (b - a)).is_finite() && values;
        prop_assert_eq!(result.is_ok(), valid, "{:?}", result);
        check(result, &["a", "b", "v0", "v1"], |p| exercise_1d(p, r));
    }

    #[test]
    fn tent(a in real(), c in real(), b in real(), r in unit()) {
        let result = Tent::new(a, c, b);
        if !(good_interval(a, b) && a <= c && c <= b) {
            prop_assert!(result.is_err());
        }
        check(result, &["a", "b", "c"], |p| exercise_1d(p, r));
        check(Tent::symmetric(a, c), &["center", "radius", "a", "b"], |p| exercise_1d(p, r));
    }

    #[test]
    fn normal(mean in real(), sd in real(), r in unit()) {
        let result = Normal::new(mean, sd);
        if !(mean.is_finite() && sd > 0.0 && sd.is_finite()) {
            prop_assert!(result.is_err());
        }
        check(result, &["mean", "sd"], |p| exercise_1d(p, r));
    }

    #[test]
    fn truncated_normal(mean in real(), sd in real(), a in real(), b in real(), r in unit()) {
        let result = TruncatedNormal::new(mean, sd, a, b);
        if !(mean.is_finite() && sd > 0.0 && sd.is_finite() && a < b) {
            prop_assert!(result.is_err());
        }
        check(result, &["mean", "sd", "[a, b]"], |p| exercise_1d(p, r));
    }

    #[test]
    fn piecewise_constant_1d(a in real(), b in real(), w in weights(), r in unit()) {
        let result = PiecewiseConstant1d::new(a, b, &w);
        if w.is_empty() || w.iter().any(|v| !(v.is_finite() && *v >= 0.0)) || !good_interval(a, b) {
            prop_assert!(result.is_err());
        }
        check(result, &["a", "b", "weights"], |p| {
            assert_eq!(p.cell_count(), w.len());
            exercise_1d(p, r)
        });
    }

    #[test]
    fn piecewise_linear_1d(
        xs in prop_oneof![
            prop::collection::vec(real(), 0..6),
            prop::collection::vec(-1e3..1e3f64, 0..6).prop_map(|mut v| { v.sort_by(f64::total_cmp); v }),
            (real(), prop::sample::select(vec![2usize, 3, 1 << 16])).prop_map(|(x0, n)| {
                (0..n).map(|i| x0 + i as f64).collect()
            }),
        ],
        values in weights(),
        r in unit(),
    ) {
        let same_length = values.len() == xs.len();
        let result = PiecewiseLinear1d::new(&xs, &values);
        if !same_length || xs.len() < 2 {
            prop_assert!(result.is_err());
        }
        check(result, &["xs", "values"], |p| exercise_1d(p, r));
    }

    #[test]
    fn piecewise_constant_2d(
        lo in [real(), real()],
        hi in [real(), real()],
        width in prop_oneof![0..4usize, Just(usize::MAX), Just(1 << 33)],
        height in prop_oneof![0..4usize, Just(usize::MAX), Just(2)],
        values in weights(),
        r in [unit(), unit()],
    ) {
        let result = PiecewiseConstant2d::new(lo, hi, width, height, &values);
        if width.checked_mul(height) != Some(values.len()) {
            prop_assert!(result.is_err());
        }
        check(result, &["width", "height", "values", "x range", "y range", "box"], |p| {
            let inside = |x: &[f64]| {
                (lo[0]..hi[0]).contains(&x[0]) && (lo[1]..hi[1]).contains(&x[1])
            };
            exercise(&p, &inside, &r, true);
        });
    }

    #[test]
    fn alias_table(w in weights(), r in unit()) {
        let result = AliasTable::new(&w);
        let valid = !w.is_empty()
            && w.iter().all(|v| v.is_finite() && *v >= 0.0)
            && w.iter().sum::<f64>() > 0.0
            && w.iter().sum::<f64>().is_finite();
        prop_assert_eq!(result.is_ok(), valid);
        check(result, &["weights"], |p| {
            let n = w.len() as f64;
            exercise(&p, &|x| x[0] >= 0.0 && x[0] < n && x[0].fract() == 0.0, &[r], true);
            // Every outcome drawn has positive probability.
            for u in PROBES.into_iter().chain([r]) {
                let (i, rest) = p.sample(u);
                assert!(p.probability(i) > 0.0 && (0.0..1.0).contains(&rest), "{i} {rest}");
            }
        });
    }

    #[test]
    fn uniform_box(
        lo in prop::collection::vec(real(), 0..4),
        hi in prop::collection::vec(real(), 0..4),
        dims in dims(),
        r in prop::collection::vec(unit(), 1..4),
    ) {
        let result = UniformBox::new(lo.clone(), hi.clone());
        if lo.len() != hi.len() || lo.is_empty() {
            prop_assert!(result.is_err());
        }
        check(result, &["lo", "hi", "box volume"], |b| {
            assert!(b.volume() > 0.0 && (1.0 / b.volume()).is_finite());
            let inside = |x: &[f64]| x.iter().zip(&lo).zip(&hi).all(|((x, l), h)| l <= x && x < h);
            exercise(&b, &inside, &r, true);
        });
        // Only sizes a box can be allocated with (a huge one is accepted, then aborts on
        // allocation like any Vec).
        if dims <= 1 << 16 || dims > isize::MAX as usize / 8 {
            let result = UniformBox::unit(dims);
            prop_assert_eq!(result.is_ok(), (1..=1 << 16).contains(&dims));
            check(result, &["dims"], |b| assert_eq!(b.volume(), 1.0));
        }
    }

    #[test]
    fn product_pdf(
        specs in prop_oneof![
            prop::collection::vec(spec_1d(), 0..5),
            // Many narrow or wide factors, whose product density overflows or underflows.
            (spec_1d(), prop::sample::select(vec![100usize, 400, 1000]))
                .prop_map(|(p, n)| vec![p; n]),
        ],
        r in prop::collection::vec(unit(), 1..5),
    ) {
        let factors: Vec<Box<dyn Pdf1d>> = specs.into_iter().map(Spec1d::build).collect();
        // The densities of many factors multiply to values that underflow away from the
        // median (which `new` checks).
        let positive = factors.len() <= 8 && factors.iter().all(|p| resolvable(p.as_ref()));
        let supports: Vec<(f64, f64)> = factors.iter().map(|p| p.support()).collect();
        let empty = factors.is_empty();
        let result = ProductPdf::new(factors);
        if empty {
            prop_assert!(result.is_err());
        }
        check(result, &["factors"], |p| {
            let inside = |x: &[f64]| x.iter().zip(&supports).all(|(x, (l, h))| l <= x && x <= h);
            exercise(&p, &inside, &r, positive);
        });
    }

    #[test]
    fn mixture(
        specs in prop::collection::vec(spec_1d(), 0..4),
        weights in prop::collection::vec(real(), 0..4),
        wrong_dims: bool,
        alpha in real(),
        r in [unit(), unit()],
    ) {
        let parts: Vec<Box<dyn Pdf1d>> = specs.into_iter().map(Spec1d::build).collect();
        let (lo, hi) = parts.iter().map(|p| p.support()).fold(
            (f64::INFINITY, f64::NEG_INFINITY),
            |(l, h), (a, b)| (l.min(a), h.max(b)),
        );
        let inside = move |x: &[f64]| lo <= x[0] && x[0] <= hi;
        let mut components: Vec<Box<dyn Pdf>> = parts.into_iter().map(|p| Box::new(p) as Box<dyn Pdf>).collect();
        if wrong_dims && !components.is_empty() {
            components.push(Box::new(UniformBox::unit(2).unwrap()));
        }
        let (n, m) = (components.len(), weights.len());
        let result = Mixture::new(components, weights);
        if n == 0 || n != m || wrong_dims {
            prop_assert!(result.is_err());
        }
        check(result, &["components", "weights"], |p| exercise(&p, &inside, &r, true));
        let proposal = Box::new(Normal::new(0.5, 0.1).unwrap());
        let domain = UniformBox::new(vec![-1.0], vec![2.0]).unwrap();
        let result = Mixture::defensive(proposal, domain, alpha);
        prop_assert_eq!(result.is_ok(), alpha > 0.0 && alpha <= 1.0);
        check(result, &["alpha"], |p| exercise(&p, &|x| x[0].is_finite(), &r, true));
    }
}

proptest! {
    #![proptest_config(config(256, 0x6e0))]

    #[test]
    fn uniform_disk(cx in real(), cy in real(), radius in real(), r in [unit(), unit()]) {
        let center = DVec2::new(cx, cy);
        let result = UniformDisk::new(center, radius);
        if !(center.is_finite() && radius > 0.0 && radius.is_finite()) {
            prop_assert!(result.is_err());
        }
        check(result, &["center", "radius"], |disk| {
            // Rounding of the centre's coordinates.
            let reach = disk.radius() + 8.0 * f64::EPSILON * (center.abs().max_element() + radius);
            let inside = |x: &[f64]| (DVec2::new(x[0], x[1]) - center).length() <= reach;
            exercise(&disk, &inside, &r, true);
        });
    }

    #[test]
    fn uniform_triangle(v in prop::collection::vec(real(), 9), r in [unit(), unit()]) {
        let [a, b, c] = [0, 3, 6].map(|i| DVec3::new(v[i], v[i + 1], v[i + 2]));
        let result = UniformTriangle::new(a, b, c);
        if !(a.is_finite() && b.is_finite() && c.is_finite()) {
            prop_assert!(result.is_err());
        }
        check(result, &["a", "b", "c", "area"], |t| {
            let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
            let slack = 1e-12 * (hi - lo).max_element();
            let inside = |x: &[f64]| {
                let x = DVec3::from_slice(x);
                x.cmpge(lo - slack).all() && x.cmple(hi + slack).all()
            };
            exercise(&t, &inside, &r, true);
        });
    }

    #[test]
    fn spherical_cap(
        cos in real(),
        theta in real(),
        axis in prop::collection::vec(real(), 3),
        r in [unit(), unit()],
    ) {
        let axis = DVec3::from_slice(&axis);
        let unit_length = |x: &[f64]| (DVec3::from_slice(x).length() - 1.0).abs() < 1e-12;
        let results = [
            SphericalCap::new(cos),
            SphericalCap::around(axis, cos),
            SphericalCap::with_angle(theta),
            SphericalCap::around_with_angle(axis, theta),
        ];
        for result in results {
            check(result, &["cos_theta_max", "theta_max", "axis"], |cap| {
                assert!(cap.solid_angle() > 0.0 && (1.0 / cap.solid_angle()).is_finite());
                exercise(&cap, &unit_length, &r, true);
            });
        }
        prop_assert_eq!(SphericalCap::new(cos).is_ok(), (-1.0..1.0).contains(&cos));
    }

    #[test]
    fn fixed_warps(r in [unit(), unit()]) {
        let unit_length = |x: &[f64]| (DVec3::from_slice(x).length() - 1.0).abs() < 1e-12;
        let upper = |x: &[f64]| unit_length(x) && x[2] >= 0.0;
        exercise(&UniformSphere, &unit_length, &r, true);
        exercise(&UniformHemisphere, &upper, &r, true);
        exercise(&CosineHemisphere, &upper, &r, true);
        exercise(&UniformDisk::unit(), &|x: &[f64]| x[0].hypot(x[1]) <= 1.0, &r, true);
    }
}
