//! RINEX 2.10/2.11 observation files read whole (`gnss::rinex2_obs`):
//! epochs, satellite lists and their continuation lines, fields that name
//! their line and columns, GLONASS-time files. The code mapping's own test
//! is beside it.

mod records {
    use memsnav_core::gnss::parse_rinex_obs;

    const HEADER: &str =
        "     2.11           OBSERVATION DATA    M (MIXED)           RINEX VERSION / TYPE
 -2703115.2660 -4291768.3440  3854247.9550                  APPROX POSITION XYZ
     6    L1    C1    P2    S1    D1    C5                  # / TYPES OF OBSERV
  2021     4    28    19     0    0.0000000     GPS         TIME OF FIRST OBS
                                                            END OF HEADER
";

    #[test]
    fn epochs_satellite_lists_and_continuation_lines() {
        // 13 satellites: the list takes two lines; each satellite 2 lines.
        let mut text = HEADER.to_string();
        text.push_str(" 21  4 28 19  0  0.0000000  0 13G01G02G03G04G05G06G07G08G09G10G11R12\n");
        text.push_str("                                E13\n");
        for j in 1..=13 {
            text.push_str(&format!(
                " 122610995.21{} 7  23332073.875    23332083.105          42.000  \n  23332000.000 \n",
                j % 10
            ));
        }
        text.push_str("                            4  1\n      a comment                                             COMMENT\n");
        text.push_str(" 21  4 28 19  0 30.0000000  0  1 01\n 122610995.213    23332073.875\n\n");
        let f = parse_rinex_obs(&text, "x.11o").unwrap();
        assert_eq!(f.epochs.len(), 2);
        assert_eq!(
            f.observation_types[&'G'],
            ["L1C", "C1C", "C2W", "S1C", "D1C", "C5X"]
        );
        // GLONASS has no C5: one code fewer.
        assert_eq!(
            f.observation_types[&'R'],
            ["L1C", "C1C", "C2P", "S1C", "D1C"]
        );
        assert_eq!(
            f.observation_types[&'E'],
            ["L1X", "C1X", "S1X", "D1X", "C5X"]
        );
        let e = &f.epochs[0];
        assert_eq!(e.satellites.len(), 13);
        let g01 = &e.satellites[0];
        assert_eq!((g01.system, g01.prn), ('G', 1));
        assert_eq!(
            g01.values,
            [
                Some(122610995.211),
                Some(23332073.875),
                Some(23332083.105),
                Some(42.0),
                None,
                Some(23332000.0)
            ]
        );
        assert_eq!(g01.lli, [0; 6]);
        let r12 = &e.satellites[11];
        assert_eq!((r12.system, r12.prn), ('R', 12));
        assert_eq!(r12.values.len(), 5);
        assert_eq!(e.satellites[12].system, 'E');
        // A blank system letter is GPS; the second epoch is 30 s later.
        assert_eq!(
            (
                f.epochs[1].satellites[0].system,
                f.epochs[1].satellites[0].prn
            ),
            ('G', 1)
        );
        assert_eq!(f.epochs[1].gps_time_s - e.gps_time_s, 30.0);
        assert_eq!(
            f.skipped["event records with flag 4 (header information follows)"],
            1
        );
        assert!(f.warnings.is_empty(), "{:?}", f.warnings);
    }

    #[test]
    fn bad_fields_name_line_and_columns() {
        let record = " 21  4 28 19  0  0.0000000  0  1G01\n 122610995.213    23332073.875\n\n";
        let next = " 21  4 28 19  0 30.0000000  0  1G01\n 122610995.213    23332073.875\n\n";
        let cases = [
            (
                record.replace("23332073.875", "2333x073.875"),
                7,
                "G01 C1 in columns 17-30",
            ),
            (record.replace(" 0  1G01", " 9  1G01"), 6, "epoch flag 9"),
            (
                record.replace(" 0  1G01", " 0  1G00"),
                6,
                "satellite 1 of 1",
            ),
            (record.replace("28 19", "28 25"), 6, "hour 25"),
            (
                record.replace("G01", "G01G01").replace(" 0  1G", " 0  2G") + "\n\n\n",
                6,
                "G01 is listed twice",
            ),
            (next.to_string() + record, 9, "does not follow"),
        ];
        for (records, line, words) in cases {
            let text = format!("{HEADER}{records}{next}");
            let e = parse_rinex_obs(&text, "x.11o").unwrap_err().to_string();
            assert!(
                e.starts_with(&format!("x.11o:{line}: ")) && e.contains(words),
                "{e}"
            );
        }
        // The last record cut short: a warning.
        let text = format!("{HEADER}{record}{}", &next[..36]);
        let f = parse_rinex_obs(&text, "x.11o").unwrap();
        assert_eq!(
            (f.epochs.len(), f.warnings.len()),
            (1, 1),
            "{:?}",
            f.warnings
        );
    }

    #[test]
    fn glonass_time_is_utc() {
        let header = HEADER
            .replace("M (MIXED)", "R (GLO)  ")
            .replace("     GPS         TIME", "     GLO         TIME");
        let text = format!(
            "{header} 21  4 28 19  0  0.0000000  0  1R01\n 122610995.213    23332073.875\n\n"
        );
        let f = parse_rinex_obs(&text, "x.11o").unwrap();
        let gps = memsnav_core::gnss::gps_time_from_calendar(2021, 4, 28, 19, 0, 18.0);
        assert_eq!(f.epochs[0].gps_time_s, gps);
        assert_eq!(f.epochs[0].satellites[0].system, 'R');
    }
}
