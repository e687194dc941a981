//! The coupled filters on real data (issue 8): `loosely_coupled` on
//! position/velocity fixes, `tightly_coupled` on pseudoranges and rates.
//! Conversions, tuning from keyword arguments and error mapping only; the
//! whole series runs in one call with the GIL released.

use memsnav_core::coupling::{
    self, BiasProcess, FilterState, FilterTuning, ImuData, InitialState, MeasurementKind,
    MeasurementRecord, MeasurementStatus, PositionFix,
};
use memsnav_core::filter::state::{ATTITUDE, POSITION, VELOCITY};
use memsnav_core::geodesy::{c_n_e, ecef_to_geodetic};
use memsnav_core::ins::NavState;
use nalgebra::{Matrix3, Vector3};
use numpy::{PyArray1, PyArray2, PyArray3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::convert;
use crate::errors::IntoPyResult;
use crate::gnss::PyGnssMeasurements;

/// The 17-state filter: the MEMS scale factors are not observable enough
/// on a short log to be worth six more states.
const N: usize = memsnav_core::filter::state::BASE_STATES;

/// A coupled filter's solution at every IMU sample, with one-sigma
/// uncertainties in local NED axes and every measurement's record.
#[pyclass(frozen, name = "CoupledSolution", module = "memsnav._memsnav")]
pub struct PyCoupledSolution {
    time_s: Vec<f64>,
    nav: Vec<NavState>,
    accel_bias: Vec<Vector3<f64>>,
    gyro_bias: Vec<Vector3<f64>>,
    clock: Vec<(f64, f64)>,
    position_std_ned: Vec<Vector3<f64>>,
    velocity_std_ned: Vec<Vector3<f64>>,
    attitude_std_ned: Vec<Vector3<f64>>,
    records: Vec<MeasurementRecord>,
}

impl PyCoupledSolution {
    fn with_capacity(n: usize) -> Self {
        Self {
            time_s: Vec::with_capacity(n),
            nav: Vec::with_capacity(n),
            accel_bias: Vec::with_capacity(n),
            gyro_bias: Vec::with_capacity(n),
            clock: Vec::with_capacity(n),
            position_std_ned: Vec::with_capacity(n),
            velocity_std_ned: Vec::with_capacity(n),
            attitude_std_ned: Vec::with_capacity(n),
            records: Vec::new(),
        }
    }

    fn push(&mut self, time_s: f64, s: &FilterState<N>) {
        let geo = ecef_to_geodetic(&s.nav.position_ecef);
        let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
        let ned_std = |first: usize| -> Vector3<f64> {
            let p: Matrix3<f64> = s.kf.p.fixed_view::<3, 3>(first, first).into();
            (cne.transpose() * p * cne)
                .diagonal()
                .map(|v| v.max(0.0).sqrt())
        };
        self.time_s.push(time_s);
        self.nav.push(s.nav);
        self.accel_bias.push(s.accel_bias_m_s2);
        self.gyro_bias.push(s.gyro_bias_rad_s);
        self.clock.push((s.clock_offset_m, s.clock_drift_m_s));
        self.position_std_ned.push(ned_std(POSITION));
        self.velocity_std_ned.push(ned_std(VELOCITY));
        self.attitude_std_ned.push(ned_std(ATTITUDE));
    }
}

#[pymethods]
impl PyCoupledSolution {
    /// IMU sample times, s, ``(N,)``.
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.time_s)
    }
    /// ECEF position of the IMU, m, ``(N, 3)``.
    #[getter]
    fn position_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let v: Vec<_> = self.nav.iter().map(|s| s.position_ecef).collect();
        convert::vectors_to_numpy(py, &v)
    }
    /// ECEF velocity, m/s, ``(N, 3)``.
    #[getter]
    fn velocity_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let v: Vec<_> = self.nav.iter().map(|s| s.velocity_ecef).collect();
        convert::vectors_to_numpy(py, &v)
    }
    /// Body-to-ECEF rotation matrices, ``(N, 3, 3)``.
    #[getter]
    fn attitude<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        let m: Vec<_> = self.nav.iter().map(|s| s.c_b_e).collect();
        convert::matrices3_to_numpy(py, &m)
    }
    /// Estimated accelerometer bias, m/s², ``(N, 3)``.
    #[getter]
    fn accel_bias<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.accel_bias)
    }
    /// Estimated gyro bias, rad/s, ``(N, 3)``.
    #[getter]
    fn gyro_bias<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.gyro_bias)
    }
    /// Receiver clock offset, m, ``(N,)`` (zero in loose coupling).
    #[getter]
    fn clock_offset<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_iter(py, self.clock.iter().map(|c| c.0))
    }
    /// Receiver clock drift, m/s, ``(N,)``.
    #[getter]
    fn clock_drift<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_iter(py, self.clock.iter().map(|c| c.1))
    }
    /// One-sigma position uncertainty along north, east, down, m, ``(N, 3)``.
    #[getter]
    fn position_std_ned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.position_std_ned)
    }
    /// One-sigma velocity uncertainty, NED, m/s, ``(N, 3)``.
    #[getter]
    fn velocity_std_ned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.velocity_std_ned)
    }
    /// One-sigma attitude uncertainty about N, E, D, rad, ``(N, 3)``.
    #[getter]
    fn attitude_std_ned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.attitude_std_ned)
    }
    /// Every scalar measurement: a dict of equal-length arrays ``time`` (s),
    /// ``id`` (PRN or axis 0-2), ``kind`` ("pseudorange", "pseudorange_rate",
    /// "position", "velocity"), ``innovation`` (measured − predicted, SI,
    /// whitened for loose coupling), ``innovation_std``, ``nis``,
    /// ``status`` ("accepted", "gated", "invalid").
    #[getter]
    fn measurements<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let d = pyo3::types::PyDict::new(py);
        let r = &self.records;
        d.set_item("time", PyArray1::from_iter(py, r.iter().map(|m| m.time_s)))?;
        d.set_item("id", PyArray1::from_iter(py, r.iter().map(|m| m.id as i64)))?;
        let kinds: Vec<&str> = r
            .iter()
            .map(|m| match m.kind {
                MeasurementKind::Pseudorange => "pseudorange",
                MeasurementKind::PseudorangeRate => "pseudorange_rate",
                MeasurementKind::Position => "position",
                MeasurementKind::Velocity => "velocity",
            })
            .collect();
        d.set_item("kind", kinds)?;
        d.set_item(
            "innovation",
            PyArray1::from_iter(py, r.iter().map(|m| m.innovation)),
        )?;
        d.set_item(
            "innovation_std",
            PyArray1::from_iter(py, r.iter().map(|m| m.innovation_std)),
        )?;
        d.set_item("nis", PyArray1::from_iter(py, r.iter().map(|m| m.nis)))?;
        let status: Vec<&str> = r
            .iter()
            .map(|m| match m.status {
                MeasurementStatus::Accepted => "accepted",
                MeasurementStatus::RejectedByGate => "gated",
                MeasurementStatus::RejectedInvalid => "invalid",
            })
            .collect();
        d.set_item("status", status)?;
        Ok(d)
    }
    fn __len__(&self) -> usize {
        self.time_s.len()
    }
}

