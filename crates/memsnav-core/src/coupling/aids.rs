//! Aids that need no GNSS: what the vehicle's own behaviour says about the
//! state. Each is one batch, tested like a GNSS epoch (a failed one is
//! recorded and skipped; only ZUPTs the filter keeps refusing at a
//! standstill reset its velocity, see [`FilterState::zero_velocity_update`]).
//!
//! - Zero-velocity update (ZUPT) at a standstill: v^e = 0 (Groves §15.3.1).
//! - Zero-angular-rate update (ZARU) at a standstill: the body turns with
//!   the Earth only, so the mean gyro reading is C_e^b ω_ie^e + b_g
//!   (Groves §15.3.2): it observes the gyro biases directly.
//! - Non-holonomic constraint (NHC) of a land vehicle: no lateral and no
//!   vertical velocity of its wheels' contact point in vehicle axes
//!   (Sukkarieh 2000; Groves §15.4.1; Shin 2001).
//! - Odometer: the forward velocity of the same point (Groves §16.1.7).
//! - Height (a barometer, Groves §16.2.1) and heading (a dual-antenna
//!   receiver or a magnetometer, Groves §6.1): one scalar each.

use nalgebra::{Matrix3, Vector3};

use super::engine::batch::BatchRules;
use super::engine::FilterState;
use super::records::MeasurementKind;
use crate::attitude::skew;
use crate::filter::state::{
    Installation, Layout, ACCEL_BIAS, ATTITUDE, GYRO_BIAS, POSITION, VELOCITY,
};
use crate::filter::SparseRow;
use crate::geodesy::wgs84::EARTH_RATE_RAD_S;
use crate::geodesy::{c_n_e, ecef_to_geodetic, gravity_ecef};
use crate::gnss::plausible;
use crate::{validate, Error, Result};

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

