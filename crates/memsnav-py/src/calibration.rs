//! `calibrate_accelerometer`, `calibrate_gyroscope` (method §3) and their
//! result class. Conversions only; the numerics are in
//! `memsnav_core::calibration`.

use memsnav_core::calibration::{
    accelerometer_parameter_names, accelerometer_std_model, calibrate_accelerometer as core_accel,
    calibrate_gyroscope as core_gyro, gyroscope_parameter_names, gyroscope_std_model, Calibration,
    CalibrationOptions, Estimate, Method,
};
use memsnav_core::experiments::calibrate_invert::calibrated_spec;
use memsnav_core::sensors::DEFAULT_SAMPLE_RATE_HZ;
use memsnav_core::sensors::{ImuModel, NoiseModel};
use memsnav_py_macros::catch_panics;
use nalgebra::{DMatrix, Vector3};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::convert;
use crate::errors::IntoPyResult;
use crate::sensors::{PyAccelerometerModel, PyGyroscopeModel, PyImuModel};

/// A calibrated sensor model with its uncertainties (method §3).
///
/// `model`: the estimated `AccelerometerModel` / `GyroscopeModel`.
/// `std`: an object of the same class whose parameter attributes hold the
/// one-sigma uncertainties (SI). `covariance`: covariance of the parameter
/// vector ordered as `parameter_names`. `residual_std` (3,): residual
/// standard deviation per output axis. `condition_number` (3,): of the
/// column-equilibrated regressors per axis. `crb`: Cramér-Rao bound of the
/// parameter vector (None unless `noise_std` was given) for references with
/// the noise the calibration was given (`reference_noise_std`: the
/// errors-in-variables bound; exact references without); `crb_std`: its
/// square-root diagonal as a model-shaped object.
/// `warnings`: parameters that are only poorly determined. `held`:
/// [(parameter, reason)] not estimated under `estimate="determinable"`.
#[pyclass(module = "memsnav._memsnav", name = "Calibration", frozen)]
pub struct PyCalibration {
    /// The estimated model: an `AccelerometerModel` or `GyroscopeModel`, like
    /// the calibrated sensor.
    #[pyo3(get)]
    model: Py<PyAny>,
    /// One-sigma uncertainties (SI) in the attributes of an object of the
    /// model's class.
    #[pyo3(get)]
    std: Py<PyAny>,
    /// Square root of the Cramér-Rao bound's diagonal in the model's
    /// attributes (SI); None unless `noise_std` was given.
    #[pyo3(get)]
    crb_std: Option<Py<PyAny>>,
    /// Names of the parameters in covariance order (`bias_u`, …).
    #[pyo3(get)]
    parameter_names: Vec<String>,
    /// Parameters that are only poorly determined (each also raised as a
    /// `UserWarning`).
    #[pyo3(get)]
    warnings: Vec<String>,
    /// [(parameter, reason)] of the parameters not estimated under
    /// `estimate="determinable"` (held at zero, with zero variance).
    #[pyo3(get)]
    held: Vec<(String, String)>,
    covariance: DMatrix<f64>,
    crb: Option<DMatrix<f64>>,
    residual_std: Vector3<f64>,
    condition_number: Vector3<f64>,
}

fn dmatrix_to_numpy<'py>(py: Python<'py>, m: &DMatrix<f64>) -> Bound<'py, PyArray2<f64>> {
    let rows: Vec<f64> = m.transpose().as_slice().to_vec();
    PyArray1::from_vec(py, rows)
        .reshape([m.nrows(), m.ncols()])
        .expect("rows × cols elements")
}

#[catch_panics]
#[pymethods]
impl PyCalibration {
    /// Covariance of the parameter vector, ordered as `parameter_names`, SI.
    #[getter]
    fn covariance<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        dmatrix_to_numpy(py, &self.covariance)
    }

    /// Cramér-Rao bound of the parameter vector (ordered as `parameter_names`),
    /// None unless `noise_std` was given: for references with the noise given as
    /// `reference_noise_std` (the errors-in-variables bound), exact references without.
    #[getter]
    fn crb<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f64>>> {
        self.crb.as_ref().map(|c| dmatrix_to_numpy(py, c))
    }

    /// Residual standard deviation per output axis, (3,) m/s² or rad/s.
    #[getter]
    fn residual_std<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        convert::vector3_to_numpy(py, &self.residual_std)
    }

    /// Condition number of the column-equilibrated regressors per output axis, (3,).
    #[getter]
    fn condition_number<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        convert::vector3_to_numpy(py, &self.condition_number)
    }

    fn __repr__(&self) -> String {
        format!(
            "Calibration(residual_std={:?}, condition_number={:?}, warnings={})",
            self.residual_std.as_slice(),
            self.condition_number.as_slice(),
            self.warnings.len()
        )
    }
}

