//! BeiDou D1 broadcast ephemeris (BDS-SIS-ICD-B1I 3.0 §5.2.4): the shared
//! [`BroadcastOrbit`] with BeiDou's constants (CGCS2000, §5.2.4.12), the
//! GEO satellites' frame, the accuracy index URAI (§5.2.4.5), the
//! autonomous health SatH1 (§5.2.4.6) and the group delays TGD1, TGD2
//! (§5.2.4.8).

use super::broadcast_orbit::{BroadcastOrbit, OrbitFrame, BEIDOU};
use super::satellite_state::SatelliteState;

/// A BeiDou broadcast ephemeris (angles rad, times GPS s since
/// 1980-01-06: BDT = GPS − 14 s is applied when a record is read).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeidouEphemeris {
    /// The satellite's PRN.
    pub prn: u16,
    /// Age of data, ephemeris (5 bits, §5.2.4.11): RINEX's IODE field for
    /// BeiDou.
    pub aode: u8,
    /// Age of data, clock (5 bits, §5.2.4.7): RINEX's IODC field.
    pub aodc: u8,
    /// Orbit and clock polynomial; the clock is referred to B3I (§5.2.4.10).
    pub orbit: BroadcastOrbit,
    /// User range accuracy index (4 bits, §5.2.4.5: GPS's URA table).
    pub urai: u8,
    /// Autonomous satellite health flag (0 good, 1 not, §5.2.4.6).
    pub sat_h1: u8,
    /// Equipment group delay differential of B1I to B3I, s.
    pub tgd1_s: f64,
    /// Equipment group delay differential of B2I to B3I, s.
    pub tgd2_s: f64,
    /// BDT week of the transmission (13 bits, from 2006-01-01).
    pub bdt_week: u16,
    /// Transmission time (subframe 1's start, or RINEX's), GPS s.
    pub transmission_gps_s: f64,
}

impl BeidouEphemeris {
    /// A GEO satellite (PRN 1-5 and 59-63, B1I ICD §5.2.4.12 and RINEX
    /// 3.05 §5.4), whose orbit uses [`OrbitFrame::BeidouGeo`].
    pub fn is_geo(&self) -> bool {
        matches!(self.prn, 1..=5 | 59..=63)
    }

    /// Healthy: SatH1 = 0.
    pub fn is_healthy(&self) -> bool {
        self.sat_h1 == 0
    }

    /// The group delay a single-frequency user subtracts from the clock
    /// correction on RINEX band `band` (B1I ICD §5.2.4.10: B1I (band 2)
    /// TGD1, B2I (band 7) TGD2, B3I (band 6) none: B3I is the clock's
    /// reference); `None` for other bands.
    pub fn group_delay_s(&self, band: char) -> Option<f64> {
        match band {
            '2' => Some(self.tgd1_s),
            '7' => Some(self.tgd2_s),
            '6' => Some(0.0),
            _ => None,
        }
    }

    fn frame(&self) -> OrbitFrame {
        if self.is_geo() {
            OrbitFrame::BeidouGeo
        } else {
            OrbitFrame::EarthFixedNode
        }
    }

    /// Position, velocity and the B3I clock correction at GPS time
    /// `gps_time_s + offset_s` (see [`BroadcastOrbit::state_at`]); apply
    /// [`Self::group_delay_s`] for B1I or B2I.
    pub fn state_at(&self, gps_time_s: f64, offset_s: f64) -> SatelliteState {
        self.orbit
            .state_at(&BEIDOU, self.frame(), gps_time_s, offset_s)
    }
}
