//! The fixed-column fields of a RINEX navigation file's lines, each error
//! naming the file and the 1-based line: shared by the GPS, Galileo and
//! BeiDou records ([`super::rinex_nav`]), GLONASS's
//! ([`super::rinex_nav_glonass`]) and GPS CNAV's ([`super::rinex_nav_cnav`]).

use super::plausible;
use crate::{Error, Result};

/// A navigation file's lines, read field by field.
pub(super) struct Cursor<'a> {
    pub(super) file: &'a str,
    pub(super) lines: Vec<&'a str>,
}

impl Cursor<'_> {
    pub(super) fn error(&self, line_index: usize, reason: impl Into<String>) -> Error {
        Error::Parse {
            file: self.file.to_string(),
            line: line_index + 1,
            reason: reason.into(),
        }
    }

    /// Field `[start, start + width)` of line `k`, trimmed ("" when the line is short).
    pub(super) fn field(&self, k: usize, start: usize, width: usize) -> &str {
        let line = self.lines[k];
        let end = (start + width).min(line.len());
        if start >= end {
            return "";
        }
        line.get(start..end).unwrap_or("").trim()
    }

    pub(super) fn number(&self, k: usize, start: usize, width: usize, what: &str) -> Result<f64> {
        let f = self.field(k, start, width);
        parse_number(f).ok_or_else(|| {
            self.error(
                k,
                format!(
                    "expected a number for {what} in columns {}-{}, got {f:?}",
                    start + 1,
                    start + width
                ),
            )
        })
    }

    pub(super) fn optional_number(
        &self,
        k: usize,
        start: usize,
        width: usize,
        what: &str,
    ) -> Result<Option<f64>> {
        if self.field(k, start, width).is_empty() {
            Ok(None)
        } else {
            self.number(k, start, width, what).map(Some)
        }
    }

    pub(super) fn integer(&self, k: usize, start: usize, width: usize, what: &str) -> Result<i64> {
        let f = self.field(k, start, width);
        f.parse::<i64>().map_err(|_| {
            self.error(
                k,
                format!(
                    "expected an integer {what} in columns {}-{}, got {f:?}",
                    start + 1,
                    start + width
                ),
            )
        })
    }

    /// The epoch of a RINEX 3/4 record's first line (`Gnn yyyy mm dd hh mm ss`,
    /// columns 4-23), in the satellite system's calendar.
    pub(super) fn rinex3_epoch(&self, k: usize) -> Result<Calendar> {
        Ok((
            self.integer(k, 3, 5, "year")?,
            self.integer(k, 8, 3, "month")?,
            self.integer(k, 11, 3, "day")?,
            self.integer(k, 14, 3, "hour")?,
            self.integer(k, 17, 3, "minute")?,
            self.number(k, 20, 3, "second")?,
        ))
    }
}

/// A calendar epoch: year, month, day, hour, minute, second.
pub(super) type Calendar = (i64, i64, i64, i64, i64, f64);

/// The satellite number of system `letter` (one that exists,
/// [`plausible::satellite_numbers`]).
pub(super) fn satellite_prn(cur: &Cursor<'_>, k: usize, letter: char, prn: i64) -> Result<u16> {
    plausible::check_satellite(letter, prn)
        .map(|()| prn as u16)
        .map_err(|reason| cur.error(k, reason))
}

/// A real number in Fortran or C notation (`0.12D+02`, `-.5E-3`, `12`).
fn parse_number(field: &str) -> Option<f64> {
    if field.is_empty()
        || field
            .chars()
            .any(|c| c.is_ascii_alphabetic() && !matches!(c, 'D' | 'd' | 'E' | 'e'))
    {
        return None;
    }
    let value: f64 = field.replace(['D', 'd'], "E").parse().ok()?;
    value.is_finite().then_some(value)
}
