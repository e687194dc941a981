//! Loosely coupled GNSS/INS on position (and velocity) fixes (Groves
//! §14.3.2): the common baseline, and the filter for logs without raw
//! pseudoranges.
//!
//! A fix of the antenna z = r_a + v, cov(v) = R, gives ẑ − z = δr_a + v
//! ([`super::antenna`] for δr_a, δv_a through the lever arm). R is whitened
//! by its Cholesky factor L (z' = L⁻¹ z) so the three components become
//! independent unit-variance measurements; the three are one batch, tested
//! together ([`super::engine::batch`]): a fix is applied whole or not at all.
//! A horizontal-only velocity (a speed and course over ground: NMEA) is
//! the two components z_h = E_hᵀ v along the local north and east axes E_h
//! at the fix, whitened by the Cholesky factor of E_hᵀ R E_h: two
//! measurements, none along the vertical, which the fix does not measure. A
//! velocity with a latency L is compared with the prediction moved back by
//! L along the INS acceleration. When fixes keep failing, position
//! (velocity) is reset to the fix. The clock states are not observed and
//! their process noise is switched off.

use nalgebra::{Matrix3, Vector3};

use super::engine::batch::BatchRules;
use super::engine::{self, FilterState, InitialState};
use super::records::MeasurementKind;
use super::run::Aiding;
use super::tuning::FilterTuning;
use crate::filter::state::VELOCITY;
use crate::gauss_markov::correlated_sample_inflation;
use crate::geodesy::{c_n_e, ecef_to_geodetic};
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
    /// Only the velocity's horizontal part is measured (a speed and course
    /// over ground: NMEA): the filter takes its north and east components
    /// at the fix's position, nothing along the local vertical (the
    /// vertical component of `velocity_ecef` and the vertical row and
    /// column of `velocity_covariance` in local axes are not read).
    pub velocity_horizontal_only: bool,
}

impl engine::AidingEpoch for PositionFix {
    fn time_s(&self) -> f64 {
        self.time_s
    }
}

/// A fix block's covariance as the filter uses it, and its whitening.
#[derive(Debug, Clone, Copy)]
pub struct Whitened {
    /// R with its eigenvalues raised to at least floor² (the floor of
    /// [`super::MeasurementFloor`] in every direction); of a horizontal
    /// block, E_h R_h Eₕᵀ (nothing along the vertical).
    covariance: Matrix3<f64>,
    /// L⁻¹ with L Lᵀ = the floored R; of a horizontal block, its first two
    /// rows are L_h⁻¹ E_hᵀ (L_h L_hᵀ = the floored R_h) and the third is zero.
    l_inv: Matrix3<f64>,
    /// The measurements of the block: 3, or 2 for a horizontal velocity.
    rows: usize,
    /// The local down axis at the fix, ECEF, for a horizontal block.
    down_ecef: Option<Vector3<f64>>,
}

/// Where a fix came from, for the words of its errors: fix i of a batch
/// (the `fixes` argument), or a single call whose arguments are named
/// (the step API's `update_fix`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum FixOrigin {
    Batch(usize),
    Single,
}

impl FixOrigin {
    /// The error that `what` is wrong: with the fix's index under
    /// `fixes`, or under `argument` for a single call.
    fn invalid(self, argument: &str, what: &str) -> Error {
        match self {
            FixOrigin::Batch(i) => Error::invalid("fixes", format!("fix {i}: {what}")),
            FixOrigin::Single => Error::invalid(argument, what),
        }
    }
}

fn whitening(origin: FixOrigin, argument: &str, r: &Matrix3<f64>, floor: f64) -> Result<Whitened> {
    let bad = || {
        origin.invalid(
            argument,
            "covariance is not finite, symmetric and positive definite",
        )
    };
    if !r.iter().all(|v| v.is_finite()) || (r - r.transpose()).abs().max() > 1e-9 * r.abs().max() {
        return Err(bad());
    }
    r.cholesky().ok_or_else(bad)?;
    let mut eig = r.symmetric_eigen();
    eig.eigenvalues.apply(|v| *v = v.max(floor * floor));
    let covariance = eig.recompose();
    let l = covariance.cholesky().ok_or_else(bad)?.l();
    Ok(Whitened {
        covariance,
        l_inv: l.try_inverse().ok_or_else(bad)?,
        rows: 3,
        down_ecef: None,
    })
}

