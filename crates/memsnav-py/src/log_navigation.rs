//! `navigate_log` and its `LogRun`; `fixes_from_solution` and its
//! `PositionFixes`: the real-log engine of memsnav-core
//! (`memsnav_core::navigate`) on the user's arrays, one call per log with
//! the GIL released.

use memsnav_core::logs;
use memsnav_core::navigate::{
    self, fixes_from_geodetic, references, score, FixOptions, GeodeticSolution, GnssInput,
    LogConfig, LogRun,
};
use memsnav_core::random::from_optional_seed;
use memsnav_core::sensors::DEFAULT_SAMPLE_RATE_HZ;
use memsnav_py_macros::catch_panics;
use nalgebra::Vector3;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::aiding::{position_fixes, PyPositionFixes};
use crate::arguments::{no_epochs, settings_tables};
use crate::convert;
use crate::coupling::PyFilterSolution;
use crate::errors::IntoPyResult;
use crate::gnss::{gnss_epochs, is_measurements};
use crate::result_record::result_record;

/// The tables and keys ``navigate_log(settings=...)`` reads (the engine's
/// part of a ``navigate`` configuration), each with what it holds.
#[catch_panics]
#[pyfunction]
fn navigate_settings<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (table, keys) in navigate::KEYS {
        let t = PyDict::new(py);
        for key in *keys {
            t.set_item(key.name, key.description)?;
        }
        d.set_item(table, t)?;
    }
    Ok(d)
}

/// The JSON schema (a JSON text) of the engine's tables of a ``navigate``
/// configuration: per table an object of its keys, each with its kind of
/// value, bounds and description, and no other key
/// (``memsnav.realdata.config.json_schema()`` joins the reading keys').
#[catch_panics]
#[pyfunction]
fn navigate_settings_schema() -> String {
    navigate::keys::json_schema().to_string()
}

/// C_b^s, the sensor-to-body rotation of a chain of [roll, pitch, yaw]
/// triples in degrees applied in order (`[imu] mounting_rpy_deg`):
/// f_b = C(last) ··· C(first) f_s, (3, 3).
///
/// `rpy_deg`: a list of [roll, pitch, yaw] triples, degrees.
#[catch_panics]
#[pyfunction]
fn mounting_matrix<'py>(
    py: Python<'py>,
    rpy_deg: Vec<[f64; 3]>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let rad: Vec<[f64; 3]> = rpy_deg.iter().map(|t| t.map(f64::to_radians)).collect();
    let c = navigate::mounting_matrix(&rad).py()?;
    Ok(convert::matrix3_to_numpy(py, &c))
}

/// Checks `settings` (`{table: {key: value}}`) as `navigate_log` would,
/// without data: unknown tables or keys, values of the wrong kind or out of
/// range raise `ValueError` naming `table.key`.
#[catch_panics]
#[pyfunction]
fn check_navigate_settings(settings: &Bound<'_, PyDict>) -> PyResult<()> {
    // Any IMU rate serves: it only scales the preset's noise per sample.
    LogConfig::from_settings(&settings_tables(Some(settings))?, DEFAULT_SAMPLE_RATE_HZ).py()?;
    Ok(())
}

