//! GLONASS L1OF/L2OF navigation strings (ICD edition 5.1, 2008, §4.4)
//! from the words of UBX-RXM-SFRBX: each string's 85 bits checked by its
//! Hamming code (§4.7), the immediate data of strings 1-4 (table 4.5) and
//! the time data of string 5 assembled into a [`GlonassEphemeris`].
//!
//! u-blox hands a string as four words of 32 bits: the string's bits 85
//! (the idle chip, 0) down to 1 (the Hamming code) in the first 85 bits,
//! most significant first, then 11 padding bits, then the frame and
//! superframe numbers in the fourth word (not read). Bit `i` of the
//! record below is the ICD's bit 85 − i.
//!
//! Fields (ICD table 4.5), positions counted from the idle chip:
//!
//! | string | fields |
//! |---|---|
//! | 1 | P1 (7, 2), t_k (9, 12: h 5, min 6, 30 s 1), ẋ (21, 24), ẍ (45, 5), x (50, 27) |
//! | 2 | B_n (5, 3), P2 (8, 1), t_b (9, 7, × 15 min), ẏ (21, 24), ÿ (45, 5), y (50, 27) |
//! | 3 | P3 (5, 1), γ_n (6, 11), P (18, 2), l_n (20, 1), ż (21, 24), z̈ (45, 5), z (50, 27) |
//! | 4 | τ_n (5, 22), Δτ_n (27, 5), E_n (32, 5), P4 (51, 1), F_T (52, 4), N_T (59, 11), n (70, 5), M (75, 2) |
//! | 5 | N^A (5, 11), τ_c (16, 32), N4 (49, 5), τ_GPS (54, 22), l_n (76, 1) |
//!
//! Every signed field is sign and magnitude (the MSB the sign), not two's
//! complement. Positions are 2⁻¹¹ km, velocities 2⁻²⁰ km/s, accelerations
//! 2⁻³⁰ km/s², τ_n 2⁻³⁰ s, γ_n 2⁻⁴⁰.
//!
//! Strings 1-4 make an ephemeris when they arrive within one 30 s frame
//! (they are its first four strings, 2 s apart). t_b is a time of day in
//! Moscow time (UTC(SU) + 3 h): its day is the one of N_T and N4 (string
//! 4's day in the four-year interval, string 5's interval since 1996) when
//! string 5 has been read and agrees with the reception time to a day,
//! else the day that puts t_b nearest the reception time. The health
//! written is RINEX's: the MSB of B_n, with string 3's l_n in bit 2.

use std::collections::HashMap;

use nalgebra::Vector3;

use super::msb_bits::{bits, word_bytes};
use crate::gnss::{gps_minus_utc_s, GlonassEphemeris};

/// Words per GLONASS string in RXM-SFRBX.
pub(super) const WORDS: usize = 4;
/// Bits of a string.
const STRING_BITS: usize = 85;
/// Moscow time minus UTC, s.
const MOSCOW_MINUS_UTC_S: f64 = 3.0 * 3600.0;
const DAY_S: f64 = 86_400.0;
/// Days from the GPS epoch (1980-01-06) to 1996-01-01, the start of
/// GLONASS's first four-year interval (N4 = 1).
const GPS_EPOCH_TO_1996_DAYS: f64 = 5839.0;
/// Strings 1-4 arrive within this span of each other (one frame is 30 s).
const FRAME_S: f64 = 30.0;

/// What the GLONASS decoder met besides ephemerides.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct GlonassStats {
    /// Strings whose Hamming code or idle chip is wrong.
    pub hamming_failures: usize,
    /// Strings 1-4 that did not make an ephemeris: not within one frame,
    /// a slot different from the one the receiver reports, or a channel
    /// outside −7..+6.
    pub inconsistent: usize,
    /// Ephemerides with a position, velocity or acceleration beyond what
    /// a GLONASS orbit has (the RINEX reader's limits, ICD table 4.5's
    /// ranges): a string whose code checks by chance.
    pub out_of_range: usize,
}

/// A string's first 12 bytes (its 85 bits and padding) and its reception
/// time, GPS s.
type Received = ([u8; 12], f64);

/// Assembles ephemerides from the strings of every satellite.
#[derive(Debug, Default)]
pub(super) struct GlonassDecoder {
    /// Per slot, strings 1-4 with their reception times.
    strings: HashMap<u16, [Option<Received>; 4]>,
    /// The latest string 5's four-year interval N4.
    four_year_interval: Option<u64>,
    pub ephemerides: Vec<GlonassEphemeris>,
    pub stats: GlonassStats,
}

/// `len` bits from `first` as a sign-and-magnitude number (ICD §4.4: the
/// MSB is the sign, 1 negative).
fn sign_magnitude(data: &[u8], first: usize, len: usize) -> f64 {
    let magnitude = bits(data, first + 1, len - 1) as f64;
    if bits(data, first, 1) == 1 {
        -magnitude
    } else {
        magnitude
    }
}

