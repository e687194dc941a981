//! The closed-loop error-state machinery both coupled filters share: the
//! corrected INS, propagation at the IMU rate, aiding epochs matched to IMU
//! times, feedback of the estimated errors, and the solution record.
//! Measurement batches, their tests and the recovery from failing ones are
//! in [`batch`]; the lever arm in [`super::antenna`].

pub(crate) mod batch;
pub(crate) mod carrier_history;
mod range_bias;

use std::ops::AddAssign;

use nalgebra::{Matrix3, SMatrix, Vector3};

use super::installation::InstallationEstimate;
use super::motion_history::MotionHistory;
use super::records::{BatchRecord, MeasurementKind, MeasurementRecord, ResetRecord};
use super::tuning::FilterTuning;
use crate::attitude::{rotation_vector_to_dcm, skew};
use crate::filter::state::{
    Layout, ACCEL_BIAS, ACCEL_SCALE_FACTOR, ATTITUDE, CLOCK_DRIFT, CLOCK_OFFSET, GYRO_BIAS,
    GYRO_SCALE_FACTOR, INSTALLATION_STATES, INTER_SYSTEM_BIAS_STATES, MAX_RANGE_BIAS_SLOTS,
    POSITION, VELOCITY,
};
use crate::filter::{ErrorStateKf, SystemInputs};
use crate::geodesy::{c_n_e, ecef_to_geodetic, gravity_ecef};
use crate::gnss::plausible;
use crate::ins::{self, ImuData, ImuIncrement, ImuSample, NavState};
use crate::limits::MAX_SENSOR_MAGNITUDE;
use crate::{validate, Error, Result};
use carrier_history::CarrierHistory;
use range_bias::RangeBiasSlots;

/// The navigation state and sensor/clock estimates the filter starts from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialState {
    /// Position, velocity and attitude at the first IMU time.
    pub nav: NavState,
    /// Accelerometer bias estimate, m/s².
    pub accel_bias_m_s2: Vector3<f64>,
    /// Gyro bias estimate, rad/s.
    pub gyro_bias_rad_s: Vector3<f64>,
    /// Receiver clock offset, m; `None`: set at the first GNSS epoch to the
    /// median of pseudorange minus predicted range (robust to an outlier).
    pub clock_offset_m: Option<f64>,
    /// Receiver clock drift, m/s; `None`: the median of the range-rate
    /// residuals at the first epoch with rates (0 without them).
    pub clock_drift_m_s: Option<f64>,
}

impl InitialState {
    /// The start every consumer of a navigation state checks
    /// ([`NavState::validate`]), sensor estimates within the sensors'
    /// range, and a receiver clock a receiver can have ([`plausible`]:
    /// offset ≤ 1e8 m, drift ≤ 3e4 m/s).
    pub fn validate(&self) -> Result<()> {
        self.nav.validate("initial.")?;
        validate::bounded_vectors(
            "initial.accel_bias",
            &[self.accel_bias_m_s2],
            MAX_SENSOR_MAGNITUDE,
        )?;
        validate::bounded_vectors(
            "initial.gyro_bias",
            &[self.gyro_bias_rad_s],
            MAX_SENSOR_MAGNITUDE,
        )?;
        // A receiver clock within its ranges ([`plausible`]).
        for (name, v, max) in [
            (
                "initial.clock_offset",
                self.clock_offset_m,
                plausible::MAX_CLOCK_OFFSET_M,
            ),
            (
                "initial.clock_drift",
                self.clock_drift_m_s,
                plausible::MAX_CLOCK_DRIFT_M_S,
            ),
        ] {
            if let Some(v) = v {
                validate::finite_scalars(name, &[v])?;
                validate::at_most(name, v.abs(), max)?;
            }
        }
        Ok(())
    }
}

impl InitialState {
    /// A position and speed a receiver can have ([`plausible`]: heights
    /// −1e4 to 1e7 m, speed ≤ 1e4 m/s): what a user starts the step API
    /// from. A batch run derives its start from the first fix or epoch and
    /// recovers from a wild one by resets, so it checks only
    /// [`Self::validate`].
    pub fn check_receiver(&self) -> Result<()> {
        plausible::check_receiver_position(&self.nav.position_ecef)
            .map_err(|reason| Error::invalid("initial.position", reason))?;
        validate::at_most(
            "initial.velocity",
            self.nav.velocity_ecef.norm(),
            plausible::MAX_SPEED_M_S,
        )
    }
}

