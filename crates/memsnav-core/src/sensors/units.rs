//! The units data sheets give IMU figures in, converted to SI: one function
//! per unit, shared by the presets and the data-sheet keys so that a figure
//! written either way is the same number (`consumer()`'s 175 µg/√Hz and
//! `[imu_spec] accel_noise_density_ug_sqrt_hz = 175` are one float).
//!
//! g0 = 9.80665 m/s² (the standard gravity data sheets' g and mg mean).
//! Random walks: a density in unit/√Hz is the same number in unit·√s (a
//! one-sided density d gives a per-sample std d·√f_s, Groves 2nd ed.
//! §4.4.3), and 1 √h = 60 √s, so x unit/√h = x/60 unit/√s (IEEE Std
//! 952-1997 annex C: angle random walk N in °/√h).

use std::f64::consts::PI;

use crate::geodesy::wgs84::STANDARD_GRAVITY_M_S2 as G0;

/// One degree, rad.
pub(crate) const DEG: f64 = PI / 180.0;

/// milli-g → m/s².
pub(crate) fn mg(x: f64) -> f64 {
    x * 1e-3 * G0
}

/// micro-g → m/s².
pub(crate) fn ug(x: f64) -> f64 {
    x * 1e-6 * G0
}

/// °/h → rad/s.
pub(crate) fn deg_h(x: f64) -> f64 {
    x * DEG / 3600.0
}

/// °/s → rad/s.
pub(crate) fn deg_s(x: f64) -> f64 {
    x * DEG
}

/// Angle random walk °/√h → rad/s/√Hz (= rad/√s): ÷ 60.
pub(crate) fn deg_sqrt_h(x: f64) -> f64 {
    x * DEG / 60.0
}

/// Velocity random walk m/s/√h → m/s²/√Hz (= m/s/√s): ÷ 60.
pub(crate) fn m_s_sqrt_h(x: f64) -> f64 {
    x / 60.0
}

/// Rate random walk °/h/√h → rad/s/√s: ÷ 3600 ÷ 60.
pub(crate) fn deg_h_sqrt_h(x: f64) -> f64 {
    deg_h(x) / 60.0
}

/// (°/s)/g → (rad/s)/(m/s²).
pub(crate) fn deg_s_per_g(x: f64) -> f64 {
    x * DEG / G0
}

/// µg/g² → 1/(m/s²): the coefficient N of N f² (µg of output per g² of
/// input).
pub(crate) fn ug_per_g2(x: f64) -> f64 {
    x / 1e6 / G0
}

/// Parts per million → dimensionless.
pub(crate) fn ppm(x: f64) -> f64 {
    x / 1e6
}

/// Percent → dimensionless.
pub(crate) fn percent(x: f64) -> f64 {
    x / 100.0
}

/// Seconds (correlation times are given in s already).
pub(crate) fn seconds(x: f64) -> f64 {
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-computed: 1 °/√h = (π/180)/60 rad/√s = 2.90888e-4; 0.065 ft/s/√h
    /// = 0.065·0.3048/60 = 3.302e-4 m/s/√s; 1 °/h = 4.84814e-6 rad/s;
    /// 1 °/h/√h = 8.08023e-8 rad/s/√s; 175 µg = 1.716164e-3 m/s²;
    /// 100 µg/g² = 1e-4/9.80665 = 1.019716e-5 per m/s².
    #[test]
    fn conversions() {
        assert!((deg_sqrt_h(1.0) - 2.908882e-4).abs() < 1e-10);
        assert!((m_s_sqrt_h(0.065 * 0.3048) - 3.302e-4).abs() < 1e-7);
        assert!((deg_h(1.0) - 4.848137e-6).abs() < 1e-12);
        assert!((deg_h_sqrt_h(1.0) - 8.080229e-8).abs() < 1e-13);
        assert!((ug(175.0) - 1.716164e-3).abs() < 1e-9);
        assert!((mg(20.0) - 0.196133).abs() < 1e-9);
        assert!((ug_per_g2(100.0) - 1.019716e-5).abs() < 1e-11);
        assert_eq!((ppm(300.0), percent(1.0)), (3e-4, 1e-2));
        assert!((deg_s_per_g(0.05) - 8.898e-5).abs() < 1e-8);
    }
}
