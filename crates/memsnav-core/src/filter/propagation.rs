//! The ECEF error-state system model and its discretised, structured
//! covariance propagation (Groves, *Principles of GNSS, Inertial, and
//! Multisensor Integrated Navigation Systems*, 2nd ed., §14.2.3,
//! eq. 14.48-14.50 for F; eq. 14.80-14.82 for Q).
//!
//! With the conventions of [`super::state`] (errors = estimate − truth,
//! f̃ = f + b_a + w_a, ω̃ = ω + b_g + w_g) the continuous model is
//!
//! ```text
//! ψ̇  = −Ω_ie ψ − Ĉ δb_g − Ĉ diag(ω̂) δs_g + Ĉ w_g
//! δv̇ = −[(Ĉ f̂)×] ψ − 2 Ω_ie δv + Γ δr − Ĉ δb_a − Ĉ diag(f̂) δs_a + Ĉ w_a
//! δṙ = δv
//! δḃ = −δb / τ + w_b        (τ = ∞: random walk)
//! δċ = δd,  δḋ = w_d       (receiver clock, two-state model)
//! ```
//!
//! Γ = ∂g/∂r is the gravity gradient: the point-mass term
//! −μ/r³ (I − 3 r̂ r̂ᵀ) plus the centrifugal term diag(ω_ie², ω_ie², 0).
//! (Groves eq. 14.49 keeps only the radial part −2g/r r̂ r̂ᵀ; the full
//! point-mass form costs the same.) Signs differ from Groves where his
//! bias states are corrections rather than errors.
//!
//! Discretisation: Φ = I + F Δt (Groves eq. 14.72, first order), except the
//! Gauss-Markov bias decay, which uses the exact e^{−Δt/τ}. The neglected
//! ½F²Δt² terms scale with (ω_ie Δt)² ≈ 5e-13 and |f| Δt² ≈ 1e-3 m/s at
//! 100 Hz, below the process noise of any IMU grade.
//!
//! Q: Groves eq. 14.82 (the diagonal first-order form, noise densities times
//! Δt; Ĉ S Ĉᵀ = S I for isotropic noise) plus the exact two-state clock
//! block (S_φ Δt + S_f Δt³/3, S_f Δt²/2, S_f Δt).
//!
//! P ← Φ P Φᵀ + Q is computed as Φ (Φ P)ᵀ + Q, applying Φ block-row by
//! block-row: only the non-zero 3×3 blocks of F are multiplied (≈ 65·N
//! multiply-adds per application instead of N³).

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::state::{
    ACCEL_BIAS, ACCEL_SCALE_FACTOR, ATTITUDE, CLOCK_DRIFT, CLOCK_OFFSET, GYRO_BIAS,
    GYRO_SCALE_FACTOR, POSITION, VELOCITY, WITH_SCALE_FACTORS,
};
use crate::attitude::skew;
use crate::geodesy::wgs84::{EARTH_RATE_RAD_S, GM_M3_S2};

/// The navigation solution the system matrix is linearised about.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SystemInputs {
    /// Estimated body-to-ECEF attitude Ĉ_b^e.
    pub c_b_e: Matrix3<f64>,
    /// Corrected specific force f̂_ib^b, m/s².
    pub specific_force_b: Vector3<f64>,
    /// Corrected angular rate ω̂_ib^b, rad/s.
    pub angular_rate_b: Vector3<f64>,
    /// Estimated position r̂^e, m.
    pub position_ecef: Vector3<f64>,
}

