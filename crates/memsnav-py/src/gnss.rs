//! GNSS bindings: constellations, SP3, measurement simulation and the
//! least-squares fix. Conversions and error mapping only.

use std::borrow::Cow;
use std::path::PathBuf;

use memsnav_core::gnss::{
    self, Constellation, GnssEpoch, SatelliteMeasurement, SimulationConfig, WalkerConfig,
};
use memsnav_core::Error;
use memsnav_core::{logs, random};
use memsnav_py_macros::catch_panics;
use nalgebra::{Matrix4, Vector3};
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arguments::{
    check_keys, field, floats_with_nan, no_epochs, optional_field, shape_error,
};
use crate::broadcast_nav::PyBroadcastEphemerides;
use crate::convert;
use crate::errors::IntoPyResult;
use crate::satellite_names::{satellite_of_name, system_of_letter};

fn array2<'py>(
    py: Python<'py>,
    flat: Vec<f64>,
    rows: usize,
    cols: usize,
) -> Bound<'py, PyArray2<f64>> {
    PyArray1::from_vec(py, flat)
        .reshape([rows, cols])
        .expect("rows × cols elements by construction")
}

fn array3<'py>(
    py: Python<'py>,
    flat: Vec<f64>,
    a: usize,
    b: usize,
    c: usize,
) -> Bound<'py, PyArray3<f64>> {
    PyArray1::from_vec(py, flat)
        .reshape([a, b, c])
        .expect("a × b × c elements by construction")
}

fn matrices4<'py>(py: Python<'py>, ms: &[Matrix4<f64>]) -> Bound<'py, PyArray3<f64>> {
    let flat: Vec<f64> = ms
        .iter()
        .flat_map(|m| m.transpose().as_slice().to_vec())
        .collect();
    array3(py, flat, ms.len(), 4, 4)
}

/// Positions and velocities as two `(n, 3)` arrays.
type ArrayPair<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>);

/// GPS satellites from broadcast ephemerides, or synthetic Walker
/// constellations (GPS, or several systems: :meth:`nominal`).
///
/// Times are GPS seconds since 1980-01-06 00:00:00 GPST; positions ECEF m,
/// velocities m/s.
#[pyclass(name = "Constellation", module = "memsnav._memsnav", frozen)]
pub struct PyConstellation {
    pub inner: Constellation,
}

#[catch_panics]
#[pymethods]
impl PyConstellation {
    /// GPS ephemerides of a RINEX 2 or 3 navigation file (other systems skipped).
    ///
    /// Raises ParseError naming the file and the 1-based line for unreadable
    /// or truncated records.
    #[staticmethod]
    fn from_rinex_nav(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let inner = py.detach(|| Constellation::from_rinex_nav(&path)).py()?;
        Ok(PyConstellation { inner })
    }

    /// A Walker delta constellation i: t/p/f of circular orbits.
    ///
    /// None takes the core's default (`defaults()`), the GPS-like pattern:
    ///
    /// - `n_satellites` t [24], `planes` p [6] and `phasing` f [1].
    /// - `inclination_deg` i, degrees [55].
    /// - `semi_major_axis_m`: the orbits' radius, m [26 560 km].
    /// - `raan0_deg`: the first plane's right ascension, degrees [0].
    #[staticmethod]
    #[pyo3(signature = (n_satellites=None, planes=None, inclination_deg=None, semi_major_axis_m=None, phasing=None, raan0_deg=None))]
    fn walker(
        n_satellites: Option<usize>,
        planes: Option<usize>,
        inclination_deg: Option<f64>,
        semi_major_axis_m: Option<f64>,
        phasing: Option<usize>,
        raan0_deg: Option<f64>,
    ) -> PyResult<Self> {
        let d = WalkerConfig::default();
        let config = WalkerConfig {
            n_satellites: n_satellites.unwrap_or(d.n_satellites),
            planes: planes.unwrap_or(d.planes),
            inclination_rad: inclination_deg.map_or(d.inclination_rad, f64::to_radians),
            semi_major_axis_m: semi_major_axis_m.unwrap_or(d.semi_major_axis_m),
            phasing: phasing.unwrap_or(d.phasing),
            raan0_rad: raan0_deg.map_or(d.raan0_rad, f64::to_radians),
            ..d
        };
        Ok(PyConstellation {
            inner: Constellation::walker(&config).py()?,
        })
    }

    /// The nominal Walker constellations of ``systems`` (RINEX letters, in
    /// this order): "G" GPS 24/6/1 at a = 26 560 km, 55°; "E" Galileo 24/3/1
    /// at 29 599.8 km, 56° (period 14 h 4 min); "C" BeiDou MEO 24/3/1 at
    /// 27 906.1 km, 55° (12 h 53 min; no GEO or IGSO satellites); "R"
    /// GLONASS 24/3/1 at 25 510 km, 64.8° (11 h 16 min; slots on the current
    /// FDMA channel plan). Satellites are numbered G 1-24, E 101-124,
    /// C 201-224, R 301-324 (``sat_id``) and named G01, E01, C01, R01, ...
    /// (``prns``). ``nominal(["G"])`` is
    /// ``walker()``.
    ///
    /// Raises ValueError for an unknown letter or a system named twice.
    #[staticmethod]
    fn nominal(systems: Vec<String>) -> PyResult<Self> {
        Ok(PyConstellation {
            inner: Constellation::nominal_walkers(&system_letters(&systems)?).py()?,
        })
    }

    /// Satellite names, e.g. ["G01", "G02", ...] (Walker slots are named
    /// like their system's PRNs: G01..GNN, E01.., C01..).
    #[getter]
    fn prns(&self) -> Vec<String> {
        self.inner.prns()
    }

    /// The satellite systems, as RINEX letters in the constellation's order.
    #[getter]
    fn systems(&self) -> Vec<String> {
        self.inner
            .systems()
            .into_iter()
            .map(|s| s.letter().to_string())
            .collect()
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    fn __repr__(&self) -> String {
        let kind = match self.inner {
            Constellation::Broadcast { .. } => "broadcast",
            Constellation::Walker(_) => "walker",
        };
        format!("Constellation({kind}, {} satellites)", self.inner.len())
    }

    /// ECEF positions (m) and velocities (m/s), each ``(n_sat, 3)``, at
    /// ``gps_time`` (s since 1980-01-06 GPST); NaN rows without a valid ephemeris.
    fn position_velocity<'py>(&self, py: Python<'py>, gps_time: f64) -> PyResult<ArrayPair<'py>> {
        let (p, v) = self.inner.position_velocity(gps_time).py()?;
        Ok((
            convert::vectors_to_numpy(py, &p),
            convert::vectors_to_numpy(py, &v),
        ))
    }

    /// Satellite clock corrections Δt_sv (s, L1 C/A: relativistic term and
    /// −T_GD included) at ``gps_time``; NaN without a valid ephemeris.
    fn clock_correction<'py>(
        &self,
        py: Python<'py>,
        gps_time: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_vec(
            py,
            self.inner.clock_correction(gps_time).py()?,
        ))
    }
}

/// The systems of RINEX letters ("G", "E", "C", "R"); ValueError names
/// `systems` and the letter.
pub(crate) fn system_letters(letters: &[String]) -> PyResult<Vec<gnss::GnssSystem>> {
    letters
        .iter()
        .map(|letter| {
            let mut chars = letter.chars();
            match (
                chars.next().and_then(gnss::GnssSystem::from_letter),
                chars.next(),
            ) {
                (Some(system), None) => Ok(system),
                _ => Err(PyValueError::new_err(format!(
                    "systems: expected the letters \"G\", \"E\", \"C\" or \"R\", got {letter:?}"
                ))),
            }
        })
        .collect()
}

/// Precise orbits from an SP3 file (centre of mass), in SI units.
#[pyclass(name = "Sp3", module = "memsnav._memsnav", frozen)]
pub struct PySp3 {
    inner: gnss::Sp3,
}

#[catch_panics]
#[pymethods]
impl PySp3 {
    fn __repr__(&self) -> String {
        let t = &self.inner.time_gps_s;
        format!(
            "Sp3({} satellites, {} epochs, GPS time {:.0}-{:.0} s)",
            self.inner.satellites.len(),
            t.len(),
            t.first().copied().unwrap_or(f64::NAN),
            t.last().copied().unwrap_or(f64::NAN)
        )
    }

