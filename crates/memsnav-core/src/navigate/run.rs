//! The run of a log: IMU into body axes and onto GNSS time, the start,
//! the scheduled outages, the coupled filter with the aids at every IMU
//! sample, and the solution.

use nalgebra::{Matrix3, Vector3};

use super::adapt::{typical_position_std_m, Adaptation, PassModel, Plan};
use super::aids::{HeadingUntilAligned, SampleAids};
use super::align::{find_start, GnssKinematics, Start};
use super::carrier_use::CarrierUse;
use super::config::{periodic_outages, LogConfig};
use super::gyro_scale::{gyro_scale, GyroScale};
use super::kinematics::EpochKinematics;
use crate::coupling::{
    self, Aiding, FilterState, FilterTuning, PositionFix, RangeBiasModel, SampleAid, Solution,
};
use crate::filter::state::{RangeBiasSlots, SizedJob, StateBlocks, POSITION, VELOCITY};
use crate::geodesy::ecef_to_geodetic;
use crate::gnss::{keep_highest, GnssEpoch};
use crate::ins::ImuData;
use crate::ins::ImuSample;
use crate::logs::{MAX_SPEED_M_S, MAX_STD, POS_HEIGHT_RANGE_M};
use crate::{validate, Error, Result};

/// The GNSS side of a log.
#[derive(Debug, Clone, PartialEq)]
pub enum GnssInput {
    /// Position (and velocity) fixes of the antenna: loose coupling.
    Fixes(Vec<PositionFix>),
    /// Pseudoranges (and rates): tight coupling.
    Measurements(Vec<GnssEpoch>),
}

/// What a log run produced.
#[derive(Debug, Clone, PartialEq)]
pub struct LogRun {
    /// The filter's solution at every IMU sample from the start, at the IMU.
    pub solution: Solution,
    /// Its fixed-interval smoothed solution, when asked for
    /// ([`LogConfig::smoother`]).
    pub smoothed: Option<Solution>,
    /// Where and how it started.
    pub start: Start,
    /// When it started late ([`super::align::LATE_START_S`] after the
    /// earliest the log allowed): where and why, in words (also among the
    /// solution's warnings).
    pub late_start: Option<String>,
    /// Every GNSS epoch's antenna position and velocity (the fixes, or the
    /// least-squares fixes of the pseudoranges: the single-point solution).
    pub gnss: Vec<GnssKinematics>,
    /// Whether each GNSS epoch reached the filter (inside the run, outside
    /// the outages).
    pub gnss_used: Vec<bool>,
    /// The outage windows, absolute (start, end) times, s (configured s
    /// after [`Start::earliest_time_s`]).
    pub outages: Vec<(f64, f64)>,
    /// The standstills the run detected, (start, end) times, s.
    pub standstills: Vec<(f64, f64)>,
    /// The satellites holding range-bias slots at the end, with their bias
    /// estimates, m.
    pub range_biases: Vec<(u16, f64)>,
    /// The antenna lever arm (IMU to antenna, body axes), m: the
    /// configured one, or with installation states the final estimate
    /// (the outputs at the antenna use it).
    pub antenna_lever_arm_b_m: Vector3<f64>,
    /// The sensor-to-body rotation the run used (body = M · sensor).
    pub mounting: Matrix3<f64>,
    /// What the run learnt from the log before the run reported
    /// ([`super::adapt`]): the IMU model chosen, the fixes' correlation
    /// time.
    pub adaptation: Adaptation,
    /// The tuning the reported run used.
    pub tuning: FilterTuning,
    /// Why the run stopped before the end of the log, when it did: the
    /// solution (and its records) then end at the last sample before it,
    /// and there is no smoothed solution.
    pub failure: Option<RunFailure>,
    /// The gyro's turns against the GNSS course's over the whole log
    /// ([`super::gyro_scale`]); None without a usable pair of epochs.
    pub gyro_scale: Option<GyroScale>,
    /// The carrier changes by fate, when the run used carrier phase
    /// (`gnss.carrier_phase`); with none used, a warning among the
    /// solution's says why.
    pub carrier_use: Option<CarrierUse>,
}

