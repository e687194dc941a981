//! Time-differenced carrier phase (TDCP) in the tight filter (issue 24;
//! Wendel, Meister & Trommer 2006; Soon et al. 2008, GPS Solutions 12).
//!
//! A carrier range λφ holds an unknown constant per continuous lock (the
//! ambiguity); its change between two consecutive epochs does not. That
//! change is the range change plus the receiver clock's, to millimetres:
//!
//! ```text
//! Δφ = φ_k − φ_{k−1} = (ρ_k − ρ_{k−1}) + (c_k − c_{k−1}) + v_Δφ
//! Δφ̂ = ρ(r̂_a,k) − ρ(r̂⁺_a,k−1) + ĉ_k − ĉ⁺_{k−1}
//! Δφ̂ − Δφ ≈ −u · δv_a Δt + δċ Δt + w_c,          Δt = t_k − t_{k−1}
//! ```
//!
//! r̂⁺_a,k−1 and ĉ⁺_{k−1} are the antenna position and clock after the
//! previous epoch's updates, and r̂_a,k the INS's propagation from there, so
//! that the only error in the predicted change is the INS's displacement
//! error over the interval, δr_a,k − δr⁺_a,k−1 = δv_a Δt to first order
//! (the velocity error changes by under a millimetre per second over one
//! interval of a consumer IMU). The change is therefore applied before the
//! epoch's pseudoranges, while r̂_a,k is still the INS's propagation; and it
//! is a velocity measurement with the precision of the phase, not of the
//! Doppler. The line of sight's turn over the interval (1e-5 rad) is
//! dropped. w_c is the clock's white phase noise over the interval,
//! S_cφ Δt (the clock model's), common to every satellite: it is put into
//! the drift's variance (S_cφ / Δt) before the batch, so the batch
//! estimates the interval's mean frequency.
//!
//! Why time differences and not float ambiguities: no state per satellite
//! (the layouts stay as they are), and a slip spoils one difference only,
//! never a state the filter would carry on wrongly. What is given up is the
//! absolute range information of a carrier-smoothed code; the filter still
//! has the pseudoranges for that.
//!
//! A change is left out as a cycle slip when the receiver flags lost lock
//! or a half-cycle change ([`crate::gnss::CarrierPhase::loss_of_lock`]), or
//! when it disagrees with the Doppler integrated over the interval
//! (trapezoid of the two epochs' rates) by more than
//! [`DOPPLER_SLIP_SIGMA`] of their joint std, after the satellites' common
//! part (the clock's white phase noise) is removed by their median. A slip
//! too small for the Doppler (one cycle at low C/N0) fails the batch's
//! residual test and is excluded there ([`super::engine::batch`]).
//!
//! Successive differences share an epoch's phase noise (correlation −½);
//! the filter takes them as independent, which overstates the noise of
//! their sum and so errs on the safe side. Phase wind-up: an antenna
//! turning about its boresight (a walker's heading) changes every
//! satellite's phase by the same angle, which the clock absorbs; the part
//! that differs between satellites comes from tilting the antenna, a few
//! millimetres per epoch for a hand-held receiver (docs/real-data.md).

use super::engine::batch::{median, BatchRules, CommonMode};
use super::engine::FilterState;
use super::records::{MeasurementKind, MeasurementRecord, MeasurementStatus};
use crate::filter::state::CLOCK_DRIFT;
use crate::gnss::{self, GnssEpoch, SatelliteMeasurement};
use crate::Result;

/// A carrier change is a slip when it departs from the Doppler-predicted
/// change by more than this many of its stds (after the common part).
pub const DOPPLER_SLIP_SIGMA: f64 = 5.0;
/// Longest interval between epochs over which a carrier change is used, s:
/// beyond it the INS's displacement error is no longer its velocity error
/// times the interval.
pub const MAX_CARRIER_INTERVAL_S: f64 = 2.0;
/// Fewest carrier changes at an epoch for the Doppler test to remove their
/// median (the clock's common part); with fewer, that part is in the std.
const MIN_FOR_COMMON_PART: usize = 3;

/// One satellite's carrier at the previous epoch.
#[derive(Debug, Clone, Copy)]
struct CarrierThen {
    sat_id: u16,
    carrier_range_m: f64,
    carrier_std_m: f64,
    /// The range predicted from the corrected antenna position then, m.
    predicted_range_m: f64,
    /// The pseudorange rate then, m/s (NaN: none), and its std.
    rate_m_s: f64,
    rate_std_m_s: f64,
}

/// A carrier change at this epoch that passed the receiver's flags.
#[derive(Debug, Clone, Copy)]
struct Change {
    /// Index of the measurement in the epoch.
    index: usize,
    /// The satellite's carrier at the previous epoch.
    then: CarrierThen,
    /// Carrier change less the Doppler-predicted change, m (NaN: no rates).
    doppler_misfit_m: f64,
    /// Its std without the clock's common part, m.
    doppler_misfit_std_m: f64,
}

/// The carriers of the filter's previous GNSS epoch, and buffers reused
/// from epoch to epoch (no allocation once grown).
#[derive(Debug, Clone, Default)]
pub(crate) struct CarrierHistory {
    /// Time of the previous epoch, s (None before the first).
    time_s: Option<f64>,
    /// Receiver clock offset estimate after that epoch's updates, m.
    clock_offset_m: f64,
    then: Vec<CarrierThen>,
    next: Vec<CarrierThen>,
    changes: Vec<Change>,
    scratch: Vec<f64>,
}

