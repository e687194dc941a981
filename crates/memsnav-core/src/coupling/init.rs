//! Initialisation from the first GNSS fix (tight) or position fix (loose)
//! and a given or coarse attitude.

use nalgebra::{Matrix3, Vector3};

use super::engine::{FilterState, InitialState};
use super::loose::PositionFix;
use super::records::{ResetKind, ResetRecord};
use crate::attitude::{dcm_to_euler, euler_to_dcm};
use crate::filter::state::{Installation, Layout, ACCEL_BIAS, ATTITUDE, POSITION};
use crate::geodesy::{c_n_e, ecef_to_geodetic};
use crate::gnss::{solve_fix_all_satellites, GnssEpoch};
use crate::ins::ImuData;
use crate::ins::NavState;
use crate::{validate, Error, Result};

/// Speed below which the GNSS velocity gives no usable heading, m/s.
pub const MIN_SPEED_FOR_HEADING_M_S: f64 = 1.0;

/// Roll and pitch, rad, from the mean specific force of a body at rest or
/// in gentle motion (Groves eq. 5.101: at rest f^b = −C_n^b g^n);
/// an error when it does not show gravity.
pub fn level(mean_specific_force_b: &Vector3<f64>) -> Result<(f64, f64)> {
    let f = mean_specific_force_b;
    if !f.iter().all(|v| v.is_finite()) || f.norm() <= 1.0 {
        return Err(Error::invalid(
            "specific_force",
            "the mean specific force does not show gravity: cannot level",
        ));
    }
    Ok((
        (-f.y).atan2(-f.z),
        f.x.atan2((f.y * f.y + f.z * f.z).sqrt()),
    ))
}

/// Coarse attitude C_b^e: roll and pitch by levelling the mean specific force
/// `mean_specific_force_b` (Groves eq. 5.101: at rest f^b = −C_n^b g^n), heading
/// from the course over ground of `velocity_ecef`. Levelling on a moving,
/// accelerating vehicle errs by about a/g rad, which the default initial
/// tilt uncertainty of 1° covers for gentle motion (a ≲ 0.17 m/s²).
pub fn coarse_attitude(
    mean_specific_force_b: &Vector3<f64>,
    position_ecef: &Vector3<f64>,
    velocity_ecef: &Vector3<f64>,
) -> Result<Matrix3<f64>> {
    let (roll, pitch) = level(mean_specific_force_b)?;
    let geo = ecef_to_geodetic(position_ecef);
    let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
    let v_ned = cne.transpose() * velocity_ecef;
    let speed = (v_ned.x * v_ned.x + v_ned.y * v_ned.y).sqrt();
    if speed.is_nan() || speed < MIN_SPEED_FOR_HEADING_M_S {
        return Err(Error::invalid(
            "initial_attitude",
            format!(
                "not given, and the ground speed {speed:.2} m/s is below {MIN_SPEED_FOR_HEADING_M_S} m/s: no heading from the GNSS velocity"
            ),
        ));
    }
    let yaw = v_ned.y.atan2(v_ned.x);
    Ok(cne * euler_to_dcm(roll, pitch, yaw))
}

/// The measurements of `epoch` a fix can use: finite pseudorange and
/// satellite position (NaN entries are the filter's to reject and report).
fn usable(epoch: &GnssEpoch) -> GnssEpoch {
    GnssEpoch {
        time_s: epoch.time_s,
        measurements: epoch
            .measurements
            .iter()
            .filter(|m| {
                m.pseudorange_m.is_finite() && m.position_ecef.iter().all(|x| x.is_finite())
            })
            .copied()
            .collect(),
    }
}