/// Why and when a run stopped before the end of its log.
#[derive(Debug, Clone, PartialEq)]
pub struct RunFailure {
    /// When, GNSS time, s: the filter's error's time, or that of the first
    /// IMU sample the solution does not hold.
    pub time_s: f64,
    /// What went wrong (the error's message).
    pub message: String,
}

/// Runs a log: `time_s` the IMU time stamps on GNSS time (before the
/// configured offset), `specific_force_s` and `angular_rate_s` in sensor
/// axes (SI).
pub fn navigate_log(
    time_s: &[f64],
    specific_force_s: &[Vector3<f64>],
    angular_rate_s: &[Vector3<f64>],
    gnss: &GnssInput,
    config: &LogConfig,
) -> Result<LogRun> {
    config.validate()?;
    let raw = ImuData {
        time_s,
        specific_force_b: specific_force_s,
        angular_rate_b: angular_rate_s,
        increments: None,
    };
    raw.validate()?;
    validate_gnss(gnss)?;
    let time: Vec<f64> = time_s
        .iter()
        .map(|t| t + config.imu_time_offset_s)
        .collect();
    validate::epochs_in_imu_span("gnss", &gnss_times(gnss), &time, 0.0)?;
    let imu_b: Vec<ImuSample> = specific_force_s
        .iter()
        .zip(angular_rate_s)
        .map(|(f, w)| ImuSample {
            specific_force_b: config.mounting * f,
            angular_rate_b: config.mounting * w,
        })
        .collect();
    let tight = matches!(gnss, GnssInput::Measurements(_));
    let range_biases = config.range_bias_states != RangeBiasSlots::None && tight;
    // With range-bias states the pseudorange errors the fixes see include
    // the biases: their covariance (the start's position uncertainty) must.
    let bias_std_m = if range_biases {
        config.tuning.initial_std.range_bias_m
    } else {
        0.0
    };
    let kinematics = match gnss {
        GnssInput::Fixes(fixes) => EpochKinematics::kinematics(fixes, bias_std_m),
        GnssInput::Measurements(epochs) => EpochKinematics::kinematics(epochs, bias_std_m),
    };
    // Before the run: a gyro read in the wrong unit is what a failed run
    // most needs to be told, so its warning also rides on any error below.
    let gyro = gyro_scale(&time, &imu_b, &kinematics);
    let gyro_warning = gyro.and_then(|g| g.unit_warning());
    let mut run = run_from_start(&time, &imu_b, gnss, kinematics, config)
        .map_err(|e| with_note(e, gyro_warning.as_deref()))?;
    run.gyro_scale = gyro;
    if let Some(w) = gyro_warning {
        run.solution.warnings.insert(0, w);
    }
    Ok(run)
}

/// An error with `note` added to its reason (None: as it is).
fn with_note(error: Error, note: Option<&str>) -> Error {
    let Some(note) = note else {
        return error;
    };
    match error {
        Error::InvalidArgument { argument, reason } => Error::InvalidArgument {
            argument,
            reason: format!("{reason} ({note})"),
        },
        Error::Divergence { time_s, reason } => Error::Divergence {
            time_s,
            reason: format!("{reason} ({note})"),
        },
        other => other,
    }
}

