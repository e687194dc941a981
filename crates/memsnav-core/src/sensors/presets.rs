//! IMU grade presets: the [`ImuSpec`] each named IMU draws its errors from.
//!
//! Every deterministic term is drawn zero-mean Gaussian with the one-sigma
//! magnitude below, independently per axis (see [`super::AccelerometerSpec::draw`]).
//! Data-sheet "±" figures are taken as one sigma. A data-sheet *in-run bias
//! stability* (the Allan-deviation floor) is used here as the Gauss-Markov
//! standard deviation σ_β itself, as these presets were first written; a
//! data sheet given as `[imu_spec]` figures converts the floor by the rule
//! of [`super::datasheet`] (σ_β = floor / 0.6174), and the presets keep
//! their σ_β so that results made with them stay as they are. The
//! correlation times are not given by data sheets and are assumed. Figures a source does not give are marked
//! *assumed* with the reasoning. Groves = P. D. Groves, *Principles of GNSS,
//! Inertial, and Multisensor Integrated Navigation Systems*, 2nd ed., 2013
//! (tables 4.1 and 4.2: accelerometer and gyro biases by grade; §4.4.2
//! scale-factor and cross-coupling errors 1e-4–1e-3, up to 1e-2 for MEMS;
//! §4.4.3 noise; optical gyros have negligible g-dependent bias).

use super::units::{deg_h, deg_s_per_g, deg_sqrt_h, m_s_sqrt_h, mg, ug, DEG};
use super::{AccelerometerSpec, GyroscopeSpec, ImuModel, ImuSpec, NoiseModel};
use crate::geodesy::wgs84::STANDARD_GRAVITY_M_S2 as G0;
use crate::random::Rng;
use crate::{Error, Result};

/// The preset a `navigate` run's tuning and a data sheet's left-out terms
/// start from when none is named: real logs come from consumer-grade IMUs.
pub const DEFAULT_PRESET: &str = "consumer";

/// The names [`preset_spec`] and `ImuModel::preset` accept.
pub const PRESET_NAMES: [&str; 5] = [
    "paper-mems",
    "consumer",
    "industrial",
    "tactical",
    "navigation",
];

impl ImuModel {
    /// A named preset drawn at [`super::DEFAULT_SAMPLE_RATE_HZ`] (method
    /// §1); names in [`PRESET_NAMES`], figures and sources in this module.
    pub fn preset(name: &str, rng: &mut Rng) -> Result<Self> {
        Self::preset_at(name, super::DEFAULT_SAMPLE_RATE_HZ, rng)
    }

    /// A named preset drawn at `sample_rate_hz`.
    pub fn preset_at(name: &str, sample_rate_hz: f64, rng: &mut Rng) -> Result<Self> {
        Self::from_spec(&preset_spec(name)?, sample_rate_hz, rng)
    }
}

