//! The step API (`FilterState::start`, `predict`, `update_*`) against the
//! batch run: the same calls in the same order give the same filter, bit
//! for bit; the increments path reproduces the INS's own increments
//! mechanization; and what the step API refuses.

use memsnav_core::coupling::{self, FilterState, FilterTuning, InitialState, PositionFix};
use memsnav_core::filter::state::BASE_STATES;
use memsnav_core::gnss::{GnssEpoch, SimulationConfig};
use memsnav_core::ins::{self, ImuData, ImuIncrement, ImuSample};
use memsnav_core::random::stream;
use memsnav_core::sensors::ImuModel;
use memsnav_core::Error;
use nalgebra::{Matrix3, Vector3};

mod common;
use common::*;

fn tuning() -> FilterTuning {
    let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
    FilterTuning::from_imu_spec(&spec, 100.0, false).unwrap()
}

/// Runs the step API over the samples the way the batch run does (each
/// epoch at its sample: the simulated epochs fall on IMU samples) and
/// returns the state after every sample.
fn stepped<E: coupling::Aiding>(
    truth: &Truth,
    f: &[Vector3<f64>],
    w: &[Vector3<f64>],
    epochs: &[E],
    initial: &InitialState,
    update: impl Fn(&mut FilterState<BASE_STATES>, &E) -> bool,
) -> (Vec<FilterState<BASE_STATES>>, Vec<bool>) {
    let sample = |k: usize| ImuSample {
        specific_force_b: f[k],
        angular_rate_b: w[k],
    };
    let t = &truth.time_s;
    let mut s = FilterState::start::<E>(initial, &tuning(), t[0], &sample(0)).unwrap();
    let mut j = 0;
    let mut states = Vec::with_capacity(t.len());
    let mut applied = Vec::with_capacity(epochs.len());
    for (k, &tk) in t.iter().enumerate() {
        if k > 0 {
            s.predict(tk, &sample(k)).unwrap();
        }
        while j < epochs.len() && epochs[j].time_s() <= tk + 1e-4 {
            applied.push(update(&mut s, &epochs[j]));
            j += 1;
        }
        states.push(s.clone());
    }
    assert_eq!(j, epochs.len(), "every epoch falls on a sample");
    (states, applied)
}

/// Whether the batch run applied each epoch whole: every batch it tested
/// at the epoch's time passed (from its records, not from the step API).
fn applied_in_batch_run<E: coupling::Aiding>(
    solution: &coupling::Solution,
    epochs: &[E],
) -> Vec<bool> {
    epochs
        .iter()
        .map(|e| {
            let mut at = solution
                .batches
                .iter()
                .filter(|b| b.time_s == e.time_s())
                .peekable();
            at.peek().is_some() && at.all(|b| b.accepted)
        })
        .collect()
}

fn assert_same(solution: &coupling::Solution, states: &[FilterState<BASE_STATES>]) {
    assert_eq!(solution.time_s.len(), states.len());
    for (k, s) in states.iter().enumerate() {
        assert_eq!(solution.position_ecef[k], s.nav.position_ecef, "sample {k}");
        assert_eq!(solution.velocity_ecef[k], s.nav.velocity_ecef, "sample {k}");
        assert_eq!(solution.c_b_e[k], s.nav.c_b_e, "sample {k}");
        assert_eq!(solution.gyro_bias_rad_s[k], s.gyro_bias_rad_s, "sample {k}");
        let diagonal = &solution.covariance_diagonal[k * BASE_STATES..(k + 1) * BASE_STATES];
        let p: Vec<f64> = (0..BASE_STATES).map(|i| s.kf.p[(i, i)]).collect();
        assert_eq!(diagonal, &p[..], "sample {k}");
    }
}

/// Tight coupling with a noisy IMU: the stepped filter is the batch run's,
/// bit for bit, at every sample, and so are its measurement records.
#[test]
fn stepping_gnss_epochs_is_the_batch_run() {
    let truth = drive(60.0, 100.0, true);
    let mut rng = stream(5, 0);
    let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
    let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
    let (f, w) = readings(&truth, &imu, &mut rng);
    let epochs = gnss_for(&truth, &SimulationConfig::default(), &mut rng);
    let initial = exact_initial(&truth);
    let data = imu_data(&truth, &f, &w);
    let solution =
        coupling::solution::<BASE_STATES, GnssEpoch>(&data, &epochs, &initial, &tuning()).unwrap();
    let (states, applied) = stepped(&truth, &f, &w, &epochs, &initial, |s, e| {
        s.update_gnss(e).unwrap()
    });
    assert_same(&solution, &states);
    assert_eq!(applied, applied_in_batch_run(&solution, &epochs));
    assert!(applied.iter().all(|&a| a), "clean pseudoranges all pass");
    let mut last = states.last().unwrap().clone();
    let records = last.take_records();
    assert!(records.measurements.len() > 500);
    assert_eq!(records.measurements, solution.measurements);
}

