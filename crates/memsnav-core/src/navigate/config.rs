//! The settings of a log run, with the defaults a log gets when its
//! configuration says nothing, and why they are what they are.

use nalgebra::{Matrix3, Vector3};

use crate::attitude::euler_to_dcm;
use crate::coupling::{FilterTuning, RangeBiasModel};
use crate::filter::state::RangeBiasSlots;
use crate::gnss::ReceiverClockModel;
use crate::{validate, Error, Result};

/// How the filter starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AlignmentMethod {
    /// At rest at the start of the log: a static start (level from the
    /// standstill, heading from the course of the first motion, biases
    /// settled by ZUPT/ZARU meanwhile); otherwise an in-motion start at the
    /// first GNSS epoch at `min_speed_m_s` or faster. The default.
    Auto,
    /// Static start with a known heading (rad): no wait for motion.
    StaticHeading(f64),
    /// In-motion start only (the standstill, if any, is skipped).
    Moving,
}

/// Alignment settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlignmentConfig {
    /// How to start.
    pub method: AlignmentMethod,
    /// Ground speed from which the GNSS course gives the heading, m/s.
    /// Default 1 m/s: at RTK velocity noise (≈ 0.02 m/s) the course is
    /// good to 1°, at Doppler noise (≈ 0.1 m/s) to 6°, and a car is past its
    /// first metres.
    pub min_speed_m_s: f64,
    /// Largest one-sigma of the GNSS course an alignment accepts, rad.
    /// Default 10°: at the first steps of a walk a Doppler velocity of
    /// ±0.2 m/s gives no course worth the name; wait for more speed.
    pub max_course_std_rad: f64,
    /// Specific force averaged for levelling before an in-motion start, s.
    /// Default 1 s.
    pub level_window_s: f64,
    /// One-sigma of the heading taken from the course, beyond the course's
    /// own noise: the body's forward axis against the direction of travel
    /// (mounting, side slip, a hand-held device), rad. Default 5°.
    pub heading_std_rad: f64,
    /// One-sigma tilt after levelling, rad. Default 1° (a/g of gentle
    /// motion and the accelerometer bias, 0.1 m/s² ≈ 0.6°).
    pub tilt_std_rad: f64,
}

impl Default for AlignmentConfig {
    fn default() -> Self {
        Self {
            method: AlignmentMethod::Auto,
            min_speed_m_s: 1.0,
            max_course_std_rad: 10f64.to_radians(),
            level_window_s: 1.0,
            heading_std_rad: 5f64.to_radians(),
            tilt_std_rad: 1f64.to_radians(),
        }
    }
}

/// The standstill detector (see [`super::standstill`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StandstillConfig {
    /// Window of IMU samples the statistics are taken over, s. Default 1 s.
    pub window_s: f64,
    /// Largest std of the specific-force magnitude in the window, m/s².
    /// Default 0.3 m/s²: above a car at rest with its engine running,
    /// below one driving or a walker (the spreads measured on the example
    /// logs: docs/reference/configuration.md, `[standstill]`).
    pub accel_std_m_s2: f64,
    /// Largest std of the angular-rate magnitude, rad/s. Default 3 °/s:
    /// above engine vibration at rest, below most driving and walking
    /// (the same measured spreads).
    pub gyro_std_rad_s: f64,
    /// Largest GNSS ground speed, m/s, when a GNSS velocity is at most
    /// `gnss_age_s` old. Default 0.2 m/s.
    pub gnss_speed_m_s: f64,
    /// Oldest GNSS velocity the detector trusts, s. Default 1.5 s.
    pub gnss_age_s: f64,
    /// Largest speed of the filter's own solution when there is no recent
    /// GNSS velocity (an outage), m/s. Default 1 m/s: a vehicle cruising
    /// smoothly is never taken for one at rest.
    pub solution_speed_m_s: f64,
    /// In an outage, a quiet IMU window is also a standstill when the
    /// solution's speed is within this many of its own along-track
    /// velocity σ of zero (the drift of a coasting solution can carry it
    /// well above `solution_speed_m_s` while the vehicle is stopped: a
    /// speed the filter cannot tell from zero does not veto what the
    /// sensors see). Default 3; 0 leaves only `solution_speed_m_s`.
    pub solution_speed_sigmas: f64,
}

