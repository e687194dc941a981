//! Filter tuning: process noise, initial uncertainties, gate and timing
//! rules, and how errors the filter does not estimate are absorbed.

use nalgebra::Vector3;

use super::installation::InstallationUncertainty;
use crate::filter::input_noise::{
    InputErrorNoise, UnmodelledErrors, DEFAULT_MANOEUVRE_CORRELATION_TIME_S,
};
use crate::filter::ProcessNoise;
use crate::geodesy::wgs84::STANDARD_GRAVITY_M_S2;
use crate::gnss::ReceiverClockModel;
use crate::{validate, Error, Result};

/// One-sigma initial uncertainties (the diagonal of P₀).
///
/// Attitude is given in the local NED frame (north and east tilt, heading)
/// and rotated into the ECEF attitude-error block. Defaults (documented, used
/// when the caller states nothing): 5 m position and 0.5 m/s velocity per axis
/// (a code-based single-point fix), 1° tilt and 5° heading (a coarse
/// alignment), 50 m clock offset and 10 m/s drift (resolved by the first
/// pseudoranges), and the IMU's own bias and scale-factor spreads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialUncertainty {
    /// Position, m, per ECEF axis.
    pub position_m: f64,
    /// Velocity, m/s, per ECEF axis.
    pub velocity_m_s: f64,
    /// Attitude in NED: north tilt, east tilt, heading, rad.
    pub attitude_ned_rad: Vector3<f64>,
    /// Accelerometer bias, m/s².
    pub accel_bias_m_s2: f64,
    /// Gyro bias, rad/s.
    pub gyro_bias_rad_s: f64,
    /// Receiver clock offset, m.
    pub clock_offset_m: f64,
    /// Receiver clock drift, m/s.
    pub clock_drift_m_s: f64,
    /// Accelerometer scale-factor error (23-state filters only).
    pub accel_scale_factor: f64,
    /// Gyro scale-factor error (23-state filters only).
    pub gyro_scale_factor: f64,
    /// Each satellite's pseudorange bias when it enters a range-bias slot,
    /// m (filters with range-bias states only).
    pub range_bias_m: f64,
    /// Each inter-system bias once the first pseudoranges of its system
    /// have set it (to their median residual less the clock's), m
    /// (filters with inter-system-bias states only).
    pub inter_system_bias_m: f64,
    /// The installation states (filters with the installation block only).
    pub installation: InstallationUncertainty,
}

impl Default for InitialUncertainty {
    fn default() -> Self {
        Self {
            position_m: 5.0,
            velocity_m_s: 0.5,
            attitude_ned_rad: Vector3::new(1.0_f64, 1.0, 5.0).map(f64::to_radians),
            accel_bias_m_s2: 0.1,
            gyro_bias_rad_s: 1e-2_f64.to_radians(),
            clock_offset_m: 50.0,
            clock_drift_m_s: 10.0,
            accel_scale_factor: 1e-3,
            gyro_scale_factor: 1e-3,
            range_bias_m: RangeBiasModel::default().std_m,
            inter_system_bias_m: DEFAULT_INTER_SYSTEM_BIAS_STD_M,
            installation: InstallationUncertainty::default(),
        }
    }
}

/// Default correlation time of the pseudoranges' fast errors, s
/// ([`FilterTuning::pseudorange_correlation_time_s`]): 0, white, as the
/// simulator draws them.
pub const DEFAULT_PSEUDORANGE_CORRELATION_TIME_S: f64 = 0.0;

/// Default floor of a carrier change's std, m ([`MeasurementFloor`]).
pub const DEFAULT_CARRIER_PHASE_FLOOR_M: f64 = 0.02;

/// The smallest measurement standard deviations the filter believes.
///
/// A receiver's formal stds can be far smaller than the errors of the
/// model that uses them (lever arm, time tags, an antenna phase centre, the
/// INS between epochs): an RTK solution reports 5 mm on fixed epochs that
/// the data's authors state good to 1-2 cm. A measurement whose std is
/// below its floor is used with the floor instead, so a few millimetres of
/// model error cannot lock the filter out (ArduPilot EKF3 and PX4 EKF2
/// floor their GNSS noise the same way).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasurementFloor {
    /// Pseudorange, m. Default 0.5 m (code multipath of a good antenna).
    pub pseudorange_m: f64,
    /// Pseudorange rate, m/s. Default 0.02 m/s.
    pub pseudorange_rate_m_s: f64,
    /// A carrier range's change between consecutive epochs, m. Default
    /// 0.02 m: what the INS's displacement over the interval gets wrong
    /// besides its velocity error (a hand-held antenna's sway about an
    /// unmodelled lever arm, time tags, phase wind-up from tilting), which
    /// is well above the phase noise (docs/how-to/multi-gnss.md).
    pub carrier_phase_m: f64,
    /// Position fix, m per axis. Default 0.02 m (the accuracy RTK fixed
    /// solutions are quoted to).
    pub position_m: f64,
    /// Velocity fix, m/s per axis. Default 0.02 m/s.
    pub velocity_m_s: f64,
}