    /// Epochs, GPS s since 1980-01-06, ``(n_epochs,)``.
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.time_gps_s)
    }

    /// Satellite names as in the file ("G01", "E05", ...).
    #[getter]
    fn satellites(&self) -> Vec<String> {
        self.inner.satellites.clone()
    }

    /// Centre-of-mass positions, ECEF m, ``(n_epochs, n_sat, 3)``; NaN if missing.
    #[getter]
    fn position_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        let flat = self
            .inner
            .position_ecef
            .iter()
            .flat_map(|v| [v.x, v.y, v.z])
            .collect();
        array3(
            py,
            flat,
            self.inner.time_gps_s.len(),
            self.inner.satellites.len(),
            3,
        )
    }

    /// Positions, velocities (ECEF, m, m/s) and clocks (s) at GPS times
    /// ``gps_time`` (a number or ``(T,)``) of ``satellites`` (names, default
    /// ``satellites``): 10-point Lagrange interpolation of the positions
    /// and its derivative, the clock linear between epochs. Shapes as
    /// ``BroadcastEphemerides.satellite_states``; NaN outside the file's
    /// epochs or where a position is missing, counted in a ``UserWarning``.
    #[pyo3(signature = (gps_time, satellites=None))]
    fn satellite_states<'py>(
        &self,
        py: Python<'py>,
        gps_time: &Bound<'py, PyAny>,
        satellites: Option<Vec<String>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (times, scalar) = crate::broadcast_nav::gps_times(gps_time)?;
        let columns = match satellites {
            None => (0..self.inner.satellites.len()).collect(),
            Some(names) => names
                .iter()
                .map(|name| {
                    self.inner
                        .satellites
                        .iter()
                        .position(|s| s == name)
                        .ok_or_else(|| {
                            PyValueError::new_err(format!(
                                "satellites: {name:?} is not in the file"
                            ))
                        })
                })
                .collect::<PyResult<Vec<usize>>>()?,
        };
        let states: Vec<_> = py.detach(|| {
            times
                .iter()
                .flat_map(|&t| columns.iter().map(move |&j| self.inner.state_at(j, t)))
                .collect()
        });
        crate::broadcast_nav::states_to_python(
            py,
            &states,
            times.len(),
            scalar,
            "no precise orbit around",
        )
    }

    /// Satellite clocks, s, ``(n_epochs, n_sat)``; NaN if missing.
    #[getter]
    fn clock<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        array2(
            py,
            self.inner.clock_s.clone(),
            self.inner.time_gps_s.len(),
            self.inner.satellites.len(),
        )
    }
}

/// Reads an SP3-c/d precise orbit file (GPS time; km and µs converted to m and s).
///
/// `path`: the file to read (str or path-like).
#[catch_panics]
#[pyfunction]
fn read_sp3(py: Python<'_>, path: PathBuf) -> PyResult<PySp3> {
    Ok(PySp3 {
        inner: py.detach(|| gnss::read_sp3(&path)).py()?,
    })
}

/// Simulated measurements; per-epoch arrays padded to n_max = n_satellites
/// (NaN for values, -1 for sat_id, where fewer satellites are tracked).
#[pyclass(name = "GnssMeasurements", module = "memsnav._memsnav", frozen)]
pub struct PyGnssMeasurements {
    pub(crate) epochs: Vec<GnssEpoch>,
    clock: Vec<gnss::ClockState>,
    start_gps_time_s: f64,
    inter_system_bias_m: [f64; gnss::INTER_SYSTEM_BIAS_SYSTEMS.len()],
    cycle_slips: Vec<gnss::CycleSlip>,
    n_max: usize,
    /// Beside each measurement, what it was made from (measurements built
    /// from observations only).
    signals: Option<gnss::EpochSignals>,
}

impl PyGnssMeasurements {
    /// A per-measurement value of `signals`, NaN-padded; None without them.
    fn padded_signal<'py>(
        &self,
        py: Python<'py>,
        f: impl Fn(&gnss::ReceivedSignal) -> f64,
    ) -> Option<Bound<'py, PyArray2<f64>>> {
        let signals = self.signals.as_ref()?;
        let mut flat = vec![f64::NAN; self.epochs.len() * self.n_max];
        for (k, epoch) in signals.iter().enumerate() {
            for (j, signal) in epoch.iter().enumerate() {
                flat[k * self.n_max + j] = f(signal);
            }
        }
        Some(array2(py, flat, self.epochs.len(), self.n_max))
    }

    fn padded<'py>(
        &self,
        py: Python<'py>,
        f: impl Fn(&gnss::SatelliteMeasurement) -> f64,
    ) -> Bound<'py, PyArray2<f64>> {
        let mut flat = vec![f64::NAN; self.epochs.len() * self.n_max];
        for (k, e) in self.epochs.iter().enumerate() {
            for (j, m) in e.measurements.iter().enumerate() {
                flat[k * self.n_max + j] = f(m);
            }
        }
        array2(py, flat, self.epochs.len(), self.n_max)
    }

    fn padded_vectors<'py>(
        &self,
        py: Python<'py>,
        f: impl Fn(&gnss::SatelliteMeasurement) -> Vector3<f64>,
    ) -> Bound<'py, PyArray3<f64>> {
        let mut flat = vec![f64::NAN; self.epochs.len() * self.n_max * 3];
        for (k, e) in self.epochs.iter().enumerate() {
            for (j, m) in e.measurements.iter().enumerate() {
                let v = f(m);
                flat[(k * self.n_max + j) * 3..][..3].copy_from_slice(v.as_slice());
            }
        }
        array3(py, flat, self.epochs.len(), self.n_max, 3)
    }
}

#[catch_panics]
#[pymethods]
impl PyGnssMeasurements {
    fn __repr__(&self) -> String {
        let satellites: std::collections::BTreeSet<u16> = self
            .epochs
            .iter()
            .flat_map(|e| e.measurements.iter().map(|m| m.sat_id))
            .collect();
        let span = match (self.epochs.first(), self.epochs.last()) {
            (Some(a), Some(b)) => format!(", {:.3}-{:.3} s", a.time_s, b.time_s),
            _ => String::new(),
        };
        format!(
            "GnssMeasurements({} epochs{span}, {} satellites)",
            self.epochs.len(),
            satellites.len()
        )
    }

