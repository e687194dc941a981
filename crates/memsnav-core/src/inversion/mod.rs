//! Model inversion (method §4, paper eq. 8-10): two random-walk EKFs that
//! estimate the true specific force Γ and angular rate Ω from the sensor
//! outputs and a calibrated model.
//!
//! ```text
//! Γ_k = Γ_{k−1} + w_Γ,  S_a,k = A_a (Γ_k − b_a − N_a (Γ_k ⊙ Γ_k)) + v_a
//! Ω_k = Ω_{k−1} + w_Ω,  S_g,k = A_g (Ω_k − b_g − K_g Γ̂_k) + v_g
//! ```
//!
//! The gyroscope filter runs after the accelerometer filter and takes its
//! estimate Γ̂_k. Measurement Jacobians: H_a = A_a (I − 2 N_a diag(Γ)),
//! H_g = A_g. Each filter is initialised by inverting the model exactly on
//! the first sample, with the covariance that one sample carries,
//! P₀ = H⁻¹ R H⁻ᵀ. Covariance updates use the Joseph form. Fixed-size 3×3
//! algebra, no allocation per sample.

use nalgebra::{Matrix3, Vector3};

use crate::sensors::{AccelerometerModel, GyroscopeModel};
use crate::{validate, Error, Result};

/// Estimates of a filter and the diagonal of their covariance, per sample.
#[derive(Debug, Clone, PartialEq)]
pub struct Inversion {
    /// The filter's estimate at each sample.
    pub estimate: Vec<Vector3<f64>>,
    /// The diagonal of its covariance at each sample.
    pub variance: Vec<Vector3<f64>>,
}

/// Noise levels of a random-walk EKF, per axis, in the state's SI unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InversionNoise {
    /// Std of the random-walk increment per sample.
    pub process_std: Vector3<f64>,
    /// Std of the output noise per sample.
    pub measurement_std: Vector3<f64>,
}

impl InversionNoise {
    fn validate(&self) -> Result<()> {
        for i in 0..3 {
            validate::positive("process_std", self.process_std[i])?;
            validate::positive("measurement_std", self.measurement_std[i])?;
        }
        Ok(())
    }
}

/// Γ from one accelerometer output, inverting eq. 2 exactly: per axis
/// N y² − y + x = 0 with x = A⁻¹S + b, the root nearest x,
/// y = 2x / (1 + √(1 − 4 N x)) (the form without cancellation).
fn invert_accelerometer_sample(
    s: &Vector3<f64>,
    a_inv: &Matrix3<f64>,
    model: &AccelerometerModel,
) -> Result<Vector3<f64>> {
    let x = a_inv * s + model.bias;
    let mut y = Vector3::zeros();
    for i in 0..3 {
        let disc = 1.0 - 4.0 * model.nonlinearity[i] * x[i];
        if disc < 0.0 {
            return Err(Error::invalid(
                "model",
                format!(
                    "the nonlinearity makes output {} unreachable on axis {i}",
                    s[i]
                ),
            ));
        }
        y[i] = 2.0 * x[i] / (1.0 + disc.sqrt());
    }
    Ok(y)
}

fn inverse(a: &Matrix3<f64>, argument: &str) -> Result<Matrix3<f64>> {
    a.try_inverse()
        .ok_or_else(|| Error::invalid(argument, "I − D − M is singular"))
}

/// One random-walk EKF step (predict + Joseph update) on a 3-state filter.
#[inline]
fn step(
    x: &mut Vector3<f64>,
    p: &mut Matrix3<f64>,
    q: &Matrix3<f64>,
    r: &Matrix3<f64>,
    innovation: Vector3<f64>,
    h: &Matrix3<f64>,
    k_index: usize,
) -> Result<()> {
    *p += q;
    let s = h * *p * h.transpose() + r;
    let s_inv = s.try_inverse().ok_or(Error::Divergence {
        time_s: k_index as f64,
        reason: "innovation covariance is singular".into(),
    })?;
    let gain = *p * h.transpose() * s_inv;
    *x += gain * innovation;
    let i_kh = Matrix3::identity() - gain * h;
    *p = i_kh * *p * i_kh.transpose() + gain * r * gain.transpose();
    *p = (*p + p.transpose()) * 0.5;
    if !x.iter().all(|v| v.is_finite()) {
        return Err(Error::Divergence {
            time_s: k_index as f64,
            reason: format!("state became non-finite at sample {k_index}"),
        });
    }
    Ok(())
}

