//! Exact variances by quadrature (1-D problems on [0, 1]): Veach's bound, the optimality of
//! the balance heuristic, the sharp-times-broad case, and one-sample balance as sampling the
//! mixture.

use super::*;

// Exact variances by quadrature (1-D problems on [0, 1])

/// Panels for the variance quadrature; a second pass with twice as many gives the tolerance
/// (the maximum and cutoff weights jump where two densities cross, which the panels do not
/// resolve exactly).
const VARIANCE_PANELS: usize = 2000;

/// A weighting as a function of the technique, `x` and the `q_j`.
type Weight<'a> = &'a dyn Fn(usize, f64, &[f64]) -> f64;
type OwnedWeight = Box<dyn Fn(usize, f64, &[f64]) -> f64>;

/// `q_j(x) = scale_j p_j(x)` for every technique.
fn densities(pdfs: &[Box<dyn Pdf>], scales: &[f64], x: f64) -> Vec<f64> {
    pdfs.iter()
        .zip(scales)
        .map(|(p, s)| s * p.pdf(&[x]))
        .collect()
}

/// `(value, tolerance)` of the quadrature of `term` on [0, 1], from two resolutions.
fn quadrature_with_tolerance(term: impl Fn(f64) -> f64) -> (f64, f64) {
    let coarse = integrate(&term, 0.0, 1.0, VARIANCE_PANELS);
    let fine = integrate(&term, 0.0, 1.0, 2 * VARIANCE_PANELS);
    (fine, 2.0 * (fine - coarse).abs() + 1e-13 * fine.abs())
}

/// Exact variance of Veach's multi-sample estimator (one contribution = one group):
/// `V = sum_i [ integral w_i^2 f^2 / (n_i p_i) - (integral w_i f)^2 / n_i ]`, and its tolerance.
fn multi_sample_variance(
    f: Integrand,
    pdfs: &[Box<dyn Pdf>],
    n: &[usize],
    weight: Weight,
) -> (f64, f64) {
    let scales: Vec<f64> = n.iter().map(|&k| k as f64).collect();
    let (mut variance, mut tolerance) = (0.0, 0.0);
    for (i, &ni) in scales.iter().enumerate() {
        let (second, e2) = quadrature_with_tolerance(|x| {
            let q = densities(pdfs, &scales, x);
            let w = weight(i, x, &q);
            if w == 0.0 {
                0.0
            } else {
                w * w * f(&[x]).powi(2) / q[i]
            }
        });
        let (first, e1) = quadrature_with_tolerance(|x| {
            let q = densities(pdfs, &scales, x);
            weight(i, x, &q) * f(&[x])
        });
        variance += second - first * first / ni;
        tolerance += e2 + 2.0 * first.abs() * e1 / ni;
    }
    (variance, tolerance)
}

/// Exact variance of the one-sample estimator: `sum_i integral w_i^2 f^2 / (c_i p_i) - F^2`.
fn one_sample_variance(
    f: Integrand,
    pdfs: &[Box<dyn Pdf>],
    c: &[f64],
    exact: f64,
    weight: Weight,
) -> (f64, f64) {
    let (mut second, mut tolerance) = (0.0, 0.0);
    for i in 0..pdfs.len() {
        let (value, e) = quadrature_with_tolerance(|x| {
            let q = densities(pdfs, c, x);
            let w = weight(i, x, &q);
            if w == 0.0 {
                0.0
            } else {
                w * w * f(&[x]).powi(2) / q[i]
            }
        });
        second += value;
        tolerance += e;
    }
    (second - exact * exact, tolerance)
}

/// Named weightings for the variance comparisons: the heuristics (through the library), fixed
/// shares, every technique alone, and a share that moves with x.
fn weightings(t: usize) -> Vec<(String, OwnedWeight)> {
    let mut list: Vec<(String, OwnedWeight)> = Vec::new();
    for h in heuristics() {
        list.push((
            format!("{h:?}"),
            Box::new(move |i: usize, _: f64, q: &[f64]| h.weight(i, q)),
        ));
    }
    list.push((
        "fixed shares".into(),
        Box::new(move |_: usize, _: f64, _: &[f64]| 1.0 / t as f64),
    ));
    for k in 0..t {
        list.push((
            format!("technique {k} alone"),
            Box::new(move |i: usize, _: f64, _: &[f64]| if i == k { 1.0 } else { 0.0 }),
        ));
    }
    list.push((
        "moving share".into(),
        Box::new(move |i: usize, x: f64, _: &[f64]| {
            let first = 0.1 + 0.8 * x;
            if i == 0 {
                first
            } else {
                (1.0 - first) / (t - 1) as f64
            }
        }),
    ));
    list
}

