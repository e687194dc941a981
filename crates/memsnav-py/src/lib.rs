//! Python bindings of memsnav-core: conversions between numpy arrays and
//! core types, and mapping of core errors to Python exceptions. No numerics.

use pyo3::prelude::*;

mod aiding;
mod allan;
mod arguments;
mod broadcast_nav;
mod calibration;
mod calibration_drive;
mod calibration_layout;
mod convert;
mod coupling;
mod defaults;
mod ephemeris_dicts;
mod errors;
mod experiments;
mod geodesy;
mod gnss;
mod gnsslogger;
mod ins;
mod inversion;
mod log_navigation;
mod logs;
mod montecarlo;
mod navigation;
mod output;
mod progress;
mod random;
mod records;
mod result_record;
mod running_filter;
mod satellite_names;
mod sensors;
mod static_calibration;
mod trajectory;
mod ubx;
mod warnings;

#[pymodule]
fn _memsnav(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    errors::register(m)?;
    geodesy::register(m)?;
    sensors::register(m)?;
    gnss::register(m)?;
    broadcast_nav::register(m)?;
    ins::register(m)?;
    trajectory::register(m)?;
    calibration::register(m)?;
    calibration_layout::register(m)?;
    calibration_drive::register(m)?;
    allan::register(m)?;
    static_calibration::register(m)?;
    inversion::register(m)?;
    experiments::register(m)?;
    aiding::register(m)?;
    coupling::register(m)?;
    running_filter::register(m)?;
    defaults::register(m)?;
    navigation::register(m)?;
    log_navigation::register(m)?;
    output::register(m)?;
    logs::register(m)?;
    montecarlo::register(m)?;
    gnsslogger::register(m)?;
    ubx::register(m)?;
    random::register(m)?;
    arguments::register(m)?;
    Ok(())
}
