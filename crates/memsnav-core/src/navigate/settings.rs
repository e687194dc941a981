//! A [`LogConfig`] from named settings (the tables of a `navigate`
//! configuration file): every key the engine understands, its unit, and
//! the checks, in one place. A key left out keeps the default of
//! [`LogConfig`]; an unknown key or a value of the wrong kind is an error
//! naming `table.key`.

use nalgebra::Vector3;

use super::adapt::IMU_CANDIDATES;
use super::config::{mounting_matrix, AlignmentMethod, LogConfig};
use super::keys::{
    check_known_keys, SettingValue, AUTO, EVERY_SATELLITE, MAX_ANGLE_DEG, MAX_ANGLE_STD_DEG,
};
use crate::coupling::{BiasProcess, FilterTuning};
use crate::filter::state::RangeBiasSlots;
use crate::gnss::ReceiverClockModel;
use crate::sensors::datasheet::{datasheet_key, TABLE as SPEC_TABLE};
use crate::sensors::presets::{preset_spec, DEFAULT_PRESET};
use crate::sensors::ImuSpec;
use crate::{validate, Error, Result};

/// The `[filter]` keys that set a quantity an `[imu_spec]` key gives too
/// (the spec field), refused together: the table describes the IMU, the
/// `[filter]` key overrides the tuning made from it, and two values for one
/// quantity would leave the reader guessing which holds.
const SPEC_OVERRIDES: [(&str, &str); 10] = [
    ("accel_noise_density", "accel_noise_density"),
    ("gyro_noise_density_deg", "gyro_noise_density"),
    ("accel_bias_std", "accel_bias_std"),
    ("gyro_bias_std_deg_s", "gyro_bias_std"),
    ("accel_bias_instability", "accel_bias_instability"),
    ("gyro_bias_instability_deg_s", "gyro_bias_instability"),
    ("bias_correlation_time_s", "accel_bias_correlation_time"),
    ("bias_correlation_time_s", "gyro_bias_correlation_time"),
    ("accel_scale_factor_std_ppm", "accel_scale_factor_std"),
    ("gyro_scale_factor_std_ppm", "gyro_scale_factor_std"),
];

/// Reads a value as the kind a key needs.
struct Reader<'a> {
    table: &'a str,
    key: &'a str,
    value: &'a SettingValue,
}

