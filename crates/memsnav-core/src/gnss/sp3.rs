//! SP3-c/d precise orbit files (positions in km, clocks in µs, GPS time):
//! read into SI units for checking broadcast orbits.

use std::path::Path;

use nalgebra::Vector3;

use super::time::{calendar_text, checked_gps_time_from_calendar};
use crate::{Error, Result};

/// Precise orbits: `n_epochs × n_satellites` positions (ECEF, m, centre
/// of mass) and clocks (s), NaN where the file marks a value missing.
#[derive(Debug, Clone, PartialEq)]
pub struct Sp3 {
    /// Epochs, GPS s since 1980-01-06.
    pub time_gps_s: Vec<f64>,
    /// Satellite names as in the file ("G01", "E05", ...).
    pub satellites: Vec<String>,
    /// Row-major `[epoch * n_satellites + satellite]`, m.
    pub position_ecef: Vec<Vector3<f64>>,
    /// Row-major like `position_ecef`, s.
    pub clock_s: Vec<f64>,
}

impl Sp3 {
    /// Position of satellite `sat` at epoch `epoch`, m (NaN if missing).
    pub fn position(&self, epoch: usize, sat: usize) -> Vector3<f64> {
        self.position_ecef[epoch * self.satellites.len() + sat]
    }

    /// Clock of satellite `sat` at epoch `epoch`, s (NaN if missing).
    pub fn clock(&self, epoch: usize, sat: usize) -> f64 {
        self.clock_s[epoch * self.satellites.len() + sat]
    }
}

/// Largest |coordinate| accepted, km (beyond geostationary orbit, 42 164 km).
const MAX_COORDINATE_KM: f64 = 1e5;

/// Most satellites × epochs an [`Sp3`] may hold (a day of 30-s orbits of
/// every GNSS satellite is under 0.5 million): more is a corrupted header,
/// refused before it allocates gigabytes.
const MAX_SATELLITE_EPOCHS: usize = 10_000_000;

/// System letters of SP3 satellite names: G GPS, R GLONASS, E Galileo,
/// C BeiDou, J QZSS, I NavIC, S SBAS (those the RINEX readers know) and L,
/// SP3's low Earth orbiters.
const SYSTEM_LETTERS: &str = "GRECJISL";

/// Whether `name` (blanks already read as zeros) is a satellite of the
/// header's list: a system letter and a number 01-99 ("G05"). A name like
/// "C3." or "G,1" is a damaged header, not a satellite: refused even when
/// no record names it.
fn is_satellite_name(name: &str) -> bool {
    let b = name.as_bytes();
    b.len() == 3
        && SYSTEM_LETTERS.as_bytes().contains(&b[0])
        && b[1..].iter().all(u8::is_ascii_digit)
        && &b[1..] != b"00"
}

/// Reads an SP3-c or SP3-d file (GPS time system).
pub fn read_sp3(path: impl AsRef<Path>) -> Result<Sp3> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|e| Error::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    parse_sp3(
        &String::from_utf8_lossy(&bytes),
        &path.display().to_string(),
    )
}

