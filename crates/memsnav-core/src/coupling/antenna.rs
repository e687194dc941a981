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
use super::motion_history::PastMotion;
use crate::attitude::skew;
use crate::filter::state::{
    Installation, Layout, ACCEL_BIAS, ATTITUDE, GYRO_BIAS, POSITION, VELOCITY,
};
use crate::filter::SparseRow;
use crate::geodesy::gravity_ecef;
use crate::geodesy::wgs84::EARTH_RATE_RAD_S;

const LEVER_ARM: usize = Installation::LEVER_ARM;
const TIME_OFFSET: usize = Installation::TIME_OFFSET;
const VELOCITY_LATENCY: usize = Installation::VELOCITY_LATENCY;

/// Earth rotation rate vector ω_ie^e.
const EARTH_RATE_ECEF: Vector3<f64> = Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S);

/// The antenna position and velocity the filter predicts for a GNSS
/// measurement (at IMU time t − t̂_o, see [`super::installation`]), with
/// the derivatives of their errors with respect to the error state.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AntennaPrediction {
    /// r_a(t − t̂_o) ≈ r_a − t̂_o v_a, ECEF, m.
    pub(crate) position_ecef: Vector3<f64>,
    /// v_a(t − t̂_o) ≈ v_a − t̂_o a, ECEF, m/s.
    pub(crate) velocity_ecef: Vector3<f64>,
    /// v_a(t − t̂_o − L̂), the fixes' velocity with its latency, ECEF, m/s.
    pub(crate) fix_velocity_ecef: Vector3<f64>,
    /// ∂δr_a/∂ψ = −[(Ĉ l)×].
    position_attitude: Matrix3<f64>,
    /// ∂δv_a/∂ψ.
    velocity_attitude: Matrix3<f64>,
    /// ∂δv_a/∂δb_g = Ĉ [l×].
    velocity_gyro_bias: Matrix3<f64>,
    /// ∂δa/∂ψ = −[(Ĉ f̂)×] and ∂δa/∂δb_a = −Ĉ, of the IMU's acceleration
    /// a = Ĉ f̂ + g − 2 Ω_ie v̂ (its −2 Ω_ie δv and Γ δr are below 1e-4 of
    /// these and left out).
    acceleration_attitude: Matrix3<f64>,
    acceleration_accel_bias: Matrix3<f64>,
    /// t̂_o and L̂, s.
    time_offset_s: f64,
    latency_s: f64,
    /// The installation block's first state, its columns below.
    installation: Option<usize>,
    /// ∂δr_a/∂δl = Ĉ.
    position_lever_arm: Matrix3<f64>,
    /// ∂δv_a/∂δl = M(t − t̂_o) − Ω_ie Ĉ, M = Ĉ [ω̂×] (for the fix velocity
    /// at t − t̂_o − L̂ in the second).
    velocity_lever_arm: Matrix3<f64>,
    fix_velocity_lever_arm: Matrix3<f64>,
    /// v_a (∂δr_a/∂δt_o = −v_a).
    antenna_velocity_ecef: Vector3<f64>,
    /// The antenna's acceleration at t − t̂_o, a + Ṁ l (∂δv_a/∂δt_o is its
    /// negative), and at t − t̂_o − L̂ (∂δv_fix/∂δt_o = ∂δv_fix/∂δL).
    acceleration_ecef: Vector3<f64>,
    fix_acceleration_ecef: Vector3<f64>,
}

impl AntennaPrediction {
    /// The row of w · δr_a(t − t̂_o) = w · (δr_a − t̂_o δv_a − v_a δt_o)
    /// (w: weights of the ECEF components, e.g. a negative line of sight or
    /// a row of a whitening matrix).
    pub(crate) fn position_row(&self, w: &Vector3<f64>) -> SparseRow {
        let mut row = block_row(w, POSITION, &[(ATTITUDE, &self.position_attitude)]);
        if let Some(first) = self.installation {
            push_block(&mut row, w, first + LEVER_ARM, &self.position_lever_arm);
            row.push(first + TIME_OFFSET, -w.dot(&self.antenna_velocity_ecef));
        }
        self.shifted(row, self.time_offset_s, || {
            self.current_velocity_row(w, &self.velocity_lever_arm)
        })
    }

