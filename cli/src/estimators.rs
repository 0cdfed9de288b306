//! Built-in estimators for the Genz families, for `integrate --estimator`: uniform sampling
//! (A.14), importance sampling from a proposal shaped like the family (A.19), multiple
//! importance sampling of uniform and proposal with the balance heuristic (Veach & Guibas
//! 1995), and the family's least-squares linear part as a control variate (A.27).

use std::f64::consts::SQRT_2;
use std::sync::Arc;

use mcint::Points;
use mcint::estimator::{
    BatchUniformEstimator, Estimator, FixedControlVariate, ImportanceEstimator, MisHeuristic,
    MultiSampleMis,
};
use mcint::pdf::{Pdf, Pdf1d, PiecewiseLinear1d, ProductPdf, TruncatedNormal, UniformBox};
use mcint::sampler::{Independent, Sampler};
use mcint::testfns::{Genz, GenzFamily, TestFunction};

/// Breakpoints of the tabulated proposals per coordinate.
const TABLE_POINTS: usize = 65;
/// Independent points of the pilot run that fits the control's slopes.
const PILOT_POINTS: u64 = 4096;
/// Keeps the pilot's points apart from the main run's for the same seed.
const PILOT_SEED_SALT: u64 = 0x7069_6c6f_7400;

/// The estimators `integrate` offers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EstimatorKind {
    Uniform,
    Importance,
    Mis,
    Control,
}

pub const ESTIMATOR_NAMES: &str = "one of uniform, importance, mis, control";

impl std::str::FromStr for EstimatorKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "uniform" => Ok(EstimatorKind::Uniform),
            "importance" => Ok(EstimatorKind::Importance),
            "mis" => Ok(EstimatorKind::Mis),
            "control" => Ok(EstimatorKind::Control),
            _ => Err(format!(
                "--estimator {s:?} is not known: use {ESTIMATOR_NAMES}"
            )),
        }
    }
}

impl EstimatorKind {
    pub fn name(self) -> &'static str {
        match self {
            EstimatorKind::Uniform => "uniform",
            EstimatorKind::Importance => "importance",
            EstimatorKind::Mis => "mis",
            EstimatorKind::Control => "control",
        }
    }
}

/// An estimator for `f` with how many integrand evaluations one contribution makes.
pub struct Built {
    pub estimator: Box<dyn Estimator>,
    pub evaluations_per_contribution: u64,
    pub description: String,
}

