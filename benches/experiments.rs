//! Calibration, inversion and Monte Carlo benchmarks:
//! `cargo bench -p memsnav-benches --bench experiments`.
//!
//! - calibration of 60 000 samples (600 s at 100 Hz), both triads, plain
//!   LS and errors-in-variables;
//! - the inversion filters (accelerometer, gyroscope), throughput per sample;
//! - one run of the calibration experiment (300 s, both triads, LS + EIV + CRB);
//! - Monte Carlo throughput with 1 and 2 threads: the calibration
//!   experiment and the navigation experiment (the paper's three IMUs),
//!   and the reference whole run (the raw MEMS IMU alone, 1 thread);
//! - the simulator of the reference workload by part (600 s trajectory,
//!   IMU errors, GNSS).

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use memsnav_benches::SEED;
use memsnav_core::calibration::{
    calibrate_accelerometer, calibrate_gyroscope, CalibrationOptions, Method,
};
use memsnav_core::experiments::navigation::paper_imus;
use memsnav_core::experiments::{
    calibration_experiment, motion, navigation_experiment, CalibrationExperimentConfig,
    NavigationExperimentConfig, REFERENCE_ANGULAR_RATE_STD, REFERENCE_SPECIFIC_FORCE_STD,
};
use memsnav_core::gnss::{self, Constellation, ReceiverTrack, SimulationConfig, WalkerConfig};
use memsnav_core::inversion::{invert_accelerometer, invert_gyroscope, InversionNoise};
use memsnav_core::montecarlo::RunOptions;
use memsnav_core::random::stream;
use memsnav_core::sensors::ImuModel;
use memsnav_core::trajectory::{RandomTrajectoryConfig, Trajectory};
use nalgebra::Vector3;
use rand::Rng as _;
use rand_distr::StandardNormal;

fn noisy(v: &[Vector3<f64>], std: f64, rng: &mut memsnav_core::random::Rng) -> Vec<Vector3<f64>> {
    v.iter()
        .map(|x| x + Vector3::from_fn(|_, _| std * rng.sample::<f64, _>(StandardNormal)))
        .collect()
}

fn calibration_and_inversion(c: &mut Criterion) {
    let mut rng = stream(SEED, 1);
    let m = motion::land_vehicle(600.0 - 0.01, 100.0, &mut rng).unwrap();
    let n = m.specific_force_b.len();
    assert_eq!(n, 60_000);
    let imu = ImuModel::preset("paper-mems", &mut rng).unwrap();
    let readings = imu
        .measure(&m.specific_force_b, &m.angular_rate_b, &mut rng)
        .unwrap();
    let (sf, sw) = (REFERENCE_SPECIFIC_FORCE_STD, REFERENCE_ANGULAR_RATE_STD);
    let f_ref = noisy(&m.specific_force_b, sf, &mut rng);
    let w_ref = noisy(&m.angular_rate_b, sw, &mut rng);
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
    let mut g = c.benchmark_group("calibration_60000_samples");
    g.sample_size(10);
    g.throughput(Throughput::Elements(n as u64));
    for (name, options) in [("ls", &ls), ("eiv", &eiv_a)] {
        g.bench_function(format!("accelerometer_{name}"), |b| {
            b.iter(|| calibrate_accelerometer(&readings.specific_force_b, &f_ref, options).unwrap())
        });
    }
    for (name, options) in [("ls", &ls), ("eiv", &eiv_g)] {
        g.bench_function(format!("gyroscope_{name}"), |b| {
            b.iter(|| {
                calibrate_gyroscope(&readings.angular_rate_b, &w_ref, &f_ref, options).unwrap()
            })
        });
    }
    g.finish();

    let mut g = c.benchmark_group("inversion");
    g.sample_size(10);
    g.throughput(Throughput::Elements(n as u64));
    let noise_a = InversionNoise {
        process_std: Vector3::repeat(0.1),
        measurement_std: Vector3::repeat(imu.accelerometer.noise.white_std_per_sample(100.0)),
    };
    let noise_g = InversionNoise {
        process_std: Vector3::repeat(1f64.to_radians()),
        measurement_std: Vector3::repeat(imu.gyroscope.noise.white_std_per_sample(100.0)),
    };
    g.bench_function("accelerometer_per_sample", |b| {
        b.iter(|| {
            invert_accelerometer(
                black_box(&readings.specific_force_b),
                &imu.accelerometer,
                &noise_a,
            )
            .unwrap()
        })
    });
    g.bench_function("gyroscope_per_sample", |b| {
        b.iter(|| {
            invert_gyroscope(
                black_box(&readings.angular_rate_b),
                &m.specific_force_b,
                &imu.gyroscope,
                &noise_g,
            )
            .unwrap()
        })
    });
    g.finish();
}