/// Power spectral densities of the filter's process noise (one value per
/// triad, the same on each axis), Groves §14.2.4.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProcessNoise {
    /// Accelerometer white noise S_ra, m²/s³ (= (velocity random walk)²;
    /// σ² / f_s for a white noise of σ per sample at f_s).
    pub accel_white_psd: f64,
    /// Gyro white noise S_rg, rad²/s (= (angle random walk)²).
    pub gyro_white_psd: f64,
    /// Driving noise of the accelerometer bias S_bad, (m/s²)²/s
    /// (2σ²/τ for a Gauss-Markov bias, the squared random-walk coefficient otherwise).
    pub accel_bias_psd: f64,
    /// Correlation time of the accelerometer bias, s; `f64::INFINITY` for a random walk.
    pub accel_bias_correlation_time_s: f64,
    /// Driving noise of the gyro bias S_bgd, (rad/s)²/s.
    pub gyro_bias_psd: f64,
    /// Correlation time of the gyro bias, s; `f64::INFINITY` for a random walk.
    pub gyro_bias_correlation_time_s: f64,
    /// Receiver clock phase noise S_cφ, m²/s.
    pub clock_phase_psd: f64,
    /// Receiver clock frequency noise S_cf, m²/s³.
    pub clock_frequency_psd: f64,
    /// Driving noise of the accelerometer scale-factor states, 1/s (23-state filters).
    pub accel_scale_factor_psd: f64,
    /// Driving noise of the gyro scale-factor states, 1/s (23-state filters).
    pub gyro_scale_factor_psd: f64,
}

/// Gravity gradient Γ = ∂g^e/∂r^e: point mass plus centrifugal term.
fn gravity_gradient(r: &Vector3<f64>) -> Matrix3<f64> {
    let r2 = r.norm_squared();
    let rn = r2.sqrt();
    let u = r / rn;
    let w2 = EARTH_RATE_RAD_S * EARTH_RATE_RAD_S;
    -GM_M3_S2 / (r2 * rn) * (Matrix3::identity() - 3.0 * u * u.transpose())
        + Matrix3::from_diagonal(&Vector3::new(w2, w2, 0.0))
}

fn decay(dt: f64, tau: f64) -> f64 {
    if tau.is_finite() {
        (-dt / tau).exp()
    } else {
        1.0
    }
}

/// The continuous system matrix F (dense), for tests and for users who
/// want it; propagation itself never forms it.
pub fn system_matrix<const N: usize>(
    inputs: &SystemInputs,
    noise: &ProcessNoise,
) -> SMatrix<f64, N, N> {
    let mut f = SMatrix::<f64, N, N>::zeros();
    let omega_ie = skew(&Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S));
    let c = inputs.c_b_e;
    let f_e = c * inputs.specific_force_b;
    let set = |f: &mut SMatrix<f64, N, N>, i: usize, j: usize, b: &Matrix3<f64>| {
        f.fixed_view_mut::<3, 3>(i, j).copy_from(b);
    };
    set(&mut f, ATTITUDE, ATTITUDE, &(-omega_ie));
    set(&mut f, ATTITUDE, GYRO_BIAS, &(-c));
    set(&mut f, VELOCITY, ATTITUDE, &(-skew(&f_e)));
    set(&mut f, VELOCITY, VELOCITY, &(-2.0 * omega_ie));
    set(
        &mut f,
        VELOCITY,
        POSITION,
        &gravity_gradient(&inputs.position_ecef),
    );
    set(&mut f, VELOCITY, ACCEL_BIAS, &(-c));
    set(&mut f, POSITION, VELOCITY, &Matrix3::identity());
    if noise.accel_bias_correlation_time_s.is_finite() {
        set(
            &mut f,
            ACCEL_BIAS,
            ACCEL_BIAS,
            &(-Matrix3::identity() / noise.accel_bias_correlation_time_s),
        );
    }
    if noise.gyro_bias_correlation_time_s.is_finite() {
        set(
            &mut f,
            GYRO_BIAS,
            GYRO_BIAS,
            &(-Matrix3::identity() / noise.gyro_bias_correlation_time_s),
        );
    }
    f[(CLOCK_OFFSET, CLOCK_DRIFT)] = 1.0;
    if N >= WITH_SCALE_FACTORS {
        set(
            &mut f,
            ATTITUDE,
            GYRO_SCALE_FACTOR,
            &(-c * Matrix3::from_diagonal(&inputs.angular_rate_b)),
        );
        set(
            &mut f,
            VELOCITY,
            ACCEL_SCALE_FACTOR,
            &(-c * Matrix3::from_diagonal(&inputs.specific_force_b)),
        );
    }
    f
}

