//! Strapdown INS and trajectory truth: closure on every kind of trajectory
//! (including motions written here in closed form, independently of the
//! generator), coning on the classic coning motion, limits, reproducibility
//! and bad input.

use std::path::PathBuf;
use std::time::Instant;

mod shared_data;
use shared_data::shared_data;

use memsnav_core::attitude::{dcm_to_rotation_vector, euler_to_dcm, rotation_vector_to_dcm};
use memsnav_core::geodesy::{ecef_to_geodetic, geodetic_to_ecef, gravity_ecef, Geodetic};
use memsnav_core::ins::{self, ImuIncrement, NavState};
use memsnav_core::random::stream;
use memsnav_core::trajectory::{RandomTrajectoryConfig, Segment, Trajectory};
use memsnav_core::Error;
use nalgebra::{Matrix3, Rotation3, Vector3};

/// ω_ie written out here (WGS84 / IS-GPS-200 value).
const OMEGA_IE: f64 = 7.292115e-5;

fn profile_path(name: &str) -> PathBuf {
    shared_data(&format!("trajectories/{name}"))
}

/// Small-angle attitude error |vee(½(E − Eᵀ))| = sin|ψ| of E = C_trueᵀ C:
/// accurate near zero, where the acos in a rotation-vector conversion
/// loses half the digits.
fn attitude_error(truth: &Matrix3<f64>, c: &Matrix3<f64>) -> f64 {
    let e = truth.transpose() * c;
    0.5 * Vector3::new(
        e[(2, 1)] - e[(1, 2)],
        e[(0, 2)] - e[(2, 0)],
        e[(1, 0)] - e[(0, 1)],
    )
    .norm()
}

struct Closure {
    position_m: f64,
    velocity_m_s: f64,
    attitude_rad: f64,
}

/// Largest errors of an INS run against the truth over the whole run.
fn closure(
    truth_r: &[Vector3<f64>],
    truth_v: &[Vector3<f64>],
    truth_c: &[Matrix3<f64>],
    nav: &[NavState],
) -> Closure {
    let mut c = Closure {
        position_m: 0.0,
        velocity_m_s: 0.0,
        attitude_rad: 0.0,
    };
    for (k, s) in nav.iter().enumerate() {
        c.position_m = c.position_m.max((s.position_ecef - truth_r[k]).norm());
        c.velocity_m_s = c.velocity_m_s.max((s.velocity_ecef - truth_v[k]).norm());
        c.attitude_rad = c.attitude_rad.max(attitude_error(&truth_c[k], &s.c_b_e));
    }
    c
}

/// Runs the three INS entry points on a trajectory's truth, prints their
/// closure and checks the whole-series integrator; returns the chained
/// two-sample step's closure for the caller's own bound.
fn run_closure(name: &str, tr: &Trajectory) -> Closure {
    let s0 = tr.nav_state(0);
    let t0 = Instant::now();
    let nav = ins::integrate(&tr.time_s, &tr.specific_force_b, &tr.angular_rate_b, &s0).unwrap();
    let rate = tr.len() as f64 / t0.elapsed().as_secs_f64();
    let c4 = closure(&tr.position_ecef, &tr.velocity_ecef, &tr.c_b_e, &nav);
    let t0 = Instant::now();
    let nav2 =
        ins::integrate_steps(&tr.time_s, &tr.specific_force_b, &tr.angular_rate_b, &s0).unwrap();
    let rate2 = tr.len() as f64 / t0.elapsed().as_secs_f64();
    let c2 = closure(&tr.position_ecef, &tr.velocity_ecef, &tr.c_b_e, &nav2);
    // The whole-series integrator is the increment form fed cubic increments.
    let inc =
        ins::increments_from_samples(&tr.time_s, &tr.specific_force_b, &tr.angular_rate_b).unwrap();
    let dv: Vec<_> = inc.iter().map(|i| i.delta_velocity_b).collect();
    let da: Vec<_> = inc.iter().map(|i| i.delta_angle_b).collect();
    let nav_inc = ins::integrate_increments(&tr.time_s, &dv, &da, &s0).unwrap();
    assert_eq!(nav_inc, nav);
    println!(
        "{name}: {:.0} s, {} epochs. integrate: max |Δr| {:.2e} m, |Δv| {:.2e} m/s, |Δψ| {:.2e} rad ({:.2e} epochs/s); \
         chained step: |Δr| {:.2e} m, |Δv| {:.2e} m/s, |Δψ| {:.2e} rad ({:.2e} epochs/s)",
        tr.time_s[tr.len() - 1] - tr.time_s[0],
        tr.len(),
        c4.position_m,
        c4.velocity_m_s,
        c4.attitude_rad,
        rate,
        c2.position_m,
        c2.velocity_m_s,
        c2.attitude_rad,
        rate2,
    );
    assert!(c4.position_m < 0.1, "{name}: {} m", c4.position_m);
    c2
}

