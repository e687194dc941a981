//! The deterministic sensor errors the error state does not contain, as
//! process noise shaped by the sensed motion (the "shaping
//! filter" option of Brown & Hwang, 4th ed., §3.9 and ch. 9, and Groves
//! §14.2.4 on unmodelled errors as noise).
//!
//! A raw MEMS reads (method §2, first order)
//!
//! ```text
//! f̃ − b_a = f − (D_a + M_a) f − N_a (f ⊙ f)      ω̃ − b_g = ω − (D_g + M_g) ω − K_g f
//! ```
//!
//! and a 17-state filter estimates b_a and b_g only. Split the specific
//! force into the part the biases absorb and the rest, f = f_ref + u, with
//! f_ref the gravity reaction in body axes at the start of the run: the
//! error J(f_ref) θ is constant and widens the initial bias uncertainty
//! (`FilterTuning::absorb_unmodelled`); the error J(u) θ + J(ω) θ changes
//! with the motion. Its variance on body axis i, with independent terms of
//! one-sigma σ (scale factor s, misalignment m per off-diagonal term,
//! nonlinearity n, g-sensitivity k per term), is
//!
//! ```text
//! accelerometer: σ_s² u_i² + σ_m² (|u|² − u_i²) + σ_n² (2 f_ref,i u_i + u_i²)²
//! gyro:          σ_s² ω_i² + σ_m² (|ω|² − ω_i²) + σ_k² |u|²
//! ```
//!
//! Such an error is a random constant times a known input: coloured, with
//! the correlation time τ of the input itself (a turn, an acceleration).
//! Its white-noise equivalent, the PSD at zero frequency of a first-order
//! Gauss-Markov process of variance σ² and correlation time τ
//! (S(ω) = 2σ²τ / (1 + ω²τ²), so S(0) = 2σ²τ), is evaluated at every IMU
//! step from the corrected inputs. Unlike a white noise sized for a typical
//! manoeuvre at all times (what the filter did before this model: a 0.2 rad/s
//! turn and 2 m/s² every second of the run), it adds nothing while the
//! vehicle drives straight and the errors do not grow, and the full amount
//! in a turn: on the paper's MEMS the typical-manoeuvre noise made the
//! 60 s outage's 3-D σ ten times the error (docs/explanation/few-satellites.md).

use nalgebra::{Matrix3, Vector3};

/// One-sigma magnitudes of the deterministic sensor errors a filter does
/// not estimate (method §2 terms; per off-diagonal term for misalignment,
/// per term for g-sensitivity).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct UnmodelledErrors {
    /// Accelerometer scale-factor error std (dimensionless).
    pub accel_scale_factor: f64,
    /// Accelerometer misalignment std (dimensionless, per off-diagonal term).
    pub accel_misalignment: f64,
    /// Accelerometer second-order nonlinearity std, 1/(m/s²).
    pub accel_nonlinearity_per_m_s2: f64,
    /// Gyro scale-factor error std (dimensionless).
    pub gyro_scale_factor: f64,
    /// Gyro misalignment std (dimensionless).
    pub gyro_misalignment: f64,
    /// Gyro g-sensitivity std, (rad/s)/(m/s²), per term.
    pub gyro_g_sensitivity_rad_s_per_m_s2: f64,
}

/// The errors the state lacks as noise shaped by the inputs (module docs).
/// Default: none.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputErrorNoise {
    /// Their one-sigma magnitudes (all zero: no such noise, as for a
    /// calibrated or ideal IMU).
    pub errors: UnmodelledErrors,
    /// Correlation time τ of the inputs that drive them (manoeuvres), s.
    pub correlation_time_s: f64,
    /// f_ref: the specific force whose error the bias states absorb, body
    /// axes, m/s² (the filter sets it from its initial attitude, see
    /// `coupling::FilterState::new`).
    pub reference_specific_force_b: Vector3<f64>,
}

impl Default for InputErrorNoise {
    fn default() -> Self {
        Self {
            errors: UnmodelledErrors::default(),
            correlation_time_s: DEFAULT_MANOEUVRE_CORRELATION_TIME_S,
            reference_specific_force_b: Vector3::zeros(),
        }
    }
}

/// Default correlation time of a land vehicle's manoeuvres, s: a turn or
/// an acceleration lasts some seconds: on six 600 s random trajectories
/// the autocorrelation of the yaw rate falls to 1/e in 4-8 s, that of the
/// horizontal specific force in 5-16 s (docs/explanation/few-satellites.md).
pub const DEFAULT_MANOEUVRE_CORRELATION_TIME_S: f64 = 10.0;

impl InputErrorNoise {
    /// Whether any error term is non-zero.
    pub fn is_active(&self) -> bool {
        self.errors != UnmodelledErrors::default()
    }

    /// The white-noise PSDs per body axis, (accelerometer (m/s²)²/Hz, gyro
    /// (rad/s)²/Hz), of the errors at corrected specific force `f` and
    /// angular rate `w` (module docs).
    pub fn body_psd(&self, f: &Vector3<f64>, w: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
        let u = f - self.reference_specific_force_b;
        let (u2, w2) = (u.component_mul(&u), w.component_mul(w));
        let (u_sq, w_sq) = (u2.sum(), w2.sum());
        let (e, sq) = (&self.errors, |x: f64| x * x);
        let (sa, ma, na) = (
            sq(e.accel_scale_factor),
            sq(e.accel_misalignment),
            sq(e.accel_nonlinearity_per_m_s2),
        );
        let (sg, mg, kg) = (
            sq(e.gyro_scale_factor),
            sq(e.gyro_misalignment),
            sq(e.gyro_g_sensitivity_rad_s_per_m_s2),
        );
        let white = 2.0 * self.correlation_time_s;
        let accel = Vector3::from_fn(|i, _| {
            let nonlinear = 2.0 * self.reference_specific_force_b[i] * u[i] + u2[i];
            white * (sa * u2[i] + ma * (u_sq - u2[i]) + na * nonlinear * nonlinear)
        });
        let gyro = Vector3::from_fn(|i, _| white * (sg * w2[i] + mg * (w_sq - w2[i]) + kg * u_sq));
        (accel, gyro)
    }
}