/// The non-identity blocks of Φ = I + FΔt for one interval.
struct Transition {
    psi_psi: Matrix3<f64>,
    psi_bg: Matrix3<f64>,
    psi_sg: Matrix3<f64>,
    v_psi: Matrix3<f64>,
    v_v: Matrix3<f64>,
    v_r: Matrix3<f64>,
    v_ba: Matrix3<f64>,
    v_sa: Matrix3<f64>,
    dt: f64,
    ba_decay: f64,
    bg_decay: f64,
}

impl Transition {
    fn new(inputs: &SystemInputs, noise: &ProcessNoise, dt: f64) -> Self {
        let omega_ie_dt = skew(&Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S * dt));
        let c_dt = inputs.c_b_e * dt;
        Self {
            psi_psi: Matrix3::identity() - omega_ie_dt,
            psi_bg: -c_dt,
            psi_sg: -c_dt * Matrix3::from_diagonal(&inputs.angular_rate_b),
            v_psi: -skew(&(c_dt * inputs.specific_force_b)),
            v_v: Matrix3::identity() - 2.0 * omega_ie_dt,
            v_r: gravity_gradient(&inputs.position_ecef) * dt,
            v_ba: -c_dt,
            v_sa: -c_dt * Matrix3::from_diagonal(&inputs.specific_force_b),
            dt,
            ba_decay: decay(dt, noise.accel_bias_correlation_time_s),
            bg_decay: decay(dt, noise.gyro_bias_correlation_time_s),
        }
    }

    /// Φ M, block-row by block-row, touching only the non-zero blocks.
    fn apply<const N: usize, const C: usize>(&self, m: &SMatrix<f64, N, C>) -> SMatrix<f64, N, C> {
        let mut out = *m;
        let rows = |i: usize| m.fixed_rows::<3>(i);
        let mut psi = self.psi_psi * rows(ATTITUDE) + self.psi_bg * rows(GYRO_BIAS);
        let mut v = self.v_psi * rows(ATTITUDE)
            + self.v_v * rows(VELOCITY)
            + self.v_r * rows(POSITION)
            + self.v_ba * rows(ACCEL_BIAS);
        if N >= WITH_SCALE_FACTORS {
            psi += self.psi_sg * rows(GYRO_SCALE_FACTOR);
            v += self.v_sa * rows(ACCEL_SCALE_FACTOR);
        }
        out.fixed_rows_mut::<3>(ATTITUDE).copy_from(&psi);
        out.fixed_rows_mut::<3>(VELOCITY).copy_from(&v);
        for j in 0..C {
            for k in 0..3 {
                out[(POSITION + k, j)] += self.dt * m[(VELOCITY + k, j)];
            }
            out[(CLOCK_OFFSET, j)] += self.dt * m[(CLOCK_DRIFT, j)];
        }
        if self.ba_decay != 1.0 {
            out.fixed_rows_mut::<3>(ACCEL_BIAS).scale_mut(self.ba_decay);
        }
        if self.bg_decay != 1.0 {
            out.fixed_rows_mut::<3>(GYRO_BIAS).scale_mut(self.bg_decay);
        }
        out
    }
}

/// x ← Φ x, P ← Φ P Φᵀ + Q over one interval `dt`.
pub(super) fn propagate<const N: usize>(
    x: &mut SVector<f64, N>,
    p: &mut SMatrix<f64, N, N>,
    inputs: &SystemInputs,
    noise: &ProcessNoise,
    dt: f64,
) {
    let phi = Transition::new(inputs, noise, dt);
    if x.iter().any(|v| *v != 0.0) {
        *x = phi.apply(x);
    }
    // Φ P Φᵀ = Φ (Φ P)ᵀ because P is symmetric.
    let phi_p = phi.apply(p);
    *p = phi.apply(&phi_p.transpose());
    add_process_noise(p, noise, dt);
}

