//! NMEA 0183 position fixes: GGA (position, fix quality, satellites,
//! HDOP, height above mean sea level and geoid separation), RMC (date,
//! speed and course), GST (position error statistics) and VTG (course and
//! speed), talkers GP, GN, GL, GA, GB, BD and GQ. Every sentence's
//! checksum is verified. Lines are sentences (`$GPGGA,...*hh`) or Android
//! GnssLogger records (`NMEA,$GPGGA,...*hh,<unix ms>`, the unix time of
//! arrival is not used); blank lines and `#` lines are skipped; other
//! sentence types (GSA, GSV, ZDA, proprietary `$P...`) are counted in a
//! warning and ignored.
//!
//! Sentences with the same UTC time of day form one epoch (VTG, which has
//! no time, joins the epoch before it). The date is RMC's; an epoch
//! without an RMC takes the date of its neighbours (the next day when its
//! time of day is earlier than the previous epoch's). UTC becomes GPS time
//! with the leap seconds ([`crate::gnss::leap_seconds_on`]). An epoch needs
//! a GGA (the only sentence with a height); ellipsoidal height = GGA's
//! height above mean sea level + its geoid separation.
//!
//! Uncertainty: GST's latitude, longitude and height σ give the NED
//! variances; its error ellipse (semi-major, semi-minor σ and the
//! orientation of the semi-major axis from true north) the north-east
//! correlation ρ (receivers' ellipses and σ do not always agree: the σ
//! are kept, so the covariance stays positive semi-definite). Without the
//! latitude and longitude σ, the ellipse gives the horizontal covariance. An epoch without
//! GST gets σ_N = σ_E = HDOP · [`NMEA_UERE_M`] / √2 (HDOP · UERE is the
//! horizontal DRMS) and σ_D = [`NMEA_VDOP_PER_HDOP`] · HDOP ·
//! [`NMEA_UERE_M`], with a warning counting them.
//!
//! Velocity: RMC's (or else VTG's) speed over ground along the true course
//! gives north and east; a speed of zero with an empty (or any) course is a
//! zero velocity. NMEA has no vertical velocity: the down component, its σ
//! and the covariance's down row and column are NaN, and loose coupling
//! takes the velocity as horizontal only
//! ([`crate::coupling::PositionFix::velocity_horizontal_only`]). NMEA has
//! no velocity accuracy either; each horizontal axis gets
//! σ = max(HDOP · [`NMEA_RANGE_RATE_ERROR_M_S`] / √2,
//! [`NMEA_VELOCITY_STD_FLOOR_M_S`]), the velocity counterpart of the
//! position σ from HDOP (a Doppler velocity's covariance is the range-rate
//! variance times the same (GᵀG)⁻¹ as the position's: Kaplan & Hegarty,
//! *Understanding GPS*, 2nd ed., §7.3), with the rounding of the sentence's
//! last digits added: (step)²/12 along the track for the speed and
//! (speed · step)²/12 across it for the course (a uniform rounding error).
//! An epoch with GST but no HDOP takes HDOP = √(σ_N² + σ_E²) / UERE.
//!
//! GGA's fix quality becomes RTKLIB's Q: 1 GPS (and 3 PPS) → 5 single,
//! 2 DGPS → 4, 4 RTK fixed → 1, 5 RTK float → 2, 6 dead reckoning → 7;
//! 0 (no fix), 7 (manual input) and 8 (simulator) epochs are skipped.

use std::collections::BTreeMap;
use std::path::Path;

use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};

use super::fields::{finite_number, in_range, parse_error};
use super::pos_solution::{std_of, MAX_STD};
use super::rtklib_pos::{MAX_SPEED_M_S, POS_HEIGHT_RANGE_M};
use super::PosSolution;
use crate::gnss::{checked_gps_time_from_utc, DEFAULT_PSEUDORANGE_RATE_STD_M_S};
use crate::Result;

/// User equivalent range error that scales HDOP into a position σ for
/// epochs without GST, m: a single-frequency standalone receiver's
/// (broadcast orbits and clocks, ionosphere model residual, multipath).
pub const NMEA_UERE_M: f64 = 5.0;

/// VDOP taken for HDOP's multiple where NMEA gives no VDOP (GGA has only
/// HDOP): the usual open-sky ratio of a GPS constellation.
pub const NMEA_VDOP_PER_HDOP: f64 = 1.5;

/// User equivalent range-rate error that scales HDOP into a velocity σ,
/// m/s: a consumer receiver's Doppler noise, the tight filter's default
/// pseudorange-rate σ ([`DEFAULT_PSEUDORANGE_RATE_STD_M_S`]).
pub const NMEA_RANGE_RATE_ERROR_M_S: f64 = DEFAULT_PSEUDORANGE_RATE_STD_M_S;

/// Smallest velocity σ per horizontal axis, m/s: the velocity accuracy
/// consumer receivers state (u-blox M8, M9 and F9 data sheets: 0.05 m/s),
/// below which a small HDOP would take the RMC speed for better than the
/// receiver makes it.
pub const NMEA_VELOCITY_STD_FLOOR_M_S: f64 = 0.05;

/// Talker ids read: GPS, multi-GNSS, GLONASS, Galileo, BeiDou (GB and the
/// older BD), QZSS.
pub const NMEA_TALKERS: [&str; 7] = ["GP", "GN", "GL", "GA", "GB", "BD", "GQ"];

/// m/s per knot (1 852 m per hour).
const M_S_PER_KNOT: f64 = 1852.0 / 3600.0;

