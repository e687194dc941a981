//! `quantile_interval` and the sequential decision levels
//! (`memsnav_core::montecarlo`). Conversions only.

use memsnav_core::montecarlo;
use memsnav_py_macros::catch_panics;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert;
use crate::errors::IntoPyResult;

/// The equal-tailed `confidence` [0.95] interval for the `p`-quantile of the
/// distribution the runs `values` (N,) were drawn from, from their order
/// statistics (distribution-free; independent runs, continuous errors):
/// dict `lower`, `upper` (-inf / inf when no run bounds that side at the
/// confidence: a 95th percentile of 20 runs has no upper bound),
/// `coverage` (the interval's exact coverage, at least `confidence`),
/// `runs_for_upper` (the fewest runs that give an upper bound).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (values, p, confidence=None))]
fn quantile_interval<'py>(
    py: Python<'py>,
    values: &Bound<'py, PyAny>,
    p: f64,
    confidence: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let confidence = confidence.unwrap_or(montecarlo::DEFAULT_CONFIDENCE);
    let values = convert::scalars(values, "values")?;
    let i = montecarlo::quantile_interval(&values, p, confidence).py()?;
    let d = PyDict::new(py);
    d.set_item("lower", i.lower)?;
    d.set_item("upper", i.upper)?;
    d.set_item("coverage", i.coverage)?;
    d.set_item("runs_for_upper", i.runs_for_upper)?;
    Ok(d)
}

/// The probability that a cell decided in looks after `looks` runs
/// (cumulative, increasing) wrongly decides at some look, when its
/// `p`-quantile sits at the requirement and each look's one-sided bounds
/// err with probability `look_error`: `(meets, fails)`. Exact (the
/// binomial count of runs at or below the requirement, carried from look
/// to look; a decision stops the cell).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (looks, p, look_error))]
fn sequential_error(looks: Vec<usize>, p: f64, look_error: f64) -> PyResult<(f64, f64)> {
    montecarlo::sequential_error(&looks, p, look_error).py()
}

/// The largest per-look one-sided error at which a cell decided in
/// `looks` errs, on either side, with probability at most
/// `1 - confidence` (`confidence` [0.95]; exact, see `sequential_error`): never below
/// Bonferroni's `(1 - confidence) / len(looks)`.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (looks, p, confidence=None))]
fn sequential_look_error(looks: Vec<usize>, p: f64, confidence: Option<f64>) -> PyResult<f64> {
    let confidence = confidence.unwrap_or(montecarlo::DEFAULT_CONFIDENCE);
    montecarlo::sequential_look_error(&looks, p, confidence).py()
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(quantile_interval, m)?)?;
    m.add_function(wrap_pyfunction!(sequential_error, m)?)?;
    m.add_function(wrap_pyfunction!(sequential_look_error, m)?)?;
    Ok(())
}
