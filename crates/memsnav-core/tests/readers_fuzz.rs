//! Fuzzing the readers: every reader, fed valid files with
//! bytes flipped, lines cut, duplicated or dropped, numbers replaced by huge,
//! negative or non-finite ones, and pure garbage, returns a result or an
//! error in bounded time: never a panic, a hang (10 s per input), or a
//! result that breaks its own guarantees (times that do not increase,
//! values out of range, orbits 1e67 m away, a satellite twice in an epoch
//! or in the SP3 header's list).
//!
//! Binary logs are also fuzzed behind their checks: the UBX mutators change
//! fields, frames and LNAV subframe words, then recompute the LNAV parity
//! and the Fletcher checksum, so the decoders see absurd contents behind
//! valid checks; NMEA sentences get their checksum recomputed. A UBX log's
//! result must then hold only values a receiver reports, and its
//! observations and ephemerides must come back whole from memsnav's own
//! RINEX writer and readers (what `memsnav convert` does).
//!
//! CI runs `MEMSNAV_FUZZ_CASES` inputs per reader and kind (default 256);
//! maintainers raise it (`MEMSNAV_FUZZ_CASES=100000`, docs/reference/robustness.md).
//! The files in `tests/data/regressions/` are replayed every time.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::sync::OnceLock;
use std::time::Duration;

use memsnav_core::gnss::{
    check_measurement, format_rinex_nav, format_rinex_obs, parse_broadcast_nav, parse_klobuchar,
    parse_rinex_obs, parse_sp3, plausible, Klobuchar, NavFileEphemerides, RinexNavVersion,
    RinexProvenance,
};
use memsnav_core::logs::{
    axes_from_name, parse_fixes_csv, parse_gnss_table, parse_gnsslogger, parse_imu_csv, parse_nmea,
    parse_pos, parse_time_tag, parse_ubx, AccelUnit, FixesCsvLayout, GyroUnit, ImuColumns,
    ImuCsvLayout, ImuLog, PosSolution, TableStds, TimeUnit, MAX_ANGULAR_RATE_RAD_S,
    MAX_SPECIFIC_FORCE_M_S2, MAX_SPEED_M_S, POS_HEIGHT_RANGE_M,
};
use proptest::prelude::*;

/// Longest a reader may take on one small input before it counts as hung.
const HANG: Duration = Duration::from_secs(10);

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Reader {
    ImuCsv,
    TimeTag,
    Pos,
    RinexObs,
    RinexNav,
    Klobuchar,
    Sp3,
    FixesCsv,
    Nmea,
    GnssTable,
    GnssLogger,
    ImuIncrements,
    Ubx,
    Rinex2Obs,
    GlonassNav,
    MixedNav,
    GalileoNav2,
    Rinex4Nav,
}

fn data(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data")
        .join(relative)
}

/// The first `n` lines of a file (all for `usize::MAX`), with their newlines.
fn head(relative: &str, n: usize) -> Vec<u8> {
    let bytes = std::fs::read(data(relative)).unwrap();
    let mut out = Vec::new();
    for line in bytes.split_inclusive(|&b| b == b'\n').take(n) {
        out.extend_from_slice(line);
    }
    out
}

const KLOBUCHAR_SEED: &str =
    "     3.04           N: GNSS NAV DATA    M: Mixed            RINEX VERSION / TYPE
GPSA   1.1176D-08 -7.4506D-09 -5.9605D-08  1.1921D-07       IONOSPHERIC CORR
GPSB   1.1674D+05 -2.2938D+05 -1.3107D+05  1.0486D+06       IONOSPHERIC CORR
     2.11           N: GPS NAV DATA                         RINEX VERSION / TYPE
    0.1118D-07 -0.7451D-08 -0.5961D-07  0.1192D-06          ION ALPHA
    0.1167D+06 -0.2294D+06 -0.1311D+06  0.1049D+07          ION BETA
                                                            END OF HEADER
";

const SP3_SEED: &str = "#dP2021  4 28  0  0  0.00000000       3 ORBIT IGb14 HLM  COD
+    3   G01G02E05  0  0  0  0  0  0  0  0  0  0  0  0  0  0
%c M  cc GPS ccc cccc cccc cccc cccc ccccc ccccc ccccc ccccc
*  2021  4 28  0  0  0.00000000
PG01  13744.405346 -22569.713946   3524.563484    -35.471733
PG02 -17432.166712   2895.601632 -19885.125497    -19.893412
PE05      0.000000      0.000000      0.000000 999999.999999
*  2021  4 28  0  5  0.00000000
PG01  13848.512383 -22211.297941   6208.223406    -35.472146
PG02 -17005.224919   3838.417103 -20029.707301    -19.893417
PE05  10000.000000  20000.000000   5000.000000      1.000000
*  2021  4 28  0 10  0.00000000
PG01  13974.113220 -21737.434722   8797.941102    -35.472561
EOF
";

const FIXES_CSV_SEED: &str = "# fixes
gps_week,gps_tow_s,lat_deg,lon_deg,height_m,cov_nn_m2,cov_ne_m2,cov_nd_m2,cov_ee_m2,cov_ed_m2,cov_dd_m2,vn_m_s,ve_m_s,vd_m_s,std_vn_m_s,std_ve_m_s,std_vd_m_s,quality,n_satellites
2374,242094.999,40.0966268,-105.1474483,1601.45,1e-4,2e-5,0,1e-4,0,1.2e-4,-0.002,0.001,0.008,0.058,0.058,0.058,1,20
2374,242095.249,40.0966268,-105.1474483,1601.453,1e-4,0,0,1e-4,0,1.2e-4,0.009,-0.001,-0.028,0.054,0.054,0.054,1,20
2374,242095.499,40.0966269,-105.1474484,1601.46,1e-4,0,-1e-5,1e-4,0,1.2e-4,,,,,,,2,19
";

const NMEA_SEED: &str =
    "$GNGGA,120000.00,5130.000000,N,00007.500000,W,4,12,0.9,45.0,M,47.0,M,1.0,0123*74
$GNRMC,120000.00,A,5130.000000,N,00007.500000,W,1.5,90.0,150320,,,R*7F
$GNGST,120000.00,1.0,0.02,0.01,45.0,0.015,0.015,0.03*4A
$GNVTG,90.0,T,,M,1.5,N,2.8,K,R*37
$GPGSV,3,1,11,10,63,137,17,07,61,098,15,05,59,290,20,08,54,157,30*70
NMEA,$GNGGA,120000.25,5130.000001,N,00007.500001,W,4,12,0.9,45.0,M,47.0,M,1.0,0123*73,1584273618250
NMEA,$GNRMC,120000.25,A,5130.000001,N,00007.500001,W,1.5,90.0,150320,,,R*78,1584273618251
$GNGST,120000.25,1.0,0.02,0.01,45.0,0.015,0.015,0.03*4D
$GNVTG,90.0,T,,M,1.5,N,2.8,K,R*37
$GNGGA,120000.50,5130.000002,N,00007.500002,W,4,12,0.9,45.0,M,47.0,M,1.0,0123*71
$GNRMC,120000.50,A,5130.000002,N,00007.500002,W,1.5,90.0,150320,,,R*7A
$GNVTG,90.0,T,,M,1.5,N,2.8,K,R*37
";

