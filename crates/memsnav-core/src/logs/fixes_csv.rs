//! GNSS fixes in CSV: one epoch a line, comma-separated columns named in a
//! header line, in any order (docs/real-data.md, "GNSS fixes in CSV").
//!
//! | group | columns (one alternative) | |
//! |---|---|---|
//! | time | `gps_time_s` (GPS s since 1980-01-06) or `gps_week`, `gps_tow_s` | required |
//! | position | `lat_deg`, `lon_deg`, `height_m` (ellipsoidal) or `x_ecef_m`, `y_ecef_m`, `z_ecef_m` | required |
//! | position σ | `std_n_m`, `std_e_m`, `std_d_m` or `cov_nn_m2`, `cov_ne_m2`, `cov_nd_m2`, `cov_ee_m2`, `cov_ed_m2`, `cov_dd_m2` | required |
//! | velocity | `vn_m_s`, `ve_m_s`, `vd_m_s` | optional; empty cells: none that epoch |
//! | velocity σ | `std_vn_m_s`, `std_ve_m_s`, `std_vd_m_s` or `cov_vnvn_m2_s2`, `cov_vnve_m2_s2`, `cov_vnvd_m2_s2`, `cov_veve_m2_s2`, `cov_vevd_m2_s2`, `cov_vdvd_m2_s2` | optional, with velocity |
//! | quality | `quality` (RTKLIB's Q, 0-7) | optional, default [`DEFAULT_CSV_QUALITY`] |
//! | satellites | `n_satellites` | optional, default 0 |
//!
//! Lines starting with `#` and blank lines are skipped. Every other column
//! name is an error naming it.

use std::collections::HashMap;
use std::path::Path;

use nalgebra::{Matrix3, Vector3};

use super::fields::{finite_number, in_range, parse_error};
use super::pos_solution::{check_covariance, std_of, MAX_STD, QUALITY_RANGE};
use super::rtklib_pos::{MAX_SPEED_M_S, POS_HEIGHT_RANGE_M};
use super::PosSolution;
use crate::geodesy::ecef_to_geodetic;
use crate::gnss::SECONDS_PER_WEEK;
use crate::Result;

/// The quality given to every epoch of a CSV without a `quality` column:
/// RTKLIB's Q = 5, single (a receiver's own fix).
pub const DEFAULT_CSV_QUALITY: u8 = 5;

const GPS_TIME: &str = "gps_time_s";
const WEEK_TOW: [&str; 2] = ["gps_week", "gps_tow_s"];
const GEODETIC: [&str; 3] = ["lat_deg", "lon_deg", "height_m"];
const ECEF: [&str; 3] = ["x_ecef_m", "y_ecef_m", "z_ecef_m"];
const STD: [&str; 3] = ["std_n_m", "std_e_m", "std_d_m"];
/// The six unique entries of a symmetric 3×3 covariance, row-major upper
/// triangle: (0,0) (0,1) (0,2) (1,1) (1,2) (2,2).
const COVARIANCE: [&str; 6] = [
    "cov_nn_m2",
    "cov_ne_m2",
    "cov_nd_m2",
    "cov_ee_m2",
    "cov_ed_m2",
    "cov_dd_m2",
];
const VELOCITY: [&str; 3] = ["vn_m_s", "ve_m_s", "vd_m_s"];
const VELOCITY_STD: [&str; 3] = ["std_vn_m_s", "std_ve_m_s", "std_vd_m_s"];
const VELOCITY_COVARIANCE: [&str; 6] = [
    "cov_vnvn_m2_s2",
    "cov_vnve_m2_s2",
    "cov_vnvd_m2_s2",
    "cov_veve_m2_s2",
    "cov_vevd_m2_s2",
    "cov_vdvd_m2_s2",
];
const QUALITY: &str = "quality";
const N_SATELLITES: &str = "n_satellites";
const UPPER: [(usize, usize); 6] = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];