    /// The row of w · δv_a(t − t̂_o) = w · (δv_a − t̂_o δa − a δt_o).
    pub(crate) fn velocity_row(&self, w: &Vector3<f64>) -> SparseRow {
        let mut row = self.current_velocity_row(w, &self.velocity_lever_arm);
        if let Some(first) = self.installation {
            row.push(first + TIME_OFFSET, -w.dot(&self.acceleration_ecef));
        }
        self.shifted(row, self.time_offset_s, || self.acceleration_row(w))
    }

    /// The row of w · (δr_a(t) − δr_a(t − Δt)), the antenna's displacement
    /// error over the last Δt seconds in terms of the state now:
    /// δv_a Δt − ½ δa Δt² (δv_a grew by δa Δt over the interval, so its
    /// mean there is δv_a − ½ δa Δt). For a consumer IMU's attitude errors
    /// the second term is what keeps carrier changes consistent: 0.05 rad
    /// of tilt is 0.5 m/s² of δa, 1.6 cm over 0.25 s.
    pub(crate) fn displacement_row(&self, w: &Vector3<f64>, dt_s: f64) -> SparseRow {
        self.velocity_row(&(w * dt_s))
            .combine(1.0, &self.acceleration_row(w), -0.5 * dt_s * dt_s)
    }

    /// The row of w · δv_fix = w · (δv_a − (t̂_o + L̂) δa − a (δt_o + δL)).
    pub(crate) fn fix_velocity_row(&self, w: &Vector3<f64>) -> SparseRow {
        let mut row = self.current_velocity_row(w, &self.fix_velocity_lever_arm);
        if let Some(first) = self.installation {
            let a = -w.dot(&self.fix_acceleration_ecef);
            row.push(first + TIME_OFFSET, a);
            row.push(first + VELOCITY_LATENCY, a);
        }
        let shift = self.time_offset_s + self.latency_s;
        self.shifted(row, shift, || self.acceleration_row(w))
    }

    /// `row` − `shift` × the row `earlier` gives (none for no shift: the
    /// rows of a filter without offsets stay as they were, bit for bit).
    fn shifted(&self, row: SparseRow, shift: f64, earlier: impl Fn() -> SparseRow) -> SparseRow {
        if shift == 0.0 {
            row
        } else {
            row.combine(1.0, &earlier(), -shift)
        }
    }

    /// The row of w · δv_a, with the lever arm's columns `lever_arm`.
    fn current_velocity_row(&self, w: &Vector3<f64>, lever_arm: &Matrix3<f64>) -> SparseRow {
        let mut row = block_row(
            w,
            VELOCITY,
            &[
                (ATTITUDE, &self.velocity_attitude),
                (GYRO_BIAS, &self.velocity_gyro_bias),
            ],
        );
        if let Some(first) = self.installation {
            push_block(&mut row, w, first + LEVER_ARM, lever_arm);
        }
        row
    }

    /// The row of w · δa.
    fn acceleration_row(&self, w: &Vector3<f64>) -> SparseRow {
        let mut row = SparseRow::default();
        push_block(&mut row, w, ATTITUDE, &self.acceleration_attitude);
        push_block(&mut row, w, ACCEL_BIAS, &self.acceleration_accel_bias);
        row
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
        push_block(&mut row, w, *start, b);
    }
    row
}

/// Adds w · B δ(start..start+3) to `row`, zero entries left out.
fn push_block(row: &mut SparseRow, w: &Vector3<f64>, start: usize, b: &Matrix3<f64>) {
    let coefficients = b.transpose() * w;
    for k in 0..3 {
        if coefficients[k] != 0.0 {
            row.push(start + k, coefficients[k]);
        }
    }
}

