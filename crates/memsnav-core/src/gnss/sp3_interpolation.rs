//! Precise orbits between their epochs: Lagrange interpolation of an SP3
//! file's positions over the 10 epochs around the time (order 9, the usual
//! choice for 5-15 min orbits: Schenewerk 2003, GPS Solutions 7, "A brief
//! review of basic GPS orbit interpolation strategies"), the velocity from
//! the polynomial's derivative, the clock linear between its two epochs.

use nalgebra::Vector3;

use super::satellite_state::SatelliteState;
use super::sp3::Sp3;

/// Epochs in each interpolation.
const POINTS: usize = 10;

impl Sp3 {
    /// The state of satellite `sat` (index into `satellites`) at GPS time
    /// `gps_time_s`: position and velocity (ECEF, m, m/s) by 10-point
    /// Lagrange interpolation, the clock (s, NaN where the file has none)
    /// linear between the epochs around the time. `None` outside the
    /// file's epochs or where one of the 10 positions is missing.
    pub fn state_at(&self, sat: usize, gps_time_s: f64) -> Option<SatelliteState> {
        let t = &self.time_gps_s;
        if t.len() < POINTS || !(t[0]..=t[t.len() - 1]).contains(&gps_time_s) {
            return None;
        }
        // The window of POINTS epochs centred on the time, inside the file.
        let after = t.partition_point(|&x| x <= gps_time_s);
        let start = after.saturating_sub(POINTS / 2).min(t.len() - POINTS);
        let window = start..start + POINTS;
        let mut position = Vector3::zeros();
        let mut velocity = Vector3::zeros();
        for i in window.clone() {
            let p = self.position(i, sat);
            if !p.iter().all(|x| x.is_finite()) {
                return None;
            }
            // L_i(t) = Π_{j≠i} (t − t_j)/(t_i − t_j) and its derivative
            // L_i'(t) = L_i(t) Σ_{j≠i} 1/(t − t_j), written without the
            // division so it holds at an epoch too.
            let mut weight = 1.0;
            let mut denominator = 1.0;
            for j in window.clone().filter(|&j| j != i) {
                weight *= gps_time_s - t[j];
                denominator *= t[i] - t[j];
            }
            let mut slope = 0.0;
            for k in window.clone().filter(|&k| k != i) {
                let mut product = 1.0;
                for j in window.clone().filter(|&j| j != i && j != k) {
                    product *= gps_time_s - t[j];
                }
                slope += product;
            }
            position += p * (weight / denominator);
            velocity += p * (slope / denominator);
        }
        let k = after.clamp(1, t.len() - 1);
        let f = (gps_time_s - t[k - 1]) / (t[k] - t[k - 1]);
        let clock = self.clock(k - 1, sat) * (1.0 - f) + self.clock(k, sat) * f;
        let drift = (self.clock(k, sat) - self.clock(k - 1, sat)) / (t[k] - t[k - 1]);
        Some(SatelliteState {
            position_ecef: position,
            velocity_ecef: velocity,
            clock_bias_s: clock,
            clock_drift_s_s: drift,
            relativistic_s: 0.0,
        })
    }
}
