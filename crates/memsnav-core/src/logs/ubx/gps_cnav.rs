//! GPS CNAV, the navigation message of L2C (IS-GPS-200 rev. N §30.3) and
//! L5 (IS-GPS-705 §20.3), from the words of UBX-RXM-SFRBX: each 300-bit
//! message checked by its CRC-24Q (§30.3.5, over bits 1-276), message
//! types 10 and 11 (ephemeris, §30.3.3.1, figures 30-1 and 30-2) and the
//! clock that types 30-37 all carry (§30.3.3.2) assembled into an
//! ephemeris when types 10 and 11 carry the same t_oe and the clock's t_oc
//! equals it (the three parts of one upload); type 30's T_GD and ISCs
//! (§30.3.3.3.1.1) and Klobuchar coefficients (§30.3.3.3.1.2) are kept.
//! Other types (almanacs, UTC, EOP, text) are counted, not decoded.
//!
//! u-blox hands a message as 10 words of 32 bits, most significant bit
//! first: the 300 bits in bits 0-299, the last 20 bits padding (checked on
//! the walk's log: every L2 CM and L5 I message starts with the preamble
//! 0x8B and passes its CRC read so).
//!
//! Bit positions below are the ICD's, 1-based, less one.

use std::collections::{BTreeMap, HashMap};

use super::gps_lnav::GPS_PI;
use super::msb_bits::{bits, crc24q, signed, word_bytes};
use crate::gnss::{
    BroadcastOrbit, CnavEphemeris, CnavGroupDelays, Klobuchar, GPS, SECONDS_PER_WEEK,
};

/// Words per CNAV message in RXM-SFRBX.
pub(super) const WORDS: usize = 10;
/// Message preamble 10001011 (§30.3.3).
const PREAMBLE: u64 = 0x8B;
/// Bits a message's CRC covers; the 24 parity bits follow (§30.3.5).
const CRC_BITS: usize = 276;
/// Reference semi-major axis A_REF, m (IS-GPS-200 table 30-I, notes).
const A_REF_M: f64 = 26_559_710.0;
/// Reference rate of right ascension Ω̇_REF, semicircles/s (table 30-I, notes).
const OMEGA_DOT_REF_SC_S: f64 = -2.6e-9;
/// The 13-bit T_GD / ISC value that means "not available" (§30.3.3.3.1.1).
const NOT_AVAILABLE: u64 = 0x1000;

/// The signal a message came on: its length in seconds (L2C 25 bps, L5
/// 50 bps, 300 bits either way).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum CnavSignal {
    L2c,
    L5,
}

impl CnavSignal {
    fn message_s(self) -> f64 {
        match self {
            CnavSignal::L2c => 12.0,
            CnavSignal::L5 => 6.0,
        }
    }
}

/// One message's bits and the GPS time its transmission started.
type Message = ([u8; 4 * WORDS], f64);

/// The messages of one satellite an ephemeris is assembled from.
#[derive(Debug, Default)]
struct Pending {
    type10: Option<Message>,
    type11: Option<Message>,
    /// The latest of types 30-37 (all carry the clock).
    clock: Option<Message>,
    type30: Option<Message>,
}

/// What the CNAV decoder met besides ephemerides.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(super) struct CnavStats {
    pub crc_failures: usize,
    /// Messages without the preamble, whose PRN is not the satellite's, or
    /// whose time of week lies beyond the week.
    pub malformed: usize,
    /// Messages of types not decoded, by type.
    pub not_decoded: BTreeMap<u8, usize>,
}

/// Assembles ephemerides from the messages of every satellite.
#[derive(Debug, Default)]
pub(super) struct CnavDecoder {
    pending: HashMap<u16, Pending>,
    pub ephemerides: Vec<CnavEphemeris>,
    /// The Klobuchar coefficients of the latest type 30, with its
    /// transmission time.
    pub klobuchar: Option<(f64, Klobuchar)>,
    pub stats: CnavStats,
}