/// Every column name the reader knows.
pub const FIXES_CSV_COLUMNS: [&str; 32] = [
    GPS_TIME,
    WEEK_TOW[0],
    WEEK_TOW[1],
    GEODETIC[0],
    GEODETIC[1],
    GEODETIC[2],
    ECEF[0],
    ECEF[1],
    ECEF[2],
    STD[0],
    STD[1],
    STD[2],
    COVARIANCE[0],
    COVARIANCE[1],
    COVARIANCE[2],
    COVARIANCE[3],
    COVARIANCE[4],
    COVARIANCE[5],
    VELOCITY[0],
    VELOCITY[1],
    VELOCITY[2],
    VELOCITY_STD[0],
    VELOCITY_STD[1],
    VELOCITY_STD[2],
    VELOCITY_COVARIANCE[0],
    VELOCITY_COVARIANCE[1],
    VELOCITY_COVARIANCE[2],
    VELOCITY_COVARIANCE[3],
    VELOCITY_COVARIANCE[4],
    VELOCITY_COVARIANCE[5],
    QUALITY,
    N_SATELLITES,
];

/// Largest |ECEF coordinate| accepted, m (beyond geostationary orbit).
const MAX_ECEF_M: f64 = 1.0e8;

/// Largest GPS time accepted, s (year 2297).
const MAX_GPS_TIME_S: f64 = 1.0e10;

/// Reads a fixes CSV (see the module documentation).
pub fn read_fixes_csv(path: impl AsRef<Path>) -> Result<PosSolution> {
    let path = path.as_ref();
    parse_fixes_csv(
        &String::from_utf8_lossy(&super::read_bytes(path)?),
        &path.display().to_string(),
    )
}

/// Where each column group sits in a line.
struct Layout {
    n_fields: usize,
    gps_time: Option<usize>,
    week_tow: Option<Vec<usize>>,
    geodetic: Option<Vec<usize>>,
    ecef: Option<Vec<usize>>,
    std: Option<Vec<usize>>,
    covariance: Option<Vec<usize>>,
    velocity: Option<Vec<usize>>,
    velocity_std: Option<Vec<usize>>,
    velocity_covariance: Option<Vec<usize>>,
    quality: Option<usize>,
    n_satellites: Option<usize>,
}

/// The columns of `group` all present (their indices), all absent (None),
/// or an error naming the missing ones.
fn group(
    names: &[&str],
    index: &HashMap<&str, usize>,
) -> std::result::Result<Option<Vec<usize>>, String> {
    let found: Vec<Option<usize>> = names.iter().map(|n| index.get(n).copied()).collect();
    if found.iter().all(Option::is_none) {
        return Ok(None);
    }
    let missing: Vec<&str> = names
        .iter()
        .zip(&found)
        .filter(|(_, f)| f.is_none())
        .map(|(n, _)| *n)
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "the columns {} go together: {} missing",
            names.join(", "),
            missing.join(", ")
        ));
    }
    Ok(Some(found.into_iter().flatten().collect()))
}

/// One of two alternatives, exactly (`required`) or at most.
fn one_of<A, B>(
    a: Option<A>,
    b: Option<B>,
    what: &str,
    a_names: &str,
    b_names: &str,
    required: bool,
) -> std::result::Result<(), String> {
    match (&a, &b) {
        (Some(_), Some(_)) => Err(format!("{what}: give {a_names} or {b_names}, not both")),
        (None, None) if required => Err(format!(
            "{what}: expected the columns {a_names} or {b_names}"
        )),
        _ => Ok(()),
    }
}

