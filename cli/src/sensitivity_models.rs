//! The two classic test models of variance-based sensitivity analysis, with their analytic
//! Sobol' indices: the Ishigami function and the Sobol' g-function.
//!
//! Both are evaluated from a point `u` of the unit cube `[0,1)^d`; each model maps `u` to
//! its own input box, so that the integration itself always runs over the unit cube (over a
//! larger box every contribution would carry the box's volume).

use mcint::testfns::{SobolGFunction, TestFunction};
use std::f64::consts::PI;

/// A model `Y = f(X)` with independent uniform inputs and known variance decomposition.
#[derive(Clone)]
pub enum Model {
    /// `sin x1 + a sin^2 x2 + b x3^4 sin x1` on `[-pi, pi]^3` (Ishigami & Homma 1990).
    Ishigami { a: f64, b: f64 },
    /// `prod (|4 x_i - 2| + a_i) / (1 + a_i)` on `[0, 1]^d` (Saltelli & Sobol' 1995).
    SobolG(SobolGFunction),
}

/// The exact variance of `Y` and its first-order and total Sobol' indices, one per input.
pub struct Indices {
    pub variance: f64,
    pub first_order: Vec<f64>,
    pub total: Vec<f64>,
}

/// The g-function weights of Saltelli et al. (2010), "Variance based sensitivity analysis of
/// model output. Design and estimator for the total sensitivity index", Comput. Phys.
/// Commun. 181, 259-270: two important inputs, two minor ones and two that hardly matter.
/// Inputs beyond the sixth get 99 as well.
pub const SALTELLI_2010_A: [f64; 6] = [0.0, 0.5, 3.0, 9.0, 99.0, 99.0];

impl Model {
    /// Ishigami with the usual `a = 7`, `b = 0.1`.
    pub fn ishigami() -> Model {
        Model::Ishigami { a: 7.0, b: 0.1 }
    }

    /// The g-function on `d` inputs with the weights of [`SALTELLI_2010_A`].
    pub fn sobol_g(d: usize) -> Result<Model, String> {
        let a = (0..d)
            .map(|i| SALTELLI_2010_A.get(i).copied().unwrap_or(99.0))
            .collect();
        SobolGFunction::new(a)
            .map(Model::SobolG)
            .map_err(|e| e.to_string())
    }

    pub fn name(&self) -> &'static str {
        match self {
            Model::Ishigami { .. } => "ishigami",
            Model::SobolG(_) => "sobol-g",
        }
    }

    pub fn dims(&self) -> usize {
        match self {
            Model::Ishigami { .. } => 3,
            Model::SobolG(g) => g.dims(),
        }
    }

    /// The model's parameters, for reports: `(name, values)`.
    pub fn parameters(&self) -> Vec<(&'static str, Vec<f64>)> {
        match self {
            Model::Ishigami { a, b } => vec![("a", vec![*a]), ("b", vec![*b])],
            Model::SobolG(g) => vec![("a", g.a().to_vec())],
        }
    }

    /// `f` at the input that the unit-cube point `u` maps to.
    pub fn eval_unit(&self, u: &[f64]) -> f64 {
        match self {
            Model::Ishigami { a, b } => {
                let x = |k: usize| PI * (2.0 * u[k] - 1.0); // [0, 1) -> [-pi, pi)
                let (x1, x2, x3) = (x(0), x(1), x(2));
                let s2 = x2.sin();
                x1.sin() * (1.0 + b * x3.powi(4)) + a * s2 * s2
            }
            Model::SobolG(g) => g.eval(u),
        }
    }

    /// The analytic variance decomposition.
    pub fn exact(&self) -> Indices {
        match self {
            Model::Ishigami { a, b } => ishigami_indices(*a, *b),
            Model::SobolG(g) => sobol_g_indices(g),
        }
    }
}

/// Ishigami's partial variances (Sobol' & Levitan 1999; Saltelli et al. 2008, "Global
/// Sensitivity Analysis: The Primer", Wiley). With `x` uniform on `[-pi, pi]`:
/// `Var sin x = 1/2`, `E sin^2 = 1/2`, `E sin^4 = 3/8`, `E x^4 = pi^4/5`, `E x^8 = pi^8/9`.
/// - `E[Y|x1] = a/2 + sin x1 (1 + b pi^4/5)`, so `V1 = (1 + b pi^4/5)^2 / 2`;
/// - `E[Y|x2] = a sin^2 x2 + const`, so `V2 = a^2 (3/8 - 1/4) = a^2/8`;
/// - `E[Y|x3]` is constant (`E sin x1 = 0`), so `V3 = 0`;
/// - the only interaction is `b sin x1 (x3^4 - pi^4/5)`, with
///   `V13 = b^2/2 (pi^8/9 - pi^8/25) = b^2 pi^8 (1/18 - 1/50)`.
///
/// So `V = V1 + V2 + V13`, `ST1 = (V1 + V13)/V`, `ST2 = V2/V`, `ST3 = V13/V`.
fn ishigami_indices(a: f64, b: f64) -> Indices {
    let pi4 = PI.powi(4);
    let v1 = 0.5 * (1.0 + b * pi4 / 5.0).powi(2);
    let v2 = a * a / 8.0;
    let v13 = b * b * pi4 * pi4 * (1.0 / 18.0 - 1.0 / 50.0);
    let variance = v1 + v2 + v13;
    Indices {
        variance,
        first_order: vec![v1 / variance, v2 / variance, 0.0],
        total: vec![(v1 + v13) / variance, v2 / variance, v13 / variance],
    }
}

/// The g-function's decomposition (Saltelli & Sobol' 1995): each factor has mean 1 and
/// variance `V_i = 1/(3 (1 + a_i)^2)`, and a product of independent factors has
/// `V = prod (1 + V_i) - 1`; the terms that contain `i` add up to
/// `V_i prod_{j != i} (1 + V_j)`.
fn sobol_g_indices(g: &SobolGFunction) -> Indices {
    let partial: Vec<f64> = g
        .a()
        .iter()
        .map(|a| 1.0 / (3.0 * (1.0 + a).powi(2)))
        .collect();
    let product: f64 = partial.iter().map(|v| 1.0 + v).product();
    let variance = product - 1.0;
    Indices {
        variance,
        first_order: partial.iter().map(|v| v / variance).collect(),
        total: partial
            .iter()
            .map(|v| v * product / (1.0 + v) / variance)
            .collect(),
    }
}
