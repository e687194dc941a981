//! A navigation solution written for other tools: memsnav's CSV (every
//! column with its unit), RTKLIB `.pos`, and tracks a person opens on a
//! map: KML 2.2, GPX 1.1 and GeoJSON (RFC 7946). One path for every
//! solution: [`LocalSolution`] (a filter's solution at the IMU, or a log
//! run's at the antenna) → [`format_solution`] → [`write_solution`].
//!
//! Heights are ellipsoidal (WGS 84) in every format. KML and GPX readers
//! often take heights above mean sea level: the KML track is drawn on the
//! ground (KML's default `clampToGround`), and a GPX `ele` is the
//! ellipsoidal height (its documentation says which).
//!
//! A format's rows are the solution's samples thinned to `rate_hz` (the
//! first sample of each 1/`rate_hz` interval counted from the first
//! sample, [`decimate`]): by default every sample for the CSV and [`MAP_RATE_HZ`] for the
//! others, so a 100 Hz run makes neither a 50 MB KML nor an RTKLIB file
//! with a hundred epochs a second.

mod csv;
mod geojson;
mod gpx;
mod kml;
mod local;

use std::io::Read;
use std::path::Path;

pub use local::LocalSolution;

use crate::logs::{format_pos, PosSolution};
use crate::{Error, Result};

/// Default rate of the `.pos`, KML, GPX and GeoJSON rows, Hz.
pub const MAP_RATE_HZ: f64 = 10.0;

/// RTKLIB's Q that a written `.pos` carries: 5, "single" (a navigation
/// solution is neither a fix nor a float; RTKLIB's readers know no other).
const POS_QUALITY: u8 = 5;

/// A file format of [`write_solution`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolutionFormat {
    /// memsnav's CSV: [`COLUMNS`], one line per row.
    Csv,
    /// RTKLIB `.pos` (GPST, lat/lon/height, velocity; [`crate::logs::format_pos`]).
    Pos,
    /// KML 2.2: the track as a `LineString`, start and end as points.
    Kml,
    /// GPX 1.1: one `trk` of one `trkseg`, each `trkpt` with its UTC time.
    Gpx,
    /// GeoJSON (RFC 7946): a `FeatureCollection` of one `LineString` feature.
    GeoJson,
}

impl SolutionFormat {
    /// Every format, in the order their names are listed.
    pub const ALL: [SolutionFormat; 5] = [
        SolutionFormat::Csv,
        SolutionFormat::Pos,
        SolutionFormat::Kml,
        SolutionFormat::Gpx,
        SolutionFormat::GeoJson,
    ];

    /// The format's name, also the usual extension of its files.
    pub fn name(self) -> &'static str {
        match self {
            SolutionFormat::Csv => "csv",
            SolutionFormat::Pos => "pos",
            SolutionFormat::Kml => "kml",
            SolutionFormat::Gpx => "gpx",
            SolutionFormat::GeoJson => "geojson",
        }
    }

    fn names() -> String {
        Self::ALL.map(|f| format!("{:?}", f.name())).join(", ")
    }

    /// The format called `name` (case-insensitive), or an error naming the
    /// argument `format` and the accepted names.
    pub fn from_name(name: &str) -> Result<Self> {
        let lower = name.to_ascii_lowercase();
        Self::ALL
            .into_iter()
            .find(|f| f.name() == lower)
            .ok_or_else(|| {
                Error::invalid(
                    "format",
                    format!(
                        "{name:?} is not a format memsnav writes; give one of {}",
                        Self::names()
                    ),
                )
            })
    }

    /// The format of a file name's extension (`.json` is GeoJSON).
    pub fn from_path(path: &Path) -> Result<Self> {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("json") => Ok(SolutionFormat::GeoJson),
            Some(e) if Self::from_name(e).is_ok() => Self::from_name(e),
            _ => Err(Error::invalid(
                "format",
                format!(
                    "not given, and the extension of {} names none; give format= one of {}",
                    path.display(),
                    Self::names()
                ),
            )),
        }
    }

    /// Text near the start of every file of this format that memsnav
    /// writes, and of no file it did not.
    fn signature(self) -> &'static str {
        match self {
            SolutionFormat::Csv => csv::HEADER,
            SolutionFormat::Pos => "% program   : memsnav",
            SolutionFormat::Kml => kml::SIGNATURE,
            SolutionFormat::Gpx => gpx::SIGNATURE,
            SolutionFormat::GeoJson => geojson::SIGNATURE,
        }
    }
}

