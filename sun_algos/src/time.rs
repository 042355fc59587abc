//! Time: whole days and the time of day kept apart.
//!
//! A Julian Day near 2.46 × 10⁶ formed in `f32` keeps only about 0.1 day of
//! resolution. [`UtcTime`] therefore stores an integer day count and an
//! integer millisecond of the day; each algorithm combines them in the way
//! that keeps its own precision (see the algorithm modules).
//!
//! The instant is read as UT1 (UTC without leap-second bookkeeping; the
//! difference is below 0.9 s, 0.004° of hour angle).
//!
//! The calendar itself (validation, leap years, the day count of a date and
//! back) is the `suntracker-time` crate's: [`Date`], [`is_leap_year`] and
//! [`days_in_month`] are re-exported from it, and [`UtcTime::date`] /
//! [`UtcTime::from_date_ms`] exchange a [`Date`] with any other user of that
//! crate (such as the clock drivers of `suntracker-drivers`) without going
//! through calendar fields again.
//!
//! Counts of seconds and milliseconds are split into days with
//! [`div_rem_euclid_i64`] (also re-exported from that crate): 32-bit steps
//! only, so an 8-bit AVR image links no 64-bit division routine.

use crate::error::Error;
use crate::float::Float;

pub use suntracker_time::{
    days_in_month, div_rem_euclid_i64, div_rem_u64, div_rem_u64_u16, is_leap_year, Date, DateError,
};

/// Milliseconds in a day.
///
/// ```
/// use sun_algos::time::MS_PER_DAY;
/// use sun_algos::UtcTime;
///
/// assert_eq!(MS_PER_DAY, 24 * 60 * 60 * 1000);
/// assert!(UtcTime::from_days_ms(0, MS_PER_DAY).is_err());
/// ```
pub const MS_PER_DAY: u32 = 86_400_000;
/// Julian Day of 2000-01-01 00:00 UT is `JD_2000_MIDNIGHT_INT + 0.5`.
///
/// ```
/// use sun_algos::time::JD_2000_MIDNIGHT_INT;
///
/// // Meeus, Astronomical Algorithms, ch. 7: 2000-01-01 12:00 is JD 2451545.0,
/// // so its midnight is JD 2451544.5.
/// assert_eq!(f64::from(JD_2000_MIDNIGHT_INT) + 0.5, 2_451_545.0 - 0.5);
/// ```
pub const JD_2000_MIDNIGHT_INT: i32 = 2_451_544;
/// First year a [`UtcTime`] accepts.
///
/// ```
/// use sun_algos::time::MIN_YEAR;
/// use sun_algos::{Error, UtcTime};
///
/// assert!(UtcTime::from_ymd_hms(MIN_YEAR, 1, 1, 0, 0, 0).is_ok());
/// assert_eq!(UtcTime::from_ymd_hms(MIN_YEAR - 1, 12, 31, 0, 0, 0), Err(Error::InvalidDate));
/// ```
pub const MIN_YEAR: i32 = -4000;
/// Last year a [`UtcTime`] accepts.
///
/// ```
/// use sun_algos::time::MAX_YEAR;
/// use sun_algos::{Error, UtcTime};
///
/// let last = UtcTime::from_ymd_hms(MAX_YEAR, 12, 31, 23, 59, 59)?;
/// assert_eq!(last.add_seconds(1), Err(Error::InvalidDate));
/// # Ok::<(), sun_algos::Error>(())
/// ```
pub const MAX_YEAR: i32 = 8000;

/// A UTC (taken as UT1) instant on the proleptic Gregorian calendar.
///
/// ```
/// use sun_algos::UtcTime;
///
/// // ISO 8601 in and out; the `Z` may be left out, a fraction of a second is
/// // read to the millisecond.
/// let t: UtcTime = "2031-04-05T06:07:08.25Z".parse()?;
/// assert_eq!(t.to_string(), "2031-04-05T06:07:08.250Z");
/// assert_eq!("2031-04-05 06:07:08".parse::<UtcTime>()?.to_string(), "2031-04-05T06:07:08Z");
/// assert!("2031-02-29T00:00:00Z".parse::<UtcTime>().is_err()); // not a leap year
/// // Ordered in time; eight bytes (a day count and the millisecond of the day).
/// assert!(t < t.add_millis(1)?);
/// assert_eq!(core::mem::size_of::<UtcTime>(), 8);
/// # Ok::<(), sun_algos::Error>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub struct UtcTime {
    /// Days since 2000-01-01 (that day is 0).
    days: i32,
    /// Milliseconds since midnight, `0..MS_PER_DAY`.
    ms_of_day: u32,
}

impl UtcTime {
    /// True when this instant is earlier than `other`: by day, then by
    /// millisecond of the day (the order a derived `Ord` of the fields
    /// gives). The one comparison behind `<`, `<=`, `>`, `>=` and `cmp`;
    /// out of line on the AVR, where a derived comparison of the two
    /// fields was inlined at every comparison of two instants (the
    /// scheduler, controller and time keeper make many).
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn is_before(&self, other: &Self) -> bool {
        self.days < other.days || (self.days == other.days && self.ms_of_day < other.ms_of_day)
    }
}

impl PartialEq for UtcTime {
    // Out of line on the AVR, as `is_before`: one copy of the comparison
    // of eight bytes.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn eq(&self, other: &Self) -> bool {
        self.days == other.days && self.ms_of_day == other.ms_of_day
    }
}

impl Eq for UtcTime {}

/// Hashes the fields in order, as a derived `Hash` would (equal instants
/// have equal fields).
impl core::hash::Hash for UtcTime {
    fn hash<H: core::hash::Hasher>(&self, state: &mut H) {
        self.days.hash(state);
        self.ms_of_day.hash(state);
    }
}

impl Ord for UtcTime {
    fn cmp(&self, other: &Self) -> core::cmp::Ordering {
        if self.is_before(other) {
            core::cmp::Ordering::Less
        } else if other.is_before(self) {
            core::cmp::Ordering::Greater
        } else {
            core::cmp::Ordering::Equal
        }
    }
}

