//! [`Integrand`]: VEGAS's view of a scalar or a vector-valued integrand, so that one
//! iteration loop serves both.

/// `m` values `f_k(x)` per point.
pub(super) trait Integrand: Sync {
    /// Number of outputs `m`.
    fn outputs(&self) -> usize;

    /// Writes `f_k(x)` to `out[k]` (`out.len() == outputs()`).
    fn eval(&self, x: &[f64], out: &mut [f64]);
}

/// A scalar integrand: one output, the very value of `f`.
pub(super) struct Scalar<'a, F>(pub(super) &'a F);

impl<F: Fn(&[f64]) -> f64 + Sync> Integrand for Scalar<'_, F> {
    fn outputs(&self) -> usize {
        1
    }

    #[inline]
    fn eval(&self, x: &[f64], out: &mut [f64]) {
        out[0] = (self.0)(x);
    }
}

/// The integrand of a vector VEGAS run, with what the run must reach: see
/// [`Vegas::new_vector`](super::super::Vegas::new_vector), which builds it.
///
/// ```
/// use mcint::adaptive::{Vegas, VegasOutputs};
/// use mcint::pdf::UniformBox;
/// fn both(x: &[f64], out: &mut [f64]) {
///     out[0] = x[0];
///     out[1] = x[0] * x[0];
/// }
/// let run: Vegas<VegasOutputs<fn(&[f64], &mut [f64])>> =
///     Vegas::new_vector(2, both as fn(&[f64], &mut [f64]), UniformBox::unit(1).unwrap());
/// assert_eq!(run.run().unwrap().len(), 2);
/// ```
pub struct VegasOutputs<F> {
    pub(super) outputs: usize,
    pub(super) f: F,
    pub(super) output_tolerances: Option<Vec<crate::stats::Tolerance>>,
    pub(super) derived_tolerances: Vec<(crate::stats::Derived, crate::stats::Tolerance)>,
}

impl<F: Fn(&[f64], &mut [f64]) + Sync> Integrand for VegasOutputs<F> {
    fn outputs(&self) -> usize {
        self.outputs
    }

    #[inline]
    fn eval(&self, x: &[f64], out: &mut [f64]) {
        // An output the integrand does not write is reported as non-finite.
        out.fill(f64::NAN);
        (self.f)(x, out);
    }
}
