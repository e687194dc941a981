//! An IMU: an accelerometer triad, a gyroscope triad, their sample rate and
//! the specification (one-sigma magnitudes) their errors come from.

use nalgebra::{Matrix3, Vector3};
use rand::Rng as _;
use rand_distr::StandardNormal;

use super::{AccelerometerModel, GyroscopeModel, NoiseModel};
use crate::limits::MAX_SENSOR_MAGNITUDE;
use crate::random::Rng;
use crate::validate::{self, SeriesCheck};
use crate::{Error, Result};

/// One-sigma magnitudes of an accelerometer triad's errors (method §2).
///
/// Each deterministic term of a drawn model is zero-mean Gaussian with this
/// standard deviation, independently per axis (per off-diagonal element for
/// the misalignment). The noise is always held in density form
/// (`noise.white_std == 0`), so it does not depend on the sample rate.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AccelerometerSpec {
    /// Turn-on bias b_a, m/s².
    pub bias_std: f64,
    /// Scale-factor error D_a, dimensionless.
    pub scale_factor_std: f64,
    /// Misalignment M_a (each off-diagonal element), dimensionless (rad).
    pub misalignment_std: f64,
    /// Second-order nonlinearity N_a, 1/(m/s²).
    pub nonlinearity_std: f64,
    /// Stochastic errors: `white_density` (m/s²/√Hz, velocity random walk),
    /// Gauss-Markov bias instability (m/s², s), acceleration random walk
    /// (m/s²/√s), quantisation (m/s²).
    pub noise: NoiseModel,
}

/// One-sigma magnitudes of a gyroscope triad's errors (method §2).
///
/// As [`AccelerometerSpec`]; the noise is in density form.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GyroscopeSpec {
    /// Turn-on bias b_g, rad/s.
    pub bias_std: f64,
    /// Scale-factor error D_g, dimensionless.
    pub scale_factor_std: f64,
    /// Misalignment M_g (each off-diagonal element), dimensionless (rad).
    pub misalignment_std: f64,
    /// g-sensitivity K_g (each of its nine elements), (rad/s)/(m/s²).
    pub g_sensitivity_std: f64,
    /// Stochastic errors: `white_density` (rad/s/√Hz, angle random walk),
    /// Gauss-Markov bias instability (rad/s, s), rate random walk
    /// (rad/s/√s), quantisation (rad/s).
    pub noise: NoiseModel,
}

/// What an IMU's errors are drawn from, and what the coupled filters tune
/// their process noise Q and initial bias covariance from: the white-noise
/// densities give the velocity/angle random walk, the bias terms the
/// initial bias standard deviation and its Gauss-Markov / random-walk
/// dynamics.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ImuSpec {
    /// The accelerometer triad's spec.
    pub accelerometer: AccelerometerSpec,
    /// The gyroscope triad's spec.
    pub gyroscope: GyroscopeSpec,
}

fn normal3(rng: &mut Rng, std: f64) -> Vector3<f64> {
    Vector3::new(
        rng.sample::<f64, _>(StandardNormal),
        rng.sample::<f64, _>(StandardNormal),
        rng.sample::<f64, _>(StandardNormal),
    ) * std
}

/// A 3×3 matrix with N(0, std²) off-diagonal elements (row-major draws) and a zero diagonal.
fn misalignment(rng: &mut Rng, std: f64) -> Matrix3<f64> {
    let mut m = Matrix3::zeros();
    for i in 0..3 {
        for j in 0..3 {
            if i != j {
                m[(i, j)] = std * rng.sample::<f64, _>(StandardNormal);
            }
        }
    }
    m
}

fn full3(rng: &mut Rng, std: f64) -> Matrix3<f64> {
    Matrix3::from_fn(|_, _| std * rng.sample::<f64, _>(StandardNormal))
}

/// A one-sigma magnitude of a spec: finite, non-negative and at most a
/// tenth of [`MAX_SENSOR_MAGNITUDE`], so that the values drawn from it
/// (beyond ten sigma with probability 10⁻²³) stay within the models' limit
/// and an error names the spec key, not the drawn parameter.
fn spec_magnitude(argument: &str, value: f64) -> Result<()> {
    validate::magnitude(argument, value, MAX_SENSOR_MAGNITUDE / 10.0)
}