/// Loose coupling on noisy position and velocity fixes: the same.
#[test]
fn stepping_fixes_is_the_batch_run() {
    let truth = drive(60.0, 100.0, true);
    let mut rng = stream(6, 0);
    let spec = bias_and_noise_spec(1e-2, 1e-4, 1e-3, 1e-4);
    let imu = ImuModel::from_spec(&spec, 100.0, &mut rng).unwrap();
    let (f, w) = readings(&truth, &imu, &mut rng);
    let fixes: Vec<PositionFix> = (0..truth.time_s.len())
        .step_by(100)
        .map(|k| PositionFix {
            time_s: truth.time_s[k],
            position_ecef: truth.nav[k].position_ecef + 2.0 * n3(&mut rng),
            position_covariance: Matrix3::identity() * 4.0,
            velocity_ecef: Some(truth.nav[k].velocity_ecef + 0.1 * n3(&mut rng)),
            velocity_covariance: Matrix3::identity() * 0.01,
            velocity_horizontal_only: false,
        })
        .collect();
    // Two fixes 100 m off in position and one 20 m/s off in velocity: the
    // gate refuses those blocks, so those fixes are not applied whole.
    let mut fixes = fixes;
    for k in [20, 40] {
        fixes[k].position_ecef.x += 100.0;
    }
    *fixes[30].velocity_ecef.as_mut().unwrap() += Vector3::new(0.0, 20.0, 0.0);
    let initial = exact_initial(&truth);
    let data = imu_data(&truth, &f, &w);
    let solution =
        coupling::solution::<BASE_STATES, PositionFix>(&data, &fixes, &initial, &tuning()).unwrap();
    let (states, applied) = stepped(&truth, &f, &w, &fixes, &initial, |s, fix| {
        s.update_fix(fix).unwrap()
    });
    assert_same(&solution, &states);
    assert_eq!(applied, applied_in_batch_run(&solution, &fixes));
    let refused: Vec<usize> = (0..applied.len()).filter(|&k| !applied[k]).collect();
    assert_eq!(refused, [20, 30, 40]);
}

