//! The calibration, inversion and partial-outage Monte Carlo experiments
//! (paper §5.1-5.3): one call runs a whole set in Rust with the GIL
//! released and returns a dict of numpy arrays; `memsnav.experiments`
//! shapes and plots them.
//!
//! Every keyword defaults to `None`, which means the core's `Default`
//! configuration: the defaults are written once, in memsnav-core. Each
//! result carries the `config` that ran, with every value filled in.

use memsnav_core::calibration::{accelerometer_parameter_names, gyroscope_parameter_names, Method};
use memsnav_core::experiments::{
    self, calibration::SensorStatistics, motion::MotionKind, navigation::Coupling,
    CalibrationExperimentConfig, InversionExperimentConfig, PartialOutageConfig,
};
use memsnav_py_macros::catch_panics;
use nalgebra::Vector3;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};

use crate::errors::IntoPyResult;
use crate::navigation::{imu_list, imu_outcomes};
use crate::progress::{run_interruptible, run_monte_carlo, Ran};

fn table<'py>(py: Python<'py>, values: &[f64], cols: usize) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_slice(py, values)
        .reshape([values.len() / cols.max(1), cols])?
        .into_any())
}

fn rows3<'py>(py: Python<'py>, rows: &[[f64; 3]]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    table(py, &flat, 3)
}

fn sensor_dict<'py>(
    py: Python<'py>,
    s: &SensorStatistics,
    names: Vec<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let p = s.parameters;
    d.set_item("parameter_names", names)?;
    for (key, values) in [
        ("truth", &s.truth),
        ("mse_ls", &s.mse_ls),
        ("mse_eiv", &s.mse_eiv),
        ("mean_error_ls", &s.mean_error_ls),
        ("mean_error_eiv", &s.mean_error_eiv),
        ("reported_variance_ls", &s.reported_variance_ls),
        ("reported_variance_eiv", &s.reported_variance_eiv),
        ("crb", &s.crb),
    ] {
        d.set_item(key, table(py, values, p)?)?;
    }
    Ok(d)
}

fn method_name(method: Method) -> &'static str {
    match method {
        Method::LeastSquares => "ls",
        Method::ErrorsInVariables => "eiv",
    }
}

/// Calibration Monte Carlo (paper figs 3-10); per-set arrays, SI, and the
/// ``config`` that ran. ``None``: the core's default (documented in
/// ``memsnav.experiments.calibration``). ``run_range=(start, end)``:
/// compute only those runs and return them encoded (bytes, a Dask task);
/// ``chunks``: fold such encoded runs instead of running (the same numbers
/// bit for bit; ``memsnav._distributed``).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (*, parameter_sets=None, runs=None, duration=None, preset=None, reference_specific_force_std=None, reference_angular_rate_std=None, motion=None, seed=None, threads=None, progress=None, run_range=None, chunks=None))]
fn calibration_experiment<'py>(
    py: Python<'py>,
    parameter_sets: Option<usize>,
    runs: Option<usize>,
    duration: Option<f64>,
    preset: Option<String>,
    reference_specific_force_std: Option<f64>,
    reference_angular_rate_std: Option<f64>,
    motion: Option<&str>,
    seed: Option<u64>,
    threads: Option<usize>,
    progress: Option<Bound<'py, PyAny>>,
    run_range: Option<(usize, usize)>,
    chunks: Option<Vec<Bound<'py, PyBytes>>>,
) -> PyResult<Bound<'py, PyAny>> {
    let kind = motion
        .map(MotionKind::from_name)
        .transpose()
        .py()?
        .unwrap_or_default();
    let d = CalibrationExperimentConfig::default();
    let config = CalibrationExperimentConfig {
        parameter_sets: parameter_sets.unwrap_or(d.parameter_sets),
        runs_per_set: runs.unwrap_or(d.runs_per_set),
        duration_s: duration.unwrap_or(d.duration_s),
        preset: preset.unwrap_or(d.preset),
        reference_specific_force_std: reference_specific_force_std
            .unwrap_or(d.reference_specific_force_std),
        reference_angular_rate_std: reference_angular_rate_std
            .unwrap_or(d.reference_angular_rate_std),
        seed: seed.unwrap_or(d.seed),
    };
    let experiment = experiments::CalibrationRuns::new(&config, kind.source()).py()?;
    let (r, interrupted) = match run_monte_carlo(
        py,
        &experiment,
        run_range,
        chunks,
        threads,
        progress.as_ref(),
    )? {
        Ran::Chunk(bytes) => return Ok(bytes.into_any()),
        Ran::Done(r, interrupted) => (r, interrupted),
    };
    let d = PyDict::new(py);
    d.set_item(
        "accelerometer",
        sensor_dict(py, &r.accelerometer, accelerometer_parameter_names())?,
    )?;
    d.set_item(
        "gyroscope",
        sensor_dict(py, &r.gyroscope, gyroscope_parameter_names())?,
    )?;
    d.set_item("completed_runs", r.completed_runs)?;
    d.set_item("interrupted", interrupted || r.cancelled)?;
    let c = PyDict::new(py);
    c.set_item("parameter_sets", config.parameter_sets)?;
    c.set_item("runs", config.runs_per_set)?;
    c.set_item("duration", config.duration_s)?;
    c.set_item("preset", &config.preset)?;
    c.set_item(
        "reference_specific_force_std",
        config.reference_specific_force_std,
    )?;
    c.set_item(
        "reference_angular_rate_std",
        config.reference_angular_rate_std,
    )?;
    c.set_item("motion", kind.name())?;
    c.set_item("seed", config.seed)?;
    d.set_item("config", c)?;
    Ok(d.into_any())
}

