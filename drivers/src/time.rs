//! A small UTC calendar date-time shared by the GPS and RTC drivers.
//!
//! The drivers know nothing about the sun: this type only carries a validated
//! proleptic-Gregorian UTC date and time of day (no leap seconds, no time zones)
//! and converts it to and from a count of seconds since 1970-01-01T00:00:00Z.
//!
//! The calendar is the `suntracker-time` crate's (re-exported here as
//! [`Date`] and [`DateError`]): a [`DateTime`] holds a [`Date`] plus the time
//! of day, and every day count, leap-year and month-length rule below is that
//! crate's, in 16- and 32-bit arithmetic (H. Hinnant, *chrono-Compatible
//! Low-Level Date Algorithms*). `sun_algos`' `UtcTime` uses the same crate, so
//! [`DateTime::date`] and [`DateTime::from_date_ms`] exchange an instant with
//! it without a second calendar.
//!
//! ```
//! use drivers::time::DateTime;
//!
//! // A GPS fix's time, then the same instant as a Unix time and back; the
//! // count is Python's
//! // datetime(2024, 3, 10, 12, 34, 56, tzinfo=timezone.utc).timestamp().
//! let t = DateTime::new(2024, 3, 10, 12, 34, 56)?;
//! assert_eq!(t.unix_seconds(), 1_710_074_096);
//! assert_eq!(DateTime::from_unix_seconds(1_710_074_096)?, t);
//! # Ok::<(), drivers::time::DateTimeError>(())
//! ```
//!
//! Optional features add chrono conversions (`chrono`), serde support
//! (`serde`, validated again on the way in) and `defmt::Format` (`defmt`).

use core::fmt;

#[cfg(feature = "chrono")]
mod with_chrono;
#[cfg(feature = "defmt")]
mod with_defmt;
#[cfg(feature = "serde")]
mod with_serde;

pub use suntracker_time::{Date, DateError};

/// Seconds in one day.
const SECONDS_PER_DAY: i64 = 86_400;
/// Milliseconds in one day.
const MS_PER_DAY: u32 = 86_400_000;

/// Smallest year accepted by [`DateTime::new`].
///
/// ```
/// use drivers::time::{DateTime, DateTimeError, MIN_YEAR};
///
/// assert!(DateTime::new(MIN_YEAR, 1, 1, 0, 0, 0).is_ok());
/// assert_eq!(DateTime::new(MIN_YEAR - 1, 1, 1, 0, 0, 0), Err(DateTimeError::Year));
/// ```
pub const MIN_YEAR: u16 = 1;
/// Largest year accepted by [`DateTime::new`].
///
/// ```
/// use drivers::time::{DateTime, DateTimeError, MAX_YEAR};
///
/// let last = DateTime::new(MAX_YEAR, 12, 31, 23, 59, 59)?;
/// assert_eq!(DateTime::from_unix_seconds(last.unix_seconds() + 1), Err(DateTimeError::Year));
/// # Ok::<(), DateTimeError>(())
/// ```
pub const MAX_YEAR: u16 = 9999;

/// Why a date-time was rejected.
///
/// ```
/// use drivers::time::{DateTime, DateTimeError};
///
/// // 2023 is not a leap year.
/// let e = DateTime::new(2023, 2, 29, 0, 0, 0).unwrap_err();
/// assert_eq!(e, DateTimeError::Day);
/// assert_eq!(e.to_string(), "day is 0 or past the end of the month");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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

impl From<DateError> for DateTimeError {
    fn from(e: DateError) -> Self {
        match e {
            DateError::Year => DateTimeError::Year,
            DateError::Month => DateTimeError::Month,
            DateError::Day => DateTimeError::Day,
        }
    }
}

/// A validated UTC date and time of day with millisecond resolution.
///
/// Fields are private so that every value in circulation is valid; the
/// derived ordering is chronological because the fields are declared from the
/// most to the least significant (a [`Date`] orders by year, month, day).
///
/// With the `serde` feature it is (de)serialized as its seven fields
/// (`year`, `month`, `day`, `hour`, `minute`, `second`, `millis`) and
/// checked again on the way in: an invalid date-time is a deserialization
/// error. With `defmt` it prints as ISO 8601, like its `Display`.
///
/// ```
/// use drivers::time::DateTime;
///
/// let a = DateTime::new(2024, 12, 31, 23, 59, 59)?;
/// let b = DateTime::new(2025, 1, 1, 0, 0, 0)?;
/// assert!(a < b);
/// assert_eq!(b.seconds_since(&a), 1);
/// assert_eq!(a.to_string(), "2024-12-31T23:59:59Z");
/// # Ok::<(), drivers::time::DateTimeError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(
        try_from = "with_serde::DateTimeFields",
        into = "with_serde::DateTimeFields"
    )
)]
pub struct DateTime {
    /// Years [`MIN_YEAR`]..=[`MAX_YEAR`] only.
    date: Date,
    hour: u8,
    minute: u8,
    second: u8,
    millis: u16,
}

