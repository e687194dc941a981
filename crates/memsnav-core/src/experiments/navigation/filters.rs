//! The coupled filter of one IMU in one run, and the error curves it leaves:
//! position error norm and NEES at the output epochs.

use nalgebra::{Matrix3, SVector, Vector3};
use serde::{Deserialize, Serialize};

use crate::attitude::dcm_to_rotation_vector;
use crate::coupling::{
    self, initial_state_from_fix, Aiding, FilterState, FilterTuning, InitialState,
    MeasurementStatus, PositionFix,
};
use crate::filter::state::ATTITUDE;
use crate::filter::state::{SizedJob, StateBlocks};
use crate::geodesy::{c_n_e, ecef_to_geodetic};
use crate::gnss::{solve_fix_all_satellites, GnssEpoch, ReceiverClockModel};
use crate::ins::{ImuData, NavState};
use crate::sensors::ImuSpec;
use crate::trajectory::Trajectory;
use crate::Result;

use super::imus::ImuInput;
use crate::coupling::RunRecords;

/// Degrees of freedom of the navigation NEES (attitude, velocity, position).
pub const NEES_DOF: usize = 9;

/// How the IMU is coupled with GNSS.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Coupling {
    /// Pseudoranges (and rates) of every tracked satellite (the paper's).
    #[default]
    Tight,
    /// Least-squares position/velocity fixes, only at epochs with at least
    /// 4 satellites: blind below 4.
    Loose,
}

/// Where the filters start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Start {
    /// Position, velocity and clock from the first epoch's least-squares
    /// fix (needs 4 satellites there); attitude as drawn.
    FirstFix { attitude: Matrix3<f64> },
    /// The given state (truth plus a drawn error); clock from the first
    /// epoch's residuals, which needs one satellite.
    Given { nav: NavState },
}

/// What a run's filters share: the options of the configuration that set
/// their tuning, and the output epochs.
pub(super) struct FilterSetup<'a> {
    pub rate_hz: f64,
    /// The simulated receiver clock: the filters' clock model is the same.
    pub receiver_clock: ReceiverClockModel,
    pub coupling: Coupling,
    pub use_pseudorange_rate: bool,
    /// Whether the tightly coupled filters use the time-differenced
    /// carrier phase (`coupling/carrier.rs`): the simulated epochs carry
    /// it. The loosely coupled filter's fixes are code only.
    pub use_carrier_phase: bool,
    pub initial_attitude_std_rad: Vector3<f64>,
    /// Initial position and velocity std of a given start, m and m/s.
    pub given_start_std: Option<(f64, f64)>,
    pub scale_factor_states: bool,
    /// Whether the filters carry the inter-system-bias states (the
    /// measurements hold a system other than GPS).
    pub inter_system_bias_states: bool,
    pub absorb_unmodelled: bool,
    /// Also run the fixed-interval smoother and score its solution.
    pub smooth: bool,
    /// The output epochs (IMU sample indices) the curves are taken at.
    pub out: &'a [usize],
    /// The IMU samples the filter runs over, from the first (None: all);
    /// the epochs given must end within them.
    pub samples: Option<usize>,
}

/// One run's curves for one IMU (what a chunk of runs carries).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ImuRun {
    /// Norm of the position error per output epoch, m.
    pub position_error: Vec<f64>,
    /// Horizontal part of the position error in the local NED frame of the
    /// true position, m.
    pub horizontal_error: Vec<f64>,
    /// The vertical part, m.
    pub vertical_error: Vec<f64>,
    /// NEES of the attitude, velocity and position errors against their block of P (9 dof).
    pub nees: Vec<f64>,
    /// The NEES of the position error alone against the position block of
    /// P (3 dof).
    pub position_nees: Vec<f64>,
    /// Measurement records not accepted (gated out or not applied).
    pub rejected: usize,
    /// Measurement records accepted.
    pub accepted: usize,
    /// Whether the run raised an integrity alert (`coupling::integrity`):
    /// its solution and covariance were flagged as not trustworthy.
    pub diverged: bool,
    /// The smoothed solution's curves (NEES NaN: the smoother keeps the
    /// diagonal blocks of P only), when smoothing was asked.
    pub smoothed: Option<Box<ImuRun>>,
}

