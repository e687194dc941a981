//! Core warnings → Python: every binding whose core result carries a list
//! of warning sentences (calibration, coupled filters, `navigate_log`)
//! raises each as a `UserWarning` through [`warn_all`].

use std::ffi::CString;

use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;

/// Raises each of `warnings` as a Python `UserWarning` attributed to the
/// caller of the binding (stack level 2). Under `-W error` the first one
/// becomes the exception the binding returns.
pub(crate) fn warn_all(py: Python<'_>, warnings: &[String]) -> PyResult<()> {
    for w in warnings {
        let message = CString::new(w.replace('\0', " ")).unwrap_or_default();
        PyErr::warn(py, &py.get_type::<PyUserWarning>(), &message, 2)?;
    }
    Ok(())
}