impl Reader<'_> {
    fn name(&self) -> String {
        format!("{}.{}", self.table, self.key)
    }

    fn wrong(&self, expected: &str) -> Error {
        Error::invalid(
            self.name(),
            format!("expected {expected}, got {}", self.value),
        )
    }

    /// `v` (entry `entry` of the key's list, if any) is within ±`max`, or
    /// an error saying it `must be` so.
    fn within(&self, v: f64, max: f64, must_be: &str, entry: Option<usize>) -> Result<f64> {
        if v.abs() <= max {
            return Ok(v);
        }
        let at = entry.map_or(String::new(), |i| format!("entry {i}: "));
        Err(Error::invalid(
            self.name(),
            format!("{at}must be {must_be}, got {v:?}"),
        ))
    }

    /// `v`, entry `entry` of the key (if a list), is an angle in degrees:
    /// within ±[`MAX_ANGLE_DEG`].
    fn angle(&self, v: f64, entry: Option<usize>) -> Result<f64> {
        self.within(v, MAX_ANGLE_DEG, "an angle within ±360°", entry)
    }

    /// `v`, entry `entry` of the key (if a list), is an angle's one-sigma in
    /// degrees: positive, at most [`MAX_ANGLE_STD_DEG`].
    fn angle_std(&self, v: f64, entry: Option<usize>) -> Result<f64> {
        // `v` is finite: read by `number` or `vector3`.
        if v <= 0.0 {
            let at = entry.map_or(String::new(), |i| format!("entry {i}: "));
            return Err(Error::invalid(
                self.name(),
                format!("{at}must be positive, got {v:?}"),
            ));
        }
        self.within(v, MAX_ANGLE_STD_DEG, "at most 180° (half a turn)", entry)
    }

    fn angle_deg(&self) -> Result<f64> {
        self.angle(self.number()?, None)
    }

    fn angle_std_deg(&self) -> Result<f64> {
        self.angle_std(self.number()?, None)
    }

    fn number(&self) -> Result<f64> {
        match self.value {
            SettingValue::Number(v) if v.is_finite() => Ok(*v),
            SettingValue::Number(v) => Err(Error::invalid(
                self.name(),
                format!("must be finite, got {v}"),
            )),
            _ => Err(self.wrong("a number")),
        }
    }

    fn positive(&self) -> Result<f64> {
        let v = self.number()?;
        validate::positive(&self.name(), v)?;
        Ok(v)
    }

    fn non_negative(&self) -> Result<f64> {
        let v = self.number()?;
        validate::non_negative(&self.name(), v)?;
        Ok(v)
    }

    fn flag(&self) -> Result<bool> {
        match self.value {
            SettingValue::Bool(b) => Ok(*b),
            _ => Err(self.wrong("true or false")),
        }
    }

    fn text(&self) -> Result<&str> {
        match self.value {
            SettingValue::Text(s) => Ok(s),
            _ => Err(self.wrong("a string")),
        }
    }

    fn numbers(value: &SettingValue, len: Option<usize>) -> Option<Vec<f64>> {
        let SettingValue::List(items) = value else {
            return None;
        };
        let v: Option<Vec<f64>> = items
            .iter()
            .map(|x| match x {
                SettingValue::Number(v) if v.is_finite() => Some(*v),
                _ => None,
            })
            .collect();
        v.filter(|v| len.is_none_or(|n| v.len() == n))
    }

    fn vector3(&self) -> Result<Vector3<f64>> {
        Self::numbers(self.value, Some(3))
            .map(|v| Vector3::new(v[0], v[1], v[2]))
            .ok_or_else(|| self.wrong("three finite numbers"))
    }

    fn pairs(&self, what: &str) -> Result<Vec<[f64; 2]>> {
        self.list_of(2, what)
            .map(|v| v.into_iter().map(|x| [x[0], x[1]]).collect())
    }

    fn triples(&self, what: &str) -> Result<Vec<[f64; 3]>> {
        self.list_of(3, what)
            .map(|v| v.into_iter().map(|x| [x[0], x[1], x[2]]).collect())
    }

    fn list_of(&self, n: usize, what: &str) -> Result<Vec<Vec<f64>>> {
        let SettingValue::List(items) = self.value else {
            return Err(self.wrong(what));
        };
        items
            .iter()
            .enumerate()
            .map(|(i, x)| {
                Self::numbers(x, Some(n)).ok_or_else(|| {
                    Error::invalid(
                        self.name(),
                        format!("entry {i}: expected {n} finite numbers ({what}), got {x}"),
                    )
                })
            })
            .collect()
    }
}

/// The value of `table.key` in `tables`, when given.
pub(super) fn find<'a>(
    tables: &'a [(String, Vec<(String, SettingValue)>)],
    table: &str,
    key: &str,
) -> Option<&'a SettingValue> {
    tables
        .iter()
        .filter(|(t, _)| t == table)
        .flat_map(|(_, e)| e.iter())
        .find(|(k, _)| k == key)
        .map(|(_, v)| v)
}

/// The IMU's filter tuning and the overrides that need each other.
#[derive(Default)]
struct Pending {
    accel_instability: Option<f64>,
    gyro_instability: Option<f64>,
    correlation_time: Option<f64>,
    imu_lever: Option<Vector3<f64>>,
    antenna_lever: Option<Vector3<f64>>,
    heading_deg: Option<f64>,
    method: Option<String>,
    periodic: [Option<f64>; 3],
}

impl LogConfig {
    /// The configuration of `tables` (table name, keys and values): the
    /// IMU spec of `filter.imu_preset` with the `[imu_spec]` figures over
    /// it, the tuning from that spec ([`FilterTuning::from_imu_spec`]) at
    /// the IMU's `imu_rate_hz`, then every other key applied over the
    /// defaults. `"auto"` (the default) builds one such configuration per
    /// candidate grade into `imu_candidates` (the log chooses;
    /// `navigate::adapt`), with the consumer grade's as the configuration.
    pub fn from_settings(
        tables: &[(String, Vec<(String, SettingValue)>)],
        imu_rate_hz: f64,
    ) -> Result<Self> {
        validate::positive("imu_rate_hz", imu_rate_hz)?;
        check_known_keys(tables)?;
        let preset = match find(tables, "filter", "imu_preset") {
            Some(v) => Reader {
                table: "filter",
                key: "imu_preset",
                value: v,
            }
            .text()?
            .to_string(),
            None => AUTO.into(),
        };
        if preset == AUTO {
            // One complete configuration per candidate grade, each built
            // from its preset and every other key as a named preset is.
            let mut candidates = Vec::with_capacity(IMU_CANDIDATES.len());
            for name in IMU_CANDIDATES {
                let c = Self::from_settings_with_preset(tables, imu_rate_hz, name)?;
                candidates.push((name.to_string(), c.tuning));
            }
            let mut config = Self::from_settings_with_preset(tables, imu_rate_hz, DEFAULT_PRESET)?;
            config.imu_candidates = candidates;
            return Ok(config);
        }
        Self::from_settings_with_preset(tables, imu_rate_hz, &preset)
    }

