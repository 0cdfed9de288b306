//! The command-line programs of mcint, as a library under thin binaries (`src/bin/`): their
//! argument parsing, output that never panics, input files, checkpoints, MPI ranks, plots, the
//! test integrands and estimators `integrate` offers, and the one place where a method is
//! chosen and run.

pub mod args;
pub mod asian;
pub mod checkpoint;
pub mod estimators;
pub mod input;
pub mod integrands;
pub mod methods;
pub mod output;
pub mod plot;
pub mod ranks;
pub mod report;
pub mod sensitivity_models;
