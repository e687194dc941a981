//! GPS broadcast ephemeris: satellite position, velocity and clock
//! correction by the user algorithm of IS-GPS-200 (rev. N, table 20-IV for
//! the position, the velocity equations that follow it, and §20.3.3.3.3.1
//! for the clock).

use nalgebra::Vector3;

use super::satellite_state::SatelliteState;
use super::time::SECONDS_PER_WEEK;

/// WGS84 value of GM that IS-GPS-200 prescribes for the orbit, m³/s².
pub const GPS_GM_M3_S2: f64 = 3.986_005e14;
/// Earth rotation rate that IS-GPS-200 prescribes, rad/s.
pub const GPS_EARTH_RATE_RAD_S: f64 = 7.292_115_146_7e-5;
/// Relativistic clock constant F = −2 √μ / c², s/√m (IS-GPS-200 §20.3.3.3.3.1).
const RELATIVITY_F: f64 = -4.442_807_633e-10;

/// One broadcast ephemeris record (one RINEX navigation message) of a GPS
/// satellite. Angles in rad, times in s; `toe_gps_s` and `toc_gps_s` are
/// absolute GPS times (s since 1980-01-06).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpsEphemeris {
    pub prn: u16,
    /// Clock reference time t_oc, GPS s.
    pub toc_gps_s: f64,
    /// Ephemeris reference time t_oe (week × 604800 + toe), GPS s.
    pub toe_gps_s: f64,
    pub af0_s: f64,
    pub af1_s_s: f64,
    pub af2_s_s2: f64,
    pub crs_m: f64,
    pub delta_n_rad_s: f64,
    pub m0_rad: f64,
    pub cuc_rad: f64,
    pub eccentricity: f64,
    pub cus_rad: f64,
    pub sqrt_a_sqrt_m: f64,
    pub cic_rad: f64,
    pub omega0_rad: f64,
    pub cis_rad: f64,
    pub i0_rad: f64,
    pub crc_m: f64,
    pub omega_rad: f64,
    pub omega_dot_rad_s: f64,
    pub idot_rad_s: f64,
    /// SV health word; 0 is healthy.
    pub health: u32,
    /// Group delay differential T_GD, s.
    pub tgd_s: f64,
    /// Fit interval, h (4 when the file leaves it blank).
    pub fit_interval_h: f64,
}

/// A decoded LNAV ephemeris with the fields of its subframes that the
/// orbit does not use.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LnavEphemeris {
    /// Orbit, clock, T_GD, health and fit interval, as the RINEX reader gives them.
    pub ephemeris: GpsEphemeris,
    /// Issue of data, ephemeris (subframes 2 and 3) and clock (subframe 1).
    pub iode: u8,
    pub iodc: u16,
    /// User range accuracy index N (0-15, table 20-I's URA in m by [`ura_m`]).
    pub ura_index: u8,
    /// Codes on L2 (subframe 1 bits 11-12) and the L2 P data flag.
    pub l2_codes: u8,
    pub l2p_data_flag: bool,
    /// The fit interval flag (0: 4 h).
    pub fit_interval_flag: bool,
    /// GPS week of t_oe (continuous), as RINEX writes it.
    pub toe_week: u16,
    /// Transmission time of the start of subframe 1, GPS s since 1980-01-06.
    pub transmission_gps_s: f64,
}

/// URA in metres of index N (IS-GPS-200 §20.3.3.3.1.3: the upper bound of
/// each bin; N = 15 means no accuracy prediction: 6144 m written, as RINEX
/// writers do).
pub fn ura_m(index: u8) -> f64 {
    const URA_M: [f64; 16] = [
        2.4, 3.4, 4.85, 6.85, 9.65, 13.65, 24.0, 48.0, 96.0, 192.0, 384.0, 768.0, 1536.0, 3072.0,
        6144.0, 6144.0,
    ];
    URA_M[usize::from(index.min(15))]
}

/// A decoded Galileo I/NAV ephemeris (angles rad, times GPS s since
/// 1980-01-06: GST is steered to GPS time within tens of ns).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InavEphemeris {
    pub svid: u16,
    pub iod_nav: u16,
    pub toc_gps_s: f64,
    pub toe_gps_s: f64,
    pub af0_s: f64,
    pub af1_s_s: f64,
    pub af2_s_s2: f64,
    pub crs_m: f64,
    pub delta_n_rad_s: f64,
    pub m0_rad: f64,
    pub cuc_rad: f64,
    pub eccentricity: f64,
    pub cus_rad: f64,
    pub sqrt_a_sqrt_m: f64,
    pub cic_rad: f64,
    pub omega0_rad: f64,
    pub cis_rad: f64,
    pub i0_rad: f64,
    pub crc_m: f64,
    pub omega_rad: f64,
    pub omega_dot_rad_s: f64,
    pub idot_rad_s: f64,
    /// Signal-in-space accuracy index (§5.1.11; 255: no accuracy prediction).
    pub sisa_index: u8,
    /// Broadcast group delays E1-E5a and E1-E5b, s.
    pub bgd_e1_e5a_s: f64,
    pub bgd_e1_e5b_s: f64,
    /// Signal health (0 OK, 1 out of service, 2 extended operations, 3 in
    /// test) and data validity (0 valid, 1 working without guarantee) of
    /// E1-B and E5b (§5.1.9.3).
    pub e1b_health: u8,
    pub e5b_health: u8,
    pub e1b_data_validity: u8,
    pub e5b_data_validity: u8,
    /// GST week of word type 5 (12 bits, counted from 1999-08-22).
    pub gst_week: u16,
    /// Word type 5's GST week and time of week, GPS s since 1980-01-06
    /// (the time of its page).
    pub transmission_gps_s: f64,
}

