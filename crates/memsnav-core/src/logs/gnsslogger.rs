//! Android GnssLogger files (the app's `gnss_log_*.txt`): comma-separated
//! records named in their first field, each record type described by a
//! `# Type,column,...` header line. Read here:
//!
//! - `Raw` (android.location.GnssMeasurement with its GnssClock) to
//!   RINEX-style observations per signal: pseudorange `C` m, carrier `L`
//!   cycles (AccumulatedDeltaRange / λ when its state says valid), Doppler
//!   `D` Hz (−PseudorangeRate / λ) and C/N0 `S` dB-Hz, in the same
//!   [`ObservationFile`] as the RINEX reader gives, so that everything
//!   downstream (`gps_l1_epochs`, the fix solver, the filters) takes either;
//! - `UncalAccel` and `UncalGyro` (the phone's raw sensors, Android sensor
//!   axes: x right, y up, z out of the screen; the phone's bias estimates
//!   are not applied) to an [`ImuLog`] on GPS time: the gyro interpolated
//!   linearly to the accelerometer's time stamps.
//!
//! Pseudorange (Android "Raw GNSS measurements" white paper, and the
//! GnssMeasurement reference): reception time
//! tRx = TimeNanos + TimeOffsetNanos − (FullBiasNanos + BiasNanos) in GPS
//! time, taken in the time scale of the constellation's ReceivedSvTimeNanos:
//! the GPS week (GPS, QZSS, IRNSS, Galileo), the BeiDou week
//! (BDT = GPST − 14 s), the GLONASS day (UTC + 3 h: GPST − leap seconds +
//! 3 h); ρ = c (tRx − tTx), wrapped over the week or day boundary. A
//! measurement is converted only when its `State` makes tTx unambiguous
//! (code lock and, per system, TOW or time of day decoded or known, not
//! millisecond-ambiguous; Galileo E1 with its secondary code locked is
//! known modulo 100 ms, more than any MEO travel time); others are skipped
//! and counted by reason in [`GnssLoggerLog::skipped`], as are SBAS and
//! unknown constellations and a clock without FullBiasNanos.

use std::collections::BTreeMap;
use std::path::Path;

use nalgebra::Vector3;

use super::fields::{finite_number, parse_error};
use super::ImuLog;
use crate::geodesy::wgs84::SPEED_OF_LIGHT_M_S;
use crate::gnss::{
    plausible, ObservationEpoch, ObservationFile, SatelliteObservations, SignalLayout,
};
use crate::{Error, Result};

const NS_PER_WEEK: i128 = 604_800_000_000_000;
const NS_PER_DAY: i128 = 86_400_000_000_000;
/// BeiDou time runs 14 s behind GPS time.
const BDT_MINUS_GPST_NS: i128 = -14_000_000_000;
/// GLONASS time is UTC + 3 h.
const GLONASS_MINUS_UTC_NS: i128 = 3 * 3_600_000_000_000;
/// GPS − UTC from 2017-01-01 on (no leap second since), s.
const GPS_MINUS_UTC_SINCE_2017_S: i128 = 18;
/// 2017-01-01 00:00:18 GPST, ns since 1980-01-06.
const START_OF_18_LEAP_SECONDS_NS: i128 = 1_167_264_018_000_000_000;
/// Galileo E1C secondary code period: the time of transmission is known
/// modulo this much with the secondary code locked.
const GALILEO_E1C_SECONDARY_NS: i128 = 100_000_000;

// GnssMeasurement.State bits.
const CODE_LOCK: u32 = 1;
const TOW_DECODED: u32 = 8;
const MSEC_AMBIGUOUS: u32 = 16;
const GLO_TOD_DECODED: u32 = 128;
const GAL_E1BC_CODE_LOCK: u32 = 1024;
const GAL_E1C_2ND_CODE_LOCK: u32 = 2048;
const TOW_KNOWN: u32 = 16384;
const GLO_TOD_KNOWN: u32 = 32768;
// AccumulatedDeltaRangeState bit.
const ADR_VALID: u32 = 1;

/// The Raw columns this reader needs (the header must name them).
const RAW_COLUMNS: [&str; 13] = [
    "TimeNanos",
    "FullBiasNanos",
    "BiasNanos",
    "TimeOffsetNanos",
    "State",
    "ReceivedSvTimeNanos",
    "Cn0DbHz",
    "PseudorangeRateMetersPerSecond",
    "AccumulatedDeltaRangeState",
    "AccumulatedDeltaRangeMeters",
    "CarrierFrequencyHz",
    "ConstellationType",
    "Svid",
];