/// Whether a fix reader's solution keeps its guarantees: times increase,
/// positions, stds and speeds in range, covariances symmetric with
/// non-negative eigenvalues (to rounding), qualities RTKLIB's.
fn solution_ok(sol: &PosSolution) -> bool {
    let psd = |c: &nalgebra::Matrix3<f64>| {
        (c - c.transpose()).abs().max() <= 1e-12 * c.abs().max()
            && c.symmetric_eigenvalues().min() >= -1e-9 * c.trace().abs().max(1e-300)
    };
    increasing(&sol.gps_time_s)
        && sol.lla.iter().all(|p| {
            p.x.abs() <= std::f64::consts::FRAC_PI_2
                && p.y.abs() <= std::f64::consts::PI
                && POS_HEIGHT_RANGE_M.contains(&p.z)
        })
        // A fixes CSV without σ columns (a truth) has NaN σ throughout.
        && sol
            .std_ned_m
            .iter()
            .all(|s| s.iter().all(|&x| x >= 0.0) || s.iter().all(|x| x.is_nan()))
        && sol
            .velocity_ned_m_s
            .iter()
            .all(|v| v.iter().all(|x| x.abs() <= MAX_SPEED_M_S || x.is_nan()))
        && sol.quality.iter().all(|&q| q <= 7)
        && sol
            .position_covariance_ned_m2()
            .iter()
            .all(|c| psd(c) || c.iter().all(|x| x.is_nan()))
        && sol.attitude_c_b_n.as_ref().is_none_or(|c| {
            c.iter().all(|m| {
                (m.transpose() * m - nalgebra::Matrix3::identity()).abs().max() < 1e-9
                    && (m.determinant() - 1.0).abs() < 1e-9
            })
        })
}

const GNSS_TABLE_SEED: &str = "time_s,gps_time_s,sat_id,sat_position_ecef_x_m,sat_position_ecef_y_m,sat_position_ecef_z_m,sat_velocity_ecef_x_m_s,sat_velocity_ecef_y_m_s,sat_velocity_ecef_z_m_s,pseudorange_m,pseudorange_rate_m_s
0,1273529464,5,-2179862.557,-26154875.769,-3437694.371,325.541,-419.725,3129.012,23052313.867,-120.5
0,1273529464,13,-5199894.405,-17419269.957,23361281.147,2239.305,700.815,1022.014,23522506.859,
1,1273529465,5,-2179537.0,-26155295.4,-3434565.4,325.5,-419.7,3129.0,23052193.2,-120.6
1,1273529465,13,-5197655.1,-17418569.1,23362303.1,2239.3,700.8,1022.0,23522640.1,133.2
";

fn seed(reader: Reader) -> &'static [u8] {
    static SEEDS: OnceLock<Vec<Vec<u8>>> = OnceLock::new();
    let seeds = SEEDS.get_or_init(|| {
        vec![
            head("real-imu-gnss/drive_60s.csv", 20),
            head("real-imu-gnss/walk_head.csv.tag", usize::MAX),
            head("real-imu-gnss/walk_head.pos", 12),
            head("real-imu-gnss/walk_head.obs", usize::MAX),
            head("real-imu-gnss/walk.nav", usize::MAX),
            KLOBUCHAR_SEED.as_bytes().to_vec(),
            SP3_SEED.as_bytes().to_vec(),
            FIXES_CSV_SEED.as_bytes().to_vec(),
            NMEA_SEED.as_bytes().to_vec(),
            GNSS_TABLE_SEED.as_bytes().to_vec(),
            head("android-gnsslogger/pixel6_excerpt.txt", usize::MAX),
            IMU_INCREMENTS_SEED.as_bytes().to_vec(),
            head("real-imu-gnss/walk_head.ubx", usize::MAX),
            head("rinex-public/14601736.18o", usize::MAX),
            head("rinex-public/brdc1360_excerpt.20g", 27),
            head(
                "rinex-public/BRDC00IGS_R_20201360000_excerpt_MN.rnx",
                usize::MAX,
            ),
            head("rinex-public/ceda2100.18e", 30),
            // 4 LNAV and 2 CNAV records of RINEX 4.00.
            head("real-imu-gnss/walk.rnx", 60),
        ]
    });
    &seeds[reader as usize]
}

/// An integrating IMU's log: a preamble line, a header in its own order,
/// increments in g·s and degrees, FLU axes, a temperature column.
const IMU_INCREMENTS_SEED: &str = "# exported by another logger
time_s,dang_z,dvel_x,dang_x,dvel_z,dang_y,dvel_y,temp_c
1735.000,0,0,0,0,0,0,21.5
1735.010,0.0012,0.0001,-0.0004,0.01,0.0002,-0.00002,21.5
1735.020,0.0011,0.0001,-0.0003,0.01,0.0002,-0.00001,21.5
1735.031,0.0013,0.0002,-0.0004,0.0101,0.0001,-0.00002,21.6
1735.040,0.0010,0.0001,-0.0005,0.0099,0.0002,0.0,21.6
";

/// The layout of [`IMU_INCREMENTS_SEED`]: columns by header name.
fn increments_layout() -> ImuCsvLayout {
    let names = [
        ("t", "time_s"),
        ("ax", "dvel_x"),
        ("ay", "dvel_y"),
        ("az", "dvel_z"),
        ("gx", "dang_x"),
        ("gy", "dang_y"),
        ("gz", "dang_z"),
    ];
    ImuCsvLayout {
        columns: ImuColumns::Header(
            names
                .iter()
                .map(|(q, n)| (q.to_string(), n.to_string()))
                .collect(),
        ),
        axes: axes_from_name("FLU").unwrap(),
        header_lines: 1,
        ..ImuCsvLayout::new(
            AccelUnit::StandardGravitySeconds,
            GyroUnit::Degrees,
            TimeUnit::Seconds,
        )
    }
}

/// Whether an IMU log keeps the reader's guarantees: sample times and line
/// stamps increase (each sample at or before its line's stamp), values in
/// the sensors' range, lines increasing and inside the file.
fn imu_log_ok(log: &ImuLog) -> bool {
    increasing(&log.time_s)
        && increasing(&log.line_time_s)
        && log.line_time_s.len() == log.time_s.len()
        && log.time_s.iter().zip(&log.line_time_s).all(|(t, s)| t <= s)
        && log
            .specific_force_m_s2
            .iter()
            .all(|f| f.amax() <= MAX_SPECIFIC_FORCE_M_S2)
        && log
            .angular_rate_rad_s
            .iter()
            .all(|w| w.amax() <= MAX_ANGULAR_RATE_RAD_S)
        && log.line.windows(2).all(|w| w[1] > w[0])
        && log.line_end_offset.iter().all(|&o| o < log.file_bytes)
        && log.timing().gap_count < log.time_s.len()
}

