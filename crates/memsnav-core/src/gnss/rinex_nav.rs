//! RINEX 2.x, 3.x and 4.x navigation files: the GPS, Galileo (I/NAV) and
//! BeiDou broadcast ephemerides (RINEX 3.05 tables A6, A8, A14; RINEX 2
//! GPS `n` and 2.12 Galileo `e` files), the
//! GLONASS ones (RINEX 2 `g` files and RINEX 3 `R` records, read by
//! [`super::rinex_nav_glonass`]) and RINEX 4's GPS CNAV records
//! ([`super::rinex_nav_cnav`]); RINEX 4's record labels are read by
//! [`super::rinex4_nav`], its STO, EOP and ION records and other messages
//! (CNV2, BeiDou CNV1-3, ...) skipped with a count. Other systems in a mixed RINEX 3 file
//! (QZSS, SBAS, ...) and Galileo F/NAV records are skipped with a count.
//! Numbers may use Fortran `D` exponents. Every error names the file and
//! the 1-based line.

use std::collections::BTreeMap;
use std::path::Path;

use super::atmosphere::{parse_klobuchar, Klobuchar};
use super::beidou_ephemeris::BeidouEphemeris;
use super::broadcast_orbit::{BroadcastOrbit, BroadcastSystem, BEIDOU, GALILEO, GPS};
use super::broadcast_ranges::{self, BEIDOU_NAMES, GALILEO_NAMES, GPS_NAMES};
use super::cnav_ephemeris::{CnavEphemeris, CnavGroupDelays};
use super::ephemeris::{ura_index, GpsEphemeris};
use super::ephemeris_conflicts;
use super::galileo_ephemeris::{sisa_index, InavEphemeris};
use super::glonass_ephemeris::GlonassEphemeris;
use super::nav_record::NavRecord;
use super::rinex4_nav::{self, Rinex4Record};
use super::rinex_fields::{satellite_prn, Cursor};
use super::rinex_nav_cnav::parse_cnav_record;
use super::rinex_nav_glonass::parse_glonass_record;
use super::time::{checked_gps_time_from_calendar, SECONDS_PER_WEEK};
use crate::{Error, Result};

/// Reads every GPS ephemeris of a RINEX 2 or 3 navigation file, in file order.
///
/// One ephemeris per satellite and t_oc, and per satellite and issue of
/// data (`crate::gnss::ephemeris_conflicts`): a merged file (a daily
/// `brdc` gathered from many stations) may hold the same ephemeris more
/// than once, so a record whose values all equal an earlier one's of the
/// same satellite and t_oc, the transmission time apart, is kept once.
/// Records that disagree are all left out and counted in
/// [`BroadcastNav::skipped`]: choosing one would be a guess of which was
/// broadcast (and the ephemeris selection would silently take the first in
/// file order).
pub fn read_rinex_nav(path: impl AsRef<Path>) -> Result<Vec<GpsEphemeris>> {
    read_broadcast_nav(path).map(|nav| nav.gps)
}

/// One system's record layout.
struct Layout {
    /// The system's constants (its letter, its time).
    constants: &'static BroadcastSystem,
    names: &'static [&'static str],
    /// Values a file may leave blank (spares, flags, the fit interval).
    may_be_blank: &'static [usize],
}

const LAYOUTS: [Layout; 3] = [
    Layout {
        constants: &GPS,
        names: &GPS_NAMES,
        may_be_blank: &[3, 20, 22, 23, 26, 27, 28],
    },
    Layout {
        constants: &GALILEO,
        names: &GALILEO_NAMES,
        may_be_blank: &[22, 27],
    },
    Layout {
        constants: &BEIDOU,
        names: &BEIDOU_NAMES,
        may_be_blank: &[20, 22, 27],
    },
];

/// Line of value `index` in a record starting at line `start`: a_f0, a_f1,
/// a_f2 on the epoch line, then four a line.
fn value_line(start: usize, index: usize) -> usize {
    start + if index < 3 { 0 } else { 1 + (index - 3) / 4 }
}

