//! Random land-vehicle trajectories (method §5: speed changes, turns, small
//! pitch and roll, smooth, starting from a given geodetic point).

use rand::Rng as _;

use super::segments::validate_origin;
use super::smooth::SMOOTHSTEP_PEAK_RATE;
use super::vehicle::{VehicleMotion, PITCH_PER_LONGITUDINAL_ACCEL, ROLL_PER_LATERAL_ACCEL};
use super::{build, time_grid, Trajectory};
use crate::geodesy::Geodetic;
use crate::random::Rng;
use crate::{validate, Error, Result};

/// What [`Trajectory::random`] draws from. Defaults: 600 s at 100 Hz from
/// Toulouse (43.6° N, 1.44° E, 150 m), speeds up to 30 m/s, longitudinal
/// acceleration up to 2 m/s², lateral up to 3 m/s², yaw rate up to
/// 0.4 rad/s, road slopes up to 0.05 rad, moving from the start.
#[derive(Debug, Clone, PartialEq)]
pub struct RandomTrajectoryConfig {
    /// Length of the trajectory, s (> 0).
    pub duration_s: f64,
    /// IMU sample rate, Hz (> 0).
    pub rate_hz: f64,
    /// Start point.
    pub origin: Geodetic,
    /// Initial heading from north, rad; `None` draws it uniformly.
    pub initial_heading_rad: Option<f64>,
    /// Highest speed, m/s (> 0).
    pub max_speed_m_s: f64,
    /// Highest longitudinal acceleration or deceleration, m/s² (> 0).
    pub max_longitudinal_acceleration_m_s2: f64,
    /// Highest lateral (centripetal) acceleration in turns, m/s² (> 0).
    pub max_lateral_acceleration_m_s2: f64,
    /// Highest yaw rate, rad/s (> 0).
    pub max_yaw_rate_rad_s: f64,
    /// Highest road slope (path angle), rad (≥ 0, < 0.5).
    pub max_slope_rad: f64,
    /// Time at rest before the vehicle moves off, s (≥ 0). Zero starts in
    /// motion at a random speed.
    pub stationary_start_s: f64,
    /// Body roll per lateral acceleration, rad/(m/s²) (≥ 0).
    pub roll_per_lateral_accel: f64,
    /// Body pitch per longitudinal acceleration, rad/(m/s²) (≥ 0).
    pub pitch_per_longitudinal_accel: f64,
}

impl Default for RandomTrajectoryConfig {
    fn default() -> Self {
        Self {
            duration_s: 600.0,
            rate_hz: crate::sensors::DEFAULT_SAMPLE_RATE_HZ,
            origin: Geodetic::new(43.6f64.to_radians(), 1.44f64.to_radians(), 150.0),
            initial_heading_rad: None,
            max_speed_m_s: 30.0,
            max_longitudinal_acceleration_m_s2: 2.0,
            max_lateral_acceleration_m_s2: 3.0,
            max_yaw_rate_rad_s: 0.4,
            max_slope_rad: 0.05,
            stationary_start_s: 0.0,
            roll_per_lateral_accel: ROLL_PER_LATERAL_ACCEL,
            pitch_per_longitudinal_accel: PITCH_PER_LONGITUDINAL_ACCEL,
        }
    }
}

impl RandomTrajectoryConfig {
    /// Checks every setting; errors name the Python keyword.
    pub fn validate(&self) -> Result<()> {
        validate::positive("duration", self.duration_s)?;
        validate::positive("rate", self.rate_hz)?;
        validate_origin(&self.origin)?;
        if let Some(h) = self.initial_heading_rad {
            validate::finite_scalars("initial_heading", &[h])?;
        }
        validate::positive("max_speed", self.max_speed_m_s)?;
        validate::positive(
            "max_longitudinal_acceleration",
            self.max_longitudinal_acceleration_m_s2,
        )?;
        validate::positive(
            "max_lateral_acceleration",
            self.max_lateral_acceleration_m_s2,
        )?;
        validate::positive("max_yaw_rate", self.max_yaw_rate_rad_s)?;
        validate::non_negative("max_slope", self.max_slope_rad)?;
        if self.max_slope_rad >= 0.5 {
            return Err(Error::invalid(
                "max_slope",
                format!("must be below 0.5 rad, got {}", self.max_slope_rad),
            ));
        }
        validate::non_negative("stationary_start", self.stationary_start_s)?;
        validate::non_negative("roll_per_lateral_accel", self.roll_per_lateral_accel)?;
        validate::non_negative(
            "pitch_per_longitudinal_accel",
            self.pitch_per_longitudinal_accel,
        )?;
        Ok(())
    }
}

