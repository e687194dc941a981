//! Stochastic sensor errors: white noise, a first-order Gauss-Markov bias
//! (bias instability), a random-walk bias and output quantisation.
//!
//! Where each enters the forward model of method §2 (paper eq. 2-3),
//! written for the accelerometer (the gyroscope is the same with Ω, b_g, K_g Γ):
//!
//! ```text
//! S_k = Q( (I − D − M) (Γ_k − (b + β_k + ρ_k) − N (Γ_k ⊙ Γ_k) − ν_k) )
//! ```
//!
//! - ν_k, white noise, is *input-referred*: it sits inside the bracket and is
//!   multiplied by (I − D − M), exactly as the paper's ν. Its per-sample
//!   standard deviation σ_ν is given either directly (`white_std`) or as a
//!   density `white_density` (unit/√Hz, i.e. the velocity or angle random
//!   walk): σ_ν = density · √(sample_rate) (white noise of one-sided density
//!   d sampled at f_s after an ideal anti-aliasing filter of bandwidth f_s/2
//!   — Groves 2nd ed. §4.4.3).
//! - β_k, the Gauss-Markov bias (bias instability), and ρ_k, the random-walk
//!   bias, *add to the constant bias b*: the slowly varying part of the
//!   turn-on bias, so they enter where b does.
//! - Q, quantisation, acts on the *output*: the reading is rounded to the
//!   nearest multiple of the LSB (half-way values away from zero).
//!
//! Discretisation at dt = 1/sample_rate, exact for both processes (the
//! solution of dβ/dt = −β/τ + w over one step, [`crate::gauss_markov`]):
//!
//! ```text
//! β_k = e^{−dt/τ} β_{k−1} + σ_β √(1 − e^{−2 dt/τ}) w_k,   β_0 ~ N(0, σ_β²)  (stationary)
//! ρ_k = ρ_{k−1} + q √dt w'_k,                              ρ_0 = 0
//! ```
//!
//! so Var β_k = σ_β² for every k, Corr(β_k, β_{k+j}) = e^{−j dt/τ}, and
//! Var ρ_k = q² k dt grows linearly with time. ρ starts at zero because the
//! random walk is measured from switch-on, where the bias is b.
//!
//! Random draws, per sample and only for the terms that are on: ν (three
//! normals), then the Gauss-Markov innovation, then the random-walk
//! innovation (none of the two on the first sample); the stationary
//! Gauss-Markov start is drawn before the first sample.

use nalgebra::Vector3;
use rand::Rng as _;
use rand_distr::StandardNormal;

use crate::gauss_markov::stationary_step;
use crate::random::Rng;
use crate::{validate, Error, Result};

/// The stochastic errors of one sensor triad (the same on its three axes).
///
/// All standard deviations are in the sensor's SI unit (m/s² or rad/s).
/// Zero switches a term off; [`NoiseModel::default`] is noise-free.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NoiseModel {
    /// White input-referred noise ν, standard deviation per sample
    /// (whatever the sample rate). Exclusive with `white_density`.
    pub white_std: f64,
    /// White input-referred noise ν as a density, unit/√Hz (m/s²/√Hz =
    /// velocity random walk, rad/s/√Hz = angle random walk); the
    /// per-sample std is `white_density · √sample_rate`. Exclusive with `white_std`.
    pub white_density: f64,
    /// Steady-state standard deviation σ_β of the Gauss-Markov bias.
    pub bias_instability_std: f64,
    /// Correlation time τ of the Gauss-Markov bias, s (> 0 when the term is on).
    pub bias_correlation_time_s: f64,
    /// Random-walk bias: q, the standard deviation of its growth per √s
    /// (m/s²/√s = acceleration random walk, rad/s/√s = rate random walk).
    pub bias_random_walk: f64,
    /// Output quantisation step (LSB); 0 for none.
    pub quantization: f64,
}

impl NoiseModel {
    /// Finite, non-negative values, the magnitudes at most
    /// [`MAX_SENSOR_MAGNITUDE`](crate::limits::MAX_SENSOR_MAGNITUDE); at most one of `white_std` and
    /// `white_density`; a positive correlation time when the Gauss-Markov
    /// term is on. Errors name the Python keyword of the parameter.
    pub fn validate(&self) -> Result<()> {
        validate::sensor_magnitude("noise_std", self.white_std)?;
        validate::sensor_magnitude("noise_density", self.white_density)?;
        validate::sensor_magnitude("bias_instability", self.bias_instability_std)?;
        validate::sensor_magnitude("bias_random_walk", self.bias_random_walk)?;
        validate::sensor_magnitude("quantization", self.quantization)?;
        validate::non_negative("bias_correlation_time", self.bias_correlation_time_s)?;
        if self.white_std > 0.0 && self.white_density > 0.0 {
            return Err(Error::invalid(
                "noise_density",
                "give the white noise either as noise_std (per sample) or as noise_density (per √Hz), not both",
            ));
        }
        if self.bias_instability_std > 0.0 {
            validate::positive("bias_correlation_time", self.bias_correlation_time_s)?;
        }
        Ok(())
    }

