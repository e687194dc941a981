//! BeiDou D1 navigation message (MEO and IGSO satellites; BDS-SIS-ICD-B1I
//! 3.0 §5.2, the same message on B3I, BDS-SIS-ICD-B3I 1.0 §5.2) from the
//! words of UBX-RXM-SFRBX: the BCH(15,11) code of every word (§5.1.3),
//! subframes 1-3 (figures 5-4 to 5-6, table 5-9) of one 30 s frame
//! assembled into a [`BeidouEphemeris`].
//!
//! u-blox hands each 30-bit word in bits 29-0 of a 32-bit word, already
//! de-interleaved: word 1 is 15 uncoded bits (preamble, revision) then one
//! BCH codeword (11 information bits, 4 parity bits); words 2-10 are 22
//! information bits then the 4 parity bits of the first 11 and the 4 of
//! the last 11 (checked on the walk's log: every B3I D1 word passes its
//! BCH check read so). Field positions below are the ICD's bit numbers,
//! from 0, counting the parity bits, as its figures draw them.
//!
//! GEO satellites (C01-C05, C59-C63) broadcast D2, not decoded here.

use std::collections::HashMap;

use crate::gnss::{BeidouEphemeris, BroadcastOrbit, BEIDOU};

/// Words per D1 subframe.
pub(super) const WORDS: usize = 10;
/// Subframe preamble 11100010010 (§5.2.2).
const PREAMBLE: u32 = 0b111_0001_0010;
/// The value of π for semicircles (§5.2.4.12, as IS-GPS-200's).
#[allow(clippy::approx_constant)]
const BEIDOU_PI: f64 = 3.141_592_653_589_8;
/// Generator polynomial of the BCH(15,11,1) code, g(x) = x⁴ + x + 1 (§5.1.3).
const BCH_GENERATOR: u32 = 0b1_0011;
/// Seconds of a week, the range of SOW.
const SOW_LIMIT: u32 = 604_800;

/// Whether a 15-bit codeword (11 information bits then 4 parity bits)
/// is one of the code: its polynomial divides by g(x) (§5.1.3).
fn bch_valid(codeword: u32) -> bool {
    let mut r = codeword & 0x7FFF;
    for k in (4..15).rev() {
        if r >> k & 1 == 1 {
            r ^= BCH_GENERATOR << (k - 4);
        }
    }
    r == 0
}

/// Whether every BCH codeword of a subframe's ten 30-bit words checks.
pub(super) fn words_valid(words: &[u32; WORDS]) -> bool {
    words.iter().enumerate().all(|(k, &w)| {
        if k == 0 {
            bch_valid(w)
        } else {
            let info_first = w >> 19 & 0x7FF;
            let info_second = w >> 8 & 0x7FF;
            bch_valid(info_first << 4 | (w >> 4 & 0xF)) && bch_valid(info_second << 4 | (w & 0xF))
        }
    })
}

/// A subframe's 300 bits (ICD numbering from 0), read by field.
struct Subframe([u32; WORDS]);

impl Subframe {
    /// The bit at ICD position `at`.
    fn bit(&self, at: usize) -> u32 {
        self.0[at / 30] >> (29 - at % 30) & 1
    }

    /// The unsigned value of `parts` ((first bit, length), most significant
    /// part first): the ICD splits a field around parity bits.
    fn unsigned(&self, parts: &[(usize, usize)]) -> u64 {
        parts
            .iter()
            .flat_map(|&(first, len)| first..first + len)
            .fold(0, |acc, at| acc << 1 | u64::from(self.bit(at)))
    }

    /// The two's complement value of `parts`.
    fn signed(&self, parts: &[(usize, usize)]) -> f64 {
        let len: usize = parts.iter().map(|p| p.1).sum();
        let v = self.unsigned(parts);
        ((v << (64 - len)) as i64 >> (64 - len)) as f64
    }
}

/// What the D1 decoder met besides ephemerides.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct D1Stats {
    /// Subframes with a word whose BCH check failed (dropped).
    pub bch_failures: usize,
    /// Subframes without the preamble, with subframe id 0, 6 or 7, or an
    /// SOW beyond the week.
    pub malformed: usize,
}

