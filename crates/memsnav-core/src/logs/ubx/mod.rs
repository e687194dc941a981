//! u-blox UBX binary logs (u-blox F9 HPG 1.32 and X20 HPG 2.00 interface
//! descriptions): the raw measurements (RXM-RAWX), the GPS, Galileo and
//! BeiDou broadcast ephemerides decoded from the navigation message words
//! (RXM-SFRBX: GPS L1 C/A LNAV, GPS L2C and L5 CNAV with the Klobuchar
//! coefficients of its message type 30, Galileo E1-B I/NAV, BeiDou D1,
//! GLONASS L1OF/L2OF strings 1-5) and
//! the receiver's own solution (NAV-PVT).
//!
//! The measurements come out twice: as the receiver reports them
//! ([`RawxEpoch`], with lock times and tracking flags), and as the same
//! [`ObservationFile`] the RINEX reader gives (RINEX 3 codes per signal,
//! `C` m, `L` cycles with the loss-of-lock indicator, `D` Hz, `S` dB-Hz),
//! so that everything downstream (`gps_l1_epochs`, the fix solver, the
//! filters, the RINEX writer) takes either. Epochs are on the receiver's
//! time (RAWX's week and time of week), as RINEX observation epochs are.
//!
//! Not decoded yet (skipped with a count): GPS CNAV message types other
//! than 10, 11 and 30-37, Galileo F/NAV and E6, BeiDou D2 (GEO), GLONASS
//! almanac strings (6-15), SBAS, and every message other than the three
//! above.
//!
//! Any byte sequence is read without a panic: frames whose checksum fails
//! are skipped and counted, a last frame cut short is reported in
//! `warnings`, a message whose payload does not fit its definition is
//! skipped and counted by reason; a file without a single good UBX frame
//! is an error.

mod beidou_d1;
mod bytes;
mod ephemeris_checks;
mod framing;
mod galileo_inav;
mod glonass_strings;
mod gps_cnav;
mod gps_lnav;
mod msb_bits;
mod nav_pvt;
mod rawx;

pub use nav_pvt::NavPvt;
pub use rawx::{RawxEpoch, RawxSignal, TrackingStatus};

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use crate::geodesy::{geodetic_to_ecef, Geodetic};
use crate::gnss::{
    BeidouEphemeris, BroadcastNav, CnavEphemeris, GlonassEphemeris, InavEphemeris, Klobuchar,
    LnavEphemeris, NavFileEphemerides, ObservationEpoch, ObservationFile, SatelliteObservations,
    SignalLayout,
};
use crate::gnss::{LLI_HALF_CYCLE, LLI_LOST_LOCK};
use crate::logs::PosSolution;
use crate::{Error, Result};

/// UBX class and id of the messages read.
const NAV_PVT: (u8, u8) = (0x01, 0x07);
const RXM_SFRBX: (u8, u8) = (0x02, 0x13);
const RXM_RAWX: (u8, u8) = (0x02, 0x15);
/// Warnings kept per kind of problem (the counts in `skipped` are complete).
const WARNINGS_PER_KIND: usize = 5;