/// [`navigate_log`] from the GNSS epochs' kinematics on: the start, the
/// outages, the filter.
fn run_from_start(
    time: &[f64],
    imu_b: &[ImuSample],
    gnss: &GnssInput,
    kinematics: Vec<GnssKinematics>,
    config: &LogConfig,
) -> Result<LogRun> {
    let tight = matches!(gnss, GnssInput::Measurements(_));
    let start = find_start(time, imu_b, &kinematics, config)?;
    let t_end = match config.duration_s {
        Some(d) => (start.time_s + d).min(time[time.len() - 1]),
        None => time[time.len() - 1],
    };
    let k0 = start.first_sample;
    let k1 = time.partition_point(|t| *t <= t_end);
    if k1 < k0 + 2 {
        return Err(Error::invalid(
            "duration_s",
            "leaves fewer than two IMU samples after the start",
        ));
    }
    let late_start = start.delay.map(|delay| {
        format!(
            "the run starts {:.1} s after the log's first GNSS epoch and {:.1} s after its first IMU sample ({} start at t = {:.3} s): {}",
            start.time_s - start.first_gnss_time_s,
            start.time_s - start.first_imu_time_s,
            start.kind.name(),
            start.time_s,
            delay.reason(config)
        )
    });
    let outages = outage_windows(config, &start, t_end, late_start.as_deref())?;
    let partial = config.outage_satellites;
    if partial > 0 && !matches!(gnss, GnssInput::Measurements(_)) {
        return Err(Error::invalid(
            "outages.keep_satellites",
            "partial outages keep satellites: they need pseudoranges (gnss.mode = \"tight\")",
        ));
    }
    let in_outage = |t: f64| outages.iter().any(|&(a, b)| t >= a && t < b);
    let in_run = |t: f64| t >= time[k0] && t <= time[k1 - 1] && (partial > 0 || !in_outage(t));
    let gnss_used: Vec<bool> = kinematics.iter().map(|g| in_run(g.time_s)).collect();
    // A partial outage: the epochs inside keep their `partial` highest
    // satellites and, with fewer than four, have no single-point fix.
    let thinned: Vec<bool> = kinematics
        .iter()
        .map(|g| partial > 0 && in_outage(g.time_s))
        .collect();
    let mut kinematics = kinematics;
    for (g, _) in kinematics.iter_mut().zip(&thinned).filter(|(_, &t)| t) {
        *g = GnssKinematics::none(g.time_s);
    }
    let run = Inputs {
        time: &time[k0..k1],
        imu_b: &imu_b[k0..k1],
        gnss,
        kinematics: &kinematics,
        used: &gnss_used,
        thinned: &thinned,
        start: &start,
        config,
    };
    // The range-bias slots carry the pseudorange biases (tight) or the
    // fixes' position errors (loose).
    let layout = |fix_error: Option<RangeBiasModel>| {
        // Galileo or BeiDou pseudoranges: one clock plus their inter-system biases.
        let inter_system_biases = match gnss {
            GnssInput::Measurements(epochs) => GnssEpoch::needs_inter_system_biases(epochs),
            GnssInput::Fixes(_) => false,
        };
        config.state_blocks(tight, inter_system_biases, fix_error.is_some())
    };
    // What the log itself says about the IMU, the vehicle and the fixes
    // (first passes), then the run that is reported.
    let fixed = [(String::new(), config.tuning)];
    let fix_error = (config.fix_error_states && !tight).then_some(config.fix_error);
    let plan = Plan {
        candidates: if config.imu_candidates.is_empty() {
            &fixed
        } else {
            &config.imu_candidates
        },
        nhc_std_m_s: config.aids.nhc_std_m_s,
        fix_error,
        learn_nhc_std: config.aids.nhc && config.aids.nhc_std_learnt,
        // Only white fixes learn: states or an inflation of the user's own
        // already model the correlation.
        fix_typical_std_m: match gnss {
            GnssInput::Fixes(fixes)
                if config.learn_fix_errors
                    && fix_error.is_none()
                    && config.tuning.fix_correlation_time_s == 0.0 =>
            {
                typical_position_std_m(fixes, &gnss_used)
            }
            _ => None,
        },
    };
    let (model, adaptation) = plan.learn(&|model: &PassModel| {
        let (solution, _, _, _) =
            run.filter(layout(model.fix_error), model, Record::MeasurementsOnly)?;
        Ok((solution.measurements, solution.resets.len()))
    })?;
    let record = if config.smoother {
        Record::Smoothed
    } else {
        Record::Solution
    };
    let (mut solution, smoothed, range_biases, failure) =
        run.filter(layout(model.fix_error), &model, record)?;
    let tuning = model.tuning;
    solution.warnings.extend(late_start.clone());
    let carrier_use = tuning
        .use_carrier_phase
        .then(|| CarrierUse::of(&solution.measurements));
    solution
        .warnings
        .extend(carrier_use.and_then(|u| u.warning()));
    let standstills = standstill_intervals(&solution);
    // With installation states, the lever arm the filter ended with.
    let antenna_lever_arm_b_m = solution
        .installation
        .last()
        .map_or(tuning.antenna_lever_arm_b_m, |row| {
            Vector3::new(row[0], row[1], row[2])
        });
    Ok(LogRun {
        solution,
        smoothed,
        start,
        late_start,
        gnss: kinematics,
        gnss_used,
        outages,
        standstills,
        range_biases,
        antenna_lever_arm_b_m,
        mounting: config.mounting,
        adaptation,
        tuning,
        failure,
        gyro_scale: None,
        carrier_use,
    })
}

