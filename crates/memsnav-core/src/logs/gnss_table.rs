//! Raw GNSS as a long table: one row per epoch and satellite with named
//! columns, the layout `memsnav simulate` writes as `gnss.csv`. Read from
//! a CSV file (first line the column names) or from columns the caller
//! already holds (a pandas or polars DataFrame, a dict of arrays).
//!
//! Columns (SI units, names say them): `time_s`, `sat_id` (its system by
//! [`crate::gnss::system_of_number`]: 101-199 Galileo, 201-299 BeiDou),
//! `sat_position_ecef_{x,y,z}_m` and `sat_velocity_ecef_{x,y,z}_m_s` at
//! transmission, `pseudorange_m` (satellite clock corrected); optional
//! `gps_time_s` (GPS s since 1980-01-06 of each row), `pseudorange_rate_m_s`
//! (an empty field or NaN: no rate for that row), `pseudorange_std_m`,
//! `pseudorange_rate_std_m_s` (σ columns left out: the caller's σ for
//! every row), `carrier_phase_m` with `carrier_phase_std_m` (both or
//! neither; the carrier range, [`crate::gnss::CarrierPhase`]: empty or NaN
//! for no carrier in that row), `loss_of_lock` (1 or 0, empty: 0). Any
//! other column is an error naming it and the closest
//! known name. Rows go in time order; rows of one epoch share its time.
//! Every row passes [`crate::gnss::check_measurement`] (its NaN policy).

use std::path::Path;

use nalgebra::Vector3;

use super::fields::{finite_number, parse_error};
use crate::gnss::plausible;
use crate::gnss::{
    carrier_of, epochs_from_rows, sat_id, system_of_number, GnssEpoch, SatelliteMeasurement,
};
use crate::gnss::{DEFAULT_PSEUDORANGE_RATE_STD_M_S, DEFAULT_PSEUDORANGE_STD_M};
use crate::{known_keys, Error, Result};

/// The columns every table must have.
pub const GNSS_TABLE_REQUIRED: [&str; 9] = [
    "time_s",
    "sat_id",
    "sat_position_ecef_x_m",
    "sat_position_ecef_y_m",
    "sat_position_ecef_z_m",
    "sat_velocity_ecef_x_m_s",
    "sat_velocity_ecef_y_m_s",
    "sat_velocity_ecef_z_m_s",
    "pseudorange_m",
];

/// The columns a table may have.
pub const GNSS_TABLE_OPTIONAL: [&str; 7] = [
    "gps_time_s",
    "pseudorange_rate_m_s",
    "pseudorange_std_m",
    "pseudorange_rate_std_m_s",
    "carrier_phase_m",
    "carrier_phase_std_m",
    "loss_of_lock",
];

/// The σ of every row of a table without σ columns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableStds {
    /// Pseudorange one-sigma, m.
    pub pseudorange_std_m: f64,
    /// Pseudorange-rate one-sigma, m/s.
    pub pseudorange_rate_std_m_s: f64,
}

impl Default for TableStds {
    /// The simulator's and the RINEX reader's defaults.
    fn default() -> Self {
        Self {
            pseudorange_std_m: DEFAULT_PSEUDORANGE_STD_M,
            pseudorange_rate_std_m_s: DEFAULT_PSEUDORANGE_RATE_STD_M_S,
        }
    }
}

/// The epochs of a long table.
#[derive(Debug, Clone, PartialEq)]
pub struct GnssTable {
    /// The epochs, in time order.
    pub epochs: Vec<GnssEpoch>,
    /// GPS time of the first epoch, s (from `gps_time_s`, when given).
    pub start_gps_time_s: Option<f64>,
}

/// What is wrong with a table: a column, or a 0-based row.
enum TableError {
    Column(String),
    Row(usize, String),
}

/// A table from columns already in memory: `(name, values)` pairs of
/// equal length. Errors are [`Error::InvalidArgument`] for `argument`,
/// naming the column or the 0-based row.
pub fn gnss_table_from_columns(
    columns: &[(&str, &[f64])],
    stds: TableStds,
    argument: &str,
) -> Result<GnssTable> {
    build(columns, stds).map_err(|e| match e {
        TableError::Column(reason) => Error::invalid(argument, reason),
        TableError::Row(row, reason) => Error::invalid(argument, format!("row {row}: {reason}")),
    })
}

/// Reads a CSV long table (see the module documentation).
pub fn read_gnss_table(path: impl AsRef<Path>, stds: TableStds) -> Result<GnssTable> {
    let path = path.as_ref();
    let bytes = super::read_bytes(path)?;
    parse_gnss_table(
        &String::from_utf8_lossy(&bytes),
        &path.display().to_string(),
        stds,
    )
}