/// Subframes 1-3 of one satellite as they arrive, with their SOW.
type Pending = [Option<(Subframe, u32)>; 3];

/// Assembles ephemerides from the subframes of every MEO/IGSO satellite.
#[derive(Default)]
pub(super) struct D1Decoder {
    pending: HashMap<u16, Pending>,
    pub ephemerides: Vec<BeidouEphemeris>,
    pub stats: D1Stats,
}

impl D1Decoder {
    /// Takes one subframe of satellite `prn` received at `reception_gps_s`
    /// (the last RAWX epoch's time, which places SOW in its week).
    pub fn push(&mut self, prn: u16, words: &[u32; WORDS], reception_gps_s: f64) {
        let words = words.map(|w| w & 0x3FFF_FFFF);
        if !words_valid(&words) {
            self.stats.bch_failures += 1;
            return;
        }
        let sf = Subframe(words);
        let id = sf.unsigned(&[(15, 3)]) as usize;
        let sow = sf.unsigned(&[(18, 8), (30, 12)]) as u32;
        if sf.unsigned(&[(0, 11)]) as u32 != PREAMBLE || !(1..=5).contains(&id) || sow >= SOW_LIMIT
        {
            self.stats.malformed += 1;
            return;
        }
        if id > 3 {
            return;
        }
        let pending = self.pending.entry(prn).or_default();
        pending[id - 1] = Some((sf, sow));
        // The three subframes of one frame: SOW 6 s apart (§5.2.2).
        let [Some((s1, sow1)), Some((s2, sow2)), Some((s3, sow3))] = pending else {
            return;
        };
        if *sow2 != *sow1 + 6 || *sow3 != *sow2 + 6 {
            return;
        }
        if let Some(e) = assemble(prn, [s1, s2, s3], *sow1, reception_gps_s) {
            let known = self.ephemerides.iter().any(|k| {
                k.prn == prn && k.aode == e.aode && k.orbit.toe_gps_s == e.orbit.toe_gps_s
            });
            if !known {
                self.ephemerides.push(e);
            }
        }
    }
}

