//! What aids a coupled filter, read from the user's Python objects: GNSS
//! epochs (a `GnssMeasurements` or padded arrays) and position fixes (a
//! `PositionFixes`, a `FixSeries` or arrays), with the `PositionFixes`
//! class itself. Shared by the filter classes (`coupling`) and
//! `navigate_log` (`log_navigation`).

use std::borrow::Cow;

use memsnav_core::coupling::PositionFix;
use memsnav_core::gnss::{self, GnssEpoch, SatelliteMeasurement};
use memsnav_py_macros::catch_panics;
use nalgebra::{Matrix3, Vector3};
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert;
use crate::errors::IntoPyResult;
use crate::gnss::{PyFixSeries, PyGnssMeasurements};

/// Position (and velocity) fixes of an antenna, ready for
/// `navigate_log` or `LooselyCoupledFilter.run`.
#[pyclass(name = "PositionFixes", module = "memsnav._memsnav", frozen)]
pub struct PyPositionFixes {
    pub(crate) fixes: Vec<PositionFix>,
}

#[catch_panics]
#[pymethods]
impl PyPositionFixes {
    /// Fix times, s, (T,).
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_iter(py, self.fixes.iter().map(|f| f.time_s))
    }
    /// Antenna positions, ECEF m, (T, 3).
    #[getter]
    fn position_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let v: Vec<Vector3<f64>> = self.fixes.iter().map(|f| f.position_ecef).collect();
        convert::vectors_to_numpy(py, &v)
    }
    /// Their covariances, m², (T, 3, 3).
    #[getter]
    fn position_covariance<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray3<f64>> {
        let m: Vec<Matrix3<f64>> = self.fixes.iter().map(|f| f.position_covariance).collect();
        convert::matrices3_to_numpy(py, &m)
    }
    /// Antenna velocities, ECEF m/s, (T, 3); NaN where a fix has none.
    #[getter]
    fn velocity_ecef<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let v: Vec<Vector3<f64>> = self
            .fixes
            .iter()
            .map(|f| f.velocity_ecef.unwrap_or(Vector3::from_element(f64::NAN)))
            .collect();
        convert::vectors_to_numpy(py, &v)
    }
    fn __len__(&self) -> usize {
        self.fixes.len()
    }
}