/// Fixes from a geodetic solution (a `PosSolution` of `read_pos`,
/// `read_fixes_csv` or `read_nmea`, or arrays): `time` (T,) s, `geodetic`
/// (T, 3) [lat rad, lon rad, h m], the position uncertainty as `std_ned`
/// (T, 3) m or `covariance_ned` (T, 3, 3) m² (exactly one), optional
/// `velocity_ned` (T, 3) with `velocity_std_ned` (T, 3) or
/// `velocity_covariance_ned` (T, 3, 3) (NaN where absent; north and east
/// with a NaN down is a horizontal-only velocity, NMEA's). Keeps the epochs
/// on the `rate_hz` grid, adds seeded white noise of
/// `added_position_noise_ned` (N, E, D one-sigma, m) and
/// `added_velocity_noise` (m/s), and rotates the covariance (+ noise²) into
/// ECEF.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (time, geodetic, std_ned=None, *, covariance_ned=None, velocity_ned=None, velocity_std_ned=None, velocity_covariance_ned=None, rate_hz=None, added_position_noise_ned=None, added_velocity_noise=None, use_velocity=None, seed=None))]
#[allow(clippy::too_many_arguments)]
fn fixes_from_solution(
    time: &Bound<'_, PyAny>,
    geodetic: &Bound<'_, PyAny>,
    std_ned: Option<&Bound<'_, PyAny>>,
    covariance_ned: Option<&Bound<'_, PyAny>>,
    velocity_ned: Option<&Bound<'_, PyAny>>,
    velocity_std_ned: Option<&Bound<'_, PyAny>>,
    velocity_covariance_ned: Option<&Bound<'_, PyAny>>,
    rate_hz: Option<f64>,
    added_position_noise_ned: Option<&Bound<'_, PyAny>>,
    added_velocity_noise: Option<f64>,
    use_velocity: Option<bool>,
    seed: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyPositionFixes> {
    let time = convert::scalars(time, "time")?;
    if time.is_empty() {
        return Err(no_epochs("time"));
    }
    let geodetic = convert::vectors(geodetic, "geodetic")?;
    let covariance = match (given(std_ned), given(covariance_ned)) {
        (Some(s), None) => logs::diagonal_covariances(&convert::vectors(s, "std_ned")?),
        (None, Some(c)) => convert::matrices3(c, "covariance_ned")?,
        _ => {
            return Err(PyValueError::new_err(
                "std_ned, covariance_ned: give exactly one (the position uncertainty)",
            ))
        }
    };
    let velocity = given(velocity_ned)
        .map(|v| convert::vectors_allow_nan(v, "velocity_ned"))
        .transpose()?;
    let velocity_covariance = match (given(velocity_std_ned), given(velocity_covariance_ned)) {
        (Some(s), None) => Some(logs::diagonal_covariances(&convert::vectors_allow_nan(
            s,
            "velocity_std_ned",
        )?)),
        (None, Some(c)) => Some(convert::matrices3_allow_nan(c, "velocity_covariance_ned")?),
        (None, None) => None,
        _ => {
            return Err(PyValueError::new_err(
                "velocity_std_ned, velocity_covariance_ned: give at most one",
            ))
        }
    };
    let defaults = FixOptions::default();
    let options = FixOptions {
        rate_hz,
        added_position_noise_ned_m: added_position_noise_ned
            .filter(|v| !v.is_none())
            .map(|v| convert::vector3(v, "added_position_noise_ned"))
            .transpose()?
            .unwrap_or(defaults.added_position_noise_ned_m),
        added_velocity_noise_m_s: added_velocity_noise.unwrap_or(defaults.added_velocity_noise_m_s),
        use_velocity: use_velocity.unwrap_or(defaults.use_velocity),
    };
    let mut rng = from_optional_seed(convert::seed(seed)?);
    let solution = GeodeticSolution {
        time_s: &time,
        geodetic: &geodetic,
        covariance_ned_m2: &covariance,
        velocity_ned_m_s: velocity.as_deref(),
        velocity_covariance_ned_m2_s2: velocity_covariance.as_deref(),
    };
    let fixes = fixes_from_geodetic(&solution, &options, &mut rng).py()?;
    Ok(PyPositionFixes { fixes })
}

/// The truth moved to the point being scored
/// (`memsnav_core::navigate::truth::truth_at_point`): `geodetic` (N, 3)
/// [lat rad, lon rad, h m] at the truth's own point, `attitude` (N, 3, 3)
/// its C_b^n (needed for a lever arm), `lever_arm` (3,) the scored point
/// from the truth's point in the truth's body axes (forward, right, down),
/// m, `offset_ned` (3,) a datum offset added in local NED, m (None: zero).
/// ECEF (N, 3), m: r_truth + C_n^e (C_b^n l + o).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (geodetic, attitude=None, *, lever_arm=None, offset_ned=None))]
fn truth_at_point<'py>(
    py: Python<'py>,
    geodetic: &Bound<'_, PyAny>,
    attitude: Option<&Bound<'_, PyAny>>,
    lever_arm: Option<&Bound<'_, PyAny>>,
    offset_ned: Option<&Bound<'_, PyAny>>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let geodetic = convert::vectors(geodetic, "geodetic")?;
    let attitude = given(attitude)
        .map(|a| convert::matrices3(a, "attitude"))
        .transpose()?;
    let vector = |v: Option<&Bound<'_, PyAny>>, name: &str| {
        given(v)
            .map(|v| convert::vector3(v, name))
            .transpose()
            .map(Option::unwrap_or_default)
    };
    let lever_arm = vector(lever_arm, "lever_arm")?;
    let offset_ned = vector(offset_ned, "offset_ned")?;
    let moved = py
        .detach(|| {
            navigate::truth::truth_at_point(&geodetic, attitude.as_deref(), &lever_arm, &offset_ned)
        })
        .py()?;
    Ok(convert::vectors_to_numpy(py, &moved))
}

/// The argument when given and not None.
fn given<'a, 'py>(o: Option<&'a Bound<'py, PyAny>>) -> Option<&'a Bound<'py, PyAny>> {
    o.filter(|v| !v.is_none())
}

result_record! {
    /// The filter's state at the sample a log run starts at, as the filter
    /// classes' `initial_state=` takes it.
    PyInitialState as "InitialState" {
        /// Position of the IMU, ECEF m, (3,).
        position_ecef: Py<PyArray1<f64>>,
        /// Velocity, ECEF m/s, (3,).
        velocity_ecef: Py<PyArray1<f64>>,
        /// Attitude C_b^e (body to ECEF), (3, 3).
        attitude: Py<PyArray2<f64>>,
    }
    repr(_s) "position_ecef, velocity_ecef, attitude"
}

