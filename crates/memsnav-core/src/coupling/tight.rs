//! Tightly coupled GNSS/INS: pseudorange and pseudorange-rate updates per
//! satellite (method §5; Groves §14.3.3).
//!
//! Measurement model at the antenna (errors = estimate − truth, u = line of
//! sight from the receiver to the satellite, [`super::antenna`] for δr_a
//! and δv_a):
//!
//! ```text
//! ρ̂ − ρ  = −u · δr_a + δc + δb_ρ + v_ρ      ρ̂ = range(r̂_a, v̂_a) + ĉ + b̂_ρ
//! ρ̂̇ − ρ̇  = −u · δv_a + g · δr_a + δċ + v_ρ̇     g = ∂ρ̇/∂r_a
//! ```
//!
//! (Sagnac and light time in [`crate::gnss::predicted_range`]; b_ρ the
//! satellite's range bias when the filter has range-bias states; a
//! Galileo, BeiDou or GLONASS pseudorange adds its system's inter-system
//! bias to ĉ, a state of its own.) GLONASS needs nothing more here: its
//! rates and carrier ranges arrive in metres, each scaled by its own
//! slot's wavelength (λ = c / (1602 + 0.5625 k) MHz,
//! [`crate::gnss::broadcast_epochs`]), and its pseudorange σ carries
//! RTKLIB's GLONASS factor 1.5 under the RTKLIB weights
//! ([`crate::gnss::rtklib_system_factor`]). The receiver's inter-frequency
//! biases differ per slot: their mean is in GLONASS's inter-system bias,
//! the rest in the range-bias states or the noise. The
//! range-rate row keeps the line of sight's turn with the receiver
//! position, g = −(I − u uᵀ) Δv / ρ + ω_ie × u (≈ 1e-4 per metre), which
//! Groves eq. 14.127 neglects. With four satellites or more the position
//! is observed directly and the term is negligible; with fewer it is what
//! makes the rate row the time derivative of the range row, so that
//! ranges and rates leave the same combination of position and clock
//! unobserved. Without it that combination looks observed as the
//! satellites move, and the covariance collapses while the error grows
//! (3 satellites, 900 s, 3σ 200 m against a 3 km error;
//! docs/explanation/few-satellites.md). An epoch's pseudoranges are one batch and its rates
//! another ([`super::engine::batch`]): tested together, a faulty satellite
//! excluded, a receiver clock jump moved into the clock; any number of
//! satellites (fewer than four included) refines the solution, and with
//! none the INS coasts. When the pseudoranges keep failing, the filter
//! resets to the epoch's least-squares fix (position, velocity, clock), or
//! opens its covariance when the epoch has fewer than four satellites.

use nalgebra::{Matrix3, Vector3};

use super::carrier;
use super::engine::batch::{median, BatchRules, CommonMode};
use super::engine::{self, FilterState, InitialState};
use super::records::MeasurementKind;
use super::run::Aiding;
use super::tuning::FilterTuning;
use crate::filter::state::{CLOCK_DRIFT, CLOCK_OFFSET, POSITION};
use crate::gauss_markov::correlated_sample_inflation;
use crate::gnss::{
    self, solve_fix_all_satellites, GnssEpoch, GnssSystem, SatelliteMeasurement,
    INTER_SYSTEM_BIAS_SYSTEMS,
};
use crate::{Error, Result};

impl engine::AidingEpoch for GnssEpoch {
    fn time_s(&self) -> f64 {
        self.time_s
    }
}

