//! Runs: the integrator (`src/integrate.rs`, `src/integrate/`, `src/engine/`), the adaptive
//! methods (`src/adaptive/`) and vector runs: one test crate, a module per topic.
//!
//! | source | tests |
//! | --- | --- |
//! | `Integrator` (thread-count independence, error bars, errors) | `integrator` |
//! | runs to a tolerance (`engine/stopping.rs`, `engine/targets.rs`) | `integrator_tolerance` |
//! | `adaptive/miser.rs` | `adaptive_miser` |
//! | MISER and VEGAS runs to a tolerance | `adaptive_tolerance` |
//! | `adaptive/two_stage.rs` | `adaptive_two_stage` |
//! | `adaptive/vegas.rs`, `vegas/`, `vegas_grid.rs` | `adaptive_vegas` |
//! | `adaptive/sobol_g.rs` | `sobol_g` |
//! | `sensitivity/` (Sobol' indices) | `sensitivity` |
//! | `multilevel/` (MLMC and MLQMC on SDE paths) | `multilevel` |
//! | batch integrands (`estimator/batch_uniform.rs`) | `batch_integrand` |
//! | MISER and two-stage sampling by blocks (`adaptive/scalar_batch.rs`) | `adaptive_batch` |
//! | vector runs (`integrate/vector.rs`, `estimator/vector*.rs`, `stats/covariance.rs`) | `vector_integrands`, `vector_coverage` |
//! | vector VEGAS | `vector_vegas` |
//! | VEGAS and VEGAS+ to a tolerance on sharp 8-D peaks | `vegas_peaks` |
//!
//! Limits, panics, checkpoints and huge values of runs are in the `contracts` crate.
//!
//! Run one module with a filter: `cargo test --release --test runs -- adaptive_vegas::`.

#[path = "../common/mod.rs"]
mod common;

mod adaptive_batch;
mod adaptive_miser;
mod adaptive_tolerance;
mod adaptive_two_stage;
mod adaptive_vegas;
mod batch_integrand;
mod integrator;
mod integrator_tolerance;
mod multilevel;
mod sensitivity;
mod sobol_g;
mod vector_coverage;
mod vector_integrands;
mod vector_vegas;
mod vegas_peaks;