impl PartialOrd for UtcTime {
    fn partial_cmp(&self, other: &Self) -> Option<core::cmp::Ordering> {
        Some(self.cmp(other))
    }
    #[inline]
    fn lt(&self, other: &Self) -> bool {
        self.is_before(other)
    }
    #[inline]
    fn le(&self, other: &Self) -> bool {
        !other.is_before(self)
    }
    #[inline]
    fn gt(&self, other: &Self) -> bool {
        other.is_before(self)
    }
    #[inline]
    fn ge(&self, other: &Self) -> bool {
        !self.is_before(other)
    }
}

/// Days from 1970-01-01 to 2000-01-01 (946 684 800 s of POSIX time / 86 400).
const UNIX_TO_2000_DAYS: i32 = 10_957;
/// Seconds in a day (no leap seconds: the time scale is read as UT1).
const SECONDS_PER_DAY: u32 = 86_400;

/// Days since 2000-01-01 of the first day of [`MIN_YEAR`] and the last day
/// of [`MAX_YEAR`] (both years lie inside a [`Date`]'s −9999…9999; a
/// compile-time check, no code in the image).
const DAYS_RANGE: (i32, i32) = match (Date::new(MIN_YEAR, 1, 1), Date::new(MAX_YEAR, 12, 31)) {
    (Ok(first), Ok(last)) => (
        first.days_since_unix_epoch() - UNIX_TO_2000_DAYS,
        last.days_since_unix_epoch() - UNIX_TO_2000_DAYS,
    ),
    _ => panic!("MIN_YEAR..=MAX_YEAR must lie inside the years of a Date"),
};

impl UtcTime {
    /// An instant from a calendar date and time of day.
    ///
    /// ```
    /// use sun_algos::{Error, UtcTime};
    ///
    /// // Meeus, Astronomical Algorithms, ch. 7: 2000-01-01 12:00 is JD 2451545.0;
    /// // example 7.a: 1957-10-04 19:26:24 (October 4.81) is JD 2436116.31.
    /// assert_eq!(UtcTime::from_ymd_hms(2000, 1, 1, 12, 0, 0)?.julian_day_f64(), 2_451_545.0);
    /// let sputnik = UtcTime::from_ymd_hms(1957, 10, 4, 19, 26, 24)?;
    /// assert!((sputnik.julian_day_f64() - 2_436_116.31).abs() < 1e-6);
    /// assert_eq!(UtcTime::from_ymd_hms(2024, 1, 1, 24, 0, 0), Err(Error::InvalidTime));
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn from_ymd_hms(
        year: i32,
        month: u8,
        day: u8,
        hour: u8,
        minute: u8,
        second: u8,
    ) -> Result<Self, Error> {
        Self::from_ymd_hms_milli(year, month, day, hour, minute, second, 0)
    }

    /// An instant from a calendar date and time of day with milliseconds.
    ///
    /// ```
    /// use sun_algos::{Error, UtcTime};
    ///
    /// // NREL SPA report, worked example: 2003-10-17 19:30:30 UT is JD
    /// // 2452930.312847 (shared/reference/nrel_spa_test_vector.json); 500 ms more
    /// // are 5.787e-6 day.
    /// let t = UtcTime::from_ymd_hms_milli(2003, 10, 17, 19, 30, 30, 500)?;
    /// assert!((t.julian_day_f64() - 2_452_930.312_847 - 0.5 / 86_400.0).abs() < 1e-6);
    /// assert_eq!(UtcTime::from_ymd_hms_milli(2003, 10, 17, 19, 30, 30, 1000), Err(Error::InvalidTime));
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn from_ymd_hms_milli(
        year: i32,
        month: u8,
        day: u8,
        hour: u8,
        minute: u8,
        second: u8,
        milli: u16,
    ) -> Result<Self, Error> {
        if !(MIN_YEAR..=MAX_YEAR).contains(&year) {
            return Err(Error::InvalidDate);
        }
        let date = Date::new(year, month, day).map_err(|_| Error::InvalidDate)?;
        if hour > 23 || minute > 59 || second > 59 || milli > 999 {
            return Err(Error::InvalidTime);
        }
        let ms = ((u32::from(hour) * 60 + u32::from(minute)) * 60 + u32::from(second)) * 1000
            + u32::from(milli);
        Ok(UtcTime {
            days: date.days_since_unix_epoch() - UNIX_TO_2000_DAYS,
            ms_of_day: ms,
        })
    }

    /// An instant from a calendar [`Date`] and the milliseconds since its
    /// midnight: [`Error::InvalidDate`] for a year outside
    /// [`MIN_YEAR`]`..=`[`MAX_YEAR`], [`Error::InvalidTime`] for
    /// `ms_of_day ≥` [`MS_PER_DAY`]. A `const fn`, so that a fixed instant
    /// can be a compile-time constant.
    ///
    /// ```
    /// use sun_algos::time::{Date, MS_PER_DAY};
    /// use sun_algos::{Error, UtcTime};
    ///
    /// // A compile-time constant instant from a calendar Date.
    /// const EQUINOX: Result<UtcTime, Error> = match Date::new(2026, 3, 20) {
    ///     Ok(d) => UtcTime::from_date_ms(d, 14 * 3_600_000 + 46 * 60_000),
    ///     Err(_) => Err(Error::InvalidDate),
    /// };
    /// assert_eq!(EQUINOX?.to_string(), "2026-03-20T14:46:00Z");
    /// let d = Date::new(2000, 1, 1).unwrap();
    /// assert_eq!(UtcTime::from_date_ms(d, 0)?, UtcTime::MIDNIGHT_2000);
    /// assert_eq!(UtcTime::from_date_ms(d, MS_PER_DAY), Err(Error::InvalidTime));
    /// // A Date of year 9000 exists, but lies outside UtcTime's years.
    /// let far = Date::new(9000, 1, 1).unwrap();
    /// assert_eq!(UtcTime::from_date_ms(far, 0), Err(Error::InvalidDate));
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub const fn from_date_ms(date: Date, ms_of_day: u32) -> Result<Self, Error> {
        let year = date.year();
        if year < MIN_YEAR || year > MAX_YEAR {
            return Err(Error::InvalidDate);
        }
        if ms_of_day >= MS_PER_DAY {
            return Err(Error::InvalidTime);
        }
        Ok(UtcTime {
            days: date.days_since_unix_epoch() - UNIX_TO_2000_DAYS,
            ms_of_day,
        })
    }

