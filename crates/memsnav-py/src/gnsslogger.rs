//! Android GnssLogger files: the `Raw` records as observations, the
//! phone's uncalibrated accelerometer and gyro as an IMU log.

use std::collections::BTreeMap;
use std::path::PathBuf;

use memsnav_core::logs;
use memsnav_py_macros::catch_panics;
use pyo3::prelude::*;

use crate::errors::IntoPyResult;
use crate::gnss::PyRinexObservations;
use crate::logs::PyImuLog;

/// What an Android GnssLogger file holds (``read_gnsslogger``).
#[pyclass(name = "GnssLoggerLog", module = "memsnav._memsnav", frozen)]
pub struct PyGnssLoggerLog {
    observations: Py<PyRinexObservations>,
    imu: Option<Py<PyImuLog>>,
    skipped: BTreeMap<String, usize>,
    warnings: Vec<String>,
}

#[catch_panics]
#[pymethods]
impl PyGnssLoggerLog {
    fn __repr__(&self, py: Python<'_>) -> String {
        let epochs = self.observations.borrow(py).inner.epochs.len();
        let skipped: usize = self.skipped.values().sum();
        format!(
            "GnssLoggerLog({epochs} epochs, {}, {skipped} records skipped, {} warnings)",
            if self.imu.is_some() {
                "with IMU"
            } else {
                "no IMU"
            },
            self.warnings.len()
        )
    }

    /// The ``Raw`` records as observations (the class ``read_rinex_obs``
    /// returns): per signal ``C`` pseudorange m, ``L`` carrier cycles
    /// (valid accumulated delta range only), ``D`` Doppler Hz, ``S`` C/N0
    /// dB-Hz, RINEX 3 codes (``C1C``, ``C5Q``, ...), epochs on GPS time.
    #[getter]
    fn observations(&self, py: Python<'_>) -> Py<PyRinexObservations> {
        self.observations.clone_ref(py)
    }

    /// ``UncalAccel`` with ``UncalGyro`` interpolated to its times, on GPS
    /// time, Android sensor axes (x right, y up, z out of the screen), the
    /// phone's bias estimates not applied; None without both sensors or
    /// without a ``Raw`` record tying their clock to GPS time.
    #[getter]
    fn imu(&self, py: Python<'_>) -> Option<Py<PyImuLog>> {
        self.imu.as_ref().map(|i| i.clone_ref(py))
    }

    /// ``Raw`` measurements left out, counted by reason (no code lock, time
    /// of week not decoded, SBAS, ...).
    #[getter]
    fn skipped(&self) -> BTreeMap<String, usize> {
        self.skipped.clone()
    }

    /// Non-fatal problems met while reading.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }
}

/// Reads an Android GnssLogger file (``gnss_log_*.txt``): pseudoranges
/// from the ``Raw`` records' clock and satellite times per constellation
/// (GPS, Galileo, BeiDou weeks, the GLONASS day), only where the
/// measurement ``State`` makes them unambiguous (the rest counted in
/// ``skipped``); errors name the file and the line.
///
/// `path`: the file to read (str or path-like).
#[catch_panics]
#[pyfunction]
fn read_gnsslogger(py: Python<'_>, path: PathBuf) -> PyResult<PyGnssLoggerLog> {
    let log = py.detach(|| logs::read_gnsslogger(&path)).py()?;
    Ok(PyGnssLoggerLog {
        observations: Py::new(
            py,
            PyRinexObservations {
                inner: log.observations,
            },
        )?,
        imu: log
            .imu
            .map(|inner| Py::new(py, PyImuLog { inner }))
            .transpose()?,
        skipped: log.skipped,
        warnings: log.warnings,
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyGnssLoggerLog>()?;
    m.add_function(wrap_pyfunction!(read_gnsslogger, m)?)?;
    Ok(())
}
