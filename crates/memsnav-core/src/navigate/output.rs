//! A run's solution as people read it: the antenna's geodetic position,
//! NED velocity, roll/pitch/yaw, and one-sigma uncertainties along local
//! north, east, down.

use nalgebra::Vector3;

use super::run::LogRun;
use crate::attitude::dcm_to_euler;
use crate::coupling::covariance_ned;
use crate::geodesy::{c_n_e, ecef_to_geodetic, Geodetic};

/// The solution at every IMU sample, in local terms.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalSolution {
    /// Time, s (GNSS time).
    pub time_s: Vec<f64>,
    /// Antenna position r̂ + Ĉ l, ECEF, m.
    pub antenna_position_ecef: Vec<Vector3<f64>>,
    /// Antenna latitude, longitude (rad) and ellipsoidal height (m).
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

impl LogRun {
    /// The solution in local terms (see [`LocalSolution`]).
    pub fn local_solution(&self) -> LocalSolution {
        self.local(&self.solution)
    }

    /// The smoothed solution in local terms, when there is one.
    pub fn local_smoothed(&self) -> Option<LocalSolution> {
        self.smoothed.as_ref().map(|s| self.local(s))
    }

    fn local(&self, s: &crate::coupling::Solution) -> LocalSolution {
        let n = s.time_s.len();
        let mut out = LocalSolution {
            time_s: s.time_s.clone(),
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
            let c = s.c_b_e[k];
            let r = s.position_ecef[k] + c * self.antenna_lever_arm_b_m;
            let geo = ecef_to_geodetic(&r);
            let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
            out.antenna_position_ecef.push(r);
            out.antenna_geodetic.push(geo);
            out.velocity_ned.push(cne.transpose() * s.velocity_ecef[k]);
            out.euler_rad.push(dcm_to_euler(&(cne.transpose() * c)));
            out.position_std_ned
                .push(std(&s.position_covariance_ecef(k), &r));
            out.velocity_std_ned
                .push(std(&s.velocity_covariance_ecef(k), &r));
            out.attitude_std_ned
                .push(std(&s.attitude_covariance_ecef(k), &r));
        }
        out
    }
}