/// The initial state from the first GNSS epochs: position, velocity, clock
/// offset and drift of the least-squares fix ([`solve_fix_all_satellites`]) of the first
/// epoch, moved back to the first IMU time along the fix velocity; attitude
/// as given, else [`coarse_attitude`] from the IMU's first second; zero bias
/// estimates.
///
/// Without pseudorange rates in the first epoch the velocity and clock
/// drift come from the difference of the first two fixes (their error is
/// about √2·σ_position/Δt: raise the filter's initial velocity std
/// accordingly, e.g. 5 m/s for 3 m pseudoranges at 1 Hz).
pub fn initial_state_from_fix(
    epochs: &[GnssEpoch],
    imu: &ImuData,
    attitude: Option<Matrix3<f64>>,
) -> Result<InitialState> {
    imu.validate()?;
    let times: Vec<f64> = epochs.iter().map(|e| e.time_s).collect();
    validate::epochs_in_imu_span("gnss", &times, imu.time_s, 0.0)?;
    let first_epoch = usable(
        epochs
            .first()
            .ok_or_else(|| Error::invalid("gnss", "has no epochs"))?,
    );
    let n = first_epoch.measurements.len();
    if n < 4 {
        return Err(Error::invalid(
            "gnss",
            format!(
                "the first epoch (t = {} s) has {n} usable satellites: at least 4 are needed for the initial fix",
                first_epoch.time_s
            ),
        ));
    }
    let mut fix = solve_fix_all_satellites(&first_epoch, None)?;
    if !fix.velocity_ecef.iter().all(|v| v.is_finite()) {
        let second = epochs[1..]
            .iter()
            .map(usable)
            .find(|e| e.measurements.len() >= 4)
            .ok_or_else(|| {
                Error::invalid(
                    "gnss",
                    "no pseudorange rates in the first epoch and no second epoch with 4 satellites: the initial velocity is unknown",
                )
            })?;
        let next = solve_fix_all_satellites(&second, Some(fix.position_ecef))?;
        let dt = next.time_s - fix.time_s;
        fix.velocity_ecef = (next.position_ecef - fix.position_ecef) / dt;
        fix.clock_drift_m_s = (next.clock_offset_m - fix.clock_offset_m) / dt;
    }
    let nav = start_at_first_sample(
        &fix.position_ecef,
        &fix.velocity_ecef,
        first_epoch.time_s,
        imu,
        attitude,
    )?;
    Ok(InitialState {
        nav,
        accel_bias_m_s2: Vector3::zeros(),
        gyro_bias_rad_s: Vector3::zeros(),
        clock_offset_m: Some(
            fix.clock_offset_m - fix.clock_drift_m_s * (first_epoch.time_s - imu.time_s[0]),
        ),
        clock_drift_m_s: Some(fix.clock_drift_m_s),
    })
}

/// The initial state of the loosely coupled filter from its first position
/// fix: position moved back to the first IMU time along the fix velocity
/// (zero when the fix has none, and then `attitude` must be given: there is
/// no course for a heading); attitude as given, else [`coarse_attitude`];
/// zero bias estimates; clock zero (loose coupling does not observe it).
pub fn initial_state_from_position_fix(
    fixes: &[PositionFix],
    imu: &ImuData,
    attitude: Option<Matrix3<f64>>,
) -> Result<InitialState> {
    imu.validate()?;
    let times: Vec<f64> = fixes.iter().map(|f| f.time_s).collect();
    validate::epochs_in_imu_span("fixes", &times, imu.time_s, 0.0)?;
    let fix = fixes
        .first()
        .ok_or_else(|| Error::invalid("fixes", "has no valid fix"))?;
    let velocity = fix.velocity_ecef.unwrap_or_else(Vector3::zeros);
    let nav = start_at_first_sample(&fix.position_ecef, &velocity, fix.time_s, imu, attitude)?;
    Ok(InitialState {
        nav,
        accel_bias_m_s2: Vector3::zeros(),
        gyro_bias_rad_s: Vector3::zeros(),
        clock_offset_m: Some(0.0),
        clock_drift_m_s: Some(0.0),
    })
}

/// The navigation state at the first IMU time from a fix at `fix_time_s`:
/// its position moved back along its velocity (constant over the gap);
/// attitude as given (checked), else [`coarse_attitude`] from the mean
/// specific force of the IMU's first second and the fix velocity.
fn start_at_first_sample(
    position_ecef: &Vector3<f64>,
    velocity_ecef: &Vector3<f64>,
    fix_time_s: f64,
    imu: &ImuData,
    attitude: Option<Matrix3<f64>>,
) -> Result<NavState> {
    let t0 = imu.time_s[0];
    let position_ecef = position_ecef - velocity_ecef * (fix_time_s - t0);
    let c_b_e = match attitude {
        Some(c) => {
            validate::rotation("initial_attitude", &c)?;
            c
        }
        None => {
            let k = imu
                .time_s
                .iter()
                .take_while(|t| **t <= t0 + 1.0)
                .count()
                .max(1);
            let mean = imu.specific_force_b[..k].iter().sum::<Vector3<f64>>() / k as f64;
            coarse_attitude(&mean, &position_ecef, velocity_ecef)?
        }
    };
    Ok(NavState {
        position_ecef,
        velocity_ecef: *velocity_ecef,
        c_b_e,
    })
}

