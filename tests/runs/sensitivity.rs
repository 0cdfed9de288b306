//! Sobol' indices of the library (`src/sensitivity/`): intervals that cover the exact indices
//! of the classic test models at the nominal rate and are not much wider than the error,
//! Gaussian inputs, groups, second order and vector models against closed forms.

use mcint::measure::{Factorization, Gaussian, Measure};
use mcint::sensitivity::{ExactIndices, Indices, SobolDesign};
use mcint::testfns::{Ishigami, SobolGFunction, TestFunction};
use mcint::{Estimate, Tolerance};

const SEEDS: u64 = 200;
/// 95% intervals over 200 seeds: at 95% coverage the count is 190 +- 3.1, and 186 is what
/// the issue asks of every index.
const LEAST_COVERED: usize = 186;
/// The most the median half-width may exceed the median actual error: an honest t interval
/// of 8 replicates is about 3.4 times it.
const MOST_WIDTH_RATIO: f64 = 5.0;

/// `(covered, median half-width, median |error|)` of one index over the seeds.
struct IndexRecord {
    name: String,
    covered: usize,
    half_widths: Vec<f64>,
    errors: Vec<f64>,
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Runs the default design of `model` over `inputs` for every seed and checks every first
/// order and total index against `exact`.
fn check_coverage<M: Measure + 'static>(
    label: &str,
    inputs: impl Fn() -> M,
    model: impl Fn(&[f64]) -> f64 + Send + Sync + Clone + 'static,
    exact: &ExactIndices,
) {
    let factors = exact.first_order.len();
    let mut records: Vec<IndexRecord> = (0..2 * factors)
        .map(|k| IndexRecord {
            name: if k < factors {
                format!("S{}", k + 1)
            } else {
                format!("ST{}", k - factors + 1)
            },
            covered: 0,
            half_widths: Vec::new(),
            errors: Vec::new(),
        })
        .collect();
    let design = SobolDesign::new(inputs()).unwrap();
    for seed in 0..SEEDS {
        let run = design
            .integrator(model.clone())
            .unwrap()
            .seed(seed)
            .run()
            .unwrap();
        let indices = design.indices(&run).unwrap();
        let estimates = indices.first_order().iter().chain(indices.total());
        let truths = exact.first_order.iter().chain(&exact.total);
        for ((record, estimate), truth) in records.iter_mut().zip(estimates).zip(truths) {
            let half_width = estimate.half_width(0.95).unwrap().unwrap();
            let error = (estimate.mean - truth).abs();
            record.covered += usize::from(error <= half_width);
            record.half_widths.push(half_width);
            record.errors.push(error);
        }
    }
    let mut failures = Vec::new();
    for record in &mut records {
        let ratio = median(&mut record.half_widths) / median(&mut record.errors);
        if record.covered < LEAST_COVERED || ratio > MOST_WIDTH_RATIO {
            failures.push(format!(
                "{} covered {}/{SEEDS}, median half-width / median error {ratio:.2}",
                record.name, record.covered
            ));
        }
    }
    assert!(failures.is_empty(), "{label}: {failures:?}");
}

#[test]
fn ishigami_intervals_cover_and_fit_the_error() {
    for (a, b) in [(7.0, 0.1), (5.0, 0.05), (2.0, 0.3)] {
        let model = Ishigami::new(a, b).unwrap();
        check_coverage(
            &format!("Ishigami a = {a}, b = {b}"),
            || model.inputs(),
            move |x: &[f64]| model.eval(x),
            &model.exact_indices(),
        );
    }
}

#[test]
fn sobol_g_intervals_cover_and_fit_the_error() {
    for weights in [
        vec![0.0, 0.5, 3.0, 9.0, 99.0, 99.0],
        vec![0.0, 0.0, 0.0, 0.0],
        vec![1.0, 2.0, 5.0, 10.0, 20.0],
    ] {
        let g = SobolGFunction::new(weights.clone()).unwrap();
        let d = weights.len();
        let exact = g.exact_indices();
        check_coverage(
            &format!("g-function a = {weights:?}"),
            || mcint::measure::Uniform::unit(d).unwrap(),
            move |x: &[f64]| g.eval(x),
            &exact,
        );
    }
}

