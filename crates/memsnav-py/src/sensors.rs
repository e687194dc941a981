//! `AccelerometerModel`, `GyroscopeModel`, `ImuModel`: the sensor error
//! models of method §2 and the IMU presets. Conversions only; the numerics
//! are in `memsnav_core::sensors`.

use memsnav_core::random;
use memsnav_core::sensors::DEFAULT_SAMPLE_RATE_HZ;
use memsnav_core::sensors::{
    presets, AccelerometerModel, GyroscopeModel, ImuModel, ImuSpec, NoiseModel,
};
use memsnav_py_macros::catch_panics;
use nalgebra::{Matrix3, Vector3};
use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::convert;
use crate::errors::IntoPyResult;

/// `(accel, gyro)`, two `(N, 3)` arrays.
type SeriesPair<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>);

/// The keyword arguments shared by both sensors, as a core noise model.
fn noise_model(
    noise_std: f64,
    noise_density: Option<f64>,
    bias_instability: f64,
    bias_correlation_time: f64,
    bias_random_walk: f64,
    quantization: f64,
) -> PyResult<NoiseModel> {
    let noise = NoiseModel {
        white_std: noise_std,
        white_density: noise_density.unwrap_or(0.0),
        bias_instability_std: bias_instability,
        bias_correlation_time_s: bias_correlation_time,
        bias_random_walk,
        quantization,
    };
    noise.validate().py()?;
    Ok(noise)
}

/// The noise keywords of a model (for pickling): white noise in the form it
/// was given (density or per sample).
fn noise_kwargs<'py>(
    py: Python<'py>,
    noise: &NoiseModel,
    sample_rate_hz: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let kwargs = PyDict::new(py);
    if noise.white_density > 0.0 {
        kwargs.set_item("noise_density", noise.white_density)?;
    } else {
        kwargs.set_item("noise_std", noise.white_std)?;
    }
    kwargs.set_item("sample_rate", sample_rate_hz)?;
    kwargs.set_item("bias_instability", noise.bias_instability_std)?;
    kwargs.set_item("bias_correlation_time", noise.bias_correlation_time_s)?;
    kwargs.set_item("bias_random_walk", noise.bias_random_walk)?;
    kwargs.set_item("quantization", noise.quantization)?;
    Ok(kwargs)
}

fn list3(v: &Vector3<f64>) -> String {
    format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z)
}

fn list33(m: &Matrix3<f64>) -> String {
    let rows: Vec<String> = m.row_iter().map(|r| list3(&r.transpose())).collect();
    format!("[{}]", rows.join(", "))
}

fn noise_repr(noise: &NoiseModel, sample_rate_hz: f64) -> String {
    let white = if noise.white_density > 0.0 {
        format!("noise_density={:?}", noise.white_density)
    } else {
        format!("noise_std={:?}", noise.white_std)
    };
    format!(
        "{white}, sample_rate={:?}, bias_instability={:?}, bias_correlation_time={:?}, bias_random_walk={:?}, quantization={:?}",
        sample_rate_hz,
        noise.bias_instability_std,
        noise.bias_correlation_time_s,
        noise.bias_random_walk,
        noise.quantization
    )
}

/// Accelerometer triad, method §2 (paper eq. 2), SI units:
/// S = Q((I − D − M)(Γ − (b + β + ρ) − N (Γ ⊙ Γ) − ν)).
///
/// `bias` (3,) m/s²; `scale_factor` (3,) D; `misalignment` (3, 3) M with a
/// zero diagonal (M[i, j] couples input axis j into output axis i);
/// `nonlinearity` (3,) N, 1/(m/s²).
///
/// Noise keywords (all optional, zero = off, units of the sensor's output):
/// `noise_std` white input-referred noise ν, std per sample; or
/// `noise_density` the same as a density per √Hz (velocity / angle random
/// walk), std per sample = density · √sample_rate (give one, not both);
/// `sample_rate` Hz; `bias_instability` steady-state std of a first-order
/// Gauss-Markov bias with correlation time `bias_correlation_time` s,
/// started stationary; `bias_random_walk` bias growth per √s, starting at
/// zero; `quantization` output LSB (readings rounded to a multiple of it).
/// The Gauss-Markov and random-walk biases add to `bias`; quantisation acts
/// on the output.
#[pyclass(module = "memsnav._memsnav", name = "AccelerometerModel", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct PyAccelerometerModel {
    pub inner: AccelerometerModel,
    pub sample_rate_hz: f64,
}