/// The scheduled outage windows, absolute (start, end) times, s: the
/// configured ones, s after the earliest start the log allows
/// ([`Start::earliest_time_s`]: the log's own time, whatever the alignment
/// decides), each inside the run from `start` to `t_end` or an error naming
/// it (and the late start's words, `late`, when that is why); and the
/// periodic ones that fit in the run.
fn outage_windows(
    config: &LogConfig,
    start: &Start,
    t_end: f64,
    late: Option<&str>,
) -> Result<Vec<(f64, f64)>> {
    let anchor = start.earliest_time_s;
    let (run_from, run_to) = (start.time_s - anchor, t_end - anchor);
    let mut windows = Vec::new();
    for (i, &(s, l)) in config.outages.iter().enumerate() {
        if s < run_from || s + l > run_to {
            return Err(Error::invalid(
                "outages.windows_s",
                format!(
                    "window {} [{s:?}, {l:?}] (start and length, s after the log's first GNSS epoch with standstill.window_s of IMU data before it) is not inside the run, which spans {run_from:.3} to {run_to:.3} s after that epoch{}",
                    i + 1,
                    late.map_or(String::new(), |words| format!("; {words}"))
                ),
            ));
        }
        windows.push((anchor + s, anchor + s + l));
    }
    if let Some((first, length, every)) = config.periodic_outages {
        windows.extend(
            periodic_outages(first, length, every, run_to)?
                .into_iter()
                .filter(|&(s, _)| s >= run_from)
                .map(|(s, l)| (anchor + s, anchor + s + l)),
        );
    }
    Ok(windows)
}

/// The standstills as intervals: runs of accepted or rejected ZUPTs.
fn standstill_intervals(solution: &Solution) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    let gap = 1.0;
    for m in solution
        .measurements
        .iter()
        .filter(|m| m.kind == coupling::MeasurementKind::ZeroVelocity && m.id == 0)
    {
        match out.last_mut() {
            Some(last) if m.time_s - last.1 <= gap => last.1 = m.time_s,
            _ => out.push((m.time_s, m.time_s)),
        }
    }
    out
}

/// What a filter run gives: the solution, the smoothed one when asked
/// for, the final range biases (satellite, m), and why it stopped early
/// when it did.
type FilterOutput = (
    Solution,
    Option<Solution>,
    Vec<(u16, f64)>,
    Option<RunFailure>,
);

/// The pieces of one run.
struct Inputs<'a> {
    time: &'a [f64],
    imu_b: &'a [ImuSample],
    gnss: &'a GnssInput,
    kinematics: &'a [GnssKinematics],
    used: &'a [bool],
    /// Epochs of a partial outage (see [`LogConfig::outage_satellites`]).
    thinned: &'a [bool],
    start: &'a Start,
    config: &'a LogConfig,
}

/// What a filter run keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Record {
    /// Only the measurement records (a first pass of [`super::adapt`]).
    MeasurementsOnly,
    /// The solution at every IMU sample.
    Solution,
    /// The solution and its fixed-interval smoothed counterpart.
    Smoothed,
}

