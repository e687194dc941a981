//! Land-vehicle motion in body axes for the calibration and inversion
//! experiments: the true f_ib^b and ω_ib^b the IMU would see.
//!
//! Calibration and inversion need only the body-frame inputs, not a
//! navigation trajectory, so this generator works in a local level frame
//! aligned with the heading and neglects Earth rotation (7.3e-5 rad/s) and
//! transport rate, far below the sensor noise. Each driver is a first-order
//! Gauss-Markov process x_{k+1} = e^{−Δt/τ} x_k + σ √(1 − e^{−2Δt/τ}) w_k
//! passed through a first-order low-pass of time constant τ_s, so its paths
//! are differentiable (a bare Gauss-Markov path has white-noise derivatives:
//! jerks and angular accelerations no vehicle makes):
//! - forward acceleration a_x: σ 1 m/s², τ 5 s, τ_s 0.5 s, plus a pull
//!   −(v − 15 m/s)/20 s that keeps the speed around 15 m/s (and v ≥ 1 m/s);
//! - yaw rate ψ̇: σ 8 °/s, τ 4 s, τ_s 0.5 s (turns); centripetal v ψ̇;
//! - vertical acceleration a_z (road): σ 0.3 m/s², τ 0.5 s, τ_s 0.1 s;
//! - roll and pitch rates: σ 2 °/s, τ 1 s, τ_s 0.2 s, with the angles
//!   leaking back to level with τ 5 s (φ̇ = u − φ/5 s), so φ, θ stay within
//!   a few degrees.
//!
//! The low-pass lowers each σ somewhat (by √(τ/(τ + τ_s)) for the stationary
//! variance).
//!
//! The body rates follow the Euler kinematics, ω = [φ̇ − ψ̇ sin θ,
//! θ̇ cos φ + ψ̇ sin φ cos θ, −θ̇ sin φ + ψ̇ cos φ cos θ], and the specific
//! force is f_b = C_l^b (a_l − g_l) with g_l = [0, 0, g0] (NED-like, z down).

use nalgebra::{Matrix3, Vector3};
use rand::Rng as _;
use rand_distr::StandardNormal;

use crate::gauss_markov::{GaussMarkov, GaussMarkovStep};
use crate::random::Rng;
use crate::{validate, Error, Result};

use super::{Motion, MotionSource};

/// The motions of this module by name, for the experiments' `motion` option.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MotionKind {
    /// [`land_vehicle`], `"land-vehicle"`.
    #[default]
    LandVehicle,
    /// [`random_trajectory`], `"trajectory"`.
    Trajectory,
}

impl MotionKind {
    /// `"land-vehicle"` or `"trajectory"`; other names are an error naming `motion`.
    pub fn from_name(name: &str) -> Result<Self> {
        match name {
            "land-vehicle" => Ok(Self::LandVehicle),
            "trajectory" => Ok(Self::Trajectory),
            other => Err(Error::invalid(
                "motion",
                format!("expected 'land-vehicle' or 'trajectory', got '{other}'"),
            )),
        }
    }

    /// The motion's name as the configuration spells it.
    pub fn name(&self) -> &'static str {
        match self {
            Self::LandVehicle => "land-vehicle",
            Self::Trajectory => "trajectory",
        }
    }

    /// The generator.
    pub fn source(&self) -> &'static MotionSource<'static> {
        match self {
            Self::LandVehicle => &land_vehicle,
            Self::Trajectory => &random_trajectory,
        }
    }
}

const G0: f64 = 9.80665;

/// A stationary Gauss-Markov driver x ([`crate::gauss_markov`]) seen
/// through a first-order low-pass y of time constant τ_s.
struct Smooth {
    driver: GaussMarkovStep,
    x: f64,
    /// e^{−Δt/τ_s}: the low-pass keeps this share of y per step.
    smoothing_decay: f64,
    y: f64,
}

impl Smooth {
    fn new(std: f64, tau_s: f64, smoothing_s: f64, dt: f64, rng: &mut Rng) -> Result<Self> {
        let driver = GaussMarkov::stationary(std, tau_s, ["driver std", "driver tau"])?.step(dt);
        let x = std * rng.sample::<f64, _>(StandardNormal);
        Ok(Self {
            driver,
            x,
            smoothing_decay: (-dt / smoothing_s).exp(),
            y: x,
        })
    }

    fn next(&mut self, rng: &mut Rng) -> f64 {
        let y = self.y;
        self.y = self.smoothing_decay * self.y + (1.0 - self.smoothing_decay) * self.x;
        self.x = self.driver.next(self.x, rng.sample(StandardNormal));
        y
    }
}