/// The running state of a closed-loop coupled filter.
#[derive(Debug, Clone)]
pub struct FilterState<const N: usize> {
    /// The corrected INS solution at the IMU.
    pub nav: NavState,
    /// Accelerometer bias estimate, m/s² (subtracted from raw samples).
    pub accel_bias_m_s2: Vector3<f64>,
    /// Gyro bias estimate, rad/s.
    pub gyro_bias_rad_s: Vector3<f64>,
    /// Accelerometer scale-factor estimate (zero without scale-factor states).
    pub accel_scale_factor: Vector3<f64>,
    /// Gyro scale-factor estimate (zero without scale-factor states).
    pub gyro_scale_factor: Vector3<f64>,
    /// Receiver clock offset estimate, m.
    pub clock_offset_m: f64,
    /// Receiver clock drift estimate, m/s.
    pub clock_drift_m_s: f64,
    /// Pseudorange-bias estimate of the satellite in each range-bias slot, m
    /// (zero without range-bias states and beyond the layout's slots).
    pub range_bias_m: [f64; MAX_RANGE_BIAS_SLOTS],
    /// Inter-system bias estimates (Galileo, BeiDou pseudoranges minus
    /// GPS's at one receiver clock), m (zero without the states).
    pub inter_system_bias_m: [f64; INTER_SYSTEM_BIAS_STATES],
    /// Lever arm, time offset, velocity latency and mounting: estimated with
    /// the installation states, the configuration's values without.
    pub installation: InstallationEstimate,
    /// Whether the clock offset / drift have been initialised.
    pub(crate) clock_known: (bool, bool),
    /// Whether each inter-system bias has been initialised.
    pub(crate) inter_system_bias_known: [bool; INTER_SYSTEM_BIAS_STATES],
    /// Which satellite holds which range-bias slot.
    pub(crate) slots: RangeBiasSlots,
    /// Error state and covariance.
    pub kf: ErrorStateKf<N>,
    /// The tuning the filter runs with.
    pub(crate) tuning: FilterTuning,
    /// The last corrected IMU sample propagated to (for the lever-arm
    /// velocity and the velocity latency).
    pub(crate) last_sample: ImuSample,
    /// The raw sample at the filter's time: the start of the next
    /// interval a [`Self::predict`] integrates over.
    pub(crate) raw_sample: ImuSample,
    /// The corrected increments of the last interval stepped by
    /// increments (for the next interval's coning and sculling terms).
    pub(crate) last_increment: ImuIncrement,
    /// Time of the last propagation, s.
    pub(crate) time_s: f64,
    /// The last second of motion, for the antenna's velocity at an
    /// earlier time ([`crate::coupling::motion_history`]).
    pub(crate) motion_history: MotionHistory,
    /// Consecutive epochs whose batch of each kind failed (index: position
    /// of the kind in [`MeasurementKind::ALL`]).
    pub(crate) failed_epochs: [usize; MeasurementKind::ALL.len()],
    /// When each kind last had a batch accepted (the start when never).
    pub(crate) last_accepted_s: [f64; MeasurementKind::ALL.len()],
    /// Resets of each kind since its last accepted batch.
    pub(crate) resets_in_a_row: [usize; MeasurementKind::ALL.len()],
    /// The batch being assembled (see [`batch`]).
    pub(crate) staged: batch::Batch,
    /// The previous GNSS epoch's carrier phases (tight coupling).
    pub(crate) carrier: CarrierHistory,
    /// Time of the previous GNSS epoch, s: the interval of the carrier
    /// changes and of the code noise's correlation (tight coupling), of
    /// the fixes' error correlation (a fix given to the step API).
    pub(crate) previous_epoch_s: Option<f64>,
    /// Every scalar measurement seen, in time order.
    pub records: Vec<MeasurementRecord>,
    /// Every batch test, in time order.
    pub batches: Vec<BatchRecord>,
    /// Every reset, in time order.
    pub resets: Vec<ResetRecord>,
}

