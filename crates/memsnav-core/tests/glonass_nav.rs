//! GLONASS navigation records read whole (`gnss::rinex_nav_glonass`):
//! RINEX 2 `g` and RINEX 3 `R` records, values out of range and cut
//! records naming their line, repeated and conflicting records.

mod records {
    use memsnav_core::gnss::{gps_time_from_calendar, parse_broadcast_nav, GlonassEphemeris};

    const HEADER_2: &str =
        "     2.01           GLONASS NAV DATA                        RINEX VERSION / TYPE
                                                            END OF HEADER
";
    /// R01 of the IGS daily file brdc1360.20g.
    const R01_2: &str =
        " 1 20  5 15 14 45  0.0 0.615613535047D-04 0.000000000000D+00 0.522000000000D+05
   -0.104974877930D+05-0.192748928070D+01 0.931322574616D-09 0.000000000000D+00
    0.446844873047D+04-0.245540046692D+01 0.000000000000D+00 0.100000000000D+01
    0.228232382812D+05-0.404355049133D+00-0.186264514923D-08 0.000000000000D+00
";

    fn r01() -> GlonassEphemeris {
        parse_broadcast_nav(&format!("{HEADER_2}{R01_2}"), "x.20g")
            .unwrap()
            .glonass[0]
    }

    #[test]
    fn rinex_2_record_in_si_units_and_gps_time() {
        let e = r01();
        assert_eq!(
            (e.slot, e.frequency_channel, e.health, e.age_days),
            (1, 1, 0, 0)
        );
        // t_b 14:45:00 UTC is 14:45:18 GPST (18 leap seconds in 2020).
        let tb = gps_time_from_calendar(2020, 5, 15, 14, 45, 18.0);
        assert_eq!(e.tb_gps_s, tb);
        assert_eq!(e.tau_n_s, -0.615613535047e-4);
        assert_eq!(e.position_ecef.x, -0.104974877930e5 * 1e3);
        assert_eq!(e.velocity_ecef.y, -0.245540046692e1 * 1e3);
        assert_eq!(e.lunisolar_m_s2.z, -0.186264514923e-8 * 1e3);
    }

    #[test]
    fn out_of_range_values_and_cut_records_name_the_line() {
        let cases = [
            (
                R01_2.replace("-0.192748928070D+01", "-0.192748928070D+02"),
                4,
                "velocity X dot",
            ),
            (
                R01_2.replace("0.100000000000D+01", "0.200000000000D+02"),
                5,
                "frequency number = 20",
            ),
            (R01_2.replace(" 1 20  5", "30 20  5"), 3, "slot 30"),
            (
                R01_2.replace("0.615613535047D-04", "0.615613535047D-01"),
                3,
                "TauN",
            ),
            (
                R01_2.lines().take(3).map(|l| format!("{l}\n")).collect(),
                6,
                "truncated record for R01",
            ),
        ];
        for (record, line, words) in cases {
            let e = parse_broadcast_nav(&format!("{HEADER_2}{record}"), "x.20g")
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with(&format!("x.20g:{line}: ")) && e.contains(words),
                "{e}"
            );
        }
        // The same record twice is kept once and counted; with another
        // value both are left out and counted, as other systems' conflicts.
        let nav = parse_broadcast_nav(&format!("{HEADER_2}{R01_2}{R01_2}"), "x.20g").unwrap();
        assert_eq!(nav.glonass.len(), 1);
        assert_eq!(nav.skipped.values().sum::<usize>(), 1);
        let other = R01_2.replace("-0.404355049133D+00", "-0.404355049134D+00");
        let nav =
            parse_broadcast_nav(&format!("{HEADER_2}{R01_2}{other}{other}"), "x.20g").unwrap();
        assert!(nav.glonass.is_empty());
        assert_eq!(
            nav.skipped
                .get("GLONASS ephemerides in conflict (one slot and t_b, other values)"),
            Some(&3)
        );
    }
}
