//! Mixtures: they integrate to one, samples follow them, the component choice is exact at
//! the edges, and the defensive mixture obeys Hesterberg's bound.

use super::*;

// Mixture

/// A test density with more canonical dimensions than dimensions: `x = u_0 + u_1`, the
/// triangular density on [0, 2).
struct SumOfTwoUniforms;

impl Pdf for SumOfTwoUniforms {
    fn canonical_dims(&self) -> usize {
        2
    }
    fn dims(&self) -> usize {
        1
    }
    fn sample(&self, u: &[f64], x: &mut [f64]) {
        x[0] = u[0] + u[1];
    }
    fn pdf(&self, x: &[f64]) -> f64 {
        match x[0] {
            t if (0.0..1.0).contains(&t) => t,
            t if (1.0..2.0).contains(&t) => 2.0 - t,
            _ => 0.0,
        }
    }
}

fn triangle_cdf(x: f64) -> f64 {
    let x = x.clamp(0.0, 2.0);
    if x < 1.0 {
        0.5 * x * x
    } else {
        1.0 - 0.5 * (2.0 - x) * (2.0 - x)
    }
}

/// A 1-D mixture on [0, 2) with exact cdf: components with unnormalised weights 3, 5, 2, 1.
fn mixture_1d() -> (Mixture, impl Fn(f64) -> f64) {
    let exponential = Exponential::new(5.0, 0.0, 2.0).unwrap();
    let normal = TruncatedNormal::new(1.2, 0.1, 0.0, 2.0).unwrap();
    let linear = Linear::new(0.0, 2.0, 1.0, 0.0).unwrap();
    let mixture = Mixture::new(
        vec![
            Box::new(exponential),
            Box::new(normal),
            Box::new(linear),
            Box::new(SumOfTwoUniforms),
        ],
        vec![3.0, 5.0, 2.0, 1.0],
    )
    .unwrap();
    let cdf = move |x: f64| {
        (3.0 * exponential.invert_1d(x)
            + 5.0 * normal.invert_1d(x)
            + 2.0 * linear.invert_1d(x)
            + triangle_cdf(x))
            / 11.0
    };
    (mixture, cdf)
}

#[test]
fn mixtures_integrate_to_one() {
    let (mixture, _) = mixture_1d();
    assert_eq!((mixture.dims(), mixture.canonical_dims()), (1, 2));
    let weights = mixture.weights();
    let expected = [3.0 / 11.0, 5.0 / 11.0, 2.0 / 11.0, 1.0 / 11.0];
    for (w, e) in weights.iter().zip(expected) {
        assert!((w - e).abs() < 1e-16);
    }
    // Panels are 1/200 wide, so the kink of the triangle at 1 is a panel edge.
    let total = integrate(|x| mixture.pdf(&[x]), 0.0, 2.0, 400);
    assert!((total - 1.0).abs() < 1e-12, "1-D mixture: {total}");

    let (mixture_2d, lo, hi) = mixture_2d();
    let total = integrate_2d(|x| mixture_2d.pdf(x), lo, hi, 24);
    assert!((total - 1.0).abs() < 1e-12, "2-D mixture: {total}");

    let defensive = Mixture::defensive(
        Box::new(TruncatedNormal::new(0.3, 0.05, -1.0, 3.0).unwrap()),
        UniformBox::new(vec![-1.0], vec![3.0]).unwrap(),
        0.1,
    )
    .unwrap();
    let total = integrate(|x| defensive.pdf(&[x]), -1.0, 3.0, 400);
    assert!((total - 1.0).abs() < 1e-12, "defensive: {total}");
}

/// Chi-square test of 1-D samples against exact cell probabilities from a cdf.
fn chi_square_1d(pdf: &dyn Pdf, cdf: &dyn Fn(f64) -> f64, lo: f64, hi: f64, seed: u64) -> f64 {
    const SAMPLES: usize = 200_000;
    const CELLS: usize = 40;
    let edge = |k: usize| lo + (hi - lo) * k as f64 / CELLS as f64;
    let expected: Vec<f64> = (0..CELLS)
        .map(|k| SAMPLES as f64 * (cdf(edge(k + 1)) - cdf(edge(k))))
        .collect();
    let dims = pdf.canonical_dims();
    let sampler = Independent::new(dims, seed).unwrap();
    let mut points = Points::new(dims, SAMPLES).unwrap();
    sampler.fill(0, &mut points).unwrap();
    let mut observed = vec![0u64; CELLS];
    let (mut u, mut x) = (vec![0.0; dims], [0.0]);
    for i in 0..SAMPLES {
        points.copy_point(i, &mut u);
        pdf.sample(&u, &mut x);
        assert!(pdf.pdf(&x) > 0.0, "sample {x:?} where the pdf is zero");
        let cell = ((x[0] - lo) / (hi - lo) * CELLS as f64) as usize;
        observed[cell.min(CELLS - 1)] += 1;
    }
    chi_square_goodness_of_fit(&observed, &expected, 5.0)
        .unwrap()
        .p_value
}

