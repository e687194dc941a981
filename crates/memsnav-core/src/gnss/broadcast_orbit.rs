//! The Keplerian broadcast orbit and clock polynomial that GPS LNAV and
//! CNAV, Galileo I/NAV and BeiDou D1 share, and the user algorithm that
//! evaluates it, parameterised by each system's constants:
//!
//! - GPS: IS-GPS-200 rev. N, table 20-IV (position), the velocity
//!   equations after it, §20.3.3.3.3.1 (clock and relativistic term);
//!   CNAV's table 30-II is the same algorithm with two more terms, the
//!   rate of the semi-major axis (A_k = A₀ + Ȧ t_k) and of the mean
//!   motion difference (Δn_A = Δn₀ + ½ Δṅ₀ t_k), zero for the others;
//! - Galileo: OS SIS ICD issue 2.1, §5.1.1 (table 58, the same algorithm
//!   with μ = 3.986004418e14 and Ω̇e = 7.2921151467e-5) and §5.1.4 (clock);
//! - BeiDou: BDS-SIS-ICD-B1I 3.0, §5.2.4.12 (table 5-11: CGCS2000
//!   μ = 3.986004418e14, Ω̇e = 7.292115e-5; the GEO satellites' extra
//!   rotation) and §5.2.4.10 (clock).
//!
//! All times are GPS seconds since 1980-01-06 (`_gps_s`): a system's own
//! time enters only where the algorithm uses a time of week, the t_oe of
//! Ω_k = Ω₀ + (Ω̇ − Ω̇e) t_k − Ω̇e t_oe, which is in the system's week.

use nalgebra::{Matrix3, Vector3};

use super::satellite_state::SatelliteState;
use super::time::SECONDS_PER_WEEK;

/// The constants of one system's broadcast orbit and time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BroadcastSystem {
    /// RINEX system letter.
    pub letter: char,
    /// Earth's gravitational constant of the system's algorithm, m³/s².
    pub gm_m3_s2: f64,
    /// Earth rotation rate of the system's algorithm, rad/s.
    pub earth_rate_rad_s: f64,
    /// Relativistic clock constant F = −2 √μ / c², s/√m, as each ICD writes it.
    pub relativity_f_s_sqrt_m: f64,
    /// System time minus GPS time, s (whole seconds by definition).
    pub time_minus_gps_s: f64,
    /// The GPS week in which the system's week 0 starts.
    pub week_zero_in_gps_weeks: f64,
}

/// GPS (IS-GPS-200 table 20-IV and §20.3.3.3.3.1: WGS84 μ, Ω̇e, F).
pub const GPS: BroadcastSystem = BroadcastSystem {
    letter: 'G',
    gm_m3_s2: 3.986_005e14,
    earth_rate_rad_s: 7.292_115_146_7e-5,
    relativity_f_s_sqrt_m: -4.442_807_633e-10,
    time_minus_gps_s: 0.0,
    week_zero_in_gps_weeks: 0.0,
};

/// Galileo (OS SIS ICD §5.1.1 table 58, §5.1.4; GST weeks start with GPS
/// weeks, week 0 at GPS week 1024, 1999-08-22, §5.1.2).
pub const GALILEO: BroadcastSystem = BroadcastSystem {
    letter: 'E',
    gm_m3_s2: 3.986_004_418e14,
    earth_rate_rad_s: 7.292_115_146_7e-5,
    relativity_f_s_sqrt_m: -4.442_807_309e-10,
    time_minus_gps_s: 0.0,
    week_zero_in_gps_weeks: 1024.0,
};

/// BeiDou (BDS-SIS-ICD-B1I 3.0 §5.2.4.12 table 5-11, §5.2.4.10; BDT week
/// 0 starts 2006-01-01 00:00:00 UTC, GPS week 1356 + 14 s, and BDT = GPS −
/// 14 s, §3.3).
pub const BEIDOU: BroadcastSystem = BroadcastSystem {
    letter: 'C',
    gm_m3_s2: 3.986_004_418e14,
    earth_rate_rad_s: 7.292_115e-5,
    relativity_f_s_sqrt_m: -4.442_807_309e-10,
    time_minus_gps_s: -14.0,
    week_zero_in_gps_weeks: 1356.0,
};

impl BroadcastSystem {
    /// GPS time (s since 1980-01-06) of `seconds_of_week` in the system's week `week`.
    pub fn gps_time_s(&self, week: f64, seconds_of_week: f64) -> f64 {
        (week + self.week_zero_in_gps_weeks) * SECONDS_PER_WEEK + seconds_of_week
            - self.time_minus_gps_s
    }

