//! A coupled filter's records (measurements, batch tests, resets,
//! integrity) as the dicts of arrays `FilterSolution` and `RunningFilter`
//! return.

use memsnav_core::coupling::{BatchRecord, Integrity, MeasurementRecord, ResetRecord};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// Resets as a dict of arrays `time`, `kind`, `change`, `unit` (of the
/// change), `failed_epochs`.
pub(crate) fn resets_to_dict<'py>(
    py: Python<'py>,
    resets: &[ResetRecord],
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item(
        "time",
        PyArray1::from_iter(py, resets.iter().map(|r| r.time_s)),
    )?;
    d.set_item(
        "kind",
        resets.iter().map(|r| r.kind.name()).collect::<Vec<_>>(),
    )?;
    d.set_item(
        "change",
        PyArray1::from_iter(py, resets.iter().map(|r| r.change)),
    )?;
    d.set_item(
        "unit",
        resets
            .iter()
            .map(|r| r.kind.change_unit())
            .collect::<Vec<_>>(),
    )?;
    d.set_item(
        "failed_epochs",
        PyArray1::from_iter(py, resets.iter().map(|r| r.failed_epochs as i64)),
    )?;
    Ok(d)
}

/// Measurement records as a dict of arrays `time`, `id`, `kind`,
/// `innovation`, `innovation_std`, `nis`, `status`.
pub(crate) fn measurements_to_dict<'py, 'r>(
    py: Python<'py>,
    records: impl Iterator<Item = &'r MeasurementRecord>,
) -> PyResult<Bound<'py, PyDict>> {
    let r: Vec<&MeasurementRecord> = records.collect();
    let d = PyDict::new(py);
    d.set_item("time", PyArray1::from_iter(py, r.iter().map(|m| m.time_s)))?;
    d.set_item("id", PyArray1::from_iter(py, r.iter().map(|m| m.id as i64)))?;
    d.set_item("kind", r.iter().map(|m| m.kind.name()).collect::<Vec<_>>())?;
    d.set_item(
        "innovation",
        PyArray1::from_iter(py, r.iter().map(|m| m.innovation)),
    )?;
    d.set_item(
        "innovation_std",
        PyArray1::from_iter(py, r.iter().map(|m| m.innovation_std)),
    )?;
    d.set_item("nis", PyArray1::from_iter(py, r.iter().map(|m| m.nis)))?;
    d.set_item(
        "status",
        r.iter().map(|m| m.status.name()).collect::<Vec<_>>(),
    )?;
    Ok(d)
}

/// Batch tests as a dict of arrays `time`, `kind`, `nis`, `dof`,
/// `threshold`, `excluded`, `accepted`, `nonlinearity`.
pub(crate) fn batches_to_dict<'py>(
    py: Python<'py>,
    b: &[BatchRecord],
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("time", PyArray1::from_iter(py, b.iter().map(|r| r.time_s)))?;
    d.set_item("kind", b.iter().map(|r| r.kind.name()).collect::<Vec<_>>())?;
    d.set_item("nis", PyArray1::from_iter(py, b.iter().map(|r| r.nis)))?;
    d.set_item(
        "dof",
        PyArray1::from_iter(py, b.iter().map(|r| r.dof as i64)),
    )?;
    d.set_item(
        "threshold",
        PyArray1::from_iter(py, b.iter().map(|r| r.threshold)),
    )?;
    d.set_item(
        "excluded",
        PyArray1::from_iter(py, b.iter().map(|r| r.excluded as i64)),
    )?;
    d.set_item(
        "accepted",
        PyArray1::from_iter(py, b.iter().map(|r| r.accepted)),
    )?;
    d.set_item(
        "nonlinearity",
        PyArray1::from_iter(py, b.iter().map(|r| r.nonlinearity)),
    )?;
    Ok(d)
}

/// A run's integrity as a dict (see `PyFilterSolution::integrity`).
pub(crate) fn integrity_to_dict<'py>(
    py: Python<'py>,
    integrity: &Integrity,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("diverged", integrity.diverged())?;
    let alerts = PyList::empty(py);
    for a in &integrity.alerts {
        let item = PyDict::new(py);
        item.set_item("kind", a.name())?;
        item.set_item("time_s", a.time_s())?;
        item.set_item("message", a.message())?;
        alerts.append(item)?;
    }
    d.set_item("alerts", alerts)?;
    let consistency = PyList::empty(py);
    for c in &integrity.consistency {
        let item = PyDict::new(py);
        item.set_item("kind", c.kind.name())?;
        item.set_item("windows", c.windows)?;
        item.set_item("windows_above_band", c.above_band)?;
        item.set_item("max_band_ratio", c.max_band_ratio)?;
        item.set_item("max_at_s", c.max_at_s)?;
        consistency.append(item)?;
    }
    d.set_item("consistency", consistency)?;
    Ok(d)
}