/// Lowest speed of a random speed change: the vehicle keeps moving
/// except at the optional stationary start and at random stops.
const MIN_CRUISE_SPEED_M_S: f64 = 3.0;

/// Probability that a speed change is a stop (to a standstill, then a
/// pause of 2-10 s).
const STOP_PROBABILITY: f64 = 0.08;

impl Trajectory {
    /// A random land-vehicle trajectory: a sequence of cruises, speed
    /// changes (occasionally to a stop) and turns, with road slope changes
    /// on their own schedule. Speed changes and turns do not overlap, so the
    /// limits hold exactly: |ṡ| ≤ max longitudinal acceleration, s ≤ max
    /// speed, |s·r| ≤ max lateral acceleration, |r| ≤ max yaw rate,
    /// |γ| ≤ max slope. Deterministic for a given `rng` state.
    pub fn random(config: &RandomTrajectoryConfig, rng: &mut Rng) -> Result<Trajectory> {
        config.validate()?;
        let time = time_grid(0.0, config.duration_s, config.rate_hz)?;
        let c = config;
        let heading = match c.initial_heading_rad {
            Some(h) => h,
            None => rng.random_range(-std::f64::consts::PI..std::f64::consts::PI),
        };
        let mut m = VehicleMotion::at_rest(heading);
        m.roll_per_lateral_accel = c.roll_per_lateral_accel;
        m.pitch_per_longitudinal_accel = c.pitch_per_longitudinal_accel;
        let low_speed = MIN_CRUISE_SPEED_M_S.min(0.5 * c.max_speed_m_s);
        if c.stationary_start_s > 0.0 {
            m.speed_m_s.hold(c.stationary_start_s);
            m.yaw_rate_rad_s.hold(c.stationary_start_s);
        } else {
            m.speed_m_s = super::SmoothSignal::new(rng.random_range(0.3..0.8) * c.max_speed_m_s);
        }
        // Manoeuvres until the duration is covered.
        while m.speed_m_s.end_s() < c.duration_s {
            let speed = m.speed_m_s.final_value();
            let choice: f64 = rng.random();
            let start = m.speed_m_s.end_s();
            if speed < low_speed || choice < 0.35 {
                // Speed change; from a standstill always move off.
                let target = if speed >= low_speed && rng.random_bool(STOP_PROBABILITY) {
                    0.0
                } else {
                    rng.random_range(low_speed..=c.max_speed_m_s)
                };
                let shortest = SMOOTHSTEP_PEAK_RATE * (target - speed).abs()
                    / c.max_longitudinal_acceleration_m_s2;
                let duration = shortest.max(2.0) * rng.random_range(1.0..2.5);
                m.speed_m_s.ramp_to(duration, target);
                if target == 0.0 {
                    m.speed_m_s.hold(rng.random_range(2.0..10.0));
                }
            } else if choice < 0.7 {
                // Turn at constant speed: ramp the yaw rate up, hold, ramp
                // down. Peak yaw rate within both limits at this speed.
                let r_limit = c
                    .max_yaw_rate_rad_s
                    .min(c.max_lateral_acceleration_m_s2 / speed);
                let r_peak = r_limit * rng.random_range(0.3..1.0);
                let ramp = rng.random_range(1.5..4.0);
                let heading_change = rng.random_range(15f64.to_radians()..150f64.to_radians());
                let hold = (heading_change / r_peak - ramp).max(0.0);
                let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
                m.yaw_rate_rad_s.hold(start - m.yaw_rate_rad_s.end_s());
                m.yaw_rate_rad_s.ramp_to(ramp, sign * r_peak);
                m.yaw_rate_rad_s.hold(hold);
                m.yaw_rate_rad_s.ramp_to(ramp, 0.0);
                m.speed_m_s.hold(m.yaw_rate_rad_s.end_s() - start);
            } else {
                m.speed_m_s.hold(rng.random_range(3.0..20.0));
            }
        }
        // Road slope on its own schedule.
        while m.path_angle_rad.end_s() < c.duration_s {
            m.path_angle_rad.hold(rng.random_range(10.0..60.0));
            let slope = if c.max_slope_rad > 0.0 {
                rng.random_range(-c.max_slope_rad..=c.max_slope_rad)
            } else {
                0.0
            };
            m.path_angle_rad.ramp_to(rng.random_range(5.0..15.0), slope);
        }
        Ok(build(&m, c.origin, time))
    }
}
