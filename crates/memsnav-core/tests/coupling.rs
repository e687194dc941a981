//! Coupled GNSS/INS filters: consistency (NEES, NIS) over seeded Monte
//! Carlo runs whose IMU errors the filter models exactly, outlier gating,
//! tight coupling with three satellites (bounded; its covariance covering
//! the open direction), outage drift against ½ b t²,
//! a two-hour positive-definiteness run, and bad input.
//!
//! Truth here is the INS itself fed error-free samples (the ins tests show
//! that this reproduces a trajectory), so every error the filters see comes
//! from the IMU and GNSS errors the tests inject.

use memsnav_core::attitude::dcm_to_rotation_vector;
use memsnav_core::coupling::{self, *};
use memsnav_core::filter::chi_square::mean_per_dof_band;
use memsnav_core::filter::nees;
use memsnav_core::gnss::{self, GnssEpoch, Outage, SimulationConfig};
use memsnav_core::ins::ImuData;
use memsnav_core::random::{stream, Rng};
use memsnav_core::sensors::ImuModel;
use memsnav_core::Error;
use nalgebra::{SMatrix, Vector3};

mod common;
use common::*;

struct Run {
    nees_1hz: Vec<f64>,
    records: Vec<MeasurementRecord>,
}

fn run_tight(
    truth: &Truth,
    epochs: &[GnssEpoch],
    imu: &ImuModel,
    tuning: &FilterTuning,
    initial: &InitialState,
    rng: &mut Rng,
) -> Run {
    let readings = imu.measure(&truth.f_b, &truth.w_b, rng).unwrap();
    let data = imu_data(truth, &readings.specific_force_b, &readings.angular_rate_b);
    let mut nees_1hz = Vec::new();
    let mut position_error = Vec::with_capacity(truth.time_s.len());
    let rate = imu.sample_rate_hz.round() as usize;
    let records = coupling::run::<17, _, _>(&data, epochs, initial, tuning, |k, s| {
        let e = nav_error(&s.nav, &truth.nav[k]);
        position_error.push(e.fixed_rows::<3>(6).norm());
        if k % rate == 0 {
            let p: SMatrix<f64, 9, 9> = s.kf.p.fixed_view::<9, 9>(0, 0).into_owned();
            nees_1hz.push(nees(&e, &p).unwrap());
        }
    })
    .unwrap();
    let _ = position_error;
    Run {
        nees_1hz,
        records: records.measurements,
    }
}

/// Mean NEES/dof over 10 seeded runs of 120 s within its chi-square 95 %
/// band, and the mean pseudorange NIS near 1.
#[test]
fn consistent_when_the_imu_errors_are_modelled_exactly() {
    let truth = drive(120.0, 100.0, true);
    let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
    let mut tuning = FilterTuning::from_imu_spec(&spec, 100.0, false).unwrap();
    tuning.initial_std.attitude_ned_rad = Vector3::new(0.2, 0.2, 0.5).map(f64::to_radians);
    let runs = 10;
    let mut nees_sum = vec![0.0; 121];
    let (mut nis_sum, mut nis_n) = (0.0, 0);
    for i in 0..runs {
        let mut rng = stream(11, i);
        let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
        let epochs = gnss_for(&truth, &SimulationConfig::default(), &mut rng);
        let init = perturbed_initial(&truth, &tuning.initial_std, &mut rng);
        let run = run_tight(&truth, &epochs, &imu, &tuning, &init, &mut rng);
        for (s, v) in nees_sum.iter_mut().zip(&run.nees_1hz) {
            *s += v / 9.0;
        }
        for r in run
            .records
            .iter()
            .filter(|r| r.status == MeasurementStatus::Accepted)
        {
            nis_sum += r.nis;
            nis_n += 1;
        }
    }
    // Per epoch the run average of NEES/dof is χ²(9·runs)/(9·runs); the time
    // average of correlated epochs varies no more than one epoch's.
    let (lo, hi) = mean_per_dof_band(9.0, runs as usize, 0.95);
    let mean = nees_sum.iter().sum::<f64>() / (nees_sum.len() as f64 * runs as f64);
    println!("mean NEES/dof = {mean:.3}, band [{lo:.3}, {hi:.3}]");
    assert!(
        mean > lo && mean < hi,
        "mean NEES/dof {mean} outside [{lo}, {hi}]"
    );
    let inside = nees_sum.iter().filter(|v| {
        let m = **v / runs as f64;
        m > lo && m < hi
    });
    assert!(inside.count() as f64 > 0.8 * nees_sum.len() as f64);
    let nis = nis_sum / nis_n as f64;
    let (lo, hi) = mean_per_dof_band(1.0, nis_n / 10, 0.95);
    println!("mean NIS = {nis:.3} over {nis_n}, band [{lo:.3}, {hi:.3}]");
    assert!(nis > lo && nis < hi, "mean NIS {nis}");
}

