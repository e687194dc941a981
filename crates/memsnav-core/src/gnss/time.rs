//! GPS time: seconds since the GPS epoch 1980-01-06 00:00:00 GPST.

/// Seconds in a GPS week.
pub const SECONDS_PER_WEEK: f64 = 604_800.0;

/// Seconds from 1970-01-01 to the GPS epoch 1980-01-06: GPS time counted
/// from 1970 without leap seconds (RTKLIB's `time_t`-like GPST, and the
/// "Unix-like" GPS stamps of many loggers) is GPS time plus this.
pub const UNIX_TO_GPS_S: f64 = 315_964_800.0;

/// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's
/// `days_from_civil`, exact for every date).
fn days_from_civil(year: i64, month: i64, day: i64) -> i64 {
    let y = if month <= 2 { year - 1 } else { year };
    let era = if y >= 0 { y } else { y - 399 } / 400;
    let yoe = y - era * 400;
    let mp = (month + 9) % 12;
    let doy = (153 * mp + 2) / 5 + day - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// Calendar date of a day count since 1970-01-01 (H. Hinnant's
/// `civil_from_days`, the inverse of `days_from_civil`).
fn civil_from_days(days: i64) -> (i64, i64, i64) {
    let z = days + 719_468;
    let era = if z >= 0 { z } else { z - 146_096 } / 146_097;
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1_460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    (yoe + era * 400 + i64::from(month <= 2), month, day)
}

/// Years a data file may carry: GPS time starts in 1980; from 2100 on a
/// date is a corrupted field, not a measurement
/// ([`super::plausible::LAST_YEAR`]).
pub const CALENDAR_YEARS: std::ops::RangeInclusive<i64> = 1980..=super::plausible::LAST_YEAR;

/// Days in `month` of `year` (Gregorian leap years).
fn days_in_month(year: i64, month: i64) -> i64 {
    match month {
        2 if (year % 4 == 0 && year % 100 != 0) || year % 400 == 0 => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

/// [`gps_time_from_calendar`] for a date read from a file: the year in
/// [`CALENDAR_YEARS`] and not before 1980-01-06, a real day of the month,
/// hour 0-23, minute 0-59, second in [0, 61) (a leap second may be 60.x).
/// The error says which field is out of range, for the reader to place in
/// the file.
pub fn checked_gps_time_from_calendar(
    year: i64,
    month: i64,
    day: i64,
    hour: i64,
    minute: i64,
    second: f64,
) -> std::result::Result<f64, String> {
    if !CALENDAR_YEARS.contains(&year) {
        return Err(format!(
            "year {year} is out of range ({}-{})",
            CALENDAR_YEARS.start(),
            CALENDAR_YEARS.end()
        ));
    }
    if !(1..=12).contains(&month) {
        return Err(format!("month {month} is out of range (1-12)"));
    }
    let last_day = days_in_month(year, month);
    if !(1..=last_day).contains(&day) {
        return Err(format!(
            "day {day} is out of range (1-{last_day} for {year}-{month:02})"
        ));
    }
    if !(0..=23).contains(&hour) {
        return Err(format!("hour {hour} is out of range (0-23)"));
    }
    if !(0..=59).contains(&minute) {
        return Err(format!("minute {minute} is out of range (0-59)"));
    }
    if !(0.0..61.0).contains(&second) {
        return Err(format!("second {second} is out of range (0-60.999)"));
    }
    let t = gps_time_from_calendar(year, month, day, hour, minute, second);
    if t < 0.0 {
        return Err(format!(
            "{year}-{month:02}-{day:02} is before the GPS epoch 1980-01-06"
        ));
    }
    Ok(t)
}

/// A calendar epoch as a reader's message shows it, `2021-04-28 00:05:00`
/// (fractions of a second kept: `17:30:39.748`), from the fields as read:
/// formatting them, not a GPS time, keeps 59.99999999 s from rounding up.
pub fn calendar_text(
    year: i64,
    month: i64,
    day: i64,
    hour: i64,
    minute: i64,
    second: f64,
) -> String {
    // 8 decimals: the finest epoch field of the formats read (SP3, F11.8).
    let second = format!("{second:011.8}");
    let second = second.trim_end_matches('0').trim_end_matches('.');
    format!("{year}-{month:02}-{day:02} {hour:02}:{minute:02}:{second}")
}

/// Calendar date and time (GPST) of a GPS time: year, month, day, hour,
/// minute and the seconds of the minute.
pub fn calendar_from_gps_time(gps_time_s: f64) -> (i64, i64, i64, i64, i64, f64) {
    let days = (gps_time_s / 86_400.0).floor();
    let seconds_of_day = gps_time_s - days * 86_400.0;
    let (year, month, day) = civil_from_days(days as i64 + days_from_civil(1980, 1, 6));
    let hour = (seconds_of_day / 3_600.0).floor();
    let minute = ((seconds_of_day - hour * 3_600.0) / 60.0).floor();
    let second = seconds_of_day - hour * 3_600.0 - minute * 60.0;
    (year, month, day, hour as i64, minute as i64, second)
}

/// GPS time (s since 1980-01-06 GPST) of a calendar date and time that is
/// already in GPST (RINEX navigation epochs and SP3 epochs are).
pub fn gps_time_from_calendar(
    year: i64,
    month: i64,
    day: i64,
    hour: i64,
    minute: i64,
    second: f64,
) -> f64 {
    let days = days_from_civil(year, month, day) - days_from_civil(1980, 1, 6);
    (days * 86_400 + hour * 3_600 + minute * 60) as f64 + second
}

/// The UTC dates (00:00:00 UTC) from which GPS − UTC grew by one second:
/// the leap seconds since the GPS epoch (IERS Bulletin C; GPS − UTC is 0 s
/// at 1980-01-06 and 18 s from 2017-01-01). The list is complete up to
/// [`LEAP_SECONDS_KNOWN_UNTIL`]; a later announcement must be added here.
pub(crate) const LEAP_SECOND_DATES: [(i64, i64, i64); 18] = [
    (1981, 7, 1),
    (1982, 7, 1),
    (1983, 7, 1),
    (1985, 7, 1),
    (1988, 1, 1),
    (1990, 1, 1),
    (1991, 1, 1),
    (1992, 7, 1),
    (1993, 7, 1),
    (1994, 7, 1),
    (1996, 1, 1),
    (1997, 7, 1),
    (1999, 1, 1),
    (2006, 1, 1),
    (2009, 1, 1),
    (2012, 7, 1),
    (2015, 7, 1),
    (2017, 1, 1),
];

/// The last day (UTC) for which `LEAP_SECOND_DATES` is known complete:
/// IERS Bulletin C 70 (July 2025) announced no leap second at the end of
/// December 2025. Later times take the last known offset, 18 s.
pub const LEAP_SECONDS_KNOWN_UNTIL: (i64, i64, i64) = (2025, 12, 31);

/// Milliseconds of GPS time at which leap second `i` (0-based) ends, that
/// is at 00:00:00 UTC of its date, when GPS − UTC becomes `i + 1` s. The
/// inserted second 23:59:60 UTC is the second before it.
fn leap_end_gps_ms(i: usize) -> i64 {
    let (y, m, d) = LEAP_SECOND_DATES[i];
    let days = days_from_civil(y, m, d) - days_from_civil(1980, 1, 6);
    (days * 86_400 + i as i64 + 1) * 1000
}

/// GPS − UTC at a GPS time, s (0 before the first leap second; during an
/// inserted second the count before it).
pub fn gps_minus_utc_s(gps_time_s: f64) -> f64 {
    let ms = (gps_time_s * 1000.0).floor() as i64;
    (0..LEAP_SECOND_DATES.len())
        .filter(|&i| leap_end_gps_ms(i) <= ms)
        .count() as f64
}

/// UTC of a GPS time as ISO 8601 with milliseconds, `2025-08-28T17:30:21.749Z`
/// (the GPS time rounded to the millisecond first); an instant inside an
/// inserted leap second reads `23:59:60.xxx`.
pub fn utc_text_from_gps_time(gps_time_s: f64) -> String {
    let gps_ms = (gps_time_s * 1000.0).round() as i64;
    let leaps = (0..LEAP_SECOND_DATES.len())
        .filter(|&i| leap_end_gps_ms(i) <= gps_ms)
        .count();
    let in_leap_second = leaps < LEAP_SECOND_DATES.len() && gps_ms >= leap_end_gps_ms(leaps) - 1000;
    // Inside the inserted second: the clock reads 23:59:59 plus one second.
    let utc_ms = gps_ms - leaps as i64 * 1000 - if in_leap_second { 1000 } else { 0 };
    let (year, month, day) =
        civil_from_days(utc_ms.div_euclid(86_400_000) + days_from_civil(1980, 1, 6));
    let ms_of_day = utc_ms.rem_euclid(86_400_000);
    let second = ms_of_day / 1000 % 60 + i64::from(in_leap_second);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{second:02}.{:03}Z",
        ms_of_day / 3_600_000,
        ms_of_day / 60_000 % 60,
        ms_of_day % 1000
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_week_starts() {
        // GPS week 1865 began on 2015-10-04 and week 2155 on 2021-04-25
        // (the week numbers in the 2015-280 and 2021-118 broadcast files).
        assert_eq!(
            gps_time_from_calendar(2015, 10, 4, 0, 0, 0.0),
            1865.0 * SECONDS_PER_WEEK
        );
        assert_eq!(
            gps_time_from_calendar(2021, 4, 25, 0, 0, 0.0),
            2155.0 * SECONDS_PER_WEEK
        );
        assert_eq!(gps_time_from_calendar(1980, 1, 6, 0, 0, 0.0), 0.0);
    }

    #[test]
    fn calendar_text_pads_fields_and_keeps_fractions() {
        assert_eq!(calendar_text(2021, 4, 28, 0, 5, 0.0), "2021-04-28 00:05:00");
        assert_eq!(
            calendar_text(2025, 8, 28, 17, 30, 39.748),
            "2025-08-28 17:30:39.748"
        );
        assert_eq!(
            calendar_text(2025, 8, 28, 17, 30, 9.5),
            "2025-08-28 17:30:09.5"
        );
        assert_eq!(
            calendar_text(2016, 12, 31, 23, 59, 60.0),
            "2016-12-31 23:59:60"
        );
    }

    #[test]
    fn the_plausible_time_range_ends_with_2099() {
        use super::super::plausible::{END_GPS_TIME_S, GPS_WEEKS, LAST_YEAR};
        assert_eq!(
            gps_time_from_calendar(LAST_YEAR + 1, 1, 1, 0, 0, 0.0),
            END_GPS_TIME_S
        );
        let last_week = f64::from(*GPS_WEEKS.end());
        assert!(last_week * SECONDS_PER_WEEK < END_GPS_TIME_S);
        assert!((last_week + 1.0) * SECONDS_PER_WEEK >= END_GPS_TIME_S);
    }

    #[test]
    fn calendar_round_trip_and_range_checks() {
        for (y, mo, d, h, mi, s) in [
            (1980, 1, 6, 0, 0, 0.0),
            (2000, 2, 29, 23, 59, 59.5),
            (2025, 7, 8, 19, 34, 18.499),
            (2099, 12, 31, 12, 0, 1.25),
        ] {
            let t = checked_gps_time_from_calendar(y, mo, d, h, mi, s).unwrap();
            let (y2, mo2, d2, h2, mi2, s2) = calendar_from_gps_time(t);
            assert_eq!((y2, mo2, d2, h2, mi2), (y, mo, d, h, mi));
            assert!((s2 - s).abs() < 1e-6, "{s2} {s}");
        }
        for (fields, word) in [
            ((2025, 13, 1, 0, 0, 0.0), "month 13"),
            ((2025, 8, 28, 25, 0, 0.0), "hour 25"),
            ((0, 8, 28, 0, 0, 0.0), "year 0"),
            (
                (2100, 1, 1, 0, 0, 0.0),
                "year 2100 is out of range (1980-2099)",
            ),
            ((2023, 2, 29, 0, 0, 0.0), "day 29"),
            ((2025, 8, 28, 0, 60, 0.0), "minute 60"),
            ((2025, 8, 28, 0, 0, 61.0), "second 61"),
            ((1980, 1, 5, 0, 0, 0.0), "before the GPS epoch"),
        ] {
            let (y, mo, d, h, mi, s) = fields;
            let e = checked_gps_time_from_calendar(y, mo, d, h, mi, s).unwrap_err();
            assert!(e.contains(word), "{e}");
        }
        assert!(checked_gps_time_from_calendar(2025, 8, 28, 0, 0, f64::NAN).is_err());
    }

    #[test]
    fn gps_minus_utc_at_known_dates() {
        // 0 s at the GPS epoch, 1 s from 1981-07-01 00:00:00 UTC (GPST
        // 00:00:01), 13 s through 2005, 17 s in 2016, 18 s since 2017.
        assert_eq!(gps_minus_utc_s(0.0), 0.0);
        let july_1981 = gps_time_from_calendar(1981, 7, 1, 0, 0, 0.0);
        assert_eq!(gps_minus_utc_s(july_1981 + 0.999), 0.0);
        assert_eq!(gps_minus_utc_s(july_1981 + 1.0), 1.0);
        assert_eq!(
            gps_minus_utc_s(gps_time_from_calendar(2005, 12, 31, 12, 0, 0.0)),
            13.0
        );
        assert_eq!(
            gps_minus_utc_s(gps_time_from_calendar(2016, 6, 1, 0, 0, 0.0)),
            17.0
        );
        assert_eq!(
            gps_minus_utc_s(gps_time_from_calendar(2025, 8, 28, 0, 0, 0.0)),
            18.0
        );
    }

    #[test]
    fn utc_text_across_the_2016_leap_second() {
        assert_eq!(utc_text_from_gps_time(0.0), "1980-01-06T00:00:00.000Z");
        // GPS week 1930 began at GPST 2017-01-01 00:00:00, which was
        // 2016-12-31 23:59:43 UTC (GPS − UTC 17 s); the leap second
        // 23:59:60 UTC spans GPST 00:00:17-00:00:18.
        let week_1930 = 1930.0 * SECONDS_PER_WEEK;
        assert_eq!(week_1930, gps_time_from_calendar(2017, 1, 1, 0, 0, 0.0));
        for (gps_s, utc) in [
            (0.0, "2016-12-31T23:59:43.000Z"),
            (16.999, "2016-12-31T23:59:59.999Z"),
            (17.0, "2016-12-31T23:59:60.000Z"),
            (17.5, "2016-12-31T23:59:60.500Z"),
            (17.9996, "2017-01-01T00:00:00.000Z"),
            (18.0, "2017-01-01T00:00:00.000Z"),
        ] {
            assert_eq!(utc_text_from_gps_time(week_1930 + gps_s), utc, "{gps_s}");
        }
        // The walk_0827 log: GPST 2025-08-28 17:30:39.749 is 17:30:21.749 UTC.
        let walk = gps_time_from_calendar(2025, 8, 28, 17, 30, 39.749);
        assert_eq!(utc_text_from_gps_time(walk), "2025-08-28T17:30:21.749Z");
    }
}
