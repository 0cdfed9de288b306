//! The estimators (`src/estimator/`) and the probability facts they rest on: one test crate, a
//! module per topic.
//!
//! | source | tests |
//! | --- | --- |
//! | `estimator/uniform.rs`, `importance.rs`, `consistent_biased.rs` | `estimators` |
//! | `estimator/control_variate.rs`, `control_variates.rs` | `control_variates` |
//! | `estimator/control_domain.rs`, the geometric-average call (`measure/geometric_brownian.rs`) | `controls_over_measures` |
//! | `estimator/*mis*.rs`, `product_importance.rs`, `pdf/mixture.rs` | `mis` |
//! | Jarosz's A.6-A.10 (no source: the identities the estimators' proofs use) | `probability` |
//!
//! Run one module with a filter: `cargo test --release --test estimators -- mis::`.

#[path = "../common/mod.rs"]
mod common;

mod control_variates;
mod controls_over_measures;
mod estimators;
mod mis;
mod probability;