impl Layout {
    fn from_header(header: &str) -> std::result::Result<Self, String> {
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        let known = FIXES_CSV_COLUMNS;
        let unknown: Vec<&str> = names
            .iter()
            .copied()
            .filter(|n| !known.contains(n))
            .collect();
        if !unknown.is_empty() {
            return Err(format!(
                "unknown column(s) {unknown:?} in the header; the columns are: {}",
                known.join(", ")
            ));
        }
        let mut index = HashMap::new();
        for (k, n) in names.iter().enumerate() {
            if index.insert(*n, k).is_some() {
                return Err(format!("column {n:?} appears twice in the header"));
            }
        }
        let layout = Self {
            n_fields: names.len(),
            gps_time: index.get(GPS_TIME).copied(),
            week_tow: group(&WEEK_TOW, &index)?,
            geodetic: group(&GEODETIC, &index)?,
            ecef: group(&ECEF, &index)?,
            std: group(&STD, &index)?,
            covariance: group(&COVARIANCE, &index)?,
            velocity: group(&VELOCITY, &index)?,
            velocity_std: group(&VELOCITY_STD, &index)?,
            velocity_covariance: group(&VELOCITY_COVARIANCE, &index)?,
            quality: index.get(QUALITY).copied(),
            n_satellites: index.get(N_SATELLITES).copied(),
        };
        let list = |n: &[&str]| n.join(", ");
        one_of(
            layout.gps_time.as_ref(),
            layout.week_tow.as_ref(),
            "time",
            GPS_TIME,
            &list(&WEEK_TOW),
            true,
        )?;
        one_of(
            layout.geodetic.as_ref(),
            layout.ecef.as_ref(),
            "position",
            &list(&GEODETIC),
            &list(&ECEF),
            true,
        )?;
        one_of(
            layout.std.as_ref(),
            layout.covariance.as_ref(),
            "position uncertainty",
            &list(&STD),
            &list(&COVARIANCE),
            true,
        )?;
        one_of(
            layout.velocity_std.as_ref(),
            layout.velocity_covariance.as_ref(),
            "velocity uncertainty",
            &list(&VELOCITY_STD),
            &list(&VELOCITY_COVARIANCE),
            false,
        )?;
        if layout.velocity.is_none()
            && (layout.velocity_std.is_some() || layout.velocity_covariance.is_some())
        {
            return Err(format!(
                "velocity uncertainty without the velocity columns {}",
                list(&VELOCITY)
            ));
        }
        Ok(layout)
    }
}

/// Physical range and unit of a column.
fn column_range(name: &str) -> (std::ops::RangeInclusive<f64>, &'static str) {
    match name {
        GPS_TIME => (0.0..=MAX_GPS_TIME_S, "s"),
        "gps_week" => (0.0..=1.0e4, ""),
        "gps_tow_s" => (0.0..=SECONDS_PER_WEEK, "s"),
        "lat_deg" => (-90.0..=90.0, "°"),
        "lon_deg" => (-180.0..=180.0, "°"),
        "height_m" => (POS_HEIGHT_RANGE_M, "m"),
        "x_ecef_m" | "y_ecef_m" | "z_ecef_m" => (-MAX_ECEF_M..=MAX_ECEF_M, "m"),
        "std_n_m" | "std_e_m" | "std_d_m" => (0.0..=MAX_STD, "m"),
        "std_vn_m_s" | "std_ve_m_s" | "std_vd_m_s" => (0.0..=MAX_STD, "m/s"),
        "cov_nn_m2" | "cov_ee_m2" | "cov_dd_m2" => (0.0..=MAX_STD * MAX_STD, "m²"),
        "cov_vnvn_m2_s2" | "cov_veve_m2_s2" | "cov_vdvd_m2_s2" => {
            (0.0..=MAX_STD * MAX_STD, "m²/s²")
        }
        "vn_m_s" | "ve_m_s" | "vd_m_s" => (-MAX_SPEED_M_S..=MAX_SPEED_M_S, "m/s"),
        QUALITY => (QUALITY_RANGE, ""),
        N_SATELLITES => (0.0..=255.0, ""),
        // Off-diagonal covariances.
        n if n.ends_with("_m2") => (-MAX_STD * MAX_STD..=MAX_STD * MAX_STD, "m²"),
        _ => (-MAX_STD * MAX_STD..=MAX_STD * MAX_STD, "m²/s²"),
    }
}

