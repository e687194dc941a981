//! The coupled filter one call at a time, for a real-time loop or a custom
//! aid: start, predict to the next IMU sample (rates or increments), then
//! any updates at that time. The batch run ([`super::run`]) is this same
//! sequence over whole series: both call [`FilterState::step_to`] and the
//! same update functions, so the same calls give the same numbers, bit
//! for bit.
//!
//! Updates apply at the filter's time (that of the last predict); a GNSS
//! epoch or fix stamped elsewhere (beyond `time_tolerance_s`) is refused,
//! not silently applied at the wrong time.
//!
//! Every update is a transaction: its arguments are checked before the
//! state is touched (stds within [`validate::MIN_AID_STD`] to
//! [`validate::MAX_AID_STD`], lever arms within
//! [`validate::MAX_LEVER_ARM_M`], a fix's position near the Earth's surface
//! ([`plausible::check_receiver_position`])), and an update that fails on
//! the way (a covariance no longer positive definite) leaves the filter
//! exactly as it was before the call, its records included
//! ([`FilterState::transaction`]).

use super::engine::{FilterState, InitialState};
use super::loose::{self, PositionFix};
use super::records::RunRecords;
use super::run::Aiding;
use super::tight;
use super::tuning::FilterTuning;
use crate::gnss::plausible;
use crate::gnss::GnssEpoch;
use crate::ins::{ImuIncrement, ImuSample};
use crate::limits::{MAX_IMU_PERIOD_S, MAX_SENSOR_MAGNITUDE};
use crate::{validate, Error, Result};
use nalgebra::Vector3;

impl<const N: usize> FilterState<N> {
    /// The filter for aiding of kind `E` ([`GnssEpoch`] or
    /// [`PositionFix`]) started at `time_s` with the raw IMU sample there:
    /// the state and tuning a batch run over such epochs starts from
    /// (position fixes hold the unobserved clock, for instance). The start
    /// must be one a receiver can have ([`InitialState::check_receiver`]).
    pub fn start<E: Aiding>(
        initial: &InitialState,
        tuning: &FilterTuning,
        time_s: f64,
        raw: &ImuSample,
    ) -> Result<Self> {
        validate::finite_scalars("time", &[time_s])?;
        check_sample(raw)?;
        initial.check_receiver()?;
        let (_, initial, tuning) = E::prepare(&[], initial, tuning)?;
        let mut state = Self::new(&initial, &tuning)?;
        state.begin_at(time_s, raw);
        Ok(state)
    }

    /// The filter's time, s: that of the last predict.
    pub fn time_s(&self) -> f64 {
        self.time_s
    }

    /// Steps the INS and the covariance to `time_s` with the raw sample
    /// there (the mechanization integrates between the previous sample
    /// and this one, as the batch run does).
    pub fn predict(&mut self, time_s: f64, raw: &ImuSample) -> Result<()> {
        self.check_step(time_s)?;
        check_sample(raw)?;
        self.step_to(time_s, raw)
    }

    /// Steps the INS and the covariance to `time_s` with the raw velocity
    /// and angle increments of the interval since the filter's time, with
    /// coning and sculling ([`crate::ins::step_increments`]).
    pub fn predict_increments(&mut self, time_s: f64, raw: &ImuIncrement) -> Result<()> {
        self.check_step(time_s)?;
        let dt = time_s - self.time_s;
        for (name, v) in [
            ("delta_v", raw.delta_velocity_b),
            ("delta_theta", raw.delta_angle_b),
        ] {
            validate::bounded_vectors(name, &[v / dt], MAX_SENSOR_MAGNITUDE)?;
        }
        self.step_increments_to(time_s, raw, dt)
    }

    /// Applies one GNSS epoch (pseudoranges, then rates when the tuning
    /// uses them) at the filter's time, as the tightly coupled run does.
    /// Returns whether it was applied whole: see `Self::all_accepted_since`.
    pub fn update_gnss(&mut self, epoch: &GnssEpoch) -> Result<bool> {
        self.check_epoch_time("gnss", epoch.time_s)?;
        self.transaction(|s| {
            let first = s.batches.len();
            tight::update_epoch(s, epoch, s.tuning.use_pseudorange_rate)?;
            Ok(s.all_accepted_since(first))
        })
    }

    /// Applies one position (and velocity) fix at the filter's time, as
    /// the loosely coupled run does. Returns whether it was applied whole:
    /// see `Self::all_accepted_since`.
    /// A fix's position must be one a receiver can have (near the
    /// Earth's surface) and its velocity one a receiver can move at:
    /// three fixes far from the solution would otherwise reset the filter
    /// to them.
    pub fn update_fix(&mut self, fix: &PositionFix) -> Result<bool> {
        self.check_epoch_time("fix", fix.time_s)?;
        validate::finite_vectors("position_ecef", &[fix.position_ecef])?;
        plausible::check_receiver_position(&fix.position_ecef)
            .map_err(|reason| Error::invalid("position_ecef", reason))?;
        if let Some(v) = fix.velocity_ecef {
            validate::finite_vectors("velocity_ecef", &[v])?;
            validate::at_most("velocity_ecef", v.norm(), plausible::MAX_SPEED_M_S)?;
        }
        let interval_s = self.previous_epoch_s.map(|before| fix.time_s - before);
        let whitened = loose::prepare_fix(loose::FixOrigin::Single, fix, interval_s, &self.tuning)?;
        self.transaction(|s| {
            let first = s.batches.len();
            loose::apply_fix(s, &whitened, fix)?;
            s.previous_epoch_s = Some(fix.time_s);
            Ok(s.all_accepted_since(first))
        })
    }