impl<const N: usize> FilterState<N> {
    /// The filter at the first IMU time: P₀ from `tuning.initial_std`
    /// (attitude rotated from NED into ECEF at the initial position).
    pub fn new(init: &InitialState, tuning: &FilterTuning) -> Result<Self> {
        init.validate()?;
        tuning.validate()?;
        // The specific force at rest in the initial attitude is the one whose
        // errors the bias states absorb (`filter::input_noise`).
        let mut tuning = *tuning;
        tuning.process_noise.input_errors.reference_specific_force_b =
            -init.nav.c_b_e.transpose() * gravity_ecef(&init.nav.position_ecef);
        let layout = Layout::for_size::<N>();
        let s = &tuning.initial_std;
        let mut p0 = SMatrix::<f64, N, N>::zeros();
        let geo = ecef_to_geodetic(&init.nav.position_ecef);
        let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
        let p_att =
            cne * Matrix3::from_diagonal(&s.attitude_ned_rad.map(|v| v * v)) * cne.transpose();
        p0.fixed_view_mut::<3, 3>(ATTITUDE, ATTITUDE)
            .copy_from(&(0.5 * (p_att + p_att.transpose())));
        for k in 0..3 {
            p0[(VELOCITY + k, VELOCITY + k)] = s.velocity_m_s.powi(2);
            p0[(POSITION + k, POSITION + k)] = s.position_m.powi(2);
            p0[(ACCEL_BIAS + k, ACCEL_BIAS + k)] = s.accel_bias_m_s2.powi(2);
            p0[(GYRO_BIAS + k, GYRO_BIAS + k)] = s.gyro_bias_rad_s.powi(2);
            if layout.scale_factors {
                p0[(ACCEL_SCALE_FACTOR + k, ACCEL_SCALE_FACTOR + k)] = s.accel_scale_factor.powi(2);
                p0[(GYRO_SCALE_FACTOR + k, GYRO_SCALE_FACTOR + k)] = s.gyro_scale_factor.powi(2);
            }
        }
        p0[(CLOCK_OFFSET, CLOCK_OFFSET)] = s.clock_offset_m.powi(2);
        p0[(CLOCK_DRIFT, CLOCK_DRIFT)] = s.clock_drift_m_s.powi(2);
        if let Some(first) = layout.installation {
            for (k, v) in s.installation.variances().into_iter().enumerate() {
                p0[(first + k, first + k)] = v;
            }
            // The start is the antenna's position less the assumed lever
            // arm: δr = δr_a − Ĉ δl, so the position carries the lever
            // arm's uncertainty and is correlated with it (without this a
            // vertical lever-arm error, which no motion reveals, would be
            // taken for the lever arm alone).
            let c = init.nav.c_b_e;
            let p_l = p0.fixed_view::<3, 3>(first, first).into_owned();
            let cross = -c * p_l;
            p0.fixed_view_mut::<3, 3>(POSITION, POSITION)
                .add_assign(&(c * p_l * c.transpose()));
            p0.fixed_view_mut::<3, 3>(POSITION, first).copy_from(&cross);
            p0.fixed_view_mut::<3, 3>(first, POSITION)
                .copy_from(&cross.transpose());
        }
        if let Some(first) = layout.inter_system_bias {
            for j in first..first + INTER_SYSTEM_BIAS_STATES {
                p0[(j, j)] = s.inter_system_bias_m.powi(2);
            }
        }
        if let Some(first) = layout.range_bias {
            for j in first..first + layout.range_bias_slots {
                p0[(j, j)] = s.range_bias_m.powi(2);
            }
        }
        Ok(Self {
            nav: init.nav,
            accel_bias_m_s2: init.accel_bias_m_s2,
            gyro_bias_rad_s: init.gyro_bias_rad_s,
            accel_scale_factor: Vector3::zeros(),
            gyro_scale_factor: Vector3::zeros(),
            clock_offset_m: init.clock_offset_m.unwrap_or(0.0),
            clock_drift_m_s: init.clock_drift_m_s.unwrap_or(0.0),
            range_bias_m: [0.0; MAX_RANGE_BIAS_SLOTS],
            inter_system_bias_m: [0.0; INTER_SYSTEM_BIAS_STATES],
            installation: InstallationEstimate::configured(
                tuning.antenna_lever_arm_b_m,
                tuning.velocity_latency_s,
            ),
            clock_known: (
                init.clock_offset_m.is_some(),
                init.clock_drift_m_s.is_some(),
            ),
            inter_system_bias_known: [false; INTER_SYSTEM_BIAS_STATES],
            slots: RangeBiasSlots::default(),
            kf: ErrorStateKf::new(p0).map_err(|e| initial_uncertainty_error(e, s))?,
            tuning,
            last_sample: ImuSample::default(),
            raw_sample: ImuSample::default(),
            last_increment: ImuIncrement::default(),
            time_s: f64::NAN,
            motion_history: MotionHistory::default(),
            failed_epochs: [0; MeasurementKind::ALL.len()],
            // Set at the first propagation (the run's first IMU time).
            last_accepted_s: [f64::NAN; MeasurementKind::ALL.len()],
            resets_in_a_row: [0; MeasurementKind::ALL.len()],
            staged: batch::Batch::default(),
            carrier: CarrierHistory::default(),
            previous_epoch_s: None,
            records: Vec::new(),
            batches: Vec::new(),
            resets: Vec::new(),
        })
    }

    /// Raw sample corrected by the current estimates: f̂ = (f̃ − b̂_a) ⊘ (1 + ŝ_a),
    /// ω̂ likewise (the inverse of the filter's sensor model, §state).
    pub fn corrected(&self, raw: &ImuSample) -> ImuSample {
        let bias = ImuSample {
            specific_force_b: self.accel_bias_m_s2,
            angular_rate_b: self.gyro_bias_rad_s,
        };
        self.corrected_by(raw, &bias)
    }

    /// `raw` less `bias`, divided by one plus the scale-factor estimates.
    fn corrected_by(&self, raw: &ImuSample, bias: &ImuSample) -> ImuSample {
        if self.accel_scale_factor == Vector3::zeros() && self.gyro_scale_factor == Vector3::zeros()
        {
            // ŝ = 0 (always without scale-factor states): the division by
            // 1 + 0 = 1 would return its dividend.
            return ImuSample {
                specific_force_b: raw.specific_force_b - bias.specific_force_b,
                angular_rate_b: raw.angular_rate_b - bias.angular_rate_b,
            };
        }
        ImuSample {
            specific_force_b: (raw.specific_force_b - bias.specific_force_b)
                .component_div(&self.accel_scale_factor.add_scalar(1.0)),
            angular_rate_b: (raw.angular_rate_b - bias.angular_rate_b)
                .component_div(&self.gyro_scale_factor.add_scalar(1.0)),
        }
    }

    /// Puts the filter at `time_s` with the raw sample there: the first
    /// sample of a run, the start of the first interval.
    pub(crate) fn begin_at(&mut self, time_s: f64, raw: &ImuSample) {
        self.raw_sample = *raw;
        self.last_sample = self.corrected(raw);
        self.time_s = time_s;
        self.last_accepted_s = [time_s; MeasurementKind::ALL.len()];
    }

    /// INS step from the filter's time and raw sample to `time_s` and the
    /// raw sample `raw` there (the mechanization integrates between the
    /// two, [`ins::step`]), clock prediction and P propagation. The one
    /// step the batch run and the step API share.
    pub(crate) fn step_to(&mut self, time_s: f64, raw: &ImuSample) -> Result<()> {
        let prev_raw = std::mem::replace(&mut self.raw_sample, *raw);
        let dt = time_s - self.time_s;
        if dt <= 0.0 {
            return Ok(());
        }
        let prev = self.corrected(&prev_raw);
        let curr = self.corrected(raw);
        let nav = ins::step(&self.nav, &prev, &curr, dt);
        self.advance(nav, curr, dt, time_s)
    }

