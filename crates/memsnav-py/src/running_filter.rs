//! `RunningFilter`: a coupled filter driven one call at a time (the core's
//! step API, `coupling::FilterState::{start, predict, update_*}`), for a
//! real-time loop or an aid memsnav does not know. Each method is one call
//! into the core; the batch `run` is the same sequence of the same calls.

use memsnav_core::coupling::factory::{self, RunningState};
use memsnav_core::coupling::{FilterTuning, InitialState, PositionFix};
use memsnav_core::filter::state::{RangeBiasSlots, StateBlocks, StateLayout};
use memsnav_core::gnss::satellite_name;
use memsnav_core::gnss::GnssEpoch;
use memsnav_core::ins::{ImuIncrement, ImuSample};
use memsnav_py_macros::catch_panics;
use nalgebra::{Matrix3, Vector3};
use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert;
use crate::errors::IntoPyResult;
use crate::gnss::gnss_epoch_at;
use crate::records::{batches_to_dict, measurements_to_dict, resets_to_dict};
use crate::result_record::result_record;

/// Which class started the filter (its aiding decides the clock model).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum StartedBy {
    Tight,
    Loose,
}

result_record! {
    /// What a running filter estimates now (`RunningFilter.state`): the
    /// corrected navigation solution and the sensor, clock and optional
    /// states' estimates (totals, not errors).
    PyFilterEstimate as "FilterEstimate" {
        /// The filter's time, s.
        time: f64,
        /// Position of the IMU, ECEF m, (3,).
        position_ecef: Py<PyArray1<f64>>,
        /// Velocity, ECEF m/s, (3,).
        velocity_ecef: Py<PyArray1<f64>>,
        /// Attitude C_b^e (body to ECEF), (3, 3).
        attitude: Py<PyArray2<f64>>,
        /// Accelerometer bias, m/s², (3,).
        accel_bias: Py<PyArray1<f64>>,
        /// Gyro bias, rad/s, (3,).
        gyro_bias: Py<PyArray1<f64>>,
        /// Receiver clock offset, m.
        clock_offset: f64,
        /// Receiver clock drift, m/s.
        clock_drift: f64,
        /// Accelerometer scale-factor errors, (3,); None without their states.
        accel_scale_factor: Option<Py<PyArray1<f64>>>,
        /// Gyro scale-factor errors, (3,); None without their states.
        gyro_scale_factor: Option<Py<PyArray1<f64>>>,
        /// Inter-system biases (Galileo, BeiDou, GLONASS minus GPS), m;
        /// None without their states.
        inter_system_bias: Option<Vec<f64>>,
        /// Range biases, m, by satellite ("G05"; the loosely coupled filter's
        /// fix errors by ECEF axis, "x", "y", "z"); None without their states.
        range_biases: Option<Py<PyDict>>,
    }
    repr(s) format!("at {:.3} s", s.time)
}

/// A coupled GNSS/INS filter driven one call at a time: `predict` (or
/// `predict_increments`) at each IMU sample, then any updates at that
/// time. Made by `TightlyCoupledFilter.start` or
/// `LooselyCoupledFilter.start`, with that filter's tuning; the batch
/// `run` is this same sequence of calls, so the same calls give the same
/// numbers, bit for bit.
///
/// Times are the IMU's time stamps, s (not intervals: the records and the
/// GNSS epochs are matched on them); each must follow the last by more
/// than 0 and at most 1 s. Updates apply at the filter's time (that of the
/// last predict); a GNSS epoch stamped more than the time tolerance
/// (1e-4 s) away is refused: predict to its time first. Every update
/// applies its rows as batches (one per block of a fix or GNSS epoch)
/// tested by the chi-square gate, and returns whether it was applied
/// whole (every batch accepted). Measurement records
/// accumulate until `take_records()` hands them over. Every update is a
/// transaction: refused calls (ValueError naming the argument: stds within
/// 1e-9 to 1e9 of their unit, lever arms within 100 m, a fix's position
/// near the Earth's surface) and updates that fail on the way
/// (DivergenceError) leave the filter exactly as it was, records included.
#[pyclass(name = "RunningFilter", module = "memsnav._memsnav")]
pub struct PyRunningFilter {
    filter: Box<dyn RunningState>,
    started_by: StartedBy,
}

