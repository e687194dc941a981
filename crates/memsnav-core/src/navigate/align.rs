//! Where and how a log's navigation starts.
//!
//! - **Static start** (the log begins at rest, [`AlignmentMethod::Auto`]):
//!   at the first GNSS epoch, with zero velocity, roll and pitch levelled
//!   from the standstill's mean specific force (Groves eq. 5.101), and the
//!   heading unknown (a wide heading uncertainty) until the first motion,
//!   when the run sets it from the GNSS course (`super::run`); meanwhile
//!   ZUPT and ZARU settle the velocity, tilt and biases. At rest means the
//!   IMU at rest by the standstill detector's statistics
//!   ([`super::standstill`]) and the GNSS velocity not showing motion
//!   ([`GnssKinematics::shows_motion`]): a velocity too noisy to tell a
//!   standstill from a crawl (position differences of metre-class fixes)
//!   leaves the decision to the IMU. A log that is not at rest at its
//!   first epoch starts at the first epoch at rest or the first fit for an
//!   in-motion start, whichever comes first, and says why it did not
//!   start earlier ([`StartDelay`]).
//! - **Static start with a heading** ([`AlignmentMethod::StaticHeading`]):
//!   the same with the heading given.
//! - **In-motion start**: at the first GNSS epoch at `min_speed_m_s` or
//!   faster whose course is known to `max_course_std_rad`, heading from
//!   that course over ground (the body's x axis taken along the direction
//!   of travel), levelled from the mean specific force of the
//!   `level_window_s` before it (gentle motion: an error of about a/g rad).

use nalgebra::{Matrix3, Vector3};

use super::config::{AlignmentMethod, LogConfig};
use super::standstill::stats;
use crate::attitude::euler_to_dcm;
use crate::coupling::{level, InitialState};
use crate::geodesy::{c_n_e, ecef_to_geodetic};
use crate::ins::{ImuSample, NavState};
use crate::{Error, Result};

/// One GNSS epoch as alignment and the standstill test see it: the
/// antenna's position and velocity (from a fix, or a least-squares fix of
/// the pseudoranges), with covariances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GnssKinematics {
    /// Epoch time, s.
    pub time_s: f64,
    /// Antenna position, ECEF, m (NaN when the epoch has no fix).
    pub position_ecef: Vector3<f64>,
    /// Its covariance, m².
    pub position_covariance: Matrix3<f64>,
    /// Antenna velocity, ECEF, m/s, when known (of a horizontal-only fix,
    /// zero along the local vertical, which it does not measure).
    pub velocity_ecef: Option<Vector3<f64>>,
    /// Its covariance, m²/s² (only its horizontal part is read).
    pub velocity_covariance: Matrix3<f64>,
    /// Whether the velocity is the difference of two positions (the fixes
    /// have none), not the receiver's own.
    pub velocity_from_positions: bool,
}

/// A start more than this after the earliest the log allows is late, s:
/// reported with its reason ([`StartDelay`]). A shorter wait is the
/// in-motion start at work on a log that begins slowly (the drive excerpt
/// of the tests, creeping below 1 m/s, starts 1.5 s in); the summary still
/// gives the start's place in the log.
pub const LATE_START_S: f64 = 10.0;

/// How many of its own one-sigmas a GNSS ground speed must lie from zero to
/// show motion: the speed of a velocity at rest, Rayleigh distributed, passes
/// 3σ at one epoch in 90 (e^(−4.5)).
pub const MOTION_SIGMAS: f64 = 3.0;

impl GnssKinematics {
    /// An epoch without a fix (NaN position and covariances).
    pub fn none(time_s: f64) -> Self {
        Self {
            time_s,
            position_ecef: Vector3::from_element(f64::NAN),
            position_covariance: Matrix3::from_element(f64::NAN),
            velocity_ecef: None,
            velocity_covariance: Matrix3::from_element(f64::NAN),
            velocity_from_positions: false,
        }
    }

    fn valid(&self) -> bool {
        self.position_ecef.iter().all(|v| v.is_finite()) && self.position_ecef.norm() > 6.0e6
    }

