//! UBX-RXM-RAWX (class 0x02, id 0x15; u-blox F9 HPG 1.32 interface
//! description §3.17.6, and the X20 HPG 2.00 one for the newer signal ids):
//! the receiver's raw measurements of one epoch, one 32-byte block per
//! tracked signal, and their RINEX 3 observation codes (RINEX 3.04 §5.1,
//! table 4).

use super::bytes::Le;
use crate::gnss::plausible;

/// RAWX header bytes before the first measurement block.
const HEADER_BYTES: usize = 16;
/// Bytes per measurement block.
const BLOCK_BYTES: usize = 32;

/// Tracking status of one signal (RAWX `trkStat`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TrackingStatus {
    /// The pseudorange is valid.
    pub pseudorange_valid: bool,
    /// The carrier phase is valid.
    pub carrier_phase_valid: bool,
    /// The half-cycle ambiguity of the phase is resolved (`halfCyc`).
    pub half_cycle_resolved: bool,
    /// Half a cycle has been subtracted from the phase (`subHalfCyc`).
    pub half_cycle_subtracted: bool,
}

/// One signal's measurements at one epoch, as the receiver reports them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RawxSignal {
    /// RINEX system letter (`G`, `S`, `E`, `C`, `J`, `R`, `I`).
    pub system: char,
    /// Satellite number within the system as RINEX counts it (SBAS: PRN − 100).
    pub prn: u16,
    /// u-blox gnssId.
    pub gnss_id: u8,
    /// u-blox svId.
    pub sv_id: u8,
    /// u-blox sigId.
    pub sig_id: u8,
    /// GLONASS frequency slot + 7 (u-blox freqId).
    pub freq_id: u8,
    /// RINEX 3 band and attribute (`1C`, `2L`, `5Q`, `6I`, ...).
    pub rinex_code: &'static str,
    /// Pseudorange, m (meaningful when `tracking.pseudorange_valid`).
    pub pseudorange_m: f64,
    /// Carrier phase, cycles (meaningful when `tracking.carrier_phase_valid`).
    pub carrier_phase_cycles: f64,
    /// Doppler, Hz, positive for an approaching satellite (as in RINEX).
    pub doppler_hz: f64,
    /// Carrier-to-noise density, dB-Hz.
    pub cn0_db_hz: f64,
    /// Time the carrier has been tracked continuously, s (saturates at 64.5 s).
    pub lock_time_s: f64,
    /// The receiver's one-sigma pseudorange estimate, m (0.01 · 2ⁿ).
    pub pseudorange_std_m: f64,
    /// The receiver's one-sigma carrier phase estimate, cycles (0.004 · n).
    pub carrier_phase_std_cycles: f64,
    /// The receiver's one-sigma Doppler estimate, Hz (0.002 · 2ⁿ).
    pub doppler_std_hz: f64,
    /// The tracking status flags.
    pub tracking: TrackingStatus,
}

/// One RAWX epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct RawxEpoch {
    /// Receiver time of week, s (the receiver's clock: not steered to GPS time).
    pub receiver_tow_s: f64,
    /// GPS week of the receiver time (continuous, no 1024 rollover).
    pub week: u16,
    /// GPS − UTC leap seconds the receiver holds; `None` when it says they
    /// are not yet known from the navigation message (`recStat` bit 0).
    pub leap_seconds: Option<i8>,
    /// The receiver reset its clock by an integer millisecond (`clkReset`).
    pub clock_reset: bool,
    /// The signals with a known system and signal id, in message order.
    pub signals: Vec<RawxSignal>,
    /// Blocks with an unknown gnssId or sigId (left out of `signals`).
    pub unknown_signals: usize,
    /// Blocks with a value no receiver reports (left out of `signals`): a
    /// pseudorange, carrier phase or Doppler not finite, or outside its
    /// range ([`plausible::observation_range`]) while flagged valid.
    pub implausible_signals: usize,
}

impl RawxEpoch {
    /// Receiver time as GPS s since 1980-01-06.
    pub fn gps_time_s(&self) -> f64 {
        f64::from(self.week) * crate::gnss::SECONDS_PER_WEEK + self.receiver_tow_s
    }
}

