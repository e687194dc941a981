//! IMU logs in CSV: one sample a line, comma-separated columns whose
//! names, units and axes the user declares (the layout of consumer loggers
//! such as the `real-imu-gnss` logs: `ax, ay, az` in g, `gx, gy, gz` in
//! °/s, `t` in ms; or an industrial IMU's velocity and angle increments in
//! its own column order and axes). Parsed with the `csv` crate; every value
//! is range-checked and converted to SI and to memsnav's FRD axes.
//!
//! **Increments.** An IMU that integrates (most industrial ones: Δθ, Δv
//! per output) is declared by its units (`accel_unit` "m/s" or "g*s",
//! `gyro_unit` "rad" or "deg"). Row k's increments cover the interval
//! since row k − 1, (t_{k−1}, t_k]; the first row only opens the first
//! interval. The coupled filter propagates from samples (its INS step
//! integrates the rate between two samples by the trapezoid, and its
//! aiding epochs fall between samples by interpolation), so each interval
//! becomes one sample: the mean rate Δθ/Δt and mean specific force Δv/Δt,
//! placed at the interval's middle (t_{k−1} + t_k)/2, where a rate that
//! varies linearly over the interval takes its mean (a second-order
//! estimate of the instantaneous rate; tagging it at t_k instead would
//! delay the whole solution by half a sample: 5 ms at 100 Hz, 10 cm at
//! 20 m/s). The division is exact up to rounding, so a log given as
//! increments and the same log given as those mean rates at the middles
//! run to the same solution (tests/test_imu_layouts.py, 1e-9 m).
//!
//! **Timing.** Time must increase strictly (a repeated or backward stamp
//! is an error naming the file and line); the INS integrates over each
//! actual interval. [`ImuTiming`] reports the median interval, the jitter
//! and the gaps (intervals longer than [`GAP_FACTOR`] median intervals:
//! at least one sample missing).

use std::path::Path;

use nalgebra::{Matrix3, Vector3};

use super::fields::{finite_number, median, parse_error, quantile};
use crate::geodesy::wgs84::STANDARD_GRAVITY_M_S2;
use crate::{known_keys, validate, Error, Result};

/// The quantities a layout must place: accelerometer, gyro, time. In the
/// `columns` list form other names are read and ignored.
pub const IMU_COLUMNS: [&str; 7] = ["ax", "ay", "az", "gx", "gy", "gz", "t"];

/// Largest specific-force component accepted, m/s² (1000 g): beyond any
/// navigation IMU's range, so a larger value is a corrupted field.
pub const MAX_SPECIFIC_FORCE_M_S2: f64 = 1_000.0 * STANDARD_GRAVITY_M_S2;

/// Largest angular-rate component accepted, rad/s (about 5 700 °/s; MEMS
/// gyros stop at ±4 000 °/s).
pub const MAX_ANGULAR_RATE_RAD_S: f64 = 100.0;

/// Longest interval an increment may cover for its range check, s: the
/// increments of a row are checked against the rate limits over this long
/// (then again as mean rates over their actual interval).
const MAX_INCREMENT_INTERVAL_S: f64 = 100.0;

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

/// A gap longer than this many median intervals (and than 1 s) is a
/// warning.
const GAP_INTERVALS: f64 = 50.0;

/// An interval longer than this many median intervals is counted as a gap
/// in [`ImuTiming`]: at least one sample is missing (a jitter of ±25 % of
/// the interval, already far beyond a logger's, stays below it).
pub const GAP_FACTOR: f64 = 1.5;

/// Unit of the accelerometer columns: a specific force (rates) or a
/// velocity increment per row (increments).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AccelUnit {
    /// Standard gravity, 9.80665 m/s².
    StandardGravity,
    /// m/s².
    MetresPerSecondSquared,
    /// Velocity increment, m/s.
    MetresPerSecond,
    /// Velocity increment in g·s (9.80665 m/s).
    StandardGravitySeconds,
}

/// Unit of the gyro columns: an angular rate (rates) or an angle
/// increment per row (increments).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GyroUnit {
    /// Angular rate, °/s.
    DegreesPerSecond,
    /// Angular rate, rad/s.
    RadiansPerSecond,
    /// Angle increment, degrees.
    Degrees,
    /// Angle increment, radians.
    Radians,
}

