//! Navigation Monte Carlo (paper §5.3, figures 14-18; method §5-6): the
//! tightly coupled GNSS/INS filter on the same random trajectories and GNSS
//! measurements with several IMUs, position error norm and NEES vs time.
//!
//! ## One run (reproducible from `(seed, run index)`)
//!
//! Draw order from `random::stream(seed, i)`: the random land-vehicle
//! trajectory ([`Trajectory::random`], 100 Hz truth), its GNSS
//! measurements ([`gnss::simulate`]: Walker constellation, 6 satellites
//! kept all along, 3 m / 0.1 m/s white noise, a TCXO clock, the optional
//! total outage), the initial attitude error (drawn once from the default
//! [`InitialUncertainty`]: 1° tilt, 5° heading), and a seed from which IMU
//! j draws its own stream `random::stream(imu_seed, j)`. Trajectory, GNSS
//! and initial error are thus *shared by every IMU of a run* (a paired
//! comparison), and an IMU's draws do not depend on the other IMUs.
//!
//! Per IMU: errors drawn from its spec ([`NavigationImu::Drawn`]) or a
//! fixed model ([`NavigationImu::Fixed`]), readings of the trajectory's
//! exact specific force and angular rate, filter tuning from the spec
//! ([`FilterTuning::from_imu_spec`], 17 states: the deterministic errors the
//! state lacks are absorbed as inflated noise), initial position, velocity
//! and clock from the least-squares fix of the first GNSS epoch.
//!
//! [`NavigationImu::Calibrated`] is the paper's "calibrated MEMS": the
//! *same* sensor and the *same* readings as its source IMU, passed through
//! the inversion filters (method §4) with parameters from a calibration
//! (method §3, errors-in-variables) done at t = 0 on its own segment of
//! `calibration_duration_s` of land-vehicle motion with GNSS-like reference
//! noise ([`super::REFERENCE_SPECIFIC_FORCE_STD`],
//! [`super::REFERENCE_ANGULAR_RATE_STD`]). The filter is then tuned from the
//! calibration's own parameter uncertainties (their RMS per term) and the
//! sensor's noise, so it trusts the calibrated model as much as the
//! calibration warrants. The calibration segment has its own noise and
//! bias-instability realisation (it happens before the run).
//!
//! ## Outputs
//!
//! At every whole second of the trajectory (1 Hz, the GNSS epochs; during
//! an outage the same grid): the position error norm |r̂ − r|, m, and the
//! NEES of (ψ, δv, δr) against the filter's 9 × 9 covariance block (ψ from
//! Ĉ Cᵀ = I + [ψ×], method §5). Per IMU they are folded in run order into
//! per-epoch statistics ([`CurveStats`]) and per-run scalars; the per-run
//! curves are kept only when asked (`keep_runs`).

use nalgebra::{Matrix3, SVector, Vector3};
use rand::Rng as _;
use rand_distr::StandardNormal;

use crate::attitude::{dcm_to_rotation_vector, rotation_vector_to_dcm};
use crate::calibration::{
    calibrate_accelerometer, calibrate_gyroscope, CalibrationOptions, Method,
};
use crate::coupling::InitialUncertainty;
use crate::coupling::{initial_state_from_fix, run_tightly_coupled, FilterTuning, ImuData};
use crate::filter::state::{ATTITUDE, BASE_STATES, WITH_SCALE_FACTORS};
use crate::geodesy::{c_n_e, ecef_to_geodetic};
use crate::gnss::{self, Constellation, Outage, ReceiverTrack, SimulationConfig, WalkerConfig};
use crate::inversion::{invert_accelerometer, invert_gyroscope, InversionNoise};
use crate::montecarlo::{self, CurveStats, RunOptions, PERCENTILES};
use crate::random::{self, Rng};
use crate::sensors::{presets, ImuModel, ImuReadings, ImuSpec};
use crate::trajectory::{RandomTrajectoryConfig, Trajectory};
use crate::{validate, Error, Result};

