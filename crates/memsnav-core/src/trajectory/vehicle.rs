//! A land vehicle described by its speed, heading and path angle, leaning
//! in turns and pitching when it accelerates.

use nalgebra::Vector3;

use super::smooth::SmoothSignal;
use super::{LocalMotion, Motion, SinCosMemo};

/// Body roll per m/s² of lateral acceleration, rad/(m/s²): 0.01 is about
/// 5.6°/g, a soft passenger car's roll gradient. The body leans out of the
/// turn (negative roll in a right turn).
pub const ROLL_PER_LATERAL_ACCEL: f64 = 0.01;

/// Body pitch per m/s² of longitudinal acceleration, rad/(m/s²): 0.004 is
/// about 2.2°/g; the nose rises when accelerating and dives when braking.
pub const PITCH_PER_LONGITUDINAL_ACCEL: f64 = 0.004;

/// Speed s (m/s), yaw rate r (rad/s) and path angle γ (rad, positive up)
/// as C² signals; heading ψ = ψ₀ + ∫ r dt in closed form.
///
/// - v^n = s (cos γ cos ψ, cos γ sin ψ, −sin γ): no sideslip.
/// - roll φ = −k_φ s r (lean out of the turn), pitch θ = γ + k_θ ṡ, yaw ψ.
///
/// φ̇ needs ṡ and ṙ, θ̇ needs s̈: all continuous for smoothstep signals,
/// so the angular rate and the specific force are continuous.
#[derive(Debug, Clone)]
pub struct VehicleMotion {
    /// Speed s, m/s.
    pub speed_m_s: SmoothSignal,
    /// Yaw rate r, rad/s.
    pub yaw_rate_rad_s: SmoothSignal,
    /// Path angle γ, rad (positive up).
    pub path_angle_rad: SmoothSignal,
    /// Heading ψ₀ at t = 0, rad (from north, clockwise).
    pub initial_heading_rad: f64,
    /// Roll gradient k_φ, rad/(m/s²) ([`ROLL_PER_LATERAL_ACCEL`] by default).
    pub roll_per_lateral_accel: f64,
    /// Pitch gradient k_θ, rad/(m/s²) ([`PITCH_PER_LONGITUDINAL_ACCEL`] by default).
    pub pitch_per_longitudinal_accel: f64,
}

impl VehicleMotion {
    /// A vehicle at rest, level, heading `initial_heading_rad`, with the
    /// default lean coefficients.
    pub fn at_rest(initial_heading_rad: f64) -> Self {
        Self {
            speed_m_s: SmoothSignal::new(0.0),
            yaw_rate_rad_s: SmoothSignal::new(0.0),
            path_angle_rad: SmoothSignal::new(0.0),
            initial_heading_rad,
            roll_per_lateral_accel: ROLL_PER_LATERAL_ACCEL,
            pitch_per_longitudinal_accel: PITCH_PER_LONGITUDINAL_ACCEL,
        }
    }

    /// The heading at `t_s`, rad.
    pub fn heading_rad(&self, t_s: f64) -> f64 {
        self.initial_heading_rad + self.yaw_rate_rad_s.integral(t_s)
    }
}

/// Lookup state of a [`VehicleMotion`] sampled at non-decreasing times:
/// the piece hints of the speed, yaw-rate and path-angle signals, and the
/// last sine and cosine of the path angle and heading (both hold still
/// for long stretches: constant slopes, straight driving).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct VehicleCursor {
    hints: [usize; 3],
    path_angle: SinCosMemo,
    heading: SinCosMemo,
}

impl Motion for VehicleMotion {
    type Cursor = VehicleCursor;

