//! Proleptic Gregorian civil dates for `no_std` targets, from 8-bit AVR to
//! hosts: one validated [`Date`] type and the day-count arithmetic behind it,
//! with no allocation, no dependencies and no panics.
//!
//! This is the one calendar of the suntracker workspace. `sun_algos` (its
//! `UtcTime`: days since 2000 and the millisecond of the day) and
//! `suntracker-drivers` (its `DateTime`: the fields an RTC chip or an NMEA
//! sentence carries) both convert through it, so a date has the same day
//! count on either side and the glue between them only hands a [`Date`]
//! across.
//!
//! # Why a crate of its own
//!
//! Both users are published alone and run on 8-bit AVR and Cortex-M. The
//! drivers must not know about the sun, and the solar algorithms must not
//! pull in device drivers, so neither can own the calendar for the other:
//! the drivers already borrow `sun_algos`' `Float` for their f32 math, but
//! taking their clock type from it as well would tie every RTC and GPS reading
//! to an astronomy crate, its error type and its year range. A third crate
//! with nothing in it but the calendar keeps both dependencies honest and is
//! small enough to cost nothing when unused.
//!
//! # Range and representation
//!
//! A [`Date`] holds a year in [`MIN_YEAR`]`..=`[`MAX_YEAR`] (−9999 to 9999,
//! the four-digit years of ISO 8601, year 0 being 1 BC), a month and a day:
//! four bytes. Its day count since 1970-01-01 is an `i32` (at most ±4.4 × 10⁶
//! over the range), and the arithmetic behind it needs neither 64-bit nor
//! signed 32-bit division, each a software routine of some hundred bytes on
//! AVR. Each user narrows the range to its own (`sun_algos`: −4000…8000; the
//! drivers: 1…9999). Everything is a `const fn`, so a fixed date or instant
//! can be a compile-time constant with no arithmetic left in the image.
//!
//! The two free functions [`days_from_civil`] and [`civil_from_days`] are the
//! same arithmetic without validation, total over their argument types, for
//! tools that must accept any input (such as device models in an emulator).
//!
//! Seconds and milliseconds counted in 64 bits are split into days (or any
//! 32-bit unit) by [`div_rem_u64`] and [`div_rem_euclid_i64`], in 32-bit
//! steps: an AVR image that uses them links no 64-bit division routine.
//!
//! # Source
//!
//! The conversions are H. Hinnant's `days_from_civil` and `civil_from_days`
//! (*chrono-Compatible Low-Level Date Algorithms*,
//! <https://howardhinnant.github.io/date_algorithms.html>): years counted
//! from 1 March so that the leap day ends the year, months from the
//! `(153 m + 2) / 5` pattern of their lengths, 400-year cycles of 146 097
//! days. One change for 8-bit targets: instead of splitting the year into
//! signed 400-year eras, the count starts 10 000 years (25 whole cycles)
//! before year 0, so every intermediate value is unsigned and the year
//! arithmetic fits 16 bits. `tests/reference.rs` checks every day of the
//! range against chrono's `NaiveDate`, an independent implementation.
//!
//! # Features
//!
//! All optional and off by default; each keeps the crate `no_std` and
//! allocation-free.
//!
//! - `chrono`: `From<Date> for chrono::NaiveDate` (every `Date` is a chrono
//!   date) and `TryFrom<chrono::NaiveDate> for Date` ([`DateError::Year`]
//!   outside [`MIN_YEAR`]`..=`[`MAX_YEAR`]); chrono with
//!   `default-features = false`.
//! - `serde`: `Serialize`/`Deserialize` for [`Date`], as its fields
//!   (`{"year":2024,"month":2,"day":29}` in JSON) checked again by
//!   [`Date::new`] when read, so an invalid date is a deserialization error;
//!   and for [`DateError`]. serde with `default-features = false`.
//! - `defmt`: `defmt::Format` for [`Date`] (ISO 8601, as its `Display`) and
//!   [`DateError`].
//!
//! # Example
//!
//! ```
//! use suntracker_time::{Date, DateError};
//!
//! let d = Date::new(2024, 2, 29)?;
//! assert_eq!(d.days_since_unix_epoch(), 19_782);
//! assert_eq!(d.day_of_year(), 60);
//! assert_eq!(d.iso_weekday(), 4); // a Thursday
//! assert_eq!(Date::from_days_since_unix_epoch(19_783)?, Date::new(2024, 3, 1)?);
//! assert_eq!(Date::new(2100, 2, 29), Err(DateError::Day)); // not a leap year
//! # Ok::<(), DateError>(())
//! ```

