//! A coupled filter's records (measurements, batch tests, resets,
//! integrity) as `FilterSolution` and `RunningFilter` return them: dicts of
//! arrays for the tables, records for the integrity.

use memsnav_core::coupling::{BatchRecord, Integrity, MeasurementRecord, ResetRecord};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::result_record::result_record;

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

result_record! {
    /// An integrity alert: the solution cannot be trusted from `time_s` on.
    PyIntegrityAlert as "IntegrityAlert" {
        /// "gated_batches", "inconsistent_innovations", "beyond_linear_model"
        /// or "applied_outliers".
        kind: String,
        /// When, GNSS time, s.
        time_s: f64,
        /// What happened, in words.
        message: String,
    }
    repr(s) format!("{} at {:.3} s", s.kind, s.time_s)
}

result_record! {
    /// The consistency of one kind of GNSS measurement over 30 s windows.
    PyConsistency as "Consistency" {
        /// The measurement kind ("pseudorange", ...).
        kind: String,
        /// Windows of 30 s.
        windows: usize,
        /// Windows whose summed NIS exceeded the 0.9999 chi-square quantile.
        windows_above_band: usize,
        /// The largest summed NIS over that quantile.
        max_band_ratio: f64,
        /// Its window's start, s.
        max_at_s: f64,
    }
    repr(s) format!("{}: {} of {} windows above the band", s.kind, s.windows_above_band, s.windows)
}

result_record! {
    /// Whether a solution can be trusted (`FilterSolution.integrity`).
    PyIntegrity as "Integrity" {
        /// Whether any alert was raised.
        diverged: bool,
        /// The alerts, in time order.
        alerts: Vec<Py<PyIntegrityAlert>>,
        /// Per GNSS kind, the windows' consistency.
        consistency: Vec<Py<PyConsistency>>,
    }
    repr(s) format!(
        "{}, {} alerts",
        if s.diverged { "diverged" } else { "trusted" },
        s.alerts.len()
    )
}

/// A solution's integrity as its record.
pub(crate) fn integrity_record(py: Python<'_>, integrity: &Integrity) -> PyResult<PyIntegrity> {
    let alerts = integrity
        .alerts
        .iter()
        .map(|a| {
            Py::new(
                py,
                PyIntegrityAlert {
                    kind: a.name().to_string(),
                    time_s: a.time_s(),
                    message: a.message(),
                },
            )
        })
        .collect::<PyResult<_>>()?;
    let consistency = integrity
        .consistency
        .iter()
        .map(|c| {
            Py::new(
                py,
                PyConsistency {
                    kind: c.kind.name().to_string(),
                    windows: c.windows,
                    windows_above_band: c.above_band,
                    max_band_ratio: c.max_band_ratio,
                    max_at_s: c.max_at_s,
                },
            )
        })
        .collect::<PyResult<_>>()?;
    Ok(PyIntegrity {
        diverged: integrity.diverged(),
        alerts,
        consistency,
    })
}
