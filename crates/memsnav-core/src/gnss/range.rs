//! Predicted range and range rate with the Sagnac correction (Groves,
//! *Principles of GNSS, Inertial, and Multisensor Integrated Navigation
//! Systems*, 2nd ed., eqs. 8.41-8.46).

use nalgebra::{Matrix3, Vector3};

use crate::geodesy::wgs84::{EARTH_RATE_RAD_S, SPEED_OF_LIGHT_M_S};

/// Range, range rate and line of sight from the receiver to a satellite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RangePrediction {
    /// Geometric range corrected for the Earth's rotation during the signal
    /// travel time (Sagnac), m.
    pub range_m: f64,
    /// Its rate of change at the receiver, m/s.
    pub range_rate_m_s: f64,
    /// Unit vector from receiver to satellite, ECEF at reception, u_as^e.
    pub line_of_sight_ecef: Vector3<f64>,
    /// ∂ρ̇/∂r_a, the rate's change with the receiver position (the line of
    /// sight turning), 1/s: −(I − u uᵀ) Δv / ρ + ω_ie × u with Δv the
    /// inertial velocity of the satellite relative to the receiver (the
    /// light-time factor, 1 + 1e-5, and the Earth's turn as the light time
    /// changes with position, ≈ 1e-9 per metre, left out).
    pub range_rate_position_gradient: Vector3<f64>,
}

/// C_e^I of Groves eq. 8.36 with the exact rotation angle ω_ie τ: turns the
/// ECEF frame of the transmission time into the ECEF frame of the
/// reception time τ seconds later.
fn sagnac_rotation(travel_time_s: f64) -> Matrix3<f64> {
    let (s, c) = (EARTH_RATE_RAD_S * travel_time_s).sin_cos();
    Matrix3::new(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0)
}

/// Predicted range and range rate (receiver clock excluded).
///
/// `sat_pos`, `sat_vel`: satellite at transmission time, in the ECEF frame
/// of the transmission time (as [`super::SatelliteMeasurement`] holds them);
/// `rx_pos`, `rx_vel`: receiver at reception time, ECEF.
///
/// The range is ρ = |C_e^I(τ) r_es − r_ea| with τ = ρ/c (Groves eqs. 8.41,
/// 8.42), iterated to convergence (three passes reach 1e-9 m). The rate is
/// Groves eq. 8.45, u_asᵀ [C_e^I (v_es + Ω_ie r_es) − (v_ea + Ω_ie r_ea)],
/// divided by (1 + u_asᵀ C_e^I (v_es + Ω_ie r_es) / c): the light-time rate
/// factor Groves neglects (≈ 1e-5 relative, up to ~1 cm/s), kept so that
/// the prediction is the exact derivative of the range.
pub fn predicted_range(
    sat_pos: &Vector3<f64>,
    sat_vel: &Vector3<f64>,
    rx_pos: &Vector3<f64>,
    rx_vel: &Vector3<f64>,
) -> RangePrediction {
    let mut range = (sat_pos - rx_pos).norm();
    let mut c_e_i = sagnac_rotation(range / SPEED_OF_LIGHT_M_S);
    for _ in 0..3 {
        range = (c_e_i * sat_pos - rx_pos).norm();
        c_e_i = sagnac_rotation(range / SPEED_OF_LIGHT_M_S);
    }
    let delta = c_e_i * sat_pos - rx_pos;
    let range = delta.norm();
    let u = delta / range;
    let omega = Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S);
    // Inertial velocities in the frame aligned with ECEF at reception.
    let sat_vel_i = c_e_i * (sat_vel + omega.cross(sat_pos));
    let rx_vel_i = rx_vel + omega.cross(rx_pos);
    let range_rate =
        u.dot(&(sat_vel_i - rx_vel_i)) / (1.0 + u.dot(&sat_vel_i) / SPEED_OF_LIGHT_M_S);
    let relative = sat_vel_i - rx_vel_i;
    RangePrediction {
        range_m: range,
        range_rate_m_s: range_rate,
        line_of_sight_ecef: u,
        range_rate_position_gradient: -(relative - u * u.dot(&relative)) / range + omega.cross(&u),
    }
}
