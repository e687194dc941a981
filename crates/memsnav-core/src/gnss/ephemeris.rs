//! GPS broadcast ephemeris (LNAV, IS-GPS-200 rev. N §20.3.3.3 and
//! §20.3.3.4): the shared [`BroadcastOrbit`] with GPS's constants, its
//! health, T_GD and fit interval, and the group delay per signal
//! (§20.3.3.3.3.2).

use super::broadcast_orbit::{BroadcastOrbit, OrbitFrame, GPS};
use super::satellite_state::SatelliteState;

/// WGS84 value of GM that IS-GPS-200 prescribes for the orbit, m³/s².
pub const GPS_GM_M3_S2: f64 = GPS.gm_m3_s2;
/// Earth rotation rate that IS-GPS-200 prescribes, rad/s.
pub const GPS_EARTH_RATE_RAD_S: f64 = GPS.earth_rate_rad_s;
/// γ = (f_L1 / f_L2)² = (77/60)² (IS-GPS-200 §20.3.3.3.3.2).
const GAMMA_L1_L2: f64 = (77.0 * 77.0) / (60.0 * 60.0);

/// One broadcast ephemeris record (one RINEX navigation message) of a GPS
/// satellite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpsEphemeris {
    /// The satellite's PRN.
    pub prn: u16,
    /// Orbit and clock polynomial (t_oe, t_oc as GPS times).
    pub orbit: BroadcastOrbit,
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
    /// Issue of data, ephemeris (subframes 2 and 3).
    pub iode: u8,
    /// Issue of data, clock (subframe 1).
    pub iodc: u16,
    /// User range accuracy index N (0-15, table 20-I's URA in m by [`ura_m`]).
    pub ura_index: u8,
    /// Codes on L2 (subframe 1 bits 11-12).
    pub l2_codes: u8,
    /// The L2 P data flag.
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

/// The URA index of `metres` as RINEX writes it ([`ura_m`] of the index):
/// the first bin whose bound reaches it (15 beyond the table).
pub fn ura_index(metres: f64) -> u8 {
    (0..15u8).find(|&n| ura_m(n) >= metres - 1e-9).unwrap_or(15)
}

impl GpsEphemeris {
    /// The group delay an LNAV user subtracts from the clock correction on
    /// RINEX band `band` (IS-GPS-200 §20.3.3.3.3.2: the clock is referred
    /// to the L1/L2 P(Y) ionosphere-free combination; L1 C/A and P(Y)
    /// subtract T_GD, L2 P(Y) γ T_GD); `None` for L5 and L2C, whose
    /// corrections (ISC) come in CNAV.
    pub fn group_delay_s(&self, band: char) -> Option<f64> {
        match band {
            '1' => Some(self.tgd_s),
            '2' => Some(GAMMA_L1_L2 * self.tgd_s),
            _ => None,
        }
    }

    /// Position and velocity (ECEF at `gps_time_s`, antenna phase centre as
    /// broadcast) and the L1 C/A clock correction at GPS time `gps_time_s`.
    pub fn state(&self, gps_time_s: f64) -> SatelliteState {
        self.state_at(gps_time_s, 0.0)
    }

    /// The L1 C/A state at `gps_time_s + offset_s` (see
    /// [`BroadcastOrbit::state_at`] for why the offset is separate).
    pub fn state_at(&self, gps_time_s: f64, offset_s: f64) -> SatelliteState {
        let mut s = self
            .orbit
            .state_at(&GPS, OrbitFrame::EarthFixedNode, gps_time_s, offset_s);
        s.clock_bias_s -= self.tgd_s;
        s
    }
}
