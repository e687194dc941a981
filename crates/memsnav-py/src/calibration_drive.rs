//! The drive calibration's numerics (`memsnav_core::calibration::inflation`
//! and `::draws`): the covariance of a fit from correlated references, and
//! calibrations drawn from it. Conversions only.

use memsnav_core::calibration::draws::{ImuDraws, ParameterDistribution};
use memsnav_core::calibration::inflation::{axis_factors, inflate_covariance, InheritedCovariance};
use memsnav_core::calibration::layout::{
    CalibrationLayout, Sensor, ACCELEROMETER_PARAMETERS, GYROSCOPE_PARAMETERS,
};
use memsnav_py_macros::catch_panics;
use nalgebra::{DMatrix, SMatrix, SVector};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::convert;
use crate::errors::IntoPyResult;

/// The inflated covariance (P, P) and the factor of each output axis (3,).
type CovarianceAndFactors<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>);
/// The accelerometer (draws, 15) and gyroscope (draws, 21) parameter vectors.
type Draws<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>);

/// A (rows, columns) array as a matrix.
fn matrix(obj: &Bound<'_, PyAny>, argument: &str, shape: (usize, usize)) -> PyResult<DMatrix<f64>> {
    let f = convert::floats(obj, argument)?;
    if f.shape != [shape.0, shape.1] {
        return Err(PyValueError::new_err(format!(
            "{argument}: expected shape {shape:?}, got {:?}",
            f.shape
        )));
    }
    Ok(DMatrix::from_row_slice(shape.0, shape.1, &f.values))
}

/// A matrix → (rows, columns) numpy array.
fn to_numpy<'py>(
    py: Python<'py>,
    rows: usize,
    cols: usize,
    row_major: Vec<f64>,
) -> Bound<'py, PyArray2<f64>> {
    PyArray1::from_vec(py, row_major)
        .reshape([rows, cols])
        .expect("rows × cols elements")
}

/// The covariance of a `sensor`'s ("accelerometer" or "gyroscope")
/// calibration from correlated references: each output axis' block of
/// `covariance` scaled by the AR(1) variance factor (1 + ρ)/(1 − ρ) of that
/// axis' column of `residual` (W, 3), ρ its lag-one autocorrelation capped
/// at 0.9, the factor at least 1 (Wilks, eq. 5.12), plus the reference
/// solution's `bias_covariance` and `scale_factor_covariance` (3, 3) on the
/// bias and scale-factor blocks, except for the parameters named in `held`.
/// Returns `(covariance, factors)`, factors (3,) per output axis.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (sensor, covariance, residual, *, held, bias_covariance, scale_factor_covariance))]
fn inflate_calibration_covariance<'py>(
    py: Python<'py>,
    sensor: &str,
    covariance: &Bound<'py, PyAny>,
    residual: &Bound<'py, PyAny>,
    held: Vec<String>,
    bias_covariance: &Bound<'py, PyAny>,
    scale_factor_covariance: &Bound<'py, PyAny>,
) -> PyResult<CovarianceAndFactors<'py>> {
    let layout = CalibrationLayout {
        sensor: Sensor::from_name(sensor).ok_or_else(|| {
            PyValueError::new_err(format!(
                "sensor: expected 'accelerometer' or 'gyroscope', got {sensor:?}"
            ))
        })?,
    };
    let p = layout.len();
    let covariance = matrix(covariance, "covariance", (p, p))?;
    let residual = convert::vectors(residual, "residual")?;
    let held = held
        .iter()
        .map(|name| {
            layout.index(name).ok_or_else(|| {
                PyValueError::new_err(format!("held: {name:?} is not a parameter of the {sensor}"))
            })
        })
        .collect::<PyResult<Vec<_>>>()?;
    let inherited = InheritedCovariance {
        bias: convert::matrix3(bias_covariance, "bias_covariance")?,
        scale_factor: convert::matrix3(scale_factor_covariance, "scale_factor_covariance")?,
    };
    let factors = axis_factors("residual", &residual).py()?;
    let out = inflate_covariance(layout, &covariance, &factors, &held, &inherited).py()?;
    Ok((
        to_numpy(py, p, p, out.transpose().as_slice().to_vec()),
        convert::vector3_to_numpy(py, &factors),
    ))
}

/// The Gaussian of a `sensor`'s P parameters from its `{sensor}_mean` (P,)
/// and `{sensor}_covariance` (P, P).
fn distribution<const P: usize>(
    mean: &Bound<'_, PyAny>,
    covariance: &Bound<'_, PyAny>,
    sensor: &str,
) -> PyResult<ParameterDistribution<P>> {
    let (mean_name, covariance_name) = (format!("{sensor}_mean"), format!("{sensor}_covariance"));
    let mean = convert::scalars(mean, &mean_name)?;
    if mean.len() != P {
        return Err(PyValueError::new_err(format!(
            "{mean_name}: expected {P} parameters, got {}",
            mean.len()
        )));
    }
    let covariance = matrix(covariance, &covariance_name, (P, P))?;
    ParameterDistribution::new(
        &covariance_name,
        &SVector::from_column_slice(&mean),
        &SMatrix::from_column_slice(covariance.as_slice()),
    )
    .py()
}

/// `draws` calibrations drawn from the Gaussians N(mean, covariance) of an
/// accelerometer (15 parameters) and a gyroscope (21) calibration, in
/// `CalibrationLayout` order: draw i takes the accelerometer's parameters,
/// then the gyroscope's, from its own random stream (seed, i), so it is the
/// same whatever `draws` is. A singular covariance (held parameters) is
/// fine; one that is not positive semi-definite is refused. Returns
/// `(accelerometer, gyroscope)` arrays of shape (draws, 15) and (draws, 21).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (accelerometer_mean, accelerometer_covariance, gyroscope_mean, gyroscope_covariance, *, draws, seed))]
fn draw_imu_calibrations<'py>(
    py: Python<'py>,
    accelerometer_mean: &Bound<'py, PyAny>,
    accelerometer_covariance: &Bound<'py, PyAny>,
    gyroscope_mean: &Bound<'py, PyAny>,
    gyroscope_covariance: &Bound<'py, PyAny>,
    draws: usize,
    seed: u64,
) -> PyResult<Draws<'py>> {
    const A: usize = ACCELEROMETER_PARAMETERS;
    const G: usize = GYROSCOPE_PARAMETERS;
    let accelerometer = distribution::<A>(
        accelerometer_mean,
        accelerometer_covariance,
        "accelerometer",
    )?;
    let gyroscope = distribution::<G>(gyroscope_mean, gyroscope_covariance, "gyroscope")?;
    let set = ImuDraws {
        accelerometer,
        gyroscope,
    };
    let (a, g) = py.detach(|| set.draw_set(seed, draws)).py()?;
    Ok((to_numpy(py, draws, A, a), to_numpy(py, draws, G, g)))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(inflate_calibration_covariance, m)?)?;
    m.add_function(wrap_pyfunction!(draw_imu_calibrations, m)?)?;
    Ok(())
}
