//! Aids that need no GNSS: what the vehicle's own behaviour says about the
//! state. Each is one batch, tested like a GNSS epoch (a failed one is
//! recorded and skipped; aids never reset the filter).
//!
//! - Zero-velocity update (ZUPT) at a standstill: v^e = 0 (Groves §15.3.1).
//! - Zero-angular-rate update (ZARU) at a standstill: the body turns with
//!   the Earth only, so the mean gyro reading is C_e^b ω_ie^e + b_g
//!   (Groves §15.3.2): it observes the gyro biases directly.
//! - Non-holonomic constraint (NHC) of a land vehicle: no lateral and no
//!   vertical velocity of its wheels' contact point in vehicle axes
//!   (Sukkarieh 2000; Groves §15.4.1; Shin 2001).

use nalgebra::{Matrix3, Vector3};

use super::engine::batch::BatchRules;
use super::engine::FilterState;
use super::records::MeasurementKind;
use crate::attitude::skew;
use crate::filter::state::{Installation, Layout, ATTITUDE, GYRO_BIAS, VELOCITY};
use crate::filter::SparseRow;
use crate::geodesy::wgs84::EARTH_RATE_RAD_S;
use crate::Result;

const AIDS: BatchRules = BatchRules {
    exclusion: false,
    common_mode: None,
};

/// The ZARU rows and predictions y = prediction − measurement: the
/// prediction Ĉᵀ ω_ie + b̂_g of the mean raw reading; with
/// Ĉᵀ = Cᵀ (I − [ψ×]) its error is δb_g + Ĉᵀ [ω_ie×] ψ.
fn zero_rate_rows(
    c_b_e: &Matrix3<f64>,
    gyro_bias_rad_s: &Vector3<f64>,
    mean_raw_rate_b: &Vector3<f64>,
) -> [(SparseRow, f64); 3] {
    let c_e_b = c_b_e.transpose();
    let earth = Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S);
    let y = c_e_b * earth + gyro_bias_rad_s - mean_raw_rate_b;
    let attitude = c_e_b * skew(&earth);
    std::array::from_fn(|k| {
        let mut h = SparseRow::new(&[(GYRO_BIAS + k, 1.0)]);
        for j in 0..3 {
            h.push(ATTITUDE + j, attitude[(k, j)]);
        }
        (h, y[k])
    })
}

/// The NHC rows and predictions (the lateral and vertical velocity of the
/// reference point at `reference_b_m`, in vehicle axes, whose measurement
/// is zero): v^b = Ĉᵀ v̂ + ω̂ × l in body axes, v^v = M v^b in vehicle
/// axes with the boresight M = I − [μ̂×]. With Ĉᵀ = Cᵀ(I − [ψ×]),
/// ω̂ − ω = −δb_g and μ̂ − μ = δμ the error is
/// M (Ĉᵀ δv + Ĉᵀ [v̂×] ψ + [l×] δb_g) + [v^b×] δμ; the δμ_y, δμ_z columns
/// only when the filter has the installation block (`mounting_state`: the
/// index of μ_y; μ_x, a roll, is not a state).
fn non_holonomic_rows(
    c_b_e: &Matrix3<f64>,
    velocity_ecef: &Vector3<f64>,
    angular_rate_b: &Vector3<f64>,
    reference_b_m: &Vector3<f64>,
    mounting_rad: &Vector3<f64>,
    mounting_state: Option<usize>,
) -> [(SparseRow, f64); 2] {
    let c_e_b = c_b_e.transpose();
    let v_b = c_e_b * velocity_ecef + angular_rate_b.cross(reference_b_m);
    let boresight = Matrix3::identity() - skew(mounting_rad);
    let v_v = boresight * v_b;
    let velocity = boresight * c_e_b;
    let attitude = velocity * skew(velocity_ecef);
    let gyro = boresight * skew(reference_b_m);
    let mounting = skew(&v_b);
    std::array::from_fn(|i| {
        let k = i + 1;
        let mut h = SparseRow::default();
        for j in 0..3 {
            h.push(VELOCITY + j, velocity[(k, j)]);
            h.push(ATTITUDE + j, attitude[(k, j)]);
            if gyro[(k, j)] != 0.0 {
                h.push(GYRO_BIAS + j, gyro[(k, j)]);
            }
            if let (Some(first), 1..) = (mounting_state, j) {
                h.push(first + j - 1, mounting[(k, j)]);
            }
        }
        (h, v_v[k])
    })
}