/// Largest HDOP accepted (NMEA's field is 99.9 at most).
const MAX_HDOP: f64 = 100.0;

/// Reads an NMEA log (see the module documentation).
pub fn read_nmea(path: impl AsRef<Path>) -> Result<PosSolution> {
    let path = path.as_ref();
    parse_nmea(
        &String::from_utf8_lossy(&super::read_bytes(path)?),
        &path.display().to_string(),
    )
}

/// A GGA sentence's fix.
#[derive(Debug, Clone, Copy)]
struct Gga {
    lla: Vector3<f64>,
    /// RTKLIB's Q, None for an epoch to skip.
    quality: Option<u8>,
    n_satellites: u16,
    hdop: Option<f64>,
    geoid_separation_given: bool,
}

/// The sentences of one UTC time of day.
#[derive(Debug, Default)]
struct Epoch {
    /// 1-based line of its first sentence.
    line: usize,
    time_of_day_s: f64,
    date: Option<(i64, i64, i64)>,
    gga: Option<Gga>,
    rmc_velocity: Option<GroundVelocity>,
    vtg_velocity: Option<GroundVelocity>,
    gst: Option<Matrix3<f64>>,
}

/// A speed and course over ground as north and east velocity, with the
/// variance of the rounding of the sentence's fields.
#[derive(Debug, Clone, Copy)]
struct GroundVelocity {
    north_east_m_s: Vector2<f64>,
    /// North-east covariance of the rounding of the speed's and the
    /// course's last digits, (m/s)².
    rounding_m2_s2: Matrix2<f64>,
}

/// What a line holds.
enum Sentence {
    Gga(f64, Gga),
    Rmc(f64, (i64, i64, i64), Option<GroundVelocity>),
    Gst(f64, Matrix3<f64>),
    Vtg(Option<GroundVelocity>),
    /// A sentence of another type (its address), ignored.
    Other(String),
}

/// The sentence of a line (`$...*hh` or GnssLogger's `NMEA,$...*hh,ms`),
/// its checksum verified.
fn sentence(line: &str) -> std::result::Result<&str, String> {
    let expected = "expected an NMEA sentence '$GPGGA,...*hh' or a GnssLogger record 'NMEA,$GPGGA,...*hh,<unix ms>'";
    let (body, wrapped) = match line.strip_prefix("NMEA,") {
        Some(rest) => (rest, true),
        None => (line, false),
    };
    if !body.starts_with('$') {
        let shown: String = line.chars().take(40).collect();
        return Err(format!("{expected}, got {shown:?}"));
    }
    if !body.is_ascii() {
        return Err("the sentence has non-ASCII characters (NMEA 0183 is ASCII)".to_string());
    }
    let Some(star) = body.find('*') else {
        return Err("no checksum ('*hh' after the sentence)".to_string());
    };
    let (sentence, tail) = body.split_at((star + 3).min(body.len()));
    let hex = &sentence[star + 1..];
    let Ok(given) = u8::from_str_radix(hex, 16).map_err(|_| ()).and_then(|v| {
        if hex.len() == 2 {
            Ok(v)
        } else {
            Err(())
        }
    }) else {
        return Err(format!(
            "checksum: expected two hex digits after '*', got {hex:?}"
        ));
    };
    let tail_ok = if wrapped {
        tail.strip_prefix(',')
            .is_some_and(|ms| !ms.is_empty() && ms.bytes().all(|b| b.is_ascii_digit()))
    } else {
        tail.is_empty()
    };
    if !tail_ok {
        return Err(format!(
            "{expected}: unexpected {tail:?} after the checksum"
        ));
    }
    let computed = sentence.as_bytes()[1..star].iter().fold(0u8, |a, b| a ^ b);
    if computed != given {
        return Err(format!(
            "checksum *{hex} does not match the sentence's (computed *{computed:02X})"
        ));
    }
    Ok(&sentence[..star])
}

/// Field `k` of a sentence, named for errors.
struct Fields<'a> {
    kind: &'a str,
    f: Vec<&'a str>,
}