#[catch_panics]
#[pymethods]
impl PyAccelerometerModel {
    #[new]
    #[pyo3(signature = (bias, scale_factor, misalignment, nonlinearity, noise_std=0.0, *, noise_density=None, sample_rate=None, bias_instability=0.0, bias_correlation_time=0.0, bias_random_walk=0.0, quantization=0.0))]
    fn new(
        bias: &Bound<'_, PyAny>,
        scale_factor: &Bound<'_, PyAny>,
        misalignment: &Bound<'_, PyAny>,
        nonlinearity: &Bound<'_, PyAny>,
        noise_std: f64,
        noise_density: Option<f64>,
        sample_rate: Option<f64>,
        bias_instability: f64,
        bias_correlation_time: f64,
        bias_random_walk: f64,
        quantization: f64,
    ) -> PyResult<Self> {
        let sample_rate = sample_rate.unwrap_or(DEFAULT_SAMPLE_RATE_HZ);
        memsnav_core::sensors::check_sample_rate(sample_rate).py()?;
        let noise = noise_model(
            noise_std,
            noise_density,
            bias_instability,
            bias_correlation_time,
            bias_random_walk,
            quantization,
        )?;
        let inner = AccelerometerModel::new(
            convert::vector3(bias, "bias")?,
            convert::vector3(scale_factor, "scale_factor")?,
            convert::matrix3(misalignment, "misalignment")?,
            convert::vector3(nonlinearity, "nonlinearity")?,
            noise,
        )
        .py()?;
        Ok(Self {
            inner,
            sample_rate_hz: sample_rate,
        })
    }