fn layout() -> ImuCsvLayout {
    ImuCsvLayout::new(
        AccelUnit::StandardGravity,
        GyroUnit::DegreesPerSecond,
        TimeUnit::Milliseconds,
    )
}

/// Whether no item comes twice (a satellite twice in an epoch or a list).
fn distinct<T: Ord>(mut items: impl Iterator<Item = T>) -> bool {
    let mut seen = std::collections::BTreeSet::new();
    items.all(|item| seen.insert(item))
}

fn increasing(times: &[f64]) -> bool {
    times.iter().all(|t| t.is_finite()) && times.windows(2).all(|w| w[1] > w[0])
}

/// Reads `bytes` as `reader` would a file named `file`: `Ok(true)` for a
/// result that keeps the reader's guarantees, `Ok(false)` for an error
/// naming the file, `Err` for anything else (a broken guarantee, an error
/// that does not say which file).
fn read(reader: Reader, bytes: &[u8], file: &str) -> Result<bool, String> {
    let text = String::from_utf8_lossy(bytes);
    let outcome: Result<Result<(), String>, memsnav_core::Error> = match reader {
        Reader::ImuCsv | Reader::ImuIncrements => {
            let layout = if reader == Reader::ImuCsv {
                layout()
            } else {
                increments_layout()
            };
            parse_imu_csv(bytes, file, &layout)
                .map(|log| imu_log_ok(&log).then_some(()).ok_or(format!("{log:?}")))
        }
        Reader::TimeTag => parse_time_tag(bytes, file).map(|tag| {
            let ok = tag.start_gps_time_s >= 0.0
                && tag.start_gps_time_s.is_finite()
                && tag.tick_ms.windows(2).all(|w| w[1] >= w[0])
                && tag.file_offset.windows(2).all(|w| w[1] >= w[0]);
            ok.then_some(()).ok_or(format!("{tag:?}"))
        }),
        Reader::Pos | Reader::FixesCsv | Reader::Nmea => {
            let parsed = match reader {
                Reader::Pos => parse_pos(&text, file),
                Reader::FixesCsv => parse_fixes_csv(&text, file, &FixesCsvLayout::default()),
                _ => parse_nmea(&text, file),
            };
            parsed.map(|sol| solution_ok(&sol).then_some(()).ok_or(format!("{sol:?}")))
        }
        Reader::RinexObs | Reader::Rinex2Obs => parse_rinex_obs(&text, file).map(|obs| {
            let times: Vec<f64> = obs.epochs.iter().map(|e| e.gps_time_s).collect();
            let ok = increasing(&times)
                && obs.epochs.iter().all(|e| {
                    e.satellites
                        .iter()
                        .all(|s| s.values.iter().flatten().all(|v| v.abs() <= 1e10))
                        && distinct(e.satellites.iter().map(|s| (s.system, s.prn)))
                });
            ok.then_some(()).ok_or(format!("{:?}", obs.epochs.first()))
        }),
        Reader::RinexNav
        | Reader::GlonassNav
        | Reader::MixedNav
        | Reader::GalileoNav2
        | Reader::Rinex4Nav => {
            parse_broadcast_nav(&text, file).map(|nav| {
                // The satellite stays near the Earth: √A ≤ 8192 √m bounds the
                // orbit to |r| ≤ a (1 + e) + 2 × 2048 m < 1.01e8 m; the same
                // for GPS, Galileo and BeiDou (GEO or not).
                let states = nav
                    .gps
                    .iter()
                    .map(|r| (format!("{r:?}"), r.orbit, r.state(r.orbit.toc_gps_s)))
                    .chain(nav.gps_cnav.iter().map(|r| {
                        (
                            format!("{r:?}"),
                            r.orbit,
                            r.state_at(r.orbit.toc_gps_s, 0.0),
                        )
                    }))
                    .chain(nav.galileo.iter().map(|r| {
                        (
                            format!("{r:?}"),
                            r.orbit,
                            r.state_at(r.orbit.toc_gps_s, 0.0),
                        )
                    }))
                    .chain(nav.beidou.iter().map(|r| {
                        (
                            format!("{r:?}"),
                            r.orbit,
                            r.state_at(r.orbit.toc_gps_s, 0.0),
                        )
                    }));
                let mut bad = states.filter(|(_, o, s)| {
                    !(s.position_ecef.norm() < 1.01e8
                        && s.velocity_ecef.norm() < 1e5
                        && s.clock_bias_s.is_finite()
                        && (o.toe_gps_s - o.toc_gps_s).abs() <= 302_400.0)
                });
                // GLONASS: the message's ranges bound |r| at t_b to 4.7e7 m;
                // 15 min of integration keep it near the Earth.
                let mut bad_glonass = nav.glonass.iter().filter(|e| {
                    let s = e.state(e.tb_gps_s + 900.0);
                    !(s.position_ecef.norm() < 1.01e8
                        && s.velocity_ecef.norm() < 1e5
                        && s.clock_bias_s.is_finite())
                });
                match (bad.next(), bad_glonass.next()) {
                    (Some((r, _, _)), _) => Err(r),
                    (None, Some(e)) => Err(format!("{e:?}")),
                    (None, None) => Ok(()),
                }
            })
        }
        Reader::Klobuchar => parse_klobuchar(&text, file).map(|k| match k {
            Some(Klobuchar { alpha, beta }) if alpha.iter().chain(&beta).all(|x| x.is_finite()) => {
                Ok(())
            }
            None => Ok(()),
            Some(k) => Err(format!("{k:?}")),
        }),
        Reader::GnssTable => parse_gnss_table(&text, file, TableStds::default()).map(|t| {
            let times: Vec<f64> = t.epochs.iter().map(|e| e.time_s).collect();
            let ok = increasing(&times)
                && t.epochs.iter().all(|e| {
                    distinct(e.measurements.iter().map(|m| m.sat_id))
                        && e.measurements.iter().all(|m| check_measurement(m).is_ok())
                });
            ok.then_some(()).ok_or(format!("{:?}", t.epochs.first()))
        }),
        Reader::GnssLogger => parse_gnsslogger(&text, file).map(|log| {
            let obs = &log.observations;
            let times: Vec<f64> = obs.epochs.iter().map(|e| e.gps_time_s).collect();
            let ok = increasing(&times)
                && obs.epochs.iter().all(|e| {
                    distinct(e.satellites.iter().map(|s| (s.system, s.prn)))
                        && e.satellites.iter().all(|s| {
                            s.values.iter().flatten().all(|v| v.abs() <= 1e10)
                                && s.values
                                    .iter()
                                    .step_by(4)
                                    .flatten()
                                    .all(|c| (1e6..=1e8).contains(c))
                        })
                })
                && log.imu.as_ref().is_none_or(|imu| {
                    increasing(&imu.time_s)
                        && imu
                            .specific_force_m_s2
                            .iter()
                            .all(|f| f.amax() <= MAX_SPECIFIC_FORCE_M_S2)
                        && imu
                            .angular_rate_rad_s
                            .iter()
                            .all(|w| w.amax() <= MAX_ANGULAR_RATE_RAD_S)
                });
            ok.then_some(()).ok_or(format!("{:?}", obs.epochs.first()))
        }),
        Reader::Ubx => parse_ubx(bytes, file).map(|log| {
            let times: Vec<f64> = log.rawx.iter().map(|e| e.gps_time_s()).collect();
            let ok = increasing(&times)
                && times.iter().all(|t| plausible::GPS_TIME_S.contains(t))
                && log.rawx.iter().flat_map(|e| &e.signals).all(|s| {
                    let within = |code: &str, v: f64, valid: bool| {
                        v.is_finite() && (!valid || plausible::observation_range(code).contains(&v))
                    };
                    within("C", s.pseudorange_m, s.tracking.pseudorange_valid)
                        && within("L", s.carrier_phase_cycles, s.tracking.carrier_phase_valid)
                        && within("D", s.doppler_hz, true)
                })
                && solution_ok(&log.fixes)
                && written_and_read_back(&log)
                && increasing(&log.fixes.gps_time_s)
                && log.observations.epochs.len() == log.rawx.len()
                && log.gps_ephemerides.iter().all(|l| {
                    let e = &l.ephemeris;
                    // Every field of a decoded ephemeris is a scaled
                    // integer of the message: finite, √A below 2^13.
                    e.orbit.sqrt_a_sqrt_m < 8192.0
                        && (0.0..0.5).contains(&e.orbit.eccentricity)
                        && (e.orbit.toe_gps_s - l.transmission_gps_s).abs() <= 302_400.0
                })
                && log.gps_cnav_ephemerides.iter().all(|e| {
                    // √(A_REF + ΔA) within 2^16 m of 26 559 710 m.
                    (5100.0..5200.0).contains(&e.orbit.sqrt_a_sqrt_m)
                        && (0.0..0.5).contains(&e.orbit.eccentricity)
                        && (e.orbit.toe_gps_s - e.transmission_gps_s).abs() <= 302_400.0
                        && e.state_at(e.orbit.toe_gps_s, 7200.0)
                            .position_ecef
                            .iter()
                            .all(|x| x.is_finite())
                })
                && log
                    .klobuchar
                    .is_none_or(|k| k.validate("klobuchar").is_ok())
                && log.beidou_ephemerides.iter().all(|e| {
                    e.orbit.sqrt_a_sqrt_m < 8192.0
                        && (0.0..0.5).contains(&e.orbit.eccentricity)
                        && (e.orbit.toe_gps_s - e.transmission_gps_s).abs() <= 302_400.0
                        && e.state_at(e.orbit.toe_gps_s, 0.0)
                            .position_ecef
                            .iter()
                            .all(|x| x.is_finite())
                });
            ok.then_some(()).ok_or(format!("{:?}", log.messages))
        }),
        Reader::Sp3 => parse_sp3(&text, file).map(|sp3| {
            let ok = increasing(&sp3.time_gps_s)
                && sp3
                    .position_ecef
                    .iter()
                    .all(|p| p.iter().all(|x| x.is_nan() || x.abs() <= 1e8))
                && sp3.clock_s.iter().all(|c| c.is_nan() || c.abs() <= 1.0)
                && sp3.position_ecef.len() == sp3.time_gps_s.len() * sp3.satellites.len()
                && distinct(sp3.satellites.iter())
                && sp3.satellites.iter().all(|name| {
                    let b = name.as_bytes();
                    b.len() == 3
                        && b[0].is_ascii_uppercase()
                        && b[1..].iter().all(u8::is_ascii_digit)
                });
            ok.then_some(()).ok_or(format!("{:?}", sp3.time_gps_s))
        }),
    };
    match outcome {
        Ok(Ok(())) => Ok(true),
        Ok(Err(garbage)) => Err(format!(
            "a result that breaks the reader's guarantees: {garbage}"
        )),
        Err(e) if e.to_string().contains(file) => Ok(false),
        Err(e) => Err(format!("an error that does not name the file: {e}")),
    }
}

