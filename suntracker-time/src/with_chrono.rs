//! Conversions between [`Date`] and chrono's [`NaiveDate`] (feature
//! `chrono`).
//!
//! chrono's proleptic Gregorian calendar numbers years as ISO 8601 does (year
//! 0 is 1 BC), as this crate does, and spans about ±262 000 years: every
//! [`Date`] is a chrono date (`From`), while a chrono date outside
//! [`MIN_YEAR`](crate::MIN_YEAR)`..=`[`MAX_YEAR`](crate::MAX_YEAR) is
//! [`DateError::Year`] (`TryFrom`). `tests/chrono.rs` checks both directions
//! on every day of the range and against chrono's own day arithmetic.

use chrono::{Datelike, NaiveDate};

use crate::{Date, DateError};

/// Every [`Date`] is a chrono date: lossless.
///
/// ```
/// use chrono::NaiveDate;
/// use suntracker_time::Date;
///
/// let d = Date::new(2024, 2, 29)?;
/// assert_eq!(NaiveDate::from(d), NaiveDate::from_ymd_opt(2024, 2, 29).unwrap());
/// // chrono's own day count agrees with this crate's (19 782 days after
/// // 1970-01-01, Python's `(date(2024, 2, 29) - date(1970, 1, 1)).days`).
/// let days = NaiveDate::from(d).signed_duration_since(NaiveDate::from(Date::UNIX_EPOCH));
/// assert_eq!(days.num_days(), 19_782);
/// assert_eq!(NaiveDate::from(Date::MIN), NaiveDate::from_ymd_opt(-9999, 1, 1).unwrap());
/// # Ok::<(), suntracker_time::DateError>(())
/// ```
impl From<Date> for NaiveDate {
    fn from(date: Date) -> NaiveDate {
        // Years −9999..=9999 lie far inside chrono's ±262 143, so
        // `from_ymd_opt` always gives a date for a valid `Date` (every one of
        // them is checked in tests/chrono.rs); the fallback is never taken
        // and only keeps a panic site out of the conversion.
        NaiveDate::from_ymd_opt(date.year(), u32::from(date.month()), u32::from(date.day()))
            .unwrap_or(NaiveDate::MIN)
    }
}

/// A chrono date as a [`Date`]: [`DateError::Year`] for a year outside
/// [`MIN_YEAR`](crate::MIN_YEAR)`..=`[`MAX_YEAR`](crate::MAX_YEAR) (chrono's
/// month and day are always valid).
///
/// ```
/// use chrono::NaiveDate;
/// use suntracker_time::{Date, DateError};
///
/// let nd = NaiveDate::from_ymd_opt(1900, 2, 28).unwrap();
/// let d = Date::try_from(nd)?;
/// // Python: (date(1900, 2, 28) - date(1970, 1, 1)).days == -25509.
/// assert_eq!(d.days_since_unix_epoch(), -25_509);
/// // chrono reaches past year 9999; this crate does not.
/// let far = NaiveDate::from_ymd_opt(10_000, 1, 1).unwrap();
/// assert_eq!(Date::try_from(far), Err(DateError::Year));
/// # Ok::<(), DateError>(())
/// ```
impl TryFrom<NaiveDate> for Date {
    type Error = DateError;

    fn try_from(date: NaiveDate) -> Result<Date, DateError> {
        // chrono's month (1..=12) and day (1..=31) always fit a u8.
        let month = u8::try_from(date.month()).map_err(|_| DateError::Month)?;
        let day = u8::try_from(date.day()).map_err(|_| DateError::Day)?;
        Date::new(date.year(), month, day)
    }
}