    /// Readings for true specific forces, sampled at `sample_rate`.
    ///
    /// - `specific_force` (N, 3) m/s²: the true input in body axes.
    /// - `seed`: the noise's random stream, an integer in [0, 2**64) [0].
    #[pyo3(signature = (specific_force, seed=None))]
    fn measure<'py>(
        &self,
        py: Python<'py>,
        specific_force: &Bound<'py, PyAny>,
        seed: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let f = convert::vectors(specific_force, "specific_force")?;
        let mut rng = random::from_optional_seed(convert::seed(seed)?);
        let out = py
            .detach(|| self.inner.measure(&f, self.sample_rate_hz, &mut rng))
            .py()?;
        Ok(convert::vectors_to_numpy(py, &out))
    }

    /// Bias b, (3,) m/s², per sensor axis.
    #[getter]
    fn bias<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        convert::vector3_to_numpy(py, &self.inner.bias)
    }
    /// Scale-factor errors D, (3,) dimensionless, per sensor axis.
    #[getter]
    fn scale_factor<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        convert::vector3_to_numpy(py, &self.inner.scale_factor)
    }
    /// Misalignment M, (3, 3) dimensionless with a zero diagonal:
    /// `M[i, j]` couples input axis j into output axis i.
    #[getter]
    fn misalignment<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::matrix3_to_numpy(py, &self.inner.misalignment)
    }
    /// Nonlinearity N, (3,) 1/(m/s²), per sensor axis.
    #[getter]
    fn nonlinearity<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        convert::vector3_to_numpy(py, &self.inner.nonlinearity)
    }
    /// White noise std per sample at `sample_rate`, m/s².
    #[getter]
    fn noise_std(&self) -> f64 {
        self.inner.noise.white_std_per_sample(self.sample_rate_hz)
    }
    /// White noise density (velocity random walk), m/s²/√Hz (= noise_std / √sample_rate).
    #[getter]
    fn noise_density(&self) -> f64 {
        self.inner.noise.white_density_at(self.sample_rate_hz)
    }
    /// Sample rate, Hz.
    #[getter]
    fn sample_rate(&self) -> f64 {
        self.sample_rate_hz
    }
    /// Gauss-Markov bias steady-state std, m/s².
    #[getter]
    fn bias_instability(&self) -> f64 {
        self.inner.noise.bias_instability_std
    }
    /// Gauss-Markov bias correlation time, s.
    #[getter]
    fn bias_correlation_time(&self) -> f64 {
        self.inner.noise.bias_correlation_time_s
    }
    /// Random-walk bias growth, m/s²/√s.
    #[getter]
    fn bias_random_walk(&self) -> f64 {
        self.inner.noise.bias_random_walk
    }
    /// Output LSB, m/s² (0: none).
    #[getter]
    fn quantization(&self) -> f64 {
        self.inner.noise.quantization
    }

    fn __repr__(&self) -> String {
        let m = &self.inner;
        format!(
            "AccelerometerModel(bias={}, scale_factor={}, misalignment={}, nonlinearity={}, {})",
            list3(&m.bias),
            list3(&m.scale_factor),
            list33(&m.misalignment),
            list3(&m.nonlinearity),
            noise_repr(&m.noise, self.sample_rate_hz)
        )
    }

    fn __getnewargs_ex__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyTuple>, Bound<'py, PyDict>)> {
        let args = PyTuple::new(
            py,
            [
                self.bias(py)?.into_any(),
                self.scale_factor(py)?.into_any(),
                self.misalignment(py)?.into_any(),
                self.nonlinearity(py)?.into_any(),
            ],
        )?;
        Ok((
            args,
            noise_kwargs(py, &self.inner.noise, self.sample_rate_hz)?,
        ))
    }
}

/// Gyroscope triad, method §2 (paper eq. 3), SI units:
/// S = Q((I − D − M)(Ω − (b + β + ρ) − K Γ − ν)).
///
/// `bias` (3,) rad/s; `scale_factor` (3,) D; `misalignment` (3, 3) M with a
/// zero diagonal; `g_sensitivity` (3, 3) K, (rad/s)/(m/s²), row i = gyro
/// axis i's sensitivity to the three specific-force components.
///
/// Noise keywords (all optional, zero = off, units of the sensor's output):
/// `noise_std` white input-referred noise ν, std per sample; or
/// `noise_density` the same as a density per √Hz (velocity / angle random
/// walk), std per sample = density · √sample_rate (give one, not both);
/// `sample_rate` Hz; `bias_instability` steady-state std of a first-order
/// Gauss-Markov bias with correlation time `bias_correlation_time` s,
/// started stationary; `bias_random_walk` bias growth per √s, starting at
/// zero; `quantization` output LSB (readings rounded to a multiple of it).
/// The Gauss-Markov and random-walk biases add to `bias`; quantisation acts
/// on the output.
#[pyclass(module = "memsnav._memsnav", name = "GyroscopeModel", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct PyGyroscopeModel {
    pub inner: GyroscopeModel,
    pub sample_rate_hz: f64,
}

