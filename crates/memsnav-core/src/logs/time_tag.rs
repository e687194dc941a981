//! RTKLIB time-tag files (`<log>.tag`), written beside a stream logged by
//! RTKLIB's `str2str`/`strsvr` (RTKLIB 2.4.3 `stream.c`, `openfile_` and
//! `writefile`): a 64-byte header, the text `TIMETAG RTKLIB <version>` with
//! the logger's absolute start tick (uint32 ms) in its last four bytes;
//! the GPST of the file's opening as a uint32 count of seconds from
//! 1970-01-01 and a double fraction of a second; then one record per write,
//! (uint32 tick, ms since the opening; uint32 file position), all
//! little-endian. `writefile` takes the tick before the write and the
//! position with `ftell` after it: a record's position is the size of the
//! log once that write was done, so byte `b` arrived with the first record
//! whose position exceeds `b`.

use std::path::Path;

use crate::gnss::UNIX_TO_GPS_S;
use crate::{Error, Result};

/// Bytes before the records: the 64-byte header and the 12-byte start time.
pub const TIME_TAG_HEADER_BYTES: usize = 76;

const MAGIC: &[u8] = b"TIMETAG RTKLIB";

/// An RTKLIB time-tag file.
#[derive(Debug, Clone, PartialEq)]
pub struct TimeTag {
    /// GPST of the log's opening, s since 1980-01-06.
    pub start_gps_time_s: f64,
    /// The logger's absolute tick at the opening, ms (to synchronise files).
    pub start_tick_ms: u32,
    /// Per write: ms since the opening, non-decreasing.
    pub tick_ms: Vec<u32>,
    /// Per write: size of the log after it, bytes, non-decreasing.
    pub file_offset: Vec<u64>,
    /// A cut last record, one sentence.
    pub warnings: Vec<String>,
}

impl TimeTag {
    /// GPS time at which the write holding byte `byte_offset` of the log
    /// (counted as the logger counted them) began; `None` past the last
    /// tagged write.
    pub fn arrival_gps_time(&self, byte_offset: u64) -> Option<f64> {
        let k = self.file_offset.partition_point(|&o| o <= byte_offset);
        self.tick_ms
            .get(k)
            .map(|&tick| self.start_gps_time_s + f64::from(tick) * 1e-3)
    }
}

/// Reads an RTKLIB `.tag` file.
pub fn read_time_tag(path: impl AsRef<Path>) -> Result<TimeTag> {
    let path = path.as_ref();
    parse_time_tag(&super::read_bytes(path)?, &path.display().to_string())
}

fn u32_at(bytes: &[u8], offset: usize) -> u32 {
    u32::from_le_bytes(bytes[offset..offset + 4].try_into().expect("4 bytes"))
}

