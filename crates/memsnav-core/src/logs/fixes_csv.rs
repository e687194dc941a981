//! GNSS fixes in CSV: one epoch a line, comma-separated columns named in a
//! header line, in any order (docs/how-to/your-own-files.md, "The fixes CSV").
//!
//! | group | columns (one alternative) | |
//! |---|---|---|
//! | time | `gps_time_s` (GPS s since 1980-01-06; see [`FixTimeReference`]) or `gps_week`, `gps_tow_s` | required |
//! | position | `lat_deg`, `lon_deg`, `height_m` (ellipsoidal) or `x_ecef_m`, `y_ecef_m`, `z_ecef_m` | required |
//! | position σ | `std_n_m`, `std_e_m`, `std_d_m` or `cov_nn_m2`, `cov_ne_m2`, `cov_nd_m2`, `cov_ee_m2`, `cov_ed_m2`, `cov_dd_m2` | optional (a truth may have none; loose coupling needs it) |
//! | velocity | `vn_m_s`, `ve_m_s`, `vd_m_s` | optional; empty cells: none that epoch |
//! | velocity σ | `std_vn_m_s`, `std_ve_m_s`, `std_vd_m_s` or `cov_vnvn_m2_s2`, `cov_vnve_m2_s2`, `cov_vnvd_m2_s2`, `cov_veve_m2_s2`, `cov_vevd_m2_s2`, `cov_vdvd_m2_s2` | optional, with velocity |
//! | attitude | `qw`, `qx`, `qy`, `qz` (scalar-first body-to-NED quaternion) or `roll_deg`, `pitch_deg`, `yaw_deg` (z-y-x Euler angles, body to NED) | optional (a truth's, to move it by a lever arm) |
//! | quality | `quality` (RTKLIB's Q, 0-7) | optional, default [`DEFAULT_CSV_QUALITY`] |
//! | satellites | `n_satellites` | optional, default 0 |
//!
//! Lines starting with `#` and blank lines are skipped. Without a column
//! mapping ([`FixesCsvLayout::columns`]) every other column name is an
//! error naming it; with one, the mapped header columns are read as the
//! names they map to, header columns named as above are read as
//! themselves, and every other column is ignored (a user's own file as it
//! is, with columns memsnav does not use).

use std::collections::HashMap;
use std::path::Path;

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

use super::fields::{finite_number, in_range, parse_error};
use super::pos_solution::{check_covariance, std_of, MAX_STD, QUALITY_RANGE};
use super::rtklib_pos::{MAX_SPEED_M_S, POS_HEIGHT_RANGE_M};
use super::PosSolution;
use crate::attitude::euler_to_dcm;
use crate::geodesy::ecef_to_geodetic;
use crate::gnss::{plausible, SECONDS_PER_WEEK, UNIX_TO_GPS_S};
use crate::{known_keys, Error, Result};

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
/// Body-to-NED attitude as a unit quaternion, scalar first: C_b^n is the
/// rotation matrix of q (v_n = q v_b q*).
const QUATERNION: [&str; 4] = ["qw", "qx", "qy", "qz"];
/// Body-to-NED attitude as z-y-x Euler angles ([`euler_to_dcm`]).
const EULER: [&str; 3] = ["roll_deg", "pitch_deg", "yaw_deg"];
const QUALITY: &str = "quality";
const N_SATELLITES: &str = "n_satellites";
const UPPER: [(usize, usize); 6] = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];

/// Every column name the reader knows.
pub const FIXES_CSV_COLUMNS: [&str; 39] = [
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
    QUATERNION[0],
    QUATERNION[1],
    QUATERNION[2],
    QUATERNION[3],
    EULER[0],
    EULER[1],
    EULER[2],
    QUALITY,
    N_SATELLITES,
];

/// Largest |ECEF coordinate| accepted, m (beyond geostationary orbit).
const MAX_ECEF_M: f64 = 1.0e8;

/// A quaternion whose norm is further than this from 1 is not an
/// attitude (a file's 8 decimals leave its norm within 1e-7 of 1).
const QUATERNION_NORM_TOLERANCE: f64 = 1e-3;

/// What the time column `gps_time_s` counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FixTimeReference {
    /// GPS seconds since the GPS epoch 1980-01-06 (`"column_gps"`).
    #[default]
    Gps,
    /// GPS seconds counted from 1970-01-01 without leap seconds
    /// (`"column_unix_gpst"`): GPS time + [`UNIX_TO_GPS_S`], the stamps of
    /// RTKLIB's `time_t`-like GPST and of many loggers.
    UnixGpst,
}