/// Filter tuning from noise densities and bias processes.
#[allow(clippy::too_many_arguments)]
fn tuning(
    accel_noise_density: f64,
    gyro_noise_density: f64,
    accel_bias_std: f64,
    gyro_bias_std: f64,
    accel_bias_instability: f64,
    gyro_bias_instability: f64,
    bias_correlation_time: f64,
    initial_position_std: f64,
    initial_velocity_std: f64,
    initial_attitude_std_deg: [f64; 3],
    gate_probability: f64,
) -> PyResult<FilterTuning> {
    let bias = |initial_std: f64, instability_std: f64| BiasProcess {
        initial_std,
        instability_std,
        correlation_time_s: bias_correlation_time,
        random_walk: 0.0,
    };
    // A white noise of density σ (unit/√s) "sampled at 1 Hz" has σ per
    // sample: FilterTuning::new turns that back into the PSD σ².
    let mut t = FilterTuning::new(
        1.0,
        accel_noise_density,
        gyro_noise_density,
        bias(accel_bias_std, accel_bias_instability),
        bias(gyro_bias_std, gyro_bias_instability),
    )
    .py()?;
    t.initial_std.position_m = initial_position_std;
    t.initial_std.velocity_m_s = initial_velocity_std;
    t.initial_std.attitude_ned_rad = Vector3::from(initial_attitude_std_deg).map(f64::to_radians);
    t.gate_probability = gate_probability;
    t.validate().py()?;
    Ok(t)
}

struct Imu {
    time: Vec<f64>,
    f: Vec<Vector3<f64>>,
    w: Vec<Vector3<f64>>,
}

fn imu(
    time: &Bound<'_, PyAny>,
    specific_force: &Bound<'_, PyAny>,
    angular_rate: &Bound<'_, PyAny>,
) -> PyResult<Imu> {
    Ok(Imu {
        time: convert::scalars(time, "time")?,
        f: convert::vectors(specific_force, "specific_force")?,
        w: convert::vectors(angular_rate, "angular_rate")?,
    })
}

