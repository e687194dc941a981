//! `defaults()`: the core's default of every optional modelling argument,
//! by the Python name of the function or class that takes it.
//!
//! Every such argument is `None` in the signatures (binding, Python
//! wrappers and stub alike) and `None` means the value listed here, read
//! from the core's own `Default`s and constants: a default changes by one
//! edit in the core (tests/test_defaults.py checks that every layer agrees).

use memsnav_core::allan_fit::DEFAULT_MIN_TAU_S;
use memsnav_core::coupling::{
    InitialUncertainty, DEFAULT_GATE_PROBABILITY, DEFAULT_PSEUDORANGE_CORRELATION_TIME_S,
};
use memsnav_core::experiments::NavigationExperimentConfig;
use memsnav_core::filter::input_noise::DEFAULT_MANOEUVRE_CORRELATION_TIME_S;
use memsnav_core::gnss::{
    ObservableOptions, ReceiverClockModel, WalkerConfig, DEFAULT_ELEVATION_MASK_DEG,
    DEFAULT_PSEUDORANGE_RATE_STD_M_S, DEFAULT_PSEUDORANGE_STD_M,
};
use memsnav_core::montecarlo::DEFAULT_CONFIDENCE;
use memsnav_core::navigate::references;
use memsnav_core::navigate::score::DEFAULT_TRUTH_TOLERANCE_S;
use memsnav_core::sensors::presets::DEFAULT_PRESET;
use memsnav_core::sensors::DEFAULT_SAMPLE_RATE_HZ;
use memsnav_py_macros::catch_panics;
use nalgebra::Vector3;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The coupled filters' defaults not derived from the IMU (the noise
/// densities, bias processes and initial bias spreads come from its spec).
fn filter<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let p0 = InitialUncertainty::default();
    let clock = ReceiverClockModel::default();
    let d = PyDict::new(py);
    d.set_item("gate_probability", DEFAULT_GATE_PROBABILITY)?;
    d.set_item("initial_position_std", p0.position_m)?;
    d.set_item("initial_velocity_std", p0.velocity_m_s)?;
    d.set_item("initial_tilt_std", p0.attitude_ned_rad.x)?;
    d.set_item("initial_heading_std", p0.attitude_ned_rad.z)?;
    d.set_item("initial_clock_offset_std", p0.clock_offset_m)?;
    d.set_item("initial_clock_drift_std", p0.clock_drift_m_s)?;
    d.set_item("clock_h0", clock.h0)?;
    d.set_item("clock_h_minus2", clock.h_minus2)?;
    d.set_item(
        "manoeuvre_correlation_time",
        DEFAULT_MANOEUVRE_CORRELATION_TIME_S,
    )?;
    d.set_item(
        "pseudorange_correlation_time",
        DEFAULT_PSEUDORANGE_CORRELATION_TIME_S,
    )?;
    Ok(d)
}

/// Degrees, as the Python arguments take angles.
fn degrees(v: &Vector3<f64>) -> (f64, f64, f64) {
    let d = v.map(f64::to_degrees);
    (d.x, d.y, d.z)
}

