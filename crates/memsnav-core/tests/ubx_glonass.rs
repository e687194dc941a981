//! GLONASS strings in UBX-RXM-SFRBX (`logs::ubx`): the broadcast records
//! of the IGS merge (R01, R02 of BRDC00IGS 2020-136, RINEX 3) encoded here
//! into strings 1-5 as the ICD lays them out (sign and magnitude, Hamming
//! code), framed as a u-blox receiver frames them, decode to the same
//! ephemerides; `memsnav convert`'s RINEX writer gives them back as `R`
//! records (RINEX 3.04 and 4.00). A string with a bit changed is counted
//! and left out. The decoder's fields are checked against a received
//! string with published values in its own unit tests.
//!
//! The encoder below is written from ICD edition 5.1 table 4.5 and §4.7,
//! independently of the decoder's code (bit numbers as the ICD counts
//! them, 85 down to 1).

use std::path::Path;

use memsnav_core::gnss::{
    gps_minus_utc_s, parse_broadcast_nav, write_rinex_nav, GlonassEphemeris, NavFileEphemerides,
    RinexNavVersion, SECONDS_PER_WEEK,
};
use memsnav_core::logs::parse_ubx;

fn igs_records() -> Vec<GlonassEphemeris> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/rinex-public/BRDC00IGS_R_20201360000_excerpt_MN.rnx");
    let text = std::fs::read_to_string(path).unwrap();
    let nav = parse_broadcast_nav(&text, "BRDC00IGS").unwrap();
    assert_eq!(nav.glonass.len(), 2);
    nav.glonass
}

/// An 85-bit string being built: `bits[k]` is the ICD's bit k (1-85).
struct IcdString {
    bits: [u8; 86],
}

impl IcdString {
    fn new(m: u64) -> Self {
        let mut s = Self { bits: [0; 86] };
        // Bit 85 is the idle chip (0); the string number m in 84-81.
        s.unsigned(84, 4, m);
        s
    }

    /// `len` bits of `value`, most significant at ICD bit `high`.
    fn unsigned(&mut self, high: usize, len: usize, value: u64) {
        assert!(value < 1 << len, "{value} does not fit {len} bits");
        for j in 0..len {
            self.bits[high - j] = (value >> (len - 1 - j) & 1) as u8;
        }
    }

    /// Sign and magnitude: the sign at `high`, |value|/scale below it.
    fn signed(&mut self, high: usize, len: usize, value: f64, scale: f64) {
        let magnitude = (value.abs() / scale).round() as u64;
        self.unsigned(high, 1, u64::from(value < 0.0 && magnitude != 0));
        self.unsigned(high - 1, len - 1, magnitude);
    }

    /// The Hamming code of ICD §4.7 in bits 8-1: β1-β7 over the data bits
    /// b9-b85 laid on the code positions that are not powers of two, β8
    /// the parity of everything.
    fn with_hamming(mut self) -> Self {
        let positions: Vec<u32> = (1..=84u32).filter(|p| !p.is_power_of_two()).collect();
        for i in 0..7 {
            let b = (9..=85)
                .zip(&positions)
                .filter(|(_, p)| *p >> i & 1 == 1)
                .fold(0, |acc, (k, _)| acc ^ self.bits[k]);
            self.bits[i + 1] = b;
        }
        // β8 makes the XOR of all 85 bits zero.
        self.bits[8] = (1..=85)
            .filter(|&k| k != 8)
            .fold(0, |acc, k| acc ^ self.bits[k]);
        self
    }

    /// The four SFRBX words: bits 85..1 from the most significant bit of
    /// the first word, then padding, then a fourth word (frame numbers).
    fn words(&self) -> [u32; 4] {
        let mut w = [0u32; 4];
        for (i, k) in (1..=85).rev().enumerate() {
            w[i / 32] |= u32::from(self.bits[k]) << (31 - i % 32);
        }
        w[3] = 1 << 16;
        w
    }
}

const KM: f64 = 1e3;