/// A 100 m error on one pseudorange is excluded from its epoch (the other
/// satellites of that epoch are applied) and reported; NaN and absurd
/// (1e9 m) pseudoranges are rejected and reported too.
#[test]
fn outliers_are_rejected_and_counted() {
    let truth = drive(60.0, 100.0, true);
    let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
    let tuning = FilterTuning::from_imu_spec(&spec, 100.0, false).unwrap();
    let mut rng = stream(3, 0);
    let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
    let mut epochs = gnss_for(&truth, &SimulationConfig::default(), &mut rng);
    let (f, w) = readings(&truth, &imu, &mut rng);
    let data = imu_data(&truth, &f, &w);
    let clean =
        coupling::solution::<17, _>(&data, &epochs, &exact_initial(&truth), &tuning).unwrap();
    let clean_rejections = clean.rejected().count();
    let hit = epochs[30].measurements[2].sat_id;
    epochs[30].measurements[2].pseudorange_m += 100.0;
    epochs[40].measurements[0].pseudorange_m = f64::NAN;
    epochs[45].measurements[1].pseudorange_m = 1e9;
    let sol = coupling::solution::<17, _>(&data, &epochs, &exact_initial(&truth), &tuning).unwrap();
    let find = |t: f64, kind| {
        sol.measurements.iter().find(|r| {
            r.time_s == t
                && r.kind == kind
                && r.status != MeasurementStatus::Accepted
                && (t != 30.0 || r.id == hit)
        })
    };
    let r = find(30.0, MeasurementKind::Pseudorange).expect("the 100 m outlier is rejected");
    assert_eq!(r.status, MeasurementStatus::Excluded);
    assert!((r.innovation - 100.0).abs() < 15.0, "{r:?}");
    let others_at_30 = sol
        .measurements
        .iter()
        .filter(|m| m.time_s == 30.0 && m.kind == MeasurementKind::Pseudorange && m.id != hit);
    assert!(others_at_30
        .clone()
        .all(|m| m.status == MeasurementStatus::Accepted));
    assert_eq!(others_at_30.count(), epochs[30].measurements.len() - 1);
    assert_eq!(
        find(40.0, MeasurementKind::Pseudorange).unwrap().status,
        MeasurementStatus::RejectedInvalid
    );
    assert_eq!(
        find(45.0, MeasurementKind::Pseudorange).unwrap().status,
        MeasurementStatus::Excluded
    );
    assert_eq!(sol.rejected().count(), clean_rejections + 3);
    // The solution is unharmed: same error as without the outliers.
    let err = |s: &Solution| (s.position_ecef[6000] - truth.nav[6000].position_ecef).norm();
    assert!(
        (err(&sol) - err(&clean)).abs() < 0.5,
        "{} vs {}",
        err(&sol),
        err(&clean)
    );
    // Without the gate the 1e9 m pseudorange is applied and wrecks the fix.
    let mut open = tuning;
    open.gate_probability = 1.0;
    let ungated = coupling::solution::<17, _>(&data, &epochs, &exact_initial(&truth), &open);
    assert!(ungated.map(|s| err(&s) > 100.0).unwrap_or(true));
}

/// A drive, its GNSS, the IMU readings (force, rate) and the tuning.
type ThreeSatellites = (
    Truth,
    Vec<GnssEpoch>,
    (Vec<Vector3<f64>>, Vec<Vector3<f64>>),
    FilterTuning,
);

/// A drive of `duration_s` whose receiver keeps 3 of its 6 satellites from
/// `from_s` on, an IMU drawn from `spec` (seeded), its readings, and the
/// tuning from the same spec (the IMU errors modelled exactly).
fn three_satellites(
    duration_s: f64,
    from_s: f64,
    spec: &memsnav_core::sensors::ImuSpec,
    seed: u64,
) -> ThreeSatellites {
    let truth = drive(duration_s, 100.0, true);
    let tuning = FilterTuning::from_imu_spec(spec, 100.0, false).unwrap();
    let mut rng = stream(seed, 0);
    let imu = ImuModel::from_spec(spec, 100.0, &mut rng).unwrap();
    let config = SimulationConfig {
        outages: vec![Outage {
            start_s: from_s,
            duration_s: 1e6,
            n_satellites: 3,
        }],
        ..Default::default()
    };
    let epochs = gnss_for(&truth, &config, &mut rng);
    assert_eq!(epochs[100].measurements.len(), 3);
    let readings = readings(&truth, &imu, &mut rng);
    (truth, epochs, readings, tuning)
}

