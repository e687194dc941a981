//! Where and how a log's navigation starts.
//!
//! - **Static start** (the log begins at rest, [`AlignmentMethod::Auto`]):
//!   at the first GNSS epoch, with zero velocity, roll and pitch levelled
//!   from the standstill's mean specific force (Groves eq. 5.101), and the
//!   heading unknown (a wide heading uncertainty) until the first motion,
//!   when the run sets it from the GNSS course ([`super::run`]); meanwhile
//!   ZUPT and ZARU settle the velocity, tilt and biases.
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
use crate::coupling::level;
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
    /// Antenna velocity, ECEF, m/s, when known.
    pub velocity_ecef: Option<Vector3<f64>>,
    /// Its covariance, m²/s².
    pub velocity_covariance: Matrix3<f64>,
}

impl GnssKinematics {
    /// An epoch without a fix (NaN position and covariances).
    pub fn none(time_s: f64) -> Self {
        Self {
            time_s,
            position_ecef: Vector3::from_element(f64::NAN),
            position_covariance: Matrix3::from_element(f64::NAN),
            velocity_ecef: None,
            velocity_covariance: Matrix3::from_element(f64::NAN),
        }
    }

    fn valid(&self) -> bool {
        self.position_ecef.iter().all(|v| v.is_finite()) && self.position_ecef.norm() > 6.0e6
    }

    /// Ground speed, course over ground (rad from north) and the course's
    /// one-sigma (rad) from the horizontal velocity and its covariance.
    pub fn course(&self) -> Option<(f64, f64, f64)> {
        let v = self.velocity_ecef?;
        let geo = ecef_to_geodetic(&self.position_ecef);
        let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
        let v_ned = cne.transpose() * v;
        let cov = cne.transpose() * self.velocity_covariance * cne;
        let speed = v_ned.x.hypot(v_ned.y);
        let sigma_h = (0.5 * (cov[(0, 0)] + cov[(1, 1)])).max(0.0).sqrt();
        speed.is_finite().then(|| {
            (
                speed,
                v_ned.y.atan2(v_ned.x),
                (sigma_h / speed.max(1e-9)).atan(),
            )
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
    /// Initial one-sigmas: position m, velocity m/s, tilt and heading rad.
    pub position_std_m: f64,
    pub velocity_std_m_s: f64,
    pub tilt_std_rad: f64,
    pub heading_std_rad: f64,
    /// Whether the heading is known (false: set at the first motion).
    pub heading_known: bool,
}

/// Position uncertainty at the start, m per axis (see [`find_start`]).
pub const START_POSITION_STD_M: f64 = 30.0;

/// Velocity uncertainty at an in-motion start, m/s per axis.
pub const START_VELOCITY_STD_M_S: f64 = 2.0;

/// Heading uncertainty while it is unknown, rad: wide enough for any
/// heading, and harmless while at rest (a heading error changes no
/// prediction of a body whose specific force is vertical).
pub const UNKNOWN_HEADING_STD_RAD: f64 = 1.0;

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
    let first_valid = gnss
        .iter()
        .position(|g| g.valid() && window(g.time_s, config.standstill.window_s).is_some());
    let static_at = |i: usize| -> Option<(usize, Vector3<f64>)> {
        let g = &gnss[i];
        let w = window(g.time_s, config.standstill.window_s)?;
        let s = stats(imu_b[w].iter());
        let slow = g
            .course()
            .is_none_or(|(speed, _, _)| speed < config.standstill.gnss_speed_m_s);
        (s.still(&config.standstill) && slow).then_some((i, s.mean_specific_force_b))
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
        (AlignmentMethod::Auto, Some(i)) => static_at(i)
            .map(|(i, f)| (i, f, None, StartKind::Static))
            .or_else(|| moving_start(gnss, imu_b, &window, config)),
        (AlignmentMethod::Moving, Some(_)) => moving_start(gnss, imu_b, &window, config),
    };
    let Some((i, mean_f, heading, kind)) = chosen else {
        return Err(Error::invalid(
            "gnss",
            format!(
                "no epoch to start from: the log is neither at rest at its first GNSS fix nor ever moving at {} m/s or faster with {} s of IMU data before",
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
    })
}

/// The first epoch at `min_speed_m_s` or faster with a levelling window.
fn moving_start(
    gnss: &[GnssKinematics],
    imu_b: &[ImuSample],
    window: &dyn Fn(f64, f64) -> Option<std::ops::Range<usize>>,
    config: &LogConfig,
) -> Option<(usize, Vector3<f64>, Option<f64>, StartKind)> {
    let a = &config.alignment;
    gnss.iter().enumerate().find_map(|(i, g)| {
        let (speed, _, course_std) = g.course()?;
        if !g.valid() || speed < a.min_speed_m_s || course_std > a.max_course_std_rad {
            return None;
        }
        let w = window(g.time_s, a.level_window_s)?;
        Some((
            i,
            stats(imu_b[w].iter()).mean_specific_force_b,
            None,
            StartKind::Moving,
        ))
    })
}
