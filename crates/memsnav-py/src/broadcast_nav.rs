//! Broadcast ephemerides of several systems (GPS LNAV, Galileo I/NAV,
//! BeiDou D1), from a RINEX navigation file or a UBX log, for
//! ``RinexObservations.measurements``.

use std::path::PathBuf;

use memsnav_core::gnss::{self, BroadcastNav, GnssSystem};
use memsnav_py_macros::catch_panics;
use pyo3::prelude::*;

use crate::errors::IntoPyResult;

/// The RINEX name of `system`'s PRN `prn`.
fn name(system: GnssSystem, prn: u16) -> String {
    gnss::satellite_name(gnss::satellite_number(system, prn))
}

/// The broadcast ephemerides of GPS, Galileo and BeiDou satellites.
#[pyclass(name = "BroadcastEphemerides", module = "memsnav._memsnav", frozen)]
pub struct PyBroadcastEphemerides {
    pub inner: BroadcastNav,
}

#[catch_panics]
#[pymethods]
impl PyBroadcastEphemerides {
    /// The satellites with at least one ephemeris, RINEX names
    /// (``["C11", "E07", "G10", ...]``), sorted.
    #[getter]
    fn satellites(&self) -> Vec<String> {
        let n = &self.inner;
        let mut names: Vec<String> = n
            .gps
            .iter()
            .map(|e| name(GnssSystem::Gps, e.prn))
            .chain(n.galileo.iter().map(|e| name(GnssSystem::Galileo, e.svid)))
            .chain(n.beidou.iter().map(|e| name(GnssSystem::Beidou, e.prn)))
            .collect();
        names.sort();
        names.dedup();
        names
    }

    /// The satellites whose ephemerides say they are healthy, RINEX names.
    #[getter]
    fn healthy_satellites(&self) -> Vec<String> {
        let n = &self.inner;
        let mut names: Vec<String> = n
            .gps
            .iter()
            .filter(|e| e.health == 0)
            .map(|e| name(GnssSystem::Gps, e.prn))
            .chain(
                n.galileo
                    .iter()
                    .filter(|e| e.is_healthy())
                    .map(|e| name(GnssSystem::Galileo, e.svid)),
            )
            .chain(
                n.beidou
                    .iter()
                    .filter(|e| e.is_healthy())
                    .map(|e| name(GnssSystem::Beidou, e.prn)),
            )
            .collect();
        names.sort();
        names.dedup();
        names
    }

    /// Records left out, by reason, with counts (a RINEX file's other
    /// systems, Galileo F/NAV records).
    #[getter]
    fn skipped(&self) -> std::collections::BTreeMap<String, usize> {
        self.inner.skipped.clone()
    }

    /// Number of ephemeris records.
    fn __len__(&self) -> usize {
        self.inner.gps.len() + self.inner.galileo.len() + self.inner.beidou.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "BroadcastEphemerides(GPS {}, Galileo {}, BeiDou {} records)",
            self.inner.gps.len(),
            self.inner.galileo.len(),
            self.inner.beidou.len()
        )
    }
}

/// The GPS, Galileo and BeiDou ephemerides of a RINEX 2 or 3 navigation
/// file (other systems, Galileo F/NAV records and ephemerides in conflict,
/// two of one satellite and t_oc or issue of data with other values,
/// counted in ``skipped``).
#[catch_panics]
#[pyfunction]
fn read_broadcast_nav(py: Python<'_>, path: PathBuf) -> PyResult<PyBroadcastEphemerides> {
    Ok(PyBroadcastEphemerides {
        inner: py.detach(|| gnss::read_broadcast_nav(&path)).py()?,
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyBroadcastEphemerides>()?;
    m.add_function(wrap_pyfunction!(read_broadcast_nav, m)?)?;
    Ok(())
}
