//! Simulated multi-position sessions with known parameters.

use nalgebra::{DMatrix, DVector, Matrix3, UnitQuaternion, Vector3};
use rand::Rng as _;

use super::*;
use crate::calibration::{accelerometer_parameters, gyroscope_parameters};
use crate::random::stream;
use crate::sensors::NoiseModel;

const G: f64 = 9.80665;

/// The truth: an accelerometer in the frame convention of [`magnitude`]
/// (no misalignment above the diagonal) and a full gyroscope.
fn truth(nonlinearity: bool) -> (AccelerometerModel, GyroscopeModel) {
    let white = |std: f64| NoiseModel {
        white_std: std,
        ..Default::default()
    };
    let accel = AccelerometerModel {
        bias: Vector3::new(0.12, -0.08, 0.2),
        scale_factor: Vector3::new(0.01, -0.015, 0.02),
        misalignment: Matrix3::new(0.0, 0.0, 0.0, 0.004, 0.0, 0.0, -0.006, 0.003, 0.0),
        nonlinearity: if nonlinearity {
            Vector3::new(3e-4, -2e-4, 4e-4)
        } else {
            Vector3::zeros()
        },
        noise: white(0.01),
    };
    let gyro = GyroscopeModel {
        bias: Vector3::new(0.01, -0.02, 0.015),
        scale_factor: Vector3::new(0.02, -0.01, 0.03),
        misalignment: Matrix3::new(0.0, 0.005, -0.01, 0.008, 0.0, 0.004, -0.003, 0.006, 0.0),
        g_sensitivity: Matrix3::from_fn(|i, j| 1e-4 * (1.0 + i as f64 - 1.5 * j as f64)),
        noise: white(0.003),
    };
    (accel, gyro)
}

/// Raw readings of a session at 100 Hz: `rest_s` at rest, then `poses`
/// random orientations held 3 s each, joined by 2 s smooth turns about a
/// fixed body axis. The raw counts invert the `nominal` scale and offset.
fn session(
    seed: u64,
    poses: usize,
    rest_s: f64,
    accel: &AccelerometerModel,
    gyro: &GyroscopeModel,
    nominal: &Nominal,
) -> (Vec<f64>, Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
    let mut rng = stream(seed, 0);
    let dt = 0.01;
    let up = Vector3::new(0.0, 0.0, G);
    let mut time = Vec::new();
    let mut force = Vec::new();
    let mut rate = Vec::new();
    let mut q = UnitQuaternion::identity();
    let hold = |q: &UnitQuaternion<f64>,
                seconds: f64,
                time: &mut Vec<f64>,
                f: &mut Vec<_>,
                w: &mut Vec<_>| {
        for _ in 0..(seconds / dt).round() as usize {
            time.push(time.len() as f64 * dt);
            f.push(q.inverse_transform_vector(&up));
            w.push(Vector3::zeros());
        }
    };
    hold(&q, rest_s, &mut time, &mut force, &mut rate);
    for _ in 0..poses {
        let axis = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        let angle = rng.random_range(1.0..2.5);
        let phi = axis.normalize() * angle;
        let steps = (2.0 / dt) as usize;
        let start = q;
        for k in 0..steps {
            // s(τ) = τ − sin(2πτ)/(2π) over τ = t/2: the body turns about φ
            // with rate ṡ φ, which starts and stops with zero slope (a kink in
            // the rate would cost the sampled integral ~h²/12 of its jump).
            let two_pi = 2.0 * std::f64::consts::PI;
            let tau = k as f64 / steps as f64;
            let s = tau - (two_pi * tau).sin() / two_pi;
            let s_dot = (1.0 - (two_pi * tau).cos()) / 2.0;
            let qk = start * UnitQuaternion::from_scaled_axis(phi * s);
            time.push(time.len() as f64 * dt);
            force.push(qk.inverse_transform_vector(&up));
            rate.push(phi * s_dot);
        }
        q = start * UnitQuaternion::from_scaled_axis(phi);
        hold(&q, 3.0, &mut time, &mut force, &mut rate);
    }
    let s_a = accel.measure(&force, 100.0, &mut stream(seed, 1)).unwrap();
    let s_g = gyro
        .measure(&rate, &force, 100.0, &mut stream(seed, 2))
        .unwrap();
    let raw = |s: &Vector3<f64>, scale: &Vector3<f64>, offset: &Vector3<f64>| {
        s.component_div(scale) + offset
    };
    (
        time,
        s_a.iter()
            .map(|s| raw(s, &nominal.accel_scale, &nominal.accel_offset))
            .collect(),
        s_g.iter()
            .map(|s| raw(s, &nominal.gyro_scale, &nominal.gyro_offset))
            .collect(),
    )
}