/// With three satellites (after 30 s of six), tight coupling stays bounded
/// where the loosely coupled filter gets no fix and coasts on a MEMS IMU.
#[test]
fn tight_coupling_survives_three_satellites() {
    let spec = bias_and_noise_spec(
        0.05,
        1e-3_f64.to_radians() * 10.0,
        2e-3,
        1e-3_f64.to_radians(),
    );
    let (truth, epochs, (f, w), tuning) = three_satellites(240.0, 30.0, &spec, 5);
    let data = imu_data(&truth, &f, &w);
    let init = exact_initial(&truth);
    let tight = coupling::solution::<17, _>(&data, &epochs, &init, &tuning).unwrap();
    let fixes: Vec<PositionFix> = epochs
        .iter()
        .filter_map(|e| gnss::solve_fix(e, None).ok().map(|fx| (e.time_s, fx)))
        .map(|(t, fx)| PositionFix {
            time_s: t,
            position_ecef: fx.position_ecef,
            position_covariance: fx
                .position_clock_covariance
                .fixed_view::<3, 3>(0, 0)
                .into_owned(),
            velocity_ecef: Some(fx.velocity_ecef),
            velocity_covariance: fx
                .velocity_drift_covariance
                .fixed_view::<3, 3>(0, 0)
                .into_owned(),
            velocity_horizontal_only: false,
        })
        .collect();
    assert_eq!(
        fixes.len(),
        30,
        "fixes only while six satellites are tracked"
    );
    let loose = coupling::solution::<17, _>(&data, &fixes, &init, &tuning).unwrap();
    let last = truth.time_s.len() - 1;
    let e_tight = (tight.position_ecef[last] - truth.nav[last].position_ecef).norm();
    let e_loose = (loose.position_ecef[last] - truth.nav[last].position_ecef).norm();
    let worst_tight = (0..=last)
        .map(|k| (tight.position_ecef[k] - truth.nav[k].position_ecef).norm())
        .fold(0.0, f64::max);
    println!("3 satellites: tight final {e_tight:.1} m (worst {worst_tight:.1}), loose final {e_loose:.1} m");
    assert!(worst_tight < 60.0, "{worst_tight}");
    assert!(e_loose > 10.0 * e_tight);
}

/// Three satellites for 15 minutes from the start, an IMU modelled exactly:
/// the pseudoranges and rates leave one direction of position and clock
/// open, and the covariance must grow along it as the error does
/// (without the rate row's line-of-sight term the model found information
/// about that direction as the satellites moved, and only 39 % of the
/// position NEES stayed under its 99.7 % quantile while the error reached
/// 3.7 km).
#[test]
fn three_satellites_leave_an_open_direction_that_the_covariance_covers() {
    let spec = bias_and_noise_spec(0.01, 1e-3_f64.to_radians(), 2e-3, 1e-3_f64.to_radians());
    let (truth, epochs, (f, w), tuning) = three_satellites(900.0, 0.5, &spec, 23);
    let data = imu_data(&truth, &f, &w);
    let sol = coupling::solution::<17, _>(&data, &epochs, &exact_initial(&truth), &tuning).unwrap();
    let quantile = memsnav_core::filter::chi_square::chi_square_quantile(3.0, 0.997);
    let (mut inside, mut total, mut worst) = (0usize, 0usize, 0.0f64);
    for k in (0..truth.time_s.len()).step_by(100) {
        let e = sol.position_ecef[k] - truth.nav[k].position_ecef;
        let n = nees(&e, &sol.position_covariance_ecef(k)).unwrap();
        inside += usize::from(n <= quantile);
        total += 1;
        worst = worst.max(e.norm());
    }
    let share = inside as f64 / total as f64;
    println!(
        "3 satellites, 900 s: worst error {worst:.0} m, position NEES within 99.7 %: {share:.3}"
    );
    assert!(share > 0.95, "{share}");
    assert!(!sol.integrity.diverged(), "{:?}", sol.integrity.alerts);
}

