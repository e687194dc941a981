//! The UBX reader on the walk's raw u-blox log (shared data): its GPS LNAV
//! ephemerides against the RINEX navigation file another converter made
//! from the same log, its epochs and messages as the data README counts
//! them, and the RINEX 3 files written from it read back by the project's
//! readers; its Galileo I/NAV ephemerides against its own pseudoranges;
//! its BeiDou D1 ephemerides, orbit and clock, against the RINEX file's;
//! its GPS CNAV ephemerides against its LNAV ones (independent uploads)
//! and, for the satellites without LNAV, against its pseudoranges. The
//! excerpt in tests/data gives the same ephemerides, and none once a bit
//! of each CNAV message is flipped. The measurements built from it carry,
//! beside each, its signal's C/N0 and the satellite's elevation.

mod figures;
mod shared_data;

use std::path::PathBuf;

use figures::Figures;
use memsnav_core::geodesy::wgs84::SPEED_OF_LIGHT_M_S;
use memsnav_core::geodesy::{ecef_to_geodetic, geodetic_to_ecef, Geodetic};
use memsnav_core::gnss::{
    broadcast_epochs, broadcast_epochs_with_signals, format_rinex_nav, format_rinex_obs,
    parse_broadcast_nav, parse_rinex_nav, parse_rinex_obs, predicted_range, read_broadcast_nav,
    read_rinex_nav, satellite_number, BroadcastOrbit, GnssSystem, GpsEphemeris, ObservableOptions,
    RinexNavVersion, RinexProvenance, SatelliteState, EPHEMERIS_VALIDITY_S,
};
use memsnav_core::logs::{parse_ubx, read_ubx, UbxLog};
use nalgebra::Vector3;
use shared_data::shared_data;

const WALK_UBX: &str = "real-imu-gnss/walk_0827/gnss_1730.ubx";
const WALK_NAV: &str = "real-imu-gnss/walk_0827/gnss_1730.nav";

fn walk() -> UbxLog {
    read_ubx(shared_data(WALK_UBX)).unwrap()
}

/// Every field of two ephemerides as (name, a, b).
fn fields(a: &GpsEphemeris, b: &GpsEphemeris) -> Vec<(&'static str, f64, f64)> {
    vec![
        ("toc", a.orbit.toc_gps_s, b.orbit.toc_gps_s),
        ("toe", a.orbit.toe_gps_s, b.orbit.toe_gps_s),
        ("af0", a.orbit.af0_s, b.orbit.af0_s),
        ("af1", a.orbit.af1_s_s, b.orbit.af1_s_s),
        ("af2", a.orbit.af2_s_s2, b.orbit.af2_s_s2),
        ("crs", a.orbit.crs_m, b.orbit.crs_m),
        ("delta_n", a.orbit.delta_n_rad_s, b.orbit.delta_n_rad_s),
        ("m0", a.orbit.m0_rad, b.orbit.m0_rad),
        ("cuc", a.orbit.cuc_rad, b.orbit.cuc_rad),
        ("e", a.orbit.eccentricity, b.orbit.eccentricity),
        ("cus", a.orbit.cus_rad, b.orbit.cus_rad),
        ("sqrt_a", a.orbit.sqrt_a_sqrt_m, b.orbit.sqrt_a_sqrt_m),
        ("cic", a.orbit.cic_rad, b.orbit.cic_rad),
        ("omega0", a.orbit.omega0_rad, b.orbit.omega0_rad),
        ("cis", a.orbit.cis_rad, b.orbit.cis_rad),
        ("i0", a.orbit.i0_rad, b.orbit.i0_rad),
        ("crc", a.orbit.crc_m, b.orbit.crc_m),
        ("omega", a.orbit.omega_rad, b.orbit.omega_rad),
        (
            "omega_dot",
            a.orbit.omega_dot_rad_s,
            b.orbit.omega_dot_rad_s,
        ),
        ("idot", a.orbit.idot_rad_s, b.orbit.idot_rad_s),
        ("health", f64::from(a.health), f64::from(b.health)),
        ("tgd", a.tgd_s, b.tgd_s),
        ("fit", a.fit_interval_h, b.fit_interval_h),
    ]
}

/// `a` and `b` agree to `digits` significant digits in every field.
fn assert_same(a: &GpsEphemeris, b: &GpsEphemeris, digits: i32) {
    assert_eq!(a.prn, b.prn);
    for (name, x, y) in fields(a, b) {
        let tolerance = 10f64.powi(-digits) * x.abs().max(y.abs());
        assert!(
            (x - y).abs() <= tolerance,
            "G{:02} {name}: {x} vs {y}",
            a.prn
        );
    }
}

