//! RINEX 3.04 writers (IGS/RTCM "RINEX 3.04", 2018, appendix A1-A4 for
//! observation files, A5-A6, A8 and A14 for GPS, Galileo and BeiDou
//! navigation messages) and the RINEX 4.00 navigation writer (IGS/RTCM
//! "RINEX 4.00", 2021: the same records labelled, and GPS CNAV's, table
//! A32): what the readers
//! of this module read, so a receiver's raw log (`memsnav convert`) serves
//! other tools too.
//!
//! Not written: `SYS / PHASE SHIFT` (the quarter-cycle alignment of phases
//! between signals is not known from a raw log) and `GLONASS COD/PHS/BIS`,
//! so files holding GLONASS phase are not complete for GLONASS; `GLONASS
//! SLOT / FRQ #` is written in files with GLONASS.

use std::fmt::Write as _;
use std::path::Path;

use super::beidou_ephemeris::BeidouEphemeris;
use super::cnav_ephemeris::CnavEphemeris;
use super::ephemeris::LnavEphemeris;
use super::galileo_ephemeris::InavEphemeris;
use super::glonass_ephemeris::GlonassEphemeris;
use super::glonass_slots::slot_lines;
use super::nav_record::NavRecord;
use super::observation_file::ObservationFile;
use super::rinex_nav::parse_broadcast_nav;
use super::rinex_nav_cnav::cnav_values;
use super::rinex_obs::parse_rinex_obs;
use super::time::{calendar_from_gps_time, gps_minus_utc_s, SECONDS_PER_WEEK};
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
    if observations.observation_types.contains_key(&'R') {
        // RINEX 3.04 table A2: required in files with GLONASS.
        for line in slot_lines(&observations.glonass_channels) {
            record(&mut out, &line, "GLONASS SLOT / FRQ #");
        }
    }
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

/// One record: the epoch line (t_oc in the system's time, the clock
/// polynomial), then the orbit lines, four values a line.
fn nav_record(out: &mut String, r: &NavRecord) {
    nav_epoch_line(
        out,
        &r.sat,
        r.toc_gps_s + r.system.time_minus_gps_s,
        [r.values[0], r.values[1], r.values[2]],
    );
    for row in r.values[3..].chunks(4) {
        let _ = writeln!(
            out,
            "    {}",
            row.iter().map(|&x| d19(x)).collect::<String>()
        );
    }
}

/// The RINEX version of a navigation file memsnav writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RinexNavVersion {
    /// RINEX 3.04: GPS LNAV, Galileo I/NAV and BeiDou D1 records; GPS
    /// CNAV ephemerides have no record and are left out.
    V3_04,
    /// RINEX 4.00 (the default): every record labelled `> EPH <sat>
    /// <message>`, GPS CNAV among them (table A32).
    #[default]
    V4_00,
}

impl RinexNavVersion {
    /// The version named `"3.04"` or `"4.00"` (`argument` names the value
    /// in the error).
    pub fn parse(text: &str, argument: &str) -> Result<Self> {
        match text.trim() {
            "3.04" => Ok(Self::V3_04),
            "4.00" | "4.0" | "4" => Ok(Self::V4_00),
            other => Err(Error::invalid(
                argument,
                format!("RINEX navigation version {other:?} is not written; expected \"4.00\" (the default) or \"3.04\""),
            )),
        }
    }

    fn number(self) -> f64 {
        match self {
            Self::V3_04 => 3.04,
            Self::V4_00 => 4.00,
        }
    }
}

/// The ephemerides a navigation file is written from, per system and message.
#[derive(Debug, Clone, Copy, Default)]
pub struct NavFileEphemerides<'a> {
    /// GPS LNAV ephemerides.
    pub gps_lnav: &'a [LnavEphemeris],
    /// GPS CNAV ephemerides.
    pub gps_cnav: &'a [CnavEphemeris],
    /// Galileo I/NAV ephemerides.
    pub galileo: &'a [InavEphemeris],
    /// BeiDou ephemerides.
    pub beidou: &'a [BeidouEphemeris],
    /// GLONASS ephemerides.
    pub glonass: &'a [GlonassEphemeris],
}

impl NavFileEphemerides<'_> {
    /// The number of records a file of `version` holds.
    pub fn records(&self, version: RinexNavVersion) -> usize {
        let cnav = match version {
            RinexNavVersion::V3_04 => 0,
            RinexNavVersion::V4_00 => self.gps_cnav.len(),
        };
        self.gps_lnav.len() + cnav + self.galileo.len() + self.beidou.len() + self.glonass.len()
    }
}