impl Inputs<'_> {
    /// Runs the filter with the state `blocks` and `model`, keeping what
    /// `record` asks for.
    fn filter(
        &self,
        blocks: StateBlocks,
        model: &PassModel,
        record: Record,
    ) -> Result<FilterOutput> {
        blocks.dispatch(FilterPass {
            inputs: self,
            model,
            record,
        })
    }

    /// [`Self::filter`] with `N` states.
    fn filter_sized<const N: usize>(
        &self,
        model: &PassModel,
        record: Record,
    ) -> Result<FilterOutput> {
        let f: Vec<Vector3<f64>> = self.imu_b.iter().map(|s| s.specific_force_b).collect();
        let w: Vec<Vector3<f64>> = self.imu_b.iter().map(|s| s.angular_rate_b).collect();
        let data = ImuData {
            time_s: self.time,
            specific_force_b: &f,
            angular_rate_b: &w,
            increments: None,
        };
        let s = self.start;
        let mut tuning = model.tuning;
        if let Some(fix_error) = &model.fix_error {
            tuning.set_range_bias_model(fix_error);
        }
        let i = &mut tuning.initial_std;
        let o = &self.config.alignment_overrides;
        i.position_m = o.position_std_m.unwrap_or(s.position_std_m);
        i.velocity_m_s = o.velocity_std_m_s.unwrap_or(s.velocity_std_m_s);
        i.attitude_ned_rad = Vector3::new(s.tilt_std_rad, s.tilt_std_rad, s.heading_std_rad);
        let initial = s.initial_state(&tuning.antenna_lever_arm_b_m);
        let keep_solution = record != Record::MeasurementsOnly;
        let capacity = if keep_solution { self.time.len() } else { 0 };
        let heading = HeadingUntilAligned {
            known: s.heading_known,
            heading_std_rad: s.heading_std_rad,
            tilt_std_rad: s.tilt_std_rad,
        };
        let mut hook = Aids {
            aids: SampleAids::new(
                self.time,
                self.imu_b,
                self.kinematics,
                self.used,
                self.config,
                heading,
                model.nhc_std_m_s,
            ),
            solution: Solution::with_capacity(capacity, N),
            keep_solution,
        };
        let smooth = record == Record::Smoothed;
        let (mut state, stopped): (FilterState<N>, _) = match self.gnss {
            GnssInput::Fixes(fixes) => {
                let used: Vec<PositionFix> = fixes
                    .iter()
                    .zip(self.used)
                    .filter_map(|(f, &u)| u.then_some(*f))
                    .collect();
                coupling::run_until_error(&data, &used, &initial, &tuning, smooth, &mut hook)?
            }
            GnssInput::Measurements(epochs) => {
                let receiver = s.antenna.position_ecef;
                let keep = self.config.outage_satellites;
                let used: Vec<GnssEpoch> = epochs
                    .iter()
                    .zip(self.used.iter().zip(self.thinned))
                    .filter(|(_, (&u, _))| u)
                    .map(|(e, (_, &thin))| {
                        let mut e = e.clone();
                        if thin {
                            keep_highest(&mut e, &receiver, keep);
                        }
                        e
                    })
                    .collect();
                coupling::run_until_error(&data, &used, &initial, &tuning, smooth, &mut hook)?
            }
        };
        let mut solution = hook.solution;
        let failure = match stopped {
            // A first pass learns from a whole run or fails; fewer than
            // two samples are no solution to keep.
            Some(e) if !keep_solution || solution.time_s.len() < 2 => return Err(e),
            Some(e) => Some(RunFailure {
                time_s: match &e {
                    Error::Divergence { time_s, .. } => *time_s,
                    _ => self.time[solution.time_s.len().min(self.time.len() - 1)],
                },
                message: e.to_string(),
            }),
            None => None,
        };
        solution.take_records(&mut state);
        if !keep_solution {
            return Ok((solution, None, Vec::new(), None));
        }
        coupling::diagnose(&mut solution, ("specific_force", &f), ("angular_rate", &w));
        // A stopped run is not smoothed: its last samples are the ones
        // that went wrong.
        let mut smoothed = match failure {
            None => state
                .kf
                .take_smoother()
                .map(|mut log| solution.smoothed(&mut log))
                .transpose()?,
            Some(_) => None,
        };
        solution.shift_onto_gnss_time();
        if let Some(s) = smoothed.as_mut() {
            s.shift_onto_gnss_time();
        }
        Ok((solution, smoothed, state.range_biases().collect(), failure))
    }
}

