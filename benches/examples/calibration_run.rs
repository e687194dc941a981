//! Times the parts of one run of the calibration experiment (300 s at
//! 100 Hz, the paper's MEMS IMU) `REPEATS` times (default 20) and prints
//! the best and median of each, for `docs/results/performance.md` and for profilers
//! (`perf record target/release/examples/calibration_run 50`):
//! `cargo run --release -p memsnav-benches --example calibration_run -- 20`.

use std::time::Instant;

use memsnav_benches::SEED;
use memsnav_core::calibration::{
    accelerometer_crb, calibrate_accelerometer, calibrate_gyroscope, gyroscope_crb,
    CalibrationOptions, Method,
};
use memsnav_core::experiments::{
    calibration_experiment, motion, CalibrationExperimentConfig, REFERENCE_ANGULAR_RATE_STD,
    REFERENCE_SPECIFIC_FORCE_STD,
};
use memsnav_core::montecarlo::RunOptions;
use memsnav_core::random::stream;
use memsnav_core::sensors::ImuModel;
use nalgebra::Vector3;
use rand::Rng as _;
use rand_distr::StandardNormal;

fn noisy(v: &[Vector3<f64>], std: f64, rng: &mut memsnav_core::random::Rng) -> Vec<Vector3<f64>> {
    v.iter()
        .map(|x| x + Vector3::from_fn(|_, _| std * rng.sample::<f64, _>(StandardNormal)))
        .collect()
}

/// Best and median of `times` (seconds) in ms.
fn report(name: &str, mut times: Vec<f64>) {
    times.sort_by(f64::total_cmp);
    println!(
        "{name:>28}: best {:7.3} ms, median {:7.3} ms",
        times[0] * 1e3,
        times[times.len() / 2] * 1e3
    );
}

fn main() {
    let repeats: usize = std::env::args()
        .nth(1)
        .map(|a| a.parse().expect("REPEATS must be a whole number"))
        .unwrap_or(20);
    let (sf, sw) = (REFERENCE_SPECIFIC_FORCE_STD, REFERENCE_ANGULAR_RATE_STD);
    let ls = CalibrationOptions::default();
    let eiv_a = CalibrationOptions {
        method: Method::ErrorsInVariables,
        reference_noise_std: Some(sf),
        ..Default::default()
    };
    let eiv_g = CalibrationOptions {
        method: Method::ErrorsInVariables,
        reference_noise_std: Some(sw),
        reference_specific_force_noise_std: Some(sf),
        ..Default::default()
    };
    let names = [
        "motion (land vehicle)",
        "sensor simulation",
        "reference noise",
        "accelerometer LS",
        "accelerometer EIV",
        "accelerometer CRB",
        "gyroscope LS",
        "gyroscope EIV",
        "gyroscope CRB",
        "whole experiment run",
    ];
    let mut times: Vec<Vec<f64>> = vec![Vec::with_capacity(repeats); names.len()];
    let config = CalibrationExperimentConfig {
        parameter_sets: 1,
        runs_per_set: 1,
        duration_s: 300.0,
        seed: SEED,
        ..Default::default()
    };
    let one_thread = RunOptions {
        threads: Some(1),
        ..Default::default()
    };
    for r in 0..repeats {
        let mut rng = stream(SEED, r as u64);
        let imu = ImuModel::preset("paper-mems", &mut rng).expect("preset");
        let mut lap = {
            let mut t = Instant::now();
            move |k: usize, times: &mut Vec<Vec<f64>>| {
                times[k].push(t.elapsed().as_secs_f64());
                t = Instant::now();
            }
        };
        let m = motion::land_vehicle(300.0, 100.0, &mut rng).expect("motion");
        lap(0, &mut times);
        let readings = imu
            .measure(&m.specific_force_b, &m.angular_rate_b, &mut rng)
            .expect("readings");
        lap(1, &mut times);
        let f_ref = noisy(&m.specific_force_b, sf, &mut rng);
        let w_ref = noisy(&m.angular_rate_b, sw, &mut rng);
        lap(2, &mut times);
        calibrate_accelerometer(&readings.specific_force_b, &f_ref, &ls).expect("LS");
        lap(3, &mut times);
        calibrate_accelerometer(&readings.specific_force_b, &f_ref, &eiv_a).expect("EIV");
        lap(4, &mut times);
        accelerometer_crb(
            &m.specific_force_b,
            &imu.accelerometer,
            1e-3,
            &Default::default(),
        )
        .expect("CRB");
        lap(5, &mut times);
        calibrate_gyroscope(&readings.angular_rate_b, &w_ref, &f_ref, &ls).expect("LS");
        lap(6, &mut times);
        calibrate_gyroscope(&readings.angular_rate_b, &w_ref, &f_ref, &eiv_g).expect("EIV");
        lap(7, &mut times);
        gyroscope_crb(
            &m.angular_rate_b,
            &m.specific_force_b,
            &imu.gyroscope,
            1e-4,
            &Default::default(),
        )
        .expect("CRB");
        lap(8, &mut times);
        let config = CalibrationExperimentConfig {
            seed: SEED + r as u64,
            ..config.clone()
        };
        calibration_experiment(&config, &motion::land_vehicle, &one_thread).expect("run");
        lap(9, &mut times);
    }
    println!(
        "one calibration-experiment run, 300 s at 100 Hz (30 001 samples), {repeats} repeats:"
    );
    for (name, t) in names.iter().zip(times) {
        report(name, t);
    }
}