/// What a GnssLogger file holds.
#[derive(Debug, Clone, PartialEq)]
pub struct GnssLoggerLog {
    /// The `Raw` records as observations (`C`, `L`, `D`, `S` per signal,
    /// RINEX 3 codes such as `C1C`, `C5Q`), epochs on GPS time.
    pub observations: ObservationFile,
    /// `UncalAccel` with `UncalGyro` interpolated to its times, on GPS time
    /// (None without both sensors or without a `Raw` record tying the
    /// sensor clock to GPS time).
    pub imu: Option<ImuLog>,
    /// Measurements left out, by reason.
    pub skipped: BTreeMap<String, usize>,
    /// Non-fatal problems, one sentence each.
    pub warnings: Vec<String>,
}

/// Reads a GnssLogger file.
pub fn read_gnsslogger(path: impl AsRef<Path>) -> Result<GnssLoggerLog> {
    let path = path.as_ref();
    let bytes = super::read_bytes(path)?;
    parse_gnsslogger(
        &String::from_utf8_lossy(&bytes),
        &path.display().to_string(),
    )
}

/// One record's fields by column name.
struct Record<'a> {
    file: &'a str,
    line: usize,
    kind: &'a str,
    columns: &'a [String],
    fields: Vec<&'a str>,
}

impl Record<'_> {
    fn text(&self, name: &str) -> Result<&str> {
        let k = self.columns.iter().position(|c| c == name).ok_or_else(|| {
            parse_error(
                self.file,
                self.line,
                format!("the '# {}' header has no {name} column", self.kind),
            )
        })?;
        Ok(self.fields[k])
    }

    fn error(&self, name: &str, text: &str, what: &str) -> Error {
        parse_error(
            self.file,
            self.line,
            format!("{} {name} = {text:?}: expected {what}", self.kind),
        )
    }

    /// A number, None for an empty field.
    fn number(&self, name: &str) -> Result<Option<f64>> {
        let text = self.text(name)?;
        if text.is_empty() {
            return Ok(None);
        }
        finite_number(text)
            .map(Some)
            .ok_or_else(|| self.error(name, text, "a finite number"))
    }

    /// A whole number, None for an empty field.
    fn integer(&self, name: &str) -> Result<Option<i64>> {
        let text = self.text(name)?;
        if text.is_empty() {
            return Ok(None);
        }
        text.parse::<i64>()
            .map(Some)
            .map_err(|_| self.error(name, text, "an integer"))
    }

    fn required_integer(&self, name: &str) -> Result<i64> {
        self.integer(name)?
            .ok_or_else(|| self.error(name, "", "an integer"))
    }
}

/// A signal's RINEX band digit and nominal carrier frequency, Hz, from the
/// carrier frequency (None: the L1/E1/B1 band) of system `system`.
fn band(system: char, carrier_hz: Option<f64>) -> Option<(char, f64)> {
    let Some(f) = carrier_hz else {
        return Some(match system {
            'C' => ('2', 1_561.098e6),
            'R' => ('1', 1_602.0e6),
            _ => ('1', 1_575.42e6),
        });
    };
    let near = |nominal: f64, width: f64| (f - nominal).abs() <= width;
    let digit = if system == 'R' && near(1_602.0e6, 10.0e6) {
        '1'
    } else if system == 'R' && near(1_246.0e6, 8.0e6) {
        '2'
    } else if near(1_575.42e6, 1.0e6) {
        '1'
    } else if near(1_561.098e6, 1.0e6) || near(1_227.60e6, 1.0e6) {
        '2'
    } else if near(1_176.45e6, 1.0e6) {
        '5'
    } else if near(1_207.14e6, 1.0e6) {
        '7'
    } else if near(1_268.52e6, 1.0e6) || near(1_278.75e6, 1.0e6) {
        '6'
    } else {
        return None;
    };
    Some((digit, f))
}

/// The system letter of an Android ConstellationType.
fn system(constellation: i64) -> Option<char> {
    match constellation {
        1 => Some('G'),
        3 => Some('R'),
        4 => Some('J'),
        5 => Some('C'),
        6 => Some('E'),
        7 => Some('I'),
        _ => None,
    }
}

