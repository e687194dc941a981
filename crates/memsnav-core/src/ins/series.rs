//! The checks every consumer of IMU data and of a navigation start runs:
//! `strapdown` ([`super::integrate`]) and both coupled filters take their
//! samples and their start through these, so a series one refuses the
//! others refuse too (the filters integrated across a 10⁶ s gap
//! that `strapdown` refused, and ended 4.7×10¹⁵ m off).

use nalgebra::Vector3;

use super::{ImuIncrement, ImuSample, NavState};
use crate::geodesy::domain::{check_position_ecef, check_speed};
use crate::limits::MAX_SENSOR_MAGNITUDE;
use crate::{validate, Error, Result};

/// A series of three-axis values.
type Vectors = Vec<Vector3<f64>>;

/// A series of raw IMU samples (instantaneous values at `time_s`), or of
/// an integrating IMU's increments.
#[derive(Debug, Clone, Copy)]
pub struct ImuData<'a> {
    /// Sample times, s, strictly increasing.
    pub time_s: &'a [f64],
    /// Measured specific force f̃_ib^b, m/s².
    pub specific_force_b: &'a [Vector3<f64>],
    /// Measured angular rate ω̃_ib^b, rad/s.
    pub angular_rate_b: &'a [Vector3<f64>],
    /// An integrating IMU's output: `increments[k − 1]` over
    /// (t_{k−1}, t_k], which the coupled filters then integrate by the
    /// increments mechanization ([`super::step_increments`]). The samples
    /// hold their means (sample k the mean over the interval ending at
    /// t_k, sample 0 that of the first), for what looks at samples
    /// (standstill tests, levelling). None: the samples are the data.
    pub increments: Option<&'a [ImuIncrement]>,
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
        validate::bounded_vectors("angular_rate", self.angular_rate_b, MAX_SENSOR_MAGNITUDE)?;
        if let Some(increments) = self.increments {
            validate::same_length(
                "delta_v",
                increments.len(),
                "time less one",
                self.time_s.len() - 1,
            )?;
            let (delta_v, delta_theta): (Vectors, Vectors) = increments
                .iter()
                .map(|d| (d.delta_velocity_b, d.delta_angle_b))
                .unzip();
            validate::finite_vectors("delta_v", &delta_v)?;
            validate::finite_vectors("delta_theta", &delta_theta)?;
        }
        Ok(())
    }

    /// Samples from an integrating IMU's increments over the intervals of
    /// `time_s` (`delta_v` m/s and `delta_theta` rad, one row fewer than
    /// the times): the mean specific force and rate of each interval, at
    /// its end (and the first's at `time_s[0]`), to go with the
    /// increments in [`ImuData::increments`]. Checked as the readers check
    /// them: finite, and within the sensor limits as means.
    pub fn means_of_increments(
        time_s: &[f64],
        increments: &[ImuIncrement],
    ) -> Result<(Vectors, Vectors)> {
        validate::increasing_times("time", time_s)?;
        validate::same_length(
            "delta_v",
            increments.len(),
            "time less one",
            time_s.len() - 1,
        )?;
        let mut specific_force = Vec::with_capacity(time_s.len());
        let mut angular_rate = Vec::with_capacity(time_s.len());
        for (k, d) in increments.iter().enumerate() {
            let dt = time_s[k + 1] - time_s[k];
            specific_force.push(d.delta_velocity_b / dt);
            angular_rate.push(d.delta_angle_b / dt);
        }
        if let (Some(&f), Some(&w)) = (specific_force.first(), angular_rate.first()) {
            specific_force.insert(0, f);
            angular_rate.insert(0, w);
        }
        validate::bounded_vectors("delta_v", &specific_force, MAX_SENSOR_MAGNITUDE)?;
        validate::bounded_vectors("delta_theta", &angular_rate, MAX_SENSOR_MAGNITUDE)?;
        Ok((specific_force, angular_rate))
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
