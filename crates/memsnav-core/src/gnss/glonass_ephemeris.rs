//! GLONASS broadcast ephemeris (GLONASS ICD edition 5.1, 2008, §4.4): the
//! satellite's PZ-90 position, velocity and lunisolar acceleration at t_b,
//! its clock offset τ_n and relative frequency offset γ_n, its FDMA
//! frequency channel; as RINEX navigation files write them (RINEX 3.05
//! table A10, RINEX 2.11 table A11).
//!
//! Choices:
//! - **Time.** GLONASS time is UTC(SU) + 3 h; RINEX writes t_b as UTC
//!   (without the 3 h), which becomes GPS time with the leap seconds of
//!   the date (`checked_gps_time_from_utc`). The UTC(SU)−UTC(USNO)
//!   offset (tens of ns) and τ_c are neglected, as in RTKLIB.
//! - **Frame.** PZ-90.11 (broadcast since 2014) agrees with ITRF2014 to a
//!   few centimetres: positions are used as ECEF ITRF/WGS84 without a
//!   transformation.
//! - **Clock.** Δt_sv = −τ_n + γ_n (t − t_b) (ICD §3.3.3), the correction
//!   of the satellite's time to GLONASS time, relativity included in the
//!   broadcast values (no separate term).

use nalgebra::Vector3;

use super::glonass_orbit::propagate_glonass;
use super::satellite_state::SatelliteState;

/// G1 carrier of channel 0, Hz, and the channel spacing (ICD §3.3.1.1).
const G1_BASE_HZ: f64 = 1_602.0e6;
const G1_SPACING_HZ: f64 = 0.5625e6;
/// G2 carrier of channel 0 and the spacing, Hz.
const G2_BASE_HZ: f64 = 1_246.0e6;
const G2_SPACING_HZ: f64 = 0.4375e6;

/// Largest |t − t_b| an ephemeris serves, s: RTKLIB's limit (its
/// `MAXDTOE_GLO`), twice the ICD's ±15 min around t_b, so one missed
/// 30-minute update does not drop the satellite.
pub const GLONASS_VALIDITY_S: f64 = 1800.0;

/// A GLONASS broadcast ephemeris (positions PZ-90 ≈ ITRF, m; times GPS s
/// since 1980-01-06).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlonassEphemeris {
    /// Orbital slot 1-24 (RINEX's PRN of an `R` satellite).
    pub slot: u16,
    /// FDMA frequency channel k (−7 to +6 today; RINEX allows to +13).
    pub frequency_channel: i8,
    /// Reference time t_b, GPS s.
    pub tb_gps_s: f64,
    /// Satellite clock offset τ_n, s (RINEX writes −τ_n).
    pub tau_n_s: f64,
    /// Relative frequency offset γ_n.
    pub gamma_n: f64,
    /// Position at t_b, PZ-90, m.
    pub position_ecef: Vector3<f64>,
    /// Velocity at t_b, PZ-90, m/s.
    pub velocity_ecef: Vector3<f64>,
    /// Lunisolar acceleration, PZ-90, m/s² (held constant over the interval).
    pub lunisolar_m_s2: Vector3<f64>,
    /// Health as RINEX writes it (0 healthy; the MSB of B_n, in RINEX
    /// 3.05 with the l_n flag in bit 2).
    pub health: u8,
    /// Age of the operational information E_n, days.
    pub age_days: u8,
}

impl GlonassEphemeris {
    /// G1 carrier frequency, Hz (1602 MHz + k × 0.5625 MHz).
    pub fn g1_frequency_hz(&self) -> f64 {
        G1_BASE_HZ + f64::from(self.frequency_channel) * G1_SPACING_HZ
    }

    /// G2 carrier frequency, Hz (1246 MHz + k × 0.4375 MHz).
    pub fn g2_frequency_hz(&self) -> f64 {
        G2_BASE_HZ + f64::from(self.frequency_channel) * G2_SPACING_HZ
    }

    /// Whether the ephemeris says the satellite is usable (B_n = 0).
    pub fn is_healthy(&self) -> bool {
        self.health == 0
    }

    /// Position, velocity (PZ-90 of the instant, m, m/s) and clock
    /// correction at GPS time `gps_time_s`: the orbit integrated from t_b
    /// ([`propagate_glonass`]), Δt_sv = −τ_n + γ_n (t − t_b).
    pub fn state(&self, gps_time_s: f64) -> SatelliteState {
        self.state_at(gps_time_s, 0.0)
    }

    /// [`GlonassEphemeris::state`] at `gps_time_s + offset_s`, the small
    /// offset (a signal's travel time) added after t − t_b to keep its
    /// precision.
    pub fn state_at(&self, gps_time_s: f64, offset_s: f64) -> SatelliteState {
        let dt = (gps_time_s - self.tb_gps_s) + offset_s;
        let (position_ecef, velocity_ecef) = propagate_glonass(
            &self.position_ecef,
            &self.velocity_ecef,
            &self.lunisolar_m_s2,
            dt,
        );
        SatelliteState {
            position_ecef,
            velocity_ecef,
            clock_bias_s: -self.tau_n_s + self.gamma_n * dt,
            clock_drift_s_s: self.gamma_n,
            relativistic_s: 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frequencies_and_clock_follow_the_icd() {
        let eph = GlonassEphemeris {
            slot: 1,
            frequency_channel: -7,
            tb_gps_s: 1000.0,
            tau_n_s: 1e-4,
            gamma_n: 1e-12,
            position_ecef: Vector3::new(7003.008789e3, -12206.626953e3, 21280.765625e3),
            velocity_ecef: Vector3::new(0.7835417e3, 2.8042530e3, 1.3525150e3),
            lunisolar_m_s2: Vector3::zeros(),
            health: 0,
            age_days: 0,
        };
        assert_eq!(eph.g1_frequency_hz(), 1598.0625e6);
        assert_eq!(eph.g2_frequency_hz(), 1242.9375e6);
        let s = eph.state(1600.0);
        assert!((s.clock_bias_s - (-1e-4 + 600e-12)).abs() < 1e-18);
        // At t_b the state is the message's.
        assert_eq!(eph.state(1000.0).position_ecef, eph.position_ecef);
    }
}
