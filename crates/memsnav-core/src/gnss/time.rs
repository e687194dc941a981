//! GPS time: seconds since the GPS epoch 1980-01-06 00:00:00 GPST.

/// Seconds in a GPS week.
pub const SECONDS_PER_WEEK: f64 = 604_800.0;

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

/// Years a data file may carry: GPS time starts in 1980; beyond 2200 a
/// date is a corrupted field, not a measurement.
pub const CALENDAR_YEARS: std::ops::RangeInclusive<i64> = 1980..=2200;

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
    fn calendar_round_trip_and_range_checks() {
        for (y, mo, d, h, mi, s) in [
            (1980, 1, 6, 0, 0, 0.0),
            (2000, 2, 29, 23, 59, 59.5),
            (2025, 7, 8, 19, 34, 18.499),
            (2100, 12, 31, 12, 0, 1.25),
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
}
