//! Galileo I/NAV broadcast ephemeris (OS SIS ICD issue 2.1): the shared
//! [`BroadcastOrbit`] with Galileo's constants (§5.1.1), the accuracy
//! (SISA, §5.1.11), health and data validity (§5.1.9.3), and the
//! broadcast group delays (§5.1.5).

use super::broadcast_orbit::{BroadcastOrbit, OrbitFrame, GALILEO};
use super::satellite_state::SatelliteState;

/// (f_E1 / f_E5b)² with 1575.42 and 1207.14 MHz (ICD §5.1.5).
const E1_E5B_FREQUENCY_RATIO_SQUARED: f64 = (1575.42 * 1575.42) / (1207.14 * 1207.14);
/// (f_E1 / f_E5a)² with 1575.42 and 1176.45 MHz.
const E1_E5A_FREQUENCY_RATIO_SQUARED: f64 = (1575.42 * 1575.42) / (1176.45 * 1176.45);

/// A Galileo I/NAV ephemeris (angles rad, times GPS s since 1980-01-06:
/// GST weeks start with GPS weeks and GST is steered to GPS time within
/// tens of ns).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InavEphemeris {
    /// The satellite's SVID (its RINEX satellite number).
    pub svid: u16,
    /// Issue of data of the navigation batch (§5.1.9.2).
    pub iod_nav: u16,
    /// Orbit and clock polynomial; the I/NAV clock is referred to the
    /// E1/E5b ionosphere-free combination (§5.1.5).
    pub orbit: BroadcastOrbit,
    /// Signal-in-space accuracy index (§5.1.11; 255: no accuracy prediction).
    pub sisa_index: u8,
    /// Broadcast group delay E1-E5a (for the F/NAV clock), s.
    pub bgd_e1_e5a_s: f64,
    /// Broadcast group delay E1-E5b (for this, the I/NAV clock), s.
    pub bgd_e1_e5b_s: f64,
    /// Signal health of E1-B (0 OK, 1 out of service, 2 extended
    /// operations, 3 in test; §5.1.9.3).
    pub e1b_health: u8,
    /// Signal health of E5b, as E1-B's.
    pub e5b_health: u8,
    /// Data validity of E1-B (0 valid, 1 working without guarantee).
    pub e1b_data_validity: u8,
    /// Data validity of E5b, as E1-B's.
    pub e5b_data_validity: u8,
    /// GST week of t_oe's transmission (12 bits, counted from 1999-08-22).
    pub gst_week: u16,
    /// Transmission time (word type 5's GST week and time of week, or
    /// RINEX's), GPS s since 1980-01-06.
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

/// The SISA index of `metres` (the inverse of [`sisa_m`], to the nearest
/// bin; 255 for a negative or beyond-table value, as RINEX writes
/// "no accuracy prediction" −1).
pub fn sisa_index(metres: f64) -> u8 {
    (0..=125u8)
        .filter_map(|n| sisa_m(n).map(|m| (n, (m - metres).abs())))
        .filter(|&(_, d)| d < 0.005)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(255, |(n, _)| n)
}

impl InavEphemeris {
    /// Healthy and valid on E1-B (health 0, data valid).
    pub fn is_healthy(&self) -> bool {
        self.e1b_health == 0 && self.e1b_data_validity == 0
    }

    /// The group delay a user subtracts from the I/NAV clock correction on
    /// RINEX band `band`: E1 BGD(E1,E5b), E5b (f_E1/f_E5b)² BGD(E1,E5b) (ICD
    /// §5.1.5), E5a BGD(E1,E5b) + ((f_E1/f_E5a)² − 1) BGD(E1,E5a) (from the
    /// definition BGD(f1,f2) = (TR1 − TR2) / (1 − (f1/f2)²): TR_E5a − TR_E1
    /// added to E1's delay); `None` for E6.
    pub fn group_delay_s(&self, band: char) -> Option<f64> {
        match band {
            '1' => Some(self.bgd_e1_e5b_s),
            '5' => {
                Some(self.bgd_e1_e5b_s + (E1_E5A_FREQUENCY_RATIO_SQUARED - 1.0) * self.bgd_e1_e5a_s)
            }
            '7' => Some(E1_E5B_FREQUENCY_RATIO_SQUARED * self.bgd_e1_e5b_s),
            _ => None,
        }
    }

    /// Position, velocity and the E1 clock correction at GPS time
    /// `gps_time_s + offset_s` (see [`BroadcastOrbit::state_at`]).
    pub fn state_at(&self, gps_time_s: f64, offset_s: f64) -> SatelliteState {
        let mut s = self
            .orbit
            .state_at(&GALILEO, OrbitFrame::EarthFixedNode, gps_time_s, offset_s);
        s.clock_bias_s -= self.bgd_e1_e5b_s;
        s
    }
}