/// Strings 1-5 of `e` as its satellite broadcasts them (t_k the frame's
/// start, N_T and N4 from t_b's Moscow date).
fn encode(e: &GlonassEphemeris) -> [IcdString; 5] {
    let leap = gps_minus_utc_s(e.tb_gps_s);
    let moscow = e.tb_gps_s - leap + 3.0 * 3600.0;
    let day = (moscow / 86_400.0).floor();
    let tb_quarter_hours = ((moscow - day * 86_400.0) / 900.0).round() as u64;
    // Days since 1996-01-01 (GPS day 5839): N4 and the day in its interval.
    let since_1996 = day as i64 - 5839;
    let (n4, nt) = (since_1996 / 1461 + 1, since_1996 % 1461 + 1);
    let axis = |s: &mut IcdString, i: usize| {
        s.signed(64, 24, e.velocity_ecef[i] / KM, 2f64.powi(-20));
        s.signed(40, 5, e.lunisolar_m_s2[i] / KM, 2f64.powi(-30));
        s.signed(35, 27, e.position_ecef[i] / KM, 2f64.powi(-11));
    };
    let mut s1 = IcdString::new(1);
    // t_k: the frame starts 10 minutes before t_b here.
    let tk = (moscow - day * 86_400.0 - 600.0).max(0.0);
    s1.unsigned(76, 5, (tk / 3600.0) as u64);
    s1.unsigned(71, 6, ((tk % 3600.0) / 60.0) as u64);
    axis(&mut s1, 0);
    let mut s2 = IcdString::new(2);
    s2.unsigned(80, 3, u64::from(e.health & 1) << 2); // B_n: its MSB
    s2.unsigned(76, 7, tb_quarter_hours);
    axis(&mut s2, 1);
    let mut s3 = IcdString::new(3);
    s3.signed(79, 11, e.gamma_n, 2f64.powi(-40));
    s3.unsigned(65, 1, u64::from(e.health >> 2 & 1)); // l_n
    axis(&mut s3, 2);
    let mut s4 = IcdString::new(4);
    s4.signed(80, 22, e.tau_n_s, 2f64.powi(-30));
    s4.unsigned(53, 5, u64::from(e.age_days));
    s4.unsigned(26, 11, nt as u64);
    s4.unsigned(15, 5, u64::from(e.slot));
    s4.unsigned(10, 2, 1); // M: GLONASS-M
    let mut s5 = IcdString::new(5);
    s5.unsigned(80, 11, nt as u64);
    s5.unsigned(36, 5, n4 as u64);
    [s1, s2, s3, s4, s5].map(IcdString::with_hamming)
}

fn ubx_frame(class: u8, id: u8, payload: &[u8]) -> Vec<u8> {
    let mut frame = vec![0xB5, 0x62, class, id];
    frame.extend_from_slice(&(payload.len() as u16).to_le_bytes());
    frame.extend_from_slice(payload);
    let (mut a, mut b) = (0u8, 0u8);
    for &x in &frame[2..] {
        a = a.wrapping_add(x);
        b = b.wrapping_add(a);
    }
    frame.extend([a, b]);
    frame
}

/// An RXM-RAWX epoch without measurements at GPS time `t` (the time the
/// strings after it were received).
fn rawx(t: f64) -> Vec<u8> {
    let week = (t / SECONDS_PER_WEEK).floor();
    let mut p = vec![0u8; 16];
    p[..8].copy_from_slice(&(t - week * SECONDS_PER_WEEK).to_le_bytes());
    p[8..10].copy_from_slice(&(week as u16).to_le_bytes());
    p[10] = 18;
    p[12] = 1;
    p[13] = 1;
    ubx_frame(0x02, 0x15, &p)
}

fn sfrbx(slot: u8, channel: i8, words: &[u32; 4]) -> Vec<u8> {
    let mut p = vec![6, slot, 0, (channel + 7) as u8, 4, 0, 2, 0];
    for w in words {
        p.extend_from_slice(&w.to_le_bytes());
    }
    ubx_frame(0x02, 0x13, &p)
}