impl FixTimeReference {
    /// The names [`FixTimeReference::from_name`] takes (the IMU's
    /// `time_reference` names for a time column).
    pub const NAMES: [&str; 2] = ["column_gps", "column_unix_gpst"];

    /// The reference named `name` (one of [`FixTimeReference::NAMES`]).
    pub fn from_name(name: &str) -> Result<Self> {
        match name {
            "column_gps" => Ok(Self::Gps),
            "column_unix_gpst" => Ok(Self::UnixGpst),
            _ => {
                let hint = known_keys::closest(name, &Self::NAMES)
                    .map(|k| format!(" (did you mean {k:?}?)"))
                    .unwrap_or_default();
                Err(Error::invalid(
                    "time_reference",
                    format!(
                        "unknown time reference {name:?}{hint}; expected one of {}",
                        Self::NAMES.join(", ")
                    ),
                ))
            }
        }
    }

    /// The column's value that is GPS time 0, s.
    fn origin_s(self) -> f64 {
        match self {
            Self::Gps => 0.0,
            Self::UnixGpst => UNIX_TO_GPS_S,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Self::Gps => Self::NAMES[0],
            Self::UnixGpst => Self::NAMES[1],
        }
    }
}

/// How to read a fixes CSV: where each of memsnav's columns is in the
/// file's header, and what its time column counts. The default reads
/// memsnav's own names, time on GPS time since 1980.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FixesCsvLayout {
    /// (memsnav's column name, the file's header name) pairs. Empty: the
    /// header names only memsnav's columns ([`FIXES_CSV_COLUMNS`]), any
    /// other name is an error. Given: each named column is read from the
    /// header column of the given name, header columns that carry one of
    /// memsnav's names (and are not mapped over) as themselves, every
    /// other column is ignored.
    pub columns: Vec<(String, String)>,
    /// What `gps_time_s` (or the column mapped to it) counts.
    pub time_reference: FixTimeReference,
}

impl FixesCsvLayout {
    /// Every key of `columns` one of [`FIXES_CSV_COLUMNS`] (an unknown one
    /// names the one meant), none twice, no header name empty.
    fn check(&self) -> Result<()> {
        for (k, (name, header)) in self.columns.iter().enumerate() {
            known_keys::check("columns", name, &FIXES_CSV_COLUMNS)?;
            if self.columns[..k].iter().any(|(n, _)| n == name) {
                return Err(Error::invalid(
                    "columns",
                    format!("{name:?} is given twice"),
                ));
            }
            if header.trim().is_empty() {
                return Err(Error::invalid(
                    "columns",
                    format!("{name:?}: the header name is empty"),
                ));
            }
        }
        Ok(())
    }
}

/// Reads a fixes CSV (see the module documentation) laid out as `layout`
/// says ([`FixesCsvLayout::default`]: memsnav's own names, GPS time).
pub fn read_fixes_csv(path: impl AsRef<Path>, layout: &FixesCsvLayout) -> Result<PosSolution> {
    let path = path.as_ref();
    layout.check()?;
    parse_fixes_csv(
        &String::from_utf8_lossy(&super::read_bytes(path)?),
        &path.display().to_string(),
        layout,
    )
}

/// Where each column group sits in a line, what each field is, and what
/// the time column counts.
struct Columns {
    n_fields: usize,
    /// The header's names, one per field.
    header: Vec<String>,
    /// memsnav's name of each field (None: ignored).
    names: Vec<Option<&'static str>>,
    time_reference: FixTimeReference,
    gps_time: Option<usize>,
    week_tow: Option<Vec<usize>>,
    geodetic: Option<Vec<usize>>,
    ecef: Option<Vec<usize>>,
    std: Option<Vec<usize>>,
    covariance: Option<Vec<usize>>,
    velocity: Option<Vec<usize>>,
    velocity_std: Option<Vec<usize>>,
    velocity_covariance: Option<Vec<usize>>,
    quaternion: Option<Vec<usize>>,
    euler: Option<Vec<usize>>,
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

/// memsnav's name of `name` ([`FIXES_CSV_COLUMNS`]), if it is one.
fn known(name: &str) -> Option<&'static str> {
    FIXES_CSV_COLUMNS.iter().copied().find(|k| *k == name)
}

