//! RINEX 3.04 writers (IGS/RTCM "RINEX 3.04", 2018, appendix A1-A4 for
//! observation files, A5-A6, A8 and A14 for GPS, Galileo and BeiDou
//! navigation messages): what the readers
//! of this module read, so a receiver's raw log (`memsnav convert`) serves
//! other tools too.
//!
//! Not written: `SYS / PHASE SHIFT` (the quarter-cycle alignment of phases
//! between signals is not known from a raw log) and the GLONASS header
//! records (`GLONASS SLOT / FRQ #`, `COD/PHS/BIS`), so files holding
//! GLONASS phase are not complete for GLONASS.

use std::fmt::Write as _;
use std::path::Path;

use super::beidou_ephemeris::BeidouEphemeris;
use super::broadcast_orbit::{BroadcastOrbit, BroadcastSystem, BEIDOU, GALILEO, GPS};
use super::ephemeris::{ura_m, LnavEphemeris};
use super::galileo_ephemeris::{sisa_m, InavEphemeris};
use super::rinex_obs::ObservationFile;
use super::time::{calendar_from_gps_time, SECONDS_PER_WEEK};
use crate::{Error, Result};

/// GPS time − Unix time at 1980-01-06 00:00:00, s (UTC without leap seconds).
const UNIX_AT_GPS_EPOCH_S: u64 = 315_964_800;

/// Who wrote a file and from what: the `PGM / RUN BY / DATE` record and
/// `COMMENT` lines of the header.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RinexProvenance {
    /// Program name and version (20 characters kept).
    pub program: String,
    /// The receiver type for `REC # / TYPE / VERS` (20 characters kept).
    pub receiver: String,
    /// Creation time `yyyymmdd hhmmss UTC`; empty: the time of writing.
    pub created: String,
    /// Header comments, 60 characters a line.
    pub comments: Vec<String>,
}

impl RinexProvenance {
    fn created(&self) -> String {
        if !self.created.is_empty() {
            return self.created.clone();
        }
        let unix_s = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        // Seconds since the GPS epoch without leap seconds is UTC on the
        // same calendar (Unix time ignores leap seconds too).
        let (y, mo, d, h, mi, s) =
            calendar_from_gps_time(unix_s.saturating_sub(UNIX_AT_GPS_EPOCH_S) as f64);
        format!("{y:04}{mo:02}{d:02} {h:02}{mi:02}{:02} UTC", s as u32)
    }
}

/// One header record: 60 columns of contents, then the label.
fn record(out: &mut String, contents: &str, label: &str) {
    let contents: String = contents.chars().take(60).collect();
    let _ = writeln!(out, "{contents:<60}{label}");
}

fn provenance_records(out: &mut String, provenance: &RinexProvenance) {
    let cut = |s: &str| s.chars().take(20).collect::<String>();
    record(
        out,
        &format!(
            "{:<20}{:<20}{:<20}",
            cut(&provenance.program),
            "",
            provenance.created()
        ),
        "PGM / RUN BY / DATE",
    );
    for c in &provenance.comments {
        for chunk in c.chars().collect::<Vec<_>>().chunks(60) {
            record(out, &chunk.iter().collect::<String>(), "COMMENT");
        }
    }
}

/// A GPS time rounded to 1 µs as calendar fields (written in the F11.7
/// seconds of the epoch records): near 1.4e9 s an f64 GPS time holds
/// 0.24 µs, so a seventh decimal would print rounding noise (a receiver
/// epoch at .748 s coming out as .7479999). The whole seconds are split
/// off first, so rounding never shows 60 s.
fn epoch_fields(gps_time_s: f64) -> (i64, i64, i64, i64, i64, f64) {
    let mut whole = gps_time_s.floor();
    let mut micros = ((gps_time_s - whole) * 1e6).round();
    if micros >= 1e6 {
        whole += 1.0;
        micros = 0.0;
    }
    let (y, mo, d, h, mi, s) = calendar_from_gps_time(whole);
    (y, mo, d, h, mi, s.round() + micros * 1e-6)
}

