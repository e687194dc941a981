//! The calibration and inversion Monte Carlo experiments (paper §5.1-5.2):
//! one call runs a whole set in Rust with the GIL released and returns a
//! dict of numpy arrays; `memsnav.experiments` shapes and plots them.

use memsnav_core::calibration::{accelerometer_parameter_names, gyroscope_parameter_names, Method};
use memsnav_core::experiments::{
    self, calibration::SensorStatistics, motion, CalibrationExperimentConfig,
    InversionExperimentConfig,
};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::IntoPyResult;
use crate::progress::run_interruptible;

fn table<'py>(py: Python<'py>, values: &[f64], cols: usize) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_slice(py, values)
        .reshape([values.len() / cols.max(1), cols])?
        .into_any())
}

fn rows3<'py>(py: Python<'py>, rows: &[[f64; 3]]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    table(py, &flat, 3)
}

fn sensor_dict<'py>(
    py: Python<'py>,
    s: &SensorStatistics,
    names: Vec<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let p = s.parameters;
    d.set_item("parameter_names", names)?;
    for (key, values) in [
        ("truth", &s.truth),
        ("mse_ls", &s.mse_ls),
        ("mse_eiv", &s.mse_eiv),
        ("mean_error_ls", &s.mean_error_ls),
        ("mean_error_eiv", &s.mean_error_eiv),
        ("reported_variance_ls", &s.reported_variance_ls),
        ("reported_variance_eiv", &s.reported_variance_eiv),
        ("crb", &s.crb),
    ] {
        d.set_item(key, table(py, values, p)?)?;
    }
    Ok(d)
}

/// Calibration Monte Carlo (paper §5.1, figs 3-10): `parameter_sets`
/// random IMUs from `preset`, `runs` runs each on fresh land-vehicle motion
/// of `duration` s, GNSS-like references with white noise
/// `reference_specific_force_std` (m/s²) and `reference_angular_rate_std`
/// (rad/s) per sample (defaults: `memsnav_core::experiments` constants).
/// `motion`: "land-vehicle" (body-frame land-vehicle motion with roll and
/// pitch dynamics) or "trajectory" (`Trajectory.random`, weaker roll/pitch
/// excitation).
/// Returns a dict of per-set arrays (SI).
#[pyfunction]
#[pyo3(signature = (*, parameter_sets=50, runs=20, duration=300.0, preset="paper-mems", reference_specific_force_std=0.03, reference_angular_rate_std=0.0017453292519943296, motion="land-vehicle", seed=0, threads=None, progress=None))]
fn calibration_experiment<'py>(
    py: Python<'py>,
    parameter_sets: usize,
    runs: usize,
    duration: f64,
    preset: &str,
    reference_specific_force_std: f64,
    reference_angular_rate_std: f64,
    motion: &str,
    seed: u64,
    threads: Option<usize>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let source: &experiments::MotionSource<'_> = match motion {
        "land-vehicle" => &motion::land_vehicle,
        "trajectory" => &motion::random_trajectory,
        other => {
            return Err(PyValueError::new_err(format!(
                "motion: expected 'land-vehicle' or 'trajectory', got '{other}'"
            )))
        }
    };
    let config = CalibrationExperimentConfig {
        parameter_sets,
        runs_per_set: runs,
        duration_s: duration,
        preset: preset.to_string(),
        reference_specific_force_std,
        reference_angular_rate_std,
        seed,
    };
    let total = parameter_sets * runs;
    let (r, interrupted) = run_interruptible(py, progress.as_ref(), total, threads, |o| {
        experiments::calibration_experiment(&config, source, o)
    })?;
    let r = r.py()?;
    let d = PyDict::new(py);
    d.set_item(
        "accelerometer",
        sensor_dict(py, &r.accelerometer, accelerometer_parameter_names())?,
    )?;
    d.set_item(
        "gyroscope",
        sensor_dict(py, &r.gyroscope, gyroscope_parameter_names())?,
    )?;
    d.set_item("completed_runs", r.completed_runs)?;
    d.set_item("interrupted", interrupted || r.cancelled)?;
    Ok(d)
}

/// Inversion Monte Carlo (paper §5.2, figs 11-12): `runs` runs, each
/// drawing an IMU from `preset`, calibrating it (`method` "eiv" or "ls") on
/// `calibration_duration` s of motion, then inverting `duration` s with
/// random-walk increments `accel_process_std` (m/s²) and
/// `gyro_process_std` (rad/s) per sample. Returns a dict of arrays (SI).
#[pyfunction]
#[pyo3(signature = (*, runs=50, duration=120.0, calibration_duration=300.0, preset="paper-mems", method="eiv", reference_specific_force_std=0.03, reference_angular_rate_std=0.0017453292519943296, accel_process_std=0.1, gyro_process_std=0.017453292519943295, seed=0, threads=None, progress=None))]
fn inversion_experiment<'py>(
    py: Python<'py>,
    runs: usize,
    duration: f64,
    calibration_duration: f64,
    preset: &str,
    method: &str,
    reference_specific_force_std: f64,
    reference_angular_rate_std: f64,
    accel_process_std: f64,
    gyro_process_std: f64,
    seed: u64,
    threads: Option<usize>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let method = match method {
        "ls" => Method::LeastSquares,
        "eiv" => Method::ErrorsInVariables,
        other => {
            return Err(PyValueError::new_err(format!(
                "method: expected 'ls' or 'eiv', got '{other}'"
            )))
        }
    };
    let config = InversionExperimentConfig {
        runs,
        duration_s: duration,
        calibration_duration_s: calibration_duration,
        preset: preset.to_string(),
        reference_specific_force_std,
        reference_angular_rate_std,
        method,
        accel_process_std,
        gyro_process_std,
        seed,
    };
    let (r, interrupted) = run_interruptible(py, progress.as_ref(), runs, threads, |o| {
        experiments::inversion_experiment(&config, &motion::land_vehicle, o)
    })?;
    let r = r.py()?;
    let d = PyDict::new(py);
    d.set_item("accel_mse", rows3(py, &r.accel_mse)?)?;
    d.set_item("gyro_mse", rows3(py, &r.gyro_mse)?)?;
    d.set_item("raw_accel_mse", rows3(py, &r.raw_accel_mse)?)?;
    d.set_item("raw_gyro_mse", rows3(py, &r.raw_gyro_mse)?)?;
    d.set_item(
        "accel_squared_error_vs_time",
        rows3(py, &r.accel_squared_error_vs_time)?,
    )?;
    d.set_item(
        "gyro_squared_error_vs_time",
        rows3(py, &r.gyro_squared_error_vs_time)?,
    )?;
    d.set_item("sample_rate", r.sample_rate_hz)?;
    d.set_item("completed_runs", r.accel_mse.len())?;
    d.set_item("interrupted", interrupted || r.cancelled)?;
    Ok(d)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(calibration_experiment, m)?)?;
    m.add_function(wrap_pyfunction!(inversion_experiment, m)?)?;
    Ok(())
}