use super::inversion::{DEFAULT_ACCEL_PROCESS_STD, DEFAULT_GYRO_PROCESS_STD};
use super::{motion, with_white_noise};

/// Default length of the calibration segment before the run, s.
pub const DEFAULT_CALIBRATION_DURATION_S: f64 = 300.0;
/// Default early window of the summaries ("calibration helps most in the
/// first ~150 s", method §6), s.
pub const DEFAULT_EARLY_WINDOW_S: f64 = 150.0;
/// Degrees of freedom of the navigation NEES (attitude, velocity, position).
pub const NEES_DOF: usize = 9;

/// Where an IMU of the experiment comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum NavigationImu {
    /// A new IMU drawn from this spec in every run (the paper's presets).
    Drawn(ImuSpec),
    /// This very sensor in every run (its noise is drawn per run); its
    /// sample rate must equal the trajectory rate.
    Fixed(Box<ImuModel>),
    /// The sensor and readings of IMU `source` (an earlier, non-calibrated
    /// entry) passed through calibration and inversion (module docs).
    Calibrated { source: usize },
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
    /// Satellites tracked all along (paper: 6); overrides `gnss.n_satellites`.
    pub n_satellites: usize,
    /// Total outage `(start_s, length_s)` (paper: 30 s), added to `gnss.outages`.
    pub outage: Option<(f64, f64)>,
    /// Random trajectory settings (default: Toulouse, 100 Hz, land vehicle).
    pub trajectory: RandomTrajectoryConfig,
    /// GNSS simulation settings (default: 1 Hz, 3 m, 0.1 m/s, TCXO clock).
    pub gnss: SimulationConfig,
    /// The constellation (default: 24 satellites, 6 planes, 55°, no file
    /// needed; a broadcast file would tie the runs to its validity window).
    pub constellation: WalkerConfig,
    /// Length of the calibration segment of calibrated IMUs, s.
    pub calibration_duration_s: f64,
    /// Reference noise of that calibration, per sample, m/s² and rad/s.
    pub reference_specific_force_std: f64,
    pub reference_angular_rate_std: f64,
    /// Early window of [`ImuOutcome::run_rms_early`], s.
    pub early_window_s: f64,
    /// Whether the filters use the pseudorange rates (default true). The
    /// paper's tight coupling names pseudoranges only; with rates (0.1 m/s
    /// at 1 Hz) the velocity is pinned every second and every IMU
    /// converges within ~30 s (see `docs/paper-comparison.md`).
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
    /// uncertainty and white noise ([`FilterTuning::absorb_unmodelled`];
    /// default true). False tunes from the spec's bias and noise only, as a
    /// filter that ignores those errors would.
    pub absorb_unmodelled: bool,
    /// Keep every run's curves (memory: runs × epochs × 2 per IMU).
    pub keep_runs: bool,
}

/// The paper's three IMUs: "ins" (tactical preset), "mems" (paper-mems,
/// raw) and "calibrated_mems" (the same MEMS, calibrated and inverted).
pub fn paper_imus() -> Vec<(String, NavigationImu)> {
    vec![
        ("ins".into(), NavigationImu::Drawn(presets::tactical())),
        ("mems".into(), NavigationImu::Drawn(presets::paper_mems())),
        (
            "calibrated_mems".into(),
            NavigationImu::Calibrated { source: 1 },
        ),
    ]
}

impl Default for NavigationExperimentConfig {
    fn default() -> Self {
        Self {
            runs: 20,
            seed: 0,
            duration_s: 600.0,
            imus: paper_imus(),
            n_satellites: 6,
            outage: None,
            trajectory: RandomTrajectoryConfig::default(),
            gnss: SimulationConfig::default(),
            constellation: WalkerConfig::default(),
            calibration_duration_s: DEFAULT_CALIBRATION_DURATION_S,
            reference_specific_force_std: super::REFERENCE_SPECIFIC_FORCE_STD,
            reference_angular_rate_std: super::REFERENCE_ANGULAR_RATE_STD,
            early_window_s: DEFAULT_EARLY_WINDOW_S,
            use_pseudorange_rate: true,
            initial_attitude_std_rad: InitialUncertainty::default().attitude_ned_rad,
            scale_factor_states: false,
            absorb_unmodelled: true,
            keep_runs: false,
        }
    }
}

