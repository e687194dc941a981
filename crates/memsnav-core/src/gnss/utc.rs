//! UTC to GPS time: the leap seconds between them.
//!
//! GPS time runs without leap seconds from 1980-01-06 00:00:00 UTC, when
//! the two scales agreed; UTC has since inserted a leap second at the end
//! of some Junes and Decembers (IERS Bulletin C), so
//! GPS = UTC + (leap seconds inserted since 1980), counted from the one
//! table of leap-second dates ([`super::time`]'s, IERS Bulletin C; the same
//! history as IS-GPS-200's ΔtLS and RTKLIB's `leaps`); later dates get the
//! last count, 18 s.

use super::time::{checked_gps_time_from_calendar, gps_time_from_calendar, LEAP_SECOND_DATES};

/// GPS − UTC, s, on a UTC date (1980-01-06 onwards).
pub fn leap_seconds_on(year: i64, month: i64, day: i64) -> i64 {
    LEAP_SECOND_DATES
        .iter()
        .filter(|&&date| (year, month, day) >= date)
        .count() as i64
}

/// GPS time (s since 1980-01-06 GPST) of a UTC date and time read from a
/// file, range-checked like [`checked_gps_time_from_calendar`]; a leap
/// second (23:59:60.x on the day before a new count) maps to its own
/// GPS second.
pub fn checked_gps_time_from_utc(
    year: i64,
    month: i64,
    day: i64,
    hour: i64,
    minute: i64,
    second: f64,
) -> std::result::Result<f64, String> {
    checked_gps_time_from_calendar(year, month, day, hour, minute, second)?;
    let t = gps_time_from_calendar(year, month, day, hour, minute, second)
        + leap_seconds_on(year, month, day) as f64;
    Ok(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Counts on known dates: 0 at the GPS epoch; 13 s through 2005
    /// (GPS − UTC in the 2005 almanacs); 15 s in 2011; 18 s since 2017
    /// (the value every receiver applies today).
    #[test]
    fn counts_on_known_dates() {
        assert_eq!(leap_seconds_on(1980, 1, 6), 0);
        assert_eq!(leap_seconds_on(1981, 6, 30), 0);
        assert_eq!(leap_seconds_on(1981, 7, 1), 1);
        assert_eq!(leap_seconds_on(2005, 12, 31), 13);
        assert_eq!(leap_seconds_on(2006, 1, 1), 14);
        assert_eq!(leap_seconds_on(2011, 6, 15), 15);
        assert_eq!(leap_seconds_on(2016, 12, 31), 17);
        assert_eq!(leap_seconds_on(2017, 1, 1), 18);
        assert_eq!(leap_seconds_on(2023, 11, 7), 18);
    }

    /// The leap second at the end of 2016: 23:59:60 UTC is GPS
    /// 2017-01-01 00:00:17, and UTC's next second 00:00:00 is GPS 00:00:18,
    /// one GPS second apart: the GPS scale has no gap and no repeat.
    #[test]
    fn leap_second_keeps_gps_time_continuous() {
        let before = checked_gps_time_from_utc(2016, 12, 31, 23, 59, 59.0).unwrap();
        let leap = checked_gps_time_from_utc(2016, 12, 31, 23, 59, 60.0).unwrap();
        let after = checked_gps_time_from_utc(2017, 1, 1, 0, 0, 0.0).unwrap();
        assert_eq!(leap - before, 1.0);
        assert_eq!(after - leap, 1.0);
        assert_eq!(after, gps_time_from_calendar(2017, 1, 1, 0, 0, 18.0));
        // GPS week 2287 began 2023-11-05 00:00:00 GPST (2023-11-04
        // 23:59:42 UTC); the pixel6.nmea epoch 2023-11-07 23:42:57 UTC is
        // 2 days, 23:43:15 into it.
        let t = checked_gps_time_from_utc(2023, 11, 7, 23, 42, 57.0).unwrap();
        assert_eq!(
            t,
            2287.0 * 604_800.0 + 2.0 * 86_400.0 + 23.0 * 3600.0 + 43.0 * 60.0 + 15.0
        );
        assert!(checked_gps_time_from_utc(2023, 2, 30, 0, 0, 0.0)
            .unwrap_err()
            .contains("day 30"));
    }
}
