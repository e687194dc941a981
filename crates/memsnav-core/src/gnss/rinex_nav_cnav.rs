//! GPS CNAV records of RINEX 4 navigation files (`> EPH Gnn CNAV`, RINEX
//! 4.00 table A32): the epoch line (t_oc, a_f0-a_f2) and eight orbit lines
//! holding the CNAV orbit (Ȧ, Δn₀ and Δṅ₀ in the place of LNAV's issue of
//! data), t_op, the four accuracy indices, the L1/L2/L5 health bits, T_GD
//! and the four inter-signal corrections of message type 30, t_tm, and the
//! week of t_op (WN_op). RINEX 3 has no such record; the writer and the reader of
//! RINEX 4 files share this layout.
//!
//! CNAV has no t_oe of its own in the record: messages 10, 11 and 30-37 of
//! one upload carry t_oe = t_oc (IS-GPS-200 §30.3.3.1.1, the decoder pairs
//! them on it), so the epoch is both.

use super::broadcast_orbit::BroadcastOrbit;
use super::broadcast_ranges::check_value;
use super::cnav_ephemeris::{CnavEphemeris, CnavGroupDelays};
use super::rinex_fields::{satellite_prn, Cursor};
use super::time::{checked_gps_time_from_calendar, SECONDS_PER_WEEK};
use crate::Result;

/// The values of a CNAV record in RINEX 4 order: a_f0-a_f2 on the epoch
/// line, then eight lines of four (the last of two).
pub(super) const CNAV_NAMES: [&str; 33] = [
    "SV clock bias",
    "SV clock drift",
    "SV clock drift rate",
    "ADOT",
    "Crs",
    "Delta n0",
    "M0",
    "Cuc",
    "e",
    "Cus",
    "sqrt(A)",
    "t_op",
    "Cic",
    "OMEGA0",
    "Cis",
    "i0",
    "Crc",
    "omega",
    "OMEGA DOT",
    "IDOT",
    "Delta n0 dot",
    "URAI_NED0",
    "URAI_NED1",
    "URAI_ED",
    "SV health",
    "TGD",
    "URAI_NED2",
    "ISC_L1CA",
    "ISC_L2C",
    "ISC_L5I5",
    "ISC_L5Q5",
    "t_tm",
    "WN_op",
];

/// The ranges of the CNAV-only values (IS-GPS-200 table 30-I and 30-III:
/// bits × scale), by index of [`CNAV_NAMES`]; the clock and Keplerian
/// values (indices 0-2, 4-10, 12-19, where the LNAV layout has the same
/// quantities) are checked against LNAV's ranges, as the UBX decoder
/// checks a decoded CNAV ephemeris, so what the decoder keeps a file of it
/// gives back.
fn cnav_range(index: usize) -> Option<(f64, f64)> {
    const PI: f64 = std::f64::consts::PI;
    // T_GD and ISCs: 13 bits × 2⁻³⁵ s.
    const DELAY_S: f64 = 1.192_092_9e-7;
    match index {
        3 => Some((-8.0, 8.0)), // Ȧ: 25 bits × 2⁻²¹ m/s
        11 | 31 => Some((0.0, SECONDS_PER_WEEK)),
        20 => Some((-2.910_383e-11 * PI, 2.910_383e-11 * PI)), // Δṅ₀: 23 bits × 2⁻⁵⁷ semicircles/s²
        21 | 23 => Some((-16.0, 15.0)),                        // URA_NED0, URA_ED: 5 bits signed
        22 | 26 => Some((0.0, 7.0)),                           // URA_NED1, URA_NED2: 3 bits
        24 => Some((0.0, 7.0)),                                // L1/L2/L5 health bits
        25 | 27..=30 => Some((-DELAY_S, DELAY_S)),
        32 => Some((0.0, 6260.0)), // GPS week, continuous, as LNAV's
        _ => None,
    }
}

/// The index in the LNAV layout of a CNAV value that has the same meaning
/// and place (clock, harmonic terms, Keplerian elements).
fn lnav_index(index: usize) -> Option<usize> {
    matches!(index, 0..=2 | 4..=10 | 12..=19).then_some(index)
}

