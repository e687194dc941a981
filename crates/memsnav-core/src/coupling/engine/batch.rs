//! An epoch's measurements of one kind as one batch: staged, floored,
//! tested together, thinned by fault exclusion, and recorded; a clock jump
//! moved into the clock; and the resets that keep failing measurements
//! from locking the filter out (see [`crate::coupling::Recovery`]).
//!
//! The test is the chi-square test of the batch innovation, νᵀ S⁻¹ ν against
//! the `gate_probability` quantile of as many degrees of freedom
//! (Bar-Shalom et al. 2001 §5.4; Groves §17.3.1 for its use on GNSS/INS
//! innovations). Fault exclusion drops the measurement with the largest
//! normalised innovation and tests the rest (Groves §17.4.2, the
//! innovation-based form of RAIM's fault detection and exclusion), at most
//! `max_excluded_share` of the batch.

use nalgebra::{Matrix3, Vector3};

use super::FilterState;
use crate::coupling::records::{
    BatchRecord, MeasurementKind, MeasurementRecord, MeasurementStatus, ResetKind, ResetRecord,
};
use crate::filter::chi_square::chi_square_quantile;
use crate::filter::state::{CLOCK_DRIFT, CLOCK_OFFSET, POSITION, VELOCITY};
use crate::filter::{ScalarMeasurement, ScalarOutcome, SparseRow};
use crate::Result;

/// The batch being assembled: parallel columns, kept between epochs so a
/// batch allocates nothing once the buffers have grown to an epoch's size.
#[derive(Debug, Clone, Default)]
pub(crate) struct Batch {
    measurements: Vec<ScalarMeasurement>,
    ids: Vec<u16>,
    active: Vec<bool>,
    outcomes: Vec<ScalarOutcome>,
    /// Innovation and its variance against the prior, per measurement.
    prior: Vec<(f64, f64)>,
    scratch: Vec<f64>,
    /// The largest nonlinearity of its measurements (None: none noted).
    nonlinearity: Option<f64>,
}

impl Batch {
    fn len(&self) -> usize {
        self.measurements.len()
    }

    fn clear(&mut self) {
        self.measurements.clear();
        self.ids.clear();
        self.active.clear();
        self.outcomes.clear();
        self.prior.clear();
        self.nonlinearity = None;
    }

    /// Notes the nonlinearity of a staged measurement (see
    /// [`BatchRecord::nonlinearity`]); the batch records the largest.
    pub(crate) fn note_nonlinearity(&mut self, value: f64) {
        self.nonlinearity = Some(self.nonlinearity.map_or(value, |v| v.max(value)));
    }

    fn active_count(&self) -> usize {
        self.active.iter().filter(|a| **a).count()
    }
}

/// The state variable a common part of all innovations of a batch belongs
/// to: a receiver clock (drift) jump.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum CommonMode {
    ClockOffset,
    ClockDrift,
}

impl CommonMode {
    fn state(self) -> usize {
        match self {
            CommonMode::ClockOffset => CLOCK_OFFSET,
            CommonMode::ClockDrift => CLOCK_DRIFT,
        }
    }
}

/// How a batch is tested.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BatchRules {
    /// Drop the worst measurements when the batch fails.
    pub(crate) exclusion: bool,
    /// The clock state a common part of the innovations may jump into.
    pub(crate) common_mode: Option<CommonMode>,
}

fn kind_index(kind: MeasurementKind) -> usize {
    MeasurementKind::ALL
        .iter()
        .position(|k| *k == kind)
        .expect("every kind is in ALL")
}

impl<const N: usize> FilterState<N> {
    /// The smallest std the filter believes for `kind` (fixes are floored
    /// before whitening, see `loose`; aids carry their own std).
    fn floor(&self, kind: MeasurementKind) -> f64 {
        let f = &self.tuning.floor;
        match kind {
            MeasurementKind::Pseudorange => f.pseudorange_m,
            MeasurementKind::PseudorangeRate => f.pseudorange_rate_m_s,
            MeasurementKind::CarrierPhase => f.carrier_phase_m,
            _ => 0.0,
        }
    }

