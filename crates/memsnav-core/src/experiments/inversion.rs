//! Inversion Monte Carlo (paper §5.2, figures 11-12): each run draws an IMU
//! from the preset, calibrates it on its own segment with GNSS-like
//! references, then inverts the outputs of a fresh random trajectory with
//! the two EKFs of method §4; MSE of Γ̂ and Ω̂ against the truth.

use nalgebra::Vector3;

use crate::calibration::{
    calibrate_accelerometer, calibrate_gyroscope, CalibrationOptions, Method,
};
use crate::inversion::{invert_accelerometer, invert_gyroscope, InversionNoise};
use crate::montecarlo::{self, RunOptions};
use crate::random::Rng;
use crate::sensors::ImuModel;
use crate::{validate, Error, Result};

use super::{with_white_noise, MotionSource};

/// What the inversion experiment runs.
#[derive(Debug, Clone, PartialEq)]
pub struct InversionExperimentConfig {
    /// Monte Carlo runs (paper: 300), each with its own IMU draw and trajectory.
    pub runs: usize,
    /// Length of the inverted trajectory, s (paper: 120).
    pub duration_s: f64,
    /// Length of the calibration segment before it, s.
    pub calibration_duration_s: f64,
    pub preset: String,
    /// Reference noise of the calibration, per sample (see [`super`]).
    pub reference_specific_force_std: f64,
    pub reference_angular_rate_std: f64,
    /// Calibration estimator (default errors-in-variables: plain LS with
    /// noisy references leaves scale-factor biases that dominate the MSE).
    pub method: Method,
    /// Random-walk increment std per sample of the two filters (m/s², rad/s).
    pub accel_process_std: f64,
    pub gyro_process_std: f64,
    pub seed: u64,
}

impl Default for InversionExperimentConfig {
    fn default() -> Self {
        Self {
            runs: 50,
            duration_s: 120.0,
            calibration_duration_s: 300.0,
            preset: "paper-mems".into(),
            reference_specific_force_std: super::REFERENCE_SPECIFIC_FORCE_STD,
            reference_angular_rate_std: super::REFERENCE_ANGULAR_RATE_STD,
            method: Method::ErrorsInVariables,
            accel_process_std: DEFAULT_ACCEL_PROCESS_STD,
            gyro_process_std: DEFAULT_GYRO_PROCESS_STD,
            seed: 0,
        }
    }
}

/// Default accelerometer random-walk increment per sample, m/s²: "set high
/// so fast motion is followed" (method §4): 0.1 m/s² per 10 ms, a jerk of
/// 10 m/s³, above what a land vehicle produces, several times the
/// paper-mems noise, so the filter mostly follows the outputs.
pub const DEFAULT_ACCEL_PROCESS_STD: f64 = 0.1;
/// Default gyroscope random-walk increment per sample, rad/s (1 °/s per
/// 10 ms: angular accelerations of 100 °/s²).
pub const DEFAULT_GYRO_PROCESS_STD: f64 = 1.0 * std::f64::consts::PI / 180.0;

/// Results of [`inversion_experiment`], SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct InversionExperiment {
    pub config: InversionExperimentConfig,
    /// Per run and axis: mean over the trajectory of (Γ̂ − Γ)², (m/s²)².
    pub accel_mse: Vec<[f64; 3]>,
    /// Per run and axis: mean of (Ω̂ − Ω)², (rad/s)².
    pub gyro_mse: Vec<[f64; 3]>,
    /// The same for the raw outputs taken as Γ and Ω (no calibration).
    pub raw_accel_mse: Vec<[f64; 3]>,
    pub raw_gyro_mse: Vec<[f64; 3]>,
    /// Per sample and axis, mean over runs of the squared errors of Γ̂ and Ω̂.
    pub accel_squared_error_vs_time: Vec<[f64; 3]>,
    pub gyro_squared_error_vs_time: Vec<[f64; 3]>,
    /// Sample rate of the series, Hz.
    pub sample_rate_hz: f64,
    /// The set was cancelled: the arrays cover the completed runs only.
    pub cancelled: bool,
}

struct RunResult {
    accel: Vec<Vector3<f64>>,
    gyro: Vec<Vector3<f64>>,
    raw_accel: [f64; 3],
    raw_gyro: [f64; 3],
    sample_rate_hz: f64,
}

fn mean_sq(e: &[Vector3<f64>]) -> [f64; 3] {
    let n = e.len() as f64;
    std::array::from_fn(|i| e.iter().map(|v| v[i] * v[i]).sum::<f64>() / n)
}

fn errors(est: &[Vector3<f64>], truth: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    est.iter().zip(truth).map(|(a, b)| a - b).collect()
}