/// One converted measurement.
struct Signal {
    system: char,
    prn: u16,
    code: String,
    values: [Option<f64>; 4],
}

/// The pseudorange of one Raw record, m, or the reason it is skipped.
fn pseudorange(
    r: &Record<'_>,
    system: char,
    rx_gps_ns: i128,
    frac_ns: f64,
) -> Result<std::result::Result<f64, String>> {
    let state = r.required_integer("State")?;
    let state = u32::try_from(state).map_err(|_| {
        r.error(
            "State",
            r.text("State").unwrap_or(""),
            "a non-negative integer",
        )
    })?;
    let tx_ns = i128::from(r.required_integer("ReceivedSvTimeNanos")?);
    let tow = state & (TOW_DECODED | TOW_KNOWN) != 0;
    let locked = state & (CODE_LOCK | GAL_E1BC_CODE_LOCK) != 0;
    if !locked {
        return Ok(Err("no code lock (State)".into()));
    }
    if state & MSEC_AMBIGUOUS != 0 {
        return Ok(Err("millisecond ambiguity (State MSEC_AMBIGUOUS)".into()));
    }
    let (rx_ns, period) = match system {
        'G' | 'J' | 'I' if tow => (rx_gps_ns, NS_PER_WEEK),
        'E' if tow => (rx_gps_ns, NS_PER_WEEK),
        'E' if state & GAL_E1C_2ND_CODE_LOCK != 0 => (rx_gps_ns, GALILEO_E1C_SECONDARY_NS),
        'C' if tow => (rx_gps_ns + BDT_MINUS_GPST_NS, NS_PER_WEEK),
        'R' if state & (GLO_TOD_DECODED | GLO_TOD_KNOWN) != 0 => {
            let leap_s = match r.integer("LeapSecond").unwrap_or(None) {
                Some(leap) => i128::from(leap),
                None if rx_gps_ns >= START_OF_18_LEAP_SECONDS_NS => GPS_MINUS_UTC_SINCE_2017_S,
                None => return Ok(Err("GLONASS before 2017 without LeapSecond".into())),
            };
            (
                rx_gps_ns - leap_s * 1_000_000_000 + GLONASS_MINUS_UTC_NS,
                NS_PER_DAY,
            )
        }
        'R' => return Ok(Err("GLONASS time of day not decoded (State)".into())),
        _ => return Ok(Err("time of week not decoded (State)".into())),
    };
    if !(0..period).contains(&tx_ns) && period != GALILEO_E1C_SECONDARY_NS {
        return Ok(Err("ReceivedSvTimeNanos out of its period".into()));
    }
    // Over a week or day boundary the difference wraps; the Galileo
    // secondary code gives the travel time itself (modulo 100 ms).
    let mut travel = (rx_ns - tx_ns).rem_euclid(period);
    if travel >= period / 2 && period != GALILEO_E1C_SECONDARY_NS {
        travel -= period;
    }
    let rho = (travel as f64 + frac_ns) * 1e-9 * SPEED_OF_LIGHT_M_S;
    // Below 1e6 m (3 ms) the travel time is an ambiguity, not a range.
    if !(1.0e6..=*plausible::PSEUDORANGE_M.end()).contains(&rho) {
        return Ok(Err("pseudorange outside 1e6 to 1e8 m".into()));
    }
    Ok(Ok(rho))
}

