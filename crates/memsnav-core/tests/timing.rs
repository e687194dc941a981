//! Time alignment: a simulated drive with a known IMU time offset and
//! known velocity latencies, recovered by the lag searches; the real logs'
//! time tags against their file sizes and the offsets found in them.

use std::path::PathBuf;

mod shared_data;
use shared_data::shared_data;

use memsnav_core::geodesy::{meridian_radius, transverse_radius};
use memsnav_core::logs::{
    read_imu_csv, read_pos, read_time_tag, AccelUnit, GyroUnit, ImuCsvLayout, TimeUnit,
};
use memsnav_core::random::stream;
use memsnav_core::timing::*;
use nalgebra::{Matrix3, Vector3};
use rand_distr::{Distribution, StandardNormal};

const G: f64 = 9.80665;

/// A car on a level road: speed and heading in closed form (speed
/// 5.5-14.5 m/s, heading swinging ±1.1 rad), position integrated finely.
struct Drive;

impl Drive {
    fn speed(t: f64) -> f64 {
        10.0 + 3.0 * (0.31 * t).sin() + 1.5 * (1.13 * t + 0.4).sin()
    }
    fn speed_rate(t: f64) -> f64 {
        0.93 * (0.31 * t).cos() + 1.695 * (1.13 * t + 0.4).cos()
    }
    fn heading(t: f64) -> f64 {
        0.8 * (0.17 * t).sin() + 0.3 * (0.61 * t + 1.0).sin()
    }
    fn heading_rate(t: f64) -> f64 {
        0.136 * (0.17 * t).cos() + 0.183 * (0.61 * t + 1.0).cos()
    }

    /// [lat, lon, h] every `step` s over `duration` s near Boulder, with the
    /// NED velocity at each epoch.
    fn gnss(duration: f64, step: f64) -> (Vec<f64>, Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
        let (lat0, lon0, h0) = (40.0966_f64.to_radians(), -105.147_f64.to_radians(), 1600.0);
        let velocity = |t: f64| {
            let (s, c) = Self::heading(t).sin_cos();
            Vector3::new(Self::speed(t) * c, Self::speed(t) * s, 0.0)
        };
        let fine = 1e-3;
        let per_epoch = (step / fine).round() as usize;
        let mut ned = Vector3::zeros();
        let (mut time, mut lla, mut vel) = (Vec::new(), Vec::new(), Vec::new());
        let n = (duration / step) as usize;
        for k in 0..=n {
            let t = k as f64 * step;
            time.push(t);
            lla.push(Vector3::new(
                lat0 + ned.x / (meridian_radius(lat0) + h0),
                lon0 + ned.y / ((transverse_radius(lat0) + h0) * lat0.cos()),
                h0,
            ));
            vel.push(velocity(t));
            for j in 0..per_epoch {
                // Simpson over each fine step.
                let a = t + j as f64 * fine;
                ned += (velocity(a) + 4.0 * velocity(a + fine / 2.0) + velocity(a + fine)) * fine
                    / 6.0;
            }
        }
        (time, lla, vel)
    }

    /// 100 Hz IMU in body axes (FRD) taken at t + `offset` but stamped t,
    /// with white noise (seeded).
    fn imu(duration: f64, offset: f64) -> (Vec<f64>, Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
        let mut rng = stream(7, 0);
        let mut noise = |std: f64| -> f64 {
            let z: f64 = StandardNormal.sample(&mut rng);
            std * z
        };
        let (mut time, mut force, mut rate) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..(duration * 100.0) as usize {
            let stamp = 0.003 + 0.01 * k as f64;
            let t = stamp + offset;
            time.push(stamp);
            force.push(Vector3::new(
                Self::speed_rate(t) + noise(0.05),
                Self::speed(t) * Self::heading_rate(t) + noise(0.05),
                -G + noise(0.05),
            ));
            rate.push(Vector3::new(
                noise(0.003),
                noise(0.003),
                Self::heading_rate(t) + noise(0.003),
            ));
        }
        (time, force, rate)
    }
}

