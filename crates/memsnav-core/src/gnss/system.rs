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
    /// GPS, the reference of the receiver clock (no inter-system bias).
    #[default]
    Gps,
    /// Galileo.
    Galileo,
    /// BeiDou.
    Beidou,
    /// GLONASS (FDMA): each satellite on its own carrier (G1 = 1602 +
    /// 0.5625 k MHz, k its slot's frequency channel), so that its Doppler
    /// and carrier phase scale by its own wavelength.
    Glonass,
}

/// Systems whose pseudoranges have an inter-system bias state in the
/// tight filter. GLONASS's also absorbs the average of the receiver's
/// inter-frequency biases over the slots in view; what each slot's bias
/// differs from that average by (decimetres to a few metres on a
/// mass-market receiver) is left to the range-bias states, when the
/// filter has them, or to the pseudorange noise.
pub const INTER_SYSTEM_BIAS_SYSTEMS: [GnssSystem; 3] =
    [GnssSystem::Galileo, GnssSystem::Beidou, GnssSystem::Glonass];

/// The inter-system biases (Galileo, BeiDou, GLONASS against GPS, m) from
/// the values a caller gives: all three, or the two of Galileo and BeiDou
/// (the layout before GLONASS was added; GLONASS's is then 0). `argument`
/// names the value in the error.
pub fn inter_system_biases(
    argument: &str,
    values: &[f64],
) -> crate::Result<[f64; INTER_SYSTEM_BIAS_SYSTEMS.len()]> {
    match *values {
        [galileo, beidou] => Ok([galileo, beidou, 0.0]),
        [galileo, beidou, glonass] => Ok([galileo, beidou, glonass]),
        _ => Err(crate::Error::invalid(
            argument,
            format!(
                "expected 2 (Galileo, BeiDou) or 3 (Galileo, BeiDou, GLONASS) biases against GPS, m, got {}",
                values.len()
            ),
        )),
    }
}

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

    /// The systems the tight filter and the simulator combine: all of them.
    pub const FILTERED: [GnssSystem; 4] = Self::ALL;

    /// The default systems of the multi-system measurements: GPS, Galileo
    /// and BeiDou. GLONASS is asked for by name (`R`): its broadcast orbits
    /// are the least accurate (RTKLIB's 5 m against GPS's 2.4 m) and each
    /// slot's receiver inter-frequency bias adds decimetres to metres that
    /// no state carries, so a run that has enough of the others gains
    /// little from it.
    pub const DEFAULT_MEASURED: [GnssSystem; 3] =
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
    /// (0 Galileo, 1 BeiDou, 2 GLONASS); `None` for GPS, the clock's
    /// reference.
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
        assert_eq!(GnssSystem::Glonass.inter_system_bias_index(), Some(2));
        assert_eq!(GnssSystem::Glonass.fix_bias_index(), Some(2));
    }
}