/// C_b^l = `euler_to_dcm(roll, pitch, 0)` (Groves eq. 2.22 transposed)
/// written out for ψ = 0 from the sines and cosines of roll and pitch, so
/// one pair of each serves it and the Euler kinematics.
#[inline]
fn level_from_body(sr: f64, cr: f64, sp: f64, cp: f64) -> Matrix3<f64> {
    Matrix3::new(cp, sp * sr, sp * cr, 0.0, cr, -sr, -sp, cp * sr, cp * cr)
}

/// A random land-vehicle motion of `duration_s` at `rate_hz` (module docs).
pub fn land_vehicle(duration_s: f64, rate_hz: f64, rng: &mut Rng) -> Result<Motion> {
    validate::positive("duration", duration_s)?;
    validate::positive("rate", rate_hz)?;
    crate::limits::duration("duration", duration_s)?;
    crate::limits::samples("duration", duration_s, rate_hz)?;
    let dt = 1.0 / rate_hz;
    let n = (duration_s * rate_hz).round() as usize + 1;
    let deg = std::f64::consts::PI / 180.0;
    let mut accel = Smooth::new(1.0, 5.0, 0.5, dt, rng)?;
    let mut yaw_rate = Smooth::new(8.0 * deg, 4.0, 0.5, dt, rng)?;
    let mut vertical = Smooth::new(0.3, 0.5, 0.1, dt, rng)?;
    let mut roll_drive = Smooth::new(2.0 * deg, 1.0, 0.2, dt, rng)?;
    let mut pitch_drive = Smooth::new(2.0 * deg, 1.0, 0.2, dt, rng)?;
    let leak_s = 5.0;
    let (mut speed, mut roll, mut pitch) = (15.0f64, 0.0f64, 0.0f64);
    let mut specific_force_b = Vec::with_capacity(n);
    let mut angular_rate_b = Vec::with_capacity(n);
    for _ in 0..n {
        let mut a_x = accel.next(rng) - (speed - 15.0) / 20.0;
        if speed < 1.0 {
            a_x = a_x.max(0.0);
        }
        let psi_dot = yaw_rate.next(rng);
        let roll_dot = roll_drive.next(rng) - roll / leak_s;
        let pitch_dot = pitch_drive.next(rng) - pitch / leak_s;
        let a_level = Vector3::new(a_x, speed * psi_dot, vertical.next(rng));
        let (sr, cr) = roll.sin_cos();
        let (sp, cp) = pitch.sin_cos();
        let c_b_l = level_from_body(sr, cr, sp, cp);
        specific_force_b.push(c_b_l.transpose() * (a_level - Vector3::new(0.0, 0.0, G0)));
        angular_rate_b.push(Vector3::new(
            roll_dot - psi_dot * sp,
            pitch_dot * cr + psi_dot * sr * cp,
            -pitch_dot * sr + psi_dot * cr * cp,
        ));
        speed += a_x * dt;
        roll += roll_dot * dt;
        pitch += pitch_dot * dt;
    }
    Ok(Motion {
        specific_force_b,
        angular_rate_b,
    })
}

/// Body-frame truth of [`crate::trajectory::Trajectory::random`] (a full
/// ECEF land-vehicle trajectory: Earth rotation, J2 gravity, speed changes,
/// turns, slopes) with its default vehicle limits. Its roll and pitch follow
/// the lateral and longitudinal accelerations only, so the roll and pitch
/// rates are small: the p and q scale factors and the vertical terms are
/// much less observable than with [`land_vehicle`] (method §3: excitation).
pub fn random_trajectory(duration_s: f64, rate_hz: f64, rng: &mut Rng) -> Result<Motion> {
    let config = crate::trajectory::RandomTrajectoryConfig {
        duration_s,
        rate_hz,
        ..Default::default()
    };
    let t = crate::trajectory::Trajectory::random(&config, rng)?;
    Ok(Motion {
        specific_force_b: t.specific_force_b,
        angular_rate_b: t.angular_rate_b,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::euler_to_dcm;

    #[test]
    fn the_written_out_attitude_is_euler_to_dcm_without_yaw() {
        for k in 0..200 {
            let roll = -0.7 + 0.007 * k as f64;
            let pitch = 0.5 - 0.0061 * k as f64;
            let (sr, cr) = roll.sin_cos();
            let (sp, cp) = pitch.sin_cos();
            assert_eq!(
                level_from_body(sr, cr, sp, cp),
                euler_to_dcm(roll, pitch, 0.0),
                "roll {roll}, pitch {pitch}"
            );
        }
    }
}