/// What a UBX log holds.
#[derive(Debug, Clone, PartialEq)]
pub struct UbxLog {
    /// RXM-RAWX epochs as the receiver reports them, in time order.
    pub rawx: Vec<RawxEpoch>,
    /// The same as RINEX 3 observations (see the module documentation);
    /// the approximate position is the first NAV-PVT fix's.
    pub observations: ObservationFile,
    /// GPS LNAV ephemerides decoded from RXM-SFRBX, one per satellite and
    /// issue of data, in the order they completed.
    pub gps_ephemerides: Vec<LnavEphemeris>,
    /// GPS CNAV ephemerides decoded from RXM-SFRBX (L2C or L5), one per
    /// satellite and t_oe, in the order they completed.
    pub gps_cnav_ephemerides: Vec<CnavEphemeris>,
    /// The Klobuchar coefficients of the latest CNAV message type 30
    /// (LNAV's page 18 of subframe 4 is not decoded).
    pub klobuchar: Option<Klobuchar>,
    /// Galileo I/NAV ephemerides decoded from RXM-SFRBX (E1-B), one per
    /// satellite and IODnav, in the order they completed.
    pub galileo_ephemerides: Vec<InavEphemeris>,
    /// BeiDou D1 ephemerides (MEO and IGSO satellites) decoded from
    /// RXM-SFRBX (B1I, B2I or B3I), one per satellite, AODE and t_oe, in
    /// the order they completed.
    pub beidou_ephemerides: Vec<BeidouEphemeris>,
    /// GLONASS ephemerides decoded from RXM-SFRBX (L1OF or L2OF strings
    /// 1-4, with string 5's four-year interval), one per slot and t_b, in
    /// the order they completed.
    pub glonass_ephemerides: Vec<GlonassEphemeris>,
    /// Every NAV-PVT solution, fix or not.
    pub nav_pvt: Vec<NavPvt>,
    /// The NAV-PVT position fixes, as the other fix readers give them.
    pub fixes: PosSolution,
    /// Messages read, by name (`RXM-RAWX`, `NAV-PVT`, `0x01-0x35` for
    /// those not read).
    pub messages: BTreeMap<String, usize>,
    /// What was left out, by reason, with counts.
    pub skipped: BTreeMap<String, usize>,
    /// Non-fatal problems, one sentence each (a few per kind).
    pub warnings: Vec<String>,
}

impl UbxLog {
    /// The decoded ephemerides a RINEX navigation file of the log holds
    /// (`memsnav convert`).
    pub fn nav_file_ephemerides(&self) -> NavFileEphemerides<'_> {
        NavFileEphemerides {
            gps_lnav: &self.gps_ephemerides,
            gps_cnav: &self.gps_cnav_ephemerides,
            galileo: &self.galileo_ephemerides,
            beidou: &self.beidou_ephemerides,
            glonass: &self.glonass_ephemerides,
        }
    }

    /// The decoded ephemerides of every system as one set, the form the
    /// RINEX navigation reader gives ([`crate::gnss::broadcast_epochs`]
    /// takes it).
    pub fn broadcast_nav(&self) -> BroadcastNav {
        BroadcastNav {
            // LNAV, and CNAV where type 30 gave its L1 C/A group delay.
            gps: self
                .gps_ephemerides
                .iter()
                .map(|l| l.ephemeris)
                .chain(
                    self.gps_cnav_ephemerides
                        .iter()
                        .filter_map(CnavEphemeris::l1_ca_ephemeris),
                )
                .collect(),
            galileo: self.galileo_ephemerides.clone(),
            beidou: self.beidou_ephemerides.clone(),
            glonass: self.glonass_ephemerides.clone(),
            gps_cnav: self.gps_cnav_ephemerides.clone(),
            klobuchar: self.klobuchar,
            // The CNAV ephemerides are in the order they completed: the
            // last of a satellite is its latest.
            gps_group_delays: self
                .gps_cnav_ephemerides
                .iter()
                .filter_map(|c| Some((c.prn, c.healthy_group_delays()?)))
                .collect(),
            skipped: BTreeMap::new(),
        }
    }
}

/// Reads a UBX log.
pub fn read_ubx(path: impl AsRef<Path>) -> Result<UbxLog> {
    let path = path.as_ref();
    let bytes = super::read_bytes(path)?;
    parse_ubx(&bytes, &path.display().to_string())
}

/// Counts and a few warnings per kind of problem.
#[derive(Default)]
struct Problems {
    skipped: BTreeMap<String, usize>,
    warnings: Vec<String>,
}

impl Problems {
    fn skip(&mut self, reason: &str, warning: impl FnOnce() -> String) {
        let n = self.skipped.entry(reason.to_string()).or_default();
        *n += 1;
        if *n <= WARNINGS_PER_KIND {
            self.warnings.push(warning());
        }
    }