/// Runs the inversion Monte Carlo.
pub fn inversion_experiment(
    config: &InversionExperimentConfig,
    motion: &MotionSource<'_>,
    options: &RunOptions<'_>,
) -> Result<InversionExperiment> {
    if config.runs == 0 {
        return Err(Error::invalid("runs", "must be at least 1"));
    }
    validate::positive("duration", config.duration_s)?;
    validate::positive("calibration_duration", config.calibration_duration_s)?;
    validate::positive(
        "reference_specific_force_std",
        config.reference_specific_force_std,
    )?;
    validate::positive(
        "reference_angular_rate_std",
        config.reference_angular_rate_std,
    )?;
    validate::positive("accel_process_std", config.accel_process_std)?;
    validate::positive("gyro_process_std", config.gyro_process_std)?;
    let (sf, sw) = (
        config.reference_specific_force_std,
        config.reference_angular_rate_std,
    );
    let run = |_: usize, rng: &mut Rng| -> Result<RunResult> {
        let imu = ImuModel::preset(&config.preset, rng)?;
        let rate = imu.sample_rate_hz;
        // Calibration on its own segment (method §6: at t = 0, before the run).
        let cal = motion(config.calibration_duration_s, rate, rng)?;
        let readings = imu.measure(&cal.specific_force_b, &cal.angular_rate_b, rng)?;
        let f_ref = with_white_noise(&cal.specific_force_b, sf, rng);
        let w_ref = with_white_noise(&cal.angular_rate_b, sw, rng);
        let eiv = config.method == Method::ErrorsInVariables;
        let acc_opts = CalibrationOptions {
            method: config.method,
            reference_noise_std: eiv.then_some(sf),
            ..Default::default()
        };
        let gyr_opts = CalibrationOptions {
            method: config.method,
            reference_noise_std: eiv.then_some(sw),
            reference_specific_force_noise_std: eiv.then_some(sf),
            ..Default::default()
        };
        let acc = calibrate_accelerometer(&readings.specific_force_b, &f_ref, &acc_opts)?;
        let gyr = calibrate_gyroscope(&readings.angular_rate_b, &w_ref, &f_ref, &gyr_opts)?;
        // Inversion of a fresh trajectory.
        let m = motion(config.duration_s, rate, rng)?;
        let readings = imu.measure(&m.specific_force_b, &m.angular_rate_b, rng)?;
        let accel_noise = InversionNoise {
            process_std: Vector3::repeat(config.accel_process_std),
            measurement_std: Vector3::repeat(imu.accelerometer.noise.white_std_per_sample(rate)),
        };
        let gyro_noise = InversionNoise {
            process_std: Vector3::repeat(config.gyro_process_std),
            measurement_std: Vector3::repeat(imu.gyroscope.noise.white_std_per_sample(rate)),
        };
        let f_hat = invert_accelerometer(&readings.specific_force_b, &acc.model, &accel_noise)?;
        let w_hat = invert_gyroscope(
            &readings.angular_rate_b,
            &f_hat.estimate,
            &gyr.model,
            &gyro_noise,
        )?;
        Ok(RunResult {
            accel: errors(&f_hat.estimate, &m.specific_force_b),
            gyro: errors(&w_hat.estimate, &m.angular_rate_b),
            raw_accel: mean_sq(&errors(&readings.specific_force_b, &m.specific_force_b)),
            raw_gyro: mean_sq(&errors(&readings.angular_rate_b, &m.angular_rate_b)),
            sample_rate_hz: rate,
        })
    };
    let mut out = InversionExperiment {
        config: config.clone(),
        accel_mse: Vec::with_capacity(config.runs),
        gyro_mse: Vec::with_capacity(config.runs),
        raw_accel_mse: Vec::with_capacity(config.runs),
        raw_gyro_mse: Vec::with_capacity(config.runs),
        accel_squared_error_vs_time: Vec::new(),
        gyro_squared_error_vs_time: Vec::new(),
        sample_rate_hz: 0.0,
        cancelled: false,
    };
    let summary = montecarlo::fold(config.seed, config.runs, 64, options, run, |_, r| {
        out.accel_mse.push(mean_sq(&r.accel));
        out.gyro_mse.push(mean_sq(&r.gyro));
        out.raw_accel_mse.push(r.raw_accel);
        out.raw_gyro_mse.push(r.raw_gyro);
        out.sample_rate_hz = r.sample_rate_hz;
        for (curve, e) in [
            (&mut out.accel_squared_error_vs_time, &r.accel),
            (&mut out.gyro_squared_error_vs_time, &r.gyro),
        ] {
            if curve.len() < e.len() {
                curve.resize(e.len(), [0.0; 3]);
            }
            for (c, v) in curve.iter_mut().zip(e) {
                for i in 0..3 {
                    c[i] += v[i] * v[i];
                }
            }
        }
        Ok(())
    })?;
    // Sums → means over the completed runs.
    let completed = summary.completed.max(1) as f64;
    for curve in [
        &mut out.accel_squared_error_vs_time,
        &mut out.gyro_squared_error_vs_time,
    ] {
        curve.iter_mut().flatten().for_each(|x| *x /= completed);
    }
    out.cancelled = summary.cancelled;
    Ok(out)
}