/// The whitening of the horizontal part of a velocity covariance `r`
/// (ECEF) at `position_ecef`: R_h = E_hᵀ R E_h in the local north-east
/// axes E_h (C_n^e's first two columns, Groves eq. 2.150), floored and
/// whitened as [`whitening`] does a full block.
fn horizontal_whitening(
    origin: FixOrigin,
    argument: &str,
    r: &Matrix3<f64>,
    position_ecef: &Vector3<f64>,
    floor: f64,
) -> Result<Whitened> {
    let geo = ecef_to_geodetic(position_ecef);
    let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
    let e_h = cne.fixed_columns::<2>(0).into_owned();
    let r_h = e_h.transpose() * r * e_h;
    let bad = || {
        origin.invalid(
            argument,
            "horizontal velocity covariance is not finite, symmetric and positive definite",
        )
    };
    if !r_h.iter().all(|v| v.is_finite())
        || (r_h - r_h.transpose()).abs().max() > 1e-9 * r_h.abs().max()
    {
        return Err(bad());
    }
    r_h.cholesky().ok_or_else(bad)?;
    let mut eig = r_h.symmetric_eigen();
    eig.eigenvalues.apply(|v| *v = v.max(floor * floor));
    let r_h = eig.recompose();
    let l_inv = r_h
        .cholesky()
        .ok_or_else(bad)?
        .l()
        .try_inverse()
        .ok_or_else(bad)?;
    let mut whitening_rows = Matrix3::zeros();
    whitening_rows
        .fixed_rows_mut::<2>(0)
        .copy_from(&(l_inv * e_h.transpose()));
    Ok(Whitened {
        covariance: e_h * r_h * e_h.transpose(),
        l_inv: whitening_rows,
        rows: 2,
        down_ecef: Some(cne.column(2).into_owned()),
    })
}

/// Applies the whitened components of one fix block (position or
/// velocity) as one batch; after `reset_after_failed_epochs` failures in a
/// row, resets the block to the fix.
fn update_block<const N: usize>(
    s: &mut FilterState<N>,
    t: f64,
    kind: MeasurementKind,
    measured: &Vector3<f64>,
    w: &Whitened,
    has_velocity: bool,
) -> Result<()> {
    let antenna = s.antenna();
    // With fix-error states the fix is r_a + b + v: b, its Gauss-Markov
    // error per ECEF axis, held in the range-bias slots (one per axis).
    let fix_error = match kind {
        MeasurementKind::Position => s.fix_error_states(t),
        _ => None,
    };
    let error_estimate = fix_error.map_or(Vector3::zeros(), |(_, b)| b);
    let predicted = match kind {
        MeasurementKind::Position => antenna.position_ecef + error_estimate,
        _ => antenna.fix_velocity_ecef,
    };
    let y = w.l_inv * (predicted - measured);
    for i in 0..w.rows as u16 {
        let row = w.l_inv.row(i as usize).transpose();
        let mut h = match kind {
            MeasurementKind::Position => antenna.position_row(&row),
            _ => antenna.fix_velocity_row(&row),
        };
        if let Some((states, _)) = fix_error {
            for (axis, &state) in states.iter().enumerate() {
                h.push(state, row[axis]);
            }
        }
        s.stage(t, kind, i, h, y[i as usize], 1.0);
    }
    let rules = BatchRules {
        exclusion: false,
        common_mode: None,
    };
    if !s.apply_staged(t, kind, rules)? && s.reset_due(kind) {
        match kind {
            MeasurementKind::Position => {
                let antenna = measured - error_estimate;
                s.reset_position(t, kind, &antenna, &w.covariance, has_velocity)?
            }
            _ => match w.down_ecef {
                // A horizontal fix resets the horizontal velocity; the
                // vertical keeps the filter's own value and variance.
                Some(d) => {
                    let vertical_variance =
                        d.dot(&(s.kf.p.fixed_view::<3, 3>(VELOCITY, VELOCITY) * d));
                    let along_down = d * d.transpose();
                    let velocity = measured - along_down * measured + along_down * predicted;
                    let covariance = w.covariance + along_down * vertical_variance;
                    s.reset_velocity(t, kind, &velocity, &covariance)?
                }
                None => s.reset_velocity(t, kind, measured, &w.covariance)?,
            },
        }
        s.recovered(t, kind)?;
    }
    Ok(())
}

