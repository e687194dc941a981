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
}