    /// Per-sample standard deviation of ν at `sample_rate_hz`:
    /// `white_std`, or `white_density · √sample_rate`.
    pub fn white_std_per_sample(&self, sample_rate_hz: f64) -> f64 {
        if self.white_density > 0.0 {
            self.white_density * sample_rate_hz.sqrt()
        } else {
            self.white_std
        }
    }

    /// Density of ν, unit/√Hz: `white_density`, or `white_std / √sample_rate`.
    pub fn white_density_at(&self, sample_rate_hz: f64) -> f64 {
        if self.white_density > 0.0 {
            self.white_density
        } else {
            self.white_std / sample_rate_hz.sqrt()
        }
    }

    /// The same noise with ν expressed as a density (at `sample_rate_hz`).
    pub fn as_density(&self, sample_rate_hz: f64) -> Self {
        Self {
            white_std: 0.0,
            white_density: self.white_density_at(sample_rate_hz),
            ..*self
        }
    }

    /// True when no stochastic term is on (the output is deterministic).
    pub fn is_silent(&self) -> bool {
        self.white_std == 0.0
            && self.white_density == 0.0
            && self.bias_instability_std == 0.0
            && self.bias_random_walk == 0.0
            && self.quantization == 0.0
    }

    /// Rounds an output to the nearest multiple of the LSB (identity when
    /// off). Where the output is 2⁵² LSBs or more, the LSB is below the
    /// output's float resolution and the output is kept as it is (dividing
    /// by an LSB of 1e-300 overflowed to inf, and inf × LSB to NaN).
    pub fn quantize(&self, output: Vector3<f64>) -> Vector3<f64> {
        const EXACT_STEPS: f64 = 4_503_599_627_370_496.0; // 2⁵²
        let lsb = self.quantization;
        if lsb > 0.0 {
            output.map(|x| {
                let steps = x / lsb;
                if steps.abs() < EXACT_STEPS {
                    steps.round() * lsb
                } else {
                    x
                }
            })
        } else {
            output
        }
    }
}

/// One sample of the stochastic terms: ν_k and β_k + ρ_k.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoiseSample {
    /// Input-referred white noise ν_k.
    pub white: Vector3<f64>,
    /// Time-varying bias β_k + ρ_k, added to the constant bias b.
    pub bias_drift: Vector3<f64>,
}

/// The running state of a [`NoiseModel`] over one series at a fixed rate.
#[derive(Debug, Clone)]
pub struct NoiseProcess {
    white_std: f64,
    markov_decay: f64,
    markov_drive_std: f64,
    walk_step_std: f64,
    markov: Vector3<f64>,
    walk: Vector3<f64>,
    started: bool,
}

fn normal3(rng: &mut Rng) -> Vector3<f64> {
    Vector3::new(
        rng.sample(StandardNormal),
        rng.sample(StandardNormal),
        rng.sample(StandardNormal),
    )
}

impl NoiseProcess {
    /// Starts the processes: β_0 from its stationary distribution, ρ_0 = 0.
    /// `noise` must be valid and `sample_rate_hz` positive (checked by the callers).
    pub fn new(noise: &NoiseModel, sample_rate_hz: f64, rng: &mut Rng) -> Self {
        let dt = 1.0 / sample_rate_hz;
        let (markov_decay, markov_drive_std, markov) = if noise.bias_instability_std > 0.0 {
            let step = stationary_step(
                noise.bias_instability_std,
                noise.bias_correlation_time_s,
                dt,
            );
            (
                step.decay,
                step.drive_std(),
                noise.bias_instability_std * normal3(rng),
            )
        } else {
            (0.0, 0.0, Vector3::zeros())
        };
        Self {
            white_std: noise.white_std_per_sample(sample_rate_hz),
            markov_decay,
            markov_drive_std,
            walk_step_std: noise.bias_random_walk * dt.sqrt(),
            markov,
            walk: Vector3::zeros(),
            started: false,
        }
    }

