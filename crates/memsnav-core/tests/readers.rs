//! Every reader range-checks its fields: the RINEX navigation
//! and SP3 cases that hung, overflowed or returned garbage, each an error
//! naming the file, the line and the field.

use std::path::PathBuf;

use memsnav_core::gnss::{read_klobuchar, read_rinex_nav, read_sp3};
use memsnav_core::Error;

fn excerpt(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/real-imu-gnss")
        .join(name)
}

fn write_temp(name: &str, text: &str) -> PathBuf {
    let path = std::env::temp_dir().join(format!("memsnav-readers-{}-{name}", std::process::id()));
    std::fs::write(&path, text).unwrap();
    path
}

/// `walk.nav` (RINEX 3.04) with value `j` (0-3) of line `line` (1-7) of the
/// first record replaced by `value`; `line` 0 edits the epoch line's text.
fn nav_with(line: usize, j: usize, value: &str) -> String {
    let text = std::fs::read_to_string(excerpt("walk.nav")).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let first = lines.iter().position(|l| l.starts_with('G')).unwrap();
    let l = &mut lines[first + line];
    let start = 4 + 19 * j;
    l.replace_range(start..start + 19, &format!("{value:>19}"));
    lines.join("\n") + "\n"
}

fn nav_error(text: &str) -> String {
    let path = write_temp("x.nav", text);
    let e = read_rinex_nav(&path).unwrap_err();
    assert!(matches!(e, Error::Parse { .. }), "{e}");
    e.to_string()
}

#[test]
fn rinex_nav_values_outside_the_navigation_message_are_refused() {
    // The header has 5 lines: the first record starts on line 6.
    let cases = [
        // A week or t_oe of 1e29 hung the week normalisation loop.
        (
            5,
            2,
            "1.000000000000D+29",
            11,
            "GPS week = 1e29 for G32 is out of range",
        ),
        (
            3,
            0,
            "1.000000000000D+29",
            9,
            "Toe = 1e29 for G32 is out of range",
        ),
        // Crs, Δn, √A of 1e30 gave infinite or 1e67 m positions.
        (
            1,
            1,
            "1.000000000000D+30",
            7,
            "Crs = 1e30 for G32 is out of range (-1.024e3 to 1.024e3)",
        ),
        (1, 2, "1.000000000000D+30", 7, "Delta n = 1e30"),
        (
            2,
            3,
            "1.000000000000D+30",
            8,
            "sqrt(A) = 1e30 for G32 is out of range (2.53e3 to 8.192e3)",
        ),
        (2, 1, "1.500000000000D+00", 8, "e = 1.5e0"),
        (6, 1, "-.500000000000D+01", 12, "SV health = -5e0"),
    ];
    for (line, j, value, at, words) in cases {
        let e = nav_error(&nav_with(line, j, value));
        assert!(
            e.contains(&format!("x.nav:{at}: ")) && e.contains(words),
            "{e}"
        );
    }
    let text = std::fs::read_to_string(excerpt("walk.nav")).unwrap();
    for (from, to, words) in [
        (
            "G32 2025 08 28",
            "G32    0 08 28",
            "epoch of G32: year 0 is out of range",
        ),
        (
            "G32 2025 08 28",
            "G32 2025 13 28",
            "epoch of G32: month 13 is out of range",
        ),
        (
            "G32 2025 08 28 18",
            "G32 2025 08 28 25",
            "hour 25 is out of range",
        ),
        (
            "G32 2025",
            "G-1 2025",
            "satellite G-1 does not exist (system G numbers 1-32)",
        ),
    ] {
        let e = nav_error(&text.replacen(from, to, 1));
        assert!(e.contains("x.nav:6: ") && e.contains(words), "{e}");
    }
    // The unchanged excerpt reads, weeks placed around t_oc.
    let records = read_rinex_nav(excerpt("walk.nav")).unwrap();
    assert!(records
        .iter()
        .all(|r| (r.orbit.toe_gps_s - r.orbit.toc_gps_s).abs() <= 302_400.0));
}