    /// The system's seconds of week at GPS time `gps_time_s`.
    pub fn seconds_of_week(&self, gps_time_s: f64) -> f64 {
        (gps_time_s + self.time_minus_gps_s).rem_euclid(SECONDS_PER_WEEK)
    }

    /// The system's week number at GPS time `gps_time_s` (continuous).
    pub fn week(&self, gps_time_s: f64) -> f64 {
        ((gps_time_s + self.time_minus_gps_s) / SECONDS_PER_WEEK).floor()
            - self.week_zero_in_gps_weeks
    }

    /// A system time of week placed in the system week that brings it
    /// closest to GPS time `reference_gps_s` (a t_oe or t_oc may lie in the
    /// week before or after the transmission's), as GPS time.
    pub fn nearest_gps_time_s(&self, seconds_of_week: f64, reference_gps_s: f64) -> f64 {
        let t = self.gps_time_s(self.week(reference_gps_s), seconds_of_week);
        t - SECONDS_PER_WEEK * ((t - reference_gps_s) / SECONDS_PER_WEEK).round()
    }
}

/// How the orbital frame turns into ECEF.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OrbitFrame {
    /// GPS, Galileo, BeiDou MEO and IGSO: the node longitude Ω_k already
    /// holds the Earth's rotation.
    EarthFixedNode,
    /// BeiDou GEO (C01-C05, C59-C63): the elements are in a frame turned
    /// by +5° about x from the inertial frame of t_oe; the ECEF position is
    /// R_Z(Ω̇e t_k) R_X(−5°) of the position there (B1I ICD §5.2.4.12).
    BeidouGeo,
}

/// A broadcast ephemeris's orbit and clock polynomial (angles in rad,
/// times in s; t_oc and t_oe as GPS times, s since 1980-01-06).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BroadcastOrbit {
    /// Clock reference time t_oc, GPS s.
    pub toc_gps_s: f64,
    /// Ephemeris reference time t_oe, GPS s.
    pub toe_gps_s: f64,
    /// Clock bias a_f0 at t_oc, s.
    pub af0_s: f64,
    /// Clock drift a_f1, s/s.
    pub af1_s_s: f64,
    /// Clock drift rate a_f2, s/s².
    pub af2_s_s2: f64,
    /// Amplitude of the sine correction to the orbit radius C_rs, m.
    pub crs_m: f64,
    /// Mean motion difference from the computed value Δn, rad/s.
    pub delta_n_rad_s: f64,
    /// Mean anomaly at t_oe M₀, rad.
    pub m0_rad: f64,
    /// Amplitude of the cosine correction to the argument of latitude C_uc, rad.
    pub cuc_rad: f64,
    /// Eccentricity e.
    pub eccentricity: f64,
    /// Amplitude of the sine correction to the argument of latitude C_us, rad.
    pub cus_rad: f64,
    /// Square root of the semi-major axis √A, √m.
    pub sqrt_a_sqrt_m: f64,
    /// Amplitude of the cosine correction to the inclination C_ic, rad.
    pub cic_rad: f64,
    /// Longitude of the ascending node at the week's start Ω₀, rad.
    pub omega0_rad: f64,
    /// Amplitude of the sine correction to the inclination C_is, rad.
    pub cis_rad: f64,
    /// Inclination at t_oe i₀, rad.
    pub i0_rad: f64,
    /// Amplitude of the cosine correction to the orbit radius C_rc, m.
    pub crc_m: f64,
    /// Argument of perigee ω, rad.
    pub omega_rad: f64,
    /// Rate of right ascension Ω̇, rad/s.
    pub omega_dot_rad_s: f64,
    /// Rate of inclination IDOT, rad/s.
    pub idot_rad_s: f64,
    /// Rate of the semi-major axis Ȧ, m/s (GPS CNAV; 0 for the others).
    pub a_dot_m_s: f64,
    /// Rate of the mean motion difference Δṅ₀, rad/s² (GPS CNAV; 0 for
    /// the others).
    pub delta_n_dot_rad_s2: f64,
}

/// Tilt of the BeiDou GEO orbital frame about x, rad (B1I ICD §5.2.4.12: −5°).
const BEIDOU_GEO_TILT_RAD: f64 = -5.0 * std::f64::consts::PI / 180.0;

/// Coordinate rotation about x by `angle` (the ICD's R_X).
fn rotation_x(angle: f64) -> Matrix3<f64> {
    let (s, c) = angle.sin_cos();
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, s, 0.0, -s, c)
}

