//! `PointSet`: any named sampler of the library, drawn from any index as numpy rows.

use mcint::Points;
use mcint::sampler::{Lloyd, PassKind, RandomCd, Sampler, SamplerKind, Scramble, lloyd, random_cd};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::{to_py, to_py_naming};

/// A sampler built by name: `kind` (one of `sampler_names()`), `d` dimensions, `size` points
/// for the samplers whose passes have a fixed size (0 for the sequences), a randomization
/// by name (`None` for the sampler's default), a strength for `oa-bush`, and a seed.
#[pyclass(module = "mcint._native", frozen)]
pub struct PointSet {
    sampler: Box<dyn Sampler>,
}

#[pymethods]
impl PointSet {
    #[new]
    #[pyo3(signature = (kind, d, size, scramble, seed, strength=None))]
    fn new(
        kind: &str,
        d: usize,
        size: u64,
        scramble: Option<&str>,
        seed: u64,
        strength: Option<u32>,
    ) -> PyResult<Self> {
        let kind: SamplerKind = kind.parse().map_err(to_py)?;
        let scramble = match scramble {
            Some(name) => name.parse::<Scramble>().map_err(to_py)?,
            None => kind.default_scramble(),
        };
        let sampler = kind
            .build_with(d, size, scramble, strength, seed)
            .map_err(|e| to_py_naming(e, &[("dims", "d")]))?;
        Ok(PointSet { sampler })
    }

    /// Points `start .. start + n` as an `(n, d)` array of rows (C order), generated with
    /// the interpreter's lock released.
    fn fill<'py>(
        &self,
        py: Python<'py>,
        start: u64,
        n: usize,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let d = self.sampler.dims();
        start.checked_add(n as u64).ok_or_else(|| {
            PyValueError::new_err(format!(
                "invalid point index {start} + {n}: the indices must stay below 2^64"
            ))
        })?;
        let rows = py.detach(|| -> mcint::Result<Vec<f64>> {
            let mut block = Points::new(d, n)?;
            self.sampler.fill(start, &mut block)?;
            let mut rows = vec![0.0; n * d];
            for k in 0..d {
                for (i, &x) in block.column(k).iter().enumerate() {
                    rows[i * d + k] = x;
                }
            }
            Ok(rows)
        });
        let rows = rows.map_err(to_py)?;
        PyArray1::from_vec(py, rows).reshape([n, d])
    }

    /// The sampler's name.
    #[getter]
    fn name(&self) -> &'static str {
        self.sampler.name()
    }

    /// The dimension.
    #[getter]
    fn d(&self) -> usize {
        self.sampler.dims()
    }

    /// Whether the points are randomized (a scramble, a shift, or built-in randomness).
    #[getter]
    fn randomized(&self) -> bool {
        self.sampler.is_randomized()
    }

    /// How the points come: `("independent", 0)`, `("fixed", size)` or
    /// `("extensible", max)`.
    #[getter]
    fn passes(&self) -> (&'static str, u64) {
        match self.sampler.passes() {
            PassKind::Independent => ("independent", 0),
            PassKind::Fixed { size } => ("fixed", size),
            PassKind::Extensible { max } => ("extensible", max),
        }
    }
}

/// The names `PointSet` accepts.
#[pyfunction]
pub fn sampler_names() -> Vec<&'static str> {
    SamplerKind::ALL.iter().map(|k| k.name()).collect()
}

/// The randomizations `PointSet` accepts by name.
#[pyfunction]
pub fn scramble_names() -> Vec<&'static str> {
    Scramble::ALL.iter().map(|s| s.name()).collect()
}

/// How the points of sampler `name` come, without building it: `"independent"`,
/// `"extensible"` (sequences: any prefix of a pass) or `"fixed"` (sets of a given size); and
/// its default randomization (`"none"` where the randomization is built in).
#[pyfunction]
pub fn sampler_info(name: &str) -> PyResult<(&'static str, &'static str)> {
    let kind: SamplerKind = name.parse().map_err(to_py)?;
    let passes = match kind {
        SamplerKind::Independent => "independent",
        SamplerKind::Sobol | SamplerKind::Halton | SamplerKind::Lattice | SamplerKind::Pmj02 => {
            "extensible"
        }
        _ => "fixed",
    };
    Ok((passes, kind.default_scramble().name()))
}

/// `points` (an `(n, d)` array in `[0, 1]^d`) optimized as scipy's engines do with
/// `optimization=`: `"random-cd"` (swaps within columns that lower the centered discrepancy,
/// scipy's 10,000 tries and patience 100) or `"lloyd"` (10 Lloyd relaxation steps), the
/// random choices drawn from `seed`; computed with the interpreter's lock released.
#[pyfunction]
pub fn optimize<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    method: &str,
    seed: u64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let view = points.as_array();
    let (n, d) = view.dim();
    let mut block = Points::new(d.max(1), n).map_err(to_py)?;
    for k in 0..d {
        for (x, &v) in block.column_mut(k).iter_mut().zip(view.column(k)) {
            *x = v;
        }
    }
    let optimized = py.detach(|| -> mcint::Result<Points> {
        match method {
            "random-cd" => random_cd(&mut block, RandomCd::default(), seed).map(|_| ()),
            "lloyd" => {
                let settings = Lloyd {
                    seed,
                    ..Lloyd::default()
                };
                lloyd(&mut block, settings).map(|_| ())
            }
            other => Err(mcint::Error::invalid(
                "optimization",
                other,
                "None, 'random-cd' or 'lloyd'",
            )),
        }?;
        Ok(block)
    });
    let block = optimized.map_err(to_py)?;
    let mut rows = vec![0.0; n * d];
    for k in 0..d {
        for (i, &x) in block.column(k).iter().enumerate() {
            rows[i * d + k] = x;
        }
    }
    PyArray1::from_vec(py, rows).reshape([n, d])
}