#[catch_panics]
#[pymethods]
impl PyGyroscopeModel {
    #[new]
    #[pyo3(signature = (bias, scale_factor, misalignment, g_sensitivity, noise_std=0.0, *, noise_density=None, sample_rate=None, bias_instability=0.0, bias_correlation_time=0.0, bias_random_walk=0.0, quantization=0.0))]
    fn new(
        bias: &Bound<'_, PyAny>,
        scale_factor: &Bound<'_, PyAny>,
        misalignment: &Bound<'_, PyAny>,
        g_sensitivity: &Bound<'_, PyAny>,
        noise_std: f64,
        noise_density: Option<f64>,
        sample_rate: Option<f64>,
        bias_instability: f64,
        bias_correlation_time: f64,
        bias_random_walk: f64,
        quantization: f64,
    ) -> PyResult<Self> {
        let sample_rate = sample_rate.unwrap_or(DEFAULT_SAMPLE_RATE_HZ);
        memsnav_core::sensors::check_sample_rate(sample_rate).py()?;
        let noise = noise_model(
            noise_std,
            noise_density,
            bias_instability,
            bias_correlation_time,
            bias_random_walk,
            quantization,
        )?;
        let inner = GyroscopeModel::new(
            convert::vector3(bias, "bias")?,
            convert::vector3(scale_factor, "scale_factor")?,
            convert::matrix3(misalignment, "misalignment")?,
            convert::matrix3(g_sensitivity, "g_sensitivity")?,
            noise,
        )
        .py()?;
        Ok(Self {
            inner,
            sample_rate_hz: sample_rate,
        })
    }

    /// Readings for true angular rates, sampled at `sample_rate`.
    ///
    /// - `angular_rate` (N, 3) rad/s: the true input in body axes.
    /// - `specific_force` (N, 3) m/s²: the true specific force (for the
    ///   g-sensitivity).
    /// - `seed`: the noise's random stream, an integer in [0, 2**64) [0].
    #[pyo3(signature = (angular_rate, specific_force, seed=None))]
    fn measure<'py>(
        &self,
        py: Python<'py>,
        angular_rate: &Bound<'py, PyAny>,
        specific_force: &Bound<'py, PyAny>,
        seed: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let w = convert::vectors(angular_rate, "angular_rate")?;
        let f = convert::vectors(specific_force, "specific_force")?;
        let mut rng = random::from_optional_seed(convert::seed(seed)?);
        let out = py
            .detach(|| self.inner.measure(&w, &f, self.sample_rate_hz, &mut rng))
            .py()?;
        Ok(convert::vectors_to_numpy(py, &out))
    }

    /// Bias b, (3,) rad/s, per sensor axis.
    #[getter]
    fn bias<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        convert::vector3_to_numpy(py, &self.inner.bias)
    }
    /// Scale-factor errors D, (3,) dimensionless, per sensor axis.
    #[getter]
    fn scale_factor<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        convert::vector3_to_numpy(py, &self.inner.scale_factor)
    }
    /// Misalignment M, (3, 3) dimensionless with a zero diagonal:
    /// `M[i, j]` couples input axis j into output axis i.
    #[getter]
    fn misalignment<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::matrix3_to_numpy(py, &self.inner.misalignment)
    }
    /// g-sensitivity K, (3, 3) (rad/s)/(m/s²): row i is gyro axis i's
    /// sensitivity to the three specific-force components.
    #[getter]
    fn g_sensitivity<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        convert::matrix3_to_numpy(py, &self.inner.g_sensitivity)
    }
    /// White noise std per sample at `sample_rate`, rad/s.
    #[getter]
    fn noise_std(&self) -> f64 {
        self.inner.noise.white_std_per_sample(self.sample_rate_hz)
    }
    /// White noise density (angle random walk), rad/s/√Hz (= noise_std / √sample_rate).
    #[getter]
    fn noise_density(&self) -> f64 {
        self.inner.noise.white_density_at(self.sample_rate_hz)
    }
    /// Sample rate, Hz.
    #[getter]
    fn sample_rate(&self) -> f64 {
        self.sample_rate_hz
    }
    /// Gauss-Markov bias steady-state std, rad/s.
    #[getter]
    fn bias_instability(&self) -> f64 {
        self.inner.noise.bias_instability_std
    }
    /// Gauss-Markov bias correlation time, s.
    #[getter]
    fn bias_correlation_time(&self) -> f64 {
        self.inner.noise.bias_correlation_time_s
    }
    /// Random-walk bias growth (rate random walk), rad/s/√s.
    #[getter]
    fn bias_random_walk(&self) -> f64 {
        self.inner.noise.bias_random_walk
    }
    /// Output LSB, rad/s (0: none).
    #[getter]
    fn quantization(&self) -> f64 {
        self.inner.noise.quantization
    }

    fn __repr__(&self) -> String {
        let m = &self.inner;
        format!(
            "GyroscopeModel(bias={}, scale_factor={}, misalignment={}, g_sensitivity={}, {})",
            list3(&m.bias),
            list3(&m.scale_factor),
            list33(&m.misalignment),
            list33(&m.g_sensitivity),
            noise_repr(&m.noise, self.sample_rate_hz)
        )
    }

    fn __getnewargs_ex__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyTuple>, Bound<'py, PyDict>)> {
        let args = PyTuple::new(
            py,
            [
                self.bias(py)?.into_any(),
                self.scale_factor(py)?.into_any(),
                self.misalignment(py)?.into_any(),
                self.g_sensitivity(py)?.into_any(),
            ],
        )?;
        Ok((
            args,
            noise_kwargs(py, &self.inner.noise, self.sample_rate_hz)?,
        ))
    }
}

