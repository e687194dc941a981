//! Gyroscope model, method §2 (paper eq. 3):
//! S_g = (I − D_g − M_g) (Ω − b_g − K_g Γ − ν_g).

use nalgebra::{Matrix3, Vector3};

use super::{check_sample_rate, output_matrix, validate_common, NoiseModel, NoiseProcess};
use crate::limits::MAX_SENSOR_MAGNITUDE;
use crate::random::Rng;
use crate::validate::{self, SeriesCheck};
use crate::Result;

/// Deterministic errors of a triad of gyroscopes plus its noise.
///
/// Units: `bias` rad/s, `scale_factor` and `misalignment` dimensionless
/// (zero diagonal), `g_sensitivity` (rad/s)/(m/s²), a full 3×3 matrix whose
/// row i gives the sensitivity of gyro axis i to the three specific-force
/// components.
#[derive(Debug, Clone, PartialEq)]
pub struct GyroscopeModel {
    /// Bias b_g per axis, rad/s.
    pub bias: Vector3<f64>,
    /// Scale-factor error per axis, the diagonal of D_g (dimensionless).
    pub scale_factor: Vector3<f64>,
    /// Misalignment M_g (dimensionless, zero diagonal).
    pub misalignment: Matrix3<f64>,
    /// Sensitivity K_g to specific force, (rad/s)/(m/s²).
    pub g_sensitivity: Matrix3<f64>,
    /// Stochastic errors and output quantisation ([`NoiseModel`]).
    pub noise: NoiseModel,
}

impl GyroscopeModel {
    /// A validated model (finite values, zero-diagonal misalignment, valid noise).
    pub fn new(
        bias: Vector3<f64>,
        scale_factor: Vector3<f64>,
        misalignment: Matrix3<f64>,
        g_sensitivity: Matrix3<f64>,
        noise: NoiseModel,
    ) -> Result<Self> {
        let model = Self {
            bias,
            scale_factor,
            misalignment,
            g_sensitivity,
            noise,
        };
        model.validate()?;
        Ok(model)
    }

    /// Finite values, zero-diagonal misalignment, non-singular I − D − M,
    /// valid noise (the fields are public, so [`Self::measure`] checks again).
    pub fn validate(&self) -> Result<()> {
        validate_common(&self.bias, &self.scale_factor, &self.misalignment)?;
        validate::bounded_matrix("g_sensitivity", &self.g_sensitivity, MAX_SENSOR_MAGNITUDE)?;
        self.noise.validate()
    }

    /// Simulated readings for series of true angular rates Ω_k (rad/s) and
    /// specific forces Γ_k (m/s², for the g-sensitivity) sampled at
    /// `sample_rate_hz`: the exact eq. 3 with the stochastic terms of
    /// [`NoiseModel`] (see `sensors::noise` for where each enters):
    ///
    /// S_k = Q((I − D_g − M_g)(Ω_k − (b_g + β_k + ρ_k) − K_g Γ_k − ν_k)).
    ///
    /// Errors name the argument: `angular_rate`, `specific_force`
    /// (non-finite rows, different lengths), `sample_rate`, or the model's
    /// own parameters.
    pub fn measure(
        &self,
        angular_rate: &[Vector3<f64>],
        specific_force: &[Vector3<f64>],
        sample_rate_hz: f64,
        rng: &mut Rng,
    ) -> Result<Vec<Vector3<f64>>> {
        self.measure_series(
            angular_rate,
            specific_force,
            sample_rate_hz,
            rng,
            SeriesCheck::Finite,
        )
    }

    /// [`Self::measure`], the O(n) finiteness checks of the series done
    /// only when `check` asks for them (skipped for series this crate
    /// generated: the same numbers either way).
    pub(crate) fn measure_series(
        &self,
        angular_rate: &[Vector3<f64>],
        specific_force: &[Vector3<f64>],
        sample_rate_hz: f64,
        rng: &mut Rng,
        check: SeriesCheck,
    ) -> Result<Vec<Vector3<f64>>> {
        self.validate()?;
        check_sample_rate(sample_rate_hz)?;
        if check == SeriesCheck::Finite {
            validate::bounded_vectors("angular_rate", angular_rate, MAX_SENSOR_MAGNITUDE)?;
            validate::bounded_vectors("specific_force", specific_force, MAX_SENSOR_MAGNITUDE)?;
        }
        validate::same_length(
            "specific_force",
            specific_force.len(),
            "angular_rate",
            angular_rate.len(),
        )?;
        let a = self.output_matrix();
        let mut noise = NoiseProcess::new(&self.noise, sample_rate_hz, rng);
        Ok(angular_rate
            .iter()
            .zip(specific_force)
            .map(|(w, g)| {
                let n = noise.next_sample(rng);
                let input = w - (self.bias + n.bias_drift) - self.g_sensitivity * g - n.white;
                self.noise.quantize(a * input)
            })
            .collect())
    }