impl Default for MeasurementFloor {
    fn default() -> Self {
        Self {
            pseudorange_m: 0.5,
            pseudorange_rate_m_s: 0.02,
            carrier_phase_m: DEFAULT_CARRIER_PHASE_FLOOR_M,
            position_m: 0.02,
            velocity_m_s: 0.02,
        }
    }
}

/// How the filter recovers when measurements keep failing their test.
///
/// A batch that fails is first tried without its worst measurements (fault
/// exclusion, for satellites); a pseudorange batch whose innovations share
/// one large common part is a receiver clock jump and is moved into the
/// clock. When a kind of measurement still fails at
/// `reset_after_failed_epochs` consecutive epochs, the filter trusts the
/// measurements over itself: position (velocity, clock) is reset to the
/// epoch's fix with the fix's covariance, or, with too few satellites for
/// a fix, the position, velocity and clock covariance is inflated until
/// the epoch passes. Every such event is a [`super::ResetRecord`].
/// (ArduPilot EKF3 resets its position to GNSS after its innovation checks
/// fail for a timeout; PX4 EKF2 after a fusion timeout.)
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Recovery {
    /// Consecutive failed epochs before a reset. Default 3 (0.75 s of 4 Hz
    /// fixes, 3 s at 1 Hz: one outlier never resets the filter, a
    /// persistent disagreement soon does).
    pub reset_after_failed_epochs: usize,
    /// A common part of all pseudorange (rate) innovations beyond this many
    /// of its predicted std is a clock (drift) jump. Default 10.
    pub clock_jump_sigma: f64,
    /// At most this share of a batch's measurements is excluded. Default
    /// 1/3 (one of 3-5 satellites, two of 6-8).
    pub max_excluded_share: f64,
    /// When a kind's resets follow each other with no accepted batch
    /// between, the whole covariance is multiplied by this (fading memory;
    /// see `FilterState::recovered`). Default 10 (σ × 3.2); 1 turns it off.
    pub fading_factor: f64,
}

impl Default for Recovery {
    fn default() -> Self {
        Self {
            reset_after_failed_epochs: 3,
            clock_jump_sigma: 10.0,
            max_excluded_share: 1.0 / 3.0,
            fading_factor: 10.0,
        }
    }
}

/// The per-satellite pseudorange bias of a filter with range-bias states:
/// a first-order Gauss-Markov process of steady-state std `std_m` and
/// correlation time `correlation_time_s` for the slowly varying errors a
/// code measurement carries (multipath of a slowly moving antenna, the
/// residual of the ionosphere and troposphere models, orbit and clock
/// errors of the broadcast ephemeris): treating them as white noise lets
/// the filter average them away and become overconfident.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RangeBiasModel {
    /// Steady-state std, m. Default 3 m: the broadcast signal-in-space
    /// error (≈ 1 m), half a Klobuchar-corrected ionospheric delay (2-5 m
    /// at mid-latitudes, Klobuchar 1987) and near-static multipath of a
    /// few metres, in quadrature.
    pub std_m: f64,
    /// Correlation time, s. Default 1800 s: the ionosphere model's residual
    /// and the broadcast orbit and clock errors change over tens of minutes
    /// to hours; a bias that wanders faster becomes indistinguishable from
    /// the drift of a dead-reckoned position between epochs (on walk_0827,
    /// 600 s lets 1 m of Doppler-integrated drift pass into the biases).
    pub correlation_time_s: f64,
}

impl Default for RangeBiasModel {
    fn default() -> Self {
        Self {
            std_m: 3.0,
            correlation_time_s: 1800.0,
        }
    }
}

impl RangeBiasModel {
    /// Driving-noise PSD 2σ²/τ, m²/s.
    pub fn psd(&self) -> f64 {
        2.0 * self.std_m.powi(2) / self.correlation_time_s
    }
}

