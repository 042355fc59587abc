//! A small UTC calendar date-time shared by the GPS and RTC drivers.
//!
//! The drivers know nothing about the sun: this type only carries a validated
//! proleptic-Gregorian UTC date and time of day (no leap seconds, no time zones)
//! and converts it to and from a count of seconds since 1970-01-01T00:00:00Z.
//!
//! The day count uses the "days from civil" construction (years counted from
//! 1 March so that the leap day is the last day of the year, then 400-year eras
//! of 146 097 days), as described in H. Hinnant, *chrono-Compatible Low-Level
//! Date Algorithms*.

use core::fmt;

/// Seconds in one day.
const SECONDS_PER_DAY: i64 = 86_400;
/// Days in one 400-year Gregorian era.
const DAYS_PER_ERA: i64 = 146_097;
/// Days from 0000-03-01 to 1970-01-01.
const UNIX_EPOCH_DAY_OFFSET: i64 = 719_468;

/// Smallest year accepted by [`DateTime::new`].
pub const MIN_YEAR: u16 = 1;
/// Largest year accepted by [`DateTime::new`].
pub const MAX_YEAR: u16 = 9999;

/// Why a date-time was rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DateTimeError {
    /// Year outside [`MIN_YEAR`]..=[`MAX_YEAR`].
    Year,
    /// Month outside 1..=12.
    Month,
    /// Day is 0 or past the end of the month.
    Day,
    /// Hour outside 0..=23.
    Hour,
    /// Minute outside 0..=59.
    Minute,
    /// Second outside 0..=59 (leap seconds are not represented).
    Second,
    /// Milliseconds outside 0..=999.
    Millis,
}

impl core::fmt::Display for DateTimeError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            DateTimeError::Year => write!(f, "year outside {MIN_YEAR}..={MAX_YEAR}"),
            DateTimeError::Month => f.write_str("month outside 1..=12"),
            DateTimeError::Day => f.write_str("day is 0 or past the end of the month"),
            DateTimeError::Hour => f.write_str("hour outside 0..=23"),
            DateTimeError::Minute => f.write_str("minute outside 0..=59"),
            DateTimeError::Second => f.write_str("second outside 0..=59"),
            DateTimeError::Millis => f.write_str("milliseconds outside 0..=999"),
        }
    }
}

impl core::error::Error for DateTimeError {}

/// A validated UTC date and time of day with millisecond resolution.
///
/// Fields are private so that every value in circulation is valid; the
/// derived ordering is chronological because the fields are declared from the
/// most to the least significant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct DateTime {
    year: u16,
    month: u8,
    day: u8,
    hour: u8,
    minute: u8,
    second: u8,
    millis: u16,
}

/// Whether `year` is a Gregorian leap year.
pub const fn is_leap_year(year: u16) -> bool {
    (year.is_multiple_of(4) && !year.is_multiple_of(100)) || year.is_multiple_of(400)
}

/// Number of days in `month` (1..=12) of `year`; 0 for an invalid month.
pub const fn days_in_month(year: u16, month: u8) -> u8 {
    match month {
        1 | 3 | 5 | 7 | 8 | 10 | 12 => 31,
        4 | 6 | 9 | 11 => 30,
        2 if is_leap_year(year) => 29,
        2 => 28,
        _ => 0,
    }
}

/// Days from 1970-01-01 to the given (already valid) civil date; negative before.
///
/// The argument types bound every intermediate value (|result| < 3 × 10⁶ for
/// any `u16` year, `u8` month and day), so nothing here can overflow, even for
/// an invalid date.
pub fn days_from_civil(year: u16, month: u8, day: u8) -> i64 {
    let m = i64::from(month);
    // Count years from March so that February (and its leap day) ends the year.
    let y = i64::from(year) - i64::from(m <= 2);
    let era = y.div_euclid(400);
    let year_of_era = y - era * 400; // 0..=399
    let month_from_march = (m + 9) % 12; // March = 0 .. February = 11
    let day_of_year = (153 * month_from_march + 2) / 5 + i64::from(day) - 1;
    let day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
    era * DAYS_PER_ERA + day_of_era - UNIX_EPOCH_DAY_OFFSET
}