/// One filter pass of [`Inputs::filter`], at the state size its blocks give.
struct FilterPass<'a> {
    inputs: &'a Inputs<'a>,
    model: &'a PassModel,
    record: Record,
}

impl SizedJob for FilterPass<'_> {
    type Output = Result<FilterOutput>;

    fn run<const N: usize>(self) -> Self::Output {
        self.inputs.filter_sized::<N>(self.model, self.record)
    }
}

/// The aids at every IMU sample ([`SampleAids`]), then the solution
/// record.
struct Aids<'a> {
    aids: SampleAids<'a>,
    solution: Solution,
    /// Whether the solution is recorded at every sample.
    keep_solution: bool,
}

impl<const N: usize> coupling::SampleHook<N> for Aids<'_> {
    fn at_sample(&mut self, k: usize, state: &mut FilterState<N>) -> Result<()> {
        // The reported run stops where no solution file can follow it; a
        // first pass only learns from the measurements.
        if self.keep_solution {
            if let Some(reason) = unrepresentable(state) {
                return Err(Error::Divergence {
                    time_s: self.aids.time_s(k),
                    reason,
                });
            }
        }
        self.aids.at_sample(k, state)?;
        if self.keep_solution {
            self.solution.push(self.aids.time_s(k), state);
        }
        Ok(())
    }
}

/// Why a state is beyond what a solution file can hold, and so beyond
/// anything a log's vehicle does (None when it is not): a height outside
/// the `.pos` range ([`POS_HEIGHT_RANGE_M`], −10 km to 10 000 km), a speed
/// above [`MAX_SPEED_M_S`] (10 km/s), a position or velocity σ above
/// [`MAX_STD`] (10 000 km), anything not finite. The run stops at the
/// first such sample: the solution up to it is what was computed before
/// the filter was lost, and every writer takes it.
fn unrepresentable<const N: usize>(state: &FilterState<N>) -> Option<String> {
    let height_m = ecef_to_geodetic(&state.nav.position_ecef).height_m;
    let speed_m_s = state.nav.velocity_ecef.norm();
    // The largest σ of a block (NaN when any variance is).
    let largest_std = |first: usize| {
        (0..3)
            .map(|i| state.kf.p[(first + i, first + i)])
            .fold(0.0_f64, |a, v| if v.is_nan() { f64::NAN } else { a.max(v) })
            .sqrt()
    };
    let (std_m, std_m_s) = (largest_std(POSITION), largest_std(VELOCITY));
    let (low, high) = (*POS_HEIGHT_RANGE_M.start(), *POS_HEIGHT_RANGE_M.end());
    let reason = if !POS_HEIGHT_RANGE_M.contains(&height_m) {
        format!("height {height_m:.0} m (a solution holds {low:e} to {high:e} m)")
    } else if !(0.0..=MAX_SPEED_M_S).contains(&speed_m_s) {
        format!("speed {speed_m_s:.0} m/s (a solution holds up to {MAX_SPEED_M_S:e} m/s)")
    } else if !((0.0..=MAX_STD).contains(&std_m) && (0.0..=MAX_STD).contains(&std_m_s)) {
        format!(
            "one-sigma {std_m:.3e} m in position, {std_m_s:.3e} m/s in velocity (a solution \
             holds up to {MAX_STD:e})"
        )
    } else {
        return None;
    };
    Some(format!(
        "the state left the range of a navigation solution: {reason}"
    ))
}

/// The mean sample rate of increasing times, Hz (the IMU's, for its tuning).
pub fn sample_rate_hz(time_s: &[f64]) -> Result<f64> {
    if time_s.len() < 2 {
        return Err(Error::invalid("time", "needs at least two samples"));
    }
    validate::increasing_times("time", time_s)?;
    Ok((time_s.len() - 1) as f64 / (time_s[time_s.len() - 1] - time_s[0]))
}