/// The observations of one Raw record, or the reason it is skipped.
fn raw_signal(r: &Record<'_>) -> Result<std::result::Result<(i128, f64, Signal), String>> {
    let time_ns = i128::from(r.required_integer("TimeNanos")?);
    let Some(full_bias_ns) = r.integer("FullBiasNanos")? else {
        return Ok(Err("no FullBiasNanos (receiver clock not set)".into()));
    };
    let bias_ns = r.number("BiasNanos")?.unwrap_or(0.0);
    let offset_ns = r.number("TimeOffsetNanos")?.unwrap_or(0.0);
    if bias_ns.abs() > 1e9 || offset_ns.abs() > 1e9 {
        return Err(parse_error(
            r.file,
            r.line,
            "Raw BiasNanos or TimeOffsetNanos beyond 1 s",
        ));
    }
    let rx_gps_ns = time_ns - i128::from(full_bias_ns);
    if !(0..=100 * 52 * NS_PER_WEEK).contains(&rx_gps_ns) {
        return Err(parse_error(
            r.file,
            r.line,
            format!(
                "Raw TimeNanos − FullBiasNanos = {rx_gps_ns} ns is not a GPS time of 1980-2080"
            ),
        ));
    }
    let Some(system) = system(r.required_integer("ConstellationType")?) else {
        return Ok(Err("constellation not converted (SBAS, unknown)".into()));
    };
    let svid = r.required_integer("Svid")?;
    // Android numbers QZSS 193-202 (RINEX J01-J10); GLONASS 93-106 is a
    // frequency channel, not a slot, and leaves the satellite unknown.
    let number = if system == 'J' && svid > 192 {
        svid - 192
    } else {
        svid
    };
    if plausible::check_satellite(system, number).is_err() {
        return Ok(Err(format!(
            "Svid outside its constellation's satellite numbers (system {system})"
        )));
    }
    let prn = number as u16;
    let carrier = r.number("CarrierFrequencyHz")?;
    let Some((digit, carrier_hz)) = band(system, carrier) else {
        return Ok(Err("carrier frequency of no known band".into()));
    };
    let attribute = match r.text("CodeType").unwrap_or("") {
        "" if system == 'C' => 'I',
        "" => 'C',
        t if t.len() == 1 && t.chars().all(|c| c.is_ascii_alphabetic()) => {
            t.chars().next().unwrap_or('C')
        }
        t => return Err(r.error("CodeType", t, "one letter")),
    };
    let lambda = SPEED_OF_LIGHT_M_S / carrier_hz;
    let cn0 = r.number("Cn0DbHz")?;
    if cn0.is_some_and(|s| !plausible::CN0_DB_HZ.contains(&s)) {
        return Err(r.error("Cn0DbHz", r.text("Cn0DbHz")?, "0 to 200 dB-Hz"));
    }
    let rate = r.number("PseudorangeRateMetersPerSecond")?;
    if rate.is_some_and(|v| !plausible::PSEUDORANGE_RATE_M_S.contains(&v)) {
        return Err(r.error(
            "PseudorangeRateMetersPerSecond",
            r.text("PseudorangeRateMetersPerSecond")?,
            "at most 1e5 m/s",
        ));
    }
    let adr_state = r.integer("AccumulatedDeltaRangeState")?.unwrap_or(0);
    let adr = r.number("AccumulatedDeltaRangeMeters")?;
    let carrier_cycles = match adr {
        Some(a) if adr_state & i64::from(ADR_VALID) != 0 && a.abs() <= 1e9 => Some(a / lambda),
        _ => None,
    };
    let rho = match pseudorange(r, system, rx_gps_ns, offset_ns - bias_ns)? {
        Ok(rho) => rho,
        Err(reason) => return Ok(Err(reason)),
    };
    let epoch_ns = rx_gps_ns as f64 - bias_ns;
    Ok(Ok((
        time_ns,
        epoch_ns,
        Signal {
            system,
            prn,
            code: format!("{digit}{attribute}"),
            values: [Some(rho), carrier_cycles, rate.map(|v| -v / lambda), cn0],
        },
    )))
}

