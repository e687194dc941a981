//! Position fixes that aid a loosely coupled filter, read from the user's
//! Python objects (a `PositionFixes`, a `FixSeries` or arrays), with the
//! `PositionFixes` class itself. Shared by the filter classes (`coupling`)
//! and `navigate_log` (`log_navigation`); GNSS measurements are read by
//! `gnss::gnss_epochs`.

use memsnav_core::coupling::PositionFix;
use memsnav_py_macros::catch_panics;
use nalgebra::{Matrix3, Vector3};
use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arguments::{check_keys, field, no_epochs, optional_field};
use crate::convert;
use crate::gnss::PyFixSeries;

/// Position (and velocity) fixes of an antenna, ready for
/// `navigate_log` or `LooselyCoupledFilter.run`.
#[pyclass(name = "PositionFixes", module = "memsnav._memsnav", frozen)]
pub struct PyPositionFixes {
    pub(crate) fixes: Vec<PositionFix>,
}

#[catch_panics]
#[pymethods]
impl PyPositionFixes {
    fn __repr__(&self) -> String {
        let with_velocity = self
            .fixes
            .iter()
            .filter(|f| f.velocity_ecef.is_some())
            .count();
        match (self.fixes.first(), self.fixes.last()) {
            (Some(a), Some(b)) => format!(
                "PositionFixes({} fixes, {:.3}-{:.3} s, {with_velocity} with velocity)",
                self.fixes.len(),
                a.time_s,
                b.time_s
            ),
            _ => "PositionFixes(no fix)".to_string(),
        }
    }

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
    /// Whether each fix's velocity is horizontal only (a speed and course
    /// over ground: NMEA; the filter takes its north and east components
    /// and nothing along the vertical), (T,).
    #[getter]
    fn velocity_horizontal_only<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        PyArray1::from_iter(py, self.fixes.iter().map(|f| f.velocity_horizontal_only))
    }
    fn __len__(&self) -> usize {
        self.fixes.len()
    }
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
                velocity_horizontal_only: false,
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
            velocity_horizontal_only: false,
        })
        .collect())
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyPositionFixes>()?;
    Ok(())
}