impl FilterTuning {
    /// The process of the range-bias slots (tight coupling's pseudorange
    /// biases, or loose coupling's fix errors): initial std, driving PSD and
    /// correlation time from `model`.
    pub fn set_range_bias_model(&mut self, model: &RangeBiasModel) {
        self.initial_std.range_bias_m = model.std_m;
        self.process_noise.range_bias_psd = model.psd();
        self.process_noise.range_bias_correlation_time_s = model.correlation_time_s;
    }
}

/// The innovation gate's default chi-square(1) probability: |ν| > 3.29 σ
/// is rejected.
pub const DEFAULT_GATE_PROBABILITY: f64 = 0.999;

/// Default one-sigma of an inter-system bias once its system's first
/// pseudoranges have set it, m: that median residual is off by the
/// position and clock errors' projections, a few metres.
pub const DEFAULT_INTER_SYSTEM_BIAS_STD_M: f64 = 10.0;

/// Default random-walk PSD of the inter-system biases, m²/s: a receiver's
/// inter-system delay is a property of its hardware and the systems' time
/// offsets (GGTO, BDT − GPST), steady over a drive; 1e-4 m²/s lets it move
/// 0.6 m in an hour (Groves §9.4.2.3 models it as a constant).
pub const DEFAULT_INTER_SYSTEM_BIAS_PSD_M2_S: f64 = 1e-4;

/// Everything a coupled filter needs besides the data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterTuning {
    /// Process noise densities (Groves §14.2.4).
    pub process_noise: ProcessNoise,
    /// Initial one-sigma uncertainties.
    pub initial_std: InitialUncertainty,
    /// Probability of the chi-square(1) innovation gate; a measurement whose
    /// NIS exceeds the quantile is rejected and reported (default 0.999,
    /// i.e. |ν| > 3.29 σ). 1.0 disables the gate.
    pub gate_probability: f64,
    /// Use pseudorange rates when the epoch carries them (tight coupling).
    pub use_pseudorange_rate: bool,
    /// Use the carrier phase's change between consecutive epochs when the
    /// epochs carry it (tight coupling; `super::carrier`). Default off.
    pub use_carrier_phase: bool,
    /// Correlation time of the pseudoranges' fast errors (code multipath), s
    /// (tight coupling). Each pseudorange's std is inflated by
    /// √((1 + ρ)/(1 − ρ)), ρ = e^(−Δt/τ), Δt the interval since the
    /// previous epoch ([`crate::gauss_markov::correlated_sample_inflation`]),
    /// so that epochs sampling one error carry its information once, not
    /// once each. Default 0: white code noise (the simulator's).
    pub pseudorange_correlation_time_s: f64,
    /// Correlation time of the position errors of GNSS fixes, s (loose
    /// coupling): each fix's position covariance is inflated by
    /// (1 + ρ)/(1 − ρ), ρ = e^(−Δt/τ), Δt the interval since the previous
    /// fix the filter used, as the pseudoranges' are. A receiver's
    /// standalone fixes err slowly (multipath, the ionosphere model, the
    /// satellites in view): taken as white, consecutive fixes are averaged
    /// as if independent and the filter's σ falls below the fixes' own
    /// error. Default 0: white (`navigate` models a correlation it learns
    /// from the log with fix-error states instead, see `navigate::adapt`).
    pub fix_correlation_time_s: f64,
    /// A GNSS epoch within this many seconds of an IMU sample is applied at
    /// that sample; otherwise the INS is propagated to the GNSS time with an
    /// interpolated IMU sample. Default 1e-4 s.
    pub time_tolerance_s: f64,
    /// Floors on the measurement stds.
    pub floor: MeasurementFloor,
    /// Fault exclusion, clock jumps and resets.
    pub recovery: Recovery,
    /// GNSS antenna relative to the IMU, body axes (forward, right, down), m:
    /// the measurements are modelled at the antenna (Groves eq. 14.121 and
    /// 14.127 with the lever arm). Default zero.
    pub antenna_lever_arm_b_m: Vector3<f64>,
    /// Latency of a position fix's velocity, s: the velocity given at t is
    /// the antenna's velocity at t − latency (receivers that difference
    /// positions or carrier phases report a mid-interval velocity). Default 0.
    pub velocity_latency_s: f64,
}