#[test]
fn walk_gps_lnav_equals_the_rinex_nav_of_the_same_log() {
    let log = walk();
    let mut prns: Vec<u16> = log
        .gps_ephemerides
        .iter()
        .map(|e| e.ephemeris.prn)
        .collect();
    prns.sort_unstable();
    // The data README: complete LNAV for G10, G23, G27 and G32 only.
    assert_eq!(prns, [10, 23, 27, 32]);
    let nav = read_rinex_nav(shared_data(WALK_NAV)).unwrap();
    let mut worst = (0.0f64, 0.0f64);
    for l in &log.gps_ephemerides {
        let other = nav.iter().find(|n| n.prn == l.ephemeris.prn).unwrap();
        // The file prints 12 significant digits.
        assert_same(&l.ephemeris, other, 11);
        assert_eq!((l.ephemeris.health, l.ura_index), (0, 0));
        let (position, clock) = largest_differences(
            &l.ephemeris.orbit,
            |t, dt| l.ephemeris.state_at(t, dt),
            |t, dt| other.state_at(t, dt),
        );
        assert!(position < 0.01 && clock < 0.01, "G{:02}", other.prn);
        worst = (worst.0.max(position), worst.1.max(clock));
    }
    eprintln!(
        "GPS: {} LNAV ephemerides against the RINEX: largest differences {:.2e} m position, \
         {:.2e} m clock",
        log.gps_ephemerides.len(),
        worst.0,
        worst.1
    );
    // docs/how-to/convert-ublox.md shows them (round-off of the file's 12
    // digits: the position to 0.01 mm, the clock to 10⁻¹⁶ s).
    Figures::new("walk_lnav")
        .add("position_mm", 1e3 * worst.0, 0.005)
        .add("clock_s", worst.1 / SPEED_OF_LIGHT_M_S, 5e-17)
        .check_or_write();
    // Every word passed its parity (the README), every frame its checksum.
    assert!(
        !log.skipped.keys().any(|k| k.contains("parity")
            || k.contains("checksum")
            || k.starts_with("RXM-") && k.contains("malformed")),
        "{:?}",
        log.skipped
    );
}

#[test]
fn walk_epochs_and_messages() {
    let log = walk();
    assert_eq!(log.messages["RXM-RAWX"], 536);
    assert_eq!(log.messages["NAV-PVT"], 536);
    let t: Vec<f64> = log.rawx.iter().map(|e| e.gps_time_s()).collect();
    // 4 Hz for 133 s.
    assert!(t.windows(2).all(|w| (w[1] - w[0] - 0.25).abs() < 1e-3));
    assert!((t[t.len() - 1] - t[0] - 133.75).abs() < 0.01);
    assert!(log.rawx.iter().all(|e| e.leap_seconds == Some(18)));
    // Three signals per system by their u-blox ids (data README).
    let g = &log.observations.observation_types[&'G'];
    assert_eq!(
        g[..],
        ["C1C", "L1C", "D1C", "S1C", "C2L", "L2L", "D2L", "S2L", "C5Q", "L5Q", "D5Q", "S5Q"]
    );
    assert_eq!(log.observations.observation_types[&'E'].len(), 12);
    assert_eq!(log.observations.observation_types[&'C'].len(), 12);
    // The receiver's own solution: 349 fixed and 187 float epochs, as the
    // RTK truth file (which is NAV-PVT) counts them.
    let fixed = log.fixes.quality.iter().filter(|&&q| q == 1).count();
    let float = log.fixes.quality.iter().filter(|&&q| q == 2).count();
    assert_eq!((fixed, float), (349, 187));
    // Ellipsoidal height 1580.048 m where the MSL one is 1601.435 m.
    let first = &log.nav_pvt[0];
    assert!((first.lla.z - first.height_msl_m + 21.387).abs() < 0.002);
}