impl Default for StandstillConfig {
    fn default() -> Self {
        Self {
            window_s: 1.0,
            accel_std_m_s2: 0.3,
            gyro_std_rad_s: 3f64.to_radians(),
            gnss_speed_m_s: 0.2,
            gnss_age_s: 1.5,
            solution_speed_m_s: 1.0,
            solution_speed_sigmas: 3.0,
        }
    }
}

/// The aids applied at standstills and while driving.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AidsConfig {
    /// Zero-velocity updates at standstills. Default on.
    pub zupt: bool,
    /// Their std, m/s. Default 0.02 m/s (vibration of a vehicle at rest).
    pub zupt_std_m_s: f64,
    /// Their interval, s. Default 0.2 s (5 Hz: the constraint is not white
    /// noise, and faster updates would treat it as more information than
    /// it is).
    pub zupt_interval_s: f64,
    /// Zero-angular-rate updates at standstills, one per detector window
    /// (each uses the window's mean gyro reading, std the window's std per
    /// axis over √n, at least `zaru_min_std_rad_s`). Default on.
    pub zaru: bool,
    /// Smallest ZARU std, rad/s. Default 0.05 °/s: a hand-held device or
    /// a car on its suspension is not perfectly still; a consumer gyro's
    /// bias (0.1-1 °/s) is still learnt to a few hundredths of a degree per
    /// second within a minute at rest.
    pub zaru_min_std_rad_s: f64,
    /// Non-holonomic constraint (land vehicles only). Default off: it is
    /// wrong for pedestrians and boats, so a configuration must ask for it.
    pub nhc: bool,
    /// Its std, m/s. Default 0.1 m/s (side slip and suspension of a car),
    /// or chosen from the log (`nhc_std_learnt`).
    pub nhc_std_m_s: f64,
    /// Choose the std from the log among multiples of `nhc_std_m_s`
    /// (`aids.nhc_std_m_s = "auto"`, the default; `super::adapt`).
    pub nhc_std_learnt: bool,
    /// Its interval, s. Default 0.5 s.
    pub nhc_interval_s: f64,
    /// Lowest speed it is applied at, m/s. Default 1 m/s.
    pub nhc_min_speed_m_s: f64,
}

impl Default for AidsConfig {
    fn default() -> Self {
        Self {
            zupt: true,
            zupt_std_m_s: 0.02,
            zupt_interval_s: 0.2,
            zaru: true,
            zaru_min_std_rad_s: 0.05f64.to_radians(),
            nhc: false,
            nhc_std_m_s: 0.1,
            nhc_std_learnt: true,
            nhc_interval_s: 0.5,
            nhc_min_speed_m_s: 1.0,
        }
    }
}

/// Initial uncertainties that replace the ones the start derives from the
/// GNSS fix.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StartOverrides {
    /// Position std, m.
    pub position_std_m: Option<f64>,
    /// Velocity std, m/s.
    pub velocity_std_m_s: Option<f64>,
}

