//! `allan_deviation` (`memsnav_core::allan`), `allan_fit` and
//! `imu_spec_from_allan` (`memsnav_core::allan_fit`). Conversions only.

use memsnav_core::allan::{cluster_sizes, default_cluster_sizes, overlapping_allan_deviation};
use memsnav_core::allan_fit::{fit_allan_terms, AllanTermsFit, ImuAllanFit, DEFAULT_MIN_TAU_S};
use memsnav_py_macros::catch_panics;
use numpy::{PyArray1, PyArrayDyn, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert;
use crate::errors::IntoPyResult;
use crate::result_record::result_record;

/// The averaging times (T,), s, and the deviations (T,) or (T, k).
type TausAndDeviation<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArrayDyn<f64>>);

/// Overlapping Allan deviation (IEEE Std 952-1997 annex C; Riley, NIST SP
/// 1065, eq. 11) of `samples` (N,) or (N, k) taken at `rate_hz`, at the
/// averaging times `taus` (s; each rounded to whole samples, between one
/// sample and half the record) or, when None, at 40 log-spaced cluster
/// sizes from one sample to a ninth of the record. Returns `(taus, adev)`,
/// adev of shape (len(taus),) or (len(taus), k) in the samples' unit.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (samples, rate_hz, taus=None))]
fn allan_deviation<'py>(
    py: Python<'py>,
    samples: &Bound<'py, PyAny>,
    rate_hz: f64,
    taus: Option<&Bound<'py, PyAny>>,
) -> PyResult<TausAndDeviation<'py>> {
    let x = convert::floats(samples, "samples")?;
    let (n, columns) = match x.shape[..] {
        [n] => (n, 1),
        [n, k] => (n, k),
        _ => {
            return Err(PyValueError::new_err(format!(
                "samples: expected a (N,) or (N, k) array, got shape {:?}",
                x.shape
            )))
        }
    };
    memsnav_core::validate::positive("rate_hz", rate_hz).py()?;
    let clusters = match taus {
        None => default_cluster_sizes(n),
        Some(t) => cluster_sizes(&convert::scalars(t, "taus")?, rate_hz, n).py()?,
    };
    let adev = py
        .detach(|| overlapping_allan_deviation(&x.values, columns, rate_hz, &clusters))
        .py()?;
    let taus_s: Vec<f64> = clusters.iter().map(|&m| m as f64 / rate_hz).collect();
    let mut shape = vec![clusters.len()];
    shape.extend(x.shape.get(1));
    let adev = PyArray1::from_vec(py, adev)
        .reshape(shape)
        .expect("clusters × columns elements");
    Ok((PyArray1::from_vec(py, taus_s), adev))
}

/// A (N,) or (N, k) array as its row-major values and k.
fn columns(samples: &Bound<'_, PyAny>, argument: &str) -> PyResult<(Vec<f64>, usize)> {
    let x = convert::floats(samples, argument)?;
    match x.shape[..] {
        [_] => Ok((x.values, 1)),
        [_, k] => Ok((x.values, k)),
        _ => Err(PyValueError::new_err(format!(
            "{argument}: expected a (N,) or (N, k) array, got shape {:?}",
            x.shape
        ))),
    }
}

result_record! {
    /// The noise terms of a static record fitted to its Allan variance
    /// (`allan_fit`), in the samples' unit; a term the record does not
    /// determine is None.
    PyAllanFit as "AllanFit" {
        /// White noise N, unit·√s (= unit/√Hz).
        white_density: Option<f64>,
        /// First-order Gauss-Markov bias instability: its std, unit.
        bias_instability: Option<f64>,
        /// Its correlation time, s.
        bias_correlation_time: Option<f64>,
        /// Bias random walk K, unit/√s.
        bias_random_walk: Option<f64>,
        /// The averaging times fitted, s, (T,).
        taus: Py<PyArray1<f64>>,
        /// The Allan deviation pooled over the columns, (T,).
        adev: Py<PyArray1<f64>>,
        /// The fitted model's deviation, (T,).
        model_adev: Py<PyArray1<f64>>,
        /// The shortest averaging time fitted, s.
        min_tau: f64,
        /// The record's length, s.
        record_s: f64,
    }
    repr(s) format!(
        "N {}, B {}, K {}; {:.0} s",
        term(s.white_density),
        term(s.bias_instability),
        term(s.bias_random_walk),
        s.record_s
    )
}