impl<const N: usize> FilterState<N> {
    /// Sets the heading (yaw of the body x axis from north) to
    /// `heading_rad`, one-sigma `std_rad`, keeping roll and pitch: the
    /// attitude turns about the local vertical, and the heading component
    /// of the attitude error becomes a new, independent error
    /// ([`crate::filter::ErrorStateKf::reset_component`]). Recorded as a
    /// [`ResetKind::Heading`] reset. For an alignment to the GNSS course at
    /// the first motion, when the heading was unknown.
    pub fn align_heading(&mut self, time_s: f64, heading_rad: f64, std_rad: f64) -> Result<()> {
        validate::finite_scalars("heading", &[heading_rad])?;
        validate::positive("heading_std", std_rad)?;
        let geo = ecef_to_geodetic(&self.nav.position_ecef);
        let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
        let euler = dcm_to_euler(&(cne.transpose() * self.nav.c_b_e));
        let change = crate::attitude::wrap_angle_rad(heading_rad - euler.z);
        let c_before = self.nav.c_b_e;
        self.nav.c_b_e = cne * euler_to_dcm(euler.x, euler.y, heading_rad);
        // The fixes measured the antenna, r + C l: it stays where they put
        // it, so the IMU moves by (C_before − C) l, and with lever-arm
        // states the position error is the same change of variables,
        // δr' = δr + (C_before − C) δl (P ← T P Tᵀ): what the fixes taught
        // about the antenna, learnt with the wrong heading, is kept.
        let turn = c_before - self.nav.c_b_e;
        self.nav.position_ecef += turn * self.installation.lever_arm_b_m;
        if let Some(first) = Layout::for_size::<N>().installation {
            self.kf
                .shear(POSITION, first + Installation::LEVER_ARM, &turn);
        }
        let down_ecef = cne * Vector3::new(0.0, 0.0, 1.0);
        self.kf
            .reset_component(ATTITUDE, &down_ecef, std_rad * std_rad);
        self.resets.push(ResetRecord {
            time_s,
            kind: ResetKind::Heading,
            change,
            failed_epochs: 0,
        });
        self.kf.check_health(time_s)
    }

    /// Keeps an unknown heading unknown: the heading component of the
    /// attitude error becomes independent of every other state again, with
    /// one-sigma `std_rad` (not recorded as a reset: nothing changes in the
    /// solution). For the time before [`Self::align_heading`], called at
    /// every aiding epoch. A heading tens of degrees off is outside the
    /// small-angle error model: left correlated, the filter reads heading
    /// information into the Earth-rate and tilt couplings that a MEMS gyro's
    /// bias hides (no gyrocompassing below a bias of 0.01 °/s), and carries
    /// a wrong tilt and horizontal accelerometer bias out of a static start
    /// (9 mrad and 0.08 m/s² after 20 s at rest on an error-free
    /// IMU, 3σ off).
    pub fn forget_heading(&mut self, std_rad: f64) {
        let down_ecef = self.local_down_ecef();
        self.kf
            .reset_component(ATTITUDE, &down_ecef, std_rad * std_rad);
    }

    /// After moving with an unknown heading, the tilt and the horizontal
    /// accelerometer bias become independent new errors again, with the
    /// tilt one-sigma `tilt_std_rad` of the start and the bias its prior:
    /// while the heading was tens of degrees off, the part of the velocity
    /// error along the acceleration (1 − cos of the heading error, half
    /// of it at 60°) has no small-angle heading term to go to and was read
    /// as tilt and bias (a 30 mrad tilt error held at σ 2 mrad
    /// for the rest of a simulated drive). Their estimates stay; the
    /// aiding corrects them from here on.
    pub fn reopen_tilt_and_horizontal_bias(&mut self, tilt_std_rad: f64) {
        let geo = ecef_to_geodetic(&self.nav.position_ecef);
        let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
        for axis in [Vector3::x(), Vector3::y()] {
            self.kf
                .reset_component(ATTITUDE, &(cne * axis), tilt_std_rad * tilt_std_rad);
        }
        let up_b = (self.nav.c_b_e.transpose() * cne * Vector3::new(0.0, 0.0, -1.0)).normalize();
        let across = up_b
            .cross(&Vector3::x())
            .try_normalize(1e-6)
            .unwrap_or_else(|| up_b.cross(&Vector3::y()).normalize());
        let variance = self.tuning.initial_std.accel_bias_m_s2.powi(2);
        for d in [across, up_b.cross(&across)] {
            self.kf.reset_component(ACCEL_BIAS, &d, variance);
        }
    }