/// Everything a log run needs besides its data.
#[derive(Debug, Clone, PartialEq)]
pub struct LogConfig {
    /// C_b^s: sensor axes to body axes (forward, right, down).
    pub mounting: Matrix3<f64>,
    /// Added to every IMU time stamp, s (the IMU's latency against GNSS
    /// time; see `estimate_time_offset`).
    pub imu_time_offset_s: f64,
    /// The vehicle reference point (where the NHC holds) relative to the
    /// IMU, body axes, m.
    pub reference_from_imu_b_m: Vector3<f64>,
    /// The filter: noise, initial uncertainties, gate, floors, recovery,
    /// the antenna lever arm and the GNSS velocity latency.
    pub tuning: FilterTuning,
    /// Range-bias states for tight coupling. Default the 12 shared slots
    /// ([`RangeBiasSlots::Shared`]): a real receiver's pseudorange errors
    /// are mostly slow biases, and a filter that takes them for white noise
    /// averages them away and reports bounds several times too tight
    /// (docs/reference/configuration.md, walk_0827). A slot for every
    /// satellite ([`RangeBiasSlots::EverySatellite`]) is asked for
    /// (`gnss.range_bias_states = "every_satellite"`): on the walk's
    /// multi-GNSS runs it gave worse precision than the shared slots
    /// (docs/decisions).
    pub range_bias_states: RangeBiasSlots,
    /// Loose coupling: a first-order Gauss-Markov error of the fixes'
    /// positions per ECEF axis, as states (the range-bias slots of tight
    /// coupling: 12 more states, three used), with the process
    /// `fix_error` (`gnss.fix_error_states = true`). A receiver's
    /// standalone fixes err slowly (multipath, the ionosphere model): a
    /// filter that takes their errors for white noise averages them and
    /// reports bounds below the fixes' own. Default off: the process is
    /// learnt from the log instead (`learn_fix_errors`).
    pub fix_error_states: bool,
    /// Their process (std and correlation time).
    pub fix_error: RangeBiasModel,
    /// The candidate tunings of an IMU chosen from the log (`imu_preset =
    /// "auto"`, [`super::adapt`]): (preset, tuning) each; empty when the
    /// configuration names its IMU and `tuning` is used as it is.
    pub imu_candidates: Vec<(String, FilterTuning)>,
    /// Learn the fixes' error process from the log and model it with
    /// fix-error states when it is correlated ([`super::adapt`]; loose
    /// coupling with white fixes, `tuning.fix_correlation_time_s = 0`;
    /// `gnss.fix_error_states = "auto"`, the default).
    pub learn_fix_errors: bool,
    /// Accelerometer and gyro scale-factor states (6 more states).
    pub scale_factor_states: bool,
    /// The lever arm, IMU time offset, velocity latency and mounting
    /// boresight as states (8 more; `coupling::InstallationEstimate`),
    /// from the configured values with the priors of
    /// `tuning.initial_std.installation`. Default off: the configured
    /// values are taken as exact.
    pub installation_states: bool,
    /// Also a fixed-interval smoothed solution (post-processing; see
    /// `filter::smoother`). Default off.
    pub smoother: bool,
    /// Alignment.
    pub alignment: AlignmentConfig,
    /// Initial stds given instead of the start's own.
    pub alignment_overrides: StartOverrides,
    /// Standstill detection.
    pub standstill: StandstillConfig,
    /// Aids.
    pub aids: AidsConfig,
    /// GNSS outages (start, length), s after the earliest start the log
    /// allows (its first GNSS epoch with `standstill.window_s` of IMU data
    /// before it): the log's own time, not the start the alignment finds (a
    /// late start does not move them); each must lie inside the run.
    pub outages: Vec<(f64, f64)>,
    /// Periodic outages (first start, length, period), s after that epoch;
    /// the windows that fit in the run (see [`periodic_outages`]).
    pub periodic_outages: Option<(f64, f64, f64)>,
    /// Satellites kept through the outages: 0 (total outages, the
    /// default), or 1-3 (partial: each epoch keeps its highest satellites,
    /// as the simulator's partial outages do; tight coupling only).
    pub outage_satellites: usize,
    /// Stop this many seconds after the start (None: the whole log).
    pub duration_s: Option<f64>,
}

/// The default fix-error process: 1 m with a 60 s correlation time, the
/// slow part of a consumer receiver's standalone fix (its error decorrelates
/// over the minute multipath and satellite geometry take to change).
pub const FIX_ERROR_DEFAULT: RangeBiasModel = RangeBiasModel {
    std_m: 1.0,
    correlation_time_s: 60.0,
};