#[test]
fn written_rinex_reads_back() {
    let log = walk();
    let header = RinexProvenance::default();
    let v3 = RinexNavVersion::V3_04;
    let nav = parse_rinex_nav(
        &format_rinex_nav(&log.nav_file_ephemerides(), v3, &header),
        "written.nav",
    )
    .unwrap();
    assert_eq!(nav.len(), log.gps_ephemerides.len());
    for (back, l) in nav.iter().zip(&log.gps_ephemerides) {
        // D19.12 keeps 13 significant digits.
        assert_same(back, &l.ephemeris, 12);
    }
    // Galileo and BeiDou read back by the same reader give the same orbit
    // and clock (D19.12: 13 digits) over ±2 h of t_oe.
    let text = format_rinex_nav(&log.nav_file_ephemerides(), v3, &header);
    let all = parse_broadcast_nav(&text, "written.nav").unwrap();
    // RINEX 3.04 has no CNAV record: only LNAV's 4 GPS satellites.
    assert!(all.gps_cnav.is_empty());
    assert_eq!(all.galileo.len(), log.galileo_ephemerides.len());
    assert_eq!(all.beidou.len(), log.beidou_ephemerides.len());
    for (back, e) in all.galileo.iter().zip(&log.galileo_ephemerides) {
        assert_eq!(
            (
                back.svid,
                back.iod_nav,
                back.sisa_index,
                back.e1b_health,
                back.gst_week
            ),
            (e.svid, e.iod_nav, e.sisa_index, e.e1b_health, e.gst_week)
        );
        let (position, clock) = largest_differences(
            &e.orbit,
            |t, dt| e.state_at(t, dt),
            |t, dt| back.state_at(t, dt),
        );
        assert!(position < 0.01 && clock < 0.01, "E{:02}", e.svid);
    }
    for (back, e) in all.beidou.iter().zip(&log.beidou_ephemerides) {
        assert_eq!(
            (
                back.prn,
                back.aode,
                back.aodc,
                back.urai,
                back.sat_h1,
                back.bdt_week
            ),
            (e.prn, e.aode, e.aodc, e.urai, e.sat_h1, e.bdt_week)
        );
        assert!((back.transmission_gps_s - e.transmission_gps_s).abs() < 1e-6);
        let (position, clock) = largest_differences(
            &e.orbit,
            |t, dt| e.state_at(t, dt),
            |t, dt| back.state_at(t, dt),
        );
        assert!(position < 0.01 && clock < 0.01, "C{:02}", e.prn);
    }
    let obs =
        parse_rinex_obs(&format_rinex_obs(&log.observations, &header), "written.obs").unwrap();
    assert_eq!(obs.observation_types, log.observations.observation_types);
    assert_eq!(obs.epochs.len(), log.observations.epochs.len());
    for (b, a) in obs.epochs.iter().zip(&log.observations.epochs) {
        assert!((b.gps_time_s - a.gps_time_s).abs() < 1e-6);
        let kept: Vec<_> = a
            .satellites
            .iter()
            .filter(|s| s.values.iter().any(Option::is_some))
            .collect();
        assert_eq!(b.satellites.len(), kept.len());
        for (sb, sa) in b.satellites.iter().zip(kept) {
            assert_eq!((sb.system, sb.prn, &sb.lli), (sa.system, sa.prn, &sa.lli));
            for (x, y) in sb.values.iter().zip(&sa.values) {
                match (x, y) {
                    (Some(x), Some(y)) => assert!((x - y).abs() <= 5.000_001e-4, "{x} vs {y}"),
                    (None, None) => {}
                    _ => panic!("{:?} vs {:?}", sb.values, sa.values),
                }
            }
        }
    }
}

/// RINEX 4.00 (`memsnav convert`'s default) carries the walk's 7 CNAV
/// ephemerides, 3 of them (G08, G18, G24) of satellites without LNAV, and
/// gives back what the log decoded: the same records, the same orbits and
/// L1 C/A clocks to D19.12's 13 digits, and the same satellites to
/// position with as the log itself.
#[test]
fn rinex4_nav_carries_the_cnav_ephemerides() {
    let log = walk();
    let text = format_rinex_nav(
        &log.nav_file_ephemerides(),
        RinexNavVersion::V4_00,
        &RinexProvenance::default(),
    );
    assert!(text.starts_with("     4.00           N: GNSS NAV DATA    M: Mixed"));
    assert_eq!(text.matches("> EPH G").count(), 4 + 7);
    assert_eq!(text.matches(" CNAV\n").count(), 7);
    let back = parse_broadcast_nav(&text, "written.rnx").unwrap();
    assert!(back.skipped.is_empty(), "{:?}", back.skipped);
    assert_eq!(back.gps_cnav.len(), 7);
    let prns = |nav: &memsnav_core::gnss::BroadcastNav| {
        let mut p: Vec<u16> = nav.gps.iter().map(|e| e.prn).collect();
        p.sort_unstable();
        p.dedup();
        p
    };
    let from_log = log.broadcast_nav();
    assert_eq!(prns(&back), prns(&from_log));
    assert_eq!(prns(&back), [8, 10, 18, 23, 24, 27, 32]);
    assert_eq!(back.gps_group_delays.len(), from_log.gps_group_delays.len());
    for (b, c) in back.gps_cnav.iter().zip(&log.gps_cnav_ephemerides) {
        assert_eq!(
            (b.prn, b.l1_health, b.l2_health, b.l5_health, b.week),
            (c.prn, c.l1_health, c.l2_health, c.l5_health, c.week)
        );
        assert_eq!(
            (
                b.ura_ed_index,
                b.ura_ned0_index,
                b.ura_ned1_index,
                b.ura_ned2_index
            ),
            (
                c.ura_ed_index,
                c.ura_ned0_index,
                c.ura_ned1_index,
                c.ura_ned2_index
            )
        );
        assert_eq!(
            (b.top_gps_s, b.transmission_gps_s),
            (c.top_gps_s, c.transmission_gps_s)
        );
        // D19.12: 13 significant digits.
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-12 * y.abs();
        let (gb, gc) = (b.group_delays.unwrap(), c.group_delays.unwrap());
        for (x, y) in [
            (gb.tgd_s, gc.tgd_s),
            (gb.isc_l1ca_s, gc.isc_l1ca_s),
            (gb.isc_l2c_s, gc.isc_l2c_s),
            (gb.isc_l5i5_s, gc.isc_l5i5_s),
            (gb.isc_l5q5_s, gc.isc_l5q5_s),
        ] {
            assert!(close(x.unwrap(), y.unwrap()), "{x:?} vs {y:?}");
        }
        assert!(close(b.orbit.a_dot_m_s, c.orbit.a_dot_m_s));
        assert!(close(
            b.orbit.delta_n_dot_rad_s2,
            c.orbit.delta_n_dot_rad_s2
        ));
        let (position, clock) = largest_differences(
            &c.orbit,
            |t, dt| c.state_at(t, dt),
            |t, dt| b.state_at(t, dt),
        );
        assert!(position < 0.01 && clock < 0.01, "G{:02}", c.prn);
    }
    // LNAV, Galileo and BeiDou come back as from RINEX 3.04.
    let v3 = parse_broadcast_nav(
        &format_rinex_nav(
            &log.nav_file_ephemerides(),
            RinexNavVersion::V3_04,
            &RinexProvenance::default(),
        ),
        "written.nav",
    )
    .unwrap();
    assert_eq!(&back.gps[..4], &v3.gps[..]);
    assert_eq!(
        (back.galileo.clone(), back.beidou.clone()),
        (v3.galileo, v3.beidou)
    );
}

