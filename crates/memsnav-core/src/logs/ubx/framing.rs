//! UBX framing (u-blox F9 HPG 1.32 interface description, §3.2 "UBX frame
//! structure"): `0xB5 0x62`, class, id, little-endian u16 payload length,
//! payload, then the two Fletcher-8 checksum bytes (§3.4, RFC 1146) over
//! class, id, length and payload.
//!
//! The framing is written here rather than taken from the `ublox` crate:
//! the reader must report where it lost sync and why (checksum, truncated
//! last frame) with the byte offset, count what it skipped, and keep going
//! through any byte sequence; that is twenty lines on a slice, while the
//! crate's parser is a streaming buffer that hands back typed packets only
//! for the messages it knows and decodes GPS LNAV without its parity check.

/// The two sync characters that open every UBX frame.
const SYNC: [u8; 2] = [0xB5, 0x62];
/// Sync (2), class, id, length (2) before the payload.
const HEADER_BYTES: usize = 6;
/// Header and the two checksum bytes.
const OVERHEAD_BYTES: usize = HEADER_BYTES + 2;

/// One frame whose checksum passed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Frame<'a> {
    /// Byte offset of the frame's first sync character in the log.
    pub offset: usize,
    pub class: u8,
    pub id: u8,
    pub payload: &'a [u8],
}

/// What the frame scan met besides good frames.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct FrameStats {
    /// Frames whose header looked right but whose checksum failed (the
    /// scan resumed at the next byte, so a false sync inside a payload is
    /// counted here too).
    pub checksum_failures: usize,
    /// Bytes outside any good frame (garbage, NMEA, failed frames).
    pub skipped_bytes: usize,
    /// Offset of a last frame cut short by the end of the log.
    pub truncated_at: Option<usize>,
}

/// Fletcher-8 over `bytes` (interface description §3.4): CK_A += byte,
/// CK_B += CK_A, both mod 256.
pub(super) fn checksum(bytes: &[u8]) -> [u8; 2] {
    let (mut a, mut b) = (0u8, 0u8);
    for &x in bytes {
        a = a.wrapping_add(x);
        b = b.wrapping_add(a);
    }
    [a, b]
}

/// Every frame of `log` with a good checksum, in log order, and what was
/// skipped. After a bad checksum the scan resumes one byte after the false
/// sync, so garbage of any length costs only the frames it overlaps.
pub(super) fn frames(log: &[u8]) -> (Vec<Frame<'_>>, FrameStats) {
    let mut out = Vec::new();
    let mut stats = FrameStats::default();
    let mut i = 0;
    while i < log.len() {
        let Some(found) = log[i..].windows(2).position(|w| w == SYNC) else {
            stats.skipped_bytes += log.len() - i;
            break;
        };
        stats.skipped_bytes += found;
        let start = i + found;
        let header = log.get(start..start + HEADER_BYTES);
        let length = header.map_or(0, |h| usize::from(u16::from_le_bytes([h[4], h[5]])));
        let end = start + OVERHEAD_BYTES + length;
        let (Some(header), Some(frame)) = (header, log.get(start..end)) else {
            // Cut short by the end of the log, or a false sync whose length
            // field points past it: keep scanning, and report the cut only
            // if no good frame follows.
            stats.truncated_at.get_or_insert(start);
            stats.skipped_bytes += 1;
            i = start + 1;
            continue;
        };
        if checksum(&frame[2..end - start - 2]) == frame[end - start - 2..] {
            out.push(Frame {
                offset: start,
                class: header[2],
                id: header[3],
                payload: &frame[HEADER_BYTES..end - start - 2],
            });
            stats.truncated_at = None;
            i = end;
        } else {
            stats.checksum_failures += 1;
            stats.skipped_bytes += 1;
            i = start + 1;
        }
    }
    (out, stats)
}

/// A frame around `payload` (the inverse of [`frames`], for tests and
/// hand-built logs).
#[cfg(test)]
pub(super) fn encode(class: u8, id: u8, payload: &[u8]) -> Vec<u8> {
    let length = u16::try_from(payload.len()).expect("UBX payloads are under 64 KiB");
    let mut frame = vec![SYNC[0], SYNC[1], class, id];
    frame.extend_from_slice(&length.to_le_bytes());
    frame.extend_from_slice(payload);
    let ck = checksum(&frame[2..]);
    frame.extend_from_slice(&ck);
    frame
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checksum_matches_the_interface_description_example() {
        // UBX-CFG-PRT poll "B5 62 06 00 00 00 06 18" is the frame u-center
        // sends; its checksum bytes are 06 18.
        assert_eq!(checksum(&[0x06, 0x00, 0x00, 0x00]), [0x06, 0x18]);
        // UBX-MON-VER poll: B5 62 0A 04 00 00 0E 34.
        assert_eq!(checksum(&[0x0A, 0x04, 0x00, 0x00]), [0x0E, 0x34]);
        assert_eq!(
            encode(0x0A, 0x04, &[]),
            [0xB5, 0x62, 0x0A, 0x04, 0, 0, 0x0E, 0x34]
        );
    }

    #[test]
    fn resynchronises_after_garbage_and_bad_checksums() {
        let a = encode(0x01, 0x07, &[1, 2, 3]);
        let b = encode(0x02, 0x15, &[0xB5, 0x62, 9]);
        let mut bad = encode(0x02, 0x13, &[7; 10]);
        let n = bad.len();
        bad[n - 1] ^= 0xFF;
        let mut log = b"$GPGGA,garbage\r\n\xB5".to_vec();
        log.extend_from_slice(&a);
        log.extend_from_slice(&bad);
        log.extend_from_slice(&b);
        let (f, stats) = frames(&log);
        assert_eq!(f.len(), 2);
        assert_eq!(
            (f[0].class, f[0].id, f[0].payload),
            (0x01, 0x07, &[1u8, 2, 3][..])
        );
        // A sync pair inside a good payload does not split the frame.
        assert_eq!(f[1].payload, &[0xB5, 0x62, 9]);
        assert_eq!(f[1].offset, 17 + a.len() + bad.len());
        assert_eq!(stats.checksum_failures, 1);
        assert_eq!(stats.skipped_bytes, 17 + bad.len());
        assert_eq!(stats.truncated_at, None);
    }

    #[test]
    fn a_truncated_last_frame_is_reported() {
        let a = encode(0x01, 0x07, &[1, 2, 3]);
        let mut log = a.clone();
        log.extend_from_slice(&a[..a.len() - 1]);
        let (f, stats) = frames(&log);
        assert_eq!(f.len(), 1);
        assert_eq!(stats.truncated_at, Some(a.len()));
        assert_eq!(stats.skipped_bytes, a.len() - 1);
        // A false sync whose length points past the end does not hide the
        // good frames after it.
        let mut log = vec![0xB5, 0x62, 1, 7, 0xFF, 0xFF];
        log.extend_from_slice(&a);
        let (f, stats) = frames(&log);
        assert_eq!(f.len(), 1);
        assert_eq!(stats.truncated_at, None);
        assert_eq!(stats.skipped_bytes, 6);
    }
}