#[test]
fn a_known_imu_offset_is_recovered_from_either_signal() {
    let offset = -0.27;
    let (gnss_time, lla, _) = Drive::gnss(240.0, 0.25);
    let (imu_time, force, rate) = Drive::imu(240.0, offset);
    for signal in [OffsetSignal::AlongTrack, OffsetSignal::YawRate] {
        let options = TimeOffsetOptions {
            signal,
            max_offset_s: 1.0,
            step_s: 0.01,
            min_speed_m_s: 3.0,
            blocks: 4,
        };
        let e = estimate_time_offset(&imu_time, &force, &rate, &gnss_time, &lla, &options).unwrap();
        // The IMU was stamped 0.27 s early: the offset to add is −0.27 s.
        assert!((e.lag_s - offset).abs() < 3e-3, "{signal:?}: {}", e.lag_s);
        assert!(e.score > 0.99 && e.curvature > 0.0, "{signal:?}: {e:?}");
        assert!(
            e.std_s < 3e-3 && e.block_lag_s.len() == 4,
            "{signal:?}: {e:?}"
        );
        assert!(e.samples > 900, "{}", e.samples);
    }
    // The peak moves with the offset: a log stamped right gives zero.
    let (imu_time, force, rate) = Drive::imu(240.0, 0.0);
    let options = TimeOffsetOptions {
        signal: OffsetSignal::AlongTrack,
        max_offset_s: 0.5,
        step_s: 0.005,
        min_speed_m_s: 3.0,
        blocks: 2,
    };
    let e = estimate_time_offset(&imu_time, &force, &rate, &gnss_time, &lla, &options).unwrap();
    assert!(e.lag_s.abs() < 3e-3, "{}", e.lag_s);
    // An offset outside the window is refused, not returned at the edge.
    let (imu_time, force, rate) = Drive::imu(240.0, 0.8);
    let err =
        estimate_time_offset(&imu_time, &force, &rate, &gnss_time, &lla, &options).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("max_offset_s: the best lag lies at the edge"),
        "{err}"
    );
}

#[test]
fn velocity_latencies_are_recovered() {
    let (time, lla, velocity) = Drive::gnss(240.0, 0.25);
    let options = VelocityLatencyOptions {
        max_latency_s: 0.5,
        step_s: 0.01,
        blocks: 4,
    };
    // The true velocity 0.1 s late.
    let (late_time, _, late) = Drive::gnss(240.0 + 0.1, 0.05);
    let delayed: Vec<Vector3<f64>> = time
        .iter()
        .map(|&t| late[((t - 0.1).max(0.0) / 0.05).round() as usize])
        .collect();
    assert_eq!(late_time[2], 0.1);
    let e = estimate_velocity_latency(&time[2..], &lla[2..], &delayed[2..], &options).unwrap();
    assert!((e.lag_s - 0.1).abs() < 2e-3 && e.score < 0.02, "{e:?}");
    // Exact velocities: no latency.
    let e = estimate_velocity_latency(&time, &lla, &velocity, &options).unwrap();
    assert!(e.lag_s.abs() < 2e-3, "{e:?}");
    assert!(e.std_s < 2e-3, "{e:?}");
    // Backward differences of the positions (what RTKLIB reports): h/2.
    let (r_m, r_n) = (
        meridian_radius(lla[0].x) + 1600.0,
        (transverse_radius(lla[0].x) + 1600.0) * lla[0].x.cos(),
    );
    let scale = Matrix3::from_diagonal(&Vector3::new(r_m, r_n, -1.0));
    let mut backward = vec![velocity[0]];
    backward.extend(lla.windows(2).map(|w| scale * (w[1] - w[0]) / 0.25));
    let e = estimate_velocity_latency(&time, &lla, &backward, &options).unwrap();
    assert!((e.lag_s - 0.125).abs() < 1e-3, "{e:?}");
    // No velocity at all (a .pos without velocity columns).
    let nan = vec![Vector3::repeat(f64::NAN); time.len()];
    let err = estimate_velocity_latency(&time, &lla, &nan, &options).unwrap_err();
    assert!(
        err.to_string().starts_with("velocity_ned: has NaN rows"),
        "{err}"
    );
}

fn real(name: &str) -> PathBuf {
    shared_data(&format!("real-imu-gnss/{name}"))
}

fn layout() -> ImuCsvLayout {
    ImuCsvLayout {
        skip_first_line: true,
        ..ImuCsvLayout::new(
            AccelUnit::StandardGravity,
            GyroUnit::DegreesPerSecond,
            TimeUnit::Milliseconds,
        )
    }
}

/// The data authors' mounting of drive_0708, sensor to body (FRD):
/// roll/pitch/yaw (180, 0, 180) then (0, −6.79, 5.35) degrees.
fn drive_mounting() -> Matrix3<f64> {
    let dcm = |r: f64, p: f64, y: f64| {
        memsnav_core::attitude::euler_to_dcm(r.to_radians(), p.to_radians(), y.to_radians())
    };
    dcm(0.0, -6.79, 5.35) * dcm(180.0, 0.0, 180.0)
}

