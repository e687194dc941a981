//! The ionosphere measured from a second signal
//! (`ObservableOptions::dual_frequency_ionosphere`) on the walk's raw
//! u-blox log (shared data): a delay added to both codes by the 1/f² law
//! (IS-GPS-200 §20.3.3.3.3.3) leaves the corrected pseudoranges as they
//! were, whatever its size, while the broadcast model would keep it; a
//! satellite group delay moved in the ephemeris and in the observations as
//! the ICDs define it (GPS: (Δt_SV)_X = Δt_SV − T_GD + ISC_X, IS-GPS-200
//! §30.3.3.3.1.1.1; Galileo: BGD(f1,f2) = (TR1 − TR2) / (1 − (f1/f2)²),
//! OS SIS ICD §5.1.5) changes nothing either, and moved in the ephemeris
//! alone it does.

mod shared_data;

use memsnav_core::geodesy::wgs84::SPEED_OF_LIGHT_M_S;
use memsnav_core::gnss::{
    broadcast_epochs, broadcast_epochs_with_signals, BroadcastNav, GnssEpoch, GnssSystem,
    ObservableOptions, ObservationFile, PseudorangeWeighting,
};
use memsnav_core::logs::{read_ubx, UbxLog};
use shared_data::shared_data;

const WALK_UBX: &str = "real-imu-gnss/walk_0827/gnss_1730.ubx";
const L1_HZ: f64 = 1_575.42e6;

/// Each system's second signal on the walk and its frequency: GPS L2C
/// (the log's CNAV flags L5 unhealthy), Galileo E5a.
fn second_signal(system: char) -> (&'static str, f64) {
    match system {
        'G' => ("C2L", 1_227.60e6),
        _ => ("C5Q", 1_176.45e6),
    }
}

/// (f₁/f₂)² of `system`'s two signals.
fn gamma(system: char) -> f64 {
    (L1_HZ / second_signal(system).1).powi(2)
}

fn walk() -> UbxLog {
    read_ubx(shared_data(WALK_UBX)).unwrap()
}

fn options(log: &UbxLog, dual_frequency_ionosphere: bool) -> ObservableOptions {
    ObservableOptions {
        systems: GnssSystem::DEFAULT_MEASURED.to_vec(),
        elevation_mask_rad: 5f64.to_radians(),
        min_cn0_db_hz: 20.0,
        dual_frequency_ionosphere,
        ..ObservableOptions::new(log.observations.approx_position_ecef.unwrap())
    }
}

/// Adds `l1_m(system, prn)` to each GPS and Galileo satellite's L1/E1
/// code (`C1C`) and `second_m(system, prn)` to its second signal's.
fn shift_codes(
    observations: &mut ObservationFile,
    l1_m: impl Fn(char, u16) -> f64,
    second_m: impl Fn(char, u16) -> f64,
) {
    let columns: Vec<(char, usize, usize)> = ['G', 'E']
        .into_iter()
        .map(|s| {
            (
                s,
                observations.type_index(s, "C1C").unwrap(),
                observations.type_index(s, second_signal(s).0).unwrap(),
            )
        })
        .collect();
    for epoch in &mut observations.epochs {
        for sat in &mut epoch.satellites {
            if let Some(&(s, c1, c5)) = columns.iter().find(|(s, ..)| *s == sat.system) {
                let prn = sat.prn;
                if let Some(v) = sat.values[c1].as_mut() {
                    *v += l1_m(s, prn);
                }
                if let Some(v) = sat.values[c5].as_mut() {
                    *v += second_m(s, prn);
                }
            }
        }
    }
}

/// The largest difference between the corrected pseudoranges of two sets
/// of epochs of the same satellites, m, and how many were compared.
fn largest_difference(a: &[GnssEpoch], b: &[GnssEpoch]) -> (f64, usize) {
    let mut worst: f64 = 0.0;
    let mut count = 0;
    for (ea, eb) in a.iter().zip(b) {
        assert_eq!(ea.measurements.len(), eb.measurements.len());
        for (ma, mb) in ea.measurements.iter().zip(&eb.measurements) {
            assert_eq!(ma.sat_id, mb.sat_id);
            worst = worst.max((ma.pseudorange_m - mb.pseudorange_m).abs());
            count += 1;
        }
    }
    (worst, count)
}

/// Each satellite's delay on L1, m: 3 to 21 m, different per satellite.
fn delay_l1_m(system: char, prn: u16) -> f64 {
    3.0 + 3.0 * f64::from(prn % 7) + if system == 'E' { 0.5 } else { 0.0 }
}