    /// Zero-velocity update at the filter's time, std `std_m_s` per axis
    /// ([`Self::zero_velocity_update`]), as a transaction.
    pub fn update_zupt(&mut self, std_m_s: f64) -> Result<bool> {
        self.transaction(|s| s.zero_velocity_update(s.time_s, std_m_s))
    }

    /// Zero-angular-rate update at the filter's time
    /// ([`Self::zero_rate_update`]), as a transaction.
    pub fn update_zaru(
        &mut self,
        mean_raw_rate_b: &Vector3<f64>,
        std_rad_s: &Vector3<f64>,
    ) -> Result<bool> {
        self.transaction(|s| s.zero_rate_update(s.time_s, mean_raw_rate_b, std_rad_s))
    }

    /// Non-holonomic constraint at the filter's time
    /// ([`Self::non_holonomic_update`]), as a transaction.
    pub fn update_non_holonomic(
        &mut self,
        reference_b_m: &Vector3<f64>,
        std_m_s: f64,
    ) -> Result<bool> {
        self.transaction(|s| s.non_holonomic_update(s.time_s, reference_b_m, std_m_s))
    }

    /// Odometer speed at the filter's time ([`Self::speed_update`]), as a
    /// transaction.
    pub fn update_speed(
        &mut self,
        speed_m_s: f64,
        reference_b_m: &Vector3<f64>,
        std_m_s: f64,
    ) -> Result<bool> {
        self.transaction(|s| s.speed_update(s.time_s, speed_m_s, reference_b_m, std_m_s))
    }

    /// Height at the filter's time ([`Self::height_update`]), as a
    /// transaction.
    pub fn update_height(&mut self, height_m: f64, std_m: f64) -> Result<bool> {
        self.transaction(|s| s.height_update(s.time_s, height_m, std_m))
    }

    /// Heading at the filter's time ([`Self::heading_update`]), as a
    /// transaction.
    pub fn update_heading(&mut self, yaw_rad: f64, std_rad: f64) -> Result<bool> {
        self.transaction(|s| s.heading_update(s.time_s, yaw_rad, std_rad))
    }

    /// Runs `update`; when it fails, puts the filter back exactly as it
    /// was: state, covariance, counters and records (those the failed
    /// update added are dropped). The snapshot leaves the records out, so
    /// its cost does not grow with them.
    pub fn transaction<T>(&mut self, update: impl FnOnce(&mut Self) -> Result<T>) -> Result<T> {
        let records = self.take_records();
        let lengths = (
            records.measurements.len(),
            records.batches.len(),
            records.resets.len(),
        );
        let snapshot = self.clone();
        self.put_records(records);
        let result = update(self);
        if result.is_err() {
            let mut records = self.take_records();
            records.measurements.truncate(lengths.0);
            records.batches.truncate(lengths.1);
            records.resets.truncate(lengths.2);
            *self = snapshot;
            self.put_records(records);
        }
        result
    }

    fn put_records(&mut self, records: RunRecords) {
        self.records = records.measurements;
        self.batches = records.batches;
        self.resets = records.resets;
    }

    /// Whether an update made of several batches (a fix's position and
    /// velocity blocks; an epoch's pseudoranges, rates and carrier phases)
    /// was applied whole: it tested at least one batch since batch record
    /// `first` and every one passed its gate (a batch that passed after
    /// excluding faulty satellites counts as passed). The one-batch aids
    /// return their batch's verdict the same way; the records say which
    /// batch of a partly applied update failed.
    fn all_accepted_since(&self, first: usize) -> bool {
        let tested = &self.batches[first..];
        !tested.is_empty() && tested.iter().all(|b| b.accepted)
    }

    fn check_step(&self, time_s: f64) -> Result<()> {
        validate::finite_scalars("time", &[time_s])?;
        let dt = time_s - self.time_s;
        if dt <= 0.0 {
            return Err(Error::invalid(
                "time",
                format!(
                    "{time_s} s does not follow the filter's time {} s: time must increase",
                    self.time_s
                ),
            ));
        }
        if dt > MAX_IMU_PERIOD_S {
            return Err(Error::invalid(
                "time",
                format!(
                    "a step of {dt} s from {} s is longer than {MAX_IMU_PERIOD_S} s: predict at \
                     every IMU sample (times in seconds expected)",
                    self.time_s
                ),
            ));
        }
        Ok(())
    }

    fn check_epoch_time(&self, argument: &str, epoch_time_s: f64) -> Result<()> {
        let tolerance = self.tuning.time_tolerance_s;
        if (epoch_time_s - self.time_s).abs() > tolerance || !epoch_time_s.is_finite() {
            return Err(Error::invalid(
                argument,
                format!(
                    "the epoch is at {epoch_time_s} s but the filter at {} s (tolerance {tolerance} \
                     s): predict to the epoch's time first",
                    self.time_s
                ),
            ));
        }
        Ok(())
    }
}

fn check_sample(raw: &ImuSample) -> Result<()> {
    validate::bounded_vectors(
        "specific_force",
        &[raw.specific_force_b],
        MAX_SENSOR_MAGNITUDE,
    )?;
    validate::bounded_vectors("angular_rate", &[raw.angular_rate_b], MAX_SENSOR_MAGNITUDE)
}
