//! The GPS time of every sample of a text log from the RTKLIB time tag
//! written beside it.
//!
//! A line's arrival time (when the logger wrote the chunk that completed
//! it) is its sampling time plus a latency that is never negative and
//! varies with the logger's buffering; the IMU's own clock keeps the rate.
//! The map is the straight line below every (IMU time, arrival − IMU time)
//! point that lies highest at the mean IMU time: an edge of the points'
//! lower convex hull (the linear-programming estimate of clock skew from
//! one-way delays, Moon, Skelly & Towsley, "Estimation and removal of clock
//! skew from network delay measurements", IEEE INFOCOM 1999). It removes
//! the buffering (taken at its minimum) and the rate difference between
//! the IMU clock and the logger's tick; the logger's own latency to GPS
//! time remains and is what a time offset (`estimate_time_offset`) finds.
//!
//! The tag's file positions count the bytes as the logger wrote them. A
//! log written with CR LF line ends and converted to LF afterwards (as the
//! `real-imu-gnss` CSV logs were) is shorter than the positions by one
//! byte per line: the last position then exceeds the file size by exactly
//! the number of newlines. The convention is detected from that.

use crate::logs::{ImuLog, TimeTag};
use crate::{Error, Result};

/// How the tag's file positions count line ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineEnds {
    /// Byte for byte as in the file.
    AsInFile,
    /// With a CR before every LF that the file now has alone.
    CrLfCounted,
}

/// Rate difference above which a warning says the tag may not belong to
/// the log (crystal clocks are within ±100 ppm).
const SUSPICIOUS_RATE_PPM: f64 = 1_000.0;

/// The GPS times of a log's samples and how they were found.
#[derive(Debug, Clone, PartialEq)]
pub struct TagClock {
    /// GPS time of every sample, s since 1980-01-06.
    pub gps_time_s: Vec<f64>,
    /// GPS time minus IMU time at the first sample, s.
    pub offset_s: f64,
    /// Rate of the mapped time against the IMU clock, minus one, ppm.
    pub rate_ppm: f64,
    /// Largest arrival lag above the fitted line, s (the logger's buffering).
    pub arrival_lag_spread_s: f64,
    /// How the tag counted line ends (detected, or as the caller said).
    pub line_ends: LineEnds,
    /// Samples that lie inside the tagged part of the log.
    pub tagged_samples: usize,
    /// Implausible results, one sentence each.
    pub warnings: Vec<String>,
}

/// Detects how `tag` counted the bytes of `log`: its last position must
/// lie between the end of the last sample line and the end of the file
/// (a cut last line may follow the samples) when counted one way, and not
/// the other.
fn detect_line_ends(log: &ImuLog, tag: &TimeTag) -> Result<LineEnds> {
    let last = *tag
        .file_offset
        .last()
        .ok_or_else(|| Error::invalid("tag", "the time tag has no records"))?;
    let samples_end = log.line_end_offset.last().map_or(0, |&o| o + 1);
    let lines = log.line.last().map_or(0, |&l| l as u64);
    let as_in_file = samples_end..=log.file_bytes;
    let crlf = samples_end + lines..=log.file_bytes + log.newline_count;
    match (as_in_file.contains(&last), crlf.contains(&last)) {
        (true, false) => Ok(LineEnds::AsInFile),
        (false, true) => Ok(LineEnds::CrLfCounted),
        (true, true) if last == log.file_bytes => Ok(LineEnds::AsInFile),
        (true, true) => Ok(LineEnds::CrLfCounted),
        (false, false) => Err(Error::invalid(
            "tag",
            format!(
                "the time tag's last file position ({last}) fits neither the log's bytes (the samples end at {}, the file at {}) nor its bytes counted with CR LF line ends ({} and {}): tag and log do not belong together (give line_ends to map them anyway)",
                as_in_file.start(),
                as_in_file.end(),
                crlf.start(),
                crlf.end()
            ),
        )),
    }
}

/// Arrival lag (arrival − IMU time, s, relative to the tag's start) of
/// each sample inside the tagged part: (sample index, IMU time, lag).
fn arrival_lags(log: &ImuLog, tag: &TimeTag, line_ends: LineEnds) -> Vec<(usize, f64, f64)> {
    (0..log.time_s.len())
        .filter_map(|k| {
            let newline_at = log.line_end_offset[k];
            // Bytes up to and including the line's newline (all of the file
            // for a last line without one); with CR LF counted, one more
            // byte for every line end up to here.
            let mut end = (newline_at + 1).min(log.file_bytes);
            if line_ends == LineEnds::CrLfCounted {
                end += log.line[k] as u64 - u64::from(newline_at >= log.file_bytes);
            }
            let arrival = tag.arrival_gps_time(end.checked_sub(1)?)?;
            // The line's own stamp: for an increment log the samples'
            // times are the middles of the intervals the lines close.
            Some((
                k,
                log.line_time_s[k],
                arrival - tag.start_gps_time_s - log.line_time_s[k],
            ))
        })
        .collect()
}