/// Unit of the time column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeUnit {
    /// Milliseconds.
    Milliseconds,
    /// Seconds.
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
    const NAMES: [&str; 6] = ["g", "m/s^2", "m/s2", "m/s", "g*s", "g.s"];

    /// The unit named `name`: rates `"g"`, `"m/s^2"` (`"m/s2"`);
    /// increments `"m/s"`, `"g*s"` (`"g.s"`).
    pub fn from_name(name: &str) -> Result<Self> {
        match name {
            "g" => Ok(Self::StandardGravity),
            "m/s^2" | "m/s2" => Ok(Self::MetresPerSecondSquared),
            "m/s" => Ok(Self::MetresPerSecond),
            "g*s" | "g.s" => Ok(Self::StandardGravitySeconds),
            _ => Err(unknown_unit("accel_unit", name, &Self::NAMES)),
        }
    }

    /// m/s² (rates) or m/s (increments) per unit.
    pub fn to_si(self) -> f64 {
        match self {
            Self::StandardGravity | Self::StandardGravitySeconds => STANDARD_GRAVITY_M_S2,
            Self::MetresPerSecondSquared | Self::MetresPerSecond => 1.0,
        }
    }

    /// Whether the column holds a velocity increment per row.
    pub fn is_increment(self) -> bool {
        matches!(self, Self::MetresPerSecond | Self::StandardGravitySeconds)
    }

    fn symbol(self) -> &'static str {
        match self {
            Self::StandardGravity => "g",
            Self::MetresPerSecondSquared => "m/s²",
            Self::MetresPerSecond => "m/s",
            Self::StandardGravitySeconds => "g·s",
        }
    }
}

impl GyroUnit {
    const NAMES: [&str; 4] = ["deg/s", "rad/s", "deg", "rad"];

    /// The unit named `name`: rates `"deg/s"`, `"rad/s"`; increments
    /// `"deg"`, `"rad"`.
    pub fn from_name(name: &str) -> Result<Self> {
        match name {
            "deg/s" => Ok(Self::DegreesPerSecond),
            "rad/s" => Ok(Self::RadiansPerSecond),
            "deg" => Ok(Self::Degrees),
            "rad" => Ok(Self::Radians),
            _ => Err(unknown_unit("gyro_unit", name, &Self::NAMES)),
        }
    }

    /// rad/s (rates) or rad (increments) per unit.
    pub fn to_si(self) -> f64 {
        match self {
            Self::DegreesPerSecond | Self::Degrees => std::f64::consts::PI / 180.0,
            Self::RadiansPerSecond | Self::Radians => 1.0,
        }
    }

    /// Whether the column holds an angle increment per row.
    pub fn is_increment(self) -> bool {
        matches!(self, Self::Degrees | Self::Radians)
    }

    fn symbol(self) -> &'static str {
        match self {
            Self::DegreesPerSecond => "°/s",
            Self::RadiansPerSecond => "rad/s",
            Self::Degrees => "°",
            Self::Radians => "rad",
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

/// The axis conventions a log's x, y, z may follow, by name.
pub const AXES_NAMES: [&str; 5] = ["FRD", "NED", "FLU", "RFU", "ENU"];

/// C: the log's axes to memsnav's sensor axes (x forward, y right, z
/// down: FRD), v_FRD = C v_log, for a convention named in [`AXES_NAMES`]:
/// `"FRD"` (memsnav's own; `"NED"`: the axes of a level IMU facing north),
/// `"FLU"` (x forward, y left, z up: ROS REP 103), `"RFU"` (x right, y
/// forward, z up; `"ENU"`: the axes of a level IMU facing north).
pub fn axes_from_name(name: &str) -> Result<Matrix3<f64>> {
    match name {
        "FRD" | "NED" => Ok(Matrix3::identity()),
        "FLU" => Ok(Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, -1.0))),
        "RFU" | "ENU" => Ok(Matrix3::new(
            0.0, 1.0, 0.0, //
            1.0, 0.0, 0.0, //
            0.0, 0.0, -1.0,
        )),
        _ => {
            let hint = known_keys::closest(name, &AXES_NAMES)
                .map(|k| format!(" (did you mean {k:?}?)"))
                .unwrap_or_default();
            Err(Error::invalid(
                "axes",
                format!(
                    "unknown axis convention {name:?}{hint}; expected one of {} or a 3×3 rotation matrix",
                    AXES_NAMES.join(", ")
                ),
            ))
        }
    }
}

/// Where each quantity of [`IMU_COLUMNS`] is in a line.
#[derive(Debug, Clone, PartialEq)]
pub enum ImuColumns {
    /// The name of every column in order; must contain each of
    /// [`IMU_COLUMNS`] once, other names are read and ignored. A line must
    /// have exactly this many fields.
    Names(Vec<String>),
    /// Each quantity's column by its name in the file's header line: the
    /// first line after `header_lines` (quantity, header name); columns
    /// not named are ignored.
    Header(Vec<(String, String)>),
    /// Each quantity's column by its 1-based number (quantity, number);
    /// columns not named are ignored, a line may have more.
    Numbers(Vec<(String, usize)>),
}

impl ImuColumns {
    /// The standard order `ax ay az gx gy gz t`.
    pub fn standard() -> Self {
        Self::Names(IMU_COLUMNS.iter().map(|s| s.to_string()).collect())
    }
}