/// Q for one interval (Groves eq. 14.82 plus the exact clock block).
fn add_process_noise<const N: usize>(p: &mut SMatrix<f64, N, N>, noise: &ProcessNoise, dt: f64) {
    let bias_q = |psd: f64, tau: f64| {
        if tau.is_finite() {
            // Exact discrete variance of a Gauss-Markov process driven by psd.
            0.5 * psd * tau * (1.0 - (-2.0 * dt / tau).exp())
        } else {
            psd * dt
        }
    };
    let qa = bias_q(noise.accel_bias_psd, noise.accel_bias_correlation_time_s);
    let qg = bias_q(noise.gyro_bias_psd, noise.gyro_bias_correlation_time_s);
    for k in 0..3 {
        p[(ATTITUDE + k, ATTITUDE + k)] += noise.gyro_white_psd * dt;
        p[(VELOCITY + k, VELOCITY + k)] += noise.accel_white_psd * dt;
        p[(ACCEL_BIAS + k, ACCEL_BIAS + k)] += qa;
        p[(GYRO_BIAS + k, GYRO_BIAS + k)] += qg;
        if N >= WITH_SCALE_FACTORS {
            p[(ACCEL_SCALE_FACTOR + k, ACCEL_SCALE_FACTOR + k)] +=
                noise.accel_scale_factor_psd * dt;
            p[(GYRO_SCALE_FACTOR + k, GYRO_SCALE_FACTOR + k)] += noise.gyro_scale_factor_psd * dt;
        }
    }
    let sf = noise.clock_frequency_psd;
    p[(CLOCK_OFFSET, CLOCK_OFFSET)] += noise.clock_phase_psd * dt + sf * dt * dt * dt / 3.0;
    p[(CLOCK_OFFSET, CLOCK_DRIFT)] += 0.5 * sf * dt * dt;
    p[(CLOCK_DRIFT, CLOCK_OFFSET)] += 0.5 * sf * dt * dt;
    p[(CLOCK_DRIFT, CLOCK_DRIFT)] += sf * dt;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::euler_to_dcm;
    use crate::geodesy::{geodetic_to_ecef, gravity_ecef, Geodetic};

    fn inputs() -> SystemInputs {
        SystemInputs {
            c_b_e: euler_to_dcm(0.3, -0.2, 1.1),
            specific_force_b: Vector3::new(1.2, -0.4, -9.7),
            angular_rate_b: Vector3::new(0.05, -0.02, 0.3),
            position_ecef: geodetic_to_ecef(Geodetic::new(0.76, 0.025, 150.0)),
        }
    }

    fn noise(tau: f64) -> ProcessNoise {
        ProcessNoise {
            accel_white_psd: 1e-4,
            gyro_white_psd: 1e-8,
            accel_bias_psd: 1e-7,
            accel_bias_correlation_time_s: tau,
            gyro_bias_psd: 1e-11,
            gyro_bias_correlation_time_s: 2.0 * tau,
            clock_phase_psd: 0.01,
            clock_frequency_psd: 0.04,
            accel_scale_factor_psd: 1e-9,
            gyro_scale_factor_psd: 2e-9,
        }
    }

    fn random_spd<const N: usize>() -> SMatrix<f64, N, N> {
        let a = SMatrix::<f64, N, N>::from_fn(|i, j| ((i * 7 + j * 13) % 11) as f64 / 11.0 - 0.4);
        a * a.transpose() + SMatrix::identity()
    }

    /// The structured Φ P Φᵀ + Q equals the dense product with Φ = I + FΔt
    /// (bias decay e^{−Δt/τ}) and the dense Q.
    fn structured_equals_dense<const N: usize>(tau: f64) {
        let (inp, nz, dt) = (inputs(), noise(tau), 0.01);
        let mut phi = SMatrix::<f64, N, N>::identity() + system_matrix::<N>(&inp, &nz) * dt;
        for k in 0..3 {
            phi[(ACCEL_BIAS + k, ACCEL_BIAS + k)] = decay(dt, nz.accel_bias_correlation_time_s);
            phi[(GYRO_BIAS + k, GYRO_BIAS + k)] = decay(dt, nz.gyro_bias_correlation_time_s);
        }
        let p0 = random_spd::<N>();
        let mut q = SMatrix::<f64, N, N>::zeros();
        add_process_noise(&mut q, &nz, dt);
        let dense = phi * p0 * phi.transpose() + q;
        let mut p = p0;
        let mut x = SVector::<f64, N>::from_fn(|i, _| i as f64 * 0.1);
        let x_dense = phi * x;
        propagate(&mut x, &mut p, &inp, &nz, dt);
        assert!((p - dense).abs().max() < 1e-12 * dense.abs().max(), "P");
        assert!((x - x_dense).abs().max() < 1e-13, "x");
        assert!((p - p.transpose()).abs().max() < 1e-13);
    }

    #[test]
    fn structured_propagation_matches_dense() {
        structured_equals_dense::<17>(300.0);
        structured_equals_dense::<17>(f64::INFINITY);
        structured_equals_dense::<23>(300.0);
    }

    /// Γ against a central difference of the J2 gravity model the INS uses
    /// (J2 adds ~1e-3 relative, far below what the filter needs).
    #[test]
    fn gravity_gradient_matches_numerical_derivative() {
        let r = inputs().position_ecef;
        let g = gravity_gradient(&r);
        for j in 0..3 {
            let mut d = Vector3::zeros();
            d[j] = 1.0;
            let col = (gravity_ecef(&(r + d)) - gravity_ecef(&(r - d))) / 2.0;
            assert!((g.column(j) - col).norm() < 1e-2 * g.norm(), "column {j}");
        }
    }

    /// F against a numerical linearisation of the ECEF velocity equation
    /// v̇ = Ĉ f̂ + g(r) − 2Ω v with Ĉ = (I + [ψ×])C, f̂ = f − δb_a − diag(f)δs_a.
    #[test]
    fn velocity_rows_match_the_perturbed_dynamics() {
        let inp = inputs();
        let f = system_matrix::<23>(&inp, &noise(100.0));
        let omega = skew(&Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S));
        let v = Vector3::new(10.0, -3.0, 1.0);
        let vdot = |x: &SVector<f64, 23>| {
            let psi = x.fixed_rows::<3>(ATTITUDE).into_owned();
            let c = crate::attitude::rotation_vector_to_dcm(&psi) * inp.c_b_e;
            let ba = x.fixed_rows::<3>(ACCEL_BIAS).into_owned();
            let sa = x.fixed_rows::<3>(ACCEL_SCALE_FACTOR).into_owned();
            let fb = inp.specific_force_b - ba - inp.specific_force_b.component_mul(&sa);
            let r = inp.position_ecef + x.fixed_rows::<3>(POSITION);
            let vv = v + x.fixed_rows::<3>(VELOCITY);
            c * fb + gravity_ecef(&r) - 2.0 * omega * vv
        };
        let x0 = SVector::<f64, 23>::zeros();
        for j in [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 17, 18, 19] {
            let h = if (6..9).contains(&j) { 1.0 } else { 1e-6 };
            let mut xp = x0;
            xp[j] = h;
            let mut xm = x0;
            xm[j] = -h;
            let col = (vdot(&xp) - vdot(&xm)) / (2.0 * h);
            let tol = if (6..9).contains(&j) {
                1e-7
            } else {
                1e-7 * col.norm().max(1.0)
            };
            assert!(
                (f.fixed_view::<3, 1>(VELOCITY, j) - col).norm() < tol,
                "column {j}: {} vs {}",
                f.fixed_view::<3, 1>(VELOCITY, j),
                col
            );
        }
    }
}