/// Whether a UBX log's observations and ephemerides come back whole from
/// memsnav's RINEX writer and readers (what `memsnav convert` writes).
fn written_and_read_back(log: &memsnav_core::logs::UbxLog) -> bool {
    let provenance = RinexProvenance::default();
    let e = log.nav_file_ephemerides();
    let nav_ok = [RinexNavVersion::V3_04, RinexNavVersion::V4_00]
        .into_iter()
        .all(|version| {
            let cnav = if version == RinexNavVersion::V4_00 {
                e.gps_cnav.len()
            } else {
                0
            };
            parse_broadcast_nav(&format_rinex_nav(&e, version, &provenance), "written.nav")
                .is_ok_and(|n| {
                    (n.gps_cnav.len(), n.galileo.len(), n.beidou.len())
                        == (cnav, e.galileo.len(), e.beidou.len())
                        && n.gps.len() >= e.gps_lnav.len()
                })
        });
    let obs = &log.observations;
    let obs_ok = obs.epochs.is_empty()
        || obs.observation_types.is_empty()
        || parse_rinex_obs(&format_rinex_obs(obs, &provenance), "written.obs")
            .is_ok_and(|back| back.epochs.len() <= obs.epochs.len());
    nav_ok && obs_ok
}

/// [`read`] on its own thread: a panic or a run longer than [`HANG`] is a
/// failure too.
fn read_in_time(reader: Reader, bytes: Vec<u8>, file: &'static str) -> Result<bool, String> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(read(reader, &bytes, file));
    });
    match rx.recv_timeout(HANG) {
        Ok(outcome) => outcome,
        Err(mpsc::RecvTimeoutError::Timeout) => Err(format!("no answer within {HANG:?}: a hang")),
        Err(mpsc::RecvTimeoutError::Disconnected) => Err("the reader panicked".into()),
    }
}

/// Values that break naive readers.
const NASTY_NUMBERS: [&str; 14] = [
    "1e308",
    "-1e308",
    "1e29",
    "1D+30",
    "NaN",
    "nan",
    "inf",
    "-inf",
    "-1",
    "0",
    "-0",
    "99999999999999999999",
    "4294967296",
    "1e-320",
];