    /// [`Self::from_settings`] with the IMU spec of `preset`.
    fn from_settings_with_preset(
        tables: &[(String, Vec<(String, SettingValue)>)],
        imu_rate_hz: f64,
        preset: &str,
    ) -> Result<Self> {
        let spec =
            preset_spec(preset).map_err(|e| Error::invalid("filter.imu_preset", e.to_string()))?;
        Self::from_settings_with_spec(tables, imu_rate_hz, spec)
    }

    /// [`Self::from_settings`] from the IMU spec `spec` (the keys checked).
    pub(super) fn from_settings_with_spec(
        tables: &[(String, Vec<(String, SettingValue)>)],
        imu_rate_hz: f64,
        mut spec: ImuSpec,
    ) -> Result<Self> {
        let scale = match find(tables, "filter", "scale_factor_states") {
            Some(v) => Reader {
                table: "filter",
                key: "scale_factor_states",
                value: v,
            }
            .flag()?,
            None => false,
        };
        // The scale-factor priors enter the tuning itself (the states' P₀, or
        // the process noise that absorbs unmodelled scale factors), so they
        // are read before it is built, like the preset.
        for (key, triad) in [
            (
                "accel_scale_factor_std_ppm",
                &mut spec.accelerometer.scale_factor_std,
            ),
            (
                "gyro_scale_factor_std_ppm",
                &mut spec.gyroscope.scale_factor_std,
            ),
        ] {
            if let Some(value) = find(tables, "filter", key) {
                *triad = Reader {
                    table: "filter",
                    key,
                    value,
                }
                .positive()?
                    * 1e-6;
            }
        }
        let spec = Self::datasheet_spec(tables, &spec)?;
        let mut config = LogConfig::new(FilterTuning::from_imu_spec(&spec, imu_rate_hz, scale)?);
        config.scale_factor_states = scale;
        let mut pending = Pending::default();
        for (table, entries) in tables {
            for (key, value) in entries {
                let r = Reader { table, key, value };
                config.apply(&r, &mut pending)?;
            }
        }
        config.finish(pending)?;
        config.validate()?;
        Ok(config)
    }

    /// `base` with the `[imu_spec]` table's figures
    /// ([`ImuSpec::from_datasheet`]); a quantity given there and by a
    /// `[filter]` key too ([`SPEC_OVERRIDES`]) is an error naming both.
    fn datasheet_spec(
        tables: &[(String, Vec<(String, SettingValue)>)],
        base: &ImuSpec,
    ) -> Result<ImuSpec> {
        let entries = tables
            .iter()
            .filter(|(t, _)| t == SPEC_TABLE)
            .flat_map(|(_, e)| e.iter())
            .map(|(key, value)| {
                let r = Reader {
                    table: SPEC_TABLE,
                    key,
                    value,
                };
                Ok((key.clone(), r.number()?))
            })
            .collect::<Result<Vec<_>>>()?;
        let filter_keys = tables
            .iter()
            .filter(|(t, _)| t == "filter")
            .flat_map(|(_, e)| e.iter().map(|(k, _)| k.as_str()));
        for filter_key in filter_keys {
            for (key, _) in &entries {
                let field = datasheet_key(key)?.field;
                if SPEC_OVERRIDES.contains(&(filter_key, field)) {
                    return Err(Error::invalid(
                        format!("filter.{filter_key}"),
                        format!(
                            "sets what {SPEC_TABLE}.{key} gives; give one of them (the [{SPEC_TABLE}] \
                             figures describe the IMU, a [filter] key overrides the tuning made from them)"
                        ),
                    ));
                }
            }
        }
        ImuSpec::from_datasheet(base, &entries)
    }

