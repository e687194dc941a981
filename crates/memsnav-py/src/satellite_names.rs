//! Satellites and systems named as RINEX names them (`"G10"`, `"E"`):
//! what the GNSS readers and the broadcast ephemerides take from Python.

use memsnav_core::gnss;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The system of a RINEX letter, or an error naming `argument`.
pub(crate) fn system_of_letter(letter: &str, argument: &str) -> PyResult<gnss::GnssSystem> {
    let mut chars = letter.chars();
    match (chars.next(), chars.next()) {
        (Some(c), None) => gnss::GnssSystem::from_letter(c),
        _ => None,
    }
    .ok_or_else(|| {
        PyValueError::new_err(format!(
            "{argument}: {letter:?} is not a system combined here (G GPS, E Galileo, C BeiDou, R GLONASS)"
        ))
    })
}

/// The system and PRN (GLONASS slot) of a RINEX name (``"R05"``).
pub(crate) fn satellite_key(name: &str) -> PyResult<(gnss::GnssSystem, u16)> {
    let number = satellite_of_name(name)?;
    Ok((gnss::system_of_number(number), number % 100))
}

/// The satellite number of a RINEX name (``"E07"`` → 107).
pub(crate) fn satellite_of_name(name: &str) -> PyResult<u16> {
    let bad = || {
        PyValueError::new_err(format!(
            "satellites: {name:?} is not a satellite name like \"G10\", \"E07\", \"C21\" or \"R05\""
        ))
    };
    let system = system_of_letter(name.get(..1).ok_or_else(bad)?, "satellites")?;
    let prn: u16 = name.get(1..).and_then(|p| p.parse().ok()).ok_or_else(bad)?;
    if !(1..=99).contains(&prn) {
        return Err(bad());
    }
    Ok(gnss::satellite_number(system, prn))
}