/// The fixes a loosely coupled filter uses: one per epoch whose
/// least-squares fix succeeds (4 satellites or more, non-singular
/// geometry), with the position and velocity blocks of its covariance;
/// no velocity where the epoch lacks 4 usable rates.
pub(super) fn position_fixes(epochs: &[GnssEpoch]) -> Vec<PositionFix> {
    epochs
        .iter()
        .filter(|e| e.measurements.len() >= 4)
        .filter_map(|e| solve_fix_all_satellites(e, None).ok())
        .map(|f| PositionFix {
            time_s: f.time_s,
            position_ecef: f.position_ecef,
            position_covariance: f.position_clock_covariance.fixed_view::<3, 3>(0, 0).into(),
            velocity_ecef: f
                .velocity_ecef
                .iter()
                .all(|v| v.is_finite())
                .then_some(f.velocity_ecef),
            velocity_covariance: f.velocity_drift_covariance.fixed_view::<3, 3>(0, 0).into(),
            velocity_horizontal_only: false,
        })
        .collect()
}

/// The filter's tuning: from the IMU's spec (the errors its state lacks
/// absorbed, or not, as configured), with the configured initial
/// uncertainties.
fn tuning(spec: &ImuSpec, setup: &FilterSetup) -> Result<FilterTuning> {
    let mut tuning_spec = *spec;
    if !setup.absorb_unmodelled {
        // Nothing left to absorb: the filter sees biases and noise only
        // (and the scale factors when they are states).
        let (a, g) = (&mut tuning_spec.accelerometer, &mut tuning_spec.gyroscope);
        if !setup.scale_factor_states {
            a.scale_factor_std = 0.0;
            g.scale_factor_std = 0.0;
        }
        a.misalignment_std = 0.0;
        a.nonlinearity_std = 0.0;
        g.misalignment_std = 0.0;
        g.g_sensitivity_std = 0.0;
    }
    let mut tuning =
        FilterTuning::from_imu_spec(&tuning_spec, setup.rate_hz, setup.scale_factor_states)?;
    tuning.use_pseudorange_rate = setup.use_pseudorange_rate;
    tuning.use_carrier_phase = setup.use_carrier_phase;
    // A simulated carrier change errs by its phase noise alone: none of the
    // model errors the default floor allows for on real data (sway about
    // the lever arm, time tags), so the filter takes the simulated std as
    // it takes the simulated clock (with 2 cm for 4 mm of noise its
    // velocity NEES/dof falls to 0.3).
    tuning.floor.carrier_phase_m = 0.0;
    tuning.set_receiver_clock(&setup.receiver_clock);
    tuning.initial_std.attitude_ned_rad = setup.initial_attitude_std_rad;
    if let Some((position_m, velocity_m_s)) = setup.given_start_std {
        tuning.initial_std.position_m = position_m;
        tuning.initial_std.velocity_m_s = velocity_m_s;
    }
    Ok(tuning)
}

/// The coupled filter on one IMU's readings (17 or 23 states as
/// configured, + 3 inter-system biases with several systems); error
/// curves at `setup.out`. `fixes` are the loosely
/// coupled filter's ([`position_fixes`] of `epochs`).
pub(super) fn navigate(
    truth: &Trajectory,
    epochs: &[GnssEpoch],
    fixes: &[PositionFix],
    input: &ImuInput,
    start: &Start,
    setup: &FilterSetup,
) -> Result<ImuRun> {
    let tuning = tuning(&input.spec, setup)?;
    blocks(setup).dispatch(Navigate {
        truth,
        epochs,
        fixes,
        input,
        start,
        tuning: &tuning,
        setup,
    })
}

/// The filters' optional blocks: scale factors and inter-system biases as
/// the setup asks.
fn blocks(setup: &FilterSetup) -> StateBlocks {
    StateBlocks {
        scale_factors: setup.scale_factor_states,
        inter_system_biases: setup.inter_system_bias_states,
        ..StateBlocks::default()
    }
}

/// [`navigate`]'s run at the size of its blocks.
struct Navigate<'a> {
    truth: &'a Trajectory,
    epochs: &'a [GnssEpoch],
    fixes: &'a [PositionFix],
    input: &'a ImuInput,
    start: &'a Start,
    tuning: &'a FilterTuning,
    setup: &'a FilterSetup<'a>,
}