/// The uniform estimator (A.14) of any test function over the unit cube.
pub fn uniform(f: &(impl TestFunction + Clone + 'static)) -> Result<Built, String> {
    let cube = UniformBox::unit(f.dims()).map_err(crate::args::flag_error)?;
    let f = f.clone();
    Ok(Built {
        // A block at a time: the Genz families' exp and cos are vectorized.
        estimator: Box::new(BatchUniformEstimator::new(
            move |points: &Points, out: &mut [f64]| f.eval_batch(points, out),
            cube,
        )),
        evaluations_per_contribution: 1,
        description: "uniform points, f(x) * volume (A.14)".into(),
    })
}

/// Builds the chosen estimator of the integral of `f` over the unit cube.
pub fn build(kind: EstimatorKind, f: &Genz, seed: u64) -> Result<Built, String> {
    let dims = f.a().len();
    let f = Arc::new(f.clone());
    let eval = {
        let f = Arc::clone(&f);
        move |x: &[f64]| f.eval(x)
    };
    let cube = UniformBox::unit(dims).map_err(crate::args::flag_error)?;
    Ok(match kind {
        EstimatorKind::Uniform => return uniform(f.as_ref()),
        EstimatorKind::Importance => {
            let (proposal, what) = proposal(&f)?;
            Built {
                estimator: Box::new(ImportanceEstimator::new(eval, proposal)),
                evaluations_per_contribution: 1,
                description: format!("importance sampling f/pdf (A.19) from {what}"),
            }
        }
        EstimatorKind::Mis => {
            let (proposal, what) = proposal(&f)?;
            let techniques: Vec<(Box<dyn Pdf>, usize)> =
                vec![(Box::new(cube), 1), (Box::new(proposal), 1)];
            let mis = MultiSampleMis::new(eval, techniques, MisHeuristic::Balance)
                .map_err(crate::args::flag_error)?;
            Built {
                estimator: Box::new(mis),
                evaluations_per_contribution: 2,
                description: format!(
                    "multiple importance sampling, balance heuristic, one uniform point and one \
                     from {what} per contribution"
                ),
            }
        }
        EstimatorKind::Control => {
            let control = linear_control(&f, seed)?;
            let cv = FixedControlVariate::new(eval, control, 0.0, cube)
                .map_err(crate::args::flag_error)?;
            Built {
                estimator: Box::new(cv),
                evaluations_per_contribution: 1,
                description: format!(
                    "control variate (A.27): the least-squares linear part of f, slopes from a \
                     {PILOT_POINTS}-point independent pilot run"
                ),
            }
        }
    })
}

/// A product density on the cube shaped like `f`, and its description.
fn proposal(f: &Genz) -> Result<(ProductPdf, &'static str), String> {
    let (a, u) = (f.a(), f.u());
    let dims = a.len();
    let mut factors: Vec<Box<dyn Pdf1d>> = Vec::with_capacity(dims);
    let what = match f.family() {
        GenzFamily::Gaussian => {
            // exp(-a^2 (x - u)^2) is a normal density with sd 1 / (a sqrt 2): exact.
            for i in 0..dims {
                let p = TruncatedNormal::new(u[i], 1.0 / (a[i] * SQRT_2), 0.0, 1.0)
                    .map_err(crate::args::flag_error)?;
                factors.push(Box::new(p));
            }
            "truncated normals proportional to f"
        }
        GenzFamily::ProductPeak => {
            for i in 0..dims {
                let inv_a2 = (a[i] * a[i]).recip();
                factors.push(table(0.0, 1.0, &[u[i]], |x| {
                    1.0 / (inv_a2 + (x - u[i]).powi(2))
                })?);
            }
            "piecewise-linear tables of f's factors"
        }
        GenzFamily::Continuous => {
            for i in 0..dims {
                factors.push(table(0.0, 1.0, &[u[i]], |x| {
                    (-a[i] * (x - u[i]).abs()).exp()
                })?);
            }
            "piecewise-linear tables of f's factors"
        }
        GenzFamily::CornerPeak => {
            // (1 + sum a x)^-(d+1) is not a product; each factor falls off like its share.
            let power = -((dims + 1) as f64) / dims as f64;
            for &ai in a {
                factors.push(table(0.0, 1.0, &[], |x| (1.0 + ai * x).powf(power))?);
            }
            "piecewise-linear tables of (1 + a_i x)^(-(d+1)/d)"
        }
        GenzFamily::Discontinuous => {
            // f vanishes where x_1 > u_1 or x_2 > u_2, and is exp(sum a x) elsewhere.
            for i in 0..dims {
                let hi = if i < 2 { u[i] } else { 1.0 };
                if hi <= 0.0 {
                    return Err(format!(
                        "the discontinuous family with u_{} = 0 vanishes almost everywhere; \
                         no proposal can sample it (its integral is 0)",
                        i + 1
                    ));
                }
                factors.push(table(0.0, hi, &[], |x| (a[i] * x).exp())?);
            }
            "piecewise-linear tables of exp(a_i x) on the support of f"
        }
        GenzFamily::Oscillatory => {
            return Err(
                "the oscillatory family changes sign, so no density follows its shape; \
                 use --estimator control (its linear part as a control variate) or uniform"
                    .into(),
            );
        }
    };
    Ok((
        ProductPdf::new(factors).map_err(crate::args::flag_error)?,
        what,
    ))
}

/// A piecewise-linear density through `phi` at evenly spaced breakpoints on `[lo, hi]` plus
/// `extra` ones (kinks of `phi`).
fn table(
    lo: f64,
    hi: f64,
    extra: &[f64],
    phi: impl Fn(f64) -> f64,
) -> Result<Box<dyn Pdf1d>, String> {
    let mut xs: Vec<f64> = (0..TABLE_POINTS)
        .map(|k| lo + (hi - lo) * k as f64 / (TABLE_POINTS - 1) as f64)
        .chain(extra.iter().copied().filter(|x| *x > lo && *x < hi))
        .collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let values: Vec<f64> = xs.iter().map(|&x| phi(x)).collect();
    Ok(Box::new(
        PiecewiseLinear1d::new(&xs, &values).map_err(crate::args::flag_error)?,
    ))
}

/// The least-squares linear part of `f` as a control: `g(x) = sum_i b_i (x_i - 1/2)` with
/// integral 0 over the cube. For uniform `x` the coordinates have covariance `I / 12`, so the
/// regression slopes are `b_i = 12 Cov(x_i, f)`; they are estimated from a pilot run of
/// independent points with their own seed, before and apart from the main run, so the main
/// estimate stays unbiased (the two-stage scheme of Kirk & Arvo 1991).
fn linear_control(
    f: &Arc<Genz>,
    seed: u64,
) -> Result<impl Fn(&[f64]) -> f64 + Send + Sync + use<>, String> {
    let dims = f.a().len();
    let pilot = Independent::new(dims, seed ^ PILOT_SEED_SALT).map_err(crate::args::flag_error)?;
    let mut x = vec![0.0; dims];
    let mut mean_f = 0.0;
    let mut sums = vec![0.0; dims];
    for i in 0..PILOT_POINTS {
        pilot.point(i, &mut x).map_err(crate::args::flag_error)?;
        let value = f.eval(&x);
        mean_f += value;
        for (s, xi) in sums.iter_mut().zip(&x) {
            *s += (xi - 0.5) * value;
        }
    }
    let n = PILOT_POINTS as f64;
    mean_f /= n;
    // Cov(x_i, f) = E[(x_i - 1/2) f] exactly, since E[x_i - 1/2] = 0.
    let slope: Vec<f64> = sums.iter().map(|s| 12.0 * s / n).collect();
    if !(mean_f.is_finite() && slope.iter().all(|b| b.is_finite())) {
        return Err("the pilot run for the control's slopes met non-finite values of f".into());
    }
    Ok(move |x: &[f64]| {
        x.iter()
            .zip(&slope)
            .map(|(xi, b)| b * (xi - 0.5))
            .sum::<f64>()
    })
}
