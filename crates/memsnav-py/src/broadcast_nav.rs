//! Broadcast ephemerides of several systems (GPS LNAV, Galileo I/NAV,
//! BeiDou D1, GLONASS), from a RINEX navigation file or a UBX log, for
//! ``RinexObservations.measurements`` and satellite states at given times.

use std::path::PathBuf;

use memsnav_core::gnss::{self, BroadcastNav, GnssSystem};
use memsnav_py_macros::catch_panics;
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::IntoPyResult;

/// The RINEX name of `system`'s PRN `prn`.
fn name(system: GnssSystem, prn: u16) -> String {
    gnss::satellite_name(gnss::satellite_number(system, prn))
}

/// Broadcast ephemerides of GPS, Galileo, BeiDou and GLONASS satellites
/// (read_broadcast_nav, UbxLog.broadcast_ephemerides).
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
            .chain(n.glonass.iter().map(|e| name(GnssSystem::Glonass, e.slot)))
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
            .chain(
                n.glonass
                    .iter()
                    .filter(|e| e.is_healthy())
                    .map(|e| name(GnssSystem::Glonass, e.slot)),
            )
            .collect();
        names.sort();
        names.dedup();
        names
    }

    /// Records left out, by reason, with counts (a RINEX file's other
    /// systems, Galileo F/NAV records, repeated GLONASS records).
    #[getter]
    fn skipped(&self) -> std::collections::BTreeMap<String, usize> {
        self.inner.skipped.clone()
    }

    /// The GPS Klobuchar coefficients ``(alpha, beta)`` the ephemerides
    /// carry (a RINEX header's, a UBX log's CNAV type 30), or None:
    /// ``measurements``' default.
    #[getter]
    fn klobuchar(&self) -> Option<([f64; 4], [f64; 4])> {
        self.inner.klobuchar.map(|k| (k.alpha, k.beta))
    }

    /// The GPS CNAV ephemerides (a RINEX 4 file's ``CNAV`` records, a UBX
    /// log's L2C/L5 messages), dicts as ``UbxLog.gps_cnav_ephemerides``;
    /// those with an L1 C/A group delay are among the GPS ephemerides the
    /// measurements use too.
    #[getter]
    fn gps_cnav_ephemerides<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.inner
            .gps_cnav
            .iter()
            .map(|e| crate::ephemeris_dicts::cnav_dict(py, e))
            .collect()
    }

    /// Each GLONASS slot's FDMA frequency channel k (G1 = 1602 + 0.5625 k
    /// MHz), from its latest ephemeris: ``{"R01": 1, ...}``.
    #[getter]
    fn glonass_channels(&self) -> std::collections::BTreeMap<String, i8> {
        self.inner
            .glonass
            .iter()
            .map(|e| (name(GnssSystem::Glonass, e.slot), e.frequency_channel))
            .collect()
    }

    /// Satellite positions, velocities (ECEF, m, m/s) and clock
    /// corrections (s) at GPS times ``gps_time`` (s since 1980-01-06, a
    /// number or ``(T,)``) of ``satellites`` (RINEX names, default
    /// ``satellites``), from the healthy ephemeris the measurements would
    /// use: ``(position (T, S, 3), velocity (T, S, 3), clock (T, S))``, one
    /// time's ``(S, 3), (S, 3), (S,)`` for a number. NaN where no
    /// ephemeris covers the time (t_oe within 2 h; GLONASS t_b within 30
    /// min), counted in a ``UserWarning``. Clocks are for GPS L1 C/A,
    /// Galileo E1, BeiDou B3I and GLONASS G1, relativity included.
    #[pyo3(signature = (gps_time, satellites=None))]
    fn satellite_states<'py>(
        &self,
        py: Python<'py>,
        gps_time: &Bound<'py, PyAny>,
        satellites: Option<Vec<String>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (times, scalar) = gps_times(gps_time)?;
        let names = match satellites {
            Some(names) => names,
            None => self.satellites()?,
        };
        let keys = names
            .iter()
            .map(|n| crate::satellite_names::satellite_key(n))
            .collect::<PyResult<Vec<_>>>()?;
        let states = py.detach(|| gnss::broadcast_states(&self.inner, &keys, &times));
        states_to_python(py, &states, times.len(), scalar, "no ephemeris covering")
    }

    /// Number of ephemeris records.
    fn __len__(&self) -> usize {
        self.inner.gps.len()
            + self.inner.galileo.len()
            + self.inner.beidou.len()
            + self.inner.glonass.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "BroadcastEphemerides(GPS {}, Galileo {}, BeiDou {}, GLONASS {} records)",
            self.inner.gps.len(),
            self.inner.galileo.len(),
            self.inner.beidou.len(),
            self.inner.glonass.len()
        )
    }
}

