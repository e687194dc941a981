//! Navigation Monte Carlo (paper §5.3, figures 14-18; method §5-6): the
//! coupled GNSS/INS filter on the same random trajectories and GNSS
//! measurements with several IMUs, position error norm and NEES vs time.
//! One job per file:
//! - `run`: the draws of one run, shared by its IMUs and filters;
//! - `imus`: the IMUs — drawn, fixed, or calibrated and inverted;
//! - `filters`: one IMU's coupled filter and its error curves;
//! - `outcome`: the statistics kept over the runs;
//! - [`partial_outage`]: the partial-outage study (0-3 satellites through a
//!   window, tight against loose coupling) on the same machinery;
//! - [`outage_study`]: the runs of the outage study (grades × outage
//!   lengths × satellites kept), cell by cell.
//!
//! ## One run (reproducible from `(seed, run index)`)
//!
//! Draw order from `random::stream(seed, i)` (`run::draw_run`): the
//! random land-vehicle trajectory ([`crate::trajectory::Trajectory::random`], 100 Hz truth),
//! its GNSS measurements ([`crate::gnss::simulate`]: Walker constellation, 6
//! satellites, 3 m / 0.1 m/s white noise, a TCXO clock, carrier phase when
//! configured; an outage keeps
//! its `n_satellites` highest satellites, see [`crate::gnss::simulate`]), the
//! initial attitude error (1° tilt, 5° heading by default), the initial
//! position and velocity errors when the initial state is given, and a
//! seed from which IMU j draws its own stream `random::stream(imu_seed, j)`.
//! Trajectory, GNSS and initial errors are thus *shared by every IMU of a
//! run* (a paired comparison), and an IMU's draws do not depend on the
//! other IMUs.
//!
//! Per IMU: errors drawn from its spec ([`NavigationImu::Drawn`]) or a
//! fixed model ([`NavigationImu::Fixed`]), readings of the trajectory's
//! exact specific force and angular rate, filter tuning from the spec
//! ([`FilterTuning::from_imu_spec`], 17 states: the deterministic errors the
//! state lacks are absorbed as initial bias uncertainty and noise shaped
//! by the sensed motion). The filter starts from the
//! least-squares fix of the first GNSS epoch (4 satellites needed there),
//! or from a given state: the truth plus drawn position and velocity errors
//! ([`InitialStateSource::Given`]), which lets a run track fewer than 4
//! satellites from the start.
//!
//! [`NavigationImu::Calibrated`] is the paper's "calibrated MEMS": the
//! *same* sensor and the *same* readings as its source IMU, passed through
//! calibration and inversion ([`super::calibrate_invert`]) with a
//! calibration done at t = 0 on its own segment of
//! `calibration_duration_s` of land-vehicle motion with GNSS-like reference
//! noise. The filter is then tuned from the calibration's own parameter
//! uncertainties and the sensor's noise, so it trusts the calibrated model
//! as much as the calibration warrants.
//!
//! ## Outputs
//!
//! At every whole second of the trajectory (1 Hz, the GNSS epochs; during
//! an outage the same grid): the position error norm |r̂ − r|, m, and the
//! NEES of (ψ, δv, δr) against the filter's 9 × 9 covariance block (ψ from
//! Ĉ Cᵀ = I + [ψ×], method §5). Per IMU they are folded in run order into
//! per-epoch statistics ([`CurveStats`]) and per-run scalars; the per-run
//! curves are kept only when asked (`keep_runs`).
//!
//! [`CurveStats`]: crate::montecarlo::CurveStats
//! [`FilterTuning::from_imu_spec`]: crate::coupling::FilterTuning::from_imu_spec

mod filters;
mod imus;
pub mod outage_study;
mod outcome;
pub mod partial_outage;
mod run;

use nalgebra::Vector3;

use crate::calibration::Method;
use crate::coupling::InitialUncertainty;
use crate::gnss::{Constellation, GnssSystem, Outage, SimulationConfig, WalkerConfig};
use crate::montecarlo::{self, FoldSummary, MonteCarlo, RunOptions};
use crate::trajectory::RandomTrajectoryConfig;
use crate::{validate, Error, Result};

use super::calibrate_invert::SegmentCalibration;