/// Within `z` standard errors (and the error bar exists).
fn near(estimate: &Estimate, exact: f64, z: f64) -> bool {
    (estimate.mean - exact).abs() <= z * estimate.std_error.unwrap()
}

/// `y = c . x` with independent Gaussian inputs: `S_i = ST_i = c_i^2 s_i^2 / sum c_j^2 s_j^2`.
#[test]
fn linear_model_of_independent_gaussians_matches_its_closed_form() {
    let (c, s) = ([1.0, -2.0, 0.5], [1.0, 0.5, 3.0]);
    let covariance = vec![
        s[0] * s[0],
        0.0,
        0.0,
        0.0,
        s[1] * s[1],
        0.0,
        0.0,
        0.0,
        s[2] * s[2],
    ];
    let inputs = Gaussian::new(vec![1.0, 2.0, -1.0], covariance, Factorization::Cholesky).unwrap();
    let design = SobolDesign::new(inputs).unwrap();
    let run = design
        .integrator(move |x: &[f64]| c.iter().zip(x).map(|(c, x)| c * x).sum())
        .unwrap()
        .seed(11)
        .run()
        .unwrap();
    let indices = design.indices(&run).unwrap();
    let parts: Vec<f64> = (0..3).map(|i| (c[i] * s[i]).powi(2)).collect();
    let variance: f64 = parts.iter().sum();
    assert!(near(&indices.outputs[0].variance, variance, 5.0));
    for (i, part) in parts.iter().enumerate() {
        let exact = part / variance;
        assert!(
            near(&indices.first_order()[i], exact, 5.0),
            "S{i}: {:?}",
            indices.first_order()[i]
        );
        assert!(
            near(&indices.total()[i], exact, 5.0),
            "ST{i}: {:?}",
            indices.total()[i]
        );
    }
}

/// Correlated Gaussians by Cholesky: the indices are those of the independent normals `z`
/// with `x = mu + L z`, so `y = c . x` has `S_i = (L' c)_i^2 / |L' c|^2`.
#[test]
fn linear_model_of_correlated_gaussians_gives_the_indices_of_its_cholesky_normals() {
    let (rho, c) = (0.6_f64, [1.0, 1.0]);
    let inputs = Gaussian::new(
        vec![0.0; 2],
        vec![1.0, rho, rho, 1.0],
        Factorization::Cholesky,
    )
    .unwrap();
    // L = [[1, 0], [rho, sqrt(1 - rho^2)]], so L' c = (1 + rho, sqrt(1 - rho^2)).
    let lc = [c[0] + rho * c[1], (1.0 - rho * rho).sqrt() * c[1]];
    let norm = lc[0] * lc[0] + lc[1] * lc[1];
    let design = SobolDesign::new(inputs).unwrap();
    let run = design
        .integrator(move |x: &[f64]| c[0] * x[0] + c[1] * x[1])
        .unwrap()
        .seed(5)
        .run()
        .unwrap();
    let indices = design.indices(&run).unwrap();
    for (estimate, part) in indices.first_order().iter().zip(lc) {
        assert!(
            near(estimate, part * part / norm, 5.0),
            "{:?}",
            indices.first_order()
        );
    }
}