/// The text of a RINEX 3.04 observation file holding `observations`
/// (every system and observation type they declare; satellites with no
/// value at an epoch left out; the loss-of-lock indicator written, the
/// signal-strength digit left blank since `S` observations carry it).
/// Values must lie in the ranges the reader accepts (F14.3 fields).
pub fn format_rinex_obs(observations: &ObservationFile, provenance: &RinexProvenance) -> String {
    let mut out = String::new();
    let system = match observations.observation_types.keys().collect::<Vec<_>>()[..] {
        [&only] => only,
        _ => 'M',
    };
    record(
        &mut out,
        &format!(
            "{:>9.2}{:11}{:<20}{system:<20}",
            3.04, "", "OBSERVATION DATA"
        ),
        "RINEX VERSION / TYPE",
    );
    provenance_records(&mut out, provenance);
    record(&mut out, "", "MARKER NAME");
    record(&mut out, "", "OBSERVER / AGENCY");
    let receiver: String = provenance.receiver.chars().take(20).collect();
    record(
        &mut out,
        &format!("{:<20}{receiver:<20}", ""),
        "REC # / TYPE / VERS",
    );
    record(&mut out, "", "ANT # / TYPE");
    let p = observations.approx_position_ecef.unwrap_or_default();
    record(
        &mut out,
        &format!("{:14.4}{:14.4}{:14.4}", p.x, p.y, p.z),
        "APPROX POSITION XYZ",
    );
    record(
        &mut out,
        &format!("{:14.4}{:14.4}{:14.4}", 0.0, 0.0, 0.0),
        "ANTENNA: DELTA H/E/N",
    );
    for (sys, types) in &observations.observation_types {
        // A1, 2X, I3, 13(1X, A3); continuation lines 6X, 13(1X, A3).
        for (k, chunk) in types.chunks(13).enumerate() {
            let mut line = if k == 0 {
                format!("{sys}  {:3}", types.len())
            } else {
                " ".repeat(6)
            };
            for code in chunk {
                let _ = write!(line, " {code:3}");
            }
            record(&mut out, &line, "SYS / # / OBS TYPES");
        }
    }
    record(&mut out, "DBHZ", "SIGNAL STRENGTH UNIT");
    if let Some(first) = observations.epochs.first() {
        let (y, mo, d, h, mi, s) = epoch_fields(first.gps_time_s);
        record(
            &mut out,
            &format!("{y:6}{mo:6}{d:6}{h:6}{mi:6}{s:13.7}     GPS"),
            "TIME OF FIRST OBS",
        );
    }
    record(&mut out, "", "END OF HEADER");
    for epoch in &observations.epochs {
        let satellites: Vec<_> = epoch
            .satellites
            .iter()
            .filter(|s| s.values.iter().any(Option::is_some))
            .collect();
        let (y, mo, d, h, mi, s) = epoch_fields(epoch.gps_time_s);
        let _ = writeln!(
            out,
            "> {y:04} {mo:02} {d:02} {h:02} {mi:02}{s:11.7}  {}{:3}",
            epoch.flag,
            satellites.len()
        );
        for sat in satellites {
            let mut line = format!("{}{:02}", sat.system, sat.prn);
            for (value, lli) in sat.values.iter().zip(&sat.lli) {
                match value {
                    Some(v) => {
                        let lli = if *lli == 0 {
                            ' '
                        } else {
                            char::from(b'0' + lli % 10)
                        };
                        let _ = write!(line, "{v:14.3}{lli} ");
                    }
                    None => line.push_str(&" ".repeat(16)),
                }
            }
            let _ = writeln!(out, "{}", line.trim_end());
        }
    }
    out
}

/// A number in the D19.12 field of navigation records, with an `E`
/// exponent of two digits (` 1.234567890123E-05`).
fn d19(x: f64) -> String {
    let text = format!("{x:.12E}");
    let (mantissa, exponent) = text.split_once('E').expect("{:E} has an exponent");
    let exponent: i32 = exponent.parse().expect("an integer exponent");
    let sign = if exponent < 0 { '-' } else { '+' };
    format!("{mantissa:>15}E{sign}{:02}", exponent.abs())
}

/// The first line of a navigation record: satellite, t_oc, clock terms.
fn nav_epoch_line(out: &mut String, sat: &str, toc_gps_s: f64, clock: [f64; 3]) {
    let (y, mo, d, h, mi, s) = epoch_fields(toc_gps_s);
    let _ = writeln!(
        out,
        "{sat} {y:04} {mo:02} {d:02} {h:02} {mi:02} {:02}{}",
        s.round() as i64,
        clock.iter().map(|&x| d19(x)).collect::<String>()
    );
}

