//! `CalibrationLayout`: which parameter of which sensor axis sits at which
//! index of a calibration's parameter vector
//! (`memsnav_core::calibration::layout`). Conversions only.

use memsnav_core::calibration::layout::{
    accelerometer_from_parameters, gyroscope_from_parameters, CalibrationLayout, Group, Sensor,
};
use memsnav_core::calibration::{accelerometer_parameters, gyroscope_parameters};
use memsnav_core::sensors::NoiseModel;
use memsnav_py_macros::catch_panics;
use nalgebra::SVector;
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PySlice, PyTuple};

use crate::convert;
use crate::errors::IntoPyResult;
use crate::sensors::{PyAccelerometerModel, PyGyroscopeModel};

/// The parameter vector of an accelerometer (15) or gyroscope (21)
/// calibration: the order of `Calibration.parameter_names`, `.covariance`
/// and `.crb`. Groups in order: `bias` (3), `scale_factor` (3),
/// `misalignment` (6, off-diagonal uv, uw, vu, vw, wu, wv) and
/// `nonlinearity` (3) or `g_sensitivity` (9, row-major). A parameter's
/// output axis is the first letter after its group (u, v, w or p, q, r:
/// the body axes x, y, z); a matrix entry's second letter is its column.
#[pyclass(module = "memsnav._memsnav", name = "CalibrationLayout", frozen)]
pub struct PyCalibrationLayout {
    inner: CalibrationLayout,
}

impl PyCalibrationLayout {
    fn group(&self, name: &str) -> PyResult<Group> {
        self.inner
            .groups()
            .into_iter()
            .find(|g| g.name() == name)
            .ok_or_else(|| {
                PyValueError::new_err(format!(
                    "group: the {} has {:?}, not {name:?}",
                    self.inner.sensor.name(),
                    self.groups()
                ))
            })
    }

    fn axis(&self, letter: &str) -> PyResult<usize> {
        let axes = self.inner.sensor.axes();
        axes.iter().position(|&a| a == letter).ok_or_else(|| {
            PyValueError::new_err(format!(
                "axis: the {} axes are {axes:?}, not {letter:?}",
                self.inner.sensor.name()
            ))
        })
    }

    fn checked(&self, index: usize) -> PyResult<usize> {
        if index < self.inner.len() {
            Ok(index)
        } else {
            Err(PyValueError::new_err(format!(
                "index: the {} has {} parameters, not {}",
                self.inner.sensor.name(),
                self.inner.len(),
                index + 1
            )))
        }
    }
}

#[catch_panics]
#[pymethods]
impl PyCalibrationLayout {
    /// The layout of `sensor`: "accelerometer" or "gyroscope".
    #[new]
    fn new(sensor: &str) -> PyResult<Self> {
        let sensor = Sensor::from_name(sensor).ok_or_else(|| {
            PyValueError::new_err(format!(
                "sensor: expected 'accelerometer' or 'gyroscope', got {sensor:?}"
            ))
        })?;
        Ok(Self {
            inner: CalibrationLayout { sensor },
        })
    }

