//! `TightlyCoupledFilter`, `LooselyCoupledFilter` and their `FilterSolution`:
//! the coupled GNSS/INS filters of memsnav-core (method §5) on the user's
//! arrays, one Rust call per series with the GIL released.

use memsnav_core::coupling::factory;
use memsnav_core::coupling::{
    self, initial_state_from_fix, initial_state_from_position_fix, FilterTuning, InitialState,
    Solution,
};
use memsnav_core::filter::state::{RangeBiasSlots, StateBlocks, StateLayout};
use memsnav_core::gnss::ReceiverClockModel;
use memsnav_core::ins::{ImuData, ImuIncrement, NavState};
use memsnav_core::navigate::FilterSettings;
use memsnav_py_macros::catch_panics;
use nalgebra::{Matrix3, Vector3};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::aiding::position_fixes;
use crate::arguments::{check_keys, field, optional_field, settings_tables};
use crate::convert;
use crate::errors::IntoPyResult;
use crate::gnss::gnss_epochs;
use crate::records::{
    batches_to_dict, integrity_record, measurements_to_dict, resets_to_dict, PyConsistency,
    PyIntegrity, PyIntegrityAlert,
};
use crate::running_filter::{sample_arg, PyRunningFilter, StartedBy};
use crate::sensors::PyImuModel;

/// The tuning both filter classes share (see the class docstrings).
#[derive(Clone)]
struct Settings {
    tuning: FilterTuning,
    scale_factor_states: bool,
    /// The filter `settings=` describes (its tuning is `tuning`).
    navigate: Option<FilterSettings>,
    sample_rate_hz: f64,
}

impl Settings {
    /// The state blocks for this class's aiding (`tight`: pseudoranges),
    /// with inter-system biases when the pseudoranges need them.
    fn blocks(&self, tight: bool, inter_system_biases: bool) -> StateBlocks {
        match &self.navigate {
            Some(f) => f.blocks(tight, inter_system_biases),
            None => StateBlocks {
                scale_factors: self.scale_factor_states,
                inter_system_biases,
                ..StateBlocks::default()
            },
        }
    }
}

/// The IMU arrays of `run` (or of `run_increments`, with the means of
/// the increments as samples), validated with the argument names.
struct ImuArrays {
    time: Vec<f64>,
    specific_force: Vec<Vector3<f64>>,
    angular_rate: Vec<Vector3<f64>>,
    increments: Option<Vec<ImuIncrement>>,
}

impl ImuArrays {
    fn new(
        time: &Bound<'_, PyAny>,
        specific_force: &Bound<'_, PyAny>,
        angular_rate: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let out = Self {
            time: convert::scalars(time, "time")?,
            specific_force: convert::vectors(specific_force, "specific_force")?,
            angular_rate: convert::vectors(angular_rate, "angular_rate")?,
            increments: None,
        };
        out.data().validate().py()?;
        Ok(out)
    }

    fn from_increments(
        time: &Bound<'_, PyAny>,
        delta_v: &Bound<'_, PyAny>,
        delta_theta: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let time = convert::scalars(time, "time")?;
        let delta_v = convert::vectors(delta_v, "delta_v")?;
        let delta_theta = convert::vectors(delta_theta, "delta_theta")?;
        memsnav_core::validate::same_length(
            "delta_theta",
            delta_theta.len(),
            "delta_v",
            delta_v.len(),
        )
        .py()?;
        let increments: Vec<ImuIncrement> = delta_v
            .iter()
            .zip(&delta_theta)
            .map(|(v, a)| ImuIncrement {
                delta_velocity_b: *v,
                delta_angle_b: *a,
            })
            .collect();
        if time.len() < 2 {
            return Err(PyValueError::new_err(format!(
                "time: needs at least two times (one interval), got {}",
                time.len()
            )));
        }
        let (specific_force, angular_rate) =
            ImuData::means_of_increments(&time, &increments).py()?;
        let out = Self {
            time,
            specific_force,
            angular_rate,
            increments: Some(increments),
        };
        out.data().validate().py()?;
        Ok(out)
    }

    fn data(&self) -> ImuData<'_> {
        ImuData {
            time_s: &self.time,
            specific_force_b: &self.specific_force,
            angular_rate_b: &self.angular_rate,
            increments: self.increments.as_deref(),
        }
    }
}

