//! `navigation_experiment`: the navigation Monte Carlo of memsnav-core
//! (paper §5.3) in one call, through [`run_interruptible`]: Ctrl-C cancels
//! the remaining runs and returns the completed ones.

use memsnav_core::experiments::navigation::{
    ImuOutcome, NavigationExperiment, NavigationExperimentConfig, NavigationImu, NavigationRuns,
};
use memsnav_core::gnss::{Outage, SimulationConfig};
use memsnav_core::sensors::presets;
use memsnav_py_macros::catch_panics;
use nalgebra::Vector3;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};

use crate::errors::IntoPyResult;
use crate::progress::{run_monte_carlo, Ran};
use crate::sensors::{update_spec, PyImuModel};

/// `(name, source)` pairs: a preset name, `(preset name, spec overrides)`,
/// `"calibrated:<raw name>"` or an `ImuModel`.
pub(crate) fn imu_list(imus: &Bound<'_, PyAny>) -> PyResult<Vec<(String, NavigationImu)>> {
    let pairs: Vec<(String, Bound<'_, PyAny>)> = imus
        .extract()
        .map_err(|_| PyValueError::new_err("imus: expected a list of (name, source) pairs"))?;
    let names: Vec<String> = pairs.iter().map(|(n, _)| n.clone()).collect();
    pairs
        .iter()
        .map(|(name, source)| {
            if let Ok(model) = source.cast::<PyImuModel>() {
                return Ok((
                    name.clone(),
                    NavigationImu::Fixed(Box::new(model.get().inner.clone())),
                ));
            }
            if let Ok((preset, overrides)) = source.extract::<(String, Bound<'_, PyDict>)>() {
                // A preset's spec with some terms changed, drawn per run
                // (and the filter tuned from it), e.g. a MEMS without
                // misalignment for an error budget.
                let mut spec = presets::preset_spec(&preset)
                    .map_err(|e| PyValueError::new_err(format!("imus: {name:?}: {e}")))?;
                update_spec(&mut spec, &overrides).map_err(|e| {
                    PyValueError::new_err(format!("imus: {name:?}: {}", e.value(imus.py())))
                })?;
                return Ok((name.clone(), NavigationImu::Drawn(spec)));
            }
            let text: String = source.extract().map_err(|_| {
                PyValueError::new_err(format!(
                    "imus: {name:?} must be an ImuModel, a preset name, (preset name, spec dict) or ('calibrated', source)"
                ))
            })?;
            if let Some(raw) = text.strip_prefix("calibrated:") {
                let source = names.iter().position(|n| n == raw).ok_or_else(|| {
                    PyValueError::new_err(format!(
                        "imus: {name:?} is calibrated from {raw:?}, which is not in the set"
                    ))
                })?;
                return Ok((name.clone(), NavigationImu::Calibrated { source }));
            }
            let spec = presets::preset_spec(&text)
                .map_err(|e| PyValueError::new_err(format!("imus: {name:?}: {e}")))?;
            Ok((name.clone(), NavigationImu::Drawn(spec)))
        })
        .collect()
}

fn rows<'py>(py: Python<'py>, rows: &[Vec<f64>], cols: usize) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([rows.len(), cols])?
        .into_any())
}

fn to_dict<'py>(
    py: Python<'py>,
    r: &NavigationExperiment,
    interrupted: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("time", PyArray1::from_slice(py, &r.time_s))?;
    d.set_item("completed_runs", r.completed_runs)?;
    d.set_item("interrupted", interrupted || r.cancelled)?;
    d.set_item("imus", imu_outcomes(py, &r.imus, r.time_s.len())?)?;
    Ok(d)
}

/// One dict per IMU outcome (the keys of `memsnav.experiments.navigation`).
pub(crate) fn imu_outcomes<'py>(
    py: Python<'py>,
    outcomes: &[ImuOutcome],
    epochs: usize,
) -> PyResult<Bound<'py, PyList>> {
    let imus = PyList::empty(py);
    for o in outcomes {
        imus.append(imu_outcome(py, o, epochs)?)?;
    }
    Ok(imus)
}