/// A horizontal-only velocity fix (NMEA's speed and course) is two
/// measurements, along the local north and east: the horizontal velocity
/// variance falls as the scalar Kalman update says, p r / (p + r), the
/// vertical one not at all, and a vertical component of any size in the
/// fix is not read. A reset to such a fix sets the horizontal velocity and
/// keeps the filter's vertical velocity and variance.
#[test]
fn horizontal_velocity_fixes_measure_nothing_vertical() {
    let truth = drive(10.0, 100.0, true);
    let sample = ImuSample {
        specific_force_b: truth.f_b[0],
        angular_rate_b: truth.w_b[0],
    };
    let initial = exact_initial(&truth);
    let nav = truth.nav[0];
    let geo = memsnav_core::geodesy::ecef_to_geodetic(&nav.position_ecef);
    let cne = memsnav_core::geodesy::c_n_e(geo.latitude_rad, geo.longitude_rad);
    let velocity_ned = |s: &FilterState<BASE_STATES>| cne.transpose() * s.nav.velocity_ecef;
    let velocity_p_ned =
        |s: &FilterState<BASE_STATES>| cne.transpose() * s.kf.p.fixed_view::<3, 3>(3, 3) * cne;
    // 0.3 m/s off north, and 100 m/s down that must not be read.
    let offset_ned = Vector3::new(0.3, 0.0, 100.0);
    let r = 0.01;
    let fix = PositionFix {
        time_s: truth.time_s[0],
        position_ecef: nav.position_ecef,
        position_covariance: Matrix3::identity() * 4.0,
        velocity_ecef: Some(nav.velocity_ecef + cne * offset_ned),
        velocity_covariance: cne
            * Matrix3::from_diagonal(&Vector3::new(r, r, 0.0))
            * cne.transpose(),
        velocity_horizontal_only: true,
    };
    let mut s =
        FilterState::start::<PositionFix>(&initial, &tuning(), fix.time_s, &sample).unwrap();
    let before = velocity_p_ned(&s);
    let v_before = velocity_ned(&s);
    s.update_fix(&fix).unwrap();
    let records = s.clone().take_records();
    let ids: Vec<u16> = records
        .measurements
        .iter()
        .filter(|m| m.kind == coupling::MeasurementKind::Velocity)
        .map(|m| m.id)
        .collect();
    assert_eq!(ids, [0, 1]);
    let after = velocity_p_ned(&s);
    for axis in 0..2 {
        let p = before[(axis, axis)];
        let want = p * r / (p + r);
        assert!((after[(axis, axis)] - want).abs() < 1e-9 * p, "{after}");
    }
    assert!((after[(2, 2)] - before[(2, 2)]).abs() < 1e-12, "{after}");
    let v = velocity_ned(&s);
    let p = before[(0, 0)];
    assert!((v.x - v_before.x - 0.3 * p / (p + r)).abs() < 1e-6, "{v}");
    assert!((v.z - v_before.z).abs() < 1e-9, "{v}");

    // A fix 50 m/s off east fails its test; reset at the first failure.
    let mut tuning = tuning();
    tuning.recovery.reset_after_failed_epochs = 1;
    let mut s = FilterState::start::<PositionFix>(&initial, &tuning, fix.time_s, &sample).unwrap();
    let far = PositionFix {
        velocity_ecef: Some(nav.velocity_ecef + cne * Vector3::new(0.0, 50.0, 100.0)),
        ..fix
    };
    s.update_fix(&far).unwrap();
    let v = velocity_ned(&s);
    let truth_ned = cne.transpose() * nav.velocity_ecef;
    assert!(
        (v.y - truth_ned.y - 50.0).abs() < 1e-9 && (v.x - truth_ned.x).abs() < 1e-9,
        "{v}"
    );
    assert!((v.z - v_before.z).abs() < 1e-9, "{v}");
    let reset = velocity_p_ned(&s);
    assert!(
        (reset[(0, 0)] - r).abs() < 1e-12 && (reset[(1, 1)] - r).abs() < 1e-12,
        "{reset}"
    );
    assert!((reset[(2, 2)] - before[(2, 2)]).abs() < 1e-12, "{reset}");
}

/// Predicting by increments runs the INS's increments mechanization
/// (coning and sculling) bit for bit when the sensor estimates are zero,
/// and so reproduces the trajectory from error-free increments.
#[test]
fn increments_run_the_increments_mechanization() {
    let truth = drive(30.0, 100.0, true);
    let increments = ins::increments_from_samples(&truth.time_s, &truth.f_b, &truth.w_b).unwrap();
    let initial = InitialState {
        clock_offset_m: Some(0.0),
        clock_drift_m_s: Some(0.0),
        ..exact_initial(&truth)
    };
    let start = ImuSample {
        specific_force_b: truth.f_b[0],
        angular_rate_b: truth.w_b[0],
    };
    let t = &truth.time_s;
    let mut s =
        FilterState::<BASE_STATES>::start::<GnssEpoch>(&initial, &tuning(), t[0], &start).unwrap();
    let mut nav = truth.nav[0];
    let mut previous = ImuIncrement::default();
    for k in 1..t.len() {
        let increment = increments[k - 1];
        s.predict_increments(t[k], &increment).unwrap();
        nav = ins::step_increments(&nav, &previous, &increment, t[k] - t[k - 1]);
        previous = increment;
        assert_eq!(s.nav, nav, "sample {k}");
    }
    let error = (s.nav.position_ecef - truth.nav.last().unwrap().position_ecef).norm();
    assert!(
        error < 0.05,
        "{error} m after 30 s from error-free increments"
    );
    // The covariance grew with the INS's own uncertainty.
    assert!(s.kf.p[(6, 6)] > tuning().initial_std.position_m.powi(2));
}

