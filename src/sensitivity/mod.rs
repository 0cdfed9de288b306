//! Global sensitivity analysis: Sobol' first-order, total and second-order indices, of single
//! inputs or groups, for scalar and vector models, over any probability law the crate samples
//! (the `measure` module's `Uniform`, `Gaussian`, `Lognormal`, and `Independent` inputs given
//! by their quantile functions).
//!
//! A [`SobolDesign`] builds the pick-freeze design of A. Saltelli, P. Annoni, I. Azzini, F.
//! Campolongo, M. Ratto and S. Tarantola, "Variance based sensitivity analysis of model
//! output. Design and estimator for the total sensitivity index", Comput. Phys. Commun. 181
//! (2010), 259-270, as one vector run of the engine, and derives every index from its
//! integrals:
//!
//! - first order: `V_j = E[f(B) (f(AB_j) - f(A))]` (Saltelli et al. 2010);
//! - total: `V_Tj = E[(f(A) - f(AB_j))^2] / 2` (M. J. W. Jansen, "Analysis of variance designs
//!   for model output", Comput. Phys. Commun. 117 (1999), 35-43);
//! - second order: `E[f(BA_j) f(AB_k) - f(A) f(B)] - V_j - V_k` (A. Saltelli, "Making best use
//!   of model evaluations to compute sensitivity indices", Comput. Phys. Commun. 145 (2002),
//!   280-297);
//!
//! each over `Var Y` from `f(A)` and `f(B)`, with `f` the model less a constant (its value at
//! the centre of the cube) so that the squares do not cancel against the mean. These are the
//! estimators SALib uses, which makes the two comparable point set for point set; the
//! alternatives measured against them (Janon et al. 2014 for the first order, Jansen's
//! numerator over the variance of the same pair or of every run, a centred Saltelli
//! numerator) were within 20% of them either way, depending on the replicates and the budget
//! (`docs/measurements.md`).
//!
//! The indices are ratios of means, so the run's error bars carry over by the delta method,
//! and a run to a [`Tolerance`](crate::Tolerance) on every index is an ordinary run of the
//! engine (time limits and MPI clusters included). Checkpoints are runs in parts
//! ([`run_part`](crate::Integrator::run_part)), which only a fixed-budget design has: a run
//! to a tolerance has no parts (its stages depend on its results so far), and `run_part`
//! refuses it.
//!
//! ```
//! use mcint::{sensitivity::SobolDesign, testfns::Ishigami};
//! let model = Ishigami::new(7.0, 0.1).unwrap();
//! let design = SobolDesign::new(model.inputs()).unwrap();
//! let run = design.integrator(move |x: &[f64]| model.eval(x)).unwrap().seed(7).run().unwrap();
//! let indices = design.indices(&run).unwrap();
//! assert!((indices.total()[2] .mean - 0.2437).abs() < 0.01);
//! ```

mod design;
mod indices;
mod layout;

pub use design::{DEFAULT_POINTS, DEFAULT_REPLICATES, DesignIntegrand, DesignRun, SobolDesign};
pub use indices::{ExactIndices, Indices, OutputIndices, SecondOrder};