    /// 2000-01-01T00:00:00Z, the origin of the day count.
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // POSIX time of 2000-01-01T00:00:00Z: 946 684 800 s.
    /// assert_eq!(UtcTime::MIDNIGHT_2000.unix_seconds(), 946_684_800);
    /// assert_eq!(UtcTime::MIDNIGHT_2000.to_string(), "2000-01-01T00:00:00Z");
    /// ```
    pub const MIDNIGHT_2000: UtcTime = UtcTime {
        days: 0,
        ms_of_day: 0,
    };

    /// An instant from days since 2000-01-01 and milliseconds of that day.
    ///
    /// ```
    /// use sun_algos::{Error, UtcTime};
    ///
    /// // Python: (date(2026, 6, 21) - date(2000, 1, 1)).days == 9668.
    /// let t = UtcTime::from_days_ms(9_668, 43_200_000)?;
    /// assert_eq!(t.to_string(), "2026-06-21T12:00:00Z");
    /// assert_eq!(UtcTime::from_days_ms(0, 86_400_000), Err(Error::InvalidTime));
    /// assert_eq!(UtcTime::from_days_ms(i32::MAX, 0), Err(Error::InvalidDate));
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn from_days_ms(days_since_2000: i32, ms_of_day: u32) -> Result<Self, Error> {
        if ms_of_day >= MS_PER_DAY {
            return Err(Error::InvalidTime);
        }
        if !(DAYS_RANGE.0..=DAYS_RANGE.1).contains(&days_since_2000) {
            return Err(Error::InvalidDate);
        }
        Ok(UtcTime {
            days: days_since_2000,
            ms_of_day,
        })
    }

    /// An instant from Unix seconds (seconds since 1970-01-01T00:00:00Z).
    ///
    /// Any `i64` is accepted: outside the calendar range the result is
    /// [`Error::InvalidDate`], never an arithmetic overflow.
    ///
    /// ```
    /// use sun_algos::{Error, UtcTime};
    ///
    /// // Python: datetime.fromtimestamp(1_700_000_000, timezone.utc) is
    /// // 2023-11-14 22:13:20+00:00.
    /// assert_eq!(UtcTime::from_unix_seconds(1_700_000_000)?.to_string(), "2023-11-14T22:13:20Z");
    /// // Before 1970 as well; any i64 is an instant or an error.
    /// assert_eq!(UtcTime::from_unix_seconds(-1)?.to_string(), "1969-12-31T23:59:59Z");
    /// assert_eq!(UtcTime::from_unix_seconds(i64::MAX), Err(Error::InvalidDate));
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn from_unix_seconds(secs: i64) -> Result<Self, Error> {
        let (days, second_of_day) =
            div_rem_euclid_i64(secs, SECONDS_PER_DAY).ok_or(Error::InvalidDate)?;
        // The subtraction can only overflow in theory, and is checked anyway.
        let days = days
            .checked_sub(i64::from(UNIX_TO_2000_DAYS))
            .ok_or(Error::InvalidDate)?;
        let days = i32::try_from(days).map_err(|_| Error::InvalidDate)?;
        // second_of_day < 86 400, so at most 86 399 000 ms.
        let ms_of_day = second_of_day.checked_mul(1000).ok_or(Error::InvalidTime)?;
        Self::from_days_ms(days, ms_of_day)
    }

