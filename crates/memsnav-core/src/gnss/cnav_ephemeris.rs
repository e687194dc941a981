//! GPS CNAV broadcast ephemeris (the L2C and L5 navigation message,
//! IS-GPS-200 rev. N §30.3.3 and IS-GPS-705 §20.3.3): the shared
//! [`BroadcastOrbit`] with GPS's constants and CNAV's two rate terms
//! (table 30-II), the L1/L2/L5 health bits, the accuracy indices URA_ED
//! and URA_NED0-2, and the group delays T_GD and the inter-signal
//! corrections (ISC) of message type 30.

use super::broadcast_orbit::{BroadcastOrbit, OrbitFrame, GPS};
use super::ephemeris::GpsEphemeris;
use super::satellite_state::SatelliteState;

/// γ = (f_L1 / f_L2)² = (77/60)² (IS-GPS-200 §30.3.3.3.1.1.1).
const GAMMA_L1_L2: f64 = (77.0 * 77.0) / (60.0 * 60.0);

/// T_GD and the inter-signal corrections of message type 30 (IS-GPS-200
/// §30.3.3.3.1.1, IS-GPS-705 §20.3.3.3.1.2), s; `None` where the message
/// says "not available" (the bit string 1000000000000).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CnavGroupDelays {
    /// Group delay differential T_GD, s.
    pub tgd_s: Option<f64>,
    /// Inter-signal correction ISC of L1 C/A, s.
    pub isc_l1ca_s: Option<f64>,
    /// Inter-signal correction ISC of L2C, s.
    pub isc_l2c_s: Option<f64>,
    /// Inter-signal correction ISC of L5 I5, s.
    pub isc_l5i5_s: Option<f64>,
    /// Inter-signal correction ISC of L5 Q5, s.
    pub isc_l5q5_s: Option<f64>,
}

impl CnavGroupDelays {
    /// The group delay a single-frequency user subtracts from the clock
    /// correction on the signal of RINEX band and attribute `code` (e.g.
    /// `"1C"`): T_GD − ISC for L1 C/A (`1C`), L2C (`2S`, `2L`, `2X`), L5 I5
    /// (`5I`) and Q5 (`5Q`), T_GD for L1 P(Y), γ T_GD for L2 P(Y)
    /// (IS-GPS-200 §30.3.3.3.1.1.1: (Δt_SV)_X = Δt_SV − T_GD + ISC_X;
    /// IS-GPS-705 §20.3.3.3.1.2.1); `None` for other signals or terms the
    /// message says are not available.
    pub fn group_delay_s(&self, code: &str) -> Option<f64> {
        let tgd = self.tgd_s?;
        match code {
            "1C" => Some(tgd - self.isc_l1ca_s?),
            "1P" | "1W" => Some(tgd),
            "2S" | "2L" | "2X" => Some(tgd - self.isc_l2c_s?),
            "2P" | "2W" => Some(GAMMA_L1_L2 * tgd),
            "5I" => Some(tgd - self.isc_l5i5_s?),
            "5Q" => Some(tgd - self.isc_l5q5_s?),
            _ => None,
        }
    }
}

/// A GPS CNAV ephemeris: message types 10 and 11 and a clock message
/// (types 30-37) of one upload (times GPS s since 1980-01-06).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CnavEphemeris {
    /// The satellite's PRN.
    pub prn: u16,
    /// Orbit (√A₀ = √(A_REF + ΔA), Ω̇ = Ω̇_REF + ΔΩ̇, Ȧ and Δṅ₀) and clock
    /// polynomial; the clock is referred to the L1/L2 P(Y)
    /// ionosphere-free combination, as LNAV's (§30.3.3.3.1.1.1).
    pub orbit: BroadcastOrbit,
    /// L1 signal health (type 10; 0 OK, 1 bad).
    pub l1_health: u8,
    /// L2 signal health (type 10; 0 OK, 1 bad).
    pub l2_health: u8,
    /// L5 signal health (type 10; 0 OK, 1 bad).
    pub l5_health: u8,
    /// Elevation-dependent accuracy index URA_ED (type 10, −16..15).
    pub ura_ed_index: i8,
    /// Non-elevation-dependent accuracy index URA_NED0 of the clock
    /// message (−16..15).
    pub ura_ned0_index: i8,
    /// Non-elevation-dependent accuracy change index URA_NED1 (0..7).
    pub ura_ned1_index: u8,
    /// Non-elevation-dependent accuracy change rate index URA_NED2 (0..7).
    pub ura_ned2_index: u8,
    /// Data predict time t_op of type 10, GPS s.
    pub top_gps_s: f64,
    /// Type 10's 13-bit week number (of its transmission).
    pub week: u16,
    /// Integrity status flag of type 10.
    pub integrity_status_flag: bool,
    /// L2C phasing bit of type 10.
    pub l2c_phasing: bool,
    /// Group delays of a type 30 of the same t_oc; `None` until one comes.
    pub group_delays: Option<CnavGroupDelays>,
    /// Transmission time of the start of message type 10, GPS s.
    pub transmission_gps_s: f64,
}

