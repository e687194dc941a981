//! RINEX files written by other tools (teqc, gLAB, Trimble's converter,
//! the IGS merge): excerpts in `tests/data/rinex-public` (sources and
//! licences in its README) read whole, with the values the files hold.

mod figures;

use std::path::{Path, PathBuf};

use figures::Figures;
use memsnav_core::gnss::{
    checked_gps_time_from_calendar, event_kind, read_broadcast_nav, read_rinex_obs, read_sp3,
};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/rinex-public")
        .join(name)
}

/// A CORS station's teqc file (RINEX 2.11, GPS, GLONASS and Galileo, 20
/// observation types over four lines a satellite).
#[test]
fn cors_rinex_2_11_file_reads_whole() {
    let f = read_rinex_obs(data("slac1180_excerpt.21o")).unwrap();
    assert_eq!(f.version, 2.11);
    assert!(f.warnings.is_empty() && f.skipped.is_empty(), "{f:?}");
    assert_eq!(f.epochs.len(), 5);
    let t0 = checked_gps_time_from_calendar(2021, 4, 28, 19, 0, 0.0).unwrap();
    for (k, e) in f.epochs.iter().enumerate() {
        assert_eq!(e.gps_time_s, t0 + 30.0 * k as f64);
    }
    let e = &f.epochs[0];
    assert_eq!(e.satellites.len(), 25);
    let count = |s: char| e.satellites.iter().filter(|x| x.system == s).count();
    assert_eq!((count('G'), count('R'), count('E')), (12, 7, 6));
    // The file's first satellite, G15: L1 with signal strength 7, L2,
    // C1, P2 on the first line; S1, S2, C2 on the second.
    let g15 = &e.satellites[0];
    assert_eq!((g15.system, g15.prn), ('G', 15));
    let value = |code: &str| g15.values[f.type_index('G', code).unwrap()];
    assert_eq!(value("L1C"), Some(122610995.213));
    assert_eq!(value("L2W"), Some(95540973.904));
    assert_eq!(value("C1C"), Some(23332073.875));
    assert_eq!(value("C2W"), Some(23332083.105));
    assert_eq!(value("C1W"), None);
    assert_eq!(value("S1C"), Some(42.2));
    assert_eq!(value("C2X"), Some(23332082.176));
    // GLONASS has no L5, L6, L7, L8 signals: its list is shorter.
    assert!(f.type_index('R', "C1C").is_some() && f.type_index('R', "C5X").is_none());
    assert_eq!(f.type_index('E', "C8X").map(|_| ()), Some(()));
}

/// A Trimble converter's mixed file whose records include events with
/// blank epoch fields: two flag 2 (start moving antenna, a comment line
/// each) and one flag 3 (new site occupation, five header lines).
#[test]
fn event_records_with_blank_epochs_are_counted() {
    let f = read_rinex_obs(data("14601736.18o")).unwrap();
    let count = |flag| f.skipped.get(&event_kind(flag)).copied();
    assert_eq!((count(2), count(3), count(4)), (Some(2), Some(1), None));
    assert!(event_kind(3).contains("new site occupation"));
    assert_eq!(f.epochs.len(), 3);
    let e = &f.epochs[0];
    assert_eq!(e.satellites.len(), 12);
    let e07 = &e.satellites[0];
    assert_eq!((e07.system, e07.prn), ('E', 7));
    assert_eq!(f.observation_types[&'E'], ["C1X", "C8X", "L1X", "L8X"]);
    assert_eq!(e07.values[0], Some(25808828.891));
    // L1 on the first line with loss-of-lock digit 1; L8 blank.
    assert_eq!(e07.values[2], Some(135626313.276));
    assert_eq!(e07.lli[2], 1);
    assert_eq!(e07.values[3], None);
}

