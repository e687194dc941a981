//! "Calibrated MEMS" (method §6): the sensor is calibrated at t = 0 on its
//! own segment of motion with GNSS-like references (method §3), then its
//! outputs are passed through the inversion filters (method §4) with the
//! calibrated model. The inversion and navigation experiments both do this,
//! through this one sequence.

use nalgebra::{DMatrix, Vector3};

use crate::calibration::{
    calibrate_accelerometer, calibrate_gyroscope, Calibration, CalibrationOptions, Method,
    OFF_DIAGONAL,
};
use crate::inversion::{invert_accelerometer, invert_gyroscope, InversionNoise};
use crate::random::Rng;
use crate::sensors::{
    AccelerometerModel, AccelerometerSpec, GyroscopeModel, GyroscopeSpec, ImuModel, ImuReadings,
    ImuSpec, NoiseModel,
};
use crate::{validate, Result};

use super::{with_white_noise, MotionSource};

/// Default accelerometer random-walk increment per sample, m/s²: "set high
/// so fast motion is followed" (method §4): 0.1 m/s² per 10 ms, a jerk of
/// 10 m/s³, above what a land vehicle produces, several times the
/// paper-mems noise, so the filter mostly follows the outputs.
pub const DEFAULT_ACCEL_PROCESS_STD: f64 = 0.1;
/// Default gyroscope random-walk increment per sample, rad/s (1 °/s per
/// 10 ms: angular accelerations of 100 °/s²).
pub const DEFAULT_GYRO_PROCESS_STD: f64 = 1.0 * std::f64::consts::PI / 180.0;

/// How the calibration segment is made and solved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentCalibration {
    /// Length of the segment, s.
    pub duration_s: f64,
    /// Reference specific-force noise per sample (module docs of
    /// [`super`]), m/s².
    pub reference_specific_force_std: f64,
    /// Reference angular-rate noise per sample, rad/s.
    pub reference_angular_rate_std: f64,
    /// Estimator (default errors-in-variables: plain LS with noisy
    /// references leaves scale-factor biases that dominate the MSE).
    pub method: Method,
}

impl Default for SegmentCalibration {
    fn default() -> Self {
        Self {
            duration_s: 300.0,
            reference_specific_force_std: super::REFERENCE_SPECIFIC_FORCE_STD,
            reference_angular_rate_std: super::REFERENCE_ANGULAR_RATE_STD,
            method: Method::ErrorsInVariables,
        }
    }
}

/// Random-walk increments per sample of the two inversion filters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InversionProcess {
    /// Accelerometer filter, m/s².
    pub accel_process_std: f64,
    /// Gyroscope filter, rad/s.
    pub gyro_process_std: f64,
}

impl Default for InversionProcess {
    fn default() -> Self {
        Self {
            accel_process_std: DEFAULT_ACCEL_PROCESS_STD,
            gyro_process_std: DEFAULT_GYRO_PROCESS_STD,
        }
    }
}

impl InversionProcess {
    /// Both process stds positive and finite (the error names the one
    /// that is not).
    pub fn validate(&self) -> Result<()> {
        validate::positive("accel_process_std", self.accel_process_std)?;
        validate::positive("gyro_process_std", self.gyro_process_std)
    }
}

impl SegmentCalibration {
    /// Checks every setting; errors name the Python keyword.
    pub fn validate(&self) -> Result<()> {
        validate::positive("calibration_duration", self.duration_s)?;
        crate::limits::duration("calibration_duration", self.duration_s)?;
        super::validate_reference_noise(
            self.reference_specific_force_std,
            self.reference_angular_rate_std,
        )
    }

    /// Calibrates `imu` on a fresh segment from `motion`. Draws, in order:
    /// the motion, the sensor's outputs, the specific-force and the
    /// angular-rate reference noise.
    pub fn calibrate(
        &self,
        imu: &ImuModel,
        motion: &MotionSource<'_>,
        rng: &mut Rng,
    ) -> Result<CalibratedImu> {
        let rate = imu.sample_rate_hz;
        let (sf, sw) = (
            self.reference_specific_force_std,
            self.reference_angular_rate_std,
        );
        let segment = motion(self.duration_s, rate, rng)?;
        let readings = imu.measure(&segment.specific_force_b, &segment.angular_rate_b, rng)?;
        let f_ref = with_white_noise(&segment.specific_force_b, sf, rng);
        let w_ref = with_white_noise(&segment.angular_rate_b, sw, rng);
        let eiv = self.method == Method::ErrorsInVariables;
        let accelerometer = calibrate_accelerometer(
            &readings.specific_force_b,
            &f_ref,
            &CalibrationOptions {
                method: self.method,
                reference_noise_std: eiv.then_some(sf),
                ..Default::default()
            },
        )?;
        let gyroscope = calibrate_gyroscope(
            &readings.angular_rate_b,
            &w_ref,
            &f_ref,
            &CalibrationOptions {
                method: self.method,
                reference_noise_std: eiv.then_some(sw),
                reference_specific_force_noise_std: eiv.then_some(sf),
                ..Default::default()
            },
        )?;
        Ok(CalibratedImu {
            accelerometer,
            gyroscope,
        })
    }
}

