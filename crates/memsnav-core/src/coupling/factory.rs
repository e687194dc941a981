//! The coupled filter at the state size a run needs, made from the blocks
//! chosen at run time ([`StateBlocks`]): a whole run ([`solve`]) or a
//! filter driven one call at a time behind one type whatever its size
//! ([`start`], [`RunningState`]). Every door that runs a filter on the
//! user's arrays (the Python filter classes and `RunningFilter`) comes
//! through here; navigate and the experiments reach the same
//! [`StateBlocks::dispatch`] with their own per-sample work.

use nalgebra::{DMatrix, Vector3};

use super::engine::{FilterState, InitialState, SampleAid, Solution};
use super::installation::InstallationEstimate;
use super::records::RunRecords;
use super::run::{aided_solution, Aiding};
use super::tuning::FilterTuning;
use super::PositionFix;
use crate::filter::state::{Layout, SizedJob, StateBlocks, INTER_SYSTEM_BIAS_STATES};
use crate::gnss::GnssEpoch;
use crate::ins::{ImuData, ImuIncrement, ImuSample, NavState};
use crate::Result;

/// The forward solution over whole series, and with `smooth` its
/// fixed-interval smoothed solution, from a filter with `blocks`.
pub fn solve<E: Aiding>(
    blocks: StateBlocks,
    imu: &ImuData,
    epochs: &[E],
    initial: &InitialState,
    tuning: &FilterTuning,
    smooth: bool,
) -> Result<(Solution, Option<Solution>)> {
    solve_aided(blocks, imu, epochs, initial, tuning, smooth, ())
}

/// [`solve`] with `aid` applied at every IMU sample (a configuration's
/// aids at standstills and while driving).
pub fn solve_aided<E: Aiding, A: SampleAid>(
    blocks: StateBlocks,
    imu: &ImuData,
    epochs: &[E],
    initial: &InitialState,
    tuning: &FilterTuning,
    smooth: bool,
    aid: A,
) -> Result<(Solution, Option<Solution>)> {
    blocks.dispatch(Solve {
        imu,
        epochs,
        initial,
        tuning,
        smooth,
        aid,
    })
}

struct Solve<'a, E, A> {
    imu: &'a ImuData<'a>,
    epochs: &'a [E],
    initial: &'a InitialState,
    tuning: &'a FilterTuning,
    smooth: bool,
    aid: A,
}

impl<E: Aiding, A: SampleAid> SizedJob for Solve<'_, E, A> {
    type Output = Result<(Solution, Option<Solution>)>;

    fn run<const N: usize>(self) -> Self::Output {
        let Solve {
            imu,
            epochs,
            initial,
            tuning,
            smooth,
            mut aid,
        } = self;
        aided_solution::<N, E, A>(imu, epochs, initial, tuning, smooth, &mut aid)
    }
}

/// What a running filter estimates now: the corrected navigation solution
/// and sensor, clock and installation estimates (totals, not errors).
#[derive(Debug, Clone, PartialEq)]
pub struct RunningEstimate {
    /// The filter's time, s.
    pub time_s: f64,
    /// Position, velocity and attitude at the IMU.
    pub nav: NavState,
    /// Accelerometer bias, m/s².
    pub accel_bias_m_s2: Vector3<f64>,
    /// Gyro bias, rad/s.
    pub gyro_bias_rad_s: Vector3<f64>,
    /// Accelerometer and gyro scale-factor errors (1), with scale-factor
    /// states.
    pub scale_factors: Option<(Vector3<f64>, Vector3<f64>)>,
    /// Receiver clock offset, m.
    pub clock_offset_m: f64,
    /// Receiver clock drift, m/s.
    pub clock_drift_m_s: f64,
    /// Galileo, BeiDou and GLONASS pseudorange biases relative to GPS, m,
    /// with inter-system-bias states.
    pub inter_system_bias_m: Option<[f64; INTER_SYSTEM_BIAS_STATES]>,
    /// The satellite in each occupied range-bias slot and its bias, m
    /// (loose coupling: the fix error of ECEF axis 0, 1, 2); empty without
    /// range-bias states.
    pub range_biases: Vec<(u16, f64)>,
    /// Lever arm, time offset, velocity latency and boresight, with
    /// installation states.
    pub installation: Option<InstallationEstimate>,
}

