//! Standstill detection from the IMU: a vehicle at rest shows little
//! spread of specific force and angular rate over a second, a moving one
//! much more (the statistics of Skog et al., "Zero-velocity detection — an
//! algorithm evaluation", IEEE TBME 2010, in their simplest, per-axis
//! variance form). The IMU test alone cannot tell rest from smooth
//! cruising, so the run adds the GNSS ground speed, or in an outage the
//! solution's own speed (see [`super::StandstillConfig`]).

use std::collections::VecDeque;

use nalgebra::Vector3;

use super::config::StandstillConfig;
use crate::ins::ImuSample;

/// Mean and per-axis std of the samples in a window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowStats {
    /// Number of samples.
    pub samples: usize,
    /// Mean specific force, m/s².
    pub mean_specific_force_b: Vector3<f64>,
    /// Mean angular rate, rad/s.
    pub mean_angular_rate_b: Vector3<f64>,
    /// Std of the specific force per axis, m/s².
    pub std_specific_force_b: Vector3<f64>,
    /// Std of the angular rate per axis, rad/s.
    pub std_angular_rate_b: Vector3<f64>,
}

impl WindowStats {
    /// Whether the IMU alone looks at rest: the norms of the per-axis stds
    /// below the thresholds of `config`.
    pub fn still(&self, config: &StandstillConfig) -> bool {
        self.std_specific_force_b.norm() < config.accel_std_m_s2
            && self.std_angular_rate_b.norm() < config.gyro_std_rad_s
    }
}

/// The last `capacity` raw IMU samples (body axes).
#[derive(Debug, Clone)]
pub(crate) struct Window {
    capacity: usize,
    samples: VecDeque<ImuSample>,
}

impl Window {
    /// A window of `window_s` seconds at `rate_hz` (at least two samples).
    pub(crate) fn new(window_s: f64, rate_hz: f64) -> Self {
        let capacity = ((window_s * rate_hz).round() as usize).max(2);
        Self {
            capacity,
            samples: VecDeque::with_capacity(capacity),
        }
    }

    pub(crate) fn push(&mut self, sample: ImuSample) {
        if self.samples.len() == self.capacity {
            self.samples.pop_front();
        }
        self.samples.push_back(sample);
    }

    /// Whether the window holds `capacity` samples.
    pub(crate) fn full(&self) -> bool {
        self.samples.len() == self.capacity
    }

    /// Mean and std of the window (two passes: no cancellation).
    pub(crate) fn stats(&self) -> WindowStats {
        stats(self.samples.iter())
    }
}

/// Mean and per-axis std (sample std, n − 1) of `samples`.
pub fn stats<'a>(samples: impl Iterator<Item = &'a ImuSample> + Clone) -> WindowStats {
    let n = samples.clone().count().max(1) as f64;
    let (sf, sw) = samples
        .clone()
        .fold((Vector3::zeros(), Vector3::zeros()), |acc, s| {
            (acc.0 + s.specific_force_b, acc.1 + s.angular_rate_b)
        });
    let (mf, mw) = (sf / n, sw / n);
    let (vf, vw) = samples
        .clone()
        .fold((Vector3::zeros(), Vector3::zeros()), |acc, s| {
            let (df, dw) = (s.specific_force_b - mf, s.angular_rate_b - mw);
            (acc.0 + df.component_mul(&df), acc.1 + dw.component_mul(&dw))
        });
    let d = (n - 1.0).max(1.0);
    WindowStats {
        samples: n as usize,
        mean_specific_force_b: mf,
        mean_angular_rate_b: mw,
        std_specific_force_b: (vf / d).map(f64::sqrt),
        std_angular_rate_b: (vw / d).map(f64::sqrt),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(f: [f64; 3], w: [f64; 3]) -> ImuSample {
        ImuSample {
            specific_force_b: Vector3::from(f),
            angular_rate_b: Vector3::from(w),
        }
    }

    /// Against numpy-style statistics written out: mean and the n − 1 std.
    #[test]
    fn window_keeps_the_last_samples_and_their_statistics() {
        let mut w = Window::new(0.03, 100.0);
        for k in 0..5 {
            let x = k as f64;
            w.push(sample([x, 2.0 * x, -9.8], [0.0, 0.0, 0.1 * x]));
        }
        assert!(w.full());
        let s = w.stats();
        assert_eq!(s.samples, 3);
        // The last three x values: 2, 3, 4: mean 3, std 1.
        assert!((s.mean_specific_force_b - Vector3::new(3.0, 6.0, -9.8)).norm() < 1e-12);
        assert!((s.std_specific_force_b - Vector3::new(1.0, 2.0, 0.0)).norm() < 1e-12);
        assert!((s.std_angular_rate_b.z - 0.1).abs() < 1e-12);
        let config = StandstillConfig::default();
        assert!(!s.still(&config));
        let mut quiet = Window::new(1.0, 10.0);
        for k in 0..10 {
            let e = 0.01 * ((k % 3) as f64 - 1.0);
            quiet.push(sample([e, -e, -9.8 + e], [e * 0.01, 0.0, 0.003]));
        }
        assert!(quiet.stats().still(&config));
    }
}
