//! `mcint._native`: the Rust side of the Python package. The Python modules in `mcint/`
//! give it its public shape (scipy engines, `integrate`, the result type); this module
//! only moves numbers between numpy and the library, and runs the library with the
//! interpreter's lock released.

use pyo3::prelude::*;

mod errors;
mod failure;
mod integrand;
mod measure;
mod multilevel;
mod point_set;
mod result;
mod run;
mod sde_levels;
mod sensitivity;

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<point_set::PointSet>()?;
    m.add_class::<result::RunResult>()?;
    m.add_class::<measure::MeasureSpec>()?;
    m.add_function(wrap_pyfunction!(run::integrate_box, m)?)?;
    m.add_class::<sensitivity::SensitivityRun>()?;
    m.add_class::<multilevel::MultilevelRun>()?;
    m.add_function(wrap_pyfunction!(multilevel::mlmc, m)?)?;
    m.add_function(wrap_pyfunction!(multilevel::mlmc_sde, m)?)?;
    m.add_class::<sde_levels::SdeModel>()?;
    m.add_function(wrap_pyfunction!(sensitivity::sobol_indices, m)?)?;
    m.add_function(wrap_pyfunction!(point_set::sampler_names, m)?)?;
    m.add_function(wrap_pyfunction!(point_set::scramble_names, m)?)?;
    m.add_function(wrap_pyfunction!(point_set::sampler_info, m)?)?;
    m.add_function(wrap_pyfunction!(point_set::optimize, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