/// Parses the text of a CSV long table; `file` names it in errors, which
/// give the 1-based line.
pub fn parse_gnss_table(text: &str, file: &str, stds: TableStds) -> Result<GnssTable> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (header_index, header) = lines.next().ok_or_else(|| {
        parse_error(
            file,
            1,
            "empty file: expected a header line of column names",
        )
    })?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let mut values: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    let mut line_of_row = Vec::new();
    for (index, line) in lines {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != names.len() {
            return Err(parse_error(
                file,
                index + 1,
                format!(
                    "{} fields where the header names {} columns",
                    fields.len(),
                    names.len()
                ),
            ));
        }
        for (k, text) in fields.iter().enumerate() {
            let value = if text.is_empty() {
                f64::NAN
            } else {
                finite_number(text).ok_or_else(|| {
                    parse_error(
                        file,
                        index + 1,
                        format!("column {}: {text:?} is not a finite number", names[k]),
                    )
                })?
            };
            values[k].push(value);
        }
        line_of_row.push(index + 1);
    }
    let columns: Vec<(&str, &[f64])> = names
        .iter()
        .zip(&values)
        .map(|(n, v)| (*n, v.as_slice()))
        .collect();
    build(&columns, stds).map_err(|e| match e {
        TableError::Column(reason) => parse_error(file, header_index + 1, reason),
        TableError::Row(row, reason) => parse_error(file, line_of_row[row], reason),
    })
}

