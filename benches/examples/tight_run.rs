//! Runs the reference 600 s tightly coupled filter `REPEATS` times (default
//! 20) for profilers (`perf record`), and prints the best and median wall
//! time per run, with an empty observer (`records`), with the whole
//! solution stored (`solution`, what the Python API returns) and with the
//! smoothed solution too (`smoothed`, `smooth=True`):
//! `cargo run --release -p memsnav-benches --example tight_run -- 20`.
//! A second argument runs one series only (to profile it):
//! `target/release/examples/tight_run 20 smoothed`.

use std::time::Instant;

use memsnav_benches::TightScenario;

const SERIES: [&str; 3] = ["records", "solution", "smoothed"];

fn main() {
    let repeats: usize = std::env::args()
        .nth(1)
        .map(|a| a.parse().expect("REPEATS must be a whole number"))
        .unwrap_or(20);
    let only = std::env::args().nth(2);
    if let Some(name) = &only {
        assert!(
            SERIES.contains(&name.as_str()),
            "the series is one of {SERIES:?}"
        );
    }
    let sc = TightScenario::new(600.0, 6);
    let run = |name: &str| match name {
        "records" => sc.run_records_only(),
        "solution" => drop(sc.run_solution()),
        _ => drop(sc.run_smoothed()),
    };
    let names: Vec<&str> = SERIES
        .into_iter()
        .filter(|n| only.as_deref().is_none_or(|o| o == *n))
        .collect();
    let mut times = vec![Vec::with_capacity(repeats); names.len()];
    for _ in 0..repeats {
        for (name, series) in names.iter().zip(&mut times) {
            let t = Instant::now();
            run(name);
            series.push(t.elapsed().as_secs_f64());
        }
    }
    let n = sc.imu_epochs() as f64;
    for (name, mut times) in names.into_iter().zip(times) {
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
