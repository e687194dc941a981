//! The `GLONASS SLOT / FRQ #` header record of RINEX 3 observation files
//! (RINEX 3.04 table A2): each GLONASS slot's FDMA frequency channel k
//! (G1 = 1602 + 0.5625 k MHz, G2 = 1246 + 0.4375 k MHz; ICD edition 5.1
//! §3.3.1.4), so that a reader knows a slot's wavelengths without a
//! navigation file. Format `I3,1X,8(A1,I2.2,1X,I2,1X)`: the number of
//! satellites, then eight `Rnn k` entries a line, continuation lines with
//! the count blank. Written in that format; read as words, since writers
//! shift it by a column.

use std::collections::BTreeMap;

/// The FDMA frequency channels a GLONASS satellite can use (ICD edition 5.1
/// §3.3.1.4: k = −7 … +6; RINEX allows up to +13 for the older plan).
const CHANNELS: std::ops::RangeInclusive<i64> = -7..=13;

/// The frequency channel k of GLONASS slot 1-24 in the current plan
/// (antipodal slots, n and n + 4 in a plane, share one; the assignment
/// broadcast in 2021-2026: R01 1, R02 −4, R03 5, R12 −1, R13 −2, R21 4 as
/// in the Pixel 6 log of the shared data). The simulator's slots take it;
/// `None` outside 1-24.
pub fn nominal_channel(slot: u16) -> Option<i8> {
    const PLAN: [i8; 8 * 3] = [
        1, -4, 5, 6, 1, -4, 5, 6, // plane 1, slots 1-8
        -2, -7, 0, -1, -2, -7, 0, -1, // plane 2, slots 9-16
        4, -3, 3, 2, 4, -3, 3, 2, // plane 3, slots 17-24
    ];
    PLAN.get(usize::from(slot).checked_sub(1)?).copied()
}

/// The G1 carrier wavelength of frequency channel `k`, m: c / (1602 +
/// 0.5625 k) MHz (ICD edition 5.1 §3.3.1.4).
pub fn g1_wavelength_m(k: i8) -> f64 {
    crate::geodesy::wgs84::SPEED_OF_LIGHT_M_S / (1_602.0e6 + 0.5625e6 * f64::from(k))
}

/// Reads one `GLONASS SLOT / FRQ #` line into `channels` (slot → k);
/// `expected` carries the header's satellite count across continuation
/// lines. The error says what is wrong in the line.
pub(super) fn read_slot_line(
    line: &str,
    channels: &mut BTreeMap<u16, i8>,
    expected: &mut Option<usize>,
) -> Result<(), String> {
    // Read as words, not columns: writers shift the fields by one (the
    // phone's GnssLogger file has the count in columns 1-2).
    let contents = line.get(..60).unwrap_or(line);
    let mut words = contents.split_whitespace().peekable();
    if let Some(count) = words.next_if(|w| !w.starts_with('R')) {
        let n: usize = count.parse().map_err(|_| {
            format!("GLONASS SLOT / FRQ #: expected the number of satellites first, got {count:?}")
        })?;
        *expected = Some(channels.len() + n);
    }
    if expected.is_none() {
        return Err("GLONASS SLOT / FRQ #: a continuation line before the first".into());
    }
    while let Some(sat) = words.next() {
        let slot = sat
            .strip_prefix('R')
            .and_then(|s| s.parse::<u16>().ok())
            .filter(|s| (1..=27).contains(s))
            .ok_or_else(|| {
                format!("GLONASS SLOT / FRQ #: expected a GLONASS slot R01-R27, got {sat:?}")
            })?;
        let k = words.next().unwrap_or("");
        let channel = k
            .parse::<i64>()
            .ok()
            .filter(|k| CHANNELS.contains(k))
            .ok_or_else(|| {
                format!("GLONASS SLOT / FRQ #: expected the frequency channel of R{slot:02} (an integer −7 to 13), got {k:?}")
            })?;
        if channels.insert(slot, channel as i8).is_some() {
            return Err(format!("GLONASS SLOT / FRQ #: R{slot:02} is listed twice"));
        }
    }
    Ok(())
}

/// The record's contents (60 columns each) for `channels`: one line even
/// when empty (count 0), as RINEX 3.04 requires the record in files with
/// GLONASS and receivers write it always.
pub(super) fn slot_lines(channels: &BTreeMap<u16, i8>) -> Vec<String> {
    let entries: Vec<String> = channels
        .iter()
        .map(|(slot, k)| format!("R{slot:02} {k:>2} "))
        .collect();
    if entries.is_empty() {
        return vec![format!("{:>3}", 0)];
    }
    entries
        .chunks(8)
        .enumerate()
        .map(|(i, chunk)| {
            let count = if i == 0 {
                format!("{:>3}", channels.len())
            } else {
                "   ".to_string()
            };
            format!("{count} {}", chunk.concat())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_phone_logs_record_and_continuations_read_back() {
        // pixel6.23o (GnssLogger via gnss_lib_py), line 13.
        let mut channels = BTreeMap::new();
        let mut expected = None;
        read_slot_line(
            " 6 R01  1 R02 -4 R03  5 R12 -1 R13 -2 R21  4                GLONASS SLOT / FRQ #",
            &mut channels,
            &mut expected,
        )
        .unwrap();
        assert_eq!(
            channels.iter().map(|(&s, &k)| (s, k)).collect::<Vec<_>>(),
            [(1, 1), (2, -4), (3, 5), (12, -1), (13, -2), (21, 4)]
        );
        // Twenty slots: three lines, read back whole.
        let many: BTreeMap<u16, i8> = (1..=20).map(|s| (s, (s as i8 % 14) - 7)).collect();
        let lines = slot_lines(&many);
        assert_eq!(lines.len(), 3);
        assert!(lines[1].starts_with("    R09"));
        let (mut back, mut expected) = (BTreeMap::new(), None);
        for l in &lines {
            assert!(l.len() <= 60);
            read_slot_line(l, &mut back, &mut expected).unwrap();
        }
        assert_eq!(back, many);
        assert_eq!(slot_lines(&BTreeMap::new()), ["  0"]);
    }

    #[test]
    fn bad_entries_are_refused_saying_why() {
        let read = |l: &str| read_slot_line(l, &mut BTreeMap::new(), &mut None);
        assert!(read("  1 R01 14")
            .unwrap_err()
            .contains("frequency channel of R01"));
        assert!(read("  1 G01  1")
            .unwrap_err()
            .contains("GLONASS slot R01-R27"));
        assert!(read("  2 R01  1 R01  1")
            .unwrap_err()
            .contains("listed twice"));
        assert!(read("    R01  1")
            .unwrap_err()
            .contains("continuation line before"));
        assert!(read(" x  R01  1")
            .unwrap_err()
            .contains("number of satellites"));
    }
}
