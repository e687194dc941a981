//! The aids a configuration applies at every IMU sample besides the GNSS
//! updates (`[aids]`, `[standstill]`): standstills detected from the IMU
//! window, the GNSS ground speed and the solution, with zero-velocity and
//! zero-angular-rate updates there, the non-holonomic constraint while
//! moving, and, until the heading is known, its alignment from the GNSS
//! course at the first motion. A log run and the filter classes on the
//! caller's arrays apply the same ones.

use super::align::GnssKinematics;
use super::config::LogConfig;
use super::standstill::{Window, WindowStats};
use crate::coupling::{FilterState, SampleAid};
use crate::filter::chi_square::chi_square_quantile;
use crate::filter::state::VELOCITY;
use crate::ins::ImuSample;
use crate::Result;

/// Whether the heading is known at the start and, until it is, the
/// one-sigmas the filter holds for it and for the tilt.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct HeadingUntilAligned {
    /// The heading is known from the start (a static start with a given
    /// heading, a moving start, the caller's initial state).
    pub known: bool,
    /// Heading std while unknown, rad.
    pub heading_std_rad: f64,
    /// Tilt std reopened once the heading is aligned, rad.
    pub tilt_std_rad: f64,
}

impl HeadingUntilAligned {
    /// A heading known from the start.
    pub(crate) const KNOWN: Self = Self {
        known: true,
        heading_std_rad: 0.0,
        tilt_std_rad: 0.0,
    };
}

/// The aids and the heading alignment of a run, at every IMU sample.
pub(crate) struct SampleAids<'a> {
    time: &'a [f64],
    imu_b: &'a [ImuSample],
    /// Every GNSS epoch's antenna position and velocity, and whether it
    /// reached the filter.
    kinematics: &'a [GnssKinematics],
    used: &'a [bool],
    config: &'a LogConfig,
    heading: HeadingUntilAligned,
    window: Window,
    /// Next GNSS epoch (into `kinematics`) not yet seen.
    next_epoch: usize,
    /// Time, ground speed, course and its std of the last used GNSS epoch with a velocity.
    last_course: Option<(f64, f64, f64, f64)>,
    still: bool,
    next_decision_s: f64,
    next_zupt_s: f64,
    next_zaru_s: f64,
    next_nhc_s: f64,
    /// The non-holonomic constraint's std, m/s (the configured one or the
    /// one learnt from the log).
    nhc_std_m_s: f64,
}

impl<'a> SampleAids<'a> {
    /// The aids of `config` over the IMU samples `imu_b` at `time` (s) and
    /// the GNSS epochs' `kinematics` (those `used` reach the filter).
    pub(crate) fn new(
        time: &'a [f64],
        imu_b: &'a [ImuSample],
        kinematics: &'a [GnssKinematics],
        used: &'a [bool],
        config: &'a LogConfig,
        heading: HeadingUntilAligned,
        nhc_std_m_s: f64,
    ) -> Self {
        let rate_hz = (time.len() - 1) as f64 / (time[time.len() - 1] - time[0]);
        Self {
            time,
            imu_b,
            kinematics,
            used,
            config,
            heading,
            window: Window::new(config.standstill.window_s, rate_hz),
            next_epoch: 0,
            last_course: None,
            still: false,
            next_decision_s: f64::NEG_INFINITY,
            next_zupt_s: f64::NEG_INFINITY,
            next_zaru_s: f64::NEG_INFINITY,
            next_nhc_s: f64::NEG_INFINITY,
            nhc_std_m_s,
        }
    }

    /// The time of IMU sample `k`, s.
    pub(crate) fn time_s(&self, k: usize) -> f64 {
        self.time[k]
    }