/// The declared layout of an IMU CSV log.
#[derive(Debug, Clone, PartialEq)]
pub struct ImuCsvLayout {
    /// Where each quantity is.
    pub columns: ImuColumns,
    /// Unit of the accelerometer columns.
    pub accel_unit: AccelUnit,
    /// Unit of the gyro columns.
    pub gyro_unit: GyroUnit,
    /// Unit of the time column.
    pub time_unit: TimeUnit,
    /// C: the log's axes to FRD sensor axes (v_FRD = C v_log): identity
    /// for FRD, [`axes_from_name`] for the named conventions, or any
    /// rotation.
    pub axes: Matrix3<f64>,
    /// Lines before the data (or before the header line of
    /// [`ImuColumns::Header`]), skipped unread.
    pub header_lines: usize,
    /// Skip the first data line unread (a log that started mid-line).
    pub skip_first_line: bool,
}

/// The columns of one file resolved: the index of each quantity, and the
/// number of fields a line must have (exactly, or at least).
struct Resolved {
    indices: [usize; 7],
    fields: usize,
    exact: bool,
    /// The data start one line later (the header line).
    header_line: bool,
}

impl ImuCsvLayout {
    /// The columns `ax ay az gx gy gz t` in that order with the given
    /// units, FRD axes, no header, the first line read; change the fields
    /// for others.
    pub fn new(accel_unit: AccelUnit, gyro_unit: GyroUnit, time_unit: TimeUnit) -> Self {
        Self {
            columns: ImuColumns::standard(),
            accel_unit,
            gyro_unit,
            time_unit,
            axes: Matrix3::identity(),
            header_lines: 0,
            skip_first_line: false,
        }
    }

    /// Whether the log holds increments (its units say so; both must).
    pub fn increments(&self) -> Result<bool> {
        let (a, g) = (
            self.accel_unit.is_increment(),
            self.gyro_unit.is_increment(),
        );
        if a != g {
            return Err(Error::invalid(
                "accel_unit, gyro_unit",
                format!(
                    "the accelerometer is declared as {} ({}) and the gyro as {} ({}): give both as rates (m/s^2 or g, rad/s or deg/s) or both as increments per row (m/s or g*s, rad or deg)",
                    if a { "increments" } else { "rates" },
                    self.accel_unit.symbol(),
                    if g { "increments" } else { "rates" },
                    self.gyro_unit.symbol()
                ),
            ));
        }
        Ok(a)
    }

    /// Each quantity's place in a map form, every quantity exactly once and
    /// no other key (an unknown one names what was meant).
    fn placed<T: Clone>(pairs: &[(String, T)]) -> Result<[T; 7]> {
        for (key, _) in pairs {
            known_keys::check("columns", key, &IMU_COLUMNS)?;
        }
        let mut out = Vec::with_capacity(7);
        for q in IMU_COLUMNS {
            let mut found = pairs.iter().filter(|(k, _)| k == q);
            let Some((_, v)) = found.next() else {
                return Err(Error::invalid(
                    "columns",
                    format!("no column given for {q:?}; it needs each of {IMU_COLUMNS:?}"),
                ));
            };
            if found.next().is_some() {
                return Err(Error::invalid("columns", format!("{q:?} is given twice")));
            }
            out.push(v.clone());
        }
        Ok(out
            .try_into()
            .unwrap_or_else(|_| unreachable!("seven quantities")))
    }

