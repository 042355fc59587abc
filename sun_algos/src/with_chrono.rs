//! Conversions between chrono's date-times and [`UtcTime`] (feature
//! `chrono`).
//!
//! Into [`UtcTime`], fallible: [`Error::InvalidDate`] for an instant outside
//! the years [`MIN_YEAR`](crate::time::MIN_YEAR)`..=`[`MAX_YEAR`](crate::time::MAX_YEAR)
//! (chrono spans about ±262 000 years), never a panic.
//! - `TryFrom<chrono::NaiveDateTime>`: the date-time read as UTC.
//! - `TryFrom<chrono::DateTime<Tz>>` for any time zone: its UTC instant.
//!
//! Precision and leap seconds, as chrono's own arithmetic counts them
//! (`timestamp_millis`, `signed_duration_since`; checked on many instants
//! in `tests/chrono.rs`):
//! - nanoseconds below the millisecond are dropped (rounded toward the past,
//!   also before 1970);
//! - a leap second (chrono's nanosecond ≥ 10⁹, its way of writing 23:59:60)
//!   is the first second of the next minute: 2016-12-31T23:59:60.500Z is
//!   2017-01-01T00:00:00.500. [`UtcTime`] is read as UT1, which has no leap
//!   seconds and stays within 0.9 s of UTC, so the inserted second and the
//!   one after it give the same [`UtcTime`].
//!
//! Out of [`UtcTime`], lossless (every [`UtcTime`] is a chrono date-time):
//! `From<UtcTime>` for `chrono::NaiveDateTime` and `chrono::DateTime<Utc>`.

use chrono::{DateTime, NaiveDate, NaiveDateTime, NaiveTime, TimeZone, Timelike, Utc};

use crate::error::Error;
use crate::time::{Date, UtcTime};

/// A chrono date-time read as UTC.
///
/// ```
/// use chrono::NaiveDate;
/// use sun_algos::{Error, UtcTime};
///
/// let naive = NaiveDate::from_ymd_opt(2003, 10, 17)
///     .unwrap()
///     .and_hms_milli_opt(19, 30, 30, 250)
///     .unwrap();
/// let t = UtcTime::try_from(naive)?;
/// // NREL SPA report, worked example: 2003-10-17 19:30:30 UT is JD
/// // 2452930.312847 (shared/reference/nrel_spa_test_vector.json); 250 ms
/// // more are 2.9e-6 day.
/// assert!((t.julian_day_f64() - (2_452_930.312_847 + 0.25 / 86_400.0)).abs() < 1e-6);
/// assert_eq!(t.hms_milli(), (19, 30, 30, 250));
///
/// // A leap second (chrono writes 23:59:60 as nanoseconds ≥ 10⁹) counts as
/// // the next day's first second, as chrono's own timestamp arithmetic does.
/// let leap = NaiveDate::from_ymd_opt(2016, 12, 31)
///     .unwrap()
///     .and_hms_milli_opt(23, 59, 59, 1_500)
///     .unwrap();
/// assert_eq!(UtcTime::try_from(leap)?, "2017-01-01T00:00:00.500Z".parse()?);
///
/// // chrono reaches far beyond the years -4000..=8000.
/// let far = NaiveDate::from_ymd_opt(9000, 1, 1).unwrap().and_hms_opt(0, 0, 0).unwrap();
/// assert_eq!(UtcTime::try_from(far), Err(Error::InvalidDate));
/// # Ok::<(), Error>(())
/// ```
impl TryFrom<NaiveDateTime> for UtcTime {
    type Error = Error;

    fn try_from(date_time: NaiveDateTime) -> Result<UtcTime, Error> {
        let date = Date::try_from(date_time.date()).map_err(|_| Error::InvalidDate)?;
        let midnight = UtcTime::from_date_ms(date, 0)?;
        let time = date_time.time();
        // Seconds 0..86 400 and nanoseconds 0..2·10⁹ (a leap second past
        // 10⁹): at most 86 400 999 ms, carried into the next day by
        // `add_millis`, which errors past 8000-12-31.
        let ms = i64::from(time.num_seconds_from_midnight()) * 1000
            + i64::from(time.nanosecond() / 1_000_000);
        midnight.add_millis(ms)
    }
}