fn initial(
    position: &Bound<'_, PyAny>,
    velocity: &Bound<'_, PyAny>,
    attitude: &Bound<'_, PyAny>,
    clock: (Option<f64>, Option<f64>),
) -> PyResult<InitialState> {
    Ok(InitialState {
        nav: NavState {
            position_ecef: convert::vector3(position, "initial_position_ecef")?,
            velocity_ecef: convert::vector3(velocity, "initial_velocity_ecef")?,
            c_b_e: convert::matrix3(attitude, "initial_attitude")?,
        },
        accel_bias_m_s2: Vector3::zeros(),
        gyro_bias_rad_s: Vector3::zeros(),
        clock_offset_m: clock.0,
        clock_drift_m_s: clock.1,
    })
}

/// Loosely coupled GNSS/INS (17-state closed-loop error-state EKF in ECEF)
/// on position fixes (and optionally velocity fixes) with full covariances.
/// Noise densities: accelerometer m/s/√s (VRW), gyro rad/√s (ARW); bias
/// stds m/s² and rad/s; a Gauss-Markov bias instability with
/// ``bias_correlation_time`` s (inf: constant biases).
#[pyfunction]
#[pyo3(signature = (time, specific_force, angular_rate, fix_time, fix_position_ecef,
    fix_position_covariance, initial_position_ecef, initial_velocity_ecef, initial_attitude, *,
    fix_velocity_ecef=None, fix_velocity_covariance=None, accel_noise_density=0.003,
    gyro_noise_density=0.0005, accel_bias_std=0.1, gyro_bias_std=0.005,
    accel_bias_instability=0.0, gyro_bias_instability=0.0, bias_correlation_time=f64::INFINITY,
    initial_position_std=5.0, initial_velocity_std=0.5, initial_attitude_std_deg=[1.0, 1.0, 5.0],
    gate_probability=0.999))]
#[allow(clippy::too_many_arguments)]
fn loosely_coupled(
    py: Python<'_>,
    time: &Bound<'_, PyAny>,
    specific_force: &Bound<'_, PyAny>,
    angular_rate: &Bound<'_, PyAny>,
    fix_time: &Bound<'_, PyAny>,
    fix_position_ecef: &Bound<'_, PyAny>,
    fix_position_covariance: &Bound<'_, PyAny>,
    initial_position_ecef: &Bound<'_, PyAny>,
    initial_velocity_ecef: &Bound<'_, PyAny>,
    initial_attitude: &Bound<'_, PyAny>,
    fix_velocity_ecef: Option<&Bound<'_, PyAny>>,
    fix_velocity_covariance: Option<&Bound<'_, PyAny>>,
    accel_noise_density: f64,
    gyro_noise_density: f64,
    accel_bias_std: f64,
    gyro_bias_std: f64,
    accel_bias_instability: f64,
    gyro_bias_instability: f64,
    bias_correlation_time: f64,
    initial_position_std: f64,
    initial_velocity_std: f64,
    initial_attitude_std_deg: [f64; 3],
    gate_probability: f64,
) -> PyResult<PyCoupledSolution> {
    let imu = imu(time, specific_force, angular_rate)?;
    let init = initial(
        initial_position_ecef,
        initial_velocity_ecef,
        initial_attitude,
        (None, None),
    )?;
    let tuning = tuning(
        accel_noise_density,
        gyro_noise_density,
        accel_bias_std,
        gyro_bias_std,
        accel_bias_instability,
        gyro_bias_instability,
        bias_correlation_time,
        initial_position_std,
        initial_velocity_std,
        initial_attitude_std_deg,
        gate_probability,
    )?;
    let t = convert::scalars(fix_time, "fix_time")?;
    let p = convert::vectors(fix_position_ecef, "fix_position_ecef")?;
    let pc = convert::matrices3(fix_position_covariance, "fix_position_covariance")?;
    let v = fix_velocity_ecef
        .map(|v| convert::vectors(v, "fix_velocity_ecef"))
        .transpose()?;
    let vc = fix_velocity_covariance
        .map(|v| convert::matrices3(v, "fix_velocity_covariance"))
        .transpose()?;
    if v.is_some() != vc.is_some() {
        return Err(PyValueError::new_err(
            "fix_velocity_ecef and fix_velocity_covariance: give both or neither",
        ));
    }
    for (name, n) in [
        ("fix_position_ecef", p.len()),
        ("fix_position_covariance", pc.len()),
        ("fix_velocity_ecef", v.as_ref().map_or(t.len(), Vec::len)),
        (
            "fix_velocity_covariance",
            vc.as_ref().map_or(t.len(), Vec::len),
        ),
    ] {
        if n != t.len() {
            return Err(PyValueError::new_err(format!(
                "{name}: {n} rows, but fix_time has {}",
                t.len()
            )));
        }
    }
    let fixes: Vec<PositionFix> = (0..t.len())
        .map(|i| PositionFix {
            time_s: t[i],
            position_ecef: p[i],
            position_covariance: pc[i],
            velocity_ecef: v.as_ref().map(|v| v[i]),
            velocity_covariance: vc.as_ref().map_or(Matrix3::zeros(), |c| c[i]),
        })
        .collect();
    py.detach(|| {
        let data = ImuData {
            time_s: &imu.time,
            specific_force_b: &imu.f,
            angular_rate_b: &imu.w,
        };
        let mut out = PyCoupledSolution::with_capacity(imu.time.len());
        let records =
            coupling::run_loosely_coupled::<N, _>(&data, &fixes, &init, &tuning, |k, s| {
                out.push(imu.time[k], s)
            })?;
        out.records = records;
        Ok(out)
    })
    .py()
}