#![no_std]
#![deny(unsafe_code)]
#![warn(missing_docs)]

// The README's examples are compiled and run as doc tests too.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

use core::fmt;

mod div64;
pub use div64::{div_rem_euclid_i64, div_rem_u64, div_rem_u64_u16};

#[cfg(feature = "chrono")]
mod with_chrono;
#[cfg(feature = "defmt")]
mod with_defmt;
#[cfg(feature = "serde")]
mod with_serde;

/// First year a [`Date`] holds (ISO 8601 astronomical numbering: year 0 is
/// 1 BC, −1 is 2 BC).
///
/// ```
/// use suntracker_time::{Date, DateError, MIN_YEAR};
///
/// assert_eq!(Date::MIN.year(), MIN_YEAR);
/// assert_eq!(Date::new(MIN_YEAR - 1, 12, 31), Err(DateError::Year));
/// ```
pub const MIN_YEAR: i32 = -9999;
/// Last year a [`Date`] holds.
///
/// ```
/// use suntracker_time::{Date, DateError, MAX_YEAR};
///
/// assert_eq!(Date::MAX.year(), MAX_YEAR);
/// assert_eq!(Date::new(MAX_YEAR + 1, 1, 1), Err(DateError::Year));
/// ```
pub const MAX_YEAR: i32 = 9999;

/// Days in one 400-year Gregorian cycle (400 × 365 + 97 leap days).
const DAYS_PER_ERA: i32 = 146_097;
/// The arithmetic counts years from 1 March of year −10 000: 10 000 years,
/// 25 whole 400-year cycles, before year 0, so that every year of a [`Date`]
/// is a non-negative count with the leap years where the calendar has them.
const YEAR_SHIFT: i16 = 10_000;
/// Days from −10000-03-01 to 1970-01-01: 25 cycles of 146 097 days, plus
/// the 719 468 days from 0000-03-01 to 1970-01-01 (Hinnant).
const DAYS_SHIFT: i32 = 25 * DAYS_PER_ERA + 719_468;

/// True for Gregorian leap years: every fourth year, except the centuries
/// not divisible by 400 (1900 and 2100 are not leap years, 2000 is).
///
/// ```
/// use suntracker_time::is_leap_year;
///
/// // Python's calendar.isleap gives the same for each year.
/// assert!(is_leap_year(2000) && is_leap_year(2024) && is_leap_year(1600));
/// assert!(!is_leap_year(1900) && !is_leap_year(2100) && !is_leap_year(2023));
/// // Proleptic and astronomical: year 0 (1 BC) and −4 (5 BC) are leap years.
/// assert!(is_leap_year(0) && is_leap_year(-4) && !is_leap_year(-100));
/// ```
pub const fn is_leap_year(year: i32) -> bool {
    // For a multiple of 4, "divisible by 100" is "divisible by 25" and
    // "divisible by 400" is "divisible by 16": the same rule with one
    // division by a constant instead of two (the powers of two are bit
    // tests, also for negative years in two's complement).
    year & 3 == 0 && (year % 25 != 0 || year & 15 == 0)
}

/// Number of days in a month (1..=12) of a year; 0 for a month outside 1..=12.
///
/// ```
/// use suntracker_time::days_in_month;
///
/// // Python: calendar.monthrange(2024, 2)[1] == 29, (2023, 2) → 28.
/// assert_eq!(days_in_month(2024, 2), 29);
/// assert_eq!(days_in_month(2023, 2), 28);
/// assert_eq!(days_in_month(2023, 4), 30);
/// assert_eq!(days_in_month(2023, 12), 31);
/// assert_eq!(days_in_month(2023, 13), 0);
/// ```
pub const fn days_in_month(year: i32, month: u8) -> u8 {
    match month {
        2 => 28 + is_leap_year(year) as u8,
        // 31 for odd months up to July and even months from August:
        // 31, _, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31.
        1..=12 => 30 + ((month + month / 8) & 1),
        _ => 0,
    }
}

