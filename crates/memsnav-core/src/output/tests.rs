use nalgebra::Vector3;

use super::*;
use crate::geodesy::Geodetic;
use crate::logs::parse_pos;

/// A 100 Hz solution of `n` samples walking north-east from Boulder.
fn solution(n: usize) -> LocalSolution {
    let time_s: Vec<f64> = (0..n).map(|k| 1_440_000_000.0 + k as f64 * 0.01).collect();
    let geodetic: Vec<Geodetic> = (0..n)
        .map(|k| {
            Geodetic::new(
                40.0_f64.to_radians() + 1e-7 * k as f64,
                (-105.0_f64).to_radians() + 2e-7 * k as f64,
                1580.0 + 0.001 * k as f64,
            )
        })
        .collect();
    let v = |k: usize| Vector3::new(0.5, 0.25 + k as f64 * 1e-3, -0.01);
    LocalSolution {
        antenna_position_ecef: geodetic
            .iter()
            .map(|g| crate::geodesy::geodetic_to_ecef(*g))
            .collect(),
        antenna_geodetic: geodetic,
        velocity_ned: (0..n).map(v).collect(),
        euler_rad: (0..n).map(|_| Vector3::new(0.01, -0.02, 1.0)).collect(),
        position_std_ned: (0..n).map(|_| Vector3::new(0.1, 0.2, 0.3)).collect(),
        velocity_std_ned: (0..n).map(|_| Vector3::new(0.01, 0.02, 0.03)).collect(),
        attitude_std_ned: (0..n).map(|_| Vector3::new(1e-3, 1e-3, 1e-2)).collect(),
        time_s,
    }
}

#[test]
fn decimation_keeps_the_first_sample_of_each_interval() {
    let t: Vec<f64> = (0..100).map(|k| k as f64 * 0.01).collect();
    assert_eq!(decimate(&t, None).unwrap().len(), 100);
    let kept = decimate(&t, Some(10.0)).unwrap();
    assert_eq!(kept, (0..10).map(|k| 10 * k).collect::<Vec<_>>());
    // Far from zero, 0.1 s steps carry rounding errors; the grid holds.
    let late: Vec<f64> = t.iter().map(|x| 1_440_000_000.0 + x).collect();
    assert_eq!(decimate(&late, Some(10.0)).unwrap(), kept);
    // A rate above the sample rate keeps every sample.
    assert_eq!(decimate(&t, Some(1000.0)).unwrap().len(), 100);
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = decimate(&t, Some(bad)).unwrap_err().to_string();
        assert!(e.starts_with("rate_hz: must be a positive number"), "{e}");
    }
}

#[test]
fn formats_by_name_and_extension() {
    assert_eq!(
        SolutionFormat::from_name("KML").unwrap(),
        SolutionFormat::Kml
    );
    let e = SolutionFormat::from_name("shp").unwrap_err().to_string();
    assert_eq!(
        e,
        "format: \"shp\" is not a format memsnav writes; give one of \"csv\", \"pos\", \
         \"kml\", \"gpx\", \"geojson\""
    );
    let of = |p: &str| SolutionFormat::from_path(Path::new(p));
    assert_eq!(of("a/run.json").unwrap(), SolutionFormat::GeoJson);
    assert_eq!(of("run.GeoJSON").unwrap(), SolutionFormat::GeoJson);
    assert_eq!(of("run.pos").unwrap(), SolutionFormat::Pos);
    let e = of("run.txt").unwrap_err().to_string();
    assert!(
        e.starts_with("format: not given, and the extension of run.txt"),
        "{e}"
    );
    assert!(of("run").is_err());
}