/// Whether value `index` must be an integer (indices, health, week).
fn is_integer(index: usize) -> bool {
    matches!(index, 21..=24 | 26 | 32)
}

/// The health bits of message type 10 as RINEX 4's one number: L1 bit 2,
/// L2 bit 1, L5 bit 0 (the message's order, L1 first).
fn health_number(c: &CnavEphemeris) -> f64 {
    f64::from(c.l1_health << 2 | c.l2_health << 1 | c.l5_health)
}

/// The record values of `c`, `None` where a group delay is not available
/// (a blank field). t_op and t_tm are seconds of their GPS weeks; the
/// week written is t_op's (WN_op), t_tm is read back within half a week of
/// t_oc.
pub(super) fn cnav_values(c: &CnavEphemeris) -> [Option<f64>; 33] {
    let o = &c.orbit;
    let week = (c.top_gps_s / SECONDS_PER_WEEK).floor();
    let of_week = |t: f64| t.rem_euclid(SECONDS_PER_WEEK);
    let delays = c.group_delays;
    let delay = |f: fn(&CnavGroupDelays) -> Option<f64>| delays.as_ref().and_then(f);
    [
        Some(o.af0_s),
        Some(o.af1_s_s),
        Some(o.af2_s_s2),
        Some(o.a_dot_m_s),
        Some(o.crs_m),
        Some(o.delta_n_rad_s),
        Some(o.m0_rad),
        Some(o.cuc_rad),
        Some(o.eccentricity),
        Some(o.cus_rad),
        Some(o.sqrt_a_sqrt_m),
        Some(c.top_gps_s - week * SECONDS_PER_WEEK),
        Some(o.cic_rad),
        Some(o.omega0_rad),
        Some(o.cis_rad),
        Some(o.i0_rad),
        Some(o.crc_m),
        Some(o.omega_rad),
        Some(o.omega_dot_rad_s),
        Some(o.idot_rad_s),
        Some(o.delta_n_dot_rad_s2),
        Some(f64::from(c.ura_ned0_index)),
        Some(f64::from(c.ura_ned1_index)),
        Some(f64::from(c.ura_ed_index)),
        Some(health_number(c)),
        delay(|d| d.tgd_s),
        Some(f64::from(c.ura_ned2_index)),
        delay(|d| d.isc_l1ca_s),
        delay(|d| d.isc_l2c_s),
        delay(|d| d.isc_l5i5_s),
        delay(|d| d.isc_l5q5_s),
        Some(of_week(c.transmission_gps_s)),
        Some(week),
    ]
}

/// Line (relative to the epoch line) and column of value `index`.
fn place(index: usize) -> (usize, usize) {
    if index < 3 {
        (0, 23 + 19 * index)
    } else {
        (1 + (index - 3) / 4, 4 + 19 * ((index - 3) % 4))
    }
}