impl LogConfig {
    /// A configuration with every default and this filter tuning, its
    /// receiver clock the `"consumer"` class
    /// ([`ReceiverClockModel::oscillator`]: real logs come from consumer
    /// receivers).
    pub fn new(mut tuning: FilterTuning) -> Self {
        tuning.set_receiver_clock(
            &ReceiverClockModel::oscillator("consumer").expect("a known class"),
        );
        Self {
            mounting: Matrix3::identity(),
            imu_time_offset_s: 0.0,
            reference_from_imu_b_m: Vector3::zeros(),
            tuning,
            range_bias_states: RangeBiasSlots::Shared,
            fix_error_states: false,
            fix_error: FIX_ERROR_DEFAULT,
            imu_candidates: Vec::new(),
            learn_fix_errors: true,
            scale_factor_states: false,
            installation_states: false,
            smoother: false,
            alignment: AlignmentConfig::default(),
            alignment_overrides: StartOverrides::default(),
            standstill: StandstillConfig::default(),
            aids: AidsConfig::default(),
            outages: Vec::new(),
            periodic_outages: None,
            outage_satellites: 0,
            duration_s: None,
        }
    }

    /// Checks every field (names the field at fault).
    pub fn validate(&self) -> Result<()> {
        validate::rotation("mounting", &self.mounting)?;
        validate::finite_scalars("imu.time_offset_s", &[self.imu_time_offset_s])?;
        validate::finite_vectors("reference_from_imu", &[self.reference_from_imu_b_m])?;
        self.tuning.validate()?;
        for (_, tuning) in &self.imu_candidates {
            tuning.validate()?;
        }
        validate::positive("gnss.fix_error_std_m", self.fix_error.std_m)?;
        validate::positive(
            "gnss.fix_error_correlation_time_s",
            self.fix_error.correlation_time_s,
        )?;
        let a = &self.alignment;
        if let AlignmentMethod::StaticHeading(h) = a.method {
            validate::finite_scalars("alignment.heading_deg", &[h])?;
        }
        validate::positive("alignment.min_speed_m_s", a.min_speed_m_s)?;
        validate::positive("alignment.max_course_std_deg", a.max_course_std_rad)?;
        validate::positive("alignment.level_window_s", a.level_window_s)?;
        validate::positive("alignment.heading_std_deg", a.heading_std_rad)?;
        validate::positive("alignment.tilt_std_deg", a.tilt_std_rad)?;
        let s = &self.standstill;
        for (name, v) in [
            ("standstill.window_s", s.window_s),
            ("standstill.accel_std_m_s2", s.accel_std_m_s2),
            ("standstill.gyro_std_deg_s", s.gyro_std_rad_s),
            ("standstill.gnss_speed_m_s", s.gnss_speed_m_s),
            ("standstill.gnss_age_s", s.gnss_age_s),
            ("standstill.solution_speed_m_s", s.solution_speed_m_s),
        ] {
            validate::positive(name, v)?;
        }
        validate::non_negative("standstill.solution_speed_sigmas", s.solution_speed_sigmas)?;
        let x = &self.aids;
        for (name, v) in [
            ("aids.zupt_std_m_s", x.zupt_std_m_s),
            ("aids.zupt_interval_s", x.zupt_interval_s),
            ("aids.zaru_min_std_deg_s", x.zaru_min_std_rad_s),
            ("aids.nhc_std_m_s", x.nhc_std_m_s),
            ("aids.nhc_interval_s", x.nhc_interval_s),
        ] {
            validate::positive(name, v)?;
        }
        validate::non_negative("aids.nhc_min_speed_m_s", x.nhc_min_speed_m_s)?;
        for (i, &(start, length)) in self.outages.iter().enumerate() {
            if !(start.is_finite() && start >= 0.0 && length.is_finite() && length > 0.0) {
                return Err(Error::invalid(
                    "outages",
                    format!("window {i} is [{start}, {length}]: start must be ≥ 0 s and length > 0 s, both finite"),
                ));
            }
        }
        if let Some(d) = self.duration_s {
            validate::positive("duration_s", d)?;
        }
        if self.outage_satellites > 3 {
            return Err(Error::invalid(
                "outages.keep_satellites",
                format!("must be 0, 1, 2 or 3, got {}", self.outage_satellites),
            ));
        }
        Ok(())
    }
}

