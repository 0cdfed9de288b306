//! The number of outputs of a vector-valued integrand, checked once for every vector
//! estimator.

use crate::error::{Error, Result};

/// The most outputs of one integrand: a run keeps, per replicate of independent points, the
/// co-moments of every pair of outputs (`m (m + 1) / 2` of them) and evaluates each block of
/// points into one column per output.
///
/// ```
/// use mcint::{Integrator, estimator::MAX_OUTPUTS, pdf::UniformBox};
/// let f = |_: &[f64], out: &mut [f64]| out.fill(0.0);
/// let run = Integrator::over_box_vector(MAX_OUTPUTS + 1, f, UniformBox::unit(1).unwrap()).run();
/// assert!(run.is_err());
/// ```
pub const MAX_OUTPUTS: usize = 256;

/// `outputs` if it is in `1..=MAX_OUTPUTS`, else an error that says so.
pub(crate) fn checked_outputs(outputs: usize) -> Result<usize> {
    if (1..=MAX_OUTPUTS).contains(&outputs) {
        return Ok(outputs);
    }
    Err(Error::invalid(
        "outputs",
        outputs,
        format!("1 to {MAX_OUTPUTS} outputs per point"),
    ))
}
