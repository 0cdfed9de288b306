//! The command-line programs (`cli/src/bin/`), run as a user would: one test crate, a module
//! per topic. `cargo test` builds the programs before running it; `common::example` finds them
//! next to the test binary. The MPI test (`cli/tests/mpi.rs`) is a crate of its own: it is a
//! program that launches itself under `mpirun`.
//!
//! | programs, behaviour | tests |
//! | --- | --- |
//! | `points`, `integrate`, `variance_reduction`, `gallery`, `convergence`: output formats, one-line errors | `cli` (`points`, `samplers`, `integrate`, `figures`) |
//! | every program on 500 generated bad command lines | `cli_bad_input` |
//! | `integrate --checkpoint` killed and resumed; the checkpoint file's guards | `cli_checkpoint_kill` |
//! | bad flags, before any work | `cli_flags` |
//! | `asian_option`, `points --measure`, `integrate --integrand keister` | `cli_measures` |
//! | `points --format sum` | `cli_points_sum` |
//! | `quality` | `cli_quality` |
//! | closed and full output, non-UTF-8 arguments, sizes beyond memory | `cli_robustness` |
//! | `mlmc` | `cli_mlmc` |
//! | `sensitivity` | `cli_sensitivity` |
//! | SIGINT, SIGTERM and `--time-limit` | `cli_signals` |
//! | `integrate --genz F1,F2,...` and `--ratio` (vector runs) | `cli_vector` |
//! | warnings and the rounding floor | `cli_warnings` |
//!
//! Run one module with a filter: `cargo test --release -p mcint-cli --test cli -- cli_signals::`.

#[path = "../common/mod.rs"]
mod common;

mod cli;
mod cli_bad_input;
mod cli_checkpoint_kill;
mod cli_flags;
mod cli_measures;
mod cli_mlmc;
mod cli_points_sum;
mod cli_quality;
mod cli_robustness;
mod cli_sensitivity;
mod cli_signals;
mod cli_vector;
mod cli_warnings;