/// The columns of the CSV and of [`columns`], units in their names.
pub const COLUMNS: [&str; 16] = [
    "gps_time_s",
    "lat_deg",
    "lon_deg",
    "height_m",
    "vn_m_s",
    "ve_m_s",
    "vd_m_s",
    "roll_deg",
    "pitch_deg",
    "yaw_deg",
    "sdn_m",
    "sde_m",
    "sdd_m",
    "sdvn_m_s",
    "sdve_m_s",
    "sdvd_m_s",
];

/// The samples kept at `rate_hz` (None: every one): the first of each
/// 1/`rate_hz` interval counted from the first sample, a sample within a
/// millionth of an interval of its start counted in it (times far from
/// zero carry rounding errors: 0.1 s after a GPS time may read 0.0999999).
pub fn decimate(time_s: &[f64], rate_hz: Option<f64>) -> Result<Vec<usize>> {
    let Some(rate) = rate_hz else {
        return Ok((0..time_s.len()).collect());
    };
    if !(rate.is_finite() && rate > 0.0) {
        return Err(Error::invalid(
            "rate_hz",
            format!("must be a positive number of Hz, got {rate}"),
        ));
    }
    let Some(&t0) = time_s.first() else {
        return Ok(Vec::new());
    };
    let mut kept = vec![0];
    let mut last = 0.0;
    for (k, &t) in time_s.iter().enumerate().skip(1) {
        let interval = ((t - t0) * rate + 1e-6).floor();
        if interval > last {
            kept.push(k);
            last = interval;
        }
    }
    Ok(kept)
}

/// The rows of `solution` at `rate_hz` as [`COLUMNS`] (degrees where the
/// name says so).
pub fn columns(solution: &LocalSolution, rate_hz: Option<f64>) -> Result<Vec<Vec<f64>>> {
    let rows = decimate(&solution.time_s, rate_hz)?;
    let pick = |f: &dyn Fn(usize) -> f64| rows.iter().map(|&k| f(k)).collect::<Vec<f64>>();
    let s = solution;
    Ok(vec![
        pick(&|k| s.time_s[k]),
        pick(&|k| s.antenna_geodetic[k].latitude_rad.to_degrees()),
        pick(&|k| s.antenna_geodetic[k].longitude_rad.to_degrees()),
        pick(&|k| s.antenna_geodetic[k].height_m),
        pick(&|k| s.velocity_ned[k].x),
        pick(&|k| s.velocity_ned[k].y),
        pick(&|k| s.velocity_ned[k].z),
        pick(&|k| s.euler_rad[k].x.to_degrees()),
        pick(&|k| s.euler_rad[k].y.to_degrees()),
        pick(&|k| s.euler_rad[k].z.to_degrees()),
        pick(&|k| s.position_std_ned[k].x),
        pick(&|k| s.position_std_ned[k].y),
        pick(&|k| s.position_std_ned[k].z),
        pick(&|k| s.velocity_std_ned[k].x),
        pick(&|k| s.velocity_std_ned[k].y),
        pick(&|k| s.velocity_std_ned[k].z),
    ])
}

/// A point of a map track: GPS time (s), longitude and latitude (deg),
/// ellipsoidal height (m).
pub(crate) struct TrackPoint {
    pub gps_time_s: f64,
    pub lon_deg: f64,
    pub lat_deg: f64,
    pub height_m: f64,
}

/// The map formats' points at `rate_hz`: at least two (a line), all finite.
fn track(solution: &LocalSolution, rate_hz: f64) -> Result<Vec<TrackPoint>> {
    let rows = decimate(&solution.time_s, Some(rate_hz))?;
    if rows.len() < 2 {
        return Err(Error::invalid(
            "solution",
            format!(
                "a track needs at least two points; {} sample(s) at rate_hz = {rate_hz}",
                rows.len()
            ),
        ));
    }
    rows.iter()
        .map(|&k| {
            let g = solution.antenna_geodetic[k];
            let point = TrackPoint {
                gps_time_s: solution.time_s[k],
                lon_deg: g.longitude_rad.to_degrees(),
                lat_deg: g.latitude_rad.to_degrees(),
                height_m: g.height_m,
            };
            let finite = [
                point.gps_time_s,
                point.lon_deg,
                point.lat_deg,
                point.height_m,
            ]
            .iter()
            .all(|x| x.is_finite());
            if finite {
                Ok(point)
            } else {
                Err(Error::invalid(
                    "solution",
                    format!("sample {k} (time {} s) is not finite", point.gps_time_s),
                ))
            }
        })
        .collect()
}