impl FilterTuning {
    /// Tuning from sensor noise per sample at `sample_rate_hz` and bias
    /// processes (std and correlation time; ∞ for a random walk), with the
    /// initial uncertainties defaulted and the bias spreads as given.
    /// Receiver clock: [`ReceiverClockModel::default`], the TCXO the GNSS
    /// simulator draws from (S_cφ = 0.009 m²/s, S_cf = 0.036 m²/s³; Groves
    /// §9.4.2 rounds them to 0.01 and 0.04), see [`Self::set_receiver_clock`].
    pub fn new(
        sample_rate_hz: f64,
        accel_white_std_m_s2: f64,
        gyro_white_std_rad_s: f64,
        accel_bias: BiasProcess,
        gyro_bias: BiasProcess,
    ) -> Result<Self> {
        validate::positive("sample_rate_hz", sample_rate_hz)?;
        validate::non_negative("accel_white_std", accel_white_std_m_s2)?;
        validate::non_negative("gyro_white_std", gyro_white_std_rad_s)?;
        accel_bias.validate("accel_bias")?;
        gyro_bias.validate("gyro_bias")?;
        let initial_std = InitialUncertainty {
            // A floor keeps P₀ positive definite for a bias-free IMU.
            accel_bias_m_s2: accel_bias.initial_std.max(1e-6),
            gyro_bias_rad_s: gyro_bias.initial_std.max(1e-9),
            ..Default::default()
        };
        let (accel_bias_psd, accel_bias_correlation_time_s) = accel_bias.state_model();
        let (gyro_bias_psd, gyro_bias_correlation_time_s) = gyro_bias.state_model();
        let clock = ReceiverClockModel::default();
        Ok(Self {
            process_noise: ProcessNoise {
                // σ per sample of a white noise sampled at f_s ⇔ PSD σ²/f_s.
                accel_white_psd: accel_white_std_m_s2.powi(2) / sample_rate_hz,
                gyro_white_psd: gyro_white_std_rad_s.powi(2) / sample_rate_hz,
                accel_bias_psd,
                accel_bias_correlation_time_s,
                gyro_bias_psd,
                gyro_bias_correlation_time_s,
                clock_phase_psd: clock.offset_psd_m2_s(),
                clock_frequency_psd: clock.drift_psd_m2_s3(),
                accel_scale_factor_psd: 0.0,
                gyro_scale_factor_psd: 0.0,
                range_bias_psd: RangeBiasModel::default().psd(),
                range_bias_correlation_time_s: RangeBiasModel::default().correlation_time_s,
                inter_system_bias_psd: DEFAULT_INTER_SYSTEM_BIAS_PSD_M2_S,
                input_errors: InputErrorNoise::default(),
            },
            initial_std,
            gate_probability: DEFAULT_GATE_PROBABILITY,
            use_pseudorange_rate: true,
            use_carrier_phase: false,
            pseudorange_correlation_time_s: DEFAULT_PSEUDORANGE_CORRELATION_TIME_S,
            fix_correlation_time_s: 0.0,
            time_tolerance_s: 1e-4,
            floor: MeasurementFloor::default(),
            recovery: Recovery::default(),
            antenna_lever_arm_b_m: Vector3::zeros(),
            velocity_latency_s: 0.0,
        }
        .floor_noise())
    }

    /// The receiver clock's process noise from its oscillator model, the
    /// one definition the GNSS simulator draws from (Brown & Hwang §9.3:
    /// S_cφ = c² h0 / 2, S_cf = 2π² c² h−2).
    pub fn set_receiver_clock(&mut self, clock: &ReceiverClockModel) {
        self.process_noise.clock_phase_psd = clock.offset_psd_m2_s();
        self.process_noise.clock_frequency_psd = clock.drift_psd_m2_s3();
    }

    /// A small floor on the white-noise densities so a noise-free IMU still
    /// gives a well-conditioned filter (1e-4 m/s/√h and 1e-4 °/√h: far
    /// below any real sensor).
    fn floor_noise(mut self) -> Self {
        let q = &mut self.process_noise;
        q.accel_white_psd = q.accel_white_psd.max((1e-4_f64 / 60.0).powi(2));
        q.gyro_white_psd = q.gyro_white_psd.max((1e-4_f64.to_radians() / 60.0).powi(2));
        self
    }

