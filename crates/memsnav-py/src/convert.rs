//! numpy ↔ core conversions. Every input is converted to float64 (lists and
//! integer arrays are accepted), checked for shape and finiteness, and the
//! error names the argument.

use memsnav_core::validate;
use nalgebra::{Matrix3, Vector3};
use numpy::{
    AllowTypeChange, PyArray1, PyArray2, PyArray3, PyArrayDyn, PyArrayLikeDyn, PyArrayMethods,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::IntoPyResult;

/// An array-like converted to a contiguous float64 vector, with its shape.
pub struct Floats {
    pub values: Vec<f64>,
    pub shape: Vec<usize>,
}

/// Any array-like as float64 values and shape; NaN and infinities rejected.
pub fn floats(obj: &Bound<'_, PyAny>, argument: &str) -> PyResult<Floats> {
    with_floats(obj, argument, |values, shape| Floats {
        values: values.to_vec(),
        shape: shape.to_vec(),
    })
}

/// Any array-like as float64 values in C order, with its shape, lent to
/// `read` (the array's own memory when it is C-contiguous float64, so
/// that nothing is copied twice); NaN and infinities rejected.
fn with_floats<R>(
    obj: &Bound<'_, PyAny>,
    argument: &str,
    read: impl FnOnce(&[f64], &[usize]) -> R,
) -> PyResult<R> {
    let array: PyArrayLikeDyn<f64, AllowTypeChange> = obj.extract().map_err(|_| {
        PyValueError::new_err(format!("{argument}: must be an array of real numbers"))
    })?;
    let shape = array.shape();
    let copy: Vec<f64>;
    let values = match array.as_slice() {
        Ok(values) if array.is_c_contiguous() => values,
        _ => {
            copy = array.as_array().iter().copied().collect();
            &copy
        }
    };
    validate::finite_array(argument, values, shape).py()?;
    Ok(read(values, shape))
}

/// An array of shape `(..., 3)` as vectors, with the leading shape.
pub fn vectors_nd(
    obj: &Bound<'_, PyAny>,
    argument: &str,
) -> PyResult<(Vec<Vector3<f64>>, Vec<usize>)> {
    let f = floats(obj, argument)?;
    if f.shape.last() != Some(&3) {
        return Err(PyValueError::new_err(format!(
            "{argument}: expected shape (..., 3), got {:?}",
            f.shape
        )));
    }
    let leading = f.shape[..f.shape.len() - 1].to_vec();
    Ok((to_vectors(&f.values), leading))
}

/// An `(N, 3)` array as N vectors, NaN allowed (absent values).
pub fn vectors_allow_nan(obj: &Bound<'_, PyAny>, argument: &str) -> PyResult<Vec<Vector3<f64>>> {
    let array: PyArrayLikeDyn<f64, AllowTypeChange> = obj.extract().map_err(|_| {
        PyValueError::new_err(format!("{argument}: must be an array of real numbers"))
    })?;
    let shape = array.shape().to_vec();
    if shape.len() != 2 || shape[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "{argument}: expected shape (N, 3), got {shape:?}"
        )));
    }
    let values: Vec<f64> = array.as_array().iter().copied().collect();
    if let Some(v) = values.iter().find(|v| v.is_infinite()) {
        return Err(PyValueError::new_err(format!(
            "{argument}: contains {v} (NaN marks an absent value; infinities are not allowed)"
        )));
    }
    Ok(to_vectors(&values))
}

/// An `(N, 3)` array as N vectors.
pub fn vectors(obj: &Bound<'_, PyAny>, argument: &str) -> PyResult<Vec<Vector3<f64>>> {
    with_floats(obj, argument, |values, shape| {
        if shape.len() != 2 || shape[1] != 3 {
            return Err(PyValueError::new_err(format!(
                "{argument}: expected shape (N, 3), got {shape:?}"
            )));
        }
        Ok(to_vectors(values))
    })?
}

/// A `(3,)` vector.
pub fn vector3(obj: &Bound<'_, PyAny>, argument: &str) -> PyResult<Vector3<f64>> {
    let f = floats(obj, argument)?;
    if f.shape != [3] {
        return Err(PyValueError::new_err(format!(
            "{argument}: expected shape (3,), got {:?}",
            f.shape
        )));
    }
    Ok(Vector3::from_column_slice(&f.values))
}

