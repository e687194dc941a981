//! Time-differenced carrier phase (TDCP) in the tight filter
//! (Wendel, Meister & Trommer 2006; Soon et al. 2008, GPS Solutions 12).
//!
//! A carrier range λφ holds an unknown constant per continuous lock (the
//! ambiguity); its change between two consecutive epochs does not. That
//! change is the range change plus the receiver clock's, to millimetres:
//!
//! ```text
//! Δφ  = φ_k − φ_{k−1} = (ρ_k − ρ_{k−1}) + (c_k − c_{k−1}) + v_Δφ
//! Δρ̂  = ρ(r̂_a,k) − ρ(r̂⁺_a,k−1)
//! Δρ̂ − Δφ ≈ −u · (δv_a Δt − ½ δa Δt²) − Δc + v,   Δt = t_k − t_{k−1}
//! ```
//!
//! r̂⁺_a,k−1 is the antenna position after the previous epoch's updates and
//! r̂_a,k the INS's propagation from there, so that the only error in the
//! predicted change is the INS's displacement error over the interval,
//! δr_a,k − δr⁺_a,k−1, in terms of the state at t_k: the velocity error
//! now less what the acceleration error δa = −[(Ĉ f̂)×] ψ − Ĉ δb_a added
//! over the interval ([`super::antenna::AntennaPrediction::displacement_row`]).
//! The δa term matters: a consumer IMU's 0.05 rad of tilt is 0.5 m/s² of
//! δa, 1.6 cm over 0.25 s, several times the phase noise; without it the
//! simulated consumer grade's NEES/dof with carrier phase was above 5.
//! The change is therefore applied before the epoch's pseudoranges, while
//! r̂_a,k is still the INS's propagation; and it measures the velocity (and
//! through δa the tilt and the accelerometer bias) with the precision of
//! the phase, not of the Doppler. The process noise entering within the
//! interval (the accelerometers' white noise: √(S Δt³/3), under a
//! millimetre for a consumer IMU over 0.25 s) is left to the phase noise
//! and the floor. The line of sight's turn over the interval (1e-5 rad) is
//! dropped.
//!
//! The clock's change Δc is the same in every satellite's change, and it is
//! eliminated rather than estimated: each change and its row have the
//! epoch's weighted mean (weights 1/σ²) removed, and are then applied as
//! independent with their own σ, which gives exactly the update of a
//! nuisance parameter with a flat prior (the projection is orthogonal in
//! the weighted norm: Hᵀ(W − w wᵀ/Σw)H either way). Estimating it through
//! the drift state instead ties the phase's clock change, the mean
//! frequency over the interval, to the drift at the epoch, which the
//! Doppler measures: the walk's receiver clock drifts from −61 to −81 m/s
//! over its 133 s (−0.17 m/s²), so the two disagree by half the change over
//! an interval, the batches pull the drift back and forth, and the
//! vertical takes part of it (docs/how-to/multi-gnss.md).
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
//! part (the clock's) is removed by their median. A change too far from the
//! INS's prediction, about the satellites' median, by more than
//! [`RESIDUAL_SIGMA`] of its predicted std is excluded (a slip too small for
//! the Doppler: one cycle at low C/N0); the rest go through the batch test
//! ([`super::engine::batch`]).
//!
//! Successive differences share an epoch's phase noise (correlation −½);
//! the filter takes them as independent, which overstates the noise of
//! their sum and so errs on the safe side. Phase wind-up: an antenna
//! turning about its boresight (a walker's heading) changes every
//! satellite's phase by the same angle, which the clock absorbs; the part
//! that differs between satellites comes from tilting the antenna, a few
//! millimetres per epoch for a hand-held receiver (docs/how-to/multi-gnss.md).

use nalgebra::Vector3;

use super::engine::batch::{median, BatchRules};
use super::engine::carrier_history::{CarrierThen, Change};
use super::engine::FilterState;
use super::records::{MeasurementKind, MeasurementRecord, MeasurementStatus};
use crate::gnss::{self, GnssEpoch};
use crate::Result;