impl NavigationExperimentConfig {
    fn validate(&self) -> Result<()> {
        if self.runs == 0 {
            return Err(Error::invalid("runs", "must be at least 1"));
        }
        validate::positive("duration", self.duration_s)?;
        if self.duration_s < 2.0 {
            return Err(Error::invalid(
                "duration",
                format!("must be at least 2 s, got {}", self.duration_s),
            ));
        }
        if self.imus.is_empty() {
            return Err(Error::invalid("imus", "needs at least one IMU"));
        }
        for (j, (name, imu)) in self.imus.iter().enumerate() {
            if self.imus[..j].iter().any(|(n, _)| n == name) {
                return Err(Error::invalid(
                    "imus",
                    format!("name {name:?} appears twice"),
                ));
            }
            match imu {
                NavigationImu::Drawn(spec) => spec.validate()?,
                NavigationImu::Fixed(model) => {
                    if (model.sample_rate_hz - self.trajectory.rate_hz).abs() > 1e-9 {
                        return Err(Error::invalid(
                            "imus",
                            format!(
                                "{name:?} samples at {} Hz but the trajectory at {} Hz",
                                model.sample_rate_hz, self.trajectory.rate_hz
                            ),
                        ));
                    }
                }
                NavigationImu::Calibrated { source } => {
                    let ok = *source < j
                        && !matches!(self.imus[*source].1, NavigationImu::Calibrated { .. });
                    if !ok {
                        return Err(Error::invalid(
                            "imus",
                            format!(
                                "{name:?}: calibrated IMUs need an earlier raw IMU as source, got index {source}"
                            ),
                        ));
                    }
                }
            }
        }
        if self.n_satellites < 4 {
            return Err(Error::invalid(
                "n_satellites",
                format!(
                    "needs at least 4 for the initial fix, got {}",
                    self.n_satellites
                ),
            ));
        }
        if let Some((start, length)) = self.outage {
            validate::finite_scalars("outage", &[start, length])?;
            if start < 1.0 || length <= 0.0 {
                return Err(Error::invalid(
                    "outage",
                    format!(
                        "(start_s, length_s) needs start ≥ 1 s (the filter starts from the first fix) and length > 0, got ({start}, {length})"
                    ),
                ));
            }
        }
        validate::positive("calibration_duration", self.calibration_duration_s)?;
        validate::positive(
            "reference_specific_force_std",
            self.reference_specific_force_std,
        )?;
        validate::positive(
            "reference_angular_rate_std",
            self.reference_angular_rate_std,
        )?;
        validate::positive("early_window", self.early_window_s)?;
        for v in self.initial_attitude_std_rad.iter() {
            validate::positive("initial_attitude_std", *v)?;
        }
        Ok(())
    }

    /// Sample indices of the whole seconds 0, 1, …, ⌊duration⌋.
    fn output_indices(&self) -> Vec<usize> {
        let n = self.duration_s.floor() as usize + 1;
        (0..n)
            .map(|m| (m as f64 * self.trajectory.rate_hz).round() as usize)
            .collect()
    }
}