#[test]
fn klobuchar_coefficients_outside_the_message_are_refused() {
    let header =
        "     3.04           N: GNSS NAV DATA    M: Mixed            RINEX VERSION / TYPE\n\
GPSA   1.1176D-08 -7.4506D-09 -5.9605D-08  1.1921D-07       IONOSPHERIC CORR\n\
GPSB   1.1674D+05 -2.2938D+05 -1.3107D+05  1.0486D+06       IONOSPHERIC CORR\n\
                                                            END OF HEADER\n";
    let k = read_klobuchar(write_temp("ok.nav", header))
        .unwrap()
        .unwrap();
    assert_eq!(k.alpha[0], 1.1176e-8);
    for (from, to, words) in [
        (
            "1.1176D-08",
            "1.0000D+30",
            "klobuchar.nav:2: Klobuchar coefficient 1 of IONOSPHERIC CORR = 1e30",
        ),
        (
            "1.0486D+06",
            "       NaN",
            "klobuchar.nav:3: Klobuchar coefficient 4 of IONOSPHERIC CORR = NaN",
        ),
    ] {
        let path = write_temp("klobuchar.nav", &header.replace(from, to));
        let e = read_klobuchar(path).unwrap_err().to_string();
        assert!(e.contains(words) && e.contains("out of range"), "{e}");
    }
}

/// An SP3-d file with `n_sat` satellites G01.., then R01.. and the other
/// systems past G99 (at most 792), and the given epochs, each with one
/// position record (x in km) per satellite.
fn sp3(n_sat: usize, epochs: &[&str], x_km: &str) -> String {
    let mut out = String::from("#dP2021  4 28  0  0  0.00000000     288 ORBIT IGb14 HLM  COD\n");
    let ids: Vec<String> = "GRECJISL"
        .chars()
        .flat_map(|system| (1..=99).map(move |i| format!("{system}{i:02}")))
        .take(n_sat)
        .collect();
    assert_eq!(ids.len(), n_sat, "SP3 names allow at most 792 satellites");
    for (k, chunk) in ids.chunks(17).enumerate() {
        let head = if k == 0 {
            format!("+  {n_sat:3}   ")
        } else {
            "+        ".to_string()
        };
        out += &format!("{head}{}\n", chunk.concat());
    }
    out += "%c M  cc GPS ccc cccc cccc cccc cccc ccccc ccccc ccccc ccccc\n";
    for e in epochs {
        out += &format!("*  {e}\n");
        for id in &ids {
            out += &format!("P{id}{x_km:>14} -15000.000000  10000.000000    100.000000\n");
        }
    }
    out
}

#[test]
fn sp3_positions_epochs_and_sizes_are_range_checked() {
    let e1 = "2021  4 28  0  0  0.00000000";
    let e2 = "2021  4 28  0  5  0.00000000";
    let ok = read_sp3(write_temp("ok.sp3", &sp3(2, &[e1, e2], "20000.000000"))).unwrap();
    assert_eq!((ok.time_gps_s.len(), ok.satellites.len()), (2, 2));
    assert_eq!(ok.position(1, 1).x, 2e7);
    let read = |name: &str, text: &str| read_sp3(write_temp(name, text)).unwrap_err().to_string();
    let e = read("far.sp3", &sp3(2, &[e1, e2], "1.0e308"));
    assert!(
        e.contains("far.sp3:5: G01 x = 1e308 km is out of range"),
        "{e}"
    );
    let e = read("back.sp3", &sp3(2, &[e2, e1], "20000.000000"));
    assert!(
        e.contains("back.sp3:7: epoch 2021-04-28 00:00:00 does not follow"),
        "{e}"
    );
    let e = read("same.sp3", &sp3(2, &[e1, e1], "20000.000000"));
    assert!(
        e.contains("same.sp3:7:") && e.contains("epochs must increase"),
        "{e}"
    );
    let e = read(
        "month.sp3",
        &sp3(2, &[&e1.replace(" 4 28", "13 28")], "20000.000000"),
    );
    assert!(
        e.contains("month.sp3:4: epoch: month 13 is out of range"),
        "{e}"
    );
    let e = read(
        "count.sp3",
        &sp3(2, &[e1], "20000.000000").replacen("+    2", "+   -2", 1),
    );
    assert!(
        e.contains("count.sp3:2: number of satellites -2 is out of range"),
        "{e}"
    );
    let clock = sp3(2, &[e1], "20000.000000").replacen("    100.000000", "1.0e300       ", 1);
    let e = read("clock.sp3", &clock);
    assert!(e.contains("G01 clock = 1e300 µs is out of range"), "{e}");
    // 792 satellites (every name SP3 allows) × 12 700 epochs would be
    // 320 MB of orbit: refused.
    let many: Vec<String> = (0..12_700)
        .map(|k| {
            format!(
                "2021  4 28 {:2} {:2} {:2}.00000000",
                k / 3600 % 24,
                k / 60 % 60,
                k % 60
            )
        })
        .collect();
    let mut text = sp3(792, &[], "");
    for e in &many {
        text += &format!("*  {e}\n");
    }
    let e = read("huge.sp3", &text);
    assert!(
        e.contains("more than 10000000 satellite-epochs (792 satellites)"),
        "{e}"
    );
}