    /// INS step over an interval of `dt` ending at `time_s` from the raw
    /// increments of that interval, with coning and sculling from the
    /// previous interval's ([`ins::step_increments`]); the mean rates
    /// α̂/dt and ν̂/dt stand for the sample at `time_s` in P's propagation
    /// and in the rows that use the current rate.
    pub(crate) fn step_increments_to(
        &mut self,
        time_s: f64,
        raw: &ImuIncrement,
        dt: f64,
    ) -> Result<()> {
        if dt <= 0.0 {
            return Ok(());
        }
        // The increments corrected as the samples are (`corrected`), the
        // bias integrated over the interval: α̂ = (α − b̂_g dt) ⊘ (1 + ŝ_g).
        let bias = ImuSample {
            specific_force_b: self.accel_bias_m_s2 * dt,
            angular_rate_b: self.gyro_bias_rad_s * dt,
        };
        let corrected = self.corrected_by(
            &ImuSample {
                specific_force_b: raw.delta_velocity_b,
                angular_rate_b: raw.delta_angle_b,
            },
            &bias,
        );
        let curr = ImuIncrement {
            delta_velocity_b: corrected.specific_force_b,
            delta_angle_b: corrected.angular_rate_b,
        };
        let mean = ImuSample {
            specific_force_b: curr.delta_velocity_b / dt,
            angular_rate_b: curr.delta_angle_b / dt,
        };
        let nav = ins::step_increments(&self.nav, &self.last_increment, &curr, dt);
        self.last_increment = curr;
        self.raw_sample = ImuSample {
            specific_force_b: raw.delta_velocity_b / dt,
            angular_rate_b: raw.delta_angle_b / dt,
        };
        self.advance(nav, mean, dt, time_s)
    }

    /// Takes the INS to `nav` (one step of `dt` ending at `time_s`, `curr`
    /// the corrected sample there): clock prediction, the motion history
    /// and P propagation.
    fn advance(&mut self, nav: NavState, curr: ImuSample, dt: f64, time_s: f64) -> Result<()> {
        let velocity_before = self.nav.velocity_ecef;
        self.nav = nav;
        self.clock_offset_m += self.clock_drift_m_s * dt;
        self.last_sample = curr;
        self.time_s = time_s;
        self.motion_history.record(
            time_s,
            self.nav.c_b_e * skew(&curr.angular_rate_b),
            self.nav.velocity_ecef - velocity_before,
        );
        let inputs = SystemInputs {
            c_b_e: self.nav.c_b_e,
            specific_force_b: curr.specific_force_b,
            angular_rate_b: curr.angular_rate_b,
            position_ecef: self.nav.position_ecef,
        };
        self.kf
            .propagate(&inputs, &self.tuning.process_noise, dt, time_s)
    }

    /// Closed loop: subtract the estimated errors from the INS, sensor,
    /// clock and range-bias estimates (errors are estimate − truth) and zero
    /// the error state; then the full health check of P.
    pub(crate) fn feedback(&mut self, time_s: f64) -> Result<()> {
        let x = self.kf.x;
        self.nav = corrected_nav(&self.nav, &x);
        self.accel_bias_m_s2 -= x.accel_bias();
        self.gyro_bias_rad_s -= x.gyro_bias();
        self.clock_offset_m -= x.clock_offset();
        self.clock_drift_m_s -= x.clock_drift();
        if let Some((sa, sg)) = x.scale_factors() {
            self.accel_scale_factor -= sa;
            self.gyro_scale_factor -= sg;
        }
        let layout = Layout::for_size::<N>();
        if let Some(first) = layout.range_bias {
            let slots = &mut self.range_bias_m[..layout.range_bias_slots];
            for (k, b) in slots.iter_mut().enumerate() {
                *b -= x.0[first + k];
            }
        }
        if let Some(first) = Layout::for_size::<N>().inter_system_bias {
            for (k, b) in self.inter_system_bias_m.iter_mut().enumerate() {
                *b -= x.0[first + k];
            }
        }
        self.installation = self.installation.corrected(&x);
        self.kf.x = crate::filter::ErrorState::zero();
        self.kf.check_health(time_s)
    }

    /// Moves out what the run recorded (measurements, batches, resets).
    pub fn take_records(&mut self) -> super::records::RunRecords {
        super::records::RunRecords {
            measurements: std::mem::take(&mut self.records),
            batches: std::mem::take(&mut self.batches),
            resets: std::mem::take(&mut self.resets),
        }
    }

    /// The tuning the filter runs with.
    pub fn tuning(&self) -> &FilterTuning {
        &self.tuning
    }

    /// Records the run of `samples` IMU samples for a smoother
    /// ([`Solution::smoothed`]).
    pub(crate) fn enable_smoother(&mut self, samples: usize) {
        self.kf
            .record_for_smoother(&self.tuning.process_noise, samples);
    }
}

/// The navigation state corrected by the error estimate `x` (errors are
/// estimate − truth, so they are subtracted): Ĉ = (I + [ψ×]) C  ⇒
/// C = R(−ψ) Ĉ, a product of rotations, then one step of C ← C (3I − CᵀC)/2
/// (the first-order polar factor) against round-off. (Not
/// `attitude::orthonormalize`: its iteration from the identity can land on
/// a wrong rotation far from the identity, as ECEF attitudes are.)
fn corrected_nav<const N: usize>(nav: &NavState, x: &crate::filter::ErrorState<N>) -> NavState {
    let c = rotation_vector_to_dcm(&(-x.attitude())) * nav.c_b_e;
    NavState {
        c_b_e: 0.5 * c * (3.0 * Matrix3::identity() - c.transpose() * c),
        velocity_ecef: nav.velocity_ecef - x.velocity(),
        position_ecef: nav.position_ecef - x.position(),
    }
}