fn threads(n: usize) -> RunOptions<'static> {
    RunOptions {
        threads: Some(n),
        ..Default::default()
    }
}

/// Runs per second of the experiments with 1 and 2 worker threads (the
/// speed-up is the ratio of the two throughputs).
fn monte_carlo(c: &mut Criterion) {
    let mut g = c.benchmark_group("calibration_experiment_300s");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(4));
    let runs = 8;
    g.throughput(Throughput::Elements(runs as u64));
    let config = CalibrationExperimentConfig {
        parameter_sets: 2,
        runs_per_set: runs / 2,
        duration_s: 300.0,
        seed: SEED,
        ..Default::default()
    };
    for t in [1, 2] {
        g.bench_function(format!("threads_{t}"), |b| {
            b.iter(|| calibration_experiment(&config, &motion::land_vehicle, &threads(t)).unwrap())
        });
    }
    g.finish();

    navigation_group(
        c,
        "navigation_experiment_600s_3imus",
        NavigationExperimentConfig {
            runs: 4,
            seed: SEED,
            ..Default::default()
        },
    );
    // The whole-run figure: the raw MEMS IMU alone, as
    // `experiments.navigation(runs=8, imus=["mems"])` (the `nav_run`
    // example times the same set outside criterion).
    navigation_group(
        c,
        "navigation_experiment_600s_mems",
        NavigationExperimentConfig {
            runs: 8,
            seed: SEED,
            imus: paper_imus()
                .into_iter()
                .filter(|(name, _)| name == "mems")
                .collect(),
            ..Default::default()
        },
    );
}

/// One navigation Monte Carlo set of `config` on 1 and on 2 threads
/// (throughput in runs).
fn navigation_group(c: &mut Criterion, name: &str, config: NavigationExperimentConfig) {
    let mut g = c.benchmark_group(name);
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(8));
    g.throughput(Throughput::Elements(config.runs as u64));
    for t in [1, 2] {
        g.bench_function(format!("threads_{t}"), |b| {
            b.iter(|| navigation_experiment(&config, &threads(t)).unwrap())
        });
    }
    g.finish();
}

/// The simulator of the reference workload (600 s at 100 Hz): the random
/// trajectory with its exact IMU truth, the IMU error synthesis and the
/// GNSS simulation (6 satellites), each timed alone.
fn simulator(c: &mut Criterion) {
    let mut g = c.benchmark_group("simulator_600s");
    g.sample_size(20);
    let trajectory =
        || Trajectory::random(&RandomTrajectoryConfig::default(), &mut stream(SEED, 0)).unwrap();
    let truth = trajectory();
    g.throughput(Throughput::Elements(truth.len() as u64));
    g.bench_function("trajectory", |b| b.iter(trajectory));
    let imu = ImuModel::preset("paper-mems", &mut stream(SEED, 1)).unwrap();
    g.bench_function("imu_errors", |b| {
        b.iter(|| {
            imu.measure(
                black_box(&truth.specific_force_b),
                &truth.angular_rate_b,
                &mut stream(SEED, 2),
            )
            .unwrap()
        })
    });
    let sky = Constellation::walker(&WalkerConfig::default()).unwrap();
    let track = ReceiverTrack {
        time_s: &truth.time_s,
        position_ecef: &truth.position_ecef,
        velocity_ecef: &truth.velocity_ecef,
    };
    let gnss_config = SimulationConfig {
        n_satellites: 6,
        ..Default::default()
    };
    g.bench_function("gnss", |b| {
        b.iter(|| {
            gnss::simulate(black_box(&track), &sky, &gnss_config, &mut stream(SEED, 3)).unwrap()
        })
    });
    g.finish();
}

fn config() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3))
}

criterion_group! {
    name = benches;
    config = config();
    targets = calibration_and_inversion, monte_carlo, simulator
}
criterion_main!(benches);
