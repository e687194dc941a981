//! Land-vehicle motion in body axes for the calibration and inversion
//! experiments: the true f_ib^b and ω_ib^b the IMU would see.
//!
//! Calibration and inversion need only the body-frame inputs, not a
//! navigation trajectory, so this generator works in a local level frame
//! aligned with the heading and neglects Earth rotation (7.3e-5 rad/s) and
//! transport rate, far below the sensor noise. Each driver is a first-order
//! Gauss-Markov process x_{k+1} = e^{−Δt/τ} x_k + σ √(1 − e^{−2Δt/τ}) w_k:
//! - forward acceleration a_x: σ 1 m/s², τ 5 s; the speed starts at 15 m/s
//!   and is kept above 1 m/s (the acceleration is reflected);
//! - yaw rate ψ̇: σ 8 °/s, τ 4 s (turns); centripetal acceleration v ψ̇;
//! - vertical acceleration a_z (road): σ 0.3 m/s², τ 0.5 s;
//! - roll and pitch rates: σ 2 °/s, τ 1 s, with angles leaking back to level
//!   with τ 5 s (φ̇ = u − φ/5 s), so φ, θ stay within a few degrees.
//! The body rates follow the Euler kinematics, ω = [φ̇ − ψ̇ sin θ,
//! θ̇ cos φ + ψ̇ sin φ cos θ, −θ̇ sin φ + ψ̇ cos φ cos θ], and the specific
//! force is f_b = C_l^b (a_l − g_l) with g_l = [0, 0, g0] (NED-like, z down).

use nalgebra::Vector3;
use rand::Rng as _;
use rand_distr::StandardNormal;

use crate::attitude::euler_to_dcm;
use crate::random::Rng;
use crate::{validate, Result};

use super::Motion;

const G0: f64 = 9.80665;

struct GaussMarkov {
    phi: f64,
    drive: f64,
    x: f64,
}

impl GaussMarkov {
    fn new(std: f64, tau_s: f64, dt: f64, rng: &mut Rng) -> Self {
        let phi = (-dt / tau_s).exp();
        Self {
            phi,
            drive: std * (1.0 - phi * phi).sqrt(),
            x: std * rng.sample::<f64, _>(StandardNormal),
        }
    }

    fn next(&mut self, rng: &mut Rng) -> f64 {
        let x = self.x;
        self.x = self.phi * self.x + self.drive * rng.sample::<f64, _>(StandardNormal);
        x
    }
}

/// A random land-vehicle motion of `duration_s` at `rate_hz` (module docs).
pub fn land_vehicle(duration_s: f64, rate_hz: f64, rng: &mut Rng) -> Result<Motion> {
    validate::positive("duration", duration_s)?;
    validate::positive("rate", rate_hz)?;
    let dt = 1.0 / rate_hz;
    let n = (duration_s * rate_hz).round() as usize + 1;
    let deg = std::f64::consts::PI / 180.0;
    let mut accel = GaussMarkov::new(1.0, 5.0, dt, rng);
    let mut yaw_rate = GaussMarkov::new(8.0 * deg, 4.0, dt, rng);
    let mut vertical = GaussMarkov::new(0.3, 0.5, dt, rng);
    let mut roll_drive = GaussMarkov::new(2.0 * deg, 1.0, dt, rng);
    let mut pitch_drive = GaussMarkov::new(2.0 * deg, 1.0, dt, rng);
    let leak_s = 5.0;
    let (mut speed, mut roll, mut pitch) = (15.0f64, 0.0f64, 0.0f64);
    let mut specific_force_b = Vec::with_capacity(n);
    let mut angular_rate_b = Vec::with_capacity(n);
    for _ in 0..n {
        let mut a_x = accel.next(rng);
        if speed < 1.0 {
            a_x = a_x.abs();
        }
        let psi_dot = yaw_rate.next(rng);
        let roll_dot = roll_drive.next(rng) - roll / leak_s;
        let pitch_dot = pitch_drive.next(rng) - pitch / leak_s;
        let a_level = Vector3::new(a_x, speed * psi_dot, vertical.next(rng));
        let c_b_l = euler_to_dcm(roll, pitch, 0.0);
        specific_force_b.push(c_b_l.transpose() * (a_level - Vector3::new(0.0, 0.0, G0)));
        let (sr, cr) = roll.sin_cos();
        let (sp, cp) = pitch.sin_cos();
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
