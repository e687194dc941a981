//! `calibrate_static` (multi-position calibration) and `correct_imu`.
//! Conversions only; the numerics and the defaults are in
//! `memsnav_core::calibration::{static_detector, static_poses}`.

use std::collections::HashMap;

use memsnav_core::calibration::static_detector::StaticDetector;
use memsnav_core::calibration::static_poses::{
    calibrate_static as core_calibrate_static, correct as core_correct, Holdout, Nominal,
    StaticCalibration, StaticCalibrationOptions,
};
use memsnav_core::calibration::{
    accelerometer_parameter_names, accelerometer_parameters, gyroscope_parameter_names,
    gyroscope_parameters,
};
use memsnav_py_macros::catch_panics;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::convert;
use crate::errors::IntoPyResult;
use crate::sensors::{PyAccelerometerModel, PyGyroscopeModel};

/// Specific force and angular rate arrays, each (N, 3).
type Corrected<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>);

/// The result of `calibrate_static` (see `memsnav.calibrate_static`).
#[pyclass(module = "memsnav._memsnav", name = "StaticCalibration", frozen)]
pub struct PyStaticCalibration {
    inner: StaticCalibration,
    sample_rate_hz: f64,
}

fn accel_py(
    py: Python<'_>,
    m: &memsnav_core::sensors::AccelerometerModel,
    rate: f64,
) -> PyResult<Py<PyAny>> {
    Ok(Py::new(
        py,
        PyAccelerometerModel {
            inner: m.clone(),
            sample_rate_hz: rate,
        },
    )?
    .into_any())
}

fn gyro_py(
    py: Python<'_>,
    m: &memsnav_core::sensors::GyroscopeModel,
    rate: f64,
) -> PyResult<Py<PyAny>> {
    Ok(Py::new(
        py,
        PyGyroscopeModel {
            inner: m.clone(),
            sample_rate_hz: rate,
        },
    )?
    .into_any())
}

#[catch_panics]
#[pymethods]
impl PyStaticCalibration {
    /// The accelerometer model of the nominal readings (SI), method §2.
    #[getter]
    fn accelerometer(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        accel_py(py, &self.inner.accelerometer, self.sample_rate_hz)
    }

    /// The gyroscope model of the nominal readings (SI), method §2.
    #[getter]
    fn gyroscope(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        gyro_py(py, &self.inner.gyroscope, self.sample_rate_hz)
    }

    /// One-sigma values in the accelerometer's attributes (SI; 0 where not estimated).
    #[getter]
    fn accelerometer_std(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        accel_py(py, &self.inner.accelerometer_std, self.sample_rate_hz)
    }

    /// One-sigma values in the gyroscope's attributes (SI; 0 where not estimated).
    #[getter]
    fn gyroscope_std(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        gyro_py(py, &self.inner.gyroscope_std, self.sample_rate_hz)
    }

