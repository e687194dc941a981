//! What a GNSS receiver can report: the one set of plausibility ranges every
//! reader and decoder (RINEX, UBX, GnssLogger, the fix readers, GNSS
//! tables) and the step API apply. A value outside cannot come from a
//! receiver or a satellite in service: it is a corrupted field, and passing
//! it on would put garbage into a fix or a filter. The broadcast orbit
//! elements have their own table (`super::broadcast_ranges`), as the
//! navigation messages define them bit by bit.
//!
//! `docs/reference/robustness.md` lists these ranges and what each reader does with a
//! value outside (a record skipped and counted, or the file refused naming
//! the line).

use std::ops::RangeInclusive;

use crate::geodesy::wgs84::{SEMI_MAJOR_AXIS_M, SEMI_MINOR_AXIS_M};
use nalgebra::Vector3;

/// Last calendar year of a GNSS epoch: GPS time starts in 1980; a date from
/// 2100 on is a corrupted field (an RXM-RAWX week of 9999 is in 2171), not
/// a measurement.
pub const LAST_YEAR: i64 = 2099;

/// GPS time of 2100-01-01 00:00:00, s since 1980-01-06: 43 825 days.
pub const END_GPS_TIME_S: f64 = 43_825.0 * 86_400.0;

/// GPS times a receiver can report, s since 1980-01-06 (to the end of
/// [`LAST_YEAR`]).
pub const GPS_TIME_S: RangeInclusive<f64> = 0.0..=END_GPS_TIME_S;

/// GPS weeks (continuous, not modulo 1024) that start before 2100.
pub const GPS_WEEKS: RangeInclusive<u32> = 0..=6260;

/// Code pseudoranges, m: beyond geostationary range plus a 1 ms receiver
/// clock error.
pub const PSEUDORANGE_M: RangeInclusive<f64> = 0.0..=1e8;

/// Pseudorange rates, m/s: a satellite's line-of-sight speed (< 1 km/s),
/// the receiver's ([`MAX_SPEED_M_S`]) and its clock drift
/// ([`MAX_CLOCK_DRIFT_M_S`]) with a wide margin.
pub const PSEUDORANGE_RATE_M_S: RangeInclusive<f64> = -1e5..=1e5;

/// Carrier phases, cycles: the RINEX F14.3 field's reach.
pub const CARRIER_PHASE_CYCLES: RangeInclusive<f64> = -1e10..=1e10;

/// Dopplers, Hz (±1 MHz: 190 km/s at L1).
pub const DOPPLER_HZ: RangeInclusive<f64> = -1e6..=1e6;

/// Signal strengths, dB-Hz.
pub const CN0_DB_HZ: RangeInclusive<f64> = 0.0..=200.0;

/// Ellipsoidal heights of a receiver, m: from below the deepest ground to
/// beyond low Earth orbit.
pub const HEIGHT_M: RangeInclusive<f64> = -1.0e4..=1.0e7;

/// Largest speed (or velocity component) of a receiver, m/s: beyond orbital
/// speed.
pub const MAX_SPEED_M_S: f64 = 1.0e4;

/// Largest receiver clock offset, m (c × 0.33 s): beyond it the offset is
/// larger than any pseudorange ([`PSEUDORANGE_M`]).
pub const MAX_CLOCK_OFFSET_M: f64 = 1e8;

/// Largest receiver clock drift, m/s (c × 100 ppm: ten times a consumer
/// TCXO's frequency tolerance).
pub const MAX_CLOCK_DRIFT_M_S: f64 = 3e4;

/// Values an observation of type `code` can take (RINEX 3.05 §5.7): `C`
/// [`PSEUDORANGE_M`], `L` [`CARRIER_PHASE_CYCLES`], `D` [`DOPPLER_HZ`],
/// `S` [`CN0_DB_HZ`]; other types the F14.3 field's reach.
pub fn observation_range(code: &str) -> RangeInclusive<f64> {
    match code.as_bytes().first() {
        Some(b'C') => PSEUDORANGE_M,
        Some(b'D') => DOPPLER_HZ,
        Some(b'S') => CN0_DB_HZ,
        _ => CARRIER_PHASE_CYCLES,
    }
}

