//! Accelerometer model, method §2 (paper eq. 2):
//! S_a = (I − D_a − M_a) (Γ − b_a − N_a (Γ ⊙ Γ) − ν_a).

use nalgebra::{Matrix3, Vector3};

use super::{check_sample_rate, output_matrix, validate_common, NoiseModel, NoiseProcess};
use crate::limits::MAX_SENSOR_MAGNITUDE;
use crate::random::Rng;
use crate::validate::{self, SeriesCheck};
use crate::Result;

/// Deterministic errors of a triad of accelerometers plus its noise.
///
/// Units: `bias` m/s², `scale_factor` dimensionless, `misalignment`
/// dimensionless (zero diagonal; `M[i][j]` couples input axis j into output
/// axis i), `nonlinearity` 1/(m/s²) (second-order coefficient per axis).
#[derive(Debug, Clone, PartialEq)]
pub struct AccelerometerModel {
    /// Bias b_a per axis, m/s².
    pub bias: Vector3<f64>,
    /// Scale-factor error per axis, the diagonal of D_a (dimensionless).
    pub scale_factor: Vector3<f64>,
    /// Misalignment M_a (dimensionless, zero diagonal).
    pub misalignment: Matrix3<f64>,
    /// Second-order coefficient per axis, the diagonal of N_a, 1/(m/s²).
    pub nonlinearity: Vector3<f64>,
    /// Stochastic errors and output quantisation ([`NoiseModel`]).
    pub noise: NoiseModel,
}

impl AccelerometerModel {
    /// A validated model (finite values, zero-diagonal misalignment, valid noise).
    pub fn new(
        bias: Vector3<f64>,
        scale_factor: Vector3<f64>,
        misalignment: Matrix3<f64>,
        nonlinearity: Vector3<f64>,
        noise: NoiseModel,
    ) -> Result<Self> {
        let model = Self {
            bias,
            scale_factor,
            misalignment,
            nonlinearity,
            noise,
        };
        model.validate()?;
        Ok(model)
    }

    /// Finite values, zero-diagonal misalignment, non-singular I − D − M,
    /// valid noise (the fields are public, so [`Self::measure`] checks again).
    pub fn validate(&self) -> Result<()> {
        validate_common(&self.bias, &self.scale_factor, &self.misalignment)?;
        validate::bounded_vectors(
            "nonlinearity",
            std::slice::from_ref(&self.nonlinearity),
            MAX_SENSOR_MAGNITUDE,
        )?;
        self.noise.validate()
    }

    /// Simulated readings for a series of true specific forces Γ_k (m/s²)
    /// sampled at `sample_rate_hz`: the exact eq. 2 with the stochastic
    /// terms of [`NoiseModel`] (see `sensors::noise` for where each enters):
    ///
    /// S_k = Q((I − D_a − M_a)(Γ_k − (b_a + β_k + ρ_k) − N_a (Γ_k ⊙ Γ_k) − ν_k)).
    ///
    /// Errors name the argument: `specific_force` (non-finite rows),
    /// `sample_rate` (not positive), or the model's own parameters.
    pub fn measure(
        &self,
        specific_force: &[Vector3<f64>],
        sample_rate_hz: f64,
        rng: &mut Rng,
    ) -> Result<Vec<Vector3<f64>>> {
        self.measure_series(specific_force, sample_rate_hz, rng, SeriesCheck::Finite)
    }

    /// [`Self::measure`], the O(n) finiteness check of the series done
    /// only when `check` asks for it (skipped for a series this crate
    /// generated: the same numbers either way).
    pub(crate) fn measure_series(
        &self,
        specific_force: &[Vector3<f64>],
        sample_rate_hz: f64,
        rng: &mut Rng,
        check: SeriesCheck,
    ) -> Result<Vec<Vector3<f64>>> {
        self.validate()?;
        check_sample_rate(sample_rate_hz)?;
        if check == SeriesCheck::Finite {
            validate::bounded_vectors("specific_force", specific_force, MAX_SENSOR_MAGNITUDE)?;
        }
        let a = self.output_matrix();
        let mut noise = NoiseProcess::new(&self.noise, sample_rate_hz, rng);
        Ok(specific_force
            .iter()
            .map(|g| {
                let n = noise.next_sample(rng);
                let input = g
                    - (self.bias + n.bias_drift)
                    - self.nonlinearity.component_mul(&g.component_mul(g))
                    - n.white;
                self.noise.quantize(a * input)
            })
            .collect())
    }

    /// An error-free accelerometer (output equals input).
    pub fn ideal() -> Self {
        Self {
            bias: Vector3::zeros(),
            scale_factor: Vector3::zeros(),
            misalignment: Matrix3::zeros(),
            nonlinearity: Vector3::zeros(),
            noise: NoiseModel::default(),
        }
    }

    /// A = I − D_a − M_a.
    pub fn output_matrix(&self) -> Matrix3<f64> {
        output_matrix(&self.scale_factor, &self.misalignment)
    }

    /// Noise-free output for a true specific force Γ (exact eq. 2 with ν = 0).
    pub fn output(&self, specific_force: &Vector3<f64>) -> Vector3<f64> {
        self.output_with_input_noise(specific_force, &Vector3::zeros())
    }

    /// Exact eq. 2 for a given input-referred noise sample ν_a.
    pub fn output_with_input_noise(
        &self,
        specific_force: &Vector3<f64>,
        nu: &Vector3<f64>,
    ) -> Vector3<f64> {
        let g = specific_force;
        self.output_matrix()
            * (g - self.bias - self.nonlinearity.component_mul(&g.component_mul(g)) - nu)
    }