    /// Seconds since 1970-01-01T00:00:00Z, milliseconds dropped.
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // Python: datetime(2026, 6, 21, 12, tzinfo=timezone.utc).timestamp() == 1782043200.
    /// let t: UtcTime = "2026-06-21T12:00:00.999Z".parse()?;
    /// assert_eq!(t.unix_seconds(), 1_782_043_200);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn unix_seconds(&self) -> i64 {
        // `days` is within the ±4.4 million days of MIN_YEAR..=MAX_YEAR (checked
        // by every constructor), so this is far from the i64 limits.
        (i64::from(self.days) + i64::from(UNIX_TO_2000_DAYS)) * i64::from(SECONDS_PER_DAY)
            + i64::from(self.ms_of_day / 1000)
    }

    /// This instant moved by `secs` seconds (either sign).
    ///
    /// Any `i64` is accepted: a result outside the calendar range is
    /// [`Error::InvalidDate`], never an arithmetic overflow (the seconds are
    /// split into whole days and a remainder before anything is multiplied).
    ///
    /// ```
    /// use sun_algos::{Error, UtcTime};
    ///
    /// // Python: datetime(2024, 2, 28, 23) + timedelta(seconds=7200) is 2024-02-29 01:00.
    /// let t: UtcTime = "2024-02-28T23:00:00Z".parse()?;
    /// assert_eq!(t.add_seconds(7_200)?.to_string(), "2024-02-29T01:00:00Z");
    /// assert_eq!(t.add_seconds(i64::MIN), Err(Error::InvalidDate));
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn add_seconds(&self, secs: i64) -> Result<Self, Error> {
        let (days, rest_s) = div_rem_euclid_i64(secs, SECONDS_PER_DAY).ok_or(Error::InvalidDate)?;
        // rest_s < 86 400, so at most 86 399 000 ms: fits a u32.
        let rest_ms = rest_s.checked_mul(1000).ok_or(Error::InvalidTime)?;
        let days = i32::try_from(days).map_err(|_| Error::InvalidDate)?;
        self.add_days_ms(days, rest_ms)
    }

    /// This instant moved by `ms` milliseconds (either sign); like
    /// [`UtcTime::add_seconds`], any `i64` gives a time or
    /// [`Error::InvalidDate`], never an overflow.
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // Python: datetime(2025, 1, 1, 0, 0, 0, 500000) - timedelta(milliseconds=1000)
    /// // is 2024-12-31 23:59:59.500.
    /// let t: UtcTime = "2025-01-01T00:00:00.500Z".parse()?;
    /// assert_eq!(t.add_millis(-1_000)?.to_string(), "2024-12-31T23:59:59.500Z");
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn add_millis(&self, ms: i64) -> Result<Self, Error> {
        let (days, rest_ms) = div_rem_euclid_i64(ms, MS_PER_DAY).ok_or(Error::InvalidDate)?;
        let days = i32::try_from(days).map_err(|_| Error::InvalidDate)?;
        self.add_days_ms(days, rest_ms)
    }

    /// This instant `ms` milliseconds later (up to 49.7 days), in 32-bit
    /// arithmetic: [`UtcTime::add_millis`] for a forward age or interval
    /// of the monotonic clock, without the 64-bit division an 8-bit MCU
    /// computes in software. A result past the calendar range is
    /// [`Error::InvalidDate`].
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // Python: datetime(2024, 12, 31, 23, 59, 59, 500000) + timedelta(milliseconds=86_400_700)
    /// // is 2025-01-02 00:00:00.200.
    /// let t: UtcTime = "2024-12-31T23:59:59.500Z".parse()?;
    /// assert_eq!(t.add_millis_u32(86_400_700)?.to_string(), "2025-01-02T00:00:00.200Z");
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn add_millis_u32(&self, ms: u32) -> Result<Self, Error> {
        // At most 49 whole days: fits an i32.
        self.add_days_ms((ms / MS_PER_DAY) as i32, ms % MS_PER_DAY)
    }

    /// This instant moved by `secs` seconds (either sign, up to ±68 years),
    /// in 32-bit arithmetic: [`UtcTime::add_seconds`] for the spans a
    /// day's search or schedule uses, without the 64-bit division an 8-bit
    /// MCU computes in software. A result outside the calendar range is
    /// [`Error::InvalidDate`].
    ///
    /// ```
    /// use sun_algos::{Error, UtcTime};
    ///
    /// // Python: datetime(2024, 2, 28, 23) + timedelta(seconds=7200) is
    /// // 2024-02-29 01:00, and - timedelta(seconds=86401) is 2024-02-27 22:59:59.
    /// let t: UtcTime = "2024-02-28T23:00:00Z".parse()?;
    /// assert_eq!(t.add_seconds_i32(7_200)?.to_string(), "2024-02-29T01:00:00Z");
    /// assert_eq!(t.add_seconds_i32(-86_401)?.to_string(), "2024-02-27T22:59:59Z");
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn add_seconds_i32(&self, secs: i32) -> Result<Self, Error> {
        // SECONDS_PER_DAY fits an i32; the Euclidean remainder is
        // 0..86 400, so at most 86 399 000 ms.
        let per_day = SECONDS_PER_DAY as i32;
        let days = secs.div_euclid(per_day);
        let rest_ms = secs.rem_euclid(per_day).unsigned_abs() * 1000;
        self.add_days_ms(days, rest_ms)
    }

    /// Whole seconds from `earlier` to this instant (negative when it is
    /// earlier), as [`UtcTime::unix_seconds`] differ; `None` when the two
    /// days are more than 24,854 days (68 years) apart, so that the
    /// difference always fits an `i32`. In 32-bit arithmetic, as
    /// [`UtcTime::add_seconds_i32`].
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// let rise: UtcTime = "2026-06-21T05:12:07.900Z".parse()?;
    /// let set: UtcTime = "2026-06-21T18:40:59.100Z".parse()?;
    /// // 18:40:59 − 05:12:07 = 13 h 28 min 52 s = 48 532 s (whole seconds).
    /// assert_eq!(set.seconds_since(&rise), Some(48_532));
    /// assert_eq!(rise.seconds_since(&set), Some(-48_532));
    /// let far: UtcTime = "2100-01-01T00:00:00Z".parse()?;
    /// assert_eq!(far.seconds_since(&rise), None);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    // Out of line on AVR: inlined, its two divisions by 1000 and its
    // product were copied into every caller (1,092 B of the Mega image).
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn seconds_since(&self, earlier: &UtcTime) -> Option<i32> {
        // Up to 24 854 days apart: 24 854 × 86 400 + 86 399 s < 2³¹. A
        // range test rather than a checked product (the overflow-checked
        // multiplication is a 500-byte routine on an AVR).
        const MAX_DAYS: i32 = (i32::MAX / SECONDS_PER_DAY as i32) - 1;
        let days = self.days.checked_sub(earlier.days)?;
        if !(-MAX_DAYS..=MAX_DAYS).contains(&days) {
            return None;
        }
        // Both below 86 400: the difference fits.
        let within_day = (self.ms_of_day / 1000) as i32 - (earlier.ms_of_day / 1000) as i32;
        Some(days * SECONDS_PER_DAY as i32 + within_day)
    }

    /// This instant plus whole days and `ms` (below one day) milliseconds.
    // Out of line on the AVR: the 32-bit adds and range checks were
    // inlined into each caller there (the time keeper's `add_millis_u32`
    // and `add_seconds_i32`).
    #[cfg_attr(target_arch = "avr", inline(never))]
    #[cfg_attr(not(target_arch = "avr"), inline)]
    fn add_days_ms(&self, whole_days: i32, ms: u32) -> Result<Self, Error> {
        // Below two days (2 × MS_PER_DAY): one comparison, not a division.
        let total_ms = ms.checked_add(self.ms_of_day).ok_or(Error::InvalidTime)?;
        let (carry_days, ms_of_day) = if total_ms >= MS_PER_DAY {
            (1, total_ms - MS_PER_DAY)
        } else {
            (0, total_ms)
        };
        let days = self
            .days
            .checked_add(whole_days)
            .and_then(|d| d.checked_add(carry_days))
            .ok_or(Error::InvalidDate)?;
        Self::from_days_ms(days, ms_of_day)
    }

    /// Midnight (00:00) of this instant's day.
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// let t: UtcTime = "2003-10-17T19:30:30Z".parse()?;
    /// assert_eq!(t.start_of_day().to_string(), "2003-10-17T00:00:00Z");
    /// assert_eq!(t.start_of_day().days_since_2000(), t.days_since_2000());
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn start_of_day(&self) -> Self {
        UtcTime {
            days: self.days,
            ms_of_day: 0,
        }
    }

    /// Days since 2000-01-01 (that day is 0; negative before).
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // Python: (date(2024, 2, 29) - date(2000, 1, 1)).days == 8825.
    /// assert_eq!("2024-02-29T18:00:00Z".parse::<UtcTime>()?.days_since_2000(), 8_825);
    /// assert_eq!("1999-12-31T23:59:59Z".parse::<UtcTime>()?.days_since_2000(), -1);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn days_since_2000(&self) -> i32 {
        self.days
    }

    /// Milliseconds since midnight.
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // 19 h 30 min 30.25 s = ((19 × 60 + 30) × 60 + 30) × 1000 + 250 ms.
    /// assert_eq!("2003-10-17T19:30:30.25Z".parse::<UtcTime>()?.ms_of_day(), 70_230_250);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn ms_of_day(&self) -> u32 {
        self.ms_of_day
    }

    /// Integer part of the Julian Day at this day's 00:00 (the JD itself is
    /// this plus one half).
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // Meeus, example 7.a: 1957 October 4.81 is JD 2436116.31, so that day's
    /// // 0 h is JD 2436115.5.
    /// let t = UtcTime::from_ymd_hms(1957, 10, 4, 19, 26, 24)?;
    /// assert_eq!(t.jd_midnight_int(), 2_436_115);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn jd_midnight_int(&self) -> i32 {
        JD_2000_MIDNIGHT_INT + self.days
    }

    /// Fraction of the day elapsed, `0 ≤ f < 1`.
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // NREL SPA worked example: JD 2452930.312847 at 19:30:30 UT, so the day
    /// // (from 0 h, JD …929.5) is 0.812847 gone.
    /// let t: UtcTime = "2003-10-17T19:30:30Z".parse()?;
    /// assert!((t.day_fraction::<f64>() - 0.812_847).abs() < 1e-6);
    /// assert!((t.day_fraction::<f32>() - 0.812_847).abs() < 1e-6);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn day_fraction<T: Float>(&self) -> T {
        T::from_u32(self.ms_of_day) / T::from_u32(MS_PER_DAY)
    }

    /// Decimal hours since midnight.
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // 19:30:30 is 19 + 30/60 + 30/3600 = 19.508333 h.
    /// let t: UtcTime = "2003-10-17T19:30:30Z".parse()?;
    /// assert!((t.hours::<f64>() - 19.508_333_333).abs() < 1e-9);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn hours<T: Float>(&self) -> T {
        T::from_u32(self.ms_of_day) / T::from_u32(3_600_000)
    }

    /// The full Julian Day in `f64` (host tools; algorithms keep days apart).
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // NREL SPA report, worked example: JD 2452930.312847.
    /// let t: UtcTime = "2003-10-17T19:30:30Z".parse()?;
    /// assert!((t.julian_day_f64() - 2_452_930.312_847).abs() < 1e-6);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn julian_day_f64(&self) -> f64 {
        f64::from(self.jd_midnight_int()) + 0.5 + f64::from(self.ms_of_day) / f64::from(MS_PER_DAY)
    }

    /// Calendar date `(year, month, day)`.
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // Python: date(2000, 1, 1) + timedelta(8825) == date(2024, 2, 29).
    /// assert_eq!(UtcTime::from_days_ms(8_825, 0)?.ymd(), (2024, 2, 29));
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn ymd(&self) -> (i32, u8, u8) {
        let date = self.date();
        (date.year(), date.month(), date.day())
    }

    /// Calendar date as a [`Date`] (for the clock drivers, or any other user
    /// of the `suntracker-time` calendar).
    ///
    /// ```
    /// use sun_algos::time::Date;
    /// use sun_algos::UtcTime;
    ///
    /// let t: UtcTime = "2024-02-29T18:00:00Z".parse()?;
    /// assert_eq!(t.date(), Date::new(2024, 2, 29).unwrap());
    /// // Python: (date(2024, 2, 29) - date(1970, 1, 1)).days == 19782.
    /// assert_eq!(t.date().days_since_unix_epoch(), 19_782);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn date(&self) -> Date {
        // `days` lies within MIN_YEAR..=MAX_YEAR (checked by every
        // constructor), inside a Date's years (the DAYS_RANGE check): the
        // shift to the Unix epoch cannot overflow and the clamp never acts.
        Date::from_days_since_unix_epoch_clamped(self.days + UNIX_TO_2000_DAYS)
    }

    /// Calendar year.
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // One second before 2000-01-01 is still 1999.
    /// assert_eq!(UtcTime::MIDNIGHT_2000.add_seconds(-1)?.year(), 1999);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn year(&self) -> i32 {
        self.ymd().0
    }

    /// Time of day `(hour, minute, second, millisecond)`.
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // 70 230 250 ms after midnight: 19 h 30 min 30 s 250 ms.
    /// assert_eq!(UtcTime::from_days_ms(0, 70_230_250)?.hms_milli(), (19, 30, 30, 250));
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn hms_milli(&self) -> (u8, u8, u8, u16) {
        let ms = self.ms_of_day;
        let s = ms / 1000;
        (
            (s / 3600) as u8,
            ((s / 60) % 60) as u8,
            (s % 60) as u8,
            (ms % 1000) as u16,
        )
    }

    /// Day of the year, 1 on 1 January.
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // Python: date(2024, 12, 31).timetuple().tm_yday == 366 (a leap year).
    /// assert_eq!("2024-12-31T12:00:00Z".parse::<UtcTime>()?.day_of_year(), 366);
    /// assert_eq!("2026-06-21T12:00:00Z".parse::<UtcTime>()?.day_of_year(), 172);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn day_of_year(&self) -> u16 {
        self.date().day_of_year()
    }

    /// Year with its elapsed fraction, e.g. 2024.5 near 1 July 2024.
    ///
    /// ```
    /// use sun_algos::UtcTime;
    ///
    /// // Noon of 31 December 2024: 365.5 of the year's 366 days have passed.
    /// let t: UtcTime = "2024-12-31T12:00:00Z".parse()?;
    /// assert_eq!(t.decimal_year::<f64>(), 2024.0 + 365.5 / 366.0);
    /// # Ok::<(), sun_algos::Error>(())
    /// ```
    pub fn decimal_year<T: Float>(&self) -> T {
        let date = self.date();
        let y = date.year();
        let len: u32 = if is_leap_year(y) { 366 } else { 365 };
        let elapsed = u32::from(date.day_of_year()) - 1;
        T::from_i32(y) + (T::from_u32(elapsed) + self.day_fraction::<T>()) / T::from_u32(len)
    }
}