/// A 2-D mixture on [0, 1] x [-1, 2) of a product density and the uniform box.
fn mixture_2d() -> (Mixture, [f64; 2], [f64; 2]) {
    let product = ProductPdf::new(vec![
        Box::new(Linear::new(0.0, 1.0, 1.0, 3.0).unwrap()),
        Box::new(TruncatedNormal::new(0.0, 0.5, -1.0, 2.0).unwrap()),
    ])
    .unwrap();
    let uniform = UniformBox::new(vec![0.0, -1.0], vec![1.0, 2.0]).unwrap();
    let mixture = Mixture::new(vec![Box::new(product), Box::new(uniform)], vec![0.7, 0.3]).unwrap();
    (mixture, [0.0, -1.0], [1.0, 2.0])
}

#[test]
fn mixture_samples_follow_the_density() {
    let (mixture, cdf) = mixture_1d();
    let p = chi_square_1d(&mixture, &cdf, 0.0, 2.0, 8000);
    assert!(p > 1e-5, "1-D mixture: p = {p}");

    let proposal = Exponential::new(-20.0, 0.0, 1.0).unwrap();
    let defensive =
        Mixture::defensive(Box::new(proposal), UniformBox::unit(1).unwrap(), 0.25).unwrap();
    let cdf = |x: f64| 0.25 * x.clamp(0.0, 1.0) + 0.75 * proposal.invert_1d(x);
    let p = chi_square_1d(&defensive, &cdf, 0.0, 1.0, 8001);
    assert!(p > 1e-5, "defensive mixture: p = {p}");

    // 2-D: 8 x 8 cells, probabilities from the factors' cdfs.
    const SAMPLES: usize = 100_000;
    const GRID: usize = 8;
    let (mixture, lo, hi) = mixture_2d();
    let linear = Linear::new(0.0, 1.0, 1.0, 3.0).unwrap();
    let normal = TruncatedNormal::new(0.0, 0.5, -1.0, 2.0).unwrap();
    let edge = |d: usize, k: usize| lo[d] + (hi[d] - lo[d]) * k as f64 / GRID as f64;
    let mut expected = vec![0.0; GRID * GRID];
    for iy in 0..GRID {
        for ix in 0..GRID {
            let px = linear.invert_1d(edge(0, ix + 1)) - linear.invert_1d(edge(0, ix));
            let py = normal.invert_1d(edge(1, iy + 1)) - normal.invert_1d(edge(1, iy));
            let cell_area = 1.0 / (GRID * GRID) as f64;
            expected[ix + GRID * iy] = SAMPLES as f64 * (0.7 * px * py + 0.3 * cell_area);
        }
    }
    let sampler = Independent::new(2, 8002).unwrap();
    let mut points = Points::new(2, SAMPLES).unwrap();
    sampler.fill(0, &mut points).unwrap();
    let mut observed = vec![0u64; GRID * GRID];
    let (mut u, mut x) = ([0.0; 2], [0.0; 2]);
    for i in 0..SAMPLES {
        points.copy_point(i, &mut u);
        mixture.sample(&u, &mut x);
        let cell = |d: usize| {
            let t = ((x[d] - lo[d]) / (hi[d] - lo[d]) * GRID as f64) as usize;
            t.min(GRID - 1)
        };
        observed[cell(0) + GRID * cell(1)] += 1;
    }
    let fit = chi_square_goodness_of_fit(&observed, &expected, 5.0).unwrap();
    assert!(fit.p_value > 1e-5, "2-D mixture: {fit:?}");
}