/// The RINEX 4 label line of a record: `> EPH G01 LNAV` (RINEX 4.00 §5.3).
fn eph_label(out: &mut String, sat: &str, message: &str) {
    let _ = writeln!(out, "> EPH {sat} {message}");
}

/// A GPS CNAV record (RINEX 4.00 table A32, [`super::rinex_nav_cnav`]):
/// blank fields for the group delays the message says are not available.
fn cnav_record(out: &mut String, c: &CnavEphemeris) {
    let sat = format!("G{:02}", c.prn);
    let values = cnav_values(c);
    let field = |v: &Option<f64>| v.map_or_else(|| " ".repeat(19), d19);
    eph_label(out, &sat, "CNAV");
    nav_epoch_line(
        out,
        &sat,
        c.orbit.toc_gps_s,
        [0, 1, 2].map(|i| values[i].unwrap_or(0.0)),
    );
    for row in values[3..].chunks(4) {
        let _ = writeln!(
            out,
            "    {}",
            row.iter().map(field).collect::<String>().trim_end()
        );
    }
}

/// A GLONASS record (RINEX 3.05 table A10, the layout
/// [`super::rinex_nav_glonass`] reads): t_b as a UTC epoch, −τ_n, γ_n and
/// the message frame time (t_b's second of the UTC week: the ephemeris
/// keeps no t_k), then position, velocity and lunisolar acceleration in
/// km, km/s, km/s² with the health, the channel and the age. RINEX 4's
/// fourth line (status flags, L1/L2 group delay, URAI, health flags) is
/// written as not known (.999999999999E+09): the strings' P, M and F_T
/// are not kept.
fn glonass_record(out: &mut String, g: &GlonassEphemeris, v4: bool) {
    let sat = format!("R{:02}", g.slot);
    if v4 {
        eph_label(out, &sat, "FDMA");
    }
    let utc = g.tb_gps_s - gps_minus_utc_s(g.tb_gps_s);
    nav_epoch_line(
        out,
        &sat,
        utc,
        [-g.tau_n_s, g.gamma_n, utc.rem_euclid(SECONDS_PER_WEEK)],
    );
    let km = |v: &nalgebra::Vector3<f64>, i: usize| v[i] * 1e-3;
    let extra = [
        f64::from(g.health),
        f64::from(g.frequency_channel),
        f64::from(g.age_days),
    ];
    for (i, last) in extra.into_iter().enumerate() {
        let row = [
            km(&g.position_ecef, i),
            km(&g.velocity_ecef, i),
            km(&g.lunisolar_m_s2, i),
            last,
        ];
        let _ = writeln!(out, "    {}", row.map(d19).concat());
    }
    if v4 {
        let _ = writeln!(out, "    {}", [0.999_999_999_999e9; 4].map(d19).concat());
    }
}

/// The text of a RINEX navigation file of `version` holding GPS LNAV
/// (RINEX 3.04 table A6), Galileo I/NAV (table A8) and BeiDou D1 (table
/// A14) ephemerides, and in RINEX 4.00 GPS CNAV ones too (table A32): t_oc
/// as the epoch (in BDT for BeiDou), angles in rad, GPS and Galileo weeks
/// continuous and aligned with GPS weeks, BeiDou's BDT weeks, t_oe and the
/// transmission time in seconds of the t_oe week. RINEX 4 keeps the RINEX
/// 3 layout of the LNAV, I/NAV and D1 records and puts a `> EPH <sat>
/// <message>` line before each record.
pub fn format_rinex_nav(
    ephemerides: &NavFileEphemerides<'_>,
    version: RinexNavVersion,
    provenance: &RinexProvenance,
) -> String {
    let e = ephemerides;
    let v4 = version == RinexNavVersion::V4_00;
    let mut out = String::new();
    let present: Vec<&str> = [
        (
            !e.gps_lnav.is_empty() || (v4 && !e.gps_cnav.is_empty()),
            "G: GPS",
        ),
        (!e.galileo.is_empty(), "E: Galileo"),
        (!e.beidou.is_empty(), "C: BeiDou"),
        (!e.glonass.is_empty(), "R: GLONASS"),
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
            version.number(),
            "",
            "N: GNSS NAV DATA"
        ),
        "RINEX VERSION / TYPE",
    );
    provenance_records(&mut out, provenance);
    record(&mut out, "", "END OF HEADER");
    let labelled = |out: &mut String, r: NavRecord, message: &str| {
        if v4 {
            eph_label(out, &r.sat, message);
        }
        nav_record(out, &r);
    };
    for l in e.gps_lnav {
        labelled(&mut out, NavRecord::lnav(l), "LNAV");
    }
    if v4 {
        for c in e.gps_cnav {
            cnav_record(&mut out, c);
        }
    }
    for g in e.galileo {
        labelled(&mut out, NavRecord::inav(g), "INAV");
    }
    for b in e.beidou {
        labelled(&mut out, NavRecord::d1(b), "D1");
    }
    for g in e.glonass {
        glonass_record(&mut out, g, v4);
    }
    out
}