    fn add(&mut self, reason: &str, count: usize) {
        if count > 0 {
            *self.skipped.entry(reason.to_string()).or_default() += count;
        }
    }
}

/// Parses the bytes of a UBX log; `file` names it in errors and warnings.
pub fn parse_ubx(log: &[u8], file: &str) -> Result<UbxLog> {
    let (frames, stats) = framing::frames(log);
    if frames.is_empty() {
        return Err(Error::ParseBinary {
            file: file.to_string(),
            byte_offset: 0,
            reason: format!(
                "no UBX frame (sync 0xB5 0x62 and a good Fletcher checksum) in its {} bytes",
                log.len()
            ),
        });
    }
    let mut problems = Problems::default();
    problems.add("frames with a bad checksum", stats.checksum_failures);
    problems.add("bytes outside UBX frames", stats.skipped_bytes);
    if let Some(at) = stats.truncated_at {
        problems.warnings.push(format!(
            "{file}: the last UBX frame, at byte {at}, is cut short by the end of the log; skipped"
        ));
    }
    let mut messages: BTreeMap<String, usize> = BTreeMap::new();
    let mut rawx: Vec<RawxEpoch> = Vec::new();
    let mut nav_pvt = Vec::new();
    let mut lnav = gps_lnav::LnavDecoder::default();
    let mut cnav = gps_cnav::CnavDecoder::default();
    let mut inav = galileo_inav::InavDecoder::default();
    let mut d1 = beidou_d1::D1Decoder::default();
    let mut glonass = glonass_strings::GlonassDecoder::default();
    for f in &frames {
        let name = match (f.class, f.id) {
            NAV_PVT => "NAV-PVT".to_string(),
            RXM_SFRBX => "RXM-SFRBX".to_string(),
            RXM_RAWX => "RXM-RAWX".to_string(),
            (c, i) => format!("0x{c:02X}-0x{i:02X}"),
        };
        *messages.entry(name.clone()).or_default() += 1;
        let at = f.offset;
        let mut malformed = |reason: String| {
            problems.skip(&format!("{name} malformed"), || {
                format!("{file}: byte {at}: {reason}; skipped")
            });
        };
        match (f.class, f.id) {
            RXM_RAWX => match rawx::decode_rawx(f.payload) {
                Ok(epoch) => {
                    if rawx
                        .last()
                        .is_some_and(|p| epoch.gps_time_s() <= p.gps_time_s())
                    {
                        malformed(format!(
                            "RXM-RAWX epoch at GPS {} s does not follow the previous one",
                            epoch.gps_time_s()
                        ));
                    } else {
                        problems.add(
                            "RXM-RAWX signals of unknown system or signal id",
                            epoch.unknown_signals,
                        );
                        problems.add(
                            "RXM-RAWX signals with a value no receiver reports",
                            epoch.implausible_signals,
                        );
                        rawx.push(epoch);
                    }
                }
                Err(reason) => malformed(reason),
            },
            NAV_PVT => match nav_pvt::decode_nav_pvt(f.payload) {
                Ok(s) => match nav_pvt::check_plausible(&s) {
                    Ok(()) => nav_pvt.push(s),
                    Err(reason) => problems
                        .skip("NAV-PVT with a value no receiver reports", || {
                            format!("{file}: byte {at}: {reason}; skipped")
                        }),
                },
                Err(reason) => malformed(reason),
            },
            RXM_SFRBX => {
                let p = f.payload;
                let words = usize::from(p.get(4).copied().unwrap_or(0));
                if p.len() < 8 || p.len() != 8 + 4 * words {
                    malformed(format!(
                        "RXM-SFRBX payload of {} bytes does not hold its {words} words",
                        p.len()
                    ));
                    continue;
                }
                let (gnss_id, sv_id, sig_id) = (p[0], p[1], p[2]);
                let Some(reception_gps_s) = rawx.last().map(RawxEpoch::gps_time_s) else {
                    problems.add("RXM-SFRBX before the first RXM-RAWX (time unknown)", 1);
                    continue;
                };
                match (gnss_id, sig_id, words) {
                    // GPS L1 C/A: LNAV, ten words a subframe.
                    (0, 0, gps_lnav::WORDS) if (1..=32).contains(&sv_id) => {
                        lnav.push(u16::from(sv_id), &sfrbx_words(p), reception_gps_s);
                    }
                    (0, 0, _) => malformed(format!(
                        "RXM-SFRBX GPS L1 C/A with {words} words (10 expected) or PRN {sv_id}"
                    )),
                    // GPS L2 CL/CM and L5 I/Q: CNAV, one 300-bit message
                    // in ten words.
                    (0, 3 | 4 | 6 | 7, gps_cnav::WORDS) if (1..=32).contains(&sv_id) => {
                        let signal = if sig_id <= 4 {
                            gps_cnav::CnavSignal::L2c
                        } else {
                            gps_cnav::CnavSignal::L5
                        };
                        cnav.push(
                            u16::from(sv_id),
                            signal,
                            &sfrbx_words(p),
                            reception_gps_s,
                        );
                    }
                    (0, 3 | 4 | 6 | 7, _) => malformed(format!(
                        "RXM-SFRBX GPS CNAV with {words} words (10 expected) or PRN {sv_id}"
                    )),
                    // Galileo E1-B: I/NAV, one page pair in eight words.
                    (2, 1, galileo_inav::WORDS) if (1..=36).contains(&sv_id) => {
                        inav.push(u16::from(sv_id), &sfrbx_words(p), reception_gps_s);
                    }
                    (2, 1, _) => malformed(format!(
                        "RXM-SFRBX Galileo E1-B with {words} words (8 expected) or SVID {sv_id}"
                    )),
                    // BeiDou D1 on B1I, B2I or B3I (sigId 0, 2, 4): ten
                    // words a subframe, MEO and IGSO satellites only.
                    (3, 0 | 2 | 4, beidou_d1::WORDS)
                        if (1..=63).contains(&sv_id) && !matches!(sv_id, 1..=5 | 59..=63) =>
                    {
                        d1.push(u16::from(sv_id), &sfrbx_words(p), reception_gps_s);
                    }
                    // D2 (GEO satellites, sigId 1, 3, 10, or a GEO PRN).
                    (3, 1 | 3 | 10, _) | (3, 0 | 2 | 4, _) if matches!(sv_id, 1..=5 | 59..=63) => {
                        problems.add("BeiDou D2 (GEO) subframes not decoded", 1)
                    }
                    (3, 0 | 2 | 4, _) => malformed(format!(
                        "RXM-SFRBX BeiDou D1 with {words} words (10 expected) or PRN {sv_id}"
                    )),
                    // GLONASS L1OF and L2OF (sigId 0, 2): one string in
                    // four words, the slot known (svId 255 until then).
                    (6, 0 | 2, glonass_strings::WORDS) if (1..=24).contains(&sv_id) => {
                        glonass.push(sv_id, p[3], &sfrbx_words(p), reception_gps_s);
                    }
                    (6, 0 | 2, glonass_strings::WORDS) if sv_id == 255 => {
                        problems.add("GLONASS strings of a slot not known yet", 1)
                    }
                    (6, 0 | 2, _) => malformed(format!(
                        "RXM-SFRBX GLONASS with {words} words (4 expected) or slot {sv_id}"
                    )),
                    _ => problems.add(
                        &format!(
                            "RXM-SFRBX of a navigation message not decoded (gnssId {gnss_id}, sigId {sig_id})"
                        ),
                        1,
                    ),
                }
            }
            _ => problems.add("messages not read", 1),
        }
    }
    problems.add(
        "GPS LNAV subframes with a parity failure",
        lnav.stats.parity_failures,
    );
    problems.add("GPS LNAV subframes malformed", lnav.stats.malformed);
    problems.add(
        "GPS CNAV messages with a CRC failure",
        cnav.stats.crc_failures,
    );
    problems.add("GPS CNAV messages malformed", cnav.stats.malformed);
    for (kind, &count) in &cnav.stats.not_decoded {
        problems.add(&format!("GPS CNAV message type {kind} not decoded"), count);
    }
    problems.add(
        "Galileo I/NAV page pairs with a CRC failure",
        inav.stats.crc_failures,
    );
    problems.add(
        "Galileo I/NAV pages without their pair",
        inav.stats.unpaired,
    );
    problems.add("Galileo I/NAV alert pages", inav.stats.alerts);
    problems.add(
        "BeiDou D1 subframes with a BCH failure",
        d1.stats.bch_failures,
    );
    problems.add("BeiDou D1 subframes malformed", d1.stats.malformed);
    problems.add(
        "GLONASS strings with a Hamming code failure",
        glonass.stats.hamming_failures,
    );
    problems.add(
        "GLONASS strings 1-4 that make no ephemeris (not one frame's, or a slot, channel or t_b out of place)",
        glonass.stats.inconsistent,
    );
    problems.add(
        "GLONASS ephemerides out of range",
        glonass.stats.out_of_range,
    );
    let ephemerides = ephemeris_checks::check(
        ephemeris_checks::Checked {
            gps: lnav.ephemerides,
            gps_cnav: cnav.ephemerides,
            galileo: inav.ephemerides,
            beidou: d1.ephemerides,
        },
        file,
        &mut problems,
    );
    let fixes = nav_pvt::fixes(&nav_pvt);
    let approx_position_ecef = fixes
        .lla
        .first()
        .map(|lla| geodetic_to_ecef(Geodetic::new(lla.x, lla.y, lla.z)));
    let mut observations = observations(&rawx);
    observations.approx_position_ecef = approx_position_ecef;
    let mut warnings = problems.warnings;
    warnings.extend(fixes.warnings.iter().cloned());
    Ok(UbxLog {
        rawx,
        observations,
        gps_ephemerides: ephemerides.gps,
        gps_cnav_ephemerides: ephemerides.gps_cnav,
        klobuchar: cnav.klobuchar.map(|(_, k)| k),
        galileo_ephemerides: ephemerides.galileo,
        beidou_ephemerides: ephemerides.beidou,
        glonass_ephemerides: glonass.ephemerides,
        nav_pvt,
        fixes,
        messages,
        skipped: problems.skipped,
        warnings,
    })
}