#[test]
fn ins_closes_on_random_trajectories() {
    for seed in [0, 1] {
        let t0 = Instant::now();
        let tr =
            Trajectory::random(&RandomTrajectoryConfig::default(), &mut stream(seed, 0)).unwrap();
        println!(
            "random trajectory, 600 s at 100 Hz, generated in {:.3} s",
            t0.elapsed().as_secs_f64()
        );
        let c = run_closure(&format!("random seed {seed}"), &tr);
        assert!(c.position_m < 0.3, "{} m", c.position_m);
    }
}

fn scripted() -> Trajectory {
    use Segment::*;
    let d = std::f64::consts::PI / 180.0;
    let segments = [
        Cruise { duration_s: 20.0 },
        Accelerate {
            duration_s: 15.0,
            target_speed_m_s: 15.0,
        },
        Cruise { duration_s: 30.0 },
        Turn {
            duration_s: 12.0,
            heading_change_rad: 90.0 * d,
        },
        Accelerate {
            duration_s: 10.0,
            target_speed_m_s: 25.0,
        },
        Climb {
            duration_s: 40.0,
            path_angle_rad: 0.04,
        },
        Turn {
            duration_s: 20.0,
            heading_change_rad: -135.0 * d,
        },
        Cruise { duration_s: 60.0 },
        Climb {
            duration_s: 30.0,
            path_angle_rad: -0.06,
        },
        Turn {
            duration_s: 60.0,
            heading_change_rad: 360.0 * d,
        },
        Stop { duration_s: 15.0 },
        Cruise { duration_s: 10.0 },
        Accelerate {
            duration_s: 20.0,
            target_speed_m_s: 20.0,
        },
        Turn {
            duration_s: 8.0,
            heading_change_rad: 45.0 * d,
        },
        Cruise { duration_s: 120.0 },
        Turn {
            duration_s: 10.0,
            heading_change_rad: -90.0 * d,
        },
        Accelerate {
            duration_s: 30.0,
            target_speed_m_s: 30.0,
        },
        Cruise { duration_s: 70.0 },
        Stop { duration_s: 20.0 },
    ];
    let origin = Geodetic::new(0.76, 0.025, 150.0);
    Trajectory::from_segments(origin, 0.3, &segments, 100.0).unwrap()
}

#[test]
fn ins_closes_on_a_scripted_trajectory() {
    let tr = scripted();
    assert_eq!(tr.len(), 60_001);
    let c = run_closure("scripted", &tr);
    assert!(c.position_m < 0.3, "{} m", c.position_m);
}