impl CnavDecoder {
    /// Takes one message of satellite `prn` on `signal` received at
    /// `reception_gps_s` (the receiver's last RAWX epoch: the message's
    /// time of week, the start of the next message (§30.3.3, IS-GPS-705
    /// §20.3.3), lies a few seconds before it, which places it in the
    /// right week).
    pub fn push(
        &mut self,
        prn: u16,
        signal: CnavSignal,
        words: &[u32; WORDS],
        reception_gps_s: f64,
    ) {
        let m: [u8; 4 * WORDS] = word_bytes(words);
        if bits(&m, 0, 8) != PREAMBLE {
            self.stats.malformed += 1;
            return;
        }
        if u64::from(crc24q(&m, 0, CRC_BITS)) != bits(&m, CRC_BITS, 24) {
            self.stats.crc_failures += 1;
            return;
        }
        let tow_count = bits(&m, 20, 17);
        if bits(&m, 8, 6) != u64::from(prn) || tow_count >= 100_800 {
            self.stats.malformed += 1;
            return;
        }
        let start_gps_s = GPS.nearest_gps_time_s(
            (tow_count as f64 * 6.0 - signal.message_s()).rem_euclid(SECONDS_PER_WEEK),
            reception_gps_s,
        );
        let kind = bits(&m, 14, 6) as u8;
        let pending = self.pending.entry(prn).or_default();
        let message = Some((m, start_gps_s));
        match kind {
            10 => pending.type10 = message,
            11 => pending.type11 = message,
            30..=37 => {
                pending.clock = message;
                if kind == 30 {
                    pending.type30 = message;
                    if self.klobuchar.is_none_or(|(t, _)| t <= start_gps_s) {
                        self.klobuchar = Some((start_gps_s, klobuchar(&m)));
                    }
                }
            }
            _ => {
                *self.stats.not_decoded.entry(kind).or_default() += 1;
                return;
            }
        }
        let Some(e) = assemble(prn, pending) else {
            return;
        };
        match self
            .ephemerides
            .iter_mut()
            .find(|k| k.prn == prn && k.orbit.toe_gps_s == e.orbit.toe_gps_s)
        {
            None => self.ephemerides.push(e),
            // A type 30 after the ephemeris was formed from another clock
            // message: its group delays complete the record.
            Some(known) if known.group_delays.is_none() => {
                known.group_delays = e.group_delays;
            }
            Some(_) => {}
        }
    }
}

/// The Klobuchar coefficients of a type 30 (§30.3.3.3.1.2: α_n × 2⁻³⁰,
/// 2⁻²⁷, 2⁻²⁴, 2⁻²⁴ s/semicircleⁿ, β_n × 2¹¹, 2¹⁴, 2¹⁶, 2¹⁶, as LNAV's).
fn klobuchar(m: &[u8]) -> Klobuchar {
    let c = |k: usize, exponent: i32| signed(bits(m, 192 + 8 * k, 8), 8) * 2f64.powi(exponent);
    Klobuchar {
        alpha: [c(0, -30), c(1, -27), c(2, -24), c(3, -24)],
        beta: [c(4, 11), c(5, 14), c(6, 16), c(7, 16)],
    }
}

