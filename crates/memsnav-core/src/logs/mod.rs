//! Readers and writers of real sensor logs, one file per format: IMU CSV
//! logs with a declared column layout and units, RTKLIB time-tag files
//! (`.tag`), and GNSS fixes as RTKLIB solution files (`.pos`), a CSV of
//! named columns and NMEA 0183, all three read into one [`PosSolution`].
//! RINEX and SP3 live in [`crate::gnss`].
//!
//! Every reader checks each field it parses against a physical range and
//! names the file, the 1-based line, the column and the field in its
//! error ([`crate::Error::Parse`]; [`crate::Error::ParseBinary`] with the
//! byte offset for binary files). Values come out in SI units (s, m, m/s,
//! m/s², rad, rad/s). A line cut short at the end of a log (the recording
//! stopped mid-line) is skipped and reported in the result's `warnings`,
//! as are implausible but possible contents (units that do not fit the
//! magnitudes, gaps in time).

mod fields;
mod fixes_csv;
mod gnss_table;
mod gnsslogger;
mod imu_csv;
mod nmea;
mod pos_solution;
mod rtklib_pos;
mod time_tag;
mod ubx;

pub use fixes_csv::{
    parse_fixes_csv, read_fixes_csv, FixTimeReference, FixesCsvLayout, DEFAULT_CSV_QUALITY,
    FIXES_CSV_COLUMNS,
};
pub use gnss_table::{
    gnss_table_from_columns, parse_gnss_table, read_gnss_table, GnssTable, TableStds,
    GNSS_TABLE_OPTIONAL, GNSS_TABLE_REQUIRED,
};
pub use gnsslogger::{parse_gnsslogger, read_gnsslogger, GnssLoggerLog};
pub use imu_csv::{
    axes_from_name, parse_imu_csv, read_imu_csv, AccelUnit, GyroUnit, ImuColumns, ImuCsvLayout,
    ImuLog, ImuTiming, TimeUnit, AXES_NAMES, GAP_FACTOR, IMU_COLUMNS, MAX_ANGULAR_RATE_RAD_S,
    MAX_SPECIFIC_FORCE_M_S2, MAX_TIME_S,
};
pub use nmea::{
    parse_nmea, read_nmea, NMEA_RANGE_RATE_ERROR_M_S, NMEA_TALKERS, NMEA_UERE_M,
    NMEA_VDOP_PER_HDOP, NMEA_VELOCITY_STD_FLOOR_M_S,
};
pub use pos_solution::{diagonal_covariances, PosSolution, MAX_STD};
pub use rtklib_pos::{
    format_pos, parse_pos, read_pos, write_pos, MAX_SPEED_M_S, POS_HEIGHT_RANGE_M,
};
pub use time_tag::{parse_time_tag, read_time_tag, TimeTag, TIME_TAG_HEADER_BYTES};
pub use ubx::{parse_ubx, read_ubx, NavPvt, RawxEpoch, RawxSignal, TrackingStatus, UbxLog};

use std::path::Path;

use crate::{Error, Result};

/// The bytes of a file, or [`Error::Io`] naming it.
fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|e| Error::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    })
}
