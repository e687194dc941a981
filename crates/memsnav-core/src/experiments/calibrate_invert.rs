//! "Calibrated MEMS" (method §6): the sensor is calibrated at t = 0 on its
//! own segment of motion with GNSS-like references (method §3), then its
//! outputs are passed through the inversion filters (method §4) with the
//! calibrated model. The inversion and navigation experiments both do this,
//! through this one sequence.

use nalgebra::Vector3;

use crate::calibration::{
    calibrate_accelerometer, calibrate_gyroscope, Calibration, CalibrationOptions, Method,
};
use crate::inversion::{invert_accelerometer, invert_gyroscope, InversionNoise};
use crate::random::Rng;
use crate::sensors::{AccelerometerModel, GyroscopeModel, ImuModel, ImuReadings, ImuSpec};
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
    /// Reference noise per sample (module docs of [`super`]), m/s² and rad/s.
    pub reference_specific_force_std: f64,
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
    pub fn validate(&self) -> Result<()> {
        validate::positive("accel_process_std", self.accel_process_std)?;
        validate::positive("gyro_process_std", self.gyro_process_std)
    }
}

impl SegmentCalibration {
    /// Checks every setting; errors name the Python keyword.
    pub fn validate(&self) -> Result<()> {
        validate::positive("calibration_duration", self.duration_s)?;
        validate::positive(
            "reference_specific_force_std",
            self.reference_specific_force_std,
        )?;
        validate::positive(
            "reference_angular_rate_std",
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
    pub accelerometer: Calibration<AccelerometerModel>,
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

    /// The spec a filter on the inverted outputs is tuned from: the RMS of
    /// each term's one-sigma calibration uncertainty (as
    /// [`ImuSpec::of_models`] takes the RMS of a model's values) and the
    /// sensor's own noise `raw`.
    pub fn spec(&self, raw: &ImuSpec, rate_hz: f64) -> ImuSpec {
        let mut spec = ImuSpec::of_models(&self.accelerometer.std, &self.gyroscope.std, rate_hz);
        spec.accelerometer.noise = raw.accelerometer.noise;
        spec.gyroscope.noise = raw.gyroscope.noise;
        spec
    }
}
