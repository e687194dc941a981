//! Motion profiles in the CSV format of Groves' book software
//! (`Profile_*.csv`): no header; t s, latitude, longitude deg, height m,
//! v_N, v_E, v_D m/s, roll, pitch, yaw deg.

use std::path::Path;

use nalgebra::Vector3;

use super::spline::CubicSpline;
use super::{build, segments::validate_origin, time_grid, LocalMotion, Motion, Trajectory};
use crate::geodesy::domain::{check_speed, MAX_HEIGHT_M, MAX_SPEED_M_S, MIN_HEIGHT_M};
use crate::geodesy::Geodetic;
use crate::{Error, Result};

const COLUMNS: usize = 10;

/// The range of each column after the time (a row's east
/// velocity of 1e308 gave 1 176 of 1 200 specific forces non-finite): the
/// angles' natural ranges (360° either way for the wrapped ones), the
/// heights of the geodesy's domain; the velocity is checked as a speed.
const COLUMN_RANGES: [(&str, f64, f64); COLUMNS - 1] = [
    ("latitude, deg", -90.0, 90.0),
    ("longitude, deg", -360.0, 360.0),
    ("height, m", MIN_HEIGHT_M, MAX_HEIGHT_M),
    ("v_N, m/s", -MAX_SPEED_M_S, MAX_SPEED_M_S),
    ("v_E, m/s", -MAX_SPEED_M_S, MAX_SPEED_M_S),
    ("v_D, m/s", -MAX_SPEED_M_S, MAX_SPEED_M_S),
    ("roll, deg", -360.0, 360.0),
    ("pitch, deg", -90.0, 90.0),
    ("yaw, deg", -360.0, 360.0),
];

/// Knot spacing of the profile splines, s. Groves' profiles switch
/// accelerations and turn rates instantaneously; splined through every
/// 100 Hz sample such a switch becomes a rate change within one IMU
/// interval, which no strapdown integrator can follow. Averaging each
/// channel over ±0.25 s around knots 0.5 s apart spreads every switch over
/// about a second (angular accelerations of ~1 rad/s² for the sharpest
/// turns) while moving the path by only centimetres.
pub const PROFILE_KNOT_SPACING_S: f64 = 0.5;

/// A profile as splines: NED velocity and Euler angles (yaw unwrapped),
/// each a natural cubic spline of time through box-averaged knots
/// ([`PROFILE_KNOT_SPACING_S`]), so the acceleration and the angular rate
/// are continuous and smooth at the IMU rate. The position is not splined: it is integrated from
/// the splined velocity (the file's positions have ~1 mm resolution, which
/// differentiated twice at 100 Hz would be metres per second squared of
/// noise); the file's first position is the origin.
struct ProfileMotion {
    velocity_ned: [CubicSpline; 3],
    euler: [CubicSpline; 3],
}

impl Motion for ProfileMotion {
    /// Interval hints of the velocity and angle splines (they share knots
    /// only by construction, so each keeps its own).
    type Cursor = [usize; 6];

    fn at(&self, t: f64, cursor: &mut [usize; 6]) -> LocalMotion {
        let (cv, ce) = cursor.split_at_mut(3);
        let v: [_; 3] = std::array::from_fn(|i| self.velocity_ned[i].at_from(t, &mut cv[i]));
        let e: [_; 3] = std::array::from_fn(|i| self.euler[i].at_from(t, &mut ce[i]));
        LocalMotion {
            velocity_ned: Vector3::new(v[0].value, v[1].value, v[2].value),
            velocity_ned_rate: Vector3::new(v[0].rate, v[1].rate, v[2].rate),
            euler_rad: Vector3::new(e[0].value, e[1].value, e[2].value),
            euler_rate_rad_s: Vector3::new(e[0].rate, e[1].rate, e[2].rate),
            yaw_sin_cos: e[2].value.sin_cos(),
        }
    }

    fn velocity_ned(&self, t: f64, cursor: &mut [usize; 6]) -> Vector3<f64> {
        Vector3::new(
            self.velocity_ned[0].at_from(t, &mut cursor[0]).value,
            self.velocity_ned[1].at_from(t, &mut cursor[1]).value,
            self.velocity_ned[2].at_from(t, &mut cursor[2]).value,
        )
    }
}

/// The parsed rows of a profile file.
struct Rows {
    time_s: Vec<f64>,
    columns: [Vec<f64>; COLUMNS - 1],
}

