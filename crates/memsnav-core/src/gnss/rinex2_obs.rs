//! RINEX 2.10/2.11 observation records (RINEX 2.11 format description,
//! Gurtner and Estey 2007, §5 and tables A1-A2), read into the same
//! [`ObservationFile`] as RINEX 3's, each 2.x observation code mapped to
//! the RINEX 3 code of the signal it holds ([`rinex3_code`]).
//!
//! A 2.x file declares one list of observation types for every system
//! (`# / TYPES OF OBSERV`, 9 a line); an epoch line lists its satellites
//! (12 a line, continuation lines indented 32 columns) and each satellite
//! then takes ⌈types / 5⌉ lines of five 16-column fields. The header lines
//! common to both versions are read by [`super::rinex_obs`] (what both
//! hold: [`super::observation_file`]).

use std::collections::BTreeMap;

use nalgebra::Vector3;

use super::observation_file::{
    event_kind, field, observation_value, EpochTimeSystem, ObservationEpoch, ObservationFile,
    SatelliteObservations,
};
use super::plausible::observation_range_text;
use super::time::calendar_text;
use crate::{Error, Result};

/// The systems a RINEX 2 file may hold (G GPS, R GLONASS, E Galileo, S
/// SBAS; RINEX 2.11 §5.1) whose codes [`rinex3_code`] maps.
const SYSTEMS_2: [char; 4] = ['G', 'R', 'E', 'S'];

/// The RINEX 3 code of RINEX 2.10/2.11 observation code `code` of
/// `system`, `None` where the system has no such signal. RTKLIB's mapping
/// (`convcode` of its `rinex.c`, for versions before 2.12), from the
/// signals each code meant (RINEX 2.11 §10.1 and RINEX 3.05 table A2):
///
/// | 2.x | GPS | GLONASS | Galileo | SBAS |
/// |---|---|---|---|---|
/// | C1 | C1C | C1C | C1X | C1C |
/// | P1 | C1W | C1P | – | – |
/// | L1 D1 S1 | x1C | x1C | x1X | x1C |
/// | C2 | C2X (L2C) | C2C | – | – |
/// | P2 | C2W | C2P | – | – |
/// | L2 D2 S2 | x2W | x2P | – | – |
/// | C5 L5 D5 S5 | x5X | – | x5X | x5X |
/// | x6, x7, x8 | – | – | x6X, x7X, x8X | – |
///
/// (GPS P1/P2 are the encrypted P(Y) code, RINEX 3's W; the 2.x files
/// do not say which L2 tracking gave L2, RINEX 3's W is the usual one.)
pub fn rinex3_code(system: char, code: &str) -> Option<String> {
    let b = code.as_bytes();
    if b.len() != 2 || !SYSTEMS_2.contains(&system) {
        return None;
    }
    let (kind, band) = (b[0] as char, b[1] as char);
    let attribute = match (kind, band, system) {
        ('P', '1', 'G') | ('P', '2', 'G') => 'W',
        ('P', '1', 'R') | ('P', '2', 'R') => 'P',
        ('C', '1', _) | ('L' | 'D' | 'S', '1', 'G' | 'R' | 'S') => {
            if system == 'E' {
                'X'
            } else {
                'C'
            }
        }
        ('L' | 'D' | 'S', '1', 'E') => 'X',
        ('C', '2', 'G') => 'X',
        ('C', '2', 'R') => 'C',
        ('L' | 'D' | 'S', '2', 'G') => 'W',
        ('L' | 'D' | 'S', '2', 'R') => 'P',
        ('C' | 'L' | 'D' | 'S', '5', 'G' | 'E' | 'S') => 'X',
        ('C' | 'L' | 'D' | 'S', '6' | '7' | '8', 'E') => 'X',
        _ => return None,
    };
    let kind = if kind == 'P' { 'C' } else { kind };
    Some(format!("{kind}{band}{attribute}"))
}

/// Reads one `# / TYPES OF OBSERV` header line into `types`: the count in
/// columns 1-6 on the first line, nine 2-character codes a line from
/// column 11, 6 columns apart; `pending` holds the count while lines
/// remain. Returns the reason when the line does not fit.
pub(super) fn header_types(
    line: &str,
    types: &mut Vec<String>,
    pending: &mut Option<usize>,
) -> std::result::Result<(), String> {
    let total = match *pending {
        Some(total) => total,
        None => {
            let total: usize = field(line, 0, 6).parse().map_err(|_| {
                "expected the number of observation types in columns 1-6".to_string()
            })?;
            if total == 0 || total > 99 {
                return Err(format!(
                    "{total} observation types: expected 1 to 99 (two digits)"
                ));
            }
            types.clear();
            total
        }
    };
    for j in 0..9 {
        if types.len() == total {
            break;
        }
        let code = field(line, 10 + 6 * j, 2);
        if code.len() != 2 {
            return Err(format!(
                "expected {total} observation types, found {}",
                types.len()
            ));
        }
        types.push(code.to_string());
    }
    *pending = (types.len() < total).then_some(total);
    Ok(())
}

