//! The checks before and after the calibration, pose by pose and turn by
//! turn, held-out ones marked: the gravity-magnitude error of each pose and
//! the angle between the carried and the measured gravity direction of
//! each turn ([`Segment::angle_error`]), once with the nominal readings and
//! no offsets (T = I), once with the calibration.

use nalgebra::{Matrix3, Vector3};

use super::gyroscope::GyroscopeStage;
use super::rotation::{Offsets, Segment};
use super::session::{GyroData, Session};
use crate::calibration::static_detector::Pose;

/// A pose and its gravity-magnitude error before (nominal readings) and
/// after the calibration, m/s².
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseCheck {
    /// The pose (its rest in the log).
    pub pose: Pose,
    /// Whether the pose was left out of the fits.
    pub held_out: bool,
    /// Gravity-magnitude error of the nominal readings, m/s².
    pub magnitude_error_before: f64,
    /// Gravity-magnitude error of the calibrated readings, m/s².
    pub magnitude_error_after: f64,
}

/// A turn between poses `from` and `from + 1` and the angle between the
/// carried and the measured gravity direction, rad, before (nominal
/// readings, no offsets) and after the calibration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TurnCheck {
    /// The index of the pose the turn starts from.
    pub from: usize,
    /// Whether the turn was left out of the fits.
    pub held_out: bool,
    /// Angle error with the nominal readings and no offsets, rad.
    pub angle_error_before: f64,
    /// Angle error with the calibrated readings, rad.
    pub angle_error_after: f64,
}

/// ‖s̄_k‖ − g of the nominal pose means `accel_means` and ‖Γ̄_k‖ − g of the
/// corrected ones in `data`, every pose of `session`.
pub fn pose_checks(
    session: &Session<'_>,
    accel_means: &[Vector3<f64>],
    data: &GyroData,
) -> Vec<PoseCheck> {
    let g = session.gravity;
    session
        .poses
        .iter()
        .enumerate()
        .map(|(k, p)| PoseCheck {
            pose: *p,
            held_out: session.held_out[k],
            magnitude_error_before: accel_means[k].norm() - g,
            magnitude_error_after: data.force_means[k].norm() - g,
        })
        .collect()
}

/// The angle error of every turn of `data`: before with the gravity
/// directions of the nominal pose means `accel_means`, T = I and no
/// offsets; after with the calibrated directions, T and offsets of `gyro`.
pub fn turn_checks(
    session: &Session<'_>,
    accel_means: &[Vector3<f64>],
    data: &GyroData,
    gyro: &GyroscopeStage,
) -> Vec<TurnCheck> {
    let nominal_offsets = Offsets {
        c0: Vector3::zeros(),
        c: Matrix3::zeros(),
    };
    data.segments
        .iter()
        .map(|s| {
            let before = Segment {
                up_from: accel_means[s.from].normalize(),
                up_to: accel_means[s.from + 1].normalize(),
                ..s.clone()
            };
            TurnCheck {
                from: s.from,
                held_out: !session.is_fit_turn(s),
                angle_error_before: before.angle_error(&Matrix3::identity(), &nominal_offsets),
                angle_error_after: s.angle_error(&gyro.t, &gyro.rest_fit.offsets),
            }
        })
        .collect()
}
