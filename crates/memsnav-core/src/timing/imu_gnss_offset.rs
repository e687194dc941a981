//! The time offset between an IMU log and GNSS positions, found from the
//! data by cross-correlation (the classical time-delay estimate, Knapp &
//! Carter, "The generalized correlation method for estimation of time
//! delay", IEEE Trans. ASSP 24(4), 1976).
//!
//! The GNSS side is the change of the segment velocities between
//! consecutive positions at epoch t_k, spaced h apart:
//!
//! - along-track: (|v_k| − |v_{k−1}|) / h, the rate of change of the
//!   horizontal speed;
//! - yaw rate: (χ_k − χ_{k−1}) / h with χ the course of a segment.
//!
//! Each is the mean of the derivative (acceleration along the track,
//! course rate) under a triangle of half-width h centred on t_k. The IMU
//! side is the body forward specific force f_x or the body yaw rate ω_z
//! under the same triangle, computed exactly for piecewise-linear samples
//! as the second difference (X(t + h) − 2 X(t) + X(t − h)) / h² of the
//! signal's double integral X. Both are then one quantity seen through one
//! filter: no filter delay or bandwidth mismatch biases the lag. The lag
//! whose correlation peaks is the offset to add to the IMU times.
//!
//! On a level road f_x is the along-track acceleration plus g·sin(pitch);
//! the slowly varying pitch term lowers the correlation but does not move
//! its peak. The course of a car or a walker follows its heading with a
//! lag (side-slip; a walker turns the device before the path), which
//! biases the yaw-rate estimate: along-track is the default.

use nalgebra::Vector3;

use super::gnss_track::{segments, validate_track};
use super::integral::Integrals;
use super::lag_search::{lag_grid, search, Criterion, LagEstimate};
use crate::validate;
use crate::{Error, Result};

/// The quantity compared between IMU and GNSS.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OffsetSignal {
    /// Body forward specific force against the rate of change of speed.
    AlongTrack,
    /// Body yaw rate against the course rate.
    YawRate,
}

impl OffsetSignal {
    /// `"along_track"` or `"yaw_rate"`.
    pub fn from_name(name: &str) -> Result<Self> {
        match name {
            "along_track" => Ok(Self::AlongTrack),
            "yaw_rate" => Ok(Self::YawRate),
            _ => Err(Error::invalid(
                "signal",
                format!("unknown signal '{name}'; expected one of ['along_track', 'yaw_rate']"),
            )),
        }
    }
}

/// How to search for the offset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeOffsetOptions {
    /// The signal compared: along-track acceleration or yaw rate.
    pub signal: OffsetSignal,
    /// Offsets from −max to +max are tried, s.
    pub max_offset_s: f64,
    /// Grid step of the search, s (the peak is refined between steps).
    pub step_s: f64,
    /// GNSS epochs slower than this (on either side) are left out, m/s:
    /// course and speed changes are noise at a standstill.
    pub min_speed_m_s: f64,
    /// Consecutive stretches of the log searched on their own for the spread.
    pub blocks: usize,
}

/// The wrapped difference of two angles, rad, in (−π, π].
fn angle_difference(a: f64, b: f64) -> f64 {
    crate::attitude::wrap_angle_rad(a - b)
}

/// The offset to add to `imu_time_s` (the IMU on GPS time as mapped so
/// far; `specific_force_body` m/s² and `angular_rate_body` rad/s in body
/// axes forward-right-down) that best aligns it with the GNSS positions
/// `lla` ([lat rad, lon rad, h m]) at `gnss_time_s`. `lag_s` of the result
/// is the offset; its score is the peak correlation.
pub fn estimate_time_offset(
    imu_time_s: &[f64],
    specific_force_body: &[Vector3<f64>],
    angular_rate_body: &[Vector3<f64>],
    gnss_time_s: &[f64],
    lla: &[Vector3<f64>],
    options: &TimeOffsetOptions,
) -> Result<LagEstimate> {
    validate::increasing_times("imu_time", imu_time_s)?;
    let n_imu = imu_time_s.len();
    validate::same_length(
        "specific_force",
        specific_force_body.len(),
        "imu_time",
        n_imu,
    )?;
    validate::same_length("angular_rate", angular_rate_body.len(), "imu_time", n_imu)?;
    validate::finite_vectors("specific_force", specific_force_body)?;
    validate::finite_vectors("angular_rate", angular_rate_body)?;
    if n_imu < 3 {
        return Err(Error::invalid(
            "imu_time",
            format!("needs at least 3 samples, got {n_imu}"),
        ));
    }
    validate_track(gnss_time_s, lla)?;
    let grid = lag_grid(
        options.max_offset_s,
        options.step_s,
        ["max_offset_s", "step_s"],
    )?;
    validate::non_negative("min_speed_m_s", options.min_speed_m_s)?;
    let max_lag = grid[grid.len() - 1];

    // GNSS epochs between two regular segments of equal length (1 %).
    let segs = segments(gnss_time_s, lla);
    let mut epochs: Vec<(f64, f64, f64)> = Vec::new(); // (t_k, h, observed)
    for k in 1..segs.len() {
        let (a, b) = (&segs[k - 1], &segs[k]);
        let speed = |s: &super::gnss_track::Segment| s.velocity_ned.xy().norm();
        let h = 0.5 * (a.duration_s + b.duration_s);
        let t = gnss_time_s[k];
        let inside = t - h - max_lag >= imu_time_s[0] && t + h + max_lag <= imu_time_s[n_imu - 1];
        if !(a.regular && b.regular)
            || (a.duration_s - b.duration_s).abs() > 0.01 * h
            || speed(a).min(speed(b)) < options.min_speed_m_s
            || !inside
        {
            continue;
        }
        let observed = match options.signal {
            OffsetSignal::AlongTrack => (speed(b) - speed(a)) / h,
            OffsetSignal::YawRate => {
                let course =
                    |s: &super::gnss_track::Segment| s.velocity_ned.y.atan2(s.velocity_ned.x);
                angle_difference(course(b), course(a)) / h
            }
        };
        epochs.push((t, h, observed));
    }
    if epochs.len() < 3 {
        return Err(Error::invalid(
            "gnss_time",
            format!(
                "only {} GNSS epochs are usable (moving faster than min_speed_m_s = {} m/s, between regular intervals, with the IMU log covering ±(interval + max_offset_s)): the logs do not overlap in motion",
                epochs.len(),
                options.min_speed_m_s
            ),
        ));
    }
    let raw: Vec<f64> = match options.signal {
        OffsetSignal::AlongTrack => specific_force_body.iter().map(|f| f.x).collect(),
        OffsetSignal::YawRate => angular_rate_body.iter().map(|w| w.z).collect(),
    };
    // The mean only shifts the triangle means (unit area), which the
    // correlation ignores; removing it keeps the double integral small.
    let mean = raw.iter().sum::<f64>() / n_imu as f64;
    let integral = Integrals::new(imu_time_s, raw.iter().map(|x| x - mean).collect());
    // An IMU sample stamped t was taken at t + offset: the GNSS window
    // around t_k is the IMU window around t_k − offset.
    search(
        &grid,
        epochs.len(),
        options.blocks,
        Criterion::Correlation,
        "max_offset_s",
        |offset, out| {
            out.extend(epochs.iter().enumerate().map(|(j, &(t, h, observed))| {
                (j, integral.triangle_mean(t - offset, h), observed)
            }));
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_wrap() {
        assert!((angle_difference(3.1, -3.1) - (6.2 - std::f64::consts::TAU)).abs() < 1e-12);
    }
}