pub use filters::{Coupling, NEES_DOF};
pub use imus::{paper_imus, NavigationImu};
pub use outcome::{ImuOutcome, OutcomeFold};

pub use filters::ImuRun;
use filters::{navigate, position_fixes, FilterSetup};

/// Default length of the calibration segment before the run, s.
pub const DEFAULT_CALIBRATION_DURATION_S: f64 = 300.0;
/// Default early window of the summaries ("calibration helps most in the
/// first ~150 s", method §6), s.
pub const DEFAULT_EARLY_WINDOW_S: f64 = 150.0;

/// Where the filters' initial position, velocity and clock come from.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum InitialStateSource {
    /// The least-squares fix of the first GNSS epoch (4 satellites needed).
    #[default]
    FirstFix,
    /// Given: the truth plus a draw of these one-sigma errors per ECEF axis
    /// (also the filters' P₀); the clock comes from the first epoch's
    /// pseudorange residuals, so one satellite is enough.
    Given {
        /// One-sigma position error per ECEF axis, m.
        position_std_m: f64,
        /// One-sigma velocity error per ECEF axis, m/s.
        velocity_std_m_s: f64,
    },
}

/// What [`navigation_experiment`] runs.
#[derive(Debug, Clone, PartialEq)]
pub struct NavigationExperimentConfig {
    /// Monte Carlo runs (paper: 200).
    pub runs: usize,
    /// Base seed; run i draws from `random::stream(seed, i)`.
    pub seed: u64,
    /// Length of each run, s (paper: 600); overrides `trajectory.duration_s`.
    pub duration_s: f64,
    /// The IMUs by name (paper: ins, mems, calibrated_mems).
    pub imus: Vec<(String, NavigationImu)>,
    /// Satellites tracked (paper: 6); overrides `gnss.n_satellites`. Fewer
    /// than 4 needs a given initial state.
    pub n_satellites: usize,
    /// An outage window (paper: 30 s with no satellite), added to
    /// `gnss.outages`: `n_satellites` 0 is total, 1-3 partial (the highest
    /// satellites are kept, [`crate::gnss::simulate`]).
    pub outage: Option<Outage>,
    /// How the IMUs are coupled with GNSS (default tight, the paper's).
    pub coupling: Coupling,
    /// Where the filters start (default: the first epoch's fix).
    pub initial_state: InitialStateSource,
    /// Random trajectory settings (default: Toulouse, 100 Hz, land vehicle).
    pub trajectory: RandomTrajectoryConfig,
    /// GNSS simulation settings (default: 1 Hz, 3 m, 0.1 m/s, TCXO clock, no
    /// carrier phase). With `gnss.carrier_phase_std_m` > 0 the epochs carry
    /// carrier phase (slipping silently with `gnss.cycle_slip_probability`)
    /// and the tightly coupled filters use its changes between epochs
    /// (time-differenced carrier phase, `coupling/carrier.rs`); 0 leaves
    /// every draw and result as they were (the simulator draws the carrier
    /// from a side stream).
    pub gnss: SimulationConfig,
    /// The constellation (default: 24 satellites, 6 planes, 55°, no file
    /// needed; a broadcast file would tie the runs to its validity window).
    pub constellation: WalkerConfig,
    /// The satellite systems simulated (default GPS alone): GPS from
    /// `constellation`, Galileo, BeiDou and GLONASS from their nominal
    /// Walker patterns ([`WalkerConfig::nominal`]). With a system other
    /// than GPS every filter carries the three inter-system-bias states, and the
    /// pseudoranges `gnss.inter_system_bias_m`. The least-squares fixes
    /// (the first-fix start, loose coupling) have one clock for all
    /// systems: non-zero biases bias them.
    pub systems: Vec<GnssSystem>,
    /// Length of the calibration segment of calibrated IMUs, s.
    pub calibration_duration_s: f64,
    /// Reference specific-force noise of that calibration, per sample, m/s².
    pub reference_specific_force_std: f64,
    /// Its reference angular-rate noise, per sample, rad/s.
    pub reference_angular_rate_std: f64,
    /// Early window of [`ImuOutcome::run_rms_early`], s.
    pub early_window_s: f64,
    /// Whether the filters use the pseudorange rates (default true). The
    /// paper's tight coupling names pseudoranges only; with rates (0.1 m/s
    /// at 1 Hz) the velocity is pinned every second and every IMU
    /// converges within ~30 s (see `docs/results/paper-comparison.md`).
    pub use_pseudorange_rate: bool,
    /// One-sigma initial attitude error in NED (north tilt, east tilt,
    /// heading), rad: each run draws the initial attitude error from it
    /// and every filter's P₀ attitude block is set to it (default 1°, 1°,
    /// 5°, [`InitialUncertainty::default`]).
    pub initial_attitude_std_rad: Vector3<f64>,
    /// Whether every filter carries the accelerometer and gyro scale-factor
    /// states (23 instead of 17, seeded from each IMU's scale-factor spec);
    /// misalignment, nonlinearity and g-sensitivity stay absorbed as noise.
    pub scale_factor_states: bool,
    /// Whether every filter's tuning absorbs the deterministic errors its
    /// state lacks (scale factor unless `scale_factor_states`,
    /// misalignment, nonlinearity, g-sensitivity) as inflated initial bias
    /// uncertainty and noise shaped by the sensed motion
    /// ([`crate::coupling::FilterTuning::absorb_unmodelled`]; default
    /// true). False tunes from the spec's bias and noise only, as a filter
    /// that ignores those errors would.
    pub absorb_unmodelled: bool,
    /// Also run the fixed-interval (RTS) smoother after each filter and
    /// score its solution ([`ImuOutcome::smoothed`]): what post-processing
    /// gets through the same outage (default false).
    pub smooth: bool,
    /// Keep every run's curves (memory: runs × epochs × 2 per IMU).
    pub keep_runs: bool,
}