/// Days from 1 March to the first day of a month, for the month counted from
/// March (0 = March … 11 = February): the month lengths 31, 30, 31, 30, 31
/// repeat, which `(153 m + 2) / 5` reproduces (Hinnant, `days_from_civil`).
const fn days_before_month_from_march(month_from_march: u16) -> u16 {
    (153 * month_from_march + 2) / 5
}

/// Days from 1970-01-01 to `year-month-day`: the one implementation of the
/// date → day count direction in this crate.
///
/// Hinnant's `days_from_civil` with the year shifted by [`YEAR_SHIFT`]
/// instead of split into signed 400-year eras: the count of March-based
/// years is then never negative, and the days before one of them are the
/// plain Gregorian sum `365 y + ⌊y/4⌋ − ⌊y/100⌋ + ⌊y/400⌋` in unsigned 16-bit
/// arithmetic (no signed 32-bit division, a library routine on AVR).
///
/// Domain: years −9999 ..= 22 767 (a [`Date`]'s, or the 0..400 to which
/// [`days_from_civil`] reduces any year), any month and day. Month 0 and 13
/// and days past either end of a month roll over (day 0 is the last day of
/// the month before, month 13 is January of the next year).
const fn days_from_civil_in_range(year: i16, month: u8, day: u8) -> i32 {
    // Years counted from 1 March: January and February belong to the year
    // before, so that February and its leap day end the year.
    let (shifted_year, month_from_march) = if month > 2 {
        (year + YEAR_SHIFT, month - 3)
    } else {
        (year + YEAR_SHIFT - 1, month + 9)
    };
    let y = shifted_year as u16; // 0..=32 766 in the domain
    let centuries = y / 100;
    let days_before_year =
        y as i32 * 365 + (y / 4) as i32 - centuries as i32 + (centuries / 4) as i32;
    days_before_year + days_before_month_from_march(month_from_march as u16) as i32 + day as i32
        - 1
        - DAYS_SHIFT
}

/// The date `days` days after 1970-01-01: the one implementation of the day
/// count → date direction.
///
/// Hinnant's `civil_from_days`, counted from −10000-03-01 (see
/// [`YEAR_SHIFT`]) so that the 400-year cycle and everything after it are
/// unsigned. Domain: counts of a [`Date`] (−4 371 587 ..= 2 932 896), or the
/// 0..146 097 to which [`civil_from_days`] reduces any count.
const fn civil_in_range(days: i32) -> (i16, u8, u8) {
    let z = (days + DAYS_SHIFT) as u32; // ≥ 0 in the domain
    let era = z / DAYS_PER_ERA as u32; // 0..=49
    let day_of_era = z % DAYS_PER_ERA as u32; // 0..=146 096
                                              // Years of the cycle: one day less every 4 years, one more every 100,
                                              // one less on the cycle's last day (its 29 February).
    let year_of_era = ((day_of_era - day_of_era / 1460 + day_of_era / 36_524
        - (day_of_era == 146_096) as u32)
        / 365) as u16; // 0..=399
    let day_of_year = (day_of_era
        - (year_of_era as u32 * 365 + (year_of_era / 4) as u32 - (year_of_era / 100) as u32))
        as u16; // 0..=365, from 1 March
    let month_from_march = (5 * day_of_year + 2) / 153; // 0..=11
    let day = day_of_year - days_before_month_from_march(month_from_march) + 1; // 1..=31
                                                                                // January and February end the March-based year: their calendar year is
                                                                                // the next one.
    let (month, next_year) = if month_from_march < 10 {
        (month_from_march + 3, 0)
    } else {
        (month_from_march - 9, 1)
    };
    // era × 400 ≤ 19 600: the year fits an i16.
    let year = (era * 400) as i16 + year_of_era as i16 + next_year - YEAR_SHIFT;
    (year, month as u8, day as u8)
}