/// Groups and second order on the g-function, whose variance is a product: a group's first
/// order index is `(prod_{i in G} (1 + V_i) - 1) / V`, and `S_ij = V_i V_j / V`.
#[test]
fn groups_and_second_order_of_the_g_function_match_its_closed_form() {
    let g = SobolGFunction::new(vec![0.0, 1.0, 4.5, 9.0]).unwrap();
    let partial: Vec<f64> = g
        .a()
        .iter()
        .map(|a| 1.0 / (3.0 * (1.0 + a).powi(2)))
        .collect();
    let variance = partial.iter().map(|v| 1.0 + v).product::<f64>() - 1.0;
    let unit = || mcint::measure::Uniform::unit(4).unwrap();

    let grouped = SobolDesign::new(unit())
        .unwrap()
        .groups(vec![vec![0, 1], vec![2, 3]])
        .unwrap();
    let model = move |x: &[f64]| g.eval(x);
    let run = grouped
        .integrator(model.clone())
        .unwrap()
        .seed(3)
        .run()
        .unwrap();
    let indices = grouped.indices(&run).unwrap();
    for (k, group) in [[0, 1], [2, 3]].iter().enumerate() {
        let closed = (1.0 + partial[group[0]]) * (1.0 + partial[group[1]]) - 1.0;
        assert!(
            near(&indices.first_order()[k], closed / variance, 5.0),
            "group {k}: {:?}",
            indices.first_order()[k]
        );
    }

    let pairs = SobolDesign::new(unit()).unwrap().second_order(true);
    let run = pairs.integrator(model).unwrap().seed(4).run().unwrap();
    let indices = pairs.indices(&run).unwrap();
    assert_eq!(indices.outputs[0].second_order.len(), 6);
    for pair in &indices.outputs[0].second_order {
        let (i, j) = pair.factors;
        let exact = partial[i] * partial[j] / variance;
        assert!(
            near(&pair.index, exact, 5.0),
            "S{i}{j}: {:?} vs {exact}",
            pair.index
        );
    }
}

/// A vector model gets the indices of each output over the same points, equal to the
/// indices of each output run alone with the same seed.
#[test]
fn vector_model_indices_are_those_of_each_output() {
    let ishigami = Ishigami::new(7.0, 0.1).unwrap();
    let design = SobolDesign::new(ishigami.inputs()).unwrap();
    let model = move |x: &[f64], out: &mut [f64]| {
        out[0] = ishigami.eval(x);
        out[1] = x[0] + 2.0 * x[2];
    };
    let run = design
        .integrator_vector(2, model)
        .unwrap()
        .seed(9)
        .run()
        .unwrap();
    let both: Indices = design.indices(&run).unwrap();
    let alone = design
        .integrator(move |x: &[f64]| ishigami.eval(x))
        .unwrap()
        .seed(9)
        .run()
        .unwrap();
    let alone = design.indices(&alone).unwrap();
    assert_eq!(both.outputs[0], alone.outputs[0]);
    // x0 + 2 x2 with both uniform on [-pi, pi]: S = (1/5, 0, 4/5).
    for (estimate, exact) in both.outputs[1].first_order.iter().zip([0.2, 0.0, 0.8]) {
        assert!(
            (estimate.mean - exact).abs() < 1e-9 + 5.0 * estimate.std_error.unwrap_or(0.0),
            "{estimate:?}"
        );
    }
    let exact = ishigami.exact_indices();
    assert!(near(&both.outputs[0].total[0], exact.total[0], 5.0));
}

/// A run to a tolerance stops with every index's half-width below it, and its intervals
/// still contain the exact indices.
#[test]
fn a_tolerance_run_meets_its_tolerance_on_every_index() {
    let ishigami = Ishigami::new(7.0, 0.1).unwrap();
    let design = SobolDesign::new(ishigami.inputs())
        .unwrap()
        .tolerance(Tolerance::absolute(2e-3).unwrap());
    let run = design
        .integrator(move |x: &[f64]| ishigami.eval(x))
        .unwrap()
        .seed(2)
        .run()
        .unwrap();
    let indices = design.indices(&run).unwrap();
    assert_eq!(indices.converged, Some(true));
    let exact = ishigami.exact_indices();
    for (estimate, truth) in indices
        .first_order()
        .iter()
        .chain(indices.total())
        .zip(exact.first_order.iter().chain(&exact.total))
    {
        assert!(estimate.half_width(0.95).unwrap().unwrap() <= 2e-3);
        assert!(near(estimate, *truth, 5.0), "{estimate:?} vs {truth}");
    }
}

