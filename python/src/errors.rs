//! The library's errors as Python exceptions.

use pyo3::PyErr;
use pyo3::exceptions::{PyFloatingPointError, PyRuntimeError, PyValueError};

/// A library error as the exception a Python user expects: bad parameters are a
/// `ValueError` carrying the library's message (what was given and what is allowed) with the
/// keyword's name; an integrand that returned NaN or an infinity is a `FloatingPointError`;
/// a run that could not finish is a `RuntimeError`.
pub fn to_py(error: mcint::Error) -> PyErr {
    to_py_naming(error, &[])
}

/// [`to_py`] for a function whose keywords spell some of the library's names its own way
/// (`own`, looked up first: `d` for `dims` in the `qmc` engines).
pub fn to_py_naming(error: mcint::Error, own: &[(&str, &str)]) -> PyErr {
    match error {
        mcint::Error::NonFiniteContribution { .. } => {
            PyFloatingPointError::new_err(error.to_string())
        }
        mcint::Error::Interrupted { .. } | mcint::Error::IntegrandPanicked { .. } => {
            PyRuntimeError::new_err(error.to_string())
        }
        _ => PyValueError::new_err(error.message_with_names(&[own, KEYWORD_NAMES].concat())),
    }
}

/// The library's names of a run's settings as the keyword arguments spell them (the others
/// are spelled alike).
const KEYWORD_NAMES: &[(&str, &str)] = &[
    ("samples", "n"),
    ("points", "n"),
    ("tol_abs", "atol"),
    ("tol_rel", "rtol"),
];