/// Veach's Theorem 9.2: for any weighting w,
/// `V[F_balance] <= V[F_w] + (1/min_i n_i - 1/sum_i n_i) F^2`, here on exact variances.
#[test]
fn balance_heuristic_obeys_veachs_bound() {
    let mut cases: Vec<(Problem, Vec<usize>)> = Vec::new();
    for problem in problems()
        .into_iter()
        .filter(|p| p.name != "2-D exponential")
    {
        let shapes: Vec<Vec<usize>> = if (problem.techniques)().len() == 2 {
            vec![vec![1, 1], vec![1, 3], vec![4, 2]]
        } else {
            vec![vec![1, 1, 1], vec![2, 1, 3]]
        };
        cases.extend(shapes.into_iter().map(|n| (problem, n)));
    }
    let mut balance_loses_somewhere = false;
    for (problem, n) in &cases {
        let pdfs = (problem.techniques)();
        let balance = |i: usize, _: f64, q: &[f64]| MisHeuristic::Balance.weight(i, q);
        let (v_balance, tol_balance) = multi_sample_variance(problem.f, &pdfs, n, &balance);
        let min_n = *n.iter().min().unwrap() as f64;
        let total_n: f64 = n.iter().sum::<usize>() as f64;
        let slack = (1.0 / min_n - 1.0 / total_n) * problem.exact * problem.exact;
        for (name, w) in weightings(pdfs.len()) {
            let (v, tol) = multi_sample_variance(problem.f, &pdfs, n, w.as_ref());
            assert!(
                v_balance <= v + slack + tol + tol_balance,
                "{} n = {n:?}: balance {v_balance} > {name} {v} + slack {slack}",
                problem.name
            );
            balance_loses_somewhere |= v_balance > v + tol + tol_balance;
        }
    }
    // The slack term is needed: where one technique is perfect (f = 1.5 p_0), that technique
    // alone has zero variance and the balance heuristic does not.
    assert!(balance_loses_somewhere);
}

/// The quadrature variances are the variances of the library's estimators: sample variances
/// of 200,000 contributions agree within 5 standard errors.
#[test]
fn exact_variances_match_the_estimators() {
    for problem in problems()
        .into_iter()
        .filter(|p| p.name != "2-D exponential")
    {
        let t = (problem.techniques)().len();
        let n = counts(t);
        let c = probabilities(t);
        for (k, h) in heuristics().into_iter().enumerate() {
            let w = move |i: usize, _: f64, q: &[f64]| h.weight(i, q);
            let pdfs = (problem.techniques)();
            let (exact, tol) = multi_sample_variance(problem.f, &pdfs, &n, &w);
            let mis = MultiSampleMis::new(problem.f, pdfs.into_iter().zip(n.clone()).collect(), h)
                .unwrap();
            let (s2, se) = variance_and_its_se(&contributions(&mis, 200_000, 5000 + k as u64));
            assert!(
                (s2 - exact).abs() <= 5.0 * se + tol,
                "{} multi-sample {h:?}: sample variance {s2} vs exact {exact} (se {se:e})",
                problem.name
            );
            let pdfs = (problem.techniques)();
            let (exact, tol) = one_sample_variance(problem.f, &pdfs, &c, problem.exact, &w);
            let mis = OneSampleMis::new(problem.f, pdfs, c.clone(), h).unwrap();
            let (s2, se) = variance_and_its_se(&contributions(&mis, 200_000, 5100 + k as u64));
            assert!(
                (s2 - exact).abs() <= 5.0 * se + tol,
                "{} one-sample {h:?}: sample variance {s2} vs exact {exact} (se {se:e})",
                problem.name
            );
        }
    }
}