/// Galileo data-source bits (RINEX 3.05 table A8): bit 8 says the clock
/// is F/NAV's (E5a,E1), bit 9 I/NAV's (E5b,E1).
const GALILEO_FNAV_CLOCK: u32 = 1 << 8;

/// The ephemerides of a RINEX navigation file, per system.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BroadcastNav {
    /// GPS ephemerides: the LNAV records and the CNAV ones that give an
    /// L1 C/A group delay ([`Self::gps_cnav`]).
    pub gps: Vec<GpsEphemeris>,
    /// Galileo I/NAV records (clock E5b,E1).
    pub galileo: Vec<InavEphemeris>,
    /// BeiDou records.
    pub beidou: Vec<BeidouEphemeris>,
    /// GLONASS ephemerides, one per slot and t_b.
    pub glonass: Vec<GlonassEphemeris>,
    /// GPS CNAV ephemerides (RINEX 4 `CNAV` records), one per satellite
    /// and t_oc; each with its L1 C/A group delay is also among
    /// [`Self::gps`] as [`CnavEphemeris::l1_ca_ephemeris`], as a UBX log's
    /// are ([`crate::logs::UbxLog::broadcast_nav`]).
    pub gps_cnav: Vec<CnavEphemeris>,
    /// GPS Klobuchar coefficients of the file's header (`ION ALPHA`/`ION
    /// BETA`, `IONOSPHERIC CORR GPSA`/`GPSB`) or of a log's CNAV message
    /// type 30; `None` without.
    pub klobuchar: Option<Klobuchar>,
    /// Each GPS satellite's latest CNAV group delays (message type 30), the
    /// inter-signal corrections a second signal needs, of the signals its
    /// ephemeris flags healthy
    /// ([`crate::gnss::CnavEphemeris::healthy_group_delays`]);
    /// empty from RINEX 3 files, whose LNAV records have T_GD alone.
    pub gps_group_delays: BTreeMap<u16, CnavGroupDelays>,
    /// Records not read, by reason, with counts (other systems; Galileo
    /// F/NAV records, whose clock is referred to E5a,E1; ephemerides in
    /// conflict, `crate::gnss::ephemeris_conflicts`, GLONASS's among
    /// them; a GLONASS record repeated with equal values).
    pub skipped: BTreeMap<String, usize>,
}