/// Inverse of [`days_from_civil`]: (year, month, day) for a day count from 1970-01-01.
/// `None` when the year would fall outside [`MIN_YEAR`]..=[`MAX_YEAR`].
///
/// Any `i64` is accepted: the only steps that depend on the size of `days`
/// (the offset to 0000-03-01 and the era arithmetic) are checked, so an
/// extreme count gives `None`, never an overflow.
pub fn civil_from_days(days: i64) -> Option<(u16, u8, u8)> {
    let z = days.checked_add(UNIX_EPOCH_DAY_OFFSET)?;
    let era = z.div_euclid(DAYS_PER_ERA);
    let day_of_era = z.rem_euclid(DAYS_PER_ERA); // 0..=146096
                                                 // From here on every value is bounded by day_of_era (< 146 097).
    let year_of_era =
        (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let month_from_march = (5 * day_of_year + 2) / 153;
    let day = day_of_year - (153 * month_from_march + 2) / 5 + 1;
    let month = if month_from_march < 10 {
        month_from_march + 3
    } else {
        month_from_march - 9
    };
    let year = era
        .checked_mul(400)?
        .checked_add(year_of_era)?
        .checked_add(i64::from(month <= 2))?;
    let year = u16::try_from(year).ok()?;
    if !(MIN_YEAR..=MAX_YEAR).contains(&year) {
        return None;
    }
    Some((year, u8::try_from(month).ok()?, u8::try_from(day).ok()?))
}

impl DateTime {
    /// A validated date-time with zero milliseconds.
    pub fn new(
        year: u16,
        month: u8,
        day: u8,
        hour: u8,
        minute: u8,
        second: u8,
    ) -> Result<Self, DateTimeError> {
        if !(MIN_YEAR..=MAX_YEAR).contains(&year) {
            return Err(DateTimeError::Year);
        }
        if !(1..=12).contains(&month) {
            return Err(DateTimeError::Month);
        }
        if day == 0 || day > days_in_month(year, month) {
            return Err(DateTimeError::Day);
        }
        if hour > 23 {
            return Err(DateTimeError::Hour);
        }
        if minute > 59 {
            return Err(DateTimeError::Minute);
        }
        if second > 59 {
            return Err(DateTimeError::Second);
        }
        Ok(Self {
            year,
            month,
            day,
            hour,
            minute,
            second,
            millis: 0,
        })
    }

    /// The same instant with the given milliseconds (0..=999).
    pub fn with_millis(self, millis: u16) -> Result<Self, DateTimeError> {
        if millis > 999 {
            return Err(DateTimeError::Millis);
        }
        Ok(Self { millis, ..self })
    }

    /// Calendar year.
    pub const fn year(&self) -> u16 {
        self.year
    }
    /// Month, 1..=12.
    pub const fn month(&self) -> u8 {
        self.month
    }
    /// Day of month, 1..=31.
    pub const fn day(&self) -> u8 {
        self.day
    }
    /// Hour, 0..=23.
    pub const fn hour(&self) -> u8 {
        self.hour
    }
    /// Minute, 0..=59.
    pub const fn minute(&self) -> u8 {
        self.minute
    }
    /// Second, 0..=59.
    pub const fn second(&self) -> u8 {
        self.second
    }
    /// Milliseconds, 0..=999.
    pub const fn millis(&self) -> u16 {
        self.millis
    }

    /// Days since 1970-01-01 (negative before).
    pub fn days_since_unix_epoch(&self) -> i64 {
        days_from_civil(self.year, self.month, self.day)
    }

    /// Seconds of the day, 0..=86399.
    pub fn seconds_of_day(&self) -> u32 {
        u32::from(self.hour) * 3600 + u32::from(self.minute) * 60 + u32::from(self.second)
    }

    /// Whole seconds since 1970-01-01T00:00:00Z (milliseconds dropped).
    ///
    /// Years 1..=9999 span ±3 × 10¹¹ s and ±3 × 10¹⁴ ms, far inside `i64`, so
    /// this and the other differences below cannot overflow.
    pub fn unix_seconds(&self) -> i64 {
        self.days_since_unix_epoch() * SECONDS_PER_DAY + i64::from(self.seconds_of_day())
    }

    /// Milliseconds since 1970-01-01T00:00:00Z.
    pub fn unix_millis(&self) -> i64 {
        self.unix_seconds() * 1000 + i64::from(self.millis)
    }

    /// The date-time `unix_s` whole seconds after 1970-01-01T00:00:00Z.
    ///
    /// Any `i64` is accepted: outside years 1..=9999 the result is
    /// [`DateTimeError::Year`], never an overflow (Euclidean division by a
    /// positive constant cannot overflow; [`civil_from_days`] is checked).
    pub fn from_unix_seconds(unix_s: i64) -> Result<Self, DateTimeError> {
        let days = unix_s.div_euclid(SECONDS_PER_DAY);
        let sod = unix_s.rem_euclid(SECONDS_PER_DAY);
        let (year, month, day) = civil_from_days(days).ok_or(DateTimeError::Year)?;
        // sod is in 0..86400, so each part fits in a u8.
        let hour = u8::try_from(sod / 3600).map_err(|_| DateTimeError::Hour)?;
        let minute = u8::try_from(sod % 3600 / 60).map_err(|_| DateTimeError::Minute)?;
        let second = u8::try_from(sod % 60).map_err(|_| DateTimeError::Second)?;
        Self::new(year, month, day, hour, minute, second)
    }

    /// `self - earlier` in whole seconds (milliseconds ignored); negative if
    /// `earlier` is in fact later.
    pub fn seconds_since(&self, earlier: &DateTime) -> i64 {
        self.unix_seconds() - earlier.unix_seconds()
    }

    /// `self - earlier` in milliseconds.
    pub fn millis_since(&self, earlier: &DateTime) -> i64 {
        self.unix_millis() - earlier.unix_millis()
    }

    /// Day of the week, 1 = Sunday .. 7 = Saturday (the numbering our DS3231
    /// and DS1302 drivers write into the chips' day-of-week registers).
    pub fn weekday_from_sunday(&self) -> u8 {
        // 1970-01-01 was a Thursday (5 when Sunday is 1).
        let w = (self.days_since_unix_epoch() + 4).rem_euclid(7); // 0 = Sunday
                                                                  // rem_euclid(7) is in 0..7, so the cast cannot truncate.
        w as u8 + 1
    }
}

/// ISO 8601, e.g. `2024-03-10T12:34:56Z`, with `.sss` only when the
/// milliseconds are not zero.
impl fmt::Display for DateTime {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}",
            self.year, self.month, self.day, self.hour, self.minute, self.second
        )?;
        if self.millis != 0 {
            write!(f, ".{:03}", self.millis)?;
        }
        f.write_str("Z")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Expected day counts and weekdays computed independently with Python's
    // `datetime` module: `(date(y, m, d) - date(1970, 1, 1)).days`, `isoweekday()`.
    #[test]
    fn days_from_civil_matches_python_datetime() {
        let cases: [(u16, u8, u8, i64); 7] = [
            (2000, 1, 1, 10_957),
            (2026, 11, 21, 20_778),
            (1900, 3, 1, -25_508),
            (2100, 2, 28, 47_540),
            (1, 1, 1, -719_162),
            (9999, 12, 31, 2_932_896),
            (2024, 2, 29, 19_782),
        ];
        for (y, m, d, days) in cases {
            assert_eq!(days_from_civil(y, m, d), days, "{y}-{m}-{d}");
            assert_eq!(civil_from_days(days), Some((y, m, d)));
        }
        assert_eq!(days_from_civil(1970, 1, 1), 0);
    }

    #[test]
    fn round_trip_every_day_of_four_centuries() {
        let start = days_from_civil(1900, 1, 1);
        let end = days_from_civil(2300, 1, 1);
        let mut previous = None;
        for days in start..end {
            let (y, m, d) = civil_from_days(days).unwrap();
            assert!(DateTime::new(y, m, d, 0, 0, 0).is_ok());
            assert_eq!(days_from_civil(y, m, d), days);
            if let Some(p) = previous {
                assert!((y, m, d) > p);
            }
            previous = Some((y, m, d));
        }
    }

    #[test]
    fn leap_years_follow_the_gregorian_rule() {
        assert!(is_leap_year(2000));
        assert!(is_leap_year(2024));
        assert!(!is_leap_year(1900));
        assert!(!is_leap_year(2100));
        assert_eq!(DateTime::new(2100, 2, 29, 0, 0, 0), Err(DateTimeError::Day));
        assert!(DateTime::new(2000, 2, 29, 0, 0, 0).is_ok());
    }

    #[test]
    fn invalid_fields_are_errors() {
        assert_eq!(DateTime::new(0, 1, 1, 0, 0, 0), Err(DateTimeError::Year));
        assert_eq!(
            DateTime::new(2024, 13, 1, 0, 0, 0),
            Err(DateTimeError::Month)
        );
        assert_eq!(
            DateTime::new(2024, 0, 1, 0, 0, 0),
            Err(DateTimeError::Month)
        );
        assert_eq!(DateTime::new(2024, 4, 31, 0, 0, 0), Err(DateTimeError::Day));
        assert_eq!(DateTime::new(2024, 4, 0, 0, 0, 0), Err(DateTimeError::Day));
        assert_eq!(
            DateTime::new(2024, 4, 1, 24, 0, 0),
            Err(DateTimeError::Hour)
        );
        assert_eq!(
            DateTime::new(2024, 4, 1, 0, 60, 0),
            Err(DateTimeError::Minute)
        );
        assert_eq!(
            DateTime::new(2024, 4, 1, 0, 0, 60),
            Err(DateTimeError::Second)
        );
        let t = DateTime::new(2024, 4, 1, 0, 0, 0).unwrap();
        assert_eq!(t.with_millis(1000), Err(DateTimeError::Millis));
    }

    #[test]
    fn unix_seconds_known_instants() {
        // 1234567890 is the well-known 2009-02-13T23:31:30Z; the second value
        // is from Python: datetime(2024,3,10,12,34,56,tzinfo=utc).timestamp().
        let t = DateTime::new(2009, 2, 13, 23, 31, 30).unwrap();
        assert_eq!(t.unix_seconds(), 1_234_567_890);
        assert_eq!(DateTime::from_unix_seconds(1_234_567_890), Ok(t));
        let u = DateTime::new(2024, 3, 10, 12, 34, 56).unwrap();
        assert_eq!(u.unix_seconds(), 1_710_074_096);
        assert_eq!(u.seconds_since(&t), 1_710_074_096 - 1_234_567_890);
        assert_eq!(t.seconds_since(&u), -(1_710_074_096 - 1_234_567_890));
        assert_eq!(
            DateTime::from_unix_seconds(-1),
            Ok(DateTime::new(1969, 12, 31, 23, 59, 59).unwrap())
        );
        assert_eq!(
            DateTime::from_unix_seconds(i64::MAX),
            Err(DateTimeError::Year)
        );
        assert_eq!(
            DateTime::from_unix_seconds(i64::MIN),
            Err(DateTimeError::Year)
        );
    }

    #[test]
    fn extreme_counts_are_errors_not_overflows() {
        for days in [
            i64::MAX,
            i64::MAX - 1,
            i64::MAX - UNIX_EPOCH_DAY_OFFSET,
            i64::MAX - UNIX_EPOCH_DAY_OFFSET + 1,
            i64::MIN,
            i64::MIN + 1,
            i64::MIN + DAYS_PER_ERA,
            i64::from(i32::MAX),
            i64::from(i32::MIN),
        ] {
            assert_eq!(civil_from_days(days), None, "{days}");
        }
        for secs in [i64::MAX - 1, i64::MIN + 1, i64::MAX / 1000, i64::MIN / 1000] {
            assert_eq!(
                DateTime::from_unix_seconds(secs),
                Err(DateTimeError::Year),
                "{secs}"
            );
        }
        // The ends of the range and one second past each.
        let first = DateTime::new(MIN_YEAR, 1, 1, 0, 0, 0).unwrap();
        let last = DateTime::new(MAX_YEAR, 12, 31, 23, 59, 59).unwrap();
        assert_eq!(DateTime::from_unix_seconds(first.unix_seconds()), Ok(first));
        assert_eq!(DateTime::from_unix_seconds(last.unix_seconds()), Ok(last));
        assert_eq!(
            DateTime::from_unix_seconds(first.unix_seconds() - 1),
            Err(DateTimeError::Year)
        );
        assert_eq!(
            DateTime::from_unix_seconds(last.unix_seconds() + 1),
            Err(DateTimeError::Year)
        );
        let last_ms = last.with_millis(999).unwrap();
        assert_eq!(
            last_ms.millis_since(&first),
            (last.unix_seconds() - first.unix_seconds()) * 1000 + 999
        );
        // Unvalidated arguments to days_from_civil do not overflow either.
        let _ = days_from_civil(u16::MAX, u8::MAX, u8::MAX);
        let _ = days_from_civil(0, 0, 0);
    }

    #[test]
    fn ordering_and_millis() {
        let a = DateTime::new(2024, 12, 31, 23, 59, 59).unwrap();
        let b = DateTime::new(2025, 1, 1, 0, 0, 0).unwrap();
        assert!(a < b);
        assert_eq!(b.seconds_since(&a), 1);
        let a5 = a.with_millis(500).unwrap();
        assert!(a < a5 && a5 < b);
        assert_eq!(b.millis_since(&a5), 500);
    }

    #[test]
    fn weekdays() {
        // isoweekday from Python: 2000-01-01 = 6 (Saturday), 2024-03-10 is a Sunday.
        let sat = DateTime::new(2000, 1, 1, 0, 0, 0).unwrap();
        assert_eq!(sat.weekday_from_sunday(), 7);
        let sun = DateTime::new(2024, 3, 10, 12, 0, 0).unwrap();
        assert_eq!(sun.weekday_from_sunday(), 1);
        let thu = DateTime::new(1900, 3, 1, 0, 0, 0).unwrap();
        assert_eq!(thu.weekday_from_sunday(), 5);
    }

    #[test]
    fn display_is_iso8601() {
        extern crate std;
        use std::format;
        let t = DateTime::new(2024, 3, 10, 2, 4, 6).unwrap();
        assert_eq!(format!("{t}"), "2024-03-10T02:04:06Z");
        assert_eq!(
            format!("{}", t.with_millis(70).unwrap()),
            "2024-03-10T02:04:06.070Z"
        );
    }
}