/// The RINEX system letter and satellite number of u-blox (gnssId, svId),
/// or `None` for an unknown system or an unknown GLONASS slot (svId 255).
/// SBAS PRNs 120-158 are `S20`-`S58` in RINEX.
pub(super) fn rinex_satellite(gnss_id: u8, sv_id: u8) -> Option<(char, u16)> {
    let sv = u16::from(sv_id);
    let (letter, number) = match gnss_id {
        0 => ('G', sv),
        1 => ('S', sv.checked_sub(100)?),
        2 => ('E', sv),
        3 => ('C', sv),
        5 => ('J', sv),
        6 => ('R', sv),
        7 => ('I', sv),
        _ => return None,
    };
    plausible::satellite_numbers(letter)?
        .contains(&number)
        .then_some((letter, number))
}

/// RINEX 3 band and attribute of u-blox (gnssId, sigId) (interface
/// description "Signal identifiers" table against RINEX 3.04 table 4):
/// data and pilot components keep their own attribute (Galileo E1 C is
/// `1C`, E1 B `1B`; BeiDou B1C pilot `1P`, data `1D`).
pub(super) fn rinex_code(gnss_id: u8, sig_id: u8) -> Option<&'static str> {
    Some(match (gnss_id, sig_id) {
        (0, 0) => "1C",      // GPS L1 C/A
        (0, 3) => "2L",      // L2 CL
        (0, 4) => "2S",      // L2 CM
        (0, 6) => "5I",      // L5 I
        (0, 7) => "5Q",      // L5 Q
        (1, 0) => "1C",      // SBAS L1 C/A
        (2, 0) => "1C",      // Galileo E1 C
        (2, 1) => "1B",      // E1 B
        (2, 3) => "5I",      // E5a I
        (2, 4) => "5Q",      // E5a Q
        (2, 5) => "7I",      // E5b I
        (2, 6) => "7Q",      // E5b Q
        (2, 8) => "6B",      // E6 B
        (2, 9) => "6C",      // E6 C
        (3, 0 | 1) => "2I",  // BeiDou B1I D1, D2
        (3, 2 | 3) => "7I",  // B2I D1, D2
        (3, 4 | 10) => "6I", // B3I D1, D2
        (3, 5) => "1P",      // B1C pilot
        (3, 6) => "1D",      // B1C data
        (3, 7) => "5P",      // B2a pilot
        (3, 8) => "5D",      // B2a data
        (5, 0) => "1C",      // QZSS L1 C/A
        (5, 1) => "1Z",      // L1S
        (5, 4) => "2S",      // L2 CM
        (5, 5) => "2L",      // L2 CL
        (5, 8) => "5I",      // L5 I
        (5, 9) => "5Q",      // L5 Q
        (6, 0) => "1C",      // GLONASS L1 OF
        (6, 2) => "2C",      // L2 OF
        (7, 0) => "5A",      // NavIC L5 A
        _ => return None,
    })
}