    /// Adds a measurement y = h·x + v with std `std` (floored for its kind)
    /// to the batch; one with a non-finite value or std is recorded as
    /// invalid instead.
    pub(crate) fn stage(
        &mut self,
        time_s: f64,
        kind: MeasurementKind,
        id: u16,
        h: SparseRow,
        y: f64,
        std: f64,
    ) {
        if !(y.is_finite() && std.is_finite() && std > 0.0) {
            self.reject_invalid(time_s, kind, id);
            return;
        }
        let std = std.max(self.floor(kind));
        let b = &mut self.staged;
        b.measurements.push(ScalarMeasurement {
            h,
            y,
            variance: std * std,
        });
        b.ids.push(id);
        b.active.push(true);
        b.outcomes.push(ScalarOutcome {
            innovation: f64::NAN,
            innovation_variance: f64::NAN,
            nis: f64::NAN,
            accepted: false,
        });
    }

    /// Records a measurement rejected before it reached the filter.
    pub(crate) fn reject_invalid(&mut self, time_s: f64, kind: MeasurementKind, id: u16) {
        self.records.push(MeasurementRecord {
            time_s,
            id,
            kind,
            innovation: f64::NAN,
            innovation_std: f64::NAN,
            nis: f64::NAN,
            status: MeasurementStatus::RejectedInvalid,
        });
    }

    /// Consecutive epochs whose `kind` batch failed, this one included.
    pub(crate) fn failed_epochs(&self, kind: MeasurementKind) -> usize {
        self.failed_epochs[kind_index(kind)]
    }

    /// Whether the batch of `kind` has failed often enough for a reset.
    pub(crate) fn reset_due(&self, kind: MeasurementKind) -> bool {
        self.failed_epochs(kind) >= self.tuning.recovery.reset_after_failed_epochs
    }

    /// The chi-square threshold for a batch of `dof` measurements.
    fn threshold(&self, dof: usize) -> f64 {
        if self.tuning.gate_probability >= 1.0 {
            f64::INFINITY
        } else {
            chi_square_quantile(dof as f64, self.tuning.gate_probability)
        }
    }

    /// Tests the staged batch against the prior: as a whole, then (when it
    /// fails) with a clock jump moved into the clock, then without its worst
    /// measurements. An accepted batch is applied and fed back. Every
    /// measurement and the test are recorded, the batch is emptied, and the
    /// count of consecutive failed epochs of `kind` is updated. Returns
    /// whether the batch was applied.
    pub(crate) fn apply_staged(
        &mut self,
        time_s: f64,
        kind: MeasurementKind,
        rules: BatchRules,
    ) -> Result<bool> {
        if self.staged.len() == 0 {
            return Ok(false);
        }
        // Innovations against the prior, for the records and the exclusion order.
        for i in 0..self.staged.len() {
            let p = self.kf.innovation(&self.staged.measurements[i]);
            self.staged.prior.push(p);
        }
        let mut outcome = self.test_active();
        if !outcome.0 {
            if let Some(mode) = rules.common_mode {
                if self.absorb_common_mode(time_s, mode) {
                    outcome = (true, self.batches_nis_of_last_test());
                }
            }
        }
        let mut excluded = 0;
        let max_excluded = if rules.exclusion {
            (self.staged.len() as f64 * self.tuning.recovery.max_excluded_share).floor() as usize
        } else {
            0
        };
        while !outcome.0 && excluded < max_excluded {
            let b = &self.staged;
            let z = |i: usize| b.prior[i].0.abs() / b.prior[i].1.sqrt();
            let worst = (0..b.len())
                .filter(|&i| b.active[i])
                .max_by(|&x, &y| z(x).total_cmp(&z(y)))
                .expect("a failed batch has an active measurement");
            self.staged.active[worst] = false;
            excluded += 1;
            outcome = self.test_active();
        }
        let (accepted, nis) = outcome;
        let dof = self.staged.active_count();
        self.batches.push(BatchRecord {
            time_s,
            kind,
            nis,
            dof,
            threshold: self.threshold(dof),
            excluded,
            accepted,
            nonlinearity: self.staged.nonlinearity.unwrap_or(f64::NAN),
        });
        let b = &self.staged;
        for i in 0..b.len() {
            let (nu, var) = b.prior[i];
            let status = match (accepted, b.active[i]) {
                (true, true) => MeasurementStatus::Accepted,
                (true, false) => MeasurementStatus::Excluded,
                (false, _) => MeasurementStatus::RejectedByGate,
            };
            self.records.push(MeasurementRecord {
                time_s,
                id: b.ids[i],
                kind,
                // ν = y − h x is prediction minus measurement: the record
                // keeps measurement minus prediction.
                innovation: -nu,
                innovation_std: var.max(0.0).sqrt(),
                nis: nu * nu / var,
                status,
            });
        }
        self.staged.clear();
        let failed = &mut self.failed_epochs[kind_index(kind)];
        *failed = if accepted { 0 } else { *failed + 1 };
        if accepted {
            self.last_accepted_s[kind_index(kind)] = time_s;
            self.resets_in_a_row[kind_index(kind)] = 0;
            self.feedback(time_s)?;
        }
        Ok(accepted)
    }