/// A carrier change is a slip when it departs from the Doppler-predicted
/// change by more than this many of its stds (after the common part).
pub const DOPPLER_SLIP_SIGMA: f64 = 3.0;
/// A carrier change is excluded when it departs from the INS's predicted
/// change by more than this many of its predicted stds (after the common
/// part).
pub const RESIDUAL_SIGMA: f64 = 4.0;
/// Longest interval between epochs over which a carrier change is used, s:
/// beyond it the INS's displacement error is no longer its velocity error
/// times the interval.
pub const MAX_CARRIER_INTERVAL_S: f64 = 2.0;
/// Fewest carrier changes at an epoch for the Doppler test to remove their
/// median (the clock's common part); with fewer, that part is in the std.
const MIN_FOR_COMMON_PART: usize = 3;
/// Fewest carrier changes an epoch's batch is applied with: one more than
/// its unknowns (velocity and the clock's change), so that the residual
/// test can find a slip the Doppler test missed. With four, a slip goes
/// into the velocity unseen: on the walk's four GPS satellites an early
/// version of this filter without the rule did worse than the code alone.
pub const MIN_CARRIER_CHANGES: usize = 5;

/// Applies the epoch's carrier changes since the previous epoch as one
/// batch (module docs). Call before the epoch's pseudoranges.
pub(crate) fn update<const N: usize>(s: &mut FilterState<N>, epoch: &GnssEpoch) -> Result<()> {
    let t = epoch.time_s;
    let Some(dt) = s.previous_epoch_s.map(|before| t - before) else {
        return Ok(());
    };
    if !(dt > 0.0 && dt <= MAX_CARRIER_INTERVAL_S) {
        return Ok(());
    }
    let kind = MeasurementKind::CarrierPhase;
    let antenna = s.antenna();
    let floor = s.tuning.floor.carrier_phase_m;
    let mut changes = std::mem::take(&mut s.carrier.changes);
    changes.clear();
    for (index, m) in epoch.measurements.iter().enumerate() {
        let Some(carrier) = m.carrier else { continue };
        let Some(then) = s.carrier.then.iter().find(|c| c.sat_id == m.sat_id) else {
            continue;
        };
        if carrier.loss_of_lock {
            s.records.push(record(
                t,
                m.sat_id,
                MeasurementStatus::CycleSlip,
                f64::NAN,
                f64::NAN,
            ));
            continue;
        }
        if !m.has_usable_satellite_state() {
            s.reject_invalid(t, kind, m.sat_id);
            continue;
        }
        let change_m = carrier.range_m - then.carrier_range_m;
        let doppler_m = 0.5 * (m.pseudorange_rate_m_s + then.rate_m_s) * dt;
        let p = gnss::predicted_range(
            &m.position_ecef,
            &m.velocity_ecef,
            &antenna.position_ecef,
            &antenna.velocity_ecef,
        );
        changes.push(Change {
            index,
            // NaN without both rates: no Doppler test.
            doppler_misfit_m: change_m - doppler_m,
            doppler_misfit_std_m: (carrier.std_m.powi(2)
                + then.carrier_std_m.powi(2)
                + (0.5 * dt).powi(2)
                    * (m.pseudorange_rate_std_m_s.powi(2) + then.rate_std_m_s.powi(2)))
            .sqrt(),
            residual_m: p.range_m - then.predicted_range_m - change_m,
            std_m: carrier.std_m.hypot(then.carrier_std_m).max(floor),
            line_of_sight_ecef: p.line_of_sight_ecef,
        });
    }
    // The Doppler test, about the satellites' median misfit (the clock's
    // white phase noise); with too few for a median, that noise in the std.
    let clock_variance = s.tuning.process_noise.clock_phase_psd * dt;
    let (common, common_variance) =
        common_part(&mut s.carrier.scratch, &changes, |c| c.doppler_misfit_m)
            .map_or((0.0, clock_variance), |m| (m, 0.0));
    changes.retain(|c| {
        let misfit = c.doppler_misfit_m - common;
        let slip = misfit.abs()
            > DOPPLER_SLIP_SIGMA * (c.doppler_misfit_std_m.powi(2) + common_variance).sqrt();
        if slip {
            let id = epoch.measurements[c.index].sat_id;
            s.records.push(record(
                t,
                id,
                MeasurementStatus::CycleSlip,
                f64::NAN,
                f64::NAN,
            ));
        }
        !slip
    });
    // The residual test against the INS's prediction, about the median.
    let common = common_part(&mut s.carrier.scratch, &changes, |c| c.residual_m);
    let p = &s.kf.p;
    changes.retain(|c| {
        let h = antenna.displacement_row(&-c.line_of_sight_ecef, dt);
        let std = (c.std_m.powi(2) + h.dot(&h.times(p))).sqrt();
        let misfit = c.residual_m - common.unwrap_or(0.0);
        let excluded = common.is_some() && misfit.abs() > RESIDUAL_SIGMA * std;
        if excluded {
            let id = epoch.measurements[c.index].sat_id;
            s.records
                .push(record(t, id, MeasurementStatus::Excluded, -misfit, std));
        }
        !excluded
    });
    if changes.len() < MIN_CARRIER_CHANGES {
        // Recorded, so that a run says why its carrier phase did nothing.
        let common = common.unwrap_or(0.0);
        for c in &changes {
            let id = epoch.measurements[c.index].sat_id;
            s.records.push(record(
                t,
                id,
                MeasurementStatus::TooFewCarrierChanges,
                -(c.residual_m - common),
                c.std_m,
            ));
        }
        s.carrier.changes = changes;
        return Ok(());
    }
    // The clock's change eliminated: weighted means removed (module docs).
    let weight = |c: &Change| c.std_m.powi(-2);
    let total: f64 = changes.iter().map(weight).sum();
    let mean_residual_m = changes
        .iter()
        .map(|c| weight(c) * c.residual_m)
        .sum::<f64>()
        / total;
    let mean_line_of_sight: Vector3<f64> = changes
        .iter()
        .map(|c| weight(c) * c.line_of_sight_ecef)
        .sum::<Vector3<f64>>()
        / total;
    for c in &changes {
        let h = antenna.displacement_row(&-(c.line_of_sight_ecef - mean_line_of_sight), dt);
        let id = epoch.measurements[c.index].sat_id;
        s.stage(t, kind, id, h, c.residual_m - mean_residual_m, c.std_m);
    }
    s.carrier.changes = changes;
    let rules = BatchRules {
        exclusion: true,
        common_mode: None,
    };
    s.apply_staged(t, kind, rules)?;
    Ok(())
}

