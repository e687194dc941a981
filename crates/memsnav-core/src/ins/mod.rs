//! Strapdown inertial navigation in ECEF (method §5; Groves ch. 5.2-5.5).
//!
//! The state is the body's position r_eb^e, velocity v_eb^e and attitude
//! C_b^e. Two forms of the same mechanization:
//!
//! - [`step`]: instantaneous specific force and angular rate at both ends
//!   of an interval (how memsnav's simulated IMUs deliver data);
//! - [`step_increments`]: velocity and angle increments per interval, with
//!   coning and sculling corrections (how most real IMUs deliver data).
//!
//! Both are pure functions with no allocation. [`integrate`] (samples,
//! fourth order), [`integrate_steps`] (chained [`step`]) and
//! [`integrate_increments`] run whole series after validating them.

mod increments;
mod integrate;
mod mechanization;
mod series;

use nalgebra::{Matrix3, Vector3};

pub use increments::{increments_from_samples, step_increments};
pub use integrate::{integrate, integrate_increments, integrate_steps};
pub use mechanization::step;
pub use series::ImuData;

/// Position, velocity and attitude of the body in ECEF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavState {
    /// r_eb^e, m.
    pub position_ecef: Vector3<f64>,
    /// v_eb^e, m/s.
    pub velocity_ecef: Vector3<f64>,
    /// C_b^e, body to ECEF.
    pub c_b_e: Matrix3<f64>,
}

/// Instantaneous IMU output at one time.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ImuSample {
    /// f_ib^b, m/s².
    pub specific_force_b: Vector3<f64>,
    /// ω_ib^b, rad/s.
    pub angular_rate_b: Vector3<f64>,
}

/// IMU output integrated over one interval, in the body axes of each
/// instant (what an integrating IMU delivers, before any coning or
/// sculling correction): Δv = ∫ f_ib^b dt, Δθ = ∫ ω_ib^b dt.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ImuIncrement {
    /// ∫ f_ib^b dt over the interval, m/s.
    pub delta_velocity_b: Vector3<f64>,
    /// ∫ ω_ib^b dt over the interval, rad.
    pub delta_angle_b: Vector3<f64>,
}

impl ImuIncrement {
    /// The increments times `share` (the part of an interval at constant
    /// rates).
    pub fn scaled(&self, share: f64) -> Self {
        Self {
            delta_velocity_b: self.delta_velocity_b * share,
            delta_angle_b: self.delta_angle_b * share,
        }
    }
}
