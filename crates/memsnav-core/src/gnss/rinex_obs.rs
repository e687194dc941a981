//! RINEX 3 observation files (RINEX 3.05 format description, IGS/RTCM
//! 2020, §5 and tables A2-A3): header observation types per system and the
//! epoch records (pseudorange `C..`, carrier phase `L..`, Doppler `D..`,
//! signal strength `S..`), every system kept. RINEX 2.10/2.11 files share
//! the header and are read by [`super::rinex2_obs`], their codes mapped to
//! RINEX 3's. Event records (flags 2-6) are skipped and counted in
//! [`ObservationFile::skipped`]. Errors name the file, the 1-based line and
//! what was expected; a record cut short at the end of the file (a log that
//! stopped mid-write) is dropped with a warning instead.

use std::collections::BTreeMap;
use std::path::Path;

use nalgebra::Vector3;

use super::glonass_slots;
use super::observation_file::{
    event_kind, field, label, observation_value, EpochTimeSystem, ObservationEpoch,
    ObservationFile, SatelliteObservations,
};
use super::plausible::{self, observation_range_text};
use super::rinex2_obs;
use super::time::calendar_text;
use crate::{Error, Result};

/// The signals of a receiver log laid out as RINEX observations: per
/// system the signal codes present, sorted, each with the four types `C`,
/// `L`, `D`, `S` in that order (the layout memsnav's log converters write).
#[derive(Debug, Clone, Default)]
pub(crate) struct SignalLayout {
    codes: BTreeMap<char, Vec<String>>,
}

impl SignalLayout {
    /// The layout of the `(system, code)` pairs a log holds.
    pub(crate) fn new<'a>(signals: impl IntoIterator<Item = (char, &'a str)>) -> Self {
        let mut codes: BTreeMap<char, Vec<String>> = BTreeMap::new();
        for (system, code) in signals {
            let list = codes.entry(system).or_default();
            if !list.iter().any(|c| c == code) {
                list.push(code.to_string());
            }
        }
        for list in codes.values_mut() {
            list.sort_unstable();
        }
        Self { codes }
    }

    /// The header's observation types per system.
    pub(crate) fn observation_types(&self) -> BTreeMap<char, Vec<String>> {
        self.codes
            .iter()
            .map(|(&system, list)| {
                let types = list
                    .iter()
                    .flat_map(|c| ["C", "L", "D", "S"].map(|k| format!("{k}{c}")))
                    .collect();
                (system, types)
            })
            .collect()
    }

    /// The `C`, `L`, `D`, `S` values and their loss-of-lock indicators of
    /// signal `code` of satellite `system` `prn` among an epoch's
    /// `satellites`, the satellite added with blank values when it is new.
    /// `code` must be one of the layout's.
    pub(crate) fn slots<'s>(
        &self,
        satellites: &'s mut Vec<SatelliteObservations>,
        system: char,
        prn: u16,
        code: &str,
    ) -> (&'s mut [Option<f64>], &'s mut [u8]) {
        let codes = &self.codes[&system];
        let j = codes
            .iter()
            .position(|c| c == code)
            .expect("a code of the layout");
        let at = match satellites
            .iter()
            .position(|x| (x.system, x.prn) == (system, prn))
        {
            Some(at) => at,
            None => {
                let n = 4 * codes.len();
                satellites.push(SatelliteObservations {
                    system,
                    prn,
                    values: vec![None; n],
                    lli: vec![0; n],
                });
                satellites.len() - 1
            }
        };
        let sat = &mut satellites[at];
        (
            &mut sat.values[4 * j..4 * j + 4],
            &mut sat.lli[4 * j..4 * j + 4],
        )
    }
}

/// Loss-of-lock indicator bit 0: lock lost since the previous epoch, a
/// cycle slip possible (RINEX 3.05 §5.7).
pub(crate) const LLI_LOST_LOCK: u8 = 1;
/// Loss-of-lock indicator bit 1: half-cycle ambiguity (the phase may still
/// jump by half a cycle when the receiver resolves it).
pub(crate) const LLI_HALF_CYCLE: u8 = 2;