/// The smoothed IMU positions of a run whose forward positions (one per
/// output of `log`) are `position_ecef`, m: each corrected by its smoothed
/// error as [`Solution::smoothed`] corrects it, bit for bit, from the
/// pass that carries the error estimates alone
/// ([`crate::filter::smoother::SmootherLog::smooth_errors`]). For runs
/// that score positions only (the Monte Carlo experiments).
pub(crate) fn smoothed_positions<const N: usize>(
    position_ecef: &[Vector3<f64>],
    log: &mut crate::filter::smoother::SmootherLog<N, crate::filter::InsStepModel>,
) -> Result<Vec<Vector3<f64>>> {
    check_outputs(log, position_ecef.len())?;
    let mut out = position_ecef.to_vec();
    log.smooth_errors(|k, error| out[k] -= crate::filter::ErrorState::<N>(*error).position());
    Ok(out)
}

/// A smoother's log must hold one output per sample to be smoothed.
fn check_outputs<const N: usize>(
    log: &crate::filter::smoother::SmootherLog<N, crate::filter::InsStepModel>,
    samples: usize,
) -> Result<()> {
    if log.outputs() == samples {
        return Ok(());
    }
    Err(Error::invalid(
        "smoother",
        format!("{} outputs recorded for {samples} samples", log.outputs()),
    ))
}

/// The upper triangles (P_xy, P_xz, P_yz) of three symmetric blocks, in
/// the layout of [`Solution::navigation_covariance_off_diagonal`].
fn off_diagonal(blocks: [Matrix3<f64>; 3]) -> [f64; 9] {
    let [a, v, r] = blocks.map(|m| [m[(0, 1)], m[(0, 2)], m[(1, 2)]]);
    [a[0], a[1], a[2], v[0], v[1], v[2], r[0], r[1], r[2]]
}

/// The error of a P₀ that is not a covariance, in the words of the
/// arguments that built it (`initial_*_std`), not the internal matrix.
fn initial_uncertainty_error(error: Error, s: &super::InitialUncertainty) -> Error {
    let Error::InvalidArgument { reason, .. } = error else {
        return error;
    };
    let a = &s.attitude_ned_rad;
    let (small, large) = (a.min(), a.max());
    if large > 1e6 * small {
        return Error::invalid(
            "initial_tilt_std, initial_heading_std",
            format!(
                "{:?} and {:?} rad are too far apart: rotated into ECEF they give an attitude covariance that {reason}; keep them within a factor of 10⁶",
                a.x, a.z
            ),
        );
    }
    Error::invalid(
        "initial uncertainties (initial_position_std, initial_velocity_std, initial_tilt_std, initial_heading_std, initial_*_bias_std, initial_clock_*_std)",
        format!("their squares span too many orders of magnitude: the initial covariance {reason}"),
    )
}

/// Anything with a time stamp that aids the INS.
pub trait AidingEpoch {
    /// Epoch time, s, on the IMU's time scale.
    fn time_s(&self) -> f64;
}

/// Checks that aiding times increase strictly and lie inside the IMU span
/// (within `tolerance`).
pub(crate) fn validate_epoch_times<E: AidingEpoch>(
    argument: &str,
    epochs: &[E],
    imu_time_s: &[f64],
    tolerance: f64,
) -> Result<()> {
    let times: Vec<f64> = epochs.iter().map(AidingEpoch::time_s).collect();
    validate::epochs_in_imu_span(argument, &times, imu_time_s, tolerance)?;
    let (t0, t1) = (imu_time_s[0], imu_time_s[imu_time_s.len() - 1]);
    for (i, e) in epochs.iter().enumerate() {
        let t = e.time_s();
        if !t.is_finite() {
            return Err(Error::invalid(
                argument,
                format!("epoch {i} has a non-finite time"),
            ));
        }
        if t < t0 - tolerance || t > t1 + tolerance {
            return Err(Error::invalid(
                argument,
                format!("epoch {i} at t = {t} s lies outside the IMU span [{t0}, {t1}] s"),
            ));
        }
        if i > 0 && t <= epochs[i - 1].time_s() {
            return Err(Error::invalid(
                argument,
                format!(
                    "epoch times must increase strictly: epoch {i} ({t} s) does not follow epoch {} ({} s)",
                    i - 1,
                    epochs[i - 1].time_s()
                ),
            ));
        }
    }
    Ok(())
}

/// What a run does at each IMU sample besides propagating: aids that use
/// the IMU itself (zero-velocity, zero-rate, non-holonomic updates, an
/// alignment), then whatever records the solution.
pub(crate) trait SampleHook<const N: usize> {
    /// Called after the INS reached sample `k` and any aiding epoch at that
    /// sample was applied.
    fn at_sample(&mut self, k: usize, state: &mut FilterState<N>) -> Result<()>;
}

/// Work at every IMU sample for a filter of any state size: the aids a
/// configuration asks for, in a run whose size is chosen at run time
/// ([`super::factory::solve_aided`]). `()` does nothing.
pub trait SampleAid {
    /// Called after the INS reached sample `k` and any aiding epoch at that
    /// sample was applied, before the solution records the sample.
    fn at_sample<const N: usize>(&mut self, k: usize, state: &mut FilterState<N>) -> Result<()>;
}

impl SampleAid for () {
    fn at_sample<const N: usize>(&mut self, _k: usize, _state: &mut FilterState<N>) -> Result<()> {
        Ok(())
    }
}

