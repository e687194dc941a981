//! The decoded ephemerides judged as memsnav's RINEX reader judges a file
//! of them: each record's values within the ranges its navigation message
//! can carry ([`crate::gnss::broadcast_ranges`]: an orbit inside the
//! Earth, a clock error of seconds are corrupted words that passed the
//! parity or CRC), then one ephemeris per satellite and t_oc and per
//! satellite and issue of data ([`crate::gnss::ephemeris_conflicts`]).
//! What fails is left out and counted, so the log's ephemerides are the
//! ones a RINEX file of them would give back.

use crate::gnss::broadcast_ranges::check_value;
use crate::gnss::ephemeris_conflicts;
use crate::gnss::nav_record::{orbit_values, NavRecord};
use crate::gnss::{BeidouEphemeris, CnavEphemeris, InavEphemeris, LnavEphemeris, SECONDS_PER_WEEK};

use super::Problems;

/// The checked ephemerides of a log.
pub(super) struct Checked {
    pub gps: Vec<LnavEphemeris>,
    pub gps_cnav: Vec<CnavEphemeris>,
    pub galileo: Vec<InavEphemeris>,
    pub beidou: Vec<BeidouEphemeris>,
}

/// Leaves out, and counts in `problems`, the ephemerides whose records hold
/// a value out of range (reason `"{kind} ephemerides out of range"`, a
/// warning naming the value) and those in conflict.
pub(super) fn check(mut e: Checked, file: &str, problems: &mut Problems) -> Checked {
    let mut in_range = |kind: &str, record: &NavRecord| match record.out_of_range() {
        None => true,
        Some(reason) => {
            problems.skip(&format!("{kind} ephemerides out of range"), || {
                format!("{file}: {kind} ephemeris: {reason}; skipped")
            });
            false
        }
    };
    e.gps.retain(|l| in_range("GPS LNAV", &NavRecord::lnav(l)));
    e.galileo
        .retain(|g| in_range("Galileo I/NAV", &NavRecord::inav(g)));
    e.beidou
        .retain(|b| in_range("BeiDou D1", &NavRecord::d1(b)));
    e.gps_cnav.retain(|c| {
        let o = &c.orbit;
        let sat = format!("G{:02}", c.prn);
        let values = orbit_values(0.0, o, o.toe_gps_s.rem_euclid(SECONDS_PER_WEEK));
        // The clock and orbit values against LNAV's ranges (slot 3, the
        // issue of data, CNAV has not).
        let out = values
            .iter()
            .enumerate()
            .filter(|&(i, _)| i != 3)
            .find_map(|(i, &v)| check_value(&sat, i, v).err());
        match out {
            None => true,
            Some(reason) => {
                problems.skip("GPS CNAV ephemerides out of range", || {
                    format!("{file}: GPS CNAV ephemeris: {reason}; skipped")
                });
                false
            }
        }
    });
    let records: Vec<NavRecord> = e
        .gps
        .iter()
        .map(NavRecord::lnav)
        .chain(e.galileo.iter().map(NavRecord::inav))
        .chain(e.beidou.iter().map(NavRecord::d1))
        .collect();
    let (keep, conflicts) = ephemeris_conflicts::resolve(&records);
    let mut flags = keep.into_iter();
    e.gps.retain(|_| flags.next().unwrap_or(true));
    e.galileo.retain(|_| flags.next().unwrap_or(true));
    e.beidou.retain(|_| flags.next().unwrap_or(true));
    for (reason, count) in conflicts {
        problems.add(&reason, count);
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gnss::{ephemeris_conflicts, BroadcastOrbit};

    /// GPS week 2381, Thursday 17:30 (t_oc = t_oe).
    const T: f64 = 2381.0 * SECONDS_PER_WEEK + 408_600.0;

    fn orbit(sqrt_a_sqrt_m: f64, toe_gps_s: f64) -> BroadcastOrbit {
        BroadcastOrbit {
            toc_gps_s: toe_gps_s,
            toe_gps_s,
            af0_s: 1e-4,
            af1_s_s: 1e-12,
            af2_s_s2: 0.0,
            crs_m: 10.0,
            delta_n_rad_s: 4e-9,
            m0_rad: 1.0,
            cuc_rad: 1e-6,
            eccentricity: 0.01,
            cus_rad: 1e-6,
            sqrt_a_sqrt_m,
            cic_rad: 1e-7,
            omega0_rad: 2.0,
            cis_rad: 1e-7,
            i0_rad: 0.96,
            crc_m: 200.0,
            omega_rad: -2.0,
            omega_dot_rad_s: -8e-9,
            idot_rad_s: 1e-10,
            a_dot_m_s: 0.0,
            delta_n_dot_rad_s2: 0.0,
        }
    }

    fn lnav(prn: u16, iode: u8, sqrt_a: f64, toe: f64) -> LnavEphemeris {
        LnavEphemeris {
            ephemeris: crate::gnss::GpsEphemeris {
                prn,
                orbit: orbit(sqrt_a, toe),
                health: 0,
                tgd_s: 1e-9,
                fit_interval_h: 4.0,
            },
            iode,
            iodc: u16::from(iode),
            ura_index: 2,
            l2_codes: 1,
            l2p_data_flag: false,
            fit_interval_flag: false,
            toe_week: 2381,
            transmission_gps_s: toe - 30.0,
        }
    }

    fn inav(svid: u16, iod_nav: u16, sqrt_a: f64, toe: f64) -> InavEphemeris {
        InavEphemeris {
            svid,
            iod_nav,
            orbit: orbit(sqrt_a, toe),
            sisa_index: 107,
            bgd_e1_e5a_s: 1e-9,
            bgd_e1_e5b_s: 1e-9,
            e1b_health: 0,
            e5b_health: 0,
            e1b_data_validity: 0,
            e5b_data_validity: 0,
            gst_week: 1357,
            transmission_gps_s: toe - 30.0,
        }
    }

    fn d1(prn: u16, aode: u8, sqrt_a: f64, toe: f64) -> BeidouEphemeris {
        BeidouEphemeris {
            prn,
            aode,
            aodc: 1,
            orbit: orbit(sqrt_a, toe),
            urai: 2,
            sat_h1: 0,
            tgd1_s: 1e-9,
            tgd2_s: 1e-9,
            bdt_week: 1025,
            transmission_gps_s: toe - 30.0,
        }
    }

    fn checked(
        gps: Vec<LnavEphemeris>,
        galileo: Vec<InavEphemeris>,
        beidou: Vec<BeidouEphemeris>,
    ) -> (Checked, Problems) {
        let mut problems = Problems::default();
        let e = Checked {
            gps,
            gps_cnav: Vec::new(),
            galileo,
            beidou,
        };
        (check(e, "x.ubx", &mut problems), problems)
    }

    #[test]
    fn orbits_inside_the_earth_are_skipped_and_named() {
        let (e, problems) = checked(
            vec![lnav(32, 83, 33.6, T), lnav(5, 7, 5153.6, T)],
            vec![inav(11, 50, 64.6, T), inav(12, 50, 5440.6, T)],
            vec![d1(21, 1, 1186.6, T), d1(22, 1, 5282.6, T)],
        );
        assert_eq!(e.gps.len(), 1);
        assert_eq!(e.gps[0].ephemeris.prn, 5);
        assert_eq!((e.galileo.len(), e.galileo[0].svid), (1, 12));
        assert_eq!((e.beidou.len(), e.beidou[0].prn), (1, 22));
        for kind in ["GPS LNAV", "Galileo I/NAV", "BeiDou D1"] {
            assert_eq!(
                problems.skipped[&format!("{kind} ephemerides out of range")],
                1
            );
        }
        assert!(
            problems.warnings.iter().any(|w| w
                == "x.ubx: GPS LNAV ephemeris: sqrt(A) = 3.36e1 for G32 is out of range \
                    (2.53e3 to 8.192e3): not a value the navigation message can carry; skipped"),
            "{:?}",
            problems.warnings
        );
    }

    #[test]
    fn a_second_set_with_the_same_issue_of_data_leaves_both_out() {
        // LNAV and I/NAV: the same IODE / IODnav, t_oe 2 h later (another
        // t_oc too, as the subframe 1 of the second set says).
        let (e, problems) = checked(
            vec![lnav(23, 77, 5153.6, T), lnav(23, 77, 5153.6, T + 7200.0)],
            vec![inav(11, 50, 5440.6, T), inav(11, 50, 5440.6, T + 7200.0)],
            vec![],
        );
        assert!(e.gps.is_empty() && e.galileo.is_empty());
        assert_eq!(problems.skipped[ephemeris_conflicts::SAME_ISSUE_OF_DATA], 4);
        // LNAV and D1: a second subframe 2 with another t_oe keeps subframe
        // 1's t_oc: two sets of one t_oc.
        let mut other = lnav(23, 77, 5153.6, T);
        other.ephemeris.orbit.toe_gps_s += 16.0;
        let mut d1_other = d1(21, 1, 5282.6, T);
        d1_other.orbit.toe_gps_s += 3600.0;
        let (e, problems) = checked(
            vec![lnav(23, 77, 5153.6, T), other],
            vec![],
            vec![d1(21, 1, 5282.6, T), d1_other],
        );
        assert!(e.gps.is_empty() && e.beidou.is_empty());
        assert_eq!(problems.skipped[ephemeris_conflicts::SAME_TOC], 4);
        // Such a pair, written as it was decoded, is a file the RINEX
        // reader keeps neither record of: the writer refuses to write it.
        let dir = std::env::temp_dir().join(format!("memsnav-conflict-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("pair.nav");
        let pair = [lnav(23, 77, 5153.6, T), lnav(23, 77, 5153.6, T + 7200.0)];
        let files = crate::gnss::NavFileEphemerides {
            gps_lnav: &pair,
            ..Default::default()
        };
        let e =
            crate::gnss::write_rinex_nav(&path, &files, Default::default(), &Default::default())
                .unwrap_err()
                .to_string();
        assert!(
            e.contains("not written: the reader would keep 0 of its 2 records"),
            "{e}"
        );
        assert!(!path.exists());
        std::fs::remove_dir_all(&dir).unwrap();
        // BeiDou's AODE is an age: one AODE, two t_oc and t_oe, both kept.
        let (e, _) = checked(
            vec![],
            vec![],
            vec![d1(21, 1, 5282.6, T), d1(21, 1, 5282.6, T + 3600.0)],
        );
        assert_eq!(e.beidou.len(), 2);
    }
}