    /// Measurements from padded arrays: ``time`` (T,) s, ``sat_id`` (T, n)
    /// (negative: an empty slot), ``satellite_position_ecef`` and
    /// ``satellite_velocity_ecef`` (T, n, 3) at transmission, m and m/s,
    /// ``pseudorange`` (T, n) m (satellite clock corrected),
    /// ``pseudorange_std`` (T, n) m, optional ``pseudorange_rate`` with
    /// ``pseudorange_rate_std`` (T, n) m/s, optional ``carrier_phase`` with
    /// ``carrier_phase_std`` (T, n) m (the carrier range λ·φ, corrected as
    /// the pseudorange with the ionosphere's sign reversed) and
    /// ``loss_of_lock`` (T, n) bool; ``start_gps_time``: the GPS time of
    /// ``time[0]`` (None: ``time`` is GPS time). NaN is refused in every
    /// non-empty slot except a rate or a carrier phase (NaN: none there);
    /// ValueError names the slot.
    #[new]
    #[pyo3(signature = (time, sat_id, satellite_position_ecef, satellite_velocity_ecef, pseudorange,
        pseudorange_std, pseudorange_rate=None, pseudorange_rate_std=None, *, start_gps_time=None,
        carrier_phase=None, carrier_phase_std=None, loss_of_lock=None))]
    fn new(
        py: Python<'_>,
        time: &Bound<'_, PyAny>,
        sat_id: &Bound<'_, PyAny>,
        satellite_position_ecef: &Bound<'_, PyAny>,
        satellite_velocity_ecef: &Bound<'_, PyAny>,
        pseudorange: &Bound<'_, PyAny>,
        pseudorange_std: &Bound<'_, PyAny>,
        pseudorange_rate: Option<&Bound<'_, PyAny>>,
        pseudorange_rate_std: Option<&Bound<'_, PyAny>>,
        start_gps_time: Option<f64>,
        carrier_phase: Option<&Bound<'_, PyAny>>,
        carrier_phase_std: Option<&Bound<'_, PyAny>>,
        loss_of_lock: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let arrays = PyDict::new(py);
        for (name, value) in [
            ("time", Some(time)),
            ("sat_id", Some(sat_id)),
            ("satellite_position_ecef", Some(satellite_position_ecef)),
            ("satellite_velocity_ecef", Some(satellite_velocity_ecef)),
            ("pseudorange", Some(pseudorange)),
            ("pseudorange_std", Some(pseudorange_std)),
            ("pseudorange_rate", pseudorange_rate),
            ("pseudorange_rate_std", pseudorange_rate_std),
            ("carrier_phase", carrier_phase),
            ("carrier_phase_std", carrier_phase_std),
            ("loss_of_lock", loss_of_lock),
        ] {
            if let Some(v) = value {
                arrays.set_item(name, v)?;
            }
        }
        let epochs = gnss_epochs(arrays.as_any())?.into_owned();
        Ok(Self::from_epochs(epochs, start_gps_time))
    }

    /// Measurements from a long table, one row per epoch and satellite (the
    /// layout ``memsnav simulate`` writes as ``gnss.csv``): the path of a
    /// CSV file, a pandas or polars DataFrame, or a dict of columns. Columns:
    /// ``time_s``, ``sat_id``, ``sat_position_ecef_{x,y,z}_m``,
    /// ``sat_velocity_ecef_{x,y,z}_m_s``, ``pseudorange_m``; optional
    /// ``gps_time_s``, ``pseudorange_rate_m_s`` (empty or NaN: no rate),
    /// ``pseudorange_std_m``, ``pseudorange_rate_std_m_s`` (left out: the
    /// σ given here, None: ``defaults()["gnss"]``). Any other column is a
    /// ValueError naming it and the closest known name; a row with NaN
    /// outside a rate is refused, naming the row (CSV: the line).
    #[staticmethod]
    #[pyo3(signature = (table, *, pseudorange_std=None, pseudorange_rate_std=None))]
    fn from_table(
        py: Python<'_>,
        table: &Bound<'_, PyAny>,
        pseudorange_std: Option<f64>,
        pseudorange_rate_std: Option<f64>,
    ) -> PyResult<Self> {
        let d = logs::TableStds::default();
        let stds = logs::TableStds {
            pseudorange_std_m: pseudorange_std.unwrap_or(d.pseudorange_std_m),
            pseudorange_rate_std_m_s: pseudorange_rate_std.unwrap_or(d.pseudorange_rate_std_m_s),
        };
        let parsed = if let Ok(path) = table.extract::<PathBuf>() {
            py.detach(|| logs::read_gnss_table(&path, stds)).py()?
        } else {
            let columns = table_columns(table)?;
            let named: Vec<(&str, &[f64])> = columns
                .iter()
                .map(|(n, v)| (n.as_str(), v.as_slice()))
                .collect();
            logs::gnss_table_from_columns(&named, stds, "table").py()?
        };
        Ok(Self::from_epochs(parsed.epochs, parsed.start_gps_time_s))
    }

    /// Epoch times on the trajectory's time axis, s, ``(T,)``.
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_iter(py, self.epochs.iter().map(|e| e.time_s))
    }

    /// Epoch times in GPS s since 1980-01-06, ``(T,)``.
    #[getter]
    fn gps_time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let t0 = self.epochs.first().map_or(0.0, |e| e.time_s);
        PyArray1::from_iter(
            py,
            self.epochs
                .iter()
                .map(|e| self.start_gps_time_s + (e.time_s - t0)),
        )
    }

    /// Number of satellites tracked at each epoch, ``(T,)``.
    #[getter]
    fn n_satellites<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        PyArray1::from_iter(py, self.epochs.iter().map(|e| e.measurements.len() as i64))
    }

    /// Satellite ids (PRN numbers), ``(T, n_max)``, −1 where padded.
    #[getter]
    fn sat_id<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        let mut flat = vec![-1i64; self.epochs.len() * self.n_max];
        for (k, e) in self.epochs.iter().enumerate() {
            for (j, m) in e.measurements.iter().enumerate() {
                flat[k * self.n_max + j] = m.sat_id as i64;
            }
        }
        PyArray1::from_vec(py, flat)
            .reshape([self.epochs.len(), self.n_max])
            .expect("T × n_max")
    }

    /// Satellite positions at transmission time (ECEF of that time), m, ``(T, n_max, 3)``, NaN-padded.
    #[getter]
    fn satellite_position_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        self.padded_vectors(py, |m| m.position_ecef)
    }

    /// Satellite velocities at transmission time, m/s, ``(T, n_max, 3)``, NaN-padded.
    #[getter]
    fn satellite_velocity_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        self.padded_vectors(py, |m| m.velocity_ecef)
    }

    /// Pseudoranges (satellite clock corrected), m, (T, n_max).
    #[getter]
    fn pseudorange<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.padded(py, |m| m.pseudorange_m)
    }

    /// Pseudorange rates, m/s, ``(T, n_max)``, NaN-padded.
    #[getter]
    fn pseudorange_rate<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.padded(py, |m| m.pseudorange_rate_m_s)
    }

    /// Pseudorange noise one-sigma, m, ``(T, n_max)``, NaN-padded.
    #[getter]
    fn pseudorange_std<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.padded(py, |m| m.pseudorange_std_m)
    }

    /// Pseudorange-rate noise one-sigma, m/s, ``(T, n_max)``, NaN-padded.
    #[getter]
    fn pseudorange_rate_std<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.padded(py, |m| m.pseudorange_rate_std_m_s)
    }

    /// The signal each measurement was taken from ("L1 C/A", "E1 C",
    /// "B3I"; "L1 C/A + L5 Q" when a second signal measured its
    /// ionosphere), ``T`` lists of ``n_max`` names, "" where padded; None
    /// for measurements not built from observations.
    #[getter]
    fn signal(&self) -> Option<Vec<Vec<String>>> {
        self.signals.as_ref().map(|signals| {
            signals
                .iter()
                .map(|epoch| {
                    let mut names: Vec<String> = epoch
                        .iter()
                        .map(|s| match s.ionosphere_signal {
                            Some(second) => format!("{} + {second}", s.name),
                            None => s.name.to_owned(),
                        })
                        .collect();
                    names.resize(self.n_max, String::new());
                    names
                })
                .collect()
        })
    }

    /// C/N0 of each measurement's signal (its S observation), dB-Hz,
    /// ``(T, n_max)``, NaN-padded and NaN where the file has none; None for
    /// measurements not built from observations.
    #[getter]
    fn cn0_db_hz<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f64>>> {
        self.padded_signal(py, |s| s.cn0_db_hz)
    }

    /// Each satellite's elevation at the reference position, rad,
    /// ``(T, n_max)``, NaN-padded; None for measurements not built from
    /// observations.
    #[getter]
    fn elevation_rad<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f64>>> {
        self.padded_signal(py, |s| s.elevation_rad)
    }

    /// Carrier ranges λ·φ, m, ``(T, n_max)``; NaN where padded or without
    /// a carrier phase. Each holds an unknown constant per lock arc.
    #[getter]
    fn carrier_phase<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.padded(py, |m| m.carrier.map_or(f64::NAN, |c| c.range_m))
    }

    /// Carrier-range noise one-sigma, m, ``(T, n_max)``; NaN where padded
    /// or without a carrier phase.
    #[getter]
    fn carrier_phase_std<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.padded(py, |m| m.carrier.map_or(f64::NAN, |c| c.std_m))
    }

    /// The receiver reports lock lost since the previous epoch (a new
    /// carrier arc), ``(T, n_max)``; False where padded or without a
    /// carrier phase.
    #[getter]
    fn loss_of_lock<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<bool>> {
        let mut flat = vec![false; self.epochs.len() * self.n_max];
        for (k, e) in self.epochs.iter().enumerate() {
            for (j, m) in e.measurements.iter().enumerate() {
                flat[k * self.n_max + j] = m.carrier.is_some_and(|c| c.loss_of_lock);
            }
        }
        PyArray1::from_vec(py, flat)
            .reshape([self.epochs.len(), self.n_max])
            .expect("T × n_max")
    }

    /// The cycle slips the simulator put in the carrier phases (unflagged:
    /// ``loss_of_lock`` stays False): a dict of ``time`` (s), ``sat_id`` and
    /// ``cycles`` (L1 cycles added from that epoch on) arrays, in epoch
    /// order; empty for measurements not simulated here.
    #[getter]
    fn cycle_slips<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let slips = &self.cycle_slips;
        d.set_item(
            "time",
            PyArray1::from_iter(py, slips.iter().map(|s| s.time_s)),
        )?;
        d.set_item(
            "sat_id",
            PyArray1::from_iter(py, slips.iter().map(|s| i64::from(s.sat_id))),
        )?;
        d.set_item(
            "cycles",
            PyArray1::from_iter(py, slips.iter().map(|s| s.cycles)),
        )?;
        Ok(d)
    }

    /// True receiver clock offset, m, ``(T,)``.
    #[getter]
    fn clock_offset<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_iter(py, self.clock.iter().map(|c| c.offset_m))
    }

    /// True receiver clock drift, m/s, ``(T,)``.
    #[getter]
    fn clock_drift<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_iter(py, self.clock.iter().map(|c| c.drift_m_s))
    }

    /// True inter-system biases (Galileo, BeiDou, GLONASS minus GPS) in
    /// the pseudoranges, m, ``(3,)``; NaN for measurements not simulated here.
    #[getter]
    fn inter_system_bias<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inter_system_bias_m)
    }

    fn __len__(&self) -> usize {
        self.epochs.len()
    }
}

/// The columns of a dict of arrays or a DataFrame (pandas, polars: any
/// object with ``columns`` whose items convert to float arrays; nulls as NaN).
fn table_columns(table: &Bound<'_, PyAny>) -> PyResult<Vec<(String, Vec<f64>)>> {
    let names: Vec<String> = if let Ok(d) = table.cast::<PyDict>() {
        d.keys().extract()
    } else {
        table.getattr("columns").and_then(|c| c.extract())
    }
    .map_err(|_| {
        PyValueError::new_err(
            "table: expected a CSV path, a DataFrame or a dict of columns with string names",
        )
    })?;
    names
        .into_iter()
        .map(|name| {
            let column = table.get_item(&name)?;
            let column = if column.hasattr("to_numpy")? {
                column.call_method0("to_numpy")?
            } else {
                column
            };
            let values: numpy::PyArrayLike1<f64, numpy::AllowTypeChange> =
                column.extract().map_err(|_| {
                    PyValueError::new_err(format!(
                        "table: column {name:?} is not a column of numbers"
                    ))
                })?;
            let values = values.as_array().to_vec();
            Ok((name, values))
        })
        .collect()
}

