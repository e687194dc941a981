//! A broadcast ephemeris as the values of its RINEX 3 navigation record
//! (RINEX 3.04 tables A6, A8, A14): the form the writer writes, the range
//! table checks ([`super::broadcast_ranges`]) and the conflict rule
//! compares ([`super::ephemeris_conflicts`]), so a decoded ephemeris is
//! judged on exactly what a file of it would hold.

use super::beidou_ephemeris::BeidouEphemeris;
use super::broadcast_orbit::{BroadcastOrbit, BroadcastSystem, BEIDOU, GALILEO, GPS};
use super::ephemeris::{ura_m, LnavEphemeris};
use super::galileo_ephemeris::{sisa_m, InavEphemeris};
use super::time::SECONDS_PER_WEEK;

/// One navigation record.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct NavRecord {
    /// The satellite, `G23`.
    pub sat: String,
    /// Its system's constants (letter, time).
    pub system: &'static BroadcastSystem,
    /// t_oc and t_oe, GPS s.
    pub toc_gps_s: f64,
    pub toe_gps_s: f64,
    /// The issue of data that names one set of values (GPS IODE, Galileo
    /// IODnav); `None` for BeiDou, whose AODE is the data's age: two sets
    /// of one age differ.
    pub issue_of_data: Option<u16>,
    /// The record's values in RINEX order (a_f0, a_f1, a_f2, then the
    /// orbit lines; 29 for GPS and BeiDou, 28 for Galileo).
    pub values: Vec<f64>,
}

/// The record values every Keplerian record shares (RINEX 3.04 tables
/// A6, A8, A14: the clock and orbit lines 1-5's first value): the issue of
/// data in slot 3, t_oe as seconds of its week in slot 11.
pub(crate) fn orbit_values(
    issue_of_data: f64,
    o: &BroadcastOrbit,
    toe_seconds_of_week: f64,
) -> [f64; 20] {
    [
        o.af0_s,
        o.af1_s_s,
        o.af2_s_s2,
        issue_of_data,
        o.crs_m,
        o.delta_n_rad_s,
        o.m0_rad,
        o.cuc_rad,
        o.eccentricity,
        o.cus_rad,
        o.sqrt_a_sqrt_m,
        toe_seconds_of_week,
        o.cic_rad,
        o.omega0_rad,
        o.cis_rad,
        o.i0_rad,
        o.crc_m,
        o.omega_rad,
        o.omega_dot_rad_s,
        o.idot_rad_s,
    ]
}

fn record(
    sat: String,
    system: &'static BroadcastSystem,
    o: &BroadcastOrbit,
    issue_of_data: Option<u16>,
    head: [f64; 20],
    tail: &[f64],
) -> NavRecord {
    NavRecord {
        sat,
        system,
        toc_gps_s: o.toc_gps_s,
        toe_gps_s: o.toe_gps_s,
        issue_of_data,
        values: head.iter().chain(tail).copied().collect(),
    }
}

impl NavRecord {
    /// A GPS LNAV ephemeris (table A6): weeks continuous, t_oe and the
    /// transmission time in seconds of the t_oe week.
    pub fn lnav(l: &LnavEphemeris) -> Self {
        let (e, o) = (&l.ephemeris, &l.ephemeris.orbit);
        let week_start = f64::from(l.toe_week) * SECONDS_PER_WEEK;
        record(
            format!("G{:02}", e.prn),
            &GPS,
            o,
            Some(u16::from(l.iode)),
            orbit_values(f64::from(l.iode), o, o.toe_gps_s - week_start),
            &[
                f64::from(l.l2_codes),
                f64::from(l.toe_week),
                f64::from(u8::from(l.l2p_data_flag)),
                ura_m(l.ura_index),
                f64::from(e.health),
                e.tgd_s,
                f64::from(l.iodc),
                l.transmission_gps_s - week_start,
                e.fit_interval_h,
            ],
        )
    }

    /// A Galileo I/NAV ephemeris (table A8): data sources I/NAV E1-B with
    /// the clock for E5b,E1; the week GPS-aligned.
    pub fn inav(e: &InavEphemeris) -> Self {
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
        record(
            format!("E{:02}", e.svid),
            &GALILEO,
            o,
            Some(e.iod_nav),
            orbit_values(f64::from(e.iod_nav), o, o.toe_gps_s - week_start),
            &[
                sources,
                toe_week,
                0.0,
                sisa_m(e.sisa_index).unwrap_or(-1.0),
                f64::from(health),
                e.bgd_e1_e5a_s,
                e.bgd_e1_e5b_s,
                e.transmission_gps_s - week_start,
            ],
        )
    }

    /// A BeiDou D1 ephemeris (table A14): t_oc in BDT when written, the
    /// BDT week.
    pub fn d1(e: &BeidouEphemeris) -> Self {
        let o = &e.orbit;
        let toe_week = BEIDOU.week(o.toe_gps_s);
        let week_start = BEIDOU.gps_time_s(toe_week, 0.0);
        record(
            format!("C{:02}", e.prn),
            &BEIDOU,
            o,
            None,
            orbit_values(f64::from(e.aode), o, o.toe_gps_s - week_start),
            &[
                0.0,
                toe_week,
                0.0,
                ura_m(e.urai),
                f64::from(e.sat_h1),
                e.tgd1_s,
                e.tgd2_s,
                e.transmission_gps_s - week_start,
                f64::from(e.aodc),
            ],
        )
    }

    /// The first value out of the range table's range, as the readers
    /// word it.
    pub fn out_of_range(&self) -> Option<String> {
        super::broadcast_ranges::check_record(&self.sat, &self.values)
            .err()
            .map(|(_, reason)| reason)
    }
}