/// One IMU's results over the completed runs.
#[derive(Debug, Clone, PartialEq)]
pub struct ImuOutcome {
    pub name: String,
    /// Per epoch: mean over runs of the position error norm, m.
    pub position_error_mean: Vec<f64>,
    /// Per epoch: its sample standard deviation over runs (NaN for one run), m.
    pub position_error_std: Vec<f64>,
    /// Per epoch: its percentiles [`PERCENTILES`] (P² estimates), m.
    pub position_error_percentiles: Vec<Vec<f64>>,
    /// Per epoch: mean over runs of the NEES (9 dof).
    pub nees_mean: Vec<f64>,
    /// Every run's position error norm per epoch (only with `keep_runs`).
    pub position_error_runs: Vec<Vec<f64>>,
    /// Every run's NEES per epoch (only with `keep_runs`).
    pub nees_runs: Vec<Vec<f64>>,
    /// Per run: RMS of the position error norm over the whole run, m.
    pub run_rms: Vec<f64>,
    /// Per run: RMS over the first `early_window_s`, m.
    pub run_rms_early: Vec<f64>,
    /// Per run: position error norm at the last epoch, m.
    pub run_final: Vec<f64>,
    /// Per run: largest error norm at the epochs inside the outage window
    /// [start, start + length) — before the first update after it (NaN
    /// without outage), m.
    pub run_max_in_outage: Vec<f64>,
    /// Per run: mean NEES per degree of freedom over the epochs.
    pub run_mean_nees_per_dof: Vec<f64>,
    /// Per run: measurements rejected by the gate or as invalid.
    pub run_rejected: Vec<usize>,
    /// Per run: scalar measurements applied (pseudoranges, and rates when
    /// used).
    pub run_accepted: Vec<usize>,
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

/// One run's curves for one IMU.
struct ImuRun {
    position_error: Vec<f64>,
    nees: Vec<f64>,
    rejected: usize,
    accepted: usize,
}

/// An IMU spec from a calibration's parameter uncertainties (the RMS of
/// each term's one-sigma, as [`ImuSpec::of_models`] takes the RMS of a
/// model's values) and the sensor's own noise.
fn calibrated_spec(
    raw: &ImuSpec,
    acc_std: &crate::sensors::AccelerometerModel,
    gyr_std: &crate::sensors::GyroscopeModel,
    rate_hz: f64,
) -> ImuSpec {
    let mut spec = ImuSpec::of_models(acc_std, gyr_std, rate_hz);
    spec.accelerometer.noise = raw.accelerometer.noise;
    spec.gyroscope.noise = raw.gyroscope.noise;
    spec
}

/// Calibrates `imu` on its own land-vehicle segment (method §3, EIV) and
/// inverts `readings` (method §4); returns the inverted readings and the
/// spec the filter is tuned from.
fn calibrate_and_invert(
    imu: &ImuModel,
    readings: &ImuReadings,
    config: &NavigationExperimentConfig,
    rng: &mut Rng,
) -> Result<(ImuReadings, ImuSpec)> {
    let rate = imu.sample_rate_hz;
    let (sf, sw) = (
        config.reference_specific_force_std,
        config.reference_angular_rate_std,
    );
    let cal = motion::land_vehicle(config.calibration_duration_s, rate, rng)?;
    let cal_readings = imu.measure(&cal.specific_force_b, &cal.angular_rate_b, rng)?;
    let f_ref = with_white_noise(&cal.specific_force_b, sf, rng);
    let w_ref = with_white_noise(&cal.angular_rate_b, sw, rng);
    let acc = calibrate_accelerometer(
        &cal_readings.specific_force_b,
        &f_ref,
        &CalibrationOptions {
            method: Method::ErrorsInVariables,
            reference_noise_std: Some(sf),
            ..Default::default()
        },
    )?;
    let gyr = calibrate_gyroscope(
        &cal_readings.angular_rate_b,
        &w_ref,
        &f_ref,
        &CalibrationOptions {
            method: Method::ErrorsInVariables,
            reference_noise_std: Some(sw),
            reference_specific_force_noise_std: Some(sf),
            ..Default::default()
        },
    )?;
    let accel_noise = InversionNoise {
        process_std: Vector3::repeat(DEFAULT_ACCEL_PROCESS_STD),
        measurement_std: Vector3::repeat(imu.accelerometer.noise.white_std_per_sample(rate)),
    };
    let gyro_noise = InversionNoise {
        process_std: Vector3::repeat(DEFAULT_GYRO_PROCESS_STD),
        measurement_std: Vector3::repeat(imu.gyroscope.noise.white_std_per_sample(rate)),
    };
    let f_hat = invert_accelerometer(&readings.specific_force_b, &acc.model, &accel_noise)?;
    let w_hat = invert_gyroscope(
        &readings.angular_rate_b,
        &f_hat.estimate,
        &gyr.model,
        &gyro_noise,
    )?;
    let spec = calibrated_spec(&imu.spec, &acc.std, &gyr.std, rate);
    Ok((
        ImuReadings {
            specific_force_b: f_hat.estimate,
            angular_rate_b: w_hat.estimate,
        },
        spec,
    ))
}

/// What a run's filters share: the options of the configuration that set
/// their tuning, and the output epochs.
struct FilterSetup<'a> {
    rate_hz: f64,
    use_pseudorange_rate: bool,
    initial_attitude_std_rad: Vector3<f64>,
    scale_factor_states: bool,
    absorb_unmodelled: bool,
    out: &'a [usize],
}

