//! Reader throughput on the whole real logs (`shared/data/real-imu-gnss`):
//! the drive's IMU CSV (2.5 MB, 54 859 lines), its RTKLIB time tag and
//! solution, parsed from memory. `cargo bench -p memsnav-benches --bench readers`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use memsnav_core::logs::{
    parse_imu_csv, parse_pos, parse_time_tag, AccelUnit, GyroUnit, ImuCsvLayout, TimeUnit,
};
use memsnav_core::timing::tag_clock;

/// The project's data root, resolved as the core's integration tests do.
#[path = "../crates/memsnav-core/tests/shared_data/mod.rs"]
mod shared_data;

fn real(name: &str) -> PathBuf {
    shared_data::shared_data(&format!("real-imu-gnss/{name}"))
}

fn readers(c: &mut Criterion) {
    let layout = ImuCsvLayout {
        skip_first_line: true,
        ..ImuCsvLayout::new(
            AccelUnit::StandardGravity,
            GyroUnit::DegreesPerSecond,
            TimeUnit::Milliseconds,
        )
    };
    let csv = std::fs::read(real("drive_0708/imu_1934.csv")).unwrap();
    let tag = std::fs::read(real("drive_0708/imu_1934.csv.tag")).unwrap();
    let pos = std::fs::read_to_string(real("drive_0708/gnss_1934_sf.pos")).unwrap();
    let mut g = c.benchmark_group("readers");
    g.measurement_time(Duration::from_secs(5)).sample_size(20);
    g.throughput(Throughput::Bytes(csv.len() as u64));
    g.bench_function("imu_csv_drive", |b| {
        b.iter(|| parse_imu_csv(black_box(&csv), "imu_1934.csv", &layout).unwrap())
    });
    let log = parse_imu_csv(&csv, "imu_1934.csv", &layout).unwrap();
    g.throughput(Throughput::Bytes(tag.len() as u64));
    g.bench_function("time_tag_and_clock_drive", |b| {
        b.iter(|| {
            let t = parse_time_tag(black_box(&tag), "imu_1934.csv.tag").unwrap();
            tag_clock(&log, &t, None).unwrap()
        })
    });
    g.throughput(Throughput::Bytes(pos.len() as u64));
    g.bench_function("pos_drive", |b| {
        b.iter(|| parse_pos(black_box(&pos), "gnss_1934_sf.pos").unwrap())
    });
    g.finish();
}

criterion_group!(benches, readers);
criterion_main!(benches);