    /// Tests the active staged measurements; applies them when they pass.
    /// Returns (accepted, batch NIS).
    fn test_active(&mut self) -> (bool, f64) {
        let b = &mut self.staged;
        let dof = b.active_count();
        let threshold = if self.tuning.gate_probability >= 1.0 {
            f64::INFINITY
        } else {
            chi_square_quantile(dof as f64, self.tuning.gate_probability)
        };
        let out = self
            .kf
            .update_batch(&b.measurements, &b.active, threshold, &mut b.outcomes);
        (out.accepted, out.nis)
    }

    /// The NIS of the active measurements' last test (their outcomes).
    fn batches_nis_of_last_test(&self) -> f64 {
        let b = &self.staged;
        (0..b.len())
            .filter(|&i| b.active[i])
            .map(|i| b.outcomes[i].nis)
            .sum()
    }

    /// A receiver clock (drift) jump shows as one common part in every
    /// innovation of a batch. When the median innovation exceeds
    /// `clock_jump_sigma` times its predicted std, it is moved into the
    /// clock (the clock's variance grows by one measurement variance, the
    /// jump being estimated from this epoch) and the batch tested again;
    /// kept (and recorded as a reset) only when the batch then passes.
    fn absorb_common_mode(&mut self, time_s: f64, mode: CommonMode) -> bool {
        let b = &mut self.staged;
        if b.len() < 2 {
            return false;
        }
        b.scratch.clear();
        b.scratch.extend(b.prior.iter().map(|p| p.0));
        let common = median(&mut b.scratch);
        b.scratch.clear();
        b.scratch.extend(b.measurements.iter().map(|m| m.variance));
        let r = median(&mut b.scratch);
        let i = mode.state();
        let sigma = (self.kf.p[(i, i)] + r).sqrt();
        // NaN (no clock variance yet) is no jump either.
        if common
            .abs()
            .partial_cmp(&(self.tuning.recovery.clock_jump_sigma * sigma))
            != Some(std::cmp::Ordering::Greater)
        {
            return false;
        }
        // Try the jump: the clock's variance grows and the innovations lose
        // their common part; undone (and the undoing recorded) if the batch
        // still fails.
        self.kf.add_variance(i, r);
        for m in &mut self.staged.measurements {
            m.y -= common;
        }
        let (accepted, _) = self.test_active();
        if !accepted {
            self.kf.add_variance(i, -r);
            for m in &mut self.staged.measurements {
                m.y += common;
            }
            return false;
        }
        // ν = prediction − measurement: the clock moves by −common.
        let kind = match mode {
            CommonMode::ClockOffset => {
                self.clock_offset_m -= common;
                ResetKind::ClockJump
            }
            CommonMode::ClockDrift => {
                self.clock_drift_m_s -= common;
                ResetKind::ClockDriftJump
            }
        };
        self.resets.push(ResetRecord {
            time_s,
            kind,
            change: -common,
            failed_epochs: 0,
        });
        true
    }

