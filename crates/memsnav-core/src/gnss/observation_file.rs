//! What a RINEX observation file holds, version 2 or 3 alike (the epochs
//! and each satellite's values), and the fields of its lines: shared by
//! the RINEX 3 reader ([`super::rinex_obs`]) and the RINEX 2 one
//! ([`super::rinex2_obs`]).

use std::collections::BTreeMap;

use nalgebra::Vector3;

use super::plausible::observation_range;
use super::time::checked_gps_time_from_calendar;
use super::utc::checked_gps_time_from_utc;

/// One satellite's observations at one epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct SatelliteObservations {
    /// System letter (`G` GPS, `E` Galileo, `R`, `C`, `J`, `S`, `I`).
    pub system: char,
    /// Satellite number within the system (PRN).
    pub prn: u16,
    /// One value per observation type of the system (header order); `None`
    /// where the field is blank. Units as in RINEX: m, cycles, Hz, dB-Hz.
    pub values: Vec<Option<f64>>,
    /// The loss-of-lock indicator of each value (RINEX 3.05 §5.7: bit 0
    /// lock lost since the previous epoch, bit 1 half-cycle ambiguity;
    /// 0 where blank).
    pub lli: Vec<u8>,
}

/// One epoch record (flag 0 or 1).
#[derive(Debug, Clone, PartialEq)]
pub struct ObservationEpoch {
    /// Reception time, GPS s since 1980-01-06 (the file's GPS time system).
    pub gps_time_s: f64,
    /// Epoch flag: 0 OK, 1 power failure since the previous epoch.
    pub flag: u8,
    /// The satellites of the record, in file order.
    pub satellites: Vec<SatelliteObservations>,
}

/// A RINEX 3 observation file.
#[derive(Debug, Clone, PartialEq)]
pub struct ObservationFile {
    /// Format version (3.xx).
    pub version: f64,
    /// Observation types per system letter, in header order (`C1C`, `D1C`, ...).
    pub observation_types: BTreeMap<char, Vec<String>>,
    /// `APPROX POSITION XYZ` of the header, ECEF m (absent or all zero: `None`).
    pub approx_position_ecef: Option<Vector3<f64>>,
    /// Epoch records in file order (special-event records skipped).
    pub epochs: Vec<ObservationEpoch>,
    /// Each GLONASS slot's FDMA frequency channel k of the header's
    /// `GLONASS SLOT / FRQ #` (G1 = 1602 + 0.5625 k MHz); empty without
    /// the record (RINEX 2 files have none).
    pub glonass_channels: BTreeMap<u16, i8>,
    /// Non-fatal problems (a truncated last record), one sentence each.
    pub warnings: Vec<String>,
    /// Records not read, by kind, with counts: event records (flags 2-5,
    /// their header lines not applied: [`event_kind`]), cycle-slip records
    /// (flag 6), RINEX 2 satellites of a system without observation codes.
    pub skipped: BTreeMap<String, usize>,
}

impl ObservationFile {
    /// Index of observation `code` (e.g. `"C1C"`) of `system`, if the header declares it.
    pub fn type_index(&self, system: char, code: &str) -> Option<usize> {
        self.observation_types
            .get(&system)?
            .iter()
            .position(|c| c == code)
    }
}

pub(super) fn label(line: &str) -> &str {
    line.get(60..).unwrap_or("").trim_end()
}

pub(super) fn field(line: &str, start: usize, width: usize) -> &str {
    let end = (start + width).min(line.len());
    if start >= end {
        return "";
    }
    line.get(start..end).unwrap_or("").trim()
}

/// One observation field of a satellite line: F14.3 at `start`, then the
/// loss-of-lock digit (RINEX 3.05 §5.7, RINEX 2.11 §5.2; blank or not a
/// digit: 0). `Ok(None)` where blank; `Err(text)` when the field is not a
/// number in [`observation_range`] of `code`.
pub(super) fn observation_value<'a>(
    line: &'a str,
    start: usize,
    code: &str,
) -> std::result::Result<Option<(f64, u8)>, &'a str> {
    let f = field(line, start, 14);
    if f.is_empty() {
        return Ok(None);
    }
    let lli = field(line, start + 14, 1).parse().unwrap_or(0);
    match f.parse::<f64>() {
        Ok(v) if observation_range(code).contains(&v) => Ok(Some((v, lli))),
        _ => Err(f),
    }
}

/// What an epoch record's flag 2-6 announces (RINEX 3.05 table A13, RINEX
/// 2.11 table A2): the key its count goes under in
/// [`ObservationFile::skipped`].
pub fn event_kind(flag: u8) -> String {
    let what = match flag {
        2 => "start moving antenna",
        3 => "new site occupation",
        4 => "header information follows",
        5 => "external event",
        _ => "cycle slips",
    };
    format!("event records with flag {flag} ({what})")
}

/// The time system of a file's epochs (TIME OF FIRST OBS, RINEX 3.05
/// §5.2): GPS, or Galileo's GST (the same seconds), or GLONASS's, which
/// RINEX writes as UTC (UTC(SU) without the 3 h), turned into GPS time
/// with the leap seconds of the date.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum EpochTimeSystem {
    Gps,
    Utc,
}

impl EpochTimeSystem {
    /// GPS time of an epoch's calendar fields, range-checked.
    pub(super) fn gps_time_s(
        self,
        (y, mo, d, h, mi, s): (i64, i64, i64, i64, i64, f64),
    ) -> std::result::Result<f64, String> {
        match self {
            Self::Gps => checked_gps_time_from_calendar(y, mo, d, h, mi, s),
            Self::Utc => checked_gps_time_from_utc(y, mo, d, h, mi, s),
        }
    }
}