impl<'a> Fields<'a> {
    fn get(&self, k: usize) -> &'a str {
        self.f.get(k).copied().unwrap_or("")
    }

    fn error(&self, k: usize, name: &str, what: impl std::fmt::Display) -> String {
        format!("{} field {k} ({name}): {what}", self.kind)
    }

    /// A number in `range`, None when the field is empty.
    fn number(
        &self,
        k: usize,
        name: &str,
        range: std::ops::RangeInclusive<f64>,
        unit: &str,
    ) -> std::result::Result<Option<f64>, String> {
        let text = self.get(k);
        if text.is_empty() {
            return Ok(None);
        }
        let x = finite_number(text)
            .ok_or_else(|| self.error(k, name, format!("expected a number, got {text:?}")))?;
        in_range(x, range, name, unit).map_err(|e| format!("{} field {k}: {e}", self.kind))?;
        Ok(Some(x))
    }

    fn required(
        &self,
        k: usize,
        name: &str,
        range: std::ops::RangeInclusive<f64>,
        unit: &str,
    ) -> std::result::Result<f64, String> {
        self.number(k, name, range, unit)?
            .ok_or_else(|| self.error(k, name, "empty"))
    }

    /// UTC time of day `hhmmss[.ss]`, s.
    fn time_of_day(&self, k: usize) -> std::result::Result<f64, String> {
        let text = self.get(k);
        let bad = || self.error(k, "UTC time", format!("expected hhmmss.ss, got {text:?}"));
        if text.len() < 6 || !text.is_char_boundary(2) || !text.is_char_boundary(4) {
            return Err(bad());
        }
        let (Ok(h), Ok(m), Some(s)) = (
            text[..2].parse::<u8>(),
            text[2..4].parse::<u8>(),
            finite_number(&text[4..]),
        ) else {
            return Err(bad());
        };
        if h > 23 || m > 59 || !(0.0..61.0).contains(&s) || text[4..].starts_with(['+', '-']) {
            return Err(self.error(
                k,
                "UTC time",
                format!("{text:?} is out of range (000000 to 235960.999)"),
            ));
        }
        Ok(f64::from(h) * 3600.0 + f64::from(m) * 60.0 + s)
    }

    /// Latitude (`ddmm.mmmm` at `k`, N/S at k + 1) or longitude
    /// (`dddmm.mmmm`, E/W), rad.
    fn angle(&self, k: usize, latitude: bool) -> std::result::Result<f64, String> {
        let (name, digits, max, signs) = if latitude {
            ("latitude", 2, 90.0, ["N", "S"])
        } else {
            ("longitude", 3, 180.0, ["E", "W"])
        };
        let text = self.get(k);
        let shape = if latitude { "ddmm.mmmm" } else { "dddmm.mmmm" };
        let bad = || self.error(k, name, format!("expected {shape}, got {text:?}"));
        let whole = text.find('.').unwrap_or(text.len());
        if whole != digits + 2 || !text.bytes().all(|b| b.is_ascii_digit() || b == b'.') {
            return Err(bad());
        }
        let degrees: f64 = text[..digits].parse().map_err(|_| bad())?;
        let minutes = finite_number(&text[digits..]).ok_or_else(bad)?;
        let value = degrees + minutes / 60.0;
        if minutes >= 60.0 || value > max {
            return Err(self.error(
                k,
                name,
                format!("{text} is out of range (0 to {max}°, minutes below 60)"),
            ));
        }
        let sign = match self.get(k + 1) {
            s if s == signs[0] => 1.0,
            s if s == signs[1] => -1.0,
            s => {
                return Err(self.error(
                    k + 1,
                    "hemisphere",
                    format!("expected {} or {}, got {s:?}", signs[0], signs[1]),
                ))
            }
        };
        Ok((sign * value).to_radians())
    }

    /// The step of the last digit of field `k` (0.01 for `012.34`; 1
    /// without a decimal point).
    fn last_digit(&self, k: usize) -> f64 {
        let text = self.get(k);
        text.find('.')
            .map_or(1.0, |dot| 10f64.powi(-((text.len() - dot - 1) as i32)))
    }

    /// North and east velocity of a speed along a true course (°, may be
    /// empty at zero speed), or None when the speed is empty: `speed` the
    /// speed's field, its unit and the unit's m/s; `course` the course's
    /// field.
    fn velocity(
        &self,
        speed: Option<(usize, &str, f64)>,
        course: usize,
    ) -> std::result::Result<Option<GroundVelocity>, String> {
        let Some((k, unit, m_s)) = speed else {
            return Ok(None);
        };
        let range = 0.0..=MAX_SPEED_M_S / m_s;
        let Some(v) = self.number(k, "speed over ground", range, unit)? else {
            return Ok(None);
        };
        let (speed, speed_step) = (v * m_s, self.last_digit(k) * m_s);
        // A uniform rounding error of one step has the variance step²/12.
        let along_variance = speed_step * speed_step / 12.0;
        match self.number(course, "true course", 0.0..=360.0, "°")? {
            Some(c) => {
                let (s, c) = c.to_radians().sin_cos();
                let across_step = speed * self.last_digit(course).to_radians();
                let (along, across) = (Vector2::new(c, s), Vector2::new(-s, c));
                Ok(Some(GroundVelocity {
                    north_east_m_s: along * speed,
                    rounding_m2_s2: along * along.transpose() * along_variance
                        + across * across.transpose() * (across_step * across_step / 12.0),
                }))
            }
            // At rest receivers leave the course empty: the rounding of the
            // speed is the only uncertainty, in any direction.
            None if speed == 0.0 => Ok(Some(GroundVelocity {
                north_east_m_s: Vector2::zeros(),
                rounding_m2_s2: Matrix2::identity() * along_variance,
            })),
            None => Ok(None),
        }
    }
}

fn gga(s: &Fields) -> std::result::Result<Sentence, String> {
    let t = s.time_of_day(1)?;
    let code = s.required(6, "fix quality", 0.0..=8.0, "")?;
    if code.fract() != 0.0 {
        return Err(s.error(6, "fix quality", format!("expected an integer, got {code}")));
    }
    let quality = match code as u8 {
        1 | 3 => Some(5),
        2 => Some(4),
        4 => Some(1),
        5 => Some(2),
        6 => Some(7),
        _ => None,
    };
    let n_satellites = s.number(7, "satellites", 0.0..=255.0, "")?.unwrap_or(0.0);
    if n_satellites.fract() != 0.0 {
        return Err(s.error(
            7,
            "satellites",
            format!("expected an integer, got {n_satellites}"),
        ));
    }
    let hdop = s.number(8, "HDOP", 0.0..=MAX_HDOP, "")?;
    if quality.is_none() {
        // No position to read: the epoch is skipped.
        let lla = Vector3::repeat(f64::NAN);
        return Ok(Sentence::Gga(
            t,
            Gga {
                lla,
                quality,
                n_satellites: 0,
                hdop,
                geoid_separation_given: false,
            },
        ));
    }
    let latitude = s.angle(2, true)?;
    let longitude = s.angle(4, false)?;
    let msl = s.required(9, "altitude above mean sea level", POS_HEIGHT_RANGE_M, "m")?;
    for (k, name) in [(10, "altitude unit"), (12, "geoid separation unit")] {
        if !matches!(s.get(k), "M" | "") {
            return Err(s.error(k, name, format!("expected M (metres), got {:?}", s.get(k))));
        }
    }
    let separation = s.number(11, "geoid separation", -200.0..=200.0, "m")?;
    let height = msl + separation.unwrap_or(0.0);
    in_range(height, POS_HEIGHT_RANGE_M, "ellipsoidal height", "m")
        .map_err(|e| format!("GGA fields 9 and 11: {e}"))?;
    Ok(Sentence::Gga(
        t,
        Gga {
            lla: Vector3::new(latitude, longitude, height),
            quality,
            n_satellites: n_satellites as u16,
            hdop,
            geoid_separation_given: separation.is_some(),
        },
    ))
}