fn attitude_arg(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Matrix3<f64>>> {
    match obj {
        Some(o) if !o.is_none() => {
            let c = convert::matrix3(o, "initial_attitude")?;
            memsnav_core::validate::rotation("initial_attitude", &c).py()?;
            Ok(Some(c))
        }
        _ => Ok(None),
    }
}

/// The entries `initial_state=` may have.
const INITIAL_STATE_KEYS: [&str; 5] = [
    "position_ecef",
    "velocity_ecef",
    "attitude",
    "clock_offset",
    "clock_drift",
];

/// `initial_state=`: a dict (no other keys) or an object with
/// `position_ecef` (3,) m and `velocity_ecef` (3,) m/s at the first IMU
/// time, `attitude` C_b^e (3, 3), optional `clock_offset` m and
/// `clock_drift` m/s (None: from the first epoch's residuals).
fn initial_state_arg(obj: &Bound<'_, PyAny>) -> PyResult<InitialState> {
    const ARG: &str = "initial_state";
    check_keys(obj, ARG, &INITIAL_STATE_KEYS)?;
    let vector = |name: &str| convert::vector3(&field(obj, name, ARG)?, &format!("{ARG}.{name}"));
    let clock = |name: &str| -> PyResult<Option<f64>> {
        optional_field(obj, name)?
            .map(|v| {
                let x: f64 = v.extract().map_err(|_| {
                    PyValueError::new_err(format!("{ARG}.{name}: must be a number or None"))
                })?;
                memsnav_core::validate::finite_scalars(&format!("{ARG}.{name}"), &[x]).py()?;
                Ok(x)
            })
            .transpose()
    };
    let c_b_e = convert::matrix3(&field(obj, "attitude", ARG)?, "initial_state.attitude")?;
    memsnav_core::validate::rotation("initial_state.attitude", &c_b_e).py()?;
    let state = InitialState {
        nav: NavState {
            position_ecef: vector("position_ecef")?,
            velocity_ecef: vector("velocity_ecef")?,
            c_b_e,
        },
        accel_bias_m_s2: Vector3::zeros(),
        gyro_bias_rad_s: Vector3::zeros(),
        clock_offset_m: clock("clock_offset")?,
        clock_drift_m_s: clock("clock_drift")?,
    };
    state.validate().py()?;
    Ok(state)
}

/// Where a run starts: the caller's state, or one the filter builds from
/// its first aiding epoch with this attitude (None: coarse).
enum Start {
    Given(InitialState),
    FromAiding(Option<Matrix3<f64>>),
}

fn start(
    initial_state: Option<&Bound<'_, PyAny>>,
    initial_attitude: Option<&Bound<'_, PyAny>>,
) -> PyResult<Start> {
    let state = initial_state.filter(|o| !o.is_none());
    let attitude = attitude_arg(initial_attitude)?;
    match (state, attitude) {
        (Some(_), Some(_)) => Err(PyValueError::new_err(
            "initial_attitude: give it or initial_state (which holds the attitude), not both",
        )),
        (Some(s), None) => Ok(Start::Given(initial_state_arg(s)?)),
        (None, a) => Ok(Start::FromAiding(a)),
    }
}

/// The whole solution of a coupled filter, at every IMU sample (SI units).
///
/// Measurement records (``measurements``, ``rejected``) are dicts of arrays:
/// ``time`` (s), ``id`` (satellite id; fix component 0-2 for the loose
/// filter; axis for the aids), ``kind`` ("pseudorange" m, "pseudorange_rate"
/// m/s, "carrier_phase" m: a carrier change between consecutive epochs with
/// the epoch's weighted mean removed, "position" / "velocity" whitened,
/// unit variance, "zero_velocity", "zero_rate", "non_holonomic"),
/// ``innovation`` (measurement minus the prediction before the epoch's
/// updates), ``innovation_std``, ``nis`` (nu²/s), ``status`` ("accepted";
/// "gate": its batch failed the chi-square test; "excluded": left out of
/// its batch by fault exclusion; "invalid": NaN/inf value or non-positive
/// std; "reset": its batch failed and the filter was reset from it;
/// "slip": a carrier change holding a cycle slip, flagged by the receiver
/// or found against the Doppler, not used; "too-few": a clean carrier
/// change whose epoch had fewer than the 5 a batch needs, not used).
#[pyclass(name = "FilterSolution", module = "memsnav._memsnav", frozen)]
pub struct PyFilterSolution {
    inner: Solution,
    smoothed: Option<Py<PyFilterSolution>>,
}

impl PyFilterSolution {
    /// The solution at the IMU in local terms (geodetic, NED, Euler angles).
    fn local(&self) -> memsnav_core::output::LocalSolution {
        memsnav_core::output::LocalSolution::new(&self.inner, Vector3::zeros())
    }

    pub(crate) fn new(inner: Solution) -> Self {
        Self {
            inner,
            smoothed: None,
        }
    }

    /// A forward solution and, when there is one, its smoothed solution.
    fn with_smoothed(
        py: Python<'_>,
        forward: Solution,
        smoothed: Option<Solution>,
    ) -> PyResult<Self> {
        Ok(Self {
            inner: forward,
            smoothed: smoothed.map(|s| Py::new(py, Self::new(s))).transpose()?,
        })
    }

    /// A navigation block of P at every sample, `(N, 3, 3)` (the solution
    /// stores each block's upper triangle beside the diagonal).
    fn navigation_covariance<'py>(
        &self,
        py: Python<'py>,
        block: fn(&Solution, usize) -> Matrix3<f64>,
    ) -> Bound<'py, numpy::PyArray3<f64>> {
        let blocks: Vec<Matrix3<f64>> = (0..self.inner.time_s.len())
            .map(|k| block(&self.inner, k))
            .collect();
        convert::matrices3_to_numpy(py, &blocks)
    }
}

#[catch_panics]
#[pymethods]
impl PyFilterSolution {
    fn __repr__(&self) -> String {
        let t = &self.inner.time_s;
        let span = match (t.first(), t.last()) {
            (Some(a), Some(b)) => format!(", {a:.3}-{b:.3} s"),
            _ => String::new(),
        };
        let smoothed = if self.smoothed.is_some() {
            ", smoothed"
        } else {
            ""
        };
        format!("FilterSolution({} samples{span}{smoothed})", t.len())
    }