fn options(nominal: Nominal) -> StaticCalibrationOptions {
    StaticCalibrationOptions {
        gravity_m_s2: G,
        nominal,
        detector: StaticDetector {
            initial_rest_s: 20.0,
            ..Default::default()
        },
        estimate: Estimate::Determinable,
        holdout: Holdout::default(),
    }
}

fn all_parameters(a: &AccelerometerModel, g: &GyroscopeModel) -> DVector<f64> {
    let pa = accelerometer_parameters(a);
    let pg = gyroscope_parameters(g);
    DVector::from_iterator(36, pa.iter().chain(pg.iter()).copied())
}

#[test]
fn noise_free_counts_give_the_parameters_to_rounding() {
    // Noise far below anything the fit resolves (the detector needs some).
    let (mut accel, mut gyro) = truth(true);
    accel.noise.white_std = 1e-8;
    gyro.noise.white_std = 1e-9;
    // Raw counts of a 16-bit part: offset 32768, ~1/3700 g and 2.1e-4 rad/s
    // per count; the calibration starts from a gyro scale 30 % off.
    let counts = Nominal {
        accel_scale: Vector3::repeat(G / 3700.0),
        accel_offset: Vector3::repeat(32768.0),
        gyro_scale: Vector3::repeat(2.1e-4),
        gyro_offset: Vector3::repeat(32768.0),
    };
    let (time, a, w) = session(1, 24, 30.0, &accel, &gyro, &counts);
    let guess = Nominal {
        gyro_scale: Vector3::repeat(1.0 / 6258.0),
        ..counts
    };
    let cal = calibrate_static(&time, &a, &w, &options(guess)).unwrap();
    assert_eq!(cal.poses.len(), 25);
    assert!(cal.held.is_empty(), "{:?}", cal.held);
    // The gyro model is relative to the wrong nominal: compare the
    // corrected outputs with the truth instead of the parameters.
    let (f, omega) = cal.correct(&a, &w).unwrap();
    let (f_true, w_true): (Vec<_>, Vec<_>) = {
        let mut o = options(counts);
        o.estimate = Estimate::All;
        let exact = calibrate_static(&time, &a, &w, &o).unwrap();
        let p = all_parameters(&exact.accelerometer, &exact.gyroscope);
        let expected = all_parameters(&accel, &gyro);
        let error = (&p - &expected).amax();
        assert!(error < 1e-7, "{}", (&p - &expected).transpose());
        exact.correct(&a, &w).unwrap()
    };
    let worst_f = f
        .iter()
        .zip(&f_true)
        .map(|(x, y)| (x - y).amax())
        .fold(0.0, f64::max);
    let worst_w = omega
        .iter()
        .zip(&w_true)
        .map(|(x, y)| (x - y).amax())
        .fold(0.0, f64::max);
    assert!(worst_f < 1e-7 && worst_w < 1e-7, "{worst_f} {worst_w}");
    assert!(
        cal.warnings
            .iter()
            .any(|w| w.contains("differs from the nominal by +3")),
        "{:?}",
        cal.warnings
    );
    for turn in &cal.turns {
        assert!(turn.angle_error_after < 1e-8, "{turn:?}");
    }
}