fn rmc(s: &Fields) -> std::result::Result<Sentence, String> {
    let t = s.time_of_day(1)?;
    let date = s.get(9);
    let bad = || s.error(9, "date", format!("expected ddmmyy, got {date:?}"));
    if date.len() != 6 || !date.bytes().all(|b| b.is_ascii_digit()) {
        return Err(bad());
    }
    let (d, m, y) = (
        date[..2].parse::<i64>().map_err(|_| bad())?,
        date[2..4].parse::<i64>().map_err(|_| bad())?,
        date[4..].parse::<i64>().map_err(|_| bad())?,
    );
    // Two-digit years: GPS starts in 1980.
    let year = if y >= 80 { 1900 + y } else { 2000 + y };
    let velocity = match s.get(2) {
        "A" => s.velocity(Some((7, "knots", M_S_PER_KNOT)), 8)?,
        "V" => None,
        other => {
            return Err(s.error(2, "status", format!("expected A or V, got {other:?}")));
        }
    };
    Ok(Sentence::Rmc(t, (year, m, d), velocity))
}

fn gst(s: &Fields) -> std::result::Result<Sentence, String> {
    let t = s.time_of_day(1)?;
    let std = |k: usize, name: &str| s.number(k, name, 0.0..=MAX_STD, "m");
    let major = std(3, "semi-major axis σ")?;
    let minor = std(4, "semi-minor axis σ")?;
    let orientation = s.number(5, "semi-major axis orientation", -360.0..=360.0, "°")?;
    let lat = std(6, "latitude σ")?;
    let lon = std(7, "longitude σ")?;
    let height = std(8, "height σ")?.ok_or_else(|| s.error(8, "height σ", "empty"))?;
    let ellipse = match (major, minor, orientation) {
        (Some(a), Some(b), Some(theta)) => {
            // C = a² u uᵀ + b² w wᵀ, u the semi-major axis (north, east),
            // w ⟂ u.
            let (sin, cos) = theta.to_radians().sin_cos();
            let (u, w) = ([cos, sin], [-sin, cos]);
            Some(nalgebra::Matrix2::from_fn(|i, j| {
                a * a * u[i] * u[j] + b * b * w[i] * w[j]
            }))
        }
        _ => None,
    };
    let mut c = Matrix3::zeros();
    match (ellipse, lat, lon) {
        (ellipse, Some(n), Some(e)) => {
            // The stated σ, correlated as the ellipse says.
            let rho = ellipse.map_or(0.0, |m| {
                let d = (m[(0, 0)] * m[(1, 1)]).sqrt();
                if d > 0.0 {
                    m[(0, 1)] / d
                } else {
                    0.0
                }
            });
            c[(0, 0)] = n * n;
            c[(1, 1)] = e * e;
            c[(0, 1)] = rho * n * e;
            c[(1, 0)] = rho * n * e;
        }
        (Some(m), _, _) => c.fixed_view_mut::<2, 2>(0, 0).copy_from(&m),
        _ => {
            return Err(format!(
                "GST: neither the latitude and longitude σ (fields 6, 7) nor the error ellipse (fields 3-5) are given, got {:?}",
                s.f.join(",")
            ))
        }
    }
    c[(2, 2)] = height * height;
    Ok(Sentence::Gst(t, c))
}

fn vtg(s: &Fields) -> std::result::Result<Sentence, String> {
    for (k, letter) in [(2, "T"), (6, "N"), (8, "K")] {
        if !matches!(s.get(k), x if x == letter || x.is_empty()) {
            return Err(s.error(
                k,
                "unit letter",
                format!("expected {letter}, got {:?}", s.get(k)),
            ));
        }
    }
    if s.get(9) == "N" {
        // Mode N: data not valid.
        return Ok(Sentence::Vtg(None));
    }
    let speed = if !s.get(7).is_empty() {
        Some((7, "km/h", 1.0 / 3.6))
    } else if !s.get(5).is_empty() {
        Some((5, "knots", M_S_PER_KNOT))
    } else {
        None
    };
    Ok(Sentence::Vtg(s.velocity(speed, 1)?))
}