    /// IMU sample times, s, (N,).
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.time_s)
    }
    /// Position, ECEF m, (N, 3).
    #[getter]
    fn position_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.position_ecef)
    }
    /// Velocity, ECEF m/s, (N, 3).
    #[getter]
    fn velocity_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.velocity_ecef)
    }
    /// Attitude C_b^e (body to ECEF), (N, 3, 3).
    #[getter]
    fn attitude<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray3<f64>> {
        convert::matrices3_to_numpy(py, &self.inner.c_b_e)
    }
    /// Accelerometer bias estimate, m/s², (N, 3), additive: reading = truth +
    /// bias (an ``AccelerometerModel.bias`` enters as S = Γ - b, so the
    /// estimate converges to minus it).
    #[getter]
    fn accel_bias<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.accel_bias_m_s2)
    }
    /// Gyro bias estimate, rad/s, (N, 3), additive like ``accel_bias``.
    #[getter]
    fn gyro_bias<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.gyro_bias_rad_s)
    }
    /// Accelerometer scale-factor estimate, (N, 3); None without scale-factor states.
    #[getter]
    fn accel_scale_factor<'py>(&self, py: Python<'py>) -> Option<Bound<'py, numpy::PyArray2<f64>>> {
        // Empty without the states (17 or 29 states with range biases).
        (!self.inner.accel_scale_factor.is_empty())
            .then(|| convert::vectors_to_numpy(py, &self.inner.accel_scale_factor))
    }
    /// Gyro scale-factor estimate, (N, 3); None without scale-factor states.
    #[getter]
    fn gyro_scale_factor<'py>(&self, py: Python<'py>) -> Option<Bound<'py, numpy::PyArray2<f64>>> {
        // Empty without the states (17 or 29 states with range biases).
        (!self.inner.gyro_scale_factor.is_empty())
            .then(|| convert::vectors_to_numpy(py, &self.inner.gyro_scale_factor))
    }
    /// Inter-system bias estimates (Galileo, BeiDou, GLONASS pseudoranges
    /// minus GPS's), m, (N, 3); None without the inter-system-bias states.
    #[getter]
    fn inter_system_bias<'py>(&self, py: Python<'py>) -> Option<Bound<'py, numpy::PyArray2<f64>>> {
        (!self.inner.inter_system_bias_m.is_empty()).then(|| {
            numpy::PyArray2::from_vec2(
                py,
                &self
                    .inner
                    .inter_system_bias_m
                    .iter()
                    .map(|r| r.to_vec())
                    .collect::<Vec<_>>(),
            )
            .expect("rows of equal length")
        })
    }

    /// Installation estimates, (N, 7): antenna lever arm x, y, z (body
    /// axes, m), IMU time offset (s), velocity latency (s), mounting
    /// boresight pitch, yaw (rad); None without the installation states.
    #[getter]
    fn installation<'py>(&self, py: Python<'py>) -> Option<Bound<'py, numpy::PyArray2<f64>>> {
        (!self.inner.installation.is_empty()).then(|| {
            numpy::PyArray2::from_vec2(
                py,
                &self
                    .inner
                    .installation
                    .iter()
                    .map(|r| r.to_vec())
                    .collect::<Vec<_>>(),
            )
            .expect("rows of equal length")
        })
    }
    /// Receiver clock offset, m, (N,).
    #[getter]
    fn clock_offset<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.clock_offset_m)
    }
    /// Receiver clock drift, m/s, (N,).
    #[getter]
    fn clock_drift<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.clock_drift_m_s)
    }
    /// Diagonal of the error covariance, (N, n_states), order ``state_names``
    /// (rad², (m/s)², m², (m/s²)², (rad/s)², m², (m/s)², dimensionless²).
    #[getter]
    fn covariance_diagonal<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
        PyArray1::from_slice(py, &self.inner.covariance_diagonal)
            .reshape([self.inner.time_s.len(), self.inner.n_states])
    }
    /// Position-error covariance (ECEF axes), m², (N, 3, 3).
    #[getter]
    fn position_covariance_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray3<f64>> {
        self.navigation_covariance(py, Solution::position_covariance_ecef)
    }
    /// Velocity-error covariance (ECEF axes), m²/s², (N, 3, 3).
    #[getter]
    fn velocity_covariance_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray3<f64>> {
        self.navigation_covariance(py, Solution::velocity_covariance_ecef)
    }
    /// Attitude-error covariance (ECEF axes), rad², (N, 3, 3).
    #[getter]
    fn attitude_covariance_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray3<f64>> {
        self.navigation_covariance(py, Solution::attitude_covariance_ecef)
    }
    /// One-sigma position uncertainty along north, east, down, m, (N, 3): the
    /// position block rotated into the local NED axes of each sample.
    #[getter]
    fn position_std_ned<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.position_std_ned())
    }
    /// One-sigma velocity uncertainty along north, east, down, m/s, (N, 3).
    #[getter]
    fn velocity_std_ned<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.velocity_std_ned())
    }
    /// One-sigma attitude uncertainty about north, east, down, rad, (N, 3).
    #[getter]
    fn attitude_std_ned<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.attitude_std_ned())
    }
    /// The fixed-interval smoothed solution (``run(..., smooth=True)``),
    /// else None.
    #[getter]
    fn smoothed(&self, py: Python<'_>) -> Option<Py<PyFilterSolution>> {
        self.smoothed.as_ref().map(|s| s.clone_ref(py))
    }
    /// Error-state names: attitude_x..z (ECEF, rad), velocity_x..z, position_x..z,
    /// accel_bias_x..z, gyro_bias_x..z, clock_offset, clock_drift
    /// [, accel_scale_factor_x..z, gyro_scale_factor_x..z]
    /// [, lever_arm_x..z, time_offset, velocity_latency, mounting_pitch, mounting_yaw]
    /// [, inter_system_bias_galileo, _beidou, _glonass] [, range_bias_0, ...].
    #[getter]
    fn state_names(&self) -> Vec<String> {
        StateLayout::names(self.inner.n_states)
    }
    /// Every batch test (an epoch's measurements of one kind): dict of arrays
    /// ``time``, ``kind``, ``nis`` (the batch's nu' S^-1 nu), ``dof``,
    /// ``threshold`` (its chi-square quantile), ``excluded`` (measurements left
    /// out by fault exclusion), ``accepted``, ``nonlinearity`` (pseudoranges:
    /// the largest expected curvature term over the position uncertainty in
    /// units of the measurement std, NaN for other kinds; above 0.1 the
    /// first-order model no longer holds, see ``integrity``).
    #[getter]
    fn batches<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        batches_to_dict(py, &self.inner.batches)
    }
    /// Whether the solution can be trusted (docs/explanation/few-satellites.md):
    /// an `Integrity` with ``diverged``, ``alerts`` (`IntegrityAlert`: ``kind``
    /// "gated_batches", "inconsistent_innovations", "beyond_linear_model" or
    /// "applied_outliers", ``time_s`` GNSS time s, ``message``, in time order)
    /// and ``consistency`` (`Consistency` per GNSS kind: ``windows`` of 30 s,
    /// ``windows_above_band`` whose summed NIS exceeded the 0.9999 chi-square
    /// quantile, ``max_band_ratio`` the largest summed NIS over that quantile,
    /// ``max_at_s`` its window's start, s). A ratio above 4 in two windows in
    /// a row is an alert; 1-4 is a tuning mismatch, reported here only.
    /// ``summary.json`` of ``navigate`` has the same keys (its times in
    /// seconds after the start).
    #[getter]
    fn integrity(&self, py: Python<'_>) -> PyResult<PyIntegrity> {
        integrity_record(py, &self.inner.integrity)
    }
    /// Every reset the filter made: dict of arrays ``time``, ``kind``
    /// ("position_to_fix", "velocity_to_fix", "velocity_to_zero" (a standstill
    /// whose ZUPTs kept failing), "clock_jump", "clock_drift_jump",
    /// "inflation", "fading", "heading"), ``change`` (m, m/s, rad, or the
    /// inflation or fading factor), ``unit`` (of each change: "m", "m/s",
    /// "rad", "" for a factor), ``failed_epochs`` (consecutive failed epochs
    /// before it).
    #[getter]
    fn resets<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        resets_to_dict(py, &self.inner.resets)
    }
    /// Every scalar measurement: dict of arrays `time`, `id`, `kind`,
    /// `innovation`, `innovation_std`, `nis`, `status`.
    #[getter]
    fn measurements<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        measurements_to_dict(py, self.inner.measurements.iter())
    }
    /// The rejected measurements only (status "gate" or "invalid").
    #[getter]
    fn rejected<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        measurements_to_dict(py, self.inner.rejected())
    }
    /// What the run found implausible, one sentence each (also raised as
    /// `UserWarning`s by `run`): IMU magnitudes that do not fit m/s² and
    /// rad/s, a filter diverged from its GNSS aiding. Empty when all is well.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }
    /// Whether the run raised an integrity alert: its solution and
    /// covariance are not trustworthy (GNSS batches mostly gated,
    /// innovations far outside their chi-square band, or a position too
    /// uncertain for the linearised model, or outliers applied with the
    /// gate off; see `integrity` and `warnings`).
    #[getter]
    fn diverged(&self) -> bool {
        self.inner.integrity.diverged()
    }
    /// Writes the solution at the IMU (its geodetic position, NED velocity, roll/pitch/yaw
    /// and NED one-sigmas) to `path` in `format`: "csv" (`columns()`,
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
        crate::output::write(py, &self.local(), path, format, rate_hz, name, overwrite)
    }
    /// The solution at the IMU (its geodetic position, NED velocity, roll/pitch/yaw
    /// and NED one-sigmas) as columns named with their units, (N,) each:
    /// `gps_time_s`, `lat_deg`, `lon_deg`, `height_m` (ellipsoidal), `vn_m_s`,
    /// `ve_m_s`, `vd_m_s`, `roll_deg`, `pitch_deg`, `yaw_deg`, `sdn_m`, `sde_m`,
    /// `sdd_m`, `sdvn_m_s`, `sdve_m_s`, `sdvd_m_s` (one-sigma, local
    /// north/east/down); `rate_hz` thins as in `write` (None: every sample).
    #[pyo3(signature = (rate_hz=None))]
    fn columns<'py>(&self, py: Python<'py>, rate_hz: Option<f64>) -> PyResult<Bound<'py, PyDict>> {
        crate::output::columns(py, &self.local(), rate_hz)
    }
    /// `columns(rate_hz)` as a pandas `DataFrame`; `ImportError` saying what
    /// to install when pandas is not installed.
    #[pyo3(signature = (rate_hz=None))]
    fn to_pandas<'py>(&self, py: Python<'py>, rate_hz: Option<f64>) -> PyResult<Bound<'py, PyAny>> {
        crate::output::data_frame(py, &self.local(), rate_hz, "pandas", "to_pandas")
    }
    /// `columns(rate_hz)` as a polars `DataFrame`; `ImportError` saying what
    /// to install when polars is not installed.
    #[pyo3(signature = (rate_hz=None))]
    fn to_polars<'py>(&self, py: Python<'py>, rate_hz: Option<f64>) -> PyResult<Bound<'py, PyAny>> {
        crate::output::data_frame(py, &self.local(), rate_hz, "polars", "to_polars")
    }
    fn __len__(&self) -> usize {
        self.inner.time_s.len()
    }
}

