//! The UBX reader on the walk's raw u-blox log (shared data): its GPS LNAV
//! ephemerides against the RINEX navigation file another converter made
//! from the same log, its epochs and messages as the data README counts
//! them, and the RINEX 3 files written from it read back by the project's
//! readers. The excerpt in tests/data gives the same ephemerides.

mod shared_data;

use std::path::PathBuf;

use memsnav_core::gnss::{
    format_rinex_nav, format_rinex_obs, parse_rinex_nav, parse_rinex_obs, read_rinex_nav,
    GpsEphemeris, RinexProvenance,
};
use memsnav_core::logs::{read_ubx, UbxLog};
use shared_data::shared_data;

const WALK_UBX: &str = "real-imu-gnss/walk_0827/gnss_1730.ubx";
const WALK_NAV: &str = "real-imu-gnss/walk_0827/gnss_1730.nav";

fn walk() -> UbxLog {
    read_ubx(shared_data(WALK_UBX)).unwrap()
}

/// Every field of two ephemerides as (name, a, b).
fn fields(a: &GpsEphemeris, b: &GpsEphemeris) -> Vec<(&'static str, f64, f64)> {
    vec![
        ("toc", a.toc_gps_s, b.toc_gps_s),
        ("toe", a.toe_gps_s, b.toe_gps_s),
        ("af0", a.af0_s, b.af0_s),
        ("af1", a.af1_s_s, b.af1_s_s),
        ("af2", a.af2_s_s2, b.af2_s_s2),
        ("crs", a.crs_m, b.crs_m),
        ("delta_n", a.delta_n_rad_s, b.delta_n_rad_s),
        ("m0", a.m0_rad, b.m0_rad),
        ("cuc", a.cuc_rad, b.cuc_rad),
        ("e", a.eccentricity, b.eccentricity),
        ("cus", a.cus_rad, b.cus_rad),
        ("sqrt_a", a.sqrt_a_sqrt_m, b.sqrt_a_sqrt_m),
        ("cic", a.cic_rad, b.cic_rad),
        ("omega0", a.omega0_rad, b.omega0_rad),
        ("cis", a.cis_rad, b.cis_rad),
        ("i0", a.i0_rad, b.i0_rad),
        ("crc", a.crc_m, b.crc_m),
        ("omega", a.omega_rad, b.omega_rad),
        ("omega_dot", a.omega_dot_rad_s, b.omega_dot_rad_s),
        ("idot", a.idot_rad_s, b.idot_rad_s),
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
    for l in &log.gps_ephemerides {
        let other = nav.iter().find(|n| n.prn == l.ephemeris.prn).unwrap();
        // The file prints 12 significant digits.
        assert_same(&l.ephemeris, other, 11);
        assert_eq!((l.ephemeris.health, l.ura_index), (0, 0));
    }
    // Every word passed its parity (the README), every frame its checksum.
    assert!(
        !log.skipped
            .keys()
            .any(|k| k.contains("parity") || k.contains("checksum") || k.contains("malformed")),
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
    let nav = parse_rinex_nav(
        &format_rinex_nav(&log.gps_ephemerides, &header),
        "written.nav",
    )
    .unwrap();
    assert_eq!(nav.len(), log.gps_ephemerides.len());
    for (back, l) in nav.iter().zip(&log.gps_ephemerides) {
        // D19.12 keeps 13 significant digits.
        assert_same(back, &l.ephemeris, 12);
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

#[test]
fn the_excerpt_gives_the_same_ephemerides() {
    let excerpt = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/real-imu-gnss/walk_head.ubx");
    let head = read_ubx(excerpt).unwrap();
    let log = walk();
    assert_eq!(head.rawx.len(), 20);
    assert_eq!(head.gps_ephemerides, log.gps_ephemerides);
}