    /// The stochastic terms of the next sample.
    #[inline]
    pub fn next_sample(&mut self, rng: &mut Rng) -> NoiseSample {
        let white = if self.white_std > 0.0 {
            self.white_std * normal3(rng)
        } else {
            Vector3::zeros()
        };
        if self.started {
            if self.markov_drive_std > 0.0 {
                self.markov =
                    self.markov_decay * self.markov + self.markov_drive_std * normal3(rng);
            }
            if self.walk_step_std > 0.0 {
                self.walk += self.walk_step_std * normal3(rng);
            }
        }
        self.started = true;
        NoiseSample {
            white,
            bias_drift: self.markov + self.walk,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;

    fn series(noise: &NoiseModel, rate: f64, n: usize, seed: u64) -> Vec<NoiseSample> {
        let mut rng = stream(seed, 0);
        let mut p = NoiseProcess::new(noise, rate, &mut rng);
        (0..n).map(|_| p.next_sample(&mut rng)).collect()
    }

    #[test]
    fn density_and_per_sample_std_agree() {
        let d = NoiseModel {
            white_density: 0.003,
            ..Default::default()
        };
        assert!((d.white_std_per_sample(100.0) - 0.03).abs() < 1e-15);
        let s = NoiseModel {
            white_std: 0.03,
            ..Default::default()
        };
        assert!((s.white_density_at(100.0) - 0.003).abs() < 1e-15);
        assert_eq!(s.as_density(100.0).white_std_per_sample(400.0), 0.06);
        assert_eq!(s.white_std_per_sample(400.0), 0.03);
    }

    #[test]
    fn white_noise_has_its_std() {
        let noise = NoiseModel {
            white_density: 0.002,
            ..Default::default()
        };
        let xs = series(&noise, 400.0, 40_000, 1);
        let var: f64 = xs.iter().map(|s| s.white.norm_squared()).sum::<f64>() / (3.0 * 40_000.0);
        let expected = 0.002 * 20.0;
        assert!((var.sqrt() / expected - 1.0).abs() < 0.01, "{}", var.sqrt());
        assert!(xs.iter().all(|s| s.bias_drift == Vector3::zeros()));
    }

    #[test]
    fn gauss_markov_is_stationary_with_exponential_autocorrelation() {
        let tau = 0.5;
        let sigma = 2.0;
        let noise = NoiseModel {
            bias_instability_std: sigma,
            bias_correlation_time_s: tau,
            ..Default::default()
        };
        // Many short independent realisations: the variance at sample 0 and at
        // sample 200 is σ², the lag-k correlation is e^{−k dt/τ}.
        let (runs, n, rate) = (3000, 201, 100.0);
        let mut var0 = 0.0;
        let mut var_end = 0.0;
        let mut lag10 = 0.0;
        for r in 0..runs {
            let xs = series(&noise, rate, n, 100 + r);
            var0 += xs[0].bias_drift.norm_squared();
            var_end += xs[n - 1].bias_drift.norm_squared();
            lag10 += xs[n - 11].bias_drift.dot(&xs[n - 1].bias_drift);
        }
        let m = 3.0 * runs as f64;
        let (var0, var_end, lag10) = (var0 / m, var_end / m, lag10 / m);
        let tol = 4.0 * (2.0f64 / m).sqrt(); // 4σ of a variance estimate, relative
        assert!((var0 / sigma.powi(2) - 1.0).abs() < tol, "{var0}");
        assert!((var_end / sigma.powi(2) - 1.0).abs() < tol, "{var_end}");
        let rho = lag10 / sigma.powi(2);
        let expected = (-10.0 / rate / tau).exp();
        assert!((rho - expected).abs() < 0.05, "{rho} vs {expected}");
    }

    #[test]
    fn random_walk_variance_grows_linearly() {
        let q = 0.1;
        let noise = NoiseModel {
            bias_random_walk: q,
            ..Default::default()
        };
        let (runs, n, rate) = (2000, 401, 100.0);
        let mut v100 = 0.0;
        let mut v400 = 0.0;
        for r in 0..runs {
            let xs = series(&noise, rate, n, 7000 + r);
            assert_eq!(xs[0].bias_drift, Vector3::zeros());
            v100 += xs[100].bias_drift.norm_squared();
            v400 += xs[400].bias_drift.norm_squared();
        }
        let m = 3.0 * runs as f64;
        let tol = 4.0 * (2.0f64 / m).sqrt();
        assert!((v100 / m / (q * q * 1.0) - 1.0).abs() < tol);
        assert!((v400 / m / (q * q * 4.0) - 1.0).abs() < tol);
    }

    #[test]
    fn quantisation_rounds_to_the_lsb() {
        let noise = NoiseModel {
            quantization: 0.25,
            ..Default::default()
        };
        let q = noise.quantize(Vector3::new(0.12, 0.13, -0.38));
        assert_eq!(q, Vector3::new(0.0, 0.25, -0.5));
        assert_eq!(
            NoiseModel::default().quantize(Vector3::repeat(0.1)),
            Vector3::repeat(0.1)
        );
    }

    #[test]
    fn validation_names_the_keyword() {
        let bad = |n: NoiseModel| n.validate().unwrap_err().to_string();
        assert!(bad(NoiseModel {
            white_std: -1.0,
            ..Default::default()
        })
        .starts_with("noise_std:"));
        assert!(bad(NoiseModel {
            white_std: 1.0,
            white_density: 1.0,
            ..Default::default()
        })
        .starts_with("noise_density:"));
        assert!(bad(NoiseModel {
            bias_instability_std: 1.0,
            ..Default::default()
        })
        .starts_with("bias_correlation_time:"));
        assert!(bad(NoiseModel {
            bias_correlation_time_s: -1.0,
            ..Default::default()
        })
        .starts_with("bias_correlation_time:"));
        assert!(bad(NoiseModel {
            quantization: f64::NAN,
            ..Default::default()
        })
        .starts_with("quantization:"));
        assert!(bad(NoiseModel {
            bias_random_walk: -0.1,
            ..Default::default()
        })
        .starts_with("bias_random_walk:"));
    }
}
