//! Outages: time windows in which the receiver keeps fewer satellites.
//!
//! An outage keeps, of the satellites tracked at an epoch, the
//! `n_satellites` *highest* (0: a total outage). That is the urban-canyon
//! view — buildings hide the low satellites first — and, of the tracked
//! set, the *worst* geometry for the horizontal position: a line of sight
//! at elevation e carries cos e of horizontal information, so the highest
//! satellites constrain mostly the height and the clock. With 1-3
//! satellites no fix exists (loose coupling is then blind), while a
//! tightly coupled filter still uses every pseudorange and rate.
//!
//! Outages are applied to the finished measurements, after every random
//! draw: the satellites kept inside a window carry the same noise as
//! without the outage, so scenarios that differ only by their outages
//! are a paired comparison on the same draws.

use nalgebra::Vector3;

use super::selection::elevation;
use super::track::ReceiverTrack;
use crate::geodesy::ecef_to_geodetic;
use crate::gnss::GnssEpoch;

/// A time window with fewer satellites: none (total outage) or at most
/// `n_satellites` (partial: the highest of the tracked ones are kept, as
/// the module docs say).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outage {
    /// Start on the trajectory's time axis, s.
    pub start_s: f64,
    /// Length, s (the window is [start, start + duration)).
    pub duration_s: f64,
    /// Satellites still tracked during the window (0: total outage).
    pub n_satellites: usize,
}

/// Satellites allowed at trajectory time `t`: the tightest active outage,
/// else `usize::MAX`.
fn allowed(outages: &[Outage], t: f64) -> usize {
    outages
        .iter()
        .filter(|o| t >= o.start_s && t < o.start_s + o.duration_s)
        .map(|o| o.n_satellites)
        .min()
        .unwrap_or(usize::MAX)
}

/// Applies `outages` to one epoch measured from `receiver_ecef`: keeps the
/// allowed number of its highest satellites, in their original order.
pub(super) fn apply(outages: &[Outage], epoch: &mut GnssEpoch, receiver_ecef: &Vector3<f64>) {
    keep_highest(epoch, receiver_ecef, allowed(outages, epoch.time_s));
}

/// Keeps the `n` highest satellites of `epoch` seen from `receiver_ecef`,
/// in their original order (all of them when it has no more than `n`): the
/// selection of an outage, for simulated and real measurements alike. A
/// satellite without a usable position counts as the lowest.
pub fn keep_highest(epoch: &mut GnssEpoch, receiver_ecef: &Vector3<f64>, n: usize) {
    if n >= epoch.measurements.len() {
        return;
    }
    let geo = ecef_to_geodetic(receiver_ecef);
    let (sl, cl) = geo.latitude_rad.sin_cos();
    let (so, co) = geo.longitude_rad.sin_cos();
    let up = Vector3::new(cl * co, cl * so, sl);
    let mut by_elevation: Vec<(usize, f64)> = epoch
        .measurements
        .iter()
        .enumerate()
        .map(|(k, m)| {
            let e = elevation(&m.position_ecef, receiver_ecef, &up);
            (k, if e.is_finite() { e } else { f64::NEG_INFINITY })
        })
        .collect();
    by_elevation.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut keep = vec![false; epoch.measurements.len()];
    for &(k, _) in &by_elevation[..n] {
        keep[k] = true;
    }
    let mut k = 0;
    epoch.measurements.retain(|_| {
        k += 1;
        keep[k - 1]
    });
}

/// Applies `outages` to measurements simulated along `track` (the epochs
/// [`super::simulate`] returned, or any epochs whose times are track
/// times, within half a sample): the same selection as inside the
/// simulator, for scenarios that share one simulation.
pub fn apply_outages(epochs: &mut [GnssEpoch], track: &ReceiverTrack<'_>, outages: &[Outage]) {
    for epoch in epochs {
        let j = track.time_s.partition_point(|&t| t < epoch.time_s);
        let nearest = if j == track.time_s.len()
            || (j > 0 && epoch.time_s - track.time_s[j - 1] <= track.time_s[j] - epoch.time_s)
        {
            j.saturating_sub(1)
        } else {
            j
        };
        apply(outages, epoch, &track.position_ecef[nearest]);
    }
}