#[test]
fn the_excerpt_gives_the_same_ephemerides() {
    let excerpt = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/real-imu-gnss/walk_head.ubx");
    let head = read_ubx(excerpt).unwrap();
    let log = walk();
    assert_eq!(head.rawx.len(), 20);
    assert_eq!(head.gps_ephemerides, log.gps_ephemerides);
    assert_eq!(head.galileo_ephemerides, log.galileo_ephemerides);
    assert_eq!(head.beidou_ephemerides, log.beidou_ephemerides);
    assert_eq!(head.gps_cnav_ephemerides, log.gps_cnav_ephemerides);
    assert_eq!(head.klobuchar, log.klobuchar);
}

fn excerpt_bytes() -> Vec<u8> {
    std::fs::read(
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../tests/data/real-imu-gnss/walk_head.ubx"),
    )
    .unwrap()
}

/// The byte offsets of the excerpt's RXM-SFRBX frames of GPS L2C and L5
/// (the excerpt holds only whole frames, back to back).
fn cnav_frames(log: &[u8]) -> Vec<usize> {
    let mut out = Vec::new();
    let mut at = 0;
    while at + 8 <= log.len() {
        let length = usize::from(u16::from_le_bytes([log[at + 4], log[at + 5]]));
        if log[at + 2..at + 4] == [0x02, 0x13]
            && log[at + 6] == 0
            && [3, 4, 6, 7].contains(&log[at + 8])
        {
            out.push(at);
        }
        at += 8 + length;
    }
    out
}

#[test]
fn a_flipped_bit_in_a_cnav_message_is_a_crc_failure() {
    let mut bytes = excerpt_bytes();
    let frames = cnav_frames(&bytes);
    assert_eq!(frames.len(), 148);
    for (k, &at) in frames.iter().enumerate() {
        // One bit of the message's first 300 (word k mod 9, bit k mod 32
        // from its least significant), then the frame's checksum anew
        // (UBX §3.4: Fletcher-8 over class to payload end).
        let word = at + 6 + 8 + 4 * (k % 9);
        bytes[word + (k / 8) % 4] ^= 1 << (k % 8);
        let length = usize::from(u16::from_le_bytes([bytes[at + 4], bytes[at + 5]]));
        let (mut a, mut b) = (0u8, 0u8);
        for &x in &bytes[at + 2..at + 6 + length] {
            a = a.wrapping_add(x);
            b = b.wrapping_add(a);
        }
        bytes[at + 6 + length] = a;
        bytes[at + 7 + length] = b;
    }
    let log = parse_ubx(&bytes, "flipped.ubx").unwrap();
    let failures = log.skipped["GPS CNAV messages with a CRC failure"];
    // A flip in a preamble bit makes a message that is not CNAV at all.
    let malformed = log
        .skipped
        .get("GPS CNAV messages malformed")
        .copied()
        .unwrap_or(0);
    assert_eq!(failures + malformed, 148, "{:?}", log.skipped);
    assert!(failures >= 140);
    assert!(log.gps_cnav_ephemerides.is_empty() && log.klobuchar.is_none());
    // Nothing else changed.
    let head = parse_ubx(&excerpt_bytes(), "walk_head.ubx").unwrap();
    assert_eq!(head.gps_ephemerides, log.gps_ephemerides);
    assert_eq!(head.gps_cnav_ephemerides.len(), 7);
}