#[test]
fn scripted_manoeuvres_do_what_they_say() {
    let tr = scripted();
    let euler = tr.euler_ned();
    let v_ned = tr.velocity_ned();
    let at = |t: f64| (t * 100.0).round() as usize;
    // At rest for the first 20 s: the accelerometers read minus gravity.
    let f_e = tr.c_b_e[at(10.0)] * tr.specific_force_b[at(10.0)];
    assert!((f_e + gravity_ecef(&tr.position_ecef[at(10.0)])).norm() < 1e-9);
    // Speed reached, heading changed by the turn (north→east clockwise).
    assert!((v_ned[at(50.0)].norm() - 15.0).abs() < 1e-9);
    let wrap = |a: f64| {
        (a + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI
    };
    assert!((wrap(euler[at(64.0)].z - 0.3)).abs() < 1e-9);
    assert!((wrap(euler[at(78.0)].z - 0.3 - std::f64::consts::FRAC_PI_2)).abs() < 1e-6);
    // Mid-turn the car leans out of the (right) turn: negative roll.
    assert!(euler[at(71.0)].x < -0.005);
    // The climb at 25 m/s, path angle 0.04 for 20 s plus two 10 s ramps
    // (mean ½): height gain 25 · (sin 0.04 · 20 + 2 · 10 · ∫ smoothstep).
    let h = |t: f64| ecef_to_geodetic(&tr.position_ecef[at(t)]).height_m;
    let gain = h(128.0) - h(88.0);
    let expected = 25.0 * 0.04 * (20.0 + 10.0); // small-angle, ±0.03 %
    assert!((gain - expected).abs() < 0.01 * expected, "{gain}");
    // Stopped after the Stop segment.
    assert!(v_ned[at(318.0)].norm() < 1e-12);
    assert!(v_ned[tr.len() - 1].norm() < 1e-12);
}

#[test]
fn ins_closes_on_profiles() {
    for name in ["Profile_2.csv", "Profile_4.csv", "Profile_3.csv"] {
        let path = profile_path(name);
        let tr = Trajectory::from_profile(&path, 100.0).unwrap();
        let c = run_closure(name, &tr);
        assert!(c.position_m < 0.3, "{name}: {} m", c.position_m);
    }
}

#[test]
fn profile_positions_follow_the_file() {
    // The position is integrated from the smoothed, splined velocity; it
    // must stay close to the file's own positions.
    let path = profile_path("Profile_2.csv");
    let tr = Trajectory::from_profile(&path, 100.0).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut worst: f64 = 0.0;
    for (k, line) in text.lines().enumerate().step_by(50) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let r = geodetic_to_ecef(Geodetic::new(v[1].to_radians(), v[2].to_radians(), v[3]));
        assert!((tr.time_s[k] - v[0]).abs() < 1e-9);
        worst = worst.max((tr.position_ecef[k] - r).norm());
    }
    println!("Profile_2: largest distance to the file's positions {worst:.3} m");
    assert!(worst < 0.5, "{worst}");
}

/// A vehicle at rest on the rotating Earth, in closed form: f = −C_e^b g,
/// ω = C_e^b ω_ie.
#[test]
fn ins_closes_at_rest_on_the_rotating_earth() {
    let r = geodetic_to_ecef(Geodetic::new(-0.6, 2.0, 800.0));
    let c = Rotation3::from_euler_angles(0.3, -0.2, 1.1).into_inner();
    let n = 60_001;
    let time: Vec<f64> = (0..n).map(|k| k as f64 * 0.01).collect();
    let f = vec![-c.transpose() * gravity_ecef(&r); n];
    let w = vec![c.transpose() * Vector3::new(0.0, 0.0, OMEGA_IE); n];
    let s0 = NavState {
        position_ecef: r,
        velocity_ecef: Vector3::zeros(),
        c_b_e: c,
    };
    for (label, nav) in [
        ("integrate", ins::integrate(&time, &f, &w, &s0).unwrap()),
        (
            "chained step",
            ins::integrate_steps(&time, &f, &w, &s0).unwrap(),
        ),
    ] {
        let cl = closure(&vec![r; n], &vec![Vector3::zeros(); n], &vec![c; n], &nav);
        println!(
            "at rest 600 s, {label}: |Δr| {:.2e} m, |Δv| {:.2e} m/s, |Δψ| {:.2e} rad",
            cl.position_m, cl.velocity_m_s, cl.attitude_rad
        );
        assert!(cl.position_m < 1e-3 && cl.attitude_rad < 1e-11);
    }
}