fn outage_list(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<gnss::Outage>> {
    let Some(obj) = obj else {
        return Ok(Vec::new());
    };
    let items: Vec<Vec<f64>> = obj.extract().map_err(|_| {
        PyValueError::new_err("outages: expected a sequence of (start, length) or (start, length, n_satellites) tuples")
    })?;
    items
        .iter()
        .enumerate()
        .map(|(k, item)| match item.as_slice() {
            [start, length] => Ok(gnss::Outage { start_s: *start, duration_s: *length, n_satellites: 0 }),
            [start, length, n] if *n >= 0.0 && n.fract() == 0.0 => Ok(gnss::Outage {
                start_s: *start,
                duration_s: *length,
                n_satellites: *n as usize,
            }),
            _ => Err(PyValueError::new_err(format!(
                "outages: item {k} must be (start, length) or (start, length, n_satellites) with a non-negative integer n_satellites, got {item:?}"
            ))),
        })
        .collect()
}

/// Pseudoranges (m) and rates (m/s) along a trajectory (method §5).
///
/// Arguments; ``None`` takes the core's default
/// (``memsnav_core::gnss::SimulationConfig``), given in brackets:
///
/// - ``time`` (N,) s, ``position_ecef`` (N, 3) m, ``velocity_ecef`` (N, 3)
///   m/s: the receiver's trajectory, time increasing.
/// - ``constellation``: the satellites (``Constellation.walker``,
///   ``nominal`` or ``from_rinex_nav``).
/// - ``rate``: epochs per second, Hz [1]; the epochs fall on the
///   trajectory samples nearest to t0 + k/rate.
/// - ``n_satellites``: satellites tracked [6].
/// - ``elevation_mask_deg``: elevation mask, degrees [10].
/// - ``pseudorange_std``, m [3], and ``pseudorange_rate_std``, m/s [0.1]:
///   white noise.
/// - ``residual_std``, m [none], and ``residual_correlation_time``, s
///   [300]: a Gauss-Markov residual per satellite (atmosphere, orbit).
/// - ``clock_h0`` [2e-19] and ``clock_h_minus2`` [2e-20]: the receiver
///   clock's Allan coefficients (a TCXO; two-state model);
///   ``clock_initial_offset_std``, m [30], and ``clock_initial_drift_std``,
///   m/s [1]: its initial one-sigmas.
/// - ``outages``: (start s, length s) total, or (start, length,
///   n_satellites) partial, keeping the highest of the tracked satellites
///   (an urban canyon's view), on the trajectory's time axis [none]. They
///   are applied after every random draw, so the kept satellites' noise
///   does not depend on them.
/// - ``seed``: the random stream, an integer in [0, 2**64) [0: the same
///   draws every call; pass different seeds for independent draws].
/// - ``start_gps_time``: GPS time of time[0], s [the earliest t_oe of a
///   broadcast file; 0 for a Walker constellation].
/// - ``inter_system_bias``: Galileo, BeiDou[, GLONASS] minus GPS, m
///   [none], added to that system's pseudoranges.
/// - ``carrier_phase_std``, m [0: no carrier phase]: adds carrier ranges:
///   the pseudorange's range, clock and bias, minus the residual (the
///   ionosphere advances the phase), plus a whole number of GPS L1 cycles
///   drawn per lock arc, plus white noise; ``loss_of_lock`` is set where a
///   satellite was not in the previous epoch. The carrier draws from a
///   stream of its own: the pseudoranges and rates are the same with or
///   without it.
/// - ``cycle_slip_probability``, per satellite and epoch [0]: silent slips
///   (±1 and ±2 cycles common, up to ±1000; ``loss_of_lock`` stays False),
///   listed in ``cycle_slips``.
///
/// At the first epoch the ``n_satellites`` with the best GDOP above the
/// mask are chosen (greedy elimination), of every system the constellation
/// holds, and kept while visible; a setting satellite is replaced by the
/// one giving the best GDOP (with several systems the GDOP has one
/// inter-system-bias unknown per system other than GPS, so a system's lone
/// satellite adds nothing). Pseudorange = exact light-time range with
/// Earth rotation + receiver clock + the system's inter-system bias + the
/// residual + white noise.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (time, position_ecef, velocity_ecef, constellation, rate=None, n_satellites=None,
    elevation_mask_deg=None, pseudorange_std=None, pseudorange_rate_std=None, residual_std=None,
    residual_correlation_time=None, clock_h0=None, clock_h_minus2=None,
    clock_initial_offset_std=None, clock_initial_drift_std=None, outages=None, seed=None,
    start_gps_time=None, inter_system_bias=None, carrier_phase_std=None,
    cycle_slip_probability=None))]
fn simulate_gnss(
    py: Python<'_>,
    time: &Bound<'_, PyAny>,
    position_ecef: &Bound<'_, PyAny>,
    velocity_ecef: &Bound<'_, PyAny>,
    constellation: &PyConstellation,
    rate: Option<f64>,
    n_satellites: Option<usize>,
    elevation_mask_deg: Option<f64>,
    pseudorange_std: Option<f64>,
    pseudorange_rate_std: Option<f64>,
    residual_std: Option<f64>,
    residual_correlation_time: Option<f64>,
    clock_h0: Option<f64>,
    clock_h_minus2: Option<f64>,
    clock_initial_offset_std: Option<f64>,
    clock_initial_drift_std: Option<f64>,
    outages: Option<&Bound<'_, PyAny>>,
    seed: Option<&Bound<'_, PyAny>>,
    start_gps_time: Option<f64>,
    inter_system_bias: Option<Vec<f64>>,
    carrier_phase_std: Option<f64>,
    cycle_slip_probability: Option<f64>,
) -> PyResult<PyGnssMeasurements> {
    let time = convert::scalars(time, "time")?;
    let position = convert::vectors(position_ecef, "position_ecef")?;
    let velocity = convert::vectors(velocity_ecef, "velocity_ecef")?;
    // None: the core's default (SimulationConfig, ReceiverClockModel,
    // AtmosphericResidual); no residual unless residual_std is given.
    let d = SimulationConfig::default();
    let (dc, dr) = (d.clock, gnss::AtmosphericResidual::default());
    let elevation_mask_rad = match elevation_mask_deg {
        Some(deg) if !deg.is_finite() => {
            return Err(PyValueError::new_err(format!(
                "elevation_mask_deg: must be finite, got {deg}"
            )))
        }
        Some(deg) => deg.to_radians(),
        None => d.elevation_mask_rad,
    };
    let config = SimulationConfig {
        rate_hz: rate.unwrap_or(d.rate_hz),
        n_satellites: n_satellites.unwrap_or(d.n_satellites),
        elevation_mask_rad,
        pseudorange_std_m: pseudorange_std.unwrap_or(d.pseudorange_std_m),
        pseudorange_rate_std_m_s: pseudorange_rate_std.unwrap_or(d.pseudorange_rate_std_m_s),
        residual: residual_std
            .filter(|std| *std != 0.0)
            .map(|std_m| gnss::AtmosphericResidual {
                std_m,
                correlation_time_s: residual_correlation_time.unwrap_or(dr.correlation_time_s),
            }),
        clock: gnss::ReceiverClockModel {
            h0: clock_h0.unwrap_or(dc.h0),
            h_minus2: clock_h_minus2.unwrap_or(dc.h_minus2),
            initial_offset_std_m: clock_initial_offset_std.unwrap_or(dc.initial_offset_std_m),
            initial_drift_std_m_s: clock_initial_drift_std.unwrap_or(dc.initial_drift_std_m_s),
        },
        outages: outage_list(outages)?,
        start_gps_time_s: start_gps_time,
        inter_system_bias_m: inter_system_bias
            .as_deref()
            .map(|v| gnss::inter_system_biases("inter_system_bias", v))
            .transpose()
            .py()?
            .unwrap_or(d.inter_system_bias_m),
        carrier_phase_std_m: carrier_phase_std.unwrap_or(d.carrier_phase_std_m),
        cycle_slip_probability: cycle_slip_probability.unwrap_or(d.cycle_slip_probability),
    };
    let n_max = config.n_satellites;
    let track = gnss::ReceiverTrack {
        time_s: &time,
        position_ecef: &position,
        velocity_ecef: &velocity,
    };
    let sky = &constellation.inner;
    let mut rng = random::from_optional_seed(convert::seed(seed)?);
    let sim = py
        .detach(|| gnss::simulate_with_truth(&track, sky, &config, &mut rng))
        .py()?;
    Ok(PyGnssMeasurements {
        epochs: sim.epochs,
        clock: sim.clock,
        start_gps_time_s: sim.start_gps_time_s,
        inter_system_bias_m: sim.inter_system_bias_m,
        cycle_slips: sim.cycle_slips,
        n_max,
        signals: None,
    })
}