/// Days from 1970-01-01 to `year-month-day` of the proleptic Gregorian
/// calendar (negative before), without validation.
///
/// For a valid date this is [`Date::days_since_unix_epoch`]. Any arguments
/// give a count and never overflow (the result is an `i64` because years
/// beyond about ±5.8 million do not fit an `i32` count). Month 0 and 13 and
/// days past either end of a month roll over (day 0 is the last day of the
/// month before, month 13 is January of the next year); months above 13 give
/// a count callers must not rely on. Firmware should use [`Date`], whose
/// arithmetic stays in 16 and 32 bits.
///
/// ```
/// use suntracker_time::days_from_civil;
///
/// // Python: (date(2000, 1, 1) - date(1970, 1, 1)).days == 10957, and
/// // (date(1, 1, 1) - date(1970, 1, 1)).days == -719162.
/// assert_eq!(days_from_civil(2000, 1, 1), 10_957);
/// assert_eq!(days_from_civil(1, 1, 1), -719_162);
/// // Month 13 and day 0 roll over.
/// assert_eq!(days_from_civil(2024, 13, 1), days_from_civil(2025, 1, 1));
/// assert_eq!(days_from_civil(2024, 3, 0), days_from_civil(2024, 2, 29));
/// // Far outside a Date's years, still a count: 1 000 000 years are
/// // 2 500 Gregorian cycles of 146 097 days.
/// assert_eq!(
///     days_from_civil(1_002_000, 1, 1) - days_from_civil(2000, 1, 1),
///     2_500 * 146_097
/// );
/// ```
pub const fn days_from_civil(year: i32, month: u8, day: u8) -> i64 {
    // The calendar repeats every 400 years (146 097 days): whole cycles are
    // counted apart, the rest goes through the one implementation.
    let eras = year.div_euclid(400) as i64;
    let year_of_era = year.rem_euclid(400) as i16; // 0..=399
    eras * DAYS_PER_ERA as i64 + days_from_civil_in_range(year_of_era, month, day) as i64
}

/// The date `(year, month, day)` `days` days after 1970-01-01 (before it
/// when negative), for any `i32`: the inverse of [`days_from_civil`].
///
/// No validation is needed (every count is a date, years within about ±5.9
/// million); [`Date::from_days_since_unix_epoch`] is the same conversion
/// limited to the years of a [`Date`].
///
/// ```
/// use suntracker_time::civil_from_days;
///
/// // Python: date(1970, 1, 1) + timedelta(19782) == date(2024, 2, 29).
/// assert_eq!(civil_from_days(19_782), (2024, 2, 29));
/// assert_eq!(civil_from_days(-1), (1969, 12, 31));
/// assert_eq!(civil_from_days(-719_162), (1, 1, 1));
/// // Total over i32: years beyond ±5 million.
/// let (year, _, _) = civil_from_days(i32::MAX);
/// assert!(year > 5_000_000);
/// ```
pub const fn civil_from_days(days: i32) -> (i32, u8, u8) {
    // As in days_from_civil: whole 400-year cycles apart (|eras| ≤ 14 699,
    // so eras × 400 is within ±5.9 × 10⁶).
    let eras = days.div_euclid(DAYS_PER_ERA);
    let (year, month, day) = civil_in_range(days.rem_euclid(DAYS_PER_ERA));
    (eras * 400 + year as i32, month, day)
}

/// Why a date was rejected.
///
/// ```
/// use suntracker_time::{Date, DateError};
///
/// // Checked in the order year, month, day.
/// assert_eq!(Date::new(12_000, 2, 30), Err(DateError::Year));
/// assert_eq!(Date::new(2024, 13, 30), Err(DateError::Month));
/// assert_eq!(Date::new(2024, 2, 30), Err(DateError::Day));
/// assert_eq!(DateError::Month.to_string(), "month outside 1..=12");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DateError {
    /// Year outside [`MIN_YEAR`]`..=`[`MAX_YEAR`] (or a day count outside
    /// those years).
    Year,
    /// Month outside 1..=12.
    Month,
    /// Day 0 or past the end of the month.
    Day,
}

impl fmt::Display for DateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DateError::Year => write!(f, "year outside {MIN_YEAR}..={MAX_YEAR}"),
            DateError::Month => f.write_str("month outside 1..=12"),
            DateError::Day => f.write_str("day is 0 or past the end of the month"),
        }
    }
}

impl core::error::Error for DateError {}