/// Sets an unknown clock offset (drift) to the median residual of this
/// epoch's finite pseudoranges (rates), so the test starts from a sane
/// prediction. The clock follows GPS when the epoch has GPS satellites (the
/// inter-system biases are relative to it), else the first system it has;
/// each other system's unknown inter-system bias is then its median
/// residual less the clock.
fn initialise_clock<const N: usize>(s: &mut FilterState<N>, epoch: &GnssEpoch, use_rate: bool) {
    let antenna = s.antenna();
    let residual = |m: &SatelliteMeasurement| {
        let p = gnss::predicted_range(
            &m.position_ecef,
            &m.velocity_ecef,
            &antenna.position_ecef,
            &antenna.velocity_ecef,
        );
        (
            m.pseudorange_m - p.range_m,
            m.pseudorange_rate_m_s - p.range_rate_m_s,
        )
    };
    let usable = epoch
        .measurements
        .iter()
        .filter(|m| m.has_usable_satellite_state());
    let range_residuals = |system: GnssSystem| -> Vec<f64> {
        usable
            .clone()
            .filter(|m| m.system == system)
            .map(|m| residual(m).0)
            .filter(|r| r.is_finite())
            .collect()
    };
    let mut rate: Vec<f64> = usable
        .clone()
        .map(|m| residual(m).1)
        .filter(|r| r.is_finite())
        .collect();
    if !s.clock_known.0 {
        let reference = GnssSystem::ALL
            .into_iter()
            .map(range_residuals)
            .find(|r| !r.is_empty());
        if let Some(mut range) = reference {
            s.clock_offset_m = median(&mut range);
            s.clock_known.0 = true;
        }
    }
    if s.clock_known.0 {
        for system in INTER_SYSTEM_BIAS_SYSTEMS {
            let k = system.inter_system_bias_index().unwrap_or_default();
            let mut range = range_residuals(system);
            if !s.inter_system_bias_known[k] && !range.is_empty() {
                s.inter_system_bias_m[k] = median(&mut range) - s.clock_offset_m;
                s.inter_system_bias_known[k] = true;
            }
        }
    }
    if !s.clock_known.1 && use_rate && !rate.is_empty() {
        s.clock_drift_m_s = median(&mut rate);
        s.clock_known.1 = true;
    }
}

/// The state index of `m`'s inter-system bias and its estimate, m: `None`
/// for GPS, the clock's reference; an error when the filter has no
/// inter-system-bias states.
fn inter_system_bias<const N: usize>(
    s: &FilterState<N>,
    m: &SatelliteMeasurement,
    time_s: f64,
) -> Result<Option<(usize, f64)>> {
    let Some(k) = m.system.inter_system_bias_index() else {
        return Ok(None);
    };
    match crate::filter::Layout::for_size::<N>().inter_system_bias {
        Some(first) => Ok(Some((first + k, s.inter_system_bias_m[k]))),
        None => Err(Error::invalid(
            "gnss",
            format!(
                "the epoch at t = {time_s} s has {} satellite {}, but this {N}-state filter has no \
                 inter-system-bias states: start it with them to combine systems",
                m.system,
                gnss::satellite_name(m.sat_id)
            ),
        )),
    }
}

/// Applies one GNSS epoch: the carrier changes since the previous epoch
/// as one batch (when used), the pseudoranges as one, then the rates.
pub(crate) fn update_epoch<const N: usize>(
    s: &mut FilterState<N>,
    epoch: &GnssEpoch,
    use_rate: bool,
) -> Result<()> {
    if !(s.clock_known.0 && (s.clock_known.1 || !use_rate)) {
        initialise_clock(s, epoch, use_rate);
    }
    if s.tuning.use_carrier_phase {
        carrier::update(s, epoch)?;
        update_code(s, epoch, use_rate)?;
        carrier::remember(s, epoch);
    } else {
        update_code(s, epoch, use_rate)?;
    }
    s.previous_epoch_s = Some(epoch.time_s);
    Ok(())
}