fn rms(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), x| (s + x * x, n + 1));
    (sum / n as f64).sqrt()
}

fn rms_off_diagonal(m: &Matrix3<f64>) -> f64 {
    rms((0..9).filter(|k| k % 4 != 0).map(|k| m[(k / 3, k % 3)]))
}

impl AccelerometerSpec {
    /// Non-negative finite magnitudes and valid noise. Errors name the
    /// `ImuModel.spec` key (`accel_bias_std`, …).
    pub fn validate(&self) -> Result<()> {
        spec_magnitude("accel_bias_std", self.bias_std)?;
        spec_magnitude("accel_scale_factor_std", self.scale_factor_std)?;
        spec_magnitude("accel_misalignment_std", self.misalignment_std)?;
        spec_magnitude("accel_nonlinearity_std", self.nonlinearity_std)?;
        self.noise.validate()
    }

    /// A model drawn from this spec. Draw order: bias (x, y, z), scale factor,
    /// misalignment (off-diagonal, row-major), nonlinearity.
    pub fn draw(&self, rng: &mut Rng) -> Result<AccelerometerModel> {
        self.validate()?;
        let bias = normal3(rng, self.bias_std);
        let scale_factor = normal3(rng, self.scale_factor_std);
        let m = misalignment(rng, self.misalignment_std);
        let nonlinearity = normal3(rng, self.nonlinearity_std);
        AccelerometerModel::new(bias, scale_factor, m, nonlinearity, self.noise)
    }

    /// The spec implied by one model: each magnitude is the RMS of the
    /// model's own values of that term (over the axes, or the six
    /// off-diagonal misalignments), the noise is the model's, as a density
    /// at `sample_rate_hz`.
    pub fn of_model(model: &AccelerometerModel, sample_rate_hz: f64) -> Self {
        Self {
            bias_std: rms(model.bias.iter().copied()),
            scale_factor_std: rms(model.scale_factor.iter().copied()),
            misalignment_std: rms_off_diagonal(&model.misalignment),
            nonlinearity_std: rms(model.nonlinearity.iter().copied()),
            noise: model.noise.as_density(sample_rate_hz),
        }
    }
}

impl GyroscopeSpec {
    /// Non-negative finite magnitudes and valid noise. Errors name the
    /// `ImuModel.spec` key (`gyro_bias_std`, …).
    pub fn validate(&self) -> Result<()> {
        spec_magnitude("gyro_bias_std", self.bias_std)?;
        spec_magnitude("gyro_scale_factor_std", self.scale_factor_std)?;
        spec_magnitude("gyro_misalignment_std", self.misalignment_std)?;
        spec_magnitude("gyro_g_sensitivity_std", self.g_sensitivity_std)?;
        self.noise.validate()
    }

    /// A model drawn from this spec. Draw order: bias, scale factor,
    /// misalignment (off-diagonal, row-major), g-sensitivity (row-major).
    pub fn draw(&self, rng: &mut Rng) -> Result<GyroscopeModel> {
        self.validate()?;
        let bias = normal3(rng, self.bias_std);
        let scale_factor = normal3(rng, self.scale_factor_std);
        let m = misalignment(rng, self.misalignment_std);
        let k = full3(rng, self.g_sensitivity_std);
        GyroscopeModel::new(bias, scale_factor, m, k, self.noise)
    }

    /// The spec implied by one model (RMS of its own values; see
    /// [`AccelerometerSpec::of_model`]).
    pub fn of_model(model: &GyroscopeModel, sample_rate_hz: f64) -> Self {
        Self {
            bias_std: rms(model.bias.iter().copied()),
            scale_factor_std: rms(model.scale_factor.iter().copied()),
            misalignment_std: rms_off_diagonal(&model.misalignment),
            g_sensitivity_std: rms(model.g_sensitivity.iter().copied()),
            noise: model.noise.as_density(sample_rate_hz),
        }
    }
}