/// The four lines of orbit values every Keplerian record shares (RINEX
/// 3.04 tables A6, A8, A14, lines 1-4): the issue of data first, t_oe as
/// seconds of its week.
fn kepler_rows(issue_of_data: f64, o: &BroadcastOrbit, toe_seconds_of_week: f64) -> [[f64; 4]; 4] {
    [
        [issue_of_data, o.crs_m, o.delta_n_rad_s, o.m0_rad],
        [o.cuc_rad, o.eccentricity, o.cus_rad, o.sqrt_a_sqrt_m],
        [toe_seconds_of_week, o.cic_rad, o.omega0_rad, o.cis_rad],
        [o.i0_rad, o.crc_m, o.omega_rad, o.omega_dot_rad_s],
    ]
}

/// One record: the epoch line (t_oc in the system's time, the clock
/// polynomial), the Kepler rows and the system's last three lines.
fn nav_record(
    out: &mut String,
    sat: &str,
    system: &BroadcastSystem,
    o: &BroadcastOrbit,
    kepler: [[f64; 4]; 4],
    tail: [&[f64]; 3],
) {
    nav_epoch_line(
        out,
        sat,
        o.toc_gps_s + system.time_minus_gps_s,
        [o.af0_s, o.af1_s_s, o.af2_s_s2],
    );
    let rows = kepler.iter().map(|r| &r[..]).chain(tail);
    for row in rows {
        let _ = writeln!(
            out,
            "    {}",
            row.iter().map(|&x| d19(x)).collect::<String>()
        );
    }
}

/// The text of a RINEX 3.04 navigation file holding GPS LNAV (table A6),
/// Galileo I/NAV (table A8) and BeiDou D1 (table A14) ephemerides: t_oc as
/// the epoch (in BDT for BeiDou), angles in rad, GPS and Galileo weeks
/// continuous and aligned with GPS weeks, BeiDou's BDT weeks, t_oe and the
/// transmission time in seconds of the t_oe week.
pub fn format_rinex_nav(
    gps: &[LnavEphemeris],
    galileo: &[InavEphemeris],
    beidou: &[BeidouEphemeris],
    provenance: &RinexProvenance,
) -> String {
    let mut out = String::new();
    let present: Vec<&str> = [
        (!gps.is_empty(), "G: GPS"),
        (!galileo.is_empty(), "E: Galileo"),
        (!beidou.is_empty(), "C: BeiDou"),
    ]
    .iter()
    .filter_map(|&(p, name)| p.then_some(name))
    .collect();
    let system = match present[..] {
        [] => "G: GPS",
        [one] => one,
        _ => "M: Mixed",
    };
    record(
        &mut out,
        &format!(
            "{:>9.2}{:11}{:<20}{system:<20}",
            3.04, "", "N: GNSS NAV DATA"
        ),
        "RINEX VERSION / TYPE",
    );
    provenance_records(&mut out, provenance);
    record(&mut out, "", "END OF HEADER");
    for l in gps {
        let e = &l.ephemeris;
        let o = &e.orbit;
        let week_start = f64::from(l.toe_week) * SECONDS_PER_WEEK;
        nav_record(
            &mut out,
            &format!("G{:02}", e.prn),
            &GPS,
            o,
            kepler_rows(f64::from(l.iode), o, o.toe_gps_s - week_start),
            [
                &[
                    o.idot_rad_s,
                    f64::from(l.l2_codes),
                    f64::from(l.toe_week),
                    f64::from(u8::from(l.l2p_data_flag)),
                ],
                &[
                    ura_m(l.ura_index),
                    f64::from(e.health),
                    e.tgd_s,
                    f64::from(l.iodc),
                ],
                &[l.transmission_gps_s - week_start, e.fit_interval_h],
            ],
        );
    }
    for e in galileo {
        let o = &e.orbit;
        let toe_week = (o.toe_gps_s / SECONDS_PER_WEEK).floor();
        let week_start = toe_week * SECONDS_PER_WEEK;
        // Data sources: bit 0 I/NAV E1-B, bit 9 clock for E5b,E1 (table A8).
        let sources = 1.0 + 512.0;
        // Health bits: 0 E1-B DVS, 1-2 E1-B HS, 6 E5b DVS, 7-8 E5b HS.
        let health = u32::from(e.e1b_data_validity)
            | u32::from(e.e1b_health) << 1
            | u32::from(e.e5b_data_validity) << 6
            | u32::from(e.e5b_health) << 7;
        nav_record(
            &mut out,
            &format!("E{:02}", e.svid),
            &GALILEO,
            o,
            kepler_rows(f64::from(e.iod_nav), o, o.toe_gps_s - week_start),
            [
                &[o.idot_rad_s, sources, toe_week, 0.0],
                &[
                    sisa_m(e.sisa_index).unwrap_or(-1.0),
                    f64::from(health),
                    e.bgd_e1_e5a_s,
                    e.bgd_e1_e5b_s,
                ],
                &[e.transmission_gps_s - week_start],
            ],
        );
    }
    for e in beidou {
        let o = &e.orbit;
        let toe_week = BEIDOU.week(o.toe_gps_s);
        let week_start = BEIDOU.gps_time_s(toe_week, 0.0);
        nav_record(
            &mut out,
            &format!("C{:02}", e.prn),
            &BEIDOU,
            o,
            kepler_rows(f64::from(e.aode), o, o.toe_gps_s - week_start),
            [
                &[o.idot_rad_s, 0.0, toe_week, 0.0],
                &[ura_m(e.urai), f64::from(e.sat_h1), e.tgd1_s, e.tgd2_s],
                &[e.transmission_gps_s - week_start, f64::from(e.aodc)],
            ],
        );
    }
    out
}