/// A log of each record's string 5, then strings 1-4 2 s apart, received
/// 10 minutes before t_b (the next record 30 s later); `damage` flips one
/// bit of R01's string 3.
fn log(records: &[GlonassEphemeris], damage: bool) -> Vec<u8> {
    let mut bytes = Vec::new();
    for (i, e) in records.iter().enumerate() {
        let strings = encode(e);
        let start = e.tb_gps_s - 600.0 + 30.0 * i as f64;
        bytes.extend(rawx(start - 2.0));
        bytes.extend(sfrbx(
            e.slot as u8,
            e.frequency_channel,
            &strings[4].words(),
        ));
        for (k, s) in strings[..4].iter().enumerate() {
            bytes.extend(rawx(start + 2.0 * k as f64));
            let mut words = s.words();
            if damage && e.slot == 1 && k == 2 {
                words[1] ^= 1 << 7;
            }
            bytes.extend(sfrbx(e.slot as u8, e.frequency_channel, &words));
        }
    }
    bytes
}

fn assert_same(decoded: &GlonassEphemeris, rinex: &GlonassEphemeris) {
    assert_eq!(
        (
            decoded.slot,
            decoded.frequency_channel,
            decoded.health,
            decoded.age_days
        ),
        (
            rinex.slot,
            rinex.frequency_channel,
            rinex.health,
            rinex.age_days
        )
    );
    assert_eq!(decoded.tb_gps_s, rinex.tb_gps_s);
    // RINEX prints 13 digits; the message's own steps are 2⁻³⁰ s, 2⁻⁴⁰,
    // 2⁻¹¹ km (0.49 m), 2⁻²⁰ km/s, 2⁻³⁰ km/s².
    assert!((decoded.tau_n_s - rinex.tau_n_s).abs() < 1e-15, "τ_n");
    assert!((decoded.gamma_n - rinex.gamma_n).abs() < 1e-20, "γ_n");
    assert!((decoded.position_ecef - rinex.position_ecef).abs().max() < 1e-4);
    assert!((decoded.velocity_ecef - rinex.velocity_ecef).abs().max() < 1e-8);
    assert!((decoded.lunisolar_m_s2 - rinex.lunisolar_m_s2).abs().max() < 1e-15);
}

#[test]
fn igs_records_through_strings_decode_and_write_back() {
    let records = igs_records();
    let decoded = parse_ubx(&log(&records, false), "encoded").unwrap();
    assert_eq!(
        decoded.glonass_ephemerides.len(),
        2,
        "{:?}",
        decoded.skipped
    );
    for (d, r) in decoded.glonass_ephemerides.iter().zip(&records) {
        assert_same(d, r);
    }
    assert_eq!(decoded.broadcast_nav().glonass, decoded.glonass_ephemerides);
    // `memsnav convert`'s writer: R records in RINEX 3.04 and 4.00.
    let dir = std::env::temp_dir().join(format!("memsnav-ubx-glonass-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (version, name) in [
        (RinexNavVersion::V3_04, "v3.nav"),
        (RinexNavVersion::V4_00, "v4.nav"),
    ] {
        let path = dir.join(name);
        let files = NavFileEphemerides {
            glonass: &decoded.glonass_ephemerides,
            ..decoded.nav_file_ephemerides()
        };
        write_rinex_nav(&path, &files, version, &Default::default()).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("R: GLONASS"), "{text}");
        let back = parse_broadcast_nav(&text, name).unwrap();
        assert_eq!(back.glonass.len(), 2);
        for (b, r) in back.glonass.iter().zip(&records) {
            assert_same(b, r);
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_damaged_string_is_counted_and_its_ephemeris_left_out() {
    let records = igs_records();
    let decoded = parse_ubx(&log(&records, true), "damaged").unwrap();
    let slots: Vec<u16> = decoded.glonass_ephemerides.iter().map(|e| e.slot).collect();
    assert_eq!(slots, [2]);
    assert_eq!(
        decoded
            .skipped
            .get("GLONASS strings with a Hamming code failure"),
        Some(&1),
        "{:?}",
        decoded.skipped
    );
}
