//! Static-interval detector of a multi-position calibration (Tedaldi,
//! Pretto and Menegatti, "A robust and easy to implement method for IMU
//! calibration without external equipments", ICRA 2014, §III-A).
//!
//! The session starts with the IMU at rest for `initial_rest_s` seconds
//! (Tedaldi's T_init, ≈ 50 s), then the IMU is turned by hand into a
//! series of poses, each held still for a few seconds. For every sample k
//! the detector computes the variance magnitude
//!
//! ```text
//! ς(k) = ‖ (var a_x, var a_y, var a_z) over the window centred on k ‖
//! ```
//!
//! of the accelerometer readings in a window of `window_s` seconds, and the
//! same magnitude ς_init over the whole initial rest (its sensor noise plus
//! any slow drift). Sample k is static when ς(k) < `threshold_factor` · ς_init
//! (Tedaldi's threshold k · ς_init; the unit of the readings cancels) and the
//! same holds for the gyroscope's readings against their own initial rest.
//! The gyroscope test is ours: a turn about the vertical leaves the
//! accelerometer still, and without it such a turn would be averaged into
//! a pose's gyro rest. A static run of at least `min_pose_s` seconds is a
//! pose: [start, end) in
//! sample indices, the centres of quiet windows, so every sample of a pose
//! is at least half a window away from the motion.
//!
//! Tedaldi et al. repeat the whole calibration for several threshold
//! factors and keep the one with the smallest accelerometer residual. This
//! detector uses one documented factor instead: on the shipped Xsens
//! session a looser threshold (3) admits poses that are still settling,
//! which lowers the in-fit residual (0.76 against 0.86 mm/s²) but raises
//! it on held-out poses from 1.4 to 52 mm/s², so the smallest residual is
//! not the best choice; factors 4 to 10 give the same figures.

use nalgebra::Vector3;

use crate::{validate, Error, Result};

/// Settings of the detector (module docs). All in seconds except the
/// dimensionless factor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticDetector {
    /// Length of the sliding variance window, s. Tedaldi et al. use a
    /// window of about 1 s (imu_tk: 101 samples at 100 Hz).
    pub window_s: f64,
    /// Static when the variance magnitude is below this multiple of the
    /// initial rest's (Tedaldi: k · ς_init with k between 2 and 10).
    pub threshold_factor: f64,
    /// Length of the rest at the start of the session, s (Tedaldi's
    /// T_init ≈ 50 s: long enough to average the gyroscope bias).
    pub initial_rest_s: f64,
    /// Shortest static run kept as a pose, s.
    pub min_pose_s: f64,
}

impl Default for StaticDetector {
    fn default() -> Self {
        Self {
            window_s: 1.0,
            threshold_factor: 6.0,
            initial_rest_s: 50.0,
            min_pose_s: 1.0,
        }
    }
}

/// One static pose: samples `start..end` (end exclusive).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pose {
    /// The first sample of the pose.
    pub start: usize,
    /// One past its last sample.
    pub end: usize,
}

impl Pose {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.end - self.start
    }

    /// True when the pose holds no sample.
    pub fn is_empty(&self) -> bool {
        self.end <= self.start
    }
}

/// The variance magnitude of one triad and its threshold.
#[derive(Debug, Clone, PartialEq)]
pub struct VarianceTest {
    /// ς(k) per sample (squared reading units); +∞ within half a window of
    /// either end, where no full window fits.
    pub variance_magnitude: Vec<f64>,
    /// ς_init, the variance magnitude of the initial rest.
    pub rest_variance_magnitude: f64,
    /// threshold_factor · ς_init.
    pub threshold: f64,
}

/// What the detector found.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticDetection {
    /// The poses in time order; the first is the initial rest.
    pub poses: Vec<Pose>,
    /// The accelerometer's variance test.
    pub accel: VarianceTest,
    /// The gyroscope's variance test.
    pub gyro: VarianceTest,
}