    /// Whether the vehicle may be at rest besides a quiet IMU: its
    /// acceleration over the detector window consistent with zero
    /// ([`FilterState::rest_acceleration_nis`] at the gate probability: a
    /// car braking smoothly through its last metre per second, or pulling
    /// away while the last 1 Hz fix still says zero, is quiet but not at
    /// rest, and a ZUPT there leaves the velocity wrong), and the latest
    /// GNSS ground speed below its threshold, or without a recent GNSS
    /// velocity (an outage) the solution's speed below its threshold or
    /// within `solution_speed_sigmas` of its own along-track σ of zero (a
    /// coasting solution that cannot tell its speed from zero does not
    /// veto a quiet IMU; the ZUPT's own batch test then weighs the two).
    fn slow<const N: usize>(&self, t: f64, state: &FilterState<N>, window: &WindowStats) -> bool {
        let c = &self.config.standstill;
        let p = state.tuning.gate_probability;
        let std_of_mean = window.std_specific_force_b / (window.samples as f64).sqrt();
        let unaccelerated = p >= 1.0
            || state.rest_acceleration_nis(&window.mean_specific_force_b, &std_of_mean)
                <= chi_square_quantile(3.0, p);
        unaccelerated
            && match self.last_course {
                Some((tg, speed, _, _)) if t - tg <= c.gnss_age_s => speed < c.gnss_speed_m_s,
                _ => {
                    let v = state.nav.velocity_ecef;
                    let speed = v.norm();
                    if speed < c.solution_speed_m_s {
                        return true;
                    }
                    let along = v / speed;
                    let p_v = state.kf.p.fixed_view::<3, 3>(VELOCITY, VELOCITY);
                    let std_along = along.dot(&(p_v * along)).max(0.0).sqrt();
                    speed < c.solution_speed_sigmas * std_along
                }
            }
    }

    /// Sets the heading from the GNSS course at the first motion (speed at
    /// least `min_speed_m_s`, course known to `max_course_std_rad`), the
    /// body's x axis taken along the direction of travel. A vehicle that
    /// reverses out of its parking place needs `alignment.heading_deg`:
    /// nothing the filter holds by then tells forward from backward (the
    /// GNSS velocity updates of the unaligned phase have already mixed the
    /// wrong heading into the body-frame velocity).
    fn align_heading<const N: usize>(&mut self, t: f64, state: &mut FilterState<N>) -> Result<()> {
        let a = &self.config.alignment;
        let Some((_, speed, heading, course_std)) = self.last_course else {
            return Ok(());
        };
        if self.heading.known || speed < a.min_speed_m_s || course_std > a.max_course_std_rad {
            return Ok(());
        }
        state.align_heading(t, heading, a.heading_std_rad.hypot(course_std))?;
        state.reopen_tilt_and_horizontal_bias(self.heading.tilt_std_rad);
        self.heading.known = true;
        Ok(())
    }
}

impl SampleAid for SampleAids<'_> {
    fn at_sample<const N: usize>(&mut self, k: usize, state: &mut FilterState<N>) -> Result<()> {
        let t = self.time[k];
        self.window.push(self.imu_b[k]);
        let kin = self.kinematics;
        while self.next_epoch < kin.len() && kin[self.next_epoch].time_s <= t {
            let i = self.next_epoch;
            self.next_epoch += 1;
            if !self.used[i] {
                continue;
            }
            if let Some((speed, course, std)) = kin[i].course() {
                self.last_course = Some((kin[i].time_s, speed, course, std));
                self.align_heading(t, state)?;
            }
            if !self.heading.known {
                state.forget_heading(self.heading.heading_std_rad);
            }
        }
        let config = self.config;
        let aids = &config.aids;
        if t >= self.next_decision_s && self.window.full() {
            self.next_decision_s = t + aids.zupt_interval_s.min(config.standstill.window_s);
            let stats = self.window.stats();
            self.still = stats.still(&config.standstill) && self.slow(t, state, &stats);
            if self.still && aids.zaru && t >= self.next_zaru_s {
                let n = stats.samples as f64;
                let std = stats
                    .std_angular_rate_b
                    .map(|s| (s / n.sqrt()).max(aids.zaru_min_std_rad_s));
                // Each ZARU uses its own window of samples.
                state.zero_rate_update(t, &stats.mean_angular_rate_b, &std)?;
                self.next_zaru_s = t + config.standstill.window_s;
            }
        }
        if self.still {
            if aids.zupt && t >= self.next_zupt_s {
                state.zero_velocity_update(t, aids.zupt_std_m_s)?;
                self.next_zupt_s = t + aids.zupt_interval_s;
            }
        } else if aids.nhc
            && self.heading.known
            && t >= self.next_nhc_s
            && state.nav.velocity_ecef.norm() >= aids.nhc_min_speed_m_s
        {
            state.non_holonomic_update(t, &config.reference_from_imu_b_m, self.nhc_std_m_s)?;
            self.next_nhc_s = t + aids.nhc_interval_s;
        }
        Ok(())
    }
}