/// The rows and predictions of the velocity of the reference point at
/// `reference_b_m` in vehicle axes (forward, lateral, vertical; the NHC
/// measures the last two as zero, an odometer the first): v^b = Ĉᵀ v̂ + ω̂ × l in body axes, v^v = M v^b in vehicle
/// axes with the boresight M = I − [μ̂×]. With Ĉᵀ = Cᵀ(I − [ψ×]),
/// ω̂ − ω = −δb_g and μ̂ − μ = δμ the error is
/// M (Ĉᵀ δv + Ĉᵀ [v̂×] ψ + [l×] δb_g) + [v^b×] δμ; the δμ_y, δμ_z columns
/// only when the filter has the installation block (`mounting_state`: the
/// index of μ_y; μ_x, a roll, is not a state).
fn vehicle_velocity_rows(
    c_b_e: &Matrix3<f64>,
    velocity_ecef: &Vector3<f64>,
    angular_rate_b: &Vector3<f64>,
    reference_b_m: &Vector3<f64>,
    mounting_rad: &Vector3<f64>,
    mounting_state: Option<usize>,
) -> [(SparseRow, f64); 3] {
    let c_e_b = c_b_e.transpose();
    let v_b = c_e_b * velocity_ecef + angular_rate_b.cross(reference_b_m);
    let boresight = Matrix3::identity() - skew(mounting_rad);
    let v_v = boresight * v_b;
    let velocity = boresight * c_e_b;
    let attitude = velocity * skew(velocity_ecef);
    let gyro = boresight * skew(reference_b_m);
    let mounting = skew(&v_b);
    std::array::from_fn(|k| {
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
    ///
    /// A standstill the sensors show while the filter keeps refusing its
    /// ZUPTs (`recovery.reset_after_failed_epochs` in a row) means the
    /// filter's velocity is further off than its covariance admits, as a
    /// fix that keeps failing does: the velocity is reset to zero with the
    /// ZUPT's std and the reset recorded (the fading of repeated resets
    /// applies as to fixes). Without it a wrong update just before a stop
    /// leaves a velocity error every later ZUPT is refused for, and the
    /// position drifts through the whole stop.
    pub fn zero_velocity_update(&mut self, time_s: f64, std_m_s: f64) -> Result<bool> {
        validate::aid_std("std", std_m_s)?;
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
        let applied = self.apply_staged(time_s, kind, AIDS)?;
        if !applied && self.reset_due(kind) {
            let covariance = Matrix3::identity() * (std_m_s * std_m_s);
            self.reset_imu_velocity(time_s, kind, &Vector3::zeros(), &covariance)?;
            self.recovered(time_s, kind)?;
        }
        Ok(applied)
    }

    /// The chi-square statistic of "the vehicle is not accelerating" over a
    /// detector window: the acceleration a = Ĉ f̂ + γ(r̂) (the corrected
    /// mean specific force `mean_specific_force_b` with gravity added back,
    /// Groves eq. 5.54 at rest, the Coriolis term of a vehicle at rest
    /// being zero) against its covariance A P Aᵀ + diag(`std_of_mean_b`²),
    /// A = ∂a/∂(ψ, δb_a) = (−[(Ĉ f̂)×], −Ĉ) (the INS error model of
    /// `crate::filter::propagation`). A car braking to a stop at half a
    /// metre per second squared passes the variance test of a quiet IMU;
    /// its mean specific force does not pass this one. Three degrees of
    /// freedom.
    pub fn rest_acceleration_nis(
        &self,
        mean_specific_force_b: &Vector3<f64>,
        std_of_mean_b: &Vector3<f64>,
    ) -> f64 {
        let raw = crate::ins::ImuSample {
            specific_force_b: *mean_specific_force_b,
            angular_rate_b: Vector3::zeros(),
        };
        let f_e = self.nav.c_b_e * self.corrected(&raw).specific_force_b;
        let a = f_e + gravity_ecef(&self.nav.position_ecef);
        let tilt = -skew(&f_e);
        let bias = -self.nav.c_b_e;
        let p = &self.kf.p;
        let p_aa = p.fixed_view::<3, 3>(ATTITUDE, ATTITUDE);
        let p_ab = p.fixed_view::<3, 3>(ATTITUDE, ACCEL_BIAS);
        let p_bb = p.fixed_view::<3, 3>(ACCEL_BIAS, ACCEL_BIAS);
        let cross = tilt * p_ab * bias.transpose();
        let s = tilt * p_aa * tilt.transpose()
            + bias * p_bb * bias.transpose()
            + cross
            + cross.transpose()
            + Matrix3::from_diagonal(&std_of_mean_b.map(|v| v * v));
        s.cholesky().map_or(f64::INFINITY, |c| a.dot(&c.solve(&a)))
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
        validate::finite_vectors("mean_angular_rate", &[*mean_raw_rate_b])?;
        for std in std_rad_s.iter() {
            validate::aid_std("std", *std)?;
        }
        let kind = MeasurementKind::ZeroRate;
        let rows = zero_rate_rows(&self.nav.c_b_e, &self.gyro_bias_rad_s, mean_raw_rate_b);
        for (k, (h, y)) in rows.into_iter().enumerate() {
            self.stage(time_s, kind, k as u16, h, y, std_rad_s[k]);
        }
        self.apply_staged(time_s, kind, AIDS)
    }

    /// The velocity rows of the reference point at `reference_b_m` with
    /// the filter's current estimates ([`vehicle_velocity_rows`]).
    fn reference_velocity_rows(&self, reference_b_m: &Vector3<f64>) -> [(SparseRow, f64); 3] {
        vehicle_velocity_rows(
            &self.nav.c_b_e,
            &self.nav.velocity_ecef,
            &self.last_sample.angular_rate_b,
            reference_b_m,
            &self.installation.mounting_rad,
            Layout::for_size::<N>()
                .installation
                .map(|first| first + Installation::MOUNTING),
        )
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
        validate::aid_std("std", std_m_s)?;
        validate::lever_arm("lever_arm", reference_b_m)?;
        let kind = MeasurementKind::NonHolonomic;
        let [_, lateral, vertical] = self.reference_velocity_rows(reference_b_m);
        for (id, (h, y)) in [(1, lateral), (2, vertical)] {
            self.stage(time_s, kind, id, h, y, std_m_s);
        }
        self.apply_staged(time_s, kind, AIDS)
    }

    /// Odometer (wheel speed): the forward speed `speed_m_s` of the
    /// vehicle's reference point at `reference_b_m` (the forward row of
    /// the NHC's vehicle velocity), std `std_m_s`. A signed speed: negative
    /// when reversing. Returns whether it was applied.
    pub fn speed_update(
        &mut self,
        time_s: f64,
        speed_m_s: f64,
        reference_b_m: &Vector3<f64>,
        std_m_s: f64,
    ) -> Result<bool> {
        validate::finite_scalars("speed", &[speed_m_s])?;
        validate::at_most("speed", speed_m_s.abs(), plausible::MAX_SPEED_M_S)?;
        validate::aid_std("std", std_m_s)?;
        validate::lever_arm("lever_arm", reference_b_m)?;
        let kind = MeasurementKind::Speed;
        let [(h, predicted), ..] = self.reference_velocity_rows(reference_b_m);
        self.stage(time_s, kind, 0, h, predicted - speed_m_s, std_m_s);
        self.apply_staged(time_s, kind, AIDS)
    }

    /// Barometric (or any) height: the IMU's ellipsoidal height `height_m`
    /// (WGS 84), std `std_m`. Returns whether it was applied.
    pub fn height_update(&mut self, time_s: f64, height_m: f64, std_m: f64) -> Result<bool> {
        plausible::check(height_m, plausible::HEIGHT_M, "height", "m")
            .map_err(|reason| Error::invalid("height", reason))?;
        validate::aid_std("std", std_m)?;
        let kind = MeasurementKind::Height;
        let (h, predicted) = height_row(&self.nav.position_ecef);
        self.stage(time_s, kind, 0, h, predicted - height_m, std_m);
        self.apply_staged(time_s, kind, AIDS)
    }

    /// Heading (dual antenna, magnetometer after declination): the body's
    /// yaw `yaw_rad` from north, positive east (NED, the yaw of
    /// [`crate::attitude::dcm_to_euler`]), std `std_rad`. The innovation is
    /// wrapped into (−π, π]. Returns whether it was applied.
    pub fn heading_update(&mut self, time_s: f64, yaw_rad: f64, std_rad: f64) -> Result<bool> {
        validate::finite_scalars("yaw", &[yaw_rad])?;
        validate::aid_std("std", std_rad)?;
        let kind = MeasurementKind::Heading;
        let (h, predicted) = heading_row(&self.nav.c_b_e, &self.nav.position_ecef);
        let innovation = crate::attitude::wrap_angle_rad(predicted - yaw_rad);
        self.stage(time_s, kind, 0, h, innovation, std_rad);
        self.apply_staged(time_s, kind, AIDS)
    }
}

/// The height row and prediction: ĥ − h = uᵀ δr with u the ellipsoid's
/// upward normal at r̂ (the gradient of the geodetic height, Groves
/// §2.4.2), u = −C_n^e (0, 0, 1)ᵀ.
fn height_row(position_ecef: &Vector3<f64>) -> (SparseRow, f64) {
    let geo = ecef_to_geodetic(position_ecef);
    let up = -c_n_e(geo.latitude_rad, geo.longitude_rad)
        .column(2)
        .into_owned();
    let h = SparseRow::new(&[(POSITION, up.x), (POSITION + 1, up.y), (POSITION + 2, up.z)]);
    (h, geo.height_m)
}

/// The heading row and prediction. With Ĉ_b^e = (I + [ψ×]) C_b^e the NED
/// attitude carries ψⁿ = C_e^n ψ (the frame's own change with a position
/// error, |δr| / R ≈ 2e-7 rad per metre, is neglected), and yaw =
/// atan2(C₂₁, C₁₁) of C = C_b^n moves by
/// δψ = ψⁿ_z − C₃₁ (C₁₁ ψⁿ_x + C₂₁ ψⁿ_y) / (C₁₁² + C₂₁²).
fn heading_row(c_b_e: &Matrix3<f64>, position_ecef: &Vector3<f64>) -> (SparseRow, f64) {
    let geo = ecef_to_geodetic(position_ecef);
    let c_e_n = c_n_e(geo.latitude_rad, geo.longitude_rad).transpose();
    let c = c_e_n * c_b_e;
    let d = c[(0, 0)].powi(2) + c[(1, 0)].powi(2);
    let row_n = Vector3::new(-c[(2, 0)] * c[(0, 0)] / d, -c[(2, 0)] * c[(1, 0)] / d, 1.0);
    let row_e = c_e_n.transpose() * row_n;
    let h = SparseRow::new(&[
        (ATTITUDE, row_e.x),
        (ATTITUDE + 1, row_e.y),
        (ATTITUDE + 2, row_e.z),
    ]);
    (h, c[(1, 0)].atan2(c[(0, 0)]))
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

    /// The vehicle-velocity (NHC, odometer), ZARU, height and heading rows
    /// are the derivatives of their predictions:
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
        let vehicle = vehicle_velocity_rows(&c_hat, &v_hat, &w_hat, &l, &mu_hat, mounting_state);
        let zaru = zero_rate_rows(&c_hat, &b_hat, &reading);
        let r_hat = s.nav.position_ecef;
        let (height, heading) = (height_row(&r_hat), heading_row(&c_hat, &r_hat));
        // The mounting columns sit at 17 and 18 here.
        for j in [0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 13, 14, 17, 18] {
            // Position steps of 1 mm: a height from ECEF coordinates of
            // 6.4e6 m carries ~1e-9 m of round-off.
            let position = (6..9).contains(&j);
            let mut x = SVector::<f64, { BASE_STATES + 2 }>::zeros();
            x[j] = if position { 1e-3 } else { 1e-6 };
            let tolerance = if position { 1e-8 } else { 1e-11 };
            // Truth = estimate − error.
            let psi = Vector3::new(x[0], x[1], x[2]);
            let c = rotation_vector_to_dcm(&(-psi)) * c_hat;
            let v = v_hat - Vector3::new(x[3], x[4], x[5]);
            let r = r_hat - Vector3::new(x[6], x[7], x[8]);
            let db = Vector3::new(x[12], x[13], x[14]);
            let mu = mu_hat - Vector3::new(0.0, x[17], x[18]);
            let truth_vehicle = vehicle_velocity_rows(&c, &v, &(w_hat + db), &l, &mu, None);
            for i in 0..3 {
                let d = vehicle[i].1 - truth_vehicle[i].1;
                assert!((vehicle[i].0.dot(&x) - d).abs() < 1e-11, "vehicle {j} {i}");
            }
            // The heading row neglects the NED frame's turn with position
            // (1.6e-10 rad for the 1 mm step).
            for (name, (row, predicted), truth) in [
                ("height", &height, height_row(&r).1),
                ("heading", &heading, heading_row(&c, &r).1),
            ] {
                let d = predicted - truth;
                assert!((row.dot(&x) - d).abs() < tolerance, "{name} {j}");
            }
            let truth_zaru = zero_rate_rows(&c, &(b_hat - db), &reading);
            for k in 0..3 {
                let d = zaru[k].1 - truth_zaru[k].1;
                assert!((zaru[k].0.dot(&x) - d).abs() < 1e-12, "zaru {j} {k}");
            }
        }
    }

    /// A failed update leaves the filter exactly as it was, records
    /// included; arguments no sensor gives are refused before it starts.
    #[test]
    fn updates_are_transactions() {
        let mut s = state();
        assert!(s.update_height(200.0, 1.0).unwrap());
        let (p, nav, counts) = (s.kf.p, s.nav, (s.records.len(), s.batches.len()));
        let failed = s.transaction(|s| {
            assert!(s.height_update(s.time_s, 200.5, 1.0)?);
            assert_ne!(s.kf.p, p);
            Err::<bool, _>(crate::Error::Divergence {
                time_s: s.time_s,
                reason: "a test's failure after the update".into(),
            })
        });
        assert!(failed.is_err());
        assert_eq!((s.kf.p, s.nav), (p, nav));
        assert_eq!((s.records.len(), s.batches.len()), counts);
        for e in [
            s.update_non_holonomic(&Vector3::new(1e30, 0.0, 0.0), 0.1),
            s.update_speed(1.0, &Vector3::new(0.0, 1e30, 0.0), 0.1),
            s.update_zupt(1e-300),
            s.update_zaru(&Vector3::zeros(), &Vector3::repeat(1e-300)),
            s.update_height(-2e4, 1.0),
        ] {
            let e = e.unwrap_err().to_string();
            let named = ["lever_arm: ", "std: 1e-300 is outside", "height = -2e4 m"];
            assert!(named.iter().any(|n| e.contains(n)), "{e}");
        }
        assert_eq!((s.kf.p, s.nav), (p, nav));
    }

    /// The rest-acceleration statistic against one written out: the
    /// specific force at rest (−Ĉᵀγ, less the bias estimate's effect)
    /// gives zero; an acceleration a added gives aᵀ S⁻¹ a with S built
    /// here from the tilt and bias variances alone (P diagonal).
    #[test]
    fn rest_acceleration_nis_is_zero_at_rest_and_chi_square_when_moving() {
        let mut s = state();
        s.accel_bias_m_s2 = Vector3::new(0.02, -0.01, 0.03);
        let (tilt_std, bias_std, noise_std) = (1e-3, 5e-3, 0.01);
        s.kf.p.fill(0.0);
        for k in 0..3 {
            s.kf.p[(ATTITUDE + k, ATTITUDE + k)] = tilt_std * tilt_std;
            s.kf.p[(ACCEL_BIAS + k, ACCEL_BIAS + k)] = bias_std * bias_std;
        }
        let c = s.nav.c_b_e;
        let gamma = gravity_ecef(&s.nav.position_ecef);
        let at_rest_b = -c.transpose() * gamma + s.accel_bias_m_s2;
        let noise = Vector3::from_element(noise_std);
        assert!(s.rest_acceleration_nis(&at_rest_b, &noise) < 1e-16);
        let a_e = c_n_e(0.7, 0.3) * Vector3::new(0.3, -0.1, 0.05);
        let braking_b = at_rest_b + c.transpose() * a_e;
        let f_e = c * (braking_b - s.accel_bias_m_s2);
        let tilt = -skew(&f_e);
        let cov = tilt * tilt.transpose() * tilt_std * tilt_std
            + Matrix3::identity() * (bias_std * bias_std + noise_std * noise_std);
        let expected = a_e.dot(&(cov.try_inverse().unwrap() * a_e));
        let got = s.rest_acceleration_nis(&braking_b, &noise);
        assert!((got / expected - 1.0).abs() < 1e-9, "{got} vs {expected}");
        // 0.3 m/s² against a few hundredths: far beyond any gate.
        assert!(got > 100.0);
    }

    /// ZUPTs the filter keeps refusing (an overconfident velocity error)
    /// reset the velocity to zero after `reset_after_failed_epochs`, and
    /// the reset is recorded.
    #[test]
    fn failing_zupts_reset_the_velocity_to_zero() {
        let mut s = state();
        s.nav.velocity_ecef = Vector3::new(0.3, -0.2, 0.1);
        s.kf.p
            .fixed_view_mut::<3, 3>(VELOCITY, VELOCITY)
            .fill_diagonal(1e-6);
        let due = s.tuning.recovery.reset_after_failed_epochs;
        for k in 0..due {
            assert!(!s.zero_velocity_update(k as f64, 0.02).unwrap());
        }
        assert_eq!(s.nav.velocity_ecef, Vector3::zeros());
        let reset = s.resets.last().unwrap();
        assert_eq!(reset.kind, super::super::records::ResetKind::VelocityToZero);
        let change: f64 = Vector3::new(0.3, -0.2, 0.1).norm();
        assert!((reset.change - change).abs() < 1e-12);
        let p_v = s.kf.p.fixed_view::<3, 3>(VELOCITY, VELOCITY);
        assert!((p_v[(0, 0)] - 0.02f64.powi(2)).abs() < 1e-15);
        // The next ZUPT agrees with the reset velocity.
        assert!(s.zero_velocity_update(due as f64, 0.02).unwrap());
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