/// What [`parse_records`] needs of the header.
pub(super) struct Header<'a> {
    pub file: &'a str,
    pub version: f64,
    /// The file's system letter (column 41; `M` mixed).
    pub file_system: char,
    /// The `# / TYPES OF OBSERV` codes, in order.
    pub types: &'a [String],
    pub time_system: EpochTimeSystem,
    pub approx_position_ecef: Option<Vector3<f64>>,
}

/// Observation fields per line of a satellite (RINEX 2.11 table A1).
const FIELDS_PER_LINE: usize = 5;
/// Satellites per epoch line.
const SATELLITES_PER_LINE: usize = 12;

/// Reads the records from line `k` (after `END OF HEADER`) of a RINEX 2
/// file whose header is `header`.
pub(super) fn parse_records(
    header: Header<'_>,
    lines: &[&str],
    mut k: usize,
    mut warnings: Vec<String>,
) -> Result<ObservationFile> {
    let file = header.file;
    let error = |k: usize, reason: String| Error::Parse {
        file: file.to_string(),
        line: k + 1,
        reason,
    };
    let n_types = header.types.len();
    if n_types == 0 {
        return Err(error(
            k.saturating_sub(1),
            "the header declares no '# / TYPES OF OBSERV'".into(),
        ));
    }
    // Per system: the RINEX 3 codes, and where each 2.x column goes.
    let systems: Vec<char> = match header.file_system {
        'M' => SYSTEMS_2.to_vec(),
        s => vec![s],
    };
    let mut observation_types: BTreeMap<char, Vec<String>> = BTreeMap::new();
    let mut columns: BTreeMap<char, Vec<Option<usize>>> = BTreeMap::new();
    for &system in &systems {
        let mut codes = Vec::new();
        let map = header
            .types
            .iter()
            .map(|t| {
                rinex3_code(system, t).map(|c| {
                    codes.push(c);
                    codes.len() - 1
                })
            })
            .collect();
        if !codes.is_empty() {
            observation_types.insert(system, codes);
            columns.insert(system, map);
        }
    }
    let lines_per_satellite = n_types.div_ceil(FIELDS_PER_LINE);
    let truncated = |k: usize, what: &str| {
        format!(
            "{file}:{}: the last record is cut short ({what}); skipped",
            k + 1
        )
    };
    let mut epochs: Vec<ObservationEpoch> = Vec::new();
    let mut skipped: BTreeMap<String, usize> = BTreeMap::new();
    while k < lines.len() {
        let line = lines[k];
        if line.trim().is_empty() {
            k += 1;
            continue;
        }
        let flag: Option<u8> = field(line, 28, 1).parse().ok();
        let count: Option<usize> = field(line, 29, 3).parse().ok();
        let (Some(flag), Some(count)) = (flag, count) else {
            if k + 1 == lines.len() {
                warnings.push(truncated(k, "incomplete epoch line"));
                break;
            }
            return Err(error(
                k,
                "expected an epoch line ' yy mm dd hh mm ss.sssssss  f nnn' (epoch, flag, number of satellites)".into(),
            ));
        };
        if flag > 6 {
            return Err(error(k, format!("epoch flag {flag} is out of range (0-6)")));
        }
        // Event records (2-5) announce `count` header lines, whatever
        // their epoch fields hold (they may be blank).
        if (2..=5).contains(&flag) {
            if k + count >= lines.len() {
                warnings.push(truncated(k, "fewer event lines than announced"));
                break;
            }
            *skipped.entry(event_kind(flag)).or_default() += 1;
            k += 1 + count;
            continue;
        }
        let list_lines = count.div_ceil(SATELLITES_PER_LINE).max(1);
        let record_lines = list_lines + count * lines_per_satellite;
        if k + record_lines > lines.len() {
            warnings.push(truncated(k, "fewer lines than its satellites need"));
            break;
        }
        let n = |s: usize, w: usize| field(line, s, w).parse::<i64>().ok();
        let calendar = (|| {
            let yy = n(1, 2)?;
            // Two-digit years: 80-99 are 1980-1999 (RINEX 2.11 §6.5).
            let y = if yy < 80 { 2000 + yy } else { 1900 + yy };
            let s: f64 = field(line, 15, 11).parse().ok()?;
            Some((y, n(4, 2)?, n(7, 2)?, n(10, 2)?, n(13, 2)?, s))
        })();
        let Some(calendar) = calendar else {
            return Err(error(
                k,
                "expected the epoch ' yy mm dd hh mm ss.sssssss' in columns 1-26".into(),
            ));
        };
        let (y, mo, d, h, mi, s) = calendar;
        // The satellite list: "Xnn" from column 33, 12 a line.
        let mut names = Vec::with_capacity(count);
        for j in 0..count {
            let kk = k + j / SATELLITES_PER_LINE;
            let at = 32 + 3 * (j % SATELLITES_PER_LINE);
            let text = lines[kk].get(at..at + 3).unwrap_or("");
            let system = match text.chars().next() {
                Some(' ') => header.file_system_default(),
                Some(c) => c,
                None => ' ',
            };
            let prn: Option<u16> = text.get(1..).and_then(|p| p.trim().parse().ok());
            match prn {
                Some(prn @ 1..=99) if system.is_ascii_uppercase() => names.push((system, prn)),
                _ => {
                    return Err(error(
                        kk,
                        format!(
                        "expected satellite {} of {count} as 'Xnn' in columns {}-{}, got {text:?}",
                        j + 1,
                        at + 1,
                        at + 3
                    ),
                    ))
                }
            }
        }
        let first_value_line = k + list_lines;
        if flag == 6 {
            // Cycle-slip records: the satellites' lines, not observations.
            *skipped.entry(event_kind(flag)).or_default() += 1;
            k += record_lines;
            continue;
        }
        let gps_time_s = header
            .time_system
            .gps_time_s(calendar)
            .map_err(|reason| error(k, format!("epoch: {reason}")))?;
        if let Some(previous) = epochs.last().map(|e| e.gps_time_s) {
            if gps_time_s <= previous {
                return Err(error(
                    k,
                    format!(
                        "epoch {} does not follow the previous epoch: epochs must increase",
                        calendar_text(y, mo, d, h, mi, s)
                    ),
                ));
            }
        }
        let mut satellites: Vec<SatelliteObservations> = Vec::with_capacity(count);
        let mut cut = false;
        for (j, &(system, prn)) in names.iter().enumerate() {
            let start = first_value_line + j * lines_per_satellite;
            if let Some(first) = names[..j].iter().position(|&x| x == (system, prn)) {
                return Err(error(
                    k,
                    format!(
                        "{system}{prn:02} is listed twice in epoch {} (satellites {} and {}): one record per satellite and epoch",
                        calendar_text(y, mo, d, h, mi, s),
                        first + 1,
                        j + 1
                    ),
                ));
            }
            let (Some(types), Some(map)) = (observation_types.get(&system), columns.get(&system))
            else {
                *skipped
                    .entry(format!(
                        "observations of system {system} (no RINEX 3 code for its 2.x types)"
                    ))
                    .or_default() += 1;
                continue;
            };
            let mut values = vec![None; types.len()];
            let mut lli = vec![0; types.len()];
            for (i, code_2) in header.types.iter().enumerate() {
                let kk = start + i / FIELDS_PER_LINE;
                let at = 16 * (i % FIELDS_PER_LINE);
                let is_last = kk + 1 == lines.len();
                let code = map[i].map_or(code_2.as_str(), |c| types[c].as_str());
                match observation_value(lines[kk], at, code) {
                    Ok(None) => {}
                    Ok(Some((v, indicator))) => {
                        if let Some(c) = map[i] {
                            values[c] = Some(v);
                            lli[c] = indicator;
                        }
                    }
                    Err(_) if is_last => {
                        cut = true;
                        break;
                    }
                    Err(f) => {
                        return Err(error(
                            kk,
                            format!(
                                "expected a number for {system}{prn:02} {code_2} in columns {}-{} ({}), got {f:?}",
                                at + 1,
                                at + 14,
                                observation_range_text(code),
                            ),
                        ))
                    }
                }
            }
            if cut {
                break;
            }
            satellites.push(SatelliteObservations {
                system,
                prn,
                values,
                lli,
            });
        }
        if cut {
            warnings.push(truncated(k + record_lines - 1, "incomplete satellite line"));
            break;
        }
        epochs.push(ObservationEpoch {
            gps_time_s,
            flag,
            satellites,
        });
        k += record_lines;
    }
    // Systems the header allows but no epoch holds are left out.
    observation_types.retain(|system, _| {
        epochs
            .iter()
            .any(|e| e.satellites.iter().any(|s| s.system == *system))
    });
    Ok(ObservationFile {
        version: header.version,
        observation_types,
        approx_position_ecef: header.approx_position_ecef,
        epochs,
        // RINEX 2 has no GLONASS SLOT / FRQ # record.
        glonass_channels: BTreeMap::new(),
        warnings,
        skipped,
    })
}

impl Header<'_> {
    /// The system of a satellite whose letter is blank: GPS (RINEX 2.11
    /// §5.1: "blank or G"), or the file's own in a single-system file.
    fn file_system_default(&self) -> char {
        match self.file_system {
            'M' | ' ' => 'G',
            s => s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_map_to_rinex_3_signals() {
        let cases = [
            ('G', "C1", Some("C1C")),
            ('G', "P1", Some("C1W")),
            ('G', "P2", Some("C2W")),
            ('G', "L1", Some("L1C")),
            ('G', "L2", Some("L2W")),
            ('G', "C2", Some("C2X")),
            ('G', "S5", Some("S5X")),
            ('R', "C1", Some("C1C")),
            ('R', "P1", Some("C1P")),
            ('R', "L2", Some("L2P")),
            ('R', "D1", Some("D1C")),
            ('R', "C5", None),
            ('E', "C1", Some("C1X")),
            ('E', "L8", Some("L8X")),
            ('E', "P2", None),
            ('S', "L1", Some("L1C")),
            ('C', "C1", None),
            ('G', "T1", None),
        ];
        for (system, code, expected) in cases {
            assert_eq!(
                rinex3_code(system, code).as_deref(),
                expected,
                "{system} {code}"
            );
        }
    }
}