/// The number in field `k` (0-based) of `f`, named and range-checked; None
/// for an empty field where `may_be_empty`.
fn value(
    f: &[&str],
    k: usize,
    names: &[&str],
    may_be_empty: bool,
) -> std::result::Result<Option<f64>, String> {
    let name = names[k];
    if f[k].is_empty() && may_be_empty {
        return Ok(None);
    }
    let x = finite_number(f[k]).ok_or_else(|| {
        format!(
            "field {} ({name}): expected a finite number, got {:?}",
            k + 1,
            f[k]
        )
    })?;
    let (range, unit) = column_range(name);
    in_range(x, range, name, unit).map_err(|e| format!("field {}: {e}", k + 1))?;
    if matches!(name, QUALITY | N_SATELLITES | "gps_week") && x.fract() != 0.0 {
        return Err(format!(
            "field {} ({name}): expected an integer, got {x}",
            k + 1
        ));
    }
    Ok(Some(x))
}

/// The three values of `columns` (all required).
fn vector(
    f: &[&str],
    columns: &[usize],
    names: &[&str],
) -> std::result::Result<Vector3<f64>, String> {
    let mut v = Vector3::zeros();
    for (i, &k) in columns.iter().enumerate() {
        v[i] = value(f, k, names, false)?.unwrap_or(f64::NAN);
    }
    Ok(v)
}