impl core::fmt::Display for UtcTime {
    /// ISO 8601, `2031-04-05T06:07:08Z` (milliseconds shown when not zero).
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let (y, mo, d) = self.ymd();
        let (h, mi, s, ms) = self.hms_milli();
        write!(f, "{y:04}-{mo:02}-{d:02}T{h:02}:{mi:02}:{s:02}")?;
        if ms != 0 {
            write!(f, ".{ms:03}")?;
        }
        f.write_str("Z")
    }
}

impl core::str::FromStr for UtcTime {
    type Err = Error;

    /// Parses `YYYY-MM-DDTHH:MM:SS[.fff]Z` (the `Z` may be omitted).
    fn from_str(s: &str) -> Result<Self, Error> {
        let s = s.trim();
        let s = s.strip_suffix('Z').unwrap_or(s);
        let (date, time) = s.split_once(['T', ' ']).ok_or(Error::InvalidDate)?;
        let (neg, date) = match date.strip_prefix('-') {
            Some(rest) => (true, rest),
            None => (false, date),
        };
        let mut dp = date.splitn(3, '-');
        let year: i32 = parse_num(dp.next())?;
        let month: u8 = parse_num(dp.next())?;
        let day: u8 = parse_num(dp.next())?;
        let year = if neg { -year } else { year };
        let (hms, frac) = match time.split_once('.') {
            Some((a, b)) => (a, Some(b)),
            None => (time, None),
        };
        let mut tp = hms.splitn(3, ':');
        let hour: u8 = parse_num(tp.next()).map_err(|_| Error::InvalidTime)?;
        let minute: u8 = parse_num(tp.next()).map_err(|_| Error::InvalidTime)?;
        let second: u8 = parse_num(tp.next()).map_err(|_| Error::InvalidTime)?;
        let milli = match frac {
            None => 0,
            Some(f) => {
                if f.is_empty() || !f.bytes().all(|b| b.is_ascii_digit()) {
                    return Err(Error::InvalidTime);
                }
                // The first three digits, right-padded with zeros ("25" is 250 ms);
                // further digits are dropped. Each digit is 0..=9, so at most 999.
                f.bytes()
                    .chain(*b"00")
                    .take(3)
                    .fold(0u16, |ms, b| ms * 10 + u16::from(b.wrapping_sub(b'0')))
            }
        };
        UtcTime::from_ymd_hms_milli(year, month, day, hour, minute, second, milli)
    }
}

