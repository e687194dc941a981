//! Trajectories with exact IMU truth (method §5, "Trajectory generation").
//!
//! A motion is described in the local navigation frame: the NED velocity
//! and its derivative, and the body's roll, pitch and yaw and their rates,
//! as smooth (C²) functions of time. The geodetic position is integrated
//! from the velocity (RK4 on Groves eq. 2.111 / 5.56), and the IMU truth
//! follows by inverse mechanization in ECEF:
//!
//! - ω_ib^b = ω_nb^b + C_n^b ω_en^n + C_e^b ω_ie^e (Groves eq. 2.48 chain,
//!   transport rate eq. 5.44, Euler-rate kinematics eq. 2.56),
//! - f_ib^b = C_e^b (a_eb^e + 2 Ω_ie v_eb^e − g^e(r)) with
//!   g = γ − Ω_ie Ω_ie r from [`crate::geodesy::gravity_ecef`] (Groves
//!   eq. 5.36 solved for f), a_eb^e = C_n^e (v̇^n + ω_en^n × v^n).
//!
//! So an INS using the same gravity model and fed this truth reproduces the
//! trajectory to its own integration accuracy.

mod profile;
mod random;
mod segments;
mod smooth;
mod spline;
mod vehicle;

use nalgebra::{Matrix3, Vector3};

use crate::attitude::dcm_to_euler;
#[cfg(doc)]
use crate::attitude::euler_to_dcm;
use crate::geodesy::wgs84::{ECCENTRICITY_SQUARED as E2, SEMI_MAJOR_AXIS_M as A};
use crate::geodesy::{
    c_n_e, c_n_e_with, ecef_to_geodetic, geodetic_to_ecef_with, gravity_ecef,
    wgs84::EARTH_RATE_RAD_S, Geodetic,
};
#[cfg(doc)]
use crate::geodesy::{meridian_radius, transverse_radius};
use crate::ins::{ImuSample, NavState};
use crate::{validate, Error, Result};

pub use profile::PROFILE_KNOT_SPACING_S;
pub use random::RandomTrajectoryConfig;
pub use segments::Segment;
pub use smooth::{SignalValue, SmoothSignal};
pub use vehicle::{VehicleMotion, PITCH_PER_LONGITUDINAL_ACCEL, ROLL_PER_LATERAL_ACCEL};

/// Truth at the IMU rate: the vehicle's position, velocity and attitude and
/// what an ideal IMU on it measures.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Sample times, s, strictly increasing.
    pub time_s: Vec<f64>,
    /// r_eb^e, m.
    pub position_ecef: Vec<Vector3<f64>>,
    /// v_eb^e, m/s.
    pub velocity_ecef: Vec<Vector3<f64>>,
    /// C_b^e, body to ECEF.
    pub c_b_e: Vec<Matrix3<f64>>,
    /// f_ib^b, m/s² (specific force).
    pub specific_force_b: Vec<Vector3<f64>>,
    /// ω_ib^b, rad/s.
    pub angular_rate_b: Vec<Vector3<f64>>,
}

/// The local-level description of a motion at one instant.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LocalMotion {
    /// v_eb^n, m/s.
    pub velocity_ned: Vector3<f64>,
    /// d/dt of the NED components of v_eb^n, m/s².
    pub velocity_ned_rate: Vector3<f64>,
    /// Roll, pitch, yaw of C_b^n, rad.
    pub euler_rad: Vector3<f64>,
    /// Their time derivatives, rad/s.
    pub euler_rate_rad_s: Vector3<f64>,
    /// `euler_rad.z.sin_cos()` (the motion often has it already).
    pub yaw_sin_cos: (f64, f64),
}

/// A motion the generator samples at non-decreasing times.
pub(crate) trait Motion {
    /// Lookup state kept between calls (start: `Default`), so that
    /// sampling at non-decreasing times costs O(1) per call. Any time may
    /// be asked; the values never depend on the cursor.
    type Cursor: Default;
    fn at(&self, t_s: f64, cursor: &mut Self::Cursor) -> LocalMotion;
    /// Only the NED velocity (the position integration needs no more),
    /// bitwise equal to `at(t_s).velocity_ned`.
    fn velocity_ned(&self, t_s: f64, cursor: &mut Self::Cursor) -> Vector3<f64>;
}

