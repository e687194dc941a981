//! Navigation benchmarks: strapdown step, 17-state propagation, GNSS
//! updates (6 and 12 satellites, pseudorange + rate), the whole 600 s
//! tightly coupled run, forward and with the fixed-interval smoother. `cargo bench -p memsnav-benches --bench filter`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use memsnav_benches::TightScenario;
use memsnav_core::coupling;
use memsnav_core::filter::state::{
    Layout, RangeBiasSlots, BASE_STATES, CLOCK_DRIFT, CLOCK_OFFSET, POSITION, VELOCITY,
};
use memsnav_core::filter::{ErrorStateKf, ProcessNoise, SparseRow, SystemInputs};
use memsnav_core::gnss;
use memsnav_core::ins::{self, ImuSample};
use nalgebra::SMatrix;

fn strapdown_and_propagation(c: &mut Criterion) {
    let sc = TightScenario::new(10.0, 6);
    let imu = sc.imu();
    let (s0, s1) = (
        ImuSample {
            specific_force_b: imu.specific_force_b[100],
            angular_rate_b: imu.angular_rate_b[100],
        },
        ImuSample {
            specific_force_b: imu.specific_force_b[101],
            angular_rate_b: imu.angular_rate_b[101],
        },
    );
    let nav = sc.truth.nav_state(100);
    let mut g = c.benchmark_group("epoch");
    g.throughput(Throughput::Elements(1));
    g.bench_function("strapdown_step", |b| {
        b.iter(|| ins::step(black_box(&nav), black_box(&s0), black_box(&s1), 0.01))
    });
    let inputs = SystemInputs {
        c_b_e: nav.c_b_e,
        specific_force_b: s1.specific_force_b,
        angular_rate_b: s1.angular_rate_b,
        position_ecef: nav.position_ecef,
    };
    let noise: ProcessNoise = sc.tuning.process_noise;
    let p0 = covariance_after_updates(&sc);
    g.bench_function("propagate_17_states", |b| {
        let mut kf = ErrorStateKf::<BASE_STATES>::new(p0).unwrap();
        let mut k = 0usize;
        b.iter(|| {
            // Restart from P₀ now and then so P stays in a realistic range.
            k += 1;
            if k.is_multiple_of(512) {
                kf.p = p0;
            }
            kf.propagate(black_box(&inputs), &noise, 0.01, 1.0).unwrap()
        })
    });
    // The multi-system state (base + inter-system biases): one state per
    // system beyond GPS's clock, what a GNSS-combining run pays per sample.
    const WITH_ISB: usize = Layout::size(false, false, true, RangeBiasSlots::None);
    let mut p_isb = SMatrix::<f64, WITH_ISB, WITH_ISB>::identity();
    p_isb
        .fixed_view_mut::<BASE_STATES, BASE_STATES>(0, 0)
        .copy_from(&p0);
    g.bench_function("propagate_inter_system_bias_states", |b| {
        let mut kf = ErrorStateKf::<WITH_ISB>::new(p_isb).unwrap();
        let mut k = 0usize;
        b.iter(|| {
            k += 1;
            if k.is_multiple_of(512) {
                kf.p = p_isb;
            }
            kf.propagate(black_box(&inputs), &noise, 0.01, 1.0).unwrap()
        })
    });
    g.finish();
}

/// P after the first 10 s of the scenario's filter (realistic correlations).
fn covariance_after_updates(sc: &TightScenario) -> SMatrix<f64, BASE_STATES, BASE_STATES> {
    let mut p = SMatrix::zeros();
    coupling::run::<BASE_STATES, _, _>(&sc.imu(), &sc.epochs, &sc.initial, &sc.tuning, |_, s| {
        p = s.kf.p
    })
    .unwrap();
    p
}

/// One epoch's updates as the tight filter applies them: a pseudorange row
/// (position, clock) per satellite, then a rate row (velocity, drift),
/// each through `gnss::predicted_range` and a gated scalar Joseph update.
fn gnss_updates(c: &mut Criterion) {
    let mut g = c.benchmark_group("gnss_update");
    for n_sat in [6usize, 12] {
        let sc = TightScenario::new(10.0, n_sat);
        let p0 = covariance_after_updates(&sc);
        let epoch = &sc.epochs[5];
        assert_eq!(epoch.measurements.len(), n_sat);
        let nav = sc.truth.nav_state(500);
        g.throughput(Throughput::Elements(1));
        g.bench_function(format!("{n_sat}_satellites_range_and_rate"), |b| {
            b.iter_batched_ref(
                || ErrorStateKf::<BASE_STATES>::new(p0).unwrap(),
                |kf| {
                    for m in &epoch.measurements {
                        let p = gnss::predicted_range(
                            &m.position_ecef,
                            &m.velocity_ecef,
                            &nav.position_ecef,
                            &nav.velocity_ecef,
                        );
                        let u = p.line_of_sight_ecef;
                        let h = SparseRow::new(&[
                            (POSITION, -u.x),
                            (POSITION + 1, -u.y),
                            (POSITION + 2, -u.z),
                            (CLOCK_OFFSET, 1.0),
                        ]);
                        kf.update_scalar(&h, p.range_m - m.pseudorange_m, 9.0, f64::INFINITY);
                    }
                    for m in &epoch.measurements {
                        let p = gnss::predicted_range(
                            &m.position_ecef,
                            &m.velocity_ecef,
                            &nav.position_ecef,
                            &nav.velocity_ecef,
                        );
                        let u = p.line_of_sight_ecef;
                        let h = SparseRow::new(&[
                            (VELOCITY, -u.x),
                            (VELOCITY + 1, -u.y),
                            (VELOCITY + 2, -u.z),
                            (CLOCK_DRIFT, 1.0),
                        ]);
                        kf.update_scalar(
                            &h,
                            p.range_rate_m_s - m.pseudorange_rate_m_s,
                            0.01,
                            f64::INFINITY,
                        );
                    }
                },
                BatchSize::SmallInput,
            )
        });
    }
    g.finish();
}

/// The reference run: 600 s, 100 Hz IMU, 1 Hz GNSS, 6 satellites.
/// Throughput in IMU epochs. `records_only`: the filter with an empty
/// observer; `solution`: with the whole per-epoch solution stored (what the
/// Python `TightlyCoupledFilter.run` returns).
fn tight_run(c: &mut Criterion) {
    let sc = TightScenario::new(600.0, 6);
    let mut g = c.benchmark_group("tight_600s_6sat");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(4));
    g.throughput(Throughput::Elements(sc.imu_epochs() as u64));
    g.bench_function("records_only", |b| b.iter(|| sc.run_records_only()));
    g.bench_function("solution", |b| b.iter(|| sc.run_solution()));
    // Forward (recording for the smoother) and backward pass: the target asks
    // that the smoother add at most twice the forward `solution` time.
    g.bench_function("solution_and_smoothed", |b| b.iter(|| sc.run_smoothed()));
    g.finish();
}

fn config() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(20)
}

criterion_group! {
    name = benches;
    config = config();
    targets = strapdown_and_propagation, gnss_updates, tight_run
}
criterion_main!(benches);
