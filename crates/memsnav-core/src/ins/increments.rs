//! The mechanization from velocity and angle increments, with coning and
//! sculling corrections from the previous interval's increments.

use nalgebra::Vector3;

use super::mechanization::{update_attitude, update_velocity_position, EARTH_RATE_ECEF};
use super::{ImuIncrement, NavState};
use crate::{validate, Error, Result};

/// One INS step over an interval of `dt` from the raw increments `curr`
/// (α = ∫ω dt, ν = ∫f dt) of that interval, using the previous
/// interval's increments `prev` for the coning and sculling corrections
/// (pass `ImuIncrement::default()` for the first interval).
///
/// - Coning (Savage 1998 eq. 7.1.1.1-11, one-previous-sample form; Groves
///   §5.5.4): θ = α + (1/12) α_prev × α.
/// - Velocity in the body axes at the interval start, rotation plus
///   sculling (Savage eq. 7.2.2.2-22; Groves §5.5.4):
///   Δv^b = C̄ ν + (1/12)(α_prev × ν + ν_prev × α), with C̄ the average
///   attitude over the interval (≈ I + ½[α×] + ⅙[α×]²), whose
///   second-order term matters when a large specific force is
///   perpendicular to a sustained rotation (a tumbling body).
/// - To ECEF with the Earth's turn during the interval to first order
///   (Groves eq. 5.84): Δv_f^e = C_b^e Δv^b − ½ dt Ω_ie C_b^e ν.
///
/// Both corrections are exact to third order for a rate and specific
/// force that vary linearly across the two intervals.
pub fn step_increments(
    state: &NavState,
    prev: &ImuIncrement,
    curr: &ImuIncrement,
    dt: f64,
) -> NavState {
    let (alpha, nu) = (curr.delta_angle_b, curr.delta_velocity_b);
    let (alpha_p, nu_p) = (prev.delta_angle_b, prev.delta_velocity_b);
    let theta = alpha + alpha_p.cross(&alpha) / 12.0;
    // Rotation of ν into the start-of-interval axes, exact for a constant
    // rate and specific force (Groves eq. 5.86's average attitude matrix):
    // ν + (1 − cos a)/a² α × ν + (1 − sin a / a)/a² α × (α × ν), a = |α|.
    let a2 = alpha.norm_squared();
    let (c1, c2) = if a2 < 1e-6 {
        // Taylor series; the next terms are below 1e-15 relative.
        (
            0.5 - a2 / 24.0 + a2 * a2 / 720.0,
            1.0 / 6.0 - a2 / 120.0 + a2 * a2 / 5040.0,
        )
    } else {
        let a = a2.sqrt();
        ((1.0 - a.cos()) / a2, (1.0 - a.sin() / a) / a2)
    };
    let a_x_nu = alpha.cross(&nu);
    let delta_v_b = nu
        + c1 * a_x_nu
        + c2 * alpha.cross(&a_x_nu)
        + (alpha_p.cross(&nu) + nu_p.cross(&alpha)) / 12.0;
    let c_nu = state.c_b_e * nu;
    let delta_v_f = state.c_b_e * delta_v_b - 0.5 * dt * EARTH_RATE_ECEF.cross(&c_nu);
    let c1 = update_attitude(&state.c_b_e, &theta, dt);
    let (r1, v1) = update_velocity_position(state, &delta_v_f, dt);
    NavState {
        position_ecef: r1,
        velocity_ecef: v1,
        c_b_e: c1,
    }
}

/// Increments ∫f dt and ∫ω dt over each interval [t_k, t_{k+1}] from
/// instantaneous samples: the integral of the cubic through the four
/// samples around the interval (one-sided at the ends; lower degree when
/// fewer than four samples), evaluated exactly by two-point Gauss-Legendre
/// quadrature. Fourth-order accurate: for smooth motion at 100 Hz the
/// result is within ~1e-10 of the exact increments, which makes it a
/// stand-in for an integrating IMU in tests and simulations.
pub fn increments_from_samples(
    time_s: &[f64],
    specific_force_b: &[Vector3<f64>],
    angular_rate_b: &[Vector3<f64>],
) -> Result<Vec<ImuIncrement>> {
    validate::increasing_times("time", time_s)?;
    validate::same_length(
        "specific_force",
        specific_force_b.len(),
        "time",
        time_s.len(),
    )?;
    validate::same_length("angular_rate", angular_rate_b.len(), "time", time_s.len())?;
    validate::finite_vectors("specific_force", specific_force_b)?;
    validate::finite_vectors("angular_rate", angular_rate_b)?;
    let n = time_s.len();
    if n < 2 {
        return Err(Error::invalid("time", "needs at least 2 samples"));
    }
    Ok((0..n - 1)
        .map(|k| cubic_increment(time_s, specific_force_b, angular_rate_b, k))
        .collect())
}

/// The increment over [t_k, t_{k+1}] from the cubic through the (up to)
/// four samples around it; see [`increments_from_samples`]. Needs
/// `time_s.len() ≥ 2` and `k + 1 < time_s.len()`.
pub(super) fn cubic_increment(
    time_s: &[f64],
    specific_force_b: &[Vector3<f64>],
    angular_rate_b: &[Vector3<f64>],
    k: usize,
) -> ImuIncrement {
    let n = time_s.len();
    let width = n.min(4);
    let first = k.saturating_sub(1).min(n - width);
    // Gauss-Legendre nodes on [0, 1], equal weights ½: exact for cubics.
    let offset = 0.5 / 3f64.sqrt();
    let (t0, dt) = (time_s[k], time_s[k + 1] - time_s[k]);
    let mut dv = Vector3::zeros();
    let mut da = Vector3::zeros();
    for u in [0.5 - offset, 0.5 + offset] {
        let t = t0 + u * dt;
        for j in first..first + width {
            // Lagrange basis polynomial of node j at t.
            let mut l = 1.0;
            for m in first..first + width {
                if m != j {
                    l *= (t - time_s[m]) / (time_s[j] - time_s[m]);
                }
            }
            dv += 0.5 * dt * l * specific_force_b[j];
            da += 0.5 * dt * l * angular_rate_b[j];
        }
    }
    ImuIncrement {
        delta_velocity_b: dv,
        delta_angle_b: da,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn increments_are_exact_for_cubics_on_uneven_times() {
        let time = [0.0, 0.1, 0.25, 0.3, 0.42, 0.5];
        let p = |t: f64| 1.0 - 2.0 * t + 3.0 * t * t - 4.0 * t * t * t;
        let integral = |t: f64| t - t * t + t * t * t - t.powi(4);
        let f: Vec<_> = time
            .iter()
            .map(|&t| Vector3::new(p(t), 2.0 * p(t), 0.0))
            .collect();
        let w: Vec<_> = time
            .iter()
            .map(|&t| Vector3::new(0.0, 0.0, -p(t)))
            .collect();
        let inc = increments_from_samples(&time, &f, &w).unwrap();
        assert_eq!(inc.len(), 5);
        for (k, i) in inc.iter().enumerate() {
            let exact = integral(time[k + 1]) - integral(time[k]);
            assert!((i.delta_velocity_b.x - exact).abs() < 1e-14, "{k}");
            assert!((i.delta_velocity_b.y - 2.0 * exact).abs() < 1e-14);
            assert!((i.delta_angle_b.z + exact).abs() < 1e-14);
        }
        // Two samples: the trapezoid.
        let inc = increments_from_samples(&[0.0, 2.0], &f[..2], &w[..2]).unwrap();
        assert!((inc[0].delta_velocity_b.x - (p(0.0) + p(0.1))).abs() < 1e-15);
    }
}
