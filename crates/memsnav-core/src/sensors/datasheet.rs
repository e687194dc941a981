//! An [`ImuSpec`] from a data sheet, in the units data sheets use: the
//! `[imu_spec]` table of a `navigate` configuration and
//! `mn.imu_spec_from_datasheet`. Each key names its quantity and its unit
//! ([`DATASHEET_KEYS`]); a quantity may be given in one of its units, and a
//! term the table leaves out keeps the base spec's (a preset's).
//!
//! The conversions (`super::units`) are exact unit changes, with one
//! modelling rule, for the bias instability:
//!
//! - A data sheet's *in-run bias stability* (bias instability) is the floor
//!   F of the Allan deviation (IEEE Std 952-1997 annex C; Analog Devices
//!   and Xsens define it so). memsnav models the bias instability as a
//!   first-order Gauss-Markov process (σ_β, τ_β) in the simulator, the
//!   filter and the Allan fit alike. Its Allan deviation has a single
//!   maximum, 0.6174 σ_β at T = 1.8926 τ_β ([`crate::gauss_markov`]), so
//!   the process whose curve reaches the floor has σ_β = F / 0.6174 =
//!   1.62 F. (IEEE 952's flicker coefficient B = F / 0.664, often taken as
//!   σ_β, gives a process whose curve peaks 7 % below the floor.) τ_β is
//!   not on data sheets: the table needs it with an instability
//!   (`*_bias_correlation_time_s`); from an Allan plot whose floor lies at
//!   T_F it is T_F / 1.89.
//! - `*_bias_markov_std_*` gives σ_β itself (a model you already have: an
//!   Allan fit's, a preset's).
//! - A turn-on bias (bias repeatability, zero-g / zero-rate offset), a
//!   scale-factor error (sensitivity tolerance), a misalignment (each
//!   off-diagonal element; a cross-axis sensitivity of x % is x/100 rad)
//!   are one-sigma values: a data sheet's "±" figure is taken as one sigma,
//!   as the presets take it.

use super::units::{
    deg_h, deg_h_sqrt_h, deg_s, deg_s_per_g, deg_sqrt_h, m_s_sqrt_h, mg, percent, ppm, seconds, ug,
    ug_per_g2, DEG,
};
use super::ImuSpec;
use crate::gauss_markov::ALLAN_PEAK_PER_STD;
use crate::limits::MAX_SENSOR_MAGNITUDE;
use crate::{validate, Error, Result};

/// The configuration table holding the keys, and the prefix of the names
/// their errors give (`imu_spec.gyro_arw_deg_sqrt_h`).
pub const TABLE: &str = "imu_spec";

/// One data-sheet key: its name (quantity and unit), the [`ImuSpec`]
/// field it sets (the flat name of [`ImuSpec::fields`]), the conversion of
/// its value to the field's SI unit, and what it holds.
#[derive(Debug, Clone, Copy)]
pub struct DatasheetKey {
    /// The key, with its unit (`gyro_arw_deg_sqrt_h`).
    pub key: &'static str,
    /// The [`ImuSpec`] field it sets, by its flat name.
    pub field: &'static str,
    /// Converts the key's value to the field's SI unit.
    pub to_si: fn(f64) -> f64,
    /// What it holds, for the key list (`navigate::KEYS`).
    pub description: &'static str,
}

/// σ_β of the Gauss-Markov process whose Allan deviation peaks at the floor
/// `floor` (module docs).
fn markov_std_of_floor(floor: f64) -> f64 {
    floor / ALLAN_PEAK_PER_STD
}

fn floor_ug(x: f64) -> f64 {
    markov_std_of_floor(ug(x))
}

fn floor_mg(x: f64) -> f64 {
    markov_std_of_floor(mg(x))
}

fn floor_deg_h(x: f64) -> f64 {
    markov_std_of_floor(deg_h(x))
}

/// Acceleration random walk µg/√s → m/s²/√s.
fn ug_sqrt_s(x: f64) -> f64 {
    ug(x)
}

/// Misalignment in degrees → rad.
fn degrees(x: f64) -> f64 {
    x * DEG
}

const fn key(
    key: &'static str,
    field: &'static str,
    to_si: fn(f64) -> f64,
    description: &'static str,
) -> DatasheetKey {
    DatasheetKey {
        key,
        field,
        to_si,
        description,
    }
}

/// Number of data-sheet keys.
const KEY_COUNT: usize = 26;