/// Time that does not increase, a step longer than an IMU period, NaN
/// samples and epochs stamped away from the filter's time are refused,
/// naming the argument; the filter is unchanged by a refused call.
#[test]
fn bad_steps_are_refused() {
    let truth = drive(5.0, 100.0, true);
    let mut rng = stream(7, 0);
    let epochs = gnss_for(&truth, &SimulationConfig::default(), &mut rng);
    let sample = ImuSample {
        specific_force_b: truth.f_b[0],
        angular_rate_b: truth.w_b[0],
    };
    let initial = exact_initial(&truth);
    let mut s =
        FilterState::<BASE_STATES>::start::<GnssEpoch>(&initial, &tuning(), 0.0, &sample).unwrap();
    let argument = |e: Error| match e {
        Error::InvalidArgument { argument, reason } => (argument, reason),
        other => panic!("{other:?}"),
    };
    let (a, reason) = argument(s.predict(0.0, &sample).unwrap_err());
    assert_eq!(a, "time");
    assert!(reason.contains("must increase"), "{reason}");
    let (a, reason) = argument(s.predict(2.5, &sample).unwrap_err());
    assert_eq!(a, "time");
    assert!(reason.contains("longer than"), "{reason}");
    let nan = ImuSample {
        specific_force_b: Vector3::new(f64::NAN, 0.0, 0.0),
        ..sample
    };
    assert_eq!(
        argument(s.predict(0.01, &nan).unwrap_err()).0,
        "specific_force"
    );
    let (a, reason) = argument(s.update_gnss(&epochs[1]).unwrap_err());
    assert_eq!(a, "gnss");
    assert!(
        reason.contains("predict to the epoch's time first"),
        "{reason}"
    );
    let before = s.nav;
    assert!(s.predict(f64::NAN, &sample).is_err());
    assert_eq!(s.nav, before);
    assert_eq!(s.time_s(), 0.0);
    s.predict(0.01, &sample).unwrap();
    assert_eq!(s.time_s(), 0.01);
}

/// A batch run on increments ([`ImuData::increments`]) is the stepped
/// `predict_increments`, bit for bit; with its epochs between samples it
/// still follows the truth (each epoch's share of the interval's
/// increments integrated up to it).
#[test]
fn a_batch_run_on_increments_is_the_stepped_one() {
    let truth = drive(60.0, 20.0, true);
    let increments = ins::increments_from_samples(&truth.time_s, &truth.f_b, &truth.w_b).unwrap();
    let (f, w) =
        memsnav_core::ins::ImuData::means_of_increments(&truth.time_s, &increments).unwrap();
    let mut rng = stream(8, 0);
    let epochs = gnss_for(&truth, &SimulationConfig::default(), &mut rng);
    let initial = exact_initial(&truth);
    let data = ImuData {
        increments: Some(&increments),
        ..imu_data(&truth, &f, &w)
    };
    let solution =
        coupling::solution::<BASE_STATES, GnssEpoch>(&data, &epochs, &initial, &tuning()).unwrap();
    let t = &truth.time_s;
    let start = ImuSample {
        specific_force_b: f[0],
        angular_rate_b: w[0],
    };
    let mut s =
        FilterState::<BASE_STATES>::start::<GnssEpoch>(&initial, &tuning(), t[0], &start).unwrap();
    let mut j = 0;
    for (k, &tk) in t.iter().enumerate() {
        if k > 0 {
            s.predict_increments(tk, &increments[k - 1]).unwrap();
        }
        while j < epochs.len() && epochs[j].time_s <= tk + 1e-4 {
            s.update_gnss(&epochs[j]).unwrap();
            j += 1;
        }
        assert_eq!(solution.position_ecef[k], s.nav.position_ecef, "sample {k}");
        assert_eq!(solution.c_b_e[k], s.nav.c_b_e, "sample {k}");
    }
    // The same epochs 0.02 s later, between the 20 Hz samples.
    let shifted: Vec<GnssEpoch> = epochs
        .iter()
        .filter(|e| e.time_s + 0.02 < *t.last().unwrap())
        .map(|e| GnssEpoch {
            time_s: e.time_s + 0.02,
            ..e.clone()
        })
        .collect();
    let between =
        coupling::solution::<BASE_STATES, GnssEpoch>(&data, &shifted, &initial, &tuning()).unwrap();
    let worst = between
        .position_ecef
        .iter()
        .zip(&truth.nav)
        .map(|(r, n)| (r - n.position_ecef).norm())
        .fold(0.0, f64::max);
    // The measurements belong 0.02 s earlier (12 m/s: 0.24 m); the filter
    // takes them at their stamp and stays within a few of that.
    assert!(worst < 3.0, "{worst} m");
}
