//! A synthetic Walker delta constellation (method §5): circular
//! Keplerian orbits in equally spaced planes, expressed in ECEF with the
//! Earth's rotation, for runs not tied to a date. [`WalkerConfig::nominal`]
//! gives the nominal pattern of GPS, Galileo and the BeiDou MEO satellites.

use nalgebra::Vector3;

use super::system::GnssSystem;
use crate::geodesy::wgs84::{EARTH_RATE_RAD_S, GM_M3_S2};
use crate::{validate, Error, Result};

/// Walker delta pattern i: t/p/f (t satellites, p planes, phasing f).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkerConfig {
    /// Total number of satellites t (a multiple of `planes`). Default 24.
    pub n_satellites: usize,
    /// Number of orbital planes p. Default 6.
    pub planes: usize,
    /// Inclination i, rad. Default 55°.
    pub inclination_rad: f64,
    /// Orbit radius (semi-major axis of the circular orbit), m. Default 26 560 km.
    pub semi_major_axis_m: f64,
    /// Walker phasing parameter f (0 ≤ f < p): satellites in adjacent planes
    /// are offset by 2π f / t in argument of latitude. Default 1.
    pub phasing: usize,
    /// Right ascension of the first plane's node at `gps_time_s = 0`,
    /// measured from the ECEF x axis at that instant, rad. Default 0.
    pub raan0_rad: f64,
    /// Argument of latitude of the first satellite at `gps_time_s = 0`, rad. Default 0.
    pub argument_of_latitude0_rad: f64,
}

impl Default for WalkerConfig {
    /// The GPS-like pattern, [`WalkerConfig::nominal`] of GPS.
    fn default() -> Self {
        Self::nominal(GnssSystem::Gps)
    }
}

impl WalkerConfig {
    /// The nominal Walker pattern of a system's MEO satellites, period
    /// T = 2π √(a³/μ):
    /// - GPS 24/6/1 at a = 26 560 km, 55° (the GPS-like reference orbit;
    ///   the real constellation has 6 planes of 4+ unevenly spaced slots),
    ///   T = 11 h 58 min;
    /// - Galileo 24/3/1 at a = 29 599.8 km (23 222 km altitude), 56°
    ///   (the nominal Galileo constellation, spares left out),
    ///   T = 14 h 4 min 41 s;
    /// - BeiDou MEO 24/3/1 at 21 528 km altitude, a = 27 906.1 km, 55°
    ///   (the BDS MEO constellation; the GEO and IGSO satellites are left
    ///   out), T = 12 h 53 min 14 s;
    /// - GLONASS 24/3/1 at a = 25 510 km (19 100 km altitude), 64.8°
    ///   (GLONASS ICD §3.1.2), T = 11 h 15 min 49 s.
    ///
    /// The first plane's node of Galileo, BeiDou and GLONASS is turned by
    /// 20°, 40° and 60° from GPS's, an arbitrary choice that keeps their first
    /// satellites from lining up with GPS's at time 0.
    pub fn nominal(system: GnssSystem) -> Self {
        let (n_satellites, planes, inclination_deg, semi_major_axis_m, raan0_deg) = match system {
            GnssSystem::Gps => (24, 6, 55.0, 26_560_000.0, 0.0),
            GnssSystem::Galileo => (24, 3, 56.0, 29_599_800.0, 20.0),
            GnssSystem::Beidou => (24, 3, 55.0, 27_906_100.0, 40.0),
            GnssSystem::Glonass => (24, 3, 64.8, 25_510_000.0, 60.0),
        };
        WalkerConfig {
            n_satellites,
            planes,
            inclination_rad: f64::to_radians(inclination_deg),
            semi_major_axis_m,
            phasing: 1,
            raan0_rad: f64::to_radians(raan0_deg),
            argument_of_latitude0_rad: 0.0,
        }
    }
}

