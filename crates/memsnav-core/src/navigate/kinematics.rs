//! Every GNSS epoch's antenna position and velocity, as the aids and the
//! start read them: the fixes as they are, or the least-squares fix of
//! each epoch's pseudoranges (the single-point solution).

use super::align::GnssKinematics;
use crate::coupling::{Aiding, PositionFix};
use crate::gnss::{solve_fix_all_satellites, GnssEpoch, SatelliteMeasurement};

/// Longest interval between two fixes whose position difference stands in
/// for a missing velocity, s.
const MAX_DIFFERENCE_INTERVAL_S: f64 = 2.0;

/// GNSS epochs whose antenna position and velocity can be read.
pub trait EpochKinematics: Aiding {
    /// The antenna position and velocity of every epoch, each epoch's
    /// pseudorange std raised by `bias_std_m` in quadrature where there are
    /// pseudoranges (range biases the fixes carry).
    fn kinematics(epochs: &[Self], bias_std_m: f64) -> Vec<GnssKinematics>;
}

impl EpochKinematics for PositionFix {
    /// The fixes as they are, those without a velocity with the backward
    /// difference of their positions (`velocity_from_positions`).
    fn kinematics(fixes: &[Self], _bias_std_m: f64) -> Vec<GnssKinematics> {
        let mut kinematics: Vec<GnssKinematics> = fixes
            .iter()
            .map(|f| GnssKinematics {
                time_s: f.time_s,
                position_ecef: f.position_ecef,
                position_covariance: f.position_covariance,
                velocity_ecef: f.velocity_ecef,
                velocity_covariance: f.velocity_covariance,
                velocity_from_positions: false,
            })
            .collect();
        velocity_from_positions(&mut kinematics);
        kinematics
    }
}

impl EpochKinematics for GnssEpoch {
    /// The least-squares fix of each epoch's usable pseudoranges (and
    /// rates), each started from the previous fix; none where an epoch has
    /// fewer than four usable satellites or no solution.
    fn kinematics(epochs: &[Self], bias_std_m: f64) -> Vec<GnssKinematics> {
        let mut prior = None;
        epochs
            .iter()
            .map(|e| {
                let usable = GnssEpoch {
                    time_s: e.time_s,
                    measurements: e
                        .measurements
                        .iter()
                        .filter(|m| {
                            m.pseudorange_m.is_finite()
                                && m.position_ecef.iter().all(|v| v.is_finite())
                        })
                        .map(|m| SatelliteMeasurement {
                            pseudorange_std_m: m.pseudorange_std_m.hypot(bias_std_m),
                            ..*m
                        })
                        .collect(),
                };
                match solve_fix_all_satellites(&usable, prior) {
                    Ok(f) => {
                        prior = Some(f.position_ecef);
                        let v = f.velocity_ecef;
                        GnssKinematics {
                            time_s: e.time_s,
                            position_ecef: f.position_ecef,
                            position_covariance: f
                                .position_clock_covariance
                                .fixed_view::<3, 3>(0, 0)
                                .into(),
                            velocity_ecef: v.iter().all(|x| x.is_finite()).then_some(v),
                            velocity_covariance: f
                                .velocity_drift_covariance
                                .fixed_view::<3, 3>(0, 0)
                                .into(),
                            velocity_from_positions: false,
                        }
                    }
                    Err(_) => GnssKinematics::none(e.time_s),
                }
            })
            .collect()
    }
}

/// Fixes without a velocity get the backward difference of their position
/// and the previous fix's (within [`MAX_DIFFERENCE_INTERVAL_S`]), with the
/// covariance of independent positions, (P_a + P_b) / Δt²: the ground speed
/// and course the aids need (the standstill test's GNSS speed, the heading
/// at the first motion). Causal, so it is the velocity half an interval
/// ago. Only the aids read it: the filter's fixes stay position-only.
fn velocity_from_positions(kinematics: &mut [GnssKinematics]) {
    for i in 1..kinematics.len() {
        let (a, b) = (&kinematics[i - 1], &kinematics[i]);
        let dt = b.time_s - a.time_s;
        if b.velocity_ecef.is_some() || !(dt > 0.0 && dt <= MAX_DIFFERENCE_INTERVAL_S) {
            continue;
        }
        let velocity = (b.position_ecef - a.position_ecef) / dt;
        if velocity.iter().all(|v| v.is_finite()) {
            let covariance = (a.position_covariance + b.position_covariance) / (dt * dt);
            kinematics[i].velocity_ecef = Some(velocity);
            kinematics[i].velocity_covariance = covariance;
            kinematics[i].velocity_from_positions = true;
        }
    }
}
