//! Tightly coupled GNSS/INS: pseudorange and pseudorange-rate updates per
//! satellite (method §5; Groves §14.3.3).
//!
//! Measurement model (errors = estimate − truth, u = line of sight from
//! the receiver to the satellite):
//!
//! ```text
//! ρ̂ − ρ  = −u · δr + δc + v_ρ           ρ̂ = range(r̂, v̂) + ĉ (Sagnac, light time)
//! ρ̂̇ − ρ̇  = −u · δv + δċ + v_ρ̇
//! ```
//!
//! The range-rate row neglects the line-of-sight change with position
//! (|v_sat − v| / ρ ≈ 2e-4 per metre of position error), as Groves eq. 14.127
//! does. Each satellite is a scalar update, so any number of satellites —
//! fewer than four included — refines the solution; with none the INS
//! coasts on its propagated covariance.

use nalgebra::Vector3;

use super::engine::{self, FilterState, ImuData, InitialState, MeasurementKind, Solution};
use super::tuning::FilterTuning;
use crate::filter::state::{CLOCK_DRIFT, CLOCK_OFFSET, POSITION, VELOCITY};
use crate::filter::SparseRow;
use crate::gnss::{self, GnssEpoch, SatelliteMeasurement};
use crate::Result;

impl engine::AidingEpoch for GnssEpoch {
    fn time_s(&self) -> f64 {
        self.time_s
    }
}

fn finite3(v: &Vector3<f64>) -> bool {
    v.iter().all(|x| x.is_finite())
}

fn satellite_usable(m: &SatelliteMeasurement) -> bool {
    finite3(&m.position_ecef) && finite3(&m.velocity_ecef) && m.position_ecef.norm() > 1.0e7
}

fn median(values: &mut [f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    values.sort_by(f64::total_cmp);
    let n = values.len();
    Some(if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    })
}

/// Sets an unknown clock offset (drift) to the median residual of this
/// epoch's finite pseudoranges (rates), so the gate starts from a sane
/// prediction. At most 64 satellites are used.
fn initialise_clock<const N: usize>(s: &mut FilterState<N>, epoch: &GnssEpoch, use_rate: bool) {
    let mut range = [0.0; 64];
    let mut rate = [0.0; 64];
    let (mut nr, mut nd) = (0, 0);
    for m in epoch
        .measurements
        .iter()
        .filter(|m| satellite_usable(m))
        .take(64)
    {
        let p = gnss::predicted_range(
            &m.position_ecef,
            &m.velocity_ecef,
            &s.nav.position_ecef,
            &s.nav.velocity_ecef,
        );
        let r = m.pseudorange_m - p.range_m;
        if r.is_finite() {
            range[nr] = r;
            nr += 1;
        }
        let d = m.pseudorange_rate_m_s - p.range_rate_m_s;
        if d.is_finite() {
            rate[nd] = d;
            nd += 1;
        }
    }
    if !s.clock_known.0 {
        if let Some(c) = median(&mut range[..nr]) {
            s.clock_offset_m = c;
            s.clock_known.0 = true;
        }
    }
    if !s.clock_known.1 && use_rate {
        if let Some(d) = median(&mut rate[..nd]) {
            s.clock_drift_m_s = d;
            s.clock_known.1 = true;
        }
    }
}

/// Applies one GNSS epoch: every pseudorange, then every pseudorange rate.
pub(crate) fn update_epoch<const N: usize>(
    s: &mut FilterState<N>,
    epoch: &GnssEpoch,
    use_rate: bool,
) {
    if !(s.clock_known.0 && (s.clock_known.1 || !use_rate)) {
        initialise_clock(s, epoch, use_rate);
    }
    let t = epoch.time_s;
    let predictions = |s: &FilterState<N>, m: &SatelliteMeasurement| {
        gnss::predicted_range(
            &m.position_ecef,
            &m.velocity_ecef,
            &s.nav.position_ecef,
            &s.nav.velocity_ecef,
        )
    };
    for m in &epoch.measurements {
        let meta = (t, m.sat_id, MeasurementKind::Pseudorange);
        if !satellite_usable(m) || !m.pseudorange_m.is_finite() {
            s.reject_invalid(meta);
            continue;
        }
        let p = predictions(s, m);
        let u = p.line_of_sight_ecef;
        let h = SparseRow::new(&[
            (POSITION, -u.x),
            (POSITION + 1, -u.y),
            (POSITION + 2, -u.z),
            (CLOCK_OFFSET, 1.0),
        ]);
        let y = p.range_m + s.clock_offset_m - m.pseudorange_m;
        s.scalar(&h, y, m.pseudorange_std_m.powi(2), meta);
    }
    if !use_rate {
        return;
    }
    for m in &epoch.measurements {
        let meta = (t, m.sat_id, MeasurementKind::PseudorangeRate);
        // A rate with no usable std is absent (not every receiver gives one).
        if !(m.pseudorange_rate_std_m_s.is_finite() && m.pseudorange_rate_std_m_s > 0.0) {
            continue;
        }
        if !satellite_usable(m) || !m.pseudorange_rate_m_s.is_finite() {
            s.reject_invalid(meta);
            continue;
        }
        let p = predictions(s, m);
        let u = p.line_of_sight_ecef;
        let h = SparseRow::new(&[
            (VELOCITY, -u.x),
            (VELOCITY + 1, -u.y),
            (VELOCITY + 2, -u.z),
            (CLOCK_DRIFT, 1.0),
        ]);
        let y = p.range_rate_m_s + s.clock_drift_m_s - m.pseudorange_rate_m_s;
        s.scalar(&h, y, m.pseudorange_rate_std_m_s.powi(2), meta);
    }
}

/// Runs the tightly coupled filter with `N` error states (17, or 23 with
/// scale factors) over the IMU series and GNSS epochs; `observe(k, state)`
/// sees the state after IMU sample k. Returns the measurement records.
pub fn run_tightly_coupled<const N: usize, O>(
    imu: &ImuData,
    gnss: &[GnssEpoch],
    initial: &InitialState,
    tuning: &FilterTuning,
    observe: O,
) -> Result<Vec<super::MeasurementRecord>>
where
    O: FnMut(usize, &FilterState<N>),
{
    imu.validate()?;
    engine::validate_epoch_times("gnss", gnss, imu.time_s, tuning.time_tolerance_s)?;
    let mut state = FilterState::<N>::new(initial, tuning)?;
    let use_rate = tuning.use_pseudorange_rate;
    engine::run(
        imu,
        gnss,
        &mut state,
        tuning.time_tolerance_s,
        |s, _, e| update_epoch(s, e, use_rate),
        observe,
    )?;
    Ok(state.records)
}

/// The tightly coupled filter's whole solution at every IMU sample.
pub fn tightly_coupled<const N: usize>(
    imu: &ImuData,
    gnss: &[GnssEpoch],
    initial: &InitialState,
    tuning: &FilterTuning,
) -> Result<Solution> {
    let mut sol = Solution::with_capacity(imu.time_s.len(), N);
    let records = run_tightly_coupled::<N, _>(imu, gnss, initial, tuning, |k, s| {
        sol.push(imu.time_s[k], s)
    })?;
    sol.measurements = records;
    Ok(sol)
}
