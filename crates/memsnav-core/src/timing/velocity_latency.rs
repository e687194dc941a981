//! The latency of a GNSS solution's velocity behind its own positions.
//!
//! A receiver or RTK engine may report at t_k a velocity that belongs to
//! an earlier instant (a velocity from the last position difference, a
//! filtered Doppler velocity). The reference is the segment velocity
//! (r_{j+1} − r_j) / h_j: the exact mean of the true velocity over
//! [t_j, t_{j+1}], with no latency. A velocity late by L has the same mean
//! over [t_j + L, t_{j+1} + L]; that mean of the reported samples, joined
//! by straight lines, is compared with the segment velocity, and L
//! minimises the RMS difference. Both sides are means over the same
//! interval, so neither the averaging nor the noise of an interpolated
//! reference (which would vary with L) moves the minimum; a velocity
//! computed as the backward difference of the positions has L = h/2.

use nalgebra::Vector3;

use super::gnss_track::{segments, validate_track};
use super::integral::Integrals;
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
    // irregular_before[j]: irregular segments among 0..j.
    let mut irregular_before = vec![0_usize; segs.len() + 1];
    for (j, s) in segs.iter().enumerate() {
        irregular_before[j + 1] = irregular_before[j] + usize::from(!s.regular);
    }
    // Segments j whose shifted interval stays among regular segments for
    // every latency of the grid.
    let last = gnss_time_s.len() - 1;
    let usable: Vec<usize> = (0..segs.len())
        .filter(|&j| {
            let first = gnss_time_s.partition_point(|&t| t <= gnss_time_s[j] - max_lag);
            let end = gnss_time_s.partition_point(|&t| t < gnss_time_s[j + 1] + max_lag);
            first >= 1 && end <= last && irregular_before[end] == irregular_before[first - 1]
        })
        .collect();
    if usable.len() < 3 {
        return Err(Error::invalid(
            "gnss_time",
            format!(
                "only {} position intervals lie within regular epochs ±max_latency_s = {max_lag} s",
                usable.len()
            ),
        ));
    }
    let components: Vec<Integrals> = (0..3)
        .map(|axis| Integrals::new(gnss_time_s, velocity_ned.iter().map(|v| v[axis]).collect()))
        .collect();
    search(
        &grid,
        usable.len(),
        options.blocks,
        Criterion::RootMeanSquare,
        "max_latency_s",
        |latency, out| {
            for (i, &j) in usable.iter().enumerate() {
                let (start, end) = (gnss_time_s[j] + latency, gnss_time_s[j + 1] + latency);
                for (axis, reported) in components.iter().enumerate() {
                    out.push((i, reported.box_mean(start, end), segs[j].velocity_ned[axis]));
                }
            }
        },
    )
}
