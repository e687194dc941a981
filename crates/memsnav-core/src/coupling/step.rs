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

use super::engine::{FilterState, InitialState};
use super::loose::{self, PositionFix};
use super::run::Aiding;
use super::tight;
use super::tuning::FilterTuning;
use crate::gnss::GnssEpoch;
use crate::ins::{ImuIncrement, ImuSample};
use crate::limits::{MAX_IMU_PERIOD_S, MAX_SENSOR_MAGNITUDE};
use crate::{validate, Error, Result};

impl<const N: usize> FilterState<N> {
    /// The filter for aiding of kind `E` ([`GnssEpoch`] or
    /// [`PositionFix`]) started at `time_s` with the raw IMU sample there:
    /// the state and tuning a batch run over such epochs starts from
    /// (position fixes hold the unobserved clock, for instance).
    pub fn start<E: Aiding>(
        initial: &InitialState,
        tuning: &FilterTuning,
        time_s: f64,
        raw: &ImuSample,
    ) -> Result<Self> {
        validate::finite_scalars("time", &[time_s])?;
        check_sample(raw)?;
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
    pub fn update_gnss(&mut self, epoch: &GnssEpoch) -> Result<()> {
        self.check_epoch_time("gnss", epoch.time_s)?;
        tight::update_epoch(self, epoch, self.tuning.use_pseudorange_rate)
    }

    /// Applies one position (and velocity) fix at the filter's time, as
    /// the loosely coupled run does.
    pub fn update_fix(&mut self, fix: &PositionFix) -> Result<()> {
        self.check_epoch_time("fix", fix.time_s)?;
        let interval_s = self.previous_epoch_s.map(|before| fix.time_s - before);
        let whitened = loose::prepare_fix(0, fix, interval_s, &self.tuning)?;
        loose::apply_fix(self, &whitened, fix)?;
        self.previous_epoch_s = Some(fix.time_s);
        Ok(())
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