/// The spec of a named preset; unknown names are an error naming `name`.
pub fn preset_spec(name: &str) -> Result<ImuSpec> {
    match name {
        "paper-mems" => Ok(paper_mems()),
        "consumer" => Ok(consumer()),
        "industrial" => Ok(industrial()),
        "tactical" => Ok(tactical()),
        "navigation" => Ok(navigation()),
        other => Err(Error::invalid(
            "name",
            format!(
                "unknown preset '{other}'; expected one of {}",
                PRESET_NAMES
                    .iter()
                    .map(|n| format!("'{n}'"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )),
    }
}

/// `"paper-mems"`: the MEMS IMU of de Boer et al. (ION GNSS 2008), method §2.
///
/// Magnitudes from the paper (g and °/s converted with g0 = 9.80665 m/s²):
/// b_a 1e-2 g, D_a 1e-5, M_a 1e-2, N_a 1e-5 /g; b_g 1e-2 °/s, D_g 1e-4,
/// M_g 1e-2, K_g 1e-3 (°/s)/g. The paper gives no noise level: white
/// noise is set *per sample* to 3e-3 g ≈ 0.0294 m/s² (accelerometer) and
/// 0.03 °/s (gyro), chosen so the model-inversion MSE lands near the
/// paper's ≈ 1e-5 g² and ≈ 1e-3 (°/s)² (fig. 11-12; the inversion filters
/// track the signal and leave about one noise variance, 9e-6 g² and
/// 9e-4 (°/s)²). At 100 Hz these are densities of 3e-4 g/√Hz and
/// 3e-3 °/s/√Hz. No bias instability, random walk or quantisation: the
/// paper models none.
pub fn paper_mems() -> ImuSpec {
    ImuSpec {
        accelerometer: AccelerometerSpec {
            bias_std: 1e-2 * G0,
            scale_factor_std: 1e-5,
            misalignment_std: 1e-2,
            nonlinearity_std: 1e-5 / G0,
            noise: NoiseModel {
                white_std: 3e-3 * G0,
                ..Default::default()
            },
        },
        gyroscope: GyroscopeSpec {
            bias_std: 1e-2 * DEG,
            scale_factor_std: 1e-4,
            misalignment_std: 1e-2,
            g_sensitivity_std: deg_s_per_g(1e-3),
            noise: NoiseModel {
                white_std: 0.03 * DEG,
                ..Default::default()
            },
        },
    }
}

/// `"consumer"`: a consumer/automotive MEMS IMU, figures of the Bosch
/// BMI088 data sheet (BST-BMI088-DS001, typical values) where it gives them.
///
/// Accelerometer: bias 20 mg (zero-g offset); scale factor and
/// cross-axis 1e-2 (Groves §4.4.2, MEMS upper range); nonlinearity 1e-4 /g
/// (assumed: ten times the paper's MEMS); noise density 175 µg/√Hz;
/// bias instability 0.1 mg with τ = 300 s (assumed; not in the data
/// sheet); no random walk; quantisation 0.183 mg (16 bits over ±6 g).
/// Gyroscope: bias 1 °/s (zero-rate offset; Groves table 4.2 gives more
/// than 100 °/h for this grade); scale factor and cross-axis 1e-2 (Groves
/// §4.4.2); g-sensitivity 0.05 (°/s)/g (assumed, typical of vibratory MEMS
/// gyros); noise density 0.014 °/s/√Hz; bias instability 2 °/h with
/// τ = 300 s (assumed); quantisation 0.0153 °/s (16 bits over ±500 °/s).
pub fn consumer() -> ImuSpec {
    ImuSpec {
        accelerometer: AccelerometerSpec {
            bias_std: mg(20.0),
            scale_factor_std: 1e-2,
            misalignment_std: 1e-2,
            nonlinearity_std: 1e-4 / G0,
            noise: NoiseModel {
                white_density: ug(175.0),
                bias_instability_std: mg(0.1),
                bias_correlation_time_s: 300.0,
                quantization: 12.0 * G0 / 65536.0,
                ..Default::default()
            },
        },
        gyroscope: GyroscopeSpec {
            bias_std: 1.0 * DEG,
            scale_factor_std: 1e-2,
            misalignment_std: 1e-2,
            g_sensitivity_std: deg_s_per_g(0.05),
            noise: NoiseModel {
                white_density: 0.014 * DEG,
                bias_instability_std: deg_h(2.0),
                bias_correlation_time_s: 300.0,
                quantization: 1000.0 * DEG / 65536.0,
                ..Default::default()
            },
        },
    }
}

/// `"industrial"`: a factory-calibrated industrial MEMS IMU, figures of the
/// Analog Devices ADIS16465-1 data sheet where it gives them.
///
/// Accelerometer: bias 2 mg (assumed: low end of Groves table 4.1's
/// tactical 1–10 mg, as calibrated industrial parts are); scale factor 1e-3
/// (assumed, Groves §4.4.2); misalignment 0.05° = 8.7e-4 rad (axis-to-axis
/// misalignment); nonlinearity 1e-5 /g (assumed, the paper's MEMS value);
/// velocity random walk 0.037 m/s/√h; bias instability 3.6 µg (in-run bias
/// stability) with τ = 1000 s (assumed); no quantisation (32-bit outputs).
/// Gyroscope: bias 0.05 °/s = 180 °/h (assumed: Groves table 4.2, MEMS
/// above the tactical range); scale factor 1e-3 (assumed); misalignment
/// 8.7e-4; g-sensitivity 0.005 (°/s)/g (assumed; the part compensates its
/// linear-acceleration effect); angle random walk 0.15 °/√h; bias
/// instability 2 °/h (in-run bias stability) with τ = 1000 s (assumed).
pub fn industrial() -> ImuSpec {
    let misalignment = 0.05 * DEG;
    ImuSpec {
        accelerometer: AccelerometerSpec {
            bias_std: mg(2.0),
            scale_factor_std: 1e-3,
            misalignment_std: misalignment,
            nonlinearity_std: 1e-5 / G0,
            noise: NoiseModel {
                white_density: m_s_sqrt_h(0.037),
                bias_instability_std: ug(3.6),
                bias_correlation_time_s: 1000.0,
                ..Default::default()
            },
        },
        gyroscope: GyroscopeSpec {
            bias_std: 0.05 * DEG,
            scale_factor_std: 1e-3,
            misalignment_std: misalignment,
            g_sensitivity_std: deg_s_per_g(0.005),
            noise: NoiseModel {
                white_density: deg_sqrt_h(0.15),
                bias_instability_std: deg_h(2.0),
                bias_correlation_time_s: 1000.0,
                ..Default::default()
            },
        },
    }
}

/// `"tactical"`: the paper's "INS", a tactical-grade IMU; figures of the
/// Honeywell HG1700 (AG58) product sheet where it gives them.
///
/// Accelerometer: bias 1 mg (Groves table 4.1 tactical: 1–10 mg); scale
/// factor 300 ppm; misalignment 1e-4 (assumed, low end of Groves §4.4.2);
/// nonlinearity 1e-6 /g (assumed); velocity random walk 0.065 ft/s/√h
/// = 3.3e-4 m/s²/√Hz; bias instability 0.05 mg with τ = 3600 s (assumed);
/// no quantisation. Gyroscope (ring laser): bias 1 °/h (Groves table 4.2
/// tactical: 1–100 °/h); scale factor 150 ppm; misalignment 1e-4
/// (assumed); no g-sensitivity (optical gyro, Groves); angle random walk
/// 0.125 °/√h; bias instability 0.1 °/h with τ = 3600 s (assumed).
pub fn tactical() -> ImuSpec {
    ImuSpec {
        accelerometer: AccelerometerSpec {
            bias_std: mg(1.0),
            scale_factor_std: 300e-6,
            misalignment_std: 1e-4,
            nonlinearity_std: 1e-6 / G0,
            noise: NoiseModel {
                white_density: 0.065 * 0.3048 / 60.0,
                bias_instability_std: mg(0.05),
                bias_correlation_time_s: 3600.0,
                ..Default::default()
            },
        },
        gyroscope: GyroscopeSpec {
            bias_std: deg_h(1.0),
            scale_factor_std: 150e-6,
            misalignment_std: 1e-4,
            g_sensitivity_std: 0.0,
            noise: NoiseModel {
                white_density: deg_sqrt_h(0.125),
                bias_instability_std: deg_h(0.1),
                bias_correlation_time_s: 3600.0,
                ..Default::default()
            },
        },
    }
}

/// `"navigation"`: a navigation-grade IMU; figures of the Honeywell HG9900
/// product sheet where it gives them.
///
/// Accelerometer: bias 25 µg (Groves table 4.1: aviation grade 30–100 µg);
/// scale factor 100 ppm; misalignment 1e-5 (assumed); no nonlinearity;
/// noise density 10 µg/√Hz (assumed; the sheet lists none); bias
/// instability 5 µg with τ = 3600 s (assumed). Gyroscope (ring laser):
/// bias 0.0035 °/h (Groves table 4.2 aviation: ≈ 0.01 °/h); scale factor
/// 5 ppm; misalignment 1e-5 (assumed); no g-sensitivity (optical); angle
/// random walk 0.002 °/√h; bias instability 0.001 °/h with τ = 3600 s
/// (assumed).
pub fn navigation() -> ImuSpec {
    ImuSpec {
        accelerometer: AccelerometerSpec {
            bias_std: ug(25.0),
            scale_factor_std: 100e-6,
            misalignment_std: 1e-5,
            nonlinearity_std: 0.0,
            noise: NoiseModel {
                white_density: ug(10.0),
                bias_instability_std: ug(5.0),
                bias_correlation_time_s: 3600.0,
                ..Default::default()
            },
        },
        gyroscope: GyroscopeSpec {
            bias_std: deg_h(0.0035),
            scale_factor_std: 5e-6,
            misalignment_std: 1e-5,
            g_sensitivity_std: 0.0,
            noise: NoiseModel {
                white_density: deg_sqrt_h(0.002),
                bias_instability_std: deg_h(0.001),
                bias_correlation_time_s: 3600.0,
                ..Default::default()
            },
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;
    use crate::sensors::ImuModel;

    #[test]
    fn every_preset_is_valid_and_ordered_by_grade() {
        for name in PRESET_NAMES {
            preset_spec(name).unwrap().validate().unwrap();
        }
        // Better grades have smaller biases and noise (Groves tables 4.1-4.2).
        let grades =
            ["consumer", "industrial", "tactical", "navigation"].map(|n| preset_spec(n).unwrap());
        for w in grades.windows(2) {
            assert!(w[1].accelerometer.bias_std < w[0].accelerometer.bias_std);
            assert!(w[1].gyroscope.bias_std < w[0].gyroscope.bias_std);
            assert!(w[1].gyroscope.noise.white_density < w[0].gyroscope.noise.white_density);
        }
    }

    #[test]
    fn the_tactical_velocity_random_walk() {
        // 0.065 ft/s/√h = 3.302e-4 m/s/√s.
        assert!((tactical().accelerometer.noise.white_density - 3.302e-4).abs() < 1e-7);
        assert!((paper_mems().accelerometer.noise.white_std - 0.0294).abs() < 1e-4);
    }

    #[test]
    fn unknown_preset_names_the_argument_and_lists_the_choices() {
        let e = ImuModel::preset("mems", &mut stream(0, 0))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("name: unknown preset 'mems'; expected one of 'paper-mems'"),
            "{e}"
        );
    }

    #[test]
    fn drawn_terms_have_the_spec_magnitudes() {
        let spec = paper_mems();
        let n = 2000;
        let (mut b, mut m, mut k) = (0.0, 0.0, 0.0);
        for i in 0..n {
            let imu = ImuModel::preset("paper-mems", &mut stream(11, i)).unwrap();
            b += imu.accelerometer.bias.norm_squared();
            m += imu.gyroscope.misalignment.norm_squared();
            k += imu.gyroscope.g_sensitivity.norm_squared();
            assert_eq!(
                imu.gyroscope.misalignment.diagonal(),
                nalgebra::Vector3::zeros()
            );
        }
        let rel = |sum: f64, count: f64, sigma: f64| (sum / count).sqrt() / sigma - 1.0;
        let n = n as f64;
        assert!(rel(b, 3.0 * n, spec.accelerometer.bias_std).abs() < 0.03);
        assert!(rel(m, 6.0 * n, spec.gyroscope.misalignment_std).abs() < 0.03);
        assert!(rel(k, 9.0 * n, spec.gyroscope.g_sensitivity_std).abs() < 0.03);
    }
}