    /// The local down direction at the current position, ECEF.
    fn local_down_ecef(&self) -> Vector3<f64> {
        let geo = ecef_to_geodetic(&self.nav.position_ecef);
        c_n_e(geo.latitude_rad, geo.longitude_rad) * Vector3::new(0.0, 0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geodesy::{geodetic_to_ecef, gravity_ecef, Geodetic};

    /// Levelling and course over ground recover a known attitude.
    #[test]
    fn coarse_attitude_recovers_roll_pitch_heading() {
        let r = geodetic_to_ecef(Geodetic::new(0.76, 0.025, 150.0));
        let geo = ecef_to_geodetic(&r);
        let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
        let c_b_n = euler_to_dcm(0.05, -0.03, 2.0);
        let c_b_e = cne * c_b_n;
        // At constant velocity the specific force is −g in body axes
        // (plus a negligible Coriolis term).
        let f_b = -(c_b_e.transpose() * gravity_ecef(&r));
        let v = cne * Vector3::new(2.0_f64.cos(), 2.0_f64.sin(), 0.0) * 10.0;
        let c = coarse_attitude(&f_b, &r, &v).unwrap();
        let err = crate::attitude::dcm_to_rotation_vector(&(c * c_b_e.transpose()));
        // Gravity deflection from the ellipsoid normal leaves ~1e-3 rad.
        assert!(err.norm() < 2e-3, "{err}");
        assert!(coarse_attitude(&f_b, &r, &(v * 0.01)).is_err());
    }

    /// The loose start moves the first fix back along its velocity to the
    /// first IMU time; without a velocity there is no heading to take.
    #[test]
    fn position_fix_start_moves_back_along_the_velocity() {
        let r = geodetic_to_ecef(Geodetic::new(0.76, 0.025, 150.0));
        let geo = ecef_to_geodetic(&r);
        let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
        let v = cne * Vector3::new(8.0, 6.0, 0.0);
        let c_b_e = cne * euler_to_dcm(0.0, 0.0, (6.0_f64).atan2(8.0));
        let f_b = -(c_b_e.transpose() * gravity_ecef(&r));
        let time_s: Vec<f64> = (0..300).map(|k| k as f64 * 0.01).collect();
        let f = vec![f_b; time_s.len()];
        let w = vec![Vector3::zeros(); time_s.len()];
        let imu = ImuData {
            time_s: &time_s,
            specific_force_b: &f,
            angular_rate_b: &w,
            increments: None,
        };
        let mut fix = PositionFix {
            time_s: 2.0,
            position_ecef: r,
            position_covariance: Matrix3::identity(),
            velocity_ecef: Some(v),
            velocity_covariance: Matrix3::identity(),
            velocity_horizontal_only: false,
        };
        let s = initial_state_from_position_fix(&[fix], &imu, None).unwrap();
        assert!((s.nav.position_ecef - (r - 2.0 * v)).norm() < 1e-9);
        assert_eq!(s.nav.velocity_ecef, v);
        let err = crate::attitude::dcm_to_rotation_vector(&(s.nav.c_b_e * c_b_e.transpose()));
        assert!(err.norm() < 2e-3, "{err}");
        fix.velocity_ecef = None;
        assert!(initial_state_from_position_fix(&[fix], &imu, None).is_err());
        let given = initial_state_from_position_fix(&[fix], &imu, Some(c_b_e)).unwrap();
        assert_eq!((given.nav.position_ecef, given.nav.c_b_e), (r, c_b_e));
        assert!(initial_state_from_position_fix(&[], &imu, Some(c_b_e)).is_err());
    }
}