/// The tightly coupled filter on one IMU's readings (17 or 23 states as
/// configured); error curves at `setup.out`.
fn navigate(
    truth: &Trajectory,
    epochs: &[gnss::GnssEpoch],
    readings: &ImuReadings,
    spec: &ImuSpec,
    initial_attitude: &Matrix3<f64>,
    setup: &FilterSetup,
) -> Result<ImuRun> {
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
    tuning.initial_std.attitude_ned_rad = setup.initial_attitude_std_rad;
    if setup.scale_factor_states {
        navigate_with::<WITH_SCALE_FACTORS>(
            truth,
            epochs,
            readings,
            &tuning,
            initial_attitude,
            setup.out,
        )
    } else {
        navigate_with::<BASE_STATES>(
            truth,
            epochs,
            readings,
            &tuning,
            initial_attitude,
            setup.out,
        )
    }
}

fn navigate_with<const N: usize>(
    truth: &Trajectory,
    epochs: &[gnss::GnssEpoch],
    readings: &ImuReadings,
    tuning: &FilterTuning,
    initial_attitude: &Matrix3<f64>,
    out: &[usize],
) -> Result<ImuRun> {
    let imu = ImuData {
        time_s: &truth.time_s,
        specific_force_b: &readings.specific_force_b,
        angular_rate_b: &readings.angular_rate_b,
    };
    let initial = initial_state_from_fix(epochs, &imu, Some(*initial_attitude))?;
    let mut position_error = Vec::with_capacity(out.len());
    let mut nees = Vec::with_capacity(out.len());
    let mut next = 0;
    let records = run_tightly_coupled::<N, _>(&imu, epochs, &initial, tuning, |k, s| {
        if next < out.len() && out[next] == k {
            let t = truth.nav_state(k);
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
            position_error.push(e.fixed_rows::<3>(6).norm());
            nees.push(crate::filter::nees(&e, &p).unwrap_or(f64::NAN));
            next += 1;
        }
    })?;
    let accepted = records
        .iter()
        .filter(|r| r.status == crate::coupling::MeasurementStatus::Accepted)
        .count();
    Ok(ImuRun {
        position_error,
        nees,
        rejected: records.len() - accepted,
        accepted,
    })
}

