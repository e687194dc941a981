//! The paper's Monte Carlo experiments on calibration and inversion
//! (paper §5.1-5.2, figures 3-12; method §6).
//!
//! Each experiment is one call that runs a whole Monte Carlo set in
//! parallel through [`crate::montecarlo::fold`]: run i draws only from
//! `random::stream(seed, i)` and results are aggregated in run order, so
//! the numbers do not depend on the thread count.
//!
//! ## References "as GNSS would give them"
//!
//! The calibration needs the true inputs; in the field they come from GNSS:
//! specific force from differentiated GNSS velocity (Doppler or RTK) rotated
//! into the body with an attitude solution, and angular rate from
//! differentiated attitude. The defaults model them as the truth plus white
//! Gaussian noise at the IMU rate:
//! - specific force: 0.03 m/s² (≈ 3 mg) per axis. Doppler velocity noise of
//!   ~2 cm/s differenced over 1 s gives √2 · 0.02 ≈ 0.03 m/s²; attitude
//!   errors of ~0.1° add g · 0.0017 ≈ 0.017 m/s² on the horizontal axes.
//! - angular rate: 0.1 °/s per axis: attitude from a multi-antenna receiver
//!   (~0.05-0.1°) differenced over 1 s.
//!
//! White noise at the IMU rate is a simplification (GNSS gives 1 Hz values
//! interpolated to 100 Hz, whose errors are correlated over a second); it
//! is what the paper's per-sample regression assumes.

pub mod calibrate_invert;
pub mod calibration;
pub mod inversion;
pub mod motion;
pub mod navigation;

use nalgebra::Vector3;
use rand::Rng as _;
use rand_distr::StandardNormal;

use crate::random::Rng;
use crate::sensors::presets;
use crate::{Error, Result};

pub use calibrate_invert::{CalibratedImu, InversionProcess, SegmentCalibration};
pub use calibration::{
    calibration_experiment, CalibrationExperiment, CalibrationExperimentConfig, CalibrationRuns,
};
pub use inversion::{
    inversion_experiment, InversionExperiment, InversionExperimentConfig, InversionRuns,
};
pub use navigation::outage_study::{
    outage_study_runs, CellRun, OutageStudyConfig, StudyCell, StudyRuns, WindowFigures,
};
pub use navigation::partial_outage::{
    partial_outage_experiment, PartialOutageConfig, PartialOutageExperiment, PartialOutageRuns,
};
pub use navigation::{
    navigation_experiment, Coupling, InitialStateSource, NavigationExperiment,
    NavigationExperimentConfig, NavigationImu, NavigationRuns,
};

/// Default reference specific-force noise, m/s² per sample (see module docs).
pub const REFERENCE_SPECIFIC_FORCE_STD: f64 = 0.03;
/// Default reference angular-rate noise, rad/s per sample (0.1 °/s).
pub const REFERENCE_ANGULAR_RATE_STD: f64 = 0.1 * std::f64::consts::PI / 180.0;

/// True IMU inputs along a motion: f_ib^b (m/s²) and ω_ib^b (rad/s) at the
/// IMU rate.
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    /// True specific force f_ib^b per sample, m/s².
    pub specific_force_b: Vec<Vector3<f64>>,
    /// True angular rate ω_ib^b per sample, rad/s.
    pub angular_rate_b: Vec<Vector3<f64>>,
}

/// Where motion comes from: `(duration_s, rate_hz, rng) -> Motion`.
pub type MotionSource<'a> = dyn Fn(f64, f64, &mut Rng) -> Result<Motion> + Sync + 'a;

/// A known preset name; the error names `preset`.
pub(crate) fn validate_preset(preset: &str) -> Result<()> {
    presets::preset_spec(preset)
        .map(|_| ())
        .map_err(|e| match e {
            Error::InvalidArgument { reason, .. } => Error::invalid("preset", reason),
            other => other,
        })
}

/// The references' noise per sample: positive and finite.
pub(crate) fn validate_reference_noise(
    specific_force_std: f64,
    angular_rate_std: f64,
) -> Result<()> {
    for (name, std) in [
        ("reference_specific_force_std", specific_force_std),
        ("reference_angular_rate_std", angular_rate_std),
    ] {
        crate::validate::positive(name, std)?;
        crate::validate::at_most(name, std, crate::limits::MAX_SENSOR_MAGNITUDE)?;
    }
    Ok(())
}

/// The truth plus white Gaussian noise of std `std` on every component.
pub(crate) fn with_white_noise(
    truth: &[Vector3<f64>],
    std: f64,
    rng: &mut Rng,
) -> Vec<Vector3<f64>> {
    truth
        .iter()
        .map(|v| v + Vector3::from_fn(|_, _| std * rng.sample::<f64, _>(StandardNormal)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::montecarlo::RunOptions;

    fn threads(n: usize) -> RunOptions<'static> {
        RunOptions {
            threads: Some(n),
            ..Default::default()
        }
    }

    #[test]
    fn same_numbers_whatever_the_thread_count() {
        let config = CalibrationExperimentConfig {
            parameter_sets: 2,
            runs_per_set: 3,
            duration_s: 20.0,
            ..Default::default()
        };
        let one = calibration_experiment(&config, &motion::land_vehicle, &threads(1)).unwrap();
        let two = calibration_experiment(&config, &motion::land_vehicle, &threads(2)).unwrap();
        assert_eq!(one, two);
        let config = InversionExperimentConfig {
            runs: 3,
            duration_s: 10.0,
            calibration: SegmentCalibration {
                duration_s: 30.0,
                ..Default::default()
            },
            ..Default::default()
        };
        let one = inversion_experiment(&config, &motion::land_vehicle, &threads(1)).unwrap();
        let two = inversion_experiment(&config, &motion::land_vehicle, &threads(2)).unwrap();
        assert_eq!(one, two);
    }

    /// With the filters following the motion, the inversion error is about
    /// the white noise per sample (≤ r²) plus small calibration residues,
    /// far below the raw outputs' error (the paper-mems biases ≈ 1e-2 g).
    #[test]
    fn inversion_error_is_about_the_noise_floor() {
        let config = InversionExperimentConfig {
            runs: 4,
            duration_s: 30.0,
            calibration: SegmentCalibration {
                duration_s: 120.0,
                ..Default::default()
            },
            ..Default::default()
        };
        let r = inversion_experiment(&config, &motion::land_vehicle, &threads(2)).unwrap();
        let noise_a = (3e-3 * 9.80665f64).powi(2);
        let noise_g = (0.03f64.to_radians()).powi(2);
        for run in 0..4 {
            for i in 0..3 {
                assert!(
                    r.accel_mse[run][i] < 2.0 * noise_a,
                    "{:?}",
                    r.accel_mse[run]
                );
                assert!(
                    r.accel_mse[run][i] > 0.2 * noise_a,
                    "{:?}",
                    r.accel_mse[run]
                );
                assert!(r.gyro_mse[run][i] < 2.0 * noise_g, "{:?}", r.gyro_mse[run]);
            }
            let total = |m: &[f64; 3]| m.iter().sum::<f64>();
            assert!(
                total(&r.raw_accel_mse[run]) > 3.0 * total(&r.accel_mse[run]),
                "raw {:?} vs inverted {:?}",
                r.raw_accel_mse[run],
                r.accel_mse[run]
            );
        }
    }
}
