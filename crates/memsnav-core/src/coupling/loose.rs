//! Loosely coupled GNSS/INS on position (and velocity) fixes (Groves
//! §14.3.2): the common baseline, and the filter for logs without raw
//! pseudoranges.
//!
//! A fix z = r + v, cov(v) = R, gives ẑ − z = δr + v. R is whitened by its
//! Cholesky factor L (z' = L⁻¹ z) so the three components become independent
//! unit-variance scalar updates, each gated like a pseudorange. The clock
//! states are not observed and their process noise is switched off.

use nalgebra::{Matrix3, Vector3};

use super::engine::{self, FilterState, ImuData, InitialState, MeasurementKind, Solution};
use super::tuning::FilterTuning;
use crate::filter::state::{POSITION, VELOCITY};
use crate::filter::SparseRow;
use crate::{validate, Error, Result};

/// A GNSS position (and optionally velocity) fix with its covariance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PositionFix {
    /// Fix time, s, on the IMU's time scale.
    pub time_s: f64,
    /// Position r^e, m.
    pub position_ecef: Vector3<f64>,
    /// Its covariance, m² (symmetric positive definite).
    pub position_covariance: Matrix3<f64>,
    /// Velocity v^e, m/s, when the receiver gives one.
    pub velocity_ecef: Option<Vector3<f64>>,
    /// Its covariance, m²/s².
    pub velocity_covariance: Matrix3<f64>,
}

impl engine::AidingEpoch for PositionFix {
    fn time_s(&self) -> f64 {
        self.time_s
    }
}

fn whitening(argument: &str, i: usize, r: &Matrix3<f64>) -> Result<Matrix3<f64>> {
    let bad = || {
        Error::invalid(
            argument,
            format!("fix {i}: covariance is not finite, symmetric and positive definite"),
        )
    };
    if !r.iter().all(|v| v.is_finite()) || (r - r.transpose()).abs().max() > 1e-9 * r.abs().max() {
        return Err(bad());
    }
    let l = r.cholesky().ok_or_else(bad)?.l();
    l.try_inverse().ok_or_else(bad)
}

/// Applies the whitened components of one fix block (position or velocity).
fn update_block<const N: usize>(
    s: &mut FilterState<N>,
    t: f64,
    first_state: usize,
    predicted_minus_measured: Vector3<f64>,
    l_inv: &Matrix3<f64>,
    kind: MeasurementKind,
) {
    let y = l_inv * predicted_minus_measured;
    for i in 0..3u16 {
        let row = i as usize;
        let meta = (t, i, kind);
        if !y[row].is_finite() {
            s.reject_invalid(meta);
            continue;
        }
        let mut entries = [(0, 0.0); 3];
        for (j, e) in entries.iter_mut().enumerate().take(row + 1) {
            *e = (first_state + j, l_inv[(row, j)]);
        }
        s.scalar(&SparseRow::new(&entries[..=row]), y[row], 1.0, meta);
    }
}

/// Runs the loosely coupled filter; `observe(k, state)` sees the state after
/// IMU sample k. Returns the measurement records.
pub fn run_loosely_coupled<const N: usize, O>(
    imu: &ImuData,
    fixes: &[PositionFix],
    initial: &InitialState,
    tuning: &FilterTuning,
    observe: O,
) -> Result<Vec<super::MeasurementRecord>>
where
    O: FnMut(usize, &FilterState<N>),
{
    imu.validate()?;
    engine::validate_epoch_times("fixes", fixes, imu.time_s, tuning.time_tolerance_s)?;
    let mut whiten = Vec::with_capacity(fixes.len());
    for (i, f) in fixes.iter().enumerate() {
        let lv = match f.velocity_ecef {
            Some(v) => {
                validate::finite_vectors("fixes.velocity_ecef", &[v]).map_err(|_| {
                    Error::invalid("fixes", format!("fix {i}: velocity is not finite"))
                })?;
                whitening("fixes", i, &f.velocity_covariance)?
            }
            None => Matrix3::zeros(),
        };
        whiten.push((whitening("fixes", i, &f.position_covariance)?, lv));
    }
    let mut tuning = *tuning;
    tuning.process_noise.clock_phase_psd = 0.0;
    tuning.process_noise.clock_frequency_psd = 0.0;
    let mut initial = *initial;
    initial.clock_offset_m.get_or_insert(0.0);
    initial.clock_drift_m_s.get_or_insert(0.0);
    let mut state = FilterState::<N>::new(&initial, &tuning)?;
    engine::run(
        imu,
        fixes,
        &mut state,
        tuning.time_tolerance_s,
        |s, i, f: &PositionFix| {
            let (lp, lv) = &whiten[i];
            update_block(
                s,
                f.time_s,
                POSITION,
                s.nav.position_ecef - f.position_ecef,
                lp,
                MeasurementKind::Position,
            );
            if let Some(v) = f.velocity_ecef {
                update_block(
                    s,
                    f.time_s,
                    VELOCITY,
                    s.nav.velocity_ecef - v,
                    lv,
                    MeasurementKind::Velocity,
                );
            }
        },
        observe,
    )?;
    Ok(state.records)
}

/// The loosely coupled filter's whole solution at every IMU sample.
pub fn loosely_coupled<const N: usize>(
    imu: &ImuData,
    fixes: &[PositionFix],
    initial: &InitialState,
    tuning: &FilterTuning,
) -> Result<Solution> {
    let mut sol = Solution::with_capacity(imu.time_s.len(), N);
    let records = run_loosely_coupled::<N, _>(imu, fixes, initial, tuning, |k, s| {
        sol.push(imu.time_s[k], s)
    })?;
    sol.measurements = records;
    Ok(sol)
}