impl SizedJob for Navigate<'_> {
    type Output = Result<ImuRun>;

    fn run<const N: usize>(self) -> Self::Output {
        let Navigate {
            truth,
            epochs,
            fixes,
            input,
            start,
            tuning,
            setup,
        } = self;
        navigate_with::<N>(truth, epochs, fixes, input, start, tuning, setup)
    }
}

fn navigate_with<const N: usize>(
    truth: &Trajectory,
    epochs: &[GnssEpoch],
    fixes: &[PositionFix],
    input: &ImuInput,
    start: &Start,
    tuning: &FilterTuning,
    setup: &FilterSetup,
) -> Result<ImuRun> {
    let imu = imu_data(truth, input, setup.samples.unwrap_or(truth.time_s.len()));
    let initial = initial_state(start, epochs, &imu)?;
    let mut curves = Curves::new(truth, setup.out);
    let observe = |k: usize, s: &FilterState<N>| curves.observe(k, s);
    let (records, smoothed) = match setup.coupling {
        Coupling::Tight => {
            forward_and_smoothed(&imu, epochs, &initial, tuning, setup.smooth, observe)?
        }
        Coupling::Loose => {
            forward_and_smoothed(&imu, fixes, &initial, tuning, setup.smooth, observe)?
        }
    };
    Ok(curves.finish(&records, smoothed.as_deref().map(|s| (s, 0))))
}

/// One branch of [`navigate_branches`]: its epochs, the IMU samples it
/// runs over (from the first) and its output epochs, all after the split;
/// in a chain, the last sample at which its epochs agree with the chain's
/// last branch's.
pub(super) struct Branch<'a> {
    pub epochs: &'a [GnssEpoch],
    pub samples: usize,
    pub out: &'a [usize],
    pub agrees_until: usize,
}

/// The tightly coupled filter of one IMU on runs that share their
/// beginning: once over `shared` to IMU sample `split`, then on from
/// copies. Each chain runs once along its last branch's epochs, and each
/// branch goes on from a copy taken at its `agrees_until` (so a chain's
/// branches must agree with its last up to there, and `shared` with every
/// branch up to `split`). Each branch's [`ImuRun`] is [`navigate`]'s on its
/// epochs (`setup.out` and `setup.samples` give way to the branch's): the
/// forward filter's bit for bit; the smoother's from a backward pass that
/// starts after `split` (the same estimates up to rounding: a
/// fixed-interval smoother's estimate at a sample depends on the forward
/// filter from that sample on). Returns the runs chain by chain.
pub(super) fn navigate_branches(
    truth: &Trajectory,
    shared: &[GnssEpoch],
    input: &ImuInput,
    start: &Start,
    setup: &FilterSetup,
    split: usize,
    chains: &[Vec<Branch<'_>>],
) -> Result<Vec<Vec<ImuRun>>> {
    let tuning = tuning(&input.spec, setup)?;
    blocks(setup).dispatch(Branches {
        truth,
        shared,
        input,
        start,
        tuning: &tuning,
        setup,
        split,
        chains,
    })
}

/// [`navigate_branches`]'s runs at the size of their blocks.
struct Branches<'a, 'b> {
    truth: &'a Trajectory,
    shared: &'a [GnssEpoch],
    input: &'a ImuInput,
    start: &'a Start,
    tuning: &'a FilterTuning,
    setup: &'a FilterSetup<'a>,
    split: usize,
    chains: &'a [Vec<Branch<'b>>],
}

impl SizedJob for Branches<'_, '_> {
    type Output = Result<Vec<Vec<ImuRun>>>;

    fn run<const N: usize>(self) -> Self::Output {
        let Branches {
            truth,
            shared,
            input,
            start,
            tuning,
            setup,
            split,
            chains,
        } = self;
        branches_with::<N>(truth, shared, input, start, tuning, setup, split, chains)
    }
}

