//! Conversions between [`DateTime`] and chrono's [`NaiveDateTime`] and
//! [`chrono::DateTime`] (feature `chrono`).
//!
//! Both calendars are the proleptic Gregorian one with UTC days of 86 400 s,
//! but the ranges differ, and so the conversions into [`DateTime`] are
//! fallible (an error value, never a panic):
//!
//! | chrono value | [`DateTime`] |
//! |---|---|
//! | year outside [`MIN_YEAR`]..=[`MAX_YEAR`] (chrono reaches ±262 143) | [`DateTimeError::Year`] |
//! | a leap second (chrono keeps it as a nanosecond value of 10⁹ or more in second 59) | [`DateTimeError::Second`] (no leap seconds here) |
//! | nanoseconds below the millisecond | dropped: the millisecond is truncated toward the earlier instant |
//!
//! The other way, every [`DateTime`] is a chrono value (`From`).
//! `tests/chrono.rs` checks both directions against chrono's own calendar.

use chrono::{Datelike, NaiveDate, NaiveDateTime, NaiveTime, TimeZone, Timelike, Utc};

use super::{DateTime, DateTimeError, MAX_YEAR, MIN_YEAR};

/// Nanoseconds per millisecond.
const NANOS_PER_MILLI: u32 = 1_000_000;
/// chrono's nanosecond field reaches this and above only in a leap second.
const NANOS_PER_SECOND: u32 = 1_000_000_000;

/// Every [`DateTime`] is a chrono date-time: lossless.
///
/// ```
/// use chrono::NaiveDate;
/// use drivers::time::DateTime;
///
/// let t = DateTime::new(2024, 2, 29, 23, 59, 59)?.with_millis(999)?;
/// let expected = NaiveDate::from_ymd_opt(2024, 2, 29)
///     .unwrap()
///     .and_hms_milli_opt(23, 59, 59, 999)
///     .unwrap();
/// assert_eq!(chrono::NaiveDateTime::from(t), expected);
/// // The same instant for chrono's clock arithmetic: 1 709 251 199 999 ms
/// // after the Unix epoch (Python:
/// // datetime(2024, 2, 29, 23, 59, 59, 999000, tzinfo=timezone.utc).timestamp()).
/// assert_eq!(expected.and_utc().timestamp_millis(), 1_709_251_199_999);
/// assert_eq!(t.unix_millis(), 1_709_251_199_999);
/// # Ok::<(), drivers::time::DateTimeError>(())
/// ```
impl From<DateTime> for NaiveDateTime {
    fn from(t: DateTime) -> NaiveDateTime {
        // Years 1..=9999 lie far inside chrono's range and every field of a
        // DateTime is valid, so both `_opt` constructors give a value (every
        // extreme is checked in tests/chrono.rs); the fallback is never taken
        // and only keeps a panic site out of the conversion.
        let date = NaiveDate::from_ymd_opt(
            i32::from(t.year()),
            u32::from(t.month()),
            u32::from(t.day()),
        );
        let time = NaiveTime::from_hms_milli_opt(
            u32::from(t.hour()),
            u32::from(t.minute()),
            u32::from(t.second()),
            u32::from(t.millis()),
        );
        match (date, time) {
            (Some(d), Some(tm)) => d.and_time(tm),
            _ => NaiveDateTime::MIN,
        }
    }
}

/// Every [`DateTime`] is a chrono UTC date-time: lossless.
///
/// ```
/// use chrono::{TimeZone, Utc};
/// use drivers::time::DateTime;
///
/// // 1234567890 s after the epoch is the well-known 2009-02-13T23:31:30Z.
/// let t = DateTime::new(2009, 2, 13, 23, 31, 30)?;
/// let utc = chrono::DateTime::<Utc>::from(t);
/// assert_eq!(utc, Utc.timestamp_opt(1_234_567_890, 0).unwrap());
/// # Ok::<(), drivers::time::DateTimeError>(())
/// ```
impl From<DateTime> for chrono::DateTime<Utc> {
    fn from(t: DateTime) -> chrono::DateTime<Utc> {
        NaiveDateTime::from(t).and_utc()
    }
}