/// Parses the bytes of an RTKLIB `.tag` file; `file` names it in errors.
/// The start must be a GPST after 1980-01-06 with a fraction in [0, 1);
/// ticks and positions must not decrease. A record cut short at the end is
/// dropped with a warning.
pub fn parse_time_tag(bytes: &[u8], file: &str) -> Result<TimeTag> {
    let error = |byte_offset: usize, reason: String| Error::ParseBinary {
        file: file.to_string(),
        byte_offset: byte_offset as u64,
        reason,
    };
    if !bytes.starts_with(MAGIC) {
        return Err(error(
            0,
            "expected the header 'TIMETAG RTKLIB ...': not an RTKLIB time-tag file".into(),
        ));
    }
    if bytes.len() < TIME_TAG_HEADER_BYTES {
        return Err(error(
            bytes.len(),
            format!(
                "expected at least {TIME_TAG_HEADER_BYTES} bytes (header and start time), got {}",
                bytes.len()
            ),
        ));
    }
    let seconds = u32_at(bytes, 64);
    if f64::from(seconds) < UNIX_TO_GPS_S {
        return Err(error(
            64,
            format!(
                "start time {seconds} s since 1970 is before the GPS epoch 1980-01-06 ({UNIX_TO_GPS_S} s)"
            ),
        ));
    }
    let fraction = f64::from_le_bytes(bytes[68..76].try_into().expect("8 bytes"));
    if !(0.0..1.0).contains(&fraction) {
        return Err(error(
            68,
            format!("start time fraction of a second {fraction} is out of range (0 to 1)"),
        ));
    }
    let records = &bytes[TIME_TAG_HEADER_BYTES..];
    let mut warnings = Vec::new();
    if records.len() % 8 != 0 {
        warnings.push(format!(
            "{file}: last time-tag record cut short ({} of 8 bytes); skipped",
            records.len() % 8
        ));
    }
    let n = records.len() / 8;
    let mut tick_ms = Vec::with_capacity(n);
    let mut file_offset = Vec::with_capacity(n);
    for k in 0..n {
        let at = TIME_TAG_HEADER_BYTES + 8 * k;
        let tick = u32_at(bytes, at);
        let offset = u64::from(u32_at(bytes, at + 4));
        if let (Some(&t0), Some(&o0)) = (tick_ms.last(), file_offset.last()) {
            if tick < t0 {
                return Err(error(
                    at,
                    format!(
                        "record {}: tick {tick} ms is before the previous record's {t0} ms",
                        k + 1
                    ),
                ));
            }
            if offset < o0 {
                return Err(error(
                    at + 4,
                    format!(
                        "record {}: file position {offset} is before the previous record's {o0}",
                        k + 1
                    ),
                ));
            }
        }
        tick_ms.push(tick);
        file_offset.push(offset);
    }
    Ok(TimeTag {
        start_gps_time_s: f64::from(seconds) - UNIX_TO_GPS_S + fraction,
        start_tick_ms: u32_at(bytes, 60),
        tick_ms,
        file_offset,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tag(seconds: u32, fraction: f64, records: &[(u32, u32)]) -> Vec<u8> {
        let mut b = b"TIMETAG RTKLIB test".to_vec();
        b.resize(60, 0);
        b.extend(7_u32.to_le_bytes());
        b.extend(seconds.to_le_bytes());
        b.extend(fraction.to_le_bytes());
        for (t, o) in records {
            b.extend(t.to_le_bytes());
            b.extend(o.to_le_bytes());
        }
        b
    }

    #[test]
    fn fields_and_arrival_of_a_byte() {
        let t = parse_time_tag(&tag(1_756_402_240, 0.5, &[(10, 100), (30, 250)]), "x.tag").unwrap();
        assert_eq!(t.start_gps_time_s, 1_756_402_240.0 - 315_964_800.0 + 0.5);
        assert_eq!((t.start_tick_ms, t.tick_ms.clone()), (7, vec![10, 30]));
        // Bytes 0-99 came with the first write, 100-249 with the second
        // (GPS times near 1.4e9 s resolve 0.24 µs).
        let at = |b| t.arrival_gps_time(b).map(|x| x - t.start_gps_time_s);
        assert!((at(99).unwrap() - 0.010).abs() < 1e-6);
        assert!((at(100).unwrap() - 0.030).abs() < 1e-6);
        assert!((at(249).unwrap() - 0.030).abs() < 1e-6);
        assert_eq!(at(250), None);
    }

    #[test]
    fn bad_files_are_errors_naming_the_byte() {
        let e = parse_time_tag(b"NOT A TAG", "x.tag").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("x.tag: byte 0: expected the header"),
            "{e}"
        );
        let e = parse_time_tag(&tag(100, 0.0, &[]), "x.tag").unwrap_err();
        assert!(
            e.to_string()
                .contains("byte 64: start time 100 s since 1970 is before"),
            "{e}"
        );
        let e = parse_time_tag(&tag(1_756_402_240, f64::NAN, &[]), "x.tag").unwrap_err();
        assert!(
            e.to_string().contains("byte 68: start time fraction"),
            "{e}"
        );
        let e = parse_time_tag(&tag(1_756_402_240, 0.0, &[(10, 0), (5, 8)]), "x.tag").unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.tag: byte 84: record 2: tick 5 ms is before the previous record's 10 ms"
        );
        let e = parse_time_tag(&tag(1_756_402_240, 0.0, &[(10, 9), (11, 8)]), "x.tag").unwrap_err();
        assert!(
            e.to_string().contains("byte 88: record 2: file position 8"),
            "{e}"
        );
        let mut b = tag(1_756_402_240, 0.0, &[(10, 9)]);
        b.extend([1, 2, 3]);
        let t = parse_time_tag(&b, "x.tag").unwrap();
        assert_eq!(t.tick_ms.len(), 1);
        assert!(t.warnings[0].contains("cut short (3 of 8 bytes)"));
    }
}