#[test]
fn bad_designs_are_refused_with_what_is_allowed() {
    let unit = || mcint::measure::Uniform::unit(3).unwrap();
    let err = SobolDesign::new(unit())
        .unwrap()
        .points(1001)
        .integrator(|x: &[f64]| x[0])
        .err()
        .unwrap();
    assert!(
        err.to_string().contains("multiple of the 8 replicates"),
        "{err}"
    );
    let err = SobolDesign::new(unit())
        .unwrap()
        .replicates(1)
        .tolerance(Tolerance::absolute(1e-2).unwrap())
        .integrator(|x: &[f64]| x[0])
        .err()
        .unwrap();
    assert!(err.to_string().contains("at least 2"), "{err}");
    let err = SobolDesign::new(unit())
        .unwrap()
        .groups(vec![vec![3]])
        .err()
        .unwrap();
    assert!(err.to_string().contains("inputs 0 to 2"), "{err}");
    let other = SobolDesign::new(mcint::measure::Uniform::unit(2).unwrap()).unwrap();
    let foreign = other
        .integrator(|x: &[f64]| x[0] + x[1])
        .unwrap()
        .run()
        .unwrap();
    let err = SobolDesign::new(unit())
        .unwrap()
        .indices(&foreign)
        .unwrap_err();
    assert!(err.to_string().contains("a run of this design"), "{err}");
    // Lebesgue measures of weight 1 at the centre of the cube and not elsewhere were taken
    // for probability laws, their weights dropped.
    use mcint::measure::{Lebesgue, UnboundedTransform};
    let scale = 1.0 / (2.0 * std::f64::consts::PI).sqrt();
    let normal = Lebesgue::whole_space(1, UnboundedTransform::Normal { scale }).unwrap();
    let err = SobolDesign::new(normal).err().unwrap().to_string();
    assert!(err.contains("probability law"), "{err}");
    let (lo, hi) = (vec![0.0, f64::NEG_INFINITY], vec![0.25, f64::INFINITY]);
    let strip = Lebesgue::new(lo, hi, UnboundedTransform::Rational).unwrap();
    let err = SobolDesign::new(strip).err().unwrap().to_string();
    assert!(err.contains("probability law"), "{err}");
}

/// A run of an 8-input design has 20 outputs, a multiple of the 10 of a 3-input design's
/// block: it was read as a 2-output model's run, and gave S = 1.09. A design knows the
/// outputs of the integrators it built.
#[test]
fn a_run_of_another_design_is_refused_with_its_outputs() {
    let unit = |d| mcint::measure::Uniform::unit(d).unwrap();
    let eight = SobolDesign::new(unit(8)).unwrap().points(1 << 10);
    let foreign = eight
        .integrator(|x: &[f64]| x.iter().sum())
        .unwrap()
        .run()
        .unwrap();
    assert_eq!(foreign.outputs.len(), 20);
    let three = SobolDesign::new(unit(3)).unwrap().points(1 << 10);
    let own = three
        .integrator(|x: &[f64]| x[0] + x[1] * x[2])
        .unwrap()
        .run()
        .unwrap();
    assert!(three.indices(&own).is_ok());
    let err = three.indices(&foreign).unwrap_err().to_string();
    assert!(
        err.contains("a run of 20 outputs") && err.contains("this design: 10 outputs"),
        "{err}"
    );
}

/// Inputs given by their quantile functions: `y = x1 + x2` with `x1` exponential (variance 1)
/// and `x2` uniform on `[0, 6)` (variance 3) has `S = ST = (1/4, 3/4)`.
#[test]
fn inputs_given_by_quantile_functions_get_their_closed_form_indices() {
    let law = mcint::measure::Independent::new(vec![
        Box::new(|u: f64| -(1.0 - u).ln()),
        Box::new(|u: f64| 6.0 * u),
    ])
    .unwrap();
    let design = SobolDesign::new(law).unwrap();
    let run = design
        .integrator(|x: &[f64]| x[0] + x[1])
        .unwrap()
        .seed(8)
        .run()
        .unwrap();
    let indices = design.indices(&run).unwrap();
    for (k, exact) in [0.25, 0.75].into_iter().enumerate() {
        assert!(
            near(&indices.first_order()[k], exact, 5.0),
            "{:?}",
            indices.first_order()[k]
        );
        assert!(
            near(&indices.total()[k], exact, 5.0),
            "{:?}",
            indices.total()[k]
        );
    }
}