/// A circle of radius ρ at constant speed in an arbitrarily tilted plane
/// through a point fixed on the Earth, in closed form:
/// r = r_c + C_p^e ρ (cos Ωt, sin Ωt, 0), body x along the velocity,
/// body z normal to the plane, so ω_eb^b = (0, 0, Ω) and
/// f = C_e^b (a + 2 ω_ie × v − g) with a = −Ω² (r − r_c).
#[test]
fn ins_closes_on_a_closed_form_circle() {
    let centre = geodetic_to_ecef(Geodetic::new(0.9, -1.3, 40.0));
    let c_pe = Rotation3::from_euler_angles(0.05, 0.1, 0.4).into_inner();
    let (rho, omega) = (80.0, 0.2); // 16 m/s, 3.2 m/s² centripetal
    let we = Vector3::new(0.0, 0.0, OMEGA_IE);
    let n = 60_001;
    let mut time = Vec::new();
    let (mut r, mut v, mut c, mut f, mut w) = (vec![], vec![], vec![], vec![], vec![]);
    for k in 0..n {
        let t = k as f64 * 0.01;
        let (s, co) = (omega * t).sin_cos();
        let rt = centre + c_pe * Vector3::new(rho * co, rho * s, 0.0);
        let vt = c_pe * Vector3::new(-rho * omega * s, rho * omega * co, 0.0);
        let at = c_pe * Vector3::new(-rho * omega * omega * co, -rho * omega * omega * s, 0.0);
        let ct = c_pe
            * Rotation3::from_axis_angle(
                &Vector3::z_axis(),
                omega * t + std::f64::consts::FRAC_PI_2,
            )
            .into_inner();
        time.push(t);
        f.push(ct.transpose() * (at + 2.0 * we.cross(&vt) - gravity_ecef(&rt)));
        w.push(Vector3::new(0.0, 0.0, omega) + ct.transpose() * we);
        r.push(rt);
        v.push(vt);
        c.push(ct);
    }
    let s0 = NavState {
        position_ecef: r[0],
        velocity_ecef: v[0],
        c_b_e: c[0],
    };
    for (label, nav) in [
        ("integrate", ins::integrate(&time, &f, &w, &s0).unwrap()),
        (
            "chained step",
            ins::integrate_steps(&time, &f, &w, &s0).unwrap(),
        ),
    ] {
        let cl = closure(&r, &v, &c, &nav);
        println!(
            "circle 600 s, {label}: |Δr| {:.2e} m, |Δv| {:.2e} m/s, |Δψ| {:.2e} rad",
            cl.position_m, cl.velocity_m_s, cl.attitude_rad
        );
        assert!(cl.position_m < 0.1, "{label}: {}", cl.position_m);
    }
}

