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

/// The noise terms of a static record fitted to its Allan variance
/// (`memsnav_core::allan_fit`; IEEE Std 952-1997 annex C): white noise N
/// (unit·√s = unit/√Hz), a first-order Gauss-Markov bias instability
/// (std, unit, and correlation time, s) and a bias random walk K
/// (unit/√s), by weighted least squares over the averaging times from
/// `min_tau` (s; None: 1 s) on the Allan variance pooled over the columns
/// of `samples` (N,) or (N, k) taken at `rate_hz`. A term the record does
/// not determine (not half of the curve over a factor 3 of τ) is None and
/// raises a `UserWarning` saying why; a record too short for a factor 3 of
/// τ from `min_tau` is a `ValueError`. Returns a dict: `white_density`,
/// `bias_instability`, `bias_correlation_time`, `bias_random_walk`
/// (float or None), `taus` (T,), `adev` (T,) pooled, `model_adev` (T,) the
/// fitted curve, `min_tau` (the shortest fitted τ), `record_s`.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (samples, rate_hz, *, min_tau=None))]
fn allan_fit<'py>(
    py: Python<'py>,
    samples: &Bound<'py, PyAny>,
    rate_hz: f64,
    min_tau: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let (values, k) = columns(samples, "samples")?;
    let tau = min_tau.unwrap_or(DEFAULT_MIN_TAU_S);
    let fit = py
        .detach(|| fit_allan_terms(&values, k, rate_hz, tau, "samples"))
        .py()?;
    crate::warnings::warn_all(py, &fit.warnings)?;
    fit_to_dict(py, &fit)
}

fn fit_to_dict<'py>(py: Python<'py>, fit: &AllanTermsFit) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("white_density", fit.white_density)?;
    d.set_item("bias_instability", fit.bias_instability.map(|(s, _)| s))?;
    d.set_item(
        "bias_correlation_time",
        fit.bias_instability.map(|(_, t)| t),
    )?;
    d.set_item("bias_random_walk", fit.random_walk)?;
    d.set_item("taus", PyArray1::from_slice(py, &fit.taus_s))?;
    d.set_item("adev", PyArray1::from_slice(py, &fit.allan_deviation))?;
    d.set_item("model_adev", PyArray1::from_slice(py, &fit.model_deviation))?;
    d.set_item("min_tau", fit.min_tau_s)?;
    d.set_item("record_s", fit.record_s)?;
    Ok(d)
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
    m.add_function(wrap_pyfunction!(allan_fit, m)?)?;
    m.add_function(wrap_pyfunction!(imu_spec_from_allan, m)?)?;
    Ok(())
}