    /// Marks the measurements of the last, failed batch as used for a reset.
    fn mark_used_for_reset(&mut self, time_s: f64, kind: MeasurementKind) {
        for r in self.records.iter_mut().rev() {
            if r.time_s != time_s || r.kind != kind {
                break;
            }
            if r.status == MeasurementStatus::RejectedByGate {
                r.status = MeasurementStatus::UsedForReset;
            }
        }
    }

    /// The fix a reset replaces the position (`kind` Position) or the
    /// velocity (any other kind) by, recorded for the smoother as the
    /// measurement it also is ([`crate::filter::ErrorStateKf::record_for_smoother_only`]):
    /// its components whitened by the Cholesky factor of `covariance`, the
    /// rows of a loosely coupled fix of the antenna.
    fn record_fix_for_smoother(
        &mut self,
        kind: MeasurementKind,
        measured: &Vector3<f64>,
        covariance: &Matrix3<f64>,
    ) {
        let Some(l_inv) = covariance.cholesky().and_then(|c| c.l().try_inverse()) else {
            return;
        };
        let antenna = self.antenna();
        let position = kind == MeasurementKind::Position;
        let predicted = if position {
            antenna.position_ecef
        } else {
            antenna.fix_velocity_ecef
        };
        let y = l_inv * (predicted - measured);
        let fix: [ScalarMeasurement; 3] = std::array::from_fn(|i| {
            let w = l_inv.row(i).transpose();
            ScalarMeasurement {
                h: if position {
                    antenna.position_row(&w)
                } else {
                    antenna.fix_velocity_row(&w)
                },
                y: y[i],
                variance: 1.0,
            }
        });
        self.kf.record_for_smoother_only(&fix);
    }

    /// Resets the IMU position to a fix of the antenna position
    /// `position_ecef` with covariance `covariance` (the lever arm taken
    /// with the current attitude), after `kind` kept failing; recorded.
    ///
    /// A position that was this far off means the velocity may be off by
    /// as much per second of the time the position went unchecked: without
    /// a velocity to reset to (`velocity_reset_too` false), the velocity
    /// becomes independent of the rest with that variance (at least its
    /// own, at most (1000 m/s)²), so the next fixes can correct it.
    pub(crate) fn reset_position(
        &mut self,
        time_s: f64,
        kind: MeasurementKind,
        antenna_position_ecef: &Vector3<f64>,
        covariance: &Matrix3<f64>,
        velocity_reset_too: bool,
    ) -> Result<()> {
        self.record_fix_for_smoother(MeasurementKind::Position, antenna_position_ecef, covariance);
        let new = antenna_position_ecef - self.nav.c_b_e * self.installation.lever_arm_b_m;
        let change = (new - self.nav.position_ecef).norm();
        self.nav.position_ecef = new;
        self.kf.reset_block::<3>(POSITION, covariance);
        if !velocity_reset_too {
            let unchecked_s = (time_s - self.last_accepted_s[kind_index(kind)]).max(1.0);
            let std = (change / unchecked_s).min(1000.0);
            let own = self.kf.p.fixed_view::<3, 3>(VELOCITY, VELOCITY).max();
            let variance = (std * std).max(own);
            self.kf
                .reset_block::<3>(VELOCITY, &(Matrix3::identity() * variance));
        }
        self.finish_reset(time_s, kind, ResetKind::PositionToFix, change)
    }

    /// Resets the IMU velocity to a fix of the antenna velocity (lever-arm
    /// terms with the current attitude and rate); recorded.
    pub(crate) fn reset_velocity(
        &mut self,
        time_s: f64,
        kind: MeasurementKind,
        antenna_velocity_ecef: &Vector3<f64>,
        covariance: &Matrix3<f64>,
    ) -> Result<()> {
        let imu_velocity_ecef = antenna_velocity_ecef - self.lever_arm_velocity();
        self.reset_imu_velocity(time_s, kind, &imu_velocity_ecef, covariance)
    }

