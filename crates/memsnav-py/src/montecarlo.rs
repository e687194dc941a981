//! `quantile_interval` and the sequential decision levels
//! (`memsnav_core::montecarlo`). Conversions only.

use memsnav_core::montecarlo;
use memsnav_py_macros::catch_panics;
use pyo3::prelude::*;

use crate::convert;
use crate::errors::IntoPyResult;
use crate::result_record::result_record;

result_record! {
    /// An equal-tailed interval for a quantile of the distribution some
    /// runs were drawn from (`quantile_interval`).
    PyQuantileInterval as "QuantileInterval" {
        /// The largest run below the quantile at the confidence (-inf when
        /// no run bounds that side).
        lower: f64,
        /// The smallest run above it (inf when no run bounds that side: a
        /// 95th percentile of 20 runs has none).
        upper: f64,
        /// The interval's exact coverage, at least the confidence asked for.
        coverage: f64,
        /// The fewest runs that give an upper bound.
        runs_for_upper: usize,
    }
    repr(s) format!("{} to {}, coverage {:.4}", s.lower, s.upper, s.coverage)
}

/// The equal-tailed `confidence` [0.95] interval for the `p`-quantile of the
/// distribution the runs `values` (N,) were drawn from, from their order
/// statistics (distribution-free; independent runs, continuous errors):
/// a `QuantileInterval` (`lower`, `upper`, `coverage`, `runs_for_upper`).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (values, p, confidence=None))]
fn quantile_interval(
    values: &Bound<'_, PyAny>,
    p: f64,
    confidence: Option<f64>,
) -> PyResult<PyQuantileInterval> {
    let confidence = confidence.unwrap_or(montecarlo::DEFAULT_CONFIDENCE);
    let values = convert::scalars(values, "values")?;
    let i = montecarlo::quantile_interval(&values, p, confidence).py()?;
    Ok(PyQuantileInterval {
        lower: i.lower,
        upper: i.upper,
        coverage: i.coverage,
        runs_for_upper: i.runs_for_upper,
    })
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
    m.add_class::<PyQuantileInterval>()?;
    m.add_function(wrap_pyfunction!(quantile_interval, m)?)?;
    m.add_function(wrap_pyfunction!(sequential_error, m)?)?;
    m.add_function(wrap_pyfunction!(sequential_look_error, m)?)?;
    Ok(())
}