/// A step in the accelerometer bias at the start of a 30 s total outage,
/// unknown to the filter, drifts the position by ½ Δb t² (noise-free IMU).
#[test]
fn outage_drift_follows_half_b_t_squared() {
    let truth = drive(150.0, 100.0, true);
    let spec = bias_and_noise_spec(1e-3, 1e-6, 1e-5, 1e-7);
    let tuning = FilterTuning::from_imu_spec(&spec, 100.0, false).unwrap();
    let mut rng = stream(9, 0);
    let config = SimulationConfig {
        pseudorange_std_m: 0.3,
        pseudorange_rate_std_m_s: 0.01,
        outages: vec![Outage {
            start_s: 120.0,
            duration_s: 30.0,
            n_satellites: 0,
        }],
        ..Default::default()
    };
    let epochs = gnss_for(&truth, &config, &mut rng);
    let step = Vector3::new(0.05, 0.0, 0.0);
    let f: Vec<_> = truth
        .f_b
        .iter()
        .zip(&truth.time_s)
        .map(|(f, t)| if *t > 120.0 { f + step } else { *f })
        .collect();
    let data = imu_data(&truth, &f, &truth.w_b);
    let sol = coupling::solution::<17, _>(&data, &epochs, &exact_initial(&truth), &tuning).unwrap();
    let k0 = 12000;
    let drift = |k: usize| {
        (sol.position_ecef[k] - truth.nav[k].position_ecef)
            - (sol.position_ecef[k0] - truth.nav[k0].position_ecef)
            - (sol.velocity_ecef[k0] - truth.nav[k0].velocity_ecef) * (truth.time_s[k] - 120.0)
    };
    // ½ b t² along the turning body axis: ∬ C_b^e(t) Δb dt² by the trapezoid rule.
    let (mut v, mut r) = (Vector3::zeros(), Vector3::zeros());
    let mut expected = vec![Vector3::zeros()];
    for k in k0..k0 + 3000 {
        let a0 = truth.nav[k].c_b_e * step;
        let a1 = truth.nav[k + 1].c_b_e * step;
        let v1 = v + 0.005 * (a0 + a1);
        r += 0.005 * (v + v1);
        v = v1;
        expected.push(r);
    }
    for secs in [5usize, 15, 30] {
        let k = k0 + secs * 100;
        let (got, want) = (drift(k), expected[secs * 100]);
        println!(
            "outage {secs} s: drift {:.3} m, ½ b t² = {:.3} m (straight: {:.3})",
            got.norm(),
            want.norm(),
            0.025 * (secs * secs) as f64
        );
        assert!(
            (got - want).norm() < 0.05 * want.norm() + 0.05,
            "{secs} s: {got} vs {want}"
        );
    }
}

/// The solution stores each navigation block of P as its diagonal (in
/// `covariance_diagonal`) and upper triangle: the blocks it gives back are
/// the filter's own P at every sample (the upper triangle and diagonal
/// bitwise, the lower triangle to rounding: P is symmetric only to
/// rounding between updates), with the other 3 × 3 blocks of P's diagonal
/// in `covariance_diagonal`.
#[test]
fn solution_blocks_are_the_filters_covariance() {
    let truth = drive(20.0, 100.0, true);
    let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
    let tuning = FilterTuning::from_imu_spec(&spec, 100.0, false).unwrap();
    let mut rng = stream(5, 0);
    let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
    let epochs = gnss_for(&truth, &SimulationConfig::default(), &mut rng);
    let (f, w) = readings(&truth, &imu, &mut rng);
    let data = imu_data(&truth, &f, &w);
    let init = exact_initial(&truth);
    let mut ps = Vec::new();
    coupling::run::<17, _, _>(&data, &epochs, &init, &tuning, |_, s| ps.push(s.kf.p)).unwrap();
    let sol = coupling::solution::<17, _>(&data, &epochs, &init, &tuning).unwrap();
    assert_eq!(ps.len(), sol.time_s.len());
    for (k, p) in ps.iter().enumerate() {
        let blocks = [
            sol.attitude_covariance_ecef(k),
            sol.velocity_covariance_ecef(k),
            sol.position_covariance_ecef(k),
        ];
        for (b, m) in blocks.iter().enumerate() {
            let q = p.fixed_view::<3, 3>(3 * b, 3 * b);
            for i in 0..3 {
                for j in i..3 {
                    assert_eq!(m[(i, j)], q[(i, j)], "sample {k}, block {b}, ({i}, {j})");
                    let tol = 1e-12 * (q[(i, i)] * q[(j, j)]).sqrt();
                    assert!(
                        (m[(j, i)] - q[(j, i)]).abs() <= tol,
                        "sample {k}, block {b}"
                    );
                }
            }
        }
        let diagonal: Vec<f64> = (0..17).map(|i| p[(i, i)]).collect();
        assert_eq!(sol.covariance_diagonal[17 * k..17 * (k + 1)], diagonal[..]);
    }
}