    /// Covariance (36, 36) of `parameter_names`.
    #[getter]
    fn covariance<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let m = &self.inner.covariance;
        PyArray1::from_vec(py, m.transpose().as_slice().to_vec())
            .reshape([m.nrows(), m.ncols()])
            .expect("rows × cols elements")
    }

    /// Cramér-Rao bound (36, 36) for white noise of the initial rest's level.
    #[getter]
    fn crb<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let m = &self.inner.crb;
        PyArray1::from_vec(py, m.transpose().as_slice().to_vec())
            .reshape([m.nrows(), m.ncols()])
            .expect("rows × cols elements")
    }

    /// White-noise variance per sample at the initial rest, (2, 3):
    /// accelerometer (m/s²)², gyroscope (rad/s)², nominal readings.
    #[getter]
    fn white_noise_variance<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::vectors_to_numpy(py, &self.inner.white_noise_variance)
    }

    /// The 36 parameters in the order of `parameter_names` (SI).
    #[getter]
    fn parameters<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let a = accelerometer_parameters(&self.inner.accelerometer);
        let g = gyroscope_parameters(&self.inner.gyroscope);
        PyArray1::from_iter(py, a.iter().chain(g.iter()).copied())
    }

    /// "accelerometer bias_u", …, "gyroscope g_sensitivity_rw".
    #[getter]
    fn parameter_names(&self) -> Vec<String> {
        accelerometer_parameter_names()
            .into_iter()
            .map(|n| format!("accelerometer {n}"))
            .chain(
                gyroscope_parameter_names()
                    .into_iter()
                    .map(|n| format!("gyroscope {n}")),
            )
            .collect()
    }

    /// accel_scale, accel_offset, gyro_scale, gyro_offset, each (3,).
    #[getter]
    fn nominal<'py>(&self, py: Python<'py>) -> HashMap<&'static str, Bound<'py, PyArray1<f64>>> {
        let n = &self.inner.nominal;
        HashMap::from([
            ("accel_scale", convert::vector3_to_numpy(py, &n.accel_scale)),
            (
                "accel_offset",
                convert::vector3_to_numpy(py, &n.accel_offset),
            ),
            ("gyro_scale", convert::vector3_to_numpy(py, &n.gyro_scale)),
            ("gyro_offset", convert::vector3_to_numpy(py, &n.gyro_offset)),
        ])
    }

    /// Local gravity magnitude used, m/s².
    #[getter]
    fn gravity(&self) -> f64 {
        self.inner.gravity_m_s2
    }

    /// Mean sample rate of the session, Hz.
    #[getter]
    fn sample_rate(&self) -> f64 {
        self.sample_rate_hz
    }

    /// (P, 2) start and end (exclusive) sample indices of the poses.
    #[getter]
    fn poses<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        let flat: Vec<i64> = self
            .inner
            .poses
            .iter()
            .flat_map(|p| [p.pose.start as i64, p.pose.end as i64])
            .collect();
        PyArray1::from_vec(py, flat)
            .reshape([self.inner.poses.len(), 2])
            .expect("2 P elements")
    }

    /// (P,) True for poses left out of the fits.
    #[getter]
    fn pose_held_out(&self) -> Vec<bool> {
        self.inner.poses.iter().map(|p| p.held_out).collect()
    }

    /// (P,) ‖f‖ − g of each pose with the nominal readings, m/s².
    #[getter]
    fn magnitude_error_before<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_iter(
            py,
            self.inner.poses.iter().map(|p| p.magnitude_error_before),
        )
    }

    /// (P,) ‖f‖ − g of each pose after the calibration, m/s².
    #[getter]
    fn magnitude_error_after<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_iter(py, self.inner.poses.iter().map(|p| p.magnitude_error_after))
    }

    /// (T,) the first pose of each turn (turn k goes from pose k to k + 1).
    #[getter]
    fn turn_from<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        PyArray1::from_iter(py, self.inner.turns.iter().map(|t| t.from as i64))
    }

    /// (T,) True for turns into or out of a held-out pose.
    #[getter]
    fn turn_held_out(&self) -> Vec<bool> {
        self.inner.turns.iter().map(|t| t.held_out).collect()
    }

    /// (T,) gravity-direction error of each turn with the nominal readings, rad.
    #[getter]
    fn turn_error_before<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_iter(py, self.inner.turns.iter().map(|t| t.angle_error_before))
    }

    /// (T,) gravity-direction error of each turn after the calibration, rad.
    #[getter]
    fn turn_error_after<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_iter(py, self.inner.turns.iter().map(|t| t.angle_error_after))
    }

    /// [(parameter, reason)] of the parameters not estimated.
    #[getter]
    fn held(&self) -> Vec<(String, String)> {
        self.inner.held.clone()
    }

    /// The models of the second-order terms each stage considered (the
    /// accelerometer's nonlinearity, the gyroscope's g-sensitivity; empty
    /// under estimate="all"): [{"stage", "chosen" (index), "candidates":
    /// [{"terms", "parameters", "observations", "residual_rms", "aicc"
    /// (None when refused), "refused"}]}].
    #[getter]
    fn model_selection<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let out = PyList::empty(py);
        for s in &self.inner.model_selection {
            let candidates = PyList::empty(py);
            for c in &s.candidates {
                let item = PyDict::new(py);
                item.set_item("terms", c.terms.clone())?;
                item.set_item("parameters", c.parameters)?;
                item.set_item("observations", c.observations)?;
                item.set_item("residual_rms", c.residual_rms)?;
                item.set_item("aicc", c.aicc)?;
                item.set_item("refused", c.refused.clone())?;
                candidates.append(item)?;
            }
            let d = PyDict::new(py);
            d.set_item("stage", s.stage.clone())?;
            d.set_item("chosen", s.chosen)?;
            d.set_item("candidates", candidates)?;
            out.append(d)?;
        }
        Ok(out)
    }

    /// Poor conditioning, a sigma above the physical size, too few poses, a
    /// nominal scale far off (each also emitted as a `UserWarning`).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }

    /// The detector's accelerometer and gyroscope variance magnitudes per
    /// sample, (N, 2) (+inf within half a window of the ends).
    #[getter]
    fn variance_magnitude<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let d = &self.inner.detection;
        let flat: Vec<f64> = d
            .accel
            .variance_magnitude
            .iter()
            .zip(&d.gyro.variance_magnitude)
            .flat_map(|(a, g)| [*a, *g])
            .collect();
        PyArray1::from_vec(py, flat)
            .reshape([d.accel.variance_magnitude.len(), 2])
            .expect("2 N elements")
    }

    /// The detector's two thresholds (accelerometer, gyroscope).
    #[getter]
    fn detector_threshold(&self) -> (f64, f64) {
        let d = &self.inner.detection;
        (d.accel.threshold, d.gyro.threshold)
    }

    /// Residual std of the gravity-magnitude fit, m/s².
    #[getter]
    fn accelerometer_residual_std(&self) -> f64 {
        self.inner.accelerometer_residual_std
    }

    /// (3,) residual std of the gyroscope rest fit per axis, rad/s.
    #[getter]
    fn rest_residual_std<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        convert::vector3_to_numpy(py, &self.inner.rest_residual_std)
    }

    /// Residual std of the turn fit per direction component, rad.
    #[getter]
    fn turn_residual_std(&self) -> f64 {
        self.inner.turn_residual_std
    }

    /// Condition numbers of the magnitude, rest and turn problems (3,).
    #[getter]
    fn condition_number<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.condition_number)
    }

    /// SI specific force and angular rate (each (N, 3)) of raw readings.
    fn correct<'py>(
        &self,
        py: Python<'py>,
        accel: &Bound<'py, PyAny>,
        gyro: &Bound<'py, PyAny>,
    ) -> PyResult<Corrected<'py>> {
        let a = convert::vectors(accel, "accel")?;
        let g = convert::vectors(gyro, "gyro")?;
        let (f, w) = py.detach(|| self.inner.correct(&a, &g)).py()?;
        Ok((
            convert::vectors_to_numpy(py, &f),
            convert::vectors_to_numpy(py, &w),
        ))
    }

    fn __repr__(&self) -> String {
        format!(
            "StaticCalibration(poses={}, turns={}, held={}, warnings={})",
            self.inner.poses.len(),
            self.inner.turns.len(),
            self.inner.held.len(),
            self.inner.warnings.len()
        )
    }
}