/// The whitened position and velocity blocks of a fix, after checking
/// that its values are finite and its covariances are covariances.
fn whiten_fix(
    origin: FixOrigin,
    f: &PositionFix,
    floor: &super::MeasurementFloor,
) -> Result<(Whitened, Option<Whitened>)> {
    validate::finite_vectors("fixes.position_ecef", &[f.position_ecef])
        .map_err(|_| origin.invalid("position_ecef", "position is not finite"))?;
    let velocity = match f.velocity_ecef {
        Some(v) => {
            validate::finite_vectors("fixes.velocity_ecef", &[v])
                .map_err(|_| origin.invalid("velocity_ecef", "velocity is not finite"))?;
            Some(if f.velocity_horizontal_only {
                horizontal_whitening(
                    origin,
                    "velocity_covariance",
                    &f.velocity_covariance,
                    &f.position_ecef,
                    floor.velocity_m_s,
                )?
            } else {
                whitening(
                    origin,
                    "velocity_covariance",
                    &f.velocity_covariance,
                    floor.velocity_m_s,
                )?
            })
        }
        None => None,
    };
    Ok((
        whitening(
            origin,
            "position_covariance",
            &f.position_covariance,
            floor.position_m,
        )?,
        velocity,
    ))
}

/// The whitened blocks of a fix (from `origin`), taken `interval_s` after the previous
/// fix the filter used (None for the first): its position covariance
/// inflated for the errors the two share
/// ([`FilterTuning::fix_correlation_time_s`]), then [`whiten_fix`].
pub(crate) fn prepare_fix(
    origin: FixOrigin,
    f: &PositionFix,
    interval_s: Option<f64>,
    tuning: &FilterTuning,
) -> Result<(Whitened, Option<Whitened>)> {
    let inflation = correlated_sample_inflation(tuning.fix_correlation_time_s, interval_s);
    let fix = PositionFix {
        position_covariance: f.position_covariance * inflation,
        ..*f
    };
    whiten_fix(origin, &fix, &tuning.floor)
}

/// Applies one fix with its whitened blocks: the position, then the
/// velocity when the fix has one.
pub(crate) fn apply_fix<const N: usize>(
    s: &mut FilterState<N>,
    (wp, wv): &(Whitened, Option<Whitened>),
    f: &PositionFix,
) -> Result<()> {
    let has_velocity = wv.is_some();
    update_block(
        s,
        f.time_s,
        MeasurementKind::Position,
        &f.position_ecef,
        wp,
        has_velocity,
    )?;
    if let (Some(v), Some(wv)) = (f.velocity_ecef, wv) {
        update_block(s, f.time_s, MeasurementKind::Velocity, &v, wv, true)?;
    }
    Ok(())
}

impl Aiding for PositionFix {
    const ARGUMENT: &'static str = "fixes";
    /// Each fix's whitened position and velocity blocks.
    type Prepared = Vec<(Whitened, Option<Whitened>)>;

    fn prepare(
        fixes: &[Self],
        initial: &InitialState,
        tuning: &FilterTuning,
    ) -> Result<(Self::Prepared, InitialState, FilterTuning)> {
        tuning.validate()?;
        let whitened = fixes
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let interval_s = i.checked_sub(1).map(|j| f.time_s - fixes[j].time_s);
                prepare_fix(FixOrigin::Batch(i), f, interval_s, tuning)
            })
            .collect::<Result<_>>()?;
        // The clock is not observed: held at zero, without process noise.
        let mut tuning = *tuning;
        tuning.process_noise.clock_phase_psd = 0.0;
        tuning.process_noise.clock_frequency_psd = 0.0;
        let mut initial = *initial;
        initial.clock_offset_m.get_or_insert(0.0);
        initial.clock_drift_m_s.get_or_insert(0.0);
        Ok((whitened, initial, tuning))
    }

    fn update<const N: usize>(
        s: &mut FilterState<N>,
        whitened: &Self::Prepared,
        i: usize,
        f: &Self,
    ) -> Result<()> {
        apply_fix(s, &whitened[i], f)
    }
}
