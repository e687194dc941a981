//! The ECEF mechanization from instantaneous samples at both ends of an
//! interval, second order (local error O(dt³) that does not accumulate
//! systematically for smooth motion).

use nalgebra::{Matrix3, Vector3};

use super::{ImuSample, NavState};
use crate::attitude::rotation_vector_to_dcm;
use crate::geodesy::{gravity_ecef, wgs84::EARTH_RATE_RAD_S};

/// ω_ie^e.
pub(super) const EARTH_RATE_ECEF: Vector3<f64> = Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S);

/// C_{e(t)}^{e(t+dt)}: the Earth turns by ω_ie dt about z during the
/// interval (exact; Groves eq. 5.73 keeps its first-order form). The
/// mechanization applies it through [`earth_rotated`]; the tests check
/// that against this matrix.
#[cfg(test)]
fn earth_rotation(dt: f64) -> Matrix3<f64> {
    let (s, c) = (EARTH_RATE_RAD_S * dt).sin_cos();
    Matrix3::new(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0)
}

/// C_{e(t)}^{e(t+dt)} C: the rows of C turned about z, the zeros of the
/// Earth rotation left out (the products and sums that remain are those
/// of the full 3 × 3 product, in its order: the same result). sin/cos of
/// ω_ie dt are kept per thread for the last dt: at a fixed IMU rate every
/// step asks for the same one.
fn earth_rotated(dt: f64, c: &Matrix3<f64>) -> Matrix3<f64> {
    thread_local! {
        static LAST: std::cell::Cell<(f64, f64, f64)> = const { std::cell::Cell::new((f64::NAN, 0.0, 1.0)) };
    }
    let (s, co) = LAST.with(|last| {
        let (t, s, co) = last.get();
        if t == dt {
            (s, co)
        } else {
            let (s, co) = (EARTH_RATE_RAD_S * dt).sin_cos();
            last.set((dt, s, co));
            (s, co)
        }
    });
    Matrix3::from_fn(|i, j| match i {
        0 => co * c[(0, j)] + s * c[(1, j)],
        1 => -s * c[(0, j)] + co * c[(1, j)],
        _ => c[(2, j)],
    })
}

/// Attitude update: C_b^e(+) = C_{e−}^{e+} C_b^e(−) exp([θ×]) where θ is
/// the body's rotation vector over the interval relative to inertial space
/// (Groves eq. 5.73/5.75 with the exact rotation instead of its series).
/// One first-order re-orthonormalisation step C ← C − ½ C (CᵀC − I) keeps
/// rounding errors from accumulating over hours.
pub(super) fn update_attitude(
    c_b_e: &Matrix3<f64>,
    rotation_vector_b: &Vector3<f64>,
    dt: f64,
) -> Matrix3<f64> {
    let c = earth_rotated(dt, c_b_e) * rotation_vector_to_dcm(rotation_vector_b);
    c - 0.5 * c * (c.transpose() * c - Matrix3::identity())
}

/// Velocity and position update given the attitude-weighted specific-force
/// velocity increment Δv_f^e = ∫ C_b^e f_ib^b dt over the interval.
///
/// v̇ = C_b^e f + g(r) − 2 Ω_ie v (Groves eq. 5.36): the gravity and
/// Coriolis terms are integrated by Heun's predictor-corrector (trapezoid),
/// the position by the trapezoid of the velocity (Groves eq. 5.38's
/// higher-order form).
pub(super) fn update_velocity_position(
    state: &NavState,
    delta_v_f_ecef: &Vector3<f64>,
    dt: f64,
) -> (Vector3<f64>, Vector3<f64>) {
    let r0 = state.position_ecef;
    let v0 = state.velocity_ecef;
    let g0 = gravity_ecef(&r0);
    let coriolis0 = 2.0 * EARTH_RATE_ECEF.cross(&v0);
    let v_pred = v0 + delta_v_f_ecef + dt * (g0 - coriolis0);
    let r_pred = r0 + 0.5 * dt * (v0 + v_pred);
    let g1 = gravity_ecef(&r_pred);
    let coriolis1 = 2.0 * EARTH_RATE_ECEF.cross(&v_pred);
    let v1 = v0 + delta_v_f_ecef + 0.5 * dt * (g0 + g1 - coriolis0 - coriolis1);
    let r1 = r0 + 0.5 * dt * (v0 + v1);
    (r1, v1)
}

/// One INS step from `state` at t to t + `dt`, with the instantaneous IMU
/// samples `prev` at t and `curr` at t + dt.
///
/// - Attitude: the rate is taken linear over the interval; its exact
///   rotation vector to second order (Bortz equation, Savage 1998 §7.1.1)
///   is θ = ½ dt (ω₀ + ω₁) + dt²/12 ω₀ × ω₁, the last term being the coning
///   correction for a linearly varying rate.
/// - Specific force: Δv_f^e = ½ dt (C_b^e(t) f₀ + C_b^e(t+dt) f₁), the
///   trapezoid of the ECEF specific force, which already accounts for the
///   body's rotation (no separate sculling term).
///
/// `dt` must be positive; the drivers check it.
pub fn step(state: &NavState, prev: &ImuSample, curr: &ImuSample, dt: f64) -> NavState {
    let (w0, w1) = (prev.angular_rate_b, curr.angular_rate_b);
    let theta = 0.5 * dt * (w0 + w1) + (dt * dt / 12.0) * w0.cross(&w1);
    let c1 = update_attitude(&state.c_b_e, &theta, dt);
    let delta_v_f = 0.5 * dt * (state.c_b_e * prev.specific_force_b + c1 * curr.specific_force_b);
    let (r1, v1) = update_velocity_position(state, &delta_v_f, dt);
    NavState {
        position_ecef: r1,
        velocity_ecef: v1,
        c_b_e: c1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The structured product is the full one, bitwise, for any dt
    /// (also when dt changes between calls).
    #[test]
    fn earth_rotated_is_the_full_product() {
        let c = crate::attitude::euler_to_dcm(0.3, -1.2, 2.9);
        for dt in [0.01, 0.005, 0.01, 3600.0, 1e-9] {
            assert_eq!(earth_rotated(dt, &c), earth_rotation(dt) * c, "dt {dt}");
        }
    }

    #[test]
    fn earth_rotation_turns_ecef_axes_backwards() {
        // A direction fixed in inertial space appears to turn by −ω dt
        // about z in ECEF.
        let dt = 3600.0;
        let c = earth_rotation(dt);
        let v = c * Vector3::x();
        let angle = v.y.atan2(v.x);
        assert!((angle + EARTH_RATE_RAD_S * dt).abs() < 1e-15);
    }
}