impl<const N: usize> FilterState<N> {
    /// The antenna's position and velocity and their error rows, from the
    /// current solution, the last corrected angular rate and the
    /// installation estimates.
    pub(crate) fn antenna(&self) -> AntennaPrediction {
        let c = self.nav.c_b_e;
        let install = &self.installation;
        let l = install.lever_arm_b_m;
        let cl = c * l;
        let omega = self.last_sample.angular_rate_b;
        let rotating = c * omega.cross(&l);
        let omega_ie = skew(&EARTH_RATE_ECEF);
        let velocity = self.nav.velocity_ecef + self.lever_arm_velocity();
        let a = self.acceleration_ecef();
        let (t_o, latency) = (install.time_offset_s, install.velocity_latency_s);
        // The antenna's velocity `shift` seconds ago (v̂ less the velocity
        // change since, with the rotating term M l then), the lever arm's
        // columns there and the antenna's acceleration then, a + Ṁ l;
        // without a shift the velocity now, bit for bit as without the
        // history (which a run's first instants lack too: v − shift·a).
        let earlier = |shift: f64| {
            let now = c * skew(&omega);
            if shift == 0.0 {
                let rate = self
                    .motion_history
                    .at(self.time_s)
                    .map_or(Matrix3::zeros(), |p| p.rotation_rate);
                return (velocity, now - omega_ie * c, a + rate * l);
            }
            let past = self
                .motion_history
                .at(self.time_s - shift)
                .unwrap_or(PastMotion {
                    rotation: now,
                    rotation_rate: Matrix3::zeros(),
                    velocity_change_since_ecef: shift * a,
                    acceleration_ecef: a,
                });
            let m = past.rotation;
            let v = self.nav.velocity_ecef - past.velocity_change_since_ecef + m * l
                - EARTH_RATE_ECEF.cross(&cl);
            (
                v,
                m - omega_ie * c,
                past.acceleration_ecef + past.rotation_rate * l,
            )
        };
        let (velocity_ecef, velocity_lever_arm, acceleration_ecef) = earlier(t_o);
        let (fix_velocity_ecef, fix_velocity_lever_arm, fix_acceleration_ecef) =
            earlier(t_o + latency);
        AntennaPrediction {
            position_ecef: self.nav.position_ecef + cl - t_o * velocity,
            velocity_ecef,
            fix_velocity_ecef,
            position_attitude: -skew(&cl),
            velocity_attitude: omega_ie * skew(&cl) - skew(&rotating),
            velocity_gyro_bias: c * skew(&l),
            acceleration_attitude: -skew(&(c * self.last_sample.specific_force_b)),
            acceleration_accel_bias: -c,
            time_offset_s: t_o,
            latency_s: latency,
            installation: Layout::for_size::<N>().installation,
            position_lever_arm: c,
            velocity_lever_arm,
            fix_velocity_lever_arm,
            antenna_velocity_ecef: velocity,
            acceleration_ecef,
            fix_acceleration_ecef,
        }
    }

    /// v_a − v̂ = Ĉ (ω̂ × l) − Ω_ie Ĉ l.
    pub(crate) fn lever_arm_velocity(&self) -> Vector3<f64> {
        let c = self.nav.c_b_e;
        let l = self.installation.lever_arm_b_m;
        c * self.last_sample.angular_rate_b.cross(&l) - EARTH_RATE_ECEF.cross(&(c * l))
    }

    /// The IMU's acceleration in ECEF, Ĉ f̂ + g(r̂) − 2 Ω_ie v̂ (Groves eq.
    /// 5.36), for moving a position or velocity to a slightly earlier time.
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
    use crate::filter::state::{BASE_STATES, INSTALLATION_STATES};
    use crate::geodesy::{c_n_e, geodetic_to_ecef, Geodetic};
    use crate::ins::NavState;
    use nalgebra::SVector;

    /// A filter with `N` states at a moving, turning, accelerating point.
    fn state<const N: usize>(lever: Vector3<f64>) -> FilterState<N> {
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
        s.last_sample.specific_force_b = Vector3::new(1.5, -0.8, -9.6);
        s
    }