result_record! {
    /// How a log run started (`LogRun.start`).
    PyRunStart as "RunStart" {
        /// "static", "static_with_heading" or "moving".
        kind: String,
        /// When, s.
        time: f64,
        /// The GNSS epoch (index) it started at.
        epoch: usize,
        /// Whether the heading was known at the start.
        heading_known: bool,
        /// The log's first IMU sample, s.
        first_imu_time: f64,
        /// The log's first GNSS epoch, s.
        first_gnss_time: f64,
        /// The earliest start the log allows (its first GNSS epoch with
        /// `standstill.window_s` of IMU data before it), s: the outages
        /// count from it.
        earliest_time: f64,
        /// Where and why the run started more than 10 s after that (late),
        /// None when it did not.
        late_reason: Option<String>,
        /// The index of the IMU sample it starts at.
        first_sample: usize,
        /// The filter's start at that sample (`initial_state=` of the filter
        /// classes).
        initial_state: Py<PyInitialState>,
        /// Its position one-sigma, m (before any `[filter]` override).
        position_std: f64,
        /// Its velocity one-sigma, m/s.
        velocity_std: f64,
        /// Its roll and pitch one-sigma, rad.
        tilt_std: f64,
        /// Its heading one-sigma, rad.
        heading_std: f64,
    }
    repr(s) format!("{} at {:.3} s, sample {}", s.kind, s.time, s.first_sample)
}

result_record! {
    /// Why a log run stopped before the end of the log (`LogRun.failure`).
    PyRunFailure as "RunFailure" {
        /// When, GNSS time, s.
        time: f64,
        /// What went wrong.
        message: String,
    }
    repr(s) format!("at {:.3} s: {}", s.time, s.message)
}

result_record! {
    /// The gyro's turns against the GNSS course's over a whole log
    /// (`LogRun.gyro_scale`).
    PyGyroScaleCheck as "GyroScaleCheck" {
        /// The gyro's turn over the course's: 1 for a gyro read in its unit,
        /// π/180 for radians read as degrees, 180/π the reverse.
        ratio: f64,
        /// Its relative std.
        relative_std: f64,
        /// The course's turn over the pairs of epochs used, deg.
        course_turn_deg: f64,
        /// The pairs of GNSS epochs used.
        pairs: usize,
        /// Enough turning for a verdict.
        conclusive: bool,
        /// A conclusive ratio beyond √(180/π) either way: the warning naming
        /// `gyro_unit` and the likely unit (also in `solution.warnings`);
        /// else None.
        warning: Option<String>,
    }
    repr(s) format!("ratio {:.4} ± {:.4}, {} pairs", s.ratio, s.ratio * s.relative_std, s.pairs)
}

result_record! {
    /// A run's carrier-phase changes between epochs by fate
    /// (`LogRun.carrier_phase`).
    PyCarrierPhaseUse as "CarrierPhaseUse" {
        /// Every change between consecutive epochs of a satellite.
        changes: usize,
        /// Applied.
        used: usize,
        /// Cycle slips (receiver flag or Doppler test).
        slips: usize,
        /// Excluded by the residual test.
        excluded: usize,
        /// Clean, but the epoch had fewer than the 5 clean changes a batch
        /// needs.
        too_few: usize,
        /// Rejected by their batch's gate, an invalid value or a reset.
        rejected: usize,
        /// Why none was used (also in `solution.warnings`); else None.
        warning: Option<String>,
    }
    repr(s) format!("{} of {} changes used", s.used, s.changes)
}

/// A real log's navigation (``navigate_log``): the solution at the antenna in
/// local terms at every IMU sample from the start, the filter's own solution
/// at the IMU, the start, the GNSS epochs, outages, standstills and range
/// biases, and the scoring against a truth.
#[pyclass(name = "LogRun", module = "memsnav._memsnav", frozen)]
pub struct PyLogRun {
    run: LogRun,
    local: memsnav_core::output::LocalSolution,
    smoothed: Option<Py<PyLogRun>>,
}

fn stats_dict<'py>(py: Python<'py>, s: &score::ErrorStats) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("epochs", s.epochs)?;
    if s.epochs > 0 {
        d.set_item("rms_horizontal_m", s.rms_horizontal_m)?;
        d.set_item("rms_vertical_m", s.rms_vertical_m)?;
        d.set_item("max_horizontal_m", s.max_horizontal_m)?;
        if s.within_3sigma_share.is_finite() {
            d.set_item("within_3sigma_share", s.within_3sigma_share)?;
            d.set_item(
                "within_3sigma_share_horizontal",
                s.within_3sigma_share_horizontal,
            )?;
            d.set_item("nees_per_dof", s.nees_per_dof)?;
        }
    }
    Ok(d)
}

#[catch_panics]
#[pymethods]
impl PyLogRun {
    fn __repr__(&self) -> String {
        let t = &self.run.solution.time_s;
        let span = match (t.first(), t.last()) {
            (Some(a), Some(b)) => format!(", {a:.3}-{b:.3} s"),
            _ => String::new(),
        };
        let used = self.run.gnss_used.iter().filter(|u| **u).count();
        let smoothed = if self.smoothed.is_some() {
            ", smoothed"
        } else {
            ""
        };
        format!(
            "LogRun({} samples{span}, {used} of {} GNSS epochs used, {} outages{smoothed})",
            t.len(),
            self.run.gnss.len(),
            self.run.outages.len()
        )
    }