#[derive(Debug, Clone)]
enum Mutation {
    FlipByte { at: usize, value: u8 },
    Truncate { at: usize },
    ReplaceNumber { nth: usize, with: usize },
    Insert { at: usize, bytes: Vec<u8> },
    DuplicateLine { nth: usize },
    DeleteLine { nth: usize },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        3 => (any::<usize>(), any::<u8>()).prop_map(|(at, value)| Mutation::FlipByte { at, value }),
        1 => any::<usize>().prop_map(|at| Mutation::Truncate { at }),
        3 => (any::<usize>(), 0..NASTY_NUMBERS.len()).prop_map(|(nth, with)| Mutation::ReplaceNumber { nth, with }),
        1 => (any::<usize>(), proptest::collection::vec(any::<u8>(), 1..16)).prop_map(|(at, bytes)| Mutation::Insert { at, bytes }),
        1 => any::<usize>().prop_map(|nth| Mutation::DuplicateLine { nth }),
        1 => any::<usize>().prop_map(|nth| Mutation::DeleteLine { nth }),
    ]
}

/// Byte ranges of the numbers in `bytes` (runs of digits, signs, points
/// and exponent letters that hold a digit).
fn numbers(bytes: &[u8]) -> Vec<(usize, usize)> {
    let part = |b: u8| b.is_ascii_digit() || matches!(b, b'.' | b'+' | b'-' | b'e' | b'E' | b'D');
    let mut out = Vec::new();
    let mut k = 0;
    while k < bytes.len() {
        if part(bytes[k]) {
            let start = k;
            while k < bytes.len() && part(bytes[k]) {
                k += 1;
            }
            if bytes[start..k].iter().any(u8::is_ascii_digit) {
                out.push((start, k));
            }
        } else {
            k += 1;
        }
    }
    out
}

/// Byte ranges of the lines of `bytes`, newline included.
fn lines(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = 0;
    for line in bytes.split_inclusive(|&b| b == b'\n') {
        out.push((start, start + line.len()));
        start += line.len();
    }
    out
}

fn apply(seed: &[u8], mutations: &[Mutation]) -> Vec<u8> {
    let mut b = seed.to_vec();
    for m in mutations {
        match m {
            Mutation::FlipByte { at, value } if !b.is_empty() => {
                let k = at % b.len();
                b[k] = *value;
            }
            Mutation::Truncate { at } => b.truncate(at % (b.len() + 1)),
            Mutation::ReplaceNumber { nth, with } => {
                let found = numbers(&b);
                if !found.is_empty() {
                    let (s, e) = found[nth % found.len()];
                    // Keep column-based formats aligned where the number fits.
                    let new = NASTY_NUMBERS[*with].as_bytes();
                    let mut field = vec![b' '; (e - s).saturating_sub(new.len())];
                    field.extend_from_slice(new);
                    b.splice(s..e, field);
                }
            }
            Mutation::Insert { at, bytes } => {
                let k = at % (b.len() + 1);
                b.splice(k..k, bytes.iter().copied());
            }
            Mutation::DuplicateLine { nth } => {
                let found = lines(&b);
                if !found.is_empty() {
                    let (s, e) = found[nth % found.len()];
                    let line = b[s..e].to_vec();
                    b.splice(e..e, line);
                }
            }
            Mutation::DeleteLine { nth } => {
                let found = lines(&b);
                if !found.is_empty() {
                    let (s, e) = found[nth % found.len()];
                    b.drain(s..e);
                }
            }
            _ => {}
        }
    }
    b
}