    /// The true specific force Γ (m/s²) behind a noise-free output S: the
    /// exact inverse of eq. 2. With x = A⁻¹S + b, each axis solves
    /// Γ_i − N_i Γ_i² = x_i; the root that tends to x_i as N_i → 0 is
    /// Γ_i = 2x_i / (1 + √(1 − 4 N_i x_i)) (the stable form of the quadratic
    /// formula). An output whose discriminant is negative lies beyond the
    /// turning point of the model's parabola (|Γ_i| > 1/(2|N_i|)): an error
    /// naming `measured`.
    pub fn correct(&self, measured: &Vector3<f64>) -> Result<Vector3<f64>> {
        let x = self
            .output_matrix()
            .try_inverse()
            .ok_or_else(|| crate::Error::invalid("scale_factor", "I - D - M is singular"))?
            * measured
            + self.bias;
        let mut gamma = Vector3::zeros();
        for i in 0..3 {
            let discriminant = 1.0 - 4.0 * self.nonlinearity[i] * x[i];
            if discriminant.is_nan() || discriminant < 0.0 {
                return Err(crate::Error::invalid(
                    "measured",
                    format!(
                        "axis {i}: output {:.6e} is beyond the range of the second-order model \
                         (nonlinearity {:.3e})",
                        measured[i], self.nonlinearity[i]
                    ),
                ));
            }
            gamma[i] = 2.0 * x[i] / (1.0 + discriminant.sqrt());
        }
        Ok(gamma)
    }

    /// ∂S_a/∂Γ = (I − D − M)(I − 2 N diag(Γ)) (method §4).
    pub fn jacobian(&self, specific_force: &Vector3<f64>) -> Matrix3<f64> {
        let d = Vector3::repeat(1.0) - 2.0 * self.nonlinearity.component_mul(specific_force);
        self.output_matrix() * Matrix3::from_diagonal(&d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;

    fn model(noise: NoiseModel) -> AccelerometerModel {
        AccelerometerModel::new(
            Vector3::new(0.1, -0.2, 0.05),
            Vector3::new(1e-3, -2e-3, 5e-4),
            Matrix3::new(0.0, 0.01, -0.02, 0.015, 0.0, 0.005, -0.01, 0.02, 0.0),
            Vector3::new(1e-4, -2e-4, 3e-4),
            noise,
        )
        .unwrap()
    }

    #[test]
    fn correct_inverts_eq_2_exactly() {
        let acc = model(NoiseModel::default());
        for f in [
            Vector3::new(1.0, -2.0, -9.81),
            Vector3::new(20.0, 5.0, 0.0),
            Vector3::new(-30.0, 0.0, 12.0),
        ] {
            let back = acc.correct(&acc.output(&f)).unwrap();
            assert!((back - f).amax() < 1e-12 * f.amax(), "{back} vs {f}");
        }
        // Zero nonlinearity: the linear inverse A⁻¹S + b.
        let mut linear = acc.clone();
        linear.nonlinearity = Vector3::zeros();
        let s = Vector3::new(3.0, -4.0, 9.0);
        let expected = linear.output_matrix().try_inverse().unwrap() * s + linear.bias;
        assert!((linear.correct(&s).unwrap() - expected).amax() < 1e-14);
        // Beyond the parabola's turning point (1/(2N) = 1667 m/s² on w).
        let err = acc.correct(&Vector3::new(0.0, 0.0, 1e4)).unwrap_err();
        assert!(err.to_string().starts_with("measured:"), "{err}");
    }

    #[test]
    fn noise_free_measure_is_eq_2_written_out() {
        let acc = model(NoiseModel::default());
        let f = [Vector3::new(1.0, -2.0, -9.81), Vector3::new(20.0, 5.0, 0.0)];
        let out = acc.measure(&f, 100.0, &mut stream(0, 0)).unwrap();
        for (g, s) in f.iter().zip(&out) {
            // Row u of eq. 2 expanded by hand: (1 − D_u) x_u − M_uv x_v − M_uw x_w,
            // x = Γ − b − N Γ².
            let x = Vector3::new(
                g.x - 0.1 - 1e-4 * g.x * g.x,
                g.y + 0.2 + 2e-4 * g.y * g.y,
                g.z - 0.05 - 3e-4 * g.z * g.z,
            );
            let u = (1.0 - 1e-3) * x.x - 0.01 * x.y + 0.02 * x.z;
            let w = 0.01 * x.x - 0.02 * x.y + (1.0 - 5e-4) * x.z;
            assert!((s.x - u).abs() < 1e-12 && (s.z - w).abs() < 1e-12);
        }
    }

    #[test]
    fn bad_arguments_are_named() {
        let acc = model(NoiseModel::default());
        let mut rng = stream(0, 0);
        let nan = [Vector3::new(0.0, f64::NAN, 0.0)];
        let e = acc.measure(&nan, 100.0, &mut rng).unwrap_err().to_string();
        assert!(e.starts_with("specific_force: row 0"), "{e}");
        let e = acc.measure(&[], 0.0, &mut rng).unwrap_err().to_string();
        assert!(e.starts_with("sample_rate:"), "{e}");
        let mut m = Matrix3::zeros();
        m[(1, 1)] = 0.1;
        let e = AccelerometerModel::new(
            Vector3::zeros(),
            Vector3::zeros(),
            m,
            Vector3::zeros(),
            NoiseModel::default(),
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("misalignment: diagonal must be zero"), "{e}");
    }
}
