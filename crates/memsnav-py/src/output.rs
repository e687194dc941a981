//! The solution writers and tables of `FilterSolution` and `LogRun`
//! (`memsnav_core::output`): arguments converted, the core called, its
//! columns handed to numpy, pandas or polars.

use std::path::PathBuf;

use memsnav_core::output::{self, LocalSolution, SolutionFormat, COLUMNS};
use numpy::PyArray1;
use pyo3::exceptions::PyImportError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::IntoPyResult;

/// `write(path, format, rate_hz, name, overwrite)` of either class.
pub fn write(
    py: Python<'_>,
    solution: &LocalSolution,
    path: PathBuf,
    format: Option<&str>,
    rate_hz: Option<f64>,
    name: Option<&str>,
    overwrite: bool,
) -> PyResult<()> {
    let format = format.map(SolutionFormat::from_name).transpose().py()?;
    py.detach(|| output::write_solution(&path, solution, format, rate_hz, name, overwrite))
        .py()
}

/// `columns(rate_hz)`: {column name: (N,) array}, in [`COLUMNS`] order.
pub fn columns<'py>(
    py: Python<'py>,
    solution: &LocalSolution,
    rate_hz: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let values = output::columns(solution, rate_hz).py()?;
    let d = PyDict::new(py);
    for (name, column) in COLUMNS.iter().zip(values) {
        d.set_item(name, PyArray1::from_vec(py, column))?;
    }
    Ok(d)
}

/// A `library.DataFrame` (pandas or polars) of [`columns`], or an
/// `ImportError` saying what to install.
pub fn data_frame<'py>(
    py: Python<'py>,
    solution: &LocalSolution,
    rate_hz: Option<f64>,
    library: &str,
    method: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let module = py.import(library).map_err(|_| {
        PyImportError::new_err(format!(
            "{method}() needs {library}, which is not installed: pip install {library} \
             (or use columns(), a dict of numpy arrays)"
        ))
    })?;
    module
        .getattr("DataFrame")?
        .call1((columns(py, solution, rate_hz)?,))
}

/// The indices of the samples kept at ``rate_hz`` (the first of each
/// 1/``rate_hz`` interval from the first sample; None: every one), as the
/// solution writers thin a solution.
#[memsnav_py_macros::catch_panics]
#[pyfunction]
#[pyo3(signature = (time, rate_hz=None))]
fn decimate<'py>(
    py: Python<'py>,
    time: &Bound<'py, PyAny>,
    rate_hz: Option<f64>,
) -> PyResult<Bound<'py, PyArray1<usize>>> {
    let time = crate::convert::scalars(time, "time")?;
    Ok(PyArray1::from_vec(
        py,
        output::decimate(&time, rate_hz).py()?,
    ))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(decimate, m)?)?;
    Ok(())
}
