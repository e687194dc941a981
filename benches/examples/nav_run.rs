//! Runs the paper's navigation Monte Carlo as the Python benchmark does
//! (`experiments.navigation(runs=8, duration=600, seed=2008,
//! imus=["mems"], threads=1)`) `REPEATS` times (default 5) and prints the
//! best and median wall time per Monte Carlo run; also the binary to
//! profile (`perf record -g target/release/examples/nav_run 5`):
//! `cargo run --release -p memsnav-benches --example nav_run -- 5`.
//! A second argument sets the runs per set (default 8).

use std::time::Instant;

use memsnav_benches::SEED;
use memsnav_core::experiments::navigation::paper_imus;
use memsnav_core::experiments::{navigation_experiment, NavigationExperimentConfig};
use memsnav_core::montecarlo::RunOptions;

fn main() {
    let arg = |i: usize, default: usize| -> usize {
        std::env::args()
            .nth(i)
            .map(|a| a.parse().expect("arguments are whole numbers"))
            .unwrap_or(default)
    };
    let (repeats, runs) = (arg(1, 5), arg(2, 8));
    let config = NavigationExperimentConfig {
        runs,
        seed: SEED,
        duration_s: 600.0,
        imus: paper_imus()
            .into_iter()
            .filter(|(name, _)| name == "mems")
            .collect(),
        ..Default::default()
    };
    let options = RunOptions {
        threads: Some(1),
        ..Default::default()
    };
    let mut times = Vec::with_capacity(repeats);
    for _ in 0..repeats {
        let t = Instant::now();
        let result = navigation_experiment(&config, &options).expect("navigation experiment");
        times.push(t.elapsed().as_secs_f64() / runs as f64);
        std::hint::black_box(result);
    }
    times.sort_by(f64::total_cmp);
    println!(
        "navigation run (mems, 600 s, 1 thread): best {:.2} ms, median {:.2} ms per run over {repeats} sets of {runs}",
        times[0] * 1e3,
        times[times.len() / 2] * 1e3
    );
}