/// Parses the text of a GnssLogger file; `file` names it in errors.
pub fn parse_gnsslogger(text: &str, file: &str) -> Result<GnssLoggerLog> {
    let mut headers: BTreeMap<&str, Vec<String>> = BTreeMap::new();
    let mut skipped: BTreeMap<String, usize> = BTreeMap::new();
    let mut warnings = Vec::new();
    // (TimeNanos, epoch GPS ns, signals) per epoch, in file order.
    let mut epochs: Vec<(i128, f64, Vec<Signal>)> = Vec::new();
    let mut elapsed_to_gps_ns: Option<f64> = None;
    // (elapsed ns, xyz, line, end offset) of each sensor.
    let mut accel: Vec<(f64, Vector3<f64>, usize, u64)> = Vec::new();
    let mut gyro: Vec<(f64, Vector3<f64>, usize, u64)> = Vec::new();
    let mut offset: u64 = 0;
    let mut newline_count: u64 = 0;
    for (k, raw_line) in text.split_inclusive('\n').enumerate() {
        offset += raw_line.len() as u64;
        let ends = raw_line.ends_with('\n');
        newline_count += u64::from(ends);
        let line = raw_line.trim_end_matches(['\n', '\r']);
        if let Some(header) = line.strip_prefix('#') {
            let names: Vec<String> = header
                .trim()
                .split(',')
                .map(|s| s.trim().to_string())
                .collect();
            if let Some(kind) = ["Raw", "UncalAccel", "UncalGyro"]
                .into_iter()
                .find(|t| names[0] == *t)
            {
                headers.insert(kind, names);
            }
            continue;
        }
        let mut fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let kind = fields[0];
        let Some(columns) = headers.get(kind) else {
            continue; // a record type this reader does not use
        };
        if !ends {
            warnings.push(format!(
                "{file}:{}: the last line has no end of line (cut short); skipped",
                k + 1
            ));
            continue;
        }
        if fields.len() != columns.len() {
            return Err(parse_error(
                file,
                k + 1,
                format!(
                    "{kind}: {} fields where its '# {kind}' header names {}",
                    fields.len(),
                    columns.len()
                ),
            ));
        }
        fields[0] = "";
        let record = Record {
            file,
            line: k + 1,
            kind,
            columns,
            fields,
        };
        match kind {
            "Raw" => {
                for name in RAW_COLUMNS {
                    record.text(name)?;
                }
                match raw_signal(&record)? {
                    Err(reason) => *skipped.entry(reason).or_default() += 1,
                    Ok((time_ns, epoch_ns, signal)) => {
                        if elapsed_to_gps_ns.is_none() {
                            if let Some(elapsed) = record
                                .integer("ChipsetElapsedRealtimeNanos")
                                .unwrap_or(None)
                                .filter(|e| *e > 0)
                            {
                                elapsed_to_gps_ns = Some(epoch_ns - elapsed as f64);
                            }
                        }
                        match epochs.last_mut() {
                            Some(e) if e.0 == time_ns => {
                                if e.2.iter().any(|s| {
                                    (s.system, s.prn, &s.code)
                                        == (signal.system, signal.prn, &signal.code)
                                }) {
                                    *skipped
                                        .entry("signal twice in an epoch".into())
                                        .or_default() += 1;
                                } else {
                                    e.2.push(signal);
                                }
                            }
                            Some(e) if e.1 >= epoch_ns => {
                                return Err(parse_error(file, k + 1, format!("Raw: epoch at GPS {} s does not come after the previous one ({} s)", epoch_ns * 1e-9, e.1 * 1e-9)));
                            }
                            _ => epochs.push((time_ns, epoch_ns, vec![signal])),
                        }
                    }
                }
            }
            _ => {
                let (prefix, unit, series) = if kind == "UncalAccel" {
                    ("UncalAccel", "Mps2", &mut accel)
                } else {
                    ("UncalGyro", "RadPerSec", &mut gyro)
                };
                let elapsed = record.required_integer("elapsedRealtimeNanos")?;
                let mut v = Vector3::zeros();
                for (i, axis) in ["X", "Y", "Z"].iter().enumerate() {
                    let name = format!("{prefix}{axis}{unit}");
                    v[i] = record
                        .number(&name)?
                        .ok_or_else(|| record.error(&name, "", "a number"))?;
                }
                let limit = if kind == "UncalAccel" {
                    super::MAX_SPECIFIC_FORCE_M_S2
                } else {
                    super::MAX_ANGULAR_RATE_RAD_S
                };
                if v.amax() > limit {
                    return Err(parse_error(
                        file,
                        k + 1,
                        format!("{kind}: |{v:?}| beyond {limit}"),
                    ));
                }
                if series.last().is_some_and(|s| s.0 >= elapsed as f64) {
                    return Err(parse_error(
                        file,
                        k + 1,
                        format!("{kind}: elapsedRealtimeNanos does not increase"),
                    ));
                }
                series.push((elapsed as f64, v, k + 1, offset - u64::from(ends)));
            }
        }
    }
    let layout = SignalLayout::new(
        epochs
            .iter()
            .flat_map(|e| &e.2)
            .map(|s| (s.system, s.code.as_str())),
    );
    let observation_epochs = epochs
        .into_iter()
        .map(|(_, epoch_ns, signals)| {
            let mut satellites: Vec<SatelliteObservations> = Vec::new();
            for s in signals {
                // Android's ADR slip flags are not mapped (yet): LLI 0.
                let (values, _) = layout.slots(&mut satellites, s.system, s.prn, &s.code);
                values.copy_from_slice(&s.values);
            }
            ObservationEpoch {
                gps_time_s: epoch_ns * 1e-9,
                flag: 0,
                satellites,
            }
        })
        .collect();
    let imu = match (accel.len() >= 2 && gyro.len() >= 2, elapsed_to_gps_ns) {
        (false, _) => None,
        (true, None) => {
            warnings.push("no Raw record with ChipsetElapsedRealtimeNanos ties the sensors' clock to GPS time: IMU left out".into());
            None
        }
        (true, Some(to_gps)) => Some(phone_imu(&accel, &gyro, to_gps, offset, newline_count)),
    };
    Ok(GnssLoggerLog {
        observations: ObservationFile {
            version: 3.05,
            observation_types: layout.observation_types(),
            approx_position_ecef: None,
            epochs: observation_epochs,
            glonass_channels: Default::default(),
            warnings: Vec::new(),
            skipped: Default::default(),
        },
        imu,
        skipped,
        warnings,
    })
}

