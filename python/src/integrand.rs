//! `PyIntegrand`: a vectorized Python function as the library's integrand, called on blocks of points.

use std::sync::Arc;

use mcint::measure::Measure;
use mcint::{CancelToken, Points};
use numpy::npyffi::NPY_ORDER;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArrayDyn};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::failure::Failure;

/// The user's vectorized Python function `f(x)`, called with an `(n, d)` float64 array and
/// returning `n` values, shape `(n,)` (or `(n, 1)`) for one output, `(n, m)` for `m`. The
/// first exception it raises (or a wrong shape) is kept, the run is cancelled, and every later
/// call returns NaN without calling it, so that the run stops at the next chunk and the
/// exception reaches the caller.
pub struct PyIntegrand {
    f: Py<PyAny>,
    outputs: usize,
    /// The measure an expectation is over: `f` then sees its points, and its weights
    /// multiply the values.
    measure: Option<Arc<dyn Measure>>,
    failure: Failure,
}

impl PyIntegrand {
    pub fn new(
        f: Py<PyAny>,
        outputs: usize,
        measure: Option<Arc<dyn Measure>>,
        cancel: CancelToken,
    ) -> Self {
        PyIntegrand {
            f,
            outputs,
            measure,
            failure: Failure::new(cancel),
        }
    }

    /// What stopped the run, if anything did: an exception of `f` (or a wrong shape), or a
    /// signal.
    pub fn failure(&self) -> &Failure {
        &self.failure
    }

    /// `g` on a block of points: `out[k * n + i]` is output `k` at point `i`.
    /// With a measure, `points` are canonical and `f` gets their images.
    pub fn batch(&self, points: &Points, out: &mut [f64]) {
        let n = points.len();
        let Some(measure) = &self.measure else {
            let d = points.dims();
            let mut columns = Vec::with_capacity(n * d);
            for k in 0..d {
                columns.extend_from_slice(points.column(k));
            }
            return self.call(None, columns, n, d, out);
        };
        let d = measure.dims();
        let (mut u, mut x) = (vec![0.0; measure.canonical_dims()], vec![0.0; d]);
        let mut columns = vec![0.0; n * d];
        let mut weights = vec![0.0; n];
        for (i, weight) in weights.iter_mut().enumerate() {
            points.copy_point(i, &mut u);
            *weight = measure.map(&u, &mut x);
            for (k, &v) in x.iter().enumerate() {
                columns[k * n + i] = v;
            }
        }
        self.call(None, columns, n, d, out);
        for column in out.chunks_exact_mut(n.max(1)) {
            for (y, &w) in column.iter_mut().zip(&weights) {
                *y *= w;
            }
        }
    }

    /// `f(level, u)` on a block of canonical points `u` of a multilevel model's level
    /// `level`: `out[k * n + i]` is output `k` at point `i`.
    pub fn level_batch(&self, level: usize, points: &Points, out: &mut [f64]) {
        let (n, d) = (points.len(), points.dims());
        let mut columns = Vec::with_capacity(n * d);
        for k in 0..d {
            columns.extend_from_slice(points.column(k));
        }
        self.call(Some(level), columns, n, d, out);
    }

    /// Calls `f` on `n` points given as `d` columns of `columns` (after `level`, when
    /// there is one), into `out`.
    fn call(&self, level: Option<usize>, columns: Vec<f64>, n: usize, d: usize, out: &mut [f64]) {
        if self.failure.happened() {
            out.fill(f64::NAN);
            return;
        }
        let called = Python::attach(|py| -> PyResult<()> {
            // Fortran order: each coordinate a contiguous column, as the library holds it.
            let x = PyArray1::from_vec(py, columns)
                .reshape_with_order([n, d], NPY_ORDER::NPY_FORTRANORDER)?;
            let f = self.f.bind(py);
            let y = match level {
                Some(level) => f.call1((level, x))?,
                None => f.call1((x,))?,
            };
            let y: PyReadonlyArrayDyn<f64> = match y.extract() {
                Ok(array) => array,
                // Another dtype, a list, a scalar: as numpy.asarray(y, dtype=float64).
                Err(_) => {
                    let numpy = py.import("numpy")?;
                    // numpy would drop the imaginary parts, with a warning only.
                    if numpy.call_method1("iscomplexobj", (&y,))?.is_truthy()? {
                        return Err(PyTypeError::new_err(
                            "the integrand returned complex values: expected real numbers \
                             (integrate the real and imaginary parts as two outputs)",
                        ));
                    }
                    numpy.call_method1("asarray", (&y, "float64"))?.extract()?
                }
            };
            let y = y.as_array();
            let m = self.outputs;
            match y.shape() {
                [rows] if *rows == n && m == 1 => {
                    out.iter_mut().zip(y.iter()).for_each(|(o, &v)| *o = v);
                }
                [rows, cols] if *rows == n && *cols == m => {
                    for ((i, k), &v) in y.indexed_iter().map(|(ix, v)| ((ix[0], ix[1]), v)) {
                        out[k * n + i] = v;
                    }
                }
                shape => {
                    let want = if m == 1 {
                        format!("({n},)")
                    } else {
                        format!("({n}, {m})")
                    };
                    let got: Vec<String> = shape.iter().map(usize::to_string).collect();
                    return Err(PyValueError::new_err(format!(
                        "the integrand returned shape ({}) for {n} points: expected {want}",
                        got.join(", ")
                    )));
                }
            }
            Ok(())
        });
        if let Err(error) = called {
            self.failure.fail(error);
            out.fill(f64::NAN);
        }
    }
}