/// The difference of two GPS states at GPS time `t`: position (m) and
/// clock (m, × c).
fn state_difference(a: &SatelliteState, b: &SatelliteState) -> (f64, f64) {
    (
        (a.position_ecef - b.position_ecef).norm(),
        SPEED_OF_LIGHT_M_S * (a.clock_bias_s - b.clock_bias_s).abs(),
    )
}

#[test]
fn walk_gps_cnav_agrees_with_lnav_and_the_pseudoranges() {
    let log = walk();
    let mut prns: Vec<u16> = log.gps_cnav_ephemerides.iter().map(|e| e.prn).collect();
    prns.sort_unstable();
    // The data README: CNAV for 7 GPS satellites, among them the 4 of LNAV.
    assert_eq!(prns, [8, 10, 18, 23, 24, 27, 32]);
    let mut covered = prns.clone();
    covered.extend(log.gps_ephemerides.iter().map(|l| l.ephemeris.prn));
    covered.sort_unstable();
    covered.dedup();
    assert!(covered.len() >= 7);
    // Every message passes its CRC (the README); types 10, 11, 30, 32
    // and 33 only, all read.
    assert!(
        !log.skipped.keys().any(|k| k.contains("CNAV")),
        "{:?}",
        log.skipped
    );
    let (first, last) = (
        log.rawx[0].gps_time_s(),
        log.rawx[log.rawx.len() - 1].gps_time_s(),
    );
    let mut worst_log = (0.0f64, 0.0f64);
    let mut worst_fit = (0.0f64, 0.0f64);
    let mut fit_orbits = Vec::new();
    let mut compared = 0;
    for c in &log.gps_cnav_ephemerides {
        // L1 and L2 healthy; L5 flagged unhealthy (pre-operational) by
        // every satellite of the walk.
        assert_eq!((c.l1_health, c.l2_health, c.l5_health), (0, 0, 1));
        assert_eq!(u32::from(c.week), 2381);
        assert!(c.group_delays.is_some(), "G{:02}", c.prn);
        let Some(l) = log
            .gps_ephemerides
            .iter()
            .find(|l| l.ephemeris.prn == c.prn)
        else {
            continue;
        };
        compared += 1;
        let lnav = &l.ephemeris;
        // Independent uploads, so the same satellite to the broadcast
        // accuracy: over the log every 1 s, and over every 60 s where both
        // are within their fit (LNAV t_oe ± 2 h, CNAV t_oe ± 2 h). The
        // clocks compared are both the L1/L2 P(Y) ionosphere-free ones.
        let difference = |t: f64| {
            state_difference(
                &lnav.orbit.state_at(
                    &memsnav_core::gnss::GPS,
                    memsnav_core::gnss::OrbitFrame::EarthFixedNode,
                    t,
                    0.0,
                ),
                &c.state_at(t, 0.0),
            )
        };
        let max = |a: (f64, f64), b: (f64, f64)| (a.0.max(b.0), a.1.max(b.1));
        let mut t = first;
        while t <= last {
            worst_log = max(worst_log, difference(t));
            t += 1.0;
        }
        let from = (lnav.orbit.toe_gps_s).max(c.orbit.toe_gps_s) - EPHEMERIS_VALIDITY_S;
        let to = (lnav.orbit.toe_gps_s).min(c.orbit.toe_gps_s) + EPHEMERIS_VALIDITY_S;
        let mut t = from;
        let mut satellite = (0.0f64, 0.0f64);
        while t <= to {
            satellite = max(satellite, difference(t));
            t += 60.0;
        }
        eprintln!(
            "G{:02}: CNAV − LNAV over their common fit ({:.1} h): {:.2} m orbit, {:.2} m clock",
            c.prn,
            (to - from) / 3600.0,
            satellite.0,
            satellite.1
        );
        worst_fit = max(worst_fit, satellite);
        fit_orbits.push(satellite.0);
        // The same T_GD (LNAV's 8 bits × 2⁻³¹ s, CNAV's 13 × 2⁻³⁵ s).
        let tgd = c.group_delays.unwrap().tgd_s.unwrap();
        assert!((tgd - lnav.tgd_s).abs() <= 2f64.powi(-32), "G{:02}", c.prn);
    }
    assert_eq!(compared, 4);
    eprintln!(
        "GPS CNAV: {} ephemerides, {compared} against LNAV: largest differences over the log \
         {:.2} m orbit, {:.2} m clock; over the common fit {:.2} m, {:.2} m",
        log.gps_cnav_ephemerides.len(),
        worst_log.0,
        worst_log.1,
        worst_fit.0,
        worst_fit.1
    );
    assert!(worst_log.0 < 1.0 && worst_log.1 < 1.0, "{worst_log:?}");
    // At the edge of LNAV's fit the two part by a little more (G10: 1.1 m).
    assert!(worst_fit.0 < 1.5 && worst_fit.1 < 1.0, "{worst_fit:?}");
    // Every CNAV satellite, the three without LNAV among them: L1 C/A
    // pseudoranges with the CNAV clock of L1 C/A (T_GD − ISC_L1CA).
    let residuals = pseudorange_residuals(
        &log,
        'G',
        "C1C",
        log.gps_cnav_ephemerides.iter().map(|c| {
            let delay = c.group_delay_s("1C").unwrap();
            let state = move |t, dt| {
                let mut s = c.state_at(t, dt);
                s.clock_bias_s -= delay;
                s
            };
            (c.prn, Box::new(state) as StateFn)
        }),
    );
    assert_eq!(residuals.len(), 7);
    let (clock_ms, spread_m) = assert_clock_and_scatter(&residuals);
    // The Klobuchar coefficients of type 30: values the message can carry,
    // and an L1 zenith delay at the walk's place and time of metres.
    let k = log.klobuchar.unwrap();
    k.validate("klobuchar").unwrap();
    let pvt = &log.nav_pvt[0];
    let zenith = k.delay_m(
        first,
        pvt.lla.x,
        pvt.lla.y,
        0.0,
        std::f64::consts::FRAC_PI_2,
    );
    eprintln!("Klobuchar of CNAV type 30: {k:?}; zenith L1 delay at the walk {zenith:.2} m");
    assert!((1.0..30.0).contains(&zenith), "{zenith}");
    // docs/how-to/convert-ublox.md shows these (orbits and clocks to the
    // centimetre, the residuals and the zenith delay to the decimetre).
    fit_orbits.sort_by(f64::total_cmp);
    Figures::new("walk_cnav")
        .add("orbit_over_log_m", worst_log.0, 0.005)
        .add("clock_over_log_m", worst_log.1, 0.005)
        .add("orbit_over_fit_m", worst_fit.0, 0.005)
        .add("clock_over_fit_m", worst_fit.1, 0.005)
        .add(
            "others_orbit_over_fit_m",
            fit_orbits[fit_orbits.len() - 2],
            0.005,
        )
        .add("pseudorange_spread_m", spread_m, 0.05)
        .add("receiver_clock_ms", clock_ms, 0.005)
        .add("klobuchar_zenith_m", zenith, 0.05)
        .check_or_write();
}