impl StaticDetector {
    fn validate(&self) -> Result<()> {
        validate::positive("window_s", self.window_s)?;
        validate::positive("threshold_factor", self.threshold_factor)?;
        validate::positive("initial_rest_s", self.initial_rest_s)?;
        validate::positive("min_pose_s", self.min_pose_s)?;
        Ok(())
    }

    /// Finds the static poses of `accel` and `gyro` (any units) sampled at
    /// `time_s` (increasing, s). Errors name the argument: too short a
    /// session, an initial rest that is not at rest, no pose after it.
    pub fn detect(
        &self,
        time_s: &[f64],
        accel: &[Vector3<f64>],
        gyro: &[Vector3<f64>],
    ) -> Result<StaticDetection> {
        self.validate()?;
        validate::increasing_times("time", time_s)?;
        validate::same_length("accel", accel.len(), "time", time_s.len())?;
        validate::same_length("gyro", gyro.len(), "time", time_s.len())?;
        validate::finite_vectors("accel", accel)?;
        validate::finite_vectors("gyro", gyro)?;
        let n = time_s.len();
        let duration =
            time_s.last().copied().unwrap_or(0.0) - time_s.first().copied().unwrap_or(0.0);
        if n < 3 || duration <= self.initial_rest_s {
            return Err(Error::invalid(
                "time",
                format!(
                    "the session lasts {duration:.1} s: it must be longer than the initial rest \
                     (initial_rest_s = {} s) followed by poses",
                    self.initial_rest_s
                ),
            ));
        }
        let period = duration / (n - 1) as f64;
        // An odd window of at least 3 samples, centred on each sample.
        let half = ((self.window_s / period / 2.0).round() as usize).max(1);
        let rest_end = time_s.partition_point(|&t| t < time_s[0] + self.initial_rest_s);
        if rest_end < 2 * half + 1 {
            return Err(Error::invalid(
                "initial_rest_s",
                format!("the initial rest holds {rest_end} samples, fewer than one window"),
            ));
        }
        let accel_test = self.variance_test(accel, half, rest_end, "accel")?;
        let gyro_test = self.variance_test(gyro, half, rest_end, "gyro")?;
        let min_samples = ((self.min_pose_s / period).round() as usize).max(1);
        let mut poses = Vec::new();
        let mut start = None;
        for k in 0..=n {
            let still = k < n
                && accel_test.variance_magnitude[k] < accel_test.threshold
                && gyro_test.variance_magnitude[k] < gyro_test.threshold;
            match (still, start) {
                (true, None) => start = Some(k),
                (false, Some(s)) => {
                    if k - s >= min_samples {
                        poses.push(Pose { start: s, end: k });
                    }
                    start = None;
                }
                _ => {}
            }
        }
        // The initial rest must be the first pose and cover most of T_init.
        let covered = poses
            .first()
            .map(|p| p.end.min(rest_end).saturating_sub(p.start))
            .unwrap_or(0);
        if (covered as f64) < 0.8 * (rest_end - half) as f64 {
            return Err(Error::invalid(
                "initial_rest_s",
                format!(
                    "the first {} s are not at rest: no static interval covers most of them \
                     (the IMU must lie still for the whole initial rest)",
                    self.initial_rest_s
                ),
            ));
        }
        if poses.len() < 2 {
            return Err(Error::invalid(
                "accel",
                "no static pose after the initial rest: the detector found only one quiet \
                 interval (raise threshold_factor or check the recording)",
            ));
        }
        Ok(StaticDetection {
            poses,
            accel: accel_test,
            gyro: gyro_test,
        })
    }

