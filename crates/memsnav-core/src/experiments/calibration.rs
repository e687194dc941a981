//! Calibration Monte Carlo (paper §5.1, figures 3-10): MSE of every
//! estimated parameter over random parameter sets, plain LS beside the
//! errors-in-variables estimator, with the Cramér-Rao bound of the problem
//! solved: noisy references, the errors-in-variables model
//! ([`crate::calibration`] module docs), at each run's true inputs.

use crate::calibration::{
    accelerometer_crb, accelerometer_parameters, gyroscope_crb, gyroscope_parameters,
    CalibrationOptions, FactoredAccelerometer, FactoredGyroscope, Method, ReferenceNoise,
};
use serde::{Deserialize, Serialize};

use crate::montecarlo::{self, FoldSummary, MonteCarlo, RunOptions};
use crate::random::{self, Rng};
use crate::sensors::ImuModel;
use crate::{validate, Error, Result};

use super::{with_white_noise, MotionSource};

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
    /// Reference angular-rate noise std per sample, rad/s.
    pub reference_angular_rate_std: f64,
    /// The seed every run's draws derive from.
    pub seed: u64,
}

impl CalibrationExperimentConfig {
    /// Checks every setting; errors name the Python keyword.
    pub fn validate(&self) -> Result<()> {
        if self.parameter_sets == 0 {
            return Err(Error::invalid("parameter_sets", "must be at least 1"));
        }
        if self.runs_per_set == 0 {
            return Err(Error::invalid("runs", "must be at least 1"));
        }
        crate::limits::monte_carlo(
            None,
            &[
                ("parameter_sets", self.parameter_sets),
                ("runs", self.runs_per_set),
            ],
        )?;
        validate::positive("duration", self.duration_s)?;
        crate::limits::duration("duration", self.duration_s)?;
        super::validate_preset(&self.preset)?;
        super::validate_reference_noise(
            self.reference_specific_force_std,
            self.reference_angular_rate_std,
        )
    }
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
            seed: crate::random::DEFAULT_SEED,
        }
    }
}

/// Per-set statistics of one sensor, each `sets × parameters`, row-major,
/// SI units, parameter order of [`crate::calibration::accelerometer_parameter_names`]
/// or [`crate::calibration::gyroscope_parameter_names`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SensorStatistics {
    /// How many parameters the sensor's calibration has.
    pub parameters: usize,
    /// True parameter values of each set.
    pub truth: Vec<f64>,
    /// Mean square error over the runs: plain LS, errors-in-variables.
    pub mse_ls: Vec<f64>,
    /// Mean square error over the runs, errors-in-variables.
    pub mse_eiv: Vec<f64>,
    /// Mean error (the bias of the estimator): plain LS, errors-in-variables.
    pub mean_error_ls: Vec<f64>,
    /// Mean error over the runs, errors-in-variables.
    pub mean_error_eiv: Vec<f64>,
    /// Mean over runs of the variance each calibration reported (LS, EIV).
    pub reported_variance_ls: Vec<f64>,
    /// Mean over runs of the variance each errors-in-variables calibration reported.
    pub reported_variance_eiv: Vec<f64>,
    /// Mean over runs of the Cramér-Rao bound (errors-in-variables: the
    /// runs' reference noise, true inputs and parameters).
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
    /// The configuration that ran.
    pub config: CalibrationExperimentConfig,
    /// The accelerometer's statistics.
    pub accelerometer: SensorStatistics,
    /// The gyroscope's statistics.
    pub gyroscope: SensorStatistics,
    /// Runs completed (fewer than asked when cancelled).
    pub completed_runs: usize,
    /// The set was cancelled: statistics cover the completed runs only
    /// (NaN for parameter sets none of whose runs completed).
    pub cancelled: bool,
}

/// One run's errors, reported variances and bound for one sensor.
#[derive(Serialize, Deserialize)]
pub struct RunStatistics {
    error_ls: Vec<f64>,
    error_eiv: Vec<f64>,
    variance_ls: Vec<f64>,
    variance_eiv: Vec<f64>,
    crb: Vec<f64>,
}

fn diag(m: &nalgebra::DMatrix<f64>) -> Vec<f64> {
    m.diagonal().iter().copied().collect()
}

/// The calibration Monte Carlo as runs and a fold ([`MonteCarlo`]).
pub struct CalibrationRuns<'a> {
    config: &'a CalibrationExperimentConfig,
    motion: &'a MotionSource<'a>,
    /// The parameter sets, drawn from their own streams.
    imus: Vec<ImuModel>,
}

impl<'a> CalibrationRuns<'a> {
    /// Checks the configuration and draws the parameter sets.
    pub fn new(
        config: &'a CalibrationExperimentConfig,
        motion: &'a MotionSource<'a>,
    ) -> Result<Self> {
        config.validate()?;
        let imus = (0..config.parameter_sets)
            .map(|s| {
                ImuModel::preset(
                    &config.preset,
                    &mut random::stream(config.seed, random::parameter_set_stream(s)),
                )
            })
            .collect::<Result<_>>()?;
        Ok(Self {
            config,
            motion,
            imus,
        })
    }
}

/// The running sums of [`CalibrationRuns`]: per sensor, and the completed
/// runs per set.
pub struct CalibrationFold {
    accelerometer: SensorStatistics,
    gyroscope: SensorStatistics,
    counts: Vec<usize>,
}