/// The ephemeris of a satellite's types 10, 11 and clock when they are of
/// one upload (types 10 and 11 share t_oe, the clock's t_oc equals it)
/// and type 10's 13-bit week number is its transmission's; `None`
/// otherwise (a part missing, or a cutover under way).
fn assemble(prn: u16, pending: &Pending) -> Option<CnavEphemeris> {
    let ((m10, transmission_gps_s), (m11, _), (mc, _)) =
        (pending.type10?, pending.type11?, pending.clock?);
    let toe = bits(&m10, 70, 11);
    if bits(&m11, 38, 11) != toe || bits(&mc, 60, 11) != toe {
        return None;
    }
    let week = bits(&m10, 38, 13) as u16;
    if (transmission_gps_s / SECONDS_PER_WEEK).floor() as u64 % 8192 != u64::from(week) {
        return None;
    }
    let at = |b: u64, scale_s: f64| GPS.nearest_gps_time_s(b as f64 * scale_s, transmission_gps_s);
    let toe_gps_s = at(toe, 300.0);
    let (sc, p) = (GPS_PI, |k: i32| 2f64.powi(k));
    let orbit = BroadcastOrbit {
        toc_gps_s: toe_gps_s,
        toe_gps_s,
        af0_s: signed(bits(&mc, 71, 26), 26) * p(-35),
        af1_s_s: signed(bits(&mc, 97, 20), 20) * p(-48),
        af2_s_s2: signed(bits(&mc, 117, 10), 10) * p(-60),
        // Type 10: ΔA, Ȧ, Δn₀, Δṅ₀, M₀, e, ω.
        sqrt_a_sqrt_m: (A_REF_M + signed(bits(&m10, 81, 26), 26) * p(-9)).sqrt(),
        a_dot_m_s: signed(bits(&m10, 107, 25), 25) * p(-21),
        delta_n_rad_s: signed(bits(&m10, 132, 17), 17) * p(-44) * sc,
        delta_n_dot_rad_s2: signed(bits(&m10, 149, 23), 23) * p(-57) * sc,
        m0_rad: signed(bits(&m10, 172, 33), 33) * p(-32) * sc,
        eccentricity: bits(&m10, 205, 33) as f64 * p(-34),
        omega_rad: signed(bits(&m10, 238, 33), 33) * p(-32) * sc,
        // Type 11: Ω₀, i₀, ΔΩ̇, i̇₀, C_is, C_ic, C_rs, C_rc, C_us, C_uc.
        omega0_rad: signed(bits(&m11, 49, 33), 33) * p(-32) * sc,
        i0_rad: signed(bits(&m11, 82, 33), 33) * p(-32) * sc,
        omega_dot_rad_s: (OMEGA_DOT_REF_SC_S + signed(bits(&m11, 115, 17), 17) * p(-44)) * sc,
        idot_rad_s: signed(bits(&m11, 132, 15), 15) * p(-44) * sc,
        cis_rad: signed(bits(&m11, 147, 16), 16) * p(-30),
        cic_rad: signed(bits(&m11, 163, 16), 16) * p(-30),
        crs_m: signed(bits(&m11, 179, 24), 24) * p(-8),
        crc_m: signed(bits(&m11, 203, 24), 24) * p(-8),
        cus_rad: signed(bits(&m11, 227, 21), 21) * p(-30),
        cuc_rad: signed(bits(&m11, 248, 21), 21) * p(-30),
    };
    let group_delays = pending
        .type30
        .filter(|(m30, _)| bits(m30, 60, 11) == toe)
        .map(|(m30, _)| {
            let delay = |first: usize| {
                let raw = bits(&m30, first, 13);
                (raw != NOT_AVAILABLE).then(|| signed(raw, 13) * p(-35))
            };
            CnavGroupDelays {
                tgd_s: delay(127),
                isc_l1ca_s: delay(140),
                isc_l2c_s: delay(153),
                isc_l5i5_s: delay(166),
                isc_l5q5_s: delay(179),
            }
        });
    let flag = |m: &[u8], at: usize| bits(m, at, 1) as u8;
    Some(CnavEphemeris {
        prn,
        orbit,
        l1_health: flag(&m10, 51),
        l2_health: flag(&m10, 52),
        l5_health: flag(&m10, 53),
        ura_ed_index: signed(bits(&m10, 65, 5), 5) as i8,
        ura_ned0_index: signed(bits(&mc, 49, 5), 5) as i8,
        ura_ned1_index: bits(&mc, 54, 3) as u8,
        ura_ned2_index: bits(&mc, 57, 3) as u8,
        top_gps_s: at(bits(&m10, 54, 11), 300.0),
        week,
        integrity_status_flag: flag(&m10, 271) == 1,
        l2c_phasing: flag(&m10, 272) == 1,
        group_delays,
        transmission_gps_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A message being written: the 300 bits MSB first in 10 words' bytes.
    struct Writer([u8; 4 * WORDS]);

    impl Writer {
        /// The common fields of §30.3.3: preamble, PRN, type, TOW count.
        fn new(prn: u16, kind: u8, tow_count: u32) -> Self {
            let mut w = Writer([0; 4 * WORDS]);
            w.put(0, 8, 0x8B);
            w.put(8, 6, i64::from(prn));
            w.put(14, 6, i64::from(kind));
            w.put(20, 17, i64::from(tow_count));
            w
        }

        /// The low `len` bits of `value` (two's complement) at bit `first`.
        fn put(&mut self, first: usize, len: usize, value: i64) {
            for k in 0..len {
                let bit = ((value >> (len - 1 - k)) & 1) as u8;
                let at = first + k;
                let mask = 1u8 << (7 - at % 8);
                self.0[at / 8] = (self.0[at / 8] & !mask) | (bit << (7 - at % 8));
            }
        }

        /// The words u-blox would hand, with the CRC in bits 277-300.
        fn words(mut self) -> [u32; WORDS] {
            let crc = crc24q(&self.0, 0, CRC_BITS);
            self.put(CRC_BITS, 24, i64::from(crc));
            std::array::from_fn(|k| {
                u32::from_be_bytes(self.0[4 * k..4 * k + 4].try_into().unwrap())
            })
        }
    }

    const WEEK: u32 = 2381;
    /// t_oe / 300 (408 600 s of week) and the TOW count of messages sent
    /// just before it.
    const TOE: i64 = 1362;
    const TOW_COUNT: u32 = 68_095;

    fn type10(prn: u16, week: u32, toe: i64) -> [u32; WORDS] {
        let mut w = Writer::new(prn, 10, TOW_COUNT);
        w.put(38, 13, i64::from(week % 8192));
        w.put(51, 3, 0b001); // L1, L2 healthy; L5 not
        w.put(54, 11, toe - 1); // t_op
        w.put(65, 5, -3); // URA_ED
        w.put(70, 11, toe);
        w.put(81, 26, -1_234_567); // ΔA
        w.put(107, 25, 3_000); // Ȧ
        w.put(132, 17, 20_000); // Δn₀
        w.put(149, 23, -400_000); // Δṅ₀
        w.put(172, 33, -3_000_000_000); // M₀
        w.put(205, 33, 50_000_000); // e
        w.put(238, 33, 2_000_000_000); // ω
        w.put(271, 1, 1); // integrity status flag
        w.words()
    }

    fn type11(prn: u16, toe: i64) -> [u32; WORDS] {
        let mut w = Writer::new(prn, 11, TOW_COUNT + 1);
        w.put(38, 11, toe);
        w.put(49, 33, 4_000_000_000); // Ω₀
        w.put(82, 33, 1_300_000_000); // i₀
        w.put(115, 17, -1_000); // ΔΩ̇
        w.put(132, 15, 500); // i̇₀
        w.put(147, 16, 100); // C_is
        w.put(163, 16, -200); // C_ic
        w.put(179, 24, 5_000); // C_rs
        w.put(203, 24, -6_000); // C_rc
        w.put(227, 21, 7_000); // C_us
        w.put(248, 21, -8_000); // C_uc
        w.words()
    }

    fn clock(prn: u16, kind: u8, toc: i64) -> [u32; WORDS] {
        let mut w = Writer::new(prn, kind, TOW_COUNT + 2);
        w.put(38, 11, toc - 1); // t_op
        w.put(49, 5, -6); // URA_NED0
        w.put(54, 3, 2);
        w.put(57, 3, 7);
        w.put(60, 11, toc);
        w.put(71, 26, -9_000_000); // a_f0
        w.put(97, 20, 30_000); // a_f1
        w.put(117, 10, -5); // a_f2
        if kind == 30 {
            w.put(127, 13, 80); // T_GD
            w.put(140, 13, -28); // ISC L1 C/A
            w.put(153, 13, 0x1000); // ISC L2C: not available
            w.put(166, 13, 300); // ISC L5 I5
            w.put(179, 13, 310); // ISC L5 Q5
            for (k, x) in [26, 16, -128, -64, 65, 3, -4, 7].iter().enumerate() {
                w.put(192 + 8 * k, 8, *x);
            }
        }
        w.words()
    }

    fn reception() -> f64 {
        f64::from(WEEK) * SECONDS_PER_WEEK + f64::from(TOW_COUNT) * 6.0 + 20.0
    }

    #[test]
    fn messages_decode_to_the_fields_they_carry() {
        let mut d = CnavDecoder::default();
        d.push(8, CnavSignal::L2c, &type10(8, WEEK, TOE), reception());
        d.push(8, CnavSignal::L2c, &type11(8, TOE), reception());
        assert!(d.ephemerides.is_empty(), "no clock yet");
        d.push(8, CnavSignal::L2c, &clock(8, 30, TOE), reception());
        assert_eq!(d.ephemerides.len(), 1);
        let e = d.ephemerides[0];
        let o = e.orbit;
        let (sc, p) = (GPS_PI, |k: i32| 2f64.powi(k));
        let week_s = f64::from(WEEK) * SECONDS_PER_WEEK;
        assert_eq!(
            (o.toe_gps_s, o.toc_gps_s),
            (week_s + 408_600.0, week_s + 408_600.0)
        );
        assert_eq!(e.top_gps_s, week_s + 408_300.0);
        // Type 10's start: the TOW count of the next message less 12 s.
        assert_eq!(
            e.transmission_gps_s,
            week_s + f64::from(TOW_COUNT) * 6.0 - 12.0
        );
        assert_eq!(
            (e.week, e.l1_health, e.l2_health, e.l5_health),
            (2381, 0, 0, 1)
        );
        assert!(e.integrity_status_flag && !e.l2c_phasing);
        assert!(e.is_healthy_on('1') && e.is_healthy_on('2') && !e.is_healthy_on('5'));
        assert_eq!(
            (
                e.ura_ed_index,
                e.ura_ned0_index,
                e.ura_ned1_index,
                e.ura_ned2_index
            ),
            (-3, -6, 2, 7)
        );
        assert_eq!(o.sqrt_a_sqrt_m, (26_559_710.0 - 1_234_567.0 * p(-9)).sqrt());
        assert_eq!(o.a_dot_m_s, 3_000.0 * p(-21));
        assert_eq!(o.delta_n_rad_s, 20_000.0 * p(-44) * sc);
        assert_eq!(o.delta_n_dot_rad_s2, -400_000.0 * p(-57) * sc);
        assert_eq!(o.m0_rad, -3e9 * p(-32) * sc);
        assert_eq!(o.eccentricity, 5e7 * p(-34));
        assert_eq!(o.omega_rad, 2e9 * p(-32) * sc);
        // Ω₀ = 4e9 needs the 33rd bit: read as 32 bits it would be negative.
        assert_eq!(o.omega0_rad, 4e9 * p(-32) * sc);
        assert_eq!(o.i0_rad, 1.3e9 * p(-32) * sc);
        assert_eq!(o.omega_dot_rad_s, (-2.6e-9 - 1_000.0 * p(-44)) * sc);
        assert_eq!(o.idot_rad_s, 500.0 * p(-44) * sc);
        assert_eq!((o.cis_rad, o.cic_rad), (100.0 * p(-30), -200.0 * p(-30)));
        assert_eq!((o.crs_m, o.crc_m), (5_000.0 * p(-8), -6_000.0 * p(-8)));
        assert_eq!(
            (o.cus_rad, o.cuc_rad),
            (7_000.0 * p(-30), -8_000.0 * p(-30))
        );
        assert_eq!(
            (o.af0_s, o.af1_s_s, o.af2_s_s2),
            (-9e6 * p(-35), 30_000.0 * p(-48), -5.0 * p(-60))
        );
        let g = e.group_delays.unwrap();
        assert_eq!(g.tgd_s, Some(80.0 * p(-35)));
        assert_eq!(g.isc_l2c_s, None);
        assert_eq!(e.group_delay_s("1C"), Some((80.0 + 28.0) * p(-35)));
        assert_eq!(e.group_delay_s("5Q"), Some((80.0 - 310.0) * p(-35)));
        assert_eq!(e.group_delay_s("2L"), None);
        let (_, k) = d.klobuchar.unwrap();
        assert_eq!(
            k.alpha,
            [
                26.0 * p(-30),
                16.0 * p(-27),
                -128.0 * p(-24),
                -64.0 * p(-24)
            ]
        );
        assert_eq!(
            k.beta,
            [65.0 * p(11), 3.0 * p(14), -4.0 * p(16), 7.0 * p(16)]
        );
        // The same messages on L5 again: no second copy.
        d.push(8, CnavSignal::L5, &type10(8, WEEK, TOE), reception());
        assert_eq!(d.ephemerides.len(), 1);
    }

    #[test]
    fn an_upload_waits_for_its_three_parts_and_its_week() {
        let mut d = CnavDecoder::default();
        // Types 10 and 11 of two uploads, a clock of a third: nothing.
        d.push(3, CnavSignal::L5, &type10(3, WEEK, TOE), reception());
        d.push(3, CnavSignal::L5, &type11(3, TOE + 1), reception());
        d.push(3, CnavSignal::L5, &clock(3, 33, TOE + 2), reception());
        assert!(d.ephemerides.is_empty());
        d.push(3, CnavSignal::L5, &type11(3, TOE), reception());
        d.push(3, CnavSignal::L5, &clock(3, 33, TOE), reception());
        // Formed from type 33's clock: no group delays until a type 30.
        assert_eq!(d.ephemerides.len(), 1);
        assert_eq!(d.ephemerides[0].group_delays, None);
        d.push(3, CnavSignal::L5, &clock(3, 30, TOE), reception());
        assert_eq!(d.ephemerides.len(), 1);
        assert!(d.ephemerides[0].group_delays.is_some());
        // A week number that is not the transmission's is refused.
        let mut d = CnavDecoder::default();
        d.push(3, CnavSignal::L5, &type10(3, WEEK + 1, TOE), reception());
        d.push(3, CnavSignal::L5, &type11(3, TOE), reception());
        d.push(3, CnavSignal::L5, &clock(3, 30, TOE), reception());
        assert!(d.ephemerides.is_empty());
    }

    #[test]
    fn damaged_and_other_messages_are_counted() {
        let mut d = CnavDecoder::default();
        let good = type10(5, WEEK, TOE);
        for bit in [0usize, 40, 150, 275, 276, 299] {
            let mut bad = good;
            bad[bit / 32] ^= 1 << (31 - bit % 32);
            d.push(5, CnavSignal::L2c, &bad, reception());
        }
        // A flipped preamble bit is a message that is not CNAV; the others
        // fail the CRC. Bits 300-319 are padding, not checked.
        assert_eq!((d.stats.malformed, d.stats.crc_failures), (1, 5));
        let mut padded = good;
        padded[9] ^= 1;
        d.push(5, CnavSignal::L2c, &padded, reception());
        assert_eq!(d.stats.crc_failures, 5);
        // On another satellite's channel: malformed.
        d.push(6, CnavSignal::L2c, &good, reception());
        assert_eq!(d.stats.malformed, 2);
        d.push(
            5,
            CnavSignal::L2c,
            &Writer::new(5, 12, TOW_COUNT).words(),
            reception(),
        );
        d.push(
            5,
            CnavSignal::L2c,
            &Writer::new(5, 15, TOW_COUNT).words(),
            reception(),
        );
        d.push(
            5,
            CnavSignal::L2c,
            &Writer::new(5, 15, TOW_COUNT).words(),
            reception(),
        );
        assert_eq!(d.stats.not_decoded, BTreeMap::from([(12, 1), (15, 2)]));
        assert!(d.ephemerides.is_empty());
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// Messages that pass the CRC with any contents, in any order, on
        /// either signal: never a panic, and every ephemeris they make has
        /// a finite orbit at t_oe ± 2 h.
        #[test]
        fn any_valid_message_sequence_is_safe(
            messages in proptest::collection::vec(
                (prop_oneof![Just(10u8), Just(11), 30u8..38, 0u8..64], proptest::collection::vec(any::<u8>(), 35), any::<bool>()),
                1..20,
            ),
            reception_offset in -1e6f64..1e6,
        ) {
            let mut d = CnavDecoder::default();
            for (kind, body, l5) in &messages {
                let mut w = Writer::new(9, *kind, TOW_COUNT);
                for (k, b) in body.iter().enumerate() {
                    let first = 38 + 8 * k;
                    let len = 8.min(CRC_BITS - first);
                    w.put(first, len, i64::from(*b));
                }
                // Half the messages of the test's upload, so that some assemble.
                if body[0] & 1 == 0 {
                    w.put(38, 13, i64::from(WEEK));
                    w.put(70, 11, TOE);
                    w.put(60, 11, TOE);
                    if *kind == 11 { w.put(38, 11, TOE); }
                }
                let signal = if *l5 { CnavSignal::L5 } else { CnavSignal::L2c };
                d.push(9, signal, &w.words(), reception() + reception_offset);
            }
            for e in &d.ephemerides {
                for dt in [-7200.0, 0.0, 7200.0] {
                    let s = e.state_at(e.orbit.toe_gps_s, dt);
                    prop_assert!(s.position_ecef.iter().all(|x| x.is_finite()));
                    prop_assert!(s.clock_bias_s.is_finite());
                }
            }
        }
    }
}
