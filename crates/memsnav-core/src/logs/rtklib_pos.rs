//! RTKLIB solution files (`.pos`, RTKLIB 2.4.3 `solution.c` `outsols`)
//! written with GPST date and time and latitude/longitude/height: the
//! header line `%  GPST  latitude(deg) longitude(deg) height(m) Q ns
//! sdn(m) ... ratio`, optionally followed by the velocity columns of
//! RTKLIB demo5 (`vn(m/s) ve(m/s) vu(m/s) sdvn ... sdvun`).

use std::path::Path;

use nalgebra::Vector3;

use super::fields::{finite_number, in_range, parse_error};
use super::pos_solution::{MAX_STD, QUALITY_RANGE};
use super::PosSolution;
use crate::gnss::{calendar_from_gps_time, checked_gps_time_from_calendar};
use crate::{Error, Result};

/// Ellipsoidal heights accepted, m: a receiver's
/// ([`crate::gnss::plausible::HEIGHT_M`]).
pub use crate::gnss::plausible::HEIGHT_M as POS_HEIGHT_RANGE_M;

/// Largest velocity component accepted, m/s: a receiver's
/// ([`crate::gnss::plausible::MAX_SPEED_M_S`]).
pub use crate::gnss::plausible::MAX_SPEED_M_S;

/// The columns after the GPST date and time, as RTKLIB names them in the
/// header; the velocity columns (RTKLIB demo5) from [`VELOCITY_COLUMN`] on.
const COLUMNS: [&str; 22] = [
    "latitude(deg)",
    "longitude(deg)",
    "height(m)",
    "Q",
    "ns",
    "sdn(m)",
    "sde(m)",
    "sdu(m)",
    "sdne(m)",
    "sdeu(m)",
    "sdun(m)",
    "age(s)",
    "ratio",
    "vn(m/s)",
    "ve(m/s)",
    "vu(m/s)",
    "sdvn",
    "sdve",
    "sdvu",
    "sdvne",
    "sdveu",
    "sdvun",
];
const VELOCITY_COLUMN: usize = 13;

/// Reads an RTKLIB `.pos` file.
pub fn read_pos(path: impl AsRef<Path>) -> Result<PosSolution> {
    let path = path.as_ref();
    parse_pos(
        &String::from_utf8_lossy(&super::read_bytes(path)?),
        &path.display().to_string(),
    )
}

/// Physical range, unit and kind of each numeric column after date and time.
fn column_range(name: &str) -> (std::ops::RangeInclusive<f64>, &'static str) {
    match name {
        "latitude(deg)" => (-90.0..=90.0, "°"),
        "longitude(deg)" => (-180.0..=180.0, "°"),
        "height(m)" => (POS_HEIGHT_RANGE_M, "m"),
        "Q" => (QUALITY_RANGE, ""),
        "ns" => (0.0..=255.0, ""),
        "sdn(m)" | "sde(m)" | "sdu(m)" => (0.0..=MAX_STD, "m"),
        "sdvn" | "sdve" | "sdvu" => (0.0..=MAX_STD, "m/s"),
        "age(s)" => (0.0..=1e9, "s"),
        "ratio" => (0.0..=1e9, ""),
        "vn(m/s)" | "ve(m/s)" | "vu(m/s)" => (-MAX_SPEED_M_S..=MAX_SPEED_M_S, "m/s"),
        // Signed square roots of the covariances.
        _ => (-MAX_STD..=MAX_STD, ""),
    }
}

/// `yyyy/mm/dd` and `hh:mm:ss.sss` as GPS seconds, range-checked.
fn gps_seconds(date: &str, clock: &str) -> std::result::Result<f64, String> {
    let expected = || format!("expected 'yyyy/mm/dd hh:mm:ss.sss', got {date:?} {clock:?}");
    let d: Vec<i64> = date
        .split('/')
        .map(|x| x.parse::<i64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| expected())?;
    let c: Vec<&str> = clock.split(':').collect();
    if d.len() != 3 || c.len() != 3 {
        return Err(expected());
    }
    let (Ok(hour), Ok(minute), Some(second)) = (
        c[0].parse::<i64>(),
        c[1].parse::<i64>(),
        finite_number(c[2]),
    ) else {
        return Err(expected());
    };
    checked_gps_time_from_calendar(d[0], d[1], d[2], hour, minute, second)
}

