//! Galileo I/NAV on E1-B (Galileo OS SIS ICD issue 2.1, §4.3) from the
//! words of UBX-RXM-SFRBX: the even and odd page of each page pair
//! checked by their CRC-24Q (§4.3.2.3: over the even page's 114 bits
//! before its tail and the odd page's first 82 bits), the 128-bit words
//! they carry (112 bits of the even page, 16 of the odd), and word types
//! 1-5 (tables 40-44) assembled into an ephemeris when types 1-4 carry the
//! same IODnav (§5.1.9.2).
//!
//! u-blox hands a page pair as 8 words of 32 bits, most significant bit
//! first: the even page's 120 bits in bits 0-119, the odd page's in bits
//! 128-247 (checked on the walk's log: every E1-B pair passes its CRC read
//! so).
//!
//! The records are kept with their health and accuracy flags; their orbit
//! and clock are [`InavEphemeris::state_at`]'s (Galileo's constants).

use std::collections::HashMap;

use super::msb_bits::{bits, crc24q, gather, signed, word_bytes};
use crate::gnss::{BroadcastOrbit, InavEphemeris, GALILEO, SECONDS_PER_WEEK};

/// Words per E1-B page pair in RXM-SFRBX.
pub(super) const WORDS: usize = 8;
/// The value of π the ICD fixes for semicircles (§5.1.1), as IS-GPS-200's.
#[allow(clippy::approx_constant)]
const GALILEO_PI: f64 = 3.141_592_653_589_8;

/// What the I/NAV decoder met besides ephemerides.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct InavStats {
    pub crc_failures: usize,
    /// Pairs whose even/odd flags are not 0 then 1 (a page lost).
    pub unpaired: usize,
    /// Alert pages (page type 1), not read.
    pub alerts: usize,
}

/// Assembles ephemerides from the words of every satellite.
#[derive(Debug, Default)]
pub(super) struct InavDecoder {
    words: HashMap<u16, [Option<[u8; 16]>; 5]>,
    pub ephemerides: Vec<InavEphemeris>,
    pub stats: InavStats,
}

impl InavDecoder {
    /// Takes one page pair of satellite `svid` received at `reception_gps_s`.
    pub fn push(&mut self, svid: u16, words: &[u32; WORDS], reception_gps_s: f64) {
        let pair: [u8; 4 * WORDS] = word_bytes(words);
        const ODD: usize = 128;
        if bits(&pair, 0, 1) != 0 || bits(&pair, ODD, 1) != 1 {
            self.stats.unpaired += 1;
            return;
        }
        if bits(&pair, 1, 1) == 1 || bits(&pair, ODD + 1, 1) == 1 {
            self.stats.alerts += 1;
            return;
        }
        // 114 + 82 bits in one run for the CRC.
        let crc_input: [u8; 25] = gather(&pair, (0..114).chain(ODD..ODD + 82));
        if u64::from(crc24q(&crc_input, 0, 196)) != bits(&pair, ODD + 82, 24) {
            self.stats.crc_failures += 1;
            return;
        }
        // The word: even page bits 2-113, odd page bits 2-17.
        let word: [u8; 16] = gather(&pair, (2..114).chain(ODD + 2..ODD + 18));
        let kind = bits(&word, 0, 6) as usize;
        if !(1..=5).contains(&kind) {
            return;
        }
        let slots = self.words.entry(svid).or_default();
        slots[kind - 1] = Some(word);
        if let [Some(w1), Some(w2), Some(w3), Some(w4), Some(w5)] = *slots {
            if let Some(e) = assemble(svid, [&w1, &w2, &w3, &w4, &w5], reception_gps_s) {
                let known = self.ephemerides.iter().any(|k| {
                    k.svid == svid
                        && k.iod_nav == e.iod_nav
                        && k.orbit.toe_gps_s == e.orbit.toe_gps_s
                });
                if !known {
                    self.ephemerides.push(e);
                }
            }
        }
    }
}