    /// ς(k), ς_init and the threshold of one triad (`name` in errors).
    fn variance_test(
        &self,
        samples: &[Vector3<f64>],
        half: usize,
        rest_end: usize,
        name: &str,
    ) -> Result<VarianceTest> {
        let rest_variance_magnitude = variance(&samples[..rest_end]).norm();
        let variance_magnitude = sliding_variance_magnitude(samples, half);
        // At rest, the variance of the whole rest is that of its windows
        // (white noise, a little more for slow drift). Motion inside the
        // rest inflates the former far above the typical window's, and
        // would make the threshold meaningless.
        let mut rest_windows: Vec<f64> = variance_magnitude[half..rest_end - half].to_vec();
        rest_windows.sort_by(f64::total_cmp);
        let typical = rest_windows[rest_windows.len() / 2];
        if rest_variance_magnitude > self.threshold_factor * typical {
            return Err(Error::invalid(
                "initial_rest_s",
                format!(
                    "the first {} s are not at rest: the {name} variance magnitude over them, \
                     {:.3e}, is {:.0} times that of a typical {}-sample window in them (the \
                     IMU must lie still for the whole initial rest)",
                    self.initial_rest_s,
                    rest_variance_magnitude,
                    rest_variance_magnitude / typical,
                    2 * half + 1
                ),
            ));
        }
        Ok(VarianceTest {
            variance_magnitude,
            rest_variance_magnitude,
            threshold: self.threshold_factor * rest_variance_magnitude,
        })
    }
}

/// Unbiased per-axis variance of a run of samples.
fn variance(samples: &[Vector3<f64>]) -> Vector3<f64> {
    let n = samples.len() as f64;
    let mean = samples.iter().sum::<Vector3<f64>>() / n;
    samples
        .iter()
        .map(|s| (s - mean).component_mul(&(s - mean)))
        .sum::<Vector3<f64>>()
        / (n - 1.0)
}