/// The calibration of both triads of one IMU.
#[derive(Debug, Clone)]
pub struct CalibratedImu {
    /// The accelerometer's calibration.
    pub accelerometer: Calibration<AccelerometerModel>,
    /// The gyroscope's calibration.
    pub gyroscope: Calibration<GyroscopeModel>,
}

impl CalibratedImu {
    /// Γ̂ and Ω̂ from `readings` of `imu` by the two inversion filters with
    /// the calibrated models; the measurement noise is the sensor's white
    /// noise per sample, the process noise `process`.
    pub fn invert(
        &self,
        imu: &ImuModel,
        readings: &ImuReadings,
        process: &InversionProcess,
    ) -> Result<ImuReadings> {
        let rate = imu.sample_rate_hz;
        let accel_noise = InversionNoise {
            process_std: Vector3::repeat(process.accel_process_std),
            measurement_std: Vector3::repeat(imu.accelerometer.noise.white_std_per_sample(rate)),
        };
        let gyro_noise = InversionNoise {
            process_std: Vector3::repeat(process.gyro_process_std),
            measurement_std: Vector3::repeat(imu.gyroscope.noise.white_std_per_sample(rate)),
        };
        let f_hat = invert_accelerometer(
            &readings.specific_force_b,
            &self.accelerometer.model,
            &accel_noise,
        )?;
        let w_hat = invert_gyroscope(
            &readings.angular_rate_b,
            &f_hat.estimate,
            &self.gyroscope.model,
            &gyro_noise,
        )?;
        Ok(ImuReadings {
            specific_force_b: f_hat.estimate,
            angular_rate_b: w_hat.estimate,
        })
    }

    /// The spec a filter on the inverted outputs is tuned from
    /// ([`calibrated_spec`]), with the sensor's own noise from `raw`.
    pub fn spec(&self, raw: &ImuSpec) -> ImuSpec {
        calibrated_spec(
            &self.accelerometer.covariance,
            &self.gyroscope.covariance,
            raw.accelerometer.noise,
            raw.gyroscope.noise,
        )
    }
}

fn rms(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v * v, n + 1));
    (sum / n.max(1) as f64).sqrt()
}

/// The one-sigma of parameter `k` of a covariance.
fn std(covariance: &DMatrix<f64>, k: usize) -> f64 {
    covariance[(k, k)].max(0.0).sqrt()
}

/// The spec that describes what a calibration leaves uncertain, for a
/// land vehicle, from the calibrations' parameter covariances (orders of
/// [`crate::calibration::accelerometer_parameters`] and
/// [`crate::calibration::gyroscope_parameters`]) and the sensors' noise.
///
/// A filter on calibrated outputs absorbs the spec's terms as uncertainty
/// ([`crate::coupling::FilterTuning::from_imu_spec`]): the part of each
/// term that multiplies a constant input widens the bias uncertainty, the
/// part that multiplies the varying inputs becomes white noise, for
/// isotropic vehicle dynamics. On a land vehicle the vertical specific
/// force stays near −g, so the w-axis scale factor and nonlinearity, the
/// misalignments onto Γw and the g-sensitivity to Γw act as biases (which
/// the filter estimates; their stds are also huge, because the motion
/// cannot separate them from the biases, while their sum at −g is well
/// determined). Taken per term and isotropically they would be charged to
/// the horizontal dynamics and drown the calibrated sensor in noise. So:
/// - bias: the calibrated biases' RMS std, all axes (initial uncertainty);
/// - accelerometer scale factor, nonlinearity: the u and v axes';
/// - misalignments: the terms whose input varies (accelerometer M_ij with
///   j = u, v; gyroscope all, the rates vary about zero on every axis);
/// - g-sensitivity: the terms on Γu, Γv.
pub fn calibrated_spec(
    accelerometer_covariance: &DMatrix<f64>,
    gyroscope_covariance: &DMatrix<f64>,
    accelerometer_noise: NoiseModel,
    gyroscope_noise: NoiseModel,
) -> ImuSpec {
    let (ca, cg) = (accelerometer_covariance, gyroscope_covariance);
    let horizontal = [0usize, 1];
    // Misalignment M_ij sits at 6 + its position in OFF_DIAGONAL.
    let varying_input_misalignments = OFF_DIAGONAL
        .iter()
        .enumerate()
        .filter(|(_, &(_, j))| j != 2)
        .map(|(k, _)| std(ca, 6 + k));
    ImuSpec {
        accelerometer: AccelerometerSpec {
            bias_std: rms((0..3).map(|k| std(ca, k))),
            scale_factor_std: rms(horizontal.iter().map(|&i| std(ca, 3 + i))),
            misalignment_std: rms(varying_input_misalignments),
            nonlinearity_std: rms(horizontal.iter().map(|&i| std(ca, 12 + i))),
            noise: accelerometer_noise,
        },
        gyroscope: GyroscopeSpec {
            bias_std: rms((0..3).map(|k| std(cg, k))),
            scale_factor_std: rms((3..6).map(|k| std(cg, k))),
            misalignment_std: rms((6..12).map(|k| std(cg, k))),
            // K_il at 12 + 3i + l.
            g_sensitivity_std: rms(
                (0..3).flat_map(|i| horizontal.iter().map(move |&l| std(cg, 12 + 3 * i + l)))
            ),
            noise: gyroscope_noise,
        },
    }
}
