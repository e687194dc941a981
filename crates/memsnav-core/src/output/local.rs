//! A solution as people read it: geodetic position, NED velocity,
//! roll/pitch/yaw, and one-sigma uncertainties along local north, east,
//! down, at every sample.

use nalgebra::Vector3;

use crate::attitude::dcm_to_euler;
use crate::coupling::{covariance_ned, Solution};
use crate::geodesy::{c_n_e, ecef_to_geodetic, Geodetic};

/// A solution at every sample, in local terms.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalSolution {
    /// Time, s (GNSS time).
    pub time_s: Vec<f64>,
    /// The point described, r̂ + Ĉ l (the IMU, or an antenna at lever arm
    /// l), ECEF, m.
    pub antenna_position_ecef: Vec<Vector3<f64>>,
    /// Its latitude, longitude (rad) and ellipsoidal height (m).
    pub antenna_geodetic: Vec<Geodetic>,
    /// Velocity of the IMU in local north, east, down, m/s.
    pub velocity_ned: Vec<Vector3<f64>>,
    /// Roll, pitch, yaw of the body relative to local NED, rad.
    pub euler_rad: Vec<Vector3<f64>>,
    /// One-sigma position along north, east, down, m.
    pub position_std_ned: Vec<Vector3<f64>>,
    /// One-sigma velocity along north, east, down, m/s.
    pub velocity_std_ned: Vec<Vector3<f64>>,
    /// One-sigma attitude about north, east, down, rad.
    pub attitude_std_ned: Vec<Vector3<f64>>,
}

impl LocalSolution {
    /// `solution` in local terms at the point `lever_arm_b_m` from the IMU
    /// in body axes (zero: the IMU itself).
    pub fn new(solution: &Solution, lever_arm_b_m: Vector3<f64>) -> Self {
        let n = solution.time_s.len();
        let mut out = LocalSolution {
            time_s: solution.time_s.clone(),
            antenna_position_ecef: Vec::with_capacity(n),
            antenna_geodetic: Vec::with_capacity(n),
            velocity_ned: Vec::with_capacity(n),
            euler_rad: Vec::with_capacity(n),
            position_std_ned: Vec::with_capacity(n),
            velocity_std_ned: Vec::with_capacity(n),
            attitude_std_ned: Vec::with_capacity(n),
        };
        let std = |p: &nalgebra::Matrix3<f64>, r: &Vector3<f64>| {
            covariance_ned(r, p).diagonal().map(|v| v.max(0.0).sqrt())
        };
        for k in 0..n {
            let c = solution.c_b_e[k];
            let r = solution.position_ecef[k] + c * lever_arm_b_m;
            let geo = ecef_to_geodetic(&r);
            let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
            out.antenna_position_ecef.push(r);
            out.antenna_geodetic.push(geo);
            out.velocity_ned
                .push(cne.transpose() * solution.velocity_ecef[k]);
            out.euler_rad.push(dcm_to_euler(&(cne.transpose() * c)));
            out.position_std_ned
                .push(std(&solution.position_covariance_ecef(k), &r));
            out.velocity_std_ned
                .push(std(&solution.velocity_covariance_ecef(k), &r));
            out.attitude_std_ned
                .push(std(&solution.attitude_covariance_ecef(k), &r));
        }
        out
    }
}
