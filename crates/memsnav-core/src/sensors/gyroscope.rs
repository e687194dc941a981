//! Gyroscope model, method §2 (paper eq. 3):
//! S_g = (I − D_g − M_g) (Ω − b_g − K_g Γ − ν_g).

use nalgebra::{Matrix3, Vector3};

use super::{output_matrix, validate_common, NoiseModel};
use crate::{validate, Result};

/// Deterministic errors of a triad of gyroscopes plus its noise.
///
/// Units: `bias` rad/s, `scale_factor` and `misalignment` dimensionless
/// (zero diagonal), `g_sensitivity` (rad/s)/(m/s²), a full 3×3 matrix whose
/// row i gives the sensitivity of gyro axis i to the three specific-force
/// components.
#[derive(Debug, Clone, PartialEq)]
pub struct GyroscopeModel {
    pub bias: Vector3<f64>,
    pub scale_factor: Vector3<f64>,
    pub misalignment: Matrix3<f64>,
    pub g_sensitivity: Matrix3<f64>,
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
        validate_common(&bias, &scale_factor, &misalignment)?;
        validate::finite_matrix("g_sensitivity", &g_sensitivity)?;
        noise.validate()?;
        Ok(Self {
            bias,
            scale_factor,
            misalignment,
            g_sensitivity,
            noise,
        })
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