/// The accelerometer samples inside the gyro's time span, with the gyro
/// interpolated linearly to their times, on GPS time.
fn phone_imu(
    accel: &[(f64, Vector3<f64>, usize, u64)],
    gyro: &[(f64, Vector3<f64>, usize, u64)],
    elapsed_to_gps_ns: f64,
    file_bytes: u64,
    newline_count: u64,
) -> ImuLog {
    let mut log = ImuLog {
        time_s: Vec::new(),
        specific_force_m_s2: Vec::new(),
        angular_rate_rad_s: Vec::new(),
        line_time_s: Vec::new(),
        line: Vec::new(),
        line_end_offset: Vec::new(),
        file_bytes,
        newline_count,
        warnings: Vec::new(),
    };
    let mut j = 0;
    for &(t, f, line, end) in accel {
        while j + 2 < gyro.len() && gyro[j + 1].0 < t {
            j += 1;
        }
        let (a, b) = (&gyro[j], &gyro[j + 1]);
        if t < a.0 || t > b.0 {
            continue;
        }
        let w = (t - a.0) / (b.0 - a.0);
        log.time_s.push((t + elapsed_to_gps_ns) * 1e-9);
        log.line_time_s.push((t + elapsed_to_gps_ns) * 1e-9);
        log.specific_force_m_s2.push(f);
        log.angular_rate_rad_s.push(a.1 + (b.1 - a.1) * w);
        log.line.push(line);
        log.line_end_offset.push(end);
    }
    let dropped = accel.len() - log.time_s.len();
    if dropped > 0 {
        log.warnings.push(format!(
            "{dropped} UncalAccel samples outside the UncalGyro time span left out"
        ));
    }
    log
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "# Raw,utcTimeMillis,TimeNanos,LeapSecond,FullBiasNanos,BiasNanos,TimeOffsetNanos,State,ReceivedSvTimeNanos,Cn0DbHz,PseudorangeRateMetersPerSecond,AccumulatedDeltaRangeState,AccumulatedDeltaRangeMeters,CarrierFrequencyHz,ConstellationType,Svid,CodeType\n";
    /// GPS time of the records: week 2287 + 258212 s + 0.5 µs, ns.
    const RX_NS: i128 = 2287 * NS_PER_WEEK + 258_212_000_000_000 + 500;

    /// A Raw line received at RX_NS with satellite time `tx_ns`.
    fn raw(state: u32, tx_ns: i128, constellation: u8, carrier: &str, code: &str) -> String {
        let time_ns = 1_000_000_000_i128;
        format!(
            "Raw,0,{time_ns},,{},0.0,0.0,{state},{tx_ns},40,100,1,500,{carrier},{constellation},7,{code}\n",
            time_ns - RX_NS
        )
    }

    fn pseudorange(line: &str) -> Option<f64> {
        let log = parse_gnsslogger(&format!("{HEADER}{line}"), "x.txt").unwrap();
        let epoch = log.observations.epochs.first()?;
        epoch.satellites[0].values[0]
    }

    #[test]
    fn time_scales_per_constellation() {
        let travel = 75_000_000_i128; // 75 ms
        let c = SPEED_OF_LIGHT_M_S * 0.075;
        let tow = RX_NS % NS_PER_WEEK - travel;
        let gps = raw(CODE_LOCK | TOW_DECODED, tow, 1, "1575420030", "C");
        assert!((pseudorange(&gps).unwrap() - c).abs() < 1e-6);
        // BeiDou: BDT = GPST − 14 s.
        let bds = raw(
            CODE_LOCK | TOW_DECODED,
            tow - 14_000_000_000,
            5,
            "1561098000",
            "I",
        );
        assert!((pseudorange(&bds).unwrap() - c).abs() < 1e-6);
        // GLONASS: time of day, UTC + 3 h, 18 leap seconds.
        let tod = (RX_NS - 18_000_000_000 + GLONASS_MINUS_UTC_NS).rem_euclid(NS_PER_DAY) - travel;
        let glo = raw(CODE_LOCK | GLO_TOD_DECODED, tod, 3, "1602000000", "C");
        assert!((pseudorange(&glo).unwrap() - c).abs() < 1e-6);
        // Galileo with only its secondary code: known modulo 100 ms.
        let sub = (RX_NS - travel).rem_euclid(GALILEO_E1C_SECONDARY_NS);
        let gal = raw(
            GAL_E1BC_CODE_LOCK | GAL_E1C_2ND_CODE_LOCK,
            sub,
            6,
            "1575420030",
            "C",
        );
        assert!((pseudorange(&gal).unwrap() - c).abs() < 1e-6);
        // A satellite time far from the reception time.
        let at_start = raw(CODE_LOCK | TOW_KNOWN, NS_PER_WEEK - 1_000, 1, "", "");
        let log = parse_gnsslogger(&format!("{HEADER}{at_start}"), "x.txt").unwrap();
        assert!(log.skipped.contains_key("pseudorange outside 1e6 to 1e8 m"));
        // Ambiguous states are skipped and counted.
        for (state, reason) in [
            (CODE_LOCK, "time of week not decoded (State)"),
            (TOW_KNOWN, "no code lock (State)"),
            (
                CODE_LOCK | TOW_KNOWN | MSEC_AMBIGUOUS,
                "millisecond ambiguity (State MSEC_AMBIGUOUS)",
            ),
        ] {
            let log = parse_gnsslogger(
                &format!("{HEADER}{}", raw(state, tow, 1, "1575420030", "C")),
                "x.txt",
            )
            .unwrap();
            assert_eq!(log.skipped.get(reason), Some(&1), "{state}");
            assert!(log.observations.epochs.is_empty());
        }
        // Doppler −rate/λ; the carrier only with a valid ADR state.
        let log = parse_gnsslogger(&format!("{HEADER}{gps}"), "x.txt").unwrap();
        let v = &log.observations.epochs[0].satellites[0].values;
        let lambda = SPEED_OF_LIGHT_M_S / 1_575_420_030.0;
        assert!((v[1].unwrap() - 500.0 / lambda).abs() < 1e-9);
        assert!((v[2].unwrap() + 100.0 / lambda).abs() < 1e-9);
        assert_eq!(v[3], Some(40.0));
    }

    #[test]
    fn satellites_that_do_not_exist_are_skipped_and_counted() {
        let tow = RX_NS % NS_PER_WEEK - 75_000_000;
        let line = raw(CODE_LOCK | TOW_DECODED, tow, 1, "1575420030", "C");
        let g255 = line.replace(",1,7,C", ",1,255,C");
        let log = parse_gnsslogger(&format!("{HEADER}{g255}"), "x.txt").unwrap();
        assert!(log.observations.epochs.is_empty());
        assert_eq!(
            log.skipped
                .get("Svid outside its constellation's satellite numbers (system G)"),
            Some(&1)
        );
        // QZSS's Android numbers 193-202 are RINEX's J01-J10.
        let j194 = line.replace(",1,7,C", ",4,194,C");
        let log = parse_gnsslogger(&format!("{HEADER}{j194}"), "x.txt").unwrap();
        let sat = &log.observations.epochs[0].satellites[0];
        assert_eq!((sat.system, sat.prn), ('J', 2));
    }

    #[test]
    fn bad_fields_name_the_line() {
        let line = raw(CODE_LOCK | TOW_DECODED, 5, 1, "1575420030", "C").replace(",40,", ",x,");
        let e = parse_gnsslogger(&format!("{HEADER}{line}"), "x.txt")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("x.txt:2: Raw Cn0DbHz = \"x\""), "{e}");
    }
}
