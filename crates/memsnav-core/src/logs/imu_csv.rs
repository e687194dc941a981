//! IMU logs in CSV: one sample a line, comma-separated columns whose
//! names and units the user declares (the layout of consumer loggers such
//! as the `real-imu-gnss` logs: `ax, ay, az` in g, `gx, gy, gz` in °/s, `t`
//! in ms). Parsed with the `csv` crate; every value is range-checked and
//! converted to SI.

use std::path::Path;

use nalgebra::Vector3;

use super::fields::{finite_number, median, parse_error, quantile};
use crate::geodesy::wgs84::STANDARD_GRAVITY_M_S2;
use crate::{Error, Result};

/// Column names a layout must contain: accelerometer, gyro, time. Other
/// names are read and ignored.
pub const IMU_COLUMNS: [&str; 7] = ["ax", "ay", "az", "gx", "gy", "gz", "t"];

/// Largest specific-force component accepted, m/s² (1000 g): beyond any
/// navigation IMU's range, so a larger value is a corrupted field.
pub const MAX_SPECIFIC_FORCE_M_S2: f64 = 1_000.0 * STANDARD_GRAVITY_M_S2;

/// Largest angular-rate component accepted, rad/s (about 5 700 °/s; MEMS
/// gyros stop at ±4 000 °/s).
pub const MAX_ANGULAR_RATE_RAD_S: f64 = 100.0;

/// Angular rate above which a log's 99th percentile is implausible for
/// navigation (573 °/s): a gyro in °/s declared as rad/s lands here.
const PLAUSIBLE_RATE_P99_RAD_S: f64 = 10.0;

/// Specific-force magnitudes an IMU on Earth reads most of the time: at
/// rest 1 g; moving, rarely a median outside 0.5-2 g.
const PLAUSIBLE_MEDIAN_FORCE_G: std::ops::RangeInclusive<f64> = 0.5..=2.0;

/// Sample intervals a navigation IMU log has, s (100 kHz to 2 Hz).
const PLAUSIBLE_INTERVAL_S: std::ops::RangeInclusive<f64> = 1e-5..=0.5;

/// Largest |time| accepted, s (3 000 years: any clock count since any
/// epoch fits, in s or ms).
pub const MAX_TIME_S: f64 = 1e11;

/// A gap longer than this many median intervals (and than 1 s) is reported.
const GAP_INTERVALS: f64 = 50.0;

/// Unit of the accelerometer columns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AccelUnit {
    /// Standard gravity, 9.80665 m/s².
    StandardGravity,
    /// m/s².
    MetresPerSecondSquared,
}

/// Unit of the gyro columns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GyroUnit {
    DegreesPerSecond,
    RadiansPerSecond,
}

/// Unit of the time column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeUnit {
    Milliseconds,
    Seconds,
}

/// `'value'; expected one of ['a', 'b']` in the user's words.
fn unknown_unit(argument: &str, value: &str, names: &[&str]) -> Error {
    let list: Vec<String> = names.iter().map(|n| format!("'{n}'")).collect();
    Error::invalid(
        argument,
        format!(
            "unknown unit '{value}'; expected one of [{}]",
            list.join(", ")
        ),
    )
}

impl AccelUnit {
    const NAMES: [&str; 3] = ["g", "m/s^2", "m/s2"];

    /// The unit named `name` (`"g"`, `"m/s^2"` or `"m/s2"`).
    pub fn from_name(name: &str) -> Result<Self> {
        match name {
            "g" => Ok(Self::StandardGravity),
            "m/s^2" | "m/s2" => Ok(Self::MetresPerSecondSquared),
            _ => Err(unknown_unit("accel_unit", name, &Self::NAMES)),
        }
    }

    /// m/s² per unit.
    pub fn to_si(self) -> f64 {
        match self {
            Self::StandardGravity => STANDARD_GRAVITY_M_S2,
            Self::MetresPerSecondSquared => 1.0,
        }
    }

    fn symbol(self) -> &'static str {
        match self {
            Self::StandardGravity => "g",
            Self::MetresPerSecondSquared => "m/s²",
        }
    }
}