    /// Resets the IMU velocity to `velocity_ecef` with `covariance` after
    /// `kind` kept failing (a velocity fix, or zero at a standstill);
    /// recorded.
    pub(crate) fn reset_imu_velocity(
        &mut self,
        time_s: f64,
        kind: MeasurementKind,
        velocity_ecef: &Vector3<f64>,
        covariance: &Matrix3<f64>,
    ) -> Result<()> {
        let change = (velocity_ecef - self.nav.velocity_ecef).norm();
        self.nav.velocity_ecef = *velocity_ecef;
        self.kf.reset_block::<3>(VELOCITY, covariance);
        let reset = if kind == MeasurementKind::ZeroVelocity {
            ResetKind::VelocityToZero
        } else {
            ResetKind::VelocityToFix
        };
        self.finish_reset(time_s, kind, reset, change)
    }

    /// Resets the receiver clock offset and drift (tight coupling, with a
    /// position reset from a fix); recorded with the position reset.
    pub(crate) fn reset_clock(
        &mut self,
        offset_m: f64,
        offset_variance: f64,
        drift_m_s: Option<(f64, f64)>,
    ) {
        self.clock_offset_m = offset_m;
        self.kf
            .reset_block::<1>(CLOCK_OFFSET, &nalgebra::Matrix1::new(offset_variance));
        if let Some((d, var)) = drift_m_s {
            self.clock_drift_m_s = d;
            self.kf
                .reset_block::<1>(CLOCK_DRIFT, &nalgebra::Matrix1::new(var));
        }
        self.clock_known = (true, self.clock_known.1 || drift_m_s.is_some());
    }

    /// Multiplies the position, velocity and clock variances by `factor`
    /// (too few satellites for a fix to reset to); recorded.
    pub(crate) fn inflate(
        &mut self,
        time_s: f64,
        kind: MeasurementKind,
        factor: f64,
    ) -> Result<()> {
        let states: [usize; 8] = [
            POSITION,
            POSITION + 1,
            POSITION + 2,
            VELOCITY,
            VELOCITY + 1,
            VELOCITY + 2,
            CLOCK_OFFSET,
            CLOCK_DRIFT,
        ];
        self.kf.inflate(&states, factor);
        self.finish_reset(time_s, kind, ResetKind::Inflation, factor)?;
        self.recovered(time_s, kind)
    }

    fn finish_reset(
        &mut self,
        time_s: f64,
        kind: MeasurementKind,
        reset: ResetKind,
        change: f64,
    ) -> Result<()> {
        self.mark_used_for_reset(time_s, kind);
        self.resets.push(ResetRecord {
            time_s,
            kind: reset,
            change,
            failed_epochs: self.failed_epochs(kind),
        });
        self.kf.check_health(time_s)
    }

    /// After the resets a failing kind led to: its measurements are
    /// trusted again (the count of failed epochs restarts). A second reset
    /// of the kind with no accepted batch since the first says that
    /// replacing position (velocity, clock) is not enough: the filter's
    /// attitude and sensor errors are further off than its covariance
    /// admits, and it would reset at every few epochs for good (a tactical
    /// tuning on a consumer IMU did, 700 times on drive_0708). The whole
    /// covariance then fades by `recovery.fading_factor`, at each such
    /// reset, so that the fixes can correct the rest.
    pub(crate) fn recovered(&mut self, time_s: f64, kind: MeasurementKind) -> Result<()> {
        self.failed_epochs[kind_index(kind)] = 0;
        self.last_accepted_s[kind_index(kind)] = time_s;
        let in_a_row = &mut self.resets_in_a_row[kind_index(kind)];
        *in_a_row += 1;
        let factor = self.tuning.recovery.fading_factor;
        if *in_a_row < 2 || factor <= 1.0 {
            return Ok(());
        }
        self.kf.fade(factor);
        self.resets.push(ResetRecord {
            time_s,
            kind: ResetKind::Fading,
            change: factor,
            failed_epochs: 0,
        });
        self.kf.check_health(time_s)
    }

    /// The batch NIS of the last failed test of `kind` over its threshold
    /// (how far the filter is from accepting it).
    pub(crate) fn last_failure_ratio(&self, kind: MeasurementKind) -> f64 {
        self.batches
            .iter()
            .rev()
            .find(|b| b.kind == kind)
            .map_or(1.0, |b| b.nis / b.threshold)
    }
}

/// The median of `values` (reordered); 0 when empty.
pub(crate) fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}