/// Parses the text of an SP3-c or SP3-d file; `file` names it in errors.
pub fn parse_sp3(text: &str, file: &str) -> Result<Sp3> {
    let err = |k: usize, reason: String| Error::Parse {
        file: file.to_string(),
        line: k + 1,
        reason,
    };
    let field = |line: &str, a: usize, b: usize| {
        line.get(a..b.min(line.len()))
            .unwrap_or("")
            .trim()
            .to_string()
    };
    let num = |line: &str, k: usize, a: usize, b: usize, what: &str| -> Result<f64> {
        let f = field(line, a, b);
        f.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| {
                err(
                    k,
                    format!(
                        "expected a number for {what} in columns {}-{}, got {f:?}",
                        a + 1,
                        b
                    ),
                )
            })
    };
    let lines: Vec<&str> = text.lines().collect();
    let first = lines.first().copied().unwrap_or("");
    if !(first.starts_with("#c") || first.starts_with("#d")) {
        return Err(err(
            0,
            "expected an SP3-c or SP3-d header ('#c' or '#d')".into(),
        ));
    }
    let mut satellites: Vec<String> = Vec::new();
    let mut declared = None;
    let mut time_gps_s = Vec::new();
    let mut position_ecef = Vec::new();
    let mut clock_s = Vec::new();
    let mut time_system_seen = false;
    // The current epoch as read (for messages), and the line of each
    // satellite's position record in it: a second record would silently
    // replace the first.
    let mut epoch = (0, 0, 0, 0, 0, 0.0);
    let mut record_line: Vec<Option<usize>> = Vec::new();
    for (k, line) in lines.iter().enumerate().skip(1) {
        if line.starts_with("+ ") {
            if declared.is_none() {
                let n = num(line, k, 1, 6, "the number of satellites")?;
                if !(n.fract() == 0.0 && (1.0..=999.0).contains(&n)) {
                    return Err(err(
                        k,
                        format!("number of satellites {n} is out of range (1-999)"),
                    ));
                }
                declared = Some(n as usize);
            }
            let mut c = 9;
            while c + 3 <= line.len().min(60) {
                let id = field(line, c, c + 3);
                if !id.is_empty()
                    && id != "0"
                    && id != "00"
                    && satellites.len() < declared.unwrap_or(0)
                {
                    let name = id.replace(' ', "0");
                    if !is_satellite_name(&name) {
                        return Err(err(
                            k,
                            format!(
                                "satellite name {id:?} in columns {}-{} is not a system letter ({SYSTEM_LETTERS}) and a number 01-99",
                                c + 1,
                                c + 3
                            ),
                        ));
                    }
                    if satellites.contains(&name) {
                        return Err(err(
                            k,
                            format!("satellite {name} is listed twice in the header"),
                        ));
                    }
                    satellites.push(name);
                }
                c += 3;
            }
        } else if line.starts_with("%c") && !time_system_seen {
            time_system_seen = true;
            let system = field(line, 9, 12);
            if system != "GPS" && system != "ccc" {
                return Err(err(
                    k,
                    format!("time system {system:?} is not supported: expected GPS"),
                ));
            }
        } else if line.starts_with('*') {
            if satellites.len() != declared.unwrap_or(0) || satellites.is_empty() {
                return Err(err(
                    k,
                    "epoch before a complete satellite list in the header".into(),
                ));
            }
            let year = num(line, k, 3, 7, "year")? as i64;
            let month = num(line, k, 8, 10, "month")? as i64;
            let day = num(line, k, 11, 13, "day")? as i64;
            let hour = num(line, k, 14, 16, "hour")? as i64;
            let minute = num(line, k, 17, 19, "minute")? as i64;
            let second = num(line, k, 20, 31, "second")?;
            let t = checked_gps_time_from_calendar(year, month, day, hour, minute, second)
                .map_err(|reason| err(k, format!("epoch: {reason}")))?;
            if let Some(&previous) = time_gps_s.last() {
                if t <= previous {
                    return Err(err(
                        k,
                        format!(
                            "epoch {} does not follow the previous epoch: epochs must increase",
                            calendar_text(year, month, day, hour, minute, second)
                        ),
                    ));
                }
            }
            if (time_gps_s.len() + 1) * satellites.len() > MAX_SATELLITE_EPOCHS {
                return Err(err(
                    k,
                    format!(
                        "more than {MAX_SATELLITE_EPOCHS} satellite-epochs ({} satellites): too large for an orbit file",
                        satellites.len()
                    ),
                ));
            }
            time_gps_s.push(t);
            position_ecef.extend(std::iter::repeat_n(
                Vector3::repeat(f64::NAN),
                satellites.len(),
            ));
            clock_s.extend(std::iter::repeat_n(f64::NAN, satellites.len()));
            epoch = (year, month, day, hour, minute, second);
            record_line.clear();
            record_line.resize(satellites.len(), None);
        } else if line.starts_with('P') {
            if time_gps_s.is_empty() {
                return Err(err(
                    k,
                    "position record before the first epoch line ('*')".into(),
                ));
            }
            let id = field(line, 1, 4).replace(' ', "0");
            let s = satellites
                .iter()
                .position(|x| *x == id)
                .ok_or_else(|| err(k, format!("satellite {id:?} is not in the header's list")))?;
            if let Some(first) = record_line[s] {
                let (year, month, day, hour, minute, second) = epoch;
                return Err(err(
                    k,
                    format!(
                        "{id} has a second position record in epoch {} (the first is on line {}): one record per satellite and epoch",
                        calendar_text(year, month, day, hour, minute, second),
                        first + 1
                    ),
                ));
            }
            record_line[s] = Some(k);
            let x = num(line, k, 4, 18, "x")?;
            let y = num(line, k, 18, 32, "y")?;
            let z = num(line, k, 32, 46, "z")?;
            let clock = num(line, k, 46, 60, "clock")?;
            for (name, value) in [("x", x), ("y", y), ("z", z)] {
                if value.abs() > MAX_COORDINATE_KM {
                    return Err(err(
                        k,
                        format!(
                            "{id} {name} = {value:e} km is out of range (±{MAX_COORDINATE_KM:e} km)"
                        ),
                    ));
                }
            }
            // 999999.999999 marks a missing clock; anything beyond is garbage.
            if clock.abs() > 1e6 {
                return Err(err(
                    k,
                    format!("{id} clock = {clock:e} µs is out of range (±999999.999999 µs)"),
                ));
            }
            let row = (time_gps_s.len() - 1) * satellites.len() + s;
            // SP3 marks a missing position with 0.000000 and a missing
            // clock with 999999.999999.
            if x != 0.0 || y != 0.0 || z != 0.0 {
                position_ecef[row] = Vector3::new(x, y, z) * 1e3;
            }
            if clock.abs() < 999_999.0 {
                clock_s[row] = clock * 1e-6;
            }
        }
    }
    if time_gps_s.is_empty() {
        return Err(err(
            lines.len().saturating_sub(1),
            "no epoch in the file".into(),
        ));
    }
    Ok(Sp3 {
        time_gps_s,
        satellites,
        position_ecef,
        clock_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "#dP2021  4 28  0  0  0.00000000       2 ORBIT IGb14 HLM  COD
+    2   G01G02  0  0  0  0  0  0  0  0  0  0  0  0  0  0  0
%c M  cc GPS ccc cccc cccc cccc cccc ccccc ccccc ccccc ccccc
";
    const EPOCH: &str = "*  2021  4 28  0  5  0.00000000\n";
    const G01: &str = "PG01  13848.512383 -22211.297941   6208.223406    -35.472146\n";
    const G02: &str = "PG02 -17005.224919   3838.417103 -20029.707301    -19.893417\n";

    fn message(text: &str) -> String {
        parse_sp3(text, "x.sp3").unwrap_err().to_string()
    }

    #[test]
    fn one_record_per_satellite_and_epoch() {
        let sp3 = parse_sp3(&format!("{HEADER}{EPOCH}{G02}{G01}"), "x.sp3").unwrap();
        assert_eq!(sp3.position(0, 0).x, 13_848_512.383);
        // The same record twice, and G02's line relabelled G01: refused,
        // not the second values in place of the first.
        let relabelled = G02.replace("PG02", "PG01");
        for second in [G01, relabelled.as_str()] {
            assert_eq!(
                message(&format!("{HEADER}{EPOCH}{G01}{second}")),
                "x.sp3:6: G01 has a second position record in epoch 2021-04-28 00:05:00 \
                 (the first is on line 5): one record per satellite and epoch"
            );
        }
        // The same satellite in the next epoch is its next record.
        let next = EPOCH.replace(" 5  0.", "10  0.");
        let sp3 = parse_sp3(&format!("{HEADER}{EPOCH}{G01}{next}{G01}"), "x.sp3").unwrap();
        assert_eq!(sp3.time_gps_s.len(), 2);
        assert!(sp3.position(1, 1).x.is_nan());
    }

    #[test]
    fn header_names_are_satellites_listed_once() {
        // (the header's list, what is said of it on line 2)
        let cases = [
            (
                "G01Cnf",
                r#"satellite name "Cnf" in columns 13-15 is not a system letter"#,
            ),
            ("G01C3.", r#"satellite name "C3." in columns 13-15"#),
            ("G,1G02", r#"satellite name "G,1" in columns 10-12"#),
            ("G01X05", r#"satellite name "X05" in columns 13-15"#),
            ("G01G00", r#"satellite name "G00" in columns 13-15"#),
            ("G01G01", "satellite G01 is listed twice in the header"),
        ];
        for (list, words) in cases {
            let text = format!("{HEADER}{EPOCH}{G01}").replacen("G01G02", list, 1);
            let message = message(&text);
            assert!(
                message.starts_with("x.sp3:2: ") && message.contains(words),
                "{message}"
            );
        }
        // Every system letter, a blank-padded number, the unused slots.
        let text = format!("{HEADER}{EPOCH}{G01}").replace(
            "G01G02  0  0  0  0  0  0  0  0",
            "G01R 2E03C04J05I06S07L08  0  0",
        );
        let text = text.replacen("+    2", "+    8", 1);
        let sp3 = parse_sp3(&text, "x.sp3").unwrap();
        assert_eq!(
            sp3.satellites,
            ["G01", "R02", "E03", "C04", "J05", "I06", "S07", "L08"]
        );
    }
}
