//! The fixed-interval smoother of the coupled filters on simulated drives
//! whose IMU errors the 17-state filter models exactly: inside a GNSS
//! outage the smoothed position is better than the forward one everywhere,
//! its covariance never exceeds the forward one, and its errors agree with
//! it (NEES in the chi-square band over seeded runs).

use memsnav_core::attitude::dcm_to_rotation_vector;
use memsnav_core::coupling::{self, *};
use memsnav_core::filter::chi_square::mean_per_dof_band;
use memsnav_core::filter::nees;
use memsnav_core::filter::state::{BASE_STATES, WITH_ALL, WITH_RANGE_BIASES, WITH_SCALE_FACTORS};
use memsnav_core::gnss::{GnssEpoch, Outage, SimulationConfig};
use memsnav_core::random::stream;
use memsnav_core::sensors::ImuModel;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

mod common;
use common::*;

const OUTAGE: (f64, f64) = (60.0, 30.0);

struct Pair {
    truth: Truth,
    forward: Solution,
    smoothed: Solution,
}

fn run(seed: u64, loose: bool) -> Pair {
    run_with::<BASE_STATES>(seed, loose)
}

/// A drive with an outage, its IMU data, GNSS epochs and loose fixes.
struct Scenario {
    truth: Truth,
    data_f: Vec<Vector3<f64>>,
    data_w: Vec<Vector3<f64>>,
    epochs: Vec<GnssEpoch>,
    fixes: Vec<PositionFix>,
    initial: InitialState,
    tuning: FilterTuning,
}

fn scenario<const N: usize>(seed: u64) -> Scenario {
    let truth = drive(150.0, 100.0, true);
    let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
    let scale_factor_states = N == WITH_SCALE_FACTORS || N == WITH_ALL;
    let mut tuning = FilterTuning::from_imu_spec(&spec, 100.0, scale_factor_states).unwrap();
    tuning.initial_std.attitude_ned_rad = Vector3::new(0.2, 0.2, 0.5).map(f64::to_radians);
    let mut rng = stream(seed, 0);
    let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
    let config = SimulationConfig {
        outages: vec![Outage {
            start_s: OUTAGE.0,
            duration_s: OUTAGE.1,
            n_satellites: 0,
        }],
        ..Default::default()
    };
    let epochs = gnss_for(&truth, &config, &mut rng);
    let (data_f, data_w) = readings(&truth, &imu, &mut rng);
    let initial = exact_initial(&truth);
    let fixes: Vec<PositionFix> = epochs
        .iter()
        .filter(|e| !e.measurements.is_empty())
        .map(|e| {
            let k = (e.time_s * 100.0).round() as usize;
            PositionFix {
                time_s: e.time_s,
                position_ecef: truth.nav[k].position_ecef + n3(&mut rng) * 2.0,
                position_covariance: Matrix3::identity() * 4.0,
                velocity_ecef: None,
                velocity_covariance: Matrix3::zeros(),
                velocity_horizontal_only: false,
            }
        })
        .collect();
    Scenario {
        truth,
        data_f,
        data_w,
        epochs,
        fixes,
        initial,
        tuning,
    }
}

/// [`run`] with `N` error states.
fn run_with<const N: usize>(seed: u64, loose: bool) -> Pair {
    let sc = scenario::<N>(seed);
    let data = imu_data(&sc.truth, &sc.data_f, &sc.data_w);
    let (forward, smoothed) = if loose {
        coupling::smoothed_solution::<N, _>(&data, &sc.fixes, &sc.initial, &sc.tuning).unwrap()
    } else {
        coupling::smoothed_solution::<N, _>(&data, &sc.epochs, &sc.initial, &sc.tuning).unwrap()
    };
    Pair {
        truth: sc.truth,
        forward,
        smoothed,
    }
}

/// The Monte Carlo's smoothing, which carries the error estimates alone,
/// gives the positions of the whole smoothed solution bit for bit, and
/// the forward run's records: tight (with range-bias slots set anew, resets
/// the smoother goes back through) and loose.
#[test]
fn smoothed_positions_alone_equal_the_smoothed_solution() {
    fn check<const N: usize>() {
        let sc = scenario::<N>(11);
        let data = imu_data(&sc.truth, &sc.data_f, &sc.data_w);
        let ignore = |_, _: &FilterState<N>| {};
        let (forward, smoothed) =
            coupling::smoothed_solution::<N, _>(&data, &sc.epochs, &sc.initial, &sc.tuning)
                .unwrap();
        let (records, positions) =
            coupling::run_smoothed::<N, _, _>(&data, &sc.epochs, &sc.initial, &sc.tuning, ignore)
                .unwrap();
        assert_eq!(positions, smoothed.position_ecef);
        assert_eq!(records.measurements, forward.measurements);
        let (_, smoothed) =
            coupling::smoothed_solution::<N, _>(&data, &sc.fixes, &sc.initial, &sc.tuning).unwrap();
        let (_, positions) =
            coupling::run_smoothed::<N, _, _>(&data, &sc.fixes, &sc.initial, &sc.tuning, ignore)
                .unwrap();
        assert_eq!(positions, smoothed.position_ecef);
    }
    check::<BASE_STATES>();
    check::<WITH_ALL>();
}

fn position_error(s: &Solution, truth: &Truth, k: usize) -> f64 {
    (s.position_ecef[k] - truth.nav[k].position_ecef).norm()
}