/// One IMU outcome as a dict; `smoothed`: the same dict of the smoothed
/// solution, or None.
fn imu_outcome<'py>(
    py: Python<'py>,
    o: &ImuOutcome,
    epochs: usize,
) -> PyResult<Bound<'py, PyDict>> {
    {
        let e = PyDict::new(py);
        e.set_item("name", &o.name)?;
        e.set_item(
            "position_error_mean",
            PyArray1::from_slice(py, &o.position_error_mean),
        )?;
        e.set_item(
            "position_error_std",
            PyArray1::from_slice(py, &o.position_error_std),
        )?;
        e.set_item(
            "position_error_percentiles",
            rows(py, &o.position_error_percentiles, epochs)?,
        )?;
        e.set_item("nees_mean", PyArray1::from_slice(py, &o.nees_mean))?;
        e.set_item(
            "position_nees_mean",
            PyArray1::from_slice(py, &o.position_nees_mean),
        )?;
        if o.position_error_runs.is_empty() {
            e.set_item("position_error_runs", py.None())?;
            e.set_item("nees_runs", py.None())?;
        } else {
            e.set_item(
                "position_error_runs",
                rows(py, &o.position_error_runs, epochs)?,
            )?;
            e.set_item("nees_runs", rows(py, &o.nees_runs, epochs)?)?;
        }
        e.set_item("run_rms", PyArray1::from_slice(py, &o.run_rms))?;
        e.set_item("run_rms_early", PyArray1::from_slice(py, &o.run_rms_early))?;
        e.set_item("run_rms_late", PyArray1::from_slice(py, &o.run_rms_late))?;
        e.set_item("run_final", PyArray1::from_slice(py, &o.run_final))?;
        e.set_item(
            "run_max_in_outage",
            PyArray1::from_slice(py, &o.run_max_in_outage),
        )?;
        e.set_item(
            "run_max_horizontal_in_outage",
            PyArray1::from_slice(py, &o.run_max_horizontal_in_outage),
        )?;
        e.set_item(
            "run_max_vertical_in_outage",
            PyArray1::from_slice(py, &o.run_max_vertical_in_outage),
        )?;
        e.set_item(
            "run_at_outage_end",
            PyArray1::from_slice(py, &o.run_at_outage_end),
        )?;
        e.set_item(
            "run_horizontal_at_outage_end",
            PyArray1::from_slice(py, &o.run_horizontal_at_outage_end),
        )?;
        e.set_item(
            "run_mean_nees_per_dof",
            PyArray1::from_slice(py, &o.run_mean_nees_per_dof),
        )?;
        e.set_item(
            "run_position_nees_per_dof_at_outage_end",
            PyArray1::from_slice(py, &o.run_position_nees_per_dof_at_outage_end),
        )?;
        e.set_item(
            "run_diverged",
            PyArray1::from_iter(py, o.run_diverged.iter().copied()),
        )?;
        e.set_item(
            "run_rejected",
            PyArray1::from_iter(py, o.run_rejected.iter().map(|&n| n as i64)),
        )?;
        e.set_item(
            "run_accepted",
            PyArray1::from_iter(py, o.run_accepted.iter().map(|&n| n as i64)),
        )?;
        match &o.smoothed {
            Some(s) => e.set_item("smoothed", imu_outcome(py, s, epochs)?)?,
            None => e.set_item("smoothed", py.None())?,
        }
        Ok(e)
    }
}

/// An outage `(start_s, length_s)` (total) or `(start_s, length_s, n_visible)`.
pub(crate) fn outage_window(values: &[f64]) -> PyResult<Outage> {
    match *values {
        [start_s, duration_s] => Ok(Outage {
            start_s,
            duration_s,
            n_satellites: 0,
        }),
        [start_s, duration_s, n] if n >= 0.0 && n.fract() == 0.0 => Ok(Outage {
            start_s,
            duration_s,
            n_satellites: n as usize,
        }),
        _ => Err(PyValueError::new_err(format!(
            "outage: expected (start_s, length_s) or (start_s, length_s, n_visible) with a whole n_visible, got {values:?}"
        ))),
    }
}