/// Checks that the GNSS series is usable before a run: times finite and
/// increasing (the filter checks the rest).
pub fn validate_gnss(gnss: &GnssInput) -> Result<()> {
    let times = gnss_times(gnss);
    if times.is_empty() {
        return Err(Error::invalid("gnss", "has no epochs"));
    }
    validate::increasing_times("gnss.time", &times)
}

/// The GNSS epochs' times, s.
fn gnss_times(gnss: &GnssInput) -> Vec<f64> {
    match gnss {
        GnssInput::Fixes(f) => f.iter().map(|x| x.time_s).collect(),
        GnssInput::Measurements(e) => e.iter().map(|x| x.time_s).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::navigate::SettingValue;
    use crate::trajectory::{RandomTrajectoryConfig, Trajectory};

    /// A drive from rest with exact IMU readings and 1 Hz fixes, GNSS out
    /// from 40 s to 140 s after the start (of 150 s); from 50 s the accelerometer's z axis
    /// reads `fault_m_s2` too much (a failed sensor). Returns the run and
    /// the time of the fault.
    fn falling(fault_m_s2: f64) -> (Result<LogRun>, f64) {
        let config = RandomTrajectoryConfig {
            duration_s: 150.0,
            stationary_start_s: 20.0,
            ..Default::default()
        };
        let truth = Trajectory::random(&config, &mut crate::random::stream(4, 0)).unwrap();
        let fault = truth.time_s[0] + 50.0;
        let f: Vec<Vector3<f64>> = truth
            .time_s
            .iter()
            .zip(&truth.specific_force_b)
            .map(|(&t, f)| f + Vector3::new(0.0, 0.0, if t >= fault { fault_m_s2 } else { 0.0 }))
            .collect();
        let fixes: Vec<PositionFix> = (0..truth.time_s.len())
            .step_by(100)
            .map(|k| PositionFix {
                time_s: truth.time_s[k],
                position_ecef: truth.position_ecef[k],
                position_covariance: Matrix3::identity() * 0.25,
                velocity_ecef: Some(truth.velocity_ecef[k]),
                velocity_covariance: Matrix3::identity() * 0.0025,
                velocity_horizontal_only: false,
            })
            .collect();
        let window = SettingValue::List(vec![
            SettingValue::Number(40.0),
            SettingValue::Number(100.0),
        ]);
        let tables = vec![(
            "outages".to_string(),
            vec![("windows_s".to_string(), SettingValue::List(vec![window]))],
        )];
        let log_config = LogConfig::from_settings(&tables, 100.0).unwrap();
        let run = navigate_log(
            &truth.time_s,
            &f,
            &truth.angular_rate_b,
            &GnssInput::Fixes(fixes),
            &log_config,
        );
        (run, fault)
    }

    /// 60 m/s² of fall from the fault: the coasting solution passes 10 km
    /// below the ellipsoid within 20 s (½ a t² = 10 km at t = 18 s); the
    /// run stops at that sample and keeps every sample before it, each
    /// one a solution file holds.
    #[test]
    fn a_state_beyond_a_solution_stops_the_run_and_keeps_the_samples_before() {
        let (run, fault) = falling(60.0);
        let run = run.unwrap();
        let failure = run.failure.clone().expect("the run stops");
        assert!(
            failure.time_s > fault && failure.time_s < fault + 20.0,
            "{failure:?}"
        );
        assert!(failure.message.contains("height"), "{failure:?}");
        let local = run.local_solution();
        assert!(*local.time_s.last().unwrap() < failure.time_s);
        assert!(local.time_s.len() > 6000);
        assert!(run.smoothed.is_none());
        for format in crate::output::SolutionFormat::ALL {
            crate::output::format_solution(&local, format, None, "x").unwrap();
        }
        // Without the fault the same run goes to the end.
        let (clean, _) = falling(0.0);
        let clean = clean.unwrap();
        assert!(clean.failure.is_none());
        assert!(clean.solution.time_s.len() > local.time_s.len());
    }
}