/// memsnav's name of each header field: by `layout`'s mapping, else the
/// field's own name when it is one of memsnav's (without a mapping any
/// other name is an error; with one it is ignored).
fn field_names(
    header: &[String],
    layout: &FixesCsvLayout,
) -> std::result::Result<Vec<Option<&'static str>>, String> {
    if layout.columns.is_empty() {
        let unknown: Vec<&str> = header
            .iter()
            .map(String::as_str)
            .filter(|n| known(n).is_none())
            .collect();
        if !unknown.is_empty() {
            return Err(format!(
                "unknown column(s) {unknown:?} in the header; the columns are: {} (or map the file's own names with columns)",
                FIXES_CSV_COLUMNS.join(", ")
            ));
        }
        return Ok(header.iter().map(|n| known(n)).collect());
    }
    let mapped: Vec<&str> = layout.columns.iter().map(|(n, _)| n.as_str()).collect();
    // Header columns with memsnav's names, unless mapped over.
    let mut names: Vec<Option<&'static str>> = header
        .iter()
        .map(|n| known(n).filter(|k| !mapped.contains(k)))
        .collect();
    for (name, wanted) in &layout.columns {
        let name = known(name).expect("checked by FixesCsvLayout::check");
        let wanted = wanted.trim();
        let mut at = header.iter().enumerate().filter(|(_, h)| *h == wanted);
        let Some((i, _)) = at.next() else {
            let listed: Vec<&str> = header.iter().map(String::as_str).take(40).collect();
            let hint = known_keys::closest(wanted, &listed)
                .map(|k| format!(" (did you mean {k:?}?)"))
                .unwrap_or_default();
            return Err(format!(
                "columns.{name}: the header has no column {wanted:?}{hint}; its columns are {listed:?}"
            ));
        };
        if at.next().is_some() {
            return Err(format!("columns.{name}: the header names {wanted:?} twice"));
        }
        if let Some(other) = names[i] {
            return Err(format!(
                "columns.{name}: the header column {wanted:?} is already read as {other}"
            ));
        }
        names[i] = Some(name);
    }
    Ok(names)
}

impl Columns {
    fn from_header(header: &str, layout: &FixesCsvLayout) -> std::result::Result<Self, String> {
        let header: Vec<String> = header.split(',').map(|n| n.trim().to_string()).collect();
        for (k, n) in header.iter().enumerate() {
            if header[..k].contains(n) && (layout.columns.is_empty() || known(n).is_some()) {
                return Err(format!("column {n:?} appears twice in the header"));
            }
        }
        let names = field_names(&header, layout)?;
        let mut index = HashMap::new();
        for (k, n) in names.iter().enumerate() {
            if let Some(n) = n {
                index.insert(*n, k);
            }
        }
        let columns = Self {
            n_fields: header.len(),
            time_reference: layout.time_reference,
            gps_time: index.get(GPS_TIME).copied(),
            week_tow: group(&WEEK_TOW, &index)?,
            geodetic: group(&GEODETIC, &index)?,
            ecef: group(&ECEF, &index)?,
            std: group(&STD, &index)?,
            covariance: group(&COVARIANCE, &index)?,
            velocity: group(&VELOCITY, &index)?,
            velocity_std: group(&VELOCITY_STD, &index)?,
            velocity_covariance: group(&VELOCITY_COVARIANCE, &index)?,
            quaternion: group(&QUATERNION, &index)?,
            euler: group(&EULER, &index)?,
            quality: index.get(QUALITY).copied(),
            n_satellites: index.get(N_SATELLITES).copied(),
            header,
            names,
        };
        let list = |n: &[&str]| n.join(", ");
        one_of(
            columns.gps_time.as_ref(),
            columns.week_tow.as_ref(),
            "time",
            GPS_TIME,
            &list(&WEEK_TOW),
            true,
        )?;
        if columns.week_tow.is_some() && columns.time_reference != FixTimeReference::Gps {
            return Err(format!(
                "time_reference = {:?} is what a {GPS_TIME} column counts; the header gives {} (GPS week and time of week)",
                columns.time_reference.name(),
                list(&WEEK_TOW)
            ));
        }
        one_of(
            columns.geodetic.as_ref(),
            columns.ecef.as_ref(),
            "position",
            &list(&GEODETIC),
            &list(&ECEF),
            true,
        )?;
        one_of(
            columns.std.as_ref(),
            columns.covariance.as_ref(),
            "position uncertainty",
            &list(&STD),
            &list(&COVARIANCE),
            false,
        )?;
        one_of(
            columns.velocity_std.as_ref(),
            columns.velocity_covariance.as_ref(),
            "velocity uncertainty",
            &list(&VELOCITY_STD),
            &list(&VELOCITY_COVARIANCE),
            false,
        )?;
        one_of(
            columns.quaternion.as_ref(),
            columns.euler.as_ref(),
            "attitude",
            &list(&QUATERNION),
            &list(&EULER),
            false,
        )?;
        if columns.velocity.is_none()
            && (columns.velocity_std.is_some() || columns.velocity_covariance.is_some())
        {
            return Err(format!(
                "velocity uncertainty without the velocity columns {}",
                list(&VELOCITY)
            ));
        }
        Ok(columns)
    }