/// The values of `columns`, all given or all empty (None).
fn optional(
    f: &[&str],
    columns: &[usize],
    names: &[&str],
) -> std::result::Result<Option<Vec<f64>>, String> {
    let values: Vec<Option<f64>> = columns
        .iter()
        .map(|&k| value(f, k, names, true))
        .collect::<std::result::Result<_, _>>()?;
    match values.iter().filter(|v| v.is_some()).count() {
        0 => Ok(None),
        n if n == values.len() => Ok(Some(values.into_iter().flatten().collect())),
        _ => Err(format!(
            "the fields {} are all given or all empty",
            columns
                .iter()
                .map(|&k| names[k])
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

/// The symmetric matrix of six upper-triangle entries.
fn symmetric(c: &[f64]) -> Matrix3<f64> {
    let mut m = Matrix3::zeros();
    for (&(i, j), &x) in UPPER.iter().zip(c) {
        m[(i, j)] = x;
        m[(j, i)] = x;
    }
    m
}

/// One epoch of a line.
struct Row {
    gps_time_s: f64,
    lla: Vector3<f64>,
    covariance: Matrix3<f64>,
    velocity: Vector3<f64>,
    velocity_covariance: Matrix3<f64>,
    quality: u8,
    n_satellites: u16,
}

fn parse_row(line: &str, layout: &Layout, names: &[&str]) -> std::result::Result<Row, String> {
    let f: Vec<&str> = line.split(',').map(str::trim).collect();
    if f.len() != layout.n_fields {
        return Err(format!(
            "expected {} fields ({}), got {}",
            layout.n_fields,
            names.join(", "),
            f.len()
        ));
    }
    let required = |k: usize| value(&f, k, names, false).map(|v| v.unwrap_or(f64::NAN));
    let gps_time_s = match (&layout.gps_time, &layout.week_tow) {
        (Some(k), _) => required(*k)?,
        (None, Some(wt)) => {
            let tow = required(wt[1])?;
            if tow >= SECONDS_PER_WEEK {
                return Err(format!(
                    "field {} (gps_tow_s) = {tow} s is out of range (0 to below {SECONDS_PER_WEEK} s)",
                    wt[1] + 1
                ));
            }
            required(wt[0])? * SECONDS_PER_WEEK + tow
        }
        (None, None) => unreachable!("the header has a time"),
    };
    let lla = match (&layout.geodetic, &layout.ecef) {
        (Some(g), _) => {
            let v = vector(&f, g, names)?;
            Vector3::new(v.x.to_radians(), v.y.to_radians(), v.z)
        }
        (None, Some(e)) => {
            let g = ecef_to_geodetic(&vector(&f, e, names)?);
            in_range(
                g.height_m,
                POS_HEIGHT_RANGE_M,
                "ellipsoidal height of the ECEF position",
                "m",
            )?;
            Vector3::new(g.latitude_rad, g.longitude_rad, g.height_m)
        }
        (None, None) => unreachable!("the header has a position"),
    };
    let covariance = match (&layout.std, &layout.covariance) {
        (Some(s), _) => {
            let s = vector(&f, s, names)?;
            Matrix3::from_diagonal(&s.component_mul(&s))
        }
        (None, Some(c)) => {
            let entries: Vec<f64> = c
                .iter()
                .map(|&k| required(k))
                .collect::<std::result::Result<_, _>>()?;
            let m = symmetric(&entries);
            check_covariance(&m, "the position covariance", "m²")?;
            m
        }
        (None, None) => unreachable!("the header has a position uncertainty"),
    };
    let nan = Matrix3::repeat(f64::NAN);
    let (velocity, velocity_covariance) = match &layout.velocity {
        Some(v) => match optional(&f, v, names)? {
            Some(v) => {
                let velocity = Vector3::from_column_slice(&v);
                let c = match (&layout.velocity_std, &layout.velocity_covariance) {
                    (Some(s), _) => optional(&f, s, names)?
                        .map(|s| Matrix3::from_diagonal(&Vector3::from_fn(|i, _| s[i] * s[i]))),
                    (None, Some(c)) => match optional(&f, c, names)? {
                        Some(entries) => {
                            let m = symmetric(&entries);
                            check_covariance(&m, "the velocity covariance", "m²/s²")?;
                            Some(m)
                        }
                        None => None,
                    },
                    (None, None) => None,
                };
                (velocity, c.unwrap_or(nan))
            }
            None => (Vector3::repeat(f64::NAN), nan),
        },
        None => (Vector3::repeat(f64::NAN), nan),
    };
    let quality = match layout.quality {
        Some(k) => required(k)? as u8,
        None => DEFAULT_CSV_QUALITY,
    };
    let n_satellites = match layout.n_satellites {
        Some(k) => required(k)? as u16,
        None => 0,
    };
    Ok(Row {
        gps_time_s,
        lla,
        covariance,
        velocity,
        velocity_covariance,
        quality,
        n_satellites,
    })
}

/// Parses the text of a fixes CSV; `file` names it in errors. Each field
/// is range-checked (latitude ±90°, longitude ±180°, height in
/// [`POS_HEIGHT_RANGE_M`], stds ≥ 0, covariances positive semi-definite,
/// speeds ≤ [`MAX_SPEED_M_S`], Q 0-7); times must increase. The last line
/// is skipped with a warning when it has no end of line or does not parse.
pub fn parse_fixes_csv(text: &str, file: &str) -> Result<PosSolution> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let lines: Vec<&str> = text.lines().collect();
    let content = |k: &usize| {
        let s = lines[*k].trim();
        !s.is_empty() && !s.starts_with('#')
    };
    let mut rows = (0..lines.len()).filter(content);
    let Some(header) = rows.next() else {
        return Err(parse_error(
            file,
            1,
            format!(
                "expected a header line naming the columns (e.g. {GPS_TIME},lat_deg,lon_deg,height_m,std_n_m,std_e_m,std_d_m)"
            ),
        ));
    };
    let layout =
        Layout::from_header(lines[header]).map_err(|e| parse_error(file, header + 1, e))?;
    let names: Vec<&str> = lines[header].split(',').map(str::trim).collect();
    let mut data: Vec<usize> = rows.collect();
    let mut warnings = Vec::new();
    if !text.ends_with('\n') && data.last() == Some(&(lines.len() - 1)) {
        warnings.push(format!(
            "{file}:{}: last line cut short (no end of line: the file stopped mid-line); skipped",
            lines.len()
        ));
        data.pop();
    }
    let mut sol = PosSolution::with_capacity(data.len());
    let mut covariances = Vec::with_capacity(data.len());
    let mut velocity_covariances = Vec::with_capacity(data.len());
    for (i, &k) in data.iter().enumerate() {
        let row = match parse_row(lines[k], &layout, &names) {
            Ok(row) => row,
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
            if row.gps_time_s <= previous {
                return Err(parse_error(
                    file,
                    k + 1,
                    format!(
                        "time {:.3} s (GPS) does not follow the previous epoch's {previous:.3} s: epochs must increase",
                        row.gps_time_s
                    ),
                ));
            }
        }
        sol.gps_time_s.push(row.gps_time_s);
        sol.lla.push(row.lla);
        sol.quality.push(row.quality);
        sol.n_satellites.push(row.n_satellites);
        sol.std_ned_m.push(std_of(&row.covariance));
        sol.velocity_ned_m_s.push(row.velocity);
        sol.velocity_std_ned_m_s
            .push(std_of(&row.velocity_covariance));
        covariances.push(row.covariance);
        velocity_covariances.push(row.velocity_covariance);
    }
    if sol.gps_time_s.is_empty() {
        return Err(parse_error(
            file,
            lines.len().max(1),
            "expected at least one line of fixes after the header",
        ));
    }
    if layout.covariance.is_some() {
        sol.covariance_ned_m2 = Some(covariances);
    }
    if layout.velocity_covariance.is_some() {
        sol.velocity_covariance_ned_m2_s2 = Some(velocity_covariances);
    }
    sol.warnings = warnings;
    Ok(sol)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geodesy::{geodetic_to_ecef, Geodetic};

    const GEODETIC_CSV: &str = "# a receiver's fixes\n\
        gps_time_s,lat_deg,lon_deg,height_m,cov_nn_m2,cov_ne_m2,cov_nd_m2,cov_ee_m2,cov_ed_m2,cov_dd_m2,vn_m_s,ve_m_s,vd_m_s,std_vn_m_s,std_ve_m_s,std_vd_m_s,quality\n\
        1000.25,40.0966268,-105.1474483,1601.45,4,1.5,-0.5,9,0.3,16,1,2,-0.5,0.1,0.2,0.3,1\n\
        1000.5,40.0966269,-105.1474484,1601.46,4,0,0,9,0,16,,,,,,,2\n";

    #[test]
    fn geodetic_with_full_covariance() {
        let sol = parse_fixes_csv(GEODETIC_CSV, "f.csv").unwrap();
        assert_eq!(sol.gps_time_s, vec![1000.25, 1000.5]);
        assert_eq!(sol.lla[0].x, 40.0966268_f64.to_radians());
        assert_eq!(sol.lla[0].z, 1601.45);
        let c = sol.covariance_ned_m2.as_ref().unwrap()[0];
        assert_eq!(
            c,
            Matrix3::new(4.0, 1.5, -0.5, 1.5, 9.0, 0.3, -0.5, 0.3, 16.0)
        );
        assert_eq!(sol.std_ned_m[0], Vector3::new(2.0, 3.0, 4.0));
        assert_eq!(sol.velocity_ned_m_s[0], Vector3::new(1.0, 2.0, -0.5));
        assert!((sol.velocity_std_ned_m_s[0] - Vector3::new(0.1, 0.2, 0.3)).norm() < 1e-15);
        assert!(sol.velocity_ned_m_s[1].x.is_nan());
        assert_eq!((sol.quality[0], sol.quality[1]), (1, 2));
        assert!(sol.velocity_covariance_ned_m2_s2.is_none());
    }

    #[test]
    fn ecef_and_week_tow() {
        let g = Geodetic::new(0.7, -1.8, 250.0);
        let r = geodetic_to_ecef(g);
        let text = format!(
            "gps_week,gps_tow_s,x_ecef_m,y_ecef_m,z_ecef_m,std_n_m,std_e_m,std_d_m\n2381,345600.5,{:.6},{:.6},{:.6},1,1,2\n",
            r.x, r.y, r.z
        );
        let sol = parse_fixes_csv(&text, "f.csv").unwrap();
        assert_eq!(sol.gps_time_s[0], 2381.0 * 604_800.0 + 345_600.5);
        assert!((sol.lla[0].x - 0.7).abs() < 1e-12 && (sol.lla[0].y + 1.8).abs() < 1e-12);
        assert!((sol.lla[0].z - 250.0).abs() < 1e-5);
        assert_eq!(sol.quality[0], DEFAULT_CSV_QUALITY);
        assert!(sol.covariance_ned_m2.is_none());
    }

    #[test]
    fn errors_name_line_column_and_range() {
        let e = parse_fixes_csv(
            "gps_time_s,lat_deg,lon_deg,height_m,std_n_m,std_e_m,std_d_m,speed\n",
            "f.csv",
        )
        .unwrap_err();
        assert!(
            e.to_string()
                .starts_with("f.csv:1: unknown column(s) [\"speed\"]"),
            "{e}"
        );
        let e = parse_fixes_csv(
            "gps_time_s,lat_deg,lon_deg,std_n_m,std_e_m,std_d_m\n",
            "f.csv",
        )
        .unwrap_err();
        assert!(e.to_string().contains("height_m missing"), "{e}");
        let e = parse_fixes_csv("gps_time_s,lat_deg,lon_deg,height_m\n", "f.csv").unwrap_err();
        assert!(
            e.to_string()
                .contains("position uncertainty: expected the columns"),
            "{e}"
        );
        let third = "1001,40.0966269,-105.1474484,1601.46,4,0,0,9,0,16,,,,,,,2\n";
        let bad_lat = GEODETIC_CSV.replace("40.0966269", "95");
        let with_third = |s: &str| format!("{s}{third}");
        let e = parse_fixes_csv(&with_third(&bad_lat), "f.csv").unwrap_err();
        assert_eq!(
            e.to_string(),
            "f.csv:4: field 2: lat_deg = 95 ° is out of range (-90 to 90 °)"
        );
        let not_psd = GEODETIC_CSV.replace("4,0,0,9", "4,7,0,9");
        let e = parse_fixes_csv(&with_third(&not_psd), "f.csv").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("f.csv:4: the position covariance is not a covariance"),
            "{e}"
        );
        let back = GEODETIC_CSV.replace("1000.5,", "1000.25,");
        let e = parse_fixes_csv(&with_third(&back), "f.csv").unwrap_err();
        assert!(e.to_string().starts_with("f.csv:4: time 1000.250 s"), "{e}");
        let half_velocity = GEODETIC_CSV.replace(",,,,,,2", ",1,,,,,2");
        let e = parse_fixes_csv(&with_third(&half_velocity), "f.csv").unwrap_err();
        assert!(e.to_string().contains("all given or all empty"), "{e}");
        let cut = &GEODETIC_CSV[..GEODETIC_CSV.len() - 10];
        let sol = parse_fixes_csv(cut, "f.csv").unwrap();
        assert_eq!(sol.gps_time_s.len(), 1);
        assert!(sol.warnings[0].starts_with("f.csv:4: last line cut short"));
        // A bad last line is taken for one cut short, like the other readers.
        let sol = parse_fixes_csv(&bad_lat, "f.csv").unwrap();
        assert_eq!(sol.gps_time_s.len(), 1);
        assert!(sol.warnings[0].starts_with("f.csv:4: last line cut short"));
    }
}
