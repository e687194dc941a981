//! Calibration references from a navigated log: the paper's GNSS-derived
//! references (method §3) of specific force and angular rate in the IMU's
//! own axes, taken from a (smoothed) GNSS/INS solution of the drive.
//!
//! A solution at every IMU sample knows the velocity and attitude far
//! better than the IMU alone: the GNSS pins them at every epoch, the
//! smoother carries each fix both ways. Its velocity and attitude at the
//! ends of a window of length T give the window's mean specific force and
//! angular rate; the IMU's mean output over the same samples is the
//! measurement they are compared with. Windows, not samples: inside a
//! window the solution moves with the IMU itself, so only changes over a
//! window long against the GNSS epoch interval carry independent
//! information.
//!
//! Specific force. The ECEF velocity equation (Groves eq. 5.35),
//! v̇ = C_b^e f^b − 2 Ω_ie v + g(r), integrated over the window:
//!
//!   ∫ C_b^e f^b dt = Δv + ∫ (2 Ω_ie v − g(r)) dt.
//!
//! With R(t) = C_b^e(m)ᵀ C_b^e(t) the attitude relative to the window's
//! middle sample m, ∫ C_b^e f^b dt = C_b^e(m) (∫ f^b dt + ∫ (R − I) f^b dt),
//! so the mean body specific force is
//!
//!   f̄^b = [C_b^e(m)ᵀ (Δv + ∫ (2 Ω_ie v − g) dt) − ∫ (R − I) f̃^b dt] / T,
//!
//! where the small rotation term takes the measured f̃^b (an error of the
//! IMU's scale factor times a rotation of a few degrees: second order).
//!
//! Angular rate. The body's rotation between two samples relative to
//! inertial space, with C_b^i = C_e^i C_b^e and C_e^i(t) = Rz(ω_ie t)
//! (Groves §2.5.1), is ΔC_k = C_b^e(k)ᵀ Rz(ω_ie Δt) C_b^e(k+1); the sum of
//! rotvec(ΔC_k) over the window divided by T is the mean body rate, as the
//! IMU's samples average it (a single rotvec over the whole window would
//! add the coning term, 3·10⁻⁴ rad/s on a car's 1 s windows).
//!
//! Both are rotated into the sensor's axes with the mounting (body =
//! M · sensor, so sensor = Mᵀ · body). The IMU side is the trapezoidal mean
//! of the raw samples a..=b, the same rule the strapdown integration uses.

use nalgebra::{Matrix3, Vector3};

use super::run::LogRun;
use crate::attitude::dcm_to_rotation_vector;
use crate::coupling::ResetKind;
use crate::filter::state::{Layout, ACCEL_BIAS, ACCEL_SCALE_FACTOR, GYRO_BIAS, GYRO_SCALE_FACTOR};
use crate::geodesy::gravity_ecef;
use crate::geodesy::wgs84::EARTH_RATE_RAD_S;
use crate::{Error, Result};

/// Window means of the IMU's outputs and of the solution's references, all
/// in the sensor's axes.
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrationReferences {
    /// Middle time of each window (the solution's time scale), s.
    pub time_s: Vec<f64>,
    /// Trapezoidal mean of the measured specific force, m/s².
    pub measured_specific_force_s: Vec<Vector3<f64>>,
    /// Trapezoidal mean of the measured angular rate, rad/s.
    pub measured_angular_rate_s: Vec<Vector3<f64>>,
    /// Reference mean specific force, m/s².
    pub reference_specific_force_s: Vec<Vector3<f64>>,
    /// Reference mean angular rate, rad/s.
    pub reference_angular_rate_s: Vec<Vector3<f64>>,
    /// The window length used, s (a whole number of IMU samples).
    pub window_s: f64,
    /// Windows left out because a reset of the filter falls inside them.
    pub skipped_for_resets: usize,
    /// Windows left out because they end before the heading alignment of a
    /// static start (the heading, and so the rotation about the vertical,
    /// is unknown there: `FilterState::forget_heading`).
    pub skipped_before_heading: usize,
    /// The solution's own uncertainty of the accelerometer biases, mean over
    /// the windows, in the sensor's axes, (m/s²)². The references inherit
    /// it: a bias the solution has wrong tilts its attitude and so the
    /// reference specific force by the same amount (the tilt-bias ambiguity
    /// of a level drive), so a calibrated bias is never better known than
    /// this.
    pub accel_bias_covariance_s: Matrix3<f64>,
    /// The same for the gyro biases, (rad/s)².
    pub gyro_bias_covariance_s: Matrix3<f64>,
    /// The same for the accelerometer scale factors when the solution has
    /// scale-factor states (zero without), 1.
    pub accel_scale_factor_covariance_s: Matrix3<f64>,
    /// The same for the gyro scale factors, 1.
    pub gyro_scale_factor_covariance_s: Matrix3<f64>,
}