/// Inversion Monte Carlo (paper figs 11-12); per-run MSE arrays, SI, and
/// the ``config`` that ran. ``None``: the core's default (documented in
/// ``memsnav.experiments.inversion``). ``run_range`` / ``chunks`` as in
/// ``calibration_experiment``.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (*, runs=None, duration=None, calibration_duration=None, preset=None, method=None, reference_specific_force_std=None, reference_angular_rate_std=None, accel_process_std=None, gyro_process_std=None, seed=None, threads=None, progress=None, run_range=None, chunks=None))]
fn inversion_experiment<'py>(
    py: Python<'py>,
    runs: Option<usize>,
    duration: Option<f64>,
    calibration_duration: Option<f64>,
    preset: Option<String>,
    method: Option<&str>,
    reference_specific_force_std: Option<f64>,
    reference_angular_rate_std: Option<f64>,
    accel_process_std: Option<f64>,
    gyro_process_std: Option<f64>,
    seed: Option<u64>,
    threads: Option<usize>,
    progress: Option<Bound<'py, PyAny>>,
    run_range: Option<(usize, usize)>,
    chunks: Option<Vec<Bound<'py, PyBytes>>>,
) -> PyResult<Bound<'py, PyAny>> {
    let d = InversionExperimentConfig::default();
    let (dc, dp) = (d.calibration, d.process);
    let config = InversionExperimentConfig {
        runs: runs.unwrap_or(d.runs),
        duration_s: duration.unwrap_or(d.duration_s),
        preset: preset.unwrap_or(d.preset),
        calibration: experiments::SegmentCalibration {
            duration_s: calibration_duration.unwrap_or(dc.duration_s),
            reference_specific_force_std: reference_specific_force_std
                .unwrap_or(dc.reference_specific_force_std),
            reference_angular_rate_std: reference_angular_rate_std
                .unwrap_or(dc.reference_angular_rate_std),
            method: method
                .map(crate::calibration::method)
                .transpose()?
                .unwrap_or(dc.method),
        },
        process: experiments::InversionProcess {
            accel_process_std: accel_process_std.unwrap_or(dp.accel_process_std),
            gyro_process_std: gyro_process_std.unwrap_or(dp.gyro_process_std),
        },
        seed: seed.unwrap_or(d.seed),
    };
    let experiment =
        experiments::InversionRuns::new(&config, &experiments::motion::land_vehicle).py()?;
    let (r, interrupted) = match run_monte_carlo(
        py,
        &experiment,
        run_range,
        chunks,
        threads,
        progress.as_ref(),
    )? {
        Ran::Chunk(bytes) => return Ok(bytes.into_any()),
        Ran::Done(r, interrupted) => (r, interrupted),
    };
    let d = PyDict::new(py);
    d.set_item("accel_mse", rows3(py, &r.accel_mse)?)?;
    d.set_item("gyro_mse", rows3(py, &r.gyro_mse)?)?;
    d.set_item("raw_accel_mse", rows3(py, &r.raw_accel_mse)?)?;
    d.set_item("raw_gyro_mse", rows3(py, &r.raw_gyro_mse)?)?;
    d.set_item(
        "accel_squared_error_vs_time",
        rows3(py, &r.accel_squared_error_vs_time)?,
    )?;
    d.set_item(
        "gyro_squared_error_vs_time",
        rows3(py, &r.gyro_squared_error_vs_time)?,
    )?;
    d.set_item("sample_rate", r.sample_rate_hz)?;
    d.set_item("completed_runs", r.accel_mse.len())?;
    d.set_item("interrupted", interrupted || r.cancelled)?;
    let c = PyDict::new(py);
    let cal = &config.calibration;
    c.set_item("runs", config.runs)?;
    c.set_item("duration", config.duration_s)?;
    c.set_item("calibration_duration", cal.duration_s)?;
    c.set_item("preset", &config.preset)?;
    c.set_item("method", method_name(cal.method))?;
    c.set_item(
        "reference_specific_force_std",
        cal.reference_specific_force_std,
    )?;
    c.set_item("reference_angular_rate_std", cal.reference_angular_rate_std)?;
    c.set_item("accel_process_std", config.process.accel_process_std)?;
    c.set_item("gyro_process_std", config.process.gyro_process_std)?;
    c.set_item("seed", config.seed)?;
    d.set_item("config", c)?;
    Ok(d.into_any())
}