/// Classic coning: C_b^i(t) = R_x(Ωt) R_y(a) R_x(−Ωt), a rotation by the
/// cone half-angle a about an axis sweeping the y-z plane. Its body rate is
/// ω = Ω (cos a − 1, −sin a sin Ωt, sin a cos Ωt) and the attitude is
/// periodic, while ∫ω_x grows: summing raw angle increments drifts about x.
/// Per interval h (x = Ωh) the missing rotation is ½ sin²a (x − sin x)
/// (½∫α×ω, exact here to O(a⁴)); the (1/12) α_prev × α correction
/// supplies (1/3) sin²a sin²(x/2) sin x of it, leaving ≈ sin²a x⁵/60.
#[test]
fn coning_correction_removes_the_coning_drift() {
    let (a, cone_hz, h): (f64, f64, f64) = (0.05, 5.0, 0.01);
    let omega = 2.0 * std::f64::consts::PI * cone_hz;
    let truth = |t: f64| {
        let ax = Rotation3::from_axis_angle(&Vector3::x_axis(), omega * t);
        (ax * Rotation3::from_axis_angle(&Vector3::y_axis(), a) * ax.inverse()).into_inner()
    };
    let rate = |t: f64| {
        omega
            * Vector3::new(
                a.cos() - 1.0,
                -a.sin() * (omega * t).sin(),
                a.sin() * (omega * t).cos(),
            )
    };
    // The rate formula against the attitude (C^T Ċ = [ω×]) by central differences.
    for t in [0.013, 0.07, 0.151] {
        let m = truth(t).transpose() * (truth(t + 1e-6) - truth(t - 1e-6)) / 2e-6;
        let w = Vector3::new(m[(2, 1)], m[(0, 2)], m[(1, 0)]);
        assert!((w - rate(t)).norm() < 1e-7);
    }
    let increment = |t0: f64, t1: f64| {
        Vector3::new(
            omega * (a.cos() - 1.0) * (t1 - t0),
            a.sin() * ((omega * t1).cos() - (omega * t0).cos()),
            a.sin() * ((omega * t1).sin() - (omega * t0).sin()),
        )
    };
    let n = 1000; // 10 s, 50 cone periods: the truth is back at C(0) = R_y(a)
    let time: Vec<f64> = (0..=n).map(|k| k as f64 * h).collect();
    let da: Vec<_> = time.windows(2).map(|w| increment(w[0], w[1])).collect();
    let dv = vec![Vector3::zeros(); n];
    // INS in ECEF with Earth rotation: the inertial truth seen from ECEF.
    let c_ie = |t: f64| rotation_vector_to_dcm(&Vector3::new(0.0, 0.0, -OMEGA_IE * t));
    let s0 = NavState {
        position_ecef: geodetic_to_ecef(Geodetic::new(0.5, 0.5, 0.0)),
        velocity_ecef: Vector3::zeros(),
        c_b_e: truth(0.0),
    };
    let error_x = |c_ins: &Matrix3<f64>| {
        let c_true = c_ie(time[n]) * truth(time[n]);
        dcm_to_rotation_vector(&(c_true.transpose() * c_ins))
    };
    // Corrected: the library's increment mechanization.
    let corrected = error_x(&ins::integrate_increments(&time, &dv, &da, &s0).unwrap()[n].c_b_e);
    // Uncorrected: the same with coning disabled, written here: C ← E C exp(α).
    let mut c = s0.c_b_e;
    for (k, alpha) in da.iter().enumerate() {
        let e = c_ie(time[k + 1]) * c_ie(time[k]).transpose();
        c = e * c * rotation_vector_to_dcm(alpha);
    }
    let uncorrected = error_x(&c);
    let x = omega * h;
    let s2 = a.sin().powi(2);
    let naive_expected = -0.5 * s2 * (x - x.sin()) * n as f64;
    let residual_expected =
        -(0.5 * s2 * (x - x.sin()) - s2 * (x / 2.0).sin().powi(2) * x.sin() / 3.0) * n as f64;
    println!(
        "coning a = {a} rad at {cone_hz} Hz, h = {h} s, 10 s: uncorrected x error {:.4e} rad (predicted {naive_expected:.4e}), \
         corrected {:.4e} rad (predicted {residual_expected:.4e})",
        uncorrected.x, corrected.x
    );
    assert!((uncorrected.x / naive_expected - 1.0).abs() < 0.01);
    assert!((corrected.x / residual_expected - 1.0).abs() < 0.05);
    assert!(uncorrected.x.abs() > 40.0 * corrected.x.abs());
    // From instantaneous samples, the whole-series integrator (cubic
    // increments + coning) does as well as exact increments. The chained
    // two-sample step cannot: with the rate linear over each interval, the
    // trapezoid shortens the rotating (y, z) rate by x²/12, which shrinks
    // the cone and drifts as much as its dt²/12 ω₀×ω₁ term corrects, so it
    // is left at about the uncorrected drift (printed, not a requirement).
    let w: Vec<_> = time.iter().map(|&t| rate(t)).collect();
    let f = vec![Vector3::zeros(); n + 1];
    let sampled = error_x(&ins::integrate(&time, &f, &w, &s0).unwrap()[n].c_b_e);
    let chained = error_x(&ins::integrate_steps(&time, &f, &w, &s0).unwrap()[n].c_b_e);
    println!(
        "coning from samples: integrate x error {:.4e} rad, chained step {:.4e} rad",
        sampled.x, chained.x
    );
    // The cubic increments shorten the rotating rate by ~(11/720) x⁴,
    // which adds a drift of that relative size: still 20× below uncorrected.
    assert!(uncorrected.x.abs() > 20.0 * sampled.norm());
}