impl<const N: usize> FilterState<N> {
    /// ZUPT: the IMU's ECEF velocity is zero, with std `std_m_s` per axis.
    /// Returns whether it was applied.
    pub fn zero_velocity_update(&mut self, time_s: f64, std_m_s: f64) -> Result<bool> {
        let kind = MeasurementKind::ZeroVelocity;
        for k in 0..3 {
            let h = SparseRow::new(&[(VELOCITY + k, 1.0)]);
            self.stage(
                time_s,
                kind,
                k as u16,
                h,
                self.nav.velocity_ecef[k],
                std_m_s,
            );
        }
        self.apply_staged(time_s, kind, AIDS)
    }

    /// ZARU: the raw gyro reading averaged over a standstill,
    /// `mean_raw_rate_b`, with std `std_rad_s` (of the mean, per axis).
    /// Returns whether it was applied.
    pub fn zero_rate_update(
        &mut self,
        time_s: f64,
        mean_raw_rate_b: &Vector3<f64>,
        std_rad_s: &Vector3<f64>,
    ) -> Result<bool> {
        let kind = MeasurementKind::ZeroRate;
        let rows = zero_rate_rows(&self.nav.c_b_e, &self.gyro_bias_rad_s, mean_raw_rate_b);
        for (k, (h, y)) in rows.into_iter().enumerate() {
            self.stage(time_s, kind, k as u16, h, y, std_rad_s[k]);
        }
        self.apply_staged(time_s, kind, AIDS)
    }