    /// The index of each quantity and the fields of a line, for a file
    /// whose header line (used by [`ImuColumns::Header`] only) is
    /// `header`; an error names the missing, repeated or unknown names (a
    /// header without them: the `file` and its line).
    fn resolve(&self, header: Option<&str>, file: &str) -> Result<Resolved> {
        let header_line = self.header_lines + 1;
        let distinct = |indices: &[usize; 7], what: &dyn Fn(usize) -> String| -> Result<()> {
            for (i, a) in indices.iter().enumerate() {
                if let Some(j) = indices[..i].iter().position(|b| b == a) {
                    return Err(Error::invalid(
                        "columns",
                        format!(
                            "{:?} and {:?} are both {}",
                            IMU_COLUMNS[j],
                            IMU_COLUMNS[i],
                            what(*a)
                        ),
                    ));
                }
            }
            Ok(())
        };
        match &self.columns {
            ImuColumns::Names(names) => {
                let missing: Vec<&str> = IMU_COLUMNS
                    .iter()
                    .copied()
                    .filter(|c| !names.iter().any(|x| x == c))
                    .collect();
                if !missing.is_empty() {
                    return Err(Error::invalid(
                        "columns",
                        format!(
                            "the layout lacks {missing:?}; it needs each of {IMU_COLUMNS:?} (other names are read and ignored)"
                        ),
                    ));
                }
                for (i, c) in names.iter().enumerate() {
                    if names[..i].contains(c) {
                        return Err(Error::invalid(
                            "columns",
                            format!("the name {c:?} appears twice in {names:?}"),
                        ));
                    }
                }
                Ok(Resolved {
                    indices: IMU_COLUMNS
                        .map(|c| names.iter().position(|x| x == c).expect("checked above")),
                    fields: names.len(),
                    exact: true,
                    header_line: false,
                })
            }
            ImuColumns::Numbers(pairs) => {
                let numbers = Self::placed(pairs)?;
                if let Some(q) = (0..7).find(|&k| numbers[k] == 0) {
                    return Err(Error::invalid(
                        "columns",
                        format!("{:?} = 0: columns are numbered from 1", IMU_COLUMNS[q]),
                    ));
                }
                let indices = numbers.map(|n| n - 1);
                distinct(&indices, &|i| format!("column {}", i + 1))?;
                Ok(Resolved {
                    indices,
                    fields: indices.iter().max().expect("seven") + 1,
                    exact: false,
                    header_line: false,
                })
            }
            ImuColumns::Header(pairs) => {
                let wanted = Self::placed(pairs)?;
                let header = header.ok_or_else(|| {
                    parse_error(
                        file,
                        header_line,
                        "columns by header name need a header line here (after header_lines): the file ends before it",
                    )
                })?;
                let names: Vec<&str> = header.split(',').map(str::trim).collect();
                let mut indices = [0; 7];
                for (k, w) in wanted.iter().enumerate() {
                    let mut at = names.iter().enumerate().filter(|(_, n)| *n == w);
                    let Some((i, _)) = at.next() else {
                        let listed: Vec<&str> = names.iter().copied().take(40).collect();
                        let hint = known_keys::closest(w, &listed)
                            .map(|k| format!(" (did you mean {k:?}?)"))
                            .unwrap_or_default();
                        return Err(parse_error(
                            file,
                            header_line,
                            format!(
                                "columns.{}: the header has no column {w:?}{hint}; its columns are {listed:?}",
                                IMU_COLUMNS[k]
                            ),
                        ));
                    };
                    if at.next().is_some() {
                        return Err(parse_error(
                            file,
                            header_line,
                            format!("columns.{}: the header names {w:?} twice", IMU_COLUMNS[k]),
                        ));
                    }
                    indices[k] = i;
                }
                distinct(&indices, &|i| format!("header column {:?}", names[i]))?;
                Ok(Resolved {
                    indices,
                    fields: names.len(),
                    exact: true,
                    header_line: true,
                })
            }
        }
    }
}

/// The sampling of a log, on the time stamps of its lines.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuTiming {
    /// Median interval between lines, s.
    pub median_interval_s: f64,
    /// Standard deviation of the intervals that are not gaps, s (the
    /// jitter of the time stamps).
    pub interval_std_s: f64,
    /// Shortest interval, s.
    pub min_interval_s: f64,
    /// Longest interval, s.
    pub max_interval_s: f64,
    /// An interval above this is a gap: [`GAP_FACTOR`] median intervals, s.
    pub gap_threshold_s: f64,
    /// Intervals above `gap_threshold_s`.
    pub gap_count: usize,
    /// The longest gap, s (0 without gaps).
    pub largest_gap_s: f64,
    /// The 1-based line after the longest gap (0 without gaps).
    pub largest_gap_line: usize,
}

impl ImuTiming {
    /// The sampling of stamps `time_s` on lines `line` (at least two).
    fn of(time_s: &[f64], line: &[usize]) -> Self {
        if time_s.len() < 2 {
            return Self {
                median_interval_s: f64::NAN,
                interval_std_s: f64::NAN,
                min_interval_s: f64::NAN,
                max_interval_s: f64::NAN,
                gap_threshold_s: f64::NAN,
                gap_count: 0,
                largest_gap_s: 0.0,
                largest_gap_line: 0,
            };
        }
        let intervals: Vec<f64> = time_s.windows(2).map(|w| w[1] - w[0]).collect();
        let step = median(&intervals);
        let gap_threshold_s = GAP_FACTOR * step;
        let regular: Vec<f64> = intervals
            .iter()
            .copied()
            .filter(|&d| d <= gap_threshold_s)
            .collect();
        let mean = regular.iter().sum::<f64>() / regular.len() as f64;
        let variance =
            regular.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / regular.len() as f64;
        let largest = (0..intervals.len())
            .filter(|&k| intervals[k] > gap_threshold_s)
            .max_by(|&a, &b| intervals[a].total_cmp(&intervals[b]));
        Self {
            median_interval_s: step,
            interval_std_s: variance.sqrt(),
            min_interval_s: intervals.iter().copied().fold(f64::INFINITY, f64::min),
            max_interval_s: intervals.iter().copied().fold(0.0, f64::max),
            gap_threshold_s,
            gap_count: intervals.iter().filter(|&&d| d > gap_threshold_s).count(),
            largest_gap_s: largest.map_or(0.0, |k| intervals[k]),
            largest_gap_line: largest.map_or(0, |k| line[k + 1]),
        }
    }
}

