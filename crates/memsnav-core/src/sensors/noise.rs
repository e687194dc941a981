//! Stochastic sensor errors: white noise, a first-order Gauss-Markov bias
//! (bias instability), a random-walk bias and output quantisation.

use crate::{validate, Result};

/// The stochastic errors of one sensor triad (the same on its three axes).
///
/// All standard deviations are in the sensor's SI unit (m/s² or rad/s).
/// Zero switches a term off; [`NoiseModel::default`] is noise-free.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NoiseModel {
    /// White output noise ν, standard deviation per sample.
    pub white_std: f64,
    /// Steady-state standard deviation of the Gauss-Markov bias.
    pub bias_instability_std: f64,
    /// Correlation time of the Gauss-Markov bias, s (> 0 when the term is on).
    pub bias_correlation_time_s: f64,
    /// Random-walk bias: standard deviation of its growth per √s
    /// (rate random walk for gyros, acceleration random walk for accelerometers).
    pub bias_random_walk: f64,
    /// Output quantisation step (LSB); 0 for none.
    pub quantization: f64,
}

impl NoiseModel {
    /// Finite, non-negative values; a positive correlation time when the
    /// Gauss-Markov term is on.
    pub fn validate(&self) -> Result<()> {
        validate::non_negative("noise_std", self.white_std)?;
        validate::non_negative("bias_instability", self.bias_instability_std)?;
        validate::non_negative("bias_random_walk", self.bias_random_walk)?;
        validate::non_negative("quantization", self.quantization)?;
        validate::non_negative("bias_correlation_time", self.bias_correlation_time_s)?;
        if self.bias_instability_std > 0.0 {
            validate::positive("bias_correlation_time", self.bias_correlation_time_s)?;
        }
        Ok(())
    }
}
