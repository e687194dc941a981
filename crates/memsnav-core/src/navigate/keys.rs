//! The keys of a `navigate` configuration's engine tables: what each
//! holds, the kind of value it takes (as `super::settings` reads it), and
//! the JSON schema of them (the reading keys' schema is the Python
//! package's; `memsnav schema` joins the two).

use serde_json::{json, Map, Value};

use crate::known_keys::closest;
use crate::sensors::datasheet::{DATASHEET_KEYS, TABLE as SPEC_TABLE};
use crate::sensors::presets::PRESET_NAMES;
use crate::{Error, Result};

/// A setting's value, as a configuration file holds it.
#[derive(Debug, Clone, PartialEq)]
pub enum SettingValue {
    /// A boolean.
    Bool(bool),
    /// A number (TOML integers and floats alike).
    Number(f64),
    /// A string.
    Text(String),
    /// An array.
    List(Vec<SettingValue>),
}

impl std::fmt::Display for SettingValue {
    /// As the configuration file writes it (`5`, `"text"`, `[1, 2]`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SettingValue::Bool(b) => write!(f, "{b}"),
            SettingValue::Number(v) => write!(f, "{v:?}"),
            SettingValue::Text(s) => write!(f, "{s:?}"),
            SettingValue::List(items) => {
                write!(f, "[")?;
                for (i, item) in items.iter().enumerate() {
                    write!(f, "{}{item}", if i > 0 { ", " } else { "" })?;
                }
                write!(f, "]")
            }
        }
    }
}

/// The value of `filter.imu_preset` and `gnss.fix_correlation_time_s`
/// that learns them from the log ([`super::adapt`]).
pub const AUTO: &str = "auto";

/// The value of `gnss.range_bias_states` that gives every satellite a
/// range-bias state ([`crate::filter::state::RangeBiasSlots::EverySatellite`]).
pub const EVERY_SATELLITE: &str = "every_satellite";

/// Settings as (table, [(key, value)]) pairs, in the file's order.
pub type SettingTables = Vec<(String, Vec<(String, SettingValue)>)>;

/// Settings from plain (table, key, value) triples, for Rust callers and tests.
pub fn tables(
    entries: &[(&str, &str, SettingValue)],
) -> Vec<(String, Vec<(String, SettingValue)>)> {
    let mut out: Vec<(String, Vec<(String, SettingValue)>)> = Vec::new();
    for (t, k, v) in entries {
        match out.iter_mut().find(|(name, _)| name == t) {
            Some((_, e)) => e.push((k.to_string(), v.clone())),
            None => out.push((t.to_string(), vec![(k.to_string(), v.clone())])),
        }
    }
    out
}