/// The pseudoranges as one batch, then the rates.
fn update_code<const N: usize>(
    s: &mut FilterState<N>,
    epoch: &GnssEpoch,
    use_rate: bool,
) -> Result<()> {
    let t = epoch.time_s;
    let rules = |mode| BatchRules {
        exclusion: true,
        common_mode: Some(mode),
    };
    let kind = MeasurementKind::Pseudorange;
    let antenna = s.antenna();
    let position_covariance: Matrix3<f64> = s.kf.p.fixed_view::<3, 3>(POSITION, POSITION).into();
    // Epochs that sample one correlated code error carry it once.
    let inflation = correlated_sample_inflation(
        s.tuning.pseudorange_correlation_time_s,
        s.previous_epoch_s.map(|before| t - before),
    )
    .sqrt();
    for m in &epoch.measurements {
        if !m.has_usable_satellite_state() || !m.pseudorange_m.is_finite() {
            s.reject_invalid(t, kind, m.sat_id);
            continue;
        }
        let p = gnss::predicted_range(
            &m.position_ecef,
            &m.velocity_ecef,
            &antenna.position_ecef,
            &antenna.velocity_ecef,
        );
        let mut h = antenna.position_row(&(-p.line_of_sight_ecef));
        h.push(CLOCK_OFFSET, 1.0);
        let mut y = p.range_m + s.clock_offset_m - m.pseudorange_m;
        if let Some((i, bias)) = inter_system_bias(s, m, t)? {
            h.push(i, 1.0);
            y += bias;
        }
        let mut std = m.pseudorange_std_m * inflation;
        match s.range_bias_state(m.sat_id, t) {
            Some((i, bias)) => {
                h.push(i, 1.0);
                y += bias;
            }
            None if crate::filter::Layout::for_size::<N>().range_bias.is_some() => {
                std = std.hypot(s.tuning.initial_std.range_bias_m);
            }
            None => {}
        }
        s.staged.note_nonlinearity(curvature(
            &position_covariance,
            &p.line_of_sight_ecef,
            p.range_m,
            std.max(s.tuning.floor.pseudorange_m),
        ));
        s.stage(t, kind, m.sat_id, h, y, std);
    }
    if !s.apply_staged(t, kind, rules(CommonMode::ClockOffset))? && s.reset_due(kind) {
        recover(s, epoch, use_rate)?;
    }
    if !use_rate {
        return Ok(());
    }
    let kind = MeasurementKind::PseudorangeRate;
    let antenna = s.antenna();
    for m in &epoch.measurements {
        // A rate with no usable std is absent (not every receiver gives one).
        if !(m.pseudorange_rate_std_m_s.is_finite() && m.pseudorange_rate_std_m_s > 0.0) {
            continue;
        }
        if !m.has_usable_satellite_state() || !m.pseudorange_rate_m_s.is_finite() {
            s.reject_invalid(t, kind, m.sat_id);
            continue;
        }
        let p = gnss::predicted_range(
            &m.position_ecef,
            &m.velocity_ecef,
            &antenna.position_ecef,
            &antenna.velocity_ecef,
        );
        let mut h = antenna.velocity_row(&(-p.line_of_sight_ecef)).combine(
            1.0,
            &antenna.position_row(&p.range_rate_position_gradient),
            1.0,
        );
        h.push(CLOCK_DRIFT, 1.0);
        let y = p.range_rate_m_s + s.clock_drift_m_s - m.pseudorange_rate_m_s;
        s.stage(t, kind, m.sat_id, h, y, m.pseudorange_rate_std_m_s);
    }
    if !s.apply_staged(t, kind, rules(CommonMode::ClockDrift))? && s.reset_due(kind) {
        recover_velocity(s, epoch)?;
    }
    Ok(())
}

/// The expected curvature term of a pseudorange over the position
/// uncertainty `p_rr`, in units of its std: the range from a position δr
/// off is ρ − u·δr + |δr⊥|² / (2ρ) + …, and E|δr⊥|² = tr((I − u uᵀ) P_rr)
/// (the second-order term the EKF drops; the second-order EKF of
/// Bar-Shalom et al. 2001, ch. 10, adds its expectation). Above about a
/// tenth, the first-order model the filter updates
/// with no longer describes the measurement (`super::integrity`).
fn curvature(p_rr: &Matrix3<f64>, u: &Vector3<f64>, range_m: f64, std_m: f64) -> f64 {
    (p_rr.trace() - u.dot(&(p_rr * u))) / (2.0 * range_m * std_m)
}

/// The epoch's satellites with finite pseudorange and satellite state, the
/// other systems' pseudoranges less their inter-system bias estimates so
/// that one receiver clock fits them all (the least-squares fix's model).
fn usable_epoch<const N: usize>(s: &FilterState<N>, epoch: &GnssEpoch) -> GnssEpoch {
    GnssEpoch {
        time_s: epoch.time_s,
        measurements: epoch
            .measurements
            .iter()
            .filter(|m| m.has_usable_satellite_state() && m.pseudorange_m.is_finite())
            .map(|m| SatelliteMeasurement {
                pseudorange_m: m.pseudorange_m
                    - m.system
                        .inter_system_bias_index()
                        .map_or(0.0, |k| s.inter_system_bias_m[k]),
                ..*m
            })
            .collect(),
    }
}