/// Whether `year` is a Gregorian leap year.
///
/// ```
/// use drivers::time::is_leap_year;
///
/// // Gregorian rule: every fourth year, except centuries not divisible by 400.
/// assert!(is_leap_year(2024) && is_leap_year(2000));
/// assert!(!is_leap_year(1900) && !is_leap_year(2100) && !is_leap_year(2023));
/// ```
pub const fn is_leap_year(year: u16) -> bool {
    suntracker_time::is_leap_year(year as i32) // u16 → i32 is lossless
}

/// Number of days in `month` (1..=12) of `year`; 0 for an invalid month.
///
/// ```
/// use drivers::time::days_in_month;
///
/// assert_eq!(days_in_month(2024, 2), 29);
/// assert_eq!(days_in_month(2100, 2), 28);
/// assert_eq!(days_in_month(2024, 4), 30);
/// assert_eq!(days_in_month(2024, 13), 0);
/// ```
pub const fn days_in_month(year: u16, month: u8) -> u8 {
    suntracker_time::days_in_month(year as i32, month) // u16 → i32 is lossless
}

/// Days from 1970-01-01 to the given (already valid) civil date; negative before.
///
/// `suntracker_time::days_from_civil`, which gives a count for any
/// arguments without overflowing, so an invalid date gives some nearby count,
/// never a panic.
///
/// ```
/// use drivers::time::days_from_civil;
///
/// // Python: (date(y, m, d) - date(1970, 1, 1)).days
/// assert_eq!(days_from_civil(1970, 1, 1), 0);
/// assert_eq!(days_from_civil(2024, 3, 10), 19_792);
/// assert_eq!(days_from_civil(1, 1, 1), -719_162);
/// ```
pub fn days_from_civil(year: u16, month: u8, day: u8) -> i64 {
    suntracker_time::days_from_civil(i32::from(year), month, day)
}

/// Inverse of [`days_from_civil`]: (year, month, day) for a day count from 1970-01-01.
/// `None` when the year would fall outside [`MIN_YEAR`]..=[`MAX_YEAR`].
///
/// Any `i64` is accepted: a count beyond `i32` or beyond a [`Date`]'s years
/// is `None`, never an overflow.
///
/// ```
/// use drivers::time::civil_from_days;
///
/// // Python: date(1970, 1, 1) + timedelta(days=n)
/// assert_eq!(civil_from_days(11_017), Some((2000, 3, 1)));
/// assert_eq!(civil_from_days(2_932_896), Some((9999, 12, 31)));
/// assert_eq!(civil_from_days(2_932_897), None); // year 10 000
/// assert_eq!(civil_from_days(i64::MIN), None);
/// ```
pub fn civil_from_days(days: i64) -> Option<(u16, u8, u8)> {
    let date = Date::from_days_since_unix_epoch(i32::try_from(days).ok()?).ok()?;
    let year = u16::try_from(date.year()).ok()?;
    if !(MIN_YEAR..=MAX_YEAR).contains(&year) {
        return None;
    }
    Some((year, date.month(), date.day()))
}