/// Least-squares fixes per epoch; NaN rows where ``valid`` is False.
#[pyclass(name = "FixSeries", module = "memsnav._memsnav", frozen)]
pub struct PyFixSeries {
    time: Vec<f64>,
    pub(crate) fixes: Vec<Option<gnss::Fix>>,
}

impl PyFixSeries {
    fn scalar<'py>(
        &self,
        py: Python<'py>,
        f: impl Fn(&gnss::Fix) -> f64,
    ) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_iter(
            py,
            self.fixes.iter().map(|x| x.as_ref().map_or(f64::NAN, &f)),
        )
    }

    fn vectors<'py>(
        &self,
        py: Python<'py>,
        f: impl Fn(&gnss::Fix) -> Vector3<f64>,
    ) -> Bound<'py, PyArray2<f64>> {
        let v: Vec<Vector3<f64>> = self
            .fixes
            .iter()
            .map(|x| x.as_ref().map_or(Vector3::repeat(f64::NAN), &f))
            .collect();
        convert::vectors_to_numpy(py, &v)
    }

    fn covariances<'py>(
        &self,
        py: Python<'py>,
        f: impl Fn(&gnss::Fix) -> Matrix4<f64>,
    ) -> Bound<'py, PyArray3<f64>> {
        let m: Vec<Matrix4<f64>> = self
            .fixes
            .iter()
            .map(|x| x.as_ref().map_or(Matrix4::repeat(f64::NAN), &f))
            .collect();
        matrices4(py, &m)
    }
}

#[catch_panics]
#[pymethods]
impl PyFixSeries {
    fn __repr__(&self) -> String {
        let solved = self.fixes.iter().flatten().count();
        let excluding = self
            .fixes
            .iter()
            .flatten()
            .filter(|f| !f.excluded.is_empty())
            .count();
        format!(
            "FixSeries({solved} fixes of {} epochs, {excluding} with satellites excluded)",
            self.time.len()
        )
    }

    /// Epoch times, s, ``(T,)``.
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.time)
    }
    /// True where the epoch had at least 4 satellites and a fix, ``(T,)``.
    #[getter]
    fn valid<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        PyArray1::from_iter(py, self.fixes.iter().map(Option::is_some))
    }
    /// ECEF position, m, ``(T, 3)`` (NaN rows where not valid).
    #[getter]
    fn position_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.vectors(py, |f| f.position_ecef)
    }
    /// ECEF velocity, m/s, ``(T, 3)``.
    #[getter]
    fn velocity_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.vectors(py, |f| f.velocity_ecef)
    }
    /// Receiver clock offset, m, ``(T,)``.
    #[getter]
    fn clock_offset<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalar(py, |f| f.clock_offset_m)
    }
    /// Inter-system biases of Galileo, BeiDou and GLONASS relative to the
    /// epoch's reference system (GPS when present), m, ``(T, 3)``; NaN for
    /// a system not in the epoch.
    #[getter]
    fn inter_system_bias<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        const N: usize = gnss::FIX_BIAS_SYSTEMS.len();
        let rows: Vec<Vec<f64>> = self
            .fixes
            .iter()
            .map(|x| {
                x.as_ref()
                    .map_or([f64::NAN; N], |f| f.inter_system_bias_m)
                    .to_vec()
            })
            .collect();
        array2(py, rows.concat(), self.fixes.len(), N)
    }
    /// Receiver clock drift, m/s, ``(T,)``.
    #[getter]
    fn clock_drift<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalar(py, |f| f.clock_drift_m_s)
    }
    /// Covariance of (x, y, z, clock offset), m², ``(T, 4, 4)``.
    #[getter]
    fn position_clock_covariance<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        self.covariances(py, |f| f.position_clock_covariance)
    }
    /// Covariance of (vx, vy, vz, clock drift), (m/s)², ``(T, 4, 4)``.
    #[getter]
    fn velocity_drift_covariance<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        self.covariances(py, |f| f.velocity_drift_covariance)
    }
    /// Geometric dilution of precision, (T,).
    #[getter]
    fn gdop<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalar(py, |f| f.dops.gdop)
    }
    /// Position dilution of precision, (T,).
    #[getter]
    fn pdop<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalar(py, |f| f.dops.pdop)
    }
    /// Horizontal dilution of precision, (T,).
    #[getter]
    fn hdop<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalar(py, |f| f.dops.hdop)
    }
    /// Vertical dilution of precision, (T,).
    #[getter]
    fn vdop<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalar(py, |f| f.dops.vdop)
    }
    /// Time dilution of precision, (T,).
    #[getter]
    fn tdop<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalar(py, |f| f.dops.tdop)
    }
    /// Satellites the residual test left out of each epoch's fix (RINEX
    /// names, in the order they were left out); empty where every
    /// satellite fits or the epoch has no fix.
    #[getter]
    fn excluded(&self) -> Vec<Vec<String>> {
        self.fixes
            .iter()
            .map(|x| {
                x.as_ref().map_or_else(Vec::new, |f| {
                    f.excluded
                        .as_slice()
                        .iter()
                        .map(|&n| gnss::satellite_name(n))
                        .collect()
                })
            })
            .collect()
    }
    /// Post-fit test statistic Σ (v/σ)² of the satellites used, ``(T,)``;
    /// NaN without redundancy, with unit weights or without a fix.
    #[getter]
    fn residual_chi_square<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalar(py, |f| f.residual_chi_square)
    }
    /// The residual test's threshold χ²(1 − false_alarm_probability,
    /// satellites − unknowns), ``(T,)``; NaN where the test did not run.
    #[getter]
    fn residual_threshold<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalar(py, |f| f.residual_threshold)
    }
}

/// Gauss-Newton position/velocity/clock fix of every epoch (Sagnac-corrected
/// predicted ranges).
///
/// - ``measurements``: a ``GnssMeasurements``, or its padded arrays as a
///   dict (the constructor's keys, no others).
/// - ``prior``: (3,) ECEF start of the first epoch's iterations, m [the
///   Earth's centre]; later epochs start from the previous fix.
/// - ``strict`` [False]: an epoch with fewer than 4 satellites is a
///   ValueError instead of a NaN row.
/// - ``false_alarm_probability`` [0.001]: the residual test's, per epoch;
///   None turns the test off.
///
/// Residual test (RAIM fault detection and exclusion): the weighted post-fit
/// residuals' sum of squares is held to the chi-square quantile
/// 1 - ``false_alarm_probability`` (default 0.001 per epoch, RTKLIB's) of
/// satellites - unknowns degrees of freedom; while it fails and a test after
/// the exclusion remains possible, the satellite with the largest normalized
/// residual is left out and the fix made again. The satellites left out are
/// in ``excluded``; the final statistic and threshold in
/// ``residual_chi_square`` and ``residual_threshold`` (a statistic still above
/// its threshold: no exclusion could make the epoch fit).
/// ``false_alarm_probability=None`` turns the test off.
#[catch_panics]
#[pyfunction]
#[pyo3(
    signature = (measurements, prior=None, strict=false, *, false_alarm_probability=Some(gnss::DEFAULT_FALSE_ALARM_PROBABILITY)),
    text_signature = "(measurements, prior=None, strict=False, *, false_alarm_probability=0.001)"
)]
fn solve_fix(
    py: Python<'_>,
    measurements: &Bound<'_, PyAny>,
    prior: Option<&Bound<'_, PyAny>>,
    strict: bool,
    false_alarm_probability: Option<f64>,
) -> PyResult<PyFixSeries> {
    let prior = prior.map(|p| convert::vector3(p, "prior")).transpose()?;
    let test = gnss::ResidualTest {
        false_alarm_probability,
    };
    let epochs = gnss_epochs(measurements)?;
    let epochs = &*epochs;
    let fixes = py
        .detach(|| {
            let mut start = prior;
            epochs
                .iter()
                .map(|e| {
                    if e.measurements.len() < 4 && !strict {
                        return Ok(None);
                    }
                    let fix = gnss::solve_fix_with(e, start, &test)?;
                    start = Some(fix.position_ecef);
                    Ok(Some(fix))
                })
                .collect::<Result<Vec<_>, Error>>()
        })
        .py()?;
    Ok(PyFixSeries {
        time: epochs.iter().map(|e| e.time_s).collect(),
        fixes,
    })
}

/// Whether `obj` holds pseudoranges (a `GnssMeasurements`, or arrays with
/// a `sat_id`) rather than position fixes.
pub(crate) fn is_measurements(obj: &Bound<'_, PyAny>) -> bool {
    obj.cast::<PyGnssMeasurements>().is_ok()
        || optional_field(obj, "sat_id").is_ok_and(|v| v.is_some())
}

