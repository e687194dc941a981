//! Tightly and loosely coupled GNSS/INS closed-loop error-state filters in
//! ECEF (method §5; Groves ch. 14).
//!
//! ## How they work
//!
//! - The INS ([`crate::ins::step`]) runs at the IMU rate on samples
//!   corrected by the current bias (and scale-factor) estimates; the error
//!   covariance is propagated alongside ([`crate::filter`]).
//! - At each GNSS epoch every measurement is a gated scalar Joseph update:
//!   pseudoranges and pseudorange rates per satellite through
//!   [`crate::gnss::predicted_range`] (Sagnac, light time) on GNSS epochs
//!   (`tight`); whitened position/velocity components on position fixes
//!   (`loose`). One run serves both ([`solution`], [`run`]: the aiding kind
//!   is the epochs' type, [`Aiding`]). Then the estimated errors are fed back into the
//!   INS, the sensor estimates and the clock, and the error state is zeroed
//!   (closed loop).
//! - GNSS epoch times must increase and lie within the IMU span; an epoch
//!   within `time_tolerance_s` of an IMU sample is applied there, otherwise
//!   the INS is stepped to the epoch's own time with an interpolated sample.
//! - The same filter runs one call at a time (`FilterState::start`,
//!   `predict`, `update_*`; `step.rs`): the batch run is that sequence.
//! - Rejections are never silent: every scalar measurement gets a
//!   [`MeasurementRecord`] (innovation, its std, NIS, status).
//!
//! ## Initialisation
//!
//! [`InitialState`] gives position, velocity, attitude, biases and
//! optionally the clock (unknown clock: the median pseudorange residual of
//! the first epoch). [`initial_state_from_fix`] builds one from the first
//! GNSS epoch's least-squares fix and a given attitude, or a coarse one:
//! roll and pitch from the mean specific force of the first second
//! (levelling), heading from the fix velocity. P₀ comes from
//! [`InitialUncertainty`] (documented defaults there).
//!
//! ## Uncertainty
//!
//! [`Solution`] keeps the diagonal of P and its attitude, velocity and
//! position blocks (ECEF axes) at every sample; `Solution::position_std_ned`
//! and its siblings rotate the blocks into local NED ([`covariance_ned`]).
//!
//! ## Tuning and unmodelled errors
//!
//! [`FilterTuning`] holds noise densities, bias processes and initial
//! uncertainties; `FilterTuning::from_imu_spec` derives them from an IMU's
//! specification and everything stays overridable. Errors the state does
//! not contain — raw MEMS scale factors (unless the 23-state filter is
//! used), misalignments, nonlinearity, g-sensitivity — are absorbed as
//! uncertainty ([`UnmodelledErrors`], `FilterTuning::absorb_unmodelled`):
//! their part driven by the specific force at rest widens the initial bias
//! uncertainty, their part driven by the motion is process noise shaped by
//! the sensed specific force and rate at every step
//! ([`crate::filter::input_noise`]). Calibration and inversion (method
//! §3-4) remove these errors instead.
//!
//! ## Integrity
//!
//! Every run is judged from its own records ([`integrity`]): GNSS batches
//! mostly gated, innovations far outside their chi-square band, or a
//! position too uncertain across the lines of sight for the first-order
//! pseudorange model each raise an [`IntegrityAlert`], a warning, and mark
//! the solution diverged (docs/explanation/few-satellites.md).

mod aids;
mod antenna;
mod carrier;
mod diagnostics;
mod engine;
pub mod factory;
mod init;
mod installation;
pub mod integrity;
mod loose;
mod motion_history;
mod ned;
mod records;
mod run;
mod step;
mod tight;
mod tuning;

pub use crate::filter::input_noise::UnmodelledErrors;
pub(crate) use diagnostics::diagnose;
pub use diagnostics::imu_unit_warnings;
pub(crate) use engine::SampleHook;
pub use engine::{AidingEpoch, FilterState, InitialState, SampleAid, Solution};
pub use init::{coarse_attitude, initial_state_from_fix, initial_state_from_position_fix, level};
pub use installation::{InstallationEstimate, InstallationUncertainty};
pub use integrity::{Integrity, IntegrityAlert};
pub use loose::PositionFix;
pub use ned::covariance_ned;
pub use records::{
    BatchRecord, MeasurementKind, MeasurementRecord, MeasurementStatus, ResetKind, ResetRecord,
    RunRecords,
};
pub use run::{run, run_smoothed, smoothed_solution, solution, Aiding};
pub(crate) use run::{run_paused, run_until_error};
pub use tuning::{
    BiasProcess, FilterTuning, InitialUncertainty, MeasurementFloor, RangeBiasModel, Recovery,
    DEFAULT_GATE_PROBABILITY, DEFAULT_PSEUDORANGE_CORRELATION_TIME_S,
};