    /// Ground speed, course over ground (rad from north) and the course's
    /// one-sigma (rad) from the horizontal velocity and its covariance.
    pub fn course(&self) -> Option<(f64, f64, f64)> {
        let (v_ne, sigma_h) = self.horizontal_velocity()?;
        let speed = v_ne.norm();
        Some((
            speed,
            v_ne.y.atan2(v_ne.x),
            (sigma_h / speed.max(1e-9)).atan(),
        ))
    }

    /// North and east velocity, m/s, and the one-sigma of each (the RMS of
    /// the two variances), m/s; None without a finite velocity.
    fn horizontal_velocity(&self) -> Option<(nalgebra::Vector2<f64>, f64)> {
        let v = self.velocity_ecef?;
        let geo = ecef_to_geodetic(&self.position_ecef);
        let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
        let v_ned = cne.transpose() * v;
        let cov = cne.transpose() * self.velocity_covariance * cne;
        let sigma_h = (0.5 * (cov[(0, 0)] + cov[(1, 1)])).max(0.0).sqrt();
        let v_ne = v_ned.xy();
        v_ne.iter()
            .all(|x| x.is_finite())
            .then_some((v_ne, sigma_h))
    }

    /// Whether the velocity shows the antenna moving: a ground speed of at
    /// least `speed_m_s` and more than [`MOTION_SIGMAS`] of its one-sigma
    /// from zero. A speed the velocity's own noise could give at rest (a
    /// difference of two metre-class positions: metres per second) shows
    /// nothing; without a velocity, nothing either.
    pub fn shows_motion(&self, speed_m_s: f64) -> bool {
        self.horizontal_velocity().is_some_and(|(v_ne, sigma_h)| {
            let speed = v_ne.norm();
            speed >= speed_m_s && speed > MOTION_SIGMAS * sigma_h
        })
    }
}

/// How the run started.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StartKind {
    /// At rest, heading from the first motion.
    Static,
    /// At rest, heading given.
    StaticWithHeading,
    /// Moving, heading from the course.
    Moving,
}

impl StartKind {
    /// `"static"`, `"static_with_heading"`, `"moving"`.
    pub fn name(self) -> &'static str {
        match self {
            StartKind::Static => "static",
            StartKind::StaticWithHeading => "static_with_heading",
            StartKind::Moving => "moving",
        }
    }
}

/// Where navigation starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Start {
    /// How.
    pub kind: StartKind,
    /// The GNSS epoch it starts at.
    pub epoch: usize,
    /// That epoch's time, s.
    pub time_s: f64,
    /// The last IMU sample at or before it.
    pub first_sample: usize,
    /// The state of the antenna's body at `first_sample`: position of the
    /// antenna (the lever arm is applied by the run), velocity, attitude.
    pub antenna: NavState,
    /// Initial one-sigma of the position, m.
    pub position_std_m: f64,
    /// Initial one-sigma of the velocity, m/s.
    pub velocity_std_m_s: f64,
    /// Initial one-sigma of the tilt, rad.
    pub tilt_std_rad: f64,
    /// Initial one-sigma of the heading, rad.
    pub heading_std_rad: f64,
    /// Whether the heading is known (false: set at the first motion).
    pub heading_known: bool,
    /// The log's first IMU sample, on GNSS time, s (the start is `time_s`
    /// minus this after it).
    pub first_imu_time_s: f64,
    /// The log's first GNSS epoch, s.
    pub first_gnss_time_s: f64,
    /// The earliest start the log allows: its first GNSS epoch with
    /// `standstill.window_s` of IMU data before it, s. The log's own time,
    /// whatever the alignment decides: the scheduled outages count from it.
    pub earliest_time_s: f64,
    /// Why the start is more than [`LATE_START_S`] later than the earliest
    /// the log allowed (None: it is not).
    pub delay: Option<StartDelay>,
}

impl Start {
    /// The filter's initial state at `first_sample`: the IMU's position
    /// (the antenna's less the lever arm `antenna_lever_arm_b_m`, body
    /// axes, m), velocity and attitude, zero sensor biases, the clock from
    /// the first epoch the filter uses.
    pub fn initial_state(&self, antenna_lever_arm_b_m: &Vector3<f64>) -> InitialState {
        InitialState {
            nav: NavState {
                position_ecef: self.antenna.position_ecef
                    - self.antenna.c_b_e * antenna_lever_arm_b_m,
                ..self.antenna
            },
            accel_bias_m_s2: Vector3::zeros(),
            gyro_bias_rad_s: Vector3::zeros(),
            clock_offset_m: None,
            clock_drift_m_s: None,
        }
    }
}