/// The entries of padded GNSS arrays (a dict, or an object's attributes).
pub(crate) const GNSS_KEYS: [&str; 11] = [
    "time",
    "sat_id",
    "satellite_position_ecef",
    "satellite_velocity_ecef",
    "pseudorange",
    "pseudorange_std",
    "pseudorange_rate",
    "pseudorange_rate_std",
    "carrier_phase",
    "carrier_phase_std",
    "loss_of_lock",
];

/// Epoch `index` of `obj` (anything [`gnss_epochs`] reads); an index past
/// the end is a ValueError naming `epoch`.
pub(crate) fn gnss_epoch_at(obj: &Bound<'_, PyAny>, index: usize) -> PyResult<GnssEpoch> {
    let epochs = gnss_epochs(obj)?;
    epochs.get(index).cloned().ok_or_else(|| {
        PyValueError::new_err(format!(
            "epoch: {index} is past the last of the {} epochs of gnss",
            epochs.len()
        ))
    })
}

/// GNSS epochs from a `GnssMeasurements` or padded user arrays (a dict,
/// no other keys, or an object with these attributes): `time` (T,),
/// `sat_id` (T, n) (finite negative = padding), `satellite_position_ecef` and
/// `satellite_velocity_ecef` (T, n, 3), `pseudorange` (T, n),
/// `pseudorange_std` (T, n), optional `pseudorange_rate` with
/// `pseudorange_rate_std` (T, n), optional `carrier_phase` with
/// `carrier_phase_std` (T, n) and optional `loss_of_lock` (T, n). Every
/// slot that is not padding passes the core's `carrier_of` and
/// `check_measurement` (NaN only for a rate or a carrier: none there); the
/// one converter of every entry point that takes GNSS measurements.
/// A `GnssMeasurements` is lent, not copied: it is frozen (immutable), and
/// `obj` keeps it alive while the epochs are in use.
pub(crate) fn gnss_epochs<'a>(obj: &'a Bound<'_, PyAny>) -> PyResult<Cow<'a, [GnssEpoch]>> {
    const ARG: &str = "gnss";
    if let Ok(m) = obj.cast::<PyGnssMeasurements>() {
        if m.get().epochs.is_empty() {
            return Err(no_epochs(ARG));
        }
        return Ok(Cow::Borrowed(&m.get().epochs));
    }
    check_keys(obj, ARG, &GNSS_KEYS)?;
    let time = convert::scalars(&field(obj, "time", ARG)?, "gnss.time")?;
    let t = time.len();
    if t == 0 {
        return Err(no_epochs("gnss.time"));
    }
    memsnav_core::validate::increasing_times("gnss.time", &time).py()?;
    let (sat_id, s) = floats_with_nan(&field(obj, "sat_id", ARG)?, "gnss.sat_id")?;
    if s.len() != 2 || s[0] != t {
        return Err(shape_error(ARG, "sat_id", "(T, n)", &s));
    }
    let n = s[1];
    let get2 = |name: &str| -> PyResult<Vec<f64>> {
        let (v, s) = floats_with_nan(&field(obj, name, ARG)?, &format!("gnss.{name}"))?;
        if s != [t, n] {
            return Err(shape_error(ARG, name, &format!("({t}, {n})"), &s));
        }
        Ok(v)
    };
    let get3 = |name: &str| -> PyResult<Vec<f64>> {
        let (v, s) = floats_with_nan(&field(obj, name, ARG)?, &format!("gnss.{name}"))?;
        if s != [t, n, 3] {
            return Err(shape_error(ARG, name, &format!("({t}, {n}, 3)"), &s));
        }
        Ok(v)
    };
    let pos = get3("satellite_position_ecef")?;
    let vel = get3("satellite_velocity_ecef")?;
    let rho = get2("pseudorange")?;
    let rho_std = get2("pseudorange_std")?;
    let (rate, rate_std) =
        match (
            optional_field(obj, "pseudorange_rate")?,
            optional_field(obj, "pseudorange_rate_std")?,
        ) {
            (Some(_), _) => (get2("pseudorange_rate")?, get2("pseudorange_rate_std")?),
            (None, Some(_)) => return Err(PyValueError::new_err(
                "gnss: pseudorange_rate_std given without pseudorange_rate (give both, or neither)",
            )),
            (None, None) => (vec![f64::NAN; t * n], vec![f64::NAN; t * n]),
        };
    let (carrier, carrier_std) = match (
        optional_field(obj, "carrier_phase")?,
        optional_field(obj, "carrier_phase_std")?,
    ) {
        (Some(_), Some(_)) => (get2("carrier_phase")?, get2("carrier_phase_std")?),
        (None, None) => (vec![f64::NAN; t * n], vec![f64::NAN; t * n]),
        _ => {
            return Err(PyValueError::new_err(
                "gnss: carrier_phase and carrier_phase_std go together (give both, or neither)",
            ))
        }
    };
    let loss_of_lock = match optional_field(obj, "loss_of_lock")? {
        Some(_) => get2("loss_of_lock")?,
        None => vec![0.0; t * n],
    };
    let mut slots = Vec::with_capacity(t * n);
    let mut rows = Vec::with_capacity(t * n);
    let mut epochs = Vec::with_capacity(t);
    for (k, &time_s) in time.iter().enumerate() {
        // An epoch without satellites (a total outage) is kept.
        epochs.push(GnssEpoch {
            time_s,
            measurements: Vec::new(),
        });
        for j in 0..n {
            let i = k * n + j;
            let id = sat_id[i];
            // A finite negative number marks an empty slot; −inf is not one
            // (as NaN and +inf, it is refused below, naming the slot).
            if id < 0.0 && id.is_finite() {
                continue; // padding
            }
            let slot_error = |reason: String| {
                PyValueError::new_err(format!("gnss: [{k}, {j}] (time {time_s} s): {reason}"))
            };
            let sat_id = gnss::sat_id(id).map_err(|e| {
                slot_error(format!("{e}; mark an empty slot with a negative number"))
            })?;
            let carrier = gnss::carrier_of(carrier[i], carrier_std[i], loss_of_lock[i])
                .map_err(slot_error)?;
            slots.push((k, j));
            rows.push((
                time_s,
                SatelliteMeasurement {
                    sat_id,
                    system: gnss::system_of_number(sat_id),
                    position_ecef: Vector3::from_column_slice(&pos[3 * i..3 * i + 3]),
                    velocity_ecef: Vector3::from_column_slice(&vel[3 * i..3 * i + 3]),
                    pseudorange_m: rho[i],
                    pseudorange_rate_m_s: rate[i],
                    pseudorange_std_m: rho_std[i],
                    pseudorange_rate_std_m_s: rate_std[i],
                    carrier,
                },
            ));
        }
    }
    let grouped = gnss::epochs_from_rows(rows).map_err(|(row, reason)| {
        let (k, j) = slots[row];
        PyValueError::new_err(format!("gnss: [{k}, {j}] (time {} s): {reason}", time[k]))
    })?;
    // The rows' epochs in time order, placed back among the empty ones.
    for e in grouped {
        let k = time
            .iter()
            .position(|&t| t == e.time_s)
            .expect("a row's own time");
        epochs[k].measurements = e.measurements;
    }
    Ok(Cow::Owned(epochs))
}

/// The RINEX name of a satellite number (``107`` → ``"E07"``; G n → n,
/// E n → 100 + n, C n → 200 + n), or the number as text beyond them.
///
/// `number`: a satellite number, as `satellite_number` gives it.
#[catch_panics]
#[pyfunction]
fn satellite_name(number: u16) -> String {
    gnss::satellite_name(number)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(satellite_name, m)?)?;
    m.add_class::<PyConstellation>()?;
    m.add_class::<PySp3>()?;
    m.add_class::<PyGnssMeasurements>()?;
    m.add_class::<PyFixSeries>()?;
    m.add_function(wrap_pyfunction!(read_sp3, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_gnss, m)?)?;
    m.add_function(wrap_pyfunction!(solve_fix, m)?)?;
    m.add_class::<PyRinexObservations>()?;
    m.add_function(wrap_pyfunction!(read_rinex_obs, m)?)?;
    m.add_function(wrap_pyfunction!(read_klobuchar, m)?)?;
    Ok(())
}

// --- real receiver data ---