fn spec_to_dict<'py>(py: Python<'py>, spec: &ImuSpec) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (key, value) in spec.fields() {
        dict.set_item(key, value)?;
    }
    Ok(dict)
}

/// Overrides `spec` with the entries of a user dict (the rules are the
/// core's, `ImuSpec::with_overrides`: unknown keys, negative or non-finite
/// values and a Gauss-Markov term without a correlation time are errors
/// naming the key).
pub(crate) fn update_spec(spec: &mut ImuSpec, dict: &Bound<'_, PyDict>) -> PyResult<()> {
    let mut overrides = Vec::with_capacity(dict.len());
    for (key, value) in dict.iter() {
        let key: String = key
            .extract()
            .map_err(|_| PyValueError::new_err(format!("spec: keys must be strings, got {key}")))?;
        let value: f64 = value
            .extract()
            .map_err(|_| PyValueError::new_err(format!("spec['{key}']: must be a number")))?;
        overrides.push((key, value));
    }
    *spec = spec.with_overrides(&overrides).py()?;
    Ok(())
}

/// A sensor's noise re-expressed for a new sample rate: white noise given
/// per sample at the sensor's own rate becomes the equivalent density, so
/// the physical noise is kept.
fn noise_for_rate(noise: NoiseModel, own_rate_hz: f64, new_rate_hz: f64) -> NoiseModel {
    if own_rate_hz == new_rate_hz {
        noise
    } else {
        noise.as_density(own_rate_hz)
    }
}

/// An accelerometer and a gyroscope triad sampled together, with the spec
/// (one-sigma magnitudes) their errors come from.
///
/// `ImuModel(acc, gyr, sample_rate=None, *, spec=None)`: `sample_rate` None
/// takes the sensors' common rate; a different rate keeps each sensor's
/// noise density (per-sample noise is converted at the sensor's own rate).
/// `spec` is a dict overriding some keys of the derived spec, whose default
/// magnitudes are the RMS of the models' own values. `ImuModel.preset(name,
/// seed=None, sample_rate=None)` draws a grade from its spec (at 100 Hz
/// unless given); names in
/// `ImuModel.presets()`. `.spec` is a dict of one-sigma magnitudes, SI:
/// accel_/gyro_ + bias_std, scale_factor_std, misalignment_std,
/// nonlinearity_std (accel, 1/(m/s²)) or g_sensitivity_std (gyro,
/// (rad/s)/(m/s²)), noise_density (per √Hz), bias_instability,
/// bias_correlation_time (s), bias_random_walk (per √s), quantization.
#[pyclass(module = "memsnav._memsnav", name = "ImuModel", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct PyImuModel {
    pub inner: ImuModel,
}