impl DateTime {
    /// A validated date-time with zero milliseconds.
    ///
    /// ```
    /// use drivers::time::{DateTime, DateTimeError};
    ///
    /// let t = DateTime::new(2024, 2, 29, 23, 59, 59)?;
    /// assert_eq!(t.millis(), 0);
    /// assert_eq!(DateTime::new(2024, 4, 31, 0, 0, 0), Err(DateTimeError::Day));
    /// assert_eq!(DateTime::new(2024, 1, 1, 24, 0, 0), Err(DateTimeError::Hour));
    /// // No leap seconds.
    /// assert_eq!(DateTime::new(2016, 12, 31, 23, 59, 60), Err(DateTimeError::Second));
    /// assert_eq!(DateTime::new(0, 1, 1, 0, 0, 0), Err(DateTimeError::Year));
    /// # Ok::<(), DateTimeError>(())
    /// ```
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
        let date = Date::new(i32::from(year), month, day)?;
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
            date,
            hour,
            minute,
            second,
            millis: 0,
        })
    }

    /// The instant `ms_of_day` milliseconds after midnight of `date`:
    /// [`DateTimeError::Year`] for a year outside
    /// [`MIN_YEAR`]..=[`MAX_YEAR`], [`DateTimeError::Hour`] for
    /// `ms_of_day` ≥ 86 400 000 (24 h).
    ///
    /// ```
    /// use drivers::time::{Date, DateTime, DateTimeError};
    ///
    /// let day = Date::new(2024, 3, 10)?;
    /// // 45 296 070 ms = 12 h 34 min 56.070 s.
    /// let t = DateTime::from_date_ms(day, 45_296_070)?;
    /// assert_eq!(t, DateTime::new(2024, 3, 10, 12, 34, 56)?.with_millis(70)?);
    /// assert_eq!(DateTime::from_date_ms(day, 86_400_000), Err(DateTimeError::Hour));
    /// // A Date reaches further back than a DateTime.
    /// assert_eq!(DateTime::from_date_ms(Date::new(0, 1, 1)?, 0), Err(DateTimeError::Year));
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn from_date_ms(date: Date, ms_of_day: u32) -> Result<Self, DateTimeError> {
        if !(i32::from(MIN_YEAR)..=i32::from(MAX_YEAR)).contains(&date.year()) {
            return Err(DateTimeError::Year);
        }
        if ms_of_day >= MS_PER_DAY {
            return Err(DateTimeError::Hour);
        }
        let s = ms_of_day / 1000; // 0..86 400: every part below fits its type
        Ok(Self {
            date,
            hour: (s / 3600) as u8,
            minute: (s / 60 % 60) as u8,
            second: (s % 60) as u8,
            millis: (ms_of_day % 1000) as u16,
        })
    }

    /// The same instant with the given milliseconds (0..=999).
    ///
    /// ```
    /// use drivers::time::{DateTime, DateTimeError};
    ///
    /// let t = DateTime::new(2024, 3, 10, 2, 4, 6)?;
    /// assert_eq!(t.with_millis(70)?.to_string(), "2024-03-10T02:04:06.070Z");
    /// assert_eq!(t.with_millis(1000), Err(DateTimeError::Millis));
    /// # Ok::<(), DateTimeError>(())
    /// ```
    pub fn with_millis(self, millis: u16) -> Result<Self, DateTimeError> {
        if millis > 999 {
            return Err(DateTimeError::Millis);
        }
        Ok(Self { millis, ..self })
    }

    /// The calendar date.
    ///
    /// ```
    /// use drivers::time::{Date, DateTime};
    ///
    /// let t = DateTime::new(2024, 3, 10, 12, 0, 0)?;
    /// assert_eq!(t.date(), Date::new(2024, 3, 10)?);
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub const fn date(&self) -> Date {
        self.date
    }
    /// Calendar year.
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// let t = DateTime::new(2024, 3, 10, 12, 34, 56)?.with_millis(70)?;
    /// assert_eq!(t.year(), 2024);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub const fn year(&self) -> u16 {
        // MIN_YEAR..=MAX_YEAR (checked by every constructor): fits a u16.
        self.date.year() as u16
    }
    /// Month, 1..=12.
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// let t = DateTime::new(2024, 3, 10, 12, 34, 56)?.with_millis(70)?;
    /// assert_eq!(t.month(), 3);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub const fn month(&self) -> u8 {
        self.date.month()
    }
    /// Day of month, 1..=31.
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// let t = DateTime::new(2024, 3, 10, 12, 34, 56)?.with_millis(70)?;
    /// assert_eq!(t.day(), 10);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub const fn day(&self) -> u8 {
        self.date.day()
    }
    /// Hour, 0..=23.
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// let t = DateTime::new(2024, 3, 10, 12, 34, 56)?.with_millis(70)?;
    /// assert_eq!(t.hour(), 12);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub const fn hour(&self) -> u8 {
        self.hour
    }
    /// Minute, 0..=59.
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// let t = DateTime::new(2024, 3, 10, 12, 34, 56)?.with_millis(70)?;
    /// assert_eq!(t.minute(), 34);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub const fn minute(&self) -> u8 {
        self.minute
    }
    /// Second, 0..=59.
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// let t = DateTime::new(2024, 3, 10, 12, 34, 56)?.with_millis(70)?;
    /// assert_eq!(t.second(), 56);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub const fn second(&self) -> u8 {
        self.second
    }
    /// Milliseconds, 0..=999.
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// let t = DateTime::new(2024, 3, 10, 12, 34, 56)?.with_millis(70)?;
    /// assert_eq!(t.millis(), 70);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub const fn millis(&self) -> u16 {
        self.millis
    }

    /// Days since 1970-01-01 (negative before).
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// // Python: (date(2024, 3, 10) - date(1970, 1, 1)).days
    /// assert_eq!(DateTime::new(2024, 3, 10, 23, 0, 0)?.days_since_unix_epoch(), 19_792);
    /// assert_eq!(DateTime::new(1969, 12, 31, 0, 0, 0)?.days_since_unix_epoch(), -1);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub fn days_since_unix_epoch(&self) -> i64 {
        i64::from(self.date.days_since_unix_epoch())
    }

    /// Seconds of the day, 0..=86399.
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// // 12·3600 + 34·60 + 56
    /// assert_eq!(DateTime::new(2024, 3, 10, 12, 34, 56)?.seconds_of_day(), 45_296);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub fn seconds_of_day(&self) -> u32 {
        u32::from(self.hour) * 3600 + u32::from(self.minute) * 60 + u32::from(self.second)
    }

    /// Milliseconds of the day, 0..=86 399 999.
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// let t = DateTime::new(2024, 3, 10, 23, 59, 59)?.with_millis(999)?;
    /// assert_eq!(t.ms_of_day(), 86_399_999);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub fn ms_of_day(&self) -> u32 {
        self.seconds_of_day() * 1000 + u32::from(self.millis)
    }

    /// Whole seconds since 1970-01-01T00:00:00Z (milliseconds dropped).
    ///
    /// Years 1..=9999 span ±3 × 10¹¹ s and ±3 × 10¹⁴ ms, far inside `i64`, so
    /// this and the other differences below cannot overflow.
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// // The well-known 1234567890 s.
    /// let t = DateTime::new(2009, 2, 13, 23, 31, 30)?.with_millis(500)?;
    /// assert_eq!(t.unix_seconds(), 1_234_567_890);
    /// // Before 1970 the count is negative: the second before the epoch.
    /// assert_eq!(DateTime::new(1969, 12, 31, 23, 59, 59)?.unix_seconds(), -1);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub fn unix_seconds(&self) -> i64 {
        self.days_since_unix_epoch() * SECONDS_PER_DAY + i64::from(self.seconds_of_day())
    }

    /// Milliseconds since 1970-01-01T00:00:00Z.
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// // Python: datetime(2024, 2, 29, 23, 59, 59, 999000, tzinfo=timezone.utc).timestamp()
    /// let t = DateTime::new(2024, 2, 29, 23, 59, 59)?.with_millis(999)?;
    /// assert_eq!(t.unix_millis(), 1_709_251_199_999);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub fn unix_millis(&self) -> i64 {
        self.unix_seconds() * 1000 + i64::from(self.millis)
    }

    /// The date-time `unix_s` whole seconds after 1970-01-01T00:00:00Z.
    ///
    /// Any `i64` is accepted: outside years 1..=9999 the result is
    /// [`DateTimeError::Year`], never an overflow (Euclidean division by a
    /// positive constant cannot overflow; the day count is checked).
    ///
    /// ```
    /// use drivers::time::{DateTime, DateTimeError};
    ///
    /// // Python: datetime.fromtimestamp(1_700_000_000, timezone.utc)
    /// assert_eq!(
    ///     DateTime::from_unix_seconds(1_700_000_000)?,
    ///     DateTime::new(2023, 11, 14, 22, 13, 20)?
    /// );
    /// assert_eq!(DateTime::from_unix_seconds(-1)?, DateTime::new(1969, 12, 31, 23, 59, 59)?);
    /// assert_eq!(DateTime::from_unix_seconds(i64::MAX), Err(DateTimeError::Year));
    /// # Ok::<(), DateTimeError>(())
    /// ```
    pub fn from_unix_seconds(unix_s: i64) -> Result<Self, DateTimeError> {
        let days =
            i32::try_from(unix_s.div_euclid(SECONDS_PER_DAY)).map_err(|_| DateTimeError::Year)?;
        // 0..86 400 s, so at most 86 399 000 ms: fits a u32.
        let sod =
            u32::try_from(unix_s.rem_euclid(SECONDS_PER_DAY)).map_err(|_| DateTimeError::Hour)?;
        let date = Date::from_days_since_unix_epoch(days)?;
        Self::from_date_ms(date, sod * 1000)
    }

    /// `self - earlier` in whole seconds (milliseconds ignored); negative if
    /// `earlier` is in fact later.
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// let gps = DateTime::new(2024, 2, 28, 23, 59, 30)?;
    /// let rtc = DateTime::new(2024, 2, 29, 0, 0, 5)?.with_millis(900)?;
    /// assert_eq!(rtc.seconds_since(&gps), 35);
    /// assert_eq!(gps.seconds_since(&rtc), -35);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub fn seconds_since(&self, earlier: &DateTime) -> i64 {
        self.unix_seconds() - earlier.unix_seconds()
    }

    /// `self - earlier` in milliseconds.
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// let a = DateTime::new(2024, 12, 31, 23, 59, 59)?.with_millis(500)?;
    /// let b = DateTime::new(2025, 1, 1, 0, 0, 0)?;
    /// assert_eq!(b.millis_since(&a), 500);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub fn millis_since(&self, earlier: &DateTime) -> i64 {
        self.unix_millis() - earlier.unix_millis()
    }

    /// Day of the week, 1 = Sunday .. 7 = Saturday (the numbering our DS3231
    /// and DS1302 drivers write into the chips' day-of-week registers).
    ///
    /// ```
    /// use drivers::time::DateTime;
    ///
    /// // Python's date.isoweekday(): 2024-03-10 is a Sunday (7), 2000-01-01
    /// // a Saturday (6), 2025-01-01 a Wednesday (3).
    /// assert_eq!(DateTime::new(2024, 3, 10, 0, 0, 0)?.weekday_from_sunday(), 1);
    /// assert_eq!(DateTime::new(2000, 1, 1, 0, 0, 0)?.weekday_from_sunday(), 7);
    /// assert_eq!(DateTime::new(2025, 1, 1, 0, 0, 0)?.weekday_from_sunday(), 4);
    /// # Ok::<(), drivers::time::DateTimeError>(())
    /// ```
    pub fn weekday_from_sunday(&self) -> u8 {
        // ISO 8601 numbers Monday 1 .. Sunday 7: Sunday becomes 1, Monday 2.
        self.date.iso_weekday() % 7 + 1
    }
}