/// The core's defaults of the detector and of the nominal readings (scale
/// 1, offset 0: readings already in SI), for the Python signature.
#[catch_panics]
#[pyfunction]
fn static_calibration_defaults() -> HashMap<&'static str, f64> {
    let d = StaticDetector::default();
    let n = Nominal::default();
    HashMap::from([
        ("window", d.window_s),
        ("threshold_factor", d.threshold_factor),
        ("initial_rest", d.initial_rest_s),
        ("min_pose", d.min_pose_s),
        ("scale", n.accel_scale.x),
        ("offset", n.accel_offset.x),
    ])
}

fn nominal(
    accel_scale: &Bound<'_, PyAny>,
    accel_offset: &Bound<'_, PyAny>,
    gyro_scale: &Bound<'_, PyAny>,
    gyro_offset: &Bound<'_, PyAny>,
) -> PyResult<Nominal> {
    Ok(Nominal {
        accel_scale: convert::per_axis(accel_scale, "accel_scale")?,
        accel_offset: convert::per_axis(accel_offset, "accel_offset")?,
        gyro_scale: convert::per_axis(gyro_scale, "gyro_scale")?,
        gyro_offset: convert::per_axis(gyro_offset, "gyro_offset")?,
    })
}

/// Every argument is required here; `memsnav.calibrate_static` documents
/// them and holds the defaults (from the core).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (time, accel, gyro, *, gravity, accel_scale, accel_offset, gyro_scale, gyro_offset, window, threshold_factor, initial_rest, min_pose, estimate, holdout_every, holdout_from))]
fn calibrate_static(
    py: Python<'_>,
    time: &Bound<'_, PyAny>,
    accel: &Bound<'_, PyAny>,
    gyro: &Bound<'_, PyAny>,
    gravity: f64,
    accel_scale: &Bound<'_, PyAny>,
    accel_offset: &Bound<'_, PyAny>,
    gyro_scale: &Bound<'_, PyAny>,
    gyro_offset: &Bound<'_, PyAny>,
    window: f64,
    threshold_factor: f64,
    initial_rest: f64,
    min_pose: f64,
    estimate: &str,
    holdout_every: Option<usize>,
    holdout_from: Option<f64>,
) -> PyResult<PyStaticCalibration> {
    let t = convert::scalars(time, "time")?;
    let a = convert::vectors(accel, "accel")?;
    let g = convert::vectors(gyro, "gyro")?;
    let options = StaticCalibrationOptions {
        gravity_m_s2: gravity,
        nominal: nominal(accel_scale, accel_offset, gyro_scale, gyro_offset)?,
        detector: StaticDetector {
            window_s: window,
            threshold_factor,
            initial_rest_s: initial_rest,
            min_pose_s: min_pose,
        },
        estimate: crate::calibration::estimate(estimate)?,
        holdout: Holdout {
            every: holdout_every,
            from_s: holdout_from,
        },
    };
    let inner = py
        .detach(|| core_calibrate_static(&t, &a, &g, &options))
        .py()?;
    // The models carry the sample rate of the session (their noise keywords).
    let span = t.last().copied().unwrap_or(0.0) - t.first().copied().unwrap_or(0.0);
    let sample_rate_hz = (t.len().saturating_sub(1)) as f64 / span;
    Ok(PyStaticCalibration {
        inner,
        sample_rate_hz,
    })
}