/// The keywords the partial-outage set and the outage study share.
struct StudyKeywords {
    runs: Option<usize>,
    duration: Option<f64>,
    seed: Option<u64>,
    calibration_duration: Option<f64>,
    smooth: Option<bool>,
    n_satellites: Option<usize>,
    systems: Option<Vec<String>>,
    inter_system_bias: Option<Vec<f64>>,
    carrier_phase_std: Option<f64>,
    cycle_slip_probability: Option<f64>,
}

/// `base` with the keywords given (None keeps the base's value).
fn study_navigation(
    base: &experiments::NavigationExperimentConfig,
    imus: &Bound<'_, PyAny>,
    k: StudyKeywords,
) -> PyResult<experiments::NavigationExperimentConfig> {
    let n = base;
    Ok(experiments::NavigationExperimentConfig {
        runs: k.runs.unwrap_or(n.runs),
        duration_s: k.duration.unwrap_or(n.duration_s),
        seed: k.seed.unwrap_or(n.seed),
        imus: imu_list(imus)?,
        calibration_duration_s: k.calibration_duration.unwrap_or(n.calibration_duration_s),
        smooth: k.smooth.unwrap_or(n.smooth),
        n_satellites: k.n_satellites.unwrap_or(n.n_satellites),
        systems: match k.systems {
            Some(letters) => crate::gnss::system_letters(&letters)?,
            None => n.systems.clone(),
        },
        gnss: memsnav_core::gnss::SimulationConfig {
            inter_system_bias_m: k
                .inter_system_bias
                .as_deref()
                .map(|v| memsnav_core::gnss::inter_system_biases("inter_system_bias", v))
                .transpose()
                .py()?
                .unwrap_or(n.gnss.inter_system_bias_m),
            carrier_phase_std_m: k.carrier_phase_std.unwrap_or(n.gnss.carrier_phase_std_m),
            cycle_slip_probability: k
                .cycle_slip_probability
                .unwrap_or(n.gnss.cycle_slip_probability),
            ..n.gnss.clone()
        },
        ..n.clone()
    })
}