    fn at(&self, t: f64, cursor: &mut VehicleCursor) -> LocalMotion {
        let s = self.speed_m_s.at_from(t, &mut cursor.hints[0]);
        let (r, yaw_integral) = self
            .yaw_rate_rad_s
            .at_and_integral_from(t, &mut cursor.hints[1]);
        let g = self.path_angle_rad.at_from(t, &mut cursor.hints[2]);
        let psi = self.initial_heading_rad + yaw_integral;
        let (sg, cg) = cursor.path_angle.sin_cos(g.value);
        let (sp, cp) = cursor.heading.sin_cos(psi);
        let direction = Vector3::new(cg * cp, cg * sp, -sg);
        let direction_rate = Vector3::new(
            -sg * cp * g.rate - cg * sp * r.value,
            -sg * sp * g.rate + cg * cp * r.value,
            -cg * g.rate,
        );
        let k_roll = self.roll_per_lateral_accel;
        let k_pitch = self.pitch_per_longitudinal_accel;
        LocalMotion {
            velocity_ned: s.value * direction,
            velocity_ned_rate: s.rate * direction + s.value * direction_rate,
            euler_rad: Vector3::new(-k_roll * s.value * r.value, g.value + k_pitch * s.rate, psi),
            euler_rate_rad_s: Vector3::new(
                -k_roll * (s.rate * r.value + s.value * r.rate),
                g.rate + k_pitch * s.accel,
                r.value,
            ),
            yaw_sin_cos: (sp, cp),
        }
    }

    fn velocity_ned(&self, t: f64, cursor: &mut VehicleCursor) -> Vector3<f64> {
        let s = self.speed_m_s.value_from(t, &mut cursor.hints[0]);
        let yaw_integral = self.yaw_rate_rad_s.integral_from(t, &mut cursor.hints[1]);
        let g = self.path_angle_rad.value_from(t, &mut cursor.hints[2]);
        let psi = self.initial_heading_rad + yaw_integral;
        let (sg, cg) = cursor.path_angle.sin_cos(g);
        let (sp, cp) = cursor.heading.sin_cos(psi);
        s * Vector3::new(cg * cp, cg * sp, -sg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A drive with holds, speed ramps, a turn and a slope change, so the
    /// held angles (heading, path angle) are reused and then change.
    fn drive() -> VehicleMotion {
        let mut m = VehicleMotion::at_rest(0.3);
        m.speed_m_s.ramp_to(4.0, 12.0);
        m.speed_m_s.hold(10.0);
        m.yaw_rate_rad_s.hold(6.0);
        m.yaw_rate_rad_s.ramp_to(2.0, 0.2);
        m.yaw_rate_rad_s.ramp_to(2.0, 0.0);
        m.path_angle_rad.hold(3.0);
        m.path_angle_rad.ramp_to(5.0, -0.04);
        m
    }

    #[test]
    fn a_kept_cursor_gives_the_values_of_a_fresh_one() {
        let m = drive();
        let (mut kept, mut kept_velocity) = (VehicleCursor::default(), VehicleCursor::default());
        let bits = |v: &Vector3<f64>| v.map(f64::to_bits);
        for k in 0..1600 {
            let t = k as f64 * 0.01;
            let fresh = m.at(t, &mut VehicleCursor::default());
            let again = m.at(t, &mut kept);
            assert_eq!(bits(&again.velocity_ned), bits(&fresh.velocity_ned), "{t}");
            assert_eq!(
                bits(&again.velocity_ned_rate),
                bits(&fresh.velocity_ned_rate)
            );
            assert_eq!(bits(&again.euler_rad), bits(&fresh.euler_rad), "{t}");
            assert_eq!(bits(&again.euler_rate_rad_s), bits(&fresh.euler_rate_rad_s));
            assert_eq!(again.yaw_sin_cos, fresh.yaw_sin_cos, "{t}");
            // The velocity alone, half a step later, as the RK4 asks.
            let th = t + 0.005;
            assert_eq!(
                bits(&m.velocity_ned(th, &mut kept_velocity)),
                bits(&m.at(th, &mut VehicleCursor::default()).velocity_ned),
                "{th}"
            );
        }
    }
}