/// The sentence of a line, parsed.
fn parse_sentence(line: &str) -> std::result::Result<Sentence, String> {
    let text = sentence(line)?;
    let f: Vec<&str> = text[1..].split(',').collect();
    let address = f[0];
    if address.starts_with('P') || address.len() != 5 || !address.is_ascii() {
        return Ok(Sentence::Other(address.chars().take(8).collect()));
    }
    let (talker, kind) = address.split_at(2);
    if !matches!(kind, "GGA" | "RMC" | "GST" | "VTG") {
        return Ok(Sentence::Other(kind.to_string()));
    }
    if !NMEA_TALKERS.contains(&talker) {
        return Err(format!(
            "talker {talker:?} of {address}: expected one of {}",
            NMEA_TALKERS.join(", ")
        ));
    }
    let s = Fields { kind, f };
    match kind {
        "GGA" => gga(&s),
        "RMC" => rmc(&s),
        "GST" => gst(&s),
        _ => vtg(&s),
    }
}

/// Counts for the warnings.
#[derive(Default)]
struct Notes {
    other: BTreeMap<String, usize>,
    repeated: usize,
    vtg_alone: usize,
}

/// Parses the text of an NMEA log; `file` names it in errors. Each field is
/// range-checked (the sentence's own ranges: minutes below 60, latitude
/// ±90°, quality 0-8, ...), checksums verified and GPS times must
/// increase. A last line that does not parse is skipped with a warning
/// (the log stopped mid-sentence).
pub fn parse_nmea(text: &str, file: &str) -> Result<PosSolution> {
    let lines: Vec<&str> = text.lines().collect();
    let content: Vec<usize> = (0..lines.len())
        .filter(|&k| {
            let s = lines[k].trim();
            !s.is_empty() && !s.starts_with('#')
        })
        .collect();
    let mut warnings = Vec::new();
    let mut epochs: Vec<Epoch> = Vec::new();
    let mut notes = Notes::default();
    for (i, &k) in content.iter().enumerate() {
        let parsed = match parse_sentence(lines[k].trim()) {
            Ok(p) => p,
            Err(reason) if i + 1 == content.len() => {
                warnings.push(format!(
                    "{file}:{}: last line cut short ({reason}); skipped",
                    k + 1
                ));
                break;
            }
            Err(reason) => return Err(parse_error(file, k + 1, reason)),
        };
        let time = match &parsed {
            Sentence::Gga(t, _) | Sentence::Rmc(t, _, _) | Sentence::Gst(t, _) => Some(*t),
            _ => None,
        };
        if let Some(t) = time {
            if epochs.last().is_none_or(|e| e.time_of_day_s != t) {
                epochs.push(Epoch {
                    line: k + 1,
                    time_of_day_s: t,
                    ..Default::default()
                });
            }
        }
        let Some(epoch) = epochs.last_mut() else {
            match parsed {
                Sentence::Other(kind) => *notes.other.entry(kind).or_default() += 1,
                _ => notes.vtg_alone += 1,
            }
            continue;
        };
        let repeated = match parsed {
            Sentence::Gga(_, g) => epoch.gga.replace(g).is_some(),
            Sentence::Rmc(_, date, v) => {
                let again = epoch.date.replace(date).is_some();
                if let Some(v) = v {
                    epoch.rmc_velocity = Some(v);
                }
                again
            }
            Sentence::Gst(_, c) => epoch.gst.replace(c).is_some(),
            Sentence::Vtg(v) => {
                if let Some(v) = v {
                    epoch.vtg_velocity = Some(v);
                }
                false
            }
            Sentence::Other(kind) => {
                *notes.other.entry(kind).or_default() += 1;
                false
            }
        };
        notes.repeated += usize::from(repeated);
    }
    if epochs.is_empty() {
        return Err(parse_error(
            file,
            lines.len().max(1),
            "expected NMEA sentences with fixes (GGA, with an RMC for the date), found none",
        ));
    }
    let times = gps_times(&epochs, file)?;
    let mut sol = PosSolution::with_capacity(epochs.len());
    let mut covariances = Vec::with_capacity(epochs.len());
    let mut velocity_covariances = Vec::with_capacity(epochs.len());
    let (mut no_gga, mut no_fix, mut from_hdop, mut no_separation) = (0, 0, 0, 0);
    for (e, t) in epochs.iter().zip(times) {
        let Some(g) = e.gga else {
            no_gga += 1;
            continue;
        };
        let Some(quality) = g.quality else {
            no_fix += 1;
            continue;
        };
        let covariance =
            match (e.gst, g.hdop) {
                (Some(c), _) => c,
                (None, Some(hdop)) => {
                    from_hdop += 1;
                    let h = hdop * NMEA_UERE_M / std::f64::consts::SQRT_2;
                    let v = NMEA_VDOP_PER_HDOP * hdop * NMEA_UERE_M;
                    Matrix3::from_diagonal(&Vector3::new(h * h, h * h, v * v))
                }
                (None, None) => return Err(parse_error(
                    file,
                    e.line,
                    "GGA field 8 (HDOP) is empty and the epoch has no GST: the fix has no accuracy",
                )),
            };
        if let Some(&previous) = sol.gps_time_s.last() {
            if t <= previous {
                return Err(parse_error(
                    file,
                    e.line,
                    format!(
                        "time {t:.3} s (GPS) does not follow the previous epoch's {previous:.3} s: epochs must increase"
                    ),
                ));
            }
        }
        no_separation += usize::from(!g.geoid_separation_given);
        // No vertical velocity: NaN down, in the velocity and its covariance.
        let mut velocity = Vector3::repeat(f64::NAN);
        let mut velocity_covariance = Matrix3::repeat(f64::NAN);
        if let Some(v) = e.rmc_velocity.or(e.vtg_velocity) {
            let hdop = g
                .hdop
                .unwrap_or_else(|| (covariance[(0, 0)] + covariance[(1, 1)]).sqrt() / NMEA_UERE_M);
            let std = (hdop * NMEA_RANGE_RATE_ERROR_M_S / std::f64::consts::SQRT_2)
                .max(NMEA_VELOCITY_STD_FLOOR_M_S);
            velocity.fixed_rows_mut::<2>(0).copy_from(&v.north_east_m_s);
            velocity_covariance
                .fixed_view_mut::<2, 2>(0, 0)
                .copy_from(&(Matrix2::identity() * (std * std) + v.rounding_m2_s2));
        }
        sol.gps_time_s.push(t);
        sol.lla.push(g.lla);
        sol.quality.push(quality);
        sol.n_satellites.push(g.n_satellites);
        sol.std_ned_m.push(std_of(&covariance));
        covariances.push(covariance);
        sol.velocity_ned_m_s.push(velocity);
        sol.velocity_std_ned_m_s.push(std_of(&velocity_covariance));
        velocity_covariances.push(velocity_covariance);
    }
    if sol.gps_time_s.is_empty() {
        return Err(parse_error(
            file,
            lines.len().max(1),
            format!(
                "no fix: expected GGA sentences with a fix quality of 1-6 ({} epochs without GGA, {} without a fix)",
                no_gga, no_fix
            ),
        ));
    }
    let mut note = |n: usize, what: String| {
        if n > 0 {
            warnings.push(format!("{file}: {n} {what}"));
        }
    };
    note(
        no_gga,
        "epoch(s) without a GGA sentence (no height): skipped".into(),
    );
    note(
        no_fix,
        "epoch(s) without a fix (GGA quality 0, 7 manual or 8 simulator): skipped".into(),
    );
    note(from_hdop, format!(
        "epoch(s) without GST: position σ from HDOP × {NMEA_UERE_M} m UERE (σ_N = σ_E = HDOP·UERE/√2, σ_D = {NMEA_VDOP_PER_HDOP}·HDOP·UERE)"
    ));
    note(no_separation, "GGA sentence(s) without a geoid separation: their altitude is taken as the ellipsoidal height (set [gnss] height = \"msl\" and geoid_separation_m if it is above mean sea level)".into());
    note(
        notes.repeated,
        "sentence(s) repeating a GGA, RMC or GST of their epoch: the last one kept".into(),
    );
    note(
        notes.vtg_alone,
        "VTG sentence(s) before the first timed sentence: ignored".into(),
    );
    if !notes.other.is_empty() {
        let kinds: Vec<String> = notes
            .other
            .iter()
            .map(|(k, n)| format!("{k} {n}"))
            .collect();
        let total: usize = notes.other.values().sum();
        note(
            total,
            format!("sentence(s) of other types ignored ({})", kinds.join(", ")),
        );
    }
    sol.covariance_ned_m2 = Some(covariances);
    sol.velocity_covariance_ned_m2_s2 = Some(velocity_covariances);
    sol.warnings = warnings;
    Ok(sol)
}