impl PyRunningFilter {
    /// The filter with `blocks` at `time_s` from `initial`, with the raw
    /// sample there.
    pub(crate) fn start(
        tuning: &FilterTuning,
        blocks: StateBlocks,
        started_by: StartedBy,
        initial: &InitialState,
        time_s: f64,
        raw: &ImuSample,
    ) -> PyResult<Self> {
        let filter = match started_by {
            StartedBy::Loose if blocks.inter_system_biases => {
                return Err(PyValueError::new_err(
                    "inter_system_biases: a loosely coupled filter takes fixes, not \
                     pseudoranges of several systems",
                ))
            }
            StartedBy::Tight => factory::start::<GnssEpoch>(blocks, initial, tuning, time_s, raw),
            StartedBy::Loose => factory::start::<PositionFix>(blocks, initial, tuning, time_s, raw),
        }
        .py()?;
        Ok(Self { filter, started_by })
    }

    fn time_s(&self) -> f64 {
        self.filter.time_s()
    }
}

/// A raw IMU sample from the two `(3,)` arguments.
pub(crate) fn sample_arg(
    specific_force: &Bound<'_, PyAny>,
    angular_rate: &Bound<'_, PyAny>,
) -> PyResult<ImuSample> {
    Ok(ImuSample {
        specific_force_b: convert::vector3(specific_force, "specific_force")?,
        angular_rate_b: convert::vector3(angular_rate, "angular_rate")?,
    })
}