/// `x.sin_cos()` with the last argument and result kept: an angle that
/// holds still between calls (the path angle on a constant slope, the
/// heading, roll and pitch while driving straight at constant speed) is
/// not evaluated again. Keyed on the argument's bits, so the result is
/// bitwise that of `sin_cos`.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SinCosMemo {
    last: Option<(u64, (f64, f64))>,
}

impl SinCosMemo {
    #[inline]
    pub fn sin_cos(&mut self, x: f64) -> (f64, f64) {
        match self.last {
            Some((bits, sc)) if bits == x.to_bits() => sc,
            _ => {
                let sc = x.sin_cos();
                self.last = Some((x.to_bits(), sc));
                sc
            }
        }
    }
}

/// Longest RK4 sub-step of the position integration, s: keeps the
/// truncation error far below a millimetre whatever the output rate.
const MAX_POSITION_STEP_S: f64 = 0.01;

/// Most samples a trajectory may have (guards against absurd requests).
const MAX_SAMPLES: usize = crate::limits::MAX_SAMPLES;

/// The radii of curvature R_N, R_E (Groves eq. 2.105-2.106) from sin φ,
/// the same arithmetic as [`meridian_radius`] and [`transverse_radius`].
fn radii(sin_lat: f64) -> (f64, f64) {
    let e = 1.0 - E2 * sin_lat.powi(2);
    let root = e.sqrt();
    (A * (1.0 - E2) / (e * root), A / root)
}

/// d(lat, lon, h)/dt from the NED velocity (Groves eq. 2.111), given the
/// radii and cos φ at the point.
fn geodetic_rate_with(
    (r_n, r_e): (f64, f64),
    cos_lat: f64,
    h: f64,
    v_ned: &Vector3<f64>,
) -> Vector3<f64> {
    Vector3::new(
        v_ned.x / (r_n + h),
        v_ned.y / ((r_e + h) * cos_lat),
        -v_ned.z,
    )
}

/// The expansion of one sample's RK4 stages about the sample's latitude
/// φ₀: sin φ and cos φ by their Taylor series to second order, and the
/// radii R_N, R_E too, so a stage needs no square root and no division
/// for them. With q = e² sin φ cos φ / W², W² = 1 − e² sin² φ:
/// R_E' = q R_E, R_N' = 3 q R_N, q' = e² (cos² φ − sin² φ) / W² + 2 q²,
/// R_E'' = (q² + q') R_E, R_N'' = 3 (3 q² + q') R_N. The stages are within
/// ~1e-7 rad of the sample (5e-7 at 300 m/s), where the neglected
/// third-order terms (< 1e-21 relative for the sines, < 1e-20 m for the
/// radii) are far below the rounding of the functions themselves.
struct StageExpansion {
    lat0: f64,
    sin_cos: (f64, f64),
    /// R_N and R_E at φ₀, their first derivatives and half their second.
    r_n: [f64; 3],
    r_e: [f64; 3],
}

impl StageExpansion {
    fn new(lat0: f64, (s0, c0): (f64, f64), (r_n, r_e): (f64, f64)) -> Self {
        let w2 = 1.0 - E2 * s0 * s0;
        let q = E2 * s0 * c0 / w2;
        let dq = E2 * (c0 * c0 - s0 * s0) / w2 + 2.0 * q * q;
        Self {
            lat0,
            sin_cos: (s0, c0),
            r_n: [r_n, 3.0 * q * r_n, 1.5 * (3.0 * q * q + dq) * r_n],
            r_e: [r_e, q * r_e, 0.5 * (q * q + dq) * r_e],
        }
    }