/// Partial-outage study (0-3 satellites through a window, tight against
/// loose coupling): ``time``, ``scenarios`` (``coupling``, ``n_visible``,
/// ``imus`` as in ``navigation_experiment``), ``completed_runs``,
/// ``interrupted``, ``config``. ``None``: the core's default (documented in
/// ``memsnav.experiments.partial_outage``). ``run_range`` / ``chunks`` as
/// in ``calibration_experiment``.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (imus, *, runs=None, duration=None, seed=None, outage_start=None, outage_length=None, satellites=None, loose=None, calibration_duration=None, smooth=None, keep_runs=None, threads=None, progress=None, run_range=None, chunks=None, n_satellites=None, systems=None, inter_system_bias=None, carrier_phase_std=None, cycle_slip_probability=None))]
fn partial_outage_experiment<'py>(
    py: Python<'py>,
    imus: &Bound<'py, PyAny>,
    runs: Option<usize>,
    duration: Option<f64>,
    seed: Option<u64>,
    outage_start: Option<f64>,
    outage_length: Option<f64>,
    satellites: Option<Vec<usize>>,
    loose: Option<bool>,
    calibration_duration: Option<f64>,
    smooth: Option<bool>,
    keep_runs: Option<bool>,
    threads: Option<usize>,
    progress: Option<Bound<'py, PyAny>>,
    run_range: Option<(usize, usize)>,
    chunks: Option<Vec<Bound<'py, PyBytes>>>,
    n_satellites: Option<usize>,
    systems: Option<Vec<String>>,
    inter_system_bias: Option<Vec<f64>>,
    carrier_phase_std: Option<f64>,
    cycle_slip_probability: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let d = PartialOutageConfig::default();
    let navigation = experiments::NavigationExperimentConfig {
        keep_runs: keep_runs.unwrap_or(d.navigation.keep_runs),
        ..study_navigation(
            &d.navigation,
            imus,
            StudyKeywords {
                runs,
                duration,
                seed,
                calibration_duration,
                smooth,
                n_satellites,
                systems,
                inter_system_bias,
                carrier_phase_std,
                cycle_slip_probability,
            },
        )?
    };
    let config = PartialOutageConfig {
        navigation,
        outage_start_s: outage_start.unwrap_or(d.outage_start_s),
        outage_length_s: outage_length.unwrap_or(d.outage_length_s),
        satellites: satellites.unwrap_or(d.satellites.clone()),
        loose: loose.unwrap_or(d.loose),
    };
    let experiment = experiments::PartialOutageRuns::new(&config).py()?;
    let (r, interrupted) = match run_monte_carlo(
        py,
        &experiment,
        run_range,
        chunks,
        threads,
        progress.as_ref(),
    )? {
        Ran::Chunk(bytes) => return Ok(bytes.into_any()),
        Ran::Done(r, interrupted) => (r, interrupted),
    };
    let out = PyDict::new(py);
    out.set_item("time", PyArray1::from_slice(py, &r.time_s))?;
    out.set_item("completed_runs", r.completed_runs)?;
    out.set_item("interrupted", interrupted || r.cancelled)?;
    let scenarios = PyList::empty(py);
    for s in &r.scenarios {
        let e = PyDict::new(py);
        e.set_item(
            "coupling",
            match s.scenario.coupling {
                Coupling::Tight => "tight",
                Coupling::Loose => "loose",
            },
        )?;
        e.set_item("n_visible", s.scenario.n_visible)?;
        e.set_item("imus", imu_outcomes(py, &s.imus, r.time_s.len())?)?;
        scenarios.append(e)?;
    }
    out.set_item("scenarios", scenarios)?;
    let nav = &config.navigation;
    let c = PyDict::new(py);
    c.set_item("runs", nav.runs)?;
    c.set_item("duration", nav.duration_s)?;
    c.set_item("seed", nav.seed)?;
    c.set_item("n_satellites", nav.n_satellites)?;
    c.set_item(
        "systems",
        nav.systems
            .iter()
            .map(|s| s.letter().to_string())
            .collect::<Vec<_>>(),
    )?;
    c.set_item("inter_system_bias", nav.gnss.inter_system_bias_m.to_vec())?;
    c.set_item("carrier_phase_std", nav.gnss.carrier_phase_std_m)?;
    c.set_item("cycle_slip_probability", nav.gnss.cycle_slip_probability)?;
    c.set_item("outage_start", config.outage_start_s)?;
    c.set_item("outage_length", config.outage_length_s)?;
    c.set_item("satellites", config.satellites.clone())?;
    c.set_item("loose", config.loose)?;
    c.set_item("calibration_duration", nav.calibration_duration_s)?;
    c.set_item("early_window", nav.early_window_s)?;
    c.set_item("pseudorange_std", nav.gnss.pseudorange_std_m)?;
    c.set_item("pseudorange_rate_std", nav.gnss.pseudorange_rate_std_m_s)?;
    let deg: Vector3<f64> = nav.initial_attitude_std_rad.map(f64::to_degrees);
    c.set_item("initial_attitude_std_deg", (deg.x, deg.y, deg.z))?;
    c.set_item("smooth", nav.smooth)?;
    out.set_item("config", c)?;
    Ok(out.into_any())
}

