//! GLONASS records of RINEX navigation files (RINEX 3.05 table A10, RINEX
//! 2.11 table A11): an epoch line (slot, t_b in UTC, −τ_n, γ_n, the
//! message frame time) and three lines of position, velocity and
//! lunisolar acceleration in km, km/s and km/s² with the health, the
//! frequency channel and the age of the data; RINEX 3.05 adds a fourth
//! line (status flags, group delay, URAI), read past. Values outside what
//! the message can carry (ICD edition 5.1 table 4.5) are refused naming
//! the line.

use nalgebra::Vector3;

use super::glonass_ephemeris::GlonassEphemeris;
use super::rinex_fields::{satellite_prn, Cursor};
use super::utc::checked_gps_time_from_utc;
use crate::Result;

/// The values of a record after the epoch: −τ_n, γ_n, t_k, then per axis
/// position, velocity, acceleration and the axis line's fourth value.
const NAMES: [&str; 15] = [
    "SV clock bias -TauN",
    "SV relative frequency bias GammaN",
    "message frame time",
    "satellite position X",
    "velocity X dot",
    "X acceleration",
    "health",
    "satellite position Y",
    "velocity Y dot",
    "Y acceleration",
    "frequency number",
    "satellite position Z",
    "velocity Z dot",
    "Z acceleration",
    "age of operation information",
];

/// The largest |value| of each of [`NAMES`] (ICD table 4.5: bits × scale;
/// km, km/s, km/s²); `None` unchecked (t_k, read past).
const LIMITS: [Option<f64>; 15] = [
    Some(1.953_125e-3),    // τ_n: 22 bits × 2⁻³⁰ s
    Some(9.313_225_8e-10), // γ_n: 11 bits × 2⁻⁴⁰
    None,
    Some(2.7e4),  // x: 27 bits × 2⁻¹¹ km
    Some(4.3),    // ẋ: 24 bits × 2⁻²⁰ km/s
    Some(6.2e-9), // ẍ: 5 bits × 2⁻³⁰ km/s²
    None,
    Some(2.7e4),
    Some(4.3),
    Some(6.2e-9),
    None,
    Some(2.7e4),
    Some(4.3),
    Some(6.2e-9),
    None,
];

/// Reads the GLONASS record starting at line `k` (`version_2`: a RINEX 2
/// `g` file's layout); returns it and the line after it.
pub(super) fn parse_glonass_record(
    cur: &Cursor<'_>,
    k: usize,
    version_2: bool,
) -> Result<(GlonassEphemeris, usize)> {
    let (slot, calendar, epoch_width, indent) = if version_2 {
        let slot = satellite_prn(cur, k, 'R', cur.integer(k, 0, 2, "slot number")?)?;
        let yy = cur.integer(k, 2, 3, "year")?;
        let year = if yy < 80 { 2000 + yy } else { 1900 + yy };
        let calendar = (
            year,
            cur.integer(k, 5, 3, "month")?,
            cur.integer(k, 8, 3, "day")?,
            cur.integer(k, 11, 3, "hour")?,
            cur.integer(k, 14, 3, "minute")?,
            cur.number(k, 17, 5, "second")?,
        );
        (slot, calendar, 22, 3)
    } else {
        let slot = satellite_prn(cur, k, 'R', cur.integer(k, 1, 2, "slot number")?)?;
        let calendar = cur.rinex3_epoch(k)?;
        (slot, calendar, 23, 4)
    };
    if slot > 27 {
        return Err(cur.error(k, format!("GLONASS slot {slot} is out of range (1-27)")));
    }
    let (y, mo, d, h, mi, s) = calendar;
    let tb_gps_s = checked_gps_time_from_utc(y, mo, d, h, mi, s)
        .map_err(|reason| cur.error(k, format!("epoch of R{slot:02}: {reason}")))?;
    let mut values = [0.0_f64; 15];
    for (j, value) in values.iter_mut().enumerate() {
        let (line, column) = if j < 3 {
            (k, epoch_width + 19 * j)
        } else {
            (k + 1 + (j - 3) / 4, indent + 19 * ((j - 3) % 4))
        };
        let is_continuation = line == k
            || (line < cur.lines.len()
                && cur.lines[line].len() > indent
                && cur.field(line, 0, indent).is_empty());
        if !is_continuation {
            return Err(cur.error(
                line,
                format!(
                    "truncated record for R{slot:02} starting at line {}: expected broadcast orbit line {} of 3",
                    k + 1,
                    line - k
                ),
            ));
        }
        *value = cur.number(line, column, 19, NAMES[j])?;
        if let Some(limit) = LIMITS[j] {
            if value.abs() > limit {
                return Err(cur.error(
                    line,
                    format!(
                        "{} = {value:e} for R{slot:02} is out of range (±{limit:e}): not a value the navigation message can carry",
                        NAMES[j]
                    ),
                ));
            }
        }
    }
    let small_integer = |j: usize, low: f64, high: f64| {
        let v = values[j];
        if v.fract() == 0.0 && (low..=high).contains(&v) {
            Ok(v)
        } else {
            Err(cur.error(
                k + 1 + (j - 3) / 4,
                format!(
                    "{} = {v} for R{slot:02} is out of range (an integer {low} to {high})",
                    NAMES[j]
                ),
            ))
        }
    };
    let health = small_integer(6, 0.0, 15.0)? as u8;
    let frequency_channel = small_integer(10, -7.0, 13.0)? as i8;
    let age_days = small_integer(14, 0.0, 31.0)? as u8;
    // RINEX 3.05's fourth orbit line, when present.
    let mut next = k + 4;
    if !version_2
        && next < cur.lines.len()
        && cur.lines[next].len() > indent
        && cur.field(next, 0, indent).is_empty()
    {
        next += 1;
    }
    let km = |a: usize| Vector3::new(values[a], values[a + 4], values[a + 8]) * 1e3;
    Ok((
        GlonassEphemeris {
            slot,
            frequency_channel,
            tb_gps_s,
            tau_n_s: -values[0],
            gamma_n: values[1],
            position_ecef: km(3),
            velocity_ecef: km(4),
            lunisolar_m_s2: km(5),
            health,
            age_days,
        },
        next,
    ))
}
