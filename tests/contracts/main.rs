//! Contracts at the edges, across the library: absurd input to every constructor, limits,
//! rounding floors, huge values, panicking integrands, pinned values, the accumulator's
//! merges, checkpoints and the pdfs' slice lengths. CI runs this crate twice: in release with
//! the rest, and in debug (overflow checks and debug assertions on) with the unit tests:
//! `cargo test --lib --test contracts`.
//!
//! | source | tests |
//! | --- | --- |
//! | every public constructor (issue 9) | `robustness` |
//! | `engine/limits.rs` (time limits, cancellation, budgets) | `run_limits` |
//! | `stats/rounding.rs` (error bars at the floor of floating point) | `rounding_floor` |
//! | `stats/accumulator.rs` scaling, runners near `f64::MAX` | `huge_values` |
//! | `Error::IntegrandPanicked` (`engine/executor.rs`) | `integrand_panics` |
//! | literal outputs of samplers, pdfs and runs | `value_stability` |
//! | `stats/accumulator.rs` | `accumulator` |
//! | `integrate/partial.rs`, `partial_format.rs` (needs the `serde` feature) | `checkpoint` |
//! | the slice lengths of `Pdf::sample`, `pdf`, `invert` | `pdf_slice_lengths` |
//!
//! Run one module with a filter: `cargo test --release --test contracts -- run_limits::`.

#[path = "../common/mod.rs"]
mod common;

mod accumulator;
// The tests see the library with serde through the dev-dependency on itself; without the
// feature the checkpoint tests are left out (they were a `required-features` test crate).
#[cfg(feature = "serde")]
mod checkpoint;
mod huge_values;
mod integrand_panics;
mod pdf_slice_lengths;
mod robustness;
mod rounding_floor;
mod run_limits;
mod value_stability;
