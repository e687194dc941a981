//! Shared pieces of the coupled-filter integration tests: a simulated
//! land-vehicle drive whose truth is the INS itself on error-free samples,
//! its GNSS measurements, IMU specs and initial states.

#![allow(dead_code)]

use memsnav_core::attitude::dcm_to_rotation_vector;
use memsnav_core::coupling::{InitialState, InitialUncertainty};
use memsnav_core::geodesy::wgs84::EARTH_RATE_RAD_S;
use memsnav_core::geodesy::{c_n_e, ecef_to_geodetic, geodetic_to_ecef, gravity_ecef, Geodetic};
use memsnav_core::gnss::{
    self, Constellation, GnssEpoch, ReceiverTrack, SimulationConfig, WalkerConfig,
};
use memsnav_core::ins::ImuData;
use memsnav_core::ins::{self, ImuSample, NavState};
use memsnav_core::random::Rng;
use memsnav_core::sensors::{AccelerometerSpec, GyroscopeSpec, ImuModel, ImuSpec, NoiseModel};
use nalgebra::{SVector, Vector3};
use rand::Rng as _;
use rand_distr::StandardNormal;

pub struct Truth {
    pub time_s: Vec<f64>,
    pub nav: Vec<NavState>,
    pub f_b: Vec<Vector3<f64>>,
    pub w_b: Vec<Vector3<f64>>,
}

pub fn origin() -> Vector3<f64> {
    geodetic_to_ecef(Geodetic::new(
        43.6_f64.to_radians(),
        1.44_f64.to_radians(),
        150.0,
    ))
}

/// A land-vehicle drive at `rate_hz`: 12 m/s heading north-east, weaving
/// turns and speed changes (`moving = false`: parked).
pub fn drive(duration_s: f64, rate_hz: f64, moving: bool) -> Truth {
    let n = (duration_s * rate_hz).round() as usize + 1;
    let dt = 1.0 / rate_hz;
    let r0 = origin();
    let geo = ecef_to_geodetic(&r0);
    let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
    let yaw0 = 0.8_f64;
    let c0 = cne * memsnav_core::attitude::euler_to_dcm(0.0, 0.0, yaw0);
    let speed = if moving { 12.0 } else { 0.0 };
    let v0 = cne * Vector3::new(yaw0.cos(), yaw0.sin(), 0.0) * speed;
    let wie = Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S);
    let sample = |t: f64, s: &NavState| {
        let (yaw_rate, along) = if moving {
            (
                0.12 * (2.0 * std::f64::consts::PI * t / 40.0).sin(),
                0.4 * (2.0 * std::f64::consts::PI * t / 55.0).sin(),
            )
        } else {
            (0.0, 0.0)
        };
        let w_eb_b = Vector3::new(0.0, 0.0, yaw_rate);
        let v = s.velocity_ecef;
        let along_e = if v.norm() > 0.1 {
            v.normalize() * along
        } else {
            Vector3::zeros()
        };
        let a_e = (s.c_b_e * w_eb_b).cross(&v) + along_e;
        let f_e = a_e - gravity_ecef(&s.position_ecef) + 2.0 * wie.cross(&v);
        ImuSample {
            specific_force_b: s.c_b_e.transpose() * f_e,
            angular_rate_b: s.c_b_e.transpose() * wie + w_eb_b,
        }
    };
    // Pass 1: the samples, from an approximately propagated state.
    let mut s = NavState {
        position_ecef: r0,
        velocity_ecef: v0,
        c_b_e: c0,
    };
    let mut samples = Vec::with_capacity(n);
    for k in 0..n {
        let smp = sample(k as f64 * dt, &s);
        samples.push(smp);
        s = ins::step(&s, &smp, &smp, dt);
    }
    // Pass 2: the truth is the INS on these samples.
    let mut s = NavState {
        position_ecef: r0,
        velocity_ecef: v0,
        c_b_e: c0,
    };
    let mut nav = Vec::with_capacity(n);
    nav.push(s);
    for k in 1..n {
        s = ins::step(&s, &samples[k - 1], &samples[k], dt);
        nav.push(s);
    }
    Truth {
        time_s: (0..n).map(|k| k as f64 * dt).collect(),
        nav,
        f_b: samples.iter().map(|s| s.specific_force_b).collect(),
        w_b: samples.iter().map(|s| s.angular_rate_b).collect(),
    }
}

