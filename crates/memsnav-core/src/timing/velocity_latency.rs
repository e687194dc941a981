//! The latency of a GNSS solution's velocity behind its own positions.
//!
//! A receiver or RTK engine may report at t_k a velocity that belongs to
//! an earlier instant (a velocity from the last position difference, a
//! filtered Doppler velocity). The reference is the mean velocity of the
//! segment between consecutive positions, placed at the segment's
//! mid-time, where it has no latency (to second order in the interval).
//! The latency L minimises the RMS of v_reported(t_k) − v_segment(t_k − L),
//! the segment velocities interpolated linearly between mid-times; a
//! velocity computed as the backward difference of the positions has
//! L = h/2 exactly.

use nalgebra::Vector3;

use super::gnss_track::{segments, validate_track};
use super::lag_search::{lag_grid, search, Criterion, LagEstimate};
use crate::validate;
use crate::{Error, Result};

/// How to search for the latency.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityLatencyOptions {
    /// Latencies from −max to +max are tried, s.
    pub max_latency_s: f64,
    /// Grid step of the search, s.
    pub step_s: f64,
    /// Consecutive stretches of the log searched on their own for the spread.
    pub blocks: usize,
}

/// The latency of `velocity_ned` (m/s, reported at `gnss_time_s`) behind
/// the positions `lla` ([lat rad, lon rad, h m]) of the same solution:
/// positive when the velocity is late. `lag_s` of the result is the
/// latency; its score the RMS velocity difference there, m/s.
pub fn estimate_velocity_latency(
    gnss_time_s: &[f64],
    lla: &[Vector3<f64>],
    velocity_ned: &[Vector3<f64>],
    options: &VelocityLatencyOptions,
) -> Result<LagEstimate> {
    validate_track(gnss_time_s, lla)?;
    validate::same_length(
        "velocity_ned",
        velocity_ned.len(),
        "gnss_time",
        gnss_time_s.len(),
    )?;
    if velocity_ned.iter().any(|v| v.iter().any(|x| x.is_nan())) {
        return Err(Error::invalid(
            "velocity_ned",
            "has NaN rows: the solution carries no velocity there (an RTKLIB .pos without velocity columns?)",
        ));
    }
    validate::finite_vectors("velocity_ned", velocity_ned)?;
    let grid = lag_grid(
        options.max_latency_s,
        options.step_s,
        ["max_latency_s", "step_s"],
    )?;
    let max_lag = grid[grid.len() - 1];
    let segs = segments(gnss_time_s, lla);
    let mid: Vec<f64> = segs.iter().map(|s| s.mid_time_s).collect();
    // irregular_before[j]: irregular segments among 0..j.
    let mut irregular_before = vec![0_usize; segs.len() + 1];
    for (j, s) in segs.iter().enumerate() {
        irregular_before[j + 1] = irregular_before[j] + usize::from(!s.regular);
    }
    // Index of the segment whose mid-time starts the bracket of `t`.
    let bracket = |t: f64| mid.partition_point(|&m| m <= t).checked_sub(1);
    let epochs: Vec<usize> = (0..gnss_time_s.len())
        .filter(|&k| {
            let t = gnss_time_s[k];
            match (bracket(t - max_lag), bracket(t + max_lag)) {
                (Some(a), Some(b)) => {
                    b + 1 < segs.len() && irregular_before[b + 2] == irregular_before[a]
                }
                _ => false,
            }
        })
        .collect();
    if epochs.len() < 3 {
        return Err(Error::invalid(
            "gnss_time",
            format!(
                "only {} epochs have regular segments within ±max_latency_s = {max_lag} s",
                epochs.len()
            ),
        ));
    }
    search(
        &grid,
        epochs.len(),
        options.blocks,
        Criterion::RootMeanSquare,
        "max_latency_s",
        |latency, out| {
            for (j, &k) in epochs.iter().enumerate() {
                let t = gnss_time_s[k] - latency;
                let a = bracket(t).expect("checked for the whole window");
                let w = (t - mid[a]) / (mid[a + 1] - mid[a]);
                let reference = segs[a].velocity_ned * (1.0 - w) + segs[a + 1].velocity_ned * w;
                for axis in 0..3 {
                    out.push((j, reference[axis], velocity_ned[k][axis]));
                }
            }
        },
    )
}