/// The validated constellation: per satellite its node and initial
/// argument of latitude.
#[derive(Debug, Clone, PartialEq)]
pub struct Walker {
    /// The configuration it was built from.
    pub config: WalkerConfig,
    /// Mean motion n = √(μ/a³), rad/s.
    pub mean_motion_rad_s: f64,
    raan_rad: Vec<f64>,
    u0_rad: Vec<f64>,
    /// `raan_rad[i].sin_cos()` and `config.inclination_rad.sin_cos()`,
    /// computed once: every state needs them.
    raan_sin_cos: Vec<(f64, f64)>,
    inclination_sin_cos: (f64, f64),
}

impl Walker {
    /// The constellation of `config` (an error names an invalid setting).
    pub fn new(config: &WalkerConfig) -> Result<Self> {
        let c = *config;
        if c.planes == 0 {
            return Err(Error::invalid("planes", "must be at least 1"));
        }
        if c.n_satellites == 0 || c.n_satellites % c.planes != 0 {
            return Err(Error::invalid(
                "n_satellites",
                format!(
                    "must be a positive multiple of planes ({}), got {}",
                    c.planes, c.n_satellites
                ),
            ));
        }
        if c.n_satellites > u16::MAX as usize {
            return Err(Error::invalid("n_satellites", "must be at most 65535"));
        }
        if c.phasing >= c.planes {
            return Err(Error::invalid(
                "phasing",
                format!("must be in 0..planes ({}), got {}", c.planes, c.phasing),
            ));
        }
        if !(c.inclination_rad.is_finite()
            && (0.0..=std::f64::consts::PI).contains(&c.inclination_rad))
        {
            return Err(Error::invalid(
                "inclination",
                format!("must be within [0°, 180°], got {} rad", c.inclination_rad),
            ));
        }
        validate::positive("semi_major_axis_m", c.semi_major_axis_m)?;
        if c.semi_major_axis_m <= crate::geodesy::wgs84::SEMI_MAJOR_AXIS_M {
            return Err(Error::invalid(
                "semi_major_axis_m",
                format!(
                    "must exceed the Earth's radius, got {} m",
                    c.semi_major_axis_m
                ),
            ));
        }
        validate::finite_scalars("raan0", &[c.raan0_rad])?;
        validate::finite_scalars("argument_of_latitude0", &[c.argument_of_latitude0_rad])?;
        let per_plane = c.n_satellites / c.planes;
        let tau = std::f64::consts::TAU;
        let mut raan_rad = Vec::with_capacity(c.n_satellites);
        let mut u0_rad = Vec::with_capacity(c.n_satellites);
        for plane in 0..c.planes {
            for slot in 0..per_plane {
                raan_rad.push(c.raan0_rad + tau * plane as f64 / c.planes as f64);
                u0_rad.push(
                    c.argument_of_latitude0_rad
                        + tau * slot as f64 / per_plane as f64
                        + tau * (c.phasing * plane) as f64 / c.n_satellites as f64,
                );
            }
        }
        let a = c.semi_major_axis_m;
        Ok(Walker {
            config: c,
            mean_motion_rad_s: (GM_M3_S2 / (a * a * a)).sqrt(),
            raan_sin_cos: raan_rad.iter().map(|o| o.sin_cos()).collect(),
            inclination_sin_cos: c.inclination_rad.sin_cos(),
            raan_rad,
            u0_rad,
        })
    }

    /// How many satellites it has.
    pub fn len(&self) -> usize {
        self.raan_rad.len()
    }

    /// Whether it has none.
    pub fn is_empty(&self) -> bool {
        self.raan_rad.is_empty()
    }

    /// ECEF position and velocity of satellite `index` at `gps_time_s`:
    /// the inertial circular orbit r_I = a (cos u cos Ω − sin u cos i sin Ω,
    /// cos u sin Ω + sin u cos i cos Ω, sin u sin i), u = u0 + n t, rotated to
    /// ECEF by the Earth angle θ = ω_ie t; v_e = C_I^e v_I − ω_ie × r_e
    /// (Groves eq. 2.146 rearranged).
    pub fn position_velocity(&self, index: usize, gps_time_s: f64) -> (Vector3<f64>, Vector3<f64>) {
        self.position_velocity_at(index, gps_time_s, 0.0)
    }