/// The design's run is an ordinary Integrator run: split into parts (as a checkpoint or an
/// MPI cluster splits it), merged and finished, it gives the same bits, and so the same
/// indices.
#[test]
fn a_run_in_parts_gives_the_same_indices() {
    let ishigami = Ishigami::new(7.0, 0.1).unwrap();
    let design = SobolDesign::new(ishigami.inputs()).unwrap().points(1 << 17);
    let integrator = design
        .integrator(move |x: &[f64]| ishigami.eval(x))
        .unwrap()
        .seed(4)
        .threads(2);
    let total = integrator.total_chunks().unwrap();
    assert!(total >= 8, "{total} chunks");
    let mut part = integrator.run_part(0..total / 3).unwrap();
    part.merge(integrator.run_part(total / 3..total).unwrap())
        .unwrap();
    let resumed = design.indices(&integrator.finish(&part).unwrap()).unwrap();
    let whole = design.indices(&integrator.run().unwrap()).unwrap();
    assert_eq!(resumed, whole);
}

#[test]
fn a_model_taking_blocks_gives_the_bits_of_the_per_point_model() {
    use mcint::Points;
    let ishigami = Ishigami::new(7.0, 0.1).unwrap();
    // Two outputs, so that the block's output-major layout is exercised.
    let point = move |x: &[f64], out: &mut [f64]| {
        out[0] = ishigami.eval(x);
        out[1] = x[0] * x[2];
    };
    let block = move |x: &Points, out: &mut [f64]| {
        let n = x.len();
        let mut row = [0.0; 3];
        let mut pair = [0.0; 2];
        for i in 0..n {
            x.copy_point(i, &mut row);
            point(&row, &mut pair);
            out[i] = pair[0];
            out[n + i] = pair[1];
        }
    };
    for (second_order, groups) in [(false, None), (true, Some(vec![vec![0, 2], vec![1]]))] {
        let mut design = SobolDesign::new(ishigami.inputs())
            .unwrap()
            .second_order(second_order)
            .points(1 << 12);
        if let Some(groups) = groups.clone() {
            design = design.groups(groups).unwrap();
        }
        let per_point = design
            .integrator_vector(2, point)
            .unwrap()
            .seed(5)
            .threads(1)
            .run()
            .unwrap();
        for threads in [1, 3] {
            let batch = design
                .integrator_batch(2, block)
                .unwrap()
                .seed(5)
                .threads(threads)
                .run()
                .unwrap();
            assert_eq!(batch, per_point, "second order {second_order}, {groups:?}");
        }
        let indices = design.indices(&per_point).unwrap();
        assert_eq!(indices.outputs.len(), 2);
    }
}

/// The indices do not depend on the model's scale, but the design squares its values and
/// the error bars square those again: a model near 1e-80 got error bars 1e-9 of the true
/// ones. From about 1e-70 up the indices are those of the model at scale 1 (exactly, for a
/// power of two); below, `indices` refuses with an error that names the output and a factor.
#[test]
fn indices_of_a_tiny_model_are_the_same_or_refused() {
    let ishigami = Ishigami::new(7.0, 0.1).unwrap();
    let design = SobolDesign::new(ishigami.inputs()).unwrap().points(1 << 12);
    let indices = |scale: f64| {
        let run = design
            .integrator(move |x: &[f64]| scale * ishigami.eval(x))
            .unwrap()
            .seed(3)
            .run()
            .unwrap();
        design.indices(&run)
    };
    let ordinary = indices(1.0).unwrap();
    let small = indices(2f64.powi(-200)).unwrap();
    let pairs = ordinary.first_order().iter().zip(small.first_order());
    for (a, b) in pairs.chain(ordinary.total().iter().zip(small.total())) {
        assert!(
            (a.mean - b.mean).abs() <= 1e-12 * a.mean.abs().max(1.0),
            "{a:?} {b:?}"
        );
        let (sa, sb) = (a.std_error.unwrap(), b.std_error.unwrap());
        assert!((sb / sa - 1.0).abs() < 1e-9, "{sa:e} {sb:e}");
    }
    // A model near 2^-1030 (subnormal) was told to multiply itself by inf.
    for exponent in [-266, -700, -1030] {
        let err = indices(2f64.powi(exponent)).unwrap_err().to_string();
        assert!(
            err.contains("model output")
                && err.contains("multiply the model by a constant such as ")
                && !err.contains("inf"),
            "2^{exponent}: {err}"
        );
    }
    let err = indices(2f64.powi(-1030)).unwrap_err().to_string();
    assert!(err.contains("such as 1e301 "), "{err}");
}