/// Parses the text of an RTKLIB `.pos` file; `file` names it in errors.
/// Each field is range-checked (latitude ±90°, longitude ±180°, height in
/// [`POS_HEIGHT_RANGE_M`], Q 0-7, stds ≥ 0, speeds ≤ [`MAX_SPEED_M_S`]);
/// times must increase. The last line is skipped with a warning when it
/// has no end of line or does not parse.
pub fn parse_pos(text: &str, file: &str) -> Result<PosSolution> {
    let lines: Vec<&str> = text.lines().collect();
    let Some(header) = lines
        .iter()
        .position(|s| s.starts_with('%') && s.contains("latitude(deg)"))
    else {
        return Err(parse_error(
            file,
            1,
            "expected a '%  GPST  latitude(deg) longitude(deg) height(m) Q ns ...' header (RTKLIB solution with GPST date/time and lat/lon/height)",
        ));
    };
    let names: Vec<&str> = lines[header]
        .trim_start_matches('%')
        .split_whitespace()
        .collect();
    if names.first() != Some(&"GPST") {
        return Err(parse_error(
            file,
            header + 1,
            format!(
                "expected times in GPST, got {:?}",
                names.first().unwrap_or(&"")
            ),
        ));
    }
    let has_velocity = names.contains(&"vn(m/s)");
    let expected = &COLUMNS[..if has_velocity {
        COLUMNS.len()
    } else {
        VELOCITY_COLUMN
    }];
    if names[1..] != *expected {
        return Err(parse_error(
            file,
            header + 1,
            format!(
                "expected the columns GPST {}, got {}",
                expected.join(" "),
                names.join(" ")
            ),
        ));
    }
    let n_fields = expected.len() + 2;
    let mut warnings = Vec::new();
    let mut data: Vec<usize> = (header + 1..lines.len())
        .filter(|&k| !lines[k].trim().is_empty() && !lines[k].starts_with('%'))
        .collect();
    if !text.ends_with('\n') && data.last() == Some(&(lines.len() - 1)) {
        warnings.push(format!(
            "{file}:{}: last line cut short (no end of line: the file stopped mid-line); skipped",
            lines.len()
        ));
        data.pop();
    }
    let mut sol = PosSolution::with_capacity(data.len());
    let parse_line = |line: &str| -> std::result::Result<(f64, Vec<f64>), String> {
        let f: Vec<&str> = line.split_whitespace().collect();
        if f.len() != n_fields {
            return Err(format!(
                "expected {n_fields} fields (date, time, {}), got {}",
                expected.join(", "),
                f.len()
            ));
        }
        let t = gps_seconds(f[0], f[1])?;
        let mut values = Vec::with_capacity(expected.len());
        for (j, name) in expected.iter().enumerate() {
            let x = finite_number(f[j + 2]).ok_or_else(|| {
                format!(
                    "field {} ({name}): expected a finite number, got {:?}",
                    j + 3,
                    f[j + 2]
                )
            })?;
            let (range, unit) = column_range(name);
            in_range(x, range, name, unit).map_err(|e| format!("field {}: {e}", j + 3))?;
            if matches!(*name, "Q" | "ns") && x.fract() != 0.0 {
                return Err(format!(
                    "field {} ({name}): expected an integer, got {x}",
                    j + 3
                ));
            }
            values.push(x);
        }
        Ok((t, values))
    };
    for (i, &k) in data.iter().enumerate() {
        let (t, v) = match parse_line(lines[k]) {
            Ok(parsed) => parsed,
            Err(reason) if i + 1 == data.len() => {
                warnings.push(format!(
                    "{file}:{}: last line cut short ({reason}); skipped",
                    k + 1
                ));
                break;
            }
            Err(reason) => return Err(parse_error(file, k + 1, reason)),
        };
        if let Some(&previous) = sol.gps_time_s.last() {
            if t <= previous {
                return Err(parse_error(
                    file,
                    k + 1,
                    format!(
                        "time {t:.3} s (GPS) does not follow the previous epoch's {previous:.3} s: epochs must increase"
                    ),
                ));
            }
        }
        sol.gps_time_s.push(t);
        sol.lla
            .push(Vector3::new(v[0].to_radians(), v[1].to_radians(), v[2]));
        sol.quality.push(v[3] as u8);
        sol.n_satellites.push(v[4] as u16);
        sol.std_ned_m.push(Vector3::new(v[5], v[6], v[7]));
        if has_velocity {
            sol.velocity_ned_m_s
                .push(Vector3::new(v[13], v[14], -v[15]));
            sol.velocity_std_ned_m_s
                .push(Vector3::new(v[16], v[17], v[18]));
        } else {
            sol.velocity_ned_m_s.push(Vector3::repeat(f64::NAN));
            sol.velocity_std_ned_m_s.push(Vector3::repeat(f64::NAN));
        }
    }
    if sol.gps_time_s.is_empty() {
        return Err(parse_error(
            file,
            lines.len().max(1),
            "expected at least one solution line",
        ));
    }
    sol.warnings = warnings;
    Ok(sol)
}

