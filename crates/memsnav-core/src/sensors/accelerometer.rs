//! Accelerometer model, method §2 (paper eq. 2):
//! S_a = (I − D_a − M_a) (Γ − b_a − N_a (Γ ⊙ Γ) − ν_a).

use nalgebra::{Matrix3, Vector3};

use super::{output_matrix, validate_common, NoiseModel};
use crate::{validate, Result};

/// Deterministic errors of a triad of accelerometers plus its noise.
///
/// Units: `bias` m/s², `scale_factor` dimensionless, `misalignment`
/// dimensionless (zero diagonal; `M[i][j]` couples input axis j into output
/// axis i), `nonlinearity` 1/(m/s²) (second-order coefficient per axis).
#[derive(Debug, Clone, PartialEq)]
pub struct AccelerometerModel {
    pub bias: Vector3<f64>,
    pub scale_factor: Vector3<f64>,
    pub misalignment: Matrix3<f64>,
    pub nonlinearity: Vector3<f64>,
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
        validate_common(&bias, &scale_factor, &misalignment)?;
        validate::finite_vectors("nonlinearity", std::slice::from_ref(&nonlinearity))?;
        noise.validate()?;
        Ok(Self {
            bias,
            scale_factor,
            misalignment,
            nonlinearity,
            noise,
        })
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

    /// ∂S_a/∂Γ = (I − D − M)(I − 2 N diag(Γ)) (method §4).
    pub fn jacobian(&self, specific_force: &Vector3<f64>) -> Matrix3<f64> {
        let d = Vector3::repeat(1.0) - 2.0 * self.nonlinearity.component_mul(specific_force);
        self.output_matrix() * Matrix3::from_diagonal(&d)
    }
}