/// A constant model has no variance to split, whatever the constant: 0.1 and 0.3 got a
/// variance of rounding noise (indices 0 with standard errors near 1e-305) where 1.0 was
/// refused.
#[test]
fn every_constant_model_is_refused_as_constant() {
    let design = SobolDesign::new(mcint::measure::Uniform::unit(2).unwrap()).unwrap();
    for constant in [0.0, 0.1, 0.3, 1.0, 7.3, -2.5e7, 1e-310] {
        let run = design
            .integrator(move |_: &[f64]| constant)
            .unwrap()
            .run()
            .unwrap();
        let err = design.indices(&run).unwrap_err().to_string();
        assert!(err.contains("constant output"), "{constant}: {err}");
    }
}

/// `c + s (x0 + 2 x1)` has `S = ST = (1/5, 4/5)` whatever `c` and `s`: far from 0
/// (`c = 1e8`) the mean of squares cancelled against the squared mean, and the model was
/// refused as constant or got `S = (-0.94, -294)`.
#[test]
fn a_model_far_from_zero_gets_the_indices_of_its_variation() {
    let design = SobolDesign::new(mcint::measure::Uniform::unit(2).unwrap()).unwrap();
    for (c, s) in [(1e8, 1.0), (1.0, 1e-6), (-3e12, 0.5), (0.0, 1.0)] {
        let run = design
            .integrator(move |x: &[f64]| c + s * (x[0] + 2.0 * x[1]))
            .unwrap()
            .seed(6)
            .run()
            .unwrap();
        let indices = design.indices(&run).unwrap();
        for (k, exact) in [0.2, 0.8].into_iter().enumerate() {
            for estimate in [&indices.first_order()[k], &indices.total()[k]] {
                assert!(
                    (estimate.mean - exact).abs() <= 1e-9 + 5.0 * estimate.std_error.unwrap(),
                    "c = {c}, s = {s}, factor {k}: {estimate:?}"
                );
            }
        }
    }
}

/// 2^16 replicates of a 126-input design (256 outputs) aborted the process out of memory:
/// the run keeps an accumulator per output of each replicate, and is refused before it
/// allocates them, with the replicates it may have.
#[test]
fn too_many_replicates_for_the_outputs_are_refused_before_allocating() {
    let replicates = 1 << 16;
    let design = SobolDesign::new(mcint::measure::Uniform::unit(126).unwrap())
        .unwrap()
        .points(replicates)
        .replicates(replicates);
    let err = design
        .integrator(|x: &[f64]| x[0])
        .unwrap()
        .run()
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("replicates = 65536 with 256 outputs") && err.contains("16384 replicates"),
        "{err}"
    );
}

/// The shift is the model's value at the centre of the cube; where that is not finite or
/// huge (a singularity or a spike there), the model is not shifted, and its indices are
/// still those of its values elsewhere: `x0 + 2 x1` plus a spike at the centre only.
#[test]
fn a_model_singular_at_the_centre_is_not_shifted_by_it() {
    let design = SobolDesign::new(mcint::measure::Uniform::unit(2).unwrap()).unwrap();
    for spike in [f64::INFINITY, f64::NAN, 1e100] {
        let model = move |x: &[f64]| {
            if x == [0.5, 0.5] {
                spike
            } else {
                x[0] + 2.0 * x[1]
            }
        };
        let run = design.integrator(model).unwrap().seed(6).run().unwrap();
        let indices = design.indices(&run).unwrap();
        for (k, exact) in [0.2, 0.8].into_iter().enumerate() {
            let estimate = &indices.first_order()[k];
            assert!(
                (estimate.mean - exact).abs() <= 5.0 * estimate.std_error.unwrap(),
                "spike {spike}, factor {k}: {estimate:?}"
            );
        }
    }
}