    /// The antenna position, velocity and fix velocity the rows linearise,
    /// written out from the formulas of [`super::super::installation`] for
    /// a truth: attitude `c`, IMU velocity `v`, rate `w`, specific force
    /// `f`, lever arm `l`, time offset `t_o`, latency `latency`.
    #[allow(clippy::too_many_arguments)]
    fn antenna_at(
        c: &Matrix3<f64>,
        r: &Vector3<f64>,
        v: &Vector3<f64>,
        w: &Vector3<f64>,
        f: &Vector3<f64>,
        l: &Vector3<f64>,
        t_o: f64,
        latency: f64,
    ) -> [Vector3<f64>; 3] {
        let v_a = v + c * w.cross(l) - EARTH_RATE_ECEF.cross(&(c * l));
        let a = c * f + gravity_ecef(r) - 2.0 * EARTH_RATE_ECEF.cross(v);
        [
            r + c * l - t_o * v_a,
            v_a - t_o * a,
            v_a - (t_o + latency) * a,
        ]
    }

    /// The rows are the derivatives of the antenna position and velocity
    /// errors: perturb the true state along each state the rows touch,
    /// recompute the antenna with the formulas written out, compare with
    /// the row times the error. With `N` = 25 the installation columns are
    /// checked too, at a time offset and latency away from zero.
    fn rows_match_perturbed_formulas<const N: usize>(t_o: f64, latency: f64) {
        let l = Vector3::new(0.4, -0.2, -0.9);
        let mut s = state::<N>(l);
        s.installation.time_offset_s = t_o;
        s.installation.velocity_latency_s = latency;
        let a = s.antenna();
        let (omega_hat, f_hat) = (s.last_sample.angular_rate_b, s.last_sample.specific_force_b);
        let first = Layout::for_size::<N>().installation;
        let mut perturbed = vec![0usize, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14];
        perturbed.extend(first.iter().flat_map(|&i| i..i + 5));
        let estimate = antenna_at(
            &s.nav.c_b_e,
            &s.nav.position_ecef,
            &s.nav.velocity_ecef,
            &omega_hat,
            &f_hat,
            &l,
            t_o,
            latency,
        );
        assert!((estimate[0] - a.position_ecef).norm() < 1e-9);
        assert!((estimate[1] - a.velocity_ecef).norm() < 1e-12);
        assert!((estimate[2] - a.fix_velocity_ecef).norm() < 1e-12);
        for j in perturbed {
            // A step of 1e-4 keeps the second-order terms (≈ h² |l| |ω|) and
            // the rounding of ECEF positions (≈ 1e-9 m) below the tolerance.
            let h = 1e-4;
            let mut x = SVector::<f64, N>::zeros();
            x[j] = h;
            // Truth = estimate − error: C = R(−ψ) Ĉ, ω = ω̂ + δb_g, f = f̂ + δb_a.
            let psi = Vector3::new(x[0], x[1], x[2]);
            let c_true = rotation_vector_to_dcm(&(-psi)) * s.nav.c_b_e;
            let v_true = s.nav.velocity_ecef - Vector3::new(x[3], x[4], x[5]);
            let r_true = s.nav.position_ecef - Vector3::new(x[6], x[7], x[8]);
            let f_true = f_hat + Vector3::new(x[9], x[10], x[11]);
            let w_true = omega_hat + Vector3::new(x[12], x[13], x[14]);
            let (mut l_true, mut t_true, mut latency_true) = (l, t_o, latency);
            if let Some(i) = first {
                l_true -= Vector3::new(x[i], x[i + 1], x[i + 2]);
                t_true -= x[i + 3];
                latency_true -= x[i + 4];
            }
            let truth = antenna_at(
                &c_true,
                &r_true,
                &v_true,
                &w_true,
                &f_true,
                &l_true,
                t_true,
                latency_true,
            );
            for k in 0..3 {
                let mut e = Vector3::zeros();
                e[k] = 1.0;
                let rows = [
                    a.position_row(&e),
                    a.velocity_row(&e),
                    a.fix_velocity_row(&e),
                ];
                for (m, row) in rows.iter().enumerate() {
                    let change = (estimate[m] - truth[m])[k];
                    // The terms left out: Γ δr and 2 Ω_ie δv in δa (times the
                    // shift), and the time offset times the lever arm's rate
                    // terms: below 1e-3 of the change.
                    let tolerance = 1e-7 + 2e-3 * change.abs();
                    let d = row.dot(&x);
                    assert!(
                        (change - d).abs() < tolerance,
                        "{m} state {j} axis {k}: {change} {d}"
                    );
                }
            }
        }
    }