    fn apply(&mut self, r: &Reader, p: &mut Pending) -> Result<()> {
        let t = &mut self.tuning;
        let q = &mut t.process_noise;
        let i = &mut t.initial_std;
        let deg = f64::to_radians;
        match (r.table, r.key) {
            ("imu", "time_offset_s") => self.imu_time_offset_s = r.number()?,
            ("imu", "mounting_rpy_deg") => {
                let triples = r.triples("roll, pitch, yaw")?;
                if triples.is_empty() {
                    // An empty chain would silently mean "no rotation".
                    return Err(r.wrong("at least one [roll, pitch, yaw] triple"));
                }
                for (i, t) in triples.iter().enumerate() {
                    for &angle in t {
                        r.angle(angle, Some(i))?;
                    }
                }
                let rad: Vec<[f64; 3]> = triples.iter().map(|t| t.map(deg)).collect();
                self.mounting = mounting_matrix(&rad)?;
            }
            ("imu", "lever_arm_m") => p.imu_lever = Some(r.vector3()?),
            ("imu", "time_offset_std_s") => i.installation.time_offset_s = r.positive()?,
            ("imu", "mounting_std_deg") => {
                i.installation.mounting_rad = deg(r.angle_std_deg()?);
            }
            ("gnss", "antenna_lever_arm_std_m") => i.installation.lever_arm_m = r.positive()?,
            ("gnss", "velocity_latency_std_s") => {
                i.installation.velocity_latency_s = r.positive()?;
            }
            ("gnss", "antenna_lever_arm_m") => p.antenna_lever = Some(r.vector3()?),
            ("gnss", "velocity_latency_s") => t.velocity_latency_s = r.number()?,
            ("gnss", "use_pseudorange_rate") => t.use_pseudorange_rate = r.flag()?,
            ("gnss", "carrier_phase") => t.use_carrier_phase = r.flag()?,
            ("gnss", "receiver_clock") => {
                let clock = ReceiverClockModel::oscillator(r.text()?)
                    .map_err(|e| Error::invalid(r.name(), e.to_string()))?;
                t.set_receiver_clock(&clock);
            }
            ("gnss", "range_bias_states") => {
                self.range_bias_states = match r.value {
                    SettingValue::Text(text) if text == EVERY_SATELLITE => {
                        RangeBiasSlots::EverySatellite
                    }
                    SettingValue::Bool(true) => RangeBiasSlots::Shared,
                    SettingValue::Bool(false) => RangeBiasSlots::None,
                    _ => return Err(r.wrong("true, false or \"every_satellite\"")),
                }
            }
            ("gnss", "range_bias_std_m") => {
                let s = r.positive()?;
                i.range_bias_m = s;
                q.range_bias_psd = 2.0 * s * s / q.range_bias_correlation_time_s;
            }
            ("gnss", "fix_error_states") => match r.value {
                SettingValue::Text(text) if text == AUTO => {
                    (self.learn_fix_errors, self.fix_error_states) = (true, false)
                }
                SettingValue::Bool(_) => {
                    (self.learn_fix_errors, self.fix_error_states) = (false, r.flag()?)
                }
                _ => return Err(r.wrong("true, false or \"auto\"")),
            },
            ("gnss", "fix_correlation_time_s") => t.fix_correlation_time_s = r.non_negative()?,
            ("gnss", "fix_error_std_m") => self.fix_error.std_m = r.positive()?,
            ("gnss", "fix_error_correlation_time_s") => {
                self.fix_error.correlation_time_s = r.positive()?
            }
            ("gnss", "range_bias_correlation_time_s") => {
                let tau = r.positive()?;
                q.range_bias_correlation_time_s = tau;
                q.range_bias_psd = 2.0 * i.range_bias_m.powi(2) / tau;
            }
            (
                "filter",
                "imu_preset"
                | "scale_factor_states"
                | "accel_scale_factor_std_ppm"
                | "gyro_scale_factor_std_ppm",
            ) => {}
            ("filter", "smoother") => self.smoother = r.flag()?,
            ("filter", "installation_states") => self.installation_states = r.flag()?,
            (SPEC_TABLE, _) => {}
            ("filter", "accel_noise_density") => q.accel_white_psd = r.non_negative()?.powi(2),
            ("filter", "gyro_noise_density_deg") => {
                q.gyro_white_psd = deg(r.non_negative()?).powi(2)
            }
            ("filter", "accel_bias_std") => i.accel_bias_m_s2 = r.positive()?,
            ("filter", "gyro_bias_std_deg_s") => i.gyro_bias_rad_s = deg(r.positive()?),
            ("filter", "accel_bias_instability") => p.accel_instability = Some(r.non_negative()?),
            ("filter", "gyro_bias_instability_deg_s") => {
                p.gyro_instability = Some(deg(r.non_negative()?))
            }
            ("filter", "bias_correlation_time_s") => p.correlation_time = Some(r.positive()?),
            ("filter", "initial_position_std_m") => {
                self.alignment_overrides.position_std_m = Some(r.positive()?)
            }
            ("filter", "initial_velocity_std_m_s") => {
                self.alignment_overrides.velocity_std_m_s = Some(r.positive()?)
            }
            ("filter", "initial_attitude_std_deg") => {
                let v = r.vector3()?;
                for (i, &std) in v.iter().enumerate() {
                    r.angle_std(std, Some(i))?;
                }
                if v.x != v.y {
                    return Err(Error::invalid(
                        r.name(),
                        format!("the filter takes one tilt std for north and east; got {v:?}"),
                    ));
                }
                self.alignment.tilt_std_rad = deg(v.x);
                self.alignment.heading_std_rad = deg(v.z);
            }
            ("filter", "gate_probability") => t.gate_probability = r.number()?,
            ("filter", "pseudorange_std_floor_m") => t.floor.pseudorange_m = r.non_negative()?,
            ("filter", "pseudorange_rate_std_floor_m_s") => {
                t.floor.pseudorange_rate_m_s = r.non_negative()?
            }
            ("filter", "position_std_floor_m") => t.floor.position_m = r.non_negative()?,
            ("filter", "velocity_std_floor_m_s") => t.floor.velocity_m_s = r.non_negative()?,
            ("filter", "pseudorange_correlation_time_s") => {
                t.pseudorange_correlation_time_s = r.non_negative()?
            }
            ("filter", "carrier_phase_std_floor_m") => {
                t.floor.carrier_phase_m = r.non_negative()?
            }
            ("filter", "reset_after_failed_epochs") => {
                let v = r.positive()?;
                if v.fract() != 0.0 || v > 1e6 {
                    return Err(Error::invalid(
                        r.name(),
                        format!("must be a whole number, got {v}"),
                    ));
                }
                t.recovery.reset_after_failed_epochs = v as usize;
            }
            ("filter", "clock_jump_sigma") => t.recovery.clock_jump_sigma = r.positive()?,
            ("filter", "reset_fading_factor") => t.recovery.fading_factor = r.positive()?,
            ("filter", "max_excluded_share") => t.recovery.max_excluded_share = r.non_negative()?,
            ("alignment", "method") => p.method = Some(r.text()?.to_string()),
            ("alignment", "min_speed_m_s") => self.alignment.min_speed_m_s = r.positive()?,
            ("alignment", "level_window_s") => self.alignment.level_window_s = r.positive()?,
            ("alignment", "max_course_std_deg") => {
                self.alignment.max_course_std_rad = deg(r.angle_std_deg()?)
            }
            ("alignment", "heading_deg") => p.heading_deg = Some(r.angle_deg()?),
            ("alignment", "heading_std_deg") => {
                self.alignment.heading_std_rad = deg(r.angle_std_deg()?)
            }
            ("alignment", "tilt_std_deg") => self.alignment.tilt_std_rad = deg(r.angle_std_deg()?),
            ("standstill", "window_s") => self.standstill.window_s = r.positive()?,
            ("standstill", "accel_std_m_s2") => self.standstill.accel_std_m_s2 = r.positive()?,
            ("standstill", "gyro_std_deg_s") => self.standstill.gyro_std_rad_s = deg(r.positive()?),
            ("standstill", "gnss_speed_m_s") => self.standstill.gnss_speed_m_s = r.positive()?,
            ("standstill", "gnss_age_s") => self.standstill.gnss_age_s = r.positive()?,
            ("standstill", "solution_speed_m_s") => {
                self.standstill.solution_speed_m_s = r.positive()?
            }
            ("standstill", "solution_speed_sigmas") => {
                self.standstill.solution_speed_sigmas = r.non_negative()?
            }
            ("aids", "zupt") => self.aids.zupt = r.flag()?,
            ("aids", "zupt_std_m_s") => self.aids.zupt_std_m_s = r.positive()?,
            ("aids", "zupt_interval_s") => self.aids.zupt_interval_s = r.positive()?,
            ("aids", "zaru") => self.aids.zaru = r.flag()?,
            ("aids", "zaru_min_std_deg_s") => self.aids.zaru_min_std_rad_s = deg(r.positive()?),
            ("aids", "nhc") => self.aids.nhc = r.flag()?,
            ("aids", "nhc_std_m_s") => match r.value {
                SettingValue::Text(text) if text == AUTO => self.aids.nhc_std_learnt = true,
                SettingValue::Number(_) => {
                    self.aids.nhc_std_m_s = r.positive()?;
                    self.aids.nhc_std_learnt = false;
                }
                _ => return Err(r.wrong("a std in m/s or \"auto\"")),
            },
            ("aids", "nhc_interval_s") => self.aids.nhc_interval_s = r.positive()?,
            ("aids", "nhc_min_speed_m_s") => self.aids.nhc_min_speed_m_s = r.non_negative()?,
            ("outages", "windows_s") => {
                self.outages = r
                    .pairs("start and length")?
                    .into_iter()
                    .map(|[s, l]| (s, l))
                    .collect()
            }
            ("outages", "keep_satellites") => {
                let v = r.non_negative()?;
                if v.fract() != 0.0 || v > 3.0 {
                    return Err(Error::invalid(
                        r.name(),
                        format!("must be 0 (a total outage), 1, 2 or 3, got {v}"),
                    ));
                }
                self.outage_satellites = v as usize;
            }
            ("outages", "first_s") => p.periodic[0] = Some(r.non_negative()?),
            ("outages", "length_s") => p.periodic[1] = Some(r.positive()?),
            ("outages", "every_s") => p.periodic[2] = Some(r.positive()?),
            _ => unreachable!("keys are checked against KEYS before they are applied"),
        }
        Ok(())
    }

