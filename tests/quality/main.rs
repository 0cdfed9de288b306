//! Quality measures of point sets and of convergence (`src/quality/`), the test functions
//! (`src/testfns/`) and the vector math kernels (`src/vector_math.rs`): one test crate, a
//! module per topic.
//!
//! | source | tests |
//! | --- | --- |
//! | `quality/convergence.rs` | `quality_convergence` |
//! | `quality/discrepancy.rs`, `discrepancy/`, `star_discrepancy.rs`, `update_discrepancy.rs`, `geometric_discrepancy.rs` | `quality_discrepancy` |
//! | `quality/nets.rs` | `quality_nets` |
//! | `quality/spectrum.rs` | `quality_spectrum` |
//! | randomized QMC rates on `testfns/genz.rs` | `qmc_rates` |
//! | `testfns/` exact integrals | `testfns_exact` |
//! | `testfns/graphics.rs` | `testfns_graphics` |
//! | `testfns/genz_batch.rs` | `genz_batch` |
//! | `src/vector_math.rs` | `vector_math` |
//!
//! Run one module with a filter: `cargo test --release --test quality -- quality_nets::`.

#[path = "../common/mod.rs"]
mod common;

mod genz_batch;
mod qmc_rates;
mod quality_convergence;
mod quality_discrepancy;
mod quality_nets;
mod quality_spectrum;
mod testfns_exact;
mod testfns_graphics;
mod vector_math;