/// A chrono date-time, taken as UTC: [`DateTimeError::Year`] outside the
/// years [`MIN_YEAR`]..=[`MAX_YEAR`], [`DateTimeError::Second`] for a leap
/// second; nanoseconds are truncated to the millisecond.
///
/// ```
/// use chrono::NaiveDate;
/// use drivers::time::{DateTime, DateTimeError};
///
/// let day = NaiveDate::from_ymd_opt(2000, 2, 29).unwrap();
/// // 12:00:00.123456789 keeps its whole milliseconds.
/// let t = DateTime::try_from(day.and_hms_nano_opt(12, 0, 0, 123_456_789).unwrap())?;
/// assert_eq!(t, DateTime::new(2000, 2, 29, 12, 0, 0)?.with_millis(123)?);
///
/// // chrono's leap second 2016-12-31T23:59:60.5Z (second 59, 1.5 × 10⁹ ns).
/// let leap = NaiveDate::from_ymd_opt(2016, 12, 31)
///     .unwrap()
///     .and_hms_nano_opt(23, 59, 59, 1_500_000_000)
///     .unwrap();
/// assert_eq!(DateTime::try_from(leap), Err(DateTimeError::Second));
///
/// // Year 10 000 is a chrono date but not a DateTime.
/// let far = NaiveDate::from_ymd_opt(10_000, 1, 1).unwrap().and_hms_opt(0, 0, 0).unwrap();
/// assert_eq!(DateTime::try_from(far), Err(DateTimeError::Year));
/// # Ok::<(), DateTimeError>(())
/// ```
impl TryFrom<NaiveDateTime> for DateTime {
    type Error = DateTimeError;

    fn try_from(t: NaiveDateTime) -> Result<DateTime, DateTimeError> {
        let year = u16::try_from(t.year())
            .ok()
            .filter(|y| (MIN_YEAR..=MAX_YEAR).contains(y))
            .ok_or(DateTimeError::Year)?;
        let nanos = t.nanosecond();
        if nanos >= NANOS_PER_SECOND {
            return Err(DateTimeError::Second);
        }
        // chrono's fields are in range (month 1..=12, day 1..=31, hour
        // 0..=23, minute and second 0..=59), so they fit a u8; the errors
        // below cannot occur but keep the conversion free of casts.
        let month = u8::try_from(t.month()).map_err(|_| DateTimeError::Month)?;
        let day = u8::try_from(t.day()).map_err(|_| DateTimeError::Day)?;
        let hour = u8::try_from(t.hour()).map_err(|_| DateTimeError::Hour)?;
        let minute = u8::try_from(t.minute()).map_err(|_| DateTimeError::Minute)?;
        let second = u8::try_from(t.second()).map_err(|_| DateTimeError::Second)?;
        let millis = u16::try_from(nanos / NANOS_PER_MILLI).map_err(|_| DateTimeError::Millis)?;
        DateTime::new(year, month, day, hour, minute, second)?.with_millis(millis)
    }
}

/// A chrono date-time in any time zone, taken at its UTC instant; the same
/// rules as from [`NaiveDateTime`].
///
/// ```
/// use chrono::{FixedOffset, TimeZone};
/// use drivers::time::{DateTime, DateTimeError};
///
/// // 2025-01-01T01:30:00+02:00 is 2024-12-31T23:30:00Z: the UTC date is
/// // the day before, in the year before.
/// let east = FixedOffset::east_opt(2 * 3600).unwrap();
/// let local = east.with_ymd_and_hms(2025, 1, 1, 1, 30, 0).unwrap();
/// assert_eq!(DateTime::try_from(local)?, DateTime::new(2024, 12, 31, 23, 30, 0)?);
///
/// let utc = chrono::Utc.with_ymd_and_hms(1999, 12, 31, 23, 59, 59).unwrap();
/// assert_eq!(DateTime::try_from(utc)?.unix_seconds(), 946_684_799);
/// # Ok::<(), DateTimeError>(())
/// ```
impl<Tz: TimeZone> TryFrom<chrono::DateTime<Tz>> for DateTime {
    type Error = DateTimeError;

    fn try_from(t: chrono::DateTime<Tz>) -> Result<DateTime, DateTimeError> {
        DateTime::try_from(t.naive_utc())
    }
}