pub(crate) fn method(name: &str) -> PyResult<Method> {
    match name {
        "ls" => Ok(Method::LeastSquares),
        "eiv" => Ok(Method::ErrorsInVariables),
        other => Err(PyValueError::new_err(format!(
            "method: expected 'ls' or 'eiv', got '{other}'"
        ))),
    }
}

/// `estimate`: "all" or "determinable" (see `memsnav_core::calibration::determinable`).
pub(crate) fn estimate(name: &str) -> PyResult<Estimate> {
    match name {
        "all" => Ok(Estimate::All),
        "determinable" => Ok(Estimate::Determinable),
        other => Err(PyValueError::new_err(format!(
            "estimate: expected 'all' or 'determinable', got '{other}'"
        ))),
    }
}

fn wrap<M>(
    py: Python<'_>,
    cal: Calibration<M>,
    names: Vec<String>,
    to_py: impl Fn(M) -> PyResult<Py<PyAny>>,
    crb_std: impl Fn(&DMatrix<f64>) -> PyResult<Py<PyAny>>,
) -> PyResult<PyCalibration> {
    // Each "poorly determined" diagnostic as a Python `UserWarning`.
    crate::warnings::warn_all(py, &cal.warnings)?;
    Ok(PyCalibration {
        crb_std: cal.crb.as_ref().map(crb_std).transpose()?,
        model: to_py(cal.model)?,
        std: to_py(cal.std)?,
        parameter_names: names,
        warnings: cal.warnings,
        held: cal.held,
        covariance: cal.covariance,
        crb: cal.crb,
        residual_std: cal.residual_std,
        condition_number: cal.condition_number,
    })
}

/// Calibrates an accelerometer triad (method §3): `measured` (N, 3) outputs
/// and `reference_specific_force` (N, 3) reference inputs, m/s², body axes.
/// `method`: "ls" (plain least squares) or "eiv" (errors-in-variables
/// correction for noisy references; needs `reference_noise_std`, m/s² per
/// sample). `noise_std`: the sensor's white noise per sample (m/s²); when
/// given, `.crb` holds the Cramér-Rao bound. `sample_rate` (Hz) is stored
/// in the returned model. `estimate`: "all" (every parameter; data that
/// cannot determine one raise `UnobservableError`) or "determinable" (only
/// what the data determine; the rest held at zero and listed in `.held`;
/// the rule is in docs/how-to/calibrate-an-imu.md).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (measured, reference_specific_force, *, method="ls", reference_noise_std=None, noise_std=None, sample_rate=None, estimate="all"))]
fn calibrate_accelerometer(
    py: Python<'_>,
    measured: &Bound<'_, PyAny>,
    reference_specific_force: &Bound<'_, PyAny>,
    method: &str,
    reference_noise_std: Option<f64>,
    noise_std: Option<f64>,
    sample_rate: Option<f64>,
    estimate: &str,
) -> PyResult<PyCalibration> {
    let sample_rate = sample_rate.unwrap_or(DEFAULT_SAMPLE_RATE_HZ);
    let s = convert::vectors(measured, "measured")?;
    let f = convert::vectors(reference_specific_force, "reference_specific_force")?;
    memsnav_core::validate::positive("sample_rate", sample_rate).py()?;
    let options = CalibrationOptions {
        method: self::method(method)?,
        reference_noise_std,
        noise_std,
        estimate: self::estimate(estimate)?,
        ..Default::default()
    };
    let cal = py.detach(|| core_accel(&s, &f, &options)).py()?;
    let to_py = |m| {
        Ok(Py::new(
            py,
            PyAccelerometerModel {
                inner: m,
                sample_rate_hz: sample_rate,
            },
        )?
        .into_any())
    };
    let crb_std = |c: &DMatrix<f64>| to_py(accelerometer_std_model(c));
    wrap(
        py,
        cal.clone(),
        accelerometer_parameter_names(),
        to_py,
        crb_std,
    )
}