impl Default for NavigationExperimentConfig {
    fn default() -> Self {
        let calibration = SegmentCalibration::default();
        Self {
            runs: 20,
            seed: crate::random::DEFAULT_SEED,
            duration_s: 600.0,
            imus: paper_imus(),
            n_satellites: 6,
            outage: None,
            coupling: Coupling::default(),
            initial_state: InitialStateSource::default(),
            trajectory: RandomTrajectoryConfig::default(),
            gnss: SimulationConfig::default(),
            constellation: WalkerConfig::default(),
            systems: vec![GnssSystem::Gps],
            calibration_duration_s: DEFAULT_CALIBRATION_DURATION_S,
            reference_specific_force_std: calibration.reference_specific_force_std,
            reference_angular_rate_std: calibration.reference_angular_rate_std,
            early_window_s: DEFAULT_EARLY_WINDOW_S,
            use_pseudorange_rate: true,
            initial_attitude_std_rad: InitialUncertainty::default().attitude_ned_rad,
            scale_factor_states: false,
            absorb_unmodelled: true,
            smooth: false,
            keep_runs: false,
        }
    }
}

impl NavigationExperimentConfig {
    /// Checks every setting, the derived GNSS and trajectory settings
    /// included, before any run starts; errors name the Python keyword.
    pub fn validate(&self) -> Result<()> {
        if self.runs == 0 {
            return Err(Error::invalid("runs", "must be at least 1"));
        }
        crate::limits::monte_carlo(None, &[("runs", self.runs)])?;
        validate::positive("duration", self.duration_s)?;
        if self.duration_s < 2.0 {
            return Err(Error::invalid(
                "duration",
                format!("must be at least 2 s, got {}", self.duration_s),
            ));
        }
        self.trajectory_config().validate()?;
        imus::validate(&self.imus, self.trajectory.rate_hz)?;
        let minimum = match self.initial_state {
            InitialStateSource::FirstFix => 4,
            InitialStateSource::Given {
                position_std_m,
                velocity_std_m_s,
            } => {
                validate::positive("initial_position_std", position_std_m)?;
                validate::positive("initial_velocity_std", velocity_std_m_s)?;
                1
            }
        };
        if self.n_satellites < minimum {
            return Err(Error::invalid(
                "n_satellites",
                format!(
                    "needs at least {minimum} {}, got {}",
                    if minimum == 4 {
                        "for the initial fix (or give the initial state)"
                    } else {
                        "satellite"
                    },
                    self.n_satellites
                ),
            ));
        }
        if let Some(o) = self.outage {
            validate_outage(&o, self.duration_s)?;
        }
        // The simulated noise is also every filter's measurement std, so
        // zero (a noise-free simulation, which `simulate_gnss` accepts)
        // would make the filters' R singular.
        validate::positive("pseudorange_std", self.gnss.pseudorange_std_m)?;
        validate::positive("pseudorange_rate_std", self.gnss.pseudorange_rate_std_m_s)?;
        self.gnss_config().validate()?;
        self.sky()?;
        self.segment_calibration().validate()?;
        validate::positive("early_window", self.early_window_s)?;
        for v in self.initial_attitude_std_rad.iter() {
            validate::positive("initial_attitude_std", *v)?;
        }
        Ok(())
    }