/// The header RTKLIB 2.4.3 demo5 writes for GPST, lat/lon/height and velocity.
const HEADER: &str = "%  GPST                  latitude(deg) longitude(deg)  height(m)   Q  ns   sdn(m)   sde(m)   sdu(m)  sdne(m)  sdeu(m)  sdun(m) age(s)  ratio    vn(m/s)    ve(m/s)    vu(m/s)      sdvn     sdve     sdvu    sdvne    sdveu    sdvun";

/// The text of a `.pos` file (GPST, lat/lon/height and the velocity
/// columns) that [`parse_pos`] and RTKLIB's `rtkplot` read; times rounded
/// to the millisecond. Every value must be finite and in the reader's
/// ranges, so that what is written can be read back.
pub fn format_pos(solution: &PosSolution, program: &str) -> Result<String> {
    let n = solution.gps_time_s.len();
    let lengths = [
        ("lla", solution.lla.len()),
        ("quality", solution.quality.len()),
        ("n_satellites", solution.n_satellites.len()),
        ("std_ned", solution.std_ned_m.len()),
        ("velocity_ned", solution.velocity_ned_m_s.len()),
        ("velocity_std_ned", solution.velocity_std_ned_m_s.len()),
    ];
    for (name, len) in lengths {
        crate::validate::same_length(name, len, "gps_time", n)?;
    }
    crate::validate::increasing_times("gps_time", &solution.gps_time_s)?;
    if program.contains('\n') {
        return Err(Error::invalid("program", "must be one line"));
    }
    let mut out = format!("% program   : {program}\n{HEADER}\n");
    for k in 0..n {
        let t = solution.gps_time_s[k];
        let (lat, lon, h) = (
            solution.lla[k].x.to_degrees(),
            solution.lla[k].y.to_degrees(),
            solution.lla[k].z,
        );
        let s = solution.std_ned_m[k];
        let v = solution.velocity_ned_m_s[k];
        let sv = solution.velocity_std_ned_m_s[k];
        let checks = [
            ("gps_time", t, 0.0..=1e10),
            ("lla latitude (deg)", lat, -90.0..=90.0),
            ("lla longitude (deg)", lon, -180.0..=180.0),
            ("lla height", h, POS_HEIGHT_RANGE_M),
            ("quality", f64::from(solution.quality[k]), QUALITY_RANGE),
        ];
        for (name, x, range) in checks {
            in_range(x, range, name, "")
                .map_err(|e| Error::invalid(name, format!("row {k}: {e}")))?;
        }
        for (name, x, range) in [
            ("std_ned", s, 0.0..=MAX_STD),
            ("velocity_std_ned", sv, 0.0..=MAX_STD),
        ] {
            if !x.iter().all(|c| range.contains(c)) {
                return Err(Error::invalid(
                    name,
                    format!("row {k}: {x:?} must be finite and in 0..{MAX_STD}"),
                ));
            }
        }
        if !v.iter().all(|c| c.abs() <= MAX_SPEED_M_S) {
            return Err(Error::invalid(
                "velocity_ned",
                format!("row {k}: {v:?} must be finite and within ±{MAX_SPEED_M_S} m/s"),
            ));
        }
        let total_ms = (t * 1000.0).round() as i64;
        let (y, mo, d, _, _, _) =
            calendar_from_gps_time((total_ms.div_euclid(86_400_000) * 86_400) as f64);
        let ms_of_day = total_ms.rem_euclid(86_400_000);
        let (hh, mm, ss, ms) = (
            ms_of_day / 3_600_000,
            ms_of_day / 60_000 % 60,
            ms_of_day / 1000 % 60,
            ms_of_day % 1000,
        );
        let zero = 0.0_f64;
        out.push_str(&format!(
            "{y:04}/{mo:02}/{d:02} {hh:02}:{mm:02}:{ss:02}.{ms:03} {lat:14.9} {lon:14.9} {h:10.4} {:3} {:3} \
             {:8.4} {:8.4} {:8.4} {zero:8.4} {zero:8.4} {zero:8.4} {zero:6.2} {zero:6.1} \
             {:10.5} {:10.5} {:10.5} {:9.5} {:9.5} {:9.5} {zero:9.5} {zero:9.5} {zero:9.5}\n",
            solution.quality[k],
            solution.n_satellites[k],
            s.x,
            s.y,
            s.z,
            v.x,
            v.y,
            -v.z,
            sv.x,
            sv.y,
            sv.z,
        ));
    }
    Ok(out)
}