#[test]
fn random_trajectories_respect_their_limits_and_are_smooth() {
    let config = RandomTrajectoryConfig {
        duration_s: 300.0,
        ..Default::default()
    };
    for seed in 0..4 {
        let tr = Trajectory::random(&config, &mut stream(seed, 7)).unwrap();
        let dt = 0.01;
        let (mut speed, mut lateral, mut longitudinal, mut tilt) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        let (mut df, mut dw, mut ddf, mut ddw) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        let euler = tr.euler_ned();
        for k in 1..tr.len() - 1 {
            speed = speed.max(tr.velocity_ecef[k].norm());
            // Acceleration relative to the Earth by central differences, in body axes.
            let a_b = tr.c_b_e[k].transpose() * (tr.velocity_ecef[k + 1] - tr.velocity_ecef[k - 1])
                / (2.0 * dt);
            lateral = lateral.max(a_b.y.abs());
            longitudinal = longitudinal.max(a_b.x.abs());
            tilt = tilt.max(euler[k].x.abs()).max(euler[k].y.abs());
            df = df.max((tr.specific_force_b[k + 1] - tr.specific_force_b[k]).norm());
            dw = dw.max((tr.angular_rate_b[k + 1] - tr.angular_rate_b[k]).norm());
            let (f, w) = (&tr.specific_force_b, &tr.angular_rate_b);
            ddf = ddf.max((f[k + 1] - 2.0 * f[k] + f[k - 1]).norm());
            ddw = ddw.max((w[k + 1] - 2.0 * w[k] + w[k - 1]).norm());
        }
        println!(
            "seed {seed}: max speed {speed:.2} m/s, lateral {lateral:.2} m/s², longitudinal {longitudinal:.2} m/s², \
             roll/pitch {:.2}°, largest step in f {df:.2e} m/s², in ω {dw:.2e} rad/s, \
             second differences {ddf:.2e}, {ddw:.2e}",
            tilt.to_degrees()
        );
        assert!(speed <= 30.0 + 1e-9 && speed > 10.0);
        assert!(lateral <= 3.0 * 1.01 && lateral > 0.5, "{lateral}");
        assert!(longitudinal <= 2.0 * 1.03, "{longitudinal}");
        assert!(tilt < 0.1);
        // Continuous f and ω: sample-to-sample steps no larger than a
        // bounded jerk (< 10 m/s³) and angular acceleration (< 1 rad/s²)
        // allow, and second differences of order dt² (a jump of size J
        // would show as a second difference of J).
        assert!(df < 0.1 && dw < 0.01, "{df} {dw}");
        assert!(ddf < 2e-3 && ddw < 1e-3, "{ddf} {ddw}");
    }
}

#[test]
fn stationary_start_is_at_rest() {
    let config = RandomTrajectoryConfig {
        duration_s: 60.0,
        stationary_start_s: 20.0,
        ..Default::default()
    };
    let tr = Trajectory::random(&config, &mut stream(3, 0)).unwrap();
    for k in [0, 1000, 2000] {
        assert!(tr.velocity_ecef[k].norm() < 1e-12);
        let f_e = tr.c_b_e[k] * tr.specific_force_b[k];
        assert!((f_e + gravity_ecef(&tr.position_ecef[k])).norm() < 1e-9);
    }
    assert!(tr.velocity_ecef[6000].norm() > 1.0);
}

#[test]
fn random_trajectories_are_reproducible_from_the_seed() {
    let config = RandomTrajectoryConfig {
        duration_s: 30.0,
        ..Default::default()
    };
    let a = Trajectory::random(&config, &mut stream(11, 2)).unwrap();
    let b = Trajectory::random(&config, &mut stream(11, 2)).unwrap();
    let c = Trajectory::random(&config, &mut stream(11, 3)).unwrap();
    assert_eq!(a, b);
    assert_ne!(a.position_ecef, c.position_ecef);
    assert_eq!(a.position_ecef[0], geodetic_to_ecef(config.origin));
}

