//! Scripted motion: a land vehicle following a list of manoeuvres.

use super::vehicle::VehicleMotion;
use super::{build, time_grid, Trajectory};
use crate::geodesy::Geodetic;
use crate::{validate, Error, Result};

/// One manoeuvre of a scripted trajectory. Manoeuvres follow each other;
/// during one, everything it does not name stays as it was. The vehicle
/// starts at rest, level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Segment {
    /// Change speed (up or down) to `target_speed_m_s` along a smoothstep
    /// lasting `duration_s` (peak acceleration 1.875 Δs / duration).
    Accelerate {
        /// How long the change takes, s.
        duration_s: f64,
        /// The speed at its end, m/s.
        target_speed_m_s: f64,
    },
    /// Keep speed, heading and path angle for `duration_s`.
    Cruise {
        /// How long, s.
        duration_s: f64,
    },
    /// Turn by `heading_change_rad` (positive clockwise seen from above,
    /// i.e. to the right): the yaw rate ramps up over the first quarter,
    /// holds, and ramps down over the last quarter.
    Turn {
        /// How long the turn takes, s.
        duration_s: f64,
        /// The change of heading, rad (positive to the right).
        heading_change_rad: f64,
    },
    /// Climb (positive) or descend at path angle `path_angle_rad`: it ramps
    /// up over the first quarter, holds, and returns to level over the last.
    Climb {
        /// How long the climb takes, s.
        duration_s: f64,
        /// The path angle held in its middle, rad (positive up).
        path_angle_rad: f64,
    },
    /// Decelerate to a standstill over `duration_s`.
    Stop {
        /// How long the deceleration takes, s.
        duration_s: f64,
    },
}

impl Segment {
    /// The segment's duration, s.
    pub fn duration_s(&self) -> f64 {
        match *self {
            Segment::Accelerate { duration_s, .. }
            | Segment::Cruise { duration_s }
            | Segment::Turn { duration_s, .. }
            | Segment::Climb { duration_s, .. }
            | Segment::Stop { duration_s } => duration_s,
        }
    }

    fn validate(&self, index: usize) -> Result<()> {
        let name = |field: &str| format!("segments[{index}].{field}");
        validate::positive(&name("duration_s"), self.duration_s())?;
        match *self {
            Segment::Accelerate {
                target_speed_m_s, ..
            } => validate::non_negative(&name("target_speed_m_s"), target_speed_m_s),
            Segment::Turn {
                heading_change_rad, ..
            } => validate::finite_scalars(&name("heading_change_rad"), &[heading_change_rad]),
            Segment::Climb { path_angle_rad, .. } => {
                if path_angle_rad.is_finite() && path_angle_rad.abs() < 1.0 {
                    Ok(())
                } else {
                    Err(Error::invalid(
                        name("path_angle_rad"),
                        format!("must be finite and within ±1 rad, got {path_angle_rad}"),
                    ))
                }
            }
            Segment::Cruise { .. } | Segment::Stop { .. } => Ok(()),
        }
    }
}

/// Ramp up over a quarter, hold for a half, ramp down over a quarter, so
/// that the signal's integral over the segment is `area` (= 0.75 · peak · T).
fn ramp_hold_ramp(signal: &mut super::SmoothSignal, duration_s: f64, area: f64) {
    let base = signal.final_value();
    let peak = area / (0.75 * duration_s);
    signal.ramp_to(0.25 * duration_s, base + peak);
    signal.hold(0.5 * duration_s);
    signal.ramp_to(0.25 * duration_s, base);
}

impl Trajectory {
    /// A scripted land-vehicle trajectory starting at rest at `origin`
    /// with heading `initial_heading_rad` (from north, clockwise), sampled
    /// at `rate_hz` over the segments' total duration.
    pub fn from_segments(
        origin: Geodetic,
        initial_heading_rad: f64,
        segments: &[Segment],
        rate_hz: f64,
    ) -> Result<Trajectory> {
        validate_origin(&origin)?;
        validate::finite_scalars("initial_heading", &[initial_heading_rad])?;
        if segments.is_empty() {
            return Err(Error::invalid("segments", "needs at least one segment"));
        }
        for (i, s) in segments.iter().enumerate() {
            s.validate(i)?;
        }
        let mut m = VehicleMotion::at_rest(initial_heading_rad);
        for s in segments {
            let d = s.duration_s();
            // All three signals end at the same time between segments.
            let start = m.speed_m_s.end_s();
            match *s {
                Segment::Accelerate {
                    target_speed_m_s, ..
                } => m.speed_m_s.ramp_to(d, target_speed_m_s),
                Segment::Stop { .. } => m.speed_m_s.ramp_to(d, 0.0),
                Segment::Turn {
                    heading_change_rad, ..
                } => ramp_hold_ramp(&mut m.yaw_rate_rad_s, d, heading_change_rad),
                Segment::Climb { path_angle_rad, .. } => {
                    ramp_hold_ramp(&mut m.path_angle_rad, d, 0.75 * d * path_angle_rad)
                }
                Segment::Cruise { .. } => {}
            }
            // Whatever this segment does not drive holds its value.
            for signal in [
                &mut m.speed_m_s,
                &mut m.yaw_rate_rad_s,
                &mut m.path_angle_rad,
            ] {
                signal.hold(start + d - signal.end_s());
            }
        }
        let total: f64 = segments.iter().map(Segment::duration_s).sum();
        let time = time_grid(0.0, total, rate_hz)?;
        Ok(build(&m, origin, time))
    }
}

impl Trajectory {
    /// The truth of a custom [`VehicleMotion`] (speed, yaw-rate and
    /// path-angle signals built by hand) from t = 0 for `duration_s`.
    pub fn from_vehicle_motion(
        motion: &VehicleMotion,
        origin: Geodetic,
        duration_s: f64,
        rate_hz: f64,
    ) -> Result<Trajectory> {
        validate_origin(&origin)?;
        validate::finite_scalars("initial_heading", &[motion.initial_heading_rad])?;
        let time = time_grid(0.0, duration_s, rate_hz)?;
        Ok(build(motion, origin, time))
    }
}

/// A finite origin with latitude within ±89° (the NED description of the
/// motion is singular at the poles) and a height between −1 km and 100 km.
pub(crate) fn validate_origin(origin: &Geodetic) -> Result<()> {
    let lat = origin.latitude_rad;
    if !(lat.is_finite() && lat.abs() <= 89f64.to_radians()) {
        return Err(Error::invalid(
            "origin",
            format!("latitude must be within ±89° (±1.553 rad), got {lat} rad"),
        ));
    }
    if !origin.longitude_rad.is_finite() {
        return Err(Error::invalid("origin", "longitude is not finite"));
    }
    let h = origin.height_m;
    if !(h.is_finite() && (-1_000.0..=100_000.0).contains(&h)) {
        return Err(Error::invalid(
            "origin",
            format!("height must be within −1 km..100 km, got {h} m"),
        ));
    }
    Ok(())
}