/// A hook that only observes the state.
pub(crate) struct Observe<O>(pub O);

impl<const N: usize, O: FnMut(usize, &FilterState<N>)> SampleHook<N> for Observe<O> {
    fn at_sample(&mut self, k: usize, state: &mut FilterState<N>) -> Result<()> {
        (self.0)(k, state);
        Ok(())
    }
}

/// Runs the closed-loop filter over the IMU series.
///
/// Time matching: an aiding epoch within `tolerance` of an IMU sample is
/// applied right after that sample; one strictly between two samples is
/// applied at its own time, the INS being stepped there with a linearly
/// interpolated IMU sample (with increments: the epoch's share of the
/// interval's, at constant rates) and then on to the next sample. `update`
/// applies one epoch's measurements (each batch fed back when it is
/// accepted, see [`batch`]); `hook` runs at every IMU sample after
/// the updates at that sample.
pub(crate) fn run<const N: usize, E, U, H>(
    imu: &ImuData,
    epochs: &[E],
    state: &mut FilterState<N>,
    tolerance: f64,
    mut update: U,
    hook: &mut H,
) -> Result<()>
where
    E: AidingEpoch,
    U: FnMut(&mut FilterState<N>, usize, &E) -> Result<()>,
    H: SampleHook<N>,
{
    let at = begin(imu, epochs, state, tolerance, &mut update, hook)?;
    run_to(
        imu,
        epochs,
        state,
        tolerance,
        update,
        hook,
        at,
        imu.time_s.len() - 1,
    )?;
    Ok(())
}

/// Where a run stands: the last IMU sample it reached (the hook has seen
/// it) and the next aiding epoch to apply. A copy of the filter state
/// with its progress continues the run on any aiding that agrees with
/// the run's so far ([`run_to`]): the run is causal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Progress {
    pub sample: usize,
    pub epoch: usize,
}

/// The first sample of [`run`]: the INS started at it and the epochs
/// there applied.
pub(crate) fn begin<const N: usize, E, U, H>(
    imu: &ImuData,
    epochs: &[E],
    state: &mut FilterState<N>,
    tolerance: f64,
    update: &mut U,
    hook: &mut H,
) -> Result<Progress>
where
    E: AidingEpoch,
    U: FnMut(&mut FilterState<N>, usize, &E) -> Result<()>,
    H: SampleHook<N>,
{
    let t0 = imu.time_s[0];
    let mut j = 0;
    state.begin_at(t0, &imu.sample(0));
    while j < epochs.len() && epochs[j].time_s() <= t0 + tolerance {
        update(state, j, &epochs[j])?;
        j += 1;
    }
    hook.at_sample(0, state)?;
    state.kf.mark_output();
    Ok(Progress {
        sample: 0,
        epoch: j,
    })
}

/// [`run`] on from `from` to IMU sample `last` (inclusive).
#[allow(clippy::too_many_arguments)]
pub(crate) fn run_to<const N: usize, E, U, H>(
    imu: &ImuData,
    epochs: &[E],
    state: &mut FilterState<N>,
    tolerance: f64,
    mut update: U,
    hook: &mut H,
    from: Progress,
    last: usize,
) -> Result<Progress>
where
    E: AidingEpoch,
    U: FnMut(&mut FilterState<N>, usize, &E) -> Result<()>,
    H: SampleHook<N>,
{
    let t = imu.time_s;
    let mut j = from.epoch;
    for k in from.sample..last {
        let (ta, tb) = (t[k], t[k + 1]);
        let (sa, sb) = (imu.sample(k), imu.sample(k + 1));
        // The part of the interval's increments integrated so far.
        let mut done = 0.0;
        while j < epochs.len() && epochs[j].time_s() < tb - tolerance {
            let tg = epochs[j].time_s();
            let w = (tg - ta) / (tb - ta);
            match imu.increments {
                // Constant rates across the interval: the part up to the
                // epoch holds its share of the increments.
                Some(increments) => {
                    let part = increments[k].scaled(w - done);
                    state.step_increments_to(tg, &part, tg - state.time_s)?;
                    done = w;
                }
                None => {
                    let sg = ImuSample {
                        specific_force_b: sa.specific_force_b.lerp(&sb.specific_force_b, w),
                        angular_rate_b: sa.angular_rate_b.lerp(&sb.angular_rate_b, w),
                    };
                    state.step_to(tg, &sg)?;
                }
            }
            update(state, j, &epochs[j])?;
            j += 1;
        }
        match imu.increments {
            Some(increments) if done == 0.0 => {
                state.step_increments_to(tb, &increments[k], tb - ta)?
            }
            Some(increments) => {
                let rest = increments[k].scaled(1.0 - done);
                state.step_increments_to(tb, &rest, tb - state.time_s)?
            }
            None => state.step_to(tb, &sb)?,
        }
        while j < epochs.len() && epochs[j].time_s() <= tb + tolerance {
            update(state, j, &epochs[j])?;
            j += 1;
        }
        hook.at_sample(k + 1, state)?;
        state.kf.mark_output();
    }
    Ok(Progress {
        sample: last.max(from.sample),
        epoch: j,
    })
}