/// gLAB's mixed example: GPS, GLONASS and SBAS, 14 satellites over two
/// list lines, blank-padded PRNs ("G 7"), the receiver clock offset after
/// the list.
#[test]
fn mixed_rinex_2_11_with_continued_satellite_lists() {
    let f = read_rinex_obs(data("demo.10o")).unwrap();
    assert!(f.warnings.is_empty(), "{:?}", f.warnings);
    let e = &f.epochs[0];
    let names: Vec<String> = e
        .satellites
        .iter()
        .map(|s| format!("{}{:02}", s.system, s.prn))
        .collect();
    assert_eq!(
        names,
        [
            "G13", "R19", "G32", "G07", "R23", "G31", "G20", "R11", "G12", "G26", "G09", "G21",
            "G15", "S24"
        ]
    );
    assert_eq!(
        f.observation_types.keys().collect::<String>(),
        "GRS",
        "Galileo declared by the mixed file but never observed is left out"
    );
    // SBAS has no P code: its list is L1, C1, S1 (and no L2, P1, P2, S2).
    assert_eq!(f.observation_types[&'S'], ["L1C", "C1C", "S1C"]);
}

/// GLONASS broadcast orbits of an IGS daily file (RINEX 2 `g`), integrated
/// by the ICD's Runge-Kutta scheme from the t_b nearest each epoch, agree
/// with CODE's precise orbits of the same day (centre of mass, IGS14) to
/// a few metres: t_b's UTC, the leap seconds and the PZ-90.11 ≈ ITRF frame
/// each checked (18 s off would be 70 km; a frame rotation of 1 mas 0.13 m).
#[test]
fn glonass_broadcast_orbits_agree_with_precise_orbits() {
    let nav = read_broadcast_nav(data("brdc1360_excerpt.20g")).unwrap();
    let sp3 = read_sp3(data("COD0MGXFIN_20201360000_R_excerpt.SP3")).unwrap();
    assert_eq!(nav.glonass.len(), 100);
    assert!(
        nav.gps.is_empty() && nav.skipped.is_empty(),
        "{:?}",
        nav.skipped
    );
    let mut errors = Vec::new();
    for (k, &t) in sp3.time_gps_s.iter().enumerate() {
        for (j, name) in sp3.satellites.iter().enumerate() {
            let slot: u16 = name[1..].parse().unwrap();
            let Some(eph) = nav
                .glonass
                .iter()
                .filter(|e| e.slot == slot && (e.tb_gps_s - t).abs() <= 900.0)
                .min_by(|a, b| (a.tb_gps_s - t).abs().total_cmp(&(b.tb_gps_s - t).abs()))
            else {
                continue;
            };
            let precise = sp3.position(k, j);
            if precise.iter().all(|x| x.is_finite()) {
                errors.push((eph.state(t).position_ecef - precise).norm());
            }
        }
    }
    let n = errors.len() as f64;
    let rms = (errors.iter().map(|e| e * e).sum::<f64>() / n).sqrt();
    let max = errors.iter().copied().fold(0.0, f64::max);
    // 17 epochs × 23 satellites, every one with an ephemeris within 15 min.
    assert!(errors.len() >= 17 * 22, "{}", errors.len());
    // GLONASS broadcast orbits are metre-level (GPS's on the 2021 day agree
    // to 1.3 m); docs/how-to/convert-ublox.md shows these.
    assert!(
        rms < 4.5 && max < 12.0,
        "rms {rms:.2} m, max {max:.2} m over {n}"
    );
    Figures::new("glonass_broadcast_vs_precise")
        .add("rms_m", rms, 0.005)
        .add("max_m", max, 0.05)
        .add("compared", n, 0.0)
        .check_or_write();
}

/// The same ephemeris as a RINEX 3 `R` record of the IGS merged file reads
/// to the same values as the RINEX 2 record.
#[test]
fn glonass_rinex_3_and_2_records_agree() {
    let v3 = read_broadcast_nav(data("BRDC00IGS_R_20201360000_excerpt_MN.rnx")).unwrap();
    let v2 = read_broadcast_nav(data("brdc1360_excerpt.20g")).unwrap();
    assert_eq!((v3.glonass.len(), v3.gps.len()), (2, 1));
    for e in &v3.glonass {
        let twin = v2
            .glonass
            .iter()
            .find(|x| (x.slot, x.tb_gps_s) == (e.slot, e.tb_gps_s))
            .unwrap();
        assert!((e.position_ecef - twin.position_ecef).amax() < 1e-3);
        assert!((e.velocity_ecef - twin.velocity_ecef).amax() < 1e-6);
        assert!((e.tau_n_s - twin.tau_n_s).abs() < 1e-15);
        assert_eq!(e.frequency_channel, twin.frequency_channel);
    }
}