/// Decodes a RAWX payload, or says why it cannot (a length that does not
/// match its measurement count, a week or time of week out of range).
pub(super) fn decode_rawx(payload: &[u8]) -> Result<RawxEpoch, String> {
    let p = Le(payload);
    if payload.len() < HEADER_BYTES {
        return Err(format!(
            "RXM-RAWX payload of {} bytes is shorter than its {HEADER_BYTES}-byte header",
            payload.len()
        ));
    }
    let count = usize::from(p.u8(11));
    if payload.len() != HEADER_BYTES + BLOCK_BYTES * count {
        return Err(format!(
            "RXM-RAWX payload of {} bytes does not hold its {count} measurements ({} bytes expected)",
            payload.len(),
            HEADER_BYTES + BLOCK_BYTES * count
        ));
    }
    let receiver_tow_s = p.f64(0);
    if !(0.0..crate::gnss::SECONDS_PER_WEEK).contains(&receiver_tow_s) {
        return Err(format!(
            "RXM-RAWX receiver time of week {receiver_tow_s} s is outside 0-604800 s"
        ));
    }
    let week = p.u16(8);
    // A receiver with an unknown week reports 0; the u-blox generations in
    // use started after week 1024 (1999), and a week from 2100 on is no
    // receiver's ([`plausible::GPS_WEEKS`]).
    let last_week = *plausible::GPS_WEEKS.end();
    if !(1024..=last_week).contains(&u32::from(week)) {
        return Err(format!(
            "RXM-RAWX week {week} is outside 1024-{last_week} (the receiver does not know the \
             time yet, or the field is corrupted)"
        ));
    }
    let status = p.u8(12);
    let mut epoch = RawxEpoch {
        receiver_tow_s,
        week,
        leap_seconds: (status & 1 == 1).then(|| p.i8(10)),
        clock_reset: status & 2 == 2,
        signals: Vec::with_capacity(count),
        unknown_signals: 0,
        implausible_signals: 0,
    };
    for k in 0..count {
        let b = Le(&payload[HEADER_BYTES + BLOCK_BYTES * k..HEADER_BYTES + BLOCK_BYTES * (k + 1)]);
        let (gnss_id, sv_id, sig_id) = (b.u8(20), b.u8(21), b.u8(22));
        let (Some((system, prn)), Some(code)) =
            (rinex_satellite(gnss_id, sv_id), rinex_code(gnss_id, sig_id))
        else {
            epoch.unknown_signals += 1;
            continue;
        };
        let track = b.u8(30);
        let signal = RawxSignal {
            system,
            prn,
            gnss_id,
            sv_id,
            sig_id,
            freq_id: b.u8(23),
            rinex_code: code,
            pseudorange_m: b.f64(0),
            carrier_phase_cycles: b.f64(8),
            doppler_hz: f64::from(b.f32(16)),
            cn0_db_hz: f64::from(b.u8(26)),
            lock_time_s: f64::from(b.u16(24)) * 1e-3,
            pseudorange_std_m: 0.01 * f64::from(1u32 << (b.u8(27) & 0x0F)),
            carrier_phase_std_cycles: 0.004 * f64::from(b.u8(28) & 0x0F),
            doppler_std_hz: 0.002 * f64::from(1u32 << (b.u8(29) & 0x0F)),
            tracking: TrackingStatus {
                pseudorange_valid: track & 1 != 0,
                carrier_phase_valid: track & 2 != 0,
                half_cycle_resolved: track & 4 != 0,
                half_cycle_subtracted: track & 8 != 0,
            },
        };
        if plausible_signal(&signal) {
            epoch.signals.push(signal);
        } else {
            epoch.implausible_signals += 1;
        }
    }
    Ok(epoch)
}

/// Whether a signal's values can come from a receiver: every value finite,
/// and a pseudorange or phase flagged valid, and the Doppler (which has no
/// flag), within the observation ranges.
fn plausible_signal(s: &RawxSignal) -> bool {
    let within = |code: &str, value: f64, valid: bool| {
        value.is_finite() && (!valid || plausible::observation_range(code).contains(&value))
    };
    let t = s.tracking;
    within("C", s.pseudorange_m, t.pseudorange_valid)
        && within("L", s.carrier_phase_cycles, t.carrier_phase_valid)
        && within("D", s.doppler_hz, true)
}