impl ImuSpec {
    /// Both halves valid.
    pub fn validate(&self) -> Result<()> {
        self.accelerometer.validate()?;
        self.gyroscope.validate()
    }

    /// The spec's fields under their flat names (`accel_bias_std`,
    /// `gyro_noise_density`, ...), the names a spec has in Python and in
    /// configuration files.
    pub fn fields_mut(&mut self) -> [(&'static str, &mut f64); 18] {
        let a = &mut self.accelerometer;
        let g = &mut self.gyroscope;
        [
            ("accel_bias_std", &mut a.bias_std),
            ("accel_scale_factor_std", &mut a.scale_factor_std),
            ("accel_misalignment_std", &mut a.misalignment_std),
            ("accel_nonlinearity_std", &mut a.nonlinearity_std),
            ("accel_noise_density", &mut a.noise.white_density),
            ("accel_bias_instability", &mut a.noise.bias_instability_std),
            (
                "accel_bias_correlation_time",
                &mut a.noise.bias_correlation_time_s,
            ),
            ("accel_bias_random_walk", &mut a.noise.bias_random_walk),
            ("accel_quantization", &mut a.noise.quantization),
            ("gyro_bias_std", &mut g.bias_std),
            ("gyro_scale_factor_std", &mut g.scale_factor_std),
            ("gyro_misalignment_std", &mut g.misalignment_std),
            ("gyro_g_sensitivity_std", &mut g.g_sensitivity_std),
            ("gyro_noise_density", &mut g.noise.white_density),
            ("gyro_bias_instability", &mut g.noise.bias_instability_std),
            (
                "gyro_bias_correlation_time",
                &mut g.noise.bias_correlation_time_s,
            ),
            ("gyro_bias_random_walk", &mut g.noise.bias_random_walk),
            ("gyro_quantization", &mut g.noise.quantization),
        ]
    }

    /// The flat fields and their values (see [`Self::fields_mut`]).
    pub fn fields(&self) -> [(&'static str, f64); 18] {
        let mut copy = *self;
        copy.fields_mut().map(|(key, value)| (key, *value))
    }

    /// This spec with some flat fields replaced: an unknown key, a value
    /// that is not a finite non-negative number, or a Gauss-Markov bias
    /// without a positive correlation time is an error naming
    /// `spec['key']`.
    pub fn with_overrides(&self, overrides: &[(String, f64)]) -> Result<Self> {
        let mut spec = *self;
        for (key, value) in overrides {
            let mut fields = spec.fields_mut();
            let Some((_, field)) = fields.iter_mut().find(|(k, _)| k == key) else {
                let names: Vec<&str> = fields.iter().map(|(k, _)| *k).collect();
                return Err(Error::invalid(
                    "spec",
                    format!("unknown key '{key}'; expected some of {}", names.join(", ")),
                ));
            };
            validate::non_negative(&format!("spec['{key}']"), *value)?;
            **field = *value;
        }
        for (prefix, noise) in [
            ("accel", &spec.accelerometer.noise),
            ("gyro", &spec.gyroscope.noise),
        ] {
            if noise.bias_instability_std > 0.0 && noise.bias_correlation_time_s <= 0.0 {
                return Err(Error::invalid(
                    format!("spec['{prefix}_bias_correlation_time']"),
                    format!("must be positive when {prefix}_bias_instability > 0"),
                ));
            }
        }
        Ok(spec)
    }

    /// The spec implied by two models at `sample_rate_hz` (see [`AccelerometerSpec::of_model`]).
    pub fn of_models(
        accelerometer: &AccelerometerModel,
        gyroscope: &GyroscopeModel,
        sample_rate_hz: f64,
    ) -> Self {
        Self {
            accelerometer: AccelerometerSpec::of_model(accelerometer, sample_rate_hz),
            gyroscope: GyroscopeSpec::of_model(gyroscope, sample_rate_hz),
        }
    }

    /// The same spec with both noises in density form at `sample_rate_hz`.
    fn in_density_form(mut self, sample_rate_hz: f64) -> Self {
        self.accelerometer.noise = self.accelerometer.noise.as_density(sample_rate_hz);
        self.gyroscope.noise = self.gyroscope.noise.as_density(sample_rate_hz);
        self
    }
}

/// Simulated readings of an IMU: measured f_ib^b (m/s²) and ω_ib^b (rad/s).
#[derive(Debug, Clone, PartialEq)]
pub struct ImuReadings {
    /// Measured specific force per sample, m/s².
    pub specific_force_b: Vec<Vector3<f64>>,
    /// Measured angular rate per sample, rad/s.
    pub angular_rate_b: Vec<Vector3<f64>>,
}

/// An accelerometer triad and a gyroscope triad sampled together.
#[derive(Debug, Clone, PartialEq)]
pub struct ImuModel {
    /// The accelerometer triad.
    pub accelerometer: AccelerometerModel,
    /// The gyroscope triad.
    pub gyroscope: GyroscopeModel,
    /// Sample rate of both triads, Hz.
    pub sample_rate_hz: f64,
    /// What the errors are drawn from (presets) or, for a hand-built IMU,
    /// the magnitudes of its own errors; noise in density form.
    pub spec: ImuSpec,
}

impl ImuModel {
    /// An IMU from explicit models. Its spec is derived from the models
    /// themselves: each deterministic magnitude is the RMS of the model's
    /// own values of that term (so a filter tuned from it starts with a
    /// bias covariance of the right size), the noise is the models' noise
    /// as densities at `sample_rate_hz`.
    pub fn new(
        accelerometer: AccelerometerModel,
        gyroscope: GyroscopeModel,
        sample_rate_hz: f64,
    ) -> Result<Self> {
        let spec = ImuSpec::of_models(&accelerometer, &gyroscope, sample_rate_hz);
        Self::with_spec(accelerometer, gyroscope, sample_rate_hz, spec)
    }

    /// An IMU from explicit models and an explicit spec (its white noise, if
    /// given per sample, is converted to a density at `sample_rate_hz`).
    pub fn with_spec(
        accelerometer: AccelerometerModel,
        gyroscope: GyroscopeModel,
        sample_rate_hz: f64,
        spec: ImuSpec,
    ) -> Result<Self> {
        super::check_sample_rate(sample_rate_hz)?;
        accelerometer.validate()?;
        gyroscope.validate()?;
        spec.validate()?;
        Ok(Self {
            accelerometer,
            gyroscope,
            sample_rate_hz,
            spec: spec.in_density_form(sample_rate_hz),
        })
    }

    /// An IMU whose errors are drawn from `spec` (accelerometer first, then
    /// gyroscope; see [`AccelerometerSpec::draw`]).
    pub fn from_spec(spec: &ImuSpec, sample_rate_hz: f64, rng: &mut Rng) -> Result<Self> {
        super::check_sample_rate(sample_rate_hz)?;
        let spec = spec.in_density_form(sample_rate_hz);
        let accelerometer = spec.accelerometer.draw(rng)?;
        let gyroscope = spec.gyroscope.draw(rng)?;
        Ok(Self {
            accelerometer,
            gyroscope,
            sample_rate_hz,
            spec,
        })
    }

    /// Readings of both triads for true specific forces Γ_k (m/s²) and
    /// angular rates Ω_k (rad/s) at the IMU's rate: accelerometer first,
    /// then gyroscope, from the same generator.
    pub fn measure(
        &self,
        specific_force: &[Vector3<f64>],
        angular_rate: &[Vector3<f64>],
        rng: &mut Rng,
    ) -> Result<ImuReadings> {
        self.measure_series(specific_force, angular_rate, rng, SeriesCheck::Finite)
    }

    /// [`Self::measure`] with the series' finiteness checked as `check`
    /// says ([`SeriesCheck::Trusted`]: series this crate generated).
    pub(crate) fn measure_series(
        &self,
        specific_force: &[Vector3<f64>],
        angular_rate: &[Vector3<f64>],
        rng: &mut Rng,
        check: SeriesCheck,
    ) -> Result<ImuReadings> {
        validate::same_length(
            "angular_rate",
            angular_rate.len(),
            "specific_force",
            specific_force.len(),
        )?;
        let specific_force_b =
            self.accelerometer
                .measure_series(specific_force, self.sample_rate_hz, rng, check)?;
        let angular_rate_b = self.gyroscope.measure_series(
            angular_rate,
            specific_force,
            self.sample_rate_hz,
            rng,
            check,
        )?;
        Ok(ImuReadings {
            specific_force_b,
            angular_rate_b,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;

    #[test]
    fn flat_fields_override_by_name_and_refuse_what_is_wrong() {
        let mut spec = ImuSpec::default();
        for (_, value) in spec.fields_mut() {
            *value = 0.5;
        }
        let names: Vec<&str> = spec.fields().iter().map(|(k, _)| *k).collect();
        assert_eq!(names.len(), 18);
        let changed = spec
            .with_overrides(&[("gyro_bias_std".into(), 1e-3)])
            .unwrap();
        assert_eq!(changed.gyroscope.bias_std, 1e-3);
        // Every other field untouched.
        let before = spec.fields();
        for ((k, a), (_, b)) in before.iter().zip(changed.fields()) {
            if *k != "gyro_bias_std" {
                assert_eq!(*a, b, "{k}");
            }
        }
        let err = |o: (&str, f64)| {
            spec.with_overrides(&[(o.0.into(), o.1)])
                .unwrap_err()
                .to_string()
        };
        assert!(err(("gyro_bias", 1.0))
            .starts_with("spec: unknown key 'gyro_bias'; expected some of accel_bias_std"));
        assert!(err(("accel_quantization", -1.0))
            .starts_with("spec['accel_quantization']: must be finite and non-negative"));
        let gauss_markov = spec.with_overrides(&[
            ("accel_bias_instability".into(), 1e-3),
            ("accel_bias_correlation_time".into(), 0.0),
        ]);
        assert!(gauss_markov
            .unwrap_err()
            .to_string()
            .starts_with("spec['accel_bias_correlation_time']: must be positive"));
    }

    #[test]
    fn hand_built_spec_is_the_rms_of_its_own_values() {
        let acc = AccelerometerModel::new(
            Vector3::new(0.3, -0.4, 0.0),
            Vector3::zeros(),
            Matrix3::new(0.0, 0.1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
            Vector3::zeros(),
            NoiseModel {
                white_std: 0.02,
                ..Default::default()
            },
        )
        .unwrap();
        let imu = ImuModel::new(acc, GyroscopeModel::ideal(), 400.0).unwrap();
        let s = imu.spec.accelerometer;
        assert!((s.bias_std - (0.25f64 / 3.0).sqrt()).abs() < 1e-15);
        assert!((s.misalignment_std - (0.01f64 / 6.0).sqrt()).abs() < 1e-15);
        assert_eq!(s.noise.white_std, 0.0);
        assert!((s.noise.white_density - 0.001).abs() < 1e-15);
        assert_eq!(imu.spec.gyroscope, GyroscopeSpec::default());
    }

    #[test]
    fn measure_checks_lengths_and_is_reproducible() {
        let imu = ImuModel::preset("paper-mems", &mut stream(3, 0)).unwrap();
        let f = vec![Vector3::new(0.0, 0.0, -9.8); 50];
        let w = vec![Vector3::new(0.01, 0.0, 0.0); 49];
        let e = imu.measure(&f, &w, &mut stream(1, 0)).unwrap_err();
        assert!(e.to_string().starts_with("angular_rate:"), "{e}");
        let w = vec![Vector3::new(0.01, 0.0, 0.0); 50];
        let a = imu.measure(&f, &w, &mut stream(1, 0)).unwrap();
        let b = imu.measure(&f, &w, &mut stream(1, 0)).unwrap();
        let c = imu.measure(&f, &w, &mut stream(2, 0)).unwrap();
        assert_eq!(a, b);
        assert_ne!(a, c);
    }
}