/// The core's default of every optional modelling argument, by the
/// Python name of the function or class that takes it
/// (``"TightlyCoupledFilter"``, ``"RinexObservations.gps_l1"``,
/// ``"navigation_experiment"``, ``"Constellation.walker"``, the sample
/// rates of the sensor models, presets, trajectories and calibrations): a
/// ``None`` in that signature means this value. The coupled filters' noise
/// densities, bias processes and initial bias spreads come from the IMU
/// model and are not listed.
#[catch_panics]
#[pyfunction]
pub fn defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("TightlyCoupledFilter", filter(py)?)?;
    out.set_item("LooselyCoupledFilter", filter(py)?)?;

    let observables = ObservableOptions::new(Vector3::zeros());
    let d = PyDict::new(py);
    d.set_item("elevation_mask_deg", DEFAULT_ELEVATION_MASK_DEG)?;
    d.set_item("min_cn0_db_hz", observables.min_cn0_db_hz)?;
    d.set_item("weighting", observables.weighting.name())?;
    // Read by the signal-strength weighting alone: the default RTKLIB model
    // refuses a value.
    d.set_item("pseudorange_std", DEFAULT_PSEUDORANGE_STD_M)?;
    d.set_item("pseudorange_rate_std", DEFAULT_PSEUDORANGE_RATE_STD_M_S)?;
    d.set_item("carrier_phase_std", observables.carrier_phase_std_m)?;
    out.set_item("RinexObservations.gps_l1", d)?;

    let n = NavigationExperimentConfig::default();
    let d = PyDict::new(py);
    d.set_item("runs", n.runs)?;
    d.set_item("duration", n.duration_s)?;
    d.set_item("seed", n.seed)?;
    d.set_item("n_satellites", n.n_satellites)?;
    d.set_item("calibration_duration", n.calibration_duration_s)?;
    d.set_item("early_window", n.early_window_s)?;
    d.set_item("pseudorange_rate", n.use_pseudorange_rate)?;
    d.set_item("pseudorange_std", n.gnss.pseudorange_std_m)?;
    d.set_item("pseudorange_rate_std", n.gnss.pseudorange_rate_std_m_s)?;
    d.set_item(
        "initial_attitude_std_deg",
        degrees(&n.initial_attitude_std_rad),
    )?;
    d.set_item("absorb_unmodelled", n.absorb_unmodelled)?;
    d.set_item("carrier_phase_std", n.gnss.carrier_phase_std_m)?;
    d.set_item("cycle_slip_probability", n.gnss.cycle_slip_probability)?;
    out.set_item("navigation_experiment", d)?;

    let w = WalkerConfig::default();
    let d = PyDict::new(py);
    d.set_item("n_satellites", w.n_satellites)?;
    d.set_item("planes", w.planes)?;
    d.set_item("inclination_deg", w.inclination_rad.to_degrees())?;
    d.set_item("semi_major_axis_m", w.semi_major_axis_m)?;
    d.set_item("phasing", w.phasing)?;
    d.set_item("raan0_deg", w.raan0_rad.to_degrees())?;
    out.set_item("Constellation.walker", d)?;

    for api in ["allan_fit", "imu_spec_from_allan"] {
        let d = PyDict::new(py);
        d.set_item("min_tau", DEFAULT_MIN_TAU_S)?;
        out.set_item(api, d)?;
    }
    let d = PyDict::new(py);
    d.set_item("base", DEFAULT_PRESET)?;
    out.set_item("imu_spec_from_datasheet", d)?;

    for api in ["quantile_interval", "sequential_look_error"] {
        let d = PyDict::new(py);
        d.set_item("confidence", DEFAULT_CONFIDENCE)?;
        out.set_item(api, d)?;
    }
    let d = PyDict::new(py);
    d.set_item("tolerance", DEFAULT_TRUTH_TOLERANCE_S)?;
    out.set_item("LogRun.score_gnss", d)?;
    let d = PyDict::new(py);
    d.set_item("window_s", references::DEFAULT_WINDOW_S)?;
    out.set_item("LogRun.calibration_references", d)?;

    for (api, argument) in [
        ("AccelerometerModel", "sample_rate"),
        ("GyroscopeModel", "sample_rate"),
        ("ImuModel.preset", "sample_rate"),
        ("CalibrationLayout.model", "sample_rate"),
        ("calibrate_accelerometer", "sample_rate"),
        ("calibrate_gyroscope", "sample_rate"),
        ("Trajectory.from_segments", "rate"),
        ("Trajectory.from_profile", "rate"),
    ] {
        let d = PyDict::new(py);
        d.set_item(argument, DEFAULT_SAMPLE_RATE_HZ)?;
        out.set_item(api, d)?;
    }
    Ok(out)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(defaults, m)?)?;
    Ok(())
}