    /// Absorbs the errors the filter does not estimate, `errors` (their
    /// one-sigma magnitudes), as the filter's uncertainty
    /// ([`crate::filter::input_noise`], documented choice: no extra states).
    /// The part driven by the specific force at rest (gravity through scale
    /// factor, nonlinearity and the misalignment terms of each axis; the
    /// gyro's g-sensitivity) is a constant and widens the initial bias
    /// uncertainty, isotropically since the IMU may be mounted any way up;
    /// the part driven by the motion becomes process noise shaped by the
    /// sensed specific force and rate at each step, with the manoeuvres'
    /// correlation time `correlation_time_s`. `scale_factor_states`: the
    /// filter estimates the scale factors (N = 23), which are then left out.
    pub fn absorb_unmodelled(
        mut self,
        errors: &UnmodelledErrors,
        correlation_time_s: f64,
        scale_factor_states: bool,
    ) -> Self {
        let mut errors = *errors;
        if scale_factor_states {
            errors.accel_scale_factor = 0.0;
            errors.gyro_scale_factor = 0.0;
        }
        let g = STANDARD_GRAVITY_M_S2;
        let accel_constant2 = (errors.accel_scale_factor * g).powi(2)
            + (errors.accel_nonlinearity_per_m_s2 * g * g).powi(2)
            + (errors.accel_misalignment * g).powi(2);
        let gyro_constant2 = (errors.gyro_g_sensitivity_rad_s_per_m_s2 * g).powi(2);
        let i = &mut self.initial_std;
        i.accel_bias_m_s2 = (i.accel_bias_m_s2.powi(2) + accel_constant2).sqrt();
        i.gyro_bias_rad_s = (i.gyro_bias_rad_s.powi(2) + gyro_constant2).sqrt();
        self.process_noise.input_errors = InputErrorNoise {
            errors,
            correlation_time_s,
            ..self.process_noise.input_errors
        };
        self
    }

    /// Checks every field (names the field at fault).
    pub fn validate(&self) -> Result<()> {
        let q = &self.process_noise;
        // The white-noise PSDs are the squares of the noise densities the
        // user gives (`accel_noise_density`, `gyro_noise_density`).
        for (name, v) in [
            ("accel_noise_density", q.accel_white_psd),
            ("gyro_noise_density", q.gyro_white_psd),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::invalid(
                    name,
                    format!(
                        "its square, the white-noise PSD, must be finite and non-negative, got {v}"
                    ),
                ));
            }
        }
        for (name, v) in [
            ("accel_bias_psd", q.accel_bias_psd),
            ("gyro_bias_psd", q.gyro_bias_psd),
            ("clock_phase_psd", q.clock_phase_psd),
            ("clock_frequency_psd", q.clock_frequency_psd),
            ("accel_scale_factor_psd", q.accel_scale_factor_psd),
            ("gyro_scale_factor_psd", q.gyro_scale_factor_psd),
            ("range_bias_psd", q.range_bias_psd),
            ("inter_system_bias_psd", q.inter_system_bias_psd),
            (
                "accel_scale_factor_std",
                q.input_errors.errors.accel_scale_factor,
            ),
            (
                "accel_misalignment_std",
                q.input_errors.errors.accel_misalignment,
            ),
            (
                "accel_nonlinearity_std",
                q.input_errors.errors.accel_nonlinearity_per_m_s2,
            ),
            (
                "gyro_scale_factor_std",
                q.input_errors.errors.gyro_scale_factor,
            ),
            (
                "gyro_misalignment_std",
                q.input_errors.errors.gyro_misalignment,
            ),
            (
                "gyro_g_sensitivity_std",
                q.input_errors.errors.gyro_g_sensitivity_rad_s_per_m_s2,
            ),
        ] {
            validate::non_negative(name, v)?;
        }
        validate::non_negative(
            "pseudorange_correlation_time",
            self.pseudorange_correlation_time_s,
        )?;
        validate::non_negative("fix_correlation_time", self.fix_correlation_time_s)?;
        validate::positive(
            "manoeuvre_correlation_time",
            q.input_errors.correlation_time_s,
        )?;
        validate::finite_vectors(
            "reference_specific_force",
            &[q.input_errors.reference_specific_force_b],
        )?;
        for (name, v) in [
            (
                "accel_bias_correlation_time",
                q.accel_bias_correlation_time_s,
            ),
            ("gyro_bias_correlation_time", q.gyro_bias_correlation_time_s),
            (
                "range_bias_correlation_time",
                q.range_bias_correlation_time_s,
            ),
        ] {
            if v.is_nan() || v <= 0.0 {
                return Err(Error::invalid(
                    name,
                    format!("must be positive (inf for a random walk), got {v}"),
                ));
            }
        }
        let i = &self.initial_std;
        for (name, v) in [
            ("initial_position_std", i.position_m),
            ("initial_velocity_std", i.velocity_m_s),
            (
                "initial_tilt_std",
                i.attitude_ned_rad.x.min(i.attitude_ned_rad.y),
            ),
            ("initial_heading_std", i.attitude_ned_rad.z),
            ("initial_accel_bias_std", i.accel_bias_m_s2),
            ("initial_gyro_bias_std", i.gyro_bias_rad_s),
            ("initial_clock_offset_std", i.clock_offset_m),
            ("initial_clock_drift_std", i.clock_drift_m_s),
            ("initial_accel_scale_factor_std", i.accel_scale_factor),
            ("initial_gyro_scale_factor_std", i.gyro_scale_factor),
            ("initial_range_bias_std", i.range_bias_m),
            ("initial_inter_system_bias_std", i.inter_system_bias_m),
            ("lever_arm_std", i.installation.lever_arm_m),
            ("time_offset_std", i.installation.time_offset_s),
            ("velocity_latency_std", i.installation.velocity_latency_s),
            ("mounting_std", i.installation.mounting_rad),
        ] {
            validate::initial_std(name, v)?;
        }
        let f = &self.floor;
        for (name, v) in [
            ("pseudorange_std_floor", f.pseudorange_m),
            ("pseudorange_rate_std_floor", f.pseudorange_rate_m_s),
            ("position_std_floor", f.position_m),
            ("velocity_std_floor", f.velocity_m_s),
        ] {
            validate::non_negative(name, v)?;
        }
        let r = &self.recovery;
        if r.reset_after_failed_epochs == 0 {
            return Err(Error::invalid(
                "reset_after_failed_epochs",
                "must be at least 1",
            ));
        }
        validate::positive("clock_jump_sigma", r.clock_jump_sigma)?;
        if !(1.0..=1e6).contains(&r.fading_factor) {
            return Err(Error::invalid(
                "reset_fading_factor",
                format!("must be in [1, 1e6], got {}", r.fading_factor),
            ));
        }
        if !(0.0..1.0).contains(&r.max_excluded_share) {
            return Err(Error::invalid(
                "max_excluded_share",
                format!("must be in [0, 1), got {}", r.max_excluded_share),
            ));
        }
        validate::finite_vectors("antenna_lever_arm", &[self.antenna_lever_arm_b_m])?;
        validate::finite_scalars("velocity_latency", &[self.velocity_latency_s])?;
        if !(self.gate_probability > 0.0 && self.gate_probability <= 1.0) {
            return Err(Error::invalid(
                "gate_probability",
                format!("must be in (0, 1], got {}", self.gate_probability),
            ));
        }
        validate::non_negative("time_tolerance", self.time_tolerance_s)?;
        Ok(())
    }
}