/// The accelerometer EKF (method §4, eq. 9) over a whole series of outputs
/// `measured` (m/s²): returns Γ̂ (m/s²) and the diagonal of its covariance.
/// Divergence errors report the sample index as `time_s`.
pub fn invert_accelerometer(
    measured: &[Vector3<f64>],
    model: &AccelerometerModel,
    noise: &InversionNoise,
) -> Result<Inversion> {
    validate::finite_vectors("measured", measured)?;
    noise.validate()?;
    if measured.is_empty() {
        return Err(Error::invalid("measured", "needs at least one sample"));
    }
    let a = model.output_matrix();
    let a_inv = inverse(&a, "model")?;
    let q = Matrix3::from_diagonal(&noise.process_std.component_mul(&noise.process_std));
    let r = Matrix3::from_diagonal(&noise.measurement_std.component_mul(&noise.measurement_std));
    let mut x = invert_accelerometer_sample(&measured[0], &a_inv, model)?;
    let h0_inv = inverse(&model.jacobian(&x), "model")?;
    let mut p = h0_inv * r * h0_inv.transpose();
    let mut estimate = Vec::with_capacity(measured.len());
    let mut variance = Vec::with_capacity(measured.len());
    estimate.push(x);
    variance.push(p.diagonal());
    for (k, s) in measured.iter().enumerate().skip(1) {
        // Linearise at the prediction (the random walk keeps x).
        let h = model.jacobian(&x);
        let innovation = s - model.output(&x);
        step(&mut x, &mut p, &q, &r, innovation, &h, k)?;
        estimate.push(x);
        variance.push(p.diagonal());
    }
    Ok(Inversion { estimate, variance })
}