impl GyroUnit {
    const NAMES: [&str; 2] = ["deg/s", "rad/s"];

    /// The unit named `name` (`"deg/s"` or `"rad/s"`).
    pub fn from_name(name: &str) -> Result<Self> {
        match name {
            "deg/s" => Ok(Self::DegreesPerSecond),
            "rad/s" => Ok(Self::RadiansPerSecond),
            _ => Err(unknown_unit("gyro_unit", name, &Self::NAMES)),
        }
    }

    /// rad/s per unit.
    pub fn to_si(self) -> f64 {
        match self {
            Self::DegreesPerSecond => std::f64::consts::PI / 180.0,
            Self::RadiansPerSecond => 1.0,
        }
    }

    fn symbol(self) -> &'static str {
        match self {
            Self::DegreesPerSecond => "°/s",
            Self::RadiansPerSecond => "rad/s",
        }
    }
}

impl TimeUnit {
    const NAMES: [&str; 2] = ["ms", "s"];

    /// The unit named `name` (`"ms"` or `"s"`).
    pub fn from_name(name: &str) -> Result<Self> {
        match name {
            "ms" => Ok(Self::Milliseconds),
            "s" => Ok(Self::Seconds),
            _ => Err(unknown_unit("time_unit", name, &Self::NAMES)),
        }
    }

    /// s per unit.
    pub fn to_si(self) -> f64 {
        match self {
            Self::Milliseconds => 1e-3,
            Self::Seconds => 1.0,
        }
    }

    fn symbol(self) -> &'static str {
        match self {
            Self::Milliseconds => "ms",
            Self::Seconds => "s",
        }
    }
}

/// The declared layout of an IMU CSV log.
#[derive(Debug, Clone, PartialEq)]
pub struct ImuCsvLayout {
    /// Name of every column in order; must contain each of [`IMU_COLUMNS`].
    pub columns: Vec<String>,
    pub accel_unit: AccelUnit,
    pub gyro_unit: GyroUnit,
    pub time_unit: TimeUnit,
    /// Lines before the data (a header), skipped unread.
    pub header_lines: usize,
    /// Skip the first data line unread (a log that started mid-line).
    pub skip_first_line: bool,
}

impl ImuCsvLayout {
    /// The columns `ax ay az gx gy gz t` in that order with the given
    /// units, no header, the first line read; change the fields for others.
    pub fn new(accel_unit: AccelUnit, gyro_unit: GyroUnit, time_unit: TimeUnit) -> Self {
        Self {
            columns: IMU_COLUMNS.iter().map(|s| s.to_string()).collect(),
            accel_unit,
            gyro_unit,
            time_unit,
            header_lines: 0,
            skip_first_line: false,
        }
    }

    /// Positions of `ax ay az gx gy gz t` in the columns; an error names
    /// the missing or repeated names.
    fn indices(&self) -> Result<[usize; 7]> {
        let missing: Vec<&str> = IMU_COLUMNS
            .iter()
            .copied()
            .filter(|c| !self.columns.iter().any(|x| x == c))
            .collect();
        if !missing.is_empty() {
            return Err(Error::invalid(
                "columns",
                format!(
                    "the layout lacks {missing:?}; it needs each of {IMU_COLUMNS:?} (other names are read and ignored)"
                ),
            ));
        }
        for (i, c) in self.columns.iter().enumerate() {
            if self.columns[..i].contains(c) {
                return Err(Error::invalid(
                    "columns",
                    format!("the name {c:?} appears twice in {:?}", self.columns),
                ));
            }
        }
        Ok(IMU_COLUMNS.map(|c| {
            self.columns
                .iter()
                .position(|x| x == c)
                .expect("checked above")
        }))
    }
}