fn parse(path: &Path) -> Result<Rows> {
    let file = path.display().to_string();
    let text = std::fs::read(path).map_err(|e| Error::Io {
        path: file.clone(),
        reason: e.to_string(),
    })?;
    let parse_error = |line: usize, reason: String| Error::Parse {
        file: file.clone(),
        line,
        reason,
    };
    let text = String::from_utf8(text).map_err(|e| {
        let line = 1 + e.as_bytes()[..e.utf8_error().valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        parse_error(line, "not UTF-8 text".into())
    })?;
    let mut rows = Rows {
        time_s: Vec::new(),
        columns: Default::default(),
    };
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        if raw.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = raw.split(',').map(str::trim).collect();
        if fields.len() != COLUMNS {
            return Err(parse_error(
                line,
                format!(
                    "expected {COLUMNS} comma-separated columns (t, lat, lon, h, v_N, v_E, v_D, roll, pitch, yaw), found {}",
                    fields.len()
                ),
            ));
        }
        let mut values = [0.0; COLUMNS];
        for (j, f) in fields.iter().enumerate() {
            values[j] = f
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    parse_error(
                        line,
                        format!("column {}: {f:?} is not a finite number", j + 1),
                    )
                })?;
        }
        for (j, &(name, low, high)) in COLUMN_RANGES.iter().enumerate() {
            let v = values[j + 1];
            if !(low..=high).contains(&v) {
                return Err(parse_error(
                    line,
                    format!(
                        "column {} ({name}): {} is outside [{low}, {high}]",
                        j + 2,
                        if v.abs() < 1e9 {
                            v.to_string()
                        } else {
                            format!("{v:e}")
                        }
                    ),
                ));
            }
        }
        check_speed("v_NED", &[Vector3::new(values[4], values[5], values[6])])
            .map_err(|e| parse_error(line, e.to_string()))?;
        if let Some(&last) = rows.time_s.last() {
            if values[0] <= last {
                return Err(parse_error(
                    line,
                    format!("time {} s does not follow {} s", values[0], last),
                ));
            }
        }
        rows.time_s.push(values[0]);
        for (column, v) in rows.columns.iter_mut().zip(&values[1..]) {
            column.push(*v);
        }
    }
    if rows.time_s.len() < 4 {
        return Err(parse_error(
            text.lines().count(),
            format!("needs at least 4 rows, found {}", rows.time_s.len()),
        ));
    }
    Ok(rows)
}

/// Knots every `spacing` s from the first to the last time (the last knot
/// moved to the last time), each valued by the mean of the samples within
/// half a spacing of it (by linear interpolation if there are none).
fn averaged_knots(time: &[f64], values: &[f64], spacing: f64) -> (Vec<f64>, Vec<f64>) {
    let (t0, t1) = (time[0], time[time.len() - 1]);
    let count = ((t1 - t0) / spacing).round().max(1.0) as usize;
    let knots: Vec<f64> = (0..=count)
        .map(|j| {
            if j == count {
                t1
            } else {
                t0 + j as f64 * spacing
            }
        })
        .collect();
    let mut out = Vec::with_capacity(knots.len());
    let (mut lo, mut hi) = (0, 0);
    for &k in &knots {
        while lo < time.len() && time[lo] < k - 0.5 * spacing {
            lo += 1;
        }
        hi = hi.max(lo);
        while hi < time.len() && time[hi] <= k + 0.5 * spacing {
            hi += 1;
        }
        if hi > lo {
            out.push(values[lo..hi].iter().sum::<f64>() / (hi - lo) as f64);
        } else {
            let i = time.partition_point(|&t| t <= k).clamp(1, time.len() - 1);
            let u = (k - time[i - 1]) / (time[i] - time[i - 1]);
            out.push(values[i - 1] + u * (values[i] - values[i - 1]));
        }
    }
    (knots, out)
}

/// Removes 360° jumps so the spline of yaw is smooth through ±180°.
fn unwrap_deg(values: &mut [f64]) {
    for k in 1..values.len() {
        let step = values[k] - values[k - 1];
        values[k] -= 360.0 * (step / 360.0).round();
    }
}

impl Trajectory {
    /// A trajectory from a profile CSV of Groves' book software, sampled at
    /// `rate_hz` from the file's first to its last time. The velocity and
    /// attitude are approximated by natural cubic splines (C²) through
    /// knots averaged over [`PROFILE_KNOT_SPACING_S`], the position
    /// integrated from the velocity, and f and ω derived exactly from that
    /// smooth motion, so an INS closes on it. Unreadable files give
    /// [`Error::Io`]; malformed or truncated lines [`Error::Parse`] with the
    /// file and the 1-based line.
    pub fn from_profile(path: &Path, rate_hz: f64) -> Result<Trajectory> {
        crate::validate::positive("rate", rate_hz)?;
        let mut rows = parse(path)?;
        let [lat, lon, h, vn, ve, vd, roll, pitch, yaw] = &mut rows.columns;
        unwrap_deg(yaw);
        let origin = Geodetic::new(lat[0].to_radians(), lon[0].to_radians(), h[0]);
        validate_origin(&origin).map_err(|e| Error::Parse {
            file: path.display().to_string(),
            line: 1,
            reason: e.to_string(),
        })?;
        let t = &rows.time_s;
        let spline = |values: &[f64], scale: f64| {
            let (knots, averaged) = averaged_knots(t, values, PROFILE_KNOT_SPACING_S);
            CubicSpline::new(knots, averaged.iter().map(|v| v * scale).collect())
        };
        let deg = 1f64.to_radians();
        let motion = ProfileMotion {
            velocity_ned: [spline(vn, 1.0), spline(ve, 1.0), spline(vd, 1.0)],
            euler: [spline(roll, deg), spline(pitch, deg), spline(yaw, deg)],
        };
        let start = t[0];
        let time = time_grid(start, t[t.len() - 1] - start, rate_hz)?;
        Ok(build(&motion, origin, time))
    }
}