/// The gyroscope EKF (method §4, eq. 10), conditioned on the estimated
/// specific force Γ̂ (m/s², from [`invert_accelerometer`]): returns Ω̂
/// (rad/s) and the diagonal of its covariance.
pub fn invert_gyroscope(
    measured: &[Vector3<f64>],
    specific_force: &[Vector3<f64>],
    model: &GyroscopeModel,
    noise: &InversionNoise,
) -> Result<Inversion> {
    validate::finite_vectors("measured", measured)?;
    validate::same_length(
        "specific_force",
        specific_force.len(),
        "measured",
        measured.len(),
    )?;
    validate::finite_vectors("specific_force", specific_force)?;
    noise.validate()?;
    if measured.is_empty() {
        return Err(Error::invalid("measured", "needs at least one sample"));
    }
    let h = model.output_matrix();
    let h_inv = inverse(&h, "model")?;
    let q = Matrix3::from_diagonal(&noise.process_std.component_mul(&noise.process_std));
    let r = Matrix3::from_diagonal(&noise.measurement_std.component_mul(&noise.measurement_std));
    // Exact inversion of eq. 3 on the first sample: Ω = A⁻¹S + b + KΓ̂.
    let mut x = h_inv * measured[0] + model.bias + model.g_sensitivity * specific_force[0];
    let mut p = h_inv * r * h_inv.transpose();
    let mut estimate = Vec::with_capacity(measured.len());
    let mut variance = Vec::with_capacity(measured.len());
    estimate.push(x);
    variance.push(p.diagonal());
    for (k, (s, f)) in measured.iter().zip(specific_force).enumerate().skip(1) {
        let innovation = s - model.output(&x, f);
        step(&mut x, &mut p, &q, &r, innovation, &h, k)?;
        estimate.push(x);
        variance.push(p.diagonal());
    }
    Ok(Inversion { estimate, variance })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;
    use crate::sensors::NoiseModel;
    use rand::Rng as _;
    use rand_distr::StandardNormal;

    fn accel() -> AccelerometerModel {
        AccelerometerModel {
            bias: Vector3::new(0.1, -0.2, 0.05),
            scale_factor: Vector3::new(1e-3, -2e-3, 5e-4),
            misalignment: Matrix3::new(0.0, 0.01, -0.02, 0.005, 0.0, 0.01, -0.01, 0.02, 0.0),
            nonlinearity: Vector3::new(1e-3, -2e-3, 1.5e-3),
            noise: NoiseModel::default(),
        }
    }

    #[test]
    fn first_sample_inverts_the_model_exactly() {
        let m = accel();
        let f = Vector3::new(3.0, -2.0, -9.8);
        let s = m.output(&f);
        let inv = invert_accelerometer(&[s], &m, &noise(0.1, 0.01)).unwrap();
        assert!((inv.estimate[0] - f).amax() < 1e-12);
        let g = GyroscopeModel {
            bias: Vector3::new(1e-3, 2e-3, -1e-3),
            scale_factor: Vector3::new(1e-3, 0.0, -1e-3),
            misalignment: Matrix3::new(0.0, 0.01, 0.0, 0.0, 0.0, -0.01, 0.02, 0.0, 0.0),
            g_sensitivity: Matrix3::from_fn(|i, j| 1e-4 * (i as f64 - j as f64)),
            noise: NoiseModel::default(),
        };
        let w = Vector3::new(0.1, -0.3, 0.2);
        let inv = invert_gyroscope(&[g.output(&w, &f)], &[f], &g, &noise(0.1, 0.01)).unwrap();
        assert!((inv.estimate[0] - w).amax() < 1e-14);
    }

    fn noise(q: f64, r: f64) -> InversionNoise {
        InversionNoise {
            process_std: Vector3::repeat(q),
            measurement_std: Vector3::repeat(r),
        }
    }

    /// For an ideal sensor (H = I) the filter is three scalar Kalman
    /// filters whose steady state is known in closed form,
    /// P⁻ = (q² + √(q⁴ + 4 q² r²)) / 2 and P⁺ = P⁻ r² / (P⁻ + r²); on a true
    /// random walk the actual mean square error equals P⁺.
    #[test]
    fn steady_state_variance_is_the_riccati_solution() {
        let m = AccelerometerModel::ideal();
        let (q, r) = (0.02, 0.05);
        let mut rng = stream(1, 0);
        let mut f = Vector3::new(1.0, 2.0, -9.8);
        let mut truth = Vec::new();
        let s: Vec<_> = (0..5000)
            .map(|_| {
                f += Vector3::from_fn(|_, _| q * rng.sample::<f64, _>(StandardNormal));
                truth.push(f);
                f + Vector3::from_fn(|_, _| r * rng.sample::<f64, _>(StandardNormal))
            })
            .collect();
        let inv = invert_accelerometer(&s, &m, &noise(q, r)).unwrap();
        let p_minus = (q * q + (q.powi(4) + 4.0 * q * q * r * r).sqrt()) / 2.0;
        let p_plus = p_minus * r * r / (p_minus + r * r);
        let v = inv.variance.last().unwrap();
        assert!((v.x / p_plus - 1.0).abs() < 1e-9, "{} vs {p_plus}", v.x);
        // And the actual error matches it: mean square error over the run.
        let mse: f64 = inv.estimate[100..]
            .iter()
            .zip(&truth[100..])
            .map(|(e, f)| (e - f).norm_squared() / 3.0)
            .sum::<f64>()
            / 4900.0;
        assert!((mse / p_plus - 1.0).abs() < 0.15, "{mse} vs {p_plus}");
    }

    #[test]
    fn bad_inputs_name_the_argument() {
        let m = accel();
        let s = vec![Vector3::new(0.0, 0.0, -9.8); 3];
        let e = invert_accelerometer(&s, &m, &noise(0.0, 0.1)).unwrap_err();
        assert!(e.to_string().starts_with("process_std:"), "{e}");
        let e = invert_accelerometer(&s, &m, &noise(0.1, -1.0)).unwrap_err();
        assert!(e.to_string().starts_with("measurement_std:"), "{e}");
        let e =
            invert_gyroscope(&s, &s[..2], &GyroscopeModel::ideal(), &noise(0.1, 0.1)).unwrap_err();
        assert!(e.to_string().starts_with("specific_force:"), "{e}");
        let e = invert_accelerometer(&[], &m, &noise(0.1, 0.1)).unwrap_err();
        assert!(e.to_string().starts_with("measured:"), "{e}");
    }
}