/// In the one-sample model the balance heuristic is optimal: `E[F^2] = sum_i integral w_i^2 f^2
/// / q_i` is minimised pointwise by `w_i = q_i / sum_j q_j` (Veach 1997, chapter 9).
#[test]
fn balance_heuristic_is_optimal_for_one_sample_mis() {
    for problem in problems()
        .into_iter()
        .filter(|p| p.name != "2-D exponential")
    {
        let pdfs = (problem.techniques)();
        let c = probabilities(pdfs.len());
        let balance = |i: usize, _: f64, q: &[f64]| MisHeuristic::Balance.weight(i, q);
        let (v_balance, tol_balance) =
            one_sample_variance(problem.f, &pdfs, &c, problem.exact, &balance);
        for (name, w) in weightings(pdfs.len()) {
            let (v, tol) = one_sample_variance(problem.f, &pdfs, &c, problem.exact, w.as_ref());
            assert!(
                v_balance <= v + tol + tol_balance,
                "{}: one-sample balance {v_balance} > {name} {v}",
                problem.name
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The classic case: a sharp lobe times a broad lobe

/// f = g h with g a sharp lobe (rate 10) on a floor and h a broad linear lobe; technique 0
/// samples the lobe of g, technique 1 samples h. Sampling the lobe alone meets the floor's
/// contribution far from the lobe, where its density is e^-10 of its peak (rare, huge
/// contributions); sampling h alone rarely lands in the lobe. MIS with one sample of each gets
/// the best of both. Variances are per group of two samples (each single technique gets two).
#[test]
fn mis_beats_both_techniques_on_sharp_times_broad() {
    let pdfs = sharp_techniques();
    let exact_f = sharp_times_broad_integral();
    let variance = |w: Weight, n: &[usize]| multi_sample_variance(sharp_times_broad, &pdfs, n, w);
    let lobe_alone = |i: usize, _: f64, _: &[f64]| if i == 0 { 1.0 } else { 0.0 };
    let broad_alone = |i: usize, _: f64, _: &[f64]| if i == 1 { 1.0 } else { 0.0 };
    let (v_lobe, _) = variance(&lobe_alone, &[2, 1]);
    let (v_broad, _) = variance(&broad_alone, &[1, 2]);
    for h in [MisHeuristic::Balance, MisHeuristic::power(2.0).unwrap()] {
        let (v_mis, tol) = variance(&move |i: usize, _: f64, q: &[f64]| h.weight(i, q), &[1, 1]);
        // A margin of 10 in variance: both single techniques need ten times the samples.
        assert!(
            10.0 * (v_mis + tol) < v_broad.min(v_lobe),
            "{h:?}: MIS {v_mis} vs lobe {v_lobe}, broad {v_broad}"
        );
        // The estimator realises that variance (its contributions are bounded, so the sample
        // variance is reliable) ...
        let mis = MultiSampleMis::new(
            sharp_times_broad,
            sharp_techniques().into_iter().zip([1, 1]).collect(),
            h,
        )
        .unwrap();
        let values = contributions(&mis, 1 << 18, 6000);
        let (s2, se) = variance_and_its_se(&values);
        assert!(
            (s2 - v_mis).abs() <= 5.0 * se + tol,
            "{h:?}: {s2} vs {v_mis}"
        );
        assert!(
            (summary(&values).mean() - exact_f).abs() <= 4.5 * (s2 / values.len() as f64).sqrt()
        );
        // ... and beats the broad technique's measured variance far beyond sampling noise.
        // (The lobe technique's variance comes from contributions of probability about e^-10
        // and size about e^10, so its sample variance is unreliable; its exact value is above.)
        let broad = MultiSampleMis::new(
            sharp_times_broad,
            vec![(Box::new(broad_lobe()) as Box<dyn Pdf>, 2)],
            MisHeuristic::Balance,
        )
        .unwrap();
        let (s2_broad, se_broad) = variance_and_its_se(&contributions(&broad, 1 << 18, 6001));
        assert!(
            (s2_broad - v_broad).abs() <= 5.0 * se_broad,
            "{s2_broad} vs {v_broad}"
        );
        assert!(
            s2_broad - 5.0 * se_broad > 10.0 * (s2 + 5.0 * se),
            "{h:?}: broad {s2_broad} +- {se_broad} vs MIS {s2} +- {se}"
        );
    }
    // The lobe technique's variance is enormous relative to the integral (F^2 is about 0.37).
    assert!(v_lobe > 50.0 * exact_f * exact_f, "{v_lobe}");
}

// ---------------------------------------------------------------------------------------------
// One-sample MIS with the balance heuristic is sampling the mixture

#[test]
fn one_sample_balance_is_importance_sampling_the_mixture() {
    for (p, problem) in problems().iter().enumerate() {
        let t = (problem.techniques)().len();
        let c = probabilities(t);
        let mis = OneSampleMis::new(
            problem.f,
            (problem.techniques)(),
            c.clone(),
            MisHeuristic::Balance,
        )
        .unwrap();
        let mixture = Mixture::new((problem.techniques)(), c).unwrap();
        let importance = ImportanceEstimator::new(problem.f, mixture);
        assert_eq!(mis.canonical_dims(), importance.canonical_dims());
        let a = contributions(&mis, 20_000, 7000 + p as u64);
        let b = contributions(&importance, 20_000, 7000 + p as u64);
        for (ya, yb) in a.iter().zip(&b) {
            assert!(
                (ya - yb).abs() <= 1e-13 * yb.abs(),
                "{}: one-sample {ya} vs mixture {yb}",
                problem.name
            );
        }
    }
}
