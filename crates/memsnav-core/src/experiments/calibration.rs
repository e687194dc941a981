//! Calibration Monte Carlo (paper §5.1, figures 3-10): MSE of every
//! estimated parameter over random parameter sets, plain LS beside the
//! errors-in-variables estimator, with the Cramér-Rao bound.

use crate::calibration::{
    accelerometer_crb, accelerometer_parameters, gyroscope_crb, gyroscope_parameters,
    CalibrationOptions, FactoredAccelerometer, FactoredGyroscope, Method,
};
use crate::montecarlo::{self, RunOptions};
use crate::random::{self, Rng};
use crate::sensors::ImuModel;
use crate::{validate, Error, Result};

use super::{set_stream, with_white_noise, MotionSource};

/// What the calibration experiment runs.
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrationExperimentConfig {
    /// Random parameter sets drawn from the preset (paper: 50).
    pub parameter_sets: usize,
    /// Monte Carlo runs per set (paper: 1000): new motion and noise each.
    pub runs_per_set: usize,
    /// Length of the calibration segment, s.
    pub duration_s: f64,
    /// IMU preset the parameter sets are drawn from.
    pub preset: String,
    /// Reference noise, per sample (module docs of [`super`]).
    pub reference_specific_force_std: f64,
    pub reference_angular_rate_std: f64,
    pub seed: u64,
}

impl Default for CalibrationExperimentConfig {
    fn default() -> Self {
        Self {
            parameter_sets: 50,
            runs_per_set: 20,
            duration_s: 300.0,
            preset: "paper-mems".into(),
            reference_specific_force_std: super::REFERENCE_SPECIFIC_FORCE_STD,
            reference_angular_rate_std: super::REFERENCE_ANGULAR_RATE_STD,
            seed: 0,
        }
    }
}

/// Per-set statistics of one sensor, each `sets × parameters`, row-major,
/// SI units, parameter order of [`crate::calibration::accelerometer_parameter_names`]
/// or [`crate::calibration::gyroscope_parameter_names`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SensorStatistics {
    pub parameters: usize,
    /// True parameter values of each set.
    pub truth: Vec<f64>,
    /// Mean square error over the runs: plain LS, errors-in-variables.
    pub mse_ls: Vec<f64>,
    pub mse_eiv: Vec<f64>,
    /// Mean error (the bias of the estimator): plain LS, errors-in-variables.
    pub mean_error_ls: Vec<f64>,
    pub mean_error_eiv: Vec<f64>,
    /// Mean over runs of the variance each calibration reported (LS, EIV).
    pub reported_variance_ls: Vec<f64>,
    pub reported_variance_eiv: Vec<f64>,
    /// Mean over runs of the Cramér-Rao bound (exact references, true parameters).
    pub crb: Vec<f64>,
}

impl SensorStatistics {
    fn new(sets: usize, parameters: usize) -> Self {
        let z = vec![0.0; sets * parameters];
        Self {
            parameters,
            truth: z.clone(),
            mse_ls: z.clone(),
            mse_eiv: z.clone(),
            mean_error_ls: z.clone(),
            mean_error_eiv: z.clone(),
            reported_variance_ls: z.clone(),
            reported_variance_eiv: z.clone(),
            crb: z,
        }
    }

    /// Turns the sums of [`Self::accumulate`] into means over each set's
    /// completed runs (NaN where none completed).
    fn normalize(&mut self, counts: &[usize]) {
        let p = self.parameters;
        for (set, &n) in counts.iter().enumerate() {
            let scale = if n > 0 { 1.0 / n as f64 } else { f64::NAN };
            for field in [
                &mut self.mse_ls,
                &mut self.mse_eiv,
                &mut self.mean_error_ls,
                &mut self.mean_error_eiv,
                &mut self.reported_variance_ls,
                &mut self.reported_variance_eiv,
                &mut self.crb,
            ] {
                field[set * p..(set + 1) * p]
                    .iter_mut()
                    .for_each(|x| *x *= scale);
            }
        }
    }

    fn accumulate(&mut self, set: usize, run: &RunStatistics, weight: f64) {
        let p = self.parameters;
        for k in 0..p {
            let i = set * p + k;
            self.mse_ls[i] += run.error_ls[k].powi(2) * weight;
            self.mse_eiv[i] += run.error_eiv[k].powi(2) * weight;
            self.mean_error_ls[i] += run.error_ls[k] * weight;
            self.mean_error_eiv[i] += run.error_eiv[k] * weight;
            self.reported_variance_ls[i] += run.variance_ls[k] * weight;
            self.reported_variance_eiv[i] += run.variance_eiv[k] * weight;
            self.crb[i] += run.crb[k] * weight;
        }
    }
}

/// Results of [`calibration_experiment`].
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrationExperiment {
    pub config: CalibrationExperimentConfig,
    pub accelerometer: SensorStatistics,
    pub gyroscope: SensorStatistics,
    /// Runs completed (fewer than asked when cancelled).
    pub completed_runs: usize,
    /// The set was cancelled: statistics cover the completed runs only
    /// (NaN for parameter sets none of whose runs completed).
    pub cancelled: bool,
}

struct RunStatistics {
    error_ls: Vec<f64>,
    error_eiv: Vec<f64>,
    variance_ls: Vec<f64>,
    variance_eiv: Vec<f64>,
    crb: Vec<f64>,
}

fn diag(m: &nalgebra::DMatrix<f64>) -> Vec<f64> {
    m.diagonal().iter().copied().collect()
}