/// Writes [`format_pos`] to `path`.
pub fn write_pos(path: impl AsRef<Path>, solution: &PosSolution, program: &str) -> Result<()> {
    let path = path.as_ref();
    let text = format_pos(solution, program)?;
    std::fs::write(path, text).map_err(|e| Error::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = "% program : x\n%  GPST latitude(deg) longitude(deg) height(m) Q ns sdn(m) sde(m) sdu(m) sdne(m) sdeu(m) sdun(m) age(s) ratio vn(m/s) ve(m/s) vu(m/s) sdvn sdve sdvu sdvne sdveu sdvun\n";
    const LINE: &str = "2025/08/28 17:30:39.749 40.0966916 -105.1471665 1601.4350000 1 25 0.0098995 0.0098995 0.0100000 0 0 0 0 0 0.001 -0.002 0.027 0.0494975 0.0494975 0.0494975 0 0 0\n";

    fn with(second_line: &str) -> String {
        format!(
            "{HEAD}{LINE}{second_line}{}",
            LINE.replace("39.749", "41.000")
        )
    }

    #[test]
    fn fields_and_round_trip() {
        let sol = parse_pos(&format!("{HEAD}{LINE}"), "x.pos").unwrap();
        let week_2381_thursday = 2381.0 * 604_800.0 + 4.0 * 86_400.0;
        assert!((sol.gps_time_s[0] - (week_2381_thursday + 63_039.749)).abs() < 1e-6);
        assert_eq!(sol.lla[0].z, 1601.435);
        assert!((sol.lla[0].x - 40.0966916_f64.to_radians()).abs() < 1e-15);
        assert_eq!((sol.quality[0], sol.n_satellites[0]), (1, 25));
        assert_eq!(sol.velocity_ned_m_s[0], Vector3::new(0.001, -0.002, -0.027));
        let text = format_pos(&sol, "memsnav").unwrap();
        let back = parse_pos(&text, "y.pos").unwrap();
        assert_eq!(back.gps_time_s, sol.gps_time_s);
        assert!((back.lla[0] - sol.lla[0]).abs().max() < 1e-10);
        assert_eq!(back.velocity_ned_m_s, sol.velocity_ned_m_s);
    }

    #[test]
    fn out_of_range_fields_name_line_and_field() {
        let bad_latitude = LINE
            .replace("40.0966916", "999")
            .replace("39.749", "40.000");
        let e = parse_pos(&with(&bad_latitude), "x.pos").unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.pos:4: field 3: latitude(deg) = 999 ° is out of range (-90 to 90 °)"
        );
        let nan = LINE
            .replace("40.0966916", "nan")
            .replace("39.749", "40.000");
        let e = parse_pos(&with(&nan), "x.pos").unwrap_err();
        assert!(
            e.to_string()
                .contains("field 3 (latitude(deg)): expected a finite number"),
            "{e}"
        );
        let negative_std = LINE
            .replace(" 0.0098995 0.0098995", " -1 0.0098995")
            .replace("39.749", "40.000");
        let e = parse_pos(&with(&negative_std), "x.pos").unwrap_err();
        assert!(
            e.to_string().contains("sdn(m) = -1 m is out of range"),
            "{e}"
        );
        let earlier = LINE.replace("39.749", "38.000");
        let e = parse_pos(&with(&earlier), "x.pos").unwrap_err();
        assert!(e.to_string().starts_with("x.pos:4: time"), "{e}");
        let month_13 = LINE.replace("2025/08/28", "2025/13/28");
        let e = parse_pos(&with(&month_13), "x.pos").unwrap_err();
        assert!(
            e.to_string().contains("x.pos:4: month 13 is out of range"),
            "{e}"
        );
        let cut = format!("{HEAD}{LINE}{}", &LINE[..60]);
        let sol = parse_pos(&cut, "x.pos").unwrap();
        assert_eq!(sol.gps_time_s.len(), 1);
        assert!(sol.warnings[0].contains("x.pos:4: last line cut short (no end of line"));
    }
}