/// Reads the GPS, Galileo, BeiDou and GLONASS ephemerides of a RINEX 2 or
/// 3 navigation file (RINEX 2: GPS `n` and GLONASS `g` files); one per
/// satellite and t_oc as [`read_rinex_nav`] says.
pub fn read_broadcast_nav(path: impl AsRef<Path>) -> Result<BroadcastNav> {
    let path = path.as_ref();
    let text = std::fs::read(path).map_err(|e| Error::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    let text = String::from_utf8_lossy(&text);
    parse_broadcast_nav(&text, &path.display().to_string())
}

/// Parses the text of a RINEX 2 or 3 navigation file; `file` names it in
/// errors. GPS records only, repeated records as in [`read_rinex_nav`].
pub fn parse_rinex_nav(text: &str, file: &str) -> Result<Vec<GpsEphemeris>> {
    parse_broadcast_nav(text, file).map(|nav| nav.gps)
}

/// [`read_broadcast_nav`] of a text; `file` names it in errors.
pub fn parse_broadcast_nav(text: &str, file: &str) -> Result<BroadcastNav> {
    let cur = Cursor {
        file,
        lines: text.lines().collect(),
    };
    if cur.lines.is_empty() {
        return Err(cur.error(0, "empty file: expected a RINEX navigation header"));
    }
    // Header line 1: version (F9.2), file type at column 21, system at column 41 (v3).
    let first = cur.lines[0];
    if !first
        .get(60..)
        .unwrap_or("")
        .starts_with("RINEX VERSION / TYPE")
    {
        return Err(cur.error(
            0,
            "expected 'RINEX VERSION / TYPE' in columns 61-80: not a RINEX file",
        ));
    }
    let version = cur.number(0, 0, 9, "the RINEX version")?;
    let file_type = cur.field(0, 20, 1).to_string();
    let system = cur.field(0, 40, 1).to_string();
    let major = version.floor() as i64;
    // RINEX 2 GLONASS files are type G ("G: GLONASS NAV DATA"), RINEX
    // 2.12 Galileo files type E ("E: Galileo NAV DATA", table A13 of
    // 2.12: the GPS layout with Galileo's values).
    let glonass_file = major == 2 && file_type == "G";
    let galileo_file = major == 2 && file_type == "E";
    match major {
        2 if file_type == "N" || glonass_file || galileo_file => {}
        3 | 4 if file_type == "N" && matches!(system.as_str(), "G" | "E" | "C" | "R" | "M" | "") => {}
        2..=4 => {
            return Err(cur.error(
                0,
                format!("not a GPS, Galileo, BeiDou or GLONASS navigation file (type {file_type:?}, system {system:?}); expected type N with system G, E, C, R or M, or a RINEX 2 GLONASS (type G) or Galileo (type E) file"),
            ))
        }
        _ => return Err(cur.error(0, format!("unsupported RINEX version {version}; expected 2.x, 3.x or 4.x"))),
    }
    let mut k = 1;
    while k < cur.lines.len()
        && !cur.lines[k]
            .get(60..)
            .unwrap_or("")
            .starts_with("END OF HEADER")
    {
        k += 1;
    }
    if k == cur.lines.len() {
        return Err(cur.error(k.saturating_sub(1), "end of file before 'END OF HEADER'"));
    }
    k += 1;
    // A Galileo 2.12 file's ION ALPHA holds NeQuick's three coefficients,
    // not Klobuchar's; a GLONASS file has none.
    let klobuchar = if galileo_file || glonass_file {
        None
    } else {
        parse_klobuchar(text, file)?
    };
    let mut out = BroadcastNav {
        klobuchar,
        ..BroadcastNav::default()
    };

    // Field layout: RINEX 2 records start with I2 PRN + epoch (22 columns)
    // and orbit lines with 3 blanks; RINEX 3 with "Gnn" + epoch (23 columns)
    // and orbit lines with 4 blanks. Each value is 19 columns wide.
    let (epoch_width, indent) = if major == 2 { (22, 3) } else { (23, 4) };
    // Every ephemeris read, for the conflict rule.
    let mut records: Vec<NavRecord> = Vec::new();
    // GLONASS (slot, t_b) read with two sets of values: both left out.
    let mut glonass_conflicts: Vec<(u16, f64)> = Vec::new();
    // GPS CNAV records (RINEX 4), for their own conflict rule.
    let mut cnav_records: Vec<CnavEphemeris> = Vec::new();
    while k < cur.lines.len() {
        if cur.lines[k].trim().is_empty() {
            k += 1;
            continue;
        }
        if major == 4 {
            // Every RINEX 4 record opens with its label line.
            match rinex4_nav::record_label(&cur, k)? {
                Rinex4Record::Rinex3Layout(sat) => {
                    rinex4_nav::check_satellite(&cur, k + 1, &sat)?;
                    k += 1;
                }
                Rinex4Record::GpsCnav(sat) => {
                    rinex4_nav::check_satellite(&cur, k + 1, &sat)?;
                    let (eph, next) = parse_cnav_record(&cur, k + 1)?;
                    cnav_records.push(eph);
                    k = next;
                    continue;
                }
                Rinex4Record::Skipped(reason) => {
                    *out.skipped.entry(reason).or_default() += 1;
                    k = rinex4_nav::next_label(&cur, k);
                    continue;
                }
            }
        }
        let start = k;
        if glonass_file || (major > 2 && cur.field(k, 0, 1) == "R") {
            let (eph, next) = parse_glonass_record(&cur, k, major == 2)?;
            match out
                .glonass
                .iter()
                .find(|e| (e.slot, e.tb_gps_s) == (eph.slot, eph.tb_gps_s))
            {
                None => out.glonass.push(eph),
                Some(first) if *first == eph => {
                    *out.skipped
                        .entry("GLONASS records repeated (same slot, t_b and values)".into())
                        .or_default() += 1;
                }
                // One slot and t_b with other values: the reader cannot
                // tell which was broadcast, as with the other systems'
                // conflicts.
                Some(_) => glonass_conflicts.push((eph.slot, eph.tb_gps_s)),
            }
            k = next;
            continue;
        }
        let prn: u16;
        let (year, month, day, hour, minute, second);
        let layout: &Layout;
        if major == 2 {
            layout = &LAYOUTS[usize::from(galileo_file)];
            prn = satellite_prn(
                &cur,
                k,
                layout.constants.letter,
                cur.integer(k, 0, 2, "satellite PRN")?,
            )?;
            let yy = cur.integer(k, 2, 3, "year")?;
            year = if yy < 80 {
                2000 + yy
            } else if yy < 100 {
                1900 + yy
            } else {
                yy
            };
            month = cur.integer(k, 5, 3, "month")?;
            day = cur.integer(k, 8, 3, "day")?;
            hour = cur.integer(k, 11, 3, "hour")?;
            minute = cur.integer(k, 14, 3, "minute")?;
            second = cur.number(k, 17, 5, "second")?;
        } else {
            let sys = cur.field(k, 0, 1).to_string();
            let Some(found) = LAYOUTS.iter().find(|l| sys.starts_with(l.constants.letter)) else {
                // Another system: skip its continuation lines (they start with blanks).
                if sys.is_empty() || !sys.chars().all(|c| c.is_ascii_uppercase()) {
                    return Err(cur.error(k, format!("expected a satellite record starting with a system letter (G, E, R, C, J, S, I), got {:?}", cur.lines[k].get(..3).unwrap_or(cur.lines[k]))));
                }
                *out.skipped
                    .entry(format!("records of system {sys}"))
                    .or_default() += 1;
                k += 1;
                while k < cur.lines.len() && cur.lines[k].starts_with(' ') {
                    k += 1;
                }
                continue;
            };
            layout = found;
            prn = satellite_prn(
                &cur,
                k,
                layout.constants.letter,
                cur.integer(k, 1, 2, "satellite PRN")?,
            )?;
            (year, month, day, hour, minute, second) = cur.rinex3_epoch(k)?;
        }
        let sat = format!("{}{prn:02}", layout.constants.letter);
        let n = layout.names.len();
        // The epoch is t_oc in the system's time: GPS and GST calendars
        // agree; BDT = GPS − 14 s.
        let toc = checked_gps_time_from_calendar(year, month, day, hour, minute, second)
            .map_err(|reason| cur.error(k, format!("epoch of {sat}: {reason}")))?
            - layout.constants.time_minus_gps_s;
        let mut values = [0.0_f64; 29];
        let mut blank = [false; 29];
        for (j, (v, b)) in values.iter_mut().zip(blank.iter_mut()).enumerate().take(3) {
            let col = epoch_width + 19 * j;
            match cur.optional_number(k, col, 19, layout.names[j])? {
                Some(x) => *v = x,
                None => *b = true,
            }
        }
        let orbit_lines = (n - 3).div_ceil(4);
        for line in 1..=orbit_lines {
            let kk = start + line;
            let is_continuation = kk < cur.lines.len()
                && cur.lines[kk].len() > indent
                && cur.lines[kk]
                    .get(..indent)
                    .is_some_and(|s| s.trim().is_empty());
            if !is_continuation {
                let reason = format!(
                    "truncated record for {sat} starting at line {}: expected broadcast orbit line {line} of {orbit_lines}, got {}",
                    start + 1,
                    if kk < cur.lines.len() { "a new record or a malformed line" } else { "end of file" }
                );
                // Named by the 1-based line where the orbit line was expected
                // (one past the last line when the file ends early).
                return Err(Error::Parse {
                    file: file.to_string(),
                    line: kk + 1,
                    reason,
                });
            }
            for j in 0..4 {
                let index = 3 + 4 * (line - 1) + j;
                if index >= n {
                    break;
                }
                match cur.optional_number(kk, indent + 19 * j, 19, layout.names[index])? {
                    Some(x) => values[index] = x,
                    None => blank[index] = true,
                }
            }
        }
        if let Some(missing) = (0..n).find(|&i| blank[i] && !layout.may_be_blank.contains(&i)) {
            return Err(cur.error(
                value_line(start, missing),
                format!(
                    "expected a value for {} for {sat}, the field is blank",
                    layout.names[missing]
                ),
            ));
        }
        for (index, value) in values.iter().enumerate().take(n) {
            if !blank[index] {
                broadcast_ranges::check_value(&sat, index, *value)
                    .map_err(|reason| cur.error(value_line(start, index), reason))?;
            }
        }
        let next = start + 1 + orbit_lines;
        // t_oe is seconds of the system's week given in the record; put it
        // in the week that brings it within half a week of t_oc (handles
        // records whose week number belongs to t_oc across a week
        // boundary). RINEX's Galileo week is GPS-aligned (table A8), so it
        // goes as GPS's; BeiDou's is BDT's. The ranges above bound the
        // weeks to move by, so no loop is needed.
        let week_system = if layout.constants.letter == 'C' {
            &BEIDOU
        } else {
            &GPS
        };
        let toe = week_system.gps_time_s(values[21], values[11]);
        let toe = toe - ((toe - toc) / SECONDS_PER_WEEK).round() * SECONDS_PER_WEEK;
        let transmission = week_system.gps_time_s(values[21], values[27]);
        let orbit = BroadcastOrbit {
            toc_gps_s: toc,
            toe_gps_s: toe,
            af0_s: values[0],
            af1_s_s: values[1],
            af2_s_s2: values[2],
            crs_m: values[4],
            delta_n_rad_s: values[5],
            m0_rad: values[6],
            cuc_rad: values[7],
            eccentricity: values[8],
            cus_rad: values[9],
            sqrt_a_sqrt_m: values[10],
            cic_rad: values[12],
            omega0_rad: values[13],
            cis_rad: values[14],
            i0_rad: values[15],
            crc_m: values[16],
            omega_rad: values[17],
            omega_dot_rad_s: values[18],
            idot_rad_s: values[19],
            a_dot_m_s: 0.0,
            delta_n_dot_rad_s2: 0.0,
        };
        let sources = values[20] as u32;
        if layout.constants.letter == 'E' && sources & GALILEO_FNAV_CLOCK != 0 {
            *out.skipped
                .entry("Galileo F/NAV records (clock E5a,E1)".to_string())
                .or_default() += 1;
            k = next;
            continue;
        }
        records.push(NavRecord {
            sat,
            system: layout.constants,
            toc_gps_s: toc,
            toe_gps_s: toe,
            // BeiDou's AODE is an age, not a name; a blank IODE names nothing.
            issue_of_data: (layout.constants.letter != 'C' && !blank[3])
                .then_some(values[3] as u16),
            values: values[..n].to_vec(),
        });
        match layout.constants.letter {
            'E' => {
                {
                    // Health bits: 0 E1-B DVS, 1-2 E1-B HS, 6 E5b DVS, 7-8 E5b HS.
                    let health = values[24] as u32;
                    out.galileo.push(InavEphemeris {
                        svid: prn,
                        iod_nav: values[3] as u16,
                        orbit,
                        sisa_index: sisa_index(values[23]),
                        bgd_e1_e5a_s: values[25],
                        bgd_e1_e5b_s: values[26],
                        e1b_data_validity: (health & 1) as u8,
                        e1b_health: (health >> 1 & 3) as u8,
                        e5b_data_validity: (health >> 6 & 1) as u8,
                        e5b_health: (health >> 7 & 3) as u8,
                        gst_week: ((values[21] - GALILEO.week_zero_in_gps_weeks).rem_euclid(4096.0))
                            as u16,
                        transmission_gps_s: transmission,
                    });
                }
            }
            'C' => out.beidou.push(BeidouEphemeris {
                prn,
                aode: values[3] as u8,
                aodc: values[28] as u8,
                orbit,
                urai: ura_index(values[23]),
                sat_h1: values[24] as u8,
                tgd1_s: values[25],
                tgd2_s: values[26],
                bdt_week: values[21] as u16,
                transmission_gps_s: transmission,
            }),
            _ => out.gps.push(GpsEphemeris {
                prn,
                orbit,
                health: values[24] as u32,
                tgd_s: values[25],
                fit_interval_h: if blank[28] || values[28] == 0.0 {
                    4.0
                } else {
                    values[28]
                },
            }),
        }
        k = next;
    }
    out.gps_cnav = cnav_unique(cnav_records, &mut out.skipped);
    out.gps.extend(
        out.gps_cnav
            .iter()
            .filter_map(CnavEphemeris::l1_ca_ephemeris),
    );
    for c in &out.gps_cnav {
        if let Some(delays) = c.healthy_group_delays() {
            // The file's last record of a satellite is its latest.
            out.gps_group_delays.insert(c.prn, delays);
        }
    }
    let (keep, conflicts) = ephemeris_conflicts::resolve(&records);
    retain_kept(&mut out.gps, &records, &keep, 'G');
    retain_kept(&mut out.galileo, &records, &keep, 'E');
    retain_kept(&mut out.beidou, &records, &keep, 'C');
    for (reason, count) in conflicts {
        *out.skipped.entry(reason).or_default() += count;
    }
    let glonass_read = out.glonass.len();
    out.glonass
        .retain(|e| !glonass_conflicts.contains(&(e.slot, e.tb_gps_s)));
    if glonass_read > out.glonass.len() {
        // Each kept first record and every other one of its (slot, t_b).
        *out.skipped
            .entry("GLONASS ephemerides in conflict (one slot and t_b, other values)".into())
            .or_default() += glonass_read - out.glonass.len() + glonass_conflicts.len();
    }
    Ok(out)
}

/// One CNAV ephemeris per satellite and t_oc: a record repeated with equal
/// values (the transmission time apart) is kept once and counted; records
/// of one satellite and t_oc that disagree are all left out and counted,
/// as the other systems' conflicts ([`crate::gnss::ephemeris_conflicts`]).
fn cnav_unique(
    records: Vec<CnavEphemeris>,
    skipped: &mut BTreeMap<String, usize>,
) -> Vec<CnavEphemeris> {
    let key = |c: &CnavEphemeris| (c.prn, c.orbit.toc_gps_s.to_bits());
    let same = |a: &CnavEphemeris, b: &CnavEphemeris| {
        CnavEphemeris {
            transmission_gps_s: 0.0,
            ..*a
        } == CnavEphemeris {
            transmission_gps_s: 0.0,
            ..*b
        }
    };
    let mut kept: Vec<CnavEphemeris> = Vec::new();
    let mut conflicting: Vec<(u16, u64)> = Vec::new();
    for c in records {
        match kept.iter().find(|k| key(k) == key(&c)) {
            None => kept.push(c),
            Some(first) if same(first, &c) => {
                *skipped
                    .entry("GPS CNAV records repeated (same satellite, t_oc and values)".into())
                    .or_default() += 1;
            }
            Some(_) => {
                conflicting.push(key(&c));
                *skipped
                    .entry(
                        "GPS CNAV ephemerides in conflict (one satellite and t_oc, other values)"
                            .into(),
                    )
                    .or_default() += 1;
            }
        }
    }
    let before = kept.len();
    kept.retain(|c| !conflicting.contains(&key(c)));
    if before > kept.len() {
        *skipped
            .entry("GPS CNAV ephemerides in conflict (one satellite and t_oc, other values)".into())
            .or_default() += before - kept.len();
    }
    kept
}

/// Keeps the ephemerides of system `letter` (in the order of its records
/// among `records`) whose flag in `keep` is set.
fn retain_kept<T>(list: &mut Vec<T>, records: &[NavRecord], keep: &[bool], letter: char) {
    let mut flags = records
        .iter()
        .zip(keep)
        .filter(|(r, _)| r.system.letter == letter)
        .map(|(_, &k)| k);
    list.retain(|_| flags.next().unwrap_or(true));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The header and first record of `tests/data/real-imu-gnss/walk.nav`.
    const HEADER: &str =
        "     3.04           N: GNSS NAV DATA    M: Mixed            RINEX VERSION / TYPE
                                        20261121 045512 UTC PGM / RUN BY / DATE 
format: u-blox UBX                                          COMMENT             
log: gnss_1730.ubx                                          COMMENT             
                                                            END OF HEADER       
";
    const G32: &str =
        "G32 2025 08 28 18 00 00 -.344484578818D-03  .131876731757D-10  .000000000000D+00
      .830000000000D+02 -.167812500000D+02  .471448209139D-08  .273480178381D+01
     -.897794961929D-06  .863428541925D-02  .561214983463D-05  .515364527702D+04
      .410400000000D+06  .111758708954D-07  .224492021439D+01 -.162050127983D-06
      .965781992719D+00  .271718750000D+03 -.206125929204D+01 -.795997442203D-08
      .971469037013D-10  .100000000000D+01  .238100000000D+04  .000000000000D+00
      .200000000000D+01  .000000000000D+00  .931322574615D-09  .830000000000D+02
      .408756000000D+06  .400000000000D+01
";

    #[test]
    fn one_ephemeris_per_satellite_and_toc() {
        let once = parse_rinex_nav(&format!("{HEADER}{G32}"), "x.nav").unwrap();
        assert_eq!(once.len(), 1);
        // The same record again, or received at another time (a merged
        // file): kept once.
        let later = G32.replace(".408756000000D+06", ".408700000000D+06");
        for copy in [G32, later.as_str()] {
            let twice = parse_rinex_nav(&format!("{HEADER}{G32}{copy}"), "x.nav").unwrap();
            assert_eq!(twice, once);
        }
        // Another t_oc is another ephemeris.
        let next = G32.replacen("18 00 00", "20 00 00", 1);
        let two = parse_rinex_nav(&format!("{HEADER}{G32}{next}"), "x.nav").unwrap();
        assert_eq!(two.len(), 2);
        // A different Crs for the same t_oc: neither used, both counted.
        let other = G32.replace("-.167812500000D+02", "-.167800000000D+02");
        let nav = parse_broadcast_nav(&format!("{HEADER}{G32}{other}"), "x.nav").unwrap();
        assert!(nav.gps.is_empty());
        assert_eq!(nav.skipped[ephemeris_conflicts::SAME_TOC], 2);
        // The same IODE with a t_oe 2 h later (and another t_oc): the
        // issue of data names two sets; neither used.
        let moved = next.replace(".410400000000D+06", ".417600000000D+06");
        let nav = parse_broadcast_nav(&format!("{HEADER}{G32}{moved}"), "x.nav").unwrap();
        assert!(nav.gps.is_empty());
        assert_eq!(nav.skipped[ephemeris_conflicts::SAME_ISSUE_OF_DATA], 2);
    }

    /// C21's record of the same file (BDT epoch and week).
    const C21: &str =
        "C21 2025 08 28 17 00 00 -.963445054367D-03 -.684696743747D-11  .000000000000D+00
      .100000000000D+01 -.350000000000D+01  .365943814457D-08  .886304528107D+00
     -.133644789457D-06  .556349870749D-03  .667152926326D-05  .528262655258D+04
      .406800000000D+06  .451691448689D-07  .175064384011D+01 -.521540641785D-07
      .983854657381D+00  .238250000000D+03  .596217207868D-01 -.666063458502D-08
      .367515308488D-09  .000000000000D+00  .102500000000D+04  .000000000000D+00
      .200000000000D+01  .000000000000D+00  .133000000000D-07  .133000000000D-07
      .408630000000D+06  .100000000000D+01
";

    #[test]
    fn beidou_records_are_on_bdt_and_checked_against_their_own_ranges() {
        let nav = parse_broadcast_nav(&format!("{HEADER}{G32}{C21}"), "x.nav").unwrap();
        assert_eq!((nav.gps.len(), nav.beidou.len()), (1, 1));
        let c = nav.beidou[0];
        // The epoch 17:00:00 BDT is 17:00:14 GPS; t_oe 406 800 s of BDT
        // week 1025 is the same instant.
        let epoch_gps = checked_gps_time_from_calendar(2025, 8, 28, 17, 0, 14.0).unwrap();
        assert_eq!(
            (c.orbit.toc_gps_s, c.orbit.toe_gps_s),
            (epoch_gps, epoch_gps)
        );
        assert_eq!(BEIDOU.seconds_of_week(c.orbit.toe_gps_s), 406_800.0);
        assert_eq!(
            (c.prn, c.aode, c.aodc, c.bdt_week, c.urai),
            (21, 1, 1, 1025, 0)
        );
        assert_eq!((c.tgd1_s, c.tgd2_s), (0.133e-7, 0.133e-7));
        // The GPS reader alone still gives the GPS record.
        assert_eq!(
            parse_rinex_nav(&format!("{HEADER}{G32}{C21}"), "x.nav").unwrap(),
            nav.gps
        );
        // TGD1 beyond its 10 bits × 0.1 ns is refused, named by system.
        let bad = C21.replace(".133000000000D-07  .133", ".133000000000D-05  .133");
        let e = parse_broadcast_nav(&format!("{HEADER}{bad}"), "x.nav").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("x.nav:12: TGD1 = 1.33e-6 for C21 is out of range"),
            "{e}"
        );
        // A BeiDou Crs of 2000 m fits 18 bits × 2⁻⁶; a GPS one does not.
        let wide = C21.replace("-.350000000000D+01", "-.200000000000D+04");
        assert!(parse_broadcast_nav(&format!("{HEADER}{wide}"), "x.nav").is_ok());
        let wide = G32.replace("-.167812500000D+02", "-.200000000000D+04");
        assert!(parse_broadcast_nav(&format!("{HEADER}{wide}"), "x.nav").is_err());
    }

    #[test]
    fn galileo_fnav_and_other_systems_are_counted() {
        // C21's numbers as a Galileo record (its last line holds only the
        // transmission time): I/NAV data sources 513, then F/NAV 258.
        let inav = C21
            .replacen("C21", "E21", 1)
            .replace(
                " .000000000000D+00  .102500000000D+04  .000000000000D+00",
                " .513000000000D+03  .238100000000D+04  .000000000000D+00",
            )
            .replace(
                " .408630000000D+06  .100000000000D+01",
                " .408630000000D+06",
            );
        let fnav = inav.replace(".513000000000D+03", ".258000000000D+03");
        // The same I/NAV ephemeris received on E5b (data sources 516): kept once.
        let e5b = inav.replace(".513000000000D+03", ".516000000000D+03");
        let qzss = "J05 2025 08 28 17 15 00  .1D-03  .0D+00  .0D+00
     .1D+05  .0D+00  .0D+00  .0D+00
     .1D+05  .0D+00  .0D+00  .1D+01
     .1D+05  .0D+00  .0D+00  .0D+00
";
        let nav =
            parse_broadcast_nav(&format!("{HEADER}{inav}{fnav}{e5b}{qzss}"), "x.nav").unwrap();
        assert_eq!(nav.galileo.len(), 1);
        let e = nav.galileo[0];
        // Galileo epochs are GST, GPS-aligned: no 14 s.
        let epoch_gps = checked_gps_time_from_calendar(2025, 8, 28, 17, 0, 0.0).unwrap();
        assert_eq!(
            (e.svid, e.iod_nav, e.gst_week, e.orbit.toc_gps_s),
            (21, 1, 1357, epoch_gps)
        );
        assert_eq!(nav.skipped["Galileo F/NAV records (clock E5a,E1)"], 1);
        assert_eq!(nav.skipped["records of system J"], 1);
    }
}
