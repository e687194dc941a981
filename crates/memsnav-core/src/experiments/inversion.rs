//! Inversion Monte Carlo (paper §5.2, figures 11-12): each run draws an IMU
//! from the preset, calibrates it on its own segment with GNSS-like
//! references, then inverts the outputs of a fresh random trajectory with
//! the two EKFs of method §4; MSE of Γ̂ and Ω̂ against the truth.

use nalgebra::Vector3;

use serde::{Deserialize, Serialize};

use crate::montecarlo::{self, FoldSummary, MonteCarlo, RunOptions};
use crate::random::Rng;
use crate::sensors::ImuModel;
use crate::{validate, Error, Result};

use super::calibrate_invert::{InversionProcess, SegmentCalibration};
use super::MotionSource;

/// What the inversion experiment runs.
#[derive(Debug, Clone, PartialEq)]
pub struct InversionExperimentConfig {
    /// Monte Carlo runs (paper: 300), each with its own IMU draw and trajectory.
    pub runs: usize,
    /// Length of the inverted trajectory, s (paper: 120).
    pub duration_s: f64,
    /// IMU preset each run's IMU is drawn from.
    pub preset: String,
    /// The calibration on its own segment before the run (default: 300 s,
    /// GNSS-like references, errors-in-variables).
    pub calibration: SegmentCalibration,
    /// Random-walk increments per sample of the two filters.
    pub process: InversionProcess,
    /// The seed every run's draws derive from.
    pub seed: u64,
}

impl Default for InversionExperimentConfig {
    fn default() -> Self {
        Self {
            runs: 50,
            duration_s: 120.0,
            preset: "paper-mems".into(),
            calibration: SegmentCalibration::default(),
            process: InversionProcess::default(),
            seed: crate::random::DEFAULT_SEED,
        }
    }
}

impl InversionExperimentConfig {
    /// Checks every setting; errors name the Python keyword.
    pub fn validate(&self) -> Result<()> {
        if self.runs == 0 {
            return Err(Error::invalid("runs", "must be at least 1"));
        }
        crate::limits::monte_carlo(None, &[("runs", self.runs)])?;
        validate::positive("duration", self.duration_s)?;
        crate::limits::duration("duration", self.duration_s)?;
        super::validate_preset(&self.preset)?;
        self.calibration.validate()?;
        self.process.validate()
    }
}

/// Results of [`inversion_experiment`], SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct InversionExperiment {
    /// The configuration that ran.
    pub config: InversionExperimentConfig,
    /// Per run and axis: mean over the trajectory of (Γ̂ − Γ)², (m/s²)².
    pub accel_mse: Vec<[f64; 3]>,
    /// Per run and axis: mean of (Ω̂ − Ω)², (rad/s)².
    pub gyro_mse: Vec<[f64; 3]>,
    /// The same for the raw outputs taken as Γ and Ω (no calibration).
    pub raw_accel_mse: Vec<[f64; 3]>,
    /// The same for the gyro, (rad/s)².
    pub raw_gyro_mse: Vec<[f64; 3]>,
    /// Per sample and axis, mean over runs of the squared errors of Γ̂ and Ω̂.
    pub accel_squared_error_vs_time: Vec<[f64; 3]>,
    /// The same for Ω̂, (rad/s)².
    pub gyro_squared_error_vs_time: Vec<[f64; 3]>,
    /// Sample rate of the series, Hz.
    pub sample_rate_hz: f64,
    /// The set was cancelled: the arrays cover the completed runs only.
    pub cancelled: bool,
}

/// One run's inversion errors per sample and raw MSE.
#[derive(Serialize, Deserialize)]
pub struct RunResult {
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

/// The inversion Monte Carlo as runs and a fold ([`MonteCarlo`]).
pub struct InversionRuns<'a> {
    config: &'a InversionExperimentConfig,
    motion: &'a MotionSource<'a>,
}

impl<'a> InversionRuns<'a> {
    /// Checks the configuration.
    pub fn new(
        config: &'a InversionExperimentConfig,
        motion: &'a MotionSource<'a>,
    ) -> Result<Self> {
        config.validate()?;
        Ok(Self { config, motion })
    }
}

impl MonteCarlo for InversionRuns<'_> {
    type Run = RunResult;
    /// The result, with sums in the per-sample curves until `finish`.
    type Fold = InversionExperiment;
    type Output = InversionExperiment;

    fn seed(&self) -> u64 {
        self.config.seed
    }
    fn runs(&self) -> usize {
        self.config.runs
    }
    fn batch(&self) -> usize {
        64
    }
    /// Run i draws, from its stream: the IMU, its calibration (segment,
    /// outputs, references), the inverted motion and the outputs along it.
    fn run(&self, _: usize, rng: &mut Rng) -> Result<RunResult> {
        let (config, motion) = (self.config, self.motion);
        let imu = ImuModel::preset(&config.preset, rng)?;
        // Calibration on its own segment (method §6: at t = 0, before the run).
        let calibrated = config.calibration.calibrate(&imu, motion, rng)?;
        // Inversion of a fresh trajectory.
        let m = motion(config.duration_s, imu.sample_rate_hz, rng)?;
        let readings = imu.measure(&m.specific_force_b, &m.angular_rate_b, rng)?;
        let estimate = calibrated.invert(&imu, &readings, &config.process)?;
        Ok(RunResult {
            accel: errors(&estimate.specific_force_b, &m.specific_force_b),
            gyro: errors(&estimate.angular_rate_b, &m.angular_rate_b),
            raw_accel: mean_sq(&errors(&readings.specific_force_b, &m.specific_force_b)),
            raw_gyro: mean_sq(&errors(&readings.angular_rate_b, &m.angular_rate_b)),
            sample_rate_hz: imu.sample_rate_hz,
        })
    }
    fn start(&self) -> InversionExperiment {
        let runs = self.config.runs;
        InversionExperiment {
            config: self.config.clone(),
            accel_mse: Vec::with_capacity(runs),
            gyro_mse: Vec::with_capacity(runs),
            raw_accel_mse: Vec::with_capacity(runs),
            raw_gyro_mse: Vec::with_capacity(runs),
            accel_squared_error_vs_time: Vec::new(),
            gyro_squared_error_vs_time: Vec::new(),
            sample_rate_hz: 0.0,
            cancelled: false,
        }
    }
    fn push(&self, fold: &mut InversionExperiment, _: usize, r: RunResult) -> Result<()> {
        fold.accel_mse.push(mean_sq(&r.accel));
        fold.gyro_mse.push(mean_sq(&r.gyro));
        fold.raw_accel_mse.push(r.raw_accel);
        fold.raw_gyro_mse.push(r.raw_gyro);
        fold.sample_rate_hz = r.sample_rate_hz;
        for (curve, e) in [
            (&mut fold.accel_squared_error_vs_time, &r.accel),
            (&mut fold.gyro_squared_error_vs_time, &r.gyro),
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
    }
    fn finish(
        &self,
        mut out: InversionExperiment,
        summary: FoldSummary,
    ) -> Result<InversionExperiment> {
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
}

/// Runs the inversion Monte Carlo ([`InversionRuns`]) over a rayon pool.
pub fn inversion_experiment(
    config: &InversionExperimentConfig,
    motion: &MotionSource<'_>,
    options: &RunOptions<'_>,
) -> Result<InversionExperiment> {
    montecarlo::execute(&InversionRuns::new(config, motion)?, options)
}