    /// d(lat, lon, h)/dt from the NED velocity (Groves eq. 2.111) at `g`.
    #[inline]
    fn geodetic_rate(&self, g: &Vector3<f64>, v_ned: &Vector3<f64>) -> Vector3<f64> {
        let (s0, c0) = self.sin_cos;
        let d = g.x - self.lat0;
        let h2 = 0.5 * d * d;
        let cos_lat = c0 - (s0 * d + c0 * h2);
        let radius = |r: &[f64; 3]| r[0] + d * (r[1] + d * r[2]);
        geodetic_rate_with((radius(&self.r_n), radius(&self.r_e)), cos_lat, g.z, v_ned)
    }
}

/// Euler-angle rates → ω_nb^b for C_b^n = R_z(ψ) R_y(θ) R_x(φ) (Groves
/// eq. 2.56 inverted), given the sines and cosines of roll and pitch.
fn body_rate_from_euler(
    (sr, cr): (f64, f64),
    (sp, cp): (f64, f64),
    rate: &Vector3<f64>,
) -> Vector3<f64> {
    Vector3::new(
        rate.x - rate.z * sp,
        rate.y * cr + rate.z * sr * cp,
        -rate.y * sr + rate.z * cr * cp,
    )
}

/// C_b^n = R_z(ψ) R_y(θ) R_x(φ) from the sines and cosines of roll, pitch
/// and yaw: the arithmetic of [`euler_to_dcm`] (nalgebra's
/// `Rotation3::from_euler_angles`) without its three `sin_cos`.
fn euler_dcm((sr, cr): (f64, f64), (sp, cp): (f64, f64), (sy, cy): (f64, f64)) -> Matrix3<f64> {
    Matrix3::new(
        cy * cp,
        cy * sp * sr - sy * cr,
        cy * sp * cr + sy * sr,
        sy * cp,
        sy * sp * sr + cy * cr,
        sy * sp * cr - cy * sr,
        -sp,
        cp * sr,
        cp * cr,
    )
}

/// The NED velocity of a motion with the last value kept: the RK4 stages
/// ask for the end of one sub-step and the start of the next at the same
/// time (bitwise), and the sample's own velocity is the first stage's.
struct VelocityMemo<'a, M: Motion> {
    motion: &'a M,
    cursor: M::Cursor,
    last: Option<(f64, Vector3<f64>)>,
}

impl<M: Motion> VelocityMemo<'_, M> {
    fn at(&mut self, t_s: f64) -> Vector3<f64> {
        match self.last {
            Some((t, v)) if t.to_bits() == t_s.to_bits() => v,
            _ => {
                let v = self.motion.velocity_ned(t_s, &mut self.cursor);
                self.last = Some((t_s, v));
                v
            }
        }
    }
}