/// The GPS time of every epoch: from its RMC date where it has one, else
/// from its neighbour's time and the time of day (the next day when the
/// time of day goes back).
fn gps_times(epochs: &[Epoch], file: &str) -> Result<Vec<f64>> {
    let Some(first) = epochs.iter().position(|e| e.date.is_some()) else {
        return Err(parse_error(
            file,
            epochs.first().map_or(1, |e| e.line),
            "no RMC sentence: the date is unknown (GGA and GST carry the time of day only)",
        ));
    };
    let dated = |e: &Epoch| -> Result<Option<f64>> {
        let Some((y, m, d)) = e.date else {
            return Ok(None);
        };
        let s = e.time_of_day_s;
        let (hour, minute) = ((s / 3600.0).floor(), ((s % 3600.0) / 60.0).floor());
        checked_gps_time_from_utc(
            y,
            m,
            d,
            hour as i64,
            minute as i64,
            s - hour * 3600.0 - minute * 60.0,
        )
        .map(Some)
        .map_err(|reason| parse_error(file, e.line, format!("RMC date: {reason}")))
    };
    let mut times = vec![f64::NAN; epochs.len()];
    for k in first..epochs.len() {
        times[k] = match dated(&epochs[k])? {
            Some(t) => t,
            None => {
                let step =
                    (epochs[k].time_of_day_s - epochs[k - 1].time_of_day_s).rem_euclid(86_400.0);
                times[k - 1] + step
            }
        };
    }
    for k in (0..first).rev() {
        let step = (epochs[k + 1].time_of_day_s - epochs[k].time_of_day_s).rem_euclid(86_400.0);
        times[k] = times[k + 1] - step;
    }
    Ok(times)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gnss::gps_time_from_calendar;

    // The textbook sentences (D. DePriest, "NMEA data"; NovAtel's GST
    // example), checksums as published.
    const GGA: &str = "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47";
    const RMC: &str = "$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A";
    const VTG: &str = "$GPVTG,054.7,T,034.4,M,005.5,N,010.2,K*48";
    const GST: &str = "$GPGST,172814.0,0.006,0.023,0.020,273.6,0.023,0.020,0.031*6A";

    #[test]
    fn textbook_epoch() {
        let sol = parse_nmea(&format!("{GGA}\n{RMC}\n"), "x.nmea").unwrap();
        // 1994-03-23 UTC: 9 leap seconds.
        assert_eq!(
            sol.gps_time_s,
            vec![gps_time_from_calendar(1994, 3, 23, 12, 35, 28.0)]
        );
        let lla = sol.lla[0];
        assert_eq!(lla.x, (48.0 + 7.038 / 60.0_f64).to_radians());
        assert_eq!(lla.y, (11.0 + 31.0 / 60.0_f64).to_radians());
        assert!((lla.z - 592.3).abs() < 1e-12);
        assert_eq!((sol.quality[0], sol.n_satellites[0]), (5, 8));
        let h = 0.9 * 5.0 / 2.0_f64.sqrt();
        assert!((sol.std_ned_m[0] - Vector3::new(h, h, 1.5 * 0.9 * 5.0)).norm() < 1e-12);
        let speed = 22.4 * 1852.0 / 3600.0;
        let course = 84.4_f64.to_radians();
        let v = sol.velocity_ned_m_s[0];
        assert!((v.x - speed * course.cos()).abs() < 1e-12);
        assert!((v.y - speed * course.sin()).abs() < 1e-12);
        // No vertical velocity; the horizontal σ from HDOP 0.9 × 0.1 m/s / √2
        // (above the 0.05 m/s floor) with the rounding of 0.1 knot along
        // the track and 0.1° across it.
        assert!(v.z.is_nan() && sol.velocity_std_ned_m_s[0].z.is_nan());
        let geometry = (0.9 * 0.1 / 2.0_f64.sqrt()).powi(2);
        let along = (0.1 * 1852.0 / 3600.0_f64).powi(2) / 12.0;
        let across = (speed * 0.1_f64.to_radians()).powi(2) / 12.0;
        let (s, c) = course.sin_cos();
        let want = [
            [
                geometry + along * c * c + across * s * s,
                (along - across) * s * c,
            ],
            [
                (along - across) * s * c,
                geometry + along * s * s + across * c * c,
            ],
        ];
        let got = sol.velocity_covariance_ned_m2_s2.as_ref().unwrap()[0];
        for (i, row) in want.iter().enumerate() {
            for (j, w) in row.iter().enumerate() {
                assert!((got[(i, j)] - w).abs() < 1e-15, "{got}");
            }
            assert!(got[(i, 2)].is_nan() && got[(2, i)].is_nan());
        }
        assert!(
            sol.warnings[0].contains("1 epoch(s) without GST"),
            "{:?}",
            sol.warnings
        );
    }

    #[test]
    fn gst_vtg_and_rollover() {
        // A GST at the GGA's time, VTG joining the epoch; a second epoch
        // after midnight with no RMC takes the next day.
        let gga = GGA.replace("123519", "172814.0");
        let gga2 = GGA.replace("123519", "000001");
        let body = |s: &str| s[1..s.find('*').unwrap()].to_string();
        let sum = |s: &str| {
            let b = body(s);
            format!("${b}*{:02X}", b.bytes().fold(0, |a, x| a ^ x))
        };
        let rmc = sum(&RMC
            .replace("123519", "172814.0")
            .replace(",022.4,084.4,", ",,,"));
        let text = format!("{}\n{GST}\n{rmc}\n{VTG}\n{}\n", sum(&gga), sum(&gga2));
        let sol = parse_nmea(&text, "x.nmea").unwrap();
        let t0 = gps_time_from_calendar(1994, 3, 23, 17, 28, 23.0);
        assert_eq!(
            sol.gps_time_s,
            vec![t0, t0 + 6.0 * 3600.0 + 31.0 * 60.0 + 47.0]
        );
        let c = &sol.covariance_ned_m2.as_ref().unwrap()[0];
        let (a, b, th) = (0.023_f64, 0.020_f64, 273.6_f64.to_radians());
        let (nn, ee) = (
            a * a * th.cos().powi(2) + b * b * th.sin().powi(2),
            a * a * th.sin().powi(2) + b * b * th.cos().powi(2),
        );
        let rho = (a * a - b * b) * th.sin() * th.cos() / (nn * ee).sqrt();
        assert!((c[(0, 0)] - 0.023 * 0.023).abs() < 1e-15);
        assert!((c[(1, 1)] - 0.020 * 0.020).abs() < 1e-15);
        assert!((c[(0, 1)] - rho * 0.023 * 0.020).abs() < 1e-15);
        assert!((c[(2, 2)] - 0.031 * 0.031).abs() < 1e-15);
        let v = sol.velocity_ned_m_s[0];
        let course = 54.7_f64.to_radians();
        assert!((v.x - 10.2 / 3.6 * course.cos()).abs() < 1e-12);
        assert!((v.y - 10.2 / 3.6 * course.sin()).abs() < 1e-12);
    }

    #[test]
    fn errors_name_line_field_and_range() {
        let e = parse_nmea(
            &format!("{RMC}\n{}\n{GGA}\n", GGA.replace("*47", "*48")),
            "x.nmea",
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.nmea:2: checksum *48 does not match the sentence's (computed *47)"
        );
        let sum = |b: &str| format!("${b}*{:02X}", b.bytes().fold(0, |a, x| a ^ x));
        let bad_quality = sum("GPGGA,123519,4807.038,N,01131.000,E,9,08,0.9,545.4,M,46.9,M,,");
        let e = parse_nmea(&format!("{bad_quality}\n{RMC}\n"), "x.nmea").unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.nmea:1: GGA field 6: fix quality = 9  is out of range (0 to 8 )"
        );
        let minutes = sum("GPGGA,123519,4867.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,");
        let e = parse_nmea(&format!("{minutes}\n{RMC}\n"), "x.nmea").unwrap_err();
        assert!(
            e.to_string()
                .contains("GGA field 2 (latitude): 4867.038 is out of range"),
            "{e}"
        );
        let talker = sum("XXGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,");
        let e = parse_nmea(&format!("{talker}\n{RMC}\n"), "x.nmea").unwrap_err();
        assert!(e.to_string().contains("talker \"XX\""), "{e}");
        let e = parse_nmea(&format!("{GGA}\n"), "x.nmea").unwrap_err();
        assert!(e.to_string().contains("no RMC sentence"), "{e}");
        let e = parse_nmea("hello\n$GPGGA\n", "x.nmea").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("x.nmea:1: expected an NMEA sentence"),
            "{e}"
        );
        // Cut short at the end: skipped with a warning.
        let sol = parse_nmea(&format!("{GGA}\n{RMC}\n{}", &GGA[..30]), "x.nmea").unwrap();
        assert_eq!(sol.gps_time_s.len(), 1);
        assert!(
            sol.warnings[0].contains("x.nmea:3: last line cut short"),
            "{:?}",
            sol.warnings
        );
        // Backwards in time by its dates: the next second a day earlier.
        let body = |t: &str| t[1..t.find('*').unwrap()].to_string();
        let gga2 = sum(&body(GGA).replace("123519", "123520"));
        let rmc2 = sum(&body(RMC)
            .replace("123519", "123520")
            .replace("230394", "220394"));
        let e =
            parse_nmea(&format!("{GGA}\n{RMC}\n{gga2}\n{rmc2}\n{GGA}\n"), "x.nmea").unwrap_err();
        assert!(
            e.to_string().starts_with("x.nmea:3: time")
                && e.to_string().contains("does not follow"),
            "{e}"
        );
    }

    /// At rest receivers give a speed of zero with an empty course, or a
    /// course of 0: a zero velocity either way, with the floor σ where HDOP
    /// is small and the speed's rounding; an epoch with GST but no HDOP
    /// takes HDOP = √(σ_N² + σ_E²) / UERE; a speed without a course is no
    /// velocity.
    #[test]
    fn standstill_and_velocity_sigma() {
        let sum = |b: &str| format!("${b}*{:02X}", b.bytes().fold(0, |a, x| a ^ x));
        let gga = |t: &str, hdop: &str| {
            sum(&format!(
                "GNGGA,{t},4807.038,N,01131.000,E,1,08,{hdop},545.4,M,46.9,M,,"
            ))
        };
        let rmc = |t: &str, speed_course: &str| {
            sum(&format!(
                "GNRMC,{t},A,4807.038,N,01131.000,E,{speed_course},230394,,,A"
            ))
        };
        let gst = sum("GNGST,120003,,,,,3.0,4.0,5.0");
        let text = [
            gga("120000", "0.5"),
            rmc("120000", "0.00,"),
            gga("120001", "2.0"),
            rmc("120001", "0.000,0.0"),
            gga("120002", "2.0"),
            rmc("120002", "0.5,"),
            gga("120003", ""),
            rmc("120003", "1,90"),
            gst,
        ]
        .join("\n");
        let sol = parse_nmea(&text, "x.nmea").unwrap();
        let v = &sol.velocity_ned_m_s;
        let c = sol.velocity_covariance_ned_m2_s2.as_ref().unwrap();
        let knot: f64 = 1852.0 / 3600.0;
        // HDOP 0.5: 0.035 m/s is below the floor; 0.01 knot of rounding.
        assert_eq!((v[0].x, v[0].y), (0.0, 0.0));
        let rest = 0.05_f64.powi(2) + (0.01 * knot).powi(2) / 12.0;
        assert!((c[0][(0, 0)] - rest).abs() < 1e-15 && c[0][(0, 1)] == 0.0);
        assert!((c[0][(1, 1)] - rest).abs() < 1e-15);
        // A course of 0 at zero speed: zero velocity, no rounding across.
        let hdop2 = (2.0 * 0.1 / 2.0_f64.sqrt()).powi(2);
        assert_eq!((v[1].x, v[1].y), (0.0, 0.0));
        assert!((c[1][(0, 0)] - hdop2 - (0.001 * knot).powi(2) / 12.0).abs() < 1e-15);
        assert!((c[1][(1, 1)] - hdop2).abs() < 1e-15);
        // A speed with no course: no velocity.
        assert!(v[2].x.is_nan() && c[2][(0, 0)].is_nan());
        // GST without HDOP: HDOP = 5 m / 5 m = 1; one knot east, rounded to
        // a knot along and a degree across.
        assert!((v[3].y - knot).abs() < 1e-15 && v[3].x.abs() < 1e-15);
        let hdop1 = (0.1 / 2.0_f64.sqrt()).powi(2);
        let across = (knot * 1.0_f64.to_radians()).powi(2) / 12.0;
        assert!((c[3][(0, 0)] - hdop1 - across).abs() < 1e-15);
        assert!((c[3][(1, 1)] - hdop1 - knot * knot / 12.0).abs() < 1e-15);
        assert!(v.iter().all(|x| x.z.is_nan()));
        assert!(sol.velocity_std_ned_m_s.iter().all(|x| x.z.is_nan()));
    }

    #[test]
    fn gnsslogger_records() {
        let text = format!("NMEA,{GGA},1699400577561\nNMEA,{RMC},1699400577566\n");
        let sol = parse_nmea(&text, "x.nmea").unwrap();
        assert_eq!(sol.gps_time_s.len(), 1, "{:?}", sol.warnings);
        let e = parse_nmea(&format!("NMEA,{GGA},15x\n{text}"), "x.nmea").unwrap_err();
        assert!(
            e.to_string()
                .contains("unexpected \",15x\" after the checksum"),
            "{e}"
        );
    }
}
