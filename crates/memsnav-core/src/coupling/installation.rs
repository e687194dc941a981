//! How the IMU sits in the vehicle and relative to the GNSS receiver, as
//! estimated constants: the antenna lever arm, the IMU-to-GNSS
//! time offset, the latency of the fixes' velocity and the mounting
//! boresight left after the configured mounting. Each starts from the
//! configuration's value with the configuration's σ; a filter with the
//! installation block ([`crate::filter::state::Installation`]) estimates
//! them, one without keeps them fixed.
//!
//! Their measurement rows (errors are estimate − truth, a GNSS measurement
//! tagged t is compared with the prediction at IMU time t − t_o):
//!
//! ```text
//! r̂_a(t − t̂_o) − r_a(t − t_o)  ≈ δr_a + Ĉ δl − v_a δt_o
//! v̂_a(t − t̂_o) − v_a(t − t_o)  ≈ δv_a + (Ĉ [ω̂×] − Ω_ie Ĉ) δl − a δt_o
//! fix velocity (latency L):      … − a δL
//! NHC, v^v = (I − [μ̂×]) v^b:     v̂^v − v^v ≈ (I − [μ̂×]) δv^b + [v^b×] δμ
//! ```
//!
//! (Groves eq. 14.113/14.127 for the lever arm; the time offset and
//! latency to first order in t_o, L: a 0.1 s offset at 1 m/s² leaves
//! 5 mm; the mounting as in Shin 2001 §4.3 and Groves §15.4.1.)

use nalgebra::Vector3;

use crate::filter::state::{Installation as At, INSTALLATION_STATES};
use crate::filter::ErrorState;

/// The installation estimates a filter runs with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InstallationEstimate {
    /// Antenna position from the IMU, body axes (forward, right, down), m.
    pub lever_arm_b_m: Vector3<f64>,
    /// Added to the IMU time stamps (on top of `[imu] time_offset_s`), s.
    pub time_offset_s: f64,
    /// The fixes' velocity at t is the antenna's at t − latency, s.
    pub velocity_latency_s: f64,
    /// Boresight μ: vehicle axes = (I − [μ×]) body axes, rad; its x
    /// (roll) is always zero (see [`At`]: the states hold pitch and yaw).
    pub mounting_rad: Vector3<f64>,
}

impl InstallationEstimate {
    /// The configuration's values (the tuning's lever arm and velocity
    /// latency), no time offset and no boresight.
    pub(crate) fn configured(lever_arm_b_m: Vector3<f64>, velocity_latency_s: f64) -> Self {
        Self {
            lever_arm_b_m,
            time_offset_s: 0.0,
            velocity_latency_s,
            mounting_rad: Vector3::zeros(),
        }
    }

    /// As a vector in the order of the installation block.
    pub fn to_array(&self) -> [f64; INSTALLATION_STATES] {
        let (l, m) = (self.lever_arm_b_m, self.mounting_rad);
        [
            l.x,
            l.y,
            l.z,
            self.time_offset_s,
            self.velocity_latency_s,
            m.y,
            m.z,
        ]
    }

    /// The estimates corrected by the error estimate `x` (subtracted).
    pub(crate) fn corrected<const N: usize>(&self, x: &ErrorState<N>) -> Self {
        match x.installation() {
            Some(d) => Self {
                lever_arm_b_m: self.lever_arm_b_m - d.fixed_rows::<3>(At::LEVER_ARM),
                time_offset_s: self.time_offset_s - d[At::TIME_OFFSET],
                velocity_latency_s: self.velocity_latency_s - d[At::VELOCITY_LATENCY],
                mounting_rad: self.mounting_rad
                    - Vector3::new(0.0, d[At::MOUNTING], d[At::MOUNTING + 1]),
            },
            None => *self,
        }
    }
}

/// The prior σ of the installation states (filters with the block only).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InstallationUncertainty {
    /// Lever arm, m, per body axis.
    pub lever_arm_m: f64,
    /// IMU time offset, s.
    pub time_offset_s: f64,
    /// Velocity latency, s.
    pub velocity_latency_s: f64,
    /// Mounting boresight, rad, pitch and yaw.
    pub mounting_rad: f64,
}

impl Default for InstallationUncertainty {
    /// Wide enough for a car whose antenna sits anywhere on the roof
    /// (2 m per axis), a logger whose clocks disagree by a tenth of a
    /// second, a receiver that reports the velocity up to 0.2 s late and a
    /// bracket a few degrees off (3°): the ranges the installation tests check.
    fn default() -> Self {
        Self {
            lever_arm_m: 2.0,
            time_offset_s: 0.1,
            velocity_latency_s: 0.2,
            mounting_rad: 3f64.to_radians(),
        }
    }
}

impl InstallationUncertainty {
    /// The variances of the block, in its order.
    pub(crate) fn variances(&self) -> [f64; INSTALLATION_STATES] {
        let (l, m) = (self.lever_arm_m.powi(2), self.mounting_rad.powi(2));
        [
            l,
            l,
            l,
            self.time_offset_s.powi(2),
            self.velocity_latency_s.powi(2),
            m,
            m,
        ]
    }
}