/// Runs the calibration Monte Carlo: `parameter_sets × runs_per_set` runs;
/// run i uses set i / runs_per_set, fresh motion of `duration_s` from
/// `motion`, fresh sensor noise and fresh reference noise.
pub fn calibration_experiment(
    config: &CalibrationExperimentConfig,
    motion: &MotionSource<'_>,
    options: &RunOptions<'_>,
) -> Result<CalibrationExperiment> {
    if config.parameter_sets == 0 {
        return Err(Error::invalid("parameter_sets", "must be at least 1"));
    }
    if config.runs_per_set == 0 {
        return Err(Error::invalid("runs", "must be at least 1"));
    }
    validate::positive("duration", config.duration_s)?;
    validate::positive(
        "reference_specific_force_std",
        config.reference_specific_force_std,
    )?;
    validate::positive(
        "reference_angular_rate_std",
        config.reference_angular_rate_std,
    )?;
    let imus: Vec<ImuModel> = (0..config.parameter_sets)
        .map(|s| {
            ImuModel::preset(
                &config.preset,
                &mut random::stream(config.seed, set_stream(s)),
            )
        })
        .collect::<Result<_>>()?;
    let (sf, sw) = (
        config.reference_specific_force_std,
        config.reference_angular_rate_std,
    );
    let run = |i: usize, rng: &mut Rng| -> Result<(RunStatistics, RunStatistics)> {
        let imu = &imus[i / config.runs_per_set];
        let rate = imu.sample_rate_hz;
        let m = motion(config.duration_s, rate, rng)?;
        let readings = imu.measure(&m.specific_force_b, &m.angular_rate_b, rng)?;
        let f_ref = with_white_noise(&m.specific_force_b, sf, rng);
        let w_ref = with_white_noise(&m.angular_rate_b, sw, rng);

        let acc_truth = accelerometer_parameters(&imu.accelerometer);
        let ls = CalibrationOptions::default();
        let eiv = CalibrationOptions {
            method: Method::ErrorsInVariables,
            reference_noise_std: Some(sf),
            ..Default::default()
        };
        // One pass over the samples serves both estimators.
        let factored = FactoredAccelerometer::new(&readings.specific_force_b, &f_ref)?;
        let a_ls = factored.calibrate(&ls)?;
        let a_eiv = factored.calibrate(&eiv)?;
        let sigma_a = imu.accelerometer.noise.white_std_per_sample(rate);
        let acc = RunStatistics {
            error_ls: (accelerometer_parameters(&a_ls.model) - acc_truth)
                .as_slice()
                .to_vec(),
            error_eiv: (accelerometer_parameters(&a_eiv.model) - acc_truth)
                .as_slice()
                .to_vec(),
            variance_ls: diag(&a_ls.covariance),
            variance_eiv: diag(&a_eiv.covariance),
            crb: diag(&accelerometer_crb(
                &m.specific_force_b,
                &imu.accelerometer,
                sigma_a,
            )?),
        };

        let gyr_truth = gyroscope_parameters(&imu.gyroscope);
        let eiv = CalibrationOptions {
            method: Method::ErrorsInVariables,
            reference_noise_std: Some(sw),
            reference_specific_force_noise_std: Some(sf),
            ..Default::default()
        };
        let factored = FactoredGyroscope::new(&readings.angular_rate_b, &w_ref, &f_ref)?;
        let g_ls = factored.calibrate(&ls)?;
        let g_eiv = factored.calibrate(&eiv)?;
        let sigma_g = imu.gyroscope.noise.white_std_per_sample(rate);
        let gyr = RunStatistics {
            error_ls: (gyroscope_parameters(&g_ls.model) - gyr_truth)
                .as_slice()
                .to_vec(),
            error_eiv: (gyroscope_parameters(&g_eiv.model) - gyr_truth)
                .as_slice()
                .to_vec(),
            variance_ls: diag(&g_ls.covariance),
            variance_eiv: diag(&g_eiv.covariance),
            crb: diag(&gyroscope_crb(
                &m.angular_rate_b,
                &m.specific_force_b,
                &imu.gyroscope,
                sigma_g,
            )?),
        };
        Ok((acc, gyr))
    };
    let sets = config.parameter_sets;
    let mut accelerometer = SensorStatistics::new(sets, 15);
    let mut gyroscope = SensorStatistics::new(sets, 21);
    for (s, imu) in imus.iter().enumerate() {
        accelerometer.truth[s * 15..(s + 1) * 15]
            .copy_from_slice(accelerometer_parameters(&imu.accelerometer).as_slice());
        gyroscope.truth[s * 21..(s + 1) * 21]
            .copy_from_slice(gyroscope_parameters(&imu.gyroscope).as_slice());
    }
    let total = sets * config.runs_per_set;
    let mut counts = vec![0usize; sets];
    let summary = montecarlo::fold(config.seed, total, 64, options, run, |i, (a, g)| {
        let set = i / config.runs_per_set;
        counts[set] += 1;
        accelerometer.accumulate(set, &a, 1.0);
        gyroscope.accumulate(set, &g, 1.0);
        Ok(())
    })?;
    accelerometer.normalize(&counts);
    gyroscope.normalize(&counts);
    Ok(CalibrationExperiment {
        config: config.clone(),
        accelerometer,
        gyroscope,
        completed_runs: summary.completed,
        cancelled: summary.cancelled,
    })
}