/// The accepted range and unit of observation type `code`, in words.
pub fn observation_range_text(code: &str) -> &'static str {
    match code.as_bytes().first() {
        Some(b'C') => "0 to 1e8 m",
        Some(b'L') => "±1e10 cycles",
        Some(b'D') => "±1e6 Hz",
        Some(b'S') => "0 to 200 dB-Hz",
        _ => "±1e10",
    }
}

/// The RINEX satellite numbers of system `letter` (RINEX 3.05 §3.5): GPS
/// 1-32, GLONASS slots 1-32, Galileo 1-36, BeiDou 1-63, QZSS 1-10 (PRN −
/// 192), NavIC 1-14, SBAS 20-58 (PRN − 100); `None` for another letter.
pub fn satellite_numbers(letter: char) -> Option<RangeInclusive<u16>> {
    Some(match letter {
        'G' | 'R' => 1..=32,
        'E' => 1..=36,
        'C' => 1..=63,
        'J' => 1..=10,
        'I' => 1..=14,
        'S' => 20..=58,
        _ => return None,
    })
}

/// `Ok` when satellite `number` of system `letter` exists, else a sentence
/// naming it and the range.
pub fn check_satellite(letter: char, number: i64) -> Result<(), String> {
    match satellite_numbers(letter) {
        Some(r) if r.contains(&u16::try_from(number).unwrap_or(0)) => Ok(()),
        Some(r) => Err(format!(
            "satellite {letter}{number:02} does not exist (system {letter} numbers {}-{})",
            r.start(),
            r.end()
        )),
        None => Err(format!("system letter {letter:?} is not a GNSS")),
    }
}

/// `Ok(value)` when `value` lies in `range`, else a sentence naming
/// `what`, the value with `unit` and the range.
pub fn check(
    value: f64,
    range: RangeInclusive<f64>,
    what: &str,
    unit: &str,
) -> Result<f64, String> {
    if range.contains(&value) {
        Ok(value)
    } else {
        Err(format!(
            "{what} = {value:e} {unit} is out of range ({:e} to {:e} {unit}): no receiver reports it",
            range.start(),
            range.end()
        ))
    }
}

/// Distances from the Earth's centre a receiver can be at, m: the height
/// range [`HEIGHT_M`] taken at the pole (below) and the equator (above).
pub const RECEIVER_RADIUS_M: RangeInclusive<f64> =
    SEMI_MINOR_AXIS_M - 1.0e4..=SEMI_MAJOR_AXIS_M + 1.0e7;

/// `Ok` when an ECEF position (m) lies within [`RECEIVER_RADIUS_M`] of the
/// Earth's centre, else a sentence giving its distance.
pub fn check_receiver_position(position_ecef: &Vector3<f64>) -> Result<(), String> {
    let r = position_ecef.norm();
    if RECEIVER_RADIUS_M.contains(&r) {
        Ok(())
    } else {
        Err(format!(
            "{r:e} m from the Earth's centre is no receiver's position (heights {:e} to {:e} m: \
             {:.0} to {:.0} m from the centre)",
            HEIGHT_M.start(),
            HEIGHT_M.end(),
            RECEIVER_RADIUS_M.start(),
            RECEIVER_RADIUS_M.end()
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn satellites_positions_and_values_are_named() {
        assert!(check_satellite('G', 32).is_ok());
        let e = check_satellite('G', 255).unwrap_err();
        assert!(
            e.contains("G255 does not exist") && e.contains("1-32"),
            "{e}"
        );
        assert!(check_satellite('C', 0).is_err());
        assert!(check_receiver_position(&Vector3::new(6.4e6, 0.0, 0.0)).is_ok());
        let e = check_receiver_position(&Vector3::new(1e30, 0.0, 0.0)).unwrap_err();
        assert!(e.starts_with("1e30 m from the Earth's centre"), "{e}");
        let e = check(-2147483.648, -MAX_SPEED_M_S..=MAX_SPEED_M_S, "velE", "m/s").unwrap_err();
        assert!(
            e.starts_with("velE = -2.147483648e6 m/s is out of range"),
            "{e}"
        );
        assert!(check(f64::NAN, PSEUDORANGE_M, "prMes", "m").is_err());
    }
}