/// A bias process: initial spread and its evolution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BiasProcess {
    /// One-sigma of the turn-on bias (initial uncertainty), SI unit.
    pub initial_std: f64,
    /// Steady-state std of a Gauss-Markov variation, SI unit (0: none).
    pub instability_std: f64,
    /// Its correlation time, s (`f64::INFINITY` with a random walk).
    pub correlation_time_s: f64,
    /// Random-walk coefficient, SI unit per √s (used when the correlation
    /// time is infinite).
    pub random_walk: f64,
}

impl BiasProcess {
    /// A constant bias of spread `initial_std`.
    pub fn constant(initial_std: f64) -> Self {
        Self {
            initial_std,
            instability_std: 0.0,
            correlation_time_s: f64::INFINITY,
            random_walk: 0.0,
        }
    }

    /// The filter's model of its bias state: (driving-noise PSD,
    /// correlation time).
    ///
    /// The state is the whole bias, turn-on part and instability together,
    /// and closed-loop feedback holds the estimate constant between
    /// updates. A Gauss-Markov decay of the state is right only when the
    /// whole bias is that process; with a turn-on part larger than the
    /// instability it would tell the filter that its bias error fades by
    /// itself, and P of the bias would shrink to the instability's σ² within
    /// a few τ with no measurement at all (the consumer preset's
    /// 1 °/s turn-on bias "known" to 2 °/h after ten minutes, the tilt NEES
    /// twice its dof). Then the instability is taken as the random walk it
    /// is over times shorter than τ: no decay, PSD 2σ²/τ added to the
    /// random walk's q².
    pub fn state_model(&self) -> (f64, f64) {
        let markov =
            crate::gauss_markov::psd_of_stationary(self.instability_std, self.correlation_time_s);
        let psd = markov + self.random_walk.powi(2);
        if self.initial_std > self.instability_std {
            (psd, f64::INFINITY)
        } else {
            (psd, self.correlation_time_s)
        }
    }

    fn validate(&self, name: &str) -> Result<()> {
        validate::non_negative(&format!("{name}.initial_std"), self.initial_std)?;
        validate::non_negative(&format!("{name}.instability_std"), self.instability_std)?;
        validate::non_negative(&format!("{name}.random_walk"), self.random_walk)?;
        if self.correlation_time_s.is_nan() || self.correlation_time_s <= 0.0 {
            return Err(Error::invalid(
                format!("{name}.correlation_time"),
                "must be positive (inf for none)",
            ));
        }
        Ok(())
    }
}

