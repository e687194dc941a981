//! The filter a `navigate` configuration describes, for IMU and GNSS
//! arrays the caller has prepared (the Python filter classes): the same
//! tables, keys, checks and defaults as a log run ([`LogConfig::from_settings`]),
//! the same aids at every IMU sample ([`super::aids`]), minus what
//! prepares a log run (its start, its outages, the IMU's time and mounting).

use nalgebra::Vector3;

use super::aids::{HeadingUntilAligned, SampleAids};
use super::config::LogConfig;
use super::keys::{check_known_keys, SettingTables, SettingValue, AUTO};
use super::kinematics::EpochKinematics;
use super::settings::find;
use crate::coupling::{factory, FilterTuning, InitialState, Solution};
use crate::filter::state::{RangeBiasSlots, StateBlocks};
use crate::ins::{ImuData, ImuSample};
use crate::sensors::ImuSpec;
use crate::{Error, Result};

/// Tables that prepare a log run (its start, scheduled outages): a filter
/// on the caller's arrays starts where the caller says and uses the
/// epochs the caller gives it.
const LOG_RUN_TABLES: [(&str, &str); 2] = [
    ("alignment", "give initial_state or initial_attitude to run"),
    ("outages", "leave the epochs out of the GNSS arrays"),
];

/// Keys of the filter's tables that a log run reads for itself, with what
/// to do instead.
const LOG_RUN_KEYS: [(&str, &str, &str); 4] = [
    (
        "filter",
        "imu_preset",
        "the IMU model gives the spec; [imu_spec] keys adjust it",
    ),
    (
        "filter",
        "smoother",
        "ask for it with run(..., smooth=True)",
    ),
    ("imu", "time_offset_s", "add the offset to the time stamps"),
    (
        "imu",
        "mounting_rpy_deg",
        "rotate the samples into body axes (mounting_matrix)",
    ),
];

/// The filter of a configuration: its tuning and optional state blocks.
#[derive(Debug, Clone, PartialEq)]
pub struct FilterSettings {
    config: LogConfig,
}

impl FilterSettings {
    /// The filter `tables` describe for an IMU of `spec` sampled at
    /// `imu_rate_hz`: the tuning from the spec with the `[imu_spec]`
    /// figures over it, then every key applied as a log run applies it.
    /// A table or key that drives a log run, or a value a log run learns
    /// (`"auto"`), is an error naming it and saying what to do instead.
    pub fn from_settings(tables: &SettingTables, spec: &ImuSpec, imu_rate_hz: f64) -> Result<Self> {
        check_known_keys(tables)?;
        for (table, entries) in tables {
            if let Some((_, instead)) = LOG_RUN_TABLES.iter().find(|(t, _)| t == table) {
                return Err(Error::invalid(
                    table.clone(),
                    format!("drives a navigate run, not the filter: {instead}"),
                ));
            }
            for (key, value) in entries {
                if let Some((_, _, instead)) =
                    LOG_RUN_KEYS.iter().find(|(t, k, _)| t == table && k == key)
                {
                    return Err(Error::invalid(
                        format!("{table}.{key}"),
                        format!("is read by a navigate run, not the filter: {instead}"),
                    ));
                }
                if matches!(value, SettingValue::Text(text) if text == AUTO) {
                    return Err(Error::invalid(
                        format!("{table}.{key}"),
                        "\"auto\" is learnt from a whole log by a navigate run; give a value",
                    ));
                }
            }
        }
        let mut config = LogConfig::from_settings_with_spec(tables, imu_rate_hz, *spec)?;
        // A log run takes these from its start; here they are the filter's.
        let i = &mut config.tuning.initial_std;
        let o = config.alignment_overrides;
        i.position_m = o.position_std_m.unwrap_or(i.position_m);
        i.velocity_m_s = o.velocity_std_m_s.unwrap_or(i.velocity_m_s);
        if find(tables, "filter", "initial_attitude_std_deg").is_some() {
            let a = &config.alignment;
            i.attitude_ned_rad = Vector3::new(a.tilt_std_rad, a.tilt_std_rad, a.heading_std_rad);
        }
        if config.fix_error_states {
            let model = config.fix_error;
            config.tuning.set_range_bias_model(&model);
        }
        if config.aids.nhc && config.aids.nhc_std_learnt {
            return Err(Error::invalid(
                "aids.nhc_std_m_s",
                "is learnt from a whole log by a navigate run by default (\"auto\"); with \
                 aids.nhc give a value",
            ));
        }
        Ok(Self { config })
    }