    /// Times, s (GNSS time), (N,).
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.local.time_s)
    }
    /// Antenna position, ECEF m, (N, 3).
    #[getter]
    fn position_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.local.antenna_position_ecef)
    }
    /// Antenna latitude, longitude (rad), ellipsoidal height (m), (N, 3).
    #[getter]
    fn geodetic<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let v: Vec<Vector3<f64>> = self
            .local
            .antenna_geodetic
            .iter()
            .map(|g| Vector3::new(g.latitude_rad, g.longitude_rad, g.height_m))
            .collect();
        convert::vectors_to_numpy(py, &v)
    }
    /// Velocity (of the IMU) north, east, down, m/s, (N, 3).
    #[getter]
    fn velocity_ned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.local.velocity_ned)
    }
    /// Roll, pitch, yaw of the body relative to local NED, rad, (N, 3).
    #[getter]
    fn euler<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.local.euler_rad)
    }
    /// One-sigma position north, east, down, m, (N, 3).
    #[getter]
    fn position_std_ned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.local.position_std_ned)
    }
    /// One-sigma velocity north, east, down, m/s, (N, 3).
    #[getter]
    fn velocity_std_ned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.local.velocity_std_ned)
    }
    /// One-sigma attitude about north, east, down, rad, (N, 3).
    #[getter]
    fn attitude_std_ned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.local.attitude_std_ned)
    }
    /// The filter's own solution at the IMU (ECEF, covariance, every
    /// measurement, batch and reset).
    #[getter]
    fn solution(&self) -> PyFilterSolution {
        PyFilterSolution::new(self.run.solution.clone())
    }
    /// The fixed-interval smoothed run (``[filter] smoother = true``): the
    /// same views of the smoothed solution; None without.
    #[getter]
    fn smoothed(&self, py: Python<'_>) -> Option<Py<PyLogRun>> {
        self.smoothed.as_ref().map(|s| s.clone_ref(py))
    }
    /// How the run started: a `RunStart` (its kind and time, the log's
    /// first IMU sample and GNSS epoch, the earliest start the log allows
    /// and why it started late if it did, the IMU sample it starts at, the
    /// filter's `initial_state` there and its one-sigmas).
    #[getter]
    fn start(&self, py: Python<'_>) -> PyResult<PyRunStart> {
        let s = &self.run.start;
        let initial = s.initial_state(&self.run.tuning.antenna_lever_arm_b_m);
        let initial_state = Py::new(
            py,
            PyInitialState {
                position_ecef: convert::vector3_to_numpy(py, &initial.nav.position_ecef).unbind(),
                velocity_ecef: convert::vector3_to_numpy(py, &initial.nav.velocity_ecef).unbind(),
                attitude: convert::matrix3_to_numpy(py, &initial.nav.c_b_e).unbind(),
            },
        )?;
        Ok(PyRunStart {
            kind: s.kind.name().to_string(),
            time: s.time_s,
            epoch: s.epoch,
            heading_known: s.heading_known,
            first_imu_time: s.first_imu_time_s,
            first_gnss_time: s.first_gnss_time_s,
            earliest_time: s.earliest_time_s,
            late_reason: self.run.late_start.clone(),
            first_sample: s.first_sample,
            initial_state,
            position_std: s.position_std_m,
            velocity_std: s.velocity_std_m_s,
            tilt_std: s.tilt_std_rad,
            heading_std: s.heading_std_rad,
        })
    }
    /// What the run learnt from the log before the run it reports
    /// (docs/results/foreign-drive.md): dict `imu_preset` (the IMU model chosen,
    /// None when the configuration names one), `imu_candidates` (a list of
    /// dicts `preset`, `log_likelihood`, `measurements`, `resets`: each
    /// candidate's first pass), `nhc_std_m_s` (the non-holonomic
    /// constraint's std chosen, m/s, None when configured) and
    /// `nhc_candidates` (dicts `std_m_s`, `log_likelihood`,
    /// `measurements`, `resets`), `fix_correlation` (None, or dict
    /// `component_s` (three correlation times, s, None where not
    /// determined), `innovation_to_fix_variance` (three ratios),
    /// `correlation_time_s` (0: white), `variance_ratio`), and
    /// `fix_error_std_m` and `fix_error_correlation_time_s` (the fix-error
    /// states learnt from it; None when the fixes stay white).
    #[getter]
    fn adaptation<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let a = &self.run.adaptation;
        let d = PyDict::new(py);
        d.set_item("imu_preset", a.imu_preset.clone())?;
        let candidates = PyList::empty(py);
        for c in &a.imu_candidates {
            let e = PyDict::new(py);
            e.set_item("preset", &c.preset)?;
            e.set_item("log_likelihood", c.log_likelihood)?;
            e.set_item("measurements", c.measurements)?;
            e.set_item("resets", c.resets)?;
            candidates.append(e)?;
        }
        d.set_item("imu_candidates", candidates)?;
        d.set_item("nhc_std_m_s", a.nhc_std_m_s)?;
        let candidates = PyList::empty(py);
        for c in &a.nhc_candidates {
            let e = PyDict::new(py);
            e.set_item("std_m_s", c.std_m_s)?;
            e.set_item("log_likelihood", c.log_likelihood)?;
            e.set_item("measurements", c.measurements)?;
            e.set_item("resets", c.resets)?;
            candidates.append(e)?;
        }
        d.set_item("nhc_candidates", candidates)?;
        match &a.fix_correlation {
            Some(c) => {
                let e = PyDict::new(py);
                e.set_item("component_s", c.component_s.to_vec())?;
                e.set_item(
                    "innovation_to_fix_variance",
                    c.innovation_to_fix_variance.to_vec(),
                )?;
                e.set_item("correlation_time_s", c.correlation_time_s)?;
                e.set_item("variance_ratio", c.variance_ratio)?;
                d.set_item("fix_correlation", e)?;
            }
            None => d.set_item("fix_correlation", py.None())?,
        }
        d.set_item("fix_error_std_m", a.fix_error.map(|m| m.std_m))?;
        d.set_item(
            "fix_error_correlation_time_s",
            a.fix_error.map(|m| m.correlation_time_s),
        )?;
        Ok(d)
    }
    /// Every GNSS epoch's antenna position and velocity (the fixes, or the
    /// single-point solution of the pseudoranges; NaN where none) and
    /// whether it reached the filter: dict `time`, `position_ecef`,
    /// `velocity_ecef`, `used`.
    #[getter]
    fn gnss<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let g = &self.run.gnss;
        let d = PyDict::new(py);
        d.set_item("time", PyArray1::from_iter(py, g.iter().map(|x| x.time_s)))?;
        let p: Vec<Vector3<f64>> = g.iter().map(|x| x.position_ecef).collect();
        let v: Vec<Vector3<f64>> = g
            .iter()
            .map(|x| x.velocity_ecef.unwrap_or(Vector3::from_element(f64::NAN)))
            .collect();
        d.set_item("position_ecef", convert::vectors_to_numpy(py, &p))?;
        d.set_item("velocity_ecef", convert::vectors_to_numpy(py, &v))?;
        d.set_item("used", PyArray1::from_slice(py, &self.run.gnss_used))?;
        Ok(d)
    }
    /// The outage windows, absolute (start, end) times, s, (K, 2) (as
    /// configured: s after ``start.earliest_time``).
    #[getter]
    fn outages<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        pairs(py, &self.run.outages)
    }
    /// The detected standstills, (start, end) times, s, (M, 2).
    #[getter]
    fn standstills<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        pairs(py, &self.run.standstills)
    }
    /// Why the run stopped before the end of the log, when it did (the
    /// filter's error, or a state beyond what a solution holds: height
    /// outside -10 km to 10 000 km, speed above 10 km/s, a σ above 10 000 km):
    /// a `RunFailure` (``time``, GNSS time, s, and ``message``). The solution
    /// ends at the last sample before it and has no smoothed run;
    /// ``navigate_log`` also warns. None for a run to the end.
    #[getter]
    fn failure(&self) -> Option<PyRunFailure> {
        self.run.failure.as_ref().map(|f| PyRunFailure {
            time: f.time_s,
            message: f.message.clone(),
        })
    }
    /// The gyro's turns against the GNSS course's over the whole log: a
    /// `GyroScaleCheck` (its ratio, whether it is conclusive, the unit
    /// warning). None without a usable pair of GNSS epochs.
    #[getter]
    fn gyro_scale(&self) -> Option<PyGyroScaleCheck> {
        self.run.gyro_scale.map(|g| PyGyroScaleCheck {
            ratio: g.ratio,
            relative_std: g.relative_std,
            course_turn_deg: g.course_turn_rad.to_degrees(),
            pairs: g.pairs,
            conclusive: g.conclusive(),
            warning: g.unit_warning(),
        })
    }
    /// The run's carrier changes between epochs by fate: a
    /// `CarrierPhaseUse`. None when the run did not use carrier phase.
    #[getter]
    fn carrier_phase(&self) -> Option<PyCarrierPhaseUse> {
        self.run.carrier_use.map(|u| PyCarrierPhaseUse {
            changes: u.changes,
            used: u.used,
            slips: u.slips,
            excluded: u.excluded,
            too_few: u.too_few,
            rejected: u.rejected,
            warning: u.warning(),
        })
    }
    /// The satellites holding range-bias states at the end: {prn: bias m}.
    #[getter]
    fn range_biases<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (sat, b) in &self.run.range_biases {
            d.set_item(sat, b)?;
        }
        Ok(d)
    }
    /// Errors of the antenna solution against a truth (`time` (T,) s,
    /// `position_ecef` (T, 3)), interpolated at the truth epochs: dict
    /// `time`, `error_ned` (T', 3), `std_ned`, `outage` (index or −1),
    /// `offset_removed_ned` (3,), and statistics `all`, `aided`,
    /// `in_outages` (every outage epoch), `outages` (list, each also with
    /// `standstill_s`, the time it spent at a standstill, and
    /// `at_standstill`, at least half of it), `by_outage_length` ({length s:
    /// stats} over the outages not at a standstill); each statistic
    /// `epochs`, `rms_horizontal_m`, `rms_vertical_m`, `max_horizontal_m`,
    /// `within_3sigma_share` (N, E and D), `within_3sigma_share_horizontal`
    /// (N and E), `nees_per_dof` (mean (e/σ)² over the epochs and N, E, D). `remove_mean_offset`: the precision score,
    /// the errors less their mean over the aided epochs (a truth with a
    /// constant unknown offset).
    #[pyo3(signature = (time, position_ecef, *, remove_mean_offset=false))]
    fn score<'py>(
        &self,
        py: Python<'py>,
        time: &Bound<'_, PyAny>,
        position_ecef: &Bound<'_, PyAny>,
        remove_mean_offset: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let truth_t = convert::scalars(time, "time")?;
        let truth_r = convert::vectors(position_ecef, "position_ecef")?;
        let l = &self.local;
        let s = score::score_solution(
            &l.time_s,
            &l.antenna_position_ecef,
            &l.position_std_ned,
            &truth_t,
            &truth_r,
            &self.run.outages,
            &self.run.standstills,
        )
        .py()?;
        let s = if remove_mean_offset {
            s.less_mean_offset()
        } else {
            s
        };
        let d = PyDict::new(py);
        d.set_item("time", PyArray1::from_slice(py, &s.time_s))?;
        d.set_item("error_ned", convert::vectors_to_numpy(py, &s.error_ned))?;
        d.set_item("std_ned", convert::vectors_to_numpy(py, &s.std_ned))?;
        d.set_item(
            "offset_removed_ned",
            PyArray1::from_slice(py, s.offset_removed_ned.as_slice()),
        )?;
        d.set_item(
            "outage",
            PyArray1::from_iter(py, s.outage.iter().map(|o| o.map_or(-1, |w| w as i64))),
        )?;
        d.set_item("all", stats_dict(py, &s.all)?)?;
        d.set_item("aided", stats_dict(py, &s.aided)?)?;
        d.set_item("in_outages", stats_dict(py, &s.in_outages)?)?;
        let windows = PyList::empty(py);
        for (w, stats) in s.outages.iter().enumerate() {
            let d = stats_dict(py, stats)?;
            d.set_item("standstill_s", s.outage_standstill_s[w])?;
            d.set_item("at_standstill", s.at_standstill(w))?;
            windows.append(d)?;
        }
        d.set_item("outages", windows)?;
        let by_length = PyDict::new(py);
        for (length, st) in &s.by_outage_length {
            by_length.set_item(length, stats_dict(py, st)?)?;
        }
        d.set_item("by_outage_length", by_length)?;
        Ok(d)
    }
    /// Errors of the GNSS epochs' own positions (the fixes for loose
    /// coupling, the single-point solution for tight) against a truth:
    /// each paired with the truth epoch within `tolerance` s [0.02], or with
    /// `interpolate` with the truth interpolated linearly at its time
    /// between truth epochs at most `score::TRUTH_MAX_GAP_S` (1 s) apart
    /// (a truth at its own rate). Dict `time`,
    /// `error_ned`, `stats`, `offset_removed_ned`. `remove_mean_offset`:
    /// the errors less their mean (precision; the mean is then
    /// `offset_removed_ned`).
    #[pyo3(signature = (time, position_ecef, *, tolerance=None, interpolate=false, remove_mean_offset=false))]
    fn score_gnss<'py>(
        &self,
        py: Python<'py>,
        time: &Bound<'_, PyAny>,
        position_ecef: &Bound<'_, PyAny>,
        tolerance: Option<f64>,
        interpolate: bool,
        remove_mean_offset: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let truth_t = convert::scalars(time, "time")?;
        let truth_r = convert::vectors(position_ecef, "position_ecef")?;
        let g = &self.run.gnss;
        let t: Vec<f64> = g.iter().map(|x| x.time_s).collect();
        let r: Vec<Vector3<f64>> = g.iter().map(|x| x.position_ecef).collect();
        let pairing = if interpolate {
            score::FixPairing::Interpolated {
                max_gap_s: score::TRUTH_MAX_GAP_S,
            }
        } else {
            score::FixPairing::Nearest {
                tolerance_s: tolerance.unwrap_or(score::DEFAULT_TRUTH_TOLERANCE_S),
            }
        };
        let scored = score::score_fixes(&t, &r, &truth_t, &truth_r, pairing).py()?;
        let scored = if remove_mean_offset {
            scored.less_mean_offset()
        } else {
            scored
        };
        let d = PyDict::new(py);
        d.set_item("time", PyArray1::from_slice(py, &scored.time_s))?;
        d.set_item(
            "error_ned",
            convert::vectors_to_numpy(py, &scored.error_ned),
        )?;
        d.set_item("stats", stats_dict(py, &scored.stats)?)?;
        d.set_item(
            "offset_removed_ned",
            PyArray1::from_slice(py, scored.offset_removed_ned.as_slice()),
        )?;
        Ok(d)
    }
    /// The GNSS-derived calibration references of this run's solution (use
    /// the smoothed run): window means of the measured and the reference
    /// specific force and angular rate in the sensor's axes
    /// (`memsnav_core::navigate::references`). `time`, `specific_force`,
    /// `angular_rate`: the arrays given to `navigate_log`; `window_s` the
    /// window length, s [1]; `until_s` only windows ending that long after the
    /// start. Dict `time`, `measured_specific_force`, `measured_angular_rate`,
    /// `reference_specific_force`, `reference_angular_rate` ((W, 3), SI),
    /// `window_s`, `skipped_for_resets`, `skipped_before_heading`, `accel_bias_covariance`, `gyro_bias_covariance`,
    /// `accel_scale_factor_covariance`, `gyro_scale_factor_covariance` ((3, 3),
    /// the solution's own uncertainty of them in sensor axes; zero scale
    /// factors without their states).
    #[pyo3(signature = (time, specific_force, angular_rate, *, window_s=None, until_s=None))]
    fn calibration_references<'py>(
        &self,
        py: Python<'py>,
        time: &Bound<'_, PyAny>,
        specific_force: &Bound<'_, PyAny>,
        angular_rate: &Bound<'_, PyAny>,
        window_s: Option<f64>,
        until_s: Option<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let window_s = window_s.unwrap_or(references::DEFAULT_WINDOW_S);
        let t = convert::scalars(time, "time")?;
        let f = convert::vectors(specific_force, "specific_force")?;
        let w = convert::vectors(angular_rate, "angular_rate")?;
        let r =
            references::calibration_references(&self.run, &t, &f, &w, window_s, until_s).py()?;
        let d = PyDict::new(py);
        d.set_item("time", PyArray1::from_slice(py, &r.time_s))?;
        for (key, v) in [
            ("measured_specific_force", &r.measured_specific_force_s),
            ("measured_angular_rate", &r.measured_angular_rate_s),
            ("reference_specific_force", &r.reference_specific_force_s),
            ("reference_angular_rate", &r.reference_angular_rate_s),
        ] {
            d.set_item(key, convert::vectors_to_numpy(py, v))?;
        }
        d.set_item("window_s", r.window_s)?;
        d.set_item("skipped_for_resets", r.skipped_for_resets)?;
        d.set_item("skipped_before_heading", r.skipped_before_heading)?;
        d.set_item(
            "accel_bias_covariance",
            convert::matrix3_to_numpy(py, &r.accel_bias_covariance_s),
        )?;
        d.set_item(
            "gyro_bias_covariance",
            convert::matrix3_to_numpy(py, &r.gyro_bias_covariance_s),
        )?;
        d.set_item(
            "accel_scale_factor_covariance",
            convert::matrix3_to_numpy(py, &r.accel_scale_factor_covariance_s),
        )?;
        d.set_item(
            "gyro_scale_factor_covariance",
            convert::matrix3_to_numpy(py, &r.gyro_scale_factor_covariance_s),
        )?;
        Ok(d)
    }
    /// Writes the solution at the antenna to `path` in `format`: "csv" (`columns()`,
    /// every sample), "pos" (RTKLIB, GPST; `read_pos` reads it), "kml" (KML
    /// 2.2: the track as a LineString, start and end placemarks), "gpx" (GPX
    /// 1.1: trk/trkseg/trkpt, times in UTC) or "geojson" (RFC 7946: a
    /// LineString Feature of [lon, lat, h] with the times as properties);
    /// None: from the extension (.csv, .pos, .kml, .gpx, .geojson or .json).
    /// Heights are ellipsoidal (WGS 84); UTC is GPS time less the leap
    /// seconds (18 s since 2017). `rate_hz`: the rows' rate (the first sample
    /// of each interval); None: every sample for "csv", 10 Hz for the others
    /// (a rate at or above the sample rate keeps every sample). `name` titles
    /// a map track (default the file's stem). The file is written whole or
    /// not at all; its folder must exist (`OSError` naming it). An existing
    /// file is replaced only when memsnav wrote it (a solution file of any of
    /// these formats) or with `overwrite=True`, a folder never (`ValueError`);
    /// an unknown format is a `ValueError` naming `format` and the accepted
    /// names.
    #[pyo3(signature = (path, format=None, *, rate_hz=None, name=None, overwrite=false))]
    fn write(
        &self,
        py: Python<'_>,
        path: std::path::PathBuf,
        format: Option<&str>,
        rate_hz: Option<f64>,
        name: Option<&str>,
        overwrite: bool,
    ) -> PyResult<()> {
        crate::output::write(py, &self.local, path, format, rate_hz, name, overwrite)
    }
    /// The solution at the antenna as columns named with their units, (N,) each:
    /// `gps_time_s`, `lat_deg`, `lon_deg`, `height_m` (ellipsoidal), `vn_m_s`,
    /// `ve_m_s`, `vd_m_s`, `roll_deg`, `pitch_deg`, `yaw_deg`, `sdn_m`, `sde_m`,
    /// `sdd_m`, `sdvn_m_s`, `sdve_m_s`, `sdvd_m_s` (one-sigma, local
    /// north/east/down); `rate_hz` thins as in `write` (None: every sample).
    #[pyo3(signature = (rate_hz=None))]
    fn columns<'py>(&self, py: Python<'py>, rate_hz: Option<f64>) -> PyResult<Bound<'py, PyDict>> {
        crate::output::columns(py, &self.local, rate_hz)
    }
    /// `columns(rate_hz)` as a pandas `DataFrame`; `ImportError` saying what
    /// to install when pandas is not installed.
    #[pyo3(signature = (rate_hz=None))]
    fn to_pandas<'py>(&self, py: Python<'py>, rate_hz: Option<f64>) -> PyResult<Bound<'py, PyAny>> {
        crate::output::data_frame(py, &self.local, rate_hz, "pandas", "to_pandas")
    }
    /// `columns(rate_hz)` as a polars `DataFrame`; `ImportError` saying what
    /// to install when polars is not installed.
    #[pyo3(signature = (rate_hz=None))]
    fn to_polars<'py>(&self, py: Python<'py>, rate_hz: Option<f64>) -> PyResult<Bound<'py, PyAny>> {
        crate::output::data_frame(py, &self.local, rate_hz, "polars", "to_polars")
    }
    fn __len__(&self) -> usize {
        self.local.time_s.len()
    }
}