impl FilterTuning {
    /// Tuning from an IMU specification ([`crate::sensors::ImuSpec`]): white
    /// noise densities (σ²/f_s when the spec gives a per-sample std), the
    /// bias spreads as initial uncertainties, the Gauss-Markov / random-walk
    /// bias dynamics, and the deterministic terms the state lacks absorbed
    /// as in [`FilterTuning::absorb_unmodelled`] with the default manoeuvre
    /// correlation time of a land vehicle. `scale_factor_states`: whether the filter has the 23-state
    /// layout (then the scale-factor spreads seed P₀ instead).
    pub fn from_imu_spec(
        spec: &crate::sensors::ImuSpec,
        sample_rate_hz: f64,
        scale_factor_states: bool,
    ) -> Result<Self> {
        spec.validate()?;
        validate::positive("sample_rate_hz", sample_rate_hz)?;
        let bias = |initial_std: f64, n: &crate::sensors::NoiseModel| BiasProcess {
            initial_std: (initial_std.powi(2) + n.bias_instability_std.powi(2)).sqrt(),
            instability_std: n.bias_instability_std,
            correlation_time_s: if n.bias_instability_std > 0.0 {
                n.bias_correlation_time_s
            } else {
                f64::INFINITY
            },
            random_walk: n.bias_random_walk,
        };
        let (a, g) = (&spec.accelerometer, &spec.gyroscope);
        let mut t = Self::new(
            sample_rate_hz,
            a.noise.white_std_per_sample(sample_rate_hz),
            g.noise.white_std_per_sample(sample_rate_hz),
            bias(a.bias_std, &a.noise),
            bias(g.bias_std, &g.noise),
        )?;
        if scale_factor_states {
            t.initial_std.accel_scale_factor = a.scale_factor_std.max(1e-6);
            t.initial_std.gyro_scale_factor = g.scale_factor_std.max(1e-6);
        }
        let unmodelled = UnmodelledErrors {
            accel_scale_factor: a.scale_factor_std,
            accel_misalignment: a.misalignment_std,
            accel_nonlinearity_per_m_s2: a.nonlinearity_std,
            gyro_scale_factor: g.scale_factor_std,
            gyro_misalignment: g.misalignment_std,
            gyro_g_sensitivity_rad_s_per_m_s2: g.g_sensitivity_std,
        };
        Ok(t.absorb_unmodelled(
            &unmodelled,
            DEFAULT_MANOEUVRE_CORRELATION_TIME_S,
            scale_factor_states,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bias with a turn-on part larger than its instability is a random
    /// walk of the instability's PSD (nothing makes the turn-on part fade);
    /// a bias that is the Gauss-Markov process alone keeps its decay.
    #[test]
    fn a_turn_on_bias_is_not_forgotten() {
        let gm = BiasProcess {
            initial_std: 1e-3,
            instability_std: 1e-3,
            correlation_time_s: 300.0,
            random_walk: 0.0,
        };
        let psd = 2.0 * 1e-6 / 300.0;
        assert_eq!(gm.state_model(), (psd, 300.0));
        let turn_on = BiasProcess {
            initial_std: 0.2,
            ..gm
        };
        let (q, tau) = turn_on.state_model();
        assert_eq!(tau, f64::INFINITY);
        assert!((q - psd).abs() < 1e-20);
        let with_walk = BiasProcess {
            random_walk: 1e-4,
            ..turn_on
        };
        assert!((with_walk.state_model().0 - (psd + 1e-8)).abs() < 1e-20);
    }

    /// The filter's clock noise is the simulator's clock model, whatever
    /// the oscillator.
    /// A tuning with constant biases (0.1 m/s², 1e-3 rad/s).
    fn constant_bias_tuning() -> FilterTuning {
        FilterTuning::new(
            100.0,
            0.01,
            1e-3,
            BiasProcess::constant(0.1),
            BiasProcess::constant(1e-3),
        )
        .unwrap()
    }

    #[test]
    fn the_clock_noise_comes_from_the_clock_model() {
        let t = constant_bias_tuning();
        let tcxo = ReceiverClockModel::default();
        assert_eq!(t.process_noise.clock_phase_psd, tcxo.offset_psd_m2_s());
        assert_eq!(t.process_noise.clock_frequency_psd, tcxo.drift_psd_m2_s3());
        let mut o = t;
        let ocxo = ReceiverClockModel::oscillator("ocxo").unwrap();
        o.set_receiver_clock(&ocxo);
        assert_eq!(o.process_noise.clock_frequency_psd, ocxo.drift_psd_m2_s3());
        // S_cf = 2π² c² h−2 for the TCXO: 0.0355 m²/s³ (Groves rounds to 0.04).
        assert!((t.process_noise.clock_frequency_psd - 0.0355).abs() < 5e-4);
    }

    /// The constant part of the unmodelled errors widens the initial bias
    /// uncertainty; the varying part becomes input-shaped noise, without
    /// the scale factors when they are states.
    #[test]
    fn unmodelled_errors_split_into_bias_and_input_shaped_noise() {
        let t = constant_bias_tuning();
        let errors = UnmodelledErrors {
            accel_scale_factor: 1e-2,
            accel_misalignment: 1e-2,
            gyro_scale_factor: 1e-3,
            gyro_misalignment: 1e-2,
            ..Default::default()
        };
        let g = STANDARD_GRAVITY_M_S2;
        let absorbed = t.absorb_unmodelled(&errors, 10.0, false);
        let expected = (0.1_f64.powi(2) + 2.0 * (1e-2 * g).powi(2)).sqrt();
        assert!((absorbed.initial_std.accel_bias_m_s2 - expected).abs() < 1e-12);
        assert_eq!(absorbed.process_noise.input_errors.errors, errors);
        assert_eq!(absorbed.process_noise.input_errors.correlation_time_s, 10.0);
        // The white-noise densities are the sensor's own.
        assert_eq!(
            absorbed.process_noise.accel_white_psd,
            t.process_noise.accel_white_psd
        );
        let states = t.absorb_unmodelled(&errors, 10.0, true);
        let e = states.process_noise.input_errors.errors;
        assert_eq!((e.accel_scale_factor, e.gyro_scale_factor), (0.0, 0.0));
        assert_eq!(e.gyro_misalignment, 1e-2);
    }

    /// The worked example of docs/reference/configuration.md to the filter's numbers, by
    /// the one rule (`FilterTuning::from_imu_spec`), against the arithmetic
    /// shown there: white PSDs N² (1.90386e-9 rad²/s, 3.80278e-7 m²/s³);
    /// the turn-on biases (the industrial preset's 0.05 °/s, 2 mg) exceed
    /// σ_β, so the instability is a random walk of PSD 2σ_β²/τ_β
    /// (4.93352e-12 rad²/s³, 6.54023e-11 m²/s⁵); initial bias stds
    /// √(turn-on² + σ_β² + the absorbed constants at rest): gyro with
    /// g-sensitivity 0.005 °/s, 8.77158e-4 rad/s; accelerometer with scale
    /// factor 1e-3 g, nonlinearity 1e-5 g, misalignment 0.05° × g,
    /// 0.0235394 m/s².
    #[test]
    fn the_worked_example_to_the_filter() {
        let spec = crate::sensors::ImuSpec::from_datasheet(
            &crate::sensors::presets::industrial(),
            &[
                ("gyro_arw_deg_sqrt_h", 0.15),
                ("gyro_bias_instability_deg_h", 2.0),
                ("gyro_bias_correlation_time_s", 100.0),
                ("gyro_misalignment_deg", 0.05),
                ("accel_vrw_m_s_sqrt_h", 0.037),
                ("accel_bias_instability_ug", 3.6),
                ("accel_bias_correlation_time_s", 100.0),
                ("accel_misalignment_deg", 0.05),
            ]
            .map(|(k, v)| (k.to_string(), v)),
        )
        .unwrap();
        let t = FilterTuning::from_imu_spec(&spec, 100.0, false).unwrap();
        let (q, i) = (&t.process_noise, &t.initial_std);
        let close = |x: f64, y: f64| (x / y - 1.0).abs() < 1e-5;
        assert!(close(q.gyro_white_psd, 1.90386e-9));
        assert!(close(q.accel_white_psd, 3.80278e-7));
        assert!(close(q.gyro_bias_psd, 4.93352e-12));
        assert!(close(q.accel_bias_psd, 6.54023e-11));
        assert_eq!(q.gyro_bias_correlation_time_s, f64::INFINITY);
        assert_eq!(q.accel_bias_correlation_time_s, f64::INFINITY);
        assert!(close(i.gyro_bias_rad_s, 8.77158e-4));
        assert!(close(i.accel_bias_m_s2, 0.0235394));
        let e = q.input_errors.errors;
        assert!(close(e.accel_misalignment, 8.72665e-4));
        assert_eq!(e.gyro_scale_factor, 1e-3);
    }
}