    #[test]
    fn rows_match_perturbed_formulas_without_and_with_installation_states() {
        rows_match_perturbed_formulas::<BASE_STATES>(0.0, 0.0);
        rows_match_perturbed_formulas::<BASE_STATES>(0.0, 0.15);
        rows_match_perturbed_formulas::<{ BASE_STATES + INSTALLATION_STATES }>(0.0, 0.0);
        rows_match_perturbed_formulas::<{ BASE_STATES + INSTALLATION_STATES }>(0.04, 0.2);
    }

    /// The displacement row against the displacement error integrated
    /// from the velocity error at the epoch back through the acceleration
    /// error of a = C f + g − 2 Ω_ie v written out for the estimate and a
    /// perturbed truth (δv(t_k − τ) = δv_k − τ δa; no lever arm). The row
    /// without its δa part misses by far more than the tolerance.
    #[test]
    fn displacement_row_integrates_the_velocity_error_over_the_interval() {
        let s = state::<BASE_STATES>(Vector3::zeros());
        let a = s.antenna();
        let (c_hat, r, v_hat) = (s.nav.c_b_e, s.nav.position_ecef, s.nav.velocity_ecef);
        let f_hat = s.last_sample.specific_force_b;
        let dt = 0.25;
        let mut x = SVector::<f64, BASE_STATES>::zeros();
        // Tilt 0.01 rad (a consumer IMU's), 0.2 m/s, accelerometer bias 0.2 m/s².
        for (i, value) in [
            0.01, -0.008, 0.004, 0.1, -0.2, 0.05, 0.0, 0.0, 0.0, 0.2, -0.1, 0.15,
        ]
        .into_iter()
        .enumerate()
        {
            x[i] = value;
        }
        let psi = Vector3::new(x[0], x[1], x[2]);
        let delta_v = Vector3::new(x[3], x[4], x[5]);
        let c_true = rotation_vector_to_dcm(&(-psi)) * c_hat;
        let f_true = f_hat + Vector3::new(x[9], x[10], x[11]);
        let acceleration = |c: &Matrix3<f64>, f: &Vector3<f64>, v: &Vector3<f64>| {
            c * f + gravity_ecef(&r) - 2.0 * EARTH_RATE_ECEF.cross(v)
        };
        let delta_a = acceleration(&c_hat, &f_hat, &v_hat)
            - acceleration(&c_true, &f_true, &(v_hat - delta_v));
        // The trapezoid is exact for the linear δv(t).
        let steps = 100;
        let h = dt / steps as f64;
        let delta_v_at = |k: usize| delta_v - (dt - k as f64 * h) * delta_a;
        let displacement: Vector3<f64> = (0..steps)
            .map(|k| 0.5 * h * (delta_v_at(k) + delta_v_at(k + 1)))
            .sum();
        for k in 0..3 {
            let mut e = Vector3::zeros();
            e[k] = 1.0;
            let acceleration_part = 0.5 * delta_a[k] * dt * dt;
            // What is left out: ψ's second order (|f| ψ²/2) and 2 Ω_ie δv
            // in δa, below 2 % of the δa part here.
            let tolerance = 1e-9 + 0.02 * acceleration_part.abs();
            let row = a.displacement_row(&e, dt).dot(&x);
            assert!(
                (row - displacement[k]).abs() < tolerance,
                "axis {k}: {row} {displacement}"
            );
            let velocity_only = a.velocity_row(&(e * dt)).dot(&x);
            assert!(
                (velocity_only - displacement[k]).abs() > 10.0 * tolerance,
                "axis {k}"
            );
        }
    }

    #[test]
    fn without_a_lever_arm_the_rows_are_the_identity() {
        let s = state::<BASE_STATES>(Vector3::zeros());
        let a = s.antenna();
        assert_eq!(a.position_ecef, s.nav.position_ecef);
        let row = a.velocity_row(&Vector3::new(0.0, 1.0, 0.0));
        assert_eq!(row, SparseRow::new(&[(VELOCITY + 1, 1.0)]));
        // Only the Earth-rate term of the lever-arm velocity is left: none.
        assert!((a.velocity_ecef - s.nav.velocity_ecef).norm() == 0.0);
    }
}