/// The outage study's runs `run_range` for `cells`, triples of indices
/// (IMU, outage length, satellites count) into `imus`, `outage_lengths`
/// and `visible_satellites` (`memsnav_core::experiments::outage_study_runs`;
/// `memsnav.experiments.outage_study` chooses the cells and the looks).
/// Every cell's run ends `tail` s after its window (default 10 s with
/// `smooth`, else 0); `duration` defaults to the start, the longest
/// window and the tail. Returns per solution (`forward`, and `smoothed`
/// with `smooth`) arrays (runs, cells): `horizontal_end`,
/// `horizontal_max`, `error_3d_end`, `error_3d_max` (m), `diverged`,
/// `rejected`, `accepted`; `completed_runs` and `interrupted`.
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (imus, *, cells, run_range, outage_lengths, visible_satellites, outage_start=None, duration=None, tail=None, seed=None, calibration_duration=None, smooth=None, threads=None, progress=None, n_satellites=None, systems=None, inter_system_bias=None, carrier_phase_std=None, cycle_slip_probability=None))]
fn outage_study_runs<'py>(
    py: Python<'py>,
    imus: &Bound<'py, PyAny>,
    cells: Vec<(usize, usize, usize)>,
    run_range: (usize, usize),
    outage_lengths: Vec<f64>,
    visible_satellites: Vec<usize>,
    outage_start: Option<f64>,
    duration: Option<f64>,
    tail: Option<f64>,
    seed: Option<u64>,
    calibration_duration: Option<f64>,
    smooth: Option<bool>,
    threads: Option<usize>,
    progress: Option<Bound<'py, PyAny>>,
    n_satellites: Option<usize>,
    systems: Option<Vec<String>>,
    inter_system_bias: Option<Vec<f64>>,
    carrier_phase_std: Option<f64>,
    cycle_slip_probability: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    if threads == Some(0) {
        return Err(pyo3::exceptions::PyValueError::new_err(
            "threads: must be at least 1 (or None)",
        ));
    }
    let (start, end) = run_range;
    if start > end {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "run_range: needs start <= end, got ({start}, {end})"
        )));
    }
    let d = PartialOutageConfig::default();
    let outage_start_s = outage_start.unwrap_or(d.outage_start_s);
    let smoothing = smooth.unwrap_or(false);
    let tail_s = tail.unwrap_or(if smoothing { 10.0 } else { 0.0 });
    let longest = outage_lengths.iter().copied().fold(0.0, f64::max);
    let navigation = study_navigation(
        &d.navigation,
        imus,
        StudyKeywords {
            runs: Some(end.max(1)),
            duration: Some(duration.unwrap_or(outage_start_s + longest + tail_s)),
            seed,
            calibration_duration,
            smooth: Some(smoothing),
            n_satellites,
            systems,
            inter_system_bias,
            carrier_phase_std,
            cycle_slip_probability,
        },
    )?;
    let config = experiments::OutageStudyConfig {
        navigation,
        outage_start_s,
        outage_lengths_s: outage_lengths,
        visible_satellites,
        tail_s,
    };
    let cells: Vec<experiments::StudyCell> = cells
        .into_iter()
        .map(|(imu, length, visible)| experiments::StudyCell {
            imu,
            length,
            visible,
        })
        .collect();
    let (runs, interrupted) =
        run_interruptible(py, progress.as_ref(), end - start, threads, |o| {
            experiments::outage_study_runs(&config, &cells, start..end, o)
        })?;
    let runs = runs.py()?;
    let out = PyDict::new(py);
    let shape = [runs.runs.len(), cells.len()];
    let figures = |pick: &dyn Fn(&experiments::CellRun) -> Option<experiments::WindowFigures>|
     -> PyResult<Option<Bound<'py, PyDict>>> {
        let all: Option<Vec<experiments::WindowFigures>> =
            runs.runs.iter().flatten().map(pick).collect();
        let Some(all) = all else { return Ok(None) };
        let d = PyDict::new(py);
        let column = |f: fn(&experiments::WindowFigures) -> f64| -> PyResult<Bound<'py, PyAny>> {
            let v: Vec<f64> = all.iter().map(f).collect();
            Ok(PyArray1::from_vec(py, v).reshape(shape)?.into_any())
        };
        d.set_item("horizontal_end", column(|f| f.horizontal_end_m)?)?;
        d.set_item("horizontal_max", column(|f| f.horizontal_max_m)?)?;
        d.set_item("error_3d_end", column(|f| f.error_3d_end_m)?)?;
        d.set_item("error_3d_max", column(|f| f.error_3d_max_m)?)?;
        let flags: Vec<bool> = all.iter().map(|f| f.diverged).collect();
        d.set_item("diverged", PyArray1::from_vec(py, flags).reshape(shape)?)?;
        let counts = |f: fn(&experiments::WindowFigures) -> usize| -> PyResult<Bound<'py, PyAny>> {
            let v: Vec<u64> = all.iter().map(|x| f(x) as u64).collect();
            Ok(PyArray1::from_vec(py, v).reshape(shape)?.into_any())
        };
        d.set_item("rejected", counts(|f| f.rejected)?)?;
        d.set_item("accepted", counts(|f| f.accepted)?)?;
        Ok(Some(d))
    };
    out.set_item("forward", figures(&|c| Some(c.forward))?)?;
    out.set_item(
        "smoothed",
        if smoothing {
            figures(&|c| c.smoothed)?
        } else {
            None
        },
    )?;
    out.set_item("completed_runs", runs.runs.len())?;
    out.set_item("interrupted", interrupted || runs.cancelled)?;
    out.set_item("duration", config.navigation.duration_s)?;
    out.set_item("tail", config.tail_s)?;
    Ok(out)
}