/// The pseudoranges kept failing: reset position, clock (and velocity and
/// drift from the rates, when the fix has them) to the epoch's
/// least-squares fix; with fewer than four satellites, or a fix that cannot
/// be solved, inflate the covariance instead.
fn recover<const N: usize>(
    s: &mut FilterState<N>,
    epoch: &GnssEpoch,
    use_rate: bool,
) -> Result<()> {
    let kind = MeasurementKind::Pseudorange;
    let usable = usable_epoch(s, epoch);
    let fix = if usable.measurements.len() >= 4 {
        solve_fix_all_satellites(&usable, Some(s.antenna().position_ecef)).ok()
    } else {
        None
    };
    let Some(fix) = fix.filter(|f| f.position_ecef.iter().all(|v| v.is_finite())) else {
        // Open the covariance by the factor the epoch missed its test by,
        // four times over, so its next epoch can pass.
        let factor = 4.0 * s.last_failure_ratio(kind).max(1.0);
        return s.inflate(epoch.time_s, kind, factor);
    };
    let pc = fix.position_clock_covariance;
    let position_cov: Matrix3<f64> = pc.fixed_view::<3, 3>(0, 0).into();
    let drift = (use_rate && fix.velocity_ecef.iter().all(|v| v.is_finite()))
        .then(|| (fix.clock_drift_m_s, fix.velocity_drift_covariance[(3, 3)]));
    s.reset_clock(fix.clock_offset_m, pc[(3, 3)], drift);
    if drift.is_some() {
        let vd = fix.velocity_drift_covariance;
        let velocity_cov: Matrix3<f64> = vd.fixed_view::<3, 3>(0, 0).into();
        s.reset_velocity(epoch.time_s, kind, &fix.velocity_ecef, &velocity_cov)?;
    }
    s.reset_position(
        epoch.time_s,
        kind,
        &fix.position_ecef,
        &position_cov,
        drift.is_some(),
    )?;
    s.recovered(epoch.time_s, kind)
}

/// The rates kept failing: reset velocity and clock drift to the epoch's
/// Doppler velocity when a fix gives one.
fn recover_velocity<const N: usize>(s: &mut FilterState<N>, epoch: &GnssEpoch) -> Result<()> {
    let kind = MeasurementKind::PseudorangeRate;
    let usable = usable_epoch(s, epoch);
    let fix = (usable.measurements.len() >= 4)
        .then(|| solve_fix_all_satellites(&usable, Some(s.antenna().position_ecef)).ok())
        .flatten()
        .filter(|f| f.velocity_ecef.iter().all(|v| v.is_finite()));
    let Some(fix) = fix else {
        let factor = 4.0 * s.last_failure_ratio(kind).max(1.0);
        return s.inflate(epoch.time_s, kind, factor);
    };
    let vd = fix.velocity_drift_covariance;
    s.clock_drift_m_s = fix.clock_drift_m_s;
    s.kf.reset_block::<1>(CLOCK_DRIFT, &nalgebra::Matrix1::new(vd[(3, 3)]));
    let velocity_cov: Matrix3<f64> = vd.fixed_view::<3, 3>(0, 0).into();
    s.reset_velocity(epoch.time_s, kind, &fix.velocity_ecef, &velocity_cov)?;
    s.recovered(epoch.time_s, kind)
}

impl Aiding for GnssEpoch {
    const ARGUMENT: &'static str = "gnss";
    /// Whether the pseudorange rates are used.
    type Prepared = bool;

    fn prepare(
        _epochs: &[Self],
        initial: &InitialState,
        tuning: &FilterTuning,
    ) -> Result<(bool, InitialState, FilterTuning)> {
        Ok((tuning.use_pseudorange_rate, *initial, *tuning))
    }

    fn needs_inter_system_biases(epochs: &[Self]) -> bool {
        epochs
            .iter()
            .flat_map(|e| &e.measurements)
            .any(|m| m.system.inter_system_bias_index().is_some())
    }

    fn update<const N: usize>(
        s: &mut FilterState<N>,
        use_rate: &bool,
        _: usize,
        epoch: &Self,
    ) -> Result<()> {
        update_epoch(s, epoch, *use_rate)
    }
}