/// Applies the epoch's carrier changes since the previous epoch as one
/// batch (module docs). Call before the epoch's pseudoranges.
pub(crate) fn update<const N: usize>(s: &mut FilterState<N>, epoch: &GnssEpoch) -> Result<()> {
    let t = epoch.time_s;
    let Some(dt) = s.carrier.time_s.map(|before| t - before) else {
        return Ok(());
    };
    if !(dt > 0.0 && dt <= MAX_CARRIER_INTERVAL_S) {
        return Ok(());
    }
    let kind = MeasurementKind::CarrierPhase;
    let mut changes = std::mem::take(&mut s.carrier.changes);
    changes.clear();
    for (index, m) in epoch.measurements.iter().enumerate() {
        let Some(carrier) = m.carrier else { continue };
        let Some(then) = s.carrier.then.iter().find(|c| c.sat_id == m.sat_id) else {
            continue;
        };
        if carrier.loss_of_lock {
            s.records.push(slip_record(t, m.sat_id));
            continue;
        }
        let rates = m.pseudorange_rate_m_s.is_finite() && then.rate_m_s.is_finite();
        let predicted = 0.5 * (m.pseudorange_rate_m_s + then.rate_m_s) * dt;
        changes.push(Change {
            index,
            then: *then,
            doppler_misfit_m: if rates {
                carrier.range_m - then.carrier_range_m - predicted
            } else {
                f64::NAN
            },
            doppler_misfit_std_m: (carrier.std_m.powi(2)
                + then.carrier_std_m.powi(2)
                + (0.5 * dt).powi(2)
                    * (m.pseudorange_rate_std_m_s.powi(2) + then.rate_std_m_s.powi(2)))
            .sqrt(),
        });
    }
    // The satellites' common part of the misfit: the clock's phase noise.
    let clock_variance = s.tuning.process_noise.clock_phase_psd * dt;
    let scratch = &mut s.carrier.scratch;
    scratch.clear();
    scratch.extend(
        changes
            .iter()
            .map(|c| c.doppler_misfit_m)
            .filter(|d| d.is_finite()),
    );
    let (common, common_variance) = if scratch.len() >= MIN_FOR_COMMON_PART {
        (median(scratch), 0.0)
    } else {
        (0.0, clock_variance)
    };
    let antenna = s.antenna();
    let mut staged = 0;
    for c in &changes {
        let m: &SatelliteMeasurement = &epoch.measurements[c.index];
        let carrier = m.carrier.expect("a change has a carrier");
        let misfit = c.doppler_misfit_m - common;
        let bound = DOPPLER_SLIP_SIGMA * (c.doppler_misfit_std_m.powi(2) + common_variance).sqrt();
        if misfit.abs() > bound {
            s.records.push(slip_record(t, m.sat_id));
            continue;
        }
        let p = gnss::predicted_range(
            &m.position_ecef,
            &m.velocity_ecef,
            &antenna.position_ecef,
            &antenna.velocity_ecef,
        );
        let mut h = antenna.velocity_row(&(-p.line_of_sight_ecef * dt));
        h.push(CLOCK_DRIFT, dt);
        let predicted_change =
            p.range_m - c.then.predicted_range_m + s.clock_offset_m - s.carrier.clock_offset_m;
        let y = predicted_change - (carrier.range_m - c.then.carrier_range_m);
        let std = carrier.std_m.hypot(c.then.carrier_std_m);
        s.stage(t, kind, m.sat_id, h, y, std);
        staged += 1;
    }
    s.carrier.changes = changes;
    if staged == 0 {
        return Ok(());
    }
    s.kf.add_variance(CLOCK_DRIFT, clock_variance / (dt * dt));
    let rules = BatchRules {
        exclusion: true,
        common_mode: Some(CommonMode::ClockDrift),
    };
    s.apply_staged(t, kind, rules)?;
    Ok(())
}

/// Remembers the epoch's carriers with the ranges predicted from the
/// antenna position after all of the epoch's updates. Call last.
pub(crate) fn remember<const N: usize>(s: &mut FilterState<N>, epoch: &GnssEpoch) {
    let antenna = s.antenna();
    let mut next = std::mem::take(&mut s.carrier.next);
    next.clear();
    next.extend(epoch.measurements.iter().filter_map(|m| {
        let carrier = m.carrier?;
        let p = gnss::predicted_range(
            &m.position_ecef,
            &m.velocity_ecef,
            &antenna.position_ecef,
            &antenna.velocity_ecef,
        );
        (carrier.range_m.is_finite() && p.range_m.is_finite()).then_some(CarrierThen {
            sat_id: m.sat_id,
            carrier_range_m: carrier.range_m,
            carrier_std_m: carrier.std_m,
            predicted_range_m: p.range_m,
            rate_m_s: if m.pseudorange_rate_std_m_s > 0.0 {
                m.pseudorange_rate_m_s
            } else {
                f64::NAN
            },
            rate_std_m_s: m.pseudorange_rate_std_m_s,
        })
    }));
    s.carrier.next = std::mem::replace(&mut s.carrier.then, next);
    s.carrier.time_s = Some(epoch.time_s);
    s.carrier.clock_offset_m = s.clock_offset_m;
}

fn slip_record(time_s: f64, sat_id: u16) -> MeasurementRecord {
    MeasurementRecord {
        time_s,
        id: sat_id,
        kind: MeasurementKind::CarrierPhase,
        innovation: f64::NAN,
        innovation_std: f64::NAN,
        nis: f64::NAN,
        status: MeasurementStatus::CycleSlip,
    }
}