/// A valid date of the proleptic Gregorian calendar, years
/// [`MIN_YEAR`]`..=`[`MAX_YEAR`].
///
/// The fields are private, so every `Date` in circulation is valid; the
/// derived ordering is chronological (year, then month, then day). `Display`
/// is ISO 8601.
///
/// ```
/// use suntracker_time::{Date, DateError};
///
/// let d = Date::new(1969, 7, 20)?;
/// assert_eq!(d.to_string(), "1969-07-20");
/// assert!(d < Date::UNIX_EPOCH && Date::MIN < d && d < Date::MAX);
/// // Python: (date(1969, 7, 20) - date(1970, 1, 1)).days == -165.
/// assert_eq!(d.days_since_unix_epoch(), -165);
/// assert_eq!(Date::new(-44, 3, 15)?.to_string(), "-0044-03-15");
/// assert_eq!(core::mem::size_of::<Date>(), 4);
/// # Ok::<(), DateError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Date {
    /// `MIN_YEAR..=MAX_YEAR`, which fits an i16.
    year: i16,
    /// 1..=12.
    month: u8,
    /// 1..=days_in_month(year, month).
    day: u8,
}

impl Date {
    /// 1970-01-01, day 0 of [`Date::days_since_unix_epoch`].
    ///
    /// ```
    /// use suntracker_time::Date;
    ///
    /// assert_eq!(Date::UNIX_EPOCH.days_since_unix_epoch(), 0);
    /// // 1 January 1970 was a Thursday (Python: date(1970, 1, 1).isoweekday() == 4).
    /// assert_eq!(Date::UNIX_EPOCH.iso_weekday(), 4);
    /// ```
    pub const UNIX_EPOCH: Date = Date {
        year: 1970,
        month: 1,
        day: 1,
    };
    /// The first date: −9999-01-01.
    ///
    /// ```
    /// use suntracker_time::{days_from_civil, Date};
    ///
    /// assert_eq!(Date::MIN.to_string(), "-9999-01-01");
    /// assert_eq!(i64::from(Date::MIN.days_since_unix_epoch()), days_from_civil(-9999, 1, 1));
    /// ```
    pub const MIN: Date = Date {
        year: MIN_YEAR as i16,
        month: 1,
        day: 1,
    };
    /// The last date: 9999-12-31.
    ///
    /// ```
    /// use suntracker_time::Date;
    ///
    /// // Python: (date(9999, 12, 31) - date(1970, 1, 1)).days == 2932896.
    /// assert_eq!(Date::MAX.days_since_unix_epoch(), 2_932_896);
    /// ```
    pub const MAX: Date = Date {
        year: MAX_YEAR as i16,
        month: 12,
        day: 31,
    };
    /// Day count of [`Date::MIN`] (−4 371 587).
    const MIN_DAYS: i32 = Date::MIN.days_since_unix_epoch();
    /// Day count of [`Date::MAX`] (2 932 896).
    const MAX_DAYS: i32 = Date::MAX.days_since_unix_epoch();

    /// A validated date; the year is checked first, then the month, then the
    /// day.
    ///
    /// ```
    /// use suntracker_time::{Date, DateError};
    ///
    /// let d = Date::new(2024, 2, 29)?;
    /// assert_eq!((d.year(), d.month(), d.day()), (2024, 2, 29));
    /// assert_eq!(Date::new(2023, 2, 29), Err(DateError::Day)); // not a leap year
    /// assert_eq!(Date::new(2024, 0, 1), Err(DateError::Month));
    /// // A const fn: a fixed date can be a compile-time constant.
    /// const START: Result<Date, DateError> = Date::new(2026, 3, 20);
    /// assert!(START.is_ok());
    /// # Ok::<(), DateError>(())
    /// ```
    pub const fn new(year: i32, month: u8, day: u8) -> Result<Date, DateError> {
        if year < MIN_YEAR || year > MAX_YEAR {
            return Err(DateError::Year);
        }
        if month < 1 || month > 12 {
            return Err(DateError::Month);
        }
        if day == 0 || day > days_in_month(year, month) {
            return Err(DateError::Day);
        }
        Ok(Date {
            year: year as i16, // within ±9999 (checked above)
            month,
            day,
        })
    }

