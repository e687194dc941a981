//! Python bindings of memsnav-core: conversions between numpy arrays and
//! core types, and mapping of core errors to Python exceptions. No numerics.

use pyo3::prelude::*;

#[allow(dead_code)] // TEMPORARY: used by the sensor bindings (issue 2).
mod convert;
mod errors;
mod geodesy;
mod progress;

#[pymodule]
fn _memsnav(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    errors::register(m)?;
    geodesy::register(m)?;
    Ok(())
}