/// The Hamming position (1-84, powers of two left to the check bits) of
/// the ICD's data bits b9..b85: the 77 positions that are not powers of
/// two, in order.
const fn hamming_positions() -> [u8; 77] {
    let mut out = [0u8; 77];
    let (mut p, mut k) = (1u8, 0usize);
    while k < 77 {
        if !p.is_power_of_two() {
            out[k] = p;
            k += 1;
        }
        p += 1;
    }
    out
}
const HAMMING_POSITIONS: [u8; 77] = hamming_positions();

/// The ICD's bit `k` (85 the idle chip … 1) of a string.
fn icd_bit(string: &[u8], k: usize) -> u8 {
    bits(string, STRING_BITS - k, 1) as u8
}

/// Whether the string's Hamming code checks (ICD §4.7): each check bit
/// β_i (i = 1-7) is the XOR of the data bits b9..b85 whose Hamming
/// position has bit i − 1 set, and β8 makes the XOR of all 85 bits zero.
/// Only an error-free string is taken (the ICD's single-error correction
/// is not applied).
pub(super) fn hamming_checks(string: &[u8]) -> bool {
    let parity_ok = (0..7).all(|i| {
        let data = (9..=85)
            .zip(HAMMING_POSITIONS)
            .filter(|(_, p)| p >> i & 1 == 1)
            .fold(0, |acc, (k, _)| acc ^ icd_bit(string, k));
        data == icd_bit(string, i + 1)
    });
    let overall = (1..=85).fold(0, |acc, k| acc ^ icd_bit(string, k));
    parity_ok && overall == 0
}

impl GlonassDecoder {
    /// Takes one string of the satellite in slot `sv_id` (1-24) on
    /// frequency channel `freq_id` − 7, received at `reception_gps_s`.
    pub fn push(&mut self, sv_id: u8, freq_id: u8, words: &[u32; WORDS], reception_gps_s: f64) {
        let string: [u8; 4 * WORDS] = word_bytes(words);
        if bits(&string, 0, 1) != 0 || !hamming_checks(&string) {
            self.stats.hamming_failures += 1;
            return;
        }
        let mut record = [0u8; 12];
        record.copy_from_slice(&string[..12]);
        match bits(&record, 1, 4) {
            m @ 1..=4 => {
                let slot = u16::from(sv_id);
                let strings = self.strings.entry(slot).or_default();
                strings[m as usize - 1] = Some((record, reception_gps_s));
                if m == 4 {
                    self.assemble(sv_id, freq_id, reception_gps_s);
                }
            }
            5 => self.four_year_interval = Some(bits(&record, 49, 5)).filter(|&n| n > 0),
            _ => {}
        }
    }

    /// The ephemeris of slot `sv_id`'s strings 1-4, once string 4 came.
    fn assemble(&mut self, sv_id: u8, freq_id: u8, reception_gps_s: f64) {
        let Some(strings) = self.strings.get(&u16::from(sv_id)) else {
            return;
        };
        let [Some((s1, t1)), Some((s2, t2)), Some((s3, t3)), Some((s4, t4))] = *strings else {
            return;
        };
        // One frame's strings: 1 before 2 before 3 before 4, within 30 s.
        if !(t1 <= t2 && t2 <= t3 && t3 <= t4 && t4 - t1 < FRAME_S) {
            return;
        }
        let slot = bits(&s4, 70, 5) as u16;
        let channel = i16::from(freq_id) - 7;
        if u16::from(sv_id) != slot || !(1..=24).contains(&slot) || !(-7..=6).contains(&channel) {
            self.stats.inconsistent += 1;
            return;
        }
        let tb_gps_s =
            match reference_time_gps_s(&s2, &s4, self.four_year_interval, reception_gps_s) {
                Some(t) => t,
                None => {
                    self.stats.inconsistent += 1;
                    return;
                }
            };
        let axis = |s: &[u8; 12]| {
            (
                sign_magnitude(s, 50, 27) * 2f64.powi(-11) * 1e3,
                sign_magnitude(s, 21, 24) * 2f64.powi(-20) * 1e3,
                sign_magnitude(s, 45, 5) * 2f64.powi(-30) * 1e3,
            )
        };
        let (x, y, z) = (axis(&s1), axis(&s2), axis(&s3));
        // The ICD's ranges (table 4.5), which the fields' bits exceed: ±2.7e4
        // km, ±4.3 km/s, ±6.2e-9 km/s² (`gnss::rinex_nav_glonass` refuses
        // a record beyond them).
        let within =
            |(r, v, a): (f64, f64, f64)| r.abs() <= 2.7e7 && v.abs() <= 4.3e3 && a.abs() <= 6.2e-6;
        if !(within(x) && within(y) && within(z)) {
            self.stats.out_of_range += 1;
            return;
        }
        let ephemeris = GlonassEphemeris {
            slot,
            frequency_channel: channel as i8,
            tb_gps_s,
            tau_n_s: sign_magnitude(&s4, 5, 22) * 2f64.powi(-30),
            gamma_n: sign_magnitude(&s3, 6, 11) * 2f64.powi(-40),
            position_ecef: Vector3::new(x.0, y.0, z.0),
            velocity_ecef: Vector3::new(x.1, y.1, z.1),
            lunisolar_m_s2: Vector3::new(x.2, y.2, z.2),
            health: (bits(&s2, 5, 1) | bits(&s3, 20, 1) << 2) as u8,
            age_days: bits(&s4, 32, 5) as u8,
        };
        let known = self
            .ephemerides
            .iter()
            .any(|k| k.slot == slot && k.tb_gps_s == tb_gps_s);
        if !known {
            self.ephemerides.push(ephemeris);
        }
    }
}