/// Every data-sheet key (module docs for the rules).
pub const DATASHEET_KEYS: [DatasheetKey; KEY_COUNT] = [
    key("accel_noise_density_ug_sqrt_hz", "accel_noise_density", ug,
        "accelerometer white noise (velocity random walk) as a density, ug/sqrt(Hz); x 1e-6 g0"),
    key("accel_vrw_m_s_sqrt_h", "accel_noise_density", m_s_sqrt_h,
        "velocity random walk, m/s/sqrt(h); / 60 = m/s/sqrt(s)"),
    key("accel_bias_instability_ug", "accel_bias_instability", floor_ug,
        "in-run bias stability (the Allan deviation's floor F), ug; Gauss-Markov std = F / 0.6174"),
    key("accel_bias_instability_mg", "accel_bias_instability", floor_mg,
        "the same in mg"),
    key("accel_bias_markov_std_ug", "accel_bias_instability", ug,
        "the Gauss-Markov bias std itself (an Allan fit's, a preset's), ug"),
    key("accel_bias_correlation_time_s", "accel_bias_correlation_time", seconds,
        "its correlation time, s (needed with an instability)"),
    key("accel_bias_random_walk_ug_sqrt_s", "accel_bias_random_walk", ug_sqrt_s,
        "acceleration random walk, ug/sqrt(s)"),
    key("accel_turn_on_bias_mg", "accel_bias_std", mg,
        "turn-on bias (bias repeatability, zero-g offset) one-sigma, mg"),
    key("accel_scale_factor_ppm", "accel_scale_factor_std", ppm,
        "scale-factor error one-sigma, ppm"),
    key("accel_scale_factor_pct", "accel_scale_factor_std", percent,
        "the same in % (sensitivity tolerance)"),
    key("accel_misalignment_deg", "accel_misalignment_std", degrees,
        "axis misalignment one-sigma, deg"),
    key("accel_cross_axis_pct", "accel_misalignment_std", percent,
        "the same as a cross-axis sensitivity, %"),
    key("accel_nonlinearity_ug_g2", "accel_nonlinearity_std", ug_per_g2,
        "second-order nonlinearity one-sigma, ug/g^2"),
    key("gyro_noise_density_deg_s_sqrt_hz", "gyro_noise_density", deg_s,
        "gyro white noise (angle random walk) as a density, deg/s/sqrt(Hz)"),
    key("gyro_arw_deg_sqrt_h", "gyro_noise_density", deg_sqrt_h,
        "angle random walk, deg/sqrt(h); / 60 = deg/sqrt(s)"),
    key("gyro_bias_instability_deg_h", "gyro_bias_instability", floor_deg_h,
        "in-run bias stability (the Allan deviation's floor F), deg/h; Gauss-Markov std = F / 0.6174"),
    key("gyro_bias_markov_std_deg_h", "gyro_bias_instability", deg_h,
        "the Gauss-Markov bias std itself (an Allan fit's, a preset's), deg/h"),
    key("gyro_bias_correlation_time_s", "gyro_bias_correlation_time", seconds,
        "its correlation time, s (needed with an instability)"),
    key("gyro_bias_random_walk_deg_h_sqrt_h", "gyro_bias_random_walk", deg_h_sqrt_h,
        "rate random walk, deg/h/sqrt(h)"),
    key("gyro_turn_on_bias_deg_s", "gyro_bias_std", deg_s,
        "turn-on bias (bias repeatability, zero-rate offset) one-sigma, deg/s"),
    key("gyro_turn_on_bias_deg_h", "gyro_bias_std", deg_h,
        "the same in deg/h"),
    key("gyro_scale_factor_ppm", "gyro_scale_factor_std", ppm,
        "scale-factor error one-sigma, ppm"),
    key("gyro_scale_factor_pct", "gyro_scale_factor_std", percent,
        "the same in % (sensitivity tolerance)"),
    key("gyro_misalignment_deg", "gyro_misalignment_std", degrees,
        "axis misalignment one-sigma, deg"),
    key("gyro_cross_axis_pct", "gyro_misalignment_std", percent,
        "the same as a cross-axis sensitivity, %"),
    key("gyro_g_sensitivity_deg_s_g", "gyro_g_sensitivity_std", deg_s_per_g,
        "g-sensitivity (linear-acceleration effect) one-sigma, (deg/s)/g"),
];

/// The name an error gives for `key`.
fn name(key: &str) -> String {
    format!("{TABLE}.{key}")
}

/// The data-sheet key `key`.
pub fn datasheet_key(key: &str) -> Result<&'static DatasheetKey> {
    DATASHEET_KEYS.iter().find(|k| k.key == key).ok_or_else(|| {
        let known: Vec<&str> = DATASHEET_KEYS.iter().map(|k| k.key).collect();
        let hint = crate::known_keys::closest(key, &known)
            .map(|k| format!(" (did you mean {k:?}?)"))
            .unwrap_or_default();
        Error::invalid(
            name(key),
            format!("unknown key{hint}; [{TABLE}] takes {}", known.join(", ")),
        )
    })
}