/// z = (estimate − truth)/σ over seeds: the Mahalanobis distances of the
/// estimated parameters sum to a χ² with (parameters × seeds) degrees of
/// freedom, and the pooled z-scores pass a Kolmogorov-Smirnov test.
#[test]
fn parameters_are_recovered_within_their_sigma_over_seeds() {
    let (accel, gyro) = truth(true);
    let expected = all_parameters(&accel, &gyro);
    let seeds = 24;
    let mut chi2 = 0.0;
    let mut dof = 0usize;
    let mut z_scores = Vec::new();
    for seed in 0..seeds {
        let (time, a, w) = session(100 + seed, 30, 30.0, &accel, &gyro, &Nominal::default());
        let mut o = options(Nominal::default());
        o.estimate = Estimate::All;
        let cal = calibrate_static(&time, &a, &w, &o).unwrap();
        let error = all_parameters(&cal.accelerometer, &cal.gyroscope) - &expected;
        let estimated: Vec<usize> = (0..36).filter(|&k| cal.covariance[(k, k)] > 0.0).collect();
        assert_eq!(estimated.len(), 12 + 21);
        let e = DVector::from_iterator(estimated.len(), estimated.iter().map(|&k| error[k]));
        let cov = cal
            .covariance
            .select_rows(estimated.iter())
            .select_columns(estimated.iter());
        let inv = cov.clone().try_inverse().unwrap();
        chi2 += (e.transpose() * inv * &e)[(0, 0)];
        dof += estimated.len();
        // White noise: the covariance from the residuals sits on the
        // Cramér-Rao bound (the median ratio of σ, within the spread of σ̂).
        let mut ratios: Vec<f64> = estimated
            .iter()
            .map(|&k| (cal.covariance[(k, k)] / cal.crb[(k, k)]).sqrt())
            .collect();
        ratios.sort_by(f64::total_cmp);
        let median = ratios[ratios.len() / 2];
        assert!((0.8..1.25).contains(&median), "sigma/CRB {ratios:?}");
        for j in 0..estimated.len() {
            z_scores.push(e[j] / cov[(j, j)].sqrt());
        }
    }
    // χ²(792): mean 792, std √1584 ≈ 40; 4σ either side.
    let d = dof as f64;
    assert!(
        (chi2 - d).abs() < 4.0 * (2.0 * d).sqrt(),
        "chi2 {chi2:.0} for {dof}"
    );
    // KS against N(0, 1): D < 1.63/√n is the 1 % critical value.
    z_scores.sort_by(f64::total_cmp);
    let n = z_scores.len() as f64;
    let ks = z_scores
        .iter()
        .enumerate()
        .map(|(i, z)| {
            let cdf = 0.5 * (1.0 + libm_erf(z / std::f64::consts::SQRT_2));
            (cdf - i as f64 / n)
                .abs()
                .max((cdf - (i + 1) as f64 / n).abs())
        })
        .fold(0.0, f64::max);
    eprintln!(
        "chi2 {chi2:.0} for {dof} degrees of freedom; KS distance {ks:.4} (1 % critical {:.4}); \
         mean z {:.3}, rms z {:.3}",
        1.63 / n.sqrt(),
        z_scores.iter().sum::<f64>() / n,
        (z_scores.iter().map(|z| z * z).sum::<f64>() / n).sqrt()
    );
    assert!(ks < 1.63 / n.sqrt(), "KS distance {ks:.3}");
}

/// erf by Abramowitz and Stegun 7.1.26 (|error| < 1.5e-7).
fn libm_erf(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.327_591_1 * x.abs());
    let y = 1.0
        - (((((1.061_405_429 * t - 1.453_152_027) * t) + 1.421_413_741) * t - 0.284_496_736) * t
            + 0.254_829_592)
            * t
            * (-x * x).exp();
    y.copysign(x)
}

