//! The GNSS antenna as the filter predicts it: the IMU solution moved by
//! the lever arm l (IMU to antenna, body axes), and the measurement rows of
//! a position or velocity at the antenna (Groves eq. 2.124-2.125 for the
//! lever arm, eq. 14.113 and 14.127 for its rows).
//!
//! ```text
//! r_a = r̂ + Ĉ l
//! v_a = v̂ + Ĉ (ω̂ × l) − Ω_ie Ĉ l
//! ```
//!
//! With Ĉ = (I + [ψ×]) C, Ĉ a − C a = −[(Ĉ a)×] ψ, and ω̂ − ω = −δb_g, the
//! errors (estimate − truth) are
//!
//! ```text
//! δr_a = δr − [(Ĉ l)×] ψ
//! δv_a = δv + (Ω_ie [(Ĉ l)×] − [(Ĉ (ω̂ × l))×]) ψ + Ĉ [l×] δb_g
//! ```

use nalgebra::{Matrix3, Vector3};

use super::engine::FilterState;
use crate::attitude::skew;
use crate::filter::state::{ATTITUDE, GYRO_BIAS, POSITION, VELOCITY};
use crate::filter::SparseRow;
use crate::geodesy::gravity_ecef;
use crate::geodesy::wgs84::EARTH_RATE_RAD_S;

/// Earth rotation rate vector ω_ie^e.
const EARTH_RATE_ECEF: Vector3<f64> = Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S);

/// The antenna position and velocity the filter predicts, with the
/// derivatives of their errors with respect to the error state.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AntennaPrediction {
    /// r_a, ECEF, m.
    pub(crate) position_ecef: Vector3<f64>,
    /// v_a, ECEF, m/s.
    pub(crate) velocity_ecef: Vector3<f64>,
    /// ∂δr_a/∂ψ = −[(Ĉ l)×].
    position_attitude: Matrix3<f64>,
    /// ∂δv_a/∂ψ.
    velocity_attitude: Matrix3<f64>,
    /// ∂δv_a/∂δb_g = Ĉ [l×].
    velocity_gyro_bias: Matrix3<f64>,
}

impl AntennaPrediction {
    /// The row of w · δr_a (w: weights of the ECEF components, e.g. a
    /// negative line of sight or a row of a whitening matrix).
    pub(crate) fn position_row(&self, w: &Vector3<f64>) -> SparseRow {
        block_row(w, POSITION, &[(ATTITUDE, &self.position_attitude)])
    }

    /// The row of w · δv_a.
    pub(crate) fn velocity_row(&self, w: &Vector3<f64>) -> SparseRow {
        block_row(
            w,
            VELOCITY,
            &[
                (ATTITUDE, &self.velocity_attitude),
                (GYRO_BIAS, &self.velocity_gyro_bias),
            ],
        )
    }
}

/// w·δ(first..first+3) + Σ w·B δ(block): the identity block at `first` and
/// the given 3×3 blocks, zero entries left out (no lever arm: no attitude
/// terms).
fn block_row(w: &Vector3<f64>, first: usize, blocks: &[(usize, &Matrix3<f64>)]) -> SparseRow {
    let mut row = SparseRow::default();
    for k in 0..3 {
        if w[k] != 0.0 {
            row.push(first + k, w[k]);
        }
    }
    for (start, b) in blocks {
        let coefficients = b.transpose() * w;
        for k in 0..3 {
            if coefficients[k] != 0.0 {
                row.push(start + k, coefficients[k]);
            }
        }
    }
    row
}

impl<const N: usize> FilterState<N> {
    /// The antenna's position and velocity and their error rows, from the
    /// current solution and the last corrected angular rate.
    pub(crate) fn antenna(&self) -> AntennaPrediction {
        let c = self.nav.c_b_e;
        let l = self.tuning.antenna_lever_arm_b_m;
        let cl = c * l;
        let rotating = c * self.last_sample.angular_rate_b.cross(&l);
        let omega_ie = skew(&EARTH_RATE_ECEF);
        AntennaPrediction {
            position_ecef: self.nav.position_ecef + cl,
            velocity_ecef: self.nav.velocity_ecef + self.lever_arm_velocity(),
            position_attitude: -skew(&cl),
            velocity_attitude: omega_ie * skew(&cl) - skew(&rotating),
            velocity_gyro_bias: c * skew(&l),
        }
    }

    /// v_a − v̂ = Ĉ (ω̂ × l) − Ω_ie Ĉ l.
    pub(crate) fn lever_arm_velocity(&self) -> Vector3<f64> {
        let c = self.nav.c_b_e;
        let l = self.tuning.antenna_lever_arm_b_m;
        c * self.last_sample.angular_rate_b.cross(&l) - EARTH_RATE_ECEF.cross(&(c * l))
    }