/// A RAWX payload from its parts (the inverse of [`decode_rawx`], for tests).
#[cfg(test)]
pub(super) fn encode_rawx(
    receiver_tow_s: f64,
    week: u16,
    leap_seconds: Option<i8>,
    signals: &[RawxSignal],
) -> Vec<u8> {
    let mut p = Vec::new();
    p.extend_from_slice(&receiver_tow_s.to_le_bytes());
    p.extend_from_slice(&week.to_le_bytes());
    p.push(leap_seconds.unwrap_or(0) as u8);
    p.push(u8::try_from(signals.len()).expect("at most 255 signals"));
    p.push(u8::from(leap_seconds.is_some()));
    p.extend_from_slice(&[1, 0, 0]);
    for s in signals {
        p.extend_from_slice(&s.pseudorange_m.to_le_bytes());
        p.extend_from_slice(&s.carrier_phase_cycles.to_le_bytes());
        p.extend_from_slice(&(s.doppler_hz as f32).to_le_bytes());
        p.extend_from_slice(&[s.gnss_id, s.sv_id, s.sig_id, s.freq_id]);
        p.extend_from_slice(&((s.lock_time_s * 1e3).round() as u16).to_le_bytes());
        let t = s.tracking;
        p.extend_from_slice(&[
            s.cn0_db_hz as u8,
            (s.pseudorange_std_m / 0.01).log2().round() as u8,
            (s.carrier_phase_std_cycles / 0.004).round() as u8,
            (s.doppler_std_hz / 0.002).log2().round() as u8,
            u8::from(t.pseudorange_valid)
                | u8::from(t.carrier_phase_valid) << 1
                | u8::from(t.half_cycle_resolved) << 2
                | u8::from(t.half_cycle_subtracted) << 3,
            0,
        ]);
    }
    p
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// A GPS L1 C/A signal with round values (exact in f32 where stored so).
    pub(crate) fn gps_l1(prn: u8, pseudorange_m: f64) -> RawxSignal {
        RawxSignal {
            system: 'G',
            prn: u16::from(prn),
            gnss_id: 0,
            sv_id: prn,
            sig_id: 0,
            freq_id: 0,
            rinex_code: "1C",
            pseudorange_m,
            carrier_phase_cycles: 1.25e8 + f64::from(prn),
            doppler_hz: -1234.5,
            cn0_db_hz: 44.0,
            lock_time_s: 12.345,
            pseudorange_std_m: 0.32,
            carrier_phase_std_cycles: 0.012,
            doppler_std_hz: 0.064,
            tracking: TrackingStatus {
                pseudorange_valid: true,
                carrier_phase_valid: true,
                half_cycle_resolved: true,
                half_cycle_subtracted: false,
            },
        }
    }

    #[test]
    fn round_trip_of_every_field() {
        let mut l2 = gps_l1(5, 2.2e7);
        (l2.sig_id, l2.rinex_code) = (3, "2L");
        l2.tracking.half_cycle_resolved = false;
        let mut sbas = gps_l1(0, 3.8e7);
        (sbas.system, sbas.prn, sbas.gnss_id, sbas.sv_id) = ('S', 31, 1, 131);
        let signals = [gps_l1(10, 2.1e7), l2, sbas];
        let epoch = decode_rawx(&encode_rawx(408_618.75, 2381, Some(18), &signals)).unwrap();
        assert_eq!(epoch.signals, signals);
        assert_eq!((epoch.week, epoch.leap_seconds), (2381, Some(18)));
        assert_eq!(epoch.gps_time_s(), 2381.0 * 604_800.0 + 408_618.75);
        assert!(!epoch.clock_reset);
    }

    #[test]
    fn unknown_signals_are_counted_and_bad_payloads_refused() {
        let mut odd = gps_l1(3, 2e7);
        odd.sig_id = 2; // not a GPS signal id
        let mut glo = gps_l1(255, 2e7);
        glo.gnss_id = 6; // GLONASS slot unknown
        let epoch =
            decode_rawx(&encode_rawx(1.0, 2381, None, &[odd, glo, gps_l1(4, 2e7)])).unwrap();
        assert_eq!((epoch.signals.len(), epoch.unknown_signals), (1, 2));
        assert_eq!(epoch.leap_seconds, None);
        let good = encode_rawx(1.0, 2381, None, &[gps_l1(4, 2e7)]);
        let e = decode_rawx(&good[..good.len() - 1]).unwrap_err();
        assert!(e.contains("does not hold its 1 measurements"), "{e}");
        let e = decode_rawx(&encode_rawx(1.0, 0, None, &[])).unwrap_err();
        assert!(e.contains("week 0"), "{e}");
        let e = decode_rawx(&encode_rawx(f64::NAN, 2381, None, &[])).unwrap_err();
        assert!(e.contains("time of week NaN"), "{e}");
        assert!(decode_rawx(&[0; 5]).unwrap_err().contains("shorter"));
    }

    #[test]
    fn weeks_after_2099_and_values_no_receiver_reports_are_left_out() {
        let e = decode_rawx(&encode_rawx(1.0, 9999, None, &[gps_l1(4, 2e7)])).unwrap_err();
        assert!(e.contains("week 9999 is outside 1024-6260"), "{e}");
        assert!(decode_rawx(&encode_rawx(1.0, 6260, None, &[])).is_ok());
        // ±inf Doppler, phase, pseudorange with their valid flags; a
        // pseudorange beyond 1e8 m flagged valid; the same flagged invalid
        // (kept: the flag says so).
        let mut bad = [gps_l1(4, 2e7), gps_l1(5, 2e7), gps_l1(6, f64::NEG_INFINITY)];
        bad[0].doppler_hz = f64::INFINITY;
        bad[1].carrier_phase_cycles = f64::NEG_INFINITY;
        let mut far = gps_l1(7, 3e8);
        let epoch = decode_rawx(&encode_rawx(
            1.0,
            2381,
            None,
            &[bad[0], bad[1], bad[2], far],
        ))
        .unwrap();
        assert_eq!((epoch.signals.len(), epoch.implausible_signals), (0, 4));
        far.tracking.pseudorange_valid = false;
        let epoch = decode_rawx(&encode_rawx(1.0, 2381, None, &[far])).unwrap();
        assert_eq!((epoch.signals.len(), epoch.implausible_signals), (1, 0));
    }
}