/// A fitted term for a repr: 3 significant digits, or "-" when the record
/// did not determine it.
fn term(value: Option<f64>) -> String {
    value.map_or_else(|| "-".to_string(), |v| format!("{v:.3e}"))
}

/// The noise terms of a static record fitted to its Allan variance
/// (`memsnav_core::allan_fit`; IEEE Std 952-1997 annex C): white noise N
/// (unit·√s = unit/√Hz), a first-order Gauss-Markov bias instability
/// (std, unit, and correlation time, s) and a bias random walk K
/// (unit/√s), by weighted least squares over the averaging times from
/// `min_tau` (s; None: 1 s) on the Allan variance pooled over the columns
/// of `samples` (N,) or (N, k) taken at `rate_hz`. A term the record does
/// not determine (not half of the curve over a factor 3 of τ) is None and
/// raises a `UserWarning` saying why; a record too short for a factor 3 of
/// τ from `min_tau` is a `ValueError`. Returns an `AllanFit`:
/// `white_density`, `bias_instability`, `bias_correlation_time`,
/// `bias_random_walk` (float or None), `taus` (T,), `adev` (T,) pooled,
/// `model_adev` (T,) the fitted curve, `min_tau` (the shortest fitted τ),
/// `record_s`.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (samples, rate_hz, *, min_tau=None))]
fn allan_fit(
    py: Python<'_>,
    samples: &Bound<'_, PyAny>,
    rate_hz: f64,
    min_tau: Option<f64>,
) -> PyResult<PyAllanFit> {
    let (values, k) = columns(samples, "samples")?;
    let tau = min_tau.unwrap_or(DEFAULT_MIN_TAU_S);
    let fit = py
        .detach(|| fit_allan_terms(&values, k, rate_hz, tau, "samples"))
        .py()?;
    crate::warnings::warn_all(py, &fit.warnings)?;
    Ok(allan_fit_record(py, &fit))
}

fn allan_fit_record(py: Python<'_>, fit: &AllanTermsFit) -> PyAllanFit {
    PyAllanFit {
        white_density: fit.white_density,
        bias_instability: fit.bias_instability.map(|(s, _)| s),
        bias_correlation_time: fit.bias_instability.map(|(_, t)| t),
        bias_random_walk: fit.random_walk,
        taus: PyArray1::from_slice(py, &fit.taus_s).unbind(),
        adev: PyArray1::from_slice(py, &fit.allan_deviation).unbind(),
        model_adev: PyArray1::from_slice(py, &fit.model_deviation).unbind(),
        min_tau: fit.min_tau_s,
        record_s: fit.record_s,
    }
}

/// The `[imu_spec]` entries (data-sheet keys, their units) of the noise
/// terms a static IMU record determines: `allan_fit` of the specific force
/// (N, 3) m/s² and of the angular rate (N, 3) rad/s taken at `rate_hz`,
/// from `min_tau` (None: 1 s). A Gauss-Markov bias comes as
/// `*_bias_markov_std_*` and `*_bias_correlation_time_s`; a term left out
/// is absent and raises a `UserWarning` naming its triad and why. Put the
/// entries in a configuration's `[imu_spec]` table (or
/// `navigate_log(settings={"imu_spec": ...})`): the terms they do not give
/// keep the preset's.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (specific_force, angular_rate, rate_hz, *, min_tau=None))]
fn imu_spec_from_allan<'py>(
    py: Python<'py>,
    specific_force: &Bound<'py, PyAny>,
    angular_rate: &Bound<'py, PyAny>,
    rate_hz: f64,
    min_tau: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let f = convert::vectors(specific_force, "specific_force")?;
    let w = convert::vectors(angular_rate, "angular_rate")?;
    let flat = |v: &[nalgebra::Vector3<f64>]| -> Vec<f64> {
        v.iter().flat_map(|x| [x.x, x.y, x.z]).collect()
    };
    let (f, w) = (flat(&f), flat(&w));
    let tau = min_tau.unwrap_or(DEFAULT_MIN_TAU_S);
    let fit = py.detach(|| ImuAllanFit::new(&f, &w, rate_hz, tau)).py()?;
    crate::warnings::warn_all(py, &fit.warnings())?;
    let d = PyDict::new(py);
    for (key, value) in fit.datasheet() {
        d.set_item(key, value)?;
    }
    Ok(d)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(allan_deviation, m)?)?;
    m.add_class::<PyAllanFit>()?;
    m.add_function(wrap_pyfunction!(allan_fit, m)?)?;
    m.add_function(wrap_pyfunction!(imu_spec_from_allan, m)?)?;
    Ok(())
}