/// One Monte Carlo run (draw order in the module docs).
fn one_run(
    config: &NavigationExperimentConfig,
    trajectory_config: &RandomTrajectoryConfig,
    gnss_config: &SimulationConfig,
    sky: &Constellation,
    out: &[usize],
    rng: &mut Rng,
) -> Result<Vec<ImuRun>> {
    let rate = trajectory_config.rate_hz;
    let setup = FilterSetup {
        rate_hz: rate,
        use_pseudorange_rate: config.use_pseudorange_rate,
        initial_attitude_std_rad: config.initial_attitude_std_rad,
        scale_factor_states: config.scale_factor_states,
        absorb_unmodelled: config.absorb_unmodelled,
        out,
    };
    let truth = Trajectory::random(trajectory_config, rng)?;
    let epochs = gnss::simulate(
        &ReceiverTrack {
            time_s: &truth.time_s,
            position_ecef: &truth.position_ecef,
            velocity_ecef: &truth.velocity_ecef,
        },
        sky,
        gnss_config,
        rng,
    )?;
    // Shared initial attitude error: ψ ~ N(0, diag(σ_N², σ_E², σ_D²)) in
    // NED, Ĉ = R(ψ) C (the filter's P₀ attitude block).
    let attitude_std = config.initial_attitude_std_rad;
    let geo = ecef_to_geodetic(&truth.position_ecef[0]);
    let psi_ned = Vector3::from_fn(|i, _| attitude_std[i] * rng.sample::<f64, _>(StandardNormal));
    let psi = c_n_e(geo.latitude_rad, geo.longitude_rad) * psi_ned;
    let initial_attitude = rotation_vector_to_dcm(&psi) * truth.c_b_e[0];
    let imu_seed: u64 = rng.random();

    let mut sensors: Vec<Option<(ImuModel, ImuReadings)>> = Vec::with_capacity(config.imus.len());
    let mut runs = Vec::with_capacity(config.imus.len());
    for (j, (_, kind)) in config.imus.iter().enumerate() {
        let mut r = random::stream(imu_seed, j as u64);
        let (readings, spec) = match kind {
            NavigationImu::Drawn(_) | NavigationImu::Fixed(_) => {
                let model = match kind {
                    NavigationImu::Drawn(spec) => ImuModel::from_spec(spec, rate, &mut r)?,
                    NavigationImu::Fixed(model) => model.as_ref().clone(),
                    NavigationImu::Calibrated { .. } => unreachable!("matched above"),
                };
                let readings =
                    model.measure(&truth.specific_force_b, &truth.angular_rate_b, &mut r)?;
                let spec = model.spec;
                sensors.push(Some((model, readings.clone())));
                (readings, spec)
            }
            NavigationImu::Calibrated { source } => {
                let (model, raw) = sensors[*source]
                    .as_ref()
                    .expect("validated: the source is an earlier raw IMU");
                let done = calibrate_and_invert(model, raw, config, &mut r)?;
                sensors.push(None);
                done
            }
        };
        runs.push(navigate(
            &truth,
            &epochs,
            &readings,
            &spec,
            &initial_attitude,
            &setup,
        )?);
    }
    Ok(runs)
}

fn rms(values: &[f64]) -> f64 {
    (values.iter().map(|v| v * v).sum::<f64>() / values.len() as f64).sqrt()
}