fn parse_num<N: core::str::FromStr>(s: Option<&str>) -> Result<N, Error> {
    let s = s.ok_or(Error::InvalidDate)?;
    if s.is_empty() || !s.bytes().all(|b| b.is_ascii_digit()) {
        return Err(Error::InvalidDate);
    }
    s.parse().map_err(|_| Error::InvalidDate)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn j2000_epoch_is_day_zero() {
        let t = UtcTime::from_ymd_hms(2000, 1, 1, 12, 0, 0).unwrap();
        assert_eq!(t.days_since_2000(), 0);
        // JD 2451545.0 is 2000-01-01 12:00 (Meeus, Astronomical Algorithms, ch. 7).
        assert_eq!(t.julian_day_f64(), 2_451_545.0);
    }

    #[test]
    fn nrel_example_julian_day() {
        // NREL SPA report worked example: 2003-10-17 19:30:30 UT → JD 2452930.312847.
        let t = UtcTime::from_ymd_hms(2003, 10, 17, 19, 30, 30).unwrap();
        assert!((t.julian_day_f64() - 2_452_930.312_847).abs() < 1e-6);
    }

    #[test]
    fn meeus_julian_days() {
        // Meeus, Astronomical Algorithms, example 7.a and the table of ch. 7.
        let t = UtcTime::from_ymd_hms(1957, 10, 4, 19, 26, 24).unwrap();
        assert!((t.julian_day_f64() - 2_436_116.31).abs() < 1e-9);
        let t = UtcTime::from_ymd_hms(1600, 1, 1, 0, 0, 0).unwrap();
        assert_eq!(t.julian_day_f64(), 2_305_447.5);
        let t = UtcTime::from_ymd_hms(-1000, 7, 12, 12, 0, 0).unwrap();
        // Proleptic Gregorian −1000-07-12 is Julian −1000-07-24... checked as a
        // round trip instead of against Meeus' Julian-calendar table.
        assert_eq!(t.ymd(), (-1000, 7, 12));
    }

    #[test]
    fn calendar_round_trip_every_day_1900_2100() {
        let start = UtcTime::from_ymd_hms(1900, 1, 1, 0, 0, 0)
            .unwrap()
            .days_since_2000();
        let end = UtcTime::from_ymd_hms(2100, 12, 31, 0, 0, 0)
            .unwrap()
            .days_since_2000();
        let mut prev: Option<(i32, u8, u8)> = None;
        for d in start..=end {
            let t = UtcTime::from_days_ms(d, 0).unwrap();
            let (y, m, dd) = t.ymd();
            assert_eq!(UtcTime::from_ymd_hms(y, m, dd, 0, 0, 0).unwrap(), t);
            if let Some(p) = prev {
                assert!((y, m, dd) > p);
            }
            prev = Some((y, m, dd));
        }
    }

    #[test]
    fn date_exchange_round_trips_over_the_whole_range() {
        let first = UtcTime::from_ymd_hms(MIN_YEAR, 1, 1, 0, 0, 0).unwrap();
        let last = UtcTime::from_ymd_hms(MAX_YEAR, 12, 31, 0, 0, 0).unwrap();
        for days in first.days_since_2000()..=last.days_since_2000() {
            let t = UtcTime::from_days_ms(days, 43_200_123).unwrap();
            let date = t.date();
            assert_eq!((date.year(), date.month(), date.day()), t.ymd());
            assert_eq!(UtcTime::from_date_ms(date, 43_200_123), Ok(t));
        }
        // 2000-01-01 is day 10 957 of the Unix epoch (946 684 800 s / 86 400,
        // POSIX time) and day 0 here.
        let d = Date::new(2000, 1, 1).unwrap();
        assert_eq!(d.days_since_unix_epoch(), 10_957);
        assert_eq!(UtcTime::from_date_ms(d, 0), Ok(UtcTime::MIDNIGHT_2000));
    }

    #[test]
    fn from_date_ms_rejects_what_utc_time_cannot_hold() {
        let d = Date::new(MAX_YEAR + 1, 1, 1).unwrap();
        assert_eq!(UtcTime::from_date_ms(d, 0), Err(Error::InvalidDate));
        let d = Date::new(MIN_YEAR - 1, 12, 31).unwrap();
        assert_eq!(UtcTime::from_date_ms(d, 0), Err(Error::InvalidDate));
        let d = Date::new(2026, 3, 20).unwrap();
        assert_eq!(
            UtcTime::from_date_ms(d, MS_PER_DAY),
            Err(Error::InvalidTime)
        );
        let t = UtcTime::from_date_ms(d, MS_PER_DAY - 1).unwrap();
        assert_eq!(t.ymd(), (2026, 3, 20));
        assert_eq!(t.hms_milli(), (23, 59, 59, 999));
        // Day of the year and decimal year from the shared Date: 2024 is a
        // leap year, so 31 December is day 366.
        let t = UtcTime::from_ymd_hms(2024, 12, 31, 12, 0, 0).unwrap();
        assert_eq!(t.day_of_year(), 366);
        assert_eq!(t.decimal_year::<f64>(), 2024.0 + 365.5 / 366.0);
    }

    #[test]
    fn rejects_bad_dates_and_times() {
        assert_eq!(
            UtcTime::from_ymd_hms(2023, 2, 29, 0, 0, 0),
            Err(Error::InvalidDate)
        );
        assert!(UtcTime::from_ymd_hms(2024, 2, 29, 0, 0, 0).is_ok());
        assert_eq!(
            UtcTime::from_ymd_hms(1900, 2, 29, 0, 0, 0),
            Err(Error::InvalidDate)
        );
        assert_eq!(
            UtcTime::from_ymd_hms(2024, 13, 1, 0, 0, 0),
            Err(Error::InvalidDate)
        );
        assert_eq!(
            UtcTime::from_ymd_hms(2024, 1, 1, 24, 0, 0),
            Err(Error::InvalidTime)
        );
        assert_eq!(
            UtcTime::from_days_ms(0, MS_PER_DAY),
            Err(Error::InvalidTime)
        );
        assert_eq!("2024-01-01".parse::<UtcTime>(), Err(Error::InvalidDate));
        assert!("2024-01-01T10:00:0xZ".parse::<UtcTime>().is_err());
    }

    #[test]
    fn parse_and_display() {
        let t: UtcTime = "2031-04-05T06:07:08Z".parse().unwrap();
        assert_eq!(t.ymd(), (2031, 4, 5));
        assert_eq!(t.hms_milli(), (6, 7, 8, 0));
        let mut buf = [0u8; 32];
        let s = fmt_to(&mut buf, &t);
        assert_eq!(s, "2031-04-05T06:07:08Z");
        let t: UtcTime = "2031-04-05T06:07:08.25Z".parse().unwrap();
        assert_eq!(t.hms_milli().3, 250);
    }

    #[test]
    fn unix_and_day_of_year() {
        // 2000-01-01T00:00:00Z is Unix 946 684 800 (POSIX time definition).
        let t = UtcTime::from_unix_seconds(946_684_800).unwrap();
        assert_eq!(t.days_since_2000(), 0);
        assert_eq!(t.unix_seconds(), 946_684_800);
        let t = UtcTime::from_ymd_hms(2024, 12, 31, 0, 0, 0).unwrap();
        assert_eq!(t.day_of_year(), 366);
        let t2 = t.add_seconds(86_400).unwrap();
        assert_eq!(t2.ymd(), (2025, 1, 1));
        assert_eq!(t2.add_seconds(-1).unwrap().hms_milli(), (23, 59, 59, 0));
    }

    #[test]
    fn add_millis_carries_days_and_stops_at_the_ends() {
        let t = UtcTime::from_ymd_hms_milli(2026, 3, 20, 23, 59, 59, 500).unwrap();
        let next = UtcTime::from_ymd_hms_milli(2026, 3, 21, 0, 0, 0, 400).unwrap();
        assert_eq!(t.add_millis(900), Ok(next));
        assert_eq!(next.add_millis(-900), Ok(t));
        assert_eq!(t.add_millis(0), Ok(t));
        for ms in [i64::MAX, i64::MIN, i64::MAX - 1, i64::MIN + 1] {
            assert_eq!(t.add_millis(ms), Err(Error::InvalidDate), "{ms}");
        }
    }

    #[test]
    fn add_seconds_at_the_ends_of_i64_is_an_error_not_a_panic() {
        let t = UtcTime::from_ymd_hms(2024, 6, 15, 12, 0, 0).unwrap();
        for secs in [
            i64::MAX,
            i64::MAX - 1,
            i64::MAX / 1000,
            i64::MAX / 1000 + 1,
            i64::MIN,
            i64::MIN + 1,
            i64::MIN / 1000,
            i64::MIN / 1000 - 1,
            i64::from(i32::MAX) * 86_400,
            i64::from(i32::MIN) * 86_400,
        ] {
            assert_eq!(t.add_seconds(secs), Err(Error::InvalidDate), "{secs}");
        }
        // The last instants that still fit: 8000-12-31T23:59:59 and
        // -4000-01-01T00:00:00, from either end of the range.
        let last = UtcTime::from_ymd_hms(MAX_YEAR, 12, 31, 23, 59, 59).unwrap();
        let first = UtcTime::from_ymd_hms(MIN_YEAR, 1, 1, 0, 0, 0).unwrap();
        assert_eq!(last.add_seconds(1), Err(Error::InvalidDate));
        assert_eq!(first.add_seconds(-1), Err(Error::InvalidDate));
        let span = last.unix_seconds() - first.unix_seconds();
        assert_eq!(first.add_seconds(span), Ok(last));
        assert_eq!(last.add_seconds(-span), Ok(first));
        assert_eq!(first.add_seconds(span + 1), Err(Error::InvalidDate));
        // Milliseconds are kept and carried across midnight.
        let t = UtcTime::from_ymd_hms_milli(2024, 12, 31, 23, 59, 59, 750).unwrap();
        let u = t.add_seconds(1).unwrap();
        assert_eq!(u.ymd(), (2025, 1, 1));
        assert_eq!(u.hms_milli(), (0, 0, 0, 750));
        assert_eq!(
            u.add_seconds(-86_401).unwrap().hms_milli(),
            (23, 59, 59, 750)
        );
    }

    #[test]
    fn unix_seconds_at_the_ends_of_i64_is_an_error_not_a_panic() {
        for secs in [i64::MAX, i64::MAX - 1, i64::MIN, i64::MIN + 1] {
            assert_eq!(UtcTime::from_unix_seconds(secs), Err(Error::InvalidDate));
        }
        let last = UtcTime::from_ymd_hms(MAX_YEAR, 12, 31, 23, 59, 59).unwrap();
        let first = UtcTime::from_ymd_hms(MIN_YEAR, 1, 1, 0, 0, 0).unwrap();
        assert_eq!(UtcTime::from_unix_seconds(last.unix_seconds()), Ok(last));
        assert_eq!(UtcTime::from_unix_seconds(first.unix_seconds()), Ok(first));
        assert_eq!(
            UtcTime::from_unix_seconds(last.unix_seconds() + 1),
            Err(Error::InvalidDate)
        );
        assert_eq!(
            UtcTime::from_unix_seconds(first.unix_seconds() - 1),
            Err(Error::InvalidDate)
        );
    }

    #[test]
    fn instants_order_by_day_then_millisecond() {
        use core::cmp::Ordering;
        use core::hash::{Hash, Hasher};
        // Pairs in time order, by their calendar readings: a later day
        // whose millisecond of the day is smaller, the same day a
        // millisecond apart, and days either side of 2000-01-01.
        let t =
            |y, mo, d, h, mi, s, ms| UtcTime::from_ymd_hms_milli(y, mo, d, h, mi, s, ms).unwrap();
        let pairs = [
            (t(2026, 6, 21, 23, 59, 59, 999), t(2026, 6, 22, 0, 0, 0, 0)),
            (t(2026, 6, 21, 12, 0, 0, 0), t(2026, 6, 21, 12, 0, 0, 1)),
            (t(1999, 12, 31, 23, 0, 0, 0), t(2000, 1, 1, 1, 0, 0, 0)),
        ];
        for (early, late) in pairs {
            // <, <=, >, >=, == and != of each way round.
            let ops = |a: UtcTime, b: UtcTime| [a < b, a <= b, a > b, a >= b, a == b, a != b];
            assert_eq!(ops(early, late), [true, true, false, false, false, true]);
            assert_eq!(ops(late, early), [false, false, true, true, false, true]);
            assert_eq!(ops(late, late), [false, true, false, true, true, false]);
            assert_eq!(early.cmp(&late), Ordering::Less);
            assert_eq!(late.cmp(&early), Ordering::Greater);
            assert_eq!(late.cmp(&late), Ordering::Equal);
            assert_eq!(early.partial_cmp(&late), Some(Ordering::Less));
            assert_eq!(late.max(early), late);
        }
        // Equal instants hash alike (a derived Hash of the fields).
        struct Sum(u64);
        impl Hasher for Sum {
            fn finish(&self) -> u64 {
                self.0
            }
            fn write(&mut self, bytes: &[u8]) {
                for &b in bytes {
                    self.0 = self.0.wrapping_mul(31).wrapping_add(u64::from(b));
                }
            }
        }
        let hash = |u: &UtcTime| {
            let mut h = Sum(0);
            u.hash(&mut h);
            h.finish()
        };
        let (a, b) = (t(2026, 6, 21, 1, 2, 3, 4), t(2026, 6, 21, 1, 2, 3, 4));
        assert_eq!(hash(&a), hash(&b));
    }

    #[test]
    fn fraction_of_a_second_is_parsed_without_indexing() {
        for (text, ms) in [("1", 100), ("12", 120), ("123", 123), ("1239", 123)] {
            let t: UtcTime = format_args_to_time(text);
            assert_eq!(t.hms_milli().3, ms, "{text}");
        }
    }

    fn format_args_to_time(frac: &str) -> UtcTime {
        extern crate std;
        std::format!("2024-01-01T00:00:00.{frac}Z").parse().unwrap()
    }

    fn fmt_to<'a>(buf: &'a mut [u8], t: &UtcTime) -> &'a str {
        use core::fmt::Write;
        struct W<'b>(&'b mut [u8], usize);
        impl Write for W<'_> {
            fn write_str(&mut self, s: &str) -> core::fmt::Result {
                let end = self.1 + s.len();
                self.0[self.1..end].copy_from_slice(s.as_bytes());
                self.1 = end;
                Ok(())
            }
        }
        let mut w = W(buf, 0);
        write!(w, "{t}").unwrap();
        let n = w.1;
        core::str::from_utf8(&buf[..n]).unwrap()
    }
}
