//! The samplers (`src/sampler/`): one test crate, a module per topic.
//!
//! | source | tests |
//! | --- | --- |
//! | the `Sampler` contract, `Independent`, `Jittered`, `LatinHypercube` | `samplers` |
//! | `sampler/antithetic.rs` | `antithetic` |
//! | `Sampler::fill_f32` | `fill_f32` |
//! | `sampler/halton.rs`, `hammersley.rs`, `radical_inverse/` | `qmc_halton` |
//! | `sampler/lattice.rs` | `qmc_lattice` |
//! | `sampler/sobol.rs`, `sobol/`, `owen.rs`, `scramble.rs` | `qmc_sobol` |
//! | the kind salt of every sampler's hashes | `sampler_independence` |
//! | `sampler/draw.rs` (scipy.stats.qmc-style point sets) | `scipy_style` |
//! | `sampler/simd.rs` (block fill kernels; Miri runs `simd_kernels::small_fills_equal_point`) | `simd_kernels` |
//! | `sampler/poisson_disk.rs`, `best_candidate.rs`, `torus*.rs` | `stratified_blue_noise` |
//! | `sampler/multi_jittered.rs`, `correlated_multi_jittered.rs` | `stratified_mj` |
//! | `sampler/orthogonal_array.rs` | `stratified_oa` |
//! | `sampler/pmj02.rs`, `multi_stage_n_rooks.rs` | `stratified_pmj` |
//! | `sampler/random_cd.rs`, `lloyd.rs` | `design_optimization` |
//!
//! Run one module with a filter: `cargo test --release --test samplers -- qmc_sobol::`.

#[path = "../common/mod.rs"]
mod common;

mod antithetic;
mod design_optimization;
mod fill_f32;
mod qmc_halton;
mod qmc_lattice;
mod qmc_sobol;
mod sampler_independence;
mod samplers;
mod scipy_style;
mod simd_kernels;
mod stratified_blue_noise;
mod stratified_mj;
mod stratified_oa;
mod stratified_pmj;