#[allow(clippy::too_many_arguments)]
fn branches_with<const N: usize>(
    truth: &Trajectory,
    shared: &[GnssEpoch],
    input: &ImuInput,
    start: &Start,
    tuning: &FilterTuning,
    setup: &FilterSetup,
    split: usize,
    chains: &[Vec<Branch<'_>>],
) -> Result<Vec<Vec<ImuRun>>> {
    let branches = || chains.iter().flatten();
    let Some(longest) = branches().map(|b| b.samples).max() else {
        return Ok(chains.iter().map(|_| Vec::new()).collect());
    };
    let misplaced = |b: &Branch| {
        b.samples <= split
            || b.out.first().is_some_and(|&k| k <= split)
            || b.agrees_until < split
            || b.agrees_until >= b.samples
    };
    if branches().any(misplaced) {
        return Err(crate::Error::invalid(
            "branches",
            format!(
                "every branch's samples and output epochs must come after the split at sample {split}, and its agreement end within its samples"
            ),
        ));
    }
    let imu = imu_data(truth, input, longest);
    let initial = initial_state(start, shared, &imu)?;
    let shared = &shared[..shared.partition_point(|e| e.time_s <= truth.time_s[longest - 1])];
    let prefix = coupling::run_paused::<N, GnssEpoch, _>(
        &imu,
        shared,
        &initial,
        tuning,
        split,
        |_, _: &FilterState<N>| {},
    )?;
    chains
        .iter()
        .map(|chain| {
            let Some(along) = chain.last() else {
                return Ok(Vec::new());
            };
            let imu_along = imu_data(truth, input, along.samples);
            let mut curves: Vec<Curves> = chain.iter().map(|b| Curves::new(truth, b.out)).collect();
            let mut runs = Vec::with_capacity(chain.len());
            let mut paused = None;
            for (i, b) in chain.iter().enumerate() {
                // On along the chain to this branch's agreement end, every
                // branch still to come observing; then this branch's end.
                let from = paused.as_ref().unwrap_or(&prefix);
                let observe = |k: usize, s: &FilterState<N>| {
                    curves[i..].iter_mut().for_each(|c| c.observe(k, s));
                };
                let here = from.advance(
                    &imu_along,
                    along.epochs,
                    b.agrees_until,
                    setup.smooth,
                    observe,
                )?;
                let observe = |k: usize, s: &FilterState<N>| curves[i].observe(k, s);
                let imu = imu_data(truth, input, b.samples);
                let (records, smoothed) = here.finish(&imu, b.epochs, setup.smooth, observe)?;
                let c = std::mem::replace(&mut curves[i], Curves::new(truth, &[]));
                runs.push(c.finish(
                    &records,
                    smoothed.as_ref().map(|(s, first)| (&s[..], *first)),
                ));
                paused = Some(here);
            }
            Ok(runs)
        })
        .collect()
}

/// The first `samples` of the truth's time axis and `input`'s readings.
fn imu_data<'a>(truth: &'a Trajectory, input: &'a ImuInput, samples: usize) -> ImuData<'a> {
    ImuData {
        time_s: &truth.time_s[..samples],
        specific_force_b: &input.readings.specific_force_b[..samples],
        angular_rate_b: &input.readings.angular_rate_b[..samples],
        increments: None,
    }
}

/// The filter's initial state from `start`.
fn initial_state(start: &Start, epochs: &[GnssEpoch], imu: &ImuData) -> Result<InitialState> {
    Ok(match *start {
        Start::FirstFix { attitude } => initial_state_from_fix(epochs, imu, Some(attitude))?,
        Start::Given { nav } => InitialState {
            nav,
            accel_bias_m_s2: Vector3::zeros(),
            gyro_bias_rad_s: Vector3::zeros(),
            clock_offset_m: None,
            clock_drift_m_s: None,
        },
    })
}

/// A run's error curves at its output epochs, taken as the filter passes
/// them.
struct Curves<'a> {
    truth: &'a Trajectory,
    out: &'a [usize],
    next: usize,
    run: ImuRun,
}

impl<'a> Curves<'a> {
    fn new(truth: &'a Trajectory, out: &'a [usize]) -> Self {
        Self {
            truth,
            out,
            next: 0,
            run: ImuRun {
                position_error: Vec::with_capacity(out.len()),
                horizontal_error: Vec::with_capacity(out.len()),
                vertical_error: Vec::with_capacity(out.len()),
                nees: Vec::with_capacity(out.len()),
                position_nees: Vec::with_capacity(out.len()),
                rejected: 0,
                accepted: 0,
                diverged: false,
                smoothed: None,
            },
        }
    }