/// C_b^s from a chain of roll, pitch, yaw triples (rad), applied in order:
/// f_b = C(last) ··· C(first) f_s, each C the body-to-reference rotation
/// of its triple ([`euler_to_dcm`]): the first triple is the sensor's
/// attitude relative to an intermediate frame, the last that frame's (or
/// the previous one's) relative to the body.
pub fn mounting_matrix(rpy_rad: &[[f64; 3]]) -> Result<Matrix3<f64>> {
    let mut c = Matrix3::identity();
    for (i, t) in rpy_rad.iter().enumerate() {
        validate::finite_scalars(&format!("mounting_rpy[{i}]"), t)?;
        c = euler_to_dcm(t[0], t[1], t[2]) * c;
    }
    Ok(c)
}

/// Outage windows (start, length) every `every_s` seconds, each
/// `length_s` long, from `first_s` until `last_end_s` (windows that would
/// end later are left out): a schedule that samples a log evenly.
pub fn periodic_outages(
    first_s: f64,
    length_s: f64,
    every_s: f64,
    last_end_s: f64,
) -> Result<Vec<(f64, f64)>> {
    validate::non_negative("outages.first_s", first_s)?;
    validate::positive("outages.length_s", length_s)?;
    validate::positive("outages.every_s", every_s)?;
    validate::finite_scalars("outages.last_end_s", &[last_end_s])?;
    if every_s < length_s {
        return Err(Error::invalid(
            "outages.every_s",
            format!(
                "{every_s} s is shorter than the outage length {length_s} s: windows would overlap"
            ),
        ));
    }
    let count = ((last_end_s - first_s - length_s) / every_s).floor();
    if count > 1.0e5 {
        return Err(Error::invalid(
            "outages",
            format!("{count} windows: more than 100 000"),
        ));
    }
    Ok((0..=count.max(-1.0) as i64)
        .map(|i| (first_s + i as f64 * every_s, length_s))
        .filter(|(s, l)| s + l <= last_end_s)
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn periodic_outages_fit_the_log() {
        let w = periodic_outages(30.0, 15.0, 60.0, 200.0).unwrap();
        assert_eq!(w, vec![(30.0, 15.0), (90.0, 15.0), (150.0, 15.0)]);
        assert!(periodic_outages(30.0, 15.0, 60.0, 40.0).unwrap().is_empty());
        assert!(periodic_outages(0.0, 20.0, 10.0, 100.0).is_err());
    }

    /// The drive's mounting: (180, 0, 180) then (0, −6.79, 5.35) degrees.
    /// Sensor z up, x backward turns into body z down, x forward.
    #[test]
    fn mounting_chain_applies_in_order() {
        let d = |v: f64| v.to_radians();
        let c = mounting_matrix(&[[d(180.0), 0.0, d(180.0)]]).unwrap();
        let f_s = Vector3::new(0.0, 0.0, 9.8); // at rest, z up reads +g
        assert!((c * f_s - Vector3::new(0.0, 0.0, -9.8)).norm() < 1e-12);
        let two = mounting_matrix(&[[d(180.0), 0.0, d(180.0)], [0.0, d(-6.79), d(5.35)]]).unwrap();
        let expected = euler_to_dcm(0.0, d(-6.79), d(5.35)) * c;
        assert!((two - expected).abs().max() < 1e-15);
        assert!(mounting_matrix(&[[f64::NAN, 0.0, 0.0]]).is_err());
    }
}