    /// Field `k` in messages: memsnav's name, with the file's own where it
    /// differs (`time_s as gps_time_s`).
    fn label(&self, k: usize) -> String {
        let name = self.names[k].unwrap_or("ignored");
        if self.header[k] == name {
            name.to_string()
        } else {
            format!("{} as {name}", self.header[k])
        }
    }
}

/// Physical range and unit of a column.
fn column_range(
    name: &str,
    time_reference: FixTimeReference,
) -> (std::ops::RangeInclusive<f64>, &'static str) {
    match name {
        GPS_TIME => {
            let origin = time_reference.origin_s();
            (origin..=origin + plausible::END_GPS_TIME_S, "s")
        }
        "gps_week" => (0.0..=f64::from(*plausible::GPS_WEEKS.end()), ""),
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
        // A unit quaternion's components, with the rounding of its digits.
        "qw" | "qx" | "qy" | "qz" => (-1.01..=1.01, ""),
        "roll_deg" | "yaw_deg" => (-360.0..=360.0, "°"),
        "pitch_deg" => (-90.0..=90.0, "°"),
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
    columns: &Columns,
    may_be_empty: bool,
) -> std::result::Result<Option<f64>, String> {
    let name = columns.names[k].expect("only named fields are read");
    if f[k].is_empty() && may_be_empty {
        return Ok(None);
    }
    let label = columns.label(k);
    let x = finite_number(f[k]).ok_or_else(|| {
        format!(
            "field {} ({label}): expected a finite number, got {:?}",
            k + 1,
            f[k]
        )
    })?;
    let (range, unit) = column_range(name, columns.time_reference);
    let described = if name == GPS_TIME && columns.time_reference != FixTimeReference::Gps {
        format!("{label} (time_reference {})", columns.time_reference.name())
    } else {
        label.clone()
    };
    in_range(x, range, &described, unit).map_err(|e| format!("field {}: {e}", k + 1))?;
    if matches!(name, QUALITY | N_SATELLITES | "gps_week") && x.fract() != 0.0 {
        return Err(format!(
            "field {} ({label}): expected an integer, got {x}",
            k + 1
        ));
    }
    Ok(Some(x))
}

/// The values of `indices` (all required).
fn values(
    f: &[&str],
    indices: &[usize],
    columns: &Columns,
) -> std::result::Result<Vec<f64>, String> {
    indices
        .iter()
        .map(|&k| value(f, k, columns, false).map(|v| v.unwrap_or(f64::NAN)))
        .collect()
}

/// The three values of `indices` (all required).
fn vector(
    f: &[&str],
    indices: &[usize],
    columns: &Columns,
) -> std::result::Result<Vector3<f64>, String> {
    Ok(Vector3::from_column_slice(&values(f, indices, columns)?))
}

/// The values of `indices`, all given or all empty (None).
fn optional(
    f: &[&str],
    indices: &[usize],
    columns: &Columns,
) -> std::result::Result<Option<Vec<f64>>, String> {
    let values: Vec<Option<f64>> = indices
        .iter()
        .map(|&k| value(f, k, columns, true))
        .collect::<std::result::Result<_, _>>()?;
    match values.iter().filter(|v| v.is_some()).count() {
        0 => Ok(None),
        n if n == values.len() => Ok(Some(values.into_iter().flatten().collect())),
        _ => Err(format!(
            "the fields {} are all given or all empty",
            indices
                .iter()
                .map(|&k| columns.label(k))
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

/// C_b^n of a scalar-first body-to-NED quaternion [w, x, y, z], normalised
/// (its norm within [`QUATERNION_NORM_TOLERANCE`] of 1).
fn quaternion_attitude(q: &[f64]) -> std::result::Result<Matrix3<f64>, String> {
    let q = Quaternion::new(q[0], q[1], q[2], q[3]);
    let norm = q.norm();
    if (norm - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
        return Err(format!(
            "the quaternion {} has norm {norm:.6}: expected a unit quaternion (scalar first, body to NED)",
            QUATERNION.join(", ")
        ));
    }
    Ok(UnitQuaternion::from_quaternion(q)
        .to_rotation_matrix()
        .into_inner())
}

/// One epoch of a line.
struct Row {
    gps_time_s: f64,
    lla: Vector3<f64>,
    covariance: Matrix3<f64>,
    velocity: Vector3<f64>,
    velocity_covariance: Matrix3<f64>,
    attitude: Option<Matrix3<f64>>,
    quality: u8,
    n_satellites: u16,
}

fn parse_row(line: &str, columns: &Columns) -> std::result::Result<Row, String> {
    let f: Vec<&str> = line.split(',').map(str::trim).collect();
    if f.len() != columns.n_fields {
        return Err(format!(
            "expected {} fields ({}), got {}",
            columns.n_fields,
            columns.header.join(", "),
            f.len()
        ));
    }
    let required = |k: usize| value(&f, k, columns, false).map(|v| v.unwrap_or(f64::NAN));
    let gps_time_s = match (&columns.gps_time, &columns.week_tow) {
        (Some(k), _) => required(*k)? - columns.time_reference.origin_s(),
        (None, Some(wt)) => {
            let tow = required(wt[1])?;
            if tow >= SECONDS_PER_WEEK {
                return Err(format!(
                    "field {} ({}) = {tow} s is out of range (0 to below {SECONDS_PER_WEEK} s)",
                    wt[1] + 1,
                    columns.label(wt[1])
                ));
            }
            required(wt[0])? * SECONDS_PER_WEEK + tow
        }
        (None, None) => unreachable!("the header has a time"),
    };
    let lla = match (&columns.geodetic, &columns.ecef) {
        (Some(g), _) => {
            let v = vector(&f, g, columns)?;
            Vector3::new(v.x.to_radians(), v.y.to_radians(), v.z)
        }
        (None, Some(e)) => {
            let g = ecef_to_geodetic(&vector(&f, e, columns)?);
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
    let nan = Matrix3::repeat(f64::NAN);
    let covariance = match (&columns.std, &columns.covariance) {
        (Some(s), _) => {
            let s = vector(&f, s, columns)?;
            Matrix3::from_diagonal(&s.component_mul(&s))
        }
        (None, Some(c)) => {
            let m = symmetric(&values(&f, c, columns)?);
            check_covariance(&m, "the position covariance", "m²")?;
            m
        }
        // No σ in the file (a truth): unknown.
        (None, None) => nan,
    };
    let (velocity, velocity_covariance) = match &columns.velocity {
        Some(v) => match optional(&f, v, columns)? {
            Some(v) => {
                let velocity = Vector3::from_column_slice(&v);
                let c = match (&columns.velocity_std, &columns.velocity_covariance) {
                    (Some(s), _) => optional(&f, s, columns)?
                        .map(|s| Matrix3::from_diagonal(&Vector3::from_fn(|i, _| s[i] * s[i]))),
                    (None, Some(c)) => match optional(&f, c, columns)? {
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
    let attitude = match (&columns.quaternion, &columns.euler) {
        (Some(q), _) => Some(quaternion_attitude(&values(&f, q, columns)?)?),
        (None, Some(e)) => {
            let e = vector(&f, e, columns)?.map(f64::to_radians);
            Some(euler_to_dcm(e.x, e.y, e.z))
        }
        (None, None) => None,
    };
    let quality = match columns.quality {
        Some(k) => required(k)? as u8,
        None => DEFAULT_CSV_QUALITY,
    };
    let n_satellites = match columns.n_satellites {
        Some(k) => required(k)? as u16,
        None => 0,
    };
    Ok(Row {
        gps_time_s,
        lla,
        covariance,
        velocity,
        velocity_covariance,
        attitude,
        quality,
        n_satellites,
    })
}

/// Parses the text of a fixes CSV laid out as `layout` says; `file` names
/// it in errors. Each field is range-checked (latitude ±90°, longitude
/// ±180°, height in [`POS_HEIGHT_RANGE_M`], stds ≥ 0, covariances positive
/// semi-definite, speeds ≤ [`MAX_SPEED_M_S`], quaternions of unit norm,
/// Q 0-7); times must increase. The last line is skipped with a warning
/// when it has no end of line or does not parse.
pub fn parse_fixes_csv(text: &str, file: &str, layout: &FixesCsvLayout) -> Result<PosSolution> {
    layout.check()?;
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
    let columns = Columns::from_header(lines[header], layout)
        .map_err(|e| parse_error(file, header + 1, e))?;
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
    let mut attitudes = Vec::with_capacity(data.len());
    for (i, &k) in data.iter().enumerate() {
        let row = match parse_row(lines[k], &columns) {
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
        attitudes.extend(row.attitude);
    }
    if sol.gps_time_s.is_empty() {
        return Err(parse_error(
            file,
            lines.len().max(1),
            "expected at least one line of fixes after the header",
        ));
    }
    if columns.covariance.is_some() {
        sol.covariance_ned_m2 = Some(covariances);
    }
    if columns.velocity_covariance.is_some() {
        sol.velocity_covariance_ned_m2_s2 = Some(velocity_covariances);
    }
    if columns.quaternion.is_some() || columns.euler.is_some() {
        sol.attitude_c_b_n = Some(attitudes);
    }
    sol.warnings = warnings;
    Ok(sol)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geodesy::{geodetic_to_ecef, Geodetic};

    fn plain() -> FixesCsvLayout {
        FixesCsvLayout::default()
    }

    const GEODETIC_CSV: &str = "# a receiver's fixes\n\
        gps_time_s,lat_deg,lon_deg,height_m,cov_nn_m2,cov_ne_m2,cov_nd_m2,cov_ee_m2,cov_ed_m2,cov_dd_m2,vn_m_s,ve_m_s,vd_m_s,std_vn_m_s,std_ve_m_s,std_vd_m_s,quality\n\
        1000.25,40.0966268,-105.1474483,1601.45,4,1.5,-0.5,9,0.3,16,1,2,-0.5,0.1,0.2,0.3,1\n\
        1000.5,40.0966269,-105.1474484,1601.46,4,0,0,9,0,16,,,,,,,2\n";

    #[test]
    fn geodetic_with_full_covariance() {
        let sol = parse_fixes_csv(GEODETIC_CSV, "f.csv", &plain()).unwrap();
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
        let sol = parse_fixes_csv(&text, "f.csv", &plain()).unwrap();
        assert_eq!(sol.gps_time_s[0], 2381.0 * 604_800.0 + 345_600.5);
        assert!((sol.lla[0].x - 0.7).abs() < 1e-12 && (sol.lla[0].y + 1.8).abs() < 1e-12);
        assert!((sol.lla[0].z - 250.0).abs() < 1e-5);
        assert_eq!(sol.quality[0], DEFAULT_CSV_QUALITY);
        assert!(sol.covariance_ned_m2.is_none());
    }

    #[test]
    fn errors_name_line_column_and_range() {
        let parse = |text: &str| parse_fixes_csv(text, "f.csv", &plain());
        let e = parse("gps_time_s,lat_deg,lon_deg,height_m,std_n_m,std_e_m,std_d_m,speed\n")
            .unwrap_err();
        assert!(
            e.to_string()
                .starts_with("f.csv:1: unknown column(s) [\"speed\"]"),
            "{e}"
        );
        let e = parse("gps_time_s,lat_deg,lon_deg,std_n_m,std_e_m,std_d_m\n").unwrap_err();
        assert!(e.to_string().contains("height_m missing"), "{e}");
        let e = parse("gps_time_s,lat_deg,lon_deg,height_m,std_n_m,std_e_m,std_d_m,qw,qx,qy,qz,roll_deg,pitch_deg,yaw_deg\n").unwrap_err();
        assert!(
            e.to_string().contains(
                "attitude: give qw, qx, qy, qz or roll_deg, pitch_deg, yaw_deg, not both"
            ),
            "{e}"
        );
        let third = "1001,40.0966269,-105.1474484,1601.46,4,0,0,9,0,16,,,,,,,2\n";
        let bad_lat = GEODETIC_CSV.replace("40.0966269", "95");
        let with_third = |s: &str| format!("{s}{third}");
        let e = parse(&with_third(&bad_lat)).unwrap_err();
        assert_eq!(
            e.to_string(),
            "f.csv:4: field 2: lat_deg = 95 ° is out of range (-90 to 90 °)"
        );
        let not_psd = GEODETIC_CSV.replace("4,0,0,9", "4,7,0,9");
        let e = parse(&with_third(&not_psd)).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("f.csv:4: the position covariance is not a covariance"),
            "{e}"
        );
        let back = GEODETIC_CSV.replace("1000.5,", "1000.25,");
        let e = parse(&with_third(&back)).unwrap_err();
        assert!(e.to_string().starts_with("f.csv:4: time 1000.250 s"), "{e}");
        let half_velocity = GEODETIC_CSV.replace(",,,,,,2", ",1,,,,,2");
        let e = parse(&with_third(&half_velocity)).unwrap_err();
        assert!(e.to_string().contains("all given or all empty"), "{e}");
        let cut = &GEODETIC_CSV[..GEODETIC_CSV.len() - 10];
        let sol = parse(cut).unwrap();
        assert_eq!(sol.gps_time_s.len(), 1);
        assert!(sol.warnings[0].starts_with("f.csv:4: last line cut short"));
        // A bad last line is taken for one cut short, like the other readers.
        let sol = parse(&bad_lat).unwrap();
        assert_eq!(sol.gps_time_s.len(), 1);
        assert!(sol.warnings[0].starts_with("f.csv:4: last line cut short"));
    }

    /// A truth without σ reads, its σ unknown (NaN), no covariance.
    #[test]
    fn position_uncertainty_is_optional() {
        let sol = parse_fixes_csv(
            "gps_time_s,lat_deg,lon_deg,height_m\n100,40,-105,1600\n",
            "f.csv",
            &plain(),
        )
        .unwrap();
        assert!(sol.std_ned_m[0].iter().all(|s| s.is_nan()));
        assert!(sol.covariance_ned_m2.is_none());
        assert!(sol.position_covariance_ned_m2()[0][(0, 0)].is_nan());
        assert!(sol.attitude_c_b_n.is_none());
    }

    /// A user's own header (another time name, covariance names without
    /// the unit suffix, a column memsnav does not read) through a mapping,
    /// its time GPS seconds since 1970: the same solution as the file
    /// written in memsnav's names on GPS time since 1980.
    #[test]
    fn mapped_columns_and_unix_gps_time() {
        let own = "time_s,lat_deg,lon_deg,height_m,cov_nn_m2,cov_ne_m2,cov_nd_m2,cov_ee_m2,cov_ed_m2,cov_dd_m2,vn_m_s,ve_m_s,vd_m_s,cov_vnvn,cov_vnve,cov_vnvd,cov_veve,cov_vevd,cov_vdvd,temperature_c\n\
            1747680880.300590,39.7575074,-84.1097485,225.148,0.1448,-4.4e-4,0.023,0.084,-0.006,0.58,-0.002,0.001,-0.003,0.0033,-2.0e-4,-1.3e-4,0.0021,2.3e-4,0.0137,21.5\n\
            1747680881.308666,39.7575075,-84.1097484,225.154,0.1449,-4.0e-4,0.023,0.084,-0.006,0.58,,,,,,,,,,21.6\n";
        let mut columns: Vec<(String, String)> = vec![("gps_time_s".into(), "time_s".into())];
        for (memsnav, file) in VELOCITY_COVARIANCE.iter().zip([
            "cov_vnvn", "cov_vnve", "cov_vnvd", "cov_veve", "cov_vevd", "cov_vdvd",
        ]) {
            columns.push((memsnav.to_string(), file.to_string()));
        }
        let layout = FixesCsvLayout {
            columns,
            time_reference: FixTimeReference::UnixGpst,
        };
        let sol = parse_fixes_csv(own, "own.csv", &layout).unwrap();
        // Written by hand in memsnav's names: 1747680880.300590 s since
        // 1970 less the 3 657 days to 1980-01-06 (315 964 800 s).
        let native = "gps_time_s,lat_deg,lon_deg,height_m,cov_nn_m2,cov_ne_m2,cov_nd_m2,cov_ee_m2,cov_ed_m2,cov_dd_m2,vn_m_s,ve_m_s,vd_m_s,cov_vnvn_m2_s2,cov_vnve_m2_s2,cov_vnvd_m2_s2,cov_veve_m2_s2,cov_vevd_m2_s2,cov_vdvd_m2_s2\n\
            1431716080.300590,39.7575074,-84.1097485,225.148,0.1448,-4.4e-4,0.023,0.084,-0.006,0.58,-0.002,0.001,-0.003,0.0033,-2.0e-4,-1.3e-4,0.0021,2.3e-4,0.0137\n\
            1431716081.308666,39.7575075,-84.1097484,225.154,0.1449,-4.0e-4,0.023,0.084,-0.006,0.58,,,,,,,,,\n";
        let want = parse_fixes_csv(native, "native.csv", &plain()).unwrap();
        assert_eq!(sol.lla, want.lla);
        assert_eq!(sol.covariance_ned_m2, want.covariance_ned_m2);
        let (got, wanted) = (
            sol.velocity_covariance_ned_m2_s2.as_ref().unwrap(),
            want.velocity_covariance_ned_m2_s2.as_ref().unwrap(),
        );
        assert_eq!(got[0], wanted[0]);
        // The second epoch has no velocity: NaN both ways.
        assert!(got[1].iter().chain(wanted[1].iter()).all(|x| x.is_nan()));
        for (a, b) in sol.gps_time_s.iter().zip(&want.gps_time_s) {
            // Two roundings of a 1.7e9 s stamp: within a few hundred ns.
            assert!((a - b).abs() < 1e-6, "{a} {b}");
        }
        // Errors name the key and the column.
        let bad = |columns: Vec<(&str, &str)>, time_reference| {
            let layout = FixesCsvLayout {
                columns: columns
                    .into_iter()
                    .map(|(a, b)| (a.to_string(), b.to_string()))
                    .collect(),
                time_reference,
            };
            parse_fixes_csv(own, "own.csv", &layout)
                .unwrap_err()
                .to_string()
        };
        let unix = FixTimeReference::UnixGpst;
        let e = bad(vec![("gps_time", "time_s")], unix);
        assert!(
            e.starts_with("columns: unknown key \"gps_time\" (did you mean \"gps_time_s\"?)"),
            "{e}"
        );
        let e = bad(vec![("gps_time_s", "times")], unix);
        assert!(
            e.starts_with("own.csv:1: columns.gps_time_s: the header has no column \"times\" (did you mean \"time_s\"?)"),
            "{e}"
        );
        let e = bad(
            vec![("gps_time_s", "time_s"), ("gps_time_s", "time_s")],
            unix,
        );
        assert_eq!(e, "columns: \"gps_time_s\" is given twice");
        let e = bad(vec![("gps_time_s", "time_s"), ("quality", "lat_deg")], unix);
        assert!(
            e.contains("columns.quality: the header column \"lat_deg\" is already read as lat_deg"),
            "{e}"
        );
        // The cov_v* columns without their mapping: ignored, and then the
        // velocity covariance is missing, not misread.
        let sol = parse_fixes_csv(
            own,
            "own.csv",
            &FixesCsvLayout {
                columns: vec![("gps_time_s".into(), "time_s".into())],
                time_reference: unix,
            },
        )
        .unwrap();
        assert!(sol.velocity_covariance_ned_m2_s2.is_none());
        assert!(sol.velocity_std_ned_m_s[0].x.is_nan());
        // A Unix-like stamp read as GPS time since 1980 is in range (a
        // date in 2035), but a GPS time since 1980 read as counted from
        // 1970 is not: the error names the reference.
        let e = parse_fixes_csv(
            &with_reference(GEODETIC_CSV),
            "f.csv",
            &FixesCsvLayout {
                time_reference: unix,
                ..plain()
            },
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("f.csv:3: field 1: gps_time_s (time_reference column_unix_gpst) = 1000.25 s is out of range (315964800 to"),
            "{e}"
        );
        let e = parse_fixes_csv(
            "gps_week,gps_tow_s,lat_deg,lon_deg,height_m\n2000,1,0,0,0\n",
            "f.csv",
            &FixesCsvLayout {
                time_reference: unix,
                ..plain()
            },
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("time_reference = \"column_unix_gpst\" is what a gps_time_s column counts"),
            "{e}"
        );
        assert!(FixTimeReference::from_name("column_unix_gps")
            .unwrap_err()
            .to_string()
            .contains("did you mean \"column_unix_gpst\"?"));
    }

    /// GEODETIC_CSV with a third line, so that a bad line is not the last.
    fn with_reference(text: &str) -> String {
        format!("{text}1001,40.0966269,-105.1474484,1601.46,4,0,0,9,0,16,,,,,,,2\n")
    }

    /// The attitude of a quaternion and of Euler angles, against rotations
    /// written by hand: a 90° yaw turns body x (forward) to east, a 90°
    /// roll body y (right) to down; the two forms give one matrix.
    #[test]
    fn attitude_from_quaternion_or_euler() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let text = format!(
            "gps_time_s,lat_deg,lon_deg,height_m,qw,qx,qy,qz\n1,40,-105,1600,{h},0,0,{h}\n2,40,-105,1600,{h},{h},0,0\n3,40,-105,1600,0.6,0,0.8,0\n"
        );
        let sol = parse_fixes_csv(&text, "q.csv", &plain()).unwrap();
        let c = sol.attitude_c_b_n.as_ref().unwrap();
        assert!((c[0] * Vector3::x() - Vector3::y()).norm() < 1e-12);
        assert!((c[1] * Vector3::y() - Vector3::z()).norm() < 1e-12);
        // A pitch of 2·atan(0.8/0.6) = 106.26°: x to (cos, 0, −sin).
        let pitch = 2.0 * 0.8f64.atan2(0.6);
        let want = Vector3::new(pitch.cos(), 0.0, -pitch.sin());
        assert!((c[2] * Vector3::x() - want).norm() < 1e-12);
        let euler = "gps_time_s,lat_deg,lon_deg,height_m,roll_deg,pitch_deg,yaw_deg\n1,40,-105,1600,0,0,90\n2,40,-105,1600,90,0,0\n";
        let by_euler = parse_fixes_csv(euler, "e.csv", &plain()).unwrap();
        let e = by_euler.attitude_c_b_n.as_ref().unwrap();
        assert!((e[0] - c[0]).abs().max() < 1e-12);
        assert!((e[1] - c[1]).abs().max() < 1e-12);
        let not_unit = text.replace("0.6,0,0.8,0", "0.6,0,0.7,0") + "4,40,-105,1600,1,0,0,0\n";
        let e = parse_fixes_csv(&not_unit, "q.csv", &plain())
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("q.csv:4: the quaternion qw, qx, qy, qz has norm 0.921954"),
            "{e}"
        );
    }
}