/// A float array that may hold NaN (padding), with its shape.
fn floats_with_nan(obj: &Bound<'_, PyAny>, argument: &str) -> PyResult<(Vec<f64>, Vec<usize>)> {
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

fn shape_error(argument: &str, name: &str, expected: &str, got: &[usize]) -> PyErr {
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

/// Whether `obj` holds pseudoranges (a `GnssMeasurements`, or arrays with
/// a `sat_id`) rather than position fixes.
pub(crate) fn is_measurements(obj: &Bound<'_, PyAny>) -> bool {
    obj.cast::<PyGnssMeasurements>().is_ok()
        || optional_field(obj, "sat_id").is_ok_and(|v| v.is_some())
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

/// The entries of padded GNSS arrays (a dict, or an object's attributes).
pub(crate) const GNSS_KEYS: [&str; 8] = [
    "time",
    "sat_id",
    "satellite_position_ecef",
    "satellite_velocity_ecef",
    "pseudorange",
    "pseudorange_std",
    "pseudorange_rate",
    "pseudorange_rate_std",
];

/// GNSS epochs from a `GnssMeasurements` or padded user arrays (a dict,
/// no other keys, or an object with these attributes): `time` (T,),
/// `sat_id` (T, n) (negative = padding), `satellite_position_ecef` and
/// `satellite_velocity_ecef` (T, n, 3), `pseudorange` (T, n),
/// `pseudorange_std` (T, n), optional `pseudorange_rate` with
/// `pseudorange_rate_std` (T, n). Every slot that is not padding passes the
/// core's `check_measurement` (NaN only for a rate: no rate there); the
/// one converter of every entry point that takes GNSS measurements.
/// A `GnssMeasurements` is lent, not copied: it is frozen (immutable), and
/// `obj` keeps it alive while the epochs are in use.
pub(crate) fn gnss_epochs<'a>(obj: &'a Bound<'_, PyAny>) -> PyResult<Cow<'a, [GnssEpoch]>> {
    const ARG: &str = "gnss";
    if let Ok(m) = obj.cast::<PyGnssMeasurements>() {
        if m.get().epochs.is_empty() {
            return Err(no_epochs(ARG));
        }
        return Ok(Cow::Borrowed(&m.get().epochs));
    }
    check_keys(obj, ARG, &GNSS_KEYS)?;
    let time = convert::scalars(&field(obj, "time", ARG)?, "gnss.time")?;
    let t = time.len();
    if t == 0 {
        return Err(no_epochs("gnss.time"));
    }
    memsnav_core::validate::increasing_times("gnss.time", &time).py()?;
    let (sat_id, s) = floats_with_nan(&field(obj, "sat_id", ARG)?, "gnss.sat_id")?;
    if s.len() != 2 || s[0] != t {
        return Err(shape_error(ARG, "sat_id", "(T, n)", &s));
    }
    let n = s[1];
    let get2 = |name: &str| -> PyResult<Vec<f64>> {
        let (v, s) = floats_with_nan(&field(obj, name, ARG)?, &format!("gnss.{name}"))?;
        if s != [t, n] {
            return Err(shape_error(ARG, name, &format!("({t}, {n})"), &s));
        }
        Ok(v)
    };
    let get3 = |name: &str| -> PyResult<Vec<f64>> {
        let (v, s) = floats_with_nan(&field(obj, name, ARG)?, &format!("gnss.{name}"))?;
        if s != [t, n, 3] {
            return Err(shape_error(ARG, name, &format!("({t}, {n}, 3)"), &s));
        }
        Ok(v)
    };
    let pos = get3("satellite_position_ecef")?;
    let vel = get3("satellite_velocity_ecef")?;
    let rho = get2("pseudorange")?;
    let rho_std = get2("pseudorange_std")?;
    let (rate, rate_std) =
        match (
            optional_field(obj, "pseudorange_rate")?,
            optional_field(obj, "pseudorange_rate_std")?,
        ) {
            (Some(_), _) => (get2("pseudorange_rate")?, get2("pseudorange_rate_std")?),
            (None, Some(_)) => return Err(PyValueError::new_err(
                "gnss: pseudorange_rate_std given without pseudorange_rate (give both, or neither)",
            )),
            (None, None) => (vec![f64::NAN; t * n], vec![f64::NAN; t * n]),
        };
    let mut slots = Vec::with_capacity(t * n);
    let mut rows = Vec::with_capacity(t * n);
    let mut epochs = Vec::with_capacity(t);
    for (k, &time_s) in time.iter().enumerate() {
        // An epoch without satellites (a total outage) is kept.
        epochs.push(GnssEpoch {
            time_s,
            measurements: Vec::new(),
        });
        for j in 0..n {
            let i = k * n + j;
            let id = sat_id[i];
            if id < 0.0 {
                continue; // padding
            }
            let slot_error = |reason: String| {
                PyValueError::new_err(format!("gnss: [{k}, {j}] (time {time_s} s): {reason}"))
            };
            let sat_id = gnss::sat_id(id).map_err(|e| {
                slot_error(format!("{e}; mark an empty slot with a negative number"))
            })?;
            slots.push((k, j));
            rows.push((
                time_s,
                SatelliteMeasurement {
                    sat_id,
                    position_ecef: Vector3::from_column_slice(&pos[3 * i..3 * i + 3]),
                    velocity_ecef: Vector3::from_column_slice(&vel[3 * i..3 * i + 3]),
                    pseudorange_m: rho[i],
                    pseudorange_rate_m_s: rate[i],
                    pseudorange_std_m: rho_std[i],
                    pseudorange_rate_std_m_s: rate_std[i],
                },
            ));
        }
    }
    let grouped = gnss::epochs_from_rows(rows).map_err(|(row, reason)| {
        let (k, j) = slots[row];
        PyValueError::new_err(format!("gnss: [{k}, {j}] (time {} s): {reason}", time[k]))
    })?;
    // The rows' epochs in time order, placed back among the empty ones.
    for e in grouped {
        let k = time
            .iter()
            .position(|&t| t == e.time_s)
            .expect("a row's own time");
        epochs[k].measurements = e.measurements;
    }
    Ok(Cow::Owned(epochs))
}

/// The entries of position-fix arrays.
const FIX_KEYS: [&str; 5] = [
    "time",
    "position_ecef",
    "position_covariance",
    "velocity_ecef",
    "velocity_covariance",
];

/// Position fixes from a `FixSeries` (invalid epochs skipped; covariances
/// the position and velocity blocks of the LS covariance) or user arrays:
/// `time` (T,), `position_ecef` (T, 3), `position_covariance` (T, 3, 3),
/// optional `velocity_ecef` (T, 3) and `velocity_covariance` (T, 3, 3).
pub(crate) fn position_fixes(obj: &Bound<'_, PyAny>) -> PyResult<Vec<PositionFix>> {
    const ARG: &str = "fixes";
    if let Ok(f) = obj.cast::<PyPositionFixes>() {
        if f.get().fixes.is_empty() {
            return Err(no_epochs(ARG));
        }
        return Ok(f.get().fixes.clone());
    }
    if let Ok(f) = obj.cast::<PyFixSeries>() {
        if f.get().fixes.is_empty() {
            return Err(no_epochs(ARG));
        }
        return Ok(f
            .get()
            .fixes
            .iter()
            .flatten()
            .map(|x| PositionFix {
                time_s: x.time_s,
                position_ecef: x.position_ecef,
                position_covariance: x.position_clock_covariance.fixed_view::<3, 3>(0, 0).into(),
                velocity_ecef: Some(x.velocity_ecef),
                velocity_covariance: x.velocity_drift_covariance.fixed_view::<3, 3>(0, 0).into(),
            })
            .collect());
    }
    check_keys(obj, ARG, &FIX_KEYS)?;
    let time = convert::scalars(&field(obj, "time", ARG)?, "fixes.time")?;
    let t = time.len();
    if t == 0 {
        return Err(no_epochs("fixes.time"));
    }
    let position = convert::vectors(&field(obj, "position_ecef", ARG)?, "fixes.position_ecef")?;
    let pcov = convert::matrices3(
        &field(obj, "position_covariance", ARG)?,
        "fixes.position_covariance",
    )?;
    let velocity = optional_field(obj, "velocity_ecef")?
        .map(|v| convert::vectors(&v, "fixes.velocity_ecef"))
        .transpose()?;
    if velocity.is_none() && optional_field(obj, "velocity_covariance")?.is_some() {
        return Err(PyValueError::new_err(
            "fixes: velocity_covariance given without velocity_ecef (give both, or neither)",
        ));
    }
    let vcov = match &velocity {
        Some(_) => Some(convert::matrices3(
            &field(obj, "velocity_covariance", ARG)?,
            "fixes.velocity_covariance",
        )?),
        None => None,
    };
    for (name, len) in [
        ("position_ecef", position.len()),
        ("position_covariance", pcov.len()),
        ("velocity_ecef", velocity.as_ref().map_or(t, Vec::len)),
        ("velocity_covariance", vcov.as_ref().map_or(t, Vec::len)),
    ] {
        if len != t {
            return Err(PyValueError::new_err(format!(
                "fixes: {name} has {len} rows but time has {t}"
            )));
        }
    }
    Ok((0..t)
        .map(|k| PositionFix {
            time_s: time[k],
            position_ecef: position[k],
            position_covariance: pcov[k],
            velocity_ecef: velocity.as_ref().map(|v| v[k]),
            velocity_covariance: vcov.as_ref().map_or(Matrix3::zeros(), |v| v[k]),
        })
        .collect())
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyPositionFixes>()?;
    Ok(())
}