/// Navigation Monte Carlo (paper §5.3) as a dict of arrays (bytes with
/// ``run_range``; ``run_range`` / ``chunks`` as in
/// ``calibration_experiment``); use
/// ``memsnav.experiments.navigation``, which documents it. ``imus``: (name,
/// source) with source a preset name, ``(preset name, spec overrides)``,
/// ``"calibrated:<raw name>"`` or an ``ImuModel``. ``pseudorange_std`` m,
/// ``pseudorange_rate_std`` m/s, ``initial_attitude_std_deg`` (north tilt,
/// east tilt, heading) degrees, None for (1, 1, 5). ``outage``: (start_s,
/// length_s) total or (start_s, length_s, n_visible) keeping n_visible (0-3)
/// satellites. ``systems``: RINEX letters of the simulated systems (None:
/// ["G"]), ``inter_system_bias``: Galileo, BeiDou[, GLONASS] pseudorange
/// biases against GPS, m (None: 0, 0, 0). ``carrier_phase_std``: simulated carrier
/// range noise, m (None: 0, no carrier phase; above 0 the tight filters use
/// its changes between epochs), ``cycle_slip_probability``: silent slips
/// per satellite and epoch (None: 0).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (imus, *, runs=None, duration=None, seed=None, n_satellites=None, outage=None, calibration_duration=None, early_window=None, pseudorange_rate=None, pseudorange_std=None, pseudorange_rate_std=None, initial_attitude_std_deg=None, scale_factor_states=false, absorb_unmodelled=None, smooth=false, keep_runs=false, threads=None, progress=None, run_range=None, chunks=None, systems=None, inter_system_bias=None, carrier_phase_std=None, cycle_slip_probability=None))]
fn navigation_experiment<'py>(
    py: Python<'py>,
    imus: &Bound<'py, PyAny>,
    runs: Option<usize>,
    duration: Option<f64>,
    seed: Option<u64>,
    n_satellites: Option<usize>,
    outage: Option<Vec<f64>>,
    calibration_duration: Option<f64>,
    early_window: Option<f64>,
    pseudorange_rate: Option<bool>,
    pseudorange_std: Option<f64>,
    pseudorange_rate_std: Option<f64>,
    initial_attitude_std_deg: Option<(f64, f64, f64)>,
    scale_factor_states: bool,
    absorb_unmodelled: Option<bool>,
    smooth: bool,
    keep_runs: bool,
    threads: Option<usize>,
    progress: Option<Bound<'py, PyAny>>,
    run_range: Option<(usize, usize)>,
    chunks: Option<Vec<Bound<'py, PyBytes>>>,
    systems: Option<Vec<String>>,
    inter_system_bias: Option<Vec<f64>>,
    carrier_phase_std: Option<f64>,
    cycle_slip_probability: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    // None keeps the core's default (`defaults()`; GPS alone, no bias, no
    // carrier phase).
    let d = NavigationExperimentConfig::default();
    let pseudorange_std = pseudorange_std.unwrap_or(d.gnss.pseudorange_std_m);
    let pseudorange_rate_std = pseudorange_rate_std.unwrap_or(d.gnss.pseudorange_rate_std_m_s);
    let config = NavigationExperimentConfig {
        runs: runs.unwrap_or(d.runs),
        seed: seed.unwrap_or(d.seed),
        duration_s: duration.unwrap_or(d.duration_s),
        imus: imu_list(imus)?,
        n_satellites: n_satellites.unwrap_or(d.n_satellites),
        outage: outage.as_deref().map(outage_window).transpose()?,
        calibration_duration_s: calibration_duration.unwrap_or(d.calibration_duration_s),
        early_window_s: early_window.unwrap_or(d.early_window_s),
        use_pseudorange_rate: pseudorange_rate.unwrap_or(d.use_pseudorange_rate),
        initial_attitude_std_rad: initial_attitude_std_deg
            .map_or(d.initial_attitude_std_rad, |(n, e, down)| {
                Vector3::new(n, e, down).map(f64::to_radians)
            }),
        scale_factor_states,
        absorb_unmodelled: absorb_unmodelled.unwrap_or(d.absorb_unmodelled),
        gnss: SimulationConfig {
            pseudorange_std_m: pseudorange_std,
            pseudorange_rate_std_m_s: pseudorange_rate_std,
            inter_system_bias_m: inter_system_bias
                .as_deref()
                .map(|v| memsnav_core::gnss::inter_system_biases("inter_system_bias", v))
                .transpose()
                .py()?
                .unwrap_or(d.gnss.inter_system_bias_m),
            carrier_phase_std_m: carrier_phase_std.unwrap_or(d.gnss.carrier_phase_std_m),
            cycle_slip_probability: cycle_slip_probability.unwrap_or(d.gnss.cycle_slip_probability),
            ..d.gnss.clone()
        },
        systems: match systems {
            Some(letters) => crate::gnss::system_letters(&letters)?,
            None => d.systems.clone(),
        },
        smooth,
        keep_runs,
        ..d
    };
    let experiment = NavigationRuns::new(&config).py()?;
    match run_monte_carlo(
        py,
        &experiment,
        run_range,
        chunks,
        threads,
        progress.as_ref(),
    )? {
        Ran::Chunk(bytes) => Ok(bytes.into_any()),
        Ran::Done(result, interrupted) => Ok(to_dict(py, &result, interrupted)?.into_any()),
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(navigation_experiment, m)?)?;
    Ok(())
}
