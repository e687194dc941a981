//! Step 1 of the module docs of [`super`]: the nominal readings
//! s = scale ⊙ (raw − offset) of raw ones, with the nominal scale and
//! offset per count (1 and 0 for readings already near SI). The sensor
//! models describe these nominal readings, so their scale factor and bias
//! are the corrections to the nominal values.

use nalgebra::Vector3;

use crate::{validate, Error, Result};

/// Nominal scale and offset of the raw readings: s = scale ⊙ (raw − offset).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nominal {
    /// Accelerometer (m/s²) per count.
    pub accel_scale: Vector3<f64>,
    /// Accelerometer reading at zero input, counts.
    pub accel_offset: Vector3<f64>,
    /// Gyroscope (rad/s) per count.
    pub gyro_scale: Vector3<f64>,
    /// Gyroscope reading at zero input, counts.
    pub gyro_offset: Vector3<f64>,
}

impl Default for Nominal {
    /// Readings already in SI: scale 1, offset 0.
    fn default() -> Self {
        Self {
            accel_scale: Vector3::repeat(1.0),
            accel_offset: Vector3::zeros(),
            gyro_scale: Vector3::repeat(1.0),
            gyro_offset: Vector3::zeros(),
        }
    }
}

impl Nominal {
    /// Errors name a non-finite field, or a zero scale.
    pub(super) fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("accel_scale", &self.accel_scale),
            ("gyro_scale", &self.gyro_scale),
        ] {
            validate::finite_vectors(name, std::slice::from_ref(v))?;
            if v.iter().any(|x| *x == 0.0) {
                return Err(Error::invalid(name, "a scale per count must not be zero"));
            }
        }
        validate::finite_vectors("accel_offset", std::slice::from_ref(&self.accel_offset))?;
        validate::finite_vectors("gyro_offset", std::slice::from_ref(&self.gyro_offset))
    }

    /// The nominal accelerometer reading of a raw one.
    pub fn accel(&self, raw: &Vector3<f64>) -> Vector3<f64> {
        self.accel_scale.component_mul(&(raw - self.accel_offset))
    }

    /// The nominal gyroscope reading of a raw one.
    pub fn gyro(&self, raw: &Vector3<f64>) -> Vector3<f64> {
        self.gyro_scale.component_mul(&(raw - self.gyro_offset))
    }
}