/// ς(k) for windows k − half ..= k + half; +∞ where the window does not fit.
/// Each window is summed afresh (two passes): running sums would carry
/// their rounding from window to window, which swamps the variance of a
/// quiet sensor whose readings have a large offset (raw counts near 32768).
fn sliding_variance_magnitude(samples: &[Vector3<f64>], half: usize) -> Vec<f64> {
    let n = samples.len();
    let mut out = vec![f64::INFINITY; n];
    for k in half..n.saturating_sub(half) {
        out[k] = variance(&samples[k - half..=k + half]).norm();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;
    use rand::Rng as _;
    use rand_distr::StandardNormal;

    /// 100 Hz: 60 s rest, then poses of `hold` s joined by 2 s moves.
    /// Times, readings and the true (start, end) of each still interval.
    type Session = (Vec<f64>, Vec<Vector3<f64>>, Vec<(f64, f64)>);

    /// A quiet gyroscope (noise only) for the sessions below.
    fn quiet_gyro(n: usize, seed: u64) -> Vec<Vector3<f64>> {
        let mut rng = stream(seed, 1);
        (0..n)
            .map(|_| Vector3::from_fn(|_, _| 0.01 * rng.sample::<f64, _>(StandardNormal)))
            .collect()
    }

    fn session(hold: &[f64], seed: u64) -> Session {
        let mut rng = stream(seed, 0);
        let mut time = Vec::new();
        let mut accel = Vec::new();
        let mut truth = vec![(0.0, 60.0)];
        let mut t = 0.0;
        let mut push = |t: f64, level: Vector3<f64>, shake: f64, rng: &mut crate::random::Rng| {
            time.push(t);
            let noise = Vector3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal));
            accel.push(level + noise * 0.01 + Vector3::new(shake, -shake, 0.5 * shake));
        };
        let mut level = Vector3::new(0.0, 0.0, 9.8);
        while t < 60.0 {
            push(t, level, 0.0, &mut rng);
            t += 0.01;
        }
        for (i, &h) in hold.iter().enumerate() {
            let end = t + 2.0;
            while t < end {
                // A turn: a swing of 2 m/s² on top of the noise.
                push(t, level, 2.0 * (3.0 * t).sin(), &mut rng);
                t += 0.01;
            }
            level = Vector3::new((i as f64).sin(), (i as f64).cos(), 9.7);
            truth.push((t, t + h));
            let end = t + h;
            while t < end {
                push(t, level, 0.0, &mut rng);
                t += 0.01;
            }
        }
        (time, accel, truth)
    }

    #[test]
    fn finds_each_pose_within_half_a_window_of_its_true_edges() {
        let (time, accel, truth) = session(&[3.0, 5.0, 2.5, 4.0], 1);
        let det = StaticDetector {
            initial_rest_s: 50.0,
            ..Default::default()
        };
        let found = det
            .detect(&time, &accel, &quiet_gyro(time.len(), 1))
            .unwrap();
        assert_eq!(found.poses.len(), truth.len());
        for (p, (t0, t1)) in found.poses.iter().zip(&truth) {
            let (s, e) = (time[p.start], time[p.end - 1]);
            // Inside the true pose, and trimmed by at most a window's width.
            assert!(s >= *t0 - 0.011 && s <= t0 + 0.55, "start {s} vs {t0}");
            assert!(e <= *t1 + 0.011 && e >= t1 - 0.56, "end {e} vs {t1}");
        }
        let expected = det.threshold_factor * found.accel.rest_variance_magnitude;
        assert_eq!(found.accel.threshold, expected);
    }

    #[test]
    fn short_poses_are_dropped_and_the_window_matches_a_direct_variance() {
        let (time, accel, _) = session(&[3.0, 0.6, 3.0], 2);
        let found = StaticDetector::default()
            .detect(&time, &accel, &quiet_gyro(time.len(), 2))
            .unwrap();
        // The 0.6 s pose is shorter than min_pose_s once trimmed.
        assert_eq!(found.poses.len(), 3);
        let k = 700;
        let direct = variance(&accel[k - 50..=k + 50]).norm();
        assert!((found.accel.variance_magnitude[k] / direct - 1.0).abs() < 1e-9);
        assert!(found.accel.variance_magnitude[10].is_infinite());
    }

    #[test]
    fn a_turn_the_accelerometer_cannot_see_splits_a_pose() {
        let (time, accel, _) = session(&[3.0, 8.0, 3.0], 4);
        let mut gyro = quiet_gyro(time.len(), 4);
        let det = StaticDetector::default();
        let whole = det.detect(&time, &accel, &gyro).unwrap();
        assert_eq!(whole.poses.len(), 4);
        // A 1 s turn about the vertical in the middle of the 8 s pose.
        let middle = (whole.poses[2].start + whole.poses[2].end) / 2;
        for (k, w) in gyro.iter_mut().enumerate().skip(middle).take(100) {
            w.z += (std::f64::consts::PI * (k - middle) as f64 / 100.0).sin();
        }
        let split = det.detect(&time, &accel, &gyro).unwrap();
        assert_eq!(split.poses.len(), 5);
        assert!(split.poses[2].end <= middle && split.poses[3].start >= middle + 100);
    }

    #[test]
    fn a_moving_start_and_bad_settings_are_named() {
        let (time, mut accel, _) = session(&[3.0, 3.0], 3);
        let gyro = quiet_gyro(time.len(), 3);
        let err = StaticDetector {
            window_s: 0.0,
            ..Default::default()
        }
        .detect(&time, &accel, &gyro)
        .unwrap_err();
        assert!(err.to_string().starts_with("window_s:"), "{err}");
        let err = StaticDetector {
            initial_rest_s: 500.0,
            ..Default::default()
        }
        .detect(&time, &accel, &gyro)
        .unwrap_err();
        assert!(err.to_string().starts_with("time:"), "{err}");
        for (k, a) in accel.iter_mut().enumerate().take(3000).skip(1000) {
            a.x += 3.0 * (k as f64 * 0.05).sin();
        }
        let err = StaticDetector::default()
            .detect(&time, &accel, &gyro)
            .unwrap_err();
        assert!(err.to_string().starts_with("initial_rest_s:"), "{err}");
    }
}