/// SI specific force and angular rate (each (N, 3)) of raw readings
/// through nominal scales and offsets and the models' exact inverses.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (accel, gyro, accelerometer, gyroscope, *, accel_scale, accel_offset, gyro_scale, gyro_offset))]
fn correct_imu<'py>(
    py: Python<'py>,
    accel: &Bound<'py, PyAny>,
    gyro: &Bound<'py, PyAny>,
    accelerometer: PyRef<'py, PyAccelerometerModel>,
    gyroscope: PyRef<'py, PyGyroscopeModel>,
    accel_scale: &Bound<'py, PyAny>,
    accel_offset: &Bound<'py, PyAny>,
    gyro_scale: &Bound<'py, PyAny>,
    gyro_offset: &Bound<'py, PyAny>,
) -> PyResult<Corrected<'py>> {
    let a = convert::vectors(accel, "accel")?;
    let g = convert::vectors(gyro, "gyro")?;
    let n = nominal(accel_scale, accel_offset, gyro_scale, gyro_offset)?;
    let (acc, gyr) = (accelerometer.inner.clone(), gyroscope.inner.clone());
    let (f, w) = py.detach(|| core_correct(&n, &acc, &gyr, &a, &g)).py()?;
    Ok((
        convert::vectors_to_numpy(py, &f),
        convert::vectors_to_numpy(py, &w),
    ))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyStaticCalibration>()?;
    m.add_function(wrap_pyfunction!(calibrate_static, m)?)?;
    m.add_function(wrap_pyfunction!(correct_imu, m)?)?;
    m.add_function(wrap_pyfunction!(static_calibration_defaults, m)?)?;
    Ok(())
}