/// `value_si` of a field in the unit of data-sheet key `key` (the inverse
/// of its linear conversion).
pub fn in_key_unit(key: &str, value_si: f64) -> Result<f64> {
    Ok(value_si / (datasheet_key(key)?.to_si)(1.0))
}

impl ImuSpec {
    /// `base` with the data-sheet figures `entries` (key, value in the
    /// key's unit; module docs). Each value must be finite and
    /// non-negative (a correlation time positive), a dimensionless one-sigma
    /// below 1 (100 %), every other one within the specs' limit; one key
    /// per quantity; an instability with its correlation time. Errors name
    /// `imu_spec.key`.
    pub fn from_datasheet(base: &ImuSpec, entries: &[(String, f64)]) -> Result<ImuSpec> {
        let mut spec = *base;
        let mut given: Vec<&DatasheetKey> = Vec::new();
        for (key, value) in entries {
            let k = datasheet_key(key)?;
            if let Some(other) = given.iter().find(|g| g.field == k.field) {
                return Err(Error::invalid(
                    name(key),
                    format!(
                        "gives the same quantity as {}; give one of them",
                        name(other.key)
                    ),
                ));
            }
            given.push(k);
            if k.field.ends_with("correlation_time") {
                validate::positive(&name(key), *value)?;
            } else {
                validate::non_negative(&name(key), *value)?;
            }
            let si = (k.to_si)(*value);
            if k.field.ends_with("scale_factor_std") || k.field.ends_with("misalignment_std") {
                if si >= 1.0 {
                    return Err(Error::invalid(
                        name(key),
                        format!("{value} is a one-sigma of 100 % (1 rad) or more"),
                    ));
                }
            } else {
                validate::at_most(&name(key), si, MAX_SENSOR_MAGNITUDE / 10.0)?;
            }
            let mut fields = spec.fields_mut();
            let (_, field) = fields
                .iter_mut()
                .find(|(f, _)| *f == k.field)
                .expect("every data-sheet key sets a spec field");
            **field = si;
        }
        for prefix in ["accel", "gyro"] {
            let instability = given
                .iter()
                .find(|g| g.field == format!("{prefix}_bias_instability"));
            let time = given
                .iter()
                .any(|g| g.field == format!("{prefix}_bias_correlation_time"));
            let value = |key: &str| entries.iter().find(|(k, _)| k == key).map(|(_, v)| *v);
            if let Some(k) = instability {
                if !time && value(k.key) != Some(0.0) {
                    return Err(Error::invalid(
                        name(&format!("{prefix}_bias_correlation_time_s")),
                        format!(
                            "is needed with {} (data sheets do not give it; an Allan plot whose floor lies at T gives T / 1.89)",
                            name(k.key)
                        ),
                    ));
                }
            }
        }
        spec.validate()?;
        Ok(spec)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensors::presets::consumer;

    fn entries(pairs: &[(&str, f64)]) -> Vec<(String, f64)> {
        pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect()
    }

    fn bad(base: &ImuSpec, pairs: &[(&str, f64)]) -> String {
        ImuSpec::from_datasheet(base, &entries(pairs))
            .unwrap_err()
            .to_string()
    }

    /// The ADIS16465-1 figures of docs/reference/configuration.md's worked example,
    /// converted by hand: ARW 0.15 °/√h = 0.0025 °/√s = 4.3633e-5 rad/√s;
    /// VRW 0.037 m/s/√h = 6.1667e-4 m/s/√s; gyro in-run bias stability
    /// 2 °/h → σ_β = 2/0.617364 = 3.23958 °/h = 1.57058e-5 rad/s; accel
    /// 3.6 µg → σ_β = 5.83124 µg = 5.71850e-5 m/s²; misalignment 0.05° =
    /// 8.72665e-4 rad.
    #[test]
    fn a_data_sheet_in_its_own_units() {
        let spec = ImuSpec::from_datasheet(
            &ImuSpec::default(),
            &entries(&[
                ("gyro_arw_deg_sqrt_h", 0.15),
                ("gyro_bias_instability_deg_h", 2.0),
                ("gyro_bias_correlation_time_s", 100.0),
                ("gyro_misalignment_deg", 0.05),
                ("accel_vrw_m_s_sqrt_h", 0.037),
                ("accel_bias_instability_ug", 3.6),
                ("accel_bias_correlation_time_s", 100.0),
            ]),
        )
        .unwrap();
        let (a, g) = (&spec.accelerometer, &spec.gyroscope);
        let close = |x: f64, y: f64| (x / y - 1.0).abs() < 1e-5;
        assert!(close(g.noise.white_density, 4.3633e-5));
        assert!(close(g.noise.bias_instability_std, 1.57058e-5));
        assert!(close(a.noise.white_density, 6.16667e-4));
        assert!(close(a.noise.bias_instability_std, 5.71850e-5));
        assert!(close(g.misalignment_std, 8.72665e-4));
        assert_eq!(g.noise.bias_correlation_time_s, 100.0);
        // Left out: the base's (here nothing).
        assert_eq!((a.bias_std, g.scale_factor_std), (0.0, 0.0));
    }

    /// The consumer preset written as a data sheet is the preset, bit for
    /// bit (the same unit functions): what lets `[imu_spec]` replace
    /// `imu_preset` with identical results. Quantisation is not a
    /// data-sheet key (the filter does not use it).
    #[test]
    fn the_consumer_preset_as_a_data_sheet_is_the_preset() {
        let spec = ImuSpec::from_datasheet(
            &ImuSpec::default(),
            &entries(&[
                ("accel_turn_on_bias_mg", 20.0),
                ("accel_scale_factor_pct", 1.0),
                ("accel_cross_axis_pct", 1.0),
                ("accel_nonlinearity_ug_g2", 100.0),
                ("accel_noise_density_ug_sqrt_hz", 175.0),
                ("accel_bias_markov_std_ug", 100.0),
                ("accel_bias_correlation_time_s", 300.0),
                ("gyro_turn_on_bias_deg_s", 1.0),
                ("gyro_scale_factor_pct", 1.0),
                ("gyro_cross_axis_pct", 1.0),
                ("gyro_g_sensitivity_deg_s_g", 0.05),
                ("gyro_noise_density_deg_s_sqrt_hz", 0.014),
                ("gyro_bias_markov_std_deg_h", 2.0),
                ("gyro_bias_correlation_time_s", 300.0),
            ]),
        )
        .unwrap();
        let mut preset = consumer();
        preset.accelerometer.noise.quantization = 0.0;
        preset.gyroscope.noise.quantization = 0.0;
        assert_eq!(spec, preset);
    }

    #[test]
    fn each_key_is_checked_and_named() {
        let base = consumer();
        assert!(bad(&base, &[("gyro_arw", 0.1)])
            .starts_with("imu_spec.gyro_arw: unknown key (did you mean \"gyro_arw_deg_sqrt_h\"?); [imu_spec] takes accel_noise_density"));
        assert_eq!(
            bad(&base, &[("gyro_arw_deg_sqrt_h", -0.1)]),
            "imu_spec.gyro_arw_deg_sqrt_h: must be finite and non-negative, got -0.1"
        );
        assert!(bad(&base, &[("accel_vrw_m_s_sqrt_h", f64::NAN)])
            .starts_with("imu_spec.accel_vrw_m_s_sqrt_h: must be finite"));
        assert_eq!(
            bad(
                &base,
                &[
                    ("gyro_arw_deg_sqrt_h", 0.1),
                    ("gyro_noise_density_deg_s_sqrt_hz", 0.01)
                ]
            ),
            "imu_spec.gyro_noise_density_deg_s_sqrt_hz: gives the same quantity as \
             imu_spec.gyro_arw_deg_sqrt_h; give one of them"
        );
        assert!(bad(&base, &[("gyro_bias_instability_deg_h", 10.0)]).starts_with(
            "imu_spec.gyro_bias_correlation_time_s: is needed with imu_spec.gyro_bias_instability_deg_h"
        ));
        assert!(bad(&base, &[("accel_bias_correlation_time_s", 0.0)])
            .starts_with("imu_spec.accel_bias_correlation_time_s: must be finite and positive"));
        assert!(bad(&base, &[("gyro_scale_factor_pct", 100.0)])
            .starts_with("imu_spec.gyro_scale_factor_pct: 100 is a one-sigma of 100 %"));
        assert!(bad(&base, &[("accel_turn_on_bias_mg", 1e12)])
            .starts_with("imu_spec.accel_turn_on_bias_mg: "));
        // A zero instability needs no correlation time.
        let off = ImuSpec::from_datasheet(&base, &entries(&[("accel_bias_instability_ug", 0.0)]));
        assert_eq!(off.unwrap().accelerometer.noise.bias_instability_std, 0.0);
    }

    /// Every key sets a field of the spec, linearly (its inverse is
    /// `in_key_unit`), and the descriptions follow the keys.
    #[test]
    fn every_key_sets_a_field_linearly() {
        let fields: Vec<&str> = ImuSpec::default().fields().map(|(f, _)| f).to_vec();
        for k in &DATASHEET_KEYS {
            assert!(fields.contains(&k.field), "{}", k.field);
            assert!(
                ((k.to_si)(3.0) / (k.to_si)(1.0) - 3.0).abs() < 1e-12,
                "{}",
                k.key
            );
            assert!((in_key_unit(k.key, (k.to_si)(2.5)).unwrap() - 2.5).abs() < 1e-12);
        }
    }
}