    /// The state at `gps_time_s + offset_s`; the angles are reduced with an
    /// exact floating-point remainder by the orbital and sidereal periods so
    /// that large GPS times keep full precision.
    pub fn position_velocity_at(
        &self,
        index: usize,
        gps_time_s: f64,
        offset_s: f64,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let (r_i, v_i) = self.inertial(index, self.angle_travelled(gps_time_s, offset_s));
        let (s, c) = Self::earth_angle_sin_cos(gps_time_s, offset_s);
        // C_I^e = R_z(θ): frame rotation by the Earth angle.
        let rot = |v: Vector3<f64>| Vector3::new(c * v.x + s * v.y, -s * v.x + c * v.y, v.z);
        let r_e = rot(r_i);
        let omega = Vector3::new(0.0, 0.0, EARTH_RATE_RAD_S);
        let v_e = rot(v_i) - omega.cross(&r_e);
        (r_e, v_e)
    }

    /// The ECEF positions of every satellite at `gps_time_s`, bitwise those
    /// of [`Self::position_velocity`]: the Earth angle and the angle every
    /// satellite has moved through, the same for all, are evaluated once.
    pub fn positions(&self, gps_time_s: f64) -> impl Iterator<Item = Vector3<f64>> + '_ {
        let (s, c) = Self::earth_angle_sin_cos(gps_time_s, 0.0);
        let travelled = self.angle_travelled(gps_time_s, 0.0);
        (0..self.len()).map(move |i| {
            let (v, _) = self.inertial(i, travelled);
            Vector3::new(c * v.x + s * v.y, -s * v.x + c * v.y, v.z)
        })
    }

    /// sin and cos of the Earth angle θ = ω_ie t at `gps_time_s + offset_s`.
    #[inline]
    fn earth_angle_sin_cos(gps_time_s: f64, offset_s: f64) -> (f64, f64) {
        let tau = std::f64::consts::TAU;
        let theta = EARTH_RATE_RAD_S * (gps_time_s % (tau / EARTH_RATE_RAD_S))
            + EARTH_RATE_RAD_S * offset_s;
        theta.sin_cos()
    }

    /// The argument of latitude every satellite has moved through since
    /// GPS time 0 at `gps_time_s + offset_s`, as the two terms n (t mod T)
    /// and n·offset (added in this order to each satellite's u0).
    #[inline]
    fn angle_travelled(&self, gps_time_s: f64, offset_s: f64) -> (f64, f64) {
        let tau = std::f64::consts::TAU;
        let n = self.mean_motion_rad_s;
        (n * (gps_time_s % (tau / n)), n * offset_s)
    }

    /// Inertial position and velocity of satellite `index` on its circular
    /// orbit, having moved through [`Self::angle_travelled`].
    #[inline]
    fn inertial(&self, index: usize, (turned, offset): (f64, f64)) -> (Vector3<f64>, Vector3<f64>) {
        let a = self.config.semi_major_axis_m;
        let n = self.mean_motion_rad_s;
        let u = self.u0_rad[index] + turned + offset;
        let (sin_u, cos_u) = u.sin_cos();
        let (sin_o, cos_o) = self.raan_sin_cos[index];
        let (sin_i, cos_i) = self.inclination_sin_cos;
        let r_i = a * Vector3::new(
            cos_u * cos_o - sin_u * cos_i * sin_o,
            cos_u * sin_o + sin_u * cos_i * cos_o,
            sin_u * sin_i,
        );
        let v_i = a
            * n
            * Vector3::new(
                -sin_u * cos_o - cos_u * cos_i * sin_o,
                -sin_u * sin_o + cos_u * cos_i * cos_o,
                cos_u * sin_i,
            );
        (r_i, v_i)
    }
}