#[test]
fn aligned_poses_hold_the_nonlinearity_and_few_turns_hold_the_gyro_scale() {
    let (accel, gyro) = truth(false);
    let (time, a, w) = session(7, 12, 30.0, &accel, &gyro, &Nominal::default());
    let cal = calibrate_static(&time, &a, &w, &options(Nominal::default())).unwrap();
    let held: Vec<&str> = cal.held.iter().map(|(n, _)| n.as_str()).collect();
    // Nonlinearity of 1e-4 per m/s² or less is below what 12 poses of
    // 3 s resolve against a 0.01 m/s² noise: held, or estimated within σ.
    for (k, name) in ["nonlinearity_u", "nonlinearity_v", "nonlinearity_w"]
        .iter()
        .enumerate()
    {
        let is_held = held.contains(&format!("accelerometer {name}").as_str());
        let sd = cal.accelerometer_std.nonlinearity[k];
        assert!(is_held == (sd == 0.0), "{name}: {held:?} {sd}");
    }
    // Too few turns for nine gyro entries with estimate = all: an error naming `poses`.
    let (time, a, w) = session(8, 4, 30.0, &accel, &gyro, &Nominal::default());
    let mut o = options(Nominal::default());
    o.estimate = Estimate::All;
    let err = calibrate_static(&time, &a, &w, &o).unwrap_err();
    assert!(err.to_string().starts_with("poses:"), "{err}");
}

#[test]
fn held_out_poses_are_reported_apart_and_the_fit_ignores_them() {
    let (accel, gyro) = truth(true);
    let (time, a, w) = session(9, 24, 30.0, &accel, &gyro, &Nominal::default());
    let mut o = options(Nominal::default());
    o.holdout.every = Some(4);
    let cal = calibrate_static(&time, &a, &w, &o).unwrap();
    let held: Vec<usize> = (0..cal.poses.len())
        .filter(|&k| cal.poses[k].held_out)
        .collect();
    assert_eq!(held, vec![3, 7, 11, 15, 19, 23]);
    assert!(cal
        .turns
        .iter()
        .all(|t| t.held_out == (held.contains(&t.from) || held.contains(&(t.from + 1)))));
    // Both of the size of a pose mean's noise, 0.01/√(≈250) ≈ 6e-4 m/s²
    // (held-out poses also carry the fit's own error).
    let fit = rms(
        cal.poses
            .iter()
            .map(|p| (p.magnitude_error_after, p.held_out)),
        false,
    );
    let out = rms(
        cal.poses
            .iter()
            .map(|p| (p.magnitude_error_after, p.held_out)),
        true,
    );
    assert!(fit < 1e-3 && out < 3e-3, "{fit} {out}");
    // Perturbing a held-out pose does not move the fit.
    let mut a2 = a.clone();
    let p = cal.poses[7].pose;
    for s in &mut a2[p.start..p.end] {
        s.x += 0.05;
    }
    let cal2 = calibrate_static(&time, &a2, &w, &o).unwrap();
    assert!(
        (all_parameters(&cal2.accelerometer, &cal2.gyroscope)
            - all_parameters(&cal.accelerometer, &cal.gyroscope))
        .amax()
            < 1e-12
    );
}

/// The session's first `end_s` seconds.
fn truncated(
    (time, a, w): &(Vec<f64>, Vec<Vector3<f64>>, Vec<Vector3<f64>>),
    end_s: f64,
) -> (Vec<f64>, Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
    let n = time.partition_point(|&t| t < end_s);
    (time[..n].to_vec(), a[..n].to_vec(), w[..n].to_vec())
}

#[test]
fn holding_out_from_a_time_fits_what_comes_before_it_alone() {
    let (accel, gyro) = truth(true);
    let data = session(11, 24, 30.0, &accel, &gyro, &Nominal::default());
    // Pose k (k ≥ 1) is held over [30 + 5k − 3, 30 + 5k) s; 91 s is in the
    // middle of the turn into pose 13.
    let cut = 91.0;
    let mut o = options(Nominal::default());
    o.holdout.from_s = Some(cut);
    let cal = calibrate_static(&data.0, &data.1, &data.2, &o).unwrap();
    let out: Vec<usize> = (0..cal.poses.len())
        .filter(|&k| cal.poses[k].held_out)
        .collect();
    assert_eq!(out, (13..25).collect::<Vec<_>>());
    // The same parameters as a calibration of the session before the cut.
    let (t, a, w) = truncated(&data, cut);
    let first = calibrate_static(&t, &a, &w, &options(Nominal::default())).unwrap();
    assert_eq!(first.poses.len(), 13);
    let difference = all_parameters(&cal.accelerometer, &cal.gyroscope)
        - all_parameters(&first.accelerometer, &first.gyroscope);
    assert!(difference.amax() < 1e-12, "{}", difference.transpose());
    assert_eq!(cal.held, first.held);
    let mut o = options(Nominal::default());
    o.holdout.from_s = Some(f64::NAN);
    let err = calibrate_static(&data.0, &data.1, &data.2, &o).unwrap_err();
    assert!(err.to_string().starts_with("holdout_from_s:"), "{err}");
}