/// Nominal URA in metres of a CNAV accuracy index N (IS-GPS-200
/// §30.3.3.1.1.4: 2^(1 + N/2) for N ≤ 6, 2^(N − 2) for 6 < N < 15);
/// `None` for N = 15, "no accuracy prediction".
pub fn cnav_ura_m(index: i8) -> Option<f64> {
    match index {
        ..=6 => Some(2f64.powf(1.0 + f64::from(index) / 2.0)),
        7..=14 => Some(2f64.powi(i32::from(index) - 2)),
        _ => None,
    }
}

impl CnavEphemeris {
    /// Healthy on RINEX band `band` ('1' L1, '2' L2, '5' L5); false for
    /// any other band. (L5, pre-operational, was flagged unhealthy by
    /// every satellite of the walk's log.)
    pub fn is_healthy_on(&self, band: char) -> bool {
        match band {
            '1' => self.l1_health == 0,
            '2' => self.l2_health == 0,
            '5' => self.l5_health == 0,
            _ => false,
        }
    }

    /// The group delay a single-frequency user subtracts from the clock
    /// correction on the signal of RINEX band and attribute `code` (e.g.
    /// `"1C"`); see [`CnavGroupDelays::group_delay_s`]. `None` until type
    /// 30 has given the terms.
    pub fn group_delay_s(&self, code: &str) -> Option<f64> {
        self.group_delays?.group_delay_s(code)
    }

    /// The group delays of the signals this ephemeris flags healthy: the
    /// ISCs of L2C and L5 are left out while their health bit (type 10)
    /// says bad, so that no measurement of an unhealthy signal is
    /// corrected (the walk's satellites flag L5, still pre-operational).
    pub fn healthy_group_delays(&self) -> Option<CnavGroupDelays> {
        let mut delays = self.group_delays?;
        if self.l2_health != 0 {
            delays.isc_l2c_s = None;
        }
        if self.l5_health != 0 {
            delays.isc_l5i5_s = None;
            delays.isc_l5q5_s = None;
        }
        Some(delays)
    }

    /// This ephemeris as an L1 C/A user's [`GpsEphemeris`]: the same orbit
    /// (with CNAV's Ȧ and Δṅ̇), L1 health, and T_GD − ISC_L1CA in the place
    /// of LNAV's T_GD, so that [`GpsEphemeris::state_at`] gives the L1 C/A
    /// clock; a 3 h fit (IS-GPS-200 §30.3.3.1.1: t_oe ± 1.5 h). For L1 C/A
    /// only (its `group_delay_s('2')` would not be L2's); `None` until a
    /// type 30 has given the group delays.
    pub fn l1_ca_ephemeris(&self) -> Option<GpsEphemeris> {
        Some(GpsEphemeris {
            prn: self.prn,
            orbit: self.orbit,
            health: u32::from(self.l1_health),
            tgd_s: self.group_delay_s("1C")?,
            fit_interval_h: 3.0,
        })
    }

    /// Position, velocity and the clock correction referred to L1/L2
    /// P(Y) ionosphere-free at GPS time `gps_time_s + offset_s` (see
    /// [`BroadcastOrbit::state_at`]); subtract [`Self::group_delay_s`] for
    /// one signal.
    pub fn state_at(&self, gps_time_s: f64, offset_s: f64) -> SatelliteState {
        self.orbit
            .state_at(&GPS, OrbitFrame::EarthFixedNode, gps_time_s, offset_s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ura_nominal_values() {
        // IS-GPS-200 §30.3.3.1.1.4: N = 0 is 2 m, N = 1 2.83 m, N = 6 16 m,
        // N = 7 32 m, N = 14 4096 m, N = −16 2^−7 m.
        assert_eq!(cnav_ura_m(0), Some(2.0));
        assert!((cnav_ura_m(1).unwrap() - 2f64.sqrt() * 2.0).abs() < 1e-12);
        assert_eq!(cnav_ura_m(6), Some(16.0));
        assert_eq!(cnav_ura_m(7), Some(32.0));
        assert_eq!(cnav_ura_m(14), Some(4096.0));
        assert_eq!(cnav_ura_m(-16), Some(2f64.powi(-7)));
        assert_eq!(cnav_ura_m(15), None);
    }
}