impl PyGnssMeasurements {
    /// Measurements of a real receiver (the receiver clock unknown, NaN):
    /// `start_gps_time_s` is the GPS time of the first epoch (None: its
    /// time is GPS time already, as a RINEX file's).
    pub(crate) fn from_epochs(epochs: Vec<GnssEpoch>, start_gps_time_s: Option<f64>) -> Self {
        let n_max = epochs
            .iter()
            .map(|e| e.measurements.len())
            .max()
            .unwrap_or(0);
        let nan = gnss::ClockState {
            offset_m: f64::NAN,
            drift_m_s: f64::NAN,
        };
        Self {
            clock: vec![nan; epochs.len()],
            start_gps_time_s: start_gps_time_s
                .unwrap_or_else(|| epochs.first().map_or(0.0, |e| e.time_s)),
            inter_system_bias_m: [f64::NAN; gnss::INTER_SYSTEM_BIAS_SYSTEMS.len()],
            cycle_slips: Vec::new(),
            n_max,
            epochs,
            signals: None,
        }
    }
}

/// A RINEX 3 or RINEX 2.10/2.11 observation file (2.x codes read as the
/// RINEX 3 codes of their signals, docs/reference/readers.md).
#[pyclass(name = "RinexObservations", module = "memsnav._memsnav", frozen)]
pub struct PyRinexObservations {
    pub(crate) inner: gnss::ObservationFile,
}

#[catch_panics]
#[pymethods]
impl PyRinexObservations {
    fn __repr__(&self) -> String {
        let systems: String = self.inner.observation_types.keys().collect();
        format!(
            "RinexObservations(RINEX {}, {} epochs, systems {systems})",
            self.inner.version,
            self.inner.epochs.len()
        )
    }

    /// Epoch times, GPS s since 1980-01-06, ``(T,)``.
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_iter(py, self.inner.epochs.iter().map(|e| e.gps_time_s))
    }

    /// Every satellite seen, e.g. ``["E07", "G10", ...]`` (sorted).
    #[getter]
    fn satellites(&self) -> Vec<String> {
        self.sat_keys()
            .iter()
            .map(|(s, p)| format!("{s}{p:02}"))
            .collect()
    }

    /// Observation types per system letter, in header order.
    #[getter]
    fn observation_types(&self) -> std::collections::BTreeMap<String, Vec<String>> {
        self.inner
            .observation_types
            .iter()
            .map(|(k, v)| (k.to_string(), v.clone()))
            .collect()
    }

    /// Each GLONASS slot's FDMA frequency channel k of the header's
    /// ``GLONASS SLOT / FRQ #`` (G1 = 1602 + 0.5625 k MHz):
    /// ``{"R01": 1, ...}``; empty without the record.
    #[getter]
    fn glonass_channels(&self) -> std::collections::BTreeMap<String, i8> {
        self.inner
            .glonass_channels
            .iter()
            .map(|(slot, &k)| (format!("R{slot:02}"), k))
            .collect()
    }

    /// ``APPROX POSITION XYZ`` of the header, ECEF m, or None.
    #[getter]
    fn approx_position_ecef<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.inner
            .approx_position_ecef
            .map(|p| convert::vector3_to_numpy(py, &p))
    }

    /// Non-fatal problems met while reading (a truncated last record).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }

    /// Records not read, by kind, with counts: event records (flags 2-5,
    /// their header lines not applied) and cycle-slip records (flag 6).
    #[getter]
    fn skipped(&self) -> std::collections::BTreeMap<String, usize> {
        self.inner.skipped.clone()
    }

    /// Values of observation ``code`` (e.g. ``"C1C"`` m, ``"D1C"`` Hz,
    /// ``"S1C"`` dB-Hz), ``(T, len(satellites))``; NaN where absent.
    fn observation<'py>(&self, py: Python<'py>, code: &str) -> Bound<'py, PyArray2<f64>> {
        let keys = self.sat_keys();
        let mut flat = vec![f64::NAN; self.inner.epochs.len() * keys.len()];
        for (k, e) in self.inner.epochs.iter().enumerate() {
            for s in &e.satellites {
                let (Some(j), Some(i)) = (
                    keys.iter().position(|x| *x == (s.system, s.prn)),
                    self.inner.type_index(s.system, code),
                ) else {
                    continue;
                };
                if let Some(v) = s.values[i] {
                    flat[k * keys.len() + j] = v;
                }
            }
        }
        array2(py, flat, self.inner.epochs.len(), keys.len())
    }

    /// GPS L1 C/A measurements (time = GPS time) for the coupled filters and
    /// ``solve_fix``: satellite states at transmission time, pseudoranges
    /// corrected for the satellite clock, the Klobuchar ionosphere
    /// (``klobuchar=(alpha, beta)``, default RTKLIB's coefficients) and the
    /// Saastamoinen troposphere at ``reference_position_ecef`` (default the
    /// header's approximate position); rates from the Doppler; carrier ranges
    /// from the phase, corrected alike with the ionosphere's sign reversed,
    /// lock lost where the loss-of-lock indicator says so
    /// (``carrier_phase_std=0``: no carrier phase). Pseudorange sigma by
    /// ``weighting``: ``"rtklib"`` (default) RTKLIB 2.4.3's single-point
    /// error model, sigma^2 = F^2 (0.3^2 + 0.3^2/sin(el)) + URA^2 + 0.3^2 +
    /// (0.5 Klobuchar)^2 + (0.3/(sin(el) + 0.1))^2 (F = 1.5 for GLONASS, else
    /// 1); ``"signal-strength"``: ``pseudorange_std`` (default 3 m, only with
    /// this model) at 45 dB-Hz and zenith, scaled by
    /// sqrt(10^((45-C/N0)/10))/sin(el). Rate and carrier sigma (m/s, m) at 45
    /// dB-Hz and zenith, scaled alike in both.
    #[pyo3(signature = (constellation, reference_position_ecef=None, *, elevation_mask_deg=None,
        min_cn0_db_hz=None, ionosphere=true, klobuchar=None, troposphere=true,
        pseudorange_std=None, pseudorange_rate_std=None, satellites=None,
        carrier_phase_std=None, weighting=None))]
    fn gps_l1(
        &self,
        py: Python<'_>,
        constellation: &PyConstellation,
        reference_position_ecef: Option<&Bound<'_, PyAny>>,
        elevation_mask_deg: Option<f64>,
        min_cn0_db_hz: Option<f64>,
        ionosphere: bool,
        klobuchar: Option<([f64; 4], [f64; 4])>,
        troposphere: bool,
        pseudorange_std: Option<f64>,
        pseudorange_rate_std: Option<f64>,
        satellites: Option<Vec<u16>>,
        carrier_phase_std: Option<f64>,
        weighting: Option<String>,
    ) -> PyResult<PyGnssMeasurements> {
        let options = self.observable_options(
            reference_position_ecef,
            ObservableArguments {
                elevation_mask_deg,
                min_cn0_db_hz,
                ionosphere,
                klobuchar,
                troposphere,
                pseudorange_std,
                pseudorange_rate_std,
                carrier_phase_std,
                dual_frequency: false,
                weighting,
            },
            vec![gnss::GnssSystem::Gps],
            satellites.unwrap_or_default(),
        )?;
        let epochs = py
            .detach(|| gnss::gps_l1_epochs(&self.inner, &constellation.inner, &options))
            .py()?;
        Ok(PyGnssMeasurements::from_epochs(epochs, None))
    }

    /// Measurements of several systems for the tight filter and
    /// ``solve_fix``: GPS L1 C/A, Galileo E1 and BeiDou B1I/B2I/B3I (the
    /// first the file has), GLONASS G1 C/A on each satellite's channel, with
    /// ``ephemerides`` (``read_broadcast_nav``, or a UBX log's
    /// ``broadcast_ephemerides``), corrected as ``gps_l1`` does with each
    /// signal's group delay and the Klobuchar delay scaled to its
    /// frequency. ``systems``: RINEX letters (``"G"``, ``"E"``, ``"C"``,
    /// ``"R"``; default G, E, C: GLONASS on request, for ``solve_fix`` and
    /// the tight filter). ``satellites``: RINEX names
    /// (``"G10"``, ``"E07"``, ``"R05"``) to keep. Satellite numbers in the
    /// result: G n → n, E n → 100 + n, C n → 200 + n, R n → 300 + n; each
    /// system's pseudoranges keep the receiver's inter-system bias, which
    /// the tight filter and ``solve_fix`` estimate. Epochs whose satellites
    /// no ephemeris covers are counted in a ``UserWarning``; when none is
    /// covered, a ``ValueError`` says so. With the troposphere on, the
    /// elevation mask must be at least 5° (``MIN_TROPOSPHERE_MASK_DEG``).
    /// ``klobuchar``: default the ephemerides' own (``klobuchar``: the
    /// navigation file's header, a UBX log's CNAV), else RTKLIB's.
    /// ``reference_position_ecef`` (also ``gps_l1``'s): ``(3,)``, or
    /// ``(T, 3)`` with one position per epoch for a moving receiver (the
    /// masks and the atmosphere at each); default the file's APPROX
    /// POSITION XYZ. Each measurement's signal, C/N0 and
    /// elevation in ``signal``, ``cn0_db_hz``, ``elevation_rad``.
    /// ``dual_frequency=True``: each satellite's ionospheric delay measured
    /// from a second signal's pseudorange where the file has one whose
    /// group delay the ephemerides give (GPS L5 or L2C with CNAV's
    /// inter-signal corrections, Galileo E5a or E5b, BeiDou another D1
    /// band), smoothed per satellite; the Klobuchar delay for the rest.
    /// ``weighting``, ``pseudorange_std``: as ``gps_l1``.
    #[pyo3(signature = (ephemerides, reference_position_ecef=None, *, systems=None,
        elevation_mask_deg=None, min_cn0_db_hz=None, ionosphere=true, klobuchar=None,
        troposphere=true, pseudorange_std=None, pseudorange_rate_std=None, satellites=None,
        carrier_phase_std=None, dual_frequency=false, weighting=None))]
    fn measurements(
        &self,
        py: Python<'_>,
        ephemerides: &PyBroadcastEphemerides,
        reference_position_ecef: Option<&Bound<'_, PyAny>>,
        systems: Option<Vec<String>>,
        elevation_mask_deg: Option<f64>,
        min_cn0_db_hz: Option<f64>,
        ionosphere: bool,
        klobuchar: Option<([f64; 4], [f64; 4])>,
        troposphere: bool,
        pseudorange_std: Option<f64>,
        pseudorange_rate_std: Option<f64>,
        satellites: Option<Vec<String>>,
        carrier_phase_std: Option<f64>,
        dual_frequency: bool,
        weighting: Option<String>,
    ) -> PyResult<PyGnssMeasurements> {
        let systems = match systems {
            None => gnss::GnssSystem::DEFAULT_MEASURED.to_vec(),
            Some(letters) => letters
                .iter()
                .map(|l| system_of_letter(l, "systems"))
                .collect::<PyResult<_>>()?,
        };
        let satellites = satellites
            .unwrap_or_default()
            .iter()
            .map(|name| satellite_of_name(name))
            .collect::<PyResult<_>>()?;
        // The ephemerides' own coefficients before RTKLIB's defaults.
        let klobuchar =
            klobuchar.or_else(|| ephemerides.inner.klobuchar.map(|k| (k.alpha, k.beta)));
        let options = self.observable_options(
            reference_position_ecef,
            ObservableArguments {
                elevation_mask_deg,
                min_cn0_db_hz,
                ionosphere,
                klobuchar,
                troposphere,
                pseudorange_std,
                pseudorange_rate_std,
                carrier_phase_std,
                dual_frequency,
                weighting,
            },
            systems,
            satellites,
        )?;
        let (epochs, signals, coverage) = py
            .detach(|| {
                gnss::broadcast_epochs_with_signals(&self.inner, &ephemerides.inner, &options).map(
                    |(epochs, signals)| {
                        let coverage =
                            gnss::ephemeris_coverage(&self.inner, &ephemerides.inner, &options);
                        (epochs, signals, coverage)
                    },
                )
            })
            .py()?;
        let uncovered = coverage.epochs_without_ephemeris;
        let never = if coverage.satellites_without_ephemeris.is_empty() {
            String::new()
        } else {
            format!(
                "; satellites never covered: {}",
                coverage.satellites_without_ephemeris.join(", ")
            )
        };
        if uncovered > 0 && uncovered == coverage.epochs_observed {
            return Err(PyValueError::new_err(format!(
                "ephemerides: none covers any satellite of the {uncovered} epochs observed (another day, or other satellites?){never}"
            )));
        }
        if uncovered > 0 {
            crate::warnings::warn_all(
                py,
                &[format!(
                    "{uncovered} of {} epochs have no satellite with an ephemeris: they give no measurement{never}",
                    coverage.epochs_observed
                )],
            )?;
        }
        Ok(PyGnssMeasurements {
            signals: Some(signals),
            ..PyGnssMeasurements::from_epochs(epochs, None)
        })
    }

    fn __len__(&self) -> usize {
        self.inner.epochs.len()
    }
}

