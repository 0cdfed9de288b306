//! The pdfs and warps (`src/pdf/`) and the measures (`src/measure/`): one test crate, a
//! module per topic.
//!
//! | source | tests |
//! | --- | --- |
//! | `pdf/uniform.rs`, `linear.rs`, `exponential.rs`, `truncated_normal.rs`, `uniform_box.rs`, `product.rs` | `pdfs` |
//! | `pdf/normal.rs`, `tent.rs`, `piecewise_constant*.rs`, `piecewise_linear.rs`, `alias_table.rs` | `pdfs_tables` |
//! | `pdf/uniform_disk.rs`, `uniform_triangle.rs`, `uniform_sphere.rs`, `uniform_hemisphere.rs`, `cosine_hemisphere.rs`, `spherical_cap.rs` | `pdfs_warps` |
//! | `pdf/warp3.rs`, `warp_to_3d.rs`, `geometric_warp.rs` (oriented warps, `Integrator::over_warp`) | `pdfs_oriented` |
//! | `src/measure/` | `measures` |
//!
//! The slice-length contract of every pdf is in the `contracts` crate (`pdf_slice_lengths`),
//! mixtures in the `estimators` crate (`mis`).
//!
//! Run one module with a filter: `cargo test --release --test pdfs -- pdfs_warps::`.

#[path = "../common/mod.rs"]
mod common;

mod measures;
mod pdfs;
mod pdfs_oriented;
mod pdfs_tables;
mod pdfs_warps;