#[test]
fn walk_galileo_inav_ephemerides_fit_the_pseudoranges() {
    let log = walk();
    let mut svids: Vec<u16> = log.galileo_ephemerides.iter().map(|e| e.svid).collect();
    svids.sort_unstable();
    // The data README: I/NAV for 7 Galileo satellites, E14 unhealthy.
    assert_eq!(svids, [7, 8, 13, 14, 26, 29, 33]);
    for e in &log.galileo_ephemerides {
        assert_eq!(e.is_healthy(), e.svid != 14, "E{:02}", e.svid);
        assert_eq!(u32::from(e.gst_week) + 1024, 2381);
    }
    assert!(
        !log.skipped.keys().any(|k| k.contains("Galileo")),
        "{:?}",
        log.skipped
    );
    // Each healthy satellite's E1 pseudorange at the middle epoch, with its
    // clock corrected, minus the range from the receiver's NAV-PVT position:
    // what remains is the receiver clock (common to all) plus the
    // atmosphere (metres). A misplaced bit would leave kilometres.
    let residuals = pseudorange_residuals(
        &log,
        'E',
        "C1C",
        log.galileo_ephemerides
            .iter()
            .filter(|e| e.is_healthy())
            .map(|e| (e.svid, Box::new(|t, dt| e.state_at(t, dt)) as StateFn)),
    );
    let (clock_ms, spread_m) = assert_clock_and_scatter(&residuals);
    Figures::new("walk_inav")
        .add("pseudorange_spread_m", spread_m, 0.05)
        .add("receiver_clock_ms", clock_ms, 0.005)
        .check_or_write();
}

/// A satellite's state (with the clock of the signal compared) at GPS
/// time `t + dt`.
type StateFn<'a> = Box<dyn Fn(f64, f64) -> SatelliteState + 'a>;