/// Inside the outage the smoothed position error is below the forward one
/// at every sample, in mean square over seeded runs (one run's errors at
/// the outage's first instants are both the last fix's, and either may be
/// the smaller; the forward drift grows to metres, smoothing bends it onto
/// the fix after the outage); and no smoothed variance exceeds its forward
/// one anywhere, in any run.
#[test]
fn smoothing_beats_the_forward_filter_in_an_outage() {
    let inside = (OUTAGE.0 * 100.0) as usize + 1..((OUTAGE.0 + OUTAGE.1) * 100.0) as usize;
    for loose in [false, true] {
        let runs = 6;
        let mut mse = vec![(0.0, 0.0); inside.len()];
        for seed in 0..runs {
            let p = run(31 + seed, loose);
            for (m, k) in mse.iter_mut().zip(inside.clone()) {
                m.0 += position_error(&p.forward, &p.truth, k).powi(2) / runs as f64;
                m.1 += position_error(&p.smoothed, &p.truth, k).powi(2) / runs as f64;
            }
            let n = p.forward.n_states;
            for (f, s) in p
                .forward
                .covariance_diagonal
                .chunks(n)
                .zip(p.smoothed.covariance_diagonal.chunks(n))
            {
                for i in 0..n {
                    assert!(
                        s[i] <= f[i] * (1.0 + 1e-9) + 1e-15,
                        "state {i}: {} > {}",
                        s[i],
                        f[i]
                    );
                }
            }
            assert_eq!(p.smoothed.measurements, p.forward.measurements);
        }
        for (i, (f, s)) in mse.iter().enumerate() {
            let t = (inside.start + i) as f64 / 100.0;
            assert!(
                s < f,
                "loose {loose}, t = {t} s: smoothed RMS {} ≥ forward {}",
                s.sqrt(),
                f.sqrt()
            );
        }
        let mid = mse[mse.len() / 2];
        println!(
            "loose {loose}: mid-outage RMS forward {:.2} m, smoothed {:.2} m",
            mid.0.sqrt(),
            mid.1.sqrt()
        );
    }
}

/// The larger layouts, whose range-bias slots are set anew when a
/// satellite is given one (resets the smoother goes back through) and whose
/// scale-factor states are weakly observable: every smoothed variance stays
/// positive and at most the forward one at every sample, and the smoothed
/// position mid-outage is the better one.
#[test]
fn larger_layouts_smooth_consistently() {
    fn check<const N: usize>() {
        let p = run_with::<N>(7, false);
        assert_eq!(p.forward.n_states, N);
        for (k, (f, s)) in p
            .forward
            .covariance_diagonal
            .chunks(N)
            .zip(p.smoothed.covariance_diagonal.chunks(N))
            .enumerate()
        {
            for i in 0..N {
                assert!(
                    s[i] > 0.0 && s[i] <= f[i] * (1.0 + 1e-9) + 1e-15,
                    "{N} states, sample {k}, state {i}: smoothed {} forward {}",
                    s[i],
                    f[i]
                );
            }
        }
        let mid = ((OUTAGE.0 + 0.5 * OUTAGE.1) * 100.0) as usize;
        let (forward, smoothed) = (
            position_error(&p.forward, &p.truth, mid),
            position_error(&p.smoothed, &p.truth, mid),
        );
        assert!(smoothed < forward, "{N} states: {smoothed} ≥ {forward} m");
    }
    check::<WITH_SCALE_FACTORS>();
    check::<WITH_RANGE_BIASES>();
    check::<WITH_ALL>();
}

/// NEES of the smoothed attitude, velocity and position over 8 seeded runs,
/// sampled at 1 Hz, in the chi-square band: the smoothed covariance is the
/// error's.
#[test]
fn smoothed_errors_agree_with_their_covariance() {
    let runs = 8;
    let mut sum = 0.0;
    let mut count = 0;
    for seed in 0..runs {
        let p = run(100 + seed, false);
        for k in (0..p.truth.time_s.len()).step_by(100) {
            let s = &p.smoothed;
            let t = &p.truth.nav[k];
            let mut e = SVector::<f64, 9>::zeros();
            e.fixed_rows_mut::<3>(0)
                .copy_from(&dcm_to_rotation_vector(&(s.c_b_e[k] * t.c_b_e.transpose())));
            e.fixed_rows_mut::<3>(3)
                .copy_from(&(s.velocity_ecef[k] - t.velocity_ecef));
            e.fixed_rows_mut::<3>(6)
                .copy_from(&(s.position_ecef[k] - t.position_ecef));
            // The 9×9 navigation block: attitude, velocity, position
            // (cross blocks from the diagonal-block form are not kept, so
            // take the three blocks as independent: a conservative NEES).
            let mut cov = SMatrix::<f64, 9, 9>::zeros();
            cov.fixed_view_mut::<3, 3>(0, 0)
                .copy_from(&s.attitude_covariance_ecef(k));
            cov.fixed_view_mut::<3, 3>(3, 3)
                .copy_from(&s.velocity_covariance_ecef(k));
            cov.fixed_view_mut::<3, 3>(6, 6)
                .copy_from(&s.position_covariance_ecef(k));
            sum += nees(&e, &cov).unwrap() / 9.0;
            count += 1;
        }
    }
    let mean = sum / count as f64;
    // Samples 1 s apart are strongly correlated: the band of one run's
    // sample stands for the average (conservative), widened as in the
    // forward filter's consistency test.
    let (lo, hi) = mean_per_dof_band(9.0, runs as usize, 0.95);
    println!("smoothed NEES/dof {mean:.3}, band [{lo:.3}, {hi:.3}]");
    assert!(mean > 0.5 * lo && mean < hi, "{mean}");
}