/// Signal-in-space accuracy in metres of index `n` (ICD §5.1.11, table
/// 89: 1 cm steps to 0.49 m, 2 cm to 0.98 m, 4 cm to 1.96 m, 16 cm to
/// 6 m); `None` for "no accuracy prediction" (255) and spare indices.
pub fn sisa_m(n: u8) -> Option<f64> {
    let n = f64::from(n);
    match n as u8 {
        0..=49 => Some(0.01 * n),
        50..=74 => Some(0.5 + 0.02 * (n - 50.0)),
        75..=99 => Some(1.0 + 0.04 * (n - 75.0)),
        100..=125 => Some(2.0 + 0.16 * (n - 100.0)),
        _ => None,
    }
}

impl InavEphemeris {
    /// Healthy and valid on E1-B (health 0, data valid).
    pub fn is_healthy(&self) -> bool {
        self.e1b_health == 0 && self.e1b_data_validity == 0
    }
}

impl GpsEphemeris {
    /// Position and velocity (ECEF at `gps_time_s`, antenna phase centre as
    /// broadcast) and the L1 C/A clock correction at GPS time `gps_time_s`.
    pub fn state(&self, gps_time_s: f64) -> SatelliteState {
        self.state_at(gps_time_s, 0.0)
    }

    /// The state at `gps_time_s + offset_s`. Absolute GPS times (~1e9 s)
    /// carry only ~0.2 µs of resolution (~1 mm of orbit); a small offset
    /// (light time, a difference step) added to t − t_oe keeps full precision.
    pub fn state_at(&self, gps_time_s: f64, offset_s: f64) -> SatelliteState {
        let a = self.sqrt_a_sqrt_m * self.sqrt_a_sqrt_m;
        let e = self.eccentricity;
        let n0 = (GPS_GM_M3_S2 / (a * a * a)).sqrt();
        let tk = (gps_time_s - self.toe_gps_s) + offset_s;
        let n = n0 + self.delta_n_rad_s;
        let mk = self.m0_rad + n * tk;
        // Kepler's equation M = E − e sin E by Newton's method; e < 0.03 for
        // GPS, so a few iterations reach machine precision.
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
        let omega_k_dot = self.omega_dot_rad_s - GPS_EARTH_RATE_RAD_S;
        let omega_k = self.omega0_rad + omega_k_dot * tk
            - GPS_EARTH_RATE_RAD_S * (self.toe_gps_s % SECONDS_PER_WEEK);
        let (sin_o, cos_o) = omega_k.sin_cos();
        let (sin_i, cos_i) = i.sin_cos();
        let position = Vector3::new(
            x_orb * cos_o - y_orb * cos_i * sin_o,
            x_orb * sin_o + y_orb * cos_i * cos_o,
            y_orb * sin_i,
        );

        // Velocity: the time derivatives of the same expressions
        // (IS-GPS-200 table 20-IV, "SV velocity" equations).
        let e_dot = n / one_minus_ecos;
        let nu_dot = e_dot * root / one_minus_ecos;
        let i_dot = self.idot_rad_s + 2.0 * nu_dot * (self.cis_rad * cos2p - self.cic_rad * sin2p);
        let u_dot = nu_dot + 2.0 * nu_dot * (self.cus_rad * cos2p - self.cuc_rad * sin2p);
        let r_dot =
            e * a * e_dot * sin_e + 2.0 * nu_dot * (self.crs_m * cos2p - self.crc_m * sin2p);
        let x_orb_dot = r_dot * cos_u - r * u_dot * sin_u;
        let y_orb_dot = r_dot * sin_u + r * u_dot * cos_u;
        let velocity = Vector3::new(
            x_orb_dot * cos_o - y_orb_dot * cos_i * sin_o + y_orb * sin_i * i_dot * sin_o
                - omega_k_dot * (x_orb * sin_o + y_orb * cos_i * cos_o),
            x_orb_dot * sin_o + y_orb_dot * cos_i * cos_o - y_orb * sin_i * i_dot * cos_o
                + omega_k_dot * (x_orb * cos_o - y_orb * cos_i * sin_o),
            y_orb_dot * sin_i + y_orb * cos_i * i_dot,
        );

        // Clock: Δt_sv = a_f0 + a_f1 (t − t_oc) + a_f2 (t − t_oc)² + Δt_r − T_GD
        // (IS-GPS-200 eqs. in §20.3.3.3.3.1 and §20.3.3.3.3.2, L1 C/A user).
        let dt = (gps_time_s - self.toc_gps_s) + offset_s;
        let relativistic = RELATIVITY_F * e * self.sqrt_a_sqrt_m * sin_e;
        let relativistic_rate = RELATIVITY_F * e * self.sqrt_a_sqrt_m * cos_e * e_dot;
        SatelliteState {
            position_ecef: position,
            velocity_ecef: velocity,
            clock_bias_s: self.af0_s + self.af1_s_s * dt + self.af2_s_s2 * dt * dt + relativistic
                - self.tgd_s,
            clock_drift_s_s: self.af1_s_s + 2.0 * self.af2_s_s2 * dt + relativistic_rate,
            relativistic_s: relativistic,
        }
    }
}