/// Maps the IMU clock of `log` to GPS time with its time tag (see the
/// module notes); `line_ends` `None` detects the convention from the sizes.
pub fn tag_clock(log: &ImuLog, tag: &TimeTag, line_ends: Option<LineEnds>) -> Result<TagClock> {
    crate::validate::same_length("imu.line", log.line.len(), "imu.time", log.time_s.len())?;
    crate::validate::same_length(
        "imu.line_end_offset",
        log.line_end_offset.len(),
        "imu.time",
        log.time_s.len(),
    )?;
    crate::validate::same_length(
        "imu.line_time",
        log.line_time_s.len(),
        "imu.time",
        log.time_s.len(),
    )?;
    crate::validate::increasing_times("imu.time", &log.time_s)?;
    let line_ends = match line_ends {
        Some(l) => l,
        None => detect_line_ends(log, tag)?,
    };
    let points = arrival_lags(log, tag, line_ends);
    let Some(&(_, t_first, _)) = points.first() else {
        return Err(Error::invalid(
            "tag",
            "no IMU line falls inside the tagged part of the log",
        ));
    };
    // Lower convex hull of (t, lag), t increasing (Andrew's monotone chain).
    let mut hull: Vec<(f64, f64)> = Vec::new();
    for &(_, t, lag) in &points {
        let p = (t - t_first, lag);
        while hull.len() >= 2 {
            let (o, a) = (hull[hull.len() - 2], hull[hull.len() - 1]);
            let cross = (a.0 - o.0) * (p.1 - o.1) - (a.1 - o.1) * (p.0 - o.0);
            if cross > 0.0 {
                break;
            }
            hull.pop();
        }
        hull.push(p);
    }
    // The supporting line highest at the mean time: the hull edge over it.
    let mean_t = points.iter().map(|p| p.1 - t_first).sum::<f64>() / points.len() as f64;
    let edge = hull.windows(2).find(|e| e[1].0 >= mean_t);
    let (slope, (t_a, lag_a)) = match edge {
        Some(e) => ((e[1].1 - e[0].1) / (e[1].0 - e[0].0), e[0]),
        None => (0.0, hull[0]),
    };
    let line = |t: f64| lag_a + slope * (t - t_first - t_a);
    let spread = points
        .iter()
        .map(|&(_, t, lag)| lag - line(t))
        .fold(0.0, f64::max);
    let gps_time_s: Vec<f64> = log
        .time_s
        .iter()
        .map(|&t| tag.start_gps_time_s + line(t) + t)
        .collect();
    let rate_ppm = slope * 1e6;
    let mut warnings = Vec::new();
    // Over a short log the rate is free within the buffering (its effect,
    // |rate| × span, stays below the spread) and means nothing.
    let span = points[points.len() - 1].1 - t_first;
    if rate_ppm.abs() > SUSPICIOUS_RATE_PPM && slope.abs() * span > spread {
        warnings.push(format!(
            "the IMU clock runs {rate_ppm:.0} ppm off the logger's clock (crystals stay within ±100 ppm): check that the time tag belongs to this log and how it counts line ends"
        ));
    }
    Ok(TagClock {
        offset_s: gps_time_s[0] - log.time_s[0],
        gps_time_s,
        rate_ppm,
        arrival_lag_spread_s: spread,
        line_ends,
        tagged_samples: points.len(),
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::logs::{parse_imu_csv, AccelUnit, GyroUnit, ImuCsvLayout, TimeUnit};

    /// A log of `n` lines `0,0,1,0,0,0,<ms>` (one every 10 ms, IMU clock
    /// starting at 5 s) and the tag a logger writing it in chunks with CR LF
    /// line ends would write: chunk j (every 3 lines) arrives at the IMU
    /// time of its last line × (1 + 50 ppm) + 0.2 s + a buffering delay of
    /// 0-30 ms.
    fn log_and_tag(n: usize) -> (ImuLog, TimeTag) {
        let lines: Vec<String> = (0..n)
            .map(|k| format!("0,0,1,0,0,0,{}\n", 5000 + 10 * k))
            .collect();
        let text: String = lines.concat();
        let layout = ImuCsvLayout::new(
            AccelUnit::StandardGravity,
            GyroUnit::DegreesPerSecond,
            TimeUnit::Milliseconds,
        );
        let log = parse_imu_csv(text.as_bytes(), "x.csv", &layout).unwrap();
        let (mut tick_ms, mut file_offset) = (Vec::new(), Vec::new());
        let mut written = 0_u64;
        for (j, chunk) in lines.chunks(3).enumerate() {
            written += chunk.iter().map(|l| l.len() as u64 + 1).sum::<u64>();
            let last_ms = 5000.0 + 10.0 * (3 * j + chunk.len() - 1) as f64;
            let buffering = [0.0, 30.0, 12.0, 4.0][j % 4];
            let tick = last_ms * (1.0 + 50e-6) + 200.0 + buffering - 5000.0;
            tick_ms.push(tick.round() as u32);
            file_offset.push(written);
        }
        let tag = TimeTag {
            start_gps_time_s: 1e9,
            start_tick_ms: 0,
            tick_ms,
            file_offset,
            warnings: Vec::new(),
        };
        (log, tag)
    }

    #[test]
    fn crlf_counted_tags_map_to_the_minimum_latency_line() {
        let (log, tag) = log_and_tag(20_000);
        let clock = tag_clock(&log, &tag, None).unwrap();
        assert_eq!(clock.line_ends, LineEnds::CrLfCounted);
        assert_eq!(clock.tagged_samples, 20_000);
        // Lines completing a chunk arrive 0.2 s + buffering after sampling;
        // the earliest ones define the line: 50 ppm, offset 0.2 s − 5 s.
        assert!((clock.rate_ppm - 50.0).abs() < 5.0, "{}", clock.rate_ppm);
        for (k, &t) in log.time_s.iter().enumerate() {
            let expected = 1e9 + t * (1.0 + 50e-6) + 0.2 - 5.0;
            assert!((clock.gps_time_s[k] - expected).abs() < 1.5e-3, "{k}");
        }
        // The buffering shows as the spread: 30 ms plus the 20 ms a chunk's
        // first line waits for its last.
        assert!(
            (clock.arrival_lag_spread_s - 0.050).abs() < 2e-3,
            "{}",
            clock.arrival_lag_spread_s
        );
        assert!(clock.warnings.is_empty());
    }

    /// The same lines read as increments (g·s, degrees): the clock is
    /// fitted on the lines' own stamps, so it is the rate log's, and each
    /// sample (the middle of the interval its line closes) maps to the
    /// rate log's map of that middle.
    #[test]
    fn increment_logs_fit_the_clock_on_their_lines() {
        let (rates, tag) = log_and_tag(3000);
        let text: String = (0..3000)
            .map(|k| format!("0,0,1,0,0,0,{}\n", 5000 + 10 * k))
            .collect();
        let layout = ImuCsvLayout::new(
            AccelUnit::StandardGravitySeconds,
            GyroUnit::Degrees,
            TimeUnit::Milliseconds,
        );
        let increments = parse_imu_csv(text.as_bytes(), "x.csv", &layout).unwrap();
        assert_eq!(increments.line_time_s, rates.time_s[1..]);
        let a = tag_clock(&rates, &tag, None).unwrap();
        let b = tag_clock(&increments, &tag, None).unwrap();
        assert_eq!(a.rate_ppm, b.rate_ppm);
        for (k, &t) in increments.time_s.iter().enumerate() {
            // The rate log's line through samples k and k + 1, at the middle.
            let expected = 0.5 * (a.gps_time_s[k] + a.gps_time_s[k + 1]);
            assert!((t - 0.5 * (rates.time_s[k] + rates.time_s[k + 1])).abs() < 1e-12);
            assert!((b.gps_time_s[k] - expected).abs() < 1e-6, "{k}");
        }
    }

    #[test]
    fn counting_lf_alone_drifts_and_mismatched_sizes_are_refused() {
        let (log, tag) = log_and_tag(3000);
        // Forced to the wrong convention the lines seem to arrive later and
        // later: the fitted rate is far from any crystal's.
        let wrong = tag_clock(&log, &tag, Some(LineEnds::AsInFile)).unwrap();
        assert!(wrong.rate_ppm.abs() > 1_000.0, "{}", wrong.rate_ppm);
        assert!(wrong.warnings[0].contains("ppm off the logger's clock"));
        // A tag that stops before the last sample line ends does not fit.
        let mut short = tag.clone();
        *short.file_offset.last_mut().unwrap() -= 2;
        let e = tag_clock(&log, &short, None).unwrap_err();
        assert!(
            e.to_string().contains("fits neither the log's bytes"),
            "{e}"
        );
        let mut empty = tag.clone();
        empty.file_offset.clear();
        empty.tick_ms.clear();
        assert!(tag_clock(&log, &empty, None).is_err());
    }
}