    /// The trajectory settings of a run.
    fn trajectory_config(&self) -> RandomTrajectoryConfig {
        RandomTrajectoryConfig {
            duration_s: self.duration_s,
            ..self.trajectory.clone()
        }
    }

    /// The GNSS settings of a run: `gnss` with `n_satellites` and the outage.
    fn gnss_config(&self) -> SimulationConfig {
        let mut config = SimulationConfig {
            n_satellites: self.n_satellites,
            ..self.gnss.clone()
        };
        config.outages.extend(self.outage);
        config
    }

    /// The simulated satellites: `constellation` for GPS, the nominal
    /// pattern of each other system.
    fn sky(&self) -> Result<Constellation> {
        let parts: Vec<(GnssSystem, WalkerConfig)> = self
            .systems
            .iter()
            .map(|&s| match s {
                GnssSystem::Gps => (s, self.constellation),
                _ => (s, WalkerConfig::nominal(s)),
            })
            .collect();
        Constellation::walkers(&parts)
    }

    /// The calibration of calibrated IMUs (errors-in-variables).
    fn segment_calibration(&self) -> SegmentCalibration {
        SegmentCalibration {
            duration_s: self.calibration_duration_s,
            reference_specific_force_std: self.reference_specific_force_std,
            reference_angular_rate_std: self.reference_angular_rate_std,
            method: Method::ErrorsInVariables,
        }
    }

    /// What the filters of a run share.
    fn filter_setup<'a>(&self, coupling: Coupling, out: &'a [usize]) -> FilterSetup<'a> {
        FilterSetup {
            rate_hz: self.trajectory.rate_hz,
            receiver_clock: self.gnss.clock,
            coupling,
            use_pseudorange_rate: self.use_pseudorange_rate,
            use_carrier_phase: self.gnss.carrier_phase_std_m > 0.0,
            initial_attitude_std_rad: self.initial_attitude_std_rad,
            given_start_std: match self.initial_state {
                InitialStateSource::FirstFix => None,
                InitialStateSource::Given {
                    position_std_m,
                    velocity_std_m_s,
                } => Some((position_std_m, velocity_std_m_s)),
            },
            scale_factor_states: self.scale_factor_states,
            inter_system_bias_states: self
                .systems
                .iter()
                .any(|s| s.inter_system_bias_index().is_some()),
            absorb_unmodelled: self.absorb_unmodelled,
            smooth: self.smooth,
            out,
            samples: None,
        }
    }

    /// Sample indices of the whole seconds 0, 1, …, ⌊duration⌋.
    fn output_indices(&self) -> Vec<usize> {
        let n = self.duration_s.floor() as usize + 1;
        (0..n)
            .map(|m| (m as f64 * self.trajectory.rate_hz).round() as usize)
            .collect()
    }
}

/// An outage window of a run of `duration_s`: finite, after the first
/// epoch (the filters start there), non-empty, at most 3 satellites
/// (4 or more is no outage for either coupling).
fn validate_outage(o: &Outage, duration_s: f64) -> Result<()> {
    validate::finite_scalars("outage", &[o.start_s, o.duration_s])?;
    if o.start_s < 1.0 || o.duration_s <= 0.0 || o.start_s >= duration_s {
        return Err(Error::invalid(
            "outage",
            format!(
                "(start_s, length_s, n_visible) needs 1 s ≤ start < duration ({duration_s} s; the filters start from the first epoch) and length > 0, got ({}, {}, {})",
                o.start_s, o.duration_s, o.n_satellites
            ),
        ));
    }
    if o.n_satellites > 3 {
        return Err(Error::invalid(
            "outage",
            format!(
                "n_visible must be 0 (total outage) to 3 (partial), got {}",
                o.n_satellites
            ),
        ));
    }
    Ok(())
}