    /// The date `days` days after 1970-01-01 (before it when negative);
    /// [`DateError::Year`] outside [`Date::MIN`]`..=`[`Date::MAX`].
    ///
    /// ```
    /// use suntracker_time::{Date, DateError};
    ///
    /// // Python: date(1970, 1, 1) + timedelta(20778) == date(2026, 11, 21).
    /// assert_eq!(Date::from_days_since_unix_epoch(20_778)?, Date::new(2026, 11, 21)?);
    /// assert_eq!(Date::from_days_since_unix_epoch(2_932_897), Err(DateError::Year));
    /// # Ok::<(), DateError>(())
    /// ```
    pub const fn from_days_since_unix_epoch(days: i32) -> Result<Date, DateError> {
        if days < Date::MIN_DAYS || days > Date::MAX_DAYS {
            return Err(DateError::Year);
        }
        let (year, month, day) = civil_in_range(days);
        Ok(Date { year, month, day })
    }

    /// The date `days` days after 1970-01-01 (before it when negative),
    /// clamped to [`Date::MIN`]`..=`[`Date::MAX`]: for callers whose count is
    /// already known to lie in the range, without an error path to carry.
    ///
    /// ```
    /// use suntracker_time::Date;
    ///
    /// // Python: date(1970, 1, 1) + timedelta(10957) == date(2000, 1, 1).
    /// assert_eq!(Date::from_days_since_unix_epoch_clamped(10_957).to_string(), "2000-01-01");
    /// assert_eq!(Date::from_days_since_unix_epoch_clamped(i32::MAX), Date::MAX);
    /// assert_eq!(Date::from_days_since_unix_epoch_clamped(i32::MIN), Date::MIN);
    /// ```
    pub const fn from_days_since_unix_epoch_clamped(days: i32) -> Date {
        let days = if days < Date::MIN_DAYS {
            Date::MIN_DAYS
        } else if days > Date::MAX_DAYS {
            Date::MAX_DAYS
        } else {
            days
        };
        let (year, month, day) = civil_in_range(days);
        Date { year, month, day }
    }

    /// Days since 1970-01-01 (negative before), −4 371 587 ..= 2 932 896.
    ///
    /// ```
    /// use suntracker_time::{Date, DateError};
    ///
    /// // POSIX time of 2000-01-01T00:00:00Z is 946 684 800 s = 10 957 days.
    /// assert_eq!(Date::new(2000, 1, 1)?.days_since_unix_epoch(), 946_684_800 / 86_400);
    /// // Python: (date(1900, 2, 28) - date(1970, 1, 1)).days == -25509.
    /// assert_eq!(Date::new(1900, 2, 28)?.days_since_unix_epoch(), -25_509);
    /// # Ok::<(), DateError>(())
    /// ```
    pub const fn days_since_unix_epoch(self) -> i32 {
        days_from_civil_in_range(self.year, self.month, self.day)
    }

    /// Year, [`MIN_YEAR`]`..=`[`MAX_YEAR`] (0 is 1 BC).
    ///
    /// ```
    /// use suntracker_time::{Date, DateError};
    ///
    /// assert_eq!(Date::new(-44, 3, 15)?.year(), -44); // 45 BC
    /// # Ok::<(), DateError>(())
    /// ```
    pub const fn year(self) -> i32 {
        self.year as i32
    }

    /// Month, 1..=12.
    ///
    /// ```
    /// use suntracker_time::{Date, DateError};
    ///
    /// // Python: date(1970, 1, 1) + timedelta(-1) is 1969-12-31.
    /// assert_eq!(Date::from_days_since_unix_epoch(-1)?.month(), 12);
    /// # Ok::<(), DateError>(())
    /// ```
    pub const fn month(self) -> u8 {
        self.month
    }

    /// Day of the month, 1..=31.
    ///
    /// ```
    /// use suntracker_time::{Date, DateError};
    ///
    /// // Python: date(1970, 1, 1) + timedelta(11016) == date(2000, 2, 29).
    /// assert_eq!(Date::from_days_since_unix_epoch(11_016)?.day(), 29);
    /// # Ok::<(), DateError>(())
    /// ```
    pub const fn day(self) -> u8 {
        self.day
    }