pub fn gnss_for(truth: &Truth, config: &SimulationConfig, rng: &mut Rng) -> Vec<GnssEpoch> {
    let sky = Constellation::walker(&WalkerConfig::default()).unwrap();
    gnss_from(truth, &sky, config, rng)
}

/// The measurements of `sky`'s satellites along the truth.
pub fn gnss_from(
    truth: &Truth,
    sky: &Constellation,
    config: &SimulationConfig,
    rng: &mut Rng,
) -> Vec<GnssEpoch> {
    let pos: Vec<_> = truth.nav.iter().map(|s| s.position_ecef).collect();
    let vel: Vec<_> = truth.nav.iter().map(|s| s.velocity_ecef).collect();
    gnss::simulate(
        &ReceiverTrack {
            time_s: &truth.time_s,
            position_ecef: &pos,
            velocity_ecef: &vel,
        },
        sky,
        config,
        rng,
    )
    .unwrap()
}

/// An IMU spec with biases and white noise only: the errors the 17-state
/// filter models exactly.
pub fn bias_and_noise_spec(
    accel_bias: f64,
    gyro_bias: f64,
    accel_density: f64,
    gyro_density: f64,
) -> ImuSpec {
    ImuSpec {
        accelerometer: AccelerometerSpec {
            bias_std: accel_bias,
            noise: NoiseModel {
                white_density: accel_density,
                ..Default::default()
            },
            ..Default::default()
        },
        gyroscope: GyroscopeSpec {
            bias_std: gyro_bias,
            noise: NoiseModel {
                white_density: gyro_density,
                ..Default::default()
            },
            ..Default::default()
        },
    }
}

pub fn n3(rng: &mut Rng) -> Vector3<f64> {
    Vector3::new(
        rng.sample(StandardNormal),
        rng.sample(StandardNormal),
        rng.sample(StandardNormal),
    )
}

pub fn readings(
    truth: &Truth,
    imu: &ImuModel,
    rng: &mut Rng,
) -> (Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
    let r = imu.measure(&truth.f_b, &truth.w_b, rng).unwrap();
    (r.specific_force_b, r.angular_rate_b)
}

/// The IMU series the filters read: the truth's times with readings `f`, `w`.
pub fn imu_data<'a>(truth: &'a Truth, f: &'a [Vector3<f64>], w: &'a [Vector3<f64>]) -> ImuData<'a> {
    ImuData {
        time_s: &truth.time_s,
        specific_force_b: f,
        angular_rate_b: w,
        increments: None,
    }
}

pub fn exact_initial(truth: &Truth) -> InitialState {
    InitialState {
        nav: truth.nav[0],
        accel_bias_m_s2: Vector3::zeros(),
        gyro_bias_rad_s: Vector3::zeros(),
        clock_offset_m: None,
        clock_drift_m_s: None,
    }
}

/// The true state perturbed by a draw from P₀ (so NEES starts consistent).
pub fn perturbed_initial(truth: &Truth, std: &InitialUncertainty, rng: &mut Rng) -> InitialState {
    let s = truth.nav[0];
    let geo = ecef_to_geodetic(&s.position_ecef);
    let cne = c_n_e(geo.latitude_rad, geo.longitude_rad);
    let psi = cne * n3(rng).component_mul(&std.attitude_ned_rad);
    InitialState {
        nav: NavState {
            position_ecef: s.position_ecef + n3(rng) * std.position_m,
            velocity_ecef: s.velocity_ecef + n3(rng) * std.velocity_m_s,
            c_b_e: memsnav_core::attitude::rotation_vector_to_dcm(&psi) * s.c_b_e,
        },
        accel_bias_m_s2: Vector3::zeros(),
        gyro_bias_rad_s: Vector3::zeros(),
        clock_offset_m: None,
        clock_drift_m_s: None,
    }
}

/// (ψ, δv, δr) of a solution against the truth.
pub fn nav_error(est: &NavState, truth: &NavState) -> SVector<f64, 9> {
    let psi = dcm_to_rotation_vector(&(est.c_b_e * truth.c_b_e.transpose()));
    let mut e = SVector::<f64, 9>::zeros();
    e.fixed_rows_mut::<3>(0).copy_from(&psi);
    e.fixed_rows_mut::<3>(3)
        .copy_from(&(est.velocity_ecef - truth.velocity_ecef));
    e.fixed_rows_mut::<3>(6)
        .copy_from(&(est.position_ecef - truth.position_ecef));
    e
}