/// Builds the truth of `motion` at `time_s`, starting at `origin`.
///
/// Every trigonometric value is computed once per point and shared
/// (latitude and longitude by the radii, C_n^e and the position; roll,
/// pitch and yaw by C_b^n and the Euler-rate kinematics), the RK4 stages
/// take sin and cos of their latitude and the radii of curvature from the
/// sample's by a second-order Taylor step ([`StageExpansion`]), R_N uses
/// e·√e for e^1.5, the
/// motion is looked up by cursors, and repeated motion requests are served
/// from memos (the motion at the end of a sample's last RK4 sub-step, when
/// that is the next sample's time, is the next sample's motion). The
/// output agrees with the plain evaluation of the formulas to ~1e-17
/// relative (tests/test_simulator_reference.py: 1e-12). Angles that hold
/// still between samples (roll, pitch; the motion's path angle and
/// heading) reuse their sine and cosine ([`SinCosMemo`]), bitwise.
pub(crate) fn build<M: Motion>(motion: &M, origin: Geodetic, time_s: Vec<f64>) -> Trajectory {
    let n = time_s.len();
    let mut out = Trajectory {
        position_ecef: Vec::with_capacity(n),
        velocity_ecef: Vec::with_capacity(n),
        c_b_e: Vec::with_capacity(n),
        specific_force_b: Vec::with_capacity(n),
        angular_rate_b: Vec::with_capacity(n),
        time_s: Vec::new(),
    };
    let omega_ie = Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S);
    let mut geodetic = Vector3::new(origin.latitude_rad, origin.longitude_rad, origin.height_m);
    let mut cursor = M::Cursor::default();
    let mut velocity = VelocityMemo {
        motion,
        cursor: M::Cursor::default(),
        last: None,
    };
    // The motion at the next sample when the last RK4 sub-step ended
    // exactly (bitwise) on it, as it does whenever there is one sub-step.
    let mut next: Option<LocalMotion> = None;
    let (mut roll_memo, mut pitch_memo) = (SinCosMemo::default(), SinCosMemo::default());
    for k in 0..n {
        let t = time_s[k];
        let m = match next.take() {
            Some(m) => m,
            None => motion.at(t, &mut cursor),
        };
        let (lat, h) = (geodetic.x, geodetic.z);
        let (sin_lat, cos_lat) = lat.sin_cos();
        let (sin_lon, cos_lon) = geodetic.y.sin_cos();
        let (r_n, r_e) = radii(sin_lat);
        let rate = geodetic_rate_with((r_n, r_e), cos_lat, h, &m.velocity_ned);
        // Transport rate ω_en^n (Groves eq. 5.44).
        let omega_en_n = Vector3::new(rate.y * cos_lat, -rate.x, -rate.y * sin_lat);
        let c_ne = c_n_e_with((sin_lat, cos_lat), (sin_lon, cos_lon));
        let r = geodetic_to_ecef_with((sin_lat, cos_lat), (sin_lon, cos_lon), r_e, h);
        let v = c_ne * m.velocity_ned;
        let a = c_ne * (m.velocity_ned_rate + omega_en_n.cross(&m.velocity_ned));
        let roll = roll_memo.sin_cos(m.euler_rad.x);
        let pitch = pitch_memo.sin_cos(m.euler_rad.y);
        let c_bn = euler_dcm(roll, pitch, m.yaw_sin_cos);
        let c_be = c_ne * c_bn;
        let c_eb = c_be.transpose();
        let omega_nb_b = body_rate_from_euler(roll, pitch, &m.euler_rate_rad_s);
        let omega_ib_b = omega_nb_b + c_bn.transpose() * omega_en_n + c_eb * omega_ie;
        let f_ib_b = c_eb * (a + 2.0 * omega_ie.cross(&v) - gravity_ecef(&r));
        out.position_ecef.push(r);
        out.velocity_ecef.push(v);
        out.c_b_e.push(c_be);
        out.specific_force_b.push(f_ib_b);
        out.angular_rate_b.push(omega_ib_b);
        if k + 1 < n {
            // RK4 on the geodetic position, sub-stepped. The first stage of
            // the first sub-step is the sample's own rate (t + 0·dt = t).
            let span = time_s[k + 1] - t;
            let steps = (span / MAX_POSITION_STEP_S).ceil().max(1.0) as usize;
            let dt = span / steps as f64;
            velocity.last = Some((t, m.velocity_ned));
            let expansion = StageExpansion::new(lat, (sin_lat, cos_lat), (r_n, r_e));
            for j in 0..steps {
                let t0 = t + j as f64 * dt;
                let near = |g: &Vector3<f64>, v: &Vector3<f64>| expansion.geodetic_rate(g, v);
                let k1 = if j == 0 {
                    rate
                } else {
                    near(&geodetic, &velocity.at(t0))
                };
                let vm = velocity.at(t0 + 0.5 * dt);
                let k2 = near(&(geodetic + 0.5 * dt * k1), &vm);
                let k3 = near(&(geodetic + 0.5 * dt * k2), &vm);
                let t1 = t0 + dt;
                let v1 = if j + 1 == steps && t1.to_bits() == time_s[k + 1].to_bits() {
                    let m1 = motion.at(t1, &mut cursor);
                    next = Some(m1);
                    m1.velocity_ned
                } else {
                    velocity.at(t1)
                };
                let k4 = near(&(geodetic + dt * k3), &v1);
                geodetic += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            }
        }
    }
    out.time_s = time_s;
    out
}