/// Reads a RINEX 3 or RINEX 2.10/2.11 observation file.
pub fn read_rinex_obs(path: impl AsRef<Path>) -> Result<ObservationFile> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|e| Error::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    parse_rinex_obs(
        &String::from_utf8_lossy(&bytes),
        &path.display().to_string(),
    )
}

/// Largest |APPROX POSITION XYZ| accepted, m (beyond geostationary orbit).
const MAX_APPROX_POSITION_M: f64 = 1e8;

/// Parses the text of a RINEX 3 or RINEX 2.10/2.11 observation file;
/// `file` names it in errors.
pub fn parse_rinex_obs(text: &str, file: &str) -> Result<ObservationFile> {
    let mut lines: Vec<&str> = text.lines().collect();
    // A file that does not end with a newline was cut mid-line: its last
    // line is not trusted (a cut number would still parse).
    let mut warnings = Vec::new();
    if !text.is_empty() && !text.ends_with('\n') && lines.len() > 1 {
        warnings.push(format!(
            "{file}:{}: the last line has no end of line (cut short); skipped",
            lines.len()
        ));
        lines.pop();
    }
    let error = |k: usize, reason: String| Error::Parse {
        file: file.to_string(),
        line: k + 1,
        reason,
    };
    let first = lines.first().copied().unwrap_or("");
    if label(first) != "RINEX VERSION / TYPE" {
        return Err(error(
            0,
            "expected 'RINEX VERSION / TYPE' in columns 61-80: not a RINEX file".into(),
        ));
    }
    let version: f64 = field(first, 0, 9)
        .parse()
        .map_err(|_| error(0, "expected the RINEX version in columns 1-9".into()))?;
    if !(2.0..4.0).contains(&version) {
        return Err(error(
            0,
            format!("unsupported RINEX version {version}: expected 2.xx or 3.xx"),
        ));
    }
    let version_2 = version < 3.0;
    if field(first, 20, 1) != "O" {
        return Err(error(
            0,
            format!(
                "expected file type 'O' (observation data) in column 21, got {:?}",
                field(first, 20, 1)
            ),
        ));
    }

    // Header.
    let mut observation_types: BTreeMap<char, Vec<String>> = BTreeMap::new();
    let mut approx_position_ecef = None;
    // RINEX 2: a GLONASS file's epochs are in GLONASS time unless the
    // header says otherwise (RINEX 2.11 §5.1).
    let file_system = field(first, 40, 1).chars().next().unwrap_or('G');
    let mut time_system = Some(if version_2 && file_system == 'R' {
        EpochTimeSystem::Utc
    } else {
        EpochTimeSystem::Gps
    });
    let mut time_system_name = String::new();
    let mut pending: Option<(char, usize)> = None;
    let mut types_2: Vec<String> = Vec::new();
    let mut pending_2: Option<usize> = None;
    let mut glonass_channels = BTreeMap::new();
    let mut glonass_listed: Option<usize> = None;
    let mut glonass_line = 0;
    let mut k = 1;
    loop {
        let Some(&line) = lines.get(k) else {
            return Err(error(
                k.saturating_sub(1),
                "end of file before 'END OF HEADER'".into(),
            ));
        };
        match label(line) {
            "END OF HEADER" => break,
            "SYS / # / OBS TYPES" => {
                // A system letter starts a list; a blank one continues it (13 types a line).
                let sys = line.chars().next().unwrap_or(' ');
                let (sys, total) = if sys == ' ' {
                    pending.ok_or_else(|| {
                        error(
                            k,
                            "a continuation 'SYS / # / OBS TYPES' line without a system".into(),
                        )
                    })?
                } else {
                    let n: usize = field(line, 3, 3).parse().map_err(|_| {
                        error(
                            k,
                            "expected the number of observation types in columns 4-6".into(),
                        )
                    })?;
                    observation_types.insert(sys, Vec::with_capacity(n));
                    (sys, n)
                };
                let list = observation_types.get_mut(&sys).expect("inserted above");
                for j in 0..13 {
                    if list.len() == total {
                        break;
                    }
                    let code = field(line, 7 + 4 * j, 3);
                    if code.len() != 3 {
                        return Err(error(
                            k,
                            format!(
                                "expected {total} observation types for system {sys}, found {}",
                                list.len()
                            ),
                        ));
                    }
                    list.push(code.to_string());
                }
                pending = (list.len() < total).then_some((sys, total));
            }
            "APPROX POSITION XYZ" => {
                let mut v = [0.0_f64; 3];
                // 3F14.4; some writers shift the columns (gLAB's 2.11
                // example): then three numbers apart in columns 1-60.
                let spaced: Vec<f64> = line
                    .get(..60)
                    .unwrap_or(line)
                    .split_whitespace()
                    .map_while(|x| x.parse().ok())
                    .collect();
                for (j, x) in v.iter_mut().enumerate() {
                    *x = match field(line, 14 * j, 14).parse() {
                        Ok(x) => x,
                        Err(_) if spaced.len() == 3 => spaced[j],
                        Err(_) => {
                            return Err(error(
                                k,
                                format!("expected coordinate {} of APPROX POSITION XYZ", j + 1),
                            ))
                        }
                    };
                }
                let p = Vector3::from(v);
                if p.norm().is_nan() || p.norm() > MAX_APPROX_POSITION_M {
                    return Err(error(
                        k,
                        format!(
                            "APPROX POSITION XYZ {:?} m is out of range (|r| ≤ {MAX_APPROX_POSITION_M:e} m)",
                            v
                        ),
                    ));
                }
                approx_position_ecef = (p.norm() > 0.0).then_some(p);
            }
            "GLONASS SLOT / FRQ #" => {
                if glonass_listed.is_none() {
                    glonass_line = k;
                }
                glonass_slots::read_slot_line(line, &mut glonass_channels, &mut glonass_listed)
                    .map_err(|reason| error(k, reason))?;
            }
            "# / TYPES OF OBSERV" if version_2 => {
                rinex2_obs::header_types(line, &mut types_2, &mut pending_2)
                    .map_err(|reason| error(k, reason))?;
            }
            "TIME OF FIRST OBS" => {
                let ts = field(line, 48, 3);
                time_system_name = ts.to_string();
                time_system = match ts {
                    "" => time_system,
                    "GPS" | "GAL" => Some(EpochTimeSystem::Gps),
                    "GLO" => Some(EpochTimeSystem::Utc),
                    _ => None,
                };
            }
            _ => {}
        }
        k += 1;
    }
    if let Some(n) = glonass_listed.filter(|&n| n != glonass_channels.len()) {
        return Err(error(
            glonass_line,
            format!(
                "GLONASS SLOT / FRQ # declares {n} satellites and lists {}",
                glonass_channels.len()
            ),
        ));
    }
    let Some(time_system) = time_system else {
        return Err(error(
            k,
            format!("time system {time_system_name:?} of TIME OF FIRST OBS is not supported: GPS, GAL or GLO"),
        ));
    };
    if version_2 {
        return rinex2_obs::parse_records(
            rinex2_obs::Header {
                file,
                version,
                file_system,
                types: &types_2,
                time_system,
                approx_position_ecef,
            },
            &lines,
            k + 1,
            warnings,
        );
    }
    if observation_types.is_empty() {
        return Err(error(
            k,
            "the header declares no 'SYS / # / OBS TYPES'".into(),
        ));
    }
    k += 1;

    let mut epochs = Vec::new();
    let mut skipped = BTreeMap::new();
    let truncated = |k: usize, what: &str| {
        format!(
            "{file}:{}: the last record is cut short ({what}); skipped",
            k + 1
        )
    };
    while k < lines.len() {
        let line = lines[k];
        if line.trim().is_empty() {
            k += 1;
            continue;
        }
        if !line.starts_with('>') {
            return Err(error(
                k,
                format!(
                    "expected an epoch line starting with '>', got {:?}",
                    line.trim_end()
                ),
            ));
        }
        let last_line = k + 1 == lines.len();
        // Flag and count first: an event record (flags 2-5) may leave the
        // epoch blank (RINEX 3.05 §5.5.1, as gfzrnx writes them).
        let event = (|| {
            let flag: u8 = field(line, 31, 1).parse().ok()?;
            let count: usize = field(line, 32, 3).parse().ok()?;
            (2..=6).contains(&flag).then_some((flag, count))
        })();
        if let Some((flag, count)) = event {
            if k + count >= lines.len() {
                warnings.push(truncated(k, "fewer event lines than announced"));
                break;
            }
            *skipped.entry(event_kind(flag)).or_default() += 1;
            k += 1 + count;
            continue;
        }
        let header_fields = (|| {
            let n = |s: usize, w: usize| field(line, s, w).parse::<i64>().ok();
            let y = n(2, 4)?;
            let mo = n(7, 2)?;
            let d = n(10, 2)?;
            let h = n(13, 2)?;
            let mi = n(16, 2)?;
            let s: f64 = field(line, 18, 11).parse().ok()?;
            let flag = n(31, 1)?;
            let count = n(32, 3)?;
            Some(((y, mo, d, h, mi, s), flag, count))
        })();
        let Some(((y, mo, d, h, mi, s), flag, count)) = header_fields else {
            if last_line {
                warnings.push(truncated(k, "incomplete epoch line"));
                break;
            }
            return Err(error(
                k,
                "expected '> yyyy mm dd hh mm ss.sssssss  f nnn' (epoch, flag, number of satellites)"
                    .into(),
            ));
        };
        // Epoch flags 0-6 (RINEX 3.05 table A13); the count is 3 digits.
        if !(0..=6).contains(&flag) {
            return Err(error(k, format!("epoch flag {flag} is out of range (0-6)")));
        }
        let Ok(count) = usize::try_from(count) else {
            return Err(error(
                k,
                format!("number of satellites {count} is negative"),
            ));
        };
        let gps_time_s = time_system
            .gps_time_s((y, mo, d, h, mi, s))
            .map_err(|reason| error(k, format!("epoch: {reason}")))?;
        if let Some(previous) = epochs.last().map(|e: &ObservationEpoch| e.gps_time_s) {
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
        if k + count >= lines.len() {
            warnings.push(truncated(k, "fewer satellite lines than announced"));
            break;
        }
        let mut satellites = Vec::with_capacity(count);
        let mut cut = false;
        for j in 1..=count {
            let sl = lines[k + j];
            let is_last = k + j + 1 == lines.len();
            let sys = sl.chars().next().unwrap_or(' ');
            let prn: Option<u16> = field(sl, 1, 2).parse().ok();
            let (Some(types), Some(prn)) = (observation_types.get(&sys), prn) else {
                if is_last {
                    cut = true;
                    break;
                }
                return Err(error(
                    k + j,
                    format!(
                        "expected a satellite 'Xnn' of a system declared in the header, got {:?}",
                        sl.get(..3).unwrap_or(sl)
                    ),
                ));
            };
            plausible::check_satellite(sys, i64::from(prn))
                .map_err(|reason| error(k + j, reason))?;
            // A satellite's second line (a relabelled one) would give it
            // two sets of values, or another satellite's: refused.
            if let Some(first) = satellites
                .iter()
                .position(|o: &SatelliteObservations| o.system == sys && o.prn == prn)
            {
                return Err(error(
                    k + j,
                    format!(
                        "{sys}{prn:02} has a second observation line in epoch {} (the first is on line {}): one line per satellite and epoch",
                        calendar_text(y, mo, d, h, mi, s),
                        k + first + 2
                    ),
                ));
            }
            let mut values = Vec::with_capacity(types.len());
            let mut lli = vec![0; types.len()];
            for (i, code) in types.iter().enumerate() {
                // Each observation: F14.3, then LLI and signal strength digits.
                match observation_value(sl, 3 + 16 * i, code) {
                    Ok(None) => values.push(None),
                    Ok(Some((v, indicator))) => {
                        values.push(Some(v));
                        lli[i] = indicator;
                    }
                    Err(_) if is_last => {
                        cut = true;
                        break;
                    }
                    Err(f) => {
                        return Err(error(
                            k + j,
                            format!(
                                "expected a number for {sys}{prn:02} {code} in columns {}-{} ({}), got {f:?}",
                                4 + 16 * i,
                                17 + 16 * i,
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
                system: sys,
                prn,
                values,
                lli,
            });
        }
        if cut {
            warnings.push(truncated(k + count, "incomplete satellite line"));
            break;
        }
        epochs.push(ObservationEpoch {
            gps_time_s,
            flag: flag as u8,
            satellites,
        });
        k += 1 + count;
    }
    Ok(ObservationFile {
        version,
        observation_types,
        approx_position_ecef,
        epochs,
        glonass_channels,
        warnings,
        skipped,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str =
        "     3.04           OBSERVATION DATA    M: Mixed            RINEX VERSION / TYPE
 -1276965.2487 -4717231.7278  4087230.1460                  APPROX POSITION XYZ 
G    4 C1C L1C D1C S1C                                      SYS / # / OBS TYPES 
E    2 C1C S1C                                              SYS / # / OBS TYPES 
  2025    08    28    17    30   39.7480000     GPS         TIME OF FIRST OBS   
                                                            END OF HEADER       
";

    #[test]
    fn reads_fields_and_skips_blanks() {
        let text = format!(
            "{HEADER}> 2025 08 28 17 30 39.7480000  0  2\n\
G10  20576396.770   108129693.9341       1064.326          51.000  \n\
E07  23205808.406                  \n"
        );
        let f = parse_rinex_obs(&text, "x.obs").unwrap();
        assert_eq!(f.observation_types[&'G'], ["C1C", "L1C", "D1C", "S1C"]);
        let p = f.approx_position_ecef.unwrap();
        assert_eq!(p, Vector3::new(-1276965.2487, -4717231.7278, 4087230.1460));
        assert_eq!(f.epochs.len(), 1);
        let e = &f.epochs[0];
        // 2025-08-28 is GPS week 2381, Thursday: 4 days + 17:30:39.748.
        let expected = 2381.0 * 604_800.0 + 4.0 * 86_400.0 + 17.0 * 3600.0 + 30.0 * 60.0 + 39.748;
        assert!((e.gps_time_s - expected).abs() < 1e-6);
        assert_eq!(e.satellites[0].prn, 10);
        assert_eq!(
            e.satellites[0].values,
            [
                Some(20576396.770),
                Some(108129693.934),
                Some(1064.326),
                Some(51.0)
            ]
        );
        assert_eq!((e.satellites[1].system, e.satellites[1].prn), ('E', 7));
        assert_eq!(e.satellites[1].values, [Some(23205808.406), None]);
        assert!(f.warnings.is_empty());
    }

    #[test]
    fn truncated_last_record_is_a_warning_and_a_bad_field_an_error() {
        let text = format!(
            "{HEADER}> 2025 08 28 17 30 39.7480000  0  1\nG10  20576396.770\n> 2025 08 28 17 30 39.9980000  0  2\nG10  20576396.770\n"
        );
        let f = parse_rinex_obs(&text, "x.obs").unwrap();
        assert_eq!(f.epochs.len(), 1);
        assert_eq!(f.warnings.len(), 1);
        assert!(f.warnings[0].contains("x.obs:9"), "{}", f.warnings[0]);

        let text = format!(
            "{HEADER}> 2025 08 28 17 30 39.7480000  0  1\nG10  2057x396.770\n> 2025 08 28 17 30 39.9980000  0  1\nG10  1.0\n"
        );
        match parse_rinex_obs(&text, "x.obs") {
            Err(Error::Parse { file, line, reason }) => {
                assert_eq!((file.as_str(), line), ("x.obs", 8));
                assert!(reason.contains("G10 C1C"), "{reason}");
            }
            other => panic!("{other:?}"),
        }
        let text = HEADER.replace("OBSERVATION DATA", "NAVIGATION DATA ");
        let err = parse_rinex_obs(&text, "x").unwrap_err();
        assert!(err.to_string().contains("file type"), "{err}");
    }

    /// Event records of every flag, their epochs blank as gfzrnx writes a
    /// merge's header change (flag 4), are skipped and counted; their
    /// lines are never read as observations.
    #[test]
    fn event_records_are_skipped_and_counted() {
        let record = "> 2025 08 28 17 30 39.7480000  0  1\nG10  20576396.770\n";
        let events = ">                              4  2\n\
                                                            COMMENT             \n\
G    2 C1C L1C                                              SYS / # / OBS TYPES \n\
> 2025 08 28 17 30 39.8000000  5  0\n\
> 2025 08 28 17 30 39.8500000  6  1\n\
G10  20576396.770\n";
        let next = "> 2025 08 28 17 30 39.9980000  1  1\nG10  20576397.770\n";
        let f = parse_rinex_obs(&format!("{HEADER}{record}{events}{next}"), "x.obs").unwrap();
        assert_eq!(f.epochs.len(), 2);
        assert_eq!(f.epochs[1].flag, 1);
        assert_eq!(f.epochs[1].satellites[0].values[0], Some(20576397.770));
        for flag in [4, 5, 6] {
            assert_eq!(f.skipped[&event_kind(flag)], 1, "{:?}", f.skipped);
        }
        // An event announcing more lines than the file holds: cut short.
        let cut = format!("{HEADER}{record}>                              4  9\n");
        let f = parse_rinex_obs(&cut, "x.obs").unwrap();
        assert_eq!((f.epochs.len(), f.warnings.len()), (1, 1));
    }

    #[test]
    fn one_line_per_satellite_and_epoch() {
        let record = "> 2025 08 28 17 30 39.7480000  0  3\n\
G10  20576396.770\n\
G12  21576396.770\n\
E07  23205808.406\n";
        let duplicated = record.replacen("G12  21576396.770", "G10  20576396.770", 1);
        let relabelled = record.replacen("G12", "G10", 1);
        // G 1 is G01, the same satellite however its number is padded.
        let padded = record.replacen("G10", "G 1", 1).replacen("G12", "G01", 1);
        for (records, name) in [(duplicated, "G10"), (relabelled, "G10"), (padded, "G01")] {
            assert_eq!(
                parse_rinex_obs(&format!("{HEADER}{records}"), "x.obs")
                    .unwrap_err()
                    .to_string(),
                format!(
                    "x.obs:9: {name} has a second observation line in epoch \
                     2025-08-28 17:30:39.748 (the first is on line 8): one line per \
                     satellite and epoch"
                )
            );
        }
        // The same PRN in another system is another satellite.
        let text = format!("{HEADER}{}", record.replacen("E07", "E10", 1));
        let f = parse_rinex_obs(&text, "x.obs").unwrap();
        assert_eq!(f.epochs[0].satellites.len(), 3);
    }

    #[test]
    fn out_of_range_epochs_counts_and_values_name_line_and_field() {
        let record = "> 2025 08 28 17 30 39.7480000  0  1\nG10  20576396.770\n";
        let next = "> 2025 08 28 17 30 39.9980000  0  1\nG10  20576396.770\n";
        // (the records after the header, the line at fault, what is said)
        let cases = [
            // A negative count used to panic (usize overflow).
            (
                record.replace("0  1\n", "0 -1\n") + next,
                7,
                "number of satellites -1 is negative",
            ),
            (
                record.replace("2025 08", "2025 13") + next,
                7,
                "epoch: month 13 is out of range",
            ),
            (
                record.replace("28 17", "28 25") + next,
                7,
                "epoch: hour 25 is out of range",
            ),
            (
                record.replace("> 2025", ">    0") + next,
                7,
                "epoch: year 0 is out of range",
            ),
            (
                record.replace("0  1\n", "9  1\n") + next,
                7,
                "epoch flag 9 is out of range",
            ),
            (
                record.replace("20576396.770", "       1e300") + next,
                8,
                "G10 C1C in columns 4-17 (0 to 1e8 m)",
            ),
            (
                record.replace("20576396.770", "  -20576.770") + next,
                8,
                "(0 to 1e8 m)",
            ),
            (
                record.to_string() + &next.replace("39.998", "38.998") + next,
                9,
                "does not follow the previous epoch",
            ),
        ];
        for (records, line, words) in cases {
            let e = parse_rinex_obs(&format!("{HEADER}{records}"), "x.obs").unwrap_err();
            let message = e.to_string();
            assert!(
                message.starts_with(&format!("x.obs:{line}: ")) && message.contains(words),
                "{message}"
            );
        }
        let header = HEADER.replace("-1276965.2487", "      1.0e300");
        let e = parse_rinex_obs(&format!("{header}{record}"), "x.obs").unwrap_err();
        assert!(
            e.to_string().contains("x.obs:2: APPROX POSITION XYZ"),
            "{e}"
        );
    }
}