/// Results of [`navigation_experiment`].
#[derive(Debug, Clone, PartialEq)]
pub struct NavigationExperiment {
    /// Output epochs, s from the start (0, 1, …).
    pub time_s: Vec<f64>,
    /// Per IMU, in the configuration's order.
    pub imus: Vec<ImuOutcome>,
    /// Runs completed (all unless cancelled).
    pub completed_runs: usize,
    /// Whether the set was cancelled before the end.
    pub cancelled: bool,
}

/// Output epochs (s) of `out`.
fn output_times(out: &[usize]) -> Vec<f64> {
    (0..out.len()).map(|m| m as f64).collect()
}

/// What the runs of a navigation set share, prepared once: the derived
/// settings, the constellation and the output epochs.
pub(super) struct Prepared {
    pub trajectory: RandomTrajectoryConfig,
    pub gnss: SimulationConfig,
    pub sky: Constellation,
    pub out: Vec<usize>,
    pub time_s: Vec<f64>,
}

impl Prepared {
    fn new(config: &NavigationExperimentConfig) -> Result<Self> {
        config.validate()?;
        let out = config.output_indices();
        Ok(Self {
            trajectory: config.trajectory_config(),
            gnss: config.gnss_config(),
            sky: config.sky()?,
            time_s: output_times(&out),
            out,
        })
    }

    /// One fold per IMU over curves with this outage window.
    pub fn folds(
        &self,
        config: &NavigationExperimentConfig,
        window: Option<(f64, f64)>,
    ) -> Vec<OutcomeFold> {
        config
            .imus
            .iter()
            .map(|(name, _)| {
                OutcomeFold::new(
                    name,
                    &self.time_s,
                    config.early_window_s,
                    window,
                    config.keep_runs,
                )
            })
            .collect()
    }
}

/// The navigation Monte Carlo as runs and a fold ([`MonteCarlo`]): run
/// here with [`montecarlo::execute`], or in chunks elsewhere.
pub struct NavigationRuns<'a> {
    config: &'a NavigationExperimentConfig,
    prepared: Prepared,
}

impl<'a> NavigationRuns<'a> {
    /// Checks the configuration and prepares what the runs share.
    pub fn new(config: &'a NavigationExperimentConfig) -> Result<Self> {
        Ok(Self {
            prepared: Prepared::new(config)?,
            config,
        })
    }
}

impl MonteCarlo for NavigationRuns<'_> {
    /// Per IMU, in the configuration's order.
    type Run = Vec<ImuRun>;
    type Fold = Vec<OutcomeFold>;
    type Output = NavigationExperiment;

    fn seed(&self) -> u64 {
        self.config.seed
    }
    fn runs(&self) -> usize {
        self.config.runs
    }
    fn batch(&self) -> usize {
        16
    }
    fn run(&self, _: usize, rng: &mut crate::random::Rng) -> Result<Vec<ImuRun>> {
        let (config, p) = (self.config, &self.prepared);
        let draws = run::draw_run(config, &p.trajectory, &p.gnss, &p.sky, rng, None)?;
        let fixes = match config.coupling {
            Coupling::Tight => Vec::new(),
            Coupling::Loose => position_fixes(&draws.epochs),
        };
        let setup = config.filter_setup(config.coupling, &p.out);
        draws
            .inputs
            .iter()
            .flatten()
            .map(|input| {
                navigate(
                    &draws.truth,
                    &draws.epochs,
                    &fixes,
                    input,
                    &draws.start,
                    &setup,
                )
            })
            .collect()
    }
    fn start(&self) -> Vec<OutcomeFold> {
        let window = self.config.outage.map(|o| (o.start_s, o.duration_s));
        self.prepared.folds(self.config, window)
    }
    fn push(&self, folds: &mut Vec<OutcomeFold>, _: usize, runs: Vec<ImuRun>) -> Result<()> {
        for (fold, r) in folds.iter_mut().zip(runs) {
            fold.push(r)?;
        }
        Ok(())
    }
    fn finish(
        &self,
        folds: Vec<OutcomeFold>,
        summary: FoldSummary,
    ) -> Result<NavigationExperiment> {
        Ok(NavigationExperiment {
            time_s: self.prepared.time_s.clone(),
            imus: folds.into_iter().map(OutcomeFold::finish).collect(),
            completed_runs: summary.completed,
            cancelled: summary.cancelled,
        })
    }
}