/// A chrono date-time of any time zone, at its UTC instant.
///
/// ```
/// use chrono::{DateTime, FixedOffset, Utc};
/// use sun_algos::{Error, UtcTime};
///
/// // The NREL SPA report's worked example is 12:30:30 local time at
/// // UTC−7, 19:30:30 UTC (shared/reference/nrel_spa_test_vector.json).
/// let local: DateTime<FixedOffset> = DateTime::parse_from_rfc3339("2003-10-17T12:30:30-07:00").unwrap();
/// let t = UtcTime::try_from(local)?;
/// assert_eq!(t, UtcTime::from_ymd_hms(2003, 10, 17, 19, 30, 30)?);
///
/// // Unix time 946 684 800 s is 2000-01-01T00:00:00Z (POSIX), day 0 here.
/// let utc = DateTime::<Utc>::from_timestamp(946_684_800, 0).unwrap();
/// assert_eq!(UtcTime::try_from(utc)?, UtcTime::MIDNIGHT_2000);
/// # Ok::<(), Error>(())
/// ```
impl<Tz: TimeZone> TryFrom<DateTime<Tz>> for UtcTime {
    type Error = Error;

    fn try_from(date_time: DateTime<Tz>) -> Result<UtcTime, Error> {
        UtcTime::try_from(date_time.naive_utc())
    }
}

/// Every [`UtcTime`] as a chrono date-time (UTC, to the millisecond).
///
/// ```
/// use chrono::{Datelike, NaiveDateTime, Timelike};
/// use sun_algos::{Error, UtcTime};
///
/// let t = UtcTime::from_ymd_hms_milli(2024, 2, 29, 23, 59, 59, 999)?;
/// let naive = NaiveDateTime::from(t);
/// assert_eq!((naive.year(), naive.month(), naive.day()), (2024, 2, 29));
/// assert_eq!(naive.nanosecond(), 999_000_000);
/// // chrono's Unix milliseconds: Python's
/// // `datetime(2024, 2, 29, 23, 59, 59, 999000, tzinfo=timezone.utc).timestamp()`
/// // is 1709251199.999.
/// assert_eq!(naive.and_utc().timestamp_millis(), 1_709_251_199_999);
/// assert_eq!(UtcTime::try_from(naive)?, t);
/// # Ok::<(), Error>(())
/// ```
impl From<UtcTime> for NaiveDateTime {
    fn from(time: UtcTime) -> NaiveDateTime {
        let ms = time.ms_of_day();
        // ms_of_day < 86 400 000 (checked by every constructor of UtcTime),
        // so the time of day always exists; years −4000…8000 lie inside
        // chrono's range. Neither fallback is ever taken (tests/chrono.rs);
        // they only keep a panic site out of the conversion.
        let time_of_day =
            NaiveTime::from_num_seconds_from_midnight_opt(ms / 1000, (ms % 1000) * 1_000_000)
                .unwrap_or(NaiveTime::MIN);
        NaiveDate::from(time.date()).and_time(time_of_day)
    }
}

/// Every [`UtcTime`] as a chrono UTC date-time.
///
/// ```
/// use chrono::{DateTime, Utc};
/// use sun_algos::{Error, UtcTime};
///
/// let t: UtcTime = "2000-01-01T12:00:00Z".parse()?;
/// let dt = DateTime::<Utc>::from(t);
/// // 2000-01-01T12:00:00Z is Unix time 946 728 000 s (POSIX: 946 684 800 + 43 200).
/// assert_eq!(dt.timestamp(), 946_728_000);
/// # Ok::<(), Error>(())
/// ```
impl From<UtcTime> for DateTime<Utc> {
    fn from(time: UtcTime) -> DateTime<Utc> {
        NaiveDateTime::from(time).and_utc()
    }
}