    /// The IMU's acceleration in ECEF, Ĉ f̂ + g(r̂) − 2 Ω_ie v̂ (Groves eq.
    /// 5.36), for moving a velocity to a slightly earlier time.
    pub(crate) fn acceleration_ecef(&self) -> Vector3<f64> {
        self.nav.c_b_e * self.last_sample.specific_force_b + gravity_ecef(&self.nav.position_ecef)
            - 2.0 * EARTH_RATE_ECEF.cross(&self.nav.velocity_ecef)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::{euler_to_dcm, rotation_vector_to_dcm};
    use crate::coupling::{FilterTuning, InitialState};
    use crate::filter::state::BASE_STATES;
    use crate::geodesy::{c_n_e, geodetic_to_ecef, Geodetic};
    use crate::ins::NavState;
    use nalgebra::SVector;

    fn state(lever: Vector3<f64>) -> FilterState<BASE_STATES> {
        let r = geodetic_to_ecef(Geodetic::new(0.7, 0.3, 200.0));
        let c = c_n_e(0.7, 0.3) * euler_to_dcm(0.1, -0.05, 2.0);
        let init = InitialState {
            nav: NavState {
                position_ecef: r,
                velocity_ecef: Vector3::new(5.0, -3.0, 1.0),
                c_b_e: c,
            },
            accel_bias_m_s2: Vector3::zeros(),
            gyro_bias_rad_s: Vector3::new(0.001, -0.002, 0.003),
            clock_offset_m: Some(0.0),
            clock_drift_m_s: Some(0.0),
        };
        let mut tuning = FilterTuning::new(
            100.0,
            0.01,
            1e-3,
            crate::coupling::BiasProcess::constant(0.1),
            crate::coupling::BiasProcess::constant(0.01),
        )
        .unwrap();
        tuning.antenna_lever_arm_b_m = lever;
        let mut s = FilterState::new(&init, &tuning).unwrap();
        s.last_sample.angular_rate_b = Vector3::new(0.3, -0.1, 0.5);
        s
    }

    /// The rows are the derivatives of the antenna position and velocity
    /// errors: perturb the true state, recompute the antenna with the
    /// formulas above written out, compare with the row times the error.
    #[test]
    fn rows_match_perturbed_lever_arm_formulas() {
        let l = Vector3::new(0.4, -0.2, -0.9);
        let s = state(l);
        let a = s.antenna();
        let omega_hat = s.last_sample.angular_rate_b;
        let antenna = |c: &Matrix3<f64>, r: &Vector3<f64>, v: &Vector3<f64>, w: &Vector3<f64>| {
            (
                r + c * l,
                v + c * w.cross(&l) - EARTH_RATE_ECEF.cross(&(c * l)),
            )
        };
        // A step of 1e-4 keeps the second-order terms (≈ h² |l| |ω|) and the
        // rounding of ECEF positions (≈ 1e-9 m) below the 1e-7 tolerance.
        for j in [0usize, 1, 2, 12, 13, 14] {
            let h = 1e-4;
            let mut x = SVector::<f64, BASE_STATES>::zeros();
            x[j] = h;
            // Truth = estimate − error: C = R(−ψ) Ĉ, ω = ω̂ + δb_g.
            let psi = Vector3::new(x[0], x[1], x[2]);
            let c_true = rotation_vector_to_dcm(&(-psi)) * s.nav.c_b_e;
            let w_true = omega_hat + Vector3::new(x[12], x[13], x[14]);
            let (r_t, v_t) = antenna(&c_true, &s.nav.position_ecef, &s.nav.velocity_ecef, &w_true);
            for k in 0..3 {
                let mut e = Vector3::zeros();
                e[k] = 1.0;
                let dr = a.position_row(&e).dot(&x);
                let dv = a.velocity_row(&e).dot(&x);
                assert!(((a.position_ecef - r_t)[k] - dr).abs() < 1e-7, "r {j} {k}");
                assert!(((a.velocity_ecef - v_t)[k] - dv).abs() < 1e-7, "v {j} {k}");
            }
        }
    }

    #[test]
    fn without_a_lever_arm_the_rows_are_the_identity() {
        let s = state(Vector3::zeros());
        let a = s.antenna();
        assert_eq!(a.position_ecef, s.nav.position_ecef);
        let row = a.velocity_row(&Vector3::new(0.0, 1.0, 0.0));
        assert_eq!(row, SparseRow::new(&[(VELOCITY + 1, 1.0)]));
        // Only the Earth-rate term of the lever-arm velocity is left: none.
        assert!((a.velocity_ecef - s.nav.velocity_ecef).norm() == 0.0);
    }
}