/// The `N` data words of an RXM-SFRBX payload whose length was checked.
fn sfrbx_words<const N: usize>(payload: &[u8]) -> [u32; N] {
    std::array::from_fn(|k| bytes::Le(payload).u32(8 + 4 * k))
}

/// RAWX epochs as RINEX observations: per system the signals present in
/// the log (codes in sorted order) with `C`, `L`, `D`, `S` each. A
/// pseudorange or phase the receiver marks invalid, or a value beyond what
/// RINEX can hold, is left blank. The phase's loss-of-lock indicator says
/// lock lost when the lock time fell since the previous epoch that had the
/// signal, and half-cycle when `halfCyc` is clear. Each GLONASS slot's
/// frequency channel is its signals' `freqId` − 7 (interface description,
/// RXM-RAWX), the last seen; a `freqId` outside 0-20 (k −7 to 13) is not
/// a channel and is left out.
fn observations(rawx: &[RawxEpoch]) -> ObservationFile {
    let layout = SignalLayout::new(
        rawx.iter()
            .flat_map(|e| &e.signals)
            .map(|s| (s.system, s.rinex_code)),
    );
    let mut last_lock: HashMap<(char, u16, &str), f64> = HashMap::new();
    let epochs = rawx
        .iter()
        .map(|e| {
            let mut satellites: Vec<SatelliteObservations> = Vec::new();
            for s in &e.signals {
                let (values, lli) = layout.slots(&mut satellites, s.system, s.prn, s.rinex_code);
                if values.iter().any(Option::is_some) {
                    // A second block of the same signal in one epoch: the first is kept.
                    continue;
                }
                let kept = |code: &str, value: f64, valid: bool| {
                    (valid
                        && value.is_finite()
                        && crate::gnss::plausible::observation_range(code).contains(&value))
                    .then_some(value)
                };
                let t = s.tracking;
                values[0] = kept("C", s.pseudorange_m, t.pseudorange_valid);
                values[1] = kept("L", s.carrier_phase_cycles, t.carrier_phase_valid);
                values[2] = kept("D", s.doppler_hz, true);
                values[3] = kept("S", s.cn0_db_hz, s.cn0_db_hz > 0.0);
                let previous = last_lock.insert((s.system, s.prn, s.rinex_code), s.lock_time_s);
                if values[1].is_some() {
                    let lost = previous.is_some_and(|p| s.lock_time_s < p);
                    lli[1] = if lost { LLI_LOST_LOCK } else { 0 }
                        | if t.half_cycle_resolved {
                            0
                        } else {
                            LLI_HALF_CYCLE
                        };
                }
            }
            ObservationEpoch {
                gps_time_s: e.gps_time_s(),
                flag: 0,
                satellites,
            }
        })
        .collect();
    let glonass_channels = rawx
        .iter()
        .flat_map(|e| &e.signals)
        .filter(|s| s.system == 'R' && s.freq_id <= 20)
        .map(|s| (s.prn, s.freq_id as i8 - 7))
        .collect();
    ObservationFile {
        version: 3.04,
        observation_types: layout.observation_types(),
        approx_position_ecef: None,
        epochs,
        glonass_channels,
        warnings: Vec::new(),
        skipped: Default::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::framing::encode;
    use super::*;

    fn sfrbx(gnss_id: u8, sv_id: u8, sig_id: u8, words: &[u32]) -> Vec<u8> {
        let mut p = vec![gnss_id, sv_id, sig_id, 0, words.len() as u8, 0, 2, 0];
        for w in words {
            p.extend_from_slice(&w.to_le_bytes());
        }
        encode(RXM_SFRBX.0, RXM_SFRBX.1, &p)
    }

    #[test]
    fn glonass_channels_reach_the_rinex_header() {
        // R05 on k = +1 (freqId 8), R12 on k = −1 (freqId 6): the
        // observation file's GLONASS SLOT / FRQ # says so and reads back.
        let glonass = |slot: u8, freq_id: u8| rawx::RawxSignal {
            system: 'R',
            prn: u16::from(slot),
            gnss_id: 6,
            sv_id: slot,
            freq_id,
            ..rawx::tests::gps_l1(slot, 2.2e7)
        };
        let signals = [rawx::tests::gps_l1(3, 2.1e7), glonass(5, 8), glonass(12, 6)];
        let log = encode(
            RXM_RAWX.0,
            RXM_RAWX.1,
            &rawx::encode_rawx(408_700.25, 2381, Some(18), &signals),
        );
        let out = parse_ubx(&log, "r.ubx").unwrap();
        let expected: BTreeMap<u16, i8> = [(5, 1), (12, -1)].into();
        assert_eq!(out.observations.glonass_channels, expected);
        let text = crate::gnss::format_rinex_obs(&out.observations, &Default::default());
        assert!(
            text.contains("  2 R05  1 R12 -1 "),
            "{}",
            &text[..text.find("END OF HEADER").unwrap()]
        );
        let back = crate::gnss::parse_rinex_obs(&text, "r.obs").unwrap();
        assert_eq!(back.glonass_channels, expected);
    }

    #[test]
    fn a_hand_built_log_with_every_kind_of_damage() {
        let week = 2381;
        let tow = 408_700.25;
        let signals = [rawx::tests::gps_l1(3, 2.1e7), rawx::tests::gps_l1(7, 2.3e7)];
        let mut second = signals;
        second[1].lock_time_s = 0.5; // lock lost: the phase gets LLI 1
        let sf = gps_lnav::tests::test_subframes(u32::from(week), 77, 77);
        let mut log = b"$GNGGA,noise\r\n".to_vec();
        log.extend(encode(
            RXM_RAWX.0,
            RXM_RAWX.1,
            &rawx::encode_rawx(tow, week, Some(18), &signals),
        ));
        log.extend(sfrbx(0, 3, 0, &sf[0]));
        // The same words on L2C are not LNAV and, without CNAV's preamble,
        // not CNAV either: counted, not decoded.
        log.extend(sfrbx(0, 3, 4, &sf[1]));
        let mut flipped = sfrbx(0, 3, 0, &sf[1]);
        let n = flipped.len();
        flipped[n - 3] ^= 0x40; // checksum no longer matches
        log.extend(flipped);
        log.extend(sfrbx(0, 3, 0, &sf[1]));
        log.extend(sfrbx(0, 3, 0, &sf[2]));
        log.extend(encode(
            RXM_RAWX.0,
            RXM_RAWX.1,
            &rawx::encode_rawx(tow + 0.25, week, Some(18), &second),
        ));
        // An epoch that goes back in time is skipped.
        log.extend(encode(
            RXM_RAWX.0,
            RXM_RAWX.1,
            &rawx::encode_rawx(tow, week, Some(18), &second),
        ));
        log.extend(encode(0x0A, 0x04, &[]));
        let full = encode(
            RXM_RAWX.0,
            RXM_RAWX.1,
            &rawx::encode_rawx(tow + 0.5, week, None, &signals),
        );
        log.extend_from_slice(&full[..full.len() - 5]);

        let out = parse_ubx(&log, "hand.ubx").unwrap();
        assert_eq!(out.rawx.len(), 2);
        assert_eq!(out.gps_ephemerides.len(), 1);
        assert_eq!(out.gps_ephemerides[0].ephemeris.prn, 3);
        assert_eq!(out.messages["RXM-RAWX"], 3);
        assert_eq!(out.messages["RXM-SFRBX"], 4);
        assert_eq!(out.messages["0x0A-0x04"], 1);
        assert_eq!(out.skipped["frames with a bad checksum"], 1);
        assert_eq!(out.skipped["RXM-RAWX malformed"], 1);
        assert_eq!(out.skipped["GPS CNAV messages malformed"], 1);
        assert!(out.gps_cnav_ephemerides.is_empty());
        assert!(
            out.warnings.iter().any(|w| w.contains("cut short")),
            "{:?}",
            out.warnings
        );
        let obs = &out.observations;
        assert_eq!(obs.observation_types[&'G'], ["C1C", "L1C", "D1C", "S1C"]);
        let g07 = &obs.epochs[1].satellites[1];
        assert_eq!(
            (g07.prn, g07.values[0], g07.lli[1]),
            (7, Some(2.3e7), LLI_LOST_LOCK)
        );
        assert_eq!(obs.epochs[0].satellites[1].lli[1], 0);
        // BeiDou D1 words: truncated (9 of 10), BCH-failing, from a GEO
        // (D2): each skipped with its count.
        let mut log = encode(
            RXM_RAWX.0,
            RXM_RAWX.1,
            &rawx::encode_rawx(tow, week, Some(18), &signals),
        );
        log.extend(sfrbx(3, 21, 4, &[0; 9]));
        log.extend(sfrbx(3, 21, 4, &[1; 10]));
        log.extend(sfrbx(3, 3, 10, &[0; 10]));
        let out = parse_ubx(&log, "beidou.ubx").unwrap();
        assert!(out.beidou_ephemerides.is_empty());
        assert_eq!(out.skipped["RXM-SFRBX malformed"], 1);
        assert_eq!(out.skipped["BeiDou D1 subframes with a BCH failure"], 1);
        assert_eq!(out.skipped["BeiDou D2 (GEO) subframes not decoded"], 1);
        let e = parse_ubx(b"\xB5\x62 not a log", "junk.ubx").unwrap_err();
        assert!(
            e.to_string().contains("junk.ubx") && e.to_string().contains("no UBX frame"),
            "{e}"
        );
    }
}