/// IMU samples in SI units and sensor axes, with where each came from.
#[derive(Debug, Clone, PartialEq)]
pub struct ImuLog {
    /// The log's own clock, s, strictly increasing.
    pub time_s: Vec<f64>,
    /// Specific force, sensor axes, m/s².
    pub specific_force_m_s2: Vec<Vector3<f64>>,
    /// Angular rate, sensor axes, rad/s.
    pub angular_rate_rad_s: Vec<Vector3<f64>>,
    /// 1-based line of each sample in the file.
    pub line: Vec<usize>,
    /// Byte offset of each sample line's newline (to match RTKLIB time tags).
    pub line_end_offset: Vec<u64>,
    /// Size of the file, bytes.
    pub file_bytes: u64,
    /// Newline characters in the whole file.
    pub newline_count: u64,
    /// Lines skipped and implausible contents, one sentence each.
    pub warnings: Vec<String>,
}

/// Reads an IMU CSV log with the declared `layout`.
pub fn read_imu_csv(path: impl AsRef<Path>, layout: &ImuCsvLayout) -> Result<ImuLog> {
    let path = path.as_ref();
    parse_imu_csv(
        &super::read_bytes(path)?,
        &path.display().to_string(),
        layout,
    )
}

/// One parsed line: time and the six sensor values, SI.
struct Sample {
    time_s: f64,
    specific_force: Vector3<f64>,
    angular_rate: Vector3<f64>,
}

/// Parses one CSV record (the fields of one line) into SI values; the
/// error is the reason, without the file and line.
fn parse_record(
    record: &csv::ByteRecord,
    layout: &ImuCsvLayout,
    indices: &[usize; 7],
) -> std::result::Result<Sample, String> {
    if record.len() != layout.columns.len() {
        return Err(format!(
            "expected {} comma-separated fields ({}), got {}",
            layout.columns.len(),
            layout.columns.join(", "),
            record.len()
        ));
    }
    let mut v = [0.0; 7];
    for (k, (&column, name)) in indices.iter().zip(IMU_COLUMNS).enumerate() {
        let bytes = record[column].trim_ascii();
        let text =
            std::str::from_utf8(bytes).map_or_else(|_| String::from_utf8_lossy(bytes), Into::into);
        let x = finite_number(&text).ok_or_else(|| {
            format!(
                "column {} ({name}): expected a finite number, got {text:?}",
                column + 1
            )
        })?;
        let (scale, limit, unit) = match k {
            0..=2 => (
                layout.accel_unit.to_si(),
                MAX_SPECIFIC_FORCE_M_S2,
                layout.accel_unit.symbol(),
            ),
            3..=5 => (
                layout.gyro_unit.to_si(),
                MAX_ANGULAR_RATE_RAD_S,
                layout.gyro_unit.symbol(),
            ),
            _ => (
                layout.time_unit.to_si(),
                MAX_TIME_S,
                layout.time_unit.symbol(),
            ),
        };
        v[k] = x * scale;
        if !v[k].is_finite() || v[k].abs() > limit {
            return Err(format!(
                "column {} ({name}): {text} {unit} is out of range (|{name}| ≤ {} {unit})",
                column + 1,
                limit / scale
            ));
        }
    }
    Ok(Sample {
        time_s: v[6],
        specific_force: Vector3::new(v[0], v[1], v[2]),
        angular_rate: Vector3::new(v[3], v[4], v[5]),
    })
}

