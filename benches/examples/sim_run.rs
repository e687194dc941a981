//! Times the simulator of the reference workload, part by part: the random
//! 600 s trajectory with its exact IMU truth, the IMU error synthesis and
//! the GNSS simulation (6 satellites), `REPEATS` times (default 20), best
//! and median per part; also the binary to profile
//! (`valgrind --tool=callgrind target/release/examples/sim_run 1`):
//! `cargo run --release -p memsnav-benches --example sim_run -- 20`.

use std::hint::black_box;
use std::time::Instant;

use memsnav_benches::SEED;
use memsnav_core::gnss::{self, Constellation, ReceiverTrack, SimulationConfig, WalkerConfig};
use memsnav_core::random::stream;
use memsnav_core::sensors::ImuModel;
use memsnav_core::trajectory::{RandomTrajectoryConfig, Trajectory};

fn main() {
    let repeats: usize = std::env::args()
        .nth(1)
        .map(|a| a.parse().expect("REPEATS must be a whole number"))
        .unwrap_or(20);
    let sky = Constellation::walker(&WalkerConfig::default()).expect("walker constellation");
    let mut parts: [Vec<f64>; 4] = Default::default();
    for _ in 0..repeats {
        let mut rng = stream(SEED, 0);
        let t = Instant::now();
        let truth = Trajectory::random(&RandomTrajectoryConfig::default(), &mut rng)
            .expect("random trajectory");
        parts[0].push(t.elapsed().as_secs_f64());
        let imu = ImuModel::preset("paper-mems", &mut rng).expect("preset");
        let t = Instant::now();
        let readings = imu
            .measure(&truth.specific_force_b, &truth.angular_rate_b, &mut rng)
            .expect("IMU readings");
        parts[1].push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let epochs = gnss::simulate(
            &ReceiverTrack {
                time_s: &truth.time_s,
                position_ecef: &truth.position_ecef,
                velocity_ecef: &truth.velocity_ecef,
            },
            &sky,
            &SimulationConfig {
                n_satellites: 6,
                ..Default::default()
            },
            &mut rng,
        )
        .expect("GNSS simulation");
        parts[2].push(t.elapsed().as_secs_f64());
        parts[3]
            .push(parts[0].last().unwrap() + parts[1].last().unwrap() + parts[2].last().unwrap());
        black_box((readings, epochs));
    }
    for (name, mut times) in ["trajectory", "imu", "gnss", "total"]
        .into_iter()
        .zip(parts)
    {
        times.sort_by(f64::total_cmp);
        println!(
            "{name:>10}: best {:.2} ms, median {:.2} ms over {repeats} runs",
            times[0] * 1e3,
            times[times.len() / 2] * 1e3
        );
    }
}