#[catch_panics]
#[pymethods]
impl PyImuModel {
    #[new]
    #[pyo3(signature = (acc, gyr, sample_rate=None, *, spec=None))]
    fn new(
        acc: &Bound<'_, PyAccelerometerModel>,
        gyr: &Bound<'_, PyGyroscopeModel>,
        sample_rate: Option<f64>,
        spec: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let (acc, gyr) = (acc.get(), gyr.get());
        let rate = match sample_rate {
            Some(r) => {
                memsnav_core::sensors::check_sample_rate(r).py()?;
                r
            }
            None if acc.sample_rate_hz == gyr.sample_rate_hz => acc.sample_rate_hz,
            None => {
                return Err(PyValueError::new_err(format!(
                    "sample_rate: the accelerometer runs at {} Hz and the gyroscope at {} Hz; pass sample_rate= to choose the IMU's rate",
                    acc.sample_rate_hz, gyr.sample_rate_hz
                )))
            }
        };
        let mut a = acc.inner.clone();
        a.noise = noise_for_rate(a.noise, acc.sample_rate_hz, rate);
        let mut g = gyr.inner.clone();
        g.noise = noise_for_rate(g.noise, gyr.sample_rate_hz, rate);
        let mut full_spec = ImuSpec::of_models(&a, &g, rate);
        if let Some(dict) = spec {
            update_spec(&mut full_spec, dict)?;
        }
        let inner = ImuModel::with_spec(a, g, rate, full_spec).py()?;
        Ok(Self { inner })
    }

    /// A named grade, every error term drawn zero-mean Gaussian from its spec.
    ///
    /// - `name`: "paper-mems", "consumer", "industrial", "tactical" or
    ///   "navigation" (`presets()`).
    /// - `seed`: the draw's random stream, an integer in [0, 2**64) [0].
    /// - `sample_rate`: Hz [100].
    #[staticmethod]
    #[pyo3(signature = (name, seed=None, sample_rate=None))]
    fn preset(
        name: &str,
        seed: Option<&Bound<'_, PyAny>>,
        sample_rate: Option<f64>,
    ) -> PyResult<Self> {
        let sample_rate = sample_rate.unwrap_or(DEFAULT_SAMPLE_RATE_HZ);
        let mut rng = random::from_optional_seed(convert::seed(seed)?);
        let inner = ImuModel::preset_at(name, sample_rate, &mut rng).py()?;
        Ok(Self { inner })
    }

