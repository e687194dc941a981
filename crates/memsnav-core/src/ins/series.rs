//! The checks every consumer of IMU data and of a navigation start runs:
//! `strapdown` ([`super::integrate`]) and both coupled filters take their
//! samples and their start through these, so a series one refuses the
//! others refuse too (issue 30: the filters integrated across a 10⁶ s gap
//! that `strapdown` refused, and ended 4.7×10¹⁵ m off).

use nalgebra::Vector3;

use super::{ImuSample, NavState};
use crate::geodesy::domain::{check_position_ecef, check_speed};
use crate::limits::MAX_SENSOR_MAGNITUDE;
use crate::{validate, Error, Result};

/// A series of raw IMU samples (instantaneous values at `time_s`).
#[derive(Debug, Clone, Copy)]
pub struct ImuData<'a> {
    /// Sample times, s, strictly increasing.
    pub time_s: &'a [f64],
    /// Measured specific force f̃_ib^b, m/s².
    pub specific_force_b: &'a [Vector3<f64>],
    /// Measured angular rate ω̃_ib^b, rad/s.
    pub angular_rate_b: &'a [Vector3<f64>],
}

impl ImuData<'_> {
    /// At least two samples; increasing finite times without a gap the
    /// integration cannot bridge ([`validate::imu_time_gaps`]); series of
    /// the same length whose values are within ±[`MAX_SENSOR_MAGNITUDE`]
    /// (10⁵ g, 10⁶ rad/s: beyond any sensor, and far enough below the
    /// float range that the mechanization's products stay finite).
    pub fn validate(&self) -> Result<()> {
        if self.time_s.len() < 2 {
            return Err(Error::invalid(
                "time",
                format!("needs at least two IMU samples, got {}", self.time_s.len()),
            ));
        }
        validate::increasing_times("time", self.time_s)?;
        validate::imu_time_gaps("time", self.time_s)?;
        validate::same_length(
            "specific_force",
            self.specific_force_b.len(),
            "time",
            self.time_s.len(),
        )?;
        validate::same_length(
            "angular_rate",
            self.angular_rate_b.len(),
            "time",
            self.time_s.len(),
        )?;
        validate::bounded_vectors(
            "specific_force",
            self.specific_force_b,
            MAX_SENSOR_MAGNITUDE,
        )?;
        validate::bounded_vectors("angular_rate", self.angular_rate_b, MAX_SENSOR_MAGNITUDE)
    }

    /// Sample `k`.
    pub fn sample(&self, k: usize) -> ImuSample {
        ImuSample {
            specific_force_b: self.specific_force_b[k],
            angular_rate_b: self.angular_rate_b[k],
        }
    }
}

impl NavState {
    /// A start the mechanization can run from: a position in the geodesy's
    /// domain, a velocity within its speed limit, a rotation matrix for the
    /// attitude. `prefix` goes before the field names in the error
    /// (`"initial."` for the filters' start, `""` for `strapdown`'s).
    pub fn validate(&self, prefix: &str) -> Result<()> {
        let position = format!("{prefix}position_ecef");
        validate::finite_vectors(&position, std::slice::from_ref(&self.position_ecef))?;
        check_position_ecef(&position, std::slice::from_ref(&self.position_ecef))?;
        let velocity = format!("{prefix}velocity_ecef");
        validate::finite_vectors(&velocity, std::slice::from_ref(&self.velocity_ecef))?;
        check_speed(&velocity, std::slice::from_ref(&self.velocity_ecef))?;
        validate::rotation(&format!("{prefix}attitude"), &self.c_b_e)
    }
}
