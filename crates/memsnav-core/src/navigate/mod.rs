//! Navigation of a real IMU/GNSS log: the engine behind `memsnav navigate`.
//!
//! [`navigate_log`] takes the raw IMU series (sensor axes, on GNSS time)
//! and the GNSS input (fixes for loose coupling, pseudoranges for tight),
//! and does everything between them and a solution:
//!
//! 1. IMU into body axes ([`LogConfig::mounting`], [`mounting_matrix`]) and
//!    onto GNSS time ([`LogConfig::imu_time_offset_s`]);
//! 2. the start ([`align`]): static (levelled at rest, heading at the first
//!    motion) or in motion (heading from the course), and why it is late
//!    when it is;
//! 3. the scheduled outages ([`LogConfig::outages`], [`periodic_outages`]),
//!    in the log's own time (from its earliest possible start);
//! 4. the coupled filter with the lever arm in its measurement models, its
//!    batch tests, fault exclusion and resets (see [`crate::coupling`]),
//!    and at every IMU sample the aids ([`AidsConfig`]): ZUPT and ZARU at
//!    standstills ([`standstill`]), the non-holonomic constraint of land
//!    vehicles, the heading from the first motion;
//! 5. the solution at the antenna in geodetic, NED and Euler terms
//!    ([`output`]), and its errors against a truth ([`score`]) moved to
//!    the antenna and into the GNSS's datum ([`truth`]);
//! 6. from a (smoothed) solution, the GNSS-derived references that
//!    calibrate the IMU on the drive itself ([`references`], method §3).

pub mod adapt;
mod aids;
pub mod align;
pub mod carrier_use;
mod config;
mod filter_settings;
pub mod fixes;
pub mod gyro_scale;
pub mod keys;
mod kinematics;
pub mod output;
pub mod references;
mod run;
pub mod score;
mod settings;
pub mod standstill;
pub mod truth;

pub use config::{
    mounting_matrix, periodic_outages, AidsConfig, AlignmentConfig, AlignmentMethod, LogConfig,
    StandstillConfig, StartOverrides,
};
pub use filter_settings::FilterSettings;
pub use fixes::{fixes_from_geodetic, FixOptions, GeodeticSolution};
pub use keys::{tables, SettingTables, SettingValue, AUTO, KEYS};
pub use kinematics::EpochKinematics;
pub use run::{navigate_log, sample_rate_hz, validate_gnss, GnssInput, LogRun, RunFailure};