fn build(
    columns: &[(&str, &[f64])],
    stds: TableStds,
) -> std::result::Result<GnssTable, TableError> {
    let known: Vec<&str> = GNSS_TABLE_REQUIRED
        .iter()
        .chain(&GNSS_TABLE_OPTIONAL)
        .copied()
        .collect();
    for (k, (name, values)) in columns.iter().enumerate() {
        known_keys::check("column", name, &known).map_err(|e| TableError::Column(e.to_string()))?;
        if columns[..k].iter().any(|(other, _)| other == name) {
            return Err(TableError::Column(format!("column {name} appears twice")));
        }
        if values.len() != columns[0].1.len() {
            return Err(TableError::Column(format!(
                "column {name} has {} rows where {} has {}",
                values.len(),
                columns[0].0,
                columns[0].1.len()
            )));
        }
    }
    let get = |name: &str| columns.iter().find(|(n, _)| *n == name).map(|(_, v)| *v);
    let mut required = Vec::with_capacity(GNSS_TABLE_REQUIRED.len());
    for name in GNSS_TABLE_REQUIRED {
        required.push(get(name).ok_or_else(|| {
            TableError::Column(format!(
                "no {name} column (a table needs {})",
                GNSS_TABLE_REQUIRED.join(", ")
            ))
        })?);
    }
    let [time, id, px, py, pz, vx, vy, vz, rho] = required[..] else {
        unreachable!("nine required columns")
    };
    let rate = get("pseudorange_rate_m_s");
    let rate_std = get("pseudorange_rate_std_m_s");
    if rate.is_none() && rate_std.is_some() {
        return Err(TableError::Column(
            "pseudorange_rate_std_m_s without a pseudorange_rate_m_s column".into(),
        ));
    }
    let carrier = get("carrier_phase_m");
    let carrier_std = get("carrier_phase_std_m");
    if carrier.is_some() != carrier_std.is_some() {
        return Err(TableError::Column(
            "carrier_phase_m and carrier_phase_std_m go together (give both, or neither)".into(),
        ));
    }
    let loss_of_lock = get("loss_of_lock");
    let rho_std = get("pseudorange_std_m");
    let n = time.len();
    if n == 0 {
        return Err(TableError::Column(
            "no rows: give at least one measurement".into(),
        ));
    }
    let mut rows = Vec::with_capacity(n);
    for i in 0..n {
        let sat_id = sat_id(id[i]).map_err(|e| TableError::Row(i, e))?;
        let carrier = match (carrier, carrier_std) {
            (Some(c), Some(s)) => carrier_of(c[i], s[i], loss_of_lock.map_or(0.0, |l| l[i]))
                .map_err(|e| TableError::Row(i, e))?,
            _ => None,
        };
        rows.push((
            time[i],
            SatelliteMeasurement {
                sat_id,
                system: system_of_number(sat_id),
                position_ecef: Vector3::new(px[i], py[i], pz[i]),
                velocity_ecef: Vector3::new(vx[i], vy[i], vz[i]),
                pseudorange_m: rho[i],
                pseudorange_rate_m_s: rate.map_or(f64::NAN, |r| r[i]),
                pseudorange_std_m: rho_std.map_or(stds.pseudorange_std_m, |s| s[i]),
                pseudorange_rate_std_m_s: rate_std.map_or(stds.pseudorange_rate_std_m_s, |s| s[i]),
                carrier,
            },
        ));
    }
    let epochs = epochs_from_rows(rows).map_err(|(i, e)| TableError::Row(i, e))?;
    let start_gps_time_s = match get("gps_time_s") {
        None => None,
        Some(gps) => {
            if let Some(i) = (0..n).find(|&i| !plausible::GPS_TIME_S.contains(&gps[i])) {
                return Err(TableError::Row(
                    i,
                    plausible::check(gps[i], plausible::GPS_TIME_S, "gps_time_s", "s").unwrap_err(),
                ));
            }
            // One clock: GPS time and time_s differ by one constant.
            let offset = gps[0] - time[0];
            if let Some(i) = (0..n).find(|&i| !((gps[i] - time[i]) - offset).abs().le(&1e-6)) {
                return Err(TableError::Row(
                    i,
                    format!(
                        "gps_time_s - time_s = {} s where the first row has {offset} s (one clock for both)",
                        gps[i] - time[i]
                    ),
                ));
            }
            Some(gps[0])
        }
    };
    Ok(GnssTable {
        epochs,
        start_gps_time_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "time_s,gps_time_s,sat_id,sat_position_ecef_x_m,sat_position_ecef_y_m,sat_position_ecef_z_m,sat_velocity_ecef_x_m_s,sat_velocity_ecef_y_m_s,sat_velocity_ecef_z_m_s,pseudorange_m,pseudorange_rate_m_s";

    #[test]
    fn rows_become_epochs() {
        let text = format!(
            "{HEADER}\n0,1e9,3,2e7,1e7,1e7,1000,0,0,2.2e7,100\n0,1e9,7,1e7,2e7,1e7,0,1000,0,2.1e7,\n1,1000000001,3,2e7,1e7,1e7,1000,0,0,2.2e7,101\n"
        );
        let t = parse_gnss_table(&text, "gnss.csv", TableStds::default()).unwrap();
        assert_eq!(t.epochs.len(), 2);
        assert_eq!(t.start_gps_time_s, Some(1e9));
        let m = &t.epochs[0].measurements;
        assert_eq!((m[0].sat_id, m[0].pseudorange_rate_m_s), (3, 100.0));
        assert!(m[1].pseudorange_rate_m_s.is_nan());
        assert_eq!(m[0].pseudorange_std_m, DEFAULT_PSEUDORANGE_STD_M);
    }

    #[test]
    fn times_ranges_and_rates_no_receiver_reports_are_refused() {
        let position = "3,2e7,1e7,1e7,1000,0,0";
        for (line, expected) in [
            (
                format!("0,1e308,{position},2.2e7,100"),
                "g.csv:2: gps_time_s = 1e308 s is out of range",
            ),
            (
                format!("0,1e9,{position},1e300,100"),
                "g.csv:2: pseudorange = 1e300 m is out of range",
            ),
            (
                format!("0,1e9,{position},2.2e7,1e300"),
                "g.csv:2: pseudorange_rate = 1e300 m/s is out of range",
            ),
        ] {
            let e = parse_gnss_table(
                &format!("{HEADER}\n{line}\n"),
                "g.csv",
                TableStds::default(),
            )
            .unwrap_err()
            .to_string();
            assert!(e.starts_with(expected), "{e}");
        }
    }

    #[test]
    fn errors_name_line_and_column() {
        let bad = HEADER.replace("pseudorange_rate_m_s", "pseudorange_rates_m_s");
        let e = parse_gnss_table(&format!("{bad}\n"), "g.csv", TableStds::default())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("g.csv:1: column: unknown key \"pseudorange_rates_m_s\" (did you mean \"pseudorange_rate_m_s\"?)"), "{e}");
        let text = format!("{HEADER}\n0,1e9,3,2e7,1e7,1e7,1000,0,0,,100\n");
        let e = parse_gnss_table(&text, "g.csv", TableStds::default())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("g.csv:2: pseudorange = NaN"), "{e}");
        let x: &[f64] = &[1.0];
        let e = gnss_table_from_columns(&[("time_s", x)], TableStds::default(), "table")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("table: no sat_id column"), "{e}");
    }

    #[test]
    fn carrier_columns_are_read_and_checked() {
        let header = format!("{HEADER},carrier_phase_m,carrier_phase_std_m,loss_of_lock");
        let row = "0,1e9,3,2e7,1e7,1e7,1000,0,0,2.2e7,100";
        let text =
            format!("{header}\n{row},2.1e7,0.003,1\n0,1e9,7,1e7,2e7,1e7,0,1000,0,2.1e7,,,,\n");
        let t = parse_gnss_table(&text, "gnss.csv", TableStds::default()).unwrap();
        let m = &t.epochs[0].measurements;
        let c = m[0].carrier.unwrap();
        assert_eq!((c.range_m, c.std_m, c.loss_of_lock), (2.1e7, 0.003, true));
        assert!(m[1].carrier.is_none());
        for (fields, message) in [
            ("2.1e7,,0", "g.csv:2: carrier_phase_std = NaN"),
            (
                "inf,0.003,0",
                "g.csv:2: column carrier_phase_m: \"inf\" is not a finite",
            ),
            ("2.1e7,0.003,3", "g.csv:2: loss_of_lock = 3"),
        ] {
            let text = format!("{header}\n{row},{fields}\n");
            let e = parse_gnss_table(&text, "g.csv", TableStds::default())
                .unwrap_err()
                .to_string();
            assert!(e.starts_with(message), "{e}");
        }
        let text = format!("{HEADER},carrier_phase_m\n{row},2.1e7\n");
        let e = parse_gnss_table(&text, "g.csv", TableStds::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("give both, or neither"), "{e}");
    }
}