#[test]
fn a_measured_ionosphere_is_taken_out_whatever_its_size() {
    let log = walk();
    let nav = log.broadcast_nav();
    let mut delayed = log.observations.clone();
    shift_codes(&mut delayed, delay_l1_m, |s, prn| {
        gamma(s) * delay_l1_m(s, prn)
    });
    let dual = options(&log, true);
    let (worst, count) = largest_difference(
        &broadcast_epochs(&log.observations, &nav, &dual).unwrap(),
        &broadcast_epochs(&delayed, &nav, &dual).unwrap(),
    );
    // What is left: the transmission time moves by delay / c, and with it
    // the satellite (≤ 1 km/s · 70 ns).
    assert!(count > 10_000, "{count}");
    assert!(worst < 1e-3, "{worst} m");
    // The broadcast model keeps the delay: the comparison can fail.
    let single = options(&log, false);
    let (kept, _) = largest_difference(
        &broadcast_epochs(&log.observations, &nav, &single).unwrap(),
        &broadcast_epochs(&delayed, &nav, &single).unwrap(),
    );
    assert!(kept > 20.0, "{kept} m");
}

#[test]
fn group_delays_are_applied_as_the_icds_define_them() {
    let log = walk();
    let nav = log.broadcast_nav();
    let dual = options(&log, true);
    let before = broadcast_epochs(&log.observations, &nav, &dual).unwrap();
    // GPS: ISC_L2C up by δ lowers L2C's group delay T_GD − ISC by δ;
    // Galileo: BGD(E1,E5a) up by δ raises E5a's by ((f_E1/f_E5a)² − 1) δ.
    let delta_s = 5e-9;
    let moved = BroadcastNav {
        gps_group_delays: nav
            .gps_group_delays
            .iter()
            .map(|(&prn, d)| {
                let mut d = *d;
                d.isc_l2c_s = d.isc_l2c_s.map(|isc| isc + delta_s);
                (prn, d)
            })
            .collect(),
        galileo: nav
            .galileo
            .iter()
            .map(|e| {
                let mut e = *e;
                e.bgd_e1_e5a_s += delta_s;
                e
            })
            .collect(),
        ..nav.clone()
    };
    let (changed, _) = largest_difference(
        &before,
        &broadcast_epochs(&log.observations, &moved, &dual).unwrap(),
    );
    assert!(changed > 1.0, "{changed} m");
    let mut observed = log.observations.clone();
    let c = SPEED_OF_LIGHT_M_S;
    shift_codes(
        &mut observed,
        |_, _| 0.0,
        |s, _| match s {
            'G' => -c * delta_s,
            s => c * (gamma(s) - 1.0) * delta_s,
        },
    );
    let (worst, count) = largest_difference(
        &before,
        &broadcast_epochs(&observed, &moved, &dual).unwrap(),
    );
    assert!(count > 10_000, "{count}");
    assert!(worst < 1e-3, "{worst} m");
}

/// On the walk every GPS satellite has L2C and CNAV's inter-signal
/// corrections (L5 too, but flagged unhealthy: its ISCs are not used),
/// every Galileo one E5a and I/NAV's BGD(E1,E5a); its BeiDou
/// signals (B1C, B2a, B3I) pair no two whose D1 group delays are known, so
/// BeiDou keeps the broadcast model. The measured delays' uncertainty is in
/// the pseudoranges' σ: added to the signal-strength σ `navigate` uses (RTKLIB's
/// model swaps its Klobuchar term for it instead, which orders neither way).
#[test]
fn the_walk_measures_gps_and_galileo_and_models_beidou() {
    let log = walk();
    let nav = log.broadcast_nav();
    let options = |log: &UbxLog, dual: bool| ObservableOptions {
        weighting: PseudorangeWeighting::SignalStrength,
        ..options(log, dual)
    };
    assert_eq!(nav.gps_group_delays.len(), 7);
    assert!(nav
        .gps_group_delays
        .values()
        .all(|d| d.isc_l2c_s.is_some() && d.isc_l5q5_s.is_none()));
    let (dual, signals) =
        broadcast_epochs_with_signals(&log.observations, &nav, &options(&log, true)).unwrap();
    let single = broadcast_epochs(&log.observations, &nav, &options(&log, false)).unwrap();
    let mut seen = std::collections::BTreeMap::new();
    for ((epoch, received), modelled) in dual.iter().zip(&signals).zip(&single) {
        for ((m, signal), k) in epoch
            .measurements
            .iter()
            .zip(received)
            .zip(&modelled.measurements)
        {
            let expected = match m.system {
                GnssSystem::Gps => Some("L2C (L)"),
                GnssSystem::Galileo => Some("E5a Q"),
                GnssSystem::Beidou | GnssSystem::Glonass => None,
            };
            assert_eq!(signal.ionosphere_signal, expected, "satellite {}", m.sat_id);
            if expected.is_some() {
                assert!(m.pseudorange_std_m > k.pseudorange_std_m);
            } else {
                assert_eq!(m.pseudorange_m, k.pseudorange_m);
            }
            *seen.entry(m.system.letter()).or_insert(0) += 1;
        }
    }
    assert_eq!(seen.len(), 3, "{seen:?}");
}
