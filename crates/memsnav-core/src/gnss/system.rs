//! The satellite systems the filters combine, and one satellite number per
//! satellite across them.
//!
//! The filters, their records and the range-bias slots key a satellite by
//! one `u16`. With several systems a PRN is no longer unique (G10 and E10),
//! so a broadcast satellite's number is its PRN plus its system's offset:
//! GPS G n → n, Galileo E n → 100 + n, BeiDou C n → 200 + n, GLONASS
//! R n (the orbital slot) → 300 + n ([`satellite_number`], [`satellite_name`]). Simulated Walker slots keep
//! their slot numbers plus their system's offset, so tables and arrays that
//! carry only the number say the system too ([`system_of_number`]).

use std::fmt;

/// A satellite system. GPS is the reference of the receiver clock; each
/// other system's pseudoranges carry an inter-system bias (ISB) the tight
/// filter estimates ([`crate::filter::state::Layout::inter_system_bias`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub enum GnssSystem {
    #[default]
    Gps,
    Galileo,
    Beidou,
    /// GLONASS (FDMA): single-point positioning only; the tight filter and
    /// the simulator do not take it.
    Glonass,
}

/// Systems whose pseudoranges have an inter-system bias state in the
/// tight filter.
pub const INTER_SYSTEM_BIAS_SYSTEMS: [GnssSystem; 2] = [GnssSystem::Galileo, GnssSystem::Beidou];

/// Systems whose pseudoranges have an inter-system bias in the
/// least-squares fix ([`crate::gnss::Fix::inter_system_bias_m`] order).
pub const FIX_BIAS_SYSTEMS: [GnssSystem; 3] =
    [GnssSystem::Galileo, GnssSystem::Beidou, GnssSystem::Glonass];

impl GnssSystem {
    /// Every system, in the order of their satellite-number offsets.
    pub const ALL: [GnssSystem; 4] = [
        GnssSystem::Gps,
        GnssSystem::Galileo,
        GnssSystem::Beidou,
        GnssSystem::Glonass,
    ];

    /// The systems the tight filter and the simulator combine (GLONASS
    /// not yet), the default of the multi-system measurements.
    pub const FILTERED: [GnssSystem; 3] =
        [GnssSystem::Gps, GnssSystem::Galileo, GnssSystem::Beidou];

    /// The RINEX system letter.
    pub fn letter(self) -> char {
        match self {
            GnssSystem::Gps => 'G',
            GnssSystem::Galileo => 'E',
            GnssSystem::Beidou => 'C',
            GnssSystem::Glonass => 'R',
        }
    }

    /// The system of a RINEX letter; `None` for systems not combined.
    pub fn from_letter(letter: char) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.letter() == letter)
    }

    /// The index of this system's inter-system bias in the tight filter
    /// (0 Galileo, 1 BeiDou); `None` for GPS, the clock's reference, and
    /// GLONASS, which the filter does not take.
    pub fn inter_system_bias_index(self) -> Option<usize> {
        INTER_SYSTEM_BIAS_SYSTEMS.iter().position(|&s| s == self)
    }

    /// The index of this system's bias in a least-squares fix (0 Galileo,
    /// 1 BeiDou, 2 GLONASS); `None` for GPS.
    pub fn fix_bias_index(self) -> Option<usize> {
        FIX_BIAS_SYSTEMS.iter().position(|&s| s == self)
    }

    fn number_offset(self) -> u16 {
        match self {
            GnssSystem::Gps => 0,
            GnssSystem::Galileo => 100,
            GnssSystem::Beidou => 200,
            GnssSystem::Glonass => 300,
        }
    }
}

impl fmt::Display for GnssSystem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            GnssSystem::Gps => "GPS",
            GnssSystem::Galileo => "Galileo",
            GnssSystem::Beidou => "BeiDou",
            GnssSystem::Glonass => "GLONASS",
        })
    }
}

/// The satellite number of `system`'s PRN `prn` (1-99).
pub fn satellite_number(system: GnssSystem, prn: u16) -> u16 {
    system.number_offset() + prn
}

/// The system a satellite number says ([`satellite_number`]): 101-199
/// Galileo, 201-299 BeiDou, 301-399 GLONASS, any other GPS (a GPS PRN or
/// a Walker slot).
/// Tables and arrays of measurements carry only the number.
pub fn system_of_number(number: u16) -> GnssSystem {
    match number {
        101..=199 => GnssSystem::Galileo,
        201..=299 => GnssSystem::Beidou,
        301..=399 => GnssSystem::Glonass,
        _ => GnssSystem::Gps,
    }
}

/// The RINEX name (`G10`, `E07`, `C21`) of a broadcast satellite number;
/// a number beyond the offsets reads as a plain number.
pub fn satellite_name(number: u16) -> String {
    match GnssSystem::ALL
        .into_iter()
        .rev()
        .find(|s| number > s.number_offset())
    {
        Some(s) if number - s.number_offset() < 100 => {
            format!("{}{:02}", s.letter(), number - s.number_offset())
        }
        _ => number.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_names_round_trip() {
        for system in GnssSystem::ALL {
            for prn in [1, 7, 63] {
                let name = satellite_name(satellite_number(system, prn));
                assert_eq!(name, format!("{}{prn:02}", system.letter()));
                assert_eq!(GnssSystem::from_letter(system.letter()), Some(system));
                assert_eq!(system_of_number(satellite_number(system, prn)), system);
            }
        }
        assert_eq!(GnssSystem::from_letter('R'), Some(GnssSystem::Glonass));
        assert_eq!(GnssSystem::from_letter('J'), None);
        assert_eq!(satellite_name(305), "R05");
        assert_eq!(GnssSystem::Gps.inter_system_bias_index(), None);
        assert_eq!(GnssSystem::Beidou.inter_system_bias_index(), Some(1));
        assert_eq!(GnssSystem::Glonass.inter_system_bias_index(), None);
        assert_eq!(GnssSystem::Glonass.fix_bias_index(), Some(2));
    }
}