#[test]
fn bad_inputs_name_the_argument() {
    let starts = |e: Error, prefix: &str| {
        let text = e.to_string();
        assert!(
            text.starts_with(prefix),
            "{text} should start with {prefix}"
        );
    };
    let s0 = NavState {
        position_ecef: geodetic_to_ecef(Geodetic::new(0.1, 0.2, 0.0)),
        velocity_ecef: Vector3::zeros(),
        c_b_e: Matrix3::identity(),
    };
    let z = vec![Vector3::zeros(); 3];
    let t = [0.0, 0.01, 0.02];
    starts(
        ins::integrate(&[0.0, 0.01, 0.01], &z, &z, &s0).unwrap_err(),
        "time:",
    );
    starts(ins::integrate(&[], &[], &[], &s0).unwrap_err(), "time:");
    starts(
        ins::integrate(&t, &z[..2], &z, &s0).unwrap_err(),
        "specific_force:",
    );
    let mut nan = z.clone();
    nan[1].y = f64::NAN;
    starts(
        ins::integrate(&t, &z, &nan, &s0).unwrap_err(),
        "angular_rate: row 1",
    );
    let bad = NavState {
        c_b_e: euler_to_dcm(0.1, 0.2, 0.3) * 1.01,
        ..s0
    };
    starts(ins::integrate(&t, &z, &z, &bad).unwrap_err(), "attitude:");
    let bad = NavState {
        velocity_ecef: Vector3::new(f64::INFINITY, 0.0, 0.0),
        ..s0
    };
    starts(
        ins::integrate(&t, &z, &z, &bad).unwrap_err(),
        "velocity_ecef:",
    );
    starts(
        ins::integrate_increments(&t, &z, &z[..2], &s0).unwrap_err(),
        "delta_velocity:",
    );
    starts(
        ins::integrate_increments(&t, &nan[..2], &z[..2], &s0).unwrap_err(),
        "delta_velocity: row 1",
    );
    starts(
        ins::increments_from_samples(&[0.0], &z[..1], &z[..1]).unwrap_err(),
        "time:",
    );

    let mut rng = stream(0, 0);
    for (config, prefix) in [
        (
            RandomTrajectoryConfig {
                duration_s: 0.0,
                ..Default::default()
            },
            "duration:",
        ),
        (
            RandomTrajectoryConfig {
                duration_s: -5.0,
                ..Default::default()
            },
            "duration:",
        ),
        (
            RandomTrajectoryConfig {
                rate_hz: 0.0,
                ..Default::default()
            },
            "rate:",
        ),
        (
            RandomTrajectoryConfig {
                rate_hz: f64::NAN,
                ..Default::default()
            },
            "rate:",
        ),
        (
            RandomTrajectoryConfig {
                max_speed_m_s: -1.0,
                ..Default::default()
            },
            "max_speed:",
        ),
        (
            RandomTrajectoryConfig {
                origin: Geodetic::new(1.6, 0.0, 0.0),
                ..Default::default()
            },
            "origin:",
        ),
        (
            RandomTrajectoryConfig {
                stationary_start_s: -1.0,
                ..Default::default()
            },
            "stationary_start:",
        ),
    ] {
        starts(Trajectory::random(&config, &mut rng).unwrap_err(), prefix);
    }
    let origin = Geodetic::new(0.7, 0.0, 0.0);
    starts(
        Trajectory::from_segments(origin, 0.0, &[], 100.0).unwrap_err(),
        "segments:",
    );
    starts(
        Trajectory::from_segments(
            origin,
            0.0,
            &[
                Segment::Cruise { duration_s: 1.0 },
                Segment::Turn {
                    duration_s: 0.0,
                    heading_change_rad: 1.0,
                },
            ],
            100.0,
        )
        .unwrap_err(),
        "segments[1].duration_s:",
    );
    starts(
        Trajectory::from_segments(
            origin,
            0.0,
            &[Segment::Accelerate {
                duration_s: 1.0,
                target_speed_m_s: -2.0,
            }],
            100.0,
        )
        .unwrap_err(),
        "segments[0].target_speed_m_s:",
    );
    starts(
        Trajectory::from_segments(origin, 0.0, &[Segment::Cruise { duration_s: 1.0 }], -1.0)
            .unwrap_err(),
        "rate:",
    );
}

