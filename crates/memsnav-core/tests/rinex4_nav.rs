//! RINEX 4 navigation records (`gnss::rinex4_nav`, `gnss::rinex_nav_cnav`):
//! a GPS CNAV record written and read back (a blank group delay, t_op in
//! the week before t_oc), repeated and conflicting records counted, bad
//! values and labels refused naming the line, other records skipped with a
//! count. The walk log's file is checked in `tests/ubx.rs`.

use memsnav_core::gnss::{
    format_rinex_nav, parse_broadcast_nav, BroadcastOrbit, CnavEphemeris, CnavGroupDelays,
    NavFileEphemerides, RinexNavVersion, RinexProvenance, SECONDS_PER_WEEK,
};

/// GPS week 2381, Thursday 18:00 (t_oc = t_oe), G08's values in range.
fn g08() -> CnavEphemeris {
    let toc = 2381.0 * SECONDS_PER_WEEK + 410_400.0;
    CnavEphemeris {
        prn: 8,
        orbit: BroadcastOrbit {
            toc_gps_s: toc,
            toe_gps_s: toc,
            af0_s: 1e-4,
            af1_s_s: 1e-12,
            af2_s_s2: 0.0,
            crs_m: 10.0,
            delta_n_rad_s: 4e-9,
            m0_rad: 1.0,
            cuc_rad: 1e-6,
            eccentricity: 0.01,
            cus_rad: 1e-6,
            sqrt_a_sqrt_m: 5153.6,
            cic_rad: 1e-7,
            omega0_rad: 2.0,
            cis_rad: 1e-7,
            i0_rad: 0.96,
            crc_m: 200.0,
            omega_rad: -2.0,
            omega_dot_rad_s: -8e-9,
            idot_rad_s: 1e-10,
            a_dot_m_s: 5e-4,
            delta_n_dot_rad_s2: -1.8e-14,
        },
        l1_health: 0,
        l2_health: 0,
        l5_health: 1,
        ura_ed_index: -1,
        ura_ned0_index: -7,
        ura_ned1_index: 2,
        ura_ned2_index: 7,
        // t_op in the week before t_oc's: placed back there.
        top_gps_s: 2380.0 * SECONDS_PER_WEEK + 604_500.0,
        week: 2381,
        integrity_status_flag: false,
        l2c_phasing: false,
        group_delays: Some(CnavGroupDelays {
            tgd_s: Some(2.25e-9),
            isc_l1ca_s: Some(-8.125e-10),
            isc_l2c_s: None,
            isc_l5i5_s: Some(1.0625e-8),
            isc_l5q5_s: Some(1.1e-8),
        }),
        transmission_gps_s: toc - 300.0,
    }
}

fn text(c: &[CnavEphemeris]) -> String {
    let files = NavFileEphemerides {
        gps_cnav: c,
        ..Default::default()
    };
    format_rinex_nav(&files, RinexNavVersion::V4_00, &RinexProvenance::default())
}

#[test]
fn a_record_reads_back_with_its_blank_group_delay() {
    let c = g08();
    let t = text(&[c]);
    assert!(t.contains("> EPH G08 CNAV\nG08 2025 08 28 18 00 00"), "{t}");
    let nav = parse_broadcast_nav(&t, "x.rnx").unwrap();
    assert_eq!(nav.gps_cnav, [c]);
    // Its L1 C/A form is among the GPS ephemerides; L2C has no ISC
    // and L5 is unhealthy: none of theirs in the group delays.
    assert_eq!(nav.gps.len(), 1);
    assert_eq!(nav.gps[0].tgd_s, 2.25e-9 + 8.125e-10);
    let d = nav.gps_group_delays[&8];
    assert_eq!((d.isc_l2c_s, d.isc_l5i5_s), (None, None));
}

#[test]
fn a_record_without_any_group_delay_reads_back() {
    // Clock messages without a type 30: all five fields blank, line 7
    // written as its 4 blanks alone.
    let c = CnavEphemeris {
        group_delays: None,
        ..g08()
    };
    let t = text(&[c]);
    assert!(t.contains("\n    \n"), "{t}");
    let nav = parse_broadcast_nav(&t, "x.rnx").unwrap();
    assert_eq!(nav.gps_cnav, [c]);
    // Without T_GD and ISC_L1CA there is no L1 C/A clock to position with.
    assert!(nav.gps.is_empty());
}

#[test]
fn repeated_and_conflicting_records_are_counted() {
    let c = g08();
    let later = CnavEphemeris {
        transmission_gps_s: c.transmission_gps_s + 12.0,
        ..c
    };
    let nav = parse_broadcast_nav(&text(&[c, later]), "x.rnx").unwrap();
    assert_eq!(nav.gps_cnav, [c]);
    assert_eq!(nav.skipped.values().sum::<usize>(), 1);
    let mut other = c;
    other.orbit.crs_m = 11.0;
    let nav = parse_broadcast_nav(&text(&[c, other]), "x.rnx").unwrap();
    assert!(nav.gps_cnav.is_empty() && nav.gps.is_empty());
    assert_eq!(
        nav.skipped["GPS CNAV ephemerides in conflict (one satellite and t_oc, other values)"],
        2
    );
}

#[test]
fn bad_values_and_labels_are_refused_naming_the_line() {
    let t = text(&[g08()]);
    let err = |t: &str| parse_broadcast_nav(t, "x.rnx").unwrap_err().to_string();
    // Health 9 is not three bits (line 8 holds URAI_ED, health, ...).
    let health = t.replace(
        " 1.000000000000E+00 2.250000000000E-09",
        " 9.000000000000E+00 2.250000000000E-09",
    );
    assert_ne!(health, t);
    let e = err(&health);
    assert!(
        e.starts_with("x.rnx:11: SV health = 9e0 for G08 is out of range"),
        "{e}"
    );
    // The epoch line of another satellite than the label's.
    let e = err(&t.replace("G08 2025", "G09 2025"));
    assert!(
        e.contains("the record labelled G08 starts with satellite \"G09\""),
        "{e}"
    );
    // A record cut short.
    let cut: String = t.lines().take(8).map(|l| format!("{l}\n")).collect();
    assert!(err(&cut).contains("truncated CNAV record for G08"));
    // A record without its label.
    let e = err(&t.replace("> EPH G08 CNAV\n", ""));
    assert!(e.contains("expected a RINEX 4 record label"), "{e}");
    // An unknown record type.
    assert!(err(&t.replace("> EPH", "> XYZ")).contains("unknown RINEX 4 record type"));
}

#[test]
fn other_records_are_skipped_with_a_count() {
    let t = text(&[g08()]);
    let extra =
        "> STO GPUT CNVX\n    2025 08 28 18 00 00 GPUT\n     4.104000000000E+05 1.0E-09 0.0 0.0\n\
                 > EPH G08 CNV2\nG08 2025 08 28 18 00 00 1.0E-04 0.0 0.0\n     1.0\n";
    let nav = parse_broadcast_nav(&format!("{t}{extra}"), "x.rnx").unwrap();
    assert_eq!(nav.gps_cnav.len(), 1);
    assert_eq!(nav.skipped["RINEX 4 STO records"], 1);
    assert_eq!(nav.skipped["RINEX 4 CNV2 records of system G"], 1);
}