/// What the epochs before a late start showed: why none of them was a
/// start. Counted from the first epoch the log allows a start at (the
/// first with `standstill.window_s` of IMU data before it) to the start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StartDelay {
    /// The alignment method (what a start needed).
    pub method: AlignmentMethod,
    /// The first epoch's time, s.
    pub first_possible_s: f64,
    /// Epochs from it to the start.
    pub epochs: usize,
    /// Of them, without a fix (no position, or too few satellites).
    pub no_fix: usize,
    /// With the IMU moving by the standstill detector's statistics.
    pub imu_moving: usize,
    /// With the IMU at rest but the GNSS velocity showing motion.
    pub gnss_moving: usize,
    /// Without a GNSS velocity.
    pub no_velocity: usize,
    /// Slower than `alignment.min_speed_m_s`.
    pub too_slow: usize,
    /// With a course σ above `alignment.max_course_std_deg`.
    pub course_unknown: usize,
    /// With a velocity only from position differences (the fixes have
    /// none).
    pub velocity_from_positions: usize,
    /// The median one-sigma of the GNSS velocity per horizontal axis over
    /// the epochs that had one, m/s (NaN: none had).
    pub median_velocity_std_m_s: f64,
}

impl StartDelay {
    /// In words: what the epochs before the start lacked.
    pub fn reason(&self, config: &LogConfig) -> String {
        let a = &config.alignment;
        let mut parts = Vec::new();
        if self.no_fix > 0 {
            parts.push(format!("{} had no fix", self.no_fix));
        }
        if matches!(self.method, AlignmentMethod::Auto) {
            parts.push(format!(
                "none was at rest (the IMU moved at {} by its standstill statistics; the GNSS velocity showed motion at {} where it did not)",
                self.imu_moving, self.gnss_moving
            ));
        }
        if !matches!(self.method, AlignmentMethod::StaticHeading(_)) {
            let mut lacks = vec![format!("{} had no GNSS velocity", self.no_velocity)];
            if self.velocity_from_positions > 0 {
                lacks.push(format!(
                    "{} a velocity only from position differences",
                    self.velocity_from_positions
                ));
            }
            lacks.push(format!(
                "{} a ground speed below alignment.min_speed_m_s = {} m/s",
                self.too_slow, a.min_speed_m_s
            ));
            lacks.push(format!(
                "{} a course σ above alignment.max_course_std_deg = {}°",
                self.course_unknown,
                a.max_course_std_rad.to_degrees()
            ));
            let velocity_std = if self.median_velocity_std_m_s.is_finite() {
                format!(
                    " (median GNSS velocity σ {:.2} m/s)",
                    self.median_velocity_std_m_s
                )
            } else {
                String::new()
            };
            parts.push(format!(
                "none could start in motion: {}{velocity_std}",
                lacks.join(", ")
            ));
        }
        format!(
            "of the {} GNSS epochs from t = {:.3} s (the first with standstill.window_s = {} s of IMU data before it), {}",
            self.epochs,
            self.first_possible_s,
            config.standstill.window_s,
            parts.join("; ")
        )
    }
}

/// Position uncertainty at the start, m per axis (see [`find_start`]).
pub const START_POSITION_STD_M: f64 = 30.0;

/// Velocity uncertainty at an in-motion start, m/s per axis.
pub const START_VELOCITY_STD_M_S: f64 = 2.0;

/// Heading uncertainty while it is unknown, rad: wide enough for any
/// heading, and harmless while at rest (a heading error changes no
/// prediction of a body whose specific force is vertical).
pub const UNKNOWN_HEADING_STD_RAD: f64 = 1.0;

/// Why an epoch is not a static start.
enum Rest {
    /// At rest: the window's mean specific force.
    Yes(Vector3<f64>),
    NoFix,
    ImuMoving,
    GnssMoving,
}

/// Why an epoch is not an in-motion start.
enum Motion {
    /// Moving with a course: the levelling window's mean specific force.
    Yes(Vector3<f64>),
    NoFix,
    NoVelocity,
    TooSlow,
    CourseUnknown,
    /// No `level_window_s` of IMU data before it.
    NoWindow,
}