/// Each satellite's pseudorange on `code` at the log's middle epoch, with
/// its clock corrected, minus the range from the receiver's NAV-PVT
/// position.
fn pseudorange_residuals<'a>(
    log: &UbxLog,
    system: char,
    code: &str,
    states: impl Iterator<Item = (u16, StateFn<'a>)>,
) -> Vec<f64> {
    let epoch = &log.observations.epochs[268];
    let column = log.observations.type_index(system, code).unwrap();
    let pvt = log
        .nav_pvt
        .iter()
        .min_by(|a, b| {
            (a.gps_time_s - epoch.gps_time_s)
                .abs()
                .total_cmp(&(b.gps_time_s - epoch.gps_time_s).abs())
        })
        .unwrap();
    let rx = geodetic_to_ecef(Geodetic::new(pvt.lla.x, pvt.lla.y, pvt.lla.z));
    states
        .map(|(prn, state_at)| {
            let sat = epoch
                .satellites
                .iter()
                .find(|s| s.system == system && s.prn == prn)
                .unwrap();
            let rho = sat.values[column].unwrap();
            let state = state_at(epoch.gps_time_s, -rho / SPEED_OF_LIGHT_M_S);
            let range = predicted_range(
                &state.position_ecef,
                &state.velocity_ecef,
                &rx,
                &Vector3::zeros(),
            );
            rho + SPEED_OF_LIGHT_M_S * state.clock_bias_s - range.range_m
        })
        .collect()
}

/// Residuals whose mean is the walk's receiver clock (about −1.5 ms, the
/// data README) and which scatter about it by the atmosphere and noise
/// (metres), not by a misread field (kilometres).
/// Checks the common receiver clock (about −1.5 ms) and each residual's
/// distance from it; returns the clock, ms, and the largest distance, m.
fn assert_clock_and_scatter(residuals: &[f64]) -> (f64, f64) {
    let mean = residuals.iter().sum::<f64>() / residuals.len() as f64;
    let spread: Vec<String> = residuals
        .iter()
        .map(|r| format!("{:.1}", r - mean))
        .collect();
    eprintln!(
        "pseudorange residuals: receiver clock {:.3} ms, about it (m): {}",
        mean / SPEED_OF_LIGHT_M_S * 1e3,
        spread.join(" ")
    );
    assert!(
        (mean / SPEED_OF_LIGHT_M_S + 1.5e-3).abs() < 0.3e-3,
        "{mean}"
    );
    for r in residuals {
        assert!((r - mean).abs() < 15.0, "{residuals:?}");
    }
    let spread = residuals
        .iter()
        .map(|r| (r - mean).abs())
        .fold(0.0, f64::max);
    (mean / SPEED_OF_LIGHT_M_S * 1e3, spread)
}

/// The largest position (m) and clock (m, × c) differences between two
/// evaluations of the same ephemeris over ±2 h of t_oe, every 5 min.
fn largest_differences(
    orbit: &BroadcastOrbit,
    a: impl Fn(f64, f64) -> SatelliteState,
    b: impl Fn(f64, f64) -> SatelliteState,
) -> (f64, f64) {
    let mut worst = (0.0f64, 0.0f64);
    let steps = (2.0 * EPHEMERIS_VALIDITY_S / 300.0) as i32;
    for k in 0..=steps {
        let offset = -EPHEMERIS_VALIDITY_S + 300.0 * f64::from(k);
        let (x, y) = (a(orbit.toe_gps_s, offset), b(orbit.toe_gps_s, offset));
        worst.0 = worst.0.max((x.position_ecef - y.position_ecef).norm());
        worst.1 = worst
            .1
            .max(SPEED_OF_LIGHT_M_S * (x.clock_bias_s - y.clock_bias_s).abs());
    }
    worst
}