/// The whole solution of a coupled filter at every IMU sample.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// IMU sample times, s.
    pub time_s: Vec<f64>,
    /// Position r^e of the IMU, m.
    pub position_ecef: Vec<Vector3<f64>>,
    /// Velocity v^e of the IMU, m/s.
    pub velocity_ecef: Vec<Vector3<f64>>,
    /// Attitude C_b^e.
    pub c_b_e: Vec<Matrix3<f64>>,
    /// Accelerometer bias estimate, m/s².
    pub accel_bias_m_s2: Vec<Vector3<f64>>,
    /// Gyro bias estimate, rad/s.
    pub gyro_bias_rad_s: Vec<Vector3<f64>>,
    /// Accelerometer scale-factor estimate (empty without scale-factor states).
    pub accel_scale_factor: Vec<Vector3<f64>>,
    /// Gyro scale-factor estimate (empty without scale-factor states).
    pub gyro_scale_factor: Vec<Vector3<f64>>,
    /// Receiver clock offset, m.
    pub clock_offset_m: Vec<f64>,
    /// Receiver clock drift, m/s.
    pub clock_drift_m_s: Vec<f64>,
    /// Installation estimates, in the order of the installation block
    /// ([`crate::filter::state::Installation`]; empty without the block).
    pub installation: Vec<[f64; INSTALLATION_STATES]>,
    /// Inter-system bias estimates (Galileo, BeiDou minus GPS), m (empty
    /// without the inter-system-bias states).
    pub inter_system_bias_m: Vec<[f64; INTER_SYSTEM_BIAS_STATES]>,
    /// Number of error states (see [`Layout::of`]).
    pub n_states: usize,
    /// Diagonal of P at each sample, row-major `(len, n_states)`, in the
    /// units of [`crate::filter::state`] squared.
    pub covariance_diagonal: Vec<f64>,
    /// The off-diagonal entries of the attitude (rad²), velocity (m²/s²)
    /// and position (m²) blocks of P (ECEF axes) at each sample, three per
    /// block in that order: P_xy, P_xz, P_yz (the upper triangle; P is
    /// symmetric). Their diagonals are in `covariance_diagonal`; the whole
    /// blocks: [`Self::attitude_covariance_ecef`],
    /// [`Self::velocity_covariance_ecef`], [`Self::position_covariance_ecef`].
    pub navigation_covariance_off_diagonal: Vec<[f64; 9]>,
    /// Every scalar measurement: innovation, NIS, status.
    pub measurements: Vec<MeasurementRecord>,
    /// Every batch test.
    pub batches: Vec<BatchRecord>,
    /// Every reset.
    pub resets: Vec<ResetRecord>,
    /// What the run found implausible (IMU units, the integrity alerts;
    /// see `coupling::diagnostics`), one sentence each.
    pub warnings: Vec<String>,
    /// Whether the solution can be trusted: innovation consistency per GNSS
    /// kind and the alerts ([`super::integrity`]).
    pub integrity: super::integrity::Integrity,
}

impl Solution {
    pub(crate) fn with_capacity(len: usize, n_states: usize) -> Self {
        let layout = Layout::of(n_states);
        let sf = if layout.is_some_and(|l| l.scale_factors) {
            len
        } else {
            0
        };
        let installation = if layout.is_some_and(|l| l.installation.is_some()) {
            len
        } else {
            0
        };
        let isb = if layout.is_some_and(|l| l.inter_system_bias.is_some()) {
            len
        } else {
            0
        };
        Self {
            time_s: Vec::with_capacity(len),
            position_ecef: Vec::with_capacity(len),
            velocity_ecef: Vec::with_capacity(len),
            c_b_e: Vec::with_capacity(len),
            accel_bias_m_s2: Vec::with_capacity(len),
            gyro_bias_rad_s: Vec::with_capacity(len),
            accel_scale_factor: Vec::with_capacity(sf),
            gyro_scale_factor: Vec::with_capacity(sf),
            clock_offset_m: Vec::with_capacity(len),
            clock_drift_m_s: Vec::with_capacity(len),
            installation: Vec::with_capacity(installation),
            inter_system_bias_m: Vec::with_capacity(isb),
            n_states,
            covariance_diagonal: Vec::with_capacity(len * n_states),
            navigation_covariance_off_diagonal: Vec::with_capacity(len),
            measurements: Vec::new(),
            batches: Vec::new(),
            resets: Vec::new(),
            warnings: Vec::new(),
            integrity: super::integrity::Integrity::default(),
        }
    }

    pub(crate) fn push<const N: usize>(&mut self, time_s: f64, s: &FilterState<N>) {
        self.time_s.push(time_s);
        self.position_ecef.push(s.nav.position_ecef);
        self.velocity_ecef.push(s.nav.velocity_ecef);
        self.c_b_e.push(s.nav.c_b_e);
        self.accel_bias_m_s2.push(s.accel_bias_m_s2);
        self.gyro_bias_rad_s.push(s.gyro_bias_rad_s);
        if Layout::for_size::<N>().scale_factors {
            self.accel_scale_factor.push(s.accel_scale_factor);
            self.gyro_scale_factor.push(s.gyro_scale_factor);
        }
        self.clock_offset_m.push(s.clock_offset_m);
        self.clock_drift_m_s.push(s.clock_drift_m_s);
        if Layout::for_size::<N>().installation.is_some() {
            self.installation.push(s.installation.to_array());
        }
        if Layout::for_size::<N>().inter_system_bias.is_some() {
            self.inter_system_bias_m.push(s.inter_system_bias_m);
        }
        // P through its array of columns (fixed sizes: no index checks).
        let columns = &s.kf.p.data.0;
        let diagonal: [f64; N] = std::array::from_fn(|i| columns[i][i]);
        self.covariance_diagonal.extend_from_slice(&diagonal);
        // The upper triangles of the three blocks: P_ij is columns[j][i].
        let upper = |first: usize| {
            let at = |i: usize, j: usize| columns[first + j][first + i];
            [at(0, 1), at(0, 2), at(1, 2)]
        };
        let (a, v, r) = (upper(ATTITUDE), upper(VELOCITY), upper(POSITION));
        self.navigation_covariance_off_diagonal
            .push([a[0], a[1], a[2], v[0], v[1], v[2], r[0], r[1], r[2]]);
    }