#[test]
fn csv_rows_and_pos_round_trip() {
    let s = solution(250);
    let csv = format_solution(&s, SolutionFormat::Csv, None, "x").unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0].split(',').collect::<Vec<_>>(), COLUMNS);
    assert_eq!(lines.len(), 251);
    let row: Vec<f64> = lines[3].split(',').map(|x| x.parse().unwrap()).collect();
    assert_eq!(row[0], 1_440_000_000.02);
    assert!((row[1] - (40.0 + 2e-7_f64.to_degrees())).abs() < 1e-9);
    assert!((row[9] - 1.0_f64.to_degrees()).abs() <= 5e-6);

    let pos = format_solution(&s, SolutionFormat::Pos, None, "x").unwrap();
    let back = parse_pos(&pos, "x.pos").unwrap();
    assert_eq!(back.gps_time_s.len(), 25); // 2.5 s at 10 Hz
    for (j, &k) in decimate(&s.time_s, Some(MAP_RATE_HZ))
        .unwrap()
        .iter()
        .enumerate()
    {
        assert!((back.gps_time_s[j] - s.time_s[k]).abs() < 5e-4);
        let g = s.antenna_geodetic[k];
        assert!((back.lla[j].x - g.latitude_rad).abs() < 1e-10);
        assert!((back.lla[j].y - g.longitude_rad).abs() < 1e-10);
        assert!((back.lla[j].z - g.height_m).abs() < 1e-4);
        assert!((back.velocity_ned_m_s[j] - s.velocity_ned[k]).abs().max() < 1e-5);
    }
}

#[test]
fn map_tracks_need_two_finite_points_and_escape_the_name() {
    let one = solution(5); // 0.04 s: one point at 10 Hz
    let e = format_solution(&one, SolutionFormat::Kml, None, "x").unwrap_err();
    assert!(e.to_string().contains("at least two points"), "{e}");
    let mut bad = solution(50);
    bad.antenna_geodetic[20].height_m = f64::NAN;
    let e = format_solution(&bad, SolutionFormat::Gpx, None, "x").unwrap_err();
    assert!(e.to_string().contains("sample 20"), "{e}");
    let s = solution(50);
    let kml = format_solution(&s, SolutionFormat::Kml, None, "a<b & \"c\"").unwrap();
    assert!(kml.contains("<name>a&lt;b &amp; &quot;c&quot;</name>"));
    let json = format_solution(&s, SolutionFormat::GeoJson, None, "a\"b\\").unwrap();
    assert!(json.contains("\"name\": \"a\\\"b\\\\\""), "{json}");
    assert!(json.starts_with(SolutionFormat::GeoJson.signature()));
}

#[test]
fn write_replaces_only_its_own_files() {
    let dir = std::env::temp_dir().join(format!("memsnav-output-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let s = solution(300);
    let path = dir.join("run.gpx");
    write_solution(&path, &s, None, None, None, false).unwrap();
    let gpx = std::fs::read_to_string(&path).unwrap();
    assert!(gpx.contains("<name>run</name>") && gpx.matches("<trkpt").count() == 30);
    for format in SolutionFormat::ALL {
        // Any memsnav solution file may be replaced, by any format.
        write_solution(&path, &s, Some(format), None, None, false).unwrap();
    }
    let foreign = dir.join("notes.kml");
    std::fs::write(&foreign, "<kml>mine</kml>").unwrap();
    let e = write_solution(&foreign, &s, None, None, None, false).unwrap_err();
    assert!(
        e.to_string()
            .contains("exists and is not a solution file memsnav wrote"),
        "{e}"
    );
    assert_eq!(
        std::fs::read_to_string(&foreign).unwrap(),
        "<kml>mine</kml>"
    );
    write_solution(&foreign, &s, None, None, None, true).unwrap();
    assert!(std::fs::read_to_string(&foreign)
        .unwrap()
        .contains("written by memsnav"));
    let e = write_solution(&dir.join("no/such.kml"), &s, None, None, None, false).unwrap_err();
    assert!(
        matches!(e, Error::Io { .. }) && e.to_string().contains("does not exist"),
        "{e}"
    );
    let e = write_solution(&dir, &s, Some(SolutionFormat::Csv), None, None, true).unwrap_err();
    assert!(e.to_string().contains("is a folder"), "{e}");
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(left.len(), 2, "no temporary file left behind");
    std::fs::remove_dir_all(&dir).unwrap();
}