#[test]
fn walk_beidou_d1_orbits_and_clocks_equal_the_rinex_nav() {
    let log = walk();
    let mut prns: Vec<u16> = log.beidou_ephemerides.iter().map(|e| e.prn).collect();
    prns.sort_unstable();
    prns.dedup();
    // The data README: D1 for 8 BeiDou satellites, C50 unhealthy; the
    // RINEX file another converter made holds the same 8.
    assert_eq!(prns, [11, 21, 22, 34, 42, 43, 44, 50]);
    let healthy = log
        .beidou_ephemerides
        .iter()
        .filter(|e| e.is_healthy())
        .count();
    assert!(healthy >= 7, "{healthy} healthy");
    // Every word passes its BCH check; one subframe (C36's subframe 2)
    // carries an SOW of 639 861 s, beyond the week: counted, not used.
    assert!(!log.skipped.keys().any(|k| k.contains("BCH")));
    assert_eq!(log.skipped["BeiDou D1 subframes malformed"], 1);
    let nav = read_broadcast_nav(shared_data(WALK_NAV)).unwrap();
    assert_eq!(nav.beidou.len(), 8);
    let mut compared = 0;
    let mut worst = (0.0f64, 0.0f64);
    for e in &log.beidou_ephemerides {
        let Some(r) = nav
            .beidou
            .iter()
            .find(|r| r.prn == e.prn && r.aode == e.aode && r.orbit.toe_gps_s == e.orbit.toe_gps_s)
        else {
            continue;
        };
        compared += 1;
        assert_eq!(
            (e.sat_h1, e.aodc, e.bdt_week, e.urai),
            (r.sat_h1, r.aodc, r.bdt_week, r.urai),
            "C{:02}",
            e.prn
        );
        assert_eq!(e.is_healthy(), e.prn != 50, "C{:02}", e.prn);
        // The clock of B1I (TGD1) is what the comparison checks, so the
        // group delays are checked too.
        let (position, clock) = largest_differences(
            &e.orbit,
            |t, dt| with_b1i(e.state_at(t, dt), e.tgd1_s),
            |t, dt| with_b1i(r.state_at(t, dt), r.tgd1_s),
        );
        assert!(
            position < 0.01 && clock < 0.01,
            "C{:02}: {position} m, {clock} m",
            e.prn
        );
        worst = (worst.0.max(position), worst.1.max(clock));
    }
    assert_eq!(compared, 8);
    eprintln!(
        "BeiDou: {} D1 ephemerides ({healthy} healthy), {compared} against the RINEX: \
         largest differences {:.2e} m position, {:.2e} m clock",
        log.beidou_ephemerides.len(),
        worst.0,
        worst.1
    );
    Figures::new("walk_beidou")
        .add("position_mm", 1e3 * worst.0, 0.005)
        .add("clock_m", worst.1, 5e-9)
        .check_or_write();
}

/// A B3I state as a B1I user's: the clock less TGD1 (B1I ICD §5.2.4.10).
fn with_b1i(mut s: SatelliteState, tgd1_s: f64) -> SatelliteState {
    s.clock_bias_s -= tgd1_s;
    s
}

/// Beside each measurement of the walk's three systems: the signal it was
/// taken from, whose C/N0 is the log's S observation of that signal, and
/// the satellite's elevation at the reference position, recomputed here
/// from the local vertical (geodetic normal).
#[test]
fn walk_measurements_carry_their_signal_strength_and_elevation() {
    let log = walk();
    let nav = log.broadcast_nav();
    let reference = log.observations.approx_position_ecef.unwrap();
    let options = ObservableOptions {
        systems: GnssSystem::DEFAULT_MEASURED.to_vec(),
        elevation_mask_rad: 5f64.to_radians(),
        min_cn0_db_hz: 20.0,
        ..ObservableOptions::new(reference)
    };
    let (epochs, signals) =
        broadcast_epochs_with_signals(&log.observations, &nav, &options).unwrap();
    assert_eq!(
        epochs,
        broadcast_epochs(&log.observations, &nav, &options).unwrap()
    );
    let g = ecef_to_geodetic(&reference);
    let (lat, lon) = (g.latitude_rad, g.longitude_rad);
    let up = Vector3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin());
    let mut names = std::collections::BTreeSet::new();
    let mut checked = 0;
    for ((epoch, received), observed) in epochs.iter().zip(&signals).zip(&log.observations.epochs) {
        assert_eq!(epoch.measurements.len(), received.len());
        for (m, signal) in epoch.measurements.iter().zip(received) {
            let letter = m.system.letter();
            // RINEX 3 codes of the signals (RINEX 3.05 §5.1, table 4).
            let code = match signal.name {
                "L1 C/A" | "E1 C" => "S1C",
                "E1 B" => "S1B",
                "B1I" => "S2I",
                "B2I" => "S7I",
                "B3I" => "S6I",
                other => panic!("unexpected signal {other}"),
            };
            let satellite = observed
                .satellites
                .iter()
                .find(|s| s.system == letter && satellite_number(m.system, s.prn) == m.sat_id)
                .unwrap();
            let column = log.observations.type_index(letter, code).unwrap();
            assert_eq!(Some(signal.cn0_db_hz), satellite.values[column]);
            assert!(
                (20.0..=60.0).contains(&signal.cn0_db_hz),
                "{}",
                signal.cn0_db_hz
            );
            let elevation = up.dot(&(m.position_ecef - reference).normalize()).asin();
            assert!((signal.elevation_rad - elevation).abs() < 1e-9);
            assert!(signal.elevation_rad >= 5f64.to_radians());
            names.insert((letter, signal.name));
            checked += 1;
        }
    }
    assert!(checked > 9_000, "{checked}");
    assert_eq!(
        names.into_iter().collect::<Vec<_>>(),
        [('C', "B3I"), ('E', "E1 C"), ('G', "L1 C/A")]
    );
}