/// t_b of string 2 as GPS time: its day from N_T (string 4) and N4 (string
/// 5) when both are known and agree with the reception time to a day,
/// else the day that puts it nearest the reception (module docs). `None`
/// for a t_b the ICD does not allow (beyond 95 quarter hours).
fn reference_time_gps_s(
    s2: &[u8; 12],
    s4: &[u8; 12],
    four_year_interval: Option<u64>,
    reception_gps_s: f64,
) -> Option<f64> {
    let tb = bits(s2, 9, 7);
    if !(1..=95).contains(&tb) {
        return None;
    }
    let tb_of_day_s = tb as f64 * 900.0;
    let leap_s = gps_minus_utc_s(reception_gps_s);
    // Moscow time counted like GPS time (s since 1980-01-06 00:00).
    let reception_moscow_s = reception_gps_s - leap_s + MOSCOW_MINUS_UTC_S;
    let day_of_reception = (reception_moscow_s / DAY_S).floor();
    let nearest = [-1.0, 0.0, 1.0]
        .map(|d| (day_of_reception + d) * DAY_S + tb_of_day_s)
        .into_iter()
        .min_by(|a, b| {
            (a - reception_moscow_s)
                .abs()
                .total_cmp(&(b - reception_moscow_s).abs())
        })?;
    let day_in_interval = bits(s4, 59, 11);
    let broadcast = four_year_interval
        .filter(|_| (1..=1461).contains(&day_in_interval))
        .map(|n4| {
            (GPS_EPOCH_TO_1996_DAYS + 1461.0 * (n4 as f64 - 1.0) + (day_in_interval as f64 - 1.0))
                * DAY_S
                + tb_of_day_s
        })
        .filter(|t| (t - reception_moscow_s).abs() <= DAY_S);
    let tb_moscow_s = broadcast.unwrap_or(nearest);
    Some(tb_moscow_s - MOSCOW_MINUS_UTC_S + leap_s)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A string (ICD bits 85..1 as '0'/'1', the idle chip first) as the
    /// first 85 bits of its bytes.
    fn from_text(text: &str) -> [u8; 12] {
        let mut out = [0u8; 12];
        for (i, c) in text.bytes().enumerate() {
            out[i / 8] |= (c - b'0') << (7 - i % 8);
        }
        out
    }

    #[test]
    fn a_received_string_1_decodes_to_its_published_values() {
        // String 1 of gnss-sdr's GLONASS GNAV message test (a string of a
        // real satellite, with its published decoded values): t_k = 2 h
        // 6 min 0 s, ẋ = −0.490900039672852 km/s, ẍ = 0,
        // x = −11025.6669921875 km. Checked by hand against table 4.5.
        let s = from_text(
            "0000100000001000011001000011111011010101110100000010101011000100011010101011000101111",
        );
        assert!(hamming_checks(&s));
        assert_eq!(bits(&s, 1, 4), 1);
        let t_k = bits(&s, 9, 5) * 3600 + bits(&s, 14, 6) * 60 + bits(&s, 20, 1) * 30;
        assert_eq!(t_k, 7560);
        assert_eq!(
            sign_magnitude(&s, 21, 24) * 2f64.powi(-20),
            -0.490_900_039_672_851_56
        );
        assert_eq!(sign_magnitude(&s, 45, 5), 0.0);
        assert_eq!(
            sign_magnitude(&s, 50, 27) * 2f64.powi(-11),
            -11_025.666_992_187_5
        );
        // Any one bit changed fails the code.
        for k in 0..STRING_BITS {
            let mut bad = s;
            bad[k / 8] ^= 1 << (7 - k % 8);
            assert!(!hamming_checks(&bad), "bit {k} flipped passes");
        }
    }

    #[test]
    fn sign_magnitude_differs_from_twos_complement() {
        // 1 0011 = −3 in sign and magnitude (−13 in two's complement).
        let data = [0b1001_1000u8];
        assert_eq!(sign_magnitude(&data, 0, 5), -3.0);
        assert_eq!(sign_magnitude(&[0b1000_0000u8], 0, 5), 0.0);
    }
}