/// The ephemeris of word types 1-5 when types 1-4 share their IODnav and
/// word 4's SVID is the satellite's; `None` during an update.
fn assemble(svid: u16, w: [&[u8; 16]; 5], reception_gps_s: f64) -> Option<InavEphemeris> {
    let iod = bits(w[0], 6, 10);
    if w[1..4].iter().any(|x| bits(*x, 6, 10) != iod) || bits(w[3], 16, 6) != u64::from(svid) {
        return None;
    }
    let (sc, p) = (GALILEO_PI, |k: i32| 2f64.powi(k));
    let [w1, w2, w3, w4, w5] = w;
    let gst_week = bits(w5, 73, 12) as u16;
    // Word 5's 12-bit GST week must agree with the reception time.
    let reception_gst_week =
        (reception_gps_s / SECONDS_PER_WEEK - GALILEO.week_zero_in_gps_weeks).floor();
    if (reception_gst_week as u32) % 4096 != u32::from(gst_week) {
        return None;
    }
    Some(InavEphemeris {
        svid,
        iod_nav: iod as u16,
        orbit: BroadcastOrbit {
            toe_gps_s: GALILEO.nearest_gps_time_s(bits(w1, 16, 14) as f64 * 60.0, reception_gps_s),
            m0_rad: signed(bits(w1, 30, 32), 32) * p(-31) * sc,
            eccentricity: bits(w1, 62, 32) as f64 * p(-33),
            sqrt_a_sqrt_m: bits(w1, 94, 32) as f64 * p(-19),
            omega0_rad: signed(bits(w2, 16, 32), 32) * p(-31) * sc,
            i0_rad: signed(bits(w2, 48, 32), 32) * p(-31) * sc,
            omega_rad: signed(bits(w2, 80, 32), 32) * p(-31) * sc,
            idot_rad_s: signed(bits(w2, 112, 14), 14) * p(-43) * sc,
            omega_dot_rad_s: signed(bits(w3, 16, 24), 24) * p(-43) * sc,
            delta_n_rad_s: signed(bits(w3, 40, 16), 16) * p(-43) * sc,
            cuc_rad: signed(bits(w3, 56, 16), 16) * p(-29),
            cus_rad: signed(bits(w3, 72, 16), 16) * p(-29),
            crc_m: signed(bits(w3, 88, 16), 16) * p(-5),
            crs_m: signed(bits(w3, 104, 16), 16) * p(-5),
            cic_rad: signed(bits(w4, 22, 16), 16) * p(-29),
            cis_rad: signed(bits(w4, 38, 16), 16) * p(-29),
            toc_gps_s: GALILEO.nearest_gps_time_s(bits(w4, 54, 14) as f64 * 60.0, reception_gps_s),
            af0_s: signed(bits(w4, 68, 31), 31) * p(-34),
            af1_s_s: signed(bits(w4, 99, 21), 21) * p(-46),
            af2_s_s2: signed(bits(w4, 120, 6), 6) * p(-59),
            a_dot_m_s: 0.0,
            delta_n_dot_rad_s2: 0.0,
        },
        sisa_index: bits(w3, 120, 8) as u8,
        bgd_e1_e5a_s: signed(bits(w5, 47, 10), 10) * p(-32),
        bgd_e1_e5b_s: signed(bits(w5, 57, 10), 10) * p(-32),
        e5b_health: bits(w5, 67, 2) as u8,
        e1b_health: bits(w5, 69, 2) as u8,
        e5b_data_validity: bits(w5, 71, 1) as u8,
        e1b_data_validity: bits(w5, 72, 1) as u8,
        gst_week,
        transmission_gps_s: (f64::from(gst_week)
            + GALILEO.week_zero_in_gps_weeks
            + 4096.0 * ((reception_gst_week - f64::from(gst_week)) / 4096.0).round())
            * SECONDS_PER_WEEK
            + bits(w5, 85, 20) as f64,
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn sisa_bins() {
        use crate::gnss::sisa_m;
        assert_eq!(sisa_m(107), Some(2.0 + 0.16 * 7.0));
        assert_eq!(sisa_m(49), Some(0.49));
        assert_eq!(sisa_m(50), Some(0.5));
        assert_eq!(sisa_m(255), None);
    }
}
