//! Reading the user's argument objects: entries of a dict or attributes
//! of an object, strictly (an unknown dict key is an error naming the
//! closest known one), arrays that may hold NaN padding, and the errors
//! naming the argument; a `navigate` configuration's tables as the core
//! reads them. Shared by every binding that takes such objects.

use memsnav_py_macros::catch_panics;
use numpy::{AllowTypeChange, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString, PyTuple};

use memsnav_core::navigate::{SettingTables, SettingValue};

use crate::errors::IntoPyResult;

/// A float array that may hold NaN (padding), with its shape.
pub(crate) fn floats_with_nan(
    obj: &Bound<'_, PyAny>,
    argument: &str,
) -> PyResult<(Vec<f64>, Vec<usize>)> {
    let array: PyArrayLikeDyn<f64, AllowTypeChange> = obj.extract().map_err(|_| {
        PyValueError::new_err(format!("{argument}: must be an array of real numbers"))
    })?;
    Ok((
        array.as_array().iter().copied().collect(),
        array.shape().to_vec(),
    ))
}

/// `obj.name` or `obj[name]` (a dict of arrays).
pub(crate) fn field<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    argument: &str,
) -> PyResult<Bound<'py, PyAny>> {
    if let Ok(d) = obj.cast::<PyDict>() {
        return d.get_item(name)?.ok_or_else(|| {
            PyValueError::new_err(format!("{argument}: the dict has no {name:?} entry"))
        });
    }
    obj.getattr(name).map_err(|_| {
        PyValueError::new_err(format!(
            "{argument}: has no {name:?} (expected the documented class, or an object or dict with that entry)"
        ))
    })
}

pub(crate) fn optional_field<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    if let Ok(d) = obj.cast::<PyDict>() {
        return Ok(d.get_item(name)?.filter(|v| !v.is_none()));
    }
    Ok(obj.getattr(name).ok().filter(|v| !v.is_none()))
}

pub(crate) fn shape_error(argument: &str, name: &str, expected: &str, got: &[usize]) -> PyErr {
    PyValueError::new_err(format!(
        "{argument}: {name} must have shape {expected}, got {got:?}"
    ))
}

/// The error of a GNSS argument without a single epoch (checked before
/// the shapes of the other arrays, which an empty series cannot fix).
pub(crate) fn no_epochs(argument: &str) -> PyErr {
    PyValueError::new_err(format!(
        "{argument}: has no epochs (length 0); give at least one GNSS epoch"
    ))
}

/// The entries a dict argument may have: an unknown one (a misspelling
/// that would drop its data without a word) is an error naming it and the
/// closest known name. Objects other than dicts are read by attribute.
pub(crate) fn check_keys(obj: &Bound<'_, PyAny>, argument: &str, known: &[&str]) -> PyResult<()> {
    let Ok(d) = obj.cast::<PyDict>() else {
        return Ok(());
    };
    for key in d.keys() {
        let name: String = key.extract().map_err(|_| {
            PyValueError::new_err(format!(
                "{argument}: keys must be strings, got {}",
                key.repr().map_or_else(|_| "?".into(), |r| r.to_string())
            ))
        })?;
        memsnav_core::known_keys::check(argument, &name, known).py()?;
    }
    Ok(())
}

/// The name of `known` that `key` is probably a misspelling of (the core's
/// `known_keys::closest`: the one rule of every "did you mean"), or None.
#[catch_panics]
#[pyfunction]
fn closest_name(key: &str, known: Vec<String>) -> Option<String> {
    let known: Vec<&str> = known.iter().map(String::as_str).collect();
    memsnav_core::known_keys::closest(key, &known).map(str::to_string)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(closest_name, m)?)
}

/// A Python value of a settings table as a core setting.
fn setting(value: &Bound<'_, PyAny>, name: &str) -> PyResult<SettingValue> {
    if value.is_instance_of::<PyBool>() {
        return Ok(SettingValue::Bool(value.extract()?));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(SettingValue::Text(value.extract()?));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items: Vec<Bound<'_, PyAny>> = value.try_iter()?.collect::<PyResult<_>>()?;
        return Ok(SettingValue::List(
            items
                .iter()
                .map(|v| setting(v, name))
                .collect::<PyResult<_>>()?,
        ));
    }
    value
        .extract::<f64>()
        .map(SettingValue::Number)
        .map_err(|_| {
            PyValueError::new_err(format!(
                "{name}: expected a number, true/false, a string or a list, got {}",
                value.repr().map(|r| r.to_string()).unwrap_or_default()
            ))
        })
}

/// `{table: {key: value}}` → the core's tables.
pub(crate) fn settings_tables(settings: Option<&Bound<'_, PyDict>>) -> PyResult<SettingTables> {
    let Some(d) = settings else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for (table, entries) in d.iter() {
        let table: String = table
            .extract()
            .map_err(|_| PyValueError::new_err("settings: table names must be strings"))?;
        let entries = entries.cast::<PyDict>().map_err(|_| {
            PyValueError::new_err(format!("settings.{table}: must be a dict of key: value"))
        })?;
        let mut keys = Vec::new();
        for (k, v) in entries.iter() {
            let key: String = k.extract().map_err(|_| {
                PyValueError::new_err(format!("settings.{table}: keys must be strings"))
            })?;
            keys.push((key.clone(), setting(&v, &format!("{table}.{key}"))?));
        }
        out.push((table, keys));
    }
    Ok(out)
}