/// Tightly coupled GNSS/INS (17-state closed-loop error-state EKF in ECEF
/// with receiver clock offset and drift) on the pseudoranges (and rates) of
/// ``measurements``, whose epoch times share the IMU time axis. Tuning as
/// in ``loosely_coupled``; the clock starts from the given values or, when
/// None, from the median residual of the first epoch. ``epoch_mask``: a
/// ``(T,)`` boolean array choosing the epochs to use (outages; default all).
#[pyfunction]
#[pyo3(signature = (time, specific_force, angular_rate, measurements, initial_position_ecef,
    initial_velocity_ecef, initial_attitude, *, epoch_mask=None, initial_clock_offset=None,
    initial_clock_drift=None, use_pseudorange_rate=true, accel_noise_density=0.003,
    gyro_noise_density=0.0005, accel_bias_std=0.1, gyro_bias_std=0.005,
    accel_bias_instability=0.0, gyro_bias_instability=0.0, bias_correlation_time=f64::INFINITY,
    initial_position_std=5.0, initial_velocity_std=0.5, initial_attitude_std_deg=[1.0, 1.0, 5.0],
    gate_probability=0.999))]
#[allow(clippy::too_many_arguments)]
fn tightly_coupled(
    py: Python<'_>,
    time: &Bound<'_, PyAny>,
    specific_force: &Bound<'_, PyAny>,
    angular_rate: &Bound<'_, PyAny>,
    measurements: &PyGnssMeasurements,
    initial_position_ecef: &Bound<'_, PyAny>,
    initial_velocity_ecef: &Bound<'_, PyAny>,
    initial_attitude: &Bound<'_, PyAny>,
    epoch_mask: Option<Vec<bool>>,
    initial_clock_offset: Option<f64>,
    initial_clock_drift: Option<f64>,
    use_pseudorange_rate: bool,
    accel_noise_density: f64,
    gyro_noise_density: f64,
    accel_bias_std: f64,
    gyro_bias_std: f64,
    accel_bias_instability: f64,
    gyro_bias_instability: f64,
    bias_correlation_time: f64,
    initial_position_std: f64,
    initial_velocity_std: f64,
    initial_attitude_std_deg: [f64; 3],
    gate_probability: f64,
) -> PyResult<PyCoupledSolution> {
    let imu = imu(time, specific_force, angular_rate)?;
    let init = initial(
        initial_position_ecef,
        initial_velocity_ecef,
        initial_attitude,
        (initial_clock_offset, initial_clock_drift),
    )?;
    let mut tuning = tuning(
        accel_noise_density,
        gyro_noise_density,
        accel_bias_std,
        gyro_bias_std,
        accel_bias_instability,
        gyro_bias_instability,
        bias_correlation_time,
        initial_position_std,
        initial_velocity_std,
        initial_attitude_std_deg,
        gate_probability,
    )?;
    tuning.use_pseudorange_rate = use_pseudorange_rate;
    let all = measurements.epochs();
    let epochs: Vec<_> = match epoch_mask {
        Some(mask) if mask.len() != all.len() => {
            return Err(PyValueError::new_err(format!(
                "epoch_mask: {} values, but measurements has {} epochs",
                mask.len(),
                all.len()
            )))
        }
        Some(mask) => all
            .iter()
            .zip(mask)
            .filter(|(_, k)| *k)
            .map(|(e, _)| e.clone())
            .collect(),
        None => all.to_vec(),
    };
    py.detach(|| {
        let data = ImuData {
            time_s: &imu.time,
            specific_force_b: &imu.f,
            angular_rate_b: &imu.w,
        };
        let mut out = PyCoupledSolution::with_capacity(imu.time.len());
        let records =
            coupling::run_tightly_coupled::<N, _>(&data, &epochs, &init, &tuning, |k, s| {
                out.push(imu.time[k], s)
            })?;
        out.records = records;
        Ok(out)
    })
    .py()
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyCoupledSolution>()?;
    m.add_function(wrap_pyfunction!(loosely_coupled, m)?)?;
    m.add_function(wrap_pyfunction!(tightly_coupled, m)?)?;
    Ok(())
}