    /// "accelerometer" or "gyroscope".
    #[getter]
    fn sensor(&self) -> &'static str {
        self.inner.sensor.name()
    }

    /// The parameter names in index order (`bias_u`, ..., `misalignment_uv`, ...).
    #[getter]
    fn names(&self) -> Vec<String> {
        self.inner.names()
    }

    /// The groups (model attributes) in index order.
    #[getter]
    fn groups(&self) -> Vec<&'static str> {
        self.inner.groups().iter().map(|g| g.name()).collect()
    }

    /// The triad's output axes: ["u", "v", "w"] or ["p", "q", "r"].
    #[getter]
    fn axes(&self) -> Vec<&'static str> {
        self.inner.sensor.axes().to_vec()
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    /// The index of parameter `name`.
    fn index(&self, name: &str) -> PyResult<usize> {
        self.inner.index(name).ok_or_else(|| {
            PyValueError::new_err(format!(
                "name: {name:?} is not a parameter of the {} ({:?})",
                self.inner.sensor.name(),
                self.inner.names()
            ))
        })
    }

    /// The indices of `group`, as a slice of the parameter vector.
    fn group_slice<'py>(&self, py: Python<'py>, group: &str) -> PyResult<Bound<'py, PySlice>> {
        let range = self
            .inner
            .range(self.group(group)?)
            .expect("a group of the layout has a range");
        Ok(PySlice::new(
            py,
            range.start as isize,
            range.end as isize,
            1,
        ))
    }

    /// The model attribute and the index in it of parameter `index`:
    /// ("bias", (0,)), ("misalignment", (0, 2)), ("g_sensitivity", (1, 2)).
    fn parameter<'py>(
        &self,
        py: Python<'py>,
        index: usize,
    ) -> PyResult<(&'static str, Bound<'py, PyTuple>)> {
        let p = self.inner.parameter(self.checked(index)?);
        let position: Vec<usize> = std::iter::once(p.output_axis).chain(p.input_axis).collect();
        let position = PyTuple::new(py, position)?;
        Ok((p.group.name(), position))
    }

    /// The indices, in order, of the parameters of `group` (all groups when
    /// None) whose output axis is `axis` (a letter of `axes`; all when None).
    #[pyo3(signature = (*, group=None, axis=None))]
    fn indices(&self, group: Option<&str>, axis: Option<&str>) -> PyResult<Vec<usize>> {
        let group = group.map(|g| self.group(g)).transpose()?;
        let axis = axis.map(|a| self.axis(a)).transpose()?;
        Ok((0..self.inner.len())
            .filter(|&i| {
                let p = self.inner.parameter(i);
                group.is_none_or(|g| p.group == g) && axis.is_none_or(|a| p.output_axis == a)
            })
            .collect())
    }

    /// The parameter vector of `model` (an `AccelerometerModel` or
    /// `GyroscopeModel` of this layout's sensor).
    fn values<'py>(
        &self,
        py: Python<'py>,
        model: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let wrong = || {
            PyValueError::new_err(format!(
                "model: expected a {} model",
                self.inner.sensor.name()
            ))
        };
        let values: Vec<f64> = match self.inner.sensor {
            Sensor::Accelerometer => {
                let m = model.cast::<PyAccelerometerModel>().map_err(|_| wrong())?;
                accelerometer_parameters(&m.get().inner).as_slice().to_vec()
            }
            Sensor::Gyroscope => {
                let m = model.cast::<PyGyroscopeModel>().map_err(|_| wrong())?;
                gyroscope_parameters(&m.get().inner).as_slice().to_vec()
            }
        };
        Ok(PyArray1::from_vec(py, values))
    }

    /// The noise-free model of this layout's sensor whose parameters are
    /// `values` (the inverse of `values`), stored with `sample_rate` (Hz)
    /// [100].
    #[pyo3(signature = (values, *, sample_rate=None))]
    fn model(
        &self,
        py: Python<'_>,
        values: &Bound<'_, PyAny>,
        sample_rate: Option<f64>,
    ) -> PyResult<Py<PyAny>> {
        let sample_rate = sample_rate.unwrap_or(memsnav_core::sensors::DEFAULT_SAMPLE_RATE_HZ);
        memsnav_core::validate::positive("sample_rate", sample_rate).py()?;
        let values = convert::scalars(values, "values")?;
        if values.len() != self.inner.len() {
            return Err(PyValueError::new_err(format!(
                "values: expected {} parameters for the {}, got {}",
                self.inner.len(),
                self.inner.sensor.name(),
                values.len()
            )));
        }
        let noise = NoiseModel::default();
        Ok(match self.inner.sensor {
            Sensor::Accelerometer => {
                let p = SVector::from_column_slice(&values);
                let inner = accelerometer_from_parameters(&p, noise).py()?;
                Py::new(
                    py,
                    PyAccelerometerModel {
                        inner,
                        sample_rate_hz: sample_rate,
                    },
                )?
                .into_any()
            }
            Sensor::Gyroscope => {
                let p = SVector::from_column_slice(&values);
                let inner = gyroscope_from_parameters(&p, noise).py()?;
                Py::new(
                    py,
                    PyGyroscopeModel {
                        inner,
                        sample_rate_hz: sample_rate,
                    },
                )?
                .into_any()
            }
        })
    }

    fn __repr__(&self) -> String {
        format!("CalibrationLayout('{}')", self.inner.sensor.name())
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyCalibrationLayout>()?;
    Ok(())
}