/// A filter class: the shared constructor and `tuning`, and `run`, which
/// reads the aiding argument `$aiding` with `$read`, starts from the given
/// state or `$initial` (from the first aiding epoch), and runs
/// `coupling::solution` (or `smoothed_solution` with `smooth=True`) with 17
/// or 23 states; the aiding kind follows from what `$read` returns.
/// The arguments of both filter classes and where their defaults come
/// from: one text for the two docstrings.
macro_rules! filter_arguments_doc {
    () => {
        "Tuning from `imu.spec` at `imu.sample_rate` (`FilterTuning::from_imu_spec`):\n\
        white-noise PSDs = noise density² (or per-sample std² / rate); bias\n\
        processes from bias instability (2 sigma²/tau) and random walk, the\n\
        instability taken as a random walk when the bias has a turn-on part\n\
        (nothing makes a turn-on bias fade); initial bias std =\n\
        sqrt(bias_std² + instability²), floored at 1e-6 m/s² and 1e-9 rad/s;\n\
        errors the states lack (scale factor unless estimated, misalignment,\n\
        nonlinearity, g-sensitivity): their part driven by the specific force at\n\
        rest widens the initial bias std, their part driven by the motion is\n\
        process noise shaped by the sensed specific force and rate at every step,\n\
        2 sigma² tau with the manoeuvres' correlation time tau = 10 s\n\
        (`filter::input_noise`). Receiver clock: the simulator's TCXO\n\
        (`clock_h0` 2e-19, `clock_h_minus2` 2e-20, the same names and model\n\
        as `simulate_gnss`: S_cφ = c² h0 / 2, S_cf = 2π² c² h−2). Every default\n\
        below can be overridden; an argument left None takes the core's\n\
        default, listed by `memsnav.defaults()` under the class name\n\
        (`tuning` shows the values in effect):\n\
        \n\
        - `imu`: the `ImuModel` whose spec and sample rate tune the filter.\n\
        - `settings` [None]: a `navigate` configuration's tables as a dict\n\
        \x20\x20(`{\"filter\": {...}, \"gnss\": {...}, \"imu\": {...}, \"imu_spec\": {...},\n\
        \x20\x20\"standstill\": {...}, \"aids\": {...}}`, the keys `navigate_settings()`\n\
        \x20\x20lists, with their units and defaults): the filter is navigate's for\n\
        \x20\x20those keys, defaults included (range-bias states on for pseudoranges;\n\
        \x20\x20`gnss.range_bias_states = \"every_satellite\"` gives each of up to 40\n\
        \x20\x20satellites one), tuned from `imu.spec`, and `run` applies navigate's\n\
        \x20\x20aids as a navigate run does: zero-velocity and zero-rate updates at the\n\
        \x20\x20standstills it detects (on unless `aids.zupt`/`aids.zaru` are false)\n\
        \x20\x20and, with `aids.nhc`, the non-holonomic constraint (give\n\
        \x20\x20`aids.nhc_std_m_s`). Tables and keys that prepare a navigate run\n\
        \x20\x20(`[alignment]`, `[outages]`, `filter.imu_preset`, `filter.smoother`,\n\
        \x20\x20`imu.time_offset_s`, `imu.mounting_rpy_deg`, any `\"auto\"`) raise\n\
        \x20\x20ValueError naming them, and `start` raises while an aid is on. Not with\n\
        \x20\x20the keywords below.\n\
        - `scale_factor_states` [False]: six more states, the accelerometer and\n\
        \x20\x20gyro scale factors (23 in all).\n\
        - `accel_noise_density` (m/s²/√Hz), `gyro_noise_density` (rad/s/√Hz):\n\
        \x20\x20replace the sensor's white PSDs by density² (the input-shaped noise of\n\
        \x20\x20the unmodelled errors stays).\n\
        - `accel_bias_psd` ((m/s²)²/s), `gyro_bias_psd` ((rad/s)²/s): bias\n\
        \x20\x20driving-noise PSDs.\n\
        - `gate_probability`: chi-square(1) gate, 0.999 (|nu| > 3.29 sigma rejected\n\
        \x20\x20and reported); 1.0 disables it.\n\
        - initial one-sigmas: `initial_position_std` 5 m and\n\
        \x20\x20`initial_velocity_std` 0.5 m/s per ECEF axis (a code fix),\n\
        \x20\x20`initial_tilt_std` 1° and `initial_heading_std` 5° (in rad),\n\
        \x20\x20`initial_accel_bias_std` / `initial_gyro_bias_std` (None: from the\n\
        \x20\x20spec as above), `initial_clock_offset_std` 50 m,\n\
        \x20\x20`initial_clock_drift_std` 10 m/s; scale factors (23 states): the\n\
        \x20\x20spec's scale_factor_std (floored at 1e-6).\n\
        - `use_pseudorange_rate`: use rates when the epoch carries them.\n\
        - `use_carrier_phase`: use each satellite's carrier-phase change\n\
        \x20\x20between consecutive epochs (time-differenced carrier phase, as a\n\
        \x20\x20velocity measurement; cycle slips found from the receiver's flags,\n\
        \x20\x20the Doppler and the residual test) when the epochs carry it.\n\
        - `clock_h0`, `clock_h_minus2`: the receiver oscillator's Allan\n\
        \x20\x20coefficients (None: the TCXO above).\n\
        - `manoeuvre_correlation_time`: tau of the input-shaped noise, s (None:\n\
        \x20\x2010 s, a land vehicle's turns and accelerations; shorter for a walker).\n\
        - `pseudorange_correlation_time`: correlation time of the code's fast\n\
        \x20\x20errors (multipath), s (None: 0, white); each pseudorange's std is\n\
        \x20\x20inflated by sqrt((1 + rho)/(1 - rho)), rho = exp(-dt/tau) over the\n\
        \x20\x20epoch interval dt, so that epochs sampling one error carry it once\n\
        \x20\x20(docs/how-to/multi-gnss.md, \"Correlated code errors\")."
    };
}