    /// Attitude-error block of P (ECEF axes), rad², at sample `k`.
    pub fn attitude_covariance_ecef(&self, k: usize) -> Matrix3<f64> {
        self.navigation_covariance(k, 0)
    }

    /// Velocity-error block of P (ECEF axes), m²/s², at sample `k`.
    pub fn velocity_covariance_ecef(&self, k: usize) -> Matrix3<f64> {
        self.navigation_covariance(k, 1)
    }

    /// Position-error block of P (ECEF axes), m², at sample `k`.
    pub fn position_covariance_ecef(&self, k: usize) -> Matrix3<f64> {
        self.navigation_covariance(k, 2)
    }

    /// Block `block` (0 attitude, 1 velocity, 2 position) of P at sample
    /// `k`, from its diagonal and its stored upper triangle.
    fn navigation_covariance(&self, k: usize, block: usize) -> Matrix3<f64> {
        let first = [ATTITUDE, VELOCITY, POSITION][block];
        let d = &self.covariance_diagonal[k * self.n_states + first..][..3];
        let o = &self.navigation_covariance_off_diagonal[k][3 * block..3 * block + 3];
        Matrix3::new(d[0], o[0], o[1], o[0], d[1], o[2], o[1], o[2], d[2])
    }

    /// The smoothed solution: each sample of this forward solution corrected
    /// by its smoothed error estimate (the way feedback corrects the
    /// filter's state) with the smoothed covariance, from the backward pass
    /// over the run's `log` (see [`crate::filter::smoother`]). The records
    /// (measurements, batches, resets) are the forward run's.
    pub(crate) fn smoothed<const N: usize>(
        &self,
        log: &mut crate::filter::smoother::SmootherLog<N, crate::filter::InsStepModel>,
    ) -> Result<Solution> {
        check_outputs(log, self.time_s.len())?;
        let mut out = self.clone();
        log.smooth(|s| {
            let k = s.output;
            let x = crate::filter::ErrorState::<N>(s.error);
            let nav = corrected_nav(
                &NavState {
                    position_ecef: self.position_ecef[k],
                    velocity_ecef: self.velocity_ecef[k],
                    c_b_e: self.c_b_e[k],
                },
                &x,
            );
            out.position_ecef[k] = nav.position_ecef;
            out.velocity_ecef[k] = nav.velocity_ecef;
            out.c_b_e[k] = nav.c_b_e;
            out.accel_bias_m_s2[k] -= x.accel_bias();
            out.gyro_bias_rad_s[k] -= x.gyro_bias();
            if let Some((sa, sg)) = x.scale_factors() {
                out.accel_scale_factor[k] -= sa;
                out.gyro_scale_factor[k] -= sg;
            }
            out.clock_offset_m[k] -= x.clock_offset();
            out.clock_drift_m_s[k] -= x.clock_drift();
            if let Some(d) = x.installation() {
                for (v, e) in out.installation[k].iter_mut().zip(d.iter()) {
                    *v -= e;
                }
            }
            if let Some(d) = x.inter_system_biases() {
                for (v, e) in out.inter_system_bias_m[k].iter_mut().zip(d) {
                    *v -= e;
                }
            }
            // Pˢ = P⁺ − P⁺ Λ P⁺ on the entries the forward solution keeps.
            let reduction = s.reduction_diagonal();
            for (p, r) in out.covariance_diagonal[k * N..(k + 1) * N]
                .iter_mut()
                .zip(reduction.iter())
            {
                *p -= r;
            }
            let reduction =
                off_diagonal([ATTITUDE, VELOCITY, POSITION].map(|b| s.reduction_block::<3>(b)));
            for (p, r) in out.navigation_covariance_off_diagonal[k]
                .iter_mut()
                .zip(reduction)
            {
                *p -= r;
            }
        });
        Ok(out)
    }

    /// Puts each sample on the GNSS time scale when the filter estimated
    /// an IMU time offset t̂_o: the INS at IMU time τ is the vehicle at
    /// τ + t̂_o, so its position at τ is moved back along its velocity,
    /// r − t̂_o v (first order: 5 mm at 0.1 s and 1 m/s²), and the time
    /// stays τ (increasing, whatever the estimate does). Without the
    /// installation states nothing changes.
    pub(crate) fn shift_onto_gnss_time(&mut self) {
        for (k, row) in self.installation.iter().enumerate() {
            let t_o = row[crate::filter::state::Installation::TIME_OFFSET];
            self.position_ecef[k] -= t_o * self.velocity_ecef[k];
        }
    }

    /// Moves the filter's records into the solution at the end of a run.
    pub(crate) fn take_records<const N: usize>(&mut self, s: &mut FilterState<N>) {
        let records = s.take_records();
        self.measurements = records.measurements;
        self.batches = records.batches;
        self.resets = records.resets;
    }

    /// The measurements that were not applied.
    pub fn rejected(&self) -> impl Iterator<Item = &MeasurementRecord> {
        self.measurements
            .iter()
            .filter(|m| m.status != super::records::MeasurementStatus::Accepted)
    }
}