#[test]
fn bad_profiles_name_the_file_and_line() {
    let dir = std::env::temp_dir().join(format!("memsnav-ins-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let good = "0,51,0,10,0,1,0,0,0,0\n0.01,51,0.0000001,10,0,1,0,0,0,0\n0.02,51,0.0000002,10,0,1,0,0,0,0\n";
    let cases = [
        (
            "truncated.csv",
            format!("{good}0.03,51,0.0000003,10,0,1"),
            4,
            "expected 10",
        ),
        (
            "garbage.csv",
            format!("{good}0.03,51,abc,10,0,1,0,0,0,0\n"),
            4,
            "column 3",
        ),
        (
            "backwards.csv",
            format!("{good}0.015,51,0,10,0,1,0,0,0,0\n"),
            4,
            "does not follow",
        ),
        ("short.csv", good.to_string(), 3, "at least 4 rows"),
    ];
    for (name, text, line, reason) in cases {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        match Trajectory::from_profile(&path, 100.0).unwrap_err() {
            Error::Parse {
                file,
                line: l,
                reason: r,
            } => {
                assert!(
                    file.ends_with(name) && l == line && r.contains(reason),
                    "{file}:{l}: {r}"
                );
            }
            e => panic!("{name}: {e}"),
        }
    }
    let missing = dir.join("missing.csv");
    assert!(matches!(
        Trajectory::from_profile(&missing, 100.0).unwrap_err(),
        Error::Io { .. }
    ));
    let path = dir.join("ok.csv");
    std::fs::write(&path, format!("{good}0.03,51,0.0000003,10,0,1,0,0,0,0\n")).unwrap();
    assert!(Trajectory::from_profile(&path, 0.0)
        .unwrap_err()
        .to_string()
        .starts_with("rate:"));
    assert_eq!(Trajectory::from_profile(&path, 100.0).unwrap().len(), 4);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_hand_built_vehicle_motion_matches_its_segments() {
    use memsnav_core::trajectory::VehicleMotion;
    let origin = Geodetic::new(0.7, 0.1, 20.0);
    let mut m = VehicleMotion::at_rest(1.0);
    m.speed_m_s.ramp_to(10.0, 12.0);
    m.speed_m_s.hold(10.0);
    m.yaw_rate_rad_s.hold(10.0);
    m.yaw_rate_rad_s.ramp_to(2.5, 0.2);
    m.yaw_rate_rad_s.hold(5.0);
    m.yaw_rate_rad_s.ramp_to(2.5, 0.0);
    let hand = Trajectory::from_vehicle_motion(&m, origin, 20.0, 50.0).unwrap();
    let scripted = Trajectory::from_segments(
        origin,
        1.0,
        &[
            Segment::Accelerate {
                duration_s: 10.0,
                target_speed_m_s: 12.0,
            },
            Segment::Turn {
                duration_s: 10.0,
                heading_change_rad: 0.2 * 7.5,
            },
        ],
        50.0,
    )
    .unwrap();
    assert_eq!(hand.len(), 1001);
    for k in 0..hand.len() {
        assert!((hand.position_ecef[k] - scripted.position_ecef[k]).norm() < 1e-6);
        assert!((hand.angular_rate_b[k] - scripted.angular_rate_b[k]).norm() < 1e-12);
    }
    assert!(Trajectory::from_vehicle_motion(&m, origin, 0.0, 50.0).is_err());
}

#[test]
fn increments_of_the_first_interval_need_no_history() {
    // A constant rotation rate with constant specific force along the
    // axis: no coning, no sculling; the first step must equal the exact
    // rotation (the zero "previous" increments add nothing).
    let w = Vector3::new(0.2, -0.1, 0.3);
    let inc = ImuIncrement {
        delta_velocity_b: Vector3::zeros(),
        delta_angle_b: w * 0.01,
    };
    let s0 = NavState {
        position_ecef: geodetic_to_ecef(Geodetic::new(0.3, 0.0, 0.0)),
        velocity_ecef: Vector3::zeros(),
        c_b_e: Matrix3::identity(),
    };
    let s1 = ins::step_increments(&s0, &ImuIncrement::default(), &inc, 0.01);
    let expected = rotation_vector_to_dcm(&Vector3::new(0.0, 0.0, -OMEGA_IE * 0.01))
        * rotation_vector_to_dcm(&(w * 0.01));
    assert!((s1.c_b_e - expected).abs().max() < 1e-15);
}