/// The ephemeris of subframes 1-3 of one frame when subframe 1's week is
/// that of its transmission and t_oc equals t_oe (as the D1 message
/// broadcasts them, §5.2.4.9 and §5.2.4.11); `None` otherwise.
fn assemble(
    prn: u16,
    [s1, s2, s3]: [&Subframe; 3],
    sow1: u32,
    reception_gps_s: f64,
) -> Option<BeidouEphemeris> {
    let transmission_gps_s = BEIDOU.nearest_gps_time_s(f64::from(sow1), reception_gps_s);
    let bdt_week = s1.unsigned(&[(60, 13)]) as u16;
    if BEIDOU.week(transmission_gps_s).rem_euclid(8192.0) != f64::from(bdt_week) {
        return None;
    }
    let toc_sow = s1.unsigned(&[(73, 9), (90, 8)]) as f64 * 8.0;
    let toe_sow = (s2.unsigned(&[(290, 2)]) << 15 | s3.unsigned(&[(42, 10), (60, 5)])) as f64 * 8.0;
    if toc_sow != toe_sow || toe_sow >= f64::from(SOW_LIMIT) {
        return None;
    }
    let (sc, p) = (BEIDOU_PI, |k: i32| 2f64.powi(k));
    let toe_gps_s = BEIDOU.nearest_gps_time_s(toe_sow, transmission_gps_s);
    Some(BeidouEphemeris {
        prn,
        aode: s1.unsigned(&[(287, 5)]) as u8,
        aodc: s1.unsigned(&[(43, 5)]) as u8,
        orbit: BroadcastOrbit {
            toc_gps_s: toe_gps_s,
            toe_gps_s,
            af0_s: s1.signed(&[(225, 7), (240, 17)]) * p(-33),
            af1_s_s: s1.signed(&[(257, 5), (270, 17)]) * p(-50),
            af2_s_s2: s1.signed(&[(214, 11)]) * p(-66),
            delta_n_rad_s: s2.signed(&[(42, 10), (60, 6)]) * p(-43) * sc,
            cuc_rad: s2.signed(&[(66, 16), (90, 2)]) * p(-31),
            m0_rad: s2.signed(&[(92, 20), (120, 12)]) * p(-31) * sc,
            eccentricity: s2.unsigned(&[(132, 10), (150, 22)]) as f64 * p(-33),
            cus_rad: s2.signed(&[(180, 18)]) * p(-31),
            crc_m: s2.signed(&[(198, 4), (210, 14)]) * p(-6),
            crs_m: s2.signed(&[(224, 8), (240, 10)]) * p(-6),
            sqrt_a_sqrt_m: s2.unsigned(&[(250, 12), (270, 20)]) as f64 * p(-19),
            i0_rad: s3.signed(&[(65, 17), (90, 15)]) * p(-31) * sc,
            cic_rad: s3.signed(&[(105, 7), (120, 11)]) * p(-31),
            omega_dot_rad_s: s3.signed(&[(131, 11), (150, 13)]) * p(-43) * sc,
            cis_rad: s3.signed(&[(163, 9), (180, 9)]) * p(-31),
            idot_rad_s: s3.signed(&[(189, 13), (210, 1)]) * p(-43) * sc,
            omega0_rad: s3.signed(&[(211, 21), (240, 11)]) * p(-31) * sc,
            omega_rad: s3.signed(&[(251, 11), (270, 21)]) * p(-31) * sc,
            a_dot_m_s: 0.0,
            delta_n_dot_rad_s2: 0.0,
        },
        urai: s1.unsigned(&[(48, 4)]) as u8,
        sat_h1: s1.unsigned(&[(42, 1)]) as u8,
        tgd1_s: s1.signed(&[(98, 10)]) * 1e-10,
        tgd2_s: s1.signed(&[(108, 4), (120, 6)]) * 1e-10,
        bdt_week,
        transmission_gps_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 4 parity bits of 11 information bits: the remainder of
    /// x⁴ · m(x) by g(x), by long division written out independently of
    /// [`bch_valid`]'s loop (§5.1.3, figure 5-2's encoder).
    fn parity(info: u32) -> u32 {
        // Shift register of the encoder: feedback at x⁰ and x¹.
        let mut reg = [0u32; 4];
        for k in (0..11).rev() {
            let feedback = (info >> k & 1) ^ reg[3];
            reg = [feedback, reg[0] ^ feedback, reg[1], reg[2]];
        }
        reg[3] << 3 | reg[2] << 2 | reg[1] << 1 | reg[0]
    }

    #[test]
    fn every_encoded_codeword_checks_and_every_single_flip_fails() {
        for info in [0u32, 1, 0x7FF, 0x555, 0x2AA, 0x123] {
            let cw = info << 4 | parity(info);
            assert!(bch_valid(cw), "{info:#x}");
            for bit in 0..15 {
                assert!(!bch_valid(cw ^ 1 << bit), "{info:#x} flip {bit}");
            }
        }
    }

    #[test]
    fn failed_and_malformed_subframes_are_counted() {
        // All-zero words are codewords, but not a subframe (no preamble).
        let mut decoder = D1Decoder::default();
        let zeros = [0u32; WORDS];
        decoder.push(21, &zeros, 1.44e9);
        assert_eq!(decoder.stats.malformed, 1);
        // One flipped bit anywhere is a BCH failure.
        for bit in [0, 14, 15, 29] {
            for word in [0, 4, 9] {
                let mut bad = zeros;
                bad[word] ^= 1 << bit;
                decoder.push(21, &bad, 1.44e9);
            }
        }
        // Bits 0-14 of word 1 (preamble, revision) are not coded.
        assert_eq!(decoder.stats.bch_failures, 10);
        assert_eq!(decoder.stats.malformed, 3);
        assert!(decoder.ephemerides.is_empty());
    }
}