/// Reads the CNAV record whose epoch line is line `k` (the line after its
/// `> EPH Gnn CNAV` label); returns it and the line after it.
pub(super) fn parse_cnav_record(cur: &Cursor<'_>, k: usize) -> Result<(CnavEphemeris, usize)> {
    if cur.field(k, 0, 1) != "G" {
        return Err(cur.error(
            k,
            format!(
                "expected the epoch line of a GPS CNAV record ('Gnn yyyy mm dd hh mm ss'), got {:?}",
                cur.lines[k].get(..3).unwrap_or(cur.lines[k])
            ),
        ));
    }
    let prn = satellite_prn(cur, k, 'G', cur.integer(k, 1, 2, "satellite PRN")?)?;
    let sat = format!("G{prn:02}");
    let (year, month, day, hour, minute, second) = cur.rinex3_epoch(k)?;
    let toc = checked_gps_time_from_calendar(year, month, day, hour, minute, second)
        .map_err(|reason| cur.error(k, format!("epoch of {sat}: {reason}")))?;
    let mut values = [None; 33];
    for (index, value) in values.iter_mut().enumerate() {
        let (offset, column) = place(index);
        let line = k + offset;
        // An orbit line starts with 4 blanks; one whose fields are all
        // blank (line 7 when no ISC is available) may be cut to nothing.
        let is_continuation = offset == 0
            || (line < cur.lines.len()
                && !cur.lines[line].starts_with('>')
                && cur.field(line, 0, 4).is_empty());
        if !is_continuation {
            return Err(cur.error(
                line.min(cur.lines.len()),
                format!(
                    "truncated CNAV record for {sat} starting at line {}: expected broadcast orbit line {offset} of 8, got {}",
                    k + 1,
                    if line < cur.lines.len() { "a new record or a malformed line" } else { "end of file" }
                ),
            ));
        }
        *value = cur.optional_number(line, column, 19, CNAV_NAMES[index])?;
        let Some(v) = *value else {
            // Only the group delays may be blank ("not available").
            if matches!(index, 25 | 27..=30) {
                continue;
            }
            return Err(cur.error(
                line,
                format!(
                    "expected a value for {} for {sat}, the field is blank",
                    CNAV_NAMES[index]
                ),
            ));
        };
        if let Some(i) = lnav_index(index) {
            check_value(&sat, i, v).map_err(|reason| cur.error(line, reason))?;
        }
        if let Some((low, high)) = cnav_range(index) {
            if !(low..=high).contains(&v) || (is_integer(index) && v.fract() != 0.0) {
                return Err(cur.error(
                    line,
                    format!(
                        "{} = {v:e} for {sat} is out of range ({}{low:e} to {high:e}): not a value the navigation message can carry",
                        CNAV_NAMES[index],
                        if is_integer(index) { "an integer " } else { "" }
                    ),
                ));
            }
        }
    }
    let v = |index: usize| values[index].unwrap_or(0.0);
    // t_op is seconds of week WN_op; t_tm seconds of its own week, put
    // within half a week of t_oc (as the other records' t_oe).
    let top = v(32) * SECONDS_PER_WEEK + v(11);
    let transmission = v(31) + ((toc - v(31)) / SECONDS_PER_WEEK).round() * SECONDS_PER_WEEK;
    let health = v(24) as u8;
    let delays = [25, 27, 28, 29, 30].map(|i| values[i]);
    let group_delays = delays
        .iter()
        .any(Option::is_some)
        .then_some(CnavGroupDelays {
            tgd_s: delays[0],
            isc_l1ca_s: delays[1],
            isc_l2c_s: delays[2],
            isc_l5i5_s: delays[3],
            isc_l5q5_s: delays[4],
        });
    let orbit = BroadcastOrbit {
        toc_gps_s: toc,
        toe_gps_s: toc,
        af0_s: v(0),
        af1_s_s: v(1),
        af2_s_s2: v(2),
        crs_m: v(4),
        delta_n_rad_s: v(5),
        m0_rad: v(6),
        cuc_rad: v(7),
        eccentricity: v(8),
        cus_rad: v(9),
        sqrt_a_sqrt_m: v(10),
        cic_rad: v(12),
        omega0_rad: v(13),
        cis_rad: v(14),
        i0_rad: v(15),
        crc_m: v(16),
        omega_rad: v(17),
        omega_dot_rad_s: v(18),
        idot_rad_s: v(19),
        a_dot_m_s: v(3),
        delta_n_dot_rad_s2: v(20),
    };
    let ephemeris = CnavEphemeris {
        prn,
        orbit,
        l1_health: health >> 2 & 1,
        l2_health: health >> 1 & 1,
        l5_health: health & 1,
        ura_ed_index: v(23) as i8,
        ura_ned0_index: v(21) as i8,
        ura_ned1_index: v(22) as u8,
        ura_ned2_index: v(26) as u8,
        top_gps_s: top,
        week: (transmission / SECONDS_PER_WEEK).floor() as u16,
        // Not in the record (RINEX 4.00 table A32 has no place for them).
        integrity_status_flag: false,
        l2c_phasing: false,
        group_delays,
        transmission_gps_s: transmission,
    };
    Ok((ephemeris, k + 9))
}