fn lever_arm_arg(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Vector3<f64>> {
    obj.filter(|o| !o.is_none())
        .map_or(Ok(Vector3::zeros()), |o| convert::vector3(o, "lever_arm"))
}

#[catch_panics]
#[pymethods]
impl PyRunningFilter {
    /// Steps the INS and the covariance to `time` (s) with the raw sample
    /// there: `specific_force` (3,) m/s² and `angular_rate` (3,) rad/s in
    /// body axes (the mechanization integrates between the previous
    /// sample and this one, as `run` does).
    fn predict(
        &mut self,
        time: f64,
        specific_force: &Bound<'_, PyAny>,
        angular_rate: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let raw = sample_arg(specific_force, angular_rate)?;
        self.filter.predict(time, &raw).py()
    }

    /// Steps to `time` (s) with the raw increments of the interval since
    /// the filter's time: `delta_v` (3,) m/s and `delta_theta` (3,) rad
    /// (∫f dt, ∫ω dt, what integrating IMUs log), with coning and sculling
    /// from the previous interval's increments.
    fn predict_increments(
        &mut self,
        time: f64,
        delta_v: &Bound<'_, PyAny>,
        delta_theta: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let raw = ImuIncrement {
            delta_velocity_b: convert::vector3(delta_v, "delta_v")?,
            delta_angle_b: convert::vector3(delta_theta, "delta_theta")?,
        };
        self.filter.predict_increments(time, &raw).py()
    }

    /// Applies epoch `epoch` of `gnss` (anything `TightlyCoupledFilter.run`
    /// takes: `GnssMeasurements` or its dict) at the filter's time: the
    /// pseudoranges as one batch, then the rates. Only for a filter started
    /// by `TightlyCoupledFilter` (the loose one holds the clock fixed).
    /// Returns whether the epoch was applied whole: every batch it made
    /// passed its gate (pseudoranges after any fault exclusion, rates); the
    /// records say which failed.
    #[pyo3(signature = (gnss, epoch=0))]
    fn update_gnss(&mut self, gnss: &Bound<'_, PyAny>, epoch: usize) -> PyResult<bool> {
        if self.started_by != StartedBy::Tight {
            return Err(PyValueError::new_err(
                "gnss: this filter was started by LooselyCoupledFilter, whose clock states are \
                 held at zero; start it with TightlyCoupledFilter.start to apply pseudoranges",
            ));
        }
        let at = gnss_epoch_at(gnss, epoch)?;
        self.filter.update_gnss(&at).py()
    }

    /// Applies a position fix of the antenna at the filter's time:
    /// `position_ecef` (3,) m with `position_covariance` (3, 3) m², and
    /// optionally `velocity_ecef` (3,) m/s with `velocity_covariance`
    /// (3, 3) m²/s² (each block tested as one batch, as `run` does).
    /// Returns whether the fix was applied whole: every block passed its
    /// gate; the records say which failed.
    #[pyo3(signature = (position_ecef, position_covariance, velocity_ecef=None, velocity_covariance=None))]
    fn update_fix(
        &mut self,
        position_ecef: &Bound<'_, PyAny>,
        position_covariance: &Bound<'_, PyAny>,
        velocity_ecef: Option<&Bound<'_, PyAny>>,
        velocity_covariance: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<bool> {
        let velocity = match (velocity_ecef, velocity_covariance) {
            (Some(v), Some(c)) => Some((
                convert::vector3(v, "velocity_ecef")?,
                convert::matrix3(c, "velocity_covariance")?,
            )),
            (None, None) => None,
            _ => {
                return Err(PyValueError::new_err(
                    "velocity_ecef, velocity_covariance: give both or neither",
                ))
            }
        };
        let fix = PositionFix {
            time_s: self.time_s(),
            position_ecef: convert::vector3(position_ecef, "position_ecef")?,
            position_covariance: convert::matrix3(position_covariance, "position_covariance")?,
            velocity_ecef: velocity.map(|v| v.0),
            velocity_covariance: velocity.map_or(Matrix3::zeros(), |v| v.1),
            velocity_horizontal_only: false,
        };
        self.filter.update_fix(&fix).py()
    }

    /// Zero-velocity update, ``std`` m/s per axis. Returns whether it
    /// passed its gate (as every update method does).
    fn update_zupt(&mut self, std: f64) -> PyResult<bool> {
        self.filter.update_zupt(std).py()
    }

    /// Zero-angular-rate update at rest: `mean_angular_rate` (3,) rad/s is
    /// the raw gyro reading averaged over the standstill, `std` rad/s (of
    /// the mean; a scalar or per axis). Returns whether it was accepted.
    fn update_zaru(
        &mut self,
        mean_angular_rate: &Bound<'_, PyAny>,
        std: &Bound<'_, PyAny>,
    ) -> PyResult<bool> {
        let rate = convert::vector3(mean_angular_rate, "mean_angular_rate")?;
        let std = convert::per_axis(std, "std")?;
        self.filter.update_zaru(&rate, &std).py()
    }

    /// Non-holonomic constraint of a land vehicle: the point at
    /// `lever_arm` (3,) m from the IMU in body axes (None: the IMU) has no
    /// lateral and no vertical velocity, `std` m/s. Body x must point
    /// forward along the vehicle. Returns whether it was accepted.
    #[pyo3(signature = (std, lever_arm=None))]
    fn update_non_holonomic(
        &mut self,
        std: f64,
        lever_arm: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<bool> {
        let l = lever_arm_arg(lever_arm)?;
        self.filter.update_non_holonomic(&l, std).py()
    }

    /// Odometer (wheel speed): the forward speed `speed` m/s (negative when
    /// reversing) of the point at `lever_arm` (3,) m in body axes (None:
    /// the IMU), `std` m/s. Returns whether it was accepted.
    #[pyo3(signature = (speed, std, lever_arm=None))]
    fn update_speed(
        &mut self,
        speed: f64,
        std: f64,
        lever_arm: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<bool> {
        let l = lever_arm_arg(lever_arm)?;
        self.filter.update_speed(speed, &l, std).py()
    }

    /// Height (a barometer referenced to the ellipsoid): the IMU's WGS 84
    /// ellipsoidal height `height` m, `std` m. Returns whether it was
    /// accepted.
    fn update_height(&mut self, height: f64, std: f64) -> PyResult<bool> {
        self.filter.update_height(height, std).py()
    }

    /// Heading (dual antenna; a magnetometer corrected for declination):
    /// the body's yaw `yaw` rad from north, positive east (NED), `std` rad.
    /// Returns whether it was accepted.
    fn update_heading(&mut self, yaw: f64, std: f64) -> PyResult<bool> {
        self.filter.update_heading(yaw, std).py()
    }

    /// The filter's time, s (that of the last predict).
    #[getter]
    fn time(&self) -> f64 {
        self.time_s()
    }

    /// Position r^e of the IMU, (3,) m.
    #[getter]
    fn position_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        convert::vector3_to_numpy(py, &self.filter.estimate().nav.position_ecef)
    }

    /// Velocity v^e of the IMU, (3,) m/s.
    #[getter]
    fn velocity_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        convert::vector3_to_numpy(py, &self.filter.estimate().nav.velocity_ecef)
    }

    /// Attitude C_b^e, (3, 3).
    #[getter]
    fn attitude<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::matrix3_to_numpy(py, &self.filter.estimate().nav.c_b_e)
    }

    /// The whole estimate, a `FilterEstimate`: `time` s, `position_ecef` m,
    /// `velocity_ecef` m/s, `attitude` C_b^e, `accel_bias` m/s²,
    /// `gyro_bias` rad/s, `clock_offset` m, `clock_drift` m/s, and the
    /// optional blocks' estimates (None without their states).
    #[getter]
    fn state(&self, py: Python<'_>) -> PyResult<PyFilterEstimate> {
        let e = self.filter.estimate();
        let vector = |v: &Vector3<f64>| convert::vector3_to_numpy(py, v).unbind();
        let range_biases = if self.filter.blocks().range_biases == RangeBiasSlots::None {
            None
        } else {
            let biases = PyDict::new(py);
            for &(holder, bias_m) in &e.range_biases {
                match self.started_by {
                    StartedBy::Tight => biases.set_item(satellite_name(holder), bias_m)?,
                    // The fixes' position error on ECEF axis 0, 1, 2.
                    StartedBy::Loose => {
                        biases.set_item(["x", "y", "z"][usize::from(holder)], bias_m)?
                    }
                }
            }
            Some(biases.unbind())
        };
        Ok(PyFilterEstimate {
            time: e.time_s,
            position_ecef: vector(&e.nav.position_ecef),
            velocity_ecef: vector(&e.nav.velocity_ecef),
            attitude: convert::matrix3_to_numpy(py, &e.nav.c_b_e).unbind(),
            accel_bias: vector(&e.accel_bias_m_s2),
            gyro_bias: vector(&e.gyro_bias_rad_s),
            clock_offset: e.clock_offset_m,
            clock_drift: e.clock_drift_m_s,
            accel_scale_factor: e.scale_factors.map(|(accel, _)| vector(&accel)),
            gyro_scale_factor: e.scale_factors.map(|(_, gyro)| vector(&gyro)),
            inter_system_bias: e.inter_system_bias_m.map(|isb| isb.to_vec()),
            range_biases,
        })
    }

    /// The error-state covariance P, (n, n), in the order of
    /// `state_names` and the units of the error states (rad, m/s, m, m/s²,
    /// rad/s, m, m/s; attitude and velocity in ECEF axes).
    #[getter]
    fn covariance<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let p = self.filter.covariance();
        let rows: Vec<Vec<f64>> = p.row_iter().map(|r| r.iter().copied().collect()).collect();
        PyArray2::from_vec2(py, &rows).expect("square")
    }

    /// Error-state names, in covariance order.
    #[getter]
    fn state_names(&self) -> Vec<String> {
        StateLayout::names(self.filter.blocks().size())
    }

    /// The records since the last call, handed over and cleared: a dict
    /// with `measurements`, `batches` and `resets`, each as in
    /// `FilterSolution`.
    fn take_records<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let records = self.filter.take_records();
        let d = PyDict::new(py);
        d.set_item(
            "measurements",
            measurements_to_dict(py, records.measurements.iter())?,
        )?;
        d.set_item("batches", batches_to_dict(py, &records.batches)?)?;
        d.set_item("resets", resets_to_dict(py, &records.resets)?)?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        let n = self.filter.blocks().size();
        let by = match self.started_by {
            StartedBy::Tight => "TightlyCoupledFilter",
            StartedBy::Loose => "LooselyCoupledFilter",
        };
        format!("RunningFilter({by}, {n} states, time={} s)", self.time_s())
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyRunningFilter>()?;
    m.add_class::<PyFilterEstimate>()
}