/// A scalar broadcast to three axes, or a `(3,)` vector.
pub fn per_axis(obj: &Bound<'_, PyAny>, argument: &str) -> PyResult<Vector3<f64>> {
    let f = floats(obj, argument)?;
    match f.shape.as_slice() {
        [] | [1] => Ok(Vector3::repeat(f.values[0])),
        [3] => Ok(Vector3::from_column_slice(&f.values)),
        s => Err(PyValueError::new_err(format!(
            "{argument}: expected a scalar or shape (3,), got {s:?}"
        ))),
    }
}

/// A `(3, 3)` matrix (row-major as numpy shows it).
pub fn matrix3(obj: &Bound<'_, PyAny>, argument: &str) -> PyResult<Matrix3<f64>> {
    let f = floats(obj, argument)?;
    if f.shape != [3, 3] {
        return Err(PyValueError::new_err(format!(
            "{argument}: expected shape (3, 3), got {:?}",
            f.shape
        )));
    }
    Ok(Matrix3::from_row_slice(&f.values))
}

/// An `(N, 3, 3)` array as N matrices.
pub fn matrices3(obj: &Bound<'_, PyAny>, argument: &str) -> PyResult<Vec<Matrix3<f64>>> {
    let f = floats(obj, argument)?;
    if f.shape.len() != 3 || f.shape[1..] != [3, 3] {
        return Err(PyValueError::new_err(format!(
            "{argument}: expected shape (N, 3, 3), got {:?}",
            f.shape
        )));
    }
    Ok(f.values
        .chunks_exact(9)
        .map(Matrix3::from_row_slice)
        .collect())
}

/// An `(N, 3, 3)` array as N matrices, NaN allowed (absent values).
pub fn matrices3_allow_nan(obj: &Bound<'_, PyAny>, argument: &str) -> PyResult<Vec<Matrix3<f64>>> {
    let array: PyArrayLikeDyn<f64, AllowTypeChange> = obj.extract().map_err(|_| {
        PyValueError::new_err(format!("{argument}: must be an array of real numbers"))
    })?;
    let shape = array.shape().to_vec();
    if shape.len() != 3 || shape[1..] != [3, 3] {
        return Err(PyValueError::new_err(format!(
            "{argument}: expected shape (N, 3, 3), got {shape:?}"
        )));
    }
    let values: Vec<f64> = array.as_array().iter().copied().collect();
    if let Some(v) = values.iter().find(|v| v.is_infinite()) {
        return Err(PyValueError::new_err(format!(
            "{argument}: contains {v} (NaN marks an absent value; infinities are not allowed)"
        )));
    }
    Ok(values
        .chunks_exact(9)
        .map(Matrix3::from_row_slice)
        .collect())
}

/// An `(N, 3)` array as N vectors, NaN allowed (the core names what a NaN
/// means for the argument).
pub fn vectors_allowing_nan(obj: &Bound<'_, PyAny>, argument: &str) -> PyResult<Vec<Vector3<f64>>> {
    let array: PyArrayLikeDyn<f64, AllowTypeChange> = obj.extract().map_err(|_| {
        PyValueError::new_err(format!("{argument}: must be an array of real numbers"))
    })?;
    if array.shape().len() != 2 || array.shape()[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "{argument}: expected shape (N, 3), got {:?}",
            array.shape()
        )));
    }
    let values: Vec<f64> = array.as_array().iter().copied().collect();
    Ok(to_vectors(&values))
}

/// A 1-D array.
pub fn scalars(obj: &Bound<'_, PyAny>, argument: &str) -> PyResult<Vec<f64>> {
    let f = floats(obj, argument)?;
    if f.shape.len() != 1 {
        return Err(PyValueError::new_err(format!(
            "{argument}: expected a 1-D array, got shape {:?}",
            f.shape
        )));
    }
    Ok(f.values)
}