/// The GPS, Galileo, BeiDou and GLONASS ephemerides of a RINEX 2 (GPS
/// ``n``, GLONASS ``g``, 2.12 Galileo ``e``) or RINEX 3 navigation file
/// (other systems, Galileo F/NAV records and ephemerides in conflict, two
/// of one satellite and t_oc or issue of data with other values, counted
/// in ``skipped``).
///
/// `path`: the file to read (str or path-like).
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

/// `gps_time` as times, and whether it was one number.
pub(crate) fn gps_times(gps_time: &Bound<'_, PyAny>) -> PyResult<(Vec<f64>, bool)> {
    let times = match gps_time.extract::<f64>() {
        Ok(t) => (vec![t], true),
        Err(_) => (
            gps_time
                .extract::<numpy::PyReadonlyArray1<f64>>()
                .map_err(|_| {
                    PyValueError::new_err("gps_time: expected a number or a (T,) float array")
                })?
                .as_slice()?
                .to_vec(),
            false,
        ),
    };
    if let Some(bad) = times.0.iter().find(|t| !t.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "gps_time: must be finite, got {bad}"
        )));
    }
    Ok(times)
}

/// Satellite states `[time][satellite]` as (position, velocity, clock)
/// arrays, `(T, S, 3), (T, S, 3), (T, S)` or one time's `(S, 3), (S, 3),
/// (S,)`; NaN where `None`, counted in a `UserWarning` that says `why`.
pub(crate) fn states_to_python<'py>(
    py: Python<'py>,
    states: &[Option<gnss::SatelliteState>],
    n_times: usize,
    scalar: bool,
    why: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let missing = states.iter().filter(|s| s.is_none()).count();
    if missing > 0 {
        crate::warnings::warn_all(
            py,
            &[format!(
                "{missing} of {} satellite states have {why} their time: NaN",
                states.len()
            )],
        )?;
    }
    let nan = [f64::NAN; 3];
    let mut position = Vec::with_capacity(3 * states.len());
    let mut velocity = Vec::with_capacity(3 * states.len());
    let mut clock = Vec::with_capacity(states.len());
    for s in states {
        position.extend(s.map_or(nan, |s| s.position_ecef.into()));
        velocity.extend(s.map_or(nan, |s| s.velocity_ecef.into()));
        clock.push(s.map_or(f64::NAN, |s| s.clock_bias_s));
    }
    let n = states.len().checked_div(n_times).unwrap_or(0);
    if scalar {
        let p = PyArray1::from_vec(py, position).reshape([n, 3])?;
        let v = PyArray1::from_vec(py, velocity).reshape([n, 3])?;
        let c = PyArray1::from_vec(py, clock);
        return Ok((p, v, c).into_pyobject(py)?.into_any());
    }
    let p: Bound<'py, PyArray3<f64>> = PyArray1::from_vec(py, position).reshape([n_times, n, 3])?;
    let v: Bound<'py, PyArray3<f64>> = PyArray1::from_vec(py, velocity).reshape([n_times, n, 3])?;
    let c: Bound<'py, PyArray2<f64>> = PyArray1::from_vec(py, clock).reshape([n_times, n])?;
    Ok((p, v, c).into_pyobject(py)?.into_any())
}