#[test]
fn real_tags_count_crlf_line_ends_and_arrive_within_40_ms() {
    for (csv, spread_limit) in [
        ("drive_0708/imu_1934.csv", 0.042),
        ("walk_0827/imu_1730.csv", 0.11),
    ] {
        let log = read_imu_csv(real(csv), &layout()).unwrap();
        let tag = read_time_tag(real(&format!("{csv}.tag"))).unwrap();
        // The tag's last file position is the file size plus one byte per
        // newline: the log was written with CR LF and stored with LF.
        let size = std::fs::metadata(real(csv)).unwrap().len();
        let newlines = std::fs::read(real(csv))
            .unwrap()
            .iter()
            .filter(|&&b| b == b'\n')
            .count() as u64;
        assert_eq!(*tag.file_offset.last().unwrap(), size + newlines, "{csv}");
        let clock = tag_clock(&log, &tag, None).unwrap();
        assert_eq!(clock.line_ends, LineEnds::CrLfCounted);
        assert_eq!(clock.tagged_samples, log.time_s.len());
        assert!(clock.rate_ppm.abs() < 100.0, "{csv}: {}", clock.rate_ppm);
        assert!(
            clock.arrival_lag_spread_s < spread_limit,
            "{csv}: {}",
            clock.arrival_lag_spread_s
        );
        // Counted byte for byte, the lag drifts by seconds (the "12.2 s
        // arrival-lag drift" once reported for the drive).
        let wrong = tag_clock(&log, &tag, Some(LineEnds::AsInFile)).unwrap();
        assert!(wrong.rate_ppm < -10_000.0, "{csv}: {}", wrong.rate_ppm);
        eprintln!(
            "{csv}: {} lines, tag ends at {} = size {size} + {newlines}; rate {:.1} ppm, spread {:.3} s (LF-only: {:.0} ppm, spread {:.2} s)",
            log.time_s.len(),
            tag.file_offset.last().unwrap(),
            clock.rate_ppm,
            clock.arrival_lag_spread_s,
            wrong.rate_ppm,
            wrong.arrival_lag_spread_s
        );
    }
}

#[test]
fn the_drive_imu_runs_a_quarter_second_early_and_rtk_velocities_lag_by_an_eighth_or_more() {
    let log = read_imu_csv(real("drive_0708/imu_1934.csv"), &layout()).unwrap();
    let tag = read_time_tag(real("drive_0708/imu_1934.csv.tag")).unwrap();
    let clock = tag_clock(&log, &tag, None).unwrap();
    let c_b_s = drive_mounting();
    let force: Vec<_> = log.specific_force_m_s2.iter().map(|f| c_b_s * f).collect();
    let rate: Vec<_> = log.angular_rate_rad_s.iter().map(|w| c_b_s * w).collect();
    let pos = read_pos(real("drive_0708/gnss_1934_sf.pos")).unwrap();
    let mut found = Vec::new();
    for signal in [OffsetSignal::AlongTrack, OffsetSignal::YawRate] {
        let options = TimeOffsetOptions {
            signal,
            max_offset_s: 1.0,
            step_s: 0.005,
            min_speed_m_s: 3.0,
            blocks: 4,
        };
        let e = estimate_time_offset(
            &clock.gps_time_s,
            &force,
            &rate,
            &pos.gps_time_s,
            &pos.lla,
            &options,
        )
        .unwrap();
        eprintln!("drive {signal:?}: offset {:.4} s ± {:.4} (blocks {:?}), correlation {:.3}, curvature {:.2}/s², {} epochs", e.lag_s, e.std_s, e.block_lag_s, e.score, e.curvature, e.samples);
        found.push(e.lag_s);
    }
    // Along-track: −0.27 s, not the data authors' −0.125 s; the yaw rate
    // (biased by side-slip) 50 ms less negative.
    assert!((-0.30..=-0.24).contains(&found[0]), "{found:?}");
    assert!((-0.26..=-0.17).contains(&found[1]), "{found:?}");
    // The RTK velocities lag their positions by a little more than the
    // h/2 = 0.125 s of a backward difference (they are within 0.03 m/s of
    // one): 0.13 s on the drive, 0.145 s on the walk.
    for (file, latency) in [
        ("drive_0708/gnss_1934_sf.pos", 0.12..=0.14),
        ("walk_0827/gnss_1730_sf.pos", 0.13..=0.16),
    ] {
        let pos = read_pos(real(file)).unwrap();
        let options = VelocityLatencyOptions {
            max_latency_s: 0.5,
            step_s: 0.005,
            blocks: 4,
        };
        let e =
            estimate_velocity_latency(&pos.gps_time_s, &pos.lla, &pos.velocity_ned_m_s, &options)
                .unwrap();
        eprintln!(
            "{file}: velocity latency {:.4} s ± {:.4} (blocks {:?}), RMS {:.3} m/s",
            e.lag_s, e.std_s, e.block_lag_s, e.score
        );
        assert!(
            latency.contains(&e.lag_s) && e.std_s < 0.005,
            "{file}: {e:?}"
        );
    }
}