/// `duration_s · rate_hz + 1` sample times from 0, validated.
pub(crate) fn time_grid(start_s: f64, duration_s: f64, rate_hz: f64) -> Result<Vec<f64>> {
    validate::positive("duration", duration_s)?;
    validate::positive("rate", rate_hz)?;
    // The position is integrated every MAX_POSITION_STEP_S whatever the
    // rate: the duration bounds that work.
    crate::limits::duration("duration", duration_s)?;
    let intervals = (duration_s * rate_hz + 1e-9).floor();
    if intervals < 1.0 {
        return Err(Error::invalid(
            "rate",
            format!("{rate_hz} Hz gives no sample interval within {duration_s} s"),
        ));
    }
    if intervals >= MAX_SAMPLES as f64 {
        return Err(Error::invalid(
            "rate",
            format!("{duration_s} s at {rate_hz} Hz is more than {MAX_SAMPLES} samples"),
        ));
    }
    Ok((0..=intervals as usize)
        .map(|k| start_s + k as f64 / rate_hz)
        .collect())
}

impl Trajectory {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time_s.len()
    }

    /// True when there are no samples.
    pub fn is_empty(&self) -> bool {
        self.time_s.is_empty()
    }

    /// The navigation state at sample `k` (to initialise an INS).
    pub fn nav_state(&self, k: usize) -> NavState {
        NavState {
            position_ecef: self.position_ecef[k],
            velocity_ecef: self.velocity_ecef[k],
            c_b_e: self.c_b_e[k],
        }
    }

    /// The ideal IMU sample at `k`.
    pub fn imu_sample(&self, k: usize) -> ImuSample {
        ImuSample {
            specific_force_b: self.specific_force_b[k],
            angular_rate_b: self.angular_rate_b[k],
        }
    }

    /// Geodetic position of each sample.
    pub fn position_geodetic(&self) -> Vec<Geodetic> {
        self.position_ecef.iter().map(ecef_to_geodetic).collect()
    }

    /// NED velocity at the true position of each sample, m/s.
    pub fn velocity_ned(&self) -> Vec<Vector3<f64>> {
        self.position_ecef
            .iter()
            .zip(&self.velocity_ecef)
            .map(|(r, v)| {
                let g = ecef_to_geodetic(r);
                c_n_e(g.latitude_rad, g.longitude_rad).transpose() * v
            })
            .collect()
    }

    /// Roll, pitch, yaw of C_b^n at the true position of each sample, rad.
    pub fn euler_ned(&self) -> Vec<Vector3<f64>> {
        self.position_ecef
            .iter()
            .zip(&self.c_b_e)
            .map(|(r, c)| {
                let g = ecef_to_geodetic(r);
                dcm_to_euler(&(c_n_e(g.latitude_rad, g.longitude_rad).transpose() * c))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A motion with every term switched on, smooth, in closed form.
    struct Wavy;
    impl Motion for Wavy {
        type Cursor = ();

        fn velocity_ned(&self, t: f64, cursor: &mut ()) -> Vector3<f64> {
            self.at(t, cursor).velocity_ned
        }

        fn at(&self, t: f64, _: &mut ()) -> LocalMotion {
            let euler_rad = Vector3::new(0.1 * (0.3 * t).sin(), 0.05 * (0.2 * t).cos(), 0.2 * t);
            LocalMotion {
                yaw_sin_cos: euler_rad.z.sin_cos(),
                velocity_ned: Vector3::new(
                    10.0 * (0.1 * t).cos(),
                    8.0 * (0.13 * t).sin() + 3.0,
                    0.5 * (0.2 * t).sin(),
                ),
                velocity_ned_rate: Vector3::new(
                    -(0.1 * t).sin(),
                    1.04 * (0.13 * t).cos(),
                    0.1 * (0.2 * t).cos(),
                ),
                euler_rad,
                euler_rate_rad_s: Vector3::new(
                    0.03 * (0.3 * t).cos(),
                    -0.01 * (0.2 * t).sin(),
                    0.2,
                ),
            }
        }
    }

    #[test]
    fn truth_agrees_with_finite_differences_of_itself() {
        // Independent of the inverse-mechanization formulas: differentiate
        // the generated position and attitude numerically, form f and ω
        // from their definitions (Groves eq. 5.36 and Ċ_b^i = C_b^i Ω_ib)
        // and compare.
        let dt = 1e-3;
        let time: Vec<f64> = (0..2001).map(|k| 10.0 + k as f64 * dt).collect();
        let tr = build(&Wavy, Geodetic::new(0.7, 0.2, 300.0), time);
        let we = Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S);
        for k in (1..2000).step_by(97) {
            let v_fd = (tr.position_ecef[k + 1] - tr.position_ecef[k - 1]) / (2.0 * dt);
            assert!((v_fd - tr.velocity_ecef[k]).norm() < 1e-5, "{k}");
            let a_fd = (tr.velocity_ecef[k + 1] - tr.velocity_ecef[k - 1]) / (2.0 * dt);
            let f_e =
                a_fd + 2.0 * we.cross(&tr.velocity_ecef[k]) - gravity_ecef(&tr.position_ecef[k]);
            assert!(
                (tr.c_b_e[k] * tr.specific_force_b[k] - f_e).norm() < 1e-5,
                "{k}"
            );
            // Ċ_b^e = C_b^e [ω_eb^b ×] − [ω_ie ×] C_b^e, so
            // ω_ib^b = vee(C_e^b Ċ_b^e) + C_e^b ω_ie.
            let c_dot = (tr.c_b_e[k + 1] - tr.c_b_e[k - 1]) / (2.0 * dt);
            let m = tr.c_b_e[k].transpose() * c_dot;
            let w_eb = Vector3::new(
                m[(2, 1)] - m[(1, 2)],
                m[(0, 2)] - m[(2, 0)],
                m[(1, 0)] - m[(0, 1)],
            ) / 2.0;
            let w_ib = w_eb + tr.c_b_e[k].transpose() * we;
            assert!((w_ib - tr.angular_rate_b[k]).norm() < 1e-7, "{k}");
        }
    }

    #[test]
    fn stage_expansion_matches_the_exact_rates() {
        // Against sin, cos and the radii evaluated at the stage's own
        // latitude, over offsets up to 1e-6 rad (aircraft speeds at the
        // longest sub-step are 5e-7) and heights apart.
        let v = Vector3::new(250.0, -180.0, 12.0);
        for lat0 in [-1.4, -0.7, 0.0, 0.3, 0.7608, 1.2, 1.55] {
            let (s0, c0) = f64::sin_cos(lat0);
            let expansion = StageExpansion::new(lat0, (s0, c0), radii(s0));
            for d in [-1e-6, -3e-7, -4.7e-8, 0.0, 1e-9, 4.7e-8, 3e-7, 1e-6] {
                let g = Vector3::new(lat0 + d, 0.2, 150.0 + 1e4 * d);
                let (s, c) = g.x.sin_cos();
                let exact = geodetic_rate_with(radii(s), c, g.z, &v);
                let taylor = expansion.geodetic_rate(&g, &v);
                for i in 0..3 {
                    let err = (taylor[i] - exact[i]).abs() / exact[i].abs();
                    assert!(err < 1e-15, "lat {lat0} d {d}: {err:e}");
                }
            }
        }
    }

    #[test]
    fn time_grid_validates() {
        assert_eq!(
            time_grid(0.0, 1.0, 4.0).unwrap(),
            vec![0.0, 0.25, 0.5, 0.75, 1.0]
        );
        assert!(time_grid(0.0, 0.0, 100.0)
            .unwrap_err()
            .to_string()
            .starts_with("duration:"));
        assert!(time_grid(0.0, 10.0, -1.0)
            .unwrap_err()
            .to_string()
            .starts_with("rate:"));
        assert!(time_grid(0.0, 1.0, 0.5)
            .unwrap_err()
            .to_string()
            .starts_with("rate:"));
        assert!(time_grid(0.0, f64::NAN, 1.0).is_err());
        // Few samples, but 1e302 integration sub-steps: refused, not run.
        assert!(time_grid(0.0, 1e300, 1e-298)
            .unwrap_err()
            .to_string()
            .starts_with("duration: 1e300 s is longer than the limit of 1e6 s"));
    }
}