/// The text of `solution` in `format` at `rate_hz` (None: the format's
/// default, see the module docs); `name` titles a map track.
pub fn format_solution(
    solution: &LocalSolution,
    format: SolutionFormat,
    rate_hz: Option<f64>,
    name: &str,
) -> Result<String> {
    if solution.time_s.is_empty() {
        return Err(Error::invalid("solution", "has no samples"));
    }
    let map_rate = rate_hz.unwrap_or(MAP_RATE_HZ);
    match format {
        SolutionFormat::Csv => Ok(csv::format(&columns(solution, rate_hz)?)),
        SolutionFormat::Pos => {
            let rows = decimate(&solution.time_s, Some(map_rate))?;
            let n = rows.len();
            let pick = |v: &[nalgebra::Vector3<f64>]| rows.iter().map(|&k| v[k]).collect();
            let pos = PosSolution {
                gps_time_s: rows.iter().map(|&k| solution.time_s[k]).collect(),
                lla: rows
                    .iter()
                    .map(|&k| {
                        let g = solution.antenna_geodetic[k];
                        nalgebra::Vector3::new(g.latitude_rad, g.longitude_rad, g.height_m)
                    })
                    .collect(),
                quality: vec![POS_QUALITY; n],
                n_satellites: vec![0; n],
                std_ned_m: pick(&solution.position_std_ned),
                covariance_ned_m2: None,
                velocity_ned_m_s: pick(&solution.velocity_ned),
                velocity_std_ned_m_s: pick(&solution.velocity_std_ned),
                velocity_covariance_ned_m2_s2: None,
                attitude_c_b_n: None,
                warnings: Vec::new(),
            };
            format_pos(&pos, "memsnav")
        }
        SolutionFormat::Kml => Ok(kml::format(&track(solution, map_rate)?, name)),
        SolutionFormat::Gpx => Ok(gpx::format(&track(solution, map_rate)?, name)),
        SolutionFormat::GeoJson => Ok(geojson::format(&track(solution, map_rate)?, name)),
    }
}

/// How many bytes of an existing file [`written_by_memsnav`] reads.
const HEAD_BYTES: u64 = 1024;

/// Whether the file at `path` starts like a solution file memsnav writes
/// (any format's signature in its first [`HEAD_BYTES`]).
fn written_by_memsnav(path: &Path) -> bool {
    let mut head = Vec::new();
    let read = std::fs::File::open(path).and_then(|f| f.take(HEAD_BYTES).read_to_end(&mut head));
    let head = String::from_utf8_lossy(&head);
    read.is_ok()
        && SolutionFormat::ALL
            .iter()
            .any(|f| head.contains(f.signature()))
}

fn io_error(path: &Path, reason: impl std::fmt::Display) -> Error {
    Error::Io {
        path: path.display().to_string(),
        reason: reason.to_string(),
    }
}

/// Writes [`format_solution`] to `path`, whole or not at all (a temporary
/// file beside it, renamed over it). `format` None: from the extension;
/// `name` None: the file's stem. The folder must exist. An existing file is
/// replaced only when memsnav wrote it (a solution file of any format) or
/// `overwrite`; a folder never.
pub fn write_solution(
    path: &Path,
    solution: &LocalSolution,
    format: Option<SolutionFormat>,
    rate_hz: Option<f64>,
    name: Option<&str>,
    overwrite: bool,
) -> Result<()> {
    let format = match format {
        Some(f) => f,
        None => SolutionFormat::from_path(path)?,
    };
    let Some(file_name) = path.file_name().and_then(|n| n.to_str()) else {
        return Err(Error::invalid(
            "path",
            format!("{} names no file", path.display()),
        ));
    };
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !folder.is_dir() {
        return Err(io_error(
            path,
            format!(
                "the folder {} does not exist; create it first",
                folder.display()
            ),
        ));
    }
    if path.is_dir() {
        return Err(Error::invalid(
            "path",
            format!("{} is a folder; give a file name", path.display()),
        ));
    }
    if path.exists() && !overwrite && !written_by_memsnav(path) {
        return Err(Error::invalid(
            "path",
            format!(
                "{} exists and is not a solution file memsnav wrote; remove it, give \
                 another name, or pass overwrite=True to replace it",
                path.display()
            ),
        ));
    }
    let stem = path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or(file_name);
    let text = format_solution(solution, format, rate_hz, name.unwrap_or(stem))?;
    let tmp = folder.join(format!(".{file_name}.{}.tmp", std::process::id()));
    let written = std::fs::write(&tmp, text).and_then(|()| std::fs::rename(&tmp, path));
    if let Err(e) = written {
        // Best effort: the temporary file may not exist.
        let _ = std::fs::remove_file(&tmp);
        return Err(io_error(path, e));
    }
    Ok(())
}

/// Characters `&`, `<`, `>`, `"` and `'` as XML entities.
fn xml_escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&apos;")
}

#[cfg(test)]
mod tests;
