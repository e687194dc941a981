//! `invert_accelerometer`, `invert_gyroscope` (method §4): conversions only;
//! the filters are in `memsnav_core::inversion`.

use memsnav_core::inversion::{self, Inversion, InversionNoise};
use memsnav_py_macros::catch_panics;
use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::IntoPyObjectExt;

use crate::convert;
use crate::errors::IntoPyResult;
use crate::sensors::{PyAccelerometerModel, PyGyroscopeModel};

fn noise(
    process_std: &Bound<'_, PyAny>,
    measurement_std: &Bound<'_, PyAny>,
) -> PyResult<InversionNoise> {
    Ok(InversionNoise {
        process_std: convert::per_axis(process_std, "process_std")?,
        measurement_std: convert::per_axis(measurement_std, "measurement_std")?,
    })
}

fn output(py: Python<'_>, inv: Inversion, return_variance: bool) -> PyResult<Py<PyAny>> {
    let estimate: Bound<'_, PyArray2<f64>> = convert::vectors_to_numpy(py, &inv.estimate);
    if return_variance {
        (estimate, convert::vectors_to_numpy(py, &inv.variance)).into_py_any(py)
    } else {
        estimate.into_py_any(py)
    }
}

/// Estimates the true specific force (N, 3), m/s², from accelerometer
/// outputs `measured` (N, 3) with the random-walk EKF of method §4 and the
/// calibrated `model`. `process_std`: std of the random-walk increment per
/// sample, `measurement_std`: std of the output noise per sample (m/s²,
/// scalar or (3,)). With `return_variance=True` returns `(estimate,
/// variance)`, the second the per-sample covariance diagonal.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (measured, model, process_std, measurement_std, *, return_variance=false))]
fn invert_accelerometer(
    py: Python<'_>,
    measured: &Bound<'_, PyAny>,
    model: &Bound<'_, PyAccelerometerModel>,
    process_std: &Bound<'_, PyAny>,
    measurement_std: &Bound<'_, PyAny>,
    return_variance: bool,
) -> PyResult<Py<PyAny>> {
    let s = convert::vectors(measured, "measured")?;
    let noise = noise(process_std, measurement_std)?;
    let model = model.get().inner.clone();
    let inv = py
        .detach(|| inversion::invert_accelerometer(&s, &model, &noise))
        .py()?;
    output(py, inv, return_variance)
}

/// Estimates the true angular rate (N, 3), rad/s, from gyroscope outputs
/// `measured` (N, 3) and the estimated specific force `specific_force`
/// (N, 3, m/s², from `invert_accelerometer`) with the EKF of method §4.
/// Noise arguments in rad/s per sample, scalar or (3,).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (measured, specific_force, model, process_std, measurement_std, *, return_variance=false))]
fn invert_gyroscope(
    py: Python<'_>,
    measured: &Bound<'_, PyAny>,
    specific_force: &Bound<'_, PyAny>,
    model: &Bound<'_, PyGyroscopeModel>,
    process_std: &Bound<'_, PyAny>,
    measurement_std: &Bound<'_, PyAny>,
    return_variance: bool,
) -> PyResult<Py<PyAny>> {
    let s = convert::vectors(measured, "measured")?;
    let f = convert::vectors(specific_force, "specific_force")?;
    let noise = noise(process_std, measurement_std)?;
    let model = model.get().inner.clone();
    let inv = py
        .detach(|| inversion::invert_gyroscope(&s, &f, &model, &noise))
        .py()?;
    output(py, inv, return_variance)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(invert_accelerometer, m)?)?;
    m.add_function(wrap_pyfunction!(invert_gyroscope, m)?)?;
    Ok(())
}