/// Runs the navigation Monte Carlo (module docs). A cancelled set returns
/// the runs completed so far with `cancelled = true`.
pub fn navigation_experiment(
    config: &NavigationExperimentConfig,
    options: &RunOptions<'_>,
) -> Result<NavigationExperiment> {
    montecarlo::execute(&NavigationRuns::new(config)?, options)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small(runs: usize, imus: Vec<(String, NavigationImu)>) -> NavigationExperimentConfig {
        NavigationExperimentConfig {
            runs,
            duration_s: 60.0,
            imus,
            calibration_duration_s: 60.0,
            keep_runs: true,
            ..Default::default()
        }
    }

    /// With a given initial state the filter runs on 3 satellites from the
    /// start (no fix ever exists) and stays far below free inertial drift;
    /// the loosely coupled filter, fed the same data with 6 satellites,
    /// converges like the tight one.
    #[test]
    fn fewer_than_four_satellites_from_a_given_state_and_loose_coupling() {
        let ins = paper_imus()[..1].to_vec();
        let given = InitialStateSource::Given {
            position_std_m: 3.0,
            velocity_std_m_s: 0.2,
        };
        let three = navigation_experiment(
            &NavigationExperimentConfig {
                n_satellites: 3,
                initial_state: given,
                ..small(2, ins.clone())
            },
            &threads(2),
        )
        .unwrap();
        // Against free inertial navigation from the same attitude error
        // (a total outage from 1 s on, after a 6-satellite first fix).
        let free = navigation_experiment(
            &NavigationExperimentConfig {
                outage: Some(Outage {
                    start_s: 1.0,
                    duration_s: 100.0,
                    n_satellites: 0,
                }),
                ..small(2, ins.clone())
            },
            &threads(2),
        )
        .unwrap();
        for (run, free_run) in three.imus[0]
            .position_error_runs
            .iter()
            .zip(&free.imus[0].position_error_runs)
        {
            let (worst, free_worst) = (run.iter().copied().fold(0.0, f64::max), free_run[60]);
            assert!(worst < 0.3 * free_worst, "{worst} vs free {free_worst}");
        }
        let loose = navigation_experiment(
            &NavigationExperimentConfig {
                coupling: Coupling::Loose,
                ..small(2, ins)
            },
            &threads(2),
        )
        .unwrap();
        let late = &loose.imus[0].position_error_runs[0][30..];
        assert!(late.iter().all(|e| *e < 10.0), "{late:?}");
        // 3 whitened position and 3 velocity components per epoch.
        let o = &loose.imus[0];
        assert_eq!(o.run_accepted[0] + o.run_rejected[0], 6 * 61);
    }

    fn threads(n: usize) -> RunOptions<'static> {
        RunOptions {
            threads: Some(n),
            ..Default::default()
        }
    }

    /// Same numbers for one or two threads, and the IMUs of a run share the
    /// trajectory: an IMU's curve does not change when another IMU is
    /// dropped from the set (its draws come from its own stream).
    #[test]
    fn reproducible_and_paired() {
        let config = small(2, paper_imus());
        let one = navigation_experiment(&config, &threads(1)).unwrap();
        let two = navigation_experiment(&config, &threads(2)).unwrap();
        // Debug text compares NaN (no outage) equal to NaN, bit for bit otherwise.
        assert_eq!(format!("{one:?}"), format!("{two:?}"));
        assert_eq!(one.time_s.len(), 61);
        assert_eq!(one.imus[0].position_error_runs.len(), 2);
        let ins_only =
            navigation_experiment(&small(2, paper_imus()[..1].to_vec()), &threads(2)).unwrap();
        assert_eq!(
            ins_only.imus[0].position_error_runs,
            one.imus[0].position_error_runs
        );
    }

    /// Chunks of runs computed apart (as Dask workers do) fold to the
    /// local numbers bit for bit, smoothed curves included; the smoother,
    /// which sees the GNSS after the outage, stays below the forward
    /// filter inside it.
    #[test]
    fn chunks_fold_to_the_local_numbers_and_smoothing_helps_in_outages() {
        let config = NavigationExperimentConfig {
            outage: Some(Outage {
                start_s: 20.0,
                duration_s: 20.0,
                n_satellites: 0,
            }),
            smooth: true,
            ..small(3, paper_imus()[1..2].to_vec())
        };
        let local = navigation_experiment(&config, &threads(2)).unwrap();
        let runs = NavigationRuns::new(&config).unwrap();
        let chunk =
            |r: std::ops::Range<usize>| montecarlo::run_chunk(&runs, r, &threads(1)).unwrap();
        let (a, b) = (chunk(2..3), chunk(0..2));
        let folded = montecarlo::fold_chunks(&runs, &[&a, &b]).unwrap();
        assert_eq!(format!("{local:?}"), format!("{folded:?}"));
        let forward = &local.imus[0];
        let smoothed = forward.smoothed.as_ref().unwrap();
        for (s, f) in smoothed
            .run_max_in_outage
            .iter()
            .zip(&forward.run_max_in_outage)
        {
            assert!(s < f, "smoothed {s} vs forward {f}");
        }
        // The error at the outage end is the curve's last epoch inside it.
        let curve = &forward.position_error_runs[0];
        assert_eq!(forward.run_at_outage_end[0], curve[39]);
    }

    /// Pseudoranges only: one scalar update per satellite and epoch instead
    /// of two, and the filter still converges to the GNSS level.
    #[test]
    fn pseudorange_only_halves_the_updates() {
        let ins = paper_imus()[..1].to_vec();
        let with_rates = navigation_experiment(&small(1, ins.clone()), &threads(1)).unwrap();
        let ranges_only = navigation_experiment(
            &NavigationExperimentConfig {
                use_pseudorange_rate: false,
                ..small(1, ins)
            },
            &threads(1),
        )
        .unwrap();
        let (a, b) = (
            with_rates.imus[0].run_accepted[0] + with_rates.imus[0].run_rejected[0],
            ranges_only.imus[0].run_accepted[0] + ranges_only.imus[0].run_rejected[0],
        );
        // 6 satellites at 61 epochs.
        assert_eq!(b, 6 * 61);
        assert_eq!(a, 2 * 6 * 61);
        let late = &ranges_only.imus[0].position_error_runs[0][30..];
        assert!(late.iter().all(|e| *e < 10.0), "{late:?}");
    }

    /// Every setting is checked before a run starts (the derived GNSS
    /// settings included), and the error names the Python keyword.
    #[test]
    fn bad_configurations_name_the_argument() {
        let refused = |c: NavigationExperimentConfig| {
            let e = navigation_experiment(&c, &threads(1))
                .unwrap_err()
                .to_string();
            e[..e.find(':').unwrap()].to_string()
        };
        let with_outage = |start_s: f64, n_satellites: usize| NavigationExperimentConfig {
            outage: Some(Outage {
                start_s,
                duration_s: 30.0,
                n_satellites,
            }),
            ..small(1, paper_imus())
        };
        let mut swapped = small(1, paper_imus());
        swapped.imus.swap(1, 2);
        assert_eq!(refused(swapped), "imus");
        assert_eq!(refused(with_outage(0.0, 0)), "outage");
        assert_eq!(refused(with_outage(10.0, 4)), "outage");
        let three = NavigationExperimentConfig {
            n_satellites: 3,
            ..small(1, paper_imus())
        };
        assert_eq!(refused(three), "n_satellites");
        let mut noisy = small(1, paper_imus());
        noisy.gnss.pseudorange_std_m = -1.0;
        assert_eq!(refused(noisy), "pseudorange_std");
        let attitude = NavigationExperimentConfig {
            initial_attitude_std_rad: Vector3::new(0.01, 0.0, 0.1),
            ..small(1, paper_imus())
        };
        assert_eq!(refused(attitude), "initial_attitude_std");
    }
}