/// Ĉ diag(q) Ĉᵀ: a body-axis diagonal PSD in ECEF axes.
pub(super) fn to_ecef(c_b_e: &Matrix3<f64>, q_b: &Vector3<f64>) -> Matrix3<f64> {
    let scaled = Matrix3::from_columns(&[
        c_b_e.column(0) * q_b.x,
        c_b_e.column(1) * q_b.y,
        c_b_e.column(2) * q_b.z,
    ]);
    scaled * c_b_e.transpose()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_distr::{Distribution, StandardNormal};

    /// The per-axis variances against a Monte Carlo of the error terms
    /// themselves: draw D, M, N (K) and take the sample variance of the
    /// varying part of the reading's error, J(f) θ − J(f_ref) θ.
    #[test]
    fn variances_match_a_monte_carlo_of_the_error_terms() {
        let e = UnmodelledErrors {
            accel_scale_factor: 3e-3,
            accel_misalignment: 1e-2,
            accel_nonlinearity_per_m_s2: 2e-4,
            gyro_scale_factor: 5e-3,
            gyro_misalignment: 8e-3,
            gyro_g_sensitivity_rad_s_per_m_s2: 1e-4,
        };
        let noise = InputErrorNoise {
            errors: e,
            correlation_time_s: 0.5,
            reference_specific_force_b: Vector3::new(0.3, -0.5, -9.7),
        };
        let f = Vector3::new(2.1, -1.4, -8.9);
        let w = Vector3::new(0.05, -0.2, 0.6);
        let (accel, gyro) = noise.body_psd(&f, &w);
        let mut rng = crate::random::stream(23, 0);
        let mut normal =
            |s: f64| s * <StandardNormal as Distribution<f64>>::sample(&StandardNormal, &mut rng);
        let (mut sum_a, mut sum_g) = (Vector3::<f64>::zeros(), Vector3::<f64>::zeros());
        let draws = 200_000;
        let f_ref = noise.reference_specific_force_b;
        for _ in 0..draws {
            let mut da =
                Matrix3::from_diagonal(&Vector3::from_fn(|_, _| normal(e.accel_scale_factor)));
            let mut dg =
                Matrix3::from_diagonal(&Vector3::from_fn(|_, _| normal(e.gyro_scale_factor)));
            for i in 0..3 {
                for j in 0..3 {
                    if i != j {
                        da[(i, j)] = normal(e.accel_misalignment);
                        dg[(i, j)] = normal(e.gyro_misalignment);
                    }
                }
            }
            let n = Vector3::from_fn(|_, _| normal(e.accel_nonlinearity_per_m_s2));
            let k = Matrix3::from_fn(|_, _| normal(e.gyro_g_sensitivity_rad_s_per_m_s2));
            let accel_error = |x: &Vector3<f64>| da * x + n.component_mul(&x.component_mul(x));
            let ea = accel_error(&f) - accel_error(&f_ref);
            let eg = dg * w + k * (f - f_ref);
            sum_a += ea.component_mul(&ea);
            sum_g += eg.component_mul(&eg);
        }
        let white = 2.0 * noise.correlation_time_s;
        for i in 0..3 {
            let (mc_a, mc_g) = (
                white * sum_a[i] / draws as f64,
                white * sum_g[i] / draws as f64,
            );
            assert!(
                (accel[i] / mc_a - 1.0).abs() < 0.02,
                "accel {i}: {} vs {mc_a}",
                accel[i]
            );
            assert!(
                (gyro[i] / mc_g - 1.0).abs() < 0.02,
                "gyro {i}: {} vs {mc_g}",
                gyro[i]
            );
        }
    }

    #[test]
    fn no_errors_or_no_motion_give_no_noise() {
        let (a, g) = InputErrorNoise::default()
            .body_psd(&Vector3::new(3.0, 1.0, -9.0), &Vector3::new(0.1, 0.2, 0.3));
        assert_eq!((a, g), (Vector3::zeros(), Vector3::zeros()));
        let noise = InputErrorNoise {
            errors: UnmodelledErrors {
                accel_misalignment: 1e-2,
                gyro_misalignment: 1e-2,
                gyro_g_sensitivity_rad_s_per_m_s2: 1e-3,
                ..Default::default()
            },
            reference_specific_force_b: Vector3::new(0.0, 0.0, -9.8),
            ..Default::default()
        };
        // At rest on the reference: the error is the constant part only.
        let (a, g) = noise.body_psd(&Vector3::new(0.0, 0.0, -9.8), &Vector3::zeros());
        assert_eq!((a, g), (Vector3::zeros(), Vector3::zeros()));
    }

    #[test]
    fn the_ecef_block_is_the_rotated_diagonal() {
        let c = crate::attitude::euler_to_dcm(0.3, -0.4, 2.0);
        let q = Vector3::new(1.0, 2.0, 5.0);
        let expected = c * Matrix3::from_diagonal(&q) * c.transpose();
        assert!((to_ecef(&c, &q) - expected).abs().max() < 1e-14);
    }
}
