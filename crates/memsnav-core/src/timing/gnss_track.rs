//! Velocities of the straight segments between consecutive GNSS
//! positions: each is the mean velocity over its interval, so it carries no
//! latency of its own and serves as the time reference of the lag searches.

use nalgebra::Vector3;

use crate::geodesy::{c_n_e, geodetic_to_ecef, Geodetic};
use crate::validate;
use crate::{Error, Result};

/// The segment from epoch `k` to `k + 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Segment {
    /// Mid-time of the interval, s.
    pub mid_time_s: f64,
    /// Length of the interval, s.
    pub duration_s: f64,
    /// Mean velocity over the interval, NED at its start, m/s.
    pub velocity_ned: Vector3<f64>,
    /// No longer than 1.5 median intervals (a gap is not a segment).
    pub regular: bool,
}

/// Checks GNSS times (finite, increasing) and positions (finite
/// [lat rad, lon rad, h m], latitude within ±90°), at least 3 epochs.
pub(super) fn validate_track(time_s: &[f64], lla: &[Vector3<f64>]) -> Result<()> {
    validate::increasing_times("gnss_time", time_s)?;
    validate::same_length("lla", lla.len(), "gnss_time", time_s.len())?;
    validate::finite_vectors("lla", lla)?;
    if let Some(k) = lla
        .iter()
        .position(|p| p.x.abs() > std::f64::consts::FRAC_PI_2)
    {
        return Err(Error::invalid(
            "lla",
            format!("row {k}: latitude {} rad is beyond ±π/2", lla[k].x),
        ));
    }
    if time_s.len() < 3 {
        return Err(Error::invalid(
            "gnss_time",
            format!("needs at least 3 epochs, got {}", time_s.len()),
        ));
    }
    Ok(())
}

/// The segments between consecutive epochs of a validated track.
pub(super) fn segments(time_s: &[f64], lla: &[Vector3<f64>]) -> Vec<Segment> {
    let ecef: Vec<Vector3<f64>> = lla
        .iter()
        .map(|p| geodetic_to_ecef(Geodetic::new(p.x, p.y, p.z)))
        .collect();
    let mut durations: Vec<f64> = time_s.windows(2).map(|w| w[1] - w[0]).collect();
    let n = durations.len();
    let median = *durations.select_nth_unstable_by(n / 2, f64::total_cmp).1;
    (0..n)
        .map(|k| {
            let dt = time_s[k + 1] - time_s[k];
            let delta_ned = c_n_e(lla[k].x, lla[k].y).transpose() * (ecef[k + 1] - ecef[k]);
            Segment {
                mid_time_s: 0.5 * (time_s[k] + time_s[k + 1]),
                duration_s: dt,
                velocity_ned: delta_ned / dt,
                regular: dt <= 1.5 * median,
            }
        })
        .collect()
}