/// Two hours at 100 Hz (parked receiver, tactical-like IMU): P stays
/// symmetric positive definite and the solution bounded.
#[test]
fn covariance_stays_positive_definite_over_two_hours() {
    let truth = drive(7200.0, 100.0, false);
    let spec = bias_and_noise_spec(1e-2, 1e-5, 5e-4, 5e-6);
    let tuning = FilterTuning::from_imu_spec(&spec, 100.0, false).unwrap();
    let mut rng = stream(1, 0);
    let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
    let epochs = gnss_for(&truth, &SimulationConfig::default(), &mut rng);
    let (f, w) = readings(&truth, &imu, &mut rng);
    let data = imu_data(&truth, &f, &w);
    let mut worst: f64 = 0.0;
    let mut last_p = None;
    let start = std::time::Instant::now();
    coupling::run::<17, _, _>(&data, &epochs, &exact_initial(&truth), &tuning, |k, s| {
        worst = worst.max((s.nav.position_ecef - truth.nav[k].position_ecef).norm());
        if k + 1 == truth.time_s.len() {
            last_p = Some(s.kf.p);
        }
    })
    .unwrap();
    let secs = start.elapsed().as_secs_f64();
    println!(
        "2 h run: {:.0} IMU epochs/s including INS and updates; worst error {worst:.1} m",
        720_000.0 / secs
    );
    let p = last_p.unwrap();
    assert!((p - p.transpose()).abs().max() <= 1e-12 * p.abs().max());
    assert!(p.cholesky().is_some());
    assert!(worst < 30.0, "{worst}");
}

#[test]
fn bad_input_is_a_clear_error() {
    let truth = drive(10.0, 100.0, true);
    let mut rng = stream(2, 0);
    let epochs = gnss_for(&truth, &SimulationConfig::default(), &mut rng);
    let tuning =
        FilterTuning::from_imu_spec(&bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4), 100.0, false)
            .unwrap();
    let init = exact_initial(&truth);
    let data = imu_data(&truth, &truth.f_b, &truth.w_b);
    let msg = |r: Result<Solution, Error>| match r {
        Err(Error::InvalidArgument { argument, reason }) => format!("{argument}: {reason}"),
        other => panic!("expected InvalidArgument, got {other:?}"),
    };
    // GNSS outside the IMU span, and not increasing.
    let mut late = epochs.clone();
    late[10].time_s = 20.0;
    assert!(
        msg(coupling::solution::<17, _>(&data, &late, &init, &tuning))
            .contains("outside the IMU span")
    );
    let mut swapped = epochs.clone();
    swapped.swap(3, 4);
    assert!(msg(coupling::solution::<17, _>(&data, &swapped, &init, &tuning)).contains("increase"));
    // Mismatched lengths and NaN IMU data.
    let short = ImuData {
        angular_rate_b: &truth.w_b[1..],
        ..data
    };
    assert!(
        msg(coupling::solution::<17, _>(&short, &epochs, &init, &tuning))
            .starts_with("angular_rate")
    );
    let mut nan_f = truth.f_b.clone();
    nan_f[7].y = f64::NAN;
    let nan = ImuData {
        specific_force_b: &nan_f,
        ..data
    };
    assert!(
        msg(coupling::solution::<17, _>(&nan, &epochs, &init, &tuning))
            .starts_with("specific_force")
    );
    // No satellites at the first epoch: no initial fix.
    let mut empty = epochs.clone();
    empty[0].measurements.clear();
    let e = initial_state_from_fix(&empty[..1], &data, None).unwrap_err();
    assert!(e.to_string().contains("0 usable satellites"), "{e}");
    // From a proper first epoch the fix-based initialisation is close to the truth.
    let from_fix = initial_state_from_fix(&epochs, &data, None).unwrap();
    assert!((from_fix.nav.position_ecef - truth.nav[0].position_ecef).norm() < 30.0);
    let psi = dcm_to_rotation_vector(&(from_fix.nav.c_b_e * truth.nav[0].c_b_e.transpose()));
    assert!(psi.norm() < 0.1, "{psi}");
    // A filter with no GNSS at all still runs (pure INS) and reports nothing.
    let sol = coupling::solution::<17, GnssEpoch>(&data, &[], &init, &tuning).unwrap();
    assert!(sol.measurements.is_empty());
    // A bad tuning value names its field.
    let mut t = tuning;
    t.gate_probability = 0.0;
    assert!(
        msg(coupling::solution::<17, _>(&data, &epochs, &init, &t)).starts_with("gate_probability")
    );
}
