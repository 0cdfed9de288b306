//! The two classic test models of variance-based sensitivity analysis that the `sensitivity`
//! binary analyses: the library's Ishigami function and Sobol' g-function, with their exact
//! indices, including the second-order ones.

use mcint::measure::Uniform;
use mcint::sensitivity::ExactIndices;
use mcint::testfns::{Ishigami, SobolGFunction, TestFunction};

/// A model `Y = f(X)` with independent uniform inputs and a known variance decomposition.
#[derive(Clone)]
pub enum Model {
    /// `sin x1 + a sin^2 x2 + b x3^4 sin x1` on `[-pi, pi]^3`.
    Ishigami { a: f64, b: f64, model: Ishigami },
    /// `prod (|4 x_i - 2| + a_i) / (1 + a_i)` on `[0, 1]^d`.
    SobolG(SobolGFunction),
}

/// The g-function weights of Saltelli et al. (2010), "Variance based sensitivity analysis of
/// model output. Design and estimator for the total sensitivity index", Comput. Phys.
/// Commun. 181, 259-270: two important inputs, two minor ones and two that hardly matter.
/// Inputs beyond the sixth get 99 as well.
pub const SALTELLI_2010_A: [f64; 6] = [0.0, 0.5, 3.0, 9.0, 99.0, 99.0];

impl Model {
    /// Ishigami with parameters `a` and `b`.
    pub fn ishigami(a: f64, b: f64) -> Result<Model, String> {
        let model = Ishigami::new(a, b).map_err(crate::args::flag_error)?;
        Ok(Model::Ishigami { a, b, model })
    }

    /// The g-function with weights `a`, given by `--weights` (the library calls them `a`,
    /// as `--a` is Ishigami's).
    pub fn sobol_g(a: Vec<f64>) -> Result<Model, String> {
        SobolGFunction::new(a)
            .map(Model::SobolG)
            .map_err(|error| error.message_with_names(&[("a", "--weights")]))
    }

    /// The g-function on `d` inputs with the weights of [`SALTELLI_2010_A`].
    pub fn sobol_g_saltelli(d: usize) -> Result<Model, String> {
        Model::sobol_g(
            (0..d)
                .map(|i| SALTELLI_2010_A.get(i).copied().unwrap_or(99.0))
                .collect(),
        )
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
            Model::Ishigami { a, b, .. } => vec![("a", vec![*a]), ("b", vec![*b])],
            Model::SobolG(g) => vec![("a", g.a().to_vec())],
        }
    }

    /// The inputs' law.
    pub fn inputs(&self) -> Uniform {
        match self {
            Model::Ishigami { model, .. } => model.inputs(),
            Model::SobolG(g) => Uniform::unit(g.dims()).expect("at least one input"),
        }
    }

    /// `f` at the input `x`.
    pub fn eval(&self, x: &[f64]) -> f64 {
        match self {
            Model::Ishigami { model, .. } => model.eval(x),
            Model::SobolG(g) => g.eval(x),
        }
    }

    /// The analytic variance decomposition.
    pub fn exact(&self) -> ExactIndices {
        match self {
            Model::Ishigami { model, .. } => model.exact_indices(),
            Model::SobolG(g) => g.exact_indices(),
        }
    }

    /// The exact second-order index of inputs `i < j`: Ishigami's one interaction is
    /// `x1 x3`, whose share is `ST_3`; the g-function's `S_ij = V_i V_j / V = S_i S_j V`.
    pub fn exact_second_order(&self, i: usize, j: usize) -> f64 {
        let exact = self.exact();
        match self {
            Model::Ishigami { .. } => {
                if (i, j) == (0, 2) {
                    exact.total[2]
                } else {
                    0.0
                }
            }
            Model::SobolG(_) => exact.first_order[i] * exact.first_order[j] * exact.variance,
        }
    }
}