macro_rules! filter_class {
    ($(#[$class_doc:meta])* $rust:ident, $py:literal, $aiding:ident, $read:ident, $initial:ident, $started_by:expr, $doc:literal) => {
        $(#[$class_doc])*
        #[doc = ""]
        #[doc = filter_arguments_doc!()]
        #[pyclass(name = $py, module = "memsnav._memsnav", frozen)]
        pub struct $rust {
            settings: Settings,
        }

        #[catch_panics]
        #[pymethods]
        impl $rust {
            fn __repr__(&self) -> String {
                let s = &self.settings;
                let blocks = s.blocks($started_by == StartedBy::Tight, false);
                let named = [
                    (blocks.scale_factors, ", scale factors"),
                    (blocks.installation, ", installation"),
                    (blocks.range_biases != RangeBiasSlots::None, ", range biases"),
                ];
                let aids = match s.navigate.as_ref().map(FilterSettings::aids) {
                    Some(aids) if !aids.is_empty() => format!(", aids {}", aids.join("+")),
                    _ => String::new(),
                };
                format!(
                    "{}({} Hz IMU, {} error states{}{aids})",
                    $py,
                    s.sample_rate_hz,
                    blocks.size(),
                    named.iter().filter(|(on, _)| *on).map(|(_, n)| *n).collect::<String>()
                )
            }

            #[new]
            #[pyo3(signature = (imu, *, settings=None, scale_factor_states=false, accel_noise_density=None, gyro_noise_density=None, accel_bias_psd=None, gyro_bias_psd=None, gate_probability=None, initial_position_std=None, initial_velocity_std=None, initial_tilt_std=None, initial_heading_std=None, initial_accel_bias_std=None, initial_gyro_bias_std=None, initial_clock_offset_std=None, initial_clock_drift_std=None, use_pseudorange_rate=true, use_carrier_phase=false, clock_h0=None, clock_h_minus2=None, manoeuvre_correlation_time=None, pseudorange_correlation_time=None))]
            fn new(
                imu: &PyImuModel,
                settings: Option<&Bound<'_, PyDict>>,
                scale_factor_states: bool,
                accel_noise_density: Option<f64>,
                gyro_noise_density: Option<f64>,
                accel_bias_psd: Option<f64>,
                gyro_bias_psd: Option<f64>,
                gate_probability: Option<f64>,
                initial_position_std: Option<f64>,
                initial_velocity_std: Option<f64>,
                initial_tilt_std: Option<f64>,
                initial_heading_std: Option<f64>,
                initial_accel_bias_std: Option<f64>,
                initial_gyro_bias_std: Option<f64>,
                initial_clock_offset_std: Option<f64>,
                initial_clock_drift_std: Option<f64>,
                use_pseudorange_rate: bool,
                use_carrier_phase: bool,
                clock_h0: Option<f64>,
                clock_h_minus2: Option<f64>,
                manoeuvre_correlation_time: Option<f64>,
                pseudorange_correlation_time: Option<f64>,
            ) -> PyResult<Self> {
                let model = &imu.inner;
                if let Some(settings) = settings {
                    let keywords = [
                        accel_noise_density, gyro_noise_density, accel_bias_psd, gyro_bias_psd,
                        gate_probability, initial_position_std, initial_velocity_std,
                        initial_tilt_std, initial_heading_std, initial_accel_bias_std,
                        initial_gyro_bias_std, initial_clock_offset_std, initial_clock_drift_std,
                        clock_h0, clock_h_minus2, manoeuvre_correlation_time,
                        pseudorange_correlation_time,
                    ];
                    if keywords.iter().any(Option::is_some)
                        || scale_factor_states
                        || !use_pseudorange_rate
                        || use_carrier_phase
                    {
                        return Err(PyValueError::new_err(
                            "settings: give the tuning as settings or as keywords, not both",
                        ));
                    }
                    let navigate = FilterSettings::from_settings(
                        &settings_tables(Some(settings))?,
                        &model.spec,
                        model.sample_rate_hz,
                    )
                    .py()?;
                    return Ok(Self {
                        settings: Settings {
                            tuning: *navigate.tuning(),
                            scale_factor_states: navigate.scale_factor_states(),
                            navigate: Some(navigate),
                            sample_rate_hz: model.sample_rate_hz,
                        },
                    });
                }
                let mut tuning =
                    FilterTuning::from_imu_spec(&model.spec, model.sample_rate_hz, scale_factor_states).py()?;
                let q = &mut tuning.process_noise;
                for (name, value, target) in [
                    (
                        "accel_noise_density",
                        accel_noise_density,
                        &mut q.accel_white_psd,
                    ),
                    (
                        "gyro_noise_density",
                        gyro_noise_density,
                        &mut q.gyro_white_psd,
                    ),
                ] {
                    if let Some(d) = value {
                        *target = memsnav_core::validate::squared_std(name, d).py()?;
                    }
                }
                if let Some(v) = accel_bias_psd {
                    q.accel_bias_psd = v;
                }
                if let Some(v) = gyro_bias_psd {
                    q.gyro_bias_psd = v;
                }
                // None keeps the core's default (`defaults()`).
                let s = &mut tuning.initial_std;
                for (value, target) in [
                    (initial_position_std, &mut s.position_m),
                    (initial_velocity_std, &mut s.velocity_m_s),
                    (initial_accel_bias_std, &mut s.accel_bias_m_s2),
                    (initial_gyro_bias_std, &mut s.gyro_bias_rad_s),
                    (initial_clock_offset_std, &mut s.clock_offset_m),
                    (initial_clock_drift_std, &mut s.clock_drift_m_s),
                    (gate_probability, &mut tuning.gate_probability),
                ] {
                    if let Some(v) = value {
                        *target = v;
                    }
                }
                let attitude = &mut s.attitude_ned_rad;
                if let Some(tilt) = initial_tilt_std {
                    (attitude.x, attitude.y) = (tilt, tilt);
                }
                if let Some(heading) = initial_heading_std {
                    attitude.z = heading;
                }
                tuning.use_pseudorange_rate = use_pseudorange_rate;
                tuning.use_carrier_phase = use_carrier_phase;
                let default_clock = ReceiverClockModel::default();
                let clock = ReceiverClockModel {
                    h0: clock_h0.unwrap_or(default_clock.h0),
                    h_minus2: clock_h_minus2.unwrap_or(default_clock.h_minus2),
                    ..default_clock
                };
                clock.validate().py()?;
                tuning.set_receiver_clock(&clock);
                if let Some(tau) = manoeuvre_correlation_time {
                    tuning.process_noise.input_errors.correlation_time_s = tau;
                }
                if let Some(tau) = pseudorange_correlation_time {
                    tuning.pseudorange_correlation_time_s = tau;
                }
                tuning.validate().py()?;
                Ok(Self {
                    settings: Settings {
                        tuning,
                        scale_factor_states,
                        navigate: None,
                        sample_rate_hz: model.sample_rate_hz,
                    },
                })
            }

            /// The tuning in effect (PSDs, correlation times, initial one-sigmas,
            /// the unmodelled errors' one-sigmas ``unmodelled_*_std`` and
            /// ``manoeuvre_correlation_time``), SI, and the optional state blocks
            /// (``scale_factor_states``, ``installation_states``,
            /// ``range_bias_states``: False, True for 12 shared slots or
            /// "every_satellite"), and the ``aids`` `run` applies ("zupt, zaru"
            /// from `settings` by default, "" without them).
            #[getter]
            fn tuning<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
                let t = &self.settings.tuning;
                let q = &t.process_noise;
                let s = &t.initial_std;
                let d = PyDict::new(py);
                d.set_item("sample_rate", self.settings.sample_rate_hz)?;
                d.set_item("scale_factor_states", self.settings.scale_factor_states)?;
                let blocks = self.settings.blocks($started_by == StartedBy::Tight, false);
                d.set_item("installation_states", blocks.installation)?;
                match blocks.range_biases {
                    RangeBiasSlots::None => d.set_item("range_bias_states", false)?,
                    RangeBiasSlots::Shared => d.set_item("range_bias_states", true)?,
                    RangeBiasSlots::EverySatellite => d.set_item("range_bias_states", "every_satellite")?,
                }
                // The aids `run` applies (navigate's `[aids]` keys), "" for none.
                let aids = self.settings.navigate.as_ref().map(FilterSettings::aids).unwrap_or_default();
                d.set_item("aids", aids.join(", "))?;
                d.set_item("accel_white_psd", q.accel_white_psd)?;
                d.set_item("gyro_white_psd", q.gyro_white_psd)?;
                d.set_item("accel_bias_psd", q.accel_bias_psd)?;
                d.set_item("accel_bias_correlation_time", q.accel_bias_correlation_time_s)?;
                d.set_item("gyro_bias_psd", q.gyro_bias_psd)?;
                d.set_item("gyro_bias_correlation_time", q.gyro_bias_correlation_time_s)?;
                d.set_item("clock_phase_psd", q.clock_phase_psd)?;
                d.set_item("clock_frequency_psd", q.clock_frequency_psd)?;
                let e = &q.input_errors;
                d.set_item("unmodelled_accel_scale_factor_std", e.errors.accel_scale_factor)?;
                d.set_item("unmodelled_accel_misalignment_std", e.errors.accel_misalignment)?;
                d.set_item("unmodelled_accel_nonlinearity_std", e.errors.accel_nonlinearity_per_m_s2)?;
                d.set_item("unmodelled_gyro_scale_factor_std", e.errors.gyro_scale_factor)?;
                d.set_item("unmodelled_gyro_misalignment_std", e.errors.gyro_misalignment)?;
                d.set_item("unmodelled_gyro_g_sensitivity_std", e.errors.gyro_g_sensitivity_rad_s_per_m_s2)?;
                d.set_item("manoeuvre_correlation_time", e.correlation_time_s)?;
                d.set_item("gate_probability", t.gate_probability)?;
                d.set_item("use_pseudorange_rate", t.use_pseudorange_rate)?;
                d.set_item("use_carrier_phase", t.use_carrier_phase)?;
                d.set_item("pseudorange_correlation_time", t.pseudorange_correlation_time_s)?;
                d.set_item("initial_position_std", s.position_m)?;
                d.set_item("initial_velocity_std", s.velocity_m_s)?;
                d.set_item("initial_tilt_std", s.attitude_ned_rad.x)?;
                d.set_item("initial_heading_std", s.attitude_ned_rad.z)?;
                d.set_item("initial_accel_bias_std", s.accel_bias_m_s2)?;
                d.set_item("initial_gyro_bias_std", s.gyro_bias_rad_s)?;
                d.set_item("initial_clock_offset_std", s.clock_offset_m)?;
                d.set_item("initial_clock_drift_std", s.clock_drift_m_s)?;
                d.set_item("initial_accel_scale_factor_std", s.accel_scale_factor)?;
                d.set_item("initial_gyro_scale_factor_std", s.gyro_scale_factor)?;
                Ok(d)
            }

            #[doc = $doc]
            #[pyo3(signature = (time, specific_force, angular_rate, $aiding, *, initial_attitude=None, initial_state=None, smooth=false))]
            fn run(
                &self,
                py: Python<'_>,
                time: &Bound<'_, PyAny>,
                specific_force: &Bound<'_, PyAny>,
                angular_rate: &Bound<'_, PyAny>,
                $aiding: &Bound<'_, PyAny>,
                initial_attitude: Option<&Bound<'_, PyAny>>,
                initial_state: Option<&Bound<'_, PyAny>>,
                smooth: bool,
            ) -> PyResult<PyFilterSolution> {
                let imu = ImuArrays::new(time, specific_force, angular_rate)?;
                self.run_on(py, &imu, $aiding, initial_attitude, initial_state, smooth)
            }

            /// `run` on an integrating IMU's output: `time` (N + 1,) s and the
            /// increments of each interval, `delta_v` (N, 3) m/s and
            /// `delta_theta` (N, 3) rad (row k over [time[k], time[k + 1]], as
            /// `imu_increments` gives them), integrated by the increments
            /// mechanization with coning and sculling (`strapdown_increments`'s)
            /// instead of from samples; an epoch between two times takes its
            /// share of the interval's increments at constant rates. The rest
            /// (aiding, start, smoothing, the solution at every time) as `run`;
            /// the mean rates of the intervals stand for samples where one is
            /// looked at (levelling the start).
            #[pyo3(signature = (time, delta_v, delta_theta, $aiding, *, initial_attitude=None, initial_state=None, smooth=false))]
            fn run_increments(
                &self,
                py: Python<'_>,
                time: &Bound<'_, PyAny>,
                delta_v: &Bound<'_, PyAny>,
                delta_theta: &Bound<'_, PyAny>,
                $aiding: &Bound<'_, PyAny>,
                initial_attitude: Option<&Bound<'_, PyAny>>,
                initial_state: Option<&Bound<'_, PyAny>>,
                smooth: bool,
            ) -> PyResult<PyFilterSolution> {
                let imu = ImuArrays::from_increments(time, delta_v, delta_theta)?;
                self.run_on(py, &imu, $aiding, initial_attitude, initial_state, smooth)
            }

            /// The filter started at `time` (s) from `initial_state` (the dict
            /// `run` takes: position_ecef m, velocity_ecef m/s, attitude C_b^e,
            /// optional clock_offset m, clock_drift m/s) with the raw sample
            /// there (`specific_force` (3,) m/s², `angular_rate` (3,) rad/s),
            /// to be driven one call at a time: a `RunningFilter` with this
            /// filter's tuning. `inter_system_biases` (tight only): with the
            /// Galileo, BeiDou and GLONASS inter-system-bias states, to
            /// update with satellites of those systems.
            #[pyo3(signature = (time, specific_force, angular_rate, initial_state, *, inter_system_biases=false))]
            fn start(
                &self,
                time: f64,
                specific_force: &Bound<'_, PyAny>,
                angular_rate: &Bound<'_, PyAny>,
                initial_state: &Bound<'_, PyAny>,
                inter_system_biases: bool,
            ) -> PyResult<PyRunningFilter> {
                if self.settings.navigate.as_ref().is_some_and(FilterSettings::has_aids) {
                    return Err(PyValueError::new_err(
                        "settings: [aids] zupt, zaru or nhc is on (zupt and zaru by default), \
                         and a RunningFilter applies no aids by itself: set them false and call \
                         update_zupt, update_zaru and update_non_holonomic",
                    ));
                }
                let raw = sample_arg(specific_force, angular_rate)?;
                let initial = initial_state_arg(initial_state)?;
                let blocks = self.settings.blocks($started_by == StartedBy::Tight, inter_system_biases);
                PyRunningFilter::start(&self.settings.tuning, blocks, $started_by, &initial, time, &raw)
            }
        }

        impl $rust {
            /// The run both `run` and `run_increments` make once the IMU
            /// data are read.
            fn run_on(
                &self,
                py: Python<'_>,
                imu: &ImuArrays,
                $aiding: &Bound<'_, PyAny>,
                initial_attitude: Option<&Bound<'_, PyAny>>,
                initial_state: Option<&Bound<'_, PyAny>>,
                smooth: bool,
            ) -> PyResult<PyFilterSolution> {
                let aiding = $read($aiding)?;
                let initial = match start(initial_state, initial_attitude)? {
                    Start::Given(state) => state,
                    Start::FromAiding(attitude) => $initial(&aiding, &imu.data(), attitude).py()?,
                };
                let tuning = &self.settings.tuning;
                // Galileo or BeiDou satellites: one clock plus their inter-system biases.
                let blocks = self.settings.blocks(
                    $started_by == StartedBy::Tight,
                    coupling::Aiding::needs_inter_system_biases(&aiding),
                );
                let (forward, smoothed) = py
                    .detach(|| match &self.settings.navigate {
                        Some(navigate) => navigate.solve(blocks, &imu.data(), &aiding, &initial, smooth),
                        None => factory::solve(blocks, &imu.data(), &aiding, &initial, tuning, smooth),
                    })
                    .py()?;
                crate::warnings::warn_all(py, &forward.warnings)?;
                PyFilterSolution::with_smoothed(py, forward, smoothed)
            }
        }
    };
}

filter_class!(
    /// Closed-loop error-state EKF in ECEF on pseudoranges and pseudorange rates
    /// (method §5; Groves §14.3.3): 17 states (attitude, velocity, position, accel
    /// and gyro biases, clock offset and drift), 23 with `scale_factor_states`.
    /// An epoch's pseudoranges are one batch and its rates another (sequential
    /// Joseph updates, Sagnac and light time in the prediction), tested together
    /// by the chi-square test of the batch NIS: a faulty satellite is excluded, a
    /// receiver clock jump moved into the clock, and when the pseudoranges keep
    /// failing (3 epochs) the filter resets to the epoch's least-squares fix (or
    /// opens its covariance with fewer than 4 satellites); every reset is in
    /// `FilterSolution.resets`. Fewer than four satellites still help (the
    /// rate row keeps the line of sight's turn with position, so ranges and
    /// rates leave the same directions unobserved); with none the INS coasts.
    /// `FilterSolution.integrity` says when the result cannot be trusted
    /// (docs/explanation/few-satellites.md). Measurement stds are floored (0.5 m, 0.02 m/s).
    ///
    /// Raises ValueError naming the argument for a bad value.
    PyTightlyCoupledFilter,
    "TightlyCoupledFilter",
    gnss,
    gnss_epochs,
    initial_state_from_fix,
    StartedBy::Tight,
    "Filters the whole series in one call (GIL released); with ``smooth``\n\
    also the fixed-interval smoothed solution, as ``.smoothed``\n\
    (docs/explanation/smoother.md).\n\
    \n\
    ``time`` (N,) s, increasing; ``specific_force`` (N, 3) m/s² and\n\
    ``angular_rate`` (N, 3) rad/s: raw IMU samples (instantaneous values).\n\
    ``gnss``: a ``simulate_gnss`` result, or an object/dict with padded\n\
    arrays ``time`` (T,) on the IMU time scale, ``sat_id`` (T, n), negative\n\
    = padding, ``satellite_position_ecef`` / ``satellite_velocity_ecef``\n\
    (T, n, 3), ``pseudorange`` and ``pseudorange_std`` (T, n), optional\n\
    ``pseudorange_rate`` and ``pseudorange_rate_std`` (T, n). Epoch times\n\
    must increase and lie in the IMU span; NaN or absurd measurements are\n\
    rejected and reported, not fatal.\n\
    \n\
    Initialisation: position, velocity and clock of the least-squares fix\n\
    of the first epoch (≥ 4 satellites, else ValueError), moved back to\n\
    ``time[0]``; attitude ``initial_attitude`` (C_b^e, 3x3) or a coarse one\n\
    (levelling on the first second of specific force, heading from the fix\n\
    velocity; needs ≥ 1 m/s ground speed); zero bias estimates.\n\
    \n\
    ``initial_state`` replaces that initialisation with the caller's own\n\
    (e.g. an alignment): a dict (no other keys) or an object with\n\
    ``position_ecef`` (3,) m and ``velocity_ecef`` (3,) m/s at ``time[0]``,\n\
    ``attitude`` C_b^e (3, 3), optional ``clock_offset`` m and\n\
    ``clock_drift`` m/s (absent or None: the median pseudorange (rate)\n\
    residual of the first epoch). Give it or ``initial_attitude``, not both.\n\
    Outages: leave the epochs out of ``gnss``."
);

filter_class!(
    /// Closed-loop error-state EKF on GNSS position (and velocity) fixes (Groves
    /// §14.3.2): each fix (floored at 2 cm, 2 cm/s) is whitened by its
    /// covariance's Cholesky factor into unit-variance updates tested together
    /// (a fix is applied whole or not at all); after 3 failed fixes in a row the
    /// position (velocity) is reset to the fix. The clock states are not
    /// observed (their process noise is off). Same states, tuning, defaults and
    /// overrides as `TightlyCoupledFilter` (`use_pseudorange_rate`, `use_carrier_phase`,
    /// `pseudorange_correlation_time` and the clock settings have no effect).
    ///
    /// Raises ValueError naming the argument for a bad value.
    PyLooselyCoupledFilter,
    "LooselyCoupledFilter",
    fixes,
    position_fixes,
    initial_state_from_position_fix,
    StartedBy::Loose,
    "Filters the whole series in one call (GIL released); with ``smooth``\n\
    also the fixed-interval smoothed solution, as ``.smoothed``.\n\
    \n\
    ``time`` (N,) s, ``specific_force`` (N, 3) m/s², ``angular_rate`` (N, 3)\n\
    rad/s and ``initial_attitude`` (C_b^e) as for the tight filter's ``run``.\n\
    ``fixes``: a ``solve_fix`` result (invalid epochs skipped; covariances =\n\
    the position and velocity blocks of the LS covariance) or an\n\
    object/dict with ``time`` (T,), ``position_ecef`` (T, 3) m,\n\
    ``position_covariance`` (T, 3, 3) m², optional ``velocity_ecef`` (T, 3)\n\
    m/s and ``velocity_covariance`` (T, 3, 3). Initial position and velocity\n\
    from the first fix (moved back to ``time[0]``); attitude as for the\n\
    tight filter. ``initial_state`` as for the tight filter (a clock there\n\
    is carried but never observed)."
);

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyTightlyCoupledFilter>()?;
    m.add_class::<PyLooselyCoupledFilter>()?;
    m.add_class::<PyFilterSolution>()?;
    m.add_class::<PyIntegrity>()?;
    m.add_class::<PyIntegrityAlert>()?;
    m.add_class::<PyConsistency>()?;
    Ok(())
}