/// IMU samples in SI units and FRD sensor axes, with where each came from.
#[derive(Debug, Clone, PartialEq)]
pub struct ImuLog {
    /// The log's own clock, s, strictly increasing: each sample's time (for
    /// increments, the middle of the interval it averages).
    pub time_s: Vec<f64>,
    /// Specific force, sensor axes, m/s².
    pub specific_force_m_s2: Vec<Vector3<f64>>,
    /// Angular rate, sensor axes, rad/s.
    pub angular_rate_rad_s: Vec<Vector3<f64>>,
    /// The time stamp written on each sample's line, s (the log's clock:
    /// `time_s` for rates, the end of the interval for increments); what a
    /// time tag's arrivals are compared with.
    pub line_time_s: Vec<f64>,
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

impl ImuLog {
    /// The sampling of the log's lines: intervals, jitter, gaps.
    pub fn timing(&self) -> ImuTiming {
        ImuTiming::of(&self.line_time_s, &self.line)
    }
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

/// One parsed line: time and the six sensor values, SI, FRD axes (rates,
/// or increments over the interval the line closes).
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
    resolved: &Resolved,
    increments: bool,
) -> std::result::Result<Sample, String> {
    let fields_ok = if resolved.exact {
        record.len() == resolved.fields
    } else {
        record.len() >= resolved.fields
    };
    if !fields_ok {
        let (count, which) = match &layout.columns {
            ImuColumns::Names(names) => (names.len().to_string(), names.join(", ")),
            ImuColumns::Header(_) => (resolved.fields.to_string(), "the header's".into()),
            ImuColumns::Numbers(_) => (
                format!("at least {}", resolved.fields),
                "the highest column number".into(),
            ),
        };
        return Err(format!(
            "expected {count} comma-separated fields ({which}), got {}",
            record.len()
        ));
    }
    // Increments are range-checked as rates held over the longest interval
    // an increment may cover (again as mean rates once the interval is known).
    let span = if increments {
        MAX_INCREMENT_INTERVAL_S
    } else {
        1.0
    };
    let mut v = [0.0; 7];
    for (k, (&column, name)) in resolved.indices.iter().zip(IMU_COLUMNS).enumerate() {
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
                MAX_SPECIFIC_FORCE_M_S2 * span,
                layout.accel_unit.symbol(),
            ),
            3..=5 => (
                layout.gyro_unit.to_si(),
                MAX_ANGULAR_RATE_RAD_S * span,
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
        specific_force: layout.axes * Vector3::new(v[0], v[1], v[2]),
        angular_rate: layout.axes * Vector3::new(v[3], v[4], v[5]),
    })
}