    /// Day of the year, 1 on 1 January, 365 or 366 on 31 December.
    ///
    /// ```
    /// use suntracker_time::{Date, DateError};
    ///
    /// // Python: date(y, m, d).timetuple().tm_yday.
    /// assert_eq!(Date::new(2024, 12, 31)?.day_of_year(), 366);
    /// assert_eq!(Date::new(2026, 6, 21)?.day_of_year(), 172);
    /// assert_eq!(Date::new(1900, 3, 1)?.day_of_year(), 60);
    /// # Ok::<(), DateError>(())
    /// ```
    pub const fn day_of_year(self) -> u16 {
        // 1..=366 counted from 1 March (1 on 1 March).
        let from_march =
            days_before_month_from_march((self.month as u16 + 9) % 12) + self.day as u16;
        if self.month >= 3 {
            // 59 days in January and February, 60 in a leap year.
            from_march + 59 + is_leap_year(self.year as i32) as u16
        } else {
            // 1 January is day 307 counted from the 1 March before.
            from_march - 306
        }
    }

    /// Day of the week as in ISO 8601: 1 = Monday … 7 = Sunday.
    ///
    /// ```
    /// use suntracker_time::{Date, DateError};
    ///
    /// // Python: date(y, m, d).isoweekday().
    /// assert_eq!(Date::new(2026, 6, 21)?.iso_weekday(), 7); // a Sunday
    /// assert_eq!(Date::new(2024, 12, 31)?.iso_weekday(), 2); // a Tuesday
    /// assert_eq!(Date::new(1, 1, 1)?.iso_weekday(), 1); // a Monday
    /// # Ok::<(), DateError>(())
    /// ```
    pub const fn iso_weekday(self) -> u8 {
        // 1970-01-01 (day 0) was a Thursday (4); counted from −10000-03-01
        // (DAYS_SHIFT ≡ 1 mod 7) the count is never negative, so the
        // remainder is an unsigned one.
        ((self.days_since_unix_epoch() + DAYS_SHIFT + 2) as u32 % 7) as u8 + 1
    }
}

