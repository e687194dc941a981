//! A satellite's position, velocity and clock correction at one GPS time:
//! what a broadcast ephemeris ([`super::BroadcastOrbit`]) and a Walker slot
//! ([`super::constellation::Orbit`]) both evaluate to.

use nalgebra::Vector3;

/// A satellite's state at one GPS time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SatelliteState {
    /// ECEF position (of the instant), m.
    pub position_ecef: Vector3<f64>,
    /// ECEF velocity, m/s.
    pub velocity_ecef: Vector3<f64>,
    /// Satellite clock correction Δt_sv, s, including the relativistic
    /// term, for the signal the evaluation names: GPS L1 C/A (−T_GD),
    /// Galileo E1 (−BGD E1/E5b), BeiDou B3I, or the clock reference without
    /// a group delay from [`super::BroadcastOrbit::state_at`]; zero for a
    /// Walker satellite.
    pub clock_bias_s: f64,
    /// Its rate, s/s.
    pub clock_drift_s_s: f64,
    /// The relativistic part Δt_r of `clock_bias_s`, s (precise clock
    /// products exclude it).
    pub relativistic_s: f64,
}