/// An optional seed: `None` or an integer in `[0, 2**64)`.
pub fn seed(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<u64>> {
    match obj {
        None => Ok(None),
        Some(o) if o.is_none() => Ok(None),
        Some(o) => o.extract::<u64>().map(Some).map_err(|_| {
            PyValueError::new_err(format!(
                "seed: must be None or an integer in [0, 2**64), got {o}"
            ))
        }),
    }
}

/// What a scalar argument of type `Self` must be, in the user's words.
pub trait ScalarKind {
    const WHAT: &'static str;
}

macro_rules! scalar_kind {
    ($($t:ty => $what:expr),* $(,)?) => {
        $(impl ScalarKind for $t { const WHAT: &'static str = $what; })*
    };
}

scalar_kind! {
    f64 => "a real number",
    f32 => "a real number",
    usize => "an integer ≥ 0",
    u64 => "an integer in [0, 2**64)",
    u32 => "an integer in [0, 2**32)",
    i64 => "an integer in [-2**63, 2**63)",
    i32 => "an integer in [-2**31, 2**31)",
}

impl<T: ScalarKind> ScalarKind for Option<T> {
    const WHAT: &'static str = T::WHAT;
}

/// A scalar argument (the `#[catch_panics]` attribute reads every one
/// through here): the error names the argument and shows the value given.
/// A number of the wrong kind or range is a `ValueError`, anything else a
/// `TypeError`.
pub fn named_scalar<'py, T>(obj: &Bound<'py, PyAny>, argument: &str) -> PyResult<T>
where
    T: ScalarKind + pyo3::conversion::FromPyObjectOwned<'py>,
{
    obj.extract::<T>().map_err(|_| {
        let given = obj
            .repr()
            .map(|r| r.to_string())
            .unwrap_or_else(|_| "?".into());
        let type_name = obj
            .get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_else(|_| "?".into());
        let message = format!("{argument}: must be {}, got {given} ({type_name})", T::WHAT);
        let is_number = obj.is_instance_of::<pyo3::types::PyInt>()
            || obj.is_instance_of::<pyo3::types::PyFloat>();
        if is_number {
            PyValueError::new_err(message)
        } else {
            pyo3::exceptions::PyTypeError::new_err(message)
        }
    })
}

fn to_vectors(values: &[f64]) -> Vec<Vector3<f64>> {
    values
        .chunks_exact(3)
        .map(Vector3::from_column_slice)
        .collect()
}

/// Vectors → numpy array of shape `leading + (3,)`.
pub fn vectors_to_numpy_nd<'py>(
    py: Python<'py>,
    vectors: &[Vector3<f64>],
    leading: &[usize],
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let flat: Vec<f64> = vectors.iter().flat_map(|v| [v.x, v.y, v.z]).collect();
    let mut shape = leading.to_vec();
    shape.push(3);
    PyArray1::from_vec(py, flat).reshape(shape)
}

/// Vectors → `(N, 3)` array.
pub fn vectors_to_numpy<'py>(
    py: Python<'py>,
    vectors: &[Vector3<f64>],
) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = vectors.iter().flat_map(|v| [v.x, v.y, v.z]).collect();
    PyArray1::from_vec(py, flat)
        .reshape([vectors.len(), 3])
        .expect("length is 3 N by construction")
}

/// `Vector3` → `(3,)` array.
pub fn vector3_to_numpy<'py>(py: Python<'py>, v: &Vector3<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v.as_slice())
}

/// `Matrix3` → `(3, 3)` array (row-major).
pub fn matrix3_to_numpy<'py>(py: Python<'py>, m: &Matrix3<f64>) -> Bound<'py, PyArray2<f64>> {
    let rows: Vec<f64> = m.transpose().as_slice().to_vec();
    PyArray1::from_vec(py, rows)
        .reshape([3, 3])
        .expect("9 elements")
}

/// Matrices → `(N, 3, 3)` array.
pub fn matrices3_to_numpy<'py>(py: Python<'py>, ms: &[Matrix3<f64>]) -> Bound<'py, PyArray3<f64>> {
    let flat: Vec<f64> = ms
        .iter()
        .flat_map(|m| m.transpose().as_slice().to_vec())
        .collect();
    PyArray1::from_vec(py, flat)
        .reshape([ms.len(), 3, 3])
        .expect("length is 9 N by construction")
}