/// The options ``gps_l1`` and ``measurements`` share; `None` keeps the
/// core's default (``defaults()``).
struct ObservableArguments {
    elevation_mask_deg: Option<f64>,
    min_cn0_db_hz: Option<f64>,
    ionosphere: bool,
    klobuchar: Option<([f64; 4], [f64; 4])>,
    troposphere: bool,
    pseudorange_std: Option<f64>,
    pseudorange_rate_std: Option<f64>,
    carrier_phase_std: Option<f64>,
    dual_frequency: bool,
    /// ``"rtklib"`` or ``"signal-strength"`` (`gnss::PseudorangeWeighting`).
    weighting: Option<String>,
}

impl PyRinexObservations {
    fn observable_options(
        &self,
        reference_position_ecef: Option<&Bound<'_, PyAny>>,
        a: ObservableArguments,
        systems: Vec<gnss::GnssSystem>,
        satellites: Vec<u16>,
    ) -> PyResult<gnss::ObservableOptions> {
        // One position, or one per epoch (a moving receiver).
        let (reference, track) = match reference_position_ecef {
            Some(r) if convert::floats(r, "reference_position_ecef")?.shape.len() == 2 => {
                let track = convert::vectors(r, "reference_position_ecef")?;
                let first = *track.first().ok_or_else(|| {
                    PyValueError::new_err("reference_position_ecef: (T, 3) with no row")
                })?;
                (first, track)
            }
            Some(r) => (convert::vector3(r, "reference_position_ecef")?, Vec::new()),
            None => (
                self.inner.approx_position_ecef.ok_or_else(|| {
                    PyValueError::new_err(
                        "reference_position_ecef: not given and the file has no APPROX POSITION XYZ",
                    )
                })?,
                Vec::new(),
            ),
        };
        let mut options = gnss::ObservableOptions::new(reference);
        options.reference_track_ecef = track;
        if let Some(name) = &a.weighting {
            options.weighting = gnss::PseudorangeWeighting::from_name(name).ok_or_else(|| {
                PyValueError::new_err(format!(
                    "weighting: {name:?} is not a weighting model: \"rtklib\" (RTKLIB's \
                     single-point error model, the default) or \"signal-strength\" (σ from C/N0 \
                     and elevation, scaled by pseudorange_std)"
                ))
            })?;
        }
        if a.pseudorange_std.is_some()
            && options.weighting != gnss::PseudorangeWeighting::SignalStrength
        {
            return Err(PyValueError::new_err(format!(
                "pseudorange_std: sets the \"signal-strength\" weighting's σ at 45 dB-Hz and the \
                 zenith; the {:?} weighting does not read it: pass weighting=\"signal-strength\" \
                 with it",
                options.weighting.name()
            )));
        }
        if let Some(mask) = a.elevation_mask_deg {
            options.elevation_mask_rad = mask.to_radians();
        }
        for (value, target) in [
            (a.min_cn0_db_hz, &mut options.min_cn0_db_hz),
            (a.pseudorange_std, &mut options.pseudorange_std_m),
            (
                a.pseudorange_rate_std,
                &mut options.pseudorange_rate_std_m_s,
            ),
            (a.carrier_phase_std, &mut options.carrier_phase_std_m),
        ] {
            if let Some(v) = value {
                *target = v;
            }
        }
        options.ionosphere = if a.ionosphere {
            Some(
                a.klobuchar
                    .map_or(gnss::Klobuchar::RTKLIB_DEFAULT, |(alpha, beta)| {
                        gnss::Klobuchar { alpha, beta }
                    }),
            )
        } else {
            None
        };
        options.troposphere = a.troposphere;
        options.dual_frequency_ionosphere = a.dual_frequency;
        options.systems = systems;
        options.satellites = satellites;
        Ok(options)
    }

    fn sat_keys(&self) -> Vec<(char, u16)> {
        let mut keys: Vec<(char, u16)> = self
            .inner
            .epochs
            .iter()
            .flat_map(|e| e.satellites.iter().map(|s| (s.system, s.prn)))
            .collect();
        keys.sort_unstable();
        keys.dedup();
        keys
    }
}

/// Reads a RINEX 3 or RINEX 2.10/2.11 observation file (errors name the
/// file and line; a truncated last record is dropped and reported in
/// ``warnings``; event records are counted in ``skipped``).
///
/// `path`: the file to read (str or path-like).
#[catch_panics]
#[pyfunction]
fn read_rinex_obs(py: Python<'_>, path: PathBuf) -> PyResult<PyRinexObservations> {
    Ok(PyRinexObservations {
        inner: py.detach(|| gnss::read_rinex_obs(&path)).py()?,
    })
}

/// The Klobuchar coefficients ``(alpha, beta)`` of a RINEX navigation
/// header (``ION ALPHA``/``ION BETA`` or ``IONOSPHERIC CORR GPSA/GPSB``),
/// or None when it has none.
///
/// `path`: the file to read (str or path-like).
#[catch_panics]
#[pyfunction]
fn read_klobuchar(path: PathBuf) -> PyResult<Option<([f64; 4], [f64; 4])>> {
    Ok(gnss::read_klobuchar(&path).py()?.map(|k| (k.alpha, k.beta)))
}