/// ISO 8601, e.g. `2024-03-10T12:34:56Z`, with `.sss` only when the
/// milliseconds are not zero.
///
/// ```
/// use drivers::time::DateTime;
///
/// let t = DateTime::new(1, 1, 1, 0, 0, 0)?;
/// assert_eq!(t.to_string(), "0001-01-01T00:00:00Z");
/// assert_eq!(t.with_millis(5)?.to_string(), "0001-01-01T00:00:00.005Z");
/// # Ok::<(), drivers::time::DateTimeError>(())
/// ```
impl fmt::Display for DateTime {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}",
            self.year(),
            self.month(),
            self.day(),
            self.hour,
            self.minute,
            self.second
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

    /// Days in one 400-year Gregorian era.
    const DAYS_PER_ERA: i64 = 146_097;
    /// Days from 0000-03-01 to 1970-01-01.
    const UNIX_EPOCH_DAY_OFFSET: i64 = 719_468;

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
    fn date_and_ms_of_day_exchange() {
        // 2024-03-10T12:34:56.070Z: 45 296 070 ms after midnight; the day
        // count is Python's (date(2024, 3, 10) - date(1970, 1, 1)).days.
        let t = DateTime::new(2024, 3, 10, 12, 34, 56)
            .unwrap()
            .with_millis(70)
            .unwrap();
        assert_eq!(t.ms_of_day(), 45_296_070);
        assert_eq!(t.date(), Date::new(2024, 3, 10).unwrap());
        assert_eq!(t.date().days_since_unix_epoch(), 19_792);
        assert_eq!(DateTime::from_date_ms(t.date(), t.ms_of_day()), Ok(t));
        let last = DateTime::from_date_ms(t.date(), 86_399_999).unwrap();
        assert_eq!(
            (last.hour(), last.minute(), last.second(), last.millis()),
            (23, 59, 59, 999)
        );
        assert_eq!(
            DateTime::from_date_ms(t.date(), 86_400_000),
            Err(DateTimeError::Hour)
        );
        // Dates a Date holds but a DateTime does not.
        for y in [0, -1, -9999] {
            let d = Date::new(y, 1, 1).unwrap();
            assert_eq!(DateTime::from_date_ms(d, 0), Err(DateTimeError::Year));
        }
        assert_eq!(
            DateTime::new(2023, 2, 29, 0, 0, 0),
            Err(DateTimeError::from(DateError::Day))
        );
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