#[test]
fn mixture_component_choice_is_exact_at_the_edges() {
    let interval = |a: f64| -> Box<dyn Pdf> { Box::new(UniformInterval::new(a, a + 1.0).unwrap()) };
    // Zero weights first, between and last: never chosen, and their pdf never read.
    let mixture = Mixture::new(
        vec![
            interval(0.0),
            interval(10.0),
            interval(20.0),
            interval(30.0),
            interval(40.0),
        ],
        vec![0.0, 1.0, 0.0, 3.0, 0.0],
    )
    .unwrap();
    let mut x = [0.0];
    for (u0, component, expected_x) in [
        (0.0, 1, 10.0),
        (0.125, 1, 10.5),
        (0.25 - f64::EPSILON / 8.0, 1, 11.0),
        (0.25, 3, 30.0),
        (0.625, 3, 30.5),
        (ONE_BELOW, 3, 31.0),
    ] {
        assert_eq!(
            mixture.sample_with_component(&[u0], &mut x),
            component,
            "u0 = {u0}"
        );
        assert!((x[0] - expected_x).abs() < 1e-14, "u0 = {u0}: x = {}", x[0]);
        // Inside the component's half-open interval [10 k, 10 k + 1).
        let start = 10.0 * component as f64;
        assert!(
            (start..start + 1.0).contains(&x[0]),
            "u0 = {u0}: x = {} outside",
            x[0]
        );
    }
    assert_eq!(mixture.pdf(&[20.5]), 0.0);
    assert_eq!(mixture.pdf(&[30.5]), 0.75);
    // invert does not exist for a mixture.
    assert_eq!(
        field(mixture.invert(&[10.5], &mut [0.0]).unwrap_err()),
        "invert"
    );
    // Weights near the top of the f64 range normalise without overflow.
    let huge = Mixture::new(vec![interval(0.0), interval(1.0)], vec![f64::MAX, f64::MAX]).unwrap();
    assert_eq!(huge.weights(), &[0.5, 0.5]);
}

/// Hesterberg's bound: importance sampling from `alpha * uniform + (1 - alpha) * proposal` has
/// variance at most `sigma_uniform^2 / alpha + (1/alpha - 1) F^2`, however bad the proposal;
/// here the proposal alone (a rate-30 exponential, whose density falls to e^-30 of its peak
/// where f is largest) is far above that bound. Exact variances by quadrature.
#[test]
fn defensive_mixture_obeys_hesterbergs_bound() {
    let proposal = || Exponential::new(30.0, 0.0, 1.0).unwrap();
    let f = |x: f64| sharp_times_broad(&[x]);
    let exact = sharp_times_broad_integral();
    let second_moment = |pdf: &dyn Pdf| integrate(|x| f(x).powi(2) / pdf.pdf(&[x]), 0.0, 1.0, 400);
    let v_uniform = second_moment(&UniformInterval::new(0.0, 1.0).unwrap()) - exact * exact;
    let v_proposal = second_moment(&proposal()) - exact * exact;
    for alpha in [0.05, 0.2, 0.5, 1.0] {
        let defensive =
            Mixture::defensive(Box::new(proposal()), UniformBox::unit(1).unwrap(), alpha).unwrap();
        let v = second_moment(&defensive) - exact * exact;
        let bound = v_uniform / alpha + (1.0 / alpha - 1.0) * exact * exact;
        assert!(v <= bound * (1.0 + 1e-12), "alpha {alpha}: {v} > {bound}");
        assert!(
            v_proposal > 1e3 * bound,
            "alpha {alpha}: proposal {v_proposal}"
        );
    }
    // The defensive estimator realises that variance.
    let defensive =
        Mixture::defensive(Box::new(proposal()), UniformBox::unit(1).unwrap(), 0.2).unwrap();
    let v = second_moment(&defensive) - exact * exact;
    let estimator = ImportanceEstimator::new(sharp_times_broad, defensive);
    let (s2, se) = variance_and_its_se(&contributions(&estimator, 200_000, 8100));
    assert!(
        (s2 - v).abs() <= 5.0 * se,
        "sample variance {s2} vs exact {v}"
    );
}

proptest! {
    #![proptest_config(config(512, 0x313))]

    /// Defensive mixtures keep at least alpha / volume of density everywhere on the domain,
    /// and every sample of a mixture lands where its density is positive.
    #[test]
    fn defensive_mixtures_are_bounded_below(
        alpha in 0.01..=1.0f64,
        x in 0.0..1.0f64,
        y in 0.0..2.0f64,
        u in prop::array::uniform2(0.0..1.0f64),
    ) {
        let proposal = ProductPdf::new(vec![
            Box::new(Exponential::new(40.0, 0.0, 1.0).unwrap()),
            Box::new(TruncatedNormal::new(0.1, 0.02, 0.0, 2.0).unwrap()),
        ])
        .unwrap();
        let domain = UniformBox::new(vec![0.0, 0.0], vec![1.0, 2.0]).unwrap();
        let p = Mixture::defensive(Box::new(proposal), domain, alpha).unwrap();
        prop_assert!(p.pdf(&[x, y]) >= alpha / 2.0 * (1.0 - 1e-15));
        let mut s = [0.0; 2];
        p.sample(&u, &mut s);
        prop_assert!(p.pdf(&s) > 0.0, "sample {:?} of u = {:?}", s, u);
    }
}
