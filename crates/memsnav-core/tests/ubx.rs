//! The UBX reader on the walk's raw u-blox log (shared data): its GPS LNAV
//! ephemerides against the RINEX navigation file another converter made
//! from the same log, its epochs and messages as the data README counts
//! them, and the RINEX 3 files written from it read back by the project's
//! readers; its Galileo I/NAV ephemerides against its own pseudoranges.
//! The excerpt in tests/data gives the same ephemerides.

mod shared_data;

use std::path::PathBuf;

use memsnav_core::geodesy::wgs84::SPEED_OF_LIGHT_M_S;
use memsnav_core::geodesy::{geodetic_to_ecef, Geodetic};
use memsnav_core::gnss::{
    format_rinex_nav, format_rinex_obs, parse_rinex_nav, parse_rinex_obs, predicted_range,
    read_rinex_nav, GpsEphemeris, InavEphemeris, RinexProvenance,
};
use memsnav_core::logs::{read_ubx, UbxLog};
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
        &format_rinex_nav(&log.gps_ephemerides, &log.galileo_ephemerides, &header),
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
    assert_eq!(head.galileo_ephemerides, log.galileo_ephemerides);
}

/// The Keplerian fields of a Galileo ephemeris in the GPS record, to put
/// its satellites on the sky with the GPS user algorithm: Galileo's GM
/// (3.986004418e14) differs from GPS's by 1.5e-7, which moves a satellite
/// by under 0.5 m at 30 min from t_oe, far inside this check.
fn as_gps(e: &InavEphemeris) -> GpsEphemeris {
    GpsEphemeris {
        prn: e.svid,
        toc_gps_s: e.toc_gps_s,
        toe_gps_s: e.toe_gps_s,
        af0_s: e.af0_s,
        af1_s_s: e.af1_s_s,
        af2_s_s2: e.af2_s_s2,
        crs_m: e.crs_m,
        delta_n_rad_s: e.delta_n_rad_s,
        m0_rad: e.m0_rad,
        cuc_rad: e.cuc_rad,
        eccentricity: e.eccentricity,
        cus_rad: e.cus_rad,
        sqrt_a_sqrt_m: e.sqrt_a_sqrt_m,
        cic_rad: e.cic_rad,
        omega0_rad: e.omega0_rad,
        cis_rad: e.cis_rad,
        i0_rad: e.i0_rad,
        crc_m: e.crc_m,
        omega_rad: e.omega_rad,
        omega_dot_rad_s: e.omega_dot_rad_s,
        idot_rad_s: e.idot_rad_s,
        health: u32::from(e.e1b_health),
        tgd_s: e.bgd_e1_e5b_s,
        fit_interval_h: 4.0,
    }
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
    let epoch = &log.observations.epochs[268];
    let c1c = log.observations.type_index('E', "C1C").unwrap();
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
    let mut residuals = Vec::new();
    for e in log.galileo_ephemerides.iter().filter(|e| e.is_healthy()) {
        let sat = epoch
            .satellites
            .iter()
            .find(|s| s.system == 'E' && s.prn == e.svid)
            .unwrap();
        let rho = sat.values[c1c].unwrap();
        let state = as_gps(e).state_at(epoch.gps_time_s, -rho / SPEED_OF_LIGHT_M_S);
        let range = predicted_range(
            &state.position_ecef,
            &state.velocity_ecef,
            &rx,
            &Vector3::zeros(),
        );
        residuals.push(rho + SPEED_OF_LIGHT_M_S * state.clock_bias_s - range.range_m);
    }
    let mean = residuals.iter().sum::<f64>() / residuals.len() as f64;
    // The receiver clock: about -1.5 ms (the data README).
    assert!(
        (mean / SPEED_OF_LIGHT_M_S + 1.5e-3).abs() < 0.3e-3,
        "{mean}"
    );
    for r in &residuals {
        assert!((r - mean).abs() < 15.0, "{residuals:?}");
    }
}