    /// NHC: the velocity of the vehicle's reference point, at
    /// `reference_b_m` from the IMU in body axes (x forward along the
    /// vehicle, up to the estimated boresight), has no lateral and no
    /// vertical component, std `std_m_s`.
    /// Returns whether it was applied.
    pub fn non_holonomic_update(
        &mut self,
        time_s: f64,
        reference_b_m: &Vector3<f64>,
        std_m_s: f64,
    ) -> Result<bool> {
        let kind = MeasurementKind::NonHolonomic;
        let rows = non_holonomic_rows(
            &self.nav.c_b_e,
            &self.nav.velocity_ecef,
            &self.last_sample.angular_rate_b,
            reference_b_m,
            &self.installation.mounting_rad,
            Layout::for_size::<N>()
                .installation
                .map(|first| first + Installation::MOUNTING),
        );
        for (i, (h, y)) in rows.into_iter().enumerate() {
            self.stage(time_s, kind, i as u16 + 1, h, y, std_m_s);
        }
        self.apply_staged(time_s, kind, AIDS)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::{euler_to_dcm, rotation_vector_to_dcm};
    use crate::coupling::{BiasProcess, FilterTuning, InitialState};
    use crate::filter::state::BASE_STATES;
    use crate::geodesy::{c_n_e, geodetic_to_ecef, Geodetic};
    use crate::ins::NavState;
    use nalgebra::SVector;

    fn state() -> FilterState<BASE_STATES> {
        let init = InitialState {
            nav: NavState {
                position_ecef: geodetic_to_ecef(Geodetic::new(0.7, 0.3, 200.0)),
                velocity_ecef: c_n_e(0.7, 0.3) * Vector3::new(8.0, 3.0, 0.1),
                c_b_e: c_n_e(0.7, 0.3) * euler_to_dcm(0.05, -0.02, 0.4),
            },
            accel_bias_m_s2: Vector3::zeros(),
            gyro_bias_rad_s: Vector3::new(1e-3, -2e-3, 3e-3),
            clock_offset_m: Some(0.0),
            clock_drift_m_s: Some(0.0),
        };
        let tuning = FilterTuning::new(
            100.0,
            0.01,
            1e-3,
            BiasProcess::constant(0.1),
            BiasProcess::constant(0.01),
        )
        .unwrap();
        let mut s = FilterState::new(&init, &tuning).unwrap();
        s.last_sample.angular_rate_b = Vector3::new(0.02, -0.01, 0.3);
        s
    }

    /// The NHC and ZARU rows are the derivatives of their predictions:
    /// move the truth behind the estimate along each state and compare the
    /// change of the prediction error with the row.
    #[test]
    fn aid_rows_match_perturbed_predictions() {
        let s = state();
        let l = Vector3::new(-1.2, 0.1, 0.6);
        let (c_hat, v_hat) = (s.nav.c_b_e, s.nav.velocity_ecef);
        let w_hat = s.last_sample.angular_rate_b;
        let b_hat = s.gyro_bias_rad_s;
        let reading = Vector3::new(0.01, 0.02, -0.03);
        let (mu_hat, mounting_state) = (Vector3::new(0.0, -0.03, 0.02), Some(BASE_STATES));
        let nhc = non_holonomic_rows(&c_hat, &v_hat, &w_hat, &l, &mu_hat, mounting_state);
        let zaru = zero_rate_rows(&c_hat, &b_hat, &reading);
        // The mounting columns sit at 17 and 18 here.
        for j in [0, 1, 2, 3, 4, 5, 12, 13, 14, 17, 18] {
            let mut x = SVector::<f64, { BASE_STATES + 2 }>::zeros();
            x[j] = 1e-6;
            // Truth = estimate − error.
            let psi = Vector3::new(x[0], x[1], x[2]);
            let c = rotation_vector_to_dcm(&(-psi)) * c_hat;
            let v = v_hat - Vector3::new(x[3], x[4], x[5]);
            let db = Vector3::new(x[12], x[13], x[14]);
            let mu = mu_hat - Vector3::new(0.0, x[17], x[18]);
            let truth_nhc = non_holonomic_rows(&c, &v, &(w_hat + db), &l, &mu, None);
            for i in 0..2 {
                let d = nhc[i].1 - truth_nhc[i].1;
                assert!((nhc[i].0.dot(&x) - d).abs() < 1e-11, "nhc {j} {i}");
            }
            let truth_zaru = zero_rate_rows(&c, &(b_hat - db), &reading);
            for k in 0..3 {
                let d = zaru[k].1 - truth_zaru[k].1;
                assert!((zaru[k].0.dot(&x) - d).abs() < 1e-12, "zaru {j} {k}");
            }
        }
    }

    /// At a standstill with a velocity error the ZUPT pulls the velocity to
    /// zero; a ZARU learns the gyro bias from the mean reading.
    #[test]
    fn zupt_and_zaru_observe_velocity_and_gyro_bias() {
        let mut s = state();
        s.nav.velocity_ecef = Vector3::new(0.05, -0.03, 0.02);
        s.kf.p
            .fixed_view_mut::<3, 3>(VELOCITY, VELOCITY)
            .fill_diagonal(0.1f64.powi(2));
        assert!(s.zero_velocity_update(1.0, 0.01).unwrap());
        assert!(s.nav.velocity_ecef.norm() < 0.01);
        let true_bias = Vector3::new(0.01, -0.02, 0.005);
        let reading =
            s.nav.c_b_e.transpose() * Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S) + true_bias;
        s.gyro_bias_rad_s = Vector3::zeros();
        s.kf.p
            .fixed_view_mut::<3, 3>(GYRO_BIAS, GYRO_BIAS)
            .fill_diagonal(0.05f64.powi(2));
        assert!(s
            .zero_rate_update(1.0, &reading, &Vector3::from_element(1e-4))
            .unwrap());
        assert!(
            (s.gyro_bias_rad_s - true_bias).norm() < 1e-4,
            "{}",
            s.gyro_bias_rad_s
        );
        assert_eq!(s.records.len(), 6);
    }
}