/// The kind of value a key takes: what the reader accepts before the
/// checks that need other keys (a window inside the run, a tilt std the
/// same for north and east).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ValueKind {
    /// true or false.
    Flag,
    /// A finite number within the bounds given.
    Number {
        /// Smallest value, when bounded below.
        minimum: Option<f64>,
        /// Whether the minimum itself is excluded.
        exclusive_minimum: bool,
        /// Largest value, when bounded above.
        maximum: Option<f64>,
        /// Whether the maximum itself is excluded.
        exclusive_maximum: bool,
    },
    /// A whole number within [minimum, maximum].
    Whole {
        /// Smallest value.
        minimum: i64,
        /// Largest value.
        maximum: i64,
    },
    /// An angle, deg, within one turn either way.
    AngleDeg,
    /// A one-sigma angle, deg, in (0, 180].
    AngleStdDeg,
    /// Three one-sigma angles, deg, each in (0, 180].
    AngleStdsDeg,
    /// Three finite numbers.
    Vector3,
    /// A list of [roll, pitch, yaw] triples, deg.
    Triples,
    /// A list of [start, length] pairs, s.
    Pairs,
    /// One of these strings.
    Choice(&'static [&'static str]),
    /// `"auto"` or an IMU preset's name.
    Preset,
    /// true, false or this string.
    FlagOr(&'static str),
    /// A positive number or this string.
    PositiveOr(&'static str),
}

/// Any finite number.
const ANY: ValueKind = ValueKind::Number {
    minimum: None,
    exclusive_minimum: false,
    maximum: None,
    exclusive_maximum: false,
};
/// A number above 0.
const POSITIVE: ValueKind = ValueKind::Number {
    minimum: Some(0.0),
    exclusive_minimum: true,
    maximum: None,
    exclusive_maximum: false,
};
/// A number of at least 0.
const NON_NEGATIVE: ValueKind = ValueKind::Number {
    minimum: Some(0.0),
    exclusive_minimum: false,
    maximum: None,
    exclusive_maximum: false,
};
/// A probability in (0, 1].
const PROBABILITY: ValueKind = ValueKind::Number {
    minimum: Some(0.0),
    exclusive_minimum: true,
    maximum: Some(1.0),
    exclusive_maximum: false,
};

/// Largest angle a key in degrees takes, in magnitude: one turn either
/// way. A larger one is a typo or an angle in another unit, not a heading
/// or a mounting rotation anyone means.
pub(super) const MAX_ANGLE_DEG: f64 = 360.0;

/// Largest one-sigma of an angle, deg: half a turn already says "unknown".
pub(super) const MAX_ANGLE_STD_DEG: f64 = 180.0;

impl ValueKind {
    /// The JSON schema of a value of this kind.
    pub fn json_schema(self) -> Value {
        let numbers = |n: usize| json!({"type": "array", "items": {"type": "number"}, "minItems": n, "maxItems": n});
        let angle_std =
            json!({"type": "number", "exclusiveMinimum": 0.0, "maximum": MAX_ANGLE_STD_DEG});
        match self {
            Self::Flag => json!({"type": "boolean"}),
            Self::Number {
                minimum,
                exclusive_minimum,
                maximum,
                exclusive_maximum,
            } => {
                let mut s = Map::new();
                s.insert("type".into(), "number".into());
                if let Some(m) = minimum {
                    let name = if exclusive_minimum {
                        "exclusiveMinimum"
                    } else {
                        "minimum"
                    };
                    s.insert(name.into(), m.into());
                }
                if let Some(m) = maximum {
                    let name = if exclusive_maximum {
                        "exclusiveMaximum"
                    } else {
                        "maximum"
                    };
                    s.insert(name.into(), m.into());
                }
                Value::Object(s)
            }
            Self::Whole { minimum, maximum } => {
                json!({"type": "integer", "minimum": minimum, "maximum": maximum})
            }
            Self::AngleDeg => {
                json!({"type": "number", "minimum": -MAX_ANGLE_DEG, "maximum": MAX_ANGLE_DEG})
            }
            Self::AngleStdDeg => angle_std,
            Self::AngleStdsDeg => {
                json!({"type": "array", "items": angle_std, "minItems": 3, "maxItems": 3})
            }
            Self::Vector3 => numbers(3),
            Self::Triples => json!({"type": "array", "items": numbers(3), "minItems": 1}),
            Self::Pairs => json!({"type": "array", "items": numbers(2)}),
            Self::Choice(choices) => json!({"enum": choices}),
            Self::Preset => {
                let mut names = vec![AUTO];
                names.extend(PRESET_NAMES);
                json!({"enum": names})
            }
            Self::FlagOr(text) => json!({"anyOf": [{"type": "boolean"}, {"const": text}]}),
            Self::PositiveOr(text) => {
                json!({"anyOf": [POSITIVE.json_schema(), {"const": text}]})
            }
        }
    }

    /// A value of this kind (the tests try one of every key's).
    pub fn example(self) -> SettingValue {
        let number = SettingValue::Number;
        let list = |v: &[f64]| SettingValue::List(v.iter().map(|&x| number(x)).collect());
        match self {
            Self::Flag | Self::FlagOr(_) => SettingValue::Bool(true),
            Self::Number {
                minimum, maximum, ..
            } => number(match (minimum, maximum) {
                (_, Some(max)) => 0.5 * (minimum.unwrap_or(0.0) + max),
                (Some(min), None) => min + 1.0,
                (None, None) => 0.5,
            }),
            Self::Whole { minimum, maximum } => number(((minimum + maximum) / 2) as f64),
            Self::AngleDeg => number(45.0),
            Self::AngleStdDeg => number(2.0),
            Self::PositiveOr(_) => number(0.5),
            Self::AngleStdsDeg => list(&[2.0, 2.0, 5.0]),
            Self::Vector3 => list(&[0.1, 0.2, 0.3]),
            Self::Triples => SettingValue::List(vec![list(&[0.0, 0.0, 90.0])]),
            Self::Pairs => SettingValue::List(vec![list(&[10.0, 5.0])]),
            Self::Choice(choices) => SettingValue::Text(choices[0].into()),
            Self::Preset => SettingValue::Text(PRESET_NAMES[0].into()),
        }
    }
}

/// One key of an engine table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Key {
    /// Its name.
    pub name: &'static str,
    /// The kind of value it takes.
    pub kind: ValueKind,
    /// What it holds, with its unit.
    pub description: &'static str,
}

