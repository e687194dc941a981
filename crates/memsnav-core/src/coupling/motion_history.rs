//! The recent motion of the IMU, for predicting the antenna's velocity at
//! a slightly earlier time (a time offset or a velocity latency: the fixes'
//! velocity at t is the antenna's at t − L).
//!
//! v_a(t − L) = v(t − L) + M(t − L) l − Ω_ie C l with M = Ĉ [ω̂×]. Moving
//! back along the acceleration alone, v − L a with M(t) l, misses the
//! change of a and of M over L: a car pitches with its acceleration
//! (squat), so ½ L² ȧ is read as a pitch rate times a vertical lever arm
//! (a 0.2 s latency biased a simulated vertical lever arm by 1.3 m), and
//! at a turn entry with a 2 m lever arm M changes by 0.1-0.2 m/s worth.
//! So the history keeps, at least [`SPACING_S`] apart over the last
//! [`SLOTS`] × that, M and the mechanization's accumulated velocity change
//! D (Σ of its velocity increments, untouched by the filter's feedback, so
//! v(t − L) = v̂(t) − (D(t) − D(t − L)) to the INS's accuracy), in a fixed
//! ring (no allocation per epoch), read back by linear interpolation.

use nalgebra::{Matrix3, Vector3};

/// Entries kept.
const SLOTS: usize = 64;
/// Least time between two entries, s: 64 × 20 ms = 1.28 s of history,
/// beyond any time offset and latency a receiver has.
const SPACING_S: f64 = 0.02;

/// One entry: time, M and D.
#[derive(Debug, Clone, Copy)]
struct Entry {
    time_s: f64,
    rotation: Matrix3<f64>,
    velocity_change_ecef: Vector3<f64>,
}

/// The motion at an earlier time, from [`MotionHistory::at`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PastMotion {
    /// M = Ĉ [ω̂×] then.
    pub(crate) rotation: Matrix3<f64>,
    /// Ṁ then, 1/s².
    pub(crate) rotation_rate: Matrix3<f64>,
    /// D(now) − D(then): the velocity change since, m/s.
    pub(crate) velocity_change_since_ecef: Vector3<f64>,
    /// Ḋ then: the IMU's acceleration, m/s².
    pub(crate) acceleration_ecef: Vector3<f64>,
}

/// M and D at recent times, oldest overwritten first, and now.
#[derive(Debug, Clone)]
pub(crate) struct MotionHistory {
    entries: [Entry; SLOTS],
    /// Index of the newest entry; `len` entries are valid.
    newest: usize,
    len: usize,
    /// M and D at the last step (the newest point of the history).
    now: Entry,
}

impl Default for MotionHistory {
    fn default() -> Self {
        let empty = Entry {
            time_s: f64::NAN,
            rotation: Matrix3::zeros(),
            velocity_change_ecef: Vector3::zeros(),
        };
        Self {
            entries: [empty; SLOTS],
            newest: 0,
            len: 0,
            now: Entry {
                velocity_change_ecef: Vector3::zeros(),
                ..empty
            },
        }
    }
}

impl MotionHistory {
    /// Adds one mechanization step's velocity change, M and the time
    /// `time_s` after it, and keeps them in the ring when its newest entry
    /// is at least [`SPACING_S`] older (times increase).
    pub(crate) fn record(
        &mut self,
        time_s: f64,
        rotation: Matrix3<f64>,
        velocity_step_ecef: Vector3<f64>,
    ) {
        self.now = Entry {
            time_s,
            rotation,
            velocity_change_ecef: self.now.velocity_change_ecef + velocity_step_ecef,
        };
        if self.len > 0 && time_s - self.entries[self.newest].time_s < SPACING_S {
            return;
        }
        self.newest = (self.newest + 1) % SLOTS;
        self.entries[self.newest] = self.now;
        self.len = (self.len + 1).min(SLOTS);
    }

    /// The motion at `time_s`: linear between the two points around it
    /// (the ring's entries and now); after now, extrapolated along the last
    /// stretch longer than a thousandth of the spacing; before the oldest
    /// entry, that entry held (no change); `None` before two entries.
    pub(crate) fn at(&self, time_s: f64) -> Option<PastMotion> {
        if self.len < 2 {
            return None;
        }
        let point = |step: usize| self.entries[(self.newest + SLOTS - step) % SLOTS];
        // From now back: the stretch (earlier, later) that holds time_s.
        let mut later = self.now;
        for step in 0..self.len {
            let earlier = point(step);
            let span = later.time_s - earlier.time_s;
            if span < 1e-3 * SPACING_S || (earlier.time_s > time_s && step + 1 < self.len) {
                if span >= 1e-3 * SPACING_S {
                    later = earlier;
                }
                continue;
            }
            let u = ((time_s - earlier.time_s) / span).max(0.0);
            let rotation_change = later.rotation - earlier.rotation;
            let velocity_change = later.velocity_change_ecef - earlier.velocity_change_ecef;
            let held = time_s < earlier.time_s;
            return Some(PastMotion {
                rotation: earlier.rotation + rotation_change * u,
                rotation_rate: if held {
                    Matrix3::zeros()
                } else {
                    rotation_change / span
                },
                velocity_change_since_ecef: self.now.velocity_change_ecef
                    - (earlier.velocity_change_ecef + velocity_change * u),
                acceleration_ecef: if held {
                    Vector3::zeros()
                } else {
                    velocity_change / span
                },
            });
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A motion whose M and D change linearly in time is read back exactly
    /// between entries, with its rates; outside the history it is the end
    /// value held; the ring keeps only the last 64 entries.
    #[test]
    fn reads_back_a_linear_history_and_its_rates() {
        let m = |t: f64| Matrix3::from_fn(|i, j| (i as f64 + 1.0) * t - j as f64);
        let rate = Matrix3::from_fn(|i, _| i as f64 + 1.0);
        let acceleration = Vector3::new(0.5, -1.0, 2.0);
        let mut h = MotionHistory::default();
        assert!(h.at(0.0).is_none());
        let dt = 0.01;
        for k in 0..1000 {
            let t = k as f64 * dt;
            h.record(t, m(t), acceleration * dt);
        }
        // D(t) = a (t + dt) after the step at t; now t = 9.99 s.
        let t = 9.5 + 0.013;
        let past = h.at(t).unwrap();
        assert!((past.rotation - m(t)).norm() < 1e-9);
        assert!((past.rotation_rate - rate).norm() < 1e-9);
        assert!((past.acceleration_ecef - acceleration).norm() < 1e-9);
        let since = acceleration * (9.99 - t);
        assert!((past.velocity_change_since_ecef - since).norm() < 1e-9);
        // After now (9.99 s): extrapolated along the last stretch.
        let ahead = h.at(10.05).unwrap();
        assert!((ahead.rotation - m(10.05)).norm() < 1e-9);
        assert!((ahead.velocity_change_since_ecef + acceleration * 0.06).norm() < 1e-9);
        // Between the newest entry (9.98 s) and now.
        let recent = h.at(9.985).unwrap();
        assert!((recent.acceleration_ecef - acceleration).norm() < 1e-9);
        // Before the oldest entry (64 entries at least 0.02 s apart, the
        // spacing rounding to 0.03 s now and then): that entry, held.
        let oldest = h.at(1.0).unwrap();
        let t_oldest = oldest.rotation[(0, 0)];
        assert!((8.0..=8.72 + 1e-9).contains(&t_oldest), "{t_oldest}");
        assert!((oldest.rotation - m(t_oldest)).norm() < 1e-9);
        assert_eq!(oldest.rotation_rate, Matrix3::zeros());
    }
}
