//! Python bindings of memsnav-core: conversions between numpy arrays and
//! core types, and mapping of core errors to Python exceptions. No numerics.

use pyo3::prelude::*;

#[allow(dead_code)] // per_axis and matrices3 wait for the inversion bindings
mod convert;
mod errors;
mod geodesy;
mod gnss;
mod ins;
mod progress;
mod sensors;
mod trajectory;

#[pymodule]
fn _memsnav(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    errors::register(m)?;
    geodesy::register(m)?;
    sensors::register(m)?;
    gnss::register(m)?;
    ins::register(m)?;
    trajectory::register(m)?;
    Ok(())
}