impl Key {
    const fn new(name: &'static str, kind: ValueKind, description: &'static str) -> Self {
        Self {
            name,
            kind,
            description,
        }
    }
}

/// The `[imu_spec]` table's keys (the datasheet figures: none negative, a
/// correlation time above 0; [`crate::sensors::datasheet`] checks the rest).
const DATASHEET_KEYS_OF_SETTINGS: [Key; DATASHEET_KEYS.len()] = {
    let mut out = [Key::new("", ANY, ""); DATASHEET_KEYS.len()];
    let mut i = 0;
    while i < DATASHEET_KEYS.len() {
        let k = &DATASHEET_KEYS[i];
        let kind = if ends_with(k.field, "correlation_time") {
            POSITIVE
        } else {
            NON_NEGATIVE
        };
        out[i] = Key::new(k.key, kind, k.description);
        i += 1;
    }
    out
};

/// `text` ends with `suffix` (in a constant).
const fn ends_with(text: &str, suffix: &str) -> bool {
    let (t, s) = (text.as_bytes(), suffix.as_bytes());
    if s.len() > t.len() {
        return false;
    }
    let mut i = 0;
    while i < s.len() {
        if t[t.len() - s.len() + i] != s[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// The tables and keys the engine reads: each key's kind of value and
/// what it holds.
pub const KEYS: &[(&str, &[Key])] = &[
    (
        "imu",
        &[
            Key::new("time_offset_s", ANY, "added to the IMU time stamps, s"),
            Key::new("mounting_rpy_deg", ValueKind::Triples, "list of [roll, pitch, yaw] sensor-to-body rotations, deg"),
            Key::new("lever_arm_m", ValueKind::Vector3, "IMU position from the vehicle reference point, body axes (forward, right, down), m"),
            Key::new("time_offset_std_s", POSITIVE, "prior std of the time offset as a state ([filter] installation_states), s"),
            Key::new("mounting_std_deg", ValueKind::AngleStdDeg, "prior std of the mounting boresight as a state, deg"),
        ],
    ),
    (
        "gnss",
        &[
            Key::new("antenna_lever_arm_m", ValueKind::Vector3, "antenna position from the vehicle reference point, body axes, m"),
            Key::new("antenna_lever_arm_std_m", POSITIVE, "prior std of the antenna lever arm as a state ([filter] installation_states), m per axis"),
            Key::new("velocity_latency_s", ANY, "latency of the fixes' velocity, s"),
            Key::new("velocity_latency_std_s", POSITIVE, "prior std of the velocity latency as a state, s"),
            Key::new("use_pseudorange_rate", ValueKind::Flag, "use Doppler (tight coupling)"),
            Key::new("carrier_phase", ValueKind::Flag, "use the carrier phase's change between epochs (tight coupling)"),
            Key::new("receiver_clock", ValueKind::Choice(&["tcxo", "ocxo", "consumer"]), "oscillator class: \"tcxo\", \"ocxo\", \"consumer\""),
            Key::new("range_bias_states", ValueKind::FlagOr(EVERY_SATELLITE), "per-satellite pseudorange-bias states (tight coupling): true (default: 12 slots held by the satellites used most recently, the rest count their bias variance as noise), false, \"every_satellite\" (40 slots: a state for every satellite of a multi-system receiver)"),
            Key::new("range_bias_std_m", POSITIVE, "their steady-state std, m"),
            Key::new("range_bias_correlation_time_s", POSITIVE, "their correlation time, s"),
            Key::new("fix_error_states", ValueKind::FlagOr(AUTO), "Gauss-Markov states for the fixes' position errors (loose coupling): true (with the two keys below), false (white), \"auto\" (default: learnt from the log)"),
            Key::new("fix_error_std_m", POSITIVE, "their steady-state std, m"),
            Key::new("fix_error_correlation_time_s", POSITIVE, "their correlation time, s"),
            Key::new("fix_correlation_time_s", NON_NEGATIVE, "correlation time of the fixes' position errors, s, matched by inflating their covariance instead of states (loose coupling); default 0: white"),
        ],
    ),
    (
        "filter",
        &[
            Key::new("imu_preset", ValueKind::Preset, "IMU class the tuning starts from: \"auto\" (default: the most likely of \"consumer\", \"industrial\" and \"tactical\" given the log), \"consumer\", \"industrial\", \"tactical\", \"navigation\", \"paper-mems\""),
            Key::new("accel_noise_density", NON_NEGATIVE, "accelerometer white noise, m/s/sqrt(s)"),
            Key::new("gyro_noise_density_deg", NON_NEGATIVE, "gyro white noise, deg/sqrt(s)"),
            Key::new("accel_bias_std", POSITIVE, "initial accelerometer bias std, m/s^2"),
            Key::new("gyro_bias_std_deg_s", POSITIVE, "initial gyro bias std, deg/s"),
            Key::new("accel_bias_instability", NON_NEGATIVE, "Gauss-Markov accelerometer bias std, m/s^2"),
            Key::new("gyro_bias_instability_deg_s", NON_NEGATIVE, "Gauss-Markov gyro bias std, deg/s"),
            Key::new("bias_correlation_time_s", POSITIVE, "their correlation time, s"),
            Key::new("initial_position_std_m", POSITIVE, "overrides the start's position std, m"),
            Key::new("initial_velocity_std_m_s", POSITIVE, "overrides the start's velocity std, m/s"),
            Key::new("initial_attitude_std_deg", ValueKind::AngleStdsDeg, "[tilt, tilt, heading] stds after alignment, deg"),
            Key::new("gate_probability", PROBABILITY, "probability of the chi-square test of each batch (1: no test)"),
            Key::new("scale_factor_states", ValueKind::Flag, "accelerometer and gyro scale-factor states"),
            Key::new("installation_states", ValueKind::Flag, "the antenna lever arm, IMU time offset, velocity latency and mounting boresight as states"),
            Key::new("accel_scale_factor_std_ppm", POSITIVE, "accelerometer scale-factor prior std (the states' initial std, else the noise that absorbs them), ppm"),
            Key::new("gyro_scale_factor_std_ppm", POSITIVE, "gyro scale-factor prior std, ppm"),
            Key::new("smoother", ValueKind::Flag, "also the fixed-interval smoothed solution (post-processing)"),
            Key::new("pseudorange_std_floor_m", NON_NEGATIVE, "smallest pseudorange std believed, m"),
            Key::new("pseudorange_rate_std_floor_m_s", NON_NEGATIVE, "smallest pseudorange-rate std, m/s"),
            Key::new("position_std_floor_m", NON_NEGATIVE, "smallest position-fix std, m"),
            Key::new("velocity_std_floor_m_s", NON_NEGATIVE, "smallest velocity-fix std, m/s"),
            Key::new("carrier_phase_std_floor_m", NON_NEGATIVE, "smallest std of a carrier change between epochs, m"),
            Key::new("pseudorange_correlation_time_s", NON_NEGATIVE, "correlation time of the code errors: their stds are inflated to match, s"),
            Key::new("reset_after_failed_epochs", ValueKind::Whole { minimum: 1, maximum: 1_000_000 }, "failed epochs in a row before a reset"),
            Key::new("reset_fading_factor", ValueKind::Number { minimum: Some(1.0), exclusive_minimum: false, maximum: Some(1e6), exclusive_maximum: false }, "whole covariance multiplied when resets follow each other with no accepted batch (1: off)"),
            Key::new("clock_jump_sigma", POSITIVE, "common innovation taken for a clock jump, in stds"),
            Key::new("max_excluded_share", ValueKind::Number { minimum: Some(0.0), exclusive_minimum: false, maximum: Some(1.0), exclusive_maximum: true }, "largest share of a batch fault exclusion may drop"),
        ],
    ),
    (SPEC_TABLE, &DATASHEET_KEYS_OF_SETTINGS),
    (
        "alignment",
        &[
            Key::new("method", ValueKind::Choice(&["auto", "static", "gnss_velocity"]), "\"auto\" (static or moving start), \"static\" (needs heading_deg), \"gnss_velocity\" (moving start only)"),
            Key::new("min_speed_m_s", POSITIVE, "speed from which the GNSS course gives the heading, m/s"),
            Key::new("max_course_std_deg", ValueKind::AngleStdDeg, "largest course std an alignment accepts, deg"),
            Key::new("level_window_s", POSITIVE, "levelling window before a moving start, s"),
            Key::new("heading_deg", ValueKind::AngleDeg, "known heading for a static start, deg"),
            Key::new("heading_std_deg", ValueKind::AngleStdDeg, "heading std after alignment, deg"),
            Key::new("tilt_std_deg", ValueKind::AngleStdDeg, "roll/pitch std after levelling, deg"),
        ],
    ),
    (
        "standstill",
        &[
            Key::new("window_s", POSITIVE, "detector window, s"),
            Key::new("accel_std_m_s2", POSITIVE, "largest specific-force spread at rest, m/s^2"),
            Key::new("gyro_std_deg_s", POSITIVE, "largest angular-rate spread at rest, deg/s"),
            Key::new("gnss_speed_m_s", POSITIVE, "largest GNSS speed at rest, m/s"),
            Key::new("gnss_age_s", POSITIVE, "oldest GNSS velocity used, s"),
            Key::new("solution_speed_m_s", POSITIVE, "largest solution speed at rest without GNSS, m/s"),
            Key::new("solution_speed_sigmas", NON_NEGATIVE, "without GNSS, also at rest when the solution's speed is within this many of its along-track sigma"),
        ],
    ),
    (
        "aids",
        &[
            Key::new("zupt", ValueKind::Flag, "zero-velocity updates at standstills"),
            Key::new("zupt_std_m_s", POSITIVE, "their std, m/s"),
            Key::new("zupt_interval_s", POSITIVE, "their interval, s"),
            Key::new("zaru", ValueKind::Flag, "zero-angular-rate updates at standstills"),
            Key::new("zaru_min_std_deg_s", POSITIVE, "their smallest std, deg/s"),
            Key::new("nhc", ValueKind::Flag, "non-holonomic constraint (land vehicles)"),
            Key::new("nhc_std_m_s", ValueKind::PositiveOr(AUTO), "its std, m/s; \"auto\" (default) chooses 0.1, 0.2 or 0.4 m/s from the log"),
            Key::new("nhc_interval_s", POSITIVE, "its interval, s"),
            Key::new("nhc_min_speed_m_s", NON_NEGATIVE, "lowest speed it applies at, m/s"),
        ],
    ),
    (
        "outages",
        &[
            Key::new("windows_s", ValueKind::Pairs, "list of [start, length], s; start after the log's first GNSS epoch with standstill.window_s of IMU data before it (the earliest start, not the start the alignment finds); a window not inside the run is an error naming it"),
            Key::new("first_s", NON_NEGATIVE, "periodic outages: start of the first, s after that same epoch (default every_s - length_s); the windows that fit in the run are kept"),
            Key::new("length_s", POSITIVE, "periodic outages: length, s"),
            Key::new("every_s", POSITIVE, "periodic outages: period, s"),
            Key::new("keep_satellites", ValueKind::Whole { minimum: 0, maximum: 3 }, "0 (default): total outages; 1-3: partial outages that keep the highest satellites of each epoch (tight coupling)"),
        ],
    ),
];

/// The keys of `table`, or an error naming it and the tables there are.
fn table_keys(table: &str) -> Result<&'static [Key]> {
    KEYS.iter()
        .find(|(t, _)| *t == table)
        .map(|(_, keys)| *keys)
        .ok_or_else(|| {
            let tables: Vec<&str> = KEYS.iter().map(|(t, _)| *t).collect();
            let hint = closest(table, &tables)
                .map(|t| format!(" (did you mean [{t}]?)"))
                .unwrap_or_default();
            Error::invalid(
                table,
                format!("unknown table{hint}; expected one of {}", tables.join(", ")),
            )
        })
}

/// Every table and key of `tables` is one [`KEYS`] lists, or an error
/// naming it, the closest known name and what its table takes.
pub(super) fn check_known_keys(tables: &[(String, Vec<(String, SettingValue)>)]) -> Result<()> {
    for (table, entries) in tables {
        let known: Vec<&str> = table_keys(table)?.iter().map(|k| k.name).collect();
        for (key, _) in entries {
            if !known.contains(&key.as_str()) {
                let hint = closest(key, &known)
                    .map(|k| format!(" (did you mean {k:?}?)"))
                    .unwrap_or_default();
                return Err(Error::invalid(
                    format!("{table}.{key}"),
                    format!("unknown key{hint}; [{table}] takes {}", known.join(", ")),
                ));
            }
        }
    }
    Ok(())
}

/// The JSON schema of the engine's tables: an object per table whose
/// properties are its keys (with their descriptions), and no others.
pub fn json_schema() -> Value {
    let tables: Map<String, Value> = KEYS
        .iter()
        .map(|(table, keys)| {
            let properties: Map<String, Value> = keys
                .iter()
                .map(|k| {
                    let mut schema = k.kind.json_schema();
                    schema["description"] = k.description.into();
                    (k.name.to_string(), schema)
                })
                .collect();
            (
                table.to_string(),
                json!({"type": "object", "properties": properties, "additionalProperties": false}),
            )
        })
        .collect();
    Value::Object(tables)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::navigate::config::LogConfig;

    /// Keys a value of their own is not enough for: (table, key) and the
    /// other settings it needs.
    fn partners(table: &str, key: &str) -> Vec<(&'static str, &'static str, SettingValue)> {
        let n = SettingValue::Number;
        match (table, key) {
            ("filter", "accel_bias_instability" | "gyro_bias_instability_deg_s") => {
                vec![("filter", "bias_correlation_time_s", n(300.0))]
            }
            ("imu_spec", k)
                if k.starts_with("accel_bias_instability")
                    || k.starts_with("accel_bias_markov") =>
            {
                vec![("imu_spec", "accel_bias_correlation_time_s", n(300.0))]
            }
            ("imu_spec", k)
                if k.starts_with("gyro_bias_instability") || k.starts_with("gyro_bias_markov") =>
            {
                vec![("imu_spec", "gyro_bias_correlation_time_s", n(300.0))]
            }
            ("outages", "first_s" | "length_s" | "every_s") => vec![
                ("outages", "length_s", n(10.0)),
                ("outages", "every_s", n(60.0)),
            ],
            _ => Vec::new(),
        }
    }

    /// A value of another kind than `kind` takes.
    fn wrong(kind: ValueKind) -> SettingValue {
        match kind {
            ValueKind::Flag | ValueKind::FlagOr(_) => SettingValue::Number(1.0),
            _ => SettingValue::Text("not this".into()),
        }
    }

    /// The reader takes an example of every key's kind (with the keys it
    /// needs) and refuses a value of another kind, naming `table.key`;
    /// the values at a number's bounds are the schema's (in or out).
    #[test]
    fn every_key_takes_its_kind_and_refuses_another() {
        for (table, keys) in KEYS {
            for k in *keys {
                let mut entries = partners(table, k.name);
                entries.retain(|(_, key, _)| *key != k.name);
                entries.push((table, k.name, k.kind.example()));
                LogConfig::from_settings(&tables(&entries), 100.0)
                    .unwrap_or_else(|e| panic!("{table}.{}: {e}", k.name));
                let bad = tables(&[(table, k.name, wrong(k.kind))]);
                let e = LogConfig::from_settings(&bad, 100.0)
                    .unwrap_err()
                    .to_string();
                assert!(e.contains(&format!("{table}.{}", k.name)), "{e}");
                if let ValueKind::Number {
                    minimum: Some(m),
                    exclusive_minimum,
                    ..
                } = k.kind
                {
                    let mut at = partners(table, k.name);
                    at.retain(|(_, key, _)| *key != k.name);
                    at.push((table, k.name, SettingValue::Number(m)));
                    let taken = LogConfig::from_settings(&tables(&at), 100.0).is_ok();
                    assert_eq!(taken, !exclusive_minimum, "{table}.{} at {m}", k.name);
                }
            }
        }
    }

    /// The schema holds every table and key, each with its description and
    /// no other key.
    #[test]
    fn the_schema_lists_every_key() {
        let schema = json_schema();
        for (table, keys) in KEYS {
            let t = &schema[*table];
            assert_eq!(t["additionalProperties"], false);
            let properties = t["properties"].as_object().unwrap();
            assert_eq!(properties.len(), keys.len(), "{table}");
            for k in *keys {
                assert_eq!(properties[k.name]["description"], k.description);
            }
        }
        assert_eq!(
            schema["gnss"]["properties"]["range_bias_states"]["anyOf"][1]["const"],
            EVERY_SATELLITE
        );
    }

    /// A misspelt key or table is refused with the name probably meant.
    #[test]
    fn a_misspelt_name_is_refused_with_the_closest() {
        let e = check_known_keys(&tables(&[(
            "filter",
            "gate_probabilty",
            SettingValue::Number(0.9),
        )]))
        .unwrap_err()
        .to_string();
        assert!(e.contains("did you mean \"gate_probability\""), "{e}");
        let e = check_known_keys(&tables(&[("filtr", "x", SettingValue::Bool(true))]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("did you mean [filter]"), "{e}");
    }
}
