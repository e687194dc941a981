//! Runs the reference 600 s tightly coupled filter `REPEATS` times (default
//! 20) for profilers (`perf record`), and prints the best and median wall
//! time per run, with an empty observer (`records`), with the whole
//! solution stored (`solution`, what the Python API returns) and with the
//! smoothed solution too (`smoothed`, `smooth=True`):
//! `cargo run --release -p memsnav-benches --example tight_run -- 20`.

use std::time::Instant;

use memsnav_benches::TightScenario;
use memsnav_core::coupling::{run_tightly_coupled, tightly_coupled, tightly_coupled_smoothed};
use memsnav_core::filter::state::BASE_STATES;

fn main() {
    let repeats: usize = std::env::args()
        .nth(1)
        .map(|a| a.parse().expect("REPEATS must be a whole number"))
        .unwrap_or(20);
    let sc = TightScenario::new(600.0, 6);
    let imu = sc.imu();
    let mut records = Vec::with_capacity(repeats);
    let mut solution = Vec::with_capacity(repeats);
    let mut smoothed = Vec::with_capacity(repeats);
    for _ in 0..repeats {
        let t = Instant::now();
        run_tightly_coupled::<BASE_STATES, _>(&imu, &sc.epochs, &sc.initial, &sc.tuning, |_, _| {})
            .expect("the reference run");
        records.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        tightly_coupled::<BASE_STATES>(&imu, &sc.epochs, &sc.initial, &sc.tuning)
            .expect("the reference run");
        solution.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        tightly_coupled_smoothed::<BASE_STATES>(&imu, &sc.epochs, &sc.initial, &sc.tuning)
            .expect("the reference run");
        smoothed.push(t.elapsed().as_secs_f64());
    }
    let n = sc.imu_epochs() as f64;
    for (name, mut times) in [
        ("records", records),
        ("solution", solution),
        ("smoothed", smoothed),
    ] {
        times.sort_by(f64::total_cmp);
        let (best, median) = (times[0], times[times.len() / 2]);
        println!(
            "{name:>8}: best {:.1} ms ({:.0} k epochs/s), median {:.1} ms ({:.0} k epochs/s) over {repeats} runs of {n} IMU epochs",
            best * 1e3,
            n / best / 1e3,
            median * 1e3,
            n / median / 1e3,
        );
    }
}