/// Calibrates a gyroscope triad (method §3): `measured` (N, 3) outputs
/// (rad/s), `reference_angular_rate` (N, 3) rad/s and
/// `reference_specific_force` (N, 3) m/s², body axes. `method`: "ls" or
/// "eiv" (needs `reference_noise_std`, rad/s per sample; the optional
/// `reference_specific_force_noise_std`, m/s², corrects the g-sensitivity
/// columns too). `noise_std`: the gyro white noise per sample (rad/s), for
/// the Cramér-Rao bound. `estimate`: "all" or "determinable" (static data:
/// bias and g-sensitivity only), as for `calibrate_accelerometer`.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (measured, reference_angular_rate, reference_specific_force, *, method="ls", reference_noise_std=None, reference_specific_force_noise_std=None, noise_std=None, sample_rate=None, estimate="all"))]
fn calibrate_gyroscope(
    py: Python<'_>,
    measured: &Bound<'_, PyAny>,
    reference_angular_rate: &Bound<'_, PyAny>,
    reference_specific_force: &Bound<'_, PyAny>,
    method: &str,
    reference_noise_std: Option<f64>,
    reference_specific_force_noise_std: Option<f64>,
    noise_std: Option<f64>,
    sample_rate: Option<f64>,
    estimate: &str,
) -> PyResult<PyCalibration> {
    let sample_rate = sample_rate.unwrap_or(DEFAULT_SAMPLE_RATE_HZ);
    let s = convert::vectors(measured, "measured")?;
    let w = convert::vectors(reference_angular_rate, "reference_angular_rate")?;
    let f = convert::vectors(reference_specific_force, "reference_specific_force")?;
    memsnav_core::validate::positive("sample_rate", sample_rate).py()?;
    let options = CalibrationOptions {
        method: self::method(method)?,
        reference_noise_std,
        reference_specific_force_noise_std,
        noise_std,
        estimate: self::estimate(estimate)?,
    };
    let cal = py.detach(|| core_gyro(&s, &w, &f, &options)).py()?;
    let to_py = |m| {
        Ok(Py::new(
            py,
            PyGyroscopeModel {
                inner: m,
                sample_rate_hz: sample_rate,
            },
        )?
        .into_any())
    };
    let crb_std = |c: &DMatrix<f64>| to_py(gyroscope_std_model(c));
    wrap(py, cal.clone(), gyroscope_parameter_names(), to_py, crb_std)
}

/// The IMU to tune a coupled filter with when it runs on outputs corrected
/// by these calibrations (`invert_accelerometer`, `invert_gyroscope`): the
/// calibrated models with the sensors' white noise per sample
/// (`accel_noise_std` m/s², `gyro_noise_std` rad/s), and a spec holding
/// what the calibrations leave uncertain at a land vehicle's operating
/// point (level, g on the vertical axis), from their full covariances:
/// terms the motion could not separate count by the combination that
/// reaches the output, not by their own large stds
/// (`memsnav_core::experiments::calibrate_invert::calibrated_spec`).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (accelerometer, gyroscope, *, accel_noise_std, gyro_noise_std))]
fn calibrated_imu(
    py: Python<'_>,
    accelerometer: &PyCalibration,
    gyroscope: &PyCalibration,
    accel_noise_std: f64,
    gyro_noise_std: f64,
) -> PyResult<PyImuModel> {
    let acc = accelerometer
        .model
        .bind(py)
        .cast::<PyAccelerometerModel>()
        .map_err(|_| PyValueError::new_err("accelerometer: expected an accelerometer Calibration"))?
        .get();
    let gyr = gyroscope
        .model
        .bind(py)
        .cast::<PyGyroscopeModel>()
        .map_err(|_| PyValueError::new_err("gyroscope: expected a gyroscope Calibration"))?
        .get();
    let noise = |name: &str, std: f64| -> PyResult<NoiseModel> {
        memsnav_core::validate::non_negative(name, std).py()?;
        Ok(NoiseModel {
            white_std: std,
            ..Default::default()
        })
    };
    let (noise_a, noise_g) = (
        noise("accel_noise_std", accel_noise_std)?,
        noise("gyro_noise_std", gyro_noise_std)?,
    );
    let spec = calibrated_spec(
        &accelerometer.covariance,
        &gyroscope.covariance,
        noise_a,
        noise_g,
    );
    let mut a = acc.inner.clone();
    a.noise = noise_a;
    let mut g = gyr.inner.clone();
    g.noise = noise_g;
    let inner = ImuModel::with_spec(a, g, acc.sample_rate_hz, spec).py()?;
    Ok(PyImuModel { inner })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyCalibration>()?;
    m.add_function(wrap_pyfunction!(calibrated_imu, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate_accelerometer, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate_gyroscope, m)?)?;
    Ok(())
}
