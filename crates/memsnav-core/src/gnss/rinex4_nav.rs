//! The record labels of RINEX 4 navigation files (RINEX 4.00 §5.3, tables
//! A32-A36): each record opens with `> EPH G01 LNAV` (an ephemeris of a
//! satellite and navigation message), `> STO`, `> EOP` or `> ION` (system
//! time offsets, Earth orientation, ionosphere). The label says which
//! records memsnav reads and in which layout; the others are skipped with
//! a count by their label, so nothing is left out without a word.

use super::rinex_fields::Cursor;
use crate::Result;

/// What a labelled record is to the reader.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Rinex4Record {
    /// An ephemeris in the RINEX 3 layout of its system (GPS LNAV,
    /// Galileo I/NAV or F/NAV, BeiDou D1 or D2, GLONASS FDMA) whose epoch
    /// line follows; the satellite, `G01`.
    Rinex3Layout(String),
    /// A GPS CNAV ephemeris (table A32).
    GpsCnav(String),
    /// A record not read, by the reason it is counted under.
    Skipped(String),
}

/// Reads the label on line `k` (which must start with `>`).
pub(super) fn record_label(cur: &Cursor<'_>, k: usize) -> Result<Rinex4Record> {
    let line = cur.lines[k];
    if !line.starts_with("> ") {
        return Err(cur.error(
            k,
            format!(
                "expected a RINEX 4 record label ('> EPH G01 LNAV', '> STO', '> EOP' or '> ION'), got {:?}",
                line.get(..14).unwrap_or(line)
            ),
        ));
    }
    let kind = cur.field(k, 2, 3);
    if matches!(kind, "STO" | "EOP" | "ION") {
        return Ok(Rinex4Record::Skipped(format!("RINEX 4 {kind} records")));
    }
    if kind != "EPH" {
        return Err(cur.error(
            k,
            format!("unknown RINEX 4 record type {kind:?}; expected EPH, STO, EOP or ION"),
        ));
    }
    let sat = cur.field(k, 6, 3).to_string();
    let message = cur.field(k, 10, 4);
    let letter = sat.chars().next().unwrap_or(' ');
    if sat.len() != 3 || !letter.is_ascii_uppercase() {
        return Err(cur.error(
            k,
            format!("expected a satellite ('G01') in columns 7-9 of the record label, got {sat:?}"),
        ));
    }
    Ok(match (letter, message) {
        ('G', "LNAV") | ('E', "INAV" | "FNAV") | ('C', "D1" | "D2") | ('R', "FDMA") => {
            Rinex4Record::Rinex3Layout(sat)
        }
        ('G', "CNAV") => Rinex4Record::GpsCnav(sat),
        _ => Rinex4Record::Skipped(format!("RINEX 4 {message} records of system {letter}")),
    })
}

/// The line after the record that starts at line `k`: the next label, or
/// the end of the file.
pub(super) fn next_label(cur: &Cursor<'_>, k: usize) -> usize {
    (k + 1..cur.lines.len())
        .find(|&j| cur.lines[j].starts_with('>'))
        .unwrap_or(cur.lines.len())
}

/// Checks that the epoch line `k` of a labelled record names the
/// satellite of its label.
pub(super) fn check_satellite(cur: &Cursor<'_>, k: usize, sat: &str) -> Result<()> {
    if k >= cur.lines.len() {
        return Err(cur.error(
            k.min(cur.lines.len().saturating_sub(1)),
            format!("end of file after the record label of {sat}: expected its epoch line"),
        ));
    }
    let found = cur.field(k, 0, 3);
    if found != sat {
        return Err(cur.error(
            k,
            format!("the record labelled {sat} starts with satellite {found:?}"),
        ));
    }
    Ok(())
}