/// Parses the bytes of an IMU CSV log; `file` names it in messages.
///
/// Lines: `header_lines` skipped, then (columns by header name) the header
/// line, then the first data line when `skip_first_line`; blank lines
/// ignored. The last line is skipped with a warning when it has no end of
/// line (the recording stopped mid-line: even a line that parses may hold
/// a cut number) or does not parse; any other bad line is an error naming
/// the line and column. Increments become mean rates at the middle of
/// their intervals (see the module notes).
pub fn parse_imu_csv(bytes: &[u8], file: &str, layout: &ImuCsvLayout) -> Result<ImuLog> {
    validate::rotation("axes", &layout.axes)?;
    let increments = layout.increments()?;
    let newlines: Vec<usize> = bytes
        .iter()
        .enumerate()
        .filter_map(|(i, &b)| (b == b'\n').then_some(i))
        .collect();
    let line_start = |k: usize| if k == 0 { 0 } else { newlines[k - 1] + 1 };
    // The header line, when the columns are named by it: the first line
    // after `header_lines` (whole, with its end of line).
    let header = (layout.header_lines < newlines.len()).then(|| {
        let k = layout.header_lines;
        String::from_utf8_lossy(&bytes[line_start(k)..newlines[k]]).into_owned()
    });
    let resolved = layout.resolve(header.as_deref(), file)?;
    let mut warnings = Vec::new();
    // The data: whole lines from `first_line` (0-based) to the last newline.
    let first_line = layout.header_lines
        + usize::from(resolved.header_line)
        + usize::from(layout.skip_first_line);
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
    let mut rows: Vec<Sample> = Vec::new();
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
        match parse_record(&record, layout, &resolved, increments) {
            Ok(s) => {
                if let Some(previous) = rows.last() {
                    if s.time_s <= previous.time_s {
                        let scale = layout.time_unit.to_si();
                        let how = if s.time_s == previous.time_s {
                            "repeats"
                        } else {
                            "goes backwards from"
                        };
                        return Err(parse_error(
                            file,
                            n,
                            format!(
                                "time {} {how} the previous line's (line {}: {}): times must increase",
                                s.time_s / scale,
                                line.last().copied().unwrap_or(0),
                                previous.time_s / scale
                            ),
                        ));
                    }
                }
                rows.push(s);
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
    let needed = if increments {
        (
            3,
            "three increment rows (the first only opens the first interval)",
        )
    } else {
        (2, "two IMU samples")
    };
    if rows.len() < needed.0 {
        return Err(parse_error(
            file,
            newlines.len().max(1),
            format!("expected at least {}, found {}", needed.1, rows.len()),
        ));
    }
    let mut log = if increments {
        mean_rates(file, &rows, &line, &line_end_offset)?
    } else {
        ImuLog {
            time_s: rows.iter().map(|s| s.time_s).collect(),
            specific_force_m_s2: rows.iter().map(|s| s.specific_force).collect(),
            angular_rate_rad_s: rows.iter().map(|s| s.angular_rate).collect(),
            line_time_s: rows.iter().map(|s| s.time_s).collect(),
            line,
            line_end_offset,
            file_bytes: 0,
            newline_count: 0,
            warnings: Vec::new(),
        }
    };
    log.file_bytes = bytes.len() as u64;
    log.newline_count = newlines.len() as u64;
    warnings.extend(plausibility(file, layout, &log));
    log.warnings = warnings;
    Ok(log)
}

/// Increment rows to samples: row k (k ≥ 1) covers (t_{k−1}, t_k] and
/// becomes its mean specific force and rate, at the interval's middle. A
/// mean beyond the sensor limits (an increment over too short an
/// interval) is an error naming the line.
fn mean_rates(
    file: &str,
    rows: &[Sample],
    line: &[usize],
    line_end_offset: &[u64],
) -> Result<ImuLog> {
    let n = rows.len() - 1;
    let mut log = ImuLog {
        time_s: Vec::with_capacity(n),
        specific_force_m_s2: Vec::with_capacity(n),
        angular_rate_rad_s: Vec::with_capacity(n),
        line_time_s: Vec::with_capacity(n),
        line: line[1..].to_vec(),
        line_end_offset: line_end_offset[1..].to_vec(),
        file_bytes: 0,
        newline_count: 0,
        warnings: Vec::new(),
    };
    for (k, w) in rows.windows(2).enumerate() {
        let dt = w[1].time_s - w[0].time_s;
        let f = w[1].specific_force / dt;
        let omega = w[1].angular_rate / dt;
        for (what, v, limit, unit) in [
            ("velocity", f, MAX_SPECIFIC_FORCE_M_S2, "m/s²"),
            ("angle", omega, MAX_ANGULAR_RATE_RAD_S, "rad/s"),
        ] {
            if v.amax() > limit {
                return Err(parse_error(
                    file,
                    line[k + 1],
                    format!(
                        "the {what} increment over the {dt:e} s since line {} is a mean of {:e} {unit}, beyond ±{limit:e} {unit}",
                        line[k],
                        v.amax()
                    ),
                ));
            }
        }
        let middle = w[0].time_s + 0.5 * dt;
        if log.time_s.last().is_some_and(|&t| middle <= t) {
            return Err(parse_error(
                file,
                line[k + 1],
                format!(
                    "the interval since line {} ({dt:e} s) is too short for its time stamps' precision: its middle does not follow the previous one",
                    line[k]
                ),
            ));
        }
        log.time_s.push(middle);
        log.specific_force_m_s2.push(f);
        log.angular_rate_rad_s.push(omega);
        log.line_time_s.push(w[1].time_s);
    }
    Ok(log)
}

/// Warnings when the magnitudes do not fit the declared units (an IMU on
/// Earth reads a specific force near 1 g; navigation rates stay below a
/// few hundred °/s; samples come 1e-5 to 0.5 s apart) or the time jumps.
/// The magnitudes are those of the samples (for increments, the mean
/// rates), quoted in SI.
fn plausibility(file: &str, layout: &ImuCsvLayout, log: &ImuLog) -> Vec<String> {
    let g = STANDARD_GRAVITY_M_S2;
    let mut out = Vec::new();
    let norms: Vec<f64> = log.specific_force_m_s2.iter().map(|f| f.norm()).collect();
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
            AccelUnit::MetresPerSecond if fits(force_g * g) => {
                "; the values look like g·s: is accel_unit \"g*s\"?"
            }
            AccelUnit::StandardGravitySeconds if fits(force_g / g) => {
                "; the values look like m/s: is accel_unit \"m/s\"?"
            }
            _ => "",
        };
        out.push(format!(
            "{file}: accel_unit: the median specific-force magnitude is {:.3} m/s² ({force_g:.3} g; accel_unit {}) where an IMU on Earth reads about 1 g (9.81 m/s²){hint}",
            force_g * g,
            layout.accel_unit.symbol()
        ));
    }
    let rates: Vec<f64> = log.angular_rate_rad_s.iter().map(|w| w.norm()).collect();
    let rate_p99 = quantile(&rates, 0.99);
    if rate_p99 > PLAUSIBLE_RATE_P99_RAD_S {
        let hint = match layout.gyro_unit {
            GyroUnit::RadiansPerSecond => "; the values look like °/s: is gyro_unit \"deg/s\"?",
            GyroUnit::Radians => "; the values look like degrees: is gyro_unit \"deg\"?",
            _ => "",
        };
        out.push(format!(
            "{file}: gyro_unit: 1 % of the angular rates exceed {rate_p99:.1} rad/s ({:.0} °/s; gyro_unit {}), more than navigation logs show{hint}",
            rate_p99.to_degrees(),
            layout.gyro_unit.symbol()
        ));
    }
    let timing = log.timing();
    let step = timing.median_interval_s;
    if !PLAUSIBLE_INTERVAL_S.contains(&step) {
        out.push(format!(
            "{file}: time_unit: the median sample interval is {step:.3e} s, outside the {:.0e}-{:.0} s of IMU logs: is the unit right?",
            PLAUSIBLE_INTERVAL_S.start(),
            PLAUSIBLE_INTERVAL_S.end()
        ));
    }
    let gap_limit = (GAP_INTERVALS * step).max(1.0);
    if timing.largest_gap_s > gap_limit {
        let gaps = log
            .line_time_s
            .windows(2)
            .filter(|w| w[1] - w[0] > gap_limit)
            .count();
        let k = log
            .line
            .iter()
            .position(|&l| l == timing.largest_gap_line)
            .expect("the gap's line is a sample's");
        out.push(format!(
            "{file}:{}: the time jumps by {:.3} s after line {} (median interval {step:.4} s); {gaps} such gap(s) in the log",
            timing.largest_gap_line,
            timing.largest_gap_s,
            log.line[k - 1],
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
            "x.csv:2: time 10 repeats the previous line's (line 1: 10): times must increase"
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
        l.columns = ImuColumns::Names(
            ["ax", "ay", "az", "gx", "gy", "gz", "time"]
                .map(String::from)
                .to_vec(),
        );
        let e = parse_imu_csv(text.as_bytes(), "x.csv", &l).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("columns: the layout lacks [\"t\"]"),
            "{e}"
        );
        l.columns = ImuColumns::Names(
            ["ax", "ay", "az", "gx", "gy", "gz", "ax"]
                .map(String::from)
                .to_vec(),
        );
        assert!(parse_imu_csv(text.as_bytes(), "x.csv", &l).is_err());
        let e = AccelUnit::from_name("gee").unwrap_err();
        assert_eq!(
            e.to_string(),
            "accel_unit: unknown unit 'gee'; expected one of ['g', 'm/s^2', 'm/s2', 'm/s', 'g*s', 'g.s']"
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

    /// Increments in FLU axes, columns by header name in another order:
    /// mean rates in FRD at the middles of the intervals, the first row
    /// only opening the first interval.
    #[test]
    fn increments_by_header_in_flu_axes() {
        let mut l = ImuCsvLayout::new(
            AccelUnit::MetresPerSecond,
            GyroUnit::Degrees,
            TimeUnit::Seconds,
        );
        l.axes = axes_from_name("FLU").unwrap();
        l.header_lines = 1;
        let map = [
            ("t", "time"),
            ("gx", "dtx"),
            ("gy", "dty"),
            ("gz", "dtz"),
            ("ax", "dvx"),
            ("ay", "dvy"),
            ("az", "dvz"),
        ];
        l.columns = ImuColumns::Header(
            map.iter()
                .map(|(q, n)| (q.to_string(), n.to_string()))
                .collect(),
        );
        let text = "# a preamble\ntime,dtx,dty,dtz,dvx,dvy,dvz,temp\n\
                    1.00,9,9,9,9,9,9,20\n1.01,0.1,0.2,-0.3,0,0,0.0981,20\n1.03,0,0,0.2,0.02,0,0.1962,21\n";
        let log = parse_imu_csv(text.as_bytes(), "x.csv", &l).unwrap();
        assert_eq!(log.line, [4, 5]);
        assert_eq!(log.line_time_s, [1.01, 1.03]);
        assert!((log.time_s[0] - 1.005).abs() < 1e-15 && (log.time_s[1] - 1.02).abs() < 1e-15);
        let d = std::f64::consts::PI / 180.0;
        let w0 = log.angular_rate_rad_s[0];
        let dt0 = 1.01 - 1.00;
        assert!((w0 - Vector3::new(0.1, -0.2, 0.3) * d / dt0).norm() < 1e-12);
        let f1 = log.specific_force_m_s2[1];
        assert!((f1 - Vector3::new(1.0, 0.0, -9.81)).norm() < 1e-9, "{f1}");
        // 1.03 − 1.01 is 0.02 s: a gap of two median intervals? Two lines
        // give one interval: no gap to count.
        assert_eq!(log.timing().gap_count, 0);
        // Unknown quantity and header name: errors naming what was meant.
        let mut bad = l.clone();
        if let ImuColumns::Header(pairs) = &mut bad.columns {
            pairs[0].0 = "tt".into();
        }
        let e = parse_imu_csv(text.as_bytes(), "x.csv", &bad).unwrap_err();
        assert!(
            e.to_string()
                .contains("unknown key \"tt\" (did you mean \"t\"?)"),
            "{e}"
        );
        let mut bad = l.clone();
        if let ImuColumns::Header(pairs) = &mut bad.columns {
            pairs[0].1 = "tme".into();
        }
        let e = parse_imu_csv(text.as_bytes(), "x.csv", &bad).unwrap_err();
        assert!(
            e.to_string().starts_with(
                "x.csv:2: columns.t: the header has no column \"tme\" (did you mean \"time\"?)"
            ),
            "{e}"
        );
        // Rates and increments mixed: refused.
        let mut bad = l.clone();
        bad.gyro_unit = GyroUnit::DegreesPerSecond;
        let e = parse_imu_csv(text.as_bytes(), "x.csv", &bad).unwrap_err();
        assert!(e.to_string().starts_with("accel_unit, gyro_unit:"), "{e}");
        // An increment over a microsecond: a mean rate beyond the gyro.
        let e = parse_imu_csv(
            b"time,dtx,dty,dtz,dvx,dvy,dvz,temp\n0,0,0,0,0,0,0,0\n0.000001,0,0,90,0,0,0,0\n0.01,0,0,0,0,0,0,0\n",
            "y.csv",
            &ImuCsvLayout {
                header_lines: 0,
                ..l.clone()
            },
        )
        .unwrap_err();
        assert!(
            e.to_string()
                .starts_with("y.csv:3: the angle increment over the 1e-6 s since line 2"),
            "{e}"
        );
    }

    /// Columns by number, any axes rotation, and the timing of a log with
    /// jitter and a gap.
    #[test]
    fn numbered_columns_rotations_and_timing() {
        let mut l = layout();
        l.columns = ImuColumns::Numbers(
            IMU_COLUMNS
                .iter()
                .enumerate()
                .map(|(k, q)| (q.to_string(), 7 - k))
                .collect(),
        );
        l.axes = axes_from_name("ENU").unwrap();
        // t gz gy gx az ay ax (and an 8th column ignored).
        let mut text = String::new();
        let mut t = 0.0;
        for k in 0..100 {
            t += if k == 50 {
                50.0
            } else if k % 2 == 0 {
                9.0
            } else {
                11.0
            };
            text += &format!("{t},0,0,0,-1,0,0,x\n");
        }
        let log = parse_imu_csv(text.as_bytes(), "x.csv", &l).unwrap();
        // ENU (x right, y forward, z up) to FRD: log z up −1 g is down +1 g;
        // log x right is FRD y.
        assert_eq!(
            log.specific_force_m_s2[0],
            Vector3::new(0.0, 0.0, STANDARD_GRAVITY_M_S2)
        );
        let timing = log.timing();
        assert_eq!((timing.gap_count, timing.largest_gap_line), (1, 51));
        assert!((timing.largest_gap_s - 0.05).abs() < 1e-12);
        assert!((timing.interval_std_s - 0.001).abs() < 1e-6, "{timing:?}");
        l.axes[(0, 0)] = 2.0;
        assert!(parse_imu_csv(text.as_bytes(), "x.csv", &l)
            .unwrap_err()
            .to_string()
            .starts_with("axes: is not a rotation"));
        l.axes = Matrix3::identity();
        let e = axes_from_name("flu").unwrap_err().to_string();
        assert!(e.contains("did you mean \"FLU\"?"), "{e}");
        l.columns = ImuColumns::Numbers(IMU_COLUMNS.iter().map(|q| (q.to_string(), 1)).collect());
        let e = parse_imu_csv(text.as_bytes(), "x.csv", &l).unwrap_err();
        assert_eq!(
            e.to_string(),
            "columns: \"ax\" and \"ay\" are both column 1"
        );
        // Time going backwards names file and line.
        let e = parse("0,0,1,0,0,0,10\n0,0,1,0,0,0,20\n0,0,1,0,0,0,15\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.csv:3: time 15 goes backwards from the previous line's (line 2: 20): times must increase"
        );
    }
}
