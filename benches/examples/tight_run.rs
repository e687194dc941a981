//! Runs the reference 600 s tightly coupled filter `REPEATS` times (default
//! 20) for profilers and cycle counters, which are steadier than wall time
//! on a shared machine:
//! `cargo run --release -p memsnav-benches --example tight_run -- 20` under
//! `perf stat -e cycles:u,instructions:u` or `perf record`.

use std::time::Instant;

use memsnav_benches::TightScenario;
use memsnav_core::coupling::run_tightly_coupled;
use memsnav_core::filter::state::BASE_STATES;

fn main() {
    let repeats: usize = std::env::args()
        .nth(1)
        .map(|a| a.parse().expect("REPEATS must be a whole number"))
        .unwrap_or(20);
    let sc = TightScenario::new(600.0, 6);
    let imu = sc.imu();
    let start = Instant::now();
    let mut accepted = 0;
    for _ in 0..repeats {
        let records = run_tightly_coupled::<BASE_STATES, _>(
            &imu,
            &sc.epochs,
            &sc.initial,
            &sc.tuning,
            |_, _| {},
        )
        .expect("the reference run");
        accepted += records.len();
    }
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "{repeats} runs of {} IMU epochs: {:.1} ms per run, {:.0} k epochs/s (wall), {} records",
        sc.imu_epochs(),
        1e3 * seconds / repeats as f64,
        (repeats * sc.imu_epochs()) as f64 / seconds / 1e3,
        accepted / repeats
    );
}