    /// An error-free gyroscope (output equals input).
    pub fn ideal() -> Self {
        Self {
            bias: Vector3::zeros(),
            scale_factor: Vector3::zeros(),
            misalignment: Matrix3::zeros(),
            g_sensitivity: Matrix3::zeros(),
            noise: NoiseModel::default(),
        }
    }

    /// A = I − D_g − M_g, which is also ∂S_g/∂Ω (method §4).
    pub fn output_matrix(&self) -> Matrix3<f64> {
        output_matrix(&self.scale_factor, &self.misalignment)
    }

    /// The true angular rate Ω (rad/s) behind a noise-free output S given
    /// the true specific force Γ (m/s²): the exact inverse of eq. 3,
    /// Ω = A⁻¹S + b + K Γ.
    pub fn correct(
        &self,
        measured: &Vector3<f64>,
        specific_force: &Vector3<f64>,
    ) -> Result<Vector3<f64>> {
        let a_inv = self
            .output_matrix()
            .try_inverse()
            .ok_or_else(|| crate::Error::invalid("scale_factor", "I - D - M is singular"))?;
        Ok(a_inv * measured + self.bias + self.g_sensitivity * specific_force)
    }

    /// Noise-free output for true angular rate Ω and specific force Γ (exact eq. 3, ν = 0).
    pub fn output(
        &self,
        angular_rate: &Vector3<f64>,
        specific_force: &Vector3<f64>,
    ) -> Vector3<f64> {
        self.output_with_input_noise(angular_rate, specific_force, &Vector3::zeros())
    }

    /// Exact eq. 3 for a given input-referred noise sample ν_g.
    pub fn output_with_input_noise(
        &self,
        angular_rate: &Vector3<f64>,
        specific_force: &Vector3<f64>,
        nu: &Vector3<f64>,
    ) -> Vector3<f64> {
        self.output_matrix() * (angular_rate - self.bias - self.g_sensitivity * specific_force - nu)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;

    #[test]
    fn correct_inverts_eq_3_exactly() {
        let gyr = GyroscopeModel::new(
            Vector3::new(1e-3, -2e-3, 3e-3),
            Vector3::new(1e-2, 2e-2, -1e-2),
            Matrix3::new(0.0, 0.01, 0.0, 0.0, 0.0, -0.02, 0.03, 0.0, 0.0),
            Matrix3::from_fn(|i, j| 1e-4 * (1 + i + 3 * j) as f64),
            NoiseModel::default(),
        )
        .unwrap();
        let (w, f) = (Vector3::new(0.5, -1.0, 2.0), Vector3::new(0.3, 9.0, -2.0));
        let back = gyr.correct(&gyr.output(&w, &f), &f).unwrap();
        assert!((back - w).amax() < 1e-14, "{back} vs {w}");
    }

    #[test]
    fn noise_free_measure_is_eq_3_and_lengths_are_checked() {
        let k = Matrix3::from_fn(|i, j| 1e-4 * (1 + i + 3 * j) as f64);
        let gyr = GyroscopeModel::new(
            Vector3::new(1e-3, -2e-3, 3e-3),
            Vector3::new(1e-4, 2e-4, -1e-4),
            Matrix3::new(0.0, 0.01, 0.0, 0.0, 0.0, -0.02, 0.03, 0.0, 0.0),
            k,
            NoiseModel::default(),
        )
        .unwrap();
        let w = [Vector3::new(0.1, -0.2, 0.3)];
        let f = [Vector3::new(0.5, 1.0, -9.8)];
        let s = gyr.measure(&w, &f, 100.0, &mut stream(0, 0)).unwrap()[0];
        // Row q of eq. 3 by hand: (1 − D_q) y_q − M_qr y_r, y = Ω − b − K Γ.
        let y = |i: usize| w[0][i] - gyr.bias[i] - (0..3).map(|j| k[(i, j)] * f[0][j]).sum::<f64>();
        assert!((s.y - ((1.0 - 2e-4) * y(1) + 0.02 * y(2))).abs() < 1e-15);
        let e = gyr
            .measure(&w, &[f[0], f[0]], 100.0, &mut stream(0, 0))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("specific_force: has 2 rows but angular_rate has 1"),
            "{e}"
        );
    }
}