/// The body-frame land-vehicle motion of the calibration experiment
/// (`memsnav_core::experiments::motion::land_vehicle`: speed changes,
/// turns, road roughness, roll and pitch dynamics): `duration` s at `rate`
/// Hz from `seed`, as (specific force (N, 3) m/s², angular rate (N, 3) rad/s).
#[catch_panics]
#[pyfunction]
#[pyo3(signature = (duration, rate, seed))]
fn land_vehicle_motion<'py>(
    py: Python<'py>,
    duration: f64,
    rate: f64,
    seed: u64,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let m = py
        .detach(|| {
            experiments::motion::land_vehicle(
                duration,
                rate,
                &mut memsnav_core::random::stream(seed, 0),
            )
        })
        .py()?;
    let rows =
        |v: &[Vector3<f64>]| -> Vec<[f64; 3]> { v.iter().map(|x| [x.x, x.y, x.z]).collect() };
    Ok((
        rows3(py, &rows(&m.specific_force_b))?,
        rows3(py, &rows(&m.angular_rate_b))?,
    ))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(land_vehicle_motion, m)?)?;
    m.add_function(wrap_pyfunction!(calibration_experiment, m)?)?;
    m.add_function(wrap_pyfunction!(inversion_experiment, m)?)?;
    m.add_function(wrap_pyfunction!(partial_outage_experiment, m)?)?;
    m.add_function(wrap_pyfunction!(outage_study_runs, m)?)?;
    Ok(())
}