/// The nonlinearity of a session: the N entries chosen, and the record.
fn chosen_nonlinearity(cal: &StaticCalibration) -> Vec<String> {
    let s = &cal.model_selection[0];
    assert_eq!(s.stage, "accelerometer nonlinearity");
    assert_eq!(s.candidates.len(), 8);
    s.best().terms.clone()
}

#[test]
fn the_information_criterion_estimates_a_nonlinearity_only_where_there_is_one() {
    // A nonlinearity of 3e-4 per m/s² moves |f| by N g² ≈ 0.03 m/s², 50
    // times a pose mean's noise (0.01/√300 m/s²): every seed keeps all
    // three entries.
    let (accel, gyro) = truth(true);
    for seed in 0..4 {
        let (time, a, w) = session(200 + seed, 30, 30.0, &accel, &gyro, &Nominal::default());
        let cal = calibrate_static(&time, &a, &w, &options(Nominal::default())).unwrap();
        assert_eq!(
            chosen_nonlinearity(&cal),
            ["nonlinearity_u", "nonlinearity_v", "nonlinearity_w"]
        );
    }
    // Without one, rules 2 and 3 pass N (its σ ≈ 1e-5 is far below the
    // physical size) but AICc rarely takes an entry: the tenth parameter
    // costs 2 + 2.9 in AICc at n = 31 poses, which noise alone beats with
    // probability P(χ²₁ > 4.9) ≈ 2.7 %: about 1 of the 3 × 12 entries here
    // (1 with these seeds), 1.6 % to see more than 3 (binomial).
    let (accel, gyro) = truth(false);
    let mut taken = 0;
    for seed in 0..12 {
        let (time, a, w) = session(300 + seed, 30, 30.0, &accel, &gyro, &Nominal::default());
        let cal = calibrate_static(&time, &a, &w, &options(Nominal::default())).unwrap();
        let chosen = chosen_nonlinearity(&cal);
        taken += chosen.len();
        for name in ["nonlinearity_u", "nonlinearity_v", "nonlinearity_w"] {
            let held = cal
                .held
                .iter()
                .find(|(n, _)| n == &format!("accelerometer {name}"));
            assert_eq!(held.is_none(), chosen.iter().any(|c| c == name));
            if let Some((_, why)) = held {
                assert!(why.contains("AICc"), "{why}");
            }
        }
        // The gyroscope's g-sensitivity (1e-4 to 3.5e-4 (rad/s)/(m/s²),
        // against 0.003/√300 rad/s) is kept whole.
        assert_eq!(cal.model_selection[1].best().terms.len(), 3);
    }
    assert!(
        taken <= 3,
        "{taken} nonlinearity entries estimated without one"
    );
}

#[test]
fn bad_arguments_are_named() {
    let (accel, gyro) = truth(false);
    let (time, a, w) = session(3, 12, 30.0, &accel, &gyro, &Nominal::default());
    let mut o = options(Nominal::default());
    o.gravity_m_s2 = 0.0;
    assert!(calibrate_static(&time, &a, &w, &o)
        .unwrap_err()
        .to_string()
        .starts_with("gravity:"));
    let mut o = options(Nominal::default());
    o.holdout.every = Some(1);
    assert!(calibrate_static(&time, &a, &w, &o)
        .unwrap_err()
        .to_string()
        .starts_with("holdout_every:"));
    let mut o = options(Nominal::default());
    o.nominal.gyro_scale = Vector3::zeros();
    assert!(calibrate_static(&time, &a, &w, &o)
        .unwrap_err()
        .to_string()
        .starts_with("gyro_scale:"));
    let o = options(Nominal::default());
    assert!(calibrate_static(&time, &a, &w[1..], &o)
        .unwrap_err()
        .to_string()
        .starts_with("gyro:"));
    let _ = DMatrix::<f64>::zeros(1, 1);
}