fn config() -> ProptestConfig {
    let cases = std::env::var("MEMSNAV_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(256);
    ProptestConfig {
        cases,
        // Shrinking a failure is worth a minute; the regression file keeps it.
        max_shrink_time: 60_000,
        ..ProptestConfig::default()
    }
}

fn check_mutated(reader: Reader, mutations: &[Mutation]) -> Result<(), TestCaseError> {
    let mut bytes = apply(seed(reader), mutations);
    if reader == Reader::Nmea {
        nmea_checksums(&mut bytes);
    }
    read_in_time(reader, bytes, "fuzzed")
        .map(|_| ())
        .map_err(TestCaseError::fail)
}

fn check_garbage(reader: Reader, prefix_len: usize, tail: &[u8]) -> Result<(), TestCaseError> {
    // A valid beginning (for the header checks to pass) and garbage after.
    let seed = seed(reader);
    let mut bytes = seed[..prefix_len % (seed.len() + 1)].to_vec();
    bytes.extend_from_slice(tail);
    read_in_time(reader, bytes, "fuzzed")
        .map(|_| ())
        .map_err(TestCaseError::fail)
}

macro_rules! fuzz_reader {
    ($mutated:ident, $garbage:ident, $reader:expr) => {
        proptest! {
            #![proptest_config(config())]
            #[test]
            fn $mutated(mutations in proptest::collection::vec(mutation(), 1..5)) {
                check_mutated($reader, &mutations)?;
            }

            #[test]
            fn $garbage(prefix_len in any::<usize>(), tail in proptest::collection::vec(any::<u8>(), 0..600)) {
                check_garbage($reader, prefix_len, &tail)?;
            }
        }
    };
}

fuzz_reader!(imu_csv_mutated, imu_csv_garbage, Reader::ImuCsv);
fuzz_reader!(time_tag_mutated, time_tag_garbage, Reader::TimeTag);
fuzz_reader!(pos_mutated, pos_garbage, Reader::Pos);
fuzz_reader!(rinex_obs_mutated, rinex_obs_garbage, Reader::RinexObs);
fuzz_reader!(rinex_nav_mutated, rinex_nav_garbage, Reader::RinexNav);
fuzz_reader!(klobuchar_mutated, klobuchar_garbage, Reader::Klobuchar);
fuzz_reader!(sp3_mutated, sp3_garbage, Reader::Sp3);
fuzz_reader!(fixes_csv_mutated, fixes_csv_garbage, Reader::FixesCsv);
fuzz_reader!(nmea_mutated, nmea_garbage, Reader::Nmea);
fuzz_reader!(gnss_table_mutated, gnss_table_garbage, Reader::GnssTable);
fuzz_reader!(gnsslogger_mutated, gnsslogger_garbage, Reader::GnssLogger);
fuzz_reader!(
    imu_increments_mutated,
    imu_increments_garbage,
    Reader::ImuIncrements
);
fuzz_reader!(ubx_mutated, ubx_garbage, Reader::Ubx);
fuzz_reader!(rinex2_obs_mutated, rinex2_obs_garbage, Reader::Rinex2Obs);
fuzz_reader!(glonass_nav_mutated, glonass_nav_garbage, Reader::GlonassNav);
fuzz_reader!(mixed_nav_mutated, mixed_nav_garbage, Reader::MixedNav);
fuzz_reader!(
    galileo_nav2_mutated,
    galileo_nav2_garbage,
    Reader::GalileoNav2
);
fuzz_reader!(rinex4_nav_mutated, rinex4_nav_garbage, Reader::Rinex4Nav);

/// A UBX frame of `class`, `id` and `payload` with its Fletcher checksum
/// (interface description §3.4).
fn ubx_frame(class: u8, id: u8, payload: &[u8]) -> Vec<u8> {
    let mut frame = vec![0xB5, 0x62, class, id];
    frame.extend_from_slice(&(payload.len() as u16).to_le_bytes());
    frame.extend_from_slice(payload);
    let (mut a, mut b) = (0u8, 0u8);
    for &x in &frame[2..] {
        a = a.wrapping_add(x);
        b = b.wrapping_add(a);
    }
    frame.extend([a, b]);
    frame
}

/// The payloads of the seed's GPS L2C and L5 RXM-SFRBX frames, and its
/// bytes up to the first of them (RAWX epochs among them, so the
/// reception time is known).
fn cnav_seed() -> (&'static [u8], Vec<&'static [u8]>) {
    let seed = seed(Reader::Ubx);
    let mut payloads = Vec::new();
    let mut first = None;
    let mut at = 0;
    while at + 8 <= seed.len() {
        let length = usize::from(u16::from_le_bytes([seed[at + 4], seed[at + 5]]));
        let payload = &seed[at + 6..at + 6 + length];
        if seed[at + 2..at + 4] == [0x02, 0x13]
            && payload[0] == 0
            && [3, 4, 6, 7].contains(&payload[2])
        {
            first.get_or_insert(at);
            payloads.push(payload);
        }
        at += 8 + length;
    }
    (&seed[..first.unwrap()], payloads)
}

/// One RXM-SFRBX of GPS L2C or L5 for the CNAV decoder: a real message
/// of the seed, the same with a byte changed (its CRC fails), or words
/// of garbage on any satellite, signal and word count.
#[derive(Debug, Clone)]
enum CnavFrame {
    Real { nth: usize },
    Damaged { nth: usize, at: usize, value: u8 },
    Garbage { sv_id: u8, sig: u8, words: Vec<u8> },
}

fn cnav_frame() -> impl Strategy<Value = CnavFrame> {
    prop_oneof![
        3 => any::<usize>().prop_map(|nth| CnavFrame::Real { nth }),
        2 => (any::<usize>(), any::<usize>(), any::<u8>()).prop_map(|(nth, at, value)| CnavFrame::Damaged { nth, at, value }),
        2 => (any::<u8>(), prop_oneof![Just(3u8), Just(4), Just(6), Just(7)], proptest::collection::vec(any::<u8>(), 0..48))
            .prop_map(|(sv_id, sig, words)| CnavFrame::Garbage { sv_id, sig, words }),
    ]
}

proptest! {
    #![proptest_config(config())]
    /// Well-framed CNAV words, real, damaged and garbage, in any order:
    /// the decoder's paths are reached behind the framing's checksum.
    #[test]
    fn ubx_cnav_frames(frames in proptest::collection::vec(cnav_frame(), 1..40)) {
        let (start, real) = cnav_seed();
        let mut bytes = start.to_vec();
        for f in &frames {
            let payload = match f {
                CnavFrame::Real { nth } => real[nth % real.len()].to_vec(),
                CnavFrame::Damaged { nth, at, value } => {
                    let mut p = real[nth % real.len()].to_vec();
                    let n = p.len() - 8;
                    p[8 + at % n] ^= value | 1;
                    p
                }
                CnavFrame::Garbage { sv_id, sig, words } => {
                    let n = words.len() / 4;
                    let mut p = vec![0, *sv_id, *sig, 0, n as u8, 0, 2, 0];
                    p.extend_from_slice(&words[..4 * n]);
                    p
                }
            };
            bytes.extend(ubx_frame(0x02, 0x13, &payload));
        }
        read_in_time(Reader::Ubx, bytes, "fuzzed")
            .map(|_| ())
            .map_err(TestCaseError::fail)?;
    }
}

/// The Hamming code of a GLONASS string (ICD edition 5.1 §4.7) written
/// into its bits 8-1, so that fuzzed contents reach the string decoder's
/// fields: `string` holds the ICD's bits 85..1 from its first bit on.
fn glonass_hamming(string: &mut [u8; 12]) {
    let get = |s: &[u8; 12], k: usize| s[(85 - k) / 8] >> (7 - (85 - k) % 8) & 1;
    let set = |s: &mut [u8; 12], k: usize, v: u8| {
        let i = 85 - k;
        s[i / 8] = (s[i / 8] & !(1 << (7 - i % 8))) | (v << (7 - i % 8));
    };
    let positions: Vec<u32> = (1..=84u32).filter(|p| !p.is_power_of_two()).collect();
    for i in 0..7 {
        let b = (9..=85)
            .zip(&positions)
            .filter(|(_, p)| *p >> i & 1 == 1)
            .fold(0, |acc, (k, _)| acc ^ get(string, k));
        set(string, i + 1, b);
    }
    let rest = (1..=85)
        .filter(|&k| k != 8)
        .fold(0, |acc, k| acc ^ get(string, k));
    set(string, 8, rest);
}

/// One RXM-SFRBX of GLONASS: string contents of any number, with a good
/// Hamming code or the bytes as drawn, the idle chip clear or not, on any
/// slot, channel and word count; or (`coherent`) a string 1-5 of slot 1-3
/// whose fields are in the ICD's ranges and whose string 4 names its slot,
/// so that ephemerides are assembled and written.
#[derive(Debug, Clone)]
struct GlonassFrame {
    sv_id: u8,
    freq_id: u8,
    m: u8,
    body: [u8; 12],
    good_code: bool,
    words: u8,
    coherent: bool,
}

/// Sets bit `i` (0 = the idle chip) of a string.
fn set_string_bit(string: &mut [u8; 12], i: usize, v: u8) {
    string[i / 8] = (string[i / 8] & !(1 << (7 - i % 8))) | (v << (7 - i % 8));
}

/// Makes a drawn string one a satellite could send: slot 1-3, channel
/// −7..+6, number 1-5, magnitudes within the ICD's ranges (their top bits
/// cleared), t_b 1-63 quarter hours, string 4's slot the frame's.
fn coherent_glonass(f: &mut GlonassFrame) {
    f.sv_id = 1 + f.sv_id % 3;
    f.freq_id %= 14;
    f.m = 1 + f.m % 5;
    f.good_code = true;
    f.words = 4;
    let s = &mut f.body;
    if (1..=3).contains(&f.m) {
        // Velocity magnitude bits 22-23, acceleration 46-47, position 51-52.
        for i in [22, 23, 46, 47, 51, 52] {
            set_string_bit(s, i, 0);
        }
    }
    if f.m == 2 {
        set_string_bit(s, 9, 0);
        set_string_bit(s, 15, 1);
    }
    if f.m == 4 {
        for (k, i) in (70..75).enumerate() {
            set_string_bit(s, i, f.sv_id >> (4 - k) & 1);
        }
    }
}

fn glonass_frame() -> impl Strategy<Value = GlonassFrame> {
    (
        prop_oneof![4 => 1u8..=24, 1 => any::<u8>()],
        prop_oneof![4 => 0u8..=13, 1 => any::<u8>()],
        prop_oneof![6 => 1u8..=5, 1 => 0u8..16],
        any::<[u8; 12]>(),
        prop_oneof![4 => Just(true), 1 => Just(false)],
        prop_oneof![6 => Just(4u8), 1 => 0u8..8],
        any::<bool>(),
    )
        .prop_map(|(sv_id, freq_id, m, body, good_code, words, coherent)| {
            let mut f = GlonassFrame {
                sv_id,
                freq_id,
                m,
                body,
                good_code,
                words,
                coherent,
            };
            if f.coherent {
                coherent_glonass(&mut f);
            }
            f
        })
}

proptest! {
    #![proptest_config(config())]
    /// GLONASS strings, most with a good Hamming code so that strings 1-5
    /// and their assembly into ephemerides are reached, in any order and
    /// on any satellite: the log reads without a panic, and any
    /// ephemeris it gives writes to a RINEX file and reads back.
    #[test]
    fn ubx_glonass_strings(frames in proptest::collection::vec(glonass_frame(), 1..60)) {
        let (start, _) = cnav_seed();
        let mut bytes = start.to_vec();
        for f in &frames {
            let mut string = f.body;
            // Bit 0 the idle chip (mostly clear), bits 1-4 the number m.
            string[0] = (string[0] & 0x87) | (f.m & 0x0F) << 3;
            if f.good_code {
                string[0] &= 0x7F;
            }
            // Bits 85-87 and the last byte are the padding after the string.
            string[10] &= 0xF8;
            string[11] = 0;
            if f.good_code {
                glonass_hamming(&mut string);
            }
            let n = usize::from(f.words);
            let mut words = [0u8; 16];
            for w in 0..3 {
                let be = [string[4 * w], string[4 * w + 1], string[4 * w + 2], string[4 * w + 3]];
                words[4 * w..4 * w + 4].copy_from_slice(&u32::from_be_bytes(be).to_le_bytes());
            }
            let mut p = vec![6, f.sv_id, 0, f.freq_id, f.words, 0, 2, 0];
            p.extend((0..4 * n).map(|k| words.get(k).copied().unwrap_or(0)));
            bytes.extend(ubx_frame(0x02, 0x13, &p));
        }
        let log = parse_ubx(&bytes, "fuzzed").map_err(|e| TestCaseError::fail(e.to_string()))?;
        if !log.glonass_ephemerides.is_empty() {
            let files = NavFileEphemerides {
                glonass: &log.glonass_ephemerides,
                ..Default::default()
            };
            let text = format_rinex_nav(&files, RinexNavVersion::V3_04, &Default::default());
            let back = parse_broadcast_nav(&text, "fuzzed.nav")
                .map_err(|e| TestCaseError::fail(e.to_string()))?;
            prop_assert_eq!(back.glonass.len(), log.glonass_ephemerides.len());
        }
    }
}

/// Recomputes the checksum of every `$...*hh` sentence (NMEA 0183: the
/// XOR of the bytes between `$` and `*`), so mutated sentences reach the
/// field parsers.
fn nmea_checksums(bytes: &mut [u8]) {
    let mut start = None;
    for k in 0..bytes.len() {
        match bytes[k] {
            b'$' => start = Some(k),
            b'\n' => start = None,
            b'*' if k + 2 < bytes.len() => {
                if let Some(s) = start.take() {
                    let sum = bytes[s + 1..k].iter().fold(0u8, |a, &b| a ^ b);
                    let hex = format!("{sum:02X}");
                    bytes[k + 1..k + 3].copy_from_slice(hex.as_bytes());
                }
            }
            _ => {}
        }
    }
}

/// The frames of a UBX log: (class, id, payload) of each whole frame.
fn ubx_frames(log: &[u8]) -> Vec<(u8, u8, Vec<u8>)> {
    let mut frames = Vec::new();
    let mut at = 0;
    while at + 8 <= log.len() {
        let length = usize::from(u16::from_le_bytes([log[at + 4], log[at + 5]]));
        if at + 8 + length > log.len() {
            break;
        }
        frames.push((
            log[at + 2],
            log[at + 3],
            log[at + 6..at + 6 + length].to_vec(),
        ));
        at += 8 + length;
    }
    frames
}

/// LNAV parity (IS-GPS-200 §20.3.5.2, table 20-XIV) of 24 source data
/// bits with the previous word's `d29`, `d30`: the word in u-blox's layout
/// (D29*, D30* in bits 31-30, the transmitted bits, the parity).
fn lnav_word(data: u32, d29: u32, d30: u32) -> u32 {
    const SUMS: [(bool, u32); 6] = [
        (false, 0b1110_1100_0111_1100_1101_0010),
        (true, 0b0111_0110_0011_1110_0110_1001),
        (false, 0b1011_1011_0001_1111_0011_0100),
        (true, 0b0101_1101_1000_1111_1001_1010),
        (true, 0b1010_1110_1100_0111_1100_1101),
        (false, 0b0010_1101_1110_1010_0010_0111),
    ];
    let parity = SUMS.iter().fold(0, |acc, &(from_d30, mask)| {
        let start = if from_d30 { d30 } else { d29 };
        (acc << 1) | (start ^ (data & mask).count_ones() & 1)
    });
    let transmitted = if d30 == 1 { data ^ 0x00FF_FFFF } else { data };
    (d29 << 31) | (d30 << 30) | (transmitted << 6) | parity
}

/// The 24 source data bits of an LNAV word in u-blox's layout.
fn lnav_data(word: u32) -> u32 {
    ((word >> 6) & 0x00FF_FFFF) ^ if word >> 30 & 1 == 1 { 0x00FF_FFFF } else { 0 }
}

/// A change to a UBX log behind its checks.
#[derive(Debug, Clone)]
enum UbxMutation {
    /// A payload byte of frame `nth` set to `value`.
    Byte {
        nth: usize,
        at: usize,
        value: u8,
    },
    /// A value no receiver reports written at a payload offset.
    Field {
        nth: usize,
        at: usize,
        with: usize,
    },
    /// Source data bits of an LNAV word flipped, the parity recomputed.
    LnavBits {
        nth: usize,
        word: usize,
        bits: u32,
    },
    /// A frame repeated, dropped, or moved.
    Duplicate {
        nth: usize,
    },
    Delete {
        nth: usize,
    },
    Move {
        nth: usize,
        to: usize,
    },
}

/// Little-endian values that break naive decoders, for [`UbxMutation::Field`].
fn nasty_field(with: usize) -> Vec<u8> {
    match with % 12 {
        0 => f64::INFINITY.to_le_bytes().to_vec(),
        1 => f64::NEG_INFINITY.to_le_bytes().to_vec(),
        2 => f64::NAN.to_le_bytes().to_vec(),
        3 => 1e300f64.to_le_bytes().to_vec(),
        4 => (-1.0f64).to_le_bytes().to_vec(),
        5 => f32::INFINITY.to_le_bytes().to_vec(),
        6 => f32::NAN.to_le_bytes().to_vec(),
        7 => i32::MIN.to_le_bytes().to_vec(),
        8 => i32::MAX.to_le_bytes().to_vec(),
        9 => 9999u16.to_le_bytes().to_vec(),
        10 => 0u16.to_le_bytes().to_vec(),
        _ => u32::MAX.to_le_bytes().to_vec(),
    }
}

fn ubx_mutation() -> impl Strategy<Value = UbxMutation> {
    prop_oneof![
        3 => (any::<usize>(), any::<usize>(), any::<u8>()).prop_map(|(nth, at, value)| UbxMutation::Byte { nth, at, value }),
        3 => (any::<usize>(), any::<usize>(), any::<usize>()).prop_map(|(nth, at, with)| UbxMutation::Field { nth, at, with }),
        4 => (any::<usize>(), 0..10usize, 1..0x0100_0000u32).prop_map(|(nth, word, bits)| UbxMutation::LnavBits { nth, word, bits }),
        1 => any::<usize>().prop_map(|nth| UbxMutation::Duplicate { nth }),
        1 => any::<usize>().prop_map(|nth| UbxMutation::Delete { nth }),
        1 => (any::<usize>(), any::<usize>()).prop_map(|(nth, to)| UbxMutation::Move { nth, to }),
    ]
}

/// The seed log with `mutations` applied, every frame re-framed with its
/// Fletcher checksum.
fn apply_ubx(mutations: &[UbxMutation]) -> Vec<u8> {
    let mut frames = ubx_frames(seed(Reader::Ubx));
    for m in mutations {
        let n = frames.len();
        if n == 0 {
            break;
        }
        match m {
            UbxMutation::Byte { nth, at, value } => {
                let p = &mut frames[nth % n].2;
                if !p.is_empty() {
                    let k = at % p.len();
                    p[k] = *value;
                }
            }
            UbxMutation::Field { nth, at, with } => {
                let p = &mut frames[nth % n].2;
                let value = nasty_field(*with);
                if p.len() >= value.len() {
                    let k = at % (p.len() - value.len() + 1);
                    p[k..k + value.len()].copy_from_slice(&value);
                }
            }
            UbxMutation::LnavBits { nth, word, bits } => {
                // The GPS L1 C/A RXM-SFRBX frames (gnssId 0, sigId 0, ten words).
                let lnav: Vec<usize> = (0..n)
                    .filter(|&k| {
                        let (c, i, p) = &frames[k];
                        (*c, *i) == (0x02, 0x13) && p.len() == 48 && p[0] == 0 && p[2] == 0
                    })
                    .collect();
                if lnav.is_empty() {
                    continue;
                }
                // The word keeps its D29*, D30* (bits 31-30, which the
                // receiver sets and the decoder reads the parity with).
                let p = &mut frames[lnav[nth % lnav.len()]].2;
                let at = 8 + 4 * word;
                let w = u32::from_le_bytes(p[at..at + 4].try_into().unwrap());
                let new = lnav_word(lnav_data(w) ^ bits, w >> 31, w >> 30 & 1);
                p[at..at + 4].copy_from_slice(&new.to_le_bytes());
            }
            UbxMutation::Duplicate { nth } => {
                let f = frames[nth % n].clone();
                frames.insert(nth % n, f);
            }
            UbxMutation::Delete { nth } => {
                frames.remove(nth % n);
            }
            UbxMutation::Move { nth, to } => {
                let f = frames.remove(nth % n);
                frames.insert(to % n, f);
            }
        }
    }
    frames
        .iter()
        .flat_map(|(c, i, p)| ubx_frame(*c, *i, p))
        .collect()
}

proptest! {
    #![proptest_config(config())]
    /// Fields, frames and LNAV words changed behind valid checks: the
    /// decoders' results hold only values a receiver reports and come
    /// back whole through memsnav's RINEX files.
    #[test]
    fn ubx_behind_valid_checks(mutations in proptest::collection::vec(ubx_mutation(), 1..6)) {
        read_in_time(Reader::Ubx, apply_ubx(&mutations), "fuzzed")
            .map(|_| ())
            .map_err(TestCaseError::fail)?;
    }
}

#[test]
fn the_structured_mutators_keep_the_checks_valid() {
    // Re-framing and re-parity of the unchanged seed give the seed back.
    assert_eq!(apply_ubx(&[]), seed(Reader::Ubx));
    let same = apply_ubx(&[UbxMutation::LnavBits {
        nth: 3,
        word: 4,
        bits: 0,
    }]);
    assert_eq!(same, seed(Reader::Ubx));
    // A flipped √A bit: the subframe still passes its parity (the log
    // decodes no fewer subframes), the orbit changes.
    let seed_log = parse_ubx(seed(Reader::Ubx), "seed").unwrap();
    let changed = apply_ubx(&[UbxMutation::LnavBits {
        nth: 0,
        word: 8,
        bits: 1 << 23,
    }]);
    let log = parse_ubx(&changed, "changed").unwrap();
    assert_eq!(
        log.skipped.get("GPS LNAV subframes with a parity failure"),
        seed_log
            .skipped
            .get("GPS LNAV subframes with a parity failure")
    );
    assert_eq!(log.skipped.get("frames with a bad checksum"), None);
    let mut nmea = NMEA_SEED.as_bytes().to_vec();
    nmea_checksums(&mut nmea);
    assert_eq!(nmea, NMEA_SEED.as_bytes());
}

#[test]
fn the_seeds_read_cleanly() {
    for reader in [
        Reader::ImuCsv,
        Reader::TimeTag,
        Reader::Pos,
        Reader::RinexObs,
        Reader::RinexNav,
        Reader::Klobuchar,
        Reader::Sp3,
        Reader::FixesCsv,
        Reader::Nmea,
        Reader::GnssTable,
        Reader::GnssLogger,
        Reader::ImuIncrements,
        Reader::Ubx,
        Reader::Rinex2Obs,
        Reader::GlonassNav,
        Reader::MixedNav,
        Reader::GalileoNav2,
        Reader::Rinex4Nav,
    ] {
        assert_eq!(read(reader, seed(reader), "seed"), Ok(true), "{reader:?}");
    }
}

#[test]
fn regression_files_are_refused_with_their_name() {
    let dir = data("regressions");
    let mut replayed = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let reader = match path.extension().and_then(|e| e.to_str()) {
            Some("csv") => Reader::ImuCsv,
            Some("tag") => Reader::TimeTag,
            Some("pos") => Reader::Pos,
            Some("obs") => Reader::RinexObs,
            Some("nav") => Reader::RinexNav,
            Some("sp3") => Reader::Sp3,
            Some("nmea") => Reader::Nmea,
            Some("ubx") => Reader::Ubx,
            _ => continue,
        };
        let name: &'static str = path
            .file_name()
            .unwrap()
            .to_str()
            .unwrap()
            .to_string()
            .leak();
        let outcome = read_in_time(reader, std::fs::read(&path).unwrap(), name);
        assert_eq!(outcome, Ok(false), "{name} must be an error naming it");
        replayed += 1;
    }
    assert!(replayed >= 22, "{replayed} files replayed");
}