/// Decides the start from the IMU (body axes, on GNSS time) and the GNSS
/// epochs.
pub fn find_start(
    time_s: &[f64],
    imu_b: &[ImuSample],
    gnss: &[GnssKinematics],
    config: &LogConfig,
) -> Result<Start> {
    let a = &config.alignment;
    let window = |end_s: f64, length_s: f64| -> Option<std::ops::Range<usize>> {
        let end = time_s.partition_point(|t| *t <= end_s);
        let start = time_s.partition_point(|t| *t <= end_s - length_s);
        (end >= 2 && start + 2 <= end && time_s[0] <= end_s - length_s).then_some(start..end)
    };
    let rest_at = |i: usize| -> Rest {
        let g = &gnss[i];
        let Some(w) = window(g.time_s, config.standstill.window_s) else {
            return Rest::NoFix;
        };
        if !g.valid() {
            return Rest::NoFix;
        }
        let s = stats(imu_b[w].iter());
        if !s.still(&config.standstill) {
            Rest::ImuMoving
        } else if g.shows_motion(config.standstill.gnss_speed_m_s) {
            Rest::GnssMoving
        } else {
            Rest::Yes(s.mean_specific_force_b)
        }
    };
    let motion_at = |i: usize| -> Motion {
        let g = &gnss[i];
        if !g.valid() {
            return Motion::NoFix;
        }
        let Some((speed, _, course_std)) = g.course() else {
            return Motion::NoVelocity;
        };
        if speed < a.min_speed_m_s {
            return Motion::TooSlow;
        }
        if course_std > a.max_course_std_rad {
            return Motion::CourseUnknown;
        }
        match window(g.time_s, a.level_window_s) {
            Some(w) => Motion::Yes(stats(imu_b[w].iter()).mean_specific_force_b),
            None => Motion::NoWindow,
        }
    };
    let has_window = |i: usize| window(gnss[i].time_s, config.standstill.window_s).is_some();
    let first_possible = (0..gnss.len()).find(|&i| has_window(i));
    let first_valid =
        first_possible.and_then(|p| (p..gnss.len()).find(|&i| gnss[i].valid() && has_window(i)));
    let first_static = |from: usize| {
        (from..gnss.len()).find_map(|i| match rest_at(i) {
            Rest::Yes(f) => Some((i, f, None, StartKind::Static)),
            _ => None,
        })
    };
    let first_moving = || {
        (0..gnss.len()).find_map(|i| match motion_at(i) {
            Motion::Yes(f) => Some((i, f, None, StartKind::Moving)),
            _ => None,
        })
    };
    let chosen = match (a.method, first_valid) {
        (_, None) => None,
        (AlignmentMethod::StaticHeading(h), Some(i)) => {
            let w = window(gnss[i].time_s, config.standstill.window_s);
            w.map(|w| {
                (
                    i,
                    stats(imu_b[w].iter()).mean_specific_force_b,
                    Some(h),
                    StartKind::StaticWithHeading,
                )
            })
        }
        // At rest at the first epoch, else the earlier of the first epoch
        // at rest and the first in motion with a course.
        (AlignmentMethod::Auto, Some(i)) => match rest_at(i) {
            Rest::Yes(f) => Some((i, f, None, StartKind::Static)),
            _ => match (first_static(i + 1), first_moving()) {
                (Some(r), Some(m)) => Some(if r.0 < m.0 { r } else { m }),
                (r, m) => r.or(m),
            },
        },
        (AlignmentMethod::Moving, Some(_)) => first_moving(),
    };
    let delay = |end: usize| -> Option<StartDelay> {
        let first = first_possible?;
        let late = gnss
            .get(end)
            .is_none_or(|g| g.time_s - gnss[first].time_s > LATE_START_S);
        (end > first && late).then(|| {
            let mut d = StartDelay {
                method: a.method,
                first_possible_s: gnss[first].time_s,
                epochs: end - first,
                no_fix: 0,
                imu_moving: 0,
                gnss_moving: 0,
                no_velocity: 0,
                too_slow: 0,
                course_unknown: 0,
                velocity_from_positions: 0,
                median_velocity_std_m_s: f64::NAN,
            };
            let mut velocity_std = Vec::new();
            for (i, g) in gnss.iter().enumerate().take(end).skip(first) {
                match rest_at(i) {
                    Rest::ImuMoving => d.imu_moving += 1,
                    Rest::GnssMoving => d.gnss_moving += 1,
                    Rest::NoFix => d.no_fix += 1,
                    Rest::Yes(_) => {}
                }
                match motion_at(i) {
                    Motion::NoVelocity => d.no_velocity += 1,
                    Motion::TooSlow => d.too_slow += 1,
                    Motion::CourseUnknown => d.course_unknown += 1,
                    Motion::Yes(_) | Motion::NoFix | Motion::NoWindow => {}
                }
                if let Some((_, std)) = g.horizontal_velocity().filter(|_| g.valid()) {
                    velocity_std.push(std);
                    d.velocity_from_positions += usize::from(g.velocity_from_positions);
                }
            }
            if !velocity_std.is_empty() {
                velocity_std.sort_by(f64::total_cmp);
                d.median_velocity_std_m_s = velocity_std[velocity_std.len() / 2];
            }
            d
        })
    };
    let Some((i, mean_f, heading, kind)) = chosen else {
        let why = delay(gnss.len()).map_or_else(
            || {
                format!(
                    "no GNSS epoch has standstill.window_s = {} s of IMU data before it",
                    config.standstill.window_s
                )
            },
            |d| d.reason(config),
        );
        return Err(Error::invalid(
            "gnss",
            format!(
                "no epoch to start from: the log is neither at rest at a GNSS fix nor ever moving at {} m/s or faster with {} s of IMU data before: {why}",
                a.min_speed_m_s, a.level_window_s
            ),
        ));
    };
    let g = &gnss[i];
    let (roll, pitch) = level(&mean_f)?;
    let geo = ecef_to_geodetic(&g.position_ecef);
    let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
    let moving = kind == StartKind::Moving;
    let (course_heading, course_std) = match g.course() {
        Some((_, c, s)) if moving => (c, s),
        _ => (0.0, 0.0),
    };
    let yaw = heading.unwrap_or(course_heading);
    let first_sample = time_s.partition_point(|t| *t <= g.time_s).saturating_sub(1);
    let velocity = if moving {
        g.velocity_ecef.unwrap_or_else(Vector3::zeros)
    } else {
        Vector3::zeros()
    };
    let position = g.position_ecef - velocity * (g.time_s - time_s[first_sample]);
    // The start epoch's fix is a linearisation point, not a measurement:
    // the epoch itself is the filter's first update, so the start is given
    // a wide uncertainty and that update sets position (and velocity) and
    // their correlation with the clock and the range biases, instead of
    // counting the same measurements twice.
    let position_std = START_POSITION_STD_M;
    let velocity_std = if moving {
        START_VELOCITY_STD_M_S
    } else {
        config.aids.zupt_std_m_s
    };
    Ok(Start {
        kind,
        epoch: i,
        time_s: g.time_s,
        first_sample,
        antenna: NavState {
            position_ecef: position,
            velocity_ecef: velocity,
            c_b_e: cne * euler_to_dcm(roll, pitch, yaw),
        },
        position_std_m: position_std,
        velocity_std_m_s: velocity_std,
        tilt_std_rad: a.tilt_std_rad,
        heading_std_rad: match kind {
            StartKind::Static => UNKNOWN_HEADING_STD_RAD,
            StartKind::StaticWithHeading => a.heading_std_rad,
            StartKind::Moving => a.heading_std_rad.hypot(course_std),
        },
        heading_known: kind != StartKind::Static,
        first_imu_time_s: time_s[0],
        first_gnss_time_s: gnss[0].time_s,
        earliest_time_s: first_possible.map_or(g.time_s, |p| gnss[p].time_s),
        delay: delay(i),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geodesy::{geodetic_to_ecef, Geodetic};

    /// 30 s at 100 Hz, the IMU moving (m/s² and rad/s of vibration) before
    /// `moving_until_s` and quiet (centimetres per second squared) after,
    /// specific force up; GNSS epochs at whole seconds at a fixed point
    /// with `velocity` (ECEF, covariance, from positions).
    fn log(
        moving_until_s: f64,
        velocity: Option<(Vector3<f64>, Matrix3<f64>, bool)>,
    ) -> (Vec<f64>, Vec<ImuSample>, Vec<GnssKinematics>) {
        let time: Vec<f64> = (0..=3000).map(|k| k as f64 / 100.0).collect();
        let imu = time
            .iter()
            .enumerate()
            .map(|(k, &t)| {
                let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
                let (f, w) = if t < moving_until_s {
                    (2.0, 0.2)
                } else {
                    (0.01, 0.001)
                };
                ImuSample {
                    specific_force_b: Vector3::new(sign * f, 0.0, -9.8),
                    angular_rate_b: Vector3::new(0.0, sign * w, 0.0),
                }
            })
            .collect();
        let position = geodetic_to_ecef(Geodetic::new(0.8, 0.2, 100.0));
        let gnss = (0..=30)
            .map(|k| GnssKinematics {
                time_s: k as f64,
                position_ecef: position,
                position_covariance: Matrix3::identity(),
                velocity_ecef: velocity.map(|v| v.0),
                velocity_covariance: velocity.map_or(Matrix3::zeros(), |v| v.1),
                velocity_from_positions: velocity.is_some_and(|v| v.2),
            })
            .collect();
        (time, imu, gnss)
    }

    fn config() -> LogConfig {
        LogConfig::from_settings(&[], 100.0).unwrap()
    }

    /// A quiet IMU with a velocity of position differences (3 m/s of
    /// noise, σ 4.5 m/s: metre-class fixes a second apart) starts static at
    /// the first epoch with a second of IMU before it; the same IMU with a
    /// precise 0.5 m/s (σ 0.02 m/s) is vetoed, and with no epoch fast
    /// enough for a course there is no start: the error says what the
    /// epochs showed.
    #[test]
    fn a_quiet_imu_starts_static_unless_the_gnss_shows_motion() {
        let east = c_n_e(0.8, 0.2).column(1).into_owned();
        let noisy = (east * 3.0, Matrix3::identity() * 4.5 * 4.5, true);
        let (t, imu, gnss) = log(0.0, Some(noisy));
        let start = find_start(&t, &imu, &gnss, &config()).unwrap();
        assert_eq!((start.kind, start.epoch), (StartKind::Static, 1));
        assert_eq!((start.earliest_time_s, start.first_gnss_time_s), (1.0, 0.0));
        assert!(start.delay.is_none());
        assert!(!gnss[1].shows_motion(0.2) && gnss[1].course().unwrap().0 > 0.2);

        let precise = (east * 0.5, Matrix3::identity() * 0.02 * 0.02, false);
        let (t, imu, gnss) = log(0.0, Some(precise));
        assert!(gnss[1].shows_motion(0.2));
        let e = find_start(&t, &imu, &gnss, &config())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("of the 30 GNSS epochs from t = 1.000 s")
                && e.contains("the IMU moved at 0")
                && e.contains("the GNSS velocity showed motion at 30")
                && e.contains("30 a ground speed below alignment.min_speed_m_s = 1 m/s"),
            "{e}"
        );
    }

    /// No GNSS velocity and the IMU moving until 5 s, or 15 s: the run
    /// starts static at 6 s, or 16 s (the first epoch whose one-second
    /// window is quiet). 5 s after the earliest start is not late; 15 s is,
    /// and the delay counts what the epochs before it lacked.
    #[test]
    fn a_late_start_counts_what_the_epochs_before_it_lacked() {
        let config = config();
        let (t, imu, gnss) = log(5.0, None);
        let start = find_start(&t, &imu, &gnss, &config).unwrap();
        assert_eq!((start.kind, start.time_s), (StartKind::Static, 6.0));
        assert!(start.delay.is_none());
        let (t, imu, gnss) = log(15.0, None);
        let start = find_start(&t, &imu, &gnss, &config).unwrap();
        assert_eq!((start.kind, start.time_s), (StartKind::Static, 16.0));
        let delay = start.delay.unwrap();
        assert_eq!(
            (
                delay.epochs,
                delay.imu_moving,
                delay.gnss_moving,
                delay.no_velocity
            ),
            (15, 15, 0, 15)
        );
        assert_eq!(delay.first_possible_s, 1.0);
        let reason = delay.reason(&config);
        assert!(
            reason.starts_with("of the 15 GNSS epochs from t = 1.000 s")
                && reason.contains("the IMU moved at 15")
                && reason.contains("15 had no GNSS velocity"),
            "{reason}"
        );
    }
}