/// Runs the navigation Monte Carlo (module docs). A cancelled set returns
/// the runs completed so far with `cancelled = true`.
pub fn navigation_experiment(
    config: &NavigationExperimentConfig,
    options: &RunOptions<'_>,
) -> Result<NavigationExperiment> {
    config.validate()?;
    let trajectory_config = RandomTrajectoryConfig {
        duration_s: config.duration_s,
        ..config.trajectory.clone()
    };
    let mut gnss_config = SimulationConfig {
        n_satellites: config.n_satellites,
        ..config.gnss.clone()
    };
    if let Some((start_s, duration_s)) = config.outage {
        gnss_config.outages.push(Outage {
            start_s,
            duration_s,
            n_satellites: 0,
        });
    }
    let sky = Constellation::walker(&config.constellation)?;
    let out = config.output_indices();
    let time_s: Vec<f64> = (0..out.len()).map(|m| m as f64).collect();
    let epochs = out.len();
    let early = time_s
        .iter()
        .take_while(|t| **t <= config.early_window_s)
        .count();
    let in_outage: Vec<usize> = match config.outage {
        Some((start, length)) => (0..epochs)
            .filter(|&m| time_s[m] >= start && time_s[m] < start + length)
            .collect(),
        None => Vec::new(),
    };
    let mut imus: Vec<ImuOutcome> = config
        .imus
        .iter()
        .map(|(name, _)| ImuOutcome {
            name: name.clone(),
            position_error_mean: Vec::new(),
            position_error_std: Vec::new(),
            position_error_percentiles: Vec::new(),
            nees_mean: Vec::new(),
            position_error_runs: Vec::new(),
            nees_runs: Vec::new(),
            run_rms: Vec::with_capacity(config.runs),
            run_rms_early: Vec::with_capacity(config.runs),
            run_final: Vec::with_capacity(config.runs),
            run_max_in_outage: Vec::with_capacity(config.runs),
            run_mean_nees_per_dof: Vec::with_capacity(config.runs),
            run_rejected: Vec::with_capacity(config.runs),
            run_accepted: Vec::with_capacity(config.runs),
        })
        .collect();
    let mut stats: Vec<(CurveStats, CurveStats)> = (0..imus.len())
        .map(|_| (CurveStats::new(epochs), CurveStats::new(epochs)))
        .collect();
    let summary = montecarlo::fold(
        config.seed,
        config.runs,
        16,
        options,
        |_, rng| one_run(config, &trajectory_config, &gnss_config, &sky, &out, rng),
        |_, runs: Vec<ImuRun>| {
            for ((o, st), r) in imus.iter_mut().zip(stats.iter_mut()).zip(runs) {
                st.0.push(&r.position_error)?;
                st.1.push(&r.nees)?;
                o.run_rms.push(rms(&r.position_error));
                o.run_rms_early.push(rms(&r.position_error[..early]));
                o.run_final.push(r.position_error[epochs - 1]);
                o.run_max_in_outage.push(
                    in_outage
                        .iter()
                        .map(|&m| r.position_error[m])
                        .fold(f64::NAN, f64::max),
                );
                o.run_mean_nees_per_dof
                    .push(r.nees.iter().sum::<f64>() / (epochs * NEES_DOF) as f64);
                o.run_rejected.push(r.rejected);
                o.run_accepted.push(r.accepted);
                if config.keep_runs {
                    o.position_error_runs.push(r.position_error);
                    o.nees_runs.push(r.nees);
                }
            }
            Ok(())
        },
    )?;
    for (o, (p, n)) in imus.iter_mut().zip(&stats) {
        o.position_error_mean = p.mean().to_vec();
        o.position_error_std = p.std();
        o.position_error_percentiles = (0..PERCENTILES.len()).map(|i| p.percentile(i)).collect();
        o.nees_mean = n.mean().to_vec();
    }
    Ok(NavigationExperiment {
        time_s,
        imus,
        completed_runs: summary.completed,
        cancelled: summary.cancelled,
    })
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

    #[test]
    fn bad_configurations_name_the_argument() {
        let mut c = small(1, paper_imus());
        c.imus.swap(1, 2);
        assert!(navigation_experiment(&c, &threads(1))
            .unwrap_err()
            .to_string()
            .starts_with("imus:"));
        let c = NavigationExperimentConfig {
            outage: Some((0.0, 30.0)),
            ..small(1, paper_imus())
        };
        assert!(navigation_experiment(&c, &threads(1))
            .unwrap_err()
            .to_string()
            .starts_with("outage:"));
        let c = NavigationExperimentConfig {
            n_satellites: 3,
            ..small(1, paper_imus())
        };
        assert!(navigation_experiment(&c, &threads(1))
            .unwrap_err()
            .to_string()
            .starts_with("n_satellites:"));
        let c = NavigationExperimentConfig {
            initial_attitude_std_rad: Vector3::new(0.01, 0.0, 0.1),
            ..small(1, paper_imus())
        };
        assert!(navigation_experiment(&c, &threads(1))
            .unwrap_err()
            .to_string()
            .starts_with("initial_attitude_std:"));
    }
}