/// ISO 8601 calendar date, `2024-02-29`; years before 1 with a minus sign and
/// four digits, `-0044-03-15`.
impl fmt::Display for Date {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.year < 0 {
            f.write_str("-")?;
        }
        write!(
            f,
            "{:04}-{:02}-{:02}",
            self.year.unsigned_abs(),
            self.month,
            self.day
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Expected values from Python's datetime module (proleptic Gregorian,
    // years 1..=9999): `(date(y, m, d) - date(1970, 1, 1)).days`,
    // `date(y, m, d).timetuple().tm_yday` and `date(y, m, d).isoweekday()`.
    const PYTHON: [(i32, u8, u8, i32, u16, u8); 16] = [
        (1970, 1, 1, 0, 1, 4),
        (1969, 12, 31, -1, 365, 3),
        (2000, 1, 1, 10_957, 1, 6),
        (2000, 2, 29, 11_016, 60, 2),
        (2000, 12, 31, 11_322, 366, 7),
        (1900, 2, 28, -25_509, 59, 3),
        (1900, 3, 1, -25_508, 60, 4),
        (2100, 2, 28, 47_540, 59, 7),
        (2100, 3, 1, 47_541, 60, 1),
        (2024, 2, 29, 19_782, 60, 4),
        (2023, 12, 31, 19_722, 365, 7),
        (2026, 11, 21, 20_778, 325, 6),
        (1600, 2, 29, -135_081, 60, 2),
        (1, 1, 1, -719_162, 1, 1),
        (9999, 12, 31, 2_932_896, 365, 5),
        (2400, 12, 31, 157_419, 366, 7),
    ];

    #[test]
    fn known_dates_match_python_datetime() {
        for (y, m, d, days, yday, wday) in PYTHON {
            let date = Date::new(y, m, d).unwrap();
            assert_eq!(date.days_since_unix_epoch(), days, "{date}");
            assert_eq!(days_from_civil(y, m, d), i64::from(days), "{date}");
            assert_eq!(Date::from_days_since_unix_epoch(days), Ok(date));
            assert_eq!(civil_from_days(days), (y, m, d));
            assert_eq!(date.day_of_year(), yday, "{date}");
            assert_eq!(date.iso_weekday(), wday, "{date}");
        }
    }

    #[test]
    fn leap_years_follow_the_gregorian_rule() {
        for (year, leap) in [
            (1900, false),
            (2000, true),
            (2100, false),
            (2024, true),
            (2023, false),
            (0, true),
            (-4, true),
            (-100, false),
            (-400, true),
        ] {
            assert_eq!(is_leap_year(year), leap, "{year}");
            assert_eq!(days_in_month(year, 2), if leap { 29 } else { 28 });
            assert_eq!(Date::new(year, 2, 29).is_ok(), leap, "{year}");
        }
    }

    #[test]
    fn invalid_fields_are_errors_in_order() {
        assert_eq!(Date::new(MIN_YEAR - 1, 1, 1), Err(DateError::Year));
        assert_eq!(Date::new(MAX_YEAR + 1, 1, 1), Err(DateError::Year));
        assert_eq!(Date::new(i32::MIN, 0, 0), Err(DateError::Year));
        assert_eq!(Date::new(2024, 0, 1), Err(DateError::Month));
        assert_eq!(Date::new(2024, 13, 0), Err(DateError::Month));
        assert_eq!(Date::new(2024, 4, 31), Err(DateError::Day));
        assert_eq!(Date::new(2024, 4, 0), Err(DateError::Day));
        assert_eq!(days_in_month(2024, 0), 0);
        assert_eq!(days_in_month(2024, 13), 0);
    }

    #[test]
    fn day_counts_outside_the_range_are_errors() {
        for days in [Date::MIN_DAYS - 1, Date::MAX_DAYS + 1, i32::MIN, i32::MAX] {
            assert_eq!(
                Date::from_days_since_unix_epoch(days),
                Err(DateError::Year),
                "{days}"
            );
        }
        assert_eq!(
            Date::from_days_since_unix_epoch(Date::MIN_DAYS),
            Ok(Date::MIN)
        );
        assert_eq!(
            Date::from_days_since_unix_epoch(Date::MAX_DAYS),
            Ok(Date::MAX)
        );
        assert_eq!(Date::from_days_since_unix_epoch(0), Ok(Date::UNIX_EPOCH));
    }

    #[test]
    fn clamped_conversion_stops_at_the_ends() {
        assert_eq!(
            Date::from_days_since_unix_epoch_clamped(0),
            Date::UNIX_EPOCH
        );
        for days in [Date::MIN_DAYS - 1, i32::MIN] {
            assert_eq!(Date::from_days_since_unix_epoch_clamped(days), Date::MIN);
        }
        for days in [Date::MAX_DAYS + 1, i32::MAX] {
            assert_eq!(Date::from_days_since_unix_epoch_clamped(days), Date::MAX);
        }
        // Inside the range it is the checked conversion.
        for (_, _, _, days, _, _) in PYTHON {
            assert_eq!(
                Ok(Date::from_days_since_unix_epoch_clamped(days)),
                Date::from_days_since_unix_epoch(days)
            );
        }
    }

    #[test]
    fn raw_arithmetic_is_total() {
        // The extreme arguments give a value, not an overflow (tests run
        // with overflow checks).
        for y in [i32::MIN, i32::MIN + 1, -1, 0, i32::MAX - 1, i32::MAX] {
            for m in [0, 1, 2, 3, 12, 13, u8::MAX] {
                for d in [0, 1, 31, u8::MAX] {
                    let _ = days_from_civil(y, m, d);
                }
            }
        }
        for days in [i32::MIN, i32::MIN + 1, -1, 0, 1, i32::MAX - 1, i32::MAX] {
            let (y, m, d) = civil_from_days(days);
            assert_eq!(days_from_civil(y, m, d), i64::from(days), "{days}");
        }
    }

    #[test]
    fn display_is_iso_8601() {
        extern crate std;
        use std::string::ToString;
        assert_eq!(Date::new(2024, 2, 9).unwrap().to_string(), "2024-02-09");
        assert_eq!(Date::new(-44, 3, 15).unwrap().to_string(), "-0044-03-15");
        assert_eq!(Date::MIN.to_string(), "-9999-01-01");
        assert_eq!(Date::new(7, 1, 1).unwrap().to_string(), "0007-01-01");
        assert_eq!(DateError::Year.to_string(), "year outside -9999..=9999");
    }
}