/// A RINEX 2.12 Galileo navigation file (teqc, UNAVCO) reads to the same
/// I/NAV ephemerides as the station's RINEX 3.03 mixed file of the day
/// (Septentrio's sbf2rin).
#[test]
fn galileo_rinex_2_12_navigation_file_matches_the_rinex_3_one() {
    let v2 = read_broadcast_nav(data("ceda2100.18e")).unwrap();
    let v3 = read_broadcast_nav(data("CEDA00USA_R_20182100000_01D_MN.rnx")).unwrap();
    assert!(v2.gps.is_empty() && v2.glonass.is_empty());
    // 29 records: 21 I/NAV, 8 F/NAV (counted, their clock is E5a,E1).
    assert_eq!(v2.galileo.len(), 21, "{:?}", v2.skipped);
    assert_eq!(v2.skipped["Galileo F/NAV records (clock E5a,E1)"], 8);
    let mut matched = 0;
    for e in &v2.galileo {
        let Some(twin) = v3
            .galileo
            .iter()
            .find(|x| x.svid == e.svid && x.orbit.toc_gps_s == e.orbit.toc_gps_s)
        else {
            continue;
        };
        matched += 1;
        assert_eq!(e.orbit, twin.orbit, "E{:02}", e.svid);
        assert_eq!((e.iod_nav, e.sisa_index), (twin.iod_nav, twin.sisa_index));
    }
    assert!(matched >= 20, "{matched} of {}", v2.galileo.len());
}

/// Precise orbits between their epochs: with one epoch left out, the
/// 10-point Lagrange interpolation of the others gives it back to
/// millimetres; at an epoch it gives the file's value; its velocity is the
/// position's rate.
#[test]
fn sp3_interpolation_recovers_a_left_out_epoch() {
    let sp3 = read_sp3(data("COD0MGXFIN_20201360000_R_excerpt.SP3")).unwrap();
    let n = sp3.satellites.len();
    let left_out = 8;
    let mut thinned = sp3.clone();
    thinned.time_gps_s.remove(left_out);
    thinned
        .position_ecef
        .drain(left_out * n..(left_out + 1) * n);
    thinned.clock_s.drain(left_out * n..(left_out + 1) * n);
    let t = sp3.time_gps_s[left_out];
    let mut worst: f64 = 0.0;
    for sat in 0..n {
        let truth = sp3.position(left_out, sat);
        if !truth.iter().all(|x| x.is_finite()) {
            continue;
        }
        let s = thinned.state_at(sat, t).unwrap();
        worst = worst.max((s.position_ecef - truth).norm());
        let at_epoch = sp3.state_at(sat, sp3.time_gps_s[3]).unwrap();
        assert!((at_epoch.position_ecef - sp3.position(3, sat)).norm() < 1e-6);
        let (before, after) = (
            thinned.state_at(sat, t - 0.5).unwrap(),
            thinned.state_at(sat, t + 0.5).unwrap(),
        );
        let rate = after.position_ecef - before.position_ecef;
        assert!(
            (s.velocity_ecef - rate).norm() < 1e-3,
            "{}",
            (s.velocity_ecef - rate).norm()
        );
    }
    // Millimetres at worst over the 22 GLONASS satellites there
    // (docs/how-to/convert-ublox.md shows it to 0.1 mm).
    assert!(worst < 0.01, "{worst}");
    Figures::new("sp3_left_out_epoch")
        .add("worst_mm", 1e3 * worst, 0.05)
        .check_or_write();
    // Outside the file: none.
    assert!(sp3.state_at(0, sp3.time_gps_s[0] - 1.0).is_none());
}
