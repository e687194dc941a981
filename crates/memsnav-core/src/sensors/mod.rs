//! MEMS accelerometer and gyroscope error models (method §2, paper eq. 1-3),
//! their stochastic errors, and IMU grade presets.
//!
//! - [`AccelerometerModel`], [`GyroscopeModel`]: the exact forward model and
//!   `measure`, which simulates a whole series in one call.
//! - [`NoiseModel`] (module `noise`): white noise (input-referred ν),
//!   Gauss-Markov and random-walk biases (added to b), quantisation (on the
//!   output), and where each enters eq. 2-3.
//! - [`ImuModel`], [`ImuSpec`]: both triads, their rate and the one-sigma
//!   magnitudes their errors come from (the filters tune from it).
//! - [`presets`]: `"paper-mems"`, `"consumer"`, `"industrial"`, `"tactical"`,
//!   `"navigation"`, each with the sources of its figures.
//! - [`datasheet`]: a spec from a data sheet's figures in their own units
//!   (the `[imu_spec]` table), converted by the unit functions the presets
//!   use.

mod accelerometer;
pub mod datasheet;
mod gyroscope;
mod imu;
mod noise;
pub mod presets;
mod units;

pub use accelerometer::AccelerometerModel;
pub use gyroscope::GyroscopeModel;
pub use imu::{AccelerometerSpec, GyroscopeSpec, ImuModel, ImuReadings, ImuSpec};
pub use noise::{NoiseModel, NoiseProcess, NoiseSample};

use nalgebra::{Matrix3, Vector3};

use crate::limits::{MAX_SAMPLE_RATE_HZ, MAX_SENSOR_MAGNITUDE, MIN_SAMPLE_RATE_HZ};
use crate::{validate, Error, Result};

/// The IMU sample rate wherever none is given, Hz: the paper's 100 Hz
/// (method §1), used by the presets, the random trajectories and the
/// Python constructors.
pub const DEFAULT_SAMPLE_RATE_HZ: f64 = 100.0;

/// A sample rate the models simulate at: within [[`MIN_SAMPLE_RATE_HZ`],
/// [`MAX_SAMPLE_RATE_HZ`]] (10³⁰⁰ Hz gave a per-sample noise std
/// of 10¹⁴⁷, a subnormal rate an infinite sample period and NaN).
pub fn check_sample_rate(sample_rate_hz: f64) -> Result<()> {
    validate::positive("sample_rate", sample_rate_hz)?;
    if sample_rate_hz < MIN_SAMPLE_RATE_HZ {
        return Err(Error::invalid(
            "sample_rate",
            format!("{sample_rate_hz:e} Hz is below the limit of {MIN_SAMPLE_RATE_HZ:e} Hz"),
        ));
    }
    validate::at_most("sample_rate", sample_rate_hz, MAX_SAMPLE_RATE_HZ)
}

/// A = I − D − M, the output matrix of both models (method §2).
pub fn output_matrix(scale_factor: &Vector3<f64>, misalignment: &Matrix3<f64>) -> Matrix3<f64> {
    Matrix3::identity() - Matrix3::from_diagonal(scale_factor) - misalignment
}

/// Checks the parameters shared by both sensors: values within
/// ±[`MAX_SENSOR_MAGNITUDE`] (so that with readings within it the model's
/// products stay finite) and a misalignment matrix with a zero diagonal.
fn validate_common(
    bias: &Vector3<f64>,
    scale_factor: &Vector3<f64>,
    misalignment: &Matrix3<f64>,
) -> Result<()> {
    validate::bounded_vectors("bias", std::slice::from_ref(bias), MAX_SENSOR_MAGNITUDE)?;
    validate::bounded_vectors(
        "scale_factor",
        std::slice::from_ref(scale_factor),
        MAX_SENSOR_MAGNITUDE,
    )?;
    validate::bounded_matrix("misalignment", misalignment, MAX_SENSOR_MAGNITUDE)?;
    if misalignment.diagonal().iter().any(|d| *d != 0.0) {
        return Err(Error::invalid(
            "misalignment",
            format!(
                "diagonal must be zero (scale factors go in scale_factor), got {:?}",
                misalignment.diagonal().as_slice()
            ),
        ));
    }
    if output_matrix(scale_factor, misalignment)
        .determinant()
        .abs()
        < 1e-6
    {
        return Err(Error::invalid(
            "scale_factor",
            "I - D - M is singular: the sensor would not respond to its input",
        ));
    }
    Ok(())
}