/// Coordinate rotation about z by `angle` (the ICD's R_Z) and its
/// derivative with respect to the angle.
fn rotation_z(angle: f64) -> (Matrix3<f64>, Matrix3<f64>) {
    let (s, c) = angle.sin_cos();
    (
        Matrix3::new(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0),
        Matrix3::new(-s, c, 0.0, -c, -s, 0.0, 0.0, 0.0, 0.0),
    )
}

impl BroadcastOrbit {
    /// Position and velocity (ECEF of the instant, antenna phase centre as
    /// broadcast) and the clock correction of the broadcast polynomial plus
    /// the relativistic term, without any group delay (so for the signals
    /// the clock is referred to: GPS L1/L2 P(Y) ionosphere-free, Galileo
    /// I/NAV E1/E5b ionosphere-free, BeiDou B3I), at GPS time
    /// `gps_time_s + offset_s`. Absolute GPS times (~1e9 s) carry only
    /// ~0.2 µs of resolution (~1 mm of orbit); a small offset (light time,
    /// a difference step) added to t − t_oe keeps full precision.
    pub fn state_at(
        &self,
        system: &BroadcastSystem,
        frame: OrbitFrame,
        gps_time_s: f64,
        offset_s: f64,
    ) -> SatelliteState {
        let earth_rate = system.earth_rate_rad_s;
        let a0 = self.sqrt_a_sqrt_m * self.sqrt_a_sqrt_m;
        let e = self.eccentricity;
        let n0 = (system.gm_m3_s2 / (a0 * a0 * a0)).sqrt();
        let tk = (gps_time_s - self.toe_gps_s) + offset_s;
        // IS-GPS-200 table 30-II: A_k = A₀ + Ȧ t_k, n_A = n₀ + Δn₀ + ½ Δṅ₀
        // t_k (table 20-IV's A and n when the rates are zero). M_k = M₀ +
        // n_A t_k, so its rate is n₀ + Δn₀ + Δṅ₀ t_k.
        let a = a0 + self.a_dot_m_s * tk;
        let n = n0 + self.delta_n_rad_s + 0.5 * self.delta_n_dot_rad_s2 * tk;
        let mk = self.m0_rad + n * tk;
        let mk_dot = n0 + self.delta_n_rad_s + self.delta_n_dot_rad_s2 * tk;
        // Kepler's equation M = E − e sin E by Newton's method; e < 0.03 for
        // these orbits, so a few iterations reach machine precision.
        let mut ek = mk;
        for _ in 0..20 {
            let step = (ek - e * ek.sin() - mk) / (1.0 - e * ek.cos());
            ek -= step;
            if step.abs() < 1e-15 {
                break;
            }
        }
        let (sin_e, cos_e) = ek.sin_cos();
        let one_minus_ecos = 1.0 - e * cos_e;
        let root = (1.0 - e * e).sqrt();
        let nu = (root * sin_e).atan2(cos_e - e);
        let phi = nu + self.omega_rad;
        let (sin2p, cos2p) = (2.0 * phi).sin_cos();
        let du = self.cus_rad * sin2p + self.cuc_rad * cos2p;
        let dr = self.crs_m * sin2p + self.crc_m * cos2p;
        let di = self.cis_rad * sin2p + self.cic_rad * cos2p;
        let u = phi + du;
        let r = a * one_minus_ecos + dr;
        let i = self.i0_rad + di + self.idot_rad_s * tk;
        let (sin_u, cos_u) = u.sin_cos();
        let x_orb = r * cos_u;
        let y_orb = r * sin_u;
        // The node: Earth-fixed for MEO/IGSO (Ω̇ − Ω̇e), inertial (of t_oe)
        // for a BeiDou GEO (Ω̇ alone, B1I ICD §5.2.4.12).
        let omega_k_dot = match frame {
            OrbitFrame::EarthFixedNode => self.omega_dot_rad_s - earth_rate,
            OrbitFrame::BeidouGeo => self.omega_dot_rad_s,
        };
        let omega_k = self.omega0_rad + omega_k_dot * tk
            - earth_rate * system.seconds_of_week(self.toe_gps_s);
        let (sin_o, cos_o) = omega_k.sin_cos();
        let (sin_i, cos_i) = i.sin_cos();
        let position = Vector3::new(
            x_orb * cos_o - y_orb * cos_i * sin_o,
            x_orb * sin_o + y_orb * cos_i * cos_o,
            y_orb * sin_i,
        );

        // Velocity: the time derivatives of the same expressions
        // (IS-GPS-200 table 20-IV, "SV velocity" equations).
        let e_dot = mk_dot / one_minus_ecos;
        let nu_dot = e_dot * root / one_minus_ecos;
        let i_dot = self.idot_rad_s + 2.0 * nu_dot * (self.cis_rad * cos2p - self.cic_rad * sin2p);
        let u_dot = nu_dot + 2.0 * nu_dot * (self.cus_rad * cos2p - self.cuc_rad * sin2p);
        let r_dot = self.a_dot_m_s * one_minus_ecos
            + e * a * e_dot * sin_e
            + 2.0 * nu_dot * (self.crs_m * cos2p - self.crc_m * sin2p);
        let x_orb_dot = r_dot * cos_u - r * u_dot * sin_u;
        let y_orb_dot = r_dot * sin_u + r * u_dot * cos_u;
        let velocity = Vector3::new(
            x_orb_dot * cos_o - y_orb_dot * cos_i * sin_o + y_orb * sin_i * i_dot * sin_o
                - omega_k_dot * (x_orb * sin_o + y_orb * cos_i * cos_o),
            x_orb_dot * sin_o + y_orb_dot * cos_i * cos_o - y_orb * sin_i * i_dot * cos_o
                + omega_k_dot * (x_orb * cos_o - y_orb * cos_i * sin_o),
            y_orb_dot * sin_i + y_orb * cos_i * i_dot,
        );
        let (position_ecef, velocity_ecef) = match frame {
            OrbitFrame::EarthFixedNode => (position, velocity),
            OrbitFrame::BeidouGeo => {
                // P = R_Z(Ω̇e t_k) R_X(−5°) P_GK; its rate adds the
                // derivative of R_Z (Ω̇e dR_Z/dφ).
                let tilt = rotation_x(BEIDOU_GEO_TILT_RAD);
                let (rz, drz) = rotation_z(earth_rate * tk);
                (
                    rz * tilt * position,
                    rz * tilt * velocity + earth_rate * drz * tilt * position,
                )
            }
        };

        // Clock: Δt_sv = a_f0 + a_f1 (t − t_oc) + a_f2 (t − t_oc)² + Δt_r,
        // Δt_r = F e √A sin E_k (IS-GPS-200 §20.3.3.3.3.1, Galileo ICD
        // §5.1.4, B1I ICD §5.2.4.10).
        let dt = (gps_time_s - self.toc_gps_s) + offset_s;
        let f = system.relativity_f_s_sqrt_m;
        // √A₀ for CNAV too: the few metres Ȧ moves A over hours change the
        // term by 1e-7 of its ~20 ns.
        let relativistic = f * e * self.sqrt_a_sqrt_m * sin_e;
        let relativistic_rate = f * e * self.sqrt_a_sqrt_m * cos_e * e_dot;
        SatelliteState {
            position_ecef,
            velocity_ecef,
            clock_bias_s: self.af0_s + self.af1_s_s * dt + self.af2_s_s2 * dt * dt + relativistic,
            clock_drift_s_s: self.af1_s_s + 2.0 * self.af2_s_s2 * dt + relativistic_rate,
            relativistic_s: relativistic,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geodesy::wgs84::SPEED_OF_LIGHT_M_S;

    #[test]
    fn relativity_constants_are_minus_two_root_mu_over_c_squared() {
        for s in [GPS, GALILEO, BEIDOU] {
            let f = -2.0 * s.gm_m3_s2.sqrt() / (SPEED_OF_LIGHT_M_S * SPEED_OF_LIGHT_M_S);
            assert!((f - s.relativity_f_s_sqrt_m).abs() < 1e-18, "{}", s.letter);
        }
    }

    #[test]
    fn system_times() {
        // BDT 0 = 2006-01-01 00:00:00 UTC = GPS week 1356, 14 s (14 leap
        // seconds then): BDT week 0 second 0 is that GPS time.
        assert_eq!(
            BEIDOU.gps_time_s(0.0, 0.0),
            1356.0 * SECONDS_PER_WEEK + 14.0
        );
        let t = BEIDOU.gps_time_s(1025.0, 417_600.0);
        assert_eq!(
            (BEIDOU.week(t), BEIDOU.seconds_of_week(t)),
            (1025.0, 417_600.0)
        );
        // GST week 1357 = GPS week 2381.
        assert_eq!(
            GALILEO.gps_time_s(1357.0, 5.0),
            2381.0 * SECONDS_PER_WEEK + 5.0
        );
        // A BDT time of week just after the week start, seen just before: next week.
        let week_start = BEIDOU.gps_time_s(1025.0, 0.0);
        assert_eq!(
            BEIDOU.nearest_gps_time_s(8.0, week_start - 30.0),
            week_start + 8.0
        );
    }

    /// The broadcast elements of a geostationary satellite at longitude
    /// `lon_rad`, built from the ICD's definition of the GEO frame: at t_k
    /// its inertial (of t_oe) position is on the equator at angle lon + Ω̇e
    /// t_k; R_X(+5°) of that is a circular orbit of inclination 5° whose
    /// ascending node lies on −x (Ω_k = π for every t_k: Ω̇ = 0, Ω₀ = π +
    /// Ω̇e t_oe) and whose argument of latitude is lon + Ω̇e t_k − π.
    fn geostationary(lon_rad: f64, toe_gps_s: f64) -> BroadcastOrbit {
        let w = BEIDOU.earth_rate_rad_s;
        let a = (BEIDOU.gm_m3_s2 / (w * w)).cbrt();
        BroadcastOrbit {
            toc_gps_s: toe_gps_s,
            toe_gps_s,
            af0_s: 0.0,
            af1_s_s: 0.0,
            af2_s_s2: 0.0,
            crs_m: 0.0,
            delta_n_rad_s: 0.0,
            m0_rad: lon_rad - std::f64::consts::PI,
            cuc_rad: 0.0,
            eccentricity: 0.0,
            cus_rad: 0.0,
            sqrt_a_sqrt_m: a.sqrt(),
            cic_rad: 0.0,
            omega0_rad: std::f64::consts::PI + w * BEIDOU.seconds_of_week(toe_gps_s),
            cis_rad: 0.0,
            i0_rad: 5f64.to_radians(),
            crc_m: 0.0,
            omega_rad: 0.0,
            omega_dot_rad_s: 0.0,
            idot_rad_s: 0.0,
            a_dot_m_s: 0.0,
            delta_n_dot_rad_s2: 0.0,
        }
    }

    #[test]
    fn a_geostationary_beidou_geo_stays_over_its_longitude() {
        // The physical invariant the GEO rotation must keep: a satellite
        // whose elements describe a geostationary orbit sits still above
        // the equator at its longitude, whatever t_k.
        let toe = BEIDOU.gps_time_s(1025.0, 417_600.0);
        let lon = 140f64.to_radians();
        let orbit = geostationary(lon, toe);
        let radius = orbit.sqrt_a_sqrt_m.powi(2);
        let expected = Vector3::new(radius * lon.cos(), radius * lon.sin(), 0.0);
        for tk in [-7200.0, -600.0, 0.0, 1.0, 3600.0, 7200.0] {
            let s = orbit.state_at(&BEIDOU, OrbitFrame::BeidouGeo, toe, tk);
            assert!(
                (s.position_ecef - expected).norm() < 1e-5,
                "t_k {tk}: {:?}",
                s.position_ecef - expected
            );
            assert!(s.velocity_ecef.norm() < 1e-9, "{}", s.velocity_ecef);
            // The MEO algorithm on the same elements puts it elsewhere:
            // the GEO branch is what keeps it there.
            let meo = orbit.state_at(&BEIDOU, OrbitFrame::EarthFixedNode, toe, tk);
            assert!((meo.position_ecef - expected).norm() > 1e5);
        }
    }

    #[test]
    fn velocity_is_the_derivative_of_position() {
        // Central differences of the position against the analytic
        // velocity, for the MEO and GEO frames alike.
        let toe = BEIDOU.gps_time_s(1025.0, 417_600.0);
        let mut orbit = geostationary(80f64.to_radians(), toe);
        orbit.eccentricity = 0.004;
        orbit.omega_dot_rad_s = -6e-9;
        orbit.idot_rad_s = 3e-10;
        orbit.crs_m = 80.0;
        orbit.cuc_rad = 2e-6;
        orbit.cis_rad = -1e-7;
        // CNAV's rates (IS-GPS-200 table 30-II), large enough that
        // leaving them out of the velocity (5 cm/s and 1 cm/s at 5000 s)
        // fails the check.
        orbit.a_dot_m_s = 0.05;
        orbit.delta_n_dot_rad_s2 = 1e-13;
        for frame in [OrbitFrame::EarthFixedNode, OrbitFrame::BeidouGeo] {
            for tk in [-3000.0, 100.0, 5000.0] {
                let h = 0.5;
                let p = |dt: f64| orbit.state_at(&BEIDOU, frame, toe, tk + dt).position_ecef;
                let numeric = (p(h) - p(-h)) / (2.0 * h);
                let v = orbit.state_at(&BEIDOU, frame, toe, tk).velocity_ecef;
                assert!(
                    (numeric - v).norm() < 1e-5,
                    "{frame:?} {tk}: {numeric} vs {v}"
                );
            }
        }
    }
}