fn write_text(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).map_err(|e| Error::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    })
}

/// Writes [`format_rinex_obs`] to `path`.
pub fn write_rinex_obs(
    path: impl AsRef<Path>,
    observations: &ObservationFile,
    provenance: &RinexProvenance,
) -> Result<()> {
    write_text(path.as_ref(), &format_rinex_obs(observations, provenance))
}

/// Writes [`format_rinex_nav`] to `path`.
pub fn write_rinex_nav(
    path: impl AsRef<Path>,
    gps: &[LnavEphemeris],
    galileo: &[InavEphemeris],
    beidou: &[BeidouEphemeris],
    provenance: &RinexProvenance,
) -> Result<()> {
    write_text(
        path.as_ref(),
        &format_rinex_nav(gps, galileo, beidou, provenance),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gnss::{parse_rinex_obs, ObservationEpoch, SatelliteObservations};
    use std::collections::BTreeMap;

    #[test]
    fn d19_fields() {
        assert_eq!(d19(-5.162092857062817e-4), "-5.162092857063E-04");
        assert_eq!(d19(0.0), " 0.000000000000E+00");
        assert_eq!(d19(5153.649108886719), " 5.153649108887E+03");
        assert_eq!(d19(1.0e-12).len(), 19);
    }

    #[test]
    fn epoch_rounding_never_shows_sixty_seconds() {
        let t = 1_440_437_459.999_999_7;
        let (.., mi, s) = epoch_fields(t);
        assert_eq!((mi, s), (31, 0.0));
        let (.., s) = epoch_fields(1_440_437_439.748);
        assert_eq!(format!("{s:11.7}"), " 39.7480000");
    }

    #[test]
    fn observations_round_trip_through_the_reader() {
        let types: BTreeMap<char, Vec<String>> = [
            ('G', ["C1C", "L1C", "D1C", "S1C"].map(String::from).to_vec()),
            (
                'E',
                (0..15u8)
                    .map(|k| format!("C{}{}", k / 10 + 1, char::from(b'A' + k % 10)))
                    .collect(),
            ),
        ]
        .into();
        let sat = |system, prn, values: Vec<Option<f64>>, lli: Vec<u8>| SatelliteObservations {
            system,
            prn,
            values,
            lli,
        };
        let obs = ObservationFile {
            version: 3.04,
            observation_types: types,
            approx_position_ecef: Some(nalgebra::Vector3::new(-1.2e6, -4.7e6, 4.1e6)),
            epochs: vec![ObservationEpoch {
                gps_time_s: 1_440_437_478.748_5,
                flag: 0,
                satellites: vec![
                    sat(
                        'G',
                        10,
                        vec![Some(2.1e7), Some(-1.25e8), None, Some(44.0)],
                        vec![0, 3, 0, 0],
                    ),
                    sat(
                        'E',
                        7,
                        (0..15).map(|k| Some(f64::from(k) + 0.125)).collect(),
                        vec![0; 15],
                    ),
                    sat('G', 11, vec![None; 4], vec![0; 4]),
                ],
            }],
            warnings: vec![],
            skipped: Default::default(),
        };
        let text = format_rinex_obs(&obs, &RinexProvenance::default());
        let back = parse_rinex_obs(&text, "written").unwrap();
        assert_eq!(back.observation_types, obs.observation_types);
        assert_eq!(back.approx_position_ecef, obs.approx_position_ecef);
        assert!((back.epochs[0].gps_time_s - obs.epochs[0].gps_time_s).abs() < 1e-6);
        // The satellite with no value is left out.
        assert_eq!(back.epochs[0].satellites, obs.epochs[0].satellites[..2]);
    }
}
