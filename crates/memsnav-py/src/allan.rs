//! `allan_deviation` (`memsnav_core::allan`). Conversions only.

use memsnav_core::allan::{cluster_sizes, default_cluster_sizes, overlapping_allan_deviation};
use memsnav_py_macros::catch_panics;
use numpy::{PyArray1, PyArrayDyn, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

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

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(allan_deviation, m)?)?;
    Ok(())
}