    /// The errors and NEES at sample `k` when it is the next output epoch.
    fn observe<const N: usize>(&mut self, k: usize, s: &FilterState<N>) {
        if self.next >= self.out.len() || self.out[self.next] != k {
            return;
        }
        let t = self.truth.nav_state(k);
        let mut e = SVector::<f64, NEES_DOF>::zeros();
        e.fixed_rows_mut::<3>(0).copy_from(&dcm_to_rotation_vector(
            &(s.nav.c_b_e * t.c_b_e.transpose()),
        ));
        e.fixed_rows_mut::<3>(3)
            .copy_from(&(s.nav.velocity_ecef - t.velocity_ecef));
        e.fixed_rows_mut::<3>(6)
            .copy_from(&(s.nav.position_ecef - t.position_ecef));
        let p =
            s.kf.p
                .fixed_view::<NEES_DOF, NEES_DOF>(ATTITUDE, ATTITUDE)
                .into_owned();
        let dr = e.fixed_rows::<3>(6).into_owned();
        let (horizontal, vertical) = horizontal_vertical(&t.position_ecef, &dr);
        let run = &mut self.run;
        run.position_error.push(dr.norm());
        run.horizontal_error.push(horizontal);
        run.vertical_error.push(vertical);
        run.nees
            .push(crate::filter::nees(&e, &p).unwrap_or(f64::NAN));
        let p_rr = p.fixed_view::<3, 3>(6, 6).into_owned();
        run.position_nees
            .push(crate::filter::nees(&dr, &p_rr).unwrap_or(f64::NAN));
        self.next += 1;
    }

    /// The run with its records' counts and, when smoothed, the smoothed
    /// curves (`smoothed`: the smoothed IMU positions and the IMU sample
    /// of the first).
    fn finish(self, records: &RunRecords, smoothed: Option<(&[Vector3<f64>], usize)>) -> ImuRun {
        let accepted = records
            .measurements
            .iter()
            .filter(|r| r.status == MeasurementStatus::Accepted)
            .count();
        let rejected = records.measurements.len() - accepted;
        let diverged = records.integrity().diverged();
        ImuRun {
            rejected,
            accepted,
            diverged,
            smoothed: smoothed.map(|(s, first)| {
                Box::new(smoothed_curves(
                    self.truth, s, first, self.out, rejected, accepted, diverged,
                ))
            }),
            ..self.run
        }
    }
}

/// The forward filter's records, and its smoothed IMU positions with
/// `smooth`.
fn forward_and_smoothed<const N: usize, E: Aiding, O>(
    imu: &ImuData,
    epochs: &[E],
    initial: &InitialState,
    tuning: &FilterTuning,
    smooth: bool,
    observe: O,
) -> Result<(RunRecords, Option<Vec<Vector3<f64>>>)>
where
    O: FnMut(usize, &FilterState<N>),
{
    if smooth {
        let (records, smoothed) = coupling::run_smoothed(imu, epochs, initial, tuning, observe)?;
        Ok((records, Some(smoothed)))
    } else {
        Ok((coupling::run(imu, epochs, initial, tuning, observe)?, None))
    }
}

/// The position error curves of smoothed IMU positions at the output
/// epochs (the first is IMU sample `first`).
fn smoothed_curves(
    truth: &Trajectory,
    smoothed_position_ecef: &[Vector3<f64>],
    first: usize,
    out: &[usize],
    rejected: usize,
    accepted: usize,
    diverged: bool,
) -> ImuRun {
    let mut run = ImuRun {
        position_error: Vec::with_capacity(out.len()),
        horizontal_error: Vec::with_capacity(out.len()),
        vertical_error: Vec::with_capacity(out.len()),
        nees: vec![f64::NAN; out.len()],
        position_nees: vec![f64::NAN; out.len()],
        rejected,
        accepted,
        diverged,
        smoothed: None,
    };
    for &k in out {
        let t = truth.nav_state(k);
        let error = smoothed_position_ecef[k - first] - t.position_ecef;
        let (horizontal, vertical) = horizontal_vertical(&t.position_ecef, &error);
        run.position_error.push(error.norm());
        run.horizontal_error.push(horizontal);
        run.vertical_error.push(vertical);
    }
    run
}

/// Horizontal and vertical (|down|) parts of an ECEF error `dr` in the
/// local NED frame of the true position, m.
fn horizontal_vertical(position_ecef: &Vector3<f64>, dr: &Vector3<f64>) -> (f64, f64) {
    let geo = ecef_to_geodetic(position_ecef);
    let ned = c_n_e(geo.latitude_rad, geo.longitude_rad).transpose() * dr;
    (ned.x.hypot(ned.y), ned.z.abs())
}