fn write_text(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).map_err(|e| Error::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    })
}

/// Writes [`format_rinex_obs`] to `path` once memsnav's reader reads the
/// text back ([`parse_rinex_obs`]): a file it would refuse is not written.
/// Observations without a single epoch or observation type are refused
/// (a RINEX file needs its `SYS / # / OBS TYPES`).
pub fn write_rinex_obs(
    path: impl AsRef<Path>,
    observations: &ObservationFile,
    provenance: &RinexProvenance,
) -> Result<()> {
    let path = path.as_ref();
    if observations.epochs.is_empty() || observations.observation_types.is_empty() {
        return Err(Error::invalid(
            "observations",
            format!(
                "no observations to write to {}: the log holds no measurement epoch (a UBX \
                 log needs RXM-RAWX messages)",
                path.display()
            ),
        ));
    }
    let text = format_rinex_obs(observations, provenance);
    read_back(
        path,
        "observations",
        parse_rinex_obs(&text, &path.display().to_string()),
    )?;
    write_text(path, &text)
}

/// Writes [`format_rinex_nav`] to `path` once memsnav's reader reads the
/// text back whole ([`parse_broadcast_nav`]: every record kept): a file
/// it would refuse, or read differently, is not written.
pub fn write_rinex_nav(
    path: impl AsRef<Path>,
    ephemerides: &NavFileEphemerides<'_>,
    version: RinexNavVersion,
    provenance: &RinexProvenance,
) -> Result<()> {
    let path = path.as_ref();
    let text = format_rinex_nav(ephemerides, version, provenance);
    let nav = read_back(
        path,
        "ephemerides",
        parse_broadcast_nav(&text, &path.display().to_string()),
    )?;
    let (written, read) = (
        ephemerides.records(version),
        // The reader gives each CNAV record also as an L1 C/A ephemeris
        // among the GPS ones (where it has T_GD and ISC_L1CA).
        nav.gps.len()
            - nav
                .gps_cnav
                .iter()
                .filter(|c| c.l1_ca_ephemeris().is_some())
                .count()
            + nav.gps_cnav.len()
            + nav.galileo.len()
            + nav.beidou.len()
            + nav.glonass.len(),
    );
    if written != read {
        return Err(Error::invalid(
            "ephemerides",
            format!(
                "{}: not written: the reader would keep {read} of its {written} records ({:?})",
                path.display(),
                nav.skipped
            ),
        ));
    }
    write_text(path, &text)
}

/// The reading of a text about to be written, or the error saying why it
/// is not written.
fn read_back<T>(path: &Path, argument: &str, read: Result<T>) -> Result<T> {
    read.map_err(|e| {
        Error::invalid(
            argument,
            format!(
                "{}: not written: memsnav's reader would refuse it: {e}",
                path.display()
            ),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gnss::{ObservationEpoch, SatelliteObservations};
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
            glonass_channels: BTreeMap::new(),
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
        // Written only when the reader reads it back; nothing to write is
        // an error saying so, and no file is made.
        let dir = std::env::temp_dir().join(format!("memsnav-write-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("x.obs");
        write_rinex_obs(&path, &obs, &RinexProvenance::default()).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
        let empty = ObservationFile {
            epochs: vec![],
            observation_types: BTreeMap::new(),
            ..obs.clone()
        };
        let none = dir.join("none.obs");
        let e = write_rinex_obs(&none, &empty, &RinexProvenance::default()).unwrap_err();
        assert!(e.to_string().contains("no observations to write"), "{e}");
        assert!(!none.exists());
        let mut far = obs.clone();
        far.epochs[0].gps_time_s = 6.0e9; // 2170: the reader refuses the year
        let e = write_rinex_obs(&none, &far, &RinexProvenance::default()).unwrap_err();
        assert!(e.to_string().contains("would refuse it"), "{e}");
        assert!(!none.exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