    /// The settings that need others: the bias processes, the lever arms,
    /// the alignment method and the periodic outages.
    fn finish(&mut self, p: Pending) -> Result<()> {
        let q = &mut self.tuning.process_noise;
        if p.accel_instability.is_some() || p.gyro_instability.is_some() {
            let tau = p.correlation_time.ok_or_else(|| {
                Error::invalid(
                    "filter.bias_correlation_time_s",
                    "is needed with a bias instability",
                )
            })?;
            let i = &self.tuning.initial_std;
            let model = |initial_std: f64, instability_std: f64| {
                BiasProcess {
                    initial_std,
                    instability_std,
                    correlation_time_s: tau,
                    random_walk: 0.0,
                }
                .state_model()
            };
            if let Some(s) = p.accel_instability {
                (q.accel_bias_psd, q.accel_bias_correlation_time_s) = model(i.accel_bias_m_s2, s);
            }
            if let Some(s) = p.gyro_instability {
                (q.gyro_bias_psd, q.gyro_bias_correlation_time_s) = model(i.gyro_bias_rad_s, s);
            }
        }
        let imu = p.imu_lever.unwrap_or_else(Vector3::zeros);
        self.reference_from_imu_b_m = -imu;
        self.tuning.antenna_lever_arm_b_m = p.antenna_lever.unwrap_or(imu) - imu;
        self.alignment.method =
            match (p.method.as_deref(), p.heading_deg) {
                (None | Some("auto"), None) => AlignmentMethod::Auto,
                (Some("gnss_velocity"), None) => AlignmentMethod::Moving,
                (None | Some("static") | Some("auto"), Some(h)) => {
                    AlignmentMethod::StaticHeading(h.to_radians())
                }
                (Some("static"), None) => {
                    return Err(Error::invalid(
                        "alignment.heading_deg",
                        "is needed with alignment.method = \"static\"",
                    ))
                }
                (Some("gnss_velocity"), Some(_)) => return Err(Error::invalid(
                    "alignment.heading_deg",
                    "is for a static start; alignment.method = \"gnss_velocity\" takes the course",
                )),
                (Some(m), _) => {
                    return Err(Error::invalid(
                        "alignment.method",
                        format!("must be \"auto\", \"static\" or \"gnss_velocity\", got {m:?}"),
                    ))
                }
            };
        match p.periodic {
            [_, None, None] => {}
            [first, Some(length), Some(every)] => {
                self.periodic_outages = Some((first.unwrap_or(every - length), length, every));
            }
            _ => {
                return Err(Error::invalid(
                    "outages",
                    "periodic outages need both length_s and every_s",
                ))
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::navigate::keys::{tables, SettingTables};
    use SettingValue::*;

    /// The scale-factor priors seed the states' P₀ when the filter has them,
    /// and otherwise widen the noise that absorbs the unmodelled scale
    /// factors (a larger prior, a larger white-noise PSD).
    #[test]
    fn scale_factor_priors_reach_the_states_or_the_absorbed_noise() {
        let with_states = LogConfig::from_settings(
            &tables(&[
                ("filter", "scale_factor_states", Bool(true)),
                ("filter", "accel_scale_factor_std_ppm", Number(2000.0)),
                ("filter", "gyro_scale_factor_std_ppm", Number(5000.0)),
            ]),
            100.0,
        )
        .unwrap();
        let i = &with_states.tuning.initial_std;
        assert!((i.accel_scale_factor - 2e-3).abs() < 1e-15);
        assert!((i.gyro_scale_factor - 5e-3).abs() < 1e-15);
        let absorbed = |ppm: f64| {
            LogConfig::from_settings(
                &tables(&[("filter", "accel_scale_factor_std_ppm", Number(ppm))]),
                100.0,
            )
            .unwrap()
            .tuning
            .process_noise
            .input_errors
            .errors
            .accel_scale_factor
        };
        assert!((absorbed(20_000.0) - 2e-2).abs() < 1e-15);
        assert!((absorbed(100.0) - 1e-4).abs() < 1e-15);
        let err = LogConfig::from_settings(
            &tables(&[("filter", "gyro_scale_factor_std_ppm", Number(-1.0))]),
            100.0,
        )
        .unwrap_err()
        .to_string();
        assert!(err.starts_with("filter.gyro_scale_factor_std_ppm"), "{err}");
    }

    /// The consumer preset written as `[imu_spec]` figures is the
    /// configuration `imu_preset = "consumer"` gives, exactly: one path from
    /// a spec to the tuning.
    #[test]
    fn the_consumer_preset_as_imu_spec_is_the_consumer_preset() {
        let consumer = [
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
        ];
        let entries: Vec<_> = consumer
            .iter()
            .map(|(k, v)| ("imu_spec", *k, Number(*v)))
            .collect();
        let mut with_spec = entries.clone();
        with_spec.push(("filter", "imu_preset", Text("tactical".into())));
        let from_spec = LogConfig::from_settings(&tables(&with_spec), 100.0).unwrap();
        let preset = LogConfig::from_settings(
            &tables(&[("filter", "imu_preset", Text("consumer".into()))]),
            100.0,
        )
        .unwrap();
        assert_eq!(from_spec, preset);
    }

    /// A data-sheet key reaches the tuning converted (0.15 °/√h → white
    /// PSD (0.15 π/180/60)² rad²/s), a bad one names `imu_spec.key`, and a
    /// `[filter]` key saying the same is refused naming both.
    #[test]
    fn imu_spec_keys_reach_the_tuning_and_are_checked() {
        let c = LogConfig::from_settings(
            &tables(&[("imu_spec", "gyro_arw_deg_sqrt_h", Number(0.15))]),
            100.0,
        )
        .unwrap();
        let expected = (0.15f64.to_radians() / 60.0).powi(2);
        assert!((c.tuning.process_noise.gyro_white_psd / expected - 1.0).abs() < 1e-12);
        let bad = |e: SettingTables| LogConfig::from_settings(&e, 100.0).unwrap_err().to_string();
        assert_eq!(
            bad(tables(&[(
                "imu_spec",
                "gyro_arw_deg_sqrt_h",
                Text("0.1".into())
            )])),
            "imu_spec.gyro_arw_deg_sqrt_h: expected a number, got \"0.1\""
        );
        assert!(
            bad(tables(&[("imu_spec", "gyro_arw", Number(0.1))])).starts_with(
                "imu_spec.gyro_arw: unknown key (did you mean \"gyro_arw_deg_sqrt_h\"?); [imu_spec] takes"
            )
        );
        assert!(bad(tables(&[(
            "imu_spec",
            "accel_turn_on_bias_mg",
            Number(-2.0)
        )]))
        .starts_with("imu_spec.accel_turn_on_bias_mg: must be finite and non-negative"));
        assert!(bad(tables(&[
            ("imu_spec", "gyro_bias_instability_deg_h", Number(10.0)),
            ("imu_spec", "gyro_bias_correlation_time_s", Number(100.0)),
            ("filter", "bias_correlation_time_s", Number(300.0)),
        ]))
        .starts_with(
            "filter.bias_correlation_time_s: sets what imu_spec.gyro_bias_correlation_time_s gives"
        ));
        assert!(bad(tables(&[
            ("filter", "accel_scale_factor_std_ppm", Number(300.0)),
            ("imu_spec", "accel_scale_factor_pct", Number(0.1)),
        ]))
        .starts_with(
            "filter.accel_scale_factor_std_ppm: sets what imu_spec.accel_scale_factor_pct gives"
        ));
    }

    #[test]
    fn keys_apply_with_their_units_and_unknown_ones_are_refused() {
        let t = tables(&[
            (
                "imu",
                "lever_arm_m",
                List(vec![Number(0.0), Number(0.0), Number(-0.65)]),
            ),
            (
                "gnss",
                "antenna_lever_arm_m",
                List(vec![Number(0.0), Number(-0.05), Number(-0.65)]),
            ),
            ("filter", "gyro_noise_density_deg", Number(0.05)),
            ("filter", "gyro_bias_instability_deg_s", Number(0.01)),
            ("filter", "bias_correlation_time_s", Number(300.0)),
            ("alignment", "heading_deg", Number(90.0)),
            ("aids", "nhc", Bool(true)),
            ("outages", "length_s", Number(15.0)),
            ("outages", "every_s", Number(60.0)),
        ]);
        let c = LogConfig::from_settings(&t, 100.0).unwrap();
        assert!((c.tuning.antenna_lever_arm_b_m - Vector3::new(0.0, -0.05, 0.0)).norm() < 1e-15);
        assert!((c.reference_from_imu_b_m - Vector3::new(0.0, 0.0, 0.65)).norm() < 1e-15);
        let q = &c.tuning.process_noise;
        assert!((q.gyro_white_psd - 0.05f64.to_radians().powi(2)).abs() < 1e-18);
        assert!((q.gyro_bias_psd - 2.0 * 0.01f64.to_radians().powi(2) / 300.0).abs() < 1e-18);
        assert_eq!(
            c.alignment.method,
            AlignmentMethod::StaticHeading(90f64.to_radians())
        );
        assert!(c.aids.nhc);
        assert_eq!(c.periodic_outages, Some((45.0, 15.0, 60.0)));
        let bad = |e: SettingTables| LogConfig::from_settings(&e, 100.0).unwrap_err().to_string();
        assert!(
            bad(tables(&[("filter", "gyro_noise_density", Number(1.0))]))
                .starts_with("filter.gyro_noise_density: unknown key")
        );
        assert!(bad(tables(&[("filtre", "x", Number(1.0))])).starts_with("filtre: unknown table"));
        assert!(bad(tables(&[("aids", "zupt", Number(1.0))])).contains("expected true or false"));
        assert!(bad(tables(&[(
            "filter",
            "accel_bias_instability",
            Number(0.01)
        )]))
        .starts_with("filter.bias_correlation_time_s"));
        assert!(
            bad(tables(&[("alignment", "method", Text("static".into()))]))
                .starts_with("alignment.heading_deg")
        );
        assert!(bad(tables(&[(
            "outages",
            "windows_s",
            List(vec![List(vec![Number(1.0)])])
        )]))
        .contains("entry 0"));
        assert!(
            bad(tables(&[("filter", "imu_preset", Text("cheap".into()))]))
                .starts_with("filter.imu_preset")
        );
    }

    /// An empty mounting chain and angles beyond a turn were
    /// accepted (`mounting_rpy_deg = []` meant no rotation, `heading_deg =
    /// 1e300` some heading); every angle key now says so, naming itself.
    #[test]
    fn angles_are_within_a_turn_and_the_mounting_chain_is_not_empty() {
        let bad = |e: SettingTables| LogConfig::from_settings(&e, 100.0).unwrap_err().to_string();
        let triple = |a: f64| List(vec![Number(0.0), Number(a), Number(0.0)]);
        assert_eq!(
            bad(tables(&[("imu", "mounting_rpy_deg", List(vec![]))])),
            "imu.mounting_rpy_deg: expected at least one [roll, pitch, yaw] triple, got []"
        );
        assert_eq!(
            bad(tables(&[(
                "imu",
                "mounting_rpy_deg",
                List(vec![triple(1.0), triple(400.0)])
            )])),
            "imu.mounting_rpy_deg: entry 1: must be an angle within ±360°, got 400.0"
        );
        assert_eq!(
            bad(tables(&[("alignment", "heading_deg", Number(1e300))])),
            "alignment.heading_deg: must be an angle within ±360°, got 1e300"
        );
        assert_eq!(
            bad(tables(&[("alignment", "heading_std_deg", Number(1e300))])),
            "alignment.heading_std_deg: must be at most 180° (half a turn), got 1e300"
        );
        assert!(bad(tables(&[(
            "filter",
            "initial_attitude_std_deg",
            List(vec![Number(1.0), Number(1.0), Number(-1.0)])
        )]))
        .starts_with("filter.initial_attitude_std_deg: entry 2: must be positive"));
        assert_eq!(
            bad(tables(&[("gnss", "receiver_clock", Number(5.0))])),
            "gnss.receiver_clock: expected a string, got 5.0"
        );
        let turn = LogConfig::from_settings(
            &tables(&[
                ("imu", "mounting_rpy_deg", List(vec![triple(-360.0)])),
                ("alignment", "heading_deg", Number(360.0)),
            ]),
            100.0,
        );
        assert!(turn.is_ok());
    }
}