/// Parses the bytes of an IMU CSV log; `file` names it in messages.
///
/// Lines: `header_lines` skipped, then the first data line when
/// `skip_first_line`; blank lines ignored. The last line is skipped with a
/// warning when it has no end of line (the recording stopped mid-line:
/// even a line that parses may hold a cut number) or does not parse; any
/// other bad line is an error naming the line and column.
pub fn parse_imu_csv(bytes: &[u8], file: &str, layout: &ImuCsvLayout) -> Result<ImuLog> {
    let indices = layout.indices()?;
    let newlines: Vec<usize> = bytes
        .iter()
        .enumerate()
        .filter_map(|(i, &b)| (b == b'\n').then_some(i))
        .collect();
    let mut warnings = Vec::new();
    // The data: whole lines from `first_line` (0-based) to the last newline.
    let first_line = layout.header_lines + usize::from(layout.skip_first_line);
    let line_start = |k: usize| if k == 0 { 0 } else { newlines[k - 1] + 1 };
    let terminated_end = newlines.last().map_or(0, |&n| n + 1);
    let unterminated = &bytes[terminated_end..];
    if !unterminated.iter().all(u8::is_ascii_whitespace) {
        warnings.push(format!(
            "{file}:{}: last line cut short (no end of line: the log stopped mid-line); skipped",
            newlines.len() + 1
        ));
    }
    let data_start = line_start(first_line.min(newlines.len()));
    let data = if first_line <= newlines.len() {
        &bytes[data_start..terminated_end]
    } else {
        &[][..]
    };
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .quoting(false)
        .from_reader(data);
    let mut time_s = Vec::new();
    let mut specific_force_m_s2 = Vec::new();
    let mut angular_rate_rad_s = Vec::new();
    let mut line = Vec::new();
    let mut line_end_offset = Vec::new();
    // A bad line is an error only once a later line shows it was not the last.
    let mut pending: Option<(usize, String)> = None;
    let mut record = csv::ByteRecord::new();
    loop {
        let more = reader
            .read_byte_record(&mut record)
            .map_err(|e| parse_error(file, first_line + 1, e.to_string()))?;
        if !more {
            break;
        }
        // The record's 1-based line, from the newline that ends it (the csv
        // crate counts neither blank lines in its line numbers nor in the
        // start positions it gives).
        let end = data_start + reader.position().byte() as usize;
        let n = newlines.partition_point(|&o| o + 1 < end) + 1;
        if record.len() == 1 && record[0].trim_ascii().is_empty() {
            continue; // a line of blanks
        }
        if let Some((k, reason)) = pending.take() {
            return Err(parse_error(file, k, reason));
        }
        match parse_record(&record, layout, &indices) {
            Ok(s) => {
                if let Some(&previous) = time_s.last() {
                    if s.time_s <= previous {
                        let scale = layout.time_unit.to_si();
                        return Err(parse_error(
                            file,
                            n,
                            format!(
                                "time {} does not increase (previous line {}: {})",
                                s.time_s / scale,
                                line.last().copied().unwrap_or(0),
                                previous / scale
                            ),
                        ));
                    }
                }
                time_s.push(s.time_s);
                specific_force_m_s2.push(s.specific_force);
                angular_rate_rad_s.push(s.angular_rate);
                line.push(n);
                line_end_offset.push(newlines.get(n - 1).map_or(bytes.len(), |&o| o) as u64);
            }
            Err(reason) => pending = Some((n, reason)),
        }
    }
    if let Some((k, reason)) = pending {
        warnings.push(format!(
            "{file}:{k}: last line cut short ({reason}); skipped"
        ));
    }
    if time_s.len() < 2 {
        return Err(parse_error(
            file,
            newlines.len().max(1),
            format!("expected at least two IMU samples, found {}", time_s.len()),
        ));
    }
    warnings.extend(plausibility(
        file,
        layout,
        &time_s,
        &specific_force_m_s2,
        &angular_rate_rad_s,
        &line,
    ));
    Ok(ImuLog {
        time_s,
        specific_force_m_s2,
        angular_rate_rad_s,
        line,
        line_end_offset,
        file_bytes: bytes.len() as u64,
        newline_count: newlines.len() as u64,
        warnings,
    })
}