    /// The preset names `preset` accepts.
    #[staticmethod]
    fn presets() -> Vec<&'static str> {
        presets::PRESET_NAMES.to_vec()
    }

    /// Readings ``(accel m/s², gyro rad/s)``, each (N, 3), sampled at the
    /// model's `sample_rate`.
    ///
    /// - `specific_force` (N, 3) m/s² and `angular_rate` (N, 3) rad/s: the
    ///   true inputs in body axes.
    /// - `seed`: the noise's random stream, an integer in [0, 2**64) [0].
    #[pyo3(signature = (specific_force, angular_rate, seed=None))]
    fn measure<'py>(
        &self,
        py: Python<'py>,
        specific_force: &Bound<'py, PyAny>,
        angular_rate: &Bound<'py, PyAny>,
        seed: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<SeriesPair<'py>> {
        let f = convert::vectors(specific_force, "specific_force")?;
        let w = convert::vectors(angular_rate, "angular_rate")?;
        let mut rng = random::from_optional_seed(convert::seed(seed)?);
        let out = py.detach(|| self.inner.measure(&f, &w, &mut rng)).py()?;
        Ok((
            convert::vectors_to_numpy(py, &out.specific_force_b),
            convert::vectors_to_numpy(py, &out.angular_rate_b),
        ))
    }

    /// The accelerometer triad, at the IMU's sample rate.
    #[getter]
    fn accelerometer(&self) -> PyAccelerometerModel {
        PyAccelerometerModel {
            inner: self.inner.accelerometer.clone(),
            sample_rate_hz: self.inner.sample_rate_hz,
        }
    }
    /// The gyroscope triad, at the IMU's sample rate.
    #[getter]
    fn gyroscope(&self) -> PyGyroscopeModel {
        PyGyroscopeModel {
            inner: self.inner.gyroscope.clone(),
            sample_rate_hz: self.inner.sample_rate_hz,
        }
    }
    /// Sample rate of both triads, Hz.
    #[getter]
    fn sample_rate(&self) -> f64 {
        self.inner.sample_rate_hz
    }
    /// One-sigma magnitudes of every error term and the noise parameters,
    /// SI: a dict keyed `accel_…` / `gyro_…` (listed in the class doc).
    #[getter]
    fn spec<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        spec_to_dict(py, &self.inner.spec)
    }

    fn __repr__(&self) -> String {
        format!(
            "ImuModel({}, {}, sample_rate={:?})",
            self.accelerometer()?.__repr__()?,
            self.gyroscope()?.__repr__()?,
            self.inner.sample_rate_hz
        )
    }

    fn __getnewargs_ex__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyTuple>, Bound<'py, PyDict>)> {
        let args = PyTuple::new(
            py,
            [
                Bound::new(py, self.accelerometer()?)?.into_any(),
                Bound::new(py, self.gyroscope()?)?.into_any(),
            ],
        )?;
        let kwargs = PyDict::new(py);
        kwargs.set_item("sample_rate", self.inner.sample_rate_hz)?;
        kwargs.set_item("spec", spec_to_dict(py, &self.inner.spec)?)?;
        Ok((args, kwargs))
    }
}

/// An IMU spec from a data sheet, in the units data sheets use
/// (`memsnav_core::sensors::datasheet`; the `[imu_spec]` table of a
/// `navigate` configuration, whose keys `navigate_settings()["imu_spec"]`
/// lists): `datasheet` maps keys such as `gyro_arw_deg_sqrt_h`,
/// `gyro_bias_instability_deg_h` (the Allan floor F; the Gauss-Markov std
/// is F / 0.6174) with `gyro_bias_correlation_time_s`,
/// `accel_turn_on_bias_mg`, `accel_scale_factor_ppm` to values. The terms
/// it leaves out are the preset `base`'s (None: "consumer", the engine's
/// default). Returns the spec as `ImuModel.spec` holds it (SI keys), for
/// `ImuModel(..., spec=...)` and the navigation experiment's
/// `(preset, overrides)`. A bad key or value is a `ValueError` naming
/// `imu_spec.key`.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (datasheet, *, base=None))]
fn imu_spec_from_datasheet<'py>(
    py: Python<'py>,
    datasheet: &Bound<'py, PyDict>,
    base: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let base = presets::preset_spec(base.unwrap_or(presets::DEFAULT_PRESET)).map_err(|e| {
        let reason = e.to_string();
        PyValueError::new_err(format!("base: {}", reason.trim_start_matches("name: ")))
    })?;
    let mut entries = Vec::with_capacity(datasheet.len());
    for (key, value) in datasheet.iter() {
        let key: String = key.extract().map_err(|_| {
            PyValueError::new_err(format!("datasheet: keys must be strings, got {key}"))
        })?;
        let value: f64 = value
            .extract()
            .map_err(|_| PyValueError::new_err(format!("imu_spec.{key}: must be a number")))?;
        entries.push((key, value));
    }
    spec_to_dict(py, &ImuSpec::from_datasheet(&base, &entries).py()?)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(imu_spec_from_datasheet, m)?)?;
    m.add_class::<PyAccelerometerModel>()?;
    m.add_class::<PyGyroscopeModel>()?;
    m.add_class::<PyImuModel>()?;
    Ok(())
}