fn pairs<'py>(py: Python<'py>, v: &[(f64, f64)]) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let flat: Vec<f64> = v.iter().flat_map(|&(a, b)| [a, b]).collect();
    PyArray1::from_vec(py, flat).reshape([v.len(), 2])
}

/// Navigates a real log: `time` (N,) IMU time stamps on GNSS time, s;
/// `specific_force`, `angular_rate` (N, 3) in the sensor's axes, SI; `gnss`
/// the GNSS measurements (`GnssMeasurements` or its padded arrays: tight
/// coupling) or position fixes (`PositionFixes`, `FixSeries` or a dict of
/// arrays: loose coupling). `settings`: `{table: {key: value}}` as in a
/// `navigate` configuration (`navigate_settings()` lists them; left-out
/// keys keep the engine's defaults). `duration_s` stops that long after
/// the start.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (time, specific_force, angular_rate, gnss, *, settings=None, duration_s=None))]
fn navigate_log(
    py: Python<'_>,
    time: &Bound<'_, PyAny>,
    specific_force: &Bound<'_, PyAny>,
    angular_rate: &Bound<'_, PyAny>,
    gnss: &Bound<'_, PyAny>,
    settings: Option<&Bound<'_, PyDict>>,
    duration_s: Option<f64>,
) -> PyResult<PyLogRun> {
    let time = convert::scalars(time, "time")?;
    let f = convert::vectors(specific_force, "specific_force")?;
    let w = convert::vectors(angular_rate, "angular_rate")?;
    let input = if gnss.cast::<PyPositionFixes>().is_ok() {
        GnssInput::Fixes(position_fixes(gnss)?)
    } else if is_measurements(gnss) {
        GnssInput::Measurements(gnss_epochs(gnss)?.into_owned())
    } else {
        GnssInput::Fixes(position_fixes(gnss)?)
    };
    let tables = settings_tables(settings)?;
    let mut config =
        LogConfig::from_settings(&tables, navigate::sample_rate_hz(&time).py()?).py()?;
    config.duration_s = duration_s;
    let run = py
        .detach(|| navigate::navigate_log(&time, &f, &w, &input, &config))
        .py()?;
    crate::warnings::warn_all(py, &run.solution.warnings)?;
    if let Some(f) = &run.failure {
        crate::warnings::warn_all(
            py,
            &[format!(
                "the run stopped at t = {} s, before the end of the log: {} (its solution ends \
                 there; LogRun.failure)",
                f.time_s, f.message
            )],
        )?;
    }
    let mut run = run;
    let local = run.local_solution();
    let smoothed = match (run.local_smoothed(), run.smoothed.take()) {
        (Some(local), Some(solution)) => Some(Py::new(
            py,
            PyLogRun {
                run: LogRun {
                    solution,
                    smoothed: None,
                    gnss: run.gnss.clone(),
                    gnss_used: run.gnss_used.clone(),
                    outages: run.outages.clone(),
                    standstills: run.standstills.clone(),
                    range_biases: run.range_biases.clone(),
                    failure: run.failure.clone(),
                    late_start: run.late_start.clone(),
                    adaptation: run.adaptation.clone(),
                    ..run
                },
                local,
                smoothed: None,
            },
        )?),
        _ => None,
    };
    Ok(PyLogRun {
        run,
        local,
        smoothed,
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(navigate_log, m)?)?;
    m.add_function(wrap_pyfunction!(navigate_settings, m)?)?;
    m.add_function(wrap_pyfunction!(navigate_settings_schema, m)?)?;
    m.add_function(wrap_pyfunction!(check_navigate_settings, m)?)?;
    m.add_function(wrap_pyfunction!(mounting_matrix, m)?)?;
    m.add_function(wrap_pyfunction!(fixes_from_solution, m)?)?;
    m.add_function(wrap_pyfunction!(truth_at_point, m)?)?;
    m.add_class::<PyLogRun>()?;
    m.add_class::<PyRunStart>()?;
    m.add_class::<PyInitialState>()?;
    m.add_class::<PyRunFailure>()?;
    m.add_class::<PyGyroScaleCheck>()?;
    m.add_class::<PyCarrierPhaseUse>()?;
    Ok(())
}