/// Warnings when the magnitudes do not fit the declared units (an IMU on
/// Earth reads a specific force near 1 g; navigation rates stay below a
/// few hundred °/s; samples come 1e-5 to 10 s apart) or the time jumps.
fn plausibility(
    file: &str,
    layout: &ImuCsvLayout,
    time_s: &[f64],
    specific_force: &[Vector3<f64>],
    angular_rate: &[Vector3<f64>],
    line: &[usize],
) -> Vec<String> {
    let g = STANDARD_GRAVITY_M_S2;
    let mut out = Vec::new();
    let norms: Vec<f64> = specific_force.iter().map(|f| f.norm()).collect();
    let force_g = median(&norms) / g;
    if !PLAUSIBLE_MEDIAN_FORCE_G.contains(&force_g) {
        let fits = |x: f64| PLAUSIBLE_MEDIAN_FORCE_G.contains(&x);
        let hint = match layout.accel_unit {
            AccelUnit::MetresPerSecondSquared if fits(force_g * g) => {
                "; the values look like g: is accel_unit \"g\"?"
            }
            AccelUnit::StandardGravity if fits(force_g / g) => {
                "; the values look like m/s²: is accel_unit \"m/s^2\"?"
            }
            _ => "",
        };
        out.push(format!(
            "{file}: accel_unit: the median specific-force magnitude is {:.3} {} where an IMU on Earth reads about 1 g (9.81 m/s²){hint}",
            force_g * g / layout.accel_unit.to_si(),
            layout.accel_unit.symbol()
        ));
    }
    let rates: Vec<f64> = angular_rate.iter().map(|w| w.norm()).collect();
    let rate_p99 = quantile(&rates, 0.99);
    if rate_p99 > PLAUSIBLE_RATE_P99_RAD_S {
        let hint = if layout.gyro_unit == GyroUnit::RadiansPerSecond {
            "; the values look like °/s: is gyro_unit \"deg/s\"?"
        } else {
            ""
        };
        out.push(format!(
            "{file}: gyro_unit: 1 % of the angular rates exceed {:.1} {} ({:.0} °/s), more than navigation logs show{hint}",
            rate_p99 / layout.gyro_unit.to_si(),
            layout.gyro_unit.symbol(),
            rate_p99.to_degrees()
        ));
    }
    let intervals: Vec<f64> = time_s.windows(2).map(|w| w[1] - w[0]).collect();
    let step = median(&intervals);
    if !PLAUSIBLE_INTERVAL_S.contains(&step) {
        out.push(format!(
            "{file}: time_unit: the median sample interval is {step:.3e} s, outside the {:.0e}-{:.0} s of IMU logs: is the unit right?",
            PLAUSIBLE_INTERVAL_S.start(),
            PLAUSIBLE_INTERVAL_S.end()
        ));
    }
    let gap_limit = (GAP_INTERVALS * step).max(1.0);
    let gaps: Vec<usize> = (0..intervals.len())
        .filter(|&k| intervals[k] > gap_limit)
        .collect();
    if let Some(&k) = gaps
        .iter()
        .max_by(|&&a, &&b| intervals[a].total_cmp(&intervals[b]))
    {
        out.push(format!(
            "{file}:{}: the time jumps by {:.3} s after line {} (median interval {step:.4} s); {} such gap(s) in the log",
            line[k + 1],
            intervals[k],
            line[k],
            gaps.len()
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout() -> ImuCsvLayout {
        ImuCsvLayout::new(
            AccelUnit::StandardGravity,
            GyroUnit::DegreesPerSecond,
            TimeUnit::Milliseconds,
        )
    }

    fn parse(text: &str) -> Result<ImuLog> {
        parse_imu_csv(text.as_bytes(), "x.csv", &layout())
    }

    #[test]
    fn values_units_lines_and_offsets() {
        let log = parse("0,0,1,0,0,90,10\n\n 0.5 , 0 ,1,0,0,-90,20\r\n0,0,1,0,0,0,30\n").unwrap();
        assert_eq!(log.time_s, [0.010, 0.020, 0.030]);
        assert_eq!(log.line, [1, 3, 4]);
        assert_eq!(log.line_end_offset, [15, 40, 55]);
        assert_eq!((log.file_bytes, log.newline_count), (56, 4));
        assert_eq!(
            log.specific_force_m_s2[1],
            Vector3::new(0.5, 0.0, 1.0) * STANDARD_GRAVITY_M_S2
        );
        assert!((log.angular_rate_rad_s[0].z - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!(log.warnings.is_empty(), "{:?}", log.warnings);
    }

    #[test]
    fn cut_last_lines_are_warnings_and_other_bad_lines_errors() {
        let log = parse("0,0,1,0,0,0,10\n0,0,1,0,0,0,20\n0,0,1,0,0,0,3").unwrap();
        assert_eq!(log.time_s.len(), 2);
        assert!(log.warnings[0].contains("x.csv:3: last line cut short (no end of line"));
        let log = parse("0,0,1,0,0,0,10\n0,0,1,0,0,0,20\n0,0,1,0\n\n").unwrap();
        assert!(
            log.warnings[0].contains("x.csv:3: last line cut short (expected 7"),
            "{:?}",
            log.warnings
        );
        let e = parse("0,0,1,0,0,0,10\n0,0,x,0,0,0,20\n0,0,1,0,0,0,30\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.csv:2: column 3 (az): expected a finite number, got \"x\""
        );
        let e = parse("0,0,1,0,0,0,10\n0,0,1e308,0,0,0,20\n0,0,1,0,0,0,30\n").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("x.csv:2: column 3 (az): 1e308 g is out of range"),
            "{e}"
        );
        let e = parse("0,0,1,0,0,0,10\n0,0,1,0,0,0,10\n0,0,1,0,0,0,30\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.csv:2: time 10 does not increase (previous line 1: 10)"
        );
        let e = parse("0,0,1,0,0,0,10\nnan,0,1,0,0,0,20\n0,0,1,0,0,0,30\n").unwrap_err();
        assert!(e.to_string().contains("column 1 (ax)"), "{e}");
        let e = parse("0,0,1,0,0,0,10\n").unwrap_err();
        assert!(e.to_string().contains("at least two IMU samples"), "{e}");
    }

    #[test]
    fn header_skip_and_layout_errors() {
        let mut l = layout();
        l.header_lines = 1;
        l.skip_first_line = true;
        let text = "ax,ay,az,gx,gy,gz,t\ncut\n0,0,1,0,0,0,10\n0,0,1,0,0,0,20\n";
        let log = parse_imu_csv(text.as_bytes(), "x.csv", &l).unwrap();
        assert_eq!(log.line, [3, 4]);
        l.columns[6] = "time".into();
        let e = parse_imu_csv(text.as_bytes(), "x.csv", &l).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("columns: the layout lacks [\"t\"]"),
            "{e}"
        );
        l.columns[6] = "ax".into();
        assert!(parse_imu_csv(text.as_bytes(), "x.csv", &l).is_err());
        let e = AccelUnit::from_name("gee").unwrap_err();
        assert_eq!(
            e.to_string(),
            "accel_unit: unknown unit 'gee'; expected one of ['g', 'm/s^2', 'm/s2']"
        );
    }

    #[test]
    fn magnitudes_that_do_not_fit_the_units_are_reported() {
        // A gyro in °/s declared as rad/s: a 30 °/s turn reads 30 rad/s.
        let mut l = layout();
        l.gyro_unit = GyroUnit::RadiansPerSecond;
        let text: String = (0..200)
            .map(|k| format!("0,0,1,0,0,{},{}\n", if k > 100 { 30 } else { 0 }, 10 * k))
            .collect();
        let log = parse_imu_csv(text.as_bytes(), "x.csv", &l).unwrap();
        assert_eq!(log.warnings.len(), 1, "{:?}", log.warnings);
        assert!(log.warnings[0].contains("is gyro_unit \"deg/s\"?"));
        // Specific force in g declared as m/s².
        l = layout();
        l.accel_unit = AccelUnit::MetresPerSecondSquared;
        let log = parse_imu_csv(b"0,0,1,0,0,0,0\n0,0,1,0,0,0,10\n", "x.csv", &l).unwrap();
        assert!(
            log.warnings[0].contains("is accel_unit \"g\"?"),
            "{:?}",
            log.warnings
        );
        // Times in ms declared as s (100 Hz read as 0.1 Hz).
        l = layout();
        l.time_unit = TimeUnit::Seconds;
        let log = parse_imu_csv(b"0,0,1,0,0,0,0\n0,0,1,0,0,0,10\n", "x.csv", &l).unwrap();
        assert!(log.warnings[0].contains("time_unit"), "{:?}", log.warnings);
        // A gap of 1e6 s in a 100 Hz log.
        let log =
            parse("0,0,1,0,0,0,0\n0,0,1,0,0,0,10\n0,0,1,0,0,0,20\n0,0,1,0,0,0,1e9\n").unwrap();
        assert_eq!(log.warnings.len(), 1, "{:?}", log.warnings);
        assert!(log.warnings[0].starts_with("x.csv:4: the time jumps by 999999.980 s after line 3"));
    }
}