/// The median of `value` over `changes` where finite (None with fewer than
/// [`MIN_FOR_COMMON_PART`]).
fn common_part(
    scratch: &mut Vec<f64>,
    changes: &[Change],
    value: impl Fn(&Change) -> f64,
) -> Option<f64> {
    scratch.clear();
    scratch.extend(changes.iter().map(value).filter(|v| v.is_finite()));
    (scratch.len() >= MIN_FOR_COMMON_PART).then(|| median(scratch))
}

/// Remembers the epoch's carriers with the ranges predicted from the
/// antenna position after all of the epoch's updates. Call last.
pub(crate) fn remember<const N: usize>(s: &mut FilterState<N>, epoch: &GnssEpoch) {
    let antenna = s.antenna();
    let mut next = std::mem::take(&mut s.carrier.next);
    next.clear();
    next.extend(epoch.measurements.iter().filter_map(|m| {
        let carrier = m.carrier.filter(|_| m.has_usable_satellite_state())?;
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
}

fn record(
    time_s: f64,
    sat_id: u16,
    status: MeasurementStatus,
    innovation: f64,
    innovation_std: f64,
) -> MeasurementRecord {
    MeasurementRecord {
        time_s,
        id: sat_id,
        kind: MeasurementKind::CarrierPhase,
        innovation,
        innovation_std,
        nis: (innovation / innovation_std).powi(2),
        status,
    }
}
