//! Python bindings of memsnav-core: conversions between numpy arrays and
//! core types, and mapping of core errors to Python exceptions. No numerics.

use pyo3::prelude::*;

// per_axis, scalars, matrices3, matrices3_to_numpy: for the trajectory, INS and calibration bindings.
#[allow(dead_code)] // until the INS and inversion bindings use per_axis and matrices3
mod convert;
mod errors;
mod geodesy;
mod gnss;
mod ins;
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