impl MonteCarlo for CalibrationRuns<'_> {
    /// Accelerometer, gyroscope.
    type Run = (RunStatistics, RunStatistics);
    type Fold = CalibrationFold;
    type Output = CalibrationExperiment;

    fn seed(&self) -> u64 {
        self.config.seed
    }
    fn runs(&self) -> usize {
        self.config.parameter_sets * self.config.runs_per_set
    }
    fn batch(&self) -> usize {
        64
    }
    /// Run i uses set i / runs_per_set, fresh motion of `duration_s`,
    /// fresh sensor noise and fresh reference noise.
    fn run(&self, i: usize, rng: &mut Rng) -> Result<Self::Run> {
        let config = self.config;
        let (sf, sw) = (
            config.reference_specific_force_std,
            config.reference_angular_rate_std,
        );
        let reference = ReferenceNoise {
            specific_force_std: sf,
            angular_rate_std: sw,
        };
        let imu = &self.imus[i / config.runs_per_set];
        let rate = imu.sample_rate_hz;
        let m = (self.motion)(config.duration_s, rate, rng)?;
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
                &reference,
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
                &reference,
            )?),
        };
        Ok((acc, gyr))
    }
    fn start(&self) -> CalibrationFold {
        let sets = self.config.parameter_sets;
        let mut accelerometer = SensorStatistics::new(sets, 15);
        let mut gyroscope = SensorStatistics::new(sets, 21);
        for (s, imu) in self.imus.iter().enumerate() {
            accelerometer.truth[s * 15..(s + 1) * 15]
                .copy_from_slice(accelerometer_parameters(&imu.accelerometer).as_slice());
            gyroscope.truth[s * 21..(s + 1) * 21]
                .copy_from_slice(gyroscope_parameters(&imu.gyroscope).as_slice());
        }
        CalibrationFold {
            accelerometer,
            gyroscope,
            counts: vec![0; sets],
        }
    }
    fn push(&self, fold: &mut CalibrationFold, i: usize, (a, g): Self::Run) -> Result<()> {
        let set = i / self.config.runs_per_set;
        fold.counts[set] += 1;
        fold.accelerometer.accumulate(set, &a, 1.0);
        fold.gyroscope.accumulate(set, &g, 1.0);
        Ok(())
    }
    fn finish(
        &self,
        mut fold: CalibrationFold,
        summary: FoldSummary,
    ) -> Result<CalibrationExperiment> {
        fold.accelerometer.normalize(&fold.counts);
        fold.gyroscope.normalize(&fold.counts);
        Ok(CalibrationExperiment {
            config: self.config.clone(),
            accelerometer: fold.accelerometer,
            gyroscope: fold.gyroscope,
            completed_runs: summary.completed,
            cancelled: summary.cancelled,
        })
    }
}

/// Runs the calibration Monte Carlo: `parameter_sets × runs_per_set` runs
/// ([`CalibrationRuns`]) over a rayon pool.
pub fn calibration_experiment(
    config: &CalibrationExperimentConfig,
    motion: &MotionSource<'_>,
    options: &RunOptions<'_>,
) -> Result<CalibrationExperiment> {
    montecarlo::execute(&CalibrationRuns::new(config, motion)?, options)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibration::{accelerometer_parameter_names, gyroscope_parameter_names};
    use crate::experiments::motion;

    fn one_set(runs: usize, duration_s: f64) -> CalibrationExperiment {
        let config = CalibrationExperimentConfig {
            parameter_sets: 1,
            runs_per_set: runs,
            duration_s,
            seed: 3,
            ..Default::default()
        };
        let options = RunOptions {
            threads: Some(2),
            ..Default::default()
        };
        calibration_experiment(&config, &motion::land_vehicle, &options).unwrap()
    }

    /// The errors-in-variables bound is attained where the theory says
    /// (module docs of [`crate::calibration`]): the corrected-score
    /// estimator's MSE equals it up to Fuller's term, a share
    /// σ_ref²/var(input) ≈ 1e-3 here, for every parameter — and keeps
    /// equalling it as the data grow (the bound shrinks as 1/n). Plain LS
    /// does not: its attenuation bias of the scale factors (σ_ref²/var(input)
    /// of 1) stays while the bound shrinks, so its efficiency MSE/CRB grows
    /// with the length of the data.
    #[test]
    fn errors_in_variables_attains_the_noisy_reference_bound() {
        let runs = 400;
        let short = one_set(runs, 60.0);
        let long = one_set(runs, 240.0);
        // The MSE of 400 runs has a relative std of √(2/400) ≈ 7 %: ±25 % is 3.5σ.
        for (stats, names) in [
            (&long.accelerometer, accelerometer_parameter_names()),
            (&long.gyroscope, gyroscope_parameter_names()),
        ] {
            for (k, name) in names.iter().enumerate() {
                let efficiency = stats.mse_eiv[k] / stats.crb[k];
                assert!(
                    (efficiency - 1.0).abs() < 0.25,
                    "{name}: EIV MSE {:e} vs bound {:e}",
                    stats.mse_eiv[k],
                    stats.crb[k]
                );
            }
        }
        // The bound shrinks with the data (about 4x for 4x the samples).
        let ratio = short.gyroscope.crb[3] / long.gyroscope.crb[3];
        assert!((2.5..6.0).contains(&ratio), "{ratio}");
        // Plain LS scale factors of the axes whose attenuation bias
        // dominates (u: forward acceleration; p, q: roll and pitch rates):
        // far from the bound, and further with more data.
        for (short_stats, long_stats, axes) in [
            (&short.accelerometer, &long.accelerometer, 3..4),
            (&short.gyroscope, &long.gyroscope, 3..5),
        ] {
            for k in axes {
                let e_short = short_stats.mse_ls[k] / short_stats.crb[k];
                let e_long = long_stats.mse_ls[k] / long_stats.crb[k];
                assert!(
                    e_long > 2.0 && e_long > 1.5 * e_short,
                    "{k}: {e_short} then {e_long}"
                );
            }
        }
    }
}