/// A coupled filter of any size driven one call at a time: the step API
/// of [`FilterState`] (see its methods for what each call does and
/// refuses) behind one type.
pub trait RunningState: Send + Sync {
    /// The optional blocks of its state.
    fn blocks(&self) -> StateBlocks;
    /// The filter's time, s ([`FilterState::time_s`]).
    fn time_s(&self) -> f64;
    /// [`FilterState::predict`].
    fn predict(&mut self, time_s: f64, raw: &ImuSample) -> Result<()>;
    /// [`FilterState::predict_increments`].
    fn predict_increments(&mut self, time_s: f64, raw: &ImuIncrement) -> Result<()>;
    /// [`FilterState::update_gnss`].
    fn update_gnss(&mut self, epoch: &GnssEpoch) -> Result<bool>;
    /// [`FilterState::update_fix`].
    fn update_fix(&mut self, fix: &PositionFix) -> Result<bool>;
    /// [`FilterState::update_zupt`].
    fn update_zupt(&mut self, std_m_s: f64) -> Result<bool>;
    /// [`FilterState::update_zaru`].
    fn update_zaru(
        &mut self,
        mean_raw_rate_b: &Vector3<f64>,
        std_rad_s: &Vector3<f64>,
    ) -> Result<bool>;
    /// [`FilterState::update_non_holonomic`].
    fn update_non_holonomic(&mut self, reference_b_m: &Vector3<f64>, std_m_s: f64) -> Result<bool>;
    /// [`FilterState::update_speed`].
    fn update_speed(
        &mut self,
        speed_m_s: f64,
        reference_b_m: &Vector3<f64>,
        std_m_s: f64,
    ) -> Result<bool>;
    /// [`FilterState::update_height`].
    fn update_height(&mut self, height_m: f64, std_m: f64) -> Result<bool>;
    /// [`FilterState::update_heading`].
    fn update_heading(&mut self, yaw_rad: f64, std_rad: f64) -> Result<bool>;
    /// The estimate now.
    fn estimate(&self) -> RunningEstimate;
    /// The error-state covariance, in the order of
    /// [`crate::filter::state::StateLayout::names`].
    fn covariance(&self) -> DMatrix<f64>;
    /// [`FilterState::take_records`].
    fn take_records(&mut self) -> RunRecords;
}

impl<const N: usize> RunningState for FilterState<N> {
    fn blocks(&self) -> StateBlocks {
        StateBlocks::of_size(N).expect("a filter's size is a layout's")
    }
    fn time_s(&self) -> f64 {
        FilterState::time_s(self)
    }
    fn predict(&mut self, time_s: f64, raw: &ImuSample) -> Result<()> {
        FilterState::predict(self, time_s, raw)
    }
    fn predict_increments(&mut self, time_s: f64, raw: &ImuIncrement) -> Result<()> {
        FilterState::predict_increments(self, time_s, raw)
    }
    fn update_gnss(&mut self, epoch: &GnssEpoch) -> Result<bool> {
        FilterState::update_gnss(self, epoch)
    }
    fn update_fix(&mut self, fix: &PositionFix) -> Result<bool> {
        FilterState::update_fix(self, fix)
    }
    fn update_zupt(&mut self, std_m_s: f64) -> Result<bool> {
        FilterState::update_zupt(self, std_m_s)
    }
    fn update_zaru(
        &mut self,
        mean_raw_rate_b: &Vector3<f64>,
        std_rad_s: &Vector3<f64>,
    ) -> Result<bool> {
        FilterState::update_zaru(self, mean_raw_rate_b, std_rad_s)
    }
    fn update_non_holonomic(&mut self, reference_b_m: &Vector3<f64>, std_m_s: f64) -> Result<bool> {
        FilterState::update_non_holonomic(self, reference_b_m, std_m_s)
    }
    fn update_speed(
        &mut self,
        speed_m_s: f64,
        reference_b_m: &Vector3<f64>,
        std_m_s: f64,
    ) -> Result<bool> {
        FilterState::update_speed(self, speed_m_s, reference_b_m, std_m_s)
    }
    fn update_height(&mut self, height_m: f64, std_m: f64) -> Result<bool> {
        FilterState::update_height(self, height_m, std_m)
    }
    fn update_heading(&mut self, yaw_rad: f64, std_rad: f64) -> Result<bool> {
        FilterState::update_heading(self, yaw_rad, std_rad)
    }
    fn estimate(&self) -> RunningEstimate {
        let layout = Layout::for_size::<N>();
        RunningEstimate {
            time_s: self.time_s,
            nav: self.nav,
            accel_bias_m_s2: self.accel_bias_m_s2,
            gyro_bias_rad_s: self.gyro_bias_rad_s,
            scale_factors: layout
                .scale_factors
                .then_some((self.accel_scale_factor, self.gyro_scale_factor)),
            clock_offset_m: self.clock_offset_m,
            clock_drift_m_s: self.clock_drift_m_s,
            inter_system_bias_m: layout.inter_system_bias.map(|_| self.inter_system_bias_m),
            range_biases: self.range_biases().collect(),
            installation: layout.installation.map(|_| self.installation),
        }
    }
    fn covariance(&self) -> DMatrix<f64> {
        DMatrix::from_iterator(N, N, self.kf.p.iter().copied())
    }
    fn take_records(&mut self) -> RunRecords {
        FilterState::take_records(self)
    }
}

/// A filter with `blocks` for aiding of kind `E` ([`GnssEpoch`] or
/// [`PositionFix`]), started at `time_s` with the raw IMU sample there
/// ([`FilterState::start`]).
pub fn start<E: Aiding>(
    blocks: StateBlocks,
    initial: &InitialState,
    tuning: &FilterTuning,
    time_s: f64,
    raw: &ImuSample,
) -> Result<Box<dyn RunningState>> {
    blocks.dispatch(Start::<E> {
        initial,
        tuning,
        time_s,
        raw,
        aiding: std::marker::PhantomData,
    })
}

struct Start<'a, E> {
    initial: &'a InitialState,
    tuning: &'a FilterTuning,
    time_s: f64,
    raw: &'a ImuSample,
    aiding: std::marker::PhantomData<E>,
}

impl<E: Aiding> SizedJob for Start<'_, E> {
    type Output = Result<Box<dyn RunningState>>;

    fn run<const N: usize>(self) -> Self::Output {
        let state = FilterState::<N>::start::<E>(self.initial, self.tuning, self.time_s, self.raw)?;
        Ok(Box::new(state))
    }
}