/// The window of the references when none is asked for, s: the
/// standstill detector's default window, long enough to average the
/// sensor noise and short enough to follow a car's manoeuvres.
pub const DEFAULT_WINDOW_S: f64 = 1.0;

/// The references of a log run (see the module docs). `time_s`,
/// `specific_force_s`, `angular_rate_s`: the raw IMU series given to
/// [`super::navigate_log`] (sensor axes, SI); `window_s`: the window length; `until_s`:
/// only windows ending within that many seconds after the run's start
/// (None: all).
pub fn calibration_references(
    run: &LogRun,
    time_s: &[f64],
    specific_force_s: &[Vector3<f64>],
    angular_rate_s: &[Vector3<f64>],
    window_s: f64,
    until_s: Option<f64>,
) -> Result<CalibrationReferences> {
    let sol = &run.solution;
    let mounting = &run.mounting;
    let k0 = run.start.first_sample;
    let n = sol.time_s.len();
    if time_s.len() != specific_force_s.len() || time_s.len() != angular_rate_s.len() {
        return Err(Error::invalid(
            "specific_force",
            "time, specific_force and angular_rate must have one row per sample",
        ));
    }
    if time_s.len() < k0 + n {
        return Err(Error::invalid(
            "time",
            format!(
                "has {} samples; the run used samples {k0}..{}: give the arrays the run was given",
                time_s.len(),
                k0 + n
            ),
        ));
    }
    // The run's times are the raw ones plus one constant offset.
    let offset = sol.time_s[0] - time_s[k0];
    if sol
        .time_s
        .iter()
        .zip(&time_s[k0..])
        .any(|(s, t)| (s - t - offset).abs() > 1e-6)
    {
        return Err(Error::invalid(
            "time",
            "does not match the run's IMU times: give the arrays the run was given",
        ));
    }
    if !(window_s.is_finite() && window_s > 0.0) {
        return Err(Error::invalid(
            "window_s",
            format!("must be a positive number of seconds, got {window_s}"),
        ));
    }
    if let Some(u) = until_s.filter(|u| !(u.is_finite() && *u > 0.0)) {
        return Err(Error::invalid(
            "until_s",
            format!("must be a positive number of seconds, got {u}"),
        ));
    }
    let dt = (sol.time_s[n - 1] - sol.time_s[0]) / (n - 1).max(1) as f64;
    let step = (window_s / dt).round().max(1.0) as usize;
    let t_end = until_s.map_or(f64::INFINITY, |u| sol.time_s[0] + u);
    let m_t = mounting.transpose();
    let mut out = CalibrationReferences {
        time_s: Vec::new(),
        measured_specific_force_s: Vec::new(),
        measured_angular_rate_s: Vec::new(),
        reference_specific_force_s: Vec::new(),
        reference_angular_rate_s: Vec::new(),
        window_s: step as f64 * dt,
        skipped_for_resets: 0,
        skipped_before_heading: 0,
        accel_bias_covariance_s: Matrix3::zeros(),
        gyro_bias_covariance_s: Matrix3::zeros(),
        accel_scale_factor_covariance_s: Matrix3::zeros(),
        gyro_scale_factor_covariance_s: Matrix3::zeros(),
    };
    let scale_factors = Layout::of(sol.n_states).is_some_and(|l| l.scale_factors);
    // The sensor-error states are in body axes; only their variances are
    // stored.
    let state_covariance_s = |k: usize, first: usize| {
        let row = &sol.covariance_diagonal[k * sol.n_states..(k + 1) * sol.n_states];
        m_t * Matrix3::from_diagonal(&Vector3::from_column_slice(&row[first..first + 3])) * mounting
    };
    let starts = (0..n)
        .step_by(step)
        .take_while(|&a| a + step < n && sol.time_s[a + step] <= t_end);
    let heading_known_s = sol
        .resets
        .iter()
        .find(|r| r.kind == ResetKind::Heading)
        .map_or(f64::NEG_INFINITY, |r| r.time_s);
    for a in starts {
        let b = a + step;
        let (ta, tb) = (sol.time_s[a], sol.time_s[b]);
        let mid = a + step / 2;
        if tb <= heading_known_s {
            out.skipped_before_heading += 1;
            continue;
        }
        // A reset inside the window breaks the kinematics.
        if sol.resets.iter().any(|r| r.time_s > ta && r.time_s <= tb) {
            out.skipped_for_resets += 1;
            continue;
        }
        let c_mid = sol.c_b_e[mid];
        // Trapezoidal integrals over the samples a..=b.
        let mut kinematic = Vector3::zeros(); // ∫ (2 Ω_ie v − g) dt
        let mut rotation = Vector3::zeros(); // ∫ (R − I) f̃^b dt
        let mut f_meas = Vector3::zeros();
        let mut w_meas = Vector3::zeros();
        for k in a..=b {
            let h = if k == a || k == b { 0.5 } else { 1.0 } * (tb - ta) / step as f64;
            let v = sol.velocity_ecef[k];
            let coriolis = 2.0 * EARTH_RATE_RAD_S * Vector3::new(-v.y, v.x, 0.0);
            kinematic += h * (coriolis - gravity_ecef(&sol.position_ecef[k]));
            let f_b = mounting * specific_force_s[k0 + k];
            rotation += h * (c_mid.transpose() * sol.c_b_e[k] - Matrix3::identity()) * f_b;
            f_meas += h * specific_force_s[k0 + k];
            w_meas += h * angular_rate_s[k0 + k];
        }
        let t = tb - ta;
        let dv = sol.velocity_ecef[b] - sol.velocity_ecef[a];
        let f_ref_b = (c_mid.transpose() * (dv + kinematic) - rotation) / t;
        // Σ over the samples of rotvec(C_b^e(k)ᵀ Rz(ω_ie Δt) C_b^e(k+1)).
        let mut rotation_b = Vector3::zeros();
        for k in a..b {
            let (s, c) = (EARTH_RATE_RAD_S * (sol.time_s[k + 1] - sol.time_s[k])).sin_cos();
            let earth = Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
            let delta = sol.c_b_e[k].transpose() * earth * sol.c_b_e[k + 1];
            rotation_b += dcm_to_rotation_vector(&delta);
        }
        let w_ref_b = rotation_b / t;
        out.time_s.push(sol.time_s[mid]);
        out.measured_specific_force_s.push(f_meas / t);
        out.measured_angular_rate_s.push(w_meas / t);
        out.reference_specific_force_s.push(m_t * f_ref_b);
        out.reference_angular_rate_s.push(m_t * w_ref_b);
        out.accel_bias_covariance_s += state_covariance_s(mid, ACCEL_BIAS);
        out.gyro_bias_covariance_s += state_covariance_s(mid, GYRO_BIAS);
        if scale_factors {
            out.accel_scale_factor_covariance_s += state_covariance_s(mid, ACCEL_SCALE_FACTOR);
            out.gyro_scale_factor_covariance_s += state_covariance_s(mid, GYRO_SCALE_FACTOR);
        }
    }
    if out.time_s.len() < 2 {
        return Err(Error::invalid(
            "window_s",
            format!(
                "leaves {} window(s) of {:.3} s in the run (until_s {until_s:?}): too few to calibrate",
                out.time_s.len(),
                out.window_s
            ),
        ));
    }
    let windows = out.time_s.len() as f64;
    out.accel_bias_covariance_s /= windows;
    out.gyro_bias_covariance_s /= windows;
    out.accel_scale_factor_covariance_s /= windows;
    out.gyro_scale_factor_covariance_s /= windows;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::euler_to_dcm;
    use crate::coupling::Solution;
    use crate::filter::state::BASE_STATES;
    use crate::ins::NavState;
    use crate::navigate::align::{Start, StartKind};
    use crate::trajectory::{RandomTrajectoryConfig, Trajectory};

    /// A run whose solution is the truth itself, at every sample from
    /// `first_sample`, with a mounting `m` (body = m · sensor).
    fn exact_run(truth: &Trajectory, first_sample: usize, m: Matrix3<f64>) -> LogRun {
        let n = truth.time_s.len() - first_sample;
        let mut solution = Solution::with_capacity(n, BASE_STATES);
        let range = first_sample..truth.time_s.len();
        solution.time_s = truth.time_s[range.clone()]
            .iter()
            .map(|t| t + 0.5)
            .collect();
        solution.position_ecef = truth.position_ecef[range.clone()].to_vec();
        solution.velocity_ecef = truth.velocity_ecef[range.clone()].to_vec();
        solution.c_b_e = truth.c_b_e[range].to_vec();
        // Variances 1e-8 rad² (attitude), 1e-4 m²/s² (velocity), 1e-6
        // elsewhere; no correlations.
        let row: Vec<f64> = (0..BASE_STATES)
            .map(|i| match i / 3 {
                0 => 1e-8,
                1 => 1e-4,
                _ => 1e-6,
            })
            .collect();
        solution.covariance_diagonal = row.repeat(n);
        solution.navigation_covariance_off_diagonal = vec![[0.0; 9]; n];
        let antenna = NavState {
            position_ecef: truth.position_ecef[first_sample],
            velocity_ecef: truth.velocity_ecef[first_sample],
            c_b_e: truth.c_b_e[first_sample],
        };
        LogRun {
            solution,
            smoothed: None,
            start: Start {
                kind: StartKind::Moving,
                epoch: 0,
                time_s: truth.time_s[first_sample] + 0.5,
                first_sample,
                antenna,
                position_std_m: 1.0,
                velocity_std_m_s: 1.0,
                tilt_std_rad: 0.01,
                heading_std_rad: 0.01,
                heading_known: true,
                first_imu_time_s: truth.time_s[0],
                first_gnss_time_s: truth.time_s[first_sample] + 0.5,
                earliest_time_s: truth.time_s[first_sample] + 0.5,
                delay: None,
            },
            late_start: None,
            gnss: Vec::new(),
            gnss_used: Vec::new(),
            outages: Vec::new(),
            standstills: Vec::new(),
            range_biases: Vec::new(),
            antenna_lever_arm_b_m: Vector3::zeros(),
            mounting: m,
            failure: None,
            gyro_scale: None,
            carrier_use: None,
            adaptation: Default::default(),
            tuning: crate::coupling::FilterTuning::new(
                100.0,
                0.0,
                0.0,
                crate::coupling::BiasProcess::constant(0.0),
                crate::coupling::BiasProcess::constant(0.0),
            )
            .expect("a valid tuning"),
        }
    }

    /// A seeded random drive of `duration_s` at the default IMU rate.
    fn drive(duration_s: f64, substream: u64) -> Trajectory {
        let config = RandomTrajectoryConfig {
            duration_s,
            ..Default::default()
        };
        Trajectory::random(&config, &mut crate::random::stream(7, substream)).unwrap()
    }

    /// With the truth as the solution the references are the trapezoidal
    /// means of the exact outputs, in the sensor's axes, to the accuracy of
    /// the trapezoidal rule.
    #[test]
    fn references_of_the_truth_are_the_exact_outputs() {
        let truth = drive(120.0, 0);
        let m = euler_to_dcm(3.0, -0.2, 1.7);
        let f_s: Vec<_> = truth
            .specific_force_b
            .iter()
            .map(|f| m.transpose() * f)
            .collect();
        let w_s: Vec<_> = truth
            .angular_rate_b
            .iter()
            .map(|w| m.transpose() * w)
            .collect();
        let run = exact_run(&truth, 30, m);
        let r = calibration_references(&run, &truth.time_s, &f_s, &w_s, 1.0, None).unwrap();
        assert_eq!(r.time_s.len(), 119);
        assert_eq!(r.skipped_for_resets, 0);
        assert!((r.window_s - 1.0).abs() < 1e-9);
        let (mut f_err, mut w_err) = (0.0_f64, 0.0_f64);
        for k in 0..r.time_s.len() {
            f_err = f_err
                .max((r.reference_specific_force_s[k] - r.measured_specific_force_s[k]).amax());
            w_err =
                w_err.max((r.reference_angular_rate_s[k] - r.measured_angular_rate_s[k]).amax());
        }
        // Against ~1 m/s² and ~0.3 rad/s of motion (measured: 1.5e-5 and
        // 1.2e-6, the trapezoid against the exact integrals).
        assert!(f_err < 5e-5, "specific force {f_err}");
        assert!(w_err < 5e-6, "angular rate {w_err}");
        // The inherited covariances are the solution's, in sensor axes.
        assert!((r.accel_bias_covariance_s - Matrix3::identity() * 1e-6).amax() < 1e-15);
    }

    /// The arrays must be the ones the run was given.
    #[test]
    fn references_refuse_other_arrays() {
        let truth = drive(10.0, 1);
        let run = exact_run(&truth, 0, Matrix3::identity());
        let (f, w) = (&truth.specific_force_b, &truth.angular_rate_b);
        let shifted: Vec<f64> = truth.time_s.iter().map(|t| t * 1.01).collect();
        let err = calibration_references(&run, &shifted, f, w, 1.0, None).unwrap_err();
        assert!(err.to_string().contains("time"), "{err}");
        let err = calibration_references(&run, &truth.time_s, f, w, 20.0, None).unwrap_err();
        assert!(err.to_string().contains("window_s"), "{err}");
        let err =
            calibration_references(&run, &truth.time_s, f, w, 1.0, Some(f64::NAN)).unwrap_err();
        assert!(err.to_string().contains("until_s"), "{err}");
    }
}
