//! The session as every stage sees it (steps 1-2 of the module docs done):
//! the nominal readings, the detected poses and which of them are held
//! out, and, for an accelerometer model, what the gyroscope stages need
//! from it: the pose means of the nominal gyro readings and of the
//! corrected specific force, and one turn [`Segment`] per pair of
//! consecutive poses.

use nalgebra::Vector3;

use super::rotation::Segment;
use crate::calibration::static_detector::Pose;
use crate::ins::increments_from_samples;
use crate::sensors::AccelerometerModel;

/// The nominal readings and the poses, with the hold-out of the module docs.
pub struct Session<'a> {
    /// Sample times, s.
    pub time: &'a [f64],
    /// Nominal readings s = scale ⊙ (raw − offset), per sample.
    pub accel_nominal: Vec<Vector3<f64>>,
    pub gyro_nominal: Vec<Vector3<f64>>,
    /// The initial rest, then the poses.
    pub poses: &'a [Pose],
    /// Per pose: left out of the fits (every h-th pose, never the rest).
    pub held_out: Vec<bool>,
    /// The poses in the fits.
    pub fit_poses: Vec<usize>,
    /// Local gravity magnitude, m/s².
    pub gravity: f64,
    /// [`Estimate::Determinable`]: hold what the poses do not determine.
    ///
    /// [`Estimate::Determinable`]: crate::calibration::determinable::Estimate
    pub determinable: bool,
}

/// Which poses the fits leave out (module docs of [`super`]); a pose that
/// either rule names is held out.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Holdout {
    /// Every h-th pose: poses h − 1, 2h − 1, …
    pub every: Option<usize>,
    /// Every pose that ends at or after this time (s, the session's time
    /// axis): a fit on the session before it, scored on the rest.
    pub from_s: Option<f64>,
}

/// Everything the gyroscope stages need from the accelerometer model.
pub struct GyroData {
    /// Pose means of the nominal gyro readings and of the corrected
    /// specific force.
    pub gyro_means: Vec<Vector3<f64>>,
    pub force_means: Vec<Vector3<f64>>,
    /// One segment per consecutive pair of poses.
    pub segments: Vec<Segment>,
}

/// Mean of samples `pose.start..pose.end`.
fn mean(samples: &[Vector3<f64>], pose: &Pose) -> Vector3<f64> {
    samples[pose.start..pose.end].iter().sum::<Vector3<f64>>() / pose.len() as f64
}

impl<'a> Session<'a> {
    /// The session of the nominal readings and the `poses` detected in
    /// them, held out by `holdout` (module docs of [`super`]), local
    /// gravity `gravity` (m/s²).
    pub fn new(
        time: &'a [f64],
        accel_nominal: Vec<Vector3<f64>>,
        gyro_nominal: Vec<Vector3<f64>>,
        poses: &'a [Pose],
        holdout: Holdout,
        gravity: f64,
        determinable: bool,
    ) -> Self {
        let held_out: Vec<bool> = poses
            .iter()
            .enumerate()
            .map(|(k, pose)| {
                k > 0
                    && (holdout.every.is_some_and(|h| k % h == h - 1)
                        || holdout.from_s.is_some_and(|t| time[pose.end - 1] >= t))
            })
            .collect();
        let fit_poses: Vec<usize> = (0..poses.len()).filter(|&k| !held_out[k]).collect();
        Self {
            time,
            accel_nominal,
            gyro_nominal,
            poses,
            held_out,
            fit_poses,
            gravity,
            determinable,
        }
    }

    /// Pose means of the nominal accelerometer readings, every pose.
    pub fn accel_means(&self) -> Vec<Vector3<f64>> {
        self.poses
            .iter()
            .map(|p| mean(&self.accel_nominal, p))
            .collect()
    }

    /// The first pose (the initial rest) of the nominal accelerometer and
    /// gyro readings.
    pub fn initial_rest(&self) -> (&[Vector3<f64>], &[Vector3<f64>]) {
        let rest = &self.poses[0];
        (
            &self.accel_nominal[rest.start..rest.end],
            &self.gyro_nominal[rest.start..rest.end],
        )
    }

    /// The pose means and turn segments under `accel_model` (None when a
    /// reading is beyond its range). A segment runs from the last sample of
    /// pose k to the first of pose k + 1, its increments of the nominal
    /// gyro reading and the corrected specific force from
    /// [`increments_from_samples`], its gravity directions the corrected
    /// pose means.
    pub fn gyro_data(&self, accel_model: &AccelerometerModel) -> Option<GyroData> {
        let (time, poses) = (self.time, self.poses);
        let (accel_nominal, gyro_nominal) = (&self.accel_nominal, &self.gyro_nominal);
        let force_means: Vec<Vector3<f64>> = poses
            .iter()
            .map(|p| accel_model.correct(&mean(accel_nominal, p)).ok())
            .collect::<Option<_>>()?;
        let gyro_means = poses.iter().map(|p| mean(gyro_nominal, p)).collect();
        let mut segments = Vec::with_capacity(poses.len().saturating_sub(1));
        for (k, pair) in poses.windows(2).enumerate() {
            // From the last sample of pose k to the first of pose k + 1.
            let (first, last) = (pair[0].end - 1, pair[1].start);
            let force: Vec<Vector3<f64>> = accel_nominal[first..=last]
                .iter()
                .map(|s| accel_model.correct(s).ok())
                .collect::<Option<_>>()?;
            let increments =
                increments_from_samples(&time[first..=last], &force, &gyro_nominal[first..=last])
                    .ok()?
                    .into_iter()
                    .zip(time[first..=last].windows(2))
                    .map(|(inc, t)| (inc.delta_angle_b, inc.delta_velocity_b, t[1] - t[0]))
                    .collect();
            segments.push(Segment {
                from: k,
                increments,
                up_from: force_means[k].normalize(),
                up_to: force_means[k + 1].normalize(),
            });
        }
        Some(GyroData {
            gyro_means,
            force_means,
            segments,
        })
    }

    /// Whether a turn is in the rotation fit: neither of its poses is held out.
    pub fn is_fit_turn(&self, segment: &Segment) -> bool {
        !self.held_out[segment.from] && !self.held_out[segment.from + 1]
    }

    /// The turns of `segments` in the rotation fit.
    pub fn fit_turns(&self, segments: &[Segment]) -> Vec<Segment> {
        segments
            .iter()
            .filter(|s| self.is_fit_turn(s))
            .cloned()
            .collect()
    }

    /// The rest fit's data: the gyro and specific-force means of the poses
    /// in the fits.
    pub fn rest_poses(&self, d: &GyroData) -> (Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
        (
            self.fit_poses.iter().map(|&k| d.gyro_means[k]).collect(),
            self.fit_poses.iter().map(|&k| d.force_means[k]).collect(),
        )
    }
}