    /// The forward solution (and with `smooth` the smoothed one) of the
    /// filter with `blocks` over `imu` and the aiding `epochs` from
    /// `initial`, with the configuration's aids at every IMU sample as a
    /// log run applies them: standstills found from the IMU window and
    /// the epochs' ground speed (the single-point solution of each epoch's
    /// pseudoranges, or the fixes) or, without a recent one, the
    /// solution's speed, with zero-velocity and zero-angular-rate updates
    /// there, and the non-holonomic constraint while moving. The heading
    /// is the initial state's.
    pub fn solve<E: EpochKinematics>(
        &self,
        blocks: StateBlocks,
        imu: &ImuData,
        epochs: &[E],
        initial: &InitialState,
        smooth: bool,
    ) -> Result<(Solution, Option<Solution>)> {
        let config = &self.config;
        let tuning = &config.tuning;
        if !self.has_aids() {
            return factory::solve(blocks, imu, epochs, initial, tuning, smooth);
        }
        imu.validate()?;
        let samples: Vec<ImuSample> = imu
            .specific_force_b
            .iter()
            .zip(imu.angular_rate_b)
            .map(|(f, w)| ImuSample {
                specific_force_b: *f,
                angular_rate_b: *w,
            })
            .collect();
        // As a log run reads them: with range-bias states the fixes'
        // covariance includes the biases.
        let bias_std_m = if blocks.range_biases == RangeBiasSlots::None {
            0.0
        } else {
            tuning.initial_std.range_bias_m
        };
        let kinematics = E::kinematics(epochs, bias_std_m);
        let used = vec![true; kinematics.len()];
        let aids = SampleAids::new(
            imu.time_s,
            &samples,
            &kinematics,
            &used,
            config,
            HeadingUntilAligned::KNOWN,
            config.aids.nhc_std_m_s,
        );
        factory::solve_aided(blocks, imu, epochs, initial, tuning, smooth, aids)
    }

    /// The aids that are on, by their `[aids]` key (`zupt`, `zaru`, `nhc`).
    pub fn aids(&self) -> Vec<&'static str> {
        let a = &self.config.aids;
        [(a.zupt, "zupt"), (a.zaru, "zaru"), (a.nhc, "nhc")]
            .into_iter()
            .filter_map(|(on, name)| on.then_some(name))
            .collect()
    }

    /// Whether any aid is on.
    pub fn has_aids(&self) -> bool {
        !self.aids().is_empty()
    }

    /// The tuning.
    pub fn tuning(&self) -> &FilterTuning {
        &self.config.tuning
    }

    /// Accelerometer and gyro scale-factor states (`filter.scale_factor_states`).
    pub fn scale_factor_states(&self) -> bool {
        self.config.scale_factor_states
    }

    /// The state blocks for pseudoranges (`tight`) or fixes, with
    /// inter-system biases when the pseudoranges need them.
    pub fn blocks(&self, tight: bool, inter_system_biases: bool) -> StateBlocks {
        self.config
            .state_blocks(tight, inter_system_biases, self.config.fix_error_states)
    }
}

impl LogConfig {
    /// The optional state blocks of a run of this configuration: scale
    /// factors and installation as configured, inter-system biases when
    /// the pseudoranges need them, and the range-bias slots: the
    /// configured ones for pseudoranges (`tight`), the shared ones for the
    /// fixes' position errors when `fix_error_states`.
    pub fn state_blocks(
        &self,
        tight: bool,
        inter_system_biases: bool,
        fix_error_states: bool,
    ) -> StateBlocks {
        StateBlocks {
            scale_factors: self.scale_factor_states,
            installation: self.installation_states,
            inter_system_biases,
            range_biases: match (tight, fix_error_states) {
                (true, _) => self.range_bias_states,
                (false, true) => RangeBiasSlots::Shared,
                (false, false) => RangeBiasSlots::None,
            },
        }
    }
}
